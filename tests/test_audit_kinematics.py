"""Audit: four-bar and slider-crank kinematics against independent derivations.

Every expected value here is computed in this file from the notes' vector loops
(review lecture 1, "FOURBAR POSITION / VELOCITY / ACCELERATION ANALYSIS";
review lecture 3, "SLIDER-CRANK" with its jerk equation) or from Norton,
*Design of Machinery*, ch. 4, 6, 7 — by a different route than machdyn takes:
positions by intersecting two circles, rates by a dense ``np.linalg.solve`` of
the differentiated loop (machdyn uses closed forms), and time finite
differences of the positions. Inputs are seeded random linkages of every
Barker class, both forms (circuits) and, for GRCR/GRRC, both branches.
"""

from __future__ import annotations

import numpy as np
import pytest

import machdyn
from machdyn import FourBar, InvertedSliderCrank, SliderCrank

TWO_PI = 2.0 * np.pi


def wrap(x):
    """Angle wrapped to (−π, π]."""
    return np.angle(np.exp(1j * np.asarray(x, dtype=float)))


def angle_error(x, y):
    return np.abs(wrap(np.asarray(x) - np.asarray(y)))


# ---------------------------------------------------------------------------
# Independent four-bar: circle intersection + dense linear solves
# ---------------------------------------------------------------------------


def fourbar_reference(r1, r2, r3, r4, t2, sign12):
    """θ3, θ4 of the pose whose φ12 = θ4 − θ3 has sign ``sign12`` (two circles: A, O4)."""
    a, b, c, d = r2, r3, r4, r1
    A = a * np.exp(1j * t2)
    f = abs(d - A)
    u = (d - A) / f
    x = (b * b - c * c + f * f) / (2 * f)
    h = np.sqrt(max(b * b - x * x, 0.0))
    for s in (1.0, -1.0):
        B = A + u * (x + 1j * s * h)
        t3, t4 = np.angle(B - A), np.angle(B - d)
        if np.sign(wrap(t4 - t3)) == sign12:
            return t3, t4
    if h < 1e-6 * b:  # a toggle of links 3 and 4: the two assemblies coincide
        return t3, t4
    raise AssertionError("no pose of that sign")


def fourbar_rates(r1, r2, r3, r4, t2, t3, t4, w2, a2, j2, p=0.0, delta=0.0):
    """ω, α, jerk of links 3, 4 and the coupler point by np.linalg.solve of the notes' loop.

    Loop ``a e^{jθ2} + b e^{jθ3} − c e^{jθ4} − d = 0`` differentiated once, twice and
    three times (``d/dt[(jα − ω²) e^{jθ}] = (jJ − 3αω − jω³) e^{jθ}``).
    """
    a, b, c = r2, r3, r4
    e2, e3, e4 = np.exp(1j * t2), np.exp(1j * t3), np.exp(1j * t4)
    # unknown x3, x4 enter as j x3 b e3 − j x4 c e4
    M = np.array(
        [[(1j * b * e3).real, (-1j * c * e4).real], [(1j * b * e3).imag, (-1j * c * e4).imag]]
    )

    def solve(known):
        return np.linalg.solve(M, [-known.real, -known.imag])

    w3, w4 = solve(1j * w2 * a * e2)
    al3, al4 = solve(a * (1j * a2 - w2**2) * e2 - b * w3**2 * e3 + c * w4**2 * e4)

    def jk(r, w, al, j, e):
        return r * (1j * j - 3 * al * w - 1j * w**3) * e

    j3, j4 = solve(jk(a, w2, a2, j2, e2) + jk(b, w3, al3, 0.0, e3) - jk(c, w4, al4, 0.0, e4))
    ep = np.exp(1j * (t3 + delta))
    P = a * e2 + p * ep
    VP = 1j * w2 * a * e2 + 1j * w3 * p * ep
    AP = (1j * a2 - w2**2) * a * e2 + (1j * al3 - w3**2) * p * ep
    JP = jk(a, w2, a2, j2, e2) + jk(p, w3, al3, j3, ep)
    return dict(
        omega3=w3,
        omega4=w4,
        alpha3=al3,
        alpha4=al4,
        jerk3=j3,
        jerk4=j4,
        coupler=P,
        coupler_velocity=VP,
        coupler_acceleration=AP,
        coupler_jerk=JP,
    )


def random_fourbars(rng, n):
    """``n`` assemblable random four-bars with a coupler point (seeded)."""
    out = []
    while len(out) < n:
        lengths = rng.uniform(0.5, 10.0, 4)
        try:
            fb = FourBar(*lengths, coupler=(rng.uniform(0, 5), rng.uniform(-np.pi, np.pi)))
        except machdyn.AssemblyError:
            continue
        out.append(fb)
    return out


def pick_pose(fb, rng):
    """A random reachable (θ2, form, branch, sign of φ12) of ``fb``."""
    for _ in range(200):
        t2 = rng.uniform(0, TWO_PI)
        f = abs(fb.r1 - fb.r2 * np.exp(1j * t2))
        if not (abs(fb.r3 - fb.r4) + 1e-6 < f < fb.r3 + fb.r4 - 1e-6):
            continue
        if fb.form_rule == "phi34":
            form = 1 if wrap(t2) > 0 else 2
            branch = int(rng.choice([1, -1]))
            return t2, form, branch, branch
        form = int(rng.integers(1, 3))
        return t2, form, None, (1 if form == 1 else -1)
    return None


def test_fourbar_random_poses_match_circle_intersection_and_linear_solves(rng, backend):
    """Norton eq. 4.10/6.18/7.12 by another route: 400 random linkages × both circuits."""
    checked = set()
    for fb in random_fourbars(rng, 400):
        pose = pick_pose(fb, rng)
        if pose is None:
            continue
        t2, form, branch, sign12 = pose
        w2, a2, j2 = rng.normal(size=3) * 3
        m = fb.solve(np.array([t2]), w2, a2, form=form, branch=branch, jerk2=j2)
        assert m.ok[0], (fb, t2, m.reason)
        t3, t4 = fourbar_reference(fb.r1, fb.r2, fb.r3, fb.r4, t2, sign12)
        assert angle_error(m.theta3[0], t3) < 1e-9
        assert angle_error(m.theta4[0], t4) < 1e-9
        p, delta = fb.coupler
        ref = fourbar_rates(fb.r1, fb.r2, fb.r3, fb.r4, t2, t3, t4, w2, a2, j2, p, delta)
        for name, value in ref.items():
            got = getattr(m, name)[0]
            assert abs(got - value) <= 1e-7 * max(1.0, abs(value)), (fb, name, got, value)
        checked.add((fb.barker_class, form))
    # every Grashof and non-Grashof class, in both forms, was exercised
    for code in ("GCCC", "GCRR", "GRCR", "GRRC", "RRR1", "RRR2", "RRR3", "RRR4"):
        assert (code, 1) in checked and (code, 2) in checked, code


def test_fourbar_rates_equal_time_finite_differences(rng):
    """Five-point central differences of θ3(t), θ4(t), P(t) with θ2(t) a cubic in time."""
    h = 1e-3
    steps = np.array([-2, -1, 0, 1, 2]) * h
    for fb in random_fourbars(rng, 40):
        pose = pick_pose(fb, rng)
        if pose is None:
            continue
        t2, form, branch, _ = pose
        w2, a2, j2 = rng.normal(size=3)
        theta2 = t2 + w2 * steps + a2 * steps**2 / 2 + j2 * steps**3 / 6
        pos = fb.solve(theta2, form=form, branch=branch, order=0)
        if not pos.assembled.all():
            continue
        m = fb.solve(t2, w2, a2, form=form, branch=branch, jerk2=j2)
        for name, rate in (("theta3", "omega3"), ("theta4", "omega4")):
            x = np.unwrap(getattr(pos, name))
            d1 = (x[0] - 8 * x[1] + 8 * x[3] - x[4]) / (12 * h)
            d2 = (-x[0] + 16 * x[1] - 30 * x[2] + 16 * x[3] - x[4]) / (12 * h * h)
            assert d1 == pytest.approx(float(getattr(m, rate)), rel=1e-5, abs=1e-5)
            acc = "alpha" + rate[-1]
            assert d2 == pytest.approx(float(getattr(m, acc)), rel=1e-4, abs=1e-3)
        P = pos.coupler
        vP = (P[0] - 8 * P[1] + 8 * P[3] - P[4]) / (12 * h)
        assert abs(vP - m.coupler_velocity) <= 1e-5 * max(1.0, abs(m.coupler_velocity))


def test_notes_mechanical_advantage_formula_and_instant_centres(rng):
    """Review lecture 2: MA = r_in ω2/(r_out ω4) = r_in R4 sin φ12 / (r_out R2 sin φ14),
    and Kennedy's I13 (O2A ∩ O4B), I24 (ground line ∩ AB) computed here by line meets."""
    for fb in random_fourbars(rng, 120):
        pose = pick_pose(fb, rng)
        if pose is None:
            continue
        t2, form, branch, sign12 = pose
        t3, t4 = fourbar_reference(fb.r1, fb.r2, fb.r3, fb.r4, t2, sign12)
        phi12, phi14 = t4 - t3, np.pi - t2 + t3
        if abs(np.sin(phi14)) < 1e-3:
            continue  # output at rest: MA unbounded
        r_in, r_out = rng.uniform(0.5, 3, 2)
        expected = r_in * fb.r4 * np.sin(phi12) / (r_out * fb.r2 * np.sin(phi14))
        for method in ("power", "instant_centres"):
            ma = fb.mechanical_advantage(t2, r_in, r_out, form, method=method, branch=branch)
            assert float(ma) == pytest.approx(expected, rel=1e-7), (fb, method)
        A = fb.r2 * np.exp(1j * t2)
        B = fb.r1 + fb.r4 * np.exp(1j * t4)
        ics = fb.instant_centres(t2, form, branch=branch)

        def meet(p1, u1, p2, u2):
            s, _ = np.linalg.solve(
                [[u1.real, -u2.real], [u1.imag, -u2.imag]], [(p2 - p1).real, (p2 - p1).imag]
            )
            return p1 + s * u1

        if abs(np.sin(t2 - t4)) > 1e-3:
            I13 = meet(0j, A, fb.r1 + 0j, B - fb.r1)
            assert abs(complex(ics[1, 3].point) - I13) <= 1e-7 * max(1.0, abs(I13))
        if abs(np.sin(t3)) > 1e-3:
            I24 = meet(0j, 1 + 0j, A, B - A)
            assert abs(complex(ics[2, 4].point) - I24) <= 1e-7 * max(1.0, abs(I24))
        assert complex(ics[2, 3].point) == pytest.approx(A)
        assert complex(ics[3, 4].point) == pytest.approx(B)


# ---------------------------------------------------------------------------
# Slider-crank: the notes' loop a e^{jθ2} − b e^{jθ3} − jc − d = 0
# ---------------------------------------------------------------------------


def slidercrank_reference(a, b, c, t2, w2, a2, j2, form):
    """The notes' slider-crank and its three derivatives, by np.linalg.solve."""
    s3 = (a * np.sin(t2) - c) / b
    c3 = np.sqrt(1 - s3 * s3) * (-1.0 if form == 1 else 1.0)  # form 1: slider right of A
    e2, e3 = np.exp(1j * t2), c3 + 1j * s3
    d = a * np.cos(t2) - b * c3
    # unknowns x3 (rod), xd (slider): −j b x3 e3 − xd = −known
    M = np.array([[(-1j * b * e3).real, -1.0], [(-1j * b * e3).imag, 0.0]])

    def solve(known):
        return np.linalg.solve(M, [-known.real, -known.imag])

    w3, dd = solve(a * 1j * w2 * e2)
    al3, ddd = solve(a * (1j * a2 - w2**2) * e2 + b * w3**2 * e3)
    j3, dddd = solve(
        a * (1j * j2 - 3 * a2 * w2 - 1j * w2**3) * e2 - b * (-3 * al3 * w3 - 1j * w3**3) * e3
    )
    return dict(
        theta3=np.angle(e3),
        d=d,
        omega3=w3,
        d_dot=dd,
        alpha3=al3,
        d_ddot=ddd,
        jerk3=j3,
        d_dddot=dddd,
    )


def test_slidercrank_random_matches_notes_loop(rng):
    """Review lecture 3 'SLIDER-CRANK' loop, both forms, offsets of either sign."""
    n = 0
    while n < 300:
        a, b = rng.uniform(0.5, 8, 2)
        c = rng.uniform(-1, 1) * (a + b) * 0.9
        sc = SliderCrank(a, b, c)
        t2 = rng.uniform(0, TWO_PI)
        s3 = (a * np.sin(t2) - c) / b
        if abs(s3) > 1 - 1e-6:
            continue
        form = int(rng.integers(1, 3))
        w2, a2, j2 = rng.normal(size=3) * 3
        m = sc.solve(t2, w2, a2, form=form, jerk2=j2)
        ref = slidercrank_reference(a, b, c, t2, w2, a2, j2, form)
        assert angle_error(m.theta3, ref.pop("theta3")) < 1e-9
        for name, value in ref.items():
            got = float(getattr(m, name))
            assert got == pytest.approx(value, rel=1e-7, abs=1e-7 * (a + b)), (sc, name)
        assert complex(m.B) == pytest.approx(ref["d"] + 1j * c)
        n += 1


def test_slidercrank_stroke_and_mechanical_advantage(rng):
    """Stroke = the crank/rod collinear positions (Norton sec. 4.6); MA = r_in ω2 / ḋ;
    I13 on O2A and on the normal to the slide through B; I24 on the normal through O2
    (the notes: "connect I.C. at ∞ to a finite point by a line normal to the plane of slip")."""
    for _ in range(60):
        a = rng.uniform(0.5, 3)
        b = a + rng.uniform(0.5, 6)
        c = rng.uniform(-1, 1) * (b - a) * 0.9
        sc = SliderCrank(a, b, c)
        lo, hi = sc.stroke(form=1)
        far, near = np.sqrt((a + b) ** 2 - c * c), np.sqrt((b - a) ** 2 - c * c)
        assert (lo, hi) == pytest.approx((near, far))
        t = np.linspace(0, TWO_PI, 20001)
        d = sc.solve(t, form=1).d
        assert d.min() >= lo - 1e-9 and d.max() <= hi + 1e-9
        assert d.max() == pytest.approx(hi, abs=1e-6) and d.min() == pytest.approx(lo, abs=1e-6)
        t2 = rng.uniform(0, TWO_PI)
        ref = slidercrank_reference(a, b, c, t2, 1.0, 0.0, 0.0, 1)
        if abs(ref["d_dot"]) < 1e-3:
            continue
        r_in = rng.uniform(0.5, 2)
        for method in ("power", "instant_centres"):
            ma = sc.mechanical_advantage(t2, r_in, method=method)
            assert float(ma) == pytest.approx(r_in / ref["d_dot"], rel=1e-7)
        ics = sc.instant_centres(t2)
        A = a * np.exp(1j * t2)
        B = ref["d"] + 1j * c
        I13 = complex(ics[1, 3].point)
        assert I13.real == pytest.approx(B.real)  # on the vertical through B
        assert abs((I13 * np.conj(A)).imag) <= 1e-8 * abs(I13) * abs(A)  # on line O2A
        I24 = complex(ics[2, 4].point)
        assert I24.real == pytest.approx(0.0, abs=1e-9 * (a + b))  # on the vertical through O2
        assert abs(((I24 - A) * np.conj(B - A)).imag) <= 1e-8 * max(1, abs(I24 - A)) * b
        assert bool(ics[1, 4].at_infinity)


# ---------------------------------------------------------------------------
# Inverted slider-crank (Norton sec. 4.7, inversion #3; notes Problem 6-13(a))
# ---------------------------------------------------------------------------


def test_inverted_slidercrank_random_matches_geometry_and_finite_differences(rng):
    """A = O4 + b û + c n̂ (slot direction û = e^{jθ4}); θ4 found here from the tangent
    construction, rates by five-point differences in time, I13/I24 by line meets."""
    n = 0
    while n < 80:
        a, d = rng.uniform(0.5, 6, 2)
        c = rng.uniform(-1, 1) * 0.8 * min(a, d)
        isc = InvertedSliderCrank(a, d, c)
        t2 = rng.uniform(0, TWO_PI)
        A = a * np.exp(1j * t2)
        q = A - d
        if abs(q) ** 2 - c * c < 1e-3:
            continue
        form = int(rng.integers(1, 3))
        b = np.sqrt(abs(q) ** 2 - c * c) * (1 if form == 1 else -1)
        t4 = np.angle(q / (b + 1j * c))  # rotate (b, c) onto O4→A
        w2, a2 = rng.normal(size=2) * 2
        m = isc.solve(t2, w2, a2, form=form)
        assert angle_error(m.theta4, t4) < 1e-9
        assert float(m.b) == pytest.approx(b)
        h = 1e-3
        steps = np.array([-2, -1, 0, 1, 2]) * h
        pos = isc.solve(t2 + w2 * steps + a2 * steps**2 / 2, form=form)
        if not pos.ok.all():
            continue
        x = np.unwrap(pos.theta4)
        assert (x[0] - 8 * x[1] + 8 * x[3] - x[4]) / (12 * h) == pytest.approx(
            float(m.omega4), rel=1e-5, abs=1e-5
        )
        assert (-x[0] + 16 * x[1] - 30 * x[2] + 16 * x[3] - x[4]) / (12 * h * h) == pytest.approx(
            float(m.alpha4), rel=1e-4, abs=1e-3
        )
        bb = pos.b
        assert (bb[0] - 8 * bb[1] + 8 * bb[3] - bb[4]) / (12 * h) == pytest.approx(
            float(m.b_dot), rel=1e-5, abs=1e-5
        )
        ics = isc.instant_centres(t2, form=form)
        u = np.exp(1j * t4)
        # I13: line O2A ∩ the slot normal through O4
        M = np.array([[A.real, -(1j * u).real], [A.imag, -(1j * u).imag]])
        if abs(np.linalg.det(M)) > 1e-3 * a:
            s, _ = np.linalg.solve(M, [d, 0.0])
            assert complex(ics[1, 3].point) == pytest.approx(s * A, rel=1e-7, abs=1e-9)
        # ω4 from I24 (a point of both 2 and 4): ω2 (I24 − O2) = ω4 (I24 − O4)
        I24 = complex(ics[2, 4].point)
        if abs(I24 - d) > 1e-6 and abs(w2) > 1e-3:
            assert float(m.omega4) == pytest.approx(w2 * (I24 - 0).real / (I24 - d).real, rel=1e-6)
        n += 1


def test_quick_return_crank_rocker_by_its_limit_positions(rng):
    """Norton sec. 3.5: the synthesized crank-rocker's rocker swings the requested angle
    between the limit positions (crank and coupler extended, |O2B| = a + b, and folded,
    |O2B| = b − a), and the crank turns 180° + δ one way and 180° − δ the other, with
    TR = (180 + δ)/(180 − δ) — limit positions found here by the law of cosines."""
    from machdyn.synthesis import quick_return

    for swing_deg, tr in ((45, 1.25), (30, 1.1), (60, 1.4), (80, 1.0)):
        fb = quick_return(np.radians(swing_deg), tr, r4=float(rng.uniform(1, 3))).fourbar
        d, a, b, c = fb.lengths
        assert fb.barker_class == "GCRR"
        psi = [np.arccos((d * d + c * c - e * e) / (2 * d * c)) for e in (a + b, b - a)]
        B = [d - c * np.exp(-1j * p) for p in psi]  # B above the ground line, seen from O4
        assert abs(psi[0] - psi[1]) == pytest.approx(np.radians(swing_deg), abs=1e-9)
        beta = abs(wrap(np.angle(B[0]) - np.angle(B[1])))
        assert (np.pi + beta) / (np.pi - beta) == pytest.approx(tr, rel=1e-9)


def test_mechanical_advantage_between_any_input_and_output():
    """Power identity (notes review lecture 2: MA = F_out/F_in = v_in*/v_out*) for a
    torque on link 2 against a force at a coupler point along a fixed direction, and for
    a force on link 4 against a torque on link 2; velocities from this file's solves."""
    from machdyn.virtual_work import fourbar_mechanical_advantage

    fb = FourBar(8, 4, 7, 6)
    for t2 in np.radians([10.0, 75.0, 140.0, 230.0, 320.0]):
        t3, t4 = fourbar_reference(8, 4, 7, 6, t2, 1.0)
        rates = fourbar_rates(8, 4, 7, 6, t2, t3, t4, 1.0, 0.0, 0.0)
        w3, w4 = rates["omega3"], rates["omega4"]
        point, direction = 3.5 + 0.7j, np.exp(0.4j)
        v = 1j * 4 * np.exp(1j * t2) + 1j * w3 * point * np.exp(1j * t3)
        v_out = (v * np.conj(direction)).real
        ma = fourbar_mechanical_advantage(fb, t2, 2, (3, point, direction))
        assert float(ma) == pytest.approx(1.0 / v_out, rel=1e-9)
        v_in = (1j * w4 * (2 + 0.5j) * np.exp(1j * t4) * np.conj(1j)).real
        ma = fourbar_mechanical_advantage(fb, t2, (4, 2 + 0.5j, 1j), 2)
        assert float(ma) == pytest.approx(v_in, rel=1e-9)


def test_slidercrank_input_range_by_brute_force(rng):
    """The rod reaches the slide while |a sin θ2 − c| ≤ b (the notes' loop, Im part):
    input_range and its mirror (π − hi, π − lo) together are exactly that set."""
    t = np.linspace(0, TWO_PI, 20001)
    for _ in range(300):
        a, b = rng.uniform(0.5, 5, 2)
        c = rng.uniform(-1, 1) * (a + b) * 0.95
        sc = SliderCrank(a, b, c)
        reach = np.abs(a * np.sin(t) - c) <= b
        r = sc.input_range()
        assert sc.crank_rotates == (a + abs(c) < b)
        if reach.all():
            assert r is None
            continue
        lo, hi = r
        inside = ((t - lo) % TWO_PI <= hi - lo) | ((t - (np.pi - hi)) % TWO_PI <= hi - lo)
        assert np.count_nonzero(inside != reach) <= 4  # grid points at the very limits


def test_mechanical_advantage_at_exact_toggles():
    """Notes review lecture 2: "M.A. large near toggle" — at a toggle of crank and coupler
    (output at rest) MA = ∞ by both routes; at the input's dead point (coupler and output
    collinear, the GRCR's input limits) MA = 0; a slider-crank at its dead centres
    (crank and rod collinear, θ2 = asin(c/(a + b)) and π + asin(c/(b − a))) gives ∞."""
    grcr = FourBar(6, 9, 3, 8)
    r = grcr.input_range(1)
    ma = grcr.mechanical_advantage(np.array([r.lo, r.hi]))
    np.testing.assert_array_equal(ma, [0.0, 0.0])
    crank_rocker = FourBar(8, 4, 7, 6)
    for t in crank_rocker.toggles():
        form = 1 if t.branch > 0 else 2
        for method in ("power", "instant_centres"):
            assert crank_rocker.mechanical_advantage(t.theta2, form=form, method=method) == np.inf
    a, b, c = 2.0, 6.0, 0.5
    sc = SliderCrank(a, b, c)
    dead = np.array([np.arcsin(c / (a + b)), np.pi + np.arcsin(c / (b - a))])
    np.testing.assert_allclose(sc.solve(dead, 1.0).d_dot, 0.0, atol=1e-12)
    for method in ("power", "instant_centres"):
        np.testing.assert_array_equal(sc.mechanical_advantage(dead, method=method), np.inf)


@pytest.mark.parametrize(
    ("lengths", "form"), [((8, 4, 7, 6), 1), ((8, 4, 7, 6), 2), ((6, 9, 3, 8), 1)]
)
def test_coupler_curve_points_lie_on_this_files_solution(lengths, form):
    """Every point of FourBar.coupler_curve is A + p e^{j(θ3 + δ)} of a pose found here by
    intersecting circles, on the branch the curve reports (Norton sec. 3.6 coupler curves)."""
    fb = FourBar(*lengths, coupler=(3.0, np.radians(35)))
    cc = fb.coupler_curve(form, n=181)
    for t2, br, point in zip(cc.theta2, cc.branch, cc.points, strict=True):
        sign = br if fb.form_rule == "phi34" else (1 if form == 1 else -1)
        t3, _ = fourbar_reference(*lengths, t2, sign)
        expected = fb.r2 * np.exp(1j * t2) + 3.0 * np.exp(1j * (t3 + np.radians(35)))
        assert abs(point - expected) < 1e-6 * max(lengths)


@pytest.mark.parametrize(
    ("func", "x_range", "t2_range", "t4_range"),
    [
        (np.log10, (1.0, 10.0), (45.0, 105.0), (135.0, 225.0)),
        (np.square, (0.0, 1.0), (30.0, 120.0), (60.0, 150.0)),
        (np.exp, (0.0, 1.0), (200.0, 290.0), (250.0, 330.0)),
    ],
)
def test_function_generator_passes_its_precision_points(func, x_range, t2_range, t4_range):
    """Freudenstein function generation (Norton sec. 5.9), checked by geometry only: at
    each Chebyshev precision point x_j = (x0 + xf)/2 − (xf − x0)/2 · cos((2j − 1)π/(2n))
    the crank pin A = R2 e^{j(θ2 + offset)} and the rocker pin B = R1 + R4 e^{j(θ4 + offset)}
    are exactly a coupler length apart, on one assembly (one sign of φ12), or a branch
    defect is named."""
    from machdyn.synthesis import function_generator

    g = function_generator(func, x_range, np.radians(t2_range), np.radians(t4_range), n=3)
    x0, xf = x_range
    j = np.arange(1, 4)
    cheb = (x0 + xf) / 2 - (xf - x0) / 2 * np.cos((2 * j - 1) * np.pi / 6)
    np.testing.assert_allclose(np.sort(g.x_precision), cheb, rtol=1e-12)
    r1, r2, r3, r4 = g.fourbar.lengths
    signs = set()
    for x in cheb:
        t2 = np.radians(t2_range[0]) + (x - x0) / (xf - x0) * np.radians(t2_range[1] - t2_range[0])
        y0, yf = func(np.array(x0)), func(np.array(xf))
        t4 = np.radians(t4_range[0]) + (func(np.array(x)) - y0) / (yf - y0) * np.radians(
            t4_range[1] - t4_range[0]
        )
        A = r2 * np.exp(1j * (t2 + g.input_offset))
        B = r1 + r4 * np.exp(1j * (t4 + g.output_offset))
        assert abs(B - A) == pytest.approx(r3, rel=1e-9)
        signs.add(np.sign(wrap(np.angle(B - r1) - np.angle(B - A))))
    if len(signs) > 1:  # the points lie on both assemblies: must be reported
        assert any(d.startswith("branch defect") for d in g.defects)
    else:
        assert signs == {g.branch}
