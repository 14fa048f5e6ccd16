"""Benchmark of machdyn.cams: python benchmarks/bench_cams.py

Target (issue 3): a 3,600-point double-dwell program with profile, pressure
angle and curvature in under 10 ms.
"""

from __future__ import annotations

import time

import numpy as np

from machdyn import cams


def best_of(fn, repeat: int = 30) -> float:
    fn()  # warm-up
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    program = cams.CamProgram.double_dwell(1.0, np.radians(60), np.radians(60), "modified_sine")
    roller = cams.TranslatingRoller(3.0, 0.5, 0.2)
    flat = cams.TranslatingFlatFace(8.0)
    rocker = cams.OscillatingRoller(2.0, 0.3, 4.0, 3.5)
    rocker_program = cams.CamProgram.double_dwell(np.radians(15), np.radians(90), np.radians(90))
    n = 3600
    profile = roller.profile(program, n)
    cases = [
        ("svaj sample, double dwell", n, lambda: program.sample(n)),
        ("svaj + translating roller profile", n, lambda: roller.profile(program, n)),
        ("svaj + flat-faced profile", n, lambda: flat.profile(program, n)),
        ("svaj + oscillating roller profile", n, lambda: rocker.profile(rocker_program, n)),
        ("svaj + roller profile", 100_000, lambda: roller.profile(program, 100_000)),
        ("continuity check", 4, program.continuity),
        ("size_roller (closed form)", n, lambda: cams.size_roller(program, 0.5)),
        (
            "surface self-intersection (global)",
            n,
            lambda: cams.surface_self_intersection(profile.theta, profile.surface),
        ),
        ("profile + every design check", n, lambda: roller.profile(program, n).checks()),
    ]
    print(f"{'what':<38} {'size':>8} {'time (ms)':>10} {'rate (samples/s)':>17}")
    for what, size, fn in cases:
        t = best_of(fn, repeat=10 if size > 10_000 else 30)
        print(f"{what:<38} {size:>8} {t * 1e3:>10.3f} {size / t:>17,.0f}")


if __name__ == "__main__":
    main()
