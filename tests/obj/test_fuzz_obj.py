"""The fuzz run of ``tests/support/fuzz_obj.py`` in CI: a fixed, derandomized sample of hostile OBJ
files (from the grammar, and mutations of the real models when ``../shared/models`` is
there) plus every file of ``tests/data/fuzz_regressions``, in a child process with a time
and a memory limit, so that a crash or a hang fails this test instead of the session."""

import sys
from support import fuzz_obj
from support.hostile import run


FUZZ = fuzz_obj.__file__  # run as a script, as by hand


def test_fuzz_sample_and_regressions_end_cleanly(tmp_path):
    outcome = run([sys.executable, FUZZ, "--grammar", "400", "--mutations", "300", "--regressions",
                   "--failures", tmp_path / "failures", "--example-seconds", "60"], timeout=600)
    assert outcome.code == 0 and not outcome.timed_out, outcome.describe() + outcome.stdout[-3000:]
    summary = outcome.stdout.strip().splitlines()[-1]
    assert summary.endswith(" 0 failures"), summary
    assert not (tmp_path / "failures").exists()


def test_the_oracle_judges_errors(tmp_path, monkeypatch):
    """The fuzz oracle itself: a clean one-line error naming the file passes; another
    exception type, a message of several lines, one without the file's name and an escaped
    warning are failures."""
    import warnings

    import pytest

    import rasterkit

    good = tmp_path / "good.obj"
    good.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    assert fuzz_obj.check(good) == "ok"
    assert fuzz_obj.check(bad) == "error"

    def raising(error):
        def load(path):
            if isinstance(error, Warning):
                warnings.warn(error)
            raise error
        return load

    for error, verdict in [(KeyError("x"), "KeyError"), (ValueError("good.obj: a\nb"), "not one line"),
                           (ValueError("line 3: bad"), "does not name the file"),
                           (RuntimeWarning("overflow"), "RuntimeWarning")]:
        monkeypatch.setattr(rasterkit, "load_obj", raising(error))
        with pytest.raises(fuzz_obj.Failure, match=verdict):
            fuzz_obj.check(good)
