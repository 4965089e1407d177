""":class:`View`: how the camera is chosen for a model, as the command line's view flags say it."""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping
from dataclasses import dataclass, field

from rasterkit import values
from rasterkit.options import MAX_IMAGE_SIZE, MODEL_CAMERAS, PROJECTIONS

__all__ = ["View"]


@dataclass(frozen=True)
class View:
    """How a camera is chosen for a model: the view flags of ``rasterkit render`` and
    ``rasterkit explain`` as one checked record. :meth:`camera_for` makes the camera; the
    command line, :func:`rasterkit.render_many` and a batch's workers pass the record whole.

    Fields
    ------
    size : (int, int)
        Image width and height in pixels.
    projection : str
        One of :data:`rasterkit.PROJECTIONS` (:meth:`rasterkit.Camera.preset`).
    eye, target, up : (x, y, z) or None
        Where the camera is, what it looks at, which way is up; None: framed automatically
        around the model's bounding sphere.
    fov : float
        Vertical field of view, degrees.
    near, far : float or None
        Clipping planes; None: around the model.
    azimuth, elevation : float
        Degrees about +Y (from +Z towards +X) and above the horizon, of the framed eye.
    distance : float or None
        The eye's distance from the target; None: the model fills the view.
    aperture : float
        Lens diameter in world units: depth of field with ``samples`` (0: a pinhole).
    focus : float or None
        Distance of the plane in focus; None: the distance to the target.
    camera_opencv : path or mapping, optional
        An OpenCV camera (:mod:`rasterkit.camera.opencv_file`: ``K``, ``R``, ``t``,
        ``width``, ``height``, optional ``dist``, ``near``, ``far``), read and checked when
        the View is made; it replaces the framing and ``size``.
    camera : {"gltf"} or None
        ``"gltf"``: the model's own camera, the first camera node of a glTF scene
        (:func:`rasterkit.gltf.camera_of`, ``size`` pixels), in place of the framing.
    """

    size: tuple = (800, 600)
    projection: str = "perspective"
    eye: tuple | None = None
    target: tuple | None = None
    up: tuple | None = None
    fov: float = 45.0
    near: float | None = None
    far: float | None = None
    azimuth: float = 30.0
    elevation: float = 20.0
    distance: float | None = None
    aperture: float = 0.0
    focus: float | None = None
    camera_opencv: dict | None = field(default=None, hash=False)
    camera: str | None = None

    def __post_init__(self):
        checked = {
            "size": values.size("size", self.size, MAX_IMAGE_SIZE),
            "projection": values.choice("projection", self.projection, PROJECTIONS),
            **{name: values.optional(values.point, name, getattr(self, name)) for name in ("eye", "target", "up")},
            **{name: values.real(name, getattr(self, name)) for name in ("fov", "azimuth", "elevation", "aperture")},
            **{name: values.optional(values.real, name, getattr(self, name)) for name in ("near", "far", "distance")},
            "focus": values.optional(values.positive, "focus", self.focus),
            "camera_opencv": None if self.camera_opencv is None else _opencv(self.camera_opencv),
            "camera": values.optional(values.choice, "camera", self.camera, MODEL_CAMERAS),
        }
        for name, value in checked.items():
            object.__setattr__(self, name, value)

    def replace(self, **changes) -> View:
        """A copy with ``changes`` (``TypeError`` naming a field that does not exist)."""
        unknown = set(changes) - FIELDS
        if unknown:
            raise TypeError(f"unknown view option {sorted(unknown)[0]!r} (the options are: {', '.join(sorted(FIELDS))})")
        return dataclasses.replace(self, **changes) if changes else self

    def frame(self, mesh, name: str | None = None):
        """``(camera, center)``: the camera for ``mesh`` and the centre of the bounding sphere
        it frames (a turntable spins about it). ``name``: the model's file, named in errors.

        Raises ``ValueError`` if the model has no extent, the fields make an invalid camera,
        or the OpenCV camera does not frame the model (its near and far, chosen around it)."""
        from rasterkit.camera import Camera

        center, radius = mesh.bounding_sphere()
        if radius == 0.0:
            raise ValueError(("" if name is None else f"{name}: ") + "the model has no extent (all vertices coincide)")
        if self.camera == "gltf":
            if getattr(mesh, "gltf_camera", None) is None:
                raise ValueError(("" if name is None else f"{name}: ") + "camera 'gltf' takes a glTF model with a "
                                 "camera node, and this model has none")
            from rasterkit.gltf import camera_of

            return camera_of(mesh, *self.size), center
        if self.camera_opencv is not None:
            from rasterkit.camera.opencv_file import opencv_camera

            return opencv_camera(self.camera_opencv, center, radius, self.near, self.far), center
        width, height = self.size
        camera = Camera.preset(self.projection, center, radius, width=width, height=height,
                               azimuth=self.azimuth, elevation=self.elevation, fov_y=self.fov,
                               distance=self.distance, eye=self.eye, target=self.target, up=self.up,
                               near=self.near, far=self.far, aperture=self.aperture, focus_distance=self.focus)
        return camera, center

    def camera_for(self, mesh):
        """The :class:`rasterkit.Camera` of this view for ``mesh`` (see :meth:`frame`)."""
        return self.frame(mesh)[0]


#: The names of :class:`View`'s fields.
FIELDS = frozenset(f.name for f in dataclasses.fields(View))


def _opencv(value) -> dict:
    """A camera file's path (read now), or a mapping of ``Camera.from_opencv``'s keywords
    (checked now), with ``source``: the file, or ``"camera_opencv"``."""
    if isinstance(value, (str, os.PathLike)):
        from rasterkit.camera.opencv_file import read_camera_file

        try:
            return read_camera_file(value)
        except ValueError as e:  # the file reader's own classes: a plain ValueError here
            raise ValueError(str(e)) from None
    if not isinstance(value, Mapping):
        raise TypeError(f"camera_opencv must be a path or a mapping of K, R, t, width, height, got "
                        f"{type(value).__name__}")
    data = {k: v for k, v in value.items() if k != "source"}
    from rasterkit.camera import Camera

    try:
        Camera.from_opencv(**data)  # every key and value checked here, once
    except (TypeError, ValueError) as e:
        raise type(e)(f"camera_opencv: {e}") from None
    return dict(data, source=os.fspath(value.get("source", "camera_opencv")))
