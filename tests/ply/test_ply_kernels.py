"""The PLY reader's kernels against slow, obvious Python: numbers against ``float``, walks of
rows against a loop over ``struct``."""

import struct

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rasterkit.ply.kernels.rows import WALKED, copy_runs, walk_binary, walk_tokens
from rasterkit.ply.kernels.tokens import OK, OTHER, count_tokens, parse_tokens

decimals = st.builds(
    lambda sign, whole, fraction, exponent: f"{sign}{whole}{fraction}{exponent}",
    st.sampled_from(["", "-", "+"]), st.text("0123456789", max_size=22),
    st.one_of(st.just(""), st.text("0123456789", max_size=22).map(lambda d: "." + d)),
    st.one_of(st.just(""), st.builds(lambda e, s, d: f"{e}{s}{d}", st.sampled_from("eE"),
                                     st.sampled_from(["", "-", "+"]), st.integers(0, 400))))


def parse(texts, separator=" "):
    data = separator.join(texts).encode()
    buf = np.frombuffer(data, np.uint8)
    n = count_tokens(buf, 0)
    assert n == len(texts)
    return parse_tokens(buf, 0, n)


@settings(max_examples=400, deadline=None)
@given(st.lists(decimals.filter(lambda t: any(c.isdigit() for c in t.split("e")[0].split("E")[0])), min_size=1,
                max_size=20))
def test_any_decimal_text_reads_as_pythons_float(texts):
    values, status = parse(texts, " \t\n")
    for text, value, state in zip(texts, values, status):
        if state == OK:
            assert value == float(text) and np.signbit(value) == np.signbit(float(text)), text
        else:
            assert state != OTHER, text  # a number: exact or left to Python, never refused


@pytest.mark.parametrize("text", ["nan", "inf", "1.#IND", "1e", "e5", ".", "-", "1.2.3", "0x10", "1,5", "1e+", "\xa0"])
def test_what_is_no_plain_decimal_is_left_to_the_caller(text):
    values, status = parse(["1", text, "2"])
    assert status.tolist() == [OK, OTHER, OK] and values[[0, 2]].tolist() == [1, 2]


def test_numbers_as_writers_print_floats_need_no_second_reading():
    """%g and %.9g (a float32 to the bit) are read by the kernel; 17 digits (a double's repr)
    need more than one rounding and are left to NumPy."""
    values = np.random.default_rng(1).standard_normal(2000) * 10.0 ** np.arange(-10, 10).repeat(100)
    texts = [f"{v:.6g}" for v in values] + [f"{v:.9g}" for v in values] + [f"{v:.6f}" for v in values]
    parsed, status = parse(texts)
    assert (status == OK).all()
    assert parsed.tolist() == [float(t) for t in texts]


def slow_walk(data: bytes, start: int, n: int, layout):
    """Row starts and counts by struct: layout is [("fixed", size) | ("list", code, item size)]."""
    starts, counts, at = [], [], start
    for _ in range(n):
        starts.append(at)
        row = []
        for part in layout:
            if part[0] == "fixed":
                at += part[1]
            else:
                size = struct.calcsize(part[1])
                (c,) = struct.unpack_from("<" + part[1], data, at)
                row.append(c)
                at += size + c * part[2]
        counts.append(row)
    return starts, counts, at


@settings(max_examples=200, deadline=None)
@given(st.data())
def test_the_binary_walk_is_a_loop_over_rows(data):
    layout = data.draw(st.lists(st.one_of(st.tuples(st.just("fixed"), st.integers(1, 9)),
                                          st.tuples(st.just("list"), st.sampled_from("BbHhIi"),
                                                    st.sampled_from([1, 2, 4, 8]))), min_size=1, max_size=5))
    if not any(p[0] == "list" for p in layout):
        layout.append(("list", "B", 4))
    rows = data.draw(st.integers(0, 20))
    prefix = data.draw(st.integers(0, 5))
    body = bytearray(b"\x07" * prefix)  # bytes before the element
    for _ in range(rows):
        for part in layout:
            if part[0] == "fixed":
                body += bytes(part[1])
            else:
                c = data.draw(st.integers(0, 5))
                body += struct.pack("<" + part[1], c) + bytes(c * part[2])
    segments, sizes, signed, items = [0], [], [], []
    for part in layout:
        if part[0] == "fixed":
            segments[-1] += part[1]
        else:
            segments.append(0)
            sizes.append(struct.calcsize(part[1]))
            signed.append(part[1].islower())
            items.append(part[2])
    buf = np.frombuffer(bytes(body), np.uint8)
    starts, counts, status, row, j, at, value = walk_binary(
        buf, prefix, rows, np.array(segments), np.array(sizes, np.int64), np.array(signed), np.array(items, np.int64),
        False)
    assert status == WALKED and row == -1 and at == len(body)
    want_starts, want_counts, _ = slow_walk(bytes(body), prefix, rows, layout)
    assert starts.tolist() == want_starts and counts.tolist() == want_counts


def test_the_token_walk_and_copying_runs():
    values = np.array([7, 3, 0, 1, 2, 9, 0, 9, 2, 5, 6, 9], np.float64)  # rows: scalar, list, scalar
    starts, counts, status, row, j, at, _ = walk_tokens(values, 1, 3, np.array([0, 1]))
    assert status == WALKED and starts.tolist() == [1, 6, 8] and counts.tolist() == [[3], [0], [2]] and at == 12
    assert copy_runs(values, starts + 1, counts[:, 0]).tolist() == [0, 1, 2, 5, 6]
    _, _, status, row, j, at, _ = walk_tokens(values[:11], 1, 3, np.array([0, 1]))
    assert (row, j) == (2, 1)  # row 2's scalar after its list is missing


@pytest.mark.parametrize("dtype", ["<i1", "<u1", "<i2", "<u2", "<i4", "<u4", "<i8"])
@pytest.mark.parametrize("k", [1, 3, 4])
def test_widen_copies_unaligned_strided_indices_and_finds_their_range(dtype, k):
    from rasterkit.ply.kernels.indices import widen

    rng = np.random.default_rng(k)
    size = np.dtype(dtype).itemsize
    n = 257
    info = np.iinfo(np.dtype(dtype))
    values = rng.integers(max(info.min, -2**40), min(info.max, 2**40), (n, k), endpoint=True).astype(dtype)
    stride = 1 + k * size  # a count byte before each row: unaligned rows, as in a binary file
    raw = bytearray(1 + n * stride)
    for i in range(n):
        raw[1 + i * stride + 1:1 + (i + 1) * stride] = values[i].tobytes()
    view = np.ndarray((n, k), dtype, buffer=raw, offset=2, strides=(stride, size))
    np.testing.assert_array_equal(view, values)
    out = np.empty((n, k), np.int64)
    lo, hi = widen(view, out)
    np.testing.assert_array_equal(out, values.astype(np.int64))
    assert (lo, hi) == (int(values.min()), int(values.max()))
    assert widen(view[:0], out[:0]) == (0, -1)
