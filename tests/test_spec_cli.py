"""The sub-commands' ``--spec FILE`` (issue #11 item 4), against ``machdyn run`` and the API.

Each command given a docs/examples machine file must print what ``machdyn run
FILE --part NAME`` prints for that part, and those numbers must be the ones the
library gives when called by hand with the file's values written out again here
(or a closed form / the notes' worked answer). Bad combinations are one error
line naming the option.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from machdyn import gears
from machdyn.balancing import static_balance, two_plane
from machdyn.cli import main
from machdyn.flywheel import disc_flywheel, size_flywheel
from machdyn.synthesis import function_generator, synthesize_path, three_position

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
RPM = 2 * math.pi / 60


def cli(argv: list[str], capsys) -> str:
    status = main(argv)
    out, err = capsys.readouterr()
    assert status == 0, err
    return out


def cli_json(argv: list[str], capsys) -> dict:
    return json.loads(cli([*argv, "--json"], capsys))


def error(argv: list[str], capsys) -> str:
    status = main(argv)
    out, err = capsys.readouterr()
    assert status != 0 and not out
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    return err


CASES = [
    (["gear", "pair"], "gears.toml", "exam"),
    (["gear", "train"], "gears.toml", "box"),
    (["gear", "planetary"], "gears.toml", "epicyclic"),
    (["flywheel"], "flywheel.toml", "shaft"),
    (["flywheel"], "press.toml", "crank"),
    (["balance", "rotor"], "rotor.toml", "shaft"),
    (["balance", "static"], "disc.toml", "disc"),
    (["synth", "three-position"], "synthesis.toml", "three"),
    (["synth", "function"], "synthesis.toml", "log"),
]


@pytest.mark.parametrize(("command", "file", "part"), CASES)
def test_spec_option_prints_what_run_prints_for_the_part(command, file, part, capsys):
    path = str(EXAMPLES / file)
    got = cli_json([*command, "--spec", path], capsys)
    assert list(got["parts"]) == [part]
    assert got == cli_json(["run", path, "--part", part], capsys)
    # the text and CSV outputs too, and --part naming the same part changes nothing
    text = cli([*command, "--spec", path, "--part", part], capsys)
    assert text == cli(["run", path, "--part", part], capsys)
    assert cli([*command, "--spec", path, "--csv"], capsys) == cli(
        ["run", path, "--part", part, "--csv"], capsys
    )


def _summary(payload: dict, part: str) -> dict:
    return payload["parts"][part]["summary"]


def _table(payload: dict, part: str, name: str) -> dict:
    t = payload["parts"][part]["tables"][name]
    return {c: [row[i] for row in t["rows"]] for i, c in enumerate(t["columns"])}


def test_gear_commands_match_the_gears_api(capsys):
    path = str(EXAMPLES / "gears.toml")
    got = cli_json(["gear", "pair", "--spec", path], capsys)
    pair = gears.GearPair(gears.Gear(24, diametral_pitch=8), gears.Gear(60, diametral_pitch=8))
    s = _summary(got, "exam")
    assert s["contact ratio"].startswith(f"{pair.contact_ratio:.4f}")
    assert s["centre distance [in]"] == pytest.approx((24 + 60) / (2 * 8), rel=1e-12)
    assert s["length of action [in]"] == pytest.approx(pair.length_of_action, rel=1e-12)
    rows = _table(got, "exam", "gears")
    assert rows["pitch_radius [in]"] == pytest.approx([24 / 16, 60 / 16], rel=1e-12)
    assert rows["speed [rpm]"] == pytest.approx([1800.0, -1800.0 * 24 / 60], rel=1e-12)
    # the same pair typed as options gives the same geometry
    typed = cli_json(["gear", "pair", "--np", "24", "--ng", "60", "--pd", "8"], capsys)
    assert typed["contact_ratio"] == pytest.approx(pair.contact_ratio, rel=1e-12)

    box = cli_json(["gear", "train", "--spec", path], capsys)
    train = gears.GearTrain([(18, 54), (20, 60)])
    assert _summary(box, "box")["train value (output/input)"] == pytest.approx(
        train.train_value, rel=1e-12
    )
    assert _summary(box, "box")["output speed [rpm]"] == pytest.approx(
        1800 * (18 / 54) * (20 / 60), rel=1e-12
    )

    epi = cli_json(["gear", "planetary", "--spec", path], capsys)
    table = gears.PlanetaryTrain.simple(sun=40, planet=20, ring=80).table(arm=-200.0, sun=100.0)
    speeds = _table(epi, "epicyclic", "speeds")
    assert speeds["speed [rpm]"] == pytest.approx(list(table.total), rel=1e-12)
    ring = dict(zip(speeds["member"], speeds["speed [rpm]"], strict=True))["ring"]
    assert ring == pytest.approx(-350.0, rel=1e-12)  # Norton Example 9-6


def test_gear_profile_and_plot_take_the_files_pair(tmp_path, capsys):
    path = str(EXAMPLES / "gears.toml")
    dxf = tmp_path / "gear.dxf"
    cli(["gear", "profile", "--spec", path, "--member", "gear", "-o", str(dxf)], capsys)
    lines = dxf.read_text().splitlines()
    assert lines[lines.index("$INSUNITS") + 2].strip() == "1"  # inches: the file's unit
    csv = tmp_path / "gear.csv"
    cli(["gear", "profile", "--spec", path, "--member", "gear", "-o", str(csv)], capsys)
    assert csv.read_text().splitlines()[0] == "x [in],y [in],segment"  # the file's unit
    xy = np.loadtxt(csv, delimiter=",", skiprows=1, usecols=(0, 1))
    radius = np.hypot(xy[:, 0], xy[:, 1])
    # a 60-tooth gear, P_d = 8 in^-1, full depth: addendum radius 30/8 + 1/8 in
    assert radius.max() == pytest.approx(60 / 16 + 1 / 8, rel=1e-9)
    svg = tmp_path / "mesh.svg"
    cli(["gear", "plot", "--spec", path, "-o", str(svg)], capsys)
    assert svg.stat().st_size > 1000


def test_flywheel_command_matches_size_flywheel(capsys):
    got = cli_json(["flywheel", "--spec", str(EXAMPLES / "flywheel.toml")], capsys)
    theta = np.radians(np.arange(0.0, 361.0, 30.0))
    torque = np.round(50 + 10 * np.sin(theta) + 4 * np.sin(2 * theta), 6)
    fw = size_flywheel(theta, torque, 500 * RPM, 0.02)
    s = _summary(got, "shaft")
    assert s["I (flywheel inertia) [kg*m^2]"] == pytest.approx(fw.inertia, rel=1e-12)
    assert s["delta_E [N*m]"] == pytest.approx(fw.delta_e, rel=1e-12)
    disc = disc_flywheel(fw.inertia, 7850.0, 0.04)
    assert s["disc outer radius [m]"] == pytest.approx(disc.outer_radius, rel=1e-12)
    # the CSV flywheel command on the same curve (rad/s, N*m) agrees
    lobes = _table(got, "shaft", "lobes")
    assert lobes["delta_E [N*m]"] == pytest.approx(list(fw.lobes.area), rel=1e-12)


def test_balance_commands_match_the_balancing_api(capsys):
    path = str(EXAMPLES / "rotor.toml")
    got = cli_json(["balance", "rotor", "--spec", path], capsys)
    mr = [0.2 * 60 * np.exp(1j * math.radians(30)), 0.3 * 50 * np.exp(1j * math.radians(150))]
    mr.append(0.1 * 80 * np.exp(1j * math.radians(270)))
    fix = two_plane(np.array(mr), np.array([100.0, 220.0, 320.0]), 0.0, 400.0)
    rows = _table(got, "shaft", "corrections")
    assert rows["mR [kg*mm]"] == pytest.approx([abs(fix.mR_a), abs(fix.mR_b)], rel=1e-12)
    assert rows["angle [deg]"] == pytest.approx([fix.angle_a_deg, fix.angle_b_deg], rel=1e-12)
    # the typed command gives the same corrections
    masses = ["--mass", "0.2,60,30,100", "--mass", "0.3,50,150,220", "--mass", "0.1,80,270,320"]
    typed = cli_json(["balance", "rotor", *masses, "--plane-a", "0", "--plane-b", "400"], capsys)
    assert typed["mR"] == pytest.approx(rows["mR [kg*mm]"], rel=1e-12)
    assert typed["angle_deg"] == pytest.approx(rows["angle [deg]"], rel=1e-12)

    disc = cli_json(["balance", "static", "--spec", str(EXAMPLES / "disc.toml")], capsys)
    rows = _table(disc, "disc", "corrections")
    # the notes' two-mass case: mR = sqrt(3^2 + 2^2) at 180 + atan(2/3) deg
    assert rows["mR [kg*mm]"] == pytest.approx([math.hypot(3, 2)], rel=1e-12)
    assert rows["angle [deg]"] == pytest.approx([180 + math.degrees(math.atan2(2, 3))], rel=1e-12)
    assert rows["mass [kg]"] == pytest.approx([math.hypot(3, 2) / 10], rel=1e-12)
    assert abs(static_balance([3, 2j]).mR) == pytest.approx(math.hypot(3, 2))


def test_synth_commands_match_the_synthesis_api(capsys):
    path = str(EXAMPLES / "synthesis.toml")
    got = cli_json(["synth", "three-position", "--spec", path], capsys)
    c = [0 + 5.086j, 2.019 + 3.181j, 3.933 + 4.051j]
    d = [0.741 + 2.703j, 4.428 + 2.529j, 6.304 + 4.83j]
    s = three_position(c, d)
    assert _summary(got, "three")["r1, r2, r3, r4 [L]"] == pytest.approx(
        [s.r1, s.r2, s.r3, s.r4], rel=1e-12
    )
    rows = _table(got, "three", "positions")
    assert rows["B_x [L]"] == pytest.approx(list(np.real(s.B)), rel=1e-12)

    got = cli_json(["synth", "function", "--spec", path], capsys)
    g = function_generator(np.log10, (1.0, 2.0), np.radians((45, 105)), np.radians((135, 225)))
    se = g.structural_error(n=11)
    assert _summary(got, "log")["r1, r2, r3, r4 [L]"] == pytest.approx(
        [g.r1, g.r2, g.r3, g.r4], rel=1e-12
    )
    err = _table(got, "log", "structural_error")
    # Freudenstein: the error vanishes at the three Chebyshev precision points
    assert err["error"] == pytest.approx(list(se.error), abs=1e-12)
    xp = 1.5 + 0.5 * np.cos(np.array([5, 3, 1]) * np.pi / 6)
    at = [err["error"][err["x"].index(pytest.approx(x))] for x in xp]
    assert at == pytest.approx([0, 0, 0], abs=1e-9)
    argv = ["synth", "function", "--f", "log10(x)", "--x", "1:2", "--theta2", "45:105"]
    typed = cli_json([*argv, "--theta4", "135:225"], capsys)
    assert typed["max_abs_error"] == pytest.approx(
        _summary(got, "log")["max |structural error|"], rel=1e-12
    )


@pytest.mark.slow
def test_synth_path_spec_matches_synthesize_path(capsys):
    got = cli_json(["synth", "path", "--spec", str(EXAMPLES / "path.toml")], capsys)
    targets = np.array([0, 20 + 8j, 40 + 10j, 60 + 8j, 80])
    r = synthesize_path(targets, mu_min=math.radians(30), seed=1, maxiter=60, popsize=15)
    s = _summary(got, "arch")
    assert s["r1, r2, r3, r4 [mm]"] == pytest.approx(list(r.fourbar.lengths), rel=1e-9)
    # the printed placement reproduces the targets: O2 + e^(j theta1) * local coupler point
    assert s["O2 [mm]"] == pytest.approx([r.linkage.O2.real, r.linkage.O2.imag], rel=1e-9)
    d = _table(got, "arch", "targets")["distance [mm]"]
    assert max(d) < 0.5 and d == pytest.approx(list(r.distance), rel=1e-9)


BAD = [
    (["gear", "pair", "--spec", "rotor.toml"], "--spec", "has no gear_pair part"),
    (["gear", "pair", "--spec", "gears.toml", "--np", "20"], "--np", "comes from --spec"),
    (["gear", "pair", "--spec", "gears.toml", "--part", "box"], "--part", "gear_train part"),
    (["gear", "pair", "--spec", "gears.toml", "--part", "nope"], "--part", "not a part"),
    (["gear", "pair", "--np", "20", "--ng", "40", "-m", "2", "--csv"], "--csv", "--spec"),
    (["gear", "pair", "--ng", "40", "-m", "2"], "--np", "missing"),
    (["gear", "train"], "STAGES", "missing"),
    (["gear", "planetary", "--sun", "40"], "--planet", "missing"),
    (
        ["gear", "profile", "-o", "x.csv", "--spec", "gears.toml", "--member", "rack"],
        "--member",
        "",
    ),
    (["flywheel", "--spec", "gears.toml"], "--spec", "gear_pair exam, gear_train box"),
    (["flywheel", "--spec", "flywheel.toml", "--k", "0.1"], "--k", "comes from --spec"),
    (["flywheel", "--omega-avg", "50", "--k", "0.02"], "CURVE", "missing"),
    (["balance", "static", "--spec", "rotor.toml"], "--spec", "rotor --spec"),
    (["balance", "rotor", "--spec", "disc.toml"], "--spec", "static --spec"),
    (["balance", "rotor", "--mass", "1,1,0,1", "--plane-a", "0"], "--plane-b", "missing"),
    (["synth", "function", "--spec", "gears.toml"], "--spec", "no function_synthesis"),
    (["synth", "three-position", "--c", "0,0; 1,1; 2,0"], "--d", "missing"),
    (["synth", "path", "--spec", "synthesis.toml"], "--spec", "no path_synthesis part"),
    (["gear", "pair", "--spec", "nowhere.toml"], "nowhere.toml", ""),
]


@pytest.mark.parametrize(("argv", "field", "words"), BAD)
def test_bad_spec_use_is_one_line_naming_the_option(argv, field, words, capsys):
    argv = [str(EXAMPLES / a) if a.endswith(".toml") else a for a in argv]
    err = error(argv, capsys)
    assert field in err and words in err, err


def test_a_file_with_several_parts_of_the_kind_asks_for_part(tmp_path, capsys):
    two = tmp_path / "two.toml"
    two.write_text(
        "machdyn = 1\n[gear_train.a]\nstages = [[18, 54]]\n[gear_train.b]\nstages = [[20, 60]]\n"
    )
    err = error(["gear", "train", "--spec", str(two)], capsys)
    assert "--part" in err and "2 gear_train parts (a, b)" in err
    got = cli_json(["gear", "train", "--spec", str(two), "--part", "b"], capsys)
    assert _summary(got, "b")["train value (output/input)"] == pytest.approx(-20 / 60)


def test_round_off_is_not_printed_as_a_value(capsys):
    """A tight standard mesh has no backlash; a crank's mean torque over a cycle is zero
    when the only load is on a rocker (it returns: no net work) and gravity (a closed path)."""
    got = cli_json(["run", str(EXAMPLES / "press.toml")], capsys)
    assert _summary(got, "reducer")["backlash [mm]"] == 0.0
    assert _summary(got, "crank")["T_avg [N*m]"] == 0.0
