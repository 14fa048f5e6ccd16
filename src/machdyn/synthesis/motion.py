"""Motion generation: four-bars that carry a coupler line through two or three positions.

The notes' Ch. 3 and Norton, *Design of Machinery*, sec. 3.4–3.6:

* **two positions** — the fixed pivots lie anywhere on the perpendicular
  bisectors of ``A1A2`` and ``B1B2`` (:func:`two_position`); or one link
  pivoted at the rotopole carries ``C1D1`` to ``C2D2`` (:func:`rotopole_link`);
  a driving dyad then turns the rocker into a crank-rocker with the required
  swing (:func:`driving_dyad`);
* **three positions** — the fixed pivots are the intersections of the two
  bisectors of each moving pivot's three positions (:func:`three_position`);
* **three positions with the fixed pivots given** — by inversion: the ground
  is carried into the coupler's frame of a reference position and the moving
  pivots are the centres of the circles through the inverted fixed pivots
  (:func:`three_position_fixed_pivots`, Norton Ex. 3-7).

Every result is checked (:class:`MotionSynthesis`): can link 2, turning one
way, carry the coupler through the positions in order, on one circuit, without
passing a toggle? Circuit, branch and order defects are reported in
``defects`` (and ``strict=True`` raises them) rather than handing back a
mechanism that cannot do the job.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .._angles import TWO_PI
from .._validate import boolean, choice, finite_scalar, positive
from ..classify import classify
from ..errors import AssemblyError, InputError
from ..fourbar import positions
from .geometry import as_points, circumcentre, perpendicular_bisector, rigid_motion, rotopole
from .placed import PlacedFourBar

__all__ = [
    "DrivingDyad",
    "MotionSynthesis",
    "RotopoleLink",
    "driving_dyad",
    "rotopole_link",
    "three_position",
    "three_position_fixed_pivots",
    "two_position",
]

#: |sin φ12| below this at a precision position counts as a toggle.
_TOGGLE_SIN = 1e-6
#: Samples per radian of input travel when scanning the motion between positions.
_SCAN_DENSITY = 200


@dataclass(frozen=True, eq=False)
class MotionSynthesis:
    """A four-bar synthesised for motion generation, with the check of its motion.

    Attributes
    ----------
    O2, O4 : complex
        Fixed pivots (global).
    r1, r2, r3, r4 : float
        Ground ``O2O4``, input ``O2A``, coupler ``AB``, output ``O4B``.
    linkage : PlacedFourBar
        The linkage placed in the plane; its coupler point is ``C``.
    A, B : ndarray of complex
        Moving pivots at each precision position (global).
    theta2 : ndarray
        Local input angle (from the ground line ``O2O4``) at each position, radians.
    branch : ndarray of int
        Sign of φ12 at each position.
    direction : int
        +1 if link 2 turns counter-clockwise from position 1 to the last, −1 if clockwise
        (0 when the positions cannot be reached in one sweep).
    mu_min : float
        Smallest transmission angle met between the first and last positions
        (radians; NaN when they are not connected by one sweep).
    defects : tuple of str
        Why the linkage cannot do the job (empty when it can).
    inverted_O2, inverted_O4 : ndarray of complex or None
        For the inverted problem: the fixed pivots carried into the coupler
        frame of the reference position (the notes' O2, O2', O2'').
    """

    O2: complex
    O4: complex
    r1: float
    r2: float
    r3: float
    r4: float
    linkage: PlacedFourBar
    A: np.ndarray
    B: np.ndarray
    theta2: np.ndarray
    branch: np.ndarray
    direction: int
    mu_min: float
    defects: tuple[str, ...]
    inverted_O2: np.ndarray | None = None
    inverted_O4: np.ndarray | None = None

    @property
    def ok(self) -> bool:
        """True when link 2 carries the coupler through every position in order."""
        return not self.defects

    @property
    def fourbar(self):
        """The :class:`~machdyn.fourbar.FourBar` in its own frame."""
        return self.linkage.fourbar

    @property
    def theta1(self) -> float:
        """Ground angle of ``O2 → O4`` from global +x, radians."""
        return self.linkage.theta1

    def require_ok(self) -> MotionSynthesis:
        """Return self, or raise :class:`~machdyn.errors.AssemblyError` listing the defects."""
        if self.defects:
            raise AssemblyError(
                "the synthesised linkage cannot do the job: " + "; ".join(self.defects)
            )
        return self

    def driving_dyad(self, distance: float) -> DrivingDyad:
        """A crank-rocker whose rocker is link 2, swinging it from ``A[0]`` to ``A[-1]``.

        See :func:`driving_dyad`; ``distance`` is from ``A[0]`` to the crank pivot.
        """
        return driving_dyad(self.O2, self.A[0], self.A[-1], distance=distance)

    def plot(self, ax=None):
        """Draw the linkage in each precision position (matplotlib imported lazily).

        Returns the axes.
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        for k in range(self.A.size):
            chain = np.array([self.O2, self.A[k], self.B[k], self.O4])
            ax.plot(chain.real, chain.imag, "-o", lw=1.2, ms=3, label=f"position {k + 1}")
        ground = np.array([self.O2, self.O4])
        ax.plot(ground.real, ground.imag, "k^", ms=8, label="fixed pivots")
        ax.set_aspect("equal")
        ax.legend()
        return ax

    def to_pandas(self, degrees: bool = False):
        """One row per precision position (pandas imported lazily)."""
        import pandas as pd

        from ..units import columns, units_of

        theta2 = np.degrees(self.theta2) if boolean("degrees", degrees) else self.theta2
        system = units_of(self)
        if system is not None:  # a machine file's task: "A_x [mm]", "theta2 [deg]"
            spec = [(f"{p}_{c}", "length", getattr(getattr(self, p), a)) for p in "AB"
                    for c, a in (("x", "real"), ("y", "imag"))]  # fmt: skip
            spec += [("theta2", "angle", self.theta2), ("branch", None, self.branch)]
            return pd.DataFrame(columns(system, spec, degrees=degrees))
        return pd.DataFrame(
            {
                "A_x": self.A.real,
                "A_y": self.A.imag,
                "B_x": self.B.real,
                "B_y": self.B.imag,
                "theta2_deg" if degrees else "theta2": theta2,
                "branch": self.branch,
            }
        )


# --------------------------------------------------------------------------------------
# constructions


def _positions(c: Any, d: Any, count: int) -> tuple[np.ndarray, np.ndarray]:
    c = as_points("c", c, count)
    d = as_points("d", d, count)
    for k in range(1, count):
        rigid_motion(c[0], d[0], c[k], d[k])  # checks C ≠ D and a rigid |CD|
    return c, d


def _carry(c: np.ndarray, d: np.ndarray, point: complex, frm: int) -> np.ndarray:
    """Positions of a point fixed to the coupler, given where it is in position ``frm``."""
    out = np.empty(c.size, dtype=complex)
    for k in range(c.size):
        rot, shift = rigid_motion(c[frm], d[frm], c[k], d[k])
        out[k] = rot * point + shift
    return out


def _centre(points: np.ndarray, field: str) -> complex:
    try:
        return complex(circumcentre(*points))
    except InputError as exc:
        raise InputError(field, exc.message) from None


def three_position(
    c: Any, d: Any, *, A: Any = None, B: Any = None, strict: bool = False
) -> MotionSynthesis:
    """Four-bar that carries the coupler line CD through three positions.

    The moving pivots are ``C`` and ``D`` themselves (or points ``A``, ``B``
    fixed to the coupler, given in position 1); the fixed pivots are the
    intersections of the perpendicular bisectors of ``A1A2`` and ``A2A3``
    (``O2``), and of ``B1B2`` and ``B2B3`` (``O4``): the notes' "use ⊥
    bisectors of both C1C2, C2C3 and intersect them".

    Parameters
    ----------
    c, d : sequence of 3 complex (or (x, y) pairs)
        The three positions of points C and D of the coupler.
    A, B : complex, optional
        Moving pivots on the coupler, in position 1 (default ``C1`` and ``D1``).
    strict : bool
        Raise :class:`~machdyn.errors.AssemblyError` when the result has a
        circuit, branch or order defect, instead of reporting it.

    Returns
    -------
    MotionSynthesis

    Raises
    ------
    InputError
        Coincident or collinear positions (no circle through them), or a
        coupler line whose length changes between positions.

    Examples
    --------
    The notes' three-position table (C pivot and link 2 as printed):

    >>> c = [0 + 5.086j, 2.019 + 3.181j, 3.933 + 4.051j]
    >>> d = [0.741 + 2.703j, 4.428 + 2.529j, 6.304 + 4.83j]
    >>> s = three_position(c, d)
    >>> print(f"O2 = ({s.O2.real:.3f}, {s.O2.imag:.3f}), r2 = {s.r2:.3f}")
    O2 = (2.178, 5.372), r2 = 2.197
    >>> print(f"O4 = ({s.O4.real:.3f}, {s.O4.imag:.3f}), r4 = {s.r4:.3f}")
    O4 = (2.736, 5.824), r4 = 3.704
    """
    c, d = _positions(c, d, 3)
    a = c if A is None else _carry(c, d, as_points("A", A, 1)[0], 0)
    b = d if B is None else _carry(c, d, as_points("B", B, 1)[0], 0)
    O2 = _centre(a, "c" if A is None else "A")
    O4 = _centre(b, "d" if B is None else "B")
    return _finish(O2, O4, a, b, c, strict)


def three_position_fixed_pivots(
    c: Any, d: Any, O2: Any, O4: Any, *, reference: int = 0, strict: bool = False
) -> MotionSynthesis:
    """Three-position synthesis with the fixed pivots given: moving pivots by inversion.

    Invert the linkage on the coupler: hold the coupler in position
    ``reference`` and carry the ground with it into the other two positions,
    i.e. map ``O2`` by the rigid motion taking ``C_k D_k`` onto
    ``C_ref D_ref`` (Norton Ex. 3-7; the notes' O2, O2', O2''). In that frame
    ``O2`` moves on a circle about the moving pivot ``A``, so ``A`` (in the
    reference position) is the centre of the circle through the three
    inverted ``O2``; likewise ``B`` from ``O4``.

    Parameters
    ----------
    c, d : sequence of 3 complex
        Three positions of the coupler line CD.
    O2, O4 : complex or (x, y)
        The required fixed pivots.
    reference : {0, 1, 2}
        Position in which the moving pivots are found (the notes use the second, 1).
    strict : bool
        Raise on a circuit, branch or order defect.

    Returns
    -------
    MotionSynthesis
        ``inverted_O2`` and ``inverted_O4`` hold the inverted pivots.

    Examples
    --------
    Round trip on exact positions: the crank and rocker pins of the notes' HW 6
    linkage (8, 4, 7, 6) at θ2 = 20°, 70°, 130°; its pivots give them back.

    >>> from machdyn.fourbar import FourBar
    >>> m = FourBar(8, 4, 7, 6).solve(np.radians([20, 70, 130]))
    >>> inv = three_position_fixed_pivots(m.A, m.B, O2=0, O4=8)
    >>> bool(np.allclose(inv.A, m.A)), bool(np.allclose(inv.B, m.B)), inv.ok
    (True, True, True)
    """
    c, d = _positions(c, d, 3)
    reference = choice("reference", reference, (0, 1, 2))
    O2 = as_points("O2", O2, 1)[0]
    O4 = as_points("O4", O4, 1)[0]
    if abs(O2 - O4) <= 1e-12 * max(abs(O2), 1.0):
        raise InputError("O4", "coincides with O2; the ground link needs two distinct pivots")
    inv2 = np.empty(3, dtype=complex)
    inv4 = np.empty(3, dtype=complex)
    for k in range(3):
        rot, shift = rigid_motion(c[k], d[k], c[reference], d[reference])
        inv2[k] = rot * O2 + shift
        inv4[k] = rot * O4 + shift
    a_ref = _centre(inv2, "O2")
    b_ref = _centre(inv4, "O4")
    a = _carry(c, d, a_ref, reference)
    b = _carry(c, d, b_ref, reference)
    result = _finish(O2, O4, a, b, c, strict)
    return replace(result, inverted_O2=inv2, inverted_O4=inv4)


def two_position(
    c: Any,
    d: Any,
    *,
    s2: float,
    s4: float,
    A: Any = None,
    B: Any = None,
    strict: bool = False,
) -> MotionSynthesis:
    """Four-bar that carries the coupler line CD between two positions.

    Any fixed pivot on the perpendicular bisector of ``A1A2`` (and of
    ``B1B2``) works (the notes: "using links along the ⊥ bisectors of lines
    C1C2 and D1D2 will give the desired motion"); ``s2`` and ``s4`` choose
    them as signed distances from the bisectors' midpoints, positive to the
    left of ``A1 → A2`` (``B1 → B2``).

    Parameters
    ----------
    c, d : sequence of 2 complex
        The two positions of points C and D.
    s2, s4 : float
        Positions of ``O2`` and ``O4`` along the bisectors.
    A, B : complex, optional
        Moving pivots on the coupler, in position 1 (default ``C1``, ``D1``).
    strict : bool
        Raise on a circuit or branch defect.

    Examples
    --------
    >>> s = two_position([0, 2], [1j, 2 + 1j], s2=3, s4=3)
    >>> complex(s.O2), complex(s.O4)
    ((1+3j), (1+4j))
    """
    c, d = _positions(c, d, 2)
    s2 = finite_scalar("s2", s2)
    s4 = finite_scalar("s4", s4)
    a = c if A is None else _carry(c, d, as_points("A", A, 1)[0], 0)
    b = d if B is None else _carry(c, d, as_points("B", B, 1)[0], 0)
    try:
        ma, ua = perpendicular_bisector(a[0], a[1])
    except InputError as exc:
        raise InputError("c" if A is None else "A", exc.message) from None
    try:
        mb, ub = perpendicular_bisector(b[0], b[1])
    except InputError as exc:
        raise InputError("d" if B is None else "B", exc.message) from None
    O2 = complex(ma + s2 * ua)
    O4 = complex(mb + s4 * ub)
    return _finish(O2, O4, a, b, c, strict)


# --------------------------------------------------------------------------------------
# the check of the motion


def _finish(
    O2: complex, O4: complex, a: np.ndarray, b: np.ndarray, c: np.ndarray, strict: bool
) -> MotionSynthesis:
    strict = boolean("strict", strict)
    if abs(O2 - O4) <= 1e-9 * max(abs(O2), abs(O4), 1.0):
        raise AssemblyError("the two fixed pivots coincide; choose other moving pivots")
    linkage = PlacedFourBar.from_pivots(O2, O4, a[0], b[0], P=c[0])
    theta2, branch, direction, mu_min, defects = _check(linkage, a, b)
    r1, r2, r3, r4 = linkage.lengths
    result = MotionSynthesis(
        O2=complex(O2),
        O4=complex(linkage.O4),
        r1=r1,
        r2=r2,
        r3=r3,
        r4=r4,
        linkage=linkage,
        A=a,
        B=b,
        theta2=theta2,
        branch=branch,
        direction=direction,
        mu_min=mu_min,
        defects=tuple(defects),
    )
    if strict:
        result.require_ok()
    return result


def _check(
    linkage: PlacedFourBar, a: np.ndarray, b: np.ndarray
) -> tuple[np.ndarray, np.ndarray, int, float, list[str]]:
    """Check that link 2, turning one way, carries the coupler through the positions in order.

    Defects (Norton, ch. 3 and 5): a **circuit** defect when two positions
    lie on different circuits (no motion joins them without disassembly), a
    **branch** defect when they are joined only through a toggle of links 3
    and 4 (a dead point for the link-2 drive), an **order** defect when a
    rocking link 2 meets the positions out of order.
    """
    fb = linkage.fourbar
    r1, r2, r3, r4 = fb.lengths
    local_a = linkage.to_local(a)
    local_b = linkage.to_local(b)
    theta2 = np.mod(np.angle(local_a), TWO_PI)
    phi12 = np.angle((local_b - r1) / (local_b - local_a))  # θ4 − θ3
    sin12 = np.sin(phi12)
    branch = np.where(sin12 >= 0.0, 1, -1)
    defects: list[str] = []
    n = a.size
    for k in np.flatnonzero(np.abs(sin12) < _TOGGLE_SIN):
        defects.append(f"position {k + 1} is a toggle (links 3 and 4 collinear)")
    cls = classify(*fb.lengths)
    if cls.code in ("GRCR", "GRRC"):
        side = np.sin(theta2) >= 0.0
        if np.any(side != side[0]):
            defects.append(
                "circuit defect: link 2 rocks on one side of the ground line, and positions "
                f"{[k + 1 for k in range(n) if side[k] == side[0]]} and "
                f"{[k + 1 for k in range(n) if side[k] != side[0]]} are on opposite sides; "
                "the linkage would have to be taken apart to move between them"
            )
            return theta2, branch, 0, float("nan"), defects
    if np.any(branch != branch[0]):
        first = [k + 1 for k in range(n) if branch[k] == branch[0]]
        other = [k + 1 for k in range(n) if branch[k] != branch[0]]
        across = _circuits_differ(cls.code, cls.condition, theta2, branch)
        kind = "circuit" if across else "branch"
        how = (
            "the linkage would have to be taken apart to move between them"
            if across
            else "link 2 would have to pass a toggle of links 3 and 4 (a dead point)"
        )
        defects.append(
            f"{kind} defect: positions {first} and {other} are on opposite sides (phi12 signs "
            f"differ); {how}"
        )
        return theta2, branch, 0, float("nan"), defects

    rng = fb.input_range(1 if fb.form_rule == "phi12" else (1 if np.sin(theta2[0]) >= 0 else 2))
    if rng.full_turn:
        ccw = np.mod(theta2 - theta2[0], TWO_PI)
        if np.all(np.diff(ccw) > 0):
            direction, travel = 1, ccw[-1]
        else:
            cw = np.mod(theta2[0] - theta2, TWO_PI)
            cw[0] = 0.0
            direction, travel = -1, cw[-1]
            if not np.all(np.diff(cw) > 0):
                defects.append("order defect: link 2 meets the positions out of order")
                return theta2, branch, 0, float("nan"), defects
        path = theta2[0] + direction * np.linspace(0.0, travel, _samples(travel))
    else:
        t = rng.lo + np.mod(theta2 - rng.lo, TWO_PI)
        steps = np.diff(t)
        if np.all(steps > 0):
            direction = 1
        elif np.all(steps < 0):
            direction = -1
        else:
            angles = ", ".join(f"{v:.2f}" for v in np.degrees(t))
            defects.append(
                f"order defect: link 2 rocks, and its angles at the positions ({angles} deg) do "
                "not run one way; it would have to reverse, meeting the positions out of order"
            )
            return theta2, branch, 0, float("nan"), defects
        path = np.linspace(t[0], t[-1], _samples(abs(t[-1] - t[0])))
    th3, th4, ok = positions(r1, r2, r3, r4, path, int(branch[0]))
    if not np.all(ok):
        defects.append("branch defect: the linkage cannot be assembled between the positions")
        return theta2, branch, 0, float("nan"), defects
    m = np.abs(np.sin(th4 - th3))
    mu_min = float(np.arcsin(np.clip(np.min(m), 0.0, 1.0)))
    return theta2, branch, direction, mu_min, defects


def _samples(travel: float) -> int:
    return max(16, int(np.ceil(_SCAN_DENSITY * travel)))


def _circuits_differ(code: str, condition: str, theta2: np.ndarray, branch: np.ndarray) -> bool:
    """True if positions with different φ12 signs lie on different circuits (not just branches)."""
    if condition != "grashof":
        return False  # one circuit; the branches meet at toggles (or change points)
    if code in ("GRCR", "GRRC"):
        # circuits are the sides of the ground line the input rocker swings on (sign of φ34);
        # within one circuit the two φ12 branches meet at the input rocker's limits.
        side = np.sin(theta2) >= 0.0
        return bool(np.any(side != side[0]))
    return True  # a Grashof chain with φ12 as its form: the two forms are the two circuits


# --------------------------------------------------------------------------------------
# rotopole and driving dyad


@dataclass(frozen=True)
class RotopoleLink:
    """One link, pivoted at the rotopole, that carries C1D1 to C2D2 by a rotation.

    Attributes
    ----------
    pole : complex
        The fixed pivot (the rotopole).
    rotation : float
        Rotation of the link from position 1 to position 2, radians in (−π, π].
    """

    pole: complex
    rotation: float


def rotopole_link(c: Any, d: Any) -> RotopoleLink:
    """The rotopole solution of two-position motion generation.

    A single link pivoted at the rotopole (the intersection of the bisectors of
    ``C1C2`` and ``D1D2``) and fixed to CD carries ``C1`` to ``C2`` and
    ``D1`` to ``D2`` (the notes, Ch. 3; Norton sec. 3.4).

    Raises
    ------
    InputError
        For a pure translation (no rotopole) or coincident C and D.

    Examples
    --------
    >>> link = rotopole_link([1, 1j], [2, 2j])
    >>> complex(link.pole), round(float(np.degrees(link.rotation)), 6)
    (0j, 90.0)
    """
    c, d = _positions(c, d, 2)
    pole = complex(rotopole(c[0], d[0], c[1], d[1]))
    rot, _ = rigid_motion(c[0], d[0], c[1], d[1])
    return RotopoleLink(pole, float(np.angle(rot)))


@dataclass(frozen=True)
class DrivingDyad:
    """A crank and coupler added to drive a rocker between two positions.

    Attributes
    ----------
    crank_pivot : complex
        Fixed pivot of the new crank.
    crank, coupler : float
        Lengths of the crank and of the coupler joining it to the rocker.
    swing : float
        Rocker swing, radians (positive, from ``b1`` to ``b2`` about the pivot).
    linkage : PlacedFourBar
        The crank-rocker: ground from the crank pivot to the rocker pivot.
    """

    crank_pivot: complex
    crank: float
    coupler: float
    swing: float
    linkage: PlacedFourBar


def driving_dyad(pivot: Any, b1: Any, b2: Any, *, distance: float) -> DrivingDyad:
    """A crank-rocker that swings a rocker (pivot, pin ``b1``) to pin position ``b2`` and back.

    The crank pivot lies on the line ``b2 → b1`` extended beyond ``b1``, at
    ``distance`` from ``b1``. At the two toggles the crank and coupler are
    folded (pin at ``b1``) and extended (pin at ``b2``), so the crank is half
    of ``|b1b2|`` and the coupler is ``distance`` plus the crank (Norton
    sec. 3.4). Both strokes then take half a turn of the crank (time ratio 1).

    Raises
    ------
    InputError
        If ``b1`` and ``b2`` are not at the same distance from the pivot, or
        ``distance`` is too small for the result to be a Grashof crank-rocker.

    Examples
    --------
    >>> dy = driving_dyad(0, 1, 1j, distance=2.0)
    >>> print(f"{dy.crank:.6f} {dy.coupler:.6f}", dy.linkage.fourbar.barker_class)
    0.707107 2.707107 GCRR
    """
    pivot = as_points("pivot", pivot, 1)[0]
    b1 = as_points("b1", b1, 1)[0]
    b2 = as_points("b2", b2, 1)[0]
    distance = positive("distance", distance)
    if distance <= 0.0:
        raise InputError("distance", f"must be a positive distance from b1, got {distance!r}")
    r4, r4b = abs(b1 - pivot), abs(b2 - pivot)
    if r4 == 0.0 or abs(r4 - r4b) > 1e-6 * r4:
        raise InputError("b2", "must be at the same distance from the pivot as b1 (one rocker)")
    chord = b2 - b1
    if abs(chord) <= 1e-12 * r4:
        raise InputError("b2", "coincides with b1; the rocker needs a swing")
    crank = 0.5 * abs(chord)
    coupler = distance + crank
    o6 = b1 - distance * chord / abs(chord)
    # folded toggle with the pin at b1: the crank points from O away from b1
    A = o6 - crank * chord / abs(chord)
    try:
        placed = PlacedFourBar.from_pivots(o6, pivot, A, b1)
    except InputError:
        raise InputError(
            "distance", "puts the crank pivot on the rocker pivot; choose another distance"
        ) from None
    if 2 not in placed.fourbar.cranks or placed.fourbar.barker_class != "GCRR":
        raise InputError(
            "distance",
            f"gives a {placed.fourbar.barker_class}, not a Grashof crank-rocker; "
            "place the crank pivot farther from the rocker",
        )
    swing = abs(float(np.angle((b2 - pivot) / (b1 - pivot))))
    return DrivingDyad(complex(o6), crank, coupler, swing, placed)
