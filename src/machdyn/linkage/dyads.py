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
>>> B, ok = rrr(4.0 + 0j, 8.0 + 0j, 7.0, 6.0, sign=1)
>>> round(float(np.degrees(np.angle(B - 4.0))), 2)  # θ3 of the notes
58.81
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["cross", "line_line", "rpr", "rrp", "rrr", "solve_pair"]


def cross(p: Any, q: Any) -> Any:
    """The planar cross product ``p × q = Im(conj(p) q)`` of complex vectors.

    Examples
    --------
    >>> cross(1 + 0j, 1j)
    1.0
    """
    return p.real * q.imag - p.imag * q.real


def rrr(A: Any, C: Any, a: Any, b: Any, sign: Any = 1) -> tuple[np.ndarray, np.ndarray]:
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
    B : complex ndarray
        NaN where the circles do not meet.
    ok : bool ndarray
        ``|a − b| ≤ |C − A| ≤ a + b`` (and ``A ≠ C``).

    Examples
    --------
    A 3-4-5 triangle on the base 0 → 5:

    >>> B, ok = rrr(0j, 5 + 0j, 3.0, 4.0, sign=[1, -1])
    >>> B.round(12).tolist(), ok.tolist()
    ([(1.8+2.4j), (1.8-2.4j)], [True, True])
    """
    A, C = np.asarray(A, complex), np.asarray(C, complex)
    a, b = np.asarray(a, float), np.asarray(b, float)
    AC = C - A
    d2 = AC.real * AC.real + AC.imag * AC.imag
    d = np.sqrt(d2)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = (a * a - b * b + d2) / (2.0 * d)
        h2 = (a - x) * (a + x)
        ok = (h2 >= -1e-14 * a * a) & (d > 0)
        h = np.sqrt(np.where(ok, np.maximum(h2, 0.0), np.nan))
        B = A + (x + 1j * (np.sign(sign) * h)) * (AC / d)
    return B, np.broadcast_to(ok, B.shape)


def rrp(A: Any, a: Any, G: Any, u: Any, sign: Any = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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
        A point of the line and its unit direction.
    sign : +1 or −1, array_like
        +1: ``B`` ahead of the foot of ``A`` along ``u`` (``(B − A)·u > 0``).

    Returns
    -------
    B : complex ndarray
    s : ndarray
        ``B = G + s u``.
    ok : bool ndarray
        The circle meets the line.

    Examples
    --------
    Slider-crank, crank 2 at 90°, rod 6, slide along +x through the origin:
    ``B = √32``:

    >>> B, s, ok = rrp(2j, 6.0, 0j, 1 + 0j, sign=1)
    >>> round(float(s), 9), bool(ok)
    (5.656854249, True)
    """
    A, G, u = np.asarray(A, complex), np.asarray(G, complex), np.asarray(u, complex)
    a = np.asarray(a, float)
    w = (G - A) * np.conj(u)  # G − A in the line's frame: along p, across e
    p, e = w.real, w.imag
    disc = (a - e) * (a + e)
    ok = disc >= -1e-14 * a * a
    with np.errstate(invalid="ignore"):
        s = -p + np.sign(sign) * np.sqrt(np.where(ok, np.maximum(disc, 0.0), np.nan))
    B = G + s * u
    return B, s, np.broadcast_to(ok, B.shape)


def rpr(A: Any, C: Any, e: Any, sign: Any = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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
    u : complex ndarray
        Unit direction of the line.
    t : ndarray
        Distance along the line from the foot of ``A`` to ``C``.
    ok : bool ndarray
        ``|C − A| ≥ |e|``.

    Examples
    --------
    A slotted link pivoted at the origin through a pin at (3, 4), no offset:

    >>> u, t, ok = rpr(0j, 3 + 4j, 0.0)
    >>> complex(u), float(t)
    ((0.6+0.8j), 5.0)
    """
    A, C = np.asarray(A, complex), np.asarray(C, complex)
    e = np.asarray(e, float)
    AC = C - A
    r = np.abs(AC)
    disc = (r - e) * (r + e)
    ok = (disc >= -1e-14 * r * r) & (r > 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.sign(sign) * np.sqrt(np.where(ok, np.maximum(disc, 0.0), np.nan))
        u = AC / (t + 1j * e)
    return u, t, np.broadcast_to(ok, u.shape)


def line_line(
    G1: Any, u1: Any, G2: Any, u2: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """PRP (and RPP) dyad: the meet ``B = G1 + s1 u1 = G2 + s2 u2`` of two lines.

    Parameters
    ----------
    G1, u1, G2, u2 : complex array_like
        A point and the unit direction of each line.

    Returns
    -------
    B : complex ndarray
    s1, s2 : ndarray
    ok : bool ndarray
        The lines are not parallel.

    Examples
    --------
    >>> B, s1, s2, ok = line_line(0j, 1 + 0j, 3 + 1j, 1j)
    >>> complex(B), float(s1), float(s2)
    ((3+0j), 3.0, -1.0)
    """
    G1, u1 = np.asarray(G1, complex), np.asarray(u1, complex)
    G2, u2 = np.asarray(G2, complex), np.asarray(u2, complex)
    s1, s2, ok = solve_pair(u1, -u2, G2 - G1)
    return G1 + s1 * u1, s1, s2, ok


def solve_pair(c1: Any, c2: Any, k: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Real ``x1, x2`` with ``c1 x1 + c2 x2 = k`` (complex ``c1, c2, k``), by Cramer's rule.

    Returns ``x1, x2`` and ``ok`` (``c1 × c2 ≠ 0``); where not ok both are NaN.

    Examples
    --------
    >>> x1, x2, ok = solve_pair(1 + 0j, 1j, 2 + 3j)
    >>> float(x1), float(x2), bool(ok)
    (2.0, 3.0, True)
    """
    det = cross(c1, c2)
    ok = det != 0
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), np.nan)
        x1 = cross(k, c2) * inv
        x2 = cross(c1, k) * inv
    return x1, x2, ok
