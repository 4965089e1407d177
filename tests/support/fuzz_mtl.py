"""Fuzzing the material reader and the texture files it opens.

Each case is a small model whose ``.mtl`` library is made of random statements (every keyword
:mod:`rasterkit.obj.mtl` reads and some it does not, with hostile numbers, options with too
few or bad arguments, odd file names, comments, random bytes spliced in) naming image files
that are real PNG, JPEG, TGA and BMP files with random mutations (bits flipped, bytes
deleted, inserted or overwritten with large numbers, truncated), plus intact ones.

The oracle: :func:`rasterkit.obj.materials.read_libraries` and ``make_materials`` never raise (a texture or
statement it cannot read is a warning) and every warning is one line; the command line's guess
at the maps before reading (:func:`rasterkit.obj.peek.map_kinds`) never raises and names every
kind of map the reader opened; no Python warning
escapes; each texture it opens samples finite values in [0, 1] at hostile coordinates;
:meth:`rasterkit.Texture.open` of each mutated file gives a texture or raises
:class:`rasterkit.material.TextureError`, one line naming the file. Anything else (another
exception, a crash, more than ``--example-seconds`` for one case) is a failure; the case's
folder is kept in ``--failures``.

Run by hand::

    python tests/support/fuzz_mtl.py --cases 5000 --seed 1 --failures /tmp/fuzz-mtl

The suite runs a short run in a child process with a time and a memory limit
(``tests/obj/test_fuzz_mtl.py``).
"""

from __future__ import annotations

import argparse
import faulthandler
import io
import random
import shutil
import sys
import tempfile
import time
import warnings
from pathlib import Path

IMAGES = {"a.png": "PNG", "b.jpg": "JPEG", "c.tga": "TGA", "d.bmp": "BMP"}
NUMBERS = ["0", "1", "0.5", "-1", "2", "1e308", "-1e308", "1e309", "nan", "inf", "-inf", "1.#IND", "", ".", "-",
           "1e", "0x10", "9" * 400, "1_0", "٣", "3"]
OPTIONS = ["-s", "-o", "-t", "-clamp", "-bm", "-mm", "-blendu", "-blendv", "-boost", "-texres", "-imfchan", "-type",
           "-cc", "-foo", "-", "--s"]
VALUES = ["on", "off", "ON", "maybe", "r", "sphere"]
FILES = [*IMAGES, *[f"ok/{name}" for name in IMAGES] * 3, "missing.png", "ok\\a.png", "C:\\x\\a.png", "/dev/zero",
         "/dev/null", ".", "..", "ok", '"ok/a.png"', "a b.png", "x" * 300, "a\x00.png", "\u00e9t\u00e9.png", "#a.png"]
KEYWORDS = ["newmtl", "Kd", "Ks", "Ke", "Ns", "d", "Tr", "map_Kd", "map_d", "map_Ks", "map_Bump", "bump", "norm",
            "MAP_KD", "map_bump", "illum", "Ka", "refl", "#", "newmtl"]


class Failure(Exception):
    """The oracle's verdict on one case."""


# --- making a case --------------------------------------------------------------------------

def images(rng: random.Random) -> dict:
    """Small valid image files, by name, in a few modes."""
    import numpy as np
    from PIL import Image

    pixels = np.random.default_rng(rng.randrange(2**32)).integers(0, 256, (rng.randint(1, 9), rng.randint(1, 9), 4),
                                                                   dtype=np.uint8)
    made = {}
    for name, fmt in IMAGES.items():
        mode = rng.choice({"PNG": ["RGB", "RGBA", "L", "LA", "P"], "JPEG": ["RGB", "L", "CMYK"],
                           "TGA": ["RGB", "RGBA", "L"], "BMP": ["RGB", "L", "P"]}[fmt])
        out = io.BytesIO()
        options = {"compression": "tga_rle"} if fmt == "TGA" and rng.random() < 0.5 else {}
        Image.fromarray(pixels).convert(mode).save(out, fmt, **options)
        made[name] = out.getvalue()
    return made


def mutate(data: bytes, rng: random.Random) -> bytes:
    """``data`` with 1-3 random mutations."""
    data = bytearray(data)
    for _ in range(rng.randint(1, 3)):
        kind = rng.randrange(5)
        at = rng.randrange(len(data) + 1)
        if kind == 0 and data:  # flip a bit
            at = min(at, len(data) - 1)
            data[at] ^= 1 << rng.randrange(8)
        elif kind == 1:  # delete a run
            del data[at:at + rng.randint(1, 16)]
        elif kind == 2:  # insert bytes
            data[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        elif kind == 3:  # a large number over a header field
            data[at:at + 4] = rng.choice([b"\xff\xff\xff\xff", b"\x00\x00\x7f\xff", b"\xff\xff", b"\x00\x00\x00\x00"])
        else:  # truncate
            del data[at:]
    return bytes(data)


def statement(rng: random.Random) -> str:
    keyword = rng.choice(KEYWORDS)
    words = []
    if keyword.lower().startswith("map") or keyword.lower() in ("bump", "norm"):
        for _ in range(rng.randint(0, 3)):
            words.append(rng.choice(OPTIONS))
            words += [rng.choice(NUMBERS + VALUES) for _ in range(rng.randint(0, 3))]
        if rng.random() < 0.9:
            words.append(rng.choice(FILES))
    elif keyword == "newmtl":
        words.append(rng.choice(["m", "n", "m", "unused", "", "m n"]))
    else:
        words += [rng.choice(NUMBERS) for _ in range(rng.randint(0, 4))]
    if rng.random() < 0.1:
        words.append("# " + rng.choice(FILES))
    separator = rng.choice([" ", " ", "\t", "  ", "\x0b"])
    return separator.join([keyword, *words])


def library(rng: random.Random) -> bytes:
    lines = (["newmtl m"] if rng.random() < 0.8 else []) + [statement(rng) for _ in range(rng.randint(1, 12))]
    data = rng.choice(["\n", "\r\n", "\r"]).join(lines).encode("utf-8", "surrogatepass")
    if rng.random() < 0.1:
        at = rng.randrange(len(data) + 1)
        data = data[:at] + bytes(rng.randrange(256) for _ in range(rng.randint(1, 10))) + data[at:]
    return data


def write_case(folder: Path, rng: random.Random) -> None:
    (folder / "ok").mkdir(parents=True)
    for name, data in images(rng).items():
        (folder / "ok" / name).write_bytes(data)
        (folder / name).write_bytes(mutate(data, rng) if rng.random() < 0.9 else data)
    (folder / "m.mtl").write_bytes(library(rng))
    (folder / "model.obj").write_text("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\nusemtl n\nf 1 2 3\n")


# --- the oracle -----------------------------------------------------------------------------

def check(folder: Path) -> dict:
    """Judge one case; returns counts of what happened, or raises :class:`Failure`."""
    import numpy as np

    from rasterkit.material import Texture, TextureError
    from rasterkit.material.sampling import sample
    from rasterkit.obj.document import Document
    from rasterkit.obj.errors import Report
    from rasterkit.obj import materials as reader
    from rasterkit.obj.peek import map_kinds

    counts = {"materials": 0, "textures": 0, "warnings": 0, "opened": 0, "refused": 0}
    hostile = np.array([[0.3, 0.7], [1e300, -1e300], [np.nan, np.inf], [-np.inf, 5e-324], [2.0**62, -0.5]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            doc = Document.read(str(folder / "model.obj"))
            report = Report(doc.name)
            materials = reader.make_materials(reader.read_libraries(doc, report, whole=True), report)
        except Exception as e:  # noqa: BLE001 - the oracle judges every exception
            raise Failure(f"reading the materials: {type(e).__name__}: {e}") from e
        for text in report.warnings:
            if "\n" in text or "\r" in text:
                raise Failure(f"warning of several lines: {text!r}")
        try:  # the command line's guess before reading: never an error, and every map opened in it
            guess = map_kinds(folder / "model.obj")
        except Exception as e:  # noqa: BLE001
            raise Failure(f"map_kinds: {type(e).__name__}: {e}") from e
        opened = {kind for material in materials.values()
                  for kind, texture in (("diffuse", material.diffuse_map), ("alpha", material.opacity_map),
                                        ("normal", material.normal_map)) if texture is not None}
        if not opened <= guess <= {"diffuse", "alpha", "normal"}:
            raise Failure(f"map_kinds guessed {sorted(guess)}, the reader opened {sorted(opened)}")
        counts["materials"] += len(materials)
        counts["warnings"] += len(report.warnings)
        for material in materials.values():
            for texture in material.textures:
                try:
                    got = sample(texture, hostile, np.array([0.0, 1e300, np.nan, -np.inf, 3.5]))
                except Exception as e:  # noqa: BLE001
                    raise Failure(f"sampling {texture!r}: {type(e).__name__}: {e}") from e
                if not (np.isfinite(got).all() and (got >= 0).all() and (got <= 1).all()):
                    raise Failure(f"sampling {texture!r} gave {got.tolist()}")
                counts["textures"] += 1
        for name in IMAGES:
            path = folder / name
            try:
                Texture.open(path)
                counts["opened"] += 1
            except TextureError as e:
                text = str(e)
                if "\n" in text or not text.startswith(f"{path}: "):
                    raise Failure(f"Texture.open: not one line naming the file: {text!r}") from e
                counts["refused"] += 1
            except Exception as e:  # noqa: BLE001
                raise Failure(f"Texture.open({name}): {type(e).__name__}: {e}") from e
    return counts


# --- the run --------------------------------------------------------------------------------

def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=200, help="cases to make and check")
    parser.add_argument("--seed", type=int, default=0, help="random seed")
    parser.add_argument("--failures", type=Path, default=None, help="folder to keep failing cases in")
    parser.add_argument("--example-seconds", type=float, default=30.0, help="time limit of one case")
    args = parser.parse_args(argv)
    rng = random.Random(args.seed)
    start = time.perf_counter()
    totals = {"materials": 0, "textures": 0, "warnings": 0, "opened": 0, "refused": 0}
    failures = 0
    with tempfile.TemporaryDirectory(prefix="rasterkit-fuzz-mtl-") as work:
        for case in range(args.cases):
            folder = Path(work) / f"case-{case:05d}"
            write_case(folder, rng)
            # a hang (even inside a kernel, without the GIL) ends the process with a traceback
            faulthandler.dump_traceback_later(args.example_seconds if case else 600.0, exit=True)
            try:
                for key, value in check(folder).items():
                    totals[key] += value
            except Failure as failure:
                failures += 1
                print(f"FAILURE case {case}: {failure}", file=sys.stderr, flush=True)
                if args.failures is not None:
                    shutil.copytree(folder, args.failures / folder.name, dirs_exist_ok=True)
            finally:
                faulthandler.cancel_dump_traceback_later()
            shutil.rmtree(folder)
    print(f"checked {args.cases} cases in {time.perf_counter() - start:.0f} s: {totals['materials']} materials, "
          f"{totals['textures']} textures sampled, {totals['warnings']} warnings, {totals['opened']} files opened, "
          f"{totals['refused']} refused cleanly, {failures} failures", flush=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
