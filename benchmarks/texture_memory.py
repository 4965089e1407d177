"""What a texture costs in memory, and whether frames copy it (the ``textures`` family's memory rows).

The issue's bar: "a texture and its mipmaps cost <= 1.4x the texture's pixels; textures are
shared between meshes and frames, not copied per frame". Measured in a new process (``python
-m benchmarks.texture_memory SPEC``, so that the suite's own allocations do not blur the
resident set) for ``spot_texture.png`` opened as one :class:`rasterkit.Texture`, given to two
spot meshes (two ``Mesh`` objects sharing it), smooth trilinear frames at the profile's size:

held
    ``texture.mipmaps.nbytes`` (every level in one buffer, level 0 included, and their table),
    plus ``texture.image.nbytes`` unless the image is a view of level 0, against the texture's
    pixels, ``width * height * channels`` bytes; the note says whether level 0 of the mipmaps
    is the image itself or a copy of it.
frames (rss, traced)
    ``VmRSS``, then tracemalloc's traced bytes, before and after :data:`FRAMES` frames drawn
    in turn from the two meshes (each figure after a garbage collection): flat when nothing
    is kept per frame. tracemalloc sees NumPy's allocations, not those of Numba's runtime;
    the resident set sees both.
frame traced peak
    The most that tracemalloc saw allocated at once above its level before the frames, over
    those textured frames, against the same number of untextured frames (``textures=False``):
    a NumPy copy of the texture made per frame would add its size. (The resident peak,
    ``VmHWM``, cannot show a copy that is freed: after the first frames the allocator reuses
    its memory.)
"""

from __future__ import annotations

import gc
import json
import subprocess
import sys
import tracemalloc

import numpy as np

import rasterkit

from .launch import ROOT, child_environment
from .memory import status
from .render import frame
from .report import Record, Target
from .textured_models import SPOT_TEXTURE, load, missing

FAMILY = "textures"
MODEL = "spot"
FRAMES = 50

TARGET = Target("a texture and its mipmaps <= 1.4x its pixels", 1.4)
"""The issue's memory bar."""


# ---------------------------------------------------------------------------- in the child


def _frames(draw, meshes, frames: int) -> None:
    for k in range(frames):
        draw(meshes[k % len(meshes)])


def _traced(draw, meshes, frames: int) -> tuple[int, int, int]:
    """(traced bytes before, after, peak above before) of ``frames`` frames; tracemalloc runs."""
    gc.collect()
    before = tracemalloc.get_traced_memory()[0]
    tracemalloc.reset_peak()
    _frames(draw, meshes, frames)
    peak = tracemalloc.get_traced_memory()[1]
    gc.collect()
    return before, tracemalloc.get_traced_memory()[0], peak - before


def child(spec: str) -> dict:
    """Measure (see the module docstring); the parent reads the returned dict as JSON."""
    request = json.loads(spec)
    frames = request["frames"]
    opened: dict = {}
    meshes = [load(MODEL, opened), load(MODEL, opened)]
    (texture,) = opened.values()
    camera = frame(meshes[0], request["width"], request["height"])

    def draw(mesh, textures=True):
        return rasterkit.render(mesh, camera, "solid", shading="smooth", texture_filter="trilinear",
                                textures=textures).color

    chain = texture.mipmaps
    out = {"pixels": texture.width * texture.height * texture.channels, "image": texture.image.nbytes,
           "mipmaps": chain.nbytes, "levels": len(chain.levels), "size": f"{texture.width}x{texture.height}",
           "channels": texture.channels, "level0_is_image": bool(np.shares_memory(texture.image, chain.texels)),
           "shared": meshes[0].textured.textures[0] is meshes[1].textured.textures[0]}
    _frames(draw, meshes, 2)
    gc.collect()
    out["rss_before"] = status("VmRSS")
    _frames(draw, meshes, frames)
    gc.collect()
    out["rss_after"] = status("VmRSS")
    tracemalloc.start()
    _frames(draw, meshes, 2)  # what the first traced frames keep (caches of the tracing itself)
    out["traced_before"], out["traced_after"], out["peak_textured"] = _traced(draw, meshes, frames)
    out["peak_untextured"] = _traced(lambda mesh: draw(mesh, textures=False), meshes, frames)[2]
    tracemalloc.stop()
    return out


# ---------------------------------------------------------------------------- in the parent


def _mib(n: float) -> str:
    return f"{n / 2**20:.2f} MiB"


def _measure(width: int, height: int) -> dict:
    spec = json.dumps({"width": width, "height": height, "frames": FRAMES})
    done = subprocess.run([sys.executable, "-m", "benchmarks.texture_memory", spec], cwd=ROOT,
                          env=child_environment(), capture_output=True, text=True)
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines() or [f"exit code {done.returncode}"]
        raise RuntimeError(lines[-1])
    return json.loads(done.stdout.strip().splitlines()[-1])


def _records(m: dict, width: int, height: int) -> list[Record]:
    base = f"textures/memory/{MODEL}/{width}x{height}"
    level0 = "level 0 is the image itself" if m["level0_is_image"] else \
        "level 0 is a separate copy of the image (image + mipmaps = 1 + 4/3 of the pixels)"
    frames = f"{FRAMES} smooth trilinear frames, two meshes sharing one Texture in turn " \
             f"(shared: {'yes' if m['shared'] else 'no'})"
    held = m["mipmaps"] + (0 if m["level0_is_image"] else m["image"])  # shared bytes counted once
    sizes = {"texture": m["size"], "channels": m["channels"]}
    drawn = {"width": width, "height": height, "frames": FRAMES}
    return [
        Record(family=FAMILY, name=f"textures/memory/{SPOT_TEXTURE}/held", peer="its pixels (W x H x C)",
               sizes=sizes, quantity="bytes", rasterkit=held, peer_value=m["pixels"], target=TARGET, runs=1,
               note=f"image {_mib(m['image'])} + mipmaps {_mib(m['mipmaps'])} ({m['levels']} levels); {level0}"),
        Record(family=FAMILY, name=f"{base}/{FRAMES}-frames/rss", peer="before the frames", sizes=drawn,
               quantity="bytes", rasterkit=m["rss_after"], peer_value=m["rss_before"], runs=1,
               note=f"VmRSS after / before {frames}: {m['rss_after'] - m['rss_before']:+,} bytes"),
        Record(family=FAMILY, name=f"{base}/{FRAMES}-frames/traced", peer="before the frames", sizes=drawn,
               quantity="bytes", rasterkit=m["traced_after"], peer_value=m["traced_before"], runs=1,
               note=f"tracemalloc after / before {frames}: {m['traced_after'] - m['traced_before']:+,} bytes"),
        Record(family=FAMILY, name=f"{base}/{FRAMES}-frames/traced-peak", peer="untextured frames", sizes=drawn,
               quantity="peak_bytes", rasterkit=m["peak_textured"], peer_value=m["peak_untextured"], runs=1,
               note=f"tracemalloc's peak above its level before the frames; a NumPy copy of the texture "
                    f"per frame would add {_mib(held)}"),
    ]


def run(settings, results) -> None:
    """The memory rows at ``settings.texture_size`` (skipped, with the reason, without spot)."""
    why = missing(MODEL)
    if why:
        results.skip(FAMILY, "textures/memory", why)
        return
    width, height = settings.texture_size
    try:
        measured = _measure(width, height)
    except RuntimeError as error:
        results.skip(FAMILY, "textures/memory", f"failed: {error}")
        return
    for record in _records(measured, width, height):
        results.add(record)


if __name__ == "__main__":
    print(json.dumps(child(sys.argv[1])))
