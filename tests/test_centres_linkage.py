"""Instant centres of any drawn linkage (machdyn.centres.linkage_centres).

Checks that share no code with the analysis:
* Kennedy's rule: the three centres of every triple of bodies are collinear;
* each centre is the point where the two bodies' velocities agree, computed here
  from the solved points' velocities (ω of a body from two of its points);
* the notes' worked numbers: the review exam's four-bar (R1 = 75, R2 = 150,
  R3 = R4 = 250 mm at θ2 = 15°: ω3 = 9.47, ω4 = 8.73 rad/s for ω2 = 5) through
  ω3 = R2 ω2 / d_A and ω4 = d_B R2 ω2 / (d_A R4) (review lecture 2, "FOURBAR INSTANT
  CENTERS"); Problem 6-13(a)'s inverted slider-crank, by hand.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np
import pytest

from closed_forms import circle_meet
from machdyn.centres import collinearity, instant_centres_of, linkage_centres
from machdyn.errors import ModelError
from machdyn.fourbar import FourBar
from machdyn.linkage import Linkage
from machdyn.slidercrank import InvertedSliderCrank


def six_bar_slider_on_ground(rng) -> Linkage:
    """Four-bar O2-A-B-O4 whose ternary coupler (A, B, C) drives a rod C-D and a
    block (D, D2) sliding on the ground along a random line through D."""
    A = rng.uniform(1.5, 2.5) * np.exp(1j * rng.uniform(0, 2 * np.pi))
    O4 = complex(rng.uniform(6, 9), rng.uniform(-1, 1))
    B = circle_meet(A, rng.uniform(6, 8), O4, rng.uniform(4, 6), 1.0)
    assert np.isfinite(B)
    C = A + (B - A) * complex(rng.uniform(0.2, 0.8), rng.uniform(0.3, 0.8))
    D = C + rng.uniform(4, 6) * np.exp(1j * rng.uniform(-0.6, 0.6))
    u = np.exp(1j * rng.uniform(-1.0, 1.0))
    pts = {"O2": 0j, "O4": O4, "A": A, "B": B, "C": C, "D": D, "D2": D + 0.7 * u}
    lk = Linkage(pts).ground("O2", "O4")
    lk.link("crank", "O2", "A").link("coupler", "A", "B", "C").link("rocker", "O4", "B")
    lk.link("rod", "C", "D").link("block", "D", "D2")
    return lk.slider("block", "ground", "D", "D2", name="guide").drive("crank")


def six_bar_slider_on_a_link(rng) -> Linkage:
    """Crank O2-A; a block (A, A2) on the crank pin slides along an arm pivoted at O4
    (the inverted slider-crank); the arm's point C drives a rod C-D and an output O6-D."""
    A = rng.uniform(1.5, 2.5) * np.exp(1j * rng.uniform(0, 2 * np.pi))
    O4 = complex(rng.uniform(4, 6), rng.uniform(-1, 1))
    along = (A - O4) / abs(A - O4)
    T = O4 + 1.5 * along
    C = O4 - rng.uniform(2, 3) * along * np.exp(1j * rng.uniform(-0.5, 0.5))
    O6 = C + complex(rng.uniform(3, 5), rng.uniform(-4, -2))
    D = circle_meet(C, rng.uniform(4, 6), O6, rng.uniform(3, 5), 1.0)
    assert np.isfinite(D)
    pts = {"O2": 0j, "O4": O4, "O6": O6, "A": A, "A2": A + 0.5 * along, "T": T, "C": C, "D": D}
    lk = Linkage(pts).ground("O2", "O4", "O6")
    lk.link("crank", "O2", "A").link("block", "A", "A2").link("arm", "O4", "T", "C")
    lk.link("rod", "C", "D").link("output", "O6", "D")
    lk.slider("block", "arm", "A", "T", through="O4", name="s")
    return lk.drive("crank")


def body_fields(lk, m):
    """(R, V, ω) of every body from two of its points (ω = Im(ΔV / ΔR))."""
    zero = np.zeros(m.ok.shape)
    out = {"ground": (zero + 0j, zero + 0j, zero)}
    for name, link in lk.links.items():
        p, q = link.points[:2]
        dr = m.points[q] - m.points[p]
        dv = m.point_velocity[q] - m.point_velocity[p]
        out[name] = (m.points[p], m.point_velocity[p], (dv / dr).imag)
    return out


def check_centres(lk, m, ics, tol=1e-7):
    ok = ics.valid
    assert ok.any()
    bodies = ["ground", *lk.links]
    assert len(ics) == len(bodies) * (len(bodies) - 1) // 2
    # Kennedy: every triple collinear
    for a, b, c in combinations(bodies, 3):
        res = collinearity(ics[a, b].homogeneous, ics[b, c].homogeneous, ics[a, c].homogeneous)
        assert np.max(np.abs(res[ok])) < tol, (a, b, c)
    # zero relative velocity, from the points' velocities (written here)
    fields = body_fields(lk, m)
    scale = max(abs(z) for z in lk.points.values())
    speed = max(np.nanmax(np.abs(v)) for v in m.point_velocity.values())
    for a, b in combinations(bodies, 2):
        (Ra, Va, wa), (Rb, Vb, wb) = fields[a], fields[b]
        # where the two bodies have no relative motion every point is a centre: skip
        moving = np.abs(wa - wb) * scale + np.abs(Vb + 1j * wb * (Ra - Rb) - Va) > 1e-9 * speed
        # V_a + j w_a (P - R_a) = V_b + j w_b (P - R_b)  =>  j (w_a - w_b) P = rhs
        rhs = Vb - Va + 1j * (wa * Ra - wb * Rb)
        # P = rhs / (j dw) = -j rhs / dw: homogeneous (-j rhs, dw), scaled by the drawing
        z = -1j * rhs
        h = np.stack([z.real / scale, z.imag / scale, wa - wb], axis=-1)
        h /= np.linalg.norm(h, axis=-1, keepdims=True)
        got = ics[a, b].homogeneous * np.array([1 / scale, 1 / scale, 1.0])
        got = got / np.linalg.norm(got, axis=-1, keepdims=True)
        err = np.minimum(np.linalg.norm(h - got, axis=-1), np.linalg.norm(h + got, axis=-1))
        assert np.max(err[ok & moving], initial=0.0) < tol, (a, b, float(np.max(err[ok])))


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("build", [six_bar_slider_on_ground, six_bar_slider_on_a_link])
def test_random_six_bars_with_sliders(build, seed):
    lk = build(np.random.default_rng(seed))
    drawn = float(np.angle(lk.points["A"]))
    theta = drawn + np.radians(np.linspace(-30, 30, 41))
    m = lk.solve(theta, velocity=1.7)
    ics = linkage_centres(lk, m)
    check_centres(lk, m, ics)
    # every centre of these six-bars follows from the joints by Kennedy's rule
    assert {ics.method(a, b) for a, b in ics} <= {"joint", "kennedy"}
    # flagged samples (if the sweep left the linkage's range) carry their reason
    assert all(r for r in ics.reason[~ics.valid])
    assert np.all(np.isnan(ics["ground", "rod"].homogeneous[~ics.valid]))


def test_slider_centre_is_at_infinity_normal_to_the_slide():
    lk = six_bar_slider_on_ground(np.random.default_rng(1))
    ics = instant_centres_of(lk, float(np.angle(lk.points["A"])))
    u = lk.points["D2"] - lk.points["D"]
    assert bool(ics["ground", "block"].at_infinity)
    d = complex(ics["ground", "block"].direction)
    assert abs((d * np.conj(u)).real) < 1e-12 * abs(u)  # normal to the slide


def test_review_exam_fourbar_angular_velocities_from_the_centres():
    # R1 = 75, R2 = 150, R3 = R4 = 250 mm, θ2 = 15°, the notes' θ3 = 128.25°, θ4 = 109.85°
    m = FourBar(75, 150, 250, 250).solve(np.radians(15), form=2)
    A, B = complex(m.A), complex(m.B)
    lk = Linkage({"O2": 0j, "O4": 75 + 0j, "A": A, "B": B}).ground("O2", "O4")
    lk.link("2", "O2", "A").link("3", "A", "B").link("4", "O4", "B").drive("2")
    ics = instant_centres_of(lk, np.radians(15))
    I13 = complex(ics["ground", "3"].point)
    d_A, d_B = abs(A - I13), abs(B - I13)
    # the notes: ω3 = R2 ω2 / d_A, ω4 = d_B R2 ω2 / (d_A R4), ω2 = 5 rad/s
    assert 150 * 5 / d_A == pytest.approx(9.47, abs=5e-3)
    assert d_B * 150 * 5 / (d_A * 250) == pytest.approx(8.73, abs=5e-3)
    assert abs(5 * float(ics.omega_ratio("2", "3"))) == pytest.approx(9.47, abs=5e-3)
    assert abs(5 * float(ics.omega_ratio("2", "4"))) == pytest.approx(8.73, abs=5e-3)


def test_problem_6_13a_inverted_slider_crank_by_hand_and_from_velocities():
    # crank 2, pivots 4 apart, θ2 = 90°: A = 2j; the slot points from O4 to A.
    # I13 (Kennedy: I12–I23 and I14–I34): x = 0 meets the normal to the slot through
    # O4, direction (2, 4) ⊥ (−4, 2): I13 = (0, −8). I24 (I12–I14 and I23–I34): the
    # ground line meets the normal through A: I24 = (−1, 0).
    isc = InvertedSliderCrank(2.0, 4.0)
    ics = isc.instant_centres(np.radians(90))
    assert complex(ics[1, 3].point) == pytest.approx(-8j, abs=1e-12)
    assert complex(ics[2, 4].point) == pytest.approx(-1 + 0j, abs=1e-12)
    assert bool(ics[3, 4].at_infinity)
    # ω4/ω2 = I12I24 / I14I24 = (−1 − 0) / (−1 − 4) = 1/5, and the closed form agrees
    assert float(ics.omega_ratio(2, 4)) == pytest.approx(0.2)
    theta2 = np.radians(np.arange(0, 360, 7.0))
    m = isc.solve(theta2, omega2=1.0)
    assert np.allclose(isc.instant_centres(theta2).omega_ratio(2, 4), m.omega4)


def test_inverted_slider_crank_as_a_linkage_agrees_with_the_closed_form():
    isc = InvertedSliderCrank(2.0, 5.0)
    A = 2.0 * np.exp(1j * np.radians(60))
    O4 = 5.0 + 0j
    along = (A - O4) / abs(A - O4)
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "A2": A + along, "T": O4 + 1.5 * along})
    lk.ground("O2", "O4").link("crank", "O2", "A").link("block", "A", "A2")
    lk.link("rocker", "O4", "T").slider("block", "rocker", "A", "T", through="O4")
    lk.drive("crank")
    theta2 = np.radians(np.arange(0, 360, 10.0))
    general = instant_centres_of(lk, theta2)
    closed = isc.instant_centres(theta2, form=2 if abs(A - O4) > 0 else 1)
    names = {1: "ground", 2: "crank", 3: "block", 4: "rocker"}
    for i, j in closed:
        a, b = general[names[i], names[j]], closed[i, j]
        fin = ~b.at_infinity
        assert np.allclose(a.point[fin], b.point[fin], atol=1e-9)
        assert np.all(a.at_infinity[~fin])


def scotch_yoke():
    lk = Linkage({"O2": 0j, "A": 2.0 + 0j, "Y": 5.0 + 0j, "Y2": 6.0 + 1j}).ground("O2")
    lk.link("crank", "O2", "A").link("yoke", "Y", "Y2")
    lk.slider("yoke", "ground", "Y", 0.0, through="O2", name="guide")
    return lk.slot("A", "crank", "yoke", np.pi / 2, name="slot").drive("crank")


def wheels():
    lk = Linkage({"O2": 0j, "O3": 5 + 0j, "P": 2 + 0j, "Q": 5 + 3j})
    lk.ground("O2", "O3").link("w2", "O2", "P").link("w3", "O3", "Q")
    return lk.roll("w2", "O2", 2.0, "w3", "O3", 3.0).drive("w2")


def wheel_on_ground():
    # crank O2-A, rod A-C to the centre C of a wheel (radius 1) rolling on y = 0
    lk = Linkage({"O2": 0j, "A": 1.5 + 0j, "C": 6 + 1j, "W": 6.5 + 1j, "T": 6 + 0j, "E": 0 + 0j})
    lk.ground("O2", "T").link("crank", "O2", "A").link("rod", "A", "C").link("wheel", "C", "W")
    return lk.roll("wheel", "C", 1.0, "ground", "T", np.inf, name="tyre").drive("crank")


def six_bar_with_a_roller():
    """Problem 6-13(c)/(d)'s kind: a four-bar whose rocker (O4, B, C) pushes a rod C-W to
    the centre W of a wheel (radius 1) rolling without slip on the ground line y = 0."""
    A, O4 = 2j, 7 + 0j
    B = circle_meet(A, 6.5, O4, 5.0, 1.0)
    C = O4 + 0.6 * (B - O4) * np.exp(-0.4j)
    W = complex(C.real + 5.0, 1.0)
    pts = {"O2": 0j, "O4": O4, "A": A, "B": B, "C": C, "W": W, "W2": W + 0.8, "T": W - 1j}
    lk = Linkage(pts).ground("O2", "O4", "T")
    lk.link("crank", "O2", "A").link("coupler", "A", "B").link("rocker", "O4", "B", "C")
    lk.link("rod", "C", "W").link("wheel", "W", "W2")
    return lk.roll("wheel", "W", 1.0, "ground", "T", np.inf, name="tyre").drive("crank")


def planet():
    lk = Linkage({"O": 0j, "C": 3 + 0j, "W": 3 + 0.5j, "K": 1 + 0j}).ground("O")
    lk.link("arm", "O", "C").link("wheel", "C", "W")
    return lk.roll("wheel", "C", 1.0, "ground", "O", 4.0, internal=True).drive("arm")


def loader():
    """Second notes' loader driven by its cylinder C–E (a linear actuator)."""
    A = 141.0 * np.exp(1j * np.radians(45))
    B = A + 120.0
    pts = {"O2": 0j, "A": A, "B": B, "O4": B - 100j, "P": A + 200.0 * np.exp(1j * np.radians(135))}
    pts |= {"C": 290.0 - 10.0j, "E": A + 50.0 * np.exp(1j * np.radians(-20))}
    lk = Linkage(pts).ground("O2", "O4", "C")
    lk.link("arm", "O2", "A").link("3", "A", "B", "P", "E").link("4", "B", "O4")
    return lk.actuator("cylinder", "C", "E").drive("cylinder")


@pytest.mark.parametrize(
    ("build", "values"),
    [
        (scotch_yoke, np.radians(np.arange(5, 360, 10.0))),
        (wheels, np.radians(np.arange(0, 360, 30.0))),
        (wheel_on_ground, np.radians(np.arange(-40, 41, 10.0))),
        (planet, np.radians(np.arange(0, 360, 30.0))),
        (six_bar_with_a_roller, np.radians(np.arange(70, 111, 5.0))),
        (loader, None),
    ],
)
def test_slots_rolling_contacts_and_actuators(build, values):
    lk = build()
    if values is None:  # the cylinder's drawn length ± 10 %
        length = abs(lk.points["E"] - lk.points["C"])
        values = length * np.linspace(0.9, 1.1, 9)
    m = lk.solve(values, velocity=1.3)
    ics = linkage_centres(lk, m)
    check_centres(lk, m, ics)
    assert not any("barrel" in str(pair) for pair in ics)  # the actuator's bodies stay inside
    if build is six_bar_with_a_roller:  # 15 centres: 7 by inspection, 8 by Kennedy's rule
        methods = [ics.method(a, b) for a, b in ics]
        assert (len(methods), methods.count("joint"), methods.count("kennedy")) == (15, 7, 8)


def test_rolling_contact_centre_is_the_contact_point():
    ics = instant_centres_of(wheels(), np.radians(40))
    assert ics.method("w2", "w3") == "joint"
    assert complex(ics["w2", "w3"].point) == pytest.approx(2 + 0j)
    ics = instant_centres_of(wheel_on_ground(), 0.2)
    wheel_centre = complex(wheel_on_ground().solve(0.2).points["C"])
    assert complex(ics["ground", "wheel"].point) == pytest.approx(wheel_centre.real + 0j)


def test_unassemblable_samples_are_flagged_never_nan_without_a_reason():
    # a crank-rocker drawn as a Linkage but the crank made too long for a full turn
    O4, A = 8 + 0j, 5 + 0j
    B = circle_meet(A, 7.0, O4, 6.0)
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "B": B}).ground("O2", "O4")
    lk.link("2", "O2", "A").link("3", "A", "B").link("4", "O4", "B").drive("2")
    ics = instant_centres_of(lk, np.radians(np.arange(0, 360, 5.0)))
    assert (~ics.valid).any() and ics.valid.any()
    for pair in ics:
        nan = ~np.all(np.isfinite(ics[pair].homogeneous), axis=-1)
        assert not np.any(nan & ics.valid)
        assert all(r for r in ics.reason[nan])


def test_translating_coupler_has_its_centre_at_infinity():
    # a parallelogram: the coupler translates, so I(ground, coupler) is a direction
    lk = Linkage({"O2": 0j, "O4": 4 + 0j, "A": 2j, "B": 4 + 2j}).ground("O2", "O4")
    lk.link("2", "O2", "A").link("3", "A", "B").link("4", "O4", "B").drive("2")
    ics = instant_centres_of(lk, np.radians([90.0, 120.0]))
    assert ics.valid.all()
    assert np.all(ics["ground", "3"].at_infinity)


def five_bar():
    pts = {"O2": 0j, "O5": 6 + 0j, "A": 2j, "B": 3 + 5j, "C": 6 + 2j}
    lk = Linkage(pts).ground("O2", "O5").link("2", "O2", "A").link("3", "A", "B")
    return lk.link("4", "B", "C").link("5", "O5", "C").drive("2", "5")


def test_a_centre_of_links_without_relative_motion_is_flagged_with_its_reason():
    # both cranks of a five-bar at rest: Kennedy's rule cannot place I(ground, 3),
    # and the velocity field has no relative motion to place it by
    at_rest = {"2": 0.0, "5": 0.0}
    ics = instant_centres_of(five_bar(), {"2": np.pi / 2, "5": np.pi / 2}, velocity=at_rest)
    assert not ics.valid.any()
    assert "no relative motion" in str(ics.reason)
    assert np.all(np.isnan(ics["ground", "3"].homogeneous))


def test_two_drivers_need_their_speeds_only_when_kennedy_cannot_decide():
    # a five-bar (two cranks): I(ground, coupler links) depend on the speed ratio
    lk = five_bar()
    with pytest.raises(ModelError, match="velocity"):
        instant_centres_of(lk, {"2": np.pi / 2, "5": np.pi / 2})
    ics = instant_centres_of(lk, {"2": np.pi / 2, "5": np.pi / 2}, velocity={"2": 1.0, "5": -0.5})
    m = lk.solve({"2": np.pi / 2, "5": np.pi / 2}, velocity={"2": 1.0, "5": -0.5})
    check_centres(lk, m, ics)
    assert ics.method("ground", "3") == "velocity"


def test_mechanical_advantage_between_any_two_links():
    lk = six_bar_slider_on_ground(np.random.default_rng(4))
    theta = float(np.angle(lk.points["A"])) + np.radians([-5.0, 0.0, 5.0])
    ics = instant_centres_of(lk, theta)
    m = lk.solve(theta, velocity=1.0)
    # rotating output: MA = (r_in/r_out) ω_in/ω_out (power identity, ω from the solve)
    ma = ics.mechanical_advantage("crank", "rocker", r_in=1.0, r_out=2.0)
    assert np.allclose(ma, 0.5 / m.omega["rocker"])
    # translating output (the block): MA = r_in ω_in / |v_block|
    ma = ics.mechanical_advantage("crank", "block", r_in=1.5)
    assert np.allclose(ma, 1.5 / np.abs(m.point_velocity["D"]))
