"""Assur groups of a drawn linkage: every dyad kind in closed form, against geometry in the test.

Each dyad kind (RRR, RRP, PRR, RPR, RPP, PRP) is checked on both assembly signs
against an intersection written independently in tests/closed_forms.py (real
coordinates, quadratic formulas, a 2 × 2 solve); six-bars, a Jansen leg and a
six-bar with a slider against the vector-loop core (machdyn.loops through the
whole-linkage loop compilation); seeded random dyad chains for closure, finite
differences and the power balance; flags at toggles and assembly gaps name
the group, never a sample on the other branch.
"""

from __future__ import annotations

import numpy as np
import pytest

from closed_forms import circle_line_meet, circle_meet, line_meet, tangent_angle
from machdyn.errors import ModelError
from machdyn.linkage import Linkage
from machdyn.linkage.kinematics import _per_driver
from machdyn.linkage.loopsolve import solve_loops
from test_linkage import _energy_rates, rigid_errors, stephenson_iii, watt_ii

# every test on the NumPy path and on the compiled kernels (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("backend")

SWEEP = np.radians(np.arange(0.0, 360.0, 3.0))


def fourbar(side: float) -> Linkage:
    A = 4.0 + 0j
    B = circle_meet(A, 7.0, 8.0 + 0j, 6.0, side)
    lk = Linkage({"O2": 0j, "O4": 8.0 + 0j, "A": A, "B": B}).ground("O2", "O4")
    return (
        lk.link("crank", "O2", "A")
        .link("coupler", "A", "B")
        .link("rocker", "O4", "B")
        .drive("crank")
    )


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_rrr_both_signs_against_two_circles(side):
    lk = fourbar(side)
    kinds = [(g.kind, g.sign) for g in lk.groups]
    assert kinds == [("driver", 0), ("RRR", int(side))]
    m = lk.solve(SWEEP, velocity=1.0)
    assert m.ok.all()
    for k, th in enumerate(SWEEP):
        B = circle_meet(4.0 * np.exp(1j * th), 7.0, 8.0 + 0j, 6.0, side)
        assert abs(m.points["B"][k] - B) < 1e-12


def offset_slider(side: float, block_first: bool) -> Linkage:
    """Crank 2, rod 6, slide line y = 1 along +x; B ahead of (side +1) or behind A's foot."""
    A = 2.0 * np.exp(1j * 0.4)
    B = circle_line_meet(A, 6.0, 1j, 1.0 + 0j, side)
    lk = Linkage({"O2": 0j, "A": A, "B": B, "Q": 1j}).ground("O2", "Q")
    lk.link("crank", "O2", "A")
    if block_first:
        lk.link("block", "B").link("rod", "A", "B")
    else:
        lk.link("rod", "A", "B").link("block", "B")
    return lk.slider("block", "ground", "B", 0.0, through="Q", name="guide").drive("crank")


@pytest.mark.parametrize("block_first", [False, True])
@pytest.mark.parametrize("side", [1.0, -1.0])
def test_rrp_and_prr_both_signs_against_a_circle_and_a_line(side, block_first):
    lk = offset_slider(side, block_first)
    (g,) = lk.groups[1:]
    assert (g.kind, g.sign) == (("PRR" if block_first else "RRP"), int(side))
    m = lk.solve(SWEEP, velocity=2.0)
    assert m.ok.all()
    for k, th in enumerate(SWEEP):
        B = circle_line_meet(2.0 * np.exp(1j * th), 6.0, 1j, 1.0 + 0j, side)
        assert abs(m.points["B"][k] - B) < 1e-12
        assert abs(m.lengths["guide"][k] - B.real) < 1e-12  # measured from Q along +x


def inverted_slider(side: float, e: float) -> Linkage:
    """Crank 2 about O2; a block pinned at A slides on a rocker pivoted at O4 = 5 whose slide
    line passes at the signed distance e from O4 (A ahead of O4's foot for side +1)."""
    A = 2.0 * np.exp(1j * 1.0)
    O4 = 5.0 + 0j
    u = np.exp(1j * tangent_angle(O4, A, e, side))
    F = O4 + e * 1j * u  # foot of O4 on the line (e > 0: O4 on the right)
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "F": F, "T": F + 3.0 * u}).ground("O2", "O4")
    lk.link("crank", "O2", "A").link("block", "A").link("rocker", "O4", "F", "T")
    return lk.slider("block", "rocker", "A", u, through="F", name="s").drive("crank")


@pytest.mark.parametrize("e", [0.0, 0.7, -0.4])
@pytest.mark.parametrize("side", [1.0, -1.0])
def test_rpr_both_signs_against_a_tangent_line(side, e):
    lk = inverted_slider(side, e)
    (g,) = lk.groups[1:]
    # the group is (block, rocker): its sign tells whether the rocker's pivot O4 lies ahead of
    # the block's pin A along the slide, the opposite of ``side`` (A ahead of O4's foot)
    assert (g.kind, g.links, g.sign) == ("RPR", ("block", "rocker"), -int(side))
    m = lk.solve(SWEEP, velocity=3.0)
    assert m.ok.all()
    th0 = float(m.theta["rocker"][0]) - tangent_angle(5.0 + 0j, 2.0 + 0j, e, side)
    for k, th in enumerate(SWEEP):
        A = 2.0 * np.exp(1j * th)
        angle = tangent_angle(5.0 + 0j, A, e, side)
        diff = (m.theta["rocker"][k] - th0 - angle + np.pi) % (2 * np.pi) - np.pi
        assert abs(diff) < 1e-12


def test_rpp_scotch_yoke_with_a_block_against_two_lines():
    """A block pinned at the crank pin A slides in the yoke's slot (along v); the yoke slides
    on the ground along u: the yoke's point Y = the meet of line(A, v) and line(Y0, u)."""
    A = 2.0 * np.exp(1j * 0.3)
    v, u = np.exp(1j * 1.2), np.exp(1j * 0.1)
    Y0 = line_meet(A, v, 6.0 + 1j, u)
    lk = Linkage({"O2": 0j, "A": A, "Y": Y0, "Z": Y0 + 2.0 * u, "G": 6.0 + 1j}).ground("O2", "G")
    lk.link("crank", "O2", "A").link("block", "A").link("yoke", "Y", "Z")
    lk.slider("block", "yoke", "A", v, through="Y", name="slot")
    lk.slider("yoke", "ground", "Y", u, through="G", name="guide").drive("crank")
    assert [(g.kind, g.sign) for g in lk.groups] == [("driver", 0), ("RPP", 0)]
    m = lk.solve(SWEEP, velocity=1.0)
    assert m.ok.all()
    for k, th in enumerate(SWEEP):
        Y = line_meet(2.0 * np.exp(1j * th), v, 6.0 + 1j, u)
        assert abs(m.points["Y"][k] - Y) < 1e-12


def test_prp_two_blocks_on_two_lines_against_two_lines():
    """A block on a horizontal guide (y = 1.5) pinned at B to a block sliding on the crank:
    B = the meet of the guide and the crank's line."""
    th0 = 0.6
    B0 = line_meet(0j, np.exp(1j * th0), 1.5j, 1 + 0j)
    lk = Linkage({"O2": 0j, "A": 2.0 * np.exp(1j * th0), "B": B0, "Q": 1.5j}).ground("O2", "Q")
    lk.link("crank", "O2", "A").link("runner", "B").link("carriage", "B")
    lk.slider("runner", "crank", "B", th0, through="O2", name="on_crank")
    lk.slider("carriage", "ground", "B", 0.0, through="Q", name="guide").drive("crank")
    assert [(g.kind, g.sign) for g in lk.groups] == [("driver", 0), ("PRP", 0)]
    theta = np.radians(np.arange(20.0, 160.0, 2.0))
    m = lk.solve(theta, velocity=1.0, acceleration=0.5)
    assert m.ok.all()
    for k, th in enumerate(theta):
        assert abs(m.points["B"][k] - line_meet(0j, np.exp(1j * th), 1.5j, 1 + 0j)) < 1e-12
    # the runner slides along the crank: |B| = 1.5 / sin θ, so its rate is -1.5 cos θ / sin² θ
    rate = -1.5 * np.cos(theta) / np.sin(theta) ** 2
    np.testing.assert_allclose(m.length_rate["on_crank"], rate, rtol=1e-10, atol=1e-12)


# ---------------------------------------------------------------------------- against the loops
def against_loops(lk: Linkage, theta, omega=1.7, alpha=0.3, tol=1e-10) -> None:
    m = lk.solve(theta, velocity=omega, acceleration=alpha)
    d = tuple(lk.drivers)
    ref = solve_loops(
        lk,
        _per_driver("v", theta, d, True),
        _per_driver("w", omega, d, True),
        _per_driver("a", alpha, d, False),
        True,
    )
    assert (m.ok == ref.ok).all()
    for table in ("theta", "omega", "alpha", "points", "point_velocity", "point_acceleration"):
        mine, theirs = getattr(m, table), getattr(ref, table)
        for k in mine:
            scale = max(1.0, np.nanmax(np.abs(theirs[k])))
            assert np.nanmax(np.abs(mine[k] - theirs[k])) <= tol * scale, (table, k)


def jansen_leg(theta=0.0) -> Linkage:
    """Theo Jansen's leg (his 'holy numbers'): crank 15 about O, frame pivot Y at (-38, -7.8)."""
    O0, Y = 0j, -38.0 - 7.8j
    X = 15.0 * np.exp(1j * theta)
    B = circle_meet(X, 50.0, Y, 41.5, -1.0)
    C = circle_meet(X, 61.9, Y, 39.3, 1.0)
    D = circle_meet(B, 55.8, Y, 40.1, -1.0)  # the frame's triangle Y-B-D: 41.5, 55.8, 40.1
    E = circle_meet(D, 39.4, C, 36.7, -1.0)
    F = circle_meet(E, 65.7, C, 49.0, -1.0)  # the foot, lowest
    lk = Linkage({"O": O0, "Y": Y, "X": X, "B": B, "C": C, "D": D, "E": E, "F": F})
    lk.ground("O", "Y").link("crank", "O", "X").link("j", "X", "B").link("upper", "Y", "B", "D")
    lk.link("k", "X", "C").link("c", "Y", "C").link("f", "D", "E").link("leg", "C", "E", "F")
    return lk.drive("crank")


def press() -> Linkage:
    """A six-bar press: crank-rocker 8-2-7-6 whose rocker point C drives a rod C-D (8) to a
    vertical ram D (a slider on the ground, on the line x = 10)."""
    A = 2.0 + 0j
    B = circle_meet(A, 7.0, 8.0 + 0j, 6.0)
    C = 8.0 + 9.0 * (B - 8.0) / 6.0
    D = circle_line_meet(C, 8.0, 10.0 + 0j, 1j, 1.0)
    lk = Linkage({"O2": 0j, "O4": 8.0 + 0j, "A": A, "B": B, "C": C, "D": D, "R": 10.0 + 0j})
    lk.ground("O2", "O4", "R").link("crank", "O2", "A").link("coupler", "A", "B")
    lk.link("rocker", "O4", "B", "C").link("rod", "C", "D").link("ram", "D")
    return lk.slider("ram", "ground", "D", np.pi / 2, through="R", name="ram").drive("crank")


@pytest.mark.parametrize(
    "build, kinds",
    [
        (watt_ii, ["driver", "RRR", "RRR"]),
        (stephenson_iii, ["driver", "RRR", "RRR"]),
        (jansen_leg, ["driver", "RRR", "RRR", "RRR"]),
        (press, ["driver", "RRR", "RRP"]),
    ],
)
def test_six_bars_jansen_leg_and_a_press_equal_the_loop_core(build, kinds):
    lk = build()
    assert [g.kind for g in lk.groups] == kinds
    against_loops(lk, SWEEP)
    against_loops(lk, SWEEP[::-1] * 2.0)  # backwards, two turns
    assert rigid_errors(lk, lk.solve(SWEEP)) < 1e-13


# ---------------------------------------------------------------------------- random chains
def random_chain(rng: np.random.Generator, n_dyads: int) -> Linkage:
    """A crank and a chain of RRR/RRP dyads, each pinned to a new point of a link already
    placed, drawn by choosing the pin first (so every dyad closes in the drawing)."""
    pts = {"O": 0j, "A": 1.5 + complex(*rng.uniform(-1, 1, 2))}
    ground = ["O"]
    links: dict[str, list[str]] = {"crank": ["O", "A"]}
    sliders = []
    for k in range(n_dyads):
        host = list(links)[rng.integers(len(links))]
        anchor, pin = f"H{k}", f"B{k}"
        pts[anchor] = pts[links[host][0]] + complex(*rng.uniform(-2, 2, 2))
        links[host].append(anchor)
        rod = 3.0 * np.exp(1j * rng.uniform(0, 2 * np.pi))
        pts[pin] = pts[anchor] + rod
        links[f"a{k}"] = [anchor, pin]
        turn = rng.uniform(0.6, 2.5) * rng.choice([-1, 1])  # well away from a toggle
        if rng.random() < 0.7:  # RRR to a new ground pivot
            piv = f"G{k}"
            pts[piv] = pts[pin] + rng.uniform(2.0, 4.0) * rod / abs(rod) * np.exp(1j * turn)
            ground.append(piv)
            links[f"b{k}"] = [piv, pin]
        else:  # RRP: a block on a ground line through the pin, within 52° of the rod
            links[f"blk{k}"] = [pin]
            sliders.append((f"blk{k}", pin, np.angle(rod) + turn / 3.0, f"s{k}"))
    lk = Linkage(pts).ground(*ground)
    for name, lpts in links.items():
        lk.link(name, *lpts, mass=1.0 + 0.1 * len(lpts), inertia=0.2, cg=0.3 + 0.1j)
    for block, pin, angle, name in sliders:
        lk.slider(block, "ground", pin, angle, name=name)
    return lk.drive("crank")


@pytest.mark.parametrize("seed", range(6))
def test_random_dyad_chains_close_match_finite_differences_and_balance_power(seed):
    rng = np.random.default_rng(seed)
    lk = random_chain(rng, 3)
    theta = lk.drawn_inputs["crank"] + np.radians(np.arange(0.0, 40.0, 0.01))
    omega = 2.0
    m = lk.solve(theta, velocity=omega, acceleration=0.0, jerk=0.0)
    ok = m.ok
    assert ok[0]
    assert rigid_errors(lk, m) < 1e-12
    dt = (theta[1] - theta[0]) / omega
    # where every dyad is well away from its toggle (the sine of the angle at its pin,
    # from the solved points): near one the derivatives blow up and differences fail
    good = ok.copy()
    for name in lk.links:
        if name.startswith("a"):  # a{k}: anchor -> pin B{k}; its partner b{k} or a block
            k = name[1:]
            u = m.points[f"B{k}"] - m.points[f"H{k}"]
            if f"b{k}" in lk.links:
                w = m.points[f"B{k}"] - m.points[f"G{k}"]
            else:
                w = 1j * next(j.direction for j in lk.joints if j.name == f"s{k}")
            sine = np.abs((np.conj(u) * w).imag) / (np.abs(u) * np.abs(w))
            good &= sine > 0.3
    both = good[1:-1] & good[2:] & good[:-2]
    assert both.sum() > 100
    for name in m.points:
        for lo, hi in (
            (m.points, m.point_velocity),
            (m.point_velocity, m.point_acceleration),
            (m.point_acceleration, m.point_jerk),
        ):
            fd = (lo[name][2:] - lo[name][:-2]) / (2 * dt)
            scale = max(np.nanmax(np.abs(hi[name][1:-1][both])), 1.0)
            assert np.nanmax(np.abs(fd - hi[name][1:-1])[both]) < 3e-4 * scale, name
    f = lk.forces(m, gravity=9.81)
    dke, dpe = _energy_rates(lk, m, 9.81)
    good = f.ok
    power = f.driver["crank"] * omega
    scale = np.abs(dke[good]).max() + np.abs(dpe[good]).max()
    assert np.abs(power - dke - dpe)[good].max() < 1e-9 * scale


# ---------------------------------------------------------------------------- flags
def triple_rocker() -> Linkage:
    """4-3-3-2.5: it assembles while cos(theta2) >= -0.21875 (|A - O4| <= 5.5 = 3 + 2.5)."""
    A = 3.0 * np.exp(1j * np.radians(60))
    B = circle_meet(A, 3.0, 4.0 + 0j, 2.5)
    lk = Linkage({"O2": 0j, "O4": 4.0 + 0j, "A": A, "B": B}).ground("O2", "O4")
    return lk.link("2", "O2", "A").link("3", "A", "B").link("4", "O4", "B").drive("2")


def test_a_sweep_through_a_toggle_flags_exactly_the_samples_past_it_naming_the_group():
    limit = np.degrees(np.arccos(-0.21875))  # written here: |A − O4|² = 25 − 24 cos θ2 = 5.5²
    theta_deg = np.arange(60.0, 150.0, 0.5)
    m = triple_rocker().solve(np.radians(theta_deg), velocity=1.0)
    past = theta_deg > limit
    assert (m.ok == ~past).all()
    assert np.isnan(m.points["B"][past]).all() and np.isfinite(m.points["B"][~past]).all()
    for r in m.reason[past]:
        assert r.startswith("cannot assemble: RRR dyad (3, 4)")
        assert f"[{-limit:.5g}°, {limit:.5g}°]" in r  # the range where it closes
    assert np.isfinite(m.theta["2"]).all()  # the crank itself is placed everywhere


def test_a_sample_at_the_toggle_is_singular_not_on_the_other_branch():
    lk = triple_rocker()
    limit = np.arccos(-0.21875)
    m = lk.solve([np.radians(60.0), limit - 1e-12, limit - 1e-3], velocity=1.0)
    assert m.ok.tolist() == [True, False, True]
    assert m.reason[1].startswith("singular Jacobian (toggle or dead point) of RRR dyad (3, 4)")
    assert np.isfinite(m.points["B"]).all() and np.isnan(m.omega["3"][1])


def watt_issue_17() -> Linkage:
    """The Watt six-bar of issue #17: four-bar O2-A-B-O4, rocker point C, dyad C-D-O6."""
    pts = {
        "O2": 0j,
        "O4": 1.556 - 0.241j,
        "A": 1.207 + 1.096j,
        "B": -0.472 - 1.807j,
        "C": -0.149 + 0.064j,
        "O6": 5.587 - 2.252j,
        "D": 3.466 - 0.775j,
    }
    lk = Linkage(pts).ground("O2", "O4", "O6")
    lk.link("2", "O2", "A").link("3", "A", "B").link("4", "O4", "B", "C")
    return lk.link("5", "C", "D").link("6", "O6", "D").drive("2")


@pytest.mark.parametrize("step", [1.0, 7.3])
def test_the_watt_six_bar_of_issue_17_never_has_an_ok_sample_on_the_other_side(step):
    lk = watt_issue_17()
    theta0 = lk.drawn_inputs["2"]
    theta = theta0 + np.radians(np.arange(0.0, 720.0, step))
    m = lk.solve(theta, velocity=1.0)
    P = lk.points

    def side(C, O6, D):  # the sign of (O6 − C) × (D − C), here in the test
        u, w = O6 - C, D - C
        return np.sign(u.real * w.imag - u.imag * w.real)

    drawn = side(P["C"], P["O6"], P["D"])
    got = side(m.points["C"][m.ok], P["O6"], m.points["D"][m.ok])
    assert m.ok.any() and (got == drawn).all()
    assert not m.ok.all()  # the output dyad has assembly gaps over two turns
    # after every gap each group reassembles on its drawn sign: samples solved one by one,
    # in a shuffled order, are the same
    rng = np.random.default_rng(17)
    order = rng.permutation(theta.size)
    alone = lk.solve(theta[order], velocity=1.0, continuation=False)
    assert (alone.ok == m.ok[order]).all()
    same = m.ok[order]
    assert np.abs(alone.points["D"][same] - m.points["D"][order][same]).max() < 1e-12


# ---------------------------------------------------------------------------- bad input
def test_more_drivers_than_freedoms_is_refused_naming_links_and_joints():
    lk = fourbar(1.0).drive("crank", "rocker")
    with pytest.raises(ModelError, match=r"link\(s\) coupler are over-constrained: pin A, pin B"):
        lk.solve(0.0)


def test_a_structure_is_refused_naming_links_and_joints():
    lk = Linkage({"O2": 0j, "O4": 4 + 0j, "A": 2 + 2j}).ground("O2", "O4")
    lk.link("a", "O2", "A").link("b", "A", "O4").drive("a")
    with pytest.raises(ModelError, match=r"structure; link\(s\) b are over-constrained"):
        lk.solve(0.0)


def test_a_floating_four_bar_is_refused_naming_its_links():
    """A driven lid beside a four-bar that nothing drives: the four-bar floats."""
    lk = fourbar(1.0)
    lk.point("G", -3 + 0j).point("L", -3 + 2j).ground("G").link("lid", "G", "L").drive("lid")
    with pytest.raises(ModelError, match=r"crank, coupler, rocker are not determined"):
        lk.solve(0.0)


def test_a_group_that_never_closes_says_so():
    """A rocker longer than the reach: the dyad closes at no crank angle but the drawn one's
    neighbourhood — draw it assembled, then sweep where it cannot be."""
    lk = triple_rocker()
    m = lk.solve(np.radians([170.0, 180.0]), continuation=False)
    assert not m.ok.any()
    assert all("it closes for 2 in" in r for r in m.reason)


def triad_with_a_dyad() -> Linkage:
    """A crank driving a triad (a ternary link T held by three binary links, to the crank pin
    and two ground pivots: an Assur group of class III, solved by the loop core), and an RRR
    dyad hung from T after it (closed form again)."""
    A = 1.5 * np.exp(1j * 0.5)
    P1, P2, P3 = 3.0 + 3.0j, 6.0 + 3.5j, 5.0 + 1.0j
    G2, G3 = 8.0 + 6.0j, 8.0 - 1.0j
    P4 = 5.5 + 4.5j
    Q = circle_meet(P4, 3.0, 9.0 + 3.0j, 2.5, 1.0)
    pts = {"O": 0j, "A": A, "P1": P1, "P2": P2, "P3": P3, "G2": G2, "G3": G3}
    pts |= {"P4": P4, "G4": 9.0 + 3.0j, "Q": Q}
    lk = Linkage(pts).ground("O", "G2", "G3", "G4").link("crank", "O", "A")
    lk.link("L1", "A", "P1").link("T", "P1", "P2", "P3", "P4")
    lk.link("L2", "G2", "P2").link("L3", "G3", "P3")
    return lk.link("M", "P4", "Q").link("N", "G4", "Q").drive("crank")


def test_a_triad_goes_to_the_loop_core_and_the_dyad_after_it_to_the_closed_form():
    lk = triad_with_a_dyad()
    assert [(g.kind, g.links) for g in lk.groups] == [
        ("driver", ("crank",)),
        ("general", ("L1", "T", "L2", "L3")),
        ("RRR", ("M", "N")),
    ]
    theta = lk.drawn_inputs["crank"] + np.radians(np.arange(-20.0, 20.0, 0.5))
    against_loops(lk, theta, tol=1e-9)
    m = lk.solve(theta, velocity=1.0, acceleration=0.0, jerk=0.0)
    assert m.ok.all() and rigid_errors(lk, m) < 1e-11
    assert np.isfinite(m.jerk["M"]).all()  # jerks through the loop core's group too


# ---------------------------------------------------------------------------- analyses on groups
def test_transmission_angles_of_an_rrr_and_an_rrp():
    from machdyn.fourbar import FourBar

    theta = np.radians(np.arange(0.0, 360.0, 15.0))
    mu = fourbar(1.0).transmission_angles(fourbar(1.0).solve(theta))
    np.testing.assert_allclose(
        mu["RRR dyad (coupler, rocker)"], FourBar(8, 4, 7, 6).solve(theta).mu
    )
    lk = offset_slider(1.0, False)
    m = lk.solve(theta)
    rod = m.points["B"] - m.points["A"]  # the slide is along x: μ = the rod's angle to the normal
    expected = np.arccos(np.abs(rod.imag) / np.abs(rod))
    np.testing.assert_allclose(lk.transmission_angles(m)["RRP dyad (rod, block)"], expected)


@pytest.mark.parametrize("build", [watt_ii, jansen_leg])
def test_a_flipped_group_is_the_other_assembly_and_flips_back(build):
    lk = build()
    for grp in lk.groups:
        if grp.sign == 0:
            continue
        other = lk.flipped(grp.name)
        again = other.flipped(grp.name)
        assert next(g for g in other.groups if g.name == grp.name).sign == -grp.sign
        for p, z in lk.points.items():
            assert abs(again.points[p] - z) < 1e-9, p
        # the flipped drawing assembles: its rigid distances are the original's
        m = other.solve(other.drawn_inputs[other.drivers[0]])
        assert rigid_errors(lk, m) < 1e-9


def test_flipping_a_group_with_one_assembly_is_refused():
    lk = watt_ii()
    with pytest.raises(ModelError, match="one assembly"):
        lk.flipped(lk.groups[0].name)
    with pytest.raises(ModelError, match="no group named"):
        lk.flipped("RRR dyad (x, y)")


def test_a_failing_compiled_kernel_hands_over_to_numpy_but_a_timeout_is_not_swallowed(
    backend, monkeypatch
):
    """The kernel failing warns once and NumPy answers (the reference); any other
    exception raised during the call (a signal's timeout, say) propagates."""
    from machdyn.linkage import kernel

    if backend != "compiled":
        pytest.skip("the hand-over is from the compiled kernel")
    lk = fourbar(1.0)
    ref = lk.solve(SWEEP, velocity=2.0)
    kern = kernel.compiled_kernel(SWEEP.size)

    class Timeout(Exception):
        pass

    def raising(exc):
        def run(*args):
            raise exc

        return run

    monkeypatch.setattr(kernel, "_failed", "")
    monkeypatch.setattr(kern, "run", raising(Timeout()))
    with pytest.raises(Timeout):
        fourbar(1.0).solve(SWEEP, velocity=2.0)
    assert kernel._failed == ""
    monkeypatch.setattr(kern, "run", raising(RuntimeError("broken")))
    with pytest.warns(RuntimeWarning, match="broken.*NumPy serves"):
        m = fourbar(1.0).solve(SWEEP, velocity=2.0)
    assert "broken" in kernel._failed
    np.testing.assert_allclose(m.points["B"], ref.points["B"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(m.omega["rocker"], ref.omega["rocker"], rtol=0, atol=1e-12)
