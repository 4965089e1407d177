"""A contact sheet: the thumbnails of a batch's images in a grid, each with its name.

Cells are at most 160 pixels wide (fewer when a row would pass 8192 pixels), the names
below them in Pillow's built-in font, shortened to fit. Missing or unreadable images get an
empty cell with their name, so the grid keeps the batch's order. The thumbnails are read a
few rows at a time (:mod:`rasterkit.batch.thumbnails`): an image of any size is one of ours,
not a decompression bomb. Written atomically.
"""

from __future__ import annotations

import math
from pathlib import Path

__all__ = ["contact_sheet"]

_CELL, _MAX_WIDTH, _LABEL, _PAD = 160, 8192, 14, 4


def contact_sheet(images: list[Path], path: Path, background=(255, 255, 255)) -> tuple[int, int]:
    """Write the sheet of ``images`` to ``path`` (PNG); returns its (width, height)."""
    from PIL import Image, ImageDraw, ImageFont

    from rasterkit.image.atomic import atomic_write
    from rasterkit.batch.thumbnails import thumbnail
    from rasterkit.limits import check_memory

    n = max(len(images), 1)
    columns = max(1, math.ceil(math.sqrt(n * 4 / 3)))
    cell = max(16, min(_CELL, (_MAX_WIDTH - _PAD) // columns - _PAD))
    rows = math.ceil(n / columns)
    width = columns * (cell + _PAD) + _PAD
    height = rows * (cell + _LABEL + _PAD) + _PAD
    check_memory(3 * width * height, "the contact sheet")
    sheet = Image.new("RGB", (width, height), background)
    draw = ImageDraw.Draw(sheet)
    font = ImageFont.load_default()
    for k, image_path in enumerate(images):
        x = _PAD + (k % columns) * (cell + _PAD)
        y = _PAD + (k // columns) * (cell + _LABEL + _PAD)
        try:
            thumb = thumbnail(image_path, cell)
            sheet.paste(thumb, (x + (cell - thumb.width) // 2, y + (cell - thumb.height) // 2), thumb)
        except (OSError, ValueError, MemoryError):
            draw.rectangle((x, y, x + cell - 1, y + cell - 1), outline=(200, 0, 0))
        name = Path(image_path).stem
        while name and draw.textlength(name, font=font) > cell:
            name = name[:-2] + "…" if len(name) > 2 else ""
        draw.text((x, y + cell + 1), name, fill=(0, 0, 0), font=font)
    with atomic_write(path) as tmp:
        sheet.save(tmp, format="PNG")
    return width, height
