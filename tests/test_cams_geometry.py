"""Radial cam geometry checked against the notes, finite differences and contact."""

import math

import numpy as np
import pytest

from machdyn import InputError, ModelError
from machdyn.cams import (
    CamProgram,
    OscillatingRoller,
    Segment,
    TranslatingFlatFace,
    TranslatingRoller,
    cam_profile,
    flat_face_radius_of_curvature,
    pitch_curve,
    pressure_angle,
    radius_of_curvature,
    roller_surface,
)
from machdyn.cams.geometry import _trace_point_geometry

deg = np.radians


def program(law="cycloidal", h=1.0, rise=60, fall=60):
    return CamProgram.double_dwell(h, deg(rise), deg(fall), law=law)


def test_final_exam_problem_9_pressure_angle():
    # Notes, final exam problem 9(v): s = 0.4, v = 1.2, Rp = 2.1, ε = 0.1.
    # By hand: φ = atan(1.1 / (0.4 + √4.40)) = atan(1.1 / 2.4976) = 23.77°.
    phi = pressure_angle(0.4, 1.2, 2.1, 0.1)
    assert math.degrees(float(phi)) == pytest.approx(23.77, abs=0.005)


def test_pressure_angle_broadcasts_and_is_zero_in_a_dwell():
    phi = pressure_angle(np.zeros((2, 3)), np.zeros(3), 2.0)
    assert phi.shape == (2, 3)
    assert np.all(phi == 0.0)
    # With offset, the dwell angle is atan(-ε/√(Rp² - ε²)).
    assert float(pressure_angle(0.0, 0.0, 2.0, 1.0)) == pytest.approx(-math.radians(30))


def _smooth(theta, starts, width=2.5):
    """Samples further than ``width`` steps from a segment boundary (jerk may jump there)."""
    step = theta[1] - theta[0]
    gap = np.abs(theta[:, None] - np.append(starts, 2 * np.pi)[None, :])
    return gap.min(axis=1) > width * step


def _finite_difference_geometry(theta, z):
    """Tangent angle and signed ρ of a closed sampled curve (periodic differences)."""
    step = theta[1] - theta[0]
    dz = (np.roll(z, -1) - np.roll(z, 1)) / (2 * step)
    ddz = (np.roll(z, -1) - 2 * z + np.roll(z, 1)) / step**2
    cross = (np.conj(dz) * ddz).imag
    # Curve runs clockwise as θ grows (CCW cam), so convex means negative cross.
    return dz, -(np.abs(dz) ** 3) / cross


@pytest.mark.parametrize("eps", [0.0, 0.4, -0.3])
def test_pressure_angle_is_angle_between_pitch_normal_and_follower_axis(eps):
    cam = TranslatingRoller(3.0, 0.5, eps).profile(program("modified_sine"), n=7200)
    dz, _ = _finite_difference_geometry(cam.theta, cam.pitch)
    # Back to the fixed frame: tangent there, its outward normal, angle from +y.
    tangent = dz * np.exp(1j * cam.theta)
    normal = 1j * tangent
    phi = np.angle(normal / 1j)
    np.testing.assert_allclose(cam.pressure_angle, phi, atol=1e-5)


@pytest.mark.parametrize(
    ("eps", "law"), [(0.0, "cycloidal"), (0.5, "poly345"), (-0.4, "modified_trapezoid")]
)
def test_radius_of_curvature_matches_numerical_curvature(eps, law):
    prog = program(law, h=1.2)
    cam = TranslatingRoller(2.5, 0.4, eps).profile(prog, n=7200)
    ok = _smooth(cam.theta, prog.starts)
    _, rho_fd = _finite_difference_geometry(cam.theta, cam.pitch)
    np.testing.assert_allclose(1 / cam.rho_pitch[ok], 1 / rho_fd[ok], atol=2e-5)
    _, rho_surface_fd = _finite_difference_geometry(cam.theta, cam.surface)
    np.testing.assert_allclose(1 / cam.rho_surface[ok], 1 / rho_surface_fd[ok], atol=2e-4)


def test_norton_zero_offset_curvature_formula():
    # Norton eq. 8.34 (ε = 0): ρ = [(Rp+s)² + v²]^1.5 / [(Rp+s)² + 2v² - a(Rp+s)].
    s, v, a, rp = 0.3, 0.9, -2.0, 2.0
    expected = ((rp + s) ** 2 + v**2) ** 1.5 / ((rp + s) ** 2 + 2 * v**2 - a * (rp + s))
    assert float(radius_of_curvature(s, v, a, rp)) == pytest.approx(expected, rel=1e-14)


def test_general_trace_point_route_agrees_with_notes_formulas(rng):
    s, v, a = rng.uniform(0, 1, 50), rng.uniform(-2, 2, 50), rng.uniform(-5, 5, 50)
    theta = rng.uniform(0, 2 * np.pi, 50)
    rp, eps = 2.2, 0.3
    d = math.sqrt(rp**2 - eps**2)
    p = eps + 1j * (d + s)
    _, _, phi, rho = _trace_point_geometry(theta, p, 1j * v, 1j * a, np.full(50, 1j))
    np.testing.assert_allclose(phi, pressure_angle(s, v, rp, eps), atol=1e-13)
    np.testing.assert_allclose(rho, radius_of_curvature(s, v, a, rp, eps), rtol=1e-11)


def _min_distance_to_surface(cam):
    gap = np.abs(cam.pitch[:, None] - cam.surface[None, :])
    return gap.min(axis=1)


@pytest.mark.parametrize(
    "follower",
    [
        TranslatingRoller(3.0, 0.6, 0.3),
        OscillatingRoller(2.0, 0.3, pivot_distance=4.0, arm_length=3.5),
        OscillatingRoller(2.0, 0.3, pivot_distance=4.0, arm_length=3.5, pivot_side="left"),
    ],
    ids=["translating", "oscillating-right", "oscillating-left"],
)
def test_roller_on_pitch_curve_touches_surface_without_cutting(follower):
    h = 1.0 if isinstance(follower, TranslatingRoller) else deg(15)
    cam = follower.profile(CamProgram.double_dwell(h, deg(90), deg(90), "modified_sine"), n=1440)
    assert not cam.is_undercut
    rf = follower.roller_radius
    nearest = _min_distance_to_surface(cam)
    # Touches (the sampled contact point is at Rf) and never cuts into the cam.
    assert nearest.min() >= rf - 1e-9
    np.testing.assert_allclose(nearest, rf, atol=1e-9)
    np.testing.assert_allclose(np.abs(cam.pitch - cam.surface), rf, atol=1e-12)


def test_undercut_is_detected_reported_and_the_roller_cuts_the_envelope():
    # Steep rise on a small cam with a large roller: convex ρ_pitch < Rf.
    steep = program("cycloidal", h=1.0, rise=30, fall=30)
    cam = TranslatingRoller(1.5, 1.0).profile(steep, n=1440)
    assert cam.is_undercut
    assert cam.rho_min < 1.0
    ranges = cam.undercut_ranges()
    assert ranges
    for start, end in ranges:
        assert 0 <= start <= end < 2 * np.pi
        assert np.all(cam.rho_pitch[(cam.theta >= start) & (cam.theta <= end)] < 1.0)
    # Independent evidence: a roller placed on the pitch curve overlaps the envelope.
    assert _min_distance_to_surface(cam).min() < 1.0 - 1e-3
    assert not next(c for c in cam.checks() if c.name == "undercut").passed
    with pytest.raises(ModelError, match="undercut at"):
        cam.to_dxf("never-written.dxf")


def _face_support(cam):
    """Largest reach of the cam along each face normal n = j e^{-jθ} (cam frame)."""
    n = 1j * np.exp(-1j * cam.theta)
    return (cam.surface[None, :] * np.conj(n[:, None])).real


def test_flat_face_cam_lies_under_every_face_position():
    # Rb = 6 keeps Rb + s + a > 0 (3-4-5 over 60°: a ≥ -5.77 h/β² ≈ -5.27).
    rb = 6.0
    cam = TranslatingFlatFace(rb, eccentricity=0.5).profile(program("poly345"), n=720)
    assert not cam.is_undercut
    support = _face_support(cam)
    # Every face position touches the cam (at its own contact point) and no point pokes through.
    np.testing.assert_allclose(support.max(axis=1), rb + cam.s, atol=1e-12)
    np.testing.assert_allclose(np.diag(support), rb + cam.s, atol=1e-12)
    assert np.all(cam.pressure_angle == 0.0)


def test_flat_face_curvature_and_undercut():
    prog = program("cycloidal")
    cam = TranslatingFlatFace(7.0).profile(prog, n=7200)
    ok = _smooth(cam.theta, prog.starts)
    _, rho_fd = _finite_difference_geometry(cam.theta, cam.surface)
    np.testing.assert_allclose(1 / cam.rho_surface[ok], 1 / rho_fd[ok], atol=1e-5)
    np.testing.assert_allclose(cam.rho_surface, 7.0 + cam.s + cam.a)
    # Base circle too small: Rb + s + a < 0 in the rise (a = -2πh/β² ≈ -22.9 there).
    small = TranslatingFlatFace(2.0).profile(program("cycloidal", rise=30, fall=30), n=720)
    assert small.is_undercut
    assert small.rho_min < 0
    # Independent evidence: the self-intersecting envelope pokes through some face positions.
    assert (_face_support(small).max(axis=1) - (2.0 + small.s)).max() > 1e-3
    assert flat_face_radius_of_curvature(0.5, -3.0, 2.0) == pytest.approx(-0.5)


def test_flat_face_width_rule():
    # Norton eq. 8.28: contact runs from v_min to v_max; cycloidal |v| ≤ 2h/β.
    cam = TranslatingFlatFace(3.0, eccentricity=0.2).profile(program("cycloidal"), n=3600)
    v_peak = 2.0 / deg(60)
    assert cam.face_width == pytest.approx(2 * v_peak, rel=1e-6)
    assert cam.face_position.max() == pytest.approx(v_peak - 0.2, rel=1e-6)
    [width] = [c for c in cam.checks(face_width=10.0) if c.name == "face width"]
    assert width.passed
    [narrow] = [c for c in cam.checks(face_width=3.0) if c.name == "face width"]
    assert not narrow.passed


@pytest.mark.parametrize("side", ["right", "left"])
def test_oscillating_follower_kinematics(side):
    follower = OscillatingRoller(2.0, 0.3, pivot_distance=4.0, arm_length=3.5, pivot_side=side)
    prog = CamProgram.double_dwell(deg(15), deg(90), deg(90))
    cam = follower.profile(prog, n=3600)
    pivot = 4.0 if side == "right" else -4.0
    fixed = cam.pitch * np.exp(1j * cam.theta)
    # The roller centre stays on the arm's circle, starts on the prime circle, above the x axis.
    np.testing.assert_allclose(np.abs(fixed - pivot), 3.5, atol=1e-12)
    assert abs(fixed[0]) == pytest.approx(2.0)
    assert fixed.imag.min() > 0
    # It swings by 15° about the pivot, carrying the roller away from the cam centre.
    swing = np.angle((fixed - pivot) / (fixed[0] - pivot))
    assert np.degrees(np.abs(swing).max()) == pytest.approx(15.0, abs=1e-9)
    assert np.all(np.abs(fixed) >= 2.0 - 1e-12)
    high = np.argmax(cam.s)
    assert abs(fixed[high]) > 2.0 + 0.1
    # Curvature and pressure angle against finite differences of the pitch curve.
    dz, rho_fd = _finite_difference_geometry(cam.theta, cam.pitch)
    ok = _smooth(cam.theta, prog.starts)
    np.testing.assert_allclose(1 / cam.rho_pitch[ok], 1 / rho_fd[ok], atol=1e-5)
    # The roller moves square to its arm, in the sense that increases s.
    sense = np.sign(swing[high])
    motion_dir = 1j * sense * (fixed - pivot)
    normal = 1j * dz * np.exp(1j * cam.theta)
    phi = np.angle(normal / motion_dir)
    np.testing.assert_allclose(cam.pressure_angle, phi, atol=1e-5)


def test_left_pivot_is_the_mirror_image_run_backwards():
    # Reflecting x -> -x turns a right-pivot cam into a left-pivot cam turning the
    # other way, i.e. the left cam with the program read backwards, P_rev(θ) = P(-θ).
    program = CamProgram(
        [
            Segment("rise", deg(60), deg(12), "cycloidal"),
            Segment("dwell", deg(60)),
            Segment("fall", deg(120), deg(12), "cycloidal"),
            Segment("dwell", deg(120)),
        ]
    )
    backwards = CamProgram(
        [
            Segment("dwell", deg(120)),
            Segment("rise", deg(120), deg(12), "cycloidal"),
            Segment("dwell", deg(60)),
            Segment("fall", deg(60), deg(12), "cycloidal"),
        ]
    )
    n = 720
    right = OscillatingRoller(2.0, 0.3, 4.0, 3.5, "right").profile(program, n)
    left = OscillatingRoller(2.0, 0.3, 4.0, 3.5, "left").profile(backwards, n)
    k = (n - np.arange(n)) % n  # sample of -θ
    np.testing.assert_allclose(left.pitch, -np.conj(right.pitch[k]), atol=1e-12)
    np.testing.assert_allclose(left.surface, -np.conj(right.surface[k]), atol=1e-12)
    np.testing.assert_allclose(left.pressure_angle, -right.pressure_angle[k], atol=1e-12)
    np.testing.assert_allclose(left.rho_pitch, right.rho_pitch[k], rtol=1e-9)
    # With the same (asymmetric) program the two sides do differ.
    same = OscillatingRoller(2.0, 0.3, 4.0, 3.5, "left").profile(program, n)
    assert abs(same.pressure_angle_max) != pytest.approx(abs(right.pressure_angle_max), abs=1e-3)


def test_design_checks_pressure_angle_limit():
    cam = TranslatingRoller(1.5, 0.2).profile(program("cycloidal"))
    [check] = [c for c in cam.checks() if c.name == "pressure angle"]
    assert not check.passed
    assert "limit 30°" in check.detail
    assert abs(cam.pressure_angle_max) > deg(30)
    assert cam.theta_pressure_angle_max == pytest.approx(deg(30), abs=deg(5))
    assert check.line().startswith("FAIL pressure angle")


def test_functional_core_points():
    z = pitch_curve(deg(90), 1.0, 2.0)
    assert (z.real, z.imag) == pytest.approx((3.0, 0.0))
    surf = roller_surface(0.0, 0.0, 0.0, 2.0, 0.5, eccentricity=0.0)
    assert (surf.real, surf.imag) == pytest.approx((0.0, 1.5))


def test_profile_to_pandas_and_cam_profile():
    cam = cam_profile(program(), TranslatingRoller(3.0, 0.5), n=90)
    frame = cam.to_pandas()
    assert len(frame) == 90
    assert {"theta_deg", "surface_x", "pressure_angle_deg", "undercut"} <= set(frame.columns)
    # Review finding 12: the angle in radians too, first, as Motion.to_pandas has it.
    assert list(frame.columns[:2]) == ["theta", "theta_deg"]
    np.testing.assert_allclose(frame["theta"], cam.theta)
    with pytest.raises(InputError, match="follower"):
        cam_profile(program(), "roller")


@pytest.mark.parametrize(
    ("make", "field"),
    [
        (lambda: TranslatingRoller(0.3, 0.1, eccentricity=0.5), "prime_radius"),
        (lambda: TranslatingRoller(2.0, -0.1), "roller_radius"),
        (lambda: TranslatingRoller(2.0, 2.5), "roller_radius"),
        (lambda: TranslatingRoller(-2.0, 0.5), "prime_radius"),
        (lambda: TranslatingFlatFace(0.0), "base_radius"),
        (lambda: OscillatingRoller(9.0, 0.3, 4.0, 3.5), "prime_radius"),
        (lambda: OscillatingRoller(2.0, 0.3, -4.0, 3.5), "pivot_distance"),
        (lambda: pressure_angle(0.0, 0.0, 1.0, 1.0), "prime_radius"),
        (lambda: pressure_angle(-3.0, 0.0, 1.0), "s"),
        (lambda: pressure_angle([0.0, np.nan], 0.0, 1.0), "s"),
    ],
)
def test_bad_geometry_input(make, field):
    with pytest.raises(InputError) as info:
        make()
    assert info.value.field == field


def test_oscillating_swing_through_line_of_centres_is_a_model_error():
    follower = OscillatingRoller(2.0, 0.3, pivot_distance=4.0, arm_length=3.5)
    with pytest.raises(ModelError, match="line of centres"):
        follower.profile(CamProgram.double_dwell(deg(170), deg(90), deg(90)))


@pytest.mark.parametrize(
    ("call", "field", "shapes"),
    [
        (lambda: pressure_angle([1.0, 2.0, 3.0], [1.0, 2.0], 2.0), "v", "(2,)"),
        (lambda: radius_of_curvature([0.1, 0.2, 0.3], [0.0, 0.1, 0.2], [1, 2], 2.0), "a", "(2,)"),
        (lambda: pitch_curve([0.0, 1.0], [0.1, 0.2, 0.3], 2.0), "s", "(3,)"),
        (lambda: roller_surface([0.0, 1.0], [0.1, 0.2, 0.3], [0.0] * 3, 2.0, 0.5), "s", "(3,)"),
        (lambda: flat_face_radius_of_curvature([0.0, 1.0], [0.0, 1.0, 2.0], 3.0), "a", "(3,)"),
    ],
)
def test_shape_mismatch_is_an_input_error(call, field, shapes):
    # Review finding 9: a bare numpy ValueError before; now the field and both shapes.
    with pytest.raises(InputError) as info:
        call()
    assert info.value.field == field
    assert shapes in str(info.value)
    assert "does not broadcast" in str(info.value)


def test_functional_core_still_broadcasts_compatible_shapes():
    phi = pressure_angle(np.zeros((3, 1)), np.zeros((1, 4)), 2.0)
    assert phi.shape == (3, 4)
    z = pitch_curve(np.zeros((2, 1)), np.zeros(5), 2.0)
    assert z.shape == (2, 5)
    np.testing.assert_allclose(z, 2.0j)


def test_design_check_limit_must_be_below_90_degrees():
    cam = TranslatingRoller(3.0, 0.5).profile(program(), n=90)
    with pytest.raises(InputError, match="90°") as info:
        cam.checks(max_pressure_angle=deg(100))
    assert info.value.field == "max_pressure_angle"
