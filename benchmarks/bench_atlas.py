"""Benchmarks of the coupler-curve atlas: build rate, Dask scaling, disk, query and synthesis time.

Run:
    python benchmarks/bench_atlas.py               # 2^19 entries; Dask scaling 1 vs 2 workers
    python benchmarks/bench_atlas.py --atlas DIR   # also query and synthesis on an existing atlas
    python benchmarks/bench_atlas.py --atlas SIXBAR_DIR --sixbar-recovery 60
                                                   # six-bar recovery rate (untimed, timed)
    python benchmarks/bench_atlas.py --build DIR --count 10000000 --scheduler local
                                                   # the big build (once, late: minutes)
    python benchmarks/bench_atlas.py --atlas DIR --recovery 20 --seed 7
                                                   # four-bar recovery: closed, timed, open,
                                                   # open-timed targets of random crank-rockers
    python benchmarks/bench_atlas.py --atlas DIR --hard [--repeats 3] [--time-limit 2.5]
                                                   # awkward open targets: time per target
    python benchmarks/bench_atlas.py --atlas DIR --cold 5 [--kinds open,closed]
                                                   # the first synthesis of a fresh process

Targets (issue 14): >= 10^7 four-bars in <= 15 min and <= 4 GB on the 2-core machine;
linear in workers within +-20 % from 1 to 2; query on a 10^7 atlas <= 1 s; query + refine
of 10 candidates <= 3 s.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from machdyn import jit
from machdyn.fourbar import FourBar
from machdyn.synthesis import PlacedFourBar, build_atlas, open_atlas, path_from_atlas


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def timed_cpu(fn):
    """Wall and CPU seconds of ``fn()`` (this process, every thread) and its result.

    On the shared machine a process may get a small share of a core (load average
    above 10 on 2 cores): CPU seconds are then the better estimate of the time on
    a free core, wall seconds an upper bound.
    """
    t0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return time.perf_counter() - t0, time.process_time() - c0, out


def disk(folder: Path) -> int:
    return sum(f.stat().st_size for f in folder.glob("*"))


def _cpu_timed_chunk(*args):
    """``build_chunk`` as a Dask task that also returns the CPU seconds its process spent."""
    from machdyn.synthesis.atlas_store import build_chunk

    t0 = time.process_time()
    build_chunk(*args)
    return time.process_time() - t0


def scaling(count: int, chunk: int, rounds: int) -> None:
    """Dask LocalCluster, 1 worker vs 2 workers, interleaved; the cluster start is not counted.

    Besides the wall-clock rate, each task reports the CPU seconds it got: their sum
    over the wall time is the number of cores the workers actually had. On a shared
    machine (other jobs on the same two cores) the 2-worker rate can only rise by the
    cores obtained, so the rate per core obtained is printed too: equal per-core rates
    mean Dask adds no serial part of its own.
    """
    from distributed import Client, LocalCluster, wait

    from machdyn.synthesis.atlas_dask import WORKER_ENV
    from machdyn.synthesis.atlas_store import Manifest, build_chunk

    rates: dict[int, list[float]] = {1: [], 2: []}
    cores: dict[int, list[float]] = {1: [], 2: []}
    clusters = {
        w: LocalCluster(n_workers=w, threads_per_worker=1, processes=True,
                        dashboard_address=None, env=WORKER_ENV)
        for w in (1, 2)
    }  # fmt: skip
    try:
        clients = {w: Client(c) for w, c in clusters.items()}
        for w, client in clients.items():  # warm-up: compile/load kernels in every worker
            folder = Path(tempfile.mkdtemp(prefix="bench_atlas_warm"))
            recipe = Manifest(count=2 * w * 1000, chunk_size=1000).to_json()
            wait(
                [
                    client.submit(build_chunk, str(folder), recipe, i, True, pure=False)
                    for i in range(2 * w)
                ]
            )
            shutil.rmtree(folder)
        for r in range(rounds):
            for w in (1, 2) if r % 2 == 0 else (2, 1):
                folder = Path(tempfile.mkdtemp(prefix="bench_atlas_scale"))
                recipe = Manifest(count=count, chunk_size=chunk, seed=r).to_json()
                n = -(-count // chunk)
                t0 = time.perf_counter()
                futures = [
                    clients[w].submit(_cpu_timed_chunk, str(folder), recipe, i, True, pure=False)
                    for i in range(n)
                ]
                cpu = sum(clients[w].gather(futures))
                wall = time.perf_counter() - t0
                rates[w].append(count / wall)
                cores[w].append(cpu / wall)
                shutil.rmtree(folder)
        for c in clients.values():
            c.close()
    finally:
        for c in clusters.values():
            c.close()
    r1, r2 = statistics.median(rates[1]), statistics.median(rates[2])
    c1, c2 = statistics.median(cores[1]), statistics.median(cores[2])
    print(f"Dask LocalCluster build, {count:,} entries ({chunk:,} per task), median of {rounds}:")
    print(f"  1 worker : {r1:12,.0f} entries/s   cores obtained {c1:.2f}")
    print(
        f"  2 workers: {r2:12,.0f} entries/s   cores obtained {c2:.2f}   speed-up {r2 / r1:.2f} "
        "(linear: 2.00, +-20 %: 1.6-2.4)"
    )
    print(f"  speed-up per core obtained: {(r2 / c2) / (r1 / c1):.2f} (no Dask overhead: 1.00)")
    print(f"  rounds: 1 worker {[f'{r:,.0f}' for r in rates[1]]}, 2 workers "
          f"{[f'{r:,.0f}' for r in rates[2]]}")  # fmt: skip


def query_bench(folder: Path, repeats: int) -> None:
    t_open, at = timed(lambda: open_atlas(folder))
    print(f"atlas {folder}: {len(at):,} entries, {disk(folder) / 1e9:.2f} GB on disk; "
          f"open + verify CRCs {t_open:.2f} s")  # fmt: skip
    at.nearest(at.desc[0][0], 160)  # touch every page once (the OS keeps them)
    rng = np.random.default_rng(5)
    qs = [at.desc[int(rng.integers(len(at.desc)))][int(rng.integers(1000))] for _ in range(repeats)]
    runs = [timed_cpu(lambda q=q: at.nearest(q, 160)) for q in qs]
    times, cpus = [r[0] for r in runs], [r[1] for r in runs]
    print(f"  k-nearest query (k = 160, 4 variants): median {statistics.median(times):.3f} s, "
          f"max {max(times):.3f} s over {repeats}; "
          f"CPU median {statistics.median(cpus):.3f} s")  # fmt: skip
    if at.manifest.kind == "sixbar":
        sixbar_bench(at, 6)
        return
    known = PlacedFourBar(FourBar(5, 2, 5, 4, coupler=(3.0, 0.6)), 1 + 2j, 0.3, 1)
    th = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    targets = known.pose(th)[2]
    size = float(np.max(np.abs(targets - targets.mean())))
    for label, kw in (("closed, untimed", {}), ("closed, timed", {"timing": th})):
        runs = [timed_cpu(lambda kw=kw: path_from_atlas(targets, at, n=5, **kw)) for _ in range(3)]
        t = statistics.median(r[0] for r in runs)
        cpu = statistics.median(r[1] for r in runs)
        res = runs[-1][2]
        print(f"  synthesis ({label}, 12 points, 10 refined): median {t:.2f} s wall, "
              f"{cpu:.2f} s CPU "
              f"(retrieve {res.seconds['retrieve']:.2f}, refine {res.seconds['refine']:.2f}); "
              f"best max error / size {np.max(res.best.distance) / size:.1e}")  # fmt: skip


def sixbar_bench(at, count: int) -> None:
    """Six-bar synthesis: 12 points of known six-bars (atlas entries with every length
    changed by 2 %, so not in the atlas), closed, untimed and timed; time and error.

    ``mu_min=0``: random six-bars often have transmission angles below the default
    30°, and the known linkage is then (rightly) rejected; this measures recovery.
    """
    from machdyn.synthesis.sixbar import sixbar_points

    rng = np.random.default_rng(3)
    th = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    out: dict[str, list[tuple[float, float, float]]] = {"untimed": [], "timed": []}
    while len(out["timed"]) < count:
        row = at.entries([int(rng.integers(len(at)))])[0].copy()
        for k in ("r1", "r3", "r4", "a", "b"):
            row[k] *= 1.02
        P, ok = sixbar_points(row[None], th)
        if not ok.all():
            continue
        targets = (3 - 1j) + 2.5 * np.exp(0.7j) * P[0]
        size = float(np.max(np.abs(targets - targets.mean())))
        for label, kw in (("untimed", {}), ("timed", {"timing": th})):
            t, cpu, res = timed_cpu(
                lambda kw=kw, p=targets: path_from_atlas(p, at, n=5, mu_min=0.0, **kw)
            )
            out[label].append((t, float(np.max(res.best.distance)) / size, cpu))
    for label, runs in out.items():
        times, errors = sorted(r[0] for r in runs), sorted(r[1] for r in runs)
        cpus = sorted(r[2] for r in runs)
        print(f"  six-bar synthesis ({label}, 12 points, 10 refined) over {count} targets: "
              f"wall median {statistics.median(times):.2f} s, max {times[-1]:.2f} s; "
              f"CPU median {statistics.median(cpus):.2f} s, max {cpus[-1]:.2f} s; "
              f"max error / size median {statistics.median(errors):.1e}, worst {errors[-1]:.1e}, "
              f"<= 1e-6 on {sum(e <= 1e-6 for e in errors)} of {count}")  # fmt: skip


def sixbar_recovery(at, count: int, seed: int = 2026, kinds=("untimed", "timed")) -> None:
    """Recovery of random six-bars: ``count`` crank-driven six-bars drawn as the atlas
    draws them (:func:`~machdyn.synthesis.sixbar.sample_sixbars`, every chain, attachment
    and coupler link; another seed, so none is an atlas entry), each placed in the
    plane by a random rotation, scale and offset; 12 points at crank angles
    0.4 + k·30°. Recovered: the best result's largest distance ≤ 1e-6 of the
    targets' size, untimed and timed (``mu_min=0``: this measures recovery).
    ``kinds`` may add "open" and "open-timed": 8 points over a part of the turn (a
    span of 60–180° of the crank from a random angle; drawn after the others, so the
    closed targets are the same whichever kinds run).
    """
    from machdyn.synthesis.sixbar import TOPOLOGIES, sample_sixbars, sixbar_points

    rows = sample_sixbars(np.random.default_rng(seed), count)
    rng = np.random.default_rng(seed + 1)
    th = 0.4 + np.linspace(0, 2 * np.pi, 12, endpoint=False)
    warm = sixbar_points(sample_sixbars(np.random.default_rng(seed - 1), 1), th)[0][0]
    for kw in ({}, {"timing": th}):  # not timed: the compiled kernels' first load
        path_from_atlas(warm, at, n=1, mu_min=0.0, **kw)
    for label in SIXBAR_KINDS:
        errors, cpus, walls, misses = [], [], [], {}
        for row in rows:
            h = rng.uniform(0.5, 3.0) * np.exp(1j * rng.uniform(0, 2 * np.pi))
            move = complex(*rng.normal(size=2))
            theta = th
            if label.startswith("open"):
                start, span = rng.uniform(0, 2 * np.pi), np.radians(rng.uniform(60, 180))
                theta = start + np.linspace(0, span, 8)
            if label not in kinds:
                continue
            targets = move + h * sixbar_points(row[None], theta)[0][0]
            size = float(np.max(np.abs(targets - targets.mean())))
            kw = {"timing": theta} if label in ("timed", "open-timed") else {}  # (not "untimed")
            closed = not label.startswith("open")
            t, cpu, res = timed_cpu(
                lambda p=targets, kw=kw, c=closed: path_from_atlas(
                    p, at, closed=c, n=1, mu_min=0.0, **kw
                )
            )
            e = float(np.max(res.best.distance)) / size
            errors.append(e), cpus.append(cpu), walls.append(t)
            if e > 1e-6:
                (l1, l2), chain = TOPOLOGIES[int(row["topology"])]
                key = f"{chain} {l1}-{l2} on {int(row['on'])}"
                misses[key] = misses.get(key, 0) + 1
                print(f"    {label} miss: six-bar {len(errors) - 1} ({key}), {e:.1e}")
        if label not in kinds:
            continue
        ok = sum(e <= 1e-6 for e in errors)
        slow = sorted(range(count), key=lambda i: -cpus[i])[:5]
        print(f"    {label} slowest: " + ", ".join(
            f"six-bar {i} {cpus[i]:.2f} s CPU ({errors[i]:.1e})" for i in slow))  # fmt: skip
        points = 8 if label.startswith("open") else 12
        print(f"  six-bar recovery ({label}, {points} points) of {count} random six-bars: "
              f"{ok} of {count} to <= 1e-6 of the size; error median "
              f"{statistics.median(errors):.1e}, worst {max(errors):.1e}; CPU median "
              f"{statistics.median(cpus):.2f} s, max {max(cpus):.2f} s; wall median "
              f"{statistics.median(walls):.2f} s; missed: {misses or 'none'}")  # fmt: skip


RECOVERY_KINDS = ("closed", "timed", "open", "open-timed")
#: --sixbar-kinds: closed untimed and timed (12 points round the turn), open ones (8 points).
SIXBAR_KINDS = ("untimed", "timed", "open", "open-timed")


def _random_crank_rocker(rng):
    """A placed crank-rocker: r2 = 1, r1, r3, r4 log-uniform over 1.5–6 (clear of a change
    point by 5 % of the links' sum), coupler point 0.3–1.5·r3 at any angle, scaled by
    0.5–20, turned and moved at random, either assembly."""
    while True:
        r1, r3, r4 = np.exp(rng.uniform(np.log(1.5), np.log(6), 3))
        lengths = sorted([r1, 1.0, r3, r4])
        if lengths[0] == 1.0 and lengths[0] + lengths[3] < lengths[1] + lengths[2] - 0.05 * sum(
            lengths
        ):
            p, delta = rng.uniform(0.3, 1.5) * r3, rng.uniform(-np.pi, np.pi)
            s = np.exp(rng.uniform(np.log(0.5), np.log(20)))
            fb = FourBar(r1 * s, s, r3 * s, r4 * s, coupler=(p * s, delta))
            O2 = complex(*rng.normal(0, 5, 2))
            return PlacedFourBar(fb, O2, rng.uniform(0, 6.28), int(rng.choice([-1, 1])))


def _recovery_targets(rng):
    """Crank angles and options of the four target kinds (all drawn, whichever are run)."""
    closed = np.sort(rng.uniform(0, 2 * np.pi, 12))
    timed = np.sort(rng.uniform(0, 2 * np.pi, 8))
    arc = rng.uniform(0, 6.28) + np.linspace(0, rng.uniform(1.0, 3.0), 9)
    arc_timed = rng.uniform(0, 6.28) + np.linspace(0, rng.uniform(1.0, 3.0), 7)
    return {
        "closed": (closed, {}),
        "timed": (timed, {"timing": timed}),
        "open": (arc, {"closed": False}),
        "open-timed": (arc_timed, {"closed": False, "timing": arc_timed}),
    }


def fourbar_recovery(at, count: int, seed: int, kinds, verbose: bool) -> None:
    """Recovery of random placed crank-rockers (:func:`_random_crank_rocker`), four kinds:
    12 untimed points round the curve (closed), 8 timed ones, 9 untimed points on a
    1–3 rad arc of the crank (open), 7 timed ones on such an arc (open-timed).
    Recovered: the best candidate's largest distance to the targets, measured by the
    tests' independent point-to-curve distance (circle intersections + a scalar
    minimisation, tests/test_synthesis_path_atlas.py), is <= 1e-6 of the targets' size
    (``mu_min=0``: this measures recovery, not the defect filter).
    """
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from tests.test_synthesis_path_atlas import _curve_distance

    rng = np.random.default_rng(seed)
    stats = {k: [] for k in kinds}
    for i in range(count):
        linkage = _random_crank_rocker(rng)
        for kind, (theta, options) in _recovery_targets(rng).items():
            if kind not in stats:
                continue
            targets = linkage.pose(theta)[2]
            size = float(np.max(np.abs(targets - targets.mean())))
            t, cpu, res = timed_cpu(
                lambda p=targets, o=options: path_from_atlas(p, at, n=3, mu_min=0.0, **o)
            )
            best = res.candidates[:1]
            e = float(_curve_distance(best[0], targets).max()) / size if best else np.inf
            stats[kind].append((e, cpu, t))
            if verbose:
                print(f"    {i:3d} {kind:10s} {e:.2e}  CPU {cpu:.2f} s  wall {t:.2f} s", flush=True)
    for kind, rows in stats.items():
        e, cpu, wall = (np.array(c) for c in zip(*rows, strict=True))
        print(f"  four-bar recovery ({kind}, seed {seed}): {int(np.sum(e <= 1e-6))} of {count} "
              f"to <= 1e-6 of the size; misses {sorted(float(f'{x:.1e}') for x in e[e > 1e-6])}; "
              f"CPU median {np.median(cpu):.2f} s, max {cpu.max():.2f} s; wall median "
              f"{np.median(wall):.2f} s")  # fmt: skip


def _hard_targets() -> dict:
    """Awkward open targets (name -> (points, timing or None)): zigzags, straight lines,
    circle arcs, paths no four-bar traces (a right-angled corner, a spiral), and one
    random crank-rocker's arc at 5 and at 40 points; timed versions of some."""
    x = np.linspace(0.0, 4.0, 13)
    fb = PlacedFourBar(FourBar(3.0, 1.0, 3.5, 3.2, coupler=(2.0, 0.8)), 1 + 1j, 0.4, 1)
    arc = np.exp(1j * np.linspace(0.2, 1.8, 9))  # a quarter-circle and a half
    t40 = np.linspace(0.0, 2.5, 40)
    corner = np.r_[np.linspace(0, 1, 6), 1 + 1j * np.linspace(0.2, 1, 5)]
    out = {
        "zigzag, 13 points": (x + 0.4j * (np.arange(13) % 2), None),
        "zigzag, 7 points": (x[::2] + 0.8j * (np.arange(7) % 2), None),
        "straight line, 6 points": (np.linspace(0, 5, 6) * np.exp(0.3j), None),
        "straight line, 40 points": (np.linspace(0, 5, 40) * np.exp(0.3j), None),
        "circle arc, 9 points": (arc, None),
        "circle arc, 40 points": (np.exp(1j * np.linspace(0.2, 1.8, 40)), None),
        "right-angled corner, 11 points": (corner, None),
        "spiral, 15 points": ((1 + 0.15 * np.arange(15)) * np.exp(0.6j * np.arange(15)), None),
        "four-bar arc, 5 points": (fb.pose(np.linspace(0.0, 2.5, 5))[2], None),
        "four-bar arc, 40 points": (fb.pose(t40)[2], None),
        "timed zigzag, 7 points": (x[::2] + 0.8j * (np.arange(7) % 2), np.linspace(0, 2, 7)),
        "timed straight line, 6 points": (np.linspace(0, 5, 6) + 0j, np.linspace(0, 1.5, 6)),
        "timed circle arc, 9 points": (arc, np.linspace(0, 2.0, 9)),
        "timed four-bar arc, 40 points": (fb.pose(t40)[2], t40),
    }
    return out


def hard_bench(at, repeats: int, time_limit: float | None) -> None:
    """Time and worst miss of :func:`_hard_targets` (open; ``mu_min`` 0, n = 3)."""
    rows = []
    for name, (pts, timing) in _hard_targets().items():
        size = float(np.max(np.abs(pts - pts.mean())))
        runs = [timed_cpu(lambda p=pts, t=timing: path_from_atlas(
            p, at, closed=False, timing=t, n=3, mu_min=0.0, time_limit=time_limit))
            for _ in range(repeats)]  # fmt: skip
        wall, cpu = min(r[0] for r in runs), min(r[1] for r in runs)
        res = runs[-1][2]
        found = res.candidates or res.rejected
        miss = float(np.max(found[0].distance)) / size if found else np.inf
        rows.append((wall, cpu))
        stopped = " (stopped at the limit)" if "time limit" in res.note else ""
        print(f"    {name:32s} CPU {cpu:5.2f} s  wall {wall:5.2f} s  best miss {miss:.1e} of the "
              f"size, {len(res.candidates)} defect-free{stopped}", flush=True)  # fmt: skip
    wall, cpu = (np.array(c) for c in zip(*rows, strict=True))
    print(f"  hard open targets ({len(rows)}, best of {repeats}): CPU median {np.median(cpu):.2f} "
          f"s, max {cpu.max():.2f} s; wall median {np.median(wall):.2f} s, max {wall.max():.2f} s"
          + (f" (time_limit {time_limit:g} s)" if time_limit is not None else ""))  # fmt: skip


#: --cold's child: what a user's script does (import, open the atlas, one synthesis),
#: then the same call twice more in the same process (the warm peers: from the second
#: query of a process on, each query builds the compact tables of a budget of the atlas's
#: chunks, _atlas_index.TABLE_BUDGET, so the later calls still pay part of that). Prints
#: one JSON line.
_COLD_CHILD = """
import json, sys, time
t0, c0 = time.perf_counter(), time.process_time()
import numpy as np
from machdyn.synthesis import open_atlas, path_from_atlas
t1, c1 = time.perf_counter(), time.process_time()
at = open_atlas(sys.argv[1], verify=False)
t2, c2 = time.perf_counter(), time.process_time()
pts = np.array([complex(*p) for p in json.loads(sys.argv[2])])
options = json.loads(sys.argv[3])
calls = []
for _ in range(3):
    w, c = time.perf_counter(), time.process_time()
    res = path_from_atlas(pts, at, n=3, mu_min=0.0, **options)
    calls.append((time.perf_counter() - w, time.process_time() - c, res.seconds,
                  float(np.max(res.best.distance))))
from machdyn import jit
print(json.dumps({"import": [t1 - t0, c1 - c0], "open": [t2 - t1, c2 - c1], "calls": calls,
                  "numba": "numba" in sys.modules, "compiled": jit.active()}))
"""


def _cold_targets() -> dict:
    """--cold's targets (kind -> points, options): a known crank-rocker's coupler curve,
    12 points round it (closed, untimed and timed) or 9 on a 2-rad arc (open, untimed and
    timed), as :func:`query_bench`'s linkage."""
    known = PlacedFourBar(FourBar(5, 2, 5, 4, coupler=(3.0, 0.6)), 1 + 2j, 0.3, 1)
    th = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    arc = np.linspace(0.3, 2.3, 9)
    return {
        "closed": (known.pose(th)[2], {}),
        "timed": (known.pose(th)[2], {"timing": th.tolist()}),
        "open": (known.pose(arc)[2], {"closed": False}),
        "open-timed": (known.pose(arc)[2], {"closed": False, "timing": arc.tolist()}),
    }


def cold_bench(folder: Path, count: int, kinds) -> None:
    """The first synthesis of a fresh process, ``count`` processes per kind, interleaved.

    Each child (:data:`_COLD_CHILD`, run by this Python with this environment: set
    ``MACHDYN_JIT`` or ``PYTHONDONTWRITEBYTECODE`` for the parent to pass them on) imports
    machdyn, opens the atlas (``verify=False``) and runs one synthesis, then the same call
    twice more (the warm peers, same process, right after). Printed per kind, medians: the
    whole process's wall and CPU (start to exit, children's rusage; it includes the two
    warm calls), the first call's wall and CPU, the second's and third's; whether numba
    was imported and the compiled kernels loaded; the worst best-miss of the first and
    the third call (absolute, in the targets' units).
    """
    import json
    import os
    import resource
    import subprocess
    import sys

    targets = _cold_targets()
    rows = {k: [] for k in kinds}
    for _ in range(count):
        for kind in kinds:
            pts, options = targets[kind]
            args = [sys.executable, "-c", _COLD_CHILD, str(folder),
                    json.dumps([[p.real, p.imag] for p in pts]), json.dumps(options)]  # fmt: skip
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            t0 = time.perf_counter()
            out = subprocess.run(args, capture_output=True, text=True, check=True).stdout
            wall = time.perf_counter() - t0
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
            rows[kind].append((wall, cpu, json.loads(out.strip().splitlines()[-1])))
    env = {k: os.environ.get(k, "") for k in ("MACHDYN_JIT", "PYTHONDONTWRITEBYTECODE")}
    print(f"  cold synthesis, {count} fresh processes per kind, interleaved; {env}")
    for kind, runs in rows.items():
        med = statistics.median
        calls = [[r[2]["calls"][i] for r in runs] for i in range(3)]
        wall, cpu = ([f"{med(c[j] for c in call):.2f}" for call in calls] for j in (0, 1))
        print(f"    {kind:10s} process wall {med(r[0] for r in runs):.2f} s CPU "
              f"{med(r[1] for r in runs):.2f} s (import {med(r[2]['import'][1] for r in runs):.2f}"
              f", open {med(r[2]['open'][1] for r in runs):.2f} s CPU); calls 1/2/3 wall "
              f"{' / '.join(wall)} s, CPU {' / '.join(cpu)} s; numba imported "
              f"{sum(r[2]['numba'] for r in runs)}/{len(runs)}, compiled "
              f"{sum(r[2]['compiled'] for r in runs)}/{len(runs)}; best miss call 1 "
              f"{max(c[3] for c in calls[0]):.1e}, call 3 {max(c[3] for c in calls[2]):.1e}",
              flush=True)  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--atlas", type=Path, help="an existing atlas to query")
    ap.add_argument("--build", type=Path, help="build an atlas here (timed)")
    ap.add_argument("--count", type=int, default=1 << 19)
    ap.add_argument("--scheduler", default=None)
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--no-scaling", action="store_true")
    ap.add_argument(
        "--sixbar-recovery",
        type=int,
        default=0,
        metavar="N",
        help="with --atlas (a six-bar atlas): recovery rate over N random six-bars",
    )
    ap.add_argument("--sixbar-seed", type=int, default=2026, help="of --sixbar-recovery's six-bars")
    ap.add_argument(
        "--sixbar-kinds",
        default="untimed,timed",
        help=f"of --sixbar-recovery's targets, of {','.join(SIXBAR_KINDS)}",
    )
    ap.add_argument(
        "--recovery",
        type=int,
        default=0,
        metavar="N",
        help="with --atlas (a four-bar atlas): recovery rates over N random crank-rockers",
    )
    ap.add_argument("--seed", type=int, default=7, help="of --recovery's random linkages")
    ap.add_argument("--kinds", default=",".join(RECOVERY_KINDS), help="of --recovery's targets")
    ap.add_argument("--verbose", action="store_true", help="print every --recovery case")
    ap.add_argument("--hard", action="store_true", help="with --atlas: awkward open targets")
    ap.add_argument("--repeats", type=int, default=1, help="of each --hard target (best taken)")
    ap.add_argument("--time-limit", type=float, default=None, help="of each --hard synthesis")
    ap.add_argument(
        "--cold",
        type=int,
        default=0,
        metavar="N",
        help="with --atlas: N fresh processes per --kinds target, one synthesis + 2 more each",
    )
    args = ap.parse_args()
    if args.atlas is not None and args.cold:  # (before this process loads the kernels)
        kinds = args.kinds.split(",")
        if not set(kinds) <= set(RECOVERY_KINDS):
            ap.error(f"--kinds: choose from {', '.join(RECOVERY_KINDS)}")
        cold_bench(args.atlas, args.cold, kinds)
        return
    jit.load()
    print(f"kernels: {'compiled' if jit.active() else 'NumPy'}")
    if args.atlas is not None and args.hard:
        at = open_atlas(args.atlas, verify=False)
        path_from_atlas(_hard_targets()["zigzag, 7 points"][0], at, closed=False)  # warm-up
        hard_bench(at, args.repeats, args.time_limit)
        return
    if args.atlas is not None and args.recovery:
        kinds = args.kinds.split(",")
        if not set(kinds) <= set(RECOVERY_KINDS):
            ap.error(f"--kinds: choose from {', '.join(RECOVERY_KINDS)}")
        fourbar_recovery(open_atlas(args.atlas, verify=False), args.recovery, args.seed, kinds,
                         args.verbose)  # fmt: skip
        return
    if args.atlas is not None and args.sixbar_recovery:
        kinds = args.sixbar_kinds.split(",")
        if not set(kinds) <= set(SIXBAR_KINDS):
            ap.error(f"--sixbar-kinds: choose from {', '.join(SIXBAR_KINDS)}")
        sixbar_recovery(open_atlas(args.atlas, verify=False), args.sixbar_recovery,
                        args.sixbar_seed, kinds)  # fmt: skip
        return
    if args.build is not None:
        t, m = timed(lambda: build_atlas(args.build, args.count, scheduler=args.scheduler,
                                         workers=args.workers, progress=True))  # fmt: skip
        print(f"built {m.count:,} entries in {t:.1f} s ({m.count / t:,.0f}/s), "
              f"{disk(args.build) / 1e9:.2f} GB")  # fmt: skip
        query_bench(args.build, 20)
    else:
        folder = Path(tempfile.mkdtemp(prefix="bench_atlas"))
        t, m = timed(lambda: build_atlas(folder, args.count, progress=False))
        print(f"serial build, this process: {m.count:,} entries in {t:.2f} s "
              f"({m.count / t:,.0f}/s); "
              f"{disk(folder) / m.count:.0f} bytes per entry "
              f"(10^7 entries: {1e7 / (m.count / t) / 60:.1f} min on one core, "
              f"{disk(folder) / m.count * 1e7 / 1e9:.2f} GB)")  # fmt: skip
        shutil.rmtree(folder)
        if not args.no_scaling:
            scaling(args.count, 1 << 16, args.rounds)
    if args.atlas is not None:
        query_bench(args.atlas, 20)


if __name__ == "__main__":
    main()
