"""Cut-outs and normal maps against independent references: which face a ray through each
pixel centre sees when the front plane's alpha is below one half there, and Lambert's law of
the normal that a tangent-space normal map gives, worked out in NumPy from each pixel's
texture coordinates (ray casting)."""

from __future__ import annotations

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, Material, Mesh, Texture

SQUARE = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float)
FACES = np.array([[0, 1, 2], [0, 2, 3]])
UV = (SQUARE[:, :2] + 1) / 2
CAMERA = Camera.look_at(eye=(0.3, -0.8, 3.0), target=(0, 0, 0), width=160, height=120)
HOLES = np.zeros((8, 8, 4), np.uint8)
HOLES[..., :3] = 200
HOLES[..., 3] = np.where((np.arange(8)[:, None] + np.arange(8)) % 2 == 0, 255, 20)  # every other texel cut out


def _ray_uv(camera, xs, ys, z=0.0):
    origin, direction = camera.ray(xs + 0.5, ys + 0.5)
    t = (z - origin[..., 2]) / direction[..., 2]
    point = origin + t[..., None] * direction
    return (point[..., :2] + 1) / 2


def _holed_scene(material):
    """A square with ``material`` at z = 0 in front of a larger untextured one at z = -0.5."""
    back = SQUARE * 3 + [0, 0, -0.5]
    vertices = np.concatenate([SQUARE, back])
    faces = np.concatenate([FACES, FACES + 4])
    uv = np.concatenate([UV, UV])
    return Mesh(vertices, faces, uv=uv, face_materials=np.array([0, 0, -1, -1], np.int32), material_names=("m",),
                materials=(material,))


@pytest.mark.parametrize("source", ["diffuse alpha", "opacity map"])
def test_a_cut_out_face_lets_what_is_behind_show_in_colour_depth_and_ids(source):
    if source == "diffuse alpha":
        material = Material(diffuse_map=Texture(HOLES, filter="nearest"))
    else:  # the alpha as a grey opacity map (its first channel), under an opaque diffuse map
        grey = np.repeat(HOLES[..., 3:], 3, axis=2)
        material = Material(diffuse_map=Texture(HOLES[..., :3], filter="nearest"),
                            opacity_map=Texture(grey, filter="nearest"))
    mesh = _holed_scene(material)
    fb = rasterkit.render(mesh, CAMERA, "solid", ids=True, texture_filter="nearest")
    ys, xs = np.nonzero(fb.ids >= 0)
    uv = _ray_uv(CAMERA, xs, ys)
    inside = np.all((uv > 0) & (uv < 1), axis=1)
    texel = np.floor(uv * 8).astype(int)
    kept = inside & ((texel.sum(axis=1) % 2) == 1)  # alpha 255: (row from the bottom 7 - j) parity
    front = fb.ids[ys, xs] < 2
    assert inside.sum() > 3000 and kept.sum() > 1000
    assert np.mean(front == kept) >= 0.995  # the rest: pixels whose ray meets a texel border
    # the depth buffer (drawn when read, by a pass of its own) and the colours agree
    back_only = rasterkit.render(Mesh(mesh.vertices, mesh.faces[2:]), CAMERA, "solid")
    holes = ~front
    assert np.array_equal(fb.depth[ys[holes], xs[holes]], back_only.depth[ys[holes], xs[holes]])
    assert np.array_equal(fb.color[ys[holes], xs[holes]], back_only.color[ys[holes], xs[holes]])
    # without textures nothing is cut out
    plain = rasterkit.render(mesh, CAMERA, "solid", ids=True, textures=False)
    assert np.all(plain.ids[ys[inside], xs[inside]] < 2)


def test_cut_outs_in_hidden_line_and_multi_sample_renders():
    mesh = _holed_scene(Material(diffuse_map=Texture(HOLES, filter="nearest")))
    hidden = rasterkit.render(mesh, CAMERA, "hidden", texture_filter="nearest").color
    no_holes = rasterkit.render(mesh, CAMERA, "hidden", textures=False).color
    assert (hidden != no_holes).any(axis=2).sum() > 20  # the back square's edges show through the holes
    fb = rasterkit.render(mesh, CAMERA, "solid", ids=True, texture_filter="nearest")
    averaged = rasterkit.render(mesh, CAMERA, "solid", samples=8, texture_filter="nearest").color.astype(int)
    one = fb.color.astype(int)
    # away from the texel borders, 8 samples see what the pixel centre sees
    ys, xs = np.nonzero(fb.ids >= 0)
    uv = _ray_uv(CAMERA, xs, ys) * 8
    interior = np.all(np.abs(uv - np.round(uv)) > 0.2, axis=1) & np.all((uv > 0.5) & (uv < 7.5), axis=1)
    assert interior.sum() > 1000
    assert np.abs(averaged[ys[interior], xs[interior]] - one[ys[interior], xs[interior]]).max() <= 2


def _normal_map(normals):
    """A tangent-space normal map image (H, W, 3) uint8 of unit vectors."""
    return np.floor((normals + 1.0) / 2.0 * 255.0 + 0.5).astype(np.uint8)


@pytest.mark.parametrize("shading", ["flat", "smooth"])
def test_a_normal_map_bends_the_normal_in_tangent_space(shading):
    """A square facing +z, u along +x and v along +y (its tangent frame is the world's),
    with random tangent-space normals (nearest filtering): each pixel is lit by Lambert's law
    of its texel's normal (decoded, its x and y times ``bump_scale``, normalised), in world
    space, under the material's diffuse colour."""
    rng = np.random.default_rng(4)
    n = rng.normal(size=(6, 6, 3))
    n[..., 2] = np.abs(n[..., 2]) + 0.5
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    image = _normal_map(n)
    material = Material(diffuse=(0.9, 0.7, 0.5), normal_map=Texture(image, filter="nearest"), bump_scale=0.8)
    mesh = Mesh(SQUARE, FACES, uv=UV, face_materials=np.zeros(2, np.int32), material_names=("m",),
                materials=(material,))
    light = np.array([0.4, -0.3, 0.8])
    fb = rasterkit.render(mesh, CAMERA, "solid", ids=True, shading=shading, light=light, texture_filter="nearest")
    ys, xs = np.nonzero(fb.ids >= 0)
    uv = _ray_uv(CAMERA, xs, ys)
    i = np.clip(np.floor(uv[:, 0] * 6).astype(int), 0, 5)
    j = np.clip(np.floor(uv[:, 1] * 6).astype(int), 0, 5)
    decoded = image[5 - j, i] / 255.0 * 2.0 - 1.0
    decoded[:, :2] *= 0.8
    decoded /= np.linalg.norm(decoded, axis=1, keepdims=True)
    cos = np.maximum(decoded @ (light / np.linalg.norm(light)), 0.0)
    expected = np.floor(np.array([0.9, 0.7, 0.5]) * 255 * (0.25 + 0.75 * cos)[:, None] + 0.5)
    difference = np.abs(fb.color[ys, xs].astype(int) - expected).max(axis=1)
    assert len(xs) > 3000
    assert np.mean(difference <= 1) >= 0.99  # the rest: rays meeting texel borders
    flat_normal = rasterkit.render(Mesh(SQUARE, FACES), CAMERA, "solid", light=light,
                                   color=(230, 179, 128)).color[ys, xs].astype(int)
    assert np.mean(np.abs(fb.color[ys, xs].astype(int) - flat_normal).max(axis=1) > 8) > 0.5


def test_a_flat_normal_map_changes_nothing_on_a_curved_mesh():
    """A normal map of (0, 0, 1) everywhere leaves smooth shading's normals as they are:
    per-pixel Lambert of the interpolated normal, close to Gouraud's interpolated Lambert."""
    ball = rasterkit.shapes.icosphere(3)
    x, y, z = ball.vertices.T
    uv = np.stack([np.arctan2(y, x) / (2 * np.pi) + 0.5, np.arccos(np.clip(z, -1, 1)) / np.pi], 1)
    flat_map = _normal_map(np.broadcast_to([0.0, 0.0, 1.0], (4, 4, 3)))
    material = Material(normal_map=Texture(flat_map))
    mesh = Mesh(ball.vertices, ball.faces, uv=uv, face_materials=np.zeros(len(ball.faces), np.int32),
                material_names=("m",), materials=(material,))
    camera = Camera.look_at((2.0, 1.5, 3.0), (0, 0, 0), width=200, height=150)
    mapped = rasterkit.render(mesh, camera, "solid", shading="smooth", ids=True)
    gouraud = rasterkit.render(mesh, camera, "solid", shading="smooth", textures=False, color=(204, 204, 204))
    covered = mapped.ids >= 0
    difference = np.abs(mapped.color.astype(int) - gouraud.color.astype(int))[covered]
    assert covered.sum() > 5000 and difference.mean() < 1.5 and difference.max() <= 12


def test_an_object_space_normal_map_is_the_normal():
    """``normal_space="object"``: the map's vector is the normal, whatever the face's: a square
    turned away from the light but mapped with normals towards it is lit as they are."""
    n = np.array([0.6, -0.48, 0.64])
    image = _normal_map(np.broadcast_to(n, (2, 2, 3)))
    material = Material(diffuse=(1.0, 1.0, 1.0), normal_map=Texture(image, filter="nearest"), normal_space="object")
    tilted = SQUARE @ rasterkit.transform.rotate_y(1.2)[:3, :3].T  # its own normal far from n
    mesh = Mesh(tilted, FACES, uv=UV, face_materials=np.zeros(2, np.int32), material_names=("m",),
                materials=(material,))
    light = np.array([0.2, -0.3, 0.9]) / np.linalg.norm([0.2, -0.3, 0.9])
    fb = rasterkit.render(mesh, CAMERA, "solid", ids=True, light=light, cull="none")
    decoded = image[0, 0] / 255.0 * 2.0 - 1.0
    decoded /= np.linalg.norm(decoded)
    expected = np.floor(255 * (0.25 + 0.75 * max(decoded @ light, 0.0)) + 0.5)
    covered = fb.ids >= 0
    assert covered.sum() > 1000
    assert np.abs(fb.color[covered].astype(int) - expected).max() <= 1


def test_a_grey_bump_map_is_a_height_map():
    """A grey ``normal_map`` holds heights: a ramp rising along ``u`` by 32 codes a texel tilts
    the normal against ``u`` by its slope times HEIGHT_SLOPE (central differences), lit by
    Lambert's law; its texels at the clamped edges see half the slope."""
    from rasterkit.raster.texturing import HEIGHT_SLOPE

    ramp = np.repeat(np.repeat((np.arange(8) * 32).astype(np.uint8)[None, :, None], 4, axis=0), 3, axis=2)
    material = Material(diffuse=(1.0, 1.0, 1.0), normal_map=Texture(ramp, filter="nearest", wrap="clamp"),
                        bump_scale=0.5)
    mesh = Mesh(SQUARE, FACES, uv=UV, face_materials=np.zeros(2, np.int32), material_names=("m",),
                materials=(material,))
    light = np.array([0.0, 0.0, 1.0])
    fb = rasterkit.render(mesh, CAMERA, "solid", ids=True, light=light, texture_filter="nearest")
    ys, xs = np.nonzero(fb.ids >= 0)
    column = np.floor(_ray_uv(CAMERA, xs, ys)[:, 0] * 8).astype(int)
    interior = (column >= 1) & (column <= 6)
    stored = np.array([-HEIGHT_SLOPE * 32 / 255, 0.0, 1.0]) / np.linalg.norm([-HEIGHT_SLOPE * 32 / 255, 0.0, 1.0])
    code = np.floor((stored + 1) / 2 * 255 + 0.5) / 255 * 2 - 1  # as the derived map stores it
    bent = np.array([code[0] * 0.5, code[1] * 0.5, code[2]])  # the bump scale bends its x and y
    expected = np.floor(255 * (0.25 + 0.75 * bent[2] / np.linalg.norm(bent)) + 0.5)
    assert interior.sum() > 1500
    assert np.abs(fb.color[ys[interior], xs[interior]].astype(int) - expected).max() <= 1
    flat = rasterkit.render(Mesh(SQUARE, FACES), CAMERA, "solid", light=light, color=(255, 255, 255)).color
    assert (np.abs(flat[ys[interior], xs[interior]].astype(int) - expected) >= 10).all()  # visibly bent


def test_materials_sharing_a_data_map_share_its_row():
    """Two materials with the same opacity map (read as data: a linear copy of it) look it up
    through one row of the band worker's texture arrays, not a copy each."""
    grey = Texture(np.repeat(HOLES[..., 3:], 3, axis=2), filter="nearest")
    skin = Texture(HOLES[..., :3], filter="nearest")
    a, b = Material("a", diffuse_map=skin, opacity_map=grey), Material("b", diffuse_map=skin, opacity_map=grey)
    mesh = Mesh(SQUARE, FACES, uv=UV, face_materials=np.array([0, 1], np.int32), material_names=("a", "b"),
                materials=(a, b))
    layout = mesh.textured
    assert len(layout.textures) == 2  # the diffuse map and the opacity map, each once
    assert layout.face_alpha[0] == layout.face_alpha[1] >= 0
