"""Benchmark of machdyn.linkage against pylinkage + numba, in one process, interleaved.

Run::

    pip install -e ".[bench]"            # pylinkage 1.3.0, the peer (never a run-time need)
    python benchmarks/bench_linkage.py [--rounds R] [--big N]

What is measured (issue 10's targets in brackets), every timing the best of
``R`` rounds, the peers' runs interleaved round by round so that a busy
machine slows both alike; the ratios are the point, the absolute numbers move
with the machine's load (printed first):

1. Watt II six-bar, positions + velocities + accelerations, one crank turn at
   3,600 poses: ``Linkage.solve`` and the general vector-loop solver
   (``machdyn.loops``, the same linkage compiled to loops by
   ``Linkage.loop_system``) against pylinkage's fastest path,
   ``Linkage.step_fast_with_kinematics`` (numba) [``Linkage.solve`` ≥ 3×
   faster, ``machdyn.loops`` ≥ 2×]. The three answers are checked to agree
   first (the same crank angles, the same joints).
2. The same at ``N`` = 10⁶ poses [≥ 2 M poses/s].
3. Building a 10-link linkage (a crank and four RRR dyads) from its points
   and its first 360-pose pos+vel+acc solve [≤ 5 ms].
4. One pose, pos+vel+acc, repeated calls on a built linkage [≤ 50 µs].
5. Newton–Euler forces given the motion: the four-bar (``fourbar_forces``,
   which assembles with the linkage's Newton–Euler blocks) [≥ 9 M samples/s]
   and the Watt II (``Linkage.forces``), 10⁶ samples.

The compiled kernels are loaded first (``machdyn.jit.load()``), and each
callable is run once before timing (numba compiles or loads its cache then).
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import statistics
import time
from collections.abc import Callable

import numpy as np

from machdyn import jit
from machdyn.dynamics import fourbar_forces
from machdyn.fourbar import FourBar
from machdyn.linkage import Linkage

THETA0 = np.pi / 6  # the drawn crank angle of the Watt II


def _meet(p: complex, r1: float, q: complex, r2: float, side: float) -> complex:
    d = abs(q - p)
    a = (r1**2 - r2**2 + d**2) / (2 * d)
    u = (q - p) / d
    return p + a * u + side * np.sqrt(r1**2 - a**2) * 1j * u


def _watt_points() -> dict[str, complex]:
    O4, O6 = 8.0 + 0j, 12.0 + 6.0j
    A = 2.0 * np.exp(1j * THETA0)
    B = _meet(A, 7.0, O4, 6.0, 1.0)
    C = O4 + 4.0 * (B - O4) / abs(B - O4) * np.exp(-1j * np.radians(35))
    D = _meet(C, 6.0, O6, 5.0, -1.0)
    return {"O2": 0j, "O4": O4, "O6": O6, "A": A, "B": B, "C": C, "D": D}


def watt_ii() -> Linkage:
    """Crank-rocker 8-2-7-6 whose ternary rocker drives the dyad C-D-O6; masses on all."""
    lk = Linkage(_watt_points())
    lk.ground("O2", "O4", "O6")
    lk.link("2", "O2", "A", mass=1.0, inertia=0.4, cg=1.0)
    lk.link("3", "A", "B", mass=2.0, inertia=8.0, cg=3.5)
    lk.link("4", "O4", "B", "C", mass=3.0, inertia=9.0, cg=3.0)
    lk.link("5", "C", "D", mass=1.5, inertia=4.5, cg=3.0)
    lk.link("6", "O6", "D", mass=2.5, inertia=5.0, cg=2.5)
    return lk.drive("2")


def pylinkage_watt_ii(n: int):
    """The same Watt II in pylinkage; its crank steps 2π/n per iteration from THETA0."""
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import FixedDyad, RRRDyad
    from pylinkage.simulation import Linkage as PLinkage

    p = _watt_points()
    g2 = Ground(0.0, 0.0, name="O2")
    g4 = Ground(p["O4"].real, p["O4"].imag, name="O4")
    g6 = Ground(p["O6"].real, p["O6"].imag, name="O6")
    crank = Crank(g2, 2.0, angular_velocity=2 * math.pi / n, initial_angle=THETA0, name="A")
    b = RRRDyad(crank.output, g4, 7.0, 6.0, x=p["B"].real, y=p["B"].imag, name="B")
    c = FixedDyad(g4, b, 4.0, -math.radians(35), name="C")
    d = RRRDyad(c, g6, 6.0, 5.0, x=p["D"].real, y=p["D"].imag, name="D")
    peer = PLinkage([g2, g4, g6, crank, b, c, d], name="Watt II")
    peer.set_input_velocity(crank, omega=10.0)
    return peer


def ten_links() -> Linkage:
    """Ten links: the ground, a crank and four RRR dyads, each driven by the one before."""
    pts = {"O": 0j, "A": 2.0 * np.exp(1j * THETA0)}
    ground, prev = ["O"], "A"
    for k in range(4):
        pivot = complex(8.0 + 6.0 * k, 0.5 * k)
        joint = _meet(pts[prev], 7.0, pivot, 6.0, 1.0)
        pts[f"G{k}"], pts[f"B{k}"] = pivot, joint
        pts[f"T{k}"] = pivot + 2.0 * (joint - pivot) / abs(joint - pivot) * np.exp(-0.6j)
        ground.append(f"G{k}")
        prev = f"T{k}"
    lk = Linkage(pts).ground(*ground).link("crank", "O", "A")
    prev = "A"
    for k in range(4):
        lk.link(f"c{k}", prev, f"B{k}").link(f"r{k}", f"G{k}", f"B{k}", f"T{k}")
        prev = f"T{k}"
    return lk.drive("crank")


def loops_solver(lk: Linkage, theta: np.ndarray) -> Callable[[], object]:
    """The Watt II compiled to vector loops, solved by machdyn.loops along ``theta``."""
    c = lk._compile().loops()
    (var,), (off,) = c.driver_vars, c.driver_offsets
    guess = {k: v for k, v in c.drawn.items() if k != var}
    u = {var: theta - off}

    def run():
        return c.system.solve(
            u, guess, velocity={var: 10.0}, acceleration={var: 0.0}, order=2, continuation=True
        )

    return run


#: CPU time (this process) of the fastest call of each callable timed last.
CPU: dict[str, float] = {}


def interleaved(fns: dict[str, Callable[[], object]], rounds: int) -> dict[str, list[float]]:
    """Time every callable once per round, in turn (after one untimed run each).

    Returns the wall times; the CPU time of each callable's fastest call goes to :data:`CPU`.
    """
    for fn in fns.values():
        fn()
    times: dict[str, list[float]] = {k: [] for k in fns}
    for _ in range(rounds):
        for k, fn in fns.items():
            c0, t0 = time.process_time(), time.perf_counter()
            fn()
            t, c = time.perf_counter() - t0, time.process_time() - c0
            if not times[k] or t < min(times[k]):
                CPU[k] = c
            times[k].append(t)
    return times


def check_same(lk: Linkage, peer, n: int) -> float:
    """Largest relative difference of pylinkage's joints, rates, accelerations vs machdyn's."""
    pos, vel, acc = peer.step_fast_with_kinematics(n)
    theta = THETA0 + 2 * np.pi * np.arange(1, n + 1) / n
    m = lk.solve(theta, velocity=10.0)
    worst = 0.0
    for j, name in zip((3, 4, 5, 6), ("A", "B", "C", "D"), strict=True):
        for arr, mine in ((pos, m.points), (vel, m.point_velocity), (acc, m.point_acceleration)):
            z = arr[:, j, 0] + 1j * arr[:, j, 1]
            scale = np.abs(mine[name]).max()
            worst = max(worst, float(np.abs(z - mine[name]).max() / scale))
    return worst


def row(what: str, size: int, t: float, target: str = "", ratio: str = "", cpu=None) -> None:
    c = f"{cpu * 1e3:>9.3f}" if cpu is not None else f"{'':9s}"
    print(f"{what:58s} {size:>9,} {t * 1e3:>11.3f} {c} {size / t:>11.3g} {ratio:>8s} {target}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--big", type=float, default=1e6)
    args = ap.parse_args()
    big = int(args.big)
    import numba
    import pylinkage

    # pylinkage's numba code first, with LLVM's options as they are before machdyn's linkage
    # kernel compiles (its warm-up raises the inlining threshold and restores the default)
    pylinkage_watt_ii(360).step_fast_with_kinematics(360)
    assert jit.load(), f"the compiled kernels do not load: {jit.reason()}"
    print(
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, numpy {np.__version__}, numba "
        f"{numba.__version__}, pylinkage {pylinkage.__version__}; load average "
        f"{' '.join(f'{x:.1f}' for x in os.getloadavg())}"
    )
    lk = watt_ii()
    n = 3600
    peer = pylinkage_watt_ii(n)
    diff = check_same(lk, peer, n)
    print(f"pylinkage vs Linkage.solve, Watt II joints A-D, pos/vel/acc: max rel. diff {diff:.1e}")
    assert diff < 1e-9, diff

    print(
        f"\n{'what':58s} {'size':>9s} {'best [ms]':>11s} {'CPU [ms]':>9s} {'per s':>11s} "
        f"{'ratio':>8s} target"
    )
    for size, rounds in ((n, args.rounds), (big, max(3, args.rounds // 5))):
        theta = THETA0 + 2 * np.pi * np.arange(1, size + 1) / size
        peer = pylinkage_watt_ii(size)
        fns = {
            "Linkage.solve": lambda theta=theta: lk.solve(theta, velocity=10.0),
            "machdyn.loops": loops_solver(lk, theta),
            "pylinkage": lambda size=size, peer=peer: peer.step_fast_with_kinematics(size),
        }
        times = interleaved(fns, rounds)
        ref, ref_med = min(times["pylinkage"]), statistics.median(times["pylinkage"])
        for k, ts in times.items():
            target = {"Linkage.solve": "≥ 3× pylinkage", "machdyn.loops": "≥ 2× pylinkage"}
            if size == big and k == "Linkage.solve":
                target[k] += ", ≥ 2 M poses/s"
            ratio = f"{ref / min(ts):.2f}×"
            med = ref_med / statistics.median(ts)
            target[k] = f"{target.get(k, '(peer)')}; median ratio {med:.2f}×"
            row(f"Watt II pos+vel+acc, {k}", size, min(ts), target[k], ratio, CPU[k])

    # build + first solve of a new 10-link linkage, and the per-call cost of one pose
    theta = THETA0 + np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    first = []
    for _ in range(args.rounds):
        t0 = time.perf_counter()
        m = ten_links().solve(theta, velocity=10.0)
        first.append(time.perf_counter() - t0)
    assert m.ok.all()
    row("10-link linkage: build + first 360-pose solve", 360, min(first), "≤ 5 ms")
    one, cpu = [], []
    for _ in range(args.rounds * 100):
        c0, t0 = time.process_time(), time.perf_counter()
        lk.solve(0.3, velocity=10.0)
        one.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    row("Watt II one pose pos+vel+acc, per call (fastest call)", 1, min(one), "≤ 50 µs",
        cpu=min(cpu))  # fmt: skip
    row("Watt II one pose pos+vel+acc, per call (median call)", 1, statistics.median(one),
        cpu=statistics.median(cpu))  # fmt: skip

    # forces given the motion, 10^6 samples
    fb = FourBar(8, 4, 7, 6)
    th = np.linspace(0.0, 2 * np.pi, big, endpoint=False)
    fm = fb.solve(th, 12.0, -4.0)
    props = dict(mass=(1.2, 2.5, 1.8), inertia=(0.8, 3.1, 1.4), cg=(1.5 + 0.3j, 3.0 - 0.8j, 2.5))
    loads = dict(gravity=9.81, load_torque4=-3.0, external_forces=[(3, 2 + 1j, 4 - 7j)])
    wm = lk.solve(THETA0 + th, velocity=10.0)
    times = interleaved(
        {
            "four-bar": lambda: fourbar_forces(fb, fm, **props, **loads),
            "Watt II": lambda: lk.forces(wm, gravity=9.81, external_torques={"6": -5.0}),
        },
        max(3, args.rounds // 5),
    )
    row("four-bar forces given the motion (fourbar_forces)", big, min(times["four-bar"]), "≥ 9 M/s")
    row("Watt II forces given the motion (Linkage.forces)", big, min(times["Watt II"]))
    # how loaded the machine is: the README's four-bar pos+vel+acc row (compiled, 1 thread,
    # 10^6 poses: 16.1-16.3 M poses/s on the idle machine), here with the default threads
    t = min(interleaved({"fb": lambda: fb.solve(th, 12.0, order=2)}, 3)["fb"])
    row("(load gauge) FourBar.solve(order=2); idle, 1 thread: 16 M/s", big, t)
    print(f"\nload average at the end: {' '.join(f'{x:.1f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
