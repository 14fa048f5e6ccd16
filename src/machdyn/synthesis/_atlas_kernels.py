"""Compiled (numba) kernels of the atlas: its build, its query, the timed scan, the refinement.

Imported only when :mod:`machdyn.jit` lets the compiled kernels serve (it is
loaded with them). The build's circuit curves resampled by arc length
(:func:`even_circuit_curves`; its NumPy reference is
:func:`machdyn.synthesis.circuits.circuit_points` followed by
:func:`machdyn.synthesis.descriptor.resample_closed`): one pass per linkage, no
temporaries, the circuit's points go to a small buffer, then straight to their
evenly spaced samples. The query's compact first stage (:func:`compact_rows`,
:func:`key_ranges`, :func:`bound_topk`; used by
:func:`machdyn.synthesis._atlas_index.bounded_topk`, tested against bounds and
top-k lists written out in NumPy).
"""

from __future__ import annotations

import math

import numpy as np

from .._kernels import OK, _unit_vectors, sincos
from .._numba_cache import njit

__all__ = [
    "bound_topk",
    "compact_rows",
    "coupler_jacobian",
    "even_circuit_curves",
    "lm_refine",
    "timed_scores",
]


@njit(cache=True, nogil=True, error_model="numpy")
def even_circuit_curves(params, m, out):  # pragma: no cover - compiled
    """Circuit curves of linkages resampled at ``out.shape[1]`` points evenly spaced by arc length.

    ``params`` (N, 10): r1 r2 r3 r4, p cos δ, p sin δ, circuit centre, half
    width, crank flag (1/0), circuit sign; ``m`` circuit samples; ``out`` (N, M)
    complex.
    """
    n_out = out.shape[1]
    xs = np.empty(m + 1)
    ys = np.empty(m + 1)
    cum = np.empty(m + 1)
    two_pi = 2.0 * math.pi
    for k in range(params.shape[0]):
        r1, r2, r3, r4 = params[k, 0], params[k, 1], params[k, 2], params[k, 3]
        pr, pi = params[k, 4], params[k, 5]
        centre, half, crank, sign = params[k, 6], params[k, 7], params[k, 8], params[k, 9]
        scale = max(max(r1, r2), max(r3, r4))
        s1, s2, s3, s4 = r1 / scale, r2 / scale, r3 / scale, r4 / scale
        for i in range(m):
            u = two_pi * i / m
            if crank > 0.5:
                theta2 = u
                branch = sign
            else:
                su, cu = sincos(u)
                theta2 = centre + half * cu
                branch = 1.0 if su >= 0.0 else -1.0
            s, c = sincos(theta2)
            e3x, e3y, _, _, _ = _unit_vectors(s1, s2, s3, s4, c, s, branch, 1.0)
            xs[i] = r2 * c + pr * e3x - pi * e3y
            ys[i] = r2 * s + pr * e3y + pi * e3x
        xs[m] = xs[0]
        ys[m] = ys[0]
        cum[0] = 0.0
        for i in range(m):
            cum[i + 1] = cum[i] + math.hypot(xs[i + 1] - xs[i], ys[i + 1] - ys[i])
        total = cum[m]
        j = 0
        for q in range(n_out):
            target = total * q / n_out
            while j < m - 1 and cum[j + 1] <= target:
                j += 1
            width = cum[j + 1] - cum[j]
            t = (target - cum[j]) / width if width > 0.0 else 0.0
            t = min(max(t, 0.0), 1.0)
            out[k, q] = complex(xs[j] + t * (xs[j + 1] - xs[j]), ys[j] + t * (ys[j + 1] - ys[j]))


@njit(cache=True, nogil=True, error_model="numpy")
def coupler_jacobian(x, theta, branch, G, J, Jt, excess):  # pragma: no cover - compiled
    """Placed coupler point of a four-bar and its derivatives, one target at a time.

    The compiled twin of :func:`machdyn.synthesis.refine.coupler_and_jacobian`
    (the same arithmetic, tested against it): ``x`` (9) the design, ``theta``
    and ``branch`` (K,); writes ``G`` (K,), ``J`` (K, 9), ``Jt`` (K,) complex and
    ``excess`` (K,) (``|cos γ| − 1``, positive where the linkage does not close).
    """
    r1, r2, r3, r4, p, delta, ox, oy, theta1 = x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8]
    ed = complex(math.cos(delta), math.sin(delta))
    rot = complex(math.cos(theta1), math.sin(theta1))
    for k in range(theta.size):
        e2 = complex(math.cos(theta[k]), math.sin(theta[k]))
        a = r2 * e2
        s = a - r1
        dd = s.real * s.real + s.imag * s.imag
        d = math.sqrt(dd)
        cg = (r4 * r4 - r3 * r3 + dd) / (2.0 * r4 * d)
        excess[k] = abs(cg) - 1.0
        cg = min(max(cg, -1.0), 1.0)
        sg = math.sqrt(1.0 - cg * cg) * branch[k]
        e4 = (s / d) * complex(cg, -sg)
        e3 = (r1 + r4 * e4 - a) / r3
        P = a + p * ed * e3
        G[k] = complex(ox, oy) + rot * P
        sin34 = (e3 * e4.conjugate()).imag
        den = r3 * (sin34 if abs(sin34) > 1e-12 else 1e-12)
        ce4 = e4.conjugate()
        tail = 1j * p * ed * e3
        ja = 1j * a
        J[k, 0] = rot * tail * ((-ce4).real / den)
        J[k, 1] = rot * (e2 + tail * ((e2 * ce4).real / den))
        J[k, 2] = rot * tail * ((e3 * ce4).real / den)
        J[k, 3] = rot * tail * ((-e4 * ce4).real / den)
        J[k, 4] = rot * ed * e3
        J[k, 5] = rot * tail
        J[k, 6] = 1.0
        J[k, 7] = 1j
        J[k, 8] = 1j * rot * P
        Jt[k] = rot * (ja + tail * ((ja * ce4).real / den))


#: Entries whose coupler points :func:`timed_scores` holds at once (their points at every
#: angle of the table, by angle: the fits then run along the entries, in SIMD lanes).
TIMED_LANES = 32


@njit(cache=True, nogil=True, error_model="numpy")
def timed_scores(lengths, offsets, cos2, sin2, close_tol, ip, im, a, centred, theta1, score, best,
                 h, qm):  # fmt: skip  # pragma: no cover - compiled
    """Best starting angle of each entry for timed targets, both mirror images, fused.

    The compiled twin of :func:`machdyn.synthesis.atlas.coupler_points` followed by
    :func:`machdyn.synthesis._atlas_retrieve._timed_scores_numpy` (tested against a fit
    written out with scipy): ``lengths`` (R, 4) and ``offsets`` (R, 3) as
    :func:`machdyn._kernels.coupler_points` takes them, ``cos2``/``sin2`` (M,) the
    table's angles; ``ip``/``im`` (G, K): the table index of ``θ0_g + Δ_k`` and of
    its negative (the mirror image's point is the conjugate of the point at the
    negative angle); ``a`` (K,) complex: the targets (centred, or less the held
    pivot); ``centred``: fit an offset too; ``theta1``: the held ground direction
    (NaN: free). Writes, for mirror ``m`` (0: as stored, 1: mirrored) and entry
    ``r``: ``score[m, r]`` (the share of the targets' spread explained, −1 where a
    pose does not assemble), ``best[m, r]`` (index g of the best θ0, the first of
    equal ones), ``h[m, r]`` (rotation and scale) and ``qm[m, r]`` (mean of the
    fitted points).

    :data:`TIMED_LANES` entries at a time: their points at every angle (by angle),
    then every fit with the entries innermost; each entry's sums run in the order
    of the targets, as one entry at a time would.
    """
    n_r, n_m = lengths.shape[0], cos2.size
    n_g, n_k = ip.shape
    lanes = TIMED_LANES
    aa = 0.0
    for k in range(n_k):
        aa += a[k].real * a[k].real + a[k].imag * a[k].imag
    aa = max(aa, 1e-300)
    held = not math.isnan(theta1)
    ct, st = (math.cos(theta1), math.sin(theta1)) if held else (1.0, 0.0)
    xr, xi = np.empty((n_m, lanes)), np.empty((n_m, lanes))
    s1, s2, s3, s4 = np.empty(lanes), np.empty(lanes), np.empty(lanes), np.empty(lanes)
    r2, pr, pi, sign = np.empty(lanes), np.empty(lanes), np.empty(lanes), np.empty(lanes)
    mr, mi, cr, ci, v = (np.empty(lanes), np.empty(lanes), np.empty(lanes), np.empty(lanes),
                         np.empty(lanes))  # fmt: skip
    top, top_hr, top_hi, top_mr, top_mi = (np.empty(lanes), np.empty(lanes), np.empty(lanes),
                                           np.empty(lanes), np.empty(lanes))  # fmt: skip
    top_g = np.empty(lanes, np.int64)
    for lo in range(0, n_r, lanes):
        w = min(lanes, n_r - lo)
        for j in range(w):
            q1, q2, q3, q4 = (lengths[lo + j, 0], lengths[lo + j, 1], lengths[lo + j, 2],
                              lengths[lo + j, 3])  # fmt: skip
            scale = max(max(q1, q2), max(q3, q4))
            s1[j], s2[j], s3[j], s4[j] = q1 / scale, q2 / scale, q3 / scale, q4 / scale
            r2[j] = q2
            pr[j], pi[j], sign[j] = offsets[lo + j, 0], offsets[lo + j, 1], offsets[lo + j, 2]
        for i in range(n_m):  # the points (as _kernels.coupler_points), entries innermost
            c, s = cos2[i], sin2[i]
            for j in range(w):
                e3x, e3y, _, _, status = _unit_vectors(s1[j], s2[j], s3[j], s4[j], c, s, sign[j],
                                                       close_tol)  # fmt: skip
                blank = 0.0 if status == OK else np.nan
                xr[i, j] = r2[j] * c + pr[j] * e3x - pi[j] * e3y + blank
                xi[i, j] = r2[j] * s + pr[j] * e3y + pi[j] * e3x + blank
        for m in range(2):
            table = ip if m == 0 else im
            sgn = 1.0 if m == 0 else -1.0
            for j in range(w):
                top[j], top_g[j] = -np.inf, 0
                top_hr[j], top_hi[j], top_mr[j], top_mi[j] = 0.0, 0.0, 0.0, 0.0
            for g in range(n_g):
                for j in range(w):
                    mr[j], mi[j] = 0.0, 0.0
                if centred:
                    for k in range(n_k):
                        t = table[g, k]
                        for j in range(w):
                            mr[j] += xr[t, j]
                            mi[j] += sgn * xi[t, j]
                    for j in range(w):
                        mr[j] /= n_k
                        mi[j] /= n_k
                for j in range(w):
                    cr[j], ci[j], v[j] = 0.0, 0.0, 0.0
                for k in range(n_k):
                    t = table[g, k]
                    ar, ai = a[k].real, a[k].imag
                    for j in range(w):
                        qr, qi = xr[t, j] - mr[j], sgn * xi[t, j] - mi[j]
                        cr[j] += qr * ar + qi * ai  # conj(q) a
                        ci[j] += qr * ai - qi * ar
                        v[j] += qr * qr + qi * qi
                for j in range(w):
                    vv = v[j] if v[j] > 0.0 else np.inf
                    if held:
                        along = max(cr[j] * ct + ci[j] * st, 0.0)
                        gain = along * along / vv
                        hr, hi = along / vv * ct, along / vv * st
                    else:
                        gain = (cr[j] * cr[j] + ci[j] * ci[j]) / vv
                        hr, hi = cr[j] / vv, ci[j] / vv
                    sc = gain / aa
                    sc = -1.0 if sc != sc else sc  # an unassembled pose fits nothing
                    if sc > top[j]:
                        top[j], top_g[j], top_hr[j], top_hi[j] = sc, g, hr, hi
                        top_mr[j], top_mi[j] = mr[j], mi[j]
            for j in range(w):
                score[m, lo + j] = top[j]
                best[m, lo + j] = top_g[j]
                h[m, lo + j] = complex(top_hr[j], top_hi[j])
                qm[m, lo + j] = complex(top_mr[j], top_mi[j])


# --------------------------------------------------------------------------------------
# the refinement's bounded Levenberg–Marquardt loop (refine(solver="lm")), whole


@njit(cache=True, nogil=True, error_model="numpy")
def _violations(r1, r2, r3, r4, cos_mu, scale, out):  # pragma: no cover - compiled
    """:func:`machdyn.synthesis.refine._violations` into ``out`` (4,)."""
    out[0] = max(0.0, abs(r3 - r4) - abs(r1 - r2)) / scale
    out[1] = max(0.0, r1 + r2 - r3 - r4) / scale
    for i in range(2):
        dgl = abs(r1 - r2) if i == 0 else r1 + r2
        c = (r3 * r3 + r4 * r4 - dgl * dgl) / (2.0 * r3 * r4)
        out[2 + i] = max(0.0, abs(c) - cos_mu)


@njit(cache=True, nogil=True, error_model="numpy")
def _lm_problem(z, targets, branch, timing, timed, crank, cos_mu, scale, weight, tie, tie_c, r,
                Jm, want_jac):  # fmt: skip  # pragma: no cover - compiled
    """Residuals ``r`` and (``want_jac``) Jacobian ``Jm`` of refine's problem at ``z``.

    The compiled twin of :func:`machdyn.synthesis.refine._problem` (same rows
    and columns). ``tie`` ≥ 0: the length ``z[tie]`` is set to ``tie_c · z[:4]``
    first (in place) and its column folded into the others (see refine's
    ``tie``). Returns the points ``G`` (K,) complex.
    """
    if tie >= 0:
        z[tie] = tie_c[0] * z[0] + tie_c[1] * z[1] + tie_c[2] * z[2] + tie_c[3] * z[3]
    k = targets.size
    theta = np.empty(k)
    for i in range(k):
        theta[i] = z[9] + timing[i] if timed else z[9 + i]
    G = np.empty(k, np.complex128)
    J = np.empty((k, 9), np.complex128)
    jt = np.empty(k, np.complex128)
    excess = np.empty(k)
    coupler_jacobian(z[:9], theta, branch, G, J, jt, excess)
    for i in range(k):
        d = (G[i] - targets[i]) / scale
        r[i] = d.real
        r[k + i] = d.imag
        r[2 * k + i] = weight * max(excess[i], 0.0)
    con = np.empty(4)
    if crank:
        _violations(z[0], z[1], z[2], z[3], cos_mu, scale, con)
        for i in range(4):
            r[3 * k + i] = weight * con[i]
    if not want_jac:
        return G
    Jm[:] = 0.0
    for i in range(k):
        for j in range(9):
            Jm[i, j] = J[i, j].real / scale
            Jm[k + i, j] = J[i, j].imag / scale
        col = 9 if timed else 9 + i
        Jm[i, col] = jt[i].real / scale
        Jm[k + i, col] = jt[i].imag / scale
    if crank:  # central differences, as refine._constraint_slopes
        h = 1e-7 * scale
        up, down, hi, lo = np.empty(4), np.empty(4), np.empty(4), np.empty(4)
        for j in range(4):
            for i in range(4):
                up[i] = z[i]
                down[i] = z[i]
            up[j] += h
            down[j] -= h
            _violations(up[0], up[1], up[2], up[3], cos_mu, scale, hi)
            _violations(down[0], down[1], down[2], down[3], cos_mu, scale, lo)
            for i in range(4):
                Jm[3 * k + i, j] = weight * ((hi[i] - lo[i]) / (2 * h))
    if tie >= 0:
        for j in range(4):
            if j != tie:
                for i in range(Jm.shape[0]):
                    Jm[i, j] += tie_c[j] * Jm[i, tie]
    return G


@njit(cache=True, nogil=True, error_model="numpy")
def lm_refine(z, free, lo, hi, max_nfev, tol, targets, branch, timing, timed, crank, cos_mu,
              scale, weight, tie, tie_c, G):  # fmt: skip  # pragma: no cover - compiled
    """:func:`machdyn.synthesis.refine._levenberg_marquardt` on refine's problem, compiled.

    The same steps as the NumPy loop (tested against it), in place on ``z``;
    writes the points at the final ``z`` to ``G`` (K,) and returns the status.
    """
    k = targets.size
    n = z.size
    rows = 3 * k + (4 if crank else 0)
    r = np.empty(rows)
    J = np.empty((rows, n))
    r_new = np.empty(rows)
    J_new = np.empty((rows, n))
    G[:] = _lm_problem(z, targets, branch, timing, timed, crank, cos_mu, scale, weight, tie, tie_c,
                       r, J, True)  # fmt: skip
    cost = 0.5 * np.dot(r, r)
    if not np.isfinite(cost):
        return 0
    D2 = np.zeros(n)
    g = np.empty(n)
    A = np.empty((n, n))
    M = np.empty((n, n))
    rhs = np.empty(n)
    act = np.empty(n, np.bool_)
    trial = np.empty(n)
    lam, nu, nfev = 1e-3, 2.0, 1
    while nfev < max_nfev:
        g[:] = J.T @ r
        A[:] = J.T @ J
        top = 0.0
        for i in range(n):
            D2[i] = max(D2[i], A[i, i])
            top = max(top, D2[i])
        gmax = 0.0
        for i in range(n):
            out = (z[i] <= lo[i] and g[i] > 0) or (z[i] >= hi[i] and g[i] < 0)
            act[i] = free[i] and not out
            if act[i]:
                if math.isnan(g[i]):
                    return 1  # (NumPy's max of the active gradient is NaN then)
                gmax = max(gmax, abs(g[i]))
        if not gmax > 0.0:
            return 1
        floor = 1e-24 * max(top, 1e-300)
        finite = True
        for i in range(n):
            for j in range(n):
                M[i, j] = A[i, j] if act[i] and act[j] else 0.0
            M[i, i] = A[i, i] + lam * max(D2[i], floor) if act[i] else 1.0
            rhs[i] = -g[i] if act[i] else 0.0
            for j in range(n):
                finite = finite and np.isfinite(M[i, j])
        if not finite:  # NumPy's solve gives NaN: a refused trial
            nfev += 1
            lam *= nu
            nu *= 2.0
            if lam > 1e20:
                return 3
            continue
        try:
            step = np.linalg.solve(M, rhs)
        except Exception:  # singular (NumPy's LinAlgError)
            return 0
        for i in range(n):
            trial[i] = min(max(z[i] + step[i], lo[i]), hi[i]) if free[i] else z[i]
        p = trial - z
        pred = -(np.dot(g, p) + 0.5 * np.dot(np.dot(p, A), p))
        Gt = _lm_problem(trial, targets, branch, timing, timed, crank, cos_mu, scale, weight, tie,
                         tie_c, r_new, J_new, True)  # fmt: skip
        nfev += 1
        cost_new = 0.5 * np.dot(r_new, r_new)
        actual = cost - cost_new if np.isfinite(cost_new) else -np.inf
        if pred > 0 and actual > 1e-4 * pred:
            z[:] = trial
            r[:] = r_new
            J[:] = J_new
            G[:] = Gt
            old, cost = cost, cost_new
            lam *= max(1.0 / 3.0, 1.0 - (2.0 * actual / pred - 1.0) ** 3)
            nu = 2.0
            if actual <= tol * old:
                return 2
            if math.sqrt(np.dot(p, p)) <= tol * (tol + math.sqrt(np.dot(z, z))):
                return 3
        else:
            lam *= nu
            nu *= 2.0
            if lam > 1e20:
                return 3
    return 0


@njit(cache=True, nogil=True, error_model="numpy")
def compact_rows(desc, rows, cols, groups, head, tail):  # pragma: no cover - compiled
    """The query's compact first-stage table of one chunk's ``rows``; returns its scales.

    ``head`` (m, N) int16 holds ``round(desc[rows[i], cols[j]] · hs)``; ``tail``
    (G, N) uint16 the norm of the row's columns of each group (``groups[j]``:
    column ``j``'s group, −1 for a head column), summed in float64, times
    ``ts[g]`` rounded *up*, so that ``tail / ts`` is never below the norm. The
    scales map the chunk's largest head magnitude to 32767 and each group's
    largest norm to 65535 (less a margin): a head value is then within
    ``0.5 / hs`` of the descriptor's. Returns ``hs``, ``ts`` (G,) and the largest
    squared norm of a row (float64, rounded up by a relative 1e-12).
    """
    m, n = head.shape
    G = tail.shape[0]
    w = desc.shape[1]
    norm = np.empty((G, n))
    value = np.empty((m, n))
    sums = np.empty(G)
    big, longest2 = 0.0, 0.0
    for i in range(n):  # one read of each row: its head, its groups' norms
        r = rows[i]
        sums[:] = 0.0
        total = 0.0
        for j in range(w):
            x = np.float64(desc[r, j])
            total += x * x
            g = groups[j]
            if g >= 0:
                sums[g] += x * x
        longest2 = max(longest2, total)
        for g in range(G):
            norm[g, i] = math.sqrt(sums[g])
        for j in range(m):
            x = np.float64(desc[r, cols[j]])
            value[j, i] = x
            big = max(big, abs(x))
    hs = 32767.0 / big if big > 0.0 else 1.0
    for j in range(m):
        for i in range(n):
            head[j, i] = np.int16(round(value[j, i] * hs))
    ts = np.empty(G)
    for g in range(G):
        longest = 0.0
        for i in range(n):
            longest = max(longest, norm[g, i])
        ts[g] = 65535.0 / (longest * (1.0 + 1e-9)) if longest > 0.0 else 1.0
        for i in range(n):
            u = min(math.ceil(norm[g, i] * ts[g]), 65535.0)
            while u < 65535.0 and u / ts[g] < norm[g, i]:
                u += 1.0
            tail[g, i] = np.uint16(u)
    return hs, ts, longest2 * (1.0 + 1e-12)


@njit(cache=True, nogil=True, error_model="numpy")
def _first_at_least(key, value, lo, hi):  # pragma: no cover - compiled
    """The first index in ``[lo, hi)`` of the ascending ``key`` whose value is ≥ ``value``."""
    while lo < hi:
        mid = (lo + hi) // 2
        if np.int64(key[mid]) < value:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True, nogil=True, error_model="numpy")
def key_ranges(key, hs, qk, qq, longest2, floor, margin):  # pragma: no cover - compiled
    """Where in the sorted ``key`` column the rows that may beat ``floor`` lie: (R, 2) ranges.

    A row ``d`` scores ``q_v·d = ½(|d|² + |q_v|² − |d − q_v|²) ≤ ½(longest2 + qq_v −
    (d_K − qk_v)²)``, so only a row with ``(d_K − qk_v)² < longest2 + qq_v − 2(floor −
    margin)`` for some variant ``v`` can score within ``margin`` of ``floor``: the
    key ``round(d_K · hs)`` then lies in a window about ``qk_v · hs`` (widened by the
    rounding and one unit). The windows are merged; ``floor = −inf``: every row.
    """
    n = key.size
    out = np.empty((4, 2), np.int64)
    if not floor > -np.inf:
        out[0, 0], out[0, 1] = 0, n
        return out[:1]
    lo = np.empty(4)
    hi = np.empty(4)
    count = 0
    for v in range(4):
        r2 = longest2 + qq[v] - 2.0 * (floor - margin)
        if r2 <= 0.0:
            continue
        r = math.sqrt(r2) * (1.0 + 1e-9)
        lo[count] = math.floor((qk[v] - r) * hs - 0.5) - 1.0
        hi[count] = math.ceil((qk[v] + r) * hs + 0.5) + 1.0
        count += 1
    order = np.argsort(lo[:count])
    m = 0
    for t in range(count):
        a, b = lo[order[t]], hi[order[t]]
        if m > 0 and a <= out[m - 1, 1]:
            out[m - 1, 1] = max(out[m - 1, 1], np.int64(b))
        else:
            out[m, 0], out[m, 1] = np.int64(a), np.int64(b)
            m += 1
    for t in range(m):  # key values to indices
        i0 = _first_at_least(key, out[t, 0], 0, n)
        out[t, 1] = _first_at_least(key, out[t, 1] + 1, i0, n)
        out[t, 0] = i0
    return out[:m]


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"contract"}, inline="always")
def _bounds(head, tail, qh, qt, lo, nb, top):  # pragma: no cover - compiled
    """:func:`bound_topk`'s bound of the table's rows ``lo … lo + nb − 1`` into ``top``.

    Six head columns and three groups, written out: the compiler keeps eight rows
    in each register (twice as fast as the loops).
    """
    h0, h1, h2, h3, h4, h5 = head[0], head[1], head[2], head[3], head[4], head[5]
    u0, u1, u2 = tail[0], tail[1], tail[2]
    q00, q01, q02, q03, q04, q05 = qh[0, 0], qh[0, 1], qh[0, 2], qh[0, 3], qh[0, 4], qh[0, 5]
    q10, q11, q12, q13, q14, q15 = qh[1, 0], qh[1, 1], qh[1, 2], qh[1, 3], qh[1, 4], qh[1, 5]
    q20, q21, q22, q23, q24, q25 = qh[2, 0], qh[2, 1], qh[2, 2], qh[2, 3], qh[2, 4], qh[2, 5]
    q30, q31, q32, q33, q34, q35 = qh[3, 0], qh[3, 1], qh[3, 2], qh[3, 3], qh[3, 4], qh[3, 5]
    p00, p01, p02 = qt[0, 0], qt[0, 1], qt[0, 2]
    p10, p11, p12 = qt[1, 0], qt[1, 1], qt[1, 2]
    p20, p21, p22 = qt[2, 0], qt[2, 1], qt[2, 2]
    p30, p31, p32 = qt[3, 0], qt[3, 1], qt[3, 2]
    for i in range(nb):
        r = lo + i
        a, b, c = np.float32(h0[r]), np.float32(h1[r]), np.float32(h2[r])
        d, e, f = np.float32(h3[r]), np.float32(h4[r]), np.float32(h5[r])
        x, y, z = np.float32(u0[r]), np.float32(u1[r]), np.float32(u2[r])
        s0 = a * q00 + b * q01 + c * q02 + d * q03 + e * q04 + f * q05
        s1 = a * q10 + b * q11 + c * q12 + d * q13 + e * q14 + f * q15
        s2 = a * q20 + b * q21 + c * q22 + d * q23 + e * q24 + f * q25
        s3 = a * q30 + b * q31 + c * q32 + d * q33 + e * q34 + f * q35
        s0 += x * p00 + y * p01 + z * p02
        s1 += x * p10 + y * p11 + z * p12
        s2 += x * p20 + y * p21 + z * p22
        s3 += x * p30 + y * p31 + z * p32
        top[i] = max(max(s0, s1), max(s2, s3))


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _scored(desc, r, variants, margin, best, out, score, count):  # pragma: no cover - compiled
    """:func:`bound_topk`'s exact stage for descriptor row ``r``; returns the new count."""
    e0, e1, e2, e3 = 0.0, 0.0, 0.0, 0.0  # (four chains at once)
    for j in range(variants.shape[1]):
        x = np.float64(desc[r, j])
        e0 += variants[0, j] * x
        e1 += variants[1, j] * x
        e2 += variants[2, j] * x
        e3 += variants[3, j] * x
    s = max(max(e0, e1), max(e2, e3))
    if s + margin <= best[0]:
        return count
    out[count] = r
    score[count] = s
    if s > best[0]:  # the root replaced, sifted down
        k = best.size
        p = 0
        while True:
            ch = 2 * p + 1
            if ch >= k:
                break
            if ch + 1 < k and best[ch + 1] < best[ch]:
                ch += 1
            if best[ch] >= s:
                break
            best[p] = best[ch]
            p = ch
        best[p] = s
    return count + 1


@njit(cache=True, nogil=True, error_model="numpy")
def bound_topk(
    head,
    tail,
    rows,
    kcol,
    desc,
    qhead,
    qnorm,
    qq,
    hs,
    ts,
    longest2,
    variants,
    slack,
    margin,
    best,
    out,
    score,
):  # pragma: no cover
    """The rows of one chunk that may be among the best ``k``; updates the best ``k`` so far.

    ``best`` (k,) float64 is a min-heap of the best exact scores met so far
    (``-inf``: none yet), its root the floor. The compact table (head, tail,
    rows, sorted by head column ``kcol``; scales ``hs``, ``ts`` and the largest
    squared norm: see :func:`compact_rows`) is scanned in the ranges of
    :func:`key_ranges` only. A row's bound is ``max_v (q_h,v · head / hs + Σ_g
    |q_g,v| tail_g / ts_g)``, in float32 with the coefficients ``|q_g,v| / ts_g``
    rounded up; the head's rounding (``½ Σ_j max_v |q_vj| / hs``) is added to
    ``slack``. ``qhead`` (4, 6), ``qnorm`` (4, 3) and ``qq`` (4,) are the
    variants' head columns, their groups' norms and their squared norms. A row
    whose bound plus the slack beats the floor is scored exactly (float64,
    ``max_v variants[v] · desc[row]``); one whose score plus ``margin`` beats the
    floor goes into ``out`` (its descriptor row; ``score`` (float64): its exact
    score) and, above the floor, into the heap. While the
    heap is empty (a thread's first chunk), the ``2k`` rows of highest bound are
    scored first: the floor then starts near its final value instead of rising
    row by row. Returns how many rows went into ``out`` and how many were scored
    (the pass's cost: a query whose bound passes most rows is cheaper by BLAS).
    """
    n = head.shape[1]
    k = best.size
    qh = np.empty((4, 6), np.float32)
    qt = np.empty((4, 3), np.float32)
    allowance = 0.0
    for j in range(6):
        most = 0.0
        for v in range(4):
            qh[v, j] = np.float32(qhead[v, j] / hs)
            most = max(most, abs(qhead[v, j]))
        allowance += 0.5 * most / hs * (1.0 + 1e-9)
    for v in range(4):
        for g in range(3):
            qt[v, g] = np.float32(qnorm[v, g] / ts[g] * (1.0 + 1e-6))  # (up, past the rounding)
    slack += allowance
    block = 512
    count = 0
    scored = 0
    seen = np.zeros(0, np.bool_)
    if not best[0] > -np.inf and n > 0:  # the first rows scored: the 2k of highest bound
        every = np.empty(n, np.float32)
        for lo in range(0, n, block):
            _bounds(head, tail, qh, qt, lo, min(n, lo + block) - lo, every[lo:])
        m = min(n, 2 * k)
        least = np.partition(every, n - m)[n - m]
        seen = every >= least
        for i in range(n):
            if seen[i]:
                count = _scored(desc, rows[i], variants, margin, best, out, score, count)
                scored += 1
    qk = np.empty(4)
    for v in range(4):
        qk[v] = qhead[v, kcol]
    ranges = key_ranges(head[kcol], hs, qk, qq, longest2, best[0], margin)
    top = np.empty(block, np.float32)
    due = np.empty(block, np.int64)
    w = desc.shape[1]
    touched = 0.0
    for t in range(ranges.shape[0]):
        for lo in range(ranges[t, 0], ranges[t, 1], block):
            nb = min(ranges[t, 1], lo + block) - lo
            _bounds(head, tail, qh, qt, lo, nb, top)
            m = 0
            for i in range(nb):
                if np.float64(top[i]) + slack > best[0] and not (seen.size and seen[lo + i]):
                    due[m] = rows[lo + i]
                    m += 1
            # the rows to score read first, side by side (their cache misses then overlap;
            # one at a time, a row's read from memory is most of its cost)
            for i in range(m):
                touched += desc[due[i], 0] + desc[due[i], w - 1]
            for i in range(m):
                count = _scored(desc, due[i], variants, margin, best, out, score, count)
            scored += m
    if touched == 1.25e300:  # (never: keeps the reads)
        best[0] = best[0]
    return count, scored
