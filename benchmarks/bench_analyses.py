"""Benchmark of the notes' analyses: python benchmarks/bench_analyses.py

No speed target is set for them (issue 16); the numbers say what they cost next
to a peer in the same run: the instant centres of a six-bar against the
solve that produces its motion, the centrodes' rolling against the centrodes,
the critical-path cam against a cycloidal program. Cases are interleaved (one
repetition of each in turn) so that the shared machine's noise hits all alike.
"""

from __future__ import annotations

import platform
import time

import numpy as np
import scipy

from machdyn import FourBar
from machdyn.cams import CamProgram, CriticalPathMotion
from machdyn.centres import linkage_centres
from machdyn.centrodes import centrodes
from machdyn.linkage import Linkage
from machdyn.rotor import Rotor


def six_bar() -> Linkage:
    """A four-bar whose coupler point drives a rod and a block sliding on the ground."""
    pts = {"O2": 0j, "O4": 7 + 0j, "A": 2j, "B": 6 + 5j, "C": 3 + 4.5j, "D": 8 + 6j, "D2": 9 + 6j}
    lk = Linkage(pts).ground("O2", "O4").link("crank", "O2", "A")
    lk.link("coupler", "A", "B", "C").link("rocker", "O4", "B").link("rod", "C", "D")
    return lk.link("block", "D", "D2").slider("block", "ground", "D", "D2").drive("crank")


def interleaved(cases: dict, repeat: int) -> dict[str, float]:
    best = dict.fromkeys(cases, np.inf)
    for fn in cases.values():
        fn()  # warm-up
    for _ in range(repeat):
        for name, fn in cases.items():
            start = time.perf_counter()
            fn()
            best[name] = min(best[name], time.perf_counter() - start)
    return best


def main() -> None:
    lk = six_bar()
    theta = np.radians(np.linspace(70, 110, 100_000))
    motion = lk.solve(theta, velocity=1.0)
    fb = FourBar(8, 4, 7, 6)
    sweep = np.radians(np.linspace(20, 80, 2001))
    c = centrodes(fb, sweep, moving=3)
    grid = np.arange(0, 360, 5.0)
    table = CamProgram.double_dwell(1.0, np.radians(90), np.radians(90)).svaj(np.radians(grid)).s
    cpm = CriticalPathMotion.from_degrees(grid, table)
    program = CamProgram.double_dwell(1.0, np.radians(90), np.radians(90))
    rotor = Rotor.from_masses([0.2, 0.15, 0.1], [0.06, 0.05j, -0.04 + 0.03j], [0.1, 0.25, 0.35])
    omega = np.linspace(1, 300, 1_000_000)
    fit = CriticalPathMotion.from_degrees
    cases = {
        "six-bar solve (100,000 poses, velocities)": lambda: lk.solve(theta, velocity=1.0),
        "six-bar instant centres (100,000 poses, 15 each)": lambda: linkage_centres(lk, motion),
        "four-bar centrodes (2,001 poses)": lambda: centrodes(fb, sweep, moving=3),
        "centrodes roll() (2,001 poses)": c.roll,
        "four-bar inversions table (4 x 2 forms)": lambda: fb.inversions(n=2001),
        "rotor bearing reactions (1,000,000 speeds)": lambda: rotor.bearing_reactions(omega, 0, 1),
        "cam: cycloidal program sample (3,600)": lambda: program.sample(3600),
        "cam: critical path fit + sample (72 pts -> 3,600)": lambda: fit(grid, table).sample(3600),
        "cam: critical path sample only (3,600)": lambda: cpm.sample(3600),
    }
    best = interleaved(cases, repeat=5)
    print(f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}")
    print(f"{'case':55s} {'best (ms)':>10s}")
    for name, t in best.items():
        print(f"{name:55s} {1e3 * t:10.2f}")
    ratio = (
        best["six-bar instant centres (100,000 poses, 15 each)"]
        / best["six-bar solve (100,000 poses, velocities)"]
    )
    print(f"instant centres / solve: {ratio:.2f}")


if __name__ == "__main__":
    main()
