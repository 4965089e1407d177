"""The command line's argument types and the view flags that ``render`` and ``explain`` share.

``render`` and ``explain`` take the same size, projection and camera flags
(:func:`add_view_arguments`) and turn them into one :class:`rasterkit.View`
(:func:`view_from_args`), so ``rasterkit explain`` always shows the camera that
``rasterkit render`` would use for that model and those flags. ``render``'s arguments become
one :class:`rasterkit.batch.task.Task` (:func:`task_from_args`): nothing below the command
line sees them.

Pure standard library at module level (NumPy loads when a camera is made), so the parser,
``--help`` and argparse's usage errors come without NumPy or Numba.
"""

from __future__ import annotations

import argparse
import math
import re

from rasterkit import limits
from rasterkit.options import MAX_IMAGE_SIZE, MODEL_CAMERAS, PROJECTIONS

__all__ = ["LIGHT_FORMS", "NUMBER_LISTS", "add_limits", "add_view_arguments", "attach_number_lists", "finite", "focus",
           "integers", "light", "non_negative", "point", "positive", "positive_int", "shadow_map_size", "softness", "samples", "size", "size_limit", "task_from_args", "unit_interval", "view_from_args",
           "whole_number"]


def size(text: str) -> tuple[int, int]:
    """``WIDTHxHEIGHT``, each 1 to :data:`MAX_IMAGE_SIZE`."""
    parts = text.lower().split("x")
    try:
        width, height = (int(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must be WIDTHxHEIGHT, e.g. 640x480, got {text!r}")
    if not (1 <= width <= MAX_IMAGE_SIZE and 1 <= height <= MAX_IMAGE_SIZE):
        raise argparse.ArgumentTypeError(
            f"width and height must be 1 to {MAX_IMAGE_SIZE}, got {text!r}")
    return width, height


def finite(text: str) -> float:
    """A finite float."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}")
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return value


def point(text: str) -> tuple[float, float, float]:
    """``X,Y,Z``: three finite floats."""
    parts = text.split(",")
    if len(parts) != 3:
        raise argparse.ArgumentTypeError(f"a point is X,Y,Z, got {text!r}")
    return tuple(finite(p) for p in parts)


def integers(count: int, form: str):
    """An argument type: ``count`` comma-separated whole numbers, written as ``form``."""
    def parse(text: str) -> tuple[int, ...]:
        parts = text.split(",")
        if len(parts) != count:
            raise argparse.ArgumentTypeError(f"expected {count} whole numbers {form}, got {text!r}")
        try:
            return tuple(int(p) for p in parts)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected whole numbers {form}, got {text!r}")
    return parse


def positive_int(text: str) -> int:
    """A whole number >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}")
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def whole_number(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}")
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be 0 or more, got {value}")
    return value


def focus(text: str) -> float | None:
    """A positive focus distance, or ``auto`` (None: the distance to the target)."""
    if text.strip().lower() == "auto":
        return None
    value = finite(text)
    if value <= 0.0:
        raise argparse.ArgumentTypeError(f"the focus distance must be positive (or 'auto'), got {text!r}")
    return value


def samples(text: str) -> int:
    """Samples per pixel, 1 to 256."""
    value = positive_int(text)
    if value > 256:
        raise argparse.ArgumentTypeError(f"at most 256 samples, got {value}")
    return value


def positive(text: str) -> float:
    """A finite float > 0."""
    value = finite(text)
    if value <= 0.0:
        raise argparse.ArgumentTypeError(f"must be positive, got {text!r}")
    return value


def unit_interval(text: str) -> float:
    """A float in [0, 1]."""
    value = finite(text)
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError(f"must lie in [0, 1], got {text!r}")
    return value


def non_negative(text: str) -> float:
    """A finite float >= 0."""
    value = finite(text)
    if value < 0.0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text!r}")
    return value


def shadow_map_size(text: str) -> int:
    """A shadow map's side, 16 to 8192 texels."""
    value = positive_int(text)
    if not 16 <= value <= 8192:
        raise argparse.ArgumentTypeError(f"a shadow map is 16 to 8192 texels a side, got {value}")
    return value


def softness(text: str) -> float:
    """A shadow filter radius, 0 to 8 texels."""
    value = non_negative(text)
    if value > 8.0:
        raise argparse.ArgumentTypeError(f"at most 8 texels, got {text!r}")
    return value


#: What ``--light`` takes after each kind: its numbers, at least and at most.
_LIGHT_NUMBERS = {"directional": (3, 3, "DX,DY,DZ"), "point": (3, 4, "X,Y,Z[,RANGE]"),
                  "spot": (6, 8, "X,Y,Z,DX,DY,DZ[,ANGLE[,BLEND]]"), "ambient": (0, 0, ""), "headlight": (0, 0, "")}
LIGHT_FORMS = ("directional:DX,DY,DZ | point:X,Y,Z[,RANGE] | spot:X,Y,Z,DX,DY,DZ[,ANGLE[,BLEND]] | ambient | "
               "headlight, then [:COLOR[:INTENSITY]]")


def light(text: str):
    """A :class:`rasterkit.Light` from ``KIND:NUMBERS[:COLOR[:INTENSITY]]`` (ambient and
    headlight have no numbers: ``KIND[:COLOR[:INTENSITY]]``; see :data:`LIGHT_FORMS`)."""
    kind, _, rest = text.partition(":")
    if kind not in _LIGHT_NUMBERS:
        raise argparse.ArgumentTypeError(f"a light is {LIGHT_FORMS}; unknown kind {kind!r} in {text!r}")
    low, high, form = _LIGHT_NUMBERS[kind]
    fields = rest.split(":") if rest else []
    numbers = [] if high == 0 else (fields.pop(0).split(",") if fields else [])
    if not low <= len(numbers) <= high or len(fields) > 2:
        raise argparse.ArgumentTypeError(f"a {kind} light is {kind}{':' + form if form else ''}[:COLOR[:INTENSITY]], "
                                         f"got {text!r}")
    values = [finite(n) for n in numbers]
    colour = fields[0] if fields and fields[0] else "white"
    intensity = non_negative(fields[1]) if len(fields) > 1 else 1.0
    from rasterkit.raster.lights import Light  # checks the colour: loads NumPy

    try:
        if kind == "directional":
            return Light.directional(values, colour, intensity)
        if kind == "point":
            return Light.point(values[:3], colour, intensity, range=values[3] if len(values) > 3 else None)
        if kind == "spot":
            return Light.spot(values[:3], values[3:6], *values[6:], color=colour, intensity=intensity)
        return Light(kind, colour, intensity)
    except (TypeError, ValueError) as e:
        raise argparse.ArgumentTypeError(f"{text!r}: {e}")


def size_limit(text: str) -> int:
    """A size in bytes, or with K, M, G, T (:func:`rasterkit.limits.parse_size`)."""
    try:
        return limits.parse_size(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e))


#: The options whose value is a list of numbers, which may start with a minus sign.
NUMBER_LISTS = ("--eye", "--target", "--up", "--point", "--line")

_NEGATIVE_START = re.compile(r"-[0-9.]")


def attach_number_lists(argv: list[str]) -> list[str]:
    """``argv`` with ``--point -1,2,3`` written as ``--point=-1,2,3``.

    argparse takes a value that starts with ``-`` for an option unless it is one plain
    negative number, so it would refuse ``--point -1,2,3`` with "expected one argument".
    """
    out, k = [], 0
    while k < len(argv):
        if argv[k] in NUMBER_LISTS and k + 1 < len(argv) and _NEGATIVE_START.match(argv[k + 1]):
            out.append(f"{argv[k]}={argv[k + 1]}")
            k += 2
        else:
            out.append(argv[k])
            k += 1
    return out


def add_view_arguments(parser: argparse.ArgumentParser) -> None:
    """``--size``, ``--projection`` and the camera flags, read by :func:`view_from_args`."""
    parser.add_argument("--size", type=size, default=(800, 600), metavar="WIDTHxHEIGHT",
                        help="image size in pixels (default 800x600)")
    parser.add_argument("--projection", choices=PROJECTIONS, default="perspective")
    cam = parser.add_argument_group("camera (default: framed automatically around the model)")
    cam.add_argument("--eye", type=point, metavar="X,Y,Z")
    cam.add_argument("--target", type=point, metavar="X,Y,Z")
    cam.add_argument("--up", type=point, metavar="X,Y,Z")
    cam.add_argument("--fov", type=finite, default=45.0, metavar="DEG",
                     help="vertical field of view (default 45)")
    cam.add_argument("--near", type=finite, metavar="N")
    cam.add_argument("--far", type=finite, metavar="F")
    cam.add_argument("--azimuth", type=finite, default=30.0, metavar="DEG",
                     help="about +Y, from +Z towards +X (default 30)")
    cam.add_argument("--elevation", type=finite, default=20.0, metavar="DEG",
                     help="above the horizon (default 20)")
    cam.add_argument("--distance", type=finite, metavar="D", help="eye distance from the target")
    cam.add_argument("--aperture", type=finite, default=0.0, metavar="A",
                     help="lens diameter, world units: depth of field with --samples (default 0, a pinhole)")
    cam.add_argument("--focus", type=focus, default=None, metavar="F",
                     help="distance of the plane in focus, or 'auto' (default): the distance to the target")
    cam.add_argument("--camera", choices=MODEL_CAMERAS, default=None,
                     help="gltf: the model's own camera (a glTF file's first camera node) in place of the framing")
    cam.add_argument("--camera-opencv", metavar="CAM.json",
                     help='an OpenCV camera: {"K": 3x3, "R": 3x3, "t": [3], "width": W, "height": H, '
                          'optional "dist", "near", "far"}; replaces the framing and --size')


def add_limits(parser: argparse.ArgumentParser) -> None:
    """``--max-file-size`` and ``--max-memory``."""
    group = parser.add_argument_group("limits (sizes in bytes, or with K, M, G, T: 512M, 4G)")
    group.add_argument("--max-file-size", type=size_limit, metavar="SIZE",
                       help="refuse model, material and camera files larger than this "
                            "(default 2G, or RASTERKIT_MAX_FILE_SIZE)")
    group.add_argument("--max-memory", type=size_limit, metavar="SIZE",
                       help="refuse work that needs more memory than this "
                            "(default: the machine's memory, or RASTERKIT_MAX_MEMORY)")


def view_from_args(args):
    """The :class:`rasterkit.View` of the view flags of :func:`add_view_arguments` (reads
    ``--camera-opencv``'s file)."""
    from rasterkit.camera.view import FIELDS, View

    return View(**{name: getattr(args, name) for name in FIELDS})


def task_from_args(args):
    """The :class:`rasterkit.batch.task.Task` of the ``render`` command's arguments: its
    :class:`rasterkit.RenderOptions`, its :class:`rasterkit.View` and its other outputs."""
    from rasterkit.batch.task import Task
    from rasterkit.options import FIELDS, RenderOptions

    maps = ("depth", "normals", "ids")  # file names here: the frame's maps follow from them (Task.frame_options)
    values = {name: getattr(args, name) for name in FIELDS if hasattr(args, name) and name not in maps}
    if values.get("background", "white") is None:  # not given: white, or clear under a shadow catcher
        values["background"] = "transparent" if values.get("ground") == "shadow" else "white"
    options = RenderOptions(**values)
    return Task(options, view_from_args(args), turntable=args.turntable, turn_lights=args.turn_lights,
                hidden=args.hidden,
                depth=args.depth, normals=args.normals, ids=args.ids)
