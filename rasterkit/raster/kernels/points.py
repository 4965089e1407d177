"""Point clouds: depth-tested square splats (rasterkit.raster.points).

Compiled only when a render draws points: a plain render never loads this module.
"""

import numpy as np

from rasterkit.runtime.jit import kernel


@kernel
def splat_points(clip, colors, size, color, depth):
    """Draw each point of ``clip`` (N, 4) float64 (homogeneous raster space) as a square of
    ``size`` x ``size`` pixels centred on it: the pixels whose centres lie in
    ``[x - size/2, x + size/2) x [y - size/2, y + size/2)`` (with ``size`` 1, the pixel
    holding the point). A pixel takes the point's depth ``z/w`` and colour when the depth
    passes ``<=`` against ``depth`` (H, W) float32, updated. Points behind the eye, outside
    the near and far planes or not finite are skipped.

    ``colors`` (1 or N, C) uint8: one colour for all, or one per point; ``color`` (H, W, C)
    uint8. Returns the number of points drawn (at least one pixel passed).
    """
    height, width = depth.shape
    per_point = colors.shape[0] > 1
    half = size / 2.0
    drawn = 0
    for p in range(clip.shape[0]):
        w = clip[p, 3]
        if not w > 0.0:
            continue
        x, y, z = clip[p, 0] / w, clip[p, 1] / w, clip[p, 2] / w
        if not (0.0 <= z <= 1.0 and np.isfinite(x) and np.isfinite(y)):
            continue
        lo_x, lo_y = np.ceil(x - half - 0.5), np.ceil(y - half - 0.5)
        if lo_x >= width or lo_y >= height or lo_x + size <= 0 or lo_y + size <= 0:
            continue
        i0, j0 = max(int(lo_x), 0), max(int(lo_y), 0)
        i1, j1 = min(int(lo_x) + size, width), min(int(lo_y) + size, height)
        k = p if per_point else 0
        zf = np.float32(z)
        hit = False
        for j in range(j0, j1):
            for i in range(i0, i1):
                if zf <= depth[j, i]:
                    depth[j, i] = zf
                    for c in range(color.shape[2]):
                        color[j, i, c] = colors[k, c]
                    hit = True
        drawn += hit
    return drawn
