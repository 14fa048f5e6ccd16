"""The polar plot of a rotor's unbalance: each mass's ``m R`` (and ``m R z``) with the corrections.

Each rotating mass is an arrow from the axis to ``m R e^{jθ}`` in the rotor's
frame (Norton's vector diagram of the unbalance, §12.1–12.2); the correction
masses are dashed arrows, the resultant of the masses a thick grey one. A
two-plane balance gets a second plot of the moments ``m R (z − z_A)`` about
plane A, where the correction in plane B closes the polygon.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .chart import COLOURS, Chart, Series
from .units import Units

__all__ = ["unbalance_chart"]


def _arrow(z: complex, label: str, colour: str, dashed: bool = False, width: float = 2.0) -> list:
    """A line from the origin to ``z`` with a head (two short strokes)."""
    if abs(z) == 0:
        return []
    head = 0.12 * abs(z) * np.exp(1j * np.radians([150.0, -150.0])) * (z / abs(z))
    x = np.array([0, z.real, np.nan, z.real + head[0].real, z.real, z.real + head[1].real])
    y = np.array([0, z.imag, np.nan, z.imag + head[0].imag, z.imag, z.imag + head[1].imag])
    return [Series(x, y, label, colour, dashed=dashed, width=width)]


def unbalance_chart(
    unbalance: Sequence[complex],
    corrections: Sequence[complex] = (),
    *,
    names: Sequence[str] | None = None,
    correction_names: Sequence[str] = ("correction A", "correction B"),
    kind: str = "unbalance",
    title: str = "unbalance m R (rotor frame)",
    units: Any = None,
) -> Chart:
    """A polar chart of the unbalance vectors, the corrections and their resultant.

    ``unbalance`` and ``corrections`` are complex ``m R e^{jθ}`` (or ``m R z``
    with ``kind="moment_of_unbalance"``) in the model's units.

    Examples
    --------
    >>> c = unbalance_chart([3.0, 2j], [-3 - 2j])
    >>> [s.label for s in c.series if s.label]
    ['m1', 'm2', 'Σ of the masses', 'correction A']
    """
    u = Units.of(units)
    z = np.asarray(u.show(kind, np.asarray(unbalance, complex)), complex)
    fix = np.asarray(u.show(kind, np.asarray(corrections, complex)), complex)
    names = list(names) if names is not None else [f"m{i + 1}" for i in range(z.size)]
    series: list[Series] = []
    for i, (v, name) in enumerate(zip(z, names, strict=True)):
        series += _arrow(complex(v), name, COLOURS[i % len(COLOURS)])
    series += _arrow(complex(z.sum()), "Σ of the masses", "#888888", width=3.5)
    for v, name in zip(fix, correction_names, strict=False):
        series += _arrow(complex(v), name, "#d62728", dashed=True)
    reach = float(np.max(np.abs(np.concatenate([z, fix, [z.sum()]]))) or 1.0)
    ring = reach * np.exp(1j * np.linspace(0, 2 * np.pi, 121))
    series.append(Series(ring.real, ring.imag, "", "#dddddd", width=1.0))
    unit = u.unit(kind)
    label = f" ({unit})" if unit else ""
    notes = [(float(v.real), float(v.imag), n) for v, n in zip(z, names, strict=True) if abs(v)]
    return Chart(title, f"x{label}", f"y{label}", series=series, notes=notes, equal=True)
