"""The periodic steady state found directly, and the flywheel sizing made honest."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import simpson

import machdyn
from machdyn.errors import InputError, ModelError
from machdyn.flywheel import size_flywheel
from machdyn.simulate import ConstantTorque, DCMotor, steady_state, torque

G = 9.81
FB = machdyn.FourBar(0.08, 0.04, 0.07, 0.06)
MASS = {"mass": (0.2, 0.3, 0.25), "inertia": (3e-5, 1.2e-4, 7.5e-5), "cg": (0.02, 0.035, 0.03)}


def energy(theta, omega, flywheel):
    """Kinetic + potential energy of the four-bar, from its kinematics (the test's own sums)."""
    m = FB.solve(theta, omega)
    c2, c3, c4 = MASS["cg"]
    e2, e3, e4 = np.exp(1j * m.theta2), np.exp(1j * m.theta3), np.exp(1j * m.theta4)
    points = (c2 * e2, m.A + c3 * e3, FB.r1 + c4 * e4)
    speeds = (
        1j * m.omega2 * c2 * e2,
        1j * m.omega2 * m.A + 1j * m.omega3 * c3 * e3,
        1j * m.omega4 * c4 * e4,
    )
    total = 0.5 * flywheel * omega**2
    for mk, ik, g, v, w in zip(
        MASS["mass"], MASS["inertia"], points, speeds, (m.omega2, m.omega3, m.omega4), strict=True
    ):
        total = total + 0.5 * mk * abs(v) ** 2 + 0.5 * ik * w**2 + mk * G * g.imag
    return total


def test_shooting_agrees_with_a_long_start_up():
    motor = DCMotor(0.5, 300.0, ratio=10.0)
    p = steady_state(FB, motor, flywheel=0.02, gravity=G, **MASS)
    run = machdyn.simulate(
        FB, motor, flywheel=0.02, gravity=G, until="steady", steady_tol=1e-11, **MASS
    )
    assert p.omega_avg == pytest.approx(run.steady.omega_avg, rel=1e-8)
    assert p.k == pytest.approx(run.steady.k, rel=1e-6)
    assert p.omega[-1] == pytest.approx(p.omega[0], rel=1e-10)  # it closes
    # over the turn the motor's work balances (gravity is conservative)
    assert simpson(p.motor_torque, x=p.theta) == pytest.approx(0.0, abs=1e-9)


def test_constant_torque_at_an_average_speed_conserves_energy():
    p = steady_state(FB, omega_avg=30.0, flywheel=0.02, gravity=G, **MASS)
    assert p.torque == pytest.approx(0.0, abs=1e-9)  # gravity does no net work per turn
    # the time average: one turn over ∮ dθ/ω
    assert 2 * math.pi / simpson(1.0 / p.omega, x=p.theta) == pytest.approx(30.0, rel=1e-7)
    e = energy(p.theta, p.omega, 0.02)
    assert np.ptp(e) < 5e-9 * e.max()  # the table interpolates to 1e-9
    fine = p.at(np.linspace(0.0, 2 * math.pi, 200001))
    assert fine.max() == pytest.approx(p.omega_max, rel=1e-10)
    assert fine.min() == pytest.approx(p.omega_min, rel=1e-10)
    assert p.k == pytest.approx((p.omega_max - p.omega_min) / 30.0, rel=1e-12)


def test_constant_torque_against_a_damper():
    sc = machdyn.SliderCrank(0.05, 0.2)
    p = steady_state(
        sc,
        omega_avg=20.0,
        flywheel=0.05,
        mass=(0.5, 1.0, 1.5),
        inertia=(2e-4, 4e-3),
        cg=(0.0, 0.06),
        friction="viscous",
        beta=8.0,
    )
    d_dot = sc.solve(p.theta, p.omega).d_dot
    # the torque's work per turn is what the damper takes: ∮ T dθ = ∮ β ḋ² dt = ∮ β ḋ²/ω dθ
    assert p.torque * 2 * math.pi == pytest.approx(
        simpson(8.0 * d_dot**2 / p.omega, x=p.theta), rel=1e-7
    )
    assert 2 * math.pi / simpson(1.0 / p.omega, x=p.theta) == pytest.approx(20.0, rel=1e-8)


def test_flywheel_sizing_says_what_it_neglects_and_simulates_it():
    theta = np.radians(np.arange(0.0, 360.0, 0.25))
    needed = FB.dynamics(theta, 30.0, gravity=G, **MASS).T12
    fw = size_flywheel(theta, needed, omega_avg=30.0, k=0.05)
    assert any("varying inertia" in text for text in fw.neglects)
    honest = fw.simulate(FB, gravity=G, **MASS)
    assert honest.omega_avg == pytest.approx(30.0, rel=1e-9)
    assert honest.added_inertia == pytest.approx(fw.inertia)
    # the linkage's own inertia stores energy too: the fluctuation is smaller than estimated
    assert honest.k < fw.k_achieved
    # its motion is a true solution: energy with the linkage's inertia is conserved
    e = energy(honest.theta, honest.omega, fw.inertia)
    assert np.ptp(e) < 5e-9 * e.max()  # the table interpolates to 1e-9
    # with massless moving links the estimate is exact: T12 is then pure gravity... of nothing
    light = {"mass": (1e-9, 1e-9, 1e-9), "inertia": (1e-15, 1e-15, 1e-15), "cg": MASS["cg"]}
    heavy_disc = size_flywheel(theta, 0.1 * np.sin(theta), omega_avg=30.0, k=0.05)
    driven = heavy_disc.simulate(FB, loads=[torque(2, lambda t, x, v: -0.1 * np.sin(x))], **light)
    assert driven.k == pytest.approx(heavy_disc.k_achieved, rel=1e-5)


def test_bad_periodic_requests():
    rocker = machdyn.FourBar(0.06, 0.09, 0.03, 0.08)
    with pytest.raises(InputError, match="turns fully"):
        steady_state(rocker, omega_avg=10.0, **MASS)
    with pytest.raises(InputError, match="omega_avg"):
        steady_state(FB, DCMotor(0.5, 300.0), omega_avg=10.0, **MASS)
    with pytest.raises(InputError, match="omega_avg"):
        steady_state(FB, **MASS)
    with pytest.raises(ModelError, match="no steady speed"):
        steady_state(FB, ConstantTorque(0.1), **MASS)


def test_flywheel_fluctuation_with_the_linkage_inertia_against_solve_ivp():
    # docs/simulate.md's worked example: a 20 mm crank at 32 rad/s, sized for k = 0.10; the
    # honest k is checked against Lagrange's equation integrated here with scipy's solve_ivp,
    #   (I_f + I(θ)) θ̈ + ½ I'(θ) θ̇² + V'(θ) = T,
    # with I(θ) and V(θ) summed here from the four-bar's kinematics and I', V' by differences.
    from scipy.integrate import solve_ivp

    fb = machdyn.FourBar(0.08, 0.02, 0.07, 0.06)
    c2, c3, c4 = MASS["cg"]

    def inertia_and_potential(theta):
        m = fb.solve(np.atleast_1d(theta), 1.0)
        e2, e3, e4 = np.exp(1j * m.theta2), np.exp(1j * m.theta3), np.exp(1j * m.theta4)
        heights = (c2 * e2, m.A + c3 * e3, fb.r1 + c4 * e4)
        speeds = (1j * c2 * e2, 1j * m.A + 1j * m.omega3 * c3 * e3, 1j * m.omega4 * c4 * e4)
        rates = (1.0, m.omega3, m.omega4)
        inertia = potential = 0.0
        for mk, ik, y, v, w in zip(MASS["mass"], MASS["inertia"], heights, speeds, rates,
                                   strict=True):  # fmt: skip
            inertia = inertia + mk * abs(v) ** 2 + ik * w**2
            potential = potential + mk * G * y.imag
        return inertia[0], potential[0]

    theta = np.radians(np.arange(0.0, 360.0, 0.5))
    fw = size_flywheel(theta, fb.dynamics(theta, 32.0, gravity=G, **MASS).T12, 32.0, k=0.10)
    honest = fw.simulate(fb, gravity=G, **MASS)
    h = 1e-6

    def rhs(_t, y):
        (i0, _), (ip, vp), (im, vm) = (inertia_and_potential(y[0] + s) for s in (0, h, -h))
        di, dv = (ip - im) / (2 * h), (vp - vm) / (2 * h)
        return [y[1], (honest.torque - 0.5 * di * y[1] ** 2 - dv) / (fw.inertia + i0)]

    def turned(_t, y):
        return y[0] - (honest.theta[0] + 2 * np.pi)

    turned.terminal = True
    sol = solve_ivp(rhs, (0.0, 1.0), [honest.theta[0], honest.omega[0]], method="DOP853",
                    rtol=1e-11, atol=1e-12, events=turned, dense_output=True)  # fmt: skip
    assert sol.t_events[0][0] == pytest.approx(honest.cycle_time, rel=1e-7)
    at = sol.sol(honest.t)
    assert np.allclose(at[0], honest.theta, atol=1e-7)
    assert np.allclose(at[1], honest.omega, rtol=1e-6)
    omega = sol.sol(np.linspace(0.0, sol.t_events[0][0], 20_001))[1]
    k = (omega.max() - omega.min()) / (2 * np.pi / sol.t_events[0][0])
    assert k == pytest.approx(honest.k, rel=1e-5)
    # and the docs' numbers: the estimate's own fluctuation vs the full model's
    assert (round(fw.k_achieved, 4), round(honest.k, 4)) == (0.0997, 0.0914)
