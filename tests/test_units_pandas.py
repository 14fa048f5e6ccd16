"""``to_pandas()`` names columns with units when the model was given units (#11 item 5).

Each result is computed twice: from a machine file in one unit system and from
the same machine in another (or unit-free); the labelled columns must hold the
same physical values after converting by hand (25.4 mm per inch, 60/2π rpm per
rad/s, ...), and a unit-free model keeps its bare column names.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import machdyn
from machdyn.cams import CamProgram

pytest.importorskip("pandas")

RPM = 2 * math.pi / 60


def cam_doc(length: str, lift: float, prime: float, roller: float, speed: str) -> dict:
    return {
        "machdyn": 1,
        "units": {"length": length, "angular_velocity": "rpm"},
        "cam": {
            "lifter": {
                "speed": speed,
                "segment": [
                    {"motion": "rise", "beta": 60, "lift": lift, "law": "cycloidal"},
                    {"motion": "dwell", "beta": 120},
                    {"motion": "fall", "beta": 60, "lift": lift, "law": "cycloidal"},
                    {"motion": "dwell", "beta": 120},
                ],
                "follower": {"type": "roller", "prime_radius": prime, "roller_radius": roller},
            }
        },
    }


def test_cam_tables_carry_the_files_units():
    mm = machdyn.from_spec(cam_doc("mm", 25.4, 76.2, 12.7, "100 rpm"))
    inch = machdyn.from_spec(cam_doc("in", 1.0, 3.0, 0.5, "100 rpm"))
    a = mm.motion(12).in_time(100 * RPM).to_pandas()
    b = inch.motion(12).in_time(100 * RPM).to_pandas()
    assert list(a) == ["t [s]", "theta [deg]", "s [mm]", "V [mm/s]", "A [mm/s^2]", "J [mm/s^3]"]
    assert list(b)[2:4] == ["s [in]", "V [in/s]"]
    np.testing.assert_allclose(a["s [mm]"], 25.4 * b["s [in]"], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(a["V [mm/s]"], 25.4 * b["V [in/s]"], rtol=1e-12, atol=1e-9)
    # cycloidal rise: peak V = 2 h / beta * omega (h = 25.4 mm over 60 deg at 100 rpm)
    assert a["V [mm/s]"].max() == pytest.approx(2 * 25.4 / (math.pi / 3) * 100 * RPM, rel=0.02)
    per_rad = mm.motion(12).to_pandas()
    assert list(per_rad) == ["theta [deg]", "s [mm]", "v [mm/rad]", "a [mm/rad^2]", "j [mm/rad^3]"]
    np.testing.assert_allclose(per_rad["theta [deg]"], np.arange(0, 360, 30), atol=1e-9)
    p = mm.profile(36).to_pandas()
    q = inch.profile(36).to_pandas()
    assert {"pitch_x [mm]", "rho_pitch [mm]", "pressure_angle [deg]"} <= set(p)
    np.testing.assert_allclose(p["surface_y [mm]"], 25.4 * q["surface_y [in]"], rtol=1e-9)
    np.testing.assert_allclose(p["pressure_angle [deg]"], q["pressure_angle [deg]"], atol=1e-9)


def test_unit_free_cam_tables_keep_their_names():
    m = CamProgram.double_dwell(1.0, math.pi / 3, math.pi / 3).sample(8)
    assert list(m.to_pandas()) == ["theta", "theta_deg", "s", "v", "a", "j"]
    assert list(m.in_time(2.0).to_pandas()) == ["t", "theta", "theta_deg", "s", "V", "A", "J"]
    free = cam_doc("mm", 25.4, 76.2, 12.7, "100 rpm")
    del free["units"], free["cam"]["lifter"]["speed"]
    cam = machdyn.from_spec(free)
    assert list(cam.motion(8).to_pandas())[:2] == ["theta", "theta_deg"]


def test_the_cam_command_labels_a_machine_files_columns(tmp_path, capsys):
    from machdyn.cli import main
    from machdyn.spec import dumps

    file = tmp_path / "cam.toml"
    file.write_text(dumps(cam_doc("mm", 25.0, 75.0, 12.5, "100 rpm")))
    csv = tmp_path / "profile.csv"
    assert main(["cam", "--program", str(file), "--points", "36", "--csv", str(csv)]) == 0
    out = capsys.readouterr().out
    assert "mm/rad" in out and "mm/s" in out and "length" not in out.split("follower:")[0]
    header = csv.read_text().splitlines()[0].split(",")
    assert header[:3] == ["theta [deg]", "s [mm]", "v [mm/rad]"]


def flywheel_doc(length: str, mass: str, speed: str, density: str) -> dict:
    theta = list(range(0, 361, 30))
    torque = [50 + 10 * math.sin(math.radians(t)) for t in theta]
    return {
        "machdyn": 1,
        "units": {"length": length, "mass": mass, "force": "N", "angular_velocity": speed},
        "flywheel": {
            "shaft": {
                "theta": theta,
                "torque": [f"{t} N*m" for t in torque],
                "omega_avg": "500 rpm",
                "k": 0.02,
                "density": density,
                "thickness": "40 mm",
            }
        },
    }


def test_flywheel_tables_carry_units():
    si = machdyn.from_spec(flywheel_doc("m", "kg", "rad/s", "7850 kg/m^3")).solve()
    mm = machdyn.from_spec(flywheel_doc("mm", "g", "rpm", "7850 kg/m^3")).solve()
    a, b = si.to_pandas(), mm.to_pandas()
    assert list(a) == ["theta [deg]", "T12 [N*m]", "T12_minus_T_avg [N*m]", "omega [rad/s]"]
    assert list(b) == ["theta [deg]", "T12 [N*mm]", "T12_minus_T_avg [N*mm]", "omega [rpm]"]
    np.testing.assert_allclose(b["T12 [N*mm]"], 1000 * a["T12 [N*m]"], rtol=1e-9)
    np.testing.assert_allclose(b["omega [rpm]"] * RPM, a["omega [rad/s]"], rtol=1e-9)
    lobes = si.lobes.to_pandas()
    assert list(lobes)[:3] == ["theta_from [deg]", "theta_to [deg]", "delta_E [N*m]"]
    from machdyn.flywheel import size_flywheel

    theta = np.radians(np.arange(0.0, 361.0, 30.0))
    bare = size_flywheel(theta, 50 + 10 * np.sin(theta), 500 * RPM, 0.02)
    # T = 50 + 10 sin(theta) sampled every 30 deg: two lobes of +-dE (2 * 10 J for the
    # smooth curve; the straight lines between samples give a little less)
    np.testing.assert_allclose(lobes["delta_E [N*m]"], bare.lobes.area, rtol=1e-9)
    assert abs(bare.lobes.area).max() == pytest.approx(20.0, rel=0.03)
    np.testing.assert_allclose(lobes["theta_to [deg]"], np.degrees(bare.lobes.theta_to))
    assert list(bare.to_pandas()) == ["theta_deg", "T12", "T12_minus_T_avg", "omega"]
    assert list(bare.lobes.to_pandas())[:2] == ["theta_from_deg", "theta_to_deg"]


def test_balance_gears_and_synthesis_tables_carry_units():
    rotor = {
        "planes": [0, 400],
        "mass": [
            {"mass": 0.2, "radius": 60, "angle": 30, "z": 100},
            {"mass": 0.3, "radius": 50, "angle": 150, "z": 220},
        ],
    }
    mm = machdyn.from_spec({"machdyn": 1, "units": {"length": "mm"}, "rotor": {"r": rotor}})
    m = machdyn.from_spec(
        {
            "machdyn": 1,
            "units": {"length": "m"},
            "rotor": {
                "r": {
                    "planes": ["0 mm", "400 mm"],
                    "mass": [
                        {k: (f"{v} mm" if k in ("radius", "z") else v) for k, v in e.items()}
                        for e in rotor["mass"]
                    ],
                }
            },
        }
    )
    a, b = mm.solve().to_pandas(), m.solve().to_pandas()
    assert list(a) == ["z [mm]", "mR [kg*mm]", "angle [deg]"]
    np.testing.assert_allclose(a["mR [kg*mm]"], 1000 * b["mR [kg*m]"], rtol=1e-9)
    np.testing.assert_allclose(a["angle [deg]"], b["angle [deg]"], rtol=1e-12)

    from machdyn.spec import load_machine as gears

    train = gears("docs/examples/gears.toml")["epicyclic"]
    t = train.table(arm=-200 * RPM, sun=100 * RPM).to_pandas()
    assert t.loc["ring", "total [rpm]"] == pytest.approx(-350.0, rel=1e-12)  # Norton Ex. 9-6
    pair = gears("docs/examples/gears.toml")["exam"].to_pandas()
    assert pair["pinion.pitch_radius [in]"] == pytest.approx(24 / 16)
    assert pair["center_distance [in]"] == pytest.approx((24 + 60) / 16)
    assert pair["pinion.diametral_pitch [1/in]"] == 8.0

    c = [[0, 5.086], [2.019, 3.181], [3.933, 4.051]]
    d = [[0.741, 2.703], [4.428, 2.529], [6.304, 4.83]]
    task = {"c": [[f"{v} in" for v in p] for p in c], "d": [[f"{v} in" for v in p] for p in d]}
    inch = machdyn.from_spec(
        {"machdyn": 1, "units": {"length": "mm"}, "motion_synthesis": {"t": task}}
    )
    got = inch.solve().to_pandas(degrees=True)
    free = machdyn.synthesis.three_position(
        [complex(*p) for p in c], [complex(*p) for p in d]
    ).to_pandas(degrees=True)
    assert list(free)[:2] == ["A_x", "A_y"]
    np.testing.assert_allclose(got["A_x [mm]"], 25.4 * free["A_x"], rtol=1e-9)
    np.testing.assert_allclose(got["theta2 [deg]"], free["theta2_deg"], rtol=1e-9)


def test_forces_and_simulation_tables_carry_units():
    fb = {"r1": 80, "r2": 40, "r3": 70, "r4": 60}
    mm = machdyn.from_spec({"machdyn": 1, "units": {"length": "mm"}, "fourbar": {"a": fb}})
    m = machdyn.FourBar(0.08, 0.04, 0.07, 0.06)
    theta = np.radians([0.0, 30.0, 60.0])
    load = {"mass": (1.0, 2.0, 1.5), "inertia": (0.01, 0.02, 0.015)}
    a = mm.dynamics(theta, 10.0, cg=(20.0, 35.0, 30.0), **load).to_pandas()
    b = m.dynamics(theta, 10.0, cg=(0.02, 0.035, 0.03), **load).to_pandas()
    assert list(b)[:3] == ["theta2", "T12", "F12_x"]  # unit-free: unchanged
    assert list(a)[:3] == ["theta2 [rad]", "T12 [N*mm]", "F12_x [N]"]
    # inertia in kg*mm^2 here: the same machine has I = 0.01 kg*m^2 = 1e4 kg*mm^2
    mm_i = mm.dynamics(theta, 10.0, cg=(20.0, 35.0, 30.0), mass=load["mass"],
                       inertia=tuple(1e6 * i for i in load["inertia"])).to_pandas()  # fmt: skip
    np.testing.assert_allclose(mm_i["T12 [N*mm]"], 1000 * b["T12"], rtol=1e-9)
    np.testing.assert_allclose(mm_i["F32_x [N]"], b["F32_x"], rtol=1e-9, atol=1e-9)

    heavy = {"mass": load["mass"], "inertia": tuple(1e6 * i for i in load["inertia"])}
    sim = machdyn.simulate(
        mm, None, omega0=10.0, t_end=0.05, samples=5, cg=(20.0, 35.0, 30.0), **heavy
    )
    table = sim.to_pandas()
    assert list(table)[:4] == [
        "t [s]",
        "theta2 [rad]",
        "theta2_dot [rad/s]",
        "theta2_ddot [rad/s^2]",
    ]
    assert [c for c in table if c.startswith("kinetic_energy [")], list(table)
    bare = machdyn.simulate(m, None, omega0=10.0, t_end=0.05, samples=5, cg=(0.02, 0.035, 0.03),
                            **load).to_pandas()  # fmt: skip
    assert list(bare)[:2] == ["t", "theta2"]
    np.testing.assert_allclose(table["theta2_dot [rad/s]"], bare["theta2_dot"], rtol=1e-6)
