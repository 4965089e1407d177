"""Reading the files of a model: every file :func:`rasterkit.load_obj` opens (the ``.obj`` and
each ``mtllib`` library) is read by :func:`read_file`: rasterkit's one reader of input files,
:func:`rasterkit.runtime.files.read_file` (regular files only, within the file size limit), with its
errors as the loader's :class:`~rasterkit.obj.ObjError`.
"""

from __future__ import annotations

from rasterkit.runtime import files as _files
from rasterkit.obj.errors import ObjError, ObjLimitError

__all__ = ["read_file"]


def read_file(name: str) -> bytes:
    """The bytes of the regular file ``name``, at most :func:`~rasterkit.limits.max_file_size`
    of them (:func:`rasterkit.runtime.files.read_file`).

    Raises
    ------
    ObjError
        One line naming the file: it cannot be opened (``cannot read: No such file or
        directory``), it is not a regular file, or (an ``ObjLimitError``, also a
        ``LimitError``) it is larger than the limit.
    """
    try:
        return _files.read_file(name)
    except _files.FileLimitError as e:
        raise ObjLimitError(e.path, None, e.reason) from None
    except _files.FileError as e:
        raise ObjError(e.path, None, e.reason) from None
