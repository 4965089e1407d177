"""rasterkit.limits: sizes people write, the settings and their environment variables."""

import pytest

from rasterkit import limits


@pytest.mark.parametrize("text, expected", [("1500", 1500), ("1K", 1024), ("512M", 512 * 2**20), ("2G", 2 * 2**30),
                                            ("2GiB", 2 * 2**30), ("1.5k", 1536), (" 3 MB ", 3 * 2**20), (7, 7)])
def test_parse_size(text, expected):
    assert limits.parse_size(text) == expected


@pytest.mark.parametrize("text", ["", "G", "-1", "0", "1X", "abc", "nanG", "infG", True])
def test_parse_size_rejects(text):
    with pytest.raises(ValueError):
        limits.parse_size(text)


def test_settings_and_environment(monkeypatch):
    monkeypatch.setenv("RASTERKIT_MAX_FILE_SIZE", "10K")
    monkeypatch.setenv("RASTERKIT_MAX_MEMORY", "1M")
    assert limits.max_file_size() == 10240 and limits.memory_limit() == 2**20
    limits.set_max_file_size("1M")
    limits.set_memory_limit(4096)
    try:
        assert limits.max_file_size() == 2**20 and limits.memory_limit() == 4096
        limits.check_memory(4096, "this")
        with pytest.raises(limits.LimitError, match=r"^a test needs about 4\.88 KiB of memory, more than .*4 KiB"):
            limits.check_memory(5000, "a test")
    finally:
        limits.set_max_file_size(None)
        limits.set_memory_limit(None)
    monkeypatch.delenv("RASTERKIT_MAX_MEMORY")
    assert limits.memory_limit() == limits.machine_memory() > 2**20
    monkeypatch.setenv("RASTERKIT_MAX_MEMORY", "lots")
    with pytest.raises(limits.LimitError, match="RASTERKIT_MAX_MEMORY"):
        limits.memory_limit()
