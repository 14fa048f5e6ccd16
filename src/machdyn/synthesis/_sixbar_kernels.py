"""Compiled (numba) six-bar coupler points for the timed scan of six-bar path synthesis.

Imported only when :mod:`machdyn.jit` lets the compiled kernels serve (the
caller decides, as :func:`machdyn.synthesis.sixbar_path.coupler_function`
does); :func:`machdyn.synthesis.sixbar.sixbar_points` (NumPy, the engine's
``dyads.rrr``) is the reference it is tested against. One pass per linkage and
crank angle, no temporaries: the scan of thousands of atlas entries at tens of
starting angles costs milliseconds instead of the NumPy path's seconds.
"""

from __future__ import annotations

import math

import numpy as np
from .._numba_cache import njit

from ._atlas_kernels import sixbar_coupler

__all__ = ["refine_loop", "sixbar_points_into"]


@njit(cache=True, nogil=True, error_model="numpy")
def _rrr(ar, ai, cr, ci, a, b, sign):  # pragma: no cover - compiled
    """The engine's ``dyads.rrr`` for one pose: the pin and whether the circles meet."""
    acr, aci = cr - ar, ci - ai
    d2 = acr * acr + aci * aci
    d = math.sqrt(d2)
    if not d > 0.0:
        return math.nan, math.nan, False
    x = (a * a - b * b + d2) / (2.0 * d)
    h2 = (a - x) * (a + x)
    if not h2 >= -1e-14 * a * a:
        return math.nan, math.nan, False
    h = sign * math.sqrt(max(h2, 0.0))
    ur, ui = acr / d, aci / d
    return ar + x * ur - h * ui, ai + x * ui + h * ur, True


@njit(cache=True, nogil=True, error_model="numpy")
def _frame(link, o2r, o2i, o4r, o4i, a_r, a_i, br, bi):  # pragma: no cover - compiled
    """Origin and x-point of link 1–4 (ground O2→O4, crank O2→A, coupler A→B, rocker O4→B)."""
    if link == 1:
        return o2r, o2i, o4r, o4i
    if link == 2:
        return o2r, o2i, a_r, a_i
    if link == 3:
        return a_r, a_i, br, bi
    return o4r, o4i, br, bi


@njit(cache=True, nogil=True, error_model="numpy")
def sixbar_points_into(f, links, theta, P):  # pragma: no cover - compiled
    """Coupler points of six-bars at crank angles ``theta`` into ``P`` (N, M) complex.

    ``f`` (N, 14): r1 r3 r4 cu cv du dv a b pu pv s4 s6 on6 (1.0 when the
    point is on link 6); ``links`` (N, 2): the dyad's attachment links. Unit
    crank, ``O2`` at the origin, ground along +x (as ``sixbar_points``); NaN
    where a dyad cannot be assembled.
    """
    ct, st = np.empty(theta.shape[0]), np.empty(theta.shape[0])
    for m in range(theta.shape[0]):  # the crank pin's positions: the same for every linkage
        ct[m], st[m] = math.cos(theta[m]), math.sin(theta[m])
    for n in range(f.shape[0]):
        r1, r3, r4 = f[n, 0], f[n, 1], f[n, 2]
        cu, cv, du, dv = f[n, 3], f[n, 4], f[n, 5], f[n, 6]
        a, b, pu, pv = f[n, 7], f[n, 8], f[n, 9], f[n, 10]
        s4, s6, on6 = f[n, 11], f[n, 12], f[n, 13] > 0.5
        l1, l2 = links[n, 0], links[n, 1]
        for m in range(theta.shape[0]):
            a_r, a_i = ct[m], st[m]
            br, bi, ok = _rrr(a_r, a_i, r1, 0.0, r3, r4, s4)
            if not ok:
                P[n, m] = complex(math.nan, math.nan)
                continue
            o_r, o_i, x_r, x_i = _frame(l1, 0.0, 0.0, r1, 0.0, a_r, a_i, br, bi)
            c_r = o_r + cu * (x_r - o_r) - cv * (x_i - o_i)
            c_i = o_i + cu * (x_i - o_i) + cv * (x_r - o_r)
            o_r, o_i, x_r, x_i = _frame(l2, 0.0, 0.0, r1, 0.0, a_r, a_i, br, bi)
            d_r = o_r + du * (x_r - o_r) - dv * (x_i - o_i)
            d_i = o_i + du * (x_i - o_i) + dv * (x_r - o_r)
            er, ei, ok = _rrr(c_r, c_i, d_r, d_i, a, b, s6)
            if not ok:
                P[n, m] = complex(math.nan, math.nan)
                continue
            g_r, g_i = (d_r, d_i) if on6 else (c_r, c_i)
            P[n, m] = complex(g_r + pu * (er - g_r) - pv * (ei - g_i),
                              g_i + pu * (ei - g_i) + pv * (er - g_r))  # fmt: skip


def sixbar_points_compiled(meta: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """:func:`machdyn.synthesis.sixbar.sixbar_points`'s points (NaN where apart), compiled."""
    from .sixbar import TOPOLOGIES

    names = ("r1", "r3", "r4", "cu", "cv", "du", "dv", "a", "b", "pu", "pv", "s4", "s6")
    f = np.empty((meta.size, 14))
    for j, k in enumerate(names):
        f[:, j] = meta[k]
    f[:, 13] = meta["on"] == 6
    links = np.array([t[0] for t in TOPOLOGIES], np.int64)[meta["topology"].astype(np.int64)]
    P = np.empty((meta.size, np.size(theta)), complex)
    sixbar_points_into(f, np.ascontiguousarray(links), np.ascontiguousarray(theta, float), P)
    return P


@njit(cache=True, nogil=True, error_model="numpy")
def _lu(M, piv):  # pragma: no cover - compiled
    """``M`` in place into its LU factors (partial pivoting); False where it is singular.

    Whole rows are swapped (as LAPACK's ``getrf``), the multipliers kept below the
    diagonal, the pivot rows in ``piv``: :func:`_lu_solve` then takes the same
    floating-point steps as eliminating on ``M`` and the right-hand side together,
    so one factorisation serves the step and its geodesic correction.
    """
    n = M.shape[0]
    for c in range(n):
        p, big = c, abs(M[c, c])
        for i in range(c + 1, n):
            if abs(M[i, c]) > big:
                p, big = i, abs(M[i, c])
        piv[c] = p
        if not big > 0.0:
            return False
        if p != c:
            for j in range(n):
                M[c, j], M[p, j] = M[p, j], M[c, j]
        for i in range(c + 1, n):
            f = M[i, c] / M[c, c]
            M[i, c] = f
            if f != 0.0:
                for j in range(c + 1, n):
                    M[i, j] -= f * M[c, j]
    return True


@njit(cache=True, nogil=True, error_model="numpy")
def _lu_solve(LU, piv, g, x):  # pragma: no cover - compiled
    """``x = M⁻¹ g`` from :func:`_lu`'s factors (rows swapped first, then the two triangles)."""
    n = g.size
    for i in range(n):
        x[i] = g[i]
    for c in range(n):
        p = piv[c]
        if p != c:
            x[c], x[p] = x[p], x[c]
    for c in range(n):
        for i in range(c + 1, n):
            f = LU[i, c]
            if f != 0.0:
                x[i] -= f * x[c]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for j in range(i + 1, n):
            s -= LU[i, j] * x[j]
        x[i] = s / LU[i, i]


@njit(cache=True, nogil=True, error_model="numpy")
def _below(w, bound):  # pragma: no cover - compiled
    """``abs(w) < bound`` for a complex ``w``, mostly without its square root.

    Both parts below half the bound put ``|w|`` below 0.71 of it; otherwise
    ``abs(w)`` decides (so NaN and infinities as before).
    """
    half = 0.5 * bound
    if abs(w.real) < half and abs(w.imag) < half:
        return True
    return abs(w) < bound


@njit(cache=True, nogil=True, error_model="numpy")
def _residuals(z, timing, timed, targets, scale, s4, s6, l1, l2, on6, steep, r, Jz):
    # pragma: no cover - compiled
    """The six-bar refinement's residuals ``r`` (2K) and Jacobian ``Jz`` (2K, nz); the cost."""
    k = targets.size
    theta = np.empty(k)
    for i in range(k):
        theta[i] = z[15] + timing[i] if timed else z[15 + i]
    P = np.empty(k, np.complex128)
    J = np.empty((k, 15), np.complex128)
    Jt = np.empty(k, np.complex128)
    ok = np.empty(k, np.bool_)
    sixbar_coupler(z[:15], theta, s4, s6, l1, l2, on6, P, J, Jt, ok)
    Jz[:] = 0.0
    cost = 0.0
    bound = steep * scale
    for i in range(k):
        good = ok[i] and _below(Jt[i], bound)
        for j in range(15):
            good = good and _below(J[i, j], bound)
        if good:  # a dyad at its toggle (derivatives without bound) counts as apart
            d = (P[i] - targets[i]) / scale
            r[i], r[k + i] = d.real, d.imag
            for j in range(15):
                Jz[i, j], Jz[k + i, j] = J[i, j].real / scale, J[i, j].imag / scale
            c = 15 if timed else 15 + i
            Jz[i, c], Jz[k + i, c] = Jt[i].real / scale, Jt[i].imag / scale
        else:  # a constant residual where apart
            r[i], r[k + i] = 10.0, 0.0
        cost += r[i] * r[i] + r[k + i] * r[k + i]
    return cost


@njit(cache=True, nogil=True, error_model="numpy")
def _dyad_point(ar, ai, cr, ci, a, b, sign):  # pragma: no cover - compiled
    """The pin of ``_atlas_kernels._sixbar_dyad`` without its gradient: the same arithmetic.

    ``(x, y, ok)``; not ok where the circles do not meet or the pin lies on the
    line of centres' ends (the gradient's ``det`` is zero), as there.
    """
    acr = cr - ar
    aci = ci - ai
    d2 = acr * acr + aci * aci
    d = math.sqrt(d2)
    if not d > 0.0:
        return 0.0, 0.0, False
    x = (a * a - b * b + d2) / (2.0 * d)
    h2 = (a - x) * (a + x)
    if not h2 >= -1e-14 * a * a:
        return 0.0, 0.0, False
    h = sign * math.sqrt(max(h2, 0.0))
    ur, ui = acr / d, aci / d
    er = ar + x * ur - h * ui
    ei = ai + x * ui + h * ur
    w1r, w1i = er - ar, ei - ai
    w2r, w2i = er - cr, ei - ci
    if w1r * w2i - w1i * w2r == 0.0:
        return er, ei, False
    return er, ei, True


@njit(cache=True, nogil=True, error_model="numpy")
def _in_frame(o_r, o_i, x_r, x_i, wr, wi):  # pragma: no cover - compiled
    """``o + (u + jv)(x − o)``: ``_atlas_kernels._sixbar_frame``'s value, the same arithmetic."""
    dr = x_r - o_r
    di = x_i - o_i
    return o_r + wr * dr - wi * di, o_i + wr * di + wi * dr


@njit(cache=True, nogil=True, error_model="numpy")
def _probe(z, timing, timed, targets, scale, s4, s6, l1, l2, on6, r):  # pragma: no cover
    """:func:`_residuals`' residuals alone, without the Jacobian (the geodesic probe's).

    The coupler point by the same arithmetic as ``_atlas_kernels.sixbar_coupler``
    computes its value, so ``r`` is the same to the bit, except at a pose where a
    derivative exceeds ``steep`` (a dyad at its toggle): ``_residuals`` counts it as
    apart, this probe does not look.
    """
    k = targets.size
    c1, s1 = math.cos(z[2]), math.sin(z[2])
    o2r, o2i = z[0], z[1]
    o4r, o4i = z[0] + z[3] * c1, z[1] + z[3] * s1
    for i in range(k):
        th = z[15] + timing[i] if timed else z[15 + i]
        ca, sa = math.cos(z[2] + th), math.sin(z[2] + th)
        a_r, a_i = z[0] + z[4] * ca, z[1] + z[4] * sa
        br, bi, good = _dyad_point(a_r, a_i, o4r, o4i, z[5], z[6], s4)
        cr = ci = dr = di = er = ei = 0.0
        if good:
            o_r, o_i, x_r, x_i = _frame(l1, o2r, o2i, o4r, o4i, a_r, a_i, br, bi)
            cr, ci = _in_frame(o_r, o_i, x_r, x_i, z[7], z[8])
            o_r, o_i, x_r, x_i = _frame(l2, o2r, o2i, o4r, o4i, a_r, a_i, br, bi)
            dr, di = _in_frame(o_r, o_i, x_r, x_i, z[9], z[10])
            er, ei, good = _dyad_point(cr, ci, dr, di, z[11], z[12], s6)
        if good:
            gr, gi = (dr, di) if on6 else (cr, ci)
            pr, pi = _in_frame(gr, gi, er, ei, z[13], z[14])
            d = (complex(pr, pi) - targets[i]) / scale
            r[i], r[k + i] = d.real, d.imag
        else:  # a constant residual where apart
            r[i], r[k + i] = 10.0, 0.0


@njit(cache=True, nogil=True, error_model="numpy")
def refine_loop(z, timing, timed, targets, scale, s4, s6, l1, l2, on6, steep, floor, iterations):
    # pragma: no cover - compiled
    """:func:`machdyn.synthesis.sixbar_path.refine_sixbar`'s damped Gauss–Newton loop, compiled.

    The same steps (Marquardt's scaling with the least damping ``floor`` of the
    largest diagonal, Transtrum's geodesic acceleration with ``h = 0.1``, λ ÷3 on
    success and ×4 on failure), on ``z`` in place.
    """
    m, n = 2 * targets.size, z.size
    r, J = np.empty(m), np.empty((m, n))
    r_new, J_new, r_h = np.empty(m), np.empty((m, n)), np.empty(m)
    M, piv, v, a = np.empty((n, n)), np.empty(n, np.int64), np.empty(n), np.empty(n)
    cost = _residuals(z, timing, timed, targets, scale, s4, s6, l1, l2, on6, steep, r, J)
    lam = 1e-3
    h = 0.1
    for _ in range(iterations):
        A = J.T @ J
        g = J.T @ r
        top = 1e-300
        for i in range(n):
            top = max(top, A[i, i])
        M[:] = A
        for i in range(n):
            M[i, i] += lam * max(A[i, i], floor * top)
        if _lu(M, piv):  # one factorisation for the step and its correction
            _lu_solve(M, piv, -g, v)
        else:
            v[:] = math.nan
        if np.all(np.isfinite(v)):  # geodesic acceleration (see sixbar_path._geodesic)
            _probe(z + h * v, timing, timed, targets, scale, s4, s6, l1, l2, on6, r_h)
            curvature = 2.0 / h * ((r_h - r) / h - J @ v)
            _lu_solve(M, piv, -(J.T @ curvature), a)
            if np.linalg.norm(a) <= 0.75 * np.linalg.norm(v):
                v[:] = v + 0.5 * a
        if not np.all(np.isfinite(v)):
            lam *= 10.0
            continue
        z_new = z + v
        cost_new = _residuals(z_new, timing, timed, targets, scale, s4, s6, l1, l2, on6, steep,
                              r_new, J_new)  # fmt: skip
        if cost_new < cost:
            small = np.max(np.abs(v)) <= 1e-15 * (1.0 + np.max(np.abs(z)))
            z[:] = z_new
            r[:], J[:] = r_new, J_new
            cost = cost_new
            lam = max(lam / 3.0, 1e-15)
            if small or cost <= 1e-30:
                break
        else:
            lam *= 4.0
            if lam > 1e15:
                break
    return z
