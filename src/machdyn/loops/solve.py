"""Numeric core of the vector-loop solver: batched Newton, continuation, derivatives.

Everything works on a :class:`Compiled` system (plain index arrays built by
:class:`machdyn.loops.LoopSystem`) and on arrays laid out as
``(variable, sample)``: one row per variable, one column per pose, so every
operation is a numpy call over the whole batch. Python loops run only over
Newton iterations, over the few unknowns (Gaussian elimination) and over the
vectors of the model.

Equations (Norton, *Design of Machinery*, ch. 4 and 6; the notes' "vector loop
equation"): each loop ``Σ s_k d_k e^{jθ_k} = 0`` gives a real and an imaginary
row; each linear constraint ``Σ c_v x_v + c0 = 0`` gives one row. The Jacobian
uses ``∂(d e^{jθ})/∂θ = j d e^{jθ}`` and ``∂(d e^{jθ})/∂d = e^{jθ}``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

__all__ = ["lu_factor", "lu_solve"]  # the rest is the engine behind LoopSystem

#: Samples whose Jacobian has a (pivot-ratio) reciprocal condition below this are
#: flagged singular. Newton converges only linearly to a toggle (a double root) and
#: stops about sqrt(tol) ~ 1e-6 rad from it, where rcond is still ~1e-5; so the
#: threshold sits above that: poses within roughly 1e-4 rad of a toggle, where
#: velocities are amplified ~1e4 times, are reported as singular.
SINGULAR_RCOND = 1e-4

# Reason codes for per-sample flags (index into REASONS).
OK, NO_ASSEMBLY, SINGULAR, JUMP, LOST = 0, 1, 2, 3, 4
REASONS = (
    "",
    "cannot assemble: Newton-Raphson did not converge at this input",
    "singular Jacobian (toggle or dead point): derivatives undefined",
    "possible branch jump: solution far from the continuation prediction",
    "cannot assemble on the starting branch after an assembly gap",
)


@dataclass(frozen=True)
class Compiled:
    """Index form of a loop system (built by ``LoopSystem``; not user facing).

    Attributes
    ----------
    names : tuple of str
        All variables; rows of the state array ``X``.
    unknown, inputs : ndarray of int
        Indices of unknown and input variables in ``names``.
    length_const, angle_const : ndarray, shape (n_vec,)
        Constant length / angle of each vector (ignored where a variable).
    length_var, angle_var : ndarray of int, shape (n_vec,)
        Variable index of each vector's length / angle, or -1 when constant.
    loops : ndarray, shape (n_loop, n_vec)
        Signed coefficients of the vectors in each loop.
    con : ndarray, shape (n_con, n_var); con0 : ndarray, shape (n_con,)
        Linear constraints ``con @ X + con0 = 0``.
    points : ndarray, shape (n_point, n_vec)
        Signed coefficients of the vector chain of each point.
    scale : float
        Characteristic length (mean constant length) for relative tolerances.
    var_scale : ndarray, shape (n_var,)
        1 for angle variables, ``scale`` for length variables.
    """

    names: tuple[str, ...]
    unknown: np.ndarray
    inputs: np.ndarray
    length_const: np.ndarray
    angle_const: np.ndarray
    length_var: np.ndarray
    angle_var: np.ndarray
    loops: np.ndarray
    con: np.ndarray
    con0: np.ndarray
    points: np.ndarray
    scale: float
    var_scale: np.ndarray

    @property
    def n_eq(self) -> int:
        """Number of scalar equations."""
        return 2 * self.loops.shape[0] + self.con.shape[0]

    @cached_property
    def loop_terms(self) -> tuple[tuple[tuple[int, float], ...], ...]:
        """Per loop, the (vector index, sign) pairs with a non-zero sign."""
        return tuple(
            tuple((int(k), float(row[k])) for k in np.flatnonzero(row)) for row in self.loops
        )

    @cached_property
    def jq_scales(self) -> tuple[np.ndarray, np.ndarray]:
        """Static row and column multipliers that make ``J_q``'s entries O(1)."""
        return self.row_weight, self.var_scale[self.unknown]

    @cached_property
    def row_weight(self) -> np.ndarray:
        """Weights that make every residual row dimensionless (loop rows / scale)."""
        con_w = 1.0 / np.maximum.reduce(
            [np.ones(len(self.con0)), np.abs(self.con0), np.abs(self.con) @ self.var_scale]
        )
        return np.concatenate([np.full(2 * self.loops.shape[0], 1.0 / self.scale), con_w])

    @cached_property
    def jq_structure(self) -> tuple:
        """:func:`lu_structure` of ``J_q``'s sparsity (which unknowns each row touches)."""
        col = {int(v): i for i, v in enumerate(self.unknown)}
        pattern = np.zeros((self.n_eq, len(col)), dtype=bool)
        for l_idx, terms in enumerate(self.loop_terms):
            for k, _ in terms:
                for v in (int(self.angle_var[k]), int(self.length_var[k])):
                    if v in col:
                        pattern[2 * l_idx : 2 * l_idx + 2, col[v]] = True
        if self.con.shape[0]:
            pattern[2 * self.loops.shape[0] :] = self.con[:, self.unknown] != 0
        return lu_structure(pattern)

    @cached_property
    def unknown_row(self) -> dict[int, int]:
        """Row of each unknown (by variable index) in ``q``."""
        return {int(v): i for i, v in enumerate(self.unknown)}

    @cached_property
    def scalar(self) -> _Scalar:
        """The plain-float twin of the equations for one pose (built once)."""
        return _Scalar(self)


# --------------------------------------------------------------------------- linear algebra
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
    """
    return _factor(a, row_scale, col_scale)


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
    lu = f.lu
    n = lu.shape[0]
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


# --------------------------------------------------------------------------- equations
def _vector_terms(c: Compiled, x: np.ndarray) -> tuple[list, list, list]:
    """Length, cos and sin of every vector for the states ``x`` (n_var, N).

    Constant parts stay Python floats (broadcast for free); vectors sharing an
    angle variable share its trigonometry.
    """
    d, cos, sin = [], [], []
    trig: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    for k in range(len(c.length_const)):
        lv, av = int(c.length_var[k]), int(c.angle_var[k])
        d.append(x[lv] if lv >= 0 else float(c.length_const[k]))
        if av >= 0:
            if av not in trig:
                trig[av] = np.cos(x[av]), np.sin(x[av])
            cos.append(trig[av][0])
            sin.append(trig[av][1])
        else:
            cos.append(float(np.cos(c.angle_const[k])))
            sin.append(float(np.sin(c.angle_const[k])))
    return d, cos, sin


def _step_terms(
    c: Compiled, x: np.ndarray, terms: tuple[list, list, list], step: np.ndarray
) -> tuple[list, list, list]:
    """``_vector_terms`` after the unknowns moved by ``step`` (n_q, N), cheaply.

    Small angle changes rotate the known cos and sin (``cos(θ+δ) = cos θ cos δ −
    sin θ sin δ`` with 5th-order series for cos δ and sin δ, exact to rounding
    for ``|δ| ≤ 2e-3``), a few multiplications instead of two transcendental
    functions; larger ones are evaluated afresh.
    """
    d, cos, sin = (list(t) for t in terms)
    rotated: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    row = c.unknown_row
    for k in range(len(c.length_const)):
        lv, av = int(c.length_var[k]), int(c.angle_var[k])
        if lv >= 0:
            d[k] = x[lv]
        if av not in row:
            continue
        if av not in rotated:
            delta = step[row[av]]
            if np.abs(delta).max() <= 2e-3:
                d2 = delta * delta
                cd = 1.0 - d2 * (0.5 - d2 / 24.0)
                sd = delta * (1.0 - d2 * (1.0 / 6.0 - d2 / 120.0))
                rotated[av] = cos[k] * cd - sin[k] * sd, sin[k] * cd + cos[k] * sd
            else:
                rotated[av] = np.cos(x[av]), np.sin(x[av])
        cos[k], sin[k] = rotated[av]
    return d, cos, sin


def residual_and_jacobian(
    c: Compiled,
    x: np.ndarray,
    cols: np.ndarray | None = None,
    jacobian: bool = True,
    terms: tuple[list, list, list] | None = None,
) -> tuple[np.ndarray, np.ndarray | None]:
    """Residual ``F(x)`` and Jacobian ``∂F/∂x[cols]`` for a batch of states.

    Parameters
    ----------
    c : Compiled
    x : ndarray, shape (n_var, N)
    cols : ndarray of int, optional
        Variables to differentiate by (default: the unknowns).
    jacobian : bool
        Skip the Jacobian when False.
    terms : tuple, optional
        ``_vector_terms(c, x)`` when already computed.

    Returns
    -------
    F : ndarray, shape (n_eq, N)
    J : ndarray, shape (n_eq, len(cols), N) or None
    """
    cols = c.unknown if cols is None else cols
    n_samples = x.shape[1]
    d, cos, sin = _vector_terms(c, x) if terms is None else terms
    n_loop = c.loops.shape[0]
    f = np.empty((c.n_eq, n_samples))
    jac = np.zeros((c.n_eq, len(cols), n_samples)) if jacobian else None
    where = {int(v): i for i, v in enumerate(cols)}
    for l_idx, terms in enumerate(c.loop_terms):
        fx, fy = f[2 * l_idx], f[2 * l_idx + 1]
        fx[...] = 0.0
        fy[...] = 0.0
        for k, s in terms:
            sd = s * d[k]
            px, py = sd * cos[k], sd * sin[k]  # the term s d e^{jθ}, real and imaginary
            fx += px
            fy += py
            if jac is None:
                continue
            a_col = where.get(int(c.angle_var[k]))
            if a_col is not None:  # ∂/∂θ = j s d e^{jθ}
                jac[2 * l_idx, a_col] -= py
                jac[2 * l_idx + 1, a_col] += px
            l_col = where.get(int(c.length_var[k]))
            if l_col is not None:  # ∂/∂d = s e^{jθ}
                jac[2 * l_idx, l_col] += s * cos[k]
                jac[2 * l_idx + 1, l_col] += s * sin[k]
    if c.con.shape[0]:
        f[2 * n_loop :] = c.con @ x + c.con0[:, None]
        if jac is not None:
            jac[2 * n_loop :] = c.con[:, cols][:, :, None]
    return f, jac


# --------------------------------------------------------------------------- Newton
@dataclass(frozen=True)
class NewtonResult:
    """Outcome of a batched Newton solve (internal).

    ``tan`` (dq/du), ``det`` and ``rcond`` are those of ``J_q`` at the converged
    solution (NaN / 0 where not converged).
    """

    q: np.ndarray  # (n_q, N) unknowns
    converged: np.ndarray  # (N,) bool
    residual: np.ndarray  # (N,) max weighted residual
    tan: np.ndarray  # (n_q, n_u, N)
    det: np.ndarray  # (N,)
    rcond: np.ndarray  # (N,)


def newton(
    c: Compiled,
    q0: np.ndarray,
    u: np.ndarray,
    max_iter: int = 30,
    tol: float = 1e-12,
    max_step: float = 0.5,
    lazy_first: bool = False,
) -> NewtonResult:
    """Batched Newton–Raphson for the unknowns ``q`` at inputs ``u``.

    Samples leave the active set as soon as their weighted residual is below
    ``tol``; steps are shortened so that no angle moves more than ``max_step``
    radians (and no length more than ``max_step`` times the model's scale) per
    iteration, which keeps a poor guess from leaping to another circuit. Each
    iteration evaluates ``F``, ``J_q`` and ``J_u`` once and factors ``J_q``
    once: the same solve gives the Newton step of the active samples and the
    continuation tangent ``dq/du = −J_q⁻¹ J_u`` of the ones that just converged.

    Parameters
    ----------
    c : Compiled
    q0 : ndarray, shape (n_q, N)
        Starting values of the unknowns.
    u : ndarray, shape (n_u, N)
        Input values.
    lazy_first : bool
        Check the starting values by their residual alone: samples that already
        satisfy the tolerance are accepted without a Jacobian (then ``tan``,
        ``det`` and ``rcond`` are NaN for them).
    """
    n_samples = q0.shape[1]
    nq, nu = len(c.unknown), len(c.inputs)
    x = np.empty((len(c.names), n_samples))
    x[c.inputs] = u
    x[c.unknown] = q0
    weight = c.row_weight[:, None]
    inv_scale = (1.0 / c.var_scale[c.unknown])[:, None]
    cols = np.concatenate([c.unknown, c.inputs])
    converged = np.zeros(n_samples, dtype=bool)
    resid = np.full(n_samples, np.inf)
    tan = np.full((nq, nu, n_samples), np.nan)
    det = np.zeros(n_samples)
    rcond = np.zeros(n_samples)
    active = np.arange(n_samples)
    xa = x
    for it in range(max_iter + 1):
        if lazy_first and it == 0:
            # Residual only: samples already converged need no Jacobian (their tangent,
            # det and rcond stay NaN: "not computed").
            f, _ = residual_and_jacobian(c, xa, cols, jacobian=False)
            done = np.abs(f * weight).max(axis=0) <= tol
            resid[active] = np.abs(f * weight).max(axis=0)
            if done.any():
                idx = active[done]
                converged[idx] = True
                x[:, idx] = xa[:, done]
                det[idx] = np.nan
                rcond[idx] = np.nan
                active, xa = active[~done], xa[:, ~done]
            if active.size == 0:
                break
            f, jac = residual_and_jacobian(c, xa, cols)
            done = np.zeros(active.size, dtype=bool)
        else:
            f, jac = residual_and_jacobian(c, xa, cols)
            r = np.abs(f * weight).max(axis=0)
            resid[active] = r
            done = r <= tol
        fac = _factor(jac[:, :nq], *c.jq_scales, c.jq_structure)
        rhs = np.concatenate([-f[:, None, :], -jac[:, nq:]], axis=1)
        sol = lu_solve(fac, rhs)
        if done.any():
            idx = active[done]
            converged[idx] = True
            x[:, idx] = xa[:, done]
            tan[:, :, idx] = sol[:, 1:, done]
            det[idx] = fac.det[done]
            rcond[idx] = fac.rcond[done]
            keep = ~done
            active, xa, sol = active[keep], xa[:, keep], sol[:, :, keep]
        if active.size == 0 or it == max_iter:
            break
        step = sol[:, 0]
        with np.errstate(invalid="ignore"):
            size = np.abs(step * inv_scale).max(axis=0)
            shrink = np.where(size > max_step, max_step / size, 1.0)
        step = np.where(np.isfinite(step), step * shrink, 0.0)
        xa[c.unknown] += step
    if active.size:
        x[:, active] = xa
    return NewtonResult(
        q=x[c.unknown], converged=converged, residual=resid, tan=tan, det=det, rcond=rcond
    )


def _small_lu(
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


def _small_solve(fac: tuple, b: list[float]) -> list[float]:
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


class _Scalar:
    """``F``, ``J`` and Newton for a single pose in plain Python floats.

    The sequential continuation march solves one pose at a time; there numpy's
    per-call overhead dominates, so this twin of :func:`residual_and_jacobian`
    and :func:`newton` (same equations, step limiting and tolerances) is several
    times faster. Everything static (which column a vector's angle or length
    feeds, the trigonometry of constant angles) is worked out once per model.
    """

    def __init__(self, c: Compiled) -> None:
        self.unknown = [int(v) for v in c.unknown]
        self.inputs = [int(v) for v in c.inputs]
        self.nq, self.nu, self.n_var = len(self.unknown), len(self.inputs), len(c.names)
        cols = self.unknown + self.inputs
        where = {v: i for i, v in enumerate(cols)}
        self.loop_terms = [
            [
                (
                    s,
                    int(c.length_var[k]),
                    int(c.angle_var[k]),
                    float(c.length_const[k]),
                    math.cos(c.angle_const[k]),
                    math.sin(c.angle_const[k]),
                    where.get(int(c.angle_var[k]), -1),
                    where.get(int(c.length_var[k]), -1),
                )
                for k, s in terms
            ]
            for terms in c.loop_terms
        ]
        self.con = [
            (row.tolist(), float(c0), [float(row[v]) for v in cols])
            for row, c0 in zip(c.con, c.con0, strict=True)
        ]
        self.n_eq = c.n_eq
        self.weight = c.row_weight.tolist()
        self.scale = [float(c.var_scale[i]) for i in self.unknown]
        self.u_scale = [float(c.var_scale[i]) for i in self.inputs]
        self.row_mul, self.col_mul = (v.tolist() for v in c.jq_scales)

    def state(self, q: list[float], u: list[float]) -> list[float]:
        """All variables from the unknowns ``q`` and inputs ``u``."""
        x = [0.0] * self.n_var
        for i, v in zip(self.unknown, q, strict=True):
            x[i] = v
        for i, v in zip(self.inputs, u, strict=True):
            x[i] = v
        return x

    def equations(self, x: list[float]) -> tuple[list[float], list[list[float]]]:
        """Residual and Jacobian (columns: unknowns, then inputs) at the state ``x``."""
        f = [0.0] * self.n_eq
        jac = [[0.0] * (self.nq + self.nu) for _ in range(self.n_eq)]
        for l_idx, terms in enumerate(self.loop_terms):
            fx = fy = 0.0
            jx, jy = jac[2 * l_idx], jac[2 * l_idx + 1]
            for sgn, lv, av, d, co, si, a_col, l_col in terms:
                if lv >= 0:
                    d = x[lv]
                if av >= 0:
                    co, si = math.cos(x[av]), math.sin(x[av])
                sd = sgn * d
                fx += sd * co
                fy += sd * si
                if a_col >= 0:
                    jx[a_col] -= sd * si
                    jy[a_col] += sd * co
                if l_col >= 0:
                    jx[l_col] += sgn * co
                    jy[l_col] += sgn * si
            f[2 * l_idx], f[2 * l_idx + 1] = fx, fy
        for r, (coefs, c0, jrow) in enumerate(self.con, start=2 * len(self.loop_terms)):
            f[r] = sum(a * b for a, b in zip(coefs, x, strict=True)) + c0
            jac[r] = list(jrow)
        return f, jac

    def newton(
        self,
        q0: list[float],
        u: list[float],
        max_iter: int,
        tol: float,
        max_step: float,
        step_tol: float = 0.0,
    ) -> tuple[list[float], bool, float, tuple | None, list[list[float]] | None]:
        """Newton–Raphson from ``q0``: (q, converged, residual, LU of J_q, J) at the end.

        With ``step_tol`` > 0 it also stops after a full Newton step no larger than
        ``step_tol`` (scaled): the error left is of the order of its square, and
        residual, LU and J are those of the last evaluation, one step back (the
        caller verifies the pose later; this saves the confirming evaluation).
        """
        nq = self.nq
        x = self.state(q0, u)
        resid = math.inf
        for it in range(max_iter + 1):
            f, jac = self.equations(x)
            resid = max((abs(fi * w) for fi, w in zip(f, self.weight, strict=True)), default=0.0)
            fac = _small_lu([r[:nq] for r in jac], self.row_mul, self.col_mul)
            if resid <= tol:
                return [x[i] for i in self.unknown], True, resid, fac, jac
            if it == max_iter:
                break
            step = _small_solve(fac, [-v for v in f])
            if not all(math.isfinite(v) for v in step):
                break
            size = max((abs(v) / sc for v, sc in zip(step, self.scale, strict=True)), default=0.0)
            shrink = max_step / size if size > max_step else 1.0
            for i, v in zip(self.unknown, step, strict=True):
                x[i] += v * shrink
            if size <= step_tol:
                return [x[i] for i in self.unknown], True, resid, fac, jac
        return [x[i] for i in self.unknown], False, resid, None, None

    def tangent(self, fac: tuple, jac: list[list[float]]) -> list[list[float]]:
        """``dq/du = −J_q⁻¹ J_u`` as rows per unknown, columns per input."""
        nq = self.nq
        cols = [_small_solve(fac, [-r[nq + m] for r in jac]) for m in range(self.nu)]
        return [[cols[m][i] for m in range(self.nu)] for i in range(nq)]


def newton_one(
    c: Compiled,
    q0: np.ndarray,
    u: np.ndarray,
    max_iter: int = 30,
    tol: float = 1e-12,
    max_step: float = 0.5,
) -> NewtonResult:
    """:func:`newton` for a single sample (columns ``[:, :1]``) in plain Python floats."""
    ks = c.scalar
    nq, nu = ks.nq, ks.nu
    q, ok, resid, fac, jac = ks.newton(
        [float(v) for v in q0[:, 0]], [float(v) for v in u[:, 0]], max_iter, tol, max_step
    )
    if ok:
        return NewtonResult(
            q=np.array(q).reshape(nq, 1),
            converged=np.ones(1, dtype=bool),
            residual=np.array([resid]),
            tan=np.array(ks.tangent(fac, jac)).reshape(nq, nu, 1),
            det=np.array([fac[4]]),
            rcond=np.array([fac[5]]),
        )
    return NewtonResult(
        q=np.array(q).reshape(nq, 1),
        converged=np.zeros(1, dtype=bool),
        residual=np.array([resid]),
        tan=np.full((nq, nu, 1), np.nan),
        det=np.zeros(1),
        rcond=np.zeros(1),
    )


# --------------------------------------------------------------------------- continuation
@dataclass(frozen=True)
class Positions:
    """Positions of the unknowns with per-sample codes (internal)."""

    q: np.ndarray  # (n_q, N)
    code: np.ndarray  # (N,) int8 reason codes
    residual: np.ndarray  # (N,)
    det: np.ndarray  # (N,)
    rcond: np.ndarray  # (N,)
    #: ``(terms, jac, factor)`` at exactly these positions when every sample came from
    #: the fast path: the derivative stage reuses them instead of recomputing.
    reuse: tuple | None = None


def _accept(
    c: Compiled,
    res: NewtonResult,
    pred: np.ndarray,
    du: np.ndarray,
    det_ref: np.ndarray,
    rc_ref: np.ndarray,
    sing_tol: float,
    q_from: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Continuation checks; returns (accepted, jump) masks.

    A converged sample is a *jump* when ``det J_q`` changed sign from its
    reference neighbour while neither is near a toggle, or when it lies farther
    from its prediction than half the (scaled) step (unless it sits at a toggle,
    where the branches meet): on one branch the
    prediction error is O(step²), a jump to another circuit is O(1). The step
    counts the input step and, when ``q_from`` (the pose predicted from) is
    given, the predicted motion of the unknowns: next to a rocker's limit
    ``dq/du`` is unbounded and a pose on the right branch lies many input steps
    from the prediction.
    """
    near_sing = ~(res.rcond >= 10 * sing_tol) | ~(rc_ref >= 10 * sing_tol)  # NaN: unknown
    same_side = (np.sign(res.det) == np.sign(det_ref)) | near_sing
    scale = c.var_scale[c.unknown][:, None]
    step = du
    if q_from is not None:
        moved = np.abs((pred - q_from) / scale).max(axis=0)
        step = du + np.where(np.isfinite(moved), moved, 0.0)
    far = np.abs((res.q - pred) / scale).max(axis=0) > 0.5 * step + 1e-9
    # At a singular pose (a toggle) the two branches meet, so it belongs to both: the
    # prediction's error is unbounded there, but the pose is no jump.
    at_toggle = res.rcond < sing_tol
    jump = res.converged & (~same_side | far) & ~at_toggle
    return res.converged & ~jump, jump


class _Store:
    """Per-sample arrays filled by the continuation (internal)."""

    def __init__(self, n_q: int, n_u: int, n: int, sing_tol: float) -> None:
        self.q = np.full((n_q, n), np.nan)
        self.code = np.full(n, NO_ASSEMBLY, dtype=np.int8)
        self.resid = np.full(n, np.inf)
        self.tan = np.full((n_q, n_u, n), np.nan)
        self.det = np.zeros(n)
        self.rc = np.zeros(n)
        self.sing_tol = sing_tol

    def put(self, idx, res: NewtonResult, sel=slice(None)) -> None:
        self.q[:, idx] = res.q[:, sel]
        self.tan[:, :, idx] = res.tan[:, :, sel]
        self.det[idx] = res.det[sel]
        self.rc[idx] = res.rcond[sel]
        self.resid[idx] = res.residual[sel]
        self.code[idx] = np.where(res.rcond[sel] < self.sing_tol, SINGULAR, OK)

    def good(self) -> np.ndarray:
        return (self.code == OK) | (self.code == SINGULAR)

    def one(self, i: int) -> NewtonResult:
        sl = slice(i, i + 1)
        return NewtonResult(
            q=self.q[:, sl],
            converged=np.ones(1, bool),
            residual=self.resid[sl],
            tan=self.tan[:, :, sl],
            det=self.det[sl],
            rcond=self.rc[sl],
        )


def solve_positions(
    c: Compiled,
    u: np.ndarray,
    guess: np.ndarray,
    continuation: bool,
    max_step: float = 0.4,
    tol: float = 1e-12,
    max_iter: int = 50,
    sing_tol: float = SINGULAR_RCOND,
    fast: bool = True,
) -> Positions:
    """Positions of the unknowns for inputs ``u`` (n_u, N).

    With ``continuation=False`` every sample starts from ``guess`` (shape
    (n_q, 1) or (n_q, N)). With ``continuation=True`` the samples are an ordered
    sweep: a coarse subsample (steps of at most ``max_step`` in input space,
    radians for angles, model scale for lengths) is marched sequentially from
    the guess with a tangent predictor and step halving; the samples in between
    are then filled in doubling waves, each a single batched Newton solve
    predicted from the already solved neighbours. Every solution is verified
    (:func:`_accept`); a failed verification is re-solved with smaller steps or
    flagged. Straight, evenly stepped sweeps first try :func:`_sweep_fast`
    (unless ``fast`` is False); if only some of its samples fail, the stretch
    holding them is re-solved this careful way (:func:`_patch`).
    """
    n_q, n_u, n_samples = guess.shape[0], u.shape[0], u.shape[1]
    if n_q == 0:  # every variable driven (an open chain): nothing to solve
        ones, zeros = np.ones(n_samples), np.zeros(n_samples)
        return Positions(np.empty((0, n_samples)), np.zeros(n_samples, np.int8), zeros, ones, ones)
    if fast and continuation and 3 <= n_samples <= FAST_MAX_SAMPLES and n_u:
        quick = _sweep_fast(c, u, guess, max_step, tol, max_iter, sing_tol)
        if quick is not None and (quick.code == OK).all():
            return quick
        if quick is not None:  # the march held; only some samples of the fill failed
            careful = {"max_step": max_step, "tol": tol, "max_iter": max_iter}
            patched = _patch(c, u, guess, quick, sing_tol=sing_tol, **careful)
            if patched is not None:
                return patched
    if not continuation or n_samples == 1:
        q0 = np.broadcast_to(guess, (n_q, n_samples))
        res = newton(c, q0, u, max_iter=max_iter, tol=tol)
        code = np.where(res.converged, OK, NO_ASSEMBLY)
        code = np.where(res.converged & (res.rcond < sing_tol), SINGULAR, code).astype(np.int8)
        q = np.where(res.converged, res.q, np.nan)
        return Positions(q, code, res.residual, res.det, res.rcond)

    u_scale = c.var_scale[c.inputs][:, None]
    steps = np.abs(np.diff(u, axis=1) / u_scale).max(axis=0)
    # Coarse stride from the typical step (a few big jumps in a sweep are bridged by the
    # march's step halving rather than making every sample sequential).
    typical = float(np.median(steps)) if steps.size else 0.0
    stride = 1
    while stride * 2 * typical <= max_step and stride * 2 < n_samples:
        stride *= 2
    coarse = np.arange(0, n_samples, stride)
    if coarse[-1] != n_samples - 1:  # march to the end too: a fill past the last coarse
        coarse = np.append(coarse, n_samples - 1)  # sample could only extrapolate
    st = _Store(n_q, n_u, n_samples, sing_tol)
    march = _March(c, tol, sing_tol)
    g0 = guess[:, :1]

    # 1. The first coarse sample from the guess, then a sequential march.
    anchor, u_anchor = None, None
    after_gap = False
    for idx in coarse:
        u_b = u[:, idx : idx + 1]
        if anchor is None:
            trial = newton_one(c, g0, u_b, max_iter=max_iter, tol=tol)
            at_toggle = trial.converged[0] and trial.rcond[0] < 10 * sing_tol
            if idx == 0 and n_samples > 2 and at_toggle:  # (the fast march refuses this too)
                options = {"max_step": max_step, "tol": tol, "max_iter": max_iter, "fast": fast}
                split = _from_a_toggle(c, u, guess, sing_tol, **options)
                if split is not None:
                    return split
            if trial.converged[0]:
                anchor, u_anchor = trial, u_b
                st.put(np.array([idx]), trial)
            continue
        reached = march.to(anchor, u_anchor, u_b, restart=after_gap, guess=g0)
        if reached is None:
            after_gap = True
            continue
        if isinstance(reached, str):  # "lost": only the other branch after a gap
            st.code[idx] = LOST
            continue
        anchor, u_anchor, after_gap = reached, u_b, False
        st.put(np.array([idx]), reached)

    # 2. Fill the rest in doubling waves.
    half = stride // 2
    while half >= 1:
        new = np.arange(half, n_samples, 2 * half)
        if new.size:
            _fill(c, new, half, u, st, tol, march)
        half //= 2
    return Positions(st.q, st.code, st.resid, st.det, st.rc)


#: Sweeps up to this many samples try :func:`_sweep_fast` first. It was measured
#: faster than the doubling waves at every size tried (3.6e3 to 1e6 samples: ~3x
#: at 3,600, ~1.5-2x at 10⁶), but when its fill fails a check the whole sweep is
#: redone by the careful path, so a hard sweep costs up to ~2x; the cap bounds
#: that waste (and the fill's memory) for huge sweeps.
FAST_MAX_SAMPLES = 2_000_000
#: The fast march stops Newton after a step this small (scaled): the pose is then
#: within ~1e-10 and is polished, and verified, with every other sample in the fill.
MARCH_STEP_TOL = 1e-5
#: Corrector steps of the fast fill (from a cubic Hermite prediction whose error
#: is O(h⁴) for a coarse step h ≤ max_step, 2–3 suffice).
FAST_ITER = 5


def _from_a_toggle(
    c: Compiled,
    u: np.ndarray,
    guess: np.ndarray,
    sing_tol: float,
    *,
    max_step: float,
    tol: float,
    max_iter: int,
    fast: bool,
) -> Positions | None:
    """A sweep whose first pose (from the guess) is at a toggle: march from elsewhere.

    At a toggle the branches meet, so a march that starts there may go on along
    either. The sweep is anchored instead at the sample whose well-conditioned
    pose lies nearest the guess, and marched from there to both ends. Returns
    None when nothing in the sweep is well conditioned.
    """
    every = newton(c, np.broadcast_to(guess[:, :1], (guess.shape[0], u.shape[1])), u, max_iter, tol)
    usable = every.converged & (every.rcond >= 10 * sing_tol)
    if not usable.any():
        return None
    scale = c.var_scale[c.unknown][:, None]
    distance = np.abs((every.q - guess[:, :1]) / scale).max(axis=0)
    k = int(np.argmin(np.where(usable, distance, np.inf)))
    options = {"max_step": max_step, "tol": tol, "max_iter": max_iter, "sing_tol": sing_tol}
    ahead = solve_positions(c, u[:, k:], every.q[:, k : k + 1], True, fast=fast, **options)
    back = solve_positions(c, u[:, k::-1], every.q[:, k : k + 1], True, fast=fast, **options)

    def joined(name: str) -> np.ndarray:
        before = getattr(back, name)[..., :0:-1]  # samples k-1 … 0, put back in order
        return np.concatenate([before, getattr(ahead, name)], axis=-1)

    return Positions(*(joined(name) for name in ("q", "code", "residual", "det", "rcond")))


def _sweep_fast(
    c: Compiled,
    u: np.ndarray,
    guess: np.ndarray,
    max_step: float,
    tol: float,
    max_iter: int,
    sing_tol: float,
) -> Positions | None:
    """Continuation for a short, evenly stepped sweep with few numpy calls.

    A sequential march in plain floats over coarse samples at most ``max_step``
    apart (tangent predictor, Newton corrector, the checks of :func:`_accept`),
    then ONE batched fill of all samples: a cubic Hermite prediction from the
    coarse poses and tangents, a few Newton iterations over the whole batch, and
    a vectorised check of every sample (converged, well conditioned, on the side
    of det J = 0 of both coarse neighbours, within a tenth of the input step of
    its prediction). Returns None, leaving the sweep to the careful path of
    :func:`solve_positions`, for an uneven sweep or a coarse step that fails;
    when only samples of the fill fail (near a toggle, a check), they are
    returned coded NO_ASSEMBLY for :func:`_patch` to re-solve carefully.
    "Evenly stepped" means equal steps along a straight line in input space
    (``np.linspace`` of every input), so that a sample's fraction of a coarse
    interval by index is its fraction by input.
    """
    n = u.shape[1]
    u_scale = c.var_scale[c.inputs][:, None]
    du = np.diff(u, axis=1) / u_scale
    biggest = float(np.abs(du).max())
    if not (0.0 < biggest < np.inf):
        return None
    if np.abs(np.diff(du, axis=1)).max(initial=0.0) > 1e-6 * biggest:
        return None  # not a straight sweep at constant steps (the fill interpolates by index)
    stride = int(max_step / biggest)
    if stride < 2:
        return None
    coarse = np.arange(0, n, stride)
    if coarse[-1] != n - 1:
        coarse = np.append(coarse, n - 1)

    # 1. The sequential march in plain floats.
    well = 10.0 * sing_tol
    u_c = u[:, coarse].T.tolist()
    march = _march_fast(c.scalar, guess[:, 0].tolist(), u_c, tol, max_iter, well)
    if march is None:
        return None
    q_c, t_c, det_c = march

    # 2. One batched fill: cubic Hermite between the coarse neighbours, as a polynomial
    #    per coarse interval (Horner in the interval fraction t).
    q_c_arr = np.array(q_c).T  # (nq, n_coarse)
    det_c_arr = np.array(det_c)
    du_c = np.diff(u[:, coarse], axis=1)  # (nu, n_coarse - 1)
    t_c_arr = np.array(t_c)  # (n_coarse, nq, nu)
    m_l = np.einsum("jqu,uj->qj", t_c_arr[:-1], du_c)
    m_r = np.einsum("jqu,uj->qj", t_c_arr[1:], du_c)
    dq = np.diff(q_c_arr, axis=1)
    coef = np.stack([m_l + m_r - 2.0 * dq, 3.0 * dq - 2.0 * m_l - m_r, m_l, q_c_arr[:, :-1]])
    counts = np.diff(coarse)  # samples per interval; the last one also takes sample n - 1
    counts[-1] += 1
    # Even steps: the fraction of the interval by index is the fraction by input.
    t = np.repeat(1.0 / np.diff(coarse), counts) * (np.arange(n) - np.repeat(coarse[:-1], counts))
    a3, a2, a1, a0 = np.repeat(coef, counts, axis=2)
    pred = a3 * t
    pred += a2
    pred *= t
    pred += a1
    pred *= t
    pred += a0
    span = np.repeat(np.abs(du_c / u_scale).max(axis=0), counts)  # scaled interval length

    x = np.empty((len(c.names), n))
    x[c.inputs] = u
    x[c.unknown] = pred
    cols = np.concatenate([c.unknown, c.inputs])
    nq = len(c.unknown)
    weight = c.row_weight[:, None]
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        # Newton from the prediction, then chord steps (the first factor kept: after one
        # step the error is ~e0², and each chord step multiplies it by ~e0, the Hermite
        # error): one Jacobian and factor at the start, one more at the solution.
        terms = _vector_terms(c, x)
        f, jac = residual_and_jacobian(c, x, cols, terms=terms)
        fac = _factor(jac[:, :nq], *c.jq_scales, c.jq_structure)
        fresh = True
        for _ in range(FAST_ITER):
            r = np.abs(f * weight).max(axis=0)
            if r.max() <= tol:
                break
            step = lu_solve(fac, f)
            step *= -1.0
            x[c.unknown] += step
            terms = _step_terms(c, x, terms, step)
            f, _ = residual_and_jacobian(c, x, cols, jacobian=False, terms=terms)
            fresh = False
        else:
            r = np.abs(f * weight).max(axis=0)
        if not fresh:  # det, rcond and the derivative stage need J at the solution
            f, jac = residual_and_jacobian(c, x, cols, terms=terms)
            fac = _factor(jac[:, :nq], *c.jq_scales, c.jq_structure)
        q = x[c.unknown]
        du = span * np.maximum(t, 1.0 - t)
        far = np.abs((q - pred) / c.var_scale[c.unknown][:, None]).max(axis=0)
        good = (
            (r <= tol)
            & (fac.rcond >= well)
            & (np.sign(fac.det) == np.repeat(np.sign(det_c_arr[:-1]), counts))
            & (np.sign(fac.det) == np.repeat(np.sign(det_c_arr[1:]), counts))
            & (far <= 0.1 * du + 1e-7)  # (+: the march's poses are polished here)
        )
    code = np.where(good, OK, NO_ASSEMBLY).astype(np.int8)
    if good.all():
        return Positions(q, code, r, fac.det, fac.rcond, reuse=(terms, jac, fac))
    return Positions(q, code, r, fac.det, fac.rcond)  # to be patched by the careful path


def _patch(
    c: Compiled, u: np.ndarray, guess: np.ndarray, fast: Positions, **careful
) -> Positions | None:
    """Re-solve the stretch of a fast sweep that holds its failed samples, carefully.

    The span runs from the last accepted sample before the first failure to the
    first accepted one after the last failure; the careful path marches it from
    the accepted pose (the guess if the sweep's first sample failed). Its end
    must agree with the fast pose there (the same branch), else None.
    """
    n = u.shape[1]
    bad = np.flatnonzero(fast.code != OK)
    lo, hi = max(int(bad[0]) - 1, 0), min(int(bad[-1]) + 1, n - 1)
    start = fast.q[:, lo : lo + 1] if fast.code[lo] == OK else guess[:, :1]
    sub = solve_positions(c, u[:, lo : hi + 1], start, True, fast=False, **careful)
    if hi < n - 1 and not (
        sub.code[-1] == OK
        and np.abs((sub.q[:, -1] - fast.q[:, hi]) / c.var_scale[c.unknown]).max() <= 1e-8
    ):
        return None
    span = slice(lo, hi + 1)
    q, code = fast.q.copy(), fast.code.copy()
    residual, det, rcond = fast.residual.copy(), fast.det.copy(), fast.rcond.copy()
    q[:, span], code[span], residual[span] = sub.q, sub.code, sub.residual
    det[span], rcond[span] = sub.det, sub.rcond
    return Positions(q, code, residual, det, rcond)


def _march_fast(
    ks: _Scalar, guess: list[float], u_c: list[list[float]], tol: float, max_iter: int, well: float
) -> tuple[list, list, list] | None:
    """The coarse march of :func:`_sweep_fast`: poses, tangents and det J, or None.

    The first pose from the guess, then each from a prediction (the tangent for
    the first step, afterwards the cubic Hermite through the last two poses and
    tangents, extrapolated) and Newton. Any step that does not converge, comes
    near a toggle, changes the sign of det J or lands farther than half the
    input step from its prediction (the checks of :func:`_accept`) gives None.
    """
    q, ok, _, fac, jac = ks.newton(guess, u_c[0], max_iter, tol, 0.5)
    if not ok or not fac[5] >= well:
        return None
    tan = ks.tangent(fac, jac)
    q_c, t_c, det_c = [q], [tan], [fac[4]]
    rng_q = range(ks.nq)
    m0: list[float] = []  # the last tangent times the last step
    du_prev = 0.0
    for j in range(1, len(u_c)):
        du_vec = [b - a for a, b in zip(u_c[j - 1], u_c[j], strict=True)]
        du = max(abs(v) / sc for v, sc in zip(du_vec, ks.u_scale, strict=True))
        m1 = [sum(t * v for t, v in zip(tan[i], du_vec, strict=True)) for i in rng_q]
        if j == 1:
            pred = [a + b for a, b in zip(q, m1, strict=True)]
        else:  # Hermite basis on the last step, at tau = 1 + du / du_prev
            tau = 1.0 + du / du_prev
            h00, h10 = (2 * tau - 3) * tau * tau + 1, ((tau - 2) * tau + 1) * tau
            h01, h11 = (3 - 2 * tau) * tau * tau, (tau - 1) * tau * tau
            h11 *= du_prev / du  # m1 runs along this step, the cubic's along the last
            pred = [
                h00 * a + h01 * b + h10 * ma + h11 * mb
                for a, b, ma, mb in zip(q_c[-2], q, m0, m1, strict=True)
            ]
        q, ok, _, new_fac, jac = ks.newton(pred, u_c[j], 20, tol, 0.5, MARCH_STEP_TOL)
        if not ok or not new_fac[5] >= well or (new_fac[4] > 0.0) != (fac[4] > 0.0):
            return None
        if max(abs(a - b) / sc for a, b, sc in zip(q, pred, ks.scale, strict=True)) > 0.5 * du:
            return None
        fac, m0, du_prev = new_fac, m1, du
        tan = ks.tangent(fac, jac)
        q_c.append(q)
        t_c.append(tan)
        det_c.append(fac[4])
    return q_c, t_c, det_c


class _March:
    """Sequential predictor–corrector steps with step halving (size-1 batches)."""

    def __init__(self, c: Compiled, tol: float, sing_tol: float) -> None:
        self.c, self.tol, self.sing_tol = c, tol, sing_tol

    def _step(self, a: NewtonResult, u_a: np.ndarray, u_b: np.ndarray) -> NewtonResult | None:
        c = self.c
        du_vec = u_b - u_a
        pred = a.q + np.einsum("qun,un->qn", a.tan, du_vec)
        pred = np.where(np.isfinite(pred), pred, a.q)
        res = newton_one(c, pred, u_b, max_iter=20, tol=self.tol)
        if not res.converged[0]:
            return None
        du = np.abs(du_vec / c.var_scale[c.inputs][:, None]).max(axis=0)
        ok, _ = _accept(c, res, pred, du, a.det, a.rcond, self.sing_tol, q_from=a.q)
        return res if ok[0] else None

    def to(
        self, a: NewtonResult, u_a: np.ndarray, u_b: np.ndarray, restart: bool, guess: np.ndarray
    ) -> NewtonResult | str | None:
        """March from solution ``a`` (at inputs ``u_a``) to ``u_b``.

        Returns the solution, None when ``u_b`` cannot be reached, or ``"lost"``
        when (after a gap) only a pose on another branch was found.
        """
        if restart:
            # After an assembly gap: re-assemble from the last good pose or the guess and
            # keep only a solution on the same side of det J = 0 (the same circuit/branch).
            found_other = False
            for start in (a.q, guess):
                res = newton_one(self.c, start, u_b, max_iter=50, tol=self.tol)
                if res.converged[0]:
                    if np.sign(res.det[0]) == np.sign(a.det[0]):
                        return res
                    found_other = True
            return "lost" if found_other else None
        cur, u_cur = a, u_a
        fraction = 1.0
        for _ in range(200):
            target = u_b if fraction >= 1.0 else u_cur + fraction * (u_b - u_cur)
            nxt = self._step(cur, u_cur, target)
            if nxt is None:
                fraction *= 0.5
                if fraction < 1.0 / 1024:
                    return None
                continue
            if fraction >= 1.0:
                return nxt
            cur, u_cur = nxt, target
            fraction = 2.0 * fraction
        return None


def _fill(c: Compiled, new, half, u, st: _Store, tol, march: _March) -> None:
    """Solve samples ``new`` from neighbours at ``new ± half`` in one batch."""
    n_samples = u.shape[1]
    good = st.good()
    left = new - half
    right = new + half
    has_right = right <= n_samples - 1
    right = np.minimum(right, n_samples - 1)
    has_left = good[left]
    has_right &= good[right]
    if not (has_left.all() and has_right[:-1].all()):
        # Neighbours that failed: fall back to the nearest solved sample on either side.
        idx = np.arange(n_samples)
        last_good = np.maximum.accumulate(np.where(good, idx, -1))
        next_good = np.minimum.accumulate(np.where(good, idx, n_samples)[::-1])[::-1]
        left = np.where(has_left, left, last_good[left])
        right = np.where(has_right, right, next_good[right])
        has_left = left >= 0
        has_right = right < n_samples
        left = np.clip(left, 0, n_samples - 1)
        right = np.clip(right, 0, n_samples - 1)
        solvable = has_left | has_right
        new, left, right = new[solvable], left[solvable], right[solvable]
        has_left, has_right = has_left[solvable], has_right[solvable]
    if new.size == 0:
        return

    scale_u = c.var_scale[c.inputs][:, None]
    u_new = u[:, new]
    dul, dur = u_new - u[:, left], u_new - u[:, right]
    dl = np.abs(dul / scale_u).max(axis=0)
    dr = np.abs(dur / scale_u).max(axis=0)
    q_l, q_r = st.q[:, left], st.q[:, right]
    t_l, t_r = st.tan[:, :, left], st.tan[:, :, right]
    # Both neighbours solved: cubic Hermite between them (positions and tangents), whose
    # error is O(step^4), so most fine-level samples converge without a Newton step.
    span = u[:, right] - u[:, left]
    span_s = span / scale_u
    denom = (span_s * span_s).sum(axis=0)
    # A neighbour at (or next to) a toggle has a useless tangent (dq/du is unbounded
    # there): predict from the other neighbour alone.
    well_l = has_left & (st.rc[left] >= 10 * march.sing_tol)
    well_r = has_right & (st.rc[right] >= 10 * march.sing_tol)
    has_left, has_right = (
        has_left & (well_l | ~well_r),  # keep a side unless only the other is well
        has_right & (well_r | ~well_l),
    )
    both = has_left & has_right & (denom > 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.clip(((dul / scale_u) * span_s).sum(axis=0) / denom, 0.0, 1.0)
    t2, t3 = t * t, t * t * t
    m_l = np.einsum("qun,un->qn", t_l, span)
    m_r = np.einsum("qun,un->qn", t_r, span)
    pred = (
        (2 * t3 - 3 * t2 + 1) * q_l
        + (t3 - 2 * t2 + t) * m_l
        + (3 * t2 - 2 * t3) * q_r
        + (t3 - t2) * m_r
    )
    if not both.all():  # one-sided: the tangent predictor from the solved neighbour
        pred_l = q_l + np.einsum("qun,un->qn", t_l, dul)
        pred_r = q_r + np.einsum("qun,un->qn", t_r, dur)
        with np.errstate(invalid="ignore"):
            pred = np.where(both, pred, np.where(has_left, pred_l, pred_r))
    du = np.maximum(np.where(has_left, dl, 0.0), np.where(has_right, dr, 0.0))
    ref = np.where(has_left, left, right)

    res = newton(c, pred, u_new, max_iter=20, tol=tol, lazy_first=half == 1)
    ok, jump = _accept(
        c, res, pred, du, st.det[ref], st.rc[ref], march.sing_tol, q_from=st.q[:, ref]
    )
    st.put(new[ok], res, ok)
    st.code[new[~res.converged]] = NO_ASSEMBLY
    # Suspected jumps: retry a few with the sequential march, flag the rest.
    jumped = np.flatnonzero(jump)
    st.code[new[jumped]] = JUMP
    for j in jumped[:64]:
        a_idx = int(ref[j])
        u_a, u_b = u[:, a_idx : a_idx + 1], u[:, new[j] : new[j] + 1]
        s = march.to(st.one(a_idx), u_a, u_b, False, st.q[:, a_idx : a_idx + 1])
        if isinstance(s, NewtonResult):
            st.put(new[j : j + 1], s)


# --------------------------------------------------------------------------- derivatives
def derivatives(
    c: Compiled,
    x0: np.ndarray,
    u_rates: list[np.ndarray],
    reuse: tuple | None = None,
) -> tuple[list[np.ndarray], Factor]:
    """Velocity, acceleration and jerk of every variable, one linear solve each.

    Differentiating each loop ``Σ s R = 0`` with ``R = d e^{jθ}`` (DESIGN.md):

    * ``Ṙ = (ḋ + j d θ̇) e^{jθ}``
    * ``R̈ = (d̈ − d θ̇² + j(d θ̈ + 2 ḋ θ̇)) e^{jθ}``
    * ``R⃛ = (d⃛ − 3 ḋ θ̇² − 3 d θ̇ θ̈ + j(d θ⃛ + 3 ḋ θ̈ + 3 d̈ θ̇ − d θ̇³)) e^{jθ}``

    The highest derivatives enter as ``(d⁽ᵏ⁾ + j d θ⁽ᵏ⁾) e^{jθ}``, i.e. through
    the position Jacobian, so ``J_q`` is factored once and solved per order.

    Parameters
    ----------
    c : Compiled
    x0 : ndarray, shape (n_var, N)
        Positions of all variables.
    u_rates : list of ndarray, each (n_u, N)
        First, second, third time derivatives of the inputs (1 to 3 entries).
    reuse : tuple, optional
        ``(terms, jacobian, factor)`` already computed at exactly ``x0`` (the
        last Newton evaluation of the position solve; ``Positions.reuse``).

    Returns
    -------
    rates : list of ndarray, each (n_var, N)
        ẋ, ẍ, x⃛ (as many as ``u_rates``).
    factor : Factor
        The factors of ``J_q`` (determinant and conditioning per sample).
    """
    nq = len(c.unknown)
    if reuse is None:
        cols = np.concatenate([c.unknown, c.inputs])
        terms = _vector_terms(c, x0)
        _, jac = residual_and_jacobian(c, x0, cols, terms=terms)
        fac = _factor(jac[:, :nq], *c.jq_scales, c.jq_structure)
    else:
        terms, jac, fac = reuse
    d, cos, sin = terms
    j_u = jac[:, nq:]
    rates: list[np.ndarray] = []
    n_loop = c.loops.shape[0]
    zero = 0.0
    for order, u_k in enumerate(u_rates, start=1):
        rhs = -np.einsum("eun,un->en", j_u, u_k)
        if order > 1:
            x1 = rates[0]
            x2 = rates[1] if order > 2 else None
            for l_idx in range(n_loop):
                for k in np.flatnonzero(c.loops[l_idx]):
                    s = c.loops[l_idx, k]
                    lv, av = c.length_var[k], c.angle_var[k]
                    if av < 0:  # constant angle: only the length's own derivatives
                        continue  # which enter through the Jacobian (no bias)
                    w1 = x1[av]
                    if lv < 0:  # constant length: the common case, fewer terms
                        if order == 2:
                            re, im = -d[k] * w1 * w1, zero
                        else:
                            w2 = x2[av]
                            re, im = -3.0 * d[k] * w1 * w2, -d[k] * w1 * w1 * w1
                    elif order == 2:
                        d1 = x1[lv]
                        re = -d[k] * w1 * w1
                        im = 2.0 * d1 * w1
                    else:
                        d1, d2, w2 = x1[lv], x2[lv], x2[av]
                        re = -3.0 * d1 * w1 * w1 - 3.0 * d[k] * w1 * w2
                        im = 3.0 * d1 * w2 + 3.0 * d2 * w1 - d[k] * w1 * w1 * w1
                    if im is zero:
                        rhs[2 * l_idx] -= s * (re * cos[k])
                        rhs[2 * l_idx + 1] -= s * (re * sin[k])
                        continue
                    rhs[2 * l_idx] -= s * (re * cos[k] - im * sin[k])
                    rhs[2 * l_idx + 1] -= s * (re * sin[k] + im * cos[k])
        xk = np.empty_like(x0)
        xk[c.inputs] = u_k
        xk[c.unknown] = lu_solve(fac, rhs)
        rates.append(xk)
    return rates, fac


def point_motion(
    c: Compiled, x: list[np.ndarray], terms: tuple[list, list, list] | None = None
) -> list[np.ndarray]:
    """Positions (and derivatives) of the named points as complex arrays (n_point, N).

    ``x`` holds the positions followed by as many rates as known; ``terms``
    are ``_vector_terms(c, x[0])`` when already computed.
    """
    if not c.points.shape[0]:
        return [np.zeros((0, x[0].shape[1]), dtype=complex) for _ in x]
    d, cos, sin = _vector_terms(c, x[0]) if terms is None else terms
    n_samples = x[0].shape[1]
    out = []
    zero = 0.0

    def der(level: int, var: int) -> np.ndarray | float:
        return x[level][var] if var >= 0 else zero

    for order in range(len(x)):
        p = np.zeros((c.points.shape[0], n_samples), dtype=complex)
        for i in range(c.points.shape[0]):
            for k in np.flatnonzero(c.points[i]):
                s = c.points[i, k]
                lv, av = c.length_var[k], c.angle_var[k]
                dk = d[k]
                if order == 0:
                    re, im = dk, zero
                elif order == 1:
                    re, im = der(1, lv), dk * der(1, av)
                elif order == 2:
                    d1, w1 = der(1, lv), der(1, av)
                    re = der(2, lv) - dk * w1 * w1
                    im = dk * der(2, av) + 2.0 * d1 * w1
                else:
                    d1, w1 = der(1, lv), der(1, av)
                    d2, w2 = der(2, lv), der(2, av)
                    re = der(3, lv) - 3.0 * d1 * w1 * w1 - 3.0 * dk * w1 * w2
                    im = dk * der(3, av) + 3.0 * d1 * w2 + 3.0 * d2 * w1 - dk * w1 * w1 * w1
                p[i] += s * ((re * cos[k] - im * sin[k]) + 1j * (re * sin[k] + im * cos[k]))
        out.append(p)
    return out
