"""Compiled (numba) kernel of a linkage's closed-form program.

Imported only through :mod:`machdyn.jit`'s rule (:func:`machdyn.linkage.kernel.compiled_kernel`);
the NumPy program of :mod:`machdyn.linkage.program` is the reference it is
tested against (every linkage test runs on both).

The program is data: each step is a row of integers and floats
(:func:`machdyn.linkage.kernel.encode`), so one compiled kernel serves every
linkage and a changed linkage compiles nothing. The kernel takes the samples
in blocks of :data:`BLOCK` and runs each step over a whole block before the
next (one dispatch per step and block, the step's loop free of branches on
the program), on a small state (one row per link and column per sample of the
block, in the first levels of cache), in **real** arithmetic (numba's complex
numbers call helper functions; the elementary functions are the polynomial
ones of :mod:`machdyn._kernels`). The arithmetic is the NumPy path's: a driver
places its link; a dyad's pin is a circle–circle (RRR), circle–line (RRP) or
line–line (PRP) meet with the drawn assembly sign, an RPR's line a tangent, an
RPP a line–line meet; every derivative order is the same 2 × 2 system solved
by Cramer's rule.

One call (:func:`run`) takes the whole sweep: the program and the tables of
what to report are packed in one integer and one float array
(:func:`machdyn.linkage.kernel.pack`), the results go to one real array
(angles, angular rates, lengths) and one complex array seen as real pairs
(points and centres of mass). The angles of links placed through an ``atan2``
(dyad arms and what turns with them) are taken when a block is written out;
along a sweep they are then unwrapped (:func:`_follow`), which also runs the
program (positions only) along the path from the drawn pose to the first
sample and between samples further apart than the path's step, as
:mod:`machdyn.linkage.sweep` does in NumPy.

State of link ``i`` (row 0 is the ground: zeros, ``E = 1``) at column ``j`` of
a block: ``st[i, :, j]`` = origin ``(ox, oy)``, rotation ``E = (ex, ey) =
e^{jΔ}``, its angle Δ (exact for links placed by a driver; not kept for those
from an ``atan2``), then for k = 1, 2, 3 the origin's rate ``(vx, vy)`` and the
angle's rate ``w`` at columns ``5 + 3 (k − 1)`` …
"""

from __future__ import annotations

import math

import llvmlite.binding
import numpy as np

from ._kernels import angle as _angle_2pi
from ._kernels import sincos
from ._numba_cache import njit
from .linkage._scalar import CRANK, DYAD, MOTOR, NF, NI, RPP, RPR, SINGULAR_SINE

# "contract" lets LLVM fuse a * b + c; "arcp" turns a division by a value used
# several times into one reciprocal. Neither assumes finite values (NaN marks
# samples that do not assemble).
_FAST = {"contract", "arcp"}
_jit = njit(cache=True, nogil=True, error_model="numpy", fastmath=_FAST)
# The per-sample helpers are separate numba functions that LLVM inlines into the
# block loops while :func:`warm_up` compiles with a high inlining threshold
# (numba's own IR inlining, ``inline="always"``, gives the same machine code but
# re-types every inlined copy: 204 s to compile from an empty cache, against 33 s).
_inline = njit(error_model="numpy", fastmath=_FAST)
#: LLVM's inlining threshold while the kernel compiles, and its default restored after.
INLINE_THRESHOLD, DEFAULT_INLINE_THRESHOLD = 100_000, 225

#: Samples per block (each step runs over a block before the next step).
BLOCK = 128
_PI = math.pi
_TWO_PI = 2.0 * math.pi
OX, OY, EX, EY, AN = 0, 1, 2, 3, 4  # then VX, VY, W of order k at 5 + 3 (k - 1)
#: Columns of a link's state.
NS = 14
#: Entries of the packed integer header (:func:`machdyn.linkage.kernel.pack`).
NH = 17


@_inline
def _atan2(y, x):  # pragma: no cover - compiled
    a = _angle_2pi(y, x)
    return a - _TWO_PI if a > _PI else a


@_inline
def _pt(st, i, rx, ry, order, j):  # pragma: no cover - compiled
    """The material point drawn at offset (rx, ry) on link i: 8 floats."""
    cx, cy = st[i, EX, j], st[i, EY, j]
    qx = rx * cx - ry * cy
    qy = rx * cy + ry * cx
    p1x = p1y = p2x = p2y = p3x = p3y = 0.0
    if order >= 1:
        w1 = st[i, 7, j]
        p1x = st[i, 5, j] - w1 * qy
        p1y = st[i, 6, j] + w1 * qx
        if order >= 2:
            w2 = st[i, 10, j]
            p2x = st[i, 8, j] - w2 * qy - w1 * w1 * qx
            p2y = st[i, 9, j] + w2 * qx - w1 * w1 * qy
            if order >= 3:
                c = st[i, 13, j] - w1 * w1 * w1
                d = 3.0 * w1 * w2
                p3x = st[i, 11, j] - c * qy - d * qx
                p3y = st[i, 12, j] + c * qx - d * qy
    return st[i, OX, j] + qx, st[i, OY, j] + qy, p1x, p1y, p2x, p2y, p3x, p3y


@_inline
def _put(st, i, order, P, rx, ry, cx, cy, a, w1, w2, w3, j):  # pragma: no cover - compiled
    """Place link i from its point drawn at (rx, ry), at P, turned by E = c."""
    st[i, EX, j] = cx
    st[i, EY, j] = cy
    st[i, AN, j] = a
    qx = -(rx * cx - ry * cy)
    qy = -(rx * cy + ry * cx)
    st[i, OX, j] = P[0] + qx
    st[i, OY, j] = P[1] + qy
    if order >= 1:
        st[i, 7, j] = w1
        st[i, 5, j] = P[2] - w1 * qy
        st[i, 6, j] = P[3] + w1 * qx
        if order >= 2:
            st[i, 10, j] = w2
            st[i, 8, j] = P[4] - w2 * qy - w1 * w1 * qx
            st[i, 9, j] = P[5] + w2 * qx - w1 * w1 * qy
            if order >= 3:
                st[i, 13, j] = w3
                c = w3 - w1 * w1 * w1
                d = 3.0 * w1 * w2
                st[i, 11, j] = P[6] - c * qy - d * qx
                st[i, 12, j] = P[7] + c * qx - d * qy


@_inline
def _rates(st, i, order, j):  # pragma: no cover - compiled
    w1 = st[i, 7, j] if order >= 1 else 0.0
    w2 = st[i, 10, j] if order >= 2 else 0.0
    w3 = st[i, 13, j] if order >= 3 else 0.0
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
def _set_r(st, R, order, P, brx, bry, vx_, vy_, ux, uy, n, x1, x2, x3, j):  # pragma: no cover
    """Place the link of an R arm: its rotation is the arm vector over the drawn one."""
    cx = (vx_ * ux + vy_ * uy) / n
    cy = (vy_ * ux - vx_ * uy) / n
    _put(st, R, order, P, brx, bry, cx, cy, 0.0, x1, x2, x3, j)  # its angle: atan2, later


# ---------------------------------------------------------------------- drivers
@_inline
def _crank(st, ri, rf, U, i, order, j):  # pragma: no cover - compiled
    L, K, d = ri[2], ri[3], ri[4]
    rkx, rky, rlx, rly, theta0 = rf[0], rf[1], rf[2], rf[3], rf[4]
    RK, RL = max(K, 0), max(L, 0)
    delta = U[4 * d, i] - theta0
    s, c = sincos(delta)
    # pivoted on the ground: the pin where it is drawn, at rest (the values _pt gives)
    P = (rkx, rky, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0) if RK == 0 else _pt(st, RK, rkx, rky, order, j)
    w1, w2, w3 = U[4 * d + 1, i], U[4 * d + 2, i], U[4 * d + 3, i]
    _put(st, RL, order, P, rlx, rly, c, s, delta, w1, w2, w3, j)


@_inline
def _motor(st, ri, rf, U, i, order, j):  # pragma: no cover - compiled
    L, K, Sr, d = ri[2], ri[3], ri[4], ri[5]
    rkx, rky, rlx, rly, sg, phi0 = (
        rf[0],
        rf[1],
        rf[2],
        rf[3],
        rf[4],
        rf[5],
    )
    RK, RL, RS = max(K, 0), max(L, 0), max(Sr, 0)
    delta = sg * (U[4 * d, i] - phi0)
    s, c = sincos(delta)
    ex, ey = st[RS, EX, j], st[RS, EY, j]
    w1, w2, w3 = _rates(st, RS, order, j)
    P = _pt(st, RK, rkx, rky, order, j)
    _put(st, RL, order, P, rlx, rly, ex * c - ey * s, ex * s + ey * c, st[RS, AN, j] + delta,
         w1 + sg * U[4 * d + 1, i], w2 + sg * U[4 * d + 2, i],
         w3 + sg * U[4 * d + 3, i], j)  # fmt: skip


@_inline
def _slide(st, ri, rf, U, i, order, j):  # pragma: no cover - compiled
    L, K, Lf, La, d, block = ri[2], ri[3], ri[4], ri[5], ri[6], ri[7]
    rfx, rfy, rax, ray, u0x, u0y = (
        rf[0],
        rf[1],
        rf[2],
        rf[3],
        rf[4],
        rf[5],
    )
    RK, RL = max(K, 0), max(L, 0)
    RB = max(Lf if block == 1 else La, 0)  # the known body's point: foot or block's pin
    bx, by = (rfx, rfy) if block == 1 else (rax, ray)
    px, py = (rax, ray) if block == 1 else (rfx, rfy)  # the moving link's point
    sg = 1.0 if block == 1 else -1.0
    cx, cy = st[RK, EX, j], st[RK, EY, j]
    ux, uy = u0x * cx - u0y * cy, u0x * cy + u0y * cx
    w1, w2, w3 = _rates(st, RK, order, j)
    Q = _pt(st, RB, bx, by, order, j)
    d0, d1, d2, d3 = U[4 * d, i], U[4 * d + 1, i], U[4 * d + 2, i], U[4 * d + 3, i]
    t1x, t1y = _p_term(1, d0, d1, d2, ux, uy, w1, w2, w3)
    t2x, t2y = _p_term(2, d0, d1, d2, ux, uy, w1, w2, w3)
    t3x, t3y = _p_term(3, d0, d1, d2, ux, uy, w1, w2, w3)
    P = (
        Q[0] + sg * d0 * ux, Q[1] + sg * d0 * uy,
        Q[2] + sg * (t1x + d1 * ux), Q[3] + sg * (t1y + d1 * uy),
        Q[4] + sg * (t2x + d2 * ux), Q[5] + sg * (t2y + d2 * uy),
        Q[6] + sg * (t3x + d3 * ux), Q[7] + sg * (t3y + d3 * uy),
    )  # fmt: skip
    _put(st, RL, order, P, px, py, cx, cy, st[RK, AN, j], w1, w2, w3, j)


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


@_inline
def _rr_solve(st, ri, rf, U, i, order, j):  # pragma: no cover
    """RRR (an arm may be an actuator's bar: a driven length): the pin, the arms' rates.

    Reads only the known links' state (:func:`_rr_put` writes the new links'),
    so two samples' solves may run side by side.
    """
    K1, d1, K2, d2 = ri[3], ri[5], ri[7], ri[9]
    r1x, r1y, len1, r2x, r2y, len2, sign = rf[0], rf[1], rf[6], rf[7], rf[8], rf[13], rf[14]
    RK1, RK2 = max(K1, 0), max(K2, 0)
    A = _pt(st, RK1, r1x, r1y, order, j)
    C = _pt(st, RK2, r2x, r2y, order, j)
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
    code = _code(ok, vax * vby - vay * vbx, a0 * c0)
    eax, eay, ebx, eby = vax / a0, vay / a0, vbx / c0, vby / c0
    # unknowns: the arms' angles; columns j·va and −j·vb
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
    return code, P, (vax, vay, vbx, vby), (xa1, xa2, xa3, xb1, xb2, xb3)


@_inline
def _rr_put(st, ri, rf, codes, g, i, order, j, R):  # pragma: no cover
    """Write an RRR's status code and place its two links (R: :func:`_rr_solve`'s answer)."""
    code, P, vv, xx = R
    vax, vay, vbx, vby = vv
    xa1, xa2, xa3, xb1, xb2, xb3 = xx
    L1, L2 = ri[4], ri[8]
    b1x, b1y, u1x, u1y = rf[2], rf[3], rf[4], rf[5]
    b2x, b2y, u2x, u2y = rf[9], rf[10], rf[11], rf[12]
    n1, n2 = u1x * u1x + u1y * u1y, u2x * u2x + u2y * u2y
    RL1, RL2 = max(L1, 0), max(L2, 0)
    codes[g, i] = code
    if L1 >= 0:
        _set_r(st, RL1, order, P, b1x, b1y, vax, vay, u1x, u1y, n1, xa1, xa2, xa3, j)
    if L2 >= 0:
        _set_r(st, RL2, order, P, b2x, b2y, vbx, vby, u2x, u2y, n2, xb1, xb2, xb3, j)


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


@_inline
def _dyad_rp(st, ar, fr, ap, fp, U, i, order, sign, codes, g, j):  # pragma: no cover
    """RRP / PRR: the R arm's integers and floats (ar, fr), the P arm's (ap, fp)."""
    K1, L1, d1, K2, L2 = ar[0], ar[1], ar[2], ap[0], ap[1]
    r1x, r1y, b1x, b1y, u1x, u1y, len1 = fr
    gx, gy, b2x, b2y, u2x, u2y = fp
    n1 = u1x * u1x + u1y * u1y
    RK1, RK2, RL1, RL2 = max(K1, 0), max(K2, 0), max(L1, 0), max(L2, 0)
    A = _pt(st, RK1, r1x, r1y, order, j)
    G = _pt(st, RK2, gx, gy, order, j)
    cx, cy = st[RK2, EX, j], st[RK2, EY, j]
    ux, uy = u2x * cx - u2y * cy, u2x * cy + u2y * cx
    w1, w2, w3 = _rates(st, RK2, order, j)
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
    codes[g, i] = _code(ok, -vay * uy - vax * ux, a0)
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
        _set_r(st, RL1, order, P, b1x, b1y, vax, vay, u1x, u1y, n1, xa1, xa2, xa3, j)
    if L2 >= 0:
        _put(st, RL2, order, P, b2x, b2y, cx, cy, st[RK2, AN, j], w1, w2, w3, j)


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


@_inline
def _dyad_pp(st, ri, rf, U, i, order, codes, g, j):  # pragma: no cover
    """PRP: two sliders pinned at B, each on a line of a known body."""
    K1, L1, K2, L2 = ri[3], ri[4], ri[7], ri[8]
    g1x, g1y, b1x = rf[0], rf[1], rf[2]
    b1y, v1x, v1y = rf[3], rf[4], rf[5]
    g2x, g2y, b2x = rf[7], rf[8], rf[9]
    b2y, v2x, v2y = rf[10], rf[11], rf[12]
    RK1, RK2, RL1, RL2 = max(K1, 0), max(K2, 0), max(L1, 0), max(L2, 0)
    G1 = _pt(st, RK1, g1x, g1y, order, j)
    G2 = _pt(st, RK2, g2x, g2y, order, j)
    c1x, c1y, c2x, c2y = st[RK1, EX, j], st[RK1, EY, j], st[RK2, EX, j], st[RK2, EY, j]
    ux, uy = v1x * c1x - v1y * c1y, v1x * c1y + v1y * c1x
    vx_, vy_ = v2x * c2x - v2y * c2y, v2x * c2y + v2y * c2x
    p1, p2, p3 = _rates(st, RK1, order, j)
    q1, q2, q3 = _rates(st, RK2, order, j)
    s0, t0 = _solve2(ux, uy, -vx_, -vy_, G2[0] - G1[0], G2[1] - G1[1])
    cr = ux * vy_ - uy * vx_
    codes[g, i] = _code(cr != 0.0, cr, 1.0)
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
        _put(st, RL1, order, P, b1x, b1y, c1x, c1y, st[RK1, AN, j], p1, p2, p3, j)
    if L2 >= 0:
        _put(st, RL2, order, P, b2x, b2y, c2x, c2y, st[RK2, AN, j], q1, q2, q3, j)


@_inline
def _rpr(st, ri, rf, U, i, order, codes, g, j):  # pragma: no cover
    """Two links pivoted at known A and C, sliding on each other along a line through C."""
    L1, KA, KC, L2 = ri[2], ri[3], ri[4], ri[5]
    rax, ray, r1x = rf[0], rf[1], rf[2]
    r1y, rcx, rcy = rf[3], rf[4], rf[5]
    r2x, r2y, e = rf[6], rf[7], rf[8]
    u0x, u0y, sign = rf[9], rf[10], rf[11]
    RA, RC, RL1, RL2 = max(KA, 0), max(KC, 0), max(L1, 0), max(L2, 0)
    A = _pt(st, RA, rax, ray, order, j)
    C = _pt(st, RC, rcx, rcy, order, j)
    wx, wy = C[0] - A[0], C[1] - A[1]
    r2 = wx * wx + wy * wy
    disc = r2 - e * e
    ok = disc >= -1e-14 * r2 and r2 > 0.0
    t = sign * math.sqrt(max(disc, 0.0))
    den = t * t + e * e
    ux = (wx * t + wy * e) / den if ok else math.nan  # w / (t + j e)
    uy = (wy * t - wx * e) / den if ok else math.nan
    codes[g, i] = _code(ok, -wy * uy - wx * ux, math.sqrt(r2))
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
    _put(st, RL1, order, A, r1x, r1y, cx, cy, 0.0, om1, om2, om3, j)  # angle: atan2 later
    if L2 >= 0:
        _put(st, RL2, order, C, r2x, r2y, cx, cy, 0.0, om1, om2, om3, j)


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


@_inline
def _rpp(st, ri, rf, U, i, order, codes, g, j):  # pragma: no cover
    """A link pivoted at known A slides on a second link that slides on a known body."""
    L1, KA, K, L2 = ri[2], ri[3], ri[4], ri[5]
    rax, ray, r1x = rf[0], rf[1], rf[2]
    r1y, rgx, rgy = rf[3], rf[4], rf[5]
    v1x, v1y, v2x = rf[6], rf[7], rf[8]
    v2y, r2x, r2y = rf[9], rf[10], rf[11]
    RA, RK, RL1, RL2 = max(KA, 0), max(K, 0), max(L1, 0), max(L2, 0)
    A = _pt(st, RA, rax, ray, order, j)
    G = _pt(st, RK, rgx, rgy, order, j)
    cx, cy = st[RK, EX, j], st[RK, EY, j]
    ux, uy = v1x * cx - v1y * cy, v1x * cy + v1y * cx
    vx_, vy_ = v2x * cx - v2y * cy, v2x * cy + v2y * cx
    w1, w2, w3 = _rates(st, RK, order, j)
    s0, t0 = _solve2(ux, uy, vx_, vy_, A[0] - G[0], A[1] - G[1])
    cr = ux * vy_ - uy * vx_
    codes[g, i] = _code(cr != 0.0, cr, 1.0)
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
    _put(st, RL2, order, X, r2x, r2y, cx, cy, st[RK, AN, j], w1, w2, w3, j)
    if L1 >= 0:
        _put(st, RL1, order, A, r1x, r1y, cx, cy, st[RK, AN, j], w1, w2, w3, j)


# ---------------------------------------------------------------------- blocks
# Each block reads its step's row into scalars before the loop over the samples
# (the row and the state are both float arrays that may alias: read in the loop,
# every parameter would be loaded again after each store to the state), and the
# loop is written out for order 2 (positions, velocities, accelerations: the usual
# call) so that the order's branches fold there; other orders branch at run time
# (a copy per order would double the compile time again).
@_inline
def _row_i(pi, ib):  # pragma: no cover - compiled
    """A step's integer row (:data:`~machdyn.linkage._scalar.NI` entries) as scalars."""
    return (pi[ib], pi[ib + 1], pi[ib + 2], pi[ib + 3], pi[ib + 4],
            pi[ib + 5], pi[ib + 6], pi[ib + 7], pi[ib + 8], pi[ib + 9])  # fmt: skip


@_inline
def _row_f(pf, fb):  # pragma: no cover - compiled
    """A step's float row (:data:`~machdyn.linkage._scalar.NF` entries) as scalars."""
    return (pf[fb], pf[fb + 1], pf[fb + 2], pf[fb + 3], pf[fb + 4], pf[fb + 5],
            pf[fb + 6], pf[fb + 7], pf[fb + 8], pf[fb + 9], pf[fb + 10], pf[fb + 11],
            pf[fb + 12], pf[fb + 13], pf[fb + 14], pf[fb + 15])  # fmt: skip


@_jit
def _crank_block(st, pi, pf, ib, fb, U, start, b, order):  # pragma: no cover - compiled
    ri, rf = _row_i(pi, ib), _row_f(pf, fb)
    if order == 2:
        for j in range(b):
            _crank(st, ri, rf, U, start + j, 2, j)
    else:
        for j in range(b):
            _crank(st, ri, rf, U, start + j, order, j)


@_jit
def _motor_block(st, pi, pf, ib, fb, U, start, b, order):  # pragma: no cover - compiled
    ri, rf = _row_i(pi, ib), _row_f(pf, fb)
    if order == 2:
        for j in range(b):
            _motor(st, ri, rf, U, start + j, 2, j)
    else:
        for j in range(b):
            _motor(st, ri, rf, U, start + j, order, j)


@_jit
def _slide_block(st, pi, pf, ib, fb, U, start, b, order):  # pragma: no cover - compiled
    ri, rf = _row_i(pi, ib), _row_f(pf, fb)
    if order == 2:
        for j in range(b):
            _slide(st, ri, rf, U, start + j, 2, j)
    else:
        for j in range(b):
            _slide(st, ri, rf, U, start + j, order, j)


@_jit
def _rr_block(st, pi, pf, ib, fb, U, start, b, order, codes, g):  # pragma: no cover
    """RRR dyads; at order 2 two samples at a time (two chains of divisions to overlap)."""
    ri, rf = _row_i(pi, ib), _row_f(pf, fb)
    j0 = 0
    if order == 2:
        for j in range(0, b - 1, 2):
            R0 = _rr_solve(st, ri, rf, U, start + j, 2, j)
            R1 = _rr_solve(st, ri, rf, U, start + j + 1, 2, j + 1)
            _rr_put(st, ri, rf, codes, g, start + j, 2, j, R0)
            _rr_put(st, ri, rf, codes, g, start + j + 1, 2, j + 1, R1)
        j0 = b - b % 2
    for j in range(j0, b):
        R = _rr_solve(st, ri, rf, U, start + j, order, j)
        _rr_put(st, ri, rf, codes, g, start + j, order, j, R)


@_jit
def _rp_block(st, pi, pf, ib, fb, flip, U, start, b, order, codes, g):  # pragma: no cover
    """An RRP (arm 1 the R arm) or, ``flip``, a PRR (arm 2 the R arm)."""
    ri, rf = _row_i(pi, ib), _row_f(pf, fb)
    r1, r2 = (ri[3], ri[4], ri[5]), (ri[7], ri[8], ri[9])
    f1 = (rf[0], rf[1], rf[2], rf[3], rf[4], rf[5], rf[6])
    f2 = (rf[7], rf[8], rf[9], rf[10], rf[11], rf[12], rf[13])
    ar, fr = (r2, f2) if flip else (r1, f1)
    ap, fq = (r1, f1) if flip else (r2, f2)
    fp = (fq[0], fq[1], fq[2], fq[3], fq[4], fq[5])
    sign = rf[14]
    if order == 2:
        for j in range(b):
            _dyad_rp(st, ar, fr, ap, fp, U, start + j, 2, sign, codes, g, j)
    else:
        for j in range(b):
            _dyad_rp(st, ar, fr, ap, fp, U, start + j, order, sign, codes, g, j)


@_jit
def _pp_block(st, pi, pf, ib, fb, U, start, b, order, codes, g):  # pragma: no cover
    ri, rf = _row_i(pi, ib), _row_f(pf, fb)
    if order == 2:
        for j in range(b):
            _dyad_pp(st, ri, rf, U, start + j, 2, codes, g, j)
    else:
        for j in range(b):
            _dyad_pp(st, ri, rf, U, start + j, order, codes, g, j)


@_jit
def _rpr_block(st, pi, pf, ib, fb, U, start, b, order, codes, g):  # pragma: no cover
    ri, rf = _row_i(pi, ib), _row_f(pf, fb)
    if order == 2:
        for j in range(b):
            _rpr(st, ri, rf, U, start + j, 2, codes, g, j)
    else:
        for j in range(b):
            _rpr(st, ri, rf, U, start + j, order, codes, g, j)


@_jit
def _rpp_block(st, pi, pf, ib, fb, U, start, b, order, codes, g):  # pragma: no cover
    ri, rf = _row_i(pi, ib), _row_f(pf, fb)
    if order == 2:
        for j in range(b):
            _rpp(st, ri, rf, U, start + j, 2, codes, g, j)
    else:
        for j in range(b):
            _rpp(st, ri, rf, U, start + j, order, codes, g, j)


# ---------------------------------------------------------------------- the program
@_jit
def _steps(st, pi, pf, ns, U, start, b, order, codes):  # pragma: no cover - compiled
    """Every step of the program at columns ``start`` … ``start + b − 1`` of U."""
    for s in range(ns):
        ib, fb = s * NI, s * NF
        op, g = pi[ib], pi[ib + 1]
        if op == DYAD:
            k1, k2 = pi[ib + 2], pi[ib + 6]
            if k1 == 0 and k2 == 0:
                _rr_block(st, pi, pf, ib, fb, U, start, b, order, codes, g)
            elif k1 == 0:
                _rp_block(st, pi, pf, ib, fb, False, U, start, b, order, codes, g)
            elif k2 == 0:
                _rp_block(st, pi, pf, ib, fb, True, U, start, b, order, codes, g)
            else:
                _pp_block(st, pi, pf, ib, fb, U, start, b, order, codes, g)
        elif op == RPR:
            _rpr_block(st, pi, pf, ib, fb, U, start, b, order, codes, g)
        elif op == RPP:
            _rpp_block(st, pi, pf, ib, fb, U, start, b, order, codes, g)
        else:  # a driver: always assembled
            if op == CRANK:
                _crank_block(st, pi, pf, ib, fb, U, start, b, order)
            elif op == MOTOR:
                _motor_block(st, pi, pf, ib, fb, U, start, b, order)
            else:
                _slide_block(st, pi, pf, ib, fb, U, start, b, order)
            codes[g, start : start + b] = 0


@_inline
def _new_state(nl):  # pragma: no cover - compiled
    st = np.zeros((nl, NS, BLOCK))
    st[:, EX, :] = 1.0
    return st


@_jit
def _angles(st, start, b, order, links, exact, theta0, F):  # pragma: no cover - compiled
    """Write a block's link angles (exact, or from the rotation's atan2) and their rates."""
    nq = len(links)
    for q in range(nq):  # rows as 1-D views: contiguous loops the vectoriser takes
        L, t0 = links[q], theta0[q]
        out = F[q, start : start + b]
        if exact[q]:
            an = st[L, AN, :b]
            for j in range(b):
                out[j] = an[j] + t0
        else:
            ey, ex = st[L, EY, :b], st[L, EX, :b]
            for j in range(b):
                out[j] = _atan2(ey[j], ex[j]) + t0
        for k in range(order):
            F[(k + 1) * nq + q, start : start + b] = st[L, 7 + 3 * k, :b]


@_inline
def _point_rows(s, rx, ry, order, R0, R1, R2, R3, b):  # pragma: no cover - compiled
    """One point's block: ``s`` its link's state, ``Rk`` its order-k row (re/im pairs)."""
    for j in range(b):
        cx, cy = s[EX, j], s[EY, j]
        qx = rx * cx - ry * cy
        qy = rx * cy + ry * cx
        R0[2 * j], R0[2 * j + 1] = s[OX, j] + qx, s[OY, j] + qy
        if order >= 1:
            w1 = s[7, j]
            R1[2 * j], R1[2 * j + 1] = s[5, j] - w1 * qy, s[6, j] + w1 * qx
            if order >= 2:
                w2 = s[10, j]
                R2[2 * j] = s[8, j] - w2 * qy - w1 * w1 * qx
                R2[2 * j + 1] = s[9, j] + w2 * qx - w1 * w1 * qy
                if order >= 3:
                    c = s[13, j] - w1 * w1 * w1
                    d = 3.0 * w1 * w2
                    R3[2 * j] = s[11, j] - c * qy - d * qx
                    R3[2 * j + 1] = s[12, j] + c * qx - d * qy


@_jit
def _points(st, start, b, order, pts_i, pts_f, Pf):  # pragma: no cover - compiled
    """Write a block's points and centres of mass (complex, as real pairs) and their rates.

    The arithmetic of :func:`_pt`, on 1-D views of the rows (order 2 written out).
    """
    npt = len(pts_i)
    c0, c1 = 2 * start, 2 * (start + b)
    for p in range(npt):
        L, rx, ry = pts_i[p], pts_f[2 * p], pts_f[2 * p + 1]
        R0 = Pf[p, c0:c1]
        R1 = Pf[min(order, 1) * npt + p, c0:c1]  # rows beyond the order: never written
        R2 = Pf[min(order, 2) * npt + p, c0:c1]
        R3 = Pf[min(order, 3) * npt + p, c0:c1]
        if L == 0:  # a ground point: where it is drawn, at rest (the values _pt gives)
            for j in range(b):
                R0[2 * j], R0[2 * j + 1] = rx, ry
            for k in range(1, order + 1):
                Pf[k * npt + p, c0:c1] = 0.0
        elif order == 2:
            _point_rows(st[L], rx, ry, 2, R0, R1, R2, R3, b)
        else:
            _point_rows(st[L], rx, ry, order, R0, R1, R2, R3, b)


@_jit
def _lengths(st, start, b, order, lens_i, lens_f, F, row0):  # pragma: no cover - compiled
    """Write a block's slider displacements and actuator lengths (rows ``row0`` on)."""
    nln = len(lens_i) // 4
    for q in range(nln):
        kind, f = lens_i[4 * q], 6 * q
        a, bb, G = lens_i[4 * q + 1], lens_i[4 * q + 2], lens_i[4 * q + 3]
        for j in range(b):
            Sp = _pt(st, a, lens_f[f], lens_f[f + 1], order, j)
            T = _pt(st, bb, lens_f[f + 2], lens_f[f + 3], order, j)
            if kind == 0:  # a slider or slot: displacement along the guide's line
                cx, cy = st[G, EX, j], st[G, EY, j]
                ux = lens_f[f + 4] * cx - lens_f[f + 5] * cy
                uy = lens_f[f + 4] * cy + lens_f[f + 5] * cx
                w1, w2, _ = _rates(st, G, order, j)
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
            i = start + j
            F[row0 + q, i] = d0
            if order >= 1:
                F[row0 + nln + q, i] = d1
                if order >= 2:
                    F[row0 + 2 * nln + q, i] = d2
                    if order >= 3:
                        F[row0 + 3 * nln + q, i] = d3


@_jit
def run(lo, hi, ii, ff, U, order, F, Pf, codes, follow):  # pragma: no cover - compiled
    """Samples ``lo`` to ``hi`` (a slice, for threads), then (``follow``) the sweep's angles.

    Returns how many status codes of those samples are not OK.

    ``ii`` and ``ff`` are the packed program and tables
    (:func:`machdyn.linkage.kernel.pack`); ``F`` receives the angles, their
    rates and the lengths, ``Pf`` the points (complex rows seen as real
    pairs), ``codes`` each group's status code.
    """
    ns, nl, nq, nln = ii[0], ii[1], ii[2], ii[4]
    pi = ii[NH : ii[5]]
    links, exact = ii[ii[5] : ii[6]], ii[ii[6] : ii[7]]
    pts_i, lens_i = ii[ii[7] : ii[8]], ii[ii[8] : ii[9]]
    pf, theta0 = ff[: ii[10]], ff[ii[10] : ii[11]]
    pts_f, lens_f = ff[ii[11] : ii[12]], ff[ii[12] : ii[13]]
    start_, scale = ff[ii[13] : ii[14]], ff[ii[14] : ii[15]]
    st = _new_state(nl)
    for start in range(lo, hi, BLOCK):
        b = min(BLOCK, hi - start)
        _steps(st, pi, pf, ns, U, start, b, order, codes)
        _angles(st, start, b, order, links, exact, theta0, F)
        _points(st, start, b, order, pts_i, pts_f, Pf)
        if nln:
            _lengths(st, start, b, order, lens_i, lens_f, F, nq * (order + 1))
    if follow:
        _follow(st, pi, pf, ns, U, links, exact, theta0, start_, scale, ff[ii[15]], F, ii[16])
    bad = 0  # samples a group flags (none, usually: the caller then skips the flags)
    for g in range(codes.shape[0]):
        for i in range(lo, hi):
            bad += codes[g, i] != 0
    return bad


@_inline
def _turn(prev, raw, k):  # pragma: no cover - compiled
    """``raw`` moved by whole turns to within π of ``prev``, and how many turns.

    ``k`` (the last sample's turns) is tried first: within 3 (< π, with room
    for rounding) of ``prev`` it is the rounded ``(prev − raw) / 2π`` and the
    result is the same number; the next angle then does not wait for this one.
    """
    t = raw + _TWO_PI * k
    if abs(prev - t) < 3.0:
        return t, k
    k = math.floor((prev - raw) / _TWO_PI + 0.5)
    return raw + _TWO_PI * k, k


@_inline
def _unwrap(ang_out, wrap, prev, turns, i0, i1):  # pragma: no cover - compiled
    """Unwrap samples ``i0`` … ``i1 − 1`` of each angle row (one row at a time)."""
    for w in range(len(wrap)):
        row = ang_out[wrap[w]]
        p, k = prev[w], turns[w]
        for i in range(i0, i1):
            raw = row[i]
            if math.isfinite(raw):
                p, k = _turn(p, raw, k)
                row[i] = p
        prev[w], turns[w] = p, k


@_jit
def _follow(st, pi, pf, ns, U, links, exact, theta0, start, scale, step, ang_out,
            ngroups):  # fmt: skip  # pragma: no cover - compiled
    """Unwrap the atan2 angles of a sweep along its path from the drawn pose (in place).

    The path runs from the drawn driver values ``start`` to the first sample and
    on through the samples; wherever two consecutive path points are further
    apart than ``step`` (each driver in units of its ``scale``) the program is
    run, positions only, at evenly spaced points in between. Every angle is
    moved by whole turns to within π of its last finite value on the path.
    """
    n = U.shape[1]
    nd = U.shape[0] // 4
    wrap = np.flatnonzero(exact == 0)
    nw = len(wrap)
    if nw == 0:
        return 0
    V = np.zeros((4 * nd, 1))
    c2 = np.zeros((ngroups, 1), np.int8)
    prev, turns = np.empty(nw), np.zeros(nw)
    for w in range(nw):
        prev[w] = theta0[wrap[w]]  # the drawn pose: Δ = 0
    cur = start.copy()
    i0 = 0  # the samples from i0 on are not unwrapped yet
    for i in range(n):
        span = 0.0
        for d in range(nd):
            span = max(span, abs(U[4 * d, i] - cur[d]) / scale[d])
        if span > step or (i == 0 and span > 1e-12):
            _unwrap(ang_out, wrap, prev, turns, i0, i)  # the samples before the gap
            i0 = i
            k = math.ceil(span / step)
            for m in range(1, k):
                f = m / k
                for d in range(nd):
                    V[4 * d, 0] = cur[d] + f * (U[4 * d, i] - cur[d])
                _steps(st, pi, pf, ns, V, 0, 1, 0, c2)
                for w in range(nw):
                    L = links[wrap[w]]
                    raw = _atan2(st[L, EY, 0], st[L, EX, 0]) + theta0[wrap[w]]
                    if math.isfinite(raw):
                        prev[w], turns[w] = _turn(prev[w], raw, turns[w])
        for d in range(nd):
            cur[d] = U[4 * d, i]
    _unwrap(ang_out, wrap, prev, turns, i0, n)
    return 0


def warm_up() -> None:
    """Compile (or load from numba's cache) the kernel."""
    from .linkage import Linkage
    from .linkage.kernel import run_compiled
    from .linkage.sweep import _info

    lk = Linkage({"O": 0, "A": 1j, "B": 3 + 1j, "Q": 4 + 0j})
    lk.ground("O", "Q").link("c", "O", "A").link("r", "A", "B").link("k", "Q", "B")
    lk.drive("c")
    model = lk._compile()
    info = _info(lk, model)
    U = np.zeros((4, 2))
    import sys

    module = sys.modules[__name__]
    # LLVM's options are process-wide: raised only while this kernel compiles (or
    # loads from numba's cache), so that other numba code keeps LLVM's default.
    llvmlite.binding.set_option("machdyn", f"-inline-threshold={INLINE_THRESHOLD}")
    try:
        for order in (0, 2, 3):
            run_compiled(module, model.program, info.tables, U, order, True)
    finally:
        llvmlite.binding.set_option("machdyn", f"-inline-threshold={DEFAULT_INLINE_THRESHOLD}")
