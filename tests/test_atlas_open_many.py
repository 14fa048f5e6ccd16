"""Open targets of many points: the re-fit on a spread subset, the compiled LM's refinement.

A target of more than ``ICP_POINTS`` points is re-fitted onto atlas curves through that
many of its points spread along it, and one of ``MANY_POINTS`` or more is screened and
refined by the compiled Levenberg–Marquardt instead of scipy's trf. Checked here against
things outside that code: a placement known by construction, and the independent
point-to-curve distance of tests/test_synthesis_path_atlas.py (circle intersections and a
scalar minimisation; no machdyn solver).
"""

from __future__ import annotations

import numpy as np
from tests.test_synthesis_path_atlas import _curve_distance

from machdyn.fourbar import FourBar
from machdyn.synthesis import PlacedFourBar, _atlas_retrieve, atlas_path, build_atlas
from machdyn.synthesis.atlas_path import MANY_POINTS, path_from_atlas
from machdyn.synthesis.atlas_store import META_DTYPE
from machdyn.synthesis.circuits import circuit_points


def _row(r1, r3, r4, p, delta, circuit):
    row = np.zeros(1, META_DTYPE)
    row["r1"], row["r3"], row["r4"], row["p"], row["delta"] = r1, r3, r4, p, delta
    row["circuit"], row["barker"] = circuit, 2
    return row


def test_refit_of_many_points_keeps_a_known_placement_and_mends_a_rough_one():
    """40 points of an atlas curve placed by a known (h, t): kept from it, neared from off it."""
    row = _row(3.0, 3.5, 3.2, 2.0, 0.8, 1)
    Q, _ = circuit_points([3.0], 1.0, [3.5], [3.2], [2.0], [0.8], [1.0], 4000)
    arc = Q[0][600:1700:27]  # 41 points of a third of the curve
    assert arc.size > _atlas_retrieve.ICP_POINTS
    h, t = 2.5 * np.exp(0.7j), 1.0 - 2.0j
    pts = t + h * arc
    size = float(np.max(np.abs(pts - pts.mean())))
    placed, miss = _atlas_retrieve._fit_to_points(row, np.array([[h, t]]), pts)
    # the curve's 720 samples are joined by chords: the misses are of the chords' sag
    assert miss[0] < 1e-5
    assert abs(placed[0, 0] - h) < 1e-4 * abs(h) and abs(placed[0, 1] - t) < 1e-4 * size
    rough = np.array([[h * 1.03 * np.exp(0.02j), t + 0.05 * abs(h)]])
    _, before = _atlas_retrieve._fit_to_points(row, rough, pts, rounds=0)
    _, after = _atlas_retrieve._fit_to_points(row, rough, pts)
    assert after[0] < 0.2 * before[0]


def test_refit_misses_are_of_every_point():
    """A target whose far points leave the curve misses, though the subset lies on it."""
    Q, _ = circuit_points([3.0], 1.0, [3.5], [3.2], [2.0], [0.8], [1.0], 4000)
    pts = Q[0][600:1700:27].copy()
    n = _atlas_retrieve.ICP_POINTS
    keep = np.unique(np.round(np.linspace(0, pts.size - 1, n)).astype(int))
    off = np.setdiff1d(np.arange(pts.size), keep)
    size = float(np.max(np.abs(pts - pts.mean())))
    pts[off] += 0.05 * size * np.exp(1j * np.arange(off.size))  # all off the curve
    _, miss = _atlas_retrieve._fit_to_points(_row(3.0, 3.5, 3.2, 2.0, 0.8, 1),
                                             np.array([[1.0, 0.0]]), pts)  # fmt: skip
    # (each moved point is ~0.05 of the size off the curve, less along its tangent; on the
    # curve at every point the misses would be ~1e-4, the chords' sag)
    assert miss[0] > 5e-3


def test_forty_point_arc_of_a_crank_rocker_is_met_with_the_compiled_lm(
    compiled, tmp_path, monkeypatch
):
    known = PlacedFourBar(FourBar(3.0, 1.0, 3.5, 3.2, coupler=(2.0, 0.8)), 1 + 1j, 0.4, 1)
    theta = np.linspace(0.0, 2.5, 40)
    targets = known.pose(theta)[2]
    assert targets.size >= MANY_POINTS
    build_atlas(tmp_path / "a", 600, chunk_size=300, seed=3, progress=False)
    solvers = set()
    refine = atlas_path.refine
    monkeypatch.setattr(atlas_path, "refine", lambda *a, **k: solvers.add(k.get("solver"))
                        or refine(*a, **k))  # fmt: skip
    res = path_from_atlas(targets, tmp_path / "a", closed=False, n=1, mu_min=0.0)
    assert solvers == {"lm"}  # no trf on this many points
    best = res.candidates[0]
    size = float(np.max(np.abs(targets - targets.mean())))
    assert float(np.max(_curve_distance(best, targets))) <= 1e-6 * size
