"""Audit: spur-gear mesh, interference and trains vs Norton ch. 9 and the notes.

Expected values are computed here: the notes' length of action (review lecture
3, "LENGTH OF ACTION", Norton eq. 9.2) and contact ratio m_p = Z / p_b (eq. 9.3),
interference decided geometrically (a tip circle reaching past the other gear's
interference point, where the line of action touches its base circle: Norton
sec. 9.5, "INVOLUTES LIE OUTSIDE THE BASE CIRCLE"), the centre-distance change
of Norton eq. 9.3 ("VELOCITY RATIO UNCHANGED!"), backlash from tooth thickness
at the operating pitch circles, and planetary speeds by superposition (Norton
Example 9-6's tabular method) written out per gear.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from machdyn.errors import ModelError
from machdyn.gears import (
    Gear,
    GearPair,
    PlanetaryTrain,
    length_of_action,
    min_pinion_teeth,
    min_teeth_equal_gears,
    min_teeth_rack,
    train_value,
    willis,
)


def inv(phi):
    return math.tan(phi) - phi


def interferes_by_geometry(n_p, n_g, phi, k=1.0, m=1.0):
    """True if either tip circle passes the other gear's interference point."""
    rp, rg = n_p * m / 2, n_g * m / 2
    c = rp + rg
    ap = ag = k * m
    limit_g = math.hypot(rg * math.cos(phi), c * math.sin(phi))  # gear tip reaches E on pinion
    limit_p = math.hypot(rp * math.cos(phi), c * math.sin(phi))
    return rg + ag > limit_g * (1 + 1e-12) or rp + ap > limit_p * (1 + 1e-12)


def test_notes_final_exam_10_length_of_action_and_contact_ratio():
    """Final exam 10 (φ = 20°, r_g = 3.75, a_g = 0.125, r_p = 1.5, a_p = 0.125 in;
    p_b = 0.3689 in): Z by the notes' formula, worked here, and m_p = Z/p_b."""
    phi = math.radians(20)
    rg, ag, rp, ap = 3.75, 0.125, 1.5, 0.125
    c = rg + rp
    z = (
        math.sqrt((rg + ag) ** 2 - (rg * math.cos(phi)) ** 2)
        + math.sqrt((rp + ap) ** 2 - (rp * math.cos(phi)) ** 2)
        - c * math.sin(phi)
    )
    assert z == pytest.approx(0.6249, abs=5e-5)
    assert length_of_action(rg, ag, rp, ap, phi) == pytest.approx(z, rel=1e-12)
    # p_b printed 0.3689 = 2π r_p cos φ / N_p with N_p = 24 (P_d = 8)
    assert 2 * math.pi * rp * math.cos(phi) / 24 == pytest.approx(0.3689, abs=2e-4)
    pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
    assert pair.base_pitch == pytest.approx(2 * math.pi * rp * math.cos(phi) / 24)
    assert pair.contact_ratio == pytest.approx(z / pair.base_pitch, rel=1e-12)


def test_random_pairs_contact_ratio_and_interference(rng):
    """300 random standard full-depth pairs, 14.5°/20°/25°, metric and inch."""
    for _ in range(300):
        n_p = int(rng.integers(8, 60))
        n_g = int(rng.integers(n_p, 200))
        phi = math.radians(float(rng.choice([14.5, 20.0, 25.0])))
        m = float(rng.uniform(0.5, 10))
        pair = GearPair(
            Gear(n_p, module=m, pressure_angle=phi), Gear(n_g, module=m, pressure_angle=phi)
        )
        assert pair.interferes == interferes_by_geometry(n_p, n_g, phi, m=m), (n_p, n_g, phi)
        rp, rg = n_p * m / 2, n_g * m / 2
        pb = 2 * math.pi * rp * math.cos(phi) / n_p
        assert pair.base_pitch == pytest.approx(pb, rel=1e-12)
        assert pair.velocity_ratio == pytest.approx(-n_p / n_g)
        if not pair.interferes:
            z = length_of_action(rg, m, rp, m, phi)
            assert pair.length_of_action == pytest.approx(z, rel=1e-12)
            assert pair.contact_ratio == pytest.approx(z / pb, rel=1e-12)
            assert pair.path_of_approach + pair.path_of_recess == pytest.approx(z, rel=1e-12)


def test_minimum_teeth_against_the_interference_geometry():
    """Norton Table 9-4/9-5 limits re-derived: the fewest teeth with no interference,
    found here by trying every tooth count against the geometric condition."""
    for deg in (14.5, 20.0, 25.0):
        phi = math.radians(deg)
        equal = next(n for n in range(4, 200) if not interferes_by_geometry(n, n, phi))
        assert min_teeth_equal_gears(phi) == equal
        # against a rack the pinion's interference point is reached when k > r_p sin²φ
        rack = next(n for n in range(4, 200) if n / 2 * math.sin(phi) ** 2 >= 1.0)
        assert min_teeth_rack(phi) == rack
        for n_g in (equal, 26, 45, 60, 101, 300, 1000):
            if n_g < equal:
                continue
            brute = next(n for n in range(4, n_g + 1) if not interferes_by_geometry(n, n_g, phi))
            assert min_pinion_teeth(n_g, phi) == brute, (deg, n_g)
    assert (min_teeth_rack(math.radians(14.5)), min_teeth_rack(math.radians(20))) == (32, 18)


def test_centre_distance_change_keeps_ratio_and_sets_pressure_angle_and_backlash(rng):
    """Notes 'CENTER DISTANCE ERROR' / Norton eq. 9.3: cos φ' = (C/C') cos φ; base circles
    and the velocity ratio do not change; Z' from the tip circles at C'; backlash on the
    operating pitch circles from tooth thicknesses t(r) = 2r(t/2r_p + inv φ − inv φ_r),
    i.e. B = 2C'(inv φ' − inv φ) for standard teeth."""
    for _ in range(50):
        n_p = int(rng.integers(18, 40))
        n_g = int(rng.integers(n_p, 120))
        phi = math.radians(20.0)
        m = float(rng.uniform(1, 5))
        pair = GearPair(Gear(n_p, module=m), Gear(n_g, module=m))
        c = pair.standard_center_distance
        assert c == pytest.approx((n_p + n_g) * m / 2)
        c2 = c + float(rng.uniform(0.01, 0.3)) * m
        wide = pair.with_center_distance(c2)
        phi2 = math.acos(c / c2 * math.cos(phi))
        assert wide.operating_pressure_angle == pytest.approx(phi2, rel=1e-12)
        assert wide.velocity_ratio == pytest.approx(pair.velocity_ratio)
        rbp, rbg = n_p * m / 2 * math.cos(phi), n_g * m / 2 * math.cos(phi)
        rap, rag = n_p * m / 2 + m, n_g * m / 2 + m
        z = math.sqrt(rag**2 - rbg**2) + math.sqrt(rap**2 - rbp**2) - c2 * math.sin(phi2)
        assert wide.length_of_action == pytest.approx(z, rel=1e-10)
        assert wide.contact_ratio == pytest.approx(z / pair.base_pitch, rel=1e-10)
        assert wide.backlash == pytest.approx(2 * c2 * (inv(phi2) - inv(phi)), rel=1e-9)


def test_train_values_and_planetary_by_superposition(rng):
    """Norton eq. 9.5 (train value = ± product of driver/driven teeth; internal mesh keeps
    the sense) and Example 9-6's tabular method: speeds = arm rotation + arm-fixed motion."""
    assert train_value([(14, 54), (14, 56)]) == pytest.approx((14 / 54) * (14 / 56))
    assert train_value([(20, 40), (30, 90, "internal")]) == pytest.approx(-(20 / 40) * (30 / 90))
    for _ in range(30):
        ns, npl = int(rng.integers(12, 60)), int(rng.integers(12, 40))
        nr = ns + 2 * npl  # coaxial simple planetary
        w_arm, w_sun = rng.uniform(-300, 300, 2)
        # tabular: (1) all locked turning with the arm; (2) arm fixed, sun turns w_sun − w_arm
        rel_sun = w_sun - w_arm
        rel_planet = -rel_sun * ns / npl
        rel_ring = rel_planet * npl / nr  # internal mesh: same sense as the planet
        train = PlanetaryTrain.simple(sun=ns, planet=npl, ring=nr)
        speeds = train.speeds(arm=w_arm, sun=w_sun)
        assert speeds["ring"] == pytest.approx(w_arm + rel_ring, rel=1e-12, abs=1e-9)
        assert train.train_value == pytest.approx(-ns / nr)
        assert float(willis(-ns / nr, first=w_sun, arm=w_arm)) == pytest.approx(w_arm + rel_ring)
        # ring fixed: ω_arm / ω_sun = N_s / (N_s + N_r)
        fixed = train.speeds(ring=0.0, sun=1.0)
        assert fixed["arm"] == pytest.approx(ns / (ns + nr))
    # arrays broadcast and agree element-wise with the scalar formula
    w = np.linspace(-100, 100, 7)
    np.testing.assert_allclose(willis(-0.5, first=w, arm=-200.0), -200 + (-0.5) * (w + 200))


def test_generated_outline_thickness_matches_the_involute_relation():
    """The rack-generated outline (gear_outline) measured here: the share of a circle of
    radius r inside the outline × 2πr / N is the tooth thickness there, which must equal
    s_r = 2r(s/(2r_p) + inv φ − inv φ_r) (Norton sec. 9.4) with s = m(π/2 + 2x tan φ)
    (ISO 21771 profile shift) — two routes that share no code."""
    from matplotlib.path import Path

    from machdyn.gears import gear_outline

    phi = math.radians(20)
    for n, m, x in ((30, 2.0, 0.3), (18, 1.0, -0.2)):
        gear = Gear(n, module=m, profile_shift=x)
        out = gear_outline(gear)
        path = Path(np.column_stack([out.x, out.y]))
        rp = n * m / 2
        s = m * (math.pi / 2 + 2 * x * math.tan(phi))
        ra = rp + (1 + x) * m
        assert gear.addendum_radius == pytest.approx(ra)
        lo = out.form_radius
        for r in np.linspace(lo + 0.05 * (ra - lo), ra - 0.05 * (ra - lo), 3):
            # the outline repeats every angular pitch: one pitch of the circle suffices
            t = np.linspace(0, 2 * np.pi / n, 20000, endpoint=False)
            inside = path.contains_points(np.column_stack([r * np.cos(t), r * np.sin(t)]))
            measured = inside.mean() * 2 * np.pi * r / n
            phi_r = math.acos(rp * math.cos(phi) / r)
            expected = 2 * r * (s / (2 * rp) + inv(phi) - inv(phi_r))
            assert measured == pytest.approx(expected, rel=5e-4), (n, x, r)
            assert float(gear.thickness_at(r)) == pytest.approx(expected, rel=1e-12)


def _interferes_vec(n_p, n_g, phi):
    rp, rg = n_p / 2, n_g / 2
    c2 = ((rp + rg) * math.sin(phi)) ** 2
    return ((rg + 1) ** 2 > (rg * math.cos(phi)) ** 2 + c2 + 1e-12) | (
        (rp + 1) ** 2 > (rp * math.cos(phi)) ** 2 + c2 + 1e-12
    )


@pytest.mark.parametrize("target", [18.0, 7.3, 0.25])
def test_reverted_compound_is_the_best_train_by_exhaustive_search(target):
    """Norton sec. 9.8 reverted compound: N2 + N3 = N4 + N5, ratio (N3 N5)/(N2 N4),
    no interference in either mesh; an exhaustive search here (12…100 teeth) finds no
    closer ratio and, at equal error, no smaller tooth sum."""
    from machdyn.gears import reverted_compound

    phi = math.radians(20)
    best = reverted_compound(target)
    n2, n3, n4, n5 = best.teeth
    assert n2 + n3 == n4 + n5
    assert best.ratio == pytest.approx(n3 * n5 / (n2 * n4))
    for a, b in ((n2, n3), (n4, n5)):
        assert not _interferes_vec(np.array([min(a, b)]), np.array([max(a, b)]), phi)[0]
    n = np.arange(12, 101)
    N2, N3, N4 = np.meshgrid(n, n, n, indexing="ij")
    N5 = N2 + N3 - N4
    ok = (N5 >= 12) & (N5 <= 100)
    for a, b in ((N2, N3), (N4, N5)):
        ok &= ~_interferes_vec(np.minimum(a, b), np.maximum(a, b), phi)
    err = np.abs(N3 * N5 / (N2 * N4) / target - 1)
    err = np.where(ok, err, np.inf)
    assert abs(best.ratio / target - 1) <= err.min() + 1e-12
    ties = ok & (err <= err.min() + 1e-12)
    assert n2 + n3 == (N2 + N3)[ties].min()


def test_min_pinion_teeth_never_exceeds_the_gear():
    """A gear below the equal-gear minimum (23 teeth at 14.5°) meshes with no pinion at all:
    every N_p ≤ N_g interferes by geometry, and min_pinion_teeth says so (it used to return a
    'pinion' larger than the gear). Above it, the answer is ≤ N_g and is the least that clears."""
    phi = math.radians(14.5)
    for n_g in (13, 16, 20, 22):
        assert all(interferes_by_geometry(n_p, n_g, phi) for n_p in range(8, n_g + 1))
        with pytest.raises(ModelError, match=f"gear of {n_g} teeth.*at least 23"):
            min_pinion_teeth(n_g, phi)
    with pytest.raises(ModelError, match="gear of 16 teeth"):
        min_pinion_teeth([40, 16], phi)
    for n_g in (23, 30, 60, 200):
        n_p = min_pinion_teeth(n_g, phi)
        assert n_p <= n_g and not interferes_by_geometry(n_p, n_g, phi)
        assert interferes_by_geometry(n_p - 1, n_g, phi)


def test_internal_pair_length_of_action_and_interference():
    """Pinion inside a ring (Norton Fig. 9-4b): both base-circle tangent points lie on the
    same side of the pitch point, so Z = √(r_ap² − r_bp²) − √(r_ag² − r_bg²) + C sin φ with
    C = r_g − r_p and the ring's tip radius r_g − a; the ring's tip interferes when it lies
    inside the pinion's interference point, r_ag² < r_bg² + (C sin φ)²."""
    phi, m = math.radians(20), 2.0
    for n_p, n_g in ((20, 60), (18, 80), (30, 100), (24, 50)):
        pair = GearPair(Gear(n_p, module=m), Gear(n_g, module=m, internal=True))
        rp, rg = n_p * m / 2, n_g * m / 2
        c = rg - rp
        rbp, rbg = rp * math.cos(phi), rg * math.cos(phi)
        rap, rag = rp + m, rg - m
        z = math.sqrt(rap**2 - rbp**2) - math.sqrt(rag**2 - rbg**2) + c * math.sin(phi)
        assert pair.center_distance == pytest.approx(c)
        assert pair.length_of_action == pytest.approx(z, rel=1e-12)
        assert pair.contact_ratio == pytest.approx(z / (2 * math.pi * rbp / n_p), rel=1e-12)
        assert pair.velocity_ratio == pytest.approx(n_p / n_g)  # same sense
        assert pair.interferes == (rag**2 < rbg**2 + (c * math.sin(phi)) ** 2)


def test_report_of_a_pair_whose_gear_is_below_the_equal_gear_minimum():
    """The design report of 12:16 teeth at 14.5° says no pinion fits that gear (every pinion
    up to 16 teeth interferes by geometry, checked above), instead of naming a 'pinion'."""
    from machdyn.gears import Gear, GearPair
    from machdyn.report import report

    phi = math.radians(14.5)
    pair = GearPair(Gear(12, module=2, pressure_angle=phi), Gear(16, module=2, pressure_angle=phi))
    page = report(pair)
    row = page[page.index("fewest pinion teeth with this 16-tooth gear") :][:300]
    assert "none: no pinion meshes without interference" in row
