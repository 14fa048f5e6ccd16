"""Benchmark of the studio, measured in Chromium: drag latency and start-up.

Run: ``python benchmarks/bench_studio.py [STEPS]`` (default 120 drag steps per case).

* **start-up**: ``machdyn studio --no-browser`` in a fresh process, from spawn to the
  address printed (listening), and to the first analysed page in the browser;
* **drag latency**: a joint of the Watt II six-bar template (masses, gravity, a load
  torque: forces over 360 poses) dragged with the mouse in Chromium, one step at a
  time; per step, from the pointer move to the redrawn mechanism, coupler curve and
  plots (the page's own clock: the move that made the request → the end of the
  drawing of its answer), median and 95th percentile; the same for a 10-link linkage
  (four RRR dyads on a crank);
* **peer**, interleaved with the drags: the bare Python API on the same document
  (``Linkage.solve`` + ``Linkage.forces`` of 360 poses), so the ratio says what the
  studio adds around the library (reading, tables, scene, JSON, HTTP, drawing).

The machine is shared: the load average is printed with the numbers, and the
server's CPU time per step (its ``Server-Timing``, the worker thread's CPU clock)
beside the bare API's, which a busy machine does not inflate as it does wall time.
"""

from __future__ import annotations

import cmath
import os
import platform
import statistics
import subprocess
import sys
import time

import numpy as np

CHROMIUM = "/usr/bin/chromium"


def ten_links() -> dict:
    """A crank and four RRR dyads hung one on another (10 links with the ground)."""
    from machdyn.linkage.dyads import rrr

    def meet(A, C, a, b, s=1):
        return complex(rrr(A, C, a, b, s).B)

    O = [0j, 80 + 0j, 130 + 60j, 190 + 0j, 240 + 70j]  # noqa: E741 - the ground pivots
    A = 20 * cmath.exp(1j * cmath.pi / 6)
    B = meet(A, O[1], 70, 60)
    C = O[1] + 40 * (B - O[1]) / abs(B - O[1]) * cmath.exp(-0.6j)
    D = meet(C, O[2], 60, 50, -1)
    E = O[2] + 35 * (D - O[2]) / abs(D - O[2]) * cmath.exp(0.5j)
    F = meet(E, O[3], 60, 55, 1)
    G = O[3] + 40 * (F - O[3]) / abs(F - O[3]) * cmath.exp(-0.5j)
    H = meet(G, O[4], 60, 55, -1)
    names = {"O2": O[0], "O4": O[1], "O6": O[2], "O8": O[3], "O10": O[4], "A": A, "B": B,
             "C": C, "D": D, "E": E, "F": F, "G": G, "H": H}  # fmt: skip

    def bar(points, m):
        return {"points": points, "mass": m, "inertia": 50.0 * m, "cg": 20.0}

    return {
        "machdyn": 1,
        "title": "ten links",
        "gravity": True,
        "units": {"length": "mm", "mass": "kg", "force": "N", "torque": "N*m"},
        "linkage": {
            "ten": {
                "points": {k: [v.real, v.imag] for k, v in names.items()},
                "ground": ["O2", "O4", "O6", "O8", "O10"],
                "drive": ["crank"],
                "report": ["H"],
                "links": {
                    "crank": bar(["O2", "A"], 0.2),
                    "c1": bar(["A", "B"], 0.3),
                    "r1": bar(["O4", "B", "C"], 0.4),
                    "c2": bar(["C", "D"], 0.3),
                    "r2": bar(["O6", "D", "E"], 0.4),
                    "c3": bar(["E", "F"], 0.3),
                    "r3": bar(["O8", "F", "G"], 0.4),
                    "c4": bar(["G", "H"], 0.3),
                    "r4": bar(["O10", "H"], 0.3),
                },
                "motion": {"crank": {"velocity": "10 rad/s"}},
            }
        },
    }


def start_server() -> tuple[subprocess.Popen, str, float]:
    t0 = time.perf_counter()
    proc = subprocess.Popen(
        [sys.executable, "-c", "from machdyn.cli import main; main()", "studio", "--no-browser"],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    line = proc.stdout.readline()
    listening = time.perf_counter() - t0
    return proc, line.split()[2], listening


def analysed(page) -> int:
    return int(page.evaluate("() => Number(document.body.dataset.analysed || 0)"))


def wait(page, count: int) -> None:
    while analysed(page) < count:
        page.wait_for_timeout(2)


def peer(doc: dict) -> tuple[float, float]:
    """Seconds (wall, CPU) of the bare Python API on the document: 360 poses, kinematics
    and forces."""
    import machdyn

    machine = machdyn.spec.read(doc)
    lk = next(iter(machine.parts.values())).model
    theta = lk.drawn_inputs["crank"] + np.linspace(0, 2 * np.pi, 360, endpoint=False)
    t0, c0 = time.perf_counter(), time.thread_time()
    m = lk.solve(theta, velocity=10.0, acceleration=0.0)
    lk.forces(m, gravity=machine.gravity or 0.0)
    return time.perf_counter() - t0, time.thread_time() - c0


def drag(page, doc: dict, point: str, steps: int) -> tuple[list[float], list[float]]:
    """Latencies (ms) of ``steps`` single drag steps of ``point``, and peer times (ms)."""
    before = analysed(page)
    page.evaluate("(d) => { window.studio.store.load(d, true); window.studio.afterLoad(); }", doc)
    wait(page, before + 1)
    page.click("button[data-tab=plots]")
    page.wait_for_timeout(300)
    box = page.locator("#canvas").bounding_box()
    x, y = doc["linkage"][next(iter(doc["linkage"]))]["points"][point]
    sx, sy = page.evaluate(f"() => [window.studio.view.sx({x}), window.studio.view.sy({y})]")
    px, py = box["x"] + sx, box["y"] + sy
    page.mouse.move(px, py)
    page.mouse.down()
    latencies, peers, parts = [], [], []
    for k in range(steps):
        n = analysed(page)
        angle = 2 * np.pi * k / steps
        page.mouse.move(px + 6 * np.cos(angle), py + 6 * np.sin(angle))
        wait(page, n + 1)
        t = page.evaluate("() => window.studio.timing")
        latencies.append(float(t["total"]))
        parts.append((t["server"] or 0.0, t["cpu"] or 0.0, t["trip"], t["draw"]))
        if k % 4 == 0:
            peers.append(peer(page.evaluate("() => window.studio.store.doc")))
    page.mouse.up()
    server, cpu, trip, draw = (statistics.median(p[k] for p in parts) for k in range(4))
    peer_cpu = 1000 * statistics.median(c for _, c in peers)
    print(
        f"  {point} of {doc['title']}: median server {server:.1f} ms wall / {cpu:.1f} ms CPU "
        f"(the bare API: {peer_cpu:.1f} ms CPU), rest of the round trip {trip:.1f} ms, "
        f"drawing {draw:.1f} ms",
        flush=True,
    )
    return latencies, [1000 * w for w, _ in peers]


def summary(name: str, ms: list[float], peers: list[float]) -> str:
    ms_sorted = sorted(ms)
    p95 = ms_sorted[min(len(ms) - 1, int(0.95 * len(ms)))]
    med, peer_med = statistics.median(ms), statistics.median(peers)
    return (
        f"{name:<44} {len(ms):>5} {med:>9.1f} {p95:>9.1f} {peer_med:>9.1f} {med / peer_med:>7.1f}"
    )


def main() -> None:
    from playwright.sync_api import sync_playwright

    from machdyn.studio.templates import template

    steps = int(sys.argv[1]) if len(sys.argv) > 1 else 120
    load0 = os.getloadavg()
    proc, url, listening = start_server()
    try:
        with sync_playwright() as pw:
            browser = pw.chromium.launch(
                executable_path=CHROMIUM, args=["--no-sandbox", "--disable-gpu"]
            )
            page = browser.new_page(viewport={"width": 1400, "height": 860})
            t0 = time.perf_counter()
            page.goto(url)
            wait(page, 1)
            first_page = time.perf_counter() - t0
            watt = drag(page, template("watt"), "C", steps)
            ten = drag(page, ten_links(), "E", steps)
            rows = [
                summary("Watt II six-bar + forces, 360 poses", *watt),
                summary("10-link linkage + forces, 360 poses", *ten),
            ]
            browser.close()
    finally:
        proc.terminate()
        proc.wait(10)
    load1 = os.getloadavg()
    print(f"machdyn studio benchmark · Python {platform.python_version()} · {platform.machine()}")
    print(f"load average before {load0[0]:.1f}, after {load1[0]:.1f} (1 min)")
    print(f"start-up: listening after {listening:.2f} s; first analysed page {first_page:.2f} s")
    head = f"{'drag step (pointer move -> redrawn)':<44} {'steps':>5} {'median':>9} {'p95':>9}"
    print(f"{head} {'peer':>9} {'ratio':>7}")
    print(f"{'':<44} {'':>5} {'[ms]':>9} {'[ms]':>9} {'[ms]':>9} {'':>7}")
    for row in rows:
        print(row)


if __name__ == "__main__":
    main()
