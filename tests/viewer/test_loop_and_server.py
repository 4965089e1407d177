"""The drawing thread draws the newest state only, and the local page's server answers its
own page only."""

from __future__ import annotations

import http.client
import json
import time

import pytest

import rasterkit as rk
from rasterkit.batch.render_one import load_drawn
from rasterkit.viewer.loop import FrameLoop
from rasterkit.viewer.server import MAX_EVENT_BYTES, ViewerServer
from rasterkit.viewer.session import ViewerSession, choices


def _loop(size=(64, 48)) -> FrameLoop:
    session = ViewerSession(load_drawn(None, rk.RenderOptions(mode="solid"), False), rk.View(size=size))
    return FrameLoop(session)


def test_events_faster_than_frames_are_drawn_as_the_newest_state_only(monkeypatch):
    render = ViewerSession.render

    def slow(self, final, number=0):  # each frame takes at least 0.1 s
        time.sleep(0.1)
        return render(self, final, number)

    monkeypatch.setattr(ViewerSession, "render", slow)
    loop = _loop()
    try:
        first = loop.wait_frame(0, 120)
        assert first.final and first.number == 1
        for k in range(40):  # 40 events in about 0.2 s
            loop.post({"kind": "drag", "dx": 1, "dy": 0, "seq": k + 1})
            time.sleep(0.005)
        loop.post({"kind": "release"})
        deadline, frame = time.monotonic() + 30, first
        while not (frame.final and frame.seq == 40) and time.monotonic() < deadline:
            frame = loop.wait_frame(frame.number, 5) or frame
        assert frame.final and frame.seq == 40
        assert frame.number <= 1 + 6  # a few frames, not one per event: no backlog was drawn
        assert frame.camera["azimuth"] == pytest.approx(first.camera["azimuth"] + 40 * 180 / 48)
    finally:
        loop.close()


def test_a_wait_for_a_frame_that_does_not_come_ends_at_its_timeout():
    loop = _loop()
    try:
        frame = loop.wait_frame(0, 120)
        begin = time.monotonic()
        assert loop.wait_frame(frame.number, 0.3) is None
        assert 0.25 < time.monotonic() - begin < 5
    finally:
        loop.close()


@pytest.fixture
def server():
    loop = _loop()
    server = ViewerServer(loop, {"model": "demo", "size": [64, 48], "choices": choices(),
                                 "current": loop.session.current()})
    server.start()
    yield server
    server.shutdown()
    server.server_close()
    loop.close()


def _request(server, method, path, body=None, headers=None):
    connection = http.client.HTTPConnection("127.0.0.1", server.port, timeout=60)
    connection.request(method, path, body=body, headers={"Host": f"127.0.0.1:{server.port}", **(headers or {})})
    answer = connection.getresponse()
    data = answer.read()
    connection.close()
    return answer, data


def test_the_page_its_state_and_its_frames(server):
    assert server.server_address[0] == "127.0.0.1"
    answer, page = _request(server, "GET", "/")
    assert answer.status == 200 and b"page.js" in page and answer.getheader("Content-Type").startswith("text/html")
    for script in ("/page.js", "/controls.js"):
        answer, _ = _request(server, "GET", script)
        assert answer.status == 200 and "javascript" in answer.getheader("Content-Type")
    answer, state = _request(server, "GET", "/state")
    assert json.loads(state)["choices"]["show"] == ["color", "depth", "normals", "ids"]
    answer, png = _request(server, "GET", "/frame?after=0")
    assert answer.status == 200 and png.startswith(b"\x89PNG") and answer.getheader("X-Frame-Final") == "1"
    camera = json.loads(answer.getheader("X-Camera"))
    number = int(answer.getheader("X-Frame-Number"))
    answer, _ = _request(server, "POST", "/event", json.dumps({"kind": "drag", "dx": 12, "dy": 0, "seq": 7}),
                         {"Content-Type": "application/json"})
    assert answer.status == 204
    answer, _ = _request(server, "GET", f"/frame?after={number}")
    assert answer.status == 200 and answer.getheader("X-Event-Seq") == "7"
    assert json.loads(answer.getheader("X-Camera"))["azimuth"] == pytest.approx(camera["azimuth"] + 12 * 180 / 48)


@pytest.mark.parametrize("headers", [
    {"Host": "evil.example:80"},  # a page of another name resolved to 127.0.0.1 (DNS rebinding)
    {"Origin": "http://evil.example"},  # another site's script
    {"Origin": "null"},
])
def test_requests_from_other_sites_are_refused(server, headers):
    for method, path, body in (("GET", "/state", None), ("GET", "/frame?after=0", None),
                               ("POST", "/event", json.dumps({"kind": "reframe"}))):
        answer, _ = _request(server, method, path, body, headers)
        assert answer.status == 403, (method, path)


def test_the_server_serves_nothing_else_and_refuses_bad_events(server):
    for path in ("/../pyproject.toml", "/static/page.html", "/etc/passwd", "/frame/x"):
        assert _request(server, "GET", path)[0].status == 404
    answer, text = _request(server, "POST", "/event", b"{not json")
    assert answer.status == 400 and text.count(b"\n") == 1
    answer, text = _request(server, "POST", "/event", json.dumps({"kind": "drag", "dx": "far"}))
    assert answer.status == 400 and b"dx must be" in text
    answer, _ = _request(server, "POST", "/event", b"x" * (MAX_EVENT_BYTES + 1))
    assert answer.status == 413
    assert _request(server, "GET", "/frame?after=soon")[0].status == 400
