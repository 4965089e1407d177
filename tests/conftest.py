"""Shared by every test folder (tests/<package>/ mirrors rasterkit/<package>/).

The helpers of ``tests/support`` (hostile children, slow references, the render corpus, the
fuzzer) import as ``support.<module>``: this file puts ``tests/`` itself on ``sys.path``, once,
so no test file needs a path of its own, and the checkout before it. The fixtures here are the ones several folders use.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
# The checkout's rasterkit, ahead of an installed copy (``pip install .``): the one the command
# line tests run too (their children get the checkout on PYTHONPATH), so both load the kernels
# one of them compiled into the same Numba cache instead of each compiling its own.
for path in (TESTS.parent, TESTS):
    if str(path) not in sys.path:
        sys.path.insert(0, str(path))

from support.paths import MODELS  # noqa: E402


@pytest.fixture(scope="session")
def models_dir() -> Path:
    """The real models of ``<repo>/../shared/models``; the test skips, with the reason, when
    the folder is absent (it is not part of the repository). For a module-level skip or
    parametrization use ``support.paths.MODELS`` and ``support.paths.needs_models``."""
    if not MODELS.is_dir():
        pytest.skip(f"{MODELS} is absent (the shared test models are not part of the repository)")
    return MODELS


def pytest_xdist_auto_num_workers(config):
    """``-n auto``: one worker per core, at most 4 (each worker compiles the kernels its tests
    need for itself unless another has cached them already; more workers mostly compile more)."""
    return max(1, min(os.cpu_count() or 1, 4))


#: The test files that take longest on a first run (most of it compiling), collected first:
#: the worker processes then finish at about the same time, instead of one running the last
#: long file alone. The others keep their order.
SLOW_FIRST = (
    "tests/tools/test_benchmarks_smoke.py",
    "tests/raster/test_lights.py",
    "tests/runtime/test_warm.py",
    "tests/cli/test_cli_lights.py",
    "tests/api/test_api_hostile.py",
    "tests/gltf/test_fuzz_gltf.py",
    "tests/obj/test_obj_polygons.py",
    "tests/raster/test_textured_frames.py",
    "tests/tools/test_benchmarks_textures.py",
    "tests/obj/test_obj_hostile.py",
    "tests/cli/test_cli_hostile.py",
)


def pytest_collection_modifyitems(session, config, items):
    rank = {path: k for k, path in enumerate(SLOW_FIRST)}
    items.sort(key=lambda item: rank.get(item.nodeid.split("::")[0], len(rank)))
