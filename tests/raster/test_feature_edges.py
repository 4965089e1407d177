"""Feature edges (silhouettes, boundaries, creases, material boundaries), in vector drawings and
in the raster modes, against geometry worked out by hand."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from rasterkit import Camera, Mesh, render, shapes
from rasterkit.raster.features import EDGE_CLASSES, feature_edges
from rasterkit.svg.visibility import split_visible
from rasterkit.mesh import polygon_edges
from rasterkit.svg import svg_drawing


def _classes(mesh, camera, crease_angle=30.0):
    edges, classes = feature_edges(mesh, camera.project_h(mesh.vertices), crease_angle)
    return {tuple(e): EDGE_CLASSES[c] for e, c in zip(edges.tolist(), classes)}


def _roof(angle_deg):
    """Two triangles meeting at the ridge x = 0, their normals ``angle_deg`` apart."""
    half = np.radians(angle_deg) / 2
    s, c = np.sin(half), np.cos(half)
    v = [(0, 0, -1), (0, 0, 1), (-c, -s, 0), (c, -s, 0)]
    faces = [(0, 1, 2), (1, 0, 3)]
    return Mesh(np.array(v, float), np.array(faces))


@pytest.mark.parametrize("dihedral", [20.0, 40.0, 89.0])
def test_crease_threshold_on_a_known_angle(dihedral):
    mesh = _roof(dihedral)
    n = mesh.face_normals.astype(float)
    assert np.degrees(np.arccos(np.clip(n[0] @ n[1], -1, 1))) == pytest.approx(dihedral, abs=1e-4)
    camera = Camera.look_at((0.3, 5, 0.2), (0, 0, 0), up=(0, 0, -1))
    below = _classes(mesh, camera, crease_angle=dihedral - 0.5)
    above = _classes(mesh, camera, crease_angle=dihedral + 0.5)
    assert below[(0, 1)] == "crease"
    assert (0, 1) not in above
    # the rim: four boundary edges, whatever the angle
    assert sorted(k for k, v in above.items() if v == "boundary") == [(0, 2), (0, 3), (1, 2), (1, 3)]


def test_cube_feature_edges_are_its_twelve_edges_not_the_diagonals():
    cube = shapes.cube()
    camera = Camera.look_at((3.1, 2.3, 4.2), (0, 0, 0))
    classes = _classes(cube, camera)
    assert set(classes) == {tuple(e) for e in cube.edges.tolist()}
    assert len(classes) == 12
    assert sorted(classes.values()).count("silhouette") == 6


def test_flat_grid_has_only_its_boundary():
    grid = shapes.grid(4, 4)
    classes = _classes(grid, Camera.look_at((1, 3, 2), (0, 0, 0)))
    assert set(classes.values()) == {"boundary"}
    assert len(classes) == 16


def test_material_boundary_between_faces_of_different_colours():
    v = np.array([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0), (2, 1, 0)], float)
    faces = np.array([(0, 1, 2), (0, 2, 3), (1, 4, 5), (1, 5, 2)])
    colors = np.array([(1, 0, 0), (1, 0, 0), (0, 0, 1), (0, 0, 1)], np.float32)
    mesh = Mesh(v, faces, face_colors=colors)
    classes = _classes(mesh, Camera.look_at((1, 0.5, 3), (1, 0.5, 0)))
    assert classes[(1, 2)] == "material"
    assert (0, 2) not in classes  # the diagonal between two red faces


def _visible_segments(drawing):
    lines = drawing.lines
    segs = []
    for q in range(len(lines)):
        p = lines.points[lines.offsets[q]:lines.offsets[q + 1]]
        segs.extend(zip(p[:-1], p[1:]))
    return segs


def test_cube_from_a_general_direction_shows_exactly_its_nine_visible_edges():
    cube = shapes.cube(2.0)
    eye = np.array([3.1, 2.3, 4.2])
    camera = Camera.look_at(eye, (0, 0, 0), width=640, height=480)
    drawing = svg_drawing(cube, camera, mode="hidden", edges="feature")
    # independent expectation: an edge of a convex solid is visible when one of its faces faces the eye
    corners = np.array(list(itertools.product([-1, 1], repeat=3)), float)
    expected = []
    for a, b in itertools.combinations(range(8), 2):
        diff = corners[a] != corners[b]
        if diff.sum() != 1:
            continue
        axis_fixed = [k for k in range(3) if not diff[k]]
        if any((eye[k] - corners[a][k]) * corners[a][k] > 0 for k in axis_fixed):
            expected.append(camera.project(corners[[a, b]])[:, :2])
    assert len(expected) == 9
    segs = _visible_segments(drawing)
    assert len(segs) == 9
    for want in expected:  # each expected edge is one drawn segment, ends to 1e-3 px
        assert any(np.abs(np.array(s) - want).max() < 1e-3 or np.abs(np.array(s)[::-1] - want).max() < 1e-3
                   for s in segs)
    length = sum(np.linalg.norm(b - a) for a, b in segs)
    want_length = sum(np.linalg.norm(w[1] - w[0]) for w in expected)
    assert length == pytest.approx(want_length, rel=1e-3)


def test_sphere_silhouette_is_one_closed_loop_of_the_analytic_radius():
    radius, distance = 1.0, 6.0
    sphere = shapes.icosphere(5, radius)
    camera = Camera.look_at((0, 0, distance), (0, 0, 0), fov_y=30.0, width=600, height=600)
    drawing = svg_drawing(sphere, camera, mode="hidden", edges="feature", crease_angle=90.0)
    assert len(drawing.lines) == 1
    loop = drawing.lines.points
    assert np.allclose(loop[0], loop[-1])
    focal = 300 / np.tan(np.radians(15.0))
    analytic = focal * np.tan(np.arcsin(radius / distance))
    r = np.hypot(loop[:, 0] - 300, loop[:, 1] - 300)
    assert np.abs(r - analytic).max() < 0.01 * analytic  # the tessellation's polygon, inside 1 %
    assert r.max() <= analytic * 1.0005


def test_torus_inner_silhouette_is_partly_hidden():
    torus = shapes.torus(1.0, 0.35, rings=96, sides=48)
    camera = Camera.look_at((0, 1.2, 4), (0, 0, 0), width=800, height=600)
    clip = camera.project_h(torus.vertices)
    edges, classes = feature_edges(torus, clip, 60.0)
    silhouettes = edges[classes == EDGE_CLASSES.index("silhouette")]
    pieces = split_visible(clip, torus.faces, silhouettes, 800, 600)
    mid_x = (pieces.xy[:, 0] + pieces.xy[:, 2]) / 2
    # the hole's half width on screen: the inner equator's radius, 1 - 0.35, projected at the centre
    hole = abs(camera.project([(1.0 - 0.35, 0, 0)])[0, 0] - 400)
    inner = np.abs(mid_x - 400) < hole
    assert pieces.hidden[inner].any() and (~pieces.hidden[inner]).any()  # the inner silhouette: both
    assert not pieces.hidden[~inner & (np.abs(mid_x - 400) > 1.2 * hole)].all()
    drawing = svg_drawing(torus, camera, mode="hidden", edges="feature", crease_angle=60.0, hidden="dashed")
    text = drawing.text
    hidden_part = text[text.index('id="layer-hidden"'):]
    visible_part = text[text.index('id="layer-visible"'):text.index('id="layer-hidden"')]
    assert 'class="silhouette"' in hidden_part and 'class="silhouette"' in visible_part


def test_raster_modes_draw_the_feature_edges():
    cube = shapes.cube()
    camera = Camera.look_at((3.1, 2.3, 4.2), (0, 0, 0), width=160, height=120)
    grid = shapes.grid(6, 6)
    grid_camera = Camera.look_at((0.5, 3, 2), (0, 0, 0), width=160, height=120)
    for mesh, cam in ((cube, camera), (grid, grid_camera)):
        feature = render(mesh, cam, "hidden", edges="feature")
        edges, _ = feature_edges(mesh, cam.project_h(mesh.vertices), 30.0)
        by_hand = render(Mesh(mesh.vertices, mesh.faces, edges=edges), cam, "hidden")
        assert np.array_equal(feature.color, by_hand.color)
    # the grid's inner lines are gone, its rim stays
    all_edges = render(grid, grid_camera, "solid+wire")
    feature = render(grid, grid_camera, "solid+wire", edges="feature")
    assert (feature.color == 0).all(axis=2).sum() < (all_edges.color == 0).all(axis=2).sum()


def test_edge_options_are_checked():
    cube = shapes.cube()
    camera = Camera.look_at((3, 2, 4), (0, 0, 0), width=32, height=32)
    with pytest.raises(ValueError, match="edges"):
        render(cube, camera, "hidden", edges="some")
    with pytest.raises(ValueError, match="crease_angle"):
        render(cube, camera, "hidden", edges="feature", crease_angle=200)
    with pytest.raises(TypeError, match="crease_angle"):
        svg_drawing(cube, camera, edges="feature", crease_angle="30")


def test_polygon_edges_of_quads_are_drawn_with_edges_all():
    quad = Mesh(np.array([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], float), np.array([(0, 1, 2), (0, 2, 3)]),
                edges=polygon_edges([[0, 1, 2, 3]]))
    camera = Camera.look_at((0.5, 0.5, 3), (0.5, 0.5, 0), width=200, height=200)
    drawing = svg_drawing(quad, camera, mode="hidden", edges="all")
    assert len(_visible_segments(drawing)) == 4  # no diagonal


def _distorted(dist, width=320, height=240):
    k = [[300.0, 0, width / 2], [0, 300.0, height / 2], [0, 0, 1]]
    r = [[1, 0, 0], [0, -1, 0], [0, 0, -1]]
    return Camera.from_opencv(k, r, [0, 0, 4.0], width, height, dist=dist), dict(K=k, R=r, t=[0, 0, 4.0], dist=dist,
                                                                                  width=width, height=height)


def _dark(fb):
    return int((fb.color.max(axis=2) < 128).sum())


def test_a_distorted_camera_draws_the_edges_asked_for():
    """Feature edges and the crease angle reach the frame through a distorted camera as through
    an undistorted one (a distortion of 1e-6 moves no pixel centre by a tenth of a pixel; the
    resampling greys some pixels of one-pixel lines, fewest where lines are dense)."""
    mesh = shapes.icosphere(2)
    plain, _ = _distorted(None)
    bent, _ = _distorted((1e-6, 0, 0, 0, 0))
    counts = {}
    for camera, name in ((plain, "plain"), (bent, "bent")):
        for edges, crease in (("all", 30.0), ("feature", 30.0), ("feature", 10.0)):
            counts[name, edges, crease] = _dark(render(mesh, camera, "wire", edges=edges, crease_angle=crease))
    assert counts["plain", "feature", 30.0] < counts["plain", "feature", 10.0] < counts["plain", "all", 30.0]
    for key in (("all", 30.0), ("feature", 30.0), ("feature", 10.0)):
        assert 0.7 * counts[("plain", *key)] <= counts[("bent", *key)] <= counts[("plain", *key)], counts


def test_the_command_line_draws_feature_edges_through_a_distorted_camera(tmp_path):
    import json

    from PIL import Image

    from rasterkit.cli import main

    mesh = shapes.icosphere(2)
    model = tmp_path / "ball.obj"
    model.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in mesh.vertices.tolist())
                     + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in mesh.faces.tolist()))
    camera, record = _distorted((0.001, 0, 0, 0, 0))
    (tmp_path / "cam.json").write_text(json.dumps(record))
    out = {}
    for edges in ("all", "feature"):
        path = tmp_path / f"{edges}.png"
        assert main(["render", str(model), "-o", str(path), "--mode", "wire", "--edges", edges,
                     "--camera-opencv", str(tmp_path / "cam.json")]) == 0
        with Image.open(path) as image:
            out[edges] = int((np.asarray(image.convert("L")) < 128).sum())
    api = _dark(render(mesh, camera, "wire", edges="feature"))
    assert out["feature"] == api and out["feature"] < out["all"] / 3
