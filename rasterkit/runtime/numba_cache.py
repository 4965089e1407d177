"""Numba's on-disk cache made safe for processes that compile at the same time.

Numba saves a compiled specialization as a data file named by the first number its index does
not use, and writes the index before the data. Two processes that compile different
specializations of one kernel at once (two test workers, a batch's workers, a render and its
warm helpers on a cold cache) can both take the same number: one's index entry can then name
the other's data, and a later process loads machine code compiled for other argument types
(wrong pixels or a crash): Numba checks nothing on load.

Patched here (once, before anything compiles, from :mod:`rasterkit.runtime.jit`): a data file
is named by a hash of its own key (signature, target, and the function's code), so two keys
never share one; the data is written before the index, and the index is read again just
before it is written, so that it adds to what others saved meanwhile. A save that still
loses a concurrent one's entry (both rewrote the index at once) costs that specialization a
compile in a later process, never a wrong load.
"""

from __future__ import annotations

import functools
import hashlib
import pickle


def data_number(key) -> int:
    """The number in the data file name of cache entry ``key``: 60 bits of its hash."""
    return int(hashlib.sha256(pickle.dumps(key, protocol=4)).hexdigest()[:15], 16)


def install() -> bool:
    """Patch ``numba.core.caching.IndexDataCacheFile.save`` (once); whether it is patched."""
    try:
        from numba.core.caching import IndexDataCacheFile
    except ImportError:
        return False
    save = getattr(IndexDataCacheFile, "save", None)
    if getattr(save, "_rasterkit", False):
        return True
    needed = ("_load_index", "_save_index", "_save_data", "_data_name")
    if save is None or not all(callable(getattr(IndexDataCacheFile, name, None)) for name in needed):
        return False

    @functools.wraps(save)
    def keyed_save(self, key, data):
        data_name = self._data_name(data_number(key))
        self._save_data(data_name, data)
        overloads = self._load_index()  # what was saved meanwhile stays
        overloads[key] = data_name
        self._save_index(overloads)

    keyed_save._rasterkit = True
    IndexDataCacheFile.save = keyed_save
    return True
