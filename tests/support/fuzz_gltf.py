"""Fuzzing the glTF reader and the renders of what it reads.

The sources: small valid files made here (a textured quad with interleaved attributes, a
cut-out material and a sampler; a mesh of every primitive mode with normalized colours; a
sparse accessor, a node hierarchy of matrices and TRS, a camera and ``KHR_lights_punctual``
point, spot and directional lights, which the render then uses), and the small public glTF
and GLB files of ``../shared/models/formats`` when the folder is there. Each case is one of
them, mutated:

- **JSON**: 1-4 changes to the document's tree: a value (a count, an offset, an index, a
  matrix entry, a URI, a whole object...) replaced by a hostile one (negative, huge, 2**64,
  1e308, NaN, a string, null, a list, an object, ``../x.bin``, ``http:``, ``data:``), a key
  or list element deleted, a subtree copied from elsewhere in the document, a node made its
  own ancestor's child, an extension required; written back as GLB or ``.gltf``;
- **bytes**: 1-3 changes to the file's bytes (the GLB, or the ``.gltf`` text or its ``.bin``):
  bytes flipped, inserted, deleted, overwritten with large integers, the file truncated.

The oracle for each case: :func:`rasterkit.gltf.read_gltf` gives a scene, or raises a
:class:`~rasterkit.gltf.GltfError` whose message is one line naming the file; no Python
warning escapes; a scene's warnings are one line each; its world mesh is framed and drawn
solid at 48x32 (with its points), and its camera made when it has one, each succeeding or
raising a one-line ``ValueError``. Anything else (another exception, a crash, more than
``--example-seconds`` for one case, memory past the child's limit) is a failure; the case's
files are kept in ``--failures``.

Run by hand (a long run)::

    python tests/support/fuzz_gltf.py --cases 20000 --seed 1 --failures /tmp/fuzz-gltf

The suite runs a short, derandomized run of this script in a child process with a time and a
memory limit (``tests/gltf/test_fuzz_gltf.py``).
"""

from __future__ import annotations

import argparse
import copy
import faulthandler
import json
import math
import random
import shutil
import struct
import sys
import tempfile
import time
import warnings
from pathlib import Path

# paths of their own, not support.paths: this file also runs as a script
TESTS = Path(__file__).resolve().parents[1]
FORMATS = TESTS.parents[1] / "shared" / "models" / "formats"
#: Public files small enough to read many times a second.
SHARED = ("gltf/BoxTextured/BoxTextured.gltf", "gltf/BoxVertexColors/BoxVertexColors.gltf",
          "gltf/TextureCoordinateTest/TextureCoordinateTest.gltf", "glb/OrientationTest.glb",
          "glb/TextureSettingsTest.glb")
HOSTILE = [-1, 0, 1, 2, 3, 7, 255, 65536, 2**31, 2**32 + 1, 2**64, -(2**63), 10**30, 1e308, -1e308, 0.5, -0.0,
           math.nan, math.inf, "", "x", "0", "SCALAR", "VEC3", "MASK", None, True, False, [], {}, [0], [[]],
           {"a": 1}, [0, 0, 0, 0], "data:,", "data:;base64,@@", "../x.bin", "/etc/passwd", "http://x/y.bin",
           "a%00b.bin", "missing.bin", "nul\x00.png", 5120, 5126, 9728, 33071]


class Failure(Exception):
    """The oracle's verdict on one case."""


def check(path: Path) -> str:
    """Read ``path`` and render what it gives; returns "ok", "error" (a clean one-line error)
    or raises :class:`Failure`."""
    import numpy as np

    import rasterkit
    from rasterkit.gltf import GltfError, camera_of, read_gltf

    def clean(error: BaseException, what: str, reader: bool) -> str:
        text = str(error)
        wanted = GltfError if reader else ValueError
        if not isinstance(error, wanted):
            raise Failure(f"{what}: {type(error).__name__}: {text}") from error
        if "\n" in text or not text.strip():
            raise Failure(f"{what}: message not one line: {text!r}") from error
        if reader and not text.startswith(str(path)):
            raise Failure(f"{what}: message does not start with the file: {text!r}") from error
        return "error"

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            scene = read_gltf(path)
        except Exception as e:  # noqa: BLE001 - the oracle judges every exception
            return clean(e, "read_gltf", reader=True)
        for line in scene.warnings:
            if "\n" in line or not line.startswith(str(path)):
                raise Failure(f"read_gltf: a warning that is not one line naming the file: {line!r}")
        if not scene.objects:
            raise Failure("read_gltf: a scene without objects")
        try:
            center, radius = scene.bounding_sphere()
            camera = rasterkit.Camera.frame(center, max(radius, 1e-9), width=48, height=32)
            fb = rasterkit.render(scene, camera, "solid", points=scene.points)
            if scene.gltf_camera is not None:
                camera_of(scene, 48, 32)
        except Exception as e:  # noqa: BLE001
            return clean(e, "frame, render or camera_of", reader=False)
        if fb.color.shape[:2] != (32, 48) or fb.color.dtype != np.uint8:
            raise Failure(f"render: colour buffer {fb.color.shape} {fb.color.dtype}")
    return "ok"


# --- the sources ----------------------------------------------------------------------------

def made_sources() -> list:
    """``(json, bin, files)`` of the valid files made here (``files``: name -> bytes beside it)."""
    import numpy as np

    if str(TESTS) not in sys.path:
        sys.path.insert(0, str(TESTS))
    from support.gltffiles import GltfBuilder

    quad = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    b = GltfBuilder()
    pos, nor, tex = b.interleaved(quad, np.tile([0, 0, 1], (4, 1)), quad[:, :2])
    pixels = np.random.default_rng(0).integers(0, 256, (4, 4, 4), dtype=np.uint8)
    material = b.textured_material(b.image(pixels), {"wrapS": 33648, "minFilter": 9729}, alphaMode="MASK",
                                   alphaCutoff=0.3, doubleSided=True)
    idx = b.accessor(np.array([0, 1, 2, 0, 2, 3], np.uint16), np.uint16)
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos, "NORMAL": nor, "TEXCOORD_0": tex}, "indices": idx,
                                "material": material})))
    sources = [b]

    b = GltfBuilder()
    strip = np.array([[0, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0], [2, 0, 0], [2, 1, 0]], np.float32)
    pos = b.accessor(strip)
    colors = b.accessor(np.arange(24, dtype=np.uint8).reshape(6, 4) * 10, np.uint8, normalized=True)
    b.scene(b.node(mesh=b.mesh(*({"attributes": {"POSITION": pos, "COLOR_0": colors}, "mode": mode}
                                 for mode in range(7)))))
    sources.append(b)

    b = GltfBuilder()
    rows = b.view(np.array([1, 3], np.uint8).tobytes())
    values = b.view(np.array([[1, 1, 1], [2, 0, 1]], np.float32).tobytes())
    pos = b.accessor(quad, sparse={"count": 2, "indices": {"bufferView": rows, "componentType": 5121},
                                   "values": {"bufferView": values}})
    mesh = b.mesh({"attributes": {"POSITION": pos}, "indices": b.accessor(np.array([0, 1, 2, 2, 3, 0], np.uint32))})
    b.json["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]
    b.json["extensionsUsed"] = ["KHR_lights_punctual"]
    b.json["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "point"},
        {"type": "spot", "color": [1, 0.8, 0.5], "intensity": 20, "range": 9,
         "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.7}, "name": "spot"},
        {"type": "directional", "color": [2, 1, 0.5], "intensity": 0.5}]}}
    lit = lambda k: {"extensions": {"KHR_lights_punctual": {"light": k}}}  # noqa: E731
    leaf = b.node(mesh=mesh, rotation=[0, 0.6, 0, 0.8], scale=[1, 2, 1])
    cam = b.node(camera=0, translation=[0, 0, 5], **lit(0))
    spot = b.node(translation=[0, 0, 3], rotation=[0.1, 0, 0, 0.995], **lit(1))
    mid = b.node(children=[leaf, cam, spot], matrix=[2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1])
    b.scene(b.node(children=[mid], translation=[0, 1, 0]), b.node(mesh=mesh),
            b.node(rotation=[-0.5, 0, 0, 0.87], **lit(2)))
    sources.append(b)
    return [(b._document(None), bytes(b.bin), {}) for b in sources]


def shared_sources() -> list:
    """``(json, bin, files)`` of the small public files (their external files in ``files``)."""
    found = []
    for name in SHARED:
        path = FORMATS / name
        if not path.is_file():
            continue
        data = path.read_bytes()
        if data[:4] == b"glTF":
            n = struct.unpack_from("<I", data, 12)[0]
            binary = data[28 + n:] if len(data) > 28 + n else b""
            found.append((json.loads(data[20:20 + n]), binary, {}))
        else:
            files = {p.name: p.read_bytes() for p in path.parent.iterdir() if p != path}
            found.append((json.loads(data), b"", files))
    return found


# --- mutations ------------------------------------------------------------------------------

def _places(tree, out, depth=0):
    """Every (container, key) in ``tree``, for choosing a value to change."""
    items = tree.items() if isinstance(tree, dict) else enumerate(tree) if isinstance(tree, list) else ()
    for key, value in items:
        out.append((tree, key))
        if depth < 12:
            _places(value, out, depth + 1)
    return out


def mutate_json(doc: dict, rng: random.Random) -> dict:
    doc = copy.deepcopy(doc)
    for _ in range(rng.randint(1, 4)):
        places = _places(doc, [])
        if not places:
            break
        container, key = rng.choice(places)
        kind = rng.randrange(6)
        if kind <= 1:
            container[key] = copy.deepcopy(rng.choice(HOSTILE))
        elif kind == 2:
            del container[key]
        elif kind == 3:
            other, other_key = rng.choice(places)
            container[key] = copy.deepcopy(other[other_key]) if other is not container or other_key != key else []
        elif kind == 4 and isinstance(doc.get("nodes"), list) and doc["nodes"]:  # a cycle, or two parents
            nodes = doc["nodes"]
            k = rng.randrange(len(nodes))
            if isinstance(nodes[k], dict):
                nodes[k].setdefault("children", [])
                if isinstance(nodes[k]["children"], list):
                    nodes[k]["children"].append(rng.randrange(len(nodes)))
        else:
            doc["extensionsRequired"] = [rng.choice(["KHR_draco_mesh_compression", "KHR_materials_unlit",
                                                     "EXT_meshopt_compression", 7])]
    return doc


def mutate_bytes(data: bytes, rng: random.Random) -> bytes:
    data = bytearray(data)
    for _ in range(rng.randint(1, 3)):
        at = rng.randrange(len(data) + 1)
        kind = rng.randrange(5)
        if kind == 0 and data:
            data[min(at, len(data) - 1)] ^= 1 << rng.randrange(8)
        elif kind == 1:
            data[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        elif kind == 2:
            del data[at:at + rng.randint(1, 64)]
        elif kind == 3:
            data[at:at + 4] = struct.pack("<I", rng.choice([0, 1, 0xFFFFFFFF, 0x7FFFFFFF, 1 << 20, len(data)]))
        else:
            del data[at:]
    return bytes(data)


def glb_bytes(doc: dict, binary: bytes) -> bytes:
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
    if binary:
        binary = binary + bytes(-len(binary) % 4)
        chunks += struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def write_case(work: Path, source, rng: random.Random) -> Path:
    """One mutated case of ``source`` written in ``work`` (emptied first); its main file."""
    doc, binary, files = source
    for old in work.iterdir():
        old.unlink()
    for name, data in files.items():
        (work / name).write_bytes(data)
    if rng.random() < 0.6:
        doc = mutate_json(doc, rng)
    as_glb = binary or not files and rng.random() < 0.5
    if as_glb:
        data = glb_bytes(doc, binary)
        path = work / "case.glb"
    else:
        data = json.dumps(doc).encode()
        path = work / "case.gltf"
    if rng.random() < 0.4 or data == b"":
        if files and rng.random() < 0.5:
            name = rng.choice(sorted(files))
            (work / name).write_bytes(mutate_bytes(files[name], rng))
        else:
            data = mutate_bytes(data, rng)
    path.write_bytes(data)
    return path


# --- the run --------------------------------------------------------------------------------

class Runner:
    """Checks each case under a watchdog, counts and keeps failures."""

    def __init__(self, failures: Path | None, example_seconds: float):
        self.failures, self.seconds = failures, example_seconds
        self.counts = {"ok": 0, "error": 0, "failure": 0}

    def __call__(self, path: Path) -> None:
        # a hang (even inside a kernel, without the GIL) ends the process with a traceback;
        # the files that caused it are still in place
        faulthandler.dump_traceback_later(self.seconds, exit=True)
        try:
            verdict = check(path)
        except Failure as failure:
            verdict = "failure"
            self.keep(path, str(failure))
        finally:
            faulthandler.cancel_dump_traceback_later()
        self.counts[verdict] += 1

    def keep(self, path: Path, message: str) -> None:
        if self.failures is not None:
            kept = self.failures / f"failure-{self.counts['failure'] + 1:04d}"
            shutil.copytree(path.parent, kept)
            message = f"{kept.name}: {message}"
        print(f"FAILURE {message}", file=sys.stderr, flush=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=300, help="mutated files")
    parser.add_argument("--seed", type=int, default=0, help="random seed (a fixed run by default)")
    parser.add_argument("--failures", type=Path, default=None, help="folder to keep failing cases in")
    parser.add_argument("--example-seconds", type=float, default=20.0, help="time limit of one case")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    sources = made_sources()
    shared = shared_sources()
    sources += shared
    rng = random.Random(args.seed)
    runner = Runner(args.failures, args.example_seconds)
    with tempfile.TemporaryDirectory(prefix="rasterkit-fuzz-gltf-") as folder:
        work = Path(folder) / "case"
        work.mkdir()
        for source in sources:  # the sources themselves first: they must read and render
            path = work / "case.glb"
            for old in work.iterdir():
                old.unlink()
            for name, data in source[2].items():
                (work / name).write_bytes(data)
            if source[2]:
                path = work / "case.gltf"
                path.write_text(json.dumps(source[0]))
            else:
                path.write_bytes(glb_bytes(source[0], source[1]))
            if check(path) != "ok":
                print(f"FAILURE a source does not read: {path}", file=sys.stderr, flush=True)
                runner.counts["failure"] += 1
        for _ in range(args.cases):
            runner(write_case(work, rng.choice(sources), rng))
    total = sum(runner.counts.values())
    print(f"checked {total} files ({len(sources)} sources, {len(shared)} of them public files, {args.cases} "
          f"mutations) in {time.perf_counter() - start:.0f} s: {runner.counts['ok']} rendered, "
          f"{runner.counts['error']} clean errors, {runner.counts['failure']} failures", flush=True)
    return 1 if runner.counts["failure"] else 0


if __name__ == "__main__":
    sys.exit(main())
