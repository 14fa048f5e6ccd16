"""Benchmarks of machdyn.synthesis (plain Python; prints a small table).

Run:  python benchmarks/bench_synthesis.py

Targets (issue 6): coupler curves of 10^5 four-bars × 360 points in under 2 s;
a path synthesis to 10 target points in under 30 s.
"""

from __future__ import annotations

import time

import numpy as np

from machdyn import jit
from machdyn.fourbar import FourBar
from machdyn.synthesis import (
    PlacedFourBar,
    atlas,
    coupler_points,
    function_generator,
    synthesize_path,
    three_position,
)


def best_of(fn, repeat):
    best = float("inf")
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main() -> None:
    rng = np.random.default_rng(7)
    rows = []

    n, m = 100_000, 360
    lengths = rng.uniform(0.5, 3.0, size=(4, n))
    p = rng.uniform(0.0, 2.0, n)
    delta = rng.uniform(-np.pi, np.pi, n)
    theta2 = np.linspace(0.0, 2.0 * np.pi, m, endpoint=False)
    t, _ = best_of(lambda: coupler_points(*lengths, p, delta, theta2), 3)
    rows.append(("coupler_points (random four-bars)", f"{n} x {m}", t, n * m / t, "points/s"))

    grid = np.linspace(1.0, 4.0, 10)
    t, at = best_of(
        lambda: atlas(grid, grid, grid, np.linspace(0, 2, 10), np.linspace(-3, 3, 10)), 3
    )
    rows.append(("atlas grid (unit crank)", f"{len(at)} x 360", t, at.points.size / t, "points/s"))

    c = [0 + 5.086j, 2.019 + 3.181j, 3.933 + 4.051j]
    d = [0.741 + 2.703j, 4.428 + 2.529j, 6.304 + 4.83j]
    t, _ = best_of(lambda: three_position(c, d), 20)
    rows.append(("three_position (notes' table)", "3 positions", t, 1 / t, "syntheses/s"))

    t, _ = best_of(
        lambda: function_generator(
            np.log10, (1.0, 2.0), np.radians((45, 105)), np.radians((135, 225)), n=25
        ),
        20,
    )
    rows.append(("function_generator (least squares)", "25 points", t, 1 / t, "syntheses/s"))

    fb = FourBar(5, 2, 5, 4, coupler=(3.0, 0.6))
    placed = PlacedFourBar(fb, 1 + 2j, 0.3, 1)
    th = np.linspace(0, 2 * np.pi, 10, endpoint=False)
    _, _, targets, _ = placed.pose(th)
    for label, timing in (("untimed", None), ("timed", th)):
        t, res = best_of(lambda timing=timing: synthesize_path(targets, timing=timing, seed=1), 1)
        rows.append(
            (
                f"synthesize_path ({label})",
                "10 targets",
                t,
                float(res.distance.max()),
                "max distance",
            )
        )

    why = jit.reason() or f"MACHDYN_JIT={jit.mode()}"
    kernels = "compiled" if jit.active() else f"NumPy ({why})"
    print(f"coupler-point kernels: {kernels} (machdyn.jit; MACHDYN_JIT=off for NumPy)\n")
    print(f"{'what':40s} {'size':>14s} {'time [s]':>10s} {'rate':>14s}")
    for what, size, t, rate, unit in rows:
        print(f"{what:40s} {size:>14s} {t:10.3f} {rate:14.4g} {unit}")


if __name__ == "__main__":
    main()
