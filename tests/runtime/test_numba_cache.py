"""rasterkit.runtime.numba_cache: two processes saving different specializations of one
kernel at once never leave an index entry that names the other's data (Numba's own save can:
it takes the first free number and writes the index before the data)."""

from __future__ import annotations

import numba
import numpy as np
from numba.core.caching import IndexDataCacheFile

from rasterkit.runtime import numba_cache
from rasterkit.runtime.jit import kernel


def _files(folder, stale_second: bool):
    """Two processes' views of one kernel's cache files; the second's index reads can be stale
    (as read before the first saved)."""
    first = IndexDataCacheFile(str(folder), "kernel-1.py311", "stamp")
    second = IndexDataCacheFile(str(folder), "kernel-1.py311", "stamp")
    if stale_second:
        second._load_index = lambda: {}
    return first, second


def _interleaved(first, second, save):
    """The first process saves ``"a"``; between its index and data writes (Numba's order) or
    after its data, the second saves ``"b"`` from its (stale) index."""
    original = first._save_index

    def save_index_then_let_the_other_save(overloads):
        original(overloads)
        first._save_index = original
        save(second, ("sig b",), "code of b")

    first._save_index = save_index_then_let_the_other_save
    save(first, ("sig a",), "code of a")


def test_the_patch_is_installed_by_the_jit_policy():
    assert getattr(IndexDataCacheFile.save, "_rasterkit", False)
    assert numba_cache.install()  # once: installing again changes nothing
    assert IndexDataCacheFile.save.__wrapped__.__name__ == "save"


def test_numbas_own_save_mixes_entries_up_where_the_patched_one_does_not(tmp_path):
    numbas = IndexDataCacheFile.save.__wrapped__
    for save, folder in ((numbas, tmp_path / "numba"), (IndexDataCacheFile.save, tmp_path / "patched")):
        folder.mkdir()
        first, second = _files(folder, stale_second=True)
        _interleaved(first, second, save)
        reader = IndexDataCacheFile(str(folder), "kernel-1.py311", "stamp")
        loaded = {key: reader.load(key) for key in (("sig a",), ("sig b",))}
        if save is numbas:  # the index names "b", the file holds "a": the race this patch closes
            assert loaded[("sig b",)] == "code of a"
        else:  # each entry its own data, or none (to be compiled again): never the other's
            assert loaded[("sig a",)] in ("code of a", None) and loaded[("sig b",)] in ("code of b", None)
            assert loaded[("sig b",)] == "code of b"


def test_saves_one_after_another_keep_every_entry_and_a_key_keeps_its_file(tmp_path):
    first, second = _files(tmp_path, stale_second=False)
    first.save(("sig a",), "code of a")
    second.save(("sig b",), "code of b")
    second.save(("sig a",), "code of a, again")  # the same key: the same file, written over
    reader = IndexDataCacheFile(str(tmp_path), "kernel-1.py311", "stamp")
    assert reader.load(("sig a",)) == "code of a, again" and reader.load(("sig b",)) == "code of b"
    assert len(list(tmp_path.glob("*.nbc"))) == 2
    assert numba_cache.data_number(("sig a",)) != numba_cache.data_number(("sig b",))


def test_a_kernel_cached_by_one_process_loads_in_the_next(tmp_path, monkeypatch):
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(tmp_path))

    def twice(a):
        return a * 2

    for dtype in (np.int64, np.float64):  # two specializations of one function, two data files
        assert kernel(twice)(np.arange(3, dtype=dtype)).tolist() == [0, 2, 4]
    fresh = kernel(twice)  # a new dispatcher: what a new process has
    assert fresh(np.arange(3.0)).tolist() == [0.0, 2.0, 4.0]
    assert fresh.stats.cache_hits and not fresh.stats.cache_misses
