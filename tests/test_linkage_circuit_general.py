"""A group solved by the vector-loop core keeps to the drawn circuit too.

A pin sliding in a circular slot about O4 (``slider(..., centre="O4")``) is Norton's
effective link O4–B: the linkage is a four-bar, but the group (coupler, block) is not
a closed-form dyad, so the vector-loop core solves it, keeping the drawn branch (the
sign of its determinant) through assembly gaps. With the coupler shortest (60, 90,
30, 80: a Grashof double rocker driven at a rocker) the group closes on two mirror
arcs of the driven angle; the drawn mechanism reaches only the one it is drawn on.
The reference is written here: the dyad closes iff ``|r4 − r3| ≤ |A − O4| ≤ r3 + r4``
(two-circle condition, Norton, *Design of Machinery*, §4.5), the arcs' edges by
Brent's method on it, B by circle intersection on the drawn side.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.optimize import brentq

from closed_forms import circle_meet
from machdyn.linkage import Linkage

R1, R2, R3, R4 = 60.0, 90.0, 30.0, 80.0
O4 = R1 + 0j


def dist(t):
    return np.abs(R2 * np.exp(1j * np.asarray(t, float)) - O4)


def arcs():
    """The two arcs (radians) where 50 ≤ |A − O4| ≤ 110: [lo, hi] and its mirror."""
    lo = brentq(lambda t: dist(t) - (R4 - R3), 0.0, np.pi, xtol=1e-14)
    hi = brentq(lambda t: dist(t) - (R3 + R4), 0.0, np.pi, xtol=1e-14)
    return (lo, hi), (-hi, -lo)


def curved(theta_deg, side=1.0):
    t = math.radians(theta_deg)
    A = R2 * np.exp(1j * t)
    B = circle_meet(A, R3, O4, R4, side)
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "B": complex(B)}).ground("O2", "O4")
    lk.link("crank", "O2", "A").link("coupler", "A", "B").link("block", "B")
    return lk.slider("block", "ground", "B", centre="O4", name="arc").drive("crank")


def inside(t, arc, eps=1e-3):
    return np.remainder(t - arc[0] - eps, 2 * np.pi) <= arc[1] - arc[0] - 2 * eps


@pytest.mark.parametrize(("drawn", "side"), [(60.0, 1.0), (60.0, -1.0), (300.0, 1.0)])
@pytest.mark.parametrize("follow", [True, False])
def test_a_curved_slot_keeps_to_the_drawn_arc(drawn, side, follow):
    lk = curved(drawn, side)
    assert [g.kind for g in lk.groups] == ["driver", "general"]
    first, mirror = arcs()
    mine, other = (first, mirror) if inside(math.radians(drawn), first) else (mirror, first)
    th = np.radians(np.arange(0.0, 360.0, 2.5))
    m = lk.solve(th, velocity=1.0, continuation=follow)
    on_mine, on_other = inside(th, mine), inside(th, other)
    assert on_mine.sum() > 10 and on_other.sum() > 10
    assert m.ok[on_mine].all() and not m.ok[on_other].any()
    gap = ~inside(th, mine, -1e-3) & ~inside(th, other, -1e-3)
    assert not m.ok[gap].any()
    for r in m.reason[on_other]:
        if not follow and r.startswith("cannot assemble: Newton-Raphson did not converge"):
            continue  # solved alone from the drawn pose, the core may not reach it at all
        assert r.startswith("group (coupler, block) is on another circuit"), r
        found = re.search(r"reaches crank in \[(-?[\d.]+)°, (-?[\d.]+)°\] only", r)
        lo, hi = float(found[1]), float(found[2])
        assert hi - lo == pytest.approx(math.degrees(mine[1] - mine[0]), abs=0.01)
        assert (lo - math.degrees(mine[0]) + 180) % 360 - 180 == pytest.approx(0, abs=0.01)
    assert np.isnan(m.points["B"][on_other]).all()
    B = circle_meet(R2 * np.exp(1j * th[on_mine]), R3, O4, R4, side)
    np.testing.assert_allclose(m.points["B"][on_mine], B, atol=1e-8)


def test_a_curved_slot_closing_everywhere_is_not_touched():
    # a crank-rocker (4, 1, 4, 3; the crank shortest) with its rocker a curved slot
    t0 = math.radians(120.0)
    A = np.exp(1j * t0)
    B = circle_meet(A, 4.0, 4.0 + 0j, 3.0, 1.0)
    lk = Linkage({"O2": 0j, "O4": 4.0 + 0j, "A": A, "B": complex(B)}).ground("O2", "O4")
    lk.link("crank", "O2", "A").link("coupler", "A", "B").link("block", "B")
    lk.slider("block", "ground", "B", centre="O4", name="arc").drive("crank")
    th = t0 + np.linspace(0.0, 4 * np.pi, 241)
    m = lk.solve(th, velocity=1.0)
    assert m.ok.all() and not any(m.reason)
    B = circle_meet(np.exp(1j * th), 4.0, 4.0 + 0j, 3.0, 1.0)
    np.testing.assert_allclose(m.points["B"], B, atol=1e-8)
