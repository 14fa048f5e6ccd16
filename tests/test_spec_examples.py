"""Every example machine file in docs/examples/, run, against the library called by hand.

Each expected value is computed here from the numbers of the file written out
again (not through the spec reader), with the library's own functions or a
closed form; where the notes or Norton print a value it is checked too.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from machdyn import cams, gears
from machdyn.balancing import two_plane
from machdyn.flywheel import disc_flywheel, size_flywheel
from machdyn.fourbar import FourBar
from machdyn.slidercrank import InvertedSliderCrank, SliderCrank
from machdyn.spec import dumps, load_machine, read
from machdyn.synthesis import function_generator, three_position

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
ALL = sorted(p.name for p in EXAMPLES.glob("*.toml"))
RPM = 2 * math.pi / 60  # rad/s per rpm
G0 = 9.80665


def run(name: str) -> tuple:
    machine = load_machine(EXAMPLES / name)
    return machine, machine.run()


def table(machine, results, part: str, name: str) -> dict:
    return results[part].table(name).labelled(machine.units)


def summary(machine, results, part: str) -> dict:
    return dict(item.shown(machine.units) for item in results[part].summary)


@pytest.mark.parametrize("name", ALL)
def test_every_example_runs_and_round_trips(name):
    machine, results = run(name)
    assert results and all(r.tables or r.summary for r in results.values())
    again = read(tomllib.loads(dumps(machine.to_spec())))
    assert again.to_spec() == machine.to_spec()


def test_examples_cover_every_kind():
    kinds = {p.kind for name in ALL for p in load_machine(EXAMPLES / name).parts.values()}
    assert kinds >= {
        "fourbar",
        "slider_crank",
        "inverted_slider_crank",
        "linkage",
        "cam",
        "gear_pair",
        "gear_train",
        "planetary",
        "flywheel",
        "rotor",
        "motion_synthesis",
        "function_synthesis",
        "path_synthesis",
    }


def test_slider_crank_example():
    machine, results = run("slider_crank.toml")
    theta2 = np.radians(np.arange(0.0, 361.0, 30.0))
    w = 3000 * RPM
    sc = SliderCrank(0.05, 0.2, 0.01)  # in metres here: the file is in mm
    f = sc.dynamics(
        theta2,
        w,
        mass=(1.0, 2.0, 1.5),
        inertia=(0.0012, 0.008),
        cg=(0.02, 0.1),
        load_force4=-2000.0,
        friction="coulomb",
        mu=0.05,
    )
    forces = table(machine, results, "engine", "forces")
    np.testing.assert_allclose(forces["T12 [N*m]"], f.T12, rtol=1e-9)
    kin = table(machine, results, "engine", "kinematics")
    np.testing.assert_allclose(kin["d [mm]"], 1000 * f.motion.d, rtol=1e-12)
    # stroke of the offset slider-crank: sqrt((a+b)^2 - c^2) - sqrt((b-a)^2 - c^2)
    lo, hi = summary(machine, results, "engine")["stroke (d min, d max) [mm]"]
    assert hi - lo == pytest.approx(math.sqrt(250**2 - 100) - math.sqrt(150**2 - 100), rel=1e-12)
    shaper = table(machine, results, "shaper", "kinematics")
    m = InvertedSliderCrank(0.1, 0.3).solve(np.radians(np.arange(0.0, 361.0, 45.0)), 60 * RPM)
    np.testing.assert_allclose(shaper["b [mm]"], 1000 * m.b, rtol=1e-12)


def test_cam_example():
    machine, results = run("cam.toml")
    program = cams.CamProgram(
        [
            cams.Segment("rise", math.radians(60), 25.0, "cycloidal"),
            cams.Segment("dwell", math.radians(120)),
            cams.Segment("fall", math.radians(60), 25.0, "cycloidal"),
            cams.Segment("dwell", math.radians(120)),
        ]
    )
    profile = cams.TranslatingRoller(75.0, 12.5).profile(program)
    s = summary(machine, results, "lifter")
    assert s["largest |pressure angle| [deg]"] == pytest.approx(
        math.degrees(abs(profile.pressure_angle_max)), rel=1e-12
    )
    motion = table(machine, results, "lifter", "motion")
    # cycloidal rise: peak V = 2 h / beta * omega = 2 * 25 / (pi/3) * (100 rpm)
    assert motion["V [mm/s]"].max() == pytest.approx(2 * 25 / (math.pi / 3) * 100 * RPM, rel=1e-9)


def test_gears_example():
    machine, results = run("gears.toml")
    pair = gears.GearPair(gears.Gear(24, diametral_pitch=8), gears.Gear(60, diametral_pitch=8))
    s = summary(machine, results, "exam")
    assert s["contact ratio"].startswith(f"{pair.contact_ratio:.4f}")
    assert s["centre distance [in]"] == 5.25  # (24 + 60) / (2 * 8)
    assert s["output speed [rpm]"] == pytest.approx(-1800 * 24 / 60, rel=1e-12)
    box = summary(machine, results, "box")
    assert box["output speed [rpm]"] == pytest.approx(1800 * (18 / 54) * (20 / 60), rel=1e-12)
    speeds = table(machine, results, "epicyclic", "speeds")
    ring = dict(zip(speeds["member"], speeds["speed [rpm]"], strict=True))["ring"]
    assert ring == pytest.approx(-350.0, rel=1e-12)  # Norton Example 9-6


def test_flywheel_example():
    machine, results = run("flywheel.toml")
    theta = np.radians(np.arange(0.0, 361.0, 30.0))
    torque = 50 + 10 * np.sin(theta) + 4 * np.sin(2 * theta)
    fw = size_flywheel(theta, np.round(torque, 6), 500 * RPM, 0.02)
    s = summary(machine, results, "shaft")
    assert s["I (flywheel inertia) [kg*m^2]"] == pytest.approx(fw.inertia, rel=1e-12)
    disc = disc_flywheel(fw.inertia, 7850.0, 0.04)
    assert s["disc outer radius [m]"] == pytest.approx(disc.outer_radius, rel=1e-12)


def test_rotor_example():
    machine, results = run("rotor.toml")
    mr = [0.2 * 60 * np.exp(1j * math.radians(30)), 0.3 * 50 * np.exp(1j * math.radians(150))]
    mr.append(0.1 * 80 * np.exp(1j * math.radians(270)))
    fix = two_plane(np.array(mr), np.array([100.0, 220.0, 320.0]), 0.0, 400.0)
    rows = table(machine, results, "shaft", "corrections")
    np.testing.assert_allclose(rows["mR [kg*mm]"], [abs(fix.mR_a), abs(fix.mR_b)], rtol=1e-12)
    np.testing.assert_allclose(rows["mass [kg]"], [abs(fix.mR_a) / 100, abs(fix.mR_b) / 100])
    # the corrections cancel the force and the moment about plane A
    z = np.array([100.0, 220.0, 320.0])
    assert abs(sum(mr) + fix.mR_a + fix.mR_b) < 1e-12
    assert abs(sum(m * zi for m, zi in zip(mr, z, strict=True)) + 400 * fix.mR_b) < 1e-9


def test_synthesis_example():
    machine, results = run("synthesis.toml")
    c = [0 + 5.086j, 2.019 + 3.181j, 3.933 + 4.051j]
    d = [0.741 + 2.703j, 4.428 + 2.529j, 6.304 + 4.83j]
    expected = three_position(c, d)
    s = summary(machine, results, "three")
    np.testing.assert_allclose(
        s["r1, r2, r3, r4 [L]"], [expected.r1, expected.r2, expected.r3, expected.r4]
    )
    # form 2 puts B on the D positions (test_synthesis_cli solves both forms to see it)
    assert s["form (FourBar, as in the notes)"] == 2
    g = function_generator(np.log10, (1.0, 2.0), np.radians((45, 105)), np.radians((135, 225)))
    np.testing.assert_allclose(
        summary(machine, results, "log")["r1, r2, r3, r4 [L]"], [g.r1, g.r2, g.r3, g.r4], rtol=1e-12
    )


def test_press_example_refers_parts_to_each_other():
    machine, results = run("press.toml")
    # the crank turns at the gear's speed: 1440 rpm * 18 / 72, reversed by the external mesh
    w2 = -1440 * RPM * 18 / 72
    fb = FourBar(0.2, 0.05, 0.18, 0.12)
    theta2 = np.radians(np.arange(0.0, 361.0, 5.0))
    f = fb.dynamics(
        theta2,
        w2,
        mass=(0.0, 2.0, 0.0),
        inertia=(0.0, 0.006, 0.0),
        cg=(0j, 0.09 + 0j, 0j),
        gravity=G0,
        load_torque4=-20.0,
    )
    forces = table(machine, results, "press", "forces")
    np.testing.assert_allclose(forces["T12 [N*m]"], f.T12, rtol=1e-9, atol=1e-12)

    # the flywheel integrates T12 over the whole turn in fine steps, not the table's 5°:
    # the trapezoid's ΔE is O(h²), so 3600 and 36000 steps agree to ~1e-6 (5° was 1e-3 off)
    def inertia(steps):
        fine = np.linspace(0.0, 2.0 * np.pi, steps + 1)
        t12 = fb.dynamics(fine, w2, mass=(0.0, 2.0, 0.0), inertia=(0.0, 0.006, 0.0),
                          cg=(0j, 0.09 + 0j, 0j), gravity=G0, load_torque4=-20.0).T12  # fmt: skip
        return size_flywheel(fine, t12, abs(w2), 0.02).inertia

    s = summary(machine, results, "crank")
    # I in the file's units: kg*mm^2 (1 kg*m^2 = 1e6 kg*mm^2)
    assert s["I (flywheel inertia) [kg*mm^2]"] == pytest.approx(inertia(3600) * 1e6, rel=1e-9)
    assert s["I (flywheel inertia) [kg*mm^2]"] == pytest.approx(inertia(36000) * 1e6, rel=2e-6)
    coarse = size_flywheel(theta2, f.T12, abs(w2), 0.02).inertia
    assert abs(coarse / inertia(36000) - 1.0) > 1e-4  # what the 5° table alone would give
    assert s["omega_avg [rpm]"] == pytest.approx(360.0, rel=1e-12)


def test_a_flywheel_takes_the_whole_turn_whatever_its_part_prints(tmp_path):
    # the press printed over a quarter turn only, in 30° steps: its flywheel is the same
    text = (EXAMPLES / "press.toml").read_text(encoding="utf-8")
    assert "theta2 = [0, 360, 5]" in text
    (tmp_path / "quarter.toml").write_text(
        text.replace("theta2 = [0, 360, 5]", "theta2 = [0, 90, 30]")
    )
    machine, results = run("press.toml")
    quarter = load_machine(tmp_path / "quarter.toml")
    quarter_results = quarter.run()
    assert len(table(quarter, quarter_results, "press", "forces")["T12 [N*m]"]) == 4
    whole = summary(machine, results, "crank")
    np.testing.assert_equal(summary(quarter, quarter_results, "crank"), whole)


def test_the_cam_command_reads_a_machine_file(tmp_path, capsys):
    """``machdyn cam --program`` takes the cam part of a machine file (DXF in the file's unit)."""
    import json

    from machdyn.cli import main

    dxf = tmp_path / "lifter.dxf"
    assert main(["cam", "--program", str(EXAMPLES / "cam.toml"), "--json", "--dxf", str(dxf)]) == 0
    got = json.loads(capsys.readouterr().out)
    program = cams.CamProgram(
        [
            cams.Segment("rise", math.radians(60), 25.0, "cycloidal"),
            cams.Segment("dwell", math.radians(120)),
            cams.Segment("fall", math.radians(60), 25.0, "cycloidal"),
            cams.Segment("dwell", math.radians(120)),
        ]
    )
    profile = cams.TranslatingRoller(75.0, 12.5).profile(program)
    assert got["pressure_angle_max_deg"] == pytest.approx(
        math.degrees(abs(profile.pressure_angle_max)),
        abs=0.1,  # the command samples 3600
    )
    assert got["rpm"] == pytest.approx(100.0, rel=1e-12)
    # cycloidal rise: peak V = 2 h / beta * omega = 2 * 25 / (pi/3) * (100 rpm), mm/s
    assert got["peaks_time"]["V"] == pytest.approx(2 * 25 / (math.pi / 3) * 100 * RPM, rel=1e-9)
    lines = dxf.read_text().splitlines()
    assert lines[lines.index("$INSUNITS") + 2].strip() == "4"  # millimetres
    # a file of several cams (or none) is refused in one line, naming the option
    two = tmp_path / "two.toml"
    two.write_text("machdyn = 1\n[fourbar.a]\nr1 = 8\nr2 = 4\nr3 = 7\nr4 = 6\n")
    assert main(["cam", "--program", str(two)]) == 1
    assert "--program" in capsys.readouterr().err
