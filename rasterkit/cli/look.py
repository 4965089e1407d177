"""The command line's appearance flags (colours, shading, lights, shadows, samples, textures),
shared by ``render`` and ``view``."""

from __future__ import annotations

from rasterkit.cli.args import (LIGHT_FORMS, finite, light, non_negative, positive, positive_int, samples,
                                shadow_map_size, softness, unit_interval)
from rasterkit.options import CULL, EDGES, HIDDEN, SHADING, TEXTURE_FILTERS

__all__ = ["add_look_arguments"]


def add_look_arguments(parser) -> None:
    """The appearance group of flags, into ``parser``."""
    look = parser.add_argument_group("appearance")
    look.add_argument("--color", default="lightgray", help="surface colour (name or #rrggbb)")
    look.add_argument("--line-color", default="black", help="line colour (name or #rrggbb)")
    look.add_argument("--background", default=None,
                      help="background colour; 'transparent' writes RGBA (default white; with "
                           "--ground shadow, transparent)")
    look.add_argument("--cull", choices=CULL, default="back")
    look.add_argument("--shading", choices=SHADING, default="flat",
                      help="per face (default), per vertex (smooth) or per pixel (phong, Blinn-Phong)")
    look.add_argument("--light", dest="lights", type=light, action="append", default=[], metavar="KIND:...",
                      help=f"a light, repeatable: {LIGHT_FORMS} (world space; directions towards the "
                           "scene, spot ANGLE the cone's full opening in degrees)")
    look.add_argument("--specular", type=unit_interval, default=0.25, metavar="S",
                      help="highlight strength of surfaces without a material, 0 to 1 (default 0.25)")
    look.add_argument("--shininess", type=non_negative, default=32.0, metavar="N",
                      help="Blinn-Phong exponent of surfaces without a material (default 32)")
    look.add_argument("--ground", nargs="?", const="#d8d8d8", default=None, metavar="COLOR",
                      help="a ground under the model that catches its shadows (default colour #d8d8d8)")
    look.add_argument("--shadows", action="store_true",
                      help="every light (but ambient ones) casts shadows (shadow maps; faces lit per pixel)")
    look.add_argument("--shadow-map-size", type=shadow_map_size, default=None, metavar="N",
                      help="side of each shadow map in texels, 16 to 8192 (default: by the image size, 512 to 4096)")
    look.add_argument("--shadow-softness", type=softness, default=1.0, metavar="S",
                      help="shadow filter radius in texels, 0 (hard) to 8 (default 1: 3x3)")
    look.add_argument("--ao", action="store_true",
                      help="ambient occlusion: creases and contacts darkened (screen space, from the depth)")
    look.add_argument("--ao-radius", type=positive, default=None, metavar="R",
                      help="how far a surface occludes, world units (default: a tenth of the model's diagonal)")
    look.add_argument("--ao-samples", type=samples, default=8, metavar="N",
                      help="ambient occlusion rays per pixel, 1 to 256 (default 8)")
    look.add_argument("--aa", action="store_true", help="anti-aliased (Wu) lines")
    look.add_argument("--edges", choices=EDGES, default="all",
                      help="the polygons' edges (default), or feature edges: silhouettes, "
                           "boundaries, creases, material boundaries")
    look.add_argument("--crease-angle", type=finite, default=30.0, metavar="DEG",
                      help="angle between face normals from which an edge is a crease (default 30)")
    look.add_argument("--hidden", choices=tuple(h for h in HIDDEN if h is not None), default=None,
                      help="SVG only: draw the hidden parts of the lines dashed, in a layer of their own")
    look.add_argument("--samples", type=samples, default=1, metavar="N",
                      help="jittered samples per pixel, averaged: anti-aliasing, and depth of field "
                           "with --aperture (1 to 256, default 1)")
    look.add_argument("--vignette", type=unit_interval, default=0.0, metavar="V",
                      help="natural cos^4 falloff towards the corners, 0 (none, default) to 1 (full)")
    look.add_argument("--point-size", type=positive_int, default=1, metavar="PX",
                      help="side in pixels (1 to 64) of the squares a point cloud's points are drawn as (default 1)")
    look.add_argument("--no-textures", dest="textures", action="store_false",
                      help="draw textured materials in their plain colour (and read no texture file)")
    look.add_argument("--texture-filter", choices=TEXTURE_FILTERS, default="trilinear",
                      help="mipmaps (trilinear, default), the 4 nearest texels (bilinear) or the nearest (nearest)")
