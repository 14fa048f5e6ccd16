"""Files the studio's *Export* menu writes, each from the library's own output.

* ``toml``, ``json`` — the document (``machdyn.spec.dumps``, JSON);
* ``csv``, ``results`` — every column of ``Machine.run`` over the studio's
  samples, labelled with units (``machdyn.cli.run.write_csv`` / ``payload``:
  the files ``machdyn run --csv/--json`` writes);
* ``svg``, ``png``, ``gif`` — the scene of ``machdyn.draw`` (inline-SVG
  back end, matplotlib still and animation);
* ``dxf`` — each link's outline at the drawn pose (the hull of circles about
  its joints, one layer per link, pin holes), for cutting or CAD;
* ``report`` — the design report of ``machdyn.report``.
"""

from __future__ import annotations

import io
import math
import re
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["FORMATS", "FileAnswer", "export"]

#: Export formats: name → (file ending, MIME type, what).
FORMATS: dict[str, tuple[str, str, str]] = {
    "toml": (".toml", "application/toml", "the machine file"),
    "json": (".json", "application/json", "the machine file as JSON"),
    "csv": (".csv", "text/csv", "every column over the range, units in the header"),
    "results": (".json", "application/json", "the results as machdyn run --json"),
    "svg": (".svg", "image/svg+xml", "the drawing"),
    "png": (".png", "image/png", "the drawing (matplotlib)"),
    "gif": (".gif", "image/gif", "the animation (matplotlib)"),
    "dxf": (".dxf", "application/dxf", "link outlines for CAD (ezdxf)"),
    "report": (".html", "text/html", "the design report"),
}

#: DXF $INSUNITS codes of the length units a machine file may declare.
_DXF_UNITS = {"in": 1, "inch": 1, "ft": 2, "foot": 2, "mm": 4, "cm": 5, "m": 6, "km": 7}


class FileAnswer:
    """A file to download: bytes, its MIME type and a suggested (safe) name."""

    def __init__(self, data: bytes, mime: str, filename: str) -> None:
        self.data = data
        self.mime = mime
        self.filename = "".join(c for c in filename if c.isalnum() or c in "._-") or "machdyn"


def _stem(doc: Mapping[str, Any], part: Any) -> str:
    title = str(doc.get("title") or part.name)
    return re.sub(r"[^A-Za-z0-9._-]+", "_", title).strip("_") or "machdyn"


def _solved(doc: Mapping[str, Any], part_name: str | None) -> tuple[Any, Any, Any, Any]:
    """The machine, part, run result and scene of the studio's samples."""
    from ..draw.linkage import linkage_scene
    from ..spec import read
    from .analysis import SAMPLES, _grid, _run_document, linkage_part

    machine = read(doc)
    part = linkage_part(machine, part_name)
    lk = part.model
    x, _, _ = _grid(lk, lk.drivers[0], SAMPLES)
    result = _run_document(part, machine, x)
    m = result.objects["motion"]
    scene = linkage_scene(lk, m, title=str(doc.get("title") or part.name))
    return machine, part, result, scene


def _columns(machine: Any, result: Any) -> dict[str, Any]:
    cols: dict[str, Any] = {}
    for table in result.tables:
        for label, values in table.labelled(machine.units).items():
            if label not in cols:
                cols[label] = values
    for key in ("ok", "reason"):  # last, once
        if key in cols:
            cols[key] = cols.pop(key)
    return cols


def _mpl() -> Any:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise InputError(
            "format", "pictures need matplotlib: pip install 'machdyn[plot]'"
        ) from None
    return plt


def _dxf(scene: Any, lk: Any, frame: int, unit: str | None) -> bytes:
    try:
        import ezdxf
    except ImportError:
        raise InputError("format", "DXF needs ezdxf: pip install 'machdyn[dxf]'") from None
    doc = ezdxf.new("R2010")
    if unit in _DXF_UNITS:
        doc.header["$INSUNITS"] = _DXF_UNITS[unit]
    msp = doc.modelspace()
    xy = {name: scene.xy[frame, i] for i, name in enumerate(scene.names)}
    r = 0.04 * scene.size
    hole = 0.4 * r
    for name, link in lk.links.items():
        layer = "link_" + re.sub(r"[^A-Za-z0-9_-]", "_", name)
        doc.layers.add(layer)
        pts = [xy[p] for p in link.points if np.isfinite(xy[p])]
        for z in pts:
            msp.add_circle((z.real, z.imag), hole, dxfattribs={"layer": layer})
        if len(pts) == 1:
            msp.add_circle((pts[0].real, pts[0].imag), r, dxfattribs={"layer": layer})
            continue
        msp.add_lwpolyline(
            _hull_outline(pts, r), format="xyb", close=True, dxfattribs={"layer": layer}
        )
    for name in lk.ground_points:
        z = xy[name]
        doc.layers.add("ground") if "ground" not in doc.layers else None
        msp.add_circle((z.real, z.imag), hole, dxfattribs={"layer": "ground"})
    out = io.StringIO()
    doc.write(out)
    return out.getvalue().encode("utf-8")


def _hull_outline(points: list[complex], r: float) -> list[tuple[float, float, float]]:
    """The outline of the convex hull of circles of radius ``r`` about ``points``.

    Vertices ``(x, y, bulge)`` of a closed polyline: the hull's edges offset by
    ``r``, joined by arcs about each hull point (bulge ``tan(turn / 4)``).
    """
    pts = sorted({(round(z.real, 12), round(z.imag, 12)) for z in points})

    def cross(o: tuple, a: tuple, b: tuple) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list[tuple] = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[tuple] = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    hull = [complex(*p) for p in lower[:-1] + upper[:-1]]  # counter-clockwise
    n = len(hull)
    out: list[tuple[float, float, float]] = []
    for i in range(n):
        prev, here, nxt = hull[i - 1], hull[i], hull[(i + 1) % n]
        d_in, d_out = here - prev, nxt - here
        n_in = -1j * d_in / abs(d_in)  # outward normal of a CCW edge
        n_out = -1j * d_out / abs(d_out)
        turn = math.atan2((n_out / n_in).imag, (n_out / n_in).real) % (2 * math.pi)
        a, b = here + r * n_in, here + r * n_out
        out.append((a.real, a.imag, math.tan(turn / 4.0)))
        out.append((b.real, b.imag, 0.0))
    return out


def export(
    doc: Mapping[str, Any], fmt: str, *, part: str | None = None, frame: int | None = None
) -> FileAnswer:
    """The file of format ``fmt`` (a key of :data:`FORMATS`) for the document."""
    if fmt not in FORMATS:
        raise InputError("format", f"must be one of {', '.join(FORMATS)}, got {fmt!r}")
    end, mime, _ = FORMATS[fmt]
    if fmt in ("toml", "json"):
        from ..spec import dumps, read

        read(doc)  # only a document that reads back is written
        import json

        text = dumps(dict(doc)) if fmt == "toml" else json.dumps(doc, indent=2)
        title = re.sub(r"[^A-Za-z0-9._-]+", "_", str(doc.get("title") or "machine")).strip("_")
        return FileAnswer(text.encode("utf-8"), mime, (title or "machine") + end)
    machine, p, result, scene = _solved(doc, part)
    stem = _stem(doc, p)
    k = scene.first_shown() if frame is None else int(frame) % len(scene)
    if fmt == "csv":
        from ..cli.run import write_csv

        out = io.StringIO()
        write_csv(_columns(machine, result), out)
        return FileAnswer(out.getvalue().encode("utf-8"), mime, stem + end)
    if fmt == "results":
        import json

        from ..cli.run import payload

        data = json.dumps(payload(machine, {p.name: result}), indent=1, allow_nan=False)
        return FileAnswer(data.encode("utf-8"), mime, stem + "-results" + end)
    if fmt == "svg":
        from ..draw.html import to_svg

        svg = to_svg(scene, k, standalone=True, uid="machdyn")
        return FileAnswer(svg.encode("utf-8"), mime, stem + end)
    if fmt == "png":
        from ..draw.mpl import draw_scene

        plt = _mpl()
        ax = draw_scene(scene, k)
        buf = io.BytesIO()
        ax.figure.savefig(buf, format="png", dpi=120, bbox_inches="tight")
        plt.close(ax.figure)
        return FileAnswer(buf.getvalue(), mime, stem + end)
    if fmt == "gif":
        from ..draw.mpl import animate_scene

        plt = _mpl()
        step = max(1, len(scene) // 90)
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "a.gif"
            animate_scene(scene.frames(np.arange(0, len(scene), step)), path, fps=20)
            plt.close("all")
            return FileAnswer(path.read_bytes(), mime, stem + end)
    if fmt == "dxf":
        return FileAnswer(_dxf(scene, p.model, k, machine.units.length), mime, stem + end)
    from ..report import report
    from ..report.machine import part_options

    # as `machdyn report` of the file: speed, gravity, loads and units (its own sweep)
    options = part_options(p, machine)
    options.pop("values", None)
    page = report(p.model, None, **options)
    return FileAnswer(page.encode("utf-8"), mime, stem + "-report" + end)
