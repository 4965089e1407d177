"""The command line: argument parsing and messages; no mathematics and no kernels here.

Exit codes: 0 success, 2 bad input or usage (one line on stderr, no traceback, no output file),
1 internal error.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

__all__ = ["main"]

EXAMPLES = """\
examples:
  rasterkit render --demo -o demo.png
  rasterkit render model.obj -o model.png --size 1920x1080
  rasterkit render model.obj -o model.png --mode solid+wire --azimuth 45 --elevation 30
"""


class UsageError(Exception):
    """Bad input or usage: reported as one line, exit code 2."""


def _size(text: str) -> tuple[int, int]:
    parts = text.lower().split("x")
    try:
        width, height = (int(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must be WIDTHxHEIGHT, e.g. 640x480, got {text!r}")
    if not (1 <= width <= 32768 and 1 <= height <= 32768):
        raise argparse.ArgumentTypeError(f"width and height must be 1 to 32768, got {text!r}")
    return width, height


def _finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}")
    if not np.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return value


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse prints usage + message; we want one line, exit 2
        raise UsageError(message)


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="rasterkit", description="Render OBJ models to images, no GPU needed.",
                     epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    render = commands.add_parser("render", help="render a model to an image",
                                 epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    render.add_argument("model", nargs="?", help="OBJ file to render")
    render.add_argument("--demo", action="store_true", help="render the built-in demo model instead")
    render.add_argument("-o", "--output", required=True, help="output image (.png)")
    render.add_argument("--size", type=_size, default=(800, 600), metavar="WIDTHxHEIGHT",
                        help="image size in pixels (default 800x600)")
    render.add_argument("--mode", choices=("wire", "hidden", "solid", "solid+wire"), default="wire")
    render.add_argument("--azimuth", type=_finite, default=30.0, metavar="DEG",
                        help="camera azimuth about +Y, degrees (default 30)")
    render.add_argument("--elevation", type=_finite, default=20.0, metavar="DEG",
                        help="camera elevation, degrees (default 20)")
    render.add_argument("--fov", type=_finite, default=45.0, metavar="DEG",
                        help="vertical field of view, degrees (default 45)")
    render.add_argument("--color", default="lightgray", help="surface colour (name or #rrggbb)")
    render.add_argument("--line-color", default="black", help="line colour (name or #rrggbb)")
    render.add_argument("--background", default="white",
                        help="background colour; 'transparent' writes RGBA")
    render.add_argument("--cull", choices=("back", "front", "none"), default="back")
    render.add_argument("--shading", choices=("flat", "smooth"), default="flat")
    render.add_argument("--aa", action="store_true", help="anti-aliased lines")
    render.add_argument("--threads", type=int, default=None, metavar="N",
                        help="threads for the kernels (default: all cores)")
    return parser


def _load(args):
    from .obj import load_obj
    from .shapes import demo

    if args.demo == (args.model is not None):
        raise UsageError("give either a MODEL.obj or --demo")
    return demo() if args.demo else load_obj(args.model)


def _render(args) -> None:
    from . import _jit
    from .camera import Camera
    from .render import render

    out = Path(args.output)
    if out.suffix.lower() != ".png":
        raise UsageError(f"{out}: the output must be a .png file")
    if not out.parent.is_dir():
        raise UsageError(f"{out}: folder {str(out.parent)!r} does not exist")
    try:
        _jit.set_threads(args.threads)
    except ValueError as e:
        raise UsageError(str(e)) from None
    mesh = _load(args)
    for warning in mesh.warnings:
        print(f"rasterkit: warning: {warning}", file=sys.stderr)
    center, radius = mesh.bounding_sphere()
    width, height = args.size
    camera = Camera.frame(center, radius, azimuth=args.azimuth, elevation=args.elevation,
                          fov_y=args.fov, width=width, height=height)
    fb = render(mesh, camera, mode=args.mode, cull=args.cull, shading=args.shading,
                color=args.color, line_color=args.line_color, background=args.background,
                aa=args.aa)
    fb.save(out)


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    from .obj import ObjError

    try:
        args = _parser().parse_args(argv)
        _render(args)
    except (UsageError, ObjError, ValueError) as e:
        print(f"rasterkit: error: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        name = f"{e.filename}: " if e.filename else ""
        print(f"rasterkit: error: {name}{e.strerror or e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("rasterkit: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # a bug of ours: still one line, but a distinct exit code
        print(f"rasterkit: internal error: {type(e).__name__}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
