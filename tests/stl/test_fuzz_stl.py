"""The fuzz run of ``tests/support/fuzz_stl.py`` in CI: a fixed, derandomized sample of hostile STL
files (from the grammar, and mutations of the grammar's clean files and of the public files when
``../shared/models`` is there), in a child process with a time and a memory limit, so that a
crash or a hang fails this test instead of the session; and the oracle judged on made-up
failures."""

import sys
import warnings

import pytest

import rasterkit.stl
from support import fuzz_formats, fuzz_stl
from support.hostile import run


def test_fuzz_sample_ends_cleanly(tmp_path):
    outcome = run([sys.executable, fuzz_stl.__file__, "--grammar", "250", "--mutations", "250",
                   "--failures", tmp_path / "failures", "--example-seconds", "60"], timeout=600)
    assert outcome.code == 0 and not outcome.timed_out, outcome.describe() + outcome.stdout[-3000:]
    summary = outcome.stdout.strip().splitlines()[-1]
    assert summary.startswith("checked 501 files") and summary.endswith(" 0 failures"), summary
    read = int(summary.split(": ")[1].split(" read")[0])
    assert read > 100, summary  # the sample goes past the checks at the door
    assert not (tmp_path / "failures").exists()


def test_the_oracle_judges_errors(tmp_path, monkeypatch):
    good, bad = tmp_path / "good.stl", tmp_path / "bad.stl"
    good.write_bytes(fuzz_stl.FIRST)
    bad.write_bytes(b"solid\nfacet normal 0 0 1\nendsolid\n")
    assert fuzz_formats.check(good, fuzz_stl.read) == "ok"
    assert fuzz_formats.check(bad, fuzz_stl.read) == "error"

    def raising(error):
        def read_stl(path):
            if isinstance(error, Warning):
                warnings.warn(error)
            raise error
        return read_stl

    for error, verdict in [(KeyError("x"), "KeyError"), (ValueError(f"{good}: a\nb"), "not one line"),
                           (ValueError("line 3: bad"), "does not start with the file's name"),
                           (RuntimeWarning("overflow"), "RuntimeWarning")]:
        monkeypatch.setattr(rasterkit.stl, "read_stl", raising(error))
        with pytest.raises(fuzz_formats.Failure, match=verdict):
            fuzz_formats.check(good, fuzz_stl.read)
