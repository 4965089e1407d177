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
    from rasterkit.obj import load_obj

    codes = []
    for name in models:
        with _report.model(name):
            try:
                mesh = load_obj(name)
            except Exception as e:
                code, line = _report.error_line(e)
                print(line, file=sys.stderr)
                codes.append(code)
                continue
        print(_describe(name, mesh), flush=True)  # a closed stdout stops all (main)
        codes.append(0)
    return 1 if 1 in codes else max(codes)


def _describe(name: str, mesh) -> str:
    lo, hi = mesh.bounds
    fmt = ", ".join
    lines = [
        f"{name}",
        f"  vertices  {len(mesh.vertices)}",
        f"  triangles {len(mesh.faces)}",
        f"  edges     {len(mesh.edges)}",
        f"  lines     {len(mesh.lines)}",
        f"  bounds    ({fmt(f'{v:.6g}' for v in lo)}) .. ({fmt(f'{v:.6g}' for v in hi)})",
        f"  attributes {fmt(a for a in ('vertex_colors', 'normals', 'texcoords', 'face_colors') if getattr(mesh, a) is not None) or 'none'}",
        f"  groups    {len(mesh.group_names)}: {fmt(mesh.group_names[:8])}{' ...' if len(mesh.group_names) > 8 else ''}",
        f"  materials {len(mesh.material_names)}: {fmt(mesh.material_names[:8])}{' ...' if len(mesh.material_names) > 8 else ''}",
        f"  warnings  {len(mesh.warnings)}",
    ]
    lines += [f"    {w}" for w in mesh.warnings]
    return "\n".join(lines)
