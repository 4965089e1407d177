"""Small glTF and GLB files made in a test, with known content: :class:`GltfBuilder` packs
arrays into one binary buffer (buffer views, accessors, sparse parts), takes meshes, nodes,
materials and images as plain JSON, and writes a ``.glb`` or a ``.gltf`` (with the buffer as
an external ``.bin`` or a ``data:`` URI).
"""

from __future__ import annotations

import base64
import io
import json
import struct
from pathlib import Path

import numpy as np

#: NumPy dtype -> glTF componentType.
COMPONENT = {np.dtype("i1"): 5120, np.dtype("u1"): 5121, np.dtype("i2"): 5122, np.dtype("u2"): 5123,
             np.dtype("u4"): 5125, np.dtype("f4"): 5126}
TYPE = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}


def png_bytes(pixels: np.ndarray) -> bytes:
    """A PNG file of (H, W, 3|4) uint8 ``pixels``."""
    from PIL import Image

    out = io.BytesIO()
    Image.fromarray(pixels).save(out, "PNG")
    return out.getvalue()


class GltfBuilder:
    """A glTF document under construction (``self.json``) and its one binary buffer."""

    def __init__(self):
        self.json = {"asset": {"version": "2.0"}}
        self.bin = bytearray()

    def table(self, name: str) -> list:
        return self.json.setdefault(name, [])

    def add(self, name: str, item: dict) -> int:
        self.table(name).append(item)
        return len(self.table(name)) - 1

    def view(self, data: bytes, stride: int | None = None) -> int:
        """A buffer view of ``data`` (4-byte aligned in the buffer)."""
        self.bin += bytes(-len(self.bin) % 4)
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if stride is not None:
            view["byteStride"] = stride
        self.bin += data
        return self.add("bufferViews", view)

    def accessor(self, array, dtype=None, normalized: bool = False, view: int | None = None, **extra) -> int:
        """An accessor of ``array`` ((N,) or (N, k)) stored as ``dtype`` in a view of its own
        (or in ``view``, with ``extra`` such as byteOffset, count, type)."""
        a = np.asarray(array)
        a = a.astype(dtype or (np.float32 if a.dtype.kind == "f" else np.uint32))
        width = 1 if a.ndim == 1 else a.shape[1]
        if view is None:
            view = self.view(np.ascontiguousarray(a).astype(a.dtype.newbyteorder("<")).tobytes())
        item = {"bufferView": view, "componentType": COMPONENT[a.dtype], "count": len(a), "type": TYPE[width]}
        if normalized:
            item["normalized"] = True
        item.update(extra)
        return self.add("accessors", {k: v for k, v in item.items() if v is not None})

    def interleaved(self, *arrays) -> list:
        """Accessors of float32 arrays (N, k_i) interleaved in one view with a byteStride."""
        arrays = [np.asarray(a, np.float32) for a in arrays]
        record = np.concatenate(arrays, axis=1)
        view = self.view(record.tobytes(), stride=record.shape[1] * 4)
        offsets = np.cumsum([0] + [a.shape[1] * 4 for a in arrays])
        return [self.accessor(a, view=view, byteOffset=int(o)) for a, o in zip(arrays, offsets)]

    def mesh(self, *primitives) -> int:
        return self.add("meshes", {"primitives": list(primitives)})

    def node(self, **fields) -> int:
        return self.add("nodes", fields)

    def scene(self, *nodes) -> None:
        self.json["scenes"] = [{"nodes": list(nodes)}]
        self.json["scene"] = 0

    def image(self, pixels: np.ndarray, uri: str | None = None, folder: Path | None = None) -> int:
        """An image from a buffer view, or the file ``uri`` written in ``folder``."""
        data = png_bytes(pixels)
        if uri is None:
            return self.add("images", {"bufferView": self.view(data), "mimeType": "image/png"})
        (folder / uri).write_bytes(data)
        return self.add("images", {"uri": uri})

    def textured_material(self, image: int, sampler: dict | None = None, **material) -> int:
        texture = {"source": image}
        if sampler is not None:
            texture["sampler"] = self.add("samplers", sampler)
        index = self.add("textures", texture)
        pbr = material.pop("pbr", {})
        return self.add("materials", {"pbrMetallicRoughness": {"baseColorTexture": {"index": index}, **pbr},
                                      **material})

    # --- writing ---------------------------------------------------------------------------

    def _document(self, uri: str | None) -> dict:
        doc = json.loads(json.dumps(self.json))
        if self.bin:
            buffer = {"byteLength": len(self.bin)}
            if uri is not None:
                buffer["uri"] = uri
            doc["buffers"] = [buffer]
        return doc

    def glb(self, json_text: bytes | None = None) -> bytes:
        text = json_text if json_text is not None else json.dumps(self._document(None)).encode()
        text += b" " * (-len(text) % 4)
        body = bytes(self.bin) + bytes(-len(self.bin) % 4)
        chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
        if self.bin:
            chunks += struct.pack("<II", len(body), 0x004E4942) + body
        return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks

    def write_glb(self, path: Path) -> Path:
        path.write_bytes(self.glb())
        return path

    def write_gltf(self, path: Path, bin_name: str | None = "buffer.bin") -> Path:
        """A ``.gltf`` with its buffer in ``bin_name`` beside it, or a ``data:`` URI (None)."""
        if bin_name is None:
            uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(self.bin)).decode()
        else:
            uri = bin_name
            (path.parent / bin_name).write_bytes(bytes(self.bin))
        path.write_text(json.dumps(self._document(uri)))
        return path


def triangle_builder() -> GltfBuilder:
    """One triangle (0,0,0), (1,0,0), (0,1,0), indexed, on one node of the default scene."""
    b = GltfBuilder()
    pos = b.accessor(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32))
    idx = b.accessor(np.array([0, 1, 2], np.uint16))
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos}, "indices": idx})))
    return b
