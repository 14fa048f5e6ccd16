"""``machdyn gear ...`` through typer's CliRunner on ``gear_app``."""

import json
import math

import pytest
from typer.testing import CliRunner

from machdyn import InputError
from machdyn.cli.gear import gear_app

runner = CliRunner()


def _run(*args):
    return runner.invoke(gear_app, list(args))


def test_pair_final_exam_set_json():
    # The notes' final exam: r_p = 1.5, r_g = 3.75, a = 0.125 in -> P_d = 8, 24/60 teeth.
    res = _run("pair", "--np", "24", "--ng", "60", "--pd", "8", "--json")
    assert res.exit_code == 0, res.output
    data = json.loads(res.output)
    assert data["length_of_action"] == pytest.approx(0.6249, abs=1e-4)
    assert data["contact_ratio"] == pytest.approx(
        0.6249 / (math.pi / 8 * math.cos(math.radians(20))), abs=1e-3
    )
    assert data["contact_ratio_rating"] == "good"
    assert data["interferes"] is False
    assert data["pinion"]["pitch_radius"] == pytest.approx(1.5)
    assert data["length_unit"] == "in"


def test_pair_table_reports_interference():
    res = _run("pair", "--np", "13", "--ng", "30", "--module", "2")
    assert res.exit_code == 0, res.output
    assert "interference_gear_tip" in res.output
    assert "contact_ratio" in res.output
    line = next(s for s in res.output.splitlines() if "interference_gear_tip" in s)
    assert line.split()[-1] == "yes"  # 13 teeth take at most 16 (Norton Table 9-5)


def test_pair_operating_center_distance():
    res = _run("pair", "--np", "20", "--ng", "40", "-m", "2", "-C", "60.5", "--json")
    data = json.loads(res.output)
    cos_op = 60 / 60.5 * math.cos(math.radians(20))
    assert data["operating_pressure_angle_deg"] == pytest.approx(math.degrees(math.acos(cos_op)))
    assert data["velocity_ratio"] == pytest.approx(-0.5)
    assert data["backlash"] > 0


def test_pair_bad_input_names_the_problem():
    res = _run("pair", "--np", "20", "--ng", "40", "-m", "2", "-C", "59")
    assert isinstance(res.exception, InputError)
    assert "center_distance" in str(res.exception)
    res = _run("pair", "--np", "20", "--ng", "40")
    assert isinstance(res.exception, InputError) and "--module" in str(res.exception)
    res = _run("pair", "--np", "20.5", "--ng", "40", "-m", "2")
    assert res.exit_code == 2 and "--np" in res.output


def test_min_teeth_table():
    res = _run("min-teeth", "--json")
    rows = json.loads(res.output)
    assert [(r["rack"], r["equal_gears"]) for r in rows] == [(32, 23), (18, 13), (12, 9)]
    res = _run("min-teeth", "--phi", "20", "--ng", "101")
    assert res.exit_code == 0 and "16" in res.output


def test_train_and_reverted():
    res = _run("train", "20:40,30:90:internal", "--json")
    assert json.loads(res.output)["train_value"] == pytest.approx(-1 / 6)
    res = _run("train", "20-40")
    assert isinstance(res.exception, InputError)
    res = _run("reverted", "18", "--json")
    data = json.loads(res.output)
    n2, n3, n4, n5 = data["teeth"]
    assert n2 + n3 == n4 + n5 and n3 * n5 == 18 * n2 * n4
    res = _run("reverted", "5000")
    assert isinstance(res.exception, InputError) and "impossible" in str(res.exception)


def test_planetary_norton_example():
    res = _run(
        "planetary", "--sun", "40", "--planet", "20", "--ring", "80",
        "--speed", "arm=-200", "--speed", "sun=100", "--json",
    )  # fmt: skip
    data = json.loads(res.output)
    assert data["total"][data["members"].index("ring")] == pytest.approx(-350)
    res = _run("planetary", "--sun", "40", "--planet", "20", "--ring", "80", "--speed", "sun=1")
    assert isinstance(res.exception, InputError)


@pytest.mark.parametrize("suffix", [".svg", ".dxf", ".csv", ".png"])
def test_profile_export(tmp_path, suffix):
    out = tmp_path / f"gear{suffix}"
    res = _run("profile", "-N", "18", "-m", "2", "-o", str(out))
    assert res.exit_code == 0, res.output
    assert out.exists() and out.stat().st_size > 0


def test_profile_bad_suffix(tmp_path):
    res = _run("profile", "-N", "18", "-m", "2", "-o", str(tmp_path / "gear.txt"))
    assert isinstance(res.exception, InputError)


def test_plot_pair(tmp_path):
    out = tmp_path / "mesh.png"
    res = _run("plot", "--np", "18", "--ng", "40", "-m", "1", "-o", str(out))
    assert res.exit_code == 0, res.output
    assert out.read_bytes()[:4] == b"\x89PNG"
