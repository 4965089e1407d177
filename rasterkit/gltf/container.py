"""The container of a glTF file: JSON text (``.gltf``) or the binary GLB (``.glb``), told apart
by their first bytes (:func:`sniff`), opened into a :class:`~rasterkit.gltf.document.Document`
(:func:`open_document`).

A GLB file is a 12-byte header (magic ``glTF``, version 2, total length), then chunks of
``(length, type, data)``: the first chunk is the JSON (type ``JSON``), an optional second one
the binary buffer (type ``BIN\\0``); chunks of other types are skipped. Every length is
checked against the file's size before it is used. A header length smaller than the file
leaves the rest unread (with a warning); a larger one is an error. The BIN chunk is kept as
a ``memoryview`` of the file's bytes: nothing is copied.

The JSON (UTF-8, a byte order mark allowed in a ``.gltf`` file) must be an object whose
``asset.version`` is ``2.x``: glTF 1.0 files are refused by name.
"""

from __future__ import annotations

import json
import os
import re
import struct

from rasterkit.gltf.document import Document, shown
from rasterkit.gltf.errors import GltfError, GltfLimitError
from rasterkit.runtime import files

__all__ = ["GLB_MAGIC", "open_document", "read_bytes", "sniff"]

GLB_MAGIC = b"glTF"
_JSON_CHUNK = 0x4E4F534A
_BIN_CHUNK = 0x004E4942
_HEADER = 12
_CHUNK_HEADER = 8

#: The keys of a glTF document's top-level object: JSON that opens with one of them is glTF.
_TOP_LEVEL = (b"asset", b"scene", b"scenes", b"nodes", b"meshes", b"accessors", b"bufferViews", b"buffers",
              b"materials", b"textures", b"images", b"samplers", b"cameras", b"skins", b"animations",
              b"extensionsUsed", b"extensionsRequired")
_FIRST_KEY = re.compile(rb'\s*\{\s*"(' + b"|".join(_TOP_LEVEL) + rb')"\s*:')
_ASSET = re.compile(rb'"asset"\s*:\s*\{[^{}]*"version"\s*:\s*"2\.')


def sniff(head: bytes) -> str | None:
    """``"glb"`` when ``head`` (the first bytes of a file: 64 are enough for most, a few
    hundred for JSON that opens with other keys) starts with the GLB magic ``glTF``;
    ``"gltf"`` for JSON whose first key is a glTF top-level key (``asset``, ``accessors``,
    ``nodes``...), or that holds ``"asset": {... "version": "2.`` within ``head``; else None.
    A UTF-8 byte order mark and white space before the ``{`` are allowed."""
    head = bytes(head)
    if head[:4] == GLB_MAGIC:
        return "glb"
    text = head.removeprefix(b"\xef\xbb\xbf")
    if _FIRST_KEY.match(text) or (text.lstrip()[:1] == b"{" and _ASSET.search(text)):
        return "gltf"
    return None


def read_bytes(path: str) -> bytes:
    """The bytes of the file ``path`` (:func:`rasterkit.runtime.files.read_file`), its errors
    as :class:`GltfError` (:class:`GltfLimitError` over the file size limit)."""
    try:
        return files.read_file(path)
    except files.FileLimitError as e:
        raise GltfLimitError(e.path, None, e.reason) from None
    except files.FileError as e:
        raise GltfError(e.path, None, e.reason) from None


def open_document(path: str) -> Document:
    """The :class:`Document` of the ``.gltf`` or ``.glb`` file ``path`` (told apart by the
    magic, whatever the extension)."""
    path = os.fsdecode(path)
    data = read_bytes(path)
    folder = os.path.dirname(os.path.abspath(path))
    warnings = []
    if data[:4] == GLB_MAGIC:
        text, binary, warnings = _glb_chunks(path, data)
        root = _json(path, bytes(text).rstrip(b"\x00"), glb=True)  # padded with NULs by some writers
    else:
        binary = None
        root = _json(path, data.removeprefix(b"\xef\xbb\xbf"), glb=False)
    doc = Document(path, folder, root, binary)
    doc.warnings.extend(warnings)
    _check_asset(doc)
    return doc


def _glb_chunks(path: str, data: bytes) -> tuple[memoryview, memoryview | None, list]:
    """``(json_bytes, bin_chunk or None, warnings)`` of a GLB file's bytes."""
    if len(data) < _HEADER:
        raise GltfError(path, "byte 0", f"a GLB file needs a 12-byte header, the file has {len(data)} bytes")
    _, version, length = struct.unpack_from("<4sII", data)
    if version != 2:
        raise GltfError(path, "byte 4", f"GLB version {version} is not supported (glTF 2.0 only)")
    warnings = []
    if length > len(data):
        raise GltfError(path, "byte 8", f"the header says the file has {length} bytes, it has {len(data)}")
    if length < len(data):
        warnings.append(f"byte {length}: {len(data) - length} bytes after the GLB's length ignored")
    view = memoryview(data)[:length]
    chunks, at = [], _HEADER
    while at < length:
        if length - at < _CHUNK_HEADER:
            raise GltfError(path, f"byte {at}", f"a chunk header needs 8 bytes, {length - at} are left")
        size, kind = struct.unpack_from("<II", view, at)
        start = at + _CHUNK_HEADER
        if size > length - start:
            raise GltfError(path, f"byte {at}", f"the chunk's length {size} goes past the end of the file "
                                                f"({length - start} bytes left)")
        chunks.append((kind, at, view[start:start + size]))
        at = start + size
    if not chunks or chunks[0][0] != _JSON_CHUNK:
        raise GltfError(path, f"byte {_HEADER}", "the first chunk of a GLB file must be its JSON")
    binary = chunks[1][2] if len(chunks) > 1 and chunks[1][0] == _BIN_CHUNK else None
    for k, (kind, at, _) in enumerate(chunks[1:], 1):
        if kind == _JSON_CHUNK or (kind == _BIN_CHUNK and k != 1):
            raise GltfError(path, f"byte {at}", "a GLB file has one JSON chunk and at most one BIN chunk, "
                                                "in that order")
    return chunks[0][2], binary, warnings


def _json(path: str, text, glb: bool):
    """The parsed JSON of ``text`` (bytes), errors at a byte (GLB) or line and column."""
    try:
        return json.loads(text.decode("utf-8"))
    except UnicodeDecodeError as e:
        where = f"byte {_HEADER + _CHUNK_HEADER + e.start}" if glb else f"byte {e.start}"
        raise GltfError(path, where, "the JSON is not UTF-8 text") from None
    except json.JSONDecodeError as e:
        where = f"byte {_HEADER + _CHUNK_HEADER + e.pos}" if glb else f"line {e.lineno} column {e.colno}"
        raise GltfError(path, where, f"invalid JSON: {e.msg}") from None
    except RecursionError:
        raise GltfError(path, None, "invalid JSON: nested too deeply") from None
    except ValueError as e:  # e.g. an integer of more digits than Python converts
        raise GltfError(path, None, f"invalid JSON: {' '.join(str(e).split())[:120]}") from None


def _check_asset(doc: Document) -> None:
    """Refuse what is not glTF 2.x (glTF 1.0 has another structure)."""
    asset = doc.root.obj("asset", None)
    if asset is None:
        raise doc.error("asset", "missing: not a glTF 2.0 file")
    version = asset.string("version")
    major = version.split(".")[0]
    if major != "2":
        raise doc.error("asset.version", f"glTF {shown(version)} is not supported (glTF 2.0 only)")
    minimum = asset.string("minVersion", None)
    if minimum is not None and minimum != "2.0":
        raise doc.error("asset.minVersion", f"this file needs glTF {shown(minimum)}, which is not supported "
                                            "(glTF 2.0 only)")
