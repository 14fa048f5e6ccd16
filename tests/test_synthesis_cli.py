"""The ``machdyn synth`` commands, through typer's CliRunner on the sub-application."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from machdyn.cli.synth import parse_function, parse_points, synth_app
from machdyn.errors import AssemblyError, InputError

runner = CliRunner()
NOTES_C = "0,5.086; 2.019,3.181; 3.933,4.051"
NOTES_D = "0.741,2.703; 4.428,2.529; 6.304,4.83"


def test_three_position_table_shows_the_notes_pivot():
    r = runner.invoke(synth_app, ["three-position", "--c", NOTES_C, "--d", NOTES_D])
    assert r.exit_code == 0, r.output
    assert "(2.1779, 5.3718)" in r.output  # the notes' C pivot (2.178, 5.372)
    assert "2.1966" in r.output  # link 2 = 2.197


def test_three_position_json():
    r = runner.invoke(synth_app, ["three-position", "--c", NOTES_C, "--d", NOTES_D, "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.output)
    assert round(out["O2"]["x"], 3) == 2.178 and round(out["O2"]["y"], 3) == 5.372
    assert round(out["r2"], 3) == 2.197
    assert out["defects"] == []


def test_three_position_says_the_form_that_reaches_its_positions():
    """A FourBar with the printed lengths and form, placed at O2 and theta1, puts its
    moving pivot B on the given D positions (to the notes' 3-decimal data); the other
    form does not: copying the lengths needs the form too."""
    from machdyn import FourBar

    r = runner.invoke(synth_app, ["three-position", "--c", NOTES_C, "--d", NOTES_D, "--json"])
    out = json.loads(r.output)
    assert out["form"] in (1, 2)
    o2 = complex(out["O2"]["x"], out["O2"]["y"])
    d = np.array([complex(*map(float, p.split(","))) for p in NOTES_D.split(";")])
    fb = FourBar(out["r1"], out["r2"], out["r3"], out["r4"])
    theta2 = np.radians(out["theta2_deg"])  # from the ground line O2O4

    def b_at(form):
        m = fb.solve(theta2, form=form)
        local = out["r2"] * np.exp(1j * m.theta2) + out["r3"] * np.exp(1j * m.theta3)
        return o2 + np.exp(1j * np.radians(out["theta1_deg"])) * local

    assert np.max(np.abs(b_at(out["form"]) - d)) < 1e-3
    assert np.max(np.abs(b_at(3 - out["form"]) - d)) > 0.1
    table = runner.invoke(synth_app, ["three-position", "--c", NOTES_C, "--d", NOTES_D])
    (line,) = [ln for ln in table.output.splitlines() if "form (FourBar" in ln]
    assert line.split()[-1] == str(out["form"])


def test_three_position_inverted_problem():
    r = runner.invoke(
        synth_app,
        ["three-position", "--c", NOTES_C, "--d", NOTES_D, "--o2", "0.995,0", "--o4", "5.298,0"],
    )
    assert r.exit_code == 0, r.output
    assert "4.3030" in r.output  # the ground |O2O4|


def test_three_position_defect_exits_nonzero():
    # positions of a crank-rocker taken on two circuits (see test_synthesis_motion)
    from machdyn.fourbar import FourBar

    fb = FourBar(8, 4, 7, 6)
    m1, m2 = fb.solve(np.radians([20, 130])), fb.solve(np.radians([70]), form=2)
    a = [m1.A[0], m2.A[0], m1.A[1]]
    b = [m1.B[0], m2.B[0], m1.B[1]]
    fmt = lambda pts: "; ".join(f"{float(z.real)!r},{float(z.imag)!r}" for z in pts)  # noqa: E731
    r = runner.invoke(synth_app, ["three-position", "--c", fmt(a), "--d", fmt(b)])
    assert r.exit_code != 0
    assert isinstance(r.exception, AssemblyError)
    assert "circuit defect" in str(r.exception)


def test_function_command():
    args = ["function", "--f", "log10(x)", "--x", "1:2", "--theta2", "45:105"]
    r = runner.invoke(synth_app, [*args, "--theta4", "135:225", "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.output)
    np.testing.assert_allclose(
        out["x_precision"], [1.5 - np.sqrt(3) / 4, 1.5, 1.5 + np.sqrt(3) / 4]
    )
    assert out["max_abs_error"] < 1e-3
    r = runner.invoke(synth_app, [*args, "--theta4", "135:225"])
    assert r.exit_code == 0 and "Structural error" in r.output


def test_bad_cli_input():
    with pytest.raises(InputError, match="expected 3 points"):
        parse_points("0,0; 1,1", "--c", 3)
    with pytest.raises(InputError, match="could not read"):
        parse_points("0,0; a,1; 2,2", "--c", 3)
    with pytest.raises(InputError, match="allowed"):
        parse_function("open('x')")
    with pytest.raises(InputError, match="allowed"):
        parse_function("x.__class__")
    r = runner.invoke(
        synth_app,
        [
            "function",
            "--f",
            "x",
            "--x",
            "1:2",
            "--theta2",
            "0:60",
            "--theta4",
            "0:60",
            "--spacing",
            "random",
        ],
    )
    assert isinstance(r.exception, InputError) and "chebyshev" in str(r.exception)
