"""The command line: argument parsing and messages; no mathematics and no kernels here.

Exit codes: 0 success, 2 bad input or usage (one line on stderr naming the file and line, no
traceback, no output file), 1 internal error.

Startup: at module level this imports only the standard library and :mod:`rasterkit.options`,
so ``--help`` and the usage errors argparse finds come without NumPy or Numba (0.04 s, not
0.5 s). Numba loads once a render or ``info`` starts; then the first kernel that has to be
compiled (no cached copy) prints one notice on stderr (:mod:`rasterkit._notice`).
"""

from __future__ import annotations

import argparse
import importlib.abc
import math
import sys
from dataclasses import dataclass
from pathlib import Path

from .options import CULL, MAX_IMAGE_SIZE, MODES, PROJECTIONS, SHADING

__all__ = ["main"]

IMAGE_SUFFIXES = (".png", ".gif", ".apng")

EXAMPLES = """\
examples:
  rasterkit render --demo -o demo.png
  rasterkit render model.obj -o model.png --size 1920x1080 --mode solid+wire
  rasterkit render model.obj -o model.png --projection isometric --mode hidden
  rasterkit render model.obj -o model.png --eye 3,2,4 --target 0,0,0 --fov 35
  rasterkit render model.obj -o spin.gif --turntable 36 --mode solid
  rasterkit render models/ -o images/ --mode solid      (every .obj in a folder)
  rasterkit info model.obj
"""


class UsageError(Exception):
    """Bad input or usage: reported as one line, exit code 2."""


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


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse prints usage + message; we want one line, exit 2
        raise UsageError(message)


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="rasterkit", description="Render OBJ models to images, no GPU needed.",
                     epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    info = commands.add_parser("info", help="print counts, bounds, groups, materials, warnings")
    info.add_argument("models", nargs="+", metavar="MODEL.obj")
    r = commands.add_parser("render", help="render models to images", epilog=EXAMPLES,
                            formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("models", nargs="*", metavar="MODEL.obj",
                   help="OBJ files or folders of them (several: -o names a folder)")
    r.add_argument("--demo", action="store_true", help="render the built-in demo model")
    r.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="image (.png; .gif/.png/.apng with --turntable), or a folder")
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
    look = r.add_argument_group("appearance")
    look.add_argument("--color", default="lightgray", help="surface colour (name or #rrggbb)")
    look.add_argument("--line-color", default="black", help="line colour (name or #rrggbb)")
    look.add_argument("--background", default="white",
                      help="background colour; 'transparent' writes RGBA")
    look.add_argument("--cull", choices=CULL, default="back")
    look.add_argument("--shading", choices=SHADING, default="flat")
    look.add_argument("--aa", action="store_true", help="anti-aliased lines")
    out = r.add_argument_group("output")
    out.add_argument("--threads", type=_positive_int, metavar="N",
                     help="threads for the kernels (default: all cores)")
    out.add_argument("--turntable", type=_positive_int, metavar="N",
                     help="N frames around the model, as an animated GIF or APNG")
    out.add_argument("--depth", metavar="OUT.npy", help="also save the depth buffer (float32)")
    return parser


@dataclass
class _Job:
    source: Path | None  # None: the demo model
    output: Path


def _inputs(models: list[str]) -> list[Path]:
    paths = []
    for name in models:
        path = Path(name)
        if path.is_dir():
            found = sorted(p for p in path.iterdir() if p.suffix.lower() == ".obj" and p.is_file())
            if not found:
                raise UsageError(f"{path}: no .obj files in this folder")
            paths.extend(found)
        else:
            paths.append(path)
    return paths


def _jobs(args) -> list[_Job]:
    if args.demo and args.models:
        raise UsageError("give MODEL.obj files or --demo, not both")
    if not args.demo and not args.models:
        raise UsageError("give a MODEL.obj (or a folder of them), or --demo")
    out = Path(args.output)
    sources = [None] if args.demo else _inputs(args.models)
    many = len(sources) > 1 or any(Path(m).is_dir() for m in args.models)
    if many:
        if out.suffix.lower() in IMAGE_SUFFIXES:
            raise UsageError(f"{out}: several models render into a folder; give a folder for -o")
        if args.depth:
            raise UsageError("--depth takes one model")
        if out.exists() and not out.is_dir():
            raise UsageError(f"{out}: not a folder")
        suffix = ".gif" if args.turntable else ".png"
        return [_Job(s, out / (s.stem + suffix)) for s in sources]
    _check_image_path(out, animated=bool(args.turntable))
    return [_Job(sources[0], out)]


def _check_image_path(out: Path, animated: bool) -> None:
    allowed = IMAGE_SUFFIXES if animated else (".png",)
    if out.suffix.lower() not in allowed:
        raise UsageError(f"{out}: the output must end in {' or '.join(allowed)}")
    if not out.parent.is_dir():
        raise UsageError(f"{out}: folder {str(out.parent)!r} does not exist")


def _camera(args, center, radius):
    from .camera import Camera

    width, height = args.size
    return Camera.preset(args.projection, center, radius, width=width, height=height,
                         azimuth=args.azimuth, elevation=args.elevation, fov_y=args.fov,
                         distance=args.distance, eye=args.eye, target=args.target, up=args.up,
                         near=args.near, far=args.far)


def _render_job(job: _Job, args) -> None:
    import numpy as np

    from . import _warm
    from .image import atomic_write, save_animation
    from .obj import load_obj
    from .render import render
    from .scene import Scene
    from .shapes import demo
    from .transform import rotate_axis

    _warm.start(dict(mode=args.mode, cull=args.cull, shading=args.shading, background=args.background,
                     aa=args.aa), depth=bool(args.depth), loading=job.source is not None)
    mesh = demo() if job.source is None else load_obj(job.source)
    for warning in mesh.warnings:
        print(f"rasterkit: warning: {warning}", file=sys.stderr)
    center, radius = mesh.bounding_sphere()
    if radius == 0.0:
        raise UsageError(f"{job.source}: the model has no extent (all vertices coincide)")
    camera = _camera(args, center, radius)
    style = dict(mode=args.mode, cull=args.cull, shading=args.shading, color=args.color,
                 line_color=args.line_color, background=args.background, aa=args.aa)
    if args.turntable:
        frames = []
        for k in range(args.turntable):
            spin = rotate_axis(2 * math.pi * k / args.turntable, (0, 1, 0), center)
            frames.append(render(Scene(camera).add(mesh, spin), **style).color)
        save_animation(frames, job.output)
        return
    fb = render(mesh, camera, **style)
    if args.depth:
        with atomic_write(args.depth) as tmp:
            with open(tmp, "wb") as f:
                np.save(f, fb.depth)
    fb.save(job.output)


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
    if args.depth and Path(args.depth).suffix.lower() != ".npy":
        raise UsageError(f"{args.depth}: the depth output must end in .npy")
    jobs = _jobs(args)
    _without_scipy()
    from . import _jit  # the first import of Numba: the usage errors above come without it
    from ._notice import compile_notice

    try:
        _jit.set_threads(args.threads)
    except ValueError as e:
        raise UsageError(str(e)) from None
    with compile_notice():
        return _render_jobs(jobs, args)


def _render_jobs(jobs: list[_Job], args) -> int:
    if len(jobs) == 1:
        _render_job(jobs[0], args)
        return 0
    jobs[0].output.parent.mkdir(parents=True, exist_ok=True)
    failed = 0
    for k, job in enumerate(jobs, 1):
        _progress(k, len(jobs), job.source.name)
        try:
            _render_job(job, args)
        except _BAD_INPUT as e:
            failed += 1
            _report(e)
    _progress_done()
    return 2 if failed else 0


def _progress(k: int, n: int, name: str) -> None:
    width = 24
    bar = "#" * (width * k // n) + "-" * (width - width * k // n)
    end = "\r" if sys.stderr.isatty() else "\n"
    print(f"[{bar}] {k}/{n} {name}".ljust(72), end=end, file=sys.stderr, flush=True)


def _progress_done() -> None:
    if sys.stderr.isatty():
        print(file=sys.stderr)


def _info(args) -> int:
    from ._notice import compile_notice

    with compile_notice():
        return _info_models(args.models)


def _info_models(models: list[str]) -> int:
    from .obj import load_obj

    failed = 0
    for name in models:
        try:
            mesh = load_obj(name)
        except _BAD_INPUT as e:
            failed += 1
            _report(e)
            continue
        print(_describe(name, mesh))
    return 2 if failed else 0


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


def _report(e: BaseException) -> None:
    if isinstance(e, OSError):
        name = f"{e.filename}: " if e.filename else ""
        print(f"rasterkit: error: {name}{e.strerror or e}", file=sys.stderr)
    else:
        print(f"rasterkit: error: {e}", file=sys.stderr)


_BAD_INPUT: tuple = (UsageError, ValueError, OSError)  # ObjError is a ValueError


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    try:
        args = _parser().parse_args(argv)
        return _render(args) if args.command == "render" else _info(args)
    except _BAD_INPUT as e:
        _report(e)
        return 2
    except KeyboardInterrupt:
        print("rasterkit: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # a bug of ours: still one line, but a distinct exit code
        print(f"rasterkit: internal error: {type(e).__name__}: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
