"""``rasterkit view`` in a real browser (headless Chromium through Selenium): a frame
appears, a drag turns the view the way it says, the mode switch changes the pixels, and the
command printed at the end draws the last frame again, pixel for pixel."""

from __future__ import annotations

import io
import os
import shlex
import shutil

import numpy as np
import pytest
from PIL import Image

from support import browser
from support.hostile import run_cli
from support.paths import MODELS

pytestmark = pytest.mark.skipif(browser.missing() is not None, reason=str(browser.missing()))

SIZE = (480, 360)


def _model() -> list[str]:
    """A public model when the shared ones are here, else the built-in demo."""
    suzanne = MODELS / "suzanne.obj"
    return [str(suzanne)] if suzanne.is_file() else ["--demo"]


def _pixels(data: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(data)))


def test_the_page_shows_frames_follows_the_mouse_and_hands_back_its_view(tmp_path):
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import Select

    process, url = browser.start_view(*_model(), "--mode", "solid", "--size", f"{SIZE[0]}x{SIZE[1]}")
    try:
        with browser.chromium(900, 620) as driver:
            driver.get(url)
            first = browser.wait_frame(driver, 0)
            before = browser.shown_picture(driver)
            assert before.startswith(b"\x89PNG") and _pixels(before).shape[:2] == SIZE[::-1]
            browser.drag(driver, 90, 0, steps=9)  # right, on a picture shown at its own size
            turned = browser.wait_frame(driver, first["number"])
            while turned["camera"]["azimuth"] == first["camera"]["azimuth"] or not turned["final"]:
                turned = browser.wait_frame(driver, turned["number"])
            assert turned["camera"]["azimuth"] == pytest.approx(first["camera"]["azimuth"] + 90 * 180 / SIZE[1])
            assert turned["camera"]["elevation"] == pytest.approx(first["camera"]["elevation"])
            after = browser.shown_picture(driver)
            assert not np.array_equal(_pixels(after), _pixels(before))
            driver.save_screenshot(str(tmp_path / "viewer.png"))
            if os.environ.get("RASTERKIT_VIEWER_SCREENSHOT"):  # the README's picture (docs/viewer.md)
                shutil.copyfile(tmp_path / "viewer.png", os.environ["RASTERKIT_VIEWER_SCREENSHOT"])
            Select(driver.find_element(By.NAME, "mode")).select_by_value("hidden")
            hidden = browser.wait_frame(driver, turned["number"])
            assert "--mode" in hidden["camera"]["command"]
            assert hidden["camera"]["command"][hidden["camera"]["command"].index("--mode") + 1] == "hidden"
            last = browser.shown_picture(driver)
            assert not np.array_equal(_pixels(last), _pixels(after))
    finally:
        command = browser.stop_view(process)
    words = shlex.split(command)
    assert words[:2] == ["rasterkit", "render"] and words[-2] == "-o"
    words[-1] = str(tmp_path / "again.png")
    done = run_cli(*words[1:])
    assert done.code == 0, done.stderr
    np.testing.assert_array_equal(np.asarray(Image.open(tmp_path / "again.png")), _pixels(last))
    assert Image.open(tmp_path / "viewer.png").size[0] > SIZE[0]
