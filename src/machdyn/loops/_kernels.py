"""Compiled (numba) kernel of the vector-loop solver: a sweep solved group by group.

Imported only when :mod:`machdyn.jit` lets the compiled kernels serve, and used
for models whose groups (:mod:`machdyn.loops._compiled`) are all dyads or linear
groups of one or two unknowns — every pin-and-slider linkage the loops describe
without a triad. The NumPy continuation in :mod:`machdyn.loops.solve` is the
reference it is tested against (the test suite runs the loop tests on both
paths).

At every sample, in solving order, each dyad is put at its root of the
sweep's determinant sign in closed form (:func:`_dyad`: the law of cosines, a
circle–line meet, a vector's own angle and length; Norton, *Design of
Machinery*, §4.5) and each linear group solved by one Newton step on its own
rows; so an assembly gap, an island, a change point is settled sample by
sample exactly as the branch rules of docs/loops.md say, with no continuation
to lose. Then the Jacobian is evaluated and factored block by block at the pose
(its conditioning: toggles are flagged; each group's determinant) and the
inputs' rates give the velocity, acceleration and jerk, one solve each.

Arrays are passed one by one (:func:`machdyn.loops._jit_sweep.arrays` builds
them): taking them out of a tuple inside the per-sample helpers costs numba a
reference count each time, more than the arithmetic.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .._kernels import angle, sincos

__all__ = ["sweep"]

_jit = njit(cache=True, nogil=True, error_model="numpy")
_inline = njit(inline="always", error_model="numpy")
_TWO_PI = 2.0 * math.pi
_INV_TWO_PI = 0.5 / math.pi


@_inline
def _equations(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, col, x, cosv, sinv, f, jac
):
    """Residual ``f`` and Jacobian ``jac`` (columns: unknowns, then inputs) at ``x``."""
    n_loop = lptr.size - 1
    jac[:, :] = 0.0
    for ell in range(n_loop):
        fx = 0.0
        fy = 0.0
        for t in range(lptr[ell], lptr[ell + 1]):
            k = lvec[t]
            s = lsgn[t]
            lv = vl[k]
            av = va[k]
            d = x[lv] if lv >= 0 else dconst[k]
            if av >= 0:
                co = cosv[av]
                si = sinv[av]
            else:
                co = ccon[k]
                si = scon[k]
            sd = s * d
            fx += sd * co
            fy += sd * si
            if av >= 0 and col[av] >= 0:
                jac[2 * ell, col[av]] -= sd * si
                jac[2 * ell + 1, col[av]] += sd * co
            if lv >= 0 and col[lv] >= 0:
                jac[2 * ell, col[lv]] += s * co
                jac[2 * ell + 1, col[lv]] += s * si
        f[2 * ell] = fx
        f[2 * ell + 1] = fy
    for r in range(con0.size):
        acc = con0[r]
        for v in range(x.size):
            acc += con[r, v] * x[v]
            if col[v] >= 0:
                jac[2 * n_loop + r, col[v]] = con[r, v]
        f[2 * n_loop + r] = acc


@_inline
def _factor(roww, qscale, gptr, grows, gcols, jac, inv, gdet, grc):  # pragma: no cover
    """Each group's scaled diagonal block of ``J_q`` (1x1 or 2x2) inverted into ``inv``.

    Also each group's determinant (of the unscaled block) and pivot ratio (that
    of partial pivoting, as :func:`machdyn.loops._linalg._factor_2x2`); returns
    the smallest ratio.
    """
    worst = 1.0
    for b in range(gptr.size - 1):
        p0 = gptr[b]
        r0 = grows[p0]
        c0 = gcols[p0]
        if gptr[b + 1] - p0 == 1:
            a = jac[r0, c0] * roww[r0] * qscale[c0]
            inv[p0, p0] = 1.0 / a
            gdet[b] = jac[r0, c0]
            grc[b] = 1.0 if a != 0.0 else 0.0
        else:
            r1 = grows[p0 + 1]
            c1 = gcols[p0 + 1]
            w0 = roww[r0]
            w1 = roww[r1]
            q0 = qscale[c0]
            q1 = qscale[c1]
            s00 = jac[r0, c0] * w0 * q0
            s01 = jac[r0, c1] * w0 * q1
            s10 = jac[r1, c0] * w1 * q0
            s11 = jac[r1, c1] * w1 * q1
            det_s = s00 * s11 - s01 * s10
            first = max(abs(s00), abs(s10))
            ratio = abs(det_s) / (first * first) if first > 0.0 else 0.0
            grc[b] = min(ratio, 1.0 / ratio) if ratio > 0.0 else 0.0
            r = 1.0 / det_s
            inv[p0, p0] = s11 * r
            inv[p0, p0 + 1] = -s01 * r
            inv[p0 + 1, p0] = -s10 * r
            inv[p0 + 1, p0 + 1] = s00 * r
            gdet[b] = det_s / (w0 * w1 * q0 * q1)
        worst = min(worst, grc[b])
    return worst


@_inline
def _solve(roww, qscale, gptr, grows, gcols, jac, inv, rhs, out):  # pragma: no cover
    """``J_q out = rhs`` group by group (forward substitution over the groups)."""
    for b in range(gptr.size - 1):
        p0 = gptr[b]
        r0 = grows[p0]
        t0 = rhs[r0]
        for jj in range(p0):  # the columns of earlier groups
            t0 -= jac[r0, gcols[jj]] * out[gcols[jj]]
        t0 *= roww[r0]
        if gptr[b + 1] - p0 == 1:
            out[gcols[p0]] = t0 * inv[p0, p0] * qscale[gcols[p0]]
            continue
        r1 = grows[p0 + 1]
        t1 = rhs[r1]
        for jj in range(p0):
            t1 -= jac[r1, gcols[jj]] * out[gcols[jj]]
        t1 *= roww[r1]
        out[gcols[p0]] = (inv[p0, p0] * t0 + inv[p0, p0 + 1] * t1) * qscale[gcols[p0]]
        out[gcols[p0 + 1]] = (inv[p0 + 1, p0] * t0 + inv[p0 + 1, p0 + 1] * t1) * qscale[
            gcols[p0 + 1]
        ]


@_jit
def _first_pose(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, col, unk, inp, angle_var,
    roww, qscale, gptr, grows, gcols, u, q0, tol, polish_from, tiny_step, max_iter,
    x, cosv, sinv, f, jac, inv, gd, gr, step,
):  # fmt: skip
    """The sweep's first pose by Newton from the guess, as the NumPy path finds it.

    The same iteration as :meth:`machdyn.loops._newton.Scalar.newton` (steps
    limited to 0.5, stop at ``min(tol, polish_from)`` or a rounding-size step,
    then the polish). ``gd``/``gr`` hold the groups' determinants and pivot
    ratios of the last evaluation. Returns the smallest ratio, or -1 where it
    does not converge.
    """
    nq = unk.size
    for k in range(nq):
        x[unk[k]] = q0[k]
    for m in range(inp.size):
        x[inp[m]] = u[m, 0]
    target = min(tol, polish_from)
    for it in range(max_iter + 1):
        for v in range(x.size):
            if angle_var[v]:
                cosv[v] = math.cos(x[v])
                sinv[v] = math.sin(x[v])
        _equations(
            vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, col, x, cosv, sinv, f, jac
        )
        r = 0.0
        for e in range(f.size):
            r = max(r, abs(f[e] * roww[e]))
            f[e] = -f[e]
        worst = _factor(roww, qscale, gptr, grows, gcols, jac, inv, gd, gr)
        _solve(roww, qscale, gptr, grows, gcols, jac, inv, f, step)
        size = 0.0
        big = 1.0
        for k in range(nq):
            size = max(size, abs(step[k]) / qscale[k])
            big = max(big, abs(x[unk[k]]) / qscale[k])
        finite = size < math.inf
        tiny = size <= tiny_step * big
        if r <= target or (r <= tol and it == max_iter) or (tiny and r <= polish_from):
            if finite:
                for k in range(nq):
                    x[unk[k]] += step[k]
            return worst
        if it == max_iter or not finite:
            break
        shrink = 1.0 if size <= 0.5 else 0.5 / size
        for k in range(nq):
            x[unk[k]] += step[k] * shrink
    return -1.0


@_inline
def _near(angle, ref):  # pragma: no cover - compiled
    """``angle`` moved by whole turns to lie within π of ``ref``."""
    return angle - _TWO_PI * math.floor((angle - ref) * _INV_TWO_PI + 0.5)


@_inline
def _dyad(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, kind, ell, a, v2, flip, tcat,
    x, cosv, sinv, want, close_tol,
):  # fmt: skip
    """Put a dyad at its root of determinant sign ``want`` (closed form); False if none.

    Its loop reads ``K + P e^{jθa} + (terms of the second unknown) = 0`` with
    everything before the group known (``x``, ``cosv``, ``sinv``); ``tcat``
    says which term is which (0 known, 1 on ``a``, 2 on ``v2``). Writes the two
    unknowns (angles within π of their values in ``x``) and the cos/sin of the
    unknown angles. ``kind`` 1: two angles; 2: an angle and a slide; 3: the
    angle and length of one vector. ``flip``: the group's columns are (v2, a).
    """
    kx = 0.0
    ky = 0.0
    p = 0.0
    qq = 0.0
    ex = 0.0
    ey = 0.0
    for t in range(lptr[ell], lptr[ell + 1]):
        k = lvec[t]
        s = lsgn[t]
        lv = vl[k]
        av = va[k]
        d = x[lv] if lv >= 0 else dconst[k]
        if av >= 0:
            co = cosv[av]
            si = sinv[av]
        else:
            co = ccon[k]
            si = scon[k]
        cat = tcat[t]
        if cat == 0:
            kx += s * d * co
            ky += s * d * si
        elif cat == 1:
            p += s * d
        elif kind == 1:
            qq += s * d
        elif kind == 2:
            ex += s * co
            ey += s * si
        else:
            qq += s
    if kind == 1:  # two angles: P e^{ja} + Q e^{jb} = V = -K
        vx = -kx
        vy = -ky
        r = math.sqrt(vx * vx + vy * vy)
        pa = abs(p)
        qa = abs(qq)
        if r == 0.0 or pa == 0.0 or qa == 0.0:
            return False
        cos_t = (pa * pa + r * r - qa * qa) / (2.0 * pa * r)
        if not abs(cos_t) <= 1.0 + close_tol:
            return False
        cos_t = min(1.0, max(-1.0, cos_t))
        sin_t = math.sqrt(1.0 - cos_t * cos_t)
        ux = vx / r
        uy = vy / r
        sp = 1.0 if p >= 0.0 else -1.0
        eax = 0.0
        eay = 0.0
        bx = 0.0
        by = 0.0
        for attempt in range(2):
            st = sin_t if attempt == 0 else -sin_t
            alx = ux * cos_t - uy * st  # the direction of P e^{ja}
            aly = uy * cos_t + ux * st
            bx = (vx - pa * alx) / qq  # e^{jb} from Q e^{jb} = V - P e^{ja}
            by = (vy - pa * aly) / qq
            eax = sp * alx
            eay = sp * aly
            det = p * qq * (eax * by - eay * bx)  # columns (a, b): P Q sin(b - a)
            if (-det if flip else det) * want > 0.0:
                break
        x[a] = _near(math.atan2(eay, eax), x[a])
        x[v2] = _near(math.atan2(by, bx), x[v2])
        cosv[a] = eax
        sinv[a] = eay
        cosv[v2] = bx
        sinv[v2] = by
        return True
    if kind == 2:  # angle and slide: K + P e^{ja} + d E = 0
        e = math.sqrt(ex * ex + ey * ey)
        if e == 0.0 or p == 0.0:
            return False
        fx = ex / e
        fy = ey / e
        kr = kx * fx + ky * fy  # K in the frame of E
        ki = ky * fx - kx * fy
        sin_t = -ki / p
        if not abs(sin_t) <= 1.0 + close_tol:
            return False
        sin_t = min(1.0, max(-1.0, sin_t))
        cos_t = math.sqrt(1.0 - sin_t * sin_t)
        eax = 0.0
        eay = 0.0
        d = 0.0
        for attempt in range(2):
            ct = cos_t if attempt == 0 else -cos_t
            eax = fx * ct - fy * sin_t
            eay = fy * ct + fx * sin_t
            d = (-kr - p * ct) / e
            det = -p * (eay * ey + eax * ex)  # columns (a, d): P j e^{ja}, E
            if (-det if flip else det) * want > 0.0:
                break
        x[a] = _near(math.atan2(eay, eax), x[a])
        x[v2] = d
        cosv[a] = eax
        sinv[a] = eay
        return True
    # the angle and length of one vector: K + (S d + P) e^{ja} = 0
    kk = math.sqrt(kx * kx + ky * ky)
    if qq == 0.0 or kk == 0.0:
        return False
    eax = 0.0
    eay = 0.0
    d = 0.0
    for attempt in range(2):
        m = kk if attempt == 0 else -kk  # S d + P
        eax = -kx / m
        eay = -ky / m
        d = (m - p) / qq
        det = -m * qq  # columns (a, d): m j e^{ja}, S e^{ja}
        if (-det if flip else det) * want > 0.0:
            break
    x[a] = _near(math.atan2(eay, eax), x[a])
    x[v2] = d
    cosv[a] = eax
    sinv[a] = eay
    return True


@_inline
def _accumulate(X, cosm, sinm, lv, av, s, sd, cc, sc, out_x, out_y, n):  # pragma: no cover
    """``out += s d e^{jθ}`` over the samples, one loop per case (vectorisable).

    ``lv``/``av``: the vector's length and angle variables (-1: constant, then
    ``sd = s d`` and ``cc``/``sc`` the constant angle's cos/sin).
    """
    if lv >= 0 and av >= 0:
        for i in range(n):
            d = s * X[lv, i]
            out_x[i] += d * cosm[av, i]
            out_y[i] += d * sinm[av, i]
    elif lv >= 0:
        for i in range(n):
            d = s * X[lv, i]
            out_x[i] += d * cc
            out_y[i] += d * sc
    elif av >= 0:
        for i in range(n):
            out_x[i] += sd * cosm[av, i]
            out_y[i] += sd * sinm[av, i]
    else:
        for i in range(n):
            out_x[i] += sd * cc
            out_y[i] += sd * sc


@_inline
def _constraint(con, con0, r, v0, rot, cos_d, sin_d, angle_var, x, cosv, sinv):  # pragma: no cover
    """One constraint (row ``r`` of ``con``) solved for its one unknown ``v0`` (scalar)."""
    acc = con0[r]
    for v in range(x.size):
        if v != v0:
            acc += con[r, v] * x[v]
    x[v0] = -acc / con[r, v0]
    if rot >= 0:  # θ = θ_rot + δ: cos/sin by rotation
        cosv[v0] = cosv[rot] * cos_d - sinv[rot] * sin_d
        sinv[v0] = sinv[rot] * cos_d + cosv[rot] * sin_d
    elif angle_var[v0]:
        cosv[v0] = math.cos(x[v0])
        sinv[v0] = math.sin(x[v0])


@_inline
def _pose(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, inp, angle_var,
    gkind, gloop, ga, gb, gflip, tcat, grow, gvar, grot, gcos, gsin,
    x, cosv, sinv, want, close_tol,
):  # fmt: skip
    """One pose in plain floats, every group in order on the branch ``want``.

    ``x`` holds the inputs and, for the angles' whole turns, a pose. Returns the
    failing group (-1: none).
    """
    for m in range(inp.size):
        v = inp[m]
        if angle_var[v]:
            cosv[v] = math.cos(x[v])
            sinv[v] = math.sin(x[v])
    for b in range(gkind.size):
        if gkind[b] == 4:
            _constraint(
                con, con0, grow[b], gvar[b], grot[b], gcos[b], gsin[b], angle_var, x, cosv, sinv
            )
        elif not _dyad(
            vl, va, dconst, ccon, scon, lptr, lvec, lsgn, gkind[b],
            gloop[b], ga[b], gb[b], gflip[b], tcat, x, cosv, sinv, want[b], close_tol,
        ):  # fmt: skip
            return b
    return -1


@_jit
def sweep(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, unk, inp, col,
    roww, qscale, uscale, gptr, grows, gcols, angle_var, parity, pptr, pvec, psgn,
    gkind, gloop, ga, gb, gflip, tcat, grow, gvar, grot, gcos, gsin,
    u, q0, want, u1, u2, u3, orders, close_tol, sing_tol, sub_step,
    tol, polish_from, tiny_step, max_iter,
    X, rates, det, rcond, gdet, grc, resid, code, group, P,
):  # fmt: skip
    """Every sample of the sweep ``u`` (n_u, N), group by group in closed form.

    The model: vectors (``vl``/``va`` variable indices or -1, constants), loops
    as (vector, sign) lists from ``lptr``, constraints ``con``/``con0``, the
    unknowns' and inputs' variable indices, each variable's Jacobian column,
    row and column scales, the groups' rows and columns from ``gptr``, which
    variables are angles, the determinant's permutation ``parity``; per group
    its kind (1–3 dyads, see :func:`_dyad`; 4 one constraint on one unknown:
    row ``grow``, variable ``gvar``, rotated from ``grot`` by the angle whose
    cos/sin are ``gcos``/``gsin`` where it is an angle offset), loop, unknowns,
    column order and terms' parts. ``q0``: the guess; the first pose found from
    it by Newton (:func:`_first_pose`, ``tol`` ... ``max_iter``) sets the
    angles' whole turns and, where ``want`` is all 0, the branch. ``u1..u3``:
    the inputs' rates, ``orders`` of them used.

    Out: ``X`` (n_var, N) every variable (unknowns NaN where the pose does not
    close), ``rates`` (orders, n_var, N; NaN where not ok), ``det``, ``rcond``,
    ``gdet``/``grc``, ``resid``, ``code`` 0 ok, 1 no assembly (``group``: the
    first group that cannot close), 2 singular (``group``: the weakest), and
    ``P`` (1 + orders, n_point, N) the named points (vector chains from
    ``pptr``) and their rates, complex.
    The samples are solved independently (loops over samples, SIMD-friendly);
    then each angle is put in the whole turn within π of the last pose solved
    before it, reached in sub-steps where the input moved by more than
    ``sub_step`` (scaled). Returns N, or 0 where the first sample gives no
    branch (a gap or a toggle there) and ``want`` was not given.
    """
    nq = unk.size
    nu = inp.size
    n_var = col.size
    ng = gkind.size
    n_loop = lptr.size - 1
    n = u.shape[1]
    cosm = np.empty((n_var, n))
    sinm = np.empty((n_var, n))
    x = np.empty(n_var)
    cosv = np.empty(n_var)
    sinv = np.empty(n_var)
    ref = np.empty(n_var)

    # 0. The branch: the groups' determinant signs at the first pose, by Newton from the
    #    guess as the NumPy path finds it (whose angles set the whole turns).
    f0 = np.empty(roww.size)
    jac0 = np.empty((roww.size, nq + nu))
    inv0 = np.empty((nq, nq))
    step0 = np.empty(nq)
    gd0 = np.empty(ng)
    gr0 = np.empty(ng)
    worst0 = _first_pose(
        vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, col, unk, inp, angle_var,
        roww, qscale, gptr, grows, gcols, u, q0, tol, polish_from, tiny_step, max_iter,
        x, cosv, sinv, f0, jac0, inv0, gd0, gr0, step0,
    )  # fmt: skip
    set_branch = True
    for b in range(ng):
        if want[b] != 0.0:
            set_branch = False
    if set_branch:
        if not worst0 >= 10.0 * sing_tol:
            return 0  # no pose there, or a toggle: no branch to keep
        for b in range(ng):
            want[b] = 1.0 if gd0[b] > 0.0 else -1.0
    first = np.empty(nq)
    for k in range(nq):
        first[k] = x[unk[k]] if worst0 >= 0.0 else q0[k]

    # 1. The inputs, and every group over all samples.
    for i in range(n):
        code[i] = 0
        group[i] = -1
    for m in range(nu):
        v = inp[m]
        for i in range(n):
            X[v, i] = u[m, i]
        if angle_var[v]:
            for i in range(n):
                sinm[v, i], cosm[v, i] = sincos(u[m, i])
    kx = np.empty(n)
    ky = np.empty(n)
    pp = np.empty(n)
    qq = np.empty(n)
    ex = np.empty(n)
    ey = np.empty(n)
    okf = np.empty(n, dtype=np.bool_)
    for b in range(ng):
        kind = gkind[b]
        if kind == 4:
            r = grow[b]
            v0 = gvar[b]
            for i in range(n):
                kx[i] = con0[r]
            for v in range(n_var):
                cv = con[r, v]
                if v != v0 and cv != 0.0:
                    for i in range(n):
                        kx[i] += cv * X[v, i]
            c0 = con[r, v0]
            for i in range(n):
                X[v0, i] = -kx[i] / c0
            if grot[b] >= 0:
                o = grot[b]
                cd = gcos[b]
                sd = gsin[b]
                for i in range(n):
                    cosm[v0, i] = cosm[o, i] * cd - sinm[o, i] * sd
                    sinm[v0, i] = sinm[o, i] * cd + cosm[o, i] * sd
            elif angle_var[v0]:
                for i in range(n):
                    sinm[v0, i], cosm[v0, i] = sincos(X[v0, i])
            continue
        ell = gloop[b]
        a = ga[b]
        v2 = gb[b]
        for i in range(n):
            kx[i] = 0.0
            ky[i] = 0.0
            pp[i] = 0.0
            qq[i] = 0.0
            ex[i] = 0.0
            ey[i] = 0.0
        for t in range(lptr[ell], lptr[ell + 1]):
            k = lvec[t]
            s = lsgn[t]
            lv = vl[k]
            av = va[k]
            cat = tcat[t]
            sd = s * dconst[k]
            if cat == 0:
                _accumulate(X, cosm, sinm, lv, av, s, sd, ccon[k], scon[k], kx, ky, n)
            elif cat == 1 or kind == 1:
                acc = pp if cat == 1 else qq
                if lv >= 0:
                    for i in range(n):
                        acc[i] += s * X[lv, i]
                else:
                    for i in range(n):
                        acc[i] += sd
            elif kind == 2:
                _accumulate(X, cosm, sinm, -1, av, s, s, ccon[k], scon[k], ex, ey, n)
            else:
                for i in range(n):
                    qq[i] += s
        sgn = want[b] * (-1.0 if gflip[b] else 1.0)
        # (one branch-free loop per kind, so that LLVM can vectorise it)
        if kind == 1:  # P e^{ja} + Q e^{jb} = V = -K
            for i in range(n):
                vx = -kx[i]
                vy = -ky[i]
                r = math.sqrt(vx * vx + vy * vy)
                p = pp[i]
                q = qq[i]
                pa = abs(p)
                cos_t = (pa * pa + r * r - q * q) / (2.0 * pa * r)
                okf[i] = abs(cos_t) <= 1.0 + close_tol
                cos_t = min(1.0, max(-1.0, cos_t))
                sin_t = math.sqrt(1.0 - cos_t * cos_t)
                rinv = 1.0 / r
                ux = vx * rinv
                uy = vy * rinv
                sp = 1.0 if p >= 0.0 else -1.0
                # the + root's determinant P Q sin(b - a) (its sign); the other root mirrors it
                alx = ux * cos_t - uy * sin_t
                aly = uy * cos_t + ux * sin_t
                dplus = p * sp * (alx * (vy - pa * aly) - aly * (vx - pa * alx))
                st = sin_t if dplus * sgn >= 0.0 else -sin_t
                alx = ux * cos_t - uy * st
                aly = uy * cos_t + ux * st
                qinv = 1.0 / q
                bx = (vx - pa * alx) * qinv
                by = (vy - pa * aly) * qinv
                eax = sp * alx
                eay = sp * aly
                X[a, i] = angle(eay, eax)
                X[v2, i] = angle(by, bx)
                cosm[a, i] = eax
                sinm[a, i] = eay
                cosm[v2, i] = bx
                sinm[v2, i] = by
        elif kind == 2:  # K + P e^{ja} + d E = 0
            for i in range(n):
                e = math.sqrt(ex[i] * ex[i] + ey[i] * ey[i])
                einv = 1.0 / e
                fx = ex[i] * einv
                fy = ey[i] * einv
                p = pp[i]
                kr = kx[i] * fx + ky[i] * fy
                ki = ky[i] * fx - kx[i] * fy
                sin_t = -ki / p
                okf[i] = abs(sin_t) <= 1.0 + close_tol
                sin_t = min(1.0, max(-1.0, sin_t))
                cos_t = math.sqrt(1.0 - sin_t * sin_t)
                eax = fx * cos_t - fy * sin_t
                eay = fy * cos_t + fx * sin_t
                dplus = -p * (eay * ey[i] + eax * ex[i])
                ct = cos_t if dplus * sgn >= 0.0 else -cos_t
                eax = fx * ct - fy * sin_t
                eay = fy * ct + fx * sin_t
                X[a, i] = angle(eay, eax)
                X[v2, i] = (-kr - p * ct) * einv
                cosm[a, i] = eax
                sinm[a, i] = eay
        else:  # K + (S d + P) e^{ja} = 0
            for i in range(n):
                kk = math.sqrt(kx[i] * kx[i] + ky[i] * ky[i])
                q = qq[i]
                mm = kk if -kk * q * sgn >= 0.0 else -kk
                minv = 1.0 / mm
                eax = -kx[i] * minv
                eay = -ky[i] * minv
                okf[i] = True
                X[a, i] = angle(eay, eax)
                X[v2, i] = (mm - pp[i]) / q
                cosm[a, i] = eax
                sinm[a, i] = eay
        for i in range(n):
            if code[i] == 0 and not (okf[i] and X[a, i] == X[a, i] and X[v2, i] == X[v2, i]):
                code[i] = 1
                group[i] = b

    # 2. Whole turns: each angle within π of the last pose solved before it (not those
    #    a constraint fixes from the inputs or lengths: they are exact as they are).
    free = np.ones(n_var, dtype=np.bool_)
    for m in range(nu):
        free[inp[m]] = False
    for b in range(ng):
        if gkind[b] == 4 and (grot[b] < 0 or not free[grot[b]]):
            free[gvar[b]] = False
    for k in range(nq):
        ref[unk[k]] = first[k]
    for m in range(nu):
        ref[inp[m]] = u[m, 0]
    prev_ok = False
    for i in range(n):
        if code[i] == 1:
            prev_ok = False
            continue
        span = 0.0
        for m in range(nu):
            span = max(span, abs(u[m, i] - ref[inp[m]]) / uscale[m])
        if prev_ok and span > sub_step:
            # walk from the last pose in sub-steps (closed forms): ref becomes the pose
            # at sample i in the whole turns of the walk
            subs = int(span / sub_step) + 1
            for v in range(n_var):
                x[v] = ref[v]
            start = np.empty(nu)
            for m in range(nu):
                start[m] = ref[inp[m]]
            for sub in range(1, subs + 1):
                for m in range(nu):
                    x[inp[m]] = start[m] + (u[m, i] - start[m]) * sub / subs
                if _pose(
                    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, inp, angle_var,
                    gkind, gloop, ga, gb, gflip, tcat, grow, gvar, grot, gcos, gsin,
                    x, cosv, sinv, want, close_tol,
                ) >= 0:  # fmt: skip
                    break  # the walk meets a gap: keep the last pose as the reference
                for v in range(n_var):
                    ref[v] = x[v]
        for k in range(nq):
            v = unk[k]
            if angle_var[v] and free[v]:
                X[v, i] = _near(X[v, i], ref[v])
            ref[v] = X[v, i]
        for m in range(nu):
            ref[inp[m]] = u[m, i]
        prev_ok = True

    # 3. The loops' residual; each group's block of J_q inverted (det, pivot ratio).
    for i in range(n):
        resid[i] = 0.0
        rcond[i] = 1.0
        det[i] = parity
    for ell in range(n_loop):
        for i in range(n):
            kx[i] = 0.0
            ky[i] = 0.0
        for t in range(lptr[ell], lptr[ell + 1]):
            k = lvec[t]
            _accumulate(
                X,
                cosm,
                sinm,
                vl[k],
                va[k],
                lsgn[t],
                lsgn[t] * dconst[k],
                ccon[k],
                scon[k],
                kx,
                ky,
                n,
            )
        w = roww[2 * ell]
        for i in range(n):
            resid[i] = max(resid[i], max(abs(kx[i]), abs(ky[i])) * w)
    for r in range(con0.size):
        for i in range(n):
            kx[i] = con0[r]
        for v in range(n_var):
            if con[r, v] != 0.0:
                cv = con[r, v]
                for i in range(n):
                    kx[i] += cv * X[v, i]
        w = roww[2 * n_loop + r]
        for i in range(n):
            resid[i] = max(resid[i], abs(kx[i]) * w)
    inv = np.empty((ng, 4, n))
    for b in range(ng):
        kind = gkind[b]
        if kind == 4:
            a0 = con[grow[b], gvar[b]]
            for i in range(n):
                gdet[b, i] = a0
                grc[b, i] = 1.0 if a0 != 0.0 else 0.0
        else:
            ell = gloop[b]
            a = ga[b]
            v2 = gb[b]
            for i in range(n):
                pp[i] = 0.0
                qq[i] = 0.0
                ex[i] = 0.0
                ey[i] = 0.0
            for t in range(lptr[ell], lptr[ell + 1]):  # the group's own coefficients
                k = lvec[t]
                s = lsgn[t]
                lv = vl[k]
                if tcat[t] == 1 or (tcat[t] == 2 and kind != 2):
                    acc = pp if tcat[t] == 1 else qq
                    if kind == 3:
                        for i in range(n):
                            acc[i] += s
                    elif lv >= 0:
                        for i in range(n):
                            acc[i] += s * X[lv, i]
                    else:
                        for i in range(n):
                            acc[i] += s * dconst[k]
                elif tcat[t] == 2:
                    _accumulate(X, cosm, sinm, -1, va[k], s, s, ccon[k], scon[k], ex, ey, n)
            # column of a: j (P [+ S d]) e^{ja}; of v2: j Q e^{jb} | E | S e^{ja}
            p0 = gptr[b]
            r0 = grows[p0]
            w0 = roww[r0]
            w1 = roww[r0 + 1]
            qa = qscale[col[a]]
            qb = qscale[col[v2]]
            unscale = 1.0 / (w0 * w1 * qa * qb)
            for i in range(n):
                ca = cosm[a, i]
                sa = sinm[a, i]
                pa = pp[i] + (qq[i] * X[v2, i] if kind == 3 else 0.0)
                ax = -pa * sa
                ay = pa * ca
                if kind == 1:
                    bx = -qq[i] * sinm[v2, i]
                    by = qq[i] * cosm[v2, i]
                elif kind == 2:
                    bx = ex[i]
                    by = ey[i]
                else:
                    bx = qq[i] * ca
                    by = qq[i] * sa
                # the scaled block, columns in the group's order (a, v2) or (v2, a)
                s00 = ax * w0 * qa
                s10 = ay * w1 * qa
                s01 = bx * w0 * qb
                s11 = by * w1 * qb
                if gflip[b]:
                    s00, s01 = s01, s00
                    s10, s11 = s11, s10
                det_s = s00 * s11 - s01 * s10
                first = max(abs(s00), abs(s10))
                ratio = abs(det_s) / (first * first)
                grc[b, i] = min(ratio, 1.0 / ratio) if ratio > 0.0 else 0.0
                rr = 1.0 / det_s
                inv[b, 0, i] = s11 * rr
                inv[b, 1, i] = -s01 * rr
                inv[b, 2, i] = -s10 * rr
                inv[b, 3, i] = s00 * rr
                gdet[b, i] = det_s * unscale
        for i in range(n):
            det[i] *= gdet[b, i]
            if grc[b, i] < rcond[i] or grc[b, i] != grc[b, i]:
                rcond[i] = grc[b, i]
                if code[i] != 1:
                    group[i] = b
    for i in range(n):
        if code[i] == 0 and not rcond[i] >= sing_tol:
            code[i] = 2
        elif code[i] == 0:
            group[i] = -1
    if set_branch and (code[0] != 0 or not rcond[0] >= 10.0 * sing_tol):
        return 0  # the first sample gives no branch: a gap or a toggle there

    # 4. Velocity, acceleration, jerk, group by group: each group's block solved for its
    #    unknowns' highest derivative, everything else of its loop known (DESIGN.md).
    zero = np.zeros(n)
    dfill = np.empty(n)
    cfill = np.empty(n)
    sfill = np.empty(n)
    for order in range(1, orders + 1):
        uk = u1 if order == 1 else (u2 if order == 2 else u3)
        out = rates[order - 1]
        for m in range(nu):
            v = inp[m]
            for i in range(n):
                out[v, i] = uk[m, i]
        for b in range(ng):
            kind = gkind[b]
            if kind == 4:  # linear: no lower-order terms
                r = grow[b]
                v0 = gvar[b]
                for i in range(n):
                    kx[i] = 0.0
                for v in range(n_var):
                    if v != v0 and con[r, v] != 0.0:
                        cv = con[r, v]
                        for i in range(n):
                            kx[i] += cv * out[v, i]
                c0 = -1.0 / con[r, v0]
                for i in range(n):
                    out[v0, i] = kx[i] * c0
                continue
            ell = gloop[b]
            a = ga[b]
            v2 = gb[b]
            for i in range(n):
                kx[i] = 0.0
                ky[i] = 0.0
            for t in range(lptr[ell], lptr[ell + 1]):
                k = lvec[t]
                s = lsgn[t]
                lv = vl[k]
                av = va[k]
                if lv >= 0:
                    dd = X[lv]
                else:
                    dd = dfill
                    for i in range(n):
                        dd[i] = dconst[k]
                if av >= 0:
                    co = cosm[av]
                    si = sinm[av]
                else:
                    co = cfill
                    si = sfill
                    for i in range(n):
                        co[i] = ccon[k]
                        si[i] = scon[k]
                # the known highest derivatives (not the group's own): s (d⁽ᵏ⁾ + j d θ⁽ᵏ⁾) e^{jθ}
                dk = out[lv] if lv >= 0 and lv != a and lv != v2 else zero
                tk = out[av] if av >= 0 and av != a and av != v2 else zero
                for i in range(n):
                    re = dk[i]
                    im = dd[i] * tk[i]
                    kx[i] += s * (re * co[i] - im * si[i])
                    ky[i] += s * (re * si[i] + im * co[i])
                if order == 1 or av < 0:
                    continue
                d1 = rates[0, lv] if lv >= 0 else zero
                w1 = rates[0, av]
                if order == 2:
                    for i in range(n):
                        re = -dd[i] * w1[i] * w1[i]
                        im = 2.0 * d1[i] * w1[i]
                        kx[i] += s * (re * co[i] - im * si[i])
                        ky[i] += s * (re * si[i] + im * co[i])
                    continue
                d2 = rates[1, lv] if lv >= 0 else zero
                w2 = rates[1, av]
                for i in range(n):
                    w = w1[i]
                    re = -3.0 * d1[i] * w * w - 3.0 * dd[i] * w * w2[i]
                    im = 3.0 * d1[i] * w2[i] + 3.0 * d2[i] * w - dd[i] * w * w * w
                    kx[i] += s * (re * co[i] - im * si[i])
                    ky[i] += s * (re * si[i] + im * co[i])
            p0 = gptr[b]
            r0 = grows[p0]
            w0 = -roww[r0]
            w1_ = -roww[r0 + 1]
            c0 = gcols[p0]
            c1 = gcols[p0 + 1]
            x0 = unk[c0]
            x1 = unk[c1]
            q0s = qscale[c0]
            q1s = qscale[c1]
            for i in range(n):
                t0 = kx[i] * w0
                t1 = ky[i] * w1_
                out[x0, i] = (inv[b, 0, i] * t0 + inv[b, 1, i] * t1) * q0s
                out[x1, i] = (inv[b, 2, i] * t0 + inv[b, 3, i] * t1) * q1s

    # 5. NaN where there is no pose, and no rates where the pose is not ok.
    for i in range(n):
        if code[i] == 1:
            for k in range(nq):
                X[unk[k], i] = math.nan
        if code[i] != 0:
            for o in range(orders):
                for v in range(n_var):
                    rates[o, v, i] = math.nan

    # 6. The named points: their vector chains and the chains' derivatives (DESIGN.md);
    #    NaN where the pose (for the rates: the sample) is not there, as the variables.
    re_ = np.empty(n)
    im_ = np.empty(n)
    for o in range(orders + 1):
        for j in range(pptr.size - 1):
            for i in range(n):
                re_[i] = 0.0
                im_[i] = 0.0
            for t in range(pptr[j], pptr[j + 1]):
                k = pvec[t]
                s = psgn[t]
                lv = vl[k]
                av = va[k]
                if lv >= 0:
                    dd = X[lv]
                else:
                    dd = dfill
                    for i in range(n):
                        dd[i] = dconst[k]
                if av >= 0:
                    co = cosm[av]
                    si = sinm[av]
                else:
                    co = cfill
                    si = sfill
                    for i in range(n):
                        co[i] = ccon[k]
                        si[i] = scon[k]
                if o == 0:
                    for i in range(n):
                        re_[i] += s * dd[i] * co[i]
                        im_[i] += s * dd[i] * si[i]
                    continue
                d1 = rates[0, lv] if lv >= 0 else zero
                w1 = rates[0, av] if av >= 0 else zero
                if o == 1:
                    for i in range(n):
                        rr = d1[i]
                        ii = dd[i] * w1[i]
                        re_[i] += s * (rr * co[i] - ii * si[i])
                        im_[i] += s * (rr * si[i] + ii * co[i])
                    continue
                d2 = rates[1, lv] if lv >= 0 else zero
                w2 = rates[1, av] if av >= 0 else zero
                if o == 2:
                    for i in range(n):
                        rr = d2[i] - dd[i] * w1[i] * w1[i]
                        ii = dd[i] * w2[i] + 2.0 * d1[i] * w1[i]
                        re_[i] += s * (rr * co[i] - ii * si[i])
                        im_[i] += s * (rr * si[i] + ii * co[i])
                    continue
                d3 = rates[2, lv] if lv >= 0 else zero
                w3 = rates[2, av] if av >= 0 else zero
                for i in range(n):
                    w = w1[i]
                    rr = d3[i] - 3.0 * d1[i] * w * w - 3.0 * dd[i] * w * w2[i]
                    ii = dd[i] * w3[i] + 3.0 * d1[i] * w2[i] + 3.0 * d2[i] * w - dd[i] * w * w * w
                    re_[i] += s * (rr * co[i] - ii * si[i])
                    im_[i] += s * (rr * si[i] + ii * co[i])
            for i in range(n):
                if code[i] == 1 or (o > 0 and code[i] != 0):  # as the positions and rates
                    P[o, j, i] = complex(math.nan, math.nan)
                else:
                    P[o, j, i] = complex(re_[i], im_[i])
    return n
