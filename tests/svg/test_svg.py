"""Vector hidden-line drawings: visibility against analytic geometry, the SVG document's
structure, path planning, and the command line."""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from rasterkit import Camera, Mesh, Scene, render_svg, shapes, transform
from rasterkit.svg.visibility import split_visible
from rasterkit.cli import main
from rasterkit.mesh import polygon_edges
from rasterkit.svg import svg_drawing

SVG = "{http://www.w3.org/2000/svg}"
INKSCAPE = "{http://www.inkscape.org/namespaces/inkscape}"


def _squares(near, far):
    """Two axis-aligned squares facing +z, ``(x0, y0, x1, y1, z)`` each, as quads."""
    v, quads = [], []
    for x0, y0, x1, y1, z in (near, far):
        k = len(v)
        v += [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]
        quads.append([k, k + 1, k + 2, k + 3])
    faces = [(q[0], q[1], q[2]) for q in quads] + [(q[0], q[2], q[3]) for q in quads]
    return Mesh(np.array(v, float), np.array(faces), edges=polygon_edges(quads))


def _crossing(p, q, r, s):
    """Intersection of the 2D lines p-q and r-s."""
    def cross(a, b):
        return a[0] * b[1] - a[1] * b[0]

    d1, d2 = q - p, s - r
    return p + cross(r - p, d2) / cross(d1, d2) * d1


def test_far_edge_is_split_exactly_where_the_near_edge_crosses_it():
    mesh = _squares((-1, -1, 1, 1, 0.0), (0, 0.3, 3, 2.5, -2.0))
    camera = Camera.look_at((0.4, 0.2, 6), (0, 0, -1), width=800, height=600)
    proj = camera.project(mesh.vertices)[:, :2]
    pieces = split_visible(camera.project_h(mesh.vertices), mesh.faces, mesh.edges, 800, 600)
    # the far square's left side (4-7) passes behind the near square's top side (2-3),
    # its bottom side (4-5) behind the near square's right side (1-2)
    for far, near in (((4, 7), (2, 3)), ((4, 5), (1, 2))):
        expected = _crossing(proj[far[0]], proj[far[1]], proj[near[0]], proj[near[1]])
        k = next(i for i, e in enumerate(mesh.edges.tolist()) if e == sorted(far))
        mine = np.flatnonzero(pieces.edge == k)
        assert len(mine) == 2
        assert sorted(pieces.hidden[mine]) == [False, True]
        ends = pieces.xy[mine].reshape(-1, 2)
        assert np.linalg.norm(ends - expected, axis=1).min() < 1e-3
        hidden_piece = pieces.xy[mine[pieces.hidden[mine]]][0].reshape(2, 2)
        assert np.linalg.norm(hidden_piece - proj[4], axis=1).min() < 1e-9  # the corner behind
    # the near square is never hidden
    near_edges = [i for i, e in enumerate(mesh.edges.tolist()) if max(e) < 4]
    assert not pieces.hidden[np.isin(pieces.edge, near_edges)].any()


def test_lines_lying_on_a_visible_face_stay_visible():
    mesh = _squares((-1, -1, 1, 1, 0.0), (-0.5, -0.4, 0.3, 0.6, 0.0))  # coplanar, on top of each other
    camera = Camera.look_at((0.7, -0.4, 4), (0, 0, 0), width=400, height=400)
    drawing = svg_drawing(mesh, camera, mode="hidden", hidden="dashed")
    assert 'id="layer-hidden"' not in drawing.text
    assert drawing.pieces == 8
    # a cube's edges: the 9 on front faces solid (silhouettes too), the 3 behind dashed
    cube = shapes.cube()
    camera = Camera.look_at((3.1, 2.3, 4.2), (0, 0, 0), width=640, height=480)
    pieces = split_visible(camera.project_h(cube.vertices), cube.faces, cube.edges, 640, 480)
    assert len(pieces.hidden) == 12
    assert pieces.hidden.sum() == 3


def _parse(text):
    root = ET.fromstring(text)
    layers = [g for g in root if g.tag == SVG + "g"]
    return root, layers


def _path_points(d):
    assert re.fullmatch(r"(M[-\d. ]+(L[-\d. ]+)?Z?)", d), d
    numbers = re.findall(r"-?\d+(?:\.\d+)?", d)
    assert all(len(n.split(".")[1]) <= 2 for n in numbers if "." in n)
    return np.array(numbers, float).reshape(-1, 2)


def test_svg_document_structure():
    scene = Scene().add(shapes.cube(), transform.translate(-1.2, 0, 0)).add(shapes.icosphere(2),
                                                                           transform.translate(1.2, 0, 0))
    camera = Camera.look_at((1.5, 2.0, 6.0), (0, 0, 0), width=320, height=200)
    text = render_svg(scene, camera, mode="hidden", edges="feature", hidden="dashed", line_color="#204080",
                      stroke_width=1.5)
    root, layers = _parse(text)
    assert root.tag == SVG + "svg" and root.get("version") == "1.1"
    assert root.get("viewBox") == "0 0 320 200"
    assert [g.get(INKSCAPE + "label") for g in layers] == ["visible", "hidden"]
    assert all(g.get(INKSCAPE + "groupmode") == "layer" for g in layers)
    assert layers[0].get("stroke") == "#204080" and layers[0].get("stroke-width") == "1.5"
    assert layers[0].get("stroke-dasharray") is None and layers[1].get("stroke-dasharray")
    assert [g.get("id") for g in layers[0]] == ["object-0", "object-1"]
    classes = set()
    for layer in layers:
        for obj in layer:
            for path in obj:
                assert path.tag == SVG + "path"
                classes.add(path.get("class"))
                pts = _path_points(path.get("d"))
                assert (pts >= 0).all() and (pts[:, 0] <= 320).all() and (pts[:, 1] <= 200).all()
    assert {"silhouette", "crease"} <= classes


def test_hidden_none_leaves_the_hidden_parts_out():
    torus = shapes.torus()
    camera = Camera.look_at((0, 2, 3), (0, 0, 0), width=300, height=200)
    plain = svg_drawing(torus, camera, mode="hidden")
    dashed = svg_drawing(torus, camera, mode="hidden", hidden="dashed")
    assert 'id="layer-hidden"' not in plain.text and 'id="layer-hidden"' in dashed.text
    assert dashed.pieces > plain.pieces
    wire = svg_drawing(torus, camera, mode="wire")
    assert wire.pieces == len(torus.edges)


def test_pen_up_travel_is_shortened():
    mesh = shapes.torus(rings=48, sides=24)
    camera = Camera.look_at((0.3, 2.0, 3.0), (0, 0, 0), width=800, height=600)
    drawing = svg_drawing(mesh, camera, mode="hidden", hidden="dashed")
    assert drawing.pen_up_after <= drawing.pen_up_before / 5
    assert len(drawing.lines) < drawing.pieces  # pieces were joined
    # the polylines hold every piece exactly: same total length
    lines = drawing.lines
    seg = np.diff(lines.points, axis=0)
    inner = np.ones(len(seg), bool)
    inner[lines.offsets[1:-1] - 1] = False
    total = np.hypot(*seg[inner].T).sum()
    pieces = split_visible(camera.project_h(mesh.vertices), mesh.faces, mesh.edges, 800, 600)
    want = np.hypot(*(pieces.xy[:, 2:] - pieces.xy[:, :2]).T).sum()
    assert total == pytest.approx(want, rel=1e-6)


def test_edges_are_clipped_to_the_image_and_the_near_plane():
    grid = shapes.grid(20, 20, size=20.0)
    camera = Camera.look_at((0.0, 0.5, 0.0), (3.0, 0.0, -3.0), width=200, height=150, near=0.1)
    drawing = svg_drawing(grid, camera, mode="hidden")
    pts = drawing.lines.points
    assert len(pts) and np.isfinite(pts).all()
    assert (pts >= -1e-9).all() and (pts[:, 0] <= 200 + 1e-9).all() and (pts[:, 1] <= 150 + 1e-9).all()


def test_api_errors():
    cube = shapes.cube()
    camera = Camera.look_at((3, 2, 4), (0, 0, 0), width=32, height=32)
    with pytest.raises(ValueError, match="mode"):
        render_svg(cube, camera, mode="solid")
    with pytest.raises(ValueError, match="hidden"):
        render_svg(cube, camera, hidden="dotted")
    with pytest.raises(TypeError, match="camera"):
        render_svg(cube, None)
    with pytest.raises(ValueError, match="stroke_width"):
        render_svg(cube, camera, stroke_width=0)


def test_cli_writes_svg_atomically(tmp_path, capsys):
    out = tmp_path / "demo.svg"
    old = os.umask(0o027)
    try:
        code = main(["render", "--demo", "-o", str(out), "--mode", "hidden", "--edges", "feature",
                     "--hidden", "dashed", "--size", "320x240"])
    finally:
        os.umask(old)
    assert code == 0
    assert os.stat(out).st_mode & 0o777 == 0o640
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo.svg"]
    root, layers = _parse(out.read_text())
    assert root.get("viewBox") == "0 0 320 240" and len(layers) == 2


@pytest.mark.parametrize("argv, message", [
    (["--mode", "solid"], "--mode wire or hidden"),
    (["--depth", "d.npy"], "--depth"),
    (["--crease-angle", "400", "--edges", "feature"], "crease_angle"),
])
def test_cli_errors_are_one_line_and_exit_2(tmp_path, capsys, argv, message):
    out = tmp_path / "x.svg"
    code = main(["render", "--demo", "-o", str(out), *argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and message in err[0]
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_cli_hidden_dashed_needs_svg(tmp_path, capsys):
    code = main(["render", "--demo", "-o", str(tmp_path / "x.png"), "--hidden", "dashed"])
    assert code == 2 and "--hidden" in capsys.readouterr().err


def test_an_edge_behind_a_comb_is_split_at_every_tooth():
    # a long far edge behind 8 near squares: 17 runs, more than the first pass keeps per edge
    v = [(-6.0, 0.0, -1.0), (6.0, 0.0, -1.0), (6.0, 0.1, -1.0)]
    faces = [(0, 1, 2)]
    for k in range(8):
        x = -4.4 + 1.1 * k
        base = len(v)
        v += [(x, -0.3, 0.0), (x + 0.5, -0.3, 0.0), (x + 0.5, 0.3, 0.0), (x, 0.3, 0.0)]
        faces += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    mesh = Mesh(np.array(v), np.array(faces))
    camera = Camera.look_at((0.3, 0.2, 8.0), (0, 0, -0.5), width=900, height=300)
    pieces = split_visible(camera.project_h(mesh.vertices), mesh.faces, np.array([[0, 1]]), 900, 300)
    assert len(pieces.xy) == 17
    assert list(pieces.hidden) == [k % 2 == 1 for k in range(17)]
    proj = camera.project(mesh.vertices)[:, :2]
    for k in range(8):  # each hidden piece starts and ends where the tooth's sides cross the edge
        left, right = 3 + 4 * k, 4 + 4 * k
        start = _crossing(proj[0], proj[1], proj[left], proj[left + 3])
        end = _crossing(proj[0], proj[1], proj[right], proj[right + 1])
        assert np.abs(pieces.xy[2 * k + 1] - [*start, *end]).max() < 1e-3
