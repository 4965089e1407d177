"""The fuzz run of ``tests/support/fuzz_gltf.py`` in CI: a fixed, derandomized sample of mutated
glTF and GLB files (made ones, and the public ones when ``../shared/models`` is there), in a
child process with a time and a memory limit, so that a crash or a hang fails this test
instead of the session."""

import sys
import warnings

import pytest

import rasterkit.gltf
from support import fuzz_gltf
from support.hostile import run

FUZZ = fuzz_gltf.__file__  # run as a script, as by hand


def test_fuzz_sample_ends_cleanly(tmp_path):
    outcome = run([sys.executable, FUZZ, "--cases", "300", "--failures", tmp_path / "failures",
                   "--example-seconds", "60"], timeout=600)
    assert outcome.code == 0 and not outcome.timed_out, outcome.describe() + outcome.stdout[-3000:]
    summary = outcome.stdout.strip().splitlines()[-1]
    assert summary.endswith(" 0 failures") and " 300 mutations" in summary, summary
    assert not (tmp_path / "failures").exists()


def test_the_sources_read_and_mutations_change_them():
    import random

    sources = fuzz_gltf.made_sources()
    assert len(sources) == 3
    rng = random.Random(0)
    doc = sources[0][0]
    assert any(fuzz_gltf.mutate_json(doc, rng) != doc for _ in range(5))
    data = fuzz_gltf.glb_bytes(doc, sources[0][1])
    assert all(fuzz_gltf.mutate_bytes(data, rng) != data for _ in range(5))


def test_the_oracle_judges_errors(tmp_path, monkeypatch):
    """A clean case passes and a clean error is an error; another exception type, a message of
    several lines or without the file's name, and an escaped warning are failures."""
    good = tmp_path / "good.glb"
    good.write_bytes(fuzz_gltf.glb_bytes(*fuzz_gltf.made_sources()[0][:2]))
    bad = tmp_path / "bad.glb"
    bad.write_bytes(b"glTF\x01\x00\x00\x00")
    assert fuzz_gltf.check(good) == "ok"
    assert fuzz_gltf.check(bad) == "error"

    def raising(error):
        def read(path):
            if isinstance(error, Warning):
                warnings.warn(error)
            raise error
        return read

    for error, verdict in [(KeyError("x"), "KeyError"), (ValueError(f"{good}: plain"), "ValueError"),
                           (rasterkit.gltf.GltfError(str(good), None, "a\nb"), "not one line"),
                           (rasterkit.gltf.GltfError("other.glb", None, "bad"), "does not start with the file"),
                           (RuntimeWarning("overflow"), "RuntimeWarning")]:
        monkeypatch.setattr(rasterkit.gltf, "read_gltf", raising(error))
        with pytest.raises(fuzz_gltf.Failure, match=verdict):
            fuzz_gltf.check(good)
