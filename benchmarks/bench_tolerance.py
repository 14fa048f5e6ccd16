"""Benchmark of the Monte Carlo tolerance analysis (issue 15), interleaved with its peer.

Run:  pip install -e ".[bench]"          # pylinkage 1.3.0, the peer (never a run-time need)
      python benchmarks/bench_tolerance.py [repeats]
      python benchmarks/bench_tolerance.py --dask 10000000 [workers]

Target: 10^5 four-bars x 360 poses in <= 5 s. The peer is pylinkage's
``Linkage.analyze_tolerance`` (the only peer with a Monte Carlo tolerance
analysis), which re-simulates one linkage per sample in Python; both run the
HW 6 crank-rocker with a coupler point, the same five dimensions uniform
within +/-0.01 (pylinkage does not tolerance the ground pivots, so neither
does machdyn here), 360 poses a turn, interleaved, best of ``repeats``. The
ratio is per sample. Wall and CPU time are both reported: the machine is shared.

``--dask N``: the same analysis for N samples on a Dask ``LocalCluster``
(``workers`` processes, one thread each), chunks of 2^15 samples; prints the
wall time and the client's peak memory (the workers hold one chunk each).
"""

from __future__ import annotations

import math
import platform
import resource
import sys
import time

import numpy as np

import machdyn

FB = machdyn.FourBar(8.0, 4.0, 7.0, 6.0, coupler=(3.0, 0.5))
TOL = {"r2": 0.01, "r3": 0.01, "r4": 0.01, "p": 0.01, "delta": 0.01}
UNIFORM = {k: (v, "uniform") for k, v in TOL.items()}


def ours(samples: int, **options):
    return machdyn.tolerance(FB, UNIFORM, samples=samples, outputs=["coupler"], **options)


def peer(samples: int):
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import FixedDyad, RRRDyad
    from pylinkage.simulation import Linkage

    o2, o4 = Ground(0.0, 0.0, name="O2"), Ground(8.0, 0.0, name="O4")
    crank = Crank(anchor=o2, radius=4.0, angular_velocity=2 * math.pi / 360, name="crank")
    rocker = RRRDyad(crank.output, o4, distance1=7.0, distance2=6.0, name="B")
    point = FixedDyad(crank.output, rocker, distance=3.0, angle=0.5, name="P")
    lk = Linkage([o2, o4, crank, rocker, point], name="hw6")
    names = ("crank_radius", "B_dist1", "B_dist2", "P_radius", "P_angle")
    return lk.analyze_tolerance(dict.fromkeys(names, 0.01), output_joint=point,
                                n_samples=samples, seed=1)  # fmt: skip


def load() -> str:
    with open("/proc/loadavg") as f:
        return f.read().split()[0]


def timed(fn):
    w0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return time.perf_counter() - w0, time.process_time() - c0, out


def main(repeat: int = 3) -> None:
    import pylinkage

    print(f"python {platform.python_version()}, numpy {np.__version__}, "
          f"pylinkage {pylinkage.__version__}, load {load()}")  # fmt: skip
    ours(1000)
    peer(5)
    mine, theirs = [], []
    for _ in range(repeat):  # interleaved: the machine's load hits both alike
        mine.append(timed(lambda: ours(100_000)))
        theirs.append(timed(lambda: peer(200)))
    wall, cpu, t = min(mine, key=lambda r: r[0])
    pw, pc, p = min(theirs, key=lambda r: r[0])
    print(f"machdyn.tolerance, 10^5 x 360 four-bars (coupler point): {wall:.2f} s wall, "
          f"{cpu:.2f} s CPU (target 5 s)  = {wall / 1e5 * 1e6:.1f} us per linkage")  # fmt: skip
    print(f"pylinkage analyze_tolerance, 200 x 360: {pw:.2f} s wall, {pc:.2f} s CPU "
          f"= {pw / 200 * 1e3:.1f} ms per linkage")  # fmt: skip
    print(f"  ratio per linkage (pylinkage / machdyn): wall {pw / 200 / (wall / 1e5):.0f}x, "
          f"CPU {pc / 200 / (cpu / 1e5):.0f}x")  # fmt: skip
    rms = t.outputs["coupler"].std
    their = np.sqrt(np.sum(np.std(p.output_cloud, axis=0) ** 2, axis=1))
    print(f"  same answer: mean RMS spread of P {rms.mean():.5f} (machdyn, 10^5) vs "
          f"{their.mean():.5f} (pylinkage, 200 samples)")  # fmt: skip


def dask(samples: int, workers: int) -> None:
    print(f"python {platform.python_version()}, numpy {np.__version__}, load {load()}")
    wall, _, t = timed(lambda: ours(samples, scheduler="local", workers=workers))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    rate = samples * 360 / wall / 1e6
    print(f"machdyn.tolerance on a LocalCluster of {workers} workers, {samples:,} x 360: "
          f"{wall:.1f} s wall ({rate:.1f} M poses/s), client peak {peak:.0f} MB")  # fmt: skip
    print(f"  {t!r}")


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--dask":
        dask(int(float(sys.argv[2])), int(sys.argv[3]) if len(sys.argv) > 3 else 2)
    else:
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 3)
