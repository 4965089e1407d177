"""Loading: OBJ (rasterkit.load_obj against trimesh and a line-by-line Python parser), then a
row per other format (:mod:`benchmarks.formats_stl_off`, :mod:`benchmarks.formats_ply`,
:mod:`benchmarks.formats_gltf`: each reader against trimesh and, where installed, numpy-stl
or plyfile).

trimesh loads with ``force='mesh', process=False`` (no merging or cleaning, like
rasterkit). The Python baseline is :func:`benchmarks.bench_obj.python_baseline`: ``v`` and
``f`` lines only, the speed of the obvious implementation. Each loader's work is the file
size, reported as MiB/s.
"""

from __future__ import annotations

from functools import partial

import rasterkit

from . import formats_gltf, formats_ply, formats_stl_off
from .bench_obj import python_baseline
from .compare import RASTERKIT, compare, start
from .settings import model_path

FAMILY = "loading"


def run(settings, results, peers) -> None:
    """Every model of ``settings``, loaded by each side."""
    trimesh = start(results, FAMILY, "trimesh", lambda: peers.module("trimesh"))
    for name in settings.models:
        path = model_path(name)
        if not path.is_file():
            results.skip(FAMILY, name, f"model file {path} not found")
            continue
        sides = {RASTERKIT: partial(rasterkit.load_obj, path),
                 "python line-by-line": partial(python_baseline, path)}
        if trimesh:
            sides["trimesh"] = partial(trimesh.load, path, force="mesh", process=False)
        mib = path.stat().st_size / 2**20
        compare(results, FAMILY, f"loading/{name}", sides, repeat=settings.repeat,
                warmup=settings.warmup, sizes={"MiB": round(mib, 2)}, work=mib, unit="MiB/s")
    formats_stl_off.run(settings, results, peers)  # its files are sized by the profile
    if settings.name == "tiny":  # their generated files take seconds to write and to read
        results.skip(FAMILY, "ply, gltf", "the tiny profile leaves out the PLY and glTF rows (files of 20-35 MiB)")
        return
    for other in (formats_ply, formats_gltf):
        other.run(settings, results, peers)
