"""How a line segment becomes pixels: brute force, DDA and Bresenham side by side.

:func:`line_steps` replays Bresenham's midpoint algorithm step by step with its decision
variable d, in plain Python integers, exactly as :mod:`rasterkit.raster.kernels.line` rounds;
:func:`line_grids` asks :func:`rasterkit.draw.line` for the pixels of each method;
:func:`format_line` prints both for ``rasterkit explain --line``.

The decision variable
---------------------
The line is stepped along its major axis u (x when ``|dx| >= |dy|``), from the end with the
smaller u, as the kernel does; ``n = |du|`` steps, ``a = |dv|`` and the minor coordinate v
moves by ``s = sign(dv)``. The ideal line rounds half up: on a tie the larger v wins, which
is a minor step when ``s = +1`` and none when ``s = -1``; ``c = 0`` or ``1`` says which.
After k minor steps, at step t, ::

    d = 2 n (a (t + 1) / n - (k + 1/2)) - c = 2 a (t + 1) - n (2 k + 1) - c,

2n times how far the ideal line at the next step passes beyond the midpoint between the two
candidate pixels (less c): ``d >= 0`` takes the minor step. It starts at ``2a - n - c`` and
grows by ``2a`` after a straight step, by ``2a - 2n`` after a minor step: the kernel's error
term r is ``d + 2n - 2a``.
"""

from __future__ import annotations

from dataclasses import dataclass

from rasterkit.explain._text import wrap

__all__ = ["MAX_GRID", "BresenhamStep", "LineSteps", "check_segment", "format_line",
           "line_grids", "line_steps"]

#: Largest grid ``explain --line`` draws, pixels in x and in y.
MAX_GRID = 64

#: Largest coordinate, as for :func:`rasterkit.draw.line`.
_COORD_LIMIT = 2**29

#: The methods of :func:`rasterkit.draw.line`, in the order printed, with their titles.
METHODS = (("naive", "brute force: v = m u + b"), ("dda", "DDA: v += m"),
           ("bresenham", "Bresenham: integers"))


@dataclass(frozen=True)
class BresenhamStep:
    """One step of Bresenham's algorithm: the pixel, and the decision taken there.

    Attributes
    ----------
    t : int
        Step number, 0 to n.
    x, y : int
        The pixel drawn at this step.
    d : int or None
        The decision variable that chooses the move to the next pixel (None at the end).
    move : str
        The move it chose, e.g. ``"x+1"`` or ``"x+1 y-1"``; ``"end"`` at the last pixel.
    """

    t: int
    x: int
    y: int
    d: int | None
    move: str


@dataclass(frozen=True)
class LineSteps:
    """Bresenham's run over a segment (see the module docstring for the symbols).

    Attributes
    ----------
    start, end : (int, int)
        The endpoints in stepping order (the one with the smaller major coordinate first).
    major, minor : {'x', 'y'}
        The axis stepped once per pixel, and the other one.
    n, a, s, c : int
        Major steps, minor extent ``|dv|``, minor direction (+1 or -1), tie offset (0, 1).
    steps : list of BresenhamStep
        n + 1 steps, from ``start`` to ``end``.
    """

    start: tuple[int, int]
    end: tuple[int, int]
    major: str
    minor: str
    n: int
    a: int
    s: int
    c: int
    steps: list[BresenhamStep]

    @property
    def pixels(self) -> list[tuple[int, int]]:
        """The (x, y) pixels, from ``start`` to ``end``."""
        return [(step.x, step.y) for step in self.steps]


def check_segment(x0: int, y0: int, x1: int, y1: int) -> None:
    """Refuse a segment that ``explain --line`` cannot draw.

    Raises
    ------
    TypeError
        If a coordinate is not an int (bools are refused).
    ValueError
        If a coordinate lies outside ``[-2**29, 2**29]`` or the segment needs a grid larger
        than :data:`MAX_GRID` pixels in x or y.
    """
    for name, value in zip(("x0", "y0", "x1", "y1"), (x0, y0, x1, y1)):
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError(f"{name} must be a whole number, got {value!r}")
        if abs(value) > _COORD_LIMIT:
            raise ValueError(f"{name} must lie in [-2**29, 2**29], got {value}")
    width, height = abs(x1 - x0) + 1, abs(y1 - y0) + 1
    if width > MAX_GRID or height > MAX_GRID:
        raise ValueError(f"the segment needs a {width}x{height} grid; explain --line draws at "
                         f"most {MAX_GRID}x{MAX_GRID} (|x1 - x0| and |y1 - y0| up to {MAX_GRID - 1})")


def line_steps(x0: int, y0: int, x1: int, y1: int) -> LineSteps:
    """Bresenham's midpoint algorithm over a segment, step by step, with its decision variable.

    Parameters
    ----------
    x0, y0, x1, y1 : int
        Endpoint pixels, raster space (x right, y down), within :func:`check_segment`'s limits.

    Returns
    -------
    LineSteps
        Its pixels are those of ``rasterkit.draw.line(x0, y0, x1, y1, "bresenham")``, in
        stepping order (reversed when the segment runs towards a smaller major coordinate).

    Examples
    --------
    >>> run = line_steps(0, 0, 4, 1)
    >>> [(s.x, s.y, s.d, s.move) for s in run.steps]   # d = 0 is a tie: towards +y
    [(0, 0, -2, 'x+1'), (1, 0, 0, 'x+1 y+1'), (2, 1, -6, 'x+1'), (3, 1, -4, 'x+1'), (4, 1, None, 'end')]
    """
    check_segment(x0, y0, x1, y1)
    steep = abs(y1 - y0) > abs(x1 - x0)
    u0, v0, u1, v1 = (y0, x0, y1, x1) if steep else (x0, y0, x1, y1)
    if u1 < u0:  # the kernel steps from the smaller major coordinate
        u0, v0, u1, v1 = u1, v1, u0, v0
    n, a = u1 - u0, abs(v1 - v0)
    s = 1 if v1 >= v0 else -1
    c = 0 if v1 > v0 else 1  # ties go to the larger v: a minor step only when s = +1
    major, minor = ("y", "x") if steep else ("x", "y")

    def xy(u: int, v: int) -> tuple[int, int]:
        return (v, u) if steep else (u, v)

    steps, v, d = [], v0, 2 * a - n - c
    for t in range(n):
        take = d >= 0
        move = f"{major}+1" + (f" {minor}{'+' if s > 0 else '-'}1" if take else "")
        steps.append(BresenhamStep(t, *xy(u0 + t, v), d, move))
        v += s if take else 0
        d += 2 * a - (2 * n if take else 0)
    steps.append(BresenhamStep(n, *xy(u1, v), None, "end"))
    return LineSteps(xy(u0, v0), xy(u1, v1), major, minor, n, a, s, c, steps)


def line_grids(x0: int, y0: int, x1: int, y1: int) -> dict[str, set[tuple[int, int]]]:
    """The pixel set of each method of :func:`rasterkit.draw.line` for a segment.

    Returns
    -------
    dict
        ``{"naive": {(x, y), ...}, "dda": ..., "bresenham": ...}``.
    """
    check_segment(x0, y0, x1, y1)
    from rasterkit.draw import line  # the kernels, and Numba, load here

    return {method: {(int(x), int(y)) for x, y in line(x0, y0, x1, y1, method)}
            for method, _ in METHODS}


def _x_header(xs: range) -> tuple[str, str]:
    """Two rows over the grid's columns: some full x values (each tenth), then x's last digit."""
    labels = [" "] * len(xs)
    free = 0  # the first column a label may start in
    for i, x in enumerate(xs):
        if i >= free and (i == 0 or x % 10 == 0):
            text = str(x)
            if i + len(text) > len(xs) and i > 0:
                break
            labels[i:i + len(text)] = text
            free = i + len(text) + 1
    return "".join(labels), "".join(str(abs(x) % 10) for x in xs)


def _grid_block(title: str, pixels: set, xs: range, ys: range) -> list[str]:
    """The lines of one grid: title, the x labels, one row per y ('#' drawn, '.' not)."""
    gutter = max(len(str(y)) for y in ys)
    tens, ones = _x_header(xs)
    lines = [" " * (gutter + 3) + tens, "x".rjust(gutter + 2) + " " + ones]
    for k, y in enumerate(ys):
        cells = "".join("#" if (x, y) in pixels else "." for x in xs)
        lines.append(f"{'y' if k == 0 else ' '} {str(y).rjust(gutter)} {cells}")
    width = max(len(title), max(len(line) for line in lines))
    return [title.ljust(width)] + [line.ljust(width) for line in lines]


def _differences(grids: dict) -> list[str]:
    reference = grids["bresenham"]
    lines = []
    for method, title in METHODS[:2]:
        name = title.split(":")[0]
        extra, missing = sorted(grids[method] - reference), sorted(reference - grids[method])
        if not extra:
            lines.append(f"{name} draws the same pixels as Bresenham.")
        else:
            lines += wrap(f"{name} differs from Bresenham (rounding error decided a tie): it "
                          f"draws {', '.join(map(str, extra))} instead of "
                          f"{', '.join(map(str, missing))}.")
    return lines


def _tie(run: LineSteps) -> str:
    """The sentence on c, the tie rule."""
    if run.a == 0:
        return f"c = 1: {run.minor} never changes, and d < 0 at every step"
    if run.c == 0:
        return (f"c = 0: {run.minor} increases, so on a tie (d = 0) the step to the "
                f"larger {run.minor} is taken")
    return (f"c = 1: {run.minor} decreases, so on a tie d = -1 < 0: no step, the larger "
            f"{run.minor} stays")


def _step_table(run: LineSteps) -> list[str]:
    straight, diagonal = 2 * run.a, 2 * run.a - 2 * run.n
    minor_move = f"{run.minor}{'+' if run.s > 0 else '-'}1"
    sentences = [
        f"Bresenham's decision variable, stepping from {run.start} to {run.end} along "
        f"{run.major}: n = |d{run.major}| = {run.n}, a = |d{run.minor}| = {run.a}.",
        f"d = 2a(t+1) - n(2k+1) - c after k {run.minor}-steps: 2n times how far the ideal line "
        f"at the next {run.major} passes the midpoint between the two candidate pixels, less c.",
        f"{_tie(run)}.",
        f"Start: d = 2a - n - c = {2 * run.a - run.n - run.c}. "
        f"d >= 0: {run.major}+1 {minor_move}, d += 2a - 2n = {diagonal}; "
        f"d < 0: {run.major}+1, d += 2a = {straight}.",
    ]
    lines = wrap(sentences[0]) + [line for text in sentences[1:] for line in wrap(text, "  ")]
    lines.append("")
    rows = [("t", "x", "y", "d", "move")] + [
        (str(s.t), str(s.x), str(s.y), "-" if s.d is None else str(s.d), s.move) for s in run.steps]
    widths = [max(len(row[j]) for row in rows) for j in range(4)]
    return lines + ["  " + "  ".join(cell.rjust(w) for cell, w in zip(row, widths)) + "  " + row[4]
                    for row in rows]


def format_line(x0: int, y0: int, x1: int, y1: int) -> str:
    """The text of ``rasterkit explain --line X0,Y0,X1,Y1``.

    Returns
    -------
    str
        The three methods' pixel grids side by side over the segment's bounding box ('#'
        drawn, '.' not; x to the right, y down), where they differ, and a table of
        Bresenham's steps: t, x, y, the decision variable d and the move it chose.
    """
    grids = line_grids(x0, y0, x1, y1)
    run = line_steps(x0, y0, x1, y1)
    xs = range(min(x0, x1), max(x0, x1) + 1)
    ys = range(min(y0, y1), max(y0, y1) + 1)
    if run.n == 0:
        intro = f"A single pixel, ({x0}, {y0}): no step, nothing to decide."
    else:
        du, dv = (x1 - x0, y1 - y0) if run.major == "x" else (y1 - y0, x1 - x0)
        intro = (f"Line from ({x0}, {y0}) to ({x1}, {y1}): dx = {x1 - x0}, dy = {y1 - y0}; "
                 f"{run.major} is the major axis (u), {run.minor} the minor one (v), slope "
                 f"m = d{run.minor}/d{run.major} = {dv}/{du}: {run.n + 1} pixels, one per "
                 f"{run.major}. Each method rounds the ideal {run.minor} half up (a tie goes to "
                 f"the larger {run.minor}).")
    lines = wrap(intro) + ["'#' drawn, '.' not; x to the right, y down.", ""]
    blocks = [_grid_block(title, grids[method], xs, ys) for method, title in METHODS]
    lines += ["   ".join(parts).rstrip() for parts in zip(*blocks)]
    lines += [""] + _differences(grids)
    return "\n".join(lines if run.n == 0 else lines + [""] + _step_table(run))
