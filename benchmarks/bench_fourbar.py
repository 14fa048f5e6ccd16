"""Four-bar closed-form throughput: positions, and positions + velocities + accelerations.

Run: python benchmarks/bench_fourbar.py  (prints a Markdown table; best of N repeats)
Each case runs on the NumPy kernels and on the compiled (numba) ones; in normal use
``machdyn.jit``'s "auto" rule moves from the first to the second once NumPy has
spent 0.5 s. ``MACHDYN_THREADS=1`` keeps large arrays on one thread.
Also measures, in fresh interpreters, `import machdyn` plus the first 3,600-pose
solve (the "auto" rule: NumPy) and the cost of loading the compiled kernels
(from numba's on-disk cache; run once beforehand so that the cache exists).
"""

from __future__ import annotations

import platform
import subprocess
import sys
import time

import numpy as np

import machdyn
from machdyn import jit
from machdyn._parallel import threads
from machdyn.fourbar import FourBar, positions


def best_of(fn, repeats: int) -> float:
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def fresh_interpreter(code: str, runs: int = 5) -> float:
    """Best time printed by ``code`` over fresh interpreters."""
    return min(float(subprocess.check_output([sys.executable, "-c", code])) for _ in range(runs))


COLD_START = (
    "import time; t0 = time.perf_counter(); import numpy as np; import machdyn; "
    "m = machdyn.FourBar(8, 4, 7, 6).solve(np.linspace(0, 2*np.pi, 3600), omega2=1.0); "
    "print(time.perf_counter() - t0)"
)
LOAD = (
    "import time; import machdyn; from machdyn import jit; t0 = time.perf_counter(); "
    "assert jit.load(), jit.reason(); print(time.perf_counter() - t0)"
)


def main() -> None:
    fb = FourBar(8, 4, 7, 6, coupler=(5.0, 0.5))
    plain = FourBar(8, 4, 7, 6)
    rows = []
    # NumPy first, as under the "auto" rule: importing numba (or scipy.optimize) leaves
    # glibc's heap so that NumPy's temporaries are trimmed and faulted in again at every
    # call, up to twice as slow (the compiled kernels allocate no temporaries).
    for backend in ("numpy", "compiled"):
        if backend == "numpy":
            jit.set_mode("off")
        else:
            assert jit.load(), jit.reason()  # compiles the first time; then numba's cache
            jit.set_mode("on")
        for n, repeats in ((3_600, 200), (1_000_000, 7)):
            theta2 = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
            cases = {
                "positions (`fourbar.positions`)": lambda t=theta2: positions(8, 4, 7, 6, t),
                "pos + vel + acc (`solve(order=2)`)": lambda t=theta2: plain.solve(
                    t, omega2=10.0, alpha2=1.0, order=2
                ),
                "pos + vel + acc + jerk (`solve()`)": lambda t=theta2: plain.solve(
                    t, omega2=10.0, alpha2=1.0
                ),
                "... with a coupler point": lambda t=theta2: fb.solve(t, omega2=10.0, alpha2=1.0),
            }
            for name, fn in cases.items():
                fn()  # warm up (and compile this variant)
                dt = best_of(fn, repeats)
                rows.append((backend, name, n, dt, n / dt))
    python = platform.python_version()
    versions = f"numpy {np.__version__}, numba {numba_version()}, Python {python}"
    print(f"machdyn {machdyn.__version__}, {versions}")
    print(f"{platform.processor() or platform.machine()}, 1 process, {threads()} thread(s)")
    print("(threads only for arrays of 65,536 samples or more)\n")
    print("| kernels | what | poses | time | poses/s |")
    print("|---|---|---:|---:|---:|")
    for backend, name, n, dt, rate in rows:
        print(f"| {backend} | {name} | {n:,} | {dt * 1e3:.2f} ms | {rate / 1e6:.1f} M |")
    cold = fresh_interpreter(COLD_START) * 1e3
    load = fresh_interpreter(LOAD) * 1e3
    print(f"| | cold `import machdyn` + first 3,600-pose solve | 3,600 | {cold:.0f} ms | |")
    print(f"| | loading the compiled kernels (cached), `jit.load()` | | {load:.0f} ms | |")


def numba_version() -> str:
    import numba

    return numba.__version__


if __name__ == "__main__":
    main()
