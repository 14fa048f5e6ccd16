"""The read-only topology view of a Linkage: complete enough to rebuild it exactly.

Each linkage below is rebuilt from its view alone (points, ground points, links,
joints, drivers, elements) by a rebuild written here from the builder's public
methods; the rebuilt linkage must have the same view and the same motion and
forces, which it could not if the view dropped a parameter.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.linkage import JOINT_KINDS, Joint, Linkage, Spring, TorsionSpring
from machdyn.massprops import MassProperties

# every test on the NumPy path and on the compiled kernels (tests/conftest.py)
pytestmark = pytest.mark.usefixtures("backend")


def rebuild(lk: Linkage) -> Linkage:
    out = Linkage(dict(lk.points))
    if lk.ground_points:
        out.ground(*lk.ground_points)
    for ln in lk.links.values():
        if ln.mass == 0:
            out.link(ln.name, *ln.points)
        elif ln.inertia == 0 or not isinstance(ln.cg, str | None):
            cg = 0j if ln.cg is None else ln.cg
            out.link(ln.name, *ln.points, body=MassProperties(ln.mass, cg, ln.inertia))
        else:
            out.link(ln.name, *ln.points, mass=ln.mass, inertia=ln.inertia, cg=ln.cg)
    for j in lk.joints:
        if j.kind == "slider":
            out.slider(
                j.links[0], j.links[1], j.points[0], j.direction, through=j.through, name=j.name
            )
        elif j.kind == "slot":
            out.slot(
                j.points[0], j.links[0], j.links[1], j.direction, through=j.through, name=j.name
            )
        elif j.kind == "actuator":
            out.actuator(j.name, *j.points, links=j.links)
        elif j.kind == "roll":
            out.roll(
                j.links[0],
                j.points[0],
                j.radii[0],
                j.links[1],
                j.points[1],
                j.radii[1],
                internal=j.internal,
                name=j.name,
            )
        elif j.kind == "motor":
            out.motor(j.name, j.points[0], links=j.links)
    out.drive(*lk.drivers)
    for e in lk.elements:
        if e.kind == "spring":
            out.spring(
                e.name,
                *e.points,
                stiffness=e.stiffness,
                free_length=e.free_length,
                damping=e.damping,
                preload=e.preload,
                links=e.links,
            )
        else:
            out.torsion_spring(
                e.name,
                e.points[0],
                stiffness=e.stiffness,
                free_angle=e.free_angle,
                damping=e.damping,
                preload=e.preload,
                links=e.links,
            )
    return out


def lid() -> Linkage:
    return (
        Linkage({"O2": (0, 0), "A": (3, 0), "S": (0, 4)})
        .ground("O2", "S")
        .link("lid", "O2", "A", mass=2.0, inertia=1.5, cg=(1.5, 0.2))
        .actuator("strut", "S", "A")
        .drive("lid")
        .spring("gas", "S", "A", stiffness=100.0, free_length=4.0, damping=3.0, preload=-5.0)
        .torsion_spring("coil", "O2", stiffness=2.0, free_angle=0.1, damping=0.5)
    )


def wheel_on_ground() -> Linkage:
    lk = Linkage({"T": (0, 0), "C": (0, 1), "W": (1, 1), "B": (2.0, 2.5), "O": (0, 2.5)})
    lk.ground("T", "O")
    lk.link("wheel", "C", "W", mass=1.0, inertia=0.5)
    lk.link("rod", "C", "B", mass=0.5, inertia=0.2, cg="B")
    lk.link("block", "B", body=MassProperties(0.3, 0j, 0.0))
    lk.slider("block", "ground", "B", 0.0, through="O", name="guide")
    lk.roll("wheel", "C", 1.0, "ground", "T", np.inf, name="tyre")
    return lk.drive("wheel")


def planetary() -> Linkage:
    r_s, r_p = 2.0, 1.0
    lk = Linkage({"O": (0, 0), "S": (r_s, 0), "Pc": (r_s + r_p, 0), "Q": (r_s + r_p, 1)})
    lk.ground("O").link("sun", "O", "S").link("arm", "O", "Pc").link("planet", "Pc", "Q")
    lk.roll("sun", "O", r_s, "planet", "Pc", r_p, name="sun/planet")
    lk.roll("planet", "Pc", r_p, "ground", "O", r_s + 2 * r_p, internal=True, name="ring")
    return lk.drive("sun")


def scotch_yoke() -> Linkage:
    return (
        Linkage({"O2": (0, 0), "A": (2, 0), "Y": (5, 0)})
        .ground("O2")
        .link("crank", "O2", "A")
        .link("yoke", "Y")
        .slider("yoke", "ground", "Y", 0.0, through="O2", name="guide")
        .slot("A", "crank", "yoke", np.pi / 2)
        .drive("crank")
    )


def elbow_fourbar() -> Linkage:
    return (
        Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0), "B": (7.625, 35.859375**0.5)})
        .ground("O2", "O4")
        .link("crank", "O2", "A")
        .link("coupler", "A", "B", mass=1.0, inertia=0.3, cg=3.5)
        .link("rocker", "O4", "B")
        .motor("elbow", "A")
        .drive("elbow")
    )


CASES = {
    "lid": (lid, [0.0, 0.3, 0.6]),
    "wheel": (wheel_on_ground, [0.0, 0.5, 1.0]),
    "planetary": (planetary, [0.0, 0.5, 1.0]),
    "scotch yoke": (scotch_yoke, [0.0, 0.5, 1.0]),
    "elbow": (elbow_fourbar, np.radians([58.81, 50.0, 40.0])),
}


@pytest.mark.parametrize("name", CASES)
def test_rebuilt_from_the_view_is_the_same_linkage(name):
    make, values = CASES[name]
    lk = make()
    again = rebuild(lk)
    assert again.points == lk.points
    assert again.ground_points == lk.ground_points
    assert again.links == lk.links
    assert again.joints == lk.joints
    assert again.drivers == lk.drivers
    assert again.elements == lk.elements
    m1, m2 = lk.solve(values, velocity=1.5), again.solve(values, velocity=1.5)
    assert m1.ok.all() and m2.ok.all()
    for k in m1.points:
        np.testing.assert_array_equal(m1.points[k], m2.points[k])
        np.testing.assert_array_equal(m1.point_acceleration[k], m2.point_acceleration[k])
    f1, f2 = lk.forces(m1, gravity=9.81), again.forces(m2, gravity=9.81)
    for k in f1.driver:
        np.testing.assert_array_equal(f1.driver[k], f2.driver[k])


def test_view_lists_every_joint_kind_with_its_parameters():
    kinds = set()
    for make, _ in CASES.values():
        kinds |= {j.kind for j in make().joints}
    assert kinds == set(JOINT_KINDS)
    wheel = wheel_on_ground()
    (guide,) = [j for j in wheel.joints if j.kind == "slider"]
    assert guide == Joint("slider", "guide", ("block", "ground"), ("B",), 1 + 0j, "O")
    (tyre,) = [j for j in wheel.joints if j.kind == "roll"]
    assert tyre.radii == (1.0, np.inf) and tyre.points == ("C", "T") and not tyre.internal
    (ring,) = [j for j in planetary().joints if j.name == "ring"]
    assert ring.internal and ring.links == ("planet", "ground")
    (elbow,) = [j for j in elbow_fourbar().joints if j.kind == "motor"]
    assert elbow.links == ("crank", "coupler")  # resolved: the carriers of A in order
    (strut,) = [j for j in lid().joints if j.kind == "actuator"]
    assert strut.links == ("ground", "lid") and strut.points == ("S", "A")
    pins = {j.name: j.links for j in wheel.joints if j.kind == "pin"}
    assert pins == {"pin C": ("wheel", "rod"), "pin B": ("rod", "block")}


def test_view_of_elements_and_links():
    lk = lid()
    gas, coil = lk.elements
    assert gas == Spring("gas", ("S", "A"), ("ground", "lid"), 100.0, 4.0, 3.0, -5.0)
    assert coil == TorsionSpring("coil", ("O2",), ("ground", "lid"), 2.0, 0.1, 0.5, 0.0)
    assert lk.links["lid"].cg == 1.5 + 0.2j
    assert wheel_on_ground().links["rod"].cg == "B"


def test_view_is_read_only():
    lk = lid()
    with pytest.raises(TypeError):
        lk.points["Z"] = 0j  # type: ignore[index]
    with pytest.raises(TypeError):
        lk.links["x"] = None  # type: ignore[index]
    old = lk.points
    lk.point("A", (3.0, 0.5))
    assert old["A"] == 3 + 0j and lk.points["A"] == 3 + 0.5j


@pytest.mark.parametrize("name", CASES)
def test_drawn_inputs_reproduce_the_drawing(name):
    lk = CASES[name][0]()
    m = lk.solve(dict(lk.drawn_inputs))
    assert m.ok.all()
    for p, z in lk.points.items():
        if p in m.points:
            assert abs(complex(m.points[p][()]) - z) < 1e-12 * max(1.0, abs(z)), p


def test_drawn_inputs_of_a_slider_are_measured_from_the_foot_of_through():
    lk = (
        Linkage({"O2": (0, 0), "A": (0, 2), "B": (6, 1), "T": (1, 1)})
        .ground("O2", "T")
        .link("crank", "O2", "A")
        .link("rod", "A", "B")
        .link("block", "B")
        .slider("block", "ground", "B", 0.0, through="T", name="guide")
        .drive("guide")
    )
    assert lk.drawn_inputs["guide"] == pytest.approx(5.0)  # B − T along +x
