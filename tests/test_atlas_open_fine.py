"""Open targets on short arcs: the fine arc fit and the point-to-line re-fit.

The target: nine points on a 1.32 rad arc of the crank of a crank-rocker whose link
ratios lie outside the atlas's (``bench_atlas.py --recovery 20 --seed 11``, open case 13,
rounded): 17.6 % of its coupler curve. Every placement is checked by the distance of the
targets to the placed curve computed here by circle intersections (no machdyn solver), and
every recovered linkage by the independent point-to-curve distance of
tests/test_synthesis_path_atlas.py.
"""

from __future__ import annotations

import numpy as np
from tests.closed_forms import circle_meet
from tests.test_atlas_open_rounds import OPTIONS, _polygon_distance, _worst

from machdyn.fourbar import FourBar
from machdyn.synthesis import PlacedFourBar, _atlas_retrieve
from machdyn.synthesis import atlas_path as AP
from machdyn.synthesis.atlas_store import META_DTYPE, even_curves, sample_fourbars
from machdyn.synthesis.descriptor import align_partial, interpolate_open

#: r1, r2, r3, r4, p, δ; O2, θ1, assembly; the arc's crank angles.
TRUTH = PlacedFourBar(FourBar(14.5, 2.5, 7.6, 11.5, coupler=(3.6, 2.5)), -0.17 + 3.97j, 3.92, -1)
THETA = 5.876 + np.linspace(0.0, 1.32, 9)
TARGETS = TRUTH.pose(THETA)[2]
SIZE = float(np.max(np.abs(TARGETS - TARGETS.mean())))


def _rows(scales=(1.0,)):
    """Atlas rows (unit crank) of the truth with its lengths and coupler point times ``scales``."""
    fb = TRUTH.fourbar
    rows = np.zeros(len(scales), META_DTYPE)
    for i, s in enumerate(scales):
        rows[i]["r1"], rows[i]["r3"], rows[i]["r4"] = np.array(s) * [fb.r1, fb.r3, fb.r4] / fb.r2
        rows[i]["p"], rows[i]["delta"] = fb.coupler[0] / fb.r2 * np.ravel(s)[0], fb.coupler[1]
    rows["circuit"], rows["barker"] = TRUTH.branch, 2
    return rows


def _placed_miss(row, h, t) -> float:
    """Largest distance of the targets to ``t + h·curve`` over the size; the curve of the
    row's unit-crank linkage swept by circle intersections (4,096 crank angles, either
    assembly: the nearer one)."""
    r1, r3, r4, p, delta = (float(row[k]) for k in ("r1", "r3", "r4", "p", "delta"))
    a = np.exp(1j * np.linspace(0.0, 2 * np.pi, 4096, endpoint=False))
    best = np.inf
    for side in (1.0, -1.0):
        b = np.array([circle_meet(x, r3, complex(r1), r4, side) for x in a])
        curve = t + h * (a + p * np.exp(1j * delta) * (b - a) / r3)
        best = min(best, float(np.max(_polygon_distance(TARGETS, curve))))
    return best / SIZE


def test_the_coarse_arc_fit_cannot_place_a_short_arc_on_its_own_curve():
    """The defect: 64 samples and eight arc lengths misfit the truth's own curve by percents."""
    rows = _rows()
    curves = even_curves(rows, 720, 128)
    target = interpolate_open(TARGETS, 24)
    (h, t), res = (x[0] for x in align_partial(target, curves[:, ::2], single=True))
    assert res > 0.02
    placed, _ = _atlas_retrieve._fit_to_points(rows, np.array([[h, t]]), TARGETS)
    assert _placed_miss(rows[0], *placed[0]) > 0.01  # the point-to-point re-fit crawls


def test_fine_arc_fit_places_the_arc_on_its_own_curve():
    rows = _rows()
    curves = even_curves(rows, 720, 128)
    _, placed = _atlas_retrieve._arc_starts(rows, curves, TARGETS, 1, fine=True)
    # the re-fit's polygon has 720 samples: its sag, well below 1e-4 of the size
    assert _placed_miss(rows[0], *placed[0]) <= 1e-4


def test_line_rounds_reach_the_curve_where_point_to_point_rounds_crawl():
    rows = _rows()
    curves = even_curves(rows, 720, 128)
    target = interpolate_open(TARGETS, 24)
    rough, _ = align_partial(target, curves, _atlas_retrieve.FINE_FRACTIONS, single=True)
    p2p, _ = _atlas_retrieve._fit_to_points(rows, rough, TARGETS, rounds=10)
    line, _ = _atlas_retrieve._fit_to_points(rows, rough, TARGETS, rounds=1, line=3)
    assert _placed_miss(rows[0], *line[0]) <= 1e-4 < _placed_miss(rows[0], *p2p[0])


def test_fine_round_starts_recover_the_arc_among_random_curves(compiled):
    """Entries 3 % off the truth among 400 random crank four-bars: the fine fit's 10 best
    starts include them (the coarse fit's do not), and refining those (as a later pool
    round does) meets the targets to 1e-6 of their size."""
    rng = np.random.default_rng(3)
    near = _rows([np.exp(rng.uniform(-0.03, 0.03, 3)) for _ in range(3)])
    others = sample_fourbars(np.random.default_rng(8), 1200)
    others = others[others["barker"] <= 2][:400]
    rows = np.concatenate([near, others])
    curves = even_curves(rows, 720, 128)
    entries, transforms = _atlas_retrieve._arc_starts(rows, curves, TARGETS, 10, fine=True)
    assert np.isin(entries["r1"], near["r1"]).any()
    coarse, _ = _atlas_retrieve._arc_starts(rows, curves, TARGETS, 10)
    assert not np.isin(coarse["r1"], near["r1"]).any()  # the coarse fit's 10 best: none
    starts = _atlas_retrieve._untimed_starts(entries, transforms, TARGETS)
    fits = AP._screened(starts, TARGETS, OPTIONS, lm=True)
    fits, met = AP._polished(fits, TARGETS, OPTIONS, 8, 100, lm=True)
    fits, met = AP._long_polished(fits, TARGETS, OPTIONS, met, [])
    best = next(f for f in fits if np.ptp(f.branch) == 0)
    assert _worst(best, TARGETS) <= 1e-6


def test_arc_share_of_a_fit_is_the_targets_share_of_its_curve():
    """The share that picks the fine round: the targets' polyline over the length of the
    fit's coupler curve, against the curve swept here by circle intersections."""
    from machdyn.synthesis.refine import Refined

    fb = TRUTH.fourbar
    x = np.array([fb.r1, fb.r2, fb.r3, fb.r4, *fb.coupler, TRUTH.O2.real, TRUTH.O2.imag,
                  TRUTH.theta1])  # fmt: skip
    fit = Refined(x, THETA, np.full(THETA.size, float(TRUTH.branch)), 0.0, True)
    th = np.linspace(0.0, 2 * np.pi, 20_000, endpoint=False)
    a = fb.r2 * np.exp(1j * th)
    shares = []
    for side in (1.0, -1.0):  # the truth's assembly: the side whose curve holds the targets
        b = np.array([circle_meet(v, fb.r3, complex(fb.r1), fb.r4, side) for v in a])
        curve = TRUTH.O2 + np.exp(1j * TRUTH.theta1) * (a + fb.coupler[0] * np.exp(
            1j * fb.coupler[1]) * (b - a) / fb.r3)  # fmt: skip
        if np.max(_polygon_distance(TARGETS, curve)) < 1e-6 * SIZE:
            closed = np.r_[curve, curve[:1]]
            shares.append(np.sum(np.abs(np.diff(TARGETS))) / np.sum(np.abs(np.diff(closed))))
    assert len(shares) == 1 and 0.15 < shares[0] < 0.2
    assert abs(AP._arc_share(fit, TARGETS) - shares[0]) < 1e-3 * shares[0]
    assert AP._arc_share(fit, TARGETS) < AP.UNTIMED_SHORT  # a short arc: the fine round
