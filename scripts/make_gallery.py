"""Render the lecture's gallery, docs/gallery/*.png (docs/lecture.md shows them).

    python scripts/make_gallery.py                 # writes docs/gallery/
    python scripts/make_gallery.py --out DIR       # somewhere else
    python scripts/make_gallery.py --only lines,culling --out DIR   # some figures only
    python scripts/make_gallery.py --check         # regenerate into a temporary folder and
                                                   # fail (exit 1) if a picture differs from docs/gallery/'s

Only rasterkit's public API, NumPy and Pillow; every piece of geometry is made in code. The
output is deterministic: the same rasterkit, NumPy and Pillow give the same bytes (``--check``
compares pixels, so another zlib's compression does not count as a difference).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the gallery_* modules beside this file

import gallery_geometry as geometry  # noqa: E402
import gallery_pixels as pixels  # noqa: E402
from gallery_canvas import save_png  # noqa: E402

GALLERY = Path(__file__).resolve().parents[1] / "docs" / "gallery"

FIGURES = {  # file name (without .png) -> the function that draws it
    "transforms": geometry.transforms,
    "coordinate_systems": geometry.coordinate_systems,
    "chain": geometry.chain_volume,
    "projections_perspective": geometry.projections_perspective,
    "projections_parallel": geometry.projections_parallel,
    "culling": pixels.culling,
    "lines": pixels.line_algorithms,
    "antialiasing": pixels.antialiasing,
    "focus": pixels.focus_series,
    "aperture": pixels.aperture_series,
    "vignette": pixels.vignetting,
}


def write(out: Path, names: list[str]) -> list[Path]:
    """Draw the figures ``names`` into ``out`` (made if missing); returns the files."""
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name in names:
        path = out / f"{name}.png"
        save_png(FIGURES[name](), path)
        written.append(path)
    return written


def same_picture(a: Path, b: Path) -> bool:
    """Equal pixels (not bytes: another zlib may compress the same picture differently)."""
    if not (a.is_file() and b.is_file()):
        return False
    with Image.open(a) as image_a, Image.open(b) as image_b:
        return image_a.mode == image_b.mode and np.array_equal(np.asarray(image_a), np.asarray(image_b))


def check(names: list[str], committed: Path) -> list[str]:
    """The figures whose fresh render differs from (or is missing in) ``committed``."""
    with tempfile.TemporaryDirectory() as tmp:
        return [p.name for p in write(Path(tmp), names) if not same_picture(p, committed / p.name)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=GALLERY, help="folder of the PNGs (default docs/gallery)")
    parser.add_argument("--only", help="comma-separated figure names: " + ", ".join(FIGURES))
    parser.add_argument("--check", action="store_true",
                        help="regenerate into a temporary folder; exit 1 if a picture differs from --out's")
    args = parser.parse_args(argv)
    names = list(FIGURES) if args.only is None else [n.strip() for n in args.only.split(",")]
    unknown = [n for n in names if n not in FIGURES]
    if unknown:
        parser.error(f"unknown figure(s): {', '.join(unknown)}")
    if args.check:
        differ = check(names, args.out)
        for name in differ:
            print(f"make_gallery: {args.out / name} differs from a fresh render", file=sys.stderr)
        print(f"make_gallery: {len(names) - len(differ)} of {len(names)} figures up to date")
        return 1 if differ else 0
    for path in write(args.out, names):
        print(f"wrote {path} ({path.stat().st_size // 1024} KiB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
