"""Cam programs: ordered segments covering one turn, their svaj and continuity.

A program is a list of :class:`Segment` (rise, fall or dwell, each with a law,
a lift ``h`` and an angle ``β`` in radians) whose angles sum to 2π. It is
sampled over cam angle θ (radians) as s, v, a, j per radian, or in time units
for a cam speed ω (``V = ωv``, ``A = ω²a``, ``J = ω³j``; notes Ch. 8).

The continuity check applies the notes' rule for dwell cams ("finite jerk
requirement: acceleration must be continuous"): it lists every boundary
(including 360° → 0°) where s, v or a jumps, and every law with a jump inside.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._summary import Summarized
from .._validate import choice, count, finite_array, items, nonnegative, positive
from ..errors import InputError
from ..units import warn_if_degrees
from .laws import LawValues, MotionLaw, PolynomialLaw, get_law

__all__ = [
    "CamProgram",
    "ContinuityReport",
    "Discontinuity",
    "Motion",
    "Segment",
    "TimeMotion",
]

MOTIONS = ("rise", "fall", "dwell")
_FULL_TURN_TOL = 1e-6  # radians; segment angles are often typed in degrees
_CLOSURE_RTOL = 1e-9  # net rise allowed, relative to the largest lift (rounding only)


def closure_message(rises: float, falls: float, unit: str = "") -> str:
    """Say that rises and falls (totals, both ≥ 0) do not cancel and what would close them.

    ``unit`` is appended to every number (e.g. ``"°"`` for a rocker whose lifts
    are typed in degrees). Used by :class:`CamProgram` and the CLI.

    Examples
    --------
    >>> closure_message(1.0, 0.6).split("; ")[0]
    'rises total 1, falls total 0.6 (net rise +0.4)'
    """
    return (
        f"rises total {rises:.6g}{unit}, falls total {falls:.6g}{unit} "
        f"(net rise {rises - falls:+.6g}{unit}); the follower must return to its start after "
        f"one turn: make the falls total {rises:.6g}{unit} or the rises total {falls:.6g}{unit}"
    )


@dataclass(frozen=True)
class Segment:
    """One segment of a cam program.

    Parameters
    ----------
    motion : {"rise", "fall", "dwell"}
    beta : float
        Segment angle β in radians (> 0).
    h : float
        Lift (≥ 0; ignored for a dwell). For an oscillating follower, an angle
        in radians.
    law : MotionLaw or str
        The motion law (a name from :data:`machdyn.cams.LAW_NAMES` or a law
        object such as :func:`machdyn.cams.polynomial_law`).

    Examples
    --------
    >>> seg = Segment("rise", np.radians(60), 1.0, "cycloidal")
    >>> seg.law.name
    'cycloidal'
    >>> Segment("rise", 0.0, 1.0, "cycloidal")
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: beta: must be positive, got 0.0
    """

    motion: str
    beta: float
    h: float = 0.0
    law: MotionLaw | str = "dwell"

    def __post_init__(self) -> None:
        motion = choice("motion", str(self.motion).lower(), MOTIONS)
        object.__setattr__(self, "motion", motion)
        object.__setattr__(self, "beta", positive("beta", self.beta, "radian"))
        law = self.law
        if motion == "dwell":
            law = get_law("dwell")
            h = 0.0
        else:
            if isinstance(law, str):
                law = get_law(law)
            if not isinstance(law, MotionLaw):
                raise InputError("law", f"must be a law name or MotionLaw, got {law!r}")
            if law.name == "dwell":
                raise InputError("law", f"a {motion} needs a moving law, not 'dwell'")
            h = nonnegative("h", self.h)
            if h == 0.0 and not isinstance(law, PolynomialLaw):
                raise InputError("h", f"a {motion} needs a positive lift, got 0.0")
        object.__setattr__(self, "law", law)
        object.__setattr__(self, "h", h)

    @property
    def signed_h(self) -> float:
        """Net change of s over the segment (negative for a fall)."""
        return -self.h if self.motion == "fall" else self.h

    def evaluate(self, x: Any) -> LawValues:
        """S (relative to the segment start), v, a, j at normalised angles x."""
        law = self.law
        assert isinstance(law, MotionLaw)
        return law(x, self.signed_h, self.beta)


@dataclass(frozen=True)
class Motion(Summarized):
    """Follower motion over cam angle: s and derivatives per radian.

    Attributes
    ----------
    theta : ndarray
        Cam angle θ in radians, in [0, 2π).
    s, v, a, j : ndarray
        Displacement and ``ds/dθ``, ``d²s/dθ²``, ``d³s/dθ³``.
    """

    theta: np.ndarray
    s: np.ndarray
    v: np.ndarray
    a: np.ndarray
    j: np.ndarray

    def in_time(self, omega: float) -> TimeMotion:
        """Return the same motion in time units for a cam speed ``omega`` (rad/s).

        Examples
        --------
        >>> program = CamProgram.double_dwell(1.0, np.radians(90), np.radians(90))
        >>> m = program.sample(8).in_time(omega=2.0)
        >>> float(m.V.max()) == 2.0 * float(program.sample(8).v.max())
        True
        """
        from ..units import units_of, with_units

        omega = positive("omega", omega, "radian / second")
        timed = TimeMotion(
            t=self.theta / omega,
            theta=self.theta,
            s=self.s,
            V=omega * self.v,
            A=omega**2 * self.a,
            J=omega**3 * self.j,
            omega=omega,
        )
        object.__setattr__(timed, "lift", getattr(self, "lift", "length"))
        return with_units(timed, units_of(self))

    def peaks(self) -> dict[str, float]:
        """Largest absolute s, v, a, j."""
        return {k: float(np.max(np.abs(getattr(self, k)))) for k in ("s", "v", "a", "j")}

    def to_pandas(self) -> Any:
        """Return a DataFrame with theta (rad), theta_deg, s, v, a, j.

        When the cam was given units (a machine file's cam) the columns say
        them instead: ``theta [deg]``, ``s [mm]``, ``v [mm/rad]``, ...
        """
        import pandas as pd

        from ..units import columns, units_of

        system = units_of(self)
        if system is not None:
            lift = getattr(self, "lift", "length")
            spec = [("theta", "angle", self.theta), ("s", lift, self.s)]
            spec += [("v", f"{lift}/rad", self.v), ("a", f"{lift}/rad^2", self.a)]
            spec += [("j", f"{lift}/rad^3", self.j)]
            return pd.DataFrame(columns(system, spec, degrees=True))
        return pd.DataFrame(
            {
                "theta": self.theta,
                "theta_deg": np.degrees(self.theta),
                "s": self.s,
                "v": self.v,
                "a": self.a,
                "j": self.j,
            }
        )

    def plot(self, **kwargs: Any) -> Any:
        """Svaj diagrams against θ in degrees (see :func:`machdyn.cams.plot_svaj`)."""
        from .plot import plot_svaj

        return plot_svaj(self, **kwargs)


@dataclass(frozen=True)
class TimeMotion(Summarized):
    """Follower motion in time units: ``V = ωv``, ``A = ω²a``, ``J = ω³j``."""

    t: np.ndarray
    theta: np.ndarray
    s: np.ndarray
    V: np.ndarray
    A: np.ndarray
    J: np.ndarray
    omega: float

    def peaks(self) -> dict[str, float]:
        """Largest absolute s, V, A, J."""
        return {k: float(np.max(np.abs(getattr(self, k)))) for k in ("s", "V", "A", "J")}

    def to_pandas(self) -> Any:
        """Return a DataFrame with t, theta (rad), theta_deg, s, V, A, J.

        When the cam was given units the columns say them instead:
        ``t [s]``, ``theta [deg]``, ``s [mm]``, ``V [mm/s]``, ...
        """
        import pandas as pd

        from ..units import columns, units_of

        system = units_of(self)
        if system is not None:
            lift = getattr(self, "lift", "length")
            rates = ("velocity", "acceleration", "jerk")
            if lift == "angle":
                rates = ("angular_velocity", "angular_acceleration", "angular_jerk")
            spec = [("t", "time", self.t), ("theta", "angle", self.theta), ("s", lift, self.s)]
            spec += [(n, k, getattr(self, n)) for n, k in zip("VAJ", rates, strict=True)]
            return pd.DataFrame(columns(system, spec, degrees=True))
        return pd.DataFrame(
            {
                "t": self.t,
                "theta": self.theta,
                "theta_deg": np.degrees(self.theta),
                "s": self.s,
                "V": self.V,
                "A": self.A,
                "J": self.J,
            }
        )


@dataclass(frozen=True)
class Discontinuity:
    """A jump of s, v or a at a cam angle (radians)."""

    theta: float
    quantity: str
    jump: float
    where: str

    def describe(self) -> str:
        """One line for reports, angle in degrees."""
        return (
            f"{self.quantity} jumps by {self.jump:+.6g} at θ = {np.degrees(self.theta):.4g}° "
            f"({self.where})"
        )


@dataclass(frozen=True)
class ContinuityReport:
    """Result of :meth:`CamProgram.continuity`.

    Attributes
    ----------
    discontinuities : tuple of Discontinuity
        Every jump in s, v or a found.
    notes : tuple of str
        Cautions from the laws used (e.g. constant velocity).
    """

    discontinuities: tuple[Discontinuity, ...]
    notes: tuple[str, ...] = field(default=())

    @property
    def ok(self) -> bool:
        """True when s, v and a are continuous everywhere (finite jerk)."""
        return not self.discontinuities

    @property
    def finite_jerk(self) -> bool:
        """True when the acceleration never jumps (the notes' requirement)."""
        return self.ok

    def lines(self) -> list[str]:
        """Human-readable report lines."""
        if self.ok:
            out = ["continuity: s, v, a continuous everywhere (finite jerk) - OK"]
        else:
            out = [f"continuity: {len(self.discontinuities)} jump(s) - FAILS the finite-jerk rule"]
            out += ["  " + d.describe() for d in self.discontinuities]
        out += ["  note: " + n for n in self.notes]
        return out


class CamProgram:
    """An ordered list of segments covering one turn of the cam.

    Parameters
    ----------
    segments : sequence of Segment
        Their β must sum to 2π (within 1e-6 rad), and the rises must cancel
        the falls: a cam turns through whole revolutions, so the follower has
        to be back at its start at 2π (a net rise would be a step in the cam
        outline). The start is the lowest position: s never goes below it.

    Examples
    --------
    Double-dwell: rise 1 over 60°, dwell 120°, fall over 60°, dwell 120°.

    >>> deg = np.radians
    >>> program = CamProgram([
    ...     Segment("rise", deg(60), 1.0, "cycloidal"),
    ...     Segment("dwell", deg(120)),
    ...     Segment("fall", deg(60), 1.0, "cycloidal"),
    ...     Segment("dwell", deg(120)),
    ... ])
    >>> program.continuity().ok
    True
    >>> m = program.sample(360)
    >>> round(m.peaks()["v"], 6)   # 2h/β
    1.909859
    """

    def __init__(self, segments: Sequence[Segment]) -> None:
        segments = items("segments", segments, what="Segments")
        if not segments:
            raise InputError("segments", "a cam program needs at least one segment")
        for i, seg in enumerate(segments):
            if not isinstance(seg, Segment):
                raise InputError(f"segments[{i}]", f"must be a Segment, got {seg!r}")
        total = sum(seg.beta for seg in segments)
        if abs(total - 2.0 * np.pi) > _FULL_TURN_TOL:
            raise InputError(
                "segments",
                f"segment angles must sum to 360°, they sum to {np.degrees(total):.6g}°",
            )
        rises = sum(seg.h for seg in segments if seg.motion == "rise")
        falls = sum(seg.h for seg in segments if seg.motion == "fall")
        tol = _CLOSURE_RTOL * max(seg.h for seg in segments)
        if abs(rises - falls) > tol:
            raise InputError("segments", closure_message(rises, falls))
        self.segments = segments
        betas = np.array([seg.beta for seg in segments])
        # Scale the angles so that they close exactly on 2π.
        self._starts = np.concatenate(([0.0], np.cumsum(betas)[:-1])) * (2.0 * np.pi / total)
        self._betas = betas * (2.0 * np.pi / total)
        self._levels = np.concatenate(([0.0], np.cumsum([seg.signed_h for seg in segments])))
        lowest = int(np.argmin(self._levels[:-1]))
        if self._levels[lowest] < -tol:
            # s is measured up from the prime (base) circle: a dip below the start
            # would put the cam inside the circles it reports.
            raise InputError(
                "segments",
                f"the follower drops below its start (lowest at θ = "
                f"{np.degrees(self._starts[lowest]):.6g}°, the start of segment {lowest + 1}); "
                f"s is measured up from the lowest position, so list the segments starting "
                f"with segment {lowest + 1}, keeping their order",
            )

    # Constructors ---------------------------------------------------------

    @classmethod
    def double_dwell(
        cls,
        h: float,
        beta_rise: float,
        beta_fall: float,
        law: MotionLaw | str = "cycloidal",
        dwell_high: float | None = None,
        fall_law: MotionLaw | str | None = None,
    ) -> CamProgram:
        """Rise–dwell–fall–dwell; the low dwell fills the turn.

        ``dwell_high`` defaults to half of what the rise and fall leave.

        Examples
        --------
        >>> p = CamProgram.double_dwell(1.0, np.pi / 3, np.pi / 3)
        >>> [s.motion for s in p.segments]
        ['rise', 'dwell', 'fall', 'dwell']
        """
        beta_rise = positive("beta_rise", beta_rise, "radian")
        beta_fall = positive("beta_fall", beta_fall, "radian")
        rest = 2.0 * np.pi - beta_rise - beta_fall
        high = rest / 2.0 if dwell_high is None else nonnegative("dwell_high", dwell_high, "radian")
        low = rest - high
        if high <= 0.0 or low <= 0.0:
            raise InputError("beta_rise", "rise and fall leave no room for both dwells")
        return cls(
            [
                Segment("rise", beta_rise, h, law),
                Segment("dwell", high),
                Segment("fall", beta_fall, h, law if fall_law is None else fall_law),
                Segment("dwell", low),
            ]
        )

    # Queries ----------------------------------------------------------------

    @property
    def starts(self) -> np.ndarray:
        """Start angle of each segment (radians)."""
        return self._starts.copy()

    @property
    def levels(self) -> np.ndarray:
        """Follower displacement at the start of each segment and at 2π."""
        return self._levels.copy()

    def svaj(self, theta: Any) -> Motion:
        """s, v, a, j at cam angles ``theta`` (radians, any shape, wrapped to [0, 2π)).

        At a boundary the value of the segment that starts there is returned.
        """
        theta = finite_array("theta", theta)
        warn_if_degrees("theta", theta)
        wrapped = np.mod(theta, 2.0 * np.pi)
        index = np.searchsorted(self._starts, wrapped, side="right") - 1
        s = np.empty_like(wrapped)
        v, a, j = np.empty_like(s), np.empty_like(s), np.empty_like(s)
        for k, seg in enumerate(self.segments):
            mask = index == k
            if not mask.any():
                continue
            x = (wrapped[mask] - self._starts[k]) / self._betas[k]
            values = seg.evaluate(np.clip(x, 0.0, 1.0))
            s[mask] = self._levels[k] + values.s
            v[mask], a[mask], j[mask] = values.v, values.a, values.j
        return Motion(wrapped, s, v, a, j)

    def sample(self, n: int = 3600) -> Motion:
        """Return the motion at ``n`` equally spaced angles θ = 2πk/n."""
        n = count("n", n, minimum=4, bytes_each=48, what="samples")
        return self.svaj(np.arange(n) * (2.0 * np.pi / n))

    def continuity(self, rtol: float = 1e-9) -> ContinuityReport:
        """Every jump of s, v or a at a segment boundary or inside a law.

        Parameters
        ----------
        rtol : float
            A jump counts when it exceeds ``rtol`` times the size of that
            quantity on the two segments that meet (the largest |s|, |v| or |a|
            over either segment, or of the two values compared), so that the
            round-off of a law's end values (a polynomial's a(1) ~ 1e-12) is not
            taken for a jump.

        Examples
        --------
        >>> p = CamProgram.double_dwell(1.0, np.pi / 3, np.pi / 3, law="shm")
        >>> [d.quantity for d in p.continuity().discontinuities]
        ['a', 'a', 'a', 'a']
        """
        rtol = nonnegative("rtol", rtol)
        found: list[Discontinuity] = []
        notes: list[str] = []
        n = len(self.segments)
        ends = [seg.evaluate(np.array([0.0, 1.0])) for seg in self.segments]
        # The size of s, v and a on each segment: what a jump is measured against.
        grid = np.linspace(0.0, 1.0, 65)
        sizes = []
        for k, seg in enumerate(self.segments):
            values = seg.evaluate(grid)
            sizes.append(
                {
                    "s": float(np.max(np.abs(self._levels[k] + values.s))),
                    "v": float(np.max(np.abs(values.v))),
                    "a": float(np.max(np.abs(values.a))),
                }
            )
        for k in range(n):
            nxt = (k + 1) % n
            before, after = ends[k], ends[nxt]
            theta = float(self._starts[nxt])
            # At the wrap (nxt = 0) the program must be back at level 0.
            s_before = self._levels[k] + before.s[1]
            s_after = self._levels[nxt] + after.s[0]
            pairs = (
                ("s", s_before, s_after),
                ("v", before.v[1], after.v[0]),
                ("a", before.a[1], after.a[0]),
            )
            where = (
                f"end of segment {k + 1} ({self.segments[k].motion}) → start of segment {nxt + 1}"
            )
            for name, left, right in pairs:
                jump = float(right - left)
                scale = max(abs(float(left)), abs(float(right)), sizes[k][name], sizes[nxt][name])
                if abs(jump) > max(rtol * scale, 1e-300):
                    found.append(Discontinuity(theta, name, jump, where))
        for k, seg in enumerate(self.segments):
            law = seg.law
            assert isinstance(law, MotionLaw)
            for x in law.interior_jumps:
                eps = 1e-9
                values = seg.evaluate(np.array([x - eps, x + eps]))
                jump = float(values.a[1] - values.a[0])
                theta = float(self._starts[k] + x * self._betas[k])
                found.append(
                    Discontinuity(theta, "a", jump, f"inside segment {k + 1} ({law.name})")
                )
            if law.note and law.note not in notes:
                notes.append(law.note)
        found.sort(key=lambda d: d.theta)
        return ContinuityReport(tuple(found), tuple(notes))

    def to_spec(self, name: str = "cam") -> dict[str, Any]:
        """The program as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from ..spec import model_spec

        return model_spec(self, "cam", name)

    def __repr__(self) -> str:
        parts = ", ".join(
            f"{seg.motion}:{getattr(seg.law, 'name', seg.law)}:{seg.h:g}:{np.degrees(seg.beta):g}°"
            for seg in self.segments
        )
        return f"CamProgram([{parts}])"
