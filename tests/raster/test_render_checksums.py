"""Images must not change when the kernels are restructured: the renders of
``tests/support/render_corpus.py`` (every mode, shapes and real models, projections, 1 and 2 threads)
against the SHA-256 digests stored before the restructuring."""

import json

import pytest
from support import render_corpus
from support.paths import DATA


STORED = json.loads((DATA / "render_checksums.json").read_text())


def test_corpus_lists_every_stored_builtin_case():
    names = {f"{name}@1" for name, _ in render_corpus.cases()}
    builtin = {k for k in STORED if k.endswith("@1") and ".obj/" not in k}
    assert builtin <= names


@pytest.mark.parametrize("threads", [1, 2])
def test_renders_are_bit_identical_to_the_stored_ones(threads):
    import rasterkit

    rasterkit.set_threads(threads)
    try:
        changed = [name for name, thunk in render_corpus.cases()
                   if thunk() != STORED[f"{name}@{threads}"]]
    finally:
        rasterkit.set_threads(None)
    assert not changed


def test_real_models_are_in_the_corpus():
    missing = [m for m in render_corpus.REAL_MODELS if not (render_corpus.MODELS / m).is_file()]
    if missing:
        pytest.skip(f"models folder absent ({render_corpus.MODELS}): {', '.join(missing)}")
    assert any(k.startswith(render_corpus.REAL_MODELS[0]) for k in STORED)
