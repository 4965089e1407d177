"""Names a package imports on first use (PEP 562), so that importing it loads nothing heavy.

``rasterkit``, ``rasterkit.batch`` and ``rasterkit.image`` list their public names with the
module that holds each; :func:`on_first_use` gives the package's ``__getattr__`` and
``__dir__``, which import a name's module when the name is first asked for and keep the
value in the package's namespace. Pure standard library.
"""

from __future__ import annotations

import importlib
import importlib.util

__all__ = ["on_first_use"]


def on_first_use(package: str, namespace: dict, homes: dict[str, str], submodules: bool = False):
    """``(__getattr__, __dir__)`` for the package ``package`` (its ``__name__``) whose module
    dictionary is ``namespace``: ``homes`` maps each public name to ``"module:attribute"``
    (absolute), or to ``"module"`` for a module itself; ``submodules``: any other name that
    is a submodule of the package is imported too (``rasterkit.camera`` after a bare
    ``import rasterkit``)."""

    def __getattr__(name: str):
        if name in homes:
            module, _, attribute = homes[name].partition(":")
            value = importlib.import_module(module)
            if attribute:
                value = getattr(value, attribute)
            namespace[name] = value  # found directly from now on
            return value
        if submodules and name.isidentifier() and not name.startswith("__") \
                and importlib.util.find_spec(f"{package}.{name}") is not None:
            return importlib.import_module(f"{package}.{name}")  # the import binds it on the package
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(homes))

    return __getattr__, __dir__
