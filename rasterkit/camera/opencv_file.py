"""An OpenCV camera given as a JSON file or a mapping (``--camera-opencv``, ``View(camera_opencv=...)``).

The file holds ``Camera.from_opencv``'s keywords: ``{"K": 3x3, "R": 3x3, "t": [3], "width": W,
"height": H}`` and optionally ``"dist"``, ``"near"``, ``"far"``. :func:`read_camera_file`
reads and checks it; :func:`opencv_camera` makes the camera for a model, choosing near and far
around the model where neither the file nor the view gives them.
"""

from __future__ import annotations

import os

__all__ = ["check_camera_fields", "opencv_camera", "read_camera_file"]

_CAMERA_KEYS = ("K", "R", "t", "width", "height")
_OPTIONAL_KEYS = ("dist", "near", "far")


def read_camera_file(path: str | os.PathLike) -> dict:
    """The keyword arguments of ``Camera.from_opencv`` from the JSON file at ``path``,
    checked, with ``source``: the path.

    The file is read by :func:`rasterkit.runtime.files.read_file` (a regular file within
    ``--max-file-size``). Raises ``ValueError``, one line starting with the file's name: it
    cannot be read, is not JSON, lacks a key or has an unknown one, or a value is wrong
    (``R must be a finite 3x3 array, got ...``)."""
    import json

    from rasterkit.runtime.files import read_file, readable

    path = os.fspath(path)
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
    """The camera of a camera file (``data``, parsed, from the file ``source``) with
    ``source`` added, after checking each key and value as ``Camera.from_opencv`` takes it.
    Raises ``ValueError`` naming the file and the key."""
    from rasterkit.camera.checks import positive
    from rasterkit.camera.opencv import from_opencv
    from rasterkit.runtime.files import readable

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


def opencv_camera(data: dict, center, radius: float, near: float | None = None, far: float | None = None):
    """The camera of ``data`` (:func:`check_camera_fields`) for a model whose bounding
    sphere is ``center``, ``radius``: near and far from the file, else ``near``/``far``, else
    enclosing the sphere with room to spare."""
    import numpy as np

    from rasterkit.camera import Camera
    from rasterkit.runtime.files import readable

    data = dict(data)
    name = readable(data.pop("source"))
    r, t = np.asarray(data["R"], float), np.asarray(data["t"], float).reshape(-1)
    offset = r @ np.asarray(center) + t  # the model's centre in the camera's space
    scale = float(np.max(np.abs(offset)))
    distance = scale * float(np.linalg.norm(offset / scale)) if scale > 0.0 else 0.0  # no overflow
    chosen = {"near": max(distance - 1.5 * radius, 1e-3 * (distance + radius)), "far": distance + 2.0 * radius}
    automatic = []
    for key, given in (("near", near), ("far", far)):
        if data.get(key) is None:
            data[key] = chosen[key] if given is None else given
            automatic += [key] if given is None else []
    if automatic and not data["near"] < data["far"]:
        raise ValueError(
            f"{name}: near {data['near']:.6g} is not smaller than far {data['far']:.6g} ({' and '.join(automatic)} "
            f"chosen from the camera's distance to the model, {distance:.6g}, and its radius, {radius:.6g}): "
            f"give near and far in the file or with --near and --far")
    try:
        return Camera.from_opencv(**data)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: {e}") from None
