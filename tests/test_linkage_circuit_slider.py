"""Several drivers: a path through a change point of an RRP dyad (a slider) is flagged.

An isosceles slider-crank (crank O2–A = rod A–B = r, the block B sliding on the
x axis through O2) has a change point where the crank stands square to the
slide, ``θ = ±90°``: there the rod is square to it too (A's height ``r sin θ``
equals the rod's length: the rod's circle about A touches the line), the block
sits on O2, and the dyad's two forms — ``B = 2 r cos θ`` (the drawn one) and
``B = 0`` — cross. Holding the drawn assembly sign through it goes on along the
other form; with a second driver machdyn flags the samples past it (as for an
RRR dyad's, ``test_linkage_circuit_narrow.py``); with one driver it follows
the drawn form through it (as a parallelogram's, ``test_linkage_change_point.py``).
The references are written here: the change points and the drawn form in closed
form, the samples reached without passing one (``reached_without_a_change_point``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from machdyn.linkage import Linkage
from test_linkage_circuit_narrow import reached_without_a_change_point

pytestmark = pytest.mark.usefixtures("backend")  # NumPy, then the compiled kernel

R = 2.0
T0 = math.radians(30.0)  # the drawn crank angle


def slider_crank_and_arm():
    A = R * np.exp(1j * T0)
    B = 2 * R * math.cos(T0) + 0j  # the drawn form: |A − B| = r
    lk = Linkage({"O2": 0j, "A": A, "B": B, "O5": 10 + 0j, "E": 11 + 0j}).ground("O2", "O5")
    lk.link("crank", "O2", "A").link("rod", "A", "B").link("block", "B").link("arm", "O5", "E")
    lk.slider("block", "ground", "B", 0.0, through="O2", name="guide")
    return lk.drive("crank", "arm")


def change_points():
    theta = np.array([-math.pi / 2, math.pi / 2])  # the crank square to the slide
    assert np.allclose(np.abs(R * np.sin(theta)), R)  # A's height equals the rod's length
    return theta


@pytest.mark.parametrize(("step", "follow"), [(0.4, True), (1.0, True), (1.0, False)])
def test_a_path_through_a_sliders_change_point_is_flagged_not_crossed(step, follow):
    lk = slider_crank_and_arm()
    th = np.radians(np.arange(30.0, 330.0 + step / 2, step))
    m = lk.solve({"crank": th, "arm": 0.5 * th}, continuation=follow)
    expected = reached_without_a_change_point(th, T0, follow, change_points())
    assert expected.sum() > 50 and (~expected).sum() > 100  # the premise: both kinds
    assert (m.ok == expected).all(), np.flatnonzero(m.ok != expected)
    # ok: the drawn form, the block at 2 r cos θ on the x axis, the rod's length kept
    B, A = m.points["B"][m.ok], R * np.exp(1j * th[m.ok])
    assert np.allclose(B, 2 * R * np.cos(th[m.ok]), atol=1e-9)
    assert np.allclose(np.abs(A - B), R, atol=1e-9)
    assert np.isnan(m.points["B"][~m.ok]).all()
    word = "them" if follow else "it"
    for r in m.reason[~expected]:
        assert "passes a change point of RRP dyad (rod, block)" in r, r
        assert r.endswith(f"cannot reach this input along {word} on its drawn form"), r


def slider_crank():
    A = R * np.exp(1j * T0)
    lk = Linkage({"O2": 0j, "A": A, "B": 2 * R * math.cos(T0) + 0j}).ground("O2")
    lk.link("crank", "O2", "A").link("rod", "A", "B").link("block", "B")
    return lk.slider("block", "ground", "B", 0.0, through="O2", name="guide").drive("crank")


@pytest.mark.parametrize("follow", [True, False])
def test_one_driver_follows_the_drawn_form_through_a_sliders_change_point(follow):
    # one driver: the drawn form goes on by continuity, as a parallelogram's does
    # (test_linkage_change_point.py); it showed B = 0 past 90° before
    lk = slider_crank()
    th = np.radians(np.arange(30.0, 390.0 + 0.5, 1.0))
    m = lk.solve(th, velocity=1.0, continuation=follow)
    at = np.abs(np.cos(th)) < 1e-9  # the crank square to the slide: a toggle
    assert at.sum() == 2 and (m.ok == ~at).all(), m.reason[~m.ok]
    B, V = m.points["B"][m.ok], m.point_velocity["B"][m.ok]
    assert np.allclose(B, 2 * R * np.cos(th[m.ok]), atol=1e-9)
    assert np.allclose(V, -2 * R * np.sin(th[m.ok]), atol=1e-8)  # d(2r cos θ)/dt, ω = 1
    assert np.allclose(np.abs(R * np.exp(1j * th[m.ok]) - B), R, atol=1e-9)
