"""Kinematic inversions of a four-bar: Barker tables with each link grounded.

An inversion grounds another link of the same chain (the notes: "kinematic
inversion: variation to mechanism by changing which link is grounded"; Norton,
*Design of Machinery*, sec. 2.11). HW 3 #2 asks for the Barker table of each
inversion of the GRCR {6, 9, 3, 8}: its class, and the range of each of the six
fundamental angles φij over form 1, over form 2, and the values common to both.

Numbering. Grounding link ``k`` of the chain 1-2-3-4 renumbers the links
cyclically, keeping the order around the loop: the grounded link becomes link
1, the next one link 2 (the input), and so on, so link ``k + i − 1`` (mod 4)
plays link ``i``. With R1 = 6, R2 = 9, R3 = 3, R4 = 8 the four inversions are
{6, 9, 3, 8} GRCR, {9, 3, 8, 6} GCRR, {3, 8, 6, 9} GCCC and {8, 6, 9, 3} GRRC —
the classical result that a Grashof chain gives two crank-rockers, a double
crank and a double rocker.

Relations between the φ's. φij is the angle between the two links other than
i and j ("faces i & j"), so every φ of an inversion is a φ of the original
chain in the same pose. One step of the renumbering (link 2 grounded) maps the
vectors ``R1' = −R2, R2' = R3, R3' = −R4, R4' = R1``, and the notes'
definitions (φ12 = θ4 − θ3, φ13 = θ2 − θ4, φ14 = π − θ2 + θ3, φ23 = π − θ4,
φ24 = θ3, φ34 = θ2) give

``φ'12 = φ23, φ'13 = φ24, φ'14 = φ12, φ'23 = φ34, φ'24 = −φ13, φ'34 = φ14``

(indices shift by one; the angle between the two non-adjacent links changes
sign because it is measured from the other one). :attr:`Inversion.phi_map`
composes this step ``k − 1`` times.

Each inversion's ranges are the exact extrema of its own closed form
(:meth:`machdyn.FourBar.extrema`, with that inversion's form rule: the sign of
φ12, or of φ34 for GRCR and GRRC); "common to both" is the intersection of the
two forms' ranges on the circle (none, one or two arcs).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._angles import TWO_PI, wrap_pi
from ._validate import (
    boolean,
    finite_array,
    finite_scalar,
    instance,
    integer,
    items,
    nonnegative,
)
from .classify import Classification
from .errors import InputError

__all__ = ["PHI_NAMES", "AngleRange", "Inversion", "InversionTable", "inversions"]

#: The six fundamental angles, in the notes' order.
PHI_NAMES = ("phi12", "phi13", "phi14", "phi23", "phi24", "phi34")

#: One renumbering step (link 2 grounded): new name -> (sign, old name).
_STEP: dict[str, tuple[int, str]] = {
    "phi12": (1, "phi23"),
    "phi13": (1, "phi24"),
    "phi14": (1, "phi12"),
    "phi23": (1, "phi34"),
    "phi24": (-1, "phi13"),
    "phi34": (1, "phi14"),
}

#: Arcs meeting within this many radians share a point.
_TOUCH = 1e-9


@dataclass(frozen=True)
class AngleRange:
    """The values an angle takes: a union of arcs of the circle, or every direction.

    Attributes
    ----------
    arcs : tuple of (float, float)
        ``(lo, hi)`` in radians with ``lo <= hi``: the angle runs from ``lo`` up
        to ``hi``. Each arc is centred in (−π, π], so one end may lie beyond ±π
        (146° … 214°). Empty when the angle takes no value (e.g. the range
        common to two forms that never meet).
    full_turn : bool
        True when the angle takes every direction (``arcs`` is then
        ``((-π, π),)``).

    Examples
    --------
    >>> r = AngleRange(((np.radians(30.0), np.radians(90.0)),))
    >>> r.text()
    '30.00 … 90.00'
    >>> AngleRange((), False).text(), AngleRange.every_direction().text()
    ('none', 'full turn')
    >>> AngleRange(((0.0, 0.0), (np.pi, np.pi))).text()   # two single values
    '0.00, 180.00'
    """

    arcs: tuple[tuple[float, float], ...]
    full_turn: bool = False

    def __post_init__(self) -> None:
        arcs = []
        for n, arc in enumerate(items("arcs", self.arcs, what="(lo, hi) arcs")):
            lo, hi = (
                finite_scalar(f"arcs[{n}] {end}", v, "radian")
                for end, v in zip(("lo", "hi"), items(f"arcs[{n}]", arc, 2, "angles"), strict=True)
            )
            if hi < lo:
                raise InputError(f"arcs[{n}]", f"needs lo <= hi, got ({lo:g}, {hi:g})")
            arcs.append((lo, hi))
        object.__setattr__(self, "arcs", tuple(arcs))
        object.__setattr__(self, "full_turn", boolean("full_turn", self.full_turn))

    @classmethod
    def every_direction(cls) -> AngleRange:
        """The range of an angle that turns fully."""
        return cls(((-np.pi, np.pi),), True)

    @property
    def empty(self) -> bool:
        """True when the angle takes no value."""
        return not self.arcs

    def contains(self, angle: Any, tol: float = 1e-9) -> np.ndarray:
        """True where ``angle`` (radians, any shape) lies in the range."""
        angle = finite_array("angle", angle, "radian")
        tol = nonnegative("tol", tol, "radian")
        if self.full_turn:
            return np.ones(angle.shape, dtype=bool)
        inside = np.zeros(angle.shape, dtype=bool)
        for lo, hi in self.arcs:
            mid = 0.5 * (lo + hi)
            inside |= np.abs(wrap_pi(angle - mid)) <= 0.5 * (hi - lo) + tol
        return inside

    def text(self, digits: int = 2) -> str:
        """The range in degrees for a table: ``"lo … hi"``, ``"full turn"`` or ``"none"``."""
        digits = integer("digits", digits, minimum=0, maximum=17)
        if self.full_turn:
            return "full turn"
        if not self.arcs:
            return "none"
        parts = []
        for lo, hi in self.arcs:
            a, b = (round(float(np.degrees(x)), digits) + 0.0 for x in (lo, hi))
            parts.append(f"{a:.{digits}f}" if a == b else f"{a:.{digits}f} … {b:.{digits}f}")
        return ", ".join(parts)

    def degrees(self) -> str | list[list[float]]:
        """Plain data for JSON: ``"full turn"`` or a list of ``[lo, hi]`` in degrees."""
        if self.full_turn:
            return "full turn"
        return [[float(np.degrees(lo)), float(np.degrees(hi))] for lo, hi in self.arcs]

    def intersection(self, other: AngleRange) -> AngleRange:
        """The values common to both ranges (arcs meeting at a point keep that point).

        Examples
        --------
        >>> a = AngleRange(((np.radians(150.0), np.radians(210.0)),))
        >>> b = AngleRange(((np.radians(-170.0), np.radians(-100.0)),))
        >>> a.intersection(b).text()
        '-170.00 … -150.00'
        """
        instance("other", other, AngleRange)
        if self.full_turn:
            return other
        if other.full_turn:
            return self
        pieces: list[tuple[float, float]] = []
        for lo1, hi1 in self.arcs:
            for lo2, hi2 in other.arcs:
                for shift in (-TWO_PI, 0.0, TWO_PI):
                    lo, hi = max(lo1, lo2 + shift), min(hi1, hi2 + shift)
                    if hi >= lo - _TOUCH:
                        hi = max(hi, lo)
                        centre = float(wrap_pi(0.5 * (lo + hi)))
                        offset = centre - 0.5 * (lo + hi)
                        pieces.append((lo + offset, hi + offset))
        pieces.sort()
        return AngleRange(tuple(pieces), False)


@dataclass(frozen=True)
class Inversion:
    """One inversion: the chain with link ``grounded`` held fixed.

    Attributes
    ----------
    grounded : int
        The link of the original chain that is grounded (1–4).
    links : tuple of int
        The original link numbers now playing links 1, 2, 3 and 4.
    lengths : tuple of float
        ``(R1, R2, R3, R4)`` of the inversion.
    classification : Classification
        Its Grashof/Barker class.
    form_rule : str
        ``"phi12"`` or ``"phi34"``: the angle whose sign is the form.
    ranges : dict
        ``ranges[name][which]`` for ``name`` in :data:`PHI_NAMES` and ``which``
        in ``"form1"``, ``"form2"``, ``"common"``: an :class:`AngleRange`.
    """

    grounded: int
    links: tuple[int, int, int, int]
    lengths: tuple[float, float, float, float]
    classification: Classification
    form_rule: str
    ranges: dict[str, dict[str, AngleRange]]

    @property
    def code(self) -> str:
        """Barker's code of the inversion, e.g. ``"GCRR"``."""
        return self.classification.code

    @property
    def phi_map(self) -> dict[str, tuple[int, str]]:
        """Each φ of this inversion as ``(sign, name)`` of a φ of the original chain.

        Examples
        --------
        >>> from machdyn import FourBar
        >>> FourBar(6, 9, 3, 8).inversions()[2].phi_map["phi24"]
        (-1, 'phi13')
        """
        mapping = {name: (1, name) for name in PHI_NAMES}
        for _ in range(self.grounded - 1):
            mapping = {
                new: (sign * mapping[old][0], mapping[old][1]) for new, (sign, old) in _STEP.items()
            }
        return mapping

    def fourbar(self) -> Any:
        """The inversion as a :class:`machdyn.FourBar`."""
        from .fourbar import FourBar

        return FourBar(*self.lengths)


class InversionTable:
    """The four inversions of a four-bar chain; index by the grounded link (1–4).

    Examples
    --------
    >>> from machdyn import FourBar
    >>> table = FourBar(6, 9, 3, 8).inversions()
    >>> [inv.code for inv in table]
    ['GRCR', 'GCRR', 'GCCC', 'GRRC']
    >>> table[2].ranges["phi12"]["form1"].text()
    '48.19 … 117.28'
    """

    def __init__(self, inversions: tuple[Inversion, ...]) -> None:
        self.inversions = inversions

    def __getitem__(self, grounded: int) -> Inversion:
        for inv in self.inversions:
            if inv.grounded == grounded:
                return inv
        from .errors import InputError

        raise InputError("grounded", f"must be a link number 1, 2, 3 or 4, got {grounded!r}")

    def __iter__(self) -> Iterator[Inversion]:
        return iter(self.inversions)

    def __len__(self) -> int:
        return len(self.inversions)

    def __repr__(self) -> str:
        parts = ", ".join(f"{inv.grounded}: {inv.code}" for inv in self.inversions)
        return f"InversionTable({parts})"

    def rows(self) -> list[dict[str, Any]]:
        """One plain row per inversion and angle (degrees), for JSON and tables."""
        out = []
        for inv in self.inversions:
            for name in PHI_NAMES:
                r = inv.ranges[name]
                out.append(
                    {
                        "grounded": inv.grounded,
                        "class": inv.code,
                        "angle": name,
                        "form1": r["form1"].text(),
                        "form2": r["form2"].text(),
                        "common": r["common"].text(),
                    }
                )
        return out

    def to_pandas(self) -> Any:
        """A DataFrame, one row per inversion and angle (ranges as text, degrees)."""
        import pandas as pd

        return pd.DataFrame(self.rows())


def inversions(r1: float, r2: float, r3: float, r4: float, n: int = 2001) -> InversionTable:
    """The Barker table of each of the four inversions of a four-bar chain.

    Parameters
    ----------
    r1, r2, r3, r4 : float
        The chain's lengths in loop order (ground, input, coupler, output).
    n : int
        Samples per branch before the extrema are refined (see
        :meth:`machdyn.FourBar.extrema`).

    Returns
    -------
    InversionTable

    Examples
    --------
    HW 3 #2: the inversions of the GRCR {6, 9, 3, 8}.

    >>> table = inversions(6, 9, 3, 8)
    >>> for inv in table:
    ...     print(inv.grounded, inv.lengths, inv.code, inv.ranges["phi34"]["form1"].text())
    1 (6.0, 9.0, 3.0, 8.0) GRCR 31.59 … 92.12
    2 (9.0, 3.0, 8.0, 6.0) GCRR full turn
    3 (3.0, 8.0, 6.0, 9.0) GCCC full turn
    4 (8.0, 6.0, 9.0, 3.0) GRRC 48.19 … 117.28
    """
    from .fourbar import FourBar

    chain = FourBar(r1, r2, r3, r4).lengths
    table = []
    for k in range(4):
        order = tuple((k + i) % 4 + 1 for i in range(4))
        lengths = tuple(float(chain[j - 1]) for j in order)
        fb = FourBar(*lengths)
        forms = {f"form{f}": _ranges(fb.extrema(form=f, n=n)) for f in (1, 2)}
        ranges = {
            name: {
                "form1": forms["form1"][name],
                "form2": forms["form2"][name],
                "common": forms["form1"][name].intersection(forms["form2"][name]),
            }
            for name in PHI_NAMES
        }
        table.append(
            Inversion(k + 1, order, lengths, fb.classification, fb.form_rule, ranges)  # type: ignore[arg-type]
        )
    return InversionTable(tuple(table))


def _ranges(extrema: dict[str, Any]) -> dict[str, AngleRange]:
    out = {}
    for name in PHI_NAMES:
        e = extrema[name]
        # a range as wide as a turn takes every direction (change points: the two
        # circuits meet and an angle can sweep all around without winding)
        every = e.full_turn or float(e.max) - float(e.min) >= TWO_PI - 1e-6
        out[name] = (
            AngleRange.every_direction()
            if every
            else AngleRange(((float(e.min), float(e.max)),), False)
        )
    return out
