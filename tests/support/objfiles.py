"""A Mesh written as the smallest OBJ file that loads back as it: ``v`` and ``f`` lines."""

from __future__ import annotations

from pathlib import Path


def write_obj(path: Path, mesh) -> Path:
    """Write ``mesh`` (vertices and triangles, 1-based indices) to ``path``; returns ``path``."""
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in mesh.vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in mesh.faces.tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


#: A closed tetrahedron, its faces counter-clockwise seen from outside.
TETRA = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
