"""Newton–Raphson for the loop equations: batched (numpy) and for one pose (plain floats).

Both stop a sample once its weighted residual is at most ``min(tol,``
:data:`POLISH_FROM` ``)`` and then take the Newton step computed from that
evaluation as well (the *polish*): Newton's error squares, so a pose accepted
at 1e-8 or 1e-12 is returned at the rounding floor whatever the sweep's order
or the path that found it. ``tol`` only decides what counts as converged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._compiled import Compiled
from ._equations import residual_and_jacobian
from ._linalg import SmallBlocks, solve

__all__ = ["NewtonResult", "newton", "newton_one"]

#: A sample whose weighted residual is at most this (and at most ``tol``) gets one
#: last Newton step and stops: from here that step leaves ~1e-16, the rounding floor.
POLISH_FROM = 1e-8
#: A Newton step this small (relative to the unknowns, scaled) is rounding: the pose
#: is as closed as double precision allows, whatever ``tol`` asked for.
TINY_STEP = 8.0 * np.finfo(float).eps
#: A prediction whose weighted residual is already this small is at the rounding
#: floor (``lazy_first``): accepted as it is.
FLOOR = 2e-15


@dataclass(frozen=True)
class NewtonResult:
    """Outcome of a Newton solve (internal).

    ``tan`` (dq/du), ``det``, ``rcond`` and the per-group ``gdet``/``grc`` are
    those of ``J_q`` at the last evaluation (NaN / 0 where not converged; NaN
    where accepted without one, see ``lazy_first``).
    """

    q: np.ndarray  # (n_q, N) unknowns
    converged: np.ndarray  # (N,) bool
    residual: np.ndarray  # (N,) max weighted residual
    tan: np.ndarray  # (n_q, n_u, N)
    det: np.ndarray  # (N,)
    rcond: np.ndarray  # (N,)
    gdet: np.ndarray  # (n_groups, N)
    grc: np.ndarray  # (n_groups, N)

    def take(self, sel) -> NewtonResult:
        """The samples ``sel`` (an index array or mask)."""
        return NewtonResult(
            self.q[:, sel],
            self.converged[sel],
            self.residual[sel],
            self.tan[:, :, sel],
            self.det[sel],
            self.rcond[sel],
            self.gdet[:, sel],
            self.grc[:, sel],
        )


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

    Samples leave the active set once their weighted residual is at most
    ``min(tol, POLISH_FROM)``, after one last (polishing) step; steps are
    shortened so that no angle moves more than ``max_step`` radians (and no
    length more than ``max_step`` times the model's scale) per iteration, which
    keeps a poor guess from leaping to another circuit. Each iteration
    evaluates ``F``, ``J_q`` and ``J_u`` once and factors ``J_q`` once (group by
    group): the same solve gives the Newton step and the continuation tangent
    ``dq/du = −J_q⁻¹ J_u``.

    Parameters
    ----------
    c : Compiled
    q0 : ndarray, shape (n_q, N)
        Starting values of the unknowns.
    u : ndarray, shape (n_u, N)
        Input values.
    lazy_first : bool
        Check the starting values by their residual alone: samples already at
        the rounding floor (:data:`FLOOR`) are accepted without a Jacobian (then
        ``tan``, ``det``, ``rcond``, ``gdet`` and ``grc`` are NaN for them).
    """
    n_samples = q0.shape[1]
    nq, nu, ng = len(c.unknown), len(c.inputs), len(c.groups)
    x = np.empty((len(c.names), n_samples))
    x[c.inputs] = u
    x[c.unknown] = q0
    weight = c.row_weight[:, None]
    inv_scale = (1.0 / c.var_scale[c.unknown])[:, None]
    cols = np.concatenate([c.unknown, c.inputs])
    converged = np.zeros(n_samples, dtype=bool)
    resid = np.full(n_samples, np.inf)
    tan = np.full((nq, nu, n_samples), np.nan)
    det, rcond = np.zeros(n_samples), np.zeros(n_samples)
    gdet, grc = np.zeros((ng, n_samples)), np.zeros((ng, n_samples))
    target = min(tol, POLISH_FROM)
    active = np.arange(n_samples)
    xa = x
    for it in range(max_iter + 1):
        if lazy_first and it == 0:
            f, _ = residual_and_jacobian(c, xa, cols, jacobian=False)
            r = np.abs(f * weight).max(axis=0) if f.size else np.zeros(active.size)
            resid[active] = r
            floor = r <= min(tol, FLOOR)
            if floor.any():
                idx = active[floor]
                converged[idx] = True
                x[:, idx] = xa[:, floor]
                det[idx], rcond[idx], gdet[:, idx], grc[:, idx] = np.nan, np.nan, np.nan, np.nan
                active, xa = active[~floor], xa[:, ~floor]
            if active.size == 0:
                break
        f, jac = residual_and_jacobian(c, xa, cols)
        r = np.abs(f * weight).max(axis=0) if f.size else np.zeros(active.size)
        resid[active] = r
        fac = c.factor(jac[:, :nq])
        rhs = np.concatenate([-f[:, None, :], -jac[:, nq:]], axis=1)
        sol = solve(fac, rhs)
        step = sol[:, 0]
        finite = np.isfinite(step).all(axis=0)
        # At the rounding floor (a step of a few ulps) the pose is as closed as doubles
        # allow, even if that is above a very tight tol.
        with np.errstate(invalid="ignore"):
            size = np.abs(step * inv_scale).max(axis=0)
            tiny = size <= TINY_STEP * np.maximum(
                1.0, np.abs(xa[c.unknown] * inv_scale).max(axis=0)
            )
        done = (r <= target) | ((r <= tol) & (it == max_iter)) | (tiny & (r <= POLISH_FROM))
        if done.any():
            idx = active[done]
            converged[idx] = True
            # The polish: the step from this evaluation, unless it is not finite (a
            # singular pose that happens to close: keep the pose as it is).
            xa[c.unknown[:, None], np.flatnonzero(done & finite)] += step[:, done & finite]
            x[:, idx] = xa[:, done]
            tan[:, :, idx] = sol[:, 1:, done]
            det[idx], rcond[idx] = fac.det[done], fac.rcond[done]
            gdet[:, idx], grc[:, idx] = fac.block_det[:, done], fac.block_rcond[:, done]
            keep = ~done
            active, xa, step = active[keep], xa[:, keep], step[:, keep]
        else:
            keep = slice(None)
        if active.size == 0 or it == max_iter:
            break
        size = size[keep]
        with np.errstate(invalid="ignore"):
            shrink = np.where(size > max_step, max_step / size, 1.0)
        step = np.where(np.isfinite(step), step * shrink, 0.0)
        xa[c.unknown] += step
    if active.size:
        x[:, active] = xa
    return NewtonResult(x[c.unknown], converged, resid, tan, det, rcond, gdet, grc)


class Scalar:
    """``F``, ``J`` and Newton for a single pose in plain Python floats.

    The sequential continuation march solves one pose at a time; there numpy's
    per-call overhead dominates, so this twin of :func:`residual_and_jacobian`
    and :func:`newton` (same equations, step limiting, tolerances and polish) is
    several times faster. Everything static (which column a vector's angle or
    length feeds, the trigonometry of constant angles) is worked out once per
    model. Factors are ``SmallBlocks.factor`` tuples ``(parts, det, rcond,
    group dets, group rconds)``.
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
        self.blocks = SmallBlocks(c.plan)

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
        """Newton–Raphson from ``q0``: (q, converged, residual, factor of J_q, J).

        The factor and J are those of the last evaluation (before the polish).
        With ``step_tol`` > 0 it also stops after a full Newton step no larger
        than ``step_tol`` (scaled): the error left is of the order of its square
        (the caller polishes and verifies the pose later; this saves the
        confirming evaluation).
        """
        x = self.state(q0, u)
        resid = math.inf
        target = min(tol, POLISH_FROM)
        for it in range(max_iter + 1):
            f, jac = self.equations(x)
            resid = max((abs(fi * w) for fi, w in zip(f, self.weight, strict=True)), default=0.0)
            fac = self.blocks.factor(jac)
            step = self.blocks.solve(fac[0], jac, [-v for v in f])
            finite = all(math.isfinite(v) for v in step)
            size = max((abs(v) / sc for v, sc in zip(step, self.scale, strict=True)), default=0.0)
            big = max(
                (abs(x[i]) / sc for i, sc in zip(self.unknown, self.scale, strict=True)),
                default=0.0,
            )
            tiny = size <= TINY_STEP * max(1.0, big)
            if (
                resid <= target
                or (resid <= tol and it == max_iter)
                or (tiny and resid <= POLISH_FROM)
            ):
                if finite:  # the polish
                    for i, v in zip(self.unknown, step, strict=True):
                        x[i] += v
                return [x[i] for i in self.unknown], True, resid, fac, jac
            if it == max_iter or not finite:
                break
            shrink = max_step / size if size > max_step else 1.0
            for i, v in zip(self.unknown, step, strict=True):
                x[i] += v * shrink
            if size <= step_tol:
                return [x[i] for i in self.unknown], True, resid, fac, jac
        return [x[i] for i in self.unknown], False, resid, None, None

    def tangent(self, fac: tuple, jac: list[list[float]]) -> list[list[float]]:
        """``dq/du = −J_q⁻¹ J_u`` as rows per unknown, columns per input."""
        nq = self.nq
        cols = [self.blocks.solve(fac[0], jac, [-r[nq + m] for r in jac]) for m in range(self.nu)]
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
    nq, nu, ng = ks.nq, ks.nu, len(c.groups)
    q, ok, resid, fac, jac = ks.newton(
        [float(v) for v in q0[:, 0]], [float(v) for v in u[:, 0]], max_iter, tol, max_step
    )
    if ok:
        return NewtonResult(
            q=np.array(q).reshape(nq, 1),
            converged=np.ones(1, dtype=bool),
            residual=np.array([resid]),
            tan=np.array(ks.tangent(fac, jac)).reshape(nq, nu, 1),
            det=np.array([fac[1]]),
            rcond=np.array([fac[2]]),
            gdet=np.array(fac[3]).reshape(ng, 1),
            grc=np.array(fac[4]).reshape(ng, 1),
        )
    return NewtonResult(
        q=np.array(q).reshape(nq, 1),
        converged=np.zeros(1, dtype=bool),
        residual=np.array([resid]),
        tan=np.full((nq, nu, 1), np.nan),
        det=np.zeros(1),
        rcond=np.zeros(1),
        gdet=np.zeros((ng, 1)),
        grc=np.zeros((ng, 1)),
    )
