"""The interactive viewer's responsiveness, measured in a real browser.

``rasterkit view MODEL --mode solid --size 960x720`` (sportsCar, 300k triangles, in the full
and quick profiles) is opened in headless Chromium through Selenium (the browser test's
helpers, ``tests/support/browser.py``). After one untimed drag, the mouse drags across the
picture in small steps, one every ~16 ms (a 60 Hz mouse), for ``settings.viewer_moves`` moves
(120 but in the smoke test's tiny profile); the page
records, for each frame it shows, the time from sending the newest event that frame shows to
the frame being on the page (``window.rasterkitViewer.latencies``, milliseconds). Reported:
the median latency against the 50 ms budget (ratio <= 1 meets it), with the 90th percentile
and the frame count in the note; and the viewer process's resident memory before and after
``settings.viewer_memory_drags`` further drag events (1,000), after 200 untimed ones (it
should stay flat: no queue, no growing cache).
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

from .report import Record, Target
from .settings import model_path

FAMILY = "viewer"
ROOT = Path(__file__).resolve().parents[1]
BUDGET = 0.050


def _browser():
    """The browser helpers of the tests (one home for driving Chromium)."""
    tests = str(ROOT / "tests")
    if tests not in sys.path:
        sys.path.insert(0, tests)
    from support import browser

    return browser


def _rss(pid: int) -> int:
    """Resident bytes of process ``pid`` (Linux)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
    return 0


def run(settings, results, peers) -> None:
    browser = _browser()
    reason = browser.missing()
    if reason is not None:
        results.skip(FAMILY, "viewer latency", reason)
        return
    name = settings.viewer_model
    model = model_path(name)
    if not model.is_file():
        results.skip(FAMILY, name, f"model file {model} not found")
        return
    width, height = settings.viewer_size
    sizes = {"width": width, "height": height}
    process, url = browser.start_view(str(model), "--mode", "solid", "--size", f"{width}x{height}")
    try:
        with browser.chromium(width + 200, height + 300) as driver:
            driver.get(url)
            first = browser.wait_frame(driver, 0, timeout=600)
            browser.drag(driver, 40, 0, steps=10, pause=0.016)  # untimed: the preview's kernels, its size
            browser.wait_frame(driver, first["number"])
            driver.execute_script("window.rasterkitViewer.latencies = [];")
            moves = settings.viewer_moves
            browser.drag(driver, moves * 2, moves // 4, steps=moves, pause=0.016)
            time.sleep(1.0)
            figures = browser.stats(driver)
            latencies = sorted(figures["latencies"])
            # each group of drags ends in the final frame drawn after the last release: waited
            # for by a number from before the group (read after it, the frame may be shown already)
            mark = browser.stats(driver)["number"]
            for _ in range(2):  # the allocator's and the page's own warm-up, before the count
                browser.drag(driver, 100, 10, steps=100)
            browser.wait_frame(driver, mark, timeout=60)
            before = _rss(process.pid)
            mark = browser.stats(driver)["number"]
            for _ in range(settings.viewer_memory_drags // 100):
                browser.drag(driver, 100, 10, steps=100)
            browser.wait_frame(driver, mark, timeout=60)
            after = _rss(process.pid)
    finally:
        browser.stop_view(process)
    if not latencies:
        results.skip(FAMILY, f"viewer/drag/{name}", "the page showed no frame while dragging")
        return
    median = statistics.median(latencies) / 1000.0
    p90 = latencies[int(0.9 * (len(latencies) - 1))] / 1000.0
    results.add(Record(family=FAMILY, name=f"viewer/drag/{name}/{width}x{height}", peer="50 ms budget", sizes=sizes,
                       rasterkit=median, peer_value=BUDGET, runs=len(latencies),
                       target=Target("median mouse event -> frame on the page <= 50 ms", 1.0),
                       note=f"headless Chromium; {settings.viewer_moves} moves at ~60 Hz, {len(latencies)} frames shown; "
                            f"90th percentile {p90 * 1000:.1f} ms"))
    results.add(Record(family=FAMILY, name=f"viewer/memory/{name}/{settings.viewer_memory_drags}-drags", peer="before the drags",
                       sizes=sizes, rasterkit=float(after), peer_value=float(before), quantity="bytes", runs=1,
                       target=Target(f"resident memory flat over {settings.viewer_memory_drags:,} drag events "
                                     "(within 10 %)", 1.10),
                       note="VmRSS of the rasterkit view process before and after the drags"))
