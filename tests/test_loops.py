"""Tests of the general vector-loop solver against references that do not share its code.

References: law-of-cosines closed forms written here, circle intersections, the
cycloid, finite differences of positions, loop closure, and the printed numbers
of the course notes (000_*: HW 6 and the 6-link position example; 003_*: the
loader and trebuchet velocity examples).
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import FourBar, jit
from machdyn.errors import InputError, ModelError, UnknownNameError
from machdyn.loops import LoopSystem, lu_factor, lu_solve
from machdyn.loops.solve import REASONS, SINGULAR

# Every test runs on the NumPy path and again on the compiled kernels.
pytestmark = pytest.mark.usefixtures("backend")


@pytest.fixture
def numpy_path():
    """For the tests that look inside the NumPy continuation: the compiled kernels off."""
    previous = jit.mode()
    jit.set_mode("off")
    yield
    jit.set_mode(previous)


# ----------------------------------------------------------------------------- helpers
def fourbar_system(r1: float, r2: float, r3: float, r4: float) -> LoopSystem:
    return (
        LoopSystem()
        .vector("R1", r1, 0.0)
        .vector("R2", r2, "theta2")
        .vector("R3", r3, "theta3")
        .vector("R4", r4, "theta4")
        .loop("R2 + R3 - R4 - R1")
        .point("B", "R2 + R3")
        .inputs("theta2")
    )


def fourbar_closed_form(r1, r2, r3, r4, theta2, form=1):
    """Law of cosines on the diagonal A-O4 (independent of the solver).

    Form 1: the open configuration, phi12 = theta4 - theta3 wrapped to (-pi, pi] > 0.
    Returns theta3, theta4 (NaN where the linkage cannot be assembled).
    """
    a = r2 * np.exp(1j * np.asarray(theta2, dtype=float))
    s = r1 - a  # from A to O4
    diag = np.abs(s)
    cos_beta = (r3**2 + diag**2 - r4**2) / (2 * r3 * diag)
    with np.errstate(invalid="ignore"):
        beta = np.arccos(cos_beta)
    out = []
    for sign in (1.0, -1.0):
        t3 = np.angle(s) + sign * beta
        b = a + r3 * np.exp(1j * t3)
        t4 = np.angle(b - r1)
        out.append((t3, t4))
    (t3a, t4a), (t3b, t4b) = out
    phi_a = np.angle(np.exp(1j * (t4a - t3a)))
    pick_a = (phi_a > 0) if form == 1 else (phi_a < 0)
    return np.where(pick_a, t3a, t3b), np.where(pick_a, t4a, t4b)


def five_point(y, h):
    """Five-point central difference (error h^4/30 y^(5)) for samples 2..n-3."""
    return (-y[4:] + 8 * y[3:-1] - 8 * y[1:-3] + y[:-4]) / (12 * h)


def wrap(angle):
    return np.angle(np.exp(1j * np.asarray(angle)))


def central(y, h, axis=-1):
    """Central difference of samples 0 and 2 along the last axis of length 3."""
    return (np.take(y, 2, axis) - np.take(y, 0, axis)) / (2 * h)


# ----------------------------------------------------------------------------- the notes
def test_hw6_gcrr_8_4_7_6_newton_raphson_matches_law_of_cosines():
    """HW 6 (notes): GCRR R1=8, R2=4, R3=7, R4=6, theta2 = 0..90 deg step 15 deg, form 1."""
    theta2 = np.radians(np.arange(0, 91, 15))
    m = fourbar_system(8, 4, 7, 6).solve({"theta2": theta2}, guess={"theta3": 0.5, "theta4": 1.5})
    t3, t4 = fourbar_closed_form(8, 4, 7, 6, theta2, form=1)
    assert m.ok.all()
    np.testing.assert_allclose(wrap(m["theta3"] - t3), 0, atol=1e-10)
    np.testing.assert_allclose(wrap(m["theta4"] - t4), 0, atol=1e-10)
    # The printed first row of the HW 6 table: theta2 = 0 -> theta3 = 58.81 deg.
    assert np.degrees(m["theta3"][0]) == pytest.approx(58.81, abs=0.005)


def six_link_notes(reduced: bool) -> LoopSystem:
    """The notes' 6-link position-analysis example (three loops, d3 and d6 variable)."""
    s = LoopSystem()
    s.vector("R1", 10.0, 0.0).vector("R2", 3.0, "theta2")
    s.vector("R5", 4.0, 0.0).vector("R6", "d6", np.pi / 2)
    s.vector("R7", 2.0, "theta7").vector("R8", 5.0, "theta8")
    s.vector("R9", 3.0, "theta9").vector("R10", 4.0, "theta10").vector("R11", 6.0, 0.3)
    if reduced:  # the notes' second form: d3 + d4 = dbar and theta3 = theta4 substituted
        s.vector("R3", "d3", "theta3").vector("R34", 9.0, "theta3")
        s.loop("R2 + R34 - R5 - R6")
    else:
        s.vector("R3", "d3", "theta3").vector("R4", "d4", "theta4")
        s.loop("R2 + R3 + R4 - R5 - R6")
        s.constraint("theta3 = theta4").constraint("d3 + d4 = dbar", dbar=9.0)
    s.loop("R2 + R3 + R7 - R8 - R1 = 0")
    s.loop("R8 + R9 - R10 - R11")
    s.constraint("theta9 - theta7 = gamma", gamma=0.4)
    return s


def test_notes_six_link_example_counts_8_variables_7_equations_dof_1():
    """Notes, position analysis example: 'VARIABLES: d3, d6, theta2, theta3, theta7..10'."""
    report = six_link_notes(reduced=True).check()
    assert sorted(report.variables) == sorted(
        ["d3", "d6", "theta2", "theta3", "theta7", "theta8", "theta9", "theta10"]
    )
    assert len(report.equations) == 7
    assert report.dof == 1
    assert "8 variables, 7 equations: DOF 1" in str(report)
    full = six_link_notes(reduced=False).check()
    assert (len(full.variables), len(full.equations), full.dof) == (10, 9, 1)


def test_notes_six_link_wrong_inputs_message():
    with pytest.raises(
        ModelError,
        match=r"8 variables, 7 equations: DOF 1, but 2 inputs were "
        r"named: theta2, d6",
    ):
        six_link_notes(reduced=True).check(inputs=("theta2", "d6"))


def test_loader_example_1_velocities():
    """Second notes, example 1 (Bobcat loader): theta4' = .4985, theta3' = -.4154, Vp."""
    s = (
        LoopSystem()
        .vector("r1", 161.0, np.pi)
        .vector("r2", 141.0, "theta2")
        .vector("r3", 120.0, "theta3")
        .vector("r4", 100.0, "theta4")
        .vector("r3p", 200.0, "theta3p")
        .loop("r1 + r2 + r3 + r4 = 0")
        .constraint("theta3p = theta3 + alpha3p", alpha3p=np.radians(135))
        .point("P = r2 + r3p")
        .inputs("theta2")
    )
    config = {
        "theta2": np.radians(45),
        "theta3": 0.0,
        "theta4": np.radians(-90),
        "theta3p": np.radians(135),
    }
    m = s.evaluate(config, velocity={"theta2": 0.5})
    assert float(m.velocity["theta4"]) == pytest.approx(0.4985, abs=5e-5)
    assert float(m.velocity["theta3"]) == pytest.approx(-0.4154, abs=5e-5)
    assert float(m.velocity["theta3p"]) == pytest.approx(-0.4154, abs=5e-5)
    vp = complex(m.point_velocity["P"])
    assert vp.real == pytest.approx(8.896, abs=5e-3)
    assert vp.imag == pytest.approx(108.6, abs=0.05)


def test_trebuchet_example_2_velocities():
    """Second notes, example 2 (floating-arm trebuchet): r1' = -144.3, theta3' = -1.443.

    The notes print Vp = (360.75, 374.84), computed with theta3' rounded to -1.443;
    with the unrounded -1.44338 the exact values are (360.84, 375.00). We compare to
    the printed numbers within the effect of that rounding (0.2 cm/s).
    """
    s = (
        LoopSystem()
        .vector("r1", "d1", np.pi)
        .vector("r2", "d2", -np.pi / 2)
        .vector("r3", 200.0, "theta3")
        .vector("r3b", 300.0, "theta3b")
        .loop("-r1 + r2 + r3")
        .constraint("theta3b = theta3 + alpha3", alpha3=0.0)
        .point("P", "r2 + r3 + r3b")
        .inputs("d2")
    )
    config = {"d1": 173.2, "d2": 100.0, "theta3": np.radians(150), "theta3b": np.radians(150)}
    m = s.evaluate(config, velocity={"d2": 250.0})
    assert float(m.velocity["d1"]) == pytest.approx(-144.3, abs=0.05)
    assert float(m.velocity["theta3"]) == pytest.approx(-1.443, abs=5e-4)
    assert float(m.velocity["theta3b"]) == pytest.approx(-1.443, abs=5e-4)
    vp = complex(m.point_velocity["P"])
    assert vp.real == pytest.approx(360.75, abs=0.2)
    assert vp.imag == pytest.approx(374.84, abs=0.2)
    # exact closed form of this configuration: theta3' = -250 / (200 cos 30 deg)
    assert float(m.velocity["theta3"]) == pytest.approx(-250 / (200 * np.cos(np.pi / 6)))


# ----------------------------------------------------------------------------- six-bar
def watt_six_bar_with_slider(constraint: bool = True) -> LoopSystem:
    """Watt II: crank-rocker 8-2-7-6, the rocker drives a slider (link 6) on y = 8."""
    s = (
        LoopSystem()
        .vector("R1", 8.0, 0.0)
        .vector("R2", 2.0, "theta2")
        .vector("R3", 7.0, "theta3")
        .vector("R4", 6.0, "theta4")
        .vector("R5", 7.0, "theta5")
        .vector("R6", "d6", 0.0)
        .vector("R7", 8.0, np.pi / 2)
        .loop("R2 + R3 - R4 - R1")
        .point("B", "R2 + R3")
        .point("D", "R7 + R6")
        .inputs("theta2")
    )
    if constraint:
        s.vector("R4c", 6.5, "theta4c").constraint("theta4c = theta4 + beta", beta=0.3)
        s.loop("R1 + R4c + R5 - R6 - R7")
        s.point("C", "R1 + R4c")
    else:
        s.vector("R4c", 6.5, "theta4").loop("R1 + R4c + R5 - R6 - R7")
    return s


def test_six_bar_with_slider_full_turn_closure_and_finite_differences():
    s = watt_six_bar_with_slider()
    h = 2e-3
    base = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    theta2 = (base[:, None] + h * np.array([-1.0, 0.0, 1.0])).ravel()
    omega2 = 3.0
    m = s.solve(
        {"theta2": theta2},
        guess={"theta3": 1.2, "theta4": 1.9, "theta4c": 2.2, "theta5": 0.4, "d6": 10.0},
        velocity={"theta2": omega2},
    )
    assert m.ok.all()

    # Loop closure, evaluated here from the solved variables.
    def e(length, angle):
        return length * np.exp(1j * angle)

    loop1 = e(2, m["theta2"]) + e(7, m["theta3"]) - e(6, m["theta4"]) - 8
    loop2 = 8 + e(6.5, m["theta4c"]) + e(7, m["theta5"]) - m["d6"] - 8j
    assert np.abs(loop1).max() < 1e-10 * 6
    assert np.abs(loop2).max() < 1e-10 * 6
    np.testing.assert_allclose(m["theta4c"] - m["theta4"], 0.3, atol=1e-12)
    # No branch jump: continuous, one branch sign, slider on its side.
    assert len(set(m.branch.tolist())) == 1
    assert np.abs(np.diff(m["theta5"])).max() < 0.1
    # Finite differences at constant speed: v = w dq/dtheta2, a = w dv/dtheta2, ...
    names = ["theta3", "theta4", "theta5", "d6"]
    for name in names:
        pos = m[name].reshape(-1, 3)
        vel = m.velocity[name].reshape(-1, 3)
        acc = m.acceleration[name].reshape(-1, 3)
        jerk = m.jerk[name].reshape(-1, 3)
        scale_v = np.abs(vel).max()
        np.testing.assert_allclose(central(pos, h) * omega2, vel[:, 1], atol=1e-5 * scale_v)
        np.testing.assert_allclose(
            central(vel, h) * omega2, acc[:, 1], atol=1e-5 * np.abs(acc).max()
        )
        np.testing.assert_allclose(
            central(acc, h) * omega2, jerk[:, 1], atol=1e-5 * np.abs(jerk).max()
        )
    # Points: position from the chain, velocity = FD of position.
    d_pt = m.points["D"].reshape(-1, 3)
    np.testing.assert_allclose(d_pt.real, m["d6"].reshape(-1, 3))
    np.testing.assert_allclose(d_pt.imag, 8.0)
    c_pt = m.points["C"].reshape(-1, 3)
    vc = m.point_velocity["C"].reshape(-1, 3)
    np.testing.assert_allclose(central(c_pt, h) * omega2, vc[:, 1], atol=1e-5 * np.abs(vc).max())


def test_six_bar_general_input_rates_match_chain_rule():
    """With alpha2 and jerk2 non-zero: xdot = x' w, xddot = x'' w^2 + x' a, ... (FD in theta2)."""
    s = watt_six_bar_with_slider(constraint=False)
    h = 2e-3
    base = np.linspace(0.1, 6.0, 12)
    theta2 = (base[:, None] + h * np.arange(-2.0, 3.0)).ravel()
    w, a, j = 2.0, -3.0, 5.0
    m = s.solve(
        {"theta2": theta2},
        guess={"theta3": 1.2, "theta4": 1.9, "theta5": 0.4, "d6": 10.0},
        velocity={"theta2": w},
        acceleration={"theta2": a},
        jerk={"theta2": j},
    )
    assert m.ok.all()
    for name in ["theta3", "theta4", "theta5", "d6"]:
        q = m[name].reshape(-1, 5)
        d1 = (q[:, 3] - q[:, 1]) / (2 * h)
        d2 = (q[:, 3] - 2 * q[:, 2] + q[:, 1]) / h**2
        d3 = (q[:, 4] - 2 * q[:, 3] + 2 * q[:, 1] - q[:, 0]) / (2 * h**3)
        vel = m.velocity[name].reshape(-1, 5)[:, 2]
        acc = m.acceleration[name].reshape(-1, 5)[:, 2]
        jerk = m.jerk[name].reshape(-1, 5)[:, 2]
        np.testing.assert_allclose(vel, d1 * w, atol=1e-5 * np.abs(vel).max())
        np.testing.assert_allclose(acc, d2 * w**2 + d1 * a, atol=1e-4 * np.abs(acc).max())
        np.testing.assert_allclose(
            jerk, d3 * w**3 + 3 * d2 * w * a + d1 * j, atol=1e-3 * np.abs(jerk).max()
        )


# ----------------------------------------------------------------------------- multi-DOF, rolling
def test_five_bar_two_inputs_matches_circle_intersection_and_fd():
    """Five-bar O2-A-P-D-O5 with cranks theta2 and theta5 (2 DOF)."""
    s = (
        LoopSystem()
        .vector("R1", 4.0, 0.0)
        .vector("R2", 2.0, "theta2")
        .vector("R3", 5.0, "theta3")
        .vector("R4", 5.0, "theta4")
        .vector("R5", 2.0, "theta5")
        .loop("R2 + R3 - R4 - R5 - R1")
        .point("P", "R2 + R3")
    )
    assert s.check(inputs=("theta2", "theta5")).dof == 2
    t = np.linspace(0, 2 * np.pi, 400)
    h = t[1] - t[0]
    theta2 = t
    theta5 = np.pi / 2 + 0.6 * np.sin(t)
    m = s.inputs("theta2", "theta5").solve(
        {"theta2": theta2, "theta5": theta5},
        guess={"theta3": 1.4, "theta4": 1.9},
        velocity={"theta2": 1.0, "theta5": 0.6 * np.cos(t)},
    )
    assert m.ok.all()
    # Independent: P is the upper intersection of circles |P-A| = 5, |P-D| = 5.
    a = 2 * np.exp(1j * theta2)
    d = 4 + 2 * np.exp(1j * theta5)
    mid = (a + d) / 2
    half = np.abs(d - a) / 2
    normal = 1j * (d - a) / np.abs(d - a)
    p_ref = mid + np.sqrt(25 - half**2) * normal  # left of A->D, i.e. above for A left of D
    np.testing.assert_allclose(m.points["P"], p_ref, atol=1e-10)
    vp = m.point_velocity["P"]
    fd = five_point(m.points["P"], h)
    np.testing.assert_allclose(vp[2:-2], fd, atol=1e-6 * np.abs(vp).max())


def test_rolling_constraint_gives_the_cycloid():
    """A wheel of radius r rolling on the ground: x + r*theta = 0; a rim point traces a cycloid."""
    r = 1.5
    s = (
        LoopSystem()
        .vector("X", "x", 0.0)
        .vector("H", r, np.pi / 2)
        .vector("Q", r, "theta")
        .constraint("x + r*theta = c", r=r, c=0.0)
        .point("P = X + H + Q")
        .inputs("theta")
    )
    theta = -np.linspace(0, 4 * np.pi, 50)  # clockwise rolling to the right
    m = s.solve({"theta": theta}, guess={"x": 0.0}, velocity={"theta": -2.0})
    phi = -theta
    # The cycloid written from the rolling geometry: centre at (r phi, r).
    ref = r * phi + 1j * r + r * np.exp(1j * theta)
    np.testing.assert_allclose(m.points["P"], ref, atol=1e-12)
    # Velocity of a rim point = omega x (P - contact point), contact point at (x, 0).
    v_ref = 1j * (-2.0) * (m.points["P"] - m["x"])
    np.testing.assert_allclose(m.point_velocity["P"], v_ref, atol=1e-12)


def test_geared_five_bar_rolling_constraint_closure_and_fd():
    """Geared five-bar: gears on links 2 and 5 roll, r2*theta2 + r5*theta5 = c (1 DOF)."""
    s = (
        LoopSystem()
        .vector("R1", 4.0, 0.0)
        .vector("R2", 2.0, "theta2")
        .vector("R3", 5.0, "theta3")
        .vector("R4", 5.0, "theta4")
        .vector("R5", 2.0, "theta5")
        .loop("R2 + R3 - R4 - R5 - R1")
        .constraint("r2*theta2 + r5*theta5 = c", r2=1.0, r5=2.0, c=np.pi)
        .inputs("theta2")
    )
    theta2 = np.linspace(0, 2 * np.pi, 721)
    m = s.solve(
        {"theta2": theta2},
        guess={"theta3": 1.4, "theta4": 1.9, "theta5": 1.57},
        velocity={"theta2": 1.0},
    )
    assert m.ok.all()
    np.testing.assert_allclose(m["theta5"], (np.pi - theta2) / 2, atol=1e-12)
    np.testing.assert_allclose(m.velocity["theta5"], -0.5, atol=1e-12)
    h = theta2[1] - theta2[0]
    np.testing.assert_allclose(m.velocity["theta3"][2:-2], five_point(m["theta3"], h), atol=1e-7)


# ----------------------------------------------------------------------------- properties
def random_crank_rockers(rng, n):
    out = []
    while len(out) < n:
        r2 = rng.uniform(0.5, 2.0)
        r1, r3, r4 = rng.uniform(3.0, 8.0, 3)
        lengths = sorted([r1, r2, r3, r4])
        if r2 == lengths[0] and lengths[0] + lengths[3] < lengths[1] + lengths[2] - 0.3:
            out.append((r1, r2, r3, r4))
    return out


@pytest.mark.parametrize("form", [1, 2])
def test_random_crank_rockers_follow_their_form_over_a_full_turn(rng, form):
    theta2 = np.linspace(0, 2 * np.pi, 721)
    h = theta2[1] - theta2[0]
    for r1, r2, r3, r4 in random_crank_rockers(rng, 8):
        t3, t4 = fourbar_closed_form(r1, r2, r3, r4, theta2, form)
        s = fourbar_system(r1, r2, r3, r4)
        guess = {"theta3": t3[0] + 0.2, "theta4": t4[0] - 0.2}
        m = s.solve({"theta2": theta2}, guess=guess, velocity={"theta2": 1.0})
        assert m.ok.all()
        np.testing.assert_allclose(wrap(m["theta3"] - t3), 0, atol=1e-9)
        np.testing.assert_allclose(wrap(m["theta4"] - t4), 0, atol=1e-9)
        closure = (
            r2 * np.exp(1j * m["theta2"])
            + r3 * np.exp(1j * m["theta3"])
            - r4 * np.exp(1j * m["theta4"])
            - r1
        )
        assert np.abs(closure).max() < 1e-10 * max(r1, r2, r3, r4)
        for name in ("theta3", "theta4"):
            vel = m.velocity[name][2:-2]
            np.testing.assert_allclose(vel, five_point(m[name], h), atol=1e-6 * np.abs(vel).max())


# ----------------------------------------------------------------------------- continuation
def test_continuation_stays_on_the_circuit_where_fixed_guess_newton_jumps():
    r1, r2, r3, r4 = 1.5, 3.0, 3.5, 3.5  # drag link (GCCC): theta3 and theta4 turn fully
    theta2 = np.linspace(0, 2 * np.pi, 361)
    s = fourbar_system(r1, r2, r3, r4)
    t3, t4 = fourbar_closed_form(r1, r2, r3, r4, theta2, form=1)
    guess = {"theta3": float(t3[0]), "theta4": float(t4[0])}
    naive = s.solve({"theta2": theta2}, guess=guess, continuation=False)
    off = np.abs(wrap(naive["theta4"] - t4)) > 1e-6
    assert off.any(), "the fixed-guess run should leave the circuit somewhere"
    m = s.solve({"theta2": theta2}, guess=guess)
    np.testing.assert_allclose(wrap(m["theta4"] - t4), 0, atol=1e-9)
    assert len(set(m.branch.tolist())) == 1
    # Angles are continuous along the sweep (not wrapped).
    assert np.abs(np.diff(m["theta3"])).max() < 0.1


def test_triple_rocker_past_its_limit_is_flagged_and_resumes_on_the_same_branch():
    r1, r2, r3, r4 = 4.0, 3.0, 3.0, 2.5  # non-Grashof (s + l = 6.5 > p + q = 6): triple rocker
    lengths = sorted((r1, r2, r3, r4))
    assert lengths[0] + lengths[3] > lengths[1] + lengths[2]
    theta2 = np.linspace(0, 2 * np.pi, 721)
    t3, t4 = fourbar_closed_form(r1, r2, r3, r4, theta2, form=1)
    can = np.isfinite(t3)
    assert (~can).any() and can[0]
    m = fourbar_system(r1, r2, r3, r4).solve(
        {"theta2": theta2}, guess={"theta3": float(t3[0]), "theta4": float(t4[0])}
    )
    flagged = ~m.ok
    # Every unassemblable input is flagged with the reason; none is reported as ok.
    assert flagged[~can].all()
    assert all("cannot assemble" in r for r in m.reason[~can])
    # Where it is solved, it is on form 1 (the same branch) both before and after the gap.
    solved = m.ok
    assert solved[can].mean() > 0.95
    np.testing.assert_allclose(wrap(m["theta4"][solved] - t4[solved]), 0, atol=1e-8)
    first_gap = np.flatnonzero(~can)[0]
    assert solved[first_gap + np.flatnonzero(can[first_gap:])[0] + 2 :].any()


def test_independent_samples_on_a_grid_two_dimensional_inputs():
    s = fourbar_system(8, 4, 7, 6)
    theta2 = np.radians(np.arange(0, 91, 15)).reshape(7, 1) * np.ones((1, 2))
    m = s.solve({"theta2": theta2}, guess={"theta3": 0.5, "theta4": 1.5})
    assert m["theta3"].shape == (7, 2)
    t3, _ = fourbar_closed_form(8, 4, 7, 6, theta2)
    np.testing.assert_allclose(wrap(m["theta3"] - t3), 0, atol=1e-10)


def test_toggle_sample_is_flagged_singular():
    """Crank-rocker at its limit position: crank and coupler collinear (extended)."""
    r1, r2, r3, r4 = 4.0, 1.0, 4.5, 3.0
    # Extended toggle: |O4 - A| = r3 + r2 ... -> O2, A, B collinear; solve for theta2 where
    # |B - O2| = r2 + r3, i.e. law of cosines in triangle O2 O4 B.
    cos_t = (r1**2 + (r2 + r3) ** 2 - r4**2) / (2 * r1 * (r2 + r3))
    theta_toggle = np.arccos(cos_t)
    s = fourbar_system(r1, r2, r3, r4)
    # At the toggle of the *output* the Jacobian wrt (theta3, theta4) stays regular;
    # a dead point of the input is when the coupler and rocker are collinear.
    m = s.solve(
        {"theta2": [theta_toggle]}, guess={"theta3": 0.4, "theta4": 1.5}, velocity={"theta2": 1.0}
    )
    assert m.ok.all()  # limit of the rocker, not a singular pose for crank input
    np.testing.assert_allclose(m.velocity["theta4"], 0.0, atol=1e-9)
    # Driving the rocker (input theta4) at its limit is a dead point: singular.
    s4 = fourbar_system(r1, r2, r3, r4).inputs("theta4")
    t4_lim = float(m["theta4"][0])
    m4 = s4.solve(
        {"theta4": [t4_lim]},
        guess={"theta2": theta_toggle, "theta3": 0.4},
        velocity={"theta4": 1.0},
    )
    assert not m4.ok[0]
    assert "singular" in m4.reason[0] or "cannot assemble" in m4.reason[0]


@pytest.mark.parametrize("toward", ["lo", "hi"])
def test_a_sweep_that_runs_into_a_toggle_ends_singular_not_jumped(toward):
    """GRCR 6-9-3-8: link 2 rocks between toggles of links 3 and 4 (the dead points)."""
    fb = FourBar(6, 9, 3, 8)
    limits = fb.input_range(1)
    far, toggle = (limits.hi, limits.lo) if toward == "lo" else (limits.lo, limits.hi)
    theta2 = np.linspace(far + (0.2 if toward == "hi" else -0.2), toggle, 50)
    start = fb.solve(theta2[0])
    s = fourbar_system(6, 9, 3, 8)
    m = s.solve(
        {"theta2": theta2},
        guess={"theta3": float(start.theta3), "theta4": float(start.theta4)},
        velocity={"theta2": 1.0},
    )
    assert m.ok[:-1].all()
    assert m.reason[-1] == REASONS[SINGULAR]  # the closed form says toggle too
    assert fb.solve(theta2[-1:], 1.0).reason[0].startswith("toggle")
    # the pose is still reported, within Newton's reach of a double root (~sqrt(tol))
    closed = fb.solve(theta2, 1.0)
    np.testing.assert_allclose(wrap(m["theta4"] - closed.theta4), 0, atol=1e-5)


@pytest.mark.parametrize("form", [1, 2])
@pytest.mark.parametrize("inset", [0.0, 1e-9])
def test_a_sweep_that_starts_at_a_toggle_stays_on_the_guessed_branch(form, inset):
    """GRCR 6-9-3-8 swept between its dead points; the guess is a pose mid-range.

    Both branches meet at the first sample, so the march is anchored where the guess
    picks one and run out to both ends; the closed form (FourBar, a separate code
    path) says which branch that is.
    """
    fb = FourBar(6, 9, 3, 8)
    limits = fb.input_range(form)
    theta2 = np.linspace(limits.lo + inset, limits.hi - inset, 41)
    middle = fb.solve(theta2[20], form=form)
    m = fourbar_system(6, 9, 3, 8).solve(
        {"theta2": theta2},
        guess={"theta3": float(middle.theta3), "theta4": float(middle.theta4)},
        velocity={"theta2": 1.0},
    )
    closed = fb.solve(theta2, 1.0, form=form)
    assert m.ok[2:-2].all()  # within ~1e-4 rad of a dead point the core flags singular
    assert set(m.reason[~m.ok]) <= {REASONS[SINGULAR]}
    np.testing.assert_allclose(wrap(m["theta4"] - closed.theta4), 0, atol=1e-5)
    np.testing.assert_allclose(wrap(m["theta4"] - closed.theta4)[2:-2], 0, atol=1e-9)


# ----------------------------------------------------------------------------- linear algebra
def test_batched_lu_matches_numpy(rng):
    for n in (1, 2, 3, 5, 8):
        a = rng.normal(size=(50, n, n))
        b = rng.normal(size=(50, n))
        x = lu_solve(lu_factor(np.moveaxis(a, 0, -1)), b.T.copy()).T
        np.testing.assert_allclose(
            x, np.linalg.solve(a, b[..., None])[..., 0], rtol=1e-8, atol=1e-9
        )
        det = lu_factor(np.moveaxis(a, 0, -1)).det
        np.testing.assert_allclose(det, np.linalg.det(a), rtol=1e-9)


def test_lu_needs_pivoting():
    a = np.array([[0.0, 1.0], [1.0, 1.0]])[:, :, None]
    x = lu_solve(lu_factor(a), np.array([[2.0], [3.0]]))
    np.testing.assert_allclose(x[:, 0], [1.0, 2.0])


# ----------------------------------------------------------------------------- results
def test_to_pandas_columns_and_read_only_arrays():
    s = fourbar_system(8, 4, 7, 6)
    m = s.solve(
        {"theta2": [0.1, 0.2]}, guess={"theta3": 0.5, "theta4": 1.5}, velocity={"theta2": 1.0}
    )
    df = m.to_pandas()
    for col in ("theta3", "theta3_dot", "theta3_ddot", "theta3_dddot", "B_x", "B_vy", "ok"):
        assert col in df.columns
    assert len(df) == 2
    with pytest.raises(ValueError):
        m["theta3"][0] = 1.0
    with pytest.raises(KeyError, match="neither a variable nor a point") as lookup:
        m["theta9"]
    assert isinstance(lookup.value, UnknownNameError)
    plain = s.solve({"theta2": [0.1]}, guess={"theta3": 0.5, "theta4": 1.5})
    assert plain.velocity is None and plain.point_velocity is None


# ----------------------------------------------------------------------------- bad input
def test_unknown_vector_in_loop_lists_the_defined_ones():
    s = fourbar_system(8, 4, 7, 6).loop("R2 + R9 - R1")
    with pytest.raises(ModelError, match=r"unknown vector\(s\) R9; defined vectors: R1, R2"):
        s.check()


def test_unknown_input_and_constraint_variable():
    with pytest.raises(ModelError, match="theta9 appear in no vector"):
        fourbar_system(8, 4, 7, 6).check(inputs=("theta9",))
    s = fourbar_system(8, 4, 7, 6).constraint("thetta3 = theta4 + g", g=0.1)
    with pytest.raises(ModelError, match="thetta3 is no variable"):
        s.check()


def test_unused_vector_is_reported():
    s = fourbar_system(8, 4, 7, 6).vector("R5", 1.0, "theta5")
    with pytest.raises(ModelError, match="R5 appear in no loop"):
        s.check()


def test_wrong_dof_over_and_under_determined():
    s = fourbar_system(8, 4, 7, 6)
    with pytest.raises(ModelError, match="3 variables, 2 equations: DOF 1, but 2 inputs"):
        s.check(inputs=("theta2", "theta3"))
    s.constraint("theta3 = theta4")
    with pytest.raises(ModelError, match="DOF 0, but 1 input was named"):
        s.check(inputs=("theta2",))


def test_redundancy_three_vectors_of_one_link():
    """Link 3 as a triangle with all three constant-angle constraints (notes: redundancy)."""
    s = (
        fourbar_system(8, 4, 7, 6)
        .vector("R3p", 3.0, "theta3p")
        .vector("R3q", 3.0, "theta3q")
        .point("P", "R2 + R3p")
        .point("Q", "R2 + R3q")
        .constraint("theta3p = theta3 + a", a=0.3)
        .constraint("theta3q = theta3 + b", b=0.5)
        .constraint("theta3q = theta3p + c", c=0.2)
    )
    with pytest.raises(ModelError, match=r"redundant formulation.*theta3q = theta3p"):
        s.check()


def test_inputs_that_do_not_determine_the_unknowns():
    s = (
        fourbar_system(8, 4, 7, 6)
        .vector("R3p", 3.0, "theta3p")
        .point("P", "R2 + R3p")
        .constraint("theta3p = theta3 + a", a=0.3)
    )
    # theta3p is tied to theta3: driving theta3p leaves theta2 free but cannot fix it... the
    # DOF count is right (1), but driving both theta3 and theta3p through one input is fine;
    # a point-only variable is not: make a vector whose angle appears in a point only.
    s2 = fourbar_system(8, 4, 7, 6).vector("R9", 1.0, "theta9").point("P9", "R2 + R9")
    with pytest.raises(ModelError, match="DOF 2"):
        s2.check(inputs=("theta2",))
    with pytest.raises(ModelError, match=r"unknowns theta9 are not determined"):
        s2.check(inputs=("theta2", "theta3"))
    assert s.check(inputs=("theta3p",)).dof == 1


def test_missing_and_extra_guesses():
    s = fourbar_system(8, 4, 7, 6)
    with pytest.raises(ModelError, match="no guess for theta4: a guess picks the branch"):
        s.solve({"theta2": [0.0]}, guess={"theta3": 0.5})
    with pytest.raises(ModelError, match="theta2, which are not unknowns"):
        s.solve({"theta2": [0.0]}, guess={"theta3": 0.5, "theta4": 1.5, "theta2": 0.0})


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("R2 + + R3", "unexpected '\\+'"),
        ("R2 + R3 -", "ends with an operator"),
        ("R2 R3", "missing '\\+', '-' or '\\*'"),
        ("R2 + 2*R3", "not a vector name"),
        ("R2 = R3 = R4", "more than one '='"),
        ("R2 + $", "unexpected"),
        ("", "signed sum"),
        ("R2 - R2", "all cancel"),
    ],
)
def test_malformed_loop_text(text, match):
    with pytest.raises(InputError, match=match):
        LoopSystem().loop(text)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("theta3 + theta4", "lhs = rhs"),
        ("theta3*theta4 = 1", "not linear"),
        ("a = 2", "contains no variable"),
    ],
)
def test_malformed_constraints(text, match):
    with pytest.raises(InputError, match=match):
        LoopSystem().constraint(text, a=1.0)


def test_non_finite_inputs_and_bad_vectors():
    s = fourbar_system(8, 4, 7, 6)
    with pytest.raises(InputError, match="theta2: must be finite; sample 1 is nan"):
        s.solve({"theta2": [0.0, np.nan]}, guess={"theta3": 0.5, "theta4": 1.5})
    with pytest.raises(InputError, match=r"guess\[theta3\]: must be finite"):
        s.solve({"theta2": [0.0]}, guess={"theta3": np.inf, "theta4": 1.5})
    with pytest.raises(InputError, match=r"velocity\[theta2\]"):
        s.solve(
            {"theta2": [0.0]},
            guess={"theta3": 0.5, "theta4": 1.5},
            velocity={"theta2": [1.0, 2.0, 3.0]},
        )
    with pytest.raises(InputError, match=r"R1\.length: must be a positive length"):
        LoopSystem().vector("R1", -1.0, 0.0)
    with pytest.raises(InputError, match="identifier"):
        LoopSystem().vector("R 1", 1.0, 0.0)
    with pytest.raises(ModelError, match="defined twice"):
        LoopSystem().vector("R1", 1.0, 0.0).vector("R1", 1.0, 0.0)
    with pytest.raises(ModelError, match="values must be given for exactly theta2; missing"):
        s.solve({"theta3": [0.0]}, guess={"theta3": 0.5, "theta4": 1.5})
    with pytest.raises(ModelError, match="velocity given for theta3"):
        s.solve(
            {"theta2": [0.0]},
            guess={"theta3": 0.5, "theta4": 1.5},
            velocity={"theta2": 1.0, "theta3": 1.0},
        )


def test_scalar_and_batched_newton_agree(rng):
    """The plain-Python single-pose Newton (used by the march) equals the batched one."""
    from machdyn.loops import solve as core

    s = watt_six_bar_with_slider()
    c = s._compile(("theta2",))
    for _ in range(5):
        u = rng.uniform(0, 2 * np.pi, (1, 1))
        q0 = np.array(
            [
                [
                    {"theta3": 1.2, "theta4": 1.9, "theta4c": 2.2, "theta5": 0.4, "d6": 10.0}[
                        c.names[i]
                    ]
                ]
                for i in c.unknown
            ]
        )
        a = core.newton(c, q0, u)
        b = core.newton_one(c, q0, u)
        assert a.converged[0] == b.converged[0]
        if a.converged[0]:
            np.testing.assert_allclose(a.q, b.q, atol=1e-10)
            np.testing.assert_allclose(a.tan, b.tan, rtol=1e-8, atol=1e-10)
            np.testing.assert_allclose(a.det, b.det, rtol=1e-8)


def test_reversed_sweep_gives_the_same_poses():
    s = fourbar_system(4.0, 1.0, 4.5, 3.0)
    theta2 = np.linspace(0, 2 * np.pi, 200)
    fwd = s.solve({"theta2": theta2}, guess={"theta3": 0.4, "theta4": 1.5})
    g = {"theta3": float(fwd["theta3"][-1]), "theta4": float(fwd["theta4"][-1])}
    back = s.solve({"theta2": theta2[::-1]}, guess=g)
    np.testing.assert_allclose(wrap(back["theta4"][::-1] - fwd["theta4"]), 0, atol=1e-10)


def test_lost_branch_and_stop_are_reported_not_silent():
    """A sweep that starts outside the assemblable range: those samples are flagged."""
    r1, r2, r3, r4 = 4.0, 3.0, 3.0, 2.5  # triple rocker
    theta2 = np.linspace(np.pi - 0.3, np.pi + 0.3, 7)  # around theta2 = 180 deg
    t3, _ = fourbar_closed_form(r1, r2, r3, r4, theta2)
    m = fourbar_system(r1, r2, r3, r4).solve(
        {"theta2": theta2}, guess={"theta3": 0.3, "theta4": 1.0}
    )
    assert (~m.ok[~np.isfinite(t3)]).all()
    assert np.isnan(m["theta3"][~m.ok]).all()
    assert (m.reason[m.ok] == "").all()


def test_sweep_with_a_big_jump_between_two_ranges():
    """Two ranges of theta2 in one sweep (a 3 rad jump between them): both solved on form 1."""
    r1, r2, r3, r4 = 4.0, 1.0, 4.5, 3.0
    theta2 = np.concatenate([np.linspace(0.0, 1.0, 500), np.linspace(4.0, 5.0, 500)])
    t3, t4 = fourbar_closed_form(r1, r2, r3, r4, theta2, form=1)
    m = fourbar_system(r1, r2, r3, r4).solve(
        {"theta2": theta2}, guess={"theta3": float(t3[0]), "theta4": float(t4[0])}
    )
    assert m.ok.all()
    np.testing.assert_allclose(wrap(m["theta4"] - t4), 0, atol=1e-9)


def test_model_changes_after_a_solve_are_checked_again():
    s = fourbar_system(8, 4, 7, 6)
    s.solve({"theta2": [0.1]}, guess={"theta3": 0.5, "theta4": 1.5})
    s.constraint("theta3 = theta4")
    with pytest.raises(ModelError, match="DOF 0, but 1 input was named"):
        s.solve({"theta2": [0.1]}, guess={"theta3": 0.5, "theta4": 1.5})


def test_plot_labels_angles_in_degrees():
    import matplotlib

    matplotlib.use("Agg")
    s = watt_six_bar_with_slider(constraint=False)
    m = s.solve(
        {"theta2": np.linspace(0, 1, 20)},
        guess={"theta3": 1.2, "theta4": 1.9, "theta5": 0.4, "d6": 10.0},
    )
    ax = m.plot()
    labels = [line.get_label() for line in ax.get_lines()]
    assert "theta3 [deg]" in labels and "d6" in labels
    assert ax.get_xlabel() == "theta2 [deg]"
    np.testing.assert_allclose(ax.get_lines()[0].get_xdata(), np.degrees(np.linspace(0, 1, 20)))


def test_notes_six_link_example_solves_along_a_sweep():
    """The notes' 6-link example (7 unknowns), with lengths chosen so that a known pose closes.

    The pose is built first (theta2 = 0.5, d3 = 3, theta3 = 1.0, theta7 = 2.0, gamma = 0.4)
    and the remaining lengths are computed from it, so the guess is an exact solution.
    """
    e = np.exp
    theta2, d3, theta3, theta7, gamma = 0.5, 3.0, 1.0, 2.0, 0.4
    d2, dbar, d7, d9, d1 = 3.0, 9.0, 2.0, 3.0, 10.0
    p1 = d2 * e(1j * theta2) + dbar * e(1j * theta3)
    d5, d6 = p1.real, p1.imag
    r8 = d2 * e(1j * theta2) + d3 * e(1j * theta3) + d7 * e(1j * theta7) - d1
    d8, theta8 = abs(r8), np.angle(r8)
    r11 = 6.0 * e(0.3j)
    r10 = r8 + d9 * e(1j * (theta7 + gamma)) - r11
    d10, theta10 = abs(r10), np.angle(r10)
    s = LoopSystem()
    s.vector("R1", d1, 0.0).vector("R2", d2, "theta2").vector("R5", d5, 0.0)
    s.vector("R6", "d6", np.pi / 2).vector("R7", d7, "theta7").vector("R8", d8, "theta8")
    s.vector("R9", d9, "theta9").vector("R10", d10, "theta10").vector("R11", 6.0, 0.3)
    s.vector("R3", "d3", "theta3").vector("R34", dbar, "theta3")
    s.loop("R2 + R34 - R5 - R6").loop("R2 + R3 + R7 - R8 - R1").loop("R8 + R9 - R10 - R11")
    s.constraint("theta9 - theta7 = gamma", gamma=gamma).inputs("theta2")
    guess = {
        "d3": d3,
        "d6": d6,
        "theta3": theta3,
        "theta7": theta7,
        "theta8": theta8,
        "theta9": theta7 + gamma,
        "theta10": theta10,
    }
    # d3 shrinks from 3 to ~1.8; near theta2 = 0.69 this circuit reaches a limit (a fold: a
    # multi-start check finds 8 distinct poses at 0.68 and 6 at 0.70).
    sweep = np.linspace(0.5, 0.62, 301)
    m = s.solve({"theta2": sweep}, guess=guess, velocity={"theta2": 2.0})
    assert m.ok.all()
    assert m["d3"][0] == pytest.approx(d3, abs=1e-10)
    loop2 = (
        d2 * e(1j * m["theta2"])
        + m["d3"] * e(1j * m["theta3"])
        + d7 * e(1j * m["theta7"])
        - d8 * e(1j * m["theta8"])
        - d1
    )
    assert np.abs(loop2).max() < 1e-10 * d1
    h = sweep[1] - sweep[0]
    for name in ("d3", "d6", "theta8", "theta10"):
        vel = m.velocity[name][2:-2]
        np.testing.assert_allclose(vel, 2.0 * five_point(m[name], h), atol=1e-6 * np.abs(vel).max())


# ----------------------------------------------------------------------------- fast path
# Short, evenly stepped sweeps take a fast path (a plain-float coarse march, one batched
# Hermite fill, vectorised checks); anything doubtful goes to the careful path (doubling
# waves). Both must give the same motion; the careful path is forced by setting the
# fast path's size limit to zero.
def _careful(monkeypatch, solve):
    from machdyn.loops import solve as core

    monkeypatch.setattr(core, "FAST_MAX_SAMPLES", 0)
    try:
        return solve()
    finally:
        monkeypatch.undo()


def _try_fast(s: LoopSystem, name: str, values: np.ndarray, guess: dict):
    """The fast path's own answer for this sweep (None: it declined)."""
    from machdyn.loops import solve as core

    c = s._checked((name,))
    q0 = np.array([[float(guess[c.names[i]])] for i in c.unknown])
    first = core.newton_one(c, q0, values[None, :1])
    want = np.sign(first.gdet[:, 0])
    options = {"max_step": 0.4, "tol": 1e-12, "max_iter": 50, "sing_tol": core.SINGULAR_RCOND}
    return core._sweep_fast(c, values[None], q0, want, first, **options)


def _fast_taken(s: LoopSystem, theta2: np.ndarray, guess: dict) -> bool:
    from machdyn.loops import solve as core

    res = _try_fast(s, "theta2", theta2, guess)
    return res is not None and bool((res.code == core.OK).all())


@pytest.mark.parametrize(
    "build, guess",
    [
        (lambda: fourbar_system(8, 2, 7, 6), {"theta3": 0.5, "theta4": 1.5}),  # crank-rocker
        (lambda: fourbar_system(1.5, 3.0, 3.5, 3.5), {"theta3": 1.0, "theta4": 1.9}),  # drag link
        (
            watt_six_bar_with_slider,
            {"theta3": 1.2, "theta4": 1.9, "theta4c": 2.2, "theta5": 0.4, "d6": 10.0},
        ),
    ],
)
@pytest.mark.usefixtures("numpy_path")
def test_fast_and_careful_paths_agree(monkeypatch, build, guess):
    s = build()
    theta2 = np.linspace(0.0, 2 * np.pi, 3600)
    assert _fast_taken(s, theta2, guess)

    def solve():
        return s.solve({"theta2": theta2}, guess=guess, velocity={"theta2": 3.0})

    fast, careful = solve(), _careful(monkeypatch, solve)
    assert fast.ok.all() and careful.ok.all()
    np.testing.assert_array_equal(fast.branch, careful.branch)
    for name in fast.positions:
        np.testing.assert_allclose(fast[name], careful[name], rtol=0, atol=1e-10)
        for a, b in (
            (fast.velocity, careful.velocity),
            (fast.acceleration, careful.acceleration),
            (fast.jerk, careful.jerk),
        ):
            np.testing.assert_allclose(a[name], b[name], rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(fast.residual, 0.0, atol=1e-12)


@pytest.mark.usefixtures("numpy_path")
def test_fast_path_four_bar_matches_the_law_of_cosines_and_finite_differences():
    r1, r2, r3, r4 = 8.0, 2.0, 7.0, 6.0
    theta2 = np.linspace(0.0, 2 * np.pi, 3600)
    t3, t4 = fourbar_closed_form(r1, r2, r3, r4, theta2, form=1)
    s = fourbar_system(r1, r2, r3, r4)
    guess = {"theta3": float(t3[0]), "theta4": float(t4[0])}
    assert _fast_taken(s, theta2, guess)
    m = s.solve({"theta2": theta2}, guess=guess, velocity={"theta2": 1.0})
    np.testing.assert_allclose(wrap(m["theta3"] - t3), 0, atol=1e-10)
    np.testing.assert_allclose(wrap(m["theta4"] - t4), 0, atol=1e-10)
    h = theta2[1] - theta2[0]
    for name in ("theta3", "theta4"):
        vel = m.velocity[name][2:-2]
        np.testing.assert_allclose(vel, five_point(m[name], h), atol=1e-8 * np.abs(vel).max())


@pytest.mark.usefixtures("numpy_path")
def test_hard_sweeps_fall_back_to_the_careful_path(monkeypatch):
    """An assembly gap, dead points, a reversing or uneven sweep: no fast path, same answers."""
    tri = fourbar_system(4.0, 3.0, 3.0, 2.5)  # triple rocker: cannot pass ~102.6 deg
    t3, t4 = fourbar_closed_form(4.0, 3.0, 3.0, 2.5, np.array([0.0]))
    tri_guess = {"theta3": float(t3[0]), "theta4": float(t4[0])}
    crank = fourbar_system(8, 2, 7, 6)
    crank_guess = {"theta3": 0.5, "theta4": 1.5}
    # Crank-rocker 4-1-4.5-3 driven by its rocker from one dead point to the other: there
    # the crank and coupler are collinear, |O2 B| = r3 -+ r2, which fixes theta4 by the
    # law of cosines in the triangle O2 O4 B.
    r1, r2, r3, r4 = 4.0, 1.0, 4.5, 3.0
    ends = [np.arccos((ln**2 - r1**2 - r4**2) / (2 * r1 * r4)) for ln in (r3 + r2, r3 - r2)]
    rocker = fourbar_system(r1, r2, r3, r4).inputs("theta4")
    b = r4 * np.exp(1j * ends[0]) + r1  # extended: crank and coupler both along O2 -> B
    rocker_guess = {"theta2": float(np.angle(b)), "theta3": float(np.angle(b))}
    there_and_back = np.concatenate([np.linspace(0, 1, 500), np.linspace(1, 0, 500)[1:]])
    cases = [
        (tri, "theta2", np.linspace(0, 2 * np.pi, 2000), tri_guess),  # assembly gap
        (rocker, "theta4", np.linspace(ends[0], ends[1], 1000), rocker_guess),  # dead points
        (crank, "theta2", there_and_back, crank_guess),  # reverses: not one straight sweep
        (crank, "theta2", np.linspace(0, 1, 1000) ** 2, crank_guess),  # uneven steps
    ]

    for s, name, values, guess in cases:
        assert _try_fast(s, name, values, guess) is None

        def solve(s=s, name=name, values=values, guess=guess):
            return s.solve({name: values}, guess=guess, velocity={name: 1.0})

        a, b = solve(), _careful(monkeypatch, solve)
        assert not a.ok.all() or s is crank
        np.testing.assert_array_equal(a.ok, b.ok)
        np.testing.assert_array_equal(a.reason, b.reason)
        np.testing.assert_array_equal(a.positions[name], b.positions[name])
        for key in a.positions:
            np.testing.assert_array_equal(a[key], b[key])


@pytest.mark.usefixtures("numpy_path")
def test_fill_that_cannot_converge_falls_back(monkeypatch):
    """With no corrector step allowed the fast fill fails its checks; the careful path
    then solves the sweep, so the answer is unchanged (against the law of cosines)."""
    from machdyn.loops import solve as core

    r1, r2, r3, r4 = 8.0, 2.0, 7.0, 6.0
    theta2 = np.linspace(0.0, 2 * np.pi, 3600)
    t3, _ = fourbar_closed_form(r1, r2, r3, r4, theta2)
    s = fourbar_system(r1, r2, r3, r4)
    guess = {"theta3": float(t3[0]), "theta4": 1.5}
    monkeypatch.setattr(core, "FAST_ITER", 0)
    assert not _fast_taken(s, theta2, guess)
    m = s.solve({"theta2": theta2}, guess=guess)
    assert m.ok.all()
    np.testing.assert_allclose(wrap(m["theta3"] - t3), 0, atol=1e-10)


def test_sparse_lu_equals_dense_lu_and_numpy(rng):
    """lu_structure: skipping structural zeros gives the dense factors (pivots and all)."""
    from machdyn.loops._linalg import _factor, lu_structure

    for n in (3, 4, 5, 6):
        for _ in range(4):
            pattern = rng.random((n, n)) < 0.45
            pattern[rng.permutation(n), np.arange(n)] = True  # structurally non-singular
            a = rng.normal(size=(n, n, 40)) * pattern[:, :, None]
            ones = np.ones(n)
            dense = lu_factor(a, ones, ones)
            sparse = _factor(a, ones, ones, lu_structure(pattern))
            np.testing.assert_allclose(sparse.lu, dense.lu, rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(sparse.det, dense.det, rtol=1e-12)
            np.testing.assert_allclose(sparse.rcond, dense.rcond, rtol=1e-12)
            a_np = np.moveaxis(a, -1, 0)
            np.testing.assert_allclose(sparse.det, np.linalg.det(a_np), rtol=1e-8, atol=1e-12)
            b = rng.normal(size=(n, 40))
            np.testing.assert_allclose(
                lu_solve(sparse, b).T,
                np.linalg.solve(a_np, b.T[..., None])[..., 0],
                rtol=1e-7,
                atol=1e-9,
            )


def test_2x2_closed_form_matches_pivoted_elimination(rng):
    """The 2x2 inverse reports the det and the pivot-ratio rcond of partial pivoting."""
    from machdyn.loops._linalg import _eliminate

    a = rng.normal(size=(2, 2, 200))
    a[:, 0, :3] = 0.0  # a zero first column: singular, rcond 0
    a[1, :, 3] = 2.0 * a[0, :, 3]  # dependent rows: singular
    f = lu_factor(a, np.ones(2), np.ones(2))
    assert f.inv is not None
    g = _eliminate(a.copy(), np.ones((2, 1)), np.ones((2, 1)), 1.0, None)
    np.testing.assert_allclose(f.det, g.det, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(f.rcond[4:], g.rcond[4:], rtol=1e-12)
    assert (f.rcond[:3] == 0.0).all() and f.rcond[3] < 1e-15
    b = rng.normal(size=(2, 3, 200))
    np.testing.assert_allclose(
        lu_solve(f, b)[..., 4:], lu_solve(g, b)[..., 4:], rtol=1e-9, atol=1e-12
    )


def test_small_step_trig_rotation_is_exact_to_rounding(rng):
    from machdyn.loops._equations import _step_terms, _vector_terms

    s = fourbar_system(8, 2, 7, 6)
    c = s._checked(("theta2",))
    x = rng.uniform(-np.pi, np.pi, (len(c.names), 500))
    for size in (1e-9, 1e-5, 2e-3, 0.3):  # the last is evaluated afresh
        step = rng.uniform(-size, size, (len(c.unknown), 500))
        x2 = x.copy()
        x2[c.unknown] += step
        _, cos, sin = _step_terms(c, x2, _vector_terms(c, x), step)
        _, cos_ref, sin_ref = _vector_terms(c, x2)
        for a, b in zip(cos + sin, cos_ref + sin_ref, strict=True):
            np.testing.assert_allclose(a, b, rtol=0, atol=4e-16)


@pytest.mark.usefixtures("numpy_path")
def test_failed_fill_samples_are_re_solved_carefully_on_their_stretch_only(monkeypatch):
    """Samples the fast fill rejects (here: forced) are re-solved by the careful path over
    the stretch that holds them; the result equals the law of cosines everywhere."""
    from machdyn.loops import solve as core

    r1, r2, r3, r4 = 8.0, 2.0, 7.0, 6.0
    theta2 = np.linspace(0.0, 2 * np.pi, 3600)
    t3, t4 = fourbar_closed_form(r1, r2, r3, r4, theta2)
    s = fourbar_system(r1, r2, r3, r4)
    fast = core._sweep_fast
    spans = []

    def failing(*args, **kw):
        res = fast(*args, **kw)
        code = res.code.copy()
        code[[1000, 1001, 1500]] = core.NO_ASSEMBLY  # as if they failed a check
        q = res.q.copy()
        q[:, code != core.OK] = np.nan
        kept = (res.residual, res.det, res.rcond, res.gdet, res.grc, res.group, res.want)
        return core.Positions(q, code, *kept)

    solve_positions = core.solve_positions

    def spy(c, u, guess, continuation, **kw):
        if kw.get("fast") is False:
            spans.append(u.shape[1])
        return solve_positions(c, u, guess, continuation, **kw)

    monkeypatch.setattr(core, "_sweep_fast", failing)
    monkeypatch.setattr(core, "solve_positions", spy)
    m = s.solve({"theta2": theta2}, guess={"theta3": 0.9, "theta4": 1.5}, velocity={"theta2": 1.0})
    assert spans == [1500 - 1000 + 3]  # from sample 999 to 1501
    assert m.ok.all()
    np.testing.assert_allclose(wrap(m["theta3"] - t3), 0, atol=1e-10)
    np.testing.assert_allclose(wrap(m["theta4"] - t4), 0, atol=1e-10)
