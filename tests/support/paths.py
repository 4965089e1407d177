"""Where the tests find things, from this file's place (``tests/support/paths.py``).

The real models sit next to the repository (``<repo>/../shared/models``) on the developers'
machines only: tests that need them skip, with the reason, when the folder is absent.
"""

from __future__ import annotations

from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parents[1]
ROOT = TESTS.parent
DATA = TESTS / "data"
SCRIPTS = ROOT / "scripts"
MODELS = ROOT.parent / "shared" / "models"

#: Skips a test (or, as ``pytestmark``, a module) when the shared models are absent.
needs_models = pytest.mark.skipif(not MODELS.is_dir(),
                                  reason=f"{MODELS} is absent (the shared test models are not part of the repository)")
