"""The Examples in the public docstrings run and print what they show."""

import doctest

import pytest

import rasterkit
import rasterkit.camera.interop
import rasterkit.colors
import rasterkit.scene
import rasterkit.transform


@pytest.mark.parametrize("module", [rasterkit, rasterkit.camera.interop, rasterkit.colors, rasterkit.scene,
                                    rasterkit.transform])
def test_docstring_examples(module):
    result = doctest.testmod(module)
    assert result.attempted > 0 and result.failed == 0
