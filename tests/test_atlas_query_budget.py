"""Every atlas query is exact while its compact tables are built a few chunks at a time.

A query builds the compact tables of at most ``TABLE_BUDGET`` chunks and scores the
chunks without them by BLAS (float32, then float64 for the rows near the k-th best);
a thread whose bound passes too many rows scores its other chunks by BLAS too. So one
query mixes both ways. Here, on a small atlas with ties (exact copies of rows) and a
dense cluster (80 rows whose scores near it lie within 1e-7 of each other, inside the
float32 scores' band, as the near-circular curves of the 10^7 atlas crowd), every
query from the first on, with the tables partly built, with and without ``crank``,
with the fallback never and always taken, is compared with a brute-force ranking
written in tests/test_atlas_topk.py: every score summed exactly (``math.fsum`` of the
float64 products of the float32 descriptor and variant, exact themselves), best first,
equal scores by the lower flat index.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np
import pytest
from tests.test_atlas_topk import _brute_force, _exact_scores

from machdyn import jit
from machdyn.synthesis import _atlas_index, build_atlas, open_atlas

N, CHUNK = 3600, 300


@pytest.fixture(scope="module")
def crowded_atlas(tmp_path_factory):
    """Twelve chunks; 40 rows copied elsewhere; 80 rows 1e-4 from one row, 50 in one chunk."""
    folder = tmp_path_factory.mktemp("budget") / "a"
    build_atlas(folder, N, chunk_size=CHUNK, seed=8, progress=False)
    names = [folder / f"chunk_{c:05d}.desc.npy" for c in range(N // CHUNK)]
    desc = np.concatenate([np.load(p) for p in names])
    rng = np.random.default_rng(31)
    spots = rng.permutation(N)
    for i in range(40):  # ties: a source row, then one or two places that take its copy
        src, *dst = spots[3 * i : 3 * i + 2 + i % 2]
        desc[dst] = desc[src]
    centre = desc[spots[200]].astype(np.float64)
    crowd = np.union1d(spots[201:231], np.setdiff1d(np.arange(900, 950), spots[:120]))
    near = centre + 2e-5 * rng.standard_normal((crowd.size, desc.shape[1]))
    desc[crowd] = (near / np.linalg.norm(near, axis=1, keepdims=True)).astype(np.float32)
    for c, p in enumerate(names):
        np.save(p, desc[c * CHUNK : (c + 1) * CHUNK])
    return folder, desc, spots[: 3 * 40 : 3], centre


def _targets(desc, copied, centre, rng, count):
    """Targets in the crowd, near copied rows, near others, and far from all."""
    out = []
    for t in range(count):
        if t % 4 == 0:
            q = centre + 1e-6 * rng.standard_normal(desc.shape[1])
        elif t % 4 == 1:
            base = desc[rng.choice(copied)].astype(np.float64)
            q = base + rng.uniform(1e-4, 0.05) * rng.standard_normal(desc.shape[1])
        elif t % 4 == 2:
            q = desc[rng.integers(N)] + 0.1 * rng.standard_normal(desc.shape[1])
        else:
            q = rng.standard_normal(desc.shape[1])
        out.append(q / np.linalg.norm(q))
    return out


@pytest.mark.parametrize("fallback", [0.2, 0.0])
def test_every_query_gives_the_brute_force_top_k_while_tables_are_built(
    crowded_atlas, compiled, monkeypatch, fallback
):
    """16 queries, two tables built each: the top k of the brute force, every one."""
    monkeypatch.setattr(_atlas_index, "TABLE_BUDGET", 2)
    monkeypatch.setattr(_atlas_index, "BOUND_FALLBACK", fallback)
    folder, desc, copied, centre = crowded_atlas
    at = open_atlas(folder, verify=False)
    crank_ok = np.concatenate([m["barker"] <= 2 for m in at.meta])
    rng = np.random.default_rng(32 + int(fallback * 10))
    partly = crowded = 0
    for t, q in enumerate(_targets(desc, copied, centre, rng, 16)):
        crank = t % 3 != 2
        k = (20, 1, 160, int(rng.integers(2, 40)))[t % 4]
        exact = _exact_scores(desc, q)
        want, score = _brute_force(exact, crank_ok if crank else np.ones(N, bool), k)
        crowded += bool(score[0] - score[-1] < 1e-6)  # (the top k within 1e-6)
        idx, dist = at.nearest(q, k, crank=crank)
        np.testing.assert_array_equal(idx, want)
        np.testing.assert_allclose(dist, 2.0 - 2.0 * score, rtol=0, atol=1e-14)
        built = len(at._compact)
        partly += 0 < built < 2 * len(at.desc)
        if t > 0:  # (the first query builds none; each later one two at most)
            assert 0 < built <= 2 * t
    assert partly >= 8  # (most queries met a partly built atlas)
    assert crowded >= 4  # (the crowd's targets: every one)


def test_a_query_builds_at_most_its_budget_of_tables(crowded_atlas, compiled, monkeypatch):
    """Four tables a query, spread over the atlas, until every one asked for is built."""
    monkeypatch.setattr(_atlas_index, "TABLE_BUDGET", 4)
    folder, desc, _, _ = crowded_atlas
    at = open_atlas(folder, verify=False)
    q = desc[5].astype(np.float64)
    at.nearest(q, 10)
    assert not at._compact  # (the first query builds none)
    at.nearest(q, 10)
    chunks = sorted(c for c, _ in at._compact)
    assert [p for _, p in at._compact] == [True] * 4 and chunks[-1] - chunks[0] > 6
    built = [len(at._compact)]
    for crank in (True, True, False, False, False, False, False, False):
        at.nearest(q, 10, crank=crank)
        built.append(len(at._compact))
    # 12 crank tables after three queries, then 12 others: 4 a query (3 when a chunk
    # lacking both does not fit in what is left), never more
    assert built[:3] == [4, 8, 12] and built[-1] == 24
    assert all(0 <= b - a <= 4 and (b - a >= 3 or b == 24) for a, b in pairwise(built))
    jit.set_mode("off")  # (NumPy: every row by BLAS, no tables built)
    at._compact.clear()
    at.nearest(q, 10, crank=False)
    assert not at._compact
