"""machdyn.simulate: forward dynamics checked against things that share no code with it.

* inverse dynamics: driving a model with the Newton–Euler torque of a prescribed
  motion reproduces that motion;
* energy: kinetic and potential energy written out in the test from the link
  kinematics, the works of motor and loads integrated in the test (Simpson);
* a slider-crank start-up against Lagrange's equation integrated in the test
  with its own closed-form kinematics;
* a FourBar against the same linkage drawn as a Linkage, and the table against
  the exact (solve-every-step) evaluation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import simpson, solve_ivp
from scipy.interpolate import CubicSpline

import machdyn
from machdyn.dynamics import fourbar_dynamics
from machdyn.errors import InputError, ModelError
from machdyn.linkage import Linkage
from machdyn.simulate import (
    ConstantTorque,
    DCMotor,
    InductionMotor,
    TorqueFunction,
    force,
    step,
    torque,
)

G = 9.81
# The HW 6 crank-rocker (8-4-7-6) in metres, with masses of a small machine.
FB = machdyn.FourBar(0.08, 0.04, 0.07, 0.06)
MASS = {
    "mass": (0.2, 0.3, 0.25),
    "inertia": (3e-5, 1.2e-4, 7.5e-5),
    "cg": (0.02 + 0.005j, 0.035 - 0.01j, 0.03),
}


def fourbar_energy(fb, theta2, omega2, mass, inertia, cg, flywheel=0.0):
    """Kinetic and potential energy of a four-bar, from the link kinematics (test's own sums)."""
    r1 = fb.r1
    m = fb.solve(theta2, omega2)
    e2, e3, e4 = np.exp(1j * m.theta2), np.exp(1j * m.theta3), np.exp(1j * m.theta4)
    G2, G3, G4 = cg[0] * e2, m.A + cg[1] * e3, r1 + cg[2] * e4
    v2 = 1j * m.omega2 * G2
    v3 = 1j * m.omega2 * m.A + 1j * m.omega3 * cg[1] * e3
    v4 = 1j * m.omega4 * cg[2] * e4
    kinetic = 0.5 * flywheel * m.omega2**2
    potential = 0.0
    for mk, ik, g, v, w in zip(
        mass, inertia, (G2, G3, G4), (v2, v3, v4), (m.omega2, m.omega3, m.omega4), strict=True
    ):
        kinetic = kinetic + 0.5 * mk * np.abs(v) ** 2 + 0.5 * ik * w**2
        potential = potential + mk * G * g.imag
    return kinetic, potential, m


def test_inverse_dynamics_torque_reproduces_the_motion():
    """Drive the four-bar with the Newton–Euler T12 of θ(t) = θ0 + Ωt + A sin νt.

    Open loop, so errors grow: with a light flywheel (4e-4) this motion amplifies a
    1e-9 rad error to 7e-5 rad in 3 s; with 1e-3 the machine is well behaved.
    """
    theta0, big_omega, amp, nu = 0.3, 20.0, 0.5, 10.0
    flywheel = 1e-3
    t = np.linspace(0.0, 2.0, 30001)  # 6.4 turns
    th = theta0 + big_omega * t + amp * np.sin(nu * t)
    w = big_omega + amp * nu * np.cos(nu * t)
    a = -amp * nu * nu * np.sin(nu * t)
    needed = fourbar_dynamics(FB, th, w, a, gravity=G, **MASS).T12 + flywheel * a
    law = CubicSpline(t, needed)
    motor = TorqueFunction(lambda time, theta, omega: float(law(time)))
    run = machdyn.simulate(
        FB, motor, theta0=theta0, omega0=w[0], t_end=2.0, flywheel=flywheel, gravity=G, **MASS
    )
    assert run.status == "t_end"
    got, speed = run.at(t)
    assert np.max(np.abs(got - th)) < 1e-6
    assert np.max(np.abs(speed - w)) < 1e-5 * big_omega
    # the motion's acceleration at the samples is the prescribed one
    assert np.allclose(run.alpha, -amp * nu * nu * np.sin(nu * run.t), atol=1e-5 * amp * nu * nu)


def _lid_linkage():
    """A four-bar drawn as a Linkage with a spring-damper on the rocker and a torsion spring."""
    B = complex(0.07625, math.sqrt(0.07**2 - 0.03625**2))
    return (
        Linkage({"O2": (0, 0), "O4": (0.08, 0), "A": (0.04, 0), "B": B, "S": (0.08, 0.1)})
        .ground("O2", "O4", "S")
        .link("crank", "O2", "A", mass=0.2, inertia=3e-5, cg=0.02)
        .link("coupler", "A", "B", mass=0.3, inertia=1.2e-4, cg=0.035 + 0.01j)
        .link("rocker", "O4", "B", mass=0.25, inertia=7.5e-5, cg=0.03)
        .drive("crank")
        .spring("k", "S", "B", stiffness=40.0, free_length=0.06, damping=0.4)
        .torsion_spring("coil", "O4", stiffness=0.05, free_angle=1.2, damping=2e-4)
    )


def test_inverse_dynamics_of_a_linkage_with_springs_and_dampers():
    lk = _lid_linkage()
    theta0, big_omega, amp, nu = 0.0, 10.0, 0.3, 7.0
    t = np.linspace(0.0, 2.0, 20001)
    th = theta0 + big_omega * t + amp * np.sin(nu * t)
    w = big_omega + amp * nu * np.cos(nu * t)
    a = -amp * nu * nu * np.sin(nu * t)
    needed = lk.forces(lk.solve(th, velocity=w, acceleration=a), gravity=G).driver["crank"]
    law = CubicSpline(t, needed)
    run = machdyn.simulate(
        lk, lambda time, theta, omega: float(law(time)), omega0=w[0], t_end=2.0, gravity=G
    )
    got, _ = run.at(t)
    assert np.max(np.abs(got - th)) < 1e-6
    # energy: the springs and dampers are in it (their work is the model's and the damping's)
    assert run.energy.damping[-1] < 0.0
    assert np.max(np.abs(run.energy.residual)) < 1e-7 * np.max(run.energy.kinetic)


def test_energy_balance_with_motor_load_and_gravity():
    """ΔKE + ΔPE = work of motor and load, each written in the test."""
    motor = DCMotor(stall_torque=0.08, no_load_speed=300.0, ratio=10.0, inertia=1e-6)
    brake = torque(4, lambda time, theta, omega: -0.002 * omega - 0.01 * np.cos(theta))
    flywheel = 1e-3
    run = machdyn.simulate(
        FB, motor, t_end=1.5, flywheel=flywheel, loads=[brake], gravity=G, **MASS
    )
    assert run.status == "t_end"
    t = np.linspace(0.0, 1.5, 60001)
    th, w = run.at(t)
    added = flywheel + 100.0 * 1e-6
    kinetic, potential, m = fourbar_energy(FB, th, w, flywheel=added, **MASS)
    motor_power = 10.0 * 0.08 * (1.0 - 10.0 * w / 300.0) * w
    load_power = (-0.002 * m.omega4 - 0.01 * np.cos(m.theta4)) * m.omega4
    balance = (kinetic[-1] - kinetic[0]) + (potential[-1] - potential[0])
    work = simpson(motor_power, x=t) + simpson(load_power, x=t)
    assert abs(balance - work) < 1e-7 * abs(kinetic[-1])
    # the run's own bookkeeping agrees with the test's
    assert run.energy.motor[-1] == pytest.approx(simpson(motor_power, x=t), rel=1e-7)
    assert run.energy.model[-1] == pytest.approx(-(potential[-1] - potential[0]), rel=1e-6)
    assert np.max(np.abs(run.energy.residual)) < 1e-8 * np.max(run.energy.kinetic)


def test_slider_crank_start_up_against_lagrange():
    """Lagrange's equation with the test's own closed-form slider-crank kinematics."""
    a, b, c = 0.05, 0.18, 0.01  # crank, rod, offset
    m2, m3, m4 = 0.6, 1.1, 1.4
    i2, i3 = 2e-4, 3.5e-3
    c2, c3 = 0.01 + 0.004j, 0.07 - 0.005j
    flywheel, stall, no_load = 0.02, 3.0, 60.0
    beta = 4.0  # viscous friction on the slider

    def geometry(th):
        A = a * np.exp(1j * th)
        dA = 1j * A
        s = a * np.sin(th) - c
        root = np.sqrt(b * b - s * s)
        B = a * np.cos(th) + root + 1j * c
        dB = -a * np.sin(th) - s * a * np.cos(th) / root + 0j
        u = (B - A) / b
        du = (dB - dA) / b
        dG2 = 1j * c2 * np.exp(1j * th)  # centres of mass: G2 = c2 e^{jθ}, G3 = A + c3 u
        dG3 = dA + c3 * du
        dphi3 = (np.conj(u) * du).imag
        inertia = (
            m2 * abs(dG2) ** 2
            + i2
            + m3 * abs(dG3) ** 2
            + i3 * dphi3**2
            + m4 * abs(dB) ** 2
            + flywheel
        )
        gravity = -G * (m2 * dG2.imag + m3 * dG3.imag)  # the slider moves along x
        return inertia, gravity, dB.real

    def rhs(t, y):
        th, w = y
        h = 1e-6
        inertia, gravity, x_rate = geometry(th)
        d_inertia = (geometry(th + h)[0] - geometry(th - h)[0]) / (2 * h)
        motor = stall * (1.0 - w / no_load)
        friction = -beta * x_rate * x_rate * w
        return [w, (motor + gravity + friction - 0.5 * d_inertia * w * w) / inertia]

    ref = solve_ivp(
        rhs, (0.0, 1.0), [0.3, 0.0], method="DOP853", rtol=1e-12, atol=1e-12, dense_output=True
    )
    sc = machdyn.SliderCrank(a, b, c)
    run = machdyn.simulate(
        sc,
        DCMotor(stall, no_load),
        theta0=0.3,
        t_end=1.0,
        flywheel=flywheel,
        mass=(m2, m3, m4),
        inertia=(i2, i3),
        cg=(c2, c3),
        gravity=G,
        friction="viscous",
        beta=beta,
    )
    t = np.linspace(0.0, 1.0, 101)
    th, w = run.at(t)
    assert np.max(np.abs(th - ref.sol(t)[0])) < 1e-7
    assert np.max(np.abs(w - ref.sol(t)[1])) < 1e-6 * no_load


def test_fourbar_and_the_same_linkage_move_alike():
    B = complex(0.07625, math.sqrt(0.07**2 - 0.03625**2))
    lk = (
        Linkage({"O2": (0, 0), "O4": (0.08, 0), "A": (0.04, 0), "B": B})
        .ground("O2", "O4")
        .link("crank", "O2", "A", mass=0.2, inertia=3e-5, cg=0.02 + 0.005j)
        .link("coupler", "A", "B", mass=0.3, inertia=1.2e-4, cg=0.035 - 0.01j)
        .link("rocker", "O4", "B", mass=0.25, inertia=7.5e-5, cg=0.03)
        .drive("crank")
    )
    motor = DCMotor(0.05, 300.0, ratio=10.0)
    one = machdyn.simulate(lk, motor, flywheel=2e-3, t_end=0.6, gravity=G)
    two = machdyn.simulate(FB, motor, flywheel=2e-3, t_end=0.6, gravity=G, **MASS)
    assert np.max(np.abs(one.theta - two.theta)) < 1e-9
    assert one.coordinate == "crank" and two.coordinate == "theta2"


def test_table_agrees_with_solving_at_every_step():
    motor = DCMotor(0.08, 300.0, ratio=10.0)
    kw = dict(flywheel=1e-3, t_end=0.12, gravity=G, samples=11, **MASS)
    fast = machdyn.simulate(FB, motor, **kw)
    slow = machdyn.simulate(FB, motor, table=False, **kw)
    assert "exact" in slow.table and "interpolation error" in fast.table
    assert np.max(np.abs(fast.theta - slow.theta)) < 1e-8
    assert np.max(np.abs(fast.omega - slow.omega)) < 1e-7


def test_start_up_to_steady_state_and_its_fluctuation():
    motor = DCMotor(0.06, 300.0, ratio=10.0)
    run = machdyn.simulate(FB, motor, flywheel=2e-3, until="steady", gravity=G, **MASS)
    assert run.status == "steady" and run.events[-1].kind == "steady"
    s = run.steady
    # the last cycle, sampled here: one period of the input in cycle_time
    t = np.linspace(run.cycles[-2], run.cycles[-1], 20001)
    th, w = run.at(t)
    assert th[-1] - th[0] == pytest.approx(2 * math.pi, abs=1e-8)
    assert s.omega_avg == pytest.approx(2 * math.pi / (t[-1] - t[0]), rel=1e-12)
    assert s.omega_max == pytest.approx(w.max(), rel=1e-8)
    assert s.omega_min == pytest.approx(w.min(), rel=1e-8)
    assert s.k == pytest.approx((w.max() - w.min()) / s.omega_avg, rel=1e-6)
    # conservative loads: at steady state the motor does no net work over a cycle
    power = 10 * 0.06 * (1 - 10 * w / 300.0) * w
    assert abs(simpson(power, x=t)) < 1e-6 * simpson(abs(power), x=t)


def test_turns_coast_down_and_load_step():
    sc = machdyn.SliderCrank(0.05, 0.2)
    kw = dict(
        mass=(0.5, 1.0, 1.5),
        inertia=(2e-4, 4e-3),
        cg=(0.0, 0.06),
        friction="viscous",
        beta=5.0,
        flywheel=0.01,
    )
    run = machdyn.simulate(sc, DCMotor(2.0, 100.0), turns=3, **kw)
    assert run.status == "turns" and run.theta[-1] == pytest.approx(6 * math.pi, abs=1e-9)

    # run for a second, switch the motor off, coast
    run = machdyn.simulate(sc, DCMotor(2.0, 100.0, off_at=1.0), t_end=3.0, **kw)
    kinds = [e.kind for e in run.events]
    assert "breakpoint" in kinds
    after = run.t > 1.0
    assert np.all(run.motor_torque[after] == 0.0)
    assert np.ptp(run.energy.motor[after]) == 0.0 or np.ptp(run.energy.motor[after]) < 1e-12
    assert run.omega[-1] < run.omega[run.t <= 1.0][-1]

    # a piston load steps on at t = 0.5: the work the test integrates balances the energies
    gas = force(4, 0.0, step(0.5, 0.0, -20.0))
    run = machdyn.simulate(sc, DCMotor(2.0, 100.0), t_end=1.0, loads=[gas], **kw)
    t = np.linspace(0.5, 1.0, 20001)  # no work before the step
    th, w = run.at(t)
    load_work = simpson(-20.0 * sc.solve(th, w).d_dot, x=t)
    assert run.energy.loads[-1] == pytest.approx(load_work, rel=1e-8)
    assert np.max(np.abs(run.energy.residual)) < 1e-8 * np.max(run.energy.kinetic)


def test_forces_along_the_simulated_motion():
    run = machdyn.simulate(
        FB,
        DCMotor(0.06, 300.0, ratio=10.0),
        flywheel=2e-3,
        t_end=0.3,
        samples=301,
        gravity=G,
        **MASS,
    )
    f = run.forces()
    assert f.ok.all()
    # the shaft delivers the motor's torque less what accelerates the flywheel
    assert np.allclose(f.T12, run.motor_torque - 2e-3 * run.alpha, rtol=1e-9, atol=1e-12)
    assert f.F12.shape == run.t.shape


def test_motor_between_moving_links():
    """HW 6 driven at its joint A (crank–coupler) against gravity: energy written in the test."""
    B = complex(0.07625, math.sqrt(0.07**2 - 0.03625**2))
    lk = (
        Linkage({"O2": (0, 0), "O4": (0.08, 0), "A": (0.04, 0), "B": B})
        .ground("O2", "O4")
        .link("crank", "O2", "A", mass=0.2, inertia=3e-5, cg=0.02)
        .link("coupler", "A", "B", mass=0.3, inertia=1.2e-4, cg=0.035)
        .link("rocker", "O4", "B", mass=0.25, inertia=7.5e-5, cg=0.03)
        .motor("elbow", "A")
        .drive("elbow")
    )
    run = machdyn.simulate(lk, ConstantTorque(0.01), t_end=0.5, gravity=G)
    assert run.coordinate == "elbow" and run.angular
    t = np.linspace(0.0, run.t[-1], 20001)
    phi, rate = run.at(t)
    m = lk.solve(phi, velocity=rate)
    kinetic = potential = 0.0
    for name, link in lk.links.items():
        kinetic = kinetic + 0.5 * link.mass * abs(m.cg_velocity[name]) ** 2
        kinetic = kinetic + 0.5 * link.inertia * m.omega[name] ** 2
        potential = potential + link.mass * G * m.cg[name].imag
    work = simpson(0.01 * rate, x=t)
    change = (kinetic[-1] - kinetic[0]) + (potential[-1] - potential[0])
    assert change == pytest.approx(work, rel=1e-7, abs=1e-12)


def test_motor_too_weak_to_start_reports_the_deficit():
    theta0 = math.radians(60.0)
    run = machdyn.simulate(FB, ConstantTorque(1e-3), theta0=theta0, t_end=1.0, gravity=G, **MASS)
    needed = float(fourbar_dynamics(FB, theta0, 0.0, 0.0, gravity=G, **MASS).T12)
    assert run.status == "stall" and len(run.t) == 1
    (event,) = run.events
    assert event.kind == "stall" and "cannot start" in event.message
    assert event.deficit == pytest.approx(needed - 1e-3, rel=1e-9)


def test_stall_during_the_motion():
    """Enough torque to start at the bottom, not enough to lift the heavy crank over the top."""
    heavy = {"mass": (2.0, 0.0, 0.0), "inertia": (1e-3, 0.0, 0.0), "cg": (0.04, 0.0, 0.0)}
    lift = 2.0 * G * 0.04  # the crank's weight at its full arm
    motor = DCMotor(0.6 * lift, 50.0)
    run = machdyn.simulate(FB, motor, theta0=-math.pi / 2, t_end=5.0, gravity=G, **heavy)
    assert run.status == "stall"
    event = run.events[-1]
    assert event.kind == "stall" and event.deficit > 0.0
    # where it stalled, the crank's weight needs more than the motor's stall torque
    assert 2.0 * G * 0.04 * math.cos(event.theta) == pytest.approx(
        0.6 * lift + event.deficit, rel=1e-6
    )
    # and it does not stop there if told to let it roll back
    back = machdyn.simulate(
        FB, motor, theta0=-math.pi / 2, t_end=1.0, gravity=G, stop_on=(), **heavy
    )
    assert back.status == "t_end" and any(e.kind == "stall" for e in back.events)


def test_a_rocker_driven_to_its_toggle_stops_naming_it():
    fb = machdyn.FourBar(0.06, 0.09, 0.03, 0.08)  # GRCR: link 2 rocks between toggles of 3-4
    run = machdyn.simulate(fb, ConstantTorque(0.2), t_end=2.0, gravity=G, **MASS)
    assert run.status == "toggle"
    event = run.events[-1]
    assert "links 3 and 4 are collinear" in event.message
    hi = fb.input_range(1).hi
    assert 0.0 < hi - event.theta < 1e-3
    # with no motor, let go at rest near the upper toggle, gravity pulls it in
    run = machdyn.simulate(fb, None, theta0=hi - 0.05, t_end=2.0, gravity=G, **MASS)
    assert run.status == "toggle" and 0.0 < hi - run.events[-1].theta < 1e-3
    # near the lower one gravity pushes it back: it rocks, reversing, without loss
    lo = fb.input_range(1).lo
    run = machdyn.simulate(fb, None, theta0=lo + 0.05, t_end=1.0, gravity=G, **MASS)
    assert run.status == "t_end" and sum(e.kind == "reversal" for e in run.events) >= 4
    assert run.theta.min() == pytest.approx(lo + 0.05, abs=1e-9)
    kinetic, potential, _ = fourbar_energy(fb, run.theta, run.omega, **MASS)
    assert np.ptp(kinetic + potential) < 1e-9


def test_a_free_swing_reverses_and_keeps_its_energy():
    """A pendulum-like crank with no motor swings back and forth; energy is conserved."""
    swing = {"mass": (1.0, 0.0, 0.0), "inertia": (1e-4, 0.0, 0.0), "cg": (0.04, 0.0, 0.0)}
    run = machdyn.simulate(FB, None, theta0=0.0, t_end=2.0, gravity=G, **swing)
    assert run.status == "t_end"
    assert sum(e.kind == "reversal" for e in run.events) >= 2
    assert run.theta.min() == pytest.approx(-math.pi, abs=2e-3)  # from horizontal to horizontal
    energy = 0.5 * (1.0 * 0.04**2 + 1e-4) * run.omega**2 + 1.0 * G * 0.04 * np.sin(run.theta)
    assert np.ptp(energy) < 1e-8


def test_motor_laws():
    dc = DCMotor.from_electrical(voltage=24.0, resistance=2.0, kt=0.05)
    assert dc.stall_torque == pytest.approx(0.6) and dc.no_load_speed == pytest.approx(480.0)
    im = InductionMotor(synchronous_speed=157.08, breakdown_torque=60.0, breakdown_slip=0.2)
    s = 1.0 - np.array([0.0, 0.8, 1.0]) * 1.0  # slips at ω = 0, 0.2 ω_s, ω_s
    got = im(0.0, 0.0, (1.0 - s) * 157.08)
    assert np.allclose(got, 2 * 60.0 * s * 0.2 / (s * s + 0.04))
    assert im(0.0, 0.0, 0.8 * 157.08) == pytest.approx(60.0)  # breakdown at s = s_b
    rated = InductionMotor.from_rating(
        20.0, rated_speed=150.0, synchronous_speed=157.08, breakdown_factor=2.5
    )
    assert rated(0.0, 0.0, 150.0) == pytest.approx(20.0, rel=1e-12)
    assert rated.breakdown_torque == pytest.approx(50.0)
    geared = ConstantTorque(2.0, ratio=5.0, inertia=1e-3)
    assert geared(0.0, 0.0, 1.0) == 10.0 and geared.reflected_inertia == pytest.approx(0.025)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"flywheel": -1.0, "t_end": 1.0}, "flywheel"),
        ({}, "t_end"),
        ({"t_end": -1.0}, "t_end"),
        ({"t_end": 1.0, "rtol": 0.0}, "rtol"),
        ({"t_end": 1.0, "until": "forever"}, "until"),
        ({"t_end": 1.0, "stop_on": ("toggle!",)}, "stop_on"),
        ({"t_end": 1.0, "wind": 3.0}, "wind"),
        ({"t_end": 1.0, "loads": [torque(5, 1.0)]}, "loads"),
        ({"t_end": 1.0, "loads": ["brake"]}, "loads[0]"),
    ],
)
def test_bad_input_names_the_field(kwargs, field):
    with pytest.raises(InputError) as err:
        machdyn.simulate(FB, 0.1, **{**MASS, **kwargs})
    assert err.value.field == field


def test_bad_models_and_options():
    with pytest.raises(InputError, match="FourBar, SliderCrank or Linkage"):
        machdyn.simulate("fourbar", 1.0, t_end=1.0)
    with pytest.raises(InputError, match="mass"):
        machdyn.simulate(FB, 1.0, t_end=1.0)
    sc = machdyn.SliderCrank(0.05, 0.2)
    kw = dict(mass=(0.5, 1.0, 1.5), inertia=(2e-4, 4e-3), cg=(0.0, 0.06))
    with pytest.raises(InputError, match="Coulomb"):
        machdyn.simulate(sc, 1.0, t_end=1.0, friction="coulomb", mu=0.1, **kw)
    with pytest.raises(InputError, match="does not turn"):
        machdyn.simulate(sc, 1.0, t_end=1.0, loads=[torque(4, 1.0)], **kw)
    rocker = machdyn.FourBar(0.06, 0.09, 0.03, 0.08)
    with pytest.raises(InputError, match="outside"):
        machdyn.simulate(rocker, 1.0, theta0=3.0, t_end=1.0, **MASS)
    with pytest.raises(InputError, match="rocker"):
        machdyn.simulate(rocker, 1.0, turns=2, **MASS)
    with pytest.raises(InputError, match="motor"):
        machdyn.simulate(FB, "strong", t_end=1.0, **MASS)
    two = (
        Linkage({"O2": (0, 0), "A": (1, 0), "B": (2, 0), "O4": (3, 0)})
        .ground("O2", "O4")
        .link("a", "O2", "A")
        .link("b", "A", "B")
        .link("c", "B", "O4")
        .drive("a", "c")
    )
    with pytest.raises(ModelError, match="one degree of freedom"):
        machdyn.simulate(two, 1.0, t_end=1.0)


def test_machdyn_simulate_is_the_function_whatever_is_imported_first():
    import importlib

    module = importlib.import_module("machdyn.simulate")
    assert callable(machdyn.simulate) and machdyn.simulate is module.simulate
    from machdyn.simulate import Simulation  # the classes load from the module

    assert Simulation.__name__ == "Simulation"
