"""Buffers and buffer views: the bytes accessors and images read, each range checked.

A buffer is the GLB's BIN chunk (``buffers[0]`` without a ``uri`` in a ``.glb`` file), a
``data:`` URI or a file beside the model (:mod:`rasterkit.gltf.uris`); it is read when first
used, once, and kept as a ``memoryview`` of its ``byteLength`` bytes (a buffer whose data are
shorter is an error; the GLB chunk's up to 3 bytes of padding are left out). A buffer view
is a ``memoryview`` of its buffer's bytes ``byteOffset`` to ``byteOffset + byteLength``,
checked to lie inside it, and its ``byteStride`` (4 to 252) when it has one. Nothing is
copied.
"""

from __future__ import annotations

from dataclasses import dataclass

from rasterkit.gltf.document import Document
from rasterkit.gltf.uris import uri_bytes

__all__ = ["View", "buffer", "buffer_view"]


@dataclass(frozen=True)
class View:
    """A checked buffer view: its ``data`` (a ``memoryview``), ``stride`` (bytes from one
    element to the next, or None: tightly packed) and ``where`` (``bufferViews[i]``)."""

    data: memoryview
    stride: int | None
    where: str


def buffer(doc: Document, index: int) -> memoryview:
    """The bytes of ``buffers[index]`` (an index already checked), read once."""
    key = ("buffer", index)
    if key not in doc.cache:
        doc.cache[key] = _read_buffer(doc, index)
    return doc.cache[key]


def _read_buffer(doc: Document, index: int) -> memoryview:
    b = doc.item("buffers", index)
    length = b.int("byteLength", low=1)
    uri = b.string("uri", None)
    if uri is None:
        if doc.binary is None:
            raise doc.error(b.where, "has no uri, and the file has no GLB binary chunk")
        if index != 0:
            raise doc.error(b.where, "has no uri (only buffers[0] of a .glb file is its binary chunk)")
        data = doc.binary
        source = "the GLB's binary chunk"
    else:
        data = memoryview(uri_bytes(doc, uri, b.path("uri")))
        doc.spent += len(data)
        source = "its data" if uri[:5].lower() == "data:" else "its file"
    if len(data) < length:
        raise doc.error(b.path("byteLength"), f"{length} bytes, but {source} holds only {len(data)}")
    return data[:length]


def buffer_view(doc: Document, index: int) -> View:
    """The checked ``bufferViews[index]`` (an index already checked), made once."""
    key = ("view", index)
    if key not in doc.cache:
        v = doc.item("bufferViews", index)
        b = v.ref("buffer", "buffers")
        data = buffer(doc, b)
        offset = v.int("byteOffset", 0)
        length = v.int("byteLength", low=1)
        if offset + length > len(data):
            raise doc.error(v.where, f"bytes {offset} to {offset + length} go past the end of buffers[{b}] "
                                     f"({len(data)} bytes)")
        stride = v.int("byteStride", None, low=4, high=252)
        doc.cache[key] = View(data[offset:offset + length], stride, v.where)
    return doc.cache[key]
