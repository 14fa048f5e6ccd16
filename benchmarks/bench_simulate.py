"""Benchmarks of machines in time and tolerance (issue 15), best of N, interleaved.

Run:  python benchmarks/bench_simulate.py [repeats]

Targets: a four-bar start-up to steady state over 20 turns ≤ 0.5 s.

The peer of the tabulated simulation is the same integration solving the
linkage at every right-hand side (``table=False``, what a direct
``solve_ivp`` over the force analysis costs); it is timed over one turn and
reported per turn, with the ratio.
"""

from __future__ import annotations

import platform
import sys
import time

import numpy as np
import scipy

import machdyn
import machdyn.jit
from machdyn.simulate import DCMotor

FB = machdyn.FourBar(0.08, 0.04, 0.07, 0.06)
MASSES = dict(mass=(0.2, 0.3, 0.25), inertia=(3e-5, 1.2e-4, 7.5e-5), cg=(0.02, 0.035, 0.03))
MOTOR = DCMotor(stall_torque=0.05, no_load_speed=300.0, ratio=10.0, inertia=2e-5)


def start_up(turns: float, table: bool = True):
    return machdyn.simulate(
        FB, MOTOR, flywheel=2e-3, turns=turns, gravity=9.81, table=table, samples=101, **MASSES
    )


def timed(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def main(repeat: int = 5) -> None:
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}",
        flush=True,
    )
    machdyn.jit.load()  # the compiled kernels (numba's cache), before anything is timed
    start_up(1.0)  # imports, caches
    rows: dict[str, list[float]] = {"table": [], "exact": []}
    for _ in range(repeat):  # interleaved: the machine's load hits both alike
        rows["table"].append(timed(lambda: start_up(20.0)))
        rows["exact"].append(timed(lambda: start_up(1.0, table=False)))
    run = start_up(20.0)
    table, exact = min(rows["table"]), min(rows["exact"])
    print(f"four-bar start-up, 20 turns, tabulated: {table:.3f} s  (target 0.5 s)")
    print(f"  {run.table}; steady k = {run.steady.k:.4f} after {len(run.cycles)} turns")
    print(f"the same solving the linkage at every step: {exact:.3f} s per turn")
    print(f"  ratio per turn (exact / tabulated): {exact / (table / 20.0):.0f}x")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
