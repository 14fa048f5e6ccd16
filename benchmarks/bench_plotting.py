"""Timings of the plotting front-end: viewer pages, still pictures, GIF animations.

Run: ``MPLBACKEND=Agg python benchmarks/bench_plotting.py``. Prints what, size,
best time of N runs and a rate.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np

from machdyn import FourBar
from machdyn.plot import animate, plot_coupler_curve, plot_kinematics, sweep
from machdyn.viewer import to_html


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    fb = FourBar(8, 4, 7, 6, coupler=(5.0, np.radians(30)))  # the notes' HW 6 linkage
    out = Path(tempfile.mkdtemp())
    motion = fb.solve(np.radians(np.arange(0.0, 360.0, 1.0)), omega2=10.0)
    animate(fb, n=4, path=out / "warm.gif")  # fonts and caches

    def still() -> None:
        plot_coupler_curve(fb).figure.savefig(out / "still.png")
        plt.close("all")

    def kinematics() -> None:
        plot_kinematics(motion, jerk=True).savefig(out / "kin.png")
        plt.close("all")

    cases = [
        ("sweep (poses)", 360, "frames", lambda: sweep(fb, n=360), 20),
        ("to_html", 360, "frames", lambda: to_html(fb, n=360), 10),
        ("plot_coupler_curve + PNG", 721, "points", still, 3),
        ("plot_kinematics(jerk) + PNG", 360, "samples", kinematics, 3),
        ("animate -> GIF, 80 dpi", 90, "frames", lambda: animate(fb, n=90, path=out / "a.gif"), 2),
    ]
    print(f"{'what':32s} {'size':>8s} {'time':>10s} {'rate':>16s}")
    for what, size, unit, fn, repeat in cases:
        t = best(fn, repeat)
        print(f"{what:32s} {size:8d} {t * 1e3:8.1f} ms {size / t:10.0f} {unit}/s")


if __name__ == "__main__":
    main()
