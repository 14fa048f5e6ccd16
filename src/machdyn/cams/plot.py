"""Plots of svaj diagrams and cam profiles (matplotlib, imported lazily)."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["plot_profile", "plot_svaj"]


def plot_svaj(motion: Any, axes: Any = None) -> Any:
    """Plot s, v, a, j against θ in degrees (the notes' svaj diagrams).

    Parameters
    ----------
    motion : Motion
        From :meth:`machdyn.cams.CamProgram.sample`.
    axes : sequence of 4 matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    if axes is None:
        fig, axes = plt.subplots(4, 1, sharex=True, figsize=(7, 8))
    else:
        fig = axes[0].figure
    deg = np.degrees(motion.theta)
    labels = ("s", "v (per rad)", "a (per rad²)", "j (per rad³)")
    for ax, key, label in zip(axes, "svaj", labels, strict=True):
        ax.plot(deg, getattr(motion, key), lw=1.2)
        ax.set_ylabel(label)
        ax.axhline(0.0, color="0.7", lw=0.6)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("cam angle θ (deg)")
    axes[-1].set_xlim(0.0, 360.0)
    return fig


def plot_profile(profile: Any, ax: Any = None) -> Any:
    """Draw the cam surface, pitch curve, base and prime circles; undercut in red.

    Returns
    -------
    matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(6, 6))
    t = np.linspace(0.0, 2.0 * np.pi, 361)
    ax.plot(
        profile.base_radius * np.cos(t),
        profile.base_radius * np.sin(t),
        ":",
        color="0.5",
        lw=0.8,
        label="base circle",
    )
    if profile.pitch is not None:
        ax.plot(
            profile.prime_radius * np.cos(t),
            profile.prime_radius * np.sin(t),
            "--",
            color="0.6",
            lw=0.8,
            label="prime circle",
        )
        ax.plot(
            profile.pitch.real, profile.pitch.imag, color="tab:green", lw=1.0, label="pitch curve"
        )
    ax.plot(profile.surface.real, profile.surface.imag, color="k", lw=1.6, label="cam surface")
    if profile.has_surface_loop:  # the outline crosses itself: cut away when made
        cut = profile.surface[profile.surface_loop]
        ax.plot(cut.real, cut.imag, ".", color="tab:orange", ms=3, label="surface loop")
    if profile.is_undercut:
        bad = profile.surface[profile.undercut]
        ax.plot(bad.real, bad.imag, ".", color="tab:red", ms=3, label="undercut")
    ax.plot([0.0], [0.0], "+", color="k")
    ax.set_aspect("equal")
    ax.set_title(f"radial cam, {profile.follower} follower")
    ax.legend(loc="upper right", fontsize="small")
    return ax
