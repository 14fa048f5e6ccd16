"""Audit 2: bad input that used to give a silently wrong answer (or a foreign exception).

A motion solved for one model handed to another model's force analysis is the
commonest slip when comparing two designs side by side: ``fourbar_forces``
refused it, ``slidercrank_forces`` and ``Linkage.forces`` computed forces from
kinematics that are not the model's (or raised a bare ``KeyError``). Expected
answers here are the refusals: a machdyn ``InputError`` naming ``motion``.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import SliderCrank
from machdyn.dynamics import slidercrank_forces
from machdyn.errors import InputError
from machdyn.linkage import Linkage

PROPS = {"mass": (1.0, 1.0, 1.0), "inertia": (0.1, 0.1), "cg": (1.0, 1.0)}


def fourbar(r1=8.0):
    B = 7.625 + 1j * np.sqrt(35.859375) if r1 == 8.0 else None
    pts = {"O2": 0j, "O4": r1 + 0j, "A": 4 + 0j}
    if B is None:  # another four-bar with the same names: B by two circles at θ2 = 0
        d = r1 - 4.0
        x = (49 - 36 + d * d) / (2 * d)
        B = 4 + x + 1j * np.sqrt(49 - x * x)
    pts["B"] = B
    return (
        Linkage(pts)
        .ground("O2", "O4")
        .link("crank", "O2", "A", mass=1.0, inertia=0.1)
        .link("coupler", "A", "B", mass=1.0, inertia=0.1)
        .link("rocker", "O4", "B", mass=1.0, inertia=0.1)
        .drive("crank")
    )


def test_slidercrank_forces_refuse_the_motion_of_another_slidercrank():
    sc, other = SliderCrank(2.0, 6.0), SliderCrank(2.0, 7.0)
    th = np.radians([10.0, 20.0])
    slidercrank_forces(sc, sc.solve(th, 10.0), **PROPS)  # its own motion: fine
    with pytest.raises(InputError, match="motion"):
        slidercrank_forces(sc, other.solve(th, 10.0), **PROPS)
    with pytest.raises(InputError, match="motion"):  # the offset differs
        slidercrank_forces(sc, SliderCrank(2.0, 6.0, offset=0.5).solve(th, 10.0), **PROPS)


def test_linkage_forces_refuse_the_motion_of_another_linkage():
    lk = fourbar()
    lk.forces(lk.solve([0.0, 0.2], velocity=1.0))  # its own motion: fine
    # same names, another ground length: the kinematics are not this linkage's
    with pytest.raises(InputError, match="motion"):
        lk.forces(fourbar(9.0).solve([0.0, 0.2], velocity=1.0))
    # other names altogether (was a bare KeyError)
    sc = (
        Linkage({"O2": (0, 0), "A": (2, 0), "B": (8, 0)})
        .ground("O2")
        .link("crank", "O2", "A")
        .link("rod", "A", "B")
        .link("block", "B")
        .slider("block", "ground", "B", 0.0)
        .drive("crank")
    )
    with pytest.raises(InputError, match="motion"):
        lk.forces(sc.solve([0.0], velocity=1.0))


def test_linkage_centres_refuse_the_motion_of_another_linkage():
    """(was: the centres of the other drawing, I(ground, coupler) at (9, 0) for O4 at (8, 0))"""
    from machdyn.centres import linkage_centres

    lk = fourbar()
    assert linkage_centres(lk, lk.solve([0.0, 0.2], velocity=1.0)).valid.all()
    with pytest.raises(InputError, match="motion"):
        linkage_centres(lk, fourbar(9.0).solve([0.0, 0.2], velocity=1.0))


def test_transmission_angles_refuse_the_motion_of_another_linkage():
    lk = fourbar()
    lk.transmission_angles(lk.solve([0.0, 0.2], velocity=1.0))
    with pytest.raises(InputError, match="motion"):
        lk.transmission_angles(fourbar(9.0).solve([0.0, 0.2], velocity=1.0))


def test_flipped_linkage_with_a_curved_slot():
    """(was: TypeError from view.rebuilt: a curved guide has no direction to turn)

    The HW 6 four-bar plus an arm pivoted at O6 whose curved slot (centre C) holds a pin Q
    of the crank; flipping the RRR dyad (coupler, rocker) puts B at its mirror image in the
    line A → O4 and leaves the rest where it is drawn."""
    pts = {"O2": 0j, "O4": 8 + 0j, "A": 4 + 0j, "B": 7.625 + 1j * np.sqrt(35.859375)}
    pts |= {"Q": -1 + 0j, "O6": -3 + 3j, "C": -3 + 0.5j}
    lk = (
        Linkage(pts)
        .ground("O2", "O4", "O6")
        .link("crank", "O2", "A", "Q")
        .link("coupler", "A", "B")
        .link("rocker", "O4", "B")
        .link("arm", "O6", "C")
        .slot("Q", "crank", "arm", centre="C", name="arc")
        .drive("crank")
    )
    rrr = next(g for g in lk.groups if g.kind == "RRR")
    other = lk.flipped(rrr.name)
    A, O4, B = pts["A"], pts["O4"], pts["B"]
    u = (O4 - A) / abs(O4 - A)
    assert abs(other.points["B"] - (A + u * np.conj((B - A) / u))) < 1e-9
    for p in ("Q", "C", "O6", "A"):
        assert abs(other.points[p] - pts[p]) < 1e-12


@pytest.mark.parametrize("r1", [0.0, -8.0])
def test_freudenstein_ground_length_must_be_positive(r1):
    """(was: r1 = −8 returned the lengths (−8, −4, 7, −6); r1 = 0 an AssemblyError saying no
    four-bar generates the precision points — there is one, at any positive scale)"""
    from machdyn.synthesis.function import function_generator, lengths_from_freudenstein

    assert lengths_from_freudenstein([2.0, 4 / 3, 67 / 48], r1=8.0) == (8.0, 4.0, 7.0, 6.0)
    with pytest.raises(InputError, match="r1"):
        lengths_from_freudenstein([2.0, 4 / 3, 67 / 48], r1=r1)
    with pytest.raises(InputError, match="r1"):
        function_generator(
            np.log10, (1.0, 2.0), np.radians((45, 105)), np.radians((135, 225)), r1=r1
        )


def test_sprockets_and_chains_need_whole_teeth():
    """(was: 17.5 teeth gave a pitch diameter 2.8002 and a chain ratio 0.3431, silently)"""
    from machdyn.gears.trains import chain_ratio, sprocket_pitch_diameter

    # d = p / sin(180°/N): 1/2-in chain, 17 teeth (Norton, chain drives)
    assert sprocket_pitch_diameter(0.5, 17) == pytest.approx(0.5 / np.sin(np.pi / 17))
    assert chain_ratio(17, 51) == pytest.approx(1 / 3)
    with pytest.raises(InputError, match="teeth"):
        sprocket_pitch_diameter(0.5, 17.5)
    with pytest.raises(InputError, match="teeth"):
        chain_ratio(17.5, 51)
    with pytest.raises(InputError, match="teeth"):
        chain_ratio(17, [51, 50.5])
