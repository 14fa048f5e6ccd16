"""Motion laws: boundary conditions, textbook peak factors, finite differences."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from machdyn import InputError
from machdyn.cams import (
    LAW_NAMES,
    fall,
    get_law,
    polynomial_law,
    scca,
    scca_peak_factor,
)

DWELL_LAWS = ["cycloidal", "modified_trapezoid", "modified_sine", "poly345", "poly4567"]
RISE_LAWS = [*DWELL_LAWS, "simple_harmonic", "constant_velocity", "constant_acceleration"]
X = np.linspace(0.0, 1.0, 200_001)

# Zone boundaries of the SCCA laws, where jerk jumps (finite differences skip them).
KINKS = {
    "modified_trapezoid": (0.125, 0.375, 0.625, 0.875),
    "modified_sine": (0.125, 0.875),
    "constant_acceleration": (0.5,),
}


@pytest.mark.parametrize("name", RISE_LAWS)
def test_rise_goes_from_zero_to_h(name):
    h, beta = 2.5, np.radians(75)
    values = get_law(name)([0.0, 1.0], h, beta)
    np.testing.assert_allclose(values.s, [0.0, h], atol=1e-12)


@pytest.mark.parametrize("name", DWELL_LAWS)
def test_double_dwell_laws_start_and_end_at_rest(name):
    # Notes, review lecture 3: a(0) = a(β) = 0, v(0) = v(β) = 0 for a dwell-to-dwell rise.
    values = get_law(name)([0.0, 1.0], 1.3, 0.9)
    np.testing.assert_allclose(values.v, 0.0, atol=1e-12)
    np.testing.assert_allclose(values.a, 0.0, atol=1e-12)


@pytest.mark.parametrize("name", [*DWELL_LAWS, "simple_harmonic"])
def test_integral_of_acceleration_is_zero_and_of_velocity_is_h(name):
    # Notes, review lecture 3: ∫a dθ = 0 and ∫v dθ = s(β) - s(0) over a rise.
    h, beta = 1.7, 1.1
    values = get_law(name)(X, h, beta)
    theta = X * beta
    assert np.trapezoid(values.a, theta) == pytest.approx(0.0, abs=1e-8)
    assert np.trapezoid(values.v, theta) == pytest.approx(h, rel=1e-9)


# Peak factors: closed forms or Norton Table 8-3 (printed to 4 decimals).
PEAKS = [
    # name, v_max·β/h, a_max·β²/h, source
    ("cycloidal", 2.0, 2.0 * math.pi, "Norton eq. 8.6: v = 2h/β, a = 2πh/β²"),
    ("simple_harmonic", math.pi / 2, math.pi**2 / 2, "Norton eq. 8.5: πh/2β, π²h/2β²"),
    ("modified_trapezoid", 2.0, 4.8881, "Norton Table 8-3: 2.0000, 4.8881"),
    ("modified_sine", 1.7596, 5.5280, "Norton Table 8-3: 1.7596, 5.5280"),
    ("poly345", 1.875, 10 / math.sqrt(3), "3-4-5: v = 15/8, a at x = 1/2 ∓ √3/6"),
    ("constant_acceleration", 2.0, 4.0, "Norton Table 8-2: constant acceleration 4h/β²"),
]


@pytest.mark.parametrize(("name", "v_peak", "a_peak", "source"), PEAKS)
def test_peak_factors(name, v_peak, a_peak, source):
    h, beta = 2.0, np.radians(60)
    values = get_law(name)(X, h, beta)
    assert values.v.max() * beta / h == pytest.approx(v_peak, abs=1e-4), source
    assert np.abs(values.a).max() * beta**2 / h == pytest.approx(a_peak, abs=1e-4), source


def test_4567_peak_acceleration_from_its_jerk_root():
    # a = 420x² - 1680x³ + 2100x⁴ - 840x⁵; j = 0 where 5x² - 5x + 1 = 0.
    x = (5 - math.sqrt(5)) / 10
    expected = 420 * x**2 - 1680 * x**3 + 2100 * x**4 - 840 * x**5
    assert expected == pytest.approx(7.5132, abs=1e-4)  # Norton Table 8-3
    values = get_law("4-5-6-7")(X, 1.0, 1.0)
    assert np.abs(values.a).max() == pytest.approx(expected, rel=1e-8)
    assert values.v.max() == pytest.approx(35 / 16, rel=1e-12)


def test_brief_peak_factor_list():
    # The brief's values, checked against the laws rather than trusted.
    factors = {
        "modified_trapezoid": 4.888,
        "modified_sine": 5.528,
        "poly345": 5.7735,
        "poly4567": 7.5132,
    }
    for name, factor in factors.items():
        a = get_law(name)(X, 1.0, 1.0).a
        assert np.abs(a).max() == pytest.approx(factor, abs=6e-4), name


def _central(f, x, delta):
    return (f(x + delta) - f(x - delta)) / (2 * delta)


@pytest.mark.parametrize("name", RISE_LAWS)
def test_finite_differences_s_to_v_to_a_to_j(name, rng):
    h, beta = 1.9, np.radians(80)
    law = get_law(name)
    delta = 1e-6
    x = rng.uniform(0.01, 0.99, 400)
    kinks = np.array(KINKS.get(name, ()))
    if kinks.size:
        x = x[np.min(np.abs(x[:, None] - kinks[None, :]), axis=1) > 1e-3]
    values = law(x, h, beta)
    for lower, higher in (("s", "v"), ("v", "a"), ("a", "j")):
        approx = _central(lambda xx, q=lower: getattr(law(xx, h, beta), q), x, delta) / beta
        scale = np.abs(getattr(values, higher)).max() + 1.0
        np.testing.assert_allclose(approx, getattr(values, higher), atol=1e-6 * scale)


@pytest.mark.parametrize("name", RISE_LAWS)
def test_fall_is_mirrored_rise(name):
    h, beta = 0.8, 1.2
    x = np.linspace(0, 1, 101)
    rise = get_law(name)(x, h, beta)
    down = fall(name, x, h, beta)
    np.testing.assert_allclose(down.s, h - rise.s, atol=1e-14)
    np.testing.assert_allclose(down.v, -rise.v)
    np.testing.assert_allclose(down.a, -rise.a)
    np.testing.assert_allclose(down.j, -rise.j)


@given(
    b=st.floats(0.0, 1.0),
    d_share=st.floats(0.0, 1.0),
)
def test_scca_peak_factor_matches_norton_closed_form(b, d_share):
    d = (1.0 - b) * d_share
    c = max(0.0, 1.0 - b - d)
    # Norton eq. 8.16b.
    norton = (
        4
        * math.pi**2
        / ((math.pi**2 - 8) * (b * b - d * d) - 2 * math.pi * (math.pi - 2) * b + math.pi**2)
    )
    # rel 1e-8: zones narrower than 1e-9 are snapped to zero by design.
    assert scca_peak_factor(b, c, d) == pytest.approx(norton, rel=1e-8)


@given(b=st.floats(0.0, 1.0), d_share=st.floats(0.0, 1.0))
def test_scca_family_ends_at_rest_and_reaches_h(b, d_share):
    d = (1.0 - b) * d_share
    c = max(0.0, 1.0 - b - d)
    values = scca([0.0, 0.5, 1.0], 1.0, 1.0, b=b, c=c, d=d)
    np.testing.assert_allclose(values.s, [0.0, 0.5, 1.0], atol=1e-12)
    assert values.v[0] == pytest.approx(0.0, abs=1e-12)
    assert values.v[2] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize(
    ("bcd", "name"),
    [
        ((0.5, 0.0, 0.5), "cycloidal"),
        ((0.0, 0.0, 1.0), "simple_harmonic"),
        ((0.25, 0.5, 0.25), "modified_trapezoid"),
        ((0.25, 0.0, 0.75), "modified_sine"),
    ],
)
def test_named_laws_are_scca_special_cases(bcd, name):
    b, c, d = bcd
    x = np.linspace(0, 1, 1001)
    general = scca(x, 1.4, 0.7, b=b, c=c, d=d)
    named = get_law(name)(x, 1.4, 0.7)
    for q in "svaj":
        np.testing.assert_allclose(getattr(general, q), getattr(named, q), atol=1e-9)


def test_constant_acceleration_is_two_parabolas():
    x = np.linspace(0, 0.5, 51)
    values = get_law("constant_acceleration")(x, 1.0, 1.0)
    np.testing.assert_allclose(values.s, 2 * x**2, atol=1e-12)


def test_polynomial_law_reproduces_345_and_4567():
    x = np.linspace(0, 1, 101)
    p5 = polynomial_law(start={"v": 0, "a": 0}, end={"v": 0, "a": 0})
    p7 = polynomial_law(start={"v": 0, "a": 0, "j": 0}, end={"v": 0, "a": 0, "j": 0})
    # Norton eq. 8.23 and 8.24 written out here, not taken from the library.
    np.testing.assert_allclose(
        p5(x, 2.0, 1.5).s, 2.0 * (10 * x**3 - 15 * x**4 + 6 * x**5), atol=1e-12
    )
    np.testing.assert_allclose(
        p7(x, 2.0, 1.5).s, 2.0 * (35 * x**4 - 84 * x**5 + 70 * x**6 - 20 * x**7), atol=1e-11
    )


def test_polynomial_law_meets_the_conditions_given():
    # Asymmetric: leave with a velocity, arrive at rest, pass through a mid point.
    beta, h = 1.2, 3.0
    law = polynomial_law(
        start={"v": 0.5, "a": 0.0}, end={"v": 0.0, "a": 0.0}, points=[(0.3, "s", 1.0)]
    )
    values = law([0.0, 0.3, 1.0], h, beta)
    np.testing.assert_allclose(values.s, [0.0, 1.0, h], atol=1e-12)
    np.testing.assert_allclose(values.v[[0, 2]], [0.5, 0.0], atol=1e-12)
    np.testing.assert_allclose(values.a[[0, 2]], [0.0, 0.0], atol=1e-10)
    assert law.coefficients(h, beta).size == 7


def test_polynomial_law_bad_conditions():
    with pytest.raises(InputError, match="repeat or contradict"):
        polynomial_law(points=[(0.0, "s", 1.0)])([0.5], 1.0, 1.0)
    with pytest.raises(InputError, match="v, a or j"):
        polynomial_law(start={"s": 1.0})
    with pytest.raises(InputError, match="name must be one of"):
        polynomial_law(points=[(0.5, "q", 1.0)])
    with pytest.raises(InputError, match=r"\[0, 1\]"):
        polynomial_law(points=[(1.5, "s", 1.0)])


def test_unknown_law_lists_the_valid_names():
    with pytest.raises(InputError) as info:
        get_law("parabolic")
    message = str(info.value)
    assert info.value.field == "law"
    for name in LAW_NAMES:
        assert name in message


def test_aliases_and_spelling():
    assert get_law("3-4-5").name == "poly345"
    assert get_law("4-5-6-7").name == "poly4567"
    assert get_law("SHM").name == "simple_harmonic"
    assert get_law("modified-trapezoid").name == "modified_trapezoid"


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"b": 0.5, "c": 0.5, "d": 0.5}, "b \\+ c \\+ d = 1"),
        ({"b": -0.1, "c": 0.6, "d": 0.5}, "\\[0, 1\\]"),
        ({"b": 0.5, "c": 0.5}, "missing d"),
    ],
)
def test_scca_bad_parameters(kwargs, match):
    with pytest.raises(InputError, match=match):
        get_law("scca", **kwargs)


def test_bad_x_beta_h():
    law = get_law("cycloidal")
    with pytest.raises(InputError, match="x"):
        law([1.5], 1.0, 1.0)
    with pytest.raises(InputError, match="beta"):
        law([0.5], 1.0, 0.0)
    with pytest.raises(InputError, match="h"):
        law([0.5], float("nan"), 1.0)
    with pytest.raises(InputError, match="no parameters"):
        get_law("cycloidal", b=0.3)
