"""Audit 7: cam programs and radial-cam geometry against derivations written here.

* Random programs of every law the library offers (the named laws, SCCA with
  random b, c, d, polynomial laws from random boundary conditions): s, v, a, j
  are checked by central differences of s in θ, the lift of each segment by
  its end levels, and the continuity report against a jump scan done here
  (values just before and after every join and every law's interior jump).
* Peak factors of Norton Table 8-3 (C_v, C_a, C_j) for the named laws.
* Translating roller with an offset of either sign, and the notes' final-exam
  pressure angle: the trace point is placed here at ``(ε, √(Rp² − ε²) + s)``
  with the cam turning counter-clockwise, the pitch curve is that point seen
  from the cam, the pressure angle is the angle between the pitch curve's
  normal (by differences) and the follower's +y motion, ρ the radius of the
  circle through three neighbouring pitch points.
* Flat-faced follower: the cam is the envelope of the face lines, whose
  radius of curvature is measured here on the sampled surface.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import cams
from machdyn.errors import MachdynError

NAMED = [n for n in cams.LAW_NAMES if n not in ("dwell", "scca")]


def random_law(rng):
    pick = rng.integers(0, 3)
    if pick == 0:
        return cams.get_law(str(rng.choice(NAMED)))
    if pick == 1:
        b, c = rng.uniform(0, 1, 2)
        if b + c > 1:
            b, c = 1 - b, 1 - c
        return cams.get_law("scca", b=b, c=c, d=1 - b - c)
    start = {"v": 0.0, "a": 0.0}
    end = {"v": 0.0, "a": 0.0}
    if rng.random() < 0.5:
        start["j"] = float(rng.uniform(-50, 50))
    # s at x = 0.3 fixes the x³(1 − x)³ term the end conditions leave free
    return cams.polynomial_law(
        start=start, end=end, points=[(0.3, "s", float(rng.uniform(0.1, 0.3)))]
    )


def random_program(rng):
    pieces = int(rng.integers(2, 6))
    betas = rng.dirichlet(np.ones(2 * pieces)) * 2 * np.pi
    segments, level = [], 0.0
    lifts = rng.uniform(0.2, 2.0, pieces)
    for i in range(pieces):
        segments.append(cams.Segment("rise", betas[2 * i], lifts[i], random_law(rng)))
        if rng.random() < 0.5:
            segments.append(cams.Segment("dwell", betas[2 * i + 1]))
        else:  # a fall then straight on (no dwell)
            segments[-1] = cams.Segment("rise", betas[2 * i] + betas[2 * i + 1], lifts[i],
                                        segments[-1].law)  # fmt: skip
        level += lifts[i]
    # one fall back to the start, taking some of the angles
    fall_beta = segments[-1].beta / 2
    last = segments[-1]
    segments[-1] = cams.Segment(last.motion, last.beta - fall_beta, last.h, last.law)
    segments.append(cams.Segment("fall", fall_beta, level, random_law(rng)))
    return cams.CamProgram(segments)


@pytest.mark.parametrize("seed", range(4))
def test_random_programs_svaj_by_differences_and_continuity_by_a_jump_scan(seed):
    rng = np.random.default_rng(seed)
    for _ in range(8):
        try:
            program = random_program(rng)
        except MachdynError:
            continue  # e.g. a polynomial that dips below the start: refused by name
        starts = program.starts
        ends = np.append(starts[1:], 2 * np.pi)
        betas = ends - starts
        # interior samples of each segment (away from joins)
        for k, seg in enumerate(program.segments):
            x = np.linspace(0.05, 0.95, 37)
            inner = [*seg.law.interior_jumps, -9.0]
            x = x[np.all(np.abs(x[:, None] - np.array(inner)) > 0.02, axis=1)]
            theta = starts[k] + x * betas[k]
            h = 1e-6 * betas[k]
            m, p, q = program.svaj(theta), program.svaj(theta + h), program.svaj(theta - h)
            scale = lambda y: np.abs(y).max() + 1.0  # noqa: E731
            np.testing.assert_allclose(m.v, (p.s - q.s) / (2 * h), atol=1e-6 * scale(m.v))
            np.testing.assert_allclose(m.a, (p.v - q.v) / (2 * h), atol=1e-6 * scale(m.a))
            np.testing.assert_allclose(m.j, (p.a - q.a) / (2 * h), atol=1e-5 * scale(m.j))
            # the segment's lift: s at its end minus s at its start
            s_end = program.svaj(ends[k] - 1e-12).s if k < len(betas) - 1 else None
            if s_end is not None:
                lift = float(s_end - program.svaj(starts[k]).s)
                assert lift == pytest.approx(seg.signed_h, abs=1e-9)
        # jump scan at every join (and the wrap), and at mid-segment (where a constant
        # acceleration or an SCCA law without its last zone flips the acceleration)
        found = set()
        sizes = []
        for k in range(len(starts)):
            m = program.svaj(starts[k] + np.linspace(0.0, 1.0, 201)[:-1] * betas[k])
            sizes.append({n: np.abs(getattr(m, n)).max() for n in ("s", "v", "a")})
        for k in range(len(starts)):
            nxt = (k + 1) % len(starts)
            at = ends[k] % (2 * np.pi)
            tiny = 1e-11 * betas[k]
            before, after = program.svaj(ends[k] - tiny), program.svaj(at + tiny)
            for name in ("s", "v", "a"):
                left, right = float(getattr(before, name)), float(getattr(after, name))
                size = max(sizes[k][name], sizes[nxt][name], 1e-300)
                if abs(right - left) > 1e-6 * size:
                    found.add((round(at, 6) % round(2 * np.pi, 6), name))
            mid = starts[k] + 0.5 * betas[k]
            left, right = program.svaj(mid - tiny).a, program.svaj(mid + tiny).a
            if abs(right - left) > 1e-6 * max(sizes[k]["a"], 1e-300):
                found.add((round(mid, 6), "a"))
        report = {
            (round(d.theta, 6) % round(2 * np.pi, 6), d.quantity)
            for d in program.continuity().discontinuities
        }
        assert report == found


def test_peak_factors_of_norton_table_8_3():
    """C_v, C_a, C_j (h = β = 1) of Norton Table 8-3 (SHM's jerk is π³/2 here: finite
    inside the rise; its jumps at the ends are what the continuity report names)."""
    x = np.linspace(0, 1, 400001)
    table = {
        "constant_acceleration": (2.0, 4.0, None),
        "modified_trapezoid": (2.0, 4.888, 61.43),
        "simple_harmonic": (1.571, 4.945, None),
        "modified_sine": (1.760, 5.528, 69.47),
        "poly345": (1.875, 5.777, 60.0),
        "cycloidal": (2.0, 6.283, 39.48),
        "poly4567": (2.188, 7.526, 52.5),
    }
    for name, (cv, ca, cj) in table.items():
        _, v, a, j = cams.get_law(name)(x, 1.0, 1.0)
        assert v.max() == pytest.approx(cv, abs=2e-3)
        assert np.abs(a).max() == pytest.approx(ca, rel=3e-3)
        if cj is not None:
            assert np.abs(j).max() == pytest.approx(cj, rel=2e-3)


def _three_point_radius(z):
    """Signed radius of the circle through neighbouring points (+: turning left)."""
    a, b, c = np.roll(z, 1), z, np.roll(z, -1)
    ab, bc, ca = np.abs(b - a), np.abs(c - b), np.abs(a - c)
    cross = ((b - a).conj() * (c - b)).imag
    with np.errstate(divide="ignore"):
        return ab * bc * ca / (2 * cross)


@pytest.mark.parametrize("eps", [-0.6, -0.2, 0.0, 0.35, 0.8])
def test_translating_roller_with_an_offset_of_either_sign(eps):
    deg = np.radians
    program = cams.CamProgram(
        [
            cams.Segment("rise", deg(80), 1.2, "poly345"),
            cams.Segment("dwell", deg(70)),
            cams.Segment("fall", deg(110), 1.2, "modified_sine"),
            cams.Segment("dwell", deg(100)),
        ]
    )
    rp, rf = 3.0, 0.6
    cam = cams.TranslatingRoller(prime_radius=rp, roller_radius=rf, eccentricity=eps).profile(
        program, n=7200
    )
    theta, s = cam.theta, cam.s
    trace = eps + 1j * (np.sqrt(rp * rp - eps * eps) + s)  # fixed frame
    pitch = trace * np.exp(-1j * theta)  # the cam turns CCW: seen from the cam
    np.testing.assert_allclose(cam.pitch, pitch, atol=1e-12)
    step = theta[1] - theta[0]
    tangent_cam = (np.roll(pitch, -1) - np.roll(pitch, 1)) / (2 * step)
    tangent = tangent_cam * np.exp(1j * theta)  # back in the fixed frame
    normal = 1j * tangent  # outward for a CCW-traced (seen from the cam: CW) curve
    # pressure angle: between the normal line and the +y follower motion; positive when
    # the normal leans to −x (the formula's sign: v > ε on the rise)
    phi = np.arctan2(-normal.real, normal.imag)
    phi = (phi + np.pi / 2) % np.pi - np.pi / 2
    np.testing.assert_allclose(cam.pressure_angle, phi, atol=2e-6)
    rho = -_three_point_radius(pitch)
    # away from the joins, where the three points straddle a jump of the jerk
    joins = np.searchsorted(theta, program.starts)
    near = np.zeros(theta.size, bool)
    for i in joins:
        near[np.arange(i - 2, i + 3) % theta.size] = True
    finite = (np.abs(cam.rho_pitch) < 100) & ~near
    np.testing.assert_allclose(cam.rho_pitch[finite], rho[finite], rtol=2e-4, atol=1e-6)
    np.testing.assert_allclose(np.abs(cam.surface - cam.pitch), rf, rtol=1e-12)


def test_notes_final_exam_pressure_angle():
    """Final exam problem 9: s = 0.4, v = 1.2, Rp = 2.1, ε = 0.1: the normal of the pitch
    curve at the trace point, built here, leans arctan(1.1 / (0.4 + √4.4)) = 23.77°."""
    s, v, rp, eps = 0.4, 1.2, 2.1, 0.1
    tangent = (np.sqrt(rp**2 - eps**2) + s) + 1j * (v - eps)  # d/dθ of the point seen from
    # the cam, rotated back: (j v) − j (ε + j(d + s))
    expected = np.degrees(np.arctan2(tangent.imag, tangent.real))
    assert expected == pytest.approx(23.77, abs=0.005)
    assert np.degrees(cams.pressure_angle(s, v, rp, eps)) == pytest.approx(expected, abs=1e-9)


def test_flat_face_cam_is_the_envelope_and_its_curvature_is_rb_plus_s_plus_a():
    deg = np.radians
    program = cams.CamProgram(
        [
            cams.Segment("rise", deg(120), 0.8, "cycloidal"),
            cams.Segment("dwell", deg(40)),
            cams.Segment("fall", deg(120), 0.8, "poly4567"),
            cams.Segment("dwell", deg(80)),
        ]
    )
    rb, eps = 2.5, 0.4
    cam = cams.TranslatingFlatFace(base_radius=rb, eccentricity=eps).profile(program, n=7200)
    # Every surface point lies on the face line of its angle, y = Rb + s in the fixed frame,
    # and no surface point lies beyond any face line (the envelope).
    fixed = cam.surface * np.exp(1j * cam.theta)
    np.testing.assert_allclose(fixed.imag, rb + cam.s, atol=1e-12)
    sample = cam.surface[::40]
    for k in range(0, cam.theta.size, 97):
        height = (sample * np.exp(1j * cam.theta[k])).imag
        assert height.max() <= rb + cam.s[k] + 1e-9
    rho = -_three_point_radius(cam.surface)
    joins = np.searchsorted(cam.theta, program.starts)  # the jerk jumps there
    away = np.ones(cam.theta.size, bool)
    for i in joins:
        away[np.arange(i - 2, i + 3) % cam.theta.size] = False
    np.testing.assert_allclose(cam.rho_surface[away], rho[away], rtol=1e-4)
    np.testing.assert_allclose(cam.rho_surface, rb + cam.s + cam.a, rtol=1e-12)
    np.testing.assert_allclose(cam.face_position, cam.v - eps, atol=1e-12)


def test_single_dwell_polynomial_is_continuous_whatever_its_angle():
    """Norton's single-dwell rise-fall (s = v = a = 0 at both ends, s(½) = 1: the 3-4-5-6
    polynomial) meets its dwell with a = 0 on both sides, so the program has finite jerk.
    Over 50° the polynomial's a(1) is 1.1e-12 from round-off, which the report took for a
    jump ("FAILS the finite-jerk rule") while the threshold was 1e-12 absolute."""
    law = cams.polynomial_law(start={"v": 0, "a": 0}, end={"v": 0, "a": 0}, points=[(0.5, "s", 1)])
    x = np.array([0.0, 0.25, 0.5, 1.0])
    np.testing.assert_allclose(law(x, 0.0, 1.0).s, 64 * x**3 - 192 * x**4 + 192 * x**5 - 64 * x**6,
                               atol=1e-12)  # fmt: skip
    for beta in range(20, 181, 5):
        program = cams.CamProgram(
            [
                cams.Segment("rise", np.radians(beta), 0.0, law),
                cams.Segment("dwell", np.radians(360 - beta)),
            ]
        )
        assert program.continuity().ok, beta


def test_a_polynomial_its_conditions_do_not_fix_is_refused_when_it_is_made():
    """v = a = 0 at both ends and a condition on v at x = ½: x³(1 − x)³ meets all the
    homogeneous ones, so no single polynomial is named. It was accepted and refused only
    when the cam was sampled, naming 'conditions' (not an argument)."""
    with pytest.raises(MachdynError) as info:
        cams.polynomial_law(start={"v": 0, "a": 0}, end={"v": 0, "a": 0}, points=[(0.5, "v", 1.5)])
    assert info.value.field == "points"
    with pytest.raises(MachdynError) as info:
        cams.polynomial_law(start={"v": 0, "a": 0}, points=[(0.0, "v", 1.0)])  # v(0) twice
    assert info.value.field == "points"
