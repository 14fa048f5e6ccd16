"""Reports of gear pairs, gear trains and planetary trains.

Independent references: Norton, *Design of Machinery*, Example 9-6/9-7 (sun 40,
planet 20, ring 80; arm −200 rpm, sun +100 rpm → ring −350 rpm) and Table 9-4
(fewest teeth: 18 against a rack, 13 for equal gears, 16 with gears up to 101
teeth at 20°); the superposition method written here (lock the train and turn
it with the arm, then hold the arm and turn the first gear) for a compound
planetary; the tooth loads ``W_t = T / r``, ``W_r = W_t tan φ`` by hand;
shaft speeds stage by stage from the tooth numbers; torques from conservation
of power written here. Every self-check is also fed wrong numbers and fails.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from machdyn.gears import Gear, GearPair, GearTrain, PlanetaryTrain, mesh_forces, train_power
from machdyn.report import report
from machdyn.report.gears import gear_pair_checks, planetary_checks, train_checks

EXAMPLES = Path(__file__).parent.parent / "docs" / "examples"


def cell(page: str, key: str) -> str:
    found = re.findall(rf'data-key="{re.escape(key)}"[^>]*>(.*?)</(?:td|span|p)>', page, re.S)
    assert len(found) == 1, (key, found)
    return re.sub(r"<[^>]+>", "", found[0])


def number(text: str) -> float:
    return float(re.match(r"\s*(-?[\d.]+(?:e[-+]?\d+)?)", text).group(1))


def checks_of(page: str) -> dict[str, str]:
    return dict(re.findall(r'data-check="([\w:]+)".*?class="state">([\w ]+)<', page, re.S))


def headline(page: str) -> str:
    return re.search(r'id="headline">(.*?)</p>', page).group(1)


def failed(checks) -> set[str]:
    return {c.name for c in checks if not c.passed}


# ----------------------------------------------------------------------------- gear pair
@pytest.fixture(scope="module")
def exam():
    return GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))


def test_gear_pair_report_numbers_checks_and_loads(exam):
    page = report(exam, input_speed=1800.0, torque=300.0)
    assert number(cell(page, "contact_ratio")) == pytest.approx(exam.contact_ratio, rel=1e-5)
    assert number(cell(page, "velocity_ratio")) == pytest.approx(-0.4, rel=1e-9)
    assert number(cell(page, "operating_phi")) == pytest.approx(20.0, rel=1e-9)
    assert number(cell(page, "omega_gear")) == pytest.approx(-720.0, rel=1e-9)
    # Norton Table 9-4 at 20°, full depth
    assert cell(page, "min_teeth_rack") == "18" and cell(page, "min_teeth_equal") == "13"
    assert cell(page, "min_pinion_teeth") == "16"
    # tooth loads by hand: r_p = 24 / (2·8) = 1.5 in
    wt = 300.0 / 1.5
    assert number(cell(page, "W_t")) == pytest.approx(wt, rel=1e-5)
    assert number(cell(page, "W_r")) == pytest.approx(wt * math.tan(math.radians(20)), rel=1e-5)
    assert number(cell(page, "W")) == pytest.approx(wt / math.cos(math.radians(20)), rel=1e-5)
    assert number(cell(page, "T_gear")) == pytest.approx(wt * 3.75, rel=1e-5)
    states = checks_of(page)
    assert len(states) == 5 and set(states.values()) == {"pass"}, states
    assert "no interference, no undercut" in headline(page)
    for section in ("model", "geometry", "mesh", "interference", "loads", "selfcheck"):
        assert f'<section id="{section}"' in page, section
    assert 'id="md' in page and "line of action" in page  # the mesh drawing


def test_mesh_forces_of_an_internal_pair_and_on_the_gear():
    pair = GearPair(Gear(20, module=2.0), Gear(80, module=2.0, internal=True))
    f = mesh_forces(pair, 400.0, "gear")  # r_g = 80 mm: W_t = 5
    assert f.tangential == pytest.approx(5.0) and f.torque_pinion == pytest.approx(100.0)
    assert f.total * pair.pinion.base_radius == pytest.approx(100.0)  # W r_b = T


def test_gear_pair_checks_fail_on_wrong_numbers(exam):
    from machdyn.report.gears import _pair_numbers

    shown = _pair_numbers(exam, 1800.0, 300.0)
    assert failed(gear_pair_checks(exam, shown)) == set()
    bad = dict(shown, contact_ratio=shown["contact_ratio"] * 1.01)
    assert failed(gear_pair_checks(exam, bad)) == {"contact ratio"}
    bad = dict(shown, operating_pressure_angle=math.radians(20.5))
    assert {"base circles", "length of action"} <= failed(gear_pair_checks(exam, bad))
    bad = dict(shown, total_force=shown["total_force"] * 1.01)
    assert failed(gear_pair_checks(exam, bad)) == {"moment of the tooth load"}
    bad = dict(shown, speeds=(1800.0, -700.0))
    assert failed(gear_pair_checks(exam, bad)) == {"power through the mesh"}


def test_an_undercut_pinion_fails_the_headline():
    pair = GearPair(Gear(12, module=1.0), Gear(40, module=1.0))
    page = report(pair)
    first = headline(page)
    assert "FAILS" in first and "pinion undercut" in first
    assert cell(page, "undercut_pinion") == "YES"
    # k − N sin²φ / 2 = 1 − 6 sin²20° (the notes' undercut relation, by hand)
    assert number(cell(page, "min_shift_pinion")) == pytest.approx(
        1 - 6 * math.sin(math.radians(20)) ** 2, rel=1e-5
    )


# ----------------------------------------------------------------------------- trains
def test_compound_train_report_speeds_torques_and_signs():
    # 18:54 external, 30:90 internal (the ring turns with its pinion), 10:25 crossed belt
    train = GearTrain([(18, 54), (30, 90, "internal"), (10, 25, "crossed_belt")])
    w_in, t_in = 1800.0, 12.0
    page = report(train, input_speed=w_in, torque=t_in)
    # stage by stage from the tooth numbers: sense flips at external meshes and crossed belts
    w = [w_in, -w_in * 18 / 54]
    w.append(w[-1] * 30 / 90)
    w.append(-w[-1] * 10 / 25)
    for k, expected in enumerate(w, start=1):
        assert number(cell(page, f"omega{k}")) == pytest.approx(expected, rel=1e-5)
        # conservation of power: T_k ω_k = T_in ω_in
        assert number(cell(page, f"T{k}")) == pytest.approx(t_in * w_in / expected, rel=1e-5)
    assert number(cell(page, "train_value")) == pytest.approx(w[-1] / w_in, rel=1e-5)
    assert number(cell(page, "load_torque")) == pytest.approx(-t_in * w_in / w[-1], rel=1e-5)
    assert cell(page, "power_in") == cell(page, "power_out")
    assert "the output turns the same way as the input" in headline(page)
    assert set(checks_of(page).values()) == {"pass"} and len(checks_of(page)) == 4


def test_train_checks_fail_on_wrong_numbers():
    train = GearTrain([(18, 54), (20, 60)])
    p = train_power(train, 100.0, 5.0)
    args = (train, p.speeds, p.torques, train.train_value, p.load_torque)
    assert failed(train_checks(*args)) == set()
    speeds = p.speeds * np.array([1, 1.01, 1])
    assert failed(train_checks(train, speeds, *args[2:])) == {"pitch-line speed at every mesh"}
    flipped = p.speeds * np.array([1, -1, -1])  # shaft 2 turning the wrong way
    assert "pitch-line speed at every mesh" in failed(train_checks(train, flipped, *args[2:]))
    assert "train value by the sign rule" in failed(train_checks(train, flipped, *args[2:]))
    torques = p.torques * np.array([1, 1, 1.01])
    bad = failed(train_checks(train, p.speeds, torques, train.train_value, p.load_torque))
    assert bad == {"tooth force at every mesh"}
    bad = failed(train_checks(train, p.speeds, p.torques, train.train_value, p.load_torque * 1.01))
    assert bad == {"power in = power out"}
    assert failed(train_checks(*args[:3], -train.train_value, p.load_torque)) == {
        "train value by the sign rule"
    }


def test_train_without_speed_or_torque_is_per_unit_and_in_the_files_units():
    from machdyn.spec import load_machine

    machine = load_machine(EXAMPLES / "gears.toml")
    page = report(machine, n=24)
    # the file's box: 1800 rpm in, 18:54 then 20:60 → 200 rpm out; torques per 1 N·m in
    assert cell(page, "box:omega3") == "200 rpm"
    assert cell(page, "box:T1").startswith("1 ") and cell(page, "box:T3").startswith("9 ")
    states = checks_of(page)
    assert set(states.values()) == {"pass"} and any(k.startswith("epicyclic:") for k in states)


# ----------------------------------------------------------------------------- planetary
def test_planetary_report_is_nortons_example_9_6():
    train = PlanetaryTrain.simple(sun=40, planet=20, ring=80)
    page = report(train, speeds={"arm": -200.0, "sun": 100.0}, torque={"sun": 10.0})
    omega = {m: number(cell(page, f"omega_{i}")) for i, m in enumerate(train.members, start=1)}
    assert omega == pytest.approx({"sun": 100.0, "planet": -800.0, "ring": -350.0, "arm": -200.0})
    assert number(cell(page, "willis_last")) == pytest.approx(-350.0)
    # torques: Σ T = 0 and Σ T ω = 0 with T_sun = 10 give T_ring and T_arm (solved here)
    a = np.array([[1.0, 1.0], [omega["ring"], omega["arm"]]])
    t_ring, t_arm = np.linalg.solve(a, [-10.0, -10.0 * omega["sun"]])
    assert number(cell(page, "T_ring")) == pytest.approx(t_ring, rel=1e-5)
    assert number(cell(page, "T_arm")) == pytest.approx(t_arm, rel=1e-5)
    assert number(cell(page, "ratio_ring_fixed")) == pytest.approx(40 / 120)  # N_s/(N_s+N_r)
    assert set(checks_of(page).values()) == {"pass"} and len(checks_of(page)) == 4
    assert "ring -350" in headline(page)


def test_compound_planetary_by_superposition_and_escaped_names():
    # sun 30 → planet 20 on a shaft with planet 25 → ring 75 (internal): the arm is driven,
    # the ring fixed. Superposition: lock everything and turn with the arm by +1 (ring +1),
    # then hold the arm and turn the ring back by −1: the sun turns (75/25)(20/30)·1 ... with
    # the sense of an external and an internal mesh: ω_sun = 1 + (75/25)(20/30).
    chain = [("<sun>", 30), ("p&1", 20, "external"), ("p2", 25, "shaft"), ("ring", 75, "internal")]
    train = PlanetaryTrain(chain)
    page = report(train, speeds={"ring": 0.0, "arm": 1.0}, torque={"arm": 4.0})
    expected_sun = 1.0 + (75 / 25) * (20 / 30)
    expected_planet = 1.0 + (-1.0) * (75 / 25)  # relative to the arm: the ring's −1 × 75/25
    assert number(cell(page, "omega_1")) == pytest.approx(expected_sun, rel=1e-5)
    assert number(cell(page, "omega_2")) == pytest.approx(expected_planet, rel=1e-5)
    assert number(cell(page, "omega_3")) == pytest.approx(expected_planet, rel=1e-5)
    assert set(checks_of(page).values()) == {"pass"}
    assert "&lt;sun&gt;" in page and "<sun>" not in page and "p&amp;1" in page


def test_planetary_checks_fail_on_wrong_numbers():
    from machdyn.gears import planetary_power

    train = PlanetaryTrain.simple(sun=40, planet=20, ring=80)
    p = planetary_power(train, {"arm": -200.0, "sun": 100.0}, {"sun": 10.0})
    speeds = dict(zip(p.members, p.speeds, strict=True))
    torques = dict(zip(p.members, p.torques, strict=True))
    assert failed(planetary_checks(train, speeds, torques)) == set()
    bad = dict(speeds, ring=speeds["ring"] * 1.01)
    assert {
        "tabular vs formula method",
        "pitch-line speed relative to the arm",
        "power in = power out",
    } <= failed(planetary_checks(train, bad, torques))
    bad = dict(speeds, planet=-speeds["planet"])
    assert "pitch-line speed relative to the arm" in failed(planetary_checks(train, bad, torques))
    bad = dict(torques, arm=torques["arm"] * 1.01)
    assert failed(planetary_checks(train, speeds, bad)) == {
        "moment balance",
        "power in = power out",
    }


def test_planetary_power_refuses_a_planet_torque():
    from machdyn.errors import InputError
    from machdyn.gears import planetary_power

    train = PlanetaryTrain.simple(sun=40, planet=20, ring=80)
    with pytest.raises(InputError, match="torque"):
        planetary_power(train, {"ring": 0.0, "sun": 1.0}, {"planet": 1.0})


# ----------------------------------------------------------------------------- drawings
def test_train_drawing_is_the_trains_geometry_and_speeds():
    from machdyn.draw.gears import planetary_scene, train_scene

    train = GearTrain([(18, 54), (20, 60)])
    s = train_scene(train, 1800.0, n=10)
    s1, s2, s3 = (s.point(n)[0] for n in ("S1 in", "S2", "S3 out"))
    assert abs(s2 - s1) == pytest.approx((18 + 54) / 2) and abs(s3 - s2) == pytest.approx(40.0)
    w = train.speeds(1800.0)
    steps = [s.angles[f"shaft{k}"][1] - s.angles[f"shaft{k}"][0] for k in (1, 2, 3)]
    assert np.array(steps) / steps[0] == pytest.approx(np.array(w) / w[0])
    p = planetary_scene(PlanetaryTrain.simple(40, 20, 80), {"arm": -200.0, "sun": 100.0}, n=10)
    arm = p.angles["arm"]
    assert np.angle(p.point("planet")) == pytest.approx(np.angle(np.exp(1j * arm)))
    assert (p.angles["g3"][1] - p.angles["g3"][0]) / (arm[1] - arm[0]) == pytest.approx(-350 / -200)


@pytest.mark.parametrize(
    "pair",
    [
        GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8)),
        GearPair(Gear(20, module=2.0), Gear(40, module=2.0), driver="gear"),
        GearPair(Gear(20, module=2.0), Gear(80, module=2.0, internal=True)),
    ],
    ids=["exam", "gear-driving", "internal"],
)
def test_the_line_of_action_drawn_is_the_pairs_contact_geometry(pair):
    from machdyn.draw.gears import mesh_chart

    chart = mesh_chart(pair)
    gid = {s.gid: s for s in chart.series if s.gid}
    pts = {n: complex(x, y) for x, y, n in chart.notes}
    c = -pair.center_distance if pair.internal else pair.center_distance
    # the tangent points on the base circles, C' sin φ' apart (Norton Fig. 9-6)
    assert abs(pts["T_p"]) == pytest.approx(pair.pinion.base_radius, rel=1e-12)
    assert abs(pts["T_g"] - c) == pytest.approx(pair.gear.base_radius, rel=1e-12)
    assert abs(pts["T_g"] - pts["T_p"]) == pytest.approx(
        pair.center_distance * math.sin(pair.operating_pressure_angle), rel=1e-12
    )
    # contact begins and ends where the tip circles cut the line: the driven member's
    # tip starts it (the pinion driving: the gear's tip), the driver's tip ends it
    first, last = pts["first contact"], pts["last contact"]
    tip_p, tip_g = pair.pinion.addendum_radius, pair.gear.addendum_radius
    starts, ends = (tip_g, tip_p) if pair.driver == "pinion" else (tip_p, tip_g)
    centre_of = {tip_p: 0j, tip_g: complex(c)}
    assert abs(first - centre_of[starts]) == pytest.approx(starts, rel=1e-12)
    assert abs(last - centre_of[ends]) == pytest.approx(ends, rel=1e-12)
    path = gid["path_of_contact"]
    assert math.hypot(np.diff(path.x)[0], np.diff(path.y)[0]) == pytest.approx(
        pair.length_of_action, rel=1e-12
    )


def test_bad_report_options_are_refused_by_name(exam):
    from machdyn.errors import InputError

    train = GearTrain([(18, 54), (20, 60)])
    planetary = PlanetaryTrain.simple(sun=40, planet=20, ring=80)
    for model, options, field in (
        (exam, {"input_speed": "fast"}, "input_speed"),
        (exam, {"torque": float("inf")}, "torque"),
        (train, {"input_speed": 0.0}, "omega_in"),
        (train, {"torque": "x"}, "torque"),
        (planetary, {"speeds": 5.0}, "speeds"),
        (planetary, {"speeds": {"sun": 1.0}}, "known"),
        (planetary, {"torque": {"planet": 1.0}}, "torque"),
    ):
        with pytest.raises(InputError, match=field):
            report(model, **options)


def test_trains_draw_through_the_one_scene_path(tmp_path):
    from machdyn.draw import scene, to_html

    train = GearTrain([(18, 54), (20, 60)])
    s = scene(train, n=8, omega_in=1800.0)
    assert [r.values[0] for r in s.readout] == pytest.approx(list(train.speeds(1800.0)))
    p = scene(PlanetaryTrain.simple(40, 20, 80), n=8, speeds={"ring": 0.0, "sun": 3.0})
    assert p.readout[-1].values[0] == pytest.approx(1.0)  # the arm: N_s / (N_s + N_r) × 3
    page = to_html(train, tmp_path / "train.html")
    assert "wheel_3a" in page and (tmp_path / "train.html").exists()
