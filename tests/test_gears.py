"""Gear geometry, meshing and interference (machdyn.gears).

References: the notes' review lecture 3 and final exam problem 10; Norton,
*Design of Machinery* (Tables 9-1, 9-4, 9-5, Figures 9-7, 9-8); the KHK gear
technical reference (profile-shifted centre distance example). Where a
published value is not at hand the test uses an independent construction
(coordinates of the line of action, brute-force searches).
"""

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from machdyn import InputError, MachdynError, gears
from machdyn.errors import ModelError
from machdyn.gears import (
    Gear,
    GearPair,
    contact_ratio,
    length_of_action,
    max_gear_teeth,
    min_pinion_teeth,
    min_profile_shift,
    min_teeth_equal_gears,
    min_teeth_rack,
    onset_gear_teeth,
    undercut,
)

DEG = math.pi / 180


# --------------------------------------------------------------------------
# Independent geometry: the line of action in coordinates
# --------------------------------------------------------------------------
def _contact_segment(rbp, rap, rbg, rag, c_op, internal=False):
    """Length of action from circle-line intersections in the plane.

    Pinion centre at the origin, gear centre at (C', 0). The line of action
    ``n·x = r_bp`` is tangent to both base circles (the gear centre on the far
    side for an external pair, on the same side for an internal one); it is
    intersected with both addendum circles by solving the quadratics.
    """
    og = np.array([c_op, 0.0])
    nx = (rbp - rbg if internal else rbp + rbg) / c_op
    n = np.array([nx, math.sqrt(1 - nx**2)])
    d = np.array([-n[1], n[0]])  # direction of the line
    p0 = rbp * n  # tangent point T_p on the pinion base circle, parameter 0
    assert abs(abs(n @ og - rbp) - rbg) < 1e-9  # tangent to the gear base circle too

    def hits(center, radius):
        b = 2 * d @ (p0 - center)
        c = (p0 - center) @ (p0 - center) - radius**2
        return np.sort(np.real(np.roots([1.0, b, c])))

    t_tg = d @ (og - p0)  # parameter of the gear tangent point T_g
    side = np.sign(t_tg)
    t_p = hits(np.zeros(2), rap)
    t_g = hits(og, rag)
    # The gear tip point lies between T_g and T_p (from T_g towards T_p); the
    # pinion tip point lies towards T_g (external) or away from it, beyond the
    # pitch point (internal).
    gear_end = t_g[0] if side > 0 else t_g[1]
    towards_tg = (side > 0) != internal
    pinion_end = t_p[1] if towards_tg else t_p[0]
    return abs(pinion_end - gear_end)


# --------------------------------------------------------------------------
# The notes' final exam, problem 10
# --------------------------------------------------------------------------
def test_final_exam_problem_10_length_of_action_and_contact_ratio():
    # phi = 20 deg, r_g = 3.75, a_g = 0.125, r_p = 1.5, a_p = 0.125 (in).
    # By hand: sqrt(3.875^2 - 3.52385^2) = 1.6119, sqrt(1.625^2 - 1.40954^2) = 0.8086,
    # C sin phi = 5.25 * 0.34202 = 1.7956 -> Z = 0.6249 in; m_p = 0.6249/0.3689 = 1.694.
    z = length_of_action(3.75, 0.125, 1.5, 0.125, 20 * DEG)
    assert z == pytest.approx(0.6249, abs=1e-4)
    assert contact_ratio(z, 0.3689) == pytest.approx(1.694, abs=1e-3)


def test_final_exam_set_as_gear_pair():
    # r_p = 1.5 and a = 0.125 in are P_d = 8 full depth: 24 and 60 teeth.
    pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
    assert pair.length_of_action == pytest.approx(0.6249, abs=1e-4)
    # p_b = pi/8 cos 20 = 0.36902 (the exam rounds to 0.3689)
    assert pair.base_pitch == pytest.approx(math.pi / 8 * math.cos(20 * DEG), rel=1e-12)
    assert pair.contact_ratio == pytest.approx(0.6249 / 0.36902, abs=1e-3)
    assert pair.contact_ratio_rating == "good"
    assert not pair.interferes


def test_length_of_action_broadcasts():
    z = length_of_action(3.75, 0.125, [1.5, 1.5], 0.125, 20 * DEG)
    assert z.shape == (2,)
    assert z[0] == z[1] == pytest.approx(0.6249, abs=1e-4)


@given(
    n_p=st.integers(18, 60),
    extra=st.integers(0, 120),
    module=st.floats(0.5, 10),
    phi_deg=st.sampled_from([14.5, 20.0, 25.0]),
    stretch=st.floats(0.0, 0.02),
)
def test_length_of_action_matches_line_of_action_coordinates(n_p, extra, module, phi_deg, stretch):
    n_g = n_p + extra
    p = Gear(n_p, module=module, pressure_angle=phi_deg * DEG)
    g = Gear(n_g, module=module, pressure_angle=phi_deg * DEG)
    pair = GearPair(p, g)
    pair = pair.with_center_distance(pair.center_distance * (1 + stretch))
    expected = _contact_segment(
        p.base_radius, p.addendum_radius, g.base_radius, g.addendum_radius, pair.center_distance
    )
    assert pair.length_of_action == pytest.approx(expected, rel=1e-9, abs=1e-12)
    # The public function gives the same with the operating centre distance.
    z = length_of_action(
        g.pitch_radius,
        g.addendum,
        p.pitch_radius,
        p.addendum,
        phi_deg * DEG,
        center_distance=pair.center_distance,
    )
    assert z == pytest.approx(expected, rel=1e-9)
    # Approach + recess = Z
    assert pair.path_of_approach + pair.path_of_recess == pytest.approx(expected, rel=1e-9)


@given(
    n_p=st.integers(10, 40),
    n_g=st.integers(20, 90),
    x_p=st.floats(0.0, 0.6),
    x_g=st.floats(-0.4, 0.4),
)
def test_shifted_pair_tight_mesh_and_length_of_action(n_p, n_g, x_p, x_g):
    try:
        p = Gear(n_p, module=1.0, profile_shift=x_p)
        g = Gear(n_g, module=1.0, profile_shift=x_g)
    except InputError:  # pointed teeth: not a pair to mesh
        assume(False)
    pair = GearPair(p, g)
    # Tight mesh: inv(phi') = inv(phi) + 2 tan(phi) (x_p + x_g) / (N_p + N_g)  (KHK / ISO 21771)
    inv = math.tan(20 * DEG) - 20 * DEG + 2 * math.tan(20 * DEG) * (x_p + x_g) / (n_p + n_g)
    phi_op = pair.operating_pressure_angle
    assert math.tan(phi_op) - phi_op == pytest.approx(inv, rel=1e-10)
    assert pair.backlash == pytest.approx(0.0, abs=1e-10)
    expected = _contact_segment(
        p.base_radius, p.addendum_radius, g.base_radius, g.addendum_radius, pair.center_distance
    )
    assert pair.length_of_action == pytest.approx(expected, rel=1e-9)


def test_internal_pair_with_shifted_pinion_tight_mesh():
    # Internal pair: inv(phi') = inv(phi) + 2 tan(phi) (x_g - x_p) / (N_g - N_p)  (KHK).
    pair = GearPair(Gear(16, module=3.0, profile_shift=0.3), Gear(40, module=3.0, internal=True))
    inv = math.tan(20 * DEG) - 20 * DEG + 2 * math.tan(20 * DEG) * (0 - 0.3) / (40 - 16)
    phi_op = pair.operating_pressure_angle
    assert math.tan(phi_op) - phi_op == pytest.approx(inv, rel=1e-10)
    assert pair.center_distance == pytest.approx(
        3.0 * (40 - 16) / 2 * math.cos(20 * DEG) / math.cos(phi_op)
    )
    assert pair.backlash == pytest.approx(0.0, abs=1e-10)


def test_internal_pair_length_of_action_matches_coordinates():
    p = Gear(20, module=2.0)
    ring = Gear(80, module=2.0, internal=True)
    pair = GearPair(p, ring)
    assert pair.center_distance == pytest.approx(60.0)
    assert pair.velocity_ratio == pytest.approx(20 / 80)  # same sense of rotation
    expected = _contact_segment(
        p.base_radius, p.addendum_radius, ring.base_radius, ring.addendum_radius, 60.0, True
    )
    assert pair.length_of_action == pytest.approx(expected, rel=1e-9)
    assert pair.path_of_approach + pair.path_of_recess == pytest.approx(expected, rel=1e-9)
    assert pair.contact_ratio > 1.4
    assert not pair.interferes


# --------------------------------------------------------------------------
# Gear dimensions
# --------------------------------------------------------------------------
def test_full_depth_and_stub_proportions_norton_table_9_1():
    g = Gear(30, diametral_pitch=10)
    assert g.pitch_diameter == pytest.approx(3.0)
    assert g.addendum == pytest.approx(0.100)  # 1.000 / P_d
    assert g.dedendum == pytest.approx(0.125)  # 1.250 / P_d
    assert g.circular_pitch == pytest.approx(math.pi / 10)
    assert g.base_radius == pytest.approx(1.5 * math.cos(20 * DEG))
    assert g.tooth_thickness == pytest.approx(math.pi / 20)
    stub = Gear(30, diametral_pitch=10, system="stub")
    assert stub.addendum == pytest.approx(0.080)
    assert stub.dedendum == pytest.approx(0.100)
    assert stub.addendum_constant == pytest.approx(0.8)


def test_metric_module_and_given_addendum():
    g = Gear(40, module=2.5, addendum=2.0, dedendum=2.9, pressure_angle=25 * DEG)
    assert g.pitch_radius == pytest.approx(50.0)
    assert g.addendum_radius == pytest.approx(52.0)
    assert g.root_radius == pytest.approx(47.1)
    assert g.base_pitch == pytest.approx(math.pi * 2.5 * math.cos(25 * DEG))


def test_profile_shift_changes_addendum_dedendum_and_thickness():
    g = Gear(12, module=3.0, profile_shift=0.5)
    assert g.addendum == pytest.approx(4.5)
    assert g.dedendum == pytest.approx(2.25)
    assert g.tooth_thickness == pytest.approx(3 * math.pi / 2 + 2 * 0.5 * 3 * math.tan(20 * DEG))


def test_internal_gear_radii():
    ring = Gear(72, module=2.0, internal=True)
    assert ring.addendum_radius == pytest.approx(70.0)
    assert ring.root_radius == pytest.approx(74.5)


def test_tooth_thickness_at_base_circle_matches_angle_form():
    # Independent: at the base circle the half angle of the tooth is s/(2r) + inv(phi).
    g = Gear(25, module=1.0)
    inv = math.tan(20 * DEG) - 20 * DEG
    expected = 2 * g.base_radius * (math.pi / 2 / 25 + inv)
    assert float(g.thickness_at(g.base_radius)) == pytest.approx(expected)


def test_inverse_involute_round_trip(rng):
    phi = rng.uniform(0.01, 1.3, 50)
    inv = np.tan(phi) - phi
    assert np.allclose(gears.inverse_involute(inv), phi, atol=1e-12)


# --------------------------------------------------------------------------
# Centre distance: velocity ratio unchanged, cos phi' = (C/C') cos phi
# --------------------------------------------------------------------------
@given(
    n_p=st.integers(18, 40),
    n_g=st.integers(40, 100),
    stretch=st.floats(0.0, 0.05),
)
def test_center_distance_change_keeps_velocity_ratio(n_p, n_g, stretch):
    pair = GearPair(Gear(n_p, module=2.0), Gear(n_g, module=2.0))
    c = pair.standard_center_distance
    if c * (1 + stretch) >= pair.contact_limit:  # pulled out of contact: refused
        with pytest.raises(InputError, match="lose contact"):
            pair.with_center_distance(c * (1 + stretch))
        return
    wide = pair.with_center_distance(c * (1 + stretch))
    assert wide.velocity_ratio == pytest.approx(-n_p / n_g, rel=1e-12)
    assert math.cos(wide.operating_pressure_angle) * wide.center_distance == pytest.approx(
        c * math.cos(20 * DEG), rel=1e-12
    )
    rp, rg = wide.operating_pitch_radii
    assert rp + rg == pytest.approx(wide.center_distance, rel=1e-12)
    assert wide.backlash >= -1e-12


@pytest.mark.parametrize("phi_deg", [14.5, 20.0, 25.0])
def test_backlash_slope_is_2_tan_phi(phi_deg):
    # Norton: a centre-distance increase dC opens a backlash of about 2 dC tan(phi).
    pair = GearPair(
        Gear(18, module=2.0, pressure_angle=phi_deg * DEG),
        Gear(45, module=2.0, pressure_angle=phi_deg * DEG),
    )
    for dc in (1e-5, 1e-4, 1e-3):
        b = pair.with_center_distance(pair.center_distance + dc).backlash
        assert b == pytest.approx(2 * dc * math.tan(phi_deg * DEG), rel=20 * dc)


def test_backlash_from_thinning_at_standard_center_distance():
    p = Gear(20, module=2.0, thickness_reduction=0.05)
    g = Gear(50, module=2.0, thickness_reduction=0.03)
    pair = GearPair(p, g)
    assert pair.center_distance == pytest.approx(70.0)
    assert pair.backlash == pytest.approx(0.08, rel=1e-12)


def test_backlash_approximation_function():
    assert gears.backlash_from_center_distance(0.5, 20 * DEG) == pytest.approx(
        2 * 0.5 * math.tan(20 * DEG)
    )


def test_profile_shifted_center_distance_khk_example():
    # KHK Gear Technical Reference, profile-shifted spur gears (Table 4.6):
    # m = 3, alpha = 20 deg, z = 12/24, x = 0.6/0.36 -> alpha_w = 26.0886 deg, a = 56.4999 mm.
    pair = GearPair(Gear(12, module=3, profile_shift=0.6), Gear(24, module=3, profile_shift=0.36))
    assert math.degrees(pair.operating_pressure_angle) == pytest.approx(26.0886, abs=1e-4)
    assert pair.center_distance == pytest.approx(56.4999, abs=1e-4)
    assert pair.backlash == pytest.approx(0.0, abs=1e-12)


def test_contact_ratio_thresholds():
    assert gears.contact_ratio_rating(1.19) == "unacceptable"
    assert gears.contact_ratio_rating(1.2) == "acceptable"
    assert gears.contact_ratio_rating(1.4) == "good"
    assert gears.contact_ratio_rating(0.95) == "no contact"
    assert gears.CONTACT_RATIO_MINIMUM == 1.2 and gears.CONTACT_RATIO_TARGET == 1.4


def test_angles_of_approach_and_recess():
    pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
    app_p, app_g = pair.angles_of_approach
    rec_p, rec_g = pair.angles_of_recess
    # The gear turns N_p/N_g as far as the pinion in each phase.
    assert app_g / app_p == pytest.approx(24 / 60)
    assert rec_g / rec_p == pytest.approx(24 / 60)
    # Total pinion angle of action = Z / r_b  (arc of action Z/cos(phi) over r).
    assert app_p + rec_p == pytest.approx(pair.length_of_action / (1.5 * math.cos(20 * DEG)))


# --------------------------------------------------------------------------
# Interference and minimum teeth
# --------------------------------------------------------------------------
def test_min_teeth_against_rack_norton_table_9_4():
    # Norton, Design of Machinery, Table 9-4 (full-depth pinion vs full-depth rack).
    assert min_teeth_rack(14.5 * DEG) == 32
    assert min_teeth_rack(20 * DEG) == 18
    assert min_teeth_rack(25 * DEG) == 12
    assert min_pinion_teeth(np.inf, 20 * DEG) == 18


def test_max_gear_for_20_deg_pinions_norton_table_9_5():
    # Norton Table 9-5 / Shigley Sec. 13-7 (20 deg full depth): pinion -> largest gear.
    published = {17: 1309, 16: 101, 15: 45, 14: 26, 13: 16}
    for n_p, n_g in published.items():
        assert max_gear_teeth(n_p, 20 * DEG) == n_g
        assert min_pinion_teeth(n_g, 20 * DEG) == n_p
        assert min_pinion_teeth(n_g + 1, 20 * DEG) == n_p + 1


def _interferes_geometrically(n_p, n_g, phi, k=1.0):
    """Brute force, no shared code: does the gear tip pass the pinion's tangent point?"""
    rp, rg = n_p / 2, n_g / 2  # module 1
    c = rp + rg
    rbg = rg * math.cos(phi)
    return math.sqrt((rg + k) ** 2 - rbg**2) > c * math.sin(phi) + 1e-12


@pytest.mark.parametrize(("phi_deg", "published"), [(14.5, 23), (20.0, 13), (25.0, 9)])
def test_min_teeth_equal_gears(phi_deg, published):
    # 20 deg: 13 teeth (Shigley Example 13-1 / eq. 13-10). 14.5 and 25 deg: checked by the
    # geometric brute force below rather than a table at hand.
    phi = phi_deg * DEG
    brute = next(n for n in range(3, 100) if not _interferes_geometrically(n, n, phi))
    assert brute == published
    assert min_teeth_equal_gears(phi) == published


@pytest.mark.parametrize("phi_deg", [14.5, 20.0, 25.0])
@pytest.mark.parametrize("k", [1.0, 0.8])
def test_onset_relation_matches_geometric_interference(phi_deg, k):
    phi = phi_deg * DEG
    for n_p in range(8, 40):
        limit = onset_gear_teeth(n_p, phi, k)
        for n_g in (n_p, n_p + 5, 2 * n_p, 5 * n_p, 1000):
            if abs(n_g - limit) < 1e-6:
                continue
            assert _interferes_geometrically(n_p, n_g, phi, k) == (n_g > limit), (n_p, n_g)


@given(
    n_g=st.integers(10, 3000),
    phi_deg=st.sampled_from([14.5, 20.0, 22.5, 25.0]),
    k=st.sampled_from([1.0, 0.8]),
)
def test_min_pinion_teeth_matches_geometric_search(n_g, phi_deg, k):
    # a pinion is the smaller gear (n ≤ n_g, where the gear's tip is the one that interferes);
    # a gear below the equal-gear minimum meshes with none (ModelError, not a larger "pinion")
    phi = phi_deg * DEG
    fits = [n for n in range(3, min(n_g, 200) + 1) if not _interferes_geometrically(n, n_g, phi, k)]
    if fits:
        assert min_pinion_teeth(n_g, phi, k) == fits[0]
    else:
        with pytest.raises(ModelError, match="no pinion meshes"):
            min_pinion_teeth(n_g, phi, k)


def test_gear_pair_interference_flag():
    pair = GearPair(Gear(13, module=1.0), Gear(17, module=1.0))
    assert pair.interference == (True, False)
    assert pair.interferes
    assert not GearPair(Gear(13, module=1.0), Gear(16, module=1.0)).interferes


@pytest.mark.parametrize("n_p", [12, 16, 18, 24, 30])
@pytest.mark.parametrize("n_g", [40, 60, 100, 160, 400])
def test_internal_involute_interference_matches_khk_condition(n_p, n_g):
    # KHK Gear Technical Reference (internal gears): no involute interference iff
    # z1/z2 >= 1 - tan(alpha_a2)/tan(alpha_w), alpha_a2 = acos(d_b2/d_a2) at the ring's tip.
    ring = Gear(n_g, module=1.0, internal=True)
    pair = GearPair(Gear(n_p, module=1.0), ring)
    alpha_a2 = math.acos(ring.base_radius / ring.addendum_radius)
    ok = n_p / n_g >= 1 - math.tan(alpha_a2) / math.tan(20 * DEG)
    assert pair.interference[0] == (not ok)


def test_undercut_and_profile_shift():
    phi = 20 * DEG
    # No shift needed exactly at the rack limit 2/sin^2(phi) = 17.1: 17 undercut, 18 not.
    assert undercut(17, phi) and not undercut(18, phi)
    x = min_profile_shift(12, phi)
    assert x == pytest.approx(1 - 12 * math.sin(phi) ** 2 / 2)
    assert not undercut(12, phi, profile_shift=x + 1e-6)
    assert undercut(12, phi, profile_shift=x - 1e-3)
    # Consistency with the rack limit: zero shift at N = 2k/sin^2(phi).
    assert min_profile_shift(18, phi) < 0 < min_profile_shift(17, phi)


# --------------------------------------------------------------------------
# Bad input
# --------------------------------------------------------------------------
def test_fractional_teeth_rejected():
    with pytest.raises(InputError, match="teeth"):
        Gear(20.5, module=1)


def test_too_few_teeth_rejected():
    with pytest.raises(InputError, match="teeth"):
        Gear(2, module=1)
    with pytest.raises(InputError, match="pointed"):
        Gear(5, module=1, profile_shift=0.8)


def test_module_and_pitch_both_or_neither_rejected():
    with pytest.raises(InputError, match="exactly one"):
        Gear(20)
    with pytest.raises(InputError, match="exactly one"):
        Gear(20, module=1, diametral_pitch=1)


def test_bad_system_lists_choices():
    with pytest.raises(InputError, match="full_depth, stub"):
        Gear(20, module=1, system="deep")


def test_pressure_angle_in_degrees_by_mistake():
    with pytest.raises(InputError, match="degrees"):
        Gear(20, module=1, pressure_angle=20)


def test_mismatched_pitch_rejected():
    with pytest.raises(InputError, match="pitch"):
        GearPair(Gear(20, diametral_pitch=8), Gear(40, diametral_pitch=10))


def test_mismatched_pressure_angle_rejected():
    with pytest.raises(InputError, match="pressure-angle"):
        GearPair(Gear(20, module=2), Gear(40, module=2, pressure_angle=25 * DEG))


def test_center_distance_too_small_rejected():
    pair = GearPair(Gear(20, module=2), Gear(40, module=2))
    with pytest.raises(InputError, match="jam"):
        pair.with_center_distance(59.9)
    # Thinned teeth allow a smaller centre distance, until a tip hits a root.
    thin = GearPair(
        Gear(20, module=2, thickness_reduction=0.6), Gear(40, module=2, thickness_reduction=0.6)
    )
    ok = thin.with_center_distance(59.6)
    assert ok.backlash > 0
    with pytest.raises(InputError, match="clearance"):
        thin.with_center_distance(59.4)  # clearance is 0.25 m = 0.5


def test_internal_pinion_and_small_ring_rejected():
    with pytest.raises(InputError, match="pinion"):
        GearPair(Gear(60, module=1, internal=True), Gear(20, module=1))
    with pytest.raises(InputError, match="more teeth"):
        GearPair(Gear(30, module=1), Gear(30, module=1, internal=True))


def test_errors_are_machdyn_errors():
    with pytest.raises(MachdynError):
        length_of_action(-1, 0.1, 1, 0.1, 20 * DEG)
    with pytest.raises(MachdynError):
        contact_ratio(0.5, 0.0)
    with pytest.raises(MachdynError):
        min_pinion_teeth(20.5, 20 * DEG)


# --------------------------------------------------------------------------
# Review finding 2: centre distances at which the teeth no longer reach
# --------------------------------------------------------------------------
def _tip_circles_meet_on_line_of_action(pair, c_op):
    """Distance from the line of action to the crossing of the two tip circles.

    Plane coordinates, independent of Z: the pinion at the origin, the gear at
    (C', 0); the tip circles cross at x = (C'^2 + r_ap^2 - r_ag^2) / (2 C'); the
    line of action is n.x = r_bp with n_x = (r_bp +- r_bg) / C'. Zero at the
    centre distance where contact is lost (both ends of the path of contact meet).
    """
    p, g = pair.pinion, pair.gear
    rap, rag = p.addendum_radius, g.addendum_radius
    x = (c_op**2 + rap**2 - rag**2) / (2 * c_op)
    y = math.sqrt(rap**2 - x**2)
    sign = -1.0 if pair.internal else 1.0
    nx = (p.base_radius + sign * g.base_radius) / c_op
    ny = math.sqrt(1 - nx**2)
    return min(abs(nx * x + ny * yy - p.base_radius) for yy in (y, -y))


@pytest.mark.parametrize(
    ("pinion", "gear"),
    [
        (Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8)),
        (Gear(20, module=2), Gear(40, module=2)),
        (Gear(13, module=1, pressure_angle=25 * DEG), Gear(90, module=1, pressure_angle=25 * DEG)),
        (Gear(20, module=2), Gear(60, module=2, internal=True)),
    ],
)
def test_contact_limit_is_where_the_tip_circles_meet_on_the_line_of_action(pinion, gear):
    pair = GearPair(pinion, gear)
    limit = pair.contact_limit
    assert _tip_circles_meet_on_line_of_action(pair, limit) == pytest.approx(0.0, abs=1e-9)
    # Just inside the limit there is a little contact left, never a negative Z.
    inside = limit * (0.999 if not pair.internal else 1.001)
    if pair.internal:
        assert inside < pair.center_distance
    close = pair.with_center_distance(inside)
    assert 0 < close.length_of_action < 0.1 * pair.base_pitch
    assert close.contact_ratio_rating == "no contact"
    # At and beyond it the pair is refused.
    beyond = limit * (1.01 if not pair.internal else 0.99)
    for c_op in (limit, beyond):
        with pytest.raises(InputError, match="lose contact") as err:
            pair.with_center_distance(c_op)
        assert err.value.field == "center_distance"
        assert f"{limit:.6g}" in err.value.message


def test_review_reproducer_gear_pair_pulled_apart():
    # 20/40 teeth, m = 2: tip radii 22 and 42; at C' = 70 they are 6 apart on the line of
    # centres (22 + 42 = 64 < 70), so there can be no contact at all.
    with pytest.raises(InputError, match="too large: the teeth lose contact"):
        GearPair(Gear(20, module=2), Gear(40, module=2), center_distance=70.0)
    # The notes' exam set at 7.5 in: addendum circles 1.625 + 3.875 = 5.5 do not touch.
    with pytest.raises(InputError, match="lose contact"):
        GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8), center_distance=7.5)


def test_length_of_action_refuses_a_centre_distance_without_contact():
    # The exam set, by hand: z_p = sqrt(1.625^2 - 1.40954^2) = 0.80859,
    # z_g = sqrt(3.875^2 - 3.52385^2) = 1.61186, r_bp + r_bg = 4.93339, so contact ends at
    # C' = sqrt(2.42046^2 + 4.93339^2) = 5.49518 in.
    args = (3.75, 0.125, 1.5, 0.125, 20 * DEG)
    assert length_of_action(*args, center_distance=5.49) > 0
    with pytest.raises(InputError, match="lose contact") as err:
        length_of_action(*args, center_distance=6.0)
    assert err.value.field == "center_distance" and "5.4951" in err.value.message
    with pytest.raises(InputError, match="lose contact"):
        length_of_action(*args, center_distance=[5.3, 6.0])
    for bad in (np.nan, np.inf, [5.3, np.nan]):
        with pytest.raises(InputError, match="center_distance"):
            length_of_action(*args, center_distance=bad)
    with pytest.raises(InputError, match="a_pinion"):  # no addendum, no contact
        length_of_action(3.75, 0.0, 1.5, 0.0, 20 * DEG)


def test_contact_ratio_refuses_negative_or_nan_length_of_action():
    for bad in (-1.0, np.nan, [0.5, -0.1], np.inf):
        with pytest.raises(InputError, match="length_of_action"):
            contact_ratio(bad, 1.0)
    assert contact_ratio(0.0, 1.0) == 0.0
    assert gears.contact_ratio_rating(0.0) == "no contact"
    for bad in (np.nan, -0.5):
        with pytest.raises(InputError, match="contact_ratio"):
            gears.contact_ratio_rating(bad)


def test_operating_pressure_angle_refuses_nan_and_degrees():
    with pytest.raises(InputError, match="center_distance"):
        gears.operating_pressure_angle(10.0, np.nan, 20 * DEG)
    with pytest.raises(InputError, match="degrees"):
        gears.operating_pressure_angle(10.0, 10.2, 20)


def test_internal_pair_limits_are_worded_for_an_internal_pair():
    # A pinion inside a ring is pushed deeper into mesh by a LARGER centre distance.
    pair = GearPair(Gear(20, module=2), Gear(60, module=2, internal=True))
    with pytest.raises(InputError, match="too large: the teeth jam"):
        pair.with_center_distance(40.2)
    with pytest.raises(InputError, match=r"too large: a tooth tip.*at most 40\.5"):
        pair.with_center_distance(41.0)  # clearance 0.25 m = 0.5
    with pytest.raises(InputError, match="too small: the teeth lose contact"):
        pair.with_center_distance(18.0)


# --------------------------------------------------------------------------
# Review finding 10: unit guard of the backlash estimate (and NaN in willis)
# --------------------------------------------------------------------------
def test_backlash_from_center_distance_rejects_degrees_and_nan():
    with pytest.raises(InputError, match="degrees"):
        gears.backlash_from_center_distance(0.1, 20)
    with pytest.raises(InputError, match="center_distance_increase"):
        gears.backlash_from_center_distance(np.nan, 20 * DEG)
    with pytest.raises(InputError, match="pressure_angle"):
        gears.backlash_from_center_distance(0.1, np.nan)
    pint = pytest.importorskip("pint")
    ureg = pint.UnitRegistry()
    assert gears.backlash_from_center_distance(0.1, 20 * ureg.degree) == pytest.approx(
        0.2 * math.tan(20 * DEG)
    )


def test_willis_rejects_nan():
    for kwargs in ({"first": np.nan, "arm": 1.0}, {"first": 1.0, "arm": np.nan}):
        with pytest.raises(InputError):
            gears.willis(-0.5, **kwargs)
    with pytest.raises(InputError, match="train_value"):
        gears.willis(np.nan, first=1.0, arm=0.0)
    with pytest.raises(InputError, match="last"):
        gears.willis(-0.5, last=np.inf, arm=0.0)


# --------------------------------------------------------------------------
# Review finding 9: shape mismatches are InputErrors naming the argument
# --------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: length_of_action([3.75, 4], 0.125, [1.5, 2, 3], 0.125, 20 * DEG), "r_pinion"),
        (
            lambda: length_of_action([3.75] * 2, 0.125, 1.5, 0.125, 0.35, [5.3] * 3),
            "center_distance",
        ),
        (lambda: contact_ratio([0.5, 0.6], [1.0, 1.0, 1.0]), "base_pitch"),
        (lambda: gears.backlash_from_center_distance([0.1, 0.2], [0.3] * 3), "pressure_angle"),
        (lambda: gears.operating_pressure_angle([10, 10], [10.1] * 3, 0.35), "center_distance"),
        (lambda: gears.base_pitch([1, 2], [20, 30, 40], 0.35), "teeth"),
        (lambda: onset_gear_teeth([17, 18], [0.3] * 3), "pressure_angle"),
        (lambda: min_pinion_teeth([40, 50], [0.3] * 3), "pressure_angle"),
        (lambda: min_profile_shift([12, 13], 0.35, [1.0] * 3), "k"),
        (lambda: undercut([12, 13], 0.35, [0.0] * 3), "profile_shift"),
        (lambda: gears.stage_ratio([20, 30], [40, 50, 60]), "driven"),
        (lambda: gears.sprocket_pitch_diameter([0.5, 0.75], [17, 18, 19]), "teeth"),
        (lambda: gears.willis([-0.5, -0.4], first=[1, 2, 3], arm=0.0), "first"),
    ],
)
def test_shape_mismatch_is_an_input_error(call, field):
    with pytest.raises(InputError, match="does not broadcast") as err:
        call()
    if field is not None:
        assert err.value.field == field


def test_tooth_thickness_at_guards_its_arguments():
    with pytest.raises(InputError, match="radius"):
        gears.tooth_thickness_at(np.nan, 10.0, 1.5, 20 * DEG)
    with pytest.raises(InputError, match="degrees"):
        gears.tooth_thickness_at(10.0, 10.0, 1.5, 20)
    with pytest.raises(InputError, match="pitch_radius"):
        gears.tooth_thickness_at(10.0, -10.0, 1.5, 20 * DEG)


def test_rating_of_an_interfering_pair_says_the_contact_ratio_is_overstated():
    # A 4-tooth pinion against 40 teeth at 20°: far below the minimum teeth, so the
    # gear's tip digs below the pinion's base circle and Z is not a real path of contact.
    from machdyn.gears import Gear, GearPair

    pair = GearPair(Gear(4, module=2), Gear(40, module=2))
    assert pair.interferes
    assert "interfere" in pair.contact_ratio_rating


# --------------------------------------------------------------------------
# Which member drives: approach and recess
# --------------------------------------------------------------------------
def _contact_by_driver(pair):
    """First contact, pitch point and last contact, found in the plane.

    Independent of ``GearPair``'s rule ("contact starts at the driven
    member's tip circle"): the test places the centres (pinion at the origin,
    gear at (C', 0)), builds the line of action tangent to both base circles,
    intersects it with both addendum circles, and orders the ends by the
    driver's motion. A flank is pushed along its normal, away from the
    driver's material: an external tooth's convex involute has its material
    on the side of its centre of curvature, the base-circle tangent point;
    a ring's tooth lies on the far side of its (concave) flank. So contact
    travels away from the driver's material, and the first contact is the
    end of the segment furthest towards it.
    """
    p, g, c_op = pair.pinion, pair.gear, pair.center_distance
    rbp, rbg = p.base_radius, g.base_radius
    og = np.array([c_op, 0.0])
    nx = (rbp - rbg if pair.internal else rbp + rbg) / c_op
    n = np.array([nx, math.sqrt(1 - nx**2)])
    d = np.array([-n[1], n[0]])
    t_p = rbp * n  # pinion tangent point
    t_g = t_p + (d @ (og - t_p)) * d  # gear tangent point: foot of the gear centre

    def hit(center, radius):
        q = t_p - center
        roots = np.real(np.roots([1.0, 2 * d @ q, q @ q - radius**2]))
        return [t_p + t * d for t in roots]

    # The pitch point: where the line crosses the line of centres (y = 0).
    pitch = t_p - (t_p[1] / d[1]) * d

    # A tip circle cuts the line twice, symmetrically about the member's own tangent point;
    # the tip point of the contact is the one on the pitch point's side.
    def tip_point(center, radius, tangent):
        return next(q for q in hit(center, radius) if (q - tangent) @ (pitch - tangent) > 0)

    gear_tip = tip_point(og, g.addendum_radius, t_g)
    pinion_tip = tip_point(np.zeros(2), p.addendum_radius, t_p)
    if pair.driver == "pinion":
        towards_material = t_p - pitch
    else:
        towards_material = (pitch - t_g) if pair.internal else (t_g - pitch)
    ends = sorted([gear_tip, pinion_tip], key=lambda q: -(q @ towards_material))
    return ends[0], pitch, ends[1], (np.zeros(2), og)


def _roll_angle(point, center, r_base):
    """``tan φ_Q`` of the contact point Q on an involute: the angle unwound from the base."""
    return math.tan(math.acos(r_base / np.linalg.norm(point - center)))


PAIRS = [
    (Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8), None),  # notes' exam set
    (Gear(18, module=2.0), Gear(41, module=2.0), 59.6),  # pulled apart: φ' ≠ φ
    (Gear(14, module=1.0, profile_shift=0.35), Gear(31, module=1.0, profile_shift=-0.1), None),
    (Gear(25, module=3.0, pressure_angle=25 * DEG), Gear(25, module=3.0, pressure_angle=25 * DEG),
     None),
    (Gear(20, module=2.0), Gear(80, module=2.0, internal=True), None),
    (Gear(28, module=1.5, profile_shift=0.2), Gear(70, module=1.5, internal=True), None),
]  # fmt: skip


@pytest.mark.parametrize(("pinion", "gear", "c_op"), PAIRS)
@pytest.mark.parametrize("driver", ["pinion", "gear"])
def test_approach_and_recess_from_line_of_action_coordinates(pinion, gear, c_op, driver):
    pair = GearPair(pinion, gear, c_op, driver=driver)
    first, pitch, last, (o_p, o_g) = _contact_by_driver(pair)
    assert pair.path_of_approach == pytest.approx(np.linalg.norm(first - pitch), rel=1e-9)
    assert pair.path_of_recess == pytest.approx(np.linalg.norm(last - pitch), rel=1e-9)
    # Norton: approach starts on the driven member's tip circle, recess ends on the driver's.
    driven_centre, driven_tip = (
        (o_g, gear.addendum_radius) if driver == "pinion" else (o_p, pinion.addendum_radius)
    )
    assert np.linalg.norm(first - driven_centre) == pytest.approx(driven_tip, rel=1e-12)
    # Angles turned: the difference of the roll angles tan φ_Q of the involutes through the
    # first contact and the pitch point (and the pitch point and the last contact).
    app = pair.angles_of_approach
    rec = pair.angles_of_recess
    for k, (centre, r_b) in enumerate(((o_p, pinion.base_radius), (o_g, gear.base_radius))):
        roll = [_roll_angle(q, centre, r_b) for q in (first, pitch, last)]
        assert app[k] == pytest.approx(abs(roll[1] - roll[0]), rel=1e-9)
        assert rec[k] == pytest.approx(abs(roll[2] - roll[1]), rel=1e-9)
        # The pitch circles roll without slip: the arcs (angle x operating pitch radius,
        # the radius read from the pitch point's position) are the same on both members.
        r_pitch = np.linalg.norm(pitch - centre)
        assert pair.arc_of_approach == pytest.approx(app[k] * r_pitch, rel=1e-9)
        assert pair.arc_of_recess == pytest.approx(rec[k] * r_pitch, rel=1e-9)


@given(
    n_p=st.integers(12, 40),
    extra=st.integers(1, 90),
    x_p=st.floats(0.0, 0.5),
    stretch=st.floats(0.0, 0.015),
    internal=st.booleans(),
)
def test_gear_driving_swaps_approach_and_recess(n_p, extra, x_p, stretch, internal):
    n_g = n_p + extra + (12 if internal else 0)
    try:
        p = Gear(n_p, module=1.0, profile_shift=x_p)
        g = Gear(n_g, module=1.0, internal=internal)
        pair = GearPair(p, g)
        pair = pair.with_center_distance(
            pair.center_distance * ((1 - stretch) if internal else (1 + stretch))
        )
    except InputError:  # pointed or out of contact: not a pair to mesh
        assume(False)
    back = pair.with_driver("gear")
    assert back.driver == "gear" and pair.driver == "pinion"
    assert back.path_of_approach == pytest.approx(pair.path_of_recess, rel=1e-12)
    assert back.path_of_recess == pytest.approx(pair.path_of_approach, rel=1e-12)
    assert back.angles_of_approach == pytest.approx(pair.angles_of_recess, rel=1e-12)
    assert back.angles_of_recess == pytest.approx(pair.angles_of_approach, rel=1e-12)
    # Only the split changes.
    z = pair.length_of_action
    assert back.path_of_approach + back.path_of_recess == pytest.approx(z, rel=1e-9)
    assert back.contact_ratio == pair.contact_ratio
    assert back.with_center_distance(pair.center_distance).driver == "gear"
    # Roles mirrored: an external pair with the gear driving is the same mesh as the gear
    # taken for the "pinion" and driving; the (pinion, gear) angle pairs swap places.
    if not internal:
        mirrored = GearPair(g, p, pair.center_distance)
        assert back.path_of_approach == pytest.approx(mirrored.path_of_approach, rel=1e-9)
        assert back.path_of_recess == pytest.approx(mirrored.path_of_recess, rel=1e-9)
        assert back.angles_of_approach[::-1] == pytest.approx(mirrored.angles_of_approach, rel=1e-9)
        assert back.angles_of_recess[::-1] == pytest.approx(mirrored.angles_of_recess, rel=1e-9)


def test_approach_and_recess_final_exam_set_by_hand():
    # The notes' final exam, problem 10, intermediate values worked by hand: the gear's tip
    # circle cuts the line of action sqrt(3.875^2 - 3.52385^2) = 1.6119 in from the gear's
    # tangent point, the pinion's 0.8086 in from its own; r_g sin 20 = 1.2826,
    # r_p sin 20 = 0.5130. Pinion driving: approach 1.6119 - 1.2826 = 0.3293 in,
    # recess 0.8086 - 0.5130 = 0.2956 in; pinion angles 0.3293 / 1.40954 = 13.39 deg and
    # 0.2956 / 1.40954 = 12.02 deg. Gear driving: the two swap.
    pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
    assert pair.path_of_approach == pytest.approx(0.3293, abs=1e-4)
    assert pair.path_of_recess == pytest.approx(0.2956, abs=1e-4)
    assert math.degrees(pair.angles_of_approach[0]) == pytest.approx(13.39, abs=0.01)
    assert math.degrees(pair.angles_of_recess[0]) == pytest.approx(12.02, abs=0.01)
    up = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8), driver="gear")
    assert up.path_of_approach == pytest.approx(0.2956, abs=1e-4)
    assert up.path_of_recess == pytest.approx(0.3293, abs=1e-4)
    summary = up.summary()
    assert summary["driver"] == "gear"
    assert summary["path_of_approach"] == pytest.approx(0.2956, abs=1e-4)
    assert summary["angle_of_approach_pinion_deg"] == pytest.approx(12.02, abs=0.01)
    assert summary["angle_of_recess_gear_deg"] == pytest.approx(13.39 * 24 / 60, abs=0.01)


@pytest.mark.parametrize("driver", ["ring", "Gear", None, 1])
def test_driver_must_be_pinion_or_gear(driver):
    with pytest.raises(InputError, match="driver: must be one of pinion, gear"):
        GearPair(Gear(20, module=1.0), Gear(40, module=1.0), driver=driver)


# --------------------------------------------------------------------------
# Profile-shifted internal gears
# --------------------------------------------------------------------------
def test_shifted_internal_pair_published_worksheet():
    # A published centre-distance worksheet for a profile-shifted internal pair (the KHK /
    # SDP-SI relation inv a_w = inv a + 2 tan a (x2 - x1) / (z2 - z1)): z1 = 17, z2 = 96,
    # m = 14 mm, x1 = 0.2, x2 = 0.5, a = 20 deg -> inv a_w = 0.01766871, a_w = 21.1251 deg,
    # centre distance 557.0887 mm.
    pair = GearPair(
        Gear(17, module=14.0, profile_shift=0.2), Gear(96, module=14.0, internal=True,
                                                       profile_shift=0.5)
    )  # fmt: skip
    phi_w = pair.operating_pressure_angle
    assert math.tan(phi_w) - phi_w == pytest.approx(0.01766871, abs=1e-8)
    assert math.degrees(phi_w) == pytest.approx(21.1251, abs=1e-4)
    assert pair.center_distance == pytest.approx(557.0887, abs=1e-4)
    assert pair.backlash == pytest.approx(0.0, abs=1e-9)
    # The ring: tip circle r - (1 - x) m = 672 - 7 = 665, root r + (1.25 + x) m = 696.5,
    # pitch-circle tooth 14 (1.570796 - 0.363970) = 16.8956 mm.
    ring = pair.gear
    assert ring.addendum_radius == pytest.approx(665.0)
    assert ring.root_radius == pytest.approx(696.5)
    assert ring.tooth_thickness == pytest.approx(16.8956, abs=1e-4)


@given(
    n_p=st.integers(14, 40),
    diff=st.integers(14, 80),
    x_p=st.floats(-0.2, 0.5),
    x_g=st.floats(-0.3, 0.8),
    stretch=st.floats(0.0, 0.01),
)
def test_shifted_internal_pair_tight_mesh_and_line_of_action(n_p, diff, x_p, x_g, stretch):
    n_g = n_p + diff
    try:
        p = Gear(n_p, module=1.0, profile_shift=x_p)
        g = Gear(n_g, module=1.0, internal=True, profile_shift=x_g)
        pair = GearPair(p, g)
    except InputError:  # pointed, tip inside the base circle, or tips that hit: not a pair
        assume(False)
    inv = math.tan(20 * DEG) - 20 * DEG + 2 * math.tan(20 * DEG) * (x_g - x_p) / (n_g - n_p)
    phi_op = pair.operating_pressure_angle
    assert math.tan(phi_op) - phi_op == pytest.approx(inv, rel=1e-10)
    assert pair.backlash == pytest.approx(0.0, abs=1e-10)
    # Pulled apart (for a ring: centres closer), the backlash is about 2 |dC| tan(phi').
    try:
        wide = pair.with_center_distance(pair.center_distance * (1 - stretch))
    except InputError:  # the teeth lose contact
        assume(False)
    expected = _contact_segment(
        p.base_radius, p.addendum_radius, g.base_radius, g.addendum_radius,
        wide.center_distance, True,
    )  # fmt: skip
    assert wide.length_of_action == pytest.approx(expected, rel=1e-9)
    # dB/dC = 2 tan(phi'(C)) and phi' moves monotonically with C, so the backlash lies
    # between 2 |dC| tan(phi') at the tight and at the new centre distance
    dc = pair.center_distance - wide.center_distance
    bounds = sorted(2 * dc * math.tan(q.operating_pressure_angle) for q in (pair, wide))
    assert bounds[0] * (1 - 1e-9) - 1e-12 <= wide.backlash <= bounds[1] * (1 + 1e-9) + 1e-12
