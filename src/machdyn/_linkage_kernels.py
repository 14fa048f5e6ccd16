"""Compiled (numba) kernel of a linkage's closed-form program.

Imported only through :mod:`machdyn.jit`'s rule (:func:`machdyn.linkage.kernel.compiled_kernel`);
the NumPy program of :mod:`machdyn.linkage.program` is the reference it is
tested against (every linkage test runs on both).

The program is data: each step is a row of integers and floats
(:func:`machdyn.linkage.kernel.encode`), so one compiled kernel serves every
linkage and a changed linkage compiles nothing. The samples are taken in
blocks of :data:`BLOCK`; within a block each step is one loop over the
samples, written in **real** arithmetic (numba's complex numbers call helper
functions and defeat vectorisation; the elementary functions are the
polynomial ones of :mod:`machdyn._kernels`), so LLVM can vectorise it. The
arithmetic is the NumPy path's: a driver places its link; a dyad's pin is a
circle–circle (RRR), circle–line (RRP) or line–line (PRP) meet with the drawn
assembly sign, an RPR's line a tangent, an RPP a line–line meet; every
derivative order is the same 2 × 2 system solved by Cramer's rule.

State of link ``i`` in a block (row 0 is the ground: zeros, ``E = 1``): origin
``(ox, oy)``, rotation ``E = (ex, ey) = e^{jΔ}``, its angle ``an`` (Δ, wrapped
where it comes from an ``atan2``), rates of the origin ``(vx, vy)[k·nl + i]``
and of the angle ``w[k·nl + i]`` (k = 0, 1, 2: velocity, acceleration, jerk).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._kernels import angle as _angle_2pi
from ._kernels import sincos
from .linkage._scalar import CRANK, DYAD, MOTOR, NF, NI, RPR, SINGULAR_SINE, SLIDE

_jit = njit(cache=True, nogil=True, error_model="numpy")
_inline = njit(inline="always", error_model="numpy")

#: Samples per block (the state of every link for a block stays in cache).
BLOCK = 256
_PI = math.pi
_TWO_PI = 2.0 * math.pi
# A link's rows (1-D views over a block): origin, rotation, angle, and per order the
# origin's rate and the angle's rate. Views taken before a loop let LLVM see through the
# runtime row numbers (2-D indexing by a link number kept every loop scalar).
OX, OY, EX, EY, AN = 0, 1, 2, 3, 4  # then VX, VY, W of order k at 5 + 3 (k - 1)


@_inline
def _rows(S, nl, i):  # pragma: no cover - compiled
    ox, oy, ex, ey, an, vx, vy, w = S
    i = max(i, 0)  # a virtual link (-1) gets the ground's rows, never written
    return (
        ox[i], oy[i], ex[i], ey[i], an[i],
        vx[i], vy[i], w[i], vx[nl + i], vy[nl + i], w[nl + i],
        vx[2 * nl + i], vy[2 * nl + i], w[2 * nl + i],
    )  # fmt: skip


@_inline
def _atan2(y, x):  # pragma: no cover - compiled
    a = _angle_2pi(y, x)
    return a - _TWO_PI if a > _PI else a


@_inline
def _pt(R, rx, ry, j, order):  # pragma: no cover - compiled
    """The material point drawn at offset (rx, ry) on the link of rows R: 8 floats."""
    cx, cy = R[EX][j], R[EY][j]
    qx = rx * cx - ry * cy
    qy = rx * cy + ry * cx
    p1x = p1y = p2x = p2y = p3x = p3y = 0.0
    if order >= 1:
        w1 = R[7][j]
        p1x = R[5][j] - w1 * qy
        p1y = R[6][j] + w1 * qx
        if order >= 2:
            w2 = R[10][j]
            p2x = R[8][j] - w2 * qy - w1 * w1 * qx
            p2y = R[9][j] + w2 * qx - w1 * w1 * qy
            if order >= 3:
                c = R[13][j] - w1 * w1 * w1
                d = 3.0 * w1 * w2
                p3x = R[11][j] - c * qy - d * qx
                p3y = R[12][j] + c * qx - d * qy
    return R[OX][j] + qx, R[OY][j] + qy, p1x, p1y, p2x, p2y, p3x, p3y


@_inline
def _put(R, j, order, P, rx, ry, cx, cy, a, w1, w2, w3):  # pragma: no cover - compiled
    """Place the link of rows R from its point drawn at (rx, ry), at P, turned by E = c."""
    R[EX][j] = cx
    R[EY][j] = cy
    R[AN][j] = a
    qx = -(rx * cx - ry * cy)
    qy = -(rx * cy + ry * cx)
    R[OX][j] = P[0] + qx
    R[OY][j] = P[1] + qy
    if order >= 1:
        R[7][j] = w1
        R[5][j] = P[2] - w1 * qy
        R[6][j] = P[3] + w1 * qx
        if order >= 2:
            R[10][j] = w2
            R[8][j] = P[4] - w2 * qy - w1 * w1 * qx
            R[9][j] = P[5] + w2 * qx - w1 * w1 * qy
            if order >= 3:
                R[13][j] = w3
                c = w3 - w1 * w1 * w1
                d = 3.0 * w1 * w2
                R[11][j] = P[6] - c * qy - d * qx
                R[12][j] = P[7] + c * qx - d * qy


@_inline
def _rates(R, j, order):  # pragma: no cover - compiled
    w1 = R[7][j] if order >= 1 else 0.0
    w2 = R[10][j] if order >= 2 else 0.0
    w3 = R[13][j] if order >= 3 else 0.0
    return w1, w2, w3


@_inline
def _comb(a, b, ux, uy):  # pragma: no cover - compiled
    """The vector ``a û + b (j û)``."""
    return a * ux - b * uy, a * uy + b * ux


@_inline
def _p_term(k, s0, s1, s2, ux, uy, w1, w2, w3):  # pragma: no cover - compiled
    """Order-k rate of s û without its s⁽ᵏ⁾ û part (û turning at w1, w2, w3)."""
    if k == 1:
        return _comb(0.0, s0 * w1, ux, uy)
    if k == 2:
        return _comb(-s0 * w1 * w1, 2.0 * s1 * w1 + s0 * w2, ux, uy)
    return _comb(
        -3.0 * s1 * w1 * w1 - 3.0 * s0 * w1 * w2,
        3.0 * s2 * w1 + 3.0 * s1 * w2 + s0 * (w3 - w1 * w1 * w1),
        ux,
        uy,
    )


@_inline
def _r_term(k, L0, L1, L2, L3, ex, ey, w1, w2):  # pragma: no cover - compiled
    """Order-k rate of L ê without its j L φ⁽ᵏ⁾ ê part (ê turning at w1, w2)."""
    if k == 1:
        return _comb(L1, 0.0, ex, ey)
    if k == 2:
        return _comb(L2 - L0 * w1 * w1, 2.0 * L1 * w1, ex, ey)
    return _comb(
        L3 - 3.0 * L1 * w1 * w1 - 3.0 * L0 * w1 * w2,
        3.0 * L2 * w1 + 3.0 * L1 * w2 - L0 * w1 * w1 * w1,
        ex,
        ey,
    )


@_inline
def _solve2(c1x, c1y, c2x, c2y, kx, ky):  # pragma: no cover - compiled
    """Real x1, x2 with c1 x1 + c2 x2 = k (Cramer)."""
    det = c1x * c2y - c1y * c2x
    return (kx * c2y - ky * c2x) / det, (c1x * ky - c1y * kx) / det


@_inline
def _code(ok, cross, norm):  # pragma: no cover - compiled
    if not ok:
        return 1
    return 0 if abs(cross) >= SINGULAR_SINE * norm else 2


@_inline
def _length(U, d, i, constant):  # pragma: no cover - compiled
    """An arm's length and rates: constant, or a driven actuator's."""
    if d < 0:
        return constant, 0.0, 0.0, 0.0
    return U[4 * d, i], U[4 * d + 1, i], U[4 * d + 2, i], U[4 * d + 3, i]


@_inline
def _set_r(R, j, order, P, brx, bry, vx_, vy_, ux, uy, n, x1, x2, x3):  # pragma: no cover
    """Place the link of an R arm: its rotation is the arm vector over the drawn one."""
    cx = (vx_ * ux + vy_ * uy) / n
    cy = (vy_ * ux - vx_ * uy) / n
    _put(R, j, order, P, brx, bry, cx, cy, _atan2(cy, cx), x1, x2, x3)


# ---------------------------------------------------------------------- drivers
@_jit
def _crank(S, nl, pi, pf, ib, fb, U, lo, b, order):  # pragma: no cover - compiled
    L, K, d = pi[ib + 2], pi[ib + 3], pi[ib + 4]
    rkx, rky, rlx, rly, theta0 = pf[fb], pf[fb + 1], pf[fb + 2], pf[fb + 3], pf[fb + 4]
    RK, RL = _rows(S, nl, K), _rows(S, nl, L)
    u0, u1, u2, u3 = U[4 * d], U[4 * d + 1], U[4 * d + 2], U[4 * d + 3]
    for j in range(b):
        i = lo + j
        delta = u0[i] - theta0
        s, c = sincos(delta)
        P = _pt(RK, rkx, rky, j, order)
        _put(RL, j, order, P, rlx, rly, c, s, delta, u1[i], u2[i], u3[i])


@_jit
def _motor(S, nl, pi, pf, ib, fb, U, lo, b, order):  # pragma: no cover - compiled
    L, K, Sr, d = pi[ib + 2], pi[ib + 3], pi[ib + 4], pi[ib + 5]
    rkx, rky, rlx, rly, sg, phi0 = (
        pf[fb],
        pf[fb + 1],
        pf[fb + 2],
        pf[fb + 3],
        pf[fb + 4],
        pf[fb + 5],
    )
    RK, RL, RS = _rows(S, nl, K), _rows(S, nl, L), _rows(S, nl, Sr)
    u0, u1, u2, u3 = U[4 * d], U[4 * d + 1], U[4 * d + 2], U[4 * d + 3]
    for j in range(b):
        i = lo + j
        delta = sg * (u0[i] - phi0)
        s, c = sincos(delta)
        ex, ey = RS[EX][j], RS[EY][j]
        w1, w2, w3 = _rates(RS, j, order)
        P = _pt(RK, rkx, rky, j, order)
        _put(RL, j, order, P, rlx, rly, ex * c - ey * s, ex * s + ey * c, RS[AN][j] + delta,
             w1 + sg * u1[i], w2 + sg * u2[i], w3 + sg * u3[i])  # fmt: skip


@_jit
def _slide(S, nl, pi, pf, ib, fb, U, lo, b, order):  # pragma: no cover - compiled
    L, K, Lf, La, d, block = pi[ib + 2], pi[ib + 3], pi[ib + 4], pi[ib + 5], pi[ib + 6], pi[ib + 7]
    rfx, rfy, rax, ray, u0x, u0y = (
        pf[fb],
        pf[fb + 1],
        pf[fb + 2],
        pf[fb + 3],
        pf[fb + 4],
        pf[fb + 5],
    )
    RK, RL = _rows(S, nl, K), _rows(S, nl, L)
    RB = _rows(S, nl, Lf if block == 1 else La)  # the known body's point: foot or block's pin
    bx, by = (rfx, rfy) if block == 1 else (rax, ray)
    px, py = (rax, ray) if block == 1 else (rfx, rfy)  # the moving link's point
    sg = 1.0 if block == 1 else -1.0
    u0, u1, u2, u3 = U[4 * d], U[4 * d + 1], U[4 * d + 2], U[4 * d + 3]
    for j in range(b):
        i = lo + j
        cx, cy = RK[EX][j], RK[EY][j]
        ux, uy = u0x * cx - u0y * cy, u0x * cy + u0y * cx
        w1, w2, w3 = _rates(RK, j, order)
        Q = _pt(RB, bx, by, j, order)
        d0, d1, d2, d3 = u0[i], u1[i], u2[i], u3[i]
        t1x, t1y = _p_term(1, d0, d1, d2, ux, uy, w1, w2, w3)
        t2x, t2y = _p_term(2, d0, d1, d2, ux, uy, w1, w2, w3)
        t3x, t3y = _p_term(3, d0, d1, d2, ux, uy, w1, w2, w3)
        P = (
            Q[0] + sg * d0 * ux, Q[1] + sg * d0 * uy,
            Q[2] + sg * (t1x + d1 * ux), Q[3] + sg * (t1y + d1 * uy),
            Q[4] + sg * (t2x + d2 * ux), Q[5] + sg * (t2y + d2 * uy),
            Q[6] + sg * (t3x + d3 * ux), Q[7] + sg * (t3y + d3 * uy),
        )  # fmt: skip
        _put(RL, j, order, P, px, py, cx, cy, RK[AN][j], w1, w2, w3)


# ---------------------------------------------------------------------- dyads
@_inline
def _rr_order(k, A, C, a_, c_, v, xa1, xa2, xb1, xb2):  # pragma: no cover - compiled
    """Order k of an RRR: the two arms' angular rates and the pin's rate."""
    vax, vay, vbx, vby, eax, eay, ebx, eby = v
    tax, tay = _r_term(k, a_[0], a_[1], a_[2], a_[3], eax, eay, xa1, xa2)
    tbx, tby = _r_term(k, c_[0], c_[1], c_[2], c_[3], ebx, eby, xb1, xb2)
    kax, kay = A[2 * k] + tax, A[2 * k + 1] + tay
    kbx, kby = C[2 * k] + tbx, C[2 * k + 1] + tby
    x1, x2 = _solve2(-vay, vax, vby, -vbx, kbx - kax, kby - kay)
    return x1, x2, kax - vay * x1, kay + vax * x1


@_jit
def _dyad_rr(S, nl, pi, pf, ib, fb, U, lo, b, order, codes, g):  # pragma: no cover
    """RRR (an arm may be an actuator's bar: a driven length)."""
    K1, L1, d1, K2, L2, d2 = pi[ib + 3], pi[ib + 4], pi[ib + 5], pi[ib + 7], pi[ib + 8], pi[ib + 9]
    r1x, r1y, b1x, b1y, u1x, u1y, len1 = pf[fb : fb + 7]
    r2x, r2y, b2x, b2y, u2x, u2y, len2 = pf[fb + 7 : fb + 14]
    sign = pf[fb + 14]
    n1, n2 = u1x * u1x + u1y * u1y, u2x * u2x + u2y * u2y
    RK1, RK2, RL1, RL2 = _rows(S, nl, K1), _rows(S, nl, K2), _rows(S, nl, L1), _rows(S, nl, L2)
    cg = codes[g]
    for j in range(b):
        i = lo + j
        A = _pt(RK1, r1x, r1y, j, order)
        C = _pt(RK2, r2x, r2y, j, order)
        a0, a1, a2, a3 = _length(U, d1, i, len1)
        c0, c1, c2, c3 = _length(U, d2, i, len2)
        acx, acy = C[0] - A[0], C[1] - A[1]
        dd2 = acx * acx + acy * acy
        dd = math.sqrt(dd2)
        x = (a0 * a0 - c0 * c0 + dd2) / (2.0 * dd)
        h2 = (a0 - x) * (a0 + x)
        ok = h2 >= -1e-14 * a0 * a0 and dd > 0.0
        h = sign * math.sqrt(max(h2, 0.0))
        bx = A[0] + (x * acx - h * acy) / dd if ok else math.nan
        by = A[1] + (x * acy + h * acx) / dd if ok else math.nan
        vax, vay, vbx, vby = bx - A[0], by - A[1], bx - C[0], by - C[1]
        cg[i] = _code(ok, vax * vby - vay * vbx, a0 * c0)
        eax, eay, ebx, eby = vax / a0, vay / a0, vbx / c0, vby / c0
        # unknowns: the arms' angles; columns j·va and −j·vb (orders unrolled: the loop over
        # the samples stays the innermost, which LLVM vectorises)
        xa1 = xa2 = xa3 = xb1 = xb2 = xb3 = 0.0
        B1x = B1y = B2x = B2y = B3x = B3y = 0.0
        a_, c_ = (a0, a1, a2, a3), (c0, c1, c2, c3)
        v = (vax, vay, vbx, vby, eax, eay, ebx, eby)
        if order >= 1:
            xa1, xb1, B1x, B1y = _rr_order(1, A, C, a_, c_, v, 0.0, 0.0, 0.0, 0.0)
            if order >= 2:
                xa2, xb2, B2x, B2y = _rr_order(2, A, C, a_, c_, v, xa1, 0.0, xb1, 0.0)
                if order >= 3:
                    xa3, xb3, B3x, B3y = _rr_order(3, A, C, a_, c_, v, xa1, xa2, xb1, xb2)
        P = (bx, by, B1x, B1y, B2x, B2y, B3x, B3y)
        if L1 >= 0:
            _set_r(RL1, j, order, P, b1x, b1y, vax, vay, u1x, u1y, n1, xa1, xa2, xa3)
        if L2 >= 0:
            _set_r(RL2, j, order, P, b2x, b2y, vbx, vby, u2x, u2y, n2, xb1, xb2, xb3)


@_inline
def _rp_order(k, A, G, a_, wk, v, xa1, xa2, s1, s2):  # pragma: no cover - compiled
    """Order k of an RRP: the R arm's angular rate, the slide's rate, the pin's rate."""
    vax, vay, eax, eay, ux, uy, s0 = v
    tax, tay = _r_term(k, a_[0], a_[1], a_[2], a_[3], eax, eay, xa1, xa2)
    tbx, tby = _p_term(k, s0, s1, s2, ux, uy, wk[0], wk[1], wk[2])
    kax, kay = A[2 * k] + tax, A[2 * k + 1] + tay
    kbx, kby = G[2 * k] + tbx, G[2 * k + 1] + tby
    x1, x2 = _solve2(-vay, vax, -ux, -uy, kbx - kax, kby - kay)
    return x1, x2, kax - vay * x1, kay + vax * x1


@_jit
def _dyad_rp(S, nl, pi, pf, ia, fa, ip, fp, U, lo, b, order, sign, codes, g):  # pragma: no cover
    """RRP / PRR: the R arm's row at (ia, fa), the P arm's at (ip, fp)."""
    K1, L1, d1, K2, L2 = pi[ia + 1], pi[ia + 2], pi[ia + 3], pi[ip + 1], pi[ip + 2]
    r1x, r1y, b1x, b1y, u1x, u1y, len1 = pf[fa : fa + 7]
    gx, gy, b2x, b2y, u2x, u2y = pf[fp : fp + 6]
    n1 = u1x * u1x + u1y * u1y
    RK1, RK2, RL1, RL2 = _rows(S, nl, K1), _rows(S, nl, K2), _rows(S, nl, L1), _rows(S, nl, L2)
    cg = codes[g]
    for j in range(b):
        i = lo + j
        A = _pt(RK1, r1x, r1y, j, order)
        G = _pt(RK2, gx, gy, j, order)
        cx, cy = RK2[EX][j], RK2[EY][j]
        ux, uy = u2x * cx - u2y * cy, u2x * cy + u2y * cx
        w1, w2, w3 = _rates(RK2, j, order)
        a0, a1, a2, a3 = _length(U, d1, i, len1)
        dx, dy = G[0] - A[0], G[1] - A[1]
        pp = dx * ux + dy * uy
        ee = dy * ux - dx * uy
        disc = (a0 - ee) * (a0 + ee)
        ok = disc >= -1e-14 * a0 * a0
        s0 = -pp + sign * math.sqrt(max(disc, 0.0))
        bx = G[0] + s0 * ux if ok else math.nan
        by = G[1] + s0 * uy if ok else math.nan
        vax, vay = bx - A[0], by - A[1]
        cg[i] = _code(ok, -vay * uy - vax * ux, a0)
        eax, eay = vax / a0, vay / a0
        xa1 = xa2 = xa3 = s1 = s2 = 0.0
        B1x = B1y = B2x = B2y = B3x = B3y = 0.0
        a_, wk = (a0, a1, a2, a3), (w1, w2, w3)
        v = (vax, vay, eax, eay, ux, uy, s0)
        if order >= 1:
            xa1, s1, B1x, B1y = _rp_order(1, A, G, a_, wk, v, 0.0, 0.0, 0.0, 0.0)
            if order >= 2:
                xa2, s2, B2x, B2y = _rp_order(2, A, G, a_, wk, v, xa1, 0.0, s1, 0.0)
                if order >= 3:
                    xa3, _, B3x, B3y = _rp_order(3, A, G, a_, wk, v, xa1, xa2, s1, s2)
        P = (bx, by, B1x, B1y, B2x, B2y, B3x, B3y)
        if L1 >= 0:
            _set_r(RL1, j, order, P, b1x, b1y, vax, vay, u1x, u1y, n1, xa1, xa2, xa3)
        if L2 >= 0:
            _put(RL2, j, order, P, b2x, b2y, cx, cy, RK2[AN][j], w1, w2, w3)


@_inline
def _pp_order(k, G1, G2, v, s1, s2, t1, t2):  # pragma: no cover - compiled
    """Order k of a PRP: the two slides' rates and the pin's rate."""
    ux, uy, vx_, vy_, s0, t0, p1, p2, p3, q1, q2, q3 = v
    tax, tay = _p_term(k, s0, s1, s2, ux, uy, p1, p2, p3)
    tbx, tby = _p_term(k, t0, t1, t2, vx_, vy_, q1, q2, q3)
    kax, kay = G1[2 * k] + tax, G1[2 * k + 1] + tay
    kbx, kby = G2[2 * k] + tbx, G2[2 * k + 1] + tby
    x1, x2 = _solve2(ux, uy, -vx_, -vy_, kbx - kax, kby - kay)
    return x1, x2, kax + ux * x1, kay + uy * x1


@_jit
def _dyad_pp(S, nl, pi, pf, ib, fb, U, lo, b, order, codes, g):  # pragma: no cover
    """PRP: two sliders pinned at B, each on a line of a known body."""
    K1, L1, K2, L2 = pi[ib + 3], pi[ib + 4], pi[ib + 7], pi[ib + 8]
    g1x, g1y, b1x, b1y, v1x, v1y = pf[fb : fb + 6]
    g2x, g2y, b2x, b2y, v2x, v2y = pf[fb + 7 : fb + 13]
    RK1, RK2, RL1, RL2 = _rows(S, nl, K1), _rows(S, nl, K2), _rows(S, nl, L1), _rows(S, nl, L2)
    cg = codes[g]
    for j in range(b):
        G1 = _pt(RK1, g1x, g1y, j, order)
        G2 = _pt(RK2, g2x, g2y, j, order)
        c1x, c1y, c2x, c2y = RK1[EX][j], RK1[EY][j], RK2[EX][j], RK2[EY][j]
        ux, uy = v1x * c1x - v1y * c1y, v1x * c1y + v1y * c1x
        vx_, vy_ = v2x * c2x - v2y * c2y, v2x * c2y + v2y * c2x
        p1, p2, p3 = _rates(RK1, j, order)
        q1, q2, q3 = _rates(RK2, j, order)
        s0, t0 = _solve2(ux, uy, -vx_, -vy_, G2[0] - G1[0], G2[1] - G1[1])
        cr = ux * vy_ - uy * vx_
        cg[lo + j] = _code(cr != 0.0, cr, 1.0)
        s1 = s2 = t1 = t2 = 0.0
        B1x = B1y = B2x = B2y = B3x = B3y = 0.0
        v = (ux, uy, vx_, vy_, s0, t0, p1, p2, p3, q1, q2, q3)
        if order >= 1:
            s1, t1, B1x, B1y = _pp_order(1, G1, G2, v, 0.0, 0.0, 0.0, 0.0)
            if order >= 2:
                s2, t2, B2x, B2y = _pp_order(2, G1, G2, v, s1, 0.0, t1, 0.0)
                if order >= 3:
                    _, _, B3x, B3y = _pp_order(3, G1, G2, v, s1, s2, t1, t2)
        P = (G1[0] + s0 * ux, G1[1] + s0 * uy, B1x, B1y, B2x, B2y, B3x, B3y)
        if L1 >= 0:
            _put(RL1, j, order, P, b1x, b1y, c1x, c1y, RK1[AN][j], p1, p2, p3)
        if L2 >= 0:
            _put(RL2, j, order, P, b2x, b2y, c2x, c2y, RK2[AN][j], q1, q2, q3)


@_jit
def _rpr(S, nl, pi, pf, ib, fb, U, lo, b, order, codes, g):  # pragma: no cover - compiled
    """Two links pivoted at known A and C, sliding on each other along a line through C."""
    L1, KA, KC, L2 = pi[ib + 2], pi[ib + 3], pi[ib + 4], pi[ib + 5]
    rax, ray, r1x, r1y, rcx, rcy, r2x, r2y, e, u0x, u0y, sign = pf[fb : fb + 12]
    RA, RC, RL1, RL2 = _rows(S, nl, KA), _rows(S, nl, KC), _rows(S, nl, L1), _rows(S, nl, L2)
    cg = codes[g]
    for j in range(b):
        A = _pt(RA, rax, ray, j, order)
        C = _pt(RC, rcx, rcy, j, order)
        wx, wy = C[0] - A[0], C[1] - A[1]
        r2 = wx * wx + wy * wy
        disc = r2 - e * e
        ok = disc >= -1e-14 * r2 and r2 > 0.0
        t = sign * math.sqrt(max(disc, 0.0))
        den = t * t + e * e
        ux = (wx * t + wy * e) / den if ok else math.nan  # w / (t + j e)
        uy = (wy * t - wx * e) / den if ok else math.nan
        cg[lo + j] = _code(ok, -wy * uy - wx * ux, math.sqrt(r2))
        om1 = om2 = om3 = t1 = t2 = 0.0
        if order >= 1:
            om1, t1 = _solve2(-wy, wx, ux, uy, C[2] - A[2], C[3] - A[3])
            if order >= 2:
                mx, my = _comb(0.0, 2.0 * t1 * om1, ux, uy)
                kx = C[4] - A[4] - mx + om1 * om1 * wx
                ky = C[5] - A[5] - my + om1 * om1 * wy
                om2, t2 = _solve2(-wy, wx, ux, uy, kx, ky)
                if order >= 3:
                    mx, my = _comb(-3.0 * t1 * om1 * om1, 3.0 * t2 * om1 + 3.0 * t1 * om2, ux, uy)
                    ax_, ay_ = _comb(3.0 * om1 * om2, om1 * om1 * om1, wx, wy)
                    kx, ky = C[6] - A[6] - mx + ax_, C[7] - A[7] - my + ay_
                    om3, _ = _solve2(-wy, wx, ux, uy, kx, ky)
        cx, cy = ux * u0x + uy * u0y, uy * u0x - ux * u0y  # E = û / û0 (û0 a unit vector)
        a = _atan2(cy, cx)
        _put(RL1, j, order, A, r1x, r1y, cx, cy, a, om1, om2, om3)
        if L2 >= 0:
            _put(RL2, j, order, C, r2x, r2y, cx, cy, a, om1, om2, om3)


@_inline
def _rpp_order(k, A, G, v, s1, s2, t1, t2):  # pragma: no cover - compiled
    """Order k of an RPP: the two slides' rates and the rate of the second link's point."""
    ux, uy, vx_, vy_, s0, t0, w1, w2, w3 = v
    px, py = _p_term(k, s0, s1, s2, ux, uy, w1, w2, w3)
    qx, qy = _p_term(k, t0, t1, t2, vx_, vy_, w1, w2, w3)
    rhsx = A[2 * k] - G[2 * k] - px - qx
    rhsy = A[2 * k + 1] - G[2 * k + 1] - py - qy
    x1, x2 = _solve2(ux, uy, vx_, vy_, rhsx, rhsy)
    return x1, x2, G[2 * k] + qx + x2 * vx_, G[2 * k + 1] + qy + x2 * vy_


@_jit
def _rpp(S, nl, pi, pf, ib, fb, U, lo, b, order, codes, g):  # pragma: no cover - compiled
    """A link pivoted at known A slides on a second link that slides on a known body."""
    L1, KA, K, L2 = pi[ib + 2], pi[ib + 3], pi[ib + 4], pi[ib + 5]
    rax, ray, r1x, r1y, rgx, rgy, v1x, v1y, v2x, v2y, r2x, r2y = pf[fb : fb + 12]
    RA, RK, RL1, RL2 = _rows(S, nl, KA), _rows(S, nl, K), _rows(S, nl, L1), _rows(S, nl, L2)
    cg = codes[g]
    for j in range(b):
        A = _pt(RA, rax, ray, j, order)
        G = _pt(RK, rgx, rgy, j, order)
        cx, cy = RK[EX][j], RK[EY][j]
        ux, uy = v1x * cx - v1y * cy, v1x * cy + v1y * cx
        vx_, vy_ = v2x * cx - v2y * cy, v2x * cy + v2y * cx
        w1, w2, w3 = _rates(RK, j, order)
        s0, t0 = _solve2(ux, uy, vx_, vy_, A[0] - G[0], A[1] - G[1])
        cr = ux * vy_ - uy * vx_
        cg[lo + j] = _code(cr != 0.0, cr, 1.0)
        s1 = s2 = t1 = t2 = 0.0
        X1x = X1y = X2x = X2y = X3x = X3y = 0.0
        v = (ux, uy, vx_, vy_, s0, t0, w1, w2, w3)
        if order >= 1:
            s1, t1, X1x, X1y = _rpp_order(1, A, G, v, 0.0, 0.0, 0.0, 0.0)
            if order >= 2:
                s2, t2, X2x, X2y = _rpp_order(2, A, G, v, s1, 0.0, t1, 0.0)
                if order >= 3:
                    _, _, X3x, X3y = _rpp_order(3, A, G, v, s1, s2, t1, t2)
        X = (G[0] + t0 * vx_, G[1] + t0 * vy_, X1x, X1y, X2x, X2y, X3x, X3y)
        _put(RL2, j, order, X, r2x, r2y, cx, cy, RK[AN][j], w1, w2, w3)
        if L1 >= 0:
            _put(RL1, j, order, A, r1x, r1y, cx, cy, RK[AN][j], w1, w2, w3)


# ---------------------------------------------------------------------- the program
@_jit
def _outputs(S, nl, lo, b, order, links, pts_i, pts_f, lens_i, lens_f,
             ang_out, rot_out, pts_re, pts_im, len_out):  # fmt: skip  # pragma: no cover
    """Write a block: angles and rates of ``links``, points (and centres), lengths."""
    nlk = len(links)
    for q in range(nlk):
        R = _rows(S, nl, links[q])
        ang_out[q, lo : lo + b] = R[AN][:b]
        for k in range(order):
            rot_out[k * nlk + q, lo : lo + b] = R[7 + 3 * k][:b]
    npt = len(pts_i)
    for p in range(npt):
        R = _rows(S, nl, pts_i[p])
        rx, ry = pts_f[2 * p], pts_f[2 * p + 1]
        x0, y0 = pts_re[p], pts_im[p]
        x1, y1 = pts_re[npt + p], pts_im[npt + p]
        x2, y2 = pts_re[min(2, order) * npt + p], pts_im[min(2, order) * npt + p]
        x3, y3 = pts_re[min(3, order) * npt + p], pts_im[min(3, order) * npt + p]
        for j in range(b):
            P = _pt(R, rx, ry, j, order)
            x0[lo + j], y0[lo + j] = P[0], P[1]
            if order >= 1:
                x1[lo + j], y1[lo + j] = P[2], P[3]
            if order >= 2:
                x2[lo + j], y2[lo + j] = P[4], P[5]
            if order >= 3:
                x3[lo + j], y3[lo + j] = P[6], P[7]
    nln = len(lens_i) // 4
    for q in range(nln):
        kind = lens_i[4 * q]
        RS = _rows(S, nl, lens_i[4 * q + 1])
        RT = _rows(S, nl, lens_i[4 * q + 2])
        RG = _rows(S, nl, lens_i[4 * q + 3])
        f = 6 * q
        for j in range(b):
            Sp = _pt(RS, lens_f[f], lens_f[f + 1], j, order)
            T = _pt(RT, lens_f[f + 2], lens_f[f + 3], j, order)
            if kind == 0:  # a slider or slot: displacement along the guide's line
                cx, cy = RG[EX][j], RG[EY][j]
                ux = lens_f[f + 4] * cx - lens_f[f + 5] * cy
                uy = lens_f[f + 4] * cy + lens_f[f + 5] * cx
                w1, w2, _ = _rates(RG, j, order)
                d0 = (T[0] - Sp[0]) * ux + (T[1] - Sp[1]) * uy
                d1 = (T[2] - Sp[2]) * ux + (T[3] - Sp[3]) * uy
                d2 = (T[4] - Sp[4]) * ux + (T[5] - Sp[5]) * uy + d0 * w1 * w1
                d3 = (T[6] - Sp[6]) * ux + (T[7] - Sp[7]) * uy
                d3 += 3.0 * d1 * w1 * w1 + 3.0 * d0 * w1 * w2
            else:  # an actuator: its length
                rx_, ry_ = T[0] - Sp[0], T[1] - Sp[1]
                d0 = math.sqrt(rx_ * rx_ + ry_ * ry_)
                ux, uy = rx_ / d0, ry_ / d0
                c1x = (T[2] - Sp[2]) * ux + (T[3] - Sp[3]) * uy
                c1y = (T[3] - Sp[3]) * ux - (T[2] - Sp[2]) * uy
                c2x = (T[4] - Sp[4]) * ux + (T[5] - Sp[5]) * uy
                c2y = (T[5] - Sp[5]) * ux - (T[4] - Sp[4]) * uy
                c3x = (T[6] - Sp[6]) * ux + (T[7] - Sp[7]) * uy
                p1 = c1y / d0
                d1 = c1x
                p2 = (c2y - 2.0 * d1 * p1) / d0
                d2 = c2x + d0 * p1 * p1
                d3 = c3x + 3.0 * d1 * p1 * p1 + 3.0 * d0 * p1 * p2
            len_out[q, lo + j] = d0
            if order >= 1:
                len_out[nln + q, lo + j] = d1
            if order >= 2:
                len_out[2 * nln + q, lo + j] = d2
            if order >= 3:
                len_out[3 * nln + q, lo + j] = d3


@_jit
def run(lo, hi, pi, pf, ns, U, order, nl, links, pts_i, pts_f, lens_i, lens_f,
        ang_out, rot_out, pts_re, pts_im, len_out, codes):  # fmt: skip  # pragma: no cover
    """Samples ``lo`` to ``hi`` (a slice, for threads), block by block, step by step."""
    S = (
        np.zeros((nl, BLOCK)), np.zeros((nl, BLOCK)), np.ones((nl, BLOCK)),
        np.zeros((nl, BLOCK)), np.zeros((nl, BLOCK)), np.zeros((3 * nl, BLOCK)),
        np.zeros((3 * nl, BLOCK)), np.zeros((3 * nl, BLOCK)),
    )  # fmt: skip
    for start in range(lo, hi, BLOCK):
        b = min(BLOCK, hi - start)
        for s in range(ns):
            ib, fb = s * NI, s * NF
            op, g = pi[ib], pi[ib + 1]
            if op == CRANK:
                _crank(S, nl, pi, pf, ib, fb, U, start, b, order)
            elif op == MOTOR:
                _motor(S, nl, pi, pf, ib, fb, U, start, b, order)
            elif op == SLIDE:
                _slide(S, nl, pi, pf, ib, fb, U, start, b, order)
            elif op == DYAD:
                k1, k2 = pi[ib + 2], pi[ib + 6]
                if k1 == 0 and k2 == 0:
                    _dyad_rr(S, nl, pi, pf, ib, fb, U, start, b, order, codes, g)
                elif k1 == 0 or k2 == 0:
                    ia, fa, ip, fp = (
                        (ib + 2, fb, ib + 6, fb + 7) if k1 == 0 else (ib + 6, fb + 7, ib + 2, fb)
                    )
                    _dyad_rp(
                        S, nl, pi, pf, ia, fa, ip, fp, U, start, b, order, pf[fb + 14], codes, g
                    )
                else:
                    _dyad_pp(S, nl, pi, pf, ib, fb, U, start, b, order, codes, g)
            elif op == RPR:
                _rpr(S, nl, pi, pf, ib, fb, U, start, b, order, codes, g)
            else:
                _rpp(S, nl, pi, pf, ib, fb, U, start, b, order, codes, g)
            if op in (CRANK, MOTOR, SLIDE):
                codes[g, start : start + b] = 0
        _outputs(S, nl, start, b, order, links, pts_i, pts_f, lens_i, lens_f,
                 ang_out, rot_out, pts_re, pts_im, len_out)  # fmt: skip
    return 0


def warm_up() -> None:
    """Compile (or load from numba's cache) the kernel."""
    from .linkage import Linkage
    from .linkage.kernel import Tables, encode

    lk = Linkage({"O": 0, "A": 1j, "B": 3 + 1j, "Q": 4 + 0j})
    lk.ground("O", "Q").link("c", "O", "A").link("r", "A", "B").link("k", "Q", "B")
    program = lk.drive("c")._compile().program
    enc = encode(program)
    n = 2
    U = np.zeros((4, n))
    tables = Tables(*(np.zeros(0, t) for t in (np.int64, np.int64, float, np.int64, float)))
    z = np.zeros((0, n))
    pts = np.zeros((0, n), complex)
    codes = np.zeros((len(program.deps), n), np.int8)
    for order in (0, 2, 3):
        run(0, n, enc.pi, enc.pf, enc.ns, U, order, program.n_links, tables.links,
            tables.pts_i, tables.pts_f, tables.lens_i, tables.lens_f, z, z, pts.real,
            pts.imag, z, codes)  # fmt: skip
