"""The command line: output, JSON, and one-line errors with a non-zero exit."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from machdyn.cli import main


def run(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_demo_prints_class_limits_and_table(capsys):
    code, out, err = run(capsys, "demo")
    assert code == 0 and err == ""
    assert "GCRR" in out and "Grashof crank-rocker-rocker" in out
    assert "min transmission angle mu = 34.7719 deg" in out  # arccos(69/84), see test_fourbar
    assert "theta3 deg" in out and "Px" in out


def test_fourbar_json_matches_the_library(capsys):
    code, out, _ = run(capsys, "fourbar", "8", "4", "7", "6", "--theta2", "0:90:15", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["class"]["code"] == "GCRR"
    rows = data["kinematics"]
    assert [r["theta2_deg"] for r in rows] == pytest.approx([0, 15, 30, 45, 60, 75, 90])
    # θ4 at θ2 = 0 by the law of cosines (HW 6)
    assert rows[0]["theta4_deg"] == pytest.approx(180 - np.degrees(np.arccos(3 / 48)))


def test_rocker_outside_range_is_reported_per_row(capsys):
    code, out, _ = run(capsys, "fourbar", "6", "9", "3", "8", "--theta2", "20:60:20")
    assert code == 0
    assert "theta2 = 20 deg: cannot be assembled" in out


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["fourbar", "20", "4", "7", "6"], "cannot be assembled"),
        (["fourbar", "8", "4", "7", "6", "--theta2", "abc"], "--theta2"),
        (["fourbar", "8", "4", "7", "6", "--form", "3"], "--form"),
        (["fourbar", "8", "0", "7", "6"], "r2: must be a positive length"),
        (["fourbar", "8", "4", "7"], "give the four lengths"),
        (["nosuchcommand"], "No such command"),
    ],
)
def test_errors_are_one_line_and_non_zero(capsys, args, needle):
    code, out, err = run(capsys, *args)
    assert code != 0
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("machdyn: error:")
    assert needle in lines[0]
    assert "Traceback" not in err + out


def test_console_script_exit_status():
    # The installed entry point, as a user runs it.
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            "import sys; from machdyn.cli import main; sys.exit(main())",
            "fourbar",
            "1",
            "1",
            "1",
            "9",
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 1
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr


def test_unwritable_output_is_one_line(capsys, tmp_path):
    missing = tmp_path / "no" / "such" / "dir" / "out.png"
    code, _, err = run(capsys, "animate", "8", "4", "7", "6", "--out", str(missing))
    assert code == 1
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "No such file or directory" in err


def test_non_utf8_input_is_one_line(capsys, tmp_path):
    csv = tmp_path / "torque.csv"
    csv.write_bytes(b"theta,torque\n0,1\n\xff\xfe,2\n")
    code, _, err = run(capsys, "flywheel", str(csv), "--omega-avg", "10", "--k", "0.05")
    assert code == 1
    assert err.count("\n") == 1 and "Traceback" not in err
