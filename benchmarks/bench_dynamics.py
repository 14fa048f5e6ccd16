"""Benchmark of the four-bar / slider-crank force analysis (plain Python, best of N).

Run:  python benchmarks/bench_dynamics.py [N]

Prints: what, size, best time, rate (samples/s). Target (issue 5): Newton–Euler
forces of a four-bar over 10^6 samples at ≥ 2 million samples/s.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from machdyn.dynamics import fourbar_dynamics, fourbar_forces, slidercrank_dynamics
from machdyn.fourbar import FourBar
from machdyn.slidercrank import SliderCrank
from machdyn.virtual_work import fourbar_input_torque


def best_of(fn, repeat: int = 5) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main(n: int = 1_000_000) -> None:
    fb = FourBar(8, 4, 7, 6)
    sc = SliderCrank(2.0, 7.0, offset=0.5)
    theta2 = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    props = dict(mass=(1.2, 2.5, 1.8), inertia=(0.8, 3.1, 1.4), cg=(1.5 + 0.3j, 3.0 - 0.8j, 2.5))
    loads = dict(gravity=9.81, load_torque4=-3.0, external_forces=[(3, 2 + 1j, 4 - 7j)])
    motion = fb.solve(theta2, 12.0, -4.0)

    def batched_9x9(m: int = min(n, 100_000)) -> None:
        a = np.broadcast_to(np.eye(9), (m, 9, 9)).copy()
        a[:, 2, 0] += theta2[:m]  # a non-trivial, well-conditioned stack of systems
        np.linalg.solve(a, np.ones((m, 9, 1)))

    rows = [
        (
            "four-bar forces, given the motion",
            n,
            lambda: fourbar_forces(fb, motion, **props, **loads),
        ),
        (
            "four-bar kinematics + forces",
            n,
            lambda: fourbar_dynamics(fb, theta2, 12.0, -4.0, **props, **loads),
        ),
        ("four-bar kinematics only (FourBar.solve)", n, lambda: fb.solve(theta2, 12.0, -4.0)),
        (
            "four-bar T12 by virtual work",
            n,
            lambda: fourbar_input_torque(fb, theta2, 12.0, -4.0, **props, **loads),
        ),
        (
            "slider-crank, Coulomb friction",
            n,
            lambda: slidercrank_dynamics(
                sc,
                theta2,
                30.0,
                mass=(1.5, 2.0, 3.0),
                inertia=(0.2, 1.8),
                cg=(0.6, 2.5),
                gravity=9.81,
                load_force4=-50.0,
                friction="coulomb",
                mu=0.15,
            ),
        ),
        ("(for scale) np.linalg.solve on (N, 9, 9)", min(n, 100_000), batched_9x9),
    ]
    print(f"{'what':44s} {'size':>9s} {'best [s]':>9s} {'rate [samples/s]':>17s}")
    for what, size, fn in rows:
        t = best_of(fn)
        print(f"{what:44s} {size:9d} {t:9.4f} {size / t:17.3g}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000)
