"""``ground="shadow"``: a ground that shows only what it catches — black of the opacity of the
light it misses (shadows, ambient occlusion) over the background — against the same frame
drawn over a white ground with and without shadows (the light missed is their ratio)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import rasterkit as rk
from support.reference_lighting import srgb_to_linear

MESH = rk.shapes.demo()
CENTRE, RADIUS = MESH.bounding_sphere()
CAMERA = rk.Camera.frame(CENTRE, RADIUS, width=240, height=180)
LIGHTS = [rk.Light.directional((-0.4, -1.0, -0.3), shadows=True), rk.Light.spot(
    (1.5, 3.0, 2.0), (-0.4, -1.0, -0.6), 50.0, 0.3, intensity=12.0, shadows=True), rk.Light.ambient("white", 0.1)]


def render(**options):
    return rk.render(MESH, CAMERA, "solid", shading="phong", lights=LIGHTS, ids=True, **options)


def test_the_opacity_is_the_light_the_ground_misses():
    caught = render(ground="shadow")
    shadowed = render(ground="white")
    unshadowed = rk.render(MESH, CAMERA, "solid", shading="phong", ids=True, ground="white",
                           lights=[replace(light, shadows=False) for light in LIGHTS])
    ground = caught.object_ids == 1
    assert ground.sum() > 10000
    # the shadowed frame over the unshadowed one, in linear light: what reaches the ground
    reached = (srgb_to_linear(shadowed.color[ground] / 255.0).sum(axis=1)
               / srgb_to_linear(unshadowed.color[ground] / 255.0).sum(axis=1))
    expected = 255.0 * (1.0 - np.clip(reached, 0.0, 1.0))
    assert caught.color.shape[2] == 4
    assert np.abs(caught.color[ground][:, 3] - expected).max() <= 2.0
    assert (caught.color[ground][:, :3] == 0).all()  # black over a transparent background
    assert (expected > 200).sum() > 500 and (expected < 1).sum() > 5000  # shadows, and open ground


def test_the_model_is_drawn_as_over_any_ground_and_the_rest_is_transparent():
    caught = render(ground="shadow")
    over_white = render(ground="white")
    model = caught.object_ids == 0
    assert model.sum() > 5000
    assert (caught.color[model][:, :3] == over_white.color[model]).all()
    assert (caught.color[model][:, 3] == 255).all()
    assert (caught.color[caught.object_ids == -1] == 0).all()


def test_over_an_opaque_background_the_shadow_is_composited():
    caught = render(ground="shadow")
    over = render(ground="shadow", background=(200, 220, 240))
    ground = caught.object_ids == 1
    a = caught.color[ground][:, 3:4] / 255.0
    expected = np.array([200, 220, 240]) * (1.0 - a)
    assert over.color.shape[2] == 3
    assert np.abs(over.color[ground].astype(float) - expected).max() <= 1.0


def test_without_shadows_the_ground_shows_its_ambient_occlusion_or_nothing():
    plain = rk.render(MESH, CAMERA, "solid", ground="shadow", ids=True)
    assert (plain.color[plain.object_ids == 1] == 0).all()  # nothing caught: fully transparent
    occluded = rk.render(MESH, CAMERA, "solid", ground="shadow", ids=True, ao=True)
    ground = occluded.object_ids == 1
    assert np.abs(occluded.color[ground][:, 3] - 255.0 * (1.0 - occluded.ao[ground])).max() <= 0.5
    assert (occluded.color[ground][:, 3] > 50).sum() > 100


def test_the_ids_are_only_kept_when_asked():
    assert rk.render(MESH, CAMERA, "solid", ground="shadow").ids is None


@pytest.mark.parametrize("bad", ["shadows", "nocolour", 3])
def test_a_ground_is_a_colour_or_shadow(bad):
    with pytest.raises((TypeError, ValueError), match="ground"):
        rk.RenderOptions(ground=bad)
