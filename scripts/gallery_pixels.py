"""Figures of the gallery's second half: backface culling, line rasterization, anti-aliasing,
the lens camera and vignetting (scripts/make_gallery.py writes them).

Each figure is a function returning a uint8 (H, W, 3) image; geometry is made in code.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

import rasterkit
from rasterkit import Camera, Scene, draw, shapes, transform

from gallery_canvas import blank, dots, grid, label, line_grid, magnify, plot, segments_3d, stack
from gallery_geometry import colored_cube

FRONT, BACK = (70, 130, 180), (235, 120, 110)

# --- backface culling ---------------------------------------------------------------------


def facing(mesh: rasterkit.Mesh, eye) -> np.ndarray:
    """True for the faces whose normal n points towards the eye: n·v > 0 with v = eye - p."""
    centroids = mesh.vertices[mesh.faces].mean(axis=1)
    return np.einsum("ij,ij->i", mesh.face_normals, np.asarray(eye) - centroids) > 0


def culling(size=(236, 170)) -> np.ndarray:
    """Left: the camera's image with cull='back', the culled faces' outlines in red.
    Right: the same icosahedron seen from the side, culled faces red, normals drawn."""
    w, h = size
    mesh = shapes.icosahedron()
    camera = Camera.look_at((2.6, 1.2, 2.0), (0, 0, 0), fov_y=45, width=w, height=h)
    front = facing(mesh, camera.eye)

    image = rasterkit.render(mesh, camera, "solid", cull="back", color=FRONT).color.copy()
    back_faces = mesh.faces[~front]
    corners = mesh.vertices[back_faces]
    segments_3d(image, camera, corners.reshape(-1, 3), np.roll(corners, -1, axis=1).reshape(-1, 3),
                color=(215, 30, 30))
    label(image, f"cull='back': {front.sum()} faces drawn,")
    label(image, f"{(~front).sum()} culled (red outlines)", (4, 15))

    observer = Camera.look_at((-1.4, 2.2, 4.6), (1.1, 0.5, 0.9), fov_y=42, width=w, height=h)
    colored = replace(mesh, face_colors=np.where(front[:, None], np.float32(FRONT) / 255,
                                                 np.float32(BACK) / 255).astype(np.float32))
    side = rasterkit.render(colored, observer, "solid+wire", cull="none").color.copy()
    centroids = mesh.vertices[mesh.faces].mean(axis=1)
    normal_tips = centroids + 0.45 * mesh.face_normals
    for keep, color in ((front, (20, 120, 40)), (~front, (200, 30, 30))):
        segments_3d(side, observer, centroids[keep], normal_tips[keep], color)
    eye = np.asarray(camera.eye)
    segments_3d(side, observer, np.repeat(eye[None], 2, 0), centroids[[int(np.argmax(front)),
                                                                       int(np.argmin(front))]],
                color=(90, 90, 90))
    dots(side, observer.project(eye[None])[:, :2], 4.0, (0, 0, 0))
    label(side, "n.v > 0 drawn (blue), n.v <= 0 culled (red)")
    label(side, "eye", tuple(observer.project(eye[None])[0, :2] + (6, -6)))
    return grid([image, side], 2)


# --- line rasterization -------------------------------------------------------------------

SEGMENT = (0, 0, 26, 15)  # at x = 13 the ideal line passes exactly half-way: y = 7.5


def line_algorithms(cell: int = 11) -> np.ndarray:
    """The pixels of brute force, DDA and Bresenham on a magnified grid, the ideal segment
    (between the end pixels' centres) in red; orange: where a method leaves Bresenham."""
    x0, y0, x1, y1 = SEGMENT
    width, height = x1 + 1, y1 + 1
    exact = {tuple(p) for p in draw.line(*SEGMENT, method="bresenham").tolist()}
    rows = []
    for method, title in (("naive", "brute force: y = m*x + b, rounded"),
                          ("dda", "DDA: y += m at each step (floating point)"),
                          ("bresenham", "Bresenham: integer decision variable")):
        pixels = draw.line(*SEGMENT, method=method)
        off = [p for p in map(tuple, pixels.tolist()) if p not in exact]
        big = line_grid(pixels, width, height, cell, (x0 + 0.5, y0 + 0.5, x1 + 0.5, y1 + 0.5), marked=off)
        title_bar = label(blank(big.shape[1], 16), f"{title} ({len(off)} pixel off)" if off else title)
        rows.append(np.concatenate([title_bar, big], axis=0))
    return stack(rows)


# --- anti-aliasing ------------------------------------------------------------------------


def antialiasing(small=(58, 44), factor: int = 4) -> np.ndarray:
    """Top: a cube rendered with 1 and 16 samples a pixel; bottom: Bresenham and Wu lines;
    each magnified ``factor`` times."""
    w, h = small
    cube = colored_cube()
    camera = Camera.frame(*cube.bounding_sphere(), width=w, height=h, azimuth=40, elevation=30)
    panels = []
    for samples in (1, 16):
        image = magnify(rasterkit.render(cube, camera, "solid", samples=samples).color, factor)
        panels.append(label(image, f"samples={samples}"))
    angles = np.linspace(0.05, math.pi / 2 - 0.05, 6)
    segments = np.stack([2 + 0 * angles, 2 + 0 * angles, 2 + 52 * np.cos(angles),
                         2 + 40 * np.sin(angles)], 1)
    for aa in (False, True):
        image = draw.lines(blank(w, h), segments, color=(20, 20, 20), aa=aa)
        panels.append(label(magnify(image, factor), f"draw.lines(..., aa={aa})", (100, h * factor - 16)))
    return grid(panels, 2)


# --- the lens camera ----------------------------------------------------------------------


def checker_floor(n: int = 16, size: float = 16.0) -> rasterkit.Mesh:
    """shapes.grid with its cells coloured in a checkerboard."""
    floor = shapes.grid(n, n, size)
    centres = floor.vertices[floor.faces].mean(axis=1)
    cell = size / n
    parity = (np.floor(centres[:, 0] / cell) + np.floor(centres[:, 2] / cell)) % 2
    colors = np.where(parity[:, None] == 0, 0.92, 0.55) * np.ones(3)
    return replace(floor, face_colors=colors.astype(np.float32))


def lens_scene() -> tuple[Scene, list[float]]:
    """Three objects on a checkerboard floor, lit from above; and their depths seen from
    :func:`lens_camera`'s eye (distances along its viewing direction)."""
    scene = Scene(light=(0.3, 1.0, 0.5))
    scene.add(checker_floor(), transform.translate(0, 0, -6))
    places = [(-0.5, 0.3, -0.9), (0.25, 0.25, -2.6), (1.5, 0.3, -7.0)]
    meshes = [shapes.icosphere(2, 0.3), colored_cube(0.5), shapes.icosphere(2, 0.3)]
    for place, mesh, color in zip(places, meshes, ["#e8604c", None, "#3cb371"]):
        scene.add(mesh, transform.translate(*place), color=color)
    camera = lens_camera(1, 1)
    forward = -camera.basis()[2]
    return scene, [float((np.subtract(p, camera.eye)) @ forward) for p in places]


def lens_camera(width: int, height: int, aperture: float = 0.0, focus: float | None = None) -> Camera:
    """The camera of the lens figures: a thin lens when ``aperture`` > 0."""
    return Camera.look_at((0, 1.3, 1.2), (0.4, 0.1, -5), fov_y=40, width=width, height=height,
                          aperture=aperture, focus_distance=focus)


def focus_series(size=(236, 150), samples: int = 48) -> np.ndarray:
    """Pinhole, then a lens of aperture 0.15 focused on each of the three objects."""
    w, h = size
    scene, depths = lens_scene()
    panels = [label(rasterkit.render(scene, lens_camera(w, h), "solid", samples=16).color.copy(),
                    "pinhole (aperture 0)")]
    for focus in depths:
        camera = lens_camera(w, h, aperture=0.15, focus=round(focus, 1))
        image = rasterkit.render(scene, camera, "solid", samples=samples).color.copy()
        panels.append(label(image, f"aperture 0.15, focus_distance {focus:.1f}"))
    return grid(panels, 2)


def aperture_series(size=(156, 110), samples: int = 48) -> np.ndarray:
    """Focused on the middle object: the larger the aperture, the shallower the depth of field."""
    w, h = size
    scene, depths = lens_scene()
    panels = []
    for aperture in (0.03, 0.1, 0.3):
        camera = lens_camera(w, h, aperture=aperture, focus=round(depths[1], 1))
        panels.append(label(rasterkit.render(scene, camera, "solid", samples=samples).color.copy(),
                            f"aperture {aperture:g}"))
    return grid(panels, 3)


# --- vignetting ---------------------------------------------------------------------------


def vignetting(size=(156, 117)) -> np.ndarray:
    """A white wall through an 80° lens with vignette 0, 0.5 and 1, and the centre row of the
    vignette=1 image (red) over cos⁴θ (grey)."""
    w, h = size
    wall = shapes.grid(10, 10, 8.0)
    facing_camera = transform.rotate_x(math.pi / 2)
    camera = Camera.look_at((0, 0, 2), (0, 0, 0), fov_y=80, width=w, height=h)
    scene = Scene(camera).add(wall, facing_camera, color="white")
    panels = []
    for strength in (0.0, 0.5, 1.0):
        image = rasterkit.render(scene, mode="solid+wire", line_color=(200, 200, 200),
                                 vignette=strength).color.copy()
        panels.append(label(image, f"vignette={strength:g}"))
    row = rasterkit.render(scene, mode="solid", vignette=1.0).color[h // 2, :, 0] / 255.0
    f_px = (h / 2) / math.tan(math.radians(40))
    x = np.arange(w) + 0.5 - w / 2
    cos4 = (f_px / np.hypot(f_px, x)) ** 4
    strip = grid(panels, 3)
    cos4, row = np.repeat(cos4, 3), np.repeat(row, 3)
    profile = plot(strip.shape[1], 90, [cos4 + 0.012, cos4, cos4 - 0.012, row],
                   [(175, 175, 175)] * 3 + [(220, 30, 30)], y_range=(0.0, 1.05))
    label(profile, "centre row of vignette=1 (red)", (12, 4))
    label(profile, "over cos^4(theta) (grey)", (12, 16))
    return stack([strip, profile])
