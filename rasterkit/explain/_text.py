"""Compact, aligned numbers for ``rasterkit explain``: scalars, tuples and matrix columns.

Plain ASCII, so the text reads the same in any terminal and any encoding.
"""

from __future__ import annotations

import math
import textwrap
from typing import Sequence

import numpy as np

#: Significant digits of every printed number.
DIGITS = 6

#: Width of the prose lines (grids, matrices and tables are as wide as they need).
WIDTH = 96


def wrap(text: str, indent: str = "", more: str = "   ") -> list[str]:
    """``text`` as lines of at most :data:`WIDTH` characters; the lines after the first are
    indented by ``more`` beyond ``indent``."""
    return textwrap.wrap(text, WIDTH, initial_indent=indent, subsequent_indent=indent + more,
                         break_on_hyphens=False, break_long_words=False)


def num(value: float) -> str:
    """``value`` with :data:`DIGITS` significant digits, no trailing zeros, no ``-0``.

    >>> num(0.1 + 0.2), num(-0.0), num(400.0), num(1e-9)
    ('0.3', '0', '400', '1e-09')
    """
    value = float(value)
    if value == 0.0:
        return "0"
    if not math.isfinite(value):
        return str(value)
    return f"{value:.{DIGITS}g}"


def tuple_text(values: Sequence[float]) -> str:
    """``(a, b, c)`` with :func:`num`."""
    return "(" + ", ".join(num(v) for v in values) + ")"


def _cleaned(values: np.ndarray) -> np.ndarray:
    """``values`` with rounding dust set to 0: entries below 1e-12 of the largest one.

    A rotation of whole degrees leaves entries like 6e-17 where the exact matrix has 0;
    printed, they would hide the structure of the matrix.
    """
    values = np.asarray(values, np.float64)
    finite = np.abs(values[np.isfinite(values)])
    if finite.size == 0:
        return values
    return np.where(np.abs(values) < 1e-12 * finite.max(), 0.0, values)


def column_texts(values: np.ndarray) -> list[list[str]]:
    """The entries of a (rows, cols) array as strings, each column right-aligned to one width."""
    values = np.atleast_2d(_cleaned(values))
    texts = [[num(v) for v in row] for row in values]
    widths = [max(len(row[j]) for row in texts) for j in range(values.shape[1])]
    return [[t.rjust(w) for t, w in zip(row, widths)] for row in texts]


def bracketed(values: np.ndarray) -> list[str]:
    """The rows of a matrix, or of a vector as a column, each as ``| a  b  c |``."""
    values = np.asarray(values, np.float64)
    if values.ndim == 1:
        values = values[:, None]
    return ["| " + "  ".join(row) + " |" for row in column_texts(values)]


def side_by_side(blocks: Sequence[list[str]], separators: Sequence[str], middle: int) -> list[str]:
    """Blocks of lines of equal count next to each other.

    ``separators[k]`` (e.g. ``" * "``) stands between block k and block k + 1 on line
    ``middle``, and as many spaces on the other lines.
    """
    lines = []
    for i in range(len(blocks[0])):
        parts = [blocks[0][i]]
        for sep, block in zip(separators, blocks[1:]):
            parts.append(sep if i == middle else " " * len(sep))
            parts.append(block[i])
        lines.append("".join(parts))
    return lines
