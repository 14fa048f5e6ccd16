"""Path synthesis from the atlas on targets from the literature, and against pylinkage's PSO.

Run:
    pip install -e ".[bench]"                 # pylinkage 1.3.0 (the peer; never a run-time need)
    python benchmarks/bench_atlas_literature.py --atlas ~/.cache/machdyn/fourbar.atlas

Each target is synthesised by :func:`machdyn.synthesis.path_from_atlas` (query + refine);
then pylinkage's particle swarm (``pylinkage.particle_swarm_optimization``, local-best
ring PSO, 100 particles) gets the *same wall time* on the same target, its fitness being
the path objective over the same 10 design numbers machdyn's differential evolution uses
(lengths, coupler point, placement, assembly; with timing, θ2 of the first point).
Both results are measured the same way, by :func:`error`: the distance from each
target to the linkage's coupler curve (3,600 samples, then polished), or to the timed
point. The literature's usual figure, the sum of squared distances, is printed too.

Targets (coordinates as given in the cited papers; the closed-form shapes — a line, a
circle, an ellipse — are how they were constructed):

* ``line6``: six points on a vertical straight line, no timing (Kunjur & Krishnamurty,
  "Genetic algorithms in mechanism synthesis", J. Appl. Mech. Robot. 4(2), 1997, problem 2;
  Cabrera, Simon & Prado, "Optimal synthesis of mechanisms with genetic algorithms",
  Mech. Mach. Theory 37, 2002, example 2).
* ``arc5``: five points on a half circle with prescribed timing θ2 = 30°, 45°, 60°, 75°,
  90° (Cabrera et al. 2002, example 1).
* ``closed18``: 18 points around a closed path, no timing (McGarva, "Rapid search and
  selection of path generating mechanisms from a library", Mech. Mach. Theory 29, 1994;
  Kunjur & Krishnamurty 1997, problem 3; Cabrera et al. 2002, example 3).
* ``ellipse10``: ten points on an ellipse (centre (10, 10), semi-axes 10 and 8, every
  40°), no timing (Ullah & Kota, "Optimal synthesis of mechanisms for path generation
  using Fourier descriptors and global search methods", J. Mech. Des. 119, 1997;
  Acharyya & Mandal, "Performance of EAs for four-bar linkage synthesis", Mech. Mach.
  Theory 44, 2009, case 3 with timing).

The published errors are not reproduced here: the papers could not be read from this
machine, and a number typed from memory is not a citation. The table's "published"
column says so; fill it in from the papers (their objective is the sum of squared
distances, printed as "SSE").
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from machdyn import jit
from machdyn.synthesis import open_atlas, path_from_atlas
from machdyn.synthesis.path import _BOUNDS, _BOUNDS_TIMED, _frame, path_objective

TARGETS = {
    "line6": dict(
        points=[(20, 20), (20, 25), (20, 30), (20, 35), (20, 40), (20, 45)], closed=False
    ),
    "arc5": dict(
        points=[(0, 0), (1.9098, 5.8779), (6.9098, 9.5106), (13.09, 9.5106), (18.09, 5.8779)],
        closed=False,
        timing=np.radians([30, 45, 60, 75, 90]),
    ),
    "closed18": dict(
        points=[
            (0.5, 1.1),
            (0.4, 1.1),
            (0.3, 1.1),
            (0.2, 1.0),
            (0.1, 0.9),
            (0.005, 0.75),
            (0.02, 0.6),
            (0.0, 0.5),
            (0.0, 0.4),
            (0.03, 0.3),
            (0.1, 0.25),
            (0.15, 0.2),
            (0.2, 0.3),
            (0.3, 0.4),
            (0.4, 0.5),
            (0.5, 0.7),
            (0.6, 0.9),
            (0.6, 1.0),
        ],
        closed=True,
    ),
    "ellipse10": dict(
        points=[
            (20, 10),
            (17.66, 15.142),
            (11.736, 17.878),
            (5, 16.928),
            (0.60307, 12.736),
            (0.60307, 7.2638),
            (5, 3.0718),
            (11.736, 2.1215),
            (17.66, 4.8577),
        ],
        closed=True,
    ),
}


def error(linkage, targets, timing=None, theta0=None) -> np.ndarray:
    """Distance from each target to a placed four-bar's coupler curve (or timed point)."""
    if timing is not None:
        P, ok = linkage.pose(theta0 + timing)[2:]
        return np.where(ok, np.abs(P - targets), np.inf)
    th = np.linspace(0, 2 * np.pi, 3600, endpoint=False)
    P, ok = linkage.pose(th)[2:]
    d = np.where(ok[None, :], np.abs(P[None, :] - targets[:, None]), np.inf)
    i = np.argmin(d, axis=1)
    out = d[np.arange(targets.size), i]
    for k in range(targets.size):  # polish on a fine grid around the nearest sample
        fine = th[i[k]] + np.linspace(-2e-3, 2e-3, 401)
        Pf, okf = linkage.pose(fine)[2:]
        out[k] = min(out[k], np.min(np.where(okf, np.abs(Pf - targets[k]), np.inf)))
    return out


def pso(targets, timing, seconds: float, seed: int):
    """pylinkage's particle swarm on the 10-number path objective, for ``seconds``."""
    import pylinkage as pl

    bounds = _BOUNDS if timing is None else _BOUNDS_TIMED
    lo = np.array([b[0] for b in bounds])
    hi = np.array([b[1] for b in bounds])
    scale, centre = _frame(targets)
    crank = pl.Crank(anchor=pl.Ground(0, 0), radius=1.0, angular_velocity=0.1)
    dummy = pl.Linkage([crank.anchor, crank], name="placeholder")  # the PSO needs one

    def fitness(_linkage, dims, _pos):
        return float(path_objective(np.asarray(dims), targets, timing=timing, n=120,
                                    scale=scale, centre=centre))  # fmt: skip

    np.random.seed(seed)  # noqa: NPY002  (pylinkage's PSO draws from NumPy's global generator)
    t0 = time.perf_counter()
    pl.particle_swarm_optimization(fitness, dummy, dimensions=lo.size, n_particles=100,
                                   iterations=1, bounds=(lo, hi), order_relation=min,
                                   verbose=False)  # fmt: skip
    per_iter = time.perf_counter() - t0
    iters = max(1, int(seconds / per_iter))
    t0 = time.perf_counter()
    ens = pl.particle_swarm_optimization(fitness, dummy, dimensions=lo.size, n_particles=100,
                                         iterations=iters, bounds=(lo, hi), order_relation=min,
                                         verbose=False)  # fmt: skip
    spent = time.perf_counter() - t0
    best = np.asarray(ens.top(1)[0].dimensions if hasattr(ens, "top") else ens[0].dimensions)
    return best, spent, iters


def linkage_of(x, targets, timing):
    """The placed four-bar of a design vector (as machdyn's DE decodes it)."""
    from machdyn.synthesis.path import _result

    scale, centre = _frame(targets)
    res = _result(x, 0.0, targets, timing, scale, centre, 0.0, None)
    return res


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--atlas", required=True)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    jit.load()
    at = open_atlas(args.atlas)
    print(f"atlas: {len(at):,} entries\n")
    head = f"{'target':10s} {'pts':>3s} {'kind':>14s} {'published':>10s} " \
           f"{'machdyn max':>12s} {'machdyn SSE':>12s} {'time':>6s} " \
           f"{'PSO max':>10s} {'PSO SSE':>10s} {'PSO iters':>9s} {'ratio':>8s}"  # fmt: skip
    print(head)
    for name, spec in TARGETS.items():
        targets = np.array([complex(*p) for p in spec["points"]])
        timing = spec.get("timing")
        closed = spec["closed"]
        t0 = time.perf_counter()
        res = path_from_atlas(targets, at, closed=closed, timing=timing, n=1, mu_min=0.0)
        t = time.perf_counter() - t0
        best = res.best
        th0 = None if timing is None else best.theta2[0] - timing[0]
        d = error(best.linkage, targets, timing, th0)
        try:
            x, _spent, iters = pso(targets, timing, t, args.seed)
            r = linkage_of(x, targets, timing)
            th0p = None if timing is None else r.theta2[0]
            dp = error(r.linkage, targets, timing, th0p)
            pso_max, pso_sse = f"{dp.max():.3e}", f"{np.sum(dp**2):.3e}"
            ratio = f"{np.sum(dp**2) / max(np.sum(d**2), 1e-300):.1e}"
        except ImportError:
            pso_max = pso_sse = "n/a"
            iters, ratio = 0, "-"
        kind = ("timed " if timing is not None else "") + ("closed" if closed else "open")
        print(f"{name:10s} {targets.size:3d} {kind:>14s} {'see paper':>10s} {d.max():12.3e} "
              f"{np.sum(d**2):12.3e} {t:6.2f} {pso_max:>10s} {pso_sse:>10s} {iters:9d} "
              f"{ratio:>8s}")  # fmt: skip
        if best.defects:
            print(f"{'':10s} machdyn's best has defects: {'; '.join(best.defects)}")
        if not res.near:
            print(f"{'':10s} {res.note}")


if __name__ == "__main__":
    main()
