"""Audit: flywheel sizing, balancing, shaking force and virtual work (Norton ch. 10–13).

Expected values are worked here: the final exam's tire (problem 8) by the
notes' moment balance about plane A, random rotors balanced and checked by
Σ mR = 0, Σ m z R = 0 (Norton eq. 12.2–12.4), flywheel energy by integrating
the torque curve on a finer grid than machdyn's (Table 11-1 method, Norton
eq. 11.19–11.21), the four-bar's shaking force as −Σ mᵢ a_Gi with a_G from this
file's own loop solution, and the input torque by the power balance
T12 ω2 = d(KE)/dt (Norton sec. 10.13–10.14) with KE differentiated numerically.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import FourBar
from machdyn.balancing import bearing_balance, static_balance, two_plane
from machdyn.dynamics import fourbar_dynamics
from machdyn.flywheel import size_flywheel
from machdyn.shaking import fourbar_counterweights
from machdyn.virtual_work import fourbar_input_torque


def test_final_exam_tire_balance_by_moments_about_plane_a():
    """Final exam 8: ω = 10 rad/s; F_L = 12 N ∠ 75°, F_R = 10 N ∠ −30°; bearings 25 cm
    apart, rim's left edge (plane A) 10 cm from the nearer bearing, rim 17.5 cm wide
    (plane B), rim diameter 37.5 cm. With the wheel outboard of both bearings (the
    Problem 12-6 layout): z_L = −0.35, z_R = −0.10, z_B = 0.175 m, R = 0.1875 m.
    Moments about A: z_L F_L + z_R F_R + z_B m_B ω² R_B = 0; forces: F_L + F_R +
    m_A ω² R_A + m_B ω² R_B = 0 (SI throughout)."""
    omega, radius = 10.0, 0.1875
    f_l = 12 * np.exp(1j * np.radians(75))
    f_r = 10 * np.exp(-1j * np.radians(30))
    mb_rb = -(-0.35 * f_l + -0.10 * f_r) / (0.175 * omega**2)
    ma_ra = -(f_l + f_r) / omega**2 - mb_rb
    m_b, m_a = abs(mb_rb) / radius, abs(ma_ra) / radius
    assert m_b == pytest.approx(1.2367, abs=1e-4)  # kg
    assert np.degrees(np.angle(mb_rb)) == pytest.approx(61.23, abs=0.01)
    assert m_a == pytest.approx(1.8857, abs=1e-4)
    assert np.degrees(np.angle(ma_ra)) % 360 == pytest.approx(229.58, abs=0.01)
    fix = bearing_balance([f_l, f_r], [-0.35, -0.10], omega=omega, plane_a=0.0, plane_b=0.175)
    m_a_got, m_b_got = fix.masses(radius)
    assert (m_a_got, m_b_got) == pytest.approx((m_a, m_b), rel=1e-10)
    assert fix.angle_b_deg == pytest.approx(np.degrees(np.angle(mb_rb)), abs=1e-9)
    assert fix.angle_a_deg == pytest.approx(np.degrees(np.angle(ma_ra)) % 360, abs=1e-9)
    # same answer in cm: lengths in cm and forces in N·(cm/m) — masses unchanged
    fix_cm = bearing_balance(
        [100 * f_l, 100 * f_r], [-35.0, -10.0], omega=omega, plane_a=0.0, plane_b=17.5
    )
    assert fix_cm.masses(18.75) == pytest.approx((m_a, m_b), rel=1e-10)


def test_random_rotors_two_plane_and_static_balance(rng):
    """Norton eq. 12.2 (static: Σ mR + m_b R_b = 0) and 12.4 (dynamic: Σ F = 0 and
    Σ M about A = 0), checked on the corrected rotor for 200 random rotors."""
    for _ in range(200):
        n = int(rng.integers(1, 6))
        mr = rng.uniform(0.1, 2, n) * np.exp(1j * rng.uniform(0, 2 * np.pi, n))
        z = rng.uniform(-1, 1, n)
        za, zb = sorted(rng.uniform(-2, 2, 2))
        if zb - za < 0.05:
            continue
        st = static_balance(mr)
        assert abs(np.sum(mr) + st.mR) < 1e-12
        fix = two_plane(mr, z, za, zb)
        mr_a, mr_b = fix
        assert abs(np.sum(mr) + mr_a + mr_b) < 1e-11
        assert abs(np.sum(mr * z) + mr_a * za + mr_b * zb) < 1e-11
        assert fix.angle_a_deg == pytest.approx(np.degrees(np.angle(mr_a)) % 360)


def test_flywheel_energy_by_fine_integration(rng):
    """Table 11-1 method on random smooth torque curves: ΔE = max − min of
    E(θ) = ∫(T − T_avg) dθ (fine grid here, coarse samples in machdyn), I = ΔE/(k ω²)."""
    for _ in range(10):
        c = rng.normal(size=(4, 2)) * rng.uniform(5, 60)

        def torque(t, c=c):
            return 200.0 + sum(
                c[i, 0] * np.sin((i + 1) * t) + c[i, 1] * np.cos((i + 1) * t) for i in range(4)
            )

        theta = np.linspace(0, 2 * np.pi, 721)[:-1]
        omega, k = float(rng.uniform(10, 100)), float(rng.uniform(0.005, 0.1))
        fw = size_flywheel(theta, torque(theta), omega_avg=omega, k=k)
        fine = np.linspace(0, 2 * np.pi, 200001)
        # the curve machdyn sees is piecewise linear between the 720 samples
        t_lin = np.interp(fine, np.append(theta, 2 * np.pi), np.append(torque(theta), torque(0)))
        t_avg = np.trapezoid(t_lin, fine) / (2 * np.pi)
        assert fw.torque_avg == pytest.approx(t_avg, rel=1e-9)
        e = np.concatenate([[0], np.cumsum(0.5 * (t_lin[1:] + t_lin[:-1]) * np.diff(fine))])
        e -= t_avg * fine
        # T12 is what the linkage takes: where the accumulated (T12 − T_avg) peaks the
        # flywheel has given the most (ω lowest)
        delta = e.max() - e.min()
        assert fw.delta_e == pytest.approx(delta, rel=1e-6)
        assert fw.inertia == pytest.approx(delta / (k * omega**2), rel=1e-6)
        assert fw.theta_omega_min == pytest.approx(fine[np.argmax(e)], abs=1e-3)
        assert fw.theta_omega_max == pytest.approx(fine[np.argmin(e)], abs=1e-3)
        assert fw.k_achieved == pytest.approx(k, rel=3 * k)
        lobes = fw.lobes
        assert np.sum(lobes.area) == pytest.approx(0, abs=1e-9 * delta)
        for t0, t1, area in zip(lobes.theta_from, lobes.theta_to, lobes.area, strict=True):
            e0, e1 = np.interp([t0, t1], fine, e)
            span = e1 - e0 if t1 > t0 else (e[-1] - e0) + (e1 - e[0])
            assert area == pytest.approx(span, rel=1e-6, abs=1e-9 * delta)
            # the lobe's ends are zero crossings of T − T_avg
            for t in (t0, t1):
                assert np.interp(t, fine, t_lin) - t_avg == pytest.approx(0, abs=1e-3 * delta)


def _fourbar_motion(fb, t2, w2, a2, sign12=1.0):
    """Positions, ω, α of links 3 and 4 from this file's own solution (circles + solves)."""
    a, b, c, d = fb.r2, fb.r3, fb.r4, fb.r1
    A = a * np.exp(1j * t2)
    f = np.abs(d - A)
    u = (d - A) / f
    x = (b * b - c * c + f * f) / (2 * f)
    h = np.sqrt(b * b - x * x)
    out = []
    for s in (1.0, -1.0):
        B = A + u * (x + 1j * s * h)
        t3, t4 = np.angle(B - A), np.angle(B - d)
        out.append((t3, t4))
    (t3a, t4a), (t3b, t4b) = out
    pick = np.sign(np.angle(np.exp(1j * (t4a - t3a)))) == sign12
    t3, t4 = np.where(pick, t3a, t3b), np.where(pick, t4a, t4b)
    e2, e3, e4 = np.exp(1j * t2), np.exp(1j * t3), np.exp(1j * t4)
    det = b * c * np.sin(t4 - t3)
    w3 = a * w2 * np.sin(t4 - t2) / (b * np.sin(t3 - t4))
    w4 = a * w2 * np.sin(t2 - t3) / (c * np.sin(t4 - t3))
    k = a * (1j * a2 - w2**2) * e2 - b * w3**2 * e3 + c * w4**2 * e4
    # j b α3 e3 − j c α4 e4 = −k  (Cramer's rule on the real/imag parts)
    al3 = (-k.real * (-c * np.cos(t4)) - (-k.imag) * (c * np.sin(t4))) / (
        (-b * np.sin(t3)) * (-c * np.cos(t4)) - (c * np.sin(t4)) * (b * np.cos(t3))
    )
    al4 = ((-b * np.sin(t3)) * (-k.imag) - (b * np.cos(t3)) * (-k.real)) / (
        (-b * np.sin(t3)) * (-c * np.cos(t4)) - (c * np.sin(t4)) * (b * np.cos(t3))
    )
    assert np.all(np.abs(det) > 1e-9)
    return t3, t4, w3, w4, al3, al4


def test_shaking_force_is_minus_sum_of_m_aG_and_berkof_lowen_balances_it(rng):
    """Norton eq. 11.15 without gravity or loads: F_s = −Σ m_i a_Gi, a_G from this file's
    kinematics; after the Berkof–Lowen counterweights (Norton sec. 12.4) the total mass
    centre, computed here, does not move and the shaking force vanishes."""
    fb = FourBar(8, 4, 7, 6)
    mass, inertia, cg = (1.2, 2.5, 1.8), (0.8, 3.1, 1.4), (2.0 + 0.3j, 3.5 + 0.4j, 3.0 - 0.2j)
    t2 = np.linspace(0, 2 * np.pi, 73)[:-1]
    w2, a2 = 12.0, 3.0
    t3, t4, w3, w4, al3, al4 = _fourbar_motion(fb, t2, w2, a2)
    A = fb.r2 * np.exp(1j * t2)
    aA = fb.r2 * (1j * a2 - w2**2) * np.exp(1j * t2)
    aG2 = (1j * a2 - w2**2) * cg[0] * np.exp(1j * t2)
    aG3 = aA + (1j * al3 - w3**2) * cg[1] * np.exp(1j * t3)
    aG4 = (1j * al4 - w4**2) * cg[2] * np.exp(1j * t4)
    expected = -(mass[0] * aG2 + mass[1] * aG3 + mass[2] * aG4)
    f = fourbar_dynamics(fb, t2, w2, a2, mass=mass, inertia=inertia, cg=cg)
    np.testing.assert_allclose(f.shaking_force, expected, rtol=1e-10, atol=1e-9)
    # shaking moment about O2 = −dH_O2/dt = −Σ(I_G α + r_G × m a_G) (Norton eq. 11.15)
    G = (
        cg[0] * np.exp(1j * t2),
        A + cg[1] * np.exp(1j * t3),
        fb.r1 + cg[2] * np.exp(1j * t4),
    )
    dH = sum(
        inertia[i] * alpha + (np.conj(G[i]) * mass[i] * aG).imag
        for i, (alpha, aG) in enumerate(((a2, aG2), (al3, aG3), (al4, aG4)))
    )
    np.testing.assert_allclose(f.shaking_moment, -dH, rtol=1e-9, atol=1e-9 * np.max(np.abs(dH)))
    # balanced linkage
    cw = fourbar_counterweights(fb, mass=mass, cg=cg)
    m_b, i_b, cg_b = cw.apply(mass, inertia, cg, counterweight_mass=(1.5, 2.5))
    total_mc = (
        m_b[0] * cg_b[0] * np.exp(1j * t2)
        + m_b[1] * (A + cg_b[1] * np.exp(1j * t3))
        + m_b[2] * (fb.r1 + cg_b[2] * np.exp(1j * t4))
    )
    assert np.ptp(total_mc.real) < 1e-9 and np.ptp(total_mc.imag) < 1e-9
    fb_bal = fourbar_dynamics(fb, t2, w2, a2, mass=m_b, inertia=i_b, cg=cg_b)
    assert np.max(np.abs(fb_bal.shaking_force)) < 1e-9 * np.max(np.abs(expected))


def test_input_torque_by_power_balance(rng):
    """T12 ω2 = d(KE)/dt with no loads or gravity (Norton sec. 10.14): KE from this file's
    kinematics, differentiated in time by five-point differences along θ2(t) = θ0 + ω2 t."""
    fb = FourBar(8, 4, 7, 6)
    mass, inertia, cg = (1.0, 2.0, 1.5), (0.5, 2.0, 1.0), (2.0, 3.5 + 1j, 3.0)
    w2 = 7.0
    h = 1e-4

    def kinetic_energy(t2):
        t3, t4, w3, w4, _, _ = _fourbar_motion(fb, t2, w2, 0.0)
        vA = 1j * w2 * fb.r2 * np.exp(1j * t2)
        vG2 = 1j * w2 * cg[0] * np.exp(1j * t2)
        vG3 = vA + 1j * w3 * cg[1] * np.exp(1j * t3)
        vG4 = 1j * w4 * cg[2] * np.exp(1j * t4)
        return 0.5 * (
            mass[0] * abs(vG2) ** 2
            + mass[1] * abs(vG3) ** 2
            + mass[2] * abs(vG4) ** 2
            + inertia[0] * w2**2
            + inertia[1] * w3**2
            + inertia[2] * w4**2
        )

    t2 = rng.uniform(0, 2 * np.pi, 20)
    ke = [kinetic_energy(t2 + w2 * k * h) for k in (-2, -1, 1, 2)]
    dke = (ke[0] - 8 * ke[1] + 8 * ke[2] - ke[3]) / (12 * h)
    f = fourbar_dynamics(fb, t2, w2, 0.0, mass=mass, inertia=inertia, cg=cg)
    np.testing.assert_allclose(f.T12 * w2, dke, rtol=1e-6, atol=1e-6 * np.max(np.abs(dke)))
    vw = fourbar_input_torque(fb, t2, w2, mass=mass, inertia=inertia, cg=cg)
    np.testing.assert_allclose(vw.T12, f.T12, rtol=1e-9, atol=1e-9)


def test_mass_properties_by_numerical_integration(rng):
    """I_G = ∫(x² + y²) dm (notes 10-27, Norton sec. 10.4) of each shape integrated
    numerically here on a fine grid; the notes' lollipop I_O = ML²/3 + ½M_dR² + M_d(l+R)²
    by the parallel-axis theorem."""
    from machdyn.massprops import annulus, disc, plate, ring, rod

    n = 1201
    u = (np.arange(n) + 0.5) / n  # midpoints

    # rod of length L along angle φ from `start`
    m, L, phi, start = 2.0, 3.0, 0.7, 1 + 2j
    r = rod(m, L, start=start, angle=phi)
    pts = start + u * L * np.exp(1j * phi)
    assert r.cg == pytest.approx(pts.mean())
    assert r.inertia == pytest.approx(m * np.mean(np.abs(pts - pts.mean()) ** 2), rel=1e-5)
    # plate w × h
    w, h = 0.4, 0.2
    X, Y = np.meshgrid((u - 0.5) * w, (u - 0.5) * h)
    assert plate(m, w, h).inertia == pytest.approx(m * np.mean(X**2 + Y**2), rel=1e-5)
    # disc, annulus, ring by radial integration (area element 2πr dr)
    R, Ri = 0.3, 0.1
    rr = u * R
    assert disc(m, R).inertia == pytest.approx(m * np.sum(rr**3) / np.sum(rr), rel=1e-5)
    ra = Ri + u * (R - Ri)
    assert annulus(m, R, Ri).inertia == pytest.approx(m * np.sum(ra**3) / np.sum(ra), rel=1e-5)
    assert ring(m, R).inertia == pytest.approx(m * R * R)
    # the notes' lollipop: rod (M_R, l) from O plus a disc (M_d, R) centred at l + R
    MR, l_, Md, Rd = 1.2, 0.9, 3.0, 0.15
    lolli = rod(MR, l_) + disc(Md, Rd, centre=l_ + Rd)
    expected = MR * l_**2 / 3 + 0.5 * Md * Rd**2 + Md * (l_ + Rd) ** 2
    assert lolli.inertia_about(0) == pytest.approx(expected, rel=1e-12)


def test_flywheel_four_stroke_period_and_uneven_samples(rng):
    """A four-stroke engine cycle of 4π (flywheel by the Table 11-1 method, `period=4π`),
    sampled unevenly from θ0 = 1 rad: ΔE from this file's integration of the piecewise
    linear curve closed over the period."""
    period = 4 * np.pi
    theta = 1.0 + np.sort(rng.uniform(0, period, 500))
    theta[0] = 1.0
    torque = 50 + 400 * np.sin(theta / 2) ** 8 - 30 * np.cos(theta)
    fw = size_flywheel(theta, torque, omega_avg=150.0, k=0.03, period=period)
    t_closed = np.append(theta, 1.0 + period)
    y_closed = np.append(torque, torque[0])
    fine = np.linspace(1.0, 1.0 + period, 400001)
    y = np.interp(fine, t_closed, y_closed)
    t_avg = np.trapezoid(y, fine) / period
    e = np.concatenate([[0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(fine))]) - t_avg * (
        fine - 1.0
    )
    assert fw.torque_avg == pytest.approx(t_avg, rel=1e-9)
    assert fw.delta_e == pytest.approx(e.max() - e.min(), rel=1e-6)
    assert fw.inertia == pytest.approx((e.max() - e.min()) / (0.03 * 150.0**2), rel=1e-6)


@pytest.mark.parametrize("friction", ["smooth", "viscous", "coulomb"])
def test_inverted_slidercrank_forces_by_power_balance(friction, rng):
    """Norton sec. 10.14 / 11.7: T12 ω2 + T4 ω4 + P_gravity + P_friction = d(KE)/dt, with
    KE from the links' centre-of-mass velocities (block turning with link 4) and the
    slot's friction power −μ|N||ḃ| (Coulomb) or −β ḃ² (viscous); d/dt by five-point
    differences along θ2(t) = θ0 + ω2 t. Random machines of either form and offset sign."""
    from machdyn import InvertedSliderCrank
    from machdyn.dynamics_inverted import inverted_slidercrank_dynamics

    h = 1e-4
    n = 0
    while n < 6:
        a, d = rng.uniform(1, 5, 2)
        c = rng.uniform(-0.5, 0.5) * min(a, d)
        isc = InvertedSliderCrank(a, d, c)
        form = int(rng.integers(1, 3))
        mass = tuple(rng.uniform(0.5, 3, 3))
        inertia = tuple(rng.uniform(0.1, 2, 3))
        cg = (a / 2 + 0.2j, 0.1 - 0.05j, complex(rng.uniform(-1, 3), c))
        w2, g, t4 = float(rng.uniform(2, 8)), 9.81, float(rng.uniform(-5, 5))
        options = dict(mass=mass, inertia=inertia, cg=cg, form=form, gravity=g)
        options |= dict(load_torque4=t4, friction=friction, mu=0.2, beta=0.7)
        t2 = rng.uniform(0, 2 * np.pi, 8)
        if not isc.solve(t2 + w2 * 2 * h * np.array([[-1], [1]]), form=form).ok.all():
            continue
        f = inverted_slidercrank_dynamics(isc, t2, w2, 0.0, **options)
        if not f.ok.all():
            continue
        n += 1

        def energy(t, isc=isc, form=form, w2=w2, mass=mass, inertia=inertia, cg=cg, g=g):
            m = isc.solve(t, w2, 0.0, form=form)
            e2, e4 = np.exp(1j * m.theta2), np.exp(1j * m.theta4)
            vA = 1j * w2 * m.A
            v = (1j * w2 * cg[0] * e2, vA + 1j * m.omega4 * cg[1] * e4, 1j * m.omega4 * cg[2] * e4)
            y = ((cg[0] * e2).imag, (m.A + cg[1] * e4).imag, (cg[2] * e4).imag)
            w = (w2, m.omega4, m.omega4)
            return sum(
                0.5 * mass[i] * abs(v[i]) ** 2 + 0.5 * inertia[i] * w[i] ** 2 + mass[i] * g * y[i]
                for i in range(3)
            )

        e = [energy(t2 + w2 * k * h) for k in (-2, -1, 1, 2)]
        de = (e[0] - 8 * e[1] + 8 * e[2] - e[3]) / (12 * h)
        m = f.motion
        if friction == "coulomb":
            loss = -0.2 * np.abs(f.normal) * np.abs(m.b_dot)
        elif friction == "viscous":
            loss = -0.7 * m.b_dot**2
        else:
            loss = 0.0
        power = f.T12 * w2 + t4 * m.omega4 + loss
        np.testing.assert_allclose(power, de, rtol=1e-6, atol=1e-6 * np.max(np.abs(de)))
