"""Units on plots and in reports: the model's unit system, or honest labels without one.

A model read from a machine file (or built from pint quantities) carries a
:class:`machdyn.units.UnitSystem` in ``model.units``: its results are held in the
system's coherent units and *shown* in its output units (forces in N for a
millimetre–kilogram model, speeds in rpm where the file says so). :class:`Units`
is that conversion for pictures: every axis label and every printed number of
a plot or a report goes through it, so the unit written is the unit of the
number shown. A model without units gets labels that say so ("model units",
"force units"), angles in degrees and rates per second (the unit of the
speed given).

Examples
--------
>>> from machdyn.units import UnitSystem
>>> u = Units(UnitSystem(length="mm", mass="kg", angular_velocity="rpm"))
>>> u.axis("F32", "force"), float(u.show("force", 1000.0))  # held in kg·mm/s² = mN
('F32 (N)', 1.0)
>>> u.axis("ω3", "angular_velocity"), u.text("torque", 2000.0)  # kg·mm²/s², shown in N·mm
('ω3 (rpm)', '2 N·mm')
>>> Units(None).axis("T12", "torque"), Units(None).axis("θ3", "angle")
('T12 (torque units)', 'θ3 (deg)')
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["Units", "pretty_unit"]

#: Labels of a model without units: numbers in any consistent system, time in seconds.
UNIT_FREE = {
    "length": "model units",
    "mass": "mass units",
    "time": "s",
    "angle": "deg",
    "angular_velocity": "rad/s",
    "angular_acceleration": "rad/s²",
    "angular_jerk": "rad/s³",
    "velocity": "model units/s",
    "acceleration": "model units/s²",
    "jerk": "model units/s³",
    "force": "force units",
    "torque": "torque units",
    "energy": "energy units",
    "inertia": "inertia units",
    "unbalance": "mass·length units",
    "moment_of_unbalance": "mass·length² units",
    "dimensionless": "",
}

_POWERS = {"^2": "²", "^3": "³", "^-1": "⁻¹", "^-2": "⁻²", "**2": "²", "**3": "³"}


def pretty_unit(unit: str) -> str:
    """A unit as written on a plot: ``'N*m'`` → ``'N·m'``, ``'rad/s^2'`` → ``'rad/s²'``.

    Examples
    --------
    >>> pretty_unit("kg*m^2"), pretty_unit("(lbf*s^2/in)*in^2")
    ('kg·m²', '(lbf·s²/in)·in²')
    """
    for raw, nice in _POWERS.items():
        unit = unit.replace(raw, nice)
    return unit.replace("*", "·")


class Units:
    """The units a plot or a report writes a model's quantities in.

    Parameters
    ----------
    system : UnitSystem or None
        The model's ``units`` (None or a unit-free system: labels say "model
        units", angles are shown in degrees, rates per second).
    """

    def __init__(self, system: Any = None) -> None:
        free = system is None or getattr(system, "is_unit_free", True)
        self.system = None if free else system

    @classmethod
    def of(cls, model: Any) -> Units:
        """The units of a model, a motion or a result (its ``units``; None: unit-free).

        A :class:`~machdyn.units.UnitSystem` or a :class:`Units` is taken as it is.
        """
        if isinstance(model, Units):
            return model
        if hasattr(model, "display") and hasattr(model, "is_unit_free"):  # a UnitSystem
            return cls(model)
        return cls(getattr(model, "units", None))

    def __repr__(self) -> str:
        return f"Units({self.system!r})"

    @property
    def free(self) -> bool:
        """True for a model without units."""
        return self.system is None

    def unit(self, kind: str) -> str:
        """The unit quantities of ``kind`` are shown in (text for a label)."""
        if self.system is None:
            return UNIT_FREE.get(kind, f"{kind.replace('_', ' ')} units")
        return pretty_unit(self.system.display(kind))

    def show(self, kind: str, values: Any) -> Any:
        """``values`` (held in the model's units; angles in radians) as they are shown."""
        if self.system is None:
            return np.degrees(values) if kind == "angle" else values
        return self.system.show(kind, values)

    def axis(self, quantity: str, kind: str) -> str:
        """An axis label: ``'T12 (N·m)'`` (the quantity alone when it has no unit)."""
        unit = self.unit(kind)
        return f"{quantity} ({unit})" if unit else quantity

    def text(self, kind: str, value: Any, digits: int = 4) -> str:
        """One value as printed, with its unit: ``'12.35 N'`` ('–' when undefined)."""
        v = float(self.show(kind, float(value)))
        if not np.isfinite(v):
            return "–"
        unit = self.unit(kind)
        number = f"{v:.{digits}g}"
        if unit in ("deg", "°"):
            return f"{number}°"
        return f"{number} {unit}" if unit else number
