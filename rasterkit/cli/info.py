"""``rasterkit info MODEL...``: what the reader made of each model, one block each."""

from __future__ import annotations

import sys

from rasterkit.batch import report as _report

__all__ = ["run"]


def run(args) -> int:
    """The ``info`` subcommand; its exit code (2 for a model that could not be read)."""
    from rasterkit.runtime.notice import compile_notice

    with compile_notice():
        return _models(args.models)


def _models(models: list[str]) -> int:
    from rasterkit.formats import as_drawn, detect, load

    codes = []
    for name in models:
        with _report.model(name):
            try:
                kind = detect(name)
                mesh, cloud = as_drawn(load(name, format=kind, textures=True))
            except Exception as e:
                code, line = _report.error_line(e)
                print(line, file=sys.stderr)
                codes.append(code)
                continue
        text = _describe_cloud(name, cloud) if mesh is None else _describe(name, kind, mesh, cloud)
        print(text, flush=True)  # a closed stdout stops all (main)
        codes.append(0)
    return 1 if 1 in codes else max(codes)


#: How ``info`` names each format.
FORMAT_NAMES = {"obj": "OBJ", "stl": "STL", "ply": "PLY", "off": "OFF", "gltf": "glTF 2.0 (the default scene, in world space)"}

#: The optional arrays of a Mesh that ``info`` names when the model has them.
ATTRIBUTES = ("vertex_colors", "normals", "texcoords", "uv", "corner_normals", "face_colors")

#: A Material's textures, with the ``.mtl`` statement that names each.
MAPS = (("diffuse_map", "map_Kd"), ("opacity_map", "map_d"), ("specular_map", "map_Ks"), ("normal_map", "bump"))


def _textures(mesh) -> list[str]:
    """One line per texture the materials use: the file, its size, and where it is used."""
    import os

    lines = []
    for material in mesh.materials:
        for field, statement in MAPS:
            texture = getattr(material, field, None)
            if texture is not None:
                lines.append(f"{os.path.basename(str(texture.name))}: {texture.width}x{texture.height}, "
                             f"{statement} of {material.name}")
    return lines


def _bounds(lo, hi) -> str:
    fmt = ", ".join
    return f"({fmt(f'{v:.6g}' for v in lo)}) .. ({fmt(f'{v:.6g}' for v in hi)})"


def _describe_cloud(name: str, cloud) -> str:
    """A point cloud's block: its points, bounds, attributes and warnings."""
    lines = [f"{name}", "  format    PLY point cloud", f"  points    {len(cloud.points)}",
             f"  bounds    {_bounds(*cloud.bounds)}",
             f"  attributes {', '.join(a for a in ('colors', 'normals') if getattr(cloud, a) is not None) or 'none'}",
             f"  warnings  {len(cloud.warnings)}"]
    lines += [f"    {w}" for w in cloud.warnings]
    return "\n".join(lines)


def _describe(name: str, kind: str, mesh, cloud=None) -> str:
    """A model's block; ``cloud``: the points drawn with it (a glTF scene's points primitives)."""
    lo, hi = mesh.bounds
    fmt = ", ".join
    lines = [
        f"{name}",
        f"  format    {FORMAT_NAMES[kind]}",
        f"  vertices  {len(mesh.vertices)}",
        f"  triangles {len(mesh.faces)}",
        f"  edges     {len(mesh.edges)}",
        f"  lines     {len(mesh.lines)}",
        *([] if cloud is None else [f"  points    {len(cloud)}"]),
        f"  bounds    {_bounds(lo, hi)}",
        f"  attributes {fmt(a for a in ATTRIBUTES if getattr(mesh, a) is not None) or 'none'}",
        f"  groups    {len(mesh.group_names)}: {fmt(mesh.group_names[:8])}{' ...' if len(mesh.group_names) > 8 else ''}",
        f"  materials {len(mesh.material_names)}: {fmt(mesh.material_names[:8])}{' ...' if len(mesh.material_names) > 8 else ''}",
    ]
    textures = _textures(mesh)
    lines.append(f"  textures  {len(textures)}" + ("" if textures else " (a texture that cannot be read is a warning)"))
    lines += [f"    {t}" for t in textures]
    lines.append(f"  warnings  {len(mesh.warnings)}")
    lines += [f"    {w}" for w in mesh.warnings]
    return "\n".join(lines)
