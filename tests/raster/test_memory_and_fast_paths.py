"""Recycled framebuffer memory, the lazy depth buffer, and the fast paths added for speed,
each against the slower path it replaces (bit for bit) or a hand-made expectation."""

import dataclasses

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, Mesh, shapes
from rasterkit.runtime import threads as _threads
from rasterkit.runtime import scratch as _memory
from rasterkit.raster.edge_pass import draw_edges, scratch
from rasterkit.runtime.jit import readonly
from rasterkit.raster.framebuffer import Framebuffer
from rasterkit.raster.kernels import edge_setup as line_kernels
from rasterkit.raster.kernels.edges import MODE_DEPTH_TEST, MODE_PLAIN
from rasterkit.raster.kernels.normals import face_normals
from rasterkit.raster.kernels.shade import flat_packed, lambert, pack_colors
from rasterkit.raster.vertex import transform_points
from rasterkit.raster.triangles import FlatLambert, rasterize_triangles

BIG = (1024, 512)  # 2 MiB of RGBA: above _memory.MIN_BYTES, so recycled


def test_a_block_is_reused_only_when_nothing_refers_to_it():
    first = _memory.take(BIG, np.uint32)
    address = first.__array_interface__["data"][0]
    view = first[10:20]
    del first
    second = _memory.take(BIG, np.uint32)  # the first block is still held by `view`
    assert second.__array_interface__["data"][0] != address
    view[:] = 7
    assert not np.shares_memory(view, second)
    del view
    third = _memory.take(BIG, np.uint32)  # now the first block is idle
    assert third.__array_interface__["data"][0] == address
    assert not np.shares_memory(second, third)


def test_small_requests_and_idle_memory_are_bounded():
    small = _memory.take((10, 10), np.float64)
    assert small.base is None  # plain allocation
    blocks = [_memory.take(BIG, np.uint32) for _ in range(3)]
    del blocks
    assert 0 < _memory.idle_bytes() <= _memory.MAX_IDLE_BYTES
    _memory.release()
    assert _memory.idle_bytes() == 0


def test_framebuffers_never_share_memory_while_alive():
    frames = [Framebuffer(640, 480, background="red") for _ in range(3)]
    for a in frames:
        for b in frames:
            if a is not b:
                assert not np.shares_memory(a.color, b.color)
                assert not np.shares_memory(a.depth, b.depth)
    kept = frames[0].color
    frames = None
    again = Framebuffer(640, 480, background="blue")
    assert np.all(kept == [255, 0, 0]) and np.all(again.color == [0, 0, 255])


def test_depth_is_made_on_first_use_and_is_farthest():
    mesh = shapes.cube()
    camera = Camera.frame(*mesh.bounding_sphere(), width=40, height=30)
    fb = rasterkit.render(mesh, camera, mode="wire")
    assert fb._depth is None  # a wireframe never needs it
    assert fb.depth.shape == (30, 40) and np.all(np.isposinf(fb.depth))
    fb.depth[3, 4] = 0.5
    assert fb.depth[3, 4] == 0.5  # the same array from then on
    fb.clear()
    assert np.all(np.isposinf(fb.depth))
    with pytest.raises(ValueError):
        fb.depth = np.zeros((2, 2), np.float32)


@pytest.mark.parametrize("width", [1, 7, 13, 64, 97])
@pytest.mark.parametrize("background", [(1, 2, 3), (9, 8, 7, 6)])
def test_wire_render_clears_every_pixel_to_an_uneven_background(width, background):
    mesh = shapes.tetrahedron()
    camera = Camera.frame(*mesh.bounding_sphere(), width=width, height=11)
    for _ in range(2):  # the second frame reuses the first one's memory
        fb = rasterkit.render(mesh, camera, mode="wire", background=background, line_color=(200, 201, 202))
        line = np.all(fb.color[..., :3] == [200, 201, 202], axis=2)
        assert np.all(fb.color[~line] == background[: fb.color.shape[2]])
        fb.color[...] = 77


def test_flat_packed_equals_normals_lambert_and_pack():
    rng = np.random.default_rng(5)
    positions = rng.normal(size=(60, 3))
    faces = rng.integers(0, 60, size=(200, 3))
    faces[:5, 1] = faces[:5, 0]  # degenerate faces: ambient only
    base = rng.uniform(0, 1, size=(200, 3)).astype(np.float32)
    light = np.array([0.48, -0.6, 0.64])
    for two_sided in (False, True):
        for colours in (base, base[:1]):
            normals = face_normals(positions, faces).astype(np.float32).astype(np.float64)
            expected = pack_colors(lambert(normals, colours * np.float32(255), light,
                                           np.zeros((0, 3)), False, 0.25, two_sided))
            got = flat_packed(positions, faces, colours, np.float32(255), light, 0.25, two_sided)
            np.testing.assert_array_equal(got, expected)
    positions[faces[7, 2]] = np.nan  # a NaN corner: ambient only, like a degenerate face
    positions[faces[9, 1]] = np.inf  # an infinite one too
    ambient = pack_colors(base * np.float32(255) * np.float32(0.25))
    for two_sided in (False, True):
        got = flat_packed(positions, faces, base, np.float32(255), light, 0.25, two_sided)
        assert got[7] == ambient[7] and got[9] == ambient[9] and got[0] == ambient[0]


def test_rasterize_triangles_takes_packed_face_colours():
    clip = np.array([[1, 1, 0.5, 1], [9, 1, 0.5, 1], [1, 7, 0.5, 1]], np.float64)
    faces = np.array([[0, 2, 1]], np.int64)  # counter-clockwise on screen (y down)
    as_floats = np.zeros((8, 10, 3), np.uint8)
    as_packed = np.zeros((8, 10, 3), np.uint8)
    depth = np.full((8, 10), np.inf, np.float32)
    rasterize_triangles(as_floats, depth.copy(), clip, faces, face_colors=np.array([[10, 20, 30]], np.float32), cull="none")
    packed = np.array([10 | 20 << 8 | 30 << 16 | 255 << 24], np.uint32)
    rasterize_triangles(as_packed, depth.copy(), clip, faces, face_colors=packed, cull="none")
    assert as_floats.any() and np.array_equal(as_floats, as_packed)
    with pytest.raises(ValueError):
        rasterize_triangles(as_packed, depth.copy(), clip, faces, face_colors=np.zeros(2, np.uint32))


def test_balanced_bands_cover_every_row_once_and_follow_the_work():
    counts = np.zeros((3, 100), np.int64)
    counts[1, 80:90] = 1000  # all the work in rows 640..719
    bounds = line_kernels.balanced_bands(line_kernels.band_work(counts, 0, 800), 4, 800)
    assert bounds[0] == 0 and bounds[-1] == 800 and np.all(np.diff(bounds) >= 0)
    assert 640 <= bounds[1] <= bounds[2] <= bounds[3] <= 720
    even = line_kernels.balanced_bands(np.zeros(10, np.int64), 3, 75)
    assert even.tolist() == [0, 25, 50, 75]
    # work per row alone: equal shares of the rows, in whole bins of ROWS_PER_BIN (8) rows
    rows = line_kernels.balanced_bands(line_kernels.band_work(np.zeros((2, 100), np.int64), 5, 800), 4, 800)
    assert rows.tolist() == [0, 200, 400, 600, 800]
    # 80 in each of bins 80..89 plus 1 for each row: the split leaves half of the total
    # above it, within one bin's work
    counts[1, 80:90] = 80
    half = line_kernels.balanced_bands(line_kernels.band_work(counts, 1, 800), 2, 800)
    work = counts.sum(axis=0) + 8
    assert half[1] % 8 == 0 and abs(work[: half[1] // 8].sum() - work.sum() / 2) <= work.max()


def test_plain_setup_records_match_the_general_path_on_random_edges():
    """The per-edge records of the plain fast path draw exactly what the general path draws."""
    rng = np.random.default_rng(17)
    height, width = 60, 80
    clip = np.empty((400, 4))
    clip[:, 3] = rng.uniform(0.5, 2.0, 400)
    clip[:, 0] = rng.uniform(-10, 90, 400) * clip[:, 3]
    clip[:, 1] = rng.uniform(-10, 70, 400) * clip[:, 3]
    clip[:, 2] = rng.uniform(0.0, 1.0, 400) * clip[:, 3]
    edges = rng.integers(0, 400, size=(1500, 2))
    rgba = np.array([255, 255, 255], np.uint8)
    fast = np.zeros((height, width, 3), np.uint8)
    draw_edges(fast, np.empty((0, 0), np.float32), clip, edges, rgba, MODE_PLAIN, n_bands=3)
    # The depth-test mode takes the general path for every edge; an infinitely far depth
    # buffer lets every pixel through.
    general = np.zeros((height, width, 3), np.uint8)
    far = np.full((height, width), np.inf, np.float32)
    draw_edges(general, far, clip, edges, rgba, MODE_DEPTH_TEST, n_bands=3)
    assert fast.any() and np.array_equal(fast, general)


def test_mesh_arrays_are_read_only_and_not_shared_with_the_callers():
    """What Mesh checked stays true: its arrays cannot be written, and writing to the arrays
    it was made from does not reach it (the renderer trusts a Mesh's indices and keeps its
    face normals)."""
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float64)
    faces = np.array([[0, 1, 2], [0, 3, 1]], np.int64)
    mesh = Mesh(vertices, faces, vertex_colors=np.ones((4, 3), np.float32))
    for name in ("vertices", "faces", "edges", "lines", "vertex_colors"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(mesh, name)[0] = 0
    faces[0, 2] = 99
    vertices[0, 0] = np.nan
    assert mesh.faces[0, 2] == 2 and mesh.vertices[0, 0] == 0
    assert vertices.flags.writeable and faces.flags.writeable
    view = readonly(faces)  # how the renderer hands arrays to the kernels
    assert not view.flags.writeable and faces.flags.writeable and np.shares_memory(view, faces)
    moved = dataclasses.replace(mesh, vertices=mesh.vertices + 1)  # how to move a mesh
    assert np.array_equal(moved.edges, mesh.edges) and moved.vertices[0, 0] == 1


def test_mesh_face_normals_are_unit_right_hand_normals_kept_per_mesh():
    vertices = np.array([[0, 0, 0], [2, 0, 0], [0, 3, 0], [0, 0, 1], [5, 5, 5]], np.float64)
    faces = np.array([[0, 1, 2], [0, 3, 1], [0, 1, 1]], np.int64)  # last: degenerate
    mesh = Mesh(vertices, faces)
    expected = np.array([[0, 0, 1], [0, 1, 0], [0, 0, 0]], np.float32)
    assert mesh.face_normals.dtype == np.float32
    assert np.array_equal(mesh.face_normals, expected)
    assert mesh.face_normals is mesh.face_normals and not mesh.face_normals.flags.writeable
    torus = shapes.torus()
    corners = [torus.vertices[torus.faces[:, k]] for k in range(3)]
    cross = np.cross(corners[1] - corners[0], corners[2] - corners[0])
    want = cross / np.linalg.norm(cross, axis=1, keepdims=True)
    assert np.allclose(torus.face_normals, want, atol=1e-6)


def test_solid_render_clears_colour_with_the_shared_pattern_fill():
    """The triangle path clears through the same word-wide fill: every pixel the cube does
    not cover is the (uneven) background, also on recycled memory at an odd width."""
    mesh = shapes.cube()
    camera = Camera.frame(*mesh.bounding_sphere(), width=37, height=23)
    for _ in range(2):
        fb = rasterkit.render(mesh, camera, mode="solid", background=(3, 5, 7), ids=True)
        empty = fb.ids < 0
        assert empty.any() and (~empty).any()
        assert np.all(fb.color[empty] == [3, 5, 7]) and np.all(np.isposinf(fb.depth[empty]))
        fb.color[...] = 99


def _random_edges(rng, n_vertices, n_edges, height, width):
    """Homogeneous vertices, some outside the image (general path), and random edges."""
    clip = np.empty((n_vertices, 4))
    clip[:, 3] = rng.uniform(0.5, 2.0, n_vertices)
    clip[:, 0] = rng.uniform(-10, width + 10, n_vertices) * clip[:, 3]
    clip[:, 1] = rng.uniform(-10, height + 10, n_vertices) * clip[:, 3]
    clip[:, 2] = rng.uniform(0.0, 1.0, n_vertices) * clip[:, 3]
    return clip, rng.integers(0, n_vertices, size=(n_edges, 2))


@pytest.mark.parametrize("channels", [3, 4])
@pytest.mark.parametrize("width", [80, 83])  # 83: mask words straddle the rows and bands
def test_marked_wire_path_equals_drawing_into_colour(channels, width):
    """Plain edges with a background go through the byte mask and the 8-pixel paint; the
    image equals the general path drawn over a background-filled buffer."""
    rng = np.random.default_rng(5)
    height = 61
    clip, edges = _random_edges(rng, 300, 1200, height, width)
    rgba = np.array([10, 200, 30, 255][:channels], np.uint8)
    background = np.array([250, 251, 252, 0][:channels], np.uint8)
    far = np.full((height, width), np.inf, np.float32)
    for n_bands in (1, 3):
        marked = np.full((height, width, channels), 77, np.uint8)  # garbage: must be cleared
        memory = scratch(len(clip), len(edges), height * width, MODE_PLAIN, take=np.empty)
        memory.mask[:] = 3  # garbage in the mask too: each band clears its part
        draw_edges(marked, None, clip, edges, rgba, MODE_PLAIN, 0.0, background, n_bands=n_bands,
                       memory=memory)
        expected = np.empty((height, width, channels), np.uint8)
        expected[...] = background
        draw_edges(expected, far, clip, edges, rgba, MODE_DEPTH_TEST, n_bands=1)
        assert (expected == rgba).all(axis=2).any()
        assert np.array_equal(marked, expected)


def test_short_edges_in_every_octant_mark_the_same_pixels_as_the_general_path():
    """Lines of 1 to 10 pixels take the unrolled steps of the mask (4 and 8 steps, the last
    pixel marked again); each is drawn alone, from a pixel centre and from off-centre ends,
    and must equal the general path's pixels."""
    width, height = 40, 30
    offsets = [(dx, dy) for dx in range(-9, 10) for dy in range(-9, 10)]
    rgba = np.array([10, 200, 30], np.uint8)
    background = np.array([250, 251, 252], np.uint8)
    far = np.full((height, width), np.inf, np.float32)
    for centre in ((20.5, 15.5), (20.3, 15.8), (19.9, 14.6)):
        for dx, dy in offsets:
            clip = np.array([[centre[0], centre[1], 0.5, 1.0], [centre[0] + dx, centre[1] + dy, 0.5, 1.0]])
            edges = np.array([[0, 1]])
            marked = np.zeros((height, width, 3), np.uint8)
            memory = scratch(2, 1, height * width, MODE_PLAIN, take=np.empty)
            draw_edges(marked, None, clip, edges, rgba, MODE_PLAIN, 0.0, background, n_bands=1,
                       memory=memory)
            expected = np.empty((height, width, 3), np.uint8)
            expected[...] = background
            draw_edges(expected, far, clip, edges, rgba, MODE_DEPTH_TEST, n_bands=1)
            drawn = (expected == rgba).all(axis=2).sum()
            assert drawn == max(abs(dx), abs(dy)) + 1 or centre != (20.5, 15.5)
            assert np.array_equal(marked, expected), (centre, dx, dy)


def _work_of(recs, height, start, stop, stride):
    """The sampled work of records start .. stop - 1 per ROWS_PER_BIN rows, in NumPy."""
    work = np.zeros((height + line_kernels.ROWS_PER_BIN - 1) // line_kernels.ROWS_PER_BIN, np.int64)
    for e in range(start, stop):
        rows = int(recs[2, e])
        if e % stride == 0 and rows >= 0:
            middle = ((rows & 0xFFFF) + (rows >> 16)) // 2
            work[middle // line_kernels.ROWS_PER_BIN] += stride * ((int(recs[1, e]) & 0x7FFF) + 1
                                                                    + line_kernels._EDGE_WORK)
    return work


def test_plain_setup_samples_the_work_of_every_stride_th_record_of_a_large_chunk():
    """Beyond _WORK_SAMPLES records of a chunk, every s-th edge counts s times; the block
    summaries hold the rows of their plain records and count the general ones."""
    rng = np.random.default_rng(4)
    height, width = 700, 900
    m = line_kernels.SETUP_CHUNKS * 3 * line_kernels._WORK_SAMPLES + 1234
    pixels = rng.integers(0, width, 3000) | rng.integers(0, height, 3000) << 32
    pixels[rng.random(3000) < 0.05] = -1  # vertices outside: their edges take the general path
    edges = rng.integers(0, 3000, (m, 2))
    recs = np.zeros((line_kernels.REC_FIELDS, m), np.int32)
    blocks = np.zeros((line_kernels.BLOCK_FIELDS, line_kernels.n_blocks(m)), np.int32)
    work = np.zeros((line_kernels.SETUP_CHUNKS, (height + 7) // 8), np.int64)
    line_kernels.plain_setup(0, np.zeros(1, np.int64), pixels, readonly(edges), width, height, recs, blocks, work)
    n = line_kernels.n_blocks(m)
    chunk = 5  # any chunk: its blocks, its sampled records
    start = n * chunk // line_kernels.SETUP_CHUNKS * line_kernels.BLOCK
    stop = n * (chunk + 1) // line_kernels.SETUP_CHUNKS * line_kernels.BLOCK
    stride = (stop - start) // line_kernels._WORK_SAMPLES
    assert stride == 3
    assert np.array_equal(work[chunk], _work_of(recs, height, start, stop, stride))
    rows = recs[2].astype(np.int64)
    for b in (0, 7, n - 1):
        r = rows[b * line_kernels.BLOCK:(b + 1) * line_kernels.BLOCK]
        plain = r[r >= 0]
        assert blocks[2, b] == np.sum(r < 0) > 0
        assert blocks[0, b] == (plain & 0xFFFF).min() and blocks[1, b] == (plain >> 16).max()


def test_record_work_counts_pixels_and_edges_by_middle_row():
    clip = np.array([[2.5, 3.5, 0.5, 1.0], [12.5, 7.5, 0.5, 1.0], [4.5, 30.5, 0.5, 1.0],
                     [-5.0, 1.0, 0.5, 1.0]])
    edges = np.array([[0, 1], [1, 2], [0, 3]])  # the last one leaves the image: general path
    memory = scratch(4, 3, 0, MODE_PLAIN, take=np.empty)
    proj, pixels, recs = memory.proj, memory.pixels, memory.recs
    counts = np.zeros((line_kernels.VERTEX_CHUNKS, 5), np.int64)
    line_kernels.project_vertices(0, np.zeros(1, np.int64), clip, proj, pixels, 20, 40, counts,
                                  readonly(np.empty((0, 3))), readonly(np.eye(4)))
    assert pixels.tolist() == [2 | 3 << 32, 12 | 7 << 32, 4 | 30 << 32, -1]
    work = np.zeros((line_kernels.SETUP_CHUNKS, 5), np.int64)
    line_kernels.plain_setup(0, np.zeros(1, np.int64), pixels, readonly(edges), 20, 40, recs, memory.blocks, work)
    assert recs[2].tolist() == [3 | 7 << 16, 7 | 30 << 16, -1]  # rows jlo | jhi << 16
    assert memory.blocks[:, 0].tolist() == [3, 30, 1]  # one block: rows 3..30, one general edge
    work = work.sum(axis=0)
    expected = np.zeros_like(work)
    per_edge = line_kernels._EDGE_WORK
    expected[(3 + 7) // 2 // line_kernels.ROWS_PER_BIN] += 11 + per_edge  # 10 steps in x, 11 pixels
    expected[(7 + 30) // 2 // line_kernels.ROWS_PER_BIN] += 24 + per_edge  # 23 steps in y
    assert np.array_equal(work, expected)


def test_camera_matrix_is_computed_once_and_cannot_be_changed_through_a_result():
    camera = Camera.frame((0, 0, 0), 1.0, width=40, height=30)
    first = camera.matrix()
    first[...] = 0.0  # the caller's copy
    again = camera.matrix()
    assert np.array_equal(again, rasterkit.transform.compose(*(m for _, m in camera.chain())))
    k = camera.world_to_raster()
    assert camera.world_to_raster() is k and not k.flags.writeable
    other = camera.with_size(80, 30)  # a new camera has its own matrix
    assert not np.array_equal(other.matrix(), again)


def _scene_with_cut_faces(rng, n_vertices=60, n_faces=150):
    """World points around the camera of a 48x40 image (some behind the near plane and
    the eye, so faces get cut), the clip coordinates and random faces."""
    camera = Camera.look_at(eye=(0, 0, 3), target=(0, 0, 0), width=48, height=40, fov_y=60, near=1.0, far=20.0)
    points = rng.uniform(-2.0, 2.0, (n_vertices, 3))
    points[: n_vertices // 5, 2] = rng.uniform(1.5, 4.0, n_vertices // 5)  # near the eye / behind it
    clip = np.hstack([points, np.ones((n_vertices, 1))]) @ camera.matrix().T
    faces = rng.integers(0, n_vertices, (n_faces, 3))
    return camera, points, np.ascontiguousarray(clip), faces


@pytest.mark.parametrize("cull", ["back", "none"])
@pytest.mark.parametrize("per_face", [False, True])
def test_flat_lambert_in_the_setup_equals_precomputed_face_colours(cull, per_face):
    """FlatLambert's colours, computed during the face setup for visible faces only (cut
    faces included), give the image of the colours of flat_packed for every face."""
    rng = np.random.default_rng(11)
    _, points, clip, faces = _scene_with_cut_faces(rng)
    base = rng.uniform(0, 1, (len(faces) if per_face else 1, 3)).astype(np.float32)
    light = np.array([0.48, 0.6, 0.64])
    two_sided = cull == "none"
    images = []
    for face_colors in (flat_packed(points, faces, base, np.float32(255), light, 0.25, two_sided),
                        FlatLambert(Mesh(points, faces).face_normals, base, light, 0.25, two_sided, 255.0)):
        color = np.zeros((40, 48, 3), np.uint8)
        depth = np.full((40, 48), np.inf, np.float32)
        stats = rasterize_triangles(color, depth, clip, faces, face_colors=face_colors, cull=cull)
        images.append(color)
    assert stats.clipped > 0 and stats.drawn > 0
    assert images[0].any() and np.array_equal(images[0], images[1])


def test_flat_lambert_is_checked_before_drawing():
    rng = np.random.default_rng(2)
    _, points, clip, faces = _scene_with_cut_faces(rng)
    color = np.zeros((40, 48, 3), np.uint8)
    depth = np.full((40, 48), np.inf, np.float32)
    base = np.ones((1, 3), np.float32)
    normals = Mesh(points, faces).face_normals
    up = np.array([0.0, 0.0, 1.0])
    bad = [FlatLambert(normals[:-1], base, up),  # a row short
           FlatLambert(normals, np.ones((2, 3), np.float32), up),
           FlatLambert(normals, base, np.array([0.0, np.nan, 1.0])),
           FlatLambert(normals.astype(np.float64), base, up),
           FlatLambert(normals[:, :2], base, up),
           FlatLambert(np.asfortranarray(np.repeat(normals, 2, axis=0)[::2]), base, up)]
    for face_colors in bad:
        with pytest.raises((TypeError, ValueError)):
            rasterize_triangles(color, depth, clip, faces, face_colors=face_colors)
    assert not color.any() and np.all(np.isinf(depth))


def test_prefetch_row_changes_nothing_and_takes_c_arrays_only():
    import numba

    from rasterkit.runtime.intrinsics import prefetch_row

    @numba.njit
    def total(rows, flat):
        s = 0.0
        for k in range(rows.shape[0]):
            prefetch_row(rows, min(k + 4, rows.shape[0] - 1))
            prefetch_row(flat, 10**9)  # far outside the array: a prefetch never faults
            s += rows[k].sum()
        return s

    rows = np.arange(12.0).reshape(4, 3)
    assert total(rows, np.zeros(3)) == rows.sum()
    with pytest.raises(numba.core.errors.TypingError):
        total(np.asfortranarray(rows), np.zeros(3))


def test_fetch_add_returns_the_old_value_and_counts_every_call_from_all_threads():
    import numba

    from rasterkit.runtime.intrinsics import fetch_add

    @numba.njit(parallel=True)
    def claim(counter, n, taken):
        for _ in numba.prange(n):
            k = fetch_add(counter, 0, 1)
            if k < taken.size:
                taken[k] += 1

    counter = np.zeros(1, np.int64)
    taken = np.zeros(5000, np.int64)
    claim(counter, 5000, taken)
    assert counter[0] == 5000 and np.all(taken == 1)  # every ticket handed out exactly once
    assert numba.njit(lambda a: fetch_add(a, 0, 5))(np.array([7], np.int64)) == 7


def test_images_wider_than_the_packed_records_take_the_general_path():
    """Past 2**15 pixels a side the packed records cannot hold n and the rows: every edge is
    drawn by the general path, with the same pixels as draw.line."""
    from rasterkit.draw import line, lines

    width = line_kernels._PACKED_LIMIT + 40
    image = np.zeros((3, width, 3), np.uint8)
    segments = np.array([[0, 0, width - 1, 2], [5, 2, width - 3, 0], [32800, 0, 32770, 1]])
    lines(image, segments, color="white")
    expected = np.zeros((3, width), bool)
    for x0, y0, x1, y1 in segments:
        xy = line(x0, y0, x1, y1)
        expected[xy[:, 1], xy[:, 0]] = True
    assert np.array_equal(image[..., 0] == 255, expected)


@pytest.mark.parametrize("channels", [3, 4])
def test_colours_carried_in_the_visibility_buffer_equal_the_looked_up_ones(channels):
    """Without ids the visibility buffer holds each face's colour (SHADE_TAGGED), with ids
    it holds the face and the colour is looked up (SHADE_FLAT): the same image, white
    faces (every colour bit 1, like the empty marker -1) included."""
    rng = np.random.default_rng(4)
    _, _, clip, faces = _scene_with_cut_faces(rng, n_faces=300)
    packed = rng.integers(0, 2**24, len(faces)).astype(np.uint32) | np.uint32(255 << 24)
    packed[::3] = 0xFFFFFFFF  # white
    images = []
    for ids in (None, np.full((40, 48), -1, np.int32)):
        color = np.full((40, 48, channels), 7, np.uint8)
        depth = np.full((40, 48), np.inf, np.float32)
        rasterize_triangles(color, depth, clip, faces, face_colors=packed, ids=ids, cull="none")
        images.append(color)
    assert (images[0] == 255).all(axis=2).any()  # white pixels drawn
    assert np.array_equal(images[0], images[1])


@pytest.mark.parametrize("bad", [-1, 60, 2**40])
def test_face_pass_rejects_out_of_range_indices_before_drawing(bad):
    """The vertex indices are checked by the face pass itself: an index out of range (or
    negative) in any chunk raises, and the buffers are left untouched."""
    rng = np.random.default_rng(8)
    _, _, clip, faces = _scene_with_cut_faces(rng, n_faces=5000)  # 60 vertices
    faces[4321, 1] = bad
    color = np.full((40, 48, 3), 9, np.uint8)
    depth = np.full((40, 48), 0.5, np.float32)
    with pytest.raises(ValueError, match="index vertices 0..59"):
        rasterize_triangles(color, depth, clip, faces, face_colors=np.zeros(len(faces), np.uint32), clear=(1, 2, 3))
    assert np.all(color == 9) and np.all(depth == 0.5)


@pytest.mark.parametrize("threads", [1, 2])
def test_draw_without_a_depth_buffer_gives_the_same_colours_and_ids(threads):
    """depth=None: the depth test runs in a band-sized scratch per thread (cleared per band,
    also on garbage), and colours and ids equal those of a draw with a full depth buffer."""
    threads = min(threads, _threads.MAX_THREADS)
    rng = np.random.default_rng(12)
    _, _, clip, faces = _scene_with_cut_faces(rng)
    colours = rng.integers(0, 2**32, len(faces), dtype=np.uint64).astype(np.uint32)
    results = []
    for depth in (np.full((40, 48), 7.0, np.float32), None):
        color = np.full((40, 48, 3), 9, np.uint8)
        ids = np.full((40, 48), 5, np.int32)
        stats = rasterize_triangles(color, depth, clip, faces, face_colors=colours, ids=ids, clear=(1, 2, 3),
                                    threads=threads)
        results.append((color, ids, stats))
    (c1, i1, s1), (c2, i2, s2) = results
    assert s1.drawn > 0 and s1.clipped > 0 and (i1 >= 0).any() and (i1 < 0).any()
    assert np.array_equal(c1, c2) and np.array_equal(i1, i2) and s1 == s2
    with pytest.raises(ValueError, match="depth can be None only"):
        rasterize_triangles(None, None, clip, faces)


def test_slot_band_buffers_lie_apart_and_draws_write_only_their_band_rows():
    """Each slot's visibility rows and depth scratch rows begin at least SLOT_GUARD_BYTES
    after the previous slot's (and after the buffer's start); a draw writes only the band
    rows (the guard rows keep a sentinel), leaves the visibility rows all -1, and a buffer
    of more slots is reused, not refilled, by a draw on fewer threads."""
    from rasterkit.raster.kernels.bands import BAND_HEIGHT, SLOT_GUARD_BYTES, slot_rows
    from rasterkit.raster.triangle_pass import WORKSPACE

    for width in (1, 7, 48, 1920, 40000):
        rows = slot_rows(width)
        assert (rows - BAND_HEIGHT) * 4 * width >= SLOT_GUARD_BYTES > (rows - BAND_HEIGHT - 1) * 4 * width
    threads = min(2, _threads.MAX_THREADS)
    rng = np.random.default_rng(13)
    _, _, clip, faces = _scene_with_cut_faces(rng)
    colours = rng.integers(0, 2**32, len(faces), dtype=np.uint64).astype(np.uint32)

    def draw(n):
        color = np.zeros((40, 48, 3), np.uint8)
        rasterize_triangles(color, None, clip, faces, face_colors=colours, clear=(1, 2, 3), threads=n)
        return color

    expected = draw(1)
    draw(threads)
    rows = slot_rows(48)
    lid = WORKSPACE.held("lid")
    scratch = WORKSPACE.held("band_depth")[: threads * rows * 48].reshape(threads, rows, 48)
    assert lid.shape[1:] == (rows, 48) and lid.shape[0] >= threads
    guard = np.zeros(rows, bool)
    guard[: rows - BAND_HEIGHT] = True
    lid[:, guard] = 7
    scratch[:, guard] = np.nan
    for n in (threads, 1, threads):
        assert np.array_equal(draw(n), expected)
        assert WORKSPACE.held("lid") is lid  # kept, not refilled, when the slots change
        assert np.all(lid[:, guard] == 7) and np.all(lid[:, ~guard] == -1)
        assert np.all(np.isnan(scratch[:, guard])) and np.isfinite(scratch[:, ~guard]).any()


def test_solid_render_makes_its_depth_when_read_and_forgets_the_recipe_when_cleared():
    mesh = shapes.torus()
    camera = Camera.frame(*mesh.bounding_sphere(), width=64, height=48)
    hidden = rasterkit.render(mesh, camera, mode="hidden")  # keeps a depth buffer as it draws
    solid = rasterkit.render(mesh, camera, mode="solid")
    assert solid._depth is None  # nothing image-sized written by the draw
    expected = np.full((48, 64), np.inf, np.float32)
    rasterize_triangles(None, expected, transform_points(mesh.vertices, camera.matrix()), mesh.faces, clear=())
    assert np.isfinite(solid.depth).any() and np.array_equal(solid.depth, expected)
    covered = np.isfinite(hidden.depth)
    assert np.array_equal(np.isfinite(solid.depth), covered)  # hidden's depths carry the polygon offset
    cleared = rasterkit.render(mesh, camera, mode="solid")
    cleared.clear()
    assert np.all(np.isposinf(cleared.depth))
    replaced = rasterkit.render(mesh, camera, mode="solid")
    replaced.depth = np.zeros((48, 64), np.float32)
    assert not replaced.depth.any()


@pytest.mark.parametrize("n_bands", [1, 3, 7])
def test_blocks_of_nearby_edges_draw_what_the_general_path_draws(n_bands):
    """Edges listed in row order, as a mesh lists nearby faces together: most blocks of
    BLOCK edges lie wholly inside one band (stepped without a test per edge) or outside it
    (skipped), some straddle a band's border, and one block holds an edge leaving the image
    (the general path). The image equals the general path's."""
    rng = np.random.default_rng(23)
    height, width = 90, 120
    m = 6 * line_kernels.BLOCK + 77
    centre = np.sort(rng.uniform(2, height - 2, m))
    x = rng.uniform(2, width - 2, m)
    ends = np.stack([x + rng.uniform(-3, 3, m), centre + rng.uniform(-2, 2, m),
                     x + rng.uniform(-3, 3, m), centre + rng.uniform(-2, 2, m)], axis=1)
    ends[:, 0::2] = ends[:, 0::2].clip(0, width - 0.01)
    ends[:, 1::2] = ends[:, 1::2].clip(0, height - 0.01)
    ends[3 * line_kernels.BLOCK + 5, 2] = width + 40.0  # leaves the image
    w = rng.uniform(0.5, 2.0, 2 * m)
    clip = np.c_[ends.reshape(-1, 2) * w[:, None], 0.5 * w, w]
    edges = np.arange(2 * m).reshape(m, 2)
    rgba = np.array([10, 200, 30], np.uint8)
    background = np.array([250, 251, 252], np.uint8)
    marked = np.zeros((height, width, 3), np.uint8)
    memory = scratch(len(clip), m, height * width, MODE_PLAIN, take=np.empty)
    draw_edges(marked, None, clip, edges, rgba, MODE_PLAIN, 0.0, background, n_bands=n_bands, memory=memory)
    summary = memory.blocks
    assert np.sum(summary[2] > 0) == 1 and np.all(summary[1] - summary[0] < height // 4)
    expected = np.empty((height, width, 3), np.uint8)
    expected[...] = background
    draw_edges(expected, np.full((height, width), np.inf, np.float32), clip, edges, rgba, MODE_DEPTH_TEST,
               n_bands=1)
    assert (expected == rgba).all(axis=2).sum() > 1000
    assert np.array_equal(marked, expected)
