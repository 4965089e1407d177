"""Vector drawings of real models against the raster hidden-line mode, and read by real SVG
software (vpype, resvg) when it is installed (the ``test`` extra)."""

from __future__ import annotations

import struct
import zlib

import numpy as np
import pytest

from rasterkit import Camera, load_obj, render, render_svg, shapes
from support.paths import MODELS, needs_models
from support.svg_raster import f_score, rasterise, svg_segments

#: Models of different kinds: a scan, a CAD part, quads, an open mesh, open boxes, a low-poly figure.
KINDS = {"armadillo": "scan", "fandisk": "CAD", "spot_quadrangulated": "quads", "teapot": "open mesh",
         "CornellBox-Original": "open boxes", "beetle": "low-poly"}


@needs_models
@pytest.mark.parametrize("name", sorted(KINDS))
def test_svg_agrees_with_the_hidden_line_png(name):
    mesh = load_obj(MODELS / f"{name}.obj")
    camera = Camera.frame(*mesh.bounding_sphere(), width=800, height=600)
    drawn = rasterise(svg_segments(render_svg(mesh, camera, mode="hidden")), 800, 600)
    png = (render(mesh, camera, "hidden").color != 255).any(axis=2)
    assert f_score(drawn, png) >= 0.97


@needs_models
@pytest.mark.parametrize("name", ["fandisk", "stanford-bunny"])
def test_feature_svg_agrees_with_the_feature_png(name):
    mesh = load_obj(MODELS / f"{name}.obj")
    camera = Camera.frame(*mesh.bounding_sphere(), width=800, height=600)
    drawn = rasterise(svg_segments(render_svg(mesh, camera, mode="hidden", edges="feature")), 800, 600)
    png = (render(mesh, camera, "hidden", edges="feature").color != 255).any(axis=2)
    assert f_score(drawn, png) >= 0.97


def _torus_svg(tmp_path, hidden="dashed"):
    mesh = shapes.torus(rings=48, sides=24)
    camera = Camera.look_at((0.3, 2.0, 3.0), (0, 0, 0), width=400, height=300)
    path = tmp_path / "torus.svg"
    path.write_text(render_svg(mesh, camera, mode="hidden", edges="all", hidden=hidden))
    return path


def test_vpype_reads_merges_sorts_and_keeps_the_layers(tmp_path):
    vpype_cli = pytest.importorskip("vpype_cli", reason="vpype is not installed (pip install rasterkit[test])")
    src = _torus_svg(tmp_path)
    out = tmp_path / "x.svg"
    doc = vpype_cli.execute(f"read '{src}' linemerge linesort write '{out}'")
    names = [doc.layers[k].property("vp_name") for k in sorted(doc.layers)]
    assert names == ["visible", "hidden"]
    assert all(len(doc.layers[k]) > 0 for k in doc.layers)
    assert 'inkscape:label="hidden"' in out.read_text()


def _png_alpha(data: bytes) -> np.ndarray:
    """The alpha channel (H, W) of an 8-bit RGBA, non-interlaced PNG (what resvg writes)."""
    pos, chunks = 8, []
    while pos < len(data):
        size, kind = struct.unpack(">I4s", data[pos:pos + 8])
        chunks.append((kind, data[pos + 8:pos + 8 + size]))
        pos += 12 + size
    header = dict(chunks)[b"IHDR"]
    width, height, depth, color = struct.unpack(">IIBB", header[:10])
    assert (depth, color) == (8, 6)
    raw = zlib.decompress(b"".join(c for k, c in chunks if k == b"IDAT"))
    stride = width * 4
    rows = np.zeros((height, stride), np.int64)
    prev = np.zeros(stride, np.int64)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1).astype(np.int64)
        cur = np.zeros(stride, np.int64)
        for x in range(stride):
            a = cur[x - 4] if x >= 4 else 0
            b, c = prev[x], prev[x - 4] if x >= 4 else 0
            if kind == 0:
                pred = 0
            elif kind == 1:
                pred = a
            elif kind == 2:
                pred = b
            elif kind == 3:
                pred = (a + b) // 2
            else:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else b if pb <= pc else c
            cur[x] = (line[x] + pred) & 255
        rows[y], prev = cur, cur
    return rows.reshape(height, width, 4)[:, :, 3]


def test_resvg_draws_it_and_the_hidden_lines_are_dashed(tmp_path):
    resvg = pytest.importorskip("resvg_py", reason="resvg-py is not installed (pip install rasterkit[test])")
    path = _torus_svg(tmp_path)
    text = path.read_text()
    drawn = _png_alpha(bytes(resvg.svg_to_bytes(svg_string=text))) > 64
    ours = rasterise(np.vstack([svg_segments(text, "visible"), svg_segments(text, "hidden")]), 400, 300)
    assert f_score(drawn, ours) >= 0.9
    # only the hidden layer, dashed and then solid: dashes 4 on, 3 off cover about 4/7 of it
    start, end = text.index('<g id="layer-visible"'), text.index('<g id="layer-hidden"')
    hidden_only = text[:start] + text[end:]
    dashed = (_png_alpha(bytes(resvg.svg_to_bytes(svg_string=hidden_only))) > 64).sum()
    solid = (_png_alpha(bytes(resvg.svg_to_bytes(svg_string=hidden_only.replace("stroke-dasharray", "x-dash")))) > 64).sum()
    assert 0.4 < dashed / solid < 0.8
