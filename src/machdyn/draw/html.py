r"""The browser back end: an inline SVG of a scene, and a self-contained animated page.

:func:`to_svg` writes one frame of a :class:`~machdyn.draw.scene.Scene` as an
``<svg>`` element; :func:`widget` adds the frames as JSON, a play/pause
button, a frame slider and a readout table; :func:`to_html` wraps a widget in a
page. The page's small script only moves the drawn elements to the embedded
solved coordinates; it computes no kinematics, and nothing is loaded from the
network (no external script, style sheet, font or image).

Everything from the user is escaped: names and labels with
:func:`html.escape`, the JSON made safe for a ``<script>`` element (``<``,
``>``, ``&`` and the line separators written as ``\u`` escapes); non-finite
numbers become ``null`` (a gap, or a hidden element, never a zero).

Coordinates are printed with :func:`decimals` places (six significant digits
of the drawing's size), in the scene's own units, y up.
"""

from __future__ import annotations

import html
import itertools
import json
import math
import re
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import finite_scalar
from ..errors import InputError
from . import symbols
from .chart import _overlap
from .scene import Item, Scene, is_static

__all__ = ["DATA_CLASS", "decimals", "script_json", "to_html", "to_svg", "widget"]

#: Class of the ``<script type="application/json">`` element holding a widget's frames.
DATA_CLASS = "machdyn-frames"

_counter = itertools.count(1)


def decimals(size: float) -> int:
    """Decimal places printed for coordinates of a drawing ``size`` across (6 digits).

    Examples
    --------
    >>> decimals(10.0), decimals(250.0), decimals(0.05)
    (4, 3, 7)
    """
    if not math.isfinite(size) or size <= 0:
        return 6
    return int(min(12, max(0, 5 - math.floor(math.log10(size)))))


def script_json(data: Any) -> str:
    r"""JSON that cannot end or break out of the ``<script>`` element it sits in.

    Examples
    --------
    >>> script_json({"name": "</script>"})
    '{"name":"\\u003c/script\\u003e"}'
    """
    text = json.dumps(data, allow_nan=False, separators=(",", ":"), ensure_ascii=False)
    for char, escape in (
        ("&", "\\u0026"),
        ("<", "\\u003c"),
        (">", "\\u003e"),
        ("\u2028", "\\u2028"),
        ("\u2029", "\\u2029"),
    ):
        text = text.replace(char, escape)
    return text


_HIDDEN = ' visibility="hidden"'
_XMLNS = ' xmlns="http://www.w3.org/2000/svg"'


def _esc(text: Any) -> str:
    return html.escape(str(text), quote=True)


def _num(v: float, places: int) -> str:
    """A number as printed in the SVG (rounded; '-0' written as '0')."""
    s = f"{v:.{places}f}"
    if "." in s:
        s = s.rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _rounded(values: np.ndarray, places: int) -> list[float | None]:
    out: list[float | None] = []
    for v in np.asarray(values, dtype=float).tolist():
        out.append(round(v, places) + 0.0 if math.isfinite(v) else None)
    return out


class _Frame:
    """Coordinates of one frame as the SVG prints them."""

    def __init__(self, scene: Scene, k: int, places: int, unit: float) -> None:
        self.scene, self.k, self.places, self.unit = scene, k, places, unit

    def z(self, name: str) -> complex:
        return complex(self.scene.xy[self.k, self.scene.index(name)])

    def n(self, v: float) -> str:
        return _num(v, self.places)

    def angle_deg(self, item: Item) -> float:
        if item.angle is None:
            return 0.0
        a = float(self.scene.angles[item.angle][self.k])
        return math.degrees(a) if math.isfinite(a) else 0.0


def _finite(*zs: complex) -> bool:
    return all(math.isfinite(z.real) and math.isfinite(z.imag) for z in zs)


def _poly(points: np.ndarray, f: _Frame, x_places: int | None = None) -> str:
    fx = f.n if x_places is None else (lambda v: _num(v, x_places))
    return " ".join(f"{fx(z.real)},{f.n(z.imag)}" for z in points)


def _transform(at: complex, deg: float, f: _Frame, scale: float | None = None) -> str:
    out = f"translate({f.n(at.real)} {f.n(at.imag)}) rotate({_num(deg, 4)})"
    if scale is not None:
        out += f" scale({f.n(scale)} 1)"
    return out


def _ns(kind: str) -> str:
    """Stroke attributes that keep a line's width in screen pixels."""
    return f'vector-effect="non-scaling-stroke" class="{kind}"'


def _item_svg(item: Item, f: _Frame, uid: str) -> str:
    """One item as SVG in frame ``f`` (y up: inside the flipped world group)."""
    u = f.unit
    pts = [f.z(p) for p in item.points]
    hidden = not _finite(*pts)
    vis = ' visibility="hidden"' if hidden else ""
    pts = [z if _finite(z) else 0j for z in pts]
    gid = f'id="{uid}-{_esc(item.gid)}" data-name="{_esc(item.body or item.label)}"'
    title = f"<title>{_esc(item.body or item.label or item.gid)}</title>"
    c = _esc(item.colour)
    k = item.kind
    if k == "bar" or k == "line":
        (p, q) = pts
        width = 6 if k == "bar" else 1.2
        dash = ' stroke-dasharray="6 4"' if k == "line" and item.body.endswith("(ground)") else ""
        return (
            f'<line {gid} x1="{f.n(p.real)}" y1="{f.n(p.imag)}" x2="{f.n(q.real)}" '
            f'y2="{f.n(q.imag)}" stroke="{c}" stroke-width="{width}" stroke-linecap="round"'
            f"{dash} {_ns(k)}{vis}>{title}</line>"
        )
    if k == "plate":
        return (
            f'<polygon {gid} points="{_poly(np.array(pts), f)}" fill="{c}" fill-opacity="0.3" '
            f'stroke="{c}" stroke-width="2" stroke-linejoin="round" {_ns(k)}{vis}>{title}</polygon>'
        )
    if k in ("pin", "point"):
        r = 1.1 * u if k == "pin" else 0.9 * u
        fill, stroke = ("#ffffff", "#000000") if k == "pin" else (c, c)
        circles = "".join(
            f'<circle cx="{f.n(z.real)}" cy="{f.n(z.imag)}" r="{f.n(r)}" fill="{fill}" '
            f'stroke="{stroke}" stroke-width="1.3" {_ns(k)}'
            f"{_HIDDEN if not _finite(f.z(p)) else ''}/>"
            for z, p in zip(pts, item.points, strict=True)
        )
        return f"<g {gid}>{circles}</g>"
    if k == "ground":
        tri, strip = symbols.ground_symbol(4.5 * u)
        at = pts[0]
        return (
            f'<g {gid} transform="{_transform(at, 0.0, f)}">{title}'
            f'<polygon points="{_poly(strip, f)}" fill="url(#{uid}-hatch)" stroke="none"/>'
            f'<polygon points="{_poly(tri, f)}" fill="#e6e6e6" stroke="#000" stroke-width="1" '
            f"{_ns(k)}/></g>"
        )
    if k == "guide":
        p, q = pts
        length = abs(q - p)
        deg = math.degrees(math.atan2((q - p).imag, (q - p).real)) if length > 0 else 0.0
        h = 0.55 * (item.size or 8 * u)
        body = (
            f'<line x1="0" y1="{f.n(-h / 2)}" x2="{f.n(length)}" y2="{f.n(-h / 2)}" '
            f'stroke="{c}" stroke-width="1.3" {_ns(k)}/>'
            f'<rect x="0" y="{f.n(-h / 2 - 1.6 * u)}" width="{f.n(length)}" '
            f'height="{f.n(1.6 * u)}" '
            f'fill="url(#{uid}-hatch)"/>'
        )
        return f'<g {gid} transform="{_transform(p, deg, f)}"{vis}>{title}{body}</g>'
    if k == "slider":
        length = item.size or 8 * u
        outline = symbols.block(length, 0.55 * length)
        return (
            f'<g {gid} transform="{_transform(pts[0], f.angle_deg(item), f)}"{vis}>{title}'
            f'<polygon points="{_poly(outline, f)}" fill="{c}" fill-opacity="0.6" stroke="#000" '
            f'stroke-width="1.3" {_ns(k)}/></g>'
        )
    if k in ("shape", "wheel"):
        if k == "wheel":
            t = np.linspace(0, 2 * np.pi, 73)
            outline = item.size * np.exp(1j * t)
            extra = (
                f'<line x1="0" y1="0" x2="{f.n(item.size)}" y2="0" stroke="{c}" '
                f'stroke-width="2" {_ns(k)}/>'
                if item.body != "ground"
                else ""
            )
            closed = item.closed
        else:
            outline = np.asarray(item.outline, complex)
            extra, closed = "", item.closed
        tag = "polygon" if closed else "polyline"
        fill = f'fill="{c}" fill-opacity="0.25"' if closed else 'fill="none"'
        return (
            f'<g {gid} transform="{_transform(pts[0], f.angle_deg(item), f)}"{vis}>{title}'
            f'<{tag} points="{_poly(outline, f)}" {fill} stroke="{c}" stroke-width="1.4" '
            f'stroke-linejoin="round" {_ns(k)}/>{extra}</g>'
        )
    if k in ("spring", "damper", "actuator"):
        p, q = pts
        length = abs(q - p)
        deg = math.degrees(math.atan2((q - p).imag, (q - p).real)) if length > 0 else 0.0
        if k == "actuator":
            barrel = _actuator_barrel(item, f.scene)
            body = (
                f'<line x1="0" y1="0" x2="{f.n(barrel)}" y2="0" stroke="{c}" stroke-width="11" '
                f'stroke-opacity="0.55" {_ns(k)}/>'
                f'<line class="rod" x1="{f.n(0.4 * barrel)}" y1="0" x2="{f.n(length)}" y2="0" '
                f'stroke="#333" stroke-width="3" vector-effect="non-scaling-stroke"/>'
            )
            return f'<g {gid} transform="{_transform(p, deg, f)}"{vis}>{title}{body}</g>'
        if k == "spring":
            x, y = symbols.spring(1.8 * u)
            lines = [(x, y)]
        else:
            lines = symbols.damper(4.0 * u)
        body = "".join(
            f'<polyline points="{_poly(xs + 1j * ys, f, x_places=4)}" '
            f'fill="none" stroke="{c}" stroke-width="1.5" {_ns(k)}/>'
            for xs, ys in lines
        )
        where = _transform(p, deg, f, scale=length or 1.0)
        return f'<g {gid} transform="{where}"{vis}>{title}{body}</g>'
    if k == "motor":
        arc = symbols.motor_arrow(3.2 * u)
        return (
            f'<g {gid} transform="{_transform(pts[0], 0.0, f)}"{vis}>{title}'
            f'<polyline points="{_poly(arc, f)}" fill="none" stroke="{c}" stroke-width="1.6" '
            f"{_ns(k)}/></g>"
        )
    raise InputError("kind", f"no SVG for {k!r}")  # pragma: no cover - KINDS is closed


def _actuator_barrel(item: Item, scene: Scene) -> float:
    p, q = (scene.point(n) for n in item.points)
    lengths = np.abs(q - p)
    lengths = lengths[np.isfinite(lengths)]
    return float(0.62 * lengths.min()) if lengths.size else 1.0


def _labels(scene: Scene, f: _Frame, uid: str) -> str:
    """Point names beside their points (in the unflipped overlay, y = −Y)."""
    named = []
    for item in scene.items:
        if item.kind in ("pin", "ground", "point"):
            named += [p for p in item.points if p not in named]
    out = []
    u, size = f.unit, 3.4 * f.unit
    placed: list[tuple[float, float, float, float]] = []
    for p in named:
        z = f.z(p)
        vis = "" if _finite(z) else ' visibility="hidden"'
        z = z if _finite(z) else 0j
        # above right of the point; else below right, above left, below left: wherever it
        # covers no name already placed (e.g. a gear mesh's close contact points)
        w = 0.62 * size * len(p)  # ~0.62 em a character
        for kx, ky in ((1.0, -1.0), (1.0, 2.7), (-1.0, -1.0), (-1.0, 2.7)):
            x, y = z.real + kx * 1.6 * u, -z.imag + ky * 1.6 * u
            box = (
                x - (w if kx < 0 else 0.0),
                y - size,
                x + (w if kx > 0 else 0.0),
                y + 0.25 * size,
            )
            if not any(_overlap(box, b) for b in placed):
                break
        placed.append(box)
        moved = "" if (kx, ky) == (1.0, -1.0) else f' data-off="{kx:g} {ky:g}"'
        anchor = ' text-anchor="end"' if kx < 0 else ""
        out.append(
            f'<text data-point="{scene.index(p)}" x="{f.n(x)}" y="{f.n(y)}"'
            f"{moved}{anchor}{vis}>{_esc(p)}</text>"
        )
    for c in scene.curves:  # numbered targets (static; drawn with the names)
        if c.style == "markers":
            for i, z in enumerate(np.ravel(np.asarray(c.points, complex)), start=1):
                if _finite(z):
                    out.append(
                        f'<text class="target-number" x="{f.n(z.real + 1.5 * f.unit)}" '
                        f'y="{f.n(-z.imag + 3.2 * f.unit)}" fill="{_esc(c.colour)}">{i}</text>'
                    )
    size = f.n(3.4 * f.unit)
    return f'<g id="{uid}-labels" class="labels" font-size="{size}">{"".join(out)}</g>'


def _curves(scene: Scene, f: _Frame, uid: str) -> str:
    out = []
    for c in scene.curves:
        pts = np.ravel(np.asarray(c.points, complex))
        gid = f'id="{uid}-{_esc(c.gid)}" data-name="{_esc(c.label)}"'
        title = f"<title>{_esc(c.label)}</title>" if c.label else ""
        if c.style == "markers":
            marks = "".join(
                f'<g class="target"><circle cx="{f.n(z.real)}" cy="{f.n(z.imag)}" '
                f'r="{f.n(1.3 * f.unit)}" fill="none" stroke="{_esc(c.colour)}" stroke-width="1.6" '
                f"{_ns('target')}/></g>"
                for z in pts
                if _finite(z)
            )
            out.append(f"<g {gid}>{title}{marks}</g>")
            continue
        # a NaN splits the curve: one polyline per run of finite points (a gap, not a zero)
        good = np.isfinite(pts)
        runs, start = [], None
        for i, ok in enumerate([*good.tolist(), False]):
            if ok and start is None:
                start = i
            elif not ok and start is not None:
                runs.append(pts[start:i])
                start = None
        dash = ' stroke-dasharray="5 4"' if c.style == "dashed" else ""
        lines = "".join(
            f'<polyline points="{_poly(run, f)}" fill="none" stroke="{_esc(c.colour)}" '
            f'stroke-width="1.6"{dash} {_ns("curve")}/>'
            for run in runs
            if run.size > 1
        )
        out.append(f"<g {gid}>{title}{lines}</g>")
    return "".join(out)


def to_svg(
    scene: Scene,
    frame: int | None = None,
    *,
    labels: bool = True,
    uid: str | None = None,
    width: str = "100%",
    standalone: bool = False,
) -> str:
    """One frame of ``scene`` as an inline ``<svg>`` element (no script needed).

    Parameters
    ----------
    scene : Scene
    frame : int, optional
        The frame drawn; by default the first one that could be assembled.
    labels : bool
        Write the point names beside the points.
    uid : str, optional
        Prefix of the element ids (several drawings on one page need distinct ones).
    width : str
        CSS width of the element.
    standalone : bool
        Declare the SVG namespace (for an ``.svg`` file; inline SVG in HTML needs none).

    Examples
    --------
    >>> from machdyn import FourBar
    >>> from machdyn.draw import scene
    >>> svg = to_svg(scene(FourBar(8, 4, 7, 6), n=4), uid="fb")
    >>> svg.startswith("<svg"), 'id="fb-link2"' in svg
    (True, True)
    """
    uid = uid or f"md{next(_counter)}"
    if not re.fullmatch(r"[A-Za-z][\w-]*", uid):
        raise InputError("uid", f"must be letters, digits, '_' or '-', got {uid!r}")
    k = scene.first_shown() if frame is None else int(frame) % max(len(scene), 1)
    xmin, xmax, ymin, ymax = scene.extent()
    size = max(xmax - xmin, ymax - ymin)
    unit = scene.size / 100.0
    f = _Frame(scene, k, decimals(size), unit)
    static, moving = [], []
    shown = bool(scene.shown[k])
    for item in scene.items:
        (static if is_static(scene, item) else moving).append(_item_svg(item, f, uid))
    hatch = 1.2 * unit
    defs = (
        f'<defs><pattern id="{uid}-hatch" patternUnits="userSpaceOnUse" width="{f.n(hatch)}" '
        f'height="{f.n(hatch)}" patternTransform="rotate(45)"><line x1="0" y1="0" x2="0" '
        f'y2="{f.n(hatch)}" stroke="#000" stroke-width="{f.n(0.3 * unit)}"/></pattern></defs>'
    )
    view = " ".join(f.n(v) for v in (xmin, -ymax, xmax - xmin, ymax - ymin))
    return (
        f'<svg id="{uid}" class="machdyn-drawing"{_XMLNS if standalone else ""} '
        f'viewBox="{view}" width="{_esc(width)}" preserveAspectRatio="xMidYMid meet" role="img" '
        f'aria-label="{_esc(scene.title)}" data-frame="{k}" data-decimals="{f.places}" '
        f'data-unit="{f.n(1.6 * unit)}">'
        f"{defs}"
        f'<g class="world" transform="scale(1 -1)">'
        f"{_curves(scene, f, uid)}"
        f'<g class="static">{"".join(static)}</g>'
        f'<g class="moving"{"" if shown else _HIDDEN}>{"".join(moving)}</g>'
        f"</g>"
        f"{_labels(scene, f, uid) if labels else ''}"
        f"</svg>"
    )


def frame_data(scene: Scene) -> dict[str, Any]:
    """The JSON a widget embeds: rounded coordinates and angles per frame, and the bindings.

    Coordinates of a point that never moves are written once.

    Examples
    --------
    >>> from machdyn import FourBar
    >>> from machdyn.draw import scene
    >>> d = frame_data(scene(FourBar(8, 4, 7, 6), n=4))
    >>> d["x"][0], d["frames"]
    (0.0, 4)
    """
    xmin, xmax, ymin, ymax = scene.extent()
    places = decimals(max(xmax - xmin, ymax - ymin))
    xs, ys = [], []
    for j in range(len(scene.names)):
        col = scene.xy[:, j]
        fin = np.isfinite(col)
        if fin.all() and np.ptp(col.real) == 0 and np.ptp(col.imag) == 0:
            xs.append(round(float(col[0].real), places) + 0.0)
            ys.append(round(float(col[0].imag), places) + 0.0)
        else:
            xs.append(_rounded(col.real, places))
            ys.append(_rounded(col.imag, places))
    items = []
    for item in scene.items:
        if is_static(scene, item):
            continue
        entry: dict[str, Any] = {
            "k": item.kind,
            "id": item.gid,
            "p": [scene.index(p) for p in item.points],
        }
        if item.angle is not None:
            entry["a"] = item.angle
        items.append(entry)
    return {
        "frames": len(scene),
        "decimals": places,
        "x": xs,
        "y": ys,
        "angles": {k: _rounded(np.degrees(v), 4) for k, v in scene.angles.items()},
        "shown": [bool(v) for v in scene.shown],
        "reason": [str(r) for r in scene.reason],
        "items": items,
        "readout": [
            {
                "label": r.label,
                "unit": r.unit,
                "digits": r.digits,
                "v": _rounded(r.values, r.digits),
            }
            for r in scene.readout
        ],
        "closed": bool(scene.closed),
    }


def widget(scene: Scene, *, fps: float = 30.0, labels: bool = True, uid: str | None = None) -> str:
    """A drawing that plays its frames: inline SVG, controls, readout, data and script.

    Several widgets can share a page; the page needs :data:`SCRIPT` once
    (:func:`to_html` and the report add it).
    """
    fps = finite_scalar("fps", fps)
    if not 0.0 < fps <= 240.0:
        raise InputError("fps", f"must be in (0, 240] frames per second, got {fps:g}")
    uid = uid or f"md{next(_counter)}"
    data = frame_data(scene)
    # a handful of frames (precision positions) is stepped through slowly enough to read
    data["fps"] = float(fps) if len(scene) >= 12 else min(float(fps), 1.0)
    rows = "".join(
        f'<tr><td>{_esc(r.label)}</td><td class="v" data-row="{i}"></td>'
        f"<td>{_esc(r.unit)}</td></tr>"
        for i, r in enumerate(scene.readout)
    )
    many = len(scene) > 1
    controls = (
        f'<div class="controls"><button type="button" class="play">Pause</button>'
        f'<input type="range" class="frame" min="0" max="{len(scene) - 1}" value="0" step="1" '
        f'aria-label="frame"><span class="count"></span></div>'
        if many
        else ""
    )
    return (
        f'<div class="machdyn-scene" id="{uid}-widget">'
        f"{to_svg(scene, 0, labels=labels, uid=uid)}"
        f"{controls}"
        f'<div class="note" role="status"></div>'
        f'<table class="readout">{rows}</table>'
        f'<script type="application/json" class="{DATA_CLASS}">{script_json(data)}</script>'
        f"</div>"
    )


def to_html(
    scene: Scene,
    path: str | Path | None = None,
    *,
    fps: float = 30.0,
    labels: bool = True,
    title: str | None = None,
) -> str:
    """A self-contained HTML page that plays ``scene`` (and write it to ``path``).

    Examples
    --------
    >>> from machdyn import SliderCrank
    >>> from machdyn.draw import scene
    >>> page = to_html(scene(SliderCrank(2.0, 6.0), n=24))
    >>> page.startswith("<!DOCTYPE html>"), "http:" in page
    (True, False)
    """
    head = _esc(title if title is not None else scene.title)
    note = f'<p class="scene-note">{_esc(scene.note)}</p>' if scene.note else ""
    unit = f" (lengths in {_esc(scene.length_unit)})" if scene.length_unit else ""
    page = (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>machdyn: {head}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n"
        f'<h1>machdyn: {head}</h1>{note}<p class="units">Drawn from the solved motion{unit}; '
        "y up.</p>\n"
        f"{widget(scene, fps=fps, labels=labels)}\n<script>{SCRIPT}</script>\n</body>\n</html>\n"
    )
    if path is not None:
        Path(path).write_text(page, encoding="utf-8")
    return page


STYLE = """
body { font-family: system-ui, sans-serif; margin: 1em; color: #222; }
h1 { font-size: 1.15em; margin: 0 0 0.4em 0; }
.machdyn-scene { max-width: 900px; }
.machdyn-drawing { display: block; max-height: 65vh; border: 1px solid #ccc; background: #fff; }
.machdyn-drawing .labels { font-family: system-ui, sans-serif; fill: #222; }
.controls { display: flex; gap: 1em; align-items: center; margin: 0.5em 0; }
.controls .frame { flex: 1; }
.controls .count { font-variant-numeric: tabular-nums; min-width: 6em; color: #555; }
.note { color: #a00; min-height: 1.2em; }
.readout { border-collapse: collapse; font-variant-numeric: tabular-nums; }
.readout td { padding: 0.1em 0.8em; text-align: right; }
.readout td:first-child { text-align: left; color: #555; }
.units, .scene-note { color: #555; margin: 0.2em 0; }
.scene-note { color: #a00; font-weight: 600; }
"""

# The script only moves elements to the embedded coordinates; no kinematics here.
SCRIPT = r"""
"use strict";
(function () {
  function fmt(v, d) { return v === null || v === undefined ? "\u2013" : v.toFixed(d); }
  function setup(root) {
    const D = JSON.parse(root.querySelector("script.machdyn-frames").textContent);
    const svg = root.querySelector("svg");
    const uid = svg.id;
    const n = D.frames;
    const P = D.x.length;
    function X(j, i) { const c = D.x[j]; return Array.isArray(c) ? c[i] : c; }
    function Y(j, i) { const c = D.y[j]; return Array.isArray(c) ? c[i] : c; }
    function ok(j, i) { return X(j, i) !== null && Y(j, i) !== null; }
    const moving = svg.querySelector("g.moving");
    const els = D.items.map(function (it) { return document.getElementById(uid + "-" + it.id); });
    const labels = Array.from(svg.querySelectorAll("g.labels text[data-point]"));
    const cells = Array.from(root.querySelectorAll("table.readout td.v"));
    const note = root.querySelector(".note");
    const count = root.querySelector(".count");
    const slider = root.querySelector("input.frame");
    const button = root.querySelector("button.play");
    function tr(i, p, a, sx) {
      let s = "translate(" + X(p, i) + " " + Y(p, i) + ") rotate(" + (a || 0) + ")";
      if (sx !== undefined) s += " scale(" + sx + " 1)";
      return s;
    }
    function show(i) {
      moving.setAttribute("visibility", D.shown[i] ? "visible" : "hidden");
      D.items.forEach(function (it, m) {
        const el = els[m];
        if (!el) return;
        const p = it.p;
        const good = p.every(function (j) { return ok(j, i); });
        el.setAttribute("visibility", good ? "visible" : "hidden");
        if (!good && it.k !== "pin" && it.k !== "point") return;
        const ang = it.a ? D.angles[it.a][i] : 0;
        if (it.k === "bar" || it.k === "line") {
          el.setAttribute("x1", X(p[0], i)); el.setAttribute("y1", Y(p[0], i));
          el.setAttribute("x2", X(p[1], i)); el.setAttribute("y2", Y(p[1], i));
        } else if (it.k === "plate") {
          const pts = p.map(function (j) { return X(j, i) + "," + Y(j, i); });
          el.setAttribute("points", pts.join(" "));
        } else if (it.k === "pin" || it.k === "point") {
          el.setAttribute("visibility", "visible");
          Array.from(el.querySelectorAll("circle")).forEach(function (c, q) {
            const j = p[q];
            if (ok(j, i)) {
              c.setAttribute("cx", X(j, i)); c.setAttribute("cy", Y(j, i));
              c.setAttribute("visibility", "visible");
            } else { c.setAttribute("visibility", "hidden"); }
          });
        } else if (it.k === "slider" || it.k === "shape" || it.k === "wheel" ||
                   it.k === "ground" || it.k === "motor") {
          el.setAttribute("transform", tr(i, p[0], ang));
        } else {  // guide, spring, damper, actuator: from p[0] towards p[1]
          const dx = X(p[1], i) - X(p[0], i), dy = Y(p[1], i) - Y(p[0], i);
          const len = Math.hypot(dx, dy);
          const deg = Math.atan2(dy, dx) * 180 / Math.PI;
          if (it.k === "spring" || it.k === "damper") {
            el.setAttribute("transform", tr(i, p[0], deg, len || 1));
          } else {
            el.setAttribute("transform", tr(i, p[0], deg));
            const rod = el.querySelector("line.rod");
            if (rod) rod.setAttribute("x2", len);
          }
        }
      });
      labels.forEach(function (t) {
        const j = Number(t.getAttribute("data-point"));
        if (ok(j, i)) {
          const u = Number(svg.getAttribute("data-unit") || 0);
          const k = (t.getAttribute("data-off") || "1 -1").split(" ").map(Number);
          t.setAttribute("x", X(j, i) + k[0] * u); t.setAttribute("y", -Y(j, i) + k[1] * u);
          t.setAttribute("visibility", "visible");
        } else { t.setAttribute("visibility", "hidden"); }
      });
      D.readout.forEach(function (r, m) {
        if (cells[m]) cells[m].textContent = fmt(r.v[i], r.digits);
      });
      note.textContent = D.reason[i];
      if (count) count.textContent = "frame " + (i + 1) + " / " + n;
      if (slider) slider.value = String(i);
      svg.setAttribute("data-frame", String(i));
    }
    let frame = 0, playing = n > 1, last = null;
    function tick(t) {
      if (playing) {
        if (last === null) last = t;
        const steps = Math.floor((t - last) * D.fps / 1000);
        if (steps > 0) { frame = (frame + steps) % n; last += steps * 1000 / D.fps; show(frame); }
      }
      window.requestAnimationFrame(tick);
    }
    if (button) button.addEventListener("click", function () {
      playing = !playing; last = null; button.textContent = playing ? "Pause" : "Play";
    });
    if (slider) slider.addEventListener("input", function () {
      frame = Number(slider.value); playing = false;
      if (button) button.textContent = "Play";
      show(frame);
    });
    root.machdynShow = function (i) {
      playing = false;
      if (button) button.textContent = "Play";
      show(i);
    };
    show(0);
    if (n > 1) window.requestAnimationFrame(tick);
  }
  document.querySelectorAll(".machdyn-scene").forEach(setup);
})();
"""
