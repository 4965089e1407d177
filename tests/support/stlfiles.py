"""STL files written from arrays, for the tests and the fuzzer: binary (the 50-byte records,
by NumPy) and ASCII (one facet per seven lines, numbers as Python's ``repr``)."""

from __future__ import annotations

import numpy as np

RECORD = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])

#: A closed tetrahedron as facets (corners counter-clockwise seen from outside).
TETRA = np.array([[[0, 0, 0], [0, 1, 0], [1, 0, 0]],
                  [[0, 0, 0], [1, 0, 0], [0, 0, 1]],
                  [[0, 0, 0], [0, 0, 1], [0, 1, 0]],
                  [[1, 0, 0], [0, 1, 0], [0, 0, 1]]], np.float64)


def normals_of(corners) -> np.ndarray:
    """Unit normals (F, 3) of facets by the right-hand rule."""
    c = np.asarray(corners, np.float64)
    n = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def binary_stl(corners, normals=None, attributes=None, header: bytes = b"written by the tests",
               count: int | None = None) -> bytes:
    """The bytes of a binary STL file of ``corners`` (F, 3, 3); ``count`` (default F) is what
    the header says."""
    corners = np.asarray(corners, np.float64)
    records = np.zeros(len(corners), RECORD)
    records["corners"] = corners
    records["normal"] = normals_of(corners) if normals is None else normals
    if attributes is not None:
        records["attribute"] = attributes
    count = len(corners) if count is None else count
    return header.ljust(80, b" ")[:80] + np.uint32(count).tobytes() + records.tobytes()


def ascii_stl(corners, normals=None, name: str = "tests", end: str = "\n") -> str:
    """The text of an ASCII STL file of ``corners`` (F, 3, 3), one ``solid`` block."""
    corners = np.asarray(corners, np.float64)
    normals = normals_of(corners) if normals is None else np.asarray(normals, np.float64)
    lines = [f"solid {name}".rstrip()]
    for facet, normal in zip(corners.tolist(), normals.tolist()):
        lines.append("  facet normal " + " ".join(map(repr, normal)))
        lines.append("    outer loop")
        lines += ["      vertex " + " ".join(map(repr, corner)) for corner in facet]
        lines += ["    endloop", "  endfacet"]
    lines.append(f"endsolid {name}".rstrip())
    return end.join(lines) + end


def reference_weld(corners):
    """``(inverse, first)``: each corner's vertex, numbered by the first appearance of its
    coordinates (compared as numbers: ``-0.0`` is ``0.0``), and the first corner of each."""
    seen: dict = {}
    inverse = [seen.setdefault(tuple(float(x) + 0.0 for x in row), len(seen)) for row in np.asarray(corners)]
    first: dict = {}
    for i, v in enumerate(inverse):
        first.setdefault(v, i)
    return np.array(inverse, np.int64), np.array([first[v] for v in range(len(seen))], np.int64)
