"""What a face element carries besides its vertices: a colour per face (``red``, ``green``,
``blue``, as vertex colours are read: :func:`rasterkit.ply.vertices.unit_colors`), MeshLab's
texture coordinates per face corner (a list ``texcoord`` of ``u v`` pairs, one per corner,
read as written) and its texture number (``texnumber``, with several ``TextureFile``
comments).

A face whose ``texcoord`` list does not hold two values per corner has no texture
coordinates (its triangles' ``uv_index`` rows are -1, with one warning for all such faces).
"""

from __future__ import annotations

import numpy as np

from rasterkit.ply.errors import Notes, count
from rasterkit.ply.faces import Polygons, Triangles
from rasterkit.ply.header import Element
from rasterkit.ply.vertices import COLORS, first_of, unit_colors

__all__ = ["CORNER_TEXCOORDS", "corner_texcoords", "corner_uv", "face_colors", "texture_numbers"]

CORNER_TEXCOORDS = "texcoord"


def corner_texcoords(element: Element | None):
    """The face element's ``texcoord`` list property (None without one)."""
    if element is None:
        return None
    prop = element.find(CORNER_TEXCOORDS)
    return prop if prop is not None and prop.is_list else None


def corner_uv(rows, prop, polygons: Polygons, triangles: Triangles, notes: Notes):
    """``(uv (C, 2) float64, uv_index (M, 3) int64)``: the pairs of ``prop`` as a table of
    one row per polygon corner, and each triangle corner's row (-1 rows where its polygon
    has none); ``(None, None)`` when no kept face has them."""
    values, offsets = rows.items(prop)
    values = np.asarray(values, np.float64).reshape(-1)
    sizes = polygons.sizes
    good = np.diff(offsets) == 2 * sizes
    if good.all():
        uv = values.reshape(-1, 2)
    else:
        uv = np.full((len(polygons.corners), 2), np.nan)
        uv[np.repeat(good, sizes)] = values[np.repeat(good, np.diff(offsets))].reshape(-1, 2)
        bad = ~good & triangles.keep
        if bad.any():
            first = int(np.argmax(bad))
            notes.warn(prop.line,
                       f"{count(np.count_nonzero(bad), 'face')} whose {prop.name!r} list does not hold two "
                       f"values per corner (the first: row {first}): no texture coordinates for them")
    index = triangles.corner_rows()
    has = triangles.per_polygon(good)
    if not has.any():
        return None, None
    if not has.all():
        index = np.where(has[:, None], index, -1)
    return uv, index


def face_colors(rows, element: Element, triangles: Triangles, notes: Notes) -> np.ndarray | None:
    """(M, 3) float32 colour of each triangle's face, or None when faces have none."""
    props = first_of(element, COLORS, notes)
    if props is None:
        return None
    return triangles.per_polygon(unit_colors(rows, props, notes))


def texture_numbers(rows, element: Element, triangles: Triangles, textures: int, notes: Notes) -> np.ndarray:
    """(M,) int32 texture of each triangle: its face's ``texnumber`` (-1 where that is not
    one of the ``textures``, with a warning), or 0 when faces have no ``texnumber``."""
    prop = element.find("texnumber")
    if prop is None or prop.is_list:
        return np.zeros(len(triangles.faces), np.int32)
    numbers = np.asarray(rows.scalar(prop), np.float64)
    valid = (numbers >= 0) & (numbers < textures) & (numbers == np.floor(numbers))
    if not valid.all():
        notes.warn(prop.line, f"{count(np.count_nonzero(~valid), 'face')} whose texnumber names no TextureFile "
                              f"(there are {textures}): drawn without a texture")
    return triangles.per_polygon(np.where(valid, numbers, -1).astype(np.int32))
