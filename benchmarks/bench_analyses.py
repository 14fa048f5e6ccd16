"""Benchmark of the notes' analyses: python benchmarks/bench_analyses.py

No speed target is set for them (issue 16); the numbers say what they cost next
to a peer in the same run: the instant centres of a six-bar against the
solve that produces its motion, the centrodes' rolling against the centrodes,
the critical-path cam against a cycloidal program, the inverted slider-crank's
closed-form forces against the slider-crank's and an equivalent Linkage's.
Cases are interleaved (one repetition of each in turn) so that the shared
machine's noise hits all alike; wall and CPU time (best of the repetitions).
"""

from __future__ import annotations

import platform
import time

import numpy as np
import scipy

from machdyn import FourBar, InvertedSliderCrank, SliderCrank
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


def shaper() -> tuple[InvertedSliderCrank, Linkage]:
    """An inverted slider-crank with masses, and the same machine drawn as a Linkage."""
    isc = InvertedSliderCrank(2.0, 4.0, 0.5)
    m0 = isc.solve(np.radians(40.0))
    A0, e4 = complex(m0.A), np.exp(1j * float(m0.theta4))
    lk = Linkage({"O2": 0j, "A": A0, "O4": 4 + 0j, "K": A0 + e4, "Q": 4 + e4})
    lk.ground("O2", "O4").link("crank", "O2", "A", **SHAPER[0])
    lk.link("block", "A", "K", **SHAPER[1]).link("rocker", "O4", "Q", **SHAPER[2])
    return isc, lk.slider("block", "rocker", "A", float(m0.theta4), name="slot").drive("crank")


SHAPER = (
    {"mass": 1.0, "inertia": 0.1, "cg": 1 + 0.2j},
    {"mass": 0.5, "inertia": 0.01, "cg": 0.1 + 0.05j},
    {"mass": 3.0, "inertia": 2.0, "cg": 2 + 0.3j},
)
SHAPER_KW = {k: tuple(link[k] for link in SHAPER) for k in ("mass", "inertia", "cg")}


def interleaved(cases: dict, repeat: int) -> tuple[dict[str, float], dict[str, float]]:
    best = dict.fromkeys(cases, np.inf)
    cpu = dict.fromkeys(cases, np.inf)
    for fn in cases.values():
        fn()  # warm-up
    for _ in range(repeat):
        for name, fn in cases.items():
            start, start_cpu = time.perf_counter(), time.process_time()
            fn()
            best[name] = min(best[name], time.perf_counter() - start)
            cpu[name] = min(cpu[name], time.process_time() - start_cpu)
    return best, cpu


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
    isc, shaper_lk = shaper()
    turn = np.linspace(0.0, 2 * np.pi, 100_000, endpoint=False) + 0.01
    sc = SliderCrank(2.0, 6.0, 0.5)
    sc_kw = {"mass": (1.0, 2.0, 0.5), "inertia": (0.1, 0.6), "cg": (1.0, 3.0 + 0.2j)}

    def shaper_linkage():
        return shaper_lk.forces(shaper_lk.solve(turn, velocity=10.0), gravity=9.81)

    cases = {
        "inverted slider-crank dynamics (100,000 poses)": lambda: isc.dynamics(
            turn, 10.0, gravity=9.81, **SHAPER_KW
        ),
        "slider-crank dynamics (100,000 poses; peer)": lambda: sc.dynamics(
            turn, 10.0, gravity=9.81, **sc_kw
        ),
        "same shaper as a Linkage: solve + forces (100,000)": shaper_linkage,
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
    best, cpu = interleaved(cases, repeat=5)
    print(f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}")
    print(f"{'case':55s} {'best (ms)':>10s} {'cpu (ms)':>10s}")
    for name, t in best.items():
        print(f"{name:55s} {1e3 * t:10.2f} {1e3 * cpu[name]:10.2f}")
    ratio = (
        best["six-bar instant centres (100,000 poses, 15 each)"]
        / best["six-bar solve (100,000 poses, velocities)"]
    )
    print(f"instant centres / solve: {ratio:.2f}")
    shaper_ratio = (
        best["same shaper as a Linkage: solve + forces (100,000)"]
        / best["inverted slider-crank dynamics (100,000 poses)"]
    )
    print(f"shaper as a Linkage / InvertedSliderCrank.dynamics: {shaper_ratio:.1f}")


if __name__ == "__main__":
    main()
