"""Open timed targets on a small atlas: the first pool's next-best starts.

An atlas of 10^4 entries holds about 5,000 crank rows, nearly all in each timed pool
of 5,000, so a fresh pool adds few new rows. A target whose ten best-scored starts all end in
other minima is then met only by the starts ranked below them. The targets are arcs
of random placed crank-rockers (as ``bench_atlas.py --recovery 20`` draws them; each
was missed by 1e-5 to 5e-4 of its size before the next-best starts), and the
recovered linkage is checked by the independent point-to-curve distance of
tests/test_synthesis_path_atlas.py (circle intersections and a scalar minimisation;
no machdyn solver): the timing is checked on the candidate's own crank angles.
"""

from __future__ import annotations

import numpy as np
import pytest
from tests.test_synthesis_path_atlas import _coupler, _curve_distance

from machdyn.fourbar import FourBar
from machdyn.synthesis import PlacedFourBar, path_from_atlas

#: (lengths, coupler point, O2, θ1, assembly, first crank angle, span of the 7 angles)
CASES = {
    "seed 11 #8": ((9.099673810211122, 2.5535722893563113, 10.82586454852299, 14.44388324863667),
                   (7.856234057331782, 0.9820001406509578),
                   3.1113125720257546 - 0.8663174031205013j,
                   4.684292080942356, -1, 0.1330944373301504, 2.6213816959601264),
    "seed 3 #1": ((32.19929245350402, 12.43332205389613, 36.26410311837023, 22.844446078826923),
                  (41.272596928008454, -1.307036903604297), -1.074144555634279 - 3.914042889819831j,
                  2.5098410686992434, 1, 0.796021272630958, 1.5935155367788991),
}  # fmt: skip


@pytest.mark.parametrize("name", CASES)
def test_open_timed_target_met_by_next_best_starts(atlas_1e4, name):
    lengths, coupler, O2, theta1, branch, theta0, span = CASES[name]
    truth = PlacedFourBar(FourBar(*lengths, coupler=coupler), O2, theta1, branch)
    theta = theta0 + np.linspace(0.0, span, 7)
    targets = truth.pose(theta)[2]
    size = float(np.max(np.abs(targets - targets.mean())))
    found = path_from_atlas(targets, atlas_1e4, closed=False, timing=theta, n=3, mu_min=0.0)
    best = found.candidates[0]
    assert float(np.max(_curve_distance(best, targets))) <= 1e-6 * size
    # reached at the prescribed crank steps: its points at its angles, by circle intersection
    assert np.allclose(np.diff(best.theta2), np.diff(theta), atol=1e-9)
    pl = best.linkage
    at = [_coupler(pl.fourbar.lengths, pl.fourbar.coupler, pl.O2, pl.theta1, side, best.theta2)
          for side in (1.0, -1.0)]  # fmt: skip
    assert min(np.max(np.abs(p - targets)) for p in at) <= 1e-6 * size
