"""docs/lecture.md stays true: its Python blocks run, its pictures exist and are up to date.

Every ```python block of the lecture runs on its own (a fresh namespace, a temporary working
directory); the blocks assert what the text says. The gallery script draws every figure the
lecture shows, the same pixels as the committed ones, the same bytes twice.
"""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

from support.paths import ROOT
from support.scripts import import_script

LECTURE = ROOT / "docs" / "lecture.md"
GALLERY = ROOT / "docs" / "gallery"
SCRIPT = ROOT / "scripts" / "make_gallery.py"


def python_blocks() -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", LECTURE.read_text(encoding="utf-8"), re.S | re.M)


def pictures() -> set[str]:
    """The gallery files the lecture shows."""
    return set(re.findall(r"\]\(gallery/([\w-]+\.png)\)", LECTURE.read_text(encoding="utf-8")))


def run_script(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True,
                          cwd=ROOT, timeout=300)


def test_the_lecture_has_a_snippet_for_each_topic():
    assert len(python_blocks()) >= 8


@pytest.mark.parametrize("index", range(len(python_blocks())))
def test_snippet_runs(index, tmp_path, monkeypatch, capsys):
    source = python_blocks()[index]
    monkeypatch.chdir(tmp_path)
    exec(compile(source, f"{LECTURE.name}, python block {index + 1}", "exec"), {"__name__": "__main__"})
    capsys.readouterr()  # the blocks print for the reader; what they assert is the check


@pytest.fixture(scope="module")
def make_gallery():
    """The script as a module (it puts its own folder on sys.path for its helpers)."""
    return import_script(SCRIPT.stem, SCRIPT.parent)


def test_every_picture_shown_is_drawn_by_the_script_and_committed(make_gallery):
    drawn = {f"{name}.png" for name in make_gallery.FIGURES}
    assert pictures() == drawn
    assert {p.name for p in GALLERY.glob("*.png")} == drawn
    total = sum(p.stat().st_size for p in GALLERY.glob("*.png"))
    assert total < 3 * 2**20


def test_gallery_is_up_to_date():
    result = run_script("--check")
    assert result.returncode == 0, (
        result.stderr + "\nthe renderer's pictures changed: run `python scripts/make_gallery.py` "
        "and look at docs/gallery/ before committing them")


def test_gallery_is_deterministic(make_gallery, tmp_path):
    names = ["lines", "culling", "focus"]
    first = make_gallery.write(tmp_path / "a", names)
    second = make_gallery.write(tmp_path / "b", names)
    assert [p.read_bytes() for p in first] == [p.read_bytes() for p in second]


def test_unknown_figure_is_a_usage_error(make_gallery, capsys):
    with pytest.raises(SystemExit) as exit_:
        make_gallery.main(["--only", "nonesuch"])
    assert exit_.value.code == 2 and "nonesuch" in capsys.readouterr().err
