"""Path synthesis of six-bars from a six-bar atlas: place, refine, check, build the Linkage.

The design of a placed six-bar is 15 numbers, ``x = (O2x, O2y, θ1, r1, r2, r3,
r4, cu, cv, du, dv, a, b, pu, pv)`` (see :mod:`machdyn.synthesis.sixbar`), plus
the assembly signs, the topology and the coupler link, which stay as retrieved.
The coupler point is built in the plane by the same steps as the atlas —
the crank pin, two RRR dyads, points in link frames — and its derivatives are
carried along each step (forward mode, analytic): an RRR dyad's pin ``E``
with ``|E − C| = a``, ``|E − D| = b`` moves by the ``dE`` that solves
``Re(conj(E − C)(dE − dC)) = a da`` and ``Re(conj(E − D)(dE − dD)) = b db``
(the circle equations differentiated; Cramer's rule). The refinement is
:func:`scipy.optimize.least_squares` on the real distances, as for four-bars.
The results are :class:`~machdyn.linkage.Linkage` objects drawn in the plane;
their distances to the targets are measured by the Linkage's own solver.
"""

from __future__ import annotations

import time
import weakref
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.lib.recfunctions import structured_to_unstructured

from ..errors import ModelError
from ._atlas_index import _NEVER
from ._atlas_result import NEAR, PathCandidates, _far_note, _limit_note, _rank
from .sixbar import TOPOLOGIES

# Internal to machdyn.synthesis, which re-exports the public names (Atlas, build_atlas,
# open_atlas, path_from_atlas, curve_descriptor, ...); the fuzz suite fuzzes those.
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
    coupler = coupler_function(compiled)
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

    if compiled:  # the same loop, compiled (machdyn.synthesis._sixbar_kernels.refine_loop)
        z = _compiled_loop(z, timing, targets, scale, fixed, iterations)
    else:
        z = _loop(evaluate, z, iterations)
    x, theta = _positive_lengths(z[:_NP].copy(), np.asarray(angles(z), float).copy())
    P, _, _, ok = coupler(x, theta, fixed)
    rms = float(np.sqrt(np.mean(np.abs(P - targets) ** 2))) if ok.all() else np.inf
    return x, theta, rms


def _compiled_loop(z, timing, targets, scale, fixed, iterations):
    from ._sixbar_kernels import refine_loop

    (l1, l2), _ = TOPOLOGIES[fixed["topology"]]
    timed = timing is not None
    timing = np.ascontiguousarray(timing if timed else np.zeros(0), dtype=float)
    return refine_loop(z.copy(), timing, timed, np.ascontiguousarray(targets, complex),
                       scale, float(fixed["s4"]), float(fixed["s6"]), l1, l2,
                       fixed["on"] == 6, _STEEP, DAMPING_FLOOR, int(iterations))  # fmt: skip


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


@dataclass(frozen=True, eq=False)
class SixBarPath:
    """A six-bar found by path synthesis, checked by the Linkage solver.

    Attributes
    ----------
    linkage : machdyn.linkage.Linkage
        Drawn in the plane at the first target's crank angle; driver ``crank``.
    chain : str
        ``"Watt I"``, ``"Watt II"`` or ``"Stephenson"`` and the dyad's links.
    design : ndarray, shape (15,)
        ``O2x O2y θ1 r1 r2 r3 r4 cu cv du dv a b pu pv``.
    targets, theta2, distance : ndarray
        Targets, crank angle (from the ground line) at each, distance to the curve.
    defects : tuple of str
    """

    linkage: Any
    chain: str
    design: np.ndarray
    fixed: dict
    targets: np.ndarray
    theta2: np.ndarray
    distance: np.ndarray
    defects: tuple[str, ...]
    barker_class: str = ""
    is_crank: bool = True
    mu_min: float = float("nan")
    in_order: bool = True

    @property
    def ok(self) -> bool:
        """True when no defect was found."""
        return not self.defects


#: Six-bars: starts screened per refined candidate, and steps of each polished one.
SIXBAR_SCREEN = 4
SIXBAR_POLISH = 600
#: Six-bars: most fits polished while none meets the targets (of 20 random timed six-bars
#: of the benchmark, none was met from a fit screened below the 23rd; a miss polished all).
SIXBAR_POLISH_MAX = 24
#: Six-bars with prescribed timing: starts screened per refined candidate, most fits polished.
SIXBAR_TIMED = (16, 96)
#: Six-bars: when none meets the targets, the best few fits polished this many steps more
#: (compiled kernels only; untimed too since a Watt II 1-4 fit at 3.8e-6 crawled to 3e-14).
SIXBAR_LONG = (2, 6000)
#: A six-bar whose RMS distance is below this share of the size meets the targets.
SIXBAR_MET = 1e-12
#: Six-bars: a fit this near (RMS over the size) takes no more rounds of starts (its valley
#: is polished longer instead; see sixbar_path.SIXBAR_ROUNDS).
SIXBAR_NEAR = 1e-8
_FIXED = ("s4", "s6", "topology", "on")
#: Six-bar entries spread over the atlas that timed targets are scanned against.
SIXBAR_TIMED_POOL = 1_000
#: Timed targets: starting angles every entry is scanned at, and entries scanned again finely.
SIXBAR_COARSE = 20
SIXBAR_FINE = 96
#: Timed targets: the pools scanned, each ``(entries spread over the atlas, nearest entries by
#: shape in units of ``retrieve``)``; each pool gives its own best starts. Spread entries
#: start most Watt II fits, the nearest by shape most Watt I and Stephenson ones.
SIXBAR_TIMED_POOLS = ((SIXBAR_TIMED_POOL, 1), (4 * SIXBAR_TIMED_POOL, 4), (0, 25), (0, 60))
#: Rounds of starts while no fit meets the targets (untimed, timed). The second round of a
#: timed target scans the first pool again on grids of starting angles turned by half a
#: step (the best-scoring entries and angles change, and with them the basins the starts
#: lie in); its third is a neighbour round (:func:`_neighbour_starts`: entries nearest to
#: its best fits in their design numbers, placed as those fits are), its fourth and fifth
#: are kind rounds (:func:`_kind_round`): entries of the kinds of its best fits. A later
#: round of an untimed target takes the next-best-placed entries of a retrieval
#: :data:`SIXBAR_WIDER` times wider than the round before. An untimed third round and a
#: timed fifth run only when the rounds before leave a target unmet, and their best fits
#: polished long too (:data:`SIXBAR_GATE`).
SIXBAR_ROUNDS = (3, 5)  # untimed, timed
#: From this round of starts on (0 the first; untimed, timed), a round runs only when the
#: best fits so far, polished long (:data:`SIXBAR_LONG`, as after the rounds; each fit
#: once), still leave the targets unmet. Seed 2026's timed six-bar 43: its best fit after
#: three rounds (3.1e-7 of the size, from the first) polished to 9e-16, and the fourth round
#: it had run for nothing; of the untimed targets two rounds leave unmet, most are met by
#: that polish.
SIXBAR_GATE = (2, 4)
#: Untimed later rounds: entries retrieved ×5, placed starts ×3, each round again (the
#: third: 25 times the first's retrieval, 4,000 entries, 360 placed). Seed 13's untimed
#: Watt I 3-4 on 5 and on 6 (six-bars 10 and 11: 1.2e-2, 6.1e-3 of the size after two rounds)
#: are met by the third (2.8e-15); a fourth (125 times) cost 4 s more and met none. No third
#: round where the best fit is within :data:`SIXBAR_CRAWL` (seeds 13 and 17: three targets
#: at 1e-8–8e-8 took it for nothing, 1.2–1.6 s of CPU).
SIXBAR_WIDER = (5, 3)
#: A kind round scans this many entries spread over those of a kind (chain, dyad links, the
#: point's link: :func:`_kind_pool`). Where the best fits are of the generating kind but at
#: a local minimum, the starts in the generating six-bar's basin are few (0.25–1.2 % of
#: random entries of its kind, for seed 7's missed Watt I 3-4 on 5) and no score finds them
#: (they ranked 500th to 150,000th by shape and by the timed scan): more entries of that
#: kind are what helps. A round of its own, not a share of the second: that share lost a
#: target the whole rescan met (best fits of another kind).
SIXBAR_KIND_POOL = 1_000
#: Kind rounds (:func:`_kind_round`): the first scans every kind whose best fit is within
#: ``SIXBAR_KIND_BAND`` times the best kind's best fit, at most ``SIXBAR_KIND_MOST`` kinds,
#: and polishes ``SIXBAR_KIND_POLISH`` fits per kind scanned. Over the benchmark's timed
#: targets that reach a kind round (seeds 2026, 7, 13, 17), where the next kind's best fit
#: was within 10 times the leader's, the generating kind was second five times (2nd/1st
#: 1.0–6.7) and first four times (1.1–3.2); where the next was 29 times or more behind, the
#: leader was the generating kind in three of four. Which of two close kinds leads is chance,
#: decided by which starts the rounds happened to have (seed 2026's six-bar 29 lost its
#: second-round start with the atlas query's exact re-ranking). The met fits of kind rounds
#: ranked 0th–13th after their screening steps.
SIXBAR_KIND_BAND = 10.0
SIXBAR_KIND_MOST = 2
SIXBAR_KIND_POLISH = 16
#: No third (or fourth) round where the best fit's RMS is within this share of the size: such
#: a fit is crawling along its valley (seed 2026's six-bars 52 and 59, 2e-8 and 4e-8 after the first
#: round), which the long polish follows (a third round cost them CPU, and six-bar 59's
#: best polished fit). The local minima the third round escapes were 8.8e-6 to 9e-4.
SIXBAR_CRAWL = 1e-7
#: A later round of a timed target: steps every start is refined before the fits are ranked
#: (the first round: 30), and most fits polished. Thirty steps rank poorly among six-bars'
#: many near-fits: the one start of a missed timed Watt I 3-4 on 6 that converged ranked
#: 452nd of 539 after 30 steps (112th of 160 in the second round), 40th (8th) after 100 and
#: first after 300. A later round has only the first pool's starts: it can afford to screen
#: them longer, and polishes half as many (the time of a miss stays as it was).
SIXBAR_LATER_TIMED = (100, 48)
#: Timed targets without the compiled kernels (``MACHDYN_JIT=off``, whose NumPy refinement
#: costs ~6 times more a step): starts screened per refined candidate and most fits
#: polished, one round, no long polish (docs/synthesis.md gives the times and rates).
SIXBAR_TIMED_NUMPY = (4, 24)


#: Untimed Watt II six-bars with the dyad on links 1 and 4 (two four-bars in series): while
#: none meets the targets, their second loop is fitted alone (see :func:`second_loop_fits`):
#: the fits whose second loop is fitted (without the compiled kernels: the second number)
#: and its steps, the best loops a six-bar is rebuilt from, and the rebuilt six-bars' steps.
#: On the benchmark's missed six-bar the loops that converged came from fits ranked 13th
#: and 33rd.
SIXBAR_SECOND_LOOP = ((40, 8), 600, 4, 300)


def _design_of(row, h, t, mirror: float = 1.0) -> tuple[np.ndarray, dict[str, int]]:
    """The placed design of an atlas row under the similarity ``t + h·z`` (mirrored: z → z̄)."""
    s = abs(h)
    f = {k: float(row[k]) for k in ("r1", "r3", "r4", "cu", "cv", "du", "dv", "a", "b", "pu", "pv")}
    x = np.array([
        t.real, t.imag, np.angle(h), f["r1"] * s, s, f["r3"] * s, f["r4"] * s,
        f["cu"], mirror * f["cv"], f["du"], mirror * f["dv"], f["a"] * s, f["b"] * s,
        f["pu"], mirror * f["pv"],
    ])  # fmt: skip
    fixed = {k: int(row[k]) for k in _FIXED}
    fixed["s4"] *= int(mirror)
    fixed["s6"] *= int(mirror)
    return x, fixed


def sixbar_starts(atlas, pts, timing, closed, retrieve, refine_count, client=None,
                  compiled=False, round_=0, fits=(), memo=None):  # fmt: skip
    """Refinement starts ``(x0, θ0, fixed)`` for six-bars: placed atlas entries.

    ``compiled``: the timed scan computes its coupler points on the compiled
    kernel (:mod:`machdyn.synthesis._sixbar_kernels`) rather than in NumPy.
    ``round_``: the round of starts (see :data:`SIXBAR_ROUNDS`); a later round's
    starts may repeat an earlier round's (the caller drops those). ``fits``: the
    fits so far ``(x, θ, rms, fixed)``: a timed target's third and fourth rounds scan
    entries of the kinds of the best ones (:func:`_kind_round`). ``memo``: a dict
    kept by the caller across the rounds of one synthesis: the entries nearest to
    the targets by shape are retrieved once into it (the second round rescans the
    first pool, and the fourth takes entries of its kinds from them; a query on the
    10^6 six-bar atlas costs about 0.3 s of CPU), and the kinds scanned.
    """
    from ._atlas_retrieve import _retrieve
    from .descriptor import curve_descriptor, interpolate_closed, resample_closed
    from .sixbar import sixbar_points

    starts = []
    if timing is None:
        if round_:
            retrieve *= SIXBAR_WIDER[0] ** round_
            refine_count *= SIXBAR_WIDER[1] ** round_
        rows, transforms = _retrieve(atlas, pts, closed, True, retrieve, refine_count, client)
        u = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
        local = sixbar_points(rows, u)[0]
        for row, (h, t), z in zip(rows, transforms, local, strict=True):
            if not np.isfinite(h) or h == 0:
                continue
            h, t, near = _placed_start(z, h, t, pts, compiled=compiled)
            x0, fixed = _design_of(row, h, t)
            starts.append((x0, u[near], fixed))
        return starts
    memo = {} if memo is None else memo
    near = np.zeros(0, np.int64)
    if closed:  # the entries whose whole curve looks like the target's (retrieved once)
        wanted = min(max(k for _, k in SIXBAR_TIMED_POOLS) * retrieve, len(atlas))
        if memo.get("near", (None, 0))[1] != wanted:
            dense = interpolate_closed(pts, 8 * atlas.manifest.samples)
            even = resample_closed(dense, atlas.manifest.samples)
            q = curve_descriptor(even, atlas.manifest.harmonics, resampled=True)
            memo["near"] = (atlas.nearest(q, wanted, client=client)[0], wanted)
        near = memo["near"][0]
    # pools, each with its own best starts (see SIXBAR_TIMED_POOLS). Their best-scoring
    # starts lie in different basins (the timed fit is over-determined: near the truth it
    # has real local minima), and a target missed from one pool is often met from another
    seen: set[tuple[int, float]] = set()
    if round_ == 2:  # the neighbour round: entries placed as the best fits are
        return _neighbour_starts(atlas, fits, pts)
    if round_ > 2:  # a kind round: entries of the kinds of the best fits (_kind_round)
        pools = _kind_round(atlas, fits, pts, near, memo)
    else:
        pools = [
            np.union1d(atlas.pool(size, crank=True), near[: k * retrieve]) if size else
            near[: k * retrieve] for size, k in SIXBAR_TIMED_POOLS[: 1 if round_ else None]
        ]  # fmt: skip
    pools = [idx for idx in pools if idx.size]
    chosen = []
    # (kind rounds: the first round's starting angles, the grid turned by one whole step)
    for best in _timed_best(atlas, pools, timing, pts, refine_count, compiled,
                            shift=0.5 * min(round_, 2)):  # fmt: skip
        for i, h, t, g0, mirror in best:
            if (i, mirror) not in seen:
                seen.add((i, mirror))
                chosen.append((i, h, t, g0, mirror))
    rows = atlas.entries(np.array([c[0] for c in chosen], np.int64))  # (one read for all)
    for row, (_, h, t, g0, mirror) in zip(rows, chosen, strict=True):
        x0, fixed = _design_of(row, h, t, mirror)
        starts.append((x0, g0 + timing, fixed))
    return starts


def _ranked_kinds(fits, pts) -> list[tuple[tuple[int, int], float]]:
    """The kinds of the fits, ``((topology, on), rms)`` best first by each kind's best fit.

    A kind: the chain and the dyad's links (``topology``) and the link that carries
    the point (``on``). Fits that come apart (``inf``) rank no kind. Empty where the
    best fit is within :data:`SIXBAR_CRAWL` of the targets' size (the long polish's).
    """
    kinds: dict[tuple[int, int], float] = {}
    for f in fits:
        key = (int(f[3]["topology"]), int(f[3]["on"]))
        if np.isfinite(f[2]) and f[2] < kinds.get(key, np.inf):
            kinds[key] = float(f[2])
    ranked = sorted(kinds.items(), key=lambda kv: (kv[1], kv[0]))
    if ranked and ranked[0][1] <= SIXBAR_CRAWL * float(np.max(np.abs(pts - pts.mean()))):
        return []
    return ranked


def _kind_round(atlas, fits, pts, near, memo) -> list[np.ndarray]:
    """The pools of entries of a kind round (a timed target's third or fourth round).

    The first kind round: for each kind whose best fit is within
    :data:`SIXBAR_KIND_BAND` times the best kind's (at most :data:`SIXBAR_KIND_MOST`
    kinds, best first: :func:`_ranked_kinds`), entries spread over the kind. The
    second: for the same kinds, their entries among ``near`` (the entries nearest to
    the targets by shape, which the first round's pools held among all kinds); and
    where the first took one kind only, entries spread over the next kind. Each pool
    gives its own best starts. ``memo["kinds"]``: the first kind round's kinds;
    ``memo["round_kinds"]``: the kinds of the round (the caller polishes
    :data:`SIXBAR_KIND_POLISH` fits per kind). No pools where the best fit is within
    :data:`SIXBAR_CRAWL` of the targets' size.
    """
    ranked = _ranked_kinds(fits, pts)
    if not ranked:
        memo["round_kinds"] = []
        return []
    first = memo.get("kinds")
    if first is None:
        band = SIXBAR_KIND_BAND * ranked[0][1]
        kinds = [k for k, rms in ranked[:SIXBAR_KIND_MOST] if rms <= band]
        memo["kinds"] = memo["round_kinds"] = kinds
        return [_kind_pool(atlas, k) for k in kinds]
    near = np.asarray(near, dtype=np.int64)
    rows = atlas.entries(near) if near.size else None  # (one read for every kind; near
    # holds crank entries only, each kind's sorted as the spread pools are)
    pools = [np.zeros(0, np.int64) if rows is None else
             np.unique(near[(rows["topology"] == k[0]) & (rows["on"] == k[1])])
             for k in first]  # fmt: skip
    other = [k for k, _ in ranked if k not in first][: max(0, SIXBAR_KIND_MOST - len(first))]
    pools += [_kind_pool(atlas, k) for k in other]
    memo["round_kinds"] = first + other
    return pools


def _kind_pool(atlas, kind: tuple[int, int]) -> np.ndarray:
    """Flat indices of :data:`SIXBAR_KIND_POOL` crank entries of one kind ``(topology, on)``.

    Spread evenly over the atlas's entries of the kind.
    """
    sel = [crank & (np.asarray(m["topology"]) == kind[0]) & (np.asarray(m["on"]) == kind[1])
           for crank, m in zip(atlas._crank, atlas.meta, strict=True)]  # fmt: skip
    allowed = np.flatnonzero(np.concatenate(sel))
    if allowed.size > SIXBAR_KIND_POOL:
        allowed = allowed[np.linspace(0, allowed.size - 1, SIXBAR_KIND_POOL).astype(np.int64)]
    return allowed


#: The neighbour round (a timed target's third, :func:`_neighbour_starts`): the kinds whose
#: best fits are taken (at most; within :data:`SIXBAR_KIND_BAND` of the best kind's), the
#: distinct best fits of each, and the atlas entries nearest to each fit in its design
#: numbers. A timed fit is over-determined: near the truth it has real local minima,
#: and the entries nearest to the truth by shape or by the timed scan are seldom in its
#: basin. Seed 13's six-bar 39 (Stephenson 1-3 on 6): of the 300 entries of its kind
#: nearest to the known six-bar in design numbers, 72 converge placed as it is (its
#: similarity and crank angles) but 6 placed by the timed scan, none of whose scores rank
#: among a pool's best 160; its best fits of its kind stop at 1.7e-2 of the size, and of the
#: 200 entries nearest to each placed as it is, 39, 18 and 16 converge (300 steps).
SIXBAR_NEIGHBOURS = (3, 1, 40)
#: The neighbour round's screening steps and most fits polished (as :data:`SIXBAR_LATER_TIMED`):
#: its starts lie around a fit, and those in the truth's basin lead after few steps (six-bar
#: 39's three met starts of 40 ranked first to third after 30, 60 or 100 steps).
SIXBAR_NEIGHBOUR_POLISH = (30, 16)


#: The atlas rows' design numbers, in :func:`_design_numbers`' order.
_NUMBERS = ("r1", "r3", "r4", "cu", "cv", "du", "dv", "a", "b", "pu", "pv")


def _design_numbers(values: np.ndarray, mirror: Any = 1.0) -> np.ndarray:
    """Atlas rows' design numbers in one metric (:func:`_neighbour_starts`').

    ``values``: the rows' :data:`_NUMBERS`, one row each. Logs of the lengths over the
    crank, the link-frame coordinates as they are (``v`` negated for a mirror image;
    ``mirror`` ±1, one for all rows or one each).
    """
    out = np.array(values, dtype=float, ndmin=2)
    out[:, [0, 1, 2, 7, 8]] = np.log(out[:, [0, 1, 2, 7, 8]])
    out[:, [4, 6, 10]] *= np.asarray(mirror, dtype=float).reshape(-1, 1)
    return out


def _fit_numbers(x: np.ndarray) -> np.ndarray:
    """A placed design's numbers in :func:`_design_numbers`' metric (positive lengths)."""
    r2 = abs(x[4])
    lengths = np.log(np.abs(x[[3, 5, 6, 11, 12]]) / r2)
    return np.array([lengths[0], lengths[1], lengths[2], *x[7:11], lengths[3], lengths[4],
                     x[13], x[14]])  # fmt: skip


def _kind_entries(atlas, fixed) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The crank entries a fit of ``fixed``'s kind and assembly signs can be placed from.

    An entry of the same signs as it is, or of both signs opposite as its mirror image
    (:func:`_design_of`). Returns flat indices, mirrors (±1) and design numbers
    (:func:`_design_numbers`, float32), kept per opened atlas: reading them costs about
    0.02 s a kind on the 10^6 six-bar atlas, and a benchmark's syntheses ask for the same
    few kinds again (at most 4 MB each).
    """
    cache = _ENTRIES.setdefault(atlas, {})
    if "codes" not in cache:  # each entry's kind and signs as one number; -1: no crank
        cache["codes"] = [
            np.where(crank, (m["topology"].astype(np.int16) * 8 + m["on"]) * 9
                     + (m["s4"] + 1) * 3 + m["s6"] + 1, -1)
            for crank, m in zip(atlas._crank, atlas.meta, strict=True)
        ]  # fmt: skip
    key = (fixed["topology"], fixed["on"], fixed["s4"], fixed["s6"])
    if key not in cache:
        base = (fixed["topology"] * 8 + fixed["on"]) * 9
        same = base + (fixed["s4"] + 1) * 3 + fixed["s6"] + 1
        mirrored = base + (1 - fixed["s4"]) * 3 + 1 - fixed["s6"]
        idx, values, mirrors = [], [], []
        for c, (code, m) in enumerate(zip(cache["codes"], atlas.meta, strict=True)):
            sel = np.flatnonzero((code == same) | (code == mirrored))
            idx.append(sel + atlas.offsets[c])
            # (the fields as columns of a view: gathering them costs a third of the rows')
            values.append(structured_to_unstructured(m[list(_NUMBERS)], copy=False)[sel])
            mirrors.append(np.where(code[sel] == same, 1.0, -1.0))
        mirrors = np.concatenate(mirrors)
        numbers = _design_numbers(np.concatenate(values), mirrors).astype(np.float32)
        cache[key] = (np.concatenate(idx), mirrors.astype(np.int8), numbers)
    return cache[key]


#: :func:`_kind_entries`' entries, per opened atlas.
_ENTRIES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _neighbour_starts(atlas, fits, pts) -> list:
    """Starts ``(x0, θ0, fixed)`` of the neighbour round (a timed target's third).

    For each of the best kinds (:func:`_ranked_kinds`; at most
    ``SIXBAR_NEIGHBOURS[0]``, within :data:`SIXBAR_KIND_BAND` of the best) its
    ``SIXBAR_NEIGHBOURS[1]`` best distinct fits; for each, the ``SIXBAR_NEIGHBOURS[2]``
    entries of its kind and signs nearest to it in design numbers
    (:func:`_kind_entries`), placed by the fit's own similarity (its ground pivot,
    ground line and crank) at the fit's crank angles. Where the fits stop at local
    minima near the truth, these starts lie around them, and some in the truth's basin.
    """
    kinds_most, per_kind, count = SIXBAR_NEIGHBOURS
    ranked = _ranked_kinds(fits, pts)
    band = SIXBAR_KIND_BAND * ranked[0][1] if ranked else 0.0
    kinds = [k for k, rms in ranked[:kinds_most] if rms <= band]
    starts = []
    for kind in kinds:
        taken: list[np.ndarray] = []
        for x, theta, rms, fixed in sorted(fits, key=lambda f: f[2]):
            if len(taken) == per_kind:
                break
            if (fixed["topology"], fixed["on"]) != kind or not np.isfinite(rms):
                continue
            v = _fit_numbers(x)
            if not np.all(np.isfinite(v)) or any(np.allclose(v, w, atol=1e-6) for w in taken):
                continue
            taken.append(v)
            idx, mirrors, numbers = _kind_entries(atlas, fixed)
            near = np.argsort(np.sum((numbers - v) ** 2, axis=1), kind="stable")[:count]
            h, t = abs(x[4]) * np.exp(1j * x[2]), complex(x[0], x[1])
            for row, mirror in zip(atlas.entries(idx[near]), mirrors[near], strict=True):
                x0, fx = _design_of(row, h, t, float(mirror))
                starts.append((x0, np.asarray(theta, float).copy(), fx))
    return starts


def polished_sixbars(starts, pts, most, check, steps, *, timing=None, compiled=False,
                     screen=30):  # fmt: skip
    """Fits ``(x, θ, rms, fixed)`` from ``starts``, screened and polished; whether one is met.

    Every start is refined ``screen`` steps; then the fits are polished (``steps`` more)
    best first — up to
    ``most`` of them — until one meets the targets to rounding and ``check(fit)``
    (the Linkage's) finds no defect: the screen's order is a poor guide among
    six-bars, whose near-fits abound, and an exact fit may be a six-bar that
    cannot turn its crank (the untimed fits form a family).
    """
    from ._atlas_result import POLISH

    size = float(np.max(np.abs(pts - pts.mean())))
    options = dict(timing=timing, compiled=compiled)
    fits = [(*refine_sixbar(x0, th0, fx, pts, iterations=screen, **options), fx)
            for x0, th0, fx in starts]  # fmt: skip
    fits.sort(key=lambda f: f[2])
    met = False
    for i, (x, th, rms, fx) in enumerate(fits[: max(POLISH, most)]):
        if i >= POLISH and met:
            break
        more = refine_sixbar(x, th, fx, pts, iterations=steps, **options)
        fits[i] = (*more, fx) if more[2] <= rms else fits[i]
        if fits[i][2] <= SIXBAR_MET * size:
            res = check(fits[i])
            met = met or (res is not None and res.ok)
    return fits, met


def second_loop_fits(fits, pts, compiled=False) -> list:
    """Untimed Watt II "1-4" six-bars fitted loop by loop: new fits ``(x, θ, rms, fixed)``.

    The dyad on the ground and the rocker makes such a six-bar two four-bars in
    series: the coupler point is the second four-bar's (ground pivots ``O4`` and
    ``C``, input link ``O4–D`` on the rocker) at the rocker's angle ``φ``, and the
    first four-bar only swings the rocker. Fitted as one, the crank angle of a
    target near a turn of the rocker is barely felt (``dφ/dθ ≈ 0``), and fits
    stall on a neighbouring second four-bar (1e-5 to 3e-3 of the size) that the
    first cannot swing to the truth. So (:data:`SIXBAR_SECOND_LOOP`): (1) the
    second four-bar of each of the best such fits is fitted to the targets alone,
    ``φ`` at each target free (:func:`_second_loop`); (2) for the best few of
    these a first four-bar is designed to swing it (:func:`_first_loop`) and the
    six-bar of the two refined. The loop fits themselves are returned too (Watt II
    1-2 six-bars: an answer where ``φ`` turns a whole turn in the targets' order),
    all best first; the caller checks them.
    """
    count, steps, best, rebuilt = SIXBAR_SECOND_LOOP
    wanted = sorted((f for f in fits if f[3]["topology"] == 1 and np.isfinite(f[2])),
                    key=lambda f: f[2])  # fmt: skip
    loops = [_second_loop(*f, pts, steps, compiled) for f in wanted[: count[not compiled]]]
    out = []
    for loop in sorted((lp for lp in loops if lp is not None), key=lambda lp: lp[2])[:best]:
        out.append(loop)
        fit = _first_loop(*loop[:2], loop[3], pts, rebuilt, compiled)
        out += [fit] if fit is not None else []
    return sorted(out, key=lambda f: f[2])


def _second_loop(x, theta, rms, fixed, pts, steps, compiled):
    """The second four-bar of a Watt II 1-4 fit refined alone: ``(x', φ, rms, fixed')``.

    Posed as a Watt II "1-2" six-bar whose crank is the input link ``O4–D``
    (``φ`` its crank angles; its own first four-bar, a dummy 1-4-4-4
    crank-rocker, does not move the point), so the same refinement serves.
    None where it comes apart.
    """
    j = _joints(x, theta, fixed)
    O4, C, D = j["O4"], j["C"], j["D"]
    rho = float(np.mean(np.abs(D - O4)))
    if not (np.all(np.isfinite(D)) and rho > 0):
        return None
    proxy = dict(s4=1, s6=fixed["s6"], topology=0, on=fixed["on"])
    c = (C - O4) / (4 * rho)
    x = np.array([O4.real, O4.imag, 0.0, 4 * rho, rho, 4 * rho, 4 * rho, c.real, c.imag,
                  1.0, 0.0, *x[11:]])  # fmt: skip
    x, theta, rms = refine_sixbar(x, np.angle(D - O4), proxy, pts, iterations=steps,
                                  compiled=compiled)  # fmt: skip
    return (x, theta, rms, proxy) if np.isfinite(rms) else None


def _first_loop(xp, phi, proxy, pts, steps, compiled):
    """A Watt II 1-4 six-bar from a fitted second loop (:func:`_second_loop`'s), refined.

    The first four-bar is a crank-rocker whose rocker (``0.6 ρ`` long) swings
    just past the fitted ``φ`` range: its crank on the line through the rocker's
    two end positions, half that chord long, so these are its limit positions
    (the two-position design of a crank-rocker, Norton §3.4); on either side, in
    either assembly. The six-bar starts at the samples of its curve nearest the
    targets in their order; the best refined one is returned (None if none assembles).
    """
    j = _joints(xp, phi, proxy)
    O4, C, D = j["O2"], j["C"], j["D"]
    rho = float(np.mean(np.abs(D - O4)))
    phi = np.sort(np.mod(np.angle(D - O4), 2 * np.pi))
    gaps = np.diff(np.concatenate([phi, phi[:1] + 2 * np.pi]))
    k = int(np.argmax(gaps))  # the swing: the circle less its widest gap between targets
    lo, hi = float(phi[(k + 1) % phi.size]), float(phi[k] + (2 * np.pi if k + 1 < phi.size else 0))
    if hi - lo > 0.8 * np.pi:  # no crank-rocker swings this far
        return None
    coupler = coupler_function(compiled)
    u = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    best = None
    for margin in (0.05, 0.01, 0.001):  # the second loop may close only just past the targets
        r4, swing = 0.6 * rho, margin * (hi - lo) + 1e-4
        B1, B2 = O4 + r4 * np.exp(1j * (lo - swing)), O4 + r4 * np.exp(1j * (hi + swing))
        r2 = abs(B2 - B1) / 2
        r3 = r2 + 1.5 * r4
        for side in (1.0, -1.0):
            O2 = (B1 + B2) / 2 + side * r3 * (B2 - B1) / (2 * r2)
            c = (C - O2) / (O4 - O2)
            x0 = np.array([O2.real, O2.imag, np.angle(O4 - O2), abs(O4 - O2), r2, r3, r4,
                           c.real, c.imag, rho / r4, 0.0, *xp[11:]])  # fmt: skip
            for s4 in (1, -1):
                fixed = dict(proxy, s4=s4, topology=1)
                P, _, _, ok = coupler(x0, u, fixed)
                if not ok.all():
                    continue
                near = _ordered_samples(P, pts, compiled=compiled)
                fit = refine_sixbar(x0, u[near], fixed, pts, iterations=steps, compiled=compiled)
                if best is None or fit[2] < best[2]:
                    best = (*fit, fixed)
        if best is not None:
            break
    return best


def _timed_best(atlas, pools, timing, pts, count, compiled=False, shift=0.0):
    """Per pool of entries, the ``count`` best timed placements: (index, h, t, θ0, mirror).

    Coarse to fine: every entry at :data:`SIXBAR_COARSE` starting angles, the best
    :data:`SIXBAR_FINE` of each direction again at every one of ``TIMED_GRID`` angles;
    both grids turned by ``shift`` of their step. An entry's coarse scan does not depend
    on its pool, so the entries that several pools share (the nearest by shape are
    nested) are scanned once.
    """
    from ._atlas_retrieve import TIMED_GRID

    if not pools:
        return []
    union = np.unique(np.concatenate(pools))
    rows = atlas.entries(union)
    at = [np.searchsorted(union, idx) for idx in pools]
    coarse = np.linspace(0.0, 2 * np.pi, SIXBAR_COARSE, endpoint=False)
    coarse = coarse + shift * coarse[1]
    grid = np.linspace(0.0, 2 * np.pi, TIMED_GRID, endpoint=False)
    grid = grid + shift * grid[1]
    found: list[list] = [[] for _ in pools]
    for mirror in (1.0, -1.0):  # the mirror image turns the other way for the same crank turn
        scores = _timed_scan(rows, coarse, timing, pts, mirror, compiled)[0]
        for p, idx in enumerate(pools):
            pick = np.argsort(-scores[at[p]])[:SIXBAR_FINE]
            fine = _timed_scan(rows[at[p][pick]], grid, timing, pts, mirror, compiled)
            score, hh, off, g = fine
            found[p] += [(score[j], int(idx[pick[j]]), hh[j], off[j], grid[g[j]], mirror)
                         for j in range(pick.size)]  # fmt: skip
    out = []
    for f in found:
        f.sort(key=lambda f: -f[0])
        out.append([f[1:] for f in f[:count]])
    return out


def _ordered_samples(curve: np.ndarray, pts: np.ndarray, rolls: int = 8,
                     compiled: bool = False) -> np.ndarray:  # fmt: skip
    """Indices of a placed curve's samples nearest the targets, in the targets' order.

    Not each target's nearest sample on its own: where the coupler point dwells
    (much of the turn on a short stretch of the curve) or the curve crosses
    itself, nearest samples jump back and forth and the refinement starts on the
    wrong arcs. Instead the samples are taken one way round, never going back
    (dynamic programming over the samples: the least sum of squared distances),
    from each of ``rolls`` starting samples in both directions at once; the best wins.
    ``compiled``: the same programme on the compiled kernel
    (:func:`machdyn.synthesis._sixbar_kernels.ordered_samples`; the same choices,
    about ten times faster), for finite distances.
    """
    n = curve.size
    c = np.abs(curve[None, :] - pts[:, None]) ** 2  # (K, N)
    if compiled and np.all(np.isfinite(c)):
        from ._sixbar_kernels import ordered_samples

        out = np.empty(pts.size, np.int64)
        ordered_samples(c, rolls, out)
        return out
    starts = np.arange(0, n, n // rolls)
    steps = np.concatenate([np.arange(n)[None, :], -np.arange(n)[None, :]])  # both ways
    order = (starts[:, None, None] + steps[None, :, :]).reshape(-1, n) % n  # (2R, N)
    c = c[:, order].transpose(1, 0, 2)  # (2R, K, N)
    total, back = c[:, 0], []
    cols = np.arange(n)
    for k in range(1, pts.size):  # target k at sample j: target k - 1 at a sample <= j
        run = np.minimum.accumulate(total, axis=1)
        better = np.concatenate([np.ones((total.shape[0], 1), bool),
                                 total[:, 1:] < run[:, :-1]], axis=1)  # fmt: skip
        back.append(np.maximum.accumulate(np.where(better, cols, 0), axis=1))
        total = c[:, k] + run
    end = np.argmin(total, axis=1)
    w = int(np.argmin(total[np.arange(end.size), end]))
    path = [int(end[w])]
    for b in reversed(back):
        path.append(int(b[w, path[-1]]))
    return order[w, np.array(path[::-1])]


def _placed_start(z: np.ndarray, h: complex, t: complex, pts: np.ndarray, rounds: int = 3,
                  compiled: bool = False):  # fmt: skip
    """Similarity ``t + h·z`` and sample indices for a curve ``z``, fitted in turns.

    The samples in the targets' order (:func:`_ordered_samples`), then the
    rotation, scale and offset that put those samples on the targets (least
    squares, closed form), a few times over: the descriptor's placement fits
    the spline through the targets, which misplaces curves that dwell.
    ``compiled``: :func:`_ordered_samples`'s.
    """
    a0 = pts - pts.mean()
    for _ in range(rounds):
        near = _ordered_samples(t + h * z, pts, compiled=compiled)
        q = z[near] - z[near].mean()
        v = float(np.sum(np.abs(q) ** 2))
        if v == 0.0:
            break
        h = complex(np.sum(np.conj(q) * a0) / v)
        t = complex(pts.mean() - h * z[near].mean())
    return h, t, _ordered_samples(t + h * z, pts, compiled=compiled)


def _timed_scan(rows, grid, timing, pts, mirror, compiled=False):
    """Each row's best starting angle on ``grid`` for timed targets: fit score, placement.

    The coupler points at ``θ0 + Δ_k`` placed on the targets by a rotation, scale and
    offset ``t + h·Q`` (closed form); the score is the share of the targets' spread the
    fit explains. Returns per row the score, ``h``, ``t`` and the index of θ0 in ``grid``.
    """
    if compiled:
        from ._sixbar_kernels import sixbar_points_compiled as points
    else:
        from .sixbar import sixbar_points

        def points(block, th):
            return sixbar_points(block, th)[0]

    a0 = pts - pts.mean()
    out = []
    for lo in range(0, rows.size, 1024):
        block = rows[lo : lo + 1024]
        th = mirror * (grid[:, None] + timing[None, :]).ravel()
        Q = points(block, th).reshape(block.size, grid.size, -1)
        if mirror < 0:
            np.conjugate(Q, out=Q)
        qm = np.nanmean(Q, axis=2, keepdims=True)
        Q -= qm
        c = np.sum(np.conj(Q) * a0, axis=2)
        v = np.sum(np.abs(Q) ** 2, axis=2)
        score = np.nan_to_num(np.abs(c) ** 2 / np.where(v > 0, v, np.inf), nan=-1.0)
        g = np.argmax(score, axis=1)
        r = np.arange(block.size)
        hh = c[r, g] / v[r, g]
        out.append((score[r, g], hh, pts.mean() - hh * qm[r, g, 0], g))
    return tuple(np.concatenate(x) for x in zip(*out, strict=True))


def sixbar_result(x, theta, fixed, pts, timing, closed, tolerance, mu_min=0.0) -> SixBarPath | None:
    """Check a refined six-bar with the Linkage solver; None if it cannot be built.

    Defects: the crank cannot turn fully, the targets are met out of order, a
    target where the six-bar comes apart (its distance is then ``inf``) or stands
    at a toggle (its distance measured), a target farther than ``tolerance``,
    and a transmission angle (of either dyad, over the whole turn, by
    :meth:`machdyn.linkage.Linkage.transmission_angles`) below ``mu_min``.
    """
    from ._atlas_checks import _in_order

    theta = np.mod(theta, 2 * np.pi)
    try:
        lk = sixbar_linkage(x, fixed, float(theta[0]))
    except Exception:  # a drawing the Linkage refuses (coincident joints …)
        return None
    try:
        m = lk.solve(x[2] + theta, continuation=False)
        turn = lk.solve(x[2] + theta[0] + np.linspace(0, 2 * np.pi, 361))
    except ModelError:  # drawn at a toggle: its branches meet there, neither can be followed
        return None
    # at a toggle (a dyad's two links in line) the Linkage places the joints but takes no
    # derivatives (not ok): the coupler point is there, so is its distance
    P = np.asarray(m.points["P"])
    placed = m.ok | np.isfinite(P)
    distance = np.where(placed, np.abs(P - pts), np.inf)
    defects = []
    mu = float("nan")
    if not np.all(turn.ok):
        defects.append("the six-bar cannot be driven round a whole turn of the crank")
    else:
        angles = [np.asarray(a, float) for a in lk.transmission_angles(turn).values()]
        if angles:
            mu = float(np.nanmin(np.concatenate(angles)))
        if mu < mu_min - np.radians(0.5):
            defects.append(f"transmission angle falls to {np.degrees(mu):.1f} deg")
    in_order = _in_order(theta, closed, timing)
    if not in_order:
        defects.append("order defect: the coupler point meets the targets out of order")
    if not np.all(placed):
        apart = [int(i) + 1 for i in np.flatnonzero(~placed)]
        defects.append(f"the linkage cannot be assembled at targets {apart}")
    if not np.all(m.ok[placed]):
        dead = [int(i) + 1 for i in np.flatnonzero(placed & ~m.ok)]
        defects.append(f"at targets {dead} the six-bar stands at a toggle (a dyad's two links "
                       "in line: a dead point, where its derivatives are undefined)")  # fmt: skip
    if tolerance is not None:
        far = np.flatnonzero(~(distance <= tolerance))
        if far.size:
            defects.append(f"targets {[int(i) + 1 for i in far]} are farther than {tolerance:g}")
    (l1, l2), chain = TOPOLOGIES[fixed["topology"]]
    name = f"{chain} (dyad on links {l1} and {l2}, point on link {fixed['on']})"
    return SixBarPath(lk, name, x, fixed, pts, theta, distance, tuple(defects), mu_min=mu,
                      in_order=in_order)  # fmt: skip


def _sixbar_path(atlas, pts, timing, closed, n, tolerance, mu_min, retrieve, refine_count, client,
                 start, deadline=_NEVER):  # fmt: skip
    """:func:`path_from_atlas` on a six-bar atlas (:mod:`machdyn.synthesis.sixbar_path`)."""
    from .. import jit

    size = float(np.max(np.abs(pts - pts.mean())))
    compiled = jit.mode() != "off" and jit.load()  # one choice for the whole synthesis
    # six-bars: many atlas entries draw nearly the same curve, so many are screened; timed
    # targets many more (their fit is over-determined: real local minima near the truth)
    screen, most = (SIXBAR_SCREEN, SIXBAR_POLISH_MAX) if timing is None else SIXBAR_TIMED
    rounds, long = SIXBAR_ROUNDS[timing is not None], SIXBAR_LONG if compiled else (0, 0)
    if not compiled and timing is not None:  # MACHDYN_JIT=off: the NumPy loop's smaller budget
        (screen, most), rounds = SIXBAR_TIMED_NUMPY, 1
    elif not compiled:  # (untimed: no third round, whose placements cost seconds in NumPy)
        rounds = min(rounds, 2)
    options = dict(timing=timing, compiled=compiled)
    checked: dict[int, Any] = {}  # the Linkage's check of the fits met so far, by id

    def check(fit):
        if id(fit) not in checked:
            checked[id(fit)] = (fit, sixbar_result(fit[0], fit[1], fit[3], pts, timing, closed,
                                                   tolerance, mu_min))  # fmt: skip
        return checked[id(fit)][1]

    polished: dict[int, Any] = {}  # the fits polished long so far, by id

    def polish_long(order):
        """Polish ``fits[i]`` for ``i`` in ``order`` :data:`SIXBAR_LONG` steps (once each)."""
        met = False
        for i in order:
            if id(fits[i]) in polished:
                continue
            x, th, rms, fx = fits[i]
            more = refine_sixbar(x, th, fx, pts, iterations=long[1], **options)
            fits[i] = (*more, fx) if more[2] <= rms else fits[i]
            polished[id(fits[i])] = fits[i]
            if fits[i][2] <= SIXBAR_MET * size:
                met = met or getattr(check(fits[i]), "ok", False)
        return met

    fits, loop, met, near, seen, scan, memo = [], [], False, False, set(), 0.0, {}
    t_begin = time.perf_counter()
    for round_ in range(rounds):  # rounds of fresh starts while none meets the targets
        gate = SIXBAR_GATE[timing is not None]
        crawl = min((f[2] for f in fits), default=np.inf) <= SIXBAR_CRAWL * size
        if timing is None and round_ >= gate and crawl:
            break  # an untimed fit crawling to the targets: the long polish's, not a wider round
        if round_ >= gate and long[0] and not (met or near or deadline.passed()):
            # a late round only while the best fits, polished long, leave the targets unmet
            fits.sort(key=lambda f: f[2])
            met = polish_long(range(min(long[0], len(fits))))
        if met or near or (round_ and deadline.passed()):
            break
        t0 = time.perf_counter()
        starts = sixbar_starts(atlas, pts, timing, closed, retrieve, screen * refine_count,
                               client, compiled, round_, fits, memo=memo)  # fmt: skip
        starts = [s for s in starts if s[0].tobytes() not in seen]
        seen.update(s[0].tobytes() for s in starts)
        scan += time.perf_counter() - t0
        steps = SIXBAR_POLISH // 2 if round_ else SIXBAR_POLISH  # later rounds: shorter
        later = SIXBAR_LATER_TIMED if round_ and timing is not None else (30, most)
        if round_ == 2 and timing is not None:  # the neighbour round
            later = SIXBAR_NEIGHBOUR_POLISH
        if round_ > 2 and timing is not None:  # a kind round: polished per kind scanned
            later = (later[0], SIXBAR_KIND_POLISH * max(1, len(memo.get("round_kinds", ()))))
        more, met = polished_sixbars(starts, pts, later[1], check, steps, screen=later[0],
                                     **options)  # fmt: skip
        fits += more
        best = min(fits, key=lambda f: f[2], default=None)
        if (
            timing is None
            and not (met or loop or deadline.passed())
            and best
            and best[3]["topology"] == 1
        ):
            # untimed Watt II 1-4 (two four-bars in series) unmet: fitted loop by loop, once
            loop = second_loop_fits(fits, pts, compiled)
            fits += loop
            met = any(f[2] <= SIXBAR_MET * size and getattr(check(f), "ok", False) for f in loop)
        near = min((f[2] for f in fits), default=np.inf) <= SIXBAR_NEAR * size
    fits.sort(key=lambda f: f[2])
    if not met and long[0] and not deadline.passed():  # the best crawl along narrow valleys:
        order = list(range(min(long[0], len(fits))))  # polish longer (and the best loop fit)
        order += [i for i, f in enumerate(fits) if loop and f is loop[0] and i >= long[0]]
        polish_long(order)
    for fit in fits[:refine_count]:
        check(fit)
    results = [r for _, r in checked.values() if r is not None]
    results.sort(key=_rank)
    t2 = time.perf_counter()
    chosen, rejected = [], []
    for r in results:
        if not r.ok:
            rejected.append(r)
        elif all(np.max(np.abs(r.design[3:] - c.design[3:])) > 0.02 * size for c in chosen):
            chosen.append(r)
    chosen = chosen[:n]
    best = chosen[0] if chosen else (rejected[0] if rejected else None)
    worst = float(np.max(best.distance)) / size if best is not None else np.inf
    note = _far_note(best, size, "six-bar")
    if best is not None and worst <= NEAR and not chosen:  # near, but every one has a defect
        defects = "; ".join(best.defects)
        note = (f"every six-bar found has a defect (see rejected); the best, {worst:.1e} of the "
                f"targets' size from them at worst: {defects}")  # fmt: skip
    seconds = {"retrieve": scan, "refine": t2 - t_begin - scan,
               "total": time.perf_counter() - start}  # fmt: skip
    note = _limit_note(note, deadline, deadline.at - start, seconds["total"])
    return PathCandidates(tuple(chosen), tuple(rejected[: max(n, 5)]), pts, worst <= NEAR, note,
                          seconds)  # fmt: skip
