"""Results of one run: records, skip reasons, and the files written from them.

``results.json`` (schema version :data:`SCHEMA`)::

    {
      "schema": 1,
      "profile": "full" | "quick" | "tiny",
      "machine": {"platform", "processor", "cpu_count", "threads", "python",
                  "versions": {"rasterkit", "numpy", "numba", "moderngl", ...},
                  "gl_renderer", "started", "seconds"},
      "records": [
        {"family":     "render" | "fill" | "threads" | "lines2d" | "loading" | "cli"
                       | "memory" | "scaling" | "startup" | "contention" | "textures" | ...,
         "name":       unique workload name, e.g. "render/solid/ogre/1920x1080",
         "peer":       the other side, e.g. "llvmpipe", or null when it could not run,
         "sizes":      workload sizes, e.g. {"width", "height", "triangles", "edges"},
         "quantity":   "seconds" (the median of the timed runs), "peak_bytes" or "bytes"
                       (memory held, not a peak),
         "rasterkit":  rasterkit's value,
         "peer_value": the peer's value, or null,
         "ratio":      rasterkit / peer (below 1: rasterkit is faster or smaller), or null,
         "throughput": {"unit", "rasterkit", "peer"} (work per second), or null,
         "target":     {"text", "max_ratio", "met"}, or null,
         "runs":       timed runs per side,
         "note":       free text}
      ],
      "fits": [{"sweep": "triangles" | "pixels", "side", "exponent", "smallest", "largest"}],
      "skipped": [{"family", "what", "reason"}]
    }

``results.md`` holds the same records as Markdown tables, targets first; the PNG plots show
time against triangle count and against pixel count, one line per side.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path

SCHEMA = 1


@dataclass(frozen=True)
class Target:
    """A goal on the ratio rasterkit / peer (of times): met when ``ratio <= max_ratio``."""

    text: str
    max_ratio: float


@dataclass
class Record:
    """One workload against one peer (see the module docstring for the fields)."""

    family: str
    name: str
    peer: str | None
    sizes: dict
    rasterkit: float
    peer_value: float | None = None
    quantity: str = "seconds"
    work: float | None = None
    unit: str | None = None
    target: Target | None = None
    runs: int = 0
    note: str = ""

    @property
    def ratio(self) -> float | None:
        if not self.peer_value:  # missing, or a peer that used no measurable memory
            return None
        return self.rasterkit / self.peer_value

    @property
    def met(self) -> bool | None:
        if self.target is None or self.ratio is None:
            return None
        return self.ratio <= self.target.max_ratio

    def as_json(self) -> dict:
        throughput = None
        if self.work is not None and self.quantity == "seconds":
            throughput = {"unit": self.unit, "rasterkit": self.work / self.rasterkit,
                          "peer": self.work / self.peer_value if self.peer_value else None}
        target = None if self.target is None else {**asdict(self.target), "met": self.met}
        return {"family": self.family, "name": self.name, "peer": self.peer, "sizes": self.sizes,
                "quantity": self.quantity, "rasterkit": self.rasterkit,
                "peer_value": self.peer_value, "ratio": self.ratio, "throughput": throughput,
                "target": target, "runs": self.runs, "note": self.note}


@dataclass
class Results:
    """Collects the records and skip reasons of one run, printing each as it arrives."""

    records: list[Record] = field(default_factory=list)
    skipped: list[dict] = field(default_factory=list)
    fits: list[dict] = field(default_factory=list)

    def add(self, record: Record) -> None:
        self.records.append(record)
        print("  " + _summary(record), flush=True)

    def fit(self, sweep: str, side: str, exponent: float, sizes: list) -> None:
        """Record the fitted growth exponent of one side over one sweep (1 = linear)."""
        self.fits.append({"sweep": sweep, "side": side, "exponent": exponent,
                          "smallest": min(sizes), "largest": max(sizes)})
        print(f"  {sweep} sweep, {side}: time grows as size^{exponent:.2f}", flush=True)

    def skip(self, family: str, what: str, reason: str) -> None:
        """Record that ``what`` did not run, and print why (never skip silently)."""
        self.skipped.append({"family": family, "what": what, "reason": reason})
        print(f"  skipped {what}: {reason}", flush=True)


def _summary(r: Record) -> str:
    text = f"{r.name:44s} rasterkit {_value(r.rasterkit, r.quantity)}"
    if r.peer_value is not None:
        text += f" | {r.peer} {_value(r.peer_value, r.quantity)} | ratio {_number(r.ratio)}"
    if r.target is not None and r.met is not None:
        text += f" | target {r.target.text}: {'met' if r.met else 'MISSED'}"
    return text


def _value(value: float, quantity: str) -> str:
    if quantity in ("peak_bytes", "bytes"):
        return f"{value / 2**20:.1f} MiB"
    return f"{value * 1e3:.3f} ms" if value < 10 else f"{value:.2f} s"


def write_json(path: Path, results: Results, profile: str, machine: dict) -> None:
    document = {"schema": SCHEMA, "profile": profile, "machine": machine,
                "records": [r.as_json() for r in results.records], "fits": results.fits,
                "skipped": results.skipped}
    path.write_text(json.dumps(document, indent=1, allow_nan=False) + "\n")


# ---------------------------------------------------------------------------- Markdown


def _number(value: float | None, digits: int = 3) -> str:
    if value is None or not math.isfinite(value):
        return "-"
    return f"{value:.{digits}g}"


def _throughput(r: Record, value: float | None) -> str:
    if r.work is None or r.quantity != "seconds" or not value:
        return "-"
    return f"{_number(r.work / value)} {r.unit}"


def _sizes(sizes: dict) -> str:
    return ", ".join(f"{k} {v}" for k, v in sizes.items())


def _row(r: Record) -> str:
    target = "-" if r.target is None else r.target.text
    met = {None: "-", True: "met", False: "**missed**"}[r.met]
    cells = [r.name, _sizes(r.sizes), r.peer or "(none)", _value(r.rasterkit, r.quantity),
             "-" if r.peer_value is None else _value(r.peer_value, r.quantity),
             _number(r.ratio), _throughput(r, r.rasterkit), _throughput(r, r.peer_value),
             target, met]
    return "| " + " | ".join(cells) + " |"


_HEADER = ("| workload | sizes | peer | rasterkit | peer | ratio rk/peer | rasterkit throughput "
           "| peer throughput | target | met |\n|" + "---|" * 10)


def markdown(results: Results, profile: str, machine: dict) -> str:
    """The records as Markdown: machine, targets, one table per family, skip reasons."""
    versions = ", ".join(f"{k} {v}" for k, v in machine["versions"].items())
    lines = [f"# rasterkit benchmarks ({profile})", "",
             f"{machine['platform']}; {machine['cpu_count']} CPUs, {machine['threads']} Numba threads "
             f"({machine.get('threading_layer') or 'layer unknown'}); "
             f"GL: {machine.get('gl_renderer') or 'unavailable'}", "", f"Versions: {versions}", "",
             "Times are medians of the timed runs; ratio = rasterkit / peer (below 1: rasterkit "
             "is faster or uses less memory).", ""]
    targeted = [r for r in results.records if r.target is not None]
    if targeted:
        lines += ["## Targets", "", _HEADER, *map(_row, targeted), ""]
    families = list(dict.fromkeys(r.family for r in results.records))
    for family in families:
        lines += [f"## {family}", "", _HEADER,
                  *(_row(r) for r in results.records if r.family == family), ""]
    if results.fits:
        lines += ["## Growth", "", "Least-squares fit of time = a * size^b (log-log); b = 1 is linear.",
                  "", "| sweep | side | b | sizes |", "|---|---|---|---|"]
        lines += [f"| {f['sweep']} | {f['side']} | {f['exponent']:.2f} | {_label(f['smallest'])} "
                  f"to {_label(f['largest'])} |" for f in results.fits]
        lines.append("")
    if results.skipped:
        lines += ["## Skipped", ""]
        lines += [f"- {s['family']}: {s['what']}: {s['reason']}" for s in results.skipped]
        lines.append("")
    return "\n".join(lines)


# ---------------------------------------------------------------------------- plots

_COLORS = [(31, 119, 180), (214, 39, 40), (44, 160, 44), (148, 103, 189), (255, 127, 14),
           (140, 86, 75)]


def _log_ticks(lo: float, hi: float) -> list[float]:
    """1-2-5 ticks covering [lo, hi] (positive)."""
    ticks = []
    for exponent in range(math.floor(math.log10(lo)), math.ceil(math.log10(hi)) + 1):
        ticks += [m * 10.0**exponent for m in (1, 2, 5) if lo <= m * 10.0**exponent <= hi]
    return ticks or [lo, hi]


def _label(value: float) -> str:
    for scale, suffix in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if value >= scale:
            return f"{value / scale:g}{suffix}"
    return f"{value:g}"


def plot(path: Path, title: str, x_label: str, y_label: str, series: dict[str, list[tuple[float, float]]]) -> None:
    """A log-log line chart drawn with Pillow: one line (with markers) per series.

    ``series`` maps a legend name to its (x, y) points; non-positive values are left out.
    """
    from PIL import Image, ImageDraw

    series = {k: sorted((x, y) for x, y in v if x > 0 and y > 0) for k, v in series.items()}
    series = {k: v for k, v in series.items() if v}
    width, height, left, right, top, bottom = 900, 560, 90, 200, 50, 70
    image = Image.new("RGB", (width, height), "white")
    draw = ImageDraw.Draw(image)
    draw.text((left, 15), title, fill="black")
    if not series:
        draw.text((left, height // 2), "no data", fill="black")
        image.save(path)
        return
    xs = [x for v in series.values() for x, _ in v]
    ys = [y for v in series.values() for _, y in v]
    (x_lo, x_hi), (y_lo, y_hi) = _padded(min(xs), max(xs)), _padded(min(ys), max(ys))

    def to_pixel(x, y):
        u = (math.log(x) - math.log(x_lo)) / (math.log(x_hi) - math.log(x_lo))
        v = (math.log(y) - math.log(y_lo)) / (math.log(y_hi) - math.log(y_lo))
        return left + u * (width - left - right), height - bottom - v * (height - top - bottom)

    draw.rectangle([left, top, width - right, height - bottom], outline="black")
    for tick in _log_ticks(x_lo, x_hi):
        px, _ = to_pixel(tick, y_lo)
        draw.line([px, top, px, height - bottom], fill=(225, 225, 225))
        draw.text((px - 10, height - bottom + 5), _label(tick), fill="black")
    for tick in _log_ticks(y_lo, y_hi):
        _, py = to_pixel(x_lo, tick)
        draw.line([left, py, width - right, py], fill=(225, 225, 225))
        draw.text((5, py - 6), f"{tick * 1e3:g} ms", fill="black")
    draw.text(((left + width - right) // 2 - 40, height - 30), x_label, fill="black")
    draw.text((5, top - 20), y_label, fill="black")
    for k, (name, points) in enumerate(series.items()):
        color = _COLORS[k % len(_COLORS)]
        pixels = [to_pixel(x, y) for x, y in points]
        if len(pixels) > 1:
            draw.line(pixels, fill=color, width=2)
        for px, py in pixels:
            draw.ellipse([px - 3, py - 3, px + 3, py + 3], fill=color)
        ly = top + 10 + 20 * k
        draw.line([width - right + 10, ly + 6, width - right + 35, ly + 6], fill=color, width=3)
        draw.text((width - right + 40, ly), name, fill="black")
    image.save(path)


def _padded(lo: float, hi: float) -> tuple[float, float]:
    """A log-scale range around [lo, hi] with a little room (never empty)."""
    if hi <= lo:
        return lo / 2, hi * 2
    pad = (hi / lo) ** 0.05
    return lo / pad, hi * pad


def _series(records, x_of) -> dict[str, list[tuple[float, float]]]:
    """One series for rasterkit and one per peer: (x_of(record), seconds) points."""
    series: dict[str, dict[str, tuple[float, float]]] = {"rasterkit": {}}
    for r in records:
        series["rasterkit"][r.name] = (x_of(r), r.rasterkit)
        if r.peer is not None and r.peer_value is not None:
            series.setdefault(r.peer, {})[r.name] = (x_of(r), r.peer_value)
    return {side: list(points.values()) for side, points in series.items() if points}


def plot_series(results: Results) -> list[tuple[str, str, str, dict]]:
    """(file name, title, x label, series) of every plot the records allow.

    ``scaling_triangles.png`` and ``scaling_pixels.png`` come from the sweeps of
    :mod:`benchmarks.scaling`; ``render_<mode>_<W>x<H>.png`` plot the real models of each
    render mode against their triangle count at each resolution.
    """
    timed = [r for r in results.records if r.quantity == "seconds"]
    plots = []
    sweeps = (("triangles", "triangle count", lambda r: r.sizes["triangles"]),
              ("pixels", "pixel count (width x height)", lambda r: r.sizes["width"] * r.sizes["height"]))
    for sweep, x_label, x_of in sweeps:
        chosen = [r for r in timed if r.name.startswith(f"scaling/{sweep}/")]
        if chosen:
            plots.append((f"scaling_{sweep}.png", f"solid frame: time against {x_label} (log-log)",
                          x_label, _series(chosen, x_of)))
    groups: dict[tuple[str, str], list[Record]] = {}
    for r in timed:
        if r.family == "render":
            _, mode, _, size = r.name.split("/")
            groups.setdefault((mode, size), []).append(r)
    for (mode, size), chosen in groups.items():
        plots.append((f"render_{mode.replace('+', '_')}_{size}.png",
                      f"{mode} frame at {size}: time against the models' triangle count (log-log)",
                      "triangle count", _series(chosen, lambda r: r.sizes["triangles"])))
    return plots
