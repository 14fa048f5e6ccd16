"""The atlas query's compact first stage, against bounds and top-k lists written here.

The query (compiled, from an atlas's second query on) bounds each row's best cosine
over the descriptor's four variants from a compact table: six columns rounded to
int16 and the norms of three groups of the others rounded up to uint16
(``compact_rows``), scans only the rows whose key column lies in a window that can
hold a row near enough (``key_ranges``), and scores exactly the rows whose bound
beats the k-th best so far (``bound_topk``, which keeps that k-th best in a heap).
Here the bound is rebuilt in float64 from the table's integers by the formula of
the docstrings and compared with the exact score of every row, the windows with a
brute-force scan, and the rows kept with the top k of a NumPy sort.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn import jit


def _kernels():
    if not jit.load():
        pytest.skip(f"compiled kernels unavailable: {jit.reason()}")
    from machdyn.synthesis import _atlas_kernels

    return _atlas_kernels


def _descriptors(rng, n, w=32):
    """Unit rows whose energy falls off over the columns, as an atlas's does."""
    d = rng.standard_normal((n, w)) * np.geomspace(1.0, 1e-3, w)[rng.permutation(w)]
    return (d / np.linalg.norm(d, axis=1, keepdims=True)).astype(np.float32)


def _variants(rng, w=32):
    """Four unit query rows: one and three of its sign-flipped, swapped copies."""
    q = rng.standard_normal(w) * np.geomspace(1.0, 1e-3, w)
    q /= np.linalg.norm(q)
    flip = np.where(np.arange(w) % 2, -1.0, 1.0)
    swap = np.arange(w).reshape(-1, 2)[:, ::-1].ravel()
    return np.stack([q, q * flip, q[swap], (q * flip)[swap]])


def _plan(rng, w=32):
    """Six head columns, the others split into three groups (−1: head)."""
    order = rng.permutation(w)
    groups = np.full(w, -1, np.int64)
    for g, part in enumerate(np.array_split(order[6:], 3)):
        groups[part] = g
    return np.sort(order[:6]).astype(np.int64), groups


def _table(K, desc, rows, cols, groups, kcol):
    """A compact table sorted by its key column, as Atlas._tables builds it."""
    head = np.empty((6, rows.size), np.int16)
    tail = np.empty((3, rows.size), np.uint16)
    hs, ts, longest2 = K.compact_rows(desc, rows, cols, groups, head, tail)
    order = np.argsort(head[kcol], kind="stable")
    return head[:, order], tail[:, order], rows[order], hs, ts, longest2


def test_the_compact_bound_is_never_below_the_exact_score():
    """Every row, every variant: the bound from the int16/uint16 table ≥ the exact cosine."""
    K = _kernels()
    rng = np.random.default_rng(11)
    desc = _descriptors(rng, 4000)
    desc[7, :] = 0.0
    desc[7, 0] = 1.0  # a row all head or all tail, one with a head value at the extreme
    desc[8, :] = np.float32(1 / np.sqrt(32))
    cols, groups = _plan(rng)
    rows = np.sort(rng.choice(4000, 3000, replace=False)).astype(np.int32)
    rows[:2] = (7, 8)
    rows.sort()
    head = np.empty((6, rows.size), np.int16)
    tail = np.empty((3, rows.size), np.uint16)
    hs, ts, longest2 = K.compact_rows(desc, rows, cols, groups, head, tail)
    d = desc[rows].astype(np.float64)
    # the table's promises, checked on their own: head within half a step, norms rounded up
    assert np.all(np.abs(head / hs - d[:, cols].T) <= 0.5 / hs * (1 + 1e-9))
    norms = np.stack([np.linalg.norm(d[:, groups == g], axis=1) for g in range(3)])
    assert np.all(tail / ts[:, None] >= norms)
    assert np.all(tail / ts[:, None] - norms <= 1.0 / ts[:, None] * (1 + 1e-9))
    assert longest2 >= np.max(np.sum(d**2, axis=1))
    for _ in range(20):
        v = _variants(rng)
        qn = np.stack([np.linalg.norm(v[:, groups == g], axis=1) for g in range(3)], axis=1)
        allowance = 0.5 * np.sum(np.max(np.abs(v[:, cols]), axis=0)) / hs
        bound = (head.T / hs) @ v[:, cols].T + (tail.T / ts) @ qn.T + allowance  # (rows, 4)
        exact = d @ v.T
        assert np.all(bound >= exact - 1e-12)
        assert np.max(bound - exact) < 2.0  # (a bound, not a blanket)


def test_the_key_windows_hold_every_row_that_can_come_near_the_floor():
    """Rows outside ``key_ranges`` score at most ``floor − margin`` (brute force)."""
    K = _kernels()
    rng = np.random.default_rng(12)
    desc = _descriptors(rng, 3000)
    cols, groups = _plan(rng)
    rows = np.arange(3000, dtype=np.int32)
    left_out = 0
    for kcol in (0, 3):
        head, _, rows_k, hs, _, longest2 = _table(K, desc, rows, cols, groups, kcol)
        assert np.all(np.diff(head[kcol].astype(int)) >= 0)
        for _ in range(15):
            v = _variants(rng)
            near = desc[rng.integers(3000)] + 0.05 * rng.standard_normal(32)
            v[0] = near / np.linalg.norm(near)  # (so that a few rows score near 1)
            exact = np.max(desc[rows_k].astype(np.float64) @ v.T, axis=1)
            floor = np.quantile(exact, rng.uniform(0.9, 0.9999))
            ranges = K.key_ranges(head[kcol], hs, v[:, cols[kcol]].copy(), np.sum(v**2, axis=1),
                                  longest2, floor, 1e-5)  # fmt: skip
            inside = np.zeros(rows_k.size, bool)
            for lo, hi in ranges:
                inside[lo:hi] = True
            assert np.all(exact[~inside] <= floor - 1e-5)
            left_out += rows_k.size - inside.sum()
        everything = K.key_ranges(head[kcol], hs, v[:, cols[kcol]].copy(), np.sum(v**2, axis=1),
                                  longest2, -np.inf, 1e-5)  # fmt: skip
        np.testing.assert_array_equal(everything, [[0, rows_k.size]])
    assert left_out > 0  # (the windows do leave rows out)


@pytest.mark.parametrize("k", [1, 25, 700])
def test_the_rows_kept_hold_the_exact_top_k_and_the_heap_its_scores(k):
    """Chunks scanned one after another, the heap carried: the top k of a NumPy sort."""
    K = _kernels()
    rng = np.random.default_rng(13 + k)
    cols, groups = _plan(rng)
    chunks = [_descriptors(rng, n) for n in (500, 1200, 900, 1500)]
    # a query near a row of the third chunk, so the floor ends high
    v = _variants(rng)
    target = chunks[2][17].astype(np.float64) + 0.02 * rng.standard_normal(32)
    v[0] = target / np.linalg.norm(target)
    qn = np.stack([np.linalg.norm(v[:, groups == g], axis=1) for g in range(3)], axis=1)
    best = np.full(k, -np.inf)
    kept, allowed = set(), []
    for c, desc in enumerate(chunks):
        rows = np.flatnonzero(rng.random(desc.shape[0]) < 0.8).astype(np.int32)
        allowed.append(rows)
        head, tail, rows, hs, ts, longest2 = _table(K, desc, rows, cols, groups, kcol=1)
        out = np.empty(rows.size, np.int64)
        score = np.empty(rows.size, np.float64)
        n, _ = K.bound_topk(head, tail, rows, 1, desc, v[:, cols].copy(), qn, np.sum(v**2, axis=1),
                         hs, ts, longest2, v, 1e-4, 1e-5, best, out, score)  # fmt: skip
        kept |= {(c, int(r)) for r in out[:n]}
        exact = np.max(desc[out[:n]].astype(np.float64) @ v.T, axis=1)
        np.testing.assert_allclose(score[:n], exact, rtol=0, atol=1e-14)  # (unit rows)
    # brute force over every allowed row of every chunk
    every = sorted(
        ((float(s), c, int(r))
         for c, (desc, rows) in enumerate(zip(chunks, allowed, strict=True))
         for s, r in zip(np.max(desc[rows].astype(np.float64) @ v.T, axis=1), rows, strict=True)),
        reverse=True,
    )  # fmt: skip
    assert {(c, r) for _, c, r in every[:k]} <= kept
    np.testing.assert_allclose(np.sort(best)[::-1], [e[0] for e in every[:k]], rtol=1e-12)
    assert len(kept) < len(every) // 2 or k == 700  # (rows were skipped)


def test_nearest_is_the_same_with_and_without_the_compact_stage(tmp_path, request):
    """A small atlas: the first query (every row by BLAS) and later ones give the same list."""
    from machdyn.synthesis import build_atlas, open_atlas

    _kernels()
    jit.set_mode("on")
    request.addfinalizer(lambda: jit.set_mode("off"))
    build_atlas(tmp_path / "a", 3000, chunk_size=700, seed=3, progress=False)
    rng = np.random.default_rng(14)
    for crank in (True, False):
        for k in (1, 60, 900):  # 900: more than a chunk's crank rows
            at = open_atlas(tmp_path / "a")
            desc = np.concatenate([np.asarray(d) for d in at.desc]).astype(np.float64)
            q = desc[rng.integers(len(desc))] + 0.1 * rng.standard_normal(desc.shape[1])
            q /= np.linalg.norm(q)
            first = at.nearest(q, k, crank=crank)  # (BLAS over every row)
            again = at.nearest(q, k, crank=crank)  # (the compact stage)
            assert at._compact  # (it ran)
            np.testing.assert_array_equal(np.sort(first[0]), np.sort(again[0]))
            np.testing.assert_allclose(np.sort(first[1]), np.sort(again[1]), atol=1e-6)
