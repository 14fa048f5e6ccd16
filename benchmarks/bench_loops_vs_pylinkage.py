"""machdyn.loops against pylinkage + numba on a Watt II six-bar (issue 10's speed row).

Run: ``pip install -e ".[bench]" && python benchmarks/bench_loops_vs_pylinkage.py [N] [ROUNDS]``
(default N = 3600 poses, one crank turn; ROUNDS = 200).

The same linkage (the crank-rocker 8-2-7-6 of ``bench_linkage.py`` whose ternary
rocker drives the dyad C-D-O6) and the same poses, positions + velocities +
accelerations, in one process, timed in interleaved rounds (machdyn, then
pylinkage, then machdyn, ...) so that the other jobs on the shared machine slow
both alike; reported: the best, 10th percentile and median of each, and the
ratios (of the bests, of the medians, and the median of the rounds' own
ratios). machdyn runs with its compiled kernels loaded (``jit.load()``);
pylinkage runs its fastest path, ``Linkage.step_fast_with_kinematics`` (numba).
Before timing, the two answers are compared (every joint's position, velocity
and acceleration), so that the race is between two right answers.
pylinkage is a benchmark-only dependency (the ``[bench]`` extra), never a
run-time one.
"""

from __future__ import annotations

import platform
import statistics
import sys
import time

import numpy as np

from machdyn import jit
from machdyn.loops import LoopSystem

# The drawing (bench_linkage.watt_ii's): O2 at the origin.
O4, O6 = 8.0 + 0j, 12.0 + 6.0j
R2, R3, R4, R4C, R5, R6 = 2.0, 7.0, 6.0, 4.0, 6.0, 5.0
BETA = -np.radians(35.0)  # C is on the rocker, 35 deg clockwise of O4->B
OMEGA2 = 10.0  # rad/s, constant
THETA0 = np.pi / 6


def _meet(p: complex, r1: float, q: complex, r2: float, side: float) -> complex:
    d = abs(q - p)
    a = (r1**2 - r2**2 + d**2) / (2 * d)
    u = (q - p) / d
    return p + a * u + side * np.sqrt(r1**2 - a**2) * 1j * u


def drawing() -> dict[str, complex]:
    A = R2 * np.exp(1j * THETA0)
    B = _meet(A, R3, O4, R4, 1.0)
    C = O4 + R4C * (B - O4) / abs(B - O4) * np.exp(1j * BETA)
    D = _meet(C, R5, O6, R6, -1.0)
    return {"O2": 0j, "O4": O4, "O6": O6, "A": A, "B": B, "C": C, "D": D}


def machdyn_model() -> tuple[LoopSystem, dict[str, float]]:
    p = drawing()
    s = (
        LoopSystem()
        .vector("R1", abs(O4), float(np.angle(O4)))
        .vector("R2", R2, "theta2")
        .vector("R3", R3, "theta3")
        .vector("R4", R4, "theta4")
        .vector("R4c", R4C, "theta4c")
        .constraint("theta4c = theta4 + beta", beta=BETA)
        .vector("R5", R5, "theta5")
        .vector("R6", R6, "theta6")
        .vector("R7", abs(O6), float(np.angle(O6)))
        .loop("R2 + R3 - R4 - R1")
        .loop("R1 + R4c + R5 - R6 - R7")
        .point("A", "R2")
        .point("B", "R2 + R3")
        .point("C", "R1 + R4c")
        .point("D", "R7 + R6")
        .inputs("theta2")
    )
    ang = np.angle
    guess = {
        "theta3": float(ang(p["B"] - p["A"])),
        "theta4": float(ang(p["B"] - O4)),
        "theta4c": float(ang(p["C"] - O4)),
        "theta5": float(ang(p["D"] - p["C"])),
        "theta6": float(ang(p["D"] - O6)),
    }
    return s, guess


def pylinkage_model(n: int):
    import pylinkage as pl

    p = drawing()
    g2, g4, g6 = (
        pl.Ground(z.real, z.imag, name=k) for k, z in (("O2", 0j), ("O4", O4), ("O6", O6))
    )
    crank = pl.Crank(g2, R2, angular_velocity=2 * np.pi / n, initial_angle=THETA0, name="A")
    b = pl.RRRDyad(crank.output, g4, R3, R4, x=p["B"].real, y=p["B"].imag, name="B")
    c = pl.FixedDyad(g4, b, R4C, BETA, name="C")
    d = pl.RRRDyad(c, g6, R5, R6, x=p["D"].real, y=p["D"].imag, name="D")
    lk = pl.Linkage([g2, g4, g6, crank, b, c, d], name="Watt II")
    lk.set_input_velocity(crank, OMEGA2, 0.0)
    return lk, ["A", "B", "C", "D"]


def run_machdyn(s: LoopSystem, guess: dict, theta2: np.ndarray):
    return s.solve({"theta2": theta2}, guess=guess, velocity={"theta2": OMEGA2}, order=2)


def check(m, lk, names, n: int) -> float:
    """Largest difference between the two answers (positions, velocities, accelerations)."""
    lk.rebuild() if hasattr(lk, "rebuild") else None
    pos, vel, acc = lk.step_fast_with_kinematics(iterations=n)
    order = [c.name for c in lk.components]
    worst = 0.0
    for name in names:
        k = order.index(name)
        # pylinkage reports the pose after each crank step: sample i is theta0 + (i+1) dtheta
        mine = [np.roll(a[name], -1) for a in (m.points, m.point_velocity, m.point_acceleration)]
        for ours, theirs in zip(mine, (pos, vel, acc), strict=True):
            other = theirs[:, k, 0] + 1j * theirs[:, k, 1]
            scale = max(np.abs(ours).max(), 1.0)
            worst = max(worst, float(np.abs(ours - other).max() / scale))
    return worst


def main() -> None:
    n = int(float(sys.argv[1])) if len(sys.argv) > 1 else 3600
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 200
    import numba
    import pylinkage

    assert jit.load(), jit.reason()
    s, guess = machdyn_model()
    theta2 = THETA0 + np.arange(n) * (2 * np.pi / n)
    m = run_machdyn(s, guess, theta2)
    assert m.ok.all(), np.unique(m.reason)
    lk, names = pylinkage_model(n)
    diff = check(m, lk, names, n)
    print(f"largest relative difference machdyn vs pylinkage (pos, vel, acc): {diff:.2e}")
    assert diff < 1e-9, diff

    def time_machdyn() -> float:
        t0 = time.perf_counter()
        run_machdyn(s, guess, theta2)
        return time.perf_counter() - t0

    def time_pylinkage() -> float:
        t0 = time.perf_counter()
        lk.step_fast_with_kinematics(iterations=n)
        return time.perf_counter() - t0

    for _ in range(3):  # warm both
        time_machdyn(), time_pylinkage()
    ours, theirs = [], []
    for _ in range(rounds):
        ours.append(time_machdyn())
        theirs.append(time_pylinkage())
    pairs = statistics.median(t / o for o, t in zip(ours, theirs, strict=True))
    print(
        f"Python {platform.python_version()}, numpy {np.__version__}, numba {numba.__version__}, "
        f"pylinkage {pylinkage.__version__}; {n} poses, {rounds} interleaved rounds"
    )
    print(f"{'':36s} {'best':>8s} {'10 %':>8s} {'median':>8s}  [ms]")
    for label, t in (
        ("machdyn.loops (compiled)", ours),
        ("pylinkage step_fast_with_kinematics", theirs),
    ):
        t = sorted(t)
        print(
            f"{label:36s} {t[0] * 1e3:8.3f} {t[len(t) // 10] * 1e3:8.3f} "
            f"{t[len(t) // 2] * 1e3:8.3f}"
        )
    print(
        f"ratio pylinkage / machdyn: of the bests {min(theirs) / min(ours):.2f}, of the medians "
        f"{statistics.median(theirs) / statistics.median(ours):.2f}, median of the rounds' own "
        f"ratios {pairs:.2f}"
    )


if __name__ == "__main__":
    main()
