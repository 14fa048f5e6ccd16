"""Four-bar closed-form throughput: positions, and positions + velocities + accelerations.

Run: python benchmarks/bench_fourbar.py  (prints a Markdown table; best of N repeats)
Also measures `import machdyn` plus the first 3,600-pose solve in a fresh interpreter.
"""

from __future__ import annotations

import platform
import subprocess
import sys
import time

import numpy as np

import machdyn
from machdyn.fourbar import FourBar, positions


def best_of(fn, repeats: int) -> float:
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def cold_start() -> float:
    code = (
        "import time; t0 = time.perf_counter(); import numpy as np; import machdyn; "
        "m = machdyn.FourBar(8, 4, 7, 6).solve(np.linspace(0, 2*np.pi, 3600), omega2=1.0); "
        "print(time.perf_counter() - t0)"
    )
    runs = [float(subprocess.check_output([sys.executable, "-c", code])) for _ in range(5)]
    return min(runs)


def main() -> None:
    fb = FourBar(8, 4, 7, 6, coupler=(5.0, 0.5))
    plain = FourBar(8, 4, 7, 6)
    rows = []
    for n, repeats in ((3_600, 200), (1_000_000, 7)):
        theta2 = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
        cases = {
            "positions (machdyn.fourbar.positions)": lambda t=theta2: positions(8, 4, 7, 6, t),
            "pos + vel + acc (FourBar.solve, order=2)": lambda t=theta2: plain.solve(
                t, omega2=10.0, alpha2=1.0, order=2
            ),
            "pos + vel + acc + jerk (FourBar.solve)": lambda t=theta2: plain.solve(
                t, omega2=10.0, alpha2=1.0
            ),
            "... with a coupler point": lambda t=theta2: fb.solve(t, omega2=10.0, alpha2=1.0),
        }
        for name, fn in cases.items():
            fn()  # warm up
            dt = best_of(fn, repeats)
            rows.append((name, n, dt, n / dt))
    versions = f"numpy {np.__version__}, Python {platform.python_version()}"
    print(f"machdyn {machdyn.__version__}, {versions}")
    print(f"{platform.processor() or platform.machine()}, 1 process, 1 thread\n")
    print("| what | poses | time | poses/s |")
    print("|---|---:|---:|---:|")
    for name, n, dt, rate in rows:
        print(f"| {name} | {n:,} | {dt * 1e3:.2f} ms | {rate / 1e6:.1f} M |")
    cold = cold_start() * 1e3
    print(f"| cold `import machdyn` + first 3,600-pose solve | 3,600 | {cold:.0f} ms | |")


if __name__ == "__main__":
    main()
