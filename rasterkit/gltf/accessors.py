"""Accessors: typed, strided arrays over buffer views, read with NumPy without a Python loop.

An accessor's elements are ``count`` rows of ``SCALAR`` (1), ``VEC2``, ``VEC3`` or ``VEC4``
components of one type (byte, unsigned byte, short, unsigned short, unsigned int, float;
little-endian), starting ``byteOffset`` bytes into its buffer view, one every ``byteStride``
bytes of the view (tightly packed without one). Before any array is made, the last byte of
the last element is checked to lie inside the view (and the view inside its buffer:
:mod:`rasterkit.gltf.buffers`); then the array is a strided, read-only NumPy view of the
file's bytes (``np.ndarray(buffer=..., strides=...)``), copied once when it is converted.

- ``normalized`` integers are read as fractions: unsigned ``c / max``, signed
  ``max(c / max, -1)`` (glTF's rule); integers that are not normalized keep their values
  (``KHR_mesh_quantization`` positions, for example).
- An accessor without a ``bufferView`` is zeros (its ``count`` checked against the memory
  limit first), to be filled by its ``sparse`` part.
- ``sparse``: ``count`` indices (unsigned byte, short or int, tightly packed) and as many
  values replace those elements of the dense array (or of the zeros); each index is checked
  to be below the accessor's ``count``.
- ``min`` and ``max`` are ignored (they are often wrong, and the arrays are read anyway).
- Matrix types (``MAT2``..``MAT4``) and the component type 5124 are not used by any
  attribute read here: an accessor of another type than its use needs is an error.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.gltf.buffers import buffer_view
from rasterkit.gltf.document import Document, Obj
from rasterkit.mesh.checks import sealed_empty

__all__ = ["Accessor", "COMPONENTS", "FLOAT", "INDEX_COMPONENTS", "TYPES", "floats", "indices", "read"]

FLOAT = 5126
#: componentType -> (NumPy dtype, the largest value: the divisor of a normalized integer).
COMPONENTS = {5120: (np.dtype("i1"), 127), 5121: (np.dtype("u1"), 255), 5122: (np.dtype("<i2"), 32767),
              5123: (np.dtype("<u2"), 65535), 5125: (np.dtype("<u4"), 4294967295), FLOAT: (np.dtype("<f4"), None)}
#: The component types of indices (of a primitive, and of a sparse accessor).
INDEX_COMPONENTS = (5121, 5123, 5125)
#: type -> components per element.
TYPES = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


@dataclass(frozen=True)
class Accessor:
    """The checked header of an accessor."""

    where: str  # accessors[i]
    count: int
    type: str
    width: int  # components per element
    component: int  # componentType
    dtype: np.dtype
    normalized: bool


def header(doc: Document, index: int) -> Accessor:
    a = doc.item("accessors", index)
    component = a.int("componentType")
    if component not in COMPONENTS:
        raise doc.error(a.path("componentType"), f"{component} is not a glTF 2.0 component type "
                                                 f"({', '.join(map(str, COMPONENTS))})")
    kind = a.string("type")
    if kind not in TYPES:
        raise doc.error(a.path("type"), f"{kind!r} is not an accessor type ({', '.join(TYPES)})")
    return Accessor(a.where, a.int("count", low=1), kind, TYPES[kind], component, COMPONENTS[component][0],
                    a.flag("normalized", False))


def read(doc: Document, index: int, use: str, types: tuple, components: tuple = tuple(COMPONENTS)):
    """``(array, header)``: the elements of ``accessors[index]`` as a (count, width) array of
    its component type (read-only, possibly a strided view of the file's bytes), refused
    unless its type is one of ``types`` and its componentType one of ``components``; ``use``
    (the JSON path that names the accessor) is named in those errors."""
    acc = header(doc, index)
    if acc.type not in types or acc.component not in components:
        wanted = " or ".join(types)
        kinds = ", ".join(map(str, components))
        raise doc.error(use, f"{acc.where} is {acc.type} of componentType {acc.component}; this needs {wanted} "
                             f"of componentType {kinds}")
    a = doc.item("accessors", index)
    array = _dense(doc, acc, a)
    sparse = a.obj("sparse", None)
    if sparse is not None:
        array = _sparse(doc, acc, sparse, array)
    return array, acc


def floats(doc: Document, index: int, use: str, types: tuple, components: tuple = tuple(COMPONENTS),
           sealed: bool = False, flip_v: bool = False):
    """``(array, header)``: :func:`read` converted to float64, normalized integers as
    fractions (see the module documentation); ``sealed``: into sealed memory
    (:func:`rasterkit.mesh.checks.sealed_empty`, read-only), which a Mesh keeps as it is;
    ``flip_v``: the second column ``1 - v`` (texture coordinates: glTF's ``v`` runs down the
    image, rasterkit's up)."""
    raw, acc = read(doc, index, use, types, components)
    doc.check_memory(raw.size * 16, f"{acc.count} elements of {acc.where}", acc.where)
    result, out = sealed_empty(raw.shape, np.float64) if sealed else (None, np.empty(raw.shape, np.float64))
    with np.errstate(invalid="ignore"):  # a signalling NaN in the file becomes a quiet one
        np.copyto(out, raw, casting="unsafe")
    divisor = COMPONENTS[acc.component][1]
    if acc.normalized and divisor is not None:
        out /= divisor
        if acc.dtype.kind == "i":
            np.maximum(out, -1.0, out=out)
    if flip_v:
        np.subtract(1.0, out[:, 1], out=out[:, 1])
    return (out if result is None else result), acc


def indices(doc: Document, index: int, use: str, n_vertices: int) -> np.ndarray:
    """The (count,) int64 vertex indices of ``accessors[index]`` (SCALAR, unsigned), each
    below ``n_vertices`` (checked on the file's integers, before they are widened)."""
    raw, acc = read(doc, index, use, ("SCALAR",), INDEX_COMPONENTS)
    if acc.normalized:
        raise doc.error(use, f"{acc.where}: indices cannot be normalized")
    doc.check_memory(raw.size * 16, f"{acc.count} indices of {acc.where}", acc.where)
    column = raw[:, 0]
    largest = int(column.max())
    if largest >= n_vertices:
        raise doc.error(use, f"index {largest} >= the vertex count {n_vertices}")
    widened, out = sealed_empty(column.shape, np.int64)  # sealed: a Mesh keeps it as its faces
    np.copyto(out, column, casting="unsafe")
    return widened


def _view_span(doc: Document, where: str, view_index: int, offset: int, count: int, size: int, stride: int | None):
    """The checked buffer view of ``count`` elements of ``size`` bytes every ``stride``
    (None: the view's own, else ``size``) from ``offset``: ``(data, stride)``."""
    view = buffer_view(doc, view_index)
    step = stride if stride is not None else (view.stride or size)
    if step < size:
        raise doc.error(f"{view.where}.byteStride", f"{step} bytes, less than the {size} bytes of an element "
                                                    f"of {where}")
    end = offset + (count - 1) * step + size
    if end > len(view.data):
        raise doc.error(where, f"{count} elements of {size} bytes every {step} from byte {offset} need "
                               f"{end} bytes, {view.where} has {len(view.data)}")
    return view.data, step


def _dense(doc: Document, acc: Accessor, a: Obj) -> np.ndarray:
    itemsize = acc.dtype.itemsize
    size = acc.width * itemsize
    view_index = a.ref("bufferView", "bufferViews", None)
    offset = a.int("byteOffset", 0)
    if view_index is None:
        doc.check_memory(2 * acc.count * size, f"the {acc.count} zeros of {acc.where}", acc.where)
        zeros = np.zeros((acc.count, acc.width), acc.dtype)
        zeros.flags.writeable = False
        return zeros
    data, step = _view_span(doc, acc.where, view_index, offset, acc.count, size, None)
    return np.ndarray((acc.count, acc.width), acc.dtype, buffer=data, offset=offset, strides=(step, itemsize))


def _sparse(doc: Document, acc: Accessor, sparse: Obj, dense: np.ndarray) -> np.ndarray:
    """``dense`` (a copy) with the elements that ``sparse`` replaces."""
    n = sparse.int("count", low=1, high=acc.count)
    places = sparse.obj("indices")
    component = places.int("componentType")
    if component not in INDEX_COMPONENTS:
        raise doc.error(places.path("componentType"), f"{component} is not an index component type "
                                                      f"({', '.join(map(str, INDEX_COMPONENTS))})")
    dtype = COMPONENTS[component][0]
    offset = places.int("byteOffset", 0)
    data, _ = _view_span(doc, places.where, places.ref("bufferView", "bufferViews"), offset, n, dtype.itemsize,
                         dtype.itemsize)
    rows = np.frombuffer(data, dtype, n, offset)
    if n and int(rows.max()) >= acc.count:
        raise doc.error(places.where, f"index {int(rows.max())} >= the accessor's count {acc.count}")
    values = sparse.obj("values")
    size = acc.width * acc.dtype.itemsize
    offset = values.int("byteOffset", 0)
    data, _ = _view_span(doc, values.where, values.ref("bufferView", "bufferViews"), offset, n, size, size)
    doc.check_memory(2 * dense.nbytes, f"the sparse elements of {acc.where}", acc.where)
    out = np.array(dense)
    out[rows] = np.frombuffer(data, acc.dtype, n * acc.width, offset).reshape(n, acc.width)
    out.flags.writeable = False
    return out
