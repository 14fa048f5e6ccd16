"""Timings and sizes of the design report and the browser animation (issue #12 targets).

Run: ``python benchmarks/bench_report.py``. Prints, best of N runs:

* the report of a Watt six-bar with masses, gravity and a flywheel, 360 poses,
  each run in a *cold* process (``python -c`` importing machdyn and writing the
  page), target ≤ 2 s; beside it, as a peer measured interleaved in the same
  run, a cold process that only imports machdyn and solves the same 360 poses
  with forces (so the ratio shows what the report itself adds on this machine);
* the size of a 120-frame HTML animation of a 10-link linkage, target ≤ 300 kB.
"""

from __future__ import annotations

import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent

WATT = """
import numpy as np
from machdyn.linkage import Linkage

def meet(p, r1, q, r2, side=1.0):
    d = abs(q - p); a = (r1**2 - r2**2 + d**2) / (2 * d); h = np.sqrt(r1**2 - a**2)
    u = (q - p) / d
    return p + a * u + side * h * 1j * u

O4, O6 = 8.0 + 0j, 12.0 + 6.0j
A = 2.0 * np.exp(1j * np.pi / 6)
B = meet(A, 7.0, O4, 6.0)
C = O4 + 4.0 * (B - O4) / abs(B - O4) * np.exp(1j * np.radians(-35))
D = meet(C, 6.0, O6, 5.0, -1.0)
lk = Linkage({"O2": 0j, "O4": O4, "O6": O6, "A": A, "B": B, "C": C, "D": D, "E": C + 2 + 1j})
lk.ground("O2", "O4", "O6")
lk.link("2", "O2", "A", mass=1.0, inertia=0.4, cg=1.0 + 0.1j)
lk.link("3", "A", "B", mass=2.0, inertia=8.0, cg=3.5 + 0.3j)
lk.link("4", "O4", "B", "C", mass=3.0, inertia=6.0, cg=2 + 0.5j)
lk.link("5", "C", "D", "E", mass=1.5, inertia=4.5, cg="E")
lk.link("6", "O6", "D", mass=2.5, inertia=5.0, cg=2.5 - 0.2j)
lk.drive("2")
"""

REPORT = (
    WATT
    + """
from machdyn.report import report
report(lk, OUT, velocity=10.0, n=360, gravity=9.81, k=0.05)
"""
)

PEER = (
    WATT
    + """
x = np.radians(30.0) + np.linspace(0, 2 * np.pi, 360, endpoint=False)
lk.forces(lk.solve(x, velocity=10.0), gravity=9.81)
"""
)


def cold(code: str) -> tuple[float, float]:
    """Wall time and CPU time (user + system) of a fresh Python process running ``code``.

    On a shared machine the wall time includes waiting for a core; the CPU time
    is what the process itself needed.
    """
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def ten_links():
    """A crank-rocker driving a chain of four dyads (10 moving links, 5 ground pivots)."""
    from machdyn.linkage import Linkage

    pts = {"O2": 0j, "O4": 8 + 0j, "A": 2j, "B": 5.5 + 5.2j}
    lk = Linkage(pts).ground("O2", "O4").link("L1", "O2", "A").link("L2", "A", "B")
    previous, out = "B", "L3"
    lk.point("P3", 9 + 3j).link(out, "O4", "B", "P3")
    for k in range(4):
        base = 12 + 7 * k
        ground, joint, tip = f"G{k}", f"J{k}", f"T{k}"
        lk.point(ground, complex(base + 4, 0)).point(joint, complex(base + 2, 6))
        lk.point(tip, complex(base + 5, 3))
        lk.ground(ground)
        source = "P3" if k == 0 else f"T{k - 1}"
        lk.link(f"C{k}", source, joint).link(f"R{k}", ground, joint, tip)
        previous = joint
    del previous
    return lk.drive("L1")


def main() -> None:
    from machdyn.draw import to_html

    out = Path(tempfile.mkdtemp()) / "watt.html"
    report_code = REPORT.replace("OUT", repr(str(out)))
    cold("import machdyn")  # warm the disk cache, not the process
    reports, peers = [], []
    for _ in range(5):  # interleaved: the machine's load hits both alike
        reports.append(cold(report_code))
        peers.append(cold(PEER))
    r, p = min(reports), min(peers)
    rc, pc = min(c for _, c in reports), min(c for _, c in peers)
    r, p = min(w for w, _ in reports), min(w for w, _ in peers)
    print(
        f"Watt six-bar report, 360 poses, forces + flywheel, cold process: wall {r:.2f} s, "
        f"CPU {rc:.2f} s (target 2 s)"
    )
    print(
        f"  peer (import + solve + forces only): wall {p:.2f} s, CPU {pc:.2f} s; "
        f"ratio report/peer: wall {r / p:.2f}, CPU {rc / pc:.2f}"
    )
    print(f"  page size {out.stat().st_size / 1e3:.0f} kB")
    lk = ten_links()
    page = to_html(lk, n=120)
    frames = page.count('"frames":120')
    print(
        f"10-link linkage ({len(lk.links)} moving links), 120-frame HTML animation: "
        f"{len(page.encode()) / 1e3:.0f} kB (target 300 kB); frames embedded: {frames == 1}"
    )
    np.seterr(all="ignore")


if __name__ == "__main__":
    main()
