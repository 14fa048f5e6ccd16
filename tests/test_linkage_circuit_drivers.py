"""Several drivers: a sample is ok only if the drivers' path from the drawing reaches it.

With two drivers what the drawing reaches is a region of the drivers' values, so
whether a sample is reached depends on the path the drivers take (docs/linkage.md,
"Circuit selection"): a sweep's own path (drawing → first sample → each next one,
straight in the drivers' values, an angle within π of the drawn one on the first
stretch) or the straight path from the drawing to the sample; a sample neither
reaches is flagged, naming the group and where the path leaves it.

The reference here is written without machdyn: the five-bar's dyad A–C–D of sides
e, f closes iff ``|e − f| ≤ |A − D| ≤ e + f`` (the two-circle condition, Norton,
*Design of Machinery*, §4.5), checked at 2,000 points of every straight stretch;
where a stretch leaves is found by Brent's method on that condition, and the pose
of a reached sample is the circle intersection on the drawn side.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from closed_forms import circle_meet
from machdyn.linkage import Linkage

DENSE = 2000
TOL = 2e-3  # a path within this of the condition's edge is not compared (a graze)


class FiveBar:
    """Cranks O2–A (r2) and O5–D (r5), both driven; dyad A–C (e), D–C (f)."""

    def __init__(self, d0, r2, r5, e, f, t2, t5, side=1.0):
        self.O5, self.r2, self.r5, self.e, self.f = complex(d0), r2, r5, e, f
        self.start = np.array([t2, t5])
        A, D = self.A(t2), self.D(t5)
        assert self.margin(t2, t5) > 0.05, "draw it well inside"
        self.side = side
        C = circle_meet(A, e, D, f, side)
        pts = {"O2": 0j, "O5": self.O5, "A": A, "D": D, "C": C}
        self.lk = Linkage(pts).ground("O2", "O5")
        self.lk.link("2", "O2", "A").link("3", "A", "C").link("4", "D", "C")
        self.lk.link("5", "O5", "D").drive("2", "5")

    def A(self, t2):
        return self.r2 * np.exp(1j * np.asarray(t2, float))

    def D(self, t5):
        return self.O5 + self.r5 * np.exp(1j * np.asarray(t5, float))

    def margin(self, t2, t5):
        """> 0 where the dyad closes (distance to the nearer bound of the two-circle condition)."""
        g = np.abs(self.A(t2) - self.D(t5))
        return np.minimum(g - abs(self.e - self.f), self.e + self.f - g)

    def leaves_at(self, p0, p1):
        """Where p0 → p1 first leaves (Brent's method on the margin)."""
        s = np.linspace(0.0, 1.0, DENSE + 1)
        m = self.margin(*(p0[:, None] + s * (p1 - p0)[:, None]))
        k = int(np.argmax(m < 0))
        assert k > 0
        x = brentq(lambda t: float(self.margin(*(p0 + t * (p1 - p0)))), s[k - 1], s[k],
                   xtol=1e-14)  # fmt: skip
        return p0 + x * (p1 - p0)

    def near(self, t):
        """Angles within π of the drawn ones (the first stretch's and a lone sample's)."""
        return t - 2 * np.pi * np.round((t - self.start) / (2 * np.pi))

    def expected(self, t2, t5, follow):
        return expected(self.margin, self.start, np.stack([t2, t5], axis=1), follow,
                        [True, True])  # fmt: skip

    def check(self, t2, t5, follow=True):
        m = self.lk.solve({"2": t2, "5": t5}, continuation=follow)
        want = self.expected(np.ravel(t2), np.ravel(t5), follow)
        ok, reason = np.ravel(m.ok), np.ravel(m.reason)
        compared = [k for k, w in enumerate(want) if w is not None]
        for k in compared:
            assert ok[k] == want[k], (k, reason[k])
            if not want[k] and self.margin(np.ravel(t2)[k], np.ravel(t5)[k]) > 0:
                assert "cannot reach this input" in reason[k] and "RRR dyad (3, 4)" in reason[k]
        good = np.flatnonzero(ok)
        C = circle_meet(self.A(np.ravel(t2)[good]), self.e, self.D(np.ravel(t5)[good]), self.f,
                        self.side)  # fmt: skip
        np.testing.assert_allclose(np.ravel(m.points["C"])[good], C, atol=1e-9)
        assert np.isnan(np.ravel(m.points["C"])[~ok]).all()
        return m, want


def _and(a, b):
    return False if a is False or b is False else None if a is None or b is None else True


def _or(a, b):
    return True if a is True or b is True else None if a is None or b is None else False


def _sure(m):
    return None if abs(m) < TOL else bool(m > 0)


def expected(margin, start, samples, follow, angle):
    """Per sample: True reached, False not (or not closing), None too near an edge to say.

    ``margin(*p) > 0`` where every group closes; a sample is reached straight from the
    drawing (angles within π of the drawn ones), or — along a sweep — from the sample
    before it if that was reached and the stretch between stays inside.
    """

    def stretch(p0, p1):
        s = np.linspace(0.0, 1.0, DENSE + 1)[1:]
        return float(margin(*(p0[:, None] + s * (p1 - p0)[:, None])).min())

    angle = np.asarray(angle)
    turns = np.where(angle, 2 * np.pi * np.round((samples - start) / (2 * np.pi)), 0.0)
    out, chain, prev = [], True, start
    for p, turn in zip(samples, turns, strict=True):
        straight = _sure(stretch(start, p - turn))
        if follow:
            here = p - turns[0]
            chain = _and(_sure(margin(*p)), _or(straight, _and(chain, _sure(stretch(prev, here)))))
            prev = here
            out.append(chain)
        else:
            out.append(_and(_sure(margin(*p)), straight))
    return out


def at_values(reason, path):
    """The driver values a reason gives for where ``path`` leaves, in degrees."""
    part = reason.split(f"drivers' {path}")[1]
    found = re.search(r"closes at 2 = (-?[\d.e+-]+)°, 5 = (-?[\d.e+-]+)°", part)
    assert found, reason
    return np.radians([float(found[1]), float(found[2])])


# annulus: closes for 2.5 ≤ |A − D| ≤ 3.5 (|A − D| spans 2 ... 10)
def annulus(side=1.0):
    return FiveBar(6.0, 2.0, 2.0, 3.0, 0.5, math.radians(40), math.radians(150), side)


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_a_sweep_leaving_the_region_is_flagged_until_a_sample_is_reached_again(side):
    fb = annulus(side)
    t2 = np.radians(np.arange(40.0, 401.0, 5.0))
    t5 = np.radians(150.0 + 20.0 * np.sin(np.radians(np.arange(40.0, 401.0, 5.0))))
    m, want = fb.check(t2, t5)
    flagged = [k for k, w in enumerate(want) if w is False and fb.margin(t2[k], t5[k]) > 0]
    assert flagged, "the premise: samples closing but not reached"
    assert want[-1] and bool(m.ok[-1])  # back at the drawing after a turn: reached straight
    # where the sweep's path left, before the first flagged sample (Brent on the margin)
    k = flagged[0]
    r = m.reason[k]
    j = int(re.search(r"before sample (\d+)", r)[1])
    pts = np.stack([t2, t5], axis=1)
    p0 = fb.start if j == 0 else pts[j - 1]
    exit_ = fb.leaves_at(p0, pts[j])
    np.testing.assert_allclose(
        at_values(r, "path along the sweep"), exit_, atol=1e-4
    )  # 5 significant digits of degrees
    straight = fb.leaves_at(fb.start, fb.near(pts[k]))
    np.testing.assert_allclose(
        at_values(r, "straight path"), straight, atol=1e-4
    )  # 5 significant digits of degrees


def test_a_grid_takes_the_straight_path_from_the_drawing():
    fb = annulus()
    g2, g5 = np.meshgrid(
        np.radians(np.arange(0.0, 360.0, 12.0)), np.radians(np.arange(0.0, 360.0, 12.0))
    )
    m, want = fb.check(g2, g5, follow=False)
    closes_not_reached = [k for k, w in enumerate(want) if w is False
                          and fb.margin(g2.ravel()[k], g5.ravel()[k]) > 0]  # fmt: skip
    assert closes_not_reached and sum(bool(w) for w in want) > 20
    for k in closes_not_reached[:5]:
        r = m.reason.ravel()[k]
        assert r.startswith("the drivers' straight path from the drawing to this input leaves")
        exit_ = fb.leaves_at(fb.start, fb.near(np.array([g2.ravel()[k], g5.ravel()[k]])))
        np.testing.assert_allclose(
            at_values(r, "straight path"), exit_, atol=1e-4
        )  # 5 significant digits of degrees
    # one pose (an editor's drag) is judged the same way
    for k in [*closes_not_reached[:3], int(np.argmax([bool(w) for w in want]))]:
        one = fb.lk.solve({"2": g2.ravel()[k], "5": g5.ravel()[k]})
        assert bool(one.ok) == bool(want[k]) and str(one.reason) == m.reason.ravel()[k]


def test_a_region_without_holes_reached_everywhere_it_closes():
    # 1 ≤ |A − D| ≤ 5 around a drawing with |A − D| ≈ 4.6: every closing sample of this
    # sweep and grid is reached (straight from the drawing at least)
    fb = FiveBar(6.0, 2.0, 2.0, 3.0, 2.0, math.radians(70), math.radians(110))
    t = np.radians(np.arange(70.0, 431.0, 3.0))
    m, _ = fb.check(t, np.radians(110.0) + 0.3 * np.sin(t))
    closes = fb.margin(t, np.radians(110.0) + 0.3 * np.sin(t)) > 0
    assert 0 < closes.sum() < t.size
    assert (m.ok == closes).all()


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(
    dims=st.tuples(*(st.floats(0.5, 4.0) for _ in range(4)), st.floats(3.0, 7.0)),
    drawn=st.tuples(st.floats(0, 2 * np.pi), st.floats(0, 2 * np.pi)),
    moves=st.lists(st.tuples(st.floats(-4.0, 4.0), st.floats(-4.0, 4.0)), min_size=1, max_size=6),
    follow=st.booleans(),
    side=st.sampled_from([1.0, -1.0]),
)
def test_random_five_bars_and_polyline_sweeps(dims, drawn, moves, follow, side):
    r2, r5, e, f, d0 = dims
    g = abs(r2 * np.exp(1j * drawn[0]) - d0 - r5 * np.exp(1j * drawn[1]))
    assume(abs(e - f) + 0.05 < g < e + f - 0.05)
    fb = FiveBar(d0, r2, r5, e, f, *drawn, side=side)
    steps = np.array(moves)
    pts = np.array(drawn) + np.cumsum(steps, axis=0)
    fb.check(pts[:, 0], pts[:, 1], follow=follow)


# -------------------------------------------------- a crank and a slider as drivers
def test_a_crank_and_a_driven_block():
    # crank O2–A (2) and a block B driven along x (d); dyad A–C (3), B–C (1.5): closes for
    # 1.5 ≤ |A − B| ≤ 4.5
    t0, d0 = math.radians(60.0), 3.0
    A0, B0 = 2 * np.exp(1j * t0), d0 + 0j
    C0 = circle_meet(A0, 3.0, B0, 1.5, 1.0)
    lk = Linkage({"O2": 0j, "A": A0, "B": B0, "C": C0}).ground("O2")
    lk.link("crank", "O2", "A").link("3", "A", "C").link("4", "B", "C").link("block", "B")
    lk.slider("block", "ground", "B", 0.0, through="O2", name="guide").drive("crank", "guide")

    def margin(t, d):
        g = np.abs(2 * np.exp(1j * np.asarray(t)) - np.asarray(d))
        return np.minimum(g - 1.5, 4.5 - g)

    # the crank through 0, where 0.5 < d < 3.5 leaves |A − B| < 1.5 (a hole in the region),
    # then the block out to 5 (reached straight from the drawing again) and back to 3
    t = np.radians(np.concatenate([np.linspace(60.0, -60.0, 49), np.full(30, -60.0)]))
    d = np.concatenate([3.0 + 0.2 * np.sin(np.linspace(0, np.pi, 49)),
                        3.0 + 2.0 * np.sin(np.linspace(0, np.pi, 30))])  # fmt: skip
    m = lk.solve({"crank": t, "guide": d})
    want = expected(margin, np.array([t0, d0]), np.stack([t, d], axis=1), True, [True, False])
    assert any(w is False and margin(t[k], d[k]) > 0 for k, w in enumerate(want))
    assert want[-1] and margin(t[30], d[30]) < 0  # the premises: a gap, then reached again
    for k, w in enumerate(want):
        if w is not None:
            assert m.ok[k] == w, (k, m.reason[k])
            if not w and margin(t[k], d[k]) > 0:
                assert "cannot reach this input along them" in m.reason[k]
                assert "guide = " in m.reason[k] and "RRR dyad (3, 4)" in m.reason[k]
    good = np.flatnonzero(m.ok)
    C = circle_meet(2 * np.exp(1j * t[good]), 3.0, d[good] + 0j, 1.5, 1.0)
    np.testing.assert_allclose(m.points["C"][good], C, atol=1e-9)
