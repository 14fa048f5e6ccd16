"""Machine-file loads: gear torques, planetary torques and rotor bearings.

The file's `run` numbers and report cells equal the Python API given the same
torque/bearings, and both equal independent derivations written here: Norton,
*Design of Machinery*, eq. 9.13 (W_t = T / r_p, W_r = W_t tan φ), power balance
through a train (T ω constant), Example 9-6 (Σ T = 0, Σ T ω = 0) and the two
bearing reactions of a rotating rigid shaft (force and moment balance).
"""

from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

from machdyn.cli import main
from machdyn.report import report
from machdyn.spec import SpecError, dumps, loads
from machdyn.units import UnitSystem

EXAMPLES = Path(__file__).parent.parent / "docs" / "examples"
RPM = 2 * math.pi / 60

SI = """machdyn = 1
[gear_pair.p]
pinion = { teeth = 18 }
gear = { teeth = 54 }
module = 0.003
input_speed = 188.49555921538757
torque = 10.0
[gear_train.t]
stages = [[18, 54], [20, 60]]
input_speed = 188.49555921538757
torque = 10.0
[planetary.e]
sun = 40
planet = 20
ring = 80
speeds = { arm = -20.943951023931955, sun = 10.471975511965978 }
torques = { sun = 10.0 }
[rotor.r]
planes = [0.0, 0.4]
speed = 157.07963267948966
bearings = [-0.05, 0.45]
[[rotor.r.mass]]
mass = 0.2
radius = 0.06
angle = 0.5235987755982988
z = 0.1
[[rotor.r.mass]]
mass = 0.3
radius = 0.05
angle = 2.6179938779914944
z = 0.22
"""

MM = """machdyn = 1
[units]
length = "mm"
force = "N"
angular_velocity = "rpm"
[gear_pair.p]
pinion = { teeth = 18 }
gear = { teeth = 54 }
module = 3
input_speed = 1800
torque = "10 N*m"
[gear_train.t]
stages = [[18, 54], [20, 60]]
input_speed = 1800
torque = "10 N*m"
[planetary.e]
sun = 40
planet = 20
ring = 80
speeds = { arm = -200, sun = 100 }
torques = { sun = "10 N*m" }
[rotor.r]
planes = [0, 400]
speed = 1500
bearings = [-50, 450]
[[rotor.r.mass]]
mass = 0.2
radius = 60
angle = 30
z = 100
[[rotor.r.mass]]
mass = 0.3
radius = 50
angle = 150
z = 220
"""


def cell(page: str, key: str) -> str:
    found = re.findall(rf'data-key="{re.escape(key)}"[^>]*>(.*?)</(?:td|span|p)>', page, re.S)
    assert len(found) == 1, (key, found)
    return re.sub(r"<[^>]+>", "", found[0])


def number(text: str) -> float:
    return float(re.match(r"\s*(-?[\d.]+(?:e[-+]?\d+)?)", text).group(1))


def summary(result, label: str, system):
    """A summary line's value as `machdyn run` prints it (the file's output units)."""
    (value,) = [s.shown(system)[1] for s in result.summary if s.label == label]
    return value


def column(result, key: str, system):
    """A table column as printed (the file's output units)."""
    table = result.tables[0]
    kind = table.kinds[key]
    return table.columns[key] if kind is None else system.show(kind, table.columns[key])


def bearing_loads_by_hand(masses, omega, za, zb):
    """|F_A|, |F_B|: Σ F = 0 and Σ M about A = 0 for the centrifugal forces m R ω²."""
    f = np.array([m * r * np.exp(1j * a) for m, r, a, _ in masses]) * omega**2
    z = np.array([e[3] for e in masses])
    fb = -(f * (z - za)).sum() / (zb - za)
    return abs(-f.sum() - fb), abs(fb)


# torque unit of each file: N·m (SI), N·mm (mm/N/rpm); speeds rad/s, rpm
@pytest.mark.parametrize(
    ("text", "t_unit", "w_unit", "l_unit"), [(SI, 1.0, 1.0, 1.0), (MM, 1e3, RPM, 1e-3)]
)
def test_run_numbers_are_the_python_api_and_the_textbook(text, t_unit, w_unit, l_unit):
    machine = loads(text, "loads.toml")
    res, sys_ = machine.run(), machine.units
    # gear pair: W_t = T / r_p (r_p = m N / 2 = 27 mm), W_r = W_t tan 20°
    wt = 10.0 / 0.027
    assert summary(res["p"], "tangential tooth load W_t", sys_) == pytest.approx(wt, rel=1e-9)
    assert summary(res["p"], "radial tooth load W_r", sys_) == pytest.approx(
        wt * math.tan(math.radians(20)), rel=1e-9
    )
    assert summary(res["p"], "total tooth load W", sys_) == pytest.approx(
        wt / math.cos(math.radians(20)), rel=1e-9
    )
    assert column(res["p"], "torque", sys_)[1] == pytest.approx(
        3 * 10.0 * t_unit, rel=1e-9
    )  # T_g = T_p N_g/N_p
    # train: T ω constant; output 1/9 of the speed → the load holds −90 N·m
    assert column(res["t"], "driven_torque", sys_) == pytest.approx(
        np.array([-30.0, 90.0]) * t_unit, rel=1e-9
    )
    assert summary(res["t"], "load torque on the output shaft", sys_) == pytest.approx(-90 * t_unit)
    # planetary, Norton Ex. 9-6 with T_sun = 10: Σ T = 0 and Σ T ω = 0 give T_ring, T_arm
    members = column(res["e"], "member", sys_)
    omega = dict(zip(members, column(res["e"], "speed", sys_), strict=True))
    a = np.array([[1.0, 1.0], [omega["ring"], omega["arm"]]])
    t_ring, t_arm = np.linalg.solve(a, [-10.0 * t_unit, -10.0 * t_unit * omega["sun"]])
    torque = dict(zip(members, column(res["e"], "torque", sys_), strict=True))
    assert torque["ring"] == pytest.approx(t_ring) and torque["arm"] == pytest.approx(t_arm)
    # rotor: bearing loads at 1500 rpm, in newtons either way (kg·m/s² ↔ kg·mm·rpm²→N)
    task = machine["r"]
    si = [(m, r * l_unit, a, z * l_unit) for m, r, a, z in task.masses]
    za, zb = (z * l_unit for z in task.bearings)
    before = bearing_loads_by_hand(si, 1500 * RPM, za, zb)
    assert summary(res["r"], "bearing loads A, B before", sys_) == pytest.approx(before, rel=1e-9)
    after = summary(res["r"], "bearing loads A, B after", sys_)
    assert max(after) < 1e-9 * max(before)


@pytest.mark.parametrize("text", [SI, MM])
def test_file_report_equals_the_python_api_report(text):
    machine = loads(text, "loads.toml")
    units = None if text is SI else UnitSystem(length="mm", force="N", angular_velocity="rpm")
    page = report(machine)
    v = {name: part.values for name, part in machine.parts.items()}
    pair = report(
        machine["p"], input_speed=v["p"]["input_speed"], torque=v["p"]["torque"], units=units
    )
    for key in ("W_t", "W_r", "W", "T_pinion", "T_gear"):
        assert cell(page, f"p:{key}") == cell(pair, key)
    train = report(
        machine["t"], input_speed=v["t"]["input_speed"], torque=v["t"]["torque"], units=units
    )
    for key in ("T1", "T2", "T3", "load_torque"):
        assert cell(page, f"t:{key}") == cell(train, key)
    planet = report(machine["e"], speeds=v["e"]["speeds"], torque=v["e"]["torques"], units=units)
    for key in ("T_sun", "T_ring", "T_arm"):
        assert cell(page, f"e:{key}") == cell(planet, key)
    rotor = report(machine["r"], bearings=machine["r"].bearings, units=units)
    for key in ("load_A_before", "load_B_before"):
        assert cell(page, f"r:{key}") == cell(rotor, key)


def test_machdyn_report_and_run_of_the_example(tmp_path, capsys):
    out = tmp_path / "loads.html"
    assert main(["report", str(EXAMPLES / "loads.toml"), "-o", str(out)]) == 0
    page = out.read_text(encoding="utf-8")
    assert number(cell(page, "exam:W_t")) == pytest.approx(100 / 1.5, rel=1e-5)  # lbf
    capsys.readouterr()
    assert main(["run", str(EXAMPLES / "loads.toml")]) == 0
    text = capsys.readouterr().out
    assert re.search(r"tangential tooth load W_t \[lbf\]\s+66\.6667", text)
    assert "bearing loads A, B before [lbf]" in text


def test_round_trip_keeps_the_loads():
    machine = loads(MM, "loads.toml")
    again = loads(dumps(machine.to_spec()), "again.toml")
    assert again.to_spec() == machine.to_spec()
    for name in ("p", "t"):
        assert again.parts[name].values["torque"] == pytest.approx(1e7)  # kg·mm²/s²
    assert again.parts["e"].values["torques"] == pytest.approx({"sun": 1e7})
    assert again["r"].bearings == (-50.0, 450.0)
    rotor = tomllib.loads(dumps(machine["r"].to_spec("r")))
    assert rotor["rotor"]["r"]["bearings"] == [-50, 450]


@pytest.mark.parametrize(
    ("old", "new", "needle"),
    [
        (
            'torque = "10 N*m"\n[gear_train',
            'torque = "10 mm"\n[gear_train',
            r"^bad\.toml:11: \[gear_pair\.p\] torque: expected a torque",
        ),
        (
            'input_speed = 1800\ntorque = "10 N*m"\n[planetary',
            'input_speed = 1800\ntorque = "3 kg"\n[planetary',
            r"^bad\.toml:15: \[gear_train\.t\] torque: expected a torque",
        ),
        (
            'torques = { sun = "10 N*m" }',
            'torques = { sun = "10 rpm" }',
            r"^bad\.toml:21: \[planetary\.e\.torques\] sun: expected a torque",
        ),
        (
            'torques = { sun = "10 N*m" }',
            'torques = { planet = "10 N*m" }',
            r"^bad\.toml:21: \[planetary\.e\.torques\]: torque: must be one of sun, ring, arm",
        ),
        (
            'torques = { sun = "10 N*m" }',
            "torques = { sun = 1, ring = 2 }",
            r"^bad\.toml:21: \[planetary\.e\] torques: give one member",
        ),
        (
            "bearings = [-50, 450]",
            'bearings = ["1 kg", "2 kg"]',
            r"^bad\.toml:25: \[rotor\.r\] bearings\[1\]: expected a length",
        ),
        (
            "bearings = [-50, 450]",
            "bearings = [5, 5]",
            r"^bad\.toml:25: \[rotor\.r\] bearings: two different",
        ),
        ("speed = 1500\n", "", r"^bad\.toml:\d+: \[rotor\.r\] bearings: bearing loads need"),
    ],
)
def test_bad_loads_are_refused_naming_file_line_key(old, new, needle):
    assert old in MM
    with pytest.raises(SpecError, match=needle):
        loads(MM.replace(old, new), "bad.toml")
