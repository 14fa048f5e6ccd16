"""A time limit cuts the atlas query between chunks, and leaves out the wide rows' starts.

No assertion is on a time: a deadline that has passed before the query is driven
directly. The query cut after one chunk per thread must return the exact nearest
entries of the chunks it scored (brute force over them, written here), and a
whole synthesis with a limit of 0 still returns a checked linkage from them.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.synthesis import _atlas_retrieve, atlas_path
from machdyn.synthesis._atlas_index import _NEVER, _Deadline
from machdyn.synthesis.atlas_path import open_atlas, path_from_atlas
from machdyn.synthesis.atlas_store import build_atlas
from machdyn.synthesis.descriptor import descriptor_variants


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    folder = tmp_path_factory.mktemp("limit") / "a"
    build_atlas(folder, 2400, chunk_size=400, seed=5, progress=False)  # 6 chunks
    return open_atlas(folder)


def _brute(at, q, k, chunks, crank):
    """The k best (cosine over the four variants) of the given chunks' entries, in float64."""
    v = descriptor_variants(q).reshape(4, -1)
    idx = np.concatenate([np.arange(at.offsets[c], at.offsets[c + 1]) for c in chunks])
    desc = np.concatenate([np.asarray(at.desc[c], float) for c in chunks])
    score = np.max(desc @ v.T, axis=1)
    if crank:
        score[np.concatenate([np.asarray(at.meta[c]["barker"]) > 2 for c in chunks])] = -np.inf
    top = np.argsort(-score)[:k]
    return set(idx[top])


@pytest.mark.parametrize("crank", [True, False])
def test_a_passed_deadline_scores_one_chunk_per_thread_and_returns_its_nearest(
    atlas, monkeypatch, crank
):
    from machdyn import _parallel

    split = _parallel.for_slices  # threads even for this small atlas
    monkeypatch.setattr(_parallel, "for_slices", lambda kernel, n, minimum=1: split(kernel, n, 1))
    rng = np.random.default_rng(2)
    q = np.asarray(atlas.desc[3][7], float) + 0.05 * rng.standard_normal(atlas.desc[0].shape[1])
    q /= np.linalg.norm(q)
    for threads, chunks in (("1", [0]), ("2", [0, 3])):  # each thread's first chunk
        monkeypatch.setenv("MACHDYN_THREADS", threads)
        passed = _Deadline(0.0)
        idx, dist = atlas._query(q, 12, crank, None, passed)
        assert passed.hit
        assert set(idx) == _brute(atlas, q, 12, chunks, crank)
        assert np.all(np.diff(dist) >= 0)
        # without a deadline: the whole atlas, as nearest() gives it
        whole = atlas._query(q, 12, crank, None, _NEVER)
        np.testing.assert_array_equal(whole[0], atlas.nearest(q, 12, crank=crank)[0])
        assert set(whole[0]) == _brute(atlas, q, 12, range(len(atlas.desc)), crank)


@pytest.mark.parametrize("timed", [False, True])
def test_a_limit_of_zero_leaves_out_the_wide_rows_and_still_answers(atlas, monkeypatch, timed):
    from machdyn.fourbar import FourBar
    from machdyn.synthesis import PlacedFourBar

    known = PlacedFourBar(FourBar(3.0, 1.0, 3.5, 2.5, coupler=(1.8, 0.6)), 0.5 + 0.2j, 0.3, 1)
    theta = np.radians(np.arange(0, 360, 30))
    targets = known.pose(theta)[2]
    options = {"timing": theta} if timed else {}
    wide = []
    rows = _atlas_retrieve._wide_rows
    monkeypatch.setattr(atlas_path, "_retrieve_wide", lambda *a: wide.append(1) or 1 / 0)
    monkeypatch.setattr(_atlas_retrieve, "_wide_rows", lambda crank: wide.append(2) or rows(crank))
    res = path_from_atlas(targets, atlas, n=1, time_limit=0.0, **options)
    assert res.note.startswith("stopped at the time limit")
    assert wide == ([2] if timed else [])  # (timed: the rows are taken, then left out)
    best = (res.candidates or res.rejected)[0]
    P = best.linkage.pose(best.theta2)[2]  # its own points where it claims to meet the targets
    np.testing.assert_allclose(np.abs(P - targets), best.distance, atol=1e-9)


def test_an_open_pool_with_a_limit_is_taken_in_slices_and_cut_after_the_first(
    atlas, monkeypatch, backend
):
    from machdyn.synthesis.atlas_store import even_curves

    man = atlas.manifest
    rows = atlas.entries(atlas.pool(900, crank=True))
    whole = even_curves(rows, man.circuit_samples, man.samples)
    monkeypatch.setattr(_atlas_retrieve, "POOL_SLICE", 250)
    monkeypatch.setattr(_atlas_retrieve, "OPEN_POOL", 900)
    seen, calls = [], []
    monkeypatch.setattr(_atlas_retrieve, "_arc_starts", lambda r, c, p, n: seen.append((r, c)) or 0)
    curves = _atlas_retrieve.even_curves
    monkeypatch.setattr(_atlas_retrieve, "even_curves", lambda r, *a: calls.append(r.size) or
                        curves(r, *a))  # fmt: skip
    pts = np.linspace(0, 1, 6) + 0.2j * np.linspace(0, 1, 6) ** 2
    for deadline, size, sizes in ((_NEVER, 900, [900]), (_Deadline(1e300), 900, [250] * 3 + [150]),
                                  (_Deadline(0.0), 250, [250])):  # fmt: skip
        seen.clear(), calls.clear()
        _atlas_retrieve._retrieve(atlas, pts, False, True, 10, 10, None, deadline)
        ((r, c),) = seen
        assert calls == sizes
        np.testing.assert_array_equal(r, rows[:size])
        # each row's curve as in one call (compiled: exactly; NumPy: to rounding)
        np.testing.assert_allclose(c, whole[:size], rtol=0, atol=0 if backend == "compiled"
                                   else 1e-10)  # fmt: skip
