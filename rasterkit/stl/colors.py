"""Per-facet colours of a binary STL file, where the file really has them.

The 16-bit attribute word after each facet is "unused" in the format, but two conventions
store a colour in it, and a third of files use it for nothing (zero, or one value everywhere).
As the STL article of Wikipedia describes them (mirrored at
http://www.liquisearch.com/stl_file_format/color_in_binary_stl) and the table of
http://rpdrc.ic.polyu.edu.hk/old_files/stl_colour_binary_format.htm:

- **VisCAM / SolidView** (A. F. van der Geest's extension): bit 15 set means the facet has a
  colour, blue in bits 0-4, green in bits 5-9, red in bits 10-14 (0..31 each); bit 15 clear
  means no colour "as with normal STL files".
- **Materialise Magics**: the 80-byte header holds ``COLOR=`` and four bytes R, G, B, A
  (0..255), the colour of the whole part; a facet whose bit 15 is *clear* has its own colour,
  red in bits 0-4, green 5-9, blue 10-14 (the reverse order of VisCAM's); a facet whose bit
  15 is set takes the part's colour.

A generic reader cannot tell the two apart from the words alone; the header decides: with
``COLOR=`` the words are read as Magics', without it as VisCAM's. Then:

- Magics, every word zero: the words are filler (no tool that writes a part colour marks every
  facet black): every facet has the part's colour.
- VisCAM, no word with bit 15 set (all zero, one repeated value, or anything else without the
  bit): no colours at all. Some words with it: those facets have theirs, the others
  :data:`rasterkit.material.DEFAULT_DIFFUSE`, with a warning.

The alpha byte of ``COLOR=`` and the ``,MATERIAL=`` colours that may follow it are not used.
"""

from __future__ import annotations

import numpy as np

from rasterkit.material import DEFAULT_DIFFUSE

__all__ = ["face_colors", "part_color"]

_VALID = 0x8000


def part_color(header: bytes) -> np.ndarray | None:
    """(3,) float32 in [0, 1]: the R, G, B bytes after ``COLOR=`` in ``header`` (the 80 bytes),
    or None when there is none."""
    at = header.find(b"COLOR=")
    if at < 0 or at + 10 > len(header):
        return None
    return np.frombuffer(header, np.uint8, 3, at + 6).astype(np.float32) / np.float32(255)


def _channels(words: np.ndarray, first: int, last: int) -> np.ndarray:
    """(K, 3) float32: the 5-bit fields of ``words`` at bit 0, 5 and 10, as R, G, B with R the
    field ``first`` (0 or 2) and B the field ``last``."""
    fields = [(words >> shift) & 31 for shift in (0, 5, 10)]
    rgb = np.stack([fields[first], fields[1], fields[last]], axis=1)
    return rgb.astype(np.float32) / np.float32(31)


def face_colors(header: bytes, words: np.ndarray) -> tuple[np.ndarray | None, str | None]:
    """(F, 3) float32 colours in [0, 1] of facets whose attribute words are ``words`` (F,)
    uint16 in a file with ``header``, or None (see the module's rules); and a warning, or
    None."""
    words = np.asarray(words, np.uint16)
    part = part_color(header)
    if part is not None:  # Materialise Magics
        if not words.any():
            return np.repeat(part[None, :], len(words), axis=0), None
        own = (words & _VALID) == 0
        colors = np.repeat(part[None, :], len(words), axis=0)
        colors[own] = _channels(words[own], 0, 2)
        return colors, None
    valid = (words & _VALID) != 0
    if not valid.any():
        return None, None
    colors = np.repeat(np.asarray(DEFAULT_DIFFUSE, np.float32)[None, :], len(words), axis=0)
    colors[valid] = _channels(words[valid], 2, 0)
    note = None
    if not valid.all():
        note = (f"{np.count_nonzero(~valid)} of {len(words)} facets have no VisCAM colour (bit 15 of the "
                f"attribute word clear): they are drawn in the default colour")
    return colors, note
