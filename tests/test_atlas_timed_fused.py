"""The fused compiled scan of timed starts, against references that do not share its code.

``_atlas_kernels.timed_scores`` computes the coupler points of a few entries at a
time and fits them at every starting angle in one kernel (the entries in SIMD
lanes). Checked here: (1) against the NumPy fits of the points computed apart
(``atlas.coupler_points``), with an unassembled pose found by the circle
condition written here; (2) split into blocks and threads, the same numbers as
one call; (3) whole syntheses from a small atlas recover timed targets drawn from
known four-bars, measured by a circle intersection written here, the same
linkage on every run.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import _parallel
from machdyn.fourbar import FourBar
from machdyn.synthesis import (
    PlacedFourBar,
    _atlas_retrieve,
    build_atlas,
    open_atlas,
    path_from_atlas,
)
from machdyn.synthesis._atlas_retrieve import _angle_table, _timed_fits, _timed_scores_numpy
from machdyn.synthesis.atlas import coupler_points
from machdyn.synthesis.atlas_store import sample_fourbars


def _assembles(rows, theta) -> np.ndarray:
    """(rows, angles): the four-bar (unit crank) closes there: |r3 − r4| ≤ |A − O4| ≤ r3 + r4."""
    r1, r3, r4 = (rows[k].astype(float)[:, None] for k in ("r1", "r3", "r4"))
    d = np.abs(np.exp(1j * np.asarray(theta))[None, :] - r1)
    return (d <= r3 + r4) & (d >= np.abs(r3 - r4))


@pytest.mark.parametrize(("O2", "theta1"), [(None, None), (0.3 - 0.2j, None), (None, 0.6)])
def test_fused_scan_matches_the_fits_of_points_computed_apart(compiled, O2, theta1):
    rng = np.random.default_rng(11)
    rows = sample_fourbars(rng, 75, (0.3, 4.0))  # every class: rockers too; 75 = 2·32 + 11 lanes
    targets = rng.normal(size=9) + 1j * rng.normal(size=9)
    uneven = np.r_[0.0, np.cumsum(rng.uniform(0.1, 0.6, 8))]
    for timing in (np.radians(40.0) * np.arange(9), uneven):
        th = np.linspace(0, 2 * np.pi, 12, endpoint=False)[:, None] + timing
        table = _angle_table(th)
        score, g, h, t = _timed_fits(rows, table, targets, O2, theta1)
        # the reference: the points computed on their own, fitted by the NumPy loop
        angles, ip, im = table
        Q = coupler_points(rows["r1"], 1.0, rows["r3"], rows["r4"], rows["p"], rows["delta"],
                           angles, rows["circuit"])[0]  # fmt: skip
        centre = targets.mean() if O2 is None else O2
        ref = (np.empty((2, rows.size)), np.empty((2, rows.size), np.int64),
               np.empty((2, rows.size), complex), np.empty((2, rows.size), complex))  # fmt: skip
        _timed_scores_numpy(Q, ip, im, targets - centre, O2 is None,
                            np.nan if theta1 is None else theta1, *ref)  # fmt: skip
        np.testing.assert_allclose(score, ref[0], rtol=0, atol=1e-12)
        np.testing.assert_array_equal(g, ref[1])
        np.testing.assert_allclose(h, ref[2], rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(t, centre - ref[2] * ref[3], rtol=1e-10, atol=1e-12)
        # −1 exactly where no starting angle assembles every pose (mirror: the negative angles)
        for m, sign in enumerate((1.0, -1.0)):
            none = ~np.any(np.all(_assembles(rows, sign * th.ravel()).reshape(-1, *th.shape),
                                  axis=2), axis=1)  # fmt: skip
            assert np.any(none) and not np.all(none)
            np.testing.assert_array_equal(score[m] == -1.0, none)


def test_blocks_and_threads_give_the_numbers_of_one_call(compiled, monkeypatch):
    rng = np.random.default_rng(3)
    rows = sample_fourbars(rng, 300, (0.3, 4.0))
    rows = rows[rows["barker"] <= 2]
    targets = rng.normal(size=7) + 1j * rng.normal(size=7)
    timing = np.radians(25.0) * np.arange(7)
    one = _atlas_retrieve._timed_scored(rows, targets, timing, {})
    monkeypatch.setattr(_atlas_retrieve, "TIMED_BLOCK", 13)
    monkeypatch.setattr(_atlas_retrieve, "TIMED_THREADS", 1)
    monkeypatch.setenv("MACHDYN_THREADS", "3")
    calls = []
    run = _parallel.for_slices
    monkeypatch.setattr(_parallel, "for_slices", lambda k, n, minimum: calls.append(n) or
                        run(k, n, minimum))  # fmt: skip
    split = _atlas_retrieve._timed_scored(rows, targets, timing, {})
    assert calls == [rows.size]
    for a, b in zip(one, split, strict=True):
        np.testing.assert_array_equal(a, b)


def _coupler(result, theta) -> np.ndarray:
    """Coupler point of a result's linkage by circle intersection (its own assembly)."""
    pl = result.linkage
    r1, r2, r3, r4 = pl.fourbar.lengths
    p, delta = pl.fourbar.coupler

    def point(t, side):
        a = r2 * np.exp(1j * t)
        d = a - r1  # O4 → A
        along = (r4**2 - r3**2 + np.abs(d) ** 2) / (2 * np.abs(d))
        b = r1 + d / np.abs(d) * (along + 1j * side * np.sqrt(np.maximum(r4**2 - along**2, 0)))
        return pl.O2 + np.exp(1j * pl.theta1) * (a + p * np.exp(1j * delta) * (b - a) / r3)

    own = pl.pose(np.asarray(theta[:1]))[2][0]
    side = min((1.0, -1.0), key=lambda s: abs(point(theta[0], s) - own))
    return point(np.asarray(theta), side)


@pytest.fixture(scope="module")
def small_atlas(tmp_path_factory):
    folder = tmp_path_factory.mktemp("timed") / "a"
    build_atlas(folder, 1500, chunk_size=750, seed=4, progress=False)
    return open_atlas(folder)


@pytest.mark.parametrize(
    ("lengths", "coupler", "place", "steps", "closed"),
    [
        ((3.0, 1.0, 3.5, 2.5), (1.8, 0.6), (0.5 + 0.2j, 0.3, 1), np.full(11, 30.0), True),
        ((2.0, 0.7, 2.4, 1.9), (1.1, -0.9), (-1.0 + 2.0j, 2.0, -1), np.full(7, 17.0), False),
        ((4.0, 1.3, 3.1, 3.6), (2.2, 2.5), (3.0 - 1.0j, -1.2, 1), [25, 40, 10, 33, 21, 28], False),
    ],
)
def test_timed_targets_of_known_four_bars_are_met_the_same_on_every_run(
    compiled, small_atlas, lengths, coupler, place, steps, closed
):
    known = PlacedFourBar(FourBar(*lengths, coupler=coupler), *place)
    theta = 0.4 + np.radians(np.r_[0.0, np.cumsum(steps)])
    targets = known.pose(theta)[2]
    size = np.max(np.abs(targets - targets.mean()))
    runs = [path_from_atlas(targets, small_atlas, timing=theta - theta[0], closed=closed, n=2)
            for _ in range(2)]  # fmt: skip
    best = runs[0].candidates[0]
    assert np.max(np.abs(_coupler(best, best.theta2) - targets)) <= 1e-9 * size
    np.testing.assert_allclose(np.diff(best.theta2), np.diff(theta), atol=1e-12)
    for a, b in zip(runs[0].candidates, runs[1].candidates, strict=True):  # deterministic
        assert a.linkage.fourbar.lengths == b.linkage.fourbar.lengths
        assert (a.linkage.O2, a.linkage.theta1) == (b.linkage.O2, b.linkage.theta1)
