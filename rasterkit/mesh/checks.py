"""The checks of a Mesh's arrays, and sealing them: what the constructor of
:class:`rasterkit.mesh.Mesh` calls on every array before the kernels may trust it.

Each check returns a C-contiguous array of the field's dtype (a new one or a view of the
argument) or raises ``TypeError`` (not numbers, not integers) or ``ValueError`` (shape, row
count, an index out of range, a colour outside [0, 1]) naming the field."""

from __future__ import annotations

import ctypes

import numpy as np

from rasterkit._arrays import real_array

__all__ = ["checked_array", "check_unit_colors", "corner_attributes", "corner_rows", "face_labels",
           "immutable", "seal", "sealed_empty", "side_flags", "vertex_indices"]


def checked_array(a, dtype, shape_tail, name, n_rows=None) -> np.ndarray:
    """``a`` as a C-contiguous array of ``dtype`` and shape ``(rows, *shape_tail)``, with
    ``n_rows`` rows when given."""
    arr = np.ascontiguousarray(real_array(a, name, dtype))
    if arr.ndim != 1 + len(shape_tail) or arr.shape[1:] != shape_tail:
        want = ", ".join(["N", *map(str, shape_tail)])
        raise ValueError(f"{name} must have shape ({want}), got {arr.shape}")
    if n_rows is not None and len(arr) != n_rows:
        raise ValueError(f"{name} must have {n_rows} rows, got {len(arr)}")
    return arr


def check_unit_colors(colors: np.ndarray, name: str) -> None:
    """ValueError unless every value of ``colors`` (float32) is finite and in [0, 1]."""
    if not colors.size:
        return
    finite = np.isfinite(colors)
    if not finite.all():
        row = int(np.argmin(finite.all(axis=1)))
        raise ValueError(f"{name}[{row}] is {colors[row].tolist()}: colours must be finite numbers in [0, 1]")
    low, high = float(colors.min()), float(colors.max())
    if low < 0.0 or high > 1.0:
        row = int(np.argmax(((colors < 0.0) | (colors > 1.0)).any(axis=1)))
        hint = " (divide 0-255 colours by 255)" if high > 1.0 else ""
        raise ValueError(f"{name}[{row}] is {colors[row].tolist()}: colours must lie in [0, 1]{hint}")


def immutable(arr) -> bool:
    """Whether ``arr`` is a read-only, C-contiguous, aligned view of a ``bytes`` object:
    memory that NumPy offers no way to write to (its ``WRITEABLE`` flag cannot be set
    again, on it or on any array made from it, and it cannot be resized)."""
    if not isinstance(arr, np.ndarray) or arr.flags.writeable or not (arr.flags.c_contiguous and arr.flags.aligned):
        return False
    base = arr
    while isinstance(base, np.ndarray):
        base = base.base
    return type(base) is bytes


def seal(arr: np.ndarray) -> np.ndarray:
    """``arr`` as an immutable array (:func:`immutable`): itself when it is one already,
    else a copy over a new ``bytes`` object (``arr`` stays as it was)."""
    if immutable(arr):
        return arr
    return np.frombuffer(np.ascontiguousarray(arr).tobytes(), dtype=arr.dtype).reshape(arr.shape)


def sealed_empty(shape, dtype) -> tuple[np.ndarray, np.ndarray]:
    """``(sealed, fill)``: a new immutable array (:func:`immutable`, zeros) and a writeable
    array over the same memory, for a reader to fill and then give the sealed one (or the
    first rows of it) to a :class:`~rasterkit.mesh.Mesh`, which keeps it as it is instead of
    copying it (:func:`seal`): a file's arrays are written once, not twice.

    The memory is that of a new ``bytes`` object, which nothing else can see yet; ``fill``
    writes into it through a ``ctypes`` view of its address (and keeps it alive). The reader
    must drop ``fill`` before the Mesh is made: nothing may write into a Mesh's arrays."""
    dtype = np.dtype(dtype)
    items = int(np.prod(shape, dtype=np.int64))
    size = items * dtype.itemsize
    # zeros, in pages the system gives on first touch; at least 2 bytes, since bytes() of 0
    # or 1 byte is a shared object, never to be written into
    memory = bytes(max(size, 2))
    sealed = np.frombuffer(memory, dtype, count=items).reshape(shape)
    view = (ctypes.c_char * size).from_address(sealed.__array_interface__["data"][0])
    view.memory = memory  # the writeable array keeps the bytes alive too
    return sealed, np.frombuffer(view, dtype).reshape(shape)


def side_flags(value, n_faces: int) -> np.ndarray:
    """(M,) uint8 ``Mesh.polygon_sides``: three bits a face."""
    flags = np.asarray(value)
    if flags.dtype.kind not in "iub":
        raise TypeError(f"polygon_sides must hold integers, got dtype {flags.dtype}")
    if flags.shape != (n_faces,) or (n_faces and (int(flags.min()) < 0 or int(flags.max()) > 7)):
        raise ValueError(f"polygon_sides must be ({n_faces},) integers in 0..7 (three side bits a face)")
    return np.ascontiguousarray(flags, np.uint8)


def _integers(a, width, name, bound, message) -> np.ndarray:
    """``a`` as an array of integers (``[]`` as an empty one of ``width`` columns); unsigned
    values of ``bound`` or more are refused with ``message`` before the conversion to int64
    could wrap them round to negative ones."""
    if a is None:
        raise TypeError(f"{name} must be an array of integers, got None")
    a = np.asarray(a)
    if a.size == 0 and a.dtype.kind in "iufO":  # [] is float64 to NumPy
        a = np.zeros((0, width), np.int64)
    if a.dtype.kind not in "iu":
        raise TypeError(f"{name} must hold integers, got dtype {a.dtype}")
    if a.dtype.kind == "u" and a.size and int(a.max()) >= bound:
        raise ValueError(message)
    return a


def vertex_indices(a, n_vertices, width, name) -> np.ndarray:
    """(K, width) int64 indices into ``n_vertices`` rows, each in [0, n_vertices)."""
    message = f"{name} index out of range [0, {n_vertices})"
    arr = checked_array(_integers(a, width, name, n_vertices, message), np.int64, (width,), name)
    if len(arr) and (arr.min() < 0 or arr.max() >= n_vertices):
        raise ValueError(message)
    return arr


def corner_rows(a, n_faces: int, n_rows: int, name: str, table: str) -> np.ndarray:
    """(M, 3) int64 rows of a per-corner table (``table``, of ``n_rows`` rows) for each face
    corner: each face's three in [0, n_rows), or all three -1 (the face has none)."""
    message = f"a face's corners are rows of {table} [0, {n_rows}), or -1, -1, -1 for a face without"
    arr = checked_array(_integers(a, 3, name, n_rows, f"{name} is out of range: {message}"), np.int64, (3,), name,
                        n_faces)
    if len(arr) and not (arr.min() >= 0 and arr.max() < n_rows):  # else each face has its rows
        a, b, c = arr.T  # columns: NumPy's reductions along a row of 3 are slow
        lo, hi = np.minimum(np.minimum(a, b), c), np.maximum(np.maximum(a, b), c)
        bad = ~(((lo >= 0) & (hi < n_rows)) | ((lo == -1) & (hi == -1)))
        if bad.any():
            f = int(np.argmax(bad))
            raise ValueError(f"{name}[{f}] is {arr[f].tolist()}: {message}")
    return arr


def face_labels(value, n_faces: int, n_names: int, name: str, names: str, none: bool) -> np.ndarray:
    """(M,) int32 index of each face into the tuple ``names`` (of ``n_names``), and -1 for
    a face with none where ``none`` allows it."""
    g = np.asarray(value)
    if g.dtype.kind not in "iu" and not (g.size == 0 and g.dtype.kind == "f"):
        raise TypeError(f"{name} must hold integers, got dtype {g.dtype}")
    low = -1 if none else 0
    if g.shape != (n_faces,) or (len(g) and (g.min() < low or g.max() >= n_names)):
        allowed = f"[{low}, {n_names})" if none else "indices"
        raise ValueError(f"{name} must be (M,) {allowed} into {names}" + (" (-1: none)" if none else ""))
    return np.ascontiguousarray(g, dtype=np.int32)


def corner_attributes(uv, uv_index, corner_normals, normal_index, faces: np.ndarray,
                      n_vertices: int) -> dict:
    """The checked per-corner arrays of a Mesh (``uv``, ``uv_index``, ``corner_normals``,
    ``normal_index``: only those it has), from its fields; ``faces`` checked already."""
    arrays = {}
    arrays.update(_table(uv, uv_index, "uv", "uv_index", 2, faces, n_vertices))
    arrays.update(_table(corner_normals, normal_index, "corner_normals", "normal_index", 3, faces, n_vertices))
    if "corner_normals" in arrays and not np.isfinite(arrays["corner_normals"]).all():
        normals = arrays["corner_normals"]
        row = int(np.argmin(np.isfinite(normals).all(axis=1)))
        raise ValueError(f"corner_normals[{row}] is {normals[row].tolist()}: normals must be finite")
    return arrays


def _table(values, rows, table: str, index: str, width: int, faces: np.ndarray, n_vertices: int) -> dict:
    """``{table: (T, width) float64, index: (M, 3) int64}`` checked, or ``{}`` without a
    table. A table given without its index holds one row per vertex, and its index is
    ``faces`` itself."""
    if values is None:
        if rows is not None:
            raise ValueError(f"{index} is given without {table}")
        return {}
    values = checked_array(values, np.float64, (width,), table)
    if rows is None:
        if len(values) != n_vertices:
            raise ValueError(f"{table} has {len(values)} rows and no {index}: without {index} it holds one row "
                             f"per vertex ({n_vertices}); a table of any size needs {index} (M, 3)")
        return {table: values, index: faces}
    return {table: values, index: corner_rows(rows, len(faces), len(values), index, table)}
