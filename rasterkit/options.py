"""The lists of choices and the size limit: one home, shared by the command line and the API.

Pure Python: importing this module imports neither NumPy nor Numba, so the command line
builds its parser, answers ``--help`` and rejects bad arguments without loading the kernels.
"""

from rasterkit.raster.kernels.limits import MAX_IMAGE_SIZE

__all__ = ["CULL", "EDGES", "HIDDEN", "MAX_IMAGE_SIZE", "MODES", "PROJECTIONS", "SHADING", "SVG_MODES", "check_choice"]

#: What :func:`rasterkit.render` draws: every edge; only the visible parts of the edges;
#: shaded triangles; shaded triangles with their visible edges on top.
MODES = ("wire", "hidden", "solid", "solid+wire")

#: Which edges are drawn: those of the original polygons, or the feature edges (silhouettes,
#: boundaries, creases, material boundaries: :mod:`rasterkit.raster.features`).
EDGES = ("all", "feature")

#: What :func:`rasterkit.render_svg` draws: every edge, or only their visible parts.
SVG_MODES = ("wire", "hidden")

#: What a vector drawing does with the hidden parts of the edges: leaves them out (None) or
#: draws them dashed.
HIDDEN = (None, "dashed")

#: Which triangles are removed before rasterization: those facing away from the camera,
#: those facing it, or none.
CULL = ("back", "front", "none")

#: Lambert shading per face, or per vertex (Gouraud).
SHADING = ("flat", "smooth")

PROJECTIONS = ("perspective", "orthographic", "isometric", "dimetric", "trimetric", "cavalier",
               "cabinet", "1-point", "2-point", "3-point")
"""Names accepted by :meth:`Camera.preset` (and the command line's ``--projection``)."""


def check_choice(name: str, value, allowed: tuple):
    """``value`` when it is one of ``allowed``, else ``ValueError`` naming ``name`` and the choices."""
    if value not in allowed:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, allowed))}, got {value!r}")
    return value
