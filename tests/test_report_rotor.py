"""The rotor report: masses and planes, corrections, bearing loads before and after.

Independent references: the notes' two-plane balance (Ch. 12, "Two-plane
dynamic balancing", Norton Fig. 12-3): moments about plane A give
``m_B l_B R_B = −Σ mᵢ lᵢ Rᵢ``, the force balance ``m_A R_A = −Σ mᵢ Rᵢ − m_B R_B``
— written here with complex numbers, apart from ``machdyn.balancing``; the
bearing loads by statics written here (moments about bearing A of the rotating
forces ``mᵢ Rᵢ ω²``); after correction the loads of the corrected rotor are ~0.
Every self-check is fed wrong numbers and fails.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from machdyn.report import report
from machdyn.report.rotor import rotor_checks
from machdyn.rotor import Rotor
from machdyn.spec import RotorBalance, load_machine

EXAMPLES = Path(__file__).parent.parent / "docs" / "examples"


def cell(page: str, key: str) -> str:
    found = re.findall(rf'data-key="{re.escape(key)}"[^>]*>(.*?)</(?:td|span|p)>', page, re.S)
    assert len(found) == 1, (key, found)
    return re.sub(r"<[^>]+>", "", found[0])


def number(text: str) -> float:
    return float(re.match(r"\s*(-?[\d.]+(?:e[-+]?\d+)?)", text).group(1))


def checks_of(page: str) -> dict[str, str]:
    return dict(re.findall(r'data-check="([\w:]+)".*?class="state">([\w ]+)<', page, re.S))


def by_hand(masses, za, zb):
    """The notes' two-plane corrections (m R as complex numbers)."""
    mr = np.array([m * r * np.exp(1j * a) for m, r, a, _ in masses])
    lever = np.array([z for *_, z in masses]) - za
    b = -(mr * lever).sum() / (zb - za)
    return -mr.sum() - b, b


def loads_by_hand(masses, omega, za, zb):
    mr = np.array([m * r * np.exp(1j * a) for m, r, a, _ in masses])
    z = np.array([e[3] for e in masses])
    lb = omega**2 * (mr * (z - za)).sum() / (zb - za)
    return omega**2 * mr.sum() - lb, lb


def test_rotor_file_report_is_the_notes_two_plane_balance():
    machine = load_machine(EXAMPLES / "rotor.toml")
    task = machine["shaft"]
    page = report(machine)
    a, b = by_hand(task.masses, 0.0, 400.0)
    for name, c in (("A", a), ("B", b)):
        assert number(cell(page, f"mR_{name}")) == pytest.approx(abs(c), rel=1e-5)  # kg·mm
        assert number(cell(page, f"angle_{name}")) == pytest.approx(
            np.degrees(np.angle(c)) % 360, rel=1e-5
        )
        assert number(cell(page, f"mass_{name}")) == pytest.approx(abs(c) / 100, rel=1e-5)
    omega = 1500 * 2 * np.pi / 60
    la, lb = loads_by_hand(task.masses, omega, 0.0, 400.0)  # kg·mm/s² = mN
    assert number(cell(page, "load_A_before")) == pytest.approx(abs(la) / 1000, rel=1e-5)
    assert number(cell(page, "load_B_before")) == pytest.approx(abs(lb) / 1000, rel=1e-5)
    assert cell(page, "load_A_before").split()[1] == "N"
    for name in ("A", "B"):
        assert number(cell(page, f"load_{name}_after")) < 1e-9 * abs(la) / 1000
    states = checks_of(page)
    assert len(states) == 4 and set(states.values()) == {"pass"}, states
    for section in ("masses", "balance", "bearings", "selfcheck"):
        assert f'<section id="{section}"' in page
    assert page.count('<svg class="chart"') == 3  # side view, unbalance and moment polars


def test_bearings_apart_from_the_correction_planes():
    masses = ((2.0, 0.1, 0.3, 0.2), (1.0, 0.05, 2.0, 0.5))
    task = RotorBalance(masses, planes=(0.1, 0.6), radii=(0.2, 0.2))
    page = report(task, bearings=(0.0, 0.8), speed=50.0)
    la, lb = loads_by_hand(masses, 50.0, 0.0, 0.8)
    assert number(cell(page, "load_A_before")) == pytest.approx(abs(la), rel=1e-5)
    assert number(cell(page, "load_B_before")) == pytest.approx(abs(lb), rel=1e-5)
    assert set(checks_of(page).values()) == {"pass"}
    assert "Bearings given" in page


def test_a_rotor_with_products_of_inertia():
    # a tilted disc off-centre: U and P from the tensor, corrected in planes 0 and 0.4
    tensor = [[0.5, 0, -0.05], [0, 0.5, 0.02], [-0.05, 0.02, 0.9]]
    rotor = Rotor(10.0, (0.001, -0.002, 0.2), tensor, about="cg")
    page = report(rotor, planes=(0.0, 0.4), speed=100.0)
    fix = rotor.two_plane_correction(0.0, 0.4)
    assert number(cell(page, "mR_A")) == pytest.approx(abs(fix.mR_a), rel=1e-5)
    u, p = rotor.unbalance, rotor.couple_unbalance
    assert abs(complex(fix.mR_a) + complex(fix.mR_b) + u) < 1e-12  # the notes' force balance
    assert abs(0.4 * complex(fix.mR_b) + p) < 1e-12  # moments about plane A
    assert set(checks_of(page).values()) == {"pass"}


def test_static_balance_without_bearings_reports_the_shaking_force():
    task = RotorBalance(((3.0, 1.0, 0.0, 0.0), (2.0, 1.0, np.pi / 2, 0.0)), speed=10.0)
    page = report(task)
    assert number(cell(page, "mR_static")) == pytest.approx(np.sqrt(13), rel=1e-5)
    assert number(cell(page, "angle_static")) == pytest.approx(213.69, abs=0.01)  # the notes
    assert number(cell(page, "shaking_before")) == pytest.approx(100 * np.sqrt(13), rel=1e-5)
    states = checks_of(page)
    assert set(states) == {"residual_bearing_forces", "force_sum_with_the_corrections"}
    assert set(states.values()) == {"pass"}


def test_rotor_checks_fail_on_wrong_numbers():
    masses = ((0.2, 60, np.radians(30), 100), (0.3, 50, np.radians(150), 220))
    a, b = by_hand(masses, 0.0, 400.0)
    mr = np.array([m * r * np.exp(1j * t) for m, r, t, _ in masses])
    z = np.array([e[3] for e in masses])
    rotor = Rotor.from_masses([m for m, *_ in masses], mr / [m for m, *_ in masses], z)
    w, scale = 100.0, float(np.abs(mr).sum())
    before = loads_by_hand(masses, w, 0.0, 400.0)

    def names(corrections, loads=before):
        c = np.array(corrections)
        after = rotor.with_masses(np.abs(c), c / np.abs(c), [0.0, 400.0])
        r = after.bearing_reactions(w, 0.0, 400.0)
        residual = max(abs(complex(r.reaction_a)), abs(complex(r.reaction_b)))
        checks = rotor_checks(
            mr.sum(),
            (mr * z).sum(),
            c,
            (0.0, 400.0),
            omega=w,
            scale=scale,
            residual=residual,
            bearings=(0.0, 400.0),
            loads_before=loads,
        )
        return {k.name for k in checks if not k.passed}

    assert names([a, b]) == set()
    turned = a * np.exp(1j * np.radians(1.0))  # plane A's mass 1° off
    assert names([turned, b]) == {"residual bearing forces", "force sum with the corrections"}
    assert names([a, b * 1.01]) == {
        "residual bearing forces",
        "force sum with the corrections",
        "moment sum with the corrections",
    }
    assert names([a, b], (before[0] * 1.01, before[1])) == {"bearing forces by statics"}


def test_the_side_view_draws_each_mass_at_its_plane_and_height():
    from machdyn.draw.rotor import rotor_side_chart

    masses = ((0.2, 60, np.radians(30), 100), (0.3, 50, np.radians(150), 220))
    chart = rotor_side_chart(masses, (0, 400), bearings=(-20, 420))
    stems = {s.gid: s for s in chart.series if s.gid.startswith("mass_")}
    for i, (_, r, a, z) in enumerate(masses, start=1):
        assert stems[f"mass_{i}"].x.tolist() == [z, z]
        assert stems[f"mass_{i}"].y[1] == pytest.approx(r * np.sin(a))
    notes = {n: x for x, _, n in chart.notes}
    assert notes["plane A"] == 0 and notes["plane B"] == 400 and notes["bearing B"] == 420


def test_bad_rotor_report_options_are_refused_by_name():
    from machdyn.errors import InputError

    task = RotorBalance(((1.0, 0.1, 0.0, 0.2),), planes=(0.0, 1.0))
    for options, field in (
        ({"bearings": (0.0,)}, "bearings"),
        ({"bearings": (0.5, 0.5)}, "bearings"),
        ({"speed": 0.0}, "speed"),
        ({"speed": float("nan")}, "speed"),
        ({"radii": (-1.0,)}, "radii"),
    ):
        with pytest.raises(InputError, match=field):
            report(task, **options)
    with pytest.raises(InputError, match="planes"):
        report(Rotor(1.0, (0.01, 0.0, 0.0)), planes=(1.0, 2.0, 3.0))
    # a rotor balanced already: no correction, nothing on the bearings, every check passes
    balanced = RotorBalance(((1.0, 0.1, 0.0, 0.2), (1.0, 0.1, np.pi, 0.2)), planes=(0.0, 1.0))
    assert set(checks_of(report(balanced, speed=10.0)).values()) == {"pass"}
