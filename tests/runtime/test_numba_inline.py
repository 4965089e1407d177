"""rasterkit's changes to Numba's inliner (rasterkit.runtime.numba_inline) compile the same
functions: inlined callees used at many call sites, with different types and from callers
with different flags, give the results plain Python gives."""

import numba
import numpy as np
import pytest

import rasterkit.runtime.jit  # noqa: F401  (installs the inliner's changes)
from rasterkit.runtime import numba_inline as _numba_inline


def test_the_inliner_is_changed_once():
    from numba.core import inline_closurecall

    assert _numba_inline.install() is True
    first = inline_closurecall.InlineWorker.inline_ir
    assert _numba_inline.install() is True
    assert inline_closurecall.InlineWorker.inline_ir is first


def _tree():
    # fresh functions each time: nothing of another test's compiling is reused
    @numba.njit(inline="always")
    def leaf(a, b):
        if a > b:
            return a - b
        return b - a

    @numba.njit(inline="always")
    def middle(a, b, c):
        s = leaf(a, b) + leaf(b, c)
        for k in range(3):
            s += leaf(a + k, c)
        return s

    def outer(xs):
        total = xs[0] * 0
        for i in range(xs.size - 2):
            total += middle(xs[i], xs[i + 1], xs[i + 2]) + leaf(xs[i], xs[i + 2])
        return total

    return leaf, middle, outer


@pytest.mark.parametrize("dtype", [np.int64, np.float64, np.float32])
def test_callees_inlined_at_many_sites_compute_what_python_does(dtype):
    _, _, outer = _tree()
    xs = np.array([3, -1, 4, 1, -5, 9, 2, -6], dtype=dtype)
    expected = outer(xs)  # plain Python
    assert numba.njit(outer)(xs) == pytest.approx(expected)
    assert numba.njit(fastmath=True, _nrt=False)(outer)(xs) == pytest.approx(expected)


def test_one_callee_in_two_callers_of_different_types():
    leaf, middle, _ = _tree()

    @numba.njit
    def ints(a, b, c):
        return middle(a, b, c) * 10 + leaf(a, c)

    @numba.njit
    def floats(a, b, c):
        return middle(a, b, c) + leaf(c, b) / 2

    assert ints(1, 5, 2) == (4 + 3 + 1 + 0 + 1) * 10 + 1
    assert floats(1.5, 5.0, 2.0) == pytest.approx(3.5 + 3.0 + 0.5 + 0.5 + 1.5 + 1.5)
    assert ints(1, 5, 2) == (4 + 3 + 1 + 0 + 1) * 10 + 1  # again: the stored IR was not changed
