"""Newton–Euler equations of one Assur group at a time, in closed form (vectorised).

The force analysis of a linkage runs through its groups from the last solved to
the first (Norton, *Design of Machinery*, §11.4–11.8; the notes' matrix method
eliminated group by group): every group's joint forces follow from its own six
(three for a driver) equations once the loads on its links are known, the
loads of the groups solved after it included (their joint forces, reversed).
These functions are those eliminations; :func:`machdyn.linkage.Linkage.forces`,
:func:`machdyn.dynamics.fourbar_forces` and
:func:`machdyn.dynamics.slidercrank_forces` all call them.

A link's **known load** is the resultant ``F`` (complex) of every force on it
that is not a joint force of the group — external forces, gravity, springs and
the reversed inertia force ``−m a_G`` — and its moment about a named point
(``M_A``: about ``A``), the reversed inertia couple ``−I_G α`` included.
Joint forces are ``F_ap``: the force on the group's link from the other one.

Examples
--------
A massless RRR dyad (A = 0, B = 1 + j, C = 2) with a load −2j at B on link 1:
its moment about A is ``(B − A) × F = −2``; link 2 is a two-force member, so the
pin forces at B and C lie along C → B:

>>> A, B, C = 0j, 1 + 1j, 2 + 0j
>>> F_A, F_B, F_C, det = rrr(B - A, B - C, -2j, -2.0, 0j, 0.0)
>>> complex(F_A), complex(F_B), complex(F_C)
((1+1j), (-1+1j), (-1+1j))
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["crank", "rpr", "rpr_coulomb", "rrp", "rrp_coulomb", "rrr", "shift"]


def _cross(u: Any, v: Any) -> Any:
    return u.real * v.imag - u.imag * v.real


#: A slide whose rate is below this × the mechanism's speed scale is at rest.
REST_TOL = 1e-12


def _slip_sign(v: Any, a: Any, speed: Any) -> Any:
    """Direction of sliding that Coulomb friction opposes: ``sign(v)``.

    At rest (a dead centre: ``v`` is zero but for rounding, ``|v| ≤ REST_TOL·speed``
    with ``speed`` the mechanism's speed scale per sample) it is the impending
    slip, ``sign(a)`` — never the sign of the rounding noise.
    """
    still = np.abs(v) <= REST_TOL * speed
    return np.where(still, np.sign(a), np.sign(v))


def shift(M_Q: Any, F: Any, Q: Any, R: Any) -> Any:
    """The moment about ``R`` of a load whose moment about ``Q`` is ``M_Q`` and resultant ``F``.

    Examples
    --------
    >>> float(shift(0.0, 1j, 0j, -2 + 0j))  # a vertical unit force at Q, 2 to the right of R
    2.0
    """
    return M_Q + _cross(Q - R, F)


def crank(F: Any, M_O: Any) -> tuple[Any, Any]:
    """A driven link pinned at ``O`` with known load ``F``, ``M_O``: the pin force and torque.

    Returns ``(F_pin, T)``: the force on the link from the pin's other side, and
    the driving torque on the link.

    Examples
    --------
    >>> crank(2 + 0j, -3.0)
    ((-2-0j), 3.0)
    """
    return -F, -M_O


def rrr(u: Any, w: Any, F1: Any, M1_A: Any, F2: Any, M2_C: Any) -> tuple[Any, ...]:
    """An RRR dyad: link 1 pinned at ``A`` and ``B``, link 2 at ``B`` and ``C``.

    ``u = B − A`` and ``w = B − C`` are the links' vectors to the middle pin.
    Moments of link 1 about ``A`` and of link 2 about ``C`` give the middle
    pin's force (``u × F_B = −M1_A``, ``w × F_B = M2_C``), the force sums the
    end pins'.

    Returns ``(F_A, F_B, F_C, det)``: the forces on link 1 at ``A``, on link 1
    at ``B`` (from link 2), on link 2 at ``C``, and ``u × w`` (0 at a toggle).
    """
    det = _cross(u, w)
    with np.errstate(divide="ignore", invalid="ignore"):
        F_B = (M1_A * w + M2_C * u) / _cross(w, u)
    return -F_B - F1, F_B, F_B - F2, det


def rrp(u: Any, x: Any, v: Any, F1: Any, M1_A: Any, F2: Any, M2_B: Any) -> tuple[Any, ...]:
    """An RRP dyad: link 1 pinned at ``A`` and ``B``; link 2 pinned at ``B``, sliding on a guide.

    ``u = B − A``; the guide pushes link 2 with ``N v`` at ``B + x`` (``v = j û + κ û``:
    the normal and, with a Coulomb coefficient ``κ``, its friction) and a couple
    ``Cp``. Link 2's forces give ``F_B = N v + F2``; link 1's moment about ``A``
    then ``N = −(M1_A + u × F2) / (u × v)``; link 2's moment about ``B`` the couple.

    Returns ``(F_A, F_B, N, Cp, den)``: the force on link 1 at ``A``, on link 1
    at ``B`` (from link 2), the normal force, the couple and ``u × v`` (0 at a
    toggle).
    """
    den = _cross(u, v)
    with np.errstate(divide="ignore", invalid="ignore"):
        N = (M1_A + _cross(u, F2)) / -den
    F_B = N * v + F2
    Cp = -M2_B - _cross(x, N * v)
    return -F_B - F1, F_B, N, Cp, den


def rrp_coulomb(
    u: Any, x: Any, uhat: Any, slip: Any, mu: float, F1: Any, M1_A: Any, F2: Any, M2_B: Any
) -> tuple[Any, ...]:
    """:func:`rrp` with Coulomb friction ``−μ |N| sign(slip)`` along the slide.

    ``slip`` is the sign of link 2's sliding velocity (at rest: of its
    acceleration, the impending motion). The sign of ``N`` is not known
    beforehand: both are tried (the notes' ±μN); where exactly one satisfies
    its assumption it is the answer. ``wedged`` marks samples where both do, or
    neither (self-locking: the normal force is not determined).

    Returns ``(F_A, F_B, N, Cp, den, kappa, wedged)``.

    Examples
    --------
    A slider-crank (crank 0.08, rod 0.11) at θ2 = 77.5° with μ = 1 wedges: both
    signs of the normal force balance the rod (the check of
    :func:`machdyn.dynamics.slidercrank_forces`):

    >>> import numpy as np
    >>> A = 0.08 * np.exp(1j * np.radians(77.5))
    >>> B = A.real + np.sqrt(0.11**2 - A.imag**2)
    >>> out = rrp_coulomb(B - A, 0j, 1 + 0j, 1.0, 1.0, 0j, 0.0, -600 + 0j, 0.0)
    >>> bool(out[-1])
    True
    """
    return _coulomb(lambda v: rrp(u, x, v, F1, M1_A, F2, M2_B), 2, uhat, slip, mu)


def _coulomb(solve: Any, at: int, uhat: Any, slip: Any, mu: float) -> tuple[Any, ...]:
    """A group with friction ``−μ |N| sign(slip)`` for both signs of ``N``; the one that fits.

    ``solve(v)`` solves the group with the guide's force ``N v``; ``at`` is
    the index of ``N`` in what it returns.
    """
    jp = 1j * uhat
    plus = solve(jp - mu * slip * uhat)  # assuming N ≥ 0
    minus = solve(jp + mu * slip * uhat)  # assuming N ≤ 0
    fits_plus, fits_minus = plus[at] >= 0.0, minus[at] <= 0.0
    wedged = (fits_plus == fits_minus) & ~((plus[at] == 0.0) & (minus[at] == 0.0))
    kappa = np.where(fits_plus, -mu * slip, mu * slip)
    out = tuple(np.where(fits_plus, p, m) for p, m in zip(plus, minus, strict=True))
    return (*out, kappa, wedged)


def rpr(r: Any, v: Any, F1: Any, M1_A: Any, F2: Any, M2_C: Any) -> tuple[Any, ...]:
    """An RPR dyad: link 1 pinned at ``A``, sliding on link 2; link 2 pinned at ``C``.

    The inverted slider-crank's block (link 1) and slotted link (link 2;
    Norton §11.7). ``r = A − C``. The slide of link 2 pushes link 1 with
    ``N v`` at ``A`` (``v = j û + κ û``: the normal to the slide direction
    ``û`` and, with a Coulomb coefficient ``κ``, its friction) and a couple
    ``Cp``; link 1 pushes link 2 back with ``−N v`` and ``−Cp``. Link 1's
    moment about ``A`` gives ``Cp = −M1_A``; the sum of link 1's moment about
    ``A`` and link 2's about ``C`` gives ``N (r × v) = M1_A + M2_C``; each
    link's force sum its pin force.

    Returns ``(F_A, N, Cp, F_C, den)``: the force on link 1 at ``A`` (from its
    other neighbour), the normal force, the couple on link 1, the force on
    link 2 at ``C`` and ``r × v`` (0 where ``A`` is at the foot of the
    perpendicular from ``C`` to the slide: a toggle).

    Examples
    --------
    A massless block at A = 2 + 0j on a slot along +x through C = 0, with a
    torque 4 (CCW) on the slotted link: the slot pushes the block up with
    ``N = 2``; the block pushes the slotted link down at 2 from C (moment −4,
    balancing the torque), and the crank holds the block with ``−2j``:

    >>> F_A, N, Cp, F_C, den = rpr(2 + 0j, 1j, 0j, 0.0, 0j, 4.0)
    >>> print(F_A + 0, N, Cp + 0, F_C, den)
    -2j 2.0 0.0 2j 2.0
    """
    den = _cross(r, v)
    with np.errstate(divide="ignore", invalid="ignore"):
        N = (M1_A + M2_C) / den
    Nv = N * v
    return -Nv - F1, N, -M1_A, Nv - F2, den


def rpr_coulomb(
    r: Any, uhat: Any, slip: Any, mu: float, F1: Any, M1_A: Any, F2: Any, M2_C: Any
) -> tuple[Any, ...]:
    """:func:`rpr` with Coulomb friction ``−μ |N| sign(slip)`` along the slide (on link 1).

    ``slip`` is the sign of link 1's sliding velocity relative to link 2 (at
    rest: of its relative acceleration). Both signs of ``N`` are tried, as
    in :func:`rrp_coulomb`; ``wedged`` marks samples where both fit, or
    neither. Returns ``(F_A, N, Cp, F_C, den, kappa, wedged)``.

    Examples
    --------
    The block of the :func:`rpr` example sliding along +x with μ = 0.5: the
    friction −μ|N| = −1 along the slide, the normal force unchanged (the
    friction's line passes through C):

    >>> out = rpr_coulomb(2 + 0j, 1 + 0j, 1.0, 0.5, 0j, 0.0, 0j, 4.0)
    >>> complex(out[0]), float(out[1]), bool(out[-1])
    ((1-2j), 2.0, False)
    """
    return _coulomb(lambda v: rpr(r, v, F1, M1_A, F2, M2_C), 1, uhat, slip, mu)
