"""Audit 3: rotors and two-plane balance checked with full 3-D sums written here.

Every expected value is summed here from the point masses themselves, as 3-D
vectors (``numpy.cross``), never from the library's unbalance/couple shortcut:

* each mass at ``r = (x, y, z)`` turning about z needs ``m a`` with
  ``a = α k × r + ω k × (ω k × r)``; a rotor is balanced (static + dynamic)
  when ``Σ m a = 0`` and ``Σ r × m a = 0`` about every point, for every ω, α, θ
  (the notes, Ch. 12, Fig. 12-3: ``ΣF = 0`` and ``ΣT_A = 0``);
* a static correction alone zeroes ``Σ m a`` but leaves the moment;
* bearing reactions of a rotor made of point masses and a tilted disc (its
  tensor written here: ``I_diam = M a²/4``, ``I_axis = M a²/2`` turned by a
  tilt) from Newton–Euler solved here: ``F_A + F_B + m g = Σ m a`` and
  ``z_A k × F_A + z_B k × F_B + Σ r × m g = dH_O/dt``;
* the same disc as a ring of point masses gives the same products of inertia;
* the notes' Problem 12-6 (a wheel on a balancing machine): the corrections
  with the measured bearing forces give zero force and zero moment about A.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from machdyn.balancing import bearing_balance, two_plane
from machdyn.errors import InputError
from machdyn.rotor import Rotor

K = np.array([0.0, 0.0, 1.0])


def positions(R, z, theta):
    """3-D positions of masses at complex radius R (rotor frame), heights z, rotor angle θ."""
    turned = np.asarray(R) * np.exp(1j * theta)
    return np.stack([turned.real, turned.imag, np.asarray(z, dtype=float)], axis=-1)


def inertia_forces(m, r, omega, alpha):
    """``m a`` of each point mass (rows), a = α k × r + ω k × (ω k × r)."""
    a = alpha * np.cross(K, r) + omega**2 * np.cross(K, np.cross(K, r))
    return np.asarray(m)[:, None] * a


def sums(m, R, z, omega, alpha, theta, about=(0.0, 0.0, 0.0)):
    r = positions(R, z, theta)
    f = inertia_forces(m, r, omega, alpha)
    return f.sum(axis=0), np.cross(r - np.asarray(about), f).sum(axis=0)


def random_rotor(rng, n=5):
    m = rng.uniform(0.05, 0.5, n)
    R = rng.uniform(0.02, 0.1, n) * np.exp(1j * rng.uniform(0, 2 * np.pi, n))
    z = rng.uniform(-0.1, 0.9, n)
    return m, R, z


@pytest.mark.parametrize("seed", range(4))
def test_two_plane_correction_zeroes_3d_force_and_moment_sums(seed):
    rng = np.random.default_rng(400 + seed)
    m, R, z = random_rotor(rng)
    za, zb = rng.uniform(-0.2, 0.2), rng.uniform(0.5, 1.1)
    fix = two_plane(m * R, z, za, zb)
    by_rotor = Rotor.from_masses(m, R, z).two_plane_correction(za, zb)
    assert complex(by_rotor.mR_a) == pytest.approx(complex(fix.mR_a), rel=1e-12, abs=1e-15)
    assert complex(by_rotor.mR_b) == pytest.approx(complex(fix.mR_b), rel=1e-12, abs=1e-15)
    # the corrections as masses at chosen radii
    ra, rb = 0.12, 0.09
    ma, mb = fix.masses(ra, rb)
    m2 = np.concatenate([m, [ma, mb]])
    R2 = np.concatenate([R, [ra * np.exp(1j * fix.theta_a), rb * np.exp(1j * fix.theta_b)]])
    z2 = np.concatenate([z, [za, zb]])
    before_f, before_m = sums(m, R, z, 100.0, 0.0, 0.0)
    scale = max(np.abs(before_f).max(), np.abs(before_m).max())
    for omega, alpha, theta in ((100.0, 0.0, 0.0), (-37.0, 250.0, 1.3), (5.0, -40.0, 4.0)):
        for about in ((0, 0, 0), (0.03, -0.02, 0.7)):
            f, mo = sums(m2, R2, z2, omega, alpha, theta, about)
            assert np.abs(f).max() < 1e-12 * scale * (1 + abs(alpha) / 1e4)
            # x, y: the bearings' moment; z is the drive torque I_zz α, no unbalance
            assert np.abs(mo[:2]).max() < 1e-12 * scale * (1 + abs(alpha) / 1e4)
            r2 = positions(R2, z2, theta)
            izz = float(np.sum(m2 * (r2[:, 0] ** 2 + r2[:, 1] ** 2)))
            assert mo[2] == pytest.approx(izz * alpha, rel=1e-12, abs=1e-12 * scale)
    assert Rotor.from_masses(m2, R2, z2).is_balanced(rtol=1e-10)


def test_a_static_correction_leaves_the_couple():
    rng = np.random.default_rng(410)
    m, R, z = random_rotor(rng)
    rotor = Rotor.from_masses(m, R, z)
    s = rotor.static_correction()
    rb = 0.1
    mb = s.mass(rb)
    m2 = np.concatenate([m, [mb]])
    R2 = np.concatenate([R, [rb * np.exp(1j * s.theta)]])
    z2 = np.concatenate([z, [0.4]])
    f, mo = sums(m2, R2, z2, 60.0, 0.0, 0.0)
    f0, mo0 = sums(m, R, z, 60.0, 0.0, 0.0)
    assert np.abs(f).max() < 1e-12 * np.abs(f0).max()
    assert np.abs(mo[:2]).max() > 1e-3 * np.abs(mo0[:2]).max()  # dynamic unbalance remains
    assert not Rotor.from_masses(m2, R2, z2).is_balanced()


def disc_tensor(M, a, tilt):
    """Inertia tensor about the centre of a thin disc whose axis is tilted from z about x."""
    c, s = math.cos(tilt), math.sin(tilt)
    Q = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    return Q @ np.diag([M * a * a / 4, M * a * a / 4, M * a * a / 2]) @ Q.T


def test_a_tilted_disc_is_a_ring_of_point_masses_with_the_same_products():
    # a thin ring of N point masses, radius a, tilted by β about x, centre at (0, 0, h):
    # ∫ y z dm of the ring = M a² sin β cos β / 2 (its I_yz about its own centre), plus M·0·h
    M, a, tilt, h, N = 2.0, 0.15, 0.1, 0.3, 720
    phi = np.linspace(0, 2 * np.pi, N, endpoint=False)
    local = np.stack([a * np.cos(phi), a * np.sin(phi), np.zeros(N)], axis=1)
    c, s = math.cos(tilt), math.sin(tilt)
    Q = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    pts = local @ Q.T + np.array([0.0, 0.0, h])
    ring = Rotor.from_masses(np.full(N, M / N), pts[:, 0] + 1j * pts[:, 1], pts[:, 2])
    ring_tensor = Q @ np.diag([M * a * a / 2, M * a * a / 2, M * a * a]) @ Q.T  # thin ring
    solid = Rotor(M, (0.0, 0.0, h), ring_tensor, about="cg")
    assert ring.I_yz == pytest.approx(M * a * a * s * c / 2, rel=1e-9)
    assert solid.I_yz == pytest.approx(ring.I_yz, rel=1e-9)
    assert solid.I_xz == pytest.approx(0.0, abs=1e-15) and abs(ring.I_xz) < 1e-15
    np.testing.assert_allclose(solid.inertia, ring.inertia, rtol=1e-9, atol=1e-15)


def test_bearing_reactions_of_masses_and_a_tilted_disc_from_3d_newton_euler():
    rng = np.random.default_rng(420)
    m, R, z = random_rotor(rng, 3)
    M, a, tilt, cg_disc = 4.0, 0.2, 0.05, np.array([0.002, -0.001, 0.45])
    disc = Rotor(M, cg_disc, disc_tensor(M, a, tilt), about="cg")
    rotor = disc.with_masses(m, R, z)
    za, zb, g = 0.0, 0.8, 9.81
    for omega, alpha, theta in ((150.0, 0.0, 0.3), (-80.0, 400.0, 2.0), (20.0, -60.0, 5.5)):
        got = rotor.bearing_reactions(omega, za, zb, alpha=alpha, theta=theta, gravity=g)
        # Newton–Euler written here, in the fixed frame
        rot = np.array([[math.cos(theta), -math.sin(theta), 0],
                        [math.sin(theta), math.cos(theta), 0], [0, 0, 1]])  # fmt: skip
        w, al = omega * K, alpha * K
        # disc: its own a_G and H_G, then moved to O; masses: point sums
        rg = rot @ cg_disc
        aG = np.cross(al, rg) + np.cross(w, np.cross(w, rg))
        IG = rot @ disc_tensor(M, a, tilt) @ rot.T
        dHG = IG @ al + np.cross(w, IG @ w)
        r_pts = positions(R, z, theta)
        f_pts = inertia_forces(m, r_pts, omega, alpha)
        ma_total = M * aG + f_pts.sum(axis=0)
        dH_O = dHG + np.cross(rg, M * aG) + np.cross(r_pts, f_pts).sum(axis=0)
        weight = np.array([0.0, -g, 0.0])
        gravity_moment = np.cross(rg, M * weight) + np.cross(r_pts, m[:, None] * weight).sum(axis=0)
        total_mass = M + m.sum()
        # unknowns FAx, FAy, FBx, FBy, T: force x, y; moment x, y, z about O
        A = np.zeros((5, 5))
        b = np.zeros(5)
        A[0, [0, 2]] = 1.0
        A[1, [1, 3]] = 1.0
        b[:2] = (ma_total - total_mass * weight)[:2]
        # (0, 0, z) × (Fx, Fy, 0) = (−z Fy, z Fx, 0)
        A[2, 1], A[2, 3] = -za, -zb
        A[3, 0], A[3, 2] = za, zb
        A[4, 4] = 1.0
        b[2:] = dH_O - gravity_moment
        FAx, FAy, FBx, FBy, T = np.linalg.solve(A, b)
        scale = total_mass * (omega**2 + abs(alpha) + g) * 0.1
        assert abs(complex(got.reaction_a) - complex(FAx, FAy)) < 1e-9 * scale
        assert abs(complex(got.reaction_b) - complex(FBx, FBy)) < 1e-9 * scale
        assert float(got.torque) == pytest.approx(T, rel=1e-9, abs=1e-9 * scale)


def test_notes_problem_12_6_corrections_close_force_and_moment_about_plane_a():
    # course notes, Ch. 12 "Dynamic balancing of a wheel", Problem 12-6: F_L = 5∠45° at
    # 14 in left of plane A, F_R = 2∠−120° at 4 in left of A, plane B 7 in right of A,
    # rim radius 7.5 in, the notes' ω = 10π/3 rad/s. Their answers: m_B = 0.0108 blob at
    # 43.09°, m_A = 0.0146 blob at 221.11°.
    w = 10 * math.pi / 3
    FL, FR = 5 * np.exp(1j * math.radians(45)), 2 * np.exp(-1j * math.radians(120))
    fix = bearing_balance([FL, FR], [-14.0, -4.0], w, 0.0, 7.0)
    ma, mb = fix.masses(7.5)
    assert (round(mb, 4), round(ma, 4)) == (0.0108, 0.0146)
    assert abs(fix.angle_b_deg - 43.09) < 0.01 and abs(fix.angle_a_deg - 221.11) < 0.01

    def vec(c, zz):
        return np.array([c.real, c.imag, 0.0]), np.array([0.0, 0.0, zz])

    forces = [vec(FL, -14.0), vec(FR, -4.0)]
    for mass, angle, zz in ((ma, fix.theta_a, 0.0), (mb, fix.theta_b, 7.0)):
        forces.append(vec(mass * w * w * 7.5 * np.exp(1j * angle), zz))
    total = sum(f for f, _ in forces)
    moment_a = sum(np.cross(r, f) for f, r in forces)
    assert np.abs(total).max() < 1e-12 and np.abs(moment_a).max() < 1e-11
    # the notes' intermediate step: 7 m_B ω² R_Bx = 70/√2 − 4, 7 m_B ω² R_By = 70/√2 − 4√3
    mRB = mb * 7.5 * np.exp(1j * fix.theta_b)
    assert 7 * w * w * mRB.real == pytest.approx(70 / math.sqrt(2) - 4, rel=1e-12)
    assert 7 * w * w * mRB.imag == pytest.approx(70 / math.sqrt(2) - 4 * math.sqrt(3), rel=1e-12)


def test_cli_balance_rotor_matches_the_3d_sums(capsys):
    from machdyn.cli import main

    masses = [(0.2, 0.06, 30.0, 0.1), (0.15, 0.05, 100.0, 0.35), (0.1, 0.04, 250.0, 0.6)]
    args = ["balance", "rotor", "--plane-a", "0", "--plane-b", "0.5", "--radius-a", "0.08"]
    for mm in masses:
        args += ["--mass", ",".join(str(v) for v in mm)]
    assert main([*args, "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    m = np.array([mm[0] for mm in masses])
    R = np.array([mm[1] * np.exp(1j * math.radians(mm[2])) for mm in masses])
    z = np.array([mm[3] for mm in masses])
    m2 = np.concatenate([m, rows["mass"]])
    R2 = np.concatenate([R, 0.08 * np.exp(1j * np.radians(rows["angle_deg"]))])
    z2 = np.concatenate([z, rows["z"]])
    f, mo = sums(m2, R2, z2, 100.0, 0.0, 0.0)
    assert np.abs(f).max() < 1e-9 and np.abs(mo).max() < 1e-9
    assert main([*args, "--plane-b", "0"]) != 0
    err = capsys.readouterr().err
    assert "plane_b" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize(
    ("build", "field"),
    [
        (lambda: Rotor.from_masses([1.0, 2.0], [0.1], [0.0, 1.0]), "R"),
        (lambda: Rotor(1.0, (0, 0, 0), np.diag([1.0, 1.0, 3.0])), "inertia"),
        (lambda: Rotor(1.0, (0, 0, 0), about="middle", inertia=np.eye(3)), "about"),
        (lambda: Rotor.from_masses([1.0], [0.1], [0.0]).bearing_reactions(10, 0.5, 0.5), "z_b"),
        (lambda: two_plane([0.1j], [0.5], 0.2, 0.2), "plane_b"),
        (lambda: bearing_balance([1.0], [0.0], 10.0, 0.0, 1.0), "bearing_forces"),
    ],
)
def test_bad_rotor_input_names_the_field(build, field):
    with pytest.raises(InputError) as info:
        build()
    assert info.value.field == field


def test_the_rotor_example_file_run_gives_corrections_that_close_the_3d_sums(capsys):
    from pathlib import Path

    from machdyn.cli import main

    example = Path(__file__).resolve().parents[1] / "docs" / "examples" / "rotor.toml"
    assert main(["run", str(example), "--json"]) == 0
    part = json.loads(capsys.readouterr().out)["parts"]["shaft"]
    # the file's masses (mm, kg, degrees), written here
    m = np.array([0.2, 0.3, 0.1])
    R = np.array([60, 50, 80]) * np.exp(1j * np.radians([30, 150, 270]))
    z = np.array([100.0, 220.0, 320.0])
    U = abs(np.sum(m * R))
    assert part["summary"]["unbalance |sum m R| [kg*mm]"] == pytest.approx(U, rel=1e-12)
    w = 1500 * 2 * math.pi / 60
    assert part["summary"]["shaking force before [N]"] == pytest.approx(U * 1e-3 * w * w, rel=1e-12)
    rows = part["tables"]["corrections"]["rows"]
    masses = [row[4] for row in rows]
    angles = np.radians([row[3] for row in rows])
    m2 = np.concatenate([m, masses])
    R2 = np.concatenate([R, 100 * np.exp(1j * angles)])  # the file's radii: 100 mm
    z2 = np.concatenate([z, [row[1] for row in rows]])
    f, mo = sums(m2, R2, z2, w, 0.0, 0.0)
    f0, mo0 = sums(m, R, z, w, 0.0, 0.0)
    assert np.abs(f).max() < 1e-12 * np.abs(f0).max() * 10
    assert np.abs(mo).max() < 1e-12 * np.abs(mo0).max() * 10
