"""Batches on a Dask cluster (``--scheduler ADDRESS``, ``render_many(client=...)``).

Each model is one task, :func:`rasterkit.batch.workers.run_task`, given the model's path and the
image's path: the workers read the models and write the images themselves (so OUTDIR must
be a folder the workers can reach, a shared file system on a real cluster), and send back
only the manifest record. The scheduler retries the task of a worker that dies (Dask's
``distributed.scheduler.allowed-failures``, 3 by default); a task that fails that often is
recorded as an error. Results are collected here as they complete, so the manifest gets
each model's line once.

Each task renders with the kernel threads its share of its machine's cores allows: the
cores of the worker's host divided by the task threads of all workers on that host.

The command line's ``--scheduler`` takes ``tcp://HOST:PORT`` (or ``HOST:PORT``): the
address is checked before anything connects (:func:`check_address`), then the peer must
answer Dask's handshake and say it is a scheduler within :data:`CONNECT_SECONDS`
(:func:`client_for`), so an address of something else (a web server, a closed port, a
worker) is one line within seconds, not a wait without end. Other transports (``tls://``
needs certificates, ``ucx://`` its library, ``inproc://`` a scheduler in this very process)
are for a ``distributed.Client`` made by the program, given as ``render_many(client=...)``.

Needs ``distributed`` (``pip install 'rasterkit[dask]'``), imported only here.
"""

from __future__ import annotations

import uuid

from rasterkit.batch import workers as _workers
from rasterkit.image.atomic import remove_temporaries_of
from rasterkit.batch.report import UsageError

__all__ = ["CONNECT_SECONDS", "check_address", "client_for", "run"]

#: The longest the command line waits for a scheduler to answer (connection, handshake, identity).
CONNECT_SECONDS = 5.0

_OTHER_TRANSPORTS = "; tls://, ucx:// and inproc:// need a distributed.Client of your own: render_many(client=...)"


def _distributed():
    try:
        import distributed
    except ImportError:
        raise UsageError("--scheduler needs Dask: pip install 'rasterkit[dask]'") from None
    return distributed


def check_address(address: str) -> str:
    """``address`` as ``tcp://HOST:PORT`` (``HOST:PORT`` gets the ``tcp://``), or
    :class:`UsageError` for anything else. Pure: nothing is imported or connected."""
    text = address.strip() if isinstance(address, str) else ""
    scheme, sep, rest = text.partition("://")
    if not sep:
        scheme, rest = "tcp", text
    host, colon, port = rest.rpartition(":")
    host = host[1:-1] if host.startswith("[") and host.endswith("]") else host  # [::1]:8786
    if scheme.lower() != "tcp":
        raise UsageError(f"--scheduler {address!r}: rasterkit connects to tcp://HOST:PORT" + _OTHER_TRANSPORTS)
    if not (colon and host and "/" not in rest and port.isdigit() and 1 <= int(port) <= 65535):
        raise UsageError(f"--scheduler {address!r}: a scheduler address is tcp://HOST:PORT (e.g. tcp://10.0.0.5:8786)")
    return f"tcp://{rest}"


async def _identity(address: str, seconds: float) -> dict:
    """The identity a Dask server at ``address`` gives (connection, handshake and reply
    within ``seconds`` in all)."""
    import asyncio

    from distributed.comm import connect

    async def ask():
        comm = await connect(address, timeout=seconds)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    return await asyncio.wait_for(ask(), seconds)


def client_for(address: str, seconds: float = CONNECT_SECONDS):
    """A Dask ``Client`` connected to the scheduler at ``address`` (:func:`check_address`'s
    form); :class:`UsageError` in one line, within about ``seconds``, when nothing there
    answers as a Dask scheduler (a closed port, another kind of server, a Dask worker)."""
    address = check_address(address)
    distributed = _distributed()
    import asyncio

    try:
        identity = asyncio.run(_identity(address, seconds))
    except (asyncio.TimeoutError, TimeoutError):
        raise UsageError(f"--scheduler {address}: no Dask scheduler answered within {seconds:g} s") from None
    except OSError as e:  # refused or unreachable (Dask retries until the time is up)
        detail = " ".join(str(e).split()) or type(e).__name__
        raise UsageError(f"--scheduler {address}: cannot connect ({detail[:200]})") from None
    except Exception as e:  # bytes that are not Dask's protocol
        detail = " ".join(str(e).split()) or type(e).__name__
        raise UsageError(f"--scheduler {address}: not a Dask scheduler ({type(e).__name__}: {detail[:200]})") from None
    kind = identity.get("type") if isinstance(identity, dict) else None
    if kind != "Scheduler":
        raise UsageError(f"--scheduler {address}: the server there is not a Dask scheduler "
                         f"(it says {kind or 'nothing'}); give the scheduler's address")
    try:
        return distributed.Client(address, timeout=f"{seconds}s")
    except Exception as e:
        detail = " ".join(str(e).split()) or type(e).__name__
        raise UsageError(f"--scheduler {address}: cannot connect to the Dask scheduler ({detail[:200]})") from None


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


def _task(source: str, output: str, task, threads_by_host: dict[str, int]) -> dict:
    """Runs on a worker: :func:`run_task` with this host's thread share."""
    from distributed import get_worker

    try:
        threads = threads_by_host.get(_host(get_worker().address), 1)
    except ValueError:  # not in a worker (a synchronous client)
        threads = 1
    return _workers.run_task(source, output, task, threads)


def run(client, pairs, task, on_result) -> None:
    """Render ``pairs`` (``(source, output)``) on ``client``'s cluster as ``task`` says,
    calling ``on_result(record)`` here as each completes."""
    distributed = _distributed()
    pairs = list(pairs)
    threads = _threads_by_host(client)
    run_id = uuid.uuid4().hex[:8]
    futures = {}
    for k, (source, output) in enumerate(pairs):
        future = client.submit(_task, source, output, task, threads, key=f"rasterkit-{run_id}-{k}", pure=False)
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
    # A worker that died while writing left its temporary file (its task ran again elsewhere)
    remove_temporaries_of(output for _, output in pairs)
