"""Untimed fits re-seeded with one target moved to another near pass of their curve.

Where a coupler curve loops or crosses itself near a target, the curve passes that
target twice, a little apart. A start puts each target at its nearest point of the
placed curve, so it can put a target on the pass the drawing linkage does not use;
the refinement keeps each target on its pass, and the fit then stalls a little off
(``bench_atlas_random.py --seed 4``'s closed case 28, a GCRR whose curve makes a
small loop next to its first target: the fits 0.08 from the drawing linkage in design
numbers ended at 3.1e-4 of the size, in order, with the first target at 6.01 rad of
crank instead of 0.42; moved to the loop's other pass, 5.6e-3 of the size from it,
the same fit refines to 2e-16). A fit through the targets out of order is re-seeded by
:func:`~machdyn.synthesis._atlas_closed._reseeded`; one in order on the wrong pass is
not, and is the business of :func:`_swapped`. Used by
:mod:`~machdyn.synthesis.atlas_path`.
"""

from __future__ import annotations

import numpy as np

from ._atlas_checks import COPY, _design_key, _in_order
from ._atlas_index import _NEVER, _Deadline
from .refine import coupler_and_jacobian, refine
from .valley import polish

__all__: list[str] = []

#: Most distinct unmet fits (on one assembly) whose targets' other passes are tried, per
#: round; most passes tried per fit; a pass is tried when it comes within SWAP_NEAR of the
#: size of its target (the loop of seed 4's closed case 28: 5.6e-3); samples of a turn.
SWAP_FITS = 4
SWAP_MOST = 4
SWAP_NEAR = 2e-2
SWAP_SAMPLES = 720


def _other_passes(fit, pts, size: float) -> list[tuple[float, int, float]]:
    """``(distance, target, angle)`` of the near passes of a fit's curve not its own, nearest first.

    The curve of the fit's design on its assembly, at :data:`SWAP_SAMPLES` input angles
    (where it assembles); a pass is a local minimum of a target's distance along it,
    the fit's own pass the one within two samples of the target's angle (a refined fit's
    angles sit at their nearest points). Those within :data:`SWAP_NEAR` of the size.
    """
    m = SWAP_SAMPLES
    grid = np.linspace(0.0, 2 * np.pi, m, endpoint=False)
    G, _, _, excess = coupler_and_jacobian(fit.x, grid, np.full(m, float(fit.branch[0])))
    with np.errstate(invalid="ignore"):
        d = np.abs(G[None, :] - pts[:, None])  # (K, m)
    d = np.where((excess <= 0.0)[None, :] & np.isfinite(d), d, np.inf)
    minima = (d <= np.roll(d, 1, axis=1)) & (d < np.roll(d, -1, axis=1)) & (d <= SWAP_NEAR * size)
    own = np.round(np.mod(fit.theta, 2 * np.pi) / (2 * np.pi) * m).astype(np.int64)
    out = []
    for k, j in zip(*np.nonzero(minima), strict=True):
        gap = abs(int(j) - int(own[k])) % m
        if min(gap, m - gap) > 2:
            out.append((float(d[k, j]), int(k), float(grid[j])))
    return sorted(out)


def _swapped(fits, pts, options, closed: bool, met: bool, tried: list,
             deadline: _Deadline = _NEVER) -> tuple[list, bool]:  # fmt: skip
    """Untimed ``fits`` and the best few unmet ones with a target moved to another near pass.

    For up to :data:`SWAP_FITS` distinct fits on one assembly that do not meet the
    targets (to :data:`~machdyn.synthesis.atlas_path.UNTIMED_MET` of their size) and
    whose keys are not in ``tried`` (appended to), each of the :data:`SWAP_MOST`
    nearest other passes (:func:`_other_passes`) in turn: the target's angle moved
    there, refined (100 steps of the compiled LM when loaded) and polished. A result
    is kept only when it is nearer than the fit it came from and through the targets
    in order. Nothing once ``met`` or
    past the ``deadline``. Returns the fits (best first) and whether one meets the
    targets (one assembly, in order).
    """
    from .atlas_path import UNTIMED_MET, UNTIMED_NFEV, _solver

    if met or not fits:
        return fits, met
    size = float(np.max(np.abs(pts - pts.mean())))
    solver = _solver(pts, True)
    more: list = []
    count = 0
    for f in fits:
        if count >= SWAP_FITS or deadline.passed():
            break
        if np.ptp(f.branch) != 0 or f.rms <= UNTIMED_MET * size:
            continue
        key = _design_key(f, size)
        if any(np.max(np.abs(key - k)) <= COPY for k in tried):
            continue
        tried.append(key)
        count += 1
        for _, k, angle in _other_passes(f, pts, size)[:SWAP_MOST]:
            theta = f.theta.copy()
            theta[k] = angle
            g = refine(f.x, theta, f.branch, pts, max_nfev=UNTIMED_NFEV[1], solver=solver,
                       **options)  # fmt: skip
            g = g if g.rms <= UNTIMED_MET * size else polish(g, pts, **options)
            # kept only in order: an exact fit out of order is no answer, and one in the
            # fits ends the rounds (_long_polished counts a fit met without its order:
            # bench_atlas_random.py --seed 6's open case 7 then stopped at 1.0e-6)
            if g.rms < f.rms and _in_order(g.theta, closed, None):
                more.append(g)
    if not more:
        return fits, met
    fits = sorted(list(fits) + more, key=lambda f: f.rms)
    met = any(f.rms <= UNTIMED_MET * size and np.ptp(f.branch) == 0
              and _in_order(f.theta, closed, None) for f in more)  # fmt: skip
    return fits, met
