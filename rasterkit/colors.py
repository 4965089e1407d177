"""Colour arguments: ``'#rrggbb'`` (or ``'#rgb'``, ``'#rrggbbaa'``), common names, or tuples.

:func:`rgba` checks one in pure Python (the command line's options are checked before NumPy
loads); :func:`parse_color` gives it as the array the kernels take."""

from __future__ import annotations

import math
import numbers
from typing import TYPE_CHECKING, Sequence, Union

if TYPE_CHECKING:
    import numpy as np

__all__ = ["ColorLike", "parse_color", "rgba", "NAMED_COLORS"]

ColorLike = Union[str, Sequence[int]]

NAMED_COLORS = {
    "black": (0, 0, 0), "white": (255, 255, 255), "red": (255, 0, 0), "green": (0, 128, 0),
    "lime": (0, 255, 0), "blue": (0, 0, 255), "yellow": (255, 255, 0), "cyan": (0, 255, 255),
    "magenta": (255, 0, 255), "gray": (128, 128, 128), "grey": (128, 128, 128),
    "lightgray": (211, 211, 211), "lightgrey": (211, 211, 211), "darkgray": (64, 64, 64),
    "darkgrey": (64, 64, 64), "orange": (255, 165, 0), "purple": (128, 0, 128),
    "brown": (139, 69, 19), "pink": (255, 192, 203), "navy": (0, 0, 128), "teal": (0, 128, 128),
    "olive": (128, 128, 0), "maroon": (128, 0, 0), "silver": (192, 192, 192),
    "gold": (255, 215, 0), "steelblue": (70, 130, 180), "skyblue": (135, 206, 235),
    "transparent": (0, 0, 0, 0),
}


def parse_color(value: ColorLike) -> np.ndarray:
    """A colour as a (4,) uint8 RGBA array (alpha 255 unless given).

    >>> parse_color('#ff8000').tolist(), parse_color('navy').tolist(), parse_color((1, 2, 3)).tolist()
    ([255, 128, 0, 255], [0, 0, 128, 255], [1, 2, 3, 255])
    """
    import numpy as np

    return np.array(rgba(value), np.uint8)


def rgba(value: ColorLike) -> tuple[int, int, int, int]:
    """A colour as a tuple ``(r, g, b, a)`` of 0-255 (alpha 255 unless given); ``ValueError``
    or ``TypeError`` saying why it is not one."""
    if isinstance(value, str):
        channels = _parse_string(value.strip().lower())
        if channels is None:
            raise ValueError(f"unknown colour {_short(value)}: use a name, #rrggbb, or (r, g, b)")
    else:
        try:
            parts = list(value)
        except TypeError:
            raise TypeError(f"a colour must be a name, '#rrggbb' or a tuple of 3 or 4 integers, "
                            f"got {type(value).__name__}") from None
        if len(parts) not in (3, 4):
            raise ValueError(f"a colour tuple must hold 3 or 4 integers 0-255, got {len(parts)} values")
        channels = tuple(_component(c) for c in parts)
    return (*channels, 255) if len(channels) == 3 else tuple(channels)


def _short(value) -> str:
    """``repr(value)`` on one line, cut to 40 characters."""
    text = " ".join(repr(value).split())
    return text if len(text) <= 40 else text[:37] + "..."


def _component(c) -> int:
    """One colour component: an integer 0-255 (an int, a NumPy integer, or a float with an
    integer value); a bool, a string or a fraction is refused rather than guessed at."""
    if isinstance(c, bool) or type(c).__name__ == "bool_" or not isinstance(c, (numbers.Integral, numbers.Real)):
        raise TypeError(f"colour components must be integers 0-255, got {type(c).__name__} {_short(c)}")
    if isinstance(c, numbers.Integral):
        value = int(c)
    elif math.isfinite(c) and float(c).is_integer():
        value = int(c)
    else:
        raise ValueError(f"colour components must be integers 0-255, got {_short(c)} "
                         "(for colours 0..1, multiply by 255)")
    if not 0 <= value <= 255:
        raise ValueError(f"colour components must be integers 0-255, got {value}")
    return value


def _parse_string(s: str):
    if s in NAMED_COLORS:
        return NAMED_COLORS[s]
    if not s.startswith("#"):
        return None
    digits = s[1:]
    if len(digits) in (3, 4):
        digits = "".join(c * 2 for c in digits)
    if len(digits) not in (6, 8):
        return None
    try:
        return tuple(int(digits[i:i + 2], 16) for i in range(0, len(digits), 2))
    except ValueError:
        return None
