"""Audit: cam motion laws, programs and radial-cam geometry vs Norton ch. 8.

Expected values are computed here: the closed forms of Norton sec. 8.3
(eq. 8.3 simple harmonic, 8.6 cycloidal, 8.24/8.25 3-4-5 and 4-5-6-7
polynomials), numerical integration of j → a → v → s for the piecewise laws
(modified trapezoid, modified sine: Norton eq. 8.15/8.16 define them through
their acceleration), and the cam geometry measured on the sampled curves
themselves (tangent of the pitch polyline for the pressure angle, the circle
through three neighbouring points for the radius of curvature) — not from the
formulas machdyn uses.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import cams
from machdyn.cams import laws

PI = np.pi


def closed_form(name, x, h, beta):
    """Norton sec. 8.3, written out here."""
    if name == "simple_harmonic":  # eq. 8.3
        return (
            h / 2 * (1 - np.cos(PI * x)),
            PI * h / (2 * beta) * np.sin(PI * x),
            PI**2 * h / (2 * beta**2) * np.cos(PI * x),
            -(PI**3) * h / (2 * beta**3) * np.sin(PI * x),
        )
    if name == "cycloidal":  # eq. 8.6
        return (
            h * (x - np.sin(2 * PI * x) / (2 * PI)),
            h / beta * (1 - np.cos(2 * PI * x)),
            2 * PI * h / beta**2 * np.sin(2 * PI * x),
            4 * PI**2 * h / beta**3 * np.cos(2 * PI * x),
        )
    if name == "poly345":  # eq. 8.24
        return (
            h * (10 * x**3 - 15 * x**4 + 6 * x**5),
            h / beta * (30 * x**2 - 60 * x**3 + 30 * x**4),
            h / beta**2 * (60 * x - 180 * x**2 + 120 * x**3),
            h / beta**3 * (60 - 360 * x + 360 * x**2),
        )
    if name == "poly4567":  # eq. 8.25
        return (
            h * (35 * x**4 - 84 * x**5 + 70 * x**6 - 20 * x**7),
            h / beta * (140 * x**3 - 420 * x**4 + 420 * x**5 - 140 * x**6),
            h / beta**2 * (420 * x**2 - 1680 * x**3 + 2100 * x**4 - 840 * x**5),
            h / beta**3 * (840 * x - 5040 * x**2 + 8400 * x**3 - 4200 * x**4),
        )
    raise KeyError(name)


@pytest.mark.parametrize("name", ["simple_harmonic", "cycloidal", "poly345", "poly4567"])
def test_laws_match_norton_closed_forms(name, rng):
    """s, v, a, j per radian of cam angle for random h, β (Norton eq. 8.3, 8.6, 8.24, 8.25)."""
    law = cams.get_law(name)
    for _ in range(5):
        h, beta = rng.uniform(0.1, 5), rng.uniform(0.2, 3)
        x = np.linspace(0, 1, 201)
        got = law(x, h, beta)
        for g, e in zip(got, closed_form(name, x, h, beta), strict=True):
            np.testing.assert_allclose(g, e, rtol=1e-10, atol=1e-10 * h / beta**3)


def _cumulative(y, x):
    """Cumulative trapezoid, starting at 0."""
    out = np.zeros_like(y)
    out[1:] = np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(x))
    return out


LAWS = [
    "simple_harmonic",
    "cycloidal",
    "poly345",
    "poly4567",
    "modified_trapezoid",
    "modified_sine",
    "constant_acceleration",
]


@pytest.mark.parametrize("name", LAWS)
def test_laws_are_consistent_derivatives_and_meet_rise_boundary_conditions(name):
    """Integrating machdyn's j gives its a, a gives v, v gives s (θ = βx, per radian);
    s(0) = 0, s(β) = h; the double-dwell conditions v = 0 at both ends, a = 0 at both
    ends except for the laws Norton lists as discontinuous (SHM, constant acceleration)."""
    h, beta = 1.7, 1.1
    x = np.linspace(0, 1, 40001)
    theta = beta * x
    s, v, a, j = cams.get_law(name)(x, h, beta)
    assert s[0] == pytest.approx(0, abs=1e-12) and s[-1] == pytest.approx(h, rel=1e-12)
    assert v[0] == pytest.approx(0, abs=1e-9) and v[-1] == pytest.approx(0, abs=1e-9)
    if name not in ("simple_harmonic", "constant_acceleration"):
        assert a[0] == pytest.approx(0, abs=1e-9) and a[-1] == pytest.approx(0, abs=1e-9)
        np.testing.assert_allclose(a[0] + _cumulative(j, theta), a, atol=2e-6 * np.abs(a).max())
    np.testing.assert_allclose(v[0] + _cumulative(a, theta), v, atol=1e-4 * np.abs(v).max())
    np.testing.assert_allclose(_cumulative(v, theta), s, atol=1e-7 * h)


def test_modified_sine_and_trapezoid_acceleration_shapes():
    """Norton Fig. 8-15/8-16: modified trapezoid has a constant-acceleration plateau over
    x ∈ [1/8, 3/8] at its peak Ca h/β² = 4.8881 h/β²; modified sine peaks at x = 1/8
    with 5.5280 h/β² (Norton Table 8-3); both antisymmetric about x = 1/2."""
    h, beta = 1.0, 1.0
    x = np.linspace(0, 1, 8001)
    a_trap = laws.modified_trapezoid(x, h, beta).a
    plateau = (x >= 0.125) & (x <= 0.375)
    np.testing.assert_allclose(a_trap[plateau], 4.8881, atol=1e-4)
    a_sine = laws.modified_sine(x, h, beta).a
    assert x[np.argmax(a_sine)] == pytest.approx(0.125, abs=1e-3)
    assert a_sine.max() == pytest.approx(5.5280, abs=1e-4)
    for a in (a_trap, a_sine):
        np.testing.assert_allclose(a, -a[::-1], atol=1e-9)


@pytest.mark.parametrize("name", LAWS)
def test_fall_mirrors_the_rise(name):
    """A fall of h over β is h − rise(x): s_f = h − s_r, v_f = −v_r, a_f = −a_r, j_f = −j_r."""
    x = np.linspace(0, 1, 101)
    h, beta = 2.0, 0.9
    rise = cams.get_law(name)(x, h, beta)
    fall = laws.fall(name, x, h, beta)
    np.testing.assert_allclose(fall[0], h - rise[0], atol=1e-12)
    for f, r in zip(fall[1:], rise[1:], strict=True):
        np.testing.assert_allclose(f, -r, atol=1e-9 * max(1.0, np.abs(r).max()))


def test_program_dwell_boundaries_and_time_units():
    """Notes review lecture 3 'DWELLS': a(0) = a(β) = v(0) = v(β) = 0; ∫a dθ = 0 and
    ∫v dθ = s(β) − s(0) over the rise; in time V = ω v, A = ω² a, J = ω³ j."""
    deg = np.radians
    program = cams.CamProgram(
        [
            cams.Segment("rise", deg(80), 1.5, "poly345"),
            cams.Segment("dwell", deg(100)),
            cams.Segment("fall", deg(70), 1.5, "modified_sine"),
            cams.Segment("dwell", deg(110)),
        ]
    )
    assert program.continuity().finite_jerk
    theta = np.linspace(0, deg(80), 20001)
    m = program.svaj(theta)
    assert m.s[0] == pytest.approx(0) and m.v[0] == pytest.approx(0) and m.a[0] == pytest.approx(0)
    assert np.trapezoid(m.a, theta) == pytest.approx(0, abs=1e-8)
    assert np.trapezoid(m.v, theta) == pytest.approx(1.5, rel=1e-8)
    d = program.svaj(np.radians([100.0, 200.0]))  # inside the high dwell, then the fall
    assert d.s[0] == pytest.approx(1.5) and d.v[0] == 0 and d.a[0] == 0
    omega = 2 * PI * 100 / 60  # 100 rpm
    t = program.sample(360).in_time(omega)
    base = program.sample(360)
    for name, k in (("v", 1), ("a", 2), ("j", 3)):
        np.testing.assert_allclose(getattr(t, name.upper()), omega**k * getattr(base, name))


# ---------------------------------------------------------------------------
# Geometry measured on the sampled curves
# ---------------------------------------------------------------------------


def _three_point_radius(z):
    """Signed radius of the circle through consecutive points (positive: turning left)."""
    p0, p1, p2 = np.roll(z, 1), z, np.roll(z, -1)
    a, b = p1 - p0, p2 - p1
    cross = (np.conj(a) * b).imag
    return np.abs(a) * np.abs(b) * np.abs(p2 - p0) / (2 * cross)


def _program():
    deg = np.radians
    return cams.CamProgram(
        [
            cams.Segment("rise", deg(90), 1.0, "cycloidal"),
            cams.Segment("dwell", deg(60)),
            cams.Segment("fall", deg(120), 1.0, "poly4567"),
            cams.Segment("dwell", deg(90)),
        ]
    )


@pytest.mark.parametrize("eccentricity", [0.0, 0.4, -0.4])
def test_translating_roller_geometry_from_the_curves(eccentricity):
    """Pitch curve: the follower's trace point (x = ε, y = √(Rp² − ε²) + s) seen from the
    turning cam. Pressure angle = angle between the follower axis (+y) and the pitch
    normal, measured from the polyline's tangent; ρ_pitch by three-point circles; the
    surface is the pitch curve moved Rf inward along that normal."""
    rp, rf = 3.0, 0.5
    cam = cams.TranslatingRoller(rp, rf, eccentricity).profile(_program(), n=7200)
    theta, s = cam.theta, cam.s
    d = np.sqrt(rp * rp - eccentricity**2)
    pitch = (eccentricity + 1j * (d + s)) * np.exp(-1j * theta)  # cam turns CCW
    np.testing.assert_allclose(cam.pitch, pitch, atol=1e-12)
    # tangent of the pitch polyline, turned back into the fixed frame
    tangent = (np.roll(pitch, -1) - np.roll(pitch, 1)) * np.exp(1j * theta)
    normal = 1j * tangent  # traced clockwise in its own frame: left of the tangent is outward
    phi = np.angle(normal / 1j)  # from the follower axis +y
    np.testing.assert_allclose(cam.pressure_angle, phi, atol=2e-6)
    # notes' final exam 9 formula at one sample as a spot check
    k = 500
    assert cam.pressure_angle[k] == pytest.approx(
        np.arctan((cam.v[k] - eccentricity) / (cam.s[k] + d)), abs=1e-12
    )
    rho = -_three_point_radius(pitch)  # convex (turning right when traced CW) is positive
    finite = np.abs(cam.rho_pitch) < 50
    np.testing.assert_allclose(cam.rho_pitch[finite], rho[finite], rtol=1e-3)
    gap = np.abs(cam.surface - cam.pitch)
    np.testing.assert_allclose(gap, rf, rtol=1e-12)
    out_dir = (cam.pitch - cam.surface) * np.exp(1j * theta)
    np.testing.assert_allclose(np.angle(out_dir / normal), 0, atol=2e-6)


def test_flat_face_follower_curvature_and_contact():
    """Norton eq. 8.27: ρ = Rb + s + a; the contact runs at x = v on the face (eq. 8.28);
    checked on the surface polyline itself."""
    rb = 4.0
    cam = cams.TranslatingFlatFace(rb).profile(_program(), n=7200)
    rho = -_three_point_radius(cam.surface)
    np.testing.assert_allclose(cam.rho_surface, rb + cam.s + cam.a, rtol=1e-12)
    np.testing.assert_allclose(rho, cam.rho_surface, rtol=1e-3)
    # the face y = Rb + s touches the cam at the sample: surface point in the fixed frame
    fixed = cam.surface * np.exp(1j * cam.theta)
    np.testing.assert_allclose(fixed.imag, rb + cam.s, atol=1e-12)
    np.testing.assert_allclose(fixed.real, cam.v, atol=1e-12)
    assert cam.face_width == pytest.approx(cam.v.max() - cam.v.min(), rel=1e-9)


def test_sizing_is_the_smallest_circle_meeting_the_rules():
    """size_roller: at the returned Rp max |φ| = 30° (the rule binds) and 0.1 % smaller
    breaks it; size_flat_face: Rb + min(s + a) = ρmin (Norton eq. 8.29)."""
    program = _program()
    for eps in (0.0, 0.3):
        sized = cams.size_roller(program, roller_radius=0.25, eccentricity=eps)
        m = program.sample(3600)

        def max_phi(rp, eps=eps, m=m):
            d = np.sqrt(rp * rp - eps * eps)
            return np.max(np.abs(np.arctan((m.v - eps) / (m.s + d))))

        if sized.governed_by == "pressure angle":
            assert max_phi(sized.prime_radius) == pytest.approx(np.radians(30), abs=1e-9)
            assert max_phi(0.999 * sized.prime_radius) > np.radians(30)
    flat = cams.size_flat_face(program, min_radius_of_curvature=0.5)
    m = program.sample(3600)
    assert flat.base_radius + np.min(m.s + m.a) == pytest.approx(0.5)


@pytest.mark.parametrize("side", ["right", "left"])
def test_oscillating_roller_geometry_from_the_curves(side):
    """Oscillating roller (Norton sec. 8.6 effective four-bar): the roller centre is
    pivot + L e^{jγ} with γ = γ0 ± s, |pivot| = C and |roller − O| = Rp at s = 0;
    the pressure angle is the angle between the pitch curve's normal and the roller
    centre's direction of travel (⟂ to the arm), measured here on the polyline; ρ by
    three-point circles; the surface lies Rf inside the pitch curve."""
    deg = np.radians
    program = cams.CamProgram(
        [
            cams.Segment("rise", deg(100), deg(15), "cycloidal"),
            cams.Segment("dwell", deg(80)),
            cams.Segment("fall", deg(100), deg(15), "poly345"),
            cams.Segment("dwell", deg(80)),
        ]
    )
    rp, rf, c, arm = 2.5, 0.4, 4.0, 3.2
    follower = cams.OscillatingRoller(rp, rf, pivot_distance=c, arm_length=arm, pivot_side=side)
    cam = follower.profile(program, n=7200)
    theta = cam.theta
    pivot = follower.pivot
    assert abs(pivot) == pytest.approx(c)
    fixed = cam.pitch * np.exp(1j * theta)  # roller centre in the fixed frame
    np.testing.assert_allclose(np.abs(fixed - pivot), arm, rtol=1e-12)
    assert abs(fixed[cam.s == 0][0]) == pytest.approx(rp)
    swing = np.unwrap(np.angle(fixed - pivot))
    np.testing.assert_allclose(np.abs(swing - swing[0]), cam.s, atol=1e-12)
    tangent = (np.roll(cam.pitch, -1) - np.roll(cam.pitch, 1)) * np.exp(1j * theta)
    normal = 1j * tangent / np.abs(tangent)
    travel = 1j * (fixed - pivot) / arm  # ⟂ to the arm
    cos_phi = np.abs((normal * np.conj(travel)).real)
    np.testing.assert_allclose(np.abs(np.cos(cam.pressure_angle)), cos_phi, atol=1e-5)
    rho = -_three_point_radius(cam.pitch)
    finite = np.abs(cam.rho_pitch) < 50
    np.testing.assert_allclose(cam.rho_pitch[finite], rho[finite], rtol=1e-3)
    np.testing.assert_allclose(np.abs(cam.surface - cam.pitch), rf, rtol=1e-12)


def test_single_dwell_polynomial_from_boundary_conditions():
    """Norton sec. 8.5 single-dwell rise-fall: s = v = a = 0 at both ends and s(½) = h
    give the 3-4-5-6 polynomial s = h(64x³ − 192x⁴ + 192x⁵ − 64x⁶) (Norton eq. 8.26);
    as a 'rise' of net lift 0 it closes a program with finite jerk."""
    h, beta = 1.3, np.radians(180)
    law = cams.polynomial_law(start={"v": 0, "a": 0}, end={"v": 0, "a": 0}, points=[(0.5, "s", h)])
    x = np.linspace(0, 1, 101)
    s, v, a, _ = law(x, 0.0, beta)
    np.testing.assert_allclose(s, h * (64 * x**3 - 192 * x**4 + 192 * x**5 - 64 * x**6), atol=1e-12)
    np.testing.assert_allclose(
        v, h / beta * (192 * x**2 - 768 * x**3 + 960 * x**4 - 384 * x**5), atol=1e-11
    )
    np.testing.assert_allclose(
        a, h / beta**2 * (384 * x - 2304 * x**2 + 3840 * x**3 - 1920 * x**4), atol=1e-10
    )
    program = cams.CamProgram([cams.Segment("rise", beta, 0.0, law), cams.Segment("dwell", beta)])
    assert program.continuity().finite_jerk
    assert program.svaj(np.radians(90.0)).s == pytest.approx(h)
