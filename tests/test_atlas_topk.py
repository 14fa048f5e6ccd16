"""The atlas's top k is one list, whatever path finds it, and it is the brute-force one.

An atlas is scored by float32 products on its first query (and on Dask), by a
compact bound and float64 scores from its second query on (compiled): near the
k-th best, the rounding of those scores and equal scores could pick different
rows. Here the top k of a small atlas, with exact copies of rows planted across
its chunks (equal scores, broken by the index), is compared with a brute-force
ranking written here: every score summed exactly (``math.fsum`` of the float64
products of the float32 descriptor and variant, exact themselves), best first,
equal scores by the lower flat index.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from machdyn.synthesis import build_atlas, open_atlas
from machdyn.synthesis.descriptor import descriptor_variants

N, CHUNK = 2400, 600


@pytest.fixture(scope="module")
def tied_atlas(tmp_path_factory):
    """An atlas of four chunks in which 60 rows have copies elsewhere (two or three each)."""
    folder = tmp_path_factory.mktemp("topk") / "a"
    build_atlas(folder, N, chunk_size=CHUNK, seed=5, progress=False)
    names = [folder / f"chunk_{c:05d}.desc.npy" for c in range(N // CHUNK)]
    desc = np.concatenate([np.load(p) for p in names])
    rng = np.random.default_rng(21)
    spots = rng.permutation(N)
    for i in range(60):  # a source row, then one or two places that take its copy
        src, *dst = spots[3 * i : 3 * i + 2 + i % 2]
        desc[dst] = desc[src]
    for c, p in enumerate(names):
        np.save(p, desc[c * CHUNK : (c + 1) * CHUNK])
    return folder, desc, spots[: 3 * 60 : 3]  # (the copied rows)


def _exact_scores(desc, q):
    """Every row's best score over the query's four variants, each sum rounded once."""
    v = descriptor_variants(q).astype(np.float64)  # (the query in float32, as stored)
    products = desc.astype(np.float64)[:, None, :] * v  # (exact: 24-bit times 24-bit)
    return np.array([max(map(math.fsum, row)) for row in products.tolist()])


def _brute_force(scores, allowed, k):
    """Flat indices and scores of the best k allowed rows (ties by the lower index)."""
    rows = np.flatnonzero(allowed)
    ranked = sorted(zip(scores[rows].tolist(), rows.tolist(), strict=True),
                    key=lambda t: (-t[0], t[1]))[:k]  # fmt: skip
    return np.array([r for _, r in ranked]), np.array([s for s, _ in ranked])


def _targets(desc, copied, rng, count):
    """Targets near copied rows (ties near the top), near others, and far from all."""
    out = []
    for t in range(count):
        if t % 3 == 0:
            base = desc[rng.choice(copied)].astype(np.float64)
            q = base + rng.uniform(1e-4, 0.05) * rng.standard_normal(desc.shape[1])
        elif t % 3 == 1:
            q = desc[rng.integers(N)] + 0.1 * rng.standard_normal(desc.shape[1])
        else:
            q = rng.standard_normal(desc.shape[1])
        out.append(q / np.linalg.norm(q))
    return out


def test_first_and_later_queries_give_the_brute_force_top_k(tied_atlas, backend):
    """24 targets, k cutting through runs of equal scores: every query, the same list."""
    folder, desc, copied = tied_atlas
    at = open_atlas(folder, verify=False)  # (chunks rewritten with the copies)
    crank_ok = np.concatenate([m["barker"] <= 2 for m in at.meta])
    rng = np.random.default_rng(22)
    checked = ties = 0
    for q in _targets(desc, copied, rng, 24):
        crank = bool(rng.random() < 0.5)
        exact = _exact_scores(desc, q)
        for k in (1, int(rng.integers(2, 40)), 160):
            want, score = _brute_force(exact, crank_ok if crank else np.ones(N, bool), k)
            ties += int(np.sum(score[1:] == score[:-1]))
            for _ in range(3):  # the first query of this atlas, then later ones
                idx, dist = at.nearest(q, k, crank=crank)
                np.testing.assert_array_equal(idx, want)
                np.testing.assert_allclose(dist, 2.0 - 2.0 * score, rtol=0, atol=1e-14)
                checked += 1
    assert ties > 20  # (equal scores were met and ordered by index)
    assert checked == 24 * 3 * 3


def test_dask_query_gives_the_brute_force_top_k(tied_atlas):
    """The chunks scored as Dask tasks: the same lists as the brute force (and the local query)."""
    distributed = pytest.importorskip("distributed")
    folder, desc, copied = tied_atlas
    at = open_atlas(folder, verify=False)
    crank_ok = np.concatenate([m["barker"] <= 2 for m in at.meta])
    rng = np.random.default_rng(23)
    targets = _targets(desc, copied, rng, 8)
    with distributed.Client(processes=False, n_workers=1, dashboard_address=None) as client:
        for q in targets:
            exact = _exact_scores(desc, q)
            for k, crank in ((1, True), (int(rng.integers(2, 40)), False), (160, True)):
                want, score = _brute_force(exact, crank_ok if crank else np.ones(N, bool), k)
                idx, dist = at.nearest(q, k, crank=crank, client=client)
                np.testing.assert_array_equal(idx, want)
                np.testing.assert_allclose(dist, 2.0 - 2.0 * score, rtol=0, atol=1e-14)
