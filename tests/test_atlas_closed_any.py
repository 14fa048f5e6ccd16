"""Closed untimed paths no four-bar traces: no pool round past the first.

Eight points round a square: every coupler curve misses the corners by some tenths of
the size, and fresh pools of the atlas do not bring one nearer. Checked by the tests'
own point-to-curve distance (circle intersection,
``tests.test_synthesis_path_atlas._curve_distance``) on the 20,000-entry test atlas.
"""

from __future__ import annotations

import numpy as np
import pytest
from tests.test_synthesis_path_atlas import _curve_distance

from machdyn.synthesis.atlas_path import open_atlas, path_from_atlas
from machdyn.synthesis.atlas_store import build_atlas


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    folder = tmp_path_factory.mktemp("atlas")
    build_atlas(folder, 20_000, chunk_size=10_000, seed=11, progress=False)
    return open_atlas(folder)


def _worst(res, pts) -> float:
    """The first result's largest distance to the targets over their size (inf if none)."""
    size = np.max(np.abs(pts - pts.mean()))
    found = (res.candidates or res.rejected)[:1]
    return float(np.max(_curve_distance(found[0], pts))) / size if found else np.inf


SQUARE = np.array([0, 1, 2, 2 + 1j, 2 + 2j, 1 + 2j, 2j, 1j])  # eight points round a square


def test_a_square_no_four_bar_traces_takes_no_later_round(atlas, monkeypatch):
    # a coupler curve is smooth: round a square's corners it misses the points by some
    # tenths of the half-diagonal; the later rounds (fresh pools of the atlas, each
    # taken by Atlas.pool) would not bring it nearer and are not taken
    pools = []
    take = atlas.pool
    monkeypatch.setattr(atlas, "pool", lambda *a, **k: pools.append(k) or take(*a, **k))
    # (with any input: the crank search, then the search of every row; both stop)
    res = path_from_atlas(SQUARE, atlas, closed=True, crank=False, n=3)
    assert _worst(res, SQUARE) > 5e-2
    assert "no atlas entry comes near" in res.note
    assert pools == []
