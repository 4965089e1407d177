"""The statements of an ``.mtl`` file that make a :class:`~rasterkit.Material`, read into
plain values (the texture files are opened by :mod:`rasterkit.obj.textures`).

Read, for the materials the model uses (``newmtl NAME``; a later definition of a name
replaces an earlier one):

- ``Kd``, ``Ks``, ``Ke`` ``r [g b]`` (one number is grey; ``Kd`` and ``Ks`` clipped to [0, 1],
  ``Ke`` to [0, inf)). A material without ``Kd`` gets :class:`~rasterkit.Material`'s default
  diffuse: (1, 1, 1) when its ``map_Kd`` could be read (the texture as it is), else (0.8,
  0.8, 0.8); its face colour (``Mesh.face_colors``) is (0.8, 0.8, 0.8) either way.
- ``Ns`` exponent (>= 0); ``d`` opacity (``d -halo x`` too) and ``Tr`` transparency,
  clipped to [0, 1]. ``d`` wins over ``Tr`` when a material has both. A ``Tr`` alone gives
  the opacity ``1 - Tr``, except ``Tr 1`` (nothing visible), which is read as opaque:
  MeshLab and some 3ds Max exporters write ``Tr`` as the opacity, and a material that draws
  nothing is not what such a file means (``fuze.obj.mtl`` has it).
- ``map_Kd``, ``map_d``, ``map_Ks`` and ``map_Bump`` / ``bump`` / ``norm`` (these keywords in
  any case: files write ``map_bump`` and ``map_kd`` too) with the options ``-s u [v [w]]``
  (scale, default 1), ``-o u [v [w]]`` (offset, default 0), ``-clamp on|off`` and ``-bm x``
  (bump multiplier); ``-blendu``, ``-blendv``, ``-boost``, ``-mm`` (2), ``-t`` (1 to 3),
  ``-texres``, ``-imfchan``, ``-type`` and ``-cc`` are skipped with their arguments. The file
  name is the rest of the line, as written (spaces included: ``map_Kd fuze uv.jpg``; a name
  in double quotes loses them).

Keywords other than the maps are matched exactly. A library is parsed once per load: for the
face colours only its ``newmtl`` and ``Kd`` lines are looked at (``load_obj`` without
textures), for whole materials every statement above. A statement that cannot be read (a
bad number, a bad option value, a map without a file name) is left out; the ``Kd`` lines of
a library left out so are one warning (the first, and how many more), its other statements
another (:meth:`Library.warn`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from rasterkit.obj.document import decode
from rasterkit.obj.errors import Report, count
from rasterkit.obj.kernels.scan import BLANKS

__all__ = ["MAP_FIELDS", "Library", "MapStatement", "MaterialSpec", "parse_library"]

#: The Material field of each map keyword (lower case).
MAP_FIELDS = {"map_kd": "diffuse_map", "map_d": "opacity_map", "map_ks": "specular_map",
              "map_bump": "normal_map", "bump": "normal_map", "norm": "normal_map"}

#: Options skipped, with their count of arguments.
_SKIPPED = {"-blendu": 1, "-blendv": 1, "-boost": 1, "-mm": 2, "-texres": 1, "-imfchan": 1, "-type": 1, "-cc": 1}
#: Options of 1 to 3 numbers, and the default of those left out.
_VECTORS = {"-s": 1.0, "-o": 0.0, "-t": 0.0}

_BLANK = re.escape(BLANKS).decode()
_KEYWORDS = "newmtl|Kd|Ks|Ke|Ns|d|Tr|(?i:map_kd|map_d|map_ks|map_bump|bump|norm)"
_STATEMENT = re.compile(f"^[{_BLANK}]*({_KEYWORDS})(?![^{_BLANK}\n])[^\n]*".encode(), re.M)
_KD_STATEMENT = re.compile(f"^[{_BLANK}]*(newmtl|Kd)(?![^{_BLANK}\n])[^\n]*".encode(), re.M)
_TOKEN = re.compile(f"[^{_BLANK}\n]+".encode())


@dataclass
class MapStatement:
    """A map statement: its keyword, the file name as written, its line and its options."""

    keyword: str
    file: str
    line: int
    wrap: str = "repeat"
    scale: tuple = (1.0, 1.0)
    offset: tuple = (0.0, 0.0)
    bump_scale: float = 1.0


@dataclass
class MaterialSpec:
    """What a library says of one material: Material field values and its map statements."""

    library: str
    values: dict = field(default_factory=dict)
    maps: dict = field(default_factory=dict)  # Material field: MapStatement
    transparency: float | None = None  # Tr, used when there is no d


class _Unreadable(Exception):
    """A statement that cannot be read."""


def _number(token: bytes, low: float = -math.inf, high: float = math.inf) -> float:
    try:
        value = float(token)
    except ValueError:
        raise _Unreadable from None
    if not math.isfinite(value):
        raise _Unreadable
    return min(max(value, low), high)


def _rgb(tokens: list, high: float) -> tuple:
    """``r [g b]`` as Kd is read: one number (grey) or three (more are ignored)."""
    rgb = [_number(t, 0.0, high) for t in tokens[:3]]
    if len(rgb) not in (1, 3):
        raise _Unreadable
    return tuple(rgb * (3 // len(rgb)))


def _map(keyword: str, text: bytes, line: int) -> MapStatement:
    """A map statement from its text (the keyword's token first)."""
    spans = [m.span() for m in _TOKEN.finditer(text)]
    for k, (a, _) in enumerate(spans):
        if text[a:a + 1] == b"#":
            spans = spans[:k]
            break
    found = MapStatement(keyword, "", line)
    k = 1
    while k < len(spans):
        option = text[spans[k][0]:spans[k][1]].lower().decode("latin-1")
        if option in _VECTORS:
            numbers = []
            while len(numbers) < 3 and k + 1 + len(numbers) < len(spans):
                try:
                    numbers.append(_number(text[slice(*spans[k + 1 + len(numbers)])]))
                except _Unreadable:
                    break
            if not numbers:
                raise _Unreadable
            pair = (numbers + [_VECTORS[option]] * 2)[:2]
            if option == "-s":
                found.scale = tuple(pair)
            elif option == "-o":
                found.offset = tuple(pair)
            k += 1 + len(numbers)
        elif option in ("-clamp", "-bm") or option in _SKIPPED:
            arity = _SKIPPED.get(option, 1)
            if k + arity >= len(spans):
                raise _Unreadable
            argument = text[slice(*spans[k + 1])]
            if option == "-clamp":
                setting = argument.lower()
                if setting not in (b"on", b"off"):
                    raise _Unreadable
                found.wrap = "clamp" if setting == b"on" else "repeat"
            elif option == "-bm":
                found.bump_scale = _number(argument)
            k += 1 + arity
        else:
            break
    if k >= len(spans):
        raise _Unreadable  # no file name
    name = decode(text[spans[k][0]:spans[-1][1]])
    if len(name) >= 2 and name[0] == name[-1] == '"':
        name = name[1:-1]
    if not name:
        raise _Unreadable
    found.file = name
    return found


def _apply(spec: MaterialSpec, keyword: str, text: bytes, line: int) -> None:
    """Read one statement of a material into ``spec`` (``keyword`` as written: a map's in any
    case); :class:`_Unreadable` when it cannot be."""
    arguments = _words(text)[1:]
    if keyword in ("Kd", "Ks"):
        spec.values["diffuse" if keyword == "Kd" else "specular"] = _rgb(arguments, 1.0)
    elif keyword == "Ke":
        spec.values["emission"] = _rgb(arguments, math.inf)
    elif keyword == "Ns":
        spec.values["shininess"] = _number(arguments[0] if arguments else b"", 0.0)
    elif keyword == "d":
        if arguments[:1] == [b"-halo"]:
            arguments = arguments[1:]
        spec.values["opacity"] = _number(arguments[0] if arguments else b"", 0.0, 1.0)
    elif keyword == "Tr":
        spec.transparency = _number(arguments[0] if arguments else b"", 0.0, 1.0)
    else:
        statement = _map(keyword, text, line)
        spec.maps[MAP_FIELDS[keyword.lower()]] = statement
        if MAP_FIELDS[keyword.lower()] == "normal_map":
            spec.values["bump_scale"] = statement.bump_scale


@dataclass
class Library:
    """What one ``.mtl`` file says of the wanted materials: a :class:`MaterialSpec` of each
    (``specs``, by name; a later definition replaces an earlier) and the statements of those
    materials that could not be read, ``(line, text)``, ``Kd`` (``bad_kd``) apart from the
    others (``bad``): each list is one warning (:meth:`warn`)."""

    name: str
    specs: dict = field(default_factory=dict)
    bad_kd: list = field(default_factory=list)
    bad: list = field(default_factory=list)

    def warn(self, report: Report, kd: bool) -> None:
        """Warn about the first unreadable ``Kd`` line (``kd``) or other statement, and count
        the rest."""
        lines, what = (self.bad_kd, "Kd ") if kd else (self.bad, "")
        if lines:
            more = f" (and {count(len(lines) - 1, 'more such line')})" if len(lines) > 1 else ""
            report.warn(lines[0][0], f"cannot read {what}{lines[0][1]!r}{more}", self.name)


def parse_library(data: bytes, name: str, wanted: set, whole: set) -> Library:
    """The :class:`Library` of an ``.mtl`` file's bytes (``name``: the file, for warnings):
    the ``Kd`` of each ``wanted`` material (what the face colours need), and every statement
    of those also in ``whole``. Without ``whole`` only the ``newmtl`` and ``Kd`` lines are
    looked at."""
    if b"\n" not in data:  # old Mac files break lines with CR alone
        data = data.replace(b"\r", b"\n")
    library = Library(name)
    specs = library.specs
    current = None
    line, counted = 1, 0
    for match in (_STATEMENT if whole else _KD_STATEMENT).finditer(data):
        line += data.count(b"\n", counted, match.start())
        counted = match.start()
        keyword = match.group(1).decode("ascii")
        text = match.group()
        if keyword == "newmtl":
            current = " ".join(decode(w) for w in _words(text)[1:])
            if current in wanted:
                specs[current] = MaterialSpec(name)
            continue
        if current not in specs or (keyword != "Kd" and current not in whole):
            continue
        try:
            _apply(specs[current], keyword, text, line)
        except _Unreadable:
            (library.bad_kd if keyword == "Kd" else library.bad).append((line, decode(text).strip()))
    return library


def _words(text: bytes) -> list:
    """The tokens of a statement before its comment (as the face colours' reader splits them)."""
    words = text.split()
    for k, word in enumerate(words):
        if word.startswith(b"#"):
            return words[:k]
    return words
