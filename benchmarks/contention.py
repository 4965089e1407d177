"""Several renderer processes at once: how each one's frame rate holds up on shared cores.

For each process count N (1, 2, 4), N processes start together and each renders solid frames
of the model (stanford-bunny, 1920x1080) in a loop for a fixed wall time. Then the same with
N llvmpipe processes (moderngl's headless EGL context, :class:`benchmarks.peers.Llvmpipe`,
the frame of the ``render`` family: clear, flat Lambert, read back). rasterkit's processes
never run at the same time as llvmpipe's.

Each child (``python -m benchmarks.contention child SPEC``) loads the model and renders two
frames untimed (kernels loaded from the cache, shaders compiled), says it is ready, then waits
for the start file: the parent writes it once every child is ready, holding a start time a
moment ahead, and every child sleeps until that time, so all of them start together. A child
then renders frames until the wall time has passed (the frame that crosses the line is the
last one counted) and prints its frame count, its elapsed time and every frame's time. The
rasterkit child uses only the public API: ``rasterkit.load_obj``, ``rasterkit.Camera.frame``
around ``Mesh.bounding_sphere()``, ``rasterkit.render(mesh, camera, mode="solid")``. Both
sides keep their default thread counts (Numba: all cores; llvmpipe: ``LP_NUM_THREADS`` or all
cores), as two users' programs would.

Per configuration: one record per process (seconds = wall seconds per frame of that process,
so the throughput column is its frames per second; the note holds its fps relative to one
process alone, and the median, 90th percentile and longest frame), and a ``total`` record
(seconds = 1 / the sum of the processes' fps).
"""

from __future__ import annotations

import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .compare import start
from .report import Record
from .settings import model_path

FAMILY = "contention"
ROOT = Path(__file__).resolve().parents[1]
SIDES = ("rasterkit", "llvmpipe")
WARMUP_FRAMES = 2
START_MARGIN = 0.2
"""Seconds between the parent writing the start file and the common start time."""
FINISH_TIMEOUT = 600
"""Seconds a child may take past its wall time to print its frames."""


# ---------------------------------------------------------------------------- in the child


def _draw(side: str, model: str, width: int, height: int):
    """The callable that renders one solid frame on ``side``, and the triangle count."""
    import rasterkit

    mesh = rasterkit.load_obj(model)
    center, radius = mesh.bounding_sphere()
    camera = rasterkit.Camera.frame(center, radius, width=width, height=height)
    if side == "rasterkit":
        return (lambda: rasterkit.render(mesh, camera, mode="solid")), len(mesh.faces)
    from .peers import Llvmpipe

    gl = Llvmpipe()
    glmesh = gl.upload(mesh, camera)
    return (lambda: gl.draw(glmesh, "solid")), len(mesh.faces)


def _wait_for_start(start_file: Path) -> float:
    """Poll for the start file, then sleep until the start time it holds; returns that time."""
    while not start_file.exists():
        time.sleep(0.001)
    start_at = float(start_file.read_text())
    while (left := start_at - time.time()) > 0:
        time.sleep(min(left, 0.01))
    return start_at


def child(spec: str) -> None:
    """A contending process: prints a ready line, then one JSON line with its frames."""
    request = json.loads(spec)
    draw, triangles = _draw(request["side"], request["model"], request["width"], request["height"])
    for _ in range(WARMUP_FRAMES):
        draw()
    print("ready", flush=True)
    start_at = _wait_for_start(Path(request["start_file"]))
    late = time.time() - start_at
    times = []
    begin = time.perf_counter()
    while True:
        a = time.perf_counter()
        draw()
        b = time.perf_counter()
        times.append(b - a)
        if b - begin >= request["seconds"]:
            break
    print(json.dumps({"frames": len(times), "elapsed": b - begin, "times": times, "late": late,
                      "triangles": triangles}), flush=True)


# ---------------------------------------------------------------------------- in the parent


def _percentile(values: list[float], q: float) -> float:
    """Nearest-rank percentile (defined for a single value too)."""
    ordered = sorted(values)
    return ordered[max(math.ceil(q / 100 * len(ordered)) - 1, 0)]


def _stats(result: dict) -> dict:
    times = result["times"]
    return {"frames": result["frames"], "elapsed": result["elapsed"],
            "fps": result["frames"] / result["elapsed"],
            "median": statistics.median(times), "p90": _percentile(times, 90), "max": max(times),
            "late": result["late"], "triangles": result["triangles"]}


def contend(side: str, count: int, model: Path, width: int, height: int, seconds: float) -> list[dict]:
    """Run ``count`` processes of ``side`` together; the statistics of each (see :func:`_stats`).

    Raises RuntimeError (with the failing child's last stderr line) if any child fails.
    """
    with tempfile.TemporaryDirectory(prefix="rasterkit-contention-") as scratch:
        start_file = Path(scratch) / "start"
        spec = json.dumps({"side": side, "model": str(model), "width": width, "height": height,
                           "seconds": seconds, "start_file": str(start_file)})
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(
            [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}
        errors = [open(Path(scratch) / f"stderr-{k}", "w+") for k in range(count)]
        children = [subprocess.Popen([sys.executable, "-m", "benchmarks.contention", "child", spec], cwd=ROOT,
                                     env=env, stdout=subprocess.PIPE, stderr=errors[k], text=True)
                    for k in range(count)]
        try:
            for k, process in enumerate(children):
                line = process.stdout.readline()  # blocks until ready, or '' if the child died
                if line.strip() != "ready":
                    raise RuntimeError(_failure(process, errors[k]))
            (Path(scratch) / "start.tmp").write_text(repr(time.time() + START_MARGIN))
            os.replace(Path(scratch) / "start.tmp", start_file)  # appears whole, never half-written
            out = []
            for k, process in enumerate(children):
                text, _ = process.communicate(timeout=seconds + FINISH_TIMEOUT)
                if process.returncode != 0 or not text.strip():
                    raise RuntimeError(_failure(process, errors[k]))
                out.append(_stats(json.loads(text.strip().splitlines()[-1])))
            return out
        finally:
            for process in children:
                if process.poll() is None:
                    process.kill()
                    process.wait()
            for f in errors:
                f.close()


def _failure(process, stderr_file) -> str:
    if process.poll() is None:
        process.kill()
    process.wait()
    stderr_file.seek(0)
    lines = stderr_file.read().strip().splitlines() or [f"exit code {process.returncode}"]
    return lines[-1]


def _ms(s: float) -> str:
    return f"{s * 1e3:.0f} ms" if s >= 0.01 else f"{s * 1e3:.2f} ms"


def _describe(side: str, stats: dict, alone: float | None) -> str:
    relative = f", {stats['fps'] / alone:.2f}x alone" if alone else ""
    return (f"{side}: {stats['frames']} frames, {stats['fps']:.2f} fps{relative}, frame median "
            f"{_ms(stats['median'])}, p90 {_ms(stats['p90'])}, max {_ms(stats['max'])}")


def _summary(count: int, side: str, stats: list[dict], alone: float | None) -> str:
    total = sum(s["fps"] for s in stats)
    each = " + ".join(f"{s['fps']:.2f}" for s in stats)
    line = f"  {count} process{'es' if count > 1 else ''}, {side}: {total:.2f} fps"
    if count > 1:
        line += f" total = {each}"
    if alone:
        line += " (" + ", ".join(f"{s['fps'] / alone:.2f}x" for s in stats) + " of one alone)"
    line += ("; frame median " + "/".join(_ms(s["median"]) for s in stats) + ", p90 "
             + "/".join(_ms(s["p90"]) for s in stats) + ", max " + "/".join(_ms(s["max"]) for s in stats))
    return line


def run(settings, results, peers) -> None:
    """Each process count of ``settings.contention_processes``, rasterkit's then llvmpipe's."""
    name, (width, height) = settings.startup_model, settings.startup_size
    model = model_path(name)
    if not model.is_file():
        results.skip(FAMILY, name, f"model file {model} not found")
        return
    seconds = settings.contention_seconds
    sides = ["rasterkit"]
    if start(results, FAMILY, "llvmpipe", peers.llvmpipe) is not None:
        sides.append("llvmpipe")
    base = f"contention/solid/{name}/{width}x{height}"
    alone: dict[str, float] = {}
    for round_, count in enumerate(settings.contention_processes):
        measured: dict[str, list[dict]] = {}
        for side in sides if round_ % 2 == 0 else reversed(sides):  # alternate who goes first
            try:
                measured[side] = contend(side, count, model, width, height, seconds)
            except (RuntimeError, subprocess.TimeoutExpired) as error:
                results.skip(FAMILY, f"{base}/{count}proc [{side}]", f"failed: {error}")
                continue
            if count == 1:
                alone[side] = measured[side][0]["fps"]
        if "rasterkit" in measured:  # records need rasterkit's side; the summary lines do not
            _records(results, base, count, measured, alone, width, height, seconds)
        for side in sides:
            if side in measured:
                print(_summary(count, side, measured[side], alone.get(side)), flush=True)


def _records(results, base, count, measured, alone, width, height, seconds) -> None:
    rk, gl = measured["rasterkit"], measured.get("llvmpipe")
    peer = "llvmpipe" if gl else None
    sizes = {"width": width, "height": height, "triangles": rk[0]["triangles"], "processes": count,
             "seconds": seconds}
    for k in range(count):
        note = _describe("rasterkit", rk[k], alone.get("rasterkit"))
        if gl:
            note += "; " + _describe("llvmpipe", gl[k], alone.get("llvmpipe"))
        results.add(Record(family=FAMILY, name=f"{base}/{count}proc/process{k + 1}", peer=peer,
                           sizes={**sizes, "process": k + 1}, rasterkit=1 / rk[k]["fps"],
                           peer_value=1 / gl[k]["fps"] if gl else None, work=1, unit="frame/s",
                           runs=rk[k]["frames"],
                           note="seconds = wall time per frame of this process; " + note))
    total = {side: sum(s["fps"] for s in stats) for side, stats in measured.items()}
    late = max(s["late"] for stats in measured.values() for s in stats)
    note = (f"seconds = 1 / total fps; total fps rasterkit {total['rasterkit']:.2f}"
            + (f", llvmpipe {total['llvmpipe']:.2f}" if gl else "")
            + f"; latest start {late * 1e3:.1f} ms after the common start time")
    results.add(Record(family=FAMILY, name=f"{base}/{count}proc/total", peer=peer, sizes=sizes,
                       rasterkit=1 / total["rasterkit"], peer_value=1 / total["llvmpipe"] if gl else None,
                       work=1, unit="frame/s", runs=sum(s["frames"] for s in rk), note=note))


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "child":
        child(sys.argv[2])
    else:
        sys.exit("usage: python -m benchmarks.contention child SPEC (started by python -m benchmarks)")
