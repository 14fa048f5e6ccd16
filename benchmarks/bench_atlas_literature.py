"""Path synthesis from the atlas on the literature's classic four-bar targets.

Run:
    pip install -e ".[bench]"        # pylinkage 1.3.0 (the PSO peer; never a run-time need)
    python benchmarks/bench_atlas_literature.py --atlas ~/.cache/machdyn/fourbar.atlas [--no-pso]
        [--seeds 5] [--seed 0] [--cases case3,case4]
        [--multistart 1500]   # an independent check of cases 3 and 4's optimum (minutes)

The targets, their constraints and the earlier methods' solution vectors are in
``benchmarks/data/path_literature.toml`` (its header names the source, file by file).
For each case this script

1. re-evaluates every published solution vector with the common error definition
   (:func:`sse_published`: the papers' closed form, written out here, one assembly),
   and checks it against the case's constraints and bounds;
2. runs :func:`machdyn.synthesis.path_from_atlas` under the same constraints (crank or
   not, fixed pivot and ground line, absolute timing, the length bound) and measures
   its result with an independent circle-intersection evaluation (:func:`sse_machdyn`),
   on the same definition: the sum of squared distances from the targets to the coupler
   point at each target's input angle;
3. gives pylinkage's particle swarm (``pylinkage.particle_swarm_optimization``, 100
   particles) the same wall time on the same target, its fitness being the path
   objective machdyn's differential evolution uses, and measures its result the same way.
   machdyn and the swarm take turns, ``--seeds`` times per case (each swarm seed gets
   the wall time of the machdyn run just before it); the median and the worst ratio of
   the swarm's SSE to machdyn's over the seeds are printed (``--seeds 1 --seed S``: one).
   The swarm gets as many whole iterations as fit in that time (at least one), and is
   also read when stopped at that time exactly; its generator is seeded (pylinkage
   1.3 leaves it unseeded), so a seed gives the same swarm on every run.

Where machdyn's problem differs from the paper's (a bound it cannot hold, the other
assembly than the papers' formula), the table says so.
"""

from __future__ import annotations

import argparse
import time
import tomllib
from pathlib import Path

import numpy as np

from machdyn import jit
from machdyn.synthesis import open_atlas, path_from_atlas

DATA = Path(__file__).with_name("data") / "path_literature.toml"


def load_cases(path: Path = DATA) -> dict:
    """The cases of the data file, with points as complex arrays and angles in radians."""
    cases = tomllib.loads(path.read_text())
    for case in cases.values():
        case["targets"] = np.array([complex(x, y) for x, y in case["points"]])
        if "theta2_deg" in case:
            case["theta2"] = np.radians(case["theta2_deg"])
    return cases


def coupler_published(x: np.ndarray, theta2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The papers' coupler point (Freudenstein's half-angle form, minus root), placed.

    ``x = r1 r2 r3 r4 rcx rcy x0 y0 θ0``. Returns the points and whether the
    linkage closes at each angle (a negative discriminant: it does not; the
    papers' code then takes the real part of a complex angle).
    """
    r1, r2, r3, r4, rcx, rcy, x0, y0, th0 = x[:9]
    k1, k4 = r1 / r2, r1 / r3
    k5 = (r4**2 - r1**2 - r2**2 - r3**2) / (2 * r3 * r2)
    c, s = np.cos(theta2), np.sin(theta2)
    d = c - k1 + k4 * c + k5
    e = -2 * s
    f = k1 + (k4 - 1) * c + k5
    disc = e**2 - 4 * d * f
    theta3 = 2 * np.arctan((-e - np.sqrt(np.maximum(disc, 0.0))) / (2 * d))
    local = r2 * np.exp(1j * theta2) + (rcx + 1j * rcy) * np.exp(1j * theta3)
    return complex(x0, y0) + np.exp(1j * th0) * local, disc >= 0


def angles_of(case: dict, x: np.ndarray) -> np.ndarray:
    """Input angle at each target for a design vector of the case."""
    n = case["targets"].size
    if case["timing"] == "absolute":
        return case["theta2"]
    if case["timing"] == "step":
        return x[9] + np.arange(n) * np.radians(case["step_deg"])
    return np.asarray(x[9 : 9 + n])


def sse_published(case: dict, x) -> tuple[float, bool]:
    """SSE of a published vector, and whether the linkage closes at every target."""
    x = np.asarray(x, dtype=float)
    P, ok = coupler_published(x, angles_of(case, x))
    return float(np.sum(np.abs(P - case["targets"]) ** 2)), bool(ok.all())


def constraint_report(case: dict, lengths, coupler, placement, theta) -> list[str]:
    """The case's constraints and bounds a design breaks (empty: none)."""
    out = []
    r = np.asarray(lengths, float)
    srt = np.sort(r)
    grashof = srt[0] + srt[3] <= srt[1] + srt[2]
    if "crank" in case["constraints"] and not (grashof and np.argmin(r) == 1):
        out.append("not a Grashof crank (r2 shortest)")
    if "grashof" in case["constraints"] and not grashof:
        out.append("not Grashof")
    b = case["bounds"]
    if np.any(r < b["lengths"][0]) or np.any(r > b["lengths"][1]):
        out.append(f"a length outside {b['lengths']}")
    if np.any(np.abs(coupler) > b["coupler"][1]):
        out.append(f"rcx/rcy outside {b['coupler']}")
    if "placement" in b and np.any(np.abs(placement) > b["placement"][1]):
        out.append(f"x0/y0 outside {b['placement']}")
    if "order" in case["constraints"]:
        steps = np.mod(np.diff(theta), 2 * np.pi)
        if not (np.all(steps <= np.pi) or np.all(steps >= np.pi)):
            out.append("targets out of order")
    return out


def sse_machdyn(case: dict, result) -> tuple[float, bool]:
    """SSE of machdyn's result by circle intersection (not machdyn's solver), and its assembly.

    The assembly is the side of ``A O4`` that reproduces the linkage's own pose at the
    first target; the second value is True when that is the papers' (minus-root) one.
    """
    pl = result.linkage
    r1, r2, r3, r4 = pl.fourbar.lengths
    p, delta = pl.fourbar.coupler
    theta = np.asarray(result.theta2, float)

    def point(t, side):
        a = r2 * np.exp(1j * t)
        d = a - r1  # O4 → A
        dist = np.abs(d)
        along = (r4**2 - r3**2 + dist**2) / (2 * dist)
        h = np.sqrt(np.maximum(r4**2 - along**2, 0.0))
        b = r1 + (d / dist) * (along + 1j * side * h)  # B on one side of O4 → A
        return pl.O2 + np.exp(1j * pl.theta1) * (a + p * np.exp(1j * delta) * (b - a) / r3)

    own = pl.pose(theta[:1])[2][0]
    side = min((1.0, -1.0), key=lambda s: abs(point(theta[0], s) - own))
    P = point(theta, side)
    x = np.array([r1, r2, r3, r4, p * np.cos(delta), p * np.sin(delta), pl.O2.real,
                  pl.O2.imag, pl.theta1])  # fmt: skip
    papers = abs(coupler_published(x, theta[:1])[0][0] - P[0]) < 1e-9 * (1 + abs(P[0]))
    return float(np.sum(np.abs(P - targets_of(case, result)) ** 2)), bool(papers)


def least_sse(case: dict, res) -> tuple:
    """Of machdyn's candidates (ranked by their worst distance), the one of least SSE.

    Returns it, its SSE (:func:`sse_machdyn`; a dropped repeated point counted twice)
    and whether it is on the papers' assembly.
    """
    best = None
    for r in res.candidates or res.rejected[:1]:
        sse, papers = sse_machdyn(case, r)
        if r.targets.size < case["targets"].size:  # a dropped repeated point counts twice
            sse += float(np.abs(r.distance[0]) ** 2)
        if best is None or sse < best[1]:
            best = (r, sse, papers)
    return best


def targets_of(case: dict, result) -> np.ndarray:
    """The targets machdyn was given (a closed path's repeated last point dropped)."""
    return result.targets


def run_machdyn(case: dict, atlas):
    """machdyn under the case's constraints: the result, wall and CPU seconds (this process)."""
    targets = case["targets"]
    closed = case["closed"]
    if closed and abs(targets[-1] - targets[0]) < 1e-12:
        # the papers' error counts the repeated first point twice, each copy with its own
        # input angle: the sum over the points of an open path (machdyn would drop the
        # repeat of a closed one). The order check still asks for less than one turn.
        closed = False
    kw = dict(closed=closed, n=5, mu_min=0.0, crank="crank" in case["constraints"])
    b = case["bounds"]
    kw["max_length"] = min(b["lengths"][1], b["coupler"][1])  # |rcx|, |rcy| <= p
    if "placement" in b:
        lo, hi = b["placement"]
        kw["pivot_box"] = (lo, lo, hi, hi)
    if case["timing"] == "absolute":
        kw.update(timing=case["theta2"], absolute_timing=True)
    elif case["timing"] == "step":
        kw.update(timing=np.arange(targets.size) * np.radians(case["step_deg"]))
    if "fixed_placement" in case:
        x0, y0, th0 = case["fixed_placement"]
        kw.update(O2=complex(x0, y0), theta1=th0)
    t0, c0 = time.perf_counter(), time.process_time()
    res = path_from_atlas(targets, atlas, **kw)
    return res, time.perf_counter() - t0, time.process_time() - c0


def multistart(case: dict, count: int, seed: int = 0) -> tuple[float, np.ndarray, int]:
    """An independent check of the optimum: ``count`` random starts of bounded least squares.

    Not machdyn's code: the papers' SSE by circle intersection on a random one of the
    two assemblies, scipy's trust-region least squares within the case's length and
    coupler bounds, each result kept only if it closes at every target and meets the
    case's Grashof/crank constraint. Returns the least SSE, its design vector
    (``r1 r2 r3 r4 rcx rcy x0 y0 θ0 [θ2_1]``) and how many results were feasible.
    """
    from scipy.optimize import least_squares

    T, n = case["targets"], case["targets"].size
    step = case["timing"] == "step"
    if case["timing"] == "free":
        raise ValueError("multistart checks the timed cases only")

    def coupler(x, side):
        r1, r2, r3, r4, rcx, rcy, x0, y0, th0 = x[:9]
        t = x[9] + np.arange(n) * np.radians(case["step_deg"]) if step else case["theta2"]
        a = r2 * np.exp(1j * t)
        d = a - r1
        along = (r4**2 - r3**2 + np.abs(d) ** 2) / (2 * np.abs(d))
        h2 = r4**2 - along**2
        b = r1 + d / np.abs(d) * (along + 1j * side * np.sqrt(np.maximum(h2, 0.0)))
        return complex(x0, y0) + np.exp(1j * th0) * (a + (rcx + 1j * rcy) * (b - a) / r3), h2

    def residual(x, side):
        P, h2 = coupler(x, side)
        return np.concatenate([(P - T).real, (P - T).imag, 1e3 * np.minimum(h2, 0.0)])

    rng = np.random.default_rng(seed)
    L, C = case["bounds"]["lengths"][1], case["bounds"]["coupler"][1]
    lo = np.r_[[1e-6] * 4, [-C] * 2, [-np.inf] * (4 if step else 3)]
    hi = np.r_[[L] * 4, [C] * 2, [np.inf] * (4 if step else 3)]
    best, feasible = (np.inf, None), 0
    for _ in range(count):
        s = np.exp(rng.uniform(np.log(0.05), np.log(L)))
        x = np.r_[rng.uniform(0.05, 1, 4) * s, rng.uniform(-1, 1, 2) * s,
                  T.mean().real + rng.uniform(-2, 2), T.mean().imag + rng.uniform(-2, 2),
                  rng.uniform(0, 2 * np.pi, 2 if step else 1)]  # fmt: skip
        side = rng.choice([-1.0, 1.0])
        x = np.clip(x, lo + 1e-9, hi - 1e-9)
        r = least_squares(residual, x, args=(side,), bounds=(lo, hi), max_nfev=400)
        P, h2 = coupler(r.x, side)
        srt = np.sort(r.x[:4])
        ok = bool(np.all(h2 >= 0)) and srt[0] + srt[3] <= srt[1] + srt[2]
        ok = ok and ("crank" not in case["constraints"] or np.argmin(r.x[:4]) == 1)
        sse = float(np.sum(np.abs(P - T) ** 2))
        feasible += ok
        if ok and sse < best[0]:
            best = (sse, r.x)
    return best[0], best[1], feasible


#: Particles of the swarm (each iteration evaluates every one; so does its start).
PARTICLES = 100


def pso(case: dict, seconds: float, seed: int) -> tuple[float, int, float, int]:
    """pylinkage's particle swarm on the 10-number path objective for ``seconds``.

    Returns its SSE after as many whole iterations as fit in ``seconds`` at the time
    its first (untimed) iteration took, at least one, and that count; then its SSE
    when stopped at ``seconds`` of wall time exactly (its best evaluation finished
    by then: with machdyn faster than one iteration, the whole-iteration rule gives
    the swarm more time than machdyn), and how many evaluations it finished by then.
    Both from one run: pylinkage 1.3's swarm keeps its inertia and coefficients
    constant, so its path does not depend on how many iterations it is asked for.
    Its generator (``np.random.default_rng()``, unseeded in pylinkage 1.3) is seeded
    with ``seed`` here, so a seed gives the same swarm on every run.
    """
    import pylinkage as pl

    from machdyn.synthesis.path import _BOUNDS, _BOUNDS_TIMED, _frame, _result, path_objective

    targets = case["targets"]
    timing = None
    if case["timing"] == "absolute":
        timing = case["theta2"] - case["theta2"][0]
    elif case["timing"] == "step":
        timing = np.arange(targets.size) * np.radians(case["step_deg"])
    bounds = _BOUNDS if timing is None else _BOUNDS_TIMED
    lo, hi = np.array([b[0] for b in bounds]), np.array([b[1] for b in bounds])
    scale, centre = _frame(targets)
    crank = pl.Crank(anchor=pl.Ground(0, 0), radius=1.0, angular_velocity=0.1)
    dummy = pl.Linkage([crank.anchor, crank], name="placeholder")  # the PSO needs one
    evals: list = []  # (finished at, cost, dims) of every evaluation of the timed run

    def fitness(_linkage, dims, _pos):
        # mu_min 0: machdyn is given no transmission-angle limit either (run_machdyn)
        cost = float(path_objective(np.asarray(dims), targets, timing=timing, n=120,
                                    mu_min=0.0, scale=scale, centre=centre))  # fmt: skip
        evals.append((time.perf_counter(), cost, np.array(dims, dtype=float)))
        return cost

    def sse(dims) -> float:
        return float(np.sum(_result(dims, 0.0, targets, timing, scale, centre, 0.0, None)
                            .distance ** 2))  # fmt: skip

    run = dict(dimensions=lo.size, n_particles=PARTICLES, bounds=(lo, hi), order_relation=min,
               verbose=False)  # fmt: skip
    unseeded = np.random.default_rng
    np.random.default_rng = lambda *a, **k: unseeded(*a, **k) if a or k else unseeded(seed)
    try:
        t0 = time.perf_counter()
        pl.particle_swarm_optimization(fitness, dummy, iterations=1, **run)
        iters = max(1, int(seconds / (time.perf_counter() - t0)))
        evals.clear()
        t0 = time.perf_counter()
        # one iteration more than the whole-iteration rule's, for the reading at the time
        pl.particle_swarm_optimization(fitness, dummy, iterations=iters + 1, **run)
    finally:
        np.random.default_rng = unseeded
    whole = min(evals[: (iters + 1) * PARTICLES], key=lambda e: e[1])
    timely = [e for e in evals if e[0] - t0 <= seconds] or evals[:1]
    best = min(timely, key=lambda e: e[1])
    return sse(whole[2]), iters, sse(best[2]), len(timely)


def compare(case: dict, at, seeds: list[int], pso_on: bool) -> None:
    """machdyn, then the swarm given machdyn's wall time, once per seed (interleaved)."""
    runs, swarm, split, iters, timely, evaluations = [], [], [], [], [], []
    for seed in seeds:
        res, seconds, cpu = run_machdyn(case, at)
        runs.append((seconds, cpu))
        split.append((res.seconds["retrieve"], res.seconds["refine"]))
        if pso_on:
            try:
                sse, its, sse_at, done = pso(case, seconds, seed)
                swarm.append(sse)
                iters.append(its)
                timely.append(sse_at)
                evaluations.append(done)
            except ImportError:
                print("  pylinkage  not installed (pip install -e '.[bench]')")
                pso_on = False
    best = published_best(case)
    r, sse, papers = least_sse(case, res)
    pl = r.linkage
    p, delta = pl.fourbar.coupler
    broken = constraint_report(case, pl.fourbar.lengths, [p * np.cos(delta), p * np.sin(delta)],
                               [pl.O2.real, pl.O2.imag], r.theta2)  # fmt: skip
    broken += list(r.defects) + ([] if papers else ["the other assembly than the papers'"])
    note = f"  [{'; '.join(broken)}]" if broken else ""
    verdict = "<= best published" if sse <= best * (1 + 1e-9) else "WORSE than published"
    wall, cpu = np.median(runs, axis=0)
    fetch, fit = np.median(split, axis=0)
    print(f"  machdyn    {'atlas + refine':52s} SSE {sse:10.3e}  {wall:5.2f} s "
          f"({cpu:.2f} s CPU; median of {len(runs)}: {', '.join(f'{w:.2f}' for w, _ in runs)} s;"
          f" retrieve {fetch:.3f} s, refine {fit:.3f} s)  {verdict}{note}")  # fmt: skip
    if swarm:
        ratio = np.array(swarm) / max(sse, 1e-300)
        print(f"  pylinkage  {'PSO, same wall time, seeds ' + str(seeds[0]) + '+':52s} SSE "
              f"{np.median(swarm):10.3e} median, {min(swarm):.3e} best seed "
              f"({', '.join(f'{x:.3g}' for x in swarm)}; iterations "
              f"{', '.join(str(i) for i in iters)})")  # fmt: skip
        med, worst = np.median(ratio), ratio.min()
        print(f"  ratio      swarm / machdyn: median {med:.3g}x, worst {worst:.3g}x")
        at = np.array(timely) / max(sse, 1e-300)
        print(f"  same swarm stopped at machdyn's wall time exactly (evaluations "
              f"{', '.join(str(e) for e in evaluations)}): SSE {np.median(timely):.3e} median "
              f"({', '.join(f'{x:.3g}' for x in timely)}); ratio median "
              f"{np.median(at):.3g}x, worst {at.min():.3g}x")  # fmt: skip


def published_best(case: dict) -> float:
    """Least SSE of the published vectors that meet the case's constraints; prints each."""
    best = np.inf
    for pub in case["published"]:
        sse, closes = sse_published(case, pub["x"])
        x = np.asarray(pub["x"], float)
        broken = constraint_report(case, x[:4], x[4:6], x[6:8], angles_of(case, x))
        broken += [] if closes else ["does not close at some target"]
        if not broken:
            best = min(best, sse)
        note = f"  [{'; '.join(broken)}]" if broken else ""
        print(f"  published  {pub['label']:52s} SSE {sse:10.3e}{note}")
    return best


def main() -> None:
    import os

    ap = argparse.ArgumentParser()
    ap.add_argument("--atlas", required=True)
    ap.add_argument("--seed", type=int, default=0, help="the first seed of the swarm")
    ap.add_argument(
        "--seeds",
        type=int,
        default=5,
        metavar="N",
        help="run machdyn and then the swarm N times per case (seeds seed … seed+N-1)",
    )
    ap.add_argument("--cases", default="", help="comma-separated case names (default: all)")
    ap.add_argument("--no-pso", action="store_true")
    ap.add_argument("--multistart", type=int, default=0, metavar="N",
                    help="also check cases 3 and 4 by N random least-squares starts")  # fmt: skip
    args = ap.parse_args()
    if args.multistart:
        for name in ("case3", "case4"):
            t0 = time.perf_counter()
            sse, x, feasible = multistart(load_cases()[name], args.multistart, args.seed)
            print(f"{name}: independent multistart, {args.multistart} starts, {feasible} "
                  f"feasible: least SSE {sse:.6e} ({time.perf_counter() - t0:.0f} s) at "
                  f"{np.array2string(x, precision=4)}")  # fmt: skip
    jit.load()
    at = open_atlas(args.atlas, verify=False)
    print(f"atlas: {len(at):,} entries; load average {os.getloadavg()[0]:.2f} "
          f"on {os.cpu_count()} CPUs")  # fmt: skip
    warm = load_cases()["case5"]["targets"][:-1]
    path_from_atlas(warm, at, n=1)  # warm-up (imports, compiled kernels), untimed and timed
    path_from_atlas(warm, at, n=1, timing=np.radians(20.0) * np.arange(warm.size))
    seeds = list(range(args.seed, args.seed + max(1, args.seeds)))
    wanted = [c for c in args.cases.split(",") if c]
    for name, case in load_cases().items():
        if wanted and name not in wanted:
            continue
        print(f"\n{name}: {case['title']} ({case['targets'].size} points)")
        compare(case, at, seeds, not args.no_pso)
    print(f"\nload average at the end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
