"""Critical path motion: a table of (θ, s) points fitted by a periodic B-spline.

The notes: "critical path motion — follower displacement is specified throughout the
motion"; "finite jerk requirement: acceleration must be continuous".
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import BSpline

from machdyn import cams
from machdyn.cams import CamProgram, CriticalPathMotion, TranslatingRoller
from machdyn.errors import InputError

deg = np.radians
TABLE_DEG = np.array([0, 30, 75, 120, 160, 200, 250, 300, 330])
TABLE_S = np.array([0.0, 0.2, 0.9, 1.2, 1.25, 1.0, 0.5, 0.15, 0.05])


@pytest.mark.parametrize("degree", [3, 4, 5, 6, 7])
def test_passes_through_its_points(degree):
    cpm = CriticalPathMotion(deg(TABLE_DEG), TABLE_S, degree=degree)
    assert np.max(np.abs(cpm.svaj(deg(TABLE_DEG)).s - TABLE_S)) < 1e-12
    assert cpm.residual < 1e-12


@pytest.mark.parametrize("degree", [3, 5])
def test_acceleration_is_continuous_everywhere_including_the_wrap(degree):
    cpm = CriticalPathMotion(deg(TABLE_DEG), TABLE_S, degree=degree)
    # one-sided values a hair either side of every knot (and of 0° = 360°)
    knots = np.append(deg(TABLE_DEG), 2 * np.pi)
    h = 1e-7
    left, right = cpm.svaj(knots - h), cpm.svaj(knots + h)
    peak = {q: np.max(np.abs(getattr(cpm.sample(3600), q))) for q in "sva"}
    for q in "sva":
        jump = np.abs(getattr(right, q) - getattr(left, q))
        assert np.max(jump) < 1e-5 * peak[q], q
    assert cpm.continuity().ok


def test_derivatives_agree_with_finite_differences_of_the_displacement():
    cpm = CriticalPathMotion(deg(TABLE_DEG), TABLE_S, degree=5)
    theta = np.linspace(0, 2 * np.pi, 721)
    h = 1e-4
    m, p, q = cpm.svaj(theta), cpm.svaj(theta + h), cpm.svaj(theta - h)
    assert np.allclose((p.s - q.s) / (2 * h), m.v, atol=1e-6)
    assert np.allclose((p.v - q.v) / (2 * h), m.a, atol=1e-5)
    assert np.allclose((p.a - q.a) / (2 * h), m.j, atol=1e-4)


def test_a_dense_table_of_a_cycloidal_program_reproduces_its_svaj():
    program = CamProgram.double_dwell(1.0, deg(90), deg(90), law="poly4567")
    grid = np.arange(0, 360, 4.0)
    cpm = CriticalPathMotion.from_degrees(grid, program.svaj(deg(grid)).s, degree=5)
    check = deg(np.arange(0, 360, 0.5))
    exact, fit = program.svaj(check), cpm.svaj(check)
    assert np.max(np.abs(fit.s - exact.s)) < 1e-5
    assert np.max(np.abs(fit.v - exact.v)) < 1e-3 * np.max(np.abs(exact.v))
    assert np.max(np.abs(fit.a - exact.a)) < 1e-2 * np.max(np.abs(exact.a))


def test_a_full_turn_table_that_closes_is_accepted_and_its_start_anywhere():
    closed = CriticalPathMotion.from_degrees([*TABLE_DEG, 360], [*TABLE_S, TABLE_S[0]])
    open_ = CriticalPathMotion.from_degrees(TABLE_DEG, TABLE_S)
    theta = np.linspace(0, 2 * np.pi, 50)
    assert np.allclose(closed.svaj(theta).s, open_.svaj(theta).s)
    shifted = CriticalPathMotion.from_degrees(TABLE_DEG - 40.0, TABLE_S)  # starts at −40°
    assert np.allclose(shifted.svaj(deg(TABLE_DEG - 40.0)).s, TABLE_S)
    assert np.all((shifted.sample(36).theta >= 0) & (shifted.sample(36).theta < 2 * np.pi))


def test_smoothing_stays_within_the_rms_asked_and_is_smoother():
    rng = np.random.default_rng(3)
    grid = np.arange(0, 360, 5.0)
    clean = 0.5 * (1 - np.cos(deg(grid)))
    noisy = clean + rng.normal(0, 0.01, grid.size)
    exact = CriticalPathMotion.from_degrees(grid, noisy, degree=5)
    smooth = CriticalPathMotion.from_degrees(grid, noisy, degree=5, smoothing=0.012)
    rms = np.sqrt(np.mean((smooth.svaj(deg(grid)).s - noisy) ** 2))
    assert rms <= 0.012 * np.sqrt(1.001)  # FITPACK meets its target to 0.1 %
    assert smooth.residual > 1e-4  # no longer through every point
    peak = lambda m: np.max(np.abs(m.sample(3600).a))  # noqa: E731
    assert peak(smooth) < 0.5 * peak(exact)
    assert smooth.continuity().ok


def test_continuity_check_finds_a_jump_it_is_shown():
    # the checker reads the spline's pieces: a degree-3 spline with a triple knot
    # has a jump in acceleration there, and the report must say where.
    cpm = CriticalPathMotion(deg(TABLE_DEG), TABLE_S, degree=3)
    t = np.concatenate([np.linspace(-3, 0, 4)[:-1], [0, 1, 2, 2, 2, 3, 4, 5, 2 * np.pi]])
    t = np.concatenate([t, 2 * np.pi + np.array([1.0, 2.0, 3.0])])
    cpm.spline = BSpline(t, np.sin(np.arange(t.size - 4)), 3, extrapolate="periodic")
    jumps = [d for d in cpm.continuity().discontinuities if abs(d.theta - 2.0) < 1e-12]
    assert any(d.quantity == "a" for d in jumps)
    assert "jerk jumps" in cpm.continuity().notes[0]


def test_profile_sizing_and_checks_accept_it():
    cpm = CriticalPathMotion.from_degrees(TABLE_DEG, TABLE_S)
    cam = TranslatingRoller(prime_radius=3.0, roller_radius=0.5).profile(cpm, n=720)
    assert cam.theta.size == 720 and np.allclose(cam.s, cpm.sample(720).s)
    assert [c.name for c in cam.checks()]
    sized = cams.size_roller(cpm, roller_radius=0.5)
    assert sized.prime_radius > 0
    assert "CriticalPathMotion(9 points, degree 5" in repr(cpm)


@pytest.mark.parametrize(
    ("theta_deg", "s", "kwargs", "field", "words"),
    [
        (TABLE_DEG[::-1], TABLE_S, {}, "theta", "increase strictly"),
        ([0, 30, 30, 90, 180, 270], [0, 1, 1, 2, 1, 0.5], {}, "theta", "increase strictly"),
        ([0, 90, 180, 270, 360], [0, 1, 2, 1, 0.5], {}, "s", "not periodic"),
        ([0, 90, 180, 270, 400], [0, 1, 2, 1, 0], {}, "theta", "more than one turn"),
        ([0, 90, 180, 270], [0, 1, 2, 1], {"degree": 5}, "theta", "at least 6"),
        (TABLE_DEG, TABLE_S, {"degree": 2}, "degree", "degree 3 or more"),
        (TABLE_DEG, TABLE_S, {"degree": 7, "smoothing": 0.1}, "smoothing", "at most 5"),
        (TABLE_DEG, TABLE_S, {"smoothing": -1.0}, "smoothing", ""),
        (TABLE_DEG, TABLE_S[:-1], {}, "s", "one value per angle"),
        ([0, 90, np.nan, 270], [0, 1, 2, 1], {}, "theta", "finite"),
    ],
)
def test_bad_tables_are_refused_naming_the_field(theta_deg, s, kwargs, field, words):
    with pytest.raises(InputError) as err:
        CriticalPathMotion.from_degrees(theta_deg, s, **kwargs)
    assert err.value.field == field
    assert words in str(err.value)


def test_cli_table_option(tmp_path, capsys):
    import json

    from machdyn.cli import main

    path = tmp_path / "path.csv"
    lines = ["theta_deg,s", *(f"{t},{s}" for t, s in zip(TABLE_DEG, TABLE_S, strict=True))]
    path.write_text("\n".join(lines) + "\n")
    args = ["cam", "--table", str(path), "--prime-radius", "3", "--roller-radius", "0.5"]
    assert main([*args, "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["segments"]["critical_path"] and payload["segments"]["degree"] == 5
    assert payload["continuity"]["ok"]
    library = CriticalPathMotion.from_degrees(TABLE_DEG, TABLE_S).sample(3600).peaks()
    assert payload["peaks_per_rad"]["a"] == pytest.approx(library["a"])
    assert main(args) == 0
    assert "critical path motion: 9 points" in capsys.readouterr().out
    bad = tmp_path / "bad.csv"
    bad.write_text("0,0\n90,1\n60,2\n270,1\n")
    assert main(["cam", "--table", str(bad), "--prime-radius", "3", "--roller-radius", "0.5"]) != 0
    err = capsys.readouterr().err
    assert "--table" in err and "increase strictly" in err and "Traceback" not in err
