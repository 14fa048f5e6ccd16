"""Tests of the slider-crank force analysis in machdyn.dynamics (Norton sec. 11.6).

Independent checks: the power balance (with the friction power), Norton's
8×8 matrix built here, and the Coulomb law checked on the returned forces.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.dynamics import slidercrank_dynamics
from machdyn.errors import InputError
from machdyn.slidercrank import SliderCrank

G = 9.81
MASS = (1.5, 2.0, 3.0)
INERTIA = (0.2, 1.8)
CG = (0.6 + 0.2j, 2.5 - 0.3j)


def cross(u, v):
    return u.real * v.imag - u.imag * v.real


def dot(u, v):
    return u.real * v.real + u.imag * v.imag


def kin(sc, m):
    """Centres of mass of crank and rod, their velocities and accelerations, from angles."""
    e2 = np.exp(1j * m.theta2)
    e3 = -np.exp(1j * m.theta3)  # rod frame x from A toward B (θ3 runs B → A)
    A = sc.a * e2
    vA = 1j * m.omega2 * A
    aA = (1j * m.alpha2 - m.omega2**2) * A
    rG = {2: CG[0] * e2, 3: A + CG[1] * e3}
    vG = {2: 1j * m.omega2 * CG[0] * e2, 3: vA + 1j * m.omega3 * CG[1] * e3}
    aG = {
        2: (1j * m.alpha2 - m.omega2**2) * CG[0] * e2,
        3: aA + (1j * m.alpha3 - m.omega3**2) * CG[1] * e3,
    }
    return rG, vG, aG


@pytest.mark.parametrize(
    ("friction", "coef"), [("smooth", {}), ("viscous", {"beta": 4.0}), ("coulomb", {"mu": 0.15})]
)
def test_power_balance(friction, coef):
    sc = SliderCrank(2.0, 7.0, offset=0.5)
    theta2 = np.linspace(0, 2 * np.pi, 241)[:-1] + 0.01
    f = slidercrank_dynamics(
        sc,
        theta2,
        30.0,
        8.0,
        mass=MASS,
        inertia=INERTIA,
        cg=CG,
        gravity=G,
        load_force4=-50.0,
        friction=friction,
        external_forces=[(3, 1.0 + 0.5j, 5 - 2j)],
        external_torques=[(3, 0.7)],
        **coef,
    )
    m = f.motion
    assert f.ok.all()
    _, vG, aG = kin(sc, m)
    e3 = -np.exp(1j * m.theta3)
    vP = vG[3] + 1j * m.omega3 * ((1.0 + 0.5j) - CG[1]) * e3
    p_ext = dot(5 - 2j, vP) + 0.7 * m.omega3 - 50.0 * m.d_dot + f.F14.real * m.d_dot
    dke = (
        MASS[0] * dot(vG[2], aG[2])
        + INERTIA[0] * m.omega2 * m.alpha2
        + MASS[1] * dot(vG[3], aG[3])
        + INERTIA[1] * m.omega3 * m.alpha3
        + MASS[2] * m.d_dot * m.d_ddot
    )
    dpe = G * (MASS[0] * vG[2].imag + MASS[1] * vG[3].imag)  # the slider stays level
    lhs = f.T12 * m.omega2 + p_ext
    np.testing.assert_allclose(lhs, dke + dpe, atol=1e-8 * np.max(np.abs(dke)))
    if friction == "viscous":
        np.testing.assert_allclose(f.F14.real, -4.0 * m.d_dot, rtol=1e-12)
    if friction == "coulomb":
        np.testing.assert_allclose(f.F14.real, -0.15 * np.abs(f.N) * np.sign(m.d_dot), rtol=1e-12)
    if friction == "smooth":
        assert np.all(f.F14.real == 0.0)


def test_matches_norton_matrix_smooth():
    """Norton eq. 11.14 (8 unknowns F12, F32, F43, F14y, T12), built here."""
    sc = SliderCrank(3.0, 10.0, offset=-1.0)
    theta2 = np.radians(np.arange(5.0, 360.0, 20.0))
    f = slidercrank_dynamics(
        sc, theta2, -20.0, 3.0, mass=MASS, inertia=INERTIA, cg=CG, gravity=G, load_force4=10.0
    )
    m = f.motion
    rG, _, aG = kin(sc, m)
    A, B = m.A, m.B
    n = theta2.size
    M = np.zeros((n, 8, 8))
    b = np.zeros((n, 8))
    # unknowns: F12x F12y F32x F32y F43x F43y F14y T12
    R12, R32 = -rG[2], A - rG[2]
    R23, R43 = A - rG[3], B - rG[3]
    M[:, 0, [0, 2]] = 1
    M[:, 1, [1, 3]] = 1
    M[:, 2, 0], M[:, 2, 1], M[:, 2, 2], M[:, 2, 3], M[:, 2, 7] = (
        -R12.imag,
        R12.real,
        -R32.imag,
        R32.real,
        1,
    )
    M[:, 3, 4], M[:, 3, 2] = 1, -1
    M[:, 4, 5], M[:, 4, 3] = 1, -1
    M[:, 5, 4], M[:, 5, 5], M[:, 5, 2], M[:, 5, 3] = -R43.imag, R43.real, R23.imag, -R23.real
    M[:, 6, 4] = -1  # slider x: −F43x = m4 aB − F_load
    M[:, 7, 5], M[:, 7, 6] = -1, 1  # slider y: F14y − F43y = m4 g
    rhs2 = MASS[0] * aG[2] + 1j * MASS[0] * G
    rhs3 = MASS[1] * aG[3] + 1j * MASS[1] * G
    b[:, 0], b[:, 1], b[:, 2] = rhs2.real, rhs2.imag, INERTIA[0] * m.alpha2
    b[:, 3], b[:, 4], b[:, 5] = rhs3.real, rhs3.imag, INERTIA[1] * m.alpha3
    b[:, 6] = MASS[2] * m.d_ddot - 10.0
    b[:, 7] = MASS[2] * G
    x = np.linalg.solve(M, b[..., None])[..., 0]
    got = np.stack(
        [f.F12.real, f.F12.imag, f.F32.real, f.F32.imag, f.F43.real, f.F43.imag, f.N, f.T12], -1
    )
    np.testing.assert_allclose(got, x, atol=1e-10 * np.max(np.abs(x)))


def test_normal_reversals_and_shaking():
    sc = SliderCrank(2.0, 6.0)
    theta2 = np.linspace(0, 2 * np.pi, 361)[:-1]
    f = slidercrank_dynamics(sc, theta2, 50.0, mass=(1.0, 2.0, 1.0), inertia=(0.1, 6.0), cg=(0, 3))
    s = np.sign(f.N)
    expected = np.flatnonzero(s[:-1] * s[1:] < 0)
    assert expected.size >= 2
    np.testing.assert_array_equal(f.normal_reversals(), expected)
    # no gravity or loads: the ground feels −Σ m aG
    e2 = np.exp(1j * theta2)
    e3 = -np.exp(1j * f.motion.theta3)
    a2 = -(50.0**2) * e2
    aG3 = 2.0 * a2 + (1j * f.motion.alpha3 - f.motion.omega3**2) * 3.0 * e3
    fs = -(2.0 * aG3 + 1.0 * f.motion.d_ddot)
    np.testing.assert_allclose(f.shaking_force, fs, atol=1e-9 * np.max(np.abs(fs)))
    assert len(f.to_pandas()) == 360
    assert len(f.plot().lines) == 5


def test_coulomb_wedging_is_flagged():
    sc = SliderCrank(2.0, 3.0)  # the rod tilts up to 41.8°: μ = 2 jams it there
    theta2 = np.radians(np.arange(0.0, 360.0, 10.0)) + 0.05
    f = slidercrank_dynamics(
        sc,
        theta2,
        10.0,
        mass=(1, 1, 1),
        inertia=(1, 1),
        cg=(1, 1.5),
        friction="coulomb",
        mu=2.0,
        load_force4=-100.0,
    )
    assert (~f.ok).any() and f.ok.any()
    assert all("wedges" in r for r in f.reason[~f.ok])


def test_bad_input():
    sc = SliderCrank(2.0, 6.0)
    kw = dict(mass=(1, 1, 1), inertia=(1, 1), cg=(0, 3))
    with pytest.raises(InputError) as err:
        slidercrank_dynamics(sc, 0.3, 1.0, friction="dry", **kw)
    assert "coulomb" in str(err.value)
    with pytest.raises(InputError):
        slidercrank_dynamics(sc, 0.3, 1.0, friction="coulomb", mu=-0.1, **kw)
    with pytest.raises(InputError):
        slidercrank_dynamics(sc, 0.3, 1.0, mass=(1, 1, 1), inertia=(1, 1, 1), cg=(0, 3))
    with pytest.raises(InputError):
        slidercrank_dynamics(sc, 0.3, 1.0, mass=(1, 1, 1), inertia=(1, 1), cg=(0,))


def test_shape_mismatch_names_the_input():
    """Review finding 9: mismatched θ2 and ω2 give an InputError naming ω2."""
    sc = SliderCrank(2.0, 6.0)
    kw = dict(mass=(1, 1, 1), inertia=(1, 1), cg=(0, 3))
    with pytest.raises(InputError) as err:
        slidercrank_dynamics(sc, [0.1, 0.2, 0.3], [1.0, 2.0], **kw)
    assert err.value.field == "omega2"


def test_coulomb_friction_at_a_dead_centre_opposes_the_impending_slip():
    """At θ2 = 0, π, 2π the piston is at rest (ḋ is zero but for rounding, of either
    sign): friction opposes the impending slip, sign(d̈). Independent check: the
    forces equal their one-sided limit, a crank angle 1e-7 later, where the piston
    already slides that way (ω2 > 0: ḋ(θ + ε) ≈ d̈ ε / ω2)."""
    sc = SliderCrank(2.0, 6.0)
    theta2 = np.array([0.0, np.pi, 2 * np.pi])
    kw = dict(mass=(1, 2, 3), inertia=(0.5, 1.5), cg=(1, 3), friction="coulomb", mu=0.3)
    kw.update(load_force4=-50.0, gravity=9.81)
    at = slidercrank_dynamics(sc, theta2, 314.159, **kw)
    after = slidercrank_dynamics(sc, theta2 + 1e-7, 314.159, **kw)
    assert np.all(np.abs(at.motion.d_dot) < 1e-12)  # rounding noise, 0 / −5e-14 / +2e-13
    np.testing.assert_allclose(at.F14, after.F14, rtol=0, atol=0.05)  # friction 11.8
    np.testing.assert_allclose(at.F12, after.F12, rtol=1e-7)
    assert np.all(np.sign(at.F14.real) == -np.sign(at.motion.d_ddot))  # opposes d̈


def test_dead_centre_friction_by_hand_in_millimetres():
    """At θ2 = 0, π, 2π the slider stops (ḋ is 0 but for rounding, ±1e-12) and is about to move
    with d̈ = ω²(∓a − a²/b) (by hand, sin θ2 = 0): friction −μ|N| sign(d̈), never the noise's."""
    a, b, w2, mu = 50.0, 200.0, 314.159, 0.3
    th = np.radians([0.0, 180.0, 360.0])
    f = slidercrank_dynamics(
        SliderCrank(a, b),
        th,
        w2,
        mass=(1, 2, 1.5),
        inertia=(10, 100),
        cg=(20, 100),
        load_force4=-2000.0,
        friction="coulomb",
        mu=mu,
        gravity=9810.0,
    )
    d_ddot = w2**2 * (-a * np.cos(th) - a * a / b)
    assert f.ok.all()
    np.testing.assert_allclose(f.F14.real, -mu * np.abs(f.N) * np.sign(d_ddot), rtol=1e-12)
