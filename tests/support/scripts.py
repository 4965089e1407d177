"""The repository's scripts (``scripts/``), which are not installed with the package, imported
by the tests that check them."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path
from types import ModuleType

from .paths import SCRIPTS


def import_script(name: str, folder: Path = SCRIPTS) -> ModuleType:
    """Import ``folder/name.py`` as the module ``name``: the folder is on ``sys.path`` while it is
    imported (for the helpers beside it) and not after."""
    entry = str(folder)
    sys.path.insert(0, entry)
    try:
        return importlib.import_module(name)
    finally:
        sys.path.remove(entry)
