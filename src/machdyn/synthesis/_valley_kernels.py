"""Compiled (numba) loop of the final polish: geodesic-acceleration Levenberg–Marquardt.

The twin of :func:`machdyn.synthesis.valley._descend` on refine's problem
(:func:`machdyn.synthesis._atlas_kernels._lm_problem`: the same rows and
columns as :func:`machdyn.synthesis.refine._problem`), the same steps up to
rounding (tests/test_atlas_open_polish.py runs both from the same starts).
The NumPy loop spends ~0.1 ms per residual in Python's overhead on these small
problems (27 rows × 18 unknowns for 9 targets); here a whole polish of a few
hundred steps takes a few milliseconds, so a near miss can be polished longer.
Imported only when :mod:`machdyn.jit` lets the compiled kernels serve.
"""

from __future__ import annotations

import math

import numpy as np

from .._numba_cache import njit
from ._atlas_kernels import _lm_problem

__all__ = ["descend"]


@njit(cache=True, nogil=True, error_model="numpy")
def _residual(z, targets, branch, timing, timed, crank, cos_mu, scale, weight, r, Jm, want):
    return _lm_problem(z, targets, branch, timing, timed, crank, cos_mu, scale, weight, -1,
                       np.zeros(4), r, Jm, want)  # fmt: skip  # pragma: no cover - compiled


@njit(cache=True, nogil=True, error_model="numpy")
def _allowed(z, max_length, box, use_box):  # pragma: no cover - compiled
    """valley.polish's ``allowed``: positive lengths, ``p ≥ 0``, length and pivot bounds."""
    for i in range(4):
        if not z[i] > 0.0:
            return False
    if z[4] < 0.0:
        return False
    for i in range(5):
        if z[i] > max_length:
            return False
    if use_box:
        return box[0] <= z[6] <= box[2] and box[1] <= z[7] <= box[3]
    return True


@njit(cache=True, nogil=True, error_model="numpy")
def _solve(M, b, out):  # pragma: no cover - compiled
    """``out = M⁻¹ b``; False where NumPy's solve would raise or give non-finite numbers."""
    for i in range(M.shape[0]):
        if not np.isfinite(b[i]):
            return False
        for j in range(M.shape[1]):
            if not np.isfinite(M[i, j]):
                return False
    try:
        out[:] = np.linalg.solve(M, b)
    except Exception:  # singular (NumPy's LinAlgError)
        return False
    return bool(np.all(np.isfinite(out)))


@njit(cache=True, nogil=True, error_model="numpy")
def descend(z, free, targets, branch, timing, timed, crank, cos_mu, scale, weight, max_length,
            box, use_box, iterations, h, alpha, done, stall):  # fmt: skip  # pragma: no cover
    """valley._descend in place on ``z``; returns the points ``G`` at the final ``z``.

    ``max_length``: ``inf`` for none; ``box`` (4,) with ``use_box``.
    """
    k = targets.size
    n = z.size
    rows = 3 * k + (4 if crank else 0)
    nf = 0
    for i in range(n):
        nf += 1 if free[i] else 0
    cols = np.empty(nf, np.int64)
    c = 0
    for i in range(n):
        if free[i]:
            cols[c] = i
            c += 1
    r = np.empty(rows)
    rn = np.empty(rows)
    rv = np.empty(rows)
    Jm = np.empty((rows, n))
    J = np.empty((rows, nf))
    dummy = np.empty((rows, n))
    M = np.empty((nf, nf))
    dv = np.empty(nf)
    da = np.empty(nf)
    zv = np.empty(n)
    zn = np.empty(n)
    G = _residual(z, targets, branch, timing, timed, crank, cos_mu, scale, weight, r, dummy, False)
    cost = np.dot(r, r)
    lam = 1e-3
    before = cost
    for it in range(iterations):
        if cost <= done * done * (2 * k):
            break
        if it and it % stall == 0:  # a minimum that is not zero, or a crawl: stop
            if cost > 0.25 * before:
                break
            before = cost
        _residual(z, targets, branch, timing, timed, crank, cos_mu, scale, weight, rv, Jm, True)
        for j in range(nf):
            J[:, j] = Jm[:, cols[j]]
        A = J.T @ J
        g = J.T @ r
        D = np.empty(nf)
        for i in range(nf):
            D[i] = max(A[i, i], 1e-30)
        while True:
            M[:] = A
            for i in range(nf):
                M[i, i] += lam * D[i]
            ok = _solve(M, -g, dv)
            if ok:
                zv[:] = z
                for j in range(nf):
                    zv[cols[j]] += h * dv[j]
                _residual(zv, targets, branch, timing, timed, crank, cos_mu, scale, weight, rv,
                          dummy, False)  # fmt: skip
                rvv = (2.0 / h) * ((rv - r) / h - J @ dv)
                ok = _solve(M, -(J.T @ rvv), da)
            if ok:
                # the accelerated step while the bend is mild, else the plain one
                bent = math.sqrt(np.dot(da, da)) > alpha * math.sqrt(np.dot(dv, dv))
                zn[:] = z
                for j in range(nf):
                    zn[cols[j]] += dv[j] if bent else dv[j] + 0.5 * da[j]
                if _allowed(zn, max_length, box, use_box):
                    Gn = _residual(zn, targets, branch, timing, timed, crank, cos_mu, scale,
                                   weight, rn, dummy, False)  # fmt: skip
                    cn = np.dot(rn, rn)
                    if np.isfinite(cn) and cn < cost:
                        z[:] = zn
                        r[:] = rn
                        G = Gn
                        cost = cn
                        lam = max(lam / 3.0, 1e-15)
                        break
            lam *= 2.0
            if lam > 1e16:
                return G
    return G
