"""Compiled (numba) kernel of the vector-loop solver: a sweep solved group by group.

Imported only when :mod:`machdyn.jit` lets the compiled kernels serve, and used
for models whose groups (:mod:`machdyn.loops._compiled`) are all dyads or linear
groups of one or two unknowns — every pin-and-slider linkage the loops describe
without a triad. The NumPy continuation in :mod:`machdyn.loops.solve` is the
reference it is tested against (the test suite runs the loop tests on both
paths).

At every sample, in solving order, each dyad is put at its root of the
sweep's determinant sign in closed form (the law of cosines, a circle–line
meet, a vector's own angle and length; Norton, *Design of Machinery*, §4.5)
and each single constraint solved for its one unknown; so an assembly gap, an
island, a change point is settled sample by sample exactly as the branch rules
of docs/loops.md say, with no continuation to lose. Then the angles' whole
turns are carried along the sweep (one pose at a time where an input step is
long: :mod:`machdyn.loops._kernels_pose`), the Jacobian is evaluated and
factored block by block at the pose (its conditioning: toggles are flagged;
each group's determinant) and the inputs' rates give the velocity,
acceleration and jerk group by group. Each step is one function below, a loop
over the samples per group (SIMD-friendly).

Arrays are passed one by one (:func:`machdyn.loops._jit_sweep.arrays` builds
them): taking them out of a tuple inside the per-sample helpers costs numba a
reference count each time, more than the arithmetic.
"""

from __future__ import annotations

import math

import numpy as np

from .._kernels import angle, sincos
from .._numba_cache import njit
from ._kernels_pose import _first_pose, _near, _pose

__all__ = ["sweep"]

_jit = njit(cache=True, nogil=True, error_model="numpy")
_inline = njit(inline="always", error_model="numpy")


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
    n = u.shape[1]
    set_branch = True
    for b in range(gkind.size):
        if want[b] != 0.0:
            set_branch = False
    # 0. The branch: the groups' determinant signs at the first pose, by Newton from the
    #    guess as the NumPy path finds it (whose angles set the whole turns).
    first = np.empty(unk.size)
    if not _start(
        vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, col, unk, inp, angle_var,
        roww, qscale, gptr, grows, gcols, u, q0, tol, polish_from, tiny_step, max_iter,
        want, set_branch, sing_tol, first,
    ):  # fmt: skip
        return 0  # no pose there, or a toggle: no branch to keep
    # 1, 3-6. Chunk by chunk (the arrays of a chunk stay in cache): the groups, residual,
    #    blocks, rates and points; NaN where there is no pose or no rates.
    for c0 in range(0, n, CHUNK):
        _chunk(
            vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, unk, inp, col,
            roww, qscale, gptr, grows, gcols, angle_var, parity, pptr, pvec, psgn,
            gkind, gloop, ga, gb, gflip, tcat, grow, gvar, grot, gcos, gsin,
            u, want, u1, u2, u3, orders, close_tol, sing_tol, c0, min(CHUNK, n - c0),
            X, rates, det, rcond, gdet, grc, resid, code, group, P,
        )  # fmt: skip
        if c0 == 0 and set_branch and (code[0] != 0 or not rcond[0] >= 10.0 * sing_tol):
            return 0  # the first sample gives no branch: a gap or a toggle there
    # 2. Whole turns: each angle within π of the last pose solved before it (the rates
    #    and points do not depend on them).
    _whole_turns(
        vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, unk, inp, angle_var, uscale,
        gkind, gloop, ga, gb, gflip, tcat, grow, gvar, grot, gcos, gsin,
        u, first, want, close_tol, sub_step, X, code,
    )  # fmt: skip
    return n


#: Samples per chunk: a chunk's arrays (a few dozen rows of this length) stay in the
#: core's cache through every step.
CHUNK = 1024


@_jit
def _chunk(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, unk, inp, col,
    roww, qscale, gptr, grows, gcols, angle_var, parity, pptr, pvec, psgn,
    gkind, gloop, ga, gb, gflip, tcat, grow, gvar, grot, gcos, gsin,
    u, want, u1, u2, u3, orders, close_tol, sing_tol, c0, m,
    X, rates, det, rcond, gdet, grc, resid, code, group, P,
):  # fmt: skip
    """Steps 1 and 3-6 of :func:`sweep` for the samples ``c0 … c0 + m - 1``.

    Computed in arrays of ``m`` samples, then copied into the sweep's.
    """
    n_var = X.shape[0]
    ng = gkind.size
    uc = _take(u, c0, m)
    Xc = np.empty((n_var, m))
    cosm = np.empty((n_var, m))
    sinm = np.empty((n_var, m))
    code_c = np.empty(m, dtype=np.int8)
    group_c = np.empty(m, dtype=np.int16)
    _solve_groups(
        vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, inp, angle_var,
        gkind, gloop, ga, gb, gflip, tcat, grow, gvar, grot, gcos, gsin,
        uc, want, close_tol, Xc, cosm, sinm, code_c, group_c,
    )  # fmt: skip
    resid_c = np.empty(m)
    _residual(vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, roww, Xc, cosm, sinm,
              resid_c)  # fmt: skip
    inv = np.empty((ng, 4, m))
    det_c = np.empty(m)
    rcond_c = np.empty(m)
    gdet_c = np.empty((ng, m))
    grc_c = np.empty((ng, m))
    _blocks(
        vl, dconst, lptr, lvec, lsgn, va, ccon, scon, con, col, roww, qscale, gptr, grows,
        parity, gkind, gloop, ga, gb, gflip, tcat, grow, gvar, sing_tol,
        Xc, cosm, sinm, inv, det_c, rcond_c, gdet_c, grc_c, code_c, group_c,
    )  # fmt: skip
    rates_c = np.empty((orders, n_var, m))
    zero = np.zeros(m)
    work = np.empty((5, m))
    for order in range(1, orders + 1):
        uk = _take(u1 if order == 1 else (u2 if order == 2 else u3), c0, m)
        _rates(
            vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, unk, inp, roww, qscale, gptr,
            grows, gcols, gkind, gloop, ga, gb, grow, gvar, order, uk, Xc, cosm, sinm, inv,
            rates_c, zero, work,
        )  # fmt: skip
    _mask(unk, orders, code_c, Xc, rates_c)
    P_c = np.empty((orders + 1, pptr.size - 1, m), dtype=np.complex128)
    for o in range(orders + 1):
        for j in range(pptr.size - 1):
            _point(
                vl, va, dconst, ccon, scon, pptr, pvec, psgn, o, j,
                Xc, cosm, sinm, rates_c, code_c, zero, work, P_c,
            )  # fmt: skip
    for i in range(m):
        code[c0 + i] = code_c[i]
        group[c0 + i] = group_c[i]
        det[c0 + i] = det_c[i]
        rcond[c0 + i] = rcond_c[i]
        resid[c0 + i] = resid_c[i]
    _put(X, Xc, c0)
    _put(gdet, gdet_c, c0)
    _put(grc, grc_c, c0)
    for o in range(orders):
        _put(rates[o], rates_c[o], c0)
    for o in range(orders + 1):
        _put(P[o], P_c[o], c0)


@_inline
def _take(a, c0, m):  # pragma: no cover - compiled
    """Columns ``c0 … c0 + m - 1`` of ``a`` (rows, N) as a new contiguous array."""
    out = np.empty((a.shape[0], m))
    for r in range(a.shape[0]):
        for i in range(m):
            out[r, i] = a[r, c0 + i]
    return out


@_inline
def _put(dst, src, c0):  # pragma: no cover - compiled
    """``src`` (rows, m) into the columns ``c0 …`` of ``dst`` (rows, N)."""
    for r in range(src.shape[0]):
        for i in range(src.shape[1]):
            dst[r, c0 + i] = src[r, i]


@_jit
def _start(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, col, unk, inp, angle_var,
    roww, qscale, gptr, grows, gcols, u, q0, tol, polish_from, tiny_step, max_iter,
    want, set_branch, sing_tol, first,
):  # fmt: skip
    """The first pose (step 0): False where it gives no branch.

    The pose goes into ``first`` (the guess where Newton fails) and, with
    ``set_branch``, its groups' determinant signs into ``want``.
    """
    nq = unk.size
    ng = gptr.size - 1
    x = np.empty(col.size)
    cosv = np.empty(col.size)
    sinv = np.empty(col.size)
    f0 = np.empty(roww.size)
    jac0 = np.empty((roww.size, nq + inp.size))
    inv0 = np.empty((nq, nq))
    step0 = np.empty(nq)
    gd0 = np.empty(ng)
    gr0 = np.empty(ng)
    worst0 = _first_pose(
        vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, col, unk, inp, angle_var,
        roww, qscale, gptr, grows, gcols, u, q0, tol, polish_from, tiny_step, max_iter,
        x, cosv, sinv, f0, jac0, inv0, gd0, gr0, step0,
    )  # fmt: skip
    if set_branch:
        if not worst0 >= 10.0 * sing_tol:
            return False
        for b in range(ng):
            want[b] = 1.0 if gd0[b] > 0.0 else -1.0
    for k in range(nq):
        first[k] = x[unk[k]] if worst0 >= 0.0 else q0[k]
    return True


@_jit
def _solve_groups(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, inp, angle_var,
    gkind, gloop, ga, gb, gflip, tcat, grow, gvar, grot, gcos, gsin,
    u, want, close_tol, X, cosm, sinm, code, group,
):  # fmt: skip
    """The inputs, then every group at every sample in solving order (step 1)."""
    n = u.shape[1]
    for i in range(n):
        code[i] = 0
        group[i] = -1
    for m in range(inp.size):
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
    for b in range(gkind.size):
        kind = gkind[b]
        if kind == 4:
            _linear_all(con, con0, grow[b], gvar[b], grot[b], gcos[b], gsin[b], angle_var,
                        X, cosm, sinm, kx)  # fmt: skip
            continue
        a = ga[b]
        v2 = gb[b]
        _dyad_terms(vl, va, dconst, ccon, scon, lptr, lvec, lsgn, tcat, kind, gloop[b],
                    X, cosm, sinm, kx, ky, pp, qq, ex, ey)  # fmt: skip
        sgn = want[b] * (-1.0 if gflip[b] else 1.0)
        if kind == 1:
            _angles_all(a, v2, sgn, close_tol, kx, ky, pp, qq, X, cosm, sinm, okf)
        elif kind == 2:
            _slide_all(a, v2, sgn, close_tol, kx, ky, pp, ex, ey, X, cosm, sinm, okf)
        else:
            _same_all(a, v2, sgn, kx, ky, pp, qq, X, cosm, sinm, okf)
        for i in range(n):
            if code[i] == 0 and not (okf[i] and X[a, i] == X[a, i] and X[v2, i] == X[v2, i]):
                code[i] = 1
                group[i] = b


@_jit
def _linear_all(con, con0, r, v0, rot, cd, sd, angle_var, X, cosm, sinm, acc):  # pragma: no cover
    """One constraint (row ``r``) solved for its one unknown ``v0`` at every sample."""
    n = X.shape[1]
    for i in range(n):
        acc[i] = con0[r]
    for v in range(X.shape[0]):
        cv = con[r, v]
        if v != v0 and cv != 0.0:
            for i in range(n):
                acc[i] += cv * X[v, i]
    c0 = con[r, v0]
    for i in range(n):
        X[v0, i] = -acc[i] / c0
    if rot >= 0:  # θ = θ_rot + δ: cos/sin by rotation
        for i in range(n):
            cosm[v0, i] = cosm[rot, i] * cd - sinm[rot, i] * sd
            sinm[v0, i] = sinm[rot, i] * cd + cosm[rot, i] * sd
    elif angle_var[v0]:
        for i in range(n):
            sinm[v0, i], cosm[v0, i] = sincos(X[v0, i])


@_jit
def _dyad_terms(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, tcat, kind, ell,
    X, cosm, sinm, kx, ky, pp, qq, ex, ey,
):  # fmt: skip
    """A dyad's loop ``ell`` at every sample: ``K`` (``kx``, ``ky``), ``P`` and ``Q`` or ``E``.

    See :func:`_dyad` for the parts; ``tcat`` says which term is which.
    """
    n = X.shape[1]
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
        cat = tcat[t]
        sd = s * dconst[k]
        if cat == 0:
            _accumulate(X, cosm, sinm, lv, va[k], s, sd, ccon[k], scon[k], kx, ky, n)
        elif cat == 1 or kind == 1:
            acc = pp if cat == 1 else qq
            if lv >= 0:
                for i in range(n):
                    acc[i] += s * X[lv, i]
            else:
                for i in range(n):
                    acc[i] += sd
        elif kind == 2:
            _accumulate(X, cosm, sinm, -1, va[k], s, s, ccon[k], scon[k], ex, ey, n)
        else:
            for i in range(n):
                qq[i] += s


@_jit
def _angles_all(a, v2, sgn, close_tol, kx, ky, pp, qq, X, cosm, sinm, okf):  # pragma: no cover
    """Two angles, ``P e^{ja} + Q e^{jb} = V = -K``, at every sample (branch-free loop)."""
    for i in range(X.shape[1]):
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


@_jit
def _slide_all(a, v2, sgn, close_tol, kx, ky, pp, ex, ey, X, cosm, sinm, okf):  # pragma: no cover
    """An angle and a slide, ``K + P e^{ja} + d E = 0``, at every sample."""
    for i in range(X.shape[1]):
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


@_jit
def _same_all(a, v2, sgn, kx, ky, pp, qq, X, cosm, sinm, okf):  # pragma: no cover - compiled
    """The angle and length of one vector, ``K + (S d + P) e^{ja} = 0``, at every sample."""
    for i in range(X.shape[1]):
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


@_jit
def _whole_turns(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, unk, inp, angle_var, uscale,
    gkind, gloop, ga, gb, gflip, tcat, grow, gvar, grot, gcos, gsin,
    u, first, want, close_tol, sub_step, X, code,
):  # fmt: skip
    """Each unknown angle within π of the last pose solved before it (step 2).

    Where the inputs moved by more than ``sub_step`` (scaled) since that pose,
    the reference is carried there by a walk of closed-form sub-steps. Angles a
    constraint fixes from the inputs or lengths are exact as they are.
    """
    n_var = X.shape[0]
    nu = inp.size
    free = np.ones(n_var, dtype=np.bool_)
    for m in range(nu):
        free[inp[m]] = False
    for b in range(gkind.size):
        if gkind[b] == 4 and (grot[b] < 0 or not free[grot[b]]):
            free[gvar[b]] = False
    ref = np.empty(n_var)
    x = np.empty(n_var)
    cosv = np.empty(n_var)
    sinv = np.empty(n_var)
    start = np.empty(nu)
    for k in range(unk.size):
        ref[unk[k]] = first[k]
    for m in range(nu):
        ref[inp[m]] = u[m, 0]
    prev_ok = False
    for i in range(u.shape[1]):
        if code[i] == 1:
            prev_ok = False
            continue
        span = 0.0
        for m in range(nu):
            span = max(span, abs(u[m, i] - ref[inp[m]]) / uscale[m])
        if prev_ok and span > sub_step:
            subs = int(span / sub_step) + 1
            for v in range(n_var):
                x[v] = ref[v]
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
        for k in range(unk.size):
            v = unk[k]
            if angle_var[v] and free[v]:
                X[v, i] = _near(X[v, i], ref[v])
            ref[v] = X[v, i]
        for m in range(nu):
            ref[inp[m]] = u[m, i]
        prev_ok = True


@_jit
def _residual(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, con0, roww, X, cosm, sinm, resid,
):  # fmt: skip
    """The largest weighted residual of every loop and constraint at every sample."""
    n = X.shape[1]
    n_loop = lptr.size - 1
    kx = np.empty(n)
    ky = np.empty(n)
    for i in range(n):
        resid[i] = 0.0
    for ell in range(n_loop):
        for i in range(n):
            kx[i] = 0.0
            ky[i] = 0.0
        for t in range(lptr[ell], lptr[ell + 1]):
            k = lvec[t]
            s = lsgn[t]
            _accumulate(
                X,
                cosm,
                sinm,
                vl[k],
                va[k],
                s,
                s * dconst[k],
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
        for v in range(X.shape[0]):
            if con[r, v] != 0.0:
                cv = con[r, v]
                for i in range(n):
                    kx[i] += cv * X[v, i]
        w = roww[2 * n_loop + r]
        for i in range(n):
            resid[i] = max(resid[i], abs(kx[i]) * w)


@_jit
def _blocks(  # pragma: no cover - compiled
    vl, dconst, lptr, lvec, lsgn, va, ccon, scon, con, col, roww, qscale, gptr, grows,
    parity, gkind, gloop, ga, gb, gflip, tcat, grow, gvar, sing_tol,
    X, cosm, sinm, inv, det, rcond, gdet, grc, code, group,
):  # fmt: skip
    """Each group's block of ``J_q`` inverted, its det and pivot ratio; toggles flagged."""
    n = X.shape[1]
    pp = np.empty(n)
    qq = np.empty(n)
    ex = np.empty(n)
    ey = np.empty(n)
    for i in range(n):
        rcond[i] = 1.0
        det[i] = parity
    for b in range(gkind.size):
        kind = gkind[b]
        if kind == 4:
            a0 = con[grow[b], gvar[b]]
            for i in range(n):
                gdet[b, i] = a0
                grc[b, i] = 1.0 if a0 != 0.0 else 0.0
        else:
            _own_terms(vl, dconst, lptr, lvec, lsgn, va, ccon, scon, tcat, kind, gloop[b],
                       X, cosm, sinm, pp, qq, ex, ey)  # fmt: skip
            r0 = grows[gptr[b]]
            _block(b, kind, ga[b], gb[b], gflip[b], roww[r0], roww[r0 + 1], qscale[col[ga[b]]],
                   qscale[col[gb[b]]], X, cosm, sinm, pp, qq, ex, ey, inv, gdet, grc)  # fmt: skip
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


@_jit
def _own_terms(  # pragma: no cover - compiled
    vl, dconst, lptr, lvec, lsgn, va, ccon, scon, tcat, kind, ell, X, cosm, sinm, pp, qq, ex, ey,
):  # fmt: skip
    """A dyad's own coefficients at every sample: ``P`` (plus ``S`` for kind 3), ``Q`` or ``E``."""
    n = X.shape[1]
    for i in range(n):
        pp[i] = 0.0
        qq[i] = 0.0
        ex[i] = 0.0
        ey[i] = 0.0
    for t in range(lptr[ell], lptr[ell + 1]):
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


@_jit
def _block(  # pragma: no cover - compiled
    b, kind, a, v2, flip, w0, w1, qa, qb, X, cosm, sinm, pp, qq, ex, ey, inv, gdet, grc,
):  # fmt: skip
    """Dyad ``b``'s scaled 2x2 block of ``J_q`` inverted into ``inv[b]``, at every sample.

    Column of ``a``: j (P [+ S d]) e^{ja}; of ``v2``: j Q e^{jb} | E | S e^{ja}
    (kinds 1, 2, 3), in the group's column order ((v2, a) where ``flip``).
    """
    unscale = 1.0 / (w0 * w1 * qa * qb)
    for i in range(X.shape[1]):
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
        s00 = ax * w0 * qa
        s10 = ay * w1 * qa
        s01 = bx * w0 * qb
        s11 = by * w1 * qb
        if flip:
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


@_jit
def _rates(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, con, unk, inp, roww, qscale, gptr,
    grows, gcols, gkind, gloop, ga, gb, grow, gvar, order, uk, X, cosm, sinm, inv, rates,
    zero, work,
):  # fmt: skip
    """The ``order``-th derivative of every variable, group by group (step 4).

    Each group's block solved for its unknowns' highest derivative, everything
    else of its loop known (the lower orders and earlier groups). ``zero``: zeros,
    ``work``: scratch (5, N).
    """
    n = X.shape[1]
    out = rates[order - 1]
    for m in range(inp.size):
        for i in range(n):
            out[inp[m], i] = uk[m, i]
    kx = work[3]
    ky = work[4]
    for b in range(gkind.size):
        if gkind[b] == 4:  # linear: no lower-order terms
            r = grow[b]
            v0 = gvar[b]
            for i in range(n):
                kx[i] = 0.0
            for v in range(X.shape[0]):
                if v != v0 and con[r, v] != 0.0:
                    cv = con[r, v]
                    for i in range(n):
                        kx[i] += cv * out[v, i]
            c0 = -1.0 / con[r, v0]
            for i in range(n):
                out[v0, i] = kx[i] * c0
            continue
        _known_rates(vl, va, dconst, ccon, scon, lptr, lvec, lsgn, gloop[b], ga[b], gb[b],
                     order, X, cosm, sinm, rates, kx, ky, zero, work)  # fmt: skip
        p0 = gptr[b]
        r0 = grows[p0]
        w0 = -roww[r0]
        w1 = -roww[r0 + 1]
        x0 = unk[gcols[p0]]
        x1 = unk[gcols[p0 + 1]]
        q0s = qscale[gcols[p0]]
        q1s = qscale[gcols[p0 + 1]]
        for i in range(n):
            t0 = kx[i] * w0
            t1 = ky[i] * w1
            out[x0, i] = (inv[b, 0, i] * t0 + inv[b, 1, i] * t1) * q0s
            out[x1, i] = (inv[b, 2, i] * t0 + inv[b, 3, i] * t1) * q1s


@_jit
def _known_rates(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, lptr, lvec, lsgn, ell, a, v2, order,
    X, cosm, sinm, rates, kx, ky, zero, work,
):  # fmt: skip
    """The known part of loop ``ell``'s ``order``-th derivative, into ``kx``, ``ky``.

    Every term's derivative of ``s d e^{jθ}`` (DESIGN.md) but the group's own
    unknowns' highest derivatives (``a``, ``v2``).
    """
    n = X.shape[1]
    out = rates[order - 1]
    fill_d = work[0]
    fill_c = work[1]
    fill_s = work[2]
    for i in range(n):
        kx[i] = 0.0
        ky[i] = 0.0
    for t in range(lptr[ell], lptr[ell + 1]):
        k = lvec[t]
        s = lsgn[t]
        lv = vl[k]
        av = va[k]
        dd = X[lv] if lv >= 0 else _filled(fill_d, dconst[k])
        co = cosm[av] if av >= 0 else _filled(fill_c, ccon[k])
        si = sinm[av] if av >= 0 else _filled(fill_s, scon[k])
        # the known highest derivatives: s (d⁽ᵏ⁾ + j d θ⁽ᵏ⁾) e^{jθ}
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


@_inline
def _filled(arr, value):  # pragma: no cover - compiled
    """``arr`` filled with ``value`` (a constant length or direction over the samples)."""
    for i in range(arr.size):
        arr[i] = value
    return arr


@_jit
def _mask(unk, orders, code, X, rates):  # pragma: no cover - compiled
    """NaN where there is no pose (the unknowns), and no rates where the pose is not ok."""
    for i in range(X.shape[1]):
        if code[i] == 1:
            for k in range(unk.size):
                X[unk[k], i] = math.nan
        if code[i] != 0:
            for o in range(orders):
                for v in range(X.shape[0]):
                    rates[o, v, i] = math.nan


@_jit
def _point(  # pragma: no cover - compiled
    vl, va, dconst, ccon, scon, pptr, pvec, psgn, o, j, X, cosm, sinm, rates, code, zero, work, P,
):  # fmt: skip
    """Point ``j``'s ``o``-th derivative (its vector chain's, DESIGN.md) into ``P[o, j]``.

    NaN where the pose (for the rates: the sample) is not there, as the variables.
    """
    n = X.shape[1]
    fill_d = work[0]
    fill_c = work[1]
    fill_s = work[2]
    re_ = work[3]
    im_ = work[4]
    for i in range(n):
        re_[i] = 0.0
        im_[i] = 0.0
    for t in range(pptr[j], pptr[j + 1]):
        k = pvec[t]
        s = psgn[t]
        lv = vl[k]
        av = va[k]
        dd = X[lv] if lv >= 0 else _filled(fill_d, dconst[k])
        co = cosm[av] if av >= 0 else _filled(fill_c, ccon[k])
        si = sinm[av] if av >= 0 else _filled(fill_s, scon[k])
        d1 = rates[0, lv] if o >= 1 and lv >= 0 else zero
        w1 = rates[0, av] if o >= 1 and av >= 0 else zero
        d2 = rates[1, lv] if o >= 2 and lv >= 0 else zero
        w2 = rates[1, av] if o >= 2 and av >= 0 else zero
        d3 = rates[2, lv] if o >= 3 and lv >= 0 else zero
        w3 = rates[2, av] if o >= 3 and av >= 0 else zero
        for i in range(n):
            w = w1[i]
            if o == 0:
                rr = dd[i]
                ii = 0.0
            elif o == 1:
                rr = d1[i]
                ii = dd[i] * w
            elif o == 2:
                rr = d2[i] - dd[i] * w * w
                ii = dd[i] * w2[i] + 2.0 * d1[i] * w
            else:
                rr = d3[i] - 3.0 * d1[i] * w * w - 3.0 * dd[i] * w * w2[i]
                ii = dd[i] * w3[i] + 3.0 * d1[i] * w2[i] + 3.0 * d2[i] * w - dd[i] * w * w * w
            re_[i] += s * (rr * co[i] - ii * si[i])
            im_[i] += s * (rr * si[i] + ii * co[i])
    for i in range(n):
        if code[i] == 1 or (o > 0 and code[i] != 0):
            P[o, j, i] = complex(math.nan, math.nan)
        else:
            P[o, j, i] = complex(re_[i], im_[i])
