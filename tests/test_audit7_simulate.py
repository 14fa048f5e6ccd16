"""Audit 7: a huge simulated time is refused by its budget, naming the key that asked for it.

Before, ``simulate(..., t_end=1e6)`` was accepted and integrated for as long as
it was asked (hours at ~450 evaluations of the equation of motion per turn of
the notes' HW 6 crank-rocker). Now a run has a documented budget,
``max_evaluations``; these tests use a small one so that they stay fast.
"""

from __future__ import annotations

import numpy as np
import pytest

import machdyn
from machdyn.cli import main
from machdyn.simulate import DCMotor, simulate

#: The notes' HW 6 crank-rocker in metres (docs/examples/motor.toml), on a DC motor.
FB = machdyn.FourBar(0.08, 0.04, 0.07, 0.06)
MASSES = dict(
    mass=(0.2, 0.3, 0.25),
    inertia=(3e-5, 1.2e-4, 7.5e-5),
    cg=(0.02, 0.035, 0.03),
    gravity=9.81,
)
MOTOR = DCMotor(stall_torque=5.0, no_load_speed=30.0)


@pytest.mark.parametrize(
    ("stop", "field"),
    [({"t_end": 1e6}, "t_end"), ({"turns": 1e7}, "turns"), ({"until": "steady"}, "until")],
)
def test_a_run_beyond_its_budget_is_refused_naming_the_key(stop, field):
    """A flywheel-less crank under gravity never settles within 3,000 evaluations."""
    with pytest.raises(machdyn.InputError) as info:
        simulate(FB, MOTOR, max_evaluations=3000, steady_tol=1e-14, **stop, **MASSES)
    assert info.value.field == field
    assert "3,000 evaluations" in str(info.value)
    # The time reached is reported: a positive number of seconds, well short of what was asked.
    reached = float(str(info.value).split("reached t = ")[1].split(" s")[0])
    assert 0.0 < reached < 1e6


def test_a_run_within_the_budget_is_the_same_run():
    """The budget only refuses: a run that fits gives the same motion as with a larger one."""
    small = simulate(FB, MOTOR, t_end=0.3, flywheel=0.02, max_evaluations=50_000, **MASSES)
    large = simulate(FB, MOTOR, t_end=0.3, flywheel=0.02, **MASSES)
    assert small.status == large.status == "t_end"
    np.testing.assert_array_equal(small.theta, large.theta)


@pytest.mark.parametrize("bad", [0, 99, 2.5, "many", float("nan")])
def test_a_bad_budget_is_refused_by_name(bad):
    with pytest.raises(machdyn.InputError) as info:
        simulate(FB, MOTOR, t_end=0.1, max_evaluations=bad, **MASSES)
    assert info.value.field == "max_evaluations"


def _five_bar():
    from machdyn.linkage import Linkage

    pts = {"O2": 0j, "O5": 6 + 0j, "A": 2j, "D": 6 + 2j, "C": 3 + 5j}
    return (
        Linkage(pts)
        .ground("O2", "O5")
        .link("2", "O2", "A", mass=1.0, inertia=0.3)
        .link("3", "A", "C", mass=1.0, inertia=2.0)
        .link("4", "D", "C", mass=1.0, inertia=2.0)
        .link("5", "O5", "D", mass=1.0, inertia=0.3)
        .drive("2", "5")
    )


def test_several_drivers_are_held_to_the_budget_too():
    from machdyn.simulate import simulate_drivers

    with pytest.raises(machdyn.InputError) as info:
        simulate_drivers(_five_bar(), {"2": 10.0, "5": -10.0}, t_end=1e6, gravity=9.81,
                         max_evaluations=100)  # fmt: skip
    assert info.value.field == "t_end"


def test_cli_refuses_a_huge_t_end_in_one_line(tmp_path, capsys):
    file = tmp_path / "motor.toml"
    file.write_text(
        'machdyn = 1\n[units]\nlength = "m"\nmass = "kg"\n'
        "[fourbar.hw6]\nr1 = 0.08\nr2 = 0.04\nr3 = 0.07\nr4 = 0.06\n"
        "[fourbar.hw6.link2]\nmass = 0.2\ninertia = 3e-5\ncg = 0.02\n"
        "[fourbar.hw6.link3]\nmass = 0.3\ninertia = 1.2e-4\ncg = 0.035\n"
        "[fourbar.hw6.link4]\nmass = 0.25\ninertia = 7.5e-5\ncg = 0.03\n"
        "[fourbar.hw6.simulate]\n"
        'motor = { kind = "dc", stall_torque = 5, no_load_speed = 30 }\n'
        't_end = "1e6 s"\nmax_evaluations = 2000\n'
    )
    status = main(["simulate", str(file)])
    err = capsys.readouterr().err
    assert status not in (0, None)
    assert len(err.strip().splitlines()) == 1
    assert "t_end" in err and "2,000 evaluations" in err and "Traceback" not in err


def test_the_default_budget_is_the_paths_own(monkeypatch):
    """Tabulated runs take MAX_EVALUATIONS, runs solving the model at every evaluation
    (table=False, several drivers; ms each) SOLVED_EVALUATIONS: each default, made small
    here, is the one a run without ``max_evaluations`` is refused by."""
    from machdyn.simulate import _integrate, _setup, simulate_drivers

    assert (_integrate.MAX_EVALUATIONS, _integrate.SOLVED_EVALUATIONS) == (2_000_000, 50_000)
    monkeypatch.setattr(_setup, "MAX_EVALUATIONS", 300)
    monkeypatch.setattr(_setup, "SOLVED_EVALUATIONS", 200)
    for table, limit in ((True, "300"), (False, "200")):
        with pytest.raises(machdyn.InputError, match=f"more than the {limit} evaluations"):
            simulate(FB, MOTOR, t_end=1e6, table=table, **MASSES)
    with pytest.raises(machdyn.InputError, match="more than the 200 evaluations"):
        simulate_drivers(_five_bar(), {"2": 10.0, "5": -10.0}, t_end=1e6, gravity=9.81)
