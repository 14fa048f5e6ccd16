"""Several drivers: a path that leaves where a dyad closes for less than a scan step.

A five-bar (cranks O1-A and O2-B, driven both; links A-C and B-C) closes while
``D = |A − B| ≤ e + f``. Its pivot distance is largest, ``D = r1 + d + r2``, at
``θ1 = 180°, θ2 = 0°``; with ``e + f`` a little less, the drivers' straight path
through that pose leaves where the dyad closes for a stretch narrower than the
scan's step (``paths.H``, half a degree): found by the dyad's margin between
scanned points. The reference is written here: ``D`` along the path, its crossing
of ``e + f`` by Brent's method (two-circle condition, Norton, *Design of
Machinery*, §4.5).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.optimize import brentq

from closed_forms import circle_meet
from machdyn.linkage import Linkage, paths

D12, R1, R2 = 3.0, 1.0, 1.2
START = np.array([math.pi - 0.5, 0.5])  # the drawing's crank angles
END = np.array([math.pi + 0.5, -0.5])  # a sample: the straight path passes (180°, 0°)
SPAN = 1.0  # the path's largest change of a driver (rad)


def dist(s):
    """|A − B| at the fraction ``s`` of the straight path START → END."""
    u = START[:, None] + np.atleast_1d(s) * (END - START)[:, None]
    return np.abs(R1 * np.exp(1j * u[0]) - (D12 + R2 * np.exp(1j * u[1])))


def five_bar(width):
    """The five-bar whose dyad stops closing for ``width`` (rad of the drivers) on the path."""
    w = width / SPAN  # in fractions of the path
    curve = (dist(0.5 + 1e-4) + dist(0.5 - 1e-4) - 2 * dist(0.5))[0] / 1e-8  # D'' there
    reach = (R1 + D12 + R2) + curve / 2 * (w / 2) ** 2  # e + f: D exceeds it over w
    e, f = 0.55 * reach, 0.45 * reach
    A, B = R1 * np.exp(1j * START[0]), D12 + R2 * np.exp(1j * START[1])
    C = circle_meet(A, e, B, f, 1.0)
    lk = Linkage({"O1": 0j, "O2": D12 + 0j, "A": A, "B": B, "C": C}).ground("O1", "O2")
    lk.link("c1", "O1", "A").link("c2", "O2", "B").link("l3", "A", "C").link("l4", "B", "C")
    return lk.drive("c1", "c2"), e + f


def leaves(reason):
    found = re.search(r"closes at c1 = (-?[\d.]+)°, c2 = (-?[\d.]+)°", reason)
    assert found, reason
    return float(found[1]), float(found[2])


@pytest.mark.usefixtures("backend")  # NumPy, then the compiled kernel
@pytest.mark.parametrize("steps", [0.3, 0.05])
def test_a_stretch_out_narrower_than_a_step_is_found(steps):
    lk, reach = five_bar(steps * paths.H)
    s_out = brentq(lambda s: dist(s)[0] - reach, 0.25, 0.5, xtol=1e-14)  # where it leaves
    assert 0 < 0.5 - s_out < 0.5 * paths.H  # the premise: narrower than a step
    m = lk.solve({"c1": END[0], "c2": END[1]})  # a pose solved alone: the straight path
    assert not bool(m.ok)
    reason = str(m.reason)
    assert reason.startswith("the drivers' straight path from the drawing to this input "
                             "leaves where RRR dyad (l3, l4) closes")  # fmt: skip
    u = np.degrees(START + s_out * (END - START))  # (printed to 5 significant digits)
    c1, c2 = leaves(reason)
    assert c1 == pytest.approx(u[0], abs=6e-3) and c2 == pytest.approx(u[1], rel=1e-4)
    # a pose short of it is reached
    near = START + 0.45 * (END - START)
    assert bool(lk.solve({"c1": near[0], "c2": near[1]}).ok)


def test_a_sweep_along_the_path_stops_at_the_narrow_stretch():
    lk, reach = five_bar(0.3 * paths.H)
    s = np.linspace(0.0, 1.0, 801)
    u = START[:, None] + s * (END - START)[:, None]
    m = lk.solve({"c1": u[0], "c2": u[1]})
    closes = dist(s) <= reach
    first_gap = int(np.argmax(~closes))
    assert closes[:first_gap].all() and m.ok[:first_gap].all()
    assert not m.ok[first_gap:].any()  # in the stretch (does not close) and past it


@pytest.mark.usefixtures("backend")  # NumPy, then the compiled kernel
@pytest.mark.parametrize("count", [200, 2000])
def test_a_sweep_of_small_steps_stops_at_a_narrow_stretch_between_its_samples(count):
    # samples 0.29° and 0.029° apart (less than a scan step), none in the stretch out
    lk, reach = five_bar(0.05 * paths.H)
    s = (np.arange(count) + 0.5) / count
    assert np.max(np.abs(np.diff(s))) * SPAN < paths.H
    assert (dist(s) <= reach).all()  # the premise: every sample closes
    s_out = brentq(lambda x: dist(x)[0] - reach, 0.25, 0.5, xtol=1e-14)
    u = START[:, None] + s * (END - START)[:, None]
    m = lk.solve({"c1": u[0], "c2": u[1]})
    # past the stretch, the straight path from the drawing crosses it too
    assert (m.ok == (s < s_out)).all()
    first = int(np.argmax(s > s_out))
    sweep = f"path along the sweep (before sample {first}) leaves where RRR dyad (l3, l4)"
    assert sweep in m.reason[first], m.reason[first]


def test_a_path_that_stays_inside_is_not_flagged():
    # the same five-bar, the path shifted so that D stays below e + f all along it
    lk, reach = five_bar(0.3 * paths.H)
    end = END + np.array([0.0, 0.02])
    s = np.linspace(0.0, 1.0, 20001)
    u = START[:, None] + s * (end - START)[:, None]
    D = np.abs(R1 * np.exp(1j * u[0]) - (D12 + R2 * np.exp(1j * u[1])))
    assert D.max() < reach  # the premise, written here
    assert bool(lk.solve({"c1": end[0], "c2": end[1]}).ok)


def parallelogram_and_arm():
    """A parallelogram four-bar O2-A-B-O4 (2, 5, 2, 5) driven at its crank, and a second
    driven link elsewhere: two drivers. Its pivots are in line at crank 0° and 180°:
    change points, where its two forms (parallelogram, antiparallelogram) cross."""
    A = 2 * np.exp(1j * math.radians(60.0))
    pts = {"O2": 0j, "O4": 5 + 0j, "A": A, "B": A + 5, "O5": 10 + 0j, "E": 11 + 0j}
    lk = Linkage(pts).ground("O2", "O4", "O5").link("c1", "O2", "A").link("cp", "A", "B")
    return lk.link("r", "O4", "B").link("arm", "O5", "E").drive("c1", "arm")


@pytest.mark.parametrize("follow", [True, False])
def test_a_change_point_on_the_path_of_several_drivers_is_flagged_not_crossed(follow):
    lk = parallelogram_and_arm()
    th = np.radians(np.linspace(60.0, 400.0, 341))
    m = lk.solve({"c1": th, "arm": 0.5 * th}, continuation=follow)
    # ok: the drawn form, the coupler parallel to the ground (θ_cp = 0: written here)
    assert m.ok.sum() > 100 and np.allclose(m.theta["cp"][m.ok], 0.0, atol=1e-9)
    # every sample whose straight path from the drawing (angles within 180° of it) passes
    # crank 0° or 180° is flagged, naming the change point; a sweep reaches no more (past
    # 180° it has passed one; from 361° on it is reached straight from the drawing again)
    straight = np.remainder(th - math.radians(60.0) + np.pi, 2 * np.pi) - np.pi
    crosses = (straight > math.radians(120.0)) | (straight < math.radians(-60.0))
    at = np.isclose(th, np.pi) | np.isclose(th, 2 * np.pi)  # at a change point: a toggle
    assert (m.ok == ~(crosses | at)).all()
    for r in m.reason[crosses & ~at]:
        assert "passes a change point of RRR dyad (cp, r)" in r, r
        assert r.endswith("cannot reach this input along " + ("them" if follow else "it")
                          + " on its drawn form")  # fmt: skip
    assert np.isnan(m.theta["cp"][crosses]).all()


def parallelogram_change_points():
    """The crank angles (rad, [0, 2π)) of the change points of ``parallelogram_and_arm``,
    written here: the crank O2-A (2) lies along the ground line O2-O4 (5) where
    ``sin θ = 0``; there ``D = |A − O4|`` is 7 = e + f or 3 = |e − f| (the coupler 5 and the
    rocker 2 in line: the two circles touch)."""
    theta = np.array([0.0, math.pi])
    D = np.abs(2 * np.exp(1j * theta) - 5)
    assert np.allclose(D, [5 - 2, 5 + 2])  # |e − f|, e + f of the dyad (cp, r)
    return theta


def reached_without_a_change_point(th, start, follow, cps=None):
    """Per sample of a sweep ``th`` of the crank: reached from the drawn crank angle
    ``start`` without passing a change point (``cps``, the parallelogram's by default;
    one at the sample itself counts: a toggle), straight from the drawing (the angle
    within 180° of it) or, along the sweep (``follow``), from the sample before if that
    one was reached."""
    cps = parallelogram_change_points() if cps is None else cps

    def passes(a, b):  # a change point in [a, b] (either way, angles unwrapped)
        lo, hi = min(a, b) - 1e-9, max(a, b) + 1e-9
        return any(math.floor((hi - c) / (2 * math.pi)) >= math.ceil((lo - c) / (2 * math.pi))
                   for c in cps)  # fmt: skip

    out = []
    for k, t in enumerate(th):
        straight = start + (t - start + math.pi) % (2 * math.pi) - math.pi
        ok = not passes(start, straight)
        if follow and k and out[-1]:
            ok = ok or not passes(th[k - 1], t)
        out.append(ok)
    return np.array(out)


@pytest.mark.parametrize("step", [0.1, 0.4, 1.0])
def test_a_sweep_of_small_steps_is_watched_between_its_samples(step):
    # the review of 2026-11-25: at 0.4° steps (less than a scan step, paths.H = 0.5°)
    # 449 samples past the change point were shown ok on the crossed form
    assert math.degrees(paths.H) == 0.5
    lk = parallelogram_and_arm()
    th = np.radians(np.arange(60.0, 400.0 + step / 2, step))
    m = lk.solve({"c1": th, "arm": 0.5 * th})
    expected = reached_without_a_change_point(th, math.radians(60.0), True)
    assert expected.sum() > 100 and (~expected).sum() > 100  # the premise: both kinds
    assert (m.ok == expected).all(), np.flatnonzero(m.ok != expected)
    # ok: the drawn form, the coupler parallel to the ground (θ_cp = 0: written here)
    assert np.allclose(m.theta["cp"][m.ok], 0.0, atol=1e-9)
    assert np.isnan(m.theta["cp"][~m.ok]).all()
    at = np.abs(np.sin(th)) < 1e-9  # at a change point: a toggle
    for r in m.reason[~expected & ~at]:
        assert "passes a change point of RRR dyad (cp, r)" in r, r
