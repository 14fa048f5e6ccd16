"""Reports of slider-cranks, the inverted slider-crank and machines of several parts.

Independent references: SliderCrank.dynamics called here for the printed
peaks; the inverted slider-crank's quick-return ratio in closed form (a slot
through O4 is tangent to the crank circle at the limits, cos θ2 = a/d; Norton
§3.8); the self-checks fed motions made wrong on purpose; the machine page's
numbers against each part's own API call.
"""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from machdyn import InvertedSliderCrank, SliderCrank
from machdyn.dynamics import slidercrank_forces
from machdyn.dynamics_inverted import inverted_slidercrank_forces
from machdyn.report import report
from machdyn.report.slidercrank import inverted_checks, slidercrank_checks, slidercrank_sweep

EXAMPLES = Path(__file__).parent.parent / "docs" / "examples"
MASS, INERTIA, CG = (1.0, 2.0, 0.5), (0.1, 0.6), (1.0, 3.0 + 0.2j)


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


@pytest.fixture(scope="module")
def sc():
    return SliderCrank(2.0, 6.0, 0.5)


def test_slider_crank_report_numbers_are_the_apis(sc):
    page = report(sc, omega2=10.0, mass=MASS, inertia=INERTIA, cg=CG, load_force4=-20.0, k=0.05)
    assert headline(page).startswith("slider-crank 2-6, offset 0.5: assembles over the full turn")
    th = slidercrank_sweep(sc, 360)
    f = sc.dynamics(th, 10.0, mass=MASS, inertia=INERTIA, cg=CG, load_force4=-20.0)
    j = int(np.argmax(np.abs(f.F32)))
    text = cell(page, "peak_F32")
    assert number(text) == pytest.approx(abs(f.F32[j]), rel=5e-4)
    assert f"θ2 = {np.degrees(th[j]):.1f}°" in text
    assert number(cell(page, "T12_max")) == pytest.approx(f.T12.max(), rel=5e-4)
    lo, hi = sc.stroke(1)
    assert f"{lo:.4g}" in cell(page, "stroke") and f"{hi:.4g}" in cell(page, "stroke")
    states = checks_of(page)
    assert len(states) == 12 and set(states.values()) == {"pass"}, states
    for section in ("model", "class", "kinematics", "forces", "flywheel", "shaking", "selfcheck"):
        assert f'<section id="{section}"' in page, section


def test_slider_crank_checks_fail_on_a_wrong_motion(sc):
    th = slidercrank_sweep(sc, 360)
    m = sc.solve(th, 10.0)
    f = sc.dynamics(th, 10.0, mass=MASS, inertia=INERTIA, cg=CG)

    def failed(motion):
        return {
            c.name
            for c in slidercrank_checks(sc, motion, 10.0, f, MASS, INERTIA, CG)
            if not c.passed
        }

    assert failed(m) == set()
    acc = failed(replace(m, alpha3=m.alpha3 * 1.01, d_ddot=m.d_ddot * 1.01))
    assert {
        "loop closure: accelerations",
        "finite differences: acceleration",
        "power balance",
        "equilibrium of each link",
    } <= acc
    assert {"loop closure: velocities", "power balance"} <= failed(
        replace(m, omega3=m.omega3 * 1.01)
    )
    # ḋ enters Kennedy's rule: I24 = −jḋ/ω2 must lie on the rod's line AB
    assert {"finite differences: velocity", "Kennedy's rule"} <= failed(
        replace(m, d_dot=m.d_dot * 1.01)
    )
    # forces solved from the wrong accelerations: only the momentum's differences
    # (and the motion checks) see it — F_s = −d/dt Σ m v_G by five-point differences
    bad = replace(m, alpha3=m.alpha3 * 1.01, d_ddot=m.d_ddot * 1.01)
    f_bad = slidercrank_forces(sc, bad, mass=MASS, inertia=INERTIA[:2], cg=CG[:2])
    consistent = {
        c.name for c in slidercrank_checks(sc, bad, 10.0, f_bad, MASS, INERTIA, CG) if not c.passed
    }
    assert consistent == {
        "loop closure: accelerations",
        "finite differences: acceleration",
        "momentum by differences",
    }
    assert {"momentum: shaking force and moment", "equilibrium of each link"} <= acc
    # a wrong position: the loop and the rod angle
    moved = failed(replace(m, B=m.B + 1e-5))
    assert {"loop closure: positions", "link angles"} <= moved
    # every self-check of the slider-crank report is failed by one of the wrong motions
    names = {c.name for c in slidercrank_checks(sc, m, 10.0, f, MASS, INERTIA, CG)}
    every = (
        acc
        | consistent
        | moved
        | failed(replace(m, omega3=m.omega3 * 1.01))
        | failed(replace(m, d_dot=m.d_dot * 1.01))
    )
    assert every == names


def test_inverted_slider_crank_report_and_its_quick_return_ratio():
    a, d = 100.0, 300.0
    isc = InvertedSliderCrank(a, d)
    page = report(isc, omega2=2.0)
    assert headline(page).startswith("inverted slider-crank, crank 100, ground 300")
    beta = np.arccos(a / d)  # limits where the slot is tangent to the crank circle
    expected = (2 * np.pi - 2 * beta) / (2 * beta)
    assert number(cell(page, "time_ratio")) == pytest.approx(expected, rel=0.02)
    assert set(checks_of(page).values()) == {"pass"}


def test_inverted_checks_catch_a_wrong_acceleration():
    isc = InvertedSliderCrank(2.0, 4.0, 0.5)
    m = isc.solve(slidercrank_sweep(isc, 360), 3.0)
    assert all(c.passed for c in inverted_checks(isc, m, 3.0))
    bad = {
        c.name
        for c in inverted_checks(isc, replace(m, b_ddot=m.b_ddot * 1.01), 3.0)
        if not c.passed
    }
    assert {"loop closure: accelerations", "finite differences: acceleration"} <= bad
    bad = {
        c.name
        for c in inverted_checks(isc, replace(m, omega4=m.omega4 * 1.01), 3.0)
        if not c.passed
    }
    assert {"loop closure: velocities", "finite differences: velocity"} <= bad


# --------------------------------------------------------------------------------------
# machine files of several parts


@pytest.fixture
def cli(capsys):
    from machdyn.cli import main

    def run(*args):
        code = main(["report", *map(str, args)])
        out = capsys.readouterr()
        return code, out.out + out.err

    return run


def test_a_machine_of_two_slider_cranks_reports_both(cli, tmp_path):
    from machdyn.spec import load_machine

    out = tmp_path / "sc.html"
    code, output = cli(EXAMPLES / "slider_crank.toml", "-o", out)
    assert code == 0, output
    page = out.read_text(encoding="utf-8")
    first = headline(page)
    assert first.startswith("Slider-cranks: 2 parts.") and "engine (slider crank)" in first
    assert "shaper (inverted slider crank)" in first
    # the engine's forces: the file's masses, gas load, Coulomb friction and speed (3000 rpm)
    machine = load_machine(EXAMPLES / "slider_crank.toml")
    sc = machine["engine"]
    th = slidercrank_sweep(sc, 360)
    v = machine.parts["engine"].values
    f = sc.dynamics(
        th,
        3000 * 2 * np.pi / 60,
        mass=(1.0, 2.0, 1.5),
        inertia=(v["link2"]["inertia"], v["link3"]["inertia"]),
        cg=(20.0, 100.0),
        load_force4=v["loads"]["force4"],
        friction="coulomb",
        mu=0.05,
    )
    text = cell(page, "engine:peak_F32")
    shown = machine.units.show("force", np.abs(f.F32).max())
    assert number(text) == pytest.approx(shown, rel=5e-4) and text.split()[1] == "N"
    states = checks_of(page)
    assert any(k.startswith("engine:") for k in states) and any(
        k.startswith("shaper:") for k in states
    )
    assert set(states.values()) == {"pass"}, states
    # each part's sections are numbered under it
    assert '<section id="part1" class="l2">' in page and 'id="part2-selfcheck"' in page


def test_a_machine_with_parts_without_a_report_shows_their_summary(cli, tmp_path):
    out = tmp_path / "press.html"
    code, output = cli(EXAMPLES / "press.toml", "-o", out, "--samples", 180)
    assert code == 0, output
    page = out.read_text(encoding="utf-8")
    assert "press:peak_F32" in page and "reducer:contact_ratio" in page
    assert re.search(r'data-key="crank:[a-z_]*inertia[a-z_]*"', page)  # the flywheel's summary
    assert set(checks_of(page).values()) == {"pass"}


def test_parts_without_a_report_show_their_curve_or_drawing(cli, tmp_path):
    from machdyn.draw.units import Units
    from machdyn.spec import load_machine

    out = tmp_path / "press.html"
    assert cli(EXAMPLES / "press.toml", "-o", out, "--samples", 90)[0] == 0
    page = out.read_text(encoding="utf-8")
    machine = load_machine(EXAMPLES / "press.toml")
    fly = machine.run()["crank"].objects["flywheel"]
    # the flywheel part: its torque curve with the energy lobes, ΔE in the file's units
    title = re.search(r"input torque and flywheel lobes: ΔE = ([-\d.e+]+) ([^,]+),", page)
    assert float(title.group(1)) == pytest.approx(
        Units.of(machine.units).show("energy", fly.delta_e), rel=1e-3
    )
    out = tmp_path / "synthesis.html"
    assert cli(EXAMPLES / "synthesis.toml", "-o", out)[0] == 0
    page = out.read_text(encoding="utf-8")
    # both synthesised four-bars drawn (the motion task in its three precision positions)
    assert len(re.findall(r'<svg id="[^"]+" class="machdyn-drawing"', page)) == 2
    assert "in its 3 precision positions" in page


def test_transmission_angles_with_their_limit_in_closed_form(sc):
    # slider-crank: μ = 90° − |rod angle|, sin(rod angle) = (a sin θ2 − c)/b, smallest at 270°
    page = report(sc, n=360)
    expected = 90.0 - np.degrees(np.arcsin((2.0 + 0.5) / 6.0))
    assert number(cell(page, "mu_min_deg")) == pytest.approx(expected, abs=5e-3)
    assert f"μ min = {expected:.2f}° at θ2 = 270.0°" in page  # the chart marks it
    assert "limit 40°" in page


def test_linkage_report_draws_the_transmission_angle_of_every_dyad():
    from test_report import watt

    lk = watt()
    page = report(lk, velocity=10.0, n=360)
    x = np.radians(np.linspace(0.0, 360.0, 360))
    m = lk.solve({"2": x})
    P = {k: np.ravel(v) for k, v in m.points.items()}
    # μ written here from the pins: the acute angle between the two links at B and at D
    for key, (mid, a, b) in {"mu_min_0": ("B", "A", "O4"), "mu_min_1": ("D", "C", "O6")}.items():
        ang = np.abs(np.angle((P[a] - P[mid]) / (P[b] - P[mid])))
        mu = np.degrees(np.minimum(ang, np.pi - ang))
        assert number(cell(page, key)) == pytest.approx(np.nanmin(mu), abs=0.3)  # 1° sweep
    for group in ("RRR dyad (3, 4)", "RRR dyad (5, 6)"):  # a chart each, with the limit
        assert f"transmission angle of the {group}" in page


def test_the_flywheel_check_fails_on_a_wrong_energy():
    from machdyn.flywheel import size_flywheel
    from machdyn.report.checks import flywheel_energy

    th = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    T = 10.0 + 4.0 * np.sin(2 * th) + np.cos(3 * th)
    right = size_flywheel(th, T, 12.0, 0.05)
    assert flywheel_energy(th, T, right).passed
    # ΔE of this curve in closed form: T − T_avg = 4 sin 2θ + cos 3θ; its integral's spread
    E = (
        -2.0 * np.cos(2 * np.linspace(0, 2 * np.pi, 100_001))
        + np.sin(3 * np.linspace(0, 2 * np.pi, 100_001)) / 3.0
    )
    assert right.delta_e == pytest.approx(np.ptp(E), rel=1e-3)
    # the sizing checked against a torque 1 % larger fails, and so does an inertia 1 % off
    assert not flywheel_energy(th, T * 1.01, right).passed
    assert not flywheel_energy(th, T, replace(right, inertia=right.inertia * 1.01)).passed


ISC_MASS, ISC_INERTIA, ISC_CG = (2.0, 0.5, 6.0), (0.01, 0.001, 0.2), (0.05, 0.01j, 0.25 + 0.01j)
ISC_KW = dict(mass=ISC_MASS, inertia=ISC_INERTIA, cg=ISC_CG, gravity=9.81, load_torque4=-40.0)


def test_inverted_slider_crank_report_shows_its_forces_as_the_api_gives_them():
    isc = InvertedSliderCrank(0.1, 0.3, 0.02)
    page = report(isc, omega2=12.0, k=0.05, **ISC_KW)
    th = slidercrank_sweep(isc, 360)
    f = isc.dynamics(th, 12.0, **ISC_KW)
    for name in ("F12", "F32", "F43", "F14"):
        j = int(np.argmax(np.abs(getattr(f, name))))
        text = cell(page, f"peak_{name}")
        assert number(text) == pytest.approx(abs(getattr(f, name)[j]), rel=5e-4), name
        assert f"θ2 = {np.degrees(th[j]):.1f}°" in text
    jmax = int(np.argmax(f.T12))
    assert number(cell(page, "T12_max")) == pytest.approx(f.T12[jmax], rel=5e-4)
    assert f"θ2 = {np.degrees(th[jmax]):.1f}°" in cell(page, "T12_max")
    assert number(cell(page, "shaking_force_max")) == pytest.approx(
        np.abs(f.shaking_force).max(), rel=5e-4
    )
    states = checks_of(page)
    assert set(states.values()) == {"pass"} and len(states) == 12, states
    for key in ("power_balance", "equilibrium_of_each_link", "momentum_shaking_force_and_moment"):
        assert key in states
    for section in ("forces", "flywheel", "shaking", "selfcheck"):
        assert f'<section id="{section}"' in page, section
    assert "No mass properties" in report(isc, omega2=12.0, n=72)


@pytest.mark.parametrize("friction", [{}, {"friction": "coulomb", "mu": 0.2}])
def test_inverted_force_checks_fail_on_a_wrong_motion_or_force(friction):
    isc = InvertedSliderCrank(0.1, 0.3, 0.02)
    th = slidercrank_sweep(isc, 360)
    m = isc.solve(th, 12.0)
    f = isc.dynamics(th, 12.0, **ISC_KW, **friction)
    kw = {k: ISC_KW[k] for k in ("mass", "inertia", "cg", "gravity", "load_torque4")}

    def failed(motion, forces=f):
        return {c.name for c in inverted_checks(isc, motion, 12.0, forces, **kw) if not c.passed}

    assert failed(m) == set()
    acc = failed(replace(m, alpha4=m.alpha4 * 1.01, b_ddot=m.b_ddot * 1.01))
    assert {
        "loop closure: accelerations",
        "finite differences: acceleration",
        "power balance",
        "equilibrium of each link",
        "momentum: shaking force and moment",
    } <= acc
    assert {"power balance", "equilibrium of each link"} <= failed(m, replace(f, T12=f.T12 * 1.01))
    assert {"equilibrium of each link"} <= failed(m, replace(f, couple=f.couple * 1.01 + 1e-3))
    assert {"momentum: shaking force and moment", "momentum by differences"} <= failed(
        m, replace(f, shaking_moment=f.shaking_moment * 1.01)
    )
    # forces solved consistently from the wrong motion: only the rates of positions catch them
    wrong = replace(m, alpha4=m.alpha4 * 1.01, b_ddot=m.b_ddot * 1.01)
    f_wrong = inverted_slidercrank_forces(isc, wrong, **ISC_KW, **friction)
    assert {"momentum by differences", "finite differences: acceleration"} <= failed(wrong, f_wrong)
