"""Slider-cranks: closed forms against independent references and invariants."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from machdyn import AssemblyError, InputError
from machdyn.centres import collinearity
from machdyn.slidercrank import InvertedSliderCrank, SliderCrank


def stencil(f, h):
    """Five-point central difference of f(t) at t = 0 (error O(h⁴))."""
    return (-f(2 * h) + 8 * f(h) - 8 * f(-h) + f(-2 * h)) / (12 * h)


def motion(solve, t, theta0, w, al, je):
    theta2 = theta0 + w * t + al * t**2 / 2 + je * t**3 / 6
    return solve(theta2, omega2=w + al * t + je * t**2 / 2, alpha2=al + je * t, jerk2=je)


def close(exact, approx, rtol=1e-6):
    return np.all(np.abs(exact - approx) <= rtol * (1.0 + np.abs(exact)))


def cont(x, ref):
    """An angle made continuous near a reference angle."""
    return ref + np.angle(np.exp(1j * (x - ref)))


# ------------------------------------------------------------------------------- SliderCrank


def test_norton_closed_form_positions():
    # Norton eq. 4.17, second solution (slider on +x): θ3 = arcsin(−(a sin θ2 − c)/b) + π,
    # d = a cos θ2 − b cos θ3
    a, b, c = 40.0, 120.0, -15.0
    theta2 = np.radians(np.arange(0, 360, 7.5))
    m = SliderCrank(a, b, c).solve(theta2)
    theta3 = np.arcsin(-(a * np.sin(theta2) - c) / b) + np.pi
    assert np.allclose(np.angle(np.exp(1j * (m.theta3 - theta3))), 0, atol=1e-13)
    assert np.allclose(m.d, a * np.cos(theta2) - b * np.cos(theta3), atol=1e-12)
    m2 = SliderCrank(a, b, c).solve(theta2, form=2)
    assert np.all(m2.d < 0)


def test_loop_closure_and_slider_on_its_line():
    sc = SliderCrank(3.0, 7.5, 1.2, point=(2.0, 0.3))
    m = sc.solve(np.linspace(0, 2 * np.pi, 97))
    residual = 3.0 * np.exp(1j * m.theta2) - 7.5 * np.exp(1j * m.theta3) - 1.2j - m.d
    assert np.max(np.abs(residual)) < 1e-13
    assert np.allclose(m.B.imag, 1.2)
    assert np.allclose(np.abs(m.B - m.A), 7.5)
    assert np.allclose(np.abs(m.coupler - m.A), 2.0)


slider_cranks = st.tuples(st.floats(0.5, 5.0), st.floats(0.5, 15.0), st.floats(-3.0, 3.0))


@given(slider_cranks, st.sampled_from([1, 2]), st.floats(-4, 4), st.floats(-5, 5), st.floats(-5, 5))
def test_derivatives_match_finite_differences(dims, form, w, al, je):
    a, b, c = dims
    assume(a + abs(c) < 0.9 * b and abs(w) > 0.1)
    sc = SliderCrank(a, b, c, point=(0.5 * b, 0.2))
    theta0 = np.linspace(0, 2 * np.pi, 13)[:-1]
    h = 1e-4

    def at(t):
        return motion(lambda *x, **k: sc.solve(*x, form=form, **k), t, theta0, w, al, je)

    mid = at(0.0)
    assert close(mid.omega3, stencil(lambda t: cont(at(t).theta3, mid.theta3), h))
    assert close(mid.alpha3, stencil(lambda t: at(t).omega3, h))
    assert close(mid.jerk3, stencil(lambda t: at(t).alpha3, h))
    assert close(mid.d_dot, stencil(lambda t: at(t).d, h))
    assert close(mid.d_ddot, stencil(lambda t: at(t).d_dot, h))
    assert close(mid.d_dddot, stencil(lambda t: at(t).d_ddot, h))
    assert close(mid.coupler_velocity, stencil(lambda t: at(t).coupler, h))
    assert close(mid.coupler_acceleration, stencil(lambda t: at(t).coupler_velocity, h))


@given(slider_cranks, st.sampled_from([1, 2]))
def test_instant_centres_kennedy_and_mechanical_advantage(dims, form):
    a, b, c = dims
    assume(a + abs(c) < 0.9 * b)
    sc = SliderCrank(a, b, c)
    theta2 = np.linspace(0.05, 2 * np.pi - 0.05, 41)
    ics = sc.instant_centres(theta2, form=form)
    assert ics[1, 4].at_infinity.all()
    assert np.allclose(ics[1, 4].direction, 1j)
    for i, j, k in [(1, 2, 3), (1, 2, 4), (1, 3, 4), (2, 3, 4)]:
        res = collinearity(ics[i, j].homogeneous, ics[j, k].homogeneous, ics[i, k].homogeneous)
        assert np.max(np.abs(res)) < 1e-9
    by_power = sc.mechanical_advantage(theta2, 1.5, form=form)
    by_ic = sc.mechanical_advantage(theta2, 1.5, form=form, method="instant_centres")
    keep = np.isfinite(by_power) & (np.abs(by_power) < 1e6)
    assert np.allclose(by_ic[keep], by_power[keep], rtol=1e-8)


def test_stroke_matches_sampled_extremes():
    sc = SliderCrank(2.0, 7.0, 0.8)
    d = sc.solve(np.linspace(0, 2 * np.pi, 400_001)).d
    lo, hi = sc.stroke()
    assert lo == pytest.approx(d.min(), abs=1e-9) and hi == pytest.approx(d.max(), abs=1e-9)
    assert hi == pytest.approx(np.sqrt(81 - 0.64)) and lo == pytest.approx(np.sqrt(25 - 0.64))


def test_rocking_crank_range_and_flags():
    sc = SliderCrank(3.0, 2.0)
    assert not sc.crank_rotates
    lo, hi = sc.input_range()
    assert 3.0 * np.sin(hi) == pytest.approx(2.0) and 3.0 * np.sin(lo) == pytest.approx(-2.0)
    m = sc.solve(np.array([0.0, np.pi / 2]))
    assert m.ok.tolist() == [True, False]
    assert "cannot be assembled" in m.reason[1]
    with pytest.raises(AssemblyError, match="rocks between"):
        sc.solve(np.pi / 2)
    edge = sc.solve(np.array([hi]), omega2=1.0)
    assert edge.assembled[0] and not edge.ok[0] and "toggle" in edge.reason[0]


@pytest.mark.parametrize(
    ("call", "exc", "match"),
    [
        (lambda: SliderCrank(0.0, 5.0), InputError, "crank"),
        (lambda: SliderCrank(1.0, -5.0), InputError, "coupler"),
        (lambda: SliderCrank(1.0, 2.0, offset=4.0), AssemblyError, "offset"),
        (lambda: SliderCrank(1.0, 5.0).solve(0.0, form=0), InputError, "form"),
        (lambda: SliderCrank(1.0, 5.0).solve([0.0, np.nan]), InputError, "theta2"),
        (lambda: SliderCrank(1.0, 5.0, point=3), InputError, "point"),
    ],
)
def test_bad_input(call, exc, match):
    with pytest.raises(exc, match=match):
        call()


# ------------------------------------------------------------------------ InvertedSliderCrank


@given(
    st.tuples(st.floats(0.5, 4.0), st.floats(0.5, 8.0), st.floats(-1.0, 1.0)),
    st.sampled_from([1, 2]),
    st.floats(-4, 4),
    st.floats(-5, 5),
    st.floats(-5, 5),
)
def test_inverted_slider_crank(dims, form, w, al, je):
    a, d, c = dims
    assume(abs(a - d) > abs(c) + 0.3 and abs(w) > 0.1)
    isc = InvertedSliderCrank(a, d, c)
    theta0 = np.linspace(0, 2 * np.pi, 13)[:-1]
    mid = isc.solve(theta0, form=form)
    assert mid.ok.all()
    # geometry: the slot line through A (direction θ4) passes at distance |c| from O4
    u = np.exp(1j * mid.theta4)
    rel = d - mid.A
    dist = (rel * np.conj(u)).imag
    assert np.allclose(np.abs(dist), abs(c), atol=1e-12)
    # and the block sits at b along the slot from the foot of the perpendicular
    foot = d + 1j * c * u
    assert np.allclose((mid.A - foot) * np.conj(u), mid.b, atol=1e-12)
    h = 1e-4

    def at(t):
        return motion(lambda *x, **k: isc.solve(*x, form=form, **k), t, theta0, w, al, je)

    mid = at(0.0)
    assert close(mid.omega4, stencil(lambda t: cont(at(t).theta4, mid.theta4), h))
    assert close(mid.alpha4, stencil(lambda t: at(t).omega4, h))
    assert close(mid.jerk4, stencil(lambda t: at(t).alpha4, h))
    assert close(mid.b_dot, stencil(lambda t: at(t).b, h))
    assert close(mid.b_ddot, stencil(lambda t: at(t).b_dot, h))
    assert close(mid.b_dddot, stencil(lambda t: at(t).b_ddot, h))


def test_inverted_slider_crank_quick_return_angles():
    # Crank 2 inside pivots 4 apart, slot through O4: the rocker's limits are the
    # tangents from O4 to the crank circle, sin = a/d (Norton sec. 3.7 Whitworth/shaper).
    isc = InvertedSliderCrank(2.0, 4.0)
    th = isc.solve(np.linspace(0, 2 * np.pi, 200_001)).theta4
    dev = np.angle(np.exp(1j * (th - np.pi)))
    assert dev.max() == pytest.approx(np.arcsin(0.5), abs=1e-8)
    with pytest.raises(AssemblyError):
        InvertedSliderCrank(2.0, 2.5, offset=1.0).solve(0.0)


def test_mismatched_rate_shapes_name_the_input():
    with pytest.raises(InputError, match=r"alpha2: shape \(2,\)"):
        SliderCrank(1.0, 4.0).solve([0.1, 0.2, 0.3], alpha2=[1.0, 2.0])


@pytest.mark.parametrize(("a", "b", "c"), [(3.0, 2.0, 1.5), (3.0, 2.0, -1.5), (3.0, 2.0, 0.0)])
def test_input_range_matches_where_the_rod_reaches(a, b, c):
    sc = SliderCrank(a, b, c)
    lo, hi = sc.input_range()
    inside = np.linspace(lo, hi, 1001)[1:-1]
    assert sc.solve(inside).ok.all()
    # just outside both ends the rod cannot reach the slide
    outside = sc.solve(np.array([lo - 1e-6, hi + 1e-6]))
    assert not outside.assembled.any()
    for end in (lo, hi):
        assert abs(a * np.sin(end) - c) == pytest.approx(b)
