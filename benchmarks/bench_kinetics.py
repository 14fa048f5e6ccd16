"""Benchmark of the kinetics helpers: flywheel sizing and rotor balancing.

Run: python benchmarks/bench_kinetics.py
"""

from __future__ import annotations

import time

import numpy as np

from machdyn.balancing import bearing_balance, static_balance, two_plane
from machdyn.flywheel import size_flywheel


def best_of(fn, repeat: int = 5) -> float:
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def main() -> None:
    rng = np.random.default_rng(1)
    rows = []

    for n in (3_600, 100_000, 1_000_000):
        theta = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
        torque = 100 + 40 * np.sin(theta) + 25 * np.cos(3 * theta) + 10 * np.sin(7 * theta)
        t = best_of(lambda th=theta, tq=torque: size_flywheel(th, tq, 50.0, 0.02), 3)
        rows.append(("size_flywheel (lobes + ω(θ))", f"{n:,} samples", t, n / t, "samples/s"))

    rotors, masses = 1_000_000, 4
    unbalance = rng.normal(size=(rotors, masses)) + 1j * rng.normal(size=(rotors, masses))
    z = np.array([0.1, 0.4, 0.7, 0.9])
    t = best_of(lambda: two_plane(unbalance, z, 0.0, 1.0))
    rows.append(("two_plane", f"{rotors:,} rotors x {masses}", t, rotors / t, "rotors/s"))
    t = best_of(lambda: static_balance(unbalance))
    rows.append(("static_balance", f"{rotors:,} rotors x {masses}", t, rotors / t, "rotors/s"))
    forces = unbalance[:, :2]
    t = best_of(lambda: bearing_balance(forces, [-0.35, -0.1], 10.0, 0.0, 0.175))
    rows.append(("bearing_balance", f"{rotors:,} wheels", t, rotors / t, "wheels/s"))

    print(f"{'what':<30} {'size':>22} {'time (s)':>10} {'rate':>14}")
    for what, size, seconds, rate, unit in rows:
        print(f"{what:<30} {size:>22} {seconds:>10.4f} {rate:>10.3g} {unit}")


if __name__ == "__main__":
    main()
