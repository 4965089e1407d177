"""Checks of single option values, shared by :class:`rasterkit.RenderOptions` and :class:`rasterkit.View`.

Each check takes the option's ``name`` and ``value`` and returns the value in its one stored
form (a bool, an int, a float, a tuple), or raises ``TypeError`` for a value of the wrong
type and ``ValueError`` for one out of its range or choices, naming the option. NumPy scalars
count as the numbers they hold (NumPy registers them with :mod:`numbers`); a bool is not a
number. Pure standard library: the command line builds these records before NumPy loads.
"""

from __future__ import annotations

import math
import numbers

__all__ = ["choice", "colour", "flag", "non_negative", "optional", "point", "positive", "real", "size", "unit_interval", "whole"]


def _is_bool(value) -> bool:
    # numpy.bool_ without importing NumPy: named bool_ before NumPy 2, bool since
    kind = type(value)
    return isinstance(value, bool) or (kind.__name__ in ("bool_", "bool") and kind.__module__ == "numpy")


def flag(name: str, value) -> bool:
    """True or False (NumPy's too)."""
    if not _is_bool(value):
        raise TypeError(f"{name} must be True or False, got {type(value).__name__} {value!r}")
    return bool(value)


def real(name: str, value) -> float:
    """A finite real number, as a float."""
    if _is_bool(value) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number, got {type(value).__name__} {_short(value)}")
    if not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return float(value)


def whole(name: str, value, low: int, high: int | None = None) -> int:
    """A whole number from ``low`` (to ``high``), as an int."""
    if _is_bool(value) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be a whole number, got {type(value).__name__} {_short(value)}")
    if value < low or (high is not None and value > high):
        raise ValueError(f"{name} must be {low} to {high}, got {value!r}" if high is not None
                         else f"{name} must be at least {low}, got {value!r}")
    return int(value)


def positive(name: str, value) -> float:
    value = real(name, value)
    if value <= 0.0:
        raise ValueError(f"{name} must be positive, got {value!r}")
    return value


def non_negative(name: str, value) -> float:
    value = real(name, value)
    if value < 0.0:
        raise ValueError(f"{name} must be >= 0, got {value!r}")
    return value


def unit_interval(name: str, value) -> float:
    value = real(name, value)
    if not 0.0 <= value <= 1.0:
        raise ValueError(f"{name} must lie in [0, 1], got {value!r}")
    return value


def choice(name: str, value, choices: tuple):
    """One of ``choices`` (strings, or None)."""
    if value is not None and not isinstance(value, str):
        raise TypeError(f"{name} must be one of {', '.join(map(repr, choices))}, got {type(value).__name__}")
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, choices))}, got {value!r}")
    return value


def colour(name: str, value):
    """A colour as it is stored: a name or ``#rrggbb`` string as given, a tuple of ints
    (checked by :func:`rasterkit.colors.rgba`, which loads NumPy)."""
    from rasterkit.colors import rgba

    try:
        rgba(value)
    except (TypeError, ValueError) as e:
        raise type(e)(f"{name}: {e}") from None
    return value if isinstance(value, str) else tuple(int(c) for c in value)


def point(name: str, value) -> tuple[float, float, float]:
    """Three finite numbers ``(x, y, z)``, as a tuple of floats."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 3:
        raise TypeError(f"{name} must be a point (x, y, z), got {_short(value)}")
    return tuple(real(name, v) for v in value)


def size(name: str, value, largest: int) -> tuple[int, int]:
    """``(width, height)``, whole numbers 1 to ``largest``."""
    ok = isinstance(value, (tuple, list)) and len(value) == 2 and all(
        isinstance(v, numbers.Integral) and not _is_bool(v) and 1 <= v <= largest for v in value)
    if not ok:
        raise ValueError(f"{name} must be (width, height), whole numbers 1 to {largest}, got {_short(value)}")
    return tuple(int(v) for v in value)


def optional(check, name: str, value, *args):
    """None, or ``check(name, value, *args)``."""
    return None if value is None else check(name, value, *args)


def _short(value) -> str:
    text = " ".join(repr(value).split())
    return text if len(text) <= 60 else text[:57] + "..."
