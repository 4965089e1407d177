"""A first use of the command line: help and usage errors come at once, without Numba. (The
first render's notice that the kernels are compiling, and a cached run's silence:
``tests/runtime/test_warm.py``.)"""

import argparse
import importlib
import importlib.util
import subprocess
import sys

import pytest

import rasterkit
from rasterkit import options
from rasterkit.cli import _parser
from support.paths import ROOT
from support.startup import MAIN, fresh


def _main(*argv: str) -> tuple[str, subprocess.CompletedProcess]:
    done = fresh(MAIN, *argv)
    assert done.returncode == 0, done.stderr
    return done.stdout.splitlines()[-1], done


@pytest.mark.parametrize("argv", [["--help"], ["render", "--help"], ["info", "--help"]])
def test_help_imports_neither_numba_nor_numpy(argv):
    last, done = _main(*argv)
    assert last == "0 []"
    assert "usage: rasterkit" in done.stdout


@pytest.mark.parametrize("argv", [
    ["render", "--demo", "-o", "x.png", "--size", "12by4"],
    ["render", "--demo", "-o", "x.png", "--size", "40000x4"],
    ["render", "--demo", "-o", "x.png", "--mode", "sketchy"],
    ["render", "-o", "x.png"],
    ["info"],
])
def test_usage_errors_exit_2_without_numba(argv, tmp_path):
    last, done = _main(*argv)
    assert last == "2 []"
    assert done.stderr.startswith("rasterkit: error:") and done.stderr.count("\n") == 1


def test_import_rasterkit_alone_imports_no_numba():
    done = fresh("import sys, rasterkit, rasterkit.options, rasterkit.raster.kernels.limits\n"
                  "print([m for m in ('numba', 'llvmlite', 'numpy') if m in sys.modules])\n"
                  "print(rasterkit.camera.Camera.__name__)")  # submodules still load on use
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["[]", "Camera"]


def test_every_public_name_resolves_and_is_listed():
    for name in rasterkit.__all__:
        assert getattr(rasterkit, name) is not None, name
    assert set(rasterkit.__all__) <= set(dir(rasterkit))
    with pytest.raises(AttributeError):
        rasterkit.no_such_name


def test_render_stays_the_function_after_its_module_is_imported():
    module = importlib.import_module("rasterkit.raster.render")
    assert rasterkit.render is module.render and callable(rasterkit.render)


def _benchmark_settings(monkeypatch):
    """benchmarks/settings.py, loaded by its path (the benchmark suite is not installed)."""
    path = ROOT / "benchmarks" / "settings.py"
    spec = importlib.util.spec_from_file_location("_benchmark_settings", path)
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, spec.name, module)  # its dataclass looks itself up there
    spec.loader.exec_module(module)
    return module


def test_each_list_of_choices_has_one_home(monkeypatch):
    from rasterkit.camera import PROJECTIONS
    from rasterkit.raster.kernels.clip import MAX_IMAGE_SIZE

    assert PROJECTIONS is options.PROJECTIONS is rasterkit.PROJECTIONS
    assert MAX_IMAGE_SIZE is options.MAX_IMAGE_SIZE
    render_module = importlib.import_module("rasterkit.raster.render")
    assert render_module.MODES is options.MODES  # imported, not a copy
    assert tuple(importlib.import_module("rasterkit.raster.modes").MODE_TABLE) == options.MODES  # a row each
    assert _benchmark_settings(monkeypatch).MODES is options.MODES
    commands = next(a for a in _parser()._actions if isinstance(a, argparse._SubParsersAction))
    choices = {a.dest: tuple(a.choices) for a in commands.choices["render"]._actions if a.choices}
    assert choices == {"mode": options.MODES, "projection": options.PROJECTIONS,
                       "cull": options.CULL, "shading": options.SHADING, "edges": options.EDGES,
                       "hidden": tuple(h for h in options.HIDDEN if h is not None),
                       "texture_filter": options.TEXTURE_FILTERS, "camera": options.MODEL_CAMERAS}
    svg_module = importlib.import_module("rasterkit.svg")
    assert svg_module.SVG_MODES is options.SVG_MODES and svg_module.HIDDEN is options.HIDDEN
    assert importlib.import_module("rasterkit.raster.features").EDGES is options.EDGES
    assert importlib.import_module("rasterkit.material.texture").FILTERS is options.TEXTURE_FILTERS
