"""The command line end to end: ``rasterkit render`` in a new process, first run and warm.

Each run is a fresh ``python -m rasterkit render MODEL -o OUT.png --size WxH --mode solid``
subprocess, timed from start to exit. The *first* run has an empty Numba cache (a new
``NUMBA_CACHE_DIR`` in a temporary folder each time), so it includes compiling every kernel
it needs; a *warm* run reuses a cache that an untimed run filled. The peer is
``benchmarks/peer_cli.py``, the equivalent short trimesh + moderngl script; its first runs get
an empty Mesa shader cache (``MESA_SHADER_CACHE_DIR``) each. Python's own bytecode caches are
warm for both sides.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

from .compare import RASTERKIT, compare, start
from .settings import model_path

FAMILY = "cli"
ROOT = Path(__file__).resolve().parents[1]
PEER = "trimesh + moderngl script"


def _run(command: list[str], env: dict) -> None:
    """Run one command to completion; a non-zero exit raises with its last stderr line."""
    done = subprocess.run(command, cwd=ROOT, env={**os.environ, **env}, capture_output=True, text=True)
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines() or [f"exit code {done.returncode}"]
        raise RuntimeError(lines[-1])


class Side:
    """One command; a *first* run gets a new, empty cache folder in ``scratch`` each time.

    Warm runs use the normal caches (Numba's ``__pycache__`` beside the kernels, which the
    in-process benchmarks have filled, and Mesa's default shader cache), as a user's
    second run would.
    """

    def __init__(self, command: list[str], cache_variable: str, first: bool, scratch: Path):
        self.command, self.variable, self.first, self.scratch = command, cache_variable, first, scratch

    def __call__(self) -> None:
        env = {self.variable: tempfile.mkdtemp(dir=self.scratch)} if self.first else {}
        _run(self.command, env)


def _commands(model: Path, out: Path, width: int, height: int) -> dict[str, list[str]]:
    size = f"{width}x{height}"
    return {
        RASTERKIT: [sys.executable, "-m", "rasterkit", "render", str(model), "-o", str(out / "rk.png"),
                    "--size", size, "--mode", "solid"],
        PEER: [sys.executable, str(ROOT / "benchmarks" / "peer_cli.py"), str(model),
               str(out / "peer.png"), str(width), str(height)],
    }


def compile_bytecode() -> None:
    """Write the bytecode caches of rasterkit's modules, as ``pip install`` does: with
    ``PYTHONDONTWRITEBYTECODE`` set (some CI machines and containers set it) an editable
    checkout would otherwise compile every module from source in every process, about
    0.15 s that no installed copy pays."""
    import compileall

    compileall.compile_dir(str(ROOT / "rasterkit"), quiet=1)


def _peer_ready(peers) -> bool:
    for module in ("moderngl", "trimesh"):
        peers.module(module)
    peers.llvmpipe()  # an EGL context can be made
    return True


def run(settings, results, peers) -> None:
    """Warm runs always; first-ever (compiling) runs when ``settings.cold_runs`` > 0."""
    compile_bytecode()
    model = model_path(settings.cli_model)
    if not model.is_file():
        results.skip(FAMILY, settings.cli_model, f"model file {model} not found")
        return
    with_peer = start(results, FAMILY, PEER, lambda: _peer_ready(peers))
    width, height = settings.cli_size
    cache_variables = {RASTERKIT: "NUMBA_CACHE_DIR", PEER: "MESA_SHADER_CACHE_DIR"}
    # Two untimed warm runs: the first process after an edit of a kernel file may still compile.
    phases = [("warm", settings.process_repeat, max(settings.warmup, 2))]
    if settings.cold_runs:
        phases.insert(0, ("first", settings.cold_runs, 0))
    else:
        results.skip(FAMILY, "first (compiling) run", f"not measured in the {settings.name} profile "
                     "(it compiles every kernel: tens of seconds)")
    with tempfile.TemporaryDirectory() as scratch:
        commands = _commands(model, Path(scratch), width, height)
        if not with_peer:
            del commands[PEER]
        for phase, repeat, warmup in phases:
            sides = {side: Side(command, cache_variables[side], phase == "first", Path(scratch))
                     for side, command in commands.items()}
            compare(results, FAMILY, f"cli/{phase}/solid/{settings.cli_model}/{width}x{height}", sides,
                    repeat=repeat, warmup=warmup,
                    sizes={"width": width, "height": height, "MiB": round(model.stat().st_size / 2**20, 2)},
                    note="whole process: start-up, load, render, PNG")
