"""Benchmark: rasterkit.load_obj against trimesh and a plain Python line-by-line parser.

Run from the repository root::

    python benchmarks/bench_obj.py                  # the two large models
    python benchmarks/bench_obj.py --repeat 9 path/to/other.obj

Each loader runs once to warm up (Numba loads or compiles its kernels, the OS caches the file),
then the loaders take turns, ``--repeat`` rounds, so that a busy machine slows all of them
alike. Medians are reported, with trimesh's median divided by rasterkit's.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT.parent / "shared" / "models"
DEFAULT_MODELS = ("lost_empire.obj", "sportsCar.obj")

sys.path.insert(0, str(ROOT))

from rasterkit.obj import load_obj  # noqa: E402


def python_baseline(path: Path):
    """A line-by-line pure-Python OBJ reader (v and f only, fan triangulation): the speed of
    the obvious implementation, for reference."""
    vertices, faces = [], []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "v":
                vertices.append((float(words[1]), float(words[2]), float(words[3])))
            elif words[0] == "f":
                n = len(vertices)
                ids = [int(w.split("/")[0]) for w in words[1:]]
                ids = [i - 1 if i > 0 else n + i for i in ids]
                faces.extend((ids[0], ids[k], ids[k + 1]) for k in range(1, len(ids) - 1))
    return vertices, faces


def trimesh_loader():
    """trimesh.load(path, force='mesh', process=False), or None when trimesh is missing."""
    try:
        import trimesh
    except ImportError:
        return None
    return lambda path: trimesh.load(path, force="mesh", process=False)


def seconds(fn, path) -> float:
    start = time.perf_counter()
    fn(path)
    return time.perf_counter() - start


def bench(path: Path, repeat: int, baseline_repeat: int) -> dict:
    """Median seconds of each loader on one file, interleaved after one warm-up run each."""
    loaders = {"rasterkit": load_obj, "trimesh": trimesh_loader(), "python": python_baseline}
    loaders = {name: fn for name, fn in loaders.items() if fn is not None}
    times = {name: [] for name in loaders}
    for fn in loaders.values():
        fn(path)
    for r in range(repeat):
        for name, fn in loaders.items():
            if name != "python" or r < baseline_repeat:
                times[name].append(seconds(fn, path))
    return {name: statistics.median(t) for name, t in times.items()}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("models", nargs="*", type=Path,
                        help=f"OBJ files (default: {', '.join(DEFAULT_MODELS)} in {MODELS})")
    parser.add_argument("--repeat", type=int, default=7, help="timed rounds (default 7)")
    parser.add_argument("--baseline-repeat", type=int, default=3,
                        help="rounds of the slow Python baseline (default 3)")
    args = parser.parse_args(argv)
    paths = args.models or [MODELS / name for name in DEFAULT_MODELS]
    missing = [str(p) for p in paths if not p.is_file()]
    if missing:
        print("skipped: model files not found: " + ", ".join(missing))
        return 0
    print(f"{'model':24s} {'MiB':>6s} {'rasterkit':>10s} {'trimesh':>10s} {'python':>10s} "
          f"{'trimesh/rk':>11s} {'python/rk':>10s}")
    for path in paths:
        median = bench(path, args.repeat, args.baseline_repeat)
        rk = median["rasterkit"]
        tm = median.get("trimesh")
        print(f"{path.name:24s} {path.stat().st_size / 2**20:6.1f} {rk * 1e3:8.1f}ms "
              + (f"{tm * 1e3:8.1f}ms " if tm else f"{'-':>10s} ")
              + f"{median['python'] * 1e3:8.1f}ms "
              + (f"{tm / rk:10.1f}x " if tm else f"{'-':>11s} ")
              + f"{median['python'] / rk:9.1f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
