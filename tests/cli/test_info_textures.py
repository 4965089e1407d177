"""``rasterkit info`` lists the textures a model's materials use, and a missing one as a warning."""

from __future__ import annotations

import numpy as np
from PIL import Image

from rasterkit.cli import main

OBJ = """mtllib look.mtl
v 0 0 0
v 1 0 0
v 0 1 0
vt 0 0
vt 1 0
vt 0 1
usemtl painted
f 1/1 2/2 3/3
usemtl lost
f 1/1 3/3 2/2
"""
MTL = """newmtl painted
Kd 1 1 1
map_Kd tex dir/paint job.png
newmtl lost
map_Kd nowhere.png
"""


def test_info_names_found_textures_and_warns_of_missing_ones(tmp_path, capsys):
    (tmp_path / "tex dir").mkdir()
    Image.fromarray(np.zeros((6, 10, 3), np.uint8)).save(tmp_path / "tex dir" / "paint job.png")
    (tmp_path / "look.mtl").write_text(MTL)
    (tmp_path / "m.obj").write_text(OBJ)
    assert main(["info", str(tmp_path / "m.obj")]) == 0
    out = capsys.readouterr().out
    assert "  materials 2: painted, lost" in out
    assert "  textures  1\n    paint job.png: 10x6, map_Kd of painted\n" in out
    warnings = out[out.index("  warnings"):]
    assert "nowhere.png" in warnings and "look.mtl" in warnings


def test_load_obj_reads_whole_materials_unless_told_not_to(tmp_path):
    import rasterkit

    (tmp_path / "tex dir").mkdir()
    Image.fromarray(np.zeros((6, 10, 3), np.uint8)).save(tmp_path / "tex dir" / "paint job.png")
    (tmp_path / "look.mtl").write_text(MTL)
    (tmp_path / "m.obj").write_text(OBJ)
    plain = rasterkit.load_obj(tmp_path / "m.obj", textures=False)
    assert plain.materials == () and plain.warnings == ()
    whole = rasterkit.load_obj(tmp_path / "m.obj")  # the default: materials whole, textures read
    assert [m.name for m in whole.materials] == ["painted", "lost"]
    assert whole.materials[0].diffuse_map.image.shape == (6, 10, 3) and whole.materials[1].diffuse_map is None
    assert len(whole.warnings) == 1 and "nowhere.png" in whole.warnings[0]
    np.testing.assert_array_equal(whole.face_materials, [0, 1])
