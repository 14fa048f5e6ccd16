r"""A self-contained HTML page that plays a four-bar's motion in the browser.

The poses are solved in Python by :meth:`FourBar.solve` (in the order of
:func:`machdyn.plot.sweep`) and embedded in the page as JSON; the page's
script only draws them (an inline SVG), with a play/pause button, a θ2 slider,
the coupler curve and a live readout. No kinematics runs in JavaScript, and the
page loads nothing from the network: no external script, style sheet, font or
image.

Everything embedded is escaped: the JSON is made safe for a ``<script>``
element (``<``, ``>``, ``&`` and the line separators are written as ``\u``
escapes), non-finite numbers become ``null``, and text is HTML-escaped.
"""

from __future__ import annotations

import html
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from ._validate import choice, finite_scalar, integer
from .errors import InputError
from .fourbar import FourBar
from .plot import sweep

__all__ = ["page_data", "to_html"]

#: Id of the ``<script type="application/json">`` element holding the poses.
DATA_ID = "machdyn-data"


def _numbers(values: Any, digits: int = 12) -> list[float | None]:
    """A JSON-ready list of floats, ``None`` where a value is not finite."""
    out: list[float | None] = []
    for v in np.ravel(np.asarray(values, dtype=float)).tolist():
        out.append(float(f"{v:.{digits}g}") if math.isfinite(v) else None)
    return out


def page_data(fourbar: FourBar, form: int = 1, n: int = 360, omega2: float = 1.0) -> dict:
    """The data a viewer page embeds: poses, coupler curve, drawing extent, labels.

    Angles are in degrees (keys end in ``_deg``), rates in rad/s for the input
    speed ``omega2`` (its sign reverses on a rocker's return stroke), lengths
    in the linkage's unit. Samples that are not solved hold ``null``.

    Examples
    --------
    >>> d = page_data(FourBar(8, 4, 7, 6), n=4)
    >>> d["frames"]["theta2_deg"]
    [0.0, 90.0, 180.0, 270.0]
    >>> d["curve"] is None
    True
    """
    if not isinstance(fourbar, FourBar):
        raise InputError("fourbar", f"expected a FourBar, got {type(fourbar).__name__}")
    choice("form", form, (1, 2))
    n = integer("n", n, minimum=2)
    if n > 20_000:
        raise InputError("n", f"at most 20000 samples per stroke are embedded, got {n}")
    omega2 = finite_scalar("omega2", omega2, "radian / second")
    s = sweep(fourbar, form, n, omega2=omega2)
    shown = s.assembled
    frames: dict[str, Any] = {
        "theta2_deg": _numbers(np.degrees(s.theta2)),
        "theta3_deg": _numbers(np.where(shown, np.degrees(s.theta3), np.nan)),
        "theta4_deg": _numbers(np.where(shown, np.degrees(s.theta4), np.nan)),
        "omega2": _numbers(s.omega2),
        "omega3": _numbers(np.where(s.ok, s.omega3, np.nan)),
        "omega4": _numbers(np.where(s.ok, s.omega4, np.nan)),
        "mu_deg": _numbers(np.where(shown, np.degrees(s.mu), np.nan)),
        "Ax": _numbers(np.where(shown, s.A.real, np.nan)),
        "Ay": _numbers(np.where(shown, s.A.imag, np.nan)),
        "Bx": _numbers(np.where(shown, s.B.real, np.nan)),
        "By": _numbers(np.where(shown, s.B.imag, np.nan)),
        "assembled": [bool(v) for v in shown],
        "reason": [str(r) for r in s.reason],
    }
    points = [0j, complex(fourbar.r1), *s.A[shown], *s.B[shown]]
    curve = None
    if fourbar.coupler is not None:
        frames["Px"] = _numbers(np.where(shown, s.coupler.real, np.nan))
        frames["Py"] = _numbers(np.where(shown, s.coupler.imag, np.nan))
        c = fourbar.coupler_curve(form, n).points
        curve = {"x": _numbers(c.real), "y": _numbers(c.imag)}
        points += [*c]
    pts = np.asarray(points)
    span = float(max(np.ptp(pts.real), np.ptp(pts.imag), 1e-12))
    pad = 0.12 * span
    rng = fourbar.input_range(form)
    return {
        "title": f"{fourbar!r}, form {form}",
        "barker_class": fourbar.barker_class,
        "form": form,
        "lengths": {"r1": fourbar.r1, "r2": fourbar.r2, "r3": fourbar.r3, "r4": fourbar.r4},
        "length_unit": fourbar.length_unit or "",
        "input": "crank" if rng.full_turn else "rocker",
        "closed": bool(rng.full_turn or fourbar.form_rule == "phi34"),
        "extent": {
            "xmin": float(pts.real.min() - pad),
            "xmax": float(pts.real.max() + pad),
            "ymin": float(pts.imag.min() - pad),
            "ymax": float(pts.imag.max() + pad),
            "size": span,
        },
        "frames": frames,
        "curve": curve,
    }


def _script_json(data: dict) -> str:
    """JSON that cannot end or break out of the ``<script>`` element it sits in."""
    text = json.dumps(data, allow_nan=False, separators=(",", ":"))
    for char, escape in (
        ("&", "\\u0026"),
        ("<", "\\u003c"),
        (">", "\\u003e"),
        ("\u2028", "\\u2028"),
        ("\u2029", "\\u2029"),
    ):
        text = text.replace(char, escape)
    return text


def to_html(
    fourbar: FourBar,
    form: int = 1,
    n: int = 360,
    path: str | Path | None = None,
    *,
    omega2: float = 1.0,
    fps: float = 30.0,
) -> str:
    """A self-contained HTML page animating ``fourbar`` (and write it to ``path``).

    Parameters
    ----------
    fourbar : FourBar
    form : {1, 2}
    n : int
        Samples per stroke (see :func:`machdyn.plot.sweep`): a crank's turn in
        ``n`` frames, a rocker's there-and-back in ``2n − 2``.
    path : str or Path, optional
        Also write the page there (UTF-8).
    omega2 : float
        Input speed (rad/s) for the ω3, ω4 readouts.
    fps : float
        Playback rate, frames per second.

    Returns
    -------
    str
        The page: an inline SVG of the linkage and its coupler curve, a
        play/pause button, a θ2 slider, and a readout of θ2, θ3, θ4, μ (deg)
        and ω3, ω4 (rad/s).

    Examples
    --------
    >>> page = to_html(FourBar(8, 4, 7, 6, coupler=(5, 0.5)), n=36)
    >>> page.startswith("<!DOCTYPE html>"), "http" in page
    (True, False)
    """
    data = page_data(fourbar, form, n, omega2)
    fps = finite_scalar("fps", fps)
    if not 0.0 < fps <= 240.0:
        raise InputError("fps", f"must be in (0, 240] frames per second, got {fps:g}")
    page = (
        _TEMPLATE.replace("%%TITLE%%", html.escape(data["title"]))
        .replace("%%FPS%%", repr(float(fps)))
        .replace("%%DATA_ID%%", DATA_ID)
        .replace("%%DATA%%", _script_json(data))
    )
    if path is not None:
        Path(path).write_text(page, encoding="utf-8")
    return page


# The page. The script reads the embedded JSON and only draws; it computes no kinematics.
# SVG elements are created with the namespace of the inline <svg> element itself.
_TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>machdyn: %%TITLE%%</title>
<style>
  body { font-family: system-ui, sans-serif; margin: 1em; color: #222; }
  h1 { font-size: 1.1em; margin: 0 0 0.5em 0; }
  #stage { width: 100%; max-width: 900px; height: 60vh; border: 1px solid #ccc;
           background: #fff; display: block; }
  .controls { display: flex; gap: 1em; align-items: center; margin: 0.6em 0;
              max-width: 900px; }
  #slider { flex: 1; }
  #readout { border-collapse: collapse; font-variant-numeric: tabular-nums; }
  #readout td { padding: 0.1em 0.8em; text-align: right; }
  #readout td:first-child { text-align: left; color: #555; }
  #note { color: #a00; min-height: 1.2em; }
  .link { stroke-linecap: round; fill: none; }
</style>
</head>
<body>
<h1>machdyn: %%TITLE%%</h1>
<svg id="stage" preserveAspectRatio="xMidYMid meet" role="img"
     aria-label="four-bar linkage"></svg>
<div class="controls">
  <button id="play" type="button">Pause</button>
  <input id="slider" type="range" min="0" value="0" step="1" aria-label="frame">
</div>
<table id="readout">
  <tr><td>&theta;2</td><td id="r-theta2"></td><td>deg</td></tr>
  <tr><td>&theta;3</td><td id="r-theta3"></td><td>deg</td></tr>
  <tr><td>&theta;4</td><td id="r-theta4"></td><td>deg</td></tr>
  <tr><td>&omega;3</td><td id="r-omega3"></td><td>rad/s</td></tr>
  <tr><td>&omega;4</td><td id="r-omega4"></td><td>rad/s</td></tr>
  <tr><td>&mu;</td><td id="r-mu"></td><td>deg</td></tr>
</table>
<div id="note"></div>
<p id="about"></p>
<script type="application/json" id="%%DATA_ID%%">%%DATA%%</script>
<script>
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("%%DATA_ID%%").textContent);
  const F = data.frames;
  const count = F.theta2_deg.length;
  const fps = %%FPS%%;
  const svg = document.getElementById("stage");
  const NS = svg.namespaceURI;
  const E = data.extent;
  const unit = E.size / 100;
  // y points up: draw in a group flipped about the x axis
  svg.setAttribute("viewBox", [E.xmin, -E.ymax, E.xmax - E.xmin, E.ymax - E.ymin].join(" "));
  const world = make("g", { transform: "scale(1,-1)" }, svg);

  function make(tag, attrs, parent) {
    const el = document.createElementNS(NS, tag);
    for (const k in attrs) el.setAttribute(k, attrs[k]);
    parent.appendChild(el);
    return el;
  }
  function pointsAttr(xs, ys) {
    const out = [];
    for (let i = 0; i < xs.length; i++) {
      if (xs[i] !== null && ys[i] !== null) out.push(xs[i] + "," + ys[i]);
    }
    return out.join(" ");
  }

  // hatch pattern for the ground
  const defs = make("defs", {}, svg);
  const pat = make("pattern", { id: "hatch", patternUnits: "userSpaceOnUse",
    width: 1.2 * unit, height: 1.2 * unit, patternTransform: "rotate(45)" }, defs);
  make("line", { x1: 0, y1: 0, x2: 0, y2: 1.2 * unit, stroke: "#000",
    "stroke-width": 0.35 * unit }, pat);

  function ground(x) {
    const s = 4.5 * unit;
    make("rect", { x: x - 0.9 * s, y: -1.35 * s, width: 1.8 * s, height: 0.35 * s,
      fill: "url(#hatch)" }, world);
    make("polygon", { points: [x, 0, x - 0.6 * s, -s, x + 0.6 * s, -s].join(" "),
      fill: "#e6e6e6", stroke: "#000", "stroke-width": 0.25 * unit }, world);
  }
  ground(0);
  ground(data.lengths.r1);
  make("line", { x1: 0, y1: 0, x2: data.lengths.r1, y2: 0, stroke: "#888",
    "stroke-width": 0.3 * unit, "stroke-dasharray": unit + " " + unit }, world);

  if (data.curve) {
    make(data.closed ? "polygon" : "polyline", {
      points: pointsAttr(data.curve.x, data.curve.y), fill: "none", stroke: "#d62728",
      "stroke-width": 0.45 * unit, id: "coupler-curve" }, world);
  }
  const moving = make("g", { id: "moving" }, world);
  const tri = data.curve ? make("polygon", { fill: "#ff7f0e", "fill-opacity": 0.25,
    stroke: "#ff7f0e", "stroke-width": 0.3 * unit }, moving) : null;
  const width = 1.6 * unit;
  const link2 = make("line", { class: "link", stroke: "#1f77b4", "stroke-width": width }, moving);
  const link3 = make("line", { class: "link", stroke: "#ff7f0e", "stroke-width": width }, moving);
  const link4 = make("line", { class: "link", stroke: "#2ca02c", "stroke-width": width }, moving);
  const pins = [];
  for (let i = 0; i < 4; i++) {
    pins.push(make("circle", { r: 1.1 * unit, fill: "#fff", stroke: "#000",
      "stroke-width": 0.35 * unit }, world));
  }
  pins[0].setAttribute("cx", 0); pins[0].setAttribute("cy", 0);
  pins[3].setAttribute("cx", data.lengths.r1); pins[3].setAttribute("cy", 0);
  const point = data.curve ? make("circle", { r: 1.0 * unit, fill: "#d62728" }, moving) : null;

  const slider = document.getElementById("slider");
  const button = document.getElementById("play");
  const note = document.getElementById("note");
  slider.max = String(count - 1);
  document.getElementById("about").textContent =
    "Barker class " + data.barker_class + ", input link is a " + data.input + ". " +
    "Poses computed by machdyn; rates for omega2 = " + Math.abs(F.omega2[0]) + " rad/s" +
    (data.input === "rocker" ? " (reversed on the return stroke)." : ".");

  function fmt(v, digits) { return v === null ? "\\u2013" : v.toFixed(digits); }
  function setLine(el, x1, y1, x2, y2) {
    el.setAttribute("x1", x1); el.setAttribute("y1", y1);
    el.setAttribute("x2", x2); el.setAttribute("y2", y2);
  }
  function show(i) {
    const ok = F.assembled[i];
    moving.setAttribute("visibility", ok ? "visible" : "hidden");
    pins[1].setAttribute("visibility", ok ? "visible" : "hidden");
    pins[2].setAttribute("visibility", ok ? "visible" : "hidden");
    if (ok) {
      const ax = F.Ax[i], ay = F.Ay[i], bx = F.Bx[i], by = F.By[i];
      setLine(link2, 0, 0, ax, ay);
      setLine(link3, ax, ay, bx, by);
      setLine(link4, data.lengths.r1, 0, bx, by);
      pins[1].setAttribute("cx", ax); pins[1].setAttribute("cy", ay);
      pins[2].setAttribute("cx", bx); pins[2].setAttribute("cy", by);
      if (tri) {
        tri.setAttribute("points", [ax, ay, bx, by, F.Px[i], F.Py[i]].join(" "));
        point.setAttribute("cx", F.Px[i]); point.setAttribute("cy", F.Py[i]);
      }
    }
    document.getElementById("r-theta2").textContent = fmt(F.theta2_deg[i], 2);
    document.getElementById("r-theta3").textContent = fmt(F.theta3_deg[i], 2);
    document.getElementById("r-theta4").textContent = fmt(F.theta4_deg[i], 2);
    document.getElementById("r-omega3").textContent = fmt(F.omega3[i], 4);
    document.getElementById("r-omega4").textContent = fmt(F.omega4[i], 4);
    document.getElementById("r-mu").textContent = fmt(F.mu_deg[i], 2);
    note.textContent = F.reason[i];
    slider.value = String(i);
  }

  let frame = 0, playing = true, last = null;
  function tick(t) {
    if (playing) {
      if (last === null) last = t;
      const steps = Math.floor((t - last) * fps / 1000);
      if (steps > 0) {
        frame = (frame + steps) % count;
        last += steps * 1000 / fps;
        show(frame);
      }
    }
    window.requestAnimationFrame(tick);
  }
  button.addEventListener("click", function () {
    playing = !playing;
    last = null;
    button.textContent = playing ? "Pause" : "Play";
  });
  slider.addEventListener("input", function () {
    frame = Number(slider.value);
    playing = false;
    button.textContent = "Play";
    show(frame);
  });
  show(0);
  window.requestAnimationFrame(tick);
})();
</script>
</body>
</html>
"""
