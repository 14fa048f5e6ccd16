"""Rigid rotor in 3-D: H_O, ω × H_O, bearing reactions and two-plane balance.

Reference: the notes, Ch. 12 ("H0 = −Ixz ω i − Iyz ω j + Izz ω k, ω × H0 = Iyz ω² i − Ixz ω² j"),
and Newton–Euler for rotation about a fixed axis written out here with 3-D cross products.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.balancing import bearing_balance
from machdyn.errors import InputError
from machdyn.rotor import Rotor


def rz(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def hand_reactions(mass, cg, inertia_o, omega, alpha, theta, z_a, z_b, g):
    """Solve ΣF = m a_G and ΣM_O = I α + ω × (I ω) for F_A, F_B (x, y) and the torque T."""
    rot = rz(theta)
    r_g = rot @ cg
    inertia = rot @ inertia_o @ rot.T
    w = np.array([0.0, 0.0, omega])
    a = np.array([0.0, 0.0, alpha])
    a_g = np.cross(a, r_g) + np.cross(w, np.cross(w, r_g))
    weight = np.array([0.0, -mass * g, 0.0])
    h_dot = inertia @ a + np.cross(w, inertia @ w)
    # unknowns u = (FAx, FAy, FBx, FBy, T); columns are the effect of each unit unknown
    rows_f = np.zeros((3, 5))
    rows_m = np.zeros((3, 5))
    for k, (z, axis) in enumerate([(z_a, 0), (z_a, 1), (z_b, 0), (z_b, 1)]):
        f = np.zeros(3)
        f[axis] = 1.0
        rows_f[:, k] = f
        rows_m[:, k] = np.cross([0.0, 0.0, z], f)
    rows_m[2, 4] = 1.0  # the drive torque about z
    matrix = np.vstack([rows_f[:2], rows_m])
    rhs = np.concatenate([(mass * a_g - weight)[:2], h_dot - np.cross(r_g, weight)])
    fax, fay, fbx, fby, torque = np.linalg.solve(matrix, rhs)
    return complex(fax, fay), complex(fbx, fby), torque


def test_notes_angular_momentum_and_gyroscopic_moment_from_point_masses():
    # m1 = 2 at (0.1, 0, 0.2), m2 = 1 at (0, 0.05, 0.5): by hand
    # I_xz = Σ m x z = 2·0.1·0.2 = 0.04, I_yz = 1·0.05·0.5 = 0.025,
    # I_zz = Σ m (x² + y²) = 2·0.01 + 1·0.0025 = 0.0225
    rotor = Rotor.from_masses([2.0, 1.0], [0.1, 0.05j], [0.2, 0.5])
    assert rotor.I_xz == pytest.approx(0.04)
    assert rotor.I_yz == pytest.approx(0.025)
    assert rotor.I_zz == pytest.approx(0.0225)
    w = 30.0
    assert np.allclose(rotor.angular_momentum(w), [-0.04 * w, -0.025 * w, 0.0225 * w])
    assert np.allclose(rotor.gyroscopic_moment(w), [0.025 * w**2, -0.04 * w**2, 0.0])
    # vectorised over speeds
    assert rotor.gyroscopic_moment([1.0, 2.0]).shape == (2, 3)


def test_inertia_tensor_with_products_about_the_cg_is_moved_to_the_axis():
    # I_G with products, cg off the axis: I_O = I_G + m(|d|² E − d dᵀ) by hand
    m, d = 12.0, np.array([0.01, -0.02, 0.3])
    i_g = np.array([[0.40, -0.01, -0.03], [-0.01, 0.45, 0.02], [-0.03, 0.02, 0.60]])
    rotor = Rotor(m, d, i_g, about="cg")
    assert rotor.I_xz == pytest.approx(0.03 + m * 0.01 * 0.3)
    assert rotor.I_yz == pytest.approx(-0.02 + m * (-0.02) * 0.3)
    assert rotor.I_zz == pytest.approx(0.60 + m * (0.01**2 + 0.02**2))
    assert rotor.unbalance == pytest.approx(complex(m * 0.01, m * -0.02))
    same = Rotor(m, d, rotor.inertia, about="origin")
    assert np.allclose(same.inertia, rotor.inertia)


@pytest.mark.parametrize("seed", range(6))
def test_bearing_reactions_against_newton_euler_by_hand(seed):
    rng = np.random.default_rng(seed)
    m = rng.uniform(1, 20)
    d = rng.normal(0, [0.02, 0.02, 0.3])
    # physical: principal moments (b + c, a + c, a + b) of second moments a, b, c > 0,
    # in random principal axes (so every product of inertia is non-zero)
    sa, sb, sc = rng.uniform(0.05, 0.3, 3)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    i_g = q @ np.diag([sb + sc, sa + sc, sa + sb]) @ q.T
    rotor = Rotor(m, d, i_g, about="cg")
    z_a, z_b = -0.2, rng.uniform(0.3, 0.8)
    omega, alpha, theta, g = rng.uniform(-200, 200), rng.uniform(-500, 500), rng.uniform(0, 6), 9.81
    r = rotor.bearing_reactions(omega, z_a, z_b, alpha=alpha, theta=theta, gravity=g)
    fa, fb, torque = hand_reactions(m, d, rotor.inertia, omega, alpha, theta, z_a, z_b, g)
    scale = m * (omega**2 + abs(alpha) + g)
    assert abs(complex(r.reaction_a) - fa) < 1e-10 * scale
    assert abs(complex(r.reaction_b) - fb) < 1e-10 * scale
    assert float(r.torque) == pytest.approx(torque, rel=1e-9, abs=1e-9 * scale)
    assert np.allclose(r.load_a, -r.reaction_a)


def test_bearing_reactions_broadcast_over_a_turn():
    rotor = Rotor.from_masses([0.5, 0.3], [0.04, -0.05j], [0.1, 0.4])
    theta = np.linspace(0, 2 * np.pi, 9)
    r = rotor.bearing_reactions(50.0, 0.0, 0.5, theta=theta)
    assert r.reaction_a.shape == theta.shape
    # a rotating load: constant magnitude, turning with the rotor
    assert np.allclose(np.abs(r.reaction_a), abs(r.reaction_a[0]))
    assert np.allclose(r.reaction_a, r.reaction_a[0] * np.exp(1j * theta))
    frame = r.to_pandas()
    assert list(frame.columns)[:3] == ["theta_deg", "omega", "alpha"] and len(frame) == 9


def test_two_plane_correction_cancels_both_reactions_at_every_speed():
    rotor = Rotor.from_masses([0.2, 0.15, 0.1], [0.06, 0.05j, -0.04 + 0.03j], [0.1, 0.25, 0.35])
    rotor = rotor + Rotor(5.0, (0, 0, 0.2), np.diag([0.1, 0.1, 0.02]), about="cg")  # shaft
    fix = rotor.two_plane_correction(0.0, 0.4)
    radius = 0.05
    corrected = rotor.with_masses(
        np.abs([fix.mR_a, fix.mR_b]) / radius,
        radius * np.exp(1j * np.array([fix.theta_a, fix.theta_b])),
        [0.0, 0.4],
    )
    assert corrected.is_balanced() and not rotor.is_balanced()
    r = corrected.bearing_reactions(
        np.array([10.0, 300.0]), -0.1, 0.5, alpha=np.array([0.0, 1e3]), theta=0.7
    )
    assert np.max(np.abs(r.reaction_a)) < 1e-9 and np.max(np.abs(r.reaction_b)) < 1e-9
    # a static correction alone leaves the couple: bearings still loaded
    static = rotor.static_correction()
    half = rotor.with_masses([abs(static.mR) / radius], [radius * np.exp(1j * static.theta)], [0.2])
    assert abs(half.unbalance) < 1e-12
    assert abs(complex(half.bearing_reactions(300.0, -0.1, 0.5).reaction_a)) > 1.0


def test_correction_agrees_with_a_balancing_machine_reading():
    # The loads the rotor puts on the bearings at ω, fed to bearing_balance
    # (the notes' Problem 12-6 method), give the same correction.
    rotor = Rotor.from_masses([0.2, 0.15], [0.06, 0.05j], [0.1, 0.35])
    z = [-0.1, 0.5]
    w = 40.0
    r = rotor.bearing_reactions(w, *z)
    measured = bearing_balance([complex(r.load_a), complex(r.load_b)], z, w, 0.0, 0.4)
    direct = rotor.two_plane_correction(0.0, 0.4)
    assert np.isclose(measured.mR_a, direct.mR_a) and np.isclose(measured.mR_b, direct.mR_b)


def test_gravity_only_rotor_on_its_principal_axis_shares_the_weight_by_the_lever_rule():
    rotor = Rotor(10.0, (0.0, 0.0, 0.3), np.diag([0.2, 0.2, 0.1]), about="cg")
    r = rotor.bearing_reactions(500.0, 0.0, 1.0, gravity=9.81)
    assert complex(r.reaction_a) == pytest.approx(complex(0, 0.7 * 98.1))
    assert complex(r.reaction_b) == pytest.approx(complex(0, 0.3 * 98.1))


@pytest.mark.parametrize(
    ("build", "field"),
    [
        (lambda: Rotor(0.0), "mass"),
        (lambda: Rotor(-1.0), "mass"),
        (lambda: Rotor.from_masses([], [], []), "masses"),
        (lambda: Rotor.from_masses([0.0, 0.0], [0.1, 0.2], [0, 1]), "masses"),
        (lambda: Rotor.from_masses([1.0, -1.0], [0.1, 0.2], [0, 1]), "masses"),
        (lambda: Rotor.from_masses([1.0, 1.0], [0.1], [0, 1]), "R"),
        (lambda: Rotor.from_masses([1.0], [0.1], [0, 1]), "z"),
        (lambda: Rotor(1.0, (0, 0)), "cg"),
        (lambda: Rotor(1.0, inertia=np.eye(2)), "inertia"),
        (lambda: Rotor(1.0, inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), "inertia"),
        (lambda: Rotor(1.0, inertia=-np.eye(3), about="cg"), "inertia"),
        (lambda: Rotor(1.0, inertia=np.diag([1.0, 1.0, 3.0]), about="cg"), "inertia"),
        (lambda: Rotor(1.0, inertia=np.eye(3), about="centre"), "about"),
        (lambda: Rotor(1.0).bearing_reactions(1.0, 0.5, 0.5), "z_b"),
        (lambda: Rotor(1.0).bearing_reactions(np.nan, 0.0, 0.5), "omega"),
    ],
)
def test_bad_rotor_input_names_the_field(build, field):
    with pytest.raises(InputError) as err:
        build()
    assert err.value.field == field


def test_cli_balance_rotor_prints_bearing_loads_before_and_after(capsys):
    import json

    from machdyn.cli import main

    args = ["balance", "rotor", "--mass", "0.2,0.06,0,0.1", "--mass", "0.15,0.05,90,0.35"]
    args += ["--plane-a", "0", "--plane-b", "0.4", "--bearings=-0.1,0.5", "--omega", "40"]
    assert main([*args, "--json"]) == 0
    loads = json.loads(capsys.readouterr().out)["bearing_loads"]["loads"]  # one document
    # by hand: centrifugal forces 0.2·0.06·40² = 19.2 at 0° (z 0.1), 0.15·0.05·40² = 12 at
    # 90° (z 0.35); lever rule over the bearings at −0.1 and 0.5: B = (19.2·0.2 + 12j·0.45)/0.6
    b = complex(19.2 * 0.2, 12 * 0.45) / 0.6
    a = complex(19.2, 12) - b
    assert loads[0][2] == pytest.approx(abs(a)) and loads[1][2] == pytest.approx(abs(b))
    assert loads[1][3] == pytest.approx(np.degrees(np.angle(b)))
    assert loads[2][2] == 0.0 and loads[3][2] == 0.0  # after the correction
    assert main([*args[:-3], "--bearings=0.5,0.5", "--omega", "3"]) != 0
    assert "--bearings" in capsys.readouterr().err
