"""Every real model of ../shared/models loads and renders in every mode.

The models are other people's files and are not part of the repository: these tests skip,
with the reason, when the folder is absent (a user's clone does not have it).
"""

import numpy as np
import pytest

import rasterkit
from support.paths import MODELS, needs_models

NAMES = sorted(p.name for p in MODELS.glob("*.obj")) if MODELS.is_dir() else []


@needs_models
def test_the_shared_folder_has_the_27_models():
    assert len(NAMES) == 27


@needs_models
@pytest.mark.parametrize("name", NAMES)
def test_model_renders_in_every_mode(name):
    mesh = rasterkit.load_obj(MODELS / name)
    camera = rasterkit.Camera.frame(*mesh.bounding_sphere(), width=96, height=72)
    images = {}
    for mode in ("wire", "hidden", "solid", "solid+wire"):
        fb = rasterkit.render(mesh, camera, mode=mode, background="white")
        drawn = np.any(fb.color != 255, axis=2)
        assert drawn.any(), f"{name}: nothing drawn in {mode} mode"
        images[mode] = drawn
    # hidden lines are a subset of all lines, and edges drawn over the shading add pixels only
    assert np.all(images["hidden"] <= images["wire"])
    assert np.all(images["solid"] <= images["solid+wire"])
