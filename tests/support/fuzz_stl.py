"""Fuzzing the STL reader and the renders of what it reads (the oracle: ``fuzz_formats.check``).

Two sources of hostile files:

- **grammar**: Hypothesis draws ASCII documents (``solid`` blocks of facets with hostile
  numbers, keywords in any case or misspelt, tokens missing or doubled, odd whitespace and
  line breaks, blocks not closed, bytes spliced in) and binary files (headers with ``solid`` or
  ``COLOR=``, counts that are right or wrong, float32 corners that repeat, are NaN, infinite,
  huge or tiny, attribute words with and without bit 15);
- **mutations**: the public STL files of ``../shared/models/formats/stl`` and ``robustness/stl``
  (where they are) and the grammar's first clean documents, with bytes flipped, ranges deleted
  or duplicated, the count changed, or cut short.

Run by hand (a long run)::

    python tests/support/fuzz_stl.py --grammar 20000 --mutations 20000 --seed 1 --failures /tmp/fuzz-stl

The suite runs a short derandomized sample in a child process with a time and a memory limit
(``tests/stl/test_fuzz_stl.py``).
"""

from __future__ import annotations

import struct
import sys
from pathlib import Path

try:
    from . import fuzz_formats
except ImportError:  # run as a script
    import fuzz_formats

FORMATS = Path(__file__).resolve().parents[2].parent / "shared" / "models" / "formats"

HOSTILE_NUMBERS = ["nan", "-nan", "inf", "-Infinity", "1e308", "-1e308", "1e309", "1e-400", "-0", "0x10", "1.#IND",
                   "1e", ".", "-", "--1", "1..2", "1_0", "9" * 400, "0." + "0" * 300 + "1", "\u0661", "1,5", ""]
KEYWORDS = ["solid", "facet", "normal", "outer", "loop", "vertex", "endloop", "endfacet", "endsolid"]


def strategies():
    """The Hypothesis strategy of STL files (bytes)."""
    from hypothesis import strategies as st

    plain = st.one_of(st.floats(width=32, allow_nan=False, allow_infinity=False).map(repr),
                      st.integers(-3, 3).map(str), st.integers(-3, 3).map(str))
    numbers = st.one_of(plain, st.floats().map(repr), st.sampled_from(HOSTILE_NUMBERS))
    separators = st.sampled_from([" "] * 8 + ["\n"] * 4 + ["\r\n", "\t", "  ", "\x0b", "\x0c"])
    hostile_separators = st.sampled_from([" ", "\n", "\x00", "\xa0", "\x1c", "\u3000", "", "#"])
    keyword = st.one_of(st.sampled_from(KEYWORDS), st.sampled_from(KEYWORDS).map(str.upper),
                        st.sampled_from(["facett", "vertx", "endsolids", "", "solid"]))

    @st.composite
    def facet(draw):
        broken = draw(st.integers(0, 5)) == 0  # most facets are well formed: the file goes on
        number = numbers if broken else plain
        tokens = ["facet", "normal", *[draw(number) for _ in range(3)], "outer", "loop"]
        for _ in range(draw(st.sampled_from([3, 2, 4])) if broken else 3):
            tokens += ["vertex", *[draw(number) for _ in range(3)]]
        tokens += ["endloop", "endfacet"]
        for _ in range(draw(st.integers(0, 2)) if broken else 0):
            at = draw(st.integers(0, len(tokens) - 1))
            choice = draw(st.integers(0, 2))
            if choice == 0:
                del tokens[at]
            elif choice == 1:
                tokens.insert(at, draw(keyword))
            else:
                tokens[at] = draw(numbers)
        return "".join(t + draw(hostile_separators if broken else separators) for t in tokens)

    @st.composite
    def ascii_document(draw):
        text = ""
        for _ in range(draw(st.integers(0, 3))):
            name = draw(st.one_of(st.just(""), st.text(st.characters(blacklist_categories=("Cc", "Cs")), max_size=8),
                                  st.text(max_size=8)))
            text += draw(st.sampled_from(["solid", "SOLID", "solid"])) + (" " + name if name else "") + "\n"
            text += "".join(draw(st.lists(facet(), max_size=6)))
            if draw(st.integers(0, 5)):
                text += "endsolid" + (" " + name if draw(st.booleans()) else "") + draw(st.sampled_from(["\n", "", "\r\n"]))
        data = text.encode("utf-8", "surrogatepass")
        if draw(st.integers(0, 9)) == 0:
            at = draw(st.integers(0, len(data)))
            data = data[:at] + draw(st.binary(max_size=12)) + data[at:]
        return data

    corner = st.one_of(
        st.tuples(*[st.integers(-2, 2).map(float)] * 3),
        st.tuples(*[st.floats(width=32)] * 3),
    )

    @st.composite
    def binary_document(draw):
        facets = draw(st.lists(st.tuples(corner, corner, corner, corner, st.integers(0, 0xFFFF)), max_size=12))
        header = draw(st.sampled_from([b"", b"solid x", b"COLOR=\xff\x00\x80\xff", b"solid COLOR=\x10\x20\x30\xff"]))
        header += draw(st.binary(max_size=8))
        count = len(facets) if draw(st.integers(0, 4)) else draw(st.sampled_from([0, 1, len(facets) + 1, 2**32 - 1]))
        body = b"".join(struct.pack("<12fH", *[x for c in f[:4] for x in c], f[4]) for f in facets)
        return header.ljust(80, b" ")[:80] + struct.pack("<I", count) + body

    return st.one_of(ascii_document(), binary_document())


def sources() -> list[bytes]:
    files = sorted((FORMATS / "stl").glob("*")) + sorted((FORMATS / "robustness" / "stl").glob("*"))
    return [p.read_bytes() for p in files if p.is_file()]


def mutate(data: bytes, rng) -> bytes:
    """``data`` with 1-4 random mutations; a binary file's mostly keep its size (flipped
    bytes, another count), so that it is read further than its size check."""
    data = bytearray(data)
    binary = len(data) >= 84 and 84 + 50 * struct.unpack("<I", data[80:84])[0] == len(data)
    for _ in range(rng.randint(1, 4)):
        kind = rng.choice([0] * 12 + [3, 1, 2, 4] if binary else [0, 1, 2, 4, 5, 5, 5])
        at = rng.randrange(len(data) + 1)
        if kind == 0 and data:  # flip bytes
            for _ in range(rng.randint(1, 8)):
                data[rng.randrange(len(data))] = rng.randrange(256)
        elif kind == 1:  # delete a range
            del data[at:at + rng.randint(1, 200)]
        elif kind == 2:  # duplicate a range
            data[at:at] = data[at:at + rng.randint(1, 200)]
        elif kind == 3 and len(data) >= 84:  # another facet count
            data[80:84] = struct.pack("<I", rng.choice([0, 1, rng.randrange(2**32), (len(data) - 84) // 50 + 1]))
        elif kind == 4:  # cut short
            del data[at:]
        else:  # a hostile token or keyword in the text
            token = rng.choice(HOSTILE_NUMBERS + KEYWORDS).encode("utf-8", "surrogatepass")
            data[at:at] = b" " + token + b" "
    return bytes(data)


def read(path):
    from rasterkit.stl import read_stl

    return read_stl(path)


FIRST = (b"solid t\nfacet normal 0 0 1 outer loop vertex 0 0 0 vertex 1 0 0 vertex 0 1 0 endloop endfacet\n"
         b"endsolid t\n")

if __name__ == "__main__":
    sys.exit(fuzz_formats.main(None, __doc__.split("\n\n")[0], ".stl", read, strategies, sources, mutate, FIRST))
