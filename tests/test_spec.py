"""Machine files (machdyn.spec): units, errors with lines, round trips, the four-bar kinds."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import machdyn
from machdyn import units as u
from machdyn.fourbar import FourBar
from machdyn.slidercrank import InvertedSliderCrank, SliderCrank
from machdyn.spec import SpecError, dumps, from_spec, load, load_machine, read
from machdyn.spec._lines import KeyLines

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
IN = 0.0254  # m per inch, exactly (written out here, not taken from pint)
G0 = 9.80665  # m/s^2


def doc(**parts) -> dict:
    return {"machdyn": 1, **parts}


def write(tmp_path: Path, text: str, name: str = "m.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


# ------------------------------------------------------------------ units
def test_unit_kinds_are_checked_and_hz_is_not_a_turning_speed():
    u.check_unit("rpm", "angular_velocity")
    u.check_unit("N*m/rad", "torsional_stiffness")
    u.check_unit("N*m", "torsional_stiffness")  # per radian understood
    for unit, kind in (("m", "mass"), ("Hz", "angular_velocity"), ("deg", "length")):
        with pytest.raises(ValueError, match="expected"):
            u.check_unit(unit, kind)
    with pytest.raises(ValueError, match="unknown unit"):
        u.check_unit("furlongz", "length")


def test_unit_system_converts_coherent_results_to_output_units():
    mm = u.UnitSystem(length="mm", mass="g", time="s", force="N", angular_velocity="rpm")
    # a force held in g*mm/s^2 is 1e-6 N; a torque in g*mm^2/s^2 is 1e-9 N*m = 1e-6 N*mm
    assert mm.factor("force") == pytest.approx(1e-6, rel=1e-15)
    assert mm.display("torque") == "N*mm"
    assert mm.factor("torque") == pytest.approx(1e-6, rel=1e-15)
    assert mm.factor("angular_velocity") == pytest.approx(60 / (2 * math.pi), rel=1e-15)
    assert mm.label("omega3", "angular_velocity") == "omega3 [rpm]"


# ------------------------------------------------------------------ lines of keys
def test_key_lines_follow_tables_arrays_and_multiline_values():
    text = """machdyn = 1  # a comment with = and [brackets]
title = '''a
[fake.header]
text'''
[linkage."my lid".points]
O2 = [
  0,
  0,
]
A = [1, 0]
[[cam.c.segment]]
motion = "rise"
[[cam.c.segment]]
"beta" = 60
"""
    lines = KeyLines(text)
    assert lines.line(("title",)) == 2
    assert lines.line(("fake", "header")) is None
    assert lines.line(("linkage", "my lid", "points", "A")) == 10
    assert lines.line(("linkage", "my lid", "points", "O2", 2)) == 6
    assert lines.line(("cam", "c", "segment", 1, "motion")) == 12
    assert lines.line(("cam", "c", "segment", 2, "beta")) == 14
    assert tomllib.loads(text)["cam"]["c"]["segment"][1]["beta"] == 60


# ------------------------------------------------------------------ errors
BASE = """machdyn = 1
[units]
length = "mm"
mass = "kg"

[fourbar.a]
r1 = 80
r2 = 40
r3 = 70
r4 = 60
"""


@pytest.mark.parametrize(
    ("change", "line", "needle"),
    [
        (
            ("r2 = 40", 'r2 = "4 kg"'),
            8,
            "[fourbar.a] r2: expected a length like '120 mm', got '4 kg'",
        ),
        (("r2 = 40", 'r2 = "4 furlongz"'), 8, "unknown unit 'furlongz'"),
        (("r2 = 40", "r2 = nan"), 8, "[fourbar.a] r2: must be finite"),
        (("r2 = 40", "r2 = inf"), 8, "[fourbar.a] r2: must be finite"),
        (("r2 = 40", "r2 = 1e200"), 8, "too large"),
        (("r2 = 40", "r2 = -4"), 8, "[fourbar.a] r2: must be positive"),
        (("r2 = 40", 'r2 = "40"'), 8, None),  # a number in quotes is still a number
        (("r2 = 40", "r2 = [4]"), 8, "got an array"),
        (("r2 = 40", "r2 = true"), 8, "got a boolean"),
        (("r4 = 60", "r4 = 60\nr5 = 1"), 11, "[fourbar.a] r5: unknown key; valid keys: r1, r2"),
        (("r2 = 40\n", ""), 6, "[fourbar.a] r2: missing: required (a length)"),
        (("machdyn = 1", "machdyn = 2"), 1, "machdyn: this file is format 2; this machdyn reads 1"),
        (("machdyn = 1", 'machdyn = "1"'), 1, "machdyn: this file is format '1'"),
        (('length = "mm"', 'length = "kg"'), 3, "[units] length: expected a length"),
        (('mass = "kg"', 'mass = "kg"\nspeed = "rpm"'), 5, "[units] speed: unknown key"),
        (("r1 = 80", "r1 = 300"), 6, "[fourbar.a]: "),  # cannot be assembled
        (("[fourbar.a]", "[fourbar]\nx = 1\n[fourbar.a]"), 7, "[fourbar.x] x"),
        (("[fourbar.a]", '[fourbar."Kurbelschwinge ü"]'), None, None),  # unicode names are fine
    ],
)
def test_bad_files_get_one_line_naming_line_key_and_remedy(tmp_path, change, line, needle):
    path = write(tmp_path, BASE.replace(*change, 1))
    if needle is None:
        assert isinstance(load(path), FourBar)
        return
    needle = needle.replace("reads 1", "reads format 1")
    with pytest.raises(SpecError) as info:
        load(path)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"{path}:{line}: " if line else str(path)), message
    assert needle.replace("[fourbar.x] x", "") in message, message


def test_duplicate_part_names_across_kinds_are_refused():
    spec = doc(
        fourbar={"a": {"r1": 8, "r2": 4, "r3": 7, "r4": 6}},
        slider_crank={"a": {"crank": 2, "coupler": 6}},
    )
    with pytest.raises(SpecError, match=r"\[slider_crank\.a\]: the name 'a' is already a fourbar"):
        from_spec(spec)


def test_bare_numbers_in_a_file_whose_numbers_carry_units_are_refused():
    spec = doc(fourbar={"a": {"r1": "8 mm", "r2": "4 mm", "r3": 7, "r4": "6 mm"}})
    with pytest.raises(SpecError, match=r"r3: a bare number \(7\) in a file whose numbers carry"):
        from_spec(spec)
    fb = from_spec(doc(fourbar={"a": {"r1": "8 mm", "r2": "4 mm", "r3": "0.7 cm", "r4": "6 mm"}}))
    assert fb.lengths == (8.0, 4.0, 7.0, 6.0) and fb.units.length == "mm"  # the first unit met


@pytest.mark.parametrize(
    ("units", "gravity", "expected"),
    [
        ({"length": "mm"}, True, G0 * 1000),
        ({"length": "in"}, 386.09, 386.09),
        ({"length": "m"}, "1.62 m/s^2", 1.62),  # the Moon: a value with its unit is taken
        ({"length": "mm"}, 9.81, "0.001 times standard gravity"),
        (None, True, "standard gravity needs units"),
        ({"length": "m"}, -9.81, "must be >= 0"),
    ],
)
def test_gravity_defaults_only_with_a_unit_system(units, gravity, expected):
    spec = doc(gravity=gravity, fourbar={"a": {"r1": 8, "r2": 4, "r3": 7, "r4": 6}})
    if units is not None:
        spec["units"] = units
    if isinstance(expected, str):
        with pytest.raises(SpecError, match=expected):
            from_spec(spec)
    else:
        assert read(spec).gravity == pytest.approx(expected, rel=1e-12)


# ------------------------------------------------------------------ the HW 6 example
def test_hw6_example_runs_as_the_python_api_computes_it():
    machine = load_machine(EXAMPLES / "hw6.toml")
    result = machine.run()["hw6"]
    # the same linkage built by hand: lengths in inches, forces in lbf, masses in blobs
    fb = FourBar(8, 4, 7, 6, coupler=(5.0, math.radians(30.0)))
    theta2 = np.radians(np.arange(0.0, 361.0, 30.0))
    m = fb.solve(theta2, omega2=10.0)
    f = fb.dynamics(
        theta2,
        10.0,
        mass=(0.002, 0.004, 0.003),
        inertia=(0.003, 0.02, 0.01),
        cg=(2.0, 3.5 + 1.0j, 3.0),
        gravity=G0 / IN,  # standard gravity in in/s^2
        load_torque4=-5.0,
    )
    kin = result.table("kinematics").labelled(machine.units)
    np.testing.assert_allclose(kin["theta3 [deg]"], np.degrees(m.theta3), rtol=1e-13)
    np.testing.assert_allclose(kin["omega4 [rad/s]"], m.omega4, rtol=1e-12, atol=1e-12)
    assert kin["theta3 [deg]"][0] == pytest.approx(58.8114, abs=5e-5)  # the notes, HW 6
    forces = result.table("forces").labelled(machine.units)
    np.testing.assert_allclose(forces["T12 [lbf*in]"], f.T12, rtol=1e-9)
    np.testing.assert_allclose(forces["F32_y [lbf]"], f.F32.imag, rtol=1e-9, atol=1e-12)
    coupler = result.table("coupler").labelled(machine.units)
    np.testing.assert_allclose(coupler["P_x [in]"], m.coupler.real, rtol=1e-12)


# ------------------------------------------------------------------ same machine, two unit systems
def _mm_and_si(si: dict, mm: dict) -> tuple:
    """The same machine with SI units, and with mm, g, deg and rpm (and gravity as in si)."""
    a = read(doc(units={"length": "m", "mass": "kg", "time": "s", "angle": "rad"}, **si))
    units = {"length": "mm", "mass": "g", "angle": "deg", "angular_velocity": "rpm"}
    b = read(doc(units=units, **({"gravity": True} if "gravity" in si else {}), **mm))
    return a, b


def test_fourbar_in_si_and_in_mm_g_deg_rpm_gives_the_same_forces():
    links = lambda m, i, c: {"mass": m, "inertia": i, "cg": c}  # noqa: E731
    si = {
        "gravity": True,
        "fourbar": {
            "f": {
                "r1": 0.2,
                "r2": 0.05,
                "r3": 0.18,
                "r4": 0.12,
                "coupler": {"p": 0.1, "delta": 0.5},
                "motion": {"theta2": [0, 6, 0.5], "omega2": 2 * math.pi, "alpha2": 3.0},
                "link2": links(0.5, 1e-4, [0.025, 0]),
                "link3": links(1.2, 4e-3, [0.09, 0.01]),
                "link4": links(0.8, 1e-3, 0.06),
                "loads": {"torque4": -2.0, "force": [{"link": 3, "at": [0.1, 0], "force": [5, 1]}]},
            }
        },
    }
    mm = {
        "fourbar": {
            "f": {
                "r1": 200,
                "r2": 50,
                "r3": "18 cm",
                "r4": 120,
                "coupler": {"p": 100, "delta": "0.5 rad"},
                "motion": {"theta2": ["0 rad", "6 rad", "0.5 rad"], "omega2": 60, "alpha2": 3},
                "link2": links(500, "1e-4 kg*m^2", [25, 0]),
                "link3": links("1.2 kg", 4e6, [90, 10]),  # g*mm^2
                "link4": links(800, 1e6, 60),
                "loads": {
                    "torque4": "-2 N*m",
                    "force": [{"link": 3, "at": [100, 0], "force": ["5 N", "1 N"]}],
                },
            }
        },
    }
    a, b = _mm_and_si(si, mm)
    ra, rb = a.run()["f"], b.run()["f"]
    fa = ra.table("forces").labelled(a.units)
    fb_ = rb.table("forces").labelled(b.units)
    # output units: N*m in the SI file, N*mm in the other; 1 N*mm = 1e-3 N*m
    np.testing.assert_allclose(fb_["T12 [N*mm]"] * 1e-3, fa["T12 [N*m]"], rtol=1e-10)
    np.testing.assert_allclose(fb_["F43_x [N]"], fa["F43_x [N]"], rtol=1e-10, atol=1e-12)
    ka = ra.table("kinematics").labelled(a.units)
    kb = rb.table("kinematics").labelled(b.units)
    np.testing.assert_allclose(np.radians(kb["theta4 [deg]"]), ka["theta4 [rad]"], rtol=1e-12)
    np.testing.assert_allclose(
        kb["omega3 [rpm]"] * 2 * math.pi / 60, ka["omega3 [rad/s]"], rtol=1e-12
    )
    pa = ra.table("coupler").labelled(a.units)
    pb = rb.table("coupler").labelled(b.units)
    np.testing.assert_allclose(pb["AP_y [mm/s^2]"] * 1e-3, pa["AP_y [m/s^2]"], rtol=1e-10)


def test_slider_cranks_in_si_and_in_mm_give_the_same_motion_and_forces():
    si = {
        "slider_crank": {
            "s": {
                "crank": 0.05,
                "coupler": 0.2,
                "offset": 0.01,
                "motion": {"omega2": 100.0},
                "link2": {"mass": 1.0, "inertia": 1e-3, "cg": 0.02},
                "link3": {"mass": 2.0, "inertia": 8e-3, "cg": 0.1},
                "link4": {"mass": 1.5},
                "loads": {"force4": -300.0, "friction": "coulomb", "mu": 0.1},
            }
        },
        "inverted_slider_crank": {"i": {"crank": 0.05, "ground": 0.2}},
    }
    mm = {
        "slider_crank": {
            "s": {
                "crank": 50,
                "coupler": 200,
                "offset": 10,
                "motion": {"omega2": "100 rad/s"},
                "link2": {"mass": 1000, "inertia": "1e-3 kg*m^2", "cg": 20},
                "link3": {"mass": 2000, "inertia": "8e-3 kg*m^2", "cg": 100},
                "link4": {"mass": 1500},
                "loads": {"force4": "-300 N", "friction": "coulomb", "mu": 0.1},
            }
        },
        "inverted_slider_crank": {"i": {"crank": 50, "ground": 200}},
    }
    a, b = _mm_and_si(si, mm)
    ra, rb = a.run(), b.run()
    fa = ra["s"].table("forces").labelled(a.units)
    fb_ = rb["s"].table("forces").labelled(b.units)
    np.testing.assert_allclose(fb_["T12 [N*mm]"] * 1e-3, fa["T12 [N*m]"], rtol=1e-10)
    ka = ra["s"].table("kinematics").labelled(a.units)
    kb = rb["s"].table("kinematics").labelled(b.units)
    np.testing.assert_allclose(kb["d_ddot [mm/s^2]"] * 1e-3, ka["d_ddot [m/s^2]"], rtol=1e-10)
    ia = ra["i"].table("kinematics").labelled(a.units)
    ib = rb["i"].table("kinematics").labelled(b.units)
    np.testing.assert_allclose(ib["b [mm]"] * 1e-3, ia["b [m]"], rtol=1e-12)
    # the SI file's forces against the library called by hand (mm file gravity: standard)
    sc = SliderCrank(0.05, 0.2, 0.01)
    theta2 = np.radians(np.arange(0.0, 361.0, 10.0))
    f = sc.dynamics(
        theta2,
        100.0,
        mass=(1.0, 2.0, 1.5),
        inertia=(1e-3, 8e-3),
        cg=(0.02, 0.1),
        load_force4=-300.0,
        friction="coulomb",
        mu=0.1,
    )
    np.testing.assert_allclose(fa["T12 [N*m]"], f.T12, rtol=1e-12)
    assert isinstance(a["i"], InvertedSliderCrank)


# ------------------------------------------------------------------ round trips
lengths = st.floats(0.01, 100.0, allow_nan=False)
angles = st.floats(-3.0, 3.0, allow_nan=False)
systems = st.sampled_from(
    [
        None,
        u.UnitSystem(length="mm", mass="kg", time="s"),
        u.UnitSystem(length="in", mass="lbf*s^2/in", time="s", force="lbf", angle="rad"),
        u.UnitSystem(length="m", mass="g", time="min", angular_velocity="rpm"),
    ]
)


@given(r=st.tuples(lengths, lengths, lengths, lengths), p=lengths, delta=angles, system=systems)
def test_fourbar_round_trips_through_its_spec_and_toml(r, p, delta, system):
    try:
        fb = FourBar(*r, coupler=(p, delta))
    except machdyn.MachdynError:
        return
    fb.units = system
    spec = fb.to_spec("hw")
    for back in (from_spec(spec), from_spec(tomllib.loads(dumps(spec)))):
        assert back.lengths == fb.lengths and back.coupler == fb.coupler
        assert back.units == system


@given(a=lengths, b=lengths, c=st.floats(-1.0, 1.0), point=st.none() | st.tuples(lengths, angles))
def test_slider_cranks_round_trip(a, b, c, point):
    try:
        sc = SliderCrank(a, b, c * (a + b) * 0.99, point=point)
        isc = InvertedSliderCrank(a, b, c * a)
    except machdyn.MachdynError:
        return
    back = from_spec(tomllib.loads(dumps(sc.to_spec())))
    assert (back.a, back.b, back.c, back.point) == (sc.a, sc.b, sc.c, sc.point)
    back = from_spec(isc.to_spec())
    assert (back.a, back.d, back.c) == (isc.a, isc.d, isc.c)


def test_machine_round_trips_with_its_settings():
    machine = load_machine(EXAMPLES / "hw6.toml")
    again = read(tomllib.loads(dumps(machine.to_spec())))
    assert again.to_spec() == machine.to_spec()
    assert again.gravity == machine.gravity and again.units == machine.units
    assert again["hw6"].lengths == machine["hw6"].lengths


def test_pint_quantities_give_a_model_its_units_and_labelled_columns():
    pytest.importorskip("pandas")
    ureg = u.registry()
    fb = FourBar(*(ureg.Quantity(v, "mm") for v in (80, 40, 70, 60)))
    assert fb.units.length == "mm"
    df = fb.solve(np.radians([0.0, 10.0]), omega2=1.0).to_pandas(degrees=True)
    assert {"theta3 [deg]", "omega4 [rad/s]", "B_x [mm]"} <= set(df.columns)
    assert "theta3_deg" in FourBar(8, 4, 7, 6).solve(0.1).to_pandas(degrees=True)


def test_loads_reads_text_as_load_machine_reads_the_file(tmp_path):
    from machdyn.spec import loads

    text = (EXAMPLES / "hw6.toml").read_text(encoding="utf-8")
    machine = loads(text, "hw6.toml")
    assert machine.to_spec() == load_machine(EXAMPLES / "hw6.toml").to_spec()
    assert machine.source == "hw6.toml" and not machine.legacy
    # errors carry the given name and the key's line, as from a file
    bad = BASE.replace("r2 = 40", 'r2 = "4 kg"')
    with pytest.raises(SpecError, match=r"^dropped\.toml:8: \[fourbar\.a\] r2: expected a length"):
        loads(bad, "dropped.toml")
    # JSON by the name's ending; an old linkage file is upgraded
    json_text = '{"machdyn": 1, "fourbar": {"a": {"r1": 8, "r2": 4, "r3": 7, "r4": 6}}}'
    assert loads(json_text, "a.json")["a"].lengths == (8.0, 4.0, 7.0, 6.0)
    old = 'ground = ["O2"]\ndrive = ["c"]\n[points]\nO2 = [0, 0]\nA = [1, 0]\n'
    old += '[[link]]\nname = "c"\npoints = ["O2", "A"]\n'
    assert loads(old, "old.toml").legacy
    for text_, source, needle in (
        (b"machdyn = 1", "a.toml", "text: expected the file's text"),
        ("machdyn = 1", "a.txt", "source: expected a name ending in .toml or .json"),
        ("machdyn = 1", "", "source: expected a name"),
    ):
        with pytest.raises(machdyn.InputError, match=needle):
            loads(text_, source)
