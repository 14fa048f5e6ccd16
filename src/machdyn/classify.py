"""Grashof condition and Barker's classification of four-bar linkages.

Link numbering as in the notes: ``R1`` ground, ``R2`` input, ``R3`` coupler,
``R4`` output. With ``s`` the shortest, ``l`` the longest and ``p``, ``q`` the
other two lengths:

* assemblability condition: ``l < s + p + q``;
* Grashof condition: ``s + l < p + q`` (at least one link fully rotates);
* Barker's table (the notes' Table 2; Norton, *Design of Machinery*,
  Table 2-4): the sign of ``s + l − (p + q)`` and which link is ``s`` (Grashof
  and change point) or ``l`` (non-Grashof) give one of 14 classes.

Change-point linkages (``s + l = p + q``) are recognised to a relative tolerance
of :data:`CHANGE_POINT_RTOL` of the total length, so lengths typed with a
finite number of digits (``6, 4, 3, 5``, or ``0.4, 0.2, 0.5, 0.7`` whose sums
differ in binary) classify as the user intends. Norton (§2.14) writes the
Grashof condition ``s + l ≤ p + q`` and calls the equality "special-case
Grashof"; machdyn follows Barker's table of the notes, where it is its own row
group: ``condition == "change point"``, :func:`is_grashof` False, and the
links that turn fully (``cranks``) those of the Grashof row with the same
shortest link (the four-bar report says "special Grashof (change point)").
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import Any, NamedTuple

from ._validate import positive_length as positive
from .errors import AssemblyError, InputError

__all__ = [
    "BARKER_CLASSES",
    "CHANGE_POINT_RTOL",
    "Classification",
    "FourBarLoop",
    "barker_class",
    "classify",
    "fourbar_loops",
    "is_assemblable",
    "is_grashof",
]

#: Relative tolerance (of R1 + R2 + R3 + R4) for ``s + l = p + q``.
CHANGE_POINT_RTOL = 1e-9

#: Barker's 14 classes: code -> (number in the notes' table, proposed name).
BARKER_CLASSES: dict[str, tuple[int, str]] = {
    "GCCC": (1, "Grashof crank-crank-crank"),
    "GCRR": (2, "Grashof crank-rocker-rocker"),
    "GRCR": (3, "Grashof rocker-crank-rocker"),
    "GRRC": (4, "Grashof rocker-rocker-crank"),
    "RRR1": (5, "Class 1 rocker-rocker-rocker"),
    "RRR2": (6, "Class 2 rocker-rocker-rocker"),
    "RRR3": (7, "Class 3 rocker-rocker-rocker"),
    "RRR4": (8, "Class 4 rocker-rocker-rocker"),
    "CPCCC": (9, "change point crank-crank-crank"),
    "CPCRR": (10, "change point crank-rocker-rocker"),
    "CPRCR": (11, "change point rocker-crank-rocker"),
    "CPRRC": (12, "change point rocker-rocker-crank"),
    "CP2X": (13, "double change point"),
    "CP3X": (14, "triple change point"),
}

_GRASHOF = ("GCCC", "GCRR", "GRCR", "GRRC")
_NON_GRASHOF = ("RRR1", "RRR2", "RRR3", "RRR4")
_CHANGE_POINT = ("CPCCC", "CPCRR", "CPRCR", "CPRRC")


@dataclass(frozen=True)
class Classification:
    """Grashof/Barker classification of a four-bar.

    Attributes
    ----------
    code : str
        Barker's symbol, e.g. ``"GCRR"``.
    number : int
        Row of Barker's table (1–14).
    name : str
        Barker's proposed name, e.g. ``"Grashof crank-rocker-rocker"``.
    condition : str
        ``"grashof"`` (s + l < p + q), ``"non-grashof"`` (>) or ``"change point"`` (=).
    s, l : float
        Shortest and longest lengths.
    shortest, longest : tuple of int
        The link numbers (1–4) having the shortest / longest length.
    cranks : tuple of int
        Moving links (2, 3, 4) that can make full turns relative to the ground.
    """

    code: str
    number: int
    name: str
    condition: str
    s: float
    l: float  # noqa: E741 - the notes' symbol
    shortest: tuple[int, ...]
    longest: tuple[int, ...]
    cranks: tuple[int, ...]

    @property
    def is_grashof(self) -> bool:
        """True for ``s + l < p + q`` (change points excluded)."""
        return self.condition == "grashof"


def _lengths(r1: float, r2: float, r3: float, r4: float) -> tuple[float, float, float, float]:
    return (positive("r1", r1), positive("r2", r2), positive("r3", r3), positive("r4", r4))


def _condition(lengths: tuple[float, ...]) -> tuple[str, float, float]:
    ordered = sorted(lengths)
    s, p, q, l = ordered  # noqa: E741
    excess = (s + l) - (p + q)
    tol = CHANGE_POINT_RTOL * sum(lengths)
    if excess < -tol:
        return "grashof", s, l
    if excess > tol:
        return "non-grashof", s, l
    return "change point", s, l


def _equal(a: float, b: float, lengths: tuple[float, ...]) -> bool:
    return abs(a - b) <= CHANGE_POINT_RTOL * sum(lengths)


def is_assemblable(r1: float, r2: float, r3: float, r4: float) -> bool:
    """Assemblability condition ``l < s + p + q`` (the notes).

    A chain whose longest link equals the sum of the others only closes flat, as
    a structure, and is reported as not assemblable.

    Examples
    --------
    >>> is_assemblable(8, 4, 7, 6)
    True
    >>> is_assemblable(20, 4, 7, 6)
    False
    """
    lengths = _lengths(r1, r2, r3, r4)
    longest = max(lengths)
    return longest < sum(lengths) - longest - CHANGE_POINT_RTOL * sum(lengths)


def is_grashof(r1: float, r2: float, r3: float, r4: float) -> bool:
    """Grashof condition ``s + l < p + q``: at least one link fully rotates.

    Change-point linkages (``s + l = p + q``) are not Grashof here; see
    :func:`classify` for their class.

    Examples
    --------
    >>> is_grashof(8, 4, 7, 6)      # HW 6: 4 + 8 < 7 + 6
    True
    >>> is_grashof(6, 4, 3, 5)      # change point: 3 + 6 = 4 + 5
    False
    """
    return _condition(_lengths(r1, r2, r3, r4))[0] == "grashof"


def classify(r1: float, r2: float, r3: float, r4: float) -> Classification:
    """Classify a four-bar by Barker's table.

    Parameters
    ----------
    r1, r2, r3, r4 : float
        Ground, input, coupler and output lengths (positive).

    Returns
    -------
    Classification

    Raises
    ------
    AssemblyError
        If the four lengths cannot form a closed chain (``l >= s + p + q``).

    Examples
    --------
    The notes' HW 6 linkage and the final exam's {8, 4, 9, 6}:

    >>> classify(8, 4, 7, 6).code
    'GCRR'
    >>> c = classify(6, 9, 3, 8)     # HW 3: GRCR {6, 9, 3, 8}
    >>> c.code, c.number, c.cranks
    ('GRCR', 3, (3,))
    >>> classify(3, 5, 4, 7).code    # non-Grashof: 3 + 7 > 5 + 4, longest is the output
    'RRR4'
    >>> classify(2, 3, 2, 3).code    # parallelogram
    'CP2X'
    """
    lengths = _lengths(r1, r2, r3, r4)
    if not is_assemblable(*lengths):
        longest = max(lengths)
        raise AssemblyError(
            f"lengths {lengths} cannot be assembled: the longest link ({longest:g}) must be "
            f"shorter than the sum of the other three ({sum(lengths) - longest:g})"
        )
    condition, s, l = _condition(lengths)  # noqa: E741
    shortest = tuple(i + 1 for i, r in enumerate(lengths) if _equal(r, s, lengths))
    longest = tuple(i + 1 for i, r in enumerate(lengths) if _equal(r, l, lengths))

    if condition == "grashof":
        code = _GRASHOF[shortest[0] - 1]
    elif condition == "non-grashof":
        code = _NON_GRASHOF[longest[0] - 1]
    elif len(shortest) == 4:
        code = "CP3X"
    elif len(shortest) > 1 or len(longest) > 1:
        code = "CP2X"  # s + l = p + q with a tie: two equal pairs
    else:
        code = _CHANGE_POINT[shortest[0] - 1]

    # A link rotates fully relative to the ground when it, or the ground, is a
    # shortest link of a Grashof or change-point chain (Norton sec. 2.12).
    if condition == "non-grashof":
        cranks: tuple[int, ...] = ()
    elif 1 in shortest:
        cranks = (2, 3, 4)
    else:
        cranks = tuple(k for k in (2, 3, 4) if k in shortest)

    number, name = BARKER_CLASSES[code]
    return Classification(code, number, name, condition, s, l, shortest, longest, cranks)


def barker_class(r1: float, r2: float, r3: float, r4: float) -> str:
    """Barker's class code (``"GCCC"`` … ``"CP3X"``) of a four-bar.

    Examples
    --------
    >>> barker_class(8, 4, 9, 6)
    'GCRR'
    """
    return classify(r1, r2, r3, r4).code


class FourBarLoop(NamedTuple):
    """A four-bar loop of a drawn linkage: unpacks as ``(links, lengths, classification)``.

    ``links`` are ``(ground, input, coupler, output)`` and ``lengths`` the
    drawn ``(R1, R2, R3, R4)``: ground pivot to ground pivot, input, coupler,
    output.
    """

    links: tuple[str, str, str, str]
    lengths: tuple[float, float, float, float]
    classification: Classification


def fourbar_loops(lk: Any) -> tuple[FourBarLoop, ...]:
    """The four-bar loops of a drawn :class:`~machdyn.linkage.Linkage`, each classified.

    A four-bar loop is a ground-pivoted link, a coupler pinned to it, and a
    second ground-pivoted link pinned to the coupler: four links joined in a
    ring by four distinct pins (a Watt six-bar has two). The input is the loop's
    driven link when it has one (else the first defined); lengths are read off
    the drawing and classified by Barker's table (:func:`classify`).

    Examples
    --------
    >>> from machdyn.linkage import Linkage
    >>> lk = (Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0), "B": (7.625, 35.859375**0.5)})
    ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
    ...       .link("rocker", "O4", "B").drive("crank"))
    >>> [(loop.links, loop.classification.code) for loop in fourbar_loops(lk)]
    [(('ground', 'crank', 'coupler', 'rocker'), 'GCRR')]
    """
    from .linkage import Linkage

    if not isinstance(lk, Linkage):
        raise InputError("lk", f"must be a machdyn.linkage.Linkage, got {lk!r}")
    pins: dict[str, list[tuple[str, str]]] = {}  # link -> [(other link, pin point)]
    for joint in lk.joints:
        if joint.kind != "pin":
            continue
        for a, b in combinations(joint.links, 2):
            pins.setdefault(a, []).append((b, joint.points[0]))
            pins.setdefault(b, []).append((a, joint.points[0]))
    ground, drivers = "ground", set(lk.drivers)
    order = {n: k for k, n in enumerate(lk.links)}
    found: dict[frozenset, FourBarLoop] = {}
    for crank, o2 in pins.get(ground, []):
        for coupler, a in pins.get(crank, []):
            if coupler in (ground, crank) or a == o2:
                continue
            for rocker, b in pins.get(coupler, []):
                if rocker in (ground, crank, coupler) or b in (a, o2):
                    continue
                for other, o4 in pins.get(rocker, []):
                    if other != ground or o4 in (o2, a, b):
                        continue
                    key = frozenset((crank, coupler, rocker, o2, a, b, o4))
                    if crank not in drivers and (rocker in drivers or order[rocker] < order[crank]):
                        continue  # the same loop is met from its other ground link
                    if key in found:
                        continue
                    p = lk.points
                    lengths = tuple(
                        float(abs(p[u] - p[v])) for u, v in ((o2, o4), (o2, a), (a, b), (o4, b))
                    )
                    found[key] = FourBarLoop(
                        (ground, crank, coupler, rocker), lengths, classify(*lengths)
                    )
    return tuple(found.values())
