"""``machdyn simulate FILE`` and ``machdyn tolerance FILE``: read the file, label, one-line errors.

The numbers are the library's (tested against independent checks in test_simulate.py and
test_tolerance.py); here: the file's motor, flywheel, masses and tolerances reach the
library unchanged (the same run made in Python from the values written in the test), the
output is in the file's units (rpm, mm), and bad files or command lines end in one line.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import machdyn
from machdyn.cli import main
from machdyn.simulate import DCMotor

EXAMPLE = str(Path(__file__).resolve().parents[1] / "docs" / "examples" / "motor.toml")
MASSES = dict(mass=(0.2, 0.3, 0.25), inertia=(3e-5, 1.2e-4, 7.5e-5), cg=(0.02, 0.035, 0.03))
FB = machdyn.FourBar(0.08, 0.04, 0.07, 0.06)
RPM = 60.0 / (2.0 * math.pi)


def cli(capsys, *args: str) -> tuple[int, str, str]:
    status = main(list(args))
    out, err = capsys.readouterr()
    return status, out, err


def test_simulate_reads_the_motor_and_prints_in_the_files_units(capsys):
    status, out, err = cli(capsys, "simulate", EXAMPLE, "--json")
    assert status == 0, err
    part = json.loads(out)["parts"]["hw6"]
    motor = DCMotor(0.5, 300.0, ratio=10.0, inertia=2e-6)
    run = machdyn.simulate(FB, motor, flywheel=0.02, until="steady", gravity=9.80665, **MASSES)
    summary = part["summary"]
    assert summary["status"] == "steady"
    assert summary["steady: k = (max - min) / avg"] == pytest.approx(run.steady.k, rel=1e-9)
    assert summary["steady: omega avg [rpm]"] == pytest.approx(run.steady.omega_avg * RPM)
    table = part["tables"]["motion"]
    assert table["columns"] == ["t [s]", "theta2 [deg]", "omega2 [rpm]", "alpha2 [rad/s^2]",
                                "T_motor [N*m]"]  # fmt: skip
    rows = np.array(table["rows"], dtype=float)
    assert np.allclose(rows[:, 2], run.omega * RPM)
    assert np.allclose(rows[:, 1], np.degrees(run.theta))
    assert part["tables"]["events"]["rows"][-1][0] == "steady"


def test_simulate_text_and_csv(capsys, tmp_path):
    status, out, err = cli(capsys, "simulate", EXAMPLE)
    assert status == 0, err
    assert "steady: omega min, max [rpm]" in out and "one row in" in out
    status, out, err = cli(capsys, "simulate", EXAMPLE, "--csv")
    lines = out.splitlines()
    header = "t [s],theta2 [deg],omega2 [rpm],alpha2 [rad/s^2],T_motor [N*m]"
    assert status == 0 and lines[0] == header
    assert len(lines) == 2002  # every sample (2001) and the header


def test_tolerance_reads_the_tolerances(capsys):
    status, out, err = cli(capsys, "tolerance", EXAMPLE, "--json", "--samples", "3000")
    assert status == 0, err
    part = json.loads(out)["parts"]["hw6"]
    omega2 = 286.0 / RPM
    t = machdyn.tolerance(FB, {f"r{k}": 1e-4 for k in range(1, 5)}, samples=3000, omega2=omega2,
                          gravity=9.80665, **MASSES)  # fmt: skip
    assert part["summary"]["unassembled"] == "0 (0 %)"
    assert part["summary"]["+/- r2 (3 sigma) [m]"] == pytest.approx(1e-4)
    theta4 = part["tables"]["theta4"]
    assert theta4["columns"][:3] == ["theta2 [deg]", "theta4_nominal [deg]", "std [deg]"]
    rows = np.array(theta4["rows"], dtype=float)
    assert np.allclose(rows[:, 2], np.degrees(t.outputs["theta4"].std))
    torque = np.array(part["tables"]["T12"]["rows"], dtype=float)
    assert np.allclose(torque[:, 3], t.outputs["T12"].linear_std)  # N*m


def _file(tmp_path: Path, extra: str) -> str:
    base = Path(EXAMPLE).read_text(encoding="utf-8")
    base = base[: base.index("[fourbar.hw6.simulate]")]
    path = tmp_path / "m.toml"
    path.write_text(base + extra, encoding="utf-8")
    return str(path)


@pytest.mark.parametrize(
    ("command", "extra", "needle"),
    [
        ("simulate", "", "no fourbar or slider_crank part has a [<kind>.<name>.simulate] table"),
        ("tolerance", "", "[<kind>.<name>.tolerance] table"),
        (
            "simulate",
            '[fourbar.hw6.simulate]\nmotor = { kind = "dc", stall_torque = 1 }\nuntil = "steady"\n',
            "a dc motor needs stall_torque, no_load_speed",
        ),
        (
            "simulate",
            '[fourbar.hw6.simulate]\nmotor = { kind = "constant", torque = 1 }\n',
            "give exactly one of t_end, turns",
        ),
        ("tolerance", '[fourbar.hw6.tolerance]\nr2 = "-0.1 mm"\n', "must be at least 0"),
        ("tolerance", '[fourbar.hw6.tolerance]\nr9 = "0.1 mm"\n', "r9: unknown key"),
        ("tolerance", "[fourbar.hw6.tolerance]\nsamples = 10\n", "give the ± tolerance"),
    ],
)
def test_bad_files_end_in_one_line(capsys, tmp_path, command, extra, needle):
    status, out, err = cli(capsys, command, _file(tmp_path, extra))
    assert status == 1 and out == ""
    assert err.count("\n") == 1 and needle in err and "Traceback" not in err


def test_a_motor_too_weak_to_start_is_a_stall_with_its_deficit(capsys, tmp_path):
    weak = '[fourbar.hw6.simulate]\nmotor = { kind = "dc", stall_torque = "0.001 N*m", '
    weak += "no_load_speed = 10 }\nt_end = 1\ntheta0 = 60\n"
    status, out, err = cli(capsys, "simulate", _file(tmp_path, weak), "--json")
    assert status == 0, err
    summary = json.loads(out)["parts"]["hw6"]["summary"]
    # the static torque at 60 deg (Newton-Euler, zero speed) less the motor's 0.001 N*m
    static = FB.dynamics(math.radians(60.0), 0.0, 0.0, gravity=9.80665, **MASSES).T12
    assert summary["status"] == "stall"
    assert summary["stall: the motor's deficit [N*m]"] == pytest.approx(float(static) - 0.001)
    # the message words the efforts in the file's output units too, not the model's own
    message = summary["message"]
    assert "the motor cannot start at theta2 = 60 deg: it gives 0.001 N*m at zero speed" in message
    assert f"where the load needs {float(static):.6g} N*m" in message


def test_a_stall_message_words_its_efforts_in_the_output_units(capsys, tmp_path):
    # in mm and g a torque's own unit is g*mm^2/s^2 (1e-9 N*m): the message must not
    # print that number under the file's output unit, N*mm
    weak = '[fourbar.hw6.simulate]\nmotor = { kind = "dc", stall_torque = "1e-9 N*m", '
    weak += "no_load_speed = 10 }\nt_end = 1\ntheta0 = 60\n"
    path = _file(tmp_path, weak)
    text = Path(path).read_text(encoding="utf-8").replace('length = "m"', 'length = "mm"')
    Path(path).write_text(text.replace('mass = "kg"', 'mass = "g"'), encoding="utf-8")
    status, out, err = cli(capsys, "simulate", path, "--json")
    assert status == 0, err
    summary = json.loads(out)["parts"]["hw6"]["summary"]
    (label,) = [k for k in summary if k.startswith("stall: the motor's deficit")]
    unit = label[label.index("[") + 1 : -1]
    message = summary["message"]
    assert unit == "N*mm"
    assert "it gives 1e-06 N*mm at zero speed" in message  # 1e-9 N*m = 1e-6 N*mm
    assert f"(a deficit of {summary[label]:.6g} {unit})" in message


def test_bad_command_lines(capsys):
    status, out, err = cli(capsys, "simulate", EXAMPLE, "--part", "nope")
    assert out == ""
    assert status == 1 and "--part: 'nope' is not a part" in err and err.count("\n") == 1
    status, _, err = cli(capsys, "tolerance", EXAMPLE, "--samples", "0")
    assert status == 1 and "samples" in err and err.count("\n") == 1
    status, _, err = cli(capsys, "tolerance", EXAMPLE, "--scheduler", "nowhere")
    assert status == 1 and "scheduler" in err and err.count("\n") == 1


def test_machdyn_run_sizes_a_flywheel_honestly(capsys):
    """press.toml: the sizing says what it neglects and gives k simulated with the press's
    own inertia; the same numbers from the library, with the file's values written here
    in its units (mm, kg, s: N*m = 1e6 kg*mm^2/s^2)."""
    from machdyn.flywheel import size_flywheel

    press = str(Path(EXAMPLE).with_name("press.toml"))
    status, out, err = cli(capsys, "run", press, "--part", "crank", "--json")
    assert status == 0, err
    summary = json.loads(out)["parts"]["crank"]["summary"]
    assert "varying inertia" in summary["the estimate neglects"]
    fb = machdyn.FourBar(200.0, 50.0, 180.0, 120.0)
    loads = dict(mass=(0.0, 2.0, 0.0), inertia=(0.0, 6000.0, 0.0), cg=(0.0, 90.0, 0.0),
                 gravity=9806.65, load_torque4=-20e6)  # fmt: skip
    theta = np.linspace(0.0, 2.0 * np.pi, 3601)  # the flywheel's turn in 0.1° steps
    omega = 360.0 / RPM  # the gear: 1440 rpm x 18/72, rad/s (turning backwards)
    needed = fb.dynamics(theta, -omega, **loads).T12
    fw = size_flywheel(theta, needed, omega_avg=omega, k=0.02)
    honest = fw.simulate(fb, **loads).k
    k = summary["k with the linkage's own inertia (simulated)"]
    assert k == pytest.approx(honest, rel=1e-9)
    assert 0.9 * fw.k_achieved < k < fw.k_achieved  # the coupler stores a little energy too


def test_tolerance_of_a_linkage_part(capsys):
    # docs/examples/watt.toml: a Watt six-bar in mm with [linkage.watt.tolerance.dimensions];
    # the same run made here in Python from the values written in the test (mm, radians)
    from machdyn.linkage import Linkage

    watt = str(Path(EXAMPLE).parent / "watt.toml")
    status, out, err = cli(capsys, "tolerance", watt, "--json", "--samples", "2000")
    assert status == 0, err
    part = json.loads(out)["parts"]["watt"]
    pts = {"O2": 0j, "O4": 60 + 0j, "O6": 100 + 30j, "A": 15 + 0j, "B": 47.5 + 37.997j,
           "C": 93.316 + 13.641j, "D": 75.444 + 54.94j, "P": 31.25 + 28.998j}  # fmt: skip
    lk = (Linkage(pts).ground("O2", "O4", "O6").link("crank", "O2", "A")
          .link("coupler", "A", "B", "P").link("rocker", "O4", "B", "C")
          .link("coupler2", "C", "D").link("output", "O6", "D").drive("crank"))  # fmt: skip
    angle = math.radians(0.05)
    tol = {
        "O2-O4": 0.1,
        "O6.p": 0.1,
        "O6.delta": angle,
        "O2-A": 0.1,
        "A-B": 0.1,
        "O4-B": 0.1,
        "C-D": 0.1,
        "O6-D": 0.1,
        "C.p": 0.1,
        "C.delta": angle,
        "P.p": 0.1,
        "P.delta": angle,
    }
    t = machdyn.tolerance(lk, tol, np.radians(np.arange(0.0, 360.0, 1.0)), samples=2000,
                          outputs=["point.P", "theta.output"])  # fmt: skip
    assert part["summary"]["+/- P.delta (3 sigma) [deg]"] == pytest.approx(0.05)
    assert part["summary"]["+/- C-D (3 sigma) [mm]"] == pytest.approx(0.1)
    P = np.array(part["tables"]["point.P"]["rows"], dtype=float)
    assert part["tables"]["point.P"]["columns"][3] == "rms [mm]"
    assert np.allclose(P[:, 3], t.outputs["point.P"].std)
    out_angle = np.array(part["tables"]["theta.output"]["rows"], dtype=float)
    assert np.allclose(out_angle[:, 2], np.degrees(t.outputs["theta.output"].std))
    status, out, err = cli(capsys, "tolerance", watt, "--part", "watt", "--samples", "10")
    assert status == 0 and "point.P: worst-case stack-up" in out


def test_a_linkage_tolerance_with_an_unknown_dimension_is_one_line(capsys, tmp_path):
    text = (Path(EXAMPLE).parent / "watt.toml").read_text(encoding="utf-8")
    path = tmp_path / "w.toml"
    path.write_text(text.replace('"C-D" = 0.1', '"C-E" = 0.1'), encoding="utf-8")
    status, out, err = cli(capsys, "tolerance", str(path), "--samples", "10")
    assert status == 1 and out == "" and err.count("\n") == 1
    assert "unknown dimension 'C-E'" in err and "O6-D" in err


def test_a_plot_of_a_file_shows_its_output_units(capsys, tmp_path):
    from machdyn.draw.simulation import plot_simulation
    from machdyn.simulate import ConstantTorque
    from machdyn.units import UnitSystem

    # a run in mm, g and s: its torques are in g*mm^2/s^2 = 1e-9 N*m = 1e-6 N*mm
    fb = machdyn.FourBar(80.0, 40.0, 70.0, 60.0)
    run = machdyn.simulate(fb, ConstantTorque(2e6), mass=(200.0, 300.0, 250.0),
                           inertia=(3e4, 1.2e5, 7.5e4), cg=(20.0, 35.0, 30.0),
                           t_end=0.05)  # fmt: skip
    units = UnitSystem(length="mm", mass="g", time="s", force="N", angular_velocity="rpm")
    fig = plot_simulation(run, units=units, title="in mm")
    q, w, effort = (ax.lines[0].get_ydata() for ax in fig.axes[:3])
    assert [ax.get_ylabel() for ax in fig.axes] == [
        "theta2 [deg]",
        "omega [rpm]",
        "motor torque [N*mm]",
    ]
    np.testing.assert_allclose(effort, run.motor_torque * 1e-6, rtol=1e-12)
    np.testing.assert_allclose(w, run.omega * 60.0 / (2.0 * math.pi), rtol=1e-12)
    np.testing.assert_allclose(q, np.degrees(run.theta), rtol=1e-12)
    assert fig._suptitle.get_text() == "in mm"
    with pytest.raises(machdyn.errors.InputError, match=r"units: must be a machdyn\.units"):
        plot_simulation(run, units="mm")
    # and the command line draws a file's run with them
    png = tmp_path / "run.png"
    status, out, err = cli(capsys, "simulate", EXAMPLE, "--plot", str(png))
    assert status == 0, err
    assert png.stat().st_size > 10_000 and f"wrote {png}" in out
