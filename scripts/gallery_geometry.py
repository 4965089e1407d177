"""Figures of the gallery's first half: transformations, coordinate systems, the camera chain
and the projections (scripts/make_gallery.py writes them).

Each figure is a function returning a uint8 (H, W, 3) image; geometry is made in code.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

import rasterkit
from rasterkit import Camera, Scene, shapes, transform
from rasterkit.transform import apply_points, compose

from gallery_canvas import (AXIS_COLORS, axes_3d, blank, box_edges, dots, grid, label, pixel_grid,
                            segments_3d)


def letter_f() -> rasterkit.Mesh:
    """The letter F in the plane z = 0 (three rectangles, 0 <= x <= 1, 0 <= y <= 1.5)."""
    boxes = [(0.0, 0.0, 0.3, 1.5), (0.3, 1.2, 1.0, 1.5), (0.3, 0.6, 0.8, 0.9)]
    vertices, faces = [], []
    for x0, y0, x1, y1 in boxes:
        k = len(vertices)
        vertices += [(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0)]
        faces += [(k, k + 1, k + 2), (k, k + 2, k + 3)]
    return rasterkit.Mesh(np.array(vertices, float), np.array(faces))


def colored_cube(size: float = 1.0) -> rasterkit.Mesh:
    """shapes.cube with its faces coloured by their normal's axis (x red, y green, z blue)."""
    cube = shapes.cube(size)
    axis = np.argmax(np.abs(cube.face_normals), axis=1)
    palette = np.array([[1.0, 0.78, 0.74], [0.78, 0.94, 0.78], [0.76, 0.82, 1.0]], np.float32)
    return replace(cube, face_colors=palette[axis])


# --- affine transformations ---------------------------------------------------------------


def transforms() -> np.ndarray:
    """The letter F under each affine transformation (grey: the original), seen from +z."""
    f = letter_f()
    t, r = transform.translate(1.0, 0.4, 0), transform.rotate_z(math.pi / 6)
    cases = [
        ("identity", transform.identity()),
        ("translate(1, 0.4, 0)", t),
        ("rotate_z(pi/6)", r),
        ("scale(1.5, 0.6, 1)", transform.scale(1.5, 0.6, 1)),
        ("reflect('x')", transform.reflect("x")),
        ("shear(xy=0.5)", transform.shear(xy=0.5)),
        ("compose(R, T): R first", compose(r, t)),
        ("compose(T, R): T first", compose(t, r)),
    ]
    camera = Camera.orthographic((0.6, 0.7, 5), (0.6, 0.7, 0), view_height=3.6, width=116, height=116)
    panels = []
    for name, m in cases:
        scene = Scene(camera).add(f, transform.translate(0, 0, -0.1), color=(215, 215, 215))
        scene.add(f, m, color="steelblue")
        image = rasterkit.render(scene, mode="solid", cull="none").color.copy()
        axes_3d(image, camera, length=0.9, names=("", "", ""))
        panels.append(label(image, name, (3, 102)))
    return grid(panels, 4)


# --- the scene of the coordinate-system panels ---------------------------------------------

PLACEMENTS = {  # object -> world: the model matrices of the scene's three objects
    "cube": compose(transform.rotate_y(0.5), transform.translate(-1.0, 0.5, 0.0)),
    "sphere": transform.translate(1.1, 0.5, 0.4),
    "floor": transform.identity(),
}


def world_scene(camera=None) -> Scene:
    """A cube and a sphere on a floor, placed by :data:`PLACEMENTS`."""
    scene = Scene(camera)
    scene.add(colored_cube(), PLACEMENTS["cube"])
    scene.add(shapes.icosphere(2, 0.5), PLACEMENTS["sphere"], color=(240, 200, 90))
    scene.add(shapes.grid(4, 4, 3.6), PLACEMENTS["floor"], color=(200, 200, 200))
    return scene


def lecture_camera(width: int = 160, height: int = 120) -> Camera:
    """The camera whose chain the coordinate-system panels follow (near and far close in,
    so the normalised depths spread out)."""
    return Camera.look_at((2.2, 2.4, 5.2), (0, 0.3, 0), fov_y=40, width=width, height=height,
                          near=3.0, far=8.5)


def frustum(camera: Camera, near: float, far: float) -> tuple[np.ndarray, np.ndarray]:
    """World-space edges of the camera's view volume between distances ``near`` and ``far``."""
    corners = [(0, 0), (camera.width, 0), (camera.width, camera.height), (0, camera.height)]
    origin, direction = camera.ray(*np.array(corners, float).T)
    axis = -camera.basis()[2]
    t = 1.0 / (direction @ axis)
    rings = [origin + (d * t)[:, None] * direction for d in (near, far)]
    starts = np.concatenate([rings[0], rings[1], rings[0]])
    ends = np.concatenate([np.roll(rings[0], -1, 0), np.roll(rings[1], -1, 0), rings[1]])
    eye = np.repeat(np.asarray(camera.eye, float)[None], 4, 0)
    return np.concatenate([starts, eye]), np.concatenate([ends, rings[0]])


def _transformed_scene(matrix: np.ndarray) -> Scene:
    """The world scene with every object moved by ``matrix`` after its model matrix (a
    projective ``matrix`` is applied to the vertices, with the divide by w)."""
    out = Scene()
    for obj in world_scene().objects:
        vertices = apply_points(compose(obj.matrix, matrix), obj.mesh.vertices)
        color = None if obj.color is None else tuple(int(c * 255) for c in obj.color)
        out.add(replace(obj.mesh, vertices=vertices), color=color)
    return out


def coordinate_systems(size=(156, 124)) -> np.ndarray:
    """One scene in object, world, camera, NDC and raster space (observers' views)."""
    w, h = size
    cam = lecture_camera()
    factors = dict(cam.chain())
    panels = []

    observer = Camera.look_at((2.2, 1.8, 3.0), (0, 0, 0), fov_y=35, width=w, height=h)
    image = rasterkit.render(colored_cube(), observer, "solid+wire").color.copy()
    axes_3d(image, observer, length=1.1)
    panels.append(label(image, "object: the cube's own frame"))

    observer = Camera.look_at((4.2, 4.6, 7.6), (0.3, 0.4, 0.6), fov_y=40, width=w, height=h)
    image = rasterkit.render(world_scene(observer), mode="solid", cull="none").color.copy()
    for name in ("cube", "sphere"):
        m = PLACEMENTS[name]
        axes_3d(image, observer, m[:3, 3], m[:3, :3].T, 0.6, names=("", "", ""))
    segments_3d(image, observer, *frustum(cam, 0.001, 1.8), color=(90, 90, 90))
    _mark(image, observer, cam.eye, "eye")
    axes_3d(image, observer, length=1.2)
    panels.append(label(image, "world: objects, camera"))

    view = compose(factors["T"], factors["R"])
    observer = Camera.look_at((9.0, 5.0, 2.5), (0, 0, -4.8), fov_y=42, width=w, height=h)
    image = rasterkit.render(_transformed_scene(view), observer, "solid", cull="none").color.copy()
    segments_3d(image, observer, *frustum(replace(cam, eye=(0, 0, 0), target=(0, 0, -1), up=(0, 1, 0)),
                                          cam.near, cam.far), color=(90, 90, 90))
    axes_3d(image, observer, length=1.5)
    _mark(image, observer, (0, 0, 0), "eye", (-24, -2))
    panels.append(label(image, "camera: eye at 0, view -z"))

    to_ndc = compose(*(factors[n] for n in ("T", "R", "H", "S_xy", "S_far", "P_persp")))
    observer = Camera.look_at((2.6, 1.9, 2.4), (0, 0, -0.5), fov_y=40, width=w, height=h)
    image = rasterkit.render(_transformed_scene(to_ndc), observer, "solid", cull="none").color.copy()
    segments_3d(image, observer, *box_edges((-1, -1, -1), (1, 1, 0)), color=(90, 90, 90))
    axes_3d(image, observer, length=0.8)
    panels.append(label(image, "NDC: box [-1,1]^2 x [-1,0]"))

    small = rasterkit.render(world_scene(lecture_camera(24, 18)), mode="solid", cull="none").color
    image = blank(w, h)
    big = pixel_grid(small, 6)
    image[h - big.shape[0] - 2:h - 2, 2:2 + big.shape[1]] = big
    label(image, "raster: 24x18 pixels")
    label(image, "x right", (w - 36, 40), AXIS_COLORS[0])
    label(image, "y down", (w - 36, 56), AXIS_COLORS[1])
    panels.append(image)

    image = rasterkit.render(world_scene(lecture_camera(w, h)), mode="solid", cull="none").color.copy()
    panels.append(label(image, "the image (160x120)"))
    return grid(panels, 3)


def _mark(image: np.ndarray, camera: Camera, point, text: str, offset=(4, -12)) -> None:
    """A dot at a world point and a label beside it."""
    xy = camera.project(np.asarray(point, float)[None])[0, :2]
    dots(image, xy[None], 2.5)
    label(image, text, tuple(xy + offset))


# --- the view volume through the chain ----------------------------------------------------


CHAIN_STEPS = {  # what the view volume looks like after each factor (side view)
    "R": "T, R: camera space", "H": "H: window centred", "S_xy": "S_xy: sides at 45 degrees",
    "S_far": "S_far: far plane at z=-1", "P_persp": "P_persp: a box, near z=0",
    "P_parallel": "P_parallel: depth 0..1",
}


def chain_volume(size=(156, 124)) -> np.ndarray:
    """The view volume (blue) and a ball (orange) in the y-z plane after each factor of a
    camera with an off-centre window; the black dot is the origin."""
    w, h = size
    cam = Camera.look_at((0, 0, 0), (0, 0, -1), fov_y=50, width=160, height=120, near=1.0,
                         far=4.0, shift=(0, 0.5))
    outline = _side_outline(cam)
    ball = np.array([[0, 0.45 + 0.3 * math.sin(a), -2.5 + 0.3 * math.cos(a)]
                     for a in np.linspace(0, 2 * math.pi, 33)])
    panels, matrix = [], np.eye(4)
    for name, factor in cam.chain():
        matrix = compose(matrix, factor)
        if name in CHAIN_STEPS:
            image = _side_plot(apply_points(matrix, outline), apply_points(matrix, ball), w, h)
            panels.append(label(image, CHAIN_STEPS[name]))
    return grid(panels, 3)


def _side_outline(cam: Camera) -> np.ndarray:
    """Closed outline of the view volume in the plane x = 0 (camera space): near bottom,
    far bottom, far top, near top, near bottom."""
    shift_y, half = cam.shift[1], math.tan(math.radians(cam.fov_y) / 2)
    points = []
    for d, top in ((cam.near, -1), (cam.far, -1), (cam.far, 1), (cam.near, 1), (cam.near, -1)):
        points.append((0.0, d * half * (shift_y + top), -d))
    return np.array(points)


def _side_plot(volume: np.ndarray, ball: np.ndarray, w: int, h: int) -> np.ndarray:
    """The y-z plane: z to the right (the eye looks to the left, towards -z), y up."""
    everything = np.concatenate([volume, ball, [[0, 0, 0]]])
    lo, hi = everything[:, 1:].min(0), everything[:, 1:].max(0)
    scale = min((w - 20) / max(hi[1] - lo[1], 1e-9), (h - 34) / max(hi[0] - lo[0], 1e-9))
    centre = (lo + hi) / 2

    def to_px(p):
        return np.stack([w / 2 + (p[:, 2] - centre[1]) * scale,
                         h / 2 + 8 - (p[:, 1] - centre[0]) * scale], 1)

    image = blank(w, h)
    axes = to_px(np.array([[0, 0, lo[1] - 1], [0, 0, hi[1] + 1], [0, lo[0] - 1, 0], [0, hi[0] + 1, 0]]))
    rasterkit.draw.lines(image, [[*axes[0], *axes[1]], [*axes[2], *axes[3]]], color=(215, 215, 215))
    v = to_px(volume)
    rasterkit.draw.lines(image, np.concatenate([v[:-1], v[1:]], 1), color=(40, 80, 215), aa=True)
    b = to_px(ball)
    rasterkit.draw.lines(image, np.concatenate([b[:-1], b[1:]], 1), color=(205, 120, 20), aa=True)
    dots(image, to_px(np.zeros((1, 3))), 2.5, (0, 0, 0))
    return image


# --- projections --------------------------------------------------------------------------


def _vanishing_lines(image, camera, cube: rasterkit.Mesh) -> None:
    """Extend the cube's edges towards the vanishing point of their direction, mark it."""
    k = camera.matrix()
    for axis in range(3):
        direction = np.zeros(4)
        direction[axis] = 1.0
        xh, yh, _, wh = k @ direction
        if abs(wh) < 1e-9:  # parallel to the image plane: no vanishing point
            continue
        vp = np.array([xh / wh, yh / wh])
        ends = camera.project(cube.vertices)[:, :2]
        rasterkit.draw.lines(image, [[*e, *vp] for e in ends], color=(170, 170, 170), aa=True)
        dots(image, vp[None], 3.0, AXIS_COLORS[axis])


def projections_perspective(size=(236, 150)) -> np.ndarray:
    """1-, 2- and 3-point perspective of a cube, its edges extended to their vanishing
    points; and a 2-point view looking down through a shifted window, not a tilted camera."""
    w, h = size
    cube = colored_cube()
    centre, radius = cube.bounding_sphere()
    cameras = [
        ("1-point: view along -z", Camera.look_at((1.1, 0.9, 3.2), (1.1, 0.9, 0), fov_y=60,
                                                  width=w, height=h)),
        ("2-point (Camera.two_point)",
         Camera.two_point(centre, radius * 2.2, fov_y=60, width=w, height=h)),
        ("3-point (Camera.three_point)",
         Camera.three_point(centre, radius * 2.2, fov_y=60, width=w, height=h)),
        ("2-point, shift=(0, -0.6)", Camera.look_at((2.0, 1.3, 2.8), (0.4, 1.3, 0.0), fov_y=60,
                                                    width=w, height=h, shift=(0, -0.6))),
    ]
    panels = []
    for name, camera in cameras:
        image = blank(w, h)
        _vanishing_lines(image, camera, cube)
        drawn = rasterkit.render(cube, camera, "solid+wire").color
        mask = np.any(drawn != 255, axis=2)
        image[mask] = drawn[mask]
        panels.append(label(image, name))
    return grid(panels, 2)


def projections_parallel(size=(156, 124)) -> np.ndarray:
    """Orthographic, axonometric and oblique views of a cube with unit axes along its edges."""
    w, h = size
    cube = colored_cube()
    centre, radius = cube.bounding_sphere()
    r = radius * 1.35
    cameras = [
        ("orthographic (front)", Camera.preset("orthographic", centre, r, width=w, height=h,
                                               azimuth=0, elevation=0)),
        ("isometric", Camera.isometric(centre, r, width=w, height=h)),
        ("dimetric", Camera.dimetric(centre, r, width=w, height=h)),
        ("trimetric", Camera.trimetric(centre, r, width=w, height=h)),
        ("cavalier (ratio 1)", Camera.cavalier(centre, r * 1.2, width=w, height=h)),
        ("cabinet (ratio 1/2)", Camera.cabinet(centre, r, width=w, height=h)),
    ]
    corner = np.array([-0.5, -0.5, 0.5])  # the front-left-bottom corner: the axes run along edges
    panels = []
    for name, camera in cameras:
        image = rasterkit.render(cube, camera, "solid+wire").color.copy()
        axes_3d(image, camera, corner, np.diag([1.0, 1.0, -1.0]), 1.0, names=("1", "1", "1"))
        panels.append(label(image, name))
    return grid(panels, 3)
