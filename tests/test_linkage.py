"""Tests of machdyn.linkage: mechanisms as drawn, compiled into vector loops.

References that do not share the code path of Linkage:
* FourBar / SliderCrank closed forms (machdyn.fourbar, machdyn.slidercrank);
* the notes' worked examples (HW 6; second notes' loader example 1 and
  trebuchet example 2), compared to the printed precision;
* rigid-body invariants (every pair of points of one link keeps its drawn
  distance), central finite differences, circle intersections written here.
"""

from __future__ import annotations

import numpy as np
import pytest

from closed_forms import circle_meet
from machdyn.errors import AssemblyError, InputError, ModelError
from machdyn.fourbar import FourBar
from machdyn.linkage import Linkage
from machdyn.massprops import point_mass, rod
from machdyn.slidercrank import SliderCrank

# every test on the NumPy path and on the compiled kernels (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("backend")

TURN = np.radians(np.arange(0.0, 360.0, 1.0))


def fourbar_drawing(r1=8.0, r2=4.0, r3=7.0, r4=6.0, theta2=0.0, side=1.0, **links) -> Linkage:
    A = r2 * np.exp(1j * theta2)
    B = circle_meet(A, r3, r1 + 0j, r4, side)
    lk = Linkage({"O2": 0j, "O4": r1 + 0j, "A": A, "B": B, "P": A + 0.4 * (B - A) + 1.5j})
    lk.ground("O2", "O4")
    lk.link("2", "O2", "A", **links.get("2", {}))
    lk.link("3", "A", "B", "P", **links.get("3", {}))
    lk.link("4", "O4", "B", **links.get("4", {}))
    return lk.drive("2")


def rigid_errors(lk: Linkage, m) -> float:
    """Largest change of any point-to-point distance on any link (relative)."""
    worst = 0.0
    for name, link in lk._links.items():
        pts = link.points
        for i, p in enumerate(pts):
            for q in pts[i + 1 :]:
                d0 = abs(lk.position(q) - lk.position(p))
                d = np.abs(m.points[q] - m.points[p])
                worst = max(worst, float(np.nanmax(np.abs(d - d0))) / max(d0, 1.0))
        for p in pts:
            g0 = abs(lk.position(p) - _drawn_cg(lk, name))
            g = np.abs(m.cg[name] - m.points[p])
            worst = max(worst, float(np.nanmax(np.abs(g - g0))) / max(g0, 1.0))
    return worst


def _drawn_cg(lk: Linkage, name: str) -> complex:
    from machdyn.linkage.kinematics import _cg_drawn

    return _cg_drawn(lk, lk._links[name])


def finite_difference_check(lk: Linkage, theta: np.ndarray, omega: float, tol: float) -> None:
    """Velocities = d/dt of positions, accelerations = d/dt of velocities (central FD)."""
    m = lk.solve(theta, velocity=omega)
    h = theta[1] - theta[0]
    dt = h / omega
    inner = slice(1, -1)
    for name in m.theta:
        fd = (m.theta[name][2:] - m.theta[name][:-2]) / (2 * dt)
        scale = np.abs(m.omega[name]).max()
        assert np.abs(fd - m.omega[name][inner]).max() <= tol * scale, name
        fd = (m.omega[name][2:] - m.omega[name][:-2]) / (2 * dt)
        scale = np.abs(m.alpha[name]).max()
        assert np.abs(fd - m.alpha[name][inner]).max() <= tol * scale, name
    for name in m.points:
        fd = (m.points[name][2:] - m.points[name][:-2]) / (2 * dt)
        scale = max(np.abs(m.point_velocity[name]).max(), 1e-9)
        assert np.abs(fd - m.point_velocity[name][inner]).max() <= tol * scale, name
        fd = (m.point_velocity[name][2:] - m.point_velocity[name][:-2]) / (2 * dt)
        scale = max(np.abs(m.point_acceleration[name]).max(), 1e-9)
        assert np.abs(fd - m.point_acceleration[name][inner]).max() <= tol * scale, name


# ----------------------------------------------------------------------------- four-bar
def test_hw6_fourbar_matches_notes_and_fourbar():
    """HW 6 (notes), GCRR 8-4-7-6: theta3 = 58.81 deg at theta2 = 0; FourBar closed form."""
    lk = fourbar_drawing()
    m = lk.solve(TURN, velocity=10.0, acceleration=3.0)
    assert np.degrees(m.theta["3"][0]) == pytest.approx(58.81, abs=0.005)
    ref = FourBar(8, 4, 7, 6).solve(TURN, 10.0, 3.0, form=1)
    assert m.ok.all()
    wrap = np.angle(np.exp(1j * (m.theta["3"] - ref.theta3)))
    assert np.abs(wrap).max() < 1e-10
    assert np.abs(np.angle(np.exp(1j * (m.theta["4"] - ref.theta4)))).max() < 1e-10
    for ours, theirs in ((m.omega["3"], ref.omega3), (m.omega["4"], ref.omega4)):
        assert np.abs(ours - theirs).max() < 1e-9 * np.abs(theirs).max()
    for ours, theirs in ((m.alpha["3"], ref.alpha3), (m.alpha["4"], ref.alpha4)):
        assert np.abs(ours - theirs).max() < 1e-9 * np.abs(theirs).max()
    assert np.abs(m.points["B"] - ref.B).max() < 1e-10
    assert np.abs(m.points["A"] - ref.A).max() < 1e-12
    assert np.abs(m.omega["2"] - 10.0).max() == 0.0


def test_fourbar_form2_is_selected_by_the_drawing():
    """Drawn in the crossed circuit (B below the line A-O4): FourBar form 2."""
    lk = fourbar_drawing(theta2=np.radians(30), side=-1.0)
    m = lk.solve(TURN, velocity=1.0)
    ref = FourBar(8, 4, 7, 6).solve(TURN, 1.0, form=2)
    assert np.abs(np.angle(np.exp(1j * (m.theta["4"] - ref.theta4)))).max() < 1e-10
    assert np.abs(m.points["B"] - ref.B).max() < 1e-10


def test_fourbar_coupler_point_and_rigid_invariants():
    lk = fourbar_drawing(theta2=np.radians(75))
    m = lk.solve(TURN, velocity=2.0)
    assert rigid_errors(lk, m) < 1e-12
    # the coupler point P follows FourBar's coupler (p, delta) from A along AB
    A0, B0, P0 = lk.position("A"), lk.position("B"), lk.position("P")
    rel = (P0 - A0) / (B0 - A0) * abs(B0 - A0)
    fb = FourBar(8, 4, 7, 6, coupler=(abs(rel), float(np.angle(rel))))
    ref = fb.solve(TURN, 2.0)
    assert np.abs(m.points["P"] - ref.coupler).max() < 1e-10
    assert np.abs(m.point_velocity["P"] - ref.coupler_velocity).max() < 1e-9


def test_fourbar_drawn_pose_is_reproduced_at_the_drawn_input():
    lk = fourbar_drawing(theta2=np.radians(200))
    m = lk.solve(np.radians([200.0]))
    for p in ("A", "B", "P"):
        assert abs(m.points[p][0] - lk.position(p)) < 1e-12


def test_fourbar_independent_samples_and_scalar_input():
    lk = fourbar_drawing()
    m = lk.solve(np.radians(10.0), velocity=1.0)
    ref = FourBar(8, 4, 7, 6).solve(np.radians(10.0), 1.0)
    assert m.theta["4"].shape == ()
    assert float(m.omega["4"]) == pytest.approx(float(ref.omega4), rel=1e-10)
    grid = lk.solve(np.radians([[0.0, 20.0], [40.0, 60.0]]), continuation=False)
    assert grid.theta["3"].shape == (2, 2)
    assert grid.ok.all()


def test_mobility_and_loop_count():
    lk = fourbar_drawing()
    assert lk.mobility() == 1
    report = lk.loop_system().check()
    assert (len(report.variables), len(report.equations), report.dof) == (3, 2, 1)


# ----------------------------------------------------------------------------- slider-crank
def slider_crank_drawing(a=2.0, b=6.0, c=0.5, theta2=0.0, **links) -> Linkage:
    A = a * np.exp(1j * theta2)
    x = A.real + np.sqrt(b**2 - (c - A.imag) ** 2)
    lk = Linkage({"O2": 0j, "A": A, "B": complex(x, c)})
    lk.ground("O2")
    lk.link("crank", "O2", "A", **links.get("crank", {}))
    lk.link("rod", "A", "B", **links.get("rod", {}))
    lk.link("block", "B", **links.get("block", {}))
    return lk.slider("block", "ground", "B", 0.0, name="guide").drive("crank")


def test_slider_crank_matches_slidercrank():
    lk = slider_crank_drawing(theta2=np.radians(40))
    m = lk.solve(TURN, velocity=10.0, acceleration=-2.0)
    ref = SliderCrank(2.0, 6.0, 0.5).solve(TURN, 10.0, -2.0)
    assert m.ok.all()
    assert np.abs(m.lengths["guide"] - ref.d).max() < 1e-10
    assert np.abs(m.length_rate["guide"] - ref.d_dot).max() < 1e-9 * np.abs(ref.d_dot).max()
    acc = np.abs(ref.d_ddot).max()
    assert np.abs(m.length_acceleration["guide"] - ref.d_ddot).max() < 1e-9 * acc
    assert np.abs(np.angle(np.exp(1j * (m.theta["rod"] - ref.theta3 - np.pi)))).max() < 1e-10
    assert np.abs(m.points["B"] - ref.B).max() < 1e-10
    assert np.abs(m.omega["block"]).max() == 0.0


def test_slider_on_a_moving_link_inverted_slider_crank():
    """Crank O2-A; A is a block sliding on a rocker pivoted at O4 (inversion 3)."""
    A = 2.0 * np.exp(1j * np.radians(60))
    O4 = 5.0 + 0j
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "T": O4 + 1.5 * (A - O4) / abs(A - O4)})
    lk.ground("O2", "O4").link("crank", "O2", "A").link("block", "A")
    lk.link("rocker", "O4", "T").slider("block", "rocker", "A", "T", through="O4", name="s")
    lk.drive("crank")
    m = lk.solve(TURN, velocity=3.0)
    assert m.ok.all()
    # closed form: the rocker points from O4 to A; the slide runs from A toward T
    # (toward O4), so the displacement from O4 is -|A - O4|
    A_t = 2.0 * np.exp(1j * TURN)
    assert np.abs(np.exp(1j * m.theta["rocker"]) - (A_t - O4) / np.abs(A_t - O4)).max() < 1e-10
    assert np.abs(m.lengths["s"] + np.abs(A_t - O4)).max() < 1e-10
    assert np.abs(m.omega["block"] - m.omega["rocker"]).max() < 1e-12
    assert rigid_errors(lk, m) < 1e-12
    finite_difference_check(lk, np.radians(np.arange(0, 360, 0.05)), 3.0, 2e-5)


def test_scotch_yoke_with_a_slot():
    lk = Linkage({"O2": 0j, "A": 2.0 + 0j, "Y": 5.0 + 0j}).ground("O2")
    lk.link("crank", "O2", "A").link("yoke", "Y")
    lk.slider("yoke", "ground", "Y", 0.0, through="O2", name="guide")
    lk.slot("A", "crank", "yoke", np.pi / 2, name="slot").drive("crank")
    m = lk.solve(TURN, velocity=4.0)
    assert np.abs(m.points["Y"] - (3.0 + 2.0 * np.cos(TURN))).max() < 1e-10
    assert np.abs(m.point_velocity["Y"] + 8.0 * np.sin(TURN)).max() < 1e-9
    assert np.abs(m.point_acceleration["Y"] + 32.0 * np.cos(TURN)).max() < 1e-8
    assert np.abs(m.lengths["slot"] - 2.0 * np.sin(TURN)).max() < 1e-10


# ----------------------------------------------------------------------------- six-bars
def watt_ii(theta2=np.pi / 6, masses=False) -> Linkage:
    """Watt II: crank-rocker 8-2-7-6 (O2, A, B, O4); the ternary rocker (O4, B, C)
    drives the dyad C-D-O6 (link 5: C, D; link 6: O6, D)."""
    O4, O6 = 8.0 + 0j, 12.0 + 6.0j
    A = 2.0 * np.exp(1j * theta2)
    B = circle_meet(A, 7.0, O4, 6.0)
    C = O4 + 4.0 * (B - O4) / abs(B - O4) * np.exp(1j * np.radians(-35))
    D = circle_meet(C, 6.0, O6, 5.0, -1.0)
    pts = {"O2": 0j, "O4": O4, "O6": O6, "A": A, "B": B, "C": C, "D": D, "E": C + 2.0 + 1j}
    lk = Linkage(pts).ground("O2", "O4", "O6")
    props = {}
    if masses:
        props = {
            "2": {"mass": 1.0, "inertia": 0.4, "cg": 1.0 + 0.1j},
            "3": {"mass": 2.0, "inertia": 8.0, "cg": 3.5 + 0.3j},
            "4": {"body": rod(3.0, 6.0)},
            "5": {"mass": 1.5, "inertia": 4.5, "cg": "E"},
            "6": {"mass": 2.5, "inertia": 5.0, "cg": 2.5 - 0.2j},
        }
    lk.link("2", "O2", "A", **props.get("2", {})).link("3", "A", "B", **props.get("3", {}))
    lk.link("4", "O4", "B", "C", **props.get("4", {}))
    lk.link("5", "C", "D", "E", **props.get("5", {})).link("6", "O6", "D", **props.get("6", {}))
    return lk.drive("2")


def stephenson_iii(theta2=np.pi / 6) -> Linkage:
    """Stephenson III: four-bar 8-2-7-6 whose coupler point P drives the dyad P-D-O6."""
    O4, O6 = 8.0 + 0j, 4.0 - 6.0j
    A = 2.0 * np.exp(1j * theta2)
    B = circle_meet(A, 7.0, O4, 6.0)
    P = A + (B - A) / 7.0 * (3.0 - 2.0j)
    D = circle_meet(P, 7.5, O6, 6.0, -1.0)
    lk = Linkage({"O2": 0j, "O4": O4, "O6": O6, "A": A, "B": B, "P": P, "D": D})
    lk.ground("O2", "O4", "O6").link("2", "O2", "A").link("3", "A", "B", "P")
    lk.link("4", "O4", "B").link("5", "P", "D").link("6", "O6", "D")
    return lk.drive("2")


@pytest.mark.parametrize("build", [watt_ii, stephenson_iii])
def test_six_bars_closure_invariants_and_finite_differences(build):
    lk = build()
    assert lk.mobility() == 1
    report = lk.loop_system().check()
    # two loops (4 equations) + one constant-angle constraint; 6 angles, DOF 1
    assert (len(report.equations), len(report.variables), report.dof) == (5, 6, 1)
    m = lk.solve(TURN, velocity=5.0)
    assert m.ok.all()
    assert rigid_errors(lk, m) < 1e-11
    # the first four links are the FourBar 8-2-7-6 (form fixed by the drawing)
    ref = FourBar(8, 2, 7, 6).solve(TURN, 5.0, form=1)
    assert np.abs(m.points["B"] - ref.B).max() < 1e-10
    finite_difference_check(lk, np.radians(np.arange(0, 360, 0.05)), 5.0, 2e-5)


def test_six_bar_solution_independent_of_the_drawn_pose():
    """The same Watt II drawn at two crank angles gives the same motion (same circuit)."""
    a = watt_ii(np.radians(30)).solve(TURN, velocity=1.0)
    b = watt_ii(np.radians(250)).solve(TURN, velocity=1.0)
    for p in ("C", "D"):
        assert np.abs(a.points[p] - b.points[p]).max() < 1e-9
    assert np.abs(a.alpha["6"] - b.alpha["6"]).max() < 1e-8


def test_six_bar_ternary_link_gets_a_constant_angle_constraint():
    """Rocker 4 sits in both loops: two of its vectors, tied by one constraint."""
    report = watt_ii().loop_system().check()
    constraints = [e for e in report.equations if e.startswith("constraint")]
    assert len(constraints) == 1 and "theta_4" in constraints[0]


# ----------------------------------------------------------------------------- second notes
def loader(with_cylinder: bool) -> Linkage:
    """Second notes' loader: r2 = 141 at 45 deg, r3 = 120 at 0, r4 = 100 at -90 deg,
    r3p = 200 at 135 deg from A (examples 1 and 4); the cylinder runs from a ground
    pivot C to a point E of link 3 (example 4's r5)."""
    A = 141.0 * np.exp(1j * np.radians(45))
    B = A + 120.0
    pts = {"O2": 0j, "A": A, "B": B, "O4": B - 100j, "P": A + 200.0 * np.exp(1j * np.radians(135))}
    pts |= {"C": 290.0 - 10.0j, "E": A + 50.0 * np.exp(1j * np.radians(-20))}
    lk = Linkage(pts).ground("O2", "O4", "C")
    lk.link("arm", "O2", "A").link("3", "A", "B", "P", "E").link("4", "B", "O4")
    if with_cylinder:
        return lk.actuator("cylinder", "C", "E").drive("cylinder")
    return lk.drive("arm")


def test_loader_example_1_velocities():
    """Second notes, example 1: theta4' = .4985, theta3' = -.4154, Vp = (8.896, 108.6)."""
    m = loader(False).solve(np.radians(45.0), velocity=0.5)
    assert float(m.omega["4"]) == pytest.approx(0.4985, abs=5e-5)
    assert float(m.omega["3"]) == pytest.approx(-0.4154, abs=5e-5)
    vp = complex(m.point_velocity["P"])
    assert vp.real == pytest.approx(8.896, abs=5e-3)
    assert vp.imag == pytest.approx(108.6, abs=0.05)


def test_loader_example_4_cylinder_driver():
    """Example 4 (with the cylinder as a length driver): same velocity ratios as
    example 1 at the drawn pose; along a stroke, closure, FD and rigid invariants."""
    lk = loader(True)
    assert lk.mobility() == 1  # 6 links with the cylinder's two, 7 full joints
    L0 = abs(lk.position("E") - lk.position("C"))
    m = lk.solve(L0, velocity=10.0)
    w2 = float(m.omega["arm"])
    assert float(m.omega["4"]) / w2 == pytest.approx(0.4985 / 0.5, abs=1e-4)
    assert float(m.omega["3"]) / w2 == pytest.approx(-0.4154 / 0.5, abs=1e-4)
    stroke = np.linspace(L0 - 50.0, L0 + 60.0, 2201)
    ms = lk.solve(stroke, velocity=10.0)
    assert ms.ok.all()
    assert np.abs(ms.lengths["cylinder"] - stroke).max() < 1e-9
    assert np.abs(np.abs(ms.points["E"] - ms.points["C"]) - stroke).max() < 1e-9
    # Newton's tolerance is 1e-12 of the mean length (~150 here): 1.5e-10 absolute
    assert rigid_errors(lk, ms) < 1e-9
    dt = (stroke[1] - stroke[0]) / 10.0
    fd = (ms.points["P"][2:] - ms.points["P"][:-2]) / (2 * dt)
    assert np.abs(fd - ms.point_velocity["P"][1:-1]).max() < 1e-5 * np.abs(fd).max()


def trebuchet() -> Linkage:
    """Second notes, example 2: floating-arm trebuchet. The arm (W, H, P) has W on a
    vertical slider (r2 = 100 below O) and H on a horizontal track (r1 = 173.2 left
    of O); r3 = 200 at 150 deg, r3b = 300 further along the arm to P."""
    W, H = -100j, -173.2 + 0j
    e3 = (H - W) / abs(H - W)
    lk = Linkage({"O": 0j, "W": W, "H": H, "P": W + 500.0 * e3}).ground("O")
    lk.link("weight", "W").link("arm", "W", "H", "P").link("roller", "H")
    lk.slider("weight", "ground", "W", -np.pi / 2, through="O", name="r2")
    lk.slider("roller", "ground", "H", np.pi, through="O", name="r1")
    return lk.drive("r2")


def test_trebuchet_example_2_velocities():
    """r1' = -144.3, theta3' = -1.443; Vp printed (360.75, 374.84) with the rounded
    theta3' (exact (360.84, 375.00): compare within that rounding, 0.2 cm/s)."""
    lk = trebuchet()
    assert lk.mobility() == 1
    m = lk.solve(100.0, velocity=250.0)
    assert float(m.length_rate["r1"]) == pytest.approx(-144.3, abs=0.05)
    assert float(m.omega["arm"]) == pytest.approx(-1.443, abs=5e-4)
    vp = complex(m.point_velocity["P"])
    assert vp.real == pytest.approx(360.75, abs=0.2)
    assert vp.imag == pytest.approx(374.84, abs=0.2)
    # closed form: theta3' = -r2' / (r3 cos 30 deg)
    assert float(m.omega["arm"]) == pytest.approx(-250.0 / (200.0 * np.cos(np.pi / 6)), rel=1e-3)


# ----------------------------------------------------------------------------- forces
FB_MASS = {
    "2": {"mass": 1.0, "inertia": 0.1, "cg": 2.0 + 0.5j},
    "3": {"mass": 2.0, "inertia": 0.2, "cg": 3.5 - 1.0j},
    "4": {"mass": 3.0, "inertia": 0.3, "cg": 3.0 + 0.2j},
}


def test_fourbar_forces_equal_machdyn_dynamics():
    """Same four-bar, masses, gravity, loads: Linkage.forces = fourbar_forces to 1e-9."""
    from machdyn.dynamics import fourbar_forces

    lk = fourbar_drawing(theta2=np.radians(123), **FB_MASS)
    m = lk.solve(TURN, velocity=10.0, acceleration=2.0)
    load = 3.0 - 2.0j
    f = lk.forces(
        m, gravity=9.81, external_torques={"4": -5.0}, external_forces=[("3", 1.0 + 1.0j, load)]
    )
    fb = FourBar(8, 4, 7, 6)
    ref = fourbar_forces(
        fb,
        fb.solve(TURN, 10.0, 2.0),
        mass=(1.0, 2.0, 3.0),
        inertia=(0.1, 0.2, 0.3),
        cg=(2.0 + 0.5j, 3.5 - 1.0j, 3.0 + 0.2j),
        gravity=9.81,
        load_torque4=-5.0,
        external_forces=[(3, 1.0 + 1.0j, load)],
    )
    assert f.ok.all()
    pairs = (
        (f.driver["2"], ref.T12),
        (f.F("ground", "2"), ref.F12),
        (f.F("2", "3"), ref.F32 * -1 * -1),  # F23 on 3 from 2 = -F32
        (f.F("4", "3"), ref.F43),
        (f.F("ground", "4"), ref.F14),
        (f.shaking_force, ref.shaking_force),
        (f.shaking_moment, ref.shaking_moment),
    )
    for ours, theirs in pairs[:2] + pairs[3:]:
        assert np.abs(ours - theirs).max() <= 1e-9 * np.abs(theirs).max()
    assert np.abs(f.F("3", "2") - ref.F32).max() <= 1e-9 * np.abs(ref.F32).max()
    assert np.abs(f.F("2", "3") + ref.F32).max() <= 1e-9 * np.abs(ref.F32).max()


def test_slider_crank_forces_equal_machdyn_dynamics_with_viscous_friction():
    from machdyn.dynamics import slidercrank_forces

    links = {
        "crank": {"mass": 1.0, "inertia": 0.1, "cg": 1.0 + 0.2j},
        "rod": {"mass": 2.0, "inertia": 0.5, "cg": 3.0 - 0.1j},
        "block": {"body": point_mass(1.5)},
    }
    lk = slider_crank_drawing(theta2=np.radians(10), **links)
    m = lk.solve(TURN, velocity=10.0, acceleration=3.0)
    f = lk.forces(m, gravity=9.81, viscous={"guide": 0.7}, external_forces=[("block", "B", -50)])
    sc = SliderCrank(2.0, 6.0, 0.5)
    ref = slidercrank_forces(
        sc,
        sc.solve(TURN, 10.0, 3.0),
        mass=(1.0, 2.0, 1.5),
        inertia=(0.1, 0.5),
        cg=(1.0 + 0.2j, 3.0 - 0.1j),
        gravity=9.81,
        friction="viscous",
        beta=0.7,
        load_force4=-50.0,
    )
    for ours, theirs in (
        (f.driver["crank"], ref.T12),
        (f.sliders["guide"], ref.F14),
        (f.F("block", "rod"), ref.F43),
        (f.F("ground", "crank"), ref.F12),
        (f.shaking_force, ref.shaking_force),
        (f.shaking_moment, ref.shaking_moment),
    ):
        assert np.abs(ours - theirs).max() <= 1e-9 * np.abs(theirs).max()
    assert np.abs(f.couple["guide"]).max() < 1e-9  # forces concurrent at B, no rotation


def _watt_forces():
    lk = watt_ii(masses=True)
    theta = np.radians(np.arange(0.0, 360.0, 0.5))
    omega2 = 4.0 + 0.5 * np.cos(theta)  # a non-uniform input speed w2(theta2)
    alpha2 = -0.5 * np.sin(theta) * omega2  # = dw2/dt
    m = lk.solve(theta, velocity=omega2, acceleration=alpha2)
    loads = [("5", "E", 20.0 - 35.0j), ("3", 2.0 + 0.5j, -10.0 + 4.0j * np.cos(theta))]
    torques = {"6": -15.0 * np.sin(theta) - 7.0, "4": 3.0}
    f = lk.forces(m, gravity=9.81, external_forces=loads, external_torques=torques)
    return lk, m, f, loads, torques


def _load_point(lk, m, link, point):
    """World position/velocity of a load point given in the link frame (test's own)."""
    if isinstance(point, str):
        return m.points[point], m.point_velocity[point]
    pts = lk._links[link].points
    p0, p1 = lk.position(pts[0]), lk.position(pts[1])
    e0 = (p1 - p0) / abs(p1 - p0)
    rel = point * e0  # drawn offset from the first point
    th0 = np.angle(e0)
    r = rel * np.exp(1j * (m.theta[link] - th0))
    return m.points[pts[0]] + r, m.point_velocity[pts[0]] + 1j * m.omega[link] * r


def test_power_balance_over_a_cycle_of_a_watt_six_bar():
    """T w + sum P_ext = d(KE)/dt + d(PE)/dt at every sample (KE, PE computed here)."""
    lk, m, f, loads, torques = _watt_forces()
    assert f.ok.all()
    g = 9.81
    dke = np.zeros(len(m))
    dpe = np.zeros(len(m))
    ke = np.zeros(len(m))
    for name, link in lk._links.items():
        v, a = m.cg_velocity[name], m.cg_acceleration[name]
        w, al = m.omega[name], m.alpha[name]
        dke += link.mass * (v.real * a.real + v.imag * a.imag) + link.inertia * w * al
        ke += 0.5 * link.mass * np.abs(v) ** 2 + 0.5 * link.inertia * w**2
        dpe += link.mass * g * v.imag
    p_ext = f.driver["2"] * m.omega["2"]
    for link, point, force in loads:
        _, v = _load_point(lk, m, link, point)
        p_ext = p_ext + (np.real(force) * v.real + np.imag(force) * v.imag)
    for link, torque in torques.items():
        p_ext = p_ext + torque * m.omega[link]
    scale = np.abs(p_ext).max() + np.abs(dke).max()
    assert np.abs(p_ext - dke - dpe).max() <= 1e-8 * scale
    # and d(KE)/dt really is the time derivative of KE (FD along the sweep)
    w = m.omega["2"]
    t = np.cumsum(np.r_[0.0, np.diff(m.inputs["2"]) * 0.5 * (1 / w[1:] + 1 / w[:-1])])
    fd = np.gradient(ke, t)
    assert np.abs(fd[5:-5] - dke[5:-5]).max() <= 1e-3 * np.abs(dke).max()


def test_every_link_equation_holds_with_the_returned_forces():
    lk, m, f, loads, torques = _watt_forces()
    g = 9.81
    on_link = {n: [] for n in lk._links}  # (point position, force)
    carriers = {p: [n for n, ln in lk._links.items() if p in ln.points] for p in lk._points}
    for p in lk._ground:
        carriers[p].insert(0, "ground")
    for (a, b), force in f.pins.items():
        point = next(p for p, ls in carriers.items() if a in ls and b in ls)
        X = m.points[point]
        if b != "ground":
            on_link[b].append((X, force))
        if a != "ground":
            on_link[a].append((X, -force))
    for link, point, force in loads:
        X, _ = _load_point(lk, m, link, point)
        on_link[link].append((X, np.broadcast_to(force, X.shape)))
    for name, link in lk._links.items():
        G = m.cg[name]
        F = sum(fr for _, fr in on_link[name]) - 1j * link.mass * g
        M = sum(((X - G).real * fr.imag - (X - G).imag * fr.real) for X, fr in on_link[name])
        M = M + np.asarray(torques.get(name, 0.0)) + (f.driver["2"] if name == "2" else 0.0)
        ma = link.mass * m.cg_acceleration[name]
        ia = link.inertia * m.alpha[name]
        scale = np.abs(ma).max() + max(np.abs(fr).max() for _, fr in on_link[name])
        assert np.abs(F - ma).max() <= 1e-9 * scale, name
        assert np.abs(M - ia).max() <= 1e-9 * scale * 10, name


def test_shaking_force_is_the_reaction_of_the_moving_links():
    """Fs = sum(external + gravity) - sum(m aG) (Newton on all moving links together)."""
    lk, m, f, loads, _ = _watt_forces()
    total = -1j * 9.81 * sum(ln.mass for ln in lk._links.values())
    total = total + sum(np.broadcast_to(force, m.ok.shape) for _, _, force in loads)
    ma = sum(ln.mass * m.cg_acceleration[n] for n, ln in lk._links.items())
    assert np.abs(f.shaking_force - (total - ma)).max() <= 1e-9 * np.abs(ma).max()


def test_virtual_work_equals_newton_euler_driving_torque():
    """Massless Watt II: T w2 = -(sum F.v + sum T w) (virtual work, no force matrix)."""
    lk = watt_ii()
    theta = np.radians(np.arange(0.0, 360.0, 2.0))
    m = lk.solve(theta, velocity=1.0)
    f = lk.forces(m, external_forces=[("6", "D", 5.0 - 12.0j)], external_torques={"4": 8.0})
    vw = -(
        (5.0 * m.point_velocity["D"].real - 12.0 * m.point_velocity["D"].imag) + 8.0 * m.omega["4"]
    )
    assert np.abs(f.driver["2"] - vw).max() <= 1e-10 * np.abs(vw).max()


def test_loader_lifting_torque_second_notes_example_1():
    """Second notes (forces), example 1: torque at link 2 to lift 1000 kg at P, by
    conservation of power with the printed Vpy = 108.6 cm/s at theta2' = .5 rad/s."""
    lk = loader(False)
    m = lk.solve(np.radians(45.0), velocity=0.5)
    g = 981.0  # cm/s^2
    f = lk.forces(m, external_forces=[("3", "P", -1000.0 * g * 1j)])
    expected = 1000.0 * g * 108.6 / 0.5
    assert float(f.driver["arm"]) == pytest.approx(expected, rel=5e-4)


def test_loader_cylinder_force_by_virtual_work():
    lk = loader(True)
    L0 = abs(lk.position("E") - lk.position("C"))
    stroke = np.linspace(L0 - 40.0, L0 + 40.0, 81)
    m = lk.solve(stroke, velocity=10.0)
    weight = -1000.0 * 981.0j
    f = lk.forces(m, external_forces=[("3", "P", weight)])
    vp = m.point_velocity["P"]
    expected = -(weight.imag * vp.imag) / 10.0  # F L' + W.Vp = 0
    assert np.abs(f.driver["cylinder"] - expected).max() <= 1e-9 * np.abs(expected).max()


def test_trebuchet_force_at_P_second_notes():
    """Second notes: 100 kg on the vertical slider; the force at P normal to the bar
    that holds it, from the printed Vp = (360.75, 374.84): f = m g r2' / (n.Vp)."""
    lk = trebuchet()
    m = lk.solve(100.0, velocity=250.0)
    n = 1j * np.exp(1j * np.radians(150))
    weight = [("weight", "W", -100.0 * 981.0j)]
    d_w = float(lk.forces(m, external_forces=weight).driver["r2"])
    d_1 = float(lk.forces(m, external_forces=[("arm", "P", n)]).driver["r2"])
    f_p = -d_w / d_1  # driver force zero: the weight alone is balanced by f_p at P
    vp = 360.75 + 374.84j
    expected = -100.0 * 981.0 * 250.0 / (n.real * vp.real + n.imag * vp.imag)
    assert f_p == pytest.approx(expected, rel=1e-3)


# ----------------------------------------------------------------------------- bad input, flags
def test_mobility_not_matching_drivers_names_both():
    lk = fourbar_drawing()
    with pytest.raises(ModelError, match=r"mobility .* is 1 but 2 driver\(s\) .*2, 4"):
        lk.drive("2", "4").solve(0.0)
    with pytest.raises(ModelError, match="no driver"):
        fourbar_drawing().drive().solve(0.0)


def test_a_structure_is_refused():
    lk = Linkage({"O2": 0j, "O4": 4 + 0j, "A": 2 + 2j}).ground("O2", "O4")
    lk.link("a", "O2", "A").link("b", "A", "O4").drive("a")
    with pytest.raises(ModelError, match=r"mobility .* is 0 .* structure"):
        lk.solve(0.0)


def test_joints_naming_missing_links_or_points():
    lk = slider_crank_drawing()
    with pytest.raises(ModelError, match="unknown link 'nolink'"):
        lk.slider("block", "nolink", "B")
    with pytest.raises(ModelError, match="unknown link 'ghost'"):
        lk.slot("B", "ghost", "ground")
    with pytest.raises(ModelError, match="point 'Q' is not on link 'block'"):
        lk.slider("block", "ground", "Q")
    with pytest.raises(ModelError, match=r"driver 'ghost' is no link.*links: crank, rod, block"):
        lk.drive("ghost")
    with pytest.raises(ModelError, match=r"point\(s\) 'Z' without coordinates"):
        Linkage({"A": 0j}).link("x", "A", "Z")
    with pytest.raises(ModelError, match="not on link 'rod'"):
        Linkage({"C": 0j, "D": 1j}).ground("C").actuator("cyl", "C", "D", links=("ground", "rod"))


def test_a_link_with_fewer_than_two_joints():
    lk = fourbar_drawing()
    lk.point("F", 1 + 1j).link("flag", "A", "F")  # pinned at A only
    with pytest.raises(ModelError, match="flag have fewer than two joints"):
        lk.solve(0.0)
    with pytest.raises(ModelError, match="has no points"):
        Linkage().link("empty")


def test_a_link_of_zero_length_is_refused_by_name():
    lk = fourbar_drawing()
    lk.point("A", 0j)  # the crank drawn with A on O2: it would turn on the spot
    with pytest.raises(ModelError, match=r"link '2' has its pins O2, A drawn at one place"):
        lk.solve(0.0)
    # a coupler point (not a pin) on a pin is fine
    ok = fourbar_drawing()
    ok.point("P", ok.position("A"))
    assert ok.solve(0.0).ok.all()


def test_non_positive_mass_or_inertia():
    with pytest.raises(InputError, match=r"2\.mass: must be positive"):
        fourbar_drawing(**{"2": {"mass": 0.0, "inertia": 1.0}})
    with pytest.raises(InputError, match=r"3\.inertia: I_G must be positive"):
        fourbar_drawing(**{"3": {"mass": 1.0, "inertia": -1.0}})
    with pytest.raises(InputError, match="give both mass and inertia"):
        fourbar_drawing(**{"3": {"mass": 1.0}})
    with pytest.raises(InputError, match="MassProperties"):
        fourbar_drawing(**{"3": {"body": (1.0, 0j, 1.0)}})


def test_drawing_that_cannot_be_assembled():
    """A slide line given through a ground point that is not on it."""
    lk = Linkage({"O2": 0j, "A": 2 + 0j, "B": 8 + 0.5j}).ground("O2")
    lk.link("crank", "O2", "A").link("rod", "A", "B").link("block", "B")
    with pytest.raises(AssemblyError, match=r"misses the sliding point by 0\.5"):
        lk.slider("block", "ground", "B", 0.0, through="O2")
    with pytest.raises(InputError, match="point"):
        Linkage({"A": (1.0, "x")})


def test_unassemblable_inputs_and_toggles_are_flagged():
    """Triple rocker 4-3-3-2.5: assembles while cos(theta2) >= -0.21875 (loops docs);
    at that limit links 3 and 4 are collinear: kinematics and forces are singular."""
    O4 = 4.0 + 0j
    A = 3.0 * np.exp(1j * np.radians(60))
    B = circle_meet(A, 3.0, O4, 2.5)
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "B": B}).ground("O2", "O4")
    lk.link("2", "O2", "A", mass=1.0, inertia=1.0).link("3", "A", "B").link("4", "O4", "B")
    lk.drive("2")
    limit = np.arccos(-0.21875) - 1e-11  # just inside: Newton converges, rcond tiny
    theta = np.array([np.radians(60), limit, np.radians(150)])
    m = lk.solve(theta, velocity=1.0, continuation=False)
    assert m.ok.tolist() == [True, False, False]
    assert "singular" in m.reason[1] and "cannot assemble" in m.reason[2]
    f = lk.forces(m)
    assert f.ok.tolist() == [True, False, False]
    assert np.isnan(f.driver["2"][1:]).all() and np.isfinite(f.driver["2"][0])
    assert f.reason[1] != ""


def test_forces_need_velocities_and_known_links():
    lk = fourbar_drawing()
    with pytest.raises(ModelError, match="velocity"):
        lk.forces(lk.solve(TURN))
    m = lk.solve(TURN[:3], velocity=1.0)
    with pytest.raises(ModelError, match="unknown link 'x'"):
        lk.forces(m, external_torques={"x": 1.0})
    with pytest.raises(ModelError, match="not on link '2'"):
        lk.forces(m, external_forces=[("2", "B", 1.0)])
    with pytest.raises(InputError, match="gravity"):
        lk.forces(m, gravity=-9.81)
    with pytest.raises(ModelError, match="no such slider"):
        lk.forces(m, viscous={"guide": 1.0})


def test_tables():
    lk = slider_crank_drawing(block={"body": point_mass(1.0)})
    m = lk.solve(TURN[:5], velocity=1.0)
    df = m.to_pandas()
    assert {"crank", "theta_rod", "omega_rod", "d_guide", "B_x", "B_ay", "ok"} <= set(df.columns)
    f = lk.forces(m, gravity=9.81).to_pandas()
    assert {"F_ground_crank_x", "N_guide", "driver_crank", "shaking_moment"} <= set(f.columns)
    assert len(f) == 5
    with pytest.raises(KeyError, match="unknown link"):
        m.angle("nolink")


def test_slider_crank_coulomb_friction_equals_machdyn_dynamics():
    """Coulomb friction -mu|N| sign(v) at the guide: same as slidercrank_forces."""
    from machdyn.dynamics import slidercrank_forces

    links = {
        "crank": {"mass": 1.0, "inertia": 0.1, "cg": 1.0 + 0.2j},
        "rod": {"mass": 2.0, "inertia": 0.5, "cg": 3.0 - 0.1j},
        "block": {"body": point_mass(1.5)},
    }
    lk = slider_crank_drawing(theta2=np.radians(10), **links)
    theta = TURN + 0.25  # avoid the dead centres, where v_slip = 0 exactly
    m = lk.solve(theta, velocity=10.0)
    f = lk.forces(m, gravity=9.81, coulomb={"guide": 0.3}, external_forces=[("block", "B", -80)])
    sc = SliderCrank(2.0, 6.0, 0.5)
    ref = slidercrank_forces(
        sc,
        sc.solve(theta, 10.0),
        mass=(1.0, 2.0, 1.5),
        inertia=(0.1, 0.5),
        cg=(1.0 + 0.2j, 3.0 - 0.1j),
        gravity=9.81,
        friction="coulomb",
        mu=0.3,
        load_force4=-80.0,
    )
    assert f.ok.all() and ref.ok.all()
    for ours, theirs in (
        (f.driver["crank"], ref.T12),
        (f.sliders["guide"], ref.F14),
        (f.shaking_force, ref.shaking_force),
    ):
        assert np.abs(ours - theirs).max() <= 1e-9 * np.abs(theirs).max()
    # friction opposes the slip and has magnitude mu |N|
    friction = f.sliders["guide"].real
    v = m.length_rate["guide"]
    assert np.all(friction * v <= 0)
    assert np.abs(np.abs(friction) - 0.3 * np.abs(f.normal["guide"])).max() < 1e-9


def test_random_crank_rockers_against_fourbar_and_dynamics(rng):
    """Seeded random Grashof crank-rockers, drawn at a random crank angle in a random
    circuit: kinematics = FourBar (form from the drawing), forces = fourbar_forces."""
    from machdyn.dynamics import fourbar_forces

    theta = np.radians(np.arange(0.0, 360.0, 5.0))
    checked = 0
    while checked < 8:
        r1, r2, r3, r4 = rng.uniform(1.0, 10.0, 4)
        if not (r2 < min(r1, r3, r4) and r2 + max(r1, r3, r4) < r1 + r3 + r4 - max(r1, r3, r4)):
            continue
        side = rng.choice([-1.0, 1.0])
        cg = rng.normal(size=3) + 1j * rng.normal(size=3)
        mass, inertia = rng.uniform(0.5, 2.0, 3), rng.uniform(0.1, 1.0, 3)
        links = {
            k: {"mass": mass[i], "inertia": inertia[i], "cg": cg[i]}
            for i, k in enumerate(("2", "3", "4"))
        }
        lk = fourbar_drawing(r1, r2, r3, r4, rng.uniform(0, 2 * np.pi), side, **links)
        m = lk.solve(theta, velocity=3.0, acceleration=1.0)
        fb = FourBar(r1, r2, r3, r4)
        form = 1 if side > 0 else 2
        ref = fb.solve(theta, 3.0, 1.0, form=form)
        assert np.abs(m.points["B"] - ref.B).max() < 1e-9 * r1
        f = lk.forces(m, gravity=9.81)
        rf = fourbar_forces(fb, ref, mass=mass, inertia=inertia, cg=cg, gravity=9.81)
        assert np.abs(f.driver["2"] - rf.T12).max() <= 1e-9 * np.abs(rf.T12).max()
        assert np.abs(f.F("4", "3") - rf.F43).max() <= 1e-9 * np.abs(rf.F43).max()
        checked += 1


# ----------------------------------------------------------------------------- other drivers
def test_five_bar_with_two_cranks():
    """Two drivers (M = 2): C is the circle intersection of the two couplers (written
    here); massless, the two torques balance a load at C by virtual work."""
    O2, O5 = 0j, 6.0 + 0j
    A, D = 2.0 * np.exp(1j * np.radians(70)), O5 + 2.0 * np.exp(1j * np.radians(110))
    C = circle_meet(A, 5.0, D, 5.0)
    lk = Linkage({"O2": O2, "O5": O5, "A": A, "D": D, "C": C}).ground("O2", "O5")
    lk.link("2", "O2", "A").link("3", "A", "C").link("4", "D", "C").link("5", "O5", "D")
    lk.drive("2", "5")
    assert lk.mobility() == 2
    t2 = np.radians(np.linspace(70, 130, 61))
    t5 = np.radians(np.linspace(110, 60, 61))
    m = lk.solve({"2": t2, "5": t5}, velocity={"2": 1.0, "5": -2.0})
    A_t, D_t = 2.0 * np.exp(1j * t2), O5 + 2.0 * np.exp(1j * t5)
    assert np.abs(m.points["C"] - circle_meet(A_t, 5.0, D_t, 5.0)).max() < 1e-10
    load = -10.0 + 25.0j
    f = lk.forces(m, external_forces=[("3", "C", load)])
    vc = m.point_velocity["C"]
    power = f.driver["2"] * 1.0 + f.driver["5"] * -2.0 + load.real * vc.real + load.imag * vc.imag
    assert np.abs(power).max() < 1e-9 * np.abs(f.driver["2"]).max()
    with pytest.raises(ModelError, match="mapping"):
        lk.solve(t2)


def test_slider_as_the_driver():
    """Slider-crank driven at the piston (a linear motor): the crank follows, and the
    motor force balances a crank load torque by virtual work."""
    lk = slider_crank_drawing(theta2=np.radians(60)).drive("guide")
    B0 = lk.position("B").real
    d = np.linspace(B0 - 1.0, B0 + 0.5, 31)
    m = lk.solve(d, velocity=2.0)
    ref = SliderCrank(2.0, 6.0, 0.5)
    back = ref.solve(m.theta["crank"])
    assert np.abs(back.d - d).max() < 1e-10
    f = lk.forces(m, external_torques={"crank": 4.0})
    assert np.abs(f.driver["guide"] * 2.0 + 4.0 * m.omega["crank"]).max() < 1e-9


def test_single_sample_far_from_the_drawing_stays_on_the_drawn_circuit():
    """Drawn at theta2 = 0 in form 2; a lone sample at 200 deg is still form 2."""
    lk = fourbar_drawing(side=-1.0)
    m = lk.solve(np.radians(200.0), velocity=1.0)
    ref = FourBar(8, 4, 7, 6).solve(np.radians(200.0), 1.0, form=2)
    assert abs(complex(m.points["B"]) - complex(ref.B)) < 1e-10


def test_motion_plot():
    import matplotlib

    matplotlib.use("Agg")
    m = fourbar_drawing().solve(TURN[::10])
    ax = m.plot()
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [
        "theta 3 [deg]",
        "theta 4 [deg]",
    ]
    assert ax.get_xlabel() == "2 [deg]"


def test_no_link_gets_more_vectors_than_its_joints_minus_one():
    """The notes' rule: never three vectors of a ternary link (the redundant triangle).
    Every vector of a link starts at one hub joint, so a link with k joints has at
    most k - 1 vectors. Checked on a 9-link, 1-DOF chain with a ternary link T."""
    # ternary link T (A, B, C) on crank 2 at A; dyads from B and C to the ground,
    # and a binary link joining the two dyads' middle points (a loop B-..-C above T)
    O2, O4, O6 = 0j, 9.0 + 0j, 4.0 + 8.0j
    A = 2.0 * np.exp(1j * np.radians(40))
    B, C = A + 4.0 + 0.5j, A + 1.0 + 3.5j
    E = circle_meet(B, 4.0, O4, 4.5)
    F = circle_meet(C, 3.0, O6, 3.5, -1.0)
    pts = {"O2": O2, "O4": O4, "O6": O6, "A": A, "B": B, "C": C, "E": E, "F": F}
    pts |= {"E2": E + 0.8j, "F2": F + 0.7}
    lk = Linkage(pts).ground("O2", "O4", "O6")
    lk.link("2", "O2", "A").link("T", "A", "B", "C")
    lk.link("5", "B", "E", "E2").link("6", "O4", "E").link("7", "C", "F", "F2").link("8", "O6", "F")
    lk.link("9", "E2", "F2").drive("2")
    assert lk.mobility() == 1
    text = " ".join(lk.loop_system().check().equations).replace("+", " ").replace("-", " ")
    words = set(text.split())
    for name, link in lk._links.items():
        mine = {w for w in words if w.startswith(f"R_{name}_")}
        assert len(mine) <= len(link.points) - 1, (name, mine)
    assert len({w for w in words if w.startswith("R_T_")}) == 2
    m = lk.solve(np.radians(np.arange(40.0, 60.0, 0.5)), velocity=1.0)
    assert m.ok.all() and rigid_errors(lk, m) < 1e-11


def _energy_rates(lk, m, g):
    dke = np.zeros(m.ok.shape)
    dpe = np.zeros(m.ok.shape)
    for name, link in lk._links.items():
        v, a = m.cg_velocity[name], m.cg_acceleration[name]
        dke = dke + link.mass * (v.real * a.real + v.imag * a.imag)
        dke = dke + link.inertia * m.omega[name] * m.alpha[name]
        dpe = dpe + link.mass * g * v.imag
    return dke, dpe


def test_power_balance_slider_on_a_moving_link_with_friction():
    """Inverted slider-crank with masses, gravity, a load torque and viscous friction
    between block and rocker: T w2 + T4 w4 - beta v_slip^2 = d(KE + PE)/dt."""
    A = 2.0 * np.exp(1j * np.radians(60))
    O4 = 5.0 + 0j
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "T": O4 + 6.0 * (A - O4) / abs(A - O4)})
    lk.ground("O2", "O4").link("crank", "O2", "A", mass=1.0, inertia=0.3, cg=1.0 + 0.2j)
    lk.link("block", "A", mass=0.5, inertia=0.05, cg=0.1 + 0.1j)
    lk.link("rocker", "O4", "T", mass=2.0, inertia=6.0, cg=3.0)
    lk.slider("block", "rocker", "A", "T", through="O4", name="s").drive("crank")
    theta = np.radians(np.arange(0.0, 360.0, 2.0))
    m = lk.solve(theta, velocity=6.0)
    f = lk.forces(m, gravity=9.81, external_torques={"rocker": -20.0}, viscous={"s": 0.8})
    assert f.ok.all()
    dke, dpe = _energy_rates(lk, m, 9.81)
    v_slip = m.length_rate["s"]
    power = f.driver["crank"] * 6.0 - 20.0 * m.omega["rocker"] - 0.8 * v_slip**2
    assert np.abs(power - dke - dpe).max() <= 1e-9 * np.abs(dke).max()
    assert np.abs(f.couple["s"]).max() > 1.0  # the block's inertia torque goes through it


def test_power_balance_trebuchet_with_masses():
    """Trebuchet with a 100 kg counterweight, arm and roller masses (cm, g = 981):
    the slider's driving force times r2' balances the energy rates."""
    W, H = -100j, -173.2 + 0j
    e3 = (H - W) / abs(H - W)
    lk = Linkage({"O": 0j, "W": W, "H": H, "P": W + 500.0 * e3}).ground("O")
    lk.link("weight", "W", body=point_mass(100.0))
    lk.link("arm", "W", "H", "P", body=rod(20.0, 500.0))
    lk.link("roller", "H", body=point_mass(5.0))
    lk.slider("weight", "ground", "W", -np.pi / 2, through="O", name="r2")
    lk.slider("roller", "ground", "H", np.pi, through="O", name="r1")
    lk.drive("r2")
    d = np.linspace(60.0, 180.0, 121)
    m = lk.solve(d, velocity=250.0, acceleration=-300.0)
    f = lk.forces(m, gravity=981.0, external_forces=[("arm", "P", 2000.0 - 500.0j)])
    assert f.ok.all()
    dke, dpe = _energy_rates(lk, m, 981.0)
    vp = m.point_velocity["P"]
    power = f.driver["r2"] * 250.0 + 2000.0 * vp.real - 500.0 * vp.imag
    assert np.abs(power - dke - dpe).max() <= 1e-9 * np.abs(dke).max()


def test_forces_plot():
    import matplotlib

    matplotlib.use("Agg")
    lk = fourbar_drawing(**FB_MASS)
    ax = lk.forces(lk.solve(TURN[::10], velocity=1.0)).plot()
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["driver 2 (torque)"]


def test_pin_joining_three_links():
    """The mobility docs' example: a dyad 5-6 hung from the crank pin A, which joins
    links 2, 3 and 5 (counted as two joints). Kinematics by invariants and FD;
    forces with masses by the power balance."""
    O2, O4, O6 = 0j, 8.0 + 0j, -3.0 + 5.0j
    A = 2.0 * np.exp(1j * np.radians(50))
    B = circle_meet(A, 7.0, O4, 6.0)
    D = circle_meet(A, 5.0, O6, 4.0)
    lk = Linkage({"O2": O2, "O4": O4, "O6": O6, "A": A, "B": B, "D": D})
    lk.ground("O2", "O4", "O6").link("2", "O2", "A", mass=1.0, inertia=0.2, cg=1.0)
    lk.link("3", "A", "B", mass=2.0, inertia=8.0, cg=3.5).link("4", "O4", "B")
    lk.link("5", "A", "D", mass=1.5, inertia=3.0, cg=2.5 + 0.3j)
    lk.link("6", "O6", "D", mass=1.0, inertia=1.5, cg=2.0).drive("2")
    assert lk.mobility() == 1
    theta = np.radians(np.arange(0.0, 360.0, 0.1))
    m = lk.solve(theta, velocity=3.0)
    assert m.ok.all() and rigid_errors(lk, m) < 1e-11
    finite_difference_check(lk, theta, 3.0, 2e-5)
    f = lk.forces(m, gravity=9.81)
    assert set(f.pins) >= {("2", "3"), ("2", "5")}  # the triple pin as two pin forces
    dke, dpe = _energy_rates(lk, m, 9.81)
    assert np.abs(f.driver["2"] * 3.0 - dke - dpe).max() <= 1e-9 * np.abs(dke).max()


def test_a_drawing_at_a_toggle_is_refused_with_the_reason():
    # Four-bar 8-4-7-3 drawn at θ2 = 0: |A − O4| = 4 = 7 − 3, links 3 and 4 folded.
    from machdyn import ModelError

    lk = Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0), "B": (5, 0)})
    lk.ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
    lk.link("rocker", "O4", "B").drive("crank")
    with pytest.raises(ModelError, match="drawing is at a toggle"):
        lk.solve(np.array([0.1, 0.2]))
