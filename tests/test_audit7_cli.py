"""Audit 7: the command line refuses bad input in one line naming the field, never a traceback.

A broad sample of malformed arguments and files across the subcommands (each
case says which option or key the message must name), plus the one this audit
found accepted: a driver given twice to ``machdyn linkage`` (``--at crank=90
--at crank=91`` silently used the last).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from machdyn.cli import main

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
FOURBAR = str(EXAMPLES / "fourbar.toml")
TORQUE = str(EXAMPLES / "torque.csv")
CAM = [
    "-s",
    "rise:cycloidal:1:60",
    "-s",
    "dwell:120",
    "-s",
    "fall:cycloidal:1:60",
    "-s",
    "dwell:120",
]

CASES = [
    (["fourbar", "0", "2", "3", "4"], "r1"),
    (["fourbar", "8", "4", "7", "6", "--form", "3"], "form"),
    (["fourbar", "8", "4", "7", "6", "--theta2", "0:360:0"], "theta2"),
    (["fourbar", "8", "4", "7", "6", "--coupler", "x:y"], "coupler"),
    (["fourbar", "1", "10", "1", "1"], ""),
    (["flywheel", TORQUE, "--omega-avg", "10", "--k", "0.7"], "k"),
    (["flywheel", TORQUE, "--omega-avg", "-10", "--k", "0.02"], "omega_avg"),
    (["flywheel", TORQUE, "--omega-avg", "10", "--k", "0.02", "--period-deg", "0"], "period"),
    (["cam", *CAM, "--prime-radius", "3", "--roller-radius", "5"], "roller-radius"),
    (
        ["cam", *CAM, "--prime-radius", "3", "--roller-radius", "0.5", "--eccentricity", "4"],
        "prime",
    ),
    (["cam", *CAM, "--prime-radius", "3", "--follower", "bogus"], "follower"),
    (["cam", *CAM, "--prime-radius", "3", "--max-pressure-angle", "100"], "max-pressure-angle"),
    (["cam", "-s", "rise:cycloidal:1:60", "-s", "dwell:300"], ""),
    (["cam", "-s", "rise:bogus:1:60", *CAM[2:], "--prime-radius", "3"], "law"),
    (["gear", "pair", "--np", "20", "--ng", "40", "-m", "2", "--phi", "50"], "phi"),
    (["gear", "pair", "--np", "20", "--ng", "40", "-m", "2", "-C", "1000"], "center-distance"),
    (["gear", "pair", "--np", "20", "--ng", "40", "-m", "2", "--driver", "x"], "driver"),
    (["gear", "train", "20:40:bogus"], "stage 1"),
    (
        [
            "gear",
            "planetary",
            "--sun",
            "40",
            "--planet",
            "20",
            "--ring",
            "81",
            "--speed",
            "arm=1",
            "--speed",
            "sun=2",
        ],
        "ring",
    ),
    (["balance", "static", "--mass", "1,2"], "mass"),
    (["balance", "static", "--mass", "1,2,3", "--radius", "-1"], "radius"),
    (
        [
            "synth",
            "function",
            "--f",
            "__import__('os')",
            "--x",
            "1:10",
            "--theta2",
            "30:120",
            "--theta4",
            "60:150",
        ],
        "f",
    ),
    (
        [
            "synth",
            "function",
            "--f",
            "x",
            "--x",
            "1:10",
            "--theta2",
            "30:120",
            "--theta4",
            "60:150",
            "--n",
            "2",
        ],
        "n",
    ),
    (["linkage", FOURBAR, "--sweep", "crank=0:90:0"], "sweep crank"),
    (["linkage", FOURBAR, "--at", "crank=90", "--at", "crank=91"], "at crank"),
    (["linkage", FOURBAR, "--sweep", "crank=0:90:10", "--at", "crank=91"], "at crank"),
    (["run", "/nonexistent/file.toml"], "nonexistent"),
    (["spec", "check", str(EXAMPLES)], "examples"),
]


@pytest.mark.parametrize(("args", "field"), CASES, ids=[" ".join(c[0][:3]) for c in CASES])
def test_bad_input_is_one_line_naming_the_field(args, field, capsys):
    status = main(args)
    out = capsys.readouterr()
    assert status not in (0, None)
    lines = out.err.strip().splitlines()
    assert len(lines) == 1, out.err
    assert "Traceback" not in out.err and "internal error" not in out.err
    assert lines[0].startswith("machdyn: error:")
    assert field in lines[0]


def test_a_driver_held_once_still_works(capsys):
    assert main(["linkage", FOURBAR, "--at", "crank=91"]) in (0, None)
    out = capsys.readouterr().out
    lines = out.splitlines()
    header = lines.index("Kinematics of hw6") + 1
    row = dict(zip(lines[header].split()[::2], lines[header + 1].split(), strict=False))
    # the drawn circuit at theta2 = 91 deg, by two circles: |B - A| = 7, |B - O4| = 6, with B
    # on the side of A -> O4 where it is drawn at theta2 = 0 (y_B > 0)
    A, O4 = 4 * np.exp(1j * np.radians(91.0)), 8.0 + 0j
    d = abs(O4 - A)
    along = (d**2 + 7**2 - 6**2) / (2 * d)
    B = A + (O4 - A) / d * complex(along, math.sqrt(7**2 - along**2))
    assert float(row["theta_crank"]) == 91.0
    assert float(row["theta_coupler"]) == pytest.approx(math.degrees(np.angle(B - A)), abs=1e-4)
    assert float(row["theta_rocker"]) == pytest.approx(math.degrees(np.angle(B - O4)), abs=1e-4)
    assert lines[header + 1].split()[-1] == "yes"
