"""The ``startup`` family's first textured render: what texturing adds to the compiling.

``rasterkit render fuze.obj -o x.png --mode solid --shading smooth`` (its ``.mtl`` names
``fuze uv.jpg``: drawn textured, trilinear) against the same command with ``--no-textures``,
each alone in a new, empty ``NUMBA_CACHE_DIR`` (so every kernel it needs compiles), as a whole
process started by :func:`benchmarks.launch.launch`: wall and user CPU seconds. Repetitions
alternate which goes first; medians are reported. The issue's bar: the textured render adds
<= 8 s of compiling, recorded as the difference of the medians against a peer ``budget`` of 8 s.
"""

from __future__ import annotations

import statistics
from pathlib import Path

from .launch import cold_runs, rasterkit_command
from .report import Record, Target
from .settings import MODELS_DIR

FAMILY = "startup"
MODEL = "fuze", "formats/obj/fuze/fuze.obj"
UNTEXTURED = "--no-textures"
BUDGET = 8.0
"""Seconds the first textured render may add to the first untextured one (issue 27)."""

TARGET = Target(f"the first textured render adds <= {BUDGET:g} s (issue 27)", 1.0)


def _argv(path: Path, scratch: Path, textured: bool) -> list[str]:
    argv = rasterkit_command() + ["render", str(path), "-o", str(scratch / "first-textured.png"),
                                  "--mode", "solid", "--shading", "smooth"]
    return argv if textured else argv + [UNTEXTURED]


def _records(name: str, runs: dict) -> list[Record]:
    """The textured render against the untextured one (wall and user CPU), and the difference
    of the wall medians against the budget."""
    sizes = {"model": name, "mode": "solid", "shading": "smooth"}
    note = "new process, empty NUMBA_CACHE_DIR each, --mode solid --shading smooth at the default size"
    base = f"startup/first-textured/{name}"
    wall = {side: statistics.median(r["seconds"] for r in done) for side, done in runs.items()}
    user = {side: statistics.median(r["user"] for r in done) for side, done in runs.items()}
    count = min(len(done) for done in runs.values())
    return [
        Record(family=FAMILY, name=base, peer=UNTEXTURED, sizes=sizes, rasterkit=wall[True],
               peer_value=wall[False], runs=count, note=note),
        Record(family=FAMILY, name=f"{base}/user-cpu", peer=UNTEXTURED, sizes=sizes, rasterkit=user[True],
               peer_value=user[False], runs=count, note=note + "; user CPU seconds"),
        Record(family=FAMILY, name=f"{base}/added", peer="budget", sizes=sizes, rasterkit=wall[True] - wall[False],
               peer_value=BUDGET, target=TARGET, runs=count,
               note=f"median wall seconds textured - {UNTEXTURED}; user CPU "
                    f"{user[True] - user[False]:+.1f} s"),
    ]


def run(settings, results, scratch: Path) -> None:
    """``settings.textured_cold_runs`` pairs of first renders (0: skipped, with the reason)."""
    name, relative = MODEL
    what = f"startup/first-textured/{name}"
    if settings.textured_cold_runs == 0:
        results.skip(FAMILY, what, f"not measured in the {settings.name} profile (two first renders "
                     "in empty caches, each compiling every kernel it needs: about a minute)")
        return
    path = MODELS_DIR / relative
    if not path.is_file():
        results.skip(FAMILY, what, f"model file {path} not found")
        return
    try:
        runs = cold_runs({True: _argv(path, scratch, True), False: _argv(path, scratch, False)},
                         settings.textured_cold_runs, scratch)
    except RuntimeError as error:
        results.skip(FAMILY, what, f"failed: {error}")
        return
    records = _records(name, runs)
    for record in records:
        results.add(record)
    print(f"  first textured render of {name} adds {records[-1].rasterkit:.2f} s over {UNTEXTURED} "
          f"(budget {BUDGET:g} s)", flush=True)
