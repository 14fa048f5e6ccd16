"""Open untimed targets: the first pool's next-best arcs, and the distance at a rocker's limit.

The recovered linkage is checked by the independent point-to-curve distance of
tests/test_synthesis_path_atlas.py (circle intersections and a scalar minimisation; no
machdyn solver). The targets are traced by a non-Grashof four-bar whose input rocks
(Barker's RRR1), over 5–95 % of its input's range on one assembly, as
``bench_atlas_random.py --kinds open`` draws them.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from tests.closed_forms import circle_meet
from tests.test_synthesis_path_atlas import _coupler, _curve_distance

from machdyn.fourbar import FourBar
from machdyn.synthesis import PlacedFourBar, _atlas_retrieve
from machdyn.synthesis import atlas_path as AP
from machdyn.synthesis.atlas_store import META_DTYPE, even_curves, sample_fourbars

OPTIONS = dict(timing=None, crank=False, mu_min=0.0, fixed={}, max_length=None, pivot_box=None)
#: r1 the longest and s + l > p + q (1 + 2.2 > 1.1 + 1.3): link 2 rocks, over ±LIMIT.
TRUTH = PlacedFourBar(FourBar(2.2, 1.0, 1.1, 1.3, coupler=(1.2, 0.7)), 0.4 - 0.3j, 0.5, 1)
#: The input's limit, where the diagonal O4A is r3 + r4 (law of cosines).
LIMIT = float(np.arccos((2.2**2 + 1.0 - (1.1 + 1.3) ** 2) / (2 * 2.2)))
THETA = np.linspace(-0.9 * LIMIT, 0.9 * LIMIT, 9)
TARGETS = TRUTH.pose(THETA)[2]
SIZE = float(np.max(np.abs(TARGETS - TARGETS.mean())))
#: The atlas argument: only its manifest is read (the retrieval is faked, no pool rounds).
ATLAS = SimpleNamespace(manifest=SimpleNamespace(circuit_samples=256, samples=128))


def _rows() -> np.ndarray:
    """Thirty random atlas rows (decoys) and, 21st, the truth's with its lengths 2 % off."""
    rows = sample_fourbars(np.random.default_rng(5), 30)
    fb = TRUTH.fourbar
    near = np.zeros(1, META_DTYPE)
    near["r1"], near["r3"], near["r4"] = 1.02 * fb.r1, 0.98 * fb.r3, 1.02 * fb.r4
    near["p"], near["delta"], near["circuit"], near["barker"] = fb.coupler[0], fb.coupler[1], 1, 5
    return np.insert(rows, 20, near)


def _retrieval(monkeypatch):
    """atlas_path's first-round retrieval faked: the rows of :func:`_rows`, each placed on the
    targets by the (fine) arc fit, in that order (the truth's the 21st best); no wide
    four-bars."""
    rows = _rows()
    curves = even_curves(rows, 256, 128)
    placed = np.empty((rows.size, 2), complex)
    for i in range(rows.size):
        _, placed[i] = _atlas_retrieve._arc_starts(rows[i : i + 1], curves[i : i + 1], TARGETS, 1,
                                                   fine=True)  # fmt: skip
    asked = []

    def retrieve(atlas, pts, closed, crank, retrieve, count, *args, **kwargs):
        asked.append(count)
        return rows[:count], placed[:count]

    monkeypatch.setattr(AP, "_retrieve", retrieve)
    monkeypatch.setattr(AP, "_retrieve_wide", lambda *a, **k: (rows[:0], placed[:0]))
    monkeypatch.setattr(AP, "UNTIMED_ROUNDS", 1)  # no pool rounds: the first round alone
    return asked


def _worst(fit) -> float:
    """The fit's largest independent distance to the targets, over their size."""
    x = fit.x
    placed = PlacedFourBar(FourBar(*x[:4], coupler=(x[4], x[5])), complex(x[6], x[7]),
                           float(x[8]), int(fit.branch[0]))  # fmt: skip
    with np.errstate(invalid="ignore"):  # (a decoy's first angle may not assemble)
        d = _curve_distance(SimpleNamespace(linkage=placed, theta2=fit.theta), TARGETS)
    return float(np.max(d)) / SIZE


def test_first_pool_next_best_arc_meets_a_rocker_arc(compiled, monkeypatch):
    asked = _retrieval(monkeypatch)
    fits, _ = AP._untimed_fits(ATLAS, TARGETS, False, False, 160, 10, None, OPTIONS)
    assert asked == [AP.OPEN_SPARE * 10]  # the pool's 40 best arcs asked for
    answers = [f for f in fits if np.ptp(f.branch) == 0 and AP._in_order(f.theta, False, None)]
    assert answers and _worst(answers[0]) <= 1e-6
    # without them (the first ten arcs only, decoys), no fit comes near
    monkeypatch.setattr(AP, "OPEN_SPARE", 1)
    fits, _ = AP._untimed_fits(ATLAS, TARGETS, False, False, 160, 10, None, OPTIONS)
    assert min(_worst(f) for f in fits[:3]) > 1e-3


def test_curve_distance_sees_a_target_just_inside_a_rockers_limit():
    """A point met 1e-9 rad inside the input's limit: the coupler point moves like the square
    root of the angle there, so the sweep's nearest sample is ~1e-2 of the size off."""
    side = float(TRUTH.branch)
    fb = TRUTH.fourbar
    theta = np.array([LIMIT - 1e-9, 0.0, -0.5 * LIMIT])
    a = fb.r2 * np.exp(1j * theta)
    b = np.array([circle_meet(x, fb.r3, complex(fb.r1), fb.r4, side) for x in a])
    points = TRUTH.O2 + np.exp(1j * TRUTH.theta1) * (
        a + fb.coupler[0] * np.exp(1j * fb.coupler[1]) * (b - a) / fb.r3
    )
    # (the point is the curve's: the same by the tests' own circle-intersection coupler)
    assert abs(_coupler(fb.lengths, fb.coupler, TRUTH.O2, TRUTH.theta1, side, theta[0])
               - points[0]) < 1e-12  # fmt: skip
    d = _curve_distance(SimpleNamespace(linkage=TRUTH, theta2=theta), points)
    assert d[0] <= 1e-9 * SIZE and np.max(d) <= 1e-7 * SIZE
