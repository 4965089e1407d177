"""A fresh interpreter, without limits, that sees what this process sees (its ``sys.path`` as
``PYTHONPATH``): how the start-up tests watch which modules the command line imports."""

from __future__ import annotations

import os
import subprocess
import sys

#: The environment of a fresh interpreter: this one's, with this process's ``sys.path``.
ENV = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}

#: Runs the command line in a fresh interpreter; prints the exit code and which of the heavy
#: modules got imported (NumPy too: it alone would take --help past its 0.15 s budget).
MAIN = """
import sys
from rasterkit.cli import main
try:
    code = main(sys.argv[1:])
except SystemExit as e:
    code = e.code
print(code, [m for m in ("numba", "llvmlite", "numpy") if m in sys.modules])
"""

#: The start of a script that records Numba's compiles: each function compiled, with the
#: process that compiled it, appended as a JSON line to the file ``sys.argv[1]`` (forked
#: helpers inherit the listener and append their own lines). numba:compile fires only for a
#: real compile, after the on-disk cache was tried.
COMPILE_LOG = """
import json, os, sys
from numba.core import event

out = sys.argv[1]


class Record(event.Listener):
    def on_start(self, ev):
        pass

    def on_end(self, ev):
        with open(out, "a") as f:
            f.write(json.dumps([os.getpid(), ev.data["dispatcher"].py_func.__name__]) + "\\n")


event.register("numba:compile", Record())
"""


def fresh(code: str, *argv: str) -> subprocess.CompletedProcess:
    """Run the Python source ``code`` with ``argv`` in a fresh interpreter (two minutes at most)."""
    return subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True,
                          env=ENV, timeout=120)
