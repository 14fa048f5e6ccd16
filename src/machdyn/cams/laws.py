"""Follower motion laws: s, v, a, j of one segment over its normalised angle.

Every law is a function of the normalised cam angle ``x = θ/β`` in ``[0, 1]``
for a rise ``h`` over the segment angle ``β`` (radians). It returns the
displacement ``s`` and its derivatives with respect to the *cam angle*
(per radian): ``v = ds/dθ``, ``a = d²s/dθ²``, ``j = d³s/dθ³`` (Norton, *Design
of Machinery*, §8.3; the notes' svaj diagrams). Time derivatives follow from
the cam speed ω: ``V = ωv``, ``A = ω²a``, ``J = ω³j`` (notes, Ch. 8).

A negative ``h`` gives the mirrored fall from 0 down to ``h``; :func:`fall`
returns the textbook fall from ``h`` down to 0.

The named double-dwell laws are members of the SCCA family (sine–constant–
cosine–acceleration, Norton §8.3, Table 8-2) with parameters ``b, c, d``
(``b + c + d = 1``):

===================  ====  ====  ====  =========================
law                  b     c     d     peak ``a`` (× h/β²)
===================  ====  ====  ====  =========================
constant accel.      0     1     0     4
modified trapezoid   0.25  0.5   0.25  8π/(π+2) ≈ 4.8881
simple harmonic      0     0     1     π²/2 ≈ 4.9348
modified sine        0.25  0     0.75  ≈ 5.5280
cycloidal            0.5   0     0.5   2π ≈ 6.2832
===================  ====  ====  ====  =========================
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from .._validate import finite_array, finite_scalar, instance, items, positive
from ..errors import InputError

__all__ = [
    "LAW_NAMES",
    "LawValues",
    "MotionLaw",
    "PolynomialLaw",
    "constant_velocity",
    "cycloidal",
    "dwell",
    "fall",
    "get_law",
    "modified_sine",
    "modified_trapezoid",
    "poly345",
    "poly4567",
    "polynomial_law",
    "scca",
    "scca_peak_factor",
    "simple_harmonic",
]

_X_TOL = 1e-9


class LawValues(NamedTuple):
    """Displacement and its first three derivatives per radian of cam angle."""

    s: np.ndarray
    v: np.ndarray
    a: np.ndarray
    j: np.ndarray


# --------------------------------------------------------------------------
# Normalised shapes: unit rise over unit x, derivatives with respect to x.
# --------------------------------------------------------------------------

Shape = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]


def _dwell_shape(x: np.ndarray) -> tuple[np.ndarray, ...]:
    zero = np.zeros_like(x)
    return zero, zero.copy(), zero.copy(), zero.copy()


def _constant_velocity_shape(x: np.ndarray) -> tuple[np.ndarray, ...]:
    zero = np.zeros_like(x)
    return x.copy(), np.ones_like(x), zero, zero.copy()


def _simple_harmonic_shape(x: np.ndarray) -> tuple[np.ndarray, ...]:
    # Norton eq. 8.5: s = h/2 (1 - cos(πθ/β)).
    px = np.pi * x
    sin, cos = np.sin(px), np.cos(px)
    half = 0.5
    return half * (1.0 - cos), half * np.pi * sin, half * np.pi**2 * cos, -half * np.pi**3 * sin


def _cycloidal_shape(x: np.ndarray) -> tuple[np.ndarray, ...]:
    # Norton eq. 8.6: s = h (x - sin(2πx)/(2π)); the notes' Fig. 8-12.
    tpx = 2.0 * np.pi * x
    sin, cos = np.sin(tpx), np.cos(tpx)
    return (
        x - sin / (2.0 * np.pi),
        1.0 - cos,
        2.0 * np.pi * sin,
        4.0 * np.pi**2 * cos,
    )


def _power_shape(coefficients: tuple[float, ...]) -> Shape:
    """Shape of the polynomial ``Σ c_k x^k`` and its three x-derivatives."""
    c0 = np.asarray(coefficients, dtype=np.float64)
    c1 = np.polynomial.polynomial.polyder(c0)
    c2 = np.polynomial.polynomial.polyder(c1)
    c3 = np.polynomial.polynomial.polyder(c2)

    def shape(x: np.ndarray) -> tuple[np.ndarray, ...]:
        polyval = np.polynomial.polynomial.polyval
        return polyval(x, c0), polyval(x, c1), polyval(x, c2), polyval(x, c3)

    return shape


# Norton eqs. 8.23 (3-4-5) and 8.24 (4-5-6-7).
_POLY345 = (0.0, 0.0, 0.0, 10.0, -15.0, 6.0)
_POLY4567 = (0.0, 0.0, 0.0, 0.0, 35.0, -84.0, 70.0, -20.0)


def _scca_half_integrals(b: float, c: float, d: float) -> tuple[float, float, float, float]:
    """Velocity and displacement at the ends of zones 1 and 2 for a unit peak.

    Integrating the unit-peak acceleration from x = 0 with zero start values:
    zone 1 (0 ≤ x ≤ b/2) ``sin(πx/b)``, zone 2 (to (1−d)/2) ``1``.
    """
    v1 = b / np.pi
    s1 = b * b * (1.0 / (2.0 * np.pi) - 1.0 / np.pi**2)
    v2 = v1 + c / 2.0
    s2 = s1 + v1 * c / 2.0 + c * c / 8.0
    return v1, s1, v2, s2


def scca_peak_factor(b: float, c: float, d: float) -> float:
    """Peak acceleration factor ``C_a`` of the SCCA law (``a_max = C_a h/β²``).

    Derived by integrating the unit-peak acceleration to mid-rise, where
    antisymmetry demands ``s(1/2) = h/2``; it agrees with Norton's eq. 8.16b
    ``C_a = 4π² / ((π² − 8)(b² − d²) − 2π(π − 2)b + π²)``.

    Examples
    --------
    >>> round(scca_peak_factor(0.25, 0.5, 0.25), 4)   # modified trapezoid
    4.8881
    >>> round(scca_peak_factor(0.25, 0.0, 0.75), 4)   # modified sine
    5.528
    """
    b, c, d = _check_bcd(b, c, d)
    _, _, v2, s2 = _scca_half_integrals(b, c, d)
    return 0.5 / (s2 + v2 * d / 2.0 + (d / np.pi) ** 2)


def _check_bcd(b: Any, c: Any, d: Any) -> tuple[float, float, float]:
    b = finite_scalar("b", b)
    c = finite_scalar("c", c)
    d = finite_scalar("d", d)
    for name, value in (("b", b), ("c", c), ("d", d)):
        if value < 0.0 or value > 1.0:
            raise InputError(name, f"SCCA fractions lie in [0, 1], got {value}")
    if abs(b + c + d - 1.0) > 1e-9:
        raise InputError("b", f"SCCA fractions must satisfy b + c + d = 1, got {b + c + d:.6g}")
    # Zones narrower than 1e-9 of the rise are taken as absent (their sine
    # pieces would overflow and change nothing measurable).
    b = 0.0 if b < 1e-9 else b
    d = 0.0 if d < 1e-9 else d
    return b, max(0.0, 1.0 - b - d), d


def _scca_shape(b: float, c: float, d: float) -> Shape:
    ca = scca_peak_factor(b, c, d)
    v1, s1, v2, s2 = _scca_half_integrals(b, c, d)
    x1, x2 = b / 2.0, (1.0 - d) / 2.0
    b_ = b if b > 0.0 else 1.0  # zone 1 (or 3) is empty when b (or d) is 0
    d_ = d if d > 0.0 else 1.0

    def half(u: np.ndarray) -> tuple[np.ndarray, ...]:
        zone1 = u < x1
        zone3 = u >= x2
        # Zone 1: quarter sine up to the peak.
        k1 = np.pi / b_
        s_1 = (b_ / np.pi) * (u - np.sin(k1 * u) / k1)
        v_1 = (b_ / np.pi) * (1.0 - np.cos(k1 * u))
        a_1 = np.sin(k1 * u)
        j_1 = k1 * np.cos(k1 * u)
        # Zone 2: constant acceleration.
        w2 = u - x1
        s_2 = s1 + v1 * w2 + 0.5 * w2 * w2
        v_2 = v1 + w2
        a_2 = np.ones_like(u)
        j_2 = np.zeros_like(u)
        # Zone 3: half cosine through zero at mid-rise.
        w3 = u - x2
        k3 = np.pi / d_
        s_3 = s2 + v2 * w3 + (1.0 - np.cos(k3 * w3)) / k3**2
        v_3 = v2 + np.sin(k3 * w3) / k3
        a_3 = np.cos(k3 * w3)
        j_3 = -k3 * np.sin(k3 * w3)
        out = []
        for z1, z2, z3 in ((s_1, s_2, s_3), (v_1, v_2, v_3), (a_1, a_2, a_3), (j_1, j_2, j_3)):
            out.append(ca * np.where(zone1, z1, np.where(zone3, z3, z2)))
        return tuple(out)

    def shape(x: np.ndarray) -> tuple[np.ndarray, ...]:
        # Acceleration is antisymmetric about x = 1/2: s(1-x) = 1 - s(x).
        mirrored = x > 0.5
        u = np.where(mirrored, 1.0 - x, x)
        s, v, a, j = half(u)
        return np.where(mirrored, 1.0 - s, s), v, np.where(mirrored, -a, a), j

    return shape


# --------------------------------------------------------------------------
# Law objects
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class MotionLaw:
    """A named follower motion law over one segment.

    Parameters
    ----------
    name : str
        Canonical name (see :data:`LAW_NAMES`).
    shape : callable
        Unit-rise shape ``x -> (S, S', S'', S''')`` (derivatives in x).
    interior_jumps : tuple of float
        Normalised angles inside the segment where the acceleration jumps
        (infinite jerk), e.g. 0.5 for constant acceleration.
    note : str
        A caution shown by the continuity check (empty when none).

    Examples
    --------
    >>> law = get_law("cycloidal")
    >>> values = law(np.array([0.0, 0.5, 1.0]), h=1.0, beta=np.pi / 2)
    >>> values.s.tolist()
    [0.0, 0.5, 1.0]
    """

    name: str
    shape: Shape = field(repr=False)
    interior_jumps: tuple[float, ...] = ()
    note: str = ""

    def __call__(self, x: Any, h: float = 1.0, beta: float = 1.0) -> LawValues:
        """Evaluate s, v, a, j for a rise ``h`` (negative: fall) over ``beta`` radians."""
        x = _check_x(x)
        h = finite_scalar("h", h)
        beta = positive("beta", beta, "radian")
        s, v, a, j = self.shape(x)
        return LawValues(h * s, h * v / beta, h * a / beta**2, h * j / beta**3)


@dataclass(frozen=True)
class PolynomialLaw(MotionLaw):
    """A polynomial fitted to boundary conditions (Norton §8.4).

    ``s(0) = 0`` and ``s(1) = h`` are always imposed; ``start`` and ``end``
    add derivative conditions per radian of cam angle (``v``, ``a``, ``j``);
    ``points`` adds ``(x, order, value)`` conditions anywhere in the segment
    (``order`` 0 for s, 1 for v, ...). The degree is the number of conditions
    minus one.
    """

    conditions: tuple[tuple[float, int, float], ...] = ()

    def coefficients(self, h: float, beta: float) -> np.ndarray:
        """Power-series coefficients ``c_k`` of ``s(x) = Σ c_k x^k``."""
        h = finite_scalar("h", h)
        beta = positive("beta", beta, "radian")
        rows = [(0.0, 0, 0.0), (1.0, 0, h), *self.conditions]
        n = len(rows)
        powers = np.arange(n)
        matrix = np.zeros((n, n))
        rhs = np.zeros(n)
        for i, (x0, order, value) in enumerate(rows):
            # d^k/dθ^k x^p = p!/(p-k)! x^(p-k) / β^k
            falling = np.array([math.perm(int(p), order) for p in powers], dtype=float)
            exponent = np.clip(powers - order, 0, None)
            matrix[i] = np.where(powers >= order, falling * x0**exponent, 0.0) / beta**order
            rhs[i] = value
        if np.linalg.matrix_rank(matrix) < n:
            raise InputError(
                "conditions", "the boundary conditions repeat or contradict each other"
            )
        return np.linalg.solve(matrix, rhs)

    def __call__(self, x: Any, h: float = 1.0, beta: float = 1.0) -> LawValues:
        """Evaluate s, v, a, j for a net change ``h`` over ``beta`` radians."""
        x = _check_x(x)
        h = finite_scalar("h", h)
        beta = positive("beta", beta, "radian")
        c = self.coefficients(h, beta)
        polyval, polyder = np.polynomial.polynomial.polyval, np.polynomial.polynomial.polyder
        out = [polyval(x, c)]
        for order in (1, 2, 3):
            out.append(polyval(x, polyder(c, order)) / beta**order)
        return LawValues(*out)


def _check_x(x: Any) -> np.ndarray:
    x = finite_array("x", x)
    if x.size and (x.min() < -_X_TOL or x.max() > 1.0 + _X_TOL):
        raise InputError("x", "the normalised angle θ/β must lie in [0, 1]")
    return np.clip(x, 0.0, 1.0)


_ORDER = {"s": 0, "v": 1, "a": 2, "j": 3}


def polynomial_law(
    start: Mapping[str, float] | None = None,
    end: Mapping[str, float] | None = None,
    points: Iterable[tuple[float, str, float]] = (),
) -> PolynomialLaw:
    """Build a polynomial law from the boundary conditions you give (Norton §8.4).

    Parameters
    ----------
    start, end : mapping, optional
        Conditions at the segment start and end on ``v``, ``a``, ``j`` (per
        radian of cam angle), e.g. ``{"v": 0, "a": 0}``. ``s(0) = 0`` and
        ``s(end) = h`` are implied.
    points : iterable of (x, name, value)
        Extra conditions at normalised angles ``x`` in ``[0, 1]`` on
        ``"s"``, ``"v"``, ``"a"`` or ``"j"``.

    Returns
    -------
    PolynomialLaw

    Examples
    --------
    The 3-4-5 polynomial is the quintic with zero v and a at both ends:

    >>> law = polynomial_law(start={"v": 0, "a": 0}, end={"v": 0, "a": 0})
    >>> np.round(law.coefficients(h=1.0, beta=1.0), 9).tolist()
    [0.0, 0.0, 0.0, 10.0, -15.0, 6.0]
    """
    rows: list[tuple[float, int, float]] = []
    for where, given in ((0.0, start), (1.0, end)):
        if given is not None and not isinstance(given, Mapping):
            raise InputError(
                "start" if where == 0.0 else "end",
                f"must map v, a or j to values, e.g. {{'v': 0}}; got {given!r}"[:200],
            )
        for name, value in (given or {}).items():
            if name not in ("v", "a", "j"):
                raise InputError(
                    "start" if where == 0.0 else "end",
                    f"end conditions are on v, a or j (s is set by h); got {name!r}",
                )
            rows.append((where, _ORDER[name], finite_scalar(name, value)))
    for item in items("points", points, what="(x, name, value) conditions"):
        try:
            x0, name, value = item
        except (TypeError, ValueError):
            raise InputError("points", f"expected (x, name, value), got {item!r}") from None
        if name not in _ORDER:
            raise InputError("points", f"name must be one of s, v, a, j; got {name!r}")
        x0 = finite_scalar("points", x0)
        if not 0.0 <= x0 <= 1.0:
            raise InputError("points", f"x must lie in [0, 1], got {x0}")
        rows.append((x0, _ORDER[name], finite_scalar(name, value)))
    law = PolynomialLaw(name="polynomial", shape=_dwell_shape, conditions=tuple(rows))
    try:  # the rank does not depend on h or β: refuse here, not when the cam is sampled
        law.coefficients(1.0, 1.0)
    except InputError:
        given = [name for name, v in (("start", start), ("end", end)) if v]
        raise InputError(
            "points" if len(rows) > sum(len(v or ()) for v in (start, end)) else given[-1],
            f"these {len(rows) + 2} conditions (s(0) = 0 and s(1) = h with the ones given) do "
            "not fix one polynomial: some repeat or contradict each other, or a polynomial "
            "meeting the rest meets them "
            "already (e.g. a condition on v at x = 0.5 with v = a = 0 at both ends: x³(1 − x)³ "
            "has s, v, a = 0 at both ends and v = 0 at 0.5, so any multiple of it can be "
            "added); change or drop a condition",
        ) from None
    return law


# Registry of the named laws ------------------------------------------------

_CV_NOTE = (
    "constant velocity: v jumps where it meets a dwell, so a and j are infinite there "
    "(unacceptable for dwell cams, notes Ch. 8)"
)

_NAMED: dict[str, MotionLaw] = {
    "dwell": MotionLaw("dwell", _dwell_shape),
    "constant_velocity": MotionLaw("constant_velocity", _constant_velocity_shape, note=_CV_NOTE),
    "constant_acceleration": MotionLaw(
        "constant_acceleration",
        _scca_shape(0.0, 1.0, 0.0),
        interior_jumps=(0.5,),
        note="constant acceleration: a jumps at the ends and mid-rise (infinite jerk)",
    ),
    "simple_harmonic": MotionLaw("simple_harmonic", _simple_harmonic_shape),
    "cycloidal": MotionLaw("cycloidal", _cycloidal_shape),
    "modified_trapezoid": MotionLaw("modified_trapezoid", _scca_shape(0.25, 0.5, 0.25)),
    "modified_sine": MotionLaw("modified_sine", _scca_shape(0.25, 0.0, 0.75)),
    "poly345": MotionLaw("poly345", _power_shape(_POLY345)),
    "poly4567": MotionLaw("poly4567", _power_shape(_POLY4567)),
}

_ALIASES = {
    "cv": "constant_velocity",
    "shm": "simple_harmonic",
    "harmonic": "simple_harmonic",
    "cycloid": "cycloidal",
    "3-4-5": "poly345",
    "345": "poly345",
    "4-5-6-7": "poly4567",
    "4567": "poly4567",
    "modtrap": "modified_trapezoid",
    "modsine": "modified_sine",
}

#: Names accepted by :func:`get_law` (aliases such as ``"3-4-5"`` also work).
LAW_NAMES: tuple[str, ...] = (*_NAMED, "scca")


def get_law(name: str, **params: float) -> MotionLaw:
    """Return the motion law called ``name``.

    Parameters
    ----------
    name : str
        One of :data:`LAW_NAMES` or an alias (``"shm"``, ``"3-4-5"``,
        ``"4-5-6-7"``, ``"modtrap"``, ``"modsine"``, ``"cv"``); case and
        spaces/hyphens are forgiven.
    **params : float
        ``b``, ``c``, ``d`` for ``"scca"``.

    Examples
    --------
    >>> get_law("Modified Sine").name
    'modified_sine'
    >>> get_law("scca", b=0.25, c=0.5, d=0.25).name
    'scca(b=0.25, c=0.5, d=0.25)'
    >>> get_law("parabolic")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: law: unknown law 'parabolic'; valid: dwell, ...
    """
    if not isinstance(name, str):
        raise InputError("law", f"must be a law name, got {name!r}")
    key = name.strip().lower().replace(" ", "_")
    key = _ALIASES.get(key, key.replace("-", "_"))
    key = _ALIASES.get(key, key)
    if key == "scca":
        missing = [p for p in ("b", "c", "d") if p not in params]
        if missing:
            raise InputError("law", f"scca needs b, c and d; missing {', '.join(missing)}")
        b, c, d = _check_bcd(params["b"], params["c"], params["d"])
        return MotionLaw(
            f"scca(b={b:g}, c={c:g}, d={d:g})",
            _scca_shape(b, c, d),
            interior_jumps=(0.5,) if d == 0.0 else (),
        )
    if params:
        raise InputError("law", f"{key} takes no parameters; got {', '.join(params)}")
    if key not in _NAMED:
        raise InputError(
            "law", f"unknown law {name!r}; valid: {', '.join(LAW_NAMES)} (or polynomial)"
        )
    return _NAMED[key]


# Plain-function forms ----------------------------------------------------


def dwell(x: Any, h: float = 1.0, beta: float = 1.0) -> LawValues:
    """Dwell: the follower stands still (``h`` is ignored).

    Examples
    --------
    >>> dwell([0.0, 1.0]).s.tolist()
    [0.0, 0.0]
    """
    finite_scalar("h", h)  # ignored, but it must still be a number
    return _NAMED["dwell"](x, 0.0, beta)


def constant_velocity(x: Any, h: float = 1.0, beta: float = 1.0) -> LawValues:
    """Constant velocity ``s = hx``: flagged, its ends give infinite acceleration.

    Examples
    --------
    >>> constant_velocity([0.5], h=2.0, beta=0.5).v.tolist()
    [4.0]
    """
    return _NAMED["constant_velocity"](x, h, beta)


def simple_harmonic(x: Any, h: float = 1.0, beta: float = 1.0) -> LawValues:
    """Evaluate simple harmonic motion ``s = h/2 (1 − cos πx)`` (Norton eq. 8.5).

    Examples
    --------
    >>> round(float(simple_harmonic([0.0], 1.0, 1.0).a[0]), 4)   # π²/2
    4.9348
    """
    return _NAMED["simple_harmonic"](x, h, beta)


def cycloidal(x: Any, h: float = 1.0, beta: float = 1.0) -> LawValues:
    """Cycloidal ``s = h (x − sin 2πx / 2π)`` (Norton eq. 8.6, notes Fig. 8-12).

    Examples
    --------
    >>> round(float(cycloidal([0.5], 1.0, 1.0).v[0]), 6)   # 2h/β
    2.0
    """
    return _NAMED["cycloidal"](x, h, beta)


def poly345(x: Any, h: float = 1.0, beta: float = 1.0) -> LawValues:
    """3-4-5 polynomial ``s = h(10x³ − 15x⁴ + 6x⁵)`` (Norton eq. 8.23).

    Examples
    --------
    >>> poly345([0.5]).s.tolist()
    [0.5]
    """
    return _NAMED["poly345"](x, h, beta)


def poly4567(x: Any, h: float = 1.0, beta: float = 1.0) -> LawValues:
    """4-5-6-7 polynomial ``s = h(35x⁴ − 84x⁵ + 70x⁶ − 20x⁷)`` (Norton eq. 8.24).

    Examples
    --------
    >>> poly4567([0.5]).s.tolist()
    [0.5]
    """
    return _NAMED["poly4567"](x, h, beta)


def modified_trapezoid(x: Any, h: float = 1.0, beta: float = 1.0) -> LawValues:
    """Evaluate the modified trapezoid, SCCA b = 0.25, c = 0.5, d = 0.25 (notes Fig. 8-15).

    Examples
    --------
    >>> round(float(modified_trapezoid([0.125]).a[0]), 4)   # peak 8π/(π+2)
    4.8881
    """
    return _NAMED["modified_trapezoid"](x, h, beta)


def modified_sine(x: Any, h: float = 1.0, beta: float = 1.0) -> LawValues:
    """Evaluate the modified sine, SCCA b = 0.25, c = 0, d = 0.75 (notes Fig. 8-16).

    Examples
    --------
    >>> round(float(modified_sine([0.125]).a[0]), 3)
    5.528
    """
    return _NAMED["modified_sine"](x, h, beta)


def scca(x: Any, h: float = 1.0, beta: float = 1.0, *, b: float, c: float, d: float) -> LawValues:
    """Evaluate the general SCCA law (Norton eq. 8.16) with fractions ``b + c + d = 1``.

    Examples
    --------
    >>> round(float(scca([0.5], b=0.5, c=0.0, d=0.5).v[0]), 6)   # = cycloidal
    2.0
    """
    return get_law("scca", b=b, c=c, d=d)(x, h, beta)


def fall(law: MotionLaw | str, x: Any, h: float = 1.0, beta: float = 1.0) -> LawValues:
    """Evaluate the fall from ``h`` to 0: the mirror ``h − s_rise``, with v, a, j negated.

    Examples
    --------
    >>> fall("cycloidal", [0.0, 1.0], h=2.0).s.tolist()
    [2.0, 0.0]
    """
    if isinstance(law, str):
        law = get_law(law)
    instance("law", law, MotionLaw, "a law name or a MotionLaw")
    s, v, a, j = law(x, h, beta)
    return LawValues(h - s, -v, -a, -j)
