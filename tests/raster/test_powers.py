"""The library-free powers of :mod:`rasterkit.raster.kernels.powers` against NumPy's."""

import numpy as np
import pytest

from rasterkit.raster.kernels import lit_columns as rows
from rasterkit.raster.kernels.powers import exp2, log2, power
from rasterkit.runtime.jit import kernel


@kernel
def _powers(x, s):
    out = np.empty_like(x)
    for k in range(x.size):
        out[k] = power(x[k], s)
    return out


@kernel
def _logs_and_exps(x, y):
    logs, exps = np.empty_like(x), np.empty_like(y)
    for k in range(x.size):
        logs[k] = log2(x[k])
    for k in range(y.size):
        exps[k] = exp2(y[k])
    return logs, exps


def test_log2_and_exp2_agree_with_numpy_over_their_range():
    rng = np.random.default_rng(3)
    x = np.concatenate([rng.random(20000), 10.0 ** rng.uniform(-300, 300, 20000), [1.0, 2.0, 0.5, np.sqrt(2.0)]])
    y = np.concatenate([rng.uniform(-1000, 1000, 20000), rng.uniform(-2, 2, 20000), [0.0, 1.0, -1.0, 0.5]])
    logs, exps = _logs_and_exps(x, y)
    np.testing.assert_allclose(logs, np.log2(x), rtol=0, atol=2e-9)
    np.testing.assert_allclose(exps, np.exp2(y), rtol=2e-8, atol=0)


@pytest.mark.parametrize("s", [0.0, 0.5, 1.0, 2.4, 1 / 2.4, 8.0, 32.0, 128.0, 1000.0])
def test_power_agrees_with_numpy_for_a_highlights_arguments(s):
    rng = np.random.default_rng(7)
    x = np.concatenate([rng.random(50000), [0.0, 1.0, 1e-300, 0.999999]])
    got = _powers(x, s)
    want = x ** s
    # log2's error, times s, is the result's relative error (an 8-bit colour needs 1e-3)
    np.testing.assert_allclose(got, want, rtol=2e-8 + 2e-9 * s, atol=1e-300)
    assert got[-4] == (1.0 if s == 0.0 else 0.0)  # Python's 0 ** 0 and 0 ** s


def test_exp2_clamps_its_argument_instead_of_overflowing_and_reads_nan_as_its_lower_limit():
    _, exps = _logs_and_exps(np.ones(1), np.array([-5000.0, 5000.0, np.nan]))
    assert exps[0] == 2.0 ** -1020 and exps[1] == 2.0 ** 1020
    assert exps[2] == 2.0 ** -1020  # a NaN highlight is selected away by the caller: no NaN escapes


@kernel
def _chunk_highlights(ndh, shininess):
    """The lit rows' highlights of one chunk: ``ndh`` raised to ``shininess`` (CHUNK values each)."""
    s = np.zeros(rows.FIELDS * rows.CHUNK)
    n = ndh.size
    for q in range(n):
        s[rows.NDH + np.uint64(q)] = ndh[q]
        s[rows.SHINE + np.uint64(q)] = shininess[q]
    whole = rows.whole_exponent(s, n)
    rows.highlights(s, n, whole)
    out = np.empty(n)
    for q in range(n):
        out[q] = s[rows.POWER + np.uint64(q)]
    return whole, out


@pytest.mark.parametrize("k", [0.0, 1.0, 2.0, 3.0, 5.0, 32.0, 255.0, 1000.0, 65535.0])
def test_a_chunk_of_one_whole_shininess_is_raised_by_squarings_to_the_last_few_places(k):
    rng = np.random.default_rng(int(k))
    x = np.concatenate([rng.random(rows.CHUNK - 4), [0.0, 1.0, 0.999999, 0.5]])
    whole, out = _chunk_highlights(x, np.full(rows.CHUNK, k))
    assert whole == k
    np.testing.assert_allclose(out, x ** k, rtol=1e-13, atol=1e-300)


@pytest.mark.parametrize("shininess", [[32.0] * 63 + [16.0], [32.5] * 64, [65536.0] * 64, [-1.0] * 64])
def test_mixed_fractional_or_huge_shininess_goes_through_the_polynomial_power(shininess):
    rng = np.random.default_rng(5)
    x = rng.random(64)
    s = np.array(shininess)
    whole, out = _chunk_highlights(x, s)
    assert whole == -1.0
    np.testing.assert_array_equal(out, [_powers(np.array([v]), e)[0] for v, e in zip(x, s)])
