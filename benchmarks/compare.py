"""Run one workload on rasterkit and its peers, and record the outcome.

Shared by every family module so that none has a timing loop of its own: each side is run
once on its own first (the first warm-up run), so that a side that fails is reported with its
reason and left out instead of ending the suite; the survivors are then timed together by
:func:`benchmarks.timing.interleaved`.
"""

from __future__ import annotations

from typing import Callable, Mapping

from .report import Record, Results
from .timing import interleaved

RASTERKIT = "rasterkit"
"""The key of rasterkit's side in every ``sides`` mapping."""


def _failure(error: BaseException) -> str:
    """One line: the exception's type and the first line of its message."""
    first_line = (str(error).strip().splitlines() or [""])[0]
    return f"failed: {type(error).__name__}: {first_line}"


def compare(results: Results, family: str, name: str, sides: Mapping[str, Callable[[], object]], *,
            repeat: int, warmup: int, sizes: dict, work: float | None = None,
            unit: str | None = None, targets: Mapping[str, object] | None = None,
            note: str = "") -> dict[str, float] | None:
    """Time ``sides`` (``"rasterkit"`` and its peers) and add one record per peer.

    Parameters
    ----------
    results : Results
        Receives the records and the skip reasons.
    family, name : str
        Workload family and unique workload name.
    sides : mapping of side name -> callable
        ``sides["rasterkit"]`` is rasterkit; every other key is a peer.
    repeat, warmup : int
        Timed and untimed runs per side (warmup >= 1 is always honoured as at least one run,
        the checking run).
    sizes : dict
        Workload sizes for the record.
    work, unit : float, str
        Work per run and its unit, for the throughput (e.g. pixels and ``"pixel/s"``).
    targets : mapping of peer name -> report.Target
        Goals of this workload against particular peers.

    Returns
    -------
    dict of side -> median seconds, or None when rasterkit itself failed.
    """
    working = {}
    for side, fn in sides.items():
        try:
            fn()
        except Exception as error:  # report and carry on: one failure must not end the suite
            what = name if side == RASTERKIT else f"{name} [{side}]"
            results.skip(family, what, _failure(error))
            if side == RASTERKIT:
                return None
            continue
        working[side] = fn
    medians = interleaved(working, repeat, max(warmup - 1, 0))
    rk = medians[RASTERKIT]
    peers = [side for side in medians if side != RASTERKIT] or [None]
    for peer in peers:
        results.add(Record(family=family, name=name, peer=peer, sizes=sizes, rasterkit=rk,
                           peer_value=medians.get(peer), work=work, unit=unit,
                           target=(targets or {}).get(peer), runs=repeat, note=note))
    return medians


def start(results: Results, family: str, what: str, factory: Callable[[], object]):
    """``factory()``, or None after recording why the peer could not start."""
    from .peers import PeerUnavailable

    try:
        return factory()
    except PeerUnavailable as reason:
        results.skip(family, what, str(reason))
        return None
