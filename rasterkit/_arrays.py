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
import numbers

import numpy as np

__all__ = ["describe", "finite_bounds", "length", "real_array", "real_number", "unit", "unit_vector"]

#: dtype kinds of real numbers: signed and unsigned integers, floats.
REAL_KINDS = "iuf"


def describe(value) -> str:
    """A short, one-line description of ``value`` for an error message: a few numbers as
    they are, anything larger by its type, shape and dtype."""
    if isinstance(value, numbers.Integral) and not -10**15 < value < 10**15:
        return f"an integer of {len(str(abs(int(value))))} digits"
    if isinstance(value, (numbers.Number, np.number, np.bool_)) or value is None:
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
    """``value`` as an array of ``dtype`` (a view when it already is one; ``dtype=None``
    keeps the dtype it has).

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
    return a if dtype is None else a.astype(dtype, copy=False)


def real_number(value, name: str) -> float:
    """``value`` as a float; ``TypeError`` (naming ``name``) unless it is a real number: an
    int, a float, a NumPy integer or float, or a 0-d array of one (not a bool, a string,
    a complex number or None)."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in REAL_KINDS:
        return float(value)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__} {describe(value)}")
    return float(value)


def unit_vector(value, name: str) -> np.ndarray:
    """``value``, three finite numbers not all zero, scaled to unit length (3,) float64.

    The length is taken after dividing by the largest component, so neither a tiny vector
    (1e-320) nor a huge one (1e308) loses its direction to underflow or overflow."""
    v = real_array(value, name)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be 3 finite numbers, got {describe(value)}")
    return unit(v, name)


def finite_bounds(points: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """``(low, high)``, the corners (3,) of the bounding box of the finite rows of ``points``
    (N, 3) float; None when no row is finite. Reduced over the columns made contiguous:
    NumPy's ``min(axis=0)`` over rows of three is some 30x slower (4.7 against 0.15 ms for
    36k points), and only a box with a value that is not finite needs the rows filtered."""
    if not len(points):
        return None
    columns = np.ascontiguousarray(points.T)
    low, high = columns.min(axis=1), columns.max(axis=1)
    if np.isfinite(low).all() and np.isfinite(high).all():
        return low, high
    finite = points[np.isfinite(points).all(axis=1)]  # (rare: filtered only then)
    return (finite.min(axis=0), finite.max(axis=0)) if len(finite) else None


def length(v: np.ndarray) -> float:
    """The Euclidean length of the (3,) float64 vector ``v``: ``np.linalg.norm(v)``, or,
    where its squares would underflow or overflow, the length found after dividing by the
    largest component (inf only when the length itself is beyond float64)."""
    with np.errstate(over="ignore", under="ignore"):
        n = float(np.linalg.norm(v))
        if 1e-150 < n < 1e150:
            return n
        largest = float(np.max(np.abs(v)))
        if largest == 0.0 or not math.isfinite(largest):
            return largest
        return largest * math.hypot(*(v / largest))


def unit(v: np.ndarray, name: str) -> np.ndarray:
    """The finite (3,) float64 vector ``v`` scaled to unit length; ``ValueError`` when it is
    zero. ``v / |v|`` as NumPy computes it, or, where the squares in ``|v|`` would
    underflow or overflow, the same direction found after dividing by the largest
    component."""
    with np.errstate(over="ignore", under="ignore"):
        length = float(np.linalg.norm(v))
    if 1e-150 < length < 1e150:
        return v / length
    largest = float(np.max(np.abs(v)))
    if largest == 0.0:
        raise ValueError(f"{name} must not be the zero vector")
    scaled = v / largest
    return scaled / math.hypot(*scaled)
