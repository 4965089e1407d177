"""NumPy's booleans are True or False wherever a flag is asked for (NumPy 2 names the type
``bool``, not ``bool_``), and nothing else that merely calls itself bool is."""

import numpy as np
import pytest

import rasterkit
from rasterkit import values


def test_numpy_booleans_are_flags():
    assert values.flag("aa", np.True_) is True and values.flag("aa", np.False_) is False
    assert rasterkit.RenderOptions(aa=np.True_, textures=np.False_).aa is True
    assert rasterkit.RenderOptions(textures=np.False_).textures is False


def test_other_types_named_bool_are_not():
    fake = type("bool", (), {})()
    with pytest.raises(TypeError, match="aa must be True or False"):
        values.flag("aa", fake)
    with pytest.raises(TypeError, match="aa must be True or False"):
        values.flag("aa", np.int8(1))
