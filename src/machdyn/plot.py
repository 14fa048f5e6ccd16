"""Pictures of solved mechanisms (moved to :mod:`machdyn.draw`; these names stay here).

Every call documented under ``machdyn.plot`` keeps working: the functions are
those of :mod:`machdyn.draw.fourbar` and :mod:`machdyn.draw.kinematics`.
"""

from __future__ import annotations

from .draw.fourbar import (
    Sweep,
    animate,
    draw_fourbar,
    plot_coupler_curve,
    plot_slider_crank,
    sweep,
)
from .draw.kinematics import plot_kinematics, plot_slider_motion

__all__ = [
    "Sweep",
    "animate",
    "draw_fourbar",
    "plot_coupler_curve",
    "plot_kinematics",
    "plot_slider_crank",
    "plot_slider_motion",
    "sweep",
]
