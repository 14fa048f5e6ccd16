"""The six-bar's design, its coupler point with derivatives, its refinement, its Linkage.

The design of a placed six-bar is 15 numbers, ``x = (O2x, O2y, θ1, r1, r2, r3,
r4, cu, cv, du, dv, a, b, pu, pv)`` (see :mod:`machdyn.synthesis.sixbar`), plus
the assembly signs, the topology and the coupler link, which stay as retrieved.
The coupler point is built in the plane by the same steps as the atlas —
the crank pin, two RRR dyads, points in link frames — and its derivatives are
carried along each step (forward mode, analytic): an RRR dyad's pin ``E``
with ``|E − C| = a``, ``|E − D| = b`` moves by the ``dE`` that solves
``Re(conj(E − C)(dE − dC)) = a da`` and ``Re(conj(E − D)(dE − dD)) = b db``
(the circle equations differentiated; Cramer's rule). The refinement
(:func:`refine_sixbar`) is Levenberg–Marquardt with geodesic acceleration on the
real distances; the compiled kernels (:mod:`machdyn.synthesis._sixbar_kernels`)
take the same steps faster. :func:`sixbar_linkage` draws a design as a
:class:`~machdyn.linkage.Linkage` in the plane.

Used by :mod:`~machdyn.synthesis.sixbar_path` (the synthesis: its fits, their
polish and the Linkage's check) and :mod:`~machdyn.synthesis._sixbar_starts` (the
starts and the loop-by-loop fits); imports neither.
"""

from __future__ import annotations

import numpy as np

from .sixbar import TOPOLOGIES

# Internal to machdyn.synthesis (see machdyn.synthesis.sixbar_path).
__all__: list[str] = []

_NP = 15  # design numbers
_STEEP = 1e10  # a coupler point moving this much faster than its design numbers: at a toggle
#: The refinement's least damping of an unknown, as a share of the largest diagonal of JᵀJ
#: (Marquardt scales each unknown's damping by its own diagonal). Without a floor well above
#: rounding, an unknown the targets barely feel — the crank angle of a target where the
#: coupler point stands still, at the turn of a Watt II "1-4" rocker — takes wild steps:
#: from untimed truths disturbed by 1 %, 5 of 16 such six-bars converged with 1e-12 and
#: 15 of 16 with 1e-6 (the 16th to 6e-11).
DAMPING_FLOOR = 1e-6


class _D:
    """A complex value per target with its gradient (targets, 15 design numbers + θ)."""

    __slots__ = ("g", "v")

    def __init__(self, v, g):
        self.v, self.g = v, g

    def __add__(self, o):
        return _D(self.v + o.v, self.g + o.g)

    def __sub__(self, o):
        return _D(self.v - o.v, self.g - o.g)

    def __mul__(self, o):
        return _D(self.v * o.v, self.g * o.v[:, None] + self.v[:, None] * o.g)


def _param(x, i, k, imag=False):
    g = np.zeros((k, _NP + 1), complex)
    g[:, i] = 1j if imag else 1.0
    return _D(np.full(k, x[i] * (1j if imag else 1.0)), g)


def _expi(phi: _D) -> _D:
    e = np.exp(1j * phi.v.real)
    return _D(e, 1j * e[:, None] * phi.g.real)


def _rrr(C: _D, D: _D, a: _D, b: _D, sign: float) -> tuple[_D, np.ndarray]:
    from ..linkage.dyads import _rrr as rrr  # the engine's dyad without its input checks

    # circles: the sign of a length is moot; NaN where they do not meet (as the kernel)
    E, _, ok = rrr(C.v, D.v, np.abs(a.v.real), np.abs(b.v.real), sign)
    w1, w2 = E - C.v, E - D.v
    # Re(conj(w) dE) = rhs: [w1.re w1.im; w2.re w2.im] [dx; dy] = [r1; r2]
    r1 = a.v.real[:, None] * a.g.real + (np.conj(w1)[:, None] * C.g).real
    r2 = b.v.real[:, None] * b.g.real + (np.conj(w2)[:, None] * D.g).real
    det = w1.real * w2.imag - w1.imag * w2.real
    det = np.where(np.abs(det) > 1e-300, det, 1e-300)[:, None]
    dx = (r1 * w2.imag[:, None] - r2 * w1.imag[:, None]) / det
    dy = (w1.real[:, None] * r2 - w2.real[:, None] * r1) / det
    return _D(E, dx + 1j * dy), ok


def sixbar_coupler(x: np.ndarray, theta: np.ndarray, fixed: dict[str, int]):
    """Coupler point of a placed six-bar at crank angles ``theta``, with its derivatives.

    Returns ``P`` (K,), ``dP/dx`` (K, 15), ``dP/dθ`` (K,) and ``ok`` (K,).

    Examples
    --------
    Against central differences:

    >>> fixed = dict(s4=1, s6=1, topology=1, on=6)
    >>> x = np.array([0.5, 0.2, 0.3, 3, 1, 3.5, 2.5, 4 / 3, 2 / 3, 1, 0, 3, 3, 0.5, 0.1])
    >>> th = np.array([0.3, 2.0])
    >>> P, J, Jt, ok = sixbar_coupler(x, th, fixed)
    >>> h = 1e-6
    >>> fd = [(sixbar_coupler(x + h * e, th, fixed)[0] - sixbar_coupler(x - h * e, th, fixed)[0])
    ...       / (2 * h) for e in np.eye(15)]
    >>> bool(ok.all()) and bool(np.allclose(np.array(fd).T, J, atol=1e-6))
    True
    """
    k = theta.size
    p = [_param(x, i, k) for i in range(_NP)]
    ox, oy, th1, r1, r2, r3, r4, cu, cv, du, dv, a, b, pu, pv = p
    g = np.zeros((k, _NP + 1), complex)
    g[:, _NP] = 1.0
    th = _D(np.asarray(theta, complex), g)

    def j(d: _D) -> _D:
        return _D(1j * d.v, 1j * d.g)

    O2 = ox + j(oy)
    e1 = _expi(th1)
    O4 = O2 + r1 * e1
    A = O2 + r2 * e1 * _expi(th)
    B, ok4 = _rrr(A, O4, r3, r4, fixed["s4"])
    frames = {1: (O2, O4), 2: (O2, A), 3: (A, B), 4: (O4, B)}
    (l1, l2), _ = TOPOLOGIES[fixed["topology"]]
    o1, x1 = frames[l1]
    o2, x2 = frames[l2]
    C = o1 + (cu + j(cv)) * (x1 - o1)
    D = o2 + (du + j(dv)) * (x2 - o2)
    E, ok6 = _rrr(C, D, a, b, fixed["s6"])
    base = D if fixed["on"] == 6 else C
    P = base + (pu + j(pv)) * (E - base)
    return P.v, P.g[:, :_NP], P.g[:, _NP], ok4 & ok6


def coupler_function(compiled: bool = False):
    """``(x, θ, fixed) → (P, dP/dx, dP/dθ, ok)``: the compiled kernel or :func:`sixbar_coupler`.

    ``compiled`` is the caller's choice (made once per synthesis, as the atlas
    build does: :func:`machdyn.jit.load` unless ``MACHDYN_JIT=off``); the kernel
    (:func:`machdyn.synthesis._sixbar_kernels.sixbar_coupler`) is tested against
    the NumPy forward mode here and both against central differences.
    """
    if not compiled:
        return sixbar_coupler
    from ._sixbar_kernels import sixbar_coupler as kernel

    def evaluate(x, theta, fixed):
        theta = np.ascontiguousarray(theta, dtype=float)
        k = theta.size
        P, J = np.empty(k, complex), np.empty((k, _NP), complex)
        Jt, ok = np.empty(k, complex), np.empty(k, bool)
        (l1, l2), _ = TOPOLOGIES[fixed["topology"]]
        kernel(np.ascontiguousarray(x, dtype=float), theta, float(fixed["s4"]),
               float(fixed["s6"]), l1, l2, fixed["on"] == 6, P, J, Jt, ok)  # fmt: skip
        return P, J, Jt, ok

    return evaluate


def refine_sixbar(x0, theta0, fixed, targets, *, timing=None, iterations=200, compiled=False):
    """Levenberg–Marquardt on the distances of the coupler point to the targets.

    The residuals are the coupler point's offsets from the targets (over the
    targets' size); the unknowns the 15 design numbers and the crank angle at
    each target (one ``θ0`` with prescribed ``timing``); the Jacobian is
    analytic (:func:`coupler_function`). A plain damped Gauss–Newton loop
    (Marquardt's scaling by the diagonal of ``JᵀJ``) rather than
    :func:`scipy.optimize.least_squares`: each step is one 30 × 30 solve, so the
    loop costs tens of microseconds a step where scipy's trust region costs
    milliseconds, and a synthesis can afford to refine many candidates. Lengths
    may pass through zero on the way; the result is re-expressed with positive
    lengths (the same joints). Returns the design, the crank angle at each
    target and the RMS distance (inf where the six-bar comes apart at a target).
    """
    k = targets.size
    scale = float(np.max(np.abs(targets - targets.mean()))) or 1.0
    timed = timing is not None
    z = np.concatenate([x0, [theta0[0] - timing[0]] if timed else theta0]).astype(float)
    rows = np.arange(k)

    def angles(z):
        return z[_NP] + timing if timed else z[_NP:]

    def evaluate(z):
        P, J, jt, ok = coupler(z[:_NP], angles(z), fixed)
        # at a dyad's toggle the derivatives grow without bound: count it as apart
        ok = ok & np.all(np.abs(J) < _STEEP * scale, axis=1) & (np.abs(jt) < _STEEP * scale)
        d = np.where(ok, (P - targets) / scale, 10.0)  # a constant residual where apart
        J = np.where(ok[:, None], J, 0.0) / scale
        jt = np.where(ok, jt, 0.0) / scale
        out = np.zeros((2 * k, z.size))
        out[:k, :_NP], out[k:, :_NP] = J.real, J.imag
        if timed:
            out[:k, _NP], out[k:, _NP] = jt.real, jt.imag
        else:
            out[rows, _NP + rows], out[k + rows, _NP + rows] = jt.real, jt.imag
        r = np.concatenate([d.real, d.imag])
        return r, out, float(r @ r)

    if compiled:  # the same loop, compiled (machdyn.synthesis._sixbar_kernels.refine_fit)
        x, theta, P, ok = _compiled_fit(z, timing, targets, scale, fixed, iterations)
    else:
        coupler = coupler_function(compiled)
        z = _loop(evaluate, z, iterations)
        x, theta = _positive_lengths(z[:_NP].copy(), np.asarray(angles(z), float).copy())
        P, _, _, ok = coupler(x, theta, fixed)
        ok = ok.all()
    rms = float(np.sqrt(np.mean(np.abs(P - targets) ** 2))) if ok else np.inf
    return x, theta, rms


def _compiled_fit(z, timing, targets, scale, fixed, iterations):
    from ._sixbar_kernels import refine_fit

    (l1, l2), _ = TOPOLOGIES[fixed["topology"]]
    timed = timing is not None
    timing = np.ascontiguousarray(timing if timed else np.zeros(0), dtype=float)
    return refine_fit(z, timing, timed, np.ascontiguousarray(targets, complex), scale,
                      float(fixed["s4"]), float(fixed["s6"]), l1, l2, fixed["on"] == 6, _STEEP,
                      DAMPING_FLOOR, int(iterations))  # fmt: skip


def _loop(evaluate, z, iterations):
    """The damped Gauss–Newton loop of :func:`refine_sixbar` (NumPy)."""
    r, J, cost = evaluate(z)
    lam = 1e-3
    for _ in range(iterations):
        A = J.T @ J
        g = J.T @ r
        diag = np.maximum(np.diag(A), DAMPING_FLOOR * max(float(np.max(np.diag(A))), 1e-300))
        M = A + lam * np.diag(diag)
        try:
            with np.errstate(over="ignore", invalid="ignore"):  # a wild step: refused below
                step = np.linalg.solve(M, -g)
                step = step + _geodesic(evaluate, z, r, J, M, step)
        except np.linalg.LinAlgError:
            step = np.full(z.size, np.nan)
        if not np.all(np.isfinite(step)):
            lam *= 10.0
            continue
        z_new = z + step
        r_new, J_new, cost_new = evaluate(z_new)
        if cost_new < cost:
            small = np.max(np.abs(step)) <= 1e-15 * (1.0 + np.max(np.abs(z)))
            z, r, J, cost = z_new, r_new, J_new, cost_new
            lam = max(lam / 3.0, 1e-15)
            if small or cost <= 1e-30:
                break
        else:
            lam *= 4.0
            if lam > 1e15:
                break
    return z


def _geodesic(evaluate, z, r, J, M, v, h=0.1):
    """Transtrum's geodesic acceleration: the second-order correction of an LM step ``v``.

    The residuals' second directional derivative along ``v`` by a finite
    difference, ``r'' ≈ 2/h (r(z + h v) − r(z))/h − J v)``, and the
    correction ``a`` that solves the same damped system for ``−Jᵀr''``; half
    of it is added when it is small beside the step (``|a| ≤ 0.75 |v|``,
    Transtrum & Sethna 2012, arXiv:1201.5885). It lets the step follow a
    curved valley, where the six-bar's many near-fitting designs lie: over 20
    starts each for five random six-bar targets, 600 steps converged (rms
    below 1e-8 of the size) 24 times with it and never without.
    """
    if not np.all(np.isfinite(v)):
        return 0.0 * v
    r_h = evaluate(z + h * v)[0]
    curvature = 2.0 / h * ((r_h - r) / h - J @ v)
    a = np.linalg.solve(M, -(J.T @ curvature))
    return 0.5 * a if np.linalg.norm(a) <= 0.75 * np.linalg.norm(v) else 0.0 * a


def _positive_lengths(x: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The same six-bar with every length positive (the joints do not move).

    r3, r4, a, b enter only through the dyads' circles (their squares); a
    negative r1 is the ground line turned half a turn (θ1 + π, and the crank
    angle from it − π, so A stays); a negative r2 is the crank half a turn on.
    """
    for i in (5, 6, 11, 12):
        x[i] = abs(x[i])
    if x[3] < 0:
        x[3], x[2] = -x[3], x[2] + np.pi
        theta = theta - np.pi
    if x[4] < 0:
        x[4] = -x[4]
        theta = theta + np.pi
    return x, theta


def sixbar_linkage(x: np.ndarray, fixed: dict[str, int], theta2: float = 0.0):
    """The placed six-bar as a :class:`~machdyn.linkage.Linkage`, drawn at crank angle ``theta2``.

    Points: ``O2 O4 A B C D E P`` (and ``G`` for a ground attachment, the
    dyad's fixed pivot); links ``crank``, ``coupler``, ``rocker``, ``link5``,
    ``link6`` (a ground attachment's link is pivoted on the ground); the driver
    is the crank (its absolute angle is ``θ1 + θ2``).
    """
    from ..linkage import Linkage

    P = sixbar_coupler(x, np.array([theta2]), fixed)[0]
    pts = {k: complex(v) for k, v in _joints(x, theta2, fixed).items()}
    (l1, l2), _ = TOPOLOGIES[fixed["topology"]]
    on = {1: [], 2: ["O2", "A"], 3: ["A", "B"], 4: ["O4", "B"]}
    on[l1] = on[l1] + ["C"]
    on[l2] = on[l2] + ["D"]
    link5 = ["C", "E"] + (["P"] if fixed["on"] == 5 else [])
    link6 = ["D", "E"] + (["P"] if fixed["on"] == 6 else [])
    lk = Linkage({**pts, "P": complex(P[0])})
    lk.ground("O2", "O4", *(["C"] if l1 == 1 else []))
    lk.link("crank", *on[2])
    lk.link("coupler", *on[3])
    lk.link("rocker", *on[4])
    lk.link("link5", *link5)
    lk.link("link6", *link6)
    lk.drive("crank")
    return lk


def _joints(x, theta2, fixed):
    """The joints of the placed six-bar at crank angles ``theta2`` (NaN where apart)."""
    from ..linkage.dyads import _rrr as rrr  # the engine's dyad without its input checks

    ox, oy, th1, r1, r2, r3, r4, cu, cv, du, dv, a, b = x[:13]
    O2 = complex(ox, oy)
    e1 = np.exp(1j * th1)
    O4 = O2 + r1 * e1
    A = O2 + r2 * e1 * np.exp(1j * np.asarray(theta2, float))
    B = rrr(A, O4, abs(r3), abs(r4), fixed["s4"])[0]
    frames = {1: (O2, O4), 2: (O2, A), 3: (A, B), 4: (O4, B)}
    (l1, l2), _ = TOPOLOGIES[fixed["topology"]]
    C = frames[l1][0] + complex(cu, cv) * (frames[l1][1] - frames[l1][0])
    D = frames[l2][0] + complex(du, dv) * (frames[l2][1] - frames[l2][0])
    E = rrr(C, D, abs(a), abs(b), fixed["s6"])[0]
    return {"O2": O2, "O4": O4, "A": A, "B": B, "C": C, "D": D, "E": E}
