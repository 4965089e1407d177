"""A kernel that calls another compiled kernel (not inlined) compiles it once per call
site: an argument that starts as a constant (``n = 0`` then ``n += 1``) would be typed
``Literal[int](0)`` in Numba's first round of type inference and compile the callee a
second time, for that literal (about a second each, in every first render)."""

import os
import subprocess
import sys
import textwrap

_SCRIPT = textwrap.dedent(
    """
    import numba
    import numpy as np

    from rasterkit import render, shapes
    from rasterkit.runtime import threads as _threads
    from rasterkit.runtime import warm as _warm
    from rasterkit.camera import Camera
    from rasterkit.raster.kernels import face_setup
    from rasterkit.raster.kernels import shade
    from rasterkit.runtime import handoff

    _warm.start = lambda *a, **k: None  # everything compiles here

    class Done(Exception):
        pass

    def hook(worker, args):
        if worker is face_setup.setup_faces:
            worker.compile(tuple(numba.typeof(a) for a in (0, *args)))
            raise Done
        return None

    _threads.intercept(hook)
    camera = Camera.look_at(eye=(2.0, 1.5, 3.0), target=(0.0, 0.0, 0.0), width=64, height=48)
    try:
        render(shapes.icosphere(1), camera, "solid")
    except Done:
        pass
    flags = np.zeros(4, np.int64)
    handoff.finish_and_watch(flags, 0, 1, 1, flags, 2, 1)
    for kernel in (shade.flat_colors, handoff.wait_for):
        print(kernel.py_func.__name__, len(kernel.signatures), "Literal" in str(kernel.signatures))
    """
)


def test_callees_compile_once_and_never_for_a_literal(tmp_path):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    done = subprocess.run([sys.executable, "-c", _SCRIPT], env=env, capture_output=True, text=True, timeout=280)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[:2] == ["flat_colors 1 False", "wait_for 1 False"]
