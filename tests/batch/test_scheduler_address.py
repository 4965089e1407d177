"""``--scheduler``: an address that is not a Dask scheduler is one line within seconds (exit
2), never a hang, an internal error or silence. Run in child processes (tests/support/hostile.py)."""

from __future__ import annotations

import http.server
import socket
import threading
import time

import pytest
from support.hostile import run_cli


SECONDS = 30  # the check answers within CONNECT_SECONDS (5 s) plus start-up


def _folder(tmp_path):
    folder = tmp_path / "models"
    folder.mkdir()
    for name in ("a", "b"):
        (folder / f"{name}.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    return folder


@pytest.mark.parametrize("address, words", [
    ("", "a scheduler address is tcp://HOST:PORT"),
    ("   ", "a scheduler address is tcp://HOST:PORT"),
    ("tcp://host", "a scheduler address is tcp://HOST:PORT"),
    ("tcp://host:99999", "a scheduler address is tcp://HOST:PORT"),
    ("tls://127.0.0.1:8786", "rasterkit connects to tcp://HOST:PORT"),
    ("ucx://127.0.0.1:8786", "rasterkit connects to tcp://HOST:PORT"),
    ("inproc://x", "rasterkit connects to tcp://HOST:PORT"),
])
def test_a_malformed_address_is_refused_at_once(tmp_path, address, words):
    started = time.monotonic()
    outcome = run_cli("render", _folder(tmp_path), "-o", tmp_path / "out", "--scheduler", address, timeout=SECONDS)
    assert words in outcome.one_line_error()
    assert time.monotonic() - started < SECONDS and not (tmp_path / "out").exists()


def test_an_empty_address_is_refused_for_one_model_too(tmp_path):
    model = _folder(tmp_path) / "a.obj"
    outcome = run_cli("render", model, "-o", tmp_path / "a.png", "--scheduler", "", timeout=SECONDS)
    assert "a scheduler address is tcp://HOST:PORT" in outcome.one_line_error()


@pytest.fixture
def web_server():
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), http.server.SimpleHTTPRequestHandler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield f"tcp://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


@pytest.fixture
def silent_server():
    """A port that accepts connections and never says a word."""
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen(8)
    yield f"127.0.0.1:{listener.getsockname()[1]}"
    listener.close()


@pytest.fixture
def closed_port():
    probe = socket.socket()
    probe.bind(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()
    return f"tcp://127.0.0.1:{port}"


@pytest.mark.parametrize("server", ["web_server", "silent_server", "closed_port"])
def test_something_that_is_no_scheduler_is_one_line_within_seconds(tmp_path, request, server):
    pytest.importorskip("distributed")
    address = request.getfixturevalue(server)
    started = time.monotonic()
    outcome = run_cli("render", _folder(tmp_path), "-o", tmp_path / "out", "--scheduler", address, timeout=SECONDS)
    line = outcome.one_line_error()
    assert address.removeprefix("tcp://") in line
    assert any(w in line for w in ("not a Dask scheduler", "no Dask scheduler answered", "cannot connect")), line
    assert time.monotonic() - started < SECONDS and not (tmp_path / "out").exists()
