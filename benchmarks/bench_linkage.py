"""Benchmark of machdyn.linkage: kinematics and Newton–Euler forces of a Watt II six-bar.

Run: ``python benchmarks/bench_linkage.py [N]`` (default N = 10**6 samples).
Prints what, size, best time of a few runs, and rate (samples/s).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from machdyn.linkage import Linkage


def _meet(p: complex, r1: float, q: complex, r2: float, side: float) -> complex:
    d = abs(q - p)
    a = (r1**2 - r2**2 + d**2) / (2 * d)
    u = (q - p) / d
    return p + a * u + side * np.sqrt(r1**2 - a**2) * 1j * u


def watt_ii() -> Linkage:
    """Crank-rocker 8-2-7-6 whose ternary rocker drives the dyad C-D-O6; masses on all."""
    O4, O6 = 8.0 + 0j, 12.0 + 6.0j
    A = 2.0 * np.exp(1j * np.pi / 6)
    B = _meet(A, 7.0, O4, 6.0, 1.0)
    C = O4 + 4.0 * (B - O4) / abs(B - O4) * np.exp(-1j * np.radians(35))
    D = _meet(C, 6.0, O6, 5.0, -1.0)
    lk = Linkage({"O2": 0j, "O4": O4, "O6": O6, "A": A, "B": B, "C": C, "D": D})
    lk.ground("O2", "O4", "O6")
    lk.link("2", "O2", "A", mass=1.0, inertia=0.4, cg=1.0)
    lk.link("3", "A", "B", mass=2.0, inertia=8.0, cg=3.5)
    lk.link("4", "O4", "B", "C", mass=3.0, inertia=9.0, cg=3.0)
    lk.link("5", "C", "D", mass=1.5, inertia=4.5, cg=3.0)
    lk.link("6", "O6", "D", mass=2.5, inertia=5.0, cg=2.5)
    return lk.drive("2")


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    lk = watt_ii()
    rows = []
    for size in (3600, n):
        theta = np.linspace(0.0, 2 * np.pi, size, endpoint=False)
        repeat = 5 if size <= 10_000 else 3
        m = lk.solve(theta, velocity=10.0)
        t_kin = best(lambda theta=theta: lk.solve(theta, velocity=10.0), repeat)
        t_f = best(lambda m=m: lk.forces(m, gravity=9.81, external_torques={"6": -5.0}), repeat)
        rows.append(("Watt II kinematics (pos+vel+acc)", size, t_kin))
        rows.append(("Watt II Newton-Euler forces (given motion)", size, t_f))
        rows.append(("Watt II kinematics + forces", size, t_kin + t_f))
    print(f"{'what':<44} {'size':>10} {'time [s]':>10} {'samples/s':>11}")
    for what, size, t in rows:
        print(f"{what:<44} {size:>10,} {t:>10.4f} {size / t:>11.3g}")


if __name__ == "__main__":
    main()
