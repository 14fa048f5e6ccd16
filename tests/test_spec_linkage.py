"""Linkage parts of machine files: round trips of every element, units, loads, old files."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from machdyn.linkage import Linkage
from machdyn.massprops import point_mass
from machdyn.spec import SpecError, dumps, from_spec, load_machine, read
from machdyn.spec._legacy import upgrade

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"


def view(lk: Linkage) -> tuple:
    """Everything the builder was given, as comparable values."""
    return (dict(lk.points), lk.ground_points, dict(lk.links), lk.joints, lk.drivers, lk.elements)


def slider_crank(a: float, b: float, angle: float, m: float) -> Linkage:
    pts = {"O2": (0, 0), "A": (a, 0), "B": (a + b, 0), "G": (a + b, 0.1)}
    return (
        Linkage(pts)
        .ground("O2", "G")
        .link("crank", "O2", "A", mass=m, inertia=m * a * a / 12, cg=a / 2)
        .link("rod", "A", "B", mass=2 * m, inertia=0.1, cg="B")
        .link("block", "B", body=point_mass(m))
        .slider("block", "ground", "B", angle, name="guide")
        .drive("crank")
        .spring("s", "G", "B", stiffness=100.0, free_length=0.05, damping=2.0, preload=-1.0)
    )


def arm(l1: float, l2: float) -> Linkage:
    return (
        Linkage({"O": 0, "E": complex(l1, 0), "H": complex(l1 + l2, 0)})
        .ground("O")
        .link("upper", "O", "E", mass=3.0, inertia=0.25, cg=l1 / 2)
        .link("fore", "E", "H", mass=1.5, inertia=0.08, cg=0.4 + 0.1j)
        .motor("elbow", "E", links=("upper", "fore"))
        .drive("upper", "elbow")
        .torsion_spring("wrist", "E", stiffness=3.0, free_angle=0.2, links=("upper", "fore"))
    )


def wheels(r2: float, r3: float) -> Linkage:
    d = r2 + r3
    return (
        Linkage({"O2": 0, "O3": complex(d, 0), "A": complex(0, r2), "R": complex(0, -1.0)})
        .ground("O2", "O3", "R")
        .link("w2", "O2", "A")
        .link("w3", "O3", "A")
        .roll("w2", "O2", r2, "w3", "O3", r3, name="mesh")
        .drive("w2")
    )


@given(
    a=st.floats(0.5, 2.0),
    b=st.floats(3.0, 8.0),
    angle=st.floats(-0.5, 0.5),
    m=st.floats(0.1, 5.0),
    unit=st.sampled_from([None, "m", "mm", "in"]),
)
def test_linkages_round_trip_through_spec_and_toml(a, b, angle, m, unit):
    from machdyn.units import UnitSystem

    for lk in (slider_crank(a, b, angle, m), arm(a, b), wheels(a, b)):
        lk.units = None if unit is None else UnitSystem(length=unit)
        spec = lk.to_spec("lk")
        back = from_spec(tomllib.loads(dumps(spec)))
        assert view(back) == view(lk)
        assert back.units == lk.units


def test_a_straight_rolling_profile_is_written_straight():
    lk = (
        Linkage({"O": 0, "C": 1j, "T": 0})
        .ground("T")
        .link("wheel", "C", "O")
        .roll("wheel", "C", 1.0, "ground", "T", math.inf, name="road")
        .slider("wheel", "ground", "C", 0.0, name="axle")
        .drive("axle")
    )
    spec = lk.to_spec("car")
    assert spec["linkage"]["car"]["rolls"]["road"]["radius_b"] == "straight"
    assert view(from_spec(tomllib.loads(dumps(spec)))) == view(lk)


# ------------------------------------------------------------------ the same lid, two unit systems
LID_SI = """machdyn = 1
gravity = "9.81 m/s^2"
[units]
length = "m"
[linkage.lid]
ground = ["O2", "S"]
drive = ["lid"]
report = ["A"]
[linkage.lid.points]
O2 = [0, 0]
A = [0.8, 0]
Q = [0.2, 0]
S = [0.15, -0.3]
[linkage.lid.links.lid]
points = ["O2", "A", "Q"]
mass = 4
shape = { rod = 0.8 }
[linkage.lid.springs.gas]
start = "S"
end = "Q"
stiffness = 500
free_length = 0.5
damping = 20
preload = -150
[linkage.lid.motion.lid]
sweep = [0, 90, 15]
velocity = 0.5
acceleration = 0.2
[[linkage.lid.forces]]
link = "lid"
at = "A"
force = [0, -20]
[linkage.lid.torques]
lid = 3
"""

LID_MM = """machdyn = 1
gravity = "9810 mm/s^2"
[units]
length = "mm"
mass = "g"
angle = "rad"
angular_velocity = "rpm"
torque = "N*mm"
[linkage.lid]
ground = ["O2", "S"]
drive = ["lid"]
report = ["A"]
[linkage.lid.points]
O2 = [0, 0]
A = [800, 0]
Q = ["0.2 m", 0]
S = [150, -300]
[linkage.lid.links.lid]
points = ["O2", "A", "Q"]
mass = "4 kg"
shape = { rod = "80 cm" }
[linkage.lid.springs.gas]
start = "S"
end = "Q"
stiffness = "0.5 N/mm"
free_length = 500
damping = "20 N*s/m"
preload = "-0.15 kN"
[linkage.lid.motion.lid]
sweep = ["0 deg", "90 deg", "15 deg"]
velocity = "0.5 rad/s"
acceleration = "0.2 rad/s^2"
[[linkage.lid.forces]]
link = "lid"
at = [800, 0]
force = ["0 N", "-20 N"]
[linkage.lid.torques]
lid = 3000
"""


def test_the_lid_in_si_and_in_mm_g_gives_the_same_forces(tmp_path):
    (tmp_path / "si.toml").write_text(LID_SI)
    (tmp_path / "mm.toml").write_text(LID_MM)
    si, mm = (load_machine(tmp_path / f"{n}.toml") for n in ("si", "mm"))
    rs, rm = si.run()["lid"], mm.run()["lid"]
    fs = rs.table("forces").labelled(si.units)
    fm = rm.table("forces").labelled(mm.units)
    np.testing.assert_allclose(fm["T_lid [N*mm]"] * 1e-3, fs["T_lid [N*m]"], rtol=1e-10)
    np.testing.assert_allclose(fm["T_gas [N]"], fs["T_gas [N]"], rtol=1e-10)
    ks = rs.table("kinematics").labelled(si.units)
    km = rm.table("kinematics").labelled(mm.units)
    np.testing.assert_allclose(km["omega_lid [rpm]"] * 2 * math.pi / 60, ks["omega_lid [rad/s]"])
    ps = rs.table("points").labelled(si.units)
    pm = rm.table("points").labelled(mm.units)
    np.testing.assert_allclose(pm["AA_y [mm/s^2]"] * 1e-3, ps["AA_y [m/s^2]"], rtol=1e-10)
    # and against the library called by hand (a rod: I_G = m L^2 / 12 about its middle)
    lk = (
        Linkage({"O2": 0, "A": 0.8, "Q": 0.2, "S": complex(0.15, -0.3)})
        .ground("O2", "S")
        .link("lid", "O2", "A", "Q", mass=4.0, inertia=4.0 * 0.8**2 / 12, cg=0.4)
        .drive("lid")
        .spring("gas", "S", "Q", stiffness=500.0, free_length=0.5, damping=20.0, preload=-150.0)
    )
    theta = np.radians(np.arange(0.0, 91.0, 15.0))
    m = lk.solve(theta, velocity=0.5, acceleration=0.2)
    f = lk.forces(
        m, gravity=9.81, external_forces=[("lid", "A", -20j)], external_torques={"lid": 3}
    )
    np.testing.assert_allclose(fs["T_lid [N*m]"], f.driver["lid"], rtol=1e-12)


# ------------------------------------------------------------------ errors and old files
@pytest.mark.parametrize(
    ("change", "needle"),
    [
        (("mass = 4\n", 'mass = "4 m"\n'), "[linkage.lid.links.lid] mass: expected a mass"),
        (("shape = { rod = 0.8 }", "shape = { rod = 0.8, disc = 1 }"), "give one shape"),
        (("shape = { rod = 0.8 }", "shape = { rod = 0.8 }\ninertia = 1"), "not both"),
        (('link = "lid"', 'link = "lud"'), "'lud' is not a link; links: lid"),
        (('at = "A"', 'at = "S"'), "'S' is not a point of it"),
        (("lid = 3\n", "lud = 3\n"), "[linkage.lid.torques] lud: 'lud' is not a link"),
        (("stiffness = 500", 'stiffness = "500 N"'), "expected a stiffness like '500 N/m'"),
        (("sweep = [0, 90, 15]", "sweep = 30"), "sweep: expected [start, stop, step]"),
        (("sweep = [0, 90, 15]", 'sweep = ["0 m", "1 m", "0.1 m"]'), "expected an angle"),
    ],
)
def test_bad_linkage_parts_name_the_key(tmp_path, change, needle):
    path = tmp_path / "lid.toml"
    path.write_text(LID_SI.replace(*change, 1))
    with pytest.raises(SpecError, match="^" + str(path).replace(".", r"\.") + r":\d+: ") as info:
        load_machine(path)
    assert needle in str(info.value)


def test_old_linkage_files_upgrade_to_the_same_machine():
    old = {
        "title": "t",
        "ground": ["O2"],
        "drive": ["crank"],
        "gravity": 9.81,
        "units": {"length": "m", "mass": "kg", "force": "N", "time": "s"},
        "points": {"O2": [0, 0], "A": [1, 0], "B": [3, 0]},
        "link": [
            {"name": "crank", "points": ["O2", "A"], "mass": 1.0, "inertia": 0.1},
            {"name": "rod", "points": ["A", "B"]},
            {"name": "block", "points": ["B"]},
        ],
        "slider": [{"block": "block", "on": "ground", "at": "B", "direction": 0.0}],
        "motion": {"crank": {"value": 30, "velocity": 2.0}},
    }
    new = upgrade(old)
    assert new["linkage"]["linkage"]["sliders"] == {
        "block/ground": {"block": "block", "on": "ground", "at": "B", "direction": 0.0}
    }
    machine = read(new)
    assert machine.gravity == 9.81 and machine["linkage"].joints[-1].name == "block/ground"
    result = machine.run()["linkage"].table("kinematics").labelled(machine.units)
    # slider-crank a = 1, b = 2 at 30 deg: x_B = a cos + sqrt(b^2 - a^2 sin^2)
    expected = math.cos(math.radians(30)) + math.sqrt(4 - math.sin(math.radians(30)) ** 2)
    assert result["d_block/ground [m]"][0] == pytest.approx(expected, rel=1e-12)


def test_the_examples_are_machine_files():
    for name in ("fourbar.toml", "lid.toml"):
        assert not load_machine(EXAMPLES / name).legacy


def test_a_reported_point_on_no_link_is_refused_at_its_key(tmp_path):
    path = tmp_path / "lid.toml"
    text = LID_SI.replace('report = ["A"]', 'report = ["A", "Z"]')
    path.write_text(text.replace("S = [0.15, -0.3]\n", "S = [0.15, -0.3]\nZ = [1, 1]\n"))
    with pytest.raises(SpecError, match=r":8: \[linkage\.lid\] report\[2\]: point 'Z' is on no"):
        load_machine(path)
