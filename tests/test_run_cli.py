"""`machdyn run FILE`: labelled tables, --json, --csv, --out, and bad input on the command line."""

from __future__ import annotations

import csv
import io
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from machdyn.cli import main
from machdyn.fourbar import FourBar

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
HW6 = str(EXAMPLES / "hw6.toml")


def run(capsys, *args: str) -> tuple[int, str, str]:
    status = main(["run", *args])
    out, err = capsys.readouterr()
    return status, out, err


def test_run_prints_every_column_with_its_unit(capsys):
    status, out, err = run(capsys, HW6)
    assert status == 0, err
    for label in ("theta3 [deg]", "omega4 [rad/s]", "alpha3 [rad/s^2]", "P_x [in]", "T12 [lbf*in]"):
        assert label in out
    assert "58.8114" in out  # the notes' HW 6: theta3 at theta2 = 0
    assert "GCRR" in out and "units: length in" in out


def test_json_rows_carry_the_same_labels_and_match_the_library(capsys):
    status, out, _ = run(capsys, HW6, "--json")
    assert status == 0
    data = json.loads(out)
    table = data["parts"]["hw6"]["tables"]["kinematics"]
    cols = table["columns"]
    assert cols[:3] == ["theta2 [deg]", "theta3 [deg]", "theta4 [deg]"]
    rows = np.array([r[:8] for r in table["rows"]], dtype=float)
    m = FourBar(8, 4, 7, 6).solve(np.radians(rows[:, 0]), omega2=10.0)
    np.testing.assert_allclose(rows[:, 2], np.degrees(m.theta4), rtol=1e-13)
    np.testing.assert_allclose(rows[:, cols.index("omega3 [rad/s]")], m.omega3, atol=1e-12)
    assert data["units"]["length"] == "in" and data["parts"]["hw6"]["kind"] == "fourbar"
    summary = data["parts"]["hw6"]["summary"]
    assert summary["mu over the sweep (min, max) [deg]"][0] == pytest.approx(34.7719, abs=5e-5)


def test_csv_has_units_in_the_header_and_full_precision(capsys):
    status, out, _ = run(capsys, HW6, "--csv")
    assert status == 0
    rows = list(csv.reader(io.StringIO(out)))
    assert rows[0][:2] == ["theta2 [deg]", "theta3 [deg]"] and rows[0][-2:] == ["ok", "reason"]
    theta3 = float(rows[1][1])
    # theta3 at theta2 = 0 by the law of cosines, written out here
    d, a, b, c = 8.0, 4.0, 7.0, 6.0
    gamma = math.acos((b * b + (d - a) ** 2 - c * c) / (2 * b * (d - a)))
    assert theta3 == pytest.approx(math.degrees(gamma), rel=1e-13)
    assert rows[1][-2:] == ["true", ""]


def test_out_writes_every_table_the_json_and_the_normalised_file(capsys, tmp_path):
    status, out, _ = run(capsys, HW6, "--out", str(tmp_path / "res"))
    assert status == 0 and "wrote" in out
    names = sorted(p.name for p in (tmp_path / "res").iterdir())
    assert names == [
        "hw6-coupler.csv",
        "hw6-forces.csv",
        "hw6-kinematics.csv",
        "machine.toml",
        "result.json",
    ]
    status, again, _ = run(capsys, str(tmp_path / "res" / "machine.toml"), "--json")
    assert (
        json.loads(again)["parts"]
        == json.loads((tmp_path / "res" / "result.json").read_text())["parts"]
    )


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["no/such.toml"], "no/such.toml: no such file"),
        ([HW6, "--part", "nope"], "--part: 'nope' is not a part; parts: hw6"),
        ([HW6, "--json", "--csv"], "--csv: choose one of --json and --csv"),
    ],
)
def test_bad_command_lines_get_one_line_and_status_1(capsys, args, needle):
    status, out, err = run(capsys, *args)
    assert status == 1 and out == ""
    assert err.count("\n") == 1 and needle in err and "Traceback" not in err


def test_a_bad_file_gets_file_line_and_key(capsys, tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(
        'machdyn = 1\n[units]\nlength = "mm"\n\n[fourbar.a]\nr1 = 8\nr2 = "4 kg"\nr3 = 7\nr4 = 6\n'
    )
    status, out, err = run(capsys, str(path))
    assert status == 1 and out == ""
    assert err == (
        f"machdyn: error: {path}:7: [fourbar.a] r2: expected a length like '120 mm', "
        "got '4 kg' (a mass)\n"
    )


def test_run_starts_without_loading_the_other_commands():
    code = (
        "import sys; from machdyn.cli import main; status = main(['run', sys.argv[1], '--json']); "
        "loaded = [m for m in ('machdyn.cams', 'machdyn.gears', 'scipy.optimize', 'rich.table') "
        "if m in sys.modules]; print(loaded, file=sys.stderr); sys.exit(status)"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, HW6], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    assert done.stderr.strip() == "[]"


def test_fourbar_takes_rpm_csv_and_a_machine_file(capsys, tmp_path):
    out = tmp_path / "fb.csv"
    args = ["fourbar", "8", "4", "7", "6", "--rpm", "60", "--theta2", "0:90:30", "--csv", str(out)]
    assert main(args) == 0
    rows = list(csv.reader(out.open()))
    assert rows[0][:4] == ["theta2 [deg]", "theta3 [deg]", "theta4 [deg]", "omega3 [rad/s]"]
    m = FourBar(8, 4, 7, 6).solve(np.radians([0.0, 30.0, 60.0, 90.0]), omega2=2 * math.pi)
    np.testing.assert_allclose([float(r[3]) for r in rows[1:]], m.omega3, rtol=1e-12)
    capsys.readouterr()
    assert main(["fourbar", "--spec", HW6, "--theta2", "0", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["lengths"] == {"r1": 8.0, "r2": 4.0, "r3": 7.0, "r4": 6.0} and data["omega2"] == 10
    assert data["kinematics"][0]["theta3_deg"] == pytest.approx(58.8114, abs=5e-5)  # HW 6
    for bad, needle in (
        (["fourbar", "8", "4", "7"], "give the four lengths"),
        (["fourbar", "8", "4", "7", "6", "--rpm", "1", "--omega2", "2"], "--rpm"),
        (["fourbar", "8", "4", "7", "6", "--spec", HW6], "not both"),
    ):
        assert main(bad) == 1 and needle in capsys.readouterr().err


def test_linkage_tables_never_cut_a_number(capsys):
    assert main(["linkage", str(EXAMPLES / "fourbar.toml"), "--forces"]) == 0
    out = capsys.readouterr().out
    assert "…" not in out and "F_coupler_rocker_y [lbf]" in out


def test_a_reader_that_stops_early_ends_the_run_quietly():
    """`machdyn run FILE --json | head -c 100`: the pipe closes mid-output; no error line
    (it printed "machdyn: error: Broken pipe"), no traceback, the status click gives its
    sub-commands in the same case (1)."""
    watt = EXAMPLES / "watt.toml"
    proc = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys; from machdyn.cli import main; sys.exit(main())",
            "run",
            str(watt),
            "--json",
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    proc.stdout.read(100)
    proc.stdout.close()  # the reader goes away while machdyn still writes
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 1
    assert err == ""


def test_fourbar_of_a_placed_part_gives_its_coupler_point_in_the_plane(capsys, tmp_path):
    """HW 6 placed at O2 = (1, 2), O2 -> O4 at 30 deg: A and B by circles in the plane,
    P = A + p e^{j(angle AB + delta)}; the angles stay measured from O2 -> O4."""
    from closed_forms import circle_meet

    text = Path(HW6).read_text(encoding="utf-8")
    placed = text.replace("r1 = 8 ", "O2 = [1, 2]\ntheta1 = 30\nr1 = 8 ", 1)
    (tmp_path / "placed.toml").write_text(placed, encoding="utf-8")
    assert (
        main(["fourbar", "--spec", str(tmp_path / "placed.toml"), "--theta2", "50", "--json"]) == 0
    )
    data = json.loads(capsys.readouterr().out)
    row = data["kinematics"][0]
    o2, t1 = 1 + 2j, math.radians(30.0)
    o4 = o2 + 8 * np.exp(1j * t1)
    a = o2 + 4 * np.exp(1j * (t1 + math.radians(50.0)))

    def theta3_deg(b):  # from the ground line O2 -> O4
        return math.degrees(np.angle((b - a) * np.exp(-1j * t1)))

    sides = (circle_meet(a, 7, o4, 6, s) for s in (1, -1))
    (b,) = [b for b in sides if abs(theta3_deg(b) - row["theta3_deg"]) < 1e-6]
    p = a + 5 * np.exp(1j * (np.angle(b - a) + math.radians(30.0)))
    assert complex(row["P"]["x"], row["P"]["y"]) == pytest.approx(complex(p), abs=1e-9)
    assert data["placed"]["theta1_deg"] == pytest.approx(30.0)
    assert main(["fourbar", "--spec", str(tmp_path / "placed.toml"), "--theta2", "50"]) == 0
    assert "placed O2 = (1, 2), theta1 = 30 deg" in capsys.readouterr().out
