"""Batched small dense linear algebra of the vector-loop core.

:func:`lu_factor`/:func:`lu_solve` factor and solve many small matrices at once
(layout ``(n, n, N)``: one numpy operation per matrix entry, not a LAPACK call
per matrix); :class:`BlockFactor` factors a loop system's Jacobian group by
group along its block-triangular form (:mod:`machdyn.loops._compiled`), which
is cheaper (a six-bar's 5×5 becomes two 2×2 inverses and a 1×1) and gives each
group's determinant, the sign the solver keeps as that group's branch.
:func:`small_lu`/:func:`small_solve` are the plain-float twins for one pose.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["BlockFactor", "Factor", "block_factor", "lu_factor", "lu_solve", "lu_structure"]


@dataclass(frozen=True)
class Factor:
    """Batched LU factors with partial pivoting, layout ``(n, n, N)``.

    The matrix is first scaled, ``diag(r) · a · diag(s)``: by the given static
    scales (one pass), or equilibrated per sample (columns, then rows, to a
    largest entry of 1). ``swaps[k]`` is the (N,) row chosen as pivot of column
    ``k`` (a plain int when it is the same row for every sample); ``det`` the
    determinant of the original matrix and ``rcond`` the ratio of the smallest
    to the largest pivot magnitude of the scaled one (a cheap reciprocal
    condition estimate). For ``n = 2`` the scaled matrix is inverted in closed
    form instead (``inv``; ``lu`` is then the scaled matrix, ``swaps`` empty),
    with the same ``det`` and the ``rcond`` that partial pivoting would give.
    """

    lu: np.ndarray
    swaps: tuple[np.ndarray | int, ...]
    row_mul: np.ndarray  # (n, N) or (n, 1)
    col_mul: np.ndarray  # (n, N) or (n, 1)
    det: np.ndarray
    rcond: np.ndarray
    inv: np.ndarray | None = None  # (2, 2, N): inverse of the scaled 2x2 matrices

    @cached_property
    def interchanges(self) -> list[tuple[int, int, np.ndarray | None]]:
        """The row interchanges ``(k, i, mask)`` in order (mask None: every sample)."""
        out: list[tuple[int, int, np.ndarray | None]] = []
        for k, p in enumerate(self.swaps):
            if isinstance(p, int):
                if p != k:
                    out.append((k, p, None))
                continue
            for i in range(k + 1, len(self.swaps)):
                m = p == i
                if m.any():
                    out.append((k, i, m))
        return out


def lu_factor(
    a: np.ndarray, row_scale: np.ndarray | None = None, col_scale: np.ndarray | None = None
) -> Factor:
    """Factor a batch of small dense matrices ``a[:, :, i]`` (Gaussian elimination).

    Hand-vectorised over the batch: one numpy operation per matrix entry and
    column, so a million 2x2 or 4x4 systems cost a few dozen array operations
    (``np.linalg.solve`` on ``(N, n, n)`` pays a LAPACK call per matrix).

    Parameters
    ----------
    a : ndarray, shape (n, n, N)
        The matrices; not modified.
    row_scale, col_scale : ndarray, shape (n,), optional
        Static multipliers that make the entries O(1) (e.g. from the model's
        units). Without them every matrix is equilibrated from its entries,
        which costs several extra passes over the batch.

    Returns
    -------
    Factor

    Examples
    --------
    >>> a = np.array([[[2.0], [1.0]], [[4.0], [3.0]]])  # [[2, 1], [4, 3]]
    >>> f = lu_factor(a)
    >>> float(f.det[0])
    2.0
    >>> lu_solve(f, np.array([[3.0], [7.0]]))[:, 0].tolist()
    [1.0, 1.0]

    Non-finite entries (a sample already marked unsolved) give non-finite
    factors of that sample only (its ``det`` and ``rcond`` are NaN).
    """
    from .._validate import as_array

    a = as_array("a", a)
    if a.ndim != 3 or a.shape[0] != a.shape[1] or 0 in a.shape:
        raise InputError("a", f"must be a batch of square matrices, shape (n, n, N), got {a.shape}")
    scales = [
        _scales(f, v, a.shape[0]) for f, v in (("row_scale", row_scale), ("col_scale", col_scale))
    ]
    return _factor(a, *scales)


def _scales(field: str, value: Any, n: int) -> np.ndarray | None:
    """Static row or column multipliers of :func:`lu_factor`: None or (n,) positive, finite."""
    if value is None:
        return None
    from .._validate import finite_array

    s = finite_array(field, value)
    if s.shape != (n,) or not np.all(s > 0.0):
        raise InputError(field, f"must be {n} positive multipliers, got shape {s.shape}")
    return s


def _factor(
    a: np.ndarray,
    row_scale: np.ndarray | None = None,
    col_scale: np.ndarray | None = None,
    structure: tuple | None = None,
) -> Factor:
    """:func:`lu_factor`, skipping the entries known to be zero.

    ``structure`` is :func:`lu_structure` of the matrices' sparsity pattern
    (same result as without it, less work).
    """
    n = a.shape[0]
    if n == 0:
        ones = np.ones(a.shape[2])
        empty = np.ones((0, a.shape[2]))
        return Factor(lu=a.copy(), swaps=(), row_mul=empty, col_mul=empty, det=ones, rcond=ones)
    if row_scale is not None and col_scale is not None:
        row_mul = np.asarray(row_scale, dtype=float)[:, None]
        col_mul = np.asarray(col_scale, dtype=float)[:, None]
        lu = a * (row_mul * col_mul.T)[:, :, None]
    else:
        col_max = np.maximum(a.max(axis=0), -a.min(axis=0))
        col_max[col_max == 0.0] = 1.0
        col_mul = 1.0 / col_max
        lu = a * col_mul[None, :, :]
        row_max = np.maximum(lu.max(axis=1), -lu.min(axis=1))
        row_max[row_max == 0.0] = 1.0
        row_mul = 1.0 / row_max
        lu *= row_mul[:, None, :]
    if row_mul.shape[1] == 1:  # static scales: the determinant's factor is one number
        det: np.ndarray | float = 1.0 / math.prod(row_mul[:, 0].tolist() + col_mul[:, 0].tolist())
    else:
        det = 1.0 / (np.prod(row_mul, axis=0) * np.prod(col_mul, axis=0))
    if n == 2:
        return _factor_2x2(lu, row_mul, col_mul, det)
    return _eliminate(lu, row_mul, col_mul, det, structure)


def lu_structure(pattern: np.ndarray) -> tuple[tuple[tuple[int, ...], tuple[int, ...]], ...]:
    """Which rows can hold a pivot, and which need elimination, column by column.

    ``pattern`` (n, n) marks the entries that may be non-zero; the others are
    exactly zero in every sample (a vector-loop Jacobian is sparse: a loop's
    rows only touch the unknowns of its own vectors). The pattern is followed
    through partial pivoting (rows that may swap take the union of their
    patterns) and elimination (fill-in), so skipping the zeros changes nothing
    but the work: it gives the pivots and factors of the dense elimination.
    """
    s = np.array(pattern, dtype=bool)
    n = s.shape[0]
    out = []
    for k in range(n):
        cands = [i for i in range(k, n) if s[i, k]] or [k]
        group = sorted(set(cands) | {k})
        s[group] = s[group].any(axis=0)
        rows = tuple(i for i in range(k + 1, n) if s[i, k])
        for i in rows:
            s[i, k + 1 :] |= s[k, k + 1 :]
        out.append((tuple(cands), rows))
    return tuple(out)


def _eliminate(lu, row_mul, col_mul, det, structure) -> Factor:
    """Gaussian elimination with partial pivoting on the scaled batch ``lu`` (in place)."""
    n, n_samples = lu.shape[0], lu.shape[2]
    if structure is None:
        dense = tuple(range(n))
        structure = tuple((dense[k:], dense[k + 1 :]) for k in range(n))
    swaps: list[np.ndarray | int] = []
    piv_min = np.full(n_samples, np.inf)
    piv_max = np.zeros(n_samples)
    with np.errstate(divide="ignore", invalid="ignore"):
        for k, (cands, rows) in enumerate(structure):
            if len(cands) == 1:
                cand = np.abs(lu[cands[0], k])[None]
            elif cands[-1] - cands[0] == len(cands) - 1:
                cand = np.abs(lu[cands[0] : cands[-1] + 1, k])
            else:
                cand = np.abs(lu[list(cands), k])
            best = cand.max(axis=0) if len(cands) > 1 else cand[0]
            # Along a sweep the pivot row is nearly always the same in every sample: test
            # the first sample's choice on all before paying for a per-sample search.
            first = int(cand[:, 0].argmax()) if n_samples else 0
            if len(cands) == 1 or (cand[first] == best).all():
                p: np.ndarray | int = cands[first]
                if p != k:  # one interchange of whole rows
                    lu[[k, p]] = lu[[p, k]]
                    det = -det
            else:
                # The first largest row, as a strict ">" scan would pick (a where-chain from
                # the bottom: cheaper than argmax over a short axis).
                p = np.where(cand[-2] == best, cands[-2], cands[-1])
                for j in range(len(cands) - 3, -1, -1):
                    p = np.where(cand[j] == best, cands[j], p)
                if len(cands) > 4:
                    # Many candidate rows: one gather and one scatter instead of a where-swap
                    # per candidate (O(n) instead of O(n^2) row passes per column).
                    moved = p != k
                    cols = np.arange(n_samples)
                    top = lu[k].copy()
                    lu[k] = lu[p, :, cols].T
                    lu[p, :, cols] = top.T
                    det = np.where(moved, -det, det)
                else:
                    for i in cands:
                        if i == k:
                            continue
                        m = p == i
                        if m.any():
                            top = lu[k].copy()
                            lu[k] = np.where(m, lu[i], lu[k])
                            lu[i] = np.where(m, top, lu[i])
                            det = np.where(m, -det, det)
            swaps.append(p)
            pivot = lu[k, k]
            det = pivot * det
            np.minimum(piv_min, best, out=piv_min)
            np.maximum(piv_max, best, out=piv_max)
            if not rows:
                continue
            safe = np.where(pivot == 0.0, 1.0, pivot)
            if len(rows) == n - k - 1:  # dense below the pivot: one slab update
                factor = lu[k + 1 :, k] / safe
                lu[k + 1 :, k] = factor
                lu[k + 1 :, k + 1 :] -= factor[:, None] * lu[k, k + 1 :][None]
            else:
                for i in rows:
                    factor = lu[i, k] / safe
                    lu[i, k] = factor
                    lu[i, k + 1 :] -= factor * lu[k, k + 1 :]
    rcond = np.where(piv_max > 0.0, piv_min / np.where(piv_max > 0.0, piv_max, 1.0), 0.0)
    return Factor(lu=lu, swaps=tuple(swaps), row_mul=row_mul, col_mul=col_mul, det=det, rcond=rcond)


def _factor_2x2(lu: np.ndarray, row_mul: np.ndarray, col_mul: np.ndarray, det) -> Factor:
    """:func:`lu_factor` for 2x2 matrices: the closed-form inverse (a few array passes)."""
    s00, s01, s10, s11 = lu[0, 0], lu[0, 1], lu[1, 0], lu[1, 1]
    det_s = s00 * s11
    det_s -= s01 * s10
    inv = np.empty_like(lu)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        # Partial pivoting's pivots: the larger entry of column 0, then |det| / that one;
        # their ratio is |det| / first².
        first = np.maximum(np.abs(s00), np.abs(s10))
        ratio = np.abs(det_s) / (first * first)
        rcond = np.minimum(ratio, 1.0 / ratio)
        rcond[~(rcond >= 0.0)] = 0.0  # a zero column (0/0)
        r = 1.0 / det_s
        np.multiply(s11, r, out=inv[0, 0])
        np.multiply(s01, -r, out=inv[0, 1])
        np.multiply(s10, -r, out=inv[1, 0])
        np.multiply(s00, r, out=inv[1, 1])
    return Factor(
        lu=lu, swaps=(), row_mul=row_mul, col_mul=col_mul, det=det_s * det, rcond=rcond, inv=inv
    )


def lu_solve(f: Factor, b: np.ndarray) -> np.ndarray:
    """Solve ``a x = b`` for every sample with the factors of :func:`lu_factor`.

    Parameters
    ----------
    f : Factor
    b : ndarray, shape (n, N) or (n, m, N)

    Returns
    -------
    ndarray, the shape of ``b``

    Examples
    --------
    Two systems at once, ``[[0, 1], [1, 1]] x = [2, 3]`` (needs pivoting) and
    ``[[2, 0], [0, 4]] x = [2, 4]``:

    >>> a = np.array([[[0.0, 2.0], [1.0, 0.0]], [[1.0, 0.0], [1.0, 4.0]]])
    >>> lu_solve(lu_factor(a), np.array([[2.0, 2.0], [3.0, 4.0]])).T.tolist()
    [[1.0, 2.0], [1.0, 1.0]]
    """
    if not isinstance(f, Factor):
        raise InputError("f", f"must be the Factor lu_factor returns, got {type(f).__name__}")
    lu = f.lu
    n = lu.shape[0]
    if not isinstance(b, np.ndarray) or b.dtype.kind != "f" or b.ndim not in (2, 3):
        raise InputError("b", "must be a float array of shape (n, N) or (n, m, N)")
    if b.shape[0] != n or b.shape[-1] not in (lu.shape[-1], 1):
        raise InputError("b", f"shape {b.shape} does not fit the factors' {lu.shape}")
    x = b * (f.row_mul if b.ndim == 2 else f.row_mul[:, None, :])
    extra = () if b.ndim == 2 else (None,)
    if f.inv is not None:  # 2x2: a product with the inverse
        inv = f.inv[:, :, None] if b.ndim == 3 else f.inv
        out = np.empty_like(x)
        with np.errstate(invalid="ignore", over="ignore"):  # singular: inf * 0
            out[0] = inv[0, 0] * x[0] + inv[0, 1] * x[1]
            out[1] = inv[1, 0] * x[0] + inv[1, 1] * x[1]
        return out * (f.col_mul if b.ndim == 2 else f.col_mul[:, None, :])
    with np.errstate(divide="ignore", invalid="ignore"):
        for k, i, m in f.interchanges:  # P b
            if m is None:
                x[[k, i]] = x[[i, k]]
                continue
            m = m[extra]
            top = x[k].copy()
            x[k] = np.where(m, x[i], x[k])
            x[i] = np.where(m, top, x[i])
        for k in range(n):  # L y = P b
            for i in range(k + 1, n):
                x[i] -= lu[i, k][extra] * x[k]
        for k in range(n - 1, -1, -1):
            for j in range(k + 1, n):
                x[k] -= lu[k, j][extra] * x[j]
            x[k] /= lu[k, k][extra]
    return x * (f.col_mul if b.ndim == 2 else f.col_mul[:, None, :])


# --------------------------------------------------------------------------- by groups
@dataclass(frozen=True)
class BlockPlan:
    """How to factor ``J_q`` group by group (built once per model; internal).

    ``blocks[g]`` is ``(rows, cols, row_mul, col_mul, structure)`` of group g's
    diagonal block; ``coupling[g]`` the structural non-zeros ``(i, row, col)``
    left of it (local row i of the group, global row and column); ``parity``
    the sign of the row and column permutations into block-triangular form.
    """

    blocks: tuple[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple | None], ...]
    coupling: tuple[tuple[tuple[int, int, int], ...], ...]
    parity: float
    n: int


def block_plan(
    groups: list[tuple[tuple[int, ...], tuple[int, ...]]],
    pattern: np.ndarray,
    row_scale: np.ndarray,
    col_scale: np.ndarray,
    parity: float,
) -> BlockPlan:
    """A :class:`BlockPlan` for the groups ``(rows, cols)`` of a sparsity ``pattern``."""
    blocks, coupling, done = [], [], []
    for rows, cols in groups:
        r, q = np.array(rows), np.array(cols)
        sub = pattern[np.ix_(r, q)]
        structure = lu_structure(sub) if len(rows) > 2 else None
        blocks.append((r, q, row_scale[r][:, None], col_scale[q][:, None], structure))
        coupling.append(
            tuple(
                (i, int(row), int(col))
                for i, row in enumerate(rows)
                for col in done
                if pattern[row, col]
            )
        )
        done.extend(cols)
    return BlockPlan(tuple(blocks), tuple(coupling), parity, len(done))


@dataclass(frozen=True)
class BlockFactor:
    """``J_q`` factored group by group (see :func:`block_factor`).

    ``det`` and ``rcond`` play the roles of :class:`Factor`'s (``det`` is that of
    the whole matrix, ``rcond`` the smallest of the groups' pivot ratios);
    ``block_det``/``block_rcond`` (n_groups, N) are per group.
    """

    plan: BlockPlan
    parts: tuple[Factor | np.ndarray, ...]
    jac: np.ndarray
    det: np.ndarray
    rcond: np.ndarray
    block_det: np.ndarray
    block_rcond: np.ndarray

    def solve(self, b: np.ndarray) -> np.ndarray:
        """Solve ``J_q x = b`` (b: (n, N) or (n, m, N)), group by group."""
        x = np.empty_like(b)
        extra = () if b.ndim == 2 else (None,)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            for (rows, cols, *_), part, coupling in zip(
                self.plan.blocks, self.parts, self.plan.coupling, strict=True
            ):
                r = b[rows]
                for i, row, col in coupling:
                    r[i] -= self.jac[row, col][extra] * x[col]
                if isinstance(part, Factor):
                    x[cols] = lu_solve(part, r)
                else:  # a 1x1 group: the reciprocal
                    x[cols[0]] = r[0] * part[extra]
        return x


def block_factor(jac: np.ndarray, plan: BlockPlan) -> BlockFactor:
    """Factor ``jac`` (n, n, N) along a :class:`BlockPlan` (each group's block by LU)."""
    n_samples = jac.shape[2]
    parts: list[Factor | np.ndarray] = []
    block_det = np.empty((len(plan.blocks), n_samples))
    block_rcond = np.empty((len(plan.blocks), n_samples))
    with np.errstate(divide="ignore", invalid="ignore"):
        for g, (rows, cols, row_mul, col_mul, structure) in enumerate(plan.blocks):
            if len(rows) == 1:
                a = jac[rows[0], cols[0]]
                parts.append(1.0 / a)
                block_det[g] = a
                block_rcond[g] = np.where(a != 0.0, 1.0, 0.0)
                continue
            sub = jac[np.ix_(rows, cols)]
            fac = _factor(sub, row_mul[:, 0], col_mul[:, 0], structure)
            parts.append(fac)
            block_det[g] = fac.det
            block_rcond[g] = fac.rcond
    det = plan.parity * np.prod(block_det, axis=0) if len(plan.blocks) else np.ones(n_samples)
    rcond = block_rcond.min(axis=0) if len(plan.blocks) else np.ones(n_samples)
    return BlockFactor(plan, tuple(parts), jac, det, rcond, block_det, block_rcond)


def solve(fac: Factor | BlockFactor, b: np.ndarray) -> np.ndarray:
    """``lu_solve`` for either kind of factor."""
    return fac.solve(b) if isinstance(fac, BlockFactor) else lu_solve(fac, b)


# --------------------------------------------------------------------------- one pose
def small_lu(
    a: list[list[float]], row: list[float], col: list[float]
) -> tuple[list[list[float]], list[int], list[float], list[float], float, float]:
    """Plain-Python twin of :func:`lu_factor` for one small matrix (the sequential march).

    ``row``/``col`` are the static multipliers. Returns (lu, pivot rows, row
    multipliers, column multipliers, det, rcond).
    """
    n = len(a)
    lu = [[v * r * s for v, s in zip(ai, col, strict=True)] for ai, r in zip(a, row, strict=True)]
    det = 1.0 / math.prod(row + col)
    piv, lo, hi = [], math.inf, 0.0
    for k in range(n):
        p, best = k, abs(lu[k][k])
        for i in range(k + 1, n):  # the first largest, as lu_factor
            v = abs(lu[i][k])
            if v > best:
                p, best = i, v
        piv.append(p)
        if p != k:
            lu[k], lu[p] = lu[p], lu[k]
            det = -det
        rk = lu[k]
        pivot = rk[k]
        det *= pivot
        lo, hi = min(lo, best), max(hi, best)
        if pivot == 0.0:
            continue
        for i in range(k + 1, n):
            ri = lu[i]
            f = ri[k] / pivot
            ri[k] = f
            if f:
                for j in range(k + 1, n):
                    ri[j] -= f * rk[j]
    return lu, piv, row, col, det, (lo / hi if hi > 0.0 else 0.0)


def small_solve(fac: tuple, b: list[float]) -> list[float]:
    """Solve with the factors of :func:`small_lu`."""
    lu, piv, row, col = fac[:4]
    n = len(lu)
    x = [b[i] * row[i] for i in range(n)]
    for k in range(n):
        if piv[k] != k:
            x[k], x[piv[k]] = x[piv[k]], x[k]
    for k in range(n):
        for i in range(k + 1, n):
            x[i] -= lu[i][k] * x[k]
    for k in range(n - 1, -1, -1):
        for j in range(k + 1, n):
            x[k] -= lu[k][j] * x[j]
        x[k] = x[k] / lu[k][k] if lu[k][k] != 0.0 else math.nan
    return [x[j] * col[j] for j in range(n)]


class SmallBlocks:
    """:class:`BlockFactor` for one pose in plain floats (the sequential march).

    ``factor(jac)`` factors and ``solve(parts, jac, b)`` solves group by group.
    """

    def __init__(self, plan: BlockPlan) -> None:
        self.blocks = [
            (r.tolist(), q.tolist(), rm[:, 0].tolist(), cm[:, 0].tolist())
            for r, q, rm, cm, _ in plan.blocks
        ]
        self.coupling = [list(c) for c in plan.coupling]
        self.parity = plan.parity
        self.n = plan.n

    def factor(self, jac: list[list[float]]) -> tuple[list, float, float, list, list]:
        """``(parts, det, rcond, group dets, group rconds)`` of ``jac``'s unknown columns."""
        parts, dets, rconds = [], [], []
        for rows, cols, rm, cm in self.blocks:
            fac = small_lu([[jac[r][q] for q in cols] for r in rows], rm, cm)
            parts.append(fac)
            dets.append(fac[4])
            rconds.append(fac[5])
        return parts, self.parity * math.prod(dets), min(rconds, default=1.0), dets, rconds

    def solve(self, parts: list, jac: list[list[float]], b: list[float]) -> list[float]:
        """Solve ``J_q x = b`` with ``parts`` from :meth:`factor` (``jac``: the same J)."""
        x = [0.0] * self.n
        for (rows, cols, _, _), fac, coupling in zip(
            self.blocks, parts, self.coupling, strict=True
        ):
            r = [b[row] for row in rows]
            for i, row, col in coupling:
                r[i] -= jac[row][col] * x[col]
            for q, v in zip(cols, small_solve(fac, r), strict=True):
                x[q] = v
        return x
