"""FourBar: the notes' worked examples, and invariants that share no code with the solver."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from machdyn import AssemblyError, InputError
from machdyn.centres import collinearity
from machdyn.classify import is_assemblable
from machdyn.fourbar import FourBar, positions

# Every test runs on the NumPy kernels and again on the compiled ones.
pytestmark = pytest.mark.usefixtures("backend")

DEG = np.pi / 180.0


# ---------------------------------------------------------------------------------------
# Independent references written here, not imported from the library.


def norton_positions(a, b, c, d, theta2, form):
    """Norton, Design of Machinery, eqs. 4.8a-4.13 (Freudenstein half-angle form).

    Returns (theta3, theta4) in [0, 2π). Norton's "open" root (the minus sign)
    is the notes' form 1 (φ12 > 0) for these test linkages.
    """
    K1, K2, K3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    K4, K5 = d / b, (c * c - d * d - a * a - b * b) / (2 * a * b)
    cos2, sin2 = np.cos(theta2), np.sin(theta2)
    A = cos2 - K1 - K2 * cos2 + K3
    B = -2 * sin2
    C = K1 - (K2 + 1) * cos2 + K3
    D = cos2 - K1 + K4 * cos2 + K5
    E = -2 * sin2
    F = K1 + (K4 - 1) * cos2 + K5
    s = -1 if form == 1 else 1
    theta4 = 2 * np.arctan2(-B + s * np.sqrt(B * B - 4 * A * C), 2 * A)
    theta3 = 2 * np.arctan2(-E + s * np.sqrt(E * E - 4 * D * F), 2 * D)
    return np.mod(theta3, 2 * np.pi), np.mod(theta4, 2 * np.pi)


def newton_raphson(a, b, c, d, theta2, guess, tol=1e-13):
    """The notes' HW 6 Newton–Raphson, one sample at a time (as the MATLAB code)."""
    th3, th4 = guess
    for _ in range(50):
        f = np.array(
            [
                a * np.cos(theta2) + b * np.cos(th3) - c * np.cos(th4) - d,
                a * np.sin(theta2) + b * np.sin(th3) - c * np.sin(th4),
            ]
        )
        J = np.array([[-b * np.sin(th3), c * np.sin(th4)], [b * np.cos(th3), -c * np.cos(th4)]])
        step = np.linalg.solve(J, -f)
        th3, th4 = th3 + step[0], th4 + step[1]
        if np.max(np.abs(step)) < tol:
            break
    return np.mod(th3, 2 * np.pi), np.mod(th4, 2 * np.pi)


def angle_close(x, y, atol):
    return np.allclose(np.angle(np.exp(1j * (np.asarray(x) - np.asarray(y)))), 0.0, atol=atol)


# ---------------------------------------------------------------------------------------
# Worked examples of the notes


HW6_THETA2 = np.arange(0, 91, 15) * DEG


def test_hw6_gcrr_8476_direct_method_matches_norton_closed_form():
    # HW 6: GCRR R1=8, R2=4, R3=7, R4=6, θ2 = 0…90° in 15° steps.
    m = FourBar(8, 4, 7, 6).solve(HW6_THETA2)
    th3, th4 = norton_positions(4, 7, 6, 8, HW6_THETA2, form=1)
    assert m.ok.all()
    assert angle_close(m.theta3, th3, 1e-12)
    assert angle_close(m.theta4, th4, 1e-12)


def test_hw6_gcrr_8476_matches_newton_raphson():
    fb = FourBar(8, 4, 7, 6)
    m = fb.solve(HW6_THETA2)
    guess = (1.0, 1.6)  # an open-configuration guess, as in the MATLAB code
    for k, t2 in enumerate(HW6_THETA2):
        guess = newton_raphson(4, 7, 6, 8, t2, guess)
        assert angle_close(m.theta3[k], guess[0], 1e-11)
        assert angle_close(m.theta4[k], guess[1], 1e-11)


def test_hw6_printed_first_row():
    # θ2 = 0: A = (4, 0), B is 6 from O4 = (8, 0) and 7 from A: cos γ = (36 + 16 − 49)/48.
    m = FourBar(8, 4, 7, 6).solve(0.0)
    assert np.degrees(m.theta4) == pytest.approx(180 - np.degrees(np.arccos(3 / 48)), abs=1e-10)
    assert np.degrees(m.theta3) == pytest.approx(58.8114, abs=5e-5)


def test_review_exam_four_bar_and_coupler_acceleration():
    # Review lecture 1, problem 1: R1 = 75, R2 = 150, R3 = R4 = 250 mm, θ2 = 15°,
    # ω2 = 5 rad/s cw, α2 = 0; printed θ3 = 128.25°, θ4 = 109.85°, ω3 = 9.47 cw,
    # ω4 = 8.73 cw, α3 = 24.00 cw, α4 = 36.13 cw; AC = 300 mm at φ = 18.19° from AB
    # → a_C = (22.78, −9.84) m/s².
    fb = FourBar(0.075, 0.150, 0.250, 0.250, coupler=(0.300, 18.19 * DEG))
    m = fb.solve(15 * DEG, omega2=-5.0, alpha2=0.0, form=2)
    assert np.degrees(m.theta3) == pytest.approx(128.25, abs=0.005)
    assert np.degrees(m.theta4) == pytest.approx(109.85, abs=0.005)
    assert m.omega3 == pytest.approx(-9.47, abs=0.005)
    assert m.omega4 == pytest.approx(-8.73, abs=0.005)
    assert m.alpha3 == pytest.approx(-24.00, abs=0.005)
    assert m.alpha4 == pytest.approx(-36.13, abs=0.005)
    assert m.coupler_acceleration.real == pytest.approx(22.78, abs=0.005)
    assert m.coupler_acceleration.imag == pytest.approx(-9.84, abs=0.005)


@pytest.mark.parametrize(
    ("lengths", "code", "source"),
    [
        ((8, 4, 7, 6), "GCRR", "HW 6"),
        ((6, 9, 3, 8), "GRCR", "HW 3 problem 1"),
        ((8, 4, 9, 6), "GCRR", "final exam problem 2"),
        ((75, 150, 250, 250), "GCCC", "review lecture 1, problem 1"),
    ],
)
def test_barker_class_of_the_notes_linkages(lengths, code, source):
    assert FourBar(*lengths).barker_class == code, source


def test_final_exam_problem_2_minimum_phi12():
    # {8, 4, 9, 6}, φ12 > 0: φ12 is smallest with links 1 and 2 overlapped (θ2 = 0),
    # where the diagonal O4A = 8 − 4 and cos φ12 = (9² + 6² − 4²)/(2·9·6).
    ex = FourBar(8, 4, 9, 6).extrema(form=1)["phi12"]
    assert ex.min == pytest.approx(np.arccos(101 / 108), abs=1e-10)
    assert ex.theta2_at_min == pytest.approx(0.0, abs=1e-6) or ex.theta2_at_min == pytest.approx(
        2 * np.pi, abs=1e-6
    )
    # and largest with links 1 and 2 extended (θ2 = π): diagonal 12
    assert ex.max == pytest.approx(np.arccos((81 + 36 - 144) / 108), abs=1e-10)


# ---------------------------------------------------------------------------------------
# Property tests over random assemblable four-bars


def linkages():
    return st.tuples(*(st.floats(0.5, 10.0) for _ in range(4)))


def usable(lengths):
    s = sorted(lengths)
    return is_assemblable(*lengths) and abs(s[0] + s[3] - s[1] - s[2]) > 1e-2 * sum(lengths)


def interior_angles(fb, form, n=64, min_sin=0.05):
    """Input angles inside the form's range, away from toggles."""
    rng = fb.input_range(form)
    u = np.linspace(0.03, 0.97, n)
    theta2 = rng.lo + u * (rng.hi - rng.lo)
    m = fb.solve(theta2, form=form)
    keep = m.ok & (np.abs(np.sin(m.phi12)) > min_sin)
    return theta2[keep]


@given(linkages(), st.sampled_from([1, 2]))
def test_loop_closure(lengths, form):
    assume(usable(lengths))
    fb = FourBar(*lengths)
    theta2 = interior_angles(fb, form)
    assume(theta2.size > 0)
    m = fb.solve(theta2, form=form)
    a, b, c, d = fb.r2, fb.r3, fb.r4, fb.r1
    residual = a * np.exp(1j * m.theta2) + b * np.exp(1j * m.theta3) - c * np.exp(1j * m.theta4) - d
    assert np.max(np.abs(residual)) < 1e-10 * (a + b + c + d)


def kinematics_at(fb, form, t, theta0, w, al, je):
    """Solve at time t for θ2(t) = θ0 + ω t + α t²/2 + j t³/6."""
    theta2 = theta0 + w * t + al * t**2 / 2 + je * t**3 / 6
    omega2 = w + al * t + je * t**2 / 2
    alpha2 = al + je * t
    return fb.solve(theta2, omega2=omega2, alpha2=alpha2, jerk2=je, form=form)


@given(
    linkages(),
    st.sampled_from([1, 2]),
    st.floats(-3.0, 3.0),
    st.floats(-5.0, 5.0),
    st.floats(-5.0, 5.0),
)
def test_derivatives_match_central_differences_in_time(lengths, form, w, al, je):
    assume(usable(lengths) and abs(w) > 0.1)
    fb = FourBar(*lengths, coupler=(0.7 * lengths[2], 0.4))
    theta0 = interior_angles(fb, form, n=8, min_sin=0.2)
    assume(theta0.size > 0)
    mid = kinematics_at(fb, form, 0.0, theta0, w, al, je)
    # step small against the fastest rotation, so every link turns < 1e-3 rad per step
    fastest = np.max(np.abs([mid.omega2, mid.omega3, mid.omega4]))
    h = 1e-3 / (1.0 + fastest)
    at = {k: kinematics_at(fb, form, k * h, theta0, w, al, je) for k in (-2, -1, 0, 1, 2)}

    def stencil(get):
        # five-point central difference, error O(h⁴)
        return (-get(at[2]) + 8 * get(at[1]) - 8 * get(at[-1]) + get(at[-2])) / (12 * h)

    def fd(name):
        if name.startswith("theta"):  # differentiate the angle continuously
            return stencil(lambda m: np.angle(np.exp(1j * (getattr(m, name) - getattr(mid, name)))))
        return stencil(lambda m: getattr(m, name))

    def check(exact, approx):
        assert np.all(np.abs(exact - approx) <= 1e-5 * (1.0 + np.abs(exact)))

    for k in (3, 4):
        check(getattr(mid, f"omega{k}"), fd(f"theta{k}"))
        check(getattr(mid, f"alpha{k}"), fd(f"omega{k}"))
        check(getattr(mid, f"jerk{k}"), fd(f"alpha{k}"))
    check(mid.coupler_velocity, stencil(lambda m: m.coupler))
    check(mid.coupler_acceleration, stencil(lambda m: m.coupler_velocity))
    check(mid.coupler_jerk, stencil(lambda m: m.coupler_acceleration))


@given(linkages(), st.sampled_from([1, 2]))
def test_kennedy_collinearity_for_every_triple(lengths, form):
    assume(usable(lengths))
    fb = FourBar(*lengths)
    theta2 = interior_angles(fb, form, n=16)
    assume(theta2.size > 0)
    ics = fb.instant_centres(theta2, form=form)
    for i, j, k in [(1, 2, 3), (1, 2, 4), (1, 3, 4), (2, 3, 4)]:
        res = collinearity(ics[i, j].homogeneous, ics[j, k].homogeneous, ics[i, k].homogeneous)
        assert np.max(np.abs(res)) < 1e-9


@given(linkages(), st.sampled_from([1, 2]))
def test_i13_and_i24_are_the_points_of_equal_velocity(lengths, form):
    # Independent of Kennedy's rule: I13 is the point of link 3 at rest,
    # A + j V_A / ω3; I24 is where ω2 × r = ω4 × (r − O4) on the ground line.
    assume(usable(lengths))
    fb = FourBar(*lengths)
    theta2 = interior_angles(fb, form, n=16)
    assume(theta2.size > 0)
    m = fb.solve(theta2, omega2=1.3, form=form)
    ics = fb.instant_centres(theta2, form=form)
    keep = (np.abs(m.omega3) > 1e-3) & (np.abs(m.omega4 - m.omega2) > 1e-3)
    assume(keep.any())
    VA = 1j * m.omega2 * m.A
    i13 = m.A + 1j * VA / m.omega3
    i24 = m.omega4 * fb.r1 / (m.omega4 - m.omega2)
    scale = sum(lengths)
    finite13 = keep & ~ics[1, 3].at_infinity
    finite24 = keep & ~ics[2, 4].at_infinity
    assert np.allclose(ics[1, 3].point[finite13], i13[finite13], atol=1e-7 * scale, rtol=1e-7)
    assert np.allclose(ics[2, 4].point[finite24], i24[finite24], atol=1e-7 * scale, rtol=1e-7)


@given(linkages(), st.sampled_from([1, 2]), st.floats(0.2, 3.0), st.floats(0.2, 3.0))
def test_mechanical_advantage_by_instant_centres_equals_power_identity(lengths, form, rin, rout):
    assume(usable(lengths))
    fb = FourBar(*lengths)
    theta2 = interior_angles(fb, form, n=16)
    assume(theta2.size > 0)
    by_power = fb.mechanical_advantage(theta2, rin, rout, form=form, method="power")
    by_ic = fb.mechanical_advantage(theta2, rin, rout, form=form, method="instant_centres")
    # and the notes' review lecture 3 formula |MA| = r_in R4 sin φ12 / (r_out R2 sin φ14)
    m = fb.solve(theta2, form=form)
    with np.errstate(divide="ignore"):
        notes = np.abs(rin * fb.r4 * np.sin(m.phi12) / (rout * fb.r2 * np.sin(m.phi14)))
    finite = np.isfinite(by_power) & (np.abs(by_power) < 1e6)
    assert np.allclose(by_ic[finite], by_power[finite], rtol=1e-8)
    assert np.allclose(np.abs(by_power[finite]), notes[finite], rtol=1e-8)


def test_mechanical_advantage_is_infinite_at_the_output_toggle():
    fb = FourBar(8, 4, 7, 6)
    extended = [t for t in fb.toggles() if t.links == (2, 3) and t.branch == 1]
    ma = fb.mechanical_advantage(np.array([t.theta2 for t in extended]))
    assert np.all(np.abs(ma) > 1e9)


# ---------------------------------------------------------------------------------------
# Limits


def test_input_range_of_a_rocker_is_where_links_3_and_4_align():
    # GRCR {6, 9, 3, 8}: the diagonal O4A = R3 ± R4 at the limits (law of cosines).
    fb = FourBar(6, 9, 3, 8)
    rng = fb.input_range(form=1)
    assert not rng.full_turn
    for limit in (rng.lo, rng.hi):
        diag = abs(9 * np.exp(1j * limit) - 6)
        assert min(abs(diag - 11), abs(diag - 5)) < 1e-12
    inside = np.linspace(rng.lo, rng.hi, 50)[1:-1]
    assert fb.solve(inside, form=1).assembled.all()
    outside = np.array([rng.lo - 1e-3, rng.hi + 1e-3])
    m = fb.solve(outside, form=1)
    assert not m.assembled.any()
    assert all("cannot be assembled" in r for r in m.reason)


def test_crank_has_full_input_range():
    assert FourBar(8, 4, 7, 6).input_range().full_turn


def test_grcr_forms_are_the_two_sides_of_the_ground_line():
    fb = FourBar(6, 9, 3, 8)
    assert fb.form_rule == "phi34"
    r1, r2 = fb.input_range(1), fb.input_range(2)
    assert 0 < r1.lo < r1.hi < np.pi
    assert np.pi < r2.lo < r2.hi < 2 * np.pi
    mid1 = 0.5 * (r1.lo + r1.hi)
    both = [fb.solve(mid1, form=1, branch=b) for b in (1, -1)]
    assert both[0].phi12 > 0 > both[1].phi12
    with pytest.raises(AssemblyError, match="other form"):
        fb.solve(-mid1, form=1)
    assert fb.solve(-mid1, form=2).ok


def test_toggles_are_collinear_pairs():
    for lengths in [(8, 4, 7, 6), (6, 9, 3, 8), (3, 5, 4, 7), (5, 2, 6, 4)]:
        fb = FourBar(*lengths)
        toggles = fb.toggles()
        assert toggles
        for t in toggles:
            if t.links == (3, 4):
                diag = abs(fb.r2 * np.exp(1j * t.theta2) - fb.r1)
                target = fb.r3 + fb.r4 if t.kind == "extended" else abs(fb.r3 - fb.r4)
                assert diag == pytest.approx(target, abs=1e-9)
            else:
                th3, _, ok = positions(*fb.lengths, t.theta2, t.branch)
                assert ok
                assert abs(np.sin(th3 - t.theta2)) < 1e-7


def test_crank_rocker_output_limits_are_its_toggles():
    # Norton sec. 4.10: a crank-rocker's θ4 extremes occur with crank and coupler collinear.
    fb = FourBar(8, 4, 7, 6)
    ex = fb.extrema(form=1)["theta4"]
    toggle_angles = sorted(t.theta2 for t in fb.toggles() if t.branch == 1)
    found = sorted([ex.theta2_at_min, ex.theta2_at_max])
    assert np.allclose(found, toggle_angles, atol=1e-5)
    # |B − O2| = 11 (extended) and 3 (folded): θ4 from the law of cosines in O2 O4 B
    th4 = sorted(np.pi - np.arccos((36 + 64 - e * e) / (2 * 6 * 8)) for e in (11, 3))
    assert [ex.min, ex.max] == pytest.approx(th4, abs=1e-9)


@pytest.mark.parametrize("lengths", [(8, 4, 7, 6), (6, 9, 3, 8), (3, 5, 4, 7), (4, 8, 3, 7)])
@pytest.mark.parametrize("form", [1, 2])
def test_extrema_agree_with_brute_force_sampling(lengths, form):
    fb = FourBar(*lengths)
    ex = fb.extrema(form=form)
    rng = fb.input_range(form)
    grid = rng.grid(200_001)
    samples = [
        fb.solve(grid, form=form, branch=b)
        for b in ((1, -1) if fb.form_rule == "phi34" else (None,))
    ]
    for name, e in ex.items():
        values = np.concatenate([np.ravel(getattr(m, name))[m.assembled] for m in samples])
        if e.full_turn:
            turns = np.unwrap(np.concatenate([np.ravel(getattr(m, name)) for m in samples]))
            assert np.ptp(turns) > 2 * np.pi - 1e-2 or fb.input_range(form).full_turn, name
            continue
        assert e.max - e.min < 2 * np.pi and -np.pi < 0.5 * (e.min + e.max) <= np.pi
        centre = 0.5 * (e.min + e.max)
        values = centre + np.angle(np.exp(1j * (values - centre)))
        # refined ends are at least as extreme as any sample, and within one step
        assert e.min <= values.min() + 1e-12 and e.max >= values.max() - 1e-12, name
        assert e.min == pytest.approx(values.min(), abs=1e-4), name
        assert e.max == pytest.approx(values.max(), abs=1e-4), name


def test_minimum_transmission_angle_of_a_crank_rocker():
    # Norton sec. 4.10: at θ2 = 0 or π, where the diagonal is d − a or d + a.
    a, b, c, d = 4, 7, 6, 8
    mu = [np.arccos((b * b + c * c - diag**2) / (2 * b * c)) for diag in (d - a, d + a)]
    mu = [min(x, np.pi - x) for x in mu]
    ta = FourBar(d, a, b, c).transmission_angle()
    assert ta.min == pytest.approx(min(mu), abs=1e-10)


def test_coupler_curve_points_lie_on_the_coupler():
    fb = FourBar(8, 4, 7, 6, coupler=(5.0, 0.5))
    curve = fb.coupler_curve(n=181)
    th3, _, _ = positions(*fb.lengths, curve.theta2, 1)
    A = 4 * np.exp(1j * curve.theta2)
    assert np.allclose(np.abs(curve.points - A), 5.0)
    assert angle_close(np.angle(curve.points - A), th3 + 0.5, 1e-12)


def test_coupler_curve_of_a_grcr_form_closes():
    fb = FourBar(6, 9, 3, 8, coupler=(2.0, 1.0))
    pts = fb.coupler_curve(form=1, n=2001).points
    assert abs(pts[0] - pts[-1]) < 1e-3 * 9  # the branches meet at the rocker limits
    steps = np.abs(np.diff(pts))
    assert steps.max() < 20 * np.median(steps)  # no jump between branches


# ---------------------------------------------------------------------------------------
# Results, units and bad input


def test_results_have_the_input_shape_and_a_dataframe():
    m = FourBar(8, 4, 7, 6, coupler=(3, 0.2)).solve(np.zeros((3, 4)), omega2=1.0)
    assert m.theta3.shape == m.coupler.shape == m.phi14.shape == (3, 4)
    df = m.to_pandas(degrees=True)
    assert len(df) == 12
    assert {"theta3_deg", "omega4", "P_x", "AP_y", "ok", "reason"} <= set(df.columns)


def test_results_do_not_share_memory_with_the_inputs():
    theta2, omega2 = np.linspace(0.0, 1.0, 5), np.full(5, 2.0)
    m = FourBar(8, 4, 7, 6).solve(theta2, omega2)
    theta2[:] = 9.0
    omega2[:] = 9.0
    assert m.theta2.tolist() == np.linspace(0.0, 1.0, 5).tolist()
    assert (m.omega2 == 2.0).all()


def test_fundamental_angles_follow_the_notes_definitions():
    m = FourBar(8, 4, 7, 6).solve(np.radians(40))
    wrap = lambda x: np.angle(np.exp(1j * x))  # noqa: E731
    assert m.phi34 == pytest.approx(wrap(m.theta2))
    assert m.phi24 == pytest.approx(wrap(m.theta3))
    assert m.phi23 == pytest.approx(wrap(np.pi - m.theta4))
    assert m.phi12 == pytest.approx(wrap(m.theta4 - m.theta3))
    assert m.phi13 == pytest.approx(wrap(m.theta2 - m.theta4))
    assert m.phi14 == pytest.approx(wrap(np.pi - m.theta2 + m.theta3))
    assert 0 <= m.mu <= np.pi / 2


def test_pint_quantities_at_the_boundary():
    pint = pytest.importorskip("pint")
    u = pint.UnitRegistry()
    fb = FourBar(8 * u.mm, 0.4 * u.cm, 7 * u.mm, 6 * u.mm)
    assert fb.length_unit == "millimeter"
    assert fb.lengths == pytest.approx((8, 4, 7, 6))
    m = fb.solve(15 * u.degree, omega2=100 * u.rpm)
    assert m.omega2 == pytest.approx(100 * 2 * np.pi / 60)
    with pytest.raises(InputError, match="r2"):
        FourBar(8 * u.mm, 4, 7, 6)


@pytest.mark.parametrize(
    ("args", "exc", "match"),
    [
        ((0, 4, 7, 6), InputError, "r1: must be a positive length"),
        ((8, -4, 7, 6), InputError, "r2"),
        ((8, 4, float("nan"), 6), InputError, "r3: must be finite"),
        ((20, 4, 7, 6), AssemblyError, "cannot be assembled"),
    ],
)
def test_bad_lengths(args, exc, match):
    with pytest.raises(exc, match=match):
        FourBar(*args)


def test_bad_solve_arguments():
    fb = FourBar(8, 4, 7, 6)
    with pytest.raises(InputError, match="form: must be one of 1, 2"):
        fb.solve(0.0, form=3)
    with pytest.raises(InputError, match="theta2: must be finite"):
        fb.solve([0.0, np.inf])
    with pytest.raises(InputError, match="branch"):
        fb.solve(0.0, branch=-1)
    with pytest.raises(InputError, match="coupler"):
        fb.coupler_curve()


def test_rocker_input_outside_its_range():
    fb = FourBar(6, 9, 3, 8)  # GRCR: link 2 rocks between 31.6° and 92.1°
    with pytest.raises(AssemblyError, match=r"theta2 must lie in \[31.58"):
        fb.solve(np.radians(10.0))
    m = fb.solve(np.radians([10.0, 60.0]))
    assert m.ok.tolist() == [False, True]
    assert np.isnan(m.theta3[0]) and np.isfinite(m.theta3[1])
    assert m.reason[1] == ""


def test_toggle_is_flagged_not_silently_infinite():
    fb = FourBar(6, 9, 3, 8)
    lo = fb.input_range(1).lo
    m = fb.solve(np.array([lo]), omega2=1.0)
    assert m.assembled[0] and not m.ok[0]
    assert "toggle" in m.reason[0]
    assert np.isnan(m.omega3[0])


def test_order_limits_the_derivatives_computed():
    fb = FourBar(8, 4, 7, 6, coupler=(3, 0.2))
    full = fb.solve(np.radians([10, 50]), omega2=2.0, alpha2=1.0)
    for order in (0, 1, 2):
        m = fb.solve(np.radians([10, 50]), omega2=2.0, alpha2=1.0, order=order)
        assert np.array_equal(m.theta4, full.theta4)
        assert (m.omega4 is None) == (order < 1) and (m.coupler_velocity is None) == (order < 1)
        assert (m.alpha4 is None) == (order < 2) and (m.jerk4 is None)
        if order >= 1:
            assert np.array_equal(m.omega3, full.omega3)
        assert "theta3" in m.to_pandas().columns
    with pytest.raises(InputError, match="order"):
        fb.solve(0.0, order=4)


def test_change_point_where_a_meets_o4_is_flagged_indeterminate():
    # CP3X rhombus: at θ2 = 0 joint A lands on O4 and B can be anywhere on its circle.
    m = FourBar(1, 1, 1, 1).solve([0.0, 1.0])
    assert m.ok.tolist() == [False, True]
    assert "indeterminate" in m.reason[0]


def test_dynamics_method_torque_equals_virtual_work():
    # Newton–Euler (force matrix) against virtual work (velocities only): no shared path.
    from machdyn.virtual_work import fourbar_input_torque

    fb = FourBar(8, 4, 7, 6)
    theta2 = np.radians(np.arange(0, 360, 10))
    props = dict(mass=(1.0, 2.0, 1.5), inertia=(0.1, 0.4, 0.2), cg=(2.0, 3.5 + 0.5j, 3.0))
    forces = fb.dynamics(theta2, 10.0, 2.0, gravity=9.81, **props)
    vw = fourbar_input_torque(fb, theta2, 10.0, 2.0, gravity=9.81, **props)
    assert forces.ok.all()
    assert np.allclose(forces.T12, vw.T12, rtol=1e-9, atol=1e-9)


def test_every_exact_rocker_limit_is_flagged_as_a_toggle(rng):
    # At the limits returned by input_range, links 3 and 4 are collinear: the
    # velocity solution is singular there, so the sample must be flagged.
    count = 0
    while count < 300:
        lengths = rng.uniform(0.3, 10.0, 4)
        if not is_assemblable(*lengths):
            continue
        fb = FourBar(*lengths)
        for form in (1, 2):
            r = fb.input_range(form)
            if r.full_turn:
                continue
            for branch in (1, -1) if fb.form_rule == "phi34" else (None,):
                m = fb.solve(np.array([r.lo, r.hi]), omega2=1.0, form=form, branch=branch)
                assert m.assembled.all() and not m.ok.any()
                assert all("toggle" in reason for reason in m.reason)
                count += 1


def test_mismatched_rate_shapes_name_the_input():
    with pytest.raises(InputError, match=r"omega2: shape \(2,\) does not broadcast with theta2"):
        FourBar(8, 4, 7, 6).solve([0.1, 0.2, 0.3], omega2=[1.0, 2.0])


@pytest.mark.parametrize("lengths", [(3, 3, 3, 3), (2, 2, 4, 4)])
def test_extrema_of_change_point_linkages_with_an_indeterminate_pose(lengths):
    # CP3X rhombus and a kite: A lands on O4 at θ2 = 0, where the pose is indeterminate.
    fb = FourBar(*lengths)
    ex = fb.extrema()
    for e in ex.values():
        assert e.full_turn or (np.isfinite(e.min) and np.isfinite(e.max))
    assert np.isfinite(fb.transmission_angle().min)


def test_mechanical_advantage_at_both_dead_points_agrees_between_methods():
    fb = FourBar(6, 9, 3, 8)  # GRCR: link 2 rocks between two toggles of links 3 and 4
    rng = fb.input_range(1)
    for method in ("power", "instant_centres"):
        assert fb.mechanical_advantage(np.array([rng.lo]), method=method)[0] == 0.0
    crank_rocker = FourBar(8, 4, 7, 6)
    stops = np.array([t.theta2 for t in crank_rocker.toggles() if t.branch == 1])
    for method in ("power", "instant_centres"):
        assert np.all(crank_rocker.mechanical_advantage(stops, method=method) == np.inf)


def test_lengths_must_be_lengths():
    pint = pytest.importorskip("pint")
    u = pint.UnitRegistry()
    with pytest.raises(InputError, match="r1: must be a length"):
        FourBar(8 * u.s, 4 * u.s, 7 * u.s, 6 * u.s)


@pytest.mark.parametrize("scale", [1e-200, 1e-8, 1e8, 1e200])
def test_angles_do_not_depend_on_the_unit_of_length(scale):
    theta2 = np.radians(np.arange(0, 360, 15))
    ref = FourBar(8, 4, 7, 6)
    fb = FourBar(8 * scale, 4 * scale, 7 * scale, 6 * scale)
    m, r = fb.solve(theta2, omega2=3.0, alpha2=1.0), ref.solve(theta2, omega2=3.0, alpha2=1.0)
    assert m.ok.all()
    assert np.allclose(m.theta4, r.theta4, rtol=0, atol=1e-12)
    assert np.allclose(m.alpha3, r.alpha3, rtol=1e-12)
    assert np.allclose(m.B / scale, r.B, rtol=1e-12)
    assert fb.input_range().full_turn and len(fb.toggles()) == len(ref.toggles())
    assert fb.transmission_angle().min == pytest.approx(ref.transmission_angle().min, abs=1e-12)
