"""Path synthesis from the atlas on targets traced by random four-bars of every Barker class.

``bench_atlas.py --recovery`` draws crank-rockers only (link 2 the shortest, the others
1.5–6 times it). Here the linkages are drawn the way someone checking the tool from
outside might draw them: every link log-uniform over a ratio of ``--spread`` (the atlas
holds 1/5–5 crank lengths), a coupler point up to ``1.8·r3`` from A at any angle, either
assembly, placed, turned and scaled at random; only linkages within 2 % of a change point
(of the links' sum) are drawn again. Four kinds of target:

* ``closed``: 12 points at random input angles round the curve of a linkage whose input
  turns fully (GCCC, GCRR), untimed, ``crank=False``;
* ``open``: 9 points evenly over a random 75–180° of a fully turning input, or over the
  longest run a rocker input reaches (from 5 % to 95 % of it), untimed, ``crank=False``;
* ``timed``: 8 points at random input angles of a fully turning input, with their timing.
* ``open-timed``: 7 points drawn as ``open`` (most inputs rock), with their input angles as
  the timing, ``crank=False``; recovered also means reached at the prescribed steps of the
  result's own input, assembled all the way between the targets (no toggle).

Recovered: the best candidate's (or, with none free of defects, the best rejected one's)
largest distance to the targets, by the tests' independent point-to-curve distance
(``tests/test_synthesis_path_atlas._curve_distance``: circle intersections and a scalar
minimisation), is at most 1e-6 of the targets' size. ``mu_min=0`` (recovery, not the
defect filter). CPU seconds of each synthesis (the budget is 3 s).

Run:
    python benchmarks/bench_atlas_random.py --atlas ATLAS_1E7 [--seed 1] [--count 30]
        [--kinds closed,open,timed,open-timed] [--spread 5] [--verbose]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.test_synthesis_path_atlas import _coupler, _curve_distance

from machdyn import jit
from machdyn.errors import AssemblyError
from machdyn.fourbar import FourBar
from machdyn.synthesis import open_atlas, path_from_atlas

#: Input angles a linkage is sampled at to draw its targets.
GRID = 720


def random_fourbar(rng, spread: float):
    """A random four-bar (any class, clear of a change point) and the assembly drawn."""
    while True:
        r = np.exp(rng.uniform(-0.5, 0.5, 4) * np.log(spread))
        s = np.sort(r)
        if s[3] >= s[:3].sum() or abs(s[0] + s[3] - s[1] - s[2]) < 0.02 * r.sum():
            continue
        p, delta = rng.uniform(0.2, 1.8) * r[2], rng.uniform(-np.pi, np.pi)
        try:
            return FourBar(*r, coupler=(p, delta)), int(rng.choice([1, 2]))
        except AssemblyError:
            continue


def draw_target(rng, kind: str, spread: float):
    """(targets, timing or None, Barker class) of one random linkage, for ``kind``."""
    theta = np.linspace(0, 2 * np.pi, GRID, endpoint=False)
    points = 7 if kind == "open-timed" else 9
    while True:
        fb, form = random_fourbar(rng, spread)
        m = fb.solve(theta, 1.0, form=form)
        ok = np.asarray(m.ok)
        turns = bool(ok.all())
        if kind in ("closed", "timed") and not turns:
            continue
        if kind == "closed":
            idx = np.sort(rng.choice(GRID, 12, replace=False))
        elif kind == "timed":
            idx = np.sort(rng.choice(GRID, 8, replace=False))
        elif turns:
            start, span = rng.integers(GRID), rng.integers(GRID // 4, GRID // 2 + 1)
            idx = (start + np.linspace(0, span, points).astype(int)) % GRID
        else:
            k = np.flatnonzero(ok)
            runs = np.split(k, np.flatnonzero(np.diff(k) != 1) + 1)
            if ok[0] and ok[-1] and len(runs) > 1:  # the run through 0 is one run
                runs = [np.concatenate([runs[-1], runs[0]]), *runs[1:-1]]
            run = max(runs, key=len)
            if run.size < GRID // 12:
                continue
            idx = run[np.linspace(0.05 * run.size, 0.95 * run.size - 1, points).astype(int)]
        place = complex(*rng.normal(0, 3, 2))
        turn = np.exp(1j * rng.uniform(0, 2 * np.pi)) * np.exp(rng.uniform(np.log(0.5), np.log(5)))
        targets = place + turn * np.asarray(m.coupler)[idx]
        timing = None
        if kind == "timed":
            timing = theta[idx] - theta[idx[0]]
        elif kind == "open-timed":  # (an arc through θ = 0 unwrapped)
            timing = np.unwrap(theta[idx]) - theta[idx[0]]
        return targets, timing, fb.barker_class


def _timed_miss(found, targets, timing) -> float:
    """A result's largest distance to the targets at the prescribed steps of its own input.

    Its coupler point by circle intersection (``tests/test_synthesis_path_atlas._coupler``,
    no machdyn solver) at ``θ0 + Δ_k`` on either assembly; infinite where the input's reach
    (the law of cosines) does not hold every angle between the first target and the last.
    """
    pl = found.linkage
    r1, r2, r3, r4 = pl.fourbar.lengths
    between = found.theta2[0] + np.linspace(0.0, timing[-1], 2001)
    d = np.abs(r2 * np.exp(1j * between) - r1)
    if np.any(d < abs(r3 - r4)) or np.any(d > r3 + r4):
        return np.inf
    theta = found.theta2[0] + timing
    return min(float(np.max(np.abs(_coupler(pl.fourbar.lengths, pl.fourbar.coupler, pl.O2,
                                             pl.theta1, side, theta) - targets)))
               for side in (1.0, -1.0))  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--atlas", required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=30)
    ap.add_argument("--kinds", default="closed,open,timed")
    ap.add_argument("--spread", type=float, default=5.0, help="largest over smallest link")
    ap.add_argument("--verbose", action="store_true")
    args = ap.parse_args()
    jit.load()
    at = open_atlas(args.atlas, verify=False)
    warm = FourBar(4, 1, 3, 3.5, coupler=(2.0, 0.5)).solve(np.linspace(0, 6, 12)).coupler
    path_from_atlas(np.asarray(warm), at, n=1, mu_min=0.0)  # the first call loads pages
    print(f"machine load {' '.join(f'{v:.1f}' for v in os.getloadavg())}")
    for kind in args.kinds.split(","):
        kinds = ["closed", "open", "timed", "open-timed"]
        rng = np.random.default_rng([args.seed, kinds.index(kind)])
        errors, cpus, misses = [], [], []
        for i in range(args.count):
            targets, timing, cls = draw_target(rng, kind, args.spread)
            size = float(np.max(np.abs(targets - targets.mean())))
            c0 = time.process_time()
            res = path_from_atlas(targets, at, closed=kind in ("closed", "timed"), timing=timing,
                                  crank=kind == "timed", n=3, mu_min=0.0)  # fmt: skip
            cpu = time.process_time() - c0
            found = (res.candidates or res.rejected)[:3]
            e = min((_timed_miss(c, targets, timing) if kind == "open-timed"
                     else float(np.max(_curve_distance(c, targets))) for c in found),
                    default=np.inf)  # fmt: skip
            e /= size
            errors.append(e)
            cpus.append(cpu)
            if e > 1e-6:
                misses.append(f"{i} {cls} {e:.1e}")
            if args.verbose:
                print(f"    {i:3d} {kind:6s} {cls:5s} {e:.1e}  CPU {cpu:.2f} s", flush=True)
        errors, cpus = np.array(errors), np.array(cpus)
        print(f"  random four-bars ({kind}, seed {args.seed}, spread {args.spread:g}): "
              f"{int(np.sum(errors <= 1e-6))} of {args.count} to <= 1e-6 of the size; "
              f"misses [{'; '.join(misses)}]; CPU median {np.median(cpus):.2f} s, "
              f"max {cpus.max():.2f} s, over 3 s: {int(np.sum(cpus > 3))}", flush=True)  # fmt: skip
    print(f"machine load {' '.join(f'{v:.1f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()
