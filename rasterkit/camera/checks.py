"""The rules for a valid camera, and checks of the numbers given to a camera or a preset.

:func:`camera_fields` checks and converts all fields of a ``Camera``; the small checks return
one value as a plain Python ``float``, ``int`` or tuple. All raise ``ValueError`` naming the
parameter. Shared by :mod:`.camera` and :mod:`.projections`.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from rasterkit._arrays import describe, real_array, real_number, unit
from rasterkit.options import MAX_IMAGE_SIZE
from rasterkit.transform import vector3

Vec3 = tuple[float, float, float]

KINDS = ("perspective", "parallel")
"""The values of ``Camera.kind``."""


def finite(value: float, name: str) -> float:
    """A finite real number as a float: ``TypeError`` for what is not a real number (a
    string, a bool, a complex number, None), ``ValueError`` for NaN and infinities."""
    x = real_number(value, name)
    if not math.isfinite(x):
        raise ValueError(f"{name} must be a finite number, got {x}")
    return x


def positive(value: float, name: str) -> float:
    x = finite(value, name)
    if x <= 0.0:
        raise ValueError(f"{name} must be positive, got {value!r}")
    return x


def positive_int(value: int, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value <= 0:
        raise ValueError(f"{name} must be a positive integer, got {describe(value)}")
    return int(value)


def image_size(value: int, name: str) -> int:
    """An image width or height: a positive integer up to :data:`MAX_IMAGE_SIZE`."""
    n = positive_int(value, name)
    if n > MAX_IMAGE_SIZE:
        raise ValueError(f"{name} must be at most {MAX_IMAGE_SIZE} pixels, got {describe(n)}")
    return n


def fov(value: float) -> float:
    """``fov_y`` in degrees, strictly between 0 and 180."""
    x = finite(value, "fov_y")
    if not 0.0 < x < 180.0:
        raise ValueError(f"fov_y must lie strictly between 0 and 180 degrees, got {value!r}")
    return x


def point(value: Sequence[float], name: str) -> Vec3:
    """Three finite numbers, e.g. a world-space point or direction."""
    x, y, z = vector3(value, name)
    return (float(x), float(y), float(z))


def camera_fields(
    *, kind: str, eye: Sequence[float], target: Sequence[float], up: Sequence[float],
    width: int, height: int, near: float, far: float, fov_y: float | None,
    shift: Sequence[float], view_height: float | None, oblique_angle: float, oblique_ratio: float,
    aperture: float = 0.0, focus_distance: float | None = None, pixel_aspect: float = 1.0,
    distortion: Sequence[float] = (),
) -> dict[str, Any]:
    """The fields of a ``Camera`` (see its docstring), checked and converted.

    Raises ``ValueError`` for the first invalid field, or for fields that do not belong to
    ``kind``.
    """
    if kind not in KINDS:
        raise ValueError(f"kind must be 'perspective' or 'parallel', got {kind!r}")
    f = dict(
        kind=kind,
        eye=point(eye, "eye"),
        target=point(target, "target"),
        up=point(up, "up"),
        width=image_size(width, "width"),
        height=image_size(height, "height"),
        near=positive(near, "near"),
        far=positive(far, "far"),
        fov_y=fov_y,
        shift=_shift(shift),
        view_height=view_height,
        oblique_angle=finite(oblique_angle, "oblique_angle"),
        oblique_ratio=finite(oblique_ratio, "oblique_ratio"),
        aperture=finite(aperture, "aperture"),
        focus_distance=None if focus_distance is None else positive(focus_distance, "focus_distance"),
        pixel_aspect=positive(pixel_aspect, "pixel_aspect"),
        distortion=distortion_coefficients(distortion),
    )
    if f["aperture"] < 0.0:
        raise ValueError(f"aperture must not be negative, got {aperture!r}")
    if not f["near"] < f["far"]:
        raise ValueError(f"near must be smaller than far, got near={f['near']}, far={f['far']}")
    _check_frame(f["eye"], f["target"], f["up"])
    if kind == "perspective":
        _check_perspective(f)
    else:
        _check_parallel(f)
    return f


def _shift(value: Sequence[float]) -> tuple[float, float]:
    shift = real_array(value, "shift")
    if shift.shape != (2,):
        raise ValueError(f"shift must be 2 finite numbers, got {describe(value)}")
    return (finite(shift[0], "shift[0]"), finite(shift[1], "shift[1]"))


#: Lengths OpenCV's distortion vector may have here: (k1, k2, p1, p2[, k3[, k4, k5, k6]]).
DISTORTION_LENGTHS = (4, 5, 8)


def distortion_coefficients(value) -> tuple[float, ...]:
    """OpenCV's distortion coefficients as a tuple of 4, 5 or 8 floats (``()`` for None or
    all zeros: no distortion)."""
    if value is None:
        return ()
    d = real_array(value, "dist").reshape(-1)
    if d.size not in DISTORTION_LENGTHS + (0,) or not np.all(np.isfinite(d)):
        raise ValueError(f"dist must be 4, 5 or 8 finite numbers (k1, k2, p1, p2[, k3[, k4, k5, k6]]), "
                         f"got {describe(value)}")
    return tuple(float(x) for x in d) if np.any(d) else ()


def _check_frame(eye: Vec3, target: Vec3, up: Vec3) -> None:
    with np.errstate(over="ignore", invalid="ignore"):
        view = np.subtract(target, eye)
    if not np.all(np.isfinite(view)):
        raise ValueError("eye and target are too far apart: target - eye overflows float64")
    if not np.any(view):
        raise ValueError("eye and target must differ")
    up = np.asarray(up)
    if not np.any(up):
        raise ValueError("up must not be the zero vector")
    # unit vectors found without squaring tiny or huge components (which underflow or overflow)
    if np.linalg.norm(np.cross(unit(up, "up"), unit(view, "target - eye"))) < 1e-9:
        raise ValueError("up must not be parallel to the view direction (target - eye)")


def _check_perspective(f: dict[str, Any]) -> None:
    """Checks ``fov_y`` in place and that no parallel-only field is set."""
    if f["fov_y"] is None:
        raise ValueError("a perspective camera needs fov_y")
    f["fov_y"] = fov(f["fov_y"])
    if f["view_height"] is not None or f["oblique_ratio"] != 0.0:
        raise ValueError("view_height and oblique_ratio belong to parallel cameras")
    if f["distortion"]:
        _check_distortion(f)


def _check_distortion(f: dict[str, Any]) -> None:
    """The distortion must leave the pixels next to the principal point an ideal point each
    (:func:`rasterkit.raster.distortion.undistort` finds one): coefficients so strong that the
    model folds, or cannot be inverted, within a pixel of the centre show nothing."""
    from rasterkit.raster.distortion import undistort

    fy = f["height"] / (2.0 * math.tan(math.radians(f["fov_y"]) / 2.0))
    fx = fy / f["pixel_aspect"]
    ring = np.array([(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1)], np.float64)
    _, _, ok = undistort(ring[:, 0] / fx, ring[:, 1] / fy, f["distortion"])
    if not ok.all():
        coefficients = ", ".join(f"{c:g}" for c in f["distortion"])
        raise ValueError(f"dist ({coefficients}) is too strong: the distortion model folds (or has "
                         "no inverse) within a pixel of the principal point, so the image would show nothing")


def _check_parallel(f: dict[str, Any]) -> None:
    """Checks ``view_height`` in place and that no perspective-only field is set."""
    if f["view_height"] is None:
        raise ValueError("a parallel camera needs view_height")
    f["view_height"] = positive(f["view_height"], "view_height")
    if f["fov_y"] is not None or f["shift"] != (0.0, 0.0):
        raise ValueError("fov_y and shift belong to perspective cameras")
    if f["distortion"]:
        raise ValueError("distortion belongs to perspective cameras")
    if f["aperture"] != 0.0 or f["focus_distance"] is not None:
        raise ValueError("aperture and focus_distance belong to perspective cameras (a parallel "
                         "camera has no lens)")
    if f["oblique_ratio"] < 0.0:
        raise ValueError(f"oblique_ratio must not be negative, got {f['oblique_ratio']}")


def check_matrix(k: np.ndarray, camera) -> None:
    """Raise ``ValueError`` unless the world -> raster matrix ``k`` of ``camera`` is finite
    (it is not when the camera's sizes and distances are too large or too small next to
    each other: ``1 / far`` or ``1 / tan(fov_y / 2)`` beyond float64, say)."""
    if not np.all(np.isfinite(k)):
        window = f"fov_y {camera.fov_y:g}" if camera.kind == "perspective" else f"view_height {camera.view_height:g}"
        raise ValueError(
            f"the camera's transformation overflows float64 (eye {describe(camera.eye)}, target "
            f"{describe(camera.target)}, near {camera.near:g}, far {camera.far:g}, {window}): its sizes and "
            f"distances are too large or too small next to each other")
