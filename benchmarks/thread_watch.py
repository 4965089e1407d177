"""2 threads vs 1 on the fill scene, run after run, for minutes: to catch slow phases.

On a shared machine the 2-thread speed-up drifts in phases of minutes (one such phase
was a layout problem of the band buffers, see ``rasterkit.raster.kernels.bands.SLOT_GUARD_BYTES``),
and one run of ``python -m benchmarks --targets`` can miss or hit one. This script repeats a
short measurement (the fill scene drawn ``--rounds`` times on 1 and on 2 threads, interleaved,
medians) in a fresh process per run, alternating between checkouts, so that two versions
meet the same phases::

    python -m benchmarks.thread_watch --minutes 10 /path/to/old-checkout .

Each run prints its speed-up; the end prints each checkout's median, lowest and the number
of runs below the rasterization issue's 1.7x.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

TARGET = 1.7

# The child uses only what older checkouts have too (set_threads, benchmarks.fill), so that
# a checkout from before this script can be compared.
_RUN = """
import sys, time
sys.path.insert(0, {root!r})
import rasterkit
from benchmarks import fill, render, settings
if {scene!r} == "fill":
    scene = fill.scene(fill.TARGET_COUNT, 1920, 1080)
    draw = lambda: fill.draw_rasterkit(scene)
else:
    mode, model = {scene!r}.split(":")
    mesh = rasterkit.load_obj(settings.model_path(model))
    camera = render.frame(mesh, 1920, 1080)
    draw = lambda: rasterkit.render(mesh, camera, mode=mode)
def frame(n):
    rasterkit.set_threads(n)
    start = time.perf_counter()
    draw()
    return time.perf_counter() - start
for _ in range(5):
    frame(1), frame(2)
one, two = [], []
for _ in range({rounds}):
    two.append(frame(2))
    one.append(frame(1))
one.sort(), two.sort()
print(one[len(one) // 2], two[len(two) // 2])
"""


def measure(root: Path, rounds: int, scene: str = "fill") -> tuple[float, float]:
    """Median 1-thread and 2-thread frame (seconds) of the checkout at ``root``: the fill
    scene, or ``"MODE:MODEL"`` (a shared model at 1920x1080, ``rasterkit.render`` mode)."""
    code = _RUN.format(root=str(root), rounds=rounds, scene=scene)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    return float(out[0]), float(out[1])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.thread_watch", description=__doc__.split("\n")[0])
    parser.add_argument("roots", nargs="*", type=Path, default=[Path(".")],
                        help="checkouts of rasterkit to compare (default: this one)")
    parser.add_argument("--minutes", type=float, default=5.0)
    parser.add_argument("--rounds", type=int, default=60, help="frames per thread count in one run")
    parser.add_argument("--scene", default="fill",
                        help="'fill' (the fill-rate scene) or MODE:MODEL, e.g. hidden:sportsCar")
    args = parser.parse_args(argv)
    roots = [root.resolve() for root in args.roots]
    for root in roots:
        if not (root / "rasterkit" / "__init__.py").is_file():
            parser.error(f"{root}: not a rasterkit checkout")
    speedups = {root: [] for root in roots}
    end = time.monotonic() + 60 * args.minutes
    while True:  # at least one run per checkout
        for root in roots:
            one, two = measure(root, args.rounds, args.scene)
            speedups[root].append(one / two)
            print(f"{time.strftime('%H:%M:%S')} {root}: 1 thread {one * 1e3:.2f} ms, "
                  f"2 threads {two * 1e3:.2f} ms, {one / two:.2f}x", flush=True)
        if time.monotonic() >= end:
            break
    for root, values in speedups.items():
        below = sum(v < TARGET for v in values)
        print(f"{root}: {len(values)} runs, median {statistics.median(values):.2f}x, "
              f"lowest {min(values):.2f}x, {below} below {TARGET}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
