"""Closed untimed targets: the search of every input, and fits re-seeded in order.

A closed path (no timing) is traced in order on one assembly by a linkage whose link 2
turns fully (Barker's GCCC, GCRR and the change points between), or by a rocker on the
arc of one assembly between its toggles. With ``crank=False`` (any input) the search
is :func:`_any_input`: the whole search of ``crank=True`` (the crank rows' retrieval
and pools, held a crank by the refinement), and while none of its fits meets the
targets, pool rounds of every row (:func:`~machdyn.synthesis.atlas_path._untimed_fits`
continued from those fits). A user who relaxes the crank requirement so loses no
answer: the fits of ``crank=True`` are all among those of ``crank=False``. Either
search re-seeds its fits that are no answer with the input angles that take the
targets round the curve in order (:func:`_reseeded`). Used by
:mod:`~machdyn.synthesis.atlas_path`.
"""

from __future__ import annotations

import numpy as np

from ._atlas_checks import COPY, _design_key, _in_order
from ._atlas_index import _NEVER, _Deadline
from .refine import refine
from .valley import polish

__all__: list[str] = []


def _any_input(atlas, pts, retrieve, refine_count, client, options,
               deadline: _Deadline = _NEVER):  # fmt: skip
    """A closed untimed target's fits with any input (``crank=False``), best first.

    First the search of ``crank=True``
    (:func:`~machdyn.synthesis.atlas_path._untimed_fits`: the nearest crank entries,
    the crank rows of the wide pool and of the later rounds' pools, refined with link
    2 held a crank); while none of its fits meets the targets (to
    :data:`~machdyn.synthesis.atlas_path.UNTIMED_MET` of their size, in order, on one
    assembly), the later pool rounds again with every row of the atlas and no crank
    held, from those fits on (:func:`~machdyn.synthesis.atlas_path._worth_a_round`
    decides each). The two searches start from different samples and meet different
    targets (session 11's generator of closed targets from random four-bars, seeds 2
    and 6–9, 150 targets: ``crank=True`` met 142, the any-input search as it was 143,
    each two or three that the other missed); the crank search comes first, so that
    every fit of ``crank=True`` is one here too, and the rows of every class only
    after it. Returns the fits and the time the crank search's retrieval ended.
    """
    from .atlas_path import UNTIMED_MET, _untimed_fits

    size = float(np.max(np.abs(pts - pts.mean())))
    fits, t1 = _untimed_fits(atlas, pts, True, True, retrieve, refine_count, client,
                             dict(options, crank=True), deadline)  # fmt: skip
    if deadline.passed() or any(_answer(f, UNTIMED_MET * size) for f in fits):
        return fits, t1
    fits, _ = _untimed_fits(atlas, pts, True, False, retrieve, refine_count, client, options,
                            deadline, start=fits)  # fmt: skip
    return fits, t1


#: Closed untimed targets: most fits that are no answer (on two assemblies, or through the
#: targets out of their order round the curve) re-seeded in order (see _reseeded), per round.
CLOSED_RESEED = 4


def _reseeded(fits, pts, options, deadline: _Deadline = _NEVER) -> tuple[list, bool]:
    """Closed targets: ``fits`` and the best few that are no answer re-seeded in order.

    A coupler curve that crosses itself near a target has two passes there. Each
    start puts a target at its nearest point of the placed curve
    (:func:`~machdyn.synthesis._atlas_retrieve._start_untimed`), so a start near the
    drawing linkage can put that target on the wrong pass; its refinement then
    keeps it there and ends a few 1e-4 of the size off, out of order (the lead's
    "c1": a GCCC through 12 points every 30° of its crank, whose curve crosses
    itself at the twelfth: every fit ended at 2.7e-4 with 11 targets at their
    angles and the twelfth 135° away, rejected with an order defect). Up to
    :data:`CLOSED_RESEED` distinct fits that are on two assemblies or out of order
    get, on each of their assemblies where link 2 turns fully, the input angles
    that take the targets round the curve in order nearest to them
    (:func:`_in_order_angles`), and are refined (the compiled LM when loaded) and
    polished from there. Returns the fits with the re-seeded ones added (best
    first), and whether one meets the targets (:data:`UNTIMED_MET` of the size,
    one assembly, in order).
    """
    from .atlas_path import UNTIMED_MET, UNTIMED_NFEV, _solver

    size = float(np.max(np.abs(pts - pts.mean())))
    solver = _solver(pts, True)
    more: list = []
    keys: list[np.ndarray] = []
    for f in fits:
        if len(keys) >= CLOSED_RESEED or deadline.passed():
            break
        if _answer(f, None):
            continue
        key = _design_key(f, size)
        if any(np.max(np.abs(key - k)) <= COPY for k in keys):
            continue  # (a copy of a fit re-seeded already)
        keys.append(key)
        for b in np.unique(f.branch):
            theta = _in_order_angles(f.x, float(b), pts)
            if theta is None:
                continue
            branch = np.full(pts.size, float(b))
            g = refine(f.x, theta, branch, pts, max_nfev=UNTIMED_NFEV[1], solver=solver,
                       **options)  # fmt: skip
            more.append(g if g.rms <= UNTIMED_MET * size else polish(g, pts, **options))
    fits = sorted(list(fits) + more, key=lambda f: f.rms)
    return fits, any(_answer(f, UNTIMED_MET * size) for f in fits)


def _answer(fit, within: float | None) -> bool:
    """A closed target's fit on one assembly, through the targets in order (within ``within``)."""
    ok = np.ptp(fit.branch) == 0 and _in_order(fit.theta, True, None)
    return bool(ok and (within is None or fit.rms <= within))


#: Samples of a fit's curve searched for the targets' in-order input angles, and the
#: passes of the curve near the first target tried as its place (see _in_order_angles).
IN_ORDER_SAMPLES = 720
IN_ORDER_PASSES = 3


def _in_order_angles(x, branch: float, pts, m: int = IN_ORDER_SAMPLES) -> np.ndarray | None:
    """Input angles that take the targets round a fit's curve in order, nearest to them.

    The curve of design ``x`` on assembly ``branch`` is sampled at ``m`` input
    angles; of every assignment of the targets to samples in their cyclic order
    (either way round), the one of least sum of squared distances is found by
    dynamic programming (target k's best cost at sample j is its own distance plus
    the least cost of target k − 1 at a sample before j), for each of
    :data:`IN_ORDER_PASSES` places of the first target (the curve's passes nearest
    to it: local minima of its distance). None when link 2 does not turn fully on
    that assembly (its curve is then no closed path).
    """
    from .refine import coupler_and_jacobian

    grid = np.linspace(0.0, 2 * np.pi, m, endpoint=False)
    G, _, _, excess = coupler_and_jacobian(x, grid, np.full(m, branch))
    if np.any(excess > 0.0) or not np.all(np.isfinite(G)):
        return None
    k = pts.size
    cost = np.abs(G[None, :] - pts[:, None]) ** 2  # (K, m)
    c0 = cost[0]
    passes = np.flatnonzero((c0 <= np.roll(c0, 1)) & (c0 < np.roll(c0, -1)))
    passes = passes[np.argsort(c0[passes])][:IN_ORDER_PASSES]
    best, out = np.inf, None
    index = np.arange(m)
    for way in (1, -1):  # the samples taken forward or backward round the curve
        for j0 in passes:
            order = (j0 + way * index) % m  # the samples from the first target's place on
            c = cost[:, order]
            total = np.full(m, np.inf)
            total[0] = c[0, 0]
            back = np.zeros((k, m), dtype=np.int64)
            for i in range(1, k):
                # the least total before each sample (strictly before), and where it is
                run = np.minimum.accumulate(total)
                at = np.maximum.accumulate(np.where(total <= run, index, 0))
                back[i, 1:] = at[:-1]
                total = c[i] + np.concatenate([[np.inf], run[:-1]])
            j = int(np.argmin(total))
            if total[j] < best:
                best = float(total[j])
                path = [j]
                for i in range(k - 1, 0, -1):
                    j = int(back[i, j])
                    path.append(j)
                out = grid[order[np.array(path[::-1])]]
    return out
