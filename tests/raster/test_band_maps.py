"""The maps a render's band worker makes (rasterkit.raster.kernels.map_rows.band_maps) against the
passes of their own (rasterkit.raster.vision.fill_maps, camera_depth) from the same ids and depth:
normals flat and smooth, scene object ids, the metric depth of ``camera_depth=True``, in
every mode that draws faces, on one thread and two."""

from __future__ import annotations

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, Scene, shapes, transform
from rasterkit.raster import vision


def _scene():
    scene = Scene()
    scene.add(shapes.cube(), transform.translate(-1.6, 0, 0))
    scene.add(shapes.icosphere(3, 0.7), transform.translate(0, 0.2, -0.5))
    scene.add(shapes.torus(0.5, 0.2), transform.compose(transform.rotate_x(1.0), transform.translate(1.5, 0, 0)))
    return scene


# wide enough that both threads draw bands, with rows of no faces above and below
CAMERA = Camera.look_at((0.3, 1.2, 6), (0, 0, 0), fov_y=40, width=320, height=240, near=0.5, far=40)


def _expected(fb_ids, mesh, shading, object_faces):
    """Normals and object ids made by the pass of their own from a copy of raw face ids."""
    class Holder:
        pass
    holder = Holder()
    holder.ids = fb_ids.copy()
    vision.fill_maps(holder, mesh, CAMERA, CAMERA.world_to_raster(), shading, object_faces)
    return holder


@pytest.fixture(params=[1, 2], ids=["1 thread", "2 threads"])
def threads(request):
    rasterkit.set_threads(request.param)
    yield request.param
    rasterkit.set_threads(None)


@pytest.mark.parametrize("mode", ["solid", "hidden", "solid+wire"])
@pytest.mark.parametrize("shading", ["flat", "smooth"])
def test_normals_and_object_ids_equal_those_of_the_pass_of_their_own(threads, mode, shading):
    scene = _scene()
    mesh = scene.world_mesh()
    raw = rasterkit.render(mesh, CAMERA, mode=mode, shading=shading, ids=True).ids  # no maps: raw face ids
    fb = rasterkit.render(scene, CAMERA, mode=mode, shading=shading, ids=True, normals=True)
    expected = _expected(raw, mesh, shading, [len(o.mesh.faces) for o in scene.objects])
    assert (raw >= 0).mean() > 0.1 and (raw < 0).any()
    assert np.array_equal(fb.normals, expected.normals, equal_nan=True)
    assert np.array_equal(fb.object_ids, expected.object_ids)
    assert np.array_equal(fb.ids, expected.ids)  # indices within each object


@pytest.mark.parametrize("mode", ["solid", "hidden", "solid+wire"])
@pytest.mark.parametrize("kind", ["perspective", "orthographic"])
def test_camera_depth_made_while_drawing_equals_the_inverted_depth_buffer(threads, mode, kind):
    mesh = _scene().world_mesh()
    camera = CAMERA if kind == "perspective" else Camera.orthographic(
        (0.3, 1.2, 6), (0, 0, 0), view_height=4, width=320, height=240, near=0.5, far=40)
    plain = rasterkit.render(mesh, camera, mode=mode)
    expected = vision.camera_depth(plain.depth, camera)
    fb = rasterkit.render(mesh, camera, mode=mode, camera_depth=True)
    made = fb.camera_depth()
    assert fb.camera_depth() is made  # kept, not made again
    assert np.array_equal(made, expected)
    assert np.array_equal(fb.depth, plain.depth)  # the depth buffer too (solid: made when read)
    assert np.array_equal(fb.color, plain.color)
    assert (made == 0).any() and (made > 0).mean() > 0.1


def test_camera_depth_with_ids_and_normals_and_a_cleared_buffer(threads):
    mesh = shapes.icosphere(3)
    fb = rasterkit.render(mesh, CAMERA, mode="solid", ids=True, normals=True, camera_depth=True)
    ref = rasterkit.render(mesh, CAMERA, mode="solid", ids=True, normals=True)
    assert np.array_equal(fb.ids, ref.ids) and np.array_equal(fb.normals, ref.normals, equal_nan=True)
    assert np.array_equal(fb.camera_depth(), ref.camera_depth())
    fb.clear()  # the kept metric depth goes with the depth buffer
    assert not fb.camera_depth().any()


@pytest.mark.parametrize("options", [dict(samples=4), dict(mode="wire"), dict(points=[[0.0, 0.0, 0.0]])])
def test_renders_without_band_maps_make_the_camera_depth_when_asked(options):
    mesh = shapes.icosphere(2)
    kwargs = {"mode": "solid", **options}
    fb = rasterkit.render(mesh, CAMERA, camera_depth=True, ids=True, normals=True, **kwargs)
    ref = rasterkit.render(mesh, CAMERA, ids=True, normals=True, **kwargs)
    assert np.array_equal(fb.camera_depth(), ref.camera_depth())
    assert np.array_equal(fb.normals, ref.normals, equal_nan=True)
