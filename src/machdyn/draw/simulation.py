"""Plots of a simulation in time: angle, speed and motor effort, with its events.

No dynamics is computed here: the :class:`~machdyn.simulate.Simulation` holds
every number drawn.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

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


def plot_simulation(sim: Any, *, fig: Figure | None = None) -> Figure:
    """θ, ω and the motor's effort of a :class:`~machdyn.simulate.Simulation` against time.

    Angles in degrees, speeds in rad/s (per the model's time unit); a linear
    driver's travel and speed in its length unit. Events (stall, reversal,
    toggle, steady state, a switching motor or load) are marked and labelled
    on the speed panel; the steady-state band ``ω_min … ω_max`` of the last
    cycle is shaded.

    Parameters
    ----------
    sim : Simulation
        From :func:`machdyn.simulate`.
    fig : matplotlib Figure, optional
        An empty figure to draw in.

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

    if fig is None:
        fig = plt.figure(figsize=(7.0, 6.5))
    axes = fig.subplots(3, 1, sharex=True)
    name = sim.coordinate
    theta = np.degrees(sim.theta) if sim.angular else sim.theta
    axes[0].plot(sim.t, theta, color="C0")
    axes[0].set_ylabel(f"{name} [deg]" if sim.angular else name)
    axes[1].plot(sim.t, sim.omega, color="C1")
    axes[1].set_ylabel("omega [rad/s]" if sim.angular else f"{name} rate")
    axes[2].plot(sim.t, sim.motor_torque, color="C2")
    axes[2].set_ylabel("motor torque" if sim.angular else "motor force")
    axes[2].set_xlabel("t [s]")
    if sim.steady is not None and sim.cycles.size >= 2:
        s = sim.steady
        axes[1].axhspan(s.omega_min, s.omega_max, color="C1", alpha=0.15, lw=0)
        axes[1].axhline(s.omega_avg, color="C1", lw=0.8, ls="--")
        axes[1].annotate(
            f"k = {s.k:.3g}", (sim.cycles[-1], s.omega_max), ha="right", va="bottom", fontsize=8
        )
    for event in sim.events:
        marker = _MARKS.get(event.kind, "*")
        axes[1].plot([event.t], [event.omega], marker=marker, color="k", ls="none")
        axes[1].annotate(event.kind, (event.t, event.omega), xytext=(3, 3),
                         textcoords="offset points", fontsize=8)  # fmt: skip
    for ax in axes:
        ax.grid(True, lw=0.3)
    fig.suptitle(sim.message, fontsize=9)
    return fig
