"""Path synthesis from an atlas: known linkages recovered, errors checked apart, bad input."""

from __future__ import annotations

import numpy as np
import pytest
from tests.closed_forms import circle_meet

from machdyn.errors import InputError
from machdyn.fourbar import FourBar
from machdyn.synthesis import PlacedFourBar
from machdyn.synthesis.atlas_path import open_atlas, path_from_atlas
from machdyn.synthesis.atlas_store import build_atlas


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    folder = tmp_path_factory.mktemp("atlas")
    build_atlas(folder, 20_000, chunk_size=10_000, seed=11, progress=False)
    return open_atlas(folder)


def _coupler(lengths, coupler, O2, theta1, side, theta2):
    """Coupler point by circle intersection, placed in the plane (no machdyn solver)."""
    r1, r2, r3, r4 = lengths
    p, delta = coupler
    a = r2 * np.exp(1j * theta2)
    b = circle_meet(a, r3, complex(r1), r4, side)
    return O2 + np.exp(1j * theta1) * (a + p * np.exp(1j * delta) * (b - a) / r3)


def _curve_distance(result, targets):
    """Distance from each target to the result's coupler curve, written out independently.

    The curve is swept densely by circle intersection; the nearest sample is then
    polished by a bounded scalar minimisation of the distance over the input angle.
    Where the input rocks, the window is first cut back to where the linkage
    assembles (its limit found by bisection): near a limit the coupler point moves
    like the square root of the angle past it, so the nearest sample can lie far
    from a target met just inside the limit (``bench_atlas_random.py --seed 3``'s
    open case 26: a fit 1.7e-8 rad inside its limit meets its first target to
    5e-11 of the size, where the sample nearest it was 4.9e-3 off and the whole
    window's minimisation gave NaN). The three nearest passes of the sweep are polished
    (where the curve crosses itself near a target, the sample nearest it can lie on the
    other pass: ``bench_atlas.py --recovery 20 --seed 3``'s open case 6, a fit through its
    last target 3.5 rad of crank after the one before, was measured 2.6e-4 off there).
    """
    from scipy.optimize import minimize_scalar

    pl = result.linkage
    lengths, coupler = pl.fourbar.lengths, pl.fourbar.coupler
    # which side of AO4 is the linkage's assembly: the one that reproduces its pose
    th0 = float(result.theta2[0])
    want = pl.pose(th0)[2]
    side = min(
        (1.0, -1.0), key=lambda s: abs(_coupler(lengths, coupler, pl.O2, pl.theta1, s, th0) - want)
    )
    grid = np.linspace(0, 2 * np.pi, 20_000, endpoint=False)
    out = []
    with np.errstate(invalid="ignore"):  # a rocker's input cannot reach every angle: NaN there
        curve = np.array([_coupler(lengths, coupler, pl.O2, pl.theta1, side, t) for t in grid])
        for T in targets:
            d = np.abs(curve - T)

            def dist(t, T=T):
                return abs(_coupler(lengths, coupler, pl.O2, pl.theta1, side, t) - T)

            found = []
            for i in _nearest_passes(d):
                lo, hi = (_assembles_to(dist, grid[i], grid[i] + w) for w in (-1e-3, 1e-3))
                # (in the offset from the sample: the tolerance is relative to the variable)
                res = minimize_scalar(lambda s, g=grid[i]: dist(g + s),
                                      bounds=(lo - grid[i], hi - grid[i]), method="bounded",
                                      options={"xatol": 1e-13})  # fmt: skip
                found += [res.fun, dist(lo), dist(hi), d[i]]
                for edge, way in ((lo, 1.0), (hi, -1.0)):  # from a limit: t = edge ± u² (smooth)
                    if edge != grid[i] + 1e-3 * (-way):  # (a window's end cut back to a limit)
                        near = minimize_scalar(lambda u, e=edge, w=way: dist(e + w * u * u),
                                               bounds=(0.0, np.sqrt(hi - lo)), method="bounded",
                                               options={"xatol": 1e-12})  # fmt: skip
                        found.append(near.fun)
            out.append(np.nanmin(found))  # (a NaN is ignored; the ends are looked at too)
    return np.array(out)


def _nearest_passes(d, count: int = 3):
    """Samples of the ``count`` nearest passes of a swept curve (local minima of the distances
    ``d``, NaN where it does not assemble), nearest first."""
    with np.errstate(invalid="ignore"):
        e = np.where(np.isfinite(d), d, np.inf)
        minima = np.flatnonzero((e <= np.roll(e, 1)) & (e <= np.roll(e, -1)) & np.isfinite(e))
    return minima[np.argsort(e[minima])][:count]


def _assembles_to(f, good, end):
    """``end`` if ``f`` is finite there, else the farthest angle toward it where it is.

    (Bisection from ``good``, where ``f`` is finite.)
    """
    if np.isfinite(f(end)):
        return end
    bad = end
    for _ in range(80):
        mid = 0.5 * (good + bad)
        good, bad = (mid, bad) if np.isfinite(f(mid)) else (good, mid)
    return good


KNOWN = PlacedFourBar(FourBar(5, 2, 5, 4, coupler=(3.0, 0.6)), 1 + 2j, 0.3, 1)


def test_closed_target_from_a_known_linkage_is_recovered(atlas):
    th = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    targets = KNOWN.pose(th)[2]
    size = np.max(np.abs(targets - targets.mean()))
    res = path_from_atlas(targets, atlas, n=3)
    assert res.near and res.candidates
    best = res.best
    assert best.ok and best.is_crank and best.in_order
    d = _curve_distance(best, targets)
    assert d.max() <= 1e-6 * size
    np.testing.assert_allclose(best.distance, d, atol=1e-7 * size)  # its own report agrees


def test_timed_target_from_a_known_linkage_is_recovered(atlas):
    th = np.radians([10, 50, 90, 140, 200, 260, 320])
    targets = KNOWN.pose(th)[2]
    size = np.max(np.abs(targets - targets.mean()))
    res = path_from_atlas(targets, atlas, timing=th, n=2)
    best = res.best
    assert best.ok
    pl = best.linkage
    # the coupler point at θ0 + Δk, by circle intersection, lands on each target
    side = min(
        (1.0, -1.0),
        key=lambda s: abs(
            _coupler(pl.fourbar.lengths, pl.fourbar.coupler, pl.O2, pl.theta1, s, best.theta2[0])
            - targets[0]
        ),
    )
    P = np.array(
        [
            _coupler(pl.fourbar.lengths, pl.fourbar.coupler, pl.O2, pl.theta1, side, t)
            for t in best.theta2
        ]
    )
    assert np.max(np.abs(P - targets)) <= 1e-6 * size
    steps = np.mod(np.diff(best.theta2) - np.diff(th) + np.pi, 2 * np.pi) - np.pi
    np.testing.assert_allclose(steps, 0.0, atol=1e-9)  # the timing is the prescribed one


def test_open_target_on_part_of_a_curve(atlas):
    th = np.linspace(0.3, 2.6, 9)
    targets = KNOWN.pose(th)[2]
    size = np.max(np.abs(targets - targets.mean()))
    res = path_from_atlas(targets, atlas, closed=False, n=2)
    assert res.candidates
    d = _curve_distance(res.best, targets)
    assert d.max() <= 1e-6 * size
    assert res.best.in_order


def _random_crank_rocker(rng, side):
    """A placed crank-rocker (r2 = 1; r1, r3, r4 from 1.5 to 6, clear of a change point)."""
    while True:
        r1, r3, r4 = np.exp(rng.uniform(np.log(1.5), np.log(6.0), 3))
        s = sorted([r1, 1.0, r3, r4])
        if s[0] == 1.0 and s[0] + s[3] < s[1] + s[2] - 0.05 * sum(s):
            fb = FourBar(r1, 1.0, r3, r4, coupler=(rng.uniform(0.3, 1.5) * r3, rng.uniform(-3, 3)))
            scale = np.exp(rng.uniform(-1.0, 2.0))
            fb = FourBar(
                *(scale * np.array(fb.lengths)), coupler=(scale * fb.coupler[0], fb.coupler[1])
            )
            return PlacedFourBar(fb, complex(*rng.normal(0, 5, 2)), rng.uniform(0, 6.28), side)


def _random_rocker(rng, side):
    """A placed non-Grashof four-bar (its input rocks) and a stretch of its input's range."""
    while True:
        r1, r3, r4 = np.exp(rng.uniform(np.log(0.7), np.log(3.0), 3))
        s = sorted([r1, 1.0, r3, r4])
        if s[0] + s[3] > s[1] + s[2] + 0.05 * sum(s) and s[3] < sum(s[:3]) - 0.05 * sum(s):
            fb = FourBar(r1, 1.0, r3, r4, coupler=(rng.uniform(0.3, 1.5) * r3, rng.uniform(-3, 3)))
            lo, hi = fb.input_range().lo, fb.input_range().hi
            if hi - lo > 1.0:
                pl = PlacedFourBar(fb, complex(*rng.normal(0, 5, 2)), rng.uniform(0, 6.28), side)
                return pl, lo + 0.1 * (hi - lo), hi - 0.1 * (hi - lo)


# (seed, side, kind): open = 9 points evenly on a 1.2-2.5 rad stretch of the crank's turn;
# partial = 7 points unevenly over 3.5-5 rad of it; rocker = 9 points over 80 % of a
# non-Grashof input's range (crank=False).
RECOVERY = [(1, 1, "open"), (2, -1, "open"), (3, 1, "partial"), (4, -1, "partial"),
            (5, 1, "rocker"), (6, -1, "rocker")]  # fmt: skip


@pytest.mark.parametrize(("seed", "side", "kind"), RECOVERY)
def test_random_open_and_partial_targets_are_recovered(atlas, seed, side, kind):
    rng = np.random.default_rng(seed)
    if kind == "rocker":
        linkage, lo, hi = _random_rocker(rng, side)
        th = np.linspace(lo, hi, 9)
    else:
        linkage = _random_crank_rocker(rng, side)
        a = rng.uniform(0, 2 * np.pi)
        if kind == "open":
            th = a + np.linspace(0.0, rng.uniform(1.2, 2.5), 9)
        else:
            th = a + np.concatenate([[0.0], np.sort(rng.uniform(0, 1, 5)), [1.0]]) * rng.uniform(
                3.5, 5.0
            )
    targets = linkage.pose(th)[2]
    size = np.max(np.abs(targets - targets.mean()))
    res = path_from_atlas(targets, atlas, closed=False, n=1, mu_min=0.0, crank=kind != "rocker")
    assert res.candidates, res.note
    best = res.best
    assert best.ok and best.in_order
    d = _curve_distance(best, targets)
    assert d.max() <= 1e-6 * size


def test_a_target_no_entry_comes_near_is_reported(atlas):
    # a ten-pointed star with sharp spikes: no four-bar coupler curve follows it
    k = np.arange(20)
    star = np.where(k % 2 == 0, 1.0, 0.15) * np.exp(2j * np.pi * k / 20)
    res = path_from_atlas(star, atlas, n=2)
    assert not res.near
    assert "no atlas entry comes near" in res.note
    assert np.max(res.best.distance) > 0.05  # the best found, reported honestly


def test_bad_targets_are_refused(atlas):
    pts = KNOWN.pose(np.linspace(0, 6, 8))[2]
    with pytest.raises(InputError, match="too few"):
        path_from_atlas(pts[:4], atlas)
    with pytest.raises(InputError, match="too few"):
        path_from_atlas(pts[:3], atlas, timing=[0, 1, 2])
    bad = pts.copy()
    bad[2] = complex(np.nan, 0)
    with pytest.raises(InputError, match="targets"):
        path_from_atlas(bad, atlas)
    dup = pts.copy()
    dup[3] = dup[2]
    with pytest.raises(InputError, match="points 3 and 4 coincide"):
        path_from_atlas(dup, atlas)
    with pytest.raises(InputError, match="coincide"):
        path_from_atlas(np.full(6, 1 + 1j), atlas)
    with pytest.raises(InputError, match="timing"):
        path_from_atlas(pts, atlas, timing=[0, 1])


def test_held_pivot_ground_line_and_absolute_timing(atlas):
    # the known linkage's crank angles from its ground line, its pivot and ground direction held
    th = np.radians([20, 55, 95, 150, 210, 270])
    targets = KNOWN.pose(th)[2]
    size = np.max(np.abs(targets - targets.mean()))
    res = path_from_atlas(
        targets, atlas, timing=th, absolute_timing=True, O2=KNOWN.O2, theta1=KNOWN.theta1, n=1
    )
    best = res.best
    pl = best.linkage
    assert pl.O2 == KNOWN.O2 and pl.theta1 == KNOWN.theta1  # held exactly
    np.testing.assert_allclose(np.mod(best.theta2 - th + np.pi, 2 * np.pi) - np.pi, 0, atol=1e-12)
    # the coupler point at the prescribed θ2, by circle intersection, on each target
    side = min(
        (1.0, -1.0),
        key=lambda s: abs(
            _coupler(pl.fourbar.lengths, pl.fourbar.coupler, pl.O2, pl.theta1, s, th[0])
            - targets[0]
        ),
    )
    P = _coupler(pl.fourbar.lengths, pl.fourbar.coupler, pl.O2, pl.theta1, side, th)
    assert np.max(np.abs(P - targets)) <= 1e-6 * size


def test_length_bound_and_pivot_box_are_kept(atlas):
    th = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    targets = KNOWN.pose(th)[2]
    box = (-1.0, -1.0, 0.5, 0.5)  # away from the known pivot 1 + 2j
    res = path_from_atlas(targets, atlas, n=3, max_length=6.0, pivot_box=box)
    for r in (*res.candidates, *res.rejected):
        pl = r.linkage
        assert max(pl.fourbar.lengths) <= 6.0 + 1e-9 and pl.fourbar.coupler[0] <= 6.0 + 1e-9
        assert box[0] - 1e-9 <= pl.O2.real <= box[2] + 1e-9
        assert box[1] - 1e-9 <= pl.O2.imag <= box[3] + 1e-9


def test_a_closed_path_written_back_to_its_start_is_accepted(atlas):
    th = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    targets = KNOWN.pose(th)[2]
    res = path_from_atlas(np.append(targets, targets[0]), atlas, n=1)
    assert res.targets.size == 12


def test_bad_constraints_are_refused(atlas):
    pts = KNOWN.pose(np.linspace(0, 6, 8))[2]
    with pytest.raises(InputError, match="absolute_timing"):
        path_from_atlas(pts, atlas, absolute_timing=True)
    with pytest.raises(InputError, match="pivot_box"):
        path_from_atlas(pts, atlas, pivot_box=(1, 1, 0, 0))
    with pytest.raises(InputError, match="max_length"):
        path_from_atlas(pts, atlas, max_length=-1)
    with pytest.raises(InputError, match="O2"):
        path_from_atlas(pts, atlas, O2="here")


def test_a_fit_past_the_change_point_is_refined_along_it():
    """With the refinement's options, the landed fit slides along the change point.

    Targets: five points of a change-point linkage (1.35 + 50 = 1.36 + 49.99), by circle
    intersection. The fit starts a hair past the change point and off the linkage;
    landing alone keeps its misses, refining along ``s + l = p + q`` removes them.
    """
    from machdyn.classify import classify
    from machdyn.synthesis._atlas_checks import _grashof_excess, _onto_grashof
    from machdyn.synthesis.refine import Refined

    x = np.array([50.0, 1.35, 1.36, 49.99, 12.0, 0.4, 10.0, -3.0, 0.1])
    theta = np.radians([30.0, 70.0, 110.0, 150.0, 190.0])
    pts = _coupler(x[:4], (x[4], x[5]), complex(x[6], x[7]), x[8], 1.0, theta)
    start = x + np.r_[3e-6, 0, 0, 0, 1e-4, -1e-4, 1e-4, 0, 1e-4]
    fit = Refined(start, theta, np.ones(5), 1.0, True)
    options = dict(timing=theta, crank=True, mu_min=0.0, fixed={9: 0.0},
                   max_length=None, pivot_box=None)  # fmt: skip
    landed = _onto_grashof(fit, pts)
    moved = _onto_grashof(fit, pts, options)
    for f in (landed, moved):
        assert _grashof_excess(f.x) <= 1e-12 * x[:4].sum()
        assert 2 in classify(*f.x[:4]).cranks
    assert landed.rms > 1e-5
    got = _coupler(moved.x[:4], (moved.x[4], moved.x[5]), complex(moved.x[6], moved.x[7]),
                   moved.x[8], 1.0, theta)  # fmt: skip
    assert np.max(np.abs(got - pts)) < 1e-8
    assert moved.rms < 1e-8


def test_copies_of_one_fit_are_refined_and_checked_once():
    from machdyn.synthesis._atlas_checks import _unique
    from machdyn.synthesis.refine import Refined

    x = np.array([5.0, 2.0, 5.0, 4.0, 3.0, 0.6, 1.0, 2.0, 0.3])
    th, br = np.zeros(4), np.ones(4)
    fits = [Refined(x, th, br, 1e-3, True), Refined(x + 1e-9, th, br, 2e-3, True),
            Refined(x * 1.01, th, br, 3e-3, True), Refined(x, th, -br, 4e-3, True)]  # fmt: skip
    assert [f.rms for f in _unique(fits, 4.0)] == [1e-3, 3e-3, 4e-3]
