"""Centrodes (the second notes: fixed and moving centrodes that "recreate the motion of
the fourbar by rolling (without slip)"; non-circular gears from them).

Checks that share no code with machdyn.centrodes:
* rolling the moving centrode on the fixed one (rebuilt from the curves alone)
  reproduces the solved motion to 1e-9;
* a wheel rolling on the ground: its centrodes are the ground line and its rim;
* friction wheels: the pitch curves are the circles of radii 2 and 3;
* the four-bar's ω4/ω2 from the closed form equals the gears' −r_a/r_b.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.centrodes import centrodes, gear_pitch_curves
from machdyn.errors import InputError
from machdyn.fourbar import FourBar
from machdyn.linkage import Linkage


def wheel_on_ground() -> Linkage:
    lk = Linkage({"T": (0, 0), "C": (0, 1), "W": (1, 1), "B": (2, 2.5), "O": (0, 2.5)})
    lk.ground("T", "O").link("wheel", "C", "W").link("rod", "C", "B").link("block", "B")
    lk.slider("block", "ground", "B", 0.0, through="O")
    return lk.roll("wheel", "C", 1.0, "ground", "T", np.inf).drive("wheel")


def wheels() -> Linkage:
    lk = Linkage({"O2": (0, 0), "O3": (5, 0), "P": (2, 0), "Q": (5, 3)})
    lk.ground("O2", "O3").link("w2", "O2", "P").link("w3", "O3", "Q")
    return lk.roll("w2", "O2", 2.0, "w3", "O3", 3.0).drive("w2")


def watt_six_bar() -> Linkage:
    O4, O6 = 8.0 + 0j, 12.0 + 6.0j
    A = 2.0 * np.exp(1j * np.pi / 6)
    pts = {"O2": 0j, "O4": O4, "O6": O6, "A": A}
    from closed_forms import circle_meet

    B = circle_meet(A, 7.0, O4, 6.0)
    C = O4 + 4.0 * (B - O4) / abs(B - O4) * np.exp(1j * np.radians(-35))
    D = circle_meet(C, 6.0, O6, 5.0, -1.0)
    pts |= {"B": B, "C": C, "D": D}
    lk = Linkage(pts).ground("O2", "O4", "O6")
    lk.link("2", "O2", "A").link("3", "A", "B").link("4", "O4", "B", "C")
    return lk.link("5", "C", "D").link("6", "O6", "D").drive("2")


def assert_rolls(c, where=None, tol=1e-9):
    rolled = c.roll()
    keep = rolled.ok if where is None else rolled.ok & where
    keep[:3] = keep[-3:] = False  # the spline fits of the curves are least accurate at the ends
    assert keep.sum() > 10
    size = np.nanmax(np.abs(c.fixed[keep])) + np.nanmax(np.abs(c.origin[keep]))
    d_angle = np.angle(np.exp(1j * (rolled.angle - c.angle)))
    assert np.max(np.abs(d_angle[keep])) < tol
    assert np.max(np.abs(rolled.origin - c.origin)[keep]) < tol * size
    # no slip: the same arc length rolled on both curves
    assert np.max(np.abs(rolled.slip[keep])) < tol * size


def test_wheel_on_the_ground_rolls_its_rim_on_the_ground_line():
    theta = np.linspace(-1.0, 5.0, 601)
    c = centrodes(wheel_on_ground(), theta, moving="wheel")
    assert c.ok.all()
    assert np.allclose(c.fixed.imag, 0.0, atol=1e-12)  # the ground line y = 0
    assert np.allclose(c.fixed.real, -theta, atol=1e-10)  # the contact moves −r θ
    assert np.allclose(np.abs(c.moving), 1.0, atol=1e-12)  # the rim, about the centre
    assert_rolls(c)


def finite_stretch(c, limit):
    """The longest stretch of the sweep where the centre stays within ``limit``."""
    near = c.ok & (np.abs(c.contact) < limit)
    edges = np.diff(np.concatenate(([0], near.astype(int), [0])))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    k = int(np.argmax(stops - starts))
    return c.parameter[starts[k]], c.parameter[stops[k] - 1]


@pytest.mark.parametrize(("moving", "fixed"), [(3, 1), (4, 2), (2, 4)])
def test_fourbar_centrodes_roll_to_reproduce_the_motion(moving, fixed):
    fb = FourBar(8, 4, 7, 6)
    coarse = centrodes(fb, np.linspace(0.0, 2 * np.pi, 721), moving=moving, fixed=fixed)
    lo, hi = finite_stretch(coarse, 30.0)
    theta2 = np.linspace(lo, hi, 2001)
    c = centrodes(fb, theta2, moving=moving, fixed=fixed)
    m = fb.solve(theta2)
    # the motion to reproduce, from the closed form
    angle = {1: 0 * theta2, 2: theta2, 3: m.theta3, 4: m.theta4}
    assert np.allclose(np.exp(1j * c.angle), np.exp(1j * (angle[moving] - angle[fixed])))
    assert_rolls(c)


def test_centrodes_of_a_pin_are_single_points_and_do_not_roll():
    c = centrodes(FourBar(8, 4, 7, 6), np.linspace(0, 1, 50), moving=3, fixed=2)
    assert np.allclose(c.fixed, 4.0) and np.allclose(c.moving, 0.0)  # A, on both links
    assert not c.roll().ok.any()  # the pole stands still: nothing to roll


def test_six_bar_centrode_relative_to_a_moving_link():
    lk = watt_six_bar()
    coarse = centrodes(lk, np.radians(np.linspace(0, 360, 721)), moving="6", fixed="3")
    lo, hi = finite_stretch(coarse, 60.0)
    theta = np.linspace(lo, hi, 2001)
    c = centrodes(lk, theta, moving="6", fixed="3")
    m = lk.solve(theta, velocity=1.0)
    assert np.allclose(np.exp(1j * c.angle), np.exp(1j * (m.theta["6"] - m.theta["3"])))
    assert_rolls(c)
    # placed at a sample, the moving centrode touches the fixed one there
    k = 1000
    assert abs(c.placed(k)[k] - c.fixed[k]) < 1e-9


def test_friction_wheels_have_circular_pitch_curves():
    g = gear_pitch_curves(wheels(), np.radians(np.arange(0, 360, 15.0)), "w2", "w3")
    assert np.allclose(g.radius_a, 2.0) and np.allclose(g.radius_b, 3.0)
    assert np.allclose(g.ratio, -2.0 / 3.0) and g.external.all()
    assert g.centre_distance == pytest.approx(5.0)


def test_fourbar_gear_pitch_curves_give_its_velocity_ratio():
    fb = FourBar(8, 4, 7, 6)
    theta2 = np.radians(np.arange(0, 360, 3.0))
    g = gear_pitch_curves(fb, theta2, 2, 4)
    m = fb.solve(theta2, omega2=1.0)
    ok = g.ok & np.isfinite(g.ratio)
    assert ok.sum() > 60
    assert np.allclose(g.ratio[ok], m.omega4[ok], rtol=1e-9, atol=1e-12)
    ext = ok & g.external
    assert ext.any() and (ok & ~g.external).any()
    # external: the pitch point between the pivots, the radii add up to the ground link
    assert np.allclose(g.radius_a[ext] + g.radius_b[ext], 8.0)


def test_centre_at_infinity_is_flagged_not_a_silent_nan():
    fb = FourBar(8, 4, 7, 6)
    theta2 = np.linspace(0.0, 2 * np.pi, 721)
    c = centrodes(fb, theta2, moving=3)
    assert c.at_infinity.any() or np.nanmax(np.abs(c.contact)) > 100
    nan = ~np.isfinite(c.fixed)
    assert np.all(~c.ok[nan]) and all(r for r in c.reason[nan])


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: centrodes(FourBar(8, 4, 7, 6), [0.0, 0.1], moving=3, fixed=3), "moving"),
        (lambda: centrodes(FourBar(8, 4, 7, 6), [0.0, 0.1], moving=7), "moving"),
        (lambda: centrodes(FourBar(8, 4, 7, 6), [[0.0, 0.1]], moving=3), "values"),
        (lambda: centrodes(FourBar(8, 4, 7, 6), [0.0], moving=3), "values"),
        (lambda: centrodes("four-bar", [0.0, 0.1], moving=3), "model"),
        (lambda: gear_pitch_curves(FourBar(8, 4, 7, 6), [0.0, 0.1, 0.2], 2, 3), "link_b"),
    ],
)
def test_bad_centrode_requests_name_the_field(call, field):
    with pytest.raises(InputError) as err:
        call()
    assert err.value.field == field


def test_drawing_shows_the_moving_centrode_touching_the_fixed_one(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    c = centrodes(FourBar(8, 4, 7, 6), np.radians(np.linspace(0, 360, 361)), moving=4, fixed=2)
    ax = c.plot(frame=100)
    lines = {ln.get_gid(): ln for ln in ax.lines}
    fixed, moving, contact = (
        lines[g].get_xydata() for g in ("fixed_centrode", "moving_centrode", "centrode_contact")
    )
    z = complex(*contact[0])
    assert z == pytest.approx(complex(*fixed[100])) and z == pytest.approx(complex(*moving[100]))
    ax.figure.savefig(tmp_path / "centrodes.png")
    assert (tmp_path / "centrodes.png").stat().st_size > 1000
    plt.close("all")


def test_rolling_a_sweep_run_backwards():
    theta = np.linspace(2.0, -1.0, 301)  # the wheel driven the other way
    c = centrodes(wheel_on_ground(), theta, moving="wheel")
    assert_rolls(c)
    with pytest.raises(InputError, match="monotonic"):
        centrodes(wheel_on_ground(), np.array([0.0, 1.0, 0.5, 2.0]), moving="wheel").roll()
