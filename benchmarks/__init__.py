"""rasterkit's benchmark suite: ``python -m benchmarks`` from the repository root.

One module per workload family (:mod:`.render`, :mod:`.fill`, :mod:`.lines2d`,
:mod:`.loading`, :mod:`.scaling`, :mod:`.memory`, :mod:`.cli` with its peer script
``peer_cli.py``, :mod:`.startup`, :mod:`.contention`); the profiles in :mod:`.settings`;
one timing loop (:mod:`.timing`) that :func:`.compare.compare` runs for every workload; the
peers (:mod:`.peers`); the writers of ``results.json``, ``results.md`` and the PNG plots
(:mod:`.report`). See ``README.md``.
"""
