"""A drawn Linkage keeps to its circuit through every group, downstream ones too.

A group hung on moving links (the second dyad of a Watt II six-bar, a dyad on a
four-bar's coupler point) can close on several separate arcs of the crank angle.
Turning the crank from the drawing, the mechanism stops where that dyad reaches a
toggle; the other arcs, where the dyad closes again on its drawn assembly, are
its other circuit: reached only by taking the mechanism apart. The expected arcs
are found here without machdyn: the first loop's rocker angle from Freudenstein's
equation (Norton, *Design of Machinery*, §4.5, eq. 4.10), the second dyad's
two-circle condition ``|e − f| ≤ |C − O6| ≤ e + f`` (§4.5: a dyad of sides e, f
closes iff its pivots are no further apart than e + f nor closer than |e − f|),
and the edges of those arcs by Brent's method on that condition.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.optimize import brentq

import machdyn
from closed_forms import circle_meet
from machdyn.linkage import Linkage, circuit

# a Grashof crank-rocker: s + l = 1 + 4 < p + q = 3 + 4, the crank shortest
R1, R2, R3, R4 = 4.0, 1.0, 4.0, 3.0  # ground O2-O4, crank, coupler, rocker
O4 = R1 + 0j


def theta4(theta2):
    """Rocker angle of the open (B above O2-O4) crank-rocker (Freudenstein, Norton 4.10)."""
    t = np.asarray(theta2, float)
    K1, K2 = R1 / R2, R1 / R4
    K3 = (R2**2 - R3**2 + R4**2 + R1**2) / (2 * R2 * R4)
    A = np.cos(t) - K1 - K2 * np.cos(t) + K3
    B = -2 * np.sin(t)
    C = K1 - (K2 + 1) * np.cos(t) + K3
    return 2 * np.arctan2(-B - np.sqrt(B * B - 4 * A * C), 2 * A)


def four_bar_points(theta2):
    A = R2 * np.exp(1j * np.asarray(theta2, float))
    return A, O4 + R4 * np.exp(1j * theta4(theta2))


def arcs(dist, lo, hi):
    """Crank intervals (radians, in [0, 2π) unwrapped upwards) where lo ≤ dist(θ2) ≤ hi."""
    grid = np.linspace(0.0, 2 * np.pi, 4001)
    edges = []
    for bound in (lo, hi):
        g = dist(grid) - bound
        for k in np.flatnonzero(np.sign(g[:-1]) != np.sign(g[1:])):
            edges.append(brentq(lambda t, b=bound: float(dist(t) - b), grid[k], grid[k + 1],
                                xtol=1e-14))  # fmt: skip
    edges = np.sort(np.remainder(edges, 2 * np.pi))
    out = []
    for a, b in zip(edges, np.roll(edges, -1), strict=True):
        b = b if b > a else b + 2 * np.pi
        mid = 0.5 * (a + b)
        if lo <= dist(mid) <= hi:
            out.append((a, b))
    return out


def within(theta, arc):
    return np.remainder(np.asarray(theta) - arc[0], 2 * np.pi) <= arc[1] - arc[0]


def reported_span(reason):
    """The crank interval a reason names, in degrees."""
    found = re.search(r"reaches crank in \[(-?[\d.]+)°, (-?[\d.]+)°\] only", reason)
    assert found, reason
    return float(found[1]), float(found[2])


def assert_same_arc(reason, arc):
    lo, hi = reported_span(reason)
    assert hi - lo == pytest.approx(math.degrees(arc[1] - arc[0]), abs=0.01)
    assert (lo - math.degrees(arc[0]) + 180) % 360 - 180 == pytest.approx(0, abs=0.01)


def group_named(lk, *links):
    return next(g.name for g in lk.groups if set(g.links) == set(links))


def check_circuit(lk, dist, lo, hi, drawn, dyad, points):
    """The flags of ``lk`` against the arcs of ``lo ≤ dist ≤ hi`` (the second dyad's)."""
    parts = arcs(dist, lo, hi)
    assert len(parts) == 2, parts  # the test's premise: two separate arcs
    mine = next(p for p in parts if within(drawn, p))
    other = next(p for p in parts if p is not mine)
    eps = 1e-7
    inside = np.linspace(mine[0] + eps, mine[1] - eps, 9)
    away = np.linspace(other[0] + eps, other[1] - eps, 7)
    gap = np.array([mine[1] + 1e-3, other[1] + 1e-3, mine[0] - 1e-3, other[0] - 1e-3])
    th = np.concatenate([inside, away, gap])
    m = lk.solve(th, velocity=1.0)
    assert m.ok[:9].all() and not m.ok[9:].any()
    for r in m.reason[9:16]:  # the other arc: named, with the drawn arc
        assert r.startswith(f"{dyad} is on another circuit at this input"), r
        assert_same_arc(r, mine)
    assert all("does not close" in r for r in m.reason[16:])
    # single poses (the editor's path) and grids without continuation say the same
    one = lk.solve(float(away[3]))
    assert not bool(one.ok) and "another circuit" in str(one.reason)
    grid = lk.solve(th.reshape(4, -1), continuation=False)
    assert (grid.ok.ravel() == m.ok).all()
    # on the drawn arc, the points are the closed form's
    for name, z in points(inside).items():
        np.testing.assert_allclose(m.points[name][:9], z, atol=1e-9)
    assert np.isnan(m.points["D"][9:16]).all()
    return m, mine


# ---------------------------------------------------------------- (a) Watt II
BETA = math.radians(-35.0)  # C on the rocker: 35° clockwise of O4-B
RC = 3.0
O6 = 9.8 - 1.5j
E, F = 6.7, 0.4  # C-D and O6-D: the dyad closes for 6.3 ≤ |C − O6| ≤ 7.1


def watt_c(theta2):
    return O4 + RC * np.exp(1j * (theta4(theta2) + BETA))


def watt(theta_deg=120.0, side=1.0):
    t = math.radians(theta_deg)
    A, B = four_bar_points(t)
    C = complex(watt_c(t))
    D = circle_meet(C, E, O6, F, side)
    lk = Linkage({"O2": 0j, "O4": O4, "O6": O6, "A": complex(A), "B": complex(B), "C": C, "D": D})
    lk.ground("O2", "O4", "O6")
    lk.link("crank", "O2", "A").link("coupler", "A", "B").link("rocker", "O4", "B", "C")
    lk.link("link5", "C", "D").link("link6", "O6", "D")
    return lk.drive("crank")


def watt_points(theta2, side=1.0):
    A, B = four_bar_points(theta2)
    C = watt_c(theta2)
    return {"A": A, "B": B, "C": C, "D": circle_meet(C, E, O6, F, side)}


def watt_dist(t):
    return np.abs(watt_c(t) - O6)


@pytest.mark.parametrize("side", [1.0, -1.0])
@pytest.mark.parametrize("drawn", [120.0, 320.0])
def test_a_watt_ii_second_loop_keeps_to_the_drawn_arc_of_the_crank(drawn, side):
    lk = watt(drawn, side)
    dyad = group_named(lk, "link5", "link6")
    check_circuit(lk, watt_dist, E - F, E + F, math.radians(drawn), dyad,
                  lambda t: watt_points(t, side))  # fmt: skip


# ---------------------------------------------------- (b) a dyad on a coupler point
P_ON, GAMMA = 2.0, math.radians(40.0)  # coupler point: 2 from A, 40° off A-B
Q6 = 3.0 + 5.0j
E2, F2 = 4.1, 0.8  # P-D and Q6-D: closes for 3.3 ≤ |P − Q6| ≤ 4.9 (|P − Q6| spans 2.9-5.2)


def coupler_p(theta2):
    A, B = four_bar_points(theta2)
    return A + P_ON * (B - A) / R3 * np.exp(1j * GAMMA)


def hung(theta_deg):
    t = math.radians(theta_deg)
    A, B = four_bar_points(t)
    P = complex(coupler_p(t))
    D = circle_meet(P, E2, Q6, F2, 1.0)
    lk = Linkage({"O2": 0j, "O4": O4, "O6": Q6, "A": complex(A), "B": complex(B), "P": P, "D": D})
    lk.ground("O2", "O4", "O6")
    lk.link("crank", "O2", "A").link("coupler", "A", "B", "P").link("rocker", "O4", "B")
    lk.link("link5", "P", "D").link("link6", "O6", "D")
    return lk.drive("crank")


def hung_points(theta2):
    A, B = four_bar_points(theta2)
    P = coupler_p(theta2)
    return {"A": A, "B": B, "P": P, "D": circle_meet(P, E2, Q6, F2, 1.0)}


@pytest.mark.parametrize("drawn", [150.0, 340.0])
def test_a_dyad_on_a_coupler_point_keeps_to_the_drawn_arc_of_the_crank(drawn):
    lk = hung(drawn)
    dyad = group_named(lk, "link5", "link6")

    def dist(t):
        return np.abs(coupler_p(t) - Q6)

    assert 2.9 < dist(np.linspace(0, 2 * np.pi, 721)).min() < 3.3  # both bounds inside
    assert dist(np.linspace(0, 2 * np.pi, 721)).max() > 4.9
    check_circuit(lk, dist, E2 - F2, E2 + F2, math.radians(drawn), dyad, hung_points)


# ------------------------------------------------- (c) closing everywhere: unchanged
def test_a_linkage_closing_over_the_whole_turn_is_not_touched(monkeypatch):
    # the same Watt II with a long second dyad: |e − f| ≤ |C − O6| ≤ e + f at every crank angle
    t0 = math.radians(120.0)
    A, B = four_bar_points(t0)
    C = complex(watt_c(t0))
    D = circle_meet(C, 6.0, O6, 5.0, 1.0)
    pts = {"O2": 0j, "O4": O4, "O6": O6, "A": complex(A), "B": complex(B), "C": C, "D": D}
    assert watt_dist(np.linspace(0, 2 * np.pi, 721)).min() > 1.0
    assert watt_dist(np.linspace(0, 2 * np.pi, 721)).max() < 11.0

    def build():
        lk = Linkage(pts).ground("O2", "O4", "O6")
        lk.link("crank", "O2", "A").link("coupler", "A", "B").link("rocker", "O4", "B", "C")
        return lk.link("link5", "C", "D").link("link6", "O6", "D").drive("crank")

    th = t0 + np.linspace(0.0, 4 * np.pi, 721)
    m = build().solve(th, velocity=2.0, acceleration=-1.0)
    assert m.ok.all() and not any(m.reason)
    np.testing.assert_allclose(m.points["D"], circle_meet(watt_c(th), 6.0, O6, 5.0, 1.0),
                               atol=1e-9)  # fmt: skip
    monkeypatch.setattr(circuit, "_circuit", lambda *a: None)  # no check at all: the same bits
    bare = build().solve(th, velocity=2.0, acceleration=-1.0)
    for name in m.points:
        assert np.array_equal(m.points[name], bare.points[name])
        assert np.array_equal(m.point_acceleration[name], bare.point_acceleration[name])


def test_a_second_dyad_closing_on_one_arc_only_does_not_close_elsewhere():
    # e + f = 7.1 with |e − f| below every distance: one arc, no other circuit
    t0 = math.radians(120.0)
    A, B = four_bar_points(t0)
    C = complex(watt_c(t0))
    D = circle_meet(C, 3.8, O6, 3.3, 1.0)
    lk = Linkage({"O2": 0j, "O4": O4, "O6": O6, "A": complex(A), "B": complex(B), "C": C, "D": D})
    lk.ground("O2", "O4", "O6")
    lk.link("crank", "O2", "A").link("coupler", "A", "B").link("rocker", "O4", "B", "C")
    lk.link("link5", "C", "D").link("link6", "O6", "D").drive("crank")
    th = np.linspace(0, 2 * np.pi, 361)
    m = lk.solve(th)
    closes = watt_dist(th) <= 7.1
    assert 0 < closes.sum() < th.size
    near = np.abs(watt_dist(th) - 7.1) < 1e-6
    assert (m.ok == closes)[~near].all()
    assert not any("another circuit" in r for r in m.reason)


# ------------------------------------------------- (d) what reads ok/reason sees it
def test_studio_sensitivity_and_tolerance_see_the_downstream_flag():
    from machdyn.errors import InputError
    from machdyn.studio.analysis import analyse

    lk = watt(120.0)
    mine, other = sorted(arcs(watt_dist, E - F, E + F), key=lambda p: not within(2.1, p))
    th = np.array([2.1, 2.3, 0.5 * (other[0] + other[1])])
    s = machdyn.sensitivity(lk, th)
    assert s.ok.tolist() == [True, True, False]
    with pytest.raises(InputError) as info:
        machdyn.tolerance(lk, {"C-D": 0.01}, th, samples=50)
    assert info.value.field == "theta2" and "another circuit" in str(info.value)
    # the studio's page of the same drawing
    doc = {
        "machdyn": 1,
        "units": {"length": "m", "angle": "deg"},
        "linkage": {
            "watt": {
                "points": {k: [v.real, v.imag] for k, v in lk.points.items()},
                "ground": ["O2", "O4", "O6"],
                "drive": ["crank"],
                "links": {n: {"points": list(ln.points)} for n, ln in lk.links.items()},
            }
        },
    }
    out = analyse(doc, samples=360)
    x = np.radians(np.asarray(out["x"], float))
    ok = np.asarray(out["ok"])
    far = within(x, (other[0] + 0.01, other[1] - 0.01))
    assert far.any() and not ok[far].any()
    assert ok[within(x, (mine[0] + 0.01, mine[1] - 0.01))].all()


# several drivers: tests/test_linkage_circuit_drivers.py
