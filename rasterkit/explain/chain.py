"""The camera transformation factor by factor, and a world point carried through it.

:func:`chain_steps` returns the data (the factors of :meth:`rasterkit.Camera.chain` with one
line on what each does, the product K, and optionally a point after every factor, then
divided by w and put in its pixel); :func:`format_chain` turns it into the text that
``rasterkit explain`` prints. The factor names are the lecture's (see
:mod:`rasterkit.camera.chain`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rasterkit.explain._text import bracketed, num, side_by_side, tuple_text, wrap

__all__ = ["ChainSteps", "Factor", "chain_steps", "format_chain"]

#: Raster coordinates beyond this are reported without a pixel number (which would be long).
_FAR = 1e9


@dataclass(frozen=True)
class Factor:
    """One factor of the chain.

    Attributes
    ----------
    name : str
        The lecture's name: ``T``, ``R``, ``H``, ``S_xy``, ... (see :meth:`Camera.chain`).
    what : str
        One line on what it does, with this camera's numbers.
    matrix : (4, 4) float64 ndarray
    point : (4,) float64 ndarray or None
        The homogeneous point after this factor (None without a point).
    """

    name: str
    what: str
    matrix: np.ndarray
    point: np.ndarray | None


@dataclass(frozen=True)
class ChainSteps:
    """The chain of a camera, first applied first, and where a point ends up.

    Attributes
    ----------
    factors : list of Factor
    product : (4, 4) float64 ndarray
        K: the factors multiplied in order, ``M_last @ ... @ M_first``.
    matrix : (4, 4) float64 ndarray
        The camera's own :meth:`Camera.matrix`, to check ``product`` against.
    point : (4,) float64 ndarray or None
        The world point, ``(x, y, z, 1)``.
    homogeneous : (4,) float64 ndarray or None
        ``K p`` as :meth:`Camera.project_h` (and the renderer) computes it: (xh, yh, zh, w).
    raster : (3,) float64 ndarray or None
        Raster x, y (pixels) and depth, ``homogeneous`` divided by w (so
        :meth:`Camera.project`'s); None when ``w <= 0`` or ``homogeneous`` overflowed.
    pixel : (int, int) or None
        ``(floor(x), floor(y))``: column and row; None without ``raster`` or when x or y
        lies beyond 1e9.
    where : str
        Where the point ends up: its pixel, or outside the image, clipped, behind the eye.
    """

    factors: list[Factor]
    product: np.ndarray
    matrix: np.ndarray
    point: np.ndarray | None = None
    homogeneous: np.ndarray | None = None
    raster: np.ndarray | None = None
    pixel: tuple[int, int] | None = None
    where: str = ""

    @property
    def difference(self) -> float:
        """Largest absolute difference between ``product`` and ``matrix``."""
        return float(np.max(np.abs(self.product - self.matrix)))

    @property
    def agrees(self) -> bool:
        """Whether ``product`` equals ``matrix`` up to float64 rounding."""
        return bool(np.allclose(self.product, self.matrix, rtol=1e-12,
                                atol=1e-12 * float(np.max(np.abs(self.matrix)))))


def _describe(name: str, camera) -> str:
    """One line on what factor ``name`` does, with ``camera``'s numbers."""
    w, h, near, far = camera.width, camera.height, camera.near, camera.far
    if name == "T":
        return f"moves the eye {tuple_text(camera.eye)} to the origin"
    if name == "R":
        return ("rotates the camera frame (u right, v up, w backwards) onto the axes x, y, z: "
                "the camera now looks down -z")
    if name == "H":
        if camera.shift == (0.0, 0.0):
            return "shears the window centre onto the -z axis: the window is centred, so H = I"
        return (f"shears the off-centre window (shift {tuple_text(camera.shift)} half windows) "
                "so that its centre lies on the -z axis")
    if name == "S_xy":
        return (f"scales x, y so the side planes have slope 1: the window at z = -1 "
                f"(fov_y {num(camera.fov_y)} deg) becomes [-1, 1] x [-1, 1]")
    if name == "S_far":
        return (f"scales by 1/far = 1/{num(far)}: the far plane goes to z = -1, "
                f"the near plane to z = -near/far = {num(-near / far)}")
    if name == "P_persp":
        return ("the perspective step: w = -z, so after the divide the frustum is the box "
                "[-1, 1]^2 x [-1, 0] (near plane z = 0, far plane z = -1)")
    if name == "P_parallel":
        oblique = " after an oblique shear along z," if camera.oblique_ratio else ""
        return (f"projects parallel onto the image plane,{oblique} keeping the depth -z "
                "(0 near, 1 far) for the depth test")
    if name == "T_near":
        return f"moves the near plane z = -near = {num(-near)} to z = 0"
    if name == "S_xyz":
        return (f"scales the view box ({num(camera.view_height * camera.aspect)} x "
                f"{num(camera.view_height)} x {num(far - near)} world units) to [-1, 1]^2 x [-1, 0]")
    if name == "S_raster":
        return f"scales [-1, 1]^2 to the image size: x by W/2 = {num(w / 2)}, y by H/2 = {num(h / 2)}"
    if name == "Raster":
        return (f"flips y (raster y points down) and moves the origin to the top-left corner: "
                f"x + {num(w / 2)}, {num(h / 2)} - y")
    raise ValueError(f"no description for the factor {name!r}")


def _where(camera, h: np.ndarray) -> tuple[np.ndarray | None, tuple[int, int] | None, str]:
    """Raster point, pixel and a sentence on where the homogeneous point ``h`` ends up."""
    if not np.all(np.isfinite(h)):
        return None, None, "too far away for float64: K p overflows, so it has no pixel"
    if not h[3] > 0.0:
        return None, None, "behind the eye (w <= 0): it has no pixel; the near plane clips it away"
    raster = h[:3] / h[3]
    size = f"{camera.width}x{camera.height}"
    x, y, depth = raster
    if not (abs(x) < _FAR and abs(y) < _FAR):
        return raster, None, f"far outside the {size} image: no pixel"
    pixel = (math.floor(x), math.floor(y))
    at = f"pixel (column {pixel[0]}, row {pixel[1]})"
    if not (0.0 <= x < camera.width and 0.0 <= y < camera.height):
        return raster, pixel, f"outside the {size} image (it would be {at})"
    if depth < 0.0:
        return raster, pixel, f"in {at}, but nearer than the near plane (depth < 0): clipped away"
    if depth > 1.0:
        return raster, pixel, f"in {at}, but beyond the far plane (depth > 1): clipped away"
    return raster, pixel, f"in {at} of the {size} image, depth {num(depth)} (0 near, 1 far)"


def chain_steps(camera, point=None) -> ChainSteps:
    """The chain of ``camera`` factor by factor, and ``point`` carried through it.

    Parameters
    ----------
    camera : rasterkit.Camera
        A perspective or parallel camera. A lens camera shows its pinhole chain (the
        centre of the lens), the one :meth:`Camera.matrix` gives.
    point : (3,) array_like of float, optional
        A finite world point.

    Returns
    -------
    ChainSteps
        The factors in the order of :meth:`Camera.chain` (first applied first), each with
        the homogeneous point after it; the product K; the raster point, pixel and a
        sentence on where the point ends up.

    Examples
    --------
    >>> from rasterkit import Camera
    >>> cam = Camera.look_at((0, 0, 5), (0, 0, 0), width=64, height=48)
    >>> steps = chain_steps(cam, (0, 0, 0))
    >>> [f.name for f in steps.factors]
    ['T', 'R', 'H', 'S_xy', 'S_far', 'P_persp', 'P_parallel', 'S_raster', 'Raster']
    >>> steps.agrees, steps.pixel
    (True, (32, 24))
    """
    h = None
    if point is not None:
        xyz = np.asarray(point, np.float64).reshape(-1)
        if xyz.shape != (3,) or not np.all(np.isfinite(xyz)):
            raise ValueError(f"the point must be three finite numbers, got {point!r}")
        h = np.append(xyz, 1.0)
    factors, product, carried = [], np.eye(4), h
    with np.errstate(over="ignore", invalid="ignore"):
        for name, m in camera.chain():
            product = m @ product
            if carried is not None:
                carried = m @ carried
            factors.append(Factor(name, _describe(name, camera), m, carried))
    if h is None:
        return ChainSteps(factors, product, camera.matrix())
    # The end as the renderer computes it, K p in one product: the factor-by-factor p'
    # above agrees with it up to rounding, which may decide a pixel on a pixel border.
    homogeneous = camera.project_h(h[None, :3])[0]
    with np.errstate(over="ignore", invalid="ignore"):
        raster, pixel, where = _where(camera, homogeneous)
    return ChainSteps(factors, product, camera.matrix(), h, homogeneous, raster, pixel, where)


def _camera_lines(camera) -> list[str]:
    if camera.kind == "perspective":
        lens = f", fov_y {num(camera.fov_y)} deg"
        chain = "K = Raster * S_raster * P_parallel * P_persp * S_far * S_xy * H * R * T"
    else:
        lens = f", view height {num(camera.view_height)}"
        if camera.oblique_ratio:
            lens += (f", oblique: angle {num(camera.oblique_angle)} deg, "
                     f"ratio {num(camera.oblique_ratio)}")
        chain = "K = Raster * S_raster * P_parallel * S_xyz * T_near * R * T"
    lines = [
        f"Camera: {camera.kind}, {camera.width}x{camera.height} pixels{lens}",
        f"  eye {tuple_text(camera.eye)}  target {tuple_text(camera.target)}  "
        f"up {tuple_text(camera.up)}  near {num(camera.near)}  far {num(camera.far)}",
    ]
    if camera.kind == "perspective" and camera.aperture > 0.0:
        lines += wrap(f"lens: aperture {num(camera.aperture)}; the chain below is the pinhole's "
                      "at the lens centre (each sample of a render moves the eye on the lens)", "  ")
    return lines + ["", chain,
                    "The rightmost factor acts first, on column vectors: p' = M p.",
                    "Raster space: origin top-left, x right, y down, pixel centres at +0.5."]


def _factor_lines(k: int, factor: Factor, before: np.ndarray | None) -> list[str]:
    lines = wrap(f"{k}. {factor.name}: {factor.what}")
    if before is None:
        return lines + ["     " + row for row in bracketed(factor.matrix)]
    rows = side_by_side([bracketed(factor.matrix), bracketed(before), bracketed(factor.point)],
                        [" * ", " = "], middle=1)
    return lines + ["     " + row for row in rows]


def format_chain(steps: ChainSteps, camera) -> str:
    """The text of ``rasterkit explain`` for a camera: the output of :func:`chain_steps`.

    Parameters
    ----------
    steps : ChainSteps
        From :func:`chain_steps` for ``camera``.
    camera : rasterkit.Camera

    Returns
    -------
    str
        The camera's parameters; each factor numbered, first applied first, with its name,
        what it does and its matrix (times the point so far, when there is a point); K and
        the check that it equals ``camera.matrix()``; the divide by w and the pixel.
    """
    lines = _camera_lines(camera)
    if steps.point is not None:
        lines += wrap(f"The point p = {tuple_text(steps.point[:3])} in world space, "
                      "w = 1, carried through each factor: M * p = p'.")
    before = steps.point
    for k, factor in enumerate(steps.factors, 1):
        lines += [""] + _factor_lines(k, factor, before)
        before = factor.point
    verdict = ("equals camera.matrix()" if steps.agrees else "DIFFERS from camera.matrix()")
    lines += ["", f"K, the product of the {len(steps.factors)} factors (world -> homogeneous raster):"]
    lines += ["     " + row for row in bracketed(steps.product)]
    lines.append(f"Check: K {verdict} (largest difference {num(steps.difference)})")
    if steps.point is not None:
        lines += [""] + _ending_lines(steps)
    else:
        lines += ["", "Add --point X,Y,Z to carry a world point through the chain to its pixel."]
    return "\n".join(lines)


def _exact(value: float) -> str:
    """:func:`num`, or all the digits when the short form would hide which pixel ``value`` is in
    (23.999999999999996 is pixel 23, but prints as 24)."""
    short = num(value)
    if abs(value) >= _FAR or math.floor(float(short)) == math.floor(value):
        return short
    return f"{float(value)!r} (all the digits: {short} would hide its pixel)"


def _ending_lines(steps: ChainSteps) -> list[str]:
    xh, yh, zh, w = steps.homogeneous
    lines = wrap(f"K p = (xh, yh, zh, w) = {tuple_text(steps.homogeneous)}: the renderer's "
                 "product, the last p' above up to rounding")
    if steps.raster is not None:
        x, y, depth = steps.raster
        lines += wrap(f"Divide by w = {num(w)}: x = xh/w = {_exact(x)}, y = yh/w = {_exact(y)}, "
                      f"depth = zh/w = {num(depth)}")
        if steps.pixel is not None:
            lines.append(f"Pixel = (floor(x), floor(y)) = {steps.pixel}")
    lines += wrap(f"The point lands {steps.where}." if steps.pixel is not None
                  else f"The point is {steps.where}.")
    return lines
