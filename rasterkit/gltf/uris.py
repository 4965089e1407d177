"""The bytes a URI of a glTF file names (``buffers[i].uri``, ``images[i].uri``).

- ``data:`` URIs (``data:application/octet-stream;base64,...``) are decoded: base64 (strict:
  no white space, correct padding) or, without ``;base64``, percent-encoded bytes. The
  decoded size (three quarters of the text) is checked against the memory limit first.
- Any other URI is a file **relative to the folder of the glTF file**: percent-decoded
  (``my%20texture.png`` is ``my texture.png``; the bytes must be UTF-8), ``\\`` read as ``/``
  (files written on Windows), ``.`` and empty segments dropped, ``..`` allowed while it stays
  inside that folder. Refused, with one line naming the URI: absolute paths (``/etc/x``,
  ``C:\\x``), URIs with a scheme (``http:``, ``https:``, ``file:``...: nothing is fetched
  from the network, and ``file:`` names absolute paths), and paths that climb out of the
  folder (``../x.bin`` next to the model). The check is on the path as written: symbolic
  links inside the folder are followed, as any program reading the folder would.
- The file is read by :func:`rasterkit.runtime.files.read_file`: regular files only, within
  the file size limit.
"""

from __future__ import annotations

import binascii
import os
import re
from urllib.parse import unquote, unquote_to_bytes

from rasterkit.gltf.document import Document, shown
from rasterkit.gltf.errors import GltfError, GltfLimitError
from rasterkit.runtime import files

__all__ = ["local_path", "uri_bytes"]

_SCHEME = re.compile(r"^([A-Za-z][A-Za-z0-9+.\-]*):")


def uri_bytes(doc: Document, uri: str, where: str) -> bytes:
    """The bytes ``uri`` names (see the module documentation); errors at ``where``."""
    if uri[:5].lower() == "data:":
        return _data(doc, uri, where)
    path = local_path(doc, uri, where)
    try:
        return files.read_file(path)
    except files.FileLimitError as e:
        raise GltfLimitError(doc.path, where, f"{shown(uri)}: {e.reason}") from None
    except files.FileError as e:
        reason = e.reason.removeprefix("cannot read: ")
        raise GltfError(doc.path, where, f"cannot read {shown(uri)}: {reason}") from None


def local_path(doc: Document, uri: str, where: str) -> str:
    """The file that the relative URI ``uri`` names in the glTF file's folder."""
    scheme = _SCHEME.match(uri)
    if scheme and len(scheme.group(1)) > 1:
        raise doc.error(where, f"{shown(uri)}: only files beside the model are read, not {scheme.group(1)}: URIs")
    try:
        name = unquote(uri, errors="strict").replace("\\", "/")
    except UnicodeDecodeError:
        raise doc.error(where, f"{shown(uri)}: its percent-encoded bytes are not UTF-8") from None
    if scheme or name.startswith("/"):
        raise doc.error(where, f"{shown(uri)}: an absolute path (only paths relative to the model's folder "
                               "are read)")
    parts = []
    for part in name.split("/"):
        if part == "..":
            if not parts:
                raise doc.error(where, f"{shown(uri)}: leads outside the model's folder")
            parts.pop()
        elif part not in ("", "."):
            parts.append(part)
    if not parts:
        raise doc.error(where, f"{shown(uri)}: names no file")
    return os.path.join(doc.folder, *parts)


def _data(doc: Document, uri: str, where: str) -> bytes:
    comma = uri.find(",")
    if comma < 0:
        raise doc.error(where, "a data: URI without a ',' before its data")
    header, payload = uri[5:comma], uri[comma + 1:]
    doc.check_memory(len(payload), f"the data: URI of {where}", where)
    if header.lower().endswith(";base64"):
        try:
            return binascii.a2b_base64(payload.encode("ascii"), strict_mode=True)
        except (binascii.Error, UnicodeEncodeError) as e:
            raise doc.error(where, f"the data: URI's base64 is invalid ({' '.join(str(e).split())})") from None
    return unquote_to_bytes(payload)
