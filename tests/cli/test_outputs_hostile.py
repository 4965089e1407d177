"""The files one command writes, under hostile paths: outputs that are one file (also through
a link or a case-folding file system), outputs that cannot be written (checked before
drawing, written all or none), names at the file system's length limit, symbolic links,
trailing slashes, contact sheets of images above Pillow's decompression-bomb limit, and a
full disk (every file named in one line, a batch that ends with its summary, never hangs)."""

import os
import stat
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit.runtime.notice import MESSAGE
from rasterkit.cli import main
from rasterkit.raster.framebuffer import Framebuffer
from support.hostile import run, run_python
from support.objfiles import TETRA

CUBE = ("v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
        "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n")


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    return code, [line for line in capsys.readouterr().err.splitlines() if line != MESSAGE]


def _files(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


@pytest.fixture
def model(tmp_path) -> Path:
    path = tmp_path / "m.obj"
    path.write_text(TETRA)
    return path


@pytest.fixture
def models(tmp_path) -> Path:
    folder = tmp_path / "models"
    folder.mkdir()
    (folder / "cube.obj").write_text(CUBE)
    (folder / "tetra.obj").write_text(TETRA)
    return folder


def _render(model, out, *extra, size="24x16"):
    return ["render", model, "-o", out, "--size", size, "--mode", "solid", *extra]


# --- outputs that are one file ----------------------------------------------------------------


def test_two_outputs_of_one_render_that_are_one_file_are_refused_before_drawing(tmp_path, model, capsys):
    (tmp_path / "link.png").symlink_to("a.png")
    cases = [
        (["-o", "a.png", "--depth", "a.png"], "-o and --depth would both be written to a.png"),
        (["-o", "a.png", "--depth", "./a.png"], "-o and --depth would both be written to ./a.png"),
        (["-o", "x.png", "--depth", "d.png", "--ids", "d.png", "--normals", "d.png"],
         "--depth and --normals would both be written to d.png"),
        (["-o", "a.png", "--ids", "link.png"], "-o and --ids would both be written to link.png"),
        (["-o", "sub/../a.png", "--normals", "a.png"], "-o and --normals would both be written to a.png"),
    ]
    (tmp_path / "sub").mkdir()
    os.chdir(tmp_path)
    for flags, message in cases:
        code, lines = _run(["render", model, *flags, "--size", "24x16"], capsys)
        assert (code, lines) == (2, [f"rasterkit: error: {message}"])
    assert _files(tmp_path) == ["link.png", "m.obj", "sub"]


def test_an_output_that_is_the_model_is_refused(tmp_path, capsys):
    model = tmp_path / "m.png"  # an OBJ file by its content
    model.write_text(TETRA)
    code, lines = _run(_render(model, model), capsys)
    assert (code, lines) == (2, [f"rasterkit: error: -o {model} would overwrite the model {model}"])
    assert model.read_text() == TETRA


def test_a_contact_sheet_over_an_image_of_the_batch_is_refused(tmp_path, models, capsys):
    out = tmp_path / "o"
    for sheet in (out / "cube.png", out / "x" / ".." / "tetra.png"):
        code, lines = _run(["render", models, "-o", out, "--contact-sheet", sheet], capsys)
        assert code == 2 and len(lines) == 1, lines
        assert lines[0].startswith(f"rasterkit: error: {models / sheet.name.replace('.png', '.obj')} and "
                                   f"--contact-sheet would both be written to {sheet}")
    assert not out.exists()  # nothing rendered, no manifest
    with pytest.raises(ValueError, match="would both be written to"):
        rasterkit.render_many(models, out, contact_sheet=out / "cube.png")
    assert not out.exists()


def test_names_that_differ_in_case_collide_only_where_the_file_system_folds_case(tmp_path, model, monkeypatch, capsys):
    from rasterkit.batch import outputs as _outputs

    os.chdir(tmp_path)
    monkeypatch.setattr(_outputs, "_folds_case", lambda folder: True)
    code, lines = _run(["render", model, "-o", "A.png", "--depth", "a.png", "--size", "24x16"], capsys)
    assert code == 2 and "-o and --depth would both be written to one file (A.png and a.png" in lines[0]
    monkeypatch.undo()
    folds = _outputs._folds_case(str(tmp_path))  # the real probe leaves nothing behind
    assert _files(tmp_path) == ["m.obj"]
    code, lines = _run(["render", model, "-o", "A.png", "--depth", "a.png", "--size", "24x16"], capsys)
    assert code == (2 if folds else 0)
    assert _files(tmp_path) == (["m.obj"] if folds else ["A.png", "a.png", "m.obj"])


# --- every output checked before drawing, written all or none ---------------------------------


def test_an_output_that_cannot_be_written_stops_the_render_before_any_file(tmp_path, model, capsys):
    os.chdir(tmp_path)
    Path("dir.png").mkdir()
    Path("old.npy").write_bytes(b"old")
    cases = [
        (["-o", "dir.png", "--depth", "d1.npy"], "dir.png: Is a directory"),
        (["-o", "pp.png", "--depth", "old.npy", "--ids", "nofolder/i.png"],
         "nofolder/i.png: folder 'nofolder' does not exist"),
        (["-o", "pp.png", "--normals", "m.obj/n.npy"], "m.obj/n.npy: 'm.obj' is not a folder"),
        (["-o", "pp.png", "--depth", "d.npy/"], "d.npy/: names a folder (it ends with a separator), not a file"),
    ]
    for flags, message in cases:
        code, lines = _run(["render", model, *flags, "--size", "24x16"], capsys)
        assert (code, lines) == (2, [f"rasterkit: error: {message}"])
    assert _files(tmp_path) == ["dir.png", "m.obj", "old.npy"] and Path("old.npy").read_bytes() == b"old"


def test_a_rename_that_fails_at_the_end_takes_the_files_written_before_it_away(tmp_path, model, monkeypatch, capsys):
    from rasterkit.image import atomic as _atomic

    replace = os.replace

    def fail_on_the_image(src, dst):
        if str(dst).endswith("x.png"):
            raise IsADirectoryError(21, "Is a directory", str(dst))
        replace(src, dst)

    monkeypatch.setattr(_atomic.os, "replace", fail_on_the_image)
    (tmp_path / "ids.npy").write_bytes(b"old")
    code, lines = _run(_render(model, tmp_path / "x.png", "--depth", tmp_path / "d.npy",
                               "--ids", tmp_path / "ids.npy"), capsys)
    assert (code, lines) == (2, [f"rasterkit: error: {model}: {tmp_path / 'x.png'}: Is a directory"])
    assert _files(tmp_path) == ["m.obj"]  # d.npy and ids.npy were renamed before x.png failed: removed


def test_several_outputs_get_the_mode_the_umask_gives(tmp_path, model):
    done = run_python(f"""
        import os, sys
        os.umask(0o027)
        from rasterkit.cli import main
        sys.exit(main({[str(a) for a in _render(model, tmp_path / "x.png", "--depth", tmp_path / "d.png",
                                                  "--normals", tmp_path / "n.npy")]!r}))
    """)
    assert done.code == 0, done.describe()
    for name in ("x.png", "d.png", "n.npy"):
        assert stat.S_IMODE((tmp_path / name).stat().st_mode) == 0o640, name


# --- names, links and folders -----------------------------------------------------------------


def test_a_name_as_long_as_the_file_system_takes_can_be_written(tmp_path, model, capsys):
    longest = os.pathconf(tmp_path, "PC_NAME_MAX")
    for name in ("a" * (longest - 4) + ".png", "é" * ((longest - 4) // 2) + ".png"):
        assert len(os.fsencode(name)) > longest - 14
        code, lines = _run(_render(model, tmp_path / name), capsys)
        assert (code, lines) == (0, [])
        with Image.open(tmp_path / name) as im:
            assert im.size == (24, 16)
        (tmp_path / name).unlink()
    too_long = "a" * (longest - 3) + ".png"
    code, lines = _run(_render(model, tmp_path / too_long), capsys)
    assert code == 2 and lines[0].endswith("File name too long") and ".tmp" not in lines[0]
    assert _files(tmp_path) == ["m.obj"]


def test_a_trailing_slash_names_a_folder_and_writes_nothing(tmp_path, model, capsys):
    code, lines = _run(_render(model, f"{tmp_path / 'x.png'}/"), capsys)
    assert (code, lines) == (2, [f"rasterkit: error: {tmp_path / 'x.png'}/: names a folder (it ends with a "
                                 f"separator), not a file"])
    for save in (lambda p: Framebuffer(4, 3).save(p), lambda p: rasterkit.image.save_npy(np.zeros(3), p)):
        with pytest.raises(IsADirectoryError, match="ends with a separator"):
            save(f"{tmp_path / 'x.png'}/")
    assert _files(tmp_path) == ["m.obj"]


def test_a_symbolic_link_is_written_through(tmp_path, model, capsys):
    (tmp_path / "real").mkdir()
    target = tmp_path / "real" / "image.png"
    target.write_bytes(b"old")
    target.chmod(0o600)
    (tmp_path / "link.png").symlink_to("real/image.png")
    (tmp_path / "dangling.png").symlink_to("real/new.png")
    for link in ("link.png", "dangling.png"):
        code, lines = _run(_render(model, tmp_path / link), capsys)
        assert (code, lines) == (0, [])
        assert (tmp_path / link).is_symlink()
        with Image.open(tmp_path / link) as im:
            assert im.size == (24, 16)
    assert stat.S_IMODE(target.stat().st_mode) == 0o600  # the file replaced keeps its mode
    assert _files(tmp_path / "real") == ["image.png", "new.png"]  # no temporary file left
    (tmp_path / "loop.png").symlink_to("loop.png")
    code, lines = _run(_render(model, tmp_path / "loop.png"), capsys)
    assert (code, lines) == (2, [f"rasterkit: error: {tmp_path / 'loop.png'}: Too many levels of symbolic links"])
    with pytest.raises(OSError, match="symbolic links"):
        Framebuffer(4, 3).save(tmp_path / "loop.png")
    assert (tmp_path / "loop.png").is_symlink()


def test_a_contact_sheet_may_go_into_the_folder_the_batch_makes(tmp_path, models, capsys):
    out = tmp_path / "new" / "o"
    code, lines = _run(["render", models, "-o", out, "--size", "24x16", "--contact-sheet", out / "s.png"], capsys)
    assert code == 0 and lines[-1].startswith("rasterkit: rendered 2, skipped 0, failed 0"), lines
    assert _files(out) == ["cube.png", "manifest.jsonl", "s.png", "tetra.png"]
    code, lines = _run(["render", models, "-o", tmp_path / "p", "--contact-sheet", out / "x" / "s.png"], capsys)
    assert (code, lines) == (2, [f"rasterkit: error: {out / 'x' / 's.png'}: folder '{out / 'x'}' does not exist"])


@pytest.mark.parametrize("scale", [float("nan"), 0, -1.0, float("inf"), True, "1000", None])
def test_save_depth_refuses_a_scale_that_is_not_a_positive_number(tmp_path, scale):
    fb = rasterkit.render(rasterkit.shapes.cube(), rasterkit.Camera.look_at((3, 2, 4), (0, 0, 0), width=8, height=6),
                          mode="solid")
    with pytest.raises(ValueError, match="scale"):
        fb.save_depth(tmp_path / "d.png", scale=scale)
    assert _files(tmp_path) == []


# --- contact sheets of images beyond Pillow's decompression-bomb limit -------------------------

BOMB_CHILD = """
import sys, warnings
import PIL.Image
PIL.Image.MAX_IMAGE_PIXELS = 500  # the renders are 48x32 = 1536 pixels: "bombs" to Pillow
warnings.simplefilter("error")  # a DecompressionBombWarning would fail
from rasterkit.cli import main
code = main(sys.argv[1:])
assert PIL.Image.MAX_IMAGE_PIXELS == 500  # not changed behind the program's back
sys.exit(code)
"""


@pytest.mark.parametrize("extra", [[], ["--turntable", "2"], ["--background", "transparent"]])
def test_a_contact_sheet_of_images_above_pillows_limit(tmp_path, models, extra):
    out, sheet = tmp_path / "o", tmp_path / "sheet.png"
    argv = ["render", models, "-o", out, "--size", "48x32", "--mode", "solid", "--contact-sheet", sheet, *extra]
    done = run([sys.executable, "-c", BOMB_CHILD, *argv])
    assert done.code == 0, done.describe()
    lines = [line for line in done.stderr.splitlines() if line != MESSAGE and not line[0].isdigit()]
    assert lines == [lines[-1]] and lines[-1].startswith("rasterkit: rendered 2, skipped 0, failed 0"), lines
    with Image.open(sheet) as im:
        pixels = np.asarray(im.convert("RGB"))
    # each cell holds its render, not enlarged, centred in the 160-pixel cell (not an empty frame)
    for k, name in enumerate(("cube", "tetra")):
        with Image.open(out / f"{name}{'.gif' if extra[:1] == ['--turntable'] else '.png'}") as im:
            expected = im.convert("RGBA")
        left, top = 4 + k * (160 + 4) + (160 - 48) // 2, 4 + (160 - 32) // 2
        cell = pixels[top:top + 32, left:left + 48]
        drawn = np.asarray(expected)
        white = np.full(drawn.shape[:2] + (3,), 255.0)
        alpha = drawn[..., 3:] / 255.0
        composed = np.rint(drawn[..., :3] * alpha + white * (1 - alpha))
        assert np.abs(cell.astype(int) - composed.astype(int)).max() <= 1, name


@pytest.mark.parametrize("size, cell, channels", [((640, 480), 160, 3), ((1000, 37), 160, 4), ((37, 1000), 100, 3),
                                                  ((3001, 2000), 77, 4), ((5, 700), 16, 3), ((100, 80), 160, 4)])
def test_thumbnails_match_pillows(tmp_path, size, cell, channels):
    from rasterkit.batch.thumbnails import thumbnail
    from rasterkit.image import save_image

    width, height = size
    rng = np.random.default_rng(width)
    y, x = np.mgrid[0:height, 0:width]
    planes = [x * 255 // width, y * 255 // height, (x + y) % 256, np.where((x // 7 + y // 5) % 3, 255, 0)]
    image = np.stack(planes[:channels], -1) + rng.integers(-20, 21, (height, width, channels))
    save_image(np.clip(image, 0, 255).astype(np.uint8), tmp_path / "a.png")
    mine = np.asarray(thumbnail(tmp_path / "a.png", cell)).astype(int)
    with Image.open(tmp_path / "a.png") as im:
        pillows = im.convert("RGBA")
    pillows.thumbnail((cell, cell))
    theirs = np.asarray(pillows).astype(int)
    assert mine.shape == theirs.shape
    # colours weighted by alpha (a transparent pixel's colour does not show)
    premultiplied = [np.concatenate([a[..., :3] * a[..., 3:] // 255, a[..., 3:]], -1) for a in (mine, theirs)]
    assert np.abs(premultiplied[0] - premultiplied[1]).max() <= 3


def test_a_thumbnail_reads_a_few_rows_at_a_time(tmp_path):
    """A 4000x3000 render's thumbnail without the 36 MB of its pixels (nor Pillow's copy)."""
    import tracemalloc

    from rasterkit.batch.thumbnails import thumbnail
    from rasterkit.image import save_image

    save_image(np.full((3000, 4000, 3), 200, np.uint8), tmp_path / "big.png")
    tracemalloc.start()
    thumb = thumbnail(tmp_path / "big.png", 160)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert thumb.size == (160, 120) and peak < 16 * 1024**2


# --- a full disk --------------------------------------------------------------------------------

# Python ignores SIGXFSZ: past RLIMIT_FSIZE a write raises OSError(EFBIG) with no file name, as
# a full disk raises ENOSPC. The child renders once without the limit (kernels cached).
FULL_CHILD = """
import os, resource, sys
from rasterkit.cli import main
argv, limit = sys.argv[1:-1], int(sys.argv[-1])
warm, o = list(argv), argv.index("-o") + 1
warm[o] = os.path.join(os.path.dirname(argv[o]), "warm-" + os.path.basename(argv[o]))
assert main(warm) == 0
print("--- full ---", file=sys.stderr)
resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
sys.exit(main(argv))
"""


def _full(argv, limit):
    return run([sys.executable, "-c", FULL_CHILD, *map(str, argv), str(limit)], timeout=120)


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_batch_into_a_full_disk_names_each_file_and_ends_with_its_summary(tmp_path, models, jobs):
    out = tmp_path / "o"
    # 300 bytes: the batch's warm-up and the manifest's first line fit, no image does
    done = _full(["render", models, "-o", out, "--size", "64x48", "--mode", "solid", "--jobs", jobs], 300)
    assert not done.timed_out, done.describe()
    assert done.code == 2, done.describe()
    lines = done.stderr.split("--- full ---\n")[1].splitlines()
    lines = [line for line in lines if not line[0].isdigit()]
    errors = sorted(lines[:-1])
    assert errors == sorted([f"rasterkit: error: {models / 'cube.obj'}: {out / 'cube.png'}: File too large",
                             f"rasterkit: error: {models / 'tetra.obj'}: {out / 'tetra.png'}: File too large",
                             f"rasterkit: error: {out / 'manifest.jsonl'}: File too large"]), lines
    assert lines[-1].startswith("rasterkit: rendered 0, skipped 0, failed 2 in ")
    assert _files(out) == ["manifest.jsonl"]


def test_a_manifest_on_a_full_disk_is_said_once_and_the_batch_goes_on(tmp_path, models, monkeypatch, capsys):
    from rasterkit.batch import manifest as _manifest

    write = os.write

    def full_for_the_manifest(fd, data):
        if data.startswith(b"{"):
            raise OSError(28, "No space left on device")
        return write(fd, data)

    monkeypatch.setattr(_manifest.os, "write", full_for_the_manifest)
    out = tmp_path / "o"
    code, lines = _run(["render", models, "-o", out, "--size", "24x16", "--contact-sheet", out / "s.png"], capsys)
    lines = [line for line in lines if not line[0].isdigit()]
    assert code == 2 and lines[0] == f"rasterkit: error: {out / 'manifest.jsonl'}: No space left on device"
    assert lines[1].startswith("rasterkit: rendered 2, skipped 0, failed 0 in ") and len(lines) == 2
    assert _files(out) == ["cube.png", "manifest.jsonl", "s.png", "tetra.png"]


def test_a_manifest_line_cut_by_a_full_disk_does_not_spoil_the_next(tmp_path, monkeypatch):
    from rasterkit.batch import manifest as _manifest

    write, calls = os.write, []

    def half_then_full(fd, data):
        calls.append(data)
        if len(calls) == 1:
            return write(fd, data[: len(data) // 2])  # a short write: part of the line
        if len(calls) == 2:
            raise OSError(28, "No space left on device")
        return write(fd, data)

    monkeypatch.setattr(_manifest.os, "write", half_then_full)
    with _manifest.Manifest(tmp_path, append=False) as manifest:
        with pytest.raises(OSError) as error:
            manifest.write({"input": "a", "status": "ok"})
        assert error.value.filename == str(tmp_path / "manifest.jsonl")
        manifest.write({"input": "b", "status": "ok"})
    assert _manifest.read_manifest(tmp_path / "manifest.jsonl") == [{"input": "b", "status": "ok"}]


def test_depth_arrays_on_a_full_disk_name_their_file_and_write_nothing(tmp_path, model):
    old = {name: (tmp_path / name) for name in ("x.png", "d.npy", "n.npy")}
    argv = _render(model, tmp_path / "x.png", "--depth", old["d.npy"], "--normals", old["n.npy"], size="500x400")
    child = FULL_CHILD.replace("sys.exit(main(argv))", f"""
for path in {[str(p) for p in old.values()]!r}:
    open(path, "wb").write(b"old")
sys.exit(main(argv))""")
    done = run([sys.executable, "-c", child, *map(str, argv), str(1_000_000)])  # d.npy fits, n.npy does not
    assert done.code == 2, done.describe()
    assert done.stderr.split("--- full ---\n")[1].splitlines() == [
        f"rasterkit: error: {model}: {old['n.npy']}: File too large"]
    assert all(path.read_bytes() == b"old" for path in old.values())  # all or none: none
    assert sorted(p.name for p in tmp_path.iterdir() if ".tmp" in p.name) == []


def test_the_temporaries_a_killed_writer_left_are_removed_and_nothing_else(tmp_path):
    from rasterkit.image.atomic import atomic_write, remove_temporaries

    target = tmp_path / "a.png"
    keep = [tmp_path / "a.png", tmp_path / ".b.png.12345678.tmp", tmp_path / ".a.png.txt", tmp_path / "a.png.1.tmp"]
    for path in keep:
        path.write_bytes(b"x")
    with pytest.raises(KeyboardInterrupt):
        with atomic_write(target) as tmp:  # as a worker killed mid-write leaves it: the file stays
            tmp.write_bytes(b"half")
            stray = tmp.with_name(tmp.name.replace(".tmp", "x.tmp"))
            os.link(tmp, stray)
            raise KeyboardInterrupt
    assert stray.exists()
    remove_temporaries(target)
    assert not stray.exists() and sorted(tmp_path.iterdir()) == sorted(keep)
    remove_temporaries(tmp_path / "missing" / "a.png")  # a folder that is gone is no error


def test_the_temporaries_of_many_outputs_are_removed_in_one_listing_per_folder(tmp_path, monkeypatch):
    from rasterkit.image import atomic as _atomic

    (tmp_path / "b").mkdir()
    left = [tmp_path / ".x.png.abcd1234.tmp", tmp_path / "b" / ".y.png.zzzzzzzz.tmp"]
    kept = [tmp_path / ".x.png.abcd123.tmp", tmp_path / ".z.png.abcd1234.tmp", tmp_path / "b" / ".x.png.abcd1234.tmp",
            tmp_path / "x.png"]
    for path in left + kept:
        path.write_bytes(b"x")
    listed, scandir = [], os.scandir
    monkeypatch.setattr(_atomic.os, "scandir", lambda folder: listed.append(folder) or scandir(folder))
    _atomic.remove_temporaries_of([tmp_path / "x.png", tmp_path / "b" / "y.png", tmp_path / "b" / "w.png",
                                   tmp_path / "gone" / "v.png"])
    assert not any(p.exists() for p in left) and all(p.exists() for p in kept)
    assert sorted(map(str, listed)) == sorted(map(str, [tmp_path, tmp_path / "b", tmp_path / "gone"]))
