"""The command line's argument types and the view flags that ``render`` and ``explain`` share.

``render`` and ``explain`` take the same size, projection and camera flags
(:func:`add_view_arguments`) and turn them into a camera with the same function
(:func:`framed_camera`), so ``rasterkit explain`` always shows the camera that
``rasterkit render`` would use for that model and those flags.

Pure standard library at module level (NumPy loads when a camera is made), so the parser,
``--help`` and argparse's usage errors come without NumPy or Numba.
"""

from __future__ import annotations

import argparse
import math
import re

from rasterkit import limits
from rasterkit.batch.report import UsageError
from rasterkit.options import MAX_IMAGE_SIZE, PROJECTIONS

__all__ = ["NUMBER_LISTS", "add_limits", "add_view_arguments", "attach_number_lists", "check_camera_fields",
           "finite", "focus", "framed_camera", "integers", "point", "positive_int", "read_camera_file",
           "samples", "size",
           "size_limit", "unit_interval"]


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


def unit_interval(text: str) -> float:
    """A float in [0, 1]."""
    value = finite(text)
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError(f"must lie in [0, 1], got {text!r}")
    return value


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
    """``--size``, ``--projection`` and the camera flags, read by :func:`framed_camera`."""
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


def framed_camera(args, mesh, name: str | None = None):
    """The camera of the view flags in ``args`` for ``mesh``, and the centre it frames.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed by a parser with :func:`add_view_arguments`.
    mesh : rasterkit.Mesh
        The model: its bounding sphere is framed (then the flags move the camera).
    name : str, optional
        The model's file, named in the error about a model with no extent.

    Returns
    -------
    camera : rasterkit.Camera
    center : (3,) float64 ndarray
        The centre of the bounding sphere (a turntable spins about it).

    Raises
    ------
    UsageError
        If the model has no extent.
    ValueError
        If the flags make an invalid camera, or the camera file's (``--camera-opencv``) does
        not frame the model.
    """
    from rasterkit.camera import Camera

    center, radius = mesh.bounding_sphere()
    if radius == 0.0:
        raise UsageError(("" if name is None else f"{name}: ") + "the model has no extent (all vertices coincide)")
    if getattr(args, "camera_opencv", None):
        return _opencv_camera(args.camera_opencv, args, center, radius), center
    width, height = args.size
    camera = Camera.preset(args.projection, center, radius, width=width, height=height,
                           azimuth=args.azimuth, elevation=args.elevation, fov_y=args.fov,
                           distance=args.distance, eye=args.eye, target=args.target, up=args.up,
                           near=args.near, far=args.far, aperture=args.aperture,
                           focus_distance=args.focus)
    return camera, center


_CAMERA_KEYS = ("K", "R", "t", "width", "height")
_OPTIONAL_KEYS = ("dist", "near", "far")


def read_camera_file(path: str) -> dict:
    """The keyword arguments of ``Camera.from_opencv`` from the JSON file of
    ``--camera-opencv``, checked, with ``source``: the path.

    The file is read by :func:`rasterkit.runtime.files.read_file` (a regular file within
    ``--max-file-size``). Raises ``ValueError``, one line starting with the file's name: it
    cannot be read, is not JSON, lacks a key or has an unknown one, or a value is wrong
    (``R must be a finite 3x3 array, got ...``)."""
    import json

    from rasterkit.runtime.files import read_file, readable

    name = readable(path)
    text = read_file(path)
    try:
        data = json.loads(text.decode("utf-8"))
    except UnicodeDecodeError as e:
        raise ValueError(f"{name}: cannot read the camera: not UTF-8 text (byte {e.start})") from None
    except RecursionError:
        raise ValueError(f"{name}: cannot read the camera: its JSON is nested too deeply") from None
    except ValueError as e:  # json.JSONDecodeError, with the line and column
        raise ValueError(f"{name}: cannot read the camera: {e}") from None
    return check_camera_fields(data, path)


def check_camera_fields(data, source: str) -> dict:
    """The camera of a ``--camera-opencv`` file (``data``, parsed, from the file ``source``)
    with ``source`` added, after checking each key and value as ``Camera.from_opencv``
    takes it. Raises ``ValueError`` naming the file and the key."""
    from rasterkit.runtime.files import readable
    from rasterkit.camera.checks import positive
    from rasterkit.camera.opencv import from_opencv

    name = readable(source)
    if not isinstance(data, dict) or any(k not in data for k in _CAMERA_KEYS):
        raise ValueError(f"{name}: the camera must be a JSON object with {', '.join(_CAMERA_KEYS)}")
    extra = set(data) - set(_CAMERA_KEYS) - set(_OPTIONAL_KEYS)
    if extra:
        raise ValueError(f"{name}: unknown camera keys: {', '.join(sorted(map(repr, extra)))}")
    try:
        from_opencv(data["K"], data["R"], data["t"], data["width"], data["height"], near=None, far=None,
                    dist=data.get("dist"))
        for key in ("near", "far"):
            if data.get(key) is not None:
                positive(data[key], key)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: {e}") from None
    return dict(data, source=source)


def _opencv_camera(data: dict, args, center, radius):
    """``--camera-opencv``'s camera; near and far from the file, else ``--near``/``--far``,
    else enclosing the model's bounding sphere with room to spare."""
    import numpy as np

    from rasterkit.runtime.files import readable
    from rasterkit.camera import Camera

    data = dict(data)
    name = readable(data.pop("source"))
    r, t = np.asarray(data["R"], float), np.asarray(data["t"], float).reshape(-1)
    offset = r @ np.asarray(center) + t  # the model's centre in the camera's space
    scale = float(np.max(np.abs(offset)))
    distance = scale * float(np.linalg.norm(offset / scale)) if scale > 0.0 else 0.0  # no overflow
    chosen = {"near": max(distance - 1.5 * radius, 1e-3 * (distance + radius)), "far": distance + 2.0 * radius}
    automatic = []
    for key, flag in (("near", args.near), ("far", args.far)):
        if data.get(key) is None:
            data[key] = chosen[key] if flag is None else flag
            automatic += [key] if flag is None else []
    if automatic and not data["near"] < data["far"]:
        raise ValueError(
            f"{name}: near {data['near']:.6g} is not smaller than far {data['far']:.6g} ({' and '.join(automatic)} "
            f"chosen from the camera's distance to the model, {distance:.6g}, and its radius, {radius:.6g}): "
            f"give near and far in the file or with --near and --far")
    try:
        return Camera.from_opencv(**data)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: {e}") from None
