"""Benchmarks of machines in time and tolerance (issue 15), best of N, interleaved.

Run:  python benchmarks/bench_simulate.py [repeats]

Targets: a four-bar start-up to steady state over 20 turns ≤ 0.5 s; the
sensitivities of all outputs to all dimensions of a six-bar over 360 poses ≤ 20 ms
(the closed-form road; the implicit road, which any linkage takes, beside it).

The peer of the tabulated simulation is the same integration solving the
linkage at every right-hand side (``table=False``, what a direct
``solve_ivp`` over the force analysis costs); it is timed over one turn and
reported per turn, with the ratio. The peer of the sensitivities is central
differences: the six-bar re-solved with each drawn coordinate moved up and down.
"""

from __future__ import annotations

import platform
import sys
import time

import numpy as np
import scipy

import machdyn
import machdyn.jit
from machdyn.simulate import DCMotor

FB = machdyn.FourBar(0.08, 0.04, 0.07, 0.06)
MASSES = dict(mass=(0.2, 0.3, 0.25), inertia=(3e-5, 1.2e-4, 7.5e-5), cg=(0.02, 0.035, 0.03))
MOTOR = DCMotor(stall_torque=0.05, no_load_speed=300.0, ratio=10.0, inertia=2e-5)


def start_up(turns: float, table: bool = True):
    return machdyn.simulate(
        FB, MOTOR, flywheel=2e-3, turns=turns, gravity=9.81, table=table, samples=101, **MASSES
    )


WATT = {"O2": 0j, "O4": 6 + 0j, "O6": 10 + 3j, "A": 1.5 + 0j, "B": 4.75 + 3.7997j,
        "C": 9.3316 + 1.3641j, "D": 7.5444 + 5.494j, "P": 3.125 + 2.8998j}  # fmt: skip
POSES = np.radians(np.arange(0.0, 360.0, 1.0))


def watt(points):
    from machdyn.linkage import Linkage

    return (
        Linkage(points).ground("O2", "O4", "O6").link("crank", "O2", "A")
        .link("coupler", "A", "B", "P").link("rocker", "O4", "B", "C")
        .link("coupler2", "C", "D").link("output", "O6", "D").drive("crank")
    )  # fmt: skip


def central_differences(h: float = 1e-6) -> None:
    for name, z in WATT.items():
        for step in (h, 1j * h):
            for sign in (1.0, -1.0):
                watt({**WATT, name: z + sign * step}).solve(POSES, velocity=1.0, acceleration=0.0)


def timed(fn) -> tuple[float, float]:
    """Wall and CPU seconds (the machine is shared: CPU time is what this process used)."""
    t0, c0 = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - t0, time.process_time() - c0


def main(repeat: int = 5) -> None:
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}",
        flush=True,
    )
    machdyn.jit.load()  # the compiled kernels (numba's cache), before anything is timed
    start_up(1.0)  # imports, caches
    rows: dict[str, list[tuple[float, float]]] = {"table": [], "exact": []}
    for _ in range(repeat):  # interleaved: the machine's load hits both alike
        rows["table"].append(timed(lambda: start_up(20.0)))
        rows["exact"].append(timed(lambda: start_up(1.0, table=False)))
    six = watt(WATT)
    from machdyn._linkage_sensitivity import implicit_sensitivity

    sens, fd, imp = [], [], []
    for _ in range(3 * repeat):
        sens.append(timed(lambda: machdyn.sensitivity(six, POSES, omega2=1.0)))
        fd.append(timed(central_differences))
        imp.append(timed(lambda: implicit_sensitivity(six, POSES, 1.0, 0.0)))
    s = machdyn.sensitivity(six, POSES, omega2=1.0)
    sw, fw = min(w for w, _ in sens), min(w for w, _ in fd)
    sc, fc = min(c for _, c in sens), min(c for _, c in fd)
    print(f"six-bar sensitivities, {len(s.derivative)} outputs x {len(s.dimensions)} dimensions x "
          f"360 poses: {sw * 1e3:.1f} ms wall, {sc * 1e3:.1f} ms CPU (target 20 ms)")  # fmt: skip
    iw, ic = min(w for w, _ in imp), min(c for _, c in imp)
    print(f"  the implicit road (any linkage; this one goes through its closed-form dyads): "
          f"{iw * 1e3:.1f} ms wall, {ic * 1e3:.1f} ms CPU, ratio {ic / sc:.1f}x CPU")  # fmt: skip
    print(f"  central differences (re-solving 2 x {len(s.dimensions)} drawings): "
          f"{fw * 1e3:.1f} ms wall, {fc * 1e3:.1f} ms CPU, ratio {fw / sw:.1f}x")  # fmt: skip
    run = start_up(20.0)
    table, exact = min(w for w, _ in rows["table"]), min(w for w, _ in rows["exact"])
    table_cpu = min(c for _, c in rows["table"])
    print(f"four-bar start-up, 20 turns, tabulated: {table:.3f} s wall, {table_cpu:.3f} s CPU "
          f"(target 0.5 s)")  # fmt: skip
    print(f"  {run.table}; steady k = {run.steady.k:.4f} after {len(run.cycles)} turns")
    print(f"the same solving the linkage at every step: {exact:.3f} s per turn")
    print(f"  ratio per turn (exact / tabulated): {exact / (table / 20.0):.0f}x")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
