"""Fuzzing the OFF reader and the renders of what it reads (the oracle: ``fuzz_formats.check``).

Two sources of hostile files:

- **grammar**: Hypothesis draws OFF documents: every keyword (``OFF``, ``COFF``, ``NOFF``,
  ``STCNOFF``, ``nOFF`` with a dimension, ``4OFF``, ``OFF BINARY``, none, misspelt), counts on
  their own line, on the keyword's or glued to it, right or wrong; vertex lines of the right
  width or not, with colours as integers or floats; faces of 0 to 7 corners with indices in
  range or not and colours of 0 to 5 numbers; hostile numbers, comments, blank lines, CRLF;
- **mutations**: the public OFF files of ``../shared/models/formats/off`` and ``robustness/off``
  (where they are) and the grammar's first clean documents, mostly with tokens replaced by
  hostile ones and bytes flipped (the line count stays, so the file is read past its header),
  now and then with lines deleted, duplicated or swapped, or cut short.

Run by hand (a long run)::

    python tests/support/fuzz_off.py --grammar 20000 --mutations 20000 --seed 1 --failures /tmp/fuzz-off

The suite runs a short derandomized sample in a child process with a time and a memory limit
(``tests/off/test_fuzz_off.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

try:
    from . import fuzz_formats
except ImportError:  # run as a script
    import fuzz_formats

FORMATS = Path(__file__).resolve().parents[2].parent / "shared" / "models" / "formats"

HOSTILE_NUMBERS = ["nan", "inf", "-inf", "1e308", "1e309", "-0", "0x10", "1.#IND", "1e", ".", "--1", "1_0",
                   "9" * 40, "99999999999999999999", "-1", "1.5", "\u0661", ""]
KEYWORDS = ["OFF", "OFF", "OFF", "COFF", "NOFF", "CNOFF", "STOFF", "STCNOFF", "nOFF 3", "nOFF 4", "4OFF", "OFF BINARY",
            "", "", "XOFF", "off", "CCOFF"]


def strategies():
    """The Hypothesis strategy of OFF files (bytes)."""
    from hypothesis import strategies as st

    plain = st.one_of(st.floats(-10, 10, allow_nan=False).map(lambda x: f"{x:.6f}"), st.integers(-3, 3).map(str))
    numbers = st.one_of(plain, plain, st.floats().map(repr), st.sampled_from(HOSTILE_NUMBERS))
    colour = st.one_of(st.integers(0, 255).map(str), st.floats(0, 1).map(lambda x: f"{x:.3f}"), st.sampled_from(
        ["300", "-1", "nan", "1", "0"]))
    ends = st.sampled_from(["\n"] * 8 + ["\r\n", " # a comment\n", "\n\n", "\t\n"])

    @st.composite
    def document(draw):
        if draw(st.integers(0, 2)):  # a well-formed file: its body is read
            return draw(well_formed())
        keyword = draw(st.sampled_from(KEYWORDS))
        n_vertices = draw(st.integers(0, 8))
        n_faces = draw(st.integers(0, 6))
        said = (n_vertices if draw(st.integers(0, 5)) else draw(st.integers(0, 10**12)),
                n_faces if draw(st.integers(0, 5)) else draw(st.integers(0, 20)))
        counts = f"{said[0]} {said[1]}" + draw(st.sampled_from([" 0", " 12", ""]))
        where = draw(st.sampled_from(["line", "line", "same", "glued"])) if keyword else "line"
        text = draw(st.sampled_from(["", "# made by the fuzzer\n", "\n\n"]))
        text += {"line": f"{keyword}\n{counts}" if keyword else counts, "same": f"{keyword} {counts}",
                 "glued": f"{keyword}{counts}"}[where] + draw(ends)
        width = 3 + 3 * ("N" in keyword) + 2 * ("ST" in keyword)
        colours = "C" in keyword or draw(st.integers(0, 3)) == 0
        for _ in range(n_vertices):
            values = [draw(plain if draw(st.integers(0, 8)) else numbers) for _ in range(width)]
            if colours:
                values += [draw(colour) for _ in range(draw(st.sampled_from([3, 4, 3, 4, 2])))]
            if not draw(st.integers(0, 12)):
                values = values[:draw(st.integers(0, len(values)))]
            text += " ".join(values) + draw(ends)
        for _ in range(n_faces):
            size = draw(st.sampled_from([3, 3, 4, 4, 5, 6, 7, 2, 0]))
            index = st.integers(0, max(n_vertices - 1, 0)) if draw(st.integers(0, 8)) else st.integers(-2, 12)
            corners = [str(draw(index)) for _ in range(size)]
            said_size = size if draw(st.integers(0, 8)) else draw(st.sampled_from([size + 1, size - 1, 10**9]))
            extra = [draw(colour) for _ in range(draw(st.sampled_from([0, 0, 3, 4, 1, 2, 5])))]
            text += " ".join([str(said_size)] + corners + extra) + draw(ends)
        data = text.encode("utf-8", "surrogatepass")
        if draw(st.integers(0, 9)) == 0:
            at = draw(st.integers(0, len(data)))
            data = data[:at] + draw(st.binary(max_size=12)) + data[at:]
        return data

    @st.composite
    def well_formed(draw):
        keyword = draw(st.sampled_from(["OFF", "COFF", "NOFF", "CNOFF", "STOFF", "STCNOFF", ""]))
        n_vertices = draw(st.integers(3, 12))
        faces = draw(st.lists(st.lists(st.integers(0, n_vertices - 1), min_size=3, max_size=7), max_size=8))
        text = f"{keyword}\n{n_vertices} {len(faces)} 0\n" if keyword else f"{n_vertices} {len(faces)}\n"
        width = 3 + 3 * ("N" in keyword) + 2 * ("ST" in keyword) + 3 * ("C" in keyword)
        for _ in range(n_vertices):
            text += " ".join(draw(plain) for _ in range(width)) + draw(ends)
        coloured = draw(st.booleans())
        for face in faces:
            extra = [draw(colour) for _ in range(3)] if coloured else []
            text += " ".join(map(str, [len(face), *face, *extra])) + draw(ends)
        return text.encode()

    return document()


def sources() -> list[bytes]:
    files = sorted((FORMATS / "off").glob("*.off")) + sorted((FORMATS / "robustness" / "off").glob("*.off"))
    return [p.read_bytes() for p in files if p.is_file()]


HOSTILE_TOKENS = [t.encode("utf-8", "surrogatepass") for t in HOSTILE_NUMBERS] + [b"#", b"OFF", b"\x00", b"\xff",
                                                                                 b"3 0 1 2", b"1 2 3 4 5 6 7"]


def mutate(data: bytes, rng) -> bytes:
    """``data`` with 1-4 random mutations, mostly ones that keep the lines."""
    lines = data.split(b"\n")
    for _ in range(rng.randint(1, 4)):
        kind = rng.choice([0] * 5 + [1] * 3 + [2, 2, 3, 4, 5])
        i = rng.randrange(len(lines))
        if kind == 0:  # a hostile token in place of a token
            words = lines[i].split(b" ")
            words[rng.randrange(len(words))] = rng.choice(HOSTILE_TOKENS)
            lines[i] = b" ".join(words)
        elif kind == 1 and lines[i]:  # flip a byte
            line = bytearray(lines[i])
            line[rng.randrange(len(line))] = rng.randrange(256)
            lines[i] = bytes(line)
        elif kind == 2:  # swap two lines
            j = rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        elif kind == 3:  # duplicate a line
            lines.insert(rng.randrange(len(lines) + 1), lines[i])
        elif kind == 4:  # delete a line
            del lines[i]
            lines = lines or [b""]
        else:  # cut short
            lines = lines[:i + 1]
            lines[-1] = lines[-1][:rng.randrange(len(lines[-1]) + 1)]
    return b"\n".join(lines)


def read(path):
    from rasterkit.off import read_off

    return read_off(path)


FIRST = b"OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3 255 0 0\n"

if __name__ == "__main__":
    sys.exit(fuzz_formats.main(None, __doc__.split("\n\n")[0], ".off", read, strategies, sources, mutate, FIRST))
