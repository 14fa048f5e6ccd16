"""Benchmark of the general vector-loop solver (run: python benchmarks/bench_loops.py).

One full input turn, continuation on (the default), positions + velocities +
accelerations (and, separately, + jerks), best of N runs, single process.
The rows are the NumPy path (``MACHDYN_JIT=off``) unless marked "compiled"
(the numba sweep, loaded first). On the NumPy path even sweeps take the fast
path (plain-float coarse march + one batched fill); the "careful path" rows
force the general doubling-wave continuation (what uneven or hard sweeps get)
for comparison. Also compares the hand-vectorised batched LU with
numpy.linalg.solve.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from machdyn import jit
from machdyn.loops import LoopSystem, lu_factor, lu_solve
from machdyn.loops import solve as core


def fourbar() -> tuple[LoopSystem, dict]:
    s = (
        LoopSystem()
        .vector("R1", 8.0, 0.0)
        .vector("R2", 2.0, "theta2")
        .vector("R3", 7.0, "theta3")
        .vector("R4", 6.0, "theta4")
        .loop("R2 + R3 - R4 - R1")
        .inputs("theta2")
    )
    return s, {"theta3": 1.2, "theta4": 1.9}


def sixbar() -> tuple[LoopSystem, dict]:
    """Watt II with a slider: 4 unknowns theta3, theta4, theta5, d6."""
    s = (
        LoopSystem()
        .vector("R1", 8.0, 0.0)
        .vector("R2", 2.0, "theta2")
        .vector("R3", 7.0, "theta3")
        .vector("R4", 6.0, "theta4")
        .vector("R4c", 6.5, "theta4")
        .vector("R5", 7.0, "theta5")
        .vector("R6", "d6", 0.0)
        .vector("R7", 8.0, np.pi / 2)
        .loop("R2 + R3 - R4 - R1")
        .loop("R1 + R4c + R5 - R6 - R7")
        .inputs("theta2")
    )
    return s, {"theta3": 1.2, "theta4": 1.9, "theta5": 0.4, "d6": 10.0}


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    big = int(float(sys.argv[1])) if len(sys.argv) > 1 else 1_000_000
    rows = []
    assert jit.load(), jit.reason()
    jit.set_mode("on")
    for label, build in (
        ("four-bar (2 unknowns)", fourbar),
        ("six-bar+slider (4 unknowns)", sixbar),
    ):
        s, guess = build()
        for n in (3_600, big):
            theta2 = np.linspace(0.0, 2 * np.pi, n)
            kw = {"velocity": {"theta2": 10.0}, "order": 2}
            m = s.solve({"theta2": theta2}, guess=guess, **kw)
            assert m.ok.all(), f"{label}: {np.unique(m.reason)}"
            t = best(
                lambda s=s, kw=kw, theta2=theta2, guess=guess: s.solve(
                    {"theta2": theta2}, guess=guess, **kw
                ),
                20 if n <= 10_000 else 5,
            )
            rows.append((f"{label} pos+vel+acc, compiled", n, t, n / t))
    jit.set_mode("off")
    for label, build in (
        ("four-bar (2 unknowns)", fourbar),
        ("six-bar+slider (4 unknowns)", sixbar),
    ):
        s, guess = build()
        for n in (3_600, big):
            theta2 = np.linspace(0.0, 2 * np.pi, n)
            repeat = 20 if n <= 10_000 else 5
            for what, kw in (
                ("pos", {}),
                ("pos+vel+acc", {"velocity": {"theta2": 10.0}, "order": 2}),
                ("pos+vel+acc+jerk", {"velocity": {"theta2": 10.0}}),
            ):
                m = s.solve({"theta2": theta2}, guess=guess, **kw)
                assert m.ok.all(), f"{label}: {np.unique(m.reason)}"
                t = best(
                    lambda s=s, kw=kw, theta2=theta2, guess=guess: s.solve(
                        {"theta2": theta2}, guess=guess, **kw
                    ),
                    repeat,
                )
                rows.append((f"{label} {what}", n, t, n / t))
            if n <= 10_000:  # the same turn on the careful path (uneven/hard sweeps)
                kw = {"velocity": {"theta2": 10.0}, "order": 2}
                fast_max, core.FAST_MAX_SAMPLES = core.FAST_MAX_SAMPLES, 0
                try:
                    t = best(
                        lambda s=s, kw=kw, theta2=theta2, guess=guess: s.solve(
                            {"theta2": theta2}, guess=guess, **kw
                        ),
                        repeat,
                    )
                finally:
                    core.FAST_MAX_SAMPLES = fast_max
                rows.append((f"{label} pos+vel+acc, careful path", n, t, n / t))
    # Linear algebra: batched LU vs numpy.linalg.solve on (N, n, n).
    rng = np.random.default_rng(0)
    for n_unk in (2, 4, 8):
        n = big
        a = rng.normal(size=(n_unk, n_unk, n)) + 3 * np.eye(n_unk)[:, :, None]
        b = rng.normal(size=(n_unk, n))
        t_lu = best(lambda a=a, b=b: lu_solve(lu_factor(a), b), 3)
        a_np = np.ascontiguousarray(np.moveaxis(a, -1, 0))
        b_np = np.ascontiguousarray(b.T)[..., None]
        t_np = best(lambda a_np=a_np, b_np=b_np: np.linalg.solve(a_np, b_np), 3)
        rows.append((f"batched LU solve {n_unk}x{n_unk}", n, t_lu, n / t_lu))
        rows.append((f"np.linalg.solve {n_unk}x{n_unk}", n, t_np, n / t_np))
    print(f"{'what':54s} {'size':>9s} {'time [s]':>10s} {'rate [/s]':>12s}")
    for what, n, t, rate in rows:
        print(f"{what:54s} {n:9d} {t:10.4f} {rate:12.3g}")


if __name__ == "__main__":
    main()
