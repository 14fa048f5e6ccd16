"""Open chains in a Linkage: links that hang on a pin outside every loop, angle driven.

A lid on its hinge with a gas spring, a two-link arm with a shoulder drive and an
elbow motor, and a four-bar carrying a driven flap: each checked against closed
forms written here (positions, velocities, Newton–Euler moments about the pins, and
the power balance with kinetic energy computed in the test).
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.errors import InputError, ModelError
from machdyn.fourbar import FourBar
from machdyn.linkage import Linkage

# every test on the NumPy path and on the compiled kernels (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("backend")

G = 9.81


def test_a_lid_on_its_hinge_with_a_gas_spring_by_hand():
    # lid O2-P (length 1, mass 2 at 0.5, I_G 0.3), spring from S = (0, 2) to P
    theta = np.linspace(0.0, 1.2, 25)
    omega, alpha = np.full(theta.size, 1.5), np.full(theta.size, -2.0)
    lk = (
        Linkage({"O2": 0, "P": 1 + 0j, "S": 2j})
        .ground("O2", "S")
        .link("lid", "O2", "P", mass=2.0, inertia=0.3, cg=0.5)
        .spring("gas", "S", "P", stiffness=40.0, free_length=1.5, damping=0.7)
        .drive("lid")
    )
    m = lk.solve({"lid": theta}, velocity={"lid": omega}, acceleration={"lid": alpha})
    assert m.ok.all()
    np.testing.assert_allclose(m.points["P"], np.exp(1j * theta), atol=1e-12)
    f = lk.forces(m, gravity=G)
    # by hand: sum of moments about the hinge, T12 + M_spring + M_gravity = I_O alpha
    p = np.exp(1j * theta)
    length = np.abs(p - 2j)
    rate = ((p - 2j).conjugate() * (1j * omega * p)).real / length  # dL/dt
    tension = 40.0 * (length - 1.5) + 0.7 * rate
    force_on_p = -tension * (p - 2j) / length  # tension pulls P toward S
    m_spring = (p.conjugate() * force_on_p).imag
    m_gravity = ((0.5 * p).conjugate() * (-2.0 * G * 1j)).imag
    i_hinge = 0.3 + 2.0 * 0.5**2
    np.testing.assert_allclose(f.driver["lid"], i_hinge * alpha - m_spring - m_gravity, atol=1e-10)


def test_a_two_link_arm_with_a_shoulder_drive_and_an_elbow_motor():
    # upper O-E (1.0), fore E-H (0.8); shoulder angle a, elbow angle b (fore relative to upper)
    t = np.linspace(0.0, 2.0, 41)
    a, da, dda = 0.3 + 0.5 * np.sin(t), 0.5 * np.cos(t), -0.5 * np.sin(t)
    b, db, ddb = 1.0 - 0.4 * t**2, -0.8 * t, np.full(t.size, -0.8)
    arm = (
        Linkage({"O": 0, "E": 1 + 0j, "H": 1.8 + 0j})
        .ground("O")
        .link("upper", "O", "E", mass=3.0, inertia=0.25, cg=0.5)
        .link("fore", "E", "H", mass=1.5, inertia=0.08, cg=0.4)
        .motor("elbow", "E", links=("upper", "fore"))
        .drive("upper", "elbow")
    )
    m = arm.solve(
        {"upper": a, "elbow": b},
        velocity={"upper": da, "elbow": db},
        acceleration={"upper": dda, "elbow": ddb},
    )
    assert m.ok.all()
    e1, e2 = np.exp(1j * a), np.exp(1j * (a + b))
    w1, w2, al1, al2 = da, da + db, dda, dda + ddb
    np.testing.assert_allclose(m.points["H"], e1 + 0.8 * e2, atol=1e-12)
    v_h = 1j * w1 * e1 + 0.8j * w2 * e2
    np.testing.assert_allclose(m.point_velocity["H"], v_h, atol=1e-12)
    f = arm.forces(m, gravity=G)
    # power balance with the energies written here: T1 w1 + Tm (w2 - w1) + P_gravity = dKE/dt
    v_g1, a_g1 = 0.5j * w1 * e1, 0.5 * (1j * al1 - w1**2) * e1
    v_g2 = 1j * w1 * e1 + 0.4j * w2 * e2
    a_g2 = (1j * al1 - w1**2) * e1 + 0.4 * (1j * al2 - w2**2) * e2
    dke = (
        3.0 * (v_g1.conjugate() * a_g1).real
        + 0.25 * w1 * al1
        + 1.5 * (v_g2.conjugate() * a_g2).real
        + 0.08 * w2 * al2
    )
    p_gravity = -G * (3.0 * v_g1.imag + 1.5 * v_g2.imag)
    power = f.driver["upper"] * w1 + f.driver["elbow"] * db + p_gravity
    np.testing.assert_allclose(power, dke, atol=1e-9 * np.abs(dke).max())
    # and the elbow torque alone: moments about E of the forearm
    r_g2 = 0.4 * e2
    m_inertia = 0.08 * al2 + 1.5 * (r_g2.conjugate() * a_g2).imag
    m_weight = (r_g2.conjugate() * (-1.5 * G * 1j)).imag
    np.testing.assert_allclose(f.driver["elbow"], m_inertia - m_weight, atol=1e-10)


def test_a_driven_flap_hanging_on_a_four_bar_coupler():
    # the HW 6 four-bar with a flap pinned at B, its absolute angle driven as a second input
    fb = FourBar(8, 4, 7, 6)
    start = fb.solve(0.0)
    b = complex(start.B)
    lk = (
        Linkage({"O2": 0, "O4": 8 + 0j, "A": 4 + 0j, "B": b, "F": b + 2.0})
        .ground("O2", "O4")
        .link("crank", "O2", "A")
        .link("coupler", "A", "B")
        .link("rocker", "O4", "B")
        .link("flap", "B", "F")
        .drive("crank", "flap")
    )
    theta2 = np.linspace(0.0, 2 * np.pi, 73)
    flap = 0.2 * np.sin(theta2)
    m = lk.solve({"crank": theta2, "flap": flap}, velocity={"crank": 1.0, "flap": 0.0})
    closed = fb.solve(theta2, 1.0)
    assert m.ok.all()
    np.testing.assert_allclose(m.points["F"], closed.B + 2.0 * np.exp(1j * flap), atol=1e-9)
    np.testing.assert_allclose(
        m.point_velocity["F"], 1j * 6 * closed.omega4 * np.exp(1j * closed.theta4), atol=1e-9
    )


def test_a_hanging_link_must_be_driven_and_only_pins_may_hang():
    lid = Linkage({"O2": 0, "P": 1 + 0j}).ground("O2").link("lid", "O2", "P")
    with pytest.raises(ModelError, match="swings freely unless its angle is driven"):
        lid.solve({"lid": [0.1]})
    arm = (
        Linkage({"O": 0, "E": 1 + 0j, "H": 2 + 0j})
        .ground("O")
        .link("upper", "O", "E")
        .link("fore", "E", "H")
        .drive("upper")
    )
    with pytest.raises(ModelError, match="fore have fewer than two joints"):
        arm.solve({"upper": [0.1]})


def test_names_of_the_wrong_type_are_machdyn_errors():
    arm = (
        Linkage({"O": 0, "E": 1 + 0j, "H": 2 + 0j})
        .ground("O")
        .link("upper", "O", "E")
        .link("fore", "E", "H")
    )
    with pytest.raises(InputError, match="name the drivers by their names"):
        arm.drive(5)
    for links in (5, "AB", ("upper",), ("upper", 2)):
        with pytest.raises(InputError, match=r"elbow\.links: give two link names"):
            arm.motor("elbow", "E", links=links)
