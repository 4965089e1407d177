"""rasterkit.runtime.decimal against Python's float: every number parse_decimal calls exact
(NUMBER_OK) and every one exact_decimals is sure of is the correctly rounded double of its
text, on the edges of float64 (subnormals, the largest double, halfway cases, 17 to 19 digits)
and on many random texts; what they cannot round for sure they say so, and what is no plain
decimal is NUMBER_OTHER."""

import random
import struct

import numpy as np
import pytest

from rasterkit.runtime.decimal import NUMBER_INEXACT, NUMBER_OK, NUMBER_OTHER, exact_decimals, parse_decimal


def parse(text: str):
    buf = np.frombuffer(text.encode(), np.uint8)
    return parse_decimal(buf, 0, len(buf))


def exact(texts: list) -> tuple:
    """exact_decimals of ``texts``: (values, sure)."""
    data = " ".join(texts).encode()
    ends = np.cumsum([len(t.encode()) + 1 for t in texts]) - 1
    starts = ends - [len(t.encode()) for t in texts]
    out = np.full(len(texts), np.nan)
    sure = exact_decimals(np.frombuffer(data, np.uint8), starts, ends, out)
    return out, sure


EDGES = ["0.30000000000000004", "1.7976931348623157e308", "1.7976931348623158e308", "1.7976931348623159e308",
         "4.9406564584124654e-324", "2.4703282292062328e-324", "2.4703282292062327e-324", "2.2250738585072011e-308",
         "2.2250738585072014e-308", "9007199254740993", "9007199254740995", "1e23", "8.98846567431158e307",
         "123456789012345678", "9999999999999999999", "1e-400", "1e400", "-0", "0.000", "7.2057594037927933e16",
         "5e-324", "1e-342", "1e308", "18446744073709551615"]


@pytest.mark.parametrize("text", EDGES)
def test_the_edges_of_float64(text):
    value, status = parse(text)
    assert status in (NUMBER_OK, NUMBER_INEXACT)
    if status == NUMBER_OK:
        assert value == float(text) and np.signbit(value) == np.signbit(float(text))
    (value,), (sure,) = exact([text])
    assert sure == (len(text.lstrip("-").replace(".", "").split("e")[0].lstrip("0")) <= 19)
    if sure:
        assert value == float(text) and np.signbit(value) == np.signbit(float(text))


def random_texts(rng, n):
    for _ in range(n):
        kind = rng.randrange(4)
        if kind == 0:  # the shortest repr of any double
            x = struct.unpack("<d", struct.pack("<Q", rng.getrandbits(64)))[0]
            if np.isfinite(x):
                yield repr(x)
        elif kind == 1:  # 1 to 19 digits, any exponent
            digits = rng.randint(1, 19)
            yield f"{rng.randrange(10 ** (digits - 1), 10 ** digits)}e{rng.randint(-360, 320)}"
        elif kind == 2:  # a float32 as %e (what CAD writers write)
            x = struct.unpack("<f", struct.pack("<I", rng.getrandbits(32)))[0]
            if np.isfinite(x):
                yield f"{x:e}"
        else:  # integers past 2**53, where halfway cases are
            yield str(rng.randrange(2**53, 10**19))


def test_random_texts_read_as_pythons_float():
    texts = list(random_texts(random.Random(7), 30_000))
    values, sure = exact(texts)
    assert sure.mean() > 0.999  # up to 19 digits Eisel-Lemire is nearly always sure
    for text, value, ok in zip(texts, values.tolist(), sure.tolist()):
        if ok:
            assert value == float(text), text
        fast, status = parse(text)
        if status == NUMBER_OK:
            assert fast == float(text), text


def test_more_than_19_digits_or_no_plain_decimal():
    assert parse("1.00000000000000000001")[1] == NUMBER_INEXACT
    assert parse("12345678901234567890123")[1] == NUMBER_INEXACT
    assert exact(["1.00000000000000000001", "12345678901234567890123", "nan", "1x"])[1].tolist() == [False] * 4
    for text in ["nan", "inf", "1e", ".", "1x", "--1", "0x10"]:
        assert parse(text)[1] == NUMBER_OTHER, text
