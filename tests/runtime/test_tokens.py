"""rasterkit.runtime.tokens against Python: the tokens of any bytes are ``bytes.split()``'s, a
number token converts as Python's ``float`` does (and what it refuses, or what the module's
rules leave out, is a BadToken at the right place), integers as ``int``."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from rasterkit.runtime.tokens import BadToken, floats, integers, shown, tokenize


def tokens_of(data: bytes):
    return tokenize(np.frombuffer(data, np.uint8))


@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.binary(max_size=60))
def test_the_tokens_of_any_bytes_are_bytes_split(data):
    tokens = tokens_of(data)
    assert [tokens.raw(k) for k in range(len(tokens))] == data.split()


def test_a_range_of_the_text():
    tokens = tokenize(np.frombuffer(b"ab cd ef", np.uint8), 1, 7)
    assert [tokens.raw(k) for k in range(len(tokens))] == [b"b", b"cd", b"e"]
    assert tokens.starts.tolist() == [1, 3, 6]


number_texts = st.one_of(
    st.floats(allow_nan=False).map(repr),
    st.floats(width=32, allow_nan=False).map(lambda x: f"{x:e}"),
    st.integers(-10**30, 10**30).map(str),
    st.tuples(st.integers(0, 10**20), st.integers(0, 10**20), st.integers(-400, 400)).map(lambda t: f"{t[0]}.{t[1]}e{t[2]}"),
    st.sampled_from(["nan", "-NaN", "inf", "-Infinity", "+.5", "5.", "1E+02", "0" * 50 + "1", "1" * 300]),
)


@settings(max_examples=400, deadline=None, derandomize=True)
@given(st.lists(number_texts, min_size=1, max_size=8))
def test_floats_read_numbers_as_python(texts):
    tokens = tokens_of(" ".join(texts).encode())
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # 1e400 is inf without a warning
        values = floats(tokens, np.arange(len(texts)))
    expected = np.array([float(t) for t in texts])
    assert np.array_equal(values, expected, equal_nan=True)


@pytest.mark.parametrize("bad", ["x", "1_0", "0x10", "1.#IND", "1,5", "--1", "1e", ".", "1\x00", "\x001", "1..2",
                                 "nan(1)", "١", "1e5e5", "in", "infinit"])
def test_floats_name_the_first_token_that_is_no_number(bad):
    tokens = tokens_of(f"1 2.5 {bad} 3 y".encode())
    with pytest.raises(BadToken) as info:
        floats(tokens, np.arange(5), "a coordinate")
    assert info.value.index == 2 and info.value.reason == f"expected a coordinate, got {bad!r}"


def test_floats_of_long_tokens_one_by_one():
    tokens = tokens_of(b"1" * 100 + b" 2 " + b"9" * 500 + b"x")
    assert floats(tokens, [0, 1])[0] == float("1" * 100)
    with pytest.raises(BadToken) as info:
        floats(tokens, [0, 1, 2])
    assert info.value.index == 2 and info.value.reason.endswith("...")


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.lists(st.integers(-(10**18) + 1, 10**18 - 1), min_size=1, max_size=8))
def test_integers_read_as_python(values):
    tokens = tokens_of(" ".join(map(str, values)).encode())
    assert integers(tokens, np.arange(len(values))).tolist() == values


@pytest.mark.parametrize("bad", ["1.0", "1e3", "+", "-", "1_000", "0x1", "1" * 19, "٣", "1-"])
def test_integers_refuse_the_rest(bad):
    tokens = tokens_of(f"7 {bad}".encode())
    with pytest.raises(BadToken) as info:
        integers(tokens, [0, 1], "an index")
    assert info.value.index == 1 and info.value.reason == f"expected an index, got {bad!r}"


def test_shown_is_one_line():
    assert shown(b"a\nb") == "'a\\nb'" and shown(b"\xff") == "'ÿ'" and shown("é".encode()) == "'é'"
