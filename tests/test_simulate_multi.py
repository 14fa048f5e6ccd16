"""Two-degree-of-freedom linkages in time (machdyn.simulate with several drivers).

Checked against what shares no code with it:

* two independent physical pendulums driven as one two-driver Linkage, against their
  own equations ``(I_G + m c²) θ̈ = T(θ̇) − m g c cos θ`` integrated here at 1e-12;
* a five-bar with two DC motors against gravity: kinetic energy written here from the
  links' velocities (``Σ ½ m |v_G|² + ½ I ω²``, from ``Linkage.solve``), potential
  energy ``Σ m g y_G``, and the motors' work by Simpson's rule: they balance;
* a five-bar pushed until its coupler pin can no longer close: stopped with the reason.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import simpson, solve_ivp

import machdyn
from machdyn.errors import InputError
from machdyn.linkage import Linkage
from machdyn.simulate import DCMotor

G = 9.81


def two_pendulums() -> Linkage:
    pts = {"O1": 0j, "P1": 0.3 + 0j, "O2": 1 + 0j, "P2": 1.0 + 0.25j}
    lk = Linkage(pts).ground("O1", "O2")
    lk.link("a", "O1", "P1", mass=2.0, inertia=0.02, cg=(0.15, 0.0))
    lk.link("b", "O2", "P2", mass=1.5, inertia=0.01, cg=(0.1, 0.0))
    return lk.drive("a", "b")


def five_bar() -> Linkage:
    pts = {"O2": 0j, "O5": 0.6 + 0j, "A": 0.2j, "D": 0.6 + 0.2j, "C": 0.3 + 0.5j}
    lk = Linkage(pts).ground("O2", "O5")
    lk.link("2", "O2", "A", mass=0.5, inertia=2e-3, cg=(0.1, 0.0))
    lk.link("3", "A", "C", mass=0.8, inertia=1.2e-2, cg=(0.2, 0.0))
    lk.link("4", "D", "C", mass=0.8, inertia=1.2e-2, cg=(0.2, 0.0))
    lk.link("5", "O5", "D", mass=0.5, inertia=2e-3, cg=(0.1, 0.0))
    return lk.drive("2", "5")


def test_two_pendulums_follow_their_own_equations():
    motors = {"a": DCMotor(2.0, 20.0), "b": DCMotor(-1.0, -15.0)}
    run = machdyn.simulate(two_pendulums(), motors, t_end=1.0, gravity=G, samples=101)
    assert run.status == "done"

    def pendulum(m, c, i_g, motor, theta0):
        def rhs(t, y):
            theta, omega = y
            return [omega, (motor(t, theta, omega) - m * G * c * np.cos(theta)) / (i_g + m * c * c)]

        sol = solve_ivp(rhs, (0.0, 1.0), [theta0, 0.0], rtol=1e-12, atol=1e-13, dense_output=True)
        return sol.sol(run.t)[0]

    a = pendulum(2.0, 0.15, 0.02, motors["a"], 0.0)
    b = pendulum(1.5, 0.1, 0.01, motors["b"], np.pi / 2)
    assert np.abs(run.q["a"] - a).max() < 1e-7
    assert np.abs(run.q["b"] - b).max() < 1e-7
    assert np.ptp(run.q["a"]) > 1.0  # it really moved


@pytest.mark.slow
def test_five_bar_with_two_motors_balances_its_energy():
    lk = five_bar()
    motors = {"2": DCMotor(0.6, 10.0), "5": DCMotor(0.3, 5.0, ratio=2.0, inertia=1e-4)}
    run = machdyn.simulate(lk, motors, t_end=0.3, gravity=G, samples=201)
    assert run.status == "done", run.message
    q = {d: run.q[d] for d in ("2", "5")}
    m = lk.solve(q, velocity={d: run.qdot[d] for d in q})
    assert np.all(m.ok)
    kinetic = 0.5 * 4.0 * 1e-4 * run.qdot["5"] ** 2  # the rotor: ratio² J
    potential = 0.0
    for name in ("2", "3", "4", "5"):
        link = lk.links[name]
        kinetic = kinetic + 0.5 * link.mass * np.abs(m.cg_velocity[name]) ** 2
        kinetic = kinetic + 0.5 * link.inertia * m.omega[name] ** 2
        potential = potential + link.mass * G * m.cg[name].imag
    assert np.allclose(run.kinetic, kinetic, rtol=1e-10, atol=1e-12)
    power = sum(run.effort[d] * run.qdot[d] for d in q)
    ends = range(2, run.t.size, 25)
    work = np.array([simpson(power[: k + 1], x=run.t[: k + 1]) for k in ends])
    change = (kinetic + potential - kinetic[0] - potential[0])[2::25]
    assert np.abs(change - work).max() < 1e-6 * np.abs(work).max()
    assert np.abs(run.residual).max() < 1e-8 * run.kinetic.max()
    assert np.allclose(run.w_model, -(potential - potential[0]), atol=1e-9)
    assert np.ptp(run.q["2"]) > 0.5 and np.ptp(run.q["5"]) > 0.05


@pytest.mark.slow
def test_a_pose_that_cannot_close_stops_the_run_with_the_reason():
    lk = five_bar()  # the motors spread the cranks until A, C, D are collinear
    motors = {"2": DCMotor(3.0, 30.0), "5": DCMotor(-2.0, -25.0)}
    run = machdyn.simulate(lk, motors, t_end=0.4, gravity=G, samples=101)
    assert run.status == "unsolved"
    assert "RRR dyad (3, 4)" in run.message and run.t[-1] < 0.4
    m = lk.solve({d: run.q[d][-1:] for d in ("2", "5")})
    assert bool(m.ok[0])  # stopped on the last pose it can take


def test_bad_requests_name_the_field():
    lk = five_bar()
    with pytest.raises(InputError, match="motor"):
        machdyn.simulate(lk, 1.0, t_end=0.1)
    with pytest.raises(InputError, match="unknown driver"):
        machdyn.simulate(lk, {"9": 1.0}, t_end=0.1)
    with pytest.raises(InputError, match="t_end"):
        machdyn.simulate(lk, {"2": 1.0})
    with pytest.raises(InputError, match="turns"):
        machdyn.simulate(lk, {"2": 1.0}, t_end=0.1, turns=2)
