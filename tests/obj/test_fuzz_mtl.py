"""The fuzz run of ``tests/support/fuzz_mtl.py`` in CI: a fixed sample of random ``.mtl``
libraries naming mutated PNG, JPEG, TGA and BMP files, in a child process with a time and a
memory limit, so that a crash or a hang fails this test instead of the session."""

import sys

from support import fuzz_mtl
from support.hostile import run

FUZZ = fuzz_mtl.__file__  # run as a script, as by hand


def test_fuzz_sample_ends_cleanly(tmp_path):
    outcome = run([sys.executable, FUZZ, "--cases", "600", "--seed", "3", "--failures", tmp_path / "failures",
                   "--example-seconds", "60"], timeout=600)
    assert outcome.code == 0 and not outcome.timed_out, outcome.describe() + outcome.stdout[-3000:]
    summary = outcome.stdout.strip().splitlines()[-1]
    assert summary.endswith(" 0 failures"), summary
    assert not (tmp_path / "failures").exists()


def test_the_oracle_judges_errors(tmp_path, monkeypatch):
    """The oracle itself: a clean case passes; an exception from the reader, a warning of
    several lines and a texture error that does not name its file are failures."""
    import random

    import pytest

    import rasterkit.obj.materials as materials
    from rasterkit.material import Texture, TextureError

    fuzz_mtl.write_case(tmp_path / "case", random.Random(0))
    assert set(fuzz_mtl.check(tmp_path / "case")) >= {"materials", "opened"}

    def two_lines(libraries, report):
        report.warnings.append("m.mtl:1: a\nb")
        return {}

    for replacement, verdict in [(lambda libraries, report: {}[0], "KeyError"), (two_lines, "several lines")]:
        monkeypatch.setattr(materials, "make_materials", replacement)
        with pytest.raises(fuzz_mtl.Failure, match=verdict):
            fuzz_mtl.check(tmp_path / "case")
    monkeypatch.undo()

    def nameless(cls, path, **settings):
        raise TextureError("elsewhere.png", "bad")

    monkeypatch.setattr(Texture, "open", classmethod(nameless))
    with pytest.raises(fuzz_mtl.Failure, match="naming the file"):
        fuzz_mtl.check(tmp_path / "case")
