"""The STL reader's kernel (:func:`rasterkit.stl.kernels.mesh.assemble`, driven by
:func:`rasterkit.stl.weld.weld_facets`) against slow, obvious references: each facet's flaws,
the welding (the hash table, its retries with a larger table, and the sort it falls back to
when corners are made to collide) and the normals kept."""


import numpy as np
import pytest

from rasterkit.stl.kernels import mesh as kernels
from rasterkit.stl.weld import weld_by_sorting, weld_facets
from support.stlfiles import RECORD, reference_weld


def reference_flaws(corners):
    """Each facet's flaw, by Python's numbers."""
    out = []
    for facet in np.asarray(corners, np.float64).tolist():
        if not all(np.isfinite(x) for corner in facet for x in corner):
            out.append(kernels.NOT_FINITE)
        elif facet[0] == facet[1] or facet[1] == facet[2] or facet[2] == facet[0]:
            out.append(kernels.TWO_EQUAL)
        else:
            out.append(kernels.SOUND)
    return out


def reference_normal(a, b, c, given):
    """``(kind, unit normal)`` of one facet, as the module documentation of
    :mod:`rasterkit.stl.normals` says: the file's where usable, else the corners'."""
    u, v = np.subtract(b, a), np.subtract(c, a)
    su, sv = np.abs(u).max(), np.abs(v).max()
    if su > 0 and sv > 0:
        u, v = u / su, v / sv
    own = np.cross(u, v)
    given = np.asarray(given, np.float64)
    if not np.isfinite(given).all() or not given.any():
        kind, n = "missing", own
    elif given @ own < 0:
        kind, n = "backwards", own
    else:
        kind, n = "given", given
    largest = np.abs(n).max()
    if not (largest > 0 and np.isfinite(largest)):
        return kind, np.zeros(3)
    n = n / largest
    return kind, n / np.linalg.norm(n)


def check_against_references(corners, normals):
    welded = weld_facets(corners, normals)
    flaws = reference_flaws(corners)
    assert welded.flaws.tolist() == flaws
    sound = np.array(flaws) == kernels.SOUND
    kept = np.asarray(corners, np.float64)[sound].reshape(-1, 3)
    inverse, first = reference_weld(kept)
    assert np.array_equal(welded.faces.ravel(), inverse)
    assert np.array_equal(welded.vertices, kept[first] + 0.0)  # without -0.0
    assert not np.signbit(welded.vertices[welded.vertices == 0]).any()
    kinds = []
    for k, (face, given) in enumerate(zip(welded.faces, np.asarray(normals, np.float64)[sound])):
        kind, unit = reference_normal(*welded.vertices[face], given)
        kinds.append(kind)
        assert np.allclose(welded.normals[k], unit, rtol=0, atol=1e-15)
    assert (welded.missing, welded.backwards) == (kinds.count("missing"), kinds.count("backwards"))
    return welded


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("distinct", [3, 40, 10_000])
def test_weld_numbers_corners_by_first_appearance_and_keeps_the_normals(dtype, distinct):
    rng = np.random.default_rng(distinct)
    corners = (rng.integers(0, distinct, (1000, 3, 3)) / 7).astype(dtype)
    corners[rng.random((1000, 3)) < 0.1] *= -1  # -0.0 among them
    corners[rng.random((1000, 3, 3)) < 0.01] = rng.choice([np.nan, np.inf, -np.inf])
    normals = rng.normal(size=(1000, 3)).astype(dtype)
    normals[rng.random(1000) < 0.1] = 0
    normals[rng.random(1000) < 0.05, 1] = np.nan
    check_against_references(corners, normals)


def test_the_corners_and_normals_are_read_where_the_file_has_them():
    rng = np.random.default_rng(2)
    records = np.zeros(500, RECORD)
    records["corners"] = rng.integers(0, 9, (500, 3, 3))
    records["normal"] = rng.normal(size=(500, 3))
    view = np.frombuffer(b"x" + records.tobytes(), RECORD, 500, 1)  # unaligned, strided
    welded = check_against_references(view["corners"], view["normal"])
    again = weld_facets(records["corners"].copy(), records["normal"].copy())
    assert np.array_equal(welded.faces, again.faces) and np.array_equal(welded.normals, again.normals)


def test_facet_flaws():
    corners = np.zeros((5, 3, 3), np.float32)
    corners[:] = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    corners[1, 2, 0], corners[3, 0, 1] = np.nan, -np.inf
    corners[2, 2] = corners[2, 0]
    corners[4, 1] = [-0.0, 0, 0]  # equal to corner 0 as a number
    corners[3, 1] = corners[3, 2]  # both: not finite first
    welded = weld_facets(corners, np.zeros((5, 3), np.float32))
    assert welded.flaws.tolist() == [kernels.SOUND, kernels.NOT_FINITE, kernels.TWO_EQUAL, kernels.NOT_FINITE,
                                     kernels.TWO_EQUAL]
    assert welded.faces.tolist() == [[0, 1, 2]] and len(welded.vertices) == 3


def test_a_table_too_small_for_the_vertices_is_grown():
    rng = np.random.default_rng(3)
    corners = rng.random((3000, 3, 3))  # every corner its own vertex: more than the first table holds
    welded = check_against_references(corners, np.zeros((3000, 3)))
    assert len(welded.vertices) == 9000
    table = np.zeros(16, np.uint64)
    out = (np.empty(3000, np.uint8), np.empty((3000, 3), np.int64), np.empty((9000, 3)), np.empty((3000, 3)))
    result = kernels.assemble(corners, np.zeros((3000, 3)), np.zeros(0, np.int64), table, *out)
    assert result[1] == kernels.FULL and out[0].tolist() == [kernels.SOUND] * 3000


def colliding_corners(n):
    """n distinct corners (float64, finite, not -0.0) whose hash, before the finaliser, is one
    value: each lands in the same slot, whatever the table's size."""
    m1, m2, m3 = (int(kernels.M1), int(kernels.M2), int(kernels.M3))
    inverse_m3, mask = pow(m3, -1, 2**64), 2**64 - 1
    seven = int(np.float64(7.0).view(np.uint64))
    rows = []
    for a in range(1, 10 * n):
        x = int(np.float64(a).view(np.uint64))
        c = ((0x1234 ^ (x * m1 & mask) ^ (seven * m2 & mask)) * inverse_m3) & mask
        if np.isfinite(np.uint64(c).view(np.float64)) and c != 1 << 63:
            rows.append((x, seven, c))
        if len(rows) == n:
            return np.array(rows, np.uint64).view(np.float64)


def test_corners_made_to_collide_are_numbered_by_sorting_instead():
    points = colliding_corners(3000)
    corners = np.concatenate([points, points[::-1]]).reshape(-1, 3, 3)
    out = (np.empty(2000, np.uint8), np.empty((2000, 3), np.int64), np.empty((6000, 3)), np.empty((2000, 3)))
    result = kernels.assemble(corners, np.zeros((2000, 3)), np.zeros(0, np.int64), np.zeros(1 << 16, np.uint64),
                              *out)
    # the kernel gives up on the table (reports COLLIDING: no probing on and on through one
    # slot) and the welding numbers the corners by sorting, the same as the references
    assert result[1] == kernels.COLLIDING and (out[0] == kernels.SOUND).all()
    welded = check_against_references(corners, np.zeros((2000, 3)))
    assert len(welded.vertices) == 3000


def test_weld_by_sorting_numbers_rows_by_first_appearance():
    rng = np.random.default_rng(1)
    corners = rng.integers(0, 50, (5000, 3)).astype(np.float32)
    inverse, first = weld_by_sorting(corners.view(np.uint32))
    expected_inverse, expected_first = reference_weld(corners)
    assert np.array_equal(inverse, expected_inverse) and np.array_equal(first, expected_first)


def test_normals_of_huge_and_tiny_facets_are_unit_vectors():
    corners = np.array([[[0, 0, 0], [1e300, 0, 0], [0, 1e300, 0]], [[0, 0, 0], [1e-300, 0, 0], [0, 1e-300, 0]],
                        [[0, 0, 0], [1, 1, 1], [2, 2, 2]]], np.float64)
    welded = check_against_references(corners, np.zeros((3, 3)))
    assert welded.normals.tolist() == [[0, 0, 1], [0, 0, 1], [0, 0, 0]]  # the last facet's corners are on one line
    given = np.array([[0, 0, 1e300], [0, 0, -2], [3, 4, 0]], np.float64)
    welded = check_against_references(corners, given)
    assert (welded.missing, welded.backwards) == (0, 1)
    assert np.allclose(welded.normals, [[0, 0, 1], [0, 0, 1], [0.6, 0.8, 0]], rtol=0, atol=1e-15)


@pytest.fixture
def in_chunks(monkeypatch):
    """weld_facets welding files of 16 facets or more in 4 chunks on 2 threads; the list of
    ``(sound facets, vertices)`` each join returned."""
    from rasterkit.runtime import threads
    from rasterkit.stl import weld
    from rasterkit.stl.kernels.merge import merge_chunks

    joins = []

    def join(*args):
        joins.append(merge_chunks(*args))
        return joins[-1]

    monkeypatch.setattr(weld, "PARALLEL_FACETS", 16)
    monkeypatch.setattr(weld, "CHUNKS_PER_THREAD", 2)
    monkeypatch.setattr(weld, "merge_chunks", join)
    saved = threads.set_threads(2)
    yield joins
    threads.set_threads(saved)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("points", [3, 40, 300])
def test_a_weld_in_chunks_on_the_threads_gives_what_one_pass_gives(in_chunks, dtype, points):
    """Chunks of facets welded apart and joined: the vertices of first appearance in the
    whole file, bit for bit (against the same references as one pass), with dropped facets in
    every chunk, and corners shared across the chunks."""
    rng = np.random.default_rng(points + 7)
    pool = rng.integers(-20, 20, (points, 3)) / 7
    corners = pool[rng.integers(0, points, (1000, 3))].astype(dtype)
    corners[rng.random((1000, 3)) < 0.1] *= -1  # -0.0 among them
    corners[rng.random((1000, 3, 3)) < 0.01] = np.nan
    normals = rng.normal(size=(1000, 3)).astype(dtype)
    welded = check_against_references(corners, normals)
    assert len(in_chunks) == 1 and in_chunks[0] == (len(welded.faces), len(welded.vertices))


def test_a_weld_in_chunks_falls_back_to_one_pass_when_a_chunk_fills_its_table(in_chunks):
    rng = np.random.default_rng(4)
    corners = rng.random((3000, 3, 3))  # 9000 vertices: more than any chunk's table holds
    welded = check_against_references(corners, np.zeros((3000, 3)))
    assert len(welded.vertices) == 9000 and in_chunks == []


def test_the_join_gives_up_when_its_table_is_full():
    """Two chunks of 4 facets, 12 vertices each, joined in a table of 32 slots (16 vertices)."""
    from rasterkit.stl.kernels.merge import merge_chunks

    rng = np.random.default_rng(5)
    corners = rng.random((8, 3, 3))
    out = (np.empty(8, np.uint8), np.empty((8, 3), np.int64), np.empty((24, 3)), np.empty((8, 3)))
    tables = [np.zeros(32, np.uint64), np.zeros(32, np.uint64)]
    results = [kernels.assemble(corners[lo:lo + 4], np.zeros((4, 3)), np.zeros(0, np.int64), tables[k],
                                out[0][lo:lo + 4], out[1][lo:lo + 4], out[2][3 * lo:3 * lo + 12], out[3][lo:lo + 4])
               for k, lo in enumerate((0, 4))]
    assert [r[:2] for r in results] == [(4, 12), (4, 12)]
    joined = merge_chunks(np.array([0, 4, 8]), np.array([4, 4]), np.array([12, 12]), tables[0], out[1], out[2],
                          out[3], np.empty(12, np.int64))
    assert joined == (0, kernels.FULL)


def test_corners_made_to_collide_in_chunks_are_numbered_by_sorting(in_chunks):
    points = colliding_corners(3000)
    corners = np.concatenate([points, points[::-1]]).reshape(-1, 3, 3)
    welded = check_against_references(corners, np.zeros((2000, 3)))
    assert len(welded.vertices) == 3000 and in_chunks == []  # the chunks collided before any join
