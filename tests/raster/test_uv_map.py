"""``render(..., uv=True)``: the texture coordinates at each pixel centre, interpolated
perspective-correctly, against an exact ray–plane intersection through the pixel centre."""

from __future__ import annotations

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, Mesh

#: A square in the plane z = 0 with uv = ((x + 1)/2, (y + 1)/2), seen at a grazing angle.
SQUARE = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float)
PLANE = Mesh(SQUARE, [[0, 1, 2], [0, 2, 3]], texcoords=(SQUARE[:, :2] + 1) / 2)
GRAZING = Camera.look_at(eye=(0.3, -2.5, 0.6), target=(0, 0.5, 0), width=160, height=120)


def _exact_uv(camera, xs, ys):
    """The uv where the ray through each pixel centre meets z = 0."""
    origin, direction = camera.ray(xs + 0.5, ys + 0.5)
    origin = np.broadcast_to(origin, direction.shape)
    t = -origin[:, 2] / direction[:, 2]
    hit = origin + t[:, None] * direction
    return (hit[:, :2] + 1) / 2


def _affine_uv(camera, xs, ys):
    """What interpolating uv linearly in screen space would give (the wrong answer)."""
    corners = camera.project(SQUARE)[:, :2]
    out = np.full((len(xs), 2), np.nan)
    p = np.stack([xs + 0.5, ys + 0.5], axis=1)
    for tri in ([0, 1, 2], [0, 2, 3]):
        a, b, c = corners[tri]
        m = np.array([[b[0] - a[0], c[0] - a[0]], [b[1] - a[1], c[1] - a[1]]])
        st = np.linalg.solve(m, (p - a).T).T
        inside = (st >= -1e-9).all(axis=1) & (st.sum(axis=1) <= 1 + 1e-9)
        uv = PLANE.texcoords[tri][:, :2]
        out[inside] = uv[0] + st[inside, :1] * (uv[1] - uv[0]) + st[inside, 1:] * (uv[2] - uv[0])
    return out


@pytest.mark.parametrize("samples", [1, 4])  # the band worker's maps, and the pass of their own
def test_uv_is_the_ray_plane_intersection_at_each_pixel_centre(samples):
    fb = rasterkit.render(PLANE, GRAZING, "solid", uv=True, cull="none", samples=samples)
    assert fb.uv.shape == (120, 160, 2) and fb.uv.dtype == np.float32
    covered = np.isfinite(fb.uv[..., 0])
    assert covered.sum() > 3000 and np.array_equal(covered, np.isfinite(fb.uv[..., 1]))
    ys, xs = np.nonzero(covered)
    exact = _exact_uv(GRAZING, xs, ys)
    np.testing.assert_allclose(fb.uv[ys, xs], exact, rtol=0, atol=2e-7)  # float32 rounding
    assert fb.ids is None  # made for the uv map, not asked for


def test_nearest_texels_match_the_exact_ones_where_affine_interpolation_fails():
    """A 64x64 checkerboard's texel at each pixel (nearest): the perspective-correct uv
    picks the texel the exact ray hits at 99.5 % or more of the covered pixels (the rest on
    texel borders), screen-space (affine) interpolation visibly does not."""
    fb = rasterkit.render(PLANE, GRAZING, "solid", uv=True, cull="none")
    ys, xs = np.nonzero(np.isfinite(fb.uv[..., 0]))
    texel = lambda uv: np.floor(np.clip(uv, 0, 1 - 1e-12) * 64).astype(int)  # noqa: E731
    exact = texel(_exact_uv(GRAZING, xs, ys))
    assert (texel(fb.uv[ys, xs].astype(np.float64)) == exact).all(axis=1).mean() >= 0.995
    affine = _affine_uv(GRAZING, xs, ys)
    known = np.isfinite(affine[:, 0])
    assert (texel(affine[known]) == exact[known]).all(axis=1).mean() < 0.5


def test_faces_without_texture_coordinates_and_empty_pixels_are_nan():
    bare = Mesh(SQUARE, [[0, 1, 2], [0, 2, 3]])
    fb = rasterkit.render(bare, GRAZING, "solid", uv=True, cull="none", ids=True)
    assert np.isnan(fb.uv).all() and (fb.ids >= 0).any()
    wire = rasterkit.render(PLANE, GRAZING, "wire", uv=True)
    assert np.isnan(wire.uv).all()


def test_a_distorted_camera_resamples_the_uv_map():
    k, r, t = GRAZING.to_opencv()
    lens = Camera.from_opencv(k, r, t, 160, 120, near=GRAZING.near, far=GRAZING.far, dist=(0.05, 0, 0, 0, 0))
    fb = rasterkit.render(PLANE, lens, "solid", uv=True, cull="none")
    covered = np.isfinite(fb.uv[..., 0])
    assert covered.sum() > 2000 and (fb.uv[covered] >= -1e-6).all() and (fb.uv[covered] <= 1 + 1e-6).all()


def test_a_scene_keeps_its_objects_texture_coordinates():
    scene = rasterkit.Scene(GRAZING).add(PLANE, rasterkit.transform.translate(0, 0, 0))
    fb = rasterkit.render(scene, mode="solid", uv=True, cull="none")
    alone = rasterkit.render(PLANE, GRAZING, "solid", uv=True, cull="none")
    np.testing.assert_array_equal(fb.uv, alone.uv)


def test_llvmpipe_samples_the_texels_that_the_uv_map_names(monkeypatch):
    """Mesa llvmpipe drawing the checkerboard plane with GL_NEAREST picks, at every covered
    pixel, the texel at rasterkit's uv (the GL side: benchmarks/texture_peer.py)."""
    pytest.importorskip("moderngl")
    from support.paths import ROOT

    monkeypatch.syspath_prepend(str(ROOT))  # the benchmark suite is not installed with the package
    from benchmarks.peers import Llvmpipe, PeerUnavailable
    from benchmarks.texture_peer import TexturedGL

    try:
        gl = TexturedGL(Llvmpipe())
    except PeerUnavailable as why:
        pytest.skip(str(why))
    checker = ((np.arange(64)[:, None] + np.arange(64)[None, :]) % 2 * 255).astype(np.uint8)
    image = np.stack([checker, 255 - checker, np.full_like(checker, 128)], axis=2)
    faces = PLANE.faces
    drawn = gl.draw(gl.upload(SQUARE, faces, PLANE.texcoords[faces], image, GRAZING, filter="nearest",
                              shading="unlit"), cull=False)
    fb = rasterkit.render(PLANE, GRAZING, "solid", uv=True, cull="none")
    ys, xs = np.nonzero(np.isfinite(fb.uv[..., 0]))
    uv = fb.uv[ys, xs].astype(np.float64)
    column = np.clip(np.floor(uv[:, 0] * 64), 0, 63).astype(int)
    row = 63 - np.clip(np.floor(uv[:, 1] * 64), 0, 63).astype(int)  # v up, the image's row 0 at the top
    agree = (np.abs(image[row, column].astype(int) - drawn[ys, xs].astype(int)).max(axis=1) <= 1).mean()
    assert agree >= 0.995, agree


def test_a_seam_keeps_each_faces_own_coordinates():
    """Two faces sharing their corners, each with texture coordinates of its own (a UV seam
    along their shared side): each face's pixels get its own, nothing averaged across."""
    own = np.array([[0.1, 0.2], [0.7, 0.9]])
    seam = Mesh(SQUARE, [[0, 1, 2], [0, 2, 3]], uv=own, uv_index=[[0, 0, 0], [1, 1, 1]])
    for scene in (False, True):
        fb = rasterkit.render(rasterkit.Scene(GRAZING).add(seam) if scene else seam, GRAZING if not scene else None,
                              "solid", uv=True, ids=True, cull="none")
        for face in (0, 1):
            seen = fb.ids == face
            assert seen.sum() > 500
            np.testing.assert_allclose(fb.uv[seen], np.broadcast_to(own[face], (seen.sum(), 2)), atol=1e-6)
