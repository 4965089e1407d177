"""rasterkit.Material: defaults, checks, immutability."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import rasterkit
from rasterkit.material import DEFAULT_DIFFUSE, Material, Texture
from rasterkit.obj.materials import DEFAULT_KD


def test_defaults():
    m = rasterkit.Material()
    assert m == Material("default", (0.8, 0.8, 0.8), (0.0, 0.0, 0.0), 32.0, 1.0, (0.0, 0.0, 0.0), None, None, None, None, 1.0)
    assert m.diffuse == DEFAULT_DIFFUSE == DEFAULT_KD
    assert m.textures == ()


def test_the_default_diffuse_is_white_under_a_diffuse_map():
    """A texture given without a colour is drawn as it is (the renderer multiplies it by
    diffuse); a colour given is kept; without a map the default stays the grey of faces
    without a material."""
    tex = Texture(np.zeros((2, 2, 3), np.uint8))
    assert Material(diffuse_map=tex).diffuse == (1.0, 1.0, 1.0) == rasterkit.material.MAPPED_DIFFUSE
    assert Material(diffuse_map=tex, diffuse=(0.8, 0.8, 0.8)).diffuse == (0.8, 0.8, 0.8)
    assert Material(diffuse=(0.25, 0.5, 1)).diffuse == (0.25, 0.5, 1.0)
    assert Material(normal_map=tex, specular_map=tex, opacity_map=tex).diffuse == DEFAULT_DIFFUSE
    assert Material(diffuse=None) == Material() and Material(diffuse=None, diffuse_map=tex) == Material(diffuse_map=tex)
    # resolved once: replace keeps the colour unless asked to choose it again
    assert dataclasses.replace(Material(), diffuse_map=tex).diffuse == DEFAULT_DIFFUSE
    assert dataclasses.replace(Material(), diffuse_map=tex, diffuse=None).diffuse == (1.0, 1.0, 1.0)
    assert dataclasses.replace(Material(diffuse_map=tex), diffuse_map=None).diffuse == (1.0, 1.0, 1.0)


def test_values_are_stored_as_floats_and_tuples():
    m = Material("brick", diffuse=np.array([1, 0.5, 0]), specular=[1, 1, 1], shininess=np.int64(8), opacity=1,
                 emission=(2, 0, 0.5), bump_scale=-2)
    assert (m.diffuse, m.specular, m.shininess, m.opacity, m.emission, m.bump_scale) == \
        ((1.0, 0.5, 0.0), (1.0, 1.0, 1.0), 8.0, 1.0, (2.0, 0.0, 0.5), -2.0)
    assert all(type(v) is float for v in m.diffuse + (m.shininess, m.opacity))


def test_textures_are_shared_objects():
    tex = Texture(np.zeros((2, 2, 3), np.uint8))
    m = Material(diffuse_map=tex, normal_map=tex.replace(srgb=False))
    assert m.diffuse_map is tex and m.textures == (tex, m.normal_map)
    assert m == Material(diffuse_map=tex, normal_map=m.normal_map)
    assert m != Material(diffuse_map=Texture(np.zeros((2, 2, 3), np.uint8)), normal_map=m.normal_map)
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.opacity = 0.5


@pytest.mark.parametrize("field,value,error,match", [
    ("name", None, TypeError, "name must be a string"),
    ("diffuse", (1, 1), TypeError, r"diffuse must be \(r, g, b\)"),
    ("diffuse", (1.5, 0, 0), ValueError, r"diffuse must lie in \[0, 1\]"),
    ("specular", (0, -0.1, 0), ValueError, r"specular must lie in \[0, 1\]"),
    ("emission", (0, -1, 0), ValueError, r"emission must lie in \[0, inf\)"),
    ("emission", (0, math.inf, 0), ValueError, "finite"),
    ("diffuse", "red", TypeError, "three numbers"),
    ("shininess", -1, ValueError, "at least 0"),
    ("shininess", math.nan, ValueError, "finite"),
    ("opacity", 1.5, ValueError, r"opacity must lie in \[0, 1\]"),
    ("opacity", True, TypeError, "number"),
    ("diffuse_map", np.zeros((2, 2, 3), np.uint8), TypeError, "rasterkit.Texture or None"),
    ("bump_scale", "1", TypeError, "bump_scale must be a number"),
    ("double_sided", 1, TypeError, "double_sided must be True or False"),
])
def test_bad_values_are_refused(field, value, error, match):
    with pytest.raises(error, match=match):
        Material(**{field: value})


def test_double_sided_is_recorded_and_off_by_default():
    """glTF's doubleSided: kept on the material (False unless asked)."""
    assert Material().double_sided is False
    assert Material(double_sided=True).double_sided is True
    assert dataclasses.replace(Material("a"), double_sided=True) != Material("a")
