"""The files rasterkit writes: their mode, errors naming the user's file, and animations
streamed frame by frame (memory flat in the frame count, every frame decoding as drawn)."""

import io
import os
import stat

import numpy as np
import pytest
from PIL import Image

from rasterkit.image import atomic as _atomic
from rasterkit.raster.framebuffer import Framebuffer
from rasterkit.image import atomic_write, save_animation, save_image
from support.hostile import run_python

WRITERS = ("save_image", "apng", "gif", "fb.save", "atomic_write")


def _write(kind: str, path) -> None:
    """Write ``path`` the way ``kind`` does."""
    pixels = np.full((6, 8, 3), 90, np.uint8)
    if kind == "save_image":
        save_image(pixels, path)
    elif kind in ("apng", "gif"):
        save_animation([pixels, pixels[::-1].copy()], path)
    elif kind == "fb.save":
        Framebuffer(8, 6).save(path)
    else:
        with atomic_write(path) as tmp:
            tmp.write_bytes(b"depth")


def _name(kind: str) -> str:
    return {"apng": "a.png", "gif": "a.gif", "atomic_write": "d.npy"}.get(kind, "a.png")


# --- modes ---------------------------------------------------------------------------------

# Each umask in its own process: it is the process's. The child writes a new file with every
# writer and prints the modes.
MODES_CHILD = """
import os, sys
sys.path.insert(0, {tests!r})
os.umask({umask})
from test_image_files import WRITERS, _write, _name
for kind in WRITERS:
    path = os.path.join({folder!r}, kind.replace(".", "_") + "-" + _name(kind))
    _write(kind, path)
    print(kind, oct(os.stat(path).st_mode & 0o7777))
"""


@pytest.mark.parametrize("umask", [0o022, 0o077, 0o002, 0o027, 0o000])
def test_a_new_file_gets_the_mode_the_umask_gives(tmp_path, umask):
    done = run_python(MODES_CHILD.format(tests=os.path.dirname(__file__), umask=umask, folder=str(tmp_path)))
    assert done.code == 0, done.describe()
    modes = dict(line.split() for line in done.stdout.splitlines())
    assert modes == {kind: oct(0o666 & ~umask) for kind in WRITERS}
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]


@pytest.mark.parametrize("mode", [0o600, 0o640, 0o644, 0o664, 0o444])
@pytest.mark.parametrize("kind", WRITERS)
def test_an_overwritten_file_keeps_its_mode(tmp_path, kind, mode):
    path = tmp_path / _name(kind)
    path.write_bytes(b"old")
    os.chmod(path, mode)
    _write(kind, path)
    assert stat.S_IMODE(os.stat(path).st_mode) == mode
    assert path.read_bytes() != b"old"
    assert [p.name for p in tmp_path.iterdir()] == [path.name]


def test_the_umask_is_read_without_proc_too(monkeypatch):
    """Where /proc cannot be read, the umask is set and restored to read it."""
    current = os.umask(0o027)
    try:
        def no_proc(*args, **kwargs):
            raise OSError("no /proc here")

        monkeypatch.setattr(_atomic, "open", no_proc, raising=False)
        assert _atomic._umask() == 0o027
        assert os.umask(0o027) == 0o027  # left as it was
    finally:
        os.umask(current)
    monkeypatch.undo()
    assert _atomic._umask() == current  # from /proc/self/status on Linux


# --- errors name the user's file -------------------------------------------------------------


def test_a_missing_folder_is_named_not_the_temporary_file(tmp_path):
    target = tmp_path / "no" / "out.png"
    with pytest.raises(FileNotFoundError) as error:
        save_image(np.zeros((2, 2, 3), np.uint8), target)
    assert error.value.filename == str(target) and ".tmp" not in str(error.value)


@pytest.mark.parametrize("kind", WRITERS)
def test_a_folder_in_the_way_is_named_and_no_temporary_file_is_left(tmp_path, kind):
    target = tmp_path / _name(kind)
    target.mkdir()
    with pytest.raises(IsADirectoryError) as error:
        _write(kind, target)
    assert error.value.filename == str(target) and ".tmp" not in str(error.value)
    assert [p.name for p in tmp_path.iterdir()] == [target.name]


def test_an_error_naming_the_temporary_file_or_no_file_names_the_output(tmp_path, monkeypatch):
    target = tmp_path / "out.png"
    target.write_bytes(b"good")

    def denied(*args, **kwargs):  # as mkstemp fails in a folder we may not write
        raise PermissionError(13, "Permission denied", str(tmp_path / ".out.png.8rkug2a1.tmp"))

    monkeypatch.setattr(_atomic.tempfile, "mkstemp", denied)
    with pytest.raises(PermissionError) as error:
        save_image(np.zeros((2, 2, 3), np.uint8), target)
    assert error.value.filename == str(target) and error.value.strerror == "Permission denied"
    monkeypatch.undo()

    with pytest.raises(OSError) as error:  # a write that fails with no file named: a full disk
        with atomic_write(target) as tmp:
            tmp.write_bytes(b"partial")
            raise OSError(28, "No space left on device")
    assert (error.value.errno, error.value.filename) == (28, str(target))
    with pytest.raises(OSError) as error:  # an error about some other file keeps its name
        with atomic_write(target):
            open(tmp_path / "elsewhere" / "x")
    assert error.value.filename == str(tmp_path / "elsewhere" / "x")
    assert target.read_bytes() == b"good" and [p.name for p in tmp_path.iterdir()] == ["out.png"]


@pytest.mark.skipif(os.geteuid() == 0, reason="root may write into a read-only folder")
def test_a_read_only_folder_is_named(tmp_path):
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        with pytest.raises(PermissionError) as error:
            save_image(np.zeros((2, 2, 3), np.uint8), folder / "out.png")
        assert error.value.filename == str(folder / "out.png")
    finally:
        folder.chmod(0o755)


FSIZE_CHILD = """
import errno, os, resource
from pathlib import Path
import numpy as np
from rasterkit.image import save_animation, save_image
folder = Path({folder!r})
resource.setrlimit(resource.RLIMIT_FSIZE, (20000, 20000))  # Python ignores SIGXFSZ: EFBIG
pixels = np.random.default_rng(0).integers(0, 256, (200, 200, 3), dtype=np.uint8)
for name, write in (("still.png", lambda p: save_image(pixels, p)),
                    ("anim.png", lambda p: save_animation([pixels] * 3, p)),
                    ("anim.gif", lambda p: save_animation([pixels] * 3, p))):
    try:
        write(folder / name)
        print(name, "written")
    except OSError as e:
        print(name, errno.errorcode[e.errno], e.filename == str(folder / name), e.strerror)
print(sorted(p.name for p in folder.iterdir()))
"""


def test_a_file_size_limit_names_the_output_and_leaves_the_old_file(tmp_path):
    for name in ("still.png", "anim.png", "anim.gif"):
        (tmp_path / name).write_bytes(b"old")
    done = run_python(FSIZE_CHILD.format(folder=str(tmp_path)))
    assert done.code == 0, done.describe()
    lines = done.stdout.splitlines()
    for line in lines[:3]:
        assert line.split(" ", 3)[1:] == ["EFBIG", "True", "File too large"], line
    assert lines[3] == "['anim.gif', 'anim.png', 'still.png']"
    assert all((tmp_path / n).read_bytes() == b"old" for n in ("still.png", "anim.png", "anim.gif"))


# --- animations -------------------------------------------------------------------------------


def _frames(n, shape=(37, 53, 3), seed=1):
    rng = np.random.default_rng(seed)
    frames = [rng.integers(0, 256, shape, dtype=np.uint8) for _ in range(n)]
    if shape[2] == 4:  # opaque and transparent pixels, as a render with a transparent background
        for f in frames:
            f[..., 3] = np.where(f[..., 0] > 100, 255, 0)
    return frames


def _read_frames(path, mode):
    with Image.open(path) as im:
        info = {"loop": im.info.get("loop"), "n": im.n_frames}
        frames, durations = [], []
        for k in range(im.n_frames):
            im.seek(k)
            frames.append(np.asarray(im.convert(mode)))
            durations.append(im.info.get("duration"))
    return frames, durations, info


def _pillow_gif(frame, mode):
    """Pillow's own quantization of one frame: a one-frame GIF of it, read back."""
    out = io.BytesIO()
    Image.fromarray(frame).save(out, "GIF")
    with Image.open(out) as im:
        return np.asarray(im.convert(mode))


@pytest.mark.parametrize("channels", [3, 4])
def test_apng_frames_read_back_as_drawn(tmp_path, channels):
    frames = _frames(6, (37, 53, channels))
    frames[3] = frames[2].copy()  # a repeated frame: the one before is shown twice as long
    path = tmp_path / "a.png"
    save_animation(iter(frames), path, fps=20)  # a generator, not a list
    mode = "RGBA" if channels == 4 else "RGB"
    got, durations, info = _read_frames(path, mode)
    assert info == {"loop": 0, "n": 5}
    assert durations == [50.0, 50.0, 100.0, 50.0, 50.0]
    for k, drawn in enumerate([0, 1, 2, 4, 5]):
        assert np.array_equal(got[k], frames[drawn]), k
    with Image.open(path) as im:
        im.verify()  # chunk CRCs


@pytest.mark.parametrize("channels", [3, 4])
def test_gif_frames_are_pillows_quantization_of_each_frame(tmp_path, channels):
    frames = _frames(5, (37, 53, channels), seed=2)
    frames[1] = frames[0].copy()
    path = tmp_path / "a.gif"
    save_animation((f for f in frames), path, fps=25)
    mode = "RGBA" if channels == 4 else "RGB"
    got, durations, info = _read_frames(path, mode)
    assert info == {"loop": 0, "n": 4}
    assert durations == [80, 40, 40, 40]
    for k, drawn in enumerate([0, 2, 3, 4]):
        expected = _pillow_gif(frames[drawn], mode)
        if channels == 4:  # transparent pixels: their colour means nothing; no frame shows through
            assert np.array_equal(got[k][..., 3], expected[..., 3]), k
            seen = expected[..., 3] > 0
            assert np.array_equal(got[k][seen], expected[seen]), k
        else:
            assert np.array_equal(got[k], expected), k


@pytest.mark.parametrize("name", ["a.gif", "a.png"])
def test_a_generator_may_draw_every_frame_into_one_array(tmp_path, name):
    frames = _frames(4, seed=4)
    buffer = np.empty_like(frames[0])

    def drawn_in_place():
        for frame in frames:
            buffer[...] = frame
            yield buffer

    save_animation(drawn_in_place(), tmp_path / name)
    got, _, info = _read_frames(tmp_path / name, "RGB")
    assert info["n"] == 4
    expected = [_pillow_gif(f, "RGB") if name.endswith("gif") else f for f in frames]
    assert all(np.array_equal(g, e) for g, e in zip(got, expected))


def test_a_long_run_of_one_frame_is_cut_where_the_delay_field_ends(tmp_path):
    frame = np.full((4, 4, 3), 7, np.uint8)
    save_animation((frame for _ in range(2000)), tmp_path / "a.png", fps=25)  # 80 s in all
    _, durations, info = _read_frames(tmp_path / "a.png", "RGB")
    assert info["n"] == 2 and durations == pytest.approx([65520, 14480])  # APNG: at most 65.535 s a frame
    save_animation((frame for _ in range(20000)), tmp_path / "a.gif", fps=25)  # 800 s
    _, durations, info = _read_frames(tmp_path / "a.gif", "RGB")
    assert info["n"] == 2 and durations == [655320, 144680]  # GIF: at most 655.35 s a frame


def test_a_large_animation_frame_goes_in_several_fdat_chunks(tmp_path, monkeypatch):
    from rasterkit.image import png as _png

    frames = _frames(3, (40, 50, 3), seed=3)
    monkeypatch.setattr(_png, "IDAT_BYTES", 1000)
    save_animation(frames, tmp_path / "a.png")
    data = (tmp_path / "a.png").read_bytes()
    assert data.count(b"fdAT") > 6 and data.count(b"IDAT") > 3
    got, _, info = _read_frames(tmp_path / "a.png", "RGB")
    assert info["n"] == 3 and all(np.array_equal(g, f) for g, f in zip(got, frames))


def test_one_frame_is_an_animation_too(tmp_path):
    frame = _frames(1)[0]
    for name in ("one.gif", "one.png", "one.apng"):
        save_animation([frame], tmp_path / name)
        with Image.open(tmp_path / name) as im:
            assert im.n_frames == 1 and im.size == (53, 37)


def test_bad_animations_write_nothing_and_keep_the_old_file(tmp_path):
    frames = _frames(3)

    def failing():
        yield frames[0]
        raise ValueError("the second frame failed")

    def bad_inputs():
        yield []
        yield iter([])
        yield failing()
        yield [frames[0], frames[1][:30]]  # frames of two sizes
        yield [frames[0], np.zeros((37, 53, 4), np.uint8)]  # RGB then RGBA
        yield [frames[0], frames[1].astype(np.float32)]  # not an image

    for name in ("a.gif", "a.png"):
        path = tmp_path / name
        path.write_bytes(b"old")
        for bad in bad_inputs():
            with pytest.raises(ValueError):
                save_animation(bad, path)
            assert path.read_bytes() == b"old"
    for fps in (0, -1, float("nan"), float("inf"), True, "25", 1e-5):
        with pytest.raises(ValueError):
            save_animation(frames, tmp_path / "a.gif", fps=fps)
    with pytest.raises(ValueError):
        save_animation(frames, tmp_path / "a.jpg")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.gif", "a.png"]


# Peak memory of a child that saves n frames of 800x600 from a generator; each frame is a new
# array, so an encoder that kept its frames would grow by 1.4 MB a frame (Pillow's, twice that).
MEMORY_CHILD = """
import resource, sys
import numpy as np
from rasterkit.image import save_animation
n, path = int(sys.argv[1]), sys.argv[2]
ramp = (np.arange(800, dtype=np.uint32)[None, :, None] + np.arange(600, dtype=np.uint32)[:, None, None]
        + np.array([0, 60, 120], np.uint32))
def frames():
    for k in range(n):
        yield ((ramp + 7 * k) % 256).astype(np.uint8)
save_animation(frames(), path, fps=25)
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
"""


@pytest.mark.parametrize("name", ["spin.gif", "spin.png"])
def test_animation_memory_does_not_grow_with_the_frame_count(tmp_path, name):
    peaks = {}
    for n in (10, 100):
        done = run_python(MEMORY_CHILD.replace("sys.argv[1]", str(n)).replace("sys.argv[2]", repr(str(tmp_path / name))))
        assert done.code == 0, done.describe()
        peaks[n] = int(done.stdout.split()[-1]) * 1024  # ru_maxrss: KiB on Linux
        with Image.open(tmp_path / name) as im:
            assert im.n_frames == n
    # keeping 90 more frames would take 130 MB more
    assert peaks[100] - peaks[10] < 30 * 1024**2, peaks


def test_png_stream_is_compressed_without_a_copy_of_the_image():
    # 4000x4000 RGB is 48 MB; a flat image compresses to almost nothing, so the encoder's
    # peak is its block of rows, not a second copy of the image.
    import io
    import tracemalloc

    from PIL import Image

    from rasterkit.image import encode_png

    image = np.full((4000, 4000, 3), 200, np.uint8)
    image[::97, ::89] = 3
    tracemalloc.start()
    data = encode_png(image)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 12 * 2**20, peak
    np.testing.assert_array_equal(np.asarray(Image.open(io.BytesIO(data))), image)
