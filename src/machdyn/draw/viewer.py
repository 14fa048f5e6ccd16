"""The browser viewer's calls: :func:`to_html` of any model, :func:`page_data` of a four-bar.

:func:`to_html` draws through the one scene path (:mod:`machdyn.draw.html`): the
poses are solved in Python and embedded as JSON; the page's script only moves
the drawing to them, and nothing is loaded from the network.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import choice, finite_scalar, integer
from ..errors import InputError
from ..fourbar import FourBar
from .build import fourbar_scene, scene
from .fourbar import sweep

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


def to_html(
    model: Any,
    form: int = 1,
    n: int = 360,
    path: str | Path | None = None,
    *,
    omega2: float = 1.0,
    fps: float = 30.0,
    **options: Any,
) -> str:
    """A self-contained HTML page animating ``model`` (and write it to ``path``).

    Parameters
    ----------
    model : FourBar, SliderCrank, InvertedSliderCrank, Linkage, cam, gear pair, ...
        Anything :func:`machdyn.draw.scene` draws.
    form : {1, 2}
    n : int
        Samples per stroke (see :func:`machdyn.plot.sweep`): a crank's turn in
        ``n`` frames, a rocker's there-and-back in ``2n − 2``.
    path : str or Path, optional
        Also write the page there (UTF-8).
    omega2 : float
        Input speed (rad/s) for the rate readouts.
    fps : float
        Playback rate, frames per second.

    Returns
    -------
    str
        The page: an inline SVG of the mechanism (and its coupler curve), a
        play/pause button, a frame slider, and a readout of the solved angles
        (deg) and rates (rad/s).

    Examples
    --------
    >>> page = to_html(FourBar(8, 4, 7, 6, coupler=(5, 0.5)), n=36)
    >>> page.startswith("<!DOCTYPE html>"), "http" in page
    (True, False)
    """
    from .html import to_html as page_of

    n = integer("n", n, minimum=2)
    if n > 20_000:
        raise InputError("n", f"at most 20000 samples per stroke are embedded, got {n}")
    omega2 = finite_scalar("omega2", omega2, "radian / second")
    if isinstance(model, FourBar):
        choice("form", form, (1, 2))
        s = sweep(model, form, n, omega2=omega2)
        curve = None
        if model.coupler is not None:
            curve = model.coupler_curve(form, n).points
            if model.input_range(form).full_turn or model.form_rule == "phi34":
                curve = np.append(curve, curve[:1])
        closed = bool(model.input_range(form).full_turn or model.form_rule == "phi34")
        drawn = fourbar_scene(model, s, coupler_curve=curve, closed=closed)
    else:
        drawn = scene(model, n=n, form=form, omega2=omega2, **options)
    return page_of(drawn, path, fps=fps)
