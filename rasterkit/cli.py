"""The command line: argument parsing, signals and exit codes; no mathematics and no kernels here.

Exit codes (also in ``rasterkit --help``): 0 success; 2 bad input or usage (one line on
stderr naming the file, and the line where there is one; no traceback, no output file); 1 an
internal error (a bug of rasterkit, one line too); 130 interrupted by Ctrl-C (SIGINT); 143
stopped by SIGTERM; 141 stdout closed by its reader (``rasterkit info ... | head``). Interrupted or stopped, rasterkit removes its temporary file and leaves
the output as it was. A folder of models renders every model it can and reports each failure
in one line (:mod:`rasterkit._batch`); every message is one line (:mod:`rasterkit._report`).

Startup: at module level this imports only the standard library and rasterkit's pure-Python
modules (:mod:`rasterkit.options`, :mod:`rasterkit.limits`), so ``--help`` and the usage
errors argparse finds come without NumPy or Numba (0.04 s, not 0.5 s). Numba loads once a
render or ``info`` starts; then the first kernel that has to be compiled (no cached copy)
prints one notice on stderr (:mod:`rasterkit._notice`).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.abc
import math
import os
import signal
import sys
import threading
from typing import Iterator

from . import _report, limits
from ._report import UsageError
from .options import CULL, EDGES, HIDDEN, MAX_IMAGE_SIZE, MODES, PROJECTIONS, SHADING

__all__ = ["main", "Terminated"]

EXAMPLES = """\
examples:
  rasterkit render --demo -o demo.png
  rasterkit render model.obj -o model.png --size 1920x1080 --mode solid+wire
  rasterkit render model.obj -o model.png --projection isometric --mode hidden
  rasterkit render model.obj -o model.png --eye 3,2,4 --target 0,0,0 --fov 35
  rasterkit render model.obj -o model.png --mode solid --samples 16 --aperture 0.2 --focus auto
  rasterkit render model.obj -o spin.gif --turntable 36 --mode solid
  rasterkit render model.obj -o drawing.svg --mode hidden --edges feature --hidden dashed
  rasterkit render models/ -o images/ --mode solid      (every .obj in a folder)
  rasterkit info model.obj

exit codes:
  0    success
  2    bad input or usage: one line "rasterkit: error: ..." naming the file; no output file.
       Several models (a folder): each failure is one line, every other model still
       renders, a last line counts them, and the exit code is 2 if any model failed
  1    internal error (a bug of rasterkit): one line "rasterkit: internal error: ...";
       with several models, 1 if any failure was one
  130  interrupted (Ctrl-C), 143 stopped (SIGTERM): no temporary file is left
  141  the reader of stdout went away (rasterkit info ... | head): no message
"""


class Terminated(BaseException):
    """SIGTERM arrived: the command line stops as for Ctrl-C (temporary files are removed
    on the way out) and exits with 143. A BaseException, like KeyboardInterrupt, so that no
    ``except Exception`` swallows it."""

def _size(text: str) -> tuple[int, int]:
    parts = text.lower().split("x")
    try:
        width, height = (int(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must be WIDTHxHEIGHT, e.g. 640x480, got {text!r}")
    if not (1 <= width <= MAX_IMAGE_SIZE and 1 <= height <= MAX_IMAGE_SIZE):
        raise argparse.ArgumentTypeError(
            f"width and height must be 1 to {MAX_IMAGE_SIZE}, got {text!r}")
    return width, height


def _finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}")
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return value


def _point(text: str) -> tuple[float, float, float]:
    parts = text.split(",")
    if len(parts) != 3:
        raise argparse.ArgumentTypeError(f"a point is X,Y,Z, got {text!r}")
    return tuple(_finite(p) for p in parts)


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}")
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def _focus(text: str) -> float | None:
    if text.strip().lower() == "auto":
        return None
    value = _finite(text)
    if value <= 0.0:
        raise argparse.ArgumentTypeError(f"the focus distance must be positive (or 'auto'), got {text!r}")
    return value


def _samples(text: str) -> int:
    value = _positive_int(text)
    if value > 256:
        raise argparse.ArgumentTypeError(f"at most 256 samples, got {value}")
    return value


def _unit_interval(text: str) -> float:
    value = _finite(text)
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError(f"must lie in [0, 1], got {text!r}")
    return value


def _size_limit(text: str) -> int:
    try:
        return limits.parse_size(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e))


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse prints usage + message; we want one line, exit 2
        raise UsageError(message)


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="rasterkit", description="Render OBJ models to images, no GPU needed.",
                     epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    info = commands.add_parser("info", help="print counts, bounds, groups, materials, warnings")
    info.add_argument("models", nargs="+", metavar="MODEL.obj")
    _add_limits(info)
    r = commands.add_parser("render", help="render models to images", epilog=EXAMPLES,
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("models", nargs="*", metavar="MODEL.obj",
                   help="OBJ files or folders of them (several: -o names a folder)")
    r.add_argument("--demo", action="store_true", help="render the built-in demo model")
    r.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="image (.png; .gif/.png/.apng with --turntable), vector drawing (.svg: "
                        "--mode wire or hidden), or a folder")
    r.add_argument("--size", type=_size, default=(800, 600), metavar="WIDTHxHEIGHT",
                   help="image size in pixels (default 800x600)")
    r.add_argument("--mode", choices=MODES, default="wire", help="default wire")
    r.add_argument("--projection", choices=PROJECTIONS, default="perspective")
    cam = r.add_argument_group("camera (default: framed automatically around the model)")
    cam.add_argument("--eye", type=_point, metavar="X,Y,Z")
    cam.add_argument("--target", type=_point, metavar="X,Y,Z")
    cam.add_argument("--up", type=_point, metavar="X,Y,Z")
    cam.add_argument("--fov", type=_finite, default=45.0, metavar="DEG",
                     help="vertical field of view (default 45)")
    cam.add_argument("--near", type=_finite, metavar="N")
    cam.add_argument("--far", type=_finite, metavar="F")
    cam.add_argument("--azimuth", type=_finite, default=30.0, metavar="DEG",
                     help="about +Y, from +Z towards +X (default 30)")
    cam.add_argument("--elevation", type=_finite, default=20.0, metavar="DEG",
                     help="above the horizon (default 20)")
    cam.add_argument("--distance", type=_finite, metavar="D", help="eye distance from the target")
    cam.add_argument("--aperture", type=_finite, default=0.0, metavar="A",
                     help="lens diameter, world units: depth of field with --samples (default 0, a pinhole)")
    cam.add_argument("--focus", type=_focus, default=None, metavar="F",
                     help="distance of the plane in focus, or 'auto' (default): the distance to the target")
    look = r.add_argument_group("appearance")
    look.add_argument("--color", default="lightgray", help="surface colour (name or #rrggbb)")
    look.add_argument("--line-color", default="black", help="line colour (name or #rrggbb)")
    look.add_argument("--background", default="white",
                      help="background colour; 'transparent' writes RGBA")
    look.add_argument("--edges", choices=EDGES, default="all",
                      help="the polygons' edges (default), or feature edges: silhouettes, "
                           "boundaries, creases, material boundaries")
    look.add_argument("--crease-angle", type=_finite, default=30.0, metavar="DEG",
                      help="angle between face normals from which an edge is a crease (default 30)")
    look.add_argument("--hidden", choices=tuple(h for h in HIDDEN if h is not None), default=None,
                      help="SVG only: draw the hidden parts of the lines dashed, in a layer of their own")
    look.add_argument("--cull", choices=CULL, default="back")
    look.add_argument("--shading", choices=SHADING, default="flat")
    look.add_argument("--aa", action="store_true", help="anti-aliased (Wu) lines")
    look.add_argument("--samples", type=_samples, default=1, metavar="N",
                      help="jittered samples per pixel, averaged: anti-aliasing, and depth of field "
                           "with --aperture (1 to 256, default 1)")
    look.add_argument("--vignette", type=_unit_interval, default=0.0, metavar="V",
                      help="natural cos^4 falloff towards the corners, 0 (none, default) to 1 (full)")
    out = r.add_argument_group("output")
    out.add_argument("--threads", type=_positive_int, metavar="N",
                     help="threads for the kernels (default: all cores)")
    out.add_argument("--turntable", type=_positive_int, metavar="N",
                     help="N frames around the model, as an animated GIF or APNG")
    out.add_argument("--depth", metavar="OUT.npy", help="also save the depth buffer (float32)")
    _add_limits(r)
    return parser


def _add_limits(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("limits (sizes in bytes, or with K, M, G, T: 512M, 4G)")
    group.add_argument("--max-file-size", type=_size_limit, metavar="SIZE",
                       help="refuse model and material files larger than this "
                            "(default 2G, or RASTERKIT_MAX_FILE_SIZE)")
    group.add_argument("--max-memory", type=_size_limit, metavar="SIZE",
                       help="refuse work that needs more memory than this "
                            "(default: the machine's memory, or RASTERKIT_MAX_MEMORY)")


class _NoScipy(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name == "scipy" or name.startswith("scipy."):
            raise ModuleNotFoundError("scipy is not used by the rasterkit command", name=name)
        return None


def _without_scipy() -> None:
    """Keep SciPy out of this process. When SciPy is installed, Numba imports it as it
    loads its registries (to offer BLAS: ``numba.np.arraymath``), 0.13 s of every
    command's start-up; no kernel of rasterkit uses BLAS. Only the command line does this:
    its process is its own."""
    if "scipy" not in sys.modules:
        sys.meta_path.insert(0, _NoScipy())


def _render(args) -> int:
    from . import _batch

    if args.depth and not args.depth.lower().endswith(".npy"):
        raise UsageError(f"{args.depth}: the depth output must end in .npy")
    jobs, batch = _batch.jobs(args)
    _without_scipy()
    from . import _jit  # the first import of Numba: the usage errors above come without it
    from ._notice import compile_notice

    try:
        _jit.set_threads(args.threads)
    except ValueError as e:
        raise UsageError(str(e)) from None
    with compile_notice():
        return _batch.render_jobs(jobs, batch, args)


def _info(args) -> int:
    from ._notice import compile_notice

    with compile_notice():
        return _info_models(args.models)


def _info_models(models: list[str]) -> int:
    from .obj import load_obj

    codes = []
    for name in models:
        with _report.model(name):
            try:
                mesh = load_obj(name)
            except Exception as e:
                code, line = _report.error_line(e)
                print(line, file=sys.stderr)
                codes.append(code)
                continue
        print(_describe(name, mesh), flush=True)  # a closed stdout stops all (main)
        codes.append(0)
    return 1 if 1 in codes else max(codes)


def _describe(name: str, mesh) -> str:
    lo, hi = mesh.bounds
    fmt = ", ".join
    lines = [
        f"{name}",
        f"  vertices  {len(mesh.vertices)}",
        f"  triangles {len(mesh.faces)}",
        f"  edges     {len(mesh.edges)}",
        f"  lines     {len(mesh.lines)}",
        f"  bounds    ({fmt(f'{v:.6g}' for v in lo)}) .. ({fmt(f'{v:.6g}' for v in hi)})",
        f"  attributes {fmt(a for a in ('vertex_colors', 'normals', 'texcoords', 'face_colors') if getattr(mesh, a) is not None) or 'none'}",
        f"  groups    {len(mesh.group_names)}: {fmt(mesh.group_names[:8])}{' ...' if len(mesh.group_names) > 8 else ''}",
        f"  materials {len(mesh.material_names)}: {fmt(mesh.material_names[:8])}{' ...' if len(mesh.material_names) > 8 else ''}",
        f"  warnings  {len(mesh.warnings)}",
    ]
    lines += [f"    {w}" for w in mesh.warnings]
    return "\n".join(lines)


@contextlib.contextmanager
def _limits(args) -> Iterator[None]:
    """Apply ``--max-file-size`` and ``--max-memory`` within the block (before anything is
    loaded), then restore what was set before: a program calling :func:`main` keeps its own."""
    saved = limits._max_file_size, limits._memory_limit
    try:
        if args.max_file_size is not None:
            limits.set_max_file_size(args.max_file_size)
        if args.max_memory is not None:
            limits.set_memory_limit(args.max_memory)
        yield
    finally:
        limits._max_file_size, limits._memory_limit = saved


@contextlib.contextmanager
def _stop_signals() -> Iterator[None]:
    """Within the block, SIGINT raises KeyboardInterrupt and SIGTERM :class:`Terminated`, once:
    a second signal is ignored while the first one's clean-up runs (a temporary file is
    removed on the way out). A signal that was ignored (``nohup``, a background job) or
    has a handler of the program's own is left alone, and so is any thread but the main one."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    ours = {signal.SIGINT: signal.default_int_handler, signal.SIGTERM: signal.SIG_DFL}
    saved = {s: signal.getsignal(s) for s in ours}
    caught = [s for s in ours if saved[s] is ours[s]]

    def stop(signum, frame):
        for s in caught:
            signal.signal(s, signal.SIG_IGN)
        raise KeyboardInterrupt if signum == signal.SIGINT else Terminated()

    try:
        for s in caught:
            signal.signal(s, stop)
        yield
    finally:
        for s in caught:
            signal.signal(s, saved[s])


def _stop_helper() -> None:
    """Stop the compiling helper of a first run (:mod:`rasterkit._warm`), if there is one."""
    warm = sys.modules.get(__package__ + "._warm")
    if warm is not None:
        warm.stop()


def _quiet_stdout() -> None:
    """Point stdout at /dev/null, so that Python's last flush of it finds no closed pipe."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):  # stdout is not a file (a test's capture)
        pass


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code (see the module's documentation)."""
    with _stop_signals(), _report.one_line_warnings():
        try:
            args = _parser().parse_args(argv)
            with _limits(args):
                return _render(args) if args.command == "render" else _info(args)
        except (KeyboardInterrupt, Terminated) as e:
            _stop_helper()
            interrupted = isinstance(e, KeyboardInterrupt)
            print(f"rasterkit: {'interrupted' if interrupted else 'terminated'}", file=sys.stderr)
            return 130 if interrupted else 143
        except Exception as e:  # bad input (2), or a bug of ours (1): one line either way
            if isinstance(e, BrokenPipeError) and e.filename is None:  # stdout: info | head
                _quiet_stdout()  # whoever read it has gone: stop without a word
                return 141
            code, line = _report.error_line(e)
            print(line, file=sys.stderr)
            return code


if __name__ == "__main__":
    sys.exit(main())
