"""Instant centres in homogeneous coordinates, and Kennedy's rule on the linear graph.

A point is stored as ``(x, y, w)``: the Cartesian point ``(x/w, y/w)`` when
``w ≠ 0``, and the *direction* ``(x, y)`` at infinity when ``w = 0`` (the
instant centre of a slider and its guide, or of two links whose Kennedy lines
are parallel). The line through two points is their cross product and the
intersection of two lines is the cross product of the lines, so centres at
infinity need no special cases (Norton, *Design of Machinery*, sec. 6.4; the
notes: "I.C. of two bodies in sliding contact is located at ∞ along the normal
to the plane of slip").

:func:`kennedy` finds every centre of a set of bodies from the ones known by
inspection (the *primary* centres) the way the notes' Problem 6-13 does it on
the linear graph: a centre ``I_ab`` is the intersection of two Kennedy lines
``I_ak – I_kb`` and ``I_am – I_mb`` ("the three instant centres of any three
bodies in plane motion are collinear"), or of one such line and a line it is
known to lie on (the common normal of a pin-in-slot), repeated until no more
centres can be found. At each sample the best-conditioned pair of lines is
used, so a centre whose two first lines coincide at some pose is still found
from a third. Where the rule leaves a centre undetermined (some multi-loop
linkages, or lines that coincide at a sample), :func:`relative_centre` takes
it from the velocity field: the point where the two bodies' velocities agree.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from itertools import combinations
from typing import Any

import numpy as np

from ._validate import broadcast, complex_array, finite_array, finite_scalar
from .errors import InputError, ModelError

__all__ = [
    "InstantCentre",
    "InstantCentres",
    "at_infinity",
    "collinearity",
    "finite",
    "instant_centres_of",
    "intersect",
    "line_through",
    "linkage_centres",
]

#: |w| below this fraction of |(x, y)| marks a point at infinity.
_INFINITY_RTOL = 1e-12
#: Two unit lines whose cross product is shorter than this are the same line.
_SAME_LINE = 1e-9
#: Relative velocity and Δω below this fraction of the speeds: no relative motion.
_STILL = 1e-12


def _finite(z: np.ndarray | complex) -> np.ndarray:
    """:func:`finite` for arguments already checked."""
    z = np.asarray(z, dtype=complex)
    return np.stack([z.real, z.imag, np.ones(z.shape)], axis=-1)


def _at_infinity(direction: np.ndarray | complex) -> np.ndarray:
    """:func:`at_infinity` for arguments already checked."""
    d = np.asarray(direction, dtype=complex)
    return np.stack([d.real, d.imag, np.zeros(d.shape)], axis=-1)


def finite(z: np.ndarray | complex) -> np.ndarray:
    """Homogeneous coordinates ``(x, y, 1)`` of finite points given as complex numbers.

    ``z`` may hold NaN (an unassembled sample): its coordinates stay NaN.

    Examples
    --------
    >>> finite(3 + 4j).tolist()
    [3.0, 4.0, 1.0]
    """
    return _finite(complex_array("z", z, nan_ok=True))


def at_infinity(direction: np.ndarray | complex) -> np.ndarray:
    """Homogeneous coordinates ``(x, y, 0)`` of the point at infinity along ``direction``.

    Examples
    --------
    >>> at_infinity(1j).tolist()
    [0.0, 1.0, 0.0]
    """
    d = complex_array("direction", direction, nan_ok=True)
    if np.any(d == 0):
        raise InputError("direction", "must be non-zero (a direction), got 0")
    return _at_infinity(d)


def line_through(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The line through two homogeneous points (their cross product).

    Examples
    --------
    >>> line_through(finite(0j), finite(1 + 0j)).tolist()  # the x axis: 0 x + 1 y + 0 = 0
    [0.0, 1.0, 0.0]
    """
    return _cross3(*_homogeneous(p=p, q=q))


def intersect(l1: np.ndarray, l2: np.ndarray) -> np.ndarray:
    """The intersection of two homogeneous lines (their cross product)."""
    return _cross3(*_homogeneous(l1=l1, l2=l2))


def _homogeneous(**arrays: Any) -> list[np.ndarray]:
    """Homogeneous coordinates (last axis of length 3, NaN allowed) that broadcast together."""
    out = []
    for field, value in arrays.items():
        h = finite_array(field, value, nan_ok=True)
        if h.ndim == 0 or h.shape[-1] != 3:
            raise InputError(
                field, f"must be homogeneous coordinates (x, y, w), shape (..., 3); got {h.shape}"
            )
        out.append(h)
    broadcast(**dict(zip(arrays, out, strict=True)))
    return out


def _cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a × b`` over the last axis (length 3), by components (faster than np.cross)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def _norm3(h: np.ndarray) -> np.ndarray:
    """Euclidean length over the last axis (length 3), without a reduction.

    Scaled by the largest coordinate first, so that coordinates of 1e200 (or
    1e-200) do not overflow (underflow) when squared; NaN for (0, 0, 0).
    """
    big = np.maximum(np.maximum(np.abs(h[..., 0]), np.abs(h[..., 1])), np.abs(h[..., 2]))
    with np.errstate(divide="ignore", invalid="ignore"):
        u = h / big[..., None]
    return big * np.sqrt(u[..., 0] * u[..., 0] + u[..., 1] * u[..., 1] + u[..., 2] * u[..., 2])


def _finite3(h: np.ndarray) -> np.ndarray:
    """True where all three coordinates are finite."""
    return np.isfinite(h[..., 0]) & np.isfinite(h[..., 1]) & np.isfinite(h[..., 2])


def collinearity(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Scale-free collinearity residual of three homogeneous points (0 when collinear).

    The determinant of the three normalised coordinate vectors; it is the sine
    of a "solid angle" and is ~1e-16 for collinear points whatever their size.
    """
    p, q, r = _homogeneous(p=p, q=q, r=r)

    def unit(v: np.ndarray) -> np.ndarray:
        with np.errstate(divide="ignore", invalid="ignore"):  # (0, 0, 0): NaN, not a point
            return v / _norm3(v)[..., None]

    p, q, r = np.broadcast_arrays(unit(p), unit(q), unit(r))
    return np.linalg.det(np.stack([p, q, r], axis=-2))


@dataclass(frozen=True)
class InstantCentre:
    """One instant centre over a set of samples.

    Attributes
    ----------
    homogeneous : ndarray, shape (..., 3)
        ``(x, y, w)`` normalised to unit length with ``w >= 0``; NaN where the
        centre is undetermined (see the owner's ``reason``).
    scale : float
        A length of the mechanism (default 1): a centre more than 10¹² of it
        from the origin is at infinity.
    """

    homogeneous: np.ndarray
    scale: float = 1.0

    @property
    def at_infinity(self) -> np.ndarray:
        """True where the centre is a point at infinity (10¹² :attr:`scale` or farther)."""
        h = self.homogeneous
        return np.abs(h[..., 2]) * self.scale <= _INFINITY_RTOL * np.hypot(h[..., 0], h[..., 1])

    @property
    def point(self) -> np.ndarray:
        """The centre as a complex number; NaN where it is at infinity (see ``direction``)."""
        h = self.homogeneous
        inf = self.at_infinity
        with np.errstate(divide="ignore", invalid="ignore"):
            z = (h[..., 0] + 1j * h[..., 1]) / h[..., 2]
        return np.where(inf, complex(np.nan, np.nan), z)

    @property
    def direction(self) -> np.ndarray:
        """Unit direction (complex) of a centre at infinity; NaN where it is finite."""
        h = self.homogeneous
        with np.errstate(divide="ignore", invalid="ignore"):
            d = (h[..., 0] + 1j * h[..., 1]) / np.hypot(h[..., 0], h[..., 1])
        return np.where(self.at_infinity, d, complex(np.nan, np.nan))


def _normalise(h: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):
        h = h / _norm3(h)[..., None]
        flip = h[..., 2:3] < 0
        return np.where(flip, -h, h)


class InstantCentres(Mapping):
    """The instant centres of a mechanism, keyed by pairs of bodies.

    Bodies are link numbers (``ics[1, 3]``, a four-bar) or names
    (``ics["ground", "crank"]``, a :class:`~machdyn.linkage.Linkage`); either
    order of the pair works. Iteration yields the pairs in the order of
    :attr:`bodies`.

    Attributes
    ----------
    bodies : tuple
        The bodies, ground first.
    valid : ndarray of bool
        False at samples where the mechanism could not be assembled or a centre
        is undetermined (``ok`` is the same array).
    reason : ndarray of str
        Why a sample is not valid ('' where it is).
    scale : float
        A length of the mechanism, which tells a far centre from one at
        infinity (:attr:`InstantCentre.scale`).
    """

    def __init__(
        self,
        centres: Mapping[tuple[Any, Any], np.ndarray],
        valid: np.ndarray,
        *,
        bodies: Sequence[Hashable] | None = None,
        reason: np.ndarray | None = None,
        methods: Mapping[tuple[Any, Any], str] | None = None,
        scale: float = 1.0,
    ) -> None:
        if bodies is None:
            bodies = sorted({b for pair in centres for b in pair})
        self.bodies = tuple(bodies)
        self.scale = float(scale)
        self._index = {b: k for k, b in enumerate(self.bodies)}
        self._centres = {
            self._key(k): InstantCentre(_normalise(np.asarray(v, dtype=float)), scale)
            for k, v in centres.items()
        }
        self._methods = {self._key(k): m for k, m in (methods or {}).items()}
        self.valid = np.asarray(valid, dtype=bool)
        if reason is None:
            reason = np.where(self.valid, "", "cannot be assembled here")
        self.reason = np.asarray(reason, dtype=object)

    @property
    def ok(self) -> np.ndarray:
        """True where every centre is determined (the same as ``valid``)."""
        return self.valid

    def _key(self, pair: tuple[Any, Any], fields: tuple[str, str] = ("key", "key")) -> tuple:
        a, b = (self._body(field, x) for field, x in zip(fields, pair, strict=True))
        return (a, b) if self._index[a] < self._index[b] else (b, a)

    def _body(self, field: str, body: Any) -> Any:
        """``body`` if it is one of :attr:`bodies`, else an error naming ``field``."""
        try:
            known = not isinstance(body, bool | np.bool_) and body in self._index
        except TypeError:  # unhashable
            known = False
        if not known:
            raise InputError(
                field, f"unknown body {body!r}; bodies: {', '.join(map(str, self.bodies))}"
            )
        return body

    def __getitem__(self, key: tuple[Any, Any]) -> InstantCentre:
        try:
            pair = self._key(key)
        except (InputError, TypeError, ValueError) as exc:  # the Mapping protocol's KeyError
            raise KeyError(str(exc)) from None
        return self._centres[pair]

    def __iter__(self) -> Iterator[tuple[Any, Any]]:
        return iter(sorted(self._centres, key=lambda k: (self._index[k[0]], self._index[k[1]])))

    def __len__(self) -> int:
        return len(self._centres)

    def __repr__(self) -> str:
        return f"InstantCentres({', '.join(f'I({i},{j})' for i, j in self)})"

    def method(self, i: Any, j: Any) -> str:
        """How ``I_ij`` was found: ``"joint"`` (by inspection), ``"kennedy"`` or ``"velocity"``."""
        return self._methods.get(self._key((i, j), ("i", "j")), "")

    def _ground(self, ground: Any) -> Any:
        return self.bodies[0] if ground is None else self._body("ground", ground)

    def omega_ratio(self, i: Any, j: Any, ground: Any = None) -> np.ndarray:
        """Angular velocity ratio ``ω_j / ω_i`` of two links, from the centres alone.

        ``I_gi``, ``I_gj`` and ``I_ij`` are collinear (Kennedy); the common point
        ``I_ij`` moves alike on both links, so ``ω_i · |I_gi I_ij| = ω_j · |I_gj I_ij|``
        with signs: ``ω_j/ω_i = (I_ij − I_gi) / (I_ij − I_gj)`` along that line.
        Exact when ``I_ij`` is at infinity (ratio 1: equal angular velocities).
        ``ground`` defaults to the first body.
        """
        g = self._ground(ground)
        i, j = self._body("i", i), self._body("j", j)
        p = self[g, i].homogeneous
        q = self[g, j].homogeneous
        x = self[i, j].homogeneous
        # Signed ratio along the line, written with homogeneous coordinates so
        # that a point at infinity (x_w = 0) needs no special case:
        # (X/xw − P/pw) / (X/xw − Q/qw) = (X pw − P xw) qw / ((X qw − Q xw) pw).
        num = x[..., :2] * p[..., 2:3] - p[..., :2] * x[..., 2:3]
        den = x[..., :2] * q[..., 2:3] - q[..., :2] * x[..., 2:3]
        # project on the line direction for a scalar ratio
        axis = np.where(np.abs(den[..., :1]) >= np.abs(den[..., 1:2]), 0, 1)
        num_s = np.take_along_axis(num, axis, axis=-1)[..., 0] * q[..., 2]
        den_s = np.take_along_axis(den, axis, axis=-1)[..., 0] * p[..., 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = num_s / den_s
        return np.where(self.valid, ratio, np.nan)

    def mechanical_advantage(
        self, input: Any, output: Any, r_in: float = 1.0, r_out: float = 1.0, ground: Any = None
    ) -> np.ndarray:
        """Mechanical advantage ``F_out / F_in`` between two links, from the centres alone.

        A force ``F_in`` at lever arm ``r_in`` on link ``input`` drives a load
        ``F_out`` at lever arm ``r_out`` on link ``output``; by the power
        identity (the notes, review lecture 2) ``MA = (r_in ω_in) / (r_out ω_out)``
        with ``ω_out/ω_in`` from :meth:`omega_ratio` (signed). When the output
        translates (its centre with the ground is at infinity) the load acts
        along its motion and ``MA = r_in |ω_in| / |v_out|``, with ``v_out`` the
        velocity of ``I_in,out`` as a point of the input, ``ω_in × (I_in,out −
        I_g,in)`` (``r_out`` is then not used); likewise ``MA = |v_in| / (r_out
        |ω_out|)`` for a translating input. Infinite where the output stops (a
        toggle), NaN where the mechanism is not assembled (and when both links
        translate).

        Examples
        --------
        >>> from machdyn import FourBar
        >>> ics = FourBar(8, 4, 7, 6).instant_centres(np.radians(60))
        >>> ma = ics.mechanical_advantage(2, 4, r_in=1.0, r_out=2.0)
        >>> bool(np.isclose(ma, FourBar(8, 4, 7, 6).mechanical_advantage(np.radians(60), 1, 2)))
        True
        """
        g = self._ground(ground)
        input, output = self._body("input", input), self._body("output", output)
        r_in = finite_scalar("r_in", r_in)
        r_out = finite_scalar("r_out", r_out)
        with np.errstate(over="ignore", divide="ignore"):
            arms = r_in / r_out if r_out else np.inf
        if not np.isfinite(arms):
            raise InputError(
                "r_out", f"must be a non-zero lever arm comparable to r_in={r_in:g}, got {r_out:g}"
            )
        slides_out = self[g, output].at_infinity
        slides_in = self[g, input].at_infinity
        ratio = self.omega_ratio(input, output, g)
        with np.errstate(divide="ignore", invalid="ignore"):
            ma = (r_in / r_out) / ratio
            v_out = _speed_per_omega(self[g, input], self[input, output])
            v_in = _speed_per_omega(self[g, output], self[input, output])
            ma = np.where(slides_out & ~slides_in, r_in / v_out, ma)
            ma = np.where(slides_in & ~slides_out, v_in / r_out, ma)
        return np.where(self.valid, ma, np.nan)


def _speed_per_omega(pivot: InstantCentre, common: InstantCentre) -> np.ndarray:
    """|I_common − I_pivot|: speed of the common centre per unit ω of the pivoting link."""
    return np.abs(common.point - pivot.point)


# --------------------------------------------------------------------------------------
# Kennedy's rule on the linear graph, and the velocity field as a fallback


@dataclass(frozen=True)
class BodyMotion:
    """The velocity field of a body over samples: ``v(P) = V + j ω (P − R)``.

    ``R`` is a reference point of the body (complex), ``V`` its velocity and
    ``omega`` the body's angular velocity (arrays of the samples' shape).
    """

    R: np.ndarray
    V: np.ndarray
    omega: np.ndarray


def relative_centre(a: BodyMotion, b: BodyMotion) -> np.ndarray:
    """The instant centre of two bodies from their velocity fields (homogeneous).

    The point where ``v_a(P) = v_b(P)``:
    ``j (ω_b − ω_a) P = (V_a − V_b) + j (ω_b R_b − ω_a R_a)``. With equal
    angular velocities it is at infinity, normal to the relative velocity; with
    no relative motion at all it is undetermined (all zeros, normalised to NaN).
    """
    num = (a.V - b.V) + 1j * (b.omega * b.R - a.omega * a.R)
    d_omega = b.omega - a.omega
    # no relative motion but rounding: all zeros (else the noise reads as a direction)
    speeds = np.abs(a.V) + np.abs(b.V) + np.abs(a.omega * a.R) + np.abs(b.omega * b.R)
    still = (np.abs(num) <= _STILL * speeds) & (
        np.abs(d_omega) <= _STILL * (np.abs(a.omega) + np.abs(b.omega))
    )
    z = np.where(still, 0j, -1j * num)  # P = num / (j Δω) = −j num / Δω
    return np.stack([z.real, z.imag, np.where(still, 0.0, d_omega)], axis=-1)


def kennedy(
    bodies: Sequence[Hashable],
    known: Mapping[tuple[Any, Any], np.ndarray],
    lines: Mapping[tuple[Any, Any], Sequence[np.ndarray]] | None = None,
    fallback: Callable[[Any, Any], np.ndarray] | None = None,
) -> tuple[dict[tuple[Any, Any], np.ndarray], dict[tuple[Any, Any], str]]:
    """Every instant centre of ``bodies`` by Kennedy's rule, from the primary ones.

    Parameters
    ----------
    bodies : sequence
        The bodies (ground first by convention); pairs are ordered as listed.
    known : mapping
        Primary centres ``(a, b) -> (..., 3)`` homogeneous arrays (pins, sliders,
        rolling contacts: found by inspection).
    lines : mapping, optional
        Lines ``(a, b) -> [(..., 3), ...]`` a centre is known to lie on (the
        common normal of a pin-in-slot).
    fallback : callable, optional
        ``fallback(a, b)`` → homogeneous centre from the velocity field, used
        for centres (or samples) Kennedy's rule leaves undetermined.

    Returns
    -------
    centres, methods : dict
        Homogeneous centre of every pair (normalised; NaN where undetermined)
        and how it was found (``"joint"``, ``"kennedy"``, ``"velocity"``).

    Examples
    --------
    A four-bar at θ2 = 90°: the primary centres are its pins; Kennedy's rule
    puts I13 where O2A meets O4B and I24 where O2O4 meets AB.

    >>> A, B = 4j, 7 + 5j
    >>> known = {(1, 2): finite(0j), (2, 3): finite(A), (3, 4): finite(B), (1, 4): finite(8 + 0j)}
    >>> centres, how = kennedy([1, 2, 3, 4], known)
    >>> complex(np.round(InstantCentre(centres[1, 3]).point, 12)), how[1, 3]
    (40j, 'kennedy')
    """
    lines = lines or {}
    pairs = list(combinations(bodies, 2))
    order = {b: k for k, b in enumerate(bodies)}

    def key(a: Any, b: Any) -> tuple[Any, Any]:
        return (a, b) if order[a] < order[b] else (b, a)

    centres = {key(*p): _normalise(np.asarray(v, dtype=float)) for p, v in known.items()}
    methods = dict.fromkeys(centres, "joint")
    extra = {key(*p): [_unit_line(v) for v in ls] for p, ls in lines.items()}
    unknown = [p for p in pairs if p not in centres]
    progress = True
    while progress and unknown:
        progress = False
        for a, b in list(unknown):
            candidates = [
                _unit_line(_cross3(centres[key(a, k)], centres[key(k, b)]))
                for k in bodies
                if k not in (a, b) and key(a, k) in centres and key(k, b) in centres
            ]
            candidates += extra.get((a, b), [])
            if len(candidates) < 2:
                continue
            centres[(a, b)] = _best_intersection(candidates)
            methods[(a, b)] = "kennedy"
            unknown.remove((a, b))
            progress = True
    if fallback is not None:
        for pair in pairs:
            h = centres.get(pair)
            missing = None if h is None else ~_finite3(h)
            if h is not None and not missing.any():
                continue
            by_velocity = _normalise(np.asarray(fallback(*pair), dtype=float))
            if h is None:
                centres[pair], methods[pair] = by_velocity, "velocity"
            else:
                centres[pair] = np.where(missing[..., None], by_velocity, h)
    return centres, methods


def _unit_line(line: np.ndarray) -> np.ndarray:
    """The line normalised to unit length; NaN where it is no line (coincident points)."""
    n = _norm3(line)[..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(n > _SAME_LINE, line / n, np.nan)


def _best_intersection(lines: list[np.ndarray]) -> np.ndarray:
    """Per sample, the intersection of the two candidate lines that cross most squarely."""
    best = None
    quality = None
    for p, q in combinations(lines, 2):
        h = _cross3(p, q)
        size = _norm3(h)
        size = np.where(np.isfinite(size), size, -1.0)
        if best is None:
            best, quality = h, size
        else:
            better = size > quality
            best = np.where(better[..., None], h, best)
            quality = np.where(better, size, quality)
    assert best is not None and quality is not None
    best = np.where((quality > _SAME_LINE)[..., None], best, np.nan)
    return _normalise(best)


# --------------------------------------------------------------------------------------
# Closed-form models


def fourbar_centres(
    r1: float, A: np.ndarray, B: np.ndarray, valid: np.ndarray, scale: float
) -> InstantCentres:
    """The six centres of a pin-jointed four-bar with ``O2`` at 0 and ``O4`` at ``r1``.

    Kennedy's lines are met in units of ``scale`` (the longest link), so that links
    of 1e-200 or 1e200 neither underflow nor overflow.
    """
    scale = float(scale)
    A = np.asarray(A, dtype=complex) / scale
    I12 = _finite(np.zeros(A.shape, dtype=complex))
    I14 = _finite(np.full(A.shape, r1 / scale, dtype=complex))
    I23 = _finite(A)
    I34 = _finite(np.asarray(B, dtype=complex) / scale)
    I13 = _cross3(_cross3(I12, I23), _cross3(I14, I34))
    I24 = _cross3(_cross3(I12, I14), _cross3(I23, I34))
    centres = {(1, 2): I12, (1, 4): I14, (2, 3): I23, (3, 4): I34, (1, 3): I13, (2, 4): I24}
    return InstantCentres(
        {k: _unscaled(v, scale) for k, v in centres.items()},
        valid,
        bodies=(1, 2, 3, 4),
        methods={(1, 3): "kennedy", (2, 4): "kennedy"}
        | dict.fromkeys([(1, 2), (1, 4), (2, 3), (3, 4)], "joint"),
        scale=scale,
    )


# --------------------------------------------------------------------------------------
# Any drawn linkage


def instant_centres_of(lk: Any, values: Any, velocity: Any = None) -> InstantCentres:
    """Solve a :class:`~machdyn.linkage.Linkage` at driver ``values`` and find all its centres.

    ``velocity`` (the drivers' speeds) defaults to 1 for a single driver: a
    one-freedom linkage's centres do not depend on its speed. A linkage with
    several drivers needs them only when Kennedy's rule leaves a centre to the
    velocity field (its centres then depend on the ratio of the speeds).

    Examples
    --------
    The notes' four-bar HW 6 (8, 4, 7, 6) drawn at θ2 = 0, as a Linkage:

    >>> from machdyn.linkage import Linkage
    >>> lk = (Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0), "B": (7.625, 35.859375**0.5)})
    ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
    ...       .link("rocker", "O4", "B").drive("crank"))
    >>> ics = instant_centres_of(lk, np.radians([30.0, 60.0]))
    >>> len(ics), ics.method("ground", "coupler")
    (6, 'kennedy')
    """
    return linkage_centres(lk, _solve_with_speeds(lk, values, velocity))


def _solve_with_speeds(lk: Any, values: Any, velocity: Any) -> Any:
    """``lk.solve(values, velocity)`` with the speeds checked (1 for a single driver)."""
    _check_linkage(lk)
    if velocity is None and len(lk.drivers) == 1:
        velocity = 1.0
    if not isinstance(values, Mapping):
        values = finite_array("values", values)
    if velocity is not None and not isinstance(velocity, Mapping):
        speeds = np.asarray(finite_array("velocity", velocity))
        try:
            np.broadcast_shapes(speeds.shape, np.shape(values))
        except ValueError:
            raise InputError(
                "velocity", f"shape {speeds.shape} does not match values {np.shape(values)}"
            ) from None
    return lk.solve(values, velocity=velocity)


def linkage_centres(lk: Any, motion: Any) -> InstantCentres:
    """All instant centres of a :class:`~machdyn.linkage.Linkage` over a solved motion.

    Reads only the linkage's public view (``points``, ``links``, ``joints``)
    and the motion's ``theta``, ``omega``, ``points`` and ``point_velocity``.
    Primary centres by inspection: a pin joins each pair of its links at the
    pin; a slider's centre is at infinity normal to the slide (which turns with
    the link it slides on), a curved slider's at the centre of curvature; a
    rolling contact's is the contact point. A pin-in-slot's centre lies on the
    slot's normal through the pin (through the centre of a curved slot): a line
    for Kennedy's rule, not a point. A linear actuator counts as its barrel and rod
    (two pins and a slider), used on the way and left out of the result. The
    rest follows by :func:`kennedy`, with the velocity field (the motion's
    ω and point velocities) for centres the rule leaves undetermined.

    Samples where the motion is not ok carry its reason; a centre of two links
    with no relative motion at a sample (every point would do) is flagged too.
    """
    _check_linkage(lk)
    from .linkage import LinkageMotion

    if not isinstance(motion, LinkageMotion):
        raise InputError("motion", f"must be a LinkageMotion from lk.solve(), got {motion!r}")
    from .linkage._common import check_motion

    check_motion(lk, motion)
    bodies = ["ground", *lk.links]
    fields = {b: _body_motion(lk, motion, b) for b in bodies}
    known: dict[tuple[str, str], np.ndarray] = {}
    lines: dict[tuple[str, str], list[np.ndarray]] = {}
    virtual: list[str] = []
    for joint in lk.joints:
        kind = joint.kind
        if kind == "pin":
            at = _finite(motion.points[joint.points[0]])
            for a, b in combinations(joint.links, 2):
                known.setdefault((a, b), at)
        elif kind == "slider" and getattr(joint, "centre", None) is not None:
            # a curved slide: the block turns about the centre of curvature
            known.setdefault(tuple(joint.links), _finite(motion.points[joint.centre]))
        elif kind == "slider":
            block, on = joint.links
            normal = 1j * _turned(lk, motion, on, joint.direction)
            known.setdefault((block, on), _at_infinity(normal))
        elif kind == "slot":
            link, on = joint.links
            pin = _finite(motion.points[joint.points[0]])
            if getattr(joint, "centre", None) is not None:  # the normal: through the centre
                normal = _finite(motion.points[joint.centre])
            else:
                normal = _at_infinity(1j * _turned(lk, motion, on, joint.direction))
            lines.setdefault((link, on), []).append(_cross3(pin, normal))
        elif kind == "roll":
            known.setdefault(tuple(joint.links), _finite(_contact_point(lk, motion, joint)))
        elif kind == "actuator":
            barrel, rod = f"{joint.name}:barrel", f"{joint.name}:rod"
            virtual += [barrel, rod]
            start, end = (motion.points[p] for p in joint.points)
            known[(joint.links[0], barrel)] = _finite(start)
            known[(joint.links[1], rod)] = _finite(end)
            known[(barrel, rod)] = _at_infinity(1j * (end - start))
            fields[barrel], fields[rod] = _actuator_motion(motion, joint)
    scale = _scale(lk)
    known = {k: _scaled(v, scale) for k, v in known.items()}
    lines = {k: [_scaled_line(v, scale) for v in ls] for k, ls in lines.items()}

    def by_velocity(a: str, b: str) -> np.ndarray:
        if fields[a] is None or fields[b] is None:
            raise _needs_velocity(lk)
        return _scaled(relative_centre(fields[a], fields[b]), scale)

    centres, methods = kennedy([*bodies, *virtual], known, lines, by_velocity)
    shape = np.shape(motion.ok)
    valid = np.array(motion.ok, dtype=bool, copy=True)
    reason = np.array(motion.reason, dtype=object, copy=True)
    out = {}
    for (a, b), h in centres.items():
        if a in virtual or b in virtual:
            continue
        h = _unscaled(h, scale)
        bad = valid & ~_finite3(h)
        reason = np.where(
            bad, f"I({a},{b}) undetermined: the links have no relative motion here", reason
        )
        valid &= ~bad
        out[(a, b)] = np.where(valid.reshape(*shape, 1), h, np.nan)
    return InstantCentres(
        out,
        valid,
        bodies=bodies,
        reason=reason,
        methods={k: v for k, v in methods.items() if k in out},
        scale=scale,
    )


def _check_linkage(lk: Any) -> None:
    from .linkage import Linkage

    if not isinstance(lk, Linkage):
        raise InputError("lk", f"must be a machdyn.linkage.Linkage, got {lk!r}")


def _body_motion(lk: Any, motion: Any, body: str) -> BodyMotion | None:
    shape = np.shape(motion.ok)
    if body == "ground":
        zero = np.zeros(shape)
        return BodyMotion(zero + 0j, zero + 0j, zero)
    if motion.omega is None or motion.point_velocity is None:
        return None
    first = lk.links[body].points[0]
    return BodyMotion(motion.points[first], motion.point_velocity[first], motion.omega[body])


def _actuator_motion(motion: Any, joint: Any) -> tuple[BodyMotion | None, BodyMotion | None]:
    """Barrel (pinned at start) and rod (pinned at end) turn with the line start→end."""
    if motion.point_velocity is None:
        return None, None
    start, end = joint.points
    r = motion.points[end] - motion.points[start]
    v = motion.point_velocity[end] - motion.point_velocity[start]
    with np.errstate(divide="ignore", invalid="ignore"):
        omega = (v / r).imag
    barrel = BodyMotion(motion.points[start], motion.point_velocity[start], omega)
    rod = BodyMotion(motion.points[end], motion.point_velocity[end], omega)
    return barrel, rod


def _ref_angle(lk: Any, link: str) -> float:
    """A link's ``theta`` in the drawing: its first→second point line (0 for one point)."""
    if link == "ground":
        return 0.0
    pts = lk.links[link].points
    if len(pts) < 2:
        return 0.0
    z = lk.points[pts[1]] - lk.points[pts[0]]
    return float(np.angle(z)) if abs(z) else 0.0


def _turned(lk: Any, motion: Any, link: str, direction: complex) -> np.ndarray:
    """A direction drawn in ``link``'s frame, as it is at each sample."""
    if link == "ground":
        return np.full(np.shape(motion.ok), complex(direction))
    return direction * np.exp(1j * (motion.theta[link] - _ref_angle(lk, link)))


def _contact_point(lk: Any, motion: Any, joint: Any) -> np.ndarray:
    """The contact point of a rolling pair (external, internal, or on a straight profile)."""
    b = joint.links[1]
    ca, cb = (motion.points[p] for p in joint.points)
    r_a, r_b = joint.radii
    if np.isinf(r_b):  # straight profile of b through cb, normal (drawn) toward ca
        drawn = lk.points[joint.points[0]] - lk.points[joint.points[1]]
        normal = _turned(lk, motion, b, drawn / abs(drawn))
        return ca - r_a * normal
    with np.errstate(divide="ignore", invalid="ignore"):
        u = (cb - ca) / np.abs(cb - ca)
    if joint.internal and r_a < r_b:  # a rolls inside the ring b
        return ca - r_a * u
    return ca + r_a * u


def _scale(lk: Any) -> float:
    """A length of the drawing, to keep homogeneous coordinates well balanced."""
    pts = np.array(list(lk.points.values()), dtype=complex)
    size = float(np.max(np.abs(pts - pts.mean()))) if pts.size else 0.0
    return size if size > 0 else 1.0


def _scaled(h: np.ndarray, scale: float) -> np.ndarray:
    return h * np.array([1.0, 1.0, scale])


def _scaled_line(line: np.ndarray, scale: float) -> np.ndarray:
    # a line (a, b, c) with a x + b y + c = 0 keeps its points under x → x/L: (a L, b L, c)
    return line * np.array([scale, scale, 1.0])


def _unscaled(h: np.ndarray, scale: float) -> np.ndarray:
    return h * np.array([1.0, 1.0, 1.0 / scale])


def _needs_velocity(lk: Any) -> Exception:
    return ModelError(
        "some instant centres of this linkage are not fixed by Kennedy's rule and depend on "
        f"how fast each driver moves ({', '.join(lk.drivers)}): pass velocity={{driver: "
        "speed}} so they can be taken from the velocity field"
    )
