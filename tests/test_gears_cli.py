"""``machdyn gear ...`` through typer's CliRunner on ``gear_app``."""

import json
import math

import numpy as np
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
    assert str(res.exception).startswith("--center-distance: ")
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
    # a 16-tooth gear is below the equal-gear minimum at 14.5° (23) but not at 20° (13)
    res = _run("min-teeth", "--phi", "14.5", "--phi", "20", "--ng", "16", "--json")
    rows = json.loads(res.output)
    assert [r["gear_16"] for r in rows] == ["none", 13]


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


# --------------------------------------------------------------------------
# Review findings 2 and 13: one line, exit 1, worded for CLI users
# --------------------------------------------------------------------------
def _main(capsys, *args):
    from machdyn.cli import main

    status = main(["gear", *args])
    out = capsys.readouterr()
    return status, out.out, out.err


def test_pair_pulled_out_of_contact_exits_with_one_line(capsys):
    # The review's reproducer: the notes' exam set (24/60 teeth, P_d = 8) at C' = 7.5 in,
    # where the addendum circles (1.625 + 3.875 = 5.5) do not even touch. By hand the
    # last centre distance with contact is sqrt(2.42046^2 + 4.93339^2) = 5.49518 in.
    status, out, err = _main(capsys, "pair", "--np", "24", "--ng", "60", "--pd", "8", "-C", "7.5")
    assert status == 1 and out == ""
    assert err.count("\n") == 1
    assert err.startswith("machdyn: error: --center-distance: 7.5 is too large")
    assert "lose contact" in err and "5.4951" in err
    for bad in ("nan", "inf"):
        res = _run("pair", "--np", "24", "--ng", "60", "--pd", "8", "-C", bad)
        assert isinstance(res.exception, InputError)
        assert res.exception.field == "--center-distance"


def test_pair_just_inside_the_contact_limit_is_reported_as_no_contact():
    res = _run("pair", "--np", "24", "--ng", "60", "--pd", "8", "-C", "5.49", "--json")
    assert res.exit_code == 0, res.output
    data = json.loads(res.output)
    assert 0 < data["contact_ratio"] < 1 and data["contact_ratio_rating"] == "no contact"


@pytest.mark.parametrize("phi", ["90", "45", "0", "-20", "nan"])
def test_phi_out_of_range_is_explained_in_degrees(phi):
    res = _run("pair", "--np", "20", "--ng", "40", "-m", "2", "--phi", phi)
    assert isinstance(res.exception, InputError)
    assert res.exception.field == "--phi"
    assert "degrees" in res.exception.message and "radians(" not in res.exception.message


@pytest.mark.parametrize(
    "args",
    [
        ("pair", "--np", "20", "--ng", "40", "-m", "2"),
        ("min-teeth",),
        ("reverted", "18"),
        ("profile", "-N", "20", "-m", "2", "-o", "unused.svg"),
    ],
)
def test_phi_typed_in_radians_is_refused_with_the_conversion(args):
    # 0.35 rad = 20.05 deg: accepting it as 0.35 deg gave contact ratio 4.0 rated "good".
    res = _run(*args, "--phi", "0.35")
    assert isinstance(res.exception, InputError) and res.exception.field == "--phi"
    assert "looks like radians (20.05°)" in res.exception.message


@pytest.mark.parametrize(
    ("args", "option"),
    [
        (("pair", "--np", "20", "--ng", "40", "-m", "2", "--thin-p", "5"), "--thin-p"),
        (("pair", "--np", "20", "--ng", "40", "-m", "2", "--thin-p", "2.5"), "--np"),
        (("pair", "--np", "20", "--ng", "40", "-m", "2", "--thin-g", "10"), "--thin-g"),
        (("pair", "--np", "20", "--ng", "40", "-m", "2", "--xp", "nan"), "--xp"),
        (("pair", "--np", "20", "--ng", "40", "-m", "2", "--pd", "8"), "--module"),
        (("pair", "--np", "20", "--ng", "40", "-m", "-2"), "--module"),
        (("pair", "--np", "20", "--ng", "40", "--pd", "0"), "--pd"),
        (("pair", "--np", "20", "--ng", "40", "-m", "2", "--system", "deep"), "--system"),
        (("pair", "--np", "20", "--ng", "20", "-m", "2", "--internal"), "--ng"),
        (("pair", "--np", "20", "--ng", "60", "-m", "2", "--internal", "-C", "30"),
         "--center-distance"),
        (("min-teeth", "--k", "-1"), "--k"),
        (("min-teeth", "--ng", "0"), "--ng"),
        (("reverted", "18", "--min-teeth", "2"), "--min-teeth"),
        (("reverted", "18", "--tolerance", "0"), "--tolerance"),
        (("reverted", "5000"), "RATIO"),
        (("profile", "-N", "20", "-m", "2", "--points", "2", "-o", "unused.svg"), "--points"),
        (("planetary", "--sun", "40", "--planet", "20", "--ring", "81",
          "--speed", "sun=1", "--speed", "arm=0"), "--ring"),
        (("planetary", "--sun", "40", "--planet", "20", "--ring", "80",
          "--speed", "moon=1", "--speed", "arm=0"), "--speed"),
        (("train", "20:0"), "stage 1"),
        (("train", "20:40:belt"), "stage 1"),
        (("plot", "--np", "20", "--ng", "40", "-m", "2", "--angle", "nan", "-o", "x.png"),
         "--angle"),
        (("plot", "--np", "20", "--ng", "40", "-m", "2", "-o", "0.5"), "--output"),
    ],
)  # fmt: skip
def test_errors_name_the_command_line_option(args, option):
    res = _run(*args)
    assert isinstance(res.exception, InputError), res.output
    assert res.exception.field == option


def test_pair_driver_option_swaps_approach_and_recess():
    # The notes' exam set by hand (see tests/test_gears.py): the gear's tip path from the pitch
    # point is 1.6119 - 1.2826 = 0.3293 in, the pinion's 0.8086 - 0.5130 = 0.2956 in.
    args = ("pair", "--np", "24", "--ng", "60", "--pd", "8", "--json")
    by_pinion = json.loads(_run(*args).output)
    by_gear = json.loads(_run(*args, "--driver", "gear").output)
    assert by_pinion["driver"] == "pinion" and by_gear["driver"] == "gear"
    assert by_pinion["path_of_approach"] == pytest.approx(0.3293, abs=1e-4)
    assert by_gear["path_of_approach"] == pytest.approx(0.2956, abs=1e-4)
    for member in ("pinion", "gear"):
        assert by_gear[f"angle_of_approach_{member}_deg"] == pytest.approx(
            by_pinion[f"angle_of_recess_{member}_deg"], rel=1e-12
        )
    table = _run(*args[:-1], "--driver", "gear").output
    row = next(s for s in table.splitlines() if "path_of_approach" in s)
    assert row.split()[-1] == "0.2956"


def test_driver_option_error_is_one_line(capsys, tmp_path):
    status, out, err = _main(capsys, "pair", "--np", "24", "--ng", "60", "--pd", "8",
                             "--driver", "ring")  # fmt: skip
    assert status == 1 and out == "" and err.count("\n") == 1
    assert err.startswith("machdyn: error: --driver: must be one of pinion, gear")
    res = _run("plot", "--np", "18", "--ng", "40", "-m", "1", "--driver", "gear",
               "-o", str(tmp_path / "m.png"))  # fmt: skip
    assert res.exit_code == 0, res.output
    res = _run("plot", "--np", "18", "--ng", "40", "-m", "1", "--driver", "wheel",
               "-o", str(tmp_path / "m.png"))  # fmt: skip
    assert isinstance(res.exception, InputError) and res.exception.field == "--driver"


def test_profile_cutter_teeth_for_an_internal_gear(tmp_path):
    out = tmp_path / "ring.csv"
    res = _run("profile", "-N", "60", "-m", "1", "--internal", "--cutter-teeth", "30",
               "-o", str(out))  # fmt: skip
    assert res.exit_code == 0, res.output
    assert "shaper cutter of 30 teeth" in res.output
    # The outline really is the one this cutter generates (not the default cutter's).
    from machdyn.gears import Gear, gear_outline

    ring = Gear(60, module=1.0, internal=True)
    rows = out.read_text().splitlines()[1:]
    expected = gear_outline(ring, 60, cutter_teeth=30)
    default = gear_outline(ring, 60)
    xs = np.array([float(r.split(",")[0]) for r in rows])
    assert xs == pytest.approx(expected.x, abs=1e-12)
    differs = default.x.size != expected.x.size or not np.allclose(default.x, expected.x)
    assert differs  # the cutter changes the fillet
    res = _run("profile", "-N", "60", "-m", "1", "--internal", "-o", str(out))
    assert "shaper cutter of 25 teeth" in res.output  # the default


@pytest.mark.parametrize(
    ("args", "message"),
    [
        # 20 deg full depth, 40 teeth: r_a = 19, r_b = 18.7939, sqrt(19^2 - r_b^2) = 2.7913;
        # 2 (20 - 2.7913 / sin 20) = 23.68, so at least 24 teeth; at most 40 - 8 = 32.
        (("--cutter-teeth", "23"), "must be from 24 to 32 to cut this 40-tooth ring, got 23"),
        (("--cutter-teeth", "33"), "must be from 24 to 32 to cut this 40-tooth ring, got 33"),
        (("--cutter-teeth", "0"), "must be from 24 to 32"),
        (("--cutter-teeth", "-5"), "must be from 24 to 32"),
    ],
)
def test_cutter_teeth_out_of_range_is_one_line(capsys, tmp_path, args, message):
    out = str(tmp_path / "r.svg")
    for command in (("profile", "-N", "40"), ("plot", "--np", "12", "--ng", "40")):
        status, stdout, err = _main(capsys, *command, "-m", "1", "--internal", *args, "-o", out)
        assert status == 1 and stdout == "" and err.count("\n") == 1, err
        assert err.startswith(f"machdyn: error: --cutter-teeth: {message}")


def test_cutter_teeth_needs_an_integer_and_an_internal_gear(capsys, tmp_path):
    out = str(tmp_path / "r.svg")
    status, _, err = _main(capsys, "profile", "-N", "40", "-m", "1", "--internal",
                           "--cutter-teeth", "24.5", "-o", out)  # fmt: skip
    assert status == 2 and err.count("\n") == 1 and "--cutter-teeth" in err
    for command in (("profile", "-N", "40"), ("plot", "--np", "12", "--ng", "40")):
        status, _, err = _main(capsys, *command, "-m", "1", "--cutter-teeth", "24", "-o", out)
        assert status == 1 and err.count("\n") == 1
        assert err.startswith("machdyn: error: --cutter-teeth: only an internal gear")
    res = _run("plot", "--np", "18", "--ng", "72", "-m", "1", "--internal",
               "--cutter-teeth", "40", "-o", str(tmp_path / "m.png"))  # fmt: skip
    assert res.exit_code == 0, res.output


def test_shifted_internal_gear_through_the_cli(tmp_path):
    # The published worksheet pair (see tests/test_gears.py): a_w = 21.1251 deg, a = 557.0887.
    res = _run("pair", "--np", "17", "--ng", "96", "-m", "14", "--xp", "0.2", "--xg", "0.5",
               "--internal", "--json")  # fmt: skip
    assert res.exit_code == 0, res.output
    data = json.loads(res.output)
    assert data["operating_pressure_angle_deg"] == pytest.approx(21.1251, abs=1e-4)
    assert data["center_distance"] == pytest.approx(557.0887, abs=1e-4)
    assert data["gear"]["addendum_radius"] == pytest.approx(672 - (1 - 0.5) * 14)
    out = tmp_path / "ring.csv"
    res = _run("profile", "-N", "60", "-m", "2", "--internal", "--shift", "0.3", "-o", str(out))
    assert res.exit_code == 0, res.output
    r = [math.hypot(*map(float, row.split(",")[:2])) for row in out.read_text().split()[1:]]
    assert min(r) == pytest.approx(60 - 0.7 * 2) and max(r) == pytest.approx(60 + 1.55 * 2)
    res = _run("profile", "-N", "60", "-m", "2", "--internal", "--shift", "2", "-o", str(out))
    assert isinstance(res.exception, InputError) and res.exception.field == "--shift"


def test_a_ring_no_cutter_can_cut_blames_the_ring_not_an_option_never_given(tmp_path):
    out = tmp_path / "m.png"
    result = runner.invoke(
        gear_app,
        [
            "plot",
            "--np",
            "12",
            "--ng",
            "24",
            "-m",
            "1",
            "--phi",
            "25",
            "--internal",
            "-o",
            str(out),
        ],
    )
    assert result.exit_code != 0
    assert isinstance(result.exception, InputError)
    assert result.exception.field == "--ng"
    assert "no shaper cutter can cut this 24-tooth ring" in str(result.exception)
