"""``rasterkit explain``: the camera chain factor by factor, and three line algorithms' pixels.

The expectations are independent of the implementation: the lecture's factor names written
out, the camera's own matrix and projection, hand-drawn grids, and the round-half-up rule of
the ideal line computed with exact fractions.
"""

import doctest
import importlib
import math
import random
import re
from fractions import Fraction

import numpy as np
import pytest

from rasterkit import Camera
from rasterkit.cli.args import attach_number_lists, view_from_args
from rasterkit.cli import _parser, main
from rasterkit.draw import line
from rasterkit.explain import chain_steps, line_steps
from rasterkit.runtime.notice import MESSAGE
from rasterkit.shapes import cube
from support.startup import MAIN, fresh

PERSPECTIVE = ["T", "R", "H", "S_xy", "S_far", "P_persp", "P_parallel", "S_raster", "Raster"]
PARALLEL = ["T", "R", "T_near", "S_xyz", "P_parallel", "S_raster", "Raster"]

# A camera the test builds on its own, and the flags that ask explain for the same one.
VIEW = ["--eye", "1,2,6", "--target", "0,0.5,0", "--fov", "50", "--near", "0.5", "--far", "20",
        "--size", "64x48"]


def _camera() -> Camera:
    return Camera.look_at((1, 2, 6), (0, 0.5, 0), fov_y=50, width=64, height=48, near=0.5, far=20)


def _run(argv, capsys) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _explain(argv, capsys) -> str:
    code, out, err = _run(["explain", *argv], capsys)
    assert code == 0, err
    assert err in ("", MESSAGE + "\n")  # the notice of a first compile, when this test runs first
    return out


# --- parsing the printed text ----------------------------------------------------------------


def _factor_names(text: str) -> list[str]:
    return re.findall(r"^\d+\. (\w+): ", text, re.M)


def _blocks(text: str) -> list[list[list[float]]]:
    """Each run of bracketed rows (``| a  b |   | c |``) as a list of rows of groups."""
    runs, current = [], []
    for line_ in text.splitlines():
        groups = re.findall(r"\|([^|]*)\|", line_)
        if line_.startswith("     |") and groups:
            current.append([[float(v) for v in g.split()] for g in groups])
        elif current:
            runs.append(current)
            current = []
    return runs + ([current] if current else [])


def _matrices_and_points(text: str):
    """The printed matrices (4x4) and, with a point, the vectors before and after each."""
    blocks = _blocks(text)
    matrices = [np.array([row[0] for row in block]) for block in blocks]
    points = [(np.array([row[1][0] for row in block]), np.array([row[2][0] for row in block]))
              for block in blocks if len(block[0]) == 3]
    return matrices, points


def _number(text: str, name: str) -> float:
    return float(re.search(rf"{re.escape(name)} = (-?[\d.e+-]+)", text).group(1))


# --- the chain -------------------------------------------------------------------------------


@pytest.mark.parametrize("flags, names", [
    ([], PERSPECTIVE),
    (["--projection", "orthographic"], PARALLEL),
    (["--projection", "cabinet"], PARALLEL),
    (["--projection", "isometric"], PARALLEL),
    (["--projection", "2-point"], PERSPECTIVE),
])
def test_factor_names_are_the_lectures_first_applied_first(flags, names, capsys):
    out = _explain(["--size", "64x48", *flags], capsys)
    assert _factor_names(out) == names
    assert ("T_near" in out) == (names is PARALLEL) and ("P_persp" in out) == (names is PERSPECTIVE)


@pytest.mark.parametrize("point", [None, (0.2, 0.7, -0.3)])
def test_the_printed_matrices_multiply_to_the_cameras_matrix(point, capsys):
    flags = VIEW + ([] if point is None else ["--point", ",".join(map(str, point))])
    out = _explain(flags, capsys)
    matrices, _ = _matrices_and_points(out)
    assert len(matrices) == len(PERSPECTIVE) + 1  # the factors, then K
    product = np.eye(4)
    for m in matrices[:-1]:
        product = m @ product  # first applied first: each one multiplies from the left
    expected = _camera().matrix()
    scale = np.abs(expected).max()
    np.testing.assert_allclose(product, expected, rtol=1e-4, atol=1e-5 * scale)
    np.testing.assert_allclose(matrices[-1], expected, rtol=1e-5, atol=1e-6 * scale)
    assert "Check: K equals camera.matrix()" in out


@pytest.mark.parametrize("camera", [
    _camera(),
    Camera.look_at((3, -1, 2), (0, 0, 0), shift=(0.4, -0.2), width=33, height=17),
    Camera.orthographic((2, 3, 4), (0, 0, 0), view_height=3, width=40, height=30),
    Camera.cabinet((0, 0, 0), 1.0, width=40, height=30),
])
def test_chain_steps_product_and_point_agree_with_the_camera(camera):
    point = (0.3, -0.4, 0.25)
    steps = chain_steps(camera, point)
    assert [f.name for f in steps.factors] == [name for name, _ in camera.chain()]
    np.testing.assert_allclose(steps.product, camera.matrix(), rtol=1e-12, atol=1e-12)
    assert steps.agrees
    np.testing.assert_allclose(steps.factors[-1].point, camera.project_h([point])[0], rtol=1e-10)
    np.testing.assert_array_equal(steps.raster, camera.project([point])[0])
    x, y, _ = camera.project([point])[0]
    assert steps.pixel == (math.floor(x), math.floor(y))


def test_the_point_after_T_and_R_is_in_camera_space(capsys):
    # Eye on +z looking at the origin: camera space is world space moved by -5 along z.
    out = _explain(["--eye", "0,0,5", "--target", "0,0,0", "--size", "64x48",
                    "--point", "1,2,0"], capsys)
    _, points = _matrices_and_points(out)
    np.testing.assert_allclose(points[0][0], [1, 2, 0, 1])  # T's input: the world point
    np.testing.assert_allclose(points[0][1], [1, 2, -5, 1])  # after T
    np.testing.assert_allclose(points[1][1], [1, 2, -5, 1])  # after R (identity here)
    for (_, after), (before, _) in zip(points, points[1:]):
        np.testing.assert_array_equal(after, before)  # each factor takes the previous result


@pytest.mark.parametrize("point", [(0.2, 0.7, -0.3), (0, 0.5, 0), (-1.5, 0, 2), (0.01, 0.51, 0.02)])
def test_the_printed_end_is_camera_project_and_its_floor(point, capsys):
    out = _explain(VIEW + ["--point", ",".join(map(str, point))], capsys)
    x, y, depth = _camera().project([point])[0]
    assert _number(out, "x = xh/w") == pytest.approx(x, rel=1e-5, abs=1e-5)
    assert _number(out, "y = yh/w") == pytest.approx(y, rel=1e-5, abs=1e-5)
    assert _number(out, "depth = zh/w") == pytest.approx(depth, rel=1e-5)
    column, row = map(int, re.search(r"Pixel = \(floor\(x\), floor\(y\)\) = \((-?\d+), (-?\d+)\)",
                                     out).groups())
    assert (column, row) == (math.floor(x), math.floor(y))
    inside = 0 <= x < 64 and 0 <= y < 48
    assert (f"in pixel (column {column}, row {row}) of the 64x48 image" in out) == inside


def test_the_target_lands_on_the_image_centre_corner(capsys):
    # The target projects to (W/2, H/2) exactly, the top-left corner of pixel (32, 24).
    out = _explain(VIEW + ["--point", "0,0.5,0"], capsys)
    assert "Pixel = (floor(x), floor(y)) = (32, 24)" in out


def test_a_point_behind_the_eye_has_no_pixel(capsys):
    out = _explain(VIEW + ["--point", "2,4,12"], capsys)
    assert "behind the eye" in out and "Pixel =" not in out


def test_a_point_outside_the_image_says_so(capsys):
    out = _explain(VIEW + ["--point", "8,0.5,0"], capsys)
    assert "outside the 64x48 image" in out


@pytest.mark.parametrize("projection", ["orthographic", "cabinet"])  # w = 1: no divide brings it back
def test_a_point_beyond_float64_is_described_not_numbered(projection, capsys):
    out = _explain(VIEW + ["--projection", projection, "--point", "1e300,1e300,-1e300"], capsys)
    last = out.rstrip().splitlines()[-1]
    assert last.startswith("The point is ") and "no pixel" in last
    assert "Pixel =" not in out and max(map(len, out.splitlines())) < 140


def test_explain_shows_the_camera_render_would_use(tmp_path, capsys):
    flags = ["--size", "50x40", "--projection", "dimetric", "--azimuth", "10", "--distance", "7"]
    render_args = _parser().parse_args(["render", "--demo", "-o", "x.png", *flags])
    explain_args = _parser().parse_args(["explain", *flags])
    mesh = cube()
    assert view_from_args(render_args).camera_for(mesh) == view_from_args(explain_args).camera_for(mesh)
    out = _explain(flags, capsys)  # no model: the unit cube
    camera = view_from_args(render_args).camera_for(mesh)
    matrices, _ = _matrices_and_points(out)
    np.testing.assert_allclose(matrices[-1], camera.matrix(), rtol=1e-5,
                               atol=1e-6 * np.abs(camera.matrix()).max())


def test_negative_number_lists_need_no_equals_sign(capsys):
    out = _explain(["--eye", "-1,2,-6", "--target", "0,0.5,0", "--point", "-0.5,0,0"], capsys)
    assert "eye (-1, 2, -6)" in out and "The point p = (-0.5, 0, 0)" in out
    argv = attach_number_lists(["render", "--demo", "-o", "x.png", "--eye", "-3,2,4", "--up", "-"])
    assert argv[-3:] == ["--eye=-3,2,4", "--up", "-"]  # render's flags too; "-" is left alone


def test_a_model_file_is_framed(tmp_path, capsys):
    path = tmp_path / "tri.obj"
    path.write_text("v 0 0 0\nv 4 0 0\nv 0 2 0\nf 1 2 3\n")
    out = _explain([path, "--size", "64x48"], capsys)
    assert "target (2, 1, 0)" in out  # the centre of the bounding box


# --- lines -----------------------------------------------------------------------------------

METHODS = ("naive", "dda", "bresenham")


def _grids(text: str, x0: int, x1: int) -> list[set]:
    """The three printed grids as pixel sets; columns start at min(x0, x1)."""
    sets = [set(), set(), set()]
    for row in text.splitlines():
        cells = re.findall(r"(-?\d+) ([#.]+)(?=\s|$)", row)
        if len(cells) != 3:
            continue
        for grid, (y, marks) in zip(sets, cells):
            grid.update((min(x0, x1) + i, int(y)) for i, c in enumerate(marks) if c == "#")
    return sets


def _table(text: str) -> list[tuple[int, int, int, int | None, str]]:
    rows = re.findall(r"^\s+(\d+)\s+(-?\d+)\s+(-?\d+)\s+(-?\d+|-)  ([xy][+-]1(?: [xy][+-]1)?|end)$",
                      text, re.M)
    return [(int(t), int(x), int(y), None if d == "-" else int(d), move) for t, x, y, d, move in rows]


def test_hand_drawn_grid_of_0_0_to_7_3(capsys):
    out = _explain(["--line", "0,0,7,3"], capsys)
    expected = ["y 0 ##......",
                "  1 ..##....",
                "  2 ....##..",
                "  3 ......##"]
    rows = [r for r in out.splitlines() if re.match(r"^[y ] \d [#.]", r)]
    assert len(rows) == 4
    for row, want in zip(rows, expected):
        assert row.split("   ")[0].rstrip() == want  # first grid: brute force
        assert row.count(want[4:]) == 3  # the same row in all three grids
    assert _table(out) == [(0, 0, 0, -1, "x+1"), (1, 1, 0, 5, "x+1 y+1"), (2, 2, 1, -3, "x+1"),
                           (3, 3, 1, 3, "x+1 y+1"), (4, 4, 2, -5, "x+1"), (5, 5, 2, 1, "x+1 y+1"),
                           (6, 6, 3, -7, "x+1"), (7, 7, 3, None, "end")]


@pytest.mark.parametrize("segment", [(0, 0, 7, 3), (3, -2, -9, 12), (5, 5, 5, 5), (0, 4, 0, -4),
                                     (-3, 0, 6, 0), (0, 0, 18, 3), (0, 0, 63, 63), (2, 9, 8, 1)])
def test_printed_grids_are_draw_lines_pixel_sets(segment, capsys):
    out = _explain(["--line", ",".join(map(str, segment))], capsys)
    printed = _grids(out, segment[0], segment[2])
    for method, pixels in zip(METHODS, printed):
        assert pixels == {tuple(p) for p in line(*segment, method).tolist()}, method


def test_a_floating_point_tie_is_pointed_out(capsys):
    # DDA's running sum decides the tie at x = 15 of (0, 0)-(18, 3) the other way.
    out = _explain(["--line", "0,0,18,3"], capsys)
    assert "DDA differs from Bresenham" in out and "(15, 2) instead of (15, 3)" in out
    assert "brute force draws the same pixels as Bresenham" in out


def _ideal(x0, y0, x1, y1) -> list[tuple[int, int]]:
    """Round half up of the ideal line along its major axis, with exact fractions."""
    steep = abs(y1 - y0) > abs(x1 - x0)
    u0, v0, u1, v1 = (y0, x0, y1, x1) if steep else (x0, y0, x1, y1)
    n = abs(u1 - u0)
    pixels = []
    for t in range(n + 1):
        u = u0 + t * (1 if u1 >= u0 else -1)
        v = math.floor(v0 + Fraction(v1 - v0, n or 1) * t + Fraction(1, 2))
        pixels.append((v, u) if steep else (u, v))
    return pixels


def _replay(start, d_moves) -> list[tuple[int, int]]:
    """Pixels from the decision variables: d >= 0 takes the minor step."""
    pixels = [start]
    for (_, _, _, d, move) in d_moves:
        if d is None:
            break
        x, y = pixels[-1]
        steps = dict((m[0], 1 if m[1] == "+" else -1) for m in move.split())
        assert (len(steps) == 2) == (d >= 0)
        pixels.append((x + steps.get("x", 0), y + steps.get("y", 0)))
    return pixels


def _octant_segments(count: int, rng: random.Random):
    for k in range(count):
        octant = k % 8
        big = rng.randint(1, 40)
        small = rng.randint(0, big - (1 if octant % 2 else 0))  # odd octants: strictly steep
        dx, dy = (small, big) if octant % 2 else (big, small)
        dx, dy = dx * (-1 if octant & 2 else 1), dy * (-1 if octant & 4 else 1)
        x0, y0 = rng.randint(-20, 20), rng.randint(-20, 20)
        yield x0, y0, x0 + dx, y0 + dy


def test_decision_variable_reproduces_bresenham_in_every_octant():
    rng = random.Random(15)
    segments = list(_octant_segments(800, rng))
    segments += [(0, 0, 4, 2), (0, 2, 4, 0), (4, 2, 0, 0), (0, 0, 2, 4), (2, 0, 0, 4),
                 (0, 0, 6, 6), (0, 0, -6, 6), (0, 0, 9, 0), (0, 0, 0, -9), (1, 1, 1, 1)]
    for segment in segments:
        run = line_steps(*segment)
        steps = [(s.t, s.x, s.y, s.d, s.move) for s in run.steps]
        drawn = [tuple(p) for p in line(*segment, "bresenham").tolist()]
        replayed = _replay(run.start, steps)
        assert replayed == [(s.x, s.y) for s in run.steps], segment
        assert replayed in (drawn, drawn[::-1]), segment
        assert set(replayed) == set(_ideal(*segment)), segment
        # d as defined in the docstring: 2a(t+1) - n(2k+1) - c after k minor steps.
        k = 0
        for t, step in enumerate(run.steps[:-1]):
            assert step.d == 2 * run.a * (t + 1) - run.n * (2 * k + 1) - run.c, segment
            k += step.d >= 0


@pytest.mark.parametrize("segment", [(0, 0, 5, 2), (5, 2, 0, 0), (0, 0, 2, -5), (-4, 3, 3, -4),
                                     (7, 1, -6, 4), (0, 0, 4, 1), (0, 1, 4, 0), (3, 0, 2, 6)])
def test_printed_d_sequence_reproduces_draw_line(segment, capsys):
    out = _explain(["--line", ",".join(map(str, segment))], capsys)
    table = _table(out)
    assert len(table) == max(abs(segment[2] - segment[0]), abs(segment[3] - segment[1])) + 1
    drawn = [tuple(p) for p in line(*segment, "bresenham").tolist()]
    replayed = _replay(table[0][1:3], table)
    assert replayed == [row[1:3] for row in table]
    assert replayed in (drawn, drawn[::-1])


# --- errors and start-up ---------------------------------------------------------------------


@pytest.mark.parametrize("argv", [
    ["--line", "1,2,3"],
    ["--line", "1,2,3,4,5"],
    ["--line", "a,b,c,d"],
    ["--line", "0,0,1.5,2"],
    ["--line", "0,0,64,0"],
    ["--line", "0,0,0,-70"],
    ["--line", "99999999999,0,99999999999,3"],
    ["--line", "0,0,3,3", "--demo"],
    ["--line", "0,0,3,3", "--point", "1,2,3"],
    ["--point", "1,2"],
    ["--point", "1,2,inf"],
    ["--point", "1,,3"],
    ["--demo", "model.obj"],
    ["no-such-model.obj"],
    ["--size", "0x3"],
    ["--fov", "200"],
    ["--eye", "0,0,0", "--target", "0,0,0"],
    ["--near", "5", "--far", "1"],
])
def test_bad_input_is_one_line_and_exit_2(argv, capsys):
    code, out, err = _run(["explain", *argv], capsys)
    assert code == 2
    assert out == ""
    assert err.startswith("rasterkit: error: ") and err.count("\n") == 1, err


def test_a_too_large_grid_says_how_large_it_may_be(capsys):
    code, _, err = _run(["explain", "--line", "0,0,100,3"], capsys)
    assert code == 2 and "101x4 grid" in err and "at most 64x64" in err


def test_explain_help_imports_neither_numba_nor_numpy():
    done = fresh(MAIN, "explain", "--help")
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[-1] == "0 []"
    assert "usage: rasterkit explain" in done.stdout and "--line X0,Y0,X1,Y1" in done.stdout


def test_a_line_too_large_is_refused_before_numba_loads():
    done = fresh(MAIN, "explain", "--line", "0,0,500,0")
    code, modules = done.stdout.splitlines()[-1].split(" ", 1)
    assert code == "2" and "numba" not in modules
    assert done.stderr.count("\n") == 1


def test_the_main_help_describes_explain(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    assert "rasterkit explain --line 0,0,7,3" in out and "decision variable" in out


@pytest.mark.parametrize("module", ["chain", "line", "_text"])
def test_docstring_examples(module):
    result = doctest.testmod(importlib.import_module(f"rasterkit.explain.{module}"))
    assert result.attempted > 0 and result.failed == 0
