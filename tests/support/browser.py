"""Driving the viewer's page in a real browser: Debian's Chromium through Selenium and its
ChromeDriver (the browser test, the viewer's latency benchmark and the README's screenshot).

:func:`missing` says why a browser cannot run here (None when it can); :func:`chromium` starts
a headless one; :func:`start_view` starts ``rasterkit view`` and returns its address.
"""

from __future__ import annotations

import base64
import contextlib
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CHROMIUM, DRIVER = Path("/usr/bin/chromium"), Path("/usr/bin/chromedriver")
# Chromium as root, headless, without the background connections this machine refuses
FLAGS = ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-dev-shm-usage")


def missing() -> str | None:
    """Why no browser test can run here, or None."""
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed (pip install '.[test]')"
    for path, package in ((CHROMIUM, "chromium"), (DRIVER, "chromium-driver")):
        if not path.is_file():
            return f"{path} is absent (Debian's {package} package; .ci/run installs it)"
    return None


@contextlib.contextmanager
def chromium(width: int = 1200, height: int = 1000):
    """A headless Chromium driven by Selenium, its window ``width`` x ``height``."""
    from selenium import webdriver

    profile = tempfile.mkdtemp(prefix="rasterkit-chromium-")
    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for flag in (*FLAGS, f"--window-size={width},{height}", f"--user-data-dir={profile}"):
        options.add_argument(flag)
    driver = webdriver.Chrome(options=options, service=webdriver.ChromeService(executable_path=str(DRIVER)))
    try:
        yield driver
    finally:
        driver.quit()
        shutil.rmtree(profile, ignore_errors=True)


def start_view(*flags: str) -> tuple[subprocess.Popen, str]:
    """``rasterkit view FLAGS --no-browser`` started; (the process, the page's address)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}
    process = subprocess.Popen([sys.executable, "-m", "rasterkit", "view", *flags, "--no-browser"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, cwd=ROOT)
    line = process.stdout.readline()
    match = re.search(r"http://127\.0\.0\.1:\d+/", line)
    if match is None:
        process.kill()
        raise RuntimeError(f"rasterkit view did not start: {line}{process.stderr.read()}")
    return process, match.group(0)


def stop_view(process: subprocess.Popen) -> str:
    """Ctrl-C to the viewer; its last line (the render command). Raises on a bad exit."""
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=60)
    if process.returncode != 0:
        raise RuntimeError(f"rasterkit view exited with {process.returncode}: {err}")
    return out.strip().splitlines()[-1]


def stats(driver) -> dict:
    """The page's figures: frames, number, final, camera, latencies (ms)."""
    return driver.execute_script("return window.rasterkitViewer || null;") or {}


def wait_frame(driver, after: int, timeout: float = 120.0, final: bool = True) -> dict:
    """The page's figures once it shows a frame numbered above ``after`` (a final one when
    ``final``)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        now = stats(driver)
        if now.get("number", 0) > after and (now.get("final") or not final):
            return now
        time.sleep(0.05)
    raise TimeoutError(f"no new frame after {after} within {timeout} s: {stats(driver)}")


def shown_picture(driver) -> bytes:
    """The bytes of the picture the page shows now (PNG for a final frame)."""
    encoded = driver.execute_async_script("""
        const done = arguments[arguments.length - 1];
        fetch(window.rasterkitViewer.url).then(r => r.arrayBuffer()).then(buffer => {
          let text = '';
          for (const byte of new Uint8Array(buffer)) text += String.fromCharCode(byte);
          done(btoa(text));
        });""")
    return base64.b64decode(encoded)


def drag(driver, dx: int, dy: int, steps: int, pause: float = 0.0, shift: bool = False) -> None:
    """Press on the picture's centre, move by (dx, dy) CSS pixels in ``steps``, release."""
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    chain = ActionChains(driver, duration=0).move_to_element(driver.find_element(By.ID, "frame"))
    if shift:
        chain = chain.key_down(Keys.SHIFT)
    chain = chain.click_and_hold()
    for k in range(steps):
        chain = chain.move_by_offset(dx // steps + (1 if k < dx % steps else 0),
                                     dy // steps + (1 if k < dy % steps else 0))
        if pause:
            chain = chain.pause(pause)
    chain = chain.release()
    if shift:
        chain = chain.key_up(Keys.SHIFT)
    chain.perform()
