"""The memory of a whole ``rasterkit render`` job, estimated before anything is drawn.

:func:`rasterkit.raster.render.render_bytes` counts what one frame's drawing needs; a command does
more around it, and :func:`job_bytes` counts all of it, so that ``--max-memory`` (and the
machine's memory) refuses a job up front, in one line, instead of failing after gigabytes:

- the model, held while it is drawn;
- a **turntable**: each frame's world-space copy of the model and its render, and the frames
  the animation writer holds at once (:data:`TURNTABLE_FRAMES` images: the frame kept to
  compare with the next one, the one drawn, the one in the framebuffer being drawn, and the
  comparison's temporary); a **GIF** frame's palette quantisation and LZW coding in Pillow
  (:func:`gif_frame_bytes`);
- a still image: the PNG stream, written as zlib makes it (:data:`rasterkit.image.png.STREAM_BYTES`);
- ``--depth``, ``--normals``, ``--ids``: the depth buffer that a solid render makes only when
  it is read, the metric depth, and the conversions to a 16-bit or RGB PNG (NumPy
  temporaries, :data:`PNG_MAP_BYTES` per pixel, and the stream held whole; ``.npy`` files
  are written from the arrays as they are);
- a distorted camera (``"dist"`` in ``--camera-opencv``'s file): its maps and resampling
  (:data:`DISTORTION_BYTES` per pixel), and the larger undistorted render;
- a batch's **contact sheet** (:func:`sheet_bytes`): the sheet and one image read back at a
  time, decoded and converted to RGBA by Pillow;
- in a process that rendered before (a batch's worker), the idle framebuffer blocks that
  :mod:`rasterkit.runtime.scratch` keeps for reuse (:func:`check_job` lets them go when needed).

The per-pixel numbers were measured (peak resident memory, ``VmHWM``, on images of random
pixels, the worst case for compression and quantisation) and rounded up;
``tests/batch/test_job_memory.py`` checks that the estimate stays above the measured peak.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["DISTORTION_BYTES", "PNG_MAP_BYTES", "TURNTABLE_FRAMES", "check_batch", "check_job", "gif_frame_bytes",
           "job_bytes", "sheet_bytes"]

#: Images of a turntable's size held at once by the frame generator and the animation writer.
TURNTABLE_FRAMES = 5

#: Bytes per pixel of NumPy's temporaries when a map is converted to a PNG, and of its
#: compressed stream held whole (at most the raw rows; three copies while the file is made).
PNG_MAP_BYTES = {"depth": 16 + 3 * 2, "normals": 27 + 3 * 3, "ids": 10 + 3 * 2}


#: Bytes per pixel of a distorted camera's image (:mod:`rasterkit.raster.distortion`): where each
#: pixel reads the undistorted image (the undistortion's iterations, the maps) and the
#: bilinear resampling's temporaries (measured about 60).
DISTORTION_BYTES = 96


def gif_frame_bytes(pixels: int) -> int:
    """Bytes that Pillow takes to quantise and LZW-code one GIF frame: its RGB(A) image (4
    bytes a pixel), the palette image, the coded data and its copies (16 bytes a pixel in
    all, measured 12-14 on renders), and the median cut's table of distinct colours (36 bytes
    per colour, at most one per pixel and 2**24 in all; measured 40-48 bytes a pixel in all
    on random pixels)."""
    return 16 * pixels + 36 * min(pixels, 1 << 24)


def _mesh_bytes(mesh) -> int:
    """Bytes of the arrays a Mesh holds (:attr:`rasterkit.Mesh.nbytes`: its per-corner
    attributes and material indices too)."""
    return mesh.nbytes


def _world_copy_bytes(mesh) -> int:
    """Bytes of a one-object Scene's world mesh (:meth:`rasterkit.Scene.world_mesh`), as
    the Scene checks them."""
    from rasterkit.mesh import mesh_bytes

    n, m, e = len(mesh.vertices), len(mesh.faces), len(mesh.edges)
    return n * (24 * 4 + 32 + 12 + 16) + m * (24 + 12) + e * 16 + mesh_bytes(n, m, e)


def job_bytes(mesh, camera, task, output: Path, ideal=None) -> int:
    """Bytes that rendering ``mesh`` through ``camera`` into ``output`` as ``task`` (a
    :class:`rasterkit.batch.task.Task`) says needs at its peak, the model included (see the
    module's documentation); ``ideal``: a distorted camera's undistorted one, which draws. An
    SVG drawing counts its own (:func:`rasterkit.svg.render_svg`)."""
    from rasterkit.colors import parse_color
    from rasterkit.raster.render import render_bytes
    from rasterkit.image.png import STREAM_BYTES

    pixels = camera.width * camera.height
    options = task.frame_options()
    channels = 4 if options.background is not None and parse_color(options.background)[3] < 255 else 3
    held = _mesh_bytes(mesh)
    if camera.distortion:
        held += DISTORTION_BYTES * pixels
        camera = ideal
    if task.turntable:
        frame = _world_copy_bytes(mesh) + render_bytes(mesh, camera, options=options)
        frames = TURNTABLE_FRAMES * pixels * channels
        gif = Path(output).suffix.lower() == ".gif"
        return held + frame + frames + (gif_frame_bytes(pixels) if gif else STREAM_BYTES)
    frame = render_bytes(mesh, camera, options=options)
    kept = 0  # arrays made for the maps' files and kept with the framebuffer
    if task.depth:
        kept += 8 * pixels  # the depth buffer when deferred, the metric depth when not made by the bands
    converting = [PNG_MAP_BYTES[name] * pixels for name in ("depth", "normals", "ids")
                  if str(getattr(task, name) or "").lower().endswith(".png")]
    return held + frame + kept + max(converting, default=0) + STREAM_BYTES


def sheet_bytes(count: int, width: int, height: int) -> int:
    """Bytes that a contact sheet of ``count`` images of ``width`` x ``height`` needs at
    most: the sheet (cells of at most 160 pixels with their label and margins, 4 bytes a
    pixel in Pillow's RGB) and one image read back at a time (Pillow's decoded image and
    its RGBA copy, 4 bytes a pixel each, and the thumbnail's reduction)."""
    return 4 * (max(count, 1) * 164 * 182 + 8200 * 4) + 10 * width * height + (16 << 20)


def _what(camera, task, output) -> str:
    frames = task.turntable
    kind = f"turntable of {frames} frame{'s' if frames != 1 else ''}" if frames else "render"
    return f"a {camera.width}x{camera.height} {task.options.mode} {kind} into {Path(output).name}"


def check_job(mesh, camera, task, output: Path) -> None:
    """:class:`rasterkit.limits.LimitError` when :func:`job_bytes`, with the idle blocks that
    :mod:`rasterkit.runtime.scratch` keeps for reuse, is over the memory limit (the idle blocks are
    let go when they alone would make it so)."""
    from rasterkit.runtime import scratch as _memory
    from rasterkit.limits import check_memory, memory_limit

    ideal = None
    if camera.distortion:  # the undistorted camera's size is worked out by the maps that resample it
        from rasterkit.raster.distortion import ideal_camera

        check_memory(_mesh_bytes(mesh) + DISTORTION_BYTES * camera.width * camera.height,
                     _what(camera, task, output))
        ideal = ideal_camera(camera)
    need = job_bytes(mesh, camera, task, output, ideal)
    if need + _memory.idle_bytes() > memory_limit():  # the recycled blocks of earlier jobs are let go first
        _memory.release()
    check_memory(need + _memory.idle_bytes(), _what(camera, task, output))


def check_batch(task, count: int, contact_sheet: bool) -> None:
    """:class:`rasterkit.limits.LimitError` before a batch of ``count`` models starts when no
    model could render within the memory limit (the images alone are over it: the job of a
    tetrahedron), or when its contact sheet could not be made."""
    from rasterkit.limits import check_memory
    from rasterkit.shapes import tetrahedron

    mesh = tetrahedron()
    camera = task.view.camera_for(mesh)
    output = Path("image.gif" if task.turntable else "image.png")
    check_memory(job_bytes(mesh, camera, task, output), "each model's " + _what(camera, task, output))
    if contact_sheet:
        check_memory(sheet_bytes(count, camera.width, camera.height),
                     f"the contact sheet of {count} images of {camera.width}x{camera.height}")
