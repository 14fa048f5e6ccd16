"""Kinematic curves: angles, rates and slider motion against the input, axes with units.

Each plot is a list of :class:`~machdyn.draw.chart.Chart` descriptions
(:func:`kinematics_charts`, :func:`slider_charts`) drawn by matplotlib
(:func:`plot_kinematics`, :func:`plot_slider_motion`, through
:func:`machdyn.draw.chart.figure`) or written as inline SVG by the report. Every
axis names its quantity and unit — the model's units where it has them
(``motion.units``, :class:`~machdyn.draw.units.Units`): lengths, speeds and
rates converted to the file's output units. Flagged samples are gaps (masked),
never zeros or lines drawn across them, and an angle's wrap from 360° to 0° is
not joined by a vertical line.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ..fourbar import FourBarMotion
from ..slidercrank import InvertedSliderCrankMotion, SliderCrankMotion
from .chart import Chart, Series, figure
from .units import Units

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = [
    "kinematics_charts",
    "length_label",
    "plot_kinematics",
    "plot_slider_motion",
    "slider_charts",
]


def length_label(unit: str | None) -> str:
    """The unit written on a length axis: the model's, or 'model units' when it has none.

    Examples
    --------
    >>> length_label("mm"), length_label(None)
    ('mm', 'model units')
    """
    return unit if unit else "model units"


def _masked(values: np.ndarray, valid: np.ndarray) -> np.ma.MaskedArray:
    """Values hidden where a sample is flagged (drawn as a gap, never joined across)."""
    values = np.ravel(values)
    return np.ma.masked_array(values, mask=~np.ravel(valid) | ~np.isfinite(values))


def _break_wraps(x: np.ndarray, y: np.ma.MaskedArray) -> tuple[np.ndarray, np.ma.MaskedArray]:
    """Insert a masked point where an angle in [0, 360) wraps, so no vertical line is drawn."""
    filled = y.filled(np.nan)
    jumps = np.flatnonzero(np.abs(np.diff(filled)) > 180.0) + 1
    if jumps.size == 0:
        return x, y
    x = np.insert(np.asarray(x, dtype=float), jumps, np.nan)
    data = np.insert(filled, jumps, np.nan)
    mask = np.insert(np.ma.getmaskarray(y), jumps, True)
    return x, np.ma.masked_array(data, mask=mask)


def _curve(
    x: np.ndarray, values: Any, valid: Any, kind: str, units: Units, label: str, gid: str
) -> Series:
    """One curve in shown units: gaps where not ``valid``; an angle's wraps broken."""
    y = _masked(units.show(kind, np.asarray(values, dtype=float)), valid)
    xs, ys = _break_wraps(x, y) if kind == "angle" else (x, y)
    return Series(np.asarray(xs, float), ys.filled(np.nan), label, gid=gid)


def _zero(chart: Chart) -> Chart:
    chart.hlines.append((0.0, "", "#999999"))
    return chart


def kinematics_charts(
    motion: FourBarMotion, *, jerk: bool = False, mu: bool = False, units: Any = None
) -> list[Chart]:
    """Charts of a four-bar's θ3, θ4, ω3, ω4, α3, α4 (and jerks) against θ2.

    The descriptions behind :func:`plot_kinematics` (which draws them with
    matplotlib) and the report's kinematics section (inline SVG). Angles in
    degrees (the unit system's angle unit), rates in its angular-velocity and
    angular-acceleration units (rad/s, rad/s² without one). Flagged samples
    are gaps; an angle's wrap from 360° to 0° is a gap too.

    Parameters
    ----------
    motion : FourBarMotion
    jerk : bool
        Add the angular jerks.
    mu : bool
        Also draw the transmission angle on the angle chart.
    units : Units or UnitSystem, optional
        Default: the motion's own (``motion.units``).

    Examples
    --------
    >>> from machdyn import FourBar
    >>> m = FourBar(8, 4, 7, 6).solve(np.radians(np.arange(0, 360, 5.0)), omega2=10.0)
    >>> [c.ylabel for c in kinematics_charts(m)]
    ['angle (deg)', 'ω (rad/s)', 'α (rad/s²)']
    """
    if not isinstance(motion, FourBarMotion):
        raise InputError(
            "motion", f"expected a FourBarMotion from FourBar.solve, got {type(motion).__name__}"
        )
    u = _units(motion, units)
    x = np.ravel(u.show("angle", np.ravel(motion.theta2).astype(float)))
    xlabel = u.axis("θ2", "angle")
    panels = [
        (
            "link angles",
            "angle",
            "angle",
            [("theta3", "θ3"), ("theta4", "θ4")] + ([("mu", "μ")] if mu else []),
        ),
        ("angular velocities", "ω", "angular_velocity", [("omega3", "ω3"), ("omega4", "ω4")]),
        (
            "angular accelerations",
            "α",
            "angular_acceleration",
            [("alpha3", "α3"), ("alpha4", "α4")],
        ),
    ]
    if jerk:
        panels.append(
            ("angular jerks", "jerk", "angular_jerk", [("jerk3", "jerk3"), ("jerk4", "jerk4")])
        )
    charts = []
    for title, quantity, kind, names in panels:
        valid = motion.assembled if kind == "angle" else motion.ok
        series = [
            _curve(x, getattr(motion, name), valid, kind, u, label, name)
            for name, label in names
            if getattr(motion, name, None) is not None
        ]
        if series:
            charts.append(_zero(Chart(title, xlabel, u.axis(quantity, kind), series)))
    return charts


def plot_kinematics(
    motion: FourBarMotion, *, jerk: bool = False, mu: bool = False, fig: Figure | None = None
) -> Figure:
    """θ3, θ4, ω3, ω4, α3, α4 (and optionally the jerks) of a four-bar against θ2.

    The charts of :func:`kinematics_charts`, drawn with matplotlib. Angles are
    drawn in degrees, rates in the motion's units (rad/s, rad/s², rad/s³ —
    the time unit of the ``omega2`` given — for a model without units).
    Flagged samples (``motion.ok`` False; positions also at toggles, where only
    the rates are undefined) are left as gaps, and an angle's wrap from 360°
    to 0° is not joined.

    Parameters
    ----------
    motion : FourBarMotion
        From :meth:`FourBar.solve`, ideally over a sorted grid of θ2.
    jerk : bool
        Add a panel with the angular jerks.
    mu : bool
        Also draw the transmission angle μ on the angle panel.
    fig : matplotlib Figure, optional
        An empty figure to draw in.

    Returns
    -------
    matplotlib.figure.Figure
        With one row of axes per quantity, sharing the θ2 axis.

    Examples
    --------
    >>> from machdyn import FourBar
    >>> m = FourBar(8, 4, 7, 6).solve(np.radians(np.arange(0, 361, 5)), omega2=10.0)
    >>> fig = plot_kinematics(m)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['angle (deg)', 'ω (rad/s)', 'α (rad/s²)']
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    charts = kinematics_charts(motion, jerk=jerk, mu=mu)
    flagged = int(np.count_nonzero(~np.ravel(motion.ok)))
    title = f"Four-bar {motion.lengths}, form {motion.form}"
    if flagged:
        title += f" ({flagged} flagged samples left blank)"
    charts = [replace(c, title=title if k == 0 else "") for k, c in enumerate(charts)]
    return figure(charts, fig=fig, sharex=True)


def slider_charts(
    motion: SliderCrankMotion | InvertedSliderCrankMotion,
    *,
    jerk: bool = True,
    rod: bool = False,
    units: Any = None,
) -> list[Chart]:
    """Charts of a slider's position and its derivatives against the crank angle θ2.

    For a :class:`~machdyn.slidercrank.SliderCrankMotion`: the slider position
    ``d`` along its line and ḋ, d̈ (and jerk); with ``rod`` also the
    connecting rod's θ3, ω3, α3 first. For an
    :class:`~machdyn.slidercrank.InvertedSliderCrankMotion`: the block's
    position ``b`` along the slot and ḃ, b̈ (and jerk); with ``rod`` the slotted
    link's θ4, ω4, α4 first. Lengths are in the motion's length unit, speeds
    in its velocity units ("model units" and seconds without units).

    Examples
    --------
    >>> from machdyn import SliderCrank
    >>> m = SliderCrank(2.0, 6.0).solve(np.radians(np.arange(0, 360, 5.0)), omega2=10.0)
    >>> [c.ylabel for c in slider_charts(m, jerk=False)]
    ['d (model units)', 'ḋ (model units/s)', 'd̈ (model units/s²)']
    """
    if isinstance(motion, SliderCrankMotion):
        s, link = "d", "3"
        names = ("d", "d_dot", "d_ddot", "d_dddot")
        labels = ("d", "ḋ", "d̈", "jerk")
    elif isinstance(motion, InvertedSliderCrankMotion):
        s, link = "b", "4"
        names = ("b", "b_dot", "b_ddot", "b_dddot")
        labels = ("b", "ḃ", "b̈", "jerk")
    else:
        raise InputError(
            "motion",
            "expected a SliderCrankMotion from SliderCrank.solve (or an "
            f"InvertedSliderCrankMotion), got {type(motion).__name__}",
        )
    u = _units(motion, units)
    x = np.ravel(u.show("angle", np.ravel(motion.theta2).astype(float)))
    xlabel = u.axis("θ2", "angle")
    assembled = getattr(motion, "assembled", None)
    assembled = motion.ok if assembled is None else assembled
    charts = []
    if rod:
        for q, kind, title in (
            ("theta", "angle", "angle"),
            ("omega", "angular_velocity", "angular velocity"),
            ("alpha", "angular_acceleration", "angular acceleration"),
        ):
            valid = assembled if kind == "angle" else motion.ok
            sym = {"theta": "θ", "omega": "ω", "alpha": "α"}[q] + link
            series = [_curve(x, getattr(motion, q + link), valid, kind, u, sym, q + link)]
            charts.append(_zero(Chart(f"link {link} {title}", xlabel, u.axis(sym, kind), series)))
    kinds = ("length", "velocity", "acceleration", "jerk")
    what = ("position", "velocity", "acceleration", "jerk")
    for k, (name, label, kind) in enumerate(zip(names, labels, kinds, strict=True)):
        if k == 3 and not jerk:
            break
        valid = assembled if k == 0 else motion.ok
        y = _masked(u.show(kind, np.asarray(getattr(motion, name), float)), valid)
        series = [Series(x, y.filled(np.nan), "", colour="#2ca02c", gid=name)]
        title = f"slider {what[k]} {s}" if k else f"slider position {s} along its line"
        charts.append(_zero(Chart(title, xlabel, u.axis(label, kind), series)))
    return charts


def plot_slider_motion(
    motion: SliderCrankMotion | InvertedSliderCrankMotion,
    *,
    jerk: bool = True,
    fig: Figure | None = None,
    length_unit: str | None = None,
    rod: bool = False,
) -> Figure:
    """Slider position and its derivatives against the crank angle (an "svaj" plot).

    The charts of :func:`slider_charts`, drawn with matplotlib. Flagged
    samples are left as gaps (positions are kept at toggles). Lengths are
    labelled in the motion's units (``motion.units``; ``length_unit`` names
    the length unit of a motion without them), else "model units"; time in
    seconds (the unit of the ``omega2`` given).

    Examples
    --------
    >>> from machdyn import SliderCrank
    >>> m = SliderCrank(2.0, 6.0).solve(np.radians(np.arange(0, 361, 5)), omega2=10.0)
    >>> fig = plot_slider_motion(m)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['d (model units)', 'ḋ (model units/s)', 'd̈ (model units/s²)', 'jerk (model units/s³)']
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    units = None
    if length_unit and getattr(motion, "units", None) is None:
        from ..units import UnitSystem

        units = Units(UnitSystem(length=length_unit))
    charts = slider_charts(motion, jerk=jerk, rod=rod, units=units)
    title = f"Slider motion, form {motion.form}"
    charts = [replace(c, title=title if k == 0 else "") for k, c in enumerate(charts)]
    return figure(charts, fig=fig, sharex=True)


def _units(motion: Any, units: Any) -> Units:
    return Units.of(motion if units is None else units)
