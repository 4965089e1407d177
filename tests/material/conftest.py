"""Fixtures of the material tests."""

from __future__ import annotations

import pytest

from support.paths import ROOT


@pytest.fixture(scope="module")
def gl():
    """Textured frames on Mesa llvmpipe (benchmarks/texture_peer.py), skipped without moderngl."""
    pytest.importorskip("moderngl")
    with pytest.MonkeyPatch.context() as patch:
        patch.syspath_prepend(str(ROOT))  # the benchmark suite is not installed with the package
        from benchmarks.peers import Llvmpipe, PeerUnavailable
        from benchmarks.texture_peer import TexturedGL

        try:
            yield TexturedGL(Llvmpipe())
        except PeerUnavailable as why:
            pytest.skip(str(why))
