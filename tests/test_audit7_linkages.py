"""Audit 7: four-bar, slider-crank and inverted slider-crank against geometry written here.

Positions come from circle intersections / the loop solved by hand in this file,
on both circuits and right next to the toggles (found here from the law of
cosines). Rates are central time differences of those positions along a
prescribed input motion θ2(t) = θ2 + ω t + α t²/2 + ψ t³/6 (5-point stencils),
so velocities, accelerations and jerks are checked against derivatives of
positions, never against machdyn's own linear solves. Kennedy's rule, the
mechanical advantage (power balance F_in r_in ω2 = F_out r_out ω4), the
transmission angle and Barker's table (Norton Table 2-4, written out here,
equalities included) complete the notes' four-bar chapter.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import machdyn
from machdyn import FourBar, InvertedSliderCrank, SliderCrank

WRAP = lambda a: (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi  # noqa: E731
H = 2e-3  # time step of the differences


def fourbar_pose(r, t2, form, code):
    """(θ3, θ4) by circle intersection, the solution the notes' form rule names, or None."""
    r1, r2, r3, r4 = r
    A = r2 * np.exp(1j * t2)
    u = r1 - A  # A → O4
    d = abs(u)
    if d > r3 + r4 or d < abs(r3 - r4) or d == 0:
        return None
    # B from A at distance r3 and from O4 at r4: angle at A between AO4 and AB.
    cos_a = np.clip((r3 * r3 + d * d - r4 * r4) / (2 * r3 * d), -1.0, 1.0)
    out = []
    for s in (1, -1):
        B = A + r3 * u / d * np.exp(1j * s * np.arccos(cos_a))
        out.append((np.angle(B - A), np.angle(B - r1)))
    want = 1 if form == 1 else -1
    for t3, t4 in out:
        key = WRAP(t2) if code in ("GRCR", "GRRC") else WRAP(t4 - t3)
        # GRCR, GRRC: within the form (sign of θ2), branch +1 is the sign of φ12
        other = code in ("GRCR", "GRRC") and np.sign(WRAP(t4 - t3)) != 1
        if np.sign(key) == want and not other:
            return t3, t4
    return None


def motion(t2, w, a, j, dt):
    return t2 + w * dt + a * dt**2 / 2 + j * dt**3 / 6


def differences(f, h=H):
    """First three time derivatives at 0 of f(dt): 5-point stencils, Richardson-extrapolated."""
    coarse, fine = _stencils(f, h), _stencils(f, h / 2)
    return tuple((4 * b - a) / 3 for a, b in zip(coarse, fine, strict=True))


def _stencils(f, h):
    ts = np.array([-2, -1, 0, 1, 2]) * h
    v = np.unwrap(np.array([f(t) for t in ts]), axis=0)
    d1 = (v[0] - 8 * v[1] + 8 * v[3] - v[4]) / (12 * h)
    d2 = (-v[0] + 16 * v[1] - 30 * v[2] + 16 * v[3] - v[4]) / (12 * h * h)
    d3 = (-v[0] + 2 * v[1] - 2 * v[3] + v[4]) / (2 * h**3)
    return d1, d2, d3


def toggle_angles(r):
    """θ2 where links 3 and 4 are in line: |A − O4| = r3 + r4 or |r3 − r4|."""
    r1, r2, r3, r4 = r
    out = []
    for reach in (r3 + r4, abs(r3 - r4)):
        c = (r1 * r1 + r2 * r2 - reach * reach) / (2 * r1 * r2)
        if -1 <= c <= 1:
            out += [np.arccos(c), -np.arccos(c)]
    return out


@pytest.mark.parametrize("seed", range(2))
def test_fourbar_both_forms_near_toggles_by_geometry_and_differences(seed):
    rng = np.random.default_rng(seed)
    checked = 0
    for _ in range(40):
        r = rng.uniform(0.3, 3.0, 4)
        if r.max() >= r.sum() - r.max():
            continue  # cannot close (refused by name elsewhere)
        fb = FourBar(*r)
        code = fb.barker_class
        angles = list(rng.uniform(-np.pi, np.pi, 6))
        for t in toggle_angles(r):
            angles += [t + 0.02, t - 0.02, t + 1e-6, t - 1e-6]
        w, a, j = rng.uniform(-3, 3, 3)
        for form in (1, 2):
            for t2 in angles:
                pose = fourbar_pose(r, t2, form, code)
                try:
                    m = fb.solve(t2, omega2=w, alpha2=a, jerk2=j, form=form)
                except machdyn.AssemblyError:
                    assert pose is None, (r, t2, form)
                    continue
                assert pose is not None, (r, t2, form)
                t3, t4 = pose
                assert WRAP(m.theta3 - t3) == pytest.approx(0, abs=1e-7)
                assert WRAP(m.theta4 - t4) == pytest.approx(0, abs=1e-7)
                if not m.ok:  # a toggle: flagged, positions still right
                    continue

                def f(dt, r=r, t2=t2, w=w, a=a, j=j, form=form, code=code):
                    pose = fourbar_pose(r, motion(t2, w, a, j, dt), form, code)
                    return np.array(pose or (np.nan, np.nan))

                d1, d2, d3 = differences(f, h=min(H, 1e-3))
                if not np.all(np.isfinite([d1, d2, d3])):
                    continue  # the stencil crosses a toggle
                got = np.array(
                    [[m.omega3, m.omega4], [m.alpha3, m.alpha4], [m.jerk3, m.jerk4]], dtype=float
                )
                scale = np.abs(got).max(axis=1, keepdims=True) + 1.0
                if scale.max() > 1e4:
                    continue  # too close to a toggle for differences of step H
                np.testing.assert_allclose(got, [d1, d2, d3], atol=2e-3 * scale.max(), rtol=0)
                checked += 1
    assert checked > 100


@pytest.mark.parametrize("seed", range(3))
def test_kennedy_centres_mechanical_advantage_and_transmission_angle(seed):
    rng = np.random.default_rng(10 + seed)
    for _ in range(30):
        r = rng.uniform(0.3, 3.0, 4)
        if r.max() >= r.sum() - r.max():
            continue
        fb = FourBar(*r)
        code = fb.barker_class
        for form in (1, 2):
            for t2 in rng.uniform(-np.pi, np.pi, 5):
                pose = fourbar_pose(r, t2, form, code)
                nearby = [fourbar_pose(r, t2 + s * 1e-6, form, code) for s in (-1, 1)]
                if pose is None or None in nearby:
                    continue
                t3, t4 = pose
                A, B = r[1] * np.exp(1j * t2), r[0] + r[3] * np.exp(1j * t4)
                if abs(np.sin(t4 - t3)) < 1e-3 or abs(np.sin(t3 - t2)) < 1e-3:
                    continue
                ratio = WRAP(nearby[1][1] - nearby[0][1]) / 2e-6  # ω4/ω2 by differences
                r_in, r_out = rng.uniform(0.5, 2.0, 2)
                ma = fb.mechanical_advantage(t2, r_in, r_out, form=form)
                assert float(ma) == pytest.approx(r_in / (r_out * ratio), rel=1e-5)
                ics = fb.instant_centres(t2, form=form)

                # I13 on lines O2A and O4B; I24 on O2O4 and AB (meet them here).
                def meet(p1, p2, q1, q2):
                    d1, d2 = p2 - p1, q2 - q1
                    s = ((q1 - p1).real * d2.imag - (q1 - p1).imag * d2.real) / (
                        d1.real * d2.imag - d1.imag * d2.real
                    )
                    return p1 + s * d1

                if abs(np.sin(t2 - t4)) > 1e-3:
                    i13 = meet(0j, A, r[0] + 0j, B)
                    assert complex(ics[1, 3].point) == pytest.approx(i13, abs=1e-7 * abs(i13))
                i24 = meet(0j, r[0] + 0j, A, B)
                assert complex(ics[2, 4].point) == pytest.approx(i24, abs=1e-7 * abs(i24))
                # ω4/ω2 = I12I24 / I14I24 (signed along the ground line).
                assert ((i24 - 0) / (i24 - r[0])).real == pytest.approx(ratio, rel=1e-5)
                # transmission angle: the acute angle at B by the law of cosines
                cos_b = (r[2] ** 2 + r[3] ** 2 - abs(A - r[0]) ** 2) / (2 * r[2] * r[3])
                mu = np.arccos(np.clip(cos_b, -1, 1))
                mu = min(mu, np.pi - mu)
                m = fb.solve(t2, form=form)
                assert float(m.mu) == pytest.approx(mu, abs=1e-9)


def barker_by_table(lengths):
    """The notes' Barker table ("Table 2. Complete classification", Norton Table 2-4)."""
    short, p, q, long_ = sorted(lengths)
    total, other = short + long_, p + q
    shortest = [i for i, x in enumerate(lengths, start=1) if x == short]
    longest = [i for i, x in enumerate(lengths, start=1) if x == long_]
    if total < other:
        return {1: "GCCC", 2: "GCRR", 3: "GRCR", 4: "GRRC"}[shortest[0]]
    if total > other:
        return {1: "RRR1", 2: "RRR2", 3: "RRR3", 4: "RRR4"}[longest[0]]
    if short == long_:
        return "CP3X"
    if short == p and q == long_:  # two equal pairs: parallelogram, deltoid
        return "CP2X"
    return {1: "CPCCC", 2: "CPCRR", 3: "CPRCR", 4: "CPRRC"}[shortest[0]]


def test_barker_classes_of_every_small_integer_linkage_including_change_points():
    seen = set()
    for lengths in itertools.product(range(1, 9), repeat=4):
        short, p, q, long_ = sorted(lengths)
        if long_ >= short + p + q:
            continue  # cannot close: refused elsewhere
        expected = barker_by_table(lengths)
        scale = 0.1  # decimal lengths: s + l = p + q only to rounding for some
        got = machdyn.barker_class(*(x * scale for x in lengths))
        assert got == expected, lengths
        seen.add(expected)
    assert len(seen) == 14  # every row of the table


@pytest.mark.parametrize("seed", range(3))
def test_slider_crank_with_offset_both_forms_by_the_loop_and_differences(seed):
    rng = np.random.default_rng(20 + seed)
    for _ in range(30):
        a, b = rng.uniform(0.3, 3.0, 2)
        c = rng.uniform(-0.9, 0.9) * (a + b)
        sc = SliderCrank(a, b, c)
        w, al, je = rng.uniform(-3, 3, 3)
        for form in (1, 2):
            sign = 1.0 if form == 1 else -1.0

            def d_of(t2, a=a, b=b, c=c, sign=sign):
                reach = b * b - (a * np.sin(t2) - c) ** 2
                return a * np.cos(t2) + sign * np.sqrt(reach) if reach >= 0 else np.nan

            for t2 in rng.uniform(-np.pi, np.pi, 6):
                d = d_of(t2)
                if not np.isfinite(d):
                    with pytest.raises(machdyn.AssemblyError):
                        sc.solve(t2, form=form)
                    continue
                m = sc.solve(t2, omega2=w, alpha2=al, jerk2=je, form=form)
                assert float(m.d) == pytest.approx(d, abs=1e-12 * (a + b))
                assert abs(complex(m.B) - complex(m.A)) == pytest.approx(b, rel=1e-12)
                if not m.ok:
                    continue
                d1, d2, d3 = differences(
                    lambda dt, k=(t2, w, al, je), d_of=d_of: d_of(motion(*k, dt)), h=1e-3
                )
                got = np.array([m.d_dot, m.d_ddot, m.d_dddot], dtype=float)
                if not np.all(np.isfinite([d1, d2, d3])) or np.abs(got).max() > 1e3:
                    continue
                np.testing.assert_allclose(got, [d1, d2, d3], atol=1e-3 * (np.abs(got).max() + 1))


@pytest.mark.parametrize("seed", range(3))
def test_inverted_slider_crank_with_offset_by_the_loop_and_differences(seed):
    rng = np.random.default_rng(30 + seed)
    for _ in range(30):
        a, d = rng.uniform(0.3, 3.0, 2)
        c = rng.uniform(-0.5, 0.5) * abs(a - d)
        isc = InvertedSliderCrank(a, d, c)
        w, al, je = rng.uniform(-3, 3, 3)
        for form in (1, 2):
            sign = 1.0 if form == 1 else -1.0

            def pose(t2, a=a, d=d, c=c, sign=sign):
                u = a * np.exp(1j * t2) - d  # O4 → A = (b + j c) e^{jθ4}
                b = sign * np.sqrt(max(abs(u) ** 2 - c * c, 0.0))
                return np.array([np.angle(u / (b + 1j * c)), b])

            for t2 in rng.uniform(-np.pi, np.pi, 6):
                m = isc.solve(t2, omega2=w, alpha2=al, jerk2=je, form=form)
                t4, b = pose(t2)
                assert WRAP(m.theta4 - t4) == pytest.approx(0, abs=1e-10)
                assert float(m.b) == pytest.approx(b, abs=1e-10 * (a + d))
                if not m.ok:
                    continue
                d1, d2, d3 = differences(
                    lambda dt, k=(t2, w, al, je), pose=pose: pose(motion(*k, dt)), h=1e-3
                )
                got = np.array(
                    [[m.omega4, m.b_dot], [m.alpha4, m.b_ddot], [m.jerk4, m.b_dddot]], dtype=float
                )
                if np.abs(got).max() > 1e3:
                    continue
                np.testing.assert_allclose(got, [d1, d2, d3], atol=1e-3 * (np.abs(got).max() + 1))
