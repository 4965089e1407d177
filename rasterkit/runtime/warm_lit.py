"""The resolve's helper of a first render lit or textured per pixel (:mod:`rasterkit.runtime.warm`).

The band worker of a frame lit per pixel calls
:func:`rasterkit.raster.kernels.phong_rows.resolve_lit_rows`, that of a textured frame
:func:`rasterkit.raster.kernels.bands.resolve_textured_rows`: the largest kernels to compile,
which the band worker compiles into its own code. A helper that compiles the band worker
would compile the two one after the other; instead a second helper, forked first, compiles
the frame's resolve alone (for the arguments the band worker passes it, :func:`rows_args`)
while the first compiles the rest of the band worker, and the first waits for it only when
its compile gets to the resolve (:func:`load_when_reported`), which then loads from Numba's
cache.
"""

from __future__ import annotations

import os

#: The resolves this helper compiles, ``module:function``: of a frame lit per pixel, and of
#: a textured frame (lit per pixel or not: its textured faces' lighting is in it).
LIT_ROWS = "rasterkit.raster.kernels.phong_rows:resolve_lit_rows"
TEXTURED_ROWS = "rasterkit.raster.kernels.bands:resolve_textured_rows"


def lit_per_pixel(style: dict) -> bool:
    """Whether a frame of ``style`` (:func:`rasterkit.runtime.warm.helper_style`) is lit per
    pixel: shaded ``"phong"`` or under a light that casts shadows."""
    return style["shading"] == "phong" or style["shadows"]


def frame_resolve(style: dict) -> str | None:
    """The resolve (:data:`TEXTURED_ROWS` or :data:`LIT_ROWS`) of a frame of ``style`` whose
    helper compiles it, or None (a frame neither textured nor lit per pixel)."""
    if style.get("maps"):
        return TEXTURED_ROWS
    return LIT_ROWS if lit_per_pixel(style) else None


def is_lit_frame(worker, args) -> bool:
    """Whether this :func:`rasterkit.runtime.threads.run_parallel` call (``args`` after the
    slot) is the band worker's call for a frame textured or lit per pixel: its textures
    (``args[-4]``) or its last argument, the frame's lights, are not None."""
    return getattr(worker, "py_func", worker).__name__ == "draw_bands" and (args[-1] is not None
                                                                            or args[-4] is not None)


def rows_args(args) -> tuple:
    """The arguments :func:`rasterkit.raster.kernels.bands.draw_bands` passes its resolve
    (types and layouts as it passes them: the textured one when the frame has textures, else
    the lit one), made from its own ``args`` (after the slot), for no rows."""
    shading, target, sample, lid, spans = args[4], args[5], args[7], args[8], args[9]
    band_lid = lid[0, lid.shape[1] - spans.shape[2]:]  # a slot's band rows: the last BAND_HEIGHT
    textures, mapped, lights = args[-4], args[-2], args[-1]
    last = (textures, mapped) if textures is not None else (lights,)
    return (0, 0, shading, target, sample, band_lid, spans[0, 0], spans[0, 1], *last)


def wait_for_report(fd: int) -> None:
    """In the band worker's helper: wait until the resolve's helper has named the resolve on
    its pipe (file descriptor ``fd``, inherited from the process that forked both) or has
    ended."""
    with os.fdopen(fd, "rb") as pipe:
        pipe.readline()


def load_when_reported(kernel, fd: int) -> None:
    """In the band worker's helper: the first compile of ``kernel`` (the resolve) here
    waits for the resolve's helper (:func:`wait_for_report`) and then finds it in Numba's
    cache. Numba compiles a callee when it types the call in its caller
    (``Dispatcher.compile``), so the band worker's compile gets that far, the rest of its
    callees compiled, before it waits."""
    compile_here = kernel.compile
    pending = [fd]

    def compile_after_report(sig):
        if pending:
            wait_for_report(pending.pop())
        return compile_here(sig)

    kernel.compile = compile_after_report


def interpret_kernels() -> None:
    """In the resolve's helper, before it renders: a kernel not yet compiled runs as plain
    Python (its ``py_func``) instead of compiling (the tiny frame's setup kernels before the
    band worker, which the band worker's helper compiles meanwhile): the resolve's compile
    starts seconds sooner and no two helpers compile the same kernels. Only the types of
    what they return reach the resolve: a kernel returns arrays of the dtypes it makes in
    Python too. Numba's dispatcher calls ``_compile_for_args`` on a call whose types it has
    no code for, and calls what that returns (the compiled function: here the Python one); a
    compile for given types (``compile``, as a caller's compile asks for its callees) is
    untouched."""
    from numba.core.dispatcher import Dispatcher

    def python_function(self, *args, **kws):
        return self.py_func

    Dispatcher._compile_for_args = python_function
