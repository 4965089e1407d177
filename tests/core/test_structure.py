"""The package's shape, read from its source: module-level imports form no cycle, no module
imports another module's private (``_name``) names, the library's packages never import the
command line, and the public names are listed once (``rasterkit/__init__.pyi``)."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

from support.paths import ROOT

PACKAGE = ROOT / "rasterkit"


def _modules() -> dict[str, Path]:
    modules = {}
    for path in PACKAGE.rglob("*.py"):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        modules[".".join(parts)] = path
    return modules


MODULES = _modules()


def _top_level_imports(path: Path) -> list[tuple[str, list[str]]]:
    """``(module, names)`` of the imports run when ``path`` is imported: at module level,
    not under ``if TYPE_CHECKING``, not inside functions."""
    found = []

    def visit(body):
        for node in body:
            if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
                continue
            if isinstance(node, (ast.If, ast.Try, ast.With)):
                visit([n for part in ("body", "orelse", "finalbody", "handlers") for n in getattr(node, part, [])])
            elif isinstance(node, ast.ExceptHandler):
                visit(node.body)
            elif isinstance(node, ast.Import):
                found.extend((alias.name, []) for alias in node.names)
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                found.append((node.module, [alias.name for alias in node.names]))

    visit(ast.parse(path.read_text()).body)
    return found


def _graph() -> dict[str, set[str]]:
    """Module -> the rasterkit modules its import runs (``from pkg import module`` counts
    as importing ``pkg.module``; importing ``a.b.c`` runs the packages ``a.b`` and ``a`` first)."""
    graph = {}
    for name, path in MODULES.items():
        targets = set()
        for module, names in _top_level_imports(path):
            if not module.startswith("rasterkit"):
                continue
            for imported in [module] + [f"{module}.{n}" for n in names if f"{module}.{n}" in MODULES]:
                parts = imported.split(".")
                targets.update(".".join(parts[:k]) for k in range(2, len(parts) + 1) if ".".join(parts[:k]) in MODULES)
        graph[name] = targets - {name}
    return graph


def _packages_of(name: str) -> set[str]:
    parts = name.split(".")
    return {".".join(parts[:k]) for k in range(1, len(parts))}


def test_module_level_imports_form_no_cycle():
    graph = _graph()
    # a package's __init__ importing its own modules is how packages work: not a cycle
    edges = {m: {t for t in ts if t not in _packages_of(m)} for m, ts in graph.items()}
    state, cycles = {}, []

    def visit(node, stack):
        state[node] = "open"
        for nxt in sorted(edges.get(node, ())):
            if state.get(nxt) == "open":
                cycles.append(stack[stack.index(nxt):] + [nxt])
            elif nxt not in state:
                visit(nxt, stack + [nxt])
        state[node] = "done"

    for node in sorted(edges):
        if node not in state:
            visit(node, [node])
    assert cycles == []


def test_no_module_imports_another_modules_private_names():
    private = [(str(path.relative_to(PACKAGE.parent)), node.module, alias.name)
               for path in MODULES.values() for node in ast.walk(ast.parse(path.read_text()))
               if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("rasterkit")
               for alias in node.names if alias.name.startswith("_") and not alias.name.startswith("__")]
    assert private == []


@pytest.mark.parametrize("package", ["rasterkit.batch", "rasterkit.raster", "rasterkit.obj", "rasterkit.svg",
                                     "rasterkit.image", "rasterkit.runtime", "rasterkit.camera"])
def test_the_library_never_imports_the_command_line(package):
    offenders = [name for name, path in MODULES.items() if name == package or name.startswith(package + ".")
                 for module, _ in _top_level_imports(path) + [(n.module, []) for n in ast.walk(ast.parse(path.read_text()))
                                                             if isinstance(n, ast.ImportFrom) and n.module]
                 if module == "rasterkit.cli" or module.startswith("rasterkit.cli.")]
    assert offenders == []


def test_public_names_are_listed_once_and_each_resolves():
    stub = (PACKAGE / "__init__.pyi").read_text()
    code = (
        "import sys, rasterkit\n"
        "assert 'numpy' not in sys.modules and 'numba' not in sys.modules\n"
        "print(' '.join(rasterkit.__all__))\n"
        "missing = [n for n in rasterkit.__all__ if getattr(rasterkit, n, None) is None]\n"
        "assert not missing, missing\n"
        "import rasterkit.raster.render\n"
        "assert callable(rasterkit.render) and not isinstance(rasterkit.render, type(sys))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    names = done.stdout.split()
    assert names == sorted(line.split(" as ")[1] for line in stub.splitlines() if line.startswith("from "))
    assert {"render", "load_obj", "Camera", "Mesh", "render_svg", "render_many"} <= set(names)


def test_no_module_is_longer_than_a_newcomer_reads_at_once():
    long = {str(path.relative_to(PACKAGE.parent)): n for path in MODULES.values()
            if (n := len(path.read_text().splitlines())) > 400}
    assert long == {}


def _all_imports(path: Path) -> set[str]:
    """Every rasterkit module ``path`` imports, at any depth (``from pkg import module``
    counts as ``pkg.module``)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.add(node.module)
            found.update(f"{node.module}.{alias.name}" for alias in node.names if f"{node.module}.{alias.name}" in MODULES)
    return {m for m in found if m.startswith("rasterkit")}


#: The imports of another package's kernels module: plain constants, read without Numba, and
#: kernels calling another package's kernels (Numba compiles a callee into its caller, so the
#: caller's module must import it): the textured resolve samples textures.
KERNEL_CONSTANTS = {("rasterkit.options", "rasterkit.raster.kernels.limits"),
                    ("rasterkit.raster.kernels.texture_shade", "rasterkit.material.kernels.sample"),
                    ("rasterkit.raster.kernels.surface", "rasterkit.material.kernels.sample"),
                    ("rasterkit.raster.kernels.cutout", "rasterkit.material.kernels.sample")}


def test_a_packages_kernels_are_imported_by_that_package_only():
    offenders = []
    for name, path in MODULES.items():
        for module in _all_imports(path):
            if ".kernels" not in module:
                continue
            owner = module.split(".kernels")[0]
            if not (name == owner or name.startswith(owner + ".")) and (name, module) not in KERNEL_CONSTANTS:
                offenders.append((name, module))
    assert offenders == []
