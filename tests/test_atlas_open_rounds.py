"""Open (untimed) targets: the single-precision arc fit, the LM look and the later rounds.

Every recovered linkage is checked by the independent point-to-curve distance of
tests/test_synthesis_path_atlas.py (circle intersections and a scalar minimisation;
no machdyn solver); the arc fit by the distance of the targets to the placed
polygon, written out here.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from tests.closed_forms import circle_meet
from tests.test_synthesis_path_atlas import _curve_distance

from machdyn.fourbar import FourBar
from machdyn.synthesis import PlacedFourBar
from machdyn.synthesis import atlas_path as AP
from machdyn.synthesis import refine as refine_module
from machdyn.synthesis.descriptor import align_partial
from machdyn.synthesis.refine import Refined

OPTIONS = dict(timing=None, crank=True, mu_min=0.0, fixed={}, max_length=None, pivot_box=None)
#: A crank-rocker and nine points on a 1.6 rad arc of its crank (an open target).
TRUTH = PlacedFourBar(FourBar(3.0, 1.0, 3.5, 3.2, coupler=(2.0, 0.8)), 1 + 1j, 0.4, 1)
THETA = 0.7 + np.linspace(0.0, 1.6, 9)


def _closed_curve(r1, r3, r4, p, delta, samples=128):
    """A crank-rocker's coupler curve (unit crank) evenly by arc length, by circle meets."""
    th = np.linspace(0.0, 2 * np.pi, 4096, endpoint=False)
    a = np.exp(1j * th)
    b = np.array([circle_meet(x, r3, complex(r1), r4, 1.0) for x in a])
    c = a + p * np.exp(1j * delta) * (b - a) / r3
    s = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(np.r_[c, c[:1]])))])
    at = np.linspace(0.0, s[-1], samples, endpoint=False)
    closed = np.r_[c, c[:1]]
    return np.interp(at, s, closed.real) + 1j * np.interp(at, s, closed.imag)


def _polygon_distance(points, polygon):
    """Distance of each point to a closed polygon (its edges), written out."""
    a, b = polygon, np.roll(polygon, -1)
    seg = b - a
    u = np.clip(np.real((points[:, None] - a) * np.conj(seg)) / np.abs(seg) ** 2, 0.0, 1.0)
    return np.min(np.abs(points[:, None] - (a + u * seg)), axis=1)


def test_single_precision_arc_fit_places_a_known_arc_and_ranks_like_double():
    rng = np.random.default_rng(3)
    shapes = [(3.0, 3.5, 3.2, 2.0, 0.8)] + [
        (rng.uniform(2.5, 4), rng.uniform(2.5, 4), rng.uniform(2.5, 4), rng.uniform(0.5, 3),
         rng.uniform(-3, 3)) for _ in range(40)
    ]  # fmt: skip
    curves = np.array([_closed_curve(*s) for s in shapes])
    curves = curves[np.all(np.isfinite(curves), axis=1)]
    # a quarter of the first curve, turned, scaled and moved: the target
    arc = 2.0 - 1.0j + 1.7 * np.exp(0.6j) * curves[0, 40:73]
    target = arc[::2]
    size = float(np.max(np.abs(target - target.mean())))
    (h, t), res = (x[0] for x in align_partial(target, curves[:1], [0.25], single=True))
    # single precision tells scores apart to ~1e-6, residuals to ~3e-3 (a neighbouring
    # start along the arc may win): the arc placed to that, no better
    placed = t + h * curves[0]
    assert np.max(_polygon_distance(target, placed)) <= 3e-3 * size
    (h2, t2), res2 = (x[0] for x in align_partial(target, curves[:1], [0.25]))
    assert np.max(_polygon_distance(target, t2 + h2 * curves[0])) <= 1e-9 * size
    assert res <= 3e-3 and res2 <= 1e-6
    # over all the curves and the default fractions, the same residuals to ~3e-3 and the
    # known curve first
    _, single = align_partial(target, curves, single=True)
    _, double = align_partial(target, curves)
    np.testing.assert_allclose(single, double, atol=3e-3)
    assert np.argsort(single)[0] == np.argsort(double)[0] == 0


def _start(scale=1.02):
    r1, r2, r3, r4 = TRUTH.fourbar.lengths
    p, delta = TRUTH.fourbar.coupler
    x = np.array([r1, r2, r3, r4, p, delta, TRUTH.O2.real, TRUTH.O2.imag, TRUTH.theta1])
    x[[0, 2, 3, 4]] *= scale
    return x


def _worst(fit, targets) -> float:
    """Largest independent point-to-curve distance of a fit over the targets' size."""
    r1, r2, r3, r4, p, delta, ox, oy, theta1 = fit.x
    placed = PlacedFourBar(FourBar(r1, r2, r3, r4, coupler=(p, delta)), complex(ox, oy),
                           float(theta1), int(fit.branch[0]))  # fmt: skip
    size = float(np.max(np.abs(targets - targets.mean())))
    d = _curve_distance(SimpleNamespace(linkage=placed, theta2=fit.theta), targets)
    return float(np.max(d)) / size


def _solvers_used(monkeypatch) -> list[str]:
    """The solver of each refinement atlas_path makes from now on (a spy on its refine)."""
    solvers: list[str] = []

    def spy(*args, **kwargs):
        solvers.append(kwargs.get("solver", "trf"))
        return refine_module.refine(*args, **kwargs)

    monkeypatch.setattr(AP, "refine", spy)
    return solvers


def test_lm_look_meets_an_open_target_without_trf(compiled, monkeypatch):
    targets = TRUTH.pose(THETA)[2]
    branch = np.full(THETA.size, float(TRUTH.branch))
    start = Refined(_start(1.01), THETA, branch, 1.0, False)
    solvers = _solvers_used(monkeypatch)
    fits, met = AP._polished([start], targets, OPTIONS, 1)
    assert met and _worst(fits[0], targets) <= 1e-6
    assert solvers == ["lm"]  # met by the look: no trf refinement


def test_later_rounds_refine_by_the_compiled_lm(compiled, monkeypatch):
    """``lm=True`` (the later pool rounds): screening and polishing by the LM, met."""
    targets = TRUTH.pose(THETA)[2]
    branch = np.full(THETA.size, float(TRUTH.branch))
    starts = [(_start(s), THETA + 0.02, branch) for s in (1.03, 0.97, 1.05)]
    solvers = _solvers_used(monkeypatch)
    fits = AP._screened(starts, targets, OPTIONS, lm=True)
    fits, met = AP._polished(fits, targets, OPTIONS, 8, 100, lm=True)
    assert met and _worst(fits[0], targets) <= 1e-6
    assert solvers and set(solvers) == {"lm"}
    solvers.clear()
    AP._screened(starts, targets, OPTIONS)  # the first round: scipy's trf, as ever
    assert set(solvers) == {"trf"}
