"""What the viewer shows of a frame: its colour, or one of its maps made into a picture; and
the picture's bytes (PNG for a finished frame, JPEG while the user drags)."""

from __future__ import annotations

import io

import numpy as np

__all__ = ["MAPS", "encode", "picture", "render_flags"]

#: What the viewer can show: the image, or the map the render makes beside it.
MAPS = ("color", "depth", "normals", "ids")

#: The JPEG quality of the frames sent while the user drags.
JPEG_QUALITY = 85


def render_flags(shown: str) -> dict:
    """The :class:`rasterkit.RenderOptions` changes that make the map ``shown``."""
    return {"ids": shown == "ids", "normals": shown == "normals", "camera_depth": shown == "depth"}


def picture(fb, shown: str) -> np.ndarray:
    """(H, W, 3 or 4) uint8 of framebuffer ``fb`` showing ``shown`` (one of :data:`MAPS`):
    the colour as drawn; the camera depth from white (nearest) to black (farthest drawn);
    the normals as ``(n + 1) / 2`` in RGB; each face id in a colour of its own (a hash of the
    id); the background black in the maps."""
    if shown == "color":
        return fb.color
    if shown == "depth":
        depth = fb.camera_depth()
        drawn = depth > 0.0  # (0 where nothing was drawn)
        out = np.zeros(depth.shape, np.uint8)
        if drawn.any():
            near, far = float(depth[drawn].min()), float(depth[drawn].max())
            span = far - near if far > near else 1.0
            out[drawn] = np.rint(255.0 - 200.0 * (depth[drawn] - near) / span).astype(np.uint8)
        return np.repeat(out[..., None], 3, axis=2)
    if shown == "normals":
        normals = np.nan_to_num(fb.normals, nan=-1.0)
        return np.clip(np.rint((normals + 1.0) * 127.5), 0, 255).astype(np.uint8)
    ids = fb.ids.astype(np.uint32)
    mixed = (ids + np.uint32(1)) * np.uint32(2654435761)  # Knuth's multiplicative hash
    rgb = np.stack([(mixed >> np.uint32(s)) & np.uint32(0xFF) for s in (8, 16, 24)], axis=2).astype(np.uint8)
    rgb[fb.ids < 0] = 0
    return rgb


def encode(rgb: np.ndarray, exact: bool) -> tuple[bytes, str]:
    """``(bytes, mime type)`` of the picture: PNG when ``exact`` (the pixels as drawn),
    else JPEG (a fraction of the bytes and of the time; RGBA composited over white)."""
    from PIL import Image

    out = io.BytesIO()
    if exact:
        Image.fromarray(rgb).save(out, format="PNG", compress_level=1)
        return out.getvalue(), "image/png"
    if rgb.shape[2] == 4:
        alpha = rgb[..., 3:4].astype(np.uint16)
        rgb = ((rgb[..., :3] * alpha + 255 * (255 - alpha) + 127) // 255).astype(np.uint8)
    Image.fromarray(rgb).save(out, format="JPEG", quality=JPEG_QUALITY)
    return out.getvalue(), "image/jpeg"
