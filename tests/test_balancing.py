"""Balancing: the notes' Problem 12-6, the final-exam tire, and force/moment invariants."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from machdyn.balancing import (
    TwoPlaneBalance,
    bearing_balance,
    shaking_force,
    shaking_moment,
    static_balance,
    two_plane,
)
from machdyn.errors import InputError

G_IN = 386.4  # in/s², the g the notes use to turn blobs into lb (W_A = 5.6338 lb)


def polar_deg(magnitude: float, angle_deg: float) -> complex:
    return magnitude * complex(math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg)))


def residual_force_and_moment(forces, z, about):
    """Σ F and Σ (z − about) k̂ × F with explicit x, y components (no complex algebra)."""
    fx = sum(f.real for f in forces)
    fy = sum(f.imag for f in forces)
    # k̂ × (Fx î + Fy ĵ) = −Fy î + Fx ĵ
    mx = sum(-(zi - about) * f.imag for f, zi in zip(forces, z, strict=True))
    my = sum((zi - about) * f.real for f, zi in zip(forces, z, strict=True))
    return math.hypot(fx, fy), math.hypot(mx, my)


# --- the notes' Problem 12-6 (Norton Fig. 12-12 wheel balancer) ------------------------
# Left bearing F_L = 5/√2 (1 + j) lb, right bearing F_R = −1 − j√3 lb. Moments about rim
# plane A: the left bearing's lever is −14 in, the right one's −4 in, plane B is at +7 in;
# rim radius 7.5 in. The notes take ω = 200π/60 = 10π/3 rad/s.
OMEGA_12_6 = 10 * math.pi / 3
F_L = 5 / math.sqrt(2) * (1 + 1j)
F_R = -1 - 1j * math.sqrt(3)


def test_problem_12_6_printed_values():
    fix = bearing_balance([F_L, F_R], [-14.0, -4.0], OMEGA_12_6, plane_a=0.0, plane_b=7.0)
    m_a, m_b = fix.masses(7.5)
    # Intermediate lines of the worked solution (printed to 4 decimals):
    # 5757.2692 m_B cos θ_B = 45.4975, 5757.2692 m_B sin θ_B = 42.5693
    assert 7 * OMEGA_12_6**2 * fix.mR_b.real == pytest.approx(45.4975, abs=5e-5)
    assert 7 * OMEGA_12_6**2 * fix.mR_b.imag == pytest.approx(42.5693, abs=5e-5)
    # 822.4670 m_A cos θ_A = −9.0352, 822.4670 m_A sin θ_A = −7.8848
    assert OMEGA_12_6**2 * fix.mR_a.real == pytest.approx(-9.0352, abs=5e-5)
    assert OMEGA_12_6**2 * fix.mR_a.imag == pytest.approx(-7.8848, abs=5e-5)
    # θ_B = 43.09° (the notes truncate 43.096°), m_B = .0108 blob, W_B = 4.1814 lb
    assert fix.angle_b_deg == pytest.approx(43.09, abs=0.01)
    assert m_b == pytest.approx(0.0108, abs=5e-5)
    assert m_b * G_IN == pytest.approx(4.1814, abs=1e-3)
    # θ_A = 221.11°, m_A = .0146 blob, W_A = 5.6338 lb
    assert fix.angle_a_deg == pytest.approx(221.11, abs=5e-3)
    assert m_a == pytest.approx(0.0146, abs=5e-5)
    assert m_a * G_IN == pytest.approx(5.6338, abs=1e-4)
    assert fix.theta_a == pytest.approx(3.8591 - 2 * math.pi, abs=1e-4)  # 3.8591 rad


def test_problem_12_6_corrected_wheel_loads_no_bearing():
    fix = bearing_balance([F_L, F_R], [-14.0, -4.0], OMEGA_12_6, 0.0, 7.0)
    w2 = OMEGA_12_6**2
    forces = [F_L, F_R, w2 * fix.mR_a, w2 * fix.mR_b]
    z = [-14.0, -4.0, 0.0, 7.0]
    for about in (-14.0, 0.0, 3.3):
        force, moment = residual_force_and_moment(forces, z, about)
        assert force < 1e-12 and moment < 1e-11


def test_true_200_rpm_gives_quarter_masses_same_angles():
    notes = bearing_balance([F_L, F_R], [-14.0, -4.0], OMEGA_12_6, 0.0, 7.0)
    true = bearing_balance([F_L, F_R], [-14.0, -4.0], 200 * 2 * math.pi / 60, 0.0, 7.0)
    np.testing.assert_allclose(true.masses(7.5), np.array(notes.masses(7.5)) / 4, rtol=1e-12)
    assert true.angle_a_deg == pytest.approx(notes.angle_a_deg)
    assert true.angle_b_deg == pytest.approx(notes.angle_b_deg)


def test_pint_rpm_is_converted():
    import pint

    ureg = pint.UnitRegistry()
    a = bearing_balance([F_L, F_R], [-14.0, -4.0], 100 * ureg.rpm, 0.0, 7.0)
    b = bearing_balance([F_L, F_R], [-14.0, -4.0], OMEGA_12_6, 0.0, 7.0)
    assert a.mR_a == pytest.approx(b.mR_a, rel=1e-12)


# --- final exam, problem 8: the tire --------------------------------------------------
# 10 rad/s; left bearing 12 N ∠ 75°, right bearing 10 N ∠ −30°; bearings 25 cm apart; the
# rim's left edge (plane A) 10 cm from the closest bearing; rim 17.5 cm wide (plane B);
# rim diameter 37.5 cm. The layout is the one of Problem 12-6 (the wheel overhangs to the
# right of both bearings): z_L = −35 cm, z_R = −10 cm, z_A = 0, z_B = 17.5 cm.
# No printed answer exists, so we solve it by hand here, in x/y components.


def exam_tire_by_hand():
    omega, radius = 10.0, 0.375 / 2
    flx, fly = 12 * math.cos(math.radians(75)), 12 * math.sin(math.radians(75))
    frx, fry = 10 * math.cos(math.radians(-30)), 10 * math.sin(math.radians(-30))
    # Σ M_A = 0:  −0.35 k̂×F_L − 0.10 k̂×F_R + 0.175 k̂×(m_B ω² R_B) = 0, component-wise
    bx = (0.35 * flx + 0.10 * frx) / (0.175 * omega**2)  # m_B R_Bx
    by = (0.35 * fly + 0.10 * fry) / (0.175 * omega**2)
    # Σ F = 0:  F_L + F_R + ω² (m_A R_A + m_B R_B) = 0
    ax = -(flx + frx) / omega**2 - bx
    ay = -(fly + fry) / omega**2 - by
    m_b, theta_b = math.hypot(bx, by) / radius, math.degrees(math.atan2(by, bx)) % 360
    m_a, theta_a = math.hypot(ax, ay) / radius, math.degrees(math.atan2(ay, ax)) % 360
    return m_a, theta_a, m_b, theta_b


def test_exam_tire_against_hand_solution():
    f_left, f_right = polar_deg(12, 75), polar_deg(10, -30)
    fix = bearing_balance([f_left, f_right], [-0.35, -0.10], 10.0, plane_a=0.0, plane_b=0.175)
    m_a, m_b = fix.masses(0.375 / 2)
    hand_a, hand_theta_a, hand_b, hand_theta_b = exam_tire_by_hand()
    assert m_b == pytest.approx(hand_b, rel=1e-12)
    assert fix.angle_b_deg == pytest.approx(hand_theta_b, abs=1e-9)
    assert m_a == pytest.approx(hand_a, rel=1e-12)
    assert fix.angle_a_deg == pytest.approx(hand_theta_a, abs=1e-9)
    # After correction the bearings feel nothing: force and moment about the left bearing.
    w2 = 100.0
    forces = [f_left, f_right, w2 * fix.mR_a, w2 * fix.mR_b]
    force, moment = residual_force_and_moment(forces, [-0.35, -0.10, 0.0, 0.175], about=-0.35)
    assert force < 1e-12 and moment < 1e-12


# --- invariants ----------------------------------------------------------------------

coords = st.floats(-10.0, 10.0, allow_nan=False)


@given(
    masses=st.lists(st.tuples(coords, coords, coords), min_size=1, max_size=6),
    plane_a=coords,
    gap=st.floats(0.5, 10.0),
    about=coords,
)
def test_two_plane_cancels_force_and_moment(masses, plane_a, gap, about):
    unbalance = [complex(x, y) for x, y, _ in masses]
    z = [zi for _, _, zi in masses]
    plane_b = plane_a + gap
    mR_a, mR_b = two_plane(unbalance, z, plane_a, plane_b)
    omega = 3.0
    forces = [omega**2 * u for u in [*unbalance, mR_a, mR_b]]
    force, moment = residual_force_and_moment(forces, [*z, plane_a, plane_b], about)
    scale = omega**2 * (1 + sum(abs(u) for u in unbalance)) * 20
    assert force <= 1e-12 * scale
    assert moment <= 1e-11 * scale
    # The library's own shaking sums agree that the corrected rotor is balanced.
    total = [*unbalance, mR_a, mR_b]
    assert abs(shaking_force(total, omega)) <= 1e-12 * scale
    assert abs(shaking_moment(total, [*z, plane_a, plane_b], omega, about)) <= 1e-11 * scale


def test_shift_and_swap_invariance(rng):
    unbalance = rng.normal(size=5) + 1j * rng.normal(size=5)
    z = rng.uniform(-1.0, 4.0, size=5)
    base = two_plane(unbalance, z, 0.0, 3.0)
    shifted = two_plane(unbalance, z + 7.5, 7.5, 10.5)
    swapped = two_plane(unbalance, z, 3.0, 0.0)
    assert shifted.mR_a == pytest.approx(base.mR_a) and shifted.mR_b == pytest.approx(base.mR_b)
    assert swapped.mR_a == pytest.approx(base.mR_b) and swapped.mR_b == pytest.approx(base.mR_a)


def test_masses_in_a_correction_plane_need_only_that_plane():
    mR_a, mR_b = two_plane([1 + 2j, -3j], [2.0, 2.0], plane_a=2.0, plane_b=5.0)
    assert mR_a == pytest.approx(-(1 - 1j))
    assert mR_b == pytest.approx(0.0, abs=1e-15)


def test_static_balance_component_formulas():
    # Notes: m_b R_bx = −m1 R1x − m2 R2x, m_b R_by = −m1 R1y − m2 R2y,
    # tan θ_b = (m1 R1y + m2 R2y)/(m1 R1x + m2 R2x) (in the opposite quadrant).
    m1, r1, m2, r2 = 2.0, polar_deg(3.0, 30.0), 1.5, polar_deg(4.0, 160.0)
    fix = static_balance([m1 * r1, m2 * r2])
    mbRb = fix.mR
    sx = m1 * r1.real + m2 * r2.real
    sy = m1 * r1.imag + m2 * r2.imag
    assert mbRb.real == pytest.approx(-sx) and mbRb.imag == pytest.approx(-sy)
    assert abs(mbRb) == pytest.approx(math.sqrt(sx**2 + sy**2))
    assert math.tan(fix.theta) == pytest.approx(sy / sx)
    assert math.tan(math.radians(fix.angle_deg)) == pytest.approx(sy / sx)
    assert fix.mass(2.0) == pytest.approx(math.sqrt(sx**2 + sy**2) / 2.0)
    # The centre of mass is then on the axis: no shaking force.
    assert abs(shaking_force([m1 * r1, m2 * r2, mbRb], 50.0)) < 1e-10


def test_batches_broadcast(rng):
    unbalance = rng.normal(size=(4, 3)) + 1j * rng.normal(size=(4, 3))
    z = np.array([0.5, 1.0, 2.5])
    batch = two_plane(unbalance, z, 0.0, 3.0)
    assert batch.mR_a.shape == (4,)
    one = two_plane(unbalance[2], z, 0.0, 3.0)
    assert batch.mR_b[2] == pytest.approx(one.mR_b)
    assert static_balance(unbalance).mR.shape == (4,)
    assert batch.masses(2.0)[0].shape == (4,)


def test_result_object():
    result = two_plane([1.0 + 0j], [1.0], 0.0, 4.0)
    assert isinstance(result, TwoPlaneBalance)
    assert len(result) == 2 and len(tuple(result)) == 2
    # −U (z_B − z)/(z_B − z_A) = −3/4 at 180°; −U (z − z_A)/(...) = −1/4 at 180°.
    assert result.angle_a_deg == pytest.approx(180.0)
    assert result.masses(0.5, 0.25) == pytest.approx((1.5, 1.0))
    frame = result.to_pandas(radius_a=0.5)
    assert list(frame.index) == ["A", "B"]
    assert frame.loc["B", "mass"] == pytest.approx(0.5)
    assert two_plane([1j], [0.0], 0.0, 1.0).angle_a_deg == pytest.approx(270.0)


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: two_plane([1j], [1.0], 2.0, 2.0), "plane_b"),
        (lambda: two_plane([complex("nan")], [1.0], 0.0, 2.0), "unbalance"),
        (lambda: two_plane([1j, 1.0], [1.0, 2.0, 3.0], 0.0, 2.0), "z"),
        (lambda: two_plane([1j], [float("inf")], 0.0, 2.0), "z"),
        (lambda: two_plane([], [], 0.0, 2.0), "unbalance"),
        (lambda: two_plane(["a"], [1.0], 0.0, 2.0), "unbalance"),
        (lambda: bearing_balance([1j], [1.0], 0.0, 0.0, 1.0), "omega"),
        (lambda: two_plane([1j], [1.0], 0.0, 2.0).masses(-1.0), "radius_a"),
        (lambda: shaking_force([1j], float("nan")), "omega"),
        (lambda: static_balance([1j]).mass(0.0), "radius"),
        # review finding 7: one z for two masses used to be broadcast over both
        (lambda: two_plane([1, 2j], [1.0], 0.0, 1.0), "z"),
        (lambda: two_plane([1, 2j], 1.0, 0.0, 1.0), "z"),
        (lambda: shaking_moment([1, 2j], [1.0], 1.0), "z"),
        # a rotor needs two bearings to carry the moment
        (lambda: bearing_balance([1j], [1.0], 10.0, 0.0, 1.0), "bearing_forces"),
        (lambda: bearing_balance([1j, 1.0], [1.0], 10.0, 0.0, 1.0), "z_bearings"),
    ],
)
def test_bad_input(call, field):
    with pytest.raises(InputError) as info:
        call()
    assert info.value.field == field


# --- command line ----------------------------------------------------------------------


def test_cli_bearings_problem_12_6():
    import json

    from typer.testing import CliRunner

    from machdyn.cli.balance import balance_app

    args = ["bearings", "--force", "5,45,-14", "--force", "2,-120,-4", "--omega", "100"]
    args += ["--rpm", "--plane-a", "0", "--plane-b", "7", "--radius", "7.5", "--json"]
    result = CliRunner().invoke(balance_app, args)  # 100 rpm = the notes' 10π/3 rad/s
    assert result.exit_code == 0, result.output
    payload = json.loads(result.output)
    assert payload["mass"] == pytest.approx([0.0146, 0.0108], abs=5e-5)
    assert payload["angle_deg"] == pytest.approx([221.11, 43.09], abs=0.01)


def test_cli_rotor_and_static():
    import json

    from typer.testing import CliRunner

    from machdyn.cli.balance import balance_app

    runner = CliRunner()
    args = ["rotor", "--mass", "1,1,0,1", "--mass", "1,1,180,3", "--plane-a", "0"]
    args += ["--plane-b", "4", "--radius-a", "0.5", "--json"]
    rotor = runner.invoke(balance_app, args)
    payload = json.loads(rotor.output)
    # By hand: U = +1 at z=1, −1 at z=3 → m_A R_A = −(3 − 1)/4 = −0.5, m_B R_B = +0.5.
    assert payload["mR"] == pytest.approx([0.5, 0.5])
    assert payload["angle_deg"] == pytest.approx([180.0, 0.0], abs=1e-9)
    assert payload["mass"] == pytest.approx([1.0, 1.0])
    static = runner.invoke(balance_app, ["static", "--mass", "2,3,30", "--mass", "1.5,4,160"])
    assert static.exit_code == 0 and "275.0000" in static.output  # −(6∠30° + 6∠160°) = ·∠275°
    bad = runner.invoke(balance_app, ["static", "--mass", "2,3"])
    assert isinstance(bad.exception, InputError) and bad.exception.field == "--mass"


RUN = ("--omega", "10", "--plane-a", "0", "--plane-b", "7")


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (["static", "--mass", "-1,2,30"], "--mass"),  # used to flip 210° to 30°
        (["static", "--mass", "0,2,30"], "--mass"),
        (["static", "--mass", "1,-2,30"], "--mass"),
        (["rotor", "--mass", "1,-2,0,1", "--plane-a", "0", "--plane-b", "4"], "--mass"),
        (["rotor", "--mass", "-1,2,0,1", "--plane-a", "0", "--plane-b", "4"], "--mass"),
        (
            ["bearings", "--force", "-2,-120,-4", "--force", "5,45,-14", *RUN],
            "--force",
        ),
        (
            ["bearings", "--force", "5,45,-14", *RUN],
            "--force",
        ),
        (
            ["bearings", "--force", "5,45,-14", "--force", "2,-120,-4", "--force", "1,0,3", *RUN],
            "--force",
        ),
        (
            ["rotor", "--mass", "1,1,0,1", "--plane-a", "0", "--plane-b", "4", "--radius-a", "-1"],
            "--radius-a",
        ),
    ],
)
def test_cli_rejects_negative_masses_radii_forces(args, field):
    """Review finding 7: the CLI checked only finiteness; a negative m, R or F turned the
    answer by 180° and exited 0, and one bearing force was accepted."""
    from typer.testing import CliRunner

    from machdyn.cli.balance import balance_app

    out = CliRunner().invoke(balance_app, args)
    assert out.exit_code != 0
    assert isinstance(out.exception, InputError), out.output
    assert out.exception.field == field


def test_cli_zero_radius_mass_is_allowed():
    """R = 0 (a mass on the axis) is legal and contributes nothing."""
    import json

    from typer.testing import CliRunner

    from machdyn.cli.balance import balance_app

    args = ["static", "--mass", "2,3,30", "--mass", "5,0,90", "--json"]
    out = CliRunner().invoke(balance_app, args)
    assert out.exit_code == 0, out.output
    assert json.loads(out.output)["angle_deg"] == pytest.approx(210.0)
