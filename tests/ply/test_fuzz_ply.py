"""The fuzz run of ``tests/support/fuzz_ply.py`` in CI: a fixed, derandomized sample of hostile PLY
files (from the grammar, and mutations of the real files of ``../shared/models/formats`` when
they are there and of files written by the script) in a child process with a time and a
memory limit, so that a crash or a hang fails this test instead of the session."""

import sys
import warnings

import pytest

import rasterkit.ply
from support import fuzz_ply
from support.hostile import run

FUZZ = fuzz_ply.__file__  # run as a script, as by hand


def test_fuzz_sample_ends_cleanly(tmp_path):
    outcome = run([sys.executable, FUZZ, "--grammar", "400", "--mutations", "400", "--failures",
                   tmp_path / "failures", "--example-seconds", "60"], timeout=600)
    assert outcome.code == 0 and not outcome.timed_out, outcome.describe() + outcome.stdout[-3000:]
    summary = outcome.stdout.strip().splitlines()[-1]
    assert summary.startswith("checked 803 files") and summary.endswith(" 0 failures"), summary
    read = int(summary.split(": ")[1].split(" read")[0])
    assert read > 25, summary  # the grammar gives files that read, not only errors
    assert not (tmp_path / "failures").exists()


def test_the_oracle_judges_errors(tmp_path, monkeypatch):
    """The fuzz oracle itself: a clean one-line error naming the file passes; another
    exception type, a message of several lines, one without the file's name and an escaped
    warning are failures."""
    good = tmp_path / "good.ply"
    good.write_bytes(fuzz_ply.written_models()[0])
    bad = tmp_path / "bad.ply"
    bad.write_bytes(fuzz_ply.written_models()[1][:-3])
    assert fuzz_ply.check(good) == "ok"
    assert fuzz_ply.check(bad) == "error"

    def raising(error):
        def read(path, **kwargs):
            if isinstance(error, Warning):
                warnings.warn(error)
            raise error
        return read

    for error, verdict in [(KeyError("x"), "KeyError"), (ValueError(f"{good}: a\nb"), "not one line"),
                           (ValueError("line 3: bad"), "does not start with the file's name"),
                           (RuntimeWarning("overflow"), "RuntimeWarning")]:
        monkeypatch.setattr(rasterkit.ply, "read_ply", raising(error))
        with pytest.raises(fuzz_ply.Failure, match=verdict):
            fuzz_ply.check(good)


def test_the_written_models_read_in_every_encoding():
    """The script's own models (its mutations' sources): a textured quad and a triangle."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as folder:
        for data in fuzz_ply.written_models():
            path = Path(folder) / "m.ply"
            path.write_bytes(data)
            mesh = rasterkit.ply.read_ply(path)
            assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3], [0, 2, 1]]
            assert mesh.uv_index.tolist() == [[0, 1, 2], [0, 2, 3], [4, 5, 6]]
