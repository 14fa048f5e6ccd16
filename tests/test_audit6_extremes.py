"""Audit round 6: extreme-but-valid magnitudes give the answers of ordinary ones.

Every closed form here is scale-free: a mechanism drawn s times larger turns
through the same angles, its instant centres are s times farther from the
origin, its mechanical advantage is the same. Each model is built at scales
from 1e-200 to 1e200 (inside the ±1e250 machdyn accepts for a length) and
checked against the same quantities derived here at scale 1: instant centres
as the meet of two lines (Kennedy's rule, solved as a 2×2 system), the
inverted slider-crank's slot length from the triangle O2–A–O4 (Pythagoras).
Where a magnitude is refused, the error names the field.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from machdyn.centres import instant_centres_of
from machdyn.errors import InputError
from machdyn.fourbar import FourBar
from machdyn.linkage import Linkage
from machdyn.slidercrank import InvertedSliderCrank, SliderCrank

THETA = np.radians(np.arange(5.0, 360.0, 30.0))
SCALES = (1e-200, 1e-100, 1e12, 1e100, 1e200)


def meet(p1: complex, d1: complex, p2: complex, d2: complex) -> complex:
    """The point of the line p1 + t d1 that lies on the line p2 + u d2 (Cramer's rule)."""
    det = (d1.conjugate() * d2).imag  # d1 × d2
    t = ((p2 - p1).conjugate() * d2).imag / det
    return p1 + t * d1


def fourbar_i13_i24(r1, r2, r3, r4, theta2, side=-1.0):
    """I13 on O2A and O4B; I24 on the ground line and AB; A, B by two circles (unit scale).

    B is on the circles about A (radius r3) and O4 (r4), on ``side`` of the line A→O4.
    """
    A = r2 * np.exp(1j * theta2)
    d = abs(A - r1)
    along = (r3**2 - r4**2 + d**2) / (2 * d)
    B = A + (r1 - A) / d * complex(along, side * np.sqrt(r3**2 - along**2))
    return meet(0j, A, r1 + 0j, B - r1), meet(0j, 1 + 0j, A, B - A), B


@pytest.mark.parametrize("s", SCALES)
def test_fourbar_centres_scale_with_the_linkage(s):
    # before the fix: links of 1e-100 gave NaN for I13 and I24 with ok True; 1e12 put every
    # centre "at infinity" (the test was |P| > 1e12 in absolute units); 1e100 overflowed
    r = (8.0, 4.0, 7.0, 6.0)
    fb = FourBar(*(x * s for x in r))
    drawn = complex(fb.solve(THETA[0]).B) / s  # form 1's side of A→O4 (a crank-rocker keeps it)
    side = min((1.0, -1.0), key=lambda k: abs(fourbar_i13_i24(*r, THETA[0], k)[2] - drawn))
    ics = fb.instant_centres(THETA)
    assert ics.ok.all()
    assert ics.scale == ics[1, 3].scale == 8.0 * s  # the documented attribute: the longest link
    for k, t in enumerate(THETA):
        i13, i24, B = fourbar_i13_i24(*r, t, side)
        assert abs(ics[3, 4].point[k] / s - B) < 1e-12 * 8
        assert abs(ics[1, 3].point[k] / s - i13) < 1e-10 * max(8, abs(i13))
        assert abs(ics[2, 4].point[k] / s - i24) < 1e-10 * max(8, abs(i24))
    ma = fb.mechanical_advantage(THETA, method="instant_centres")
    same = FourBar(*r).mechanical_advantage(THETA, method="power")
    assert np.allclose(ma, same, rtol=1e-9)


@pytest.mark.parametrize("s", SCALES)
def test_slider_crank_centres_scale_with_the_linkage(s):
    a, b, c = 4.0, 12.0, 1.5
    ics = SliderCrank(a * s, b * s, c * s).instant_centres(THETA)
    assert ics.ok.all() and ics[1, 4].at_infinity.all()
    for k, t in enumerate(THETA):
        A = a * np.exp(1j * t)
        B = complex(A.real + np.sqrt(b * b - (c - A.imag) ** 2), c)  # the block right of A
        assert abs(ics[1, 3].point[k] / s - meet(0j, A, B, 1j)) < 1e-10 * 16
        # I24: on the rod's line AB and on the line through O2 and I14 (normal to the slide)
        assert abs(ics[2, 4].point[k] / s - meet(0j, 1j, A, B - A)) < 1e-10 * 16


@pytest.mark.parametrize("s", SCALES)
def test_inverted_slider_crank_slot_and_centres_scale_with_the_linkage(s):
    # before the fix: lengths above ~1e154 overflowed |S|² (b NaN, a RuntimeWarning)
    a, d, c = 4.0, 6.0, 1.0
    isc = InvertedSliderCrank(a * s, d * s, c * s)
    m = isc.solve(THETA, omega2=1.0)
    A = a * np.exp(1j * THETA)
    b = np.sqrt(np.abs(A - d) ** 2 - c * c)  # O4A² = b² + c² (the slot offset ⟂ the slot)
    assert m.ok.all()
    assert np.allclose(m.b / s, b, rtol=1e-12)
    ics = isc.instant_centres(THETA)
    assert ics.ok.all() and np.allclose(ics[1, 4].point / s, d) and ics[3, 4].at_infinity.all()
    for k in range(THETA.size):
        slot = np.exp(1j * m.theta4[k])  # the normal through O4 meets O2A at I13
        assert abs(ics[1, 3].point[k] / s - meet(0j, A[k], d + 0j, 1j * slot)) < 1e-9 * 8


def _drawn_fourbar(s: float) -> Linkage:
    r1, r2, r3, r4 = 8.0, 4.0, 7.0, 6.0
    _, _, B = fourbar_i13_i24(r1, r2, r3, r4, 0.5)
    A = r2 * np.exp(0.5j)
    pts = {"O2": 0j, "O4": r1 * s + 0j, "A": A * s, "B": B * s}
    lk = Linkage(pts).ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
    return lk.link("rocker", "O4", "B").drive("crank")


@pytest.mark.parametrize("s", [1e-45, 1e12, 1e45])
def test_a_drawn_linkage_has_its_centres_at_any_scale(s):
    # before the fix: a drawing 1e12 long had every centre NaN with ok True
    theta = np.array([0.5, 0.8, 1.4])
    ics = instant_centres_of(_drawn_fourbar(s), theta)
    assert ics.ok.all()
    for k, t in enumerate(theta):
        i13, i24, _ = fourbar_i13_i24(8.0, 4.0, 7.0, 6.0, t)
        assert abs(ics["ground", "coupler"].point[k] / s - i13) < 1e-9 * max(8, abs(i13))
        assert abs(ics["crank", "rocker"].point[k] / s - i24) < 1e-9 * max(8, abs(i24))


def test_a_drawing_too_small_to_compute_is_refused_by_name():
    # before the fix: a drawing 1e-199 across was "at a toggle" (its squared lengths underflow)
    with pytest.raises(InputError, match=r"^points: the drawing is \S+e-200 across, below 1e-50"):
        _drawn_fourbar(1e-200).solve(0.5)
    m = _drawn_fourbar(1e-45).solve(np.array([0.5, 0.9]))  # just inside: computed
    _, _, B = fourbar_i13_i24(8.0, 4.0, 7.0, 6.0, 0.9)
    assert m.ok.all() and abs(m.points["B"][1] / 1e-45 - B) < 1e-12 * 8


def test_fewest_teeth_of_a_tiny_pressure_angle_are_counted_or_refused_by_name():
    # before the fix: φ = 1e-10 rad gave 2/sin²φ = 2e20 teeth cast to int64 (a RuntimeWarning
    # and -9223372036854775808); Norton's rack relation N = 2k/sin²φ, whole teeth, rounded up
    from machdyn import gears

    phi = 1e-5  # 2e10 teeth: still a count
    assert gears.min_teeth_rack(phi) == math.ceil(2.0 / math.sin(phi) ** 2 - 1e-9)
    assert gears.min_pinion_teeth(pressure_angle=phi) == gears.min_teeth_rack(phi)
    too_small = r"^pressure_angle: is too small: the fewest teeth would be (2|1\.33)e\+20"
    for f in (gears.min_teeth_rack, gears.min_teeth_equal_gears):
        with pytest.raises(InputError, match=too_small):
            f(1e-10)
    with pytest.raises(InputError, match=too_small):
        gears.min_pinion_teeth(pressure_angle=1e-10)


@pytest.mark.parametrize("k", [1, 2, 3, 4])
def test_a_four_bar_link_that_is_a_point_is_refused_by_name(k, capsys):
    # before the fix: `machdyn fourbar 1e-300 4 7 6` printed a table; FourBar(6, 9, 3e-40, 8)
    # had an input range of zero width and extrema() raised IndexError. As Linkage refuses
    # pins drawn within 1e-12 of the drawing's size, a link at most 1e-12 of the longest is
    # refused by its name.
    from machdyn.cli import main

    r = [6.0, 9.0, 3.0, 8.0]
    for small in (1e-300, 9e-13):
        r[k - 1] = small
        with pytest.raises(InputError, match=rf"^r{k}: {small:g} is a point next to the longest"):
            FourBar(*r)
    assert main(["fourbar", *map(str, r)]) == 1
    out, err = capsys.readouterr()
    assert not out and err.strip() == err.strip().splitlines()[0] and f"r{k}: 9e-13" in err


def test_a_tiny_coupler_above_the_floor_has_the_input_range_of_two_circles():
    # the crank swings while A stays between r4 − r3 and r4 + r3 from O4 (law of cosines)
    r1, r2, r3, r4 = 6.0, 9.0, 3e-9, 8.0
    fb = FourBar(r1, r2, r3, r4)
    ends = sorted(
        math.acos((r1 * r1 + r2 * r2 - reach**2) / (2 * r1 * r2)) for reach in (r4 - r3, r4 + r3)
    )
    got = fb.input_range(1)
    assert abs(got.lo - ends[0]) < 1e-12 and abs(got.hi - ends[1]) < 1e-12
    assert all(np.isfinite([e.min, e.max]).all() for e in fb.extrema(form=1, n=51).values())


def test_tolerance_worst_case_of_a_fast_machine_scales_as_omega_squared():
    # before the fix: per-sample peaks were float32, so T12 deviations past 3.4e38 became inf
    # and were dropped: the worst case was NaN (a RuntimeWarning) at omega2 = 1e20. With no
    # gravity, load or alpha2, Newton-Euler's T12 is omega2² times the one at omega2 = 1.
    from machdyn.tolerance import tolerance

    def worst(omega2):
        run = tolerance(
            FourBar(8, 4, 7, 6), {"r2": 0.01, "r3": 0.02}, np.radians([10.0, 50.0]),
            samples=20, seed=1, outputs=["T12"], omega2=omega2,
            mass=(1.0, 2.0, 1.5), inertia=(0.1, 0.5, 0.3), cg=(2.0, 3.5, 3.0),
        )  # fmt: skip
        return run.outputs["T12"].worst

    assert worst(1e20) == pytest.approx(1e40 * worst(1.0), rel=1e-6)


def test_a_relative_tolerance_below_what_the_integrator_takes_is_refused_by_name():
    # before the fix: rtol = 1.5e-14 passed the check (>= 1e-14) and scipy's solve_ivp
    # warned "rtol is too small" and integrated with 2.2e-14 (100 eps) instead
    import fuzz_support
    from fuzz_catalogue import catalogue

    call = catalogue()["machdyn.simulate:simulate_drivers"]
    with pytest.raises(InputError, match=r"^rtol: "):
        fuzz_support.invoke(call, "rtol", 1.5e-14)
