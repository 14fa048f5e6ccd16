"""Coupler-curve atlas kernel, path synthesis by optimisation, quick-return design."""

from __future__ import annotations

import math

import numpy as np
import pytest

from machdyn.errors import InputError
from machdyn.fourbar import FourBar
from machdyn.synthesis import (
    PlacedFourBar,
    atlas,
    coupler_points,
    path_objective,
    quick_return,
    synthesize_path,
    time_ratio_angle,
)

# Every test runs on the NumPy kernels and again on the compiled ones (coupler_points).
pytestmark = pytest.mark.usefixtures("backend")

# --------------------------------------------------------------------------------------
# the vectorised kernel against FourBar (a separate code path: unit vectors + solve)


def test_coupler_points_match_fourbar_for_random_linkages(rng):
    n = 50
    lengths = rng.uniform(0.5, 3.0, size=(4, n))
    p = rng.uniform(0.0, 2.0, n)
    delta = rng.uniform(-np.pi, np.pi, n)
    branch = rng.choice([-1, 1], n)
    theta2 = np.linspace(0, 2 * np.pi, 37)
    pts, ok = coupler_points(*lengths, p, delta, theta2, branch)
    assert pts.shape == ok.shape == (n, theta2.size)
    checked = 0
    for i in range(n):
        try:
            fb = FourBar(*lengths[:, i], coupler=(p[i], delta[i]))
        except Exception:
            assert not ok[i].any()
            continue
        if fb.form_rule != "phi12":
            continue  # GRCR/GRRC forms are not the sign of phi12; compared below by branch
        m = fb.solve(theta2, form=1 if branch[i] == 1 else 2)
        np.testing.assert_array_equal(ok[i], m.assembled)
        np.testing.assert_allclose(pts[i][ok[i]], m.coupler[ok[i]], atol=1e-9)
        assert np.all(np.isnan(pts[i][~ok[i]]))
        checked += 1
    assert checked > 10


def test_coupler_point_keeps_its_distances_to_a_and_b():
    """P is rigid with the coupler: |P − A| = p, and the angle to AB is delta."""
    theta2 = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    pts, _ = coupler_points(8, 4, 7, 6, 3.0, 0.7, theta2)
    a = 4 * np.exp(1j * theta2)
    np.testing.assert_allclose(np.abs(pts[0] - a), 3.0, rtol=1e-12)
    b = FourBar(8, 4, 7, 6).solve(theta2).B
    np.testing.assert_allclose(np.angle((pts[0] - a) / (b - a)), 0.7, atol=1e-12)


def test_atlas_grid_and_crank_rockers():
    at = atlas([2.0, 3.0, 5.0], [2.5, 3.0], [2.0, 3.0], [0.5, 1.0], [0.0, 1.0], n=72)
    assert len(at) == 3 * 2 * 2 * 2 * 2
    assert at.points.shape == (len(at), 72)
    # a unit crank turns fully exactly when the classification says link 2 is a crank
    kinds = set()
    for row, full in zip(at.lengths, at.full_turn, strict=True):
        expected = 2 in FourBar(*row).cranks
        assert full == expected
        kinds.add(bool(full))
    assert kinds == {True, False}
    df = at.to_pandas()
    assert len(df) == len(at) * 72


def test_coupler_points_bad_input():
    with pytest.raises(InputError, match="one value per candidate"):
        coupler_points([1, 2], [1, 1], [1, 1, 1], 1, 0, 0, [0.0])
    with pytest.raises(InputError, match="positive"):
        coupler_points(1, -1, 1, 1, 0, 0, [0.0])


# --------------------------------------------------------------------------------------
# path synthesis


def _known_targets(k, timing=False):
    fb = FourBar(5, 2, 5, 4, coupler=(3.0, 0.6))
    placed = PlacedFourBar(fb, 1 + 2j, 0.3, 1)
    theta2 = np.linspace(0, 2 * np.pi, k, endpoint=False)
    _, _, targets, ok = placed.pose(theta2)
    assert ok.all()
    return placed, targets, theta2


def test_path_objective_is_zero_for_the_generating_linkage():
    placed, targets, theta2 = _known_targets(8)
    scale = float(np.max(np.abs(targets - targets.mean())))
    centre = complex(targets.mean())
    o = (placed.O2 - centre) / scale
    x = np.array(
        [5 / scale, 2 / scale, 5 / scale, 4 / scale, 3 / scale, 0.6, o.real, o.imag, 0.3, 1.0]
    )
    assert path_objective(x, targets) < 1e-5  # nearest point of a 120-sample polyline
    # with timing the placement is solved in closed form: lengths, coupler, branch, θ2_0
    timed = np.array([5 / scale, 2 / scale, 5 / scale, 4 / scale, 3 / scale, 0.6, 1.0, 0.0])
    assert path_objective(timed, targets, timing=theta2) < 1e-24
    shifted = timed.copy()
    shifted[7] = 0.2  # another θ2_0: the timed points no longer fit
    assert path_objective(shifted, targets, timing=theta2) > 1e-4
    # and many candidates at once give the same values as one at a time
    xs = np.column_stack([x, x * 1.1, x * 0.9])
    many = path_objective(xs, targets)
    one = [path_objective(xs[:, i], targets) for i in range(3)]
    np.testing.assert_allclose(many, one)


def test_path_synthesis_with_timing_recovers_a_known_linkage():
    _, targets, theta2 = _known_targets(6)
    res = synthesize_path(targets, timing=theta2, popsize=15, maxiter=150, seed=0, mu_min=0.35)
    scale = float(np.max(np.abs(targets - targets.mean())))
    assert res.distance.max() < 1e-3 * scale
    assert res.is_crank and res.barker_class in ("GCRR", "GCCC")
    assert res.ok, res.defects
    # independent check: the found linkage, posed by FourBar.solve, passes the targets
    fb = res.fourbar
    m = fb.solve(res.theta2, form=1 if res.linkage.branch == 1 else 2)
    global_p = res.linkage.to_global(m.coupler)
    np.testing.assert_allclose(global_p, targets, atol=1e-3 * scale)
    assert res.mu_min >= 0.35 - np.radians(0.5)


def test_path_synthesis_without_timing_matches_the_curve():
    _, targets, _ = _known_targets(8)
    # a small, seeded search (the default budget is larger); the tolerance is 0.4 % of the
    # target set's size (2.52)
    res = synthesize_path(targets, popsize=15, maxiter=150, seed=0, mu_min=0.35, tolerance=0.01)
    assert res.distance.max() < 0.01
    assert res.ok, res.defects
    assert res.is_crank
    assert res.in_order
    # the reported distances are to the found curve (checked densely, independently)
    curve = res.curve(20000)
    d = np.min(np.abs(curve[None, :] - targets[:, None]), axis=1)
    np.testing.assert_allclose(d, res.distance, atol=2e-3)
    import matplotlib

    matplotlib.use("Agg")
    assert res.plot().lines


def test_unreachable_targets_are_reported():
    # a sharp-cornered zigzag no coupler curve follows to 1e-4
    targets = [0, 1 + 1j, 2, 3 + 1j, 4, 5 + 1j]
    res = synthesize_path(targets, popsize=6, maxiter=10, seed=0, polish=False, tolerance=1e-4)
    assert not res.ok
    assert any("not reached" in d for d in res.defects)


def test_path_bad_input():
    with pytest.raises(InputError, match="at least 3"):
        synthesize_path([0, 1])
    with pytest.raises(InputError, match="timing"):
        synthesize_path([0, 1, 1j], timing=[0, 1])


# --------------------------------------------------------------------------------------
# quick return


def test_time_ratio_angle_norton():
    # TR = 1.25 -> delta = 180 (0.25 / 2.25) = 20 deg (Norton sec. 3.5)
    assert math.isclose(time_ratio_angle(1.25), math.radians(20.0))
    assert time_ratio_angle(1.0) == 0.0


@pytest.mark.parametrize(("swing_deg", "tr"), [(45, 1.25), (60, 1.0), (30, 1.5), (80, 1.8)])
def test_quick_return_swing_and_time_ratio_from_fourbar(swing_deg, tr):
    qr = quick_return(np.radians(swing_deg), tr, r4=2.0)
    fb = qr.fourbar
    assert fb.barker_class == "GCRR"
    form = 1 if qr.linkage.branch == 1 else 2
    # swing: the output's range over a full turn of the crank (FourBar.extrema)
    ex = fb.extrema(form=form)["theta4"]
    assert math.isclose(ex.max - ex.min, math.radians(swing_deg), abs_tol=1e-9)
    # time ratio: crank angles between the two output limits (FourBar.toggles)
    t = [tg.theta2 for tg in fb.toggles() if tg.links == (2, 3) and tg.branch == qr.linkage.branch]
    assert len(t) == 2
    gap = (t[1] - t[0]) % (2 * math.pi)
    assert math.isclose(max(gap, 2 * math.pi - gap) / min(gap, 2 * math.pi - gap), tr, rel_tol=1e-9)
    # the reported transmission angle agrees with FourBar's own search
    assert math.isclose(qr.mu_min, fb.transmission_angle(form=form).min, abs_tol=1e-9)
    assert math.isclose(fb.r4, 2.0)


def test_quick_return_bad_input():
    with pytest.raises(InputError, match="time_ratio"):
        quick_return(np.radians(45), 0.8)
    with pytest.raises(InputError, match="swing"):
        quick_return(np.radians(200), 1.2)


def test_tables_and_plots():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from machdyn.synthesis import function_generator, three_position

    at = atlas([2.0], [2.5], [2.0], [1.0], [0.0, 0.5], n=36)
    assert at.plot().lines and len(at.to_pandas()) == 72
    g = function_generator(np.log10, (1.0, 2.0), np.radians((45, 105)), np.radians((135, 225)))
    se = g.structural_error(n=21)
    assert se.plot().lines
    assert list(se.to_pandas().columns[:4]) == ["x", "y_desired", "y_generated", "error"]
    s = three_position(
        [5.086j, 2.019 + 3.181j, 3.933 + 4.051j], [0.741 + 2.703j, 4.428 + 2.529j, 6.304 + 4.83j]
    )
    df = s.to_pandas(degrees=True)
    assert "theta2_deg" in df.columns and len(df) == 3
    assert len(s.plot().lines) == 4  # three positions and the fixed pivots
    plt.close("all")
