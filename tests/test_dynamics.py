"""Tests of machdyn.dynamics: four-bar Newton–Euler forces.

Every check here is written out in the test from the textbook equations (Norton,
*Design of Machinery*, eq. 11.9/11.10; the notes' "FORCE ANALYSIS" section)
and from the kinematics (angles, rates) alone: the 9×9 matrix, each link's
three equations, the power balance, and the shaking force/moment sums.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from machdyn.dynamics import (
    FORCE_REASONS,
    PointLoad,
    fourbar_dynamics,
    fourbar_forces,
    from_bodies,
    link_equations,
    link_properties,
)
from machdyn.errors import InputError
from machdyn.fourbar import FourBar

G = 9.81


def cross(u, v):
    return u.real * v.imag - u.imag * v.real


def dot(u, v):
    return u.real * v.real + u.imag * v.imag


class Case:
    """A loaded four-bar with masses, gravity, point forces and torques."""

    def __init__(self, fb, mass, inertia, cg, gravity=G, t4=-3.0, loads=(), torques=()):
        self.fb, self.mass, self.inertia, self.cg = fb, mass, inertia, cg
        self.gravity, self.t4, self.loads, self.torques = gravity, t4, loads, torques

    def forces(self, motion):
        return fourbar_forces(
            self.fb,
            motion,
            mass=self.mass,
            inertia=self.inertia,
            cg=self.cg,
            gravity=self.gravity,
            load_torque4=self.t4,
            external_forces=self.loads,
            external_torques=self.torques,
        )


def kinematics(fb, m, cg):
    """Positions, velocities and accelerations of the centres of mass, from the angles."""
    r1, r2, _, _ = fb.lengths
    th = {2: m.theta2, 3: m.theta3, 4: m.theta4}
    om = {2: m.omega2, 3: m.omega3, 4: m.omega4}
    al = {2: m.alpha2, 3: m.alpha3, 4: m.alpha4}
    e = {k: np.exp(1j * th[k]) for k in th}
    joint = {2: 0.0 * e[2], 3: r2 * e[2], 4: r1 + 0.0 * e[4]}  # first joints O2, A, O4
    vO = {2: 0.0 * e[2], 3: 1j * r2 * om[2] * e[2], 4: 0.0 * e[4]}
    aO = {
        2: 0.0 * e[2],
        3: r2 * (1j * al[2] - om[2] ** 2) * e[2],
        4: 0.0 * e[4],
    }
    c = dict(zip((2, 3, 4), cg, strict=True))
    rG = {k: joint[k] + c[k] * e[k] for k in th}
    vG = {k: vO[k] + 1j * om[k] * c[k] * e[k] for k in th}
    aG = {k: aO[k] + (1j * al[k] - om[k] ** 2) * c[k] * e[k] for k in th}
    return dict(e=e, O=joint, rG=rG, vG=vG, aG=aG, om=om, al=al)


def external(case, k, frame):
    """External point loads of link k: list of (point in ground frame, force)."""
    out = []
    for link, point, force in case.loads:
        if link == k:
            out.append((frame["O"][k] + point * frame["e"][k], np.asarray(force, dtype=complex)))
    return out


def ext_torque(case, k):
    t = sum(torque for link, torque in case.torques if link == k)
    return t + (case.t4 if k == 4 else 0.0)


@pytest.fixture
def case():
    fb = FourBar(8, 4, 7, 6)  # the notes' HW 6 crank-rocker
    return Case(
        fb,
        mass=(1.2, 2.5, 1.8),
        inertia=(0.8, 3.1, 1.4),
        cg=(1.5 + 0.3j, 3.0 - 0.8j, 2.5 + 0.4j),
        gravity=G,
        t4=-3.0,
        loads=((3, 2.0 + 1.0j, 4.0 - 7.0j), (2, 3.0, -1.5 + 2.0j), (4, 5.0 - 1j, 2.0 + 3.0j)),
        torques=((3, 1.25), (2, -0.5)),
    )


def full_cycle(fb, n=73, omega2=12.0, alpha2=-4.0):
    theta2 = np.linspace(0.0, 2 * np.pi, n)
    return fb.solve(theta2, omega2, alpha2)


# --------------------------------------------------------------------------------------
# The notes' matrix method, built independently


def norton_matrix(case, motion):
    """Norton eq. 11.10 per sample: A (N, 9, 9), b (N, 9); unknowns
    F12x F12y F32x F32y F43x F43y F14x F14y T12."""
    fb = case.fb
    k = kinematics(fb, motion, case.cg)
    r1, r2, _, r4 = fb.lengths
    A_pt = r2 * k["e"][2]
    B_pt = r1 + r4 * k["e"][4]
    rG = k["rG"]
    R12, R32 = 0.0 - rG[2], A_pt - rG[2]
    R23, R43 = A_pt - rG[3], B_pt - rG[3]
    R14, R34 = r1 - rG[4], B_pt - rG[4]
    n = motion.theta2.size
    M = np.zeros((n, 9, 9))
    b = np.zeros((n, 9))
    m2, m3, m4 = case.mass
    I2, I3, I4 = case.inertia
    # link 2: F12 + F32 = m2 aG2 − Fext;  T12 + R12×F12 + R32×F32 = I α − Mext
    M[:, 0, 0] = M[:, 0, 2] = 1
    M[:, 1, 1] = M[:, 1, 3] = 1
    M[:, 2, 0], M[:, 2, 1] = -R12.imag, R12.real
    M[:, 2, 2], M[:, 2, 3] = -R32.imag, R32.real
    M[:, 2, 8] = 1
    # link 3: F43 − F32 = ...;  R43×F43 − R23×F32 = ...
    M[:, 3, 4], M[:, 3, 2] = 1, -1
    M[:, 4, 5], M[:, 4, 3] = 1, -1
    M[:, 5, 4], M[:, 5, 5] = -R43.imag, R43.real
    M[:, 5, 2], M[:, 5, 3] = R23.imag, -R23.real
    # link 4: F14 − F43 = ...;  R14×F14 − R34×F43 = ...
    M[:, 6, 6], M[:, 6, 4] = 1, -1
    M[:, 7, 7], M[:, 7, 5] = 1, -1
    M[:, 8, 6], M[:, 8, 7] = -R14.imag, R14.real
    M[:, 8, 4], M[:, 8, 5] = R34.imag, -R34.real
    rows = {2: 0, 3: 3, 4: 6}
    for link, mk, ik in zip((2, 3, 4), case.mass, case.inertia, strict=True):
        fsum = -1j * mk * case.gravity + 0 * rG[link]
        msum = ext_torque(case, link) + 0 * rG[link].real
        for p, f in external(case, link, k):
            fsum = fsum + f
            msum = msum + cross(p - rG[link], f)
        rhs_f = mk * k["aG"][link] - fsum
        i = rows[link]
        b[:, i] = rhs_f.real
        b[:, i + 1] = rhs_f.imag
        b[:, i + 2] = ik * k["al"][link] - msum
    del m2, m3, m4, I2, I3, I4
    return M, b


def test_matches_norton_9x9_matrix(case):
    motion = full_cycle(case.fb)
    f = case.forces(motion)
    assert f.ok.all()
    M, b = norton_matrix(case, motion)
    x = np.linalg.solve(M, b[..., None])[..., 0]
    scale = np.max(np.abs(x))
    np.testing.assert_allclose(f.F12.real, x[:, 0], atol=1e-11 * scale)
    np.testing.assert_allclose(f.F12.imag, x[:, 1], atol=1e-11 * scale)
    np.testing.assert_allclose(f.F32.real, x[:, 2], atol=1e-11 * scale)
    np.testing.assert_allclose(f.F32.imag, x[:, 3], atol=1e-11 * scale)
    np.testing.assert_allclose(f.F43.real, x[:, 4], atol=1e-11 * scale)
    np.testing.assert_allclose(f.F43.imag, x[:, 5], atol=1e-11 * scale)
    np.testing.assert_allclose(f.F14.real, x[:, 6], atol=1e-11 * scale)
    np.testing.assert_allclose(f.F14.imag, x[:, 7], atol=1e-11 * scale)
    np.testing.assert_allclose(f.T12, x[:, 8], atol=1e-11 * scale)


def test_each_link_equations_hold(case):
    """ΣF = m aG and ΣM_G = IG α for links 2, 3 and 4, written out here."""
    motion = full_cycle(case.fb, n=181)
    f = case.forces(motion)
    k = kinematics(case.fb, motion, case.cg)
    r1, r2, _, r4 = case.fb.lengths
    A_pt, B_pt = r2 * k["e"][2], r1 + r4 * k["e"][4]
    joint_forces = {
        2: [(0.0, f.F12), (A_pt, f.F32)],
        3: [(A_pt, -f.F32), (B_pt, f.F43)],
        4: [(B_pt, -f.F43), (r1, f.F14)],
    }
    scale = max(np.max(np.abs(f.F12)), np.max(np.abs(f.T12)))
    for link, mk, ik in zip((2, 3, 4), case.mass, case.inertia, strict=True):
        G_pt = k["rG"][link]
        fsum = sum(F for _, F in joint_forces[link]) - 1j * mk * G
        msum = sum(cross(P - G_pt, F) for P, F in joint_forces[link]) + ext_torque(case, link)
        for p, fe in external(case, link, k):
            fsum = fsum + fe
            msum = msum + cross(p - G_pt, fe)
        if link == 2:
            msum = msum + f.T12
        np.testing.assert_allclose(fsum - mk * k["aG"][link], 0.0, atol=1e-12 * scale)
        np.testing.assert_allclose(msum - ik * k["al"][link], 0.0, atol=1e-12 * scale * 10)


def test_power_balance_over_a_cycle(case):
    """T12 ω2 + Σ P_ext = d(KE)/dt + d(PE)/dt (energy; shares nothing with the solve)."""
    motion = full_cycle(case.fb, n=361, omega2=15.0, alpha2=7.0)
    f = case.forces(motion)
    k = kinematics(case.fb, motion, case.cg)
    p_ext = 0.0
    dke = 0.0
    dpe = 0.0
    for link, mk, ik in zip((2, 3, 4), case.mass, case.inertia, strict=True):
        for p, fe in external(case, link, k):
            # velocity of the load point: the link's first joint + ω × (P − O)
            vp = (k["vG"][link] - 1j * k["om"][link] * (k["rG"][link] - k["O"][link])) + 1j * k[
                "om"
            ][link] * (p - k["O"][link])
            p_ext = p_ext + dot(fe, vp)
        p_ext = p_ext + ext_torque(case, link) * k["om"][link]
        dke = dke + mk * dot(k["vG"][link], k["aG"][link]) + ik * k["om"][link] * k["al"][link]
        dpe = dpe + mk * G * k["vG"][link].imag
    lhs = f.T12 * motion.omega2 + p_ext
    rhs = dke + dpe
    scale = np.max(np.abs(rhs))
    np.testing.assert_allclose(lhs, rhs, rtol=0, atol=1e-8 * scale)


def test_kinetic_energy_rate_by_finite_differences(case):
    """The test's own d(KE)/dt formula against a 5-point stencil in time."""
    fb = case.fb
    omega2, alpha2, h = 3.0, 1.5, 1e-4
    t = np.linspace(0.0, 1.5, 31)

    def energy(time):
        th = 0.2 + omega2 * time + 0.5 * alpha2 * time**2
        m = fb.solve(th, omega2 + alpha2 * time, alpha2)
        k = kinematics(fb, m, case.cg)
        ke = sum(
            0.5 * mk * np.abs(k["vG"][j]) ** 2 + 0.5 * ik * k["om"][j] ** 2
            for j, mk, ik in zip((2, 3, 4), case.mass, case.inertia, strict=True)
        )
        return ke, m, k

    stencil = (
        -energy(t + 2 * h)[0] + 8 * energy(t + h)[0] - 8 * energy(t - h)[0] + energy(t - 2 * h)[0]
    ) / (12 * h)
    _, _, k = energy(t)
    analytic = sum(
        mk * dot(k["vG"][j], k["aG"][j]) + ik * k["om"][j] * k["al"][j]
        for j, mk, ik in zip((2, 3, 4), case.mass, case.inertia, strict=True)
    )
    np.testing.assert_allclose(stencil, analytic, rtol=1e-6, atol=1e-6 * np.max(np.abs(analytic)))


def test_shaking_force_and_moment_are_the_ground_reactions(case):
    """Fs = Σ F_ext − Σ m aG and Ms = Σ M_ext,O2 − Σ (IG α + rG × m aG) (Norton 11.15)."""
    motion = full_cycle(case.fb)
    f = case.forces(motion)
    k = kinematics(case.fb, motion, case.cg)
    fs = 0.0
    ms = 0.0
    for link, mk, ik in zip((2, 3, 4), case.mass, case.inertia, strict=True):
        rG, aG = k["rG"][link], k["aG"][link]
        fs = fs - mk * aG - 1j * mk * G
        ms = ms - ik * k["al"][link] - mk * cross(rG, aG) + cross(rG, -1j * mk * G + 0 * rG)
        ms = ms + ext_torque(case, link)
        for p, fe in external(case, link, k):
            fs = fs + fe
            ms = ms + cross(p, fe)
    scale = np.max(np.abs(fs))
    np.testing.assert_allclose(f.shaking_force, fs, atol=1e-11 * scale)
    np.testing.assert_allclose(f.shaking_moment, ms, atol=1e-10 * np.max(np.abs(ms)))
    np.testing.assert_allclose(f.F21 + f.F41, f.shaking_force)
    np.testing.assert_array_equal(f.shaking_torque, -f.T12)


def test_static_output_torque_by_velocity_ratio():
    """No masses: T12 ω2 + T4 ω4 = 0 (the notes' virtual work, a closed form)."""
    fb = FourBar(8, 4, 7, 6)
    theta2 = np.radians(np.arange(0, 360, 7.5))
    f = fourbar_dynamics(
        fb, theta2, 2.0, mass=(0, 0, 0), inertia=(0, 0, 0), cg=(0, 0, 0), load_torque4=-40.0
    )
    np.testing.assert_allclose(f.T12 * 2.0, 40.0 * f.motion.omega4, rtol=1e-12)
    # pins: a two-force member (link 3) carries its force along AB
    u = f.motion.B - f.motion.A
    np.testing.assert_allclose(cross(u, f.F43), 0.0, atol=1e-10 * np.max(np.abs(f.F43)))


def test_crank_alone_single_link_closed_form():
    """Only link 2 has mass: F12 = m2 aG2 and T12 = IO2 α2 (pure rotation about O2)."""
    fb = FourBar(8, 4, 7, 6)
    theta2 = np.linspace(0, 2 * np.pi, 25)
    m2, ig2, c2 = 2.0, 0.3, 1.5
    f = fourbar_dynamics(fb, theta2, 5.0, 2.0, mass=(m2, 0, 0), inertia=(ig2, 0, 0), cg=(c2, 0, 0))
    aG = c2 * np.exp(1j * theta2) * (2.0j - 25.0)
    np.testing.assert_allclose(f.F12, m2 * aG, atol=1e-12)
    np.testing.assert_allclose(f.T12, (ig2 + m2 * c2**2) * 2.0, rtol=1e-12)
    np.testing.assert_allclose(f.F43, 0.0, atol=1e-12)


def test_per_sample_external_force_and_shapes():
    fb = FourBar(8, 4, 7, 6)
    theta2 = np.radians(np.arange(0, 360, 30.0)).reshape(3, 4)
    force = (np.arange(12.0) * (1 + 1j)).reshape(3, 4)
    f = fourbar_dynamics(
        fb,
        theta2,
        1.0,
        mass=(0, 0, 0),
        inertia=(0, 0, 0),
        cg=(0, 0, 0),
        external_forces=[PointLoad(3, 3.5 + 1j, force)],
    )
    assert f.T12.shape == (3, 4) and f.F12.shape == (3, 4)
    # one sample at a time gives the same answer
    g = fourbar_dynamics(
        fb,
        theta2[1, 2],
        1.0,
        mass=(0, 0, 0),
        inertia=(0, 0, 0),
        cg=(0, 0, 0),
        external_forces=[(3, 3.5 + 1j, force[1, 2])],
    )
    assert np.isclose(g.T12, f.T12[1, 2], rtol=1e-13)
    df = f.to_pandas()
    assert len(df) == 12 and {"T12", "F32_x", "F32_mag", "shaking_moment", "ok"} <= set(df)


def test_random_linkages_match_matrix(rng):
    """Seeded random crank-rockers, masses and loads: closed-form elimination = 9×9 solve."""
    for _ in range(10):
        while True:
            r = rng.uniform(1.0, 10.0, 4)
            try:
                fb = FourBar(*r)
            except Exception:
                continue
            if fb.cranks and 2 in fb.cranks:
                break
        case = Case(
            fb,
            mass=tuple(rng.uniform(0.5, 3.0, 3)),
            inertia=tuple(rng.uniform(0.1, 2.0, 3)),
            cg=tuple(rng.normal(size=3) + 1j * rng.normal(size=3)),
            gravity=rng.uniform(0, 10),
            t4=rng.normal(),
            loads=(
                (
                    int(rng.integers(2, 5)),
                    complex(*rng.normal(size=2)),
                    complex(*rng.normal(size=2)),
                ),
            ),
            torques=((int(rng.integers(2, 5)), float(rng.normal())),),
        )
        motion = fb.solve(rng.uniform(0, 2 * np.pi, 20), rng.normal() * 10, rng.normal() * 10)
        f = case.forces(motion)
        ok = f.ok
        M, b = norton_matrix(case, motion)
        x = np.linalg.solve(M[ok], b[ok][..., None])[..., 0]
        got = np.stack(
            [
                f.F12.real,
                f.F12.imag,
                f.F32.real,
                f.F32.imag,
                f.F43.real,
                f.F43.imag,
                f.F14.real,
                f.F14.imag,
                f.T12,
            ],
            axis=-1,
        )[ok]
        np.testing.assert_allclose(got, x, atol=1e-9 * max(1.0, np.max(np.abs(x))))


# --------------------------------------------------------------------------------------
# Toggles and bad input


def test_toggle_is_flagged_with_a_reason():
    fb = FourBar(6, 9, 3, 8)  # GRCR: a rocker input; its limits are toggles of links 3–4
    rng_ = fb.input_range(form=1)
    theta2 = np.array([rng_.lo, 0.5 * (rng_.lo + rng_.hi), rng_.hi])
    f = fourbar_dynamics(fb, theta2, 1.0, mass=(1, 1, 1), inertia=(1, 1, 1), cg=(1, 1, 1))
    assert f.ok.tolist() == [False, True, False]
    assert "singular" in f.reason[0] and f.reason[1] == ""
    assert np.isnan(f.T12[0]) and np.isfinite(f.T12[1])


def test_unassemblable_samples_are_flagged():
    fb = FourBar(6, 9, 3, 8)
    f = fourbar_dynamics(
        fb, np.radians([60.0, 200.0]), 1.0, mass=(1, 1, 1), inertia=(1, 1, 1), cg=(1, 1, 1)
    )
    assert f.ok.tolist() == [True, False]
    assert f.reason[1] in FORCE_REASONS and f.reason[1]


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        (dict(mass=(1, 2)), "mass"),
        (dict(mass=(1, 2, 3, 4)), "mass"),
        (dict(mass=5.0), "mass"),
        (dict(mass=(1, -2, 3)), "mass m3"),
        (dict(inertia=(1, 2, -3)), "inertia IG4"),
        (dict(mass=(1, 0, 3)), "mass m3"),
        (dict(mass=(1, float("nan"), 3)), "mass m3"),
        (dict(cg=(1, "a", 3)), "cg c3"),
        (dict(gravity=-9.81), "gravity"),
        (dict(external_forces=[(5, 1.0, 1j)]), "external_forces[0] link"),
        (dict(external_forces=[(3, 1.0)]), "external_forces[0]"),
        (dict(external_forces=[(3, 1.0, float("inf"))]), "external_forces[0] force"),
        (dict(external_torques=[(1, 2.0)]), "external_torques[0] link"),
        (dict(load_torque4=float("nan")), "load_torque4"),
        (dict(external_forces=[(3, 1.0, np.ones(4))]), "external_forces[0] force"),
        (dict(load_torque4=np.ones(2)), "load_torque4"),
        (dict(external_torques={3: np.ones(3)}), "external_torques[0] torque"),
    ],
)
def test_bad_input_names_the_field(kwargs, field):
    args = dict(mass=(1, 2, 3), inertia=(1, 2, 3), cg=(1, 2, 3))
    args.update(kwargs)
    with pytest.raises(InputError) as err:
        fourbar_dynamics(FourBar(8, 4, 7, 6), 0.5, 1.0, **args)
    assert err.value.field == field


def test_massless_links_and_point_masses():
    props = link_properties((0, 1, 0), (0, 0.5, 0), (0, 1, 0))
    assert props.mass == (0.0, 1.0, 0.0)
    # a point mass (no inertia) is accepted: Norton's lumped-mass model
    assert link_properties((1, 1, 1), (0, 0.5, 0), (1, 1, 1)).inertia == (0.0, 0.5, 0.0)


def test_from_massprops_bodies():
    from machdyn.massprops import point_mass, rod

    fb = FourBar(8, 4, 7, 6)
    bodies = (rod(1.0, 4.0), rod(2.0, 7.0), rod(1.5, 6.0) + point_mass(0.5, 6.0))
    f = fourbar_dynamics(fb, np.radians([30.0, 200.0]), 10.0, **from_bodies(*bodies))
    g = fourbar_dynamics(
        fb,
        np.radians([30.0, 200.0]),
        10.0,
        mass=(1.0, 2.0, 2.0),
        inertia=(16 / 12, 2 * 49 / 12, 1.5 * 36 / 12 + 1.5 * 0.75**2 + 0.5 * 2.25**2),
        cg=(2.0, 3.5, 3.75),  # link 4: (1.5·3 + 0.5·6) / 2
    )
    np.testing.assert_allclose(f.T12, g.T12, rtol=1e-12)
    with pytest.raises(InputError):
        from_bodies(1.0, 2.0, 3.0)


# --------------------------------------------------------------------------------------
# One link's equations


def test_final_exam_problem_7():
    """The notes' final exam problem 7: m = 8 kg, IG3 = 6 kg·m², α = 5 rad/s² CW.

    Written by hand from m aG = F43 − F32 + FP and IG α = R43×F43 − R23×F32 + RP×FP + TP:
      F43x − F32x = 8(−4) − 3 = −35
      F43y − F32y = 8(−5) + 5 = −40 + 5 = −35
      6 F43x + F43y + F32x + 4 F32y = 6(−5) − (−1·−5 − 1.5·3) − 12 = −42.5
    """
    eq = link_equations(
        8,
        6,
        -4 - 5j,
        -5,
        {"F32": (-4 + 1j, -1), "F43": (1 - 6j, +1)},
        forces=[(-1 + 1.5j, 3 - 5j)],
        torque=12,
    )
    assert eq.unknowns == ("F32x", "F32y", "F43x", "F43y")
    np.testing.assert_array_equal(eq.matrix, [[-1, 0, 1, 0], [0, -1, 0, 1], [1, 4, 6, 1]])
    np.testing.assert_allclose(eq.rhs, [-35, -35, -42.5])
    assert np.allclose(eq.residual([0, 0, -35, -35]), [0, 0, -210 - 35 + 42.5])


def test_link_equations_gravity_and_bad_sign():
    eq = link_equations(2, 1, 0, 0, {"F12": (1, 1)}, gravity=10)
    np.testing.assert_allclose(eq.rhs, [0, 20, 0])
    with pytest.raises(InputError):
        link_equations(2, 1, 0, 0, {"F12": (1, 2)})


# --------------------------------------------------------------------------------------
# Property test: the power balance on random crank-rockers, masses and loads


_lengths = st.tuples(*(st.floats(1.0, 10.0) for _ in range(4)))
_positive = st.floats(0.1, 5.0)
_coord = st.floats(-3.0, 3.0)


@given(
    lengths=_lengths,
    masses=st.tuples(_positive, _positive, _positive),
    inertias=st.tuples(_positive, _positive, _positive),
    cgs=st.tuples(*(st.tuples(_coord, _coord) for _ in range(3))),
    omega2=st.floats(-30.0, 30.0),
    alpha2=st.floats(-50.0, 50.0),
    t4=st.floats(-10.0, 10.0),
)
def test_power_balance_property(lengths, masses, inertias, cgs, omega2, alpha2, t4):
    try:
        fb = FourBar(*lengths)
    except Exception:
        assume(False)
    assume(fb.is_grashof and 2 in fb.cranks)  # change points: see the report (fourbar.py)
    cg = tuple(complex(x, y) for x, y in cgs)
    case = Case(fb, masses, inertias, cg, gravity=G, t4=t4)
    motion = fb.solve(np.linspace(0, 2 * np.pi, 37), omega2, alpha2)
    f = case.forces(motion)
    ok = f.ok
    assume(ok.sum() > 10)
    k = kinematics(fb, motion, cg)
    rhs = sum(
        mk * dot(k["vG"][j], k["aG"][j]) + ik * k["om"][j] * k["al"][j] + mk * G * k["vG"][j].imag
        for j, mk, ik in zip((2, 3, 4), masses, inertias, strict=True)
    )
    lhs = f.T12 * motion.omega2 + t4 * motion.omega4
    # scale: the largest power term of the sample
    scale = np.abs(f.T12 * motion.omega2) + np.abs(rhs) + abs(t4 * motion.omega4) + 1e-300
    assert np.all(np.abs(lhs - rhs)[ok] <= 1e-8 * np.max(scale[ok]))


def test_plot_draws_lines():
    fb = FourBar(8, 4, 7, 6)
    f = fourbar_dynamics(
        fb, np.linspace(0, 2 * np.pi, 10), 1.0, mass=(1, 1, 1), inertia=(1, 1, 1), cg=(1, 1, 1)
    )
    ax = f.plot()
    assert len(ax.lines) == 5


def test_pint_quantities_are_converted_once():
    """Lengths in mm, masses in g, inertia in g·cm²: results in kg·mm/s² (forces) and
    kg·mm²/s² (torques); compare to the same linkage in plain SI numbers."""
    pint = pytest.importorskip("pint")
    u = pint.UnitRegistry()
    fb_mm = FourBar(80 * u.mm, 40 * u.mm, 70 * u.mm, 60 * u.mm)
    fb_m = FourBar(0.08, 0.04, 0.07, 0.06)
    theta2 = np.radians([10.0, 100.0, 250.0])
    f_mm = fourbar_dynamics(
        fb_mm,
        theta2,
        20.0,
        mass=(100 * u.g, 250 * u.g, 180 * u.g),
        inertia=(80 * u.g * u.cm**2, 310 * u.g * u.cm**2, 140 * u.g * u.cm**2),
        cg=(2 * u.cm, (35 + 5j) * u.mm, 0.03 * u.m),
        gravity=9.81 * u.m / u.s**2,
        load_torque4=-0.5 * u.N * u.m,
    )
    f_m = fourbar_dynamics(
        fb_m,
        theta2,
        20.0,
        mass=(0.1, 0.25, 0.18),
        inertia=(80e-7, 310e-7, 140e-7),
        cg=(0.02, 0.035 + 0.005j, 0.03),
        gravity=9.81,
        load_torque4=-0.5,
    )
    np.testing.assert_allclose(f_mm.F32 * 1e-3, f_m.F32, rtol=1e-12)
    np.testing.assert_allclose(f_mm.T12 * 1e-6, f_m.T12, rtol=1e-12)
    with pytest.raises(InputError) as err:
        fourbar_dynamics(fb_m, 0.3, 1.0, mass=(1 * u.m, 1, 1), inertia=(1, 1, 1), cg=(0, 0, 0))
    assert err.value.field == "mass m2"


def test_motion_of_another_linkage_is_rejected():
    motion = FourBar(8, 4, 7, 6).solve(0.3, 1.0)
    with pytest.raises(InputError) as err:
        fourbar_forces(FourBar(8, 4, 7, 5), motion, mass=(1, 1, 1), inertia=(1, 1, 1), cg=(0, 0, 0))
    assert err.value.field == "motion"


def test_many_samples_in_blocks_match_single_samples():
    """Beyond one processing block (2**14 samples) per-sample loads stay aligned."""
    fb = FourBar(8, 4, 7, 6)
    n = 40_000
    theta2 = np.linspace(0, 2 * np.pi, n)
    kw = dict(mass=(1, 2, 3), inertia=(1, 2, 3), cg=(1, 2 + 1j, 3))
    f = fourbar_dynamics(fb, theta2, 3.0, external_forces=[(3, 1.0, np.arange(n) * 1j)], **kw)
    pick = np.array([0, 16383, 16384, 32768, n - 1])
    g = fourbar_dynamics(fb, theta2[pick], 3.0, external_forces=[(3, 1.0, pick * 1j)], **kw)
    np.testing.assert_allclose(f.T12[pick], g.T12, rtol=1e-13)
    np.testing.assert_allclose(f.F14[pick], g.F14, rtol=1e-13)
    empty = fourbar_dynamics(fb, np.array([]), 3.0, **kw)
    assert empty.T12.shape == (0,) and len(empty) == 0


def test_docs_examples_run():
    """The python blocks of docs/dynamics.md run, in order, as one script."""
    import re
    from pathlib import Path

    doc = Path(__file__).resolve().parents[1] / "docs" / "dynamics.md"
    code = "\n".join(re.findall(r"```python\n(.*?)```", doc.read_text(), flags=re.S))
    namespace: dict = {}
    exec(compile(code, str(doc), "exec"), namespace)
    assert namespace["f"].ok.any() and namespace["table"].shape[0] == 360


@pytest.mark.parametrize(
    ("omega2", "alpha2", "field"),
    [([1.0, 2.0], 0.0, "omega2"), (1.0, [1.0, 2.0], "alpha2"), (np.ones((2, 2)), 0.0, "omega2")],
)
def test_shape_mismatch_names_the_input(omega2, alpha2, field):
    """Review finding 9: θ2 (3,) with ω2 (2,) raised a bare numpy ValueError."""
    fb = FourBar(8, 4, 7, 6)
    kw = dict(mass=(1, 1, 1), inertia=(1, 1, 1), cg=(1, 1, 1))
    with pytest.raises(InputError, match=r"does not broadcast with theta2 \(3,\)") as err:
        fb.dynamics([0.1, 0.2, 0.3], omega2, alpha2, **kw)
    assert err.value.field == field
    with pytest.raises(InputError) as err:
        fourbar_dynamics(fb, [0.1, 0.2, 0.3], omega2, alpha2, **kw)
    assert err.value.field == field
