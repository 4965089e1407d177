"""Peak memory of each workload family, rasterkit against its peer, one process per side.

Method: each measurement runs in a new Python process (``python -m benchmarks.memory
SPEC``). The process builds the workload, runs it once (so kernels are compiled or loaded
from the cache and the GL driver is initialised), collects garbage and reads its resident
set size ``VmRSS``; it then resets the kernel's peak-RSS counter (``echo 5 >
/proc/self/clear_refs``, Linux >= 4.0), runs the workload once more and reads the peak
``VmHWM``. The reported figure is ``VmHWM - VmRSS``: the memory the workload itself touches
at its peak, whoever allocates it (NumPy, Numba's runtime, llvmpipe), which tracemalloc
cannot see. Where the counter cannot be reset, the whole process's ``ru_maxrss`` is reported
instead (with the baseline), and the record's note says so.
"""

from __future__ import annotations

import gc
import json
import resource
import subprocess
import sys
from pathlib import Path

from .compare import start
from .report import Record
from .settings import TARGET_SIZE, model_path

FAMILY = "memory"
ROOT = Path(__file__).resolve().parents[1]
PEERS = {"render": "llvmpipe", "fill": "llvmpipe", "lines2d": "cv2.polylines", "loading": "trimesh"}
PEER_MODULES = {"llvmpipe": "moderngl", "cv2.polylines": "cv2", "trimesh": "trimesh"}


# ---------------------------------------------------------------------------- in the child


def _workload(family: str, side: str, args: dict):
    """The callable that does one unit of ``family``'s work on ``side``."""
    import rasterkit

    from . import fill, lines2d, render
    from .peers import Llvmpipe, Peers

    if family == "loading":
        path = model_path(args["model"])
        if side == "rasterkit":
            return lambda: rasterkit.load_obj(path)
        trimesh = Peers().module("trimesh")
        return lambda: trimesh.load(path, force="mesh", process=False)
    if family == "lines2d":
        segs = lines2d.segments(args["segments"], args["width"], args["height"])
        if side == "rasterkit":
            return lines2d.rasterkit_side(segs, args["width"], args["height"])
        return lines2d.cv2_polylines(Peers(), segs, args["width"], args["height"])
    if family == "fill":
        scene = fill.scene(args["count"], args["width"], args["height"])
        mesh, camera, mode, cull = scene.mesh, scene.camera, "solid", "none"
    else:
        mesh = rasterkit.load_obj(model_path(args["model"]))
        camera, mode, cull = render.frame(mesh, args["width"], args["height"]), args["mode"], "back"
    if side == "rasterkit":
        return lambda: rasterkit.render(mesh, camera, mode=mode, cull=cull).color
    gl = Llvmpipe()
    glmesh = gl.upload(mesh, camera, cull=cull)
    return lambda: gl.draw(glmesh, mode)


def status(field: str) -> int:
    """A ``kB`` field of /proc/self/status, in bytes."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1]) * 1024
    raise KeyError(field)


def _reset_peak() -> bool:
    try:
        Path("/proc/self/clear_refs").write_text("5")
        return True
    except OSError:
        return False


def measure(fn) -> dict:
    """Peak extra resident memory of one call of ``fn`` (see the module docstring)."""
    fn()
    gc.collect()
    baseline = status("VmRSS")
    if _reset_peak():
        fn()
        return {"baseline": baseline, "peak": status("VmHWM"), "method": "VmHWM after clear_refs"}
    fn()
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    return {"baseline": baseline, "peak": peak, "method": "ru_maxrss (whole process)"}


def child(spec: str) -> None:
    """Entry point of a measuring process: prints one JSON line."""
    request = json.loads(spec)
    print(json.dumps(measure(_workload(request["family"], request["side"], request["args"]))))


# ---------------------------------------------------------------------------- in the parent


def _measure_in_child(family: str, side: str, args: dict) -> dict:
    spec = json.dumps({"family": family, "side": side, "args": args})
    done = subprocess.run([sys.executable, "-m", "benchmarks.memory", spec], cwd=ROOT,
                          capture_output=True, text=True)
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines() or [f"exit code {done.returncode}"]
        raise RuntimeError(lines[-1])
    return json.loads(done.stdout.strip().splitlines()[-1])


def _workloads(settings) -> list[tuple[str, str, dict]]:
    """(family, name, args) of every workload whose memory is measured."""
    width, height = TARGET_SIZE if TARGET_SIZE in settings.sizes else settings.sizes[-1]
    out = []
    if "render" in settings.memory:
        out += [("render", f"{model}/solid+wire/{width}x{height}",
                 {"model": model, "mode": "solid+wire", "width": width, "height": height})
                for model in settings.models if model_path(model).is_file()]
    fw, fh = settings.fill_size
    if "fill" in settings.memory:
        count = settings.fill_counts[-1]
        out.append(("fill", f"{count}tri/{fw}x{fh}", {"count": count, "width": fw, "height": fh}))
    if "lines2d" in settings.memory:
        sw, sh = settings.segment_size
        out.append(("lines2d", f"{settings.segments}seg/{sw}x{sh}",
                    {"segments": settings.segments, "width": sw, "height": sh}))
    if "loading" in settings.memory and model_path(settings.models[-1]).is_file():
        out.append(("loading", settings.models[-1], {"model": settings.models[-1]}))
    return out


def _mib(n: int) -> str:
    return f"{n / 2**20:.0f} MiB"


def run(settings, results, peers) -> None:
    """One record per measured workload: peak extra bytes of rasterkit and of its peer."""
    available = {peer: start(results, FAMILY, peer, lambda m=module: peers.module(m)) is not None
                 for peer, module in PEER_MODULES.items()}
    for family, name, args in _workloads(settings):
        peer = PEERS[family]
        try:
            rk = _measure_in_child(family, "rasterkit", args)
        except RuntimeError as error:
            results.skip(FAMILY, f"{family}/{name}", f"rasterkit failed: {error}")
            continue
        other = None
        if available[peer]:
            try:
                other = _measure_in_child(family, peer, args)
            except RuntimeError as error:
                results.skip(FAMILY, f"{family}/{name} [{peer}]", f"failed: {error}")
        note = f"{rk['method']}; process peak rasterkit {_mib(rk['peak'])}"
        if other:
            note += f", {peer} {_mib(other['peak'])}"
        results.add(Record(family=FAMILY, name=f"memory/{family}/{name}", peer=peer if other else None,
                           sizes=args, quantity="peak_bytes", rasterkit=rk["peak"] - rk["baseline"],
                           peer_value=other["peak"] - other["baseline"] if other else None, runs=1,
                           note=note))


if __name__ == "__main__":
    child(sys.argv[1])
