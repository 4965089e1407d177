"""``python -m benchmarks [--quick | --targets] [--out DIR] [--only FAMILY,...] [--no-peers]``.

Runs the workload families in turn, printing each result (and each skipped peer, with the
reason) as it comes, then writes ``results.json``, ``results.md`` and the PNG plots to DIR.
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import importlib.metadata
import os
import platform
import sys
import time
from pathlib import Path

import numba

from . import (aa, batch, cli, contention, cv, fill, lighting, lines2d, loading, memory, render, report, scaling,
               startup, svg, textures, viewer)
from .first_models import MODES as FIRST_MODES
from .peers import Peers
from .settings import FULL, QUICK, TARGETS, TINY

# The families that start processes come last: in one run, rasterkit's 2-thread kernels in this
# process were seen to slow down ~10x for a minute after the CLI family's subprocesses.
FAMILIES = {"render": render.run, "aa": aa.run, "cv": cv.run, "textures": textures.run, "lighting": lighting.run,
            "svg": svg.run, "fill": fill.run, "lines2d": lines2d.run, "loading": loading.run, "scaling": scaling.run,
            "memory": memory.run, "cli": cli.run, "startup": startup.run, "contention": contention.run, "batch": batch.run,
            "threads": scaling.run_threads, "viewer": viewer.run}
DEFAULT_FAMILIES = ("render", "aa", "cv", "textures", "lighting", "svg", "fill", "lines2d", "loading", "scaling",
                    "memory", "cli", "startup", "contention", "batch", "viewer")
"""What a run measures unless ``--only`` says otherwise (``threads`` is part of ``scaling``)."""
TARGET_FAMILIES = ("render", "aa", "fill", "threads", "textures", "lighting")

PACKAGES = ("rasterkit", "numpy", "numba", "llvmlite", "pillow", "moderngl", "opencv-python-headless",
            "trimesh", "scikit-image")

TINY_VARIABLE = "RASTERKIT_BENCH_TINY"
"""Set to 1 for the tiny profile (64x48, one run): the smoke test's way in, like ``--tiny``."""


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="a small version (about 4 minutes, most of it cold start-up runs)")
    parser.add_argument("--targets", action="store_true",
                        help="only the targets: 3 models at 1920x1080, 4 samples against 4x MSAA, "
                             "the fill scene, 2 threads vs 1, textured and lit frames (about a minute; "
                             "families render,aa,fill,threads,textures,lighting)")
    parser.add_argument("--tiny", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--out", type=Path, default=Path("benchmark-results"),
                        help="folder for results.json, results.md and the plots "
                             "(default: benchmark-results)")
    parser.add_argument("--only", default=None, metavar="FAMILY,...",
                        help=f"families to run (default: {','.join(DEFAULT_FAMILIES)}; also threads)")
    parser.add_argument("--no-peers", action="store_true", help="time rasterkit alone")
    parser.add_argument("--first-modes", default=None, metavar="MODE,...",
                        help="modes of the startup family's first renders of ten models "
                             "(default: solid; also wire, hidden, solid+wire)")
    return parser


def _versions() -> dict:
    versions = {}
    for package in PACKAGES:
        try:
            versions[package] = importlib.metadata.version(package)
        except importlib.metadata.PackageNotFoundError:
            versions[package] = "not installed"
    return versions


ENVIRONMENT = ("NUMBA_NUM_THREADS", "NUMBA_THREADING_LAYER", "OMP_WAIT_POLICY", "LP_NUM_THREADS")
"""Environment variables that change the threading of either side, recorded when set."""


def _threading_layer() -> str | None:
    try:
        return numba.threading_layer()
    except ValueError:  # no parallel kernel has run in this process
        return None


def machine(peers: Peers, started: float) -> dict:
    """What the figures were measured on."""
    return {"platform": platform.platform(), "processor": platform.processor() or platform.machine(),
            "cpu_count": os.cpu_count(), "threads": numba.config.NUMBA_NUM_THREADS,
            "python": platform.python_version(), "versions": _versions(),
            "threading_layer": _threading_layer(),
            "environment": {k: os.environ[k] for k in ENVIRONMENT if k in os.environ},
            "gl_renderer": peers.gl_renderer,
            "started": datetime.datetime.fromtimestamp(started).isoformat(timespec="seconds"),
            "seconds": round(time.time() - started, 1)}


def write(out: Path, results: report.Results, profile: str, info: dict) -> None:
    """results.json, results.md and the plots (see report.py)."""
    out.mkdir(parents=True, exist_ok=True)
    report.write_json(out / "results.json", results, profile, info)
    (out / "results.md").write_text(report.markdown(results, profile, info))
    for name, title, x_label, series in report.plot_series(results):
        report.plot(out / name, title, x_label, "median time", series)


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    settings = TINY if args.tiny or os.environ.get(TINY_VARIABLE) == "1" else QUICK if args.quick \
        else TARGETS if args.targets else FULL
    if args.only is not None:
        families = [f.strip() for f in args.only.split(",") if f.strip()]
    else:
        families = list(TARGET_FAMILIES if args.targets else DEFAULT_FAMILIES)
    if args.first_modes is not None:
        modes = tuple(m.strip() for m in args.first_modes.split(",") if m.strip())
        if not modes or set(modes) - set(FIRST_MODES):
            print(f"--first-modes: choose from {', '.join(FIRST_MODES)}", file=sys.stderr)
            return 2
        settings = dataclasses.replace(settings, first_model_modes=modes)
    unknown = sorted(set(families) - set(FAMILIES))
    if unknown:
        print(f"unknown families: {', '.join(unknown)} (choose from {', '.join(FAMILIES)})", file=sys.stderr)
        return 2
    started = time.time()
    peers, results = Peers(enabled=not args.no_peers), report.Results()
    print(f"rasterkit benchmarks, {settings.name} profile, {numba.config.NUMBA_NUM_THREADS} threads, "
          f"{os.cpu_count()} CPUs", flush=True)
    for family in families:
        print(f"{family}:", flush=True)
        FAMILIES[family](settings, results, peers)
    info = machine(peers, started)
    write(args.out, results, settings.name, info)
    print(f"wrote {args.out}/results.json, results.md and plots in {info['seconds']:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
