"""Plane geometry of graphical synthesis, done algebraically with complex numbers.

The notes (Ch. 3, "perp. bisector problem → required to do this
algebraically") and Norton, *Design of Machinery*, sec. 3.4–3.6 construct
linkages from perpendicular bisectors, their intersections and rotopoles. Each
construction here is the closed form of one of those drawings. Points are
complex numbers ``x + jy``; every function broadcasts over arrays of points.

Degenerate drawings (coincident points, parallel bisectors, collinear points,
a pure translation without a rotopole) raise :class:`~machdyn.errors.InputError`
naming the points involved, never return NaN or infinity.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import TINY, complex_array, point
from ..errors import InputError

__all__ = [
    "as_points",
    "circumcentre",
    "intersect_lines",
    "perpendicular_bisector",
    "rigid_motion",
    "rotopole",
]

#: Relative tolerance (of the drawing's size) below which points coincide or lines are parallel.
GEOMETRY_RTOL = 1e-9


def as_points(field: str, value: Any, count: int | None = None) -> np.ndarray:
    """Return ``value`` as a 1-D complex array of finite points.

    Accepts complex numbers, ``(x, y)`` pairs, or a sequence of either.

    Examples
    --------
    >>> as_points("c", [(0, 1), 2 + 3j])
    array([0.+1.j, 2.+3.j])
    >>> as_points("c", np.array([[0.0, 1.0], [2.0, 3.0]]))
    array([0.+1.j, 2.+3.j])
    >>> as_points("c", [0, 1j], count=3)
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: c: expected 3 points, got 2
    """
    is_xy = isinstance(value, np.ndarray) and value.ndim == 2 and value.shape[1] == 2
    if is_xy and value.dtype.kind in "fiu":  # an (N, 2) array of x, y
        value = value[:, 0].astype(float) + 1j * value[:, 1].astype(float)
    if isinstance(value, list | tuple) and not (
        len(value) == 2 and count == 1 and all(np.isscalar(v) for v in value)
    ):
        pts = np.array([point(f"{field}[{i}]", v) for i, v in enumerate(value)], dtype=complex)
    elif isinstance(value, list | tuple):
        pts = np.array([point(field, value)], dtype=complex)
    else:
        pts = np.atleast_1d(complex_array(field, value))
    if pts.ndim != 1:
        raise InputError(field, f"expected a flat list of points, got shape {pts.shape}")
    if count is not None and pts.size != count:
        raise InputError(field, f"expected {count} points, got {pts.size}")
    if not np.all(np.isfinite(pts)):
        raise InputError(field, "every coordinate must be finite")
    return pts


def _scale(*points: Any) -> float:
    """A length scale of a drawing (for relative tolerances)."""
    flat = np.concatenate([np.ravel(np.asarray(p, dtype=complex)) for p in points])
    return float(max(np.max(np.abs(flat - flat.mean())), np.max(np.abs(flat)), 1e-300))


def perpendicular_bisector(p: Any, q: Any) -> tuple[np.ndarray, np.ndarray]:
    """The perpendicular bisector of segment ``pq`` as (midpoint, unit direction).

    The direction is ``j (q − p) / |q − p|``: the segment turned 90° CCW, so
    points ``m + t·u`` with ``t > 0`` lie to the left of ``p → q``.

    Raises
    ------
    InputError
        If ``p`` and ``q`` coincide (the bisector is undefined).

    Examples
    --------
    >>> m, u = perpendicular_bisector(0, 2)
    >>> complex(m), complex(u)
    ((1+0j), 1j)
    """
    p = complex_array("p", p)
    q = complex_array("q", q)
    chord = q - p
    length = np.abs(chord)
    if np.any(length <= GEOMETRY_RTOL * _scale(p, q)):
        raise InputError(
            "points",
            "two positions coincide, so their perpendicular bisector is undefined; "
            "give distinct positions",
        )
    return 0.5 * (p + q), 1j * chord / length


def intersect_lines(p1: Any, u1: Any, p2: Any, u2: Any) -> np.ndarray:
    """Intersection of the lines ``p1 + s·u1`` and ``p2 + t·u2``.

    Raises
    ------
    InputError
        If the lines are parallel (no intersection, or the same line).

    Examples
    --------
    >>> complex(intersect_lines(0, 1, 1j, 1 + 1j))
    (-1+0j)
    """
    p1, u1, p2, u2 = (
        complex_array(name, v)
        for name, v in zip(("p1", "u1", "p2", "u2"), (p1, u1, p2, u2), strict=True)
    )
    for name, u in (("u1", u1), ("u2", u2)):
        if np.any(np.abs(u) < TINY):
            raise InputError(name, "must be a non-zero direction")
    cross = (np.conj(u1) * u2).imag  # u1 × u2
    if np.any(np.abs(cross) <= GEOMETRY_RTOL * np.abs(u1) * np.abs(u2)):
        raise InputError("lines", "the lines are parallel, so they do not intersect in one point")
    # p1 + s u1 = p2 + t u2  ->  s = ((p2 − p1) × u2) / (u1 × u2)
    s = (np.conj(p2 - p1) * u2).imag / cross
    return p1 + s * u1


def circumcentre(p1: Any, p2: Any, p3: Any) -> np.ndarray:
    """Centre of the circle through three points: the intersection of two bisectors.

    This is the notes' three-position construction: "use ⊥ bisectors of both
    C1C2, C2C3 and intersect them".

    Raises
    ------
    InputError
        If two points coincide or the three are collinear (parallel bisectors).

    Examples
    --------
    >>> z = complex(circumcentre(1, 1j, -1))
    >>> round(z.real, 12), round(z.imag, 12)
    (0.0, 0.0)
    """
    p1, p2, p3 = (
        complex_array(name, v) for name, v in zip(("p1", "p2", "p3"), (p1, p2, p3), strict=True)
    )
    for a, b, names in ((p1, p2, "1 and 2"), (p2, p3, "2 and 3"), (p1, p3, "1 and 3")):
        if np.any(np.abs(b - a) <= GEOMETRY_RTOL * _scale(p1, p2, p3)):
            raise InputError(
                "points", f"positions {names} coincide; three distinct positions are needed"
            )
    a, b = p2 - p1, p3 - p1
    cross = (np.conj(a) * b).imag
    if np.any(np.abs(cross) <= GEOMETRY_RTOL * np.abs(a) * np.abs(b)):
        raise InputError(
            "points",
            "the three positions are collinear, so their perpendicular bisectors are parallel "
            "and no pivot exists; move one position off the line",
        )
    # centre − p1 = −j (|a|² b − |b|² a) / (2 a × b)
    return p1 - 1j * (np.abs(a) ** 2 * b - np.abs(b) ** 2 * a) / (2.0 * cross)


def rigid_motion(c_from: Any, d_from: Any, c_to: Any, d_to: Any) -> tuple[np.ndarray, np.ndarray]:
    """The plane motion ``z ↦ rot·z + shift`` carrying line ``CD`` from one position to another.

    Returns ``(rot, shift)`` with ``|rot| = 1`` (the rotation ``e^{jΔθ}``).

    Raises
    ------
    InputError
        If ``C`` and ``D`` coincide in either position, or ``|CD|`` changes (not rigid).

    Examples
    --------
    >>> rot, shift = rigid_motion(0, 1, 1, 1 + 1j)     # quarter turn about 1
    >>> complex(rot), complex(rot * 0.5 + shift)
    (1j, (1+0.5j))
    """
    names = ("c_from", "d_from", "c_to", "d_to")
    c_from, d_from, c_to, d_to = (
        complex_array(name, v) for name, v in zip(names, (c_from, d_from, c_to, d_to), strict=True)
    )
    v_from, v_to = d_from - c_from, d_to - c_to
    l_from, l_to = np.abs(v_from), np.abs(v_to)
    scale = _scale(c_from, d_from, c_to, d_to)
    if np.any(l_from <= GEOMETRY_RTOL * scale) or np.any(l_to <= GEOMETRY_RTOL * scale):
        raise InputError(
            "c, d", "C and D coincide in a position; the coupler line needs two distinct points"
        )
    if np.any(np.abs(l_from - l_to) > 1e-3 * np.maximum(l_from, l_to)):
        raise InputError(
            "c, d",
            f"|CD| differs between positions ({np.ravel(l_from)[0]:.6g} vs "
            f"{np.ravel(l_to)[0]:.6g}); "
            "a rigid coupler keeps C and D the same distance apart",
        )
    rot = (v_to / l_to) / (v_from / l_from)
    return rot, c_to - rot * c_from


def rotopole(c1: Any, d1: Any, c2: Any, d2: Any) -> np.ndarray:
    """The rotopole: the one point about which a rotation carries C1D1 onto C2D2.

    It is the intersection of the perpendicular bisectors of ``C1C2`` and
    ``D1D2`` (Norton sec. 3.4, "a link at the rotopole fixed to CD"), computed
    as the fixed point of the rigid motion, ``shift / (1 − rot)``, which also
    covers the case where both bisectors coincide.

    Raises
    ------
    InputError
        If the motion is a pure translation (no rotation: the pole is at infinity).

    Examples
    --------
    >>> complex(rotopole(1, 2, 1j, 2j))       # a quarter turn about the origin
    0j
    """
    rot, shift = rigid_motion(c1, d1, c2, d2)
    if np.any(np.abs(1.0 - rot) <= 1e-9):
        raise InputError(
            "c, d",
            "C1D1 and C2D2 are parallel and equally oriented (a pure translation); the rotopole "
            "is at infinity, use two_position() with pivots on the bisectors instead",
        )
    return shift / (1.0 - rot)
