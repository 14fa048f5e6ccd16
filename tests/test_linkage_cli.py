"""`machdyn linkage FILE`: the example files against closed forms, outputs, bad input."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from machdyn.cli import app, main
from machdyn.fourbar import FourBar

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
FOURBAR = str(EXAMPLES / "fourbar.toml")
LID = str(EXAMPLES / "lid.toml")


def invoke(*args: str) -> str:
    result = CliRunner().invoke(app, ["linkage", *args])
    assert result.exit_code == 0, result.output
    return result.stdout


def rows_of(*args: str) -> list[dict]:
    """One dict per sample, every table of the part joined (names carry their units)."""
    data = json.loads(invoke(*args, "--json"))
    (part,) = data["parts"].values()
    rows: list[dict] = []
    for table in part["tables"].values():
        for i, row in enumerate(table["rows"]):
            if len(rows) <= i:
                rows.append({})
            rows[i].update(zip(table["columns"], row, strict=True))
    return rows


def column(rows: list[dict], name: str) -> np.ndarray:
    return np.array([r[name] for r in rows], dtype=float)


# ------------------------------------------------------------------ the HW 6 four-bar
def test_hw6_file_reproduces_the_notes_angles_in_the_table():
    out = invoke(FOURBAR, "--at", "crank=0")
    # the notes' HW 6 (GCRR 8-4-7-6) at theta2 = 0: theta3 = 58.8114 deg, theta4 = 93.5833 deg
    assert "58.8114" in out and "93.5833" in out
    assert "[deg]" in out and "[rad/s]" in out and "[rad/s^2]" in out and "P_x [in]" in out
    assert "VP_y [in/s]" in out and "AP_x [in/s^2]" in out  # point velocity, acceleration


def test_hw6_file_matches_fourbar_closed_form_over_a_turn():
    rows = rows_of(FOURBAR)  # the file's sweep: 0:360:30, omega2 = 10 rad/s, alpha2 = 0
    theta2 = np.radians(np.arange(0.0, 361.0, 30.0))
    fb = FourBar(8, 4, 7, 6, coupler=(5.0, math.radians(30.0))).solve(theta2, omega2=10.0)
    np.testing.assert_allclose(column(rows, "theta_crank [deg]"), np.degrees(theta2), atol=1e-12)
    wrap = lambda deg: (deg + 180.0) % 360.0 - 180.0  # noqa: E731
    for name, ref in (("coupler", fb.theta3), ("rocker", fb.theta4)):
        diff = wrap(column(rows, f"theta_{name} [deg]") - np.degrees(ref))
        np.testing.assert_allclose(diff, 0.0, atol=1e-9)
    np.testing.assert_allclose(column(rows, "omega_coupler [rad/s]"), fb.omega3, atol=1e-9)
    np.testing.assert_allclose(column(rows, "omega_rocker [rad/s]"), fb.omega4, atol=1e-9)
    np.testing.assert_allclose(column(rows, "alpha_coupler [rad/s^2]"), fb.alpha3, atol=1e-7)
    np.testing.assert_allclose(column(rows, "alpha_rocker [rad/s^2]"), fb.alpha4, atol=1e-7)
    np.testing.assert_allclose(column(rows, "P_x [in]"), fb.coupler.real, atol=1e-9)
    np.testing.assert_allclose(column(rows, "P_y [in]"), fb.coupler.imag, atol=1e-9)
    assert all(r["ok"] and r["reason"] == "" for r in rows)
    # point velocity and acceleration of P against the closed form's coupler point
    np.testing.assert_allclose(column(rows, "VP_x [in/s]"), fb.coupler_velocity.real, atol=1e-9)
    np.testing.assert_allclose(
        column(rows, "AP_y [in/s^2]"), fb.coupler_acceleration.imag, atol=1e-7
    )
    assert rows[0]["theta_coupler [deg]"] == pytest.approx(58.8114, abs=5e-5)  # notes, HW 6
    assert rows[0]["theta_rocker [deg]"] == pytest.approx(93.5833, abs=5e-5)


def test_sweep_and_at_override_the_file():
    rows = rows_of(FOURBAR, "--sweep", "crank=10:40:15")
    assert column(rows, "theta_crank [deg]").tolist() == pytest.approx([10.0, 25.0, 40.0])
    one = rows_of(FOURBAR, "--at", "crank=45")
    fb = FourBar(8, 4, 7, 6).solve(np.radians([45.0]), omega2=10.0)
    assert len(one) == 1
    assert one[0]["omega_rocker [rad/s]"] == pytest.approx(float(fb.omega4[0]), abs=1e-9)


def test_json_carries_units_and_forces():
    data = json.loads(invoke(FOURBAR, "--at", "crank=30", "--forces", "--json"))
    part = data["parts"]["hw6"]
    kin, forces = part["tables"]["kinematics"], part["tables"]["forces"]
    assert {"theta_coupler [deg]", "omega_coupler [rad/s]"} <= set(kin["columns"])
    assert {"T_crank [lbf*in]", "F_ground_crank_x [lbf]"} <= set(forces["columns"])
    assert data["units"]["length"] == "in"
    row = dict(zip(forces["columns"], forces["rows"][0], strict=True))
    for key in ("T_crank [lbf*in]", "F_ground_crank_x [lbf]", "F_crank_coupler_y [lbf]"):
        assert math.isfinite(row[key])


# ------------------------------------------------------------------ the lid with a gas spring
def lid_torque_by_hand(theta, omega, alpha):
    """Hinge moment balance of the lid in docs/examples/lid.toml, about O2 (fixed)."""
    m, i_g, a, g = 4.0, 0.2133, 0.4, 9.81  # the file: gravity = "9.81 m/s^2"
    k, free, c, pre = 500.0, 0.5, 20.0, -150.0  # gas spring S -> Q (on the lid)
    kt, free_angle = 2.0, math.radians(10.0)  # torsion spring ground -> lid at O2
    s, q = complex(0.15, -0.3), 0.2 * np.exp(1j * theta)
    vq = 1j * omega * q
    length = abs(q - s)
    u = (q - s) / length
    rate = (vq * u.conjugate()).real
    tension = k * (length - free) + c * rate + pre
    f_on_lid = -tension * u  # -T u on the lid at the spring's end Q
    m_spring = (q.conjugate() * f_on_lid).imag  # r x F
    m_gravity = -m * g * a * np.cos(theta)
    tau = kt * (theta - free_angle)  # -tau acts on the lid
    i_o = i_g + m * a**2
    torque = i_o * alpha - m_spring - m_gravity + tau
    a_g = (1j * alpha - omega**2) * a * np.exp(1j * theta)
    pin = m * a_g - f_on_lid + 1j * m * g  # F_ground_lid from sum F = m a_G
    return torque, pin, tension, tau


def test_lid_driver_torque_equals_the_hinge_moment_by_hand():
    rows = rows_of(LID, "--forces")  # the file's sweep 0:90:15, omega 0.5, alpha 0.2
    theta = np.radians(column(rows, "theta_lid [deg]"))
    assert theta.size == 7
    torque, pin, tension, tau = lid_torque_by_hand(theta, 0.5, 0.2)
    np.testing.assert_allclose(column(rows, "T_lid [N*m]"), torque, atol=1e-9)
    np.testing.assert_allclose(column(rows, "F_ground_lid_x [N]"), pin.real, atol=1e-9)
    np.testing.assert_allclose(column(rows, "F_ground_lid_y [N]"), pin.imag, atol=1e-9)
    np.testing.assert_allclose(column(rows, "T_gas [N]"), tension, atol=1e-9)
    np.testing.assert_allclose(column(rows, "tau_hinge [N*m]"), tau, atol=1e-12)
    np.testing.assert_allclose(column(rows, "Q_x [m]"), 0.2 * np.cos(theta), atol=1e-12)
    assert (column(rows, "T_gas [N]") < 0).all()  # a gas spring pushes


def test_lid_table_prints_forces_with_units():
    out = invoke(LID, "--at", "lid=45", "--forces")
    torque = lid_torque_by_hand(math.radians(45.0), 0.5, 0.2)[0]
    assert f"{torque:.4f}" in out
    assert "T_lid [N*m]" in out and "Forces on lid" in out and "Kinematics of lid" in out


def test_csv_has_the_expected_columns(tmp_path):
    out = tmp_path / "lid.csv"
    invoke(LID, "--forces", "--csv", str(out))
    with open(out, newline="") as fh:
        table = list(csv.reader(fh))
    assert table[0] == [
        "theta_lid [deg]",
        "omega_lid [rad/s]",
        "alpha_lid [rad/s^2]",
        *(
            f"{p}_{xy} [{u}]"
            for p, u in (("A", "m"), ("VA", "m/s"), ("AA", "m/s^2"))
            for xy in "xy"
        ),
        *(
            f"{p}_{xy} [{u}]"
            for p, u in (("Q", "m"), ("VQ", "m/s"), ("AQ", "m/s^2"))
            for xy in "xy"
        ),
        "T_lid [N*m]",
        "F_ground_lid_x [N]",
        "F_ground_lid_y [N]",
        "T_gas [N]",
        "tau_hinge [N*m]",
        "ok",
        "reason",
    ]
    assert len(table) == 1 + 7
    torque = lid_torque_by_hand(math.radians(90.0), 0.5, 0.2)[0]
    assert float(table[-1][table[0].index("T_lid [N*m]")]) == pytest.approx(torque, abs=1e-9)
    assert table[-1][-2:] == ["true", ""]


def test_a_slider_crank_file_reports_the_slide_and_its_force(tmp_path):
    path = tmp_path / "sc.toml"
    path.write_text(
        """
ground = ["O2"]
drive = ["crank"]
[points]
O2 = [0, 0]
A = [2, 0]
B = [8, 0]
[[link]]
name = "crank"
points = ["O2", "A"]
[[link]]
name = "rod"
points = ["A", "B"]
[[link]]
name = "block"
points = ["B"]
[[slider]]
name = "guide"
block = "block"
on = "ground"
at = "B"
direction = 0.0
[motion.crank]
value = 90
velocity = 1.0
"""
    )
    (row,) = rows_of(str(path), "--forces")
    # slider-crank a = 2, b = 6 at theta2 = 90 deg: x_B = sqrt(36 - 4), xdot_B = -a omega2
    # an old-format file without units: lengths labelled L, forces F, time T
    assert row["d_guide [L]"] == pytest.approx(math.sqrt(32.0), abs=1e-12)
    assert row["ddot_guide [L/T]"] == pytest.approx(-2.0, abs=1e-12)
    assert row["T_crank [F*L]"] == pytest.approx(0.0, abs=1e-12)  # massless, no load


# ------------------------------------------------------------------ bad input
GOOD = """\
machdyn = 1
[linkage.fb]
ground = ["O2", "O4"]
drive = ["crank"]
[linkage.fb.points]
O2 = [0, 0]
O4 = [8, 0]
A = [4, 0]
B = [7.625, 5.988269783501742]
[linkage.fb.links.crank]
points = ["O2", "A"]
[linkage.fb.links.coupler]
points = ["A", "B"]
[linkage.fb.links.rocker]
points = ["O4", "B"]
[linkage.fb.motion.crank]
sweep = [0, 60, 30]
"""
#: The same linkage in the format before machine files (still read, with a note).
OLD = """\
ground = ["O2", "O4"]
drive = ["crank"]
[points]
O2 = [0, 0]
O4 = [8, 0]
A = [4, 0]
B = [7.625, 5.988269783501742]
[[link]]
name = "crank"
points = ["O2", "A"]
[[link]]
name = "coupler"
points = ["A", "B"]
[[link]]
name = "rocker"
points = ["O4", "B"]
[motion.crank]
sweep = [0, 60, 30]
"""


def run_main(capsys, *args):
    code = main(["linkage", *args])
    out, err = capsys.readouterr()
    return code, out, err


def test_the_good_file_runs(tmp_path, capsys):
    path = tmp_path / "good.toml"
    path.write_text(GOOD)
    code, out, err = run_main(capsys, str(path))
    assert code == 0 and err == "" and "58.8114" in out


ROCKER = 'points = ["O4", "B"]'
MOTION = "[linkage.fb.motion.crank]\nsweep = [0, 60, 30]\n"


@pytest.mark.parametrize(
    ("text", "args", "needles"),
    [
        (None, (), ["no such file"]),
        (GOOD.replace("fb.points]", "fb.points"), (), ["bad.toml:5: TOML syntax error"]),
        (
            GOOD.replace('points = ["O2", "A"]', 'points = ["O2", "A"]\nmas = 1.0'),
            (),
            ["bad.toml:12: [linkage.fb.links.crank] mas: unknown key; valid keys: points, mass"],
        ),
        (GOOD.replace("[linkage.fb.motion.", "[linkage.fb.motoin."), (), ["motoin", "valid keys"]),
        (
            GOOD.replace(ROCKER, ROCKER + '\nmass = "heavy"'),
            (),
            ["bad.toml:16: [linkage.fb.links.rocker] mass: expected a mass like '2.5 kg'"],
        ),
        (GOOD.replace('["O4", "B"]', '["O4", "Z"]'), (), ["links.rocker]", "'Z'"]),
        (GOOD.replace(ROCKER, 'points = "O4"'), (), ["links.rocker] points"]),
        (GOOD.replace("O4 = [8, 0]", "O4 = [8]"), (), ["bad.toml:7: [linkage.fb.points] O4"]),
        (GOOD.replace('drive = ["crank"]', 'drive = ["crnak"]'), (), ["drive", "crnak"]),
        (GOOD + 'report = ["Q"]', (), ["motion.crank] report", "valid keys: value, sweep"]),
        (
            GOOD.replace('drive = ["crank"]', 'drive = ["crank"]\nreport = ["Q"]'),
            (),
            ["report[1]", "'Q'"],
        ),
        (GOOD.replace("machdyn = 1", "machdyn = 1\ngravity = -9.81"), (), ["gravity", ">= 0"]),
        (
            GOOD.replace("fb.motion.crank]", "fb.motion.rocker]"),
            (),
            ["motion.rocker", "drivers: crank"],
        ),
        (GOOD.replace("sweep = [0, 60, 30]", "sweep = [0, 60]"), (), ["motion.crank] sweep"]),
        (GOOD, ("--sweep", "rocker=0:10:5"), ["--sweep", "'rocker' is not a driver"]),
        (GOOD, ("--sweep", "crank=a:b"), ["--sweep crank"]),
        (GOOD, ("--at", "crank"), ["--at", "DRIVER="]),
        (GOOD, ("--at", "crank=3 kg"), ["--at crank: expected an angle like '30 deg'"]),
        (GOOD.replace(MOTION, ""), (), ["no value", "--sweep"]),
        (GOOD.replace("[linkage.fb.links.crank]", "[linkage.fb.links.crank"), (), ["TOML syntax"]),
        (GOOD.replace("drive = [", "drive = 3 #"), (), ["drive", "array of names"]),
        (OLD.replace('name = "crank"', 'name = "crank"\nmas = 1.0'), (), ["bad.toml:10: ", "mas"]),
        (OLD.replace('name = "coupler"', 'name = "crank"'), (), ["[link[2]] name", "named twice"]),
    ],
)
def test_bad_input_is_one_line_and_non_zero(tmp_path, capsys, text, args, needles):
    # every message names the TOML key or the option (arrays counted from 1)
    path = tmp_path / "bad.toml"
    if text is not None:
        path.write_text(text)
    code, _, err = run_main(capsys, str(path), *args)
    assert code != 0
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("machdyn: error:")
    for needle in needles:
        assert needle in lines[0]


def test_a_pose_that_cannot_be_assembled_is_flagged_not_fatal(tmp_path, capsys):
    # the HW 6 rocker swings between about 77 and 162 deg (FourBar limits): 60 deg is outside
    path = tmp_path / "rocker.toml"
    path.write_text(
        GOOD.replace('drive = ["crank"]', 'drive = ["rocker"]').replace(
            MOTION, "[linkage.fb.motion.rocker]\nsweep = [60, 90, 30]\n"
        )
    )
    extrema = FourBar(8, 4, 7, 6).extrema(1)["theta4"]
    assert np.degrees(extrema.min) > 60.0  # the reference for the flag
    code, out, err = run_main(capsys, str(path), "--json")
    assert code == 0 and err == ""
    table = json.loads(out)["parts"]["fb"]["tables"]["kinematics"]
    first, second = (dict(zip(table["columns"], r, strict=True)) for r in table["rows"])
    assert first["ok"] is False and "cannot assemble" in first["reason"]
    assert first["theta_crank [deg]"] is None  # not a silent NaN: null with a reason
    assert second["ok"] is True
    code, out, _ = run_main(capsys, str(path))
    assert code == 0 and "theta_rocker [deg] = 60: cannot assemble" in out


def test_the_example_in_the_docs_is_the_example_file():
    import tomllib

    text = (EXAMPLES.parents[0] / "linkage.md").read_text(encoding="utf-8")
    block = text.split("## From the command line", 1)[1].split("```toml\n", 1)[1]
    shown = tomllib.loads(block.split("```", 1)[0])
    with open(FOURBAR, "rb") as fh:
        assert shown == tomllib.load(fh)


def test_an_old_linkage_file_reads_with_a_note(tmp_path, capsys):
    path = tmp_path / "old.toml"
    path.write_text(OLD + "velocity = 10.0\n")
    code, out, err = run_main(capsys, str(path), "--at", "crank=0")
    assert code == 0 and "58.8114" in out
    assert "old linkage file" in err and "machdyn spec upgrade" in err
