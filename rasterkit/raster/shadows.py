"""Shadow maps: the depth of the scene seen from each shadowing light, drawn by the depth pass
of the triangle rasterizer, for the per-pixel lighting to look up
(:func:`rasterkit.raster.kernels.lights.shadow_factor`).

- A directional light (and a headlight) sees the scene through a parallel camera looking along
  its direction, fitted to the casters' box where the frame's camera can see it; then, when the
  frame's visible surface (drawn small from its camera) has its shadowed points in a smaller
  part of that window, fitted again to that part (and a margin): the texels go where shadows
  are seen, not to a ground stretching to the horizon.
- A spot light sees it through a perspective camera at its position along its direction, its
  field of view the cone's opening (and a margin).
- A point light sees it through six perspective cameras (a cube map), one along each axis,
  each a little wider than 90 degrees so that the filter of a lookup near a face's edge stays
  within that face: no seams.
- A perspective map's near plane is put just before the nearest caster it sees (found in a
  small first drawing): its depth buffer's precision goes as ``near / distance²``, and a near
  plane at the light's own position would leave its depths coarser than a texel.

Each map is the depth buffer its camera's drawing left (:mod:`rasterkit.raster.vision`: a
parallel camera's ``(d - n) / (f - n)``, a perspective one's ``f (d - n) / (d (f - n))`` of the
distance ``d`` along its optical axis; +inf where nothing was drawn), square, ``size`` texels a
side: the lookup turns the point's distance into those units rather than each texel into a
distance. Faces cast shadows from both sides.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from rasterkit._arrays import finite_bounds
from rasterkit.camera import Camera
from rasterkit.raster.kernels.shadow_fit import shadowed_extent, visible_points
from rasterkit.raster.vertex import transform_points

__all__ = ["AXES_WIDTH", "ShadowMaps", "default_map_size", "shadow_maps"]

#: Columns of :attr:`ShadowMaps.axes`: the camera's eye (3), unit viewing direction (3), the
#: size of a texel (world units; per unit of distance for a perspective camera), 1 for a
#: perspective camera (else 0), its near and far distances, the unit world directions of the
#: map's x (3) and y (3, raster y: down).
AXES_WIDTH = 16

#: The six directions of a point light's cube map, in the order the lookup picks them
#: (+x, -x, +y, -y, +z, -z: ``2 * axis + (component < 0)``).
CUBE = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], np.float64)


@dataclass(frozen=True)
class ShadowMaps:
    """The shadow maps of a frame's lights."""

    maps: np.ndarray  # (K, S, S) float32 each camera's depth buffer (see the module docstring), +inf: nothing
    matrices: np.ndarray  # (K, 4, 4) float64 world -> raster of each map's camera
    axes: np.ndarray  # (K, AXES_WIDTH) float64, see AXES_WIDTH
    first: np.ndarray  # (L,) int64 each light's first map (-1: none); a point light's are six


def default_map_size(width: int, height: int) -> int:
    """The side of a shadow map for an image of ``width`` x ``height``: the power of two at
    least as large as its longer side, 512 to 4096."""
    side = max(width, height, 1)
    return int(min(4096, max(512, 1 << (side - 1).bit_length())))


def shadow_maps(mesh, lights: tuple, camera: Camera, size: int, softness: float, casters=None) -> ShadowMaps:
    """The maps of the shadowing ``lights`` (:class:`rasterkit.Light` with ``shadows``; a
    headlight along ``camera``'s viewing direction) of ``mesh`` (world space) seen by
    ``camera``, ``size`` texels a side, for lookups filtered over ``softness`` texels;
    ``casters``: ``(vertices, faces)``, the counts of the mesh's first vertices and faces that
    cast shadows (the others, a ground under them, only receive them), None: all. The maps
    are fitted to the casters: a point outside a map has nothing between it and the light."""
    vertices = mesh.vertices if casters is None else mesh.vertices[:casters[0]]
    faces = mesh.faces if casters is None else mesh.faces[:casters[1]]
    low, high = finite_bounds(vertices) or (np.zeros(3), np.zeros(3))
    centre = low / 2.0 + high / 2.0
    radius = max(float(np.linalg.norm(high - low)) / 2.0, 1e-9 * max(1.0, float(np.abs(centre).max())))
    corners = _box_corners(np.stack([low, high]))
    cameras, first = [], np.full(len(lights), -1, np.int64)
    for k, light in enumerate(lights):
        if not light.shadows:
            continue
        first[k] = len(cameras)
        if light.kind in ("directional", "headlight"):
            direction = -np.asarray(camera.backward()) if light.kind == "headlight" else np.asarray(light.direction)
            cameras.append(_parallel(corners, _seen(camera, centre, radius), direction, size))
        elif light.kind == "spot":
            margin = 2.0 * math.degrees(math.atan((softness + 2.0) / size))
            cameras.append(_perspective(np.asarray(light.position), np.asarray(light.direction),
                                        min(light.angle + margin, 170.0), centre, radius, size))
        else:  # point: a cube, each face wide enough for the filter at its edges
            fov = 2.0 * math.degrees(math.atan(1.0 + 2.0 * (softness + 2.0) / size))
            cameras += [_perspective(np.asarray(light.position), axis, fov, centre, radius, size) for axis in CUBE]
    maps = np.empty((len(cameras), size, size), np.float32)
    matrices = np.empty((len(cameras), 4, 4))
    axes = np.empty((len(cameras), AXES_WIDTH))
    visible = None
    for k, view in enumerate(cameras):
        if view.kind == "perspective":
            view = _nearer(mesh.vertices, faces, view)
        if view.kind != "perspective":  # where in the window are shadows seen? (a map a quarter as fine)
            if visible is None:
                visible = _visible(mesh, camera)
            coarse = view.with_size(max(16, size // COARSE), max(16, size // COARSE))
            view = _refit(coarse, _depth(mesh.vertices, faces, coarse), visible, corners, softness, size) or view
        matrices[k] = view.world_to_raster()
        _depth(mesh.vertices, faces, view, maps[k])
        axes[k] = _axes(view, size)
    return ShadowMaps(maps, matrices, axes, first)


def _up(direction: np.ndarray) -> np.ndarray:
    """A world axis far from parallel to ``direction``."""
    return np.eye(3)[int(np.argmin(np.abs(direction)))]


def _box_corners(bounds: np.ndarray) -> np.ndarray:
    """(8, 3): the corners of the box ``bounds`` (2, 3)."""
    return np.array([[bounds[i, 0], bounds[j, 1], bounds[k, 2]] for i in (0, 1) for j in (0, 1) for k in (0, 1)])


def _seen(camera: Camera, centre: np.ndarray, radius: float) -> np.ndarray:
    """(8, 3): the corners of the part of ``camera``'s view between the nearest and the
    farthest points of the sphere (``centre``, ``radius``): the rays through the image's
    corners, from where they could first meet the scene to where they leave it."""
    x = np.array([0.0, camera.width, 0.0, camera.width])
    y = np.array([0.0, 0.0, camera.height, camera.height])
    origin, direction = camera.ray(x, y)
    along = ((centre - origin) * direction).sum(axis=1)  # each ray's closest approach to the centre
    near, far = np.maximum(along - radius, 0.0), along + radius
    return np.concatenate([origin + direction * near[:, None], origin + direction * far[:, None]])


def _light_basis(direction: np.ndarray) -> np.ndarray:
    """(3, 3): rows right, up, forward of a parallel camera looking along ``direction``."""
    forward = direction / np.linalg.norm(direction)
    right = np.cross(forward, _up(forward))
    right /= np.linalg.norm(right)
    return np.stack([right, np.cross(right, forward), forward])


def _parallel(corners: np.ndarray, seen: np.ndarray, direction: np.ndarray, size: int) -> ParallelView:
    """A directional light's camera: looking along ``direction`` at the scene whose box has
    ``corners``, its square window the box's extent across the light, cut down to where the
    camera's view (``seen``, :func:`_seen`) spreads across it (only there can a shadow be
    seen), its depth the whole box's (every caster)."""
    basis = _light_basis(direction)
    scene, view = corners @ basis.T, seen @ basis.T
    low = np.maximum(scene.min(axis=0)[:2], view.min(axis=0)[:2])
    high = np.minimum(scene.max(axis=0)[:2], view.max(axis=0)[:2])
    if not (high > low).all():  # the view misses the scene's box: the whole box
        low, high = scene.min(axis=0)[:2], scene.max(axis=0)[:2]
    return _window(basis, low, high, scene[:, 2].min(), scene[:, 2].max(), size)


@dataclass(frozen=True)
class ParallelView:
    """A directional light's camera: what the map's drawing and lookup need of the
    orthographic :class:`rasterkit.Camera` looking from ``eye`` along ``frame[2]`` (its rows
    right, up, forward: :func:`_light_basis`) through a square window ``view_height`` a side,
    ``width`` (= ``height``) texels, seeing ``near`` to ``far`` along its axis (the same
    matrices, made directly: building and checking a Camera costs more than a millisecond
    per map, and a map is fitted anew in each frame)."""

    frame: np.ndarray
    eye: np.ndarray
    view_height: float
    width: int
    height: int
    near: float
    far: float
    kind: str = "parallel"

    def backward(self) -> np.ndarray:
        return -self.frame[2]

    def basis(self) -> tuple:
        """(right, up, backward), as :meth:`rasterkit.Camera.basis`."""
        return self.frame[0], self.frame[1], -self.frame[2]

    def with_size(self, width: int, height: int) -> ParallelView:
        return replace(self, width=width, height=height)

    def world_to_raster(self) -> np.ndarray:
        """(4, 4): world -> raster (x right, y down, pixel centres at half-integers; z the depth
        buffer's ``(d - near) / (far - near)``), the orthographic camera's."""
        texels = self.width / self.view_height
        matrix = np.zeros((4, 4))
        matrix[0, :3], matrix[1, :3] = self.frame[0] * texels, -self.frame[1] * texels
        matrix[2, :3] = self.frame[2] / (self.far - self.near)
        matrix[:3, 3] = -matrix[:3, :3] @ self.eye + (self.width / 2.0, self.height / 2.0, 0.0)
        matrix[2, 3] -= self.near / (self.far - self.near)
        matrix[3, 3] = 1.0
        return matrix


def _window(basis: np.ndarray, low: np.ndarray, high: np.ndarray, depth_low: float, depth_high: float,
            size: int) -> ParallelView:
    """The parallel camera of ``basis`` (:func:`_light_basis`) whose square window holds the
    rectangle ``low`` to ``high`` (light space, across the light; a texel or two of margin for
    the filter), seeing depths ``depth_low`` to ``depth_high`` along it (and a margin)."""
    right, up, forward = basis
    scale = max(1.0, float(np.abs(low).max()), float(np.abs(high).max()), abs(depth_low), abs(depth_high))
    extent = max(float((high - low).max()), 1e-9 * scale)
    pad = 0.05 * max(depth_high - depth_low, extent)
    side = extent * (1.0 + 4.0 / size)  # a texel or two of margin for the filter
    mid = (low + high) / 2.0
    eye = mid[0] * right + mid[1] * up + (depth_low - pad) * forward
    return ParallelView(basis, eye, side, size, size, pad * 0.5, depth_high - depth_low + pad * 1.5)


#: How many times coarser than the final map is the first drawing a directional light's map is
#: fitted from (:func:`_refit`).
COARSE = 4

#: The longer side of the small drawing of the frame's visible surface that a directional
#: light's map is fitted to (:func:`_visible`).
VISIBLE_SIDE = 384


def _visible(mesh, camera: Camera) -> np.ndarray:
    """(7, N): the points of ``mesh`` that ``camera`` sees, one per pixel of a drawing at most
    :data:`VISIBLE_SIDE` pixels a side (faces drawn from both sides: the nearest surface):
    rows x, y, z, the unit normal of its face turned towards the camera (3) and the radius
    (world units) of the patch around it that its pixel stands for."""
    from rasterkit.raster.triangles import rasterize_checked

    scale = min(1.0, VISIBLE_SIDE / max(camera.width, camera.height))
    small = camera.with_size(max(1, round(camera.width * scale)), max(1, round(camera.height * scale)))
    depth = np.full((small.height, small.width), np.inf, np.float32)
    ids = np.full((small.height, small.width), -1, np.int32)
    matrix = small.world_to_raster()
    clip = transform_points(np.ascontiguousarray(mesh.vertices, np.float64), np.ascontiguousarray(matrix))
    rasterize_checked(None, depth, clip, mesh.faces, None, None, ids, "none", (), (0.0, 0.0), None, trusted=True)
    out = np.empty((7, int(np.count_nonzero(ids >= 0))))
    perspective = small.kind == "perspective"
    tangent = math.tan(math.radians(small.fov_y) / 2.0) if perspective else 0.0
    count = visible_points(depth, ids, np.linalg.inv(matrix), mesh.face_normals, np.asarray(small.eye, np.float64),
                           np.asarray(small.backward(), np.float64), perspective, tangent,
                           0.0 if perspective else float(small.view_height), out)
    return out if count == out.shape[1] else np.ascontiguousarray(out[:, :count])


def _refit(view: ParallelView, depth: np.ndarray, visible: np.ndarray, corners: np.ndarray, softness: float,
           side: int) -> ParallelView | None:
    """A directional light's camera, ``side`` texels a side, fitted to the part of ``view``'s
    window (its map ``depth``) where the frame's ``visible`` points (:func:`_visible`) may be
    in shadow: those facing the light with something nearer to it than their face's plane
    (by two texels) in their texel or the next ones (those facing away are in their own
    shadow without a map: :func:`rasterkit.raster.kernels.lights.shadow_factor`); with a
    margin of each point's footprint, the filter's reach and a few texels. None when that
    part is not much smaller than the window (or is empty: no shadow in view)."""
    size = depth.shape[0]
    basis = view.frame
    texel = view.view_height / size
    count, low0, low1, high0, high1 = shadowed_extent(
        visible, view.world_to_raster(), np.ascontiguousarray(basis, np.float64),
        float(basis[2] @ np.asarray(view.eye)), depth, texel, float(view.near),
        view.far - view.near,  # the depth buffer's units (a parallel camera's): (d - near) / span
        (math.ceil(softness) + 4.0) * texel)
    if count == 0:
        return None
    low, high = np.array([low0, low1]), np.array([high0, high1])
    centre = basis[:2] @ np.asarray(view.eye)
    half = view.view_height / 2.0
    low, high = np.maximum(low, centre - half), np.minimum(high, centre + half)
    if not (high > low).all() or float((high - low).max()) > 0.75 * view.view_height:
        return None
    scene = corners @ basis.T
    return _window(basis, low, high, scene[:, 2].min(), scene[:, 2].max(), side)


def _perspective(position, direction, fov, centre, radius, size) -> Camera:
    direction = direction / np.linalg.norm(direction)
    distance = float(np.linalg.norm(centre - position))
    far = (distance + radius) * 1.01
    near = max(distance - radius, far * 1e-4) * 0.99
    return Camera.look_at(tuple(position), tuple(position + direction), up=tuple(_up(direction)), fov_y=fov,
                          width=size, height=size, near=near, far=far)


def _nearer(vertices, faces, view: Camera) -> Camera:
    """``view`` (a perspective map's camera) with its near plane moved up to half the
    distance of the nearest of ``faces`` it sees, found in a drawing a quarter of its size (or
    as it is when that is not farther): the depth buffer's precision, about
    ``near / distance²``, then serves the texels."""
    small = view.with_size(max(16, view.width // 4), max(16, view.height // 4))
    seen = _depth(vertices, faces, small)
    finite = seen[np.isfinite(seen)]
    if len(finite) == 0:
        return view
    nearest = float(finite.min())  # the depth buffer's f (d - n) / (d (f - n)) of the nearest: its d
    near = 0.5 * view.far * view.near / (view.far - nearest * (view.far - view.near))
    if not near > 2.0 * view.near:
        return view
    return replace(view, near=near)


def _axes(camera, size: int) -> np.ndarray:
    """The row of :data:`AXES_WIDTH` of a map's ``camera`` (a Camera or a ParallelView)."""
    row = np.zeros(AXES_WIDTH)
    row[0:3] = camera.eye
    row[3:6] = -np.asarray(camera.backward())
    if camera.kind == "perspective":
        row[6] = 2.0 * math.tan(math.radians(camera.fov_y) / 2.0) / size
        row[7] = 1.0
    else:
        row[6] = camera.view_height / size
    row[8], row[9] = camera.near, camera.far
    right, up, _ = camera.basis()
    row[10:13], row[13:16] = right, -np.asarray(up)
    return row


def _depth(vertices, faces, camera, out: np.ndarray | None = None) -> np.ndarray:
    """(S, S) float32 ``out`` (None: a new array): ``camera``'s (a Camera or a ParallelView) depth buffer of ``faces`` (of a
    Mesh's ``vertices``; +inf where none), faces drawn from both sides. The draw clears each
    band of it before drawing there (the empty clear colour of a draw without colours)."""
    from rasterkit.raster.triangles import rasterize_checked

    depth = np.empty((camera.height, camera.width), np.float32) if out is None else out
    clip = transform_points(np.ascontiguousarray(vertices, np.float64), np.ascontiguousarray(camera.world_to_raster()))
    rasterize_checked(None, depth, clip, faces, None, None, None, "none", (), (0.0, 0.0), None, trusted=True)
    return depth
