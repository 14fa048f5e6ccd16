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


# --------------------------------------------------------------------------- linear algebra
@dataclass(frozen=True)
class Factor:
    """Batched LU factors with partial pivoting, layout ``(n, n, N)``.

    The matrix is first scaled, ``diag(r) · a · diag(s)``: by the given static
    scales (one pass), or equilibrated per sample (columns, then rows, to a
    largest entry of 1). ``swaps[k]`` is the (N,) row chosen as pivot of column
    ``k``; ``det`` the determinant of the original matrix and ``rcond`` the ratio
    of the smallest to the largest pivot magnitude of the scaled one (a cheap
    reciprocal condition estimate).
    """

    lu: np.ndarray
    swaps: tuple[np.ndarray, ...]
    row_mul: np.ndarray  # (n, N) or (n, 1)
    col_mul: np.ndarray  # (n, N) or (n, 1)
    det: np.ndarray
    rcond: np.ndarray


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
    det = 1.0 / (np.prod(row_mul, axis=0) * np.prod(col_mul, axis=0))
    swaps = []
    piv_min = np.full(a.shape[2], np.inf)
    piv_max = np.zeros(a.shape[2])
    with np.errstate(divide="ignore", invalid="ignore"):
        for k in range(n):
            best = np.abs(lu[k, k])
            p: np.ndarray | int = k
            for i in range(k + 1, n):
                cand = np.abs(lu[i, k])
                bigger = cand > best
                best = np.where(bigger, cand, best)
                p = np.where(bigger, i, p)
            swaps.append(p)
            if n - k > 3 and not np.isscalar(p):
                # Many candidate rows: one gather and one scatter instead of a where-swap
                # per candidate (O(n) instead of O(n^2) row passes per column).
                moved = p != k
                if moved.any():
                    cols = np.arange(a.shape[2])
                    top = lu[k].copy()
                    lu[k] = lu[p, :, cols].T
                    lu[p, :, cols] = top.T
                    det = np.where(moved, -det, det)
            else:
                for i in range(k + 1, n):
                    m = p == i
                    if m.any():
                        top = lu[k].copy()
                        lu[k] = np.where(m, lu[i], lu[k])
                        lu[i] = np.where(m, top, lu[i])
                        det = np.where(m, -det, det)
            pivot = lu[k, k]
            det = det * pivot
            np.minimum(piv_min, best, out=piv_min)
            np.maximum(piv_max, best, out=piv_max)
            safe = np.where(pivot == 0.0, 1.0, pivot)
            for i in range(k + 1, n):
                factor = lu[i, k] / safe
                lu[i, k] = factor
                lu[i, k + 1 :] -= factor * lu[k, k + 1 :]
    rcond = np.where(piv_max > 0.0, piv_min / np.where(piv_max > 0.0, piv_max, 1.0), 0.0)
    return Factor(lu=lu, swaps=tuple(swaps), row_mul=row_mul, col_mul=col_mul, det=det, rcond=rcond)


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
    with np.errstate(divide="ignore", invalid="ignore"):
        for k in range(n):  # P b: the row interchanges, in order
            p = f.swaps[k]
            for i in range(k + 1, n):
                m = (p == i)[extra]
                if m.any():
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

    Constant parts stay Python floats (broadcast for free).
    """
    d, cos, sin = [], [], []
    for k in range(len(c.length_const)):
        lv, av = c.length_var[k], c.angle_var[k]
        d.append(x[lv] if lv >= 0 else float(c.length_const[k]))
        if av >= 0:
            cos.append(np.cos(x[av]))
            sin.append(np.sin(x[av]))
        else:
            cos.append(float(np.cos(c.angle_const[k])))
            sin.append(float(np.sin(c.angle_const[k])))
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
        re: np.ndarray | float = 0.0
        im: np.ndarray | float = 0.0
        for k, s in terms:
            sd = s * d[k]
            re = re + sd * cos[k]
            im = im + sd * sin[k]
            if jac is None:
                continue
            a_col = where.get(int(c.angle_var[k]))
            if a_col is not None:
                jac[2 * l_idx, a_col] -= sd * sin[k]
                jac[2 * l_idx + 1, a_col] += sd * cos[k]
            l_col = where.get(int(c.length_var[k]))
            if l_col is not None:
                jac[2 * l_idx, l_col] += s * cos[k]
                jac[2 * l_idx + 1, l_col] += s * sin[k]
        f[2 * l_idx] = re
        f[2 * l_idx + 1] = im
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
        fac = lu_factor(jac[:, :nq], *c.jq_scales)
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
    lu = [[a[i][j] * row[i] * col[j] for j in range(n)] for i in range(n)]
    det = 1.0
    for v in row + col:
        det /= v
    piv, lo, hi = [], math.inf, 0.0
    for k in range(n):
        p = max(range(k, n), key=lambda i: abs(lu[i][k]))
        piv.append(p)
        if p != k:
            lu[k], lu[p] = lu[p], lu[k]
            det = -det
        pivot = lu[k][k]
        det *= pivot
        lo, hi = min(lo, abs(pivot)), max(hi, abs(pivot))
        if pivot == 0.0:
            continue
        for i in range(k + 1, n):
            f = lu[i][k] / pivot
            lu[i][k] = f
            if f:
                rk, ri = lu[k], lu[i]
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


def newton_one(
    c: Compiled,
    q0: np.ndarray,
    u: np.ndarray,
    max_iter: int = 30,
    tol: float = 1e-12,
    max_step: float = 0.5,
) -> NewtonResult:
    """:func:`newton` for a single sample in plain Python floats.

    The sequential continuation march solves one pose at a time; there numpy's
    per-call overhead dominates, so this scalar twin (same equations, same
    step limiting and tolerances) is several times faster.
    """
    nq, nu = len(c.unknown), len(c.inputs)
    x = [0.0] * len(c.names)
    for i, v in zip(c.unknown, q0[:, 0], strict=True):
        x[i] = float(v)
    for i, v in zip(c.inputs, u[:, 0], strict=True):
        x[i] = float(v)
    cols = [int(v) for v in c.unknown] + [int(v) for v in c.inputs]
    where = {v: i for i, v in enumerate(cols)}
    weight = c.row_weight.tolist()
    con, con0 = c.con.tolist(), c.con0.tolist()
    lvar, avar = c.length_var.tolist(), c.angle_var.tolist()
    lconst, aconst = c.length_const.tolist(), c.angle_const.tolist()
    scale = [float(c.var_scale[i]) for i in c.unknown]
    row_mul, col_mul = (v.tolist() for v in c.jq_scales)
    n_eq = c.n_eq
    resid = math.inf
    for it in range(max_iter + 1):
        f = [0.0] * n_eq
        jac = [[0.0] * (nq + nu) for _ in range(n_eq)]
        for l_idx, terms in enumerate(c.loop_terms):
            rx, ry = 2 * l_idx, 2 * l_idx + 1
            for k, sgn in terms:
                d = x[lvar[k]] if lvar[k] >= 0 else lconst[k]
                th = x[avar[k]] if avar[k] >= 0 else aconst[k]
                co, si = math.cos(th), math.sin(th)
                sd = sgn * d
                f[rx] += sd * co
                f[ry] += sd * si
                col = where.get(avar[k])
                if col is not None:
                    jac[rx][col] -= sd * si
                    jac[ry][col] += sd * co
                col = where.get(lvar[k])
                if col is not None:
                    jac[rx][col] += sgn * co
                    jac[ry][col] += sgn * si
        for r, (coefs, c0) in enumerate(zip(con, con0, strict=True), start=2 * len(c.loop_terms)):
            f[r] = sum(a * b for a, b in zip(coefs, x, strict=True)) + c0
            for j, v in enumerate(cols):
                jac[r][j] = coefs[v]
        resid = max((abs(fi * w) for fi, w in zip(f, weight, strict=True)), default=0.0)
        fac = _small_lu([r[:nq] for r in jac], row_mul, col_mul)
        if resid <= tol:
            tan = [_small_solve(fac, [-r[nq + m] for r in jac]) for m in range(nu)]
            return NewtonResult(
                q=np.array([[x[i]] for i in c.unknown]).reshape(nq, 1),
                converged=np.ones(1, dtype=bool),
                residual=np.array([resid]),
                tan=np.array(tan).T.reshape(nq, nu, 1),
                det=np.array([fac[4]]),
                rcond=np.array([fac[5]]),
            )
        if it == max_iter:
            break
        step = _small_solve(fac, [-v for v in f])
        if not all(math.isfinite(v) for v in step):
            break
        size = max((abs(v) / sc for v, sc in zip(step, scale, strict=True)), default=0.0)
        shrink = max_step / size if size > max_step else 1.0
        for i, v in zip(c.unknown, step, strict=True):
            x[i] += v * shrink
    return NewtonResult(
        q=np.array([x[i] for i in c.unknown]).reshape(nq, 1),
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


def _accept(
    c: Compiled,
    res: NewtonResult,
    pred: np.ndarray,
    du: np.ndarray,
    det_ref: np.ndarray,
    rc_ref: np.ndarray,
    sing_tol: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Continuation checks; returns (accepted, jump) masks.

    A converged sample is a *jump* when ``det J_q`` changed sign from its
    reference neighbour while neither is near a toggle, or when it lies farther
    from its tangent prediction than half the (scaled) input step: on one
    branch the prediction error is O(step²), a jump to another circuit is O(1).
    """
    near_sing = ~(res.rcond >= 10 * sing_tol) | ~(rc_ref >= 10 * sing_tol)  # NaN: unknown
    same_side = (np.sign(res.det) == np.sign(det_ref)) | near_sing
    far = np.abs((res.q - pred) / c.var_scale[c.unknown][:, None]).max(axis=0) > 0.5 * du + 1e-9
    jump = res.converged & (~same_side | far)
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
    flagged.
    """
    n_q, n_u, n_samples = guess.shape[0], u.shape[0], u.shape[1]
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
        ok, _ = _accept(c, res, pred, du, a.det, a.rcond, self.sing_tol)
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
    ok, jump = _accept(c, res, pred, du, st.det[ref], st.rc[ref], march.sing_tol)
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

    Returns
    -------
    rates : list of ndarray, each (n_var, N)
        ẋ, ẍ, x⃛ (as many as ``u_rates``).
    factor : Factor
        The factors of ``J_q`` (determinant and conditioning per sample).
    """
    cols = np.concatenate([c.unknown, c.inputs])
    terms = _vector_terms(c, x0)
    d, cos, sin = terms
    _, jac = residual_and_jacobian(c, x0, cols, terms=terms)
    nq = len(c.unknown)
    fac = lu_factor(jac[:, :nq], *c.jq_scales)
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


def point_motion(c: Compiled, x: list[np.ndarray]) -> list[np.ndarray]:
    """Positions (and derivatives) of the named points as complex arrays (n_point, N).

    ``x`` holds the positions followed by as many rates as known.
    """
    d, cos, sin = _vector_terms(c, x[0])
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
