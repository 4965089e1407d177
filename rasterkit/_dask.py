"""Batches on a Dask cluster (``--scheduler ADDRESS``, ``render_many(client=...)``).

Each model is one task, :func:`rasterkit._workers.run_task`, given the model's path and the
image's path: the workers read the models and write the images themselves (so OUTDIR must
be a folder the workers can reach, a shared file system on a real cluster), and send back
only the manifest record. The scheduler retries the task of a worker that dies (Dask's
``distributed.scheduler.allowed-failures``, 3 by default); a task that fails that often is
recorded as an error. Results are collected here as they complete, so the manifest gets
each model's line once.

Each task renders with the kernel threads its share of its machine's cores allows: the
cores of the worker's host divided by the task threads of all workers on that host.

Needs ``distributed`` (``pip install 'rasterkit[dask]'``), imported only here.
"""

from __future__ import annotations

import uuid

from . import _workers
from ._report import UsageError

__all__ = ["client_for", "run"]


def _distributed():
    try:
        import distributed
    except ImportError:
        raise UsageError("--scheduler needs Dask: pip install 'rasterkit[dask]'") from None
    return distributed


def client_for(address: str):
    """A Dask ``Client`` connected to the scheduler at ``address`` (one-line error if none)."""
    distributed = _distributed()
    try:
        return distributed.Client(address, timeout="10s")
    except (OSError, TimeoutError) as e:
        raise UsageError(f"cannot reach the Dask scheduler at {address}: {e}") from None


def _host(address: str) -> str:
    return address.split("://")[-1].rsplit(":", 1)[0]


def _threads_by_host(client) -> dict[str, int]:
    """Kernel threads per task on each host of the cluster."""
    workers = client.scheduler_info().get("workers", {})
    cores = client.run(_workers.cores)  # {worker address: cores of its machine}
    slots: dict[str, int] = {}
    host_cores: dict[str, int] = {}
    for address, info in workers.items():
        host = _host(address)
        slots[host] = slots.get(host, 0) + int(info.get("nthreads", 1))
        host_cores[host] = max(host_cores.get(host, 1), int(cores.get(address, 1)))
    return {host: max(1, host_cores[host] // max(slots[host], 1)) for host in slots}


def _task(source: str, output: str, options, threads_by_host: dict[str, int]) -> dict:
    """Runs on a worker: :func:`run_task` with this host's thread share."""
    from distributed import get_worker

    try:
        threads = threads_by_host.get(_host(get_worker().address), 1)
    except ValueError:  # not in a worker (a synchronous client)
        threads = 1
    return _workers.run_task(source, output, options, threads)


def run(client, tasks, options, on_result) -> None:
    """Render ``tasks`` (``(source, output)`` pairs) on ``client``'s cluster, calling
    ``on_result(record)`` here as each completes."""
    distributed = _distributed()
    threads = _threads_by_host(client)
    run_id = uuid.uuid4().hex[:8]
    futures = {}
    for k, (source, output) in enumerate(tasks):
        future = client.submit(_task, source, output, options, threads, key=f"rasterkit-{run_id}-{k}", pure=False)
        futures[future] = (source, output)
    try:
        for future in distributed.as_completed(futures):
            try:
                record = future.result()
            except Exception as e:  # the task failed on the cluster: a worker kept dying
                source, output = futures[future]
                record = {"input": source, "output": output, "status": "error", "code": 1,
                          "error": f"{source}: {type(e).__name__}: {e}".splitlines()[0],
                          "seconds": None, "triangles": None}
            on_result(record)
    finally:
        client.cancel(list(futures))
