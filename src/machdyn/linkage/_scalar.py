"""One pose of a linkage's closed-form program, in plain Python (complex scalars).

A single pose is what an editor solves on every mouse move; NumPy's cost per
call (hundreds of array operations on one element) would dominate it, and the
compiled kernel (:mod:`machdyn._linkage_kernels`) is loaded only when the jit
rule says it pays. This is the same program (:func:`machdyn.linkage.kernel.encode`)
run sample by sample with Python's complex numbers: a driver places its link;
a dyad's pin is a circle–circle, circle–line or line–line meet with the drawn
assembly sign; every derivative order is the same 2 × 2 system (Cramer). The
tests run every single-pose solve through it and compare with NumPy.

State of link ``i`` (index 0 is the ground: zeros, ``E = 1``): origin ``Og``,
rotation ``E = e^{jΔ}`` and its angle ``A`` (Δ, wrapped where it comes from an
``atan2``), rates ``V[k·nl + i]`` (origin) and ``W[k·nl + i]`` (angle) for the
orders kept (k = 0, 1, 2: velocity, acceleration, jerk).
"""

from __future__ import annotations

import math


def _jit(f):  # the functions are plain Python: the decorators only mark their roles
    return f


_inline = _jit

# opcodes (machdyn.linkage.program.encode) and status codes (machdyn.linkage.program)
CRANK, MOTOR, SLIDE, DYAD, RPR, RPP = 0, 1, 2, 3, 4, 5
OK, NO_ASSEMBLY, SINGULAR = 0, 1, 2
SINGULAR_SINE = 1e-4
#: Integers and floats per step row.
NI, NF = 10, 16


@_inline
def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


@_inline
def _prates(Og, E, V, W, nl, i, r):
    """Position and three rates of the material point ``r`` (drawn offset) of link ``i``.

    ``nl`` is the number of links times the state's order sign: the rates past
    the order kept in ``V`` and ``W`` (``W`` holds only as many) are not computed.
    """
    q = r * E[i]
    p1 = p2 = p3 = 0j
    n3 = len(W)
    if n3 > 0:
        w = W[i]
        p1 = V[i] + 1j * w * q
        if n3 > nl:
            al = W[nl + i]
            p2 = V[nl + i] + (1j * al - w * w) * q
            if n3 > 2 * nl:
                z = W[2 * nl + i]
                p3 = V[2 * nl + i] + (1j * z - 3.0 * w * al - 1j * w * w * w) * q
    return Og[i] + q, p1, p2, p3


@_inline
def _place(Og, E, A, V, W, nl, i, P0, P1, P2, P3, r, e, a, w1, w2, w3):
    """Place link ``i`` from one of its points (drawn offset ``r``) at ``P`` with rates."""
    E[i] = e
    A[i] = a
    q = -r * e
    Og[i] = P0 + q
    n3 = len(W)
    if n3 > 0:
        W[i] = w1
        V[i] = P1 + 1j * w1 * q
        if n3 > nl:
            W[nl + i] = w2
            V[nl + i] = P2 + (1j * w2 - w1 * w1) * q
            if n3 > 2 * nl:
                W[2 * nl + i] = w3
                V[2 * nl + i] = P3 + (1j * w3 - 3.0 * w1 * w2 - 1j * w1 * w1 * w1) * q


@_inline
def _w(W, nl, k, i):
    """Rate k (0: ω, 1: α, 2: ζ) of link i's angle, 0 past the order kept."""
    j = k * nl + i
    return W[j] if j < len(W) else 0.0


@_inline
def _p_term(k, s0, s1, s2, u, w1, w2, w3):
    """Order-k rate of ``s û`` without its ``s⁽ᵏ⁾ û`` part (``û`` turning at w1, w2, w3)."""
    if k == 1:
        return 1j * s0 * w1 * u
    if k == 2:
        return (2j * s1 * w1 + s0 * (1j * w2 - w1 * w1)) * u
    return (
        3j * s2 * w1 + 3.0 * s1 * (1j * w2 - w1 * w1) + s0 * (1j * w3 - 3.0 * w1 * w2 - 1j * w1**3)
    ) * u


@_inline
def _r_term(k, L0, L1, L2, L3, e, w1, w2):
    """Order-k rate of ``L ê`` without its ``j L φ⁽ᵏ⁾ ê`` part (``ê`` turning at w1, w2)."""
    if k == 1:
        return L1 * e
    if k == 2:
        return (L2 - L0 * w1 * w1 + 2j * L1 * w1) * e
    return (
        L3
        - 3.0 * L1 * w1 * w1
        - 3.0 * L0 * w1 * w2
        + 1j * (3.0 * L2 * w1 + 3.0 * L1 * w2 - L0 * w1**3)
    ) * e


@_inline
def _status(ok, c1, c2):
    if not ok:
        return NO_ASSEMBLY
    n = abs(c1) * abs(c2)
    if not (abs(_cross(c1.real, c1.imag, c2.real, c2.imag)) >= SINGULAR_SINE * n):
        return SINGULAR
    return OK


@_inline
def _pair(c1, c2, k):
    """Real x1, x2 with c1 x1 + c2 x2 = k (Cramer); NaN when singular."""
    det = _cross(c1.real, c1.imag, c2.real, c2.imag)
    if det == 0.0:
        return math.nan, math.nan
    return (
        _cross(k.real, k.imag, c2.real, c2.imag) / det,
        _cross(c1.real, c1.imag, k.real, k.imag) / det,
    )


@_inline
def sample(pi, pf, ns, u, order, Og, E, A, V, W, nl, codes):
    """Run the program's ``ns`` steps for one sample; ``u[4·d + k]`` is driver d's k-th rate."""
    for s in range(ns):
        ib, fb = s * NI, s * NF
        op, g = pi[ib], pi[ib + 1]
        code = OK
        if op == CRANK:
            L, K, d = pi[ib + 2], pi[ib + 3], pi[ib + 4]
            delta = u[4 * d] - pf[fb + 4]
            e = complex(math.cos(delta), math.sin(delta))
            P0, P1, P2, P3 = _prates(Og, E, V, W, nl, K, complex(pf[fb], pf[fb + 1]))
            r = complex(pf[fb + 2], pf[fb + 3])
            _place(Og, E, A, V, W, nl, L, P0, P1, P2, P3, r, e, delta,
                   u[4 * d + 1], u[4 * d + 2], u[4 * d + 3])  # fmt: skip
        elif op == MOTOR:
            L, K, S, d = pi[ib + 2], pi[ib + 3], pi[ib + 4], pi[ib + 5]
            sg = pf[fb + 4]
            delta = sg * (u[4 * d] - pf[fb + 5])
            e = E[S] * complex(math.cos(delta), math.sin(delta))
            P0, P1, P2, P3 = _prates(Og, E, V, W, nl, K, complex(pf[fb], pf[fb + 1]))
            r = complex(pf[fb + 2], pf[fb + 3])
            _place(Og, E, A, V, W, nl, L, P0, P1, P2, P3, r, e, A[S] + delta,
                   _w(W, nl, 0, S) + sg * u[4 * d + 1], _w(W, nl, 1, S) + sg * u[4 * d + 2],
                   _w(W, nl, 2, S) + sg * u[4 * d + 3])  # fmt: skip
        elif op == SLIDE:
            L, K, Lf, La, d, block = (
                pi[ib + 2],
                pi[ib + 3],
                pi[ib + 4],
                pi[ib + 5],
                pi[ib + 6],
                pi[ib + 7],
            )
            uh = complex(pf[fb + 4], pf[fb + 5]) * E[K]
            w1, w2, w3 = _w(W, nl, 0, K), _w(W, nl, 1, K), _w(W, nl, 2, K)
            d0, d1, d2, d3 = u[4 * d], u[4 * d + 1], u[4 * d + 2], u[4 * d + 3]
            sg = 1.0 if block == 1 else -1.0
            if block == 1:
                B0, B1, B2, B3 = _prates(Og, E, V, W, nl, Lf, complex(pf[fb], pf[fb + 1]))
                r = complex(pf[fb + 2], pf[fb + 3])
            else:
                B0, B1, B2, B3 = _prates(Og, E, V, W, nl, La, complex(pf[fb + 2], pf[fb + 3]))
                r = complex(pf[fb], pf[fb + 1])
            P0 = B0 + sg * d0 * uh
            P1 = B1 + sg * (_p_term(1, d0, d1, d2, uh, w1, w2, w3) + d1 * uh)
            P2 = B2 + sg * (_p_term(2, d0, d1, d2, uh, w1, w2, w3) + d2 * uh)
            P3 = B3 + sg * (_p_term(3, d0, d1, d2, uh, w1, w2, w3) + d3 * uh)
            _place(Og, E, A, V, W, nl, L, P0, P1, P2, P3, r, E[K], A[K], w1, w2, w3)
        elif op == DYAD:
            code = _dyad(pi, pf, ib, fb, u, order, Og, E, A, V, W, nl)
        elif op == RPR:
            code = _rpr(pi, pf, ib, fb, order, Og, E, A, V, W, nl)
        else:
            code = _rpp(pi, pf, ib, fb, order, Og, E, A, V, W, nl)
        codes[g] = code


@_inline
def _arm(pi, pf, ib, fb, u, Og, E, V, W, nl):
    """An arm's base point (pivot or line point) with rates, its length and direction."""
    kind, c, drv = pi[ib], pi[ib + 1], pi[ib + 3]
    b0, b1, b2, b3 = _prates(Og, E, V, W, nl, c, complex(pf[fb], pf[fb + 1]))
    if kind == 0:  # R: length (driven: an actuator's) and its rates
        if drv >= 0:
            return b0, b1, b2, b3, u[4 * drv], u[4 * drv + 1], u[4 * drv + 2], u[4 * drv + 3], 0j
        return b0, b1, b2, b3, pf[fb + 6], 0.0, 0.0, 0.0, 0j
    uh = complex(pf[fb + 4], pf[fb + 5]) * E[c]
    return b0, b1, b2, b3, 0.0, 0.0, 0.0, 0.0, uh


@_inline
def _dyad(pi, pf, ib, fb, u, order, Og, E, A, V, W, nl):
    """RRR, RRP, PRR or PRP: two arms meeting at the pin ``B``."""
    k1, k2 = pi[ib + 2], pi[ib + 6]
    sign = pf[fb + 14]
    a0, a1, a2, a3, La0, La1, La2, La3, ua = _arm(pi, pf, ib + 2, fb, u, Og, E, V, W, nl)
    b0, b1, b2, b3, Lb0, Lb1, Lb2, Lb3, ub = _arm(pi, pf, ib + 6, fb + 7, u, Og, E, V, W, nl)
    ok = True
    if k1 == 0 and k2 == 0:
        ac = b0 - a0
        d2 = ac.real * ac.real + ac.imag * ac.imag
        d = math.sqrt(d2)
        x = (La0 * La0 - Lb0 * Lb0 + d2) / (2.0 * d) if d > 0 else math.nan
        h2 = (La0 - x) * (La0 + x)
        ok = h2 >= -1e-14 * La0 * La0 and d > 0
        B = (
            a0 + (x + 1j * sign * math.sqrt(max(h2, 0.0))) * (ac / d)
            if ok
            else complex(math.nan, math.nan)
        )
    elif k1 == 0 or k2 == 0:
        if k1 == 0:
            P, L, G, uh = a0, La0, b0, ub
        else:
            P, L, G, uh = b0, Lb0, a0, ua
        w = (G - P) * uh.conjugate()
        disc = (L - w.imag) * (L + w.imag)
        ok = disc >= -1e-14 * L * L
        s = -w.real + sign * math.sqrt(max(disc, 0.0))
        B = G + s * uh if ok else complex(math.nan, math.nan)
    else:
        s1, _ = _pair(ua, -ub, b0 - a0)
        B = a0 + s1 * ua
        ok = not math.isnan(s1)
    # each arm's unknown: its angle (R) or its slide s (P); coefficients of the rate systems
    if k1 == 0:
        va = B - a0
        c1 = 1j * va
        ea = va / abs(va)
    else:
        c1 = ua
        ea = 0j
    if k2 == 0:
        vb = B - b0
        c2 = 1j * vb
        eb = vb / abs(vb)
    else:
        c2 = ub
        eb = 0j
    code = _status(ok, c1, c2)
    xa = ((B - a0) * ua.conjugate()).real if k1 == 1 else 0.0
    xb = ((B - b0) * ub.conjugate()).real if k2 == 1 else 0.0
    xa1 = xa2 = xa3 = xb1 = xb2 = xb3 = 0.0
    B1 = B2 = B3 = 0j
    Ka, Kb = pi[ib + 3], pi[ib + 7]  # the known link of a P arm (its rotation)
    for k in range(1, order + 1):
        if k1 == 0:
            kna = _r_term(k, La0, La1, La2, La3, ea, xa1, xa2)
        else:
            kna = _p_term(k, xa, xa1, xa2, ua, _w(W, nl, 0, Ka), _w(W, nl, 1, Ka), _w(W, nl, 2, Ka))
        if k2 == 0:
            knb = _r_term(k, Lb0, Lb1, Lb2, Lb3, eb, xb1, xb2)
        else:
            knb = _p_term(k, xb, xb1, xb2, ub, _w(W, nl, 0, Kb), _w(W, nl, 1, Kb), _w(W, nl, 2, Kb))
        base_a = a1 if k == 1 else a2 if k == 2 else a3
        base_b = b1 if k == 1 else b2 if k == 2 else b3
        ka, kb = base_a + kna, base_b + knb
        x1, x2 = _pair(c1, -c2, kb - ka)
        Bk = ka + c1 * x1
        if k == 1:
            xa1, xb1, B1 = x1, x2, Bk
        elif k == 2:
            xa2, xb2, B2 = x1, x2, Bk
        else:
            xa3, xb3, B3 = x1, x2, Bk
    _set_arm(pi, pf, ib + 2, fb, k1, B, B1, B2, B3, a0, xa1, xa2, xa3, Og, E, A, V, W, nl)
    _set_arm(pi, pf, ib + 6, fb + 7, k2, B, B1, B2, B3, b0, xb1, xb2, xb3, Og, E, A, V, W, nl)
    return code


@_inline
def _set_arm(pi, pf, ib, fb, kind, B, B1, B2, B3, base, x1, x2, x3, Og, E, A, V, W, nl):
    link = pi[ib + 2]
    if link < 0:
        return
    r = complex(pf[fb + 2], pf[fb + 3])
    if kind == 0:
        e = (B - base) / complex(pf[fb + 4], pf[fb + 5])
        _place(
            Og, E, A, V, W, nl, link, B, B1, B2, B3, r, e, math.atan2(e.imag, e.real), x1, x2, x3
        )
    else:
        K = pi[ib + 1]
        _place(
            Og,
            E,
            A,
            V,
            W,
            nl,
            link,
            B,
            B1,
            B2,
            B3,
            r,
            E[K],
            A[K],
            _w(W, nl, 0, K),
            _w(W, nl, 1, K),
            _w(W, nl, 2, K),
        )


@_inline
def _rpr(pi, pf, ib, fb, order, Og, E, A, V, W, nl):
    L1, KA, KC, L2 = pi[ib + 2], pi[ib + 3], pi[ib + 4], pi[ib + 5]
    a0, a1, a2, a3 = _prates(Og, E, V, W, nl, KA, complex(pf[fb], pf[fb + 1]))
    c0, cc1, cc2, cc3 = _prates(Og, E, V, W, nl, KC, complex(pf[fb + 4], pf[fb + 5]))
    e_off, sign = pf[fb + 8], pf[fb + 11]
    w = c0 - a0
    rr = abs(w)
    disc = (rr - e_off) * (rr + e_off)
    ok = disc >= -1e-14 * rr * rr and rr > 0
    t = sign * math.sqrt(max(disc, 0.0))
    uh = w / complex(t, e_off) if ok and (t != 0 or e_off != 0) else complex(math.nan, math.nan)
    c1, c2 = 1j * w, uh
    code = _status(ok, c1, c2)
    om1 = om2 = om3 = t1 = t2 = 0.0
    for k in range(1, order + 1):
        if k == 1:
            rhs = cc1 - a1
        elif k == 2:
            rhs = cc2 - a2 - 2j * t1 * om1 * uh + om1 * om1 * w
        else:
            rhs = (
                cc3
                - a3
                - (3j * t2 * om1 + 3j * t1 * om2 - 3.0 * t1 * om1 * om1) * uh
                + (3.0 * om1 * om2 + 1j * om1 * om1 * om1) * w
            )
        x1, x2 = _pair(c1, c2, rhs)
        if k == 1:
            om1, t1 = x1, x2
        elif k == 2:
            om2, t2 = x1, x2
        else:
            om3 = x1
    e = uh / complex(pf[fb + 9], pf[fb + 10])
    ang = math.atan2(e.imag, e.real)
    _place(Og, E, A, V, W, nl, L1, a0, a1, a2, a3, complex(pf[fb + 2], pf[fb + 3]), e, ang,
           om1, om2, om3)  # fmt: skip
    if L2 >= 0:
        _place(Og, E, A, V, W, nl, L2, c0, cc1, cc2, cc3, complex(pf[fb + 6], pf[fb + 7]), e, ang,
               om1, om2, om3)  # fmt: skip
    return code


@_inline
def _rpp(pi, pf, ib, fb, order, Og, E, A, V, W, nl):
    L1, KA, K, L2 = pi[ib + 2], pi[ib + 3], pi[ib + 4], pi[ib + 5]
    a0, a1, a2, a3 = _prates(Og, E, V, W, nl, KA, complex(pf[fb], pf[fb + 1]))
    g0, g1, g2, g3 = _prates(Og, E, V, W, nl, K, complex(pf[fb + 4], pf[fb + 5]))
    e = E[K]
    u1 = complex(pf[fb + 6], pf[fb + 7]) * e
    u2 = complex(pf[fb + 8], pf[fb + 9]) * e
    w1, w2, w3 = _w(W, nl, 0, K), _w(W, nl, 1, K), _w(W, nl, 2, K)
    s1, s2 = _pair(u1, u2, a0 - g0)
    code = _status(not math.isnan(s1), u1, u2)
    X0 = g0 + s2 * u2
    X1 = X2 = X3 = 0j
    p1 = p2 = q1 = q2 = 0.0
    for k in range(1, order + 1):
        pt2 = _p_term(k, s2, q1, q2, u2, w1, w2, w3)
        base = a1 - g1 if k == 1 else a2 - g2 if k == 2 else a3 - g3
        gk = g1 if k == 1 else g2 if k == 2 else g3
        rhs = base - _p_term(k, s1, p1, p2, u1, w1, w2, w3) - pt2
        x1, x2 = _pair(u1, u2, rhs)
        Xk = gk + pt2 + x2 * u2
        if k == 1:
            p1, q1, X1 = x1, x2, Xk
        elif k == 2:
            p2, q2, X2 = x1, x2, Xk
        else:
            X3 = Xk
    _place(Og, E, A, V, W, nl, L2, X0, X1, X2, X3, complex(pf[fb + 10], pf[fb + 11]), e, A[K],
           w1, w2, w3)  # fmt: skip
    if L1 >= 0:
        _place(Og, E, A, V, W, nl, L1, a0, a1, a2, a3, complex(pf[fb + 2], pf[fb + 3]), e, A[K],
               w1, w2, w3)  # fmt: skip
    return code


@_inline
def outputs(i, Og, E, A, V, W, nl, order, links, pts_i, pts_f, lens_i, lens_f,
            ang_out, rot_out, pts_out, len_out):  # fmt: skip
    """Write sample ``i``: angles and rates of ``links``, points (and centres of mass), lengths."""
    nlk = len(links)
    for j in range(nlk):
        L = links[j]
        ang_out[j, i] = A[L]
        for k in range(order):
            rot_out[k * nlk + j, i] = W[k * nl + L]
    npt = len(pts_i)
    for p in range(npt):
        P0, P1, P2, P3 = _prates(Og, E, V, W, nl, pts_i[p], complex(pts_f[2 * p], pts_f[2 * p + 1]))
        pts_out[p, i] = P0
        if order >= 1:
            pts_out[npt + p, i] = P1
        if order >= 2:
            pts_out[2 * npt + p, i] = P2
        if order >= 3:
            pts_out[3 * npt + p, i] = P3
    nln = len(lens_i) // 4
    for q in range(nln):
        kind, a, b, guide = lens_i[4 * q], lens_i[4 * q + 1], lens_i[4 * q + 2], lens_i[4 * q + 3]
        f = 6 * q
        S0, S1, S2, S3 = _prates(Og, E, V, W, nl, a, complex(lens_f[f], lens_f[f + 1]))
        T0, T1, T2, T3 = _prates(Og, E, V, W, nl, b, complex(lens_f[f + 2], lens_f[f + 3]))
        r0, r1, r2, r3 = T0 - S0, T1 - S1, T2 - S2, T3 - S3
        if kind == 0:  # a slider or slot: displacement along the guide's line
            uh = complex(lens_f[f + 4], lens_f[f + 5]) * E[guide]
            w, al = _w(W, nl, 0, guide), _w(W, nl, 1, guide)
            d0 = (r0 * uh.conjugate()).real
            d1 = (r1 * uh.conjugate()).real
            d2 = (r2 * uh.conjugate()).real + d0 * w * w
            d3 = (r3 * uh.conjugate()).real + 3.0 * d1 * w * w + 3.0 * d0 * w * al
        else:  # an actuator: its length
            d0 = abs(r0)
            e = r0 / d0 if d0 > 0 else complex(math.nan, math.nan)
            c1, c2, c3 = r1 * e.conjugate(), r2 * e.conjugate(), r3 * e.conjugate()
            p1 = c1.imag / d0
            d1 = c1.real
            p2 = (c2.imag - 2.0 * d1 * p1) / d0
            d2 = c2.real + d0 * p1 * p1
            d3 = c3.real + 3.0 * d1 * p1 * p1 + 3.0 * d0 * p1 * p2
        len_out[q, i] = d0
        if order >= 1:
            len_out[nln + q, i] = d1
        if order >= 2:
            len_out[2 * nln + q, i] = d2
        if order >= 3:
            len_out[3 * nln + q, i] = d3
