"""The JSON of one glTF file, read through typed getters: :class:`Document` (the whole file,
its GLB binary chunk, its warnings and its memory budget) and :class:`Obj` (one JSON object
and its path in the file).

JSON gives any value any type: ``"count": "12"``, ``"count": -1``, ``"count": 1e300``,
``"children": {}``. Every value the reader uses is taken through a getter of :class:`Obj`,
which checks its type and range and raises a :class:`~rasterkit.gltf.GltfError` naming its
JSON path (``accessors[3].count: must be an integer from 1, got -1``); a reference to
another table (``"indices": 7``) is checked to be an index of that table. Booleans are not
numbers here (JSON ``true`` is not ``1``), and numbers must be finite.
"""

from __future__ import annotations

import math

from rasterkit.gltf.errors import GltfError, GltfLimitError
from rasterkit.limits import LimitError, check_memory, memory_limit

__all__ = ["Document", "MISSING", "Obj"]

#: A getter's default when the key is required.
MISSING = object()

#: Longest JSON value quoted whole in a message.
_QUOTE = 40

#: Warnings kept of one file; the others are counted (:attr:`Document.dropped`).
MAX_WARNINGS = 50


def shown(value) -> str:
    """A JSON value for a one-line message: its ``repr``, shortened."""
    if isinstance(value, dict):
        return "an object"
    if isinstance(value, list):
        return f"a list of {len(value)}"
    text = repr(value)
    return text if len(text) <= _QUOTE else text[: _QUOTE - 3] + "..."


def _is_int(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class Document:
    """One glTF file: ``path`` (as given), ``folder`` (where its URIs are resolved),
    ``root`` (its JSON object, an :class:`Obj`), ``binary`` (the GLB's BIN chunk, a
    ``memoryview``, or None), ``warnings`` (one-line strings, the first
    :data:`MAX_WARNINGS` different ones; ``dropped`` counts the others) and ``spent`` (bytes
    of the buffers and arrays held so far, counted against the memory limit)."""

    def __init__(self, path: str, folder: str, root, binary: memoryview | None):
        self.path = path
        self.folder = folder
        self.binary = binary
        self.warnings: list[str] = []
        self.dropped = 0
        self.spent = 0
        self.limit = memory_limit()  # read once: it reads the environment
        self.cache: dict = {}  # what was read once: buffers, images, materials, meshes
        self.textures = True  # whether materials' images are read (read_gltf's textures)
        if not isinstance(root, dict):
            raise self.error(None, f"the JSON must be an object, got {shown(root)}")
        self.root = Obj(self, root, "")

    def error(self, where: str | None, reason: str) -> GltfError:
        return GltfError(self.path, where, reason)

    def warn(self, where: str | None, message: str) -> None:
        """Note a warning, ``where: message`` (the file's name is added by the reader)."""
        text = message if where is None else f"{where}: {message}"
        if text in self.warnings:
            return
        if len(self.warnings) < MAX_WARNINGS:
            self.warnings.append(text)
        else:
            self.dropped += 1

    def check_memory(self, nbytes: float, what: str, where: str | None) -> None:
        """:func:`rasterkit.limits.check_memory` of ``nbytes`` more than :attr:`spent`, as a
        :class:`GltfLimitError` at ``where``."""
        if self.spent + nbytes <= self.limit:
            return
        try:
            check_memory(self.spent + nbytes, what)
        except LimitError as e:
            raise GltfLimitError(self.path, where, str(e)) from None

    def table(self, name: str) -> list:
        """The top-level list ``name`` (empty when absent)."""
        return self.root.list(name, [])

    def item(self, name: str, index: int) -> Obj:
        """The object ``name[index]`` (``index`` already checked by :meth:`Obj.ref`)."""
        where = f"{name}[{index}]"
        value = self.table(name)[index]
        if not isinstance(value, dict):
            raise self.error(where, f"must be an object, got {shown(value)}")
        return Obj(self, value, where)


class Obj:
    """One JSON object of the file and its path (``where``); the getters check each value."""

    __slots__ = ("doc", "value", "where")

    def __init__(self, doc: Document, value: dict, where: str):
        self.doc, self.value, self.where = doc, value, where

    def path(self, key: str) -> str:
        return key if not self.where else f"{self.where}.{key}"

    def has(self, key: str) -> bool:
        return key in self.value

    def _get(self, key: str, default):
        if key in self.value:
            return self.value[key]
        if default is MISSING:
            raise self.doc.error(self.path(key), "missing")
        return default

    def _bad(self, key: str, wanted: str, value) -> GltfError:
        return self.doc.error(self.path(key), f"must be {wanted}, got {shown(value)}")

    def int(self, key: str, default=MISSING, low: int = 0, high: int | None = None):
        """An integer from ``low`` to ``high`` (inclusive; None: no upper bound)."""
        value = self._get(key, default)
        if value is default and key not in self.value:
            return value
        if not _is_int(value) or value < low or (high is not None and value > high):
            span = f"from {low}" if high is None else f"from {low} to {high}"
            raise self._bad(key, f"an integer {span}", value)
        return value

    def number(self, key: str, default=MISSING, low: float = -math.inf, high: float = math.inf):
        """A finite number from ``low`` to ``high``, as a float."""
        value = self._get(key, default)
        if value is default and key not in self.value:
            return value
        if not _is_number(value) or not math.isfinite(value) or not low <= value <= high:
            raise self._bad(key, "a finite number" if math.isinf(low) and math.isinf(high)
                            else f"a number from {low:g} to {high:g}", value)
        return float(value)

    def numbers(self, key: str, lengths: tuple, default=MISSING):
        """A list of finite numbers whose length is one of ``lengths``, as a tuple of floats."""
        value = self._get(key, default)
        if value is default and key not in self.value:
            return value
        if not isinstance(value, list) or len(value) not in lengths or \
                not all(_is_number(v) and math.isfinite(v) for v in value):
            counts = " or ".join(map(str, lengths))
            raise self._bad(key, f"a list of {counts} finite numbers", value)
        return tuple(float(v) for v in value)

    def string(self, key: str, default=MISSING):
        value = self._get(key, default)
        if value is default and key not in self.value:
            return value
        if not isinstance(value, str):
            raise self._bad(key, "a string", value)
        return value

    def flag(self, key: str, default=MISSING) -> bool:
        value = self._get(key, default)
        if not isinstance(value, bool):
            raise self._bad(key, "true or false", value)
        return value

    def list(self, key: str, default=MISSING) -> list:
        value = self._get(key, default)
        if value is default and key not in self.value:
            return value
        if not isinstance(value, list):
            raise self._bad(key, "a list", value)
        return value

    def obj(self, key: str, default=MISSING):
        """The object under ``key`` as an :class:`Obj` (``default`` when absent)."""
        value = self._get(key, default)
        if value is default and key not in self.value:
            return value
        if not isinstance(value, dict):
            raise self._bad(key, "an object", value)
        return Obj(self.doc, value, self.path(key))

    def objects(self, key: str) -> list:
        """The list of objects under ``key`` (required), each an :class:`Obj`."""
        where = self.path(key)
        found = []
        for k, value in enumerate(self.list(key)):
            if not isinstance(value, dict):
                raise self.doc.error(f"{where}[{k}]", f"must be an object, got {shown(value)}")
            found.append(Obj(self.doc, value, f"{where}[{k}]"))
        return found

    def ref(self, key: str, table: str, default=MISSING):
        """An index into the top-level list ``table``."""
        value = self._get(key, default)
        if value is default and key not in self.value:
            return value
        return self._index(self.path(key), value, table)

    def refs(self, key: str, table: str) -> list:
        """A list (``[]`` when absent) of indices into the top-level list ``table``."""
        where = self.path(key)
        return [self._index(f"{where}[{k}]", v, table) for k, v in enumerate(self.list(key, []))]

    def _index(self, where: str, value, table: str) -> int:
        size = len(self.doc.table(table))
        if not _is_int(value) or not 0 <= value < size:
            have = f"{table} has {size} entries" if size else f"there are no {table}"
            raise self.doc.error(where, f"must be an index of {table} ({have}), got {shown(value)}")
        return value

    def keys(self):
        return self.value.keys()
