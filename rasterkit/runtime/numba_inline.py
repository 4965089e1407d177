"""Numba's inliner, made to do each piece of work once.

Numba inlines an ``inline="always"`` function at every call site by running the untyped
pipeline on the callee (``InlineWorker.inline_function``), which inlines the callee's own
``inline="always"`` callees the same way, and then deep-copying the resulting IR block by
block, twice (``InlineWorker.inline_ir``). Both costs grow with the number of call sites
of the whole tree (a triangle rasterizer inlined through three levels into a band worker),
and the copies also with its size: each block's copy starts a fresh memo, every block refers
to the function's one ``Scope``, and a scope holds all the function's variables, so a callee
of B blocks and V variables costs B x V copies (numba/numba#8989 and #9204 describe the
same). For the band workers that was about a quarter of all compile time.

:func:`install` changes two things, neither the IR that is compiled:

- **One memo per call site.** The copies made by one ``inline_ir`` call share a memo, so the
  scope and its variables are copied once and the copied blocks share one scope, as the
  callee's own blocks do (``inline_ir`` renames the variables of that one scope; it asserts
  there is one).
- **The callee's untyped IR once per function.** ``inline_function`` (run the untyped
  pipeline on the callee, then ``inline_ir``) reuses the untyped IR of a function it ran
  the pipeline on before with the same flags and locals: ``inline_ir`` copies that IR before
  changing anything, so the stored IR is never changed. (Other users of
  ``run_untyped_passes``, which change the IR they get, are left alone.)

Installed by :mod:`rasterkit.runtime.jit` before anything compiles; a Numba whose inliner is not
shaped this way (no ``copy`` module reference, no ``InlineWorker.inline_ir``, or an
``inline_function`` that does more than those two calls) is left as it is.
"""

from __future__ import annotations

import contextvars
import copy
import functools
import types

__all__ = ["install"]

#: The memo the copies of the current ``inline_ir`` call share (None: not in one).
_memo: contextvars.ContextVar[dict | None] = contextvars.ContextVar("rasterkit_inline_memo", default=None)

#: Untyped IR (no SSA) by (function, contexts, flags, locals).
_untyped: dict = {}


def _deepcopy(x, memo=None):
    shared = _memo.get()
    return copy.deepcopy(x, shared if memo is None and shared is not None else memo)


def _flags_key(worker) -> str:
    values = worker.flags.values() if worker.flags is not None else {}
    return repr(sorted((name, repr(value)) for name, value in values.items() if name != "enable_ssa"))


def install() -> bool:
    """Patch Numba's inliner (once); whether it is patched."""
    try:
        from numba.core import inline_closurecall as module
    except ImportError:
        return False
    worker = getattr(module, "InlineWorker", None)
    inline_ir = getattr(worker, "inline_ir", None)
    inline_function = getattr(worker, "inline_function", None)
    if getattr(inline_ir, "_rasterkit", False):
        return True
    expected = {"run_untyped_passes", "inline_ir", "__code__", "co_freevars"}
    if (inline_ir is None or getattr(module, "copy", None) is not copy
            or set(getattr(getattr(inline_function, "__code__", None), "co_names", ())) != expected):
        return False

    @functools.wraps(inline_ir)
    def shared_inline_ir(self, *args, **kwargs):
        token = _memo.set({})  # both copies of this call: the second copies the first's objects
        try:
            return inline_ir(self, *args, **kwargs)
        finally:
            _memo.reset(token)

    @functools.wraps(inline_function)
    def stored_inline_function(self, caller_ir, block, i, function, arg_typs=None):
        key = (function, id(self.typingctx), id(self.targetctx), _flags_key(self), repr(self.locals))
        callee_ir = _untyped.get(key)
        if callee_ir is None:
            callee_ir = _untyped[key] = self.run_untyped_passes(function)
        elif self.flags is not None:
            self.flags.enable_ssa = False  # as the pipeline's run leaves the flags
        return self.inline_ir(caller_ir, block, i, callee_ir, function.__code__.co_freevars, arg_typs=arg_typs)

    shared_inline_ir._rasterkit = True
    shim = types.ModuleType("copy", "The copy module, with a deepcopy that shares one memo within inline_ir.")
    shim.__dict__.update({name: getattr(copy, name) for name in dir(copy) if not name.startswith("__")})
    shim.deepcopy = _deepcopy
    module.copy = shim
    worker.inline_ir = shared_inline_ir
    worker.inline_function = stored_inline_function
    return True
