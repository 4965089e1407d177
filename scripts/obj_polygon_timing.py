"""Time and peak memory of load_obj on single huge polygons (issue 14, item 5).

``python scripts/obj_polygon_timing.py [CASE ...] [--timeout S]`` writes each model into a
temporary folder and loads it in a new process (after loading a small polygon there, so
that compiling is not counted), printing the wall time of load_obj and the process's peak
resident memory. Cases: convex-10k, convex-100k, convex-1m (regular polygons), repeated-300k
(``f 1 1 1 ... 2 3``), cycled-300k (``f 1 2 3 1 2 3 ...``), star-100k (a concave star of
alternating radii), line-50mb (one 50 MB face line walking a 1000-gon round and round) and
random-50mb (one 50 MB face line of random corners of a 1000-gon).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def _ring(n: int, radii=(1.0,)) -> str:
    t = 2 * np.pi * np.arange(n) / n
    r = np.resize(np.asarray(radii, float), n)
    xy = np.stack([r * np.cos(t), r * np.sin(t)], axis=1)
    return "".join(f"v {x:.17g} {y:.17g} 0\n" for x, y in xy)


def _face(indices) -> str:
    return "f " + " ".join(map(str, indices)) + "\n"


def _long_line(n_vertices: int, size: int, rng=None) -> str:
    """A face line of about size bytes over a regular n_vertices-gon."""
    digits = np.mean([len(str(k)) for k in range(1, n_vertices + 1)]) + 1
    count = int(size / digits)
    if rng is None:
        indices = np.arange(count) % n_vertices + 1
    else:
        indices = rng.integers(1, n_vertices + 1, count)
    return _ring(n_vertices) + _face(indices)


CASES = {
    "convex-10k": lambda: _ring(10_000) + _face(range(1, 10_001)),
    "convex-100k": lambda: _ring(100_000) + _face(range(1, 100_001)),
    "convex-1m": lambda: _ring(1_000_000) + _face(range(1, 1_000_001)),
    "repeated-300k": lambda: _ring(3) + _face([1] * (300_000 - 2) + [2, 3]),
    "cycled-300k": lambda: _ring(3) + _face([1, 2, 3] * 100_000),
    "star-100k": lambda: _ring(100_000, (1.0, 0.5)) + _face(range(1, 100_001)),
    "line-50mb": lambda: _long_line(1000, 50_000_000),
    "random-50mb": lambda: _long_line(1000, 50_000_000, np.random.default_rng(1)),
}

CHILD = """
import resource, sys, time
import rasterkit
warm = sys.argv[2]
rasterkit.load_obj(warm)
t = time.perf_counter()
mesh = rasterkit.load_obj(sys.argv[1])
elapsed = time.perf_counter() - t
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(f"{elapsed:.2f} s, peak RSS {peak:.0f} MiB, {len(mesh.faces)} triangles, "
      f"{len(mesh.warnings)} warnings")
"""

WARM = "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 1 1 0\nv 0 2 0\nf 1 2 3 4 5\nf 1 2 3 5 4\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", metavar="CASE", help=", ".join(CASES))
    parser.add_argument("--timeout", type=float, default=300.0)
    args = parser.parse_args()
    unknown = set(args.cases) - set(CASES)
    if unknown:
        parser.error(f"unknown cases: {', '.join(sorted(unknown))}")
    with tempfile.TemporaryDirectory() as folder:
        warm = Path(folder) / "warm.obj"
        warm.write_text(WARM)
        for name in args.cases or CASES:
            path = Path(folder) / f"{name}.obj"
            path.write_text(CASES[name]())
            size = path.stat().st_size / 1024**2
            start = time.perf_counter()
            try:
                done = subprocess.run([sys.executable, "-c", CHILD, str(path), str(warm)],
                                      capture_output=True, text=True, timeout=args.timeout,
                                      cwd=ROOT)
                result = done.stdout.strip() or done.stderr.strip().splitlines()[-1]
            except subprocess.TimeoutExpired:
                result = f"more than {args.timeout:.0f} s (stopped)"
            print(f"{name:14} {size:6.1f} MiB  {result}  "
                  f"[process {time.perf_counter() - start:.1f} s]", flush=True)
            path.unlink()


if __name__ == "__main__":
    main()
