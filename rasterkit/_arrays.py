"""What the public functions accept as numbers: checked conversion of their arguments.

An argument that stands for numbers (vertices, colours, points, matrices, camera vectors)
must hold real numbers: NumPy integers or floats, or lists of Python ints and floats.
Booleans, complex numbers, strings, dates and objects (``None`` among them) are refused with
a ``TypeError`` that names the argument and the dtype, instead of being converted on the
quiet (``np.asarray(x, float)`` turns ``"1"`` into 1.0, ``True`` into 1.0 and ``None`` into
NaN, and drops imaginary parts). Messages describe a value by its shape and dtype, never
by printing it: an error stays one line whatever was passed.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["describe", "real_array", "unit_vector"]

#: dtype kinds of real numbers: signed and unsigned integers, floats.
REAL_KINDS = "iuf"


def describe(value) -> str:
    """A short, one-line description of ``value`` for an error message: a few numbers as
    they are, anything larger by its type, shape and dtype."""
    if isinstance(value, (int, float, np.number, bool, np.bool_)) or value is None:
        return repr(value)
    if isinstance(value, str):
        return repr(value) if len(value) <= 40 else f"a string of {len(value)} characters"
    try:
        a = np.asarray(value)
    except Exception:  # noqa: BLE001 - anything NumPy cannot take: its type will do
        return type(value).__name__
    if a.dtype.kind in REAL_KINDS + "b" and a.size <= 4 and a.ndim <= 1:
        return "(" + ", ".join(f"{x:g}" if a.dtype.kind == "f" else str(x) for x in a.tolist()) + ")"
    return f"{type(value).__name__} of shape {a.shape} and dtype {a.dtype}"


def real_array(value, name: str, dtype=np.float64) -> np.ndarray:
    """``value`` as an array of ``dtype`` (a view when it already is one).

    Raises ``TypeError`` (naming ``name``) unless ``value`` holds real numbers, and
    ``ValueError`` when it is ragged (lists of unequal lengths).
    """
    if value is None:
        raise TypeError(f"{name} must be an array of numbers, got None")
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be an array of numbers, got a {type(value).__name__}")
    try:
        a = np.asarray(value)
    except (ValueError, TypeError):  # ragged nested lists, or objects NumPy refuses
        raise ValueError(f"{name} must be a rectangular array of numbers (rows of equal length)") from None
    if a.dtype.kind not in REAL_KINDS:
        raise TypeError(f"{name} must hold real numbers (integers or floats), got dtype {a.dtype}")
    return a.astype(dtype, copy=False)


def unit_vector(value, name: str) -> np.ndarray:
    """``value``, three finite numbers not all zero, scaled to unit length (3,) float64.

    The length is taken after dividing by the largest component, so neither a tiny vector
    (1e-320) nor a huge one (1e308) loses its direction to underflow or overflow."""
    v = real_array(value, name)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be 3 finite numbers, got {describe(value)}")
    largest = float(np.max(np.abs(v)))
    if largest == 0.0:
        raise ValueError(f"{name} must not be the zero vector")
    scaled = v / largest
    return scaled / math.hypot(*scaled)
