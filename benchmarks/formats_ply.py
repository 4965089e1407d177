"""PLY reading: :func:`rasterkit.ply.read_ply` against trimesh and plyfile.

trimesh loads with ``process=False`` (no merging or cleaning; it makes no edges and checks
no index), plyfile reads the elements into NumPy records (faces as an object array of
lists). rasterkit's side makes a checked :class:`rasterkit.Mesh`: triangles, the polygons'
edges, colours. The files: the Stanford bunny (``bun_zipper.ply``, ASCII, 35,947 vertices,
in ``../shared/models/formats``) and a grid of about a million triangles written once into
the temporary folder (``rasterkit-bench-ply/``): binary and ASCII as trimesh writes them
(``float`` x y z, ``list uchar int vertex_indices``), the same grid as quads, and as
triangles and quads mixed (rows of different lengths: the walk). Each side's work is the
file size, reported as MiB/s.

Part of the ``loading`` family (:mod:`benchmarks.loading`); run alone with::

    python -c "from benchmarks import formats_ply; formats_ply.main()"
"""

from __future__ import annotations

import tempfile
from functools import partial
from pathlib import Path

import numpy as np

from rasterkit.ply import read_ply

from .compare import RASTERKIT, compare, start
from .report import Target
from .settings import MODELS_DIR

FAMILY = "loading"

BUNNY = MODELS_DIR / "formats" / "ply" / "bun_zipper.ply"
FOLDER = Path(tempfile.gettempdir()) / "rasterkit-bench-ply"

#: Grid of SIDE x SIDE vertices: 2 (SIDE - 1)^2 = 999,698 triangles.
SIDE = 708

#: Issue 28's goal for binary PLY against trimesh.
BINARY_TARGET = Target("binary PLY <= 0.2x trimesh's time", 0.2)


def grid() -> tuple[np.ndarray, np.ndarray]:
    """Vertices (SIDE^2, 3) float32 of a wavy sheet, and its quads (Q, 4) int32, row by row."""
    u, v = np.meshgrid(np.linspace(0, 1, SIDE), np.linspace(0, 1, SIDE))
    z = 0.05 * np.sin(12 * u) * np.cos(9 * v)
    vertices = np.stack([u, v, z], axis=-1).reshape(-1, 3).astype(np.float32)
    i, j = np.meshgrid(np.arange(SIDE - 1), np.arange(SIDE - 1), indexing="ij")
    a = (i * SIDE + j).ravel()
    return vertices, np.stack([a, a + 1, a + SIDE + 1, a + SIDE], axis=1).astype(np.int32)


def _header(encoding: str, vertices: int, faces: int) -> bytes:
    return (f"ply\nformat {encoding} 1.0\ncomment rasterkit benchmark grid\nelement vertex {vertices}\n"
            "property float x\nproperty float y\nproperty float z\n"
            f"element face {faces}\nproperty list uchar int vertex_indices\nend_header\n").encode()


def _binary(vertices: np.ndarray, polygons: list) -> bytes:
    """The body: vertices, then the rows (count and indices) of one (P, k) array of
    polygons, or of two arrays of as many rows, taken in turn."""
    parts = [vertices.astype("<f4").tobytes()]
    rows = []
    for p in polygons:
        record = np.empty(len(p), [("n", "u1"), ("i", "<i4", (p.shape[1],))])
        record["n"], record["i"] = p.shape[1], p
        rows.append(record.tobytes())
    if len(polygons) == 2 and len(polygons[0]) == len(polygons[1]):  # mixed: alternate rows
        a = np.frombuffer(rows[0], np.uint8).reshape(len(polygons[0]), -1)
        b = np.frombuffer(rows[1], np.uint8).reshape(len(polygons[1]), -1)
        rows = [np.concatenate([a, b], axis=1).tobytes()]
    return b"".join(parts + rows)


def _ascii(vertices: np.ndarray, triangles: np.ndarray) -> bytes:
    lines = [" ".join(f"{x:g}" for x in v) for v in vertices.tolist()]
    lines += ["3 " + " ".join(map(str, t)) for t in triangles.tolist()]
    return ("\n".join(lines) + "\n").encode()


def files() -> dict:
    """{name: path} of the generated files, written on first use."""
    FOLDER.mkdir(exist_ok=True)
    paths = {name: FOLDER / f"{name}.ply" for name in ("grid-1M-binary", "grid-1M-ascii", "grid-quads-binary",
                                                         "grid-mixed-binary")}
    if all(p.is_file() for p in paths.values()):
        return paths
    vertices, quads = grid()
    triangles = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    n, half = len(vertices), len(quads) // 2
    writes = {
        "grid-1M-binary": _header("binary_little_endian", n, len(triangles)) + _binary(vertices, [triangles]),
        "grid-1M-ascii": _header("ascii", n, len(triangles)) + _ascii(vertices, triangles),
        "grid-quads-binary": _header("binary_little_endian", n, len(quads)) + _binary(vertices, [quads]),
        # every other quad as one of its triangles: rows of 13 and 17 bytes in turn
        "grid-mixed-binary": _header("binary_little_endian", n, 2 * half)
        + _binary(vertices, [quads[0:2 * half:2, :3], quads[1:2 * half:2]]),
    }
    for name, data in writes.items():
        paths[name].with_suffix(".tmp").write_bytes(data)
        paths[name].with_suffix(".tmp").replace(paths[name])
    return paths


def run(settings, results, peers=None) -> None:
    """The bunny and the generated files, read by each side."""
    trimesh = start(results, FAMILY, "trimesh", lambda: peers.module("trimesh")) if peers else None
    plyfile = start(results, FAMILY, "plyfile", lambda: peers.module("plyfile")) if peers else None
    paths = {"bun_zipper": BUNNY, **files()}
    for name, path in paths.items():
        if not path.is_file():
            results.skip(FAMILY, f"ply/{name}", f"model file {path} not found")
            continue
        sides = {RASTERKIT: partial(read_ply, path)}
        if trimesh:
            sides["trimesh"] = partial(trimesh.load, path, process=False)
            sides["trimesh (default)"] = partial(trimesh.load, path)  # what a user calls: merges vertices
        if plyfile and path.stat().st_size < 2**24:  # plyfile takes seconds per million faces
            sides["plyfile"] = partial(plyfile.PlyData.read, str(path))
        mib = path.stat().st_size / 2**20
        targets = {"trimesh": BINARY_TARGET} if "binary" in name else None
        compare(results, FAMILY, f"loading/ply/{name}", sides, repeat=settings.repeat, warmup=settings.warmup,
                sizes={"MiB": round(mib, 2)}, work=mib, unit="MiB/s", targets=targets)


def main() -> None:
    """Run this family alone with the full profile's repeats, printing each record."""
    from .peers import Peers
    from .report import Results
    from .settings import FULL

    run(FULL, Results(), Peers())
