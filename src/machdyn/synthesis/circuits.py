"""Four-bar coupler curves circuit by circuit, for every Barker class.

A four-bar's coupler curve has one closed branch per *circuit* (the
configurations reachable without taking the linkage apart). Where the input
link 2 turns fully (Barker's GCCC and GCRR), each circuit is one assembly
(the sign of φ12 = θ4 − θ3) over the whole turn. Where link 2 rocks, its
range is one interval (non-Grashof linkages, one circuit) or two mirror-image
intervals (GRCR, GRRC: two circuits); at either end links 3 and 4 are in line
(φ12 = 0 or π) and the linkage passes from one assembly to the other, so the
circuit is the interval run forward on φ12 > 0 and back on φ12 < 0.

Both cases are one parametrisation, ``u ∈ [0, 2π)``:

* crank: ``θ2 = u`` on the assembly ``circuit``;
* rocker: ``θ2 = θc + h cos u`` on the assembly ``sign(sin u)``, with
  ``θc ± h`` the input's limits. Near a limit θ3 moves like the square root of
  the distance to it, and ``1 − cos u`` is quadratic there: the samples stay
  evenly spread along the curve.

The limits come from the diagonal ``|O4 A|² = r1² + r2² − 2 r1 r2 cos θ2``,
which must lie between ``|r3 − r4|`` and ``r3 + r4`` (Norton, *Design of
Machinery*, sec. 4.10, "toggle positions").
"""

from __future__ import annotations

from typing import Any

import numpy as np

# Internal to machdyn.synthesis, which re-exports the public names (Atlas, build_atlas,
# open_atlas, path_from_atlas, curve_descriptor, ...); the fuzz suite fuzzes those.
__all__: list[str] = []


def circuit_range(
    r1: Any, r2: Any, r3: Any, r4: Any, circuit: Any = 1
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centre and half-width of link 2's range on a circuit, and whether it is a crank.

    Parameters
    ----------
    r1, r2, r3, r4 : array_like
        Link lengths (assemblable linkages).
    circuit : array_like of {1, −1}
        Which circuit: the assembly (sign of φ12) for a crank; for a rocker
        with two ranges, the one above (+1) or below (−1) the ground line.

    Returns
    -------
    centre, half : ndarray
        θ2 runs over ``centre ± half`` (``0 ± π`` for a crank).
    crank : ndarray of bool
        True where link 2 turns fully.

    Examples
    --------
    A GRCR (coupler shortest) rocks on two mirror-image ranges, where the
    diagonal O4A is |r3 − r4| = 2.5 (cos θ2 = 0.78125) and r3 + r4 = 4.5 (0.19792):

    >>> c, h, crank = circuit_range(4, 3, 1, 3.5, [1, -1])
    >>> np.round(np.degrees(c - h), 2), np.round(np.degrees(c + h), 2), crank
    (array([ 38.62, -78.58]), array([ 78.58, -38.62]), array([False, False]))
    """
    r1, r2, r3, r4, circuit = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (r1, r2, r3, r4, circuit))
    )
    two = 2.0 * r1 * r2
    cos_hi = (r1 * r1 + r2 * r2 - (r3 - r4) ** 2) / two  # diagonal at |r3 − r4|
    cos_lo = (r1 * r1 + r2 * r2 - (r3 + r4) ** 2) / two  # diagonal at r3 + r4
    a_hi = np.arccos(np.clip(cos_hi, -1.0, 1.0))  # smallest reachable θ2 ≥ 0
    a_lo = np.arccos(np.clip(cos_lo, -1.0, 1.0))  # largest reachable θ2 ≤ π
    crank = (cos_hi >= 1.0) & (cos_lo <= -1.0)
    around0 = (cos_hi >= 1.0) & ~crank  # one range, −a_lo … a_lo
    aroundpi = (cos_lo <= -1.0) & ~crank  # one range, a_hi … 2π − a_hi
    sign = np.where(circuit >= 0.0, 1.0, -1.0)
    centre = np.where(around0, 0.0, np.where(aroundpi, np.pi, sign * 0.5 * (a_hi + a_lo)))
    half = np.where(around0, a_lo, np.where(aroundpi, np.pi - a_hi, 0.5 * (a_lo - a_hi)))
    centre = np.where(crank, 0.0, centre)
    half = np.where(crank, np.pi, half)
    return centre, half, crank


def circuit_angles(
    u: Any, centre: Any, half: Any, crank: Any, circuit: Any
) -> tuple[np.ndarray, np.ndarray]:
    """Input angle θ2 and assembly (sign of φ12) at circuit parameters ``u``.

    Broadcasts ``u`` against the per-linkage arrays (use column vectors for a
    (linkage, sample) grid).
    """
    u = np.asarray(u, dtype=float)
    crank = np.asarray(crank, dtype=bool)
    theta2 = np.where(crank, u, centre + half * np.cos(u))
    branch = np.where(crank, np.where(np.asarray(circuit) >= 0, 1.0, -1.0), 1.0)
    branch = np.where(crank, branch, np.where(np.sin(u) >= 0.0, 1.0, -1.0))
    return theta2, branch


def circuit_points(
    r1: Any,
    r2: Any,
    r3: Any,
    r4: Any,
    p: Any,
    delta: Any,
    circuit: Any = 1,
    m: int = 256,
) -> tuple[np.ndarray, np.ndarray]:
    """Coupler points of N four-bars around one circuit each, in their own frames.

    Parameters
    ----------
    r1, r2, r3, r4, p, delta : array_like, shape (N,)
        Lengths and coupler point (distance from A, angle from AB).
    circuit : array_like of {1, −1}
        Which circuit (see :func:`circuit_range`).
    m : int
        Samples of the circuit parameter ``u`` over ``[0, 2π)``.

    Returns
    -------
    points : ndarray of complex, shape (N, m)
        ``O2`` at the origin, ground along +x.
    theta2 : ndarray, shape (N, m)
        The input angle of each sample.

    Examples
    --------
    On a crank circuit this is :func:`~machdyn.synthesis.coupler_points` at
    evenly spaced input angles:

    >>> from machdyn.synthesis import coupler_points
    >>> pts, th = circuit_points([8], [4], [7], [6], [3.0], [0.5], [-1], m=8)
    >>> ref, ok = coupler_points(8, 4, 7, 6, 3.0, 0.5, th[0], -1)
    >>> bool(np.allclose(pts, ref))
    True
    """
    r1, r2, r3, r4, p, delta, circuit = (
        np.ravel(np.asarray(v, dtype=float)) for v in (r1, r2, r3, r4, p, delta, circuit)
    )
    r1, r2, r3, r4, p, delta, circuit = np.broadcast_arrays(r1, r2, r3, r4, p, delta, circuit)
    centre, half, crank = circuit_range(r1, r2, r3, r4, circuit)
    u = np.linspace(0.0, 2.0 * np.pi, m, endpoint=False)
    col = (r[:, None] for r in (r1, r2, r3, r4, p, delta, centre, half, crank, circuit))
    c1, c2, c3, c4, cp, cd, cc, ch, ck, ci = col
    theta2, branch = circuit_angles(u[None, :], cc, ch, ck, ci)
    return coupler_at(c1, c2, c3, c4, cp, cd, theta2, branch), theta2


def coupler_at(r1, r2, r3, r4, p, delta, theta2, branch) -> np.ndarray:
    """Coupler point at one input angle per element (broadcasting; clamped at toggles).

    The same closed form as :func:`machdyn.synthesis.coupler_points`, but the
    law-of-cosines value is clamped to ±1: a circuit's samples at its limits
    are toggles, where rounding may step past them.
    """
    ax, ay = r2 * np.cos(theta2), r2 * np.sin(theta2)
    sx = ax - r1
    dd = sx * sx + ay * ay
    inv = 1.0 / np.sqrt(dd)
    cg = np.clip((r4 * r4 - r3 * r3 + dd) * inv * (0.5 / r4), -1.0, 1.0)
    sg = np.sqrt(1.0 - cg * cg) * branch
    ux, uy = sx * inv, ay * inv
    bx = r1 + r4 * (ux * cg + uy * sg)  # B = O4 + r4 e^{jθ4}
    by = r4 * (uy * cg - ux * sg)
    kr, ki = p * np.cos(delta) / r3, p * np.sin(delta) / r3
    dx, dy = bx - ax, by - ay
    return (ax + kr * dx - ki * dy) + 1j * (ay + kr * dy + ki * dx)
