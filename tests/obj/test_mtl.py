"""Reading whole materials from .mtl files (rasterkit.obj.materials.read_libraries and
make_materials, with rasterkit.obj.mtl and rasterkit.obj.textures): every statement and map option, texture paths,
shared textures, and each way a texture can fail (one warning naming the .mtl line and the
file). The face colours that load_obj makes are not changed by any of it."""

from __future__ import annotations

import io
import os
import struct
import zlib

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit import limits
from rasterkit.material.images import decoding_bytes
from rasterkit.material.mipmaps import mipmaps_bytes
from rasterkit.obj.document import Document
from rasterkit.obj.errors import Report
from rasterkit.obj.materials import make_materials, read_libraries
from rasterkit.obj.textures import TEXTURE_WARNINGS

TRIANGLE = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"


def read(folder, mtl, uses=("m",)):
    """The materials and warnings of a model in ``folder`` whose library ``m.mtl`` is ``mtl``
    and whose faces use the materials ``uses``."""
    (folder / "m.mtl").write_bytes(mtl.encode() if isinstance(mtl, str) else mtl)
    text = "mtllib m.mtl\n" + TRIANGLE + "".join(f"usemtl {name}\nf 1 2 3\n" for name in uses)
    (folder / "model.obj").write_text(text)
    doc = Document.read(str(folder / "model.obj"))
    report = Report(doc.name)
    return make_materials(read_libraries(doc, report, whole=True), report), tuple(report.warnings)


def png(path, colour=(10, 20, 30), size=(4, 2), mode="RGB"):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    Image.new(mode, size, colour).save(path)
    return path


@pytest.fixture
def restore_limits():
    yield
    limits.set_memory_limit(None)


# --- statements -----------------------------------------------------------------------------

def test_every_colour_statement(tmp_path):
    materials, warnings = read(tmp_path, "newmtl m\nKd 1 0.5 0.25\nKs 0.5\nKe 2 0 0.5\nNs 96\nd 0.75\nillum 2\nKa 1 1 1\n")
    m = materials["m"]
    assert (m.name, m.diffuse, m.specular, m.emission, m.shininess, m.opacity) == \
        ("m", (1.0, 0.5, 0.25), (0.5, 0.5, 0.5), (2.0, 0.0, 0.5), 96.0, 0.75)
    assert warnings == ()


def test_defaults_of_a_bare_material(tmp_path):
    materials, _ = read(tmp_path, "newmtl m\n")
    assert materials["m"] == rasterkit.Material("m")


@pytest.mark.parametrize("lines,opacity", [("Tr 0.25", 0.75), ("Tr 0", 1.0), ("Tr 1", 1.0), ("d 0.5\nTr 0.25", 0.5),
                                           ("Tr 0.25\nd 0.5", 0.5), ("d -halo 0.3", 0.3), ("d 1.5", 1.0), ("d 1", 1.0)])
def test_opacity_from_d_and_tr(tmp_path, lines, opacity):
    materials, warnings = read(tmp_path, f"newmtl m\n{lines}\n")
    assert materials["m"].opacity == pytest.approx(opacity) and warnings == ()


def test_a_diffuse_map_without_kd_is_drawn_white(tmp_path):
    """map_Kd without Kd: diffuse (1, 1, 1), the texture as it is; an explicit Kd is kept as
    written; a map that cannot be read leaves the default grey. The face colours (what an
    untextured render draws) keep the grey of a material without Kd."""
    png(tmp_path / "t.png")
    mtl = ("newmtl bare\nmap_Kd t.png\nnewmtl grey\nKd 0.8 0.8 0.8\nmap_Kd t.png\n"
           "newmtl dark\nmap_Kd t.png\nKd 0.25 0.5 0.75\nnewmtl lost\nmap_Kd gone.png\n")
    materials, warnings = read(tmp_path, mtl, uses=("bare", "grey", "dark", "lost"))
    assert [materials[n].diffuse for n in ("bare", "grey", "dark", "lost")] == \
        [(1.0, 1.0, 1.0), (0.8, 0.8, 0.8), (0.25, 0.5, 0.75), (0.8, 0.8, 0.8)]
    assert materials["bare"].diffuse_map is materials["grey"].diffuse_map and materials["lost"].diffuse_map is None
    assert len(warnings) == 1 and "'gone.png' cannot be read" in warnings[0]
    mesh = rasterkit.load_obj(tmp_path / "model.obj", textures=True)
    assert [m.diffuse for m in mesh.materials] == [materials[n].diffuse for n in mesh.material_names]
    np.testing.assert_array_equal(mesh.face_colors, np.float32([[0.8] * 3, [0.8] * 3, [0.25, 0.5, 0.75], [0.8] * 3]))


def test_values_are_clipped_as_kd_is(tmp_path):
    materials, _ = read(tmp_path, "newmtl m\nKd 2 -1 0.5\nKs 3\nNs -4\nKe 5 5 5\n")
    m = materials["m"]
    assert (m.diffuse, m.specular, m.shininess, m.emission) == ((1.0, 0.0, 0.5), (1.0, 1.0, 1.0), 0.0, (5.0, 5.0, 5.0))


def test_only_used_materials_and_later_definitions(tmp_path):
    mtl = "newmtl m\nKd 1 0 0\nmap_Kd gone.png\nnewmtl unused\nmap_Kd also-gone.png\nnewmtl m\nKd 0 1 0\n"
    materials, warnings = read(tmp_path, mtl)
    assert list(materials) == ["m"] and materials["m"].diffuse == (0.0, 1.0, 0.0)
    assert materials["m"].diffuse_map is None and warnings == ()  # the first m's map went with it


def test_comments_cr_line_breaks_and_tabs(tmp_path):
    png(tmp_path / "t.png")
    materials, warnings = read(tmp_path, b"newmtl\tm # the name\rKd 1 0 0 # red\rmap_Kd\tt.png   # a comment\r")
    assert materials["m"].diffuse == (1.0, 0.0, 0.0) and materials["m"].diffuse_map.width == 4
    assert warnings == ()


def test_unreadable_statements_are_one_warning_per_library(tmp_path):
    mtl = ("newmtl m\nKs a b c\nNs\nd nan\nKe 1 2\nmap_Kd -s x t.png\nmap_Kd -clamp maybe t.png\nmap_Ks -bm\n"
           "map_d -s 1 2\nnorm\nKd bad\nTr inf\n")
    materials, warnings = read(tmp_path, mtl)
    assert warnings == (f"{tmp_path / 'm.mtl'}:11: cannot read Kd 'Kd bad'",
                        f"{tmp_path / 'm.mtl'}:2: cannot read 'Ks a b c' (and 9 more such lines)")
    assert materials["m"] == rasterkit.Material("m")


# --- maps and their options -------------------------------------------------------------------

def test_every_map_and_option(tmp_path):
    for name in ("c.png", "o.png", "s.png", "n.png", "h.png"):
        png(tmp_path / name)
    mtl = ("newmtl m\n"
           "map_Kd -s 2 3 1 -o 0.5 0.25 0 -clamp on -blendu off -blendv on -boost 2 -mm 0 1 -t 0 0 0 "
           "-texres 512 -imfchan r -type sphere -cc on -bm 4 c.png\n"
           "map_d -s 2 o.png\nmap_Ks -o 0.5 -clamp off s.png\nmap_Bump -bm 0.5 n.png\n")
    m = read(tmp_path, mtl)[0]["m"]
    kd, d, ks, bump = m.diffuse_map, m.opacity_map, m.specular_map, m.normal_map
    assert (kd.scale, kd.offset, kd.wrap, kd.srgb) == ((2.0, 3.0), (0.5, 0.25), "clamp", True)
    assert (d.scale, d.offset, d.wrap, d.srgb) == ((2.0, 1.0), (0.0, 0.0), "repeat", False)
    assert (ks.scale, ks.offset, ks.wrap, ks.srgb) == ((1.0, 1.0), (0.5, 0.0), "repeat", False)
    assert (bump.srgb, m.bump_scale) == (False, 0.5)
    assert kd.name == str(tmp_path / "c.png") and kd.filter == "trilinear"


@pytest.mark.parametrize("keyword", ["map_Bump", "map_bump", "bump", "norm", "BUMP"])
def test_bump_keywords_fill_the_normal_map(tmp_path, keyword):
    png(tmp_path / "n.png")
    m = read(tmp_path, f"newmtl m\n{keyword} -bm 2 n.png\nMAP_KD n.png\n")[0]["m"]
    assert m.normal_map is not None and m.bump_scale == 2.0 and m.diffuse_map.srgb


@pytest.mark.parametrize("written,stored", [
    ("fuze uv.png", "fuze uv.png"), ("two  spaces.png", "two  spaces.png"), ("textures\\sub\\a.png", "textures/sub/a.png"),
    ("textures/sub/a.png", "textures/sub/a.png"), ('"quoted name.png"', "quoted name.png"),
    ("C:\\Users\\someone\\model\\beside.png", "beside.png"), ("../up/x.png", "../up/x.png"),
])
def test_texture_paths(tmp_path, written, stored):
    folder = tmp_path / "model"
    png(folder / stored)
    m = read(folder, f"newmtl m\nmap_Kd -s 1 1 {written}\n")[0]["m"]
    assert m.diffuse_map is not None and os.path.samefile(m.diffuse_map.name, folder / stored)


def test_an_absolute_path(tmp_path):
    path = png(tmp_path / "elsewhere" / "abs.png")
    assert read(tmp_path, f"newmtl m\nmap_Kd {path}\n")[0]["m"].diffuse_map.name == str(path)


def test_textures_are_opened_once_and_shared(tmp_path, monkeypatch):
    import rasterkit.obj.textures as textures

    png(tmp_path / "t.png")
    opened = []
    real = textures.read_image
    monkeypatch.setattr(textures, "read_image", lambda path, spent: opened.append(path) or real(path, spent))
    mtl = ("newmtl a\nmap_Kd t.png\nmap_d t.png\nnewmtl b\nmap_Kd ./t.png\nnewmtl c\nmap_Kd -s 2 t.png\n")
    materials, warnings = read(tmp_path, mtl, uses=("a", "b", "c"))
    a, b, c = (materials[n] for n in "abc")
    assert len(opened) == 1 and warnings == ()
    assert a.diffuse_map is b.diffuse_map  # the same file and settings: one object
    assert c.diffuse_map is not a.diffuse_map and c.diffuse_map.image is a.diffuse_map.image
    assert a.opacity_map.image is a.diffuse_map.image and not a.opacity_map.srgb
    assert c.diffuse_map.mipmaps is a.diffuse_map.mipmaps


# --- textures that cannot be read -------------------------------------------------------------

def _huge_png(width, height):
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(b"")) + chunk(b"IEND", b""))


def _noise(fmt):
    out = io.BytesIO()
    Image.fromarray(np.random.default_rng(0).integers(0, 256, (40, 40, 3), dtype=np.uint8)).save(out, fmt)
    return out.getvalue()


@pytest.mark.parametrize("data,reason", [
    (None, "No such file or directory"),
    (b"", "not a PNG, JPEG, TGA or BMP image"),
    (_noise("PNG")[:300], "cannot decode the PNG image"),
    (_noise("JPEG")[:len(_noise("JPEG")) * 3 // 4], "cannot decode the JPEG image"),
    (_noise("TGA")[:1000], "cannot decode the TGA image"),
    (b"\x89PNG\r\n\x1a\n garbage", "cannot read the PNG header"),
    ("directory", "not a regular file (a directory)"),
])
def test_a_bad_texture_is_one_warning_and_the_colour_stays(tmp_path, data, reason):
    if data == "directory":
        (tmp_path / "t x.png").mkdir()
    elif data is not None:
        (tmp_path / "t x.png").write_bytes(data)
    mtl = "# library\nnewmtl m\nKd 0.5 0.5 0.5\nmap_Kd -clamp on t x.png\nnewmtl n\nmap_Kd t x.png\n"
    materials, warnings = read(tmp_path, mtl, uses=("m", "n"))
    assert materials["m"].diffuse_map is None and materials["n"].diffuse_map is None
    assert materials["m"].diffuse == (0.5, 0.5, 0.5)
    assert len(warnings) == 1, warnings
    assert warnings[0].startswith(f"{tmp_path / 'm.mtl'}:4: map_Kd texture 't x.png' cannot be read: ")
    assert reason in warnings[0] and warnings[0].endswith("; drawn without it")


def test_many_bad_textures_are_counted(tmp_path):
    mtl = "newmtl m\n" + "".join(f"map_Kd gone{k}.png\nnewmtl m{k}\n" for k in range(8))
    materials, warnings = read(tmp_path, mtl, uses=["m"] + [f"m{k}" for k in range(7)])
    assert len(warnings) == TEXTURE_WARNINGS + 1
    assert warnings[-1] == f"{tmp_path / 'm.mtl'}:{2 + 2 * TEXTURE_WARNINGS}: 3 more textures cannot be read; drawn without them"


def test_a_decompression_bomb_is_a_warning_before_decoding(tmp_path, restore_limits, monkeypatch):
    from PIL import ImageFile

    (tmp_path / "bomb.png").write_bytes(_huge_png(40000, 30000))
    monkeypatch.setattr(ImageFile.ImageFile, "load", lambda self: pytest.fail("decoded"))
    limits.set_memory_limit("64M")
    materials, warnings = read(tmp_path, "newmtl m\nmap_Kd bomb.png\n")
    assert materials["m"].diffuse_map is None
    assert warnings == (f"{tmp_path / 'm.mtl'}:2: map_Kd texture 'bomb.png' cannot be read: decoding the 40000x30000 "
                        f"PNG image needs about {limits.format_bytes(decoding_bytes(40000, 30000))} of memory, "
                        "more than the limit of 64 MiB (set by --max-memory "
                        "or rasterkit.limits.set_memory_limit); drawn without it",)


def test_textures_share_one_memory_budget(tmp_path, restore_limits):
    png(tmp_path / "a.png", size=(64, 64))
    png(tmp_path / "b.png", size=(64, 64))
    one = decoding_bytes(64, 64)
    kept = 64 * 64 * 3 + mipmaps_bytes(64, 64, 3)
    limits.set_memory_limit(max(one, kept + one - 1))
    materials, warnings = read(tmp_path, "newmtl a\nmap_Kd a.png\nnewmtl b\nmap_Kd b.png\n", uses=("a", "b"))
    assert materials["a"].diffuse_map is not None and materials["b"].diffuse_map is None
    assert len(warnings) == 1 and "b.png" in warnings[0] and "needs about" in warnings[0]


def test_an_unknown_option_starts_the_file_name(tmp_path):
    materials, warnings = read(tmp_path, "newmtl m\nmap_Kd -foo t.png\n")
    assert "map_Kd texture '-foo t.png' cannot be read" in warnings[0]


# --- load_obj is unchanged --------------------------------------------------------------------

def test_load_obj_face_colours_agree_and_no_texture_is_opened(tmp_path):
    png(tmp_path / "t.png")
    mtl = "newmtl red\nKd 1 0 0\nmap_Kd missing.png\nnewmtl grey\nKd 0.5\nKs 1 1 1\nnewmtl plain\n"
    materials, _ = read(tmp_path, mtl, uses=("red", "grey", "plain"))
    mesh = rasterkit.load_obj(tmp_path / "model.obj", textures=False)
    assert mesh.warnings == () and mesh.material_names == ("red", "grey", "plain")
    np.testing.assert_array_equal(mesh.face_colors, np.float32([materials[n].diffuse for n in ("red", "grey", "plain")]))


@pytest.mark.parametrize("textures", [False, True])
def test_each_library_is_read_once_per_load(tmp_path, monkeypatch, textures):
    from rasterkit.obj import materials as reader

    png(tmp_path / "t.png")
    (tmp_path / "b.mtl").write_text("newmtl b\nKd 0 0 1\n")
    (tmp_path / "m.mtl").write_text("newmtl m\nKd 1 0 0\nmap_Kd t.png\n")
    (tmp_path / "model.obj").write_text("mtllib m.mtl b.mtl\nmtllib m.mtl\n" + TRIANGLE +
                                        "usemtl m\nf 1 2 3\nusemtl b\nf 1 2 3\n")
    read_paths = []
    original = reader.read_file
    monkeypatch.setattr(reader, "read_file", lambda path: read_paths.append(os.path.basename(path)) or original(path))
    mesh = rasterkit.load_obj(tmp_path / "model.obj", textures=textures)
    assert sorted(read_paths) == ["b.mtl", "m.mtl"]
    np.testing.assert_array_equal(mesh.face_colors, np.float32([[1, 0, 0], [0, 0, 1]]))
    assert [m.diffuse_map is not None for m in mesh.materials] == ([True, False] if textures else [])


def test_load_obj_warns_in_one_order(tmp_path):
    """Each kind of warning about materials once, in the documented order: unreadable Kd
    lines, unreadable libraries, materials no library defines, other unreadable statements,
    textures that cannot be read."""
    (tmp_path / "m.mtl").write_text("newmtl m\nKs x\nKd y\nmap_Kd gone.png\n")
    (tmp_path / "model.obj").write_text("mtllib m.mtl lost.mtl\n" + TRIANGLE + "usemtl m\nf 1 2 3\nusemtl q\nf 1 2 3\n")
    mtl, obj = tmp_path / "m.mtl", tmp_path / "model.obj"
    plain = rasterkit.load_obj(obj, textures=False)
    whole = rasterkit.load_obj(obj)
    assert plain.warnings == (f"{mtl}:3: cannot read Kd 'Kd y'",
                              f"{obj}:1: material library 'lost.mtl' cannot be read: No such file or directory",
                              f"{obj}:7: 1 material not in the material libraries: 'q'")
    assert whole.warnings[:3] == plain.warnings and len(whole.warnings) == 5
    assert whole.warnings[3] == f"{mtl}:2: cannot read 'Ks x'"
    assert whole.warnings[4].startswith(f"{mtl}:4: map_Kd texture 'gone.png' cannot be read: ")
    np.testing.assert_array_equal(whole.face_colors, plain.face_colors)


# --- the public models ------------------------------------------------------------------------

def test_fuze_names_a_texture_with_a_space(models_dir):
    path = models_dir / "formats" / "obj" / "fuze" / "fuze.obj"
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    doc = Document.read(str(path))
    report = Report(doc.name)
    (m,) = make_materials(read_libraries(doc, report, whole=True), report).values()
    assert report.warnings == []
    assert m.name == "a-super-duper-material" and m.diffuse == (1.0, 1.0, 1.0) and m.specular == (1.0, 1.0, 1.0)
    assert m.opacity == 1.0 and m.shininess == 0.0  # "Tr 1": MeshLab's opaque
    assert os.path.basename(m.diffuse_map.name) == "fuze uv.jpg" and m.diffuse_map.image.shape == (1024, 1024, 3)


def test_african_head_maps(models_dir, tmp_path):
    folder = models_dir / "formats" / "obj" / "african_head"
    if not folder.is_dir():
        pytest.skip(f"{folder} is absent")
    mtl = (f"newmtl head\nmap_Kd {folder / 'african_head_diffuse.tga'}\nnorm {folder / 'african_head_nm.tga'}\n"
           f"map_Ks {folder / 'african_head_spec.tga'}\n")
    materials, warnings = read(tmp_path, mtl, uses=("head",))
    m = materials["head"]
    assert warnings == ()
    assert (m.diffuse_map.channels, m.diffuse_map.srgb) == (3, True)
    assert (m.normal_map.channels, m.normal_map.srgb) == (4, False)
    assert (m.specular_map.channels, m.specular_map.srgb) == (3, False)
    assert all(t.image.shape[:2] == (1024, 1024) for t in m.textures)
