"""Audit 3: a drawn linkage swept past its own circuit (found through the studio).

A Grashof four-bar whose coupler is the shortest link (r1, r2, r3, r4 = 60, 90,
30, 80: s + l = 120 < p + q = 140) driven at link 2: link 2 rocks, and the
cosine law ``|A − O4|² = r1² + r2² − 2 r1 r2 cos θ2`` with
``r4 − r3 ≤ |A − O4| ≤ r3 + r4`` gives two separate arcs of θ2,
[31.586°, 92.123°] and its mirror [−92.123°, −31.586°]. They are the two
circuits of the linkage: no motion takes the drawn one (θ2 = 60°) to the
other without taking it apart. ``FourBar.solve`` flags the mirror arc ("input
angle belongs to the other form (circuit) of this linkage"); the same linkage
drawn as a ``Linkage`` kept the dyad's assembly sign there and returned those
poses as ``ok`` — poses on another circuit passed off as the drawn mechanism's
motion (the studio plotted and animated them as valid, ``machdyn.tolerance`` and
``machdyn.sensitivity`` of the Linkage reported them). Fixed: a dyad placed
straight from the driver that closes on separate arcs of the driver angle is
flagged outside the drawn pose's arc.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import machdyn
from machdyn.linkage import Linkage

R = (60.0, 90.0, 30.0, 80.0)


def ends():
    r1, r2, r3, r4 = R
    return [
        math.degrees(math.acos((r1**2 + r2**2 - L**2) / (2 * r1 * r2))) for L in (r4 - r3, r3 + r4)
    ]


def drawn(theta_deg=60.0):
    r1, r2, r3, r4 = R
    A = r2 * np.exp(1j * math.radians(theta_deg))
    d = r1 - A
    L = abs(d)
    along = (r3**2 - r4**2 + L**2) / (2 * L)
    B = A + (along + 1j * math.sqrt(r3**2 - along**2)) * d / L
    return (
        Linkage({"O2": 0j, "O4": r1 + 0j, "A": A, "B": B})
        .ground("O2", "O4")
        .link("crank", "O2", "A")
        .link("coupler", "A", "B")
        .link("rocker", "O4", "B")
        .drive("crank")
    ), B


def test_inside_the_drawn_arc_the_linkage_is_the_two_circle_solution():
    lo, hi = ends()
    lk, _ = drawn()
    th = np.radians(np.linspace(lo + 0.5, hi - 0.5, 13))
    m = lk.solve(th)
    assert m.ok.all()
    r1, r2, r3, r4 = R
    A = r2 * np.exp(1j * th)
    d = r1 - A
    L = np.abs(d)
    along = (r3**2 - r4**2 + L**2) / (2 * L)
    B = A + (along + 1j * np.sqrt(r3**2 - along**2)) * d / L
    np.testing.assert_allclose(np.exp(1j * m.theta["rocker"]), (B - r1) / r4, atol=1e-12)
    fb = machdyn.FourBar(*R)
    assert fb.input_range(1).lo == pytest.approx(math.radians(lo), abs=1e-9)
    assert not fb.solve(np.radians([-60.0]), 1.0, 0.0, 1).ok.any()  # FourBar: other circuit


def test_a_drawn_linkage_flags_poses_on_its_other_circuit():
    lk, _ = drawn()
    th = np.radians([60.0, 80.0, 300.0, 320.0])
    m = lk.solve(th)
    assert m.ok.tolist() == [True, True, False, False]
    assert np.isnan(m.theta["rocker"][2:]).all()


def test_the_studio_does_not_show_the_other_circuit_as_the_motion():
    from machdyn.studio.analysis import analyse

    _, B = drawn()
    r1, r2 = R[0], R[1]
    A = r2 * np.exp(1j * math.radians(60.0))
    doc = {
        "machdyn": 1,
        "units": {"length": "mm", "angle": "deg"},
        "linkage": {
            "grrr": {
                "points": {
                    "O2": [0, 0],
                    "O4": [r1, 0],
                    "A": [A.real, A.imag],
                    "B": [B.real, B.imag],
                },
                "ground": ["O2", "O4"],
                "drive": ["crank"],
                "links": {
                    "crank": {"points": ["O2", "A"]},
                    "coupler": {"points": ["A", "B"]},
                    "rocker": {"points": ["O4", "B"]},
                },
            }
        },
    }
    out = analyse(doc, samples=360)
    lo, hi = ends()
    x = np.asarray(out["x"]) % 360.0
    mirror = (x > 360 - hi + 0.5) & (x < 360 - lo - 0.5)
    assert mirror.any()
    assert not np.asarray(out["ok"])[mirror].any()


def test_sensitivity_and_tolerance_of_the_drawn_linkage_refuse_the_other_circuit():
    from machdyn.errors import InputError

    lk, _ = drawn()
    th = np.radians([60.0, 80.0, 300.0, 320.0])
    s = machdyn.sensitivity(lk, th)
    assert s.ok.tolist() == [True, True, False, False]
    with pytest.raises(InputError) as info:
        machdyn.tolerance(lk, {"A-B": 0.01}, th, samples=100)
    assert info.value.field == "theta2" and "other circuit" in str(info.value)
    mc = machdyn.tolerance(lk, {"A-B": 0.01}, th[:2], samples=100)  # on its own arc: fine
    assert mc.failed == 0


def in_line_slider_crank(a: float, b: float, t0: float, driver: str) -> Linkage:
    """Crank ``a``, rod ``b``, block on a slide along x through O2, drawn at crank angle
    ``t0`` with the block right of the crank pin; driven at ``driver`` (crank or guide)."""
    A = a * np.exp(1j * t0)
    x = a * math.cos(t0) + math.sqrt(b * b - (a * math.sin(t0)) ** 2)
    return (
        Linkage({"O2": 0j, "A": A, "B": x + 0j})
        .ground("O2")
        .link("crank", "O2", "A")
        .link("rod", "A", "B")
        .link("block", "B")
        .slider("block", "ground", "B", 0.0, name="guide")
        .drive(driver)
    )


def test_a_slider_crank_with_a_long_crank_keeps_to_its_arc():
    # crank a = 2 longer than the rod b = 1 on a slide through O2: the rod reaches the slide
    # for |a sin θ| ≤ b, two arcs (around 0° and around 180°): the other one is the other
    # circuit. Drawn at θ = 10°.
    a, b = 2.0, 1.0
    lk = in_line_slider_crank(a, b, math.radians(10.0), "crank")
    edge = math.degrees(math.asin(b / a))  # 30°
    th = np.radians([0.0, 20.0, edge + 5, 180.0, 200.0])
    m = lk.solve(th)
    assert m.ok.tolist() == [True, True, False, False, False]
    assert "does not close" in m.reason[2] and "another circuit" in m.reason[3]
    np.testing.assert_allclose(
        m.points["B"][:2].real, a * np.cos(th[:2]) + np.sqrt(b * b - (a * np.sin(th[:2])) ** 2)
    )


def test_a_slider_driven_slider_crank_keeps_its_block_on_the_drawn_side():
    # driven at the block, d ∈ [b − a, a + b] = [0.15, 0.25] on the drawn side; at d = −0.2
    # the dyad closes again (the crank turned over, the block left of O2): the other circuit
    a, b = 0.05, 0.2
    lk = in_line_slider_crank(a, b, 1.2, "guide")
    d = np.array([0.2, 0.1, -0.2, 0.16, 0.249])
    m = lk.solve(d)
    assert m.ok.tolist() == [True, False, False, True, True]
    assert "another circuit" in m.reason[2] and "[0.15, 0.25]" in m.reason[2]
    # the crank angle from the cosine law on the drawn (upper) side
    ok = m.ok
    expect = np.arccos((a * a + d[ok] ** 2 - b * b) / (2 * a * d[ok]))
    got = np.exp(1j * m.theta["crank"][ok])  # angles run on along a sweep (not wrapped)
    np.testing.assert_allclose(got, np.exp(1j * expect), atol=1e-12)
