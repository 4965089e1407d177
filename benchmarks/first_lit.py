"""The ``startup`` family's first lit renders: what lights, shadows and ambient occlusion add
to the compiling of a first render.

``rasterkit render stanford-bunny.obj -o x.png --mode solid`` (the plain first render)
against the same command with ``--shading phong`` and two lights (a directional and a point
light), with ``--shading phong --light directional:... --shadows``, and with ``--ao``, each
alone in a new, empty ``NUMBA_CACHE_DIR`` (every kernel it needs compiles, the command line's
first-run helpers included), as a whole process started by :func:`benchmarks.launch.launch`:
wall and user CPU seconds (user CPU counts the helper processes' compiling too). The order
rotates each round; medians are reported. Issue 29's bar: each adds <= 8 s of compiling,
recorded as the difference of the wall medians against a peer ``budget`` of 8 s.
"""

from __future__ import annotations

import statistics
from pathlib import Path

from .launch import cold_runs, rasterkit_command
from .report import Record, Target
from .settings import model_path

FAMILY = "startup"
MODEL = "stanford-bunny"
BUDGET = 8.0
"""Seconds a first lit render may add to the first plain one (issue 29)."""

TARGET = Target(f"a first lit render adds <= {BUDGET:g} s (issue 29)", 1.0)

#: The lit variants: label -> the flags added to the plain render.
VARIANTS = {
    "phong": ["--shading", "phong", "--light", "directional:-1,-2,-1:#ffe0b0:0.9",
              "--light", "point:1,0.5,1:#80b0ff:0.3"],
    "shadows": ["--shading", "phong", "--light", "directional:-1,-2,-1", "--shadows"],
    "ao": ["--ao"],
}


def _argv(path: Path, scratch: Path, flags: list[str]) -> list[str]:
    return rasterkit_command() + ["render", str(path), "-o", str(scratch / "first-lit.png"), "--mode", "solid",
                                  *flags]


def _records(runs: dict) -> list[Record]:
    """Each variant against the plain render (wall and user CPU), and the difference of the
    wall medians against the budget."""
    wall = {label: statistics.median(r["seconds"] for r in done) for label, done in runs.items()}
    user = {label: statistics.median(r["user"] for r in done) for label, done in runs.items()}
    count = min(len(done) for done in runs.values())
    note = "new process, empty NUMBA_CACHE_DIR each, --mode solid at the default size"
    records = []
    for label in VARIANTS:
        sizes = {"model": MODEL, "mode": "solid", "variant": label}
        base = f"startup/first-lit/{label}/{MODEL}"
        flags = " ".join(VARIANTS[label])
        records += [
            Record(family=FAMILY, name=base, peer="plain", sizes=sizes, rasterkit=wall[label], peer_value=wall["plain"],
                   runs=count, note=f"{note}; {flags}"),
            Record(family=FAMILY, name=f"{base}/added", peer="budget", sizes=sizes,
                   rasterkit=wall[label] - wall["plain"], peer_value=BUDGET, target=TARGET, runs=count,
                   note=f"median wall seconds {label} - plain; user CPU {user[label] - user['plain']:+.1f} s"),
        ]
    return records


def run(settings, results, scratch: Path) -> None:
    """``settings.lit_cold_runs`` rounds of first renders (0: skipped, with the reason)."""
    what = f"startup/first-lit/{MODEL}"
    if settings.lit_cold_runs == 0:
        results.skip(FAMILY, what, f"not measured in the {settings.name} profile (four first renders "
                     "in empty caches each round, each compiling every kernel it needs: about a minute)")
        return
    path = model_path(MODEL)
    if not path.is_file():
        results.skip(FAMILY, what, f"model file {path} not found")
        return
    commands = {"plain": _argv(path, scratch, [])}
    commands.update({label: _argv(path, scratch, flags) for label, flags in VARIANTS.items()})
    try:
        runs = cold_runs(commands, settings.lit_cold_runs, scratch)
    except RuntimeError as error:
        results.skip(FAMILY, what, f"failed: {error}")
        return
    for record in _records(runs):
        results.add(record)
