"""Recycled memory for framebuffers and per-frame scratch arrays.

Fresh memory from the operating system arrives one zero-filled page at a time, on first
touch. A 1920x1080 frame is 14 MB of colour and depth, about 3500 pages, and on this
project's test machines those page faults cost 4-8 ms a frame: more than drawing it.
So the buffers of a :class:`~rasterkit.Framebuffer` come from a few blocks kept here, and
a block is handed out again once nothing refers to it any more: no framebuffer, no array,
view or buffer export of its memory. A block still in use is never reused, so recycling
is invisible to the caller except in speed.

Whether a block is in use is read from its reference count (CPython counts one reference
per view, since a NumPy view keeps its base array alive). :data:`ENABLED` is False, and
every call allocates fresh memory, where reference counts do not behave as measured at
import (another Python implementation).

The triangle path keeps its per-draw scratch elsewhere (``_Workspace.reserve`` in
:mod:`rasterkit.raster.triangle_pass`: named, per thread, grown by a quarter and never handed back).
This module serves memory that may outlive the call (framebuffers, arrays given to the
caller), which must not be handed out again while anything uses it, so it hands out exact
sizes and checks reference counts. The triangle records change size from frame to frame
(the fans of faces cut by the near plane); exact sizes would make each such frame take
fresh memory, which was measured 4-19 % slower (a turntable with the camera inside the model's
bounding sphere), while the named buffers never leave the draw and need neither the lock
nor the reference counts.
"""

from __future__ import annotations

import math
import sys
import threading

import numpy as np

__all__ = ["ENABLED", "idle_bytes", "release", "take"]

MAX_IDLE_BYTES = 256 * 2**20
"""Idle blocks beyond this total are let go (the oldest first)."""

MIN_BYTES = 1 << 20
"""Smaller requests are not worth recycling: malloc keeps such blocks itself."""

_lock = threading.Lock()
_blocks: list[np.ndarray] = []  # uint8 blocks, most recently handed out last


def _refs(blocks: list, i: int) -> int:
    return sys.getrefcount(blocks[i])


def _calibrate():
    """The reference count of an idle block, or None when views do not show in it."""
    probe = [np.empty(16, np.uint8)]
    idle = _refs(probe, 0)
    view = probe[0][4:].view(np.int32)
    busy = _refs(probe, 0)
    del view
    return idle if busy == idle + 1 and _refs(probe, 0) == idle else None


_IDLE_REFS = _calibrate()
ENABLED = _IDLE_REFS is not None


def _idle(i: int) -> bool:
    """Whether nothing but this module refers to block ``i``."""
    return _refs(_blocks, i) == _IDLE_REFS


def take(shape, dtype) -> np.ndarray:
    """An uninitialised C-contiguous array, on a recycled block when one is idle."""
    dtype = np.dtype(dtype)
    shape = tuple(int(n) for n in shape)
    nbytes = math.prod(shape) * dtype.itemsize
    if not ENABLED or nbytes < MIN_BYTES:
        return np.empty(shape, dtype)
    with _lock:
        block = None
        for i in range(len(_blocks) - 1, -1, -1):
            if _blocks[i].size == nbytes and _idle(i):
                block = _blocks.pop(i)
                break
        if block is None:
            block = np.empty(nbytes, np.uint8)
            _blocks.append(block)
            _trim()  # the memory held grows only here: bound the idle blocks now
        else:
            _blocks.append(block)
        # A view of the block (its base), so the block is busy while the array lives.
        return block.view(dtype).reshape(shape)


def _trim():
    """Forget the oldest idle blocks while the idle ones hold more than MAX_IDLE_BYTES."""
    idle = [i for i in range(len(_blocks)) if _idle(i)]
    excess = sum(_blocks[i].size for i in idle) - MAX_IDLE_BYTES
    dropped = set()
    for i in idle:  # oldest first
        if excess <= 0:
            break
        excess -= _blocks[i].size
        dropped.add(i)
    _blocks[:] = [b for i, b in enumerate(_blocks) if i not in dropped]


def idle_bytes() -> int:
    """Bytes held in blocks that nothing uses (ready to be handed out again)."""
    with _lock:
        return sum(_blocks[i].size for i in range(len(_blocks)) if _idle(i))


def release() -> None:
    """Let go of every idle block (blocks in use are forgotten too, and freed with their
    last user)."""
    with _lock:
        _blocks.clear()
