"""Compiled (numba) helpers of the vector-loop kernel for one pose at a time.

:func:`_first_pose` finds a sweep's first pose by Newton from the guess (as the
NumPy path does); :func:`_pose` puts every group of a pose on the sweep's
branch in closed form (used by :mod:`machdyn.loops._kernels` to walk a long
input step in sub-steps and so keep every angle's whole turn). The dyads'
closed forms are :func:`_dyad`'s (the law of cosines, a circle–line meet, a
vector's own angle and length; Norton, *Design of Machinery*, §4.5).
"""

from __future__ import annotations

import math

from .._numba_cache import njit

__all__: list[str] = []

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
            vl,
            va,
            dconst,
            ccon,
            scon,
            lptr,
            lvec,
            lsgn,
            con,
            con0,
            col,
            x,
            cosv,
            sinv,
            f,
            jac,
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
    if kind == 1:
        return _put_angles(a, v2, flip, kx, ky, p, qq, x, cosv, sinv, want, close_tol)
    if kind == 2:
        return _put_slide(a, v2, flip, kx, ky, p, ex, ey, x, cosv, sinv, want, close_tol)
    return _put_same(a, v2, flip, kx, ky, p, qq, x, cosv, sinv, want)


@_inline
def _put_angles(a, v2, flip, kx, ky, p, qq, x, cosv, sinv, want, close_tol):  # pragma: no cover
    """Two angles: ``P e^{ja} + Q e^{jb} = V = -K`` at the root of sign ``want``."""
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


@_inline
def _put_slide(a, v2, flip, kx, ky, p, ex, ey, x, cosv, sinv, want, close_tol):  # pragma: no cover
    """An angle and a slide: ``K + P e^{ja} + d E = 0`` at the root of sign ``want``."""
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


@_inline
def _put_same(a, v2, flip, kx, ky, p, qq, x, cosv, sinv, want):  # pragma: no cover - compiled
    """The angle and length of one vector: ``K + (S d + P) e^{ja} = 0``, sign ``want``."""
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
                con,
                con0,
                grow[b],
                gvar[b],
                grot[b],
                gcos[b],
                gsin[b],
                angle_var,
                x,
                cosv,
                sinv,
            )
        elif not _dyad(
            vl, va, dconst, ccon, scon, lptr, lvec, lsgn, gkind[b],
            gloop[b], ga[b], gb[b], gflip[b], tcat, x, cosv, sinv, want[b], close_tol,
        ):  # fmt: skip
            return b
    return -1
