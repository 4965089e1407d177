"""STL and OFF loading: rasterkit.stl.read_stl and rasterkit.off.read_off against trimesh (and
numpy-stl where installed), on the public files of ``../shared/models/formats`` and on larger
files generated here.

What each side does with a binary STL file: trimesh loads with ``process=False`` (no merging
or cleaning; also with its default, ``trimesh (welding)``, which merges the corners as
rasterkit welds them: the like-for-like side of issue 28's goal): one ``frombuffer`` of the records, three float64 vertices per facet (not welded:
3M vertices for 1M facets) and faces ``0 .. 3F-1``, the file's normals kept as they are, and a
hash of its arrays for its cache. rasterkit checks every facet's numbers (NaN, infinite, two
equal corners), welds the corners into shared vertices, checks each normal against its
facet's winding, reads the colours of the attribute words, and makes a Mesh, which checks its
indices and copies each array into memory of its own (``rasterkit.mesh.checks.seal``): the
edges are not made (a Mesh works them out on first use). numpy-stl reads the facets only. So
the two sides do different work, and fresh memory (page faults: about 0.5-1 ms per MiB on the
shared machine) is most of either side's time: rasterkit's Mesh alone touches twice its
arrays (the arrays and their sealed copies, 80 MiB each for 1M facets). Each side's work is
the file size, reported as MiB/s.

The generated files (in a temporary folder, removed afterwards): a sphere of triangles written
as binary STL, as ASCII STL with numbers like most CAD writers' (``%e``, 7 digits) and with
Python's ``repr`` (17 digits, as trimesh writes them: these need the exact second conversion of
:func:`rasterkit.runtime.tokens.floats`), and as OFF (``%.6f``). Their sizes follow the profile.

Part of the ``loading`` family (:mod:`benchmarks.loading`); by itself::

    python -m benchmarks.formats_stl_off [--tiny | --quick]
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from functools import partial
from pathlib import Path

import numpy as np

from rasterkit.off import read_off
from rasterkit.stl import read_stl

from .compare import RASTERKIT, compare
from .report import Results, Target
from .settings import FULL, MODELS_DIR, QUICK, TINY

FAMILY = "loading"

#: Issue 28's goal for binary STL, both sides welding the corners (trimesh's default load).
BINARY_TARGET = Target("binary STL <= 0.2x trimesh's welding load", 0.2)

#: Facets of the generated sphere for each profile: binary STL, ASCII STL (both styles), OFF.
SIZES = {"full": (1_000_000, 250_000, 500_000), "quick": (200_000, 50_000, 100_000),
         "targets": (200_000, 50_000, 100_000), "tiny": (4_000, 2_000, 2_000)}

_FACET = "facet normal {} {} {}\n outer loop\n  vertex {} {} {}\n  vertex {} {} {}\n  vertex {} {} {}\n endloop\nendfacet\n"


def sphere(facets: int) -> tuple[np.ndarray, np.ndarray]:
    """A UV sphere of about ``facets`` triangles: vertices (N, 3) float32-exact float64, faces (M, 3)."""
    rings = max(int(np.sqrt(facets / 4)), 3)  # 2 rings around, rings - 1 bands of 2 triangles: about 4 rings**2
    theta = np.linspace(0, np.pi, rings + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, 2 * rings, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1).reshape(-1, 3)
    vertices = np.concatenate([[[0, 0, 1]], ring, [[0, 0, -1]]]).astype(np.float32).astype(np.float64)
    k = 2 * rings
    grid = 1 + np.arange((rings - 1) * k).reshape(rings - 1, k)
    right = np.roll(grid, -1, axis=1)
    top = np.stack([np.zeros(k, np.int64), grid[0], right[0]], axis=1)
    bottom = np.stack([np.full(k, len(vertices) - 1), right[-1], grid[-1]], axis=1)
    a, b, c, d = grid[:-1], grid[1:], right[1:], right[:-1]
    quads = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices, np.concatenate([top, quads, bottom])


def write_files(folder: Path, profile: str) -> dict[str, Path]:
    """The generated files of ``profile`` in ``folder``: {name: path}."""
    binary, text, off = SIZES.get(profile, SIZES["quick"])
    files = {}
    vertices, faces = sphere(binary)
    corners = vertices[faces]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    records = np.zeros(len(faces), [("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
    records["normal"], records["corners"] = normals, corners
    files[f"sphere-{len(faces)}-binary.stl"] = b"generated sphere".ljust(80) + np.uint32(len(faces)).tobytes() + \
        records.tobytes()
    vertices, faces = sphere(text)
    rows = np.concatenate([normals_of(vertices, faces), vertices[faces].reshape(-1, 9)], axis=1)
    for style, number in (("e", "{:e}"), ("repr", "{!r}")):
        facet = _FACET.replace("{}", number)
        body = "".join(facet.format(*row) for row in rows.tolist())
        files[f"sphere-{len(faces)}-ascii-{style}.stl"] = ("solid sphere\n" + body + "endsolid sphere\n").encode()
    vertices, faces = sphere(off)
    lines = [f"OFF\n{len(vertices)} {len(faces)} 0\n"] + [f"{x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in vertices.tolist()]
    lines += [f"3 {a} {b} {c}\n" for a, b, c in faces.tolist()]
    files[f"sphere-{len(faces)}.off"] = "".join(lines).encode()
    paths = {}
    for name, data in files.items():
        (folder / name).write_bytes(data)
        paths[name] = folder / name
    return paths


def normals_of(vertices, faces):
    c = vertices[faces]
    n = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def _sides(path: Path, trimesh, numpy_stl) -> dict:
    reader = read_off if path.suffix.lower() == ".off" else read_stl
    sides = {RASTERKIT: partial(reader, path)}
    if trimesh is not None:
        sides["trimesh"] = partial(trimesh.load, path, process=False)
        if path.suffix.lower() == ".stl":  # trimesh's default: its corners merged, as rasterkit welds them
            sides["trimesh (welding)"] = partial(trimesh.load, path)
    if numpy_stl is not None and path.suffix.lower() == ".stl":
        sides["numpy-stl"] = partial(numpy_stl.mesh.Mesh.from_file, str(path))
    return sides


def _peer(peers, results, name: str):
    """The peer module ``name``, or None (with the reason recorded)."""
    try:
        if peers is not None:
            return peers.module(name)
        return __import__(name)
    except Exception as reason:  # noqa: BLE001 - PeerUnavailable or ImportError: recorded, not fatal
        results.skip(FAMILY, f"stl/off [{name}]", str(reason) or type(reason).__name__)
        return None


def run(settings, results, peers=None) -> None:
    """The public STL and OFF files and the generated ones, loaded by each side."""
    trimesh = _peer(peers, results, "trimesh")
    numpy_stl = _peer(peers, results, "stl")
    if numpy_stl is not None and not hasattr(numpy_stl, "mesh"):
        numpy_stl = None
    public = sorted((MODELS_DIR / "formats" / "stl").glob("*")) + sorted((MODELS_DIR / "formats" / "off").glob("*.off"))
    if not public:
        results.skip(FAMILY, "stl/off public files", f"{MODELS_DIR / 'formats'} not found")
    folder = Path(tempfile.mkdtemp(prefix="rasterkit-bench-formats-"))
    try:
        for path in public + list(write_files(folder, settings.name).values()):
            mib = path.stat().st_size / 2**20
            targets = {"trimesh (welding)": BINARY_TARGET} if path.name.endswith("-binary.stl") else None
            compare(results, FAMILY, f"loading/{path.name}", _sides(path, trimesh, numpy_stl),
                    repeat=settings.repeat, warmup=settings.warmup, sizes={"MiB": round(mib, 2)}, work=mib,
                    unit="MiB/s", targets=targets)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def main(argv: list[str]) -> int:
    settings = TINY if "--tiny" in argv else QUICK if "--quick" in argv else FULL
    results = Results()
    run(settings, results)
    print(f"{'workload':44s} {'rasterkit':>10s} {'MiB/s':>8s}  peer: time, ratio", flush=True)
    for r in results.records:
        speed = r.work / r.rasterkit if r.work else float("nan")
        peer = f"{r.peer} {r.peer_value * 1e3:.1f} ms, {r.ratio:.3f}x" if r.peer_value is not None else ""
        print(f"{r.name:44s} {r.rasterkit * 1e3:8.1f} ms {speed:8.1f}  {peer}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
