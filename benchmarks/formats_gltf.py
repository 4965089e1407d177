"""glTF loading: rasterkit.gltf.read_gltf against trimesh.

Files: the public glTF and GLB models of ``../shared/models/formats`` and a generated GLB of
about a million triangles (a wavy grid with normals and texture coordinates, written by
trimesh to the temporary folder once and kept). Sides: ``read_gltf(path)`` (the default
scene, every mesh node, textures decoded), ``trimesh.load(path)`` (its defaults; its images
are Pillow images decoded on first use), ``trimesh.load(path, process=False)``, and
``trimesh.load(path)`` with its materials' images decoded. Work: the file's MiB (for a
``.gltf``, its ``.bin`` and images too).

Both sides give float64 positions and int64 faces (converted from the file's float32 and
unsigned integers). rasterkit also reads the normals and texture coordinates as float64,
checks every index against the vertex count and every normal for NaN and infinities, flips
``v``, gives each face its material's colour and index, and makes a Mesh, which checks its
arrays and copies each into memory of its own (``rasterkit.mesh.checks.seal``): for the
generated grid that is 69 MiB of arrays touched twice, and fresh memory (page faults) is
most of the time on a busy machine.

Part of the ``loading`` family (:mod:`benchmarks.loading`); run on its own::

    python -m benchmarks.formats_gltf [--quick]
"""

from __future__ import annotations

import argparse
import tempfile
from functools import partial
from pathlib import Path

import numpy as np

from .compare import RASTERKIT, compare
from .settings import MODELS_DIR

FAMILY = "loading"
FORMATS = MODELS_DIR / "formats"
SHARED = ("gltf/BoxTextured/BoxTextured.gltf", "gltf/TextureCoordinateTest/TextureCoordinateTest.gltf",
          "glb/OrientationTest.glb", "glb/TextureSettingsTest.glb", "glb/CesiumMilkTruck.glb")
#: Side of the generated grid: 2 * (GRID - 1)**2 triangles.
GRID = 708


def big_glb(folder: Path | None = None) -> Path:
    """The generated GLB of 2 * (GRID - 1)**2 (999,698) triangles, made once."""
    path = (folder or Path(tempfile.gettempdir())) / f"rasterkit-bench-grid{GRID}.glb"
    if path.is_file():
        return path
    import trimesh

    u, v = np.meshgrid(np.linspace(0, 1, GRID), np.linspace(0, 1, GRID))
    vertices = np.column_stack([u.ravel() * 10, np.sin(u.ravel() * 20) * np.cos(v.ravel() * 20) * 0.3,
                                v.ravel() * 10])
    k = np.arange(GRID * GRID).reshape(GRID, GRID)[:-1, :-1].ravel()
    faces = np.concatenate([np.column_stack([k, k + GRID, k + 1]), np.column_stack([k + 1, k + GRID, k + GRID + 1])])
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    mesh.visual = trimesh.visual.TextureVisuals(uv=np.column_stack([u.ravel(), v.ravel()]))
    mesh.vertex_normals  # noqa: B018 - worked out now, so that the file has NORMAL
    path.write_bytes(trimesh.exchange.gltf.export_glb(trimesh.Scene(mesh), include_normals=True))
    return path


def _mib(path: Path) -> float:
    """The file's MiB, with the files beside a ``.gltf`` (its buffers and images)."""
    if path.suffix == ".gltf":
        return sum(p.stat().st_size for p in path.parent.iterdir() if p.is_file()) / 2**20
    return path.stat().st_size / 2**20


def _trimesh_decoded(trimesh, path: Path):
    """``trimesh.load(path)`` and its materials' images decoded: trimesh keeps a Pillow image
    that decodes on first use, which a renderer makes at once (as read_gltf does)."""
    scene = trimesh.load(path)
    for geometry in scene.geometry.values():
        material = getattr(geometry.visual, "material", None)
        image = getattr(material, "baseColorTexture", None) if material is not None else None
        if image is not None:
            np.asarray(image)
    return scene


def run(settings, results, peers=None) -> None:
    """Each file, read by each side."""
    from rasterkit.gltf import read_gltf

    try:
        import trimesh
    except ImportError as e:
        results.skip(FAMILY, "gltf against trimesh", f"trimesh not installed: {e}")
        trimesh = None
    paths = [FORMATS / name for name in SHARED]
    if trimesh is not None:
        paths.append(big_glb())
    for path in paths:
        if not path.is_file():
            results.skip(FAMILY, path.name, f"model file {path} not found")
            continue
        scene = read_gltf(path)
        triangles = sum(len(o.mesh.faces) for o in scene.objects)
        sides = {RASTERKIT: partial(read_gltf, path)}
        if trimesh is not None:
            sides["trimesh"] = partial(trimesh.load, path)
            sides["trimesh process=False"] = partial(trimesh.load, path, process=False)
            sides["trimesh + images decoded"] = partial(_trimesh_decoded, trimesh, path)
        mib = _mib(path)
        compare(results, FAMILY, f"loading/gltf/{path.name}", sides, repeat=settings.repeat, warmup=settings.warmup,
                sizes={"MiB": round(mib, 2), "triangles": triangles}, work=mib, unit="MiB/s")


def main(argv=None) -> int:
    from . import report
    from .settings import FULL, QUICK

    parser = argparse.ArgumentParser(description="glTF loading: rasterkit against trimesh")
    parser.add_argument("--quick", action="store_true", help="fewer runs")
    args = parser.parse_args(argv)
    results = report.Results()
    run(QUICK if args.quick else FULL, results)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
