"""What a notebook shows: a framebuffer as PNG, a turntable as an inline animation, a vector
drawing as SVG."""

from __future__ import annotations

import base64
import io
import math
import re

import numpy as np
import pytest
from PIL import Image

import rasterkit as rk
from rasterkit.transform import rotate_axis


def test_a_turntable_is_the_renders_of_the_spun_model_and_shows_as_an_inline_apng(tmp_path):
    mesh = rk.shapes.cube()
    camera = rk.Camera.look_at((2.0, 1.5, 3.0), (0, 0, 0), width=40, height=30)
    options = rk.RenderOptions(mode="solid")
    spin = rk.turntable(mesh, camera, frames=3, options=options, fps=10)  # 120°: no two alike
    assert len(spin) == 3 and repr(spin) == "Animation(3 frames, 40x30, 10 fps)"
    center = mesh.bounding_sphere()[0]
    for k, frame in enumerate(spin):  # each frame: the model turned by k thirds about its centre
        turned = rk.Scene(camera).add(mesh, rotate_axis(2 * math.pi * k / 3, (0, 1, 0), center))
        np.testing.assert_array_equal(frame, rk.render(turned, options=options).color)
    html = spin._repr_html_()
    data = base64.b64decode(re.search(r'src="data:image/png;base64,([^"]+)"', html).group(1))
    with Image.open(io.BytesIO(data)) as apng:
        assert apng.n_frames == 3 and apng.info["duration"] == 100
        for k in range(3):
            apng.seek(k)
            np.testing.assert_array_equal(np.asarray(apng.convert("RGB")), spin[k])
    spin.save(tmp_path / "spin.gif")
    assert Image.open(tmp_path / "spin.gif").n_frames == 3


def test_a_turntable_refuses_what_it_cannot_draw():
    with pytest.raises(ValueError, match="frames must be"):
        rk.turntable(rk.shapes.cube(), frames=0)
    with pytest.raises(TypeError, match="camera must be"):
        rk.turntable(rk.shapes.cube(), camera="side", frames=2)
    with pytest.raises(ValueError, match="at least one frame"):
        rk.image.movie.Animation([])


def test_a_vector_drawing_is_text_that_a_notebook_shows_as_svg():
    mesh = rk.shapes.cube()
    camera = rk.Camera.look_at((2.0, 1.5, 3.0), (0, 0, 0), width=40, height=30)
    svg = rk.render_svg(mesh, camera)
    assert isinstance(svg, str) and svg._repr_svg_() == str(svg) and svg.startswith("<?xml")
    assert rk.render(mesh, camera, "solid")._repr_png_().startswith(b"\x89PNG")
