"""Critical path motion: the follower's displacement given as a table of points.

The notes distinguish two kinds of motion constraint: *critical extreme
position* (only the ends of a rise are specified — the laws of
:mod:`machdyn.cams.laws`) and *critical path motion* (CPM): "follower
displacement is specified throughout the motion (full-blown function
generator)", with the finite-jerk requirement "acceleration must be
continuous". Here the path is a table of ``(θ, s)`` points over one turn, and
the motion is the periodic B-spline of a chosen degree through them (or, with
``smoothing``, near them), as Norton's *Design of Machinery* (Ch. 8, spline
functions for CPM) recommends: a spline of degree ``k`` has ``k − 1``
continuous derivatives everywhere, so degree 3 already gives a continuous
acceleration and degree ≥ 4 a continuous jerk; periodicity makes the joint at
360° → 0° as smooth as any other.

The fit is scipy's: ``make_interp_spline(..., bc_type="periodic")`` through
the points, or FITPACK's periodic smoothing spline (``splrep(per=True)``) when
``smoothing`` (the RMS deviation allowed) is positive.

A :class:`CriticalPathMotion` answers like a :class:`~machdyn.cams.CamProgram`
(``svaj``, ``sample``, ``continuity``), so every follower's ``profile()``, the
sizing functions and the plots accept it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import count, finite_array, integer, nonnegative
from ..errors import InputError
from .program import ContinuityReport, Discontinuity, Motion

__all__ = ["CriticalPathMotion"]

_TWO_PI = 2.0 * np.pi
_FULL_TURN_TOL = 1e-6  # radians, as CamProgram: tables are often typed in degrees
_PERIODIC_RTOL = 1e-9  # s at the end of a full-turn table vs at its start
_MAX_SMOOTHING_DEGREE = 5  # FITPACK


class CriticalPathMotion:
    """Follower motion through a table of ``(θ, s)`` points: a periodic B-spline.

    Parameters
    ----------
    theta : array_like
        Cam angles of the points, radians, strictly increasing, spanning at most
        one turn. If the last angle is the first plus 2π, its ``s`` must equal
        the first (the table closes); otherwise the spline closes the gap
        smoothly.
    s : array_like
        Follower displacement at each angle (any length unit; radians for an
        oscillating follower).
    degree : int
        Degree of the spline, 3 to 7 (its order, in de Boor's sense, is
        ``degree + 1``). 3 gives a continuous acceleration, ≥ 4 a continuous
        jerk too. Default 5.
    smoothing : float
        0 (default) passes through every point. A positive value is the RMS
        deviation from the points allowed (met to FITPACK's 0.1 % on the sum
        of squares), traded for a smoother curve (degree ≤ 5).

    Raises
    ------
    InputError
        Angles not strictly increasing or spanning more than a turn, a
        full-turn table whose end does not return to its start (not periodic),
        too few points for the degree, or a bad degree or smoothing.

    Examples
    --------
    A follower that must pass through six positions (degrees for readability):

    >>> deg = np.radians
    >>> cpm = CriticalPathMotion(deg([0, 60, 120, 180, 240, 300]), [0, 0.4, 1.0, 1.0, 0.5, 0.1])
    >>> m = cpm.svaj(deg([60, 120]))
    >>> np.round(m.s, 12).tolist()
    [0.4, 1.0]
    >>> cpm.continuity().ok          # s, v, a continuous everywhere, 360° → 0° included
    True
    """

    def __init__(self, theta: Any, s: Any, degree: int = 5, smoothing: float = 0.0) -> None:
        theta = finite_array("theta", theta, "radian")
        s = finite_array("s", s)
        if theta.ndim != 1 or s.ndim != 1:
            raise InputError("theta", "the table is two 1-D arrays of equal length: theta and s")
        if theta.size != s.size:
            raise InputError("s", f"needs one value per angle ({theta.size}), got {s.size}")
        self.degree = integer("degree", degree)
        if not 3 <= self.degree <= 7:
            raise InputError(
                "degree",
                f"must be 3 to 7, got {self.degree}: a continuous acceleration (finite jerk, "
                "the notes' rule) needs a spline of degree 3 or more",
            )
        self.smoothing = nonnegative("smoothing", smoothing)
        if self.smoothing > 0.0 and self.degree > _MAX_SMOOTHING_DEGREE:
            raise InputError(
                "smoothing", f"a smoothing spline has degree at most 5, got degree {self.degree}"
            )
        theta, s = _check_table(theta, s, self.degree)
        self.theta, self.s = theta, s
        self.spline = _fit(theta, s, self.degree, self.smoothing)

    @classmethod
    def from_degrees(
        cls, theta_deg: Any, s: Any, degree: int = 5, smoothing: float = 0.0
    ) -> CriticalPathMotion:
        """The same, with the table's angles in degrees.

        Examples
        --------
        >>> cpm = CriticalPathMotion.from_degrees([0, 90, 180, 270, 360], [0, 1, 2, 1, 0], 3)
        >>> len(cpm.theta), round(float(cpm.svaj(np.pi).s), 12)
        (4, 2.0)
        """
        return cls(np.radians(finite_array("theta", theta_deg)), s, degree, smoothing)

    def __repr__(self) -> str:
        return (
            f"CriticalPathMotion({self.theta.size} points, degree {self.degree}, "
            f"smoothing {self.smoothing:g})"
        )

    @property
    def residual(self) -> float:
        """Largest |s_fit(θᵢ) − sᵢ| over the table (rounding only when not smoothing)."""
        return float(np.max(np.abs(self.spline(self.theta) - self.s)))

    def svaj(self, theta: Any) -> Motion:
        """s, v, a, j (per radian of cam angle) at ``theta`` (radians, wrapped to [0, 2π))."""
        theta = finite_array("theta", theta, "radian")
        wrapped = np.mod(theta, _TWO_PI)
        wrapped = np.where(wrapped >= _TWO_PI, 0.0, wrapped)
        values = [self.spline(wrapped, nu) for nu in range(4)]
        return Motion(wrapped, *values)

    def sample(self, n: int = 3600) -> Motion:
        """The motion at ``n`` equally spaced angles θ = 2πk/n."""
        n = count("n", n, minimum=4, bytes_each=48, what="samples")
        return self.svaj(np.arange(n) * (_TWO_PI / n))

    def continuity(self, rtol: float = 1e-9) -> ContinuityReport:
        """Every jump of s, v or a at a knot of the spline (360° → 0° included).

        Measured on the spline's polynomial pieces (left limit of one piece
        against the right limit of the next), not assumed from its degree. The
        report's notes say whether the jerk is continuous too.

        Examples
        --------
        >>> cpm = CriticalPathMotion.from_degrees([0, 90, 180, 270], [0, 1, 2, 1], degree=3)
        >>> report = cpm.continuity()
        >>> report.ok, report.notes[0][:34]
        (True, 'degree 3: the jerk jumps at knots ')
        """
        rtol = nonnegative("rtol", rtol)
        from scipy.interpolate import PPoly

        pieces = PPoly.from_spline(self.spline)
        breaks = pieces.x
        lo, hi = self.theta[0], self.theta[0] + _TWO_PI
        inside = np.unique(breaks[(breaks > lo + 1e-12) & (breaks < hi - 1e-12)])
        knots = np.concatenate(([lo], inside))
        found: list[Discontinuity] = []
        for order, name in enumerate(("s", "v", "a")):
            left = self._limit(pieces, knots, order, side=-1)
            right = self._limit(pieces, knots, order, side=+1)
            scale = np.maximum(np.abs(left), np.abs(right))
            jump = right - left
            for x, dj, sc in zip(knots, jump, scale, strict=True):
                if abs(dj) > max(rtol * sc, 1e-12):
                    where = "360° → 0°" if x == lo else "knot of the spline"
                    found.append(Discontinuity(float(np.mod(x, _TWO_PI)), name, float(dj), where))
        found.sort(key=lambda d: d.theta)
        note = (
            f"degree {self.degree}: the jerk jumps at knots (finite), as for a cubic spline"
            if self.degree == 3
            else f"degree {self.degree}: the jerk is continuous too"
        )
        return ContinuityReport(tuple(found), (note,))

    @staticmethod
    def _limit(pieces: Any, knots: np.ndarray, order: int, side: int) -> np.ndarray:
        """One-sided limits (side −1 left, +1 right) of a derivative at ``knots``.

        The left limit at the first knot θ0 is taken at θ0 + 2π, the end of the
        turn, so the comparison there is the joint 360° → 0°.
        """
        poly = pieces.derivative(order) if order else pieces
        at = knots.copy()
        if side < 0:
            at[0] += _TWO_PI
        k = np.searchsorted(poly.x, at, side="left" if side < 0 else "right") - 1
        k = np.clip(k, 0, poly.c.shape[1] - 1)
        dx = at - poly.x[k]
        value = np.zeros(at.size)
        for row in poly.c[:, k]:  # Horner over the pieces' local power series
            value = value * dx + row
        return value


def _check_table(theta: np.ndarray, s: np.ndarray, degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Strictly increasing angles within one turn; a full-turn table must close."""
    steps = np.diff(theta)
    if np.any(steps <= 0.0):
        i = int(np.flatnonzero(steps <= 0.0)[0]) + 1
        raise InputError(
            "theta",
            f"the table's angles must increase strictly (monotonic in angle): point {i} at "
            f"{np.degrees(theta[i]):.6g}° does not come after point {i - 1} at "
            f"{np.degrees(theta[i - 1]):.6g}°",
        )
    span = float(theta[-1] - theta[0]) if theta.size else 0.0
    if span > _TWO_PI + _FULL_TURN_TOL:
        raise InputError(
            "theta",
            f"the table spans {np.degrees(span):.6g}°, more than one turn: a cam repeats "
            "every 360°, so give one turn of points",
        )
    if span >= _TWO_PI - _FULL_TURN_TOL:
        tol = _PERIODIC_RTOL * max(float(np.max(np.abs(s))), 1e-300)
        if abs(s[-1] - s[0]) > tol:
            raise InputError(
                "s",
                f"not periodic: s = {s[-1]:.6g} at {np.degrees(theta[-1]):.6g}° but "
                f"{s[0]:.6g} at {np.degrees(theta[0]):.6g}° (one turn earlier); the follower "
                "must return to its start after one turn",
            )
        theta, s = theta[:-1], s[:-1]
    if theta.size < max(degree + 1, 4):
        raise InputError(
            "theta",
            f"a degree-{degree} spline needs at least {max(degree + 1, 4)} distinct points in "
            f"the turn, got {theta.size}",
        )
    return theta, s


def _fit(theta: np.ndarray, s: np.ndarray, degree: int, smoothing: float) -> Any:
    """The periodic B-spline (extrapolating periodically) through or near the points."""
    from scipy.interpolate import BSpline, make_interp_spline, splrep

    x = np.append(theta, theta[0] + _TWO_PI)
    y = np.append(s, s[0])
    if smoothing == 0.0:
        return make_interp_spline(x, y, k=degree, bc_type="periodic")
    t, c, k = splrep(x, y, k=degree, s=theta.size * smoothing**2, per=True)
    return BSpline(t, c, k, extrapolate="periodic")
