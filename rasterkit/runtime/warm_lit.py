"""The lit resolve's helper of a first render lit per pixel (:mod:`rasterkit.runtime.warm`).

The band worker of a frame lit per pixel calls
:func:`rasterkit.raster.kernels.phong_rows.resolve_lit_rows`, the largest kernel to compile,
and compiles it into its own code. A helper that compiles the band worker would compile the
two one after the other; instead a second helper, forked first, compiles the lit resolve
alone (for the arguments the band worker passes it, :func:`rows_args`) while the first
compiles the rest of the band worker, and the first waits for it only when its compile gets
to the lit resolve (:func:`load_when_reported`), which then loads from Numba's cache.
"""

from __future__ import annotations

import os

#: The kernel this helper compiles, ``module:function``.
LIT_ROWS = "rasterkit.raster.kernels.phong_rows:resolve_lit_rows"


def lit_per_pixel(style: dict) -> bool:
    """Whether a frame of ``style`` (:func:`rasterkit.runtime.warm.helper_style`) is lit per
    pixel: shaded ``"phong"`` or under a light that casts shadows."""
    return style["shading"] == "phong" or style["shadows"]


def is_lit_frame(worker, args) -> bool:
    """Whether this :func:`rasterkit.runtime.threads.run_parallel` call (``args`` after the
    slot) is the band worker's call for a frame lit per pixel: its last argument, the frame's
    lights, is not None."""
    return getattr(worker, "py_func", worker).__name__ == "draw_bands" and args[-1] is not None


def rows_args(args) -> tuple:
    """The arguments :func:`rasterkit.raster.kernels.bands.draw_bands` passes the lit resolve
    (types and layouts as it passes them), made from its own ``args`` (after the slot), for
    no rows."""
    shading, target, sample, lid, spans, lights = args[4], args[5], args[7], args[8], args[9], args[-1]
    band_lid = lid[0, lid.shape[1] - spans.shape[2]:]  # a slot's band rows: the last BAND_HEIGHT
    return 0, 0, shading, target, sample, band_lid, spans[0, 0], spans[0, 1], lights


def wait_for_report(fd: int) -> None:
    """In the band worker's helper: wait until the lit helper has named the lit resolve on its
    pipe (file descriptor ``fd``, inherited from the process that forked both) or has ended."""
    with os.fdopen(fd, "rb") as pipe:
        pipe.readline()


def load_when_reported(kernel, fd: int) -> None:
    """In the band worker's helper: the first compile of ``kernel`` (the lit resolve) here
    waits for the lit helper (:func:`wait_for_report`) and then finds it in Numba's cache. Numba
    compiles a callee when it types the call in its caller (``Dispatcher.compile``), so the
    band worker's compile gets that far, the rest of its callees compiled, before it waits."""
    compile_here = kernel.compile
    pending = [fd]

    def compile_after_report(sig):
        if pending:
            wait_for_report(pending.pop())
        return compile_here(sig)

    kernel.compile = compile_after_report
