"""Multi-sample renders: the samples drawn, summed, averaged once.

:func:`rasterkit.render` with ``samples > 1`` (or a ``vignette``) comes here. Sample ``s``
sees the scene through its own world -> raster matrix
(:func:`rasterkit.camera.lens.sample_matrices`: a sub-pixel shift of the window, and for a
lens camera an eye moved across the lens). The colours are summed in 16 bits (256 samples of
255 fit) and divided once, with rounding; an RGBA render (transparent background) sums colour
times alpha and alpha, in 32 bits, so that a half-covered edge keeps its colour at half
opacity. The result's depth buffer and ids are those of the centre sample (the ``samples=1``
render): the depth is drawn when first read (:meth:`Framebuffer.defer_depth`), the ids, when
asked for, by drawing the centre sample once more.

What the samples share
    Through a pinhole (a parallel camera, or a perspective one without ``aperture``) the
    samples differ only in where each pixel is sampled: the pixel offsets
    (:func:`rasterkit.raster.samples.pixel_offsets`) are rounded to the 1/256-pixel grid the vertices
    are snapped to (:func:`grid_offsets`), and the faces are set up once, through the centre
    sample's matrix, for all of them (:mod:`rasterkit.raster.shared_samples`: vertex pass, face
    pass with clipping, culling, snapping and flat colours, the cut faces' fans, binning,
    polygon offset, the smooth colours' terms); each sample draws only the bands, at its
    offset, which is exactly the draw of the vertices moved by the offset. A solid RGB
    render without points draws every sample of a band in turn and averages them there, in
    one pass over the bands, with no frame per sample at all
    (:mod:`rasterkit.raster.kernels.sample_bands`), and makes the pixels where the samples saw one
    face and the background, or that one face's outline crosses, exact: the face's share of
    the pixel (:mod:`rasterkit.raster.kernels.coverage`); so does a transparent one (its alpha). The hidden and solid+wire modes draw each sample
    into one reused scratch framebuffer (the faces from the shared setup, the edges and
    points through the sample's matrix: they are not shared) and add its colours into the
    sums (:mod:`rasterkit.raster.kernels.accumulate`); so do wireframes (no faces to share) and RGBA
    renders. A lens camera's samples move the eye, a different projection each: each is a
    whole frame through its matrix, at the exact (unrounded) pixel offsets.

Nothing here depends on the thread count: each sample's image does not, and every pixel's
sum is added in the samples' fixed order.
"""

from __future__ import annotations

from functools import partial

import numpy as np

from rasterkit.runtime import scratch as _memory
from rasterkit._arrays import real_number
from rasterkit.runtime.threads import run_workers
from rasterkit.raster.kernels.accumulate import add_sample, add_sample_rgba, average_samples, average_samples_rgba
from rasterkit.camera.lens import sample_matrices, vignette_factor
from rasterkit.raster.framebuffer import Framebuffer, buffer_bytes
from rasterkit.raster.samples import check_samples as _check_samples, lens_points, pixel_offsets

__all__ = ["check", "extra_bytes", "grid_offsets", "pinhole", "render_samples"]


#: Whether a pinhole render's one-pass average makes the pixels where the samples saw one
#: face and the background exact (:meth:`SharedTriangles.draw_average`). Tests that compare
#: it with the frame-per-sample path, which has no such step, turn it off.
EXACT_COVERAGE = True


def check(samples, vignette) -> tuple[int, float]:
    """``samples`` (an int, 1..256) and ``vignette`` (a real number in [0, 1]), checked."""
    samples = _check_samples(samples)
    v = real_number(vignette, "vignette")
    if not 0.0 <= v <= 1.0:
        raise ValueError(f"vignette must lie in [0, 1], got {vignette!r}")
    return samples, v


def extra_bytes(width: int, height: int, alpha: bool, samples: int, vignette: float, faces: int = 0) -> int:
    """Bytes a render needs beyond one frame's: the scratch framebuffer and the 16-bit sums
    of the samples, the ``faces``' records moved to each sample point (a pinhole render's
    shared setup, :func:`rasterkit.raster.kernels.triangle_samples.move_records`: 40 bytes a record, grown
    by a quarter), and the vignette's float32 factors and products."""
    pixels, channels = width * height, 4 if alpha else 3
    total = 0
    if samples > 1:
        total += buffer_bytes(width, height, alpha) + (16 * pixels if alpha else 2 * pixels * channels) + faces * 50
    if vignette:
        total += 4 * pixels * (1 + channels)
    return total


def render_samples(camera, samples: int, vignette: float, background, ids: bool, draw, share, centre) -> Framebuffer:
    """The averaged render.

    ``draw(fb, matrix, shared=None)`` draws one sample into ``fb`` (clearing it); for a
    pinhole camera ``shared`` is ``(setup, sample)``: the faces set up once
    (:class:`rasterkit.raster.shared_samples.SharedTriangles`, None when the mode draws none) and
    the sample's offset from the pixel centres in 1/256 pixel, by which ``matrix`` moves the
    image. ``share()`` makes the setup: ``(setup, whole)``, ``whole`` when the setup's faces
    are all a sample draws (then an RGB render draws and averages every sample in one pass,
    :meth:`SharedTriangles.draw_average`). ``centre(ids)`` renders the centre sample into a
    new framebuffer (``samples=1``)."""
    if samples == 1:
        fb = centre(ids)
    else:
        fb = Framebuffer(camera.width, camera.height, background=background, ids=ids, cleared=False)
        _average(fb, camera, samples, background, draw, share)
        _centre_buffers(fb, ids, centre)
    factor = vignette_factor(camera, vignette)
    if factor is not None:
        rgb = fb.color[..., :3]
        shaded = rgb * factor[..., None]
        shaded += 0.5
        rgb[...] = shaded  # in [0.5, 255.5): truncation rounds
    return fb


def pinhole(camera) -> bool:
    """Whether every sample of ``camera`` sees through one point: a parallel camera, or a
    perspective one without an aperture (no lens)."""
    return camera.kind != "perspective" or camera.aperture == 0.0


def grid_offsets(samples: int) -> np.ndarray:
    """The pixel offsets of ``samples`` samples (:func:`rasterkit.raster.samples.pixel_offsets`)
    rounded to the nearest 1/256 pixel, in 1/256 pixel, (n, 2) int64 in -128..128."""
    return np.rint(pixel_offsets(samples) * 256.0).astype(np.int64)


def _average(fb: Framebuffer, camera, samples: int, background, draw, share) -> None:
    """Draw every sample, sum them and divide once, with rounding, into ``fb.color``: in one
    pass over the bands when a pinhole render's samples draw only the shared faces in RGB,
    else each sample into one scratch framebuffer (the first sample written into the sums,
    the others added: no clear)."""
    color = fb.color
    if pinhole(camera):
        offsets = grid_offsets(samples)
        matrices = sample_matrices(camera, offsets / 256.0, np.zeros((samples, 2)))
        setup, whole = share()
        clear = tuple(int(c) for c in fb.background[: color.shape[2]])
        if whole and (color.shape[2] == 3 or EXACT_COVERAGE and clear == (0, 0, 0, 0)):
            setup.draw_average(color, offsets, clear=clear, exact=EXACT_COVERAGE)
            return
        draws = [partial(draw, matrix=m, shared=None if setup is None else (setup, (int(x), int(y))))
                 for m, (x, y) in zip(matrices, offsets.tolist())]
    else:
        matrices = sample_matrices(camera, pixel_offsets(samples), lens_points(samples))
        draws = [partial(draw, matrix=m) for m in matrices]
    scratch = Framebuffer(camera.width, camera.height, background=background, cleared=False)
    if color.shape[2] == 4:  # transparent: premultiplied sums (kernels.accumulate)
        pixels = color.shape[0] * color.shape[1]
        premultiplied = _memory.take((pixels, 3), np.uint32)
        alpha = _memory.take((pixels,), np.uint32)
        for k, draw_sample in enumerate(draws):
            draw_sample(scratch)
            run_workers(add_sample_rgba, premultiplied, alpha, scratch.color.reshape(pixels, 4), k == 0)
        run_workers(average_samples_rgba, premultiplied, alpha, color.reshape(pixels, 4), samples)
        return
    total = _memory.take((color.size,), np.uint16)
    for k, draw_sample in enumerate(draws):
        draw_sample(scratch)
        run_workers(add_sample, total, scratch.color.reshape(-1), k == 0)
    run_workers(average_samples, total, color.reshape(-1), 1.0 / samples, (samples // 2 + 0.5) / samples)


def _centre_buffers(fb: Framebuffer, ids: bool, centre) -> None:
    """The depth (drawn when read) and ids (now) of the centre sample, into ``fb``."""
    if ids:
        first = centre(True)
        fb.ids[...] = first.ids
        fb.defer_depth(lambda depth: np.copyto(depth, first.depth))
    else:
        fb.defer_depth(lambda depth: np.copyto(depth, centre(False).depth))
