"""A parallelogram four-bar keeps its form through its change points.

At θ2 = θ1 and θ1 + π a parallelogram's four pivots are in line: its two forms, the
parallelogram and the antiparallelogram, meet and cross there (Norton, *Design of
Machinery*, §2.8: the Grashof special case s + l = p + q). Holding the drawn
assembly sign through it would give the antiparallelogram for half of every turn;
the Linkage follows the drawn form by continuity (the coupler angle and its rate
continuous). The references here are closed forms: the parallelogram's coupler
stays parallel to the ground (θ3 = θ1) and its rocker parallel to the crank
(θ4 = θ2, ω4 = ω2, ω3 = 0); the antiparallelogram's B is the parallelogram's B
mirrored in the line A–O4 (the other intersection of the circles about A and O4).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from closed_forms import circle_meet
from machdyn.linkage import Linkage

A_, D_ = 1.5, 4.0  # crank = rocker, coupler = ground


def parallelogram(theta_deg, theta1_deg=0.0, crossed=False):
    t1 = math.radians(theta1_deg)
    O4 = D_ * np.exp(1j * t1)
    A = A_ * np.exp(1j * math.radians(theta_deg))
    B = A + O4  # the parallelogram
    if crossed:
        B = mirror(B, A, O4)
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "B": B}).ground("O2", "O4")
    lk.link("crank", "O2", "A").link("coupler", "A", "B").link("rocker", "O4", "B")
    return lk.drive("crank"), O4


def mirror(P, A, O4):
    u = (O4 - A) / np.abs(O4 - A)
    return A + u * np.conj((P - A) / u)


@pytest.mark.usefixtures("backend")  # NumPy, then the compiled kernel (which ran the drawn
# program past the change points until 2026-11-25: the packed rows were kept per tables)
@pytest.mark.parametrize("theta1", [0.0, 25.0])
@pytest.mark.parametrize("drawn", [60.0, 250.0])
@pytest.mark.parametrize("follow", [True, False])
def test_a_parallelogram_stays_a_parallelogram(drawn, theta1, follow):
    lk, O4 = parallelogram(drawn, theta1)
    th = (
        math.radians(drawn) + np.radians(np.arange(0.0, 720.0, 7.0)) + 0.01
    )  # no sample at a change point
    m = lk.solve(th, velocity=3.0, acceleration=0.5, continuation=follow)
    assert m.ok.all(), set(m.reason)
    A = A_ * np.exp(1j * th)
    np.testing.assert_allclose(m.points["B"], A + O4, atol=1e-9)
    t1 = math.radians(theta1)
    np.testing.assert_allclose(np.exp(1j * m.theta["coupler"]), np.exp(1j * t1), atol=1e-9)
    np.testing.assert_allclose(np.exp(1j * m.theta["rocker"]), np.exp(1j * th), atol=1e-9)
    np.testing.assert_allclose(m.omega["coupler"], 0.0, atol=1e-9)
    np.testing.assert_allclose(m.omega["rocker"], 3.0, atol=1e-9)
    np.testing.assert_allclose(m.alpha["rocker"], 0.5, atol=1e-9)
    if follow:  # continuous angles along the sweep
        assert np.abs(np.diff(m.theta["rocker"])).max() < 0.2
        assert np.abs(np.diff(m.theta["coupler"])).max() < 1e-6


@pytest.mark.usefixtures("backend")
def test_an_antiparallelogram_stays_crossed():
    lk, O4 = parallelogram(60.0, crossed=True)
    th = np.radians(np.arange(61.5, 780.0, 7.0))
    m = lk.solve(th, velocity=1.0)
    assert m.ok.all()
    A = A_ * np.exp(1j * th)
    np.testing.assert_allclose(m.points["B"], mirror(A + O4, A, O4), atol=1e-9)
    # and the other intersection of the two circles, on the side the sign of each half gives
    side = np.sign(np.sin(th))
    np.testing.assert_allclose(m.points["B"], circle_meet(A, D_, O4, A_, -side), atol=1e-9)


def test_at_the_change_point_itself_the_rates_are_flagged():
    lk, _ = parallelogram(60.0)
    m = lk.solve(np.array([math.pi - 0.3, math.pi, math.pi + 0.3]), velocity=1.0)
    assert m.ok.tolist() == [True, False, True]
    assert "toggle" in m.reason[1] or "does not close" in m.reason[1]  # (rounding decides)


def test_fourbar_form_is_read_sample_by_sample_past_the_change_point():
    """FourBar's form (the sign of φ12, as in the notes) is the other shape past π.

    The documented contrast with Linkage: form 1 is the parallelogram before the
    change point and the antiparallelogram after it (B mirrored in A–O4), every
    sample closing the loop; the change point itself is flagged.
    """
    from machdyn import FourBar

    th = np.radians([60.0, 120.0, 180.0, 240.0, 300.0])
    m = FourBar(D_, A_, D_, A_).solve(th, omega2=1.0, form=1)
    assert m.ok.tolist() == [True, True, False, True, True]
    A = A_ * np.exp(1j * th)
    B = A + D_ * np.exp(1j * m.theta3)
    assert np.allclose(np.abs(B - D_), A_, atol=1e-12)  # the rocker's length: closed
    parallel = A + D_
    crossed = mirror(parallel, A, D_)
    assert np.allclose(B[:2], parallel[:2], atol=1e-12)
    assert np.allclose(B[3:], crossed[3:], atol=1e-12)
    lk, _ = parallelogram(60.0)
    np.testing.assert_allclose(np.exp(1j * lk.solve(th[3:]).theta["coupler"]), 1.0, atol=1e-9)


def test_a_near_parallelogram_is_not_flipped():
    # a Grashof crank-rocker 1e-3 short of the change point (crank 1.499: s + l = 5.499 <
    # p + q = 5.5): |A − O4| stays within [2.501, 5.499], inside the dyad's [2.5, 5.5], so
    # it never toggles and the drawn sign is its one circuit (circle intersection, one side)
    O4 = 4.0 + 0j
    A = 1.499 * np.exp(1j * math.radians(60.0))
    B = circle_meet(A, 4.0, O4, 1.5, 1.0)
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "B": B}).ground("O2", "O4")
    lk.link("crank", "O2", "A").link("coupler", "A", "B").link("rocker", "O4", "B")
    lk.drive("crank")
    th = np.radians(np.arange(0.0, 360.0, 3.0))
    m = lk.solve(th)
    assert m.ok.all()
    want = circle_meet(1.499 * np.exp(1j * th), 4.0, O4, 1.5, 1.0)
    np.testing.assert_allclose(m.points["B"], want, atol=1e-9)


@settings(max_examples=25, deadline=None)
@given(
    crank=st.floats(0.3, 3.0),
    ground=st.floats(0.5, 5.0),
    theta1=st.floats(-np.pi, np.pi),
    drawn=st.floats(0.05, np.pi - 0.05),
    half=st.sampled_from([0.0, np.pi]),
    moves=st.lists(st.floats(-7.0, 7.0), min_size=1, max_size=8),
    follow=st.booleans(),
)
def test_random_parallelograms_keep_their_coupler_parallel(
    crank, ground, theta1, drawn, half, moves, follow
):
    assume(abs(crank - ground) > 0.05 * ground)  # (crank = ground: a rhombus, a kite too)
    O4 = ground * np.exp(1j * theta1)
    t0 = theta1 + drawn + half  # off the change points θ1, θ1 + π
    A = crank * np.exp(1j * t0)
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "B": A + O4}).ground("O2", "O4")
    lk.link("crank", "O2", "A").link("coupler", "A", "B").link("rocker", "O4", "B")
    lk.drive("crank")
    th = t0 + np.cumsum(moves)
    m = lk.solve(th, velocity=1.0, continuation=follow)
    off = np.abs(np.sin(th - theta1)) > 1e-3  # not at a change point (a toggle there)
    assert m.ok[off].all()
    np.testing.assert_allclose(m.points["B"][off], crank * np.exp(1j * th[off]) + O4, atol=1e-9)
    np.testing.assert_allclose(m.omega["coupler"][off], 0.0, atol=1e-9)
