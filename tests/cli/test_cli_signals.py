"""Ctrl-C and SIGTERM on the command line when the exception its handler raises does not
come through: a C extension that Python calls back can lose it (Numba's dispatcher clears
it) or turn it into a ``SystemError``. The command still stops, at the next parallel pass,
as it would have: exit 130 or 143, one line, no temporary file."""

from __future__ import annotations

import signal

import pytest
from support.hostile import run_python


LOST = """
import importlib, os, signal, sys
from rasterkit.cli import main

module = importlib.import_module("rasterkit.raster.render")

signal.signal(signal.SIGINT, signal.default_int_handler)  # as an interactive shell starts it
signal.signal(signal.SIGTERM, signal.SIG_DFL)
render, frames = module.render, []

def frame(*args, **kwargs):  # the third frame gets the signal inside code that loses its exception
    frames.append(1)
    if len(frames) == 3:
        try:
            os.kill(os.getpid(), SIGNAL)
            for _ in range(100000):
                pass
        except BaseException as e:
            MANGLE
    return render(*args, **kwargs)

module.render = frame
code = main(["render", "--demo", "-o", os.path.join(FOLDER, "spin.gif"), "--turntable", "100000000", "--size", "8x8"])
print(code, len(frames), sorted(os.listdir(FOLDER)))
"""


@pytest.mark.parametrize("mangle", ["pass", "raise SystemError('returned a result with an exception set') from e"])
@pytest.mark.parametrize("sig, code, word", [(signal.SIGTERM, 143, "terminated"), (signal.SIGINT, 130, "interrupted")])
def test_a_signal_whose_exception_is_lost_or_changed_still_stops_the_command(tmp_path, mangle, sig, code, word):
    script = LOST.replace("SIGNAL", f"signal.{sig.name}").replace("MANGLE", mangle).replace("FOLDER", repr(str(tmp_path)))
    done = run_python(script, timeout=60)  # the old command line rendered on, forever
    assert not done.timed_out and done.code == 0, done.describe()
    result, frames, left = done.stdout.split(" ", 2)
    assert int(result) == code and done.stderr.splitlines()[-1] == f"rasterkit: {word}", done.stderr
    assert int(frames) <= 4 and left.strip() == "[]"
