"""Timed-target starts of the atlas path synthesis, against a direct fit written here.

``_timed_fits`` scores every atlas entry (and its mirror image) at every starting
crank angle θ0 by fitting its coupler points at ``θ0 + Δ_k`` onto the targets: it
computes each distinct angle once, takes a mirror image's points as conjugates at
the negative angles, and (compiled) fuses the fits. The check here builds each
linkage with :class:`PlacedFourBar` (the four-bar's own solver, the mirror image
as its own linkage: δ → −δ on the other circuit), and solves each placement as a
linear least-squares problem with scipy, bounds and all; both backends.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import lsq_linear

from machdyn.fourbar import FourBar
from machdyn.synthesis import PlacedFourBar
from machdyn.synthesis._atlas_retrieve import _angle_table, _timed_fits
from machdyn.synthesis.atlas_store import sample_fourbars


def _points(row, mirror, theta):
    """Coupler points of an entry (unit crank, O2 at the origin) or of its mirror image."""
    fb = FourBar(float(row["r1"]), 1.0, float(row["r3"]), float(row["r4"]),
                 coupler=(float(row["p"]), mirror * float(row["delta"])))  # fmt: skip
    return PlacedFourBar(fb, 0.0, 0.0, int(mirror * row["circuit"])).pose(theta)[2]


def _direct(Q, targets, O2, theta1):
    """Least-squares placement of points Q on the targets: score, h and t (scipy, bounded)."""
    k = Q.size
    # unknowns: [tx, ty] (free offset) then h as (hr, hi) or as s >= 0 along e^{jθ1}
    one, zero = np.ones(k), np.zeros(k)
    cols = [] if O2 is not None else [np.r_[one, zero], np.r_[zero, one]]
    if theta1 is None:
        cols += [np.r_[Q.real, Q.imag], np.r_[-Q.imag, Q.real]]
    else:
        R = Q * np.exp(1j * theta1)
        cols += [np.r_[R.real, R.imag]]
    A = np.column_stack(cols)
    b = targets - (0 if O2 is None else O2)
    lo = np.full(A.shape[1], -np.inf)
    if theta1 is not None:
        lo[-1] = 0.0
    sol = lsq_linear(A, np.r_[b.real, b.imag], bounds=(lo, np.inf), tol=1e-14)
    r = A @ sol.x - np.r_[b.real, b.imag]
    centred = targets - (targets.mean() if O2 is None else O2)
    score = 1.0 - np.sum(r**2) / np.sum(np.abs(centred) ** 2)
    u = sol.x[2:] if O2 is None else sol.x
    h = complex(u[0], u[1]) if theta1 is None else u[0] * np.exp(1j * theta1)
    t = complex(sol.x[0], sol.x[1]) if O2 is None else O2
    return score, h, t


@pytest.mark.parametrize(
    ("O2", "theta1", "grid"),
    [(None, None, 9), (0.4 - 0.3j, None, 9), (None, 0.7, 9), (0.2 + 0.1j, -0.5, 1)],
)
def test_timed_fits_match_a_direct_fit_of_every_entry_and_its_mirror(backend, O2, theta1, grid):
    rng = np.random.default_rng(5)
    rows = sample_fourbars(rng, 40, (0.4, 3.0))
    rows = rows[rows["barker"] <= 2][:8]
    targets = rng.normal(size=6) + 1j * rng.normal(size=6)
    # steps of 20 deg from a 40-deg grid (angles repeat across rows) and uneven steps
    for timing in (np.radians(20.0) * np.arange(6), np.r_[0.0, np.cumsum(rng.uniform(0.1, 1, 5))]):
        th = np.linspace(0, 2 * np.pi, grid, endpoint=False)[:, None] + timing
        score, g, h, t = _timed_fits(rows, _angle_table(th), targets, O2, theta1)
        for m, mirror in enumerate((1.0, -1.0)):
            for i, row in enumerate(rows):
                Q = _points(row, mirror, th.ravel()).reshape(th.shape)
                fits = [_direct(Q[j], targets, O2, theta1) for j in range(grid)]
                best = max(f[0] for f in fits)
                assert score[m, i] == pytest.approx(best, abs=1e-9)
                # the chosen angle fits as well as the best, with its own placement
                s, hh, tt = fits[g[m, i]]
                assert s == pytest.approx(best, abs=1e-9)
                assert abs(h[m, i] - hh) <= 1e-7 * (1 + abs(hh))
                assert abs(t[m, i] - tt) <= 1e-7 * (1 + abs(tt))


def test_the_angle_table_holds_each_angle_and_its_negative_once():
    th = np.radians(6.0) * np.arange(60)[:, None] + np.radians(20.0) * np.arange(18)
    angles, ip, im = _angle_table(th)
    assert angles.size == 180  # multiples of 2 deg: 6 and 20 meet on gcd 2
    np.testing.assert_allclose(np.exp(1j * angles[ip]), np.exp(1j * th), atol=1e-11)
    np.testing.assert_allclose(np.exp(1j * angles[im]), np.exp(-1j * th), atol=1e-11)


# --------------------------------------------------------------------------------------
# the nearest entries, scored by chunks on several threads


@pytest.mark.parametrize("crank", [True, False])
@pytest.mark.parametrize("compiled", [False, True])
def test_nearest_on_threads_is_the_exact_top_k_of_a_brute_force_search(
    tmp_path_factory, monkeypatch, request, crank, compiled
):
    """Compiled, queries after the first go in two stages (a bound, then the exact scores)."""
    from machdyn import _parallel, jit
    from machdyn.synthesis import _atlas_index
    from machdyn.synthesis.atlas_path import open_atlas
    from machdyn.synthesis.atlas_store import build_atlas
    from machdyn.synthesis.descriptor import descriptor_variants

    if compiled and not jit.load():
        pytest.skip(f"compiled kernels unavailable: {jit.reason()}")
    jit.set_mode("on" if compiled else "off")
    request.addfinalizer(lambda: jit.set_mode("off"))  # conftest.py's mode
    folder = tmp_path_factory.mktemp("near") / "a"
    build_atlas(folder, 2500, chunk_size=400, seed=8, progress=False)  # 7 chunks
    at = open_atlas(folder)
    monkeypatch.setattr(_parallel, "MIN_PARALLEL", 1)  # threads even for this small atlas
    monkeypatch.setenv("MACHDYN_THREADS", "3")
    two = []
    bounded = _atlas_index.bounded_topk
    monkeypatch.setattr(_atlas_index, "bounded_topk", lambda *a: two.append(1) or bounded(*a))
    desc = np.concatenate([np.asarray(d, float) for d in at.desc])
    allowed = np.concatenate([np.asarray(m["barker"]) <= 2 for m in at.meta])
    rng = np.random.default_rng(4)
    for _ in range(4):
        q = desc[rng.integers(len(desc))] + 0.05 * rng.standard_normal(desc.shape[1])
        q /= np.linalg.norm(q)  # a descriptor has unit length
        idx, dist = at.nearest(q, 40, crank=crank)
        # brute force in float64: the best cosine over the descriptor's four variants
        v = descriptor_variants(q).reshape(4, -1)
        score = np.max(desc @ v.T, axis=1)
        score[~allowed if crank else np.zeros(len(desc), bool)] = -np.inf
        want = np.argsort(-score)[:40]
        assert set(idx) == set(want)
        np.testing.assert_allclose(dist, 2 - 2 * score[want], atol=1e-5)
    assert bool(two) == compiled  # the two stages ran (compiled), or never (NumPy)
