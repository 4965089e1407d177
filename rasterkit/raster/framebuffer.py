"""Framebuffer: the colour, depth and (optional) primitive-id images a render draws into."""

from __future__ import annotations

import os

import numpy as np

from rasterkit.runtime import scratch as _memory
from rasterkit.colors import ColorLike, parse_color
from rasterkit.image.files import encode_png, save_image, to_pil
from rasterkit.limits import check_memory
from rasterkit.options import MAX_IMAGE_SIZE

__all__ = ["Framebuffer", "buffer_bytes"]

FARTHEST = np.float32(np.inf)


def buffer_bytes(width: int, height: int, alpha: bool = False, ids: bool = False, depth: bool = False) -> int:
    """Bytes of a framebuffer's buffers: colour (3 or 4 bytes a pixel), and the id and
    depth buffers (4 bytes a pixel each) when asked for."""
    return width * height * ((4 if alpha else 3) + (4 if ids else 0) + (4 if depth else 0))


class Framebuffer:
    """Colour, depth and optional id buffers of one image.

    Parameters
    ----------
    width, height : int
        Size in pixels.
    alpha : bool
        Four colour channels (RGBA) instead of three. Implied by a background with alpha < 255.
    background : colour
        ``'#rrggbb'``, a name (``'transparent'`` included) or an ``(r, g, b[, a])`` tuple.
    ids : bool
        Also keep a primitive-id buffer.
    cleared : bool
        False leaves the colour and id buffers uninitialised, for a renderer that clears
        them itself (faster, in parallel); :meth:`clear` does it in NumPy. The depth buffer
        is made on first use either way (by renderers through :meth:`uncleared_depth`).

    Attributes
    ----------
    color : (H, W, 3 or 4) uint8
        Cleared to the background.
    depth : (H, W) float32
        Cleared to +inf ("farthest"); drawn depths lie in [0, 1], 0 at the near plane.
        Made on first use: a wireframe render never needs it, and a solid render draws
        with a band-sized depth buffer per thread and leaves a recipe that makes this one
        (the same depths, by a depth-only pass over the same triangles) when it is read.
    ids : (H, W) int32 or None
        Index of the triangle seen at each pixel, -1 where none (for a scene rendered with
        ``ids=True``: its index within its object).
    object_ids : (H, W) int32 or None
        ``render(scene, ids=True)``: the index of the scene object seen, -1 where none.
    normals : (H, W, 3) float32 or None
        ``render(..., normals=True)``: unit surface normals in camera space (x right, y up,
        looking down -z), NaN where nothing was drawn.
    uv : (H, W, 2) float32 or None
        ``render(..., uv=True)``: the texture coordinates (u, v) seen at each pixel centre,
        interpolated perspective-correctly; NaN where nothing, or a face without texture
        coordinates, was drawn.
    ao : (H, W) float32 or None
        ``render(..., ao=True)``: the ambient light each pixel's surface receives, 1 in the
        open to 0 fully enclosed (one minus its ambient occlusion, :mod:`rasterkit.raster.ao`),
        NaN where no face was drawn; the colour was multiplied by it. Made on first read,
        from the frame's depth buffer as the render left it.
    camera : Camera or None
        The camera a render drew with (:meth:`camera_depth` inverts its depth mapping).
    width, height : int
        The colour buffer's size (read-only).

    Raises
    ------
    rasterkit.limits.LimitError
        When the buffers would need more than :func:`rasterkit.limits.memory_limit`; the
        depth buffer is checked when it is made.

    Notes
    -----
    The buffers' memory is recycled (:mod:`rasterkit.runtime.scratch`): a new framebuffer reuses
    the memory of one that nothing refers to any more, which saves the operating system's
    page faults on fresh memory (several milliseconds per 1080p frame).
    """

    def __init__(self, width: int, height: int, alpha: bool = False,
                 background: ColorLike = "white", ids: bool = False, *, cleared: bool = True):
        if isinstance(width, bool) or isinstance(height, bool) or int(width) != width \
                or int(height) != height \
                or not (1 <= width <= MAX_IMAGE_SIZE and 1 <= height <= MAX_IMAGE_SIZE):
            raise ValueError(
                f"size must be whole numbers from 1 to {MAX_IMAGE_SIZE}, got {width}x{height}")
        self.background = parse_color(background)
        alpha = bool(alpha) or self.background[3] < 255
        width, height = int(width), int(height)
        check_memory(buffer_bytes(width, height, alpha, ids), f"a {width}x{height} framebuffer")
        self.color = _memory.take((height, width, 4 if alpha else 3), np.uint8)
        self._depth = None  # not made yet: all farthest, or what _depth_source draws (defer_depth)
        self._depth_source = None
        self.ids = _memory.take((height, width), np.int32) if ids else None
        self.object_ids = self.normals = self.uv = self.camera = None
        self._ao, self._ao_source = None, None  # the AO map, or what makes it (defer_ao)
        self.object_first = None  # (K,) int64: each scene object's first face, with object_ids
        self._camera_depth = None  # (metric depth, its camera), made by a render (keep_camera_depth)
        if cleared:
            self.clear()

    @property
    def width(self) -> int:
        """Image width in pixels: the colour buffer's."""
        return self.color.shape[1]

    @property
    def height(self) -> int:
        """Image height in pixels: the colour buffer's."""
        return self.color.shape[0]

    @property
    def depth(self) -> np.ndarray:
        if self._depth is None:
            source = self._depth_source
            if source is not None and source[1] != (self.height, self.width):
                raise ValueError(f"the depth buffer of this {source[1][1]}x{source[1][0]} render cannot be made: "
                                 f"Framebuffer.color was replaced by a {self.width}x{self.height} one")
            self.uncleared_depth().fill(FARTHEST)
            self._depth_source = None
            if source is not None:
                source[0](self._depth)
        return self._depth

    @depth.setter
    def depth(self, value) -> None:
        value = np.asarray(value)
        if value.shape != (self.height, self.width) or value.dtype != np.float32:
            raise ValueError(f"depth must be a ({self.height}, {self.width}) float32 array")
        self._depth = value
        self._depth_source = None
        self._camera_depth = None

    @property
    def ao(self) -> np.ndarray | None:
        if self._ao_source is not None:
            source, self._ao_source = self._ao_source, None
            self._ao = source()
        return self._ao

    @ao.setter
    def ao(self, value) -> None:
        self._ao, self._ao_source = value, None

    def defer_ao(self, source) -> None:
        """Leave the AO map to ``source()``, called on the first read of :attr:`ao`."""
        self._ao, self._ao_source = None, source

    def uncleared_depth(self) -> np.ndarray:
        """The depth buffer, for a renderer that writes every pixel of it (it clears the
        buffer itself, band by band in its drawing threads).

        Made uninitialised when it does not exist yet: reading :attr:`depth` instead would
        first fill it with +inf, a pass over the whole buffer that the renderer's own clear
        makes useless. An existing buffer is returned as it is.

        Returns
        -------
        (H, W) float32
        """
        if self._depth is None:
            height, width = self.height, self.width
            check_memory(buffer_bytes(width, height, self.alpha, self.ids is not None, depth=True),
                         f"the depth buffer of a {width}x{height} framebuffer")
            self._depth = _memory.take((height, width), np.float32)
        return self._depth

    def defer_depth(self, source) -> None:
        """Have the depth buffer made only when it is first read, by ``source``.

        For a renderer that tests depth in scratch memory of its own and keeps no
        image-sized depth buffer: it leaves the recipe of the depth it tested, and a caller
        that never reads :attr:`depth` never pays for it. The current depth buffer is
        dropped; the first read of :attr:`depth` fills a new one with +inf and calls
        ``source(depth)`` with it, once. :meth:`clear` and assigning :attr:`depth` forget
        the recipe.

        Parameters
        ----------
        source : callable
            ``source(depth)``: draws into the (H, W) float32 buffer, cleared to +inf.
        """
        self._depth = self._camera_depth = None
        self._depth_source = (source, (self.height, self.width))  # drawn for this size only

    @property
    def alpha(self) -> bool:
        return self.color.shape[2] == 4

    def clear(self) -> None:
        """Colour to the background, depth to +inf, ids to -1, and no AO map (:attr:`ao` None)."""
        self.color[...] = self.background[: self.color.shape[2]]
        self._depth_source = self._camera_depth = self._ao = self._ao_source = None
        if self._depth is not None:
            self._depth.fill(FARTHEST)
        if self.ids is not None:
            self.ids.fill(-1)

    # --- the images of a vision pipeline (rasterkit.raster.vision) -------------------------------

    def camera_depth(self) -> np.ndarray:
        """Depth along the camera's optical axis, world units: (H, W) float32, 0 where nothing
        was drawn (pyrender's convention); the exact inverse of :attr:`depth` for the camera
        of the render (:mod:`rasterkit.raster.vision`). A render with ``camera_depth=True`` made it
        while drawing: that array is returned (the same one each call, until the depth
        buffer is cleared or replaced); otherwise it is made here. Raises ``ValueError`` for
        a framebuffer that no render drew."""
        from rasterkit.raster.vision import camera_depth

        camera = self._camera("camera_depth")
        kept = self._camera_depth
        if kept is not None and kept[1] is camera and kept[0].shape == (self.height, self.width):
            return kept[0]
        return camera_depth(self.depth, camera)

    def keep_camera_depth(self, metric: np.ndarray) -> None:
        """Keep ``metric`` (H, W) float32, the metric depth that a render made of this
        framebuffer's depth while drawing, for :meth:`camera_depth` (for the camera set now)."""
        self._camera_depth = (metric, self.camera)

    def visible_faces(self) -> tuple[np.ndarray, np.ndarray]:
        """``(face_ids, pixel_counts)``, int64 arrays: the faces seen (ascending) and the
        pixels each covers, from :attr:`ids` (``render(..., ids=True)``). For a scene a
        face's index is its index in ``scene.world_mesh()``."""
        if self.ids is None:
            raise ValueError("visible_faces needs the face ids: render with ids=True")
        from rasterkit.raster.vision import visible_faces

        return visible_faces(self.ids, self.object_ids, self.object_first)

    def save_depth(self, path: str | os.PathLike, scale: float = 1000.0) -> None:
        """:meth:`camera_depth` to ``.npy`` (float32, as it is) or to a 16-bit greyscale
        ``.png`` holding ``round(depth·scale)``, by default millimetres when the world unit
        is the metre, clipped to 65535; 0 where nothing was drawn. Written atomically.
        ``scale`` must be a finite number above 0 (ValueError otherwise)."""
        from rasterkit.raster.vision import save_depth

        save_depth(self.camera_depth(), path, scale)

    def save_normals(self, path: str | os.PathLike) -> None:
        """:attr:`normals` to ``.npy`` or to an RGB ``.png`` of ``(n + 1)/2·255`` (black where
        nothing was drawn)."""
        if self.normals is None:
            raise ValueError("no normals: render with normals=True")
        from rasterkit.raster.vision import save_normals

        save_normals(self.normals, path)

    def save_ids(self, path: str | os.PathLike, objects: bool = False) -> None:
        """:attr:`ids` (or :attr:`object_ids` when ``objects``) to ``.npy`` (int32, -1 for
        none) or to a 16-bit greyscale ``.png`` of ``id + 1`` (0 for none)."""
        ids = self.object_ids if objects else self.ids
        if ids is None:
            raise ValueError("no ids: render with ids=True" + (" a Scene" if objects else ""))
        from rasterkit.raster.vision import save_ids

        save_ids(ids, path)

    def _camera(self, what: str):
        if self.camera is None:
            raise ValueError(f"{what} needs the camera of a render: this framebuffer was not drawn by render()")
        return self.camera

    def to_image(self):
        """The colour buffer as a Pillow image (RGB or RGBA)."""
        return to_pil(self.color)

    def save(self, path: str | os.PathLike) -> None:
        """Write the colour buffer as a PNG (RGBA when it has alpha), atomically."""
        save_image(self.color, path)

    def _repr_png_(self) -> bytes:
        return encode_png(self.color)

    def __repr__(self) -> str:
        kind = "RGBA" if self.alpha else "RGB"
        return f"Framebuffer({self.width}x{self.height}, {kind}{', ids' if self.ids is not None else ''})"
