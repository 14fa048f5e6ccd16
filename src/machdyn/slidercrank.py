"""Slider-crank linkages in closed form: the offset slider-crank and its inversion.

:class:`SliderCrank` follows the notes' loop (review lecture 3, "SLIDER-CRANK")
``a e^{jθ2} − b e^{jθ3} − j c − d = 0``: crank ``a = O2A`` (input θ2), coupler
(connecting rod) ``b`` with θ3 the direction *from the slider pin B to A*, the
slide line at offset ``c`` above ``O2`` along +x, and ``d`` the slider position
(``B = d + j c``). Differentiating gives the notes' velocity, acceleration and
jerk equations, each solved in closed form.

:class:`InvertedSliderCrank` is Norton's inversion #3 (*Design of Machinery*,
sec. 4.7): the crank ``O2A`` drives a block pinned at A that slides along a slot
in link 4, which pivots at ``O4 = d`` on the ground line. The slot runs at a
perpendicular offset ``c`` from ``O4``; ``b`` is the block's position along the
slot (from the foot of that perpendicular), so
``a e^{jθ2} − (b + j c) e^{jθ4} − d = 0`` and the block turns with link 4 (θ3 = θ4).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._angles import wrap_2pi
from ._flags import Flagged
from ._validate import (
    choice,
    common_length_unit,
    finite_array,
    finite_scalar,
    input_motion,
    is_scalar,
    length,
)
from .centres import InstantCentres, _unscaled
from .centres import _at_infinity as at_infinity
from .centres import _cross3 as intersect
from .centres import _cross3 as line_through
from .centres import _finite as finite
from .errors import AssemblyError, InputError
from .units import UnitSystem, from_quantity_unit

#: Memory per pose of a solve (rate arrays, complex points, status) for the budget check.
_BYTES_PER_POSE = 12 * 8 + 5 * 16 + 1

__all__ = ["InvertedSliderCrank", "InvertedSliderCrankMotion", "SliderCrank", "SliderCrankMotion"]

OK, NOT_ASSEMBLABLE, TOGGLE = 0, 1, 2
STATUS_REASONS = (
    "",
    "cannot be assembled at this input angle (outside the crank's range)",
    "toggle: the velocity solution is singular here",
)
_CLOSE_TOL = 1e-12
_TOGGLE_TOL = 2e-6


def _rates(theta: np.ndarray, w: np.ndarray, al: np.ndarray, je: np.ndarray):
    """Derivatives of e^{jθ} up to the third: jω e, (jα − ω²) e, (jφ − 3αω − jω³) e."""
    e = np.exp(1j * theta)
    return e, 1j * w * e, (1j * al - w * w) * e, (1j * je - 3 * al * w - 1j * w**3) * e


@dataclass(frozen=True, eq=False)
class SliderCrankMotion(Flagged):
    """Kinematics of a slider-crank over a set of input angles.

    Attributes
    ----------
    theta2, theta3 : ndarray
        Crank angle (as given) and connecting-rod angle (B→A), radians; θ3 in ``[0, 2π)``.
    omega2, omega3, alpha2, alpha3, jerk2, jerk3 : ndarray
        Angular rates of crank and rod.
    d, d_dot, d_ddot, d_dddot : ndarray
        Slider position along the slide line and its time derivatives.
    A, B : ndarray of complex
        Crank pin and slider pin positions.
    coupler, coupler_velocity, coupler_acceleration : ndarray of complex or None
        A point on the rod, when defined.
    status : ndarray of uint8
        0 where solved; otherwise an index into :data:`STATUS_REASONS`.
    """

    REASONS = STATUS_REASONS

    theta2: np.ndarray
    theta3: np.ndarray
    omega2: np.ndarray
    omega3: np.ndarray
    alpha2: np.ndarray
    alpha3: np.ndarray
    jerk2: np.ndarray
    jerk3: np.ndarray
    d: np.ndarray
    d_dot: np.ndarray
    d_ddot: np.ndarray
    d_dddot: np.ndarray
    A: np.ndarray
    B: np.ndarray
    coupler: np.ndarray | None
    coupler_velocity: np.ndarray | None
    coupler_acceleration: np.ndarray | None
    status: np.ndarray
    form: int
    offset: float = field(repr=False)
    #: The model's unit system (labels of :meth:`to_pandas`); None: unit-free.
    units: Any = field(default=None, repr=False)

    @property
    def assembled(self) -> np.ndarray:
        """True where the positions are valid (toggles included)."""
        return self.status != NOT_ASSEMBLABLE

    def to_pandas(self):
        """A :class:`pandas.DataFrame`, one row per sample (pandas imported lazily)."""
        import pandas as pd

        from .units import columns

        kinds = {"theta": "angle", "omega": "angular_velocity", "alpha": "angular_acceleration"}
        kinds |= {"jerk": "angular_jerk"}
        spec: list[tuple[str, str | None, Any]] = [
            (f"{k}{n}", kind, getattr(self, f"{k}{n}")) for k, kind in kinds.items() for n in (2, 3)
        ]
        spec += [("d", "length", self.d), ("d_dot", "velocity", self.d_dot)]
        spec += [("d_ddot", "acceleration", self.d_ddot), ("d_dddot", "jerk", self.d_dddot)]
        cols = columns(self.units, spec)
        cols["ok"] = np.ravel(self.ok)
        cols["reason"] = np.ravel(self.reason)
        return pd.DataFrame(cols)

    def plot(self, **options: Any):
        """Slider position and derivatives against θ2 (:func:`machdyn.plot.plot_slider_motion`)."""
        from .plot import plot_slider_motion

        return plot_slider_motion(self, **options)


class SliderCrank:
    """An offset slider-crank (the notes' loop ``a e^{jθ2} − b e^{jθ3} − j c − d = 0``).

    Parameters
    ----------
    crank : float
        Crank length ``a = O2A``.
    coupler : float
        Connecting-rod length ``b = AB``.
    offset : float, optional
        Offset ``c`` of the slide line above O2 (negative below).
    point : (p, delta), optional
        A point on the rod at distance ``p`` from A, at angle ``delta`` from the
        line A→B (counter-clockwise).

    Examples
    --------
    >>> sc = SliderCrank(crank=2.0, coupler=6.0)
    >>> m = sc.solve(np.radians([0, 90, 180]), omega2=10.0)
    >>> np.round(m.d, 6)
    array([8.      , 5.656854, 4.      ])
    >>> np.round(m.d_dot, 6)       # at θ2 = 90°: ḋ = −a ω2 (the rod's ω3 is zero)
    array([ -0.,  -20., 0.])
    """

    #: The units the model computes in and labels its results with; None: unit-free.
    units: UnitSystem | None = None

    def __init__(self, crank: Any, coupler: Any, offset: Any = 0.0, point: Any = None) -> None:
        values, unit = common_length_unit(crank=crank, coupler=coupler, offset=offset)
        for name in ("crank", "coupler"):
            if values[name] <= 0.0:
                raise InputError(name, f"must be a positive length, got {values[name]:g}")
        self.a, self.b, self.c = values["crank"], values["coupler"], values["offset"]
        self.length_unit = unit
        self.units = from_quantity_unit(unit)
        if abs(self.c) >= self.a + self.b:
            raise AssemblyError(
                f"offset {self.c:g} is out of reach: |offset| must be less than "
                f"crank + coupler = {self.a + self.b:g}"
            )
        if point is None:
            self.point = None
        else:
            try:
                p, delta = point
            except (TypeError, ValueError):
                raise InputError("point", f"expected (p, delta), got {point!r}") from None
            self.point = (
                length("point p", p, unit),
                finite_scalar("point delta", delta, "radian"),
            )

    def to_spec(self, name: str = "slider_crank") -> dict[str, Any]:
        """The slider-crank as a machine-file dict (see ``docs/spec.md``)."""
        from .spec import model_spec

        return model_spec(self, "slider_crank", name)

    def __repr__(self) -> str:
        return f"SliderCrank(crank={self.a:g}, coupler={self.b:g}, offset={self.c:g})"

    @property
    def crank_rotates(self) -> bool:
        """True if the crank can make full turns (``a + |c| < b``)."""
        return self.a + abs(self.c) < self.b

    def input_range(self) -> tuple[float, float] | None:
        """θ2 limits ``(lo, hi)`` of a crank that cannot turn fully; None when it can.

        The rod reaches the slide only while ``|a sin θ2 − c| ≤ b``. When the
        crank can pass over the top (or under the bottom) the range is one arc
        through 90° (or 270°), with ``hi`` possibly beyond π. Otherwise it rocks in
        one of two mirror-image arcs; this returns the one around θ2 = 0 (the
        other is ``(π − hi, π − lo)``).

        Examples
        --------
        >>> lo, hi = SliderCrank(3.0, 2.0).input_range()
        >>> print(f"{np.degrees(lo):.4f} {np.degrees(hi):.4f}")
        -41.8103 41.8103

        A crank that clears the top but not the bottom swings through 90°:

        >>> lo, hi = SliderCrank(3.0, 2.0, 1.5).input_range()
        >>> print(f"{np.degrees(lo):.4f} {np.degrees(hi):.4f}")
        -9.5941 189.5941
        """
        if self.crank_rotates:
            return None
        low, high = (self.c - self.b) / self.a, (self.c + self.b) / self.a
        if high >= 1.0 and low <= -1.0:
            return None  # a + |c| = b exactly: turns fully, touching a toggle
        if high >= 1.0:  # over the top: sin θ2 ≥ low
            start = float(np.arcsin(low))
            return start, float(np.pi - start)
        if low <= -1.0:  # under the bottom: sin θ2 ≤ high
            top = float(np.arcsin(high))
            return float(np.pi - top), float(2.0 * np.pi + top)
        return float(np.arcsin(low)), float(np.arcsin(high))

    def stroke(self, form: int = 1) -> tuple[float, float]:
        """Extreme slider positions ``(d_min, d_max)`` of a form (crank and rod aligned).

        Examples
        --------
        >>> SliderCrank(2.0, 6.0).stroke()
        (4.0, 8.0)
        """
        choice("form", form, (1, 2))
        if not self.crank_rotates:
            raise InputError("form", "the stroke is defined for a full-turning crank (a + |c| < b)")
        s = 1.0 if form == 1 else -1.0
        far = s * np.sqrt((self.a + self.b) ** 2 - self.c**2)
        near = s * np.sqrt((self.b - self.a) ** 2 - self.c**2)
        return float(min(far, near)), float(max(far, near))

    def solve(
        self,
        theta2: Any,
        omega2: Any = 0.0,
        alpha2: Any = 0.0,
        form: int = 1,
        *,
        jerk2: Any = 0.0,
    ) -> SliderCrankMotion:
        """Positions, velocities, accelerations and jerks for crank angles ``theta2``.

        Parameters
        ----------
        form : {1, 2}
            1: slider on the +x side of A (θ3 in (π/2, 3π/2); Norton's second
            solution θ3 = arcsin(·) + π); 2: slider on the −x side.

        Raises
        ------
        AssemblyError
            If ``theta2`` is a single angle the rod cannot reach (arrays are flagged).
        """
        choice("form", form, (1, 2))
        scalar = is_scalar(theta2)
        extent = max(self.a, self.b, abs(self.c), 0.0 if self.point is None else self.point[0])
        _, (t2, w2, a2, j2) = input_motion(
            theta2, omega2, alpha2, jerk2, bytes_per_sample=_BYTES_PER_POSE, length=extent
        )
        a, b, c = self.a, self.b, self.c
        e2, v2, acc2, jer2 = _rates(t2, w2, a2, j2)
        s3 = (a * e2.imag - c) / b
        status = np.where(np.abs(s3) <= 1.0 + _CLOSE_TOL, OK, NOT_ASSEMBLABLE).astype(np.uint8)
        if scalar and status.item() != OK:
            raise AssemblyError(
                f"{self!r}: theta2 = {np.degrees(float(t2)):.6g} deg cannot be assembled; "
                f"the crank rocks between {np.degrees(self.input_range()[0]):.6g} and "
                f"{np.degrees(self.input_range()[1]):.6g} deg"
            )
        s3 = np.clip(s3, -1.0, 1.0)
        c3 = np.sqrt(1.0 - s3 * s3) * (-1.0 if form == 1 else 1.0)
        status[(status == OK) & (np.abs(c3) < _TOGGLE_TOL)] = TOGGLE
        bad = status == NOT_ASSEMBLABLE
        c3 = np.where(bad, np.nan, c3)
        e3 = c3 + 1j * s3
        d = a * e2.real - b * c3

        def solve_pair(K):
            # −j b x3 e3 − x_d = K  →  x3 = −Im K / (b cos θ3),  x_d = b x3 sin θ3 − Re K
            x3 = -K.imag / (b * e3.real)
            return x3, b * x3 * e3.imag - K.real

        with np.errstate(divide="ignore", invalid="ignore"):  # flagged samples only
            w3, dd = solve_pair(-a * v2)
            al3, ddd = solve_pair(-a * acc2 - b * w3 * w3 * e3)
            je3, dddd = solve_pair(-a * jer2 + b * (-3 * al3 * w3 - 1j * w3**3) * e3)
        toggled = status == TOGGLE
        w3, dd, al3, ddd, je3, dddd = (
            np.where(toggled, np.nan, x) for x in (w3, dd, al3, ddd, je3, dddd)
        )
        A = a * e2
        B = d + 1j * c
        P = VP = AP = None
        if self.point is not None:
            p, delta = self.point
            ep = -e3 * np.exp(1j * delta)  # direction A→B is θ3 + π
            P = A + p * ep
            VP = a * v2 + 1j * w3 * p * ep
            AP = a * acc2 + (1j * al3 - w3 * w3) * p * ep
        return SliderCrankMotion(
            theta2=t2,
            theta3=wrap_2pi(np.angle(e3)),
            omega2=w2,
            omega3=w3,
            alpha2=a2,
            alpha3=al3,
            jerk2=j2,
            jerk3=je3,
            d=d,
            d_dot=dd,
            d_ddot=ddd,
            d_dddot=dddd,
            A=A,
            B=B,
            coupler=P,
            coupler_velocity=VP,
            coupler_acceleration=AP,
            status=status,
            form=form,
            offset=c,
            units=self.units,
        )

    def draw(self, theta2: Any, ax: Any = None, **options: Any):
        """Draw the mechanism in one pose (see :func:`machdyn.plot.plot_slider_crank`)."""
        from .plot import plot_slider_crank

        return plot_slider_crank(self, theta2, ax=ax, **options)

    def animate(self, **options: Any):
        """A matplotlib animation; GIF/MP4/HTML with ``path=`` (:func:`machdyn.plot.animate`)."""
        from .draw import animate

        return animate(self, **options)

    def to_html(self, path: Any = None, **options: Any) -> str:
        """A self-contained HTML page animating the mechanism (:func:`machdyn.draw.to_html`)."""
        from .draw import to_html

        return to_html(self, path, **options)

    def report(self, path: Any = None, **options: Any) -> str:
        """The design report as one HTML page (:func:`machdyn.report.report`)."""
        from .report import report

        return report(self, path, **options)

    def dynamics(self, theta2: Any, omega2: Any, alpha2: Any = 0.0, **options: Any):
        """Joint forces, guide normal force and crank torque (with slider friction).

        Keyword options are those of :func:`machdyn.dynamics.slidercrank_dynamics`
        (``mass, inertia, cg, form, gravity, load_force4, friction, mu, beta``, ...).
        """
        from .dynamics import slidercrank_dynamics

        return slidercrank_dynamics(self, theta2, omega2, alpha2, **options)

    def instant_centres(self, theta2: Any, form: int = 1) -> InstantCentres:
        """The six instant centres (1 ground, 2 crank, 3 rod, 4 slider).

        I14 is at infinity, normal to the slide (the notes: "I.C. of two bodies in
        sliding contact is located at ∞ along the normal to the plane of slip").
        """
        m = self.solve(theta2, form=form)
        shape = np.shape(m.A)
        scale = max(self.a, self.b, abs(self.c))  # lines met in its units: no overflow
        I12 = finite(np.zeros(shape, dtype=complex))
        I23 = finite(m.A / scale)
        I34 = finite(m.B / scale)
        I14 = at_infinity(np.full(shape, 1j))
        I13 = intersect(line_through(I12, I23), line_through(I14, I34))
        I24 = intersect(line_through(I12, I14), line_through(I23, I34))
        centres = {(1, 2): I12, (2, 3): I23, (3, 4): I34, (1, 4): I14, (1, 3): I13, (2, 4): I24}
        return InstantCentres(
            {k: _unscaled(v, scale) for k, v in centres.items()}, m.assembled, scale=scale
        )

    def mechanical_advantage(
        self, theta2: Any, r_in: float = 1.0, form: int = 1, *, method: str = "power"
    ) -> np.ndarray:
        """Force on the slider per force ``F_in`` at radius ``r_in`` on the crank.

        ``MA = r_in ω2 / ḋ`` (power identity). With ``method="instant_centres"``
        the slider speed is ``ω2 × I24`` (I24 moves with the slider), so
        ``ḋ = −ω2 · Im(I24)``.
        """
        method = choice("method", method, ("power", "instant_centres"))
        r_in = finite_scalar("r_in", r_in, self.length_unit)
        if method == "power":
            m = self.solve(theta2, omega2=1.0, form=form)
            speed, valid = m.d_dot, m.ok
        else:
            ics = self.instant_centres(theta2, form=form)
            speed, valid = -ics[2, 4].point.imag, ics.valid & ~ics[2, 4].at_infinity
        with np.errstate(divide="ignore", invalid="ignore"):
            ma = r_in / speed
        # at a dead centre the slider stops: unbounded force, whichever sign of zero
        ma = np.where(np.abs(speed) <= _TOGGLE_TOL * self.a, np.inf, ma)
        return np.where(valid, ma, np.nan)


@dataclass(frozen=True, eq=False)
class InvertedSliderCrankMotion(Flagged):
    """Kinematics of an inverted slider-crank.

    ``theta4`` (= θ3, the block turns with link 4), ``b`` (the block's position
    along the slot) and their derivatives; ``A`` the crank pin.
    """

    REASONS = STATUS_REASONS

    theta2: np.ndarray
    theta4: np.ndarray
    omega2: np.ndarray
    omega4: np.ndarray
    alpha2: np.ndarray
    alpha4: np.ndarray
    jerk2: np.ndarray
    jerk4: np.ndarray
    b: np.ndarray
    b_dot: np.ndarray
    b_ddot: np.ndarray
    b_dddot: np.ndarray
    A: np.ndarray
    status: np.ndarray
    form: int
    #: The model's unit system; None: unit-free.
    units: Any = field(default=None, repr=False)

    @property
    def theta3(self) -> np.ndarray:
        """The block's angle: equal to θ4."""
        return self.theta4


class InvertedSliderCrank:
    """Norton's inverted slider-crank (inversion #3): a block on the crank slides in link 4.

    Parameters
    ----------
    crank : float
        ``a = O2A``.
    ground : float
        ``d = O2O4`` (O4 on +x).
    offset : float, optional
        Perpendicular distance ``c`` from O4 to the slot's line (0: the slot
        passes through O4).

    Examples
    --------
    A quick-return shaper: crank 2, pivots 4 apart; at θ2 = 90° the slot points
    at A = (0, 2), so θ4 = atan2(2, −4):

    >>> m = InvertedSliderCrank(2.0, 4.0).solve(np.radians(90))
    >>> print(f"{np.degrees(m.theta4):.4f} {m.b:.6f}")
    153.4349 4.472136
    """

    #: The units the model computes in and labels its results with; None: unit-free.
    units: UnitSystem | None = None

    def __init__(self, crank: Any, ground: Any, offset: Any = 0.0) -> None:
        values, unit = common_length_unit(crank=crank, ground=ground, offset=offset)
        for name in ("crank", "ground"):
            if values[name] <= 0.0:
                raise InputError(name, f"must be a positive length, got {values[name]:g}")
        self.a, self.d, self.c = values["crank"], values["ground"], values["offset"]
        self.length_unit = unit
        self.units = from_quantity_unit(unit)

    def to_spec(self, name: str = "inverted_slider_crank") -> dict[str, Any]:
        """The inverted slider-crank as a machine-file dict (see ``docs/spec.md``)."""
        from .spec import model_spec

        return model_spec(self, "inverted_slider_crank", name)

    def __repr__(self) -> str:
        return f"InvertedSliderCrank(crank={self.a:g}, ground={self.d:g}, offset={self.c:g})"

    def instant_centres(self, theta2: Any, form: int = 1) -> InstantCentres:
        """The six instant centres (1 ground, 2 crank, 3 block, 4 slotted link).

        By inspection I12 = O2, I23 = A, I14 = O4 and I34 at infinity normal to
        the slot; by Kennedy's rule, as the notes' Problem 6-13(a) does it,
        I13 on I12–I23 and I14–I34, I24 on I12–I14 and I23–I34.

        Examples
        --------
        Crank 2, pivots 4 apart, θ2 = 90°: A = 2j, the slot runs from O4 toward
        A, and the normal through O4 meets O2A at I13 = −8j:

        >>> ics = InvertedSliderCrank(2.0, 4.0).instant_centres(np.radians(90))
        >>> complex(np.round(ics[1, 3].point, 9) + 0), complex(np.round(ics[2, 4].point, 9) + 0)
        (-8j, (-1+0j))
        """
        m = self.solve(finite_array("theta2", theta2), form=form)
        shape = np.shape(m.A)
        scale = max(self.a, self.d, abs(self.c))  # lines met in its units: no overflow
        I12 = finite(np.zeros(shape, dtype=complex))
        I14 = finite(np.full(shape, self.d / scale, dtype=complex))
        I23 = finite(m.A / scale)
        I34 = at_infinity(1j * np.exp(1j * m.theta4))
        I13 = intersect(line_through(I12, I23), line_through(I14, I34))
        I24 = intersect(line_through(I12, I14), line_through(I23, I34))
        valid = m.status != NOT_ASSEMBLABLE
        centres = {(1, 2): I12, (2, 3): I23, (3, 4): I34, (1, 4): I14, (1, 3): I13, (2, 4): I24}
        return InstantCentres(
            {k: _unscaled(v, scale) for k, v in centres.items()},
            valid,
            scale=scale,
            bodies=(1, 2, 3, 4),
            reason=np.where(valid, "", STATUS_REASONS[NOT_ASSEMBLABLE]),
            methods={(1, 3): "kennedy", (2, 4): "kennedy"}
            | dict.fromkeys([(1, 2), (2, 3), (1, 4), (3, 4)], "joint"),
        )

    def draw(self, frame: int | None = None, ax: Any = None, **options: Any):
        """Draw the mechanism in one pose of its turn (see :func:`machdyn.draw.draw`)."""
        from .draw import draw

        return draw(self, frame, ax, **options)

    def animate(self, **options: Any):
        """A matplotlib animation; GIF/MP4/HTML with ``path=`` (:func:`machdyn.plot.animate`)."""
        from .draw import animate

        return animate(self, **options)

    def to_html(self, path: Any = None, **options: Any) -> str:
        """A self-contained HTML page animating the mechanism (:func:`machdyn.draw.to_html`)."""
        from .draw import to_html

        return to_html(self, path, **options)

    def report(self, path: Any = None, **options: Any) -> str:
        """The design report as one HTML page (:func:`machdyn.report.report`)."""
        from .report import report

        return report(self, path, **options)

    def dynamics(self, theta2: Any, omega2: Any, alpha2: Any = 0.0, **options: Any):
        """Joint forces, the slot's normal force and couple, crank torque (Norton §11.7).

        Keyword options are those of
        :func:`machdyn.dynamics_inverted.inverted_slidercrank_dynamics` (``mass``,
        ``inertia``, ``cg``, ``form``, ``gravity``, ``load_torque4``,
        ``friction``, ``mu``, ``beta``, ...).

        Examples
        --------
        >>> f = InvertedSliderCrank(2.0, 4.0).dynamics(
        ...     np.radians([0, 90]), 10.0, mass=(1, 0.5, 3), inertia=(0.1, 0.01, 2), cg=(1, 0, 2))
        >>> bool(f.ok.all())
        True
        """
        from .dynamics_inverted import inverted_slidercrank_dynamics

        return inverted_slidercrank_dynamics(self, theta2, omega2, alpha2, **options)

    def solve(
        self,
        theta2: Any,
        omega2: Any = 0.0,
        alpha2: Any = 0.0,
        form: int = 1,
        *,
        jerk2: Any = 0.0,
    ) -> InvertedSliderCrankMotion:
        """Kinematics for crank angles ``theta2``; form 1: ``b > 0``, form 2: ``b < 0``."""
        choice("form", form, (1, 2))
        scalar = is_scalar(theta2)
        extent = max(self.a, self.d, abs(self.c))
        _, (t2, w2, a2, j2) = input_motion(
            theta2, omega2, alpha2, jerk2, bytes_per_sample=_BYTES_PER_POSE, length=extent
        )
        a, d, c = self.a, self.d, self.c
        e2, v2, acc2, jer2 = _rates(t2, w2, a2, j2)
        S = a * e2 - d
        # b² = |S|² − c², in units of the extent: squares of lengths up to 1e250 stay finite
        b2 = np.abs(S / extent) ** 2 - (c / extent) ** 2
        tol = _CLOSE_TOL * ((a + d) / extent) ** 2
        status = np.where(b2 >= -tol, OK, NOT_ASSEMBLABLE).astype(np.uint8)
        if scalar and status.item() != OK:
            raise AssemblyError(
                f"{self!r}: theta2 = {np.degrees(float(t2)):.6g} deg cannot be assembled "
                f"(A comes closer to O4 than the slot offset {abs(c):g})"
            )
        b = extent * np.sqrt(np.clip(b2, 0.0, None)) * (1.0 if form == 1 else -1.0)
        status[(status == OK) & (np.abs(b) < _TOGGLE_TOL * (a + d))] = TOGGLE
        b = np.where(status == NOT_ASSEMBLABLE, np.nan, b)
        Z = b + 1j * c
        with np.errstate(divide="ignore", invalid="ignore"):
            E = S / Z  # e^{jθ4}

            def solve_pair(R):
                # b⁽ⁿ⁾ + j Z θ4⁽ⁿ⁾ = R  →  θ4⁽ⁿ⁾ = Im R / b,  b⁽ⁿ⁾ = Re R + c θ4⁽ⁿ⁾
                x = R.imag / b
                return x, R.real + c * x

            w4, bd = solve_pair(a * v2 / E)
            al4, bdd = solve_pair(a * acc2 / E - 2j * bd * w4 + Z * w4 * w4)
            je4, bddd = solve_pair(
                a * jer2 / E
                - 3j * bdd * w4
                - 3 * bd * (1j * al4 - w4 * w4)
                - Z * (-3 * al4 * w4 - 1j * w4**3)
            )
        toggled = status == TOGGLE
        w4, bd, al4, bdd, je4, bddd = (
            np.where(toggled, np.nan, x) for x in (w4, bd, al4, bdd, je4, bddd)
        )
        return InvertedSliderCrankMotion(
            theta2=t2,
            theta4=wrap_2pi(np.angle(E)),
            omega2=w2,
            omega4=w4,
            alpha2=a2,
            alpha4=al4,
            jerk2=j2,
            jerk4=je4,
            b=b,
            b_dot=bd,
            b_ddot=bdd,
            b_dddot=bddd,
            A=a * e2,
            status=status,
            form=form,
            units=self.units,
        )
