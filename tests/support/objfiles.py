"""A Mesh written as the smallest OBJ file that loads back as it: ``v`` and ``f`` lines."""

from __future__ import annotations

from pathlib import Path


def write_obj(path: Path, mesh) -> Path:
    """Write ``mesh`` (vertices and triangles, 1-based indices) to ``path``; returns ``path``."""
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in mesh.vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in mesh.faces.tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_textured_obj(path: Path, mesh, image) -> Path:
    """Write ``mesh`` with its per-vertex ``uv`` (``v``, ``vt`` and ``f v/vt`` lines), a
    ``.mtl`` beside it whose one material has ``image`` ((H, W, 3) uint8, written as a PNG) as
    its ``map_Kd``; returns ``path``."""
    from PIL import Image

    Image.fromarray(image).save(path.with_suffix(".png"))
    path.with_suffix(".mtl").write_text(f"newmtl skin\nKd 1 1 1\nmap_Kd {path.with_suffix('.png').name}\n")
    lines = [f"mtllib {path.with_suffix('.mtl').name}"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in mesh.vertices.tolist()]
    lines += [f"vt {u!r} {v!r}" for u, v in mesh.uv.tolist()]
    lines.append("usemtl skin")
    lines += [f"f {a + 1}/{a + 1} {b + 1}/{b + 1} {c + 1}/{c + 1}" for a, b, c in mesh.faces.tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


#: A closed tetrahedron, its faces counter-clockwise seen from outside.
TETRA = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
