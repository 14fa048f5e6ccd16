"""Kinematic curves: angles, rates and slider motion against the input, axes with units.

Flagged samples are gaps (masked), never zeros or lines drawn across them, and
an angle's wrap from 360° to 0° is not joined by a vertical line.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ..fourbar import FourBarMotion
from ..slidercrank import SliderCrankMotion

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from .chart import Chart

__all__ = ["kinematics_charts", "length_label", "plot_kinematics", "plot_slider_motion"]


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


def plot_kinematics(
    motion: FourBarMotion, *, jerk: bool = False, mu: bool = False, fig: Figure | None = None
) -> Figure:
    """θ3, θ4, ω3, ω4, α3, α4 (and optionally the jerks) of a four-bar against θ2.

    Angles are drawn in degrees, rates in rad/s, rad/s², rad/s³ (the time unit
    of the ``omega2`` given to the solver). Flagged samples (``motion.ok``
    False; positions also at toggles, where only the rates are undefined) are
    left as gaps, and an angle's wrap from 360° to 0° is not joined.

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
    if not isinstance(motion, FourBarMotion):
        raise InputError(
            "motion", f"expected a FourBarMotion from FourBar.solve, got {type(motion).__name__}"
        )
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(7, 7 if jerk else 5.5), layout="constrained")
    panels: list[tuple[str, list[tuple[str, str, bool, bool]]]] = [
        (
            "angle (deg)",
            [("theta3", "θ3", True, True), ("theta4", "θ4", True, True)]
            + ([("mu", "μ", True, False)] if mu else []),
        ),
        ("ω (rad/s)", [("omega3", "ω3", False, False), ("omega4", "ω4", False, False)]),
        ("α (rad/s²)", [("alpha3", "α3", False, False), ("alpha4", "α4", False, False)]),
    ]
    if jerk:
        panels.append(
            ("jerk (rad/s³)", [("jerk3", "jerk3", False, False), ("jerk4", "jerk4", False, False)])
        )
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    x = np.degrees(np.ravel(motion.theta2))
    for ax, (ylabel, curves) in zip(axes, panels, strict=True):
        for name, label, is_angle, wraps in curves:
            valid = motion.assembled if is_angle else motion.ok
            values = np.ravel(getattr(motion, name))
            y = _masked(np.degrees(values) if is_angle else values, valid)
            xs, ys = _break_wraps(x, y) if wraps else (x, y)
            (line,) = ax.plot(xs, ys, label=label)
            line.set_gid(name)
        ax.set_ylabel(ylabel)
        ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
        ax.grid(True, lw=0.3)
        ax.legend(loc="best", fontsize=8)
    axes[-1].set_xlabel("θ2 (deg)")
    flagged = int(np.count_nonzero(~np.ravel(motion.ok)))
    title = f"Four-bar {motion.lengths}, form {motion.form}"
    if flagged:
        title += f" ({flagged} flagged samples left blank)"
    axes[0].set_title(title, fontsize=10)
    return fig


def plot_slider_motion(
    motion: SliderCrankMotion,
    *,
    jerk: bool = True,
    fig: Figure | None = None,
    length_unit: str | None = None,
) -> Figure:
    """Slider position d and its derivatives against the crank angle (an "svaj" plot).

    Flagged samples are left as gaps (positions are kept at toggles). Lengths
    are labelled with ``length_unit`` (the model's, e.g. ``SliderCrank.length_unit``),
    or "model units"; time in seconds (the unit of the ``omega2`` given).

    Examples
    --------
    >>> from machdyn import SliderCrank
    >>> m = SliderCrank(2.0, 6.0).solve(np.radians(np.arange(0, 361, 5)), omega2=10.0)
    >>> fig = plot_slider_motion(m)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['d (model units)', 'ḋ (model units/s)', 'd̈ (model units/s²)', 'jerk (model units/s³)']
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    if not isinstance(motion, SliderCrankMotion):
        raise InputError(
            "motion",
            f"expected a SliderCrankMotion from SliderCrank.solve, got {type(motion).__name__}",
        )
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(7, 7 if jerk else 5.5), layout="constrained")
    u = length_label(length_unit)
    rows = [
        ("d", f"d ({u})", True),
        ("d_dot", f"ḋ ({u}/s)", False),
        ("d_ddot", f"d̈ ({u}/s²)", False),
    ]
    if jerk:
        rows.append(("d_dddot", f"jerk ({u}/s³)", False))
    axes = fig.subplots(len(rows), 1, sharex=True, squeeze=False)[:, 0]
    x = np.degrees(np.ravel(motion.theta2))
    for ax, (name, ylabel, is_position) in zip(axes, rows, strict=True):
        valid = motion.assembled if is_position else motion.ok
        (line,) = ax.plot(x, _masked(getattr(motion, name), valid), color="C2")
        line.set_gid(name)
        ax.set_ylabel(ylabel)
        ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
        ax.grid(True, lw=0.3)
    axes[-1].set_xlabel("θ2 (deg)")
    axes[0].set_title(f"Slider motion, form {motion.form}", fontsize=10)
    return fig


def kinematics_charts(motion: FourBarMotion) -> list[Chart]:
    """Charts of a four-bar's θ3, θ4 (deg), ω3, ω4 (rad/s) and α3, α4 (rad/s²) against θ2 (deg).

    The same quantities as :func:`plot_kinematics`, as :class:`~machdyn.draw.chart.Chart`
    descriptions (the report writes them as inline SVG). Flagged samples are
    gaps; an angle's wrap from 360° to 0° is a gap too.

    Examples
    --------
    >>> from machdyn import FourBar
    >>> m = FourBar(8, 4, 7, 6).solve(np.radians(np.arange(0, 360, 5.0)), omega2=10.0)
    >>> [c.ylabel for c in kinematics_charts(m)]
    ['angle (deg)', 'ω (rad/s)', 'α (rad/s²)']
    """
    from .chart import Chart, Series

    x = np.degrees(np.ravel(motion.theta2).astype(float))
    charts = []
    for title, ylabel, names, is_angle in (
        ("link angles", "angle (deg)", ("theta3", "theta4"), True),
        ("angular velocities", "ω (rad/s)", ("omega3", "omega4"), False),
        ("angular accelerations", "α (rad/s²)", ("alpha3", "alpha4"), False),
    ):
        series = []
        for name in names:
            values = getattr(motion, name)
            if values is None:
                continue
            valid = motion.assembled if is_angle else motion.ok
            y = _masked(np.degrees(values) if is_angle else values, valid)
            xs, ys = _break_wraps(x, y) if is_angle else (x, y)
            label = name.replace("theta", "θ").replace("omega", "ω").replace("alpha", "α")
            series.append(Series(np.asarray(xs, float), ys.filled(np.nan), label))
        if series:
            charts.append(Chart(title, "θ2 (deg)", ylabel, series))
    return charts
