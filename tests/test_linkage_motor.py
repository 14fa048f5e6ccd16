"""Tests of Linkage.motor: a rotary motor at a pin between two moving links.

The motor drives the relative angle ``phi = theta_b - theta_a`` of its two links
and its effort is the torque ``T`` on link b (``-T`` on link a). References that
do not share the code path of the motor:

* FourBar / SliderCrank closed forms (machdyn.fourbar, machdyn.slidercrank),
  solved at the crank angle that gives the relative angle, with the chain rule
  for the rates: ``phi' = omega3 - omega2`` so ``omega2 = phi' / (k3 - 1)``
  where ``k3 = omega3 / omega2`` is FourBar's velocity ratio;
* conservation of power ``T phi' + sum P_ext = d(KE)/dt + d(PE)/dt`` with KE and
  PE computed here from the kinematics;
* virtual work with FourBar's velocity ratios for a massless linkage;
* central finite differences of positions and velocities along a sweep;
* the same six-bar driven by its ground crank (round trip).
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

from closed_forms import circle_meet
from machdyn.errors import InputError, ModelError
from machdyn.fourbar import FourBar
from machdyn.linkage import Linkage
from machdyn.slidercrank import SliderCrank

# every test on the NumPy path and on the compiled kernels (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("backend")

matplotlib.use("Agg")

G = 9.81


def wrap(x):
    return np.angle(np.exp(1j * x))


def hw6(masses: bool = False) -> Linkage:
    """HW 6 (notes) GCRR 8-4-7-6 drawn at theta2 = 0, B above the ground (form 1)."""
    A, O4 = 4 + 0j, 8 + 0j
    B = circle_meet(A, 7.0, O4, 6.0)
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "B": B, "P": A + 0.4 * (B - A) + 1.5j})
    lk.ground("O2", "O4")
    kw = (
        [
            dict(mass=1.0, inertia=0.05, cg=2.0),
            dict(mass=2.5, inertia=0.4, cg="P"),
            dict(mass=1.8, inertia=0.3, cg=3.0),
        ]
        if masses
        else [{}, {}, {}]
    )
    lk.link("2", "O2", "A", **kw[0])
    lk.link("3", "A", "B", "P", **kw[1])
    lk.link("4", "O4", "B", **kw[2])
    return lk.motor("elbow", "A").drive("elbow")


# HW 6 over a crank turn; the crank-coupler pair turns fully (the crank is the
# shortest link of a Grashof chain), and phi = theta3 - theta2 falls monotonically
THETA2 = np.radians(np.arange(0.0, 360.0, 1.0))


def fourbar_reference(theta2=THETA2):
    return FourBar(8, 4, 7, 6).solve(theta2, 1.0, 0.0, form=1)


def fourbar_phi(ref) -> np.ndarray:
    return np.unwrap(ref.theta3) - ref.theta2


# ----------------------------------------------------------------------------- kinematics
def test_fourbar_driven_at_joint_A_matches_fourbar_and_the_chain_rule():
    """positions from FourBar at the theta2 where theta3 - theta2 = phi; rates by chain rule."""
    ref = fourbar_reference()
    phi = fourbar_phi(ref)
    assert np.all(np.diff(phi) < 0)  # the sweep is a sweep of phi
    k3, k4 = ref.omega3, ref.omega4  # d theta3 / d theta2, d theta4 / d theta2
    dk3, dk4 = ref.alpha3, ref.alpha4  # their derivatives in theta2 (omega2 = 1, alpha2 = 0)
    phi_dot, phi_ddot = 5.0, -3.0
    m = hw6().solve(phi, velocity=phi_dot, acceleration=phi_ddot)
    assert m.ok.all()
    assert np.abs(wrap(m.theta["2"] - ref.theta2)).max() < 1e-10
    assert np.abs(wrap(m.theta["3"] - ref.theta3)).max() < 1e-10
    assert np.abs(wrap(m.theta["4"] - ref.theta4)).max() < 1e-10
    assert np.abs(m.points["A"] - ref.A).max() < 1e-10
    assert np.abs(m.points["B"] - ref.B).max() < 1e-10
    # phi' = omega3 - omega2 = (k3 - 1) omega2
    w2 = phi_dot / (k3 - 1.0)
    # phi'' = alpha3 - alpha2 = dk3 w2^2 + (k3 - 1) alpha2
    a2 = (phi_ddot - dk3 * w2**2) / (k3 - 1.0)
    for ours, theirs in (
        (m.omega["2"], w2),
        (m.omega["3"], k3 * w2),
        (m.omega["4"], k4 * w2),
        (m.alpha["2"], a2),
        (m.alpha["3"], dk3 * w2**2 + k3 * a2),
        (m.alpha["4"], dk4 * w2**2 + k4 * a2),
    ):
        assert np.abs(ours - theirs).max() < 1e-9 * np.abs(theirs).max()
    assert np.abs(m.omega["3"] - m.omega["2"] - phi_dot).max() < 1e-12
    assert np.abs(m.alpha["3"] - m.alpha["2"] - phi_ddot).max() < 1e-10
    assert np.all(m.inputs["elbow"] == phi)


def test_random_crank_rockers_driven_at_joint_A(rng):
    """Seeded random Grashof crank-rockers drawn at a random crank angle in either
    circuit, driven by the crank-coupler angle over a turn: FourBar at the same poses."""
    checked = 0
    while checked < 8:
        r1, r2, r3, r4 = rng.uniform(1.0, 10.0, 4)
        longest = max(r1, r3, r4)
        if not (r2 < min(r1, r3, r4) and r2 + longest < r1 + r3 + r4 - longest):
            continue
        side = rng.choice([-1.0, 1.0])
        theta2 = rng.uniform(0, 2 * np.pi) + np.radians(np.arange(0.0, 360.0, 2.0))
        ref = FourBar(r1, r2, r3, r4).solve(theta2, 1.0, 0.0, form=1 if side > 0 else 2)
        if np.abs(ref.omega3 - 1.0).min() < 0.05:  # phi' = 0: B crosses the line O2-O4
            continue
        A = r2 * np.exp(1j * theta2[0])
        lk = (
            Linkage({"O2": 0j, "O4": r1 + 0j, "A": A, "B": circle_meet(A, r3, r1 + 0j, r4, side)})
            .ground("O2", "O4")
            .link("2", "O2", "A")
            .link("3", "A", "B")
            .link("4", "O4", "B")
            .motor("elbow", "A")
            .drive("elbow")
        )
        phi = np.unwrap(ref.theta3) - theta2
        m = lk.solve(phi, velocity=2.0)
        assert m.ok.all()
        assert np.abs(m.points["B"] - ref.B).max() < 1e-9 * r1
        w2 = 2.0 / (ref.omega3 - 1.0)
        assert np.abs(m.omega["4"] - ref.omega4 * w2).max() < 1e-9 * np.abs(ref.omega4 * w2).max()
        checked += 1


def test_drawn_pose_and_hw6_printed_angle():
    """HW 6: theta3 = 58.81 deg at theta2 = 0 (notes); the drawing is at phi = theta3, and
    the notes' rounded 58.81 deg gives theta2 = 0 to the same rounding."""
    lk = hw6()
    m = lk.solve(np.radians(58.81), velocity=1.0)
    assert abs(np.degrees(m.theta["2"])) < 0.005
    assert np.degrees(m.theta["3"] - m.theta["2"]) == pytest.approx(58.81, abs=1e-9)
    B = lk.position("B")
    m = lk.solve(np.angle(B - lk.position("A")))  # the drawn relative angle exactly
    assert abs(m.theta["2"]) < 1e-12
    assert abs(m.points["B"] - B) < 1e-12


def test_finite_differences_along_a_motor_sweep():
    """phi = phi0 + 4 t: central FD of points and angles equal the velocities, FD of those the
    accelerations (h = 1e-4 rad of phi)."""
    lk = hw6()
    phi_dot = 4.0
    h = 1e-4
    phi = np.radians(58.81) - np.arange(0.0, 2 * np.pi, h * 50)
    m0 = lk.solve(phi, velocity=phi_dot)
    mp = lk.solve(phi + h, velocity=phi_dot)
    mm = lk.solve(phi - h, velocity=phi_dot)
    dt = h / phi_dot
    assert m0.ok.all() and mp.ok.all() and mm.ok.all()
    for n in ("2", "3", "4"):
        fd = (mp.theta[n] - mm.theta[n]) / (2 * dt)
        assert np.abs(fd - m0.omega[n]).max() < 1e-6 * np.abs(m0.omega[n]).max()
        fd = (mp.omega[n] - mm.omega[n]) / (2 * dt)
        assert np.abs(fd - m0.alpha[n]).max() < 1e-5 * np.abs(m0.alpha[n]).max()
    for p in ("A", "B", "P"):
        fd = (mp.points[p] - mm.points[p]) / (2 * dt)
        assert np.abs(fd - m0.point_velocity[p]).max() < 1e-6 * np.abs(m0.point_velocity[p]).max()
        fd = (mp.point_velocity[p] - mm.point_velocity[p]) / (2 * dt)
        scale = np.abs(m0.point_acceleration[p]).max()
        assert np.abs(fd - m0.point_acceleration[p]).max() < 1e-5 * scale


def test_motor_on_a_slider_block_drives_the_rod_angle():
    """Slider-crank (crank 2, rod 6): a motor on the block (which does not turn) at its
    pin B drives theta3 itself; SliderCrank gives theta2 and the chain rule the rates."""
    sc = SliderCrank(2.0, 6.0)
    theta2 = np.radians(np.linspace(10.0, 80.0, 71))  # theta3 is monotonic here
    ref = sc.solve(theta2, 1.0, 0.0)
    lk = (
        Linkage({"O2": 0j, "A": 2 * np.exp(1j * theta2[0]), "B": ref.B[0]})
        .ground("O2")
        .link("crank", "O2", "A")
        .link("rod", "A", "B")
        .link("block", "B")
        .slider("block", "ground", "B", 0.0, name="guide")
        .motor("wrist", "B", links=("block", "rod"))
        .drive("wrist")
    )
    phi = np.unwrap(np.angle(ref.B - ref.A))  # the block's theta is 0: phi is the rod's angle
    assert np.all(np.diff(phi) < 0)
    m = lk.solve(phi, velocity=2.0)
    assert m.ok.all()
    assert np.abs(wrap(m.theta["crank"] - theta2)).max() < 1e-10
    assert np.abs(m.points["B"] - ref.B).max() < 1e-10
    w2 = 2.0 / ref.omega3  # omega3 = k3 omega2 with k3 from omega2 = 1
    assert np.abs(m.omega["crank"] - w2).max() < 1e-9 * np.abs(w2).max()
    assert np.abs(m.omega["rod"] - 2.0).max() < 1e-12


def first_run(mask: np.ndarray) -> slice:
    """The first run of consecutive True values of ``mask``."""
    start = int(np.argmax(mask))
    stop = start + int(np.argmax(~mask[start:])) if (~mask[start:]).any() else mask.size
    return slice(start, stop)


def sixbar(masses: bool = False, drive: str = "motor", links=("4", "5")) -> Linkage:
    """A six-bar with a pin B joining three links: four-bar O2-A-B-O4 (HW 6) and the
    dyad B-C-O6 (7, 6); the motor at B turns link 5 relative to the rocker 4. The knee
    angle phi = theta5 - theta4 falls from theta2 = 32 to 219.5 deg, rises elsewhere: a
    motor there can only swing the crank between those toggles (drawn in that range)."""
    A, O4, O6 = 4j, 8 + 0j, 14 + 2j  # drawn at theta2 = 90 deg
    B = circle_meet(A, 7.0, O4, 6.0)
    C = circle_meet(B, 7.0, O6, 6.0, side=-1.0)
    lk = Linkage({"O2": 0j, "O4": O4, "O6": O6, "A": A, "B": B, "C": C, "P": B + 1.0 + 1j})
    lk.ground("O2", "O4", "O6")
    mk = [
        dict(mass=1.0 + 0.3 * i, inertia=0.1 + 0.05 * i, cg=1.0 + 0.5j) if masses else {}
        for i in range(5)
    ]
    lk.link("2", "O2", "A", **mk[0]).link("3", "A", "B", **mk[1]).link("4", "O4", "B", **mk[2])
    lk.link("5", "B", "C", "P", **mk[3]).link("6", "O6", "C", **mk[4])
    lk.motor("knee", "B", links=links)
    return lk.drive("knee" if drive == "motor" else "2")


def test_pin_joining_three_links_round_trip_with_the_crank_driver():
    """Driven by the crank, the six-bar gives phi = theta5 - theta4; driving the motor with
    that phi gives back the crank angle and every point."""
    theta2 = np.radians(np.arange(0.0, 360.0, 2.0))
    by_crank = sixbar(drive="crank").solve(theta2, velocity=1.0)
    assert by_crank.ok.all()
    phi = by_crank.theta["5"] - by_crank.theta["4"]
    dphi = by_crank.omega["5"] - by_crank.omega["4"]  # per unit omega2
    stretch = first_run(dphi < -0.05)  # phi falls here: the drawn branch, away from toggles
    lk = sixbar()
    m = lk.solve(phi[stretch], velocity=dphi[stretch])
    assert m.ok.all() and len(m) > 60
    assert np.abs(wrap(m.theta["2"] - theta2[stretch])).max() < 1e-9
    for p in ("A", "B", "C", "P"):
        assert np.abs(m.points[p] - by_crank.points[p][stretch]).max() < 1e-9
    assert np.abs(m.omega["2"] - 1.0).max() < 1e-8  # phi' chosen as omega2 = 1 gives it


def test_five_bar_with_a_ground_crank_and_a_motor_between_moving_links():
    """Two drivers (theta2 and the elbow phi at A): A and C follow in closed form,
    C = A + 4 e^{j(theta2 + phi)}, and B is the intersection of two circles."""
    O5 = 7.0 + 0j

    def pose(theta2, phi):
        A = 3.0 * np.exp(1j * theta2)
        C = A + 4.0 * np.exp(1j * (theta2 + phi))
        return A, C, circle_meet(C, 4.0, O5, 3.5, side=-1.0)

    A0, C0, B0 = pose(np.radians(60.0), np.radians(-30.0))
    lk = (
        Linkage({"O2": 0j, "O5": O5, "A": A0, "C": C0, "B": B0})
        .ground("O2", "O5")
        .link("2", "O2", "A")
        .link("3", "A", "C")
        .link("4", "C", "B")
        .link("5", "O5", "B")
        .motor("elbow", "A")
        .drive("2", "elbow")
    )
    assert lk.mobility() == 2
    theta2 = np.radians(np.linspace(60.0, 100.0, 81))
    phi = np.radians(np.linspace(-30.0, -60.0, 81))
    m = lk.solve({"2": theta2, "elbow": phi}, velocity={"2": 2.0, "elbow": -1.5})
    assert m.ok.all()
    A, C, B = pose(theta2, phi)
    for name, ref in (("A", A), ("C", C), ("B", B)):
        assert np.abs(m.points[name] - ref).max() < 1e-10
    assert np.abs(m.omega["3"] - 0.5).max() < 1e-12  # omega2 + phi'
    # two-input finite differences of B: dB/dt = dB/dtheta2 * 2 + dB/dphi * (-1.5)
    h = 1e-6
    fd = (pose(theta2 + h, phi)[2] - pose(theta2 - h, phi)[2]) / (2 * h) * 2.0
    fd += (pose(theta2, phi + h)[2] - pose(theta2, phi - h)[2]) / (2 * h) * -1.5
    assert np.abs(m.point_velocity["B"] - fd).max() < 1e-6 * np.abs(fd).max()


def test_motor_between_two_moving_links_on_a_ground_pin():
    """Links 2 and 5 both pivot on the ground at O2 (a pin of three links); a motor there
    between 2 and 5 (not the ground) sets theta5 = theta2 + phi: B = 3 e^{j theta5} and C
    the intersection of circles about A and B."""

    def pose(theta2, phi):
        A, B = 2.0 * np.exp(1j * theta2), 3.0 * np.exp(1j * (theta2 + phi))
        return A, B, circle_meet(A, 4.0, B, 3.5)

    A0, B0, C0 = pose(0.3, 1.2)
    lk = (
        Linkage({"O2": 0j, "A": A0, "B": B0, "C": C0})
        .ground("O2")
        .link("2", "O2", "A")
        .link("3", "A", "C")
        .link("4", "C", "B")
        .link("5", "O2", "B")
        .motor("scissor", "O2", links=("2", "5"))
        .drive("2", "scissor")
    )
    theta2, phi = np.linspace(0.3, 2.0, 30), np.linspace(1.2, 0.9, 30)
    m = lk.solve({"2": theta2, "scissor": phi}, velocity={"2": 1.0, "scissor": 0.5})
    A, B, C = pose(theta2, phi)
    assert m.ok.all()
    for name, ref in (("A", A), ("B", B), ("C", C)):
        assert np.abs(m.points[name] - ref).max() < 1e-10
    assert np.abs(m.omega["5"] - 1.5).max() < 1e-12
    f = lk.forces(m, external_torques={"4": 2.0})
    # virtual work: T2 omega2 + T phi' + 2 omega4 = 0 for massless links
    assert np.abs(f.driver["2"] + 0.5 * f.driver["scissor"] + 2.0 * m.omega["4"]).max() < 1e-9


def test_the_order_of_the_links_sets_the_sign_of_phi_and_of_the_torque():
    """links=("3", "2") drives theta2 - theta3 = -phi: same motion, opposite torque."""
    lk_ab = hw6()
    lk_ba = hw6().motor("elbow2", "A", links=("3", "2")).drive("elbow2")
    phi = np.radians([50.0, 20.0, -40.0])
    m_ab = lk_ab.solve(phi, velocity=2.0, acceleration=1.0)
    m_ba = lk_ba.solve(-phi, velocity=-2.0, acceleration=-1.0)
    for n in ("2", "3", "4"):
        assert np.abs(m_ab.theta[n] - m_ba.theta[n]).max() < 1e-10
        assert np.abs(m_ab.alpha[n] - m_ba.alpha[n]).max() < 1e-9
    f_ab = lk_ab.forces(m_ab, external_torques={"4": 3.0})
    f_ba = lk_ba.forces(m_ba, external_torques={"4": 3.0})
    assert np.abs(f_ab.driver["elbow"] + f_ba.driver["elbow2"]).max() < 1e-9


# ----------------------------------------------------------------------------- forces
def kinetic_rates(lk, m):
    dke = np.zeros(len(m))
    dpe = np.zeros(len(m))
    for name, link in lk._links.items():
        v, a = m.cg_velocity[name], m.cg_acceleration[name]
        dke += link.mass * (v.real * a.real + v.imag * a.imag)
        dke += link.inertia * m.omega[name] * m.alpha[name]
        dpe += link.mass * G * v.imag
    return dke, dpe


def test_power_balance_fourbar_motor_at_a_moving_pin():
    """T phi' + T4 omega4 + F.V_P = d(KE)/dt + d(PE)/dt at every sample, with gravity, a
    torque on the rocker, a force at P and a non-uniform phi' (phi'' = d phi'/dt)."""
    lk = hw6(masses=True)
    phi = fourbar_phi(fourbar_reference())
    phi_dot = 4.0 + np.sin(phi)
    phi_ddot = np.cos(phi) * phi_dot
    m = lk.solve(phi, velocity=phi_dot, acceleration=phi_ddot)
    T4, F = -7.0, 3.0 - 2.0j
    f = lk.forces(m, gravity=G, external_torques={"4": T4}, external_forces=[("3", "P", F)])
    assert f.ok.all()
    dke, dpe = kinetic_rates(lk, m)
    vp = m.point_velocity["P"]
    p_ext = T4 * m.omega["4"] + F.real * vp.real + F.imag * vp.imag
    power = f.driver["elbow"] * phi_dot + p_ext
    scale = np.abs(f.driver["elbow"] * phi_dot).max() + np.abs(dke).max()
    assert np.abs(power - dke - dpe).max() <= 1e-8 * scale
    # the torque acts between two moving links: the ground sees no motor reaction, so
    # the shaking moment is the moment of the ground pins' reactions only
    moment = sum(
        (z.conjugate() * (-f.F("ground", n))).imag
        for z, n in ((m.points["O2"], "2"), (m.points["O4"], "4"))
    )
    assert np.abs(f.shaking_moment - moment).max() <= 1e-9 * np.abs(moment).max()


def test_power_balance_six_bar_motor_at_a_three_link_pin():
    lk = sixbar(masses=True)
    theta2 = np.radians(np.arange(0.0, 360.0, 2.0))
    by_crank = sixbar(drive="crank").solve(theta2, velocity=1.0)
    phi = (by_crank.theta["5"] - by_crank.theta["4"])[
        first_run(by_crank.omega["5"] - by_crank.omega["4"] < -0.05)
    ]
    m = lk.solve(phi, velocity=1.5, acceleration=-0.7)
    f = lk.forces(m, gravity=G, external_torques={"6": 2.0})
    assert m.ok.all() and f.ok.all()
    dke, dpe = kinetic_rates(lk, m)
    power = f.driver["knee"] * 1.5 + 2.0 * m.omega["6"]
    scale = np.abs(f.driver["knee"] * 1.5).max() + np.abs(dke).max()
    assert np.abs(power - dke - dpe).max() <= 1e-8 * scale


def test_massless_fourbar_motor_torque_by_virtual_work_with_fourbar_ratios():
    """T phi' + T4 omega4 = 0 with omega4 / phi' = k4 / (k3 - 1) from FourBar."""
    ref = fourbar_reference()
    lk = hw6()
    m = lk.solve(fourbar_phi(ref), velocity=1.0)
    f = lk.forces(m, external_torques={"4": 10.0})
    expected = -10.0 * ref.omega4 / (ref.omega3 - 1.0)
    assert np.abs(f.driver["elbow"] - expected).max() < 1e-9 * np.abs(expected).max()


def test_motor_torque_acts_on_b_and_its_reaction_on_a():
    """Statics of each link with the returned forces: the crank (a) carries -T, the
    coupler (b) +T (massless links, a torque on the coupler only)."""
    lk = hw6()
    m = lk.solve(np.radians([40.0, 10.0, -60.0]), velocity=1.0)
    f = lk.forces(m, external_torques={"3": 5.0})
    T = f.driver["elbow"]
    O2, A, B = m.points["O2"], m.points["A"], m.points["B"]

    def moment(X, F, about):
        return ((X - about).conjugate() * F).imag

    # crank about O2: pin A force from the coupler, and -T
    crank = moment(A, f.F("3", "2"), O2) - T
    # coupler about A: pin B force from the rocker, +T and the load 5
    coupler = moment(B, f.F("4", "3"), A) + T + 5.0
    assert np.abs(crank).max() < 1e-9 and np.abs(coupler).max() < 1e-9
    # the rocker is a two-force member, the crank's ground force balances pin A
    assert np.abs(f.F("ground", "2") + f.F("3", "2")).max() < 1e-9


# ----------------------------------------------------------------------------- misc.
def test_undriven_motor_is_a_free_pin():
    lk = hw6(masses=True).drive("2")
    m = lk.solve(THETA2[:30], velocity=3.0)
    ref = fourbar_reference(THETA2[:30])
    assert np.abs(wrap(m.theta["3"] - ref.theta3)).max() < 1e-10
    f = lk.forces(m, gravity=G)
    assert set(f.driver) == {"2"}


def test_tables_and_plots_label_the_motor_as_an_angle_and_a_torque():
    lk = hw6()
    m = lk.solve(np.radians([50.0, 40.0]), velocity=1.0)
    f = lk.forces(m, external_torques={"4": 1.0})
    assert "driver_elbow" in f.to_pandas().columns
    assert list(m.to_pandas()["elbow"]) == list(np.radians([50.0, 40.0]))
    assert m.plot().get_xlabel() == "elbow [deg]"
    ax = f.plot()
    assert ax.get_xlabel() == "elbow [deg]"
    assert ax.get_legend_handles_labels()[1] == ["driver elbow (torque)"]


# ----------------------------------------------------------------------------- bad input
def base() -> Linkage:
    A, O4 = 4 + 0j, 8 + 0j
    B = circle_meet(A, 7.0, O4, 6.0)
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "B": B, "P": A + 1j, "Q": 99j})
    return lk.ground("O2", "O4").link("2", "O2", "A").link("3", "A", "B", "P").link("4", "O4", "B")


def test_a_motor_on_a_ground_pin_is_an_ordinary_link_driver():
    lk = base().motor("m", "O2").drive("m")
    with pytest.raises(ModelError, match=r"joins the ground.*ordinary link driver.*drive\('2'\)"):
        lk.solve(0.1)
    with pytest.raises(ModelError, match=r"drive\('4'\)"):  # refused at once when named
        base().motor("m", "O4", links=("ground", "4"))


def test_a_pin_of_three_links_asks_which_two():
    lk = sixbar(links=None)
    with pytest.raises(ModelError, match=r"pin 'B' joins 3 links \(3, 4, 5\).*links="):
        lk.solve(0.1)


def test_bad_motor_names_points_and_links():
    with pytest.raises(ModelError, match="unknown link 'x'"):
        base().motor("m", "A", links=("2", "x"))
    with pytest.raises(ModelError, match="without coordinates"):
        base().motor("m", "Z")
    with pytest.raises(ModelError, match="to itself"):
        base().motor("m", "A", links=("2", "2"))
    with pytest.raises(InputError, match="two link names"):
        base().motor("m", "A", links=("2",))
    with pytest.raises(InputError, match="non-empty"):
        base().motor("", "A")
    with pytest.raises(ModelError, match="link's"):
        base().motor("3", "A")
    with pytest.raises(ModelError, match="used twice"):
        base().motor("m", "A").motor("m", "B")
    with pytest.raises(ModelError, match=r"no link, slider, slot, actuator or motor.*motor"):
        base().drive("pin A")
    # a point of one link only, a point on no link, a pin of other links
    for at, links, what in (
        ("P", None, "no pin"),
        ("Q", None, "no pin"),
        ("B", ("2", "3"), "not on link '2'"),
    ):
        lk = base().motor("m", at, links=links).drive("m")
        with pytest.raises(ModelError, match=what):
            lk.solve(0.1)


def test_motor_values_must_be_finite():
    with pytest.raises(InputError, match="velocity"):
        hw6().solve([0.5, 0.6], velocity=[1.0, np.nan])
