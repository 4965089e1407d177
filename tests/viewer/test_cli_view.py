"""``rasterkit view``: a page on 127.0.0.1 driven over HTTP as the page's script drives it,
ended with Ctrl-C; the command it prints draws its last frame again, byte for byte."""

from __future__ import annotations

import http.client
import io
import json
import os
import re
import shlex
import signal
import subprocess
import sys
import time

import numpy as np
from PIL import Image

from support.hostile import run_cli
from support.paths import ROOT


def _start(*flags):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}
    process = subprocess.Popen([sys.executable, "-m", "rasterkit", "view", *flags], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, env=env, cwd=ROOT)
    line = process.stdout.readline()
    match = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
    assert match, line + process.stderr.read() if process.poll() is not None else line
    return process, int(match.group(1))


def _get(port, path, method="GET", body=None):
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    connection.request(method, path, body=body, headers={"Content-Type": "application/json"})
    answer = connection.getresponse()
    return answer, answer.read()


def test_a_view_ended_with_ctrl_c_prints_the_render_command_of_its_last_frame(tmp_path):
    process, port = _start("--demo", "--no-browser", "--size", "120x90", "--color", "#88aacc", "--azimuth", "10")
    try:
        answer, data = _get(port, "/frame?after=0")
        assert answer.status == 200
        number = int(answer.getheader("X-Frame-Number"))
        for event in ({"kind": "drag", "dx": 30, "dy": -12, "seq": 1}, {"kind": "set", "mode": "solid+wire", "seq": 2},
                      {"kind": "wheel", "steps": -2, "seq": 3}):
            assert _get(port, "/event", "POST", json.dumps(event))[0].status == 204
        final = None
        deadline = time.monotonic() + 120
        while final is None and time.monotonic() < deadline:
            answer, data = _get(port, f"/frame?after={number}")
            if answer.status == 200:
                number = int(answer.getheader("X-Frame-Number"))
                if answer.getheader("X-Frame-Final") == "1" and answer.getheader("X-Event-Seq") == "3":
                    final = data
        assert final is not None
    finally:
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=60)
    assert process.returncode == 0, err
    command = out.strip().splitlines()[-1]
    assert command.startswith("rasterkit render ") and "--color '#88aacc'" in command and "--azimuth" not in command
    words = shlex.split(command)[2:]
    words[words.index("-o") + 1] = str(tmp_path / "again.png")
    done = run_cli("render", *words)
    assert done.code == 0, done.stderr
    again = np.asarray(Image.open(tmp_path / "again.png"))
    np.testing.assert_array_equal(np.asarray(Image.open(io.BytesIO(final))), again)
    assert "--mode solid+wire" in command


def test_a_port_in_use_and_a_second_model_are_one_line_errors(tmp_path):
    process, port = _start("--demo", "--no-browser", "--size", "40x30")
    try:
        done = run_cli("view", "--demo", "--no-browser", "--port", str(port))
        assert done.code == 2 and f"port {port}" in done.stderr and done.stderr.count("\n") == 1, done.stderr
    finally:
        process.send_signal(signal.SIGINT)
        process.communicate(timeout=60)
    done = run_cli("view", "--no-browser")
    assert done.code == 2 and "one model file, or --demo" in done.stderr
    done = run_cli("view", "--demo", "--port", "70000")
    assert done.code == 2 and "1 to 65535" in done.stderr
