"""Path synthesis from the atlas on hundreds of untimed targets (a digitised path).

Each untimed target adds an unknown, its input angle, and the refinement's steps cost
the cube of the unknowns: 500 targets took 17.5 s of CPU and 2,000 did not finish in
150 s (the audit of 2026-11-25). Past ``MANY_TARGETS`` the search runs on 40 of them,
evenly along them, and every result is checked on all. The targets are a known
four-bar's coupler points by circle intersection, and the results' distances are
measured by the independent point-to-curve distance of tests/test_synthesis_path_atlas.py
(circle intersections and a scalar minimisation; no machdyn solver).
"""

from __future__ import annotations

import numpy as np
import pytest
from tests.test_synthesis_path_atlas import _coupler, _curve_distance

from machdyn.synthesis import path_from_atlas

LENGTHS, COUPLER, O2, THETA1 = (3.0, 1.0, 3.5, 2.5), (1.8, 0.6), 0.5 + 0.2j, 0.3


@pytest.mark.parametrize(("count", "closed"), [(400, True), (250, False)])
def test_hundreds_of_exact_targets_are_met_on_every_one(atlas_1e4, compiled, count, closed):
    theta = (np.linspace(0, 2 * np.pi, count, endpoint=False) if closed
             else np.linspace(0.3, 2.8, count))  # fmt: skip
    targets = _coupler(LENGTHS, COUPLER, O2, THETA1, 1.0, theta)
    size = float(np.max(np.abs(targets - targets.mean())))
    found = path_from_atlas(targets, atlas_1e4, closed=closed, n=2, mu_min=0.0)
    assert f"searched on 40 of the {count} targets" in found.note
    best = found.candidates[0]
    assert best.distance.size == best.theta2.size == count
    assert float(np.max(_curve_distance(best, targets))) <= 1e-6 * size


def test_noisy_dense_targets_get_true_distances_and_no_false_order_defect(atlas_1e4, compiled):
    rng = np.random.default_rng(7)
    theta = np.linspace(0.3, 2.8, 300)
    exact = _coupler(LENGTHS, COUPLER, O2, THETA1, 1.0, theta)
    size = float(np.max(np.abs(exact - exact.mean())))
    # noise of 1e-3 of the size: more than the spacing along the path in places
    targets = exact + 1e-3 * size * (rng.normal(size=300) + 1j * rng.normal(size=300))
    found = path_from_atlas(targets, atlas_1e4, closed=False, n=2, mu_min=0.0, time_limit=3.0)
    best = (found.candidates or found.rejected)[0]
    assert not any(d.startswith("order defect") for d in best.defects)
    # the distances reported are the targets' distances to its curve, every one
    independent = _curve_distance(best, targets)
    assert np.allclose(best.distance, independent, rtol=0.0, atol=1e-7 * size)
    assert float(np.max(independent)) <= 1e-2 * size  # (the noise: ~3.5e-3 at most)
