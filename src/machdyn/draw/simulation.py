"""Plots of a simulation in time: angle, speed and motor effort, with its events.

No dynamics is computed here: the :class:`~machdyn.simulate.Simulation` holds
every number drawn.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["plot_simulation"]

_MARKS = {
    "stall": "x",
    "reversal": "|",
    "rest": "o",
    "toggle": "D",
    "steady": "s",
    "breakpoint": "v",
}


def plot_simulation(
    sim: Any, *, fig: Figure | None = None, units: Any = None, title: str | None = None
) -> Figure:
    """θ, ω and the motor's effort of a :class:`~machdyn.simulate.Simulation` against time.

    Angles in degrees, speeds in rad/s (per the model's time unit); a linear
    driver's travel and speed in its length unit. With ``units`` (a machine
    file's :class:`~machdyn.units.UnitSystem`) every axis is in its output units
    and labelled with them. Events (stall, reversal,
    toggle, steady state, a switching motor or load) are marked and labelled
    on the speed panel; the steady-state band ``ω_min … ω_max`` of the last
    cycle is shaded.

    Parameters
    ----------
    sim : Simulation
        From :func:`machdyn.simulate`.
    fig : matplotlib Figure, optional
        An empty figure to draw in.
    units : UnitSystem, optional
        The model's units (internal) and the units to show (output).
    title : str, optional
        The figure's title; the simulation's message by default.

    Returns
    -------
    matplotlib.figure.Figure
        Three axes sharing the time axis.

    Examples
    --------
    >>> import machdyn
    >>> from machdyn.simulate import DCMotor
    >>> fb = machdyn.FourBar(0.08, 0.04, 0.07, 0.06)
    >>> run = machdyn.simulate(fb, DCMotor(0.5, 300.0, ratio=10.0), mass=(0.2, 0.3, 0.25),
    ...                        inertia=(3e-5, 1.2e-4, 7.5e-5), cg=(0.02, 0.035, 0.03),
    ...                        flywheel=0.02, t_end=0.5)
    >>> fig = plot_simulation(run)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['theta2 [deg]', 'omega [rad/s]', 'motor torque']
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    import matplotlib.pyplot as plt

    from ..units import UnitSystem

    if units is not None and not isinstance(units, UnitSystem):
        raise InputError("units", f"must be a machdyn.units.UnitSystem or None, got {units!r}")
    if fig is None:
        fig = plt.figure(figsize=(7.0, 6.5))
    axes = fig.subplots(3, 1, sharex=True)
    name = sim.coordinate
    if sim.angular:
        kinds = {"q": "angle", "w": "angular_velocity", "effort": "torque"}
        names = {"q": name, "w": "omega", "effort": "motor torque"}
    else:
        kinds = {"q": "length", "w": "velocity", "effort": "force"}
        names = {"q": name, "w": f"{name} rate", "effort": "motor force"}
    kinds["t"], names["t"] = "time", "t"

    def shown(what: str, value: Any) -> Any:
        value = np.asarray(value, dtype=float)
        if units is not None:
            return units.show(kinds[what], value)
        return np.degrees(value) if kinds[what] == "angle" else value

    def label(what: str) -> str:
        if units is not None:
            return units.label(names[what], kinds[what])
        bare = {"angle": " [deg]", "angular_velocity": " [rad/s]", "time": " [s]"}
        return names[what] + bare.get(kinds[what], "")

    t = shown("t", sim.t)
    for ax, what, value, color in zip(axes, ("q", "w", "effort"),
                                      (sim.theta, sim.omega, sim.motor_torque),
                                      ("C0", "C1", "C2"), strict=True):  # fmt: skip
        ax.plot(t, shown(what, value), color=color)
        ax.set_ylabel(label(what))
    axes[2].set_xlabel(label("t"))
    if sim.steady is not None and sim.cycles.size >= 2:
        s = sim.steady
        low, high, avg = (float(shown("w", v)) for v in (s.omega_min, s.omega_max, s.omega_avg))
        axes[1].axhspan(low, high, color="C1", alpha=0.15, lw=0)
        axes[1].axhline(avg, color="C1", lw=0.8, ls="--")
        axes[1].annotate(
            f"k = {s.k:.3g}",
            (float(shown("t", sim.cycles[-1])), high),
            xytext=(-14, 3),  # clear of the last event's label
            textcoords="offset points",
            ha="right",
            va="bottom",
            fontsize=8,
        )
    for event in sim.events:
        marker = _MARKS.get(event.kind, "*")
        at = (float(shown("t", event.t)), float(shown("w", event.omega)))
        axes[1].plot([at[0]], [at[1]], marker=marker, color="k", ls="none")
        axes[1].annotate(event.kind, at, xytext=(3, 3),
                         textcoords="offset points", fontsize=8)  # fmt: skip
    for ax in axes:
        ax.grid(True, lw=0.3)
    fig.suptitle(sim.message if title is None else title, fontsize=9)
    return fig
