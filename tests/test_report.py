"""The design report: its numbers are the API's, its self-checks catch a wrong motion.

Independent references: the public API called here (FourBar.transmission_angle,
FourBar.dynamics, size_flywheel, Linkage.forces) for the numbers printed; the
self-checks fed motions made wrong on purpose (accelerations × 1.01, ω3 × 1.01,
a joint moved by 1e-5); the page opened in a real browser (test_report_browser).
"""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np
import pytest

from closed_forms import circle_meet
from machdyn import FourBar
from machdyn.dynamics import fourbar_forces
from machdyn.flywheel import size_flywheel
from machdyn.linkage import Linkage
from machdyn.report import report
from machdyn.report.fourbar import fourbar_checks, fourbar_report, fourbar_sweep
from machdyn.report.linkage import linkage_checks

MASS, INERTIA, CG = (1.0, 2.0, 1.5), (0.1, 0.5, 0.3), (2.0, 3.5 + 0.5j, 3.0)


def cell(page: str, key: str) -> str:
    found = re.findall(rf'data-key="{key}"[^>]*>(.*?)</(?:td|span)>', page, re.S)
    assert len(found) == 1, (key, found)
    return re.sub(r"<[^>]+>", "", found[0])


def number(text: str) -> float:
    return float(re.match(r"\s*(-?[\d.]+(?:e[-+]?\d+)?)", text).group(1))


def at_deg(text: str) -> float:
    return float(re.search(r"(?:at θ2 =|=)\s*(-?[\d.]+)°?\s*$", text.strip()).group(1))


def checks_of(page: str) -> dict[str, str]:
    return dict(re.findall(r'data-check="(\w+)".*?class="state">([\w ]+)<', page, re.S))


@pytest.fixture(scope="module")
def hw6():
    return FourBar(8, 4, 7, 6, coupler=(5.0, np.radians(30)))


@pytest.fixture(scope="module")
def hw6_page(hw6):
    return report(hw6, omega2=10.0, mass=MASS, inertia=INERTIA, cg=CG, k=0.05, gravity=9.81)


def test_the_first_line_says_what_the_machine_is(hw6_page):
    first = re.search(r'<body>\s*<p class="headline" id="headline">(.*?)</p>', hw6_page).group(1)
    assert first.startswith("four-bar 8-4-7-6 (GCRR)") and "full turn" in first


def test_report_numbers_equal_the_api(hw6, hw6_page):
    page = hw6_page
    assert cell(page, "barker_class") == "GCRR"
    ta = hw6.transmission_angle(1)
    text = cell(page, "mu_min_deg")
    assert number(text) == pytest.approx(np.degrees(ta.min), abs=5e-4)
    assert at_deg(text) == pytest.approx(np.degrees(ta.theta2_at_min), abs=5e-3)
    ex = hw6.extrema(1)
    assert number(cell(page, "theta4_min_deg")) == pytest.approx(
        np.degrees(ex["theta4"].min), abs=5e-4
    )
    # peak pin force and torque, and where, from FourBar.dynamics on the report's sweep
    th = fourbar_sweep(hw6, 1, 360)
    f = hw6.dynamics(th, 10.0, mass=MASS, inertia=INERTIA, cg=CG, gravity=9.81)
    k = int(np.argmax(np.abs(f.F32)))
    text = cell(page, "peak_F32")
    assert number(text) == pytest.approx(abs(f.F32[k]), rel=5e-4)
    assert at_deg(text) == pytest.approx(np.degrees(th[k]), abs=0.05)
    assert number(cell(page, "T12_max")) == pytest.approx(f.T12.max(), rel=5e-4)
    fly = size_flywheel(th, f.T12, 10.0, 0.05)
    assert number(cell(page, "flywheel_inertia")) == pytest.approx(fly.inertia, rel=5e-4)
    assert number(cell(page, "delta_e")) == pytest.approx(fly.delta_e, rel=5e-4)
    # toggles: the API's four output limits, listed in the table
    for t in hw6.toggles():
        assert f"{np.degrees(t.theta2):.3f}" in page


def test_every_self_check_passes_on_the_solved_motion(hw6_page):
    states = checks_of(hw6_page)
    # 6 motion checks, link angles, 4 force checks (power, equilibrium, momentum twice),
    # flywheel
    assert len(states) == 12 and set(states.values()) == {"pass"}, states


def wrong_motions(fb):
    th = fourbar_sweep(fb, 1, 360)
    m = fb.solve(th, 10.0)
    return m, {
        "accelerations × 1.01": replace(
            m,
            alpha3=m.alpha3 * 1.01,
            alpha4=m.alpha4 * 1.01,
            coupler_acceleration=m.coupler_acceleration * 1.01,
        ),
        "ω3 × 1.01": replace(m, omega3=m.omega3 * 1.01),
        "ω4 × 1.01": replace(m, omega4=m.omega4 * 1.01),
        "B moved by 1e-5": replace(m, B=m.B + 1e-5),
    }


def test_self_checks_fail_on_a_wrong_motion(hw6):
    th = fourbar_sweep(hw6, 1, 360)
    f = hw6.dynamics(th, 10.0, mass=MASS, inertia=INERTIA, cg=CG)
    right, wrong = wrong_motions(hw6)
    assert all(c.passed for c in fourbar_checks(hw6, right, 10.0, f, MASS, INERTIA, CG))
    failed = {}
    for label, m in wrong.items():
        failed[label] = {
            c.name for c in fourbar_checks(hw6, m, 10.0, f, MASS, INERTIA, CG) if not c.passed
        }
    # accelerations × 1.01: every check that involves accelerations fails
    assert failed["accelerations × 1.01"] == {
        "loop closure: accelerations",
        "finite differences: acceleration",
        "power balance",
        "equilibrium of each link",
        "momentum: shaking force and moment",
    }
    # a wrong angular velocity: the velocity field, Kennedy's rule and the power balance
    assert {"loop closure: velocities", "Kennedy's rule", "power balance"} <= failed["ω3 × 1.01"]
    # the output's rate against the differences of its positions
    assert "finite differences: velocity" in failed["ω4 × 1.01"]
    # a wrong position: the loop itself (and the fields built on it)
    assert {"loop closure: positions", "link angles"} <= failed["B moved by 1e-5"]
    # forces solved from the wrong accelerations agree with them (equilibrium, power and
    # the momentum balance written with a_G pass) but not with the momentum's differences
    bad = wrong["accelerations × 1.01"]
    f_bad = fourbar_forces(hw6, bad, mass=MASS, inertia=INERTIA, cg=CG)
    failed["forces from accelerations × 1.01"] = {
        c.name for c in fourbar_checks(hw6, bad, 10.0, f_bad, MASS, INERTIA, CG) if not c.passed
    }
    assert failed["forces from accelerations × 1.01"] == {
        "loop closure: accelerations",
        "finite differences: acceleration",
        "momentum by differences",
    }
    # every check is failed by one of the wrong motions
    names = {c.name for c in fourbar_checks(hw6, right, 10.0, f, MASS, INERTIA, CG)}
    assert set().union(*failed.values()) == names


def test_a_failed_check_is_the_first_thing_the_page_says(hw6):
    _, wrong = wrong_motions(hw6)
    page = fourbar_report(
        hw6, omega2=10.0, mass=MASS, inertia=INERTIA, cg=CG, motion=wrong["accelerations × 1.01"]
    ).html()
    first = re.search(r'id="headline">(.*?)</p>', page).group(1)
    assert first.startswith("SELF-CHECK FAILED")
    assert checks_of(page)["power_balance"] == "FAIL"


def watt(names=None, masses=True) -> Linkage:
    n = {k: k for k in ("O2", "O4", "O6", "A", "B", "C", "D", "E", "2", "3", "4", "5", "6")}
    n.update(names or {})
    O4, O6 = 8.0 + 0j, 12.0 + 6.0j
    A = 2.0 * np.exp(1j * np.pi / 6)
    B = circle_meet(A, 7.0, O4, 6.0)
    C = O4 + 4.0 * (B - O4) / abs(B - O4) * np.exp(1j * np.radians(-35))
    D = circle_meet(C, 6.0, O6, 5.0, -1.0)
    pts = {
        n["O2"]: 0j,
        n["O4"]: O4,
        n["O6"]: O6,
        n["A"]: A,
        n["B"]: B,
        n["C"]: C,
        n["D"]: D,
        n["E"]: C + 2.0 + 1j,
    }
    lk = Linkage(pts).ground(n["O2"], n["O4"], n["O6"])
    p = (lambda m, i, c: {"mass": m, "inertia": i, "cg": c}) if masses else (lambda *a: {})
    lk.link(n["2"], n["O2"], n["A"], **p(1.0, 0.4, 1.0 + 0.1j))
    lk.link(n["3"], n["A"], n["B"], **p(2.0, 8.0, 3.5 + 0.3j))
    lk.link(n["4"], n["O4"], n["B"], n["C"], **p(3.0, 6.0, 2 + 0.5j))
    lk.link(n["5"], n["C"], n["D"], n["E"], **p(1.5, 4.5, n["E"]))
    lk.link(n["6"], n["O6"], n["D"], **p(2.5, 5.0, 2.5 - 0.2j))
    return lk.drive(n["2"])


def test_linkage_report_numbers_and_checks():
    lk = watt()
    page = report(lk, velocity=10.0, n=360, gravity=9.81, k=0.05)
    assert set(checks_of(page).values()) == {"pass"}
    assert cell(page, "mobility") == "1"
    x = np.radians(30.0) + np.linspace(0, 2 * np.pi, 360, endpoint=False)
    m = lk.solve(x, velocity=10.0)
    f = lk.forces(m, gravity=9.81)
    T = f.driver["2"]
    assert number(cell(page, "driver_2_max")) == pytest.approx(T.max(), rel=5e-4)
    F = f.pins[("3", "4")]
    assert number(cell(page, "peak_F_3_4")) == pytest.approx(np.abs(F).max(), rel=5e-4)
    fly = size_flywheel(x, T, 10.0, 0.05)
    assert number(cell(page, "flywheel_inertia")) == pytest.approx(fly.inertia, rel=5e-4)


def test_linkage_self_checks_fail_on_a_wrong_motion():
    lk = watt()
    x = np.radians(30.0) + np.linspace(0, 2 * np.pi, 360, endpoint=False)
    m = lk.solve(x, velocity=10.0)
    f = lk.forces(m, gravity=9.81)
    right = linkage_checks(lk, m, x, 10.0, f, 9.81)
    names = {c.name for c in right}
    assert (
        all(c.passed for c in right)
        and {
            "equilibrium of each link",
            "momentum: shaking force and moment",
            "momentum by differences",
        }
        <= names
    )
    bad = replace(
        m,
        alpha={k: v * 1.01 for k, v in m.alpha.items()},
        point_acceleration={k: v * 1.01 for k, v in m.point_acceleration.items()},
        cg_acceleration={k: v * 1.01 for k, v in m.cg_acceleration.items()},
    )
    failed = {}
    # the forces of the right motion checked against a motion with accelerations × 1.01
    failed["acc"] = {c.name for c in linkage_checks(lk, bad, x, 10.0, f, 9.81) if not c.passed}
    assert failed["acc"] == {
        "loop closure: accelerations",
        "finite differences: acceleration",
        "power balance",
        "equilibrium of each link",
        "momentum: shaking force and moment",
    }
    # forces solved from the wrong motion: the momentum's differences (velocities only)
    # still see it (a_G × 1.01 is not the rigid field of α × 1.01, so more checks fail)
    f_bad = lk.forces(bad, gravity=9.81)
    failed["forces"] = {
        c.name for c in linkage_checks(lk, bad, x, 10.0, f_bad, 9.81) if not c.passed
    }
    assert {"finite differences: acceleration", "momentum by differences"} <= failed["forces"]
    bad = replace(m, omega={k: v * (1.01 if k == "3" else 1.0) for k, v in m.omega.items()})
    failed["w3"] = {c.name for c in linkage_checks(lk, bad, x, 10.0, f, 9.81) if not c.passed}
    assert {"loop closure: velocities", "Kennedy's rule", "momentum by differences"} <= failed["w3"]
    bad = replace(m, points={k: v + (1e-5 if k == "B" else 0.0) for k, v in m.points.items()})
    failed["B"] = {c.name for c in linkage_checks(lk, bad, x, 10.0, f, 9.81) if not c.passed}
    assert "loop closure: positions" in failed["B"]
    bad = replace(
        m, point_velocity={k: v * (1.01 if k == "D" else 1.0) for k, v in m.point_velocity.items()}
    )
    failed["vD"] = {c.name for c in linkage_checks(lk, bad, x, 10.0, f, 9.81) if not c.passed}
    assert "finite differences: velocity" in failed["vD"]
    # every self-check of the linkage report is failed by one of the wrong motions
    assert set().union(*failed.values()) == names


def test_linkage_equilibrium_with_every_kind_of_load():
    """Free bodies with sliders, springs, motors, actuators, rolling: ΣF = m a_G, ΣM_G = I_G α."""
    slider = (
        Linkage({"O2": (0, 0), "A": (0, 2), "B": (6, 0), "S": (3, 3)})
        .ground("O2", "S")
        .link("crank", "O2", "A", mass=1.0, inertia=0.2, cg=1 + 0.1j)
        .link("rod", "A", "B", mass=2.0, inertia=3.0, cg=3 + 0.2j)
        .link("block", "B", mass=2.0, inertia=0.01)
        .slider("block", "ground", "B", 0.0, name="guide")
        .spring("k1", "S", "A", stiffness=50.0, free_length=1.0)
        .drive("crank")
    )
    arm = (
        Linkage({"O": (0, 0), "A": (2, 0.5), "B": (3.5, 2)})
        .ground("O")
        .link("upper", "O", "A", mass=2.0, inertia=0.5, cg=1 + 0.1j)
        .link("fore", "A", "B", mass=1.0, inertia=0.2, cg=0.7 - 0.1j)
        .motor("elbow", "A")
        .torsion_spring("ts", "O", stiffness=10.0, free_angle=0.0, links=("ground", "upper"))
        .drive("upper", "elbow")
    )
    boom = (
        Linkage({"C": (0, 0), "D": (3, 4), "P": (0, 5)})
        .ground("C", "P")
        .link("arm", "P", "D", mass=3.0, inertia=1.0, cg=1.5 + 0.2j)
        .actuator("cyl", "C", "D", links=("ground", "arm"))
        .drive("cyl")
    )
    from test_linkage_rolling import planetary, wheel_on_ground

    def mp(m, i, c):
        return {"mass": m, "inertia": i, "cg": c}

    wheel = wheel_on_ground(
        wheel=mp(2.0, 0.5, 0.1 + 0.05j), rod=mp(1.0, 0.4, 1.0), block=mp(1.5, 0.01, 0)
    )
    gears, _ = planetary(sun=mp(1, 0.3, 0.1), arm=mp(0.5, 0.2, 1.0), planet=mp(0.7, 0.1, 0.05j))
    n = 200
    t = np.linspace(0.0, 1.0, n)
    cases = [
        (slider, 0.3 + 2 * np.pi * t, 5.0, None),
        (arm, 0.2 + t, 2.0, {"upper": 0.2 + t, "elbow": 0.3 + 0.5 * t}),
        (boom, 4.5 + t, 0.7, None),
        (wheel, 2 * t - 1, 2.0, None),  # rolling on the ground
        (gears, 2 * np.pi * t, 3.0, None),  # rolling contacts carried by one link
    ]
    for lk, x, rate, values in cases:
        if values is None:
            m = lk.solve(x, velocity=rate)
        else:
            m = lk.solve(values, velocity={"upper": np.full(n, rate), "elbow": np.full(n, 1.0)})
        f = lk.forces(m, gravity=9.81)
        checks = {c.name: c for c in linkage_checks(lk, m, x, rate, f, 9.81)}
        assert checks["equilibrium of each link"].passed, (lk, checks)
        assert checks["momentum: shaking force and moment"].passed
        # a wrong driver effort breaks the equilibrium of its link
        wrong = replace(f, driver={k: v * 1.01 for k, v in f.driver.items()})
        assert not {c.name: c for c in linkage_checks(lk, m, x, rate, wrong, 9.81)}[
            "equilibrium of each link"
        ].passed


def test_unreachable_driver_values_give_a_first_line_and_the_drawing_as_given():
    # a rocker-driven four-bar asked for angles it cannot reach
    A = 9.0 * np.exp(1j * np.radians(60))
    B = A + 3 * np.exp(1j * np.radians(-10))
    d = abs(B)
    a = (6**2 - 8**2 + d**2) / (2 * d)
    O4 = a * B / d + np.sqrt(36 - a**2) * 1j * B / d
    lk = Linkage({"O2": 0j, "O4": O4, "A": A, "B": B}).ground("O2", "O4")
    lk = lk.link("in", "O2", "A").link("c", "A", "B").link("out", "O4", "B").drive("in")
    far = np.radians(60) + np.pi + np.linspace(-0.05, 0.05, 5)
    assert not lk.solve(far).ok.any()
    page = report(lk, values=far)
    first = re.search(r'id="headline">(.*?)</p>', page).group(1)
    assert "cannot be assembled" in first and first.startswith("linkage of 3 moving links")
    # the drawing as given: the drawn coordinates of B are in the page's SVG
    svg = re.search(r"<svg id=.*?</svg>", page, re.S).group(0)
    assert f"{B.real:.4f}".rstrip("0") in svg


def test_user_names_are_escaped_everywhere():
    evil = "<script>alert(1)</script>"
    lk = watt(names={"3": evil, "C": "<b>C</b>", "5": 'a"b&c'})
    page = report(lk, velocity=5.0, n=90)
    assert evil not in page and "<b>C</b>" not in page and 'a"b&c' not in page
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in page
    assert "&lt;b&gt;C&lt;/b&gt;" in page


def test_the_page_loads_nothing(hw6_page):
    assert not re.search(r"\b(src|href)\s*=\s*\"(?!#)", hw6_page)
    assert "<link" not in hw6_page and "@import" not in hw6_page
    assert not re.search(r"https?:", hw6_page)


def test_bad_model_is_refused():
    from machdyn.errors import InputError

    with pytest.raises(InputError, match="no report for a str"):
        report("four-bar")


# --------------------------------------------------------------------------------------
# machdyn report FILE -o report.html


@pytest.fixture
def cli(capsys):
    from machdyn.cli import main

    def run(*args):
        code = main(["report", *map(str, args)])
        out = capsys.readouterr()
        return code, out.out + out.err

    return run


EXAMPLES = __import__("pathlib").Path(__file__).parent.parent / "docs" / "examples"


def test_cli_writes_the_report_of_a_linkage_file(cli, tmp_path):
    out = tmp_path / "lid.html"
    code, output = cli(EXAMPLES / "lid.toml", "-o", out, "--samples", 120)
    assert code == 0, output
    page = out.read_text(encoding="utf-8")
    first = re.search(r'id="headline">(.*?)</p>', page).group(1)
    assert first in output.replace("'", "&#x27;")
    assert "0 to 90 deg" in first  # the file's sweep range
    assert set(checks_of(page).values()) <= {"pass", "not measured"}
    assert "x (m)" in page  # the file's length unit labels the tables


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("nofile.toml", "-o", "x.html"), "no such file"),
        ((EXAMPLES / "lid.toml", "-o", "x.docx"), "--out"),
        ((EXAMPLES / "lid.toml", "-o", "x.html", "--samples", 2), "--samples"),
        ((EXAMPLES / "lid.toml", "-o", "x.html", "--k", 0.9), "--k"),
    ],
)
def test_cli_bad_input_is_one_line(cli, args, needle, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, output = cli(*args)
    assert code != 0
    assert needle in output and "Traceback" not in output and len(output.splitlines()) == 1


def test_cli_reports_a_machine_file_with_its_units_and_masses(cli, tmp_path):
    import machdyn

    out = tmp_path / "hw6.html"
    code, output = cli(EXAMPLES / "hw6.toml", "-o", out, "--k", 0.05)
    assert code == 0, output
    page = out.read_text(encoding="utf-8")
    # the file's model, speed, masses, load and gravity, solved here through the API
    fb = machdyn.spec.load_machine(EXAMPLES / "hw6.toml")["hw6"]
    th = fourbar_sweep(fb, 1, 360)
    f = fb.dynamics(
        th,
        10.0,
        mass=(0.002, 0.004, 0.003),
        inertia=(0.003, 0.02, 0.01),
        cg=(2, 3.5 + 1j, 3),
        gravity=386.08858267716533,
        load_torque4=-5.0,
    )
    text = cell(page, "peak_F32")
    assert number(text) == pytest.approx(np.abs(f.F32).max(), rel=5e-4)
    assert "lbf" in text and "in)" in page  # the file's units label the numbers
    assert set(checks_of(page).values()) == {"pass"}


# --------------------------------------------------------------------------------------
# machine elements


def test_cam_report_lists_the_profiles_own_checks():
    from machdyn import cams

    prog = cams.CamProgram(
        [
            cams.Segment("rise", np.radians(60), 1.0, "cycloidal"),
            cams.Segment("dwell", np.radians(120)),
            cams.Segment("fall", np.radians(60), 1.0, "cycloidal"),
            cams.Segment("dwell", np.radians(120)),
        ]
    )
    cam = cams.TranslatingRoller(prime_radius=3.0, roller_radius=0.5).profile(prog)
    page = report(cam)
    for check in cam.checks():
        assert check.detail.replace("|", "|") in page.replace("&#x27;", "'")
    first = re.search(r'id="headline">(.*?)</p>', page).group(1)
    assert "passes every design check" in first
    # a cam too small for its lift fails the pressure angle, and the first line says so
    small = cams.TranslatingRoller(prime_radius=1.2, roller_radius=0.3).profile(prog)
    first = re.search(r'id="headline">(.*?)</p>', report(small)).group(1)
    assert "FAILS" in first and "pressure angle" in first


def test_gear_report_numbers_are_the_pairs():
    from machdyn.gears import Gear, GearPair

    pair = GearPair(Gear(18, module=1.0), Gear(40, module=1.0))
    page = report(pair)
    assert number(cell(page, "contact_ratio")) == pytest.approx(pair.contact_ratio, rel=1e-5)
    assert number(cell(page, "center_distance")) == pytest.approx(pair.center_distance, rel=1e-5)
    assert "no interference" in re.search(r'id="headline">(.*?)</p>', page).group(1)


def test_cli_report_of_a_machine_that_cannot_be_assembled_says_so_first(cli, tmp_path):
    spec = tmp_path / "bad.toml"
    spec.write_text("machdyn = 1\n[fourbar.bad]\nr1 = 20\nr2 = 4\nr3 = 7\nr4 = 6\n")
    out = tmp_path / "bad.html"
    code, output = cli(spec, "-o", out)
    assert code == 0, output
    page = out.read_text(encoding="utf-8")
    first = re.search(r'<body>\s*<p class="headline bad" id="headline">(.*?)</p>', page).group(1)
    assert "cannot be assembled" in first and "17" in first  # the sum of the other three
    assert "r1 = 20" in page  # the machine as given
