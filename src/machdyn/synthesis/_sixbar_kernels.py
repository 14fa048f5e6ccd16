"""Compiled (numba) kernels of six-bar path synthesis: points, Jacobian, refinement, ordering.

Imported only when :mod:`machdyn.jit` lets the compiled kernels serve (the
caller decides, as :func:`machdyn.synthesis._sixbar_refine.coupler_function`
does). The timed scan's coupler points (:func:`sixbar_points_into`; its
reference :func:`machdyn.synthesis.sixbar.sixbar_points`, NumPy, the engine's
``dyads.rrr``): one pass per linkage and crank angle, no temporaries, so the
scan of thousands of atlas entries at tens of starting angles costs
milliseconds instead of the NumPy path's seconds. The coupler point with its
derivatives (:func:`sixbar_coupler`; reference
:func:`machdyn.synthesis._sixbar_refine.sixbar_coupler`, NumPy forward mode), the
refinement's loop (:func:`refine_loop`; reference ``_sixbar_refine._loop``) and
the ordering of a placed curve's samples (:func:`ordered_samples`; reference
``_sixbar_starts._ordered_samples``).
"""

from __future__ import annotations

import math

import numpy as np

from .._numba_cache import njit

__all__ = [
    "ordered_samples",
    "ordered_samples_many",
    "refine_fit",
    "refine_loop",
    "sixbar_coupler",
    "sixbar_points_into",
]


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


# --------------------------------------------------------------------------------------
# six-bar coupler point and its derivatives (the six-bar refinement's Jacobian)

#: Partial derivatives carried: the 15 design numbers and the crank angle.
_NG = 16


@njit(cache=True, nogil=True, error_model="numpy")
def _sixbar_frame(G, slot_o, slot_x, wr, wi, iu, iv, out):  # pragma: no cover - compiled
    """``out = o + (u + jv)(x − o)`` with its gradient, (u, v) the design numbers iu, iv."""
    o_r, o_i = G[slot_o, 0, _NG], G[slot_o, 1, _NG]
    dr = G[slot_x, 0, _NG] - o_r
    di = G[slot_x, 1, _NG] - o_i
    G[out, 0, _NG] = o_r + wr * dr - wi * di
    G[out, 1, _NG] = o_i + wr * di + wi * dr
    for j in range(_NG):
        ddr = G[slot_x, 0, j] - G[slot_o, 0, j]
        ddi = G[slot_x, 1, j] - G[slot_o, 1, j]
        G[out, 0, j] = G[slot_o, 0, j] + wr * ddr - wi * ddi
        G[out, 1, j] = G[slot_o, 1, j] + wr * ddi + wi * ddr
    G[out, 0, iu] += dr
    G[out, 1, iu] += di
    G[out, 0, iv] -= di
    G[out, 1, iv] += dr


@njit(cache=True, nogil=True, error_model="numpy")
def _sixbar_dyad(G, sa, sc, a, ia, b, ib, sign, out):  # pragma: no cover - compiled
    """RRR pin ``out`` (|out − A| = a, |out − C| = b, the engine's dyads.rrr) and its gradient.

    The gradient solves the two circle equations differentiated (Cramer's
    rule). False where the circles do not meet.
    """
    ar, ai = G[sa, 0, _NG], G[sa, 1, _NG]
    acr = G[sc, 0, _NG] - ar
    aci = G[sc, 1, _NG] - ai
    d2 = acr * acr + aci * aci
    d = math.sqrt(d2)
    if not d > 0.0:
        return False
    x = (a * a - b * b + d2) / (2.0 * d)
    h2 = (a - x) * (a + x)
    if not h2 >= -1e-14 * a * a:
        return False
    h = sign * math.sqrt(max(h2, 0.0))
    ur, ui = acr / d, aci / d
    er = ar + x * ur - h * ui
    ei = ai + x * ui + h * ur
    G[out, 0, _NG], G[out, 1, _NG] = er, ei
    w1r, w1i = er - ar, ei - ai
    w2r, w2i = er - G[sc, 0, _NG], ei - G[sc, 1, _NG]
    det = w1r * w2i - w1i * w2r
    if det == 0.0:
        return False
    for j in range(_NG):
        q1 = w1r * G[sa, 0, j] + w1i * G[sa, 1, j] + (a if j == ia else 0.0)
        q2 = w2r * G[sc, 0, j] + w2i * G[sc, 1, j] + (b if j == ib else 0.0)
        G[out, 0, j] = (q1 * w2i - q2 * w1i) / det
        G[out, 1, j] = (w1r * q2 - w2r * q1) / det
    return True


@njit(cache=True, nogil=True, error_model="numpy")
def sixbar_coupler(x, theta, s4, s6, l1, l2, on6, P, J, Jt, ok):  # pragma: no cover - compiled
    """Coupler point of a placed six-bar at crank angles ``theta`` and its derivatives.

    ``x`` (15): ``O2x O2y θ1 r1 r2 r3 r4 cu cv du dv a b pu pv`` (see
    :mod:`machdyn.synthesis._sixbar_refine`); ``s4, s6`` the dyads' assembly signs,
    ``l1, l2`` the links (1–4) carrying C and D, ``on6`` 1 if the point is on link 6.
    Writes ``P`` (K,) complex, ``J`` (K, 15) complex, ``Jt`` (K,) complex, ``ok`` (K,).
    """
    _coupler_into(x, theta, s4, s6, l1, l2, on6, P, J, Jt, ok, np.empty((8, 2, _NG + 1)))


@njit(cache=True, nogil=True, error_model="numpy")
def _frame_slots(link):  # pragma: no cover - compiled
    """Slots of link 1–4's origin and x-point (O2→O4, O2→A, A→B, O4→B: ground to rocker)."""
    if link == 1:
        return 0, 1
    if link == 2:
        return 0, 2
    if link == 3:
        return 2, 3
    return 1, 3


@njit(cache=True, nogil=True, error_model="numpy")
def _coupler_into(x, theta, s4, s6, l1, l2, on6, P, J, Jt, ok, G):  # pragma: no cover - compiled
    """:func:`sixbar_coupler` with its work array ``G`` (8, 2, 17) given.

    ``G`` is zeroed once: every target writes the same entries of the ground
    pivots and the crank pin and the whole of every later slot it reads.
    """
    # slots: 0 O2, 1 O4, 2 A, 3 B, 4 C, 5 D, 6 E, 7 P; last index _NG holds the value
    G[:] = 0.0
    o1, x1 = _frame_slots(l1)
    o2, x2 = _frame_slots(l2)
    c1, s1 = math.cos(x[2]), math.sin(x[2])
    for k in range(theta.size):
        G[0, 0, _NG], G[0, 1, _NG] = x[0], x[1]
        G[0, 0, 0], G[0, 1, 1] = 1.0, 1.0
        # O4 = O2 + r1 e^{jθ1}
        G[1, 0, _NG] = x[0] + x[3] * c1
        G[1, 1, _NG] = x[1] + x[3] * s1
        G[1, 0, 0], G[1, 1, 1] = 1.0, 1.0
        G[1, 0, 2], G[1, 1, 2] = -x[3] * s1, x[3] * c1
        G[1, 0, 3], G[1, 1, 3] = c1, s1
        # A = O2 + r2 e^{j(θ1 + θ)}
        ca, sa = math.cos(x[2] + theta[k]), math.sin(x[2] + theta[k])
        G[2, 0, _NG] = x[0] + x[4] * ca
        G[2, 1, _NG] = x[1] + x[4] * sa
        G[2, 0, 0], G[2, 1, 1] = 1.0, 1.0
        G[2, 0, 2], G[2, 1, 2] = -x[4] * sa, x[4] * ca
        G[2, 0, 15], G[2, 1, 15] = -x[4] * sa, x[4] * ca
        G[2, 0, 4], G[2, 1, 4] = ca, sa
        good = _sixbar_dyad(G, 2, 1, x[5], 5, x[6], 6, s4, 3)
        if good:
            _sixbar_frame(G, o1, x1, x[7], x[8], 7, 8, 4)
            _sixbar_frame(G, o2, x2, x[9], x[10], 9, 10, 5)
            good = _sixbar_dyad(G, 4, 5, x[11], 11, x[12], 12, s6, 6)
        ok[k] = good
        if not good:
            P[k] = complex(np.nan, np.nan)
            for j in range(15):
                J[k, j] = complex(np.nan, np.nan)
            Jt[k] = complex(np.nan, np.nan)
            continue
        base = 5 if on6 else 4
        _sixbar_frame(G, base, 6, x[13], x[14], 13, 14, 7)
        P[k] = complex(G[7, 0, _NG], G[7, 1, _NG])
        for j in range(15):
            J[k, j] = complex(G[7, 0, j], G[7, 1, j])
        Jt[k] = complex(G[7, 0, 15], G[7, 1, 15])


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
    return _residuals_into(z, timing, timed, targets, scale, s4, s6, l1, l2, on6, steep, r, Jz,
                           _work(targets.size))  # fmt: skip


@njit(cache=True, nogil=True, error_model="numpy")
def _work(k):  # pragma: no cover - compiled
    """:func:`_residuals_into`'s work arrays for ``k`` targets: θ, P, J, Jt, ok, G."""
    return (
        np.empty(k),
        np.empty(k, np.complex128),
        np.empty((k, 15), np.complex128),
        np.empty(k, np.complex128),
        np.empty(k, np.bool_),
        np.empty((8, 2, _NG + 1)),
    )


@njit(cache=True, nogil=True, error_model="numpy")
def _residuals_into(z, timing, timed, targets, scale, s4, s6, l1, l2, on6, steep, r, Jz, work):
    # pragma: no cover - compiled
    """:func:`_residuals` with its work arrays given (:func:`_work`)."""
    k = targets.size
    theta, P, J, Jt, ok, G = work
    for i in range(k):
        theta[i] = z[15] + timing[i] if timed else z[15 + i]
    _coupler_into(z[:15], theta, s4, s6, l1, l2, on6, P, J, Jt, ok, G)
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
    """The pin of :func:`_sixbar_dyad` without its gradient: the same arithmetic.

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
    """``o + (u + jv)(x − o)``: :func:`_sixbar_frame`'s value, the same arithmetic."""
    dr = x_r - o_r
    di = x_i - o_i
    return o_r + wr * dr - wi * di, o_i + wr * di + wi * dr


@njit(cache=True, nogil=True, error_model="numpy")
def _probe(z, timing, timed, targets, scale, s4, s6, l1, l2, on6, r):  # pragma: no cover
    """:func:`_residuals`' residuals alone, without the Jacobian (the geodesic probe's).

    The coupler point by the same arithmetic as :func:`sixbar_coupler`
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
def _finite(v):  # pragma: no cover - compiled
    """Whether every entry of ``v`` is finite."""
    finite = True
    for i in range(v.size):
        finite = finite and math.isfinite(v[i])
    return finite


@njit(cache=True, nogil=True, error_model="numpy")
def refine_loop(z, timing, timed, targets, scale, s4, s6, l1, l2, on6, steep, floor, iterations):
    # pragma: no cover - compiled
    """:func:`machdyn.synthesis._sixbar_refine.refine_sixbar`'s damped Gauss–Newton loop, compiled.

    The same steps (Marquardt's scaling with the least damping ``floor`` of the
    largest diagonal, Transtrum's geodesic acceleration with ``h = 0.1``, λ ÷3 on
    success and ×4 on failure), on ``z`` in place.
    """
    m, n = 2 * targets.size, z.size
    r, J = np.empty(m), np.empty((m, n))
    r_new, J_new, r_h = np.empty(m), np.empty((m, n)), np.empty(m)
    M, piv, v, a = np.empty((n, n)), np.empty(n, np.int64), np.empty(n), np.empty(n)
    z_new, rhs, curvature = np.empty(n), np.empty(n), np.empty(m)
    A, g, Jv, Jc = np.empty((n, n)), np.empty(n), np.empty(m), np.empty(n)
    work = _work(targets.size)
    cost = _residuals_into(z, timing, timed, targets, scale, s4, s6, l1, l2, on6, steep, r, J,
                           work)  # fmt: skip
    lam = 1e-3
    h = 0.1
    for _ in range(iterations):
        np.dot(J.T, J, A)
        np.dot(J.T, r, g)
        top = 1e-300
        for i in range(n):
            top = max(top, A[i, i])
        M[:] = A
        for i in range(n):
            M[i, i] += lam * max(A[i, i], floor * top)
        finite = _lu(M, piv)  # one factorisation for the step and its correction
        if finite:
            for i in range(n):
                rhs[i] = -g[i]
            _lu_solve(M, piv, rhs, v)
            finite = _finite(v)
        else:
            v[:] = math.nan
        if finite:  # geodesic acceleration (see _sixbar_refine._geodesic)
            for i in range(n):
                z_new[i] = z[i] + h * v[i]
            _probe(z_new, timing, timed, targets, scale, s4, s6, l1, l2, on6, r_h)
            np.dot(J, v, Jv)
            for i in range(m):
                curvature[i] = 2.0 / h * ((r_h[i] - r[i]) / h - Jv[i])
            np.dot(J.T, curvature, Jc)
            for i in range(n):
                rhs[i] = -Jc[i]
            _lu_solve(M, piv, rhs, a)
            if np.linalg.norm(a) <= 0.75 * np.linalg.norm(v):
                for i in range(n):
                    v[i] = v[i] + 0.5 * a[i]
                finite = _finite(v)
        if not finite:
            lam *= 10.0
            continue
        for i in range(n):
            z_new[i] = z[i] + v[i]
        cost_new = _residuals_into(z_new, timing, timed, targets, scale, s4, s6, l1, l2, on6,
                                   steep, r_new, J_new, work)  # fmt: skip
        if cost_new < cost:
            big, top = 0.0, 0.0
            for i in range(n):
                big, top = max(big, abs(v[i])), max(top, abs(z[i]))
            small = big <= 1e-15 * (1.0 + top)
            z[:] = z_new
            r, r_new = r_new, r  # (the new residuals and Jacobian become the current ones)
            J, J_new = J_new, J
            cost = cost_new
            lam = max(lam / 3.0, 1e-15)
            if small or cost <= 1e-30:
                break
        else:
            lam *= 4.0
            if lam > 1e15:
                break
    return z


@njit(cache=True, nogil=True, error_model="numpy")
def refine_fit(z, timing, timed, targets, scale, s4, s6, l1, l2, on6, steep, floor, iterations):
    # pragma: no cover - compiled
    """:func:`refine_loop` on a copy of ``z``, then the fit as ``refine_sixbar`` returns it.

    Every length made positive (``_sixbar_refine._positive_lengths``' steps) and the
    coupler point at the fit's crank angles: ``(x (15,), θ (K,), P (K,), ok)``, ``ok``
    whether the six-bar is assembled at every target. One call instead of the loop's
    and the point's, each wrapped in NumPy (about 0.1 ms a fit).
    """
    z = refine_loop(z.copy(), timing, timed, targets, scale, s4, s6, l1, l2, on6, steep, floor,
                    iterations)  # fmt: skip
    k = targets.size
    x = z[:15].copy()
    theta = np.empty(k)
    for i in range(k):
        theta[i] = z[15] + timing[i] if timed else z[15 + i]
    for i in (5, 6, 11, 12):
        x[i] = abs(x[i])
    if x[3] < 0:
        x[3], x[2] = -x[3], x[2] + math.pi
        for i in range(k):
            theta[i] = theta[i] - math.pi
    if x[4] < 0:
        x[4] = -x[4]
        for i in range(k):
            theta[i] = theta[i] + math.pi
    P = np.empty(k, np.complex128)
    work = _work(k)
    _coupler_into(x, theta, s4, s6, l1, l2, on6, P, work[2], work[3], work[4], work[5])
    return x, theta, P, np.all(work[4])


@njit(cache=True, nogil=True, error_model="numpy")
def _ordered_total(c, start, way, back):  # pragma: no cover - compiled
    """The least sum of squared distances along one ordering of the samples, and its end.

    ``c`` (K, N): squared distance of target k to sample j; the samples are taken
    ``start, start + way, …`` (mod N). ``back`` (K − 1, N), written unless it has no
    rows: for target k at the j-th sample of the ordering, the sample (of the
    ordering) of target k − 1 — the first least ``total`` up to j, as
    :func:`machdyn.synthesis._sixbar_starts._ordered_samples`'s running minimum.
    """
    k_count, n = c.shape
    order = np.empty(n, np.int64)
    for j in range(n):
        order[j] = (start + way * j + n) % n
    total = np.empty(n)
    for j in range(n):
        total[j] = c[0, order[j]]
    keep = back.shape[0] > 0
    for k in range(1, k_count):
        run, arg = total[0], 0
        for j in range(n):
            if total[j] < run:
                run, arg = total[j], j
            if keep:
                back[k - 1, j] = arg
            total[j] = c[k, order[j]] + run
    end = 0
    for j in range(1, n):
        if total[j] < total[end]:
            end = j
    return total[end], end


@njit(cache=True, nogil=True, error_model="numpy")
def ordered_samples(c, rolls, out):  # pragma: no cover - compiled
    """:func:`machdyn.synthesis._sixbar_starts._ordered_samples`'s dynamic programme, compiled.

    ``c`` (K, N) finite: squared distances of the targets to the curve's samples;
    the sample indices of the least ordered sum go into ``out`` (K,). The same
    orderings (``rolls`` starting samples, forward then backward from each) and
    the same comparisons, so the same choices, ties included.
    """
    k_count, n = c.shape
    none = np.empty((0, n), np.int64)
    best, w_start, w_way = np.inf, 0, 1
    for start in range(0, n, n // rolls):
        for way in (1, -1):
            value, _ = _ordered_total(c, start, way, none)
            if value < best or (start == 0 and way == 1):
                best, w_start, w_way = value, start, way
    back = np.empty((k_count - 1, n), np.int64)
    _, j = _ordered_total(c, w_start, w_way, back)
    for k in range(k_count - 1, -1, -1):
        out[k] = (w_start + w_way * j + n) % n
        if k:
            j = back[k - 1, j]


@njit(cache=True, nogil=True, error_model="numpy")
def ordered_samples_many(c, rolls, out):  # pragma: no cover - compiled
    """:func:`ordered_samples` for each of many curves: ``c`` (E, K, N), ``out`` (E, K)."""
    for e in range(c.shape[0]):
        ordered_samples(c[e], rolls, out[e])
