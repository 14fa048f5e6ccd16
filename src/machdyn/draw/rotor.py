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

__all__ = ["rotor_side_chart", "unbalance_chart"]


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


def rotor_side_chart(
    masses: Sequence[tuple[float, float, float, float]],
    planes: Sequence[float] = (),
    corrections: Sequence[complex] = (),
    radii: Sequence[float] | None = None,
    bearings: Sequence[float] | None = None,
    *,
    units: Any = None,
) -> Chart:
    """The rotor seen from the side: the shaft along z, each mass at its plane, the planes.

    ``masses`` are ``(m, R, θ, z)``; each is drawn at height ``R sin θ`` (its
    projection on the y–z plane at θ = 0) with its name; the correction planes
    are vertical lines, each correction mass at its radius and angle; the
    bearings are marked on the axis.

    Examples
    --------
    >>> c = rotor_side_chart([(0.2, 60, 0.5, 100), (0.3, 50, 2.6, 220)], (0, 400))
    >>> [s.gid for s in c.series if s.gid][:4]
    ['shaft', 'mass_1', 'mass_2', 'plane_A']
    """
    u = Units.of(units)
    length = lambda v: np.asarray(u.show("length", np.asarray(v, float)), float)  # noqa: E731
    z = [e[3] for e in masses]
    ends = [*z, *planes, *(bearings or ())]
    lo, hi = float(min(ends)), float(max(ends))
    pad = 0.08 * (hi - lo or 1.0)
    series = [
        Series(
            length([lo - pad, hi + pad]), np.zeros(2), "shaft", "#555555", width=5.0, gid="shaft"
        )
    ]
    notes = []
    for i, (_, r, a, zi) in enumerate(masses, start=1):
        y = r * np.sin(a)
        series.append(
            Series(
                length([zi, zi]),
                length([0.0, y]),
                "",
                COLOURS[(i - 1) % 7],
                width=2.5,
                gid=f"mass_{i}",
            )
        )
        series.append(Series(length([zi]), length([y]), "", COLOURS[(i - 1) % 7], marker=True))
        notes.append((float(length(zi)), float(length(y)), f"m{i}"))
    reach = max([abs(e[1]) for e in masses] + list(radii or ()) + [1e-300])
    for name, zp, c in zip(("A", "B"), planes, [*corrections, None, None], strict=False):
        series.append(
            Series(
                length([zp, zp]),
                length([-1.1 * reach, 1.1 * reach]),
                "",
                "#d62728",
                dashed=True,
                width=1.0,
                gid=f"plane_{name}",
            )
        )
        notes.append((float(length(zp)), float(length(1.15 * reach)), f"plane {name}"))
        if c is not None and radii:
            r = radii[0 if name == "A" else -1]
            y = r * np.sin(np.angle(c))
            series.append(Series(length([zp]), length([y]), "", "#d62728", marker=True))
    for name, zb in zip(("A", "B"), bearings or (), strict=False):
        series.append(Series(length([zb]), np.zeros(1), "", "#000000", marker=True))
        notes.append((float(length(zb)), float(length(-0.2 * reach)), f"bearing {name}"))
    unit = u.unit("length")
    return Chart(
        "the rotor from the side (heights R sin θ at θ = 0)",
        f"z ({unit})",
        f"y ({unit})",
        series=series,
        notes=notes,
    )
