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

``--linkage [samples]``: a drawn Watt six-bar (machdyn.linkage.Linkage) on the
family solver, every link length, the coupler point's and the ternary
rocker's polar parameters and the frame's distances ±0.01 (normal, 3σ), the
coupler point P and the output angle over 360 poses, 10^5 samples by default;
its peer is the same analysis done by hand, each sample built as its own
Linkage and solved by ``Linkage.solve`` (200 samples), interleaved.

``--linkage-dask N [workers]``: the six-bar analysis for N samples on a Dask
``LocalCluster`` (as ``--dask`` for the four-bar).

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


def dask(samples: int, workers: int, run=None) -> None:
    run = ours if run is None else run
    print(f"python {platform.python_version()}, numpy {np.__version__}, load {load()}")
    wall, _, t = timed(lambda: run(samples, scheduler="local", workers=workers))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    rate = samples * 360 / wall / 1e6
    print(f"machdyn.tolerance on a LocalCluster of {workers} workers, {samples:,} x 360: "
          f"{wall:.1f} s wall ({rate:.1f} M poses/s), client peak {peak:.0f} MB")  # fmt: skip
    print(f"  {t!r}")


WATT = {"O2": 0j, "O4": 6 + 0j, "O6": 10 + 3j, "A": 1.5 + 0j, "B": 4.75 + 3.7997j,
        "C": 9.3316 + 1.3641j, "D": 7.5444 + 5.494j, "P": 3.125 + 2.8998j}  # fmt: skip
SIX = ("O2-O4", "O6.p", "O6.delta", "O2-A", "A-B", "P.p", "P.delta", "O4-B", "C.p", "C.delta",
       "C-D", "O6-D")  # fmt: skip


def watt(points):
    from machdyn.linkage import Linkage

    return (
        Linkage(points).ground("O2", "O4", "O6").link("crank", "O2", "A")
        .link("coupler", "A", "B", "P").link("rocker", "O4", "B", "C")
        .link("coupler2", "C", "D").link("output", "O6", "D").drive("crank")
    )  # fmt: skip


def six_ours(samples: int, **options):
    tol = {k: 0.01 if not k.endswith("delta") else 0.002 for k in SIX}
    return machdyn.tolerance(
        watt(WATT), tol, samples=samples, outputs=["point.P", "theta.output"], **options
    )


def six_by_hand(samples: int) -> float:
    """Each sample its own drawing (moved points, a first-order stand-in) and Linkage.solve."""
    rng = np.random.default_rng(0)
    theta = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    nominal = watt(WATT).solve(theta).points["P"]
    worst = 0.0
    for _ in range(samples):
        moved = {k: z + complex(*rng.normal(0.0, 0.01 / 3, 2)) for k, z in WATT.items()}
        m = watt(moved).solve(theta)
        worst = max(worst, float(np.abs(m.points["P"] - nominal).max()))
    return worst


def linkage(samples: int, repeat: int = 3) -> None:
    print(f"python {platform.python_version()}, numpy {np.__version__}, load {load()}")
    six_ours(2000)
    six_by_hand(5)
    mine, theirs = [], []
    for _ in range(repeat):
        mine.append(timed(lambda: six_ours(samples)))
        theirs.append(timed(lambda: six_by_hand(200)))
    wall, cpu, t = min(mine, key=lambda r: r[0])
    pw, pc, _ = min(theirs, key=lambda r: r[0])
    print(
        f"machdyn.tolerance, {samples:,} x 360 Watt six-bars (12 dimensions, 2 outputs): "
        f"{wall:.2f} s wall, {cpu:.2f} s CPU = {cpu / samples * 1e6:.1f} us CPU per linkage"
    )
    print(
        f"each sample its own Linkage + Linkage.solve, 200 x 360: {pw:.2f} s wall, {pc:.2f} s "
        f"CPU = {pc / 200 * 1e3:.2f} ms CPU per linkage; ratio {pc / 200 / (cpu / samples):.0f}x"
    )
    s = t.outputs["point.P"]
    print(
        f"  P: std {s.std.max():.5f} (linear {s.linear_std.max():.5f}), worst {s.worst:.5f}, "
        f"stack-up {s.worst_case.max():.5f}; {t.failed} unassembled; load {load()}"
    )


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--linkage-dask":
        dask(int(float(sys.argv[2])), int(sys.argv[3]) if len(sys.argv) > 3 else 2, six_ours)
    elif len(sys.argv) > 1 and sys.argv[1] == "--linkage":
        linkage(int(float(sys.argv[2])) if len(sys.argv) > 2 else 100_000)
    elif len(sys.argv) > 1 and sys.argv[1] == "--dask":
        dask(int(float(sys.argv[2])), int(sys.argv[3]) if len(sys.argv) > 3 else 2)
    else:
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 3)
