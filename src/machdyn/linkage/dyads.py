"""Closed-form dyads: the position of a two-link Assur group, vectorised.

A dyad is two links joined to each other and each to a known body, every joint
a revolute (R) or a prismatic (P) pair. Its position is a circle–circle (RRR),
circle–line (RRP, PRR), tangent-line (RPR) or line–line (PRP, RPP)
intersection (Norton, *Design of Machinery*, §4.5–4.7 write them as vector
loops; these are the same equations solved geometrically). Points and
directions are complex numbers ``x + jy``; every argument broadcasts like a
ufunc, over poses **and** over dimensions (arrays of lengths and pivots), so one
call solves a sweep of one linkage or one pose of a million linkages.

Each solver returns its answer and an ``ok`` mask (False where the dyad cannot
be assembled: the circles do not meet, the lines are parallel); ``sign``
(+1 or −1) picks the assembly (branch) and is never switched.

The derivatives of every dyad are linear in the unknown rates with the same
2 × 2 Jacobian as the position (DESIGN.md): :func:`solve_pair` solves
``c1 x1 + c2 x2 = k`` for real ``x1, x2`` by Cramer's rule.

Examples
--------
The HW 6 four-bar (GCRR 8-4-7-6) at θ2 = 0: crank pin A = 4, rocker pivot
O4 = 8, coupler 7, rocker 6; B on the left of A → O4 (form 1):

>>> import numpy as np
>>> B, _, ok = rrr(4.0 + 0j, 8.0 + 0j, 7.0, 6.0, sign=1)
>>> round(float(np.degrees(np.angle(B - 4.0))), 2)  # θ3 of the notes
58.81
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from .._validate import LIMIT, TINY, as_array, broadcast, magnitude
from ..errors import InputError

__all__ = [
    "Pair",
    "PinOnLine",
    "Slotted",
    "TwoLines",
    "line_line",
    "rpr",
    "rrp",
    "rrr",
    "solve_pair",
]


class PinOnLine(NamedTuple):
    """The pin ``B`` of an RRR or RRP dyad, ``s`` (RRP: ``B = G + s u``) and ``ok``."""

    B: np.ndarray
    s: np.ndarray
    ok: np.ndarray


class Slotted(NamedTuple):
    """An RPR dyad: the line's direction ``u``, the distance ``t`` along it, and ``ok``."""

    u: np.ndarray
    t: np.ndarray
    ok: np.ndarray


class TwoLines(NamedTuple):
    """Two lines' meet ``B = G1 + s1 u1 = G2 + s2 u2`` and ``ok``."""

    B: np.ndarray
    s1: np.ndarray
    s2: np.ndarray
    ok: np.ndarray


class Pair(NamedTuple):
    """The solution ``x1, x2`` of a 2 × 2 system, and ``ok`` (non-singular)."""

    x1: np.ndarray
    x2: np.ndarray
    ok: np.ndarray


def _reals(field: str, value: Any, positive: bool = False) -> np.ndarray:
    """A real array; NaN passes (an unsolved sample stays unsolved), ±inf does not."""
    out = as_array(field, value)
    _finite(field, out)
    if positive and (out < TINY).any():
        raise InputError(field, f"must be positive, got {out[out < TINY].ravel()[0]:g}")
    return out


def _finite(field: str, out: np.ndarray) -> None:
    with np.errstate(invalid="ignore"):
        big = np.abs(out) > LIMIT
    if np.isinf(out).any() or big.any():
        raise InputError(
            field, f"must be finite and within ±{LIMIT:g} (NaN marks an unsolved sample)"
        )


def _points(field: str, value: Any) -> np.ndarray:
    """Points ``x + jy`` (reals are on the x axis); NaN passes, ±inf does not."""
    value = magnitude(value, None, field)
    if value is None or isinstance(value, str | bytes | bool | np.bool_):
        raise InputError(field, f"must be a point x + jy or an array of them, got {value!r}")
    try:
        out = np.asarray(value)
    except (TypeError, ValueError):
        raise InputError(field, "must be a point x + jy or a rectangular array of them") from None
    if out.dtype.kind not in "fciu":
        raise InputError(field, f"must be a point x + jy or an array of them, got {out.dtype}")
    out = out.astype(complex, copy=False)
    _finite(field, out)
    return out


def _sign(value: Any) -> np.ndarray:
    out = as_array("sign", value)
    if not np.isin(out, (-1.0, 1.0)).all():
        raise InputError("sign", "must be +1 or -1 (the assembly), got other values")
    return out


def cross(p: Any, q: Any) -> Any:
    """The planar cross product ``p × q = Im(conj(p) q)`` of complex vectors (no checks).

    Examples
    --------
    >>> cross(1 + 0j, 1j)
    1.0
    """
    return p.real * q.imag - p.imag * q.real


def rrr(A: Any, C: Any, a: Any, b: Any, sign: Any = 1) -> PinOnLine:
    """RRR dyad: the pin ``B`` with ``|B − A| = a`` and ``|B − C| = b``.

    Parameters
    ----------
    A, C : complex array_like
        The known pivots of the two links (A of the link of length ``a``).
    a, b : array_like
        The two links' lengths (pivot to ``B``), positive.
    sign : +1 or −1, array_like
        +1: ``B`` on the left of the line ``A → C`` (``(C − A) × (B − A) > 0``).

    Returns
    -------
    PinOnLine
        ``B`` (NaN where the circles do not meet), ``s`` (``|B − A|``, i.e.
        ``a``), ``ok``: ``|a − b| ≤ |C − A| ≤ a + b``. Unpacks as ``B, s, ok``.

    Examples
    --------
    A 3-4-5 triangle on the base 0 → 5:

    >>> B, _, ok = rrr(0j, 5 + 0j, 3.0, 4.0, sign=[1, -1])
    >>> B.round(12).tolist(), ok.tolist()
    ([(1.8+2.4j), (1.8-2.4j)], [True, True])
    """
    A, C = _points("A", A), _points("C", C)
    a, b = _reals("a", a, positive=True), _reals("b", b, positive=True)
    sign = _sign(sign)
    broadcast(A=A, C=C, a=a, b=b, sign=sign)
    B, s, ok = _rrr(A, C, a, b, sign)
    ok = _closes(_closes(ok, B, A, a), B, C, b)
    return PinOnLine(np.where(ok, B, np.nan + 0j), np.where(ok, s, np.nan), ok)


def _rrr(A: Any, C: Any, a: Any, b: Any, sign: Any) -> tuple[Any, Any, Any]:
    """:func:`rrr` without the checks (the program's hot path)."""
    with np.errstate(all="ignore"):
        AC = C - A
        d2 = AC.real * AC.real + AC.imag * AC.imag
        d = np.sqrt(d2)
        x = (a * a - b * b + d2) / (2.0 * d)
        h2 = (a - x) * (a + x)
        ok = (h2 >= -1e-14 * a * a) & (d > 0)
        h = np.sqrt(np.where(ok, np.maximum(h2, 0.0), np.nan))
        B = A + (x + 1j * (sign * h)) * (AC / d)
        ok = ok & np.isfinite(B)
    return np.where(ok, B, np.nan + 0j), np.where(ok, a, np.nan), ok


def rrp(A: Any, a: Any, G: Any, u: Any, sign: Any = 1) -> PinOnLine:
    """RRP dyad: the pin ``B = G + s u`` on a line with ``|B − A| = a``.

    The link of length ``a`` turns about the known pivot ``A``; the other link
    slides along the line through ``G`` with unit direction ``u`` (a line fixed
    in a known body) and carries ``B``. (PRR is the same dyad read from the
    other end.)

    Parameters
    ----------
    A : complex array_like
        The pivot.
    a : array_like
        Pivot to ``B``, positive.
    G, u : complex array_like
        A point of the line and its direction (normalised here).
    sign : +1 or −1, array_like
        +1: ``B`` ahead of the foot of ``A`` along ``u`` (``(B − A)·u > 0``).

    Returns
    -------
    PinOnLine
        ``B``, ``s`` with ``B = G + s u``, and ``ok`` (the circle meets the line).

    Examples
    --------
    Slider-crank, crank 2 at 90°, rod 6, slide along +x through the origin:
    ``B = √32``:

    >>> B, s, ok = rrp(2j, 6.0, 0j, 1 + 0j, sign=1)
    >>> round(float(s), 9), bool(ok)
    (5.656854249, True)
    """
    A, G = _points("A", A), _points("G", G)
    u = _direction("u", u)
    a = _reals("a", a, positive=True)
    sign = _sign(sign)
    broadcast(A=A, a=a, G=G, u=u, sign=sign)
    B, s, ok = _rrp(A, a, G, u, sign)
    ok = _closes(ok, B, A, a)
    return PinOnLine(np.where(ok, B, np.nan + 0j), np.where(ok, s, np.nan), ok)


def _rrp(A: Any, a: Any, G: Any, u: Any, sign: Any) -> tuple[Any, Any, Any]:
    """:func:`rrp` without the checks."""
    with np.errstate(all="ignore"):
        w = (G - A) * np.conj(u)  # G − A in the line's frame: along p, across e
        p, e = w.real, w.imag
        disc = (a - e) * (a + e)
        ok = disc >= -1e-14 * a * a
        s = -p + sign * np.sqrt(np.where(ok, np.maximum(disc, 0.0), np.nan))
        B = G + s * u
        ok = ok & np.isfinite(B)
    return np.where(ok, B, np.nan + 0j), np.where(ok, s, np.nan), ok


def rpr(A: Any, C: Any, e: Any, sign: Any = 1) -> Slotted:
    """RPR dyad: the direction ``u`` of a line, fixed in a link turning about ``A``, through ``C``.

    The two links turn together about the known pivots ``A`` and ``C`` and
    slide on each other along a line that passes at the signed distance ``e``
    from ``A`` (``e > 0``: ``A`` is on the right of the line, which runs along
    ``u``) — an inverted slider-crank, a pin ``C`` in a slot of a link pivoted
    at ``A``. Then ``C = A + (t + j e) u``.

    Parameters
    ----------
    A, C : complex array_like
        The pivots.
    e : array_like
        Signed offset of the line from ``A`` (0: the line passes through ``A``).
    sign : +1 or −1, array_like
        The sign of ``t``: ``C`` ahead of (+1) or behind the foot of ``A``.

    Returns
    -------
    Slotted
        ``u`` (unit direction), ``t`` (from the foot of ``A`` to ``C``), ``ok``
        (``|C − A| ≥ |e|``).

    Examples
    --------
    A slotted link pivoted at the origin through a pin at (3, 4), no offset:

    >>> u, t, ok = rpr(0j, 3 + 4j, 0.0)
    >>> complex(u), float(t)
    ((0.6+0.8j), 5.0)
    """
    A, C = _points("A", A), _points("C", C)
    e = _reals("e", e)
    sign = _sign(sign)
    broadcast(A=A, C=C, e=e, sign=sign)
    return Slotted(*_rpr(A, C, e, sign))


def _rpr(A: Any, C: Any, e: Any, sign: Any) -> tuple[Any, Any, Any]:
    """:func:`rpr` without the checks."""
    with np.errstate(all="ignore"):
        AC = C - A
        r = np.abs(AC)
        disc = (r - e) * (r + e)
        ok = (disc >= -1e-14 * r * r) & (r > 0)
        t = sign * np.sqrt(np.where(ok, np.maximum(disc, 0.0), np.nan))
        u = AC / (t + 1j * e)
        ok = ok & np.isfinite(u) & np.isfinite(t)
    return np.where(ok, u, np.nan + 0j), np.where(ok, t, np.nan), ok


def line_line(G1: Any, u1: Any, G2: Any, u2: Any) -> TwoLines:
    """PRP (and RPP) dyad: the meet ``B = G1 + s1 u1 = G2 + s2 u2`` of two lines.

    Parameters
    ----------
    G1, u1, G2, u2 : complex array_like
        A point and the direction (normalised here) of each line.

    Returns
    -------
    TwoLines
        ``B``, ``s1``, ``s2`` and ``ok`` (the lines are not parallel).

    Examples
    --------
    >>> B, s1, s2, ok = line_line(0j, 1 + 0j, 3 + 1j, 1j)
    >>> complex(B), float(s1), float(s2)
    ((3+0j), 3.0, -1.0)
    """
    G1, G2 = _points("G1", G1), _points("G2", G2)
    u1, u2 = _direction("u1", u1), _direction("u2", u2)
    broadcast(G1=G1, u1=u1, G2=G2, u2=u2)
    return TwoLines(*_line_line(G1, u1, G2, u2))


def _line_line(G1: Any, u1: Any, G2: Any, u2: Any) -> tuple[Any, Any, Any, Any]:
    """:func:`line_line` without the checks."""
    s1, s2, ok = _pair(u1, -u2, G2 - G1)
    with np.errstate(all="ignore"):
        B = G1 + s1 * u1
    return B, s1, s2, ok & np.isfinite(B)


def solve_pair(c1: Any, c2: Any, k: Any) -> Pair:
    """Real ``x1, x2`` with ``c1 x1 + c2 x2 = k`` (complex ``c1, c2, k``), by Cramer's rule.

    Every derivative order of a dyad is such a system, with the columns of its
    position Jacobian. Where ``c1 × c2 = 0`` (a toggle) ``ok`` is False and
    ``x1, x2`` are NaN.

    Examples
    --------
    >>> x1, x2, ok = solve_pair(1 + 0j, 1j, 2 + 3j)
    >>> float(x1), float(x2), bool(ok)
    (2.0, 3.0, True)
    """
    c1, c2, k = _points("c1", c1), _points("c2", c2), _points("k", k)
    broadcast(c1=c1, c2=c2, k=k)
    return Pair(*_pair(c1, c2, k))


def _pair(c1: Any, c2: Any, k: Any) -> tuple[Any, Any, Any]:
    """:func:`solve_pair` without the checks (the kernels' hot path)."""
    with np.errstate(all="ignore"):
        det = cross(c1, c2)
        ok = (det != 0) & np.isfinite(det)
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), np.nan)
        x1 = cross(k, c2) * inv
        x2 = cross(c1, k) * inv
        ok = ok & np.isfinite(x1) & np.isfinite(x2)
    return np.where(ok, x1, np.nan), np.where(ok, x2, np.nan), ok


def _direction(field: str, value: Any) -> np.ndarray:
    u = _points(field, value)
    with np.errstate(all="ignore"):
        n = np.abs(u)
        if (n < TINY).any():
            raise InputError(field, "must be a non-zero direction")
        return u / n


def _closes(ok: np.ndarray, B: Any, A: Any, a: Any) -> np.ndarray:
    """``ok`` where ``|B − A| = a`` holds to 1e-9 (not where the points swamp ``a``)."""
    with np.errstate(all="ignore"):
        return ok & (np.abs(np.abs(B - A) - a) <= 1e-9 * a)
