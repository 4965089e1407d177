"""The command line: argument parsing, signals and exit codes; no mathematics and no kernels here.

Exit codes (also in ``rasterkit --help``): 0 success; 2 bad input or usage (one line on
stderr naming the file, and the line where there is one; no traceback, no output file); 1 an
internal error (a bug of rasterkit, one line too); 130 interrupted by Ctrl-C (SIGINT); 143
stopped by SIGTERM; 141 stdout closed by its reader (``rasterkit info ... | head``). Interrupted or stopped, rasterkit removes its temporary file and leaves
the output as it was. A folder of models renders every model it can and reports each failure
in one line (:mod:`rasterkit.batch.plan`); every message is one line (:mod:`rasterkit.batch.report`).
``explain`` prints the lecture's camera chain or line algorithms (:mod:`rasterkit.explain`)
for the camera ``render`` would use: both build it with the argument types and view flags
of :mod:`rasterkit.cli.args`.

Startup: at module level this imports only the standard library and rasterkit's pure-Python
modules (:mod:`rasterkit.options`, :mod:`rasterkit.limits`, :mod:`rasterkit.cli.args`), so
``--help`` and the usage errors argparse finds come without NumPy or Numba (0.04 s, not
0.5 s). Numba loads once a render or ``info`` starts (for ``explain``: a model file or
``--line``'s grids); then the first kernel that has to be compiled (no cached copy) prints
one notice on stderr (:mod:`rasterkit.runtime.notice`).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.abc
import os
import signal
import sys
import threading
from typing import Iterator

from rasterkit import limits
from rasterkit.batch import report as _report
from rasterkit.runtime import stop as _stop
from rasterkit.batch.report import UsageError
from rasterkit.cli.args import (add_limits, add_view_arguments, attach_number_lists, integers, point, positive_int,
                                task_from_args, view_from_args, whole_number)
from rasterkit.cli.look import add_look_arguments
from rasterkit.cli.view import add_view_command
from rasterkit.options import MODES

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
  rasterkit render model.obj -o rgb.png --mode solid --camera-opencv cam.json --depth depth.png --ids ids.png
  rasterkit info model.obj
  rasterkit explain model.obj --point 0.5,0.5,0.5 --projection cabinet
  rasterkit explain --line 0,0,7,3

explain: the lecture made visible, as text. 'rasterkit explain [MODEL | --demo]' prints
  the camera that 'render' would use with the same flags, factor by factor as in the
  lecture (T, R, H, S_xy, S_far, P_persp, P_parallel, S_raster, Raster; T_near, S_xyz for
  parallel cameras): what each does, its 4x4 matrix, their product K checked against the
  camera's matrix; --point X,Y,Z carries a world point through every factor to its pixel.
  Without a model it frames the unit cube. 'rasterkit explain --line X0,Y0,X1,Y1' draws
  the segment's pixels by brute force, DDA and Bresenham side by side (at most 64x64) and
  tabulates Bresenham's decision variable d at each step.

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


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse prints usage + message; we want one line, exit 2
        raise UsageError(message)


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="rasterkit", description="Render OBJ models to images, no GPU needed.",
                     epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    info = commands.add_parser("info", help="print counts, bounds, groups, materials, textures, warnings")
    info.add_argument("models", nargs="+", metavar="MODEL.obj")
    add_limits(info)
    r = commands.add_parser("render", help="render models to images", epilog=EXAMPLES,
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("models", nargs="*", metavar="MODEL.obj",
                   help="OBJ files or folders of them (several: -o names a folder)")
    r.add_argument("--demo", action="store_true", help="render the built-in demo model")
    r.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="image (.png; .gif/.png/.apng with --turntable), vector drawing (.svg: "
                        "--mode wire or hidden), or a folder")
    r.add_argument("--mode", choices=MODES, default="wire", help="default wire")
    add_view_arguments(r)
    add_look_arguments(r)
    out = r.add_argument_group("output")
    out.add_argument("--threads", type=positive_int, metavar="N",
                     help="threads for the kernels (default: all cores)")
    out.add_argument("--turntable", type=positive_int, metavar="N",
                     help="N frames around the model, as an animated GIF or APNG")
    out.add_argument("--turn-lights", action="store_true",
                     help="with --turntable: the lights turn with the model (default: they stay, "
                          "and its shadows move over it)")
    out.add_argument("--depth", metavar="OUT.npy|OUT.png",
                     help="also save the depth along the optical axis, world units, 0 where nothing "
                          "was drawn: .npy float32, or .png 16-bit in thousandths (mm for metres)")
    out.add_argument("--normals", metavar="OUT.npy|OUT.png",
                     help="also save the camera-space unit normals: .npy float32 (NaN: empty), "
                          "or .png RGB (n + 1)/2")
    out.add_argument("--ids", metavar="OUT.npy|OUT.png",
                     help="also save the visible face's index: .npy int32 (-1: none), or .png "
                          "16-bit id + 1 (0: none)")
    _add_batch_arguments(r)
    add_limits(r)
    _add_explain(commands)
    add_view_command(commands)
    return parser


def _add_batch_arguments(r) -> None:
    many = r.add_argument_group("batches (several models or folders into the folder -o)")
    many.add_argument("--jobs", type=whole_number, default=1, metavar="N",
                      help="N worker processes sharing the cores (default 1; 0: one per core)")
    many.add_argument("--scheduler", metavar="ADDRESS",
                      help="render on a Dask cluster (tcp://host:port); its workers must reach -o")
    many.add_argument("--resume", action="store_true",
                      help="skip models whose image is complete and newer than the model")
    many.add_argument("--contact-sheet", metavar="SHEET.png", help="also write a grid of all thumbnails")


def _add_explain(commands) -> None:
    e = commands.add_parser(
        "explain", help="print the camera chain factor by factor, or how a line becomes pixels",
        description="Print the camera chain of 'render' factor by factor (with a point carried "
                    "through it), or (--line) the pixels of three line algorithms.",
        epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    e.add_argument("model", nargs="?", metavar="MODEL.obj",
                   help="the model the camera frames (default: the unit cube, shapes.cube())")
    e.add_argument("--demo", action="store_true", help="frame the built-in demo model")
    e.add_argument("--point", type=point, metavar="X,Y,Z",
                   help="carry this world point through every factor to its pixel")
    e.add_argument("--line", type=integers(4, "X0,Y0,X1,Y1"), metavar="X0,Y0,X1,Y1",
                   help="instead: the pixels of this segment by brute force, DDA and Bresenham, "
                        "and Bresenham's decision variable (at most 64x64 pixels)")
    add_view_arguments(e)
    add_limits(e)


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
    from rasterkit.batch import plan as _batch

    for flag in ("depth", "normals", "ids"):
        path = getattr(args, flag)
        if path and not path.rstrip(os.sep).lower().endswith((".npy", ".png")):  # "d.npy/": _batch says
            raise UsageError(f"{path}: the {flag} output must end in .npy or .png")
        if path and args.turntable:
            raise UsageError(f"--{flag} takes a still image, not --turntable")
    maps = {flag: getattr(args, flag) for flag in ("depth", "normals", "ids")}
    request = _batch.Request(args.models, args.demo, args.output, animated=bool(args.turntable), maps=maps,
                             contact_sheet=args.contact_sheet, scheduler=args.scheduler, workers=args.jobs,
                             resume=args.resume)
    jobs, batch, scheduler = _batch.jobs(request)  # before NumPy loads: the usage errors come at once
    task = task_from_args(args)  # (reads --camera-opencv's file)
    _without_scipy()
    from rasterkit.runtime import threads as _threads  # the first import of Numba: the usage errors above come without it
    from rasterkit.runtime.notice import compile_notice

    try:
        _threads.set_threads(args.threads)
    except ValueError as e:
        raise UsageError(str(e)) from None
    with compile_notice():
        return _batch.render_jobs(jobs, batch, task, request, scheduler)


def _info_command(args) -> int:
    from rasterkit.cli import info

    return info.run(args)


def _explain(args) -> int:
    from rasterkit import explain

    if args.line is not None:
        if args.model or args.demo or args.point:
            raise UsageError("--line takes no MODEL, --demo or --point")
        explain.check_segment(*args.line)  # before Numba loads
        _without_scipy()
        from rasterkit.runtime.notice import compile_notice

        with compile_notice():
            text = explain.format_line(*args.line)
    else:
        if args.model and args.demo:
            raise UsageError("give a MODEL.obj or --demo, not both")
        camera, _ = view_from_args(args).frame(_explained_mesh(args), name=args.model)
        text = explain.format_chain(explain.chain_steps(camera, args.point), camera)
    print(text, flush=True)
    return 0


def _explained_mesh(args):
    """The model of ``explain``: MODEL.obj, the demo model, or the unit cube."""
    from rasterkit import shapes

    if args.model is None:
        return shapes.demo() if args.demo else shapes.cube()
    _without_scipy()
    from rasterkit.runtime.notice import compile_notice
    from rasterkit.formats import as_drawn, load

    with _report.model(args.model), compile_notice():
        mesh, cloud = as_drawn(load(args.model, textures=False))  # the camera needs the geometry only
    if mesh is None:
        mesh = cloud.as_mesh()
    for warning in mesh.warnings:
        print(f"rasterkit: warning: {args.model}: {_report.one_line(warning)}", file=sys.stderr)
    return mesh


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
    removed on the way out). The stop is also recorded (:mod:`rasterkit.runtime.stop`): a render
    whose exception a C extension lost stops at its next parallel pass. A signal that was
    ignored (``nohup``, a background job) or has a handler of the program's own is left
    alone, and so is any thread but the main one."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    ours = {signal.SIGINT: signal.default_int_handler, signal.SIGTERM: signal.SIG_DFL}
    saved = {s: signal.getsignal(s) for s in ours}
    caught = [s for s in ours if saved[s] is ours[s]]

    def stop(signum, frame):
        for s in caught:
            signal.signal(s, signal.SIG_IGN)
        exception = KeyboardInterrupt if signum == signal.SIGINT else Terminated
        _stop.request(exception)  # raised again if this one is lost on its way (rasterkit.runtime.stop)
        raise exception()

    try:
        for s in caught:
            signal.signal(s, stop)
        yield
    finally:
        for s in caught:
            signal.signal(s, saved[s])
        _stop.clear()


def _stopped(interrupted: bool) -> int:
    """Ctrl-C (``interrupted``) or SIGTERM stopped the command: its line and exit code."""
    _stop.clear()
    _stop_helper()
    print(f"rasterkit: {'interrupted' if interrupted else 'terminated'}", file=sys.stderr)
    return 130 if interrupted else 143


def _stop_helper() -> None:
    """Stop the compiling helper of a first run (:mod:`rasterkit.runtime.warm`), if there is one."""
    warm = sys.modules.get("rasterkit.runtime.warm")
    if warm is not None:
        warm.stop()


def _finish_helper() -> None:
    """Wait for the demo's compiling helper (:func:`rasterkit.runtime.warm.finish`), if there is one."""
    warm = sys.modules.get("rasterkit.runtime.warm")
    if warm is not None:
        warm.finish()


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
            argv = list(sys.argv[1:] if argv is None else argv)
            args = _parser().parse_args(attach_number_lists(argv))
            with _limits(args):
                if args.command == "view":
                    from rasterkit.cli import view

                    return view.run(args, argv)
                code = {"render": _render, "info": _info_command, "explain": _explain}[args.command](args)
            _finish_helper()
            return code
        except (KeyboardInterrupt, Terminated) as e:
            return _stopped(isinstance(e, KeyboardInterrupt))
        except Exception as e:  # bad input (2), or a bug of ours (1): one line either way
            _stop_helper()
            if _stop.pending() is not None:  # the signal's exception, turned into another on its way
                return _stopped(_stop.pending() is KeyboardInterrupt)
            if isinstance(e, BrokenPipeError) and e.filename is None:  # stdout: info | head
                _quiet_stdout()  # whoever read it has gone: stop without a word
                return 141
            code, line = _report.error_line(e)
            print(line, file=sys.stderr)
            return code


if __name__ == "__main__":
    sys.exit(main())
