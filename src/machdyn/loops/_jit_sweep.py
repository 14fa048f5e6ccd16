"""The compiled path of a continuation sweep (:mod:`machdyn.loops._kernels`).

When :mod:`machdyn.jit` lets the compiled kernels serve and every group of the
model is a dyad or linear, a sweep is solved by
:func:`machdyn.loops._kernels.sweep`: each dyad in closed form on the sweep's
branch (so gaps, islands, change points and toggles are settled sample by
sample, as the branch rules of docs/loops.md say), then the Jacobian and the
user's velocity, acceleration and jerk. This module turns a
:class:`~machdyn.loops._compiled.Compiled` model into the kernel's arrays.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import jit
from ._compiled import DYAD_ANGLES, DYAD_SAME, DYAD_SLIDE, LINEAR, Compiled
from ._newton import POLISH_FROM, TINY_STEP

__all__ = ["arrays", "dyad_arrays", "sweep"]


def arrays(c) -> tuple:
    """The model's arrays for :func:`sweep` (built once per compiled model)."""
    n_var = len(c.names)
    nq, nu = len(c.unknown), len(c.inputs)
    col = np.full(n_var, -1, dtype=np.int64)
    col[c.unknown] = np.arange(nq)
    col[c.inputs] = nq + np.arange(nu)
    lptr = [0]
    lvec, lsgn = [], []
    for terms in c.loop_terms:
        for k, s in terms:
            lvec.append(k)
            lsgn.append(s)
        lptr.append(len(lvec))
    gptr = [0]
    grows, gcols = [], []
    for g in c.groups:
        grows += list(g.rows)
        gcols += list(g.cols)
        gptr.append(len(grows))
    pptr, pvec, psgn = [0], [], []
    for row in c.points:
        for k in np.flatnonzero(row):
            pvec.append(int(k))
            psgn.append(float(row[k]))
        pptr.append(len(pvec))
    angle_var = np.zeros(n_var, dtype=np.bool_)
    angle_var[c.angle_var[c.angle_var >= 0]] = True
    return (
        np.asarray(c.length_var, dtype=np.int64),
        np.asarray(c.angle_var, dtype=np.int64),
        np.asarray(c.length_const, dtype=np.float64),
        np.cos(c.angle_const),
        np.sin(c.angle_const),
        np.array(lptr, dtype=np.int64),
        np.array(lvec, dtype=np.int64),
        np.array(lsgn, dtype=np.float64),
        np.ascontiguousarray(c.con, dtype=np.float64).reshape(len(c.con0), n_var),
        np.asarray(c.con0, dtype=np.float64),
        np.asarray(c.unknown, dtype=np.int64),
        np.asarray(c.inputs, dtype=np.int64),
        col,
        np.asarray(c.row_weight, dtype=np.float64),
        np.asarray(c.var_scale[c.unknown], dtype=np.float64),
        np.asarray(c.var_scale[c.inputs], dtype=np.float64),
        np.array(gptr, dtype=np.int64),
        np.array(grows, dtype=np.int64),
        np.array(gcols, dtype=np.int64),
        angle_var,
        float(c.group_parity),
        np.array(pptr, dtype=np.int64),
        np.array(pvec, dtype=np.int64),
        np.array(psgn, dtype=np.float64),
    )


def dyad_arrays(c: Compiled) -> tuple:
    """The groups' closed-form data for the compiled sweep.

    Each group's kind (0 linear, 1 two angles, 2 angle and slide, 3 angle and
    length of one vector, 4 one constraint on one unknown), loop, unknown
    variables, column order, each loop term's part in its dyad (0 known, 1 on
    the first angle, 2 on the second unknown; -1 no dyad), and for kind 4 the
    constraint's row and unknown, and the angle it is a constant offset of
    (``grot``, -1: none) with the offset's cos and sin.
    """
    kinds = {LINEAR: 0, DYAD_ANGLES: 1, DYAD_SLIDE: 2, DYAD_SAME: 3}
    ng = len(c.groups)
    gkind = np.zeros(ng, dtype=np.int64)
    gloop = np.full(ng, -1, dtype=np.int64)
    ga = np.full(ng, -1, dtype=np.int64)
    gb = np.full(ng, -1, dtype=np.int64)
    gflip = np.zeros(ng, dtype=np.bool_)
    starts = np.cumsum([0] + [len(t) for t in c.loop_terms])
    tcat = np.full(starts[-1], -1, dtype=np.int64)
    grow = np.full(ng, -1, dtype=np.int64)
    gvar = np.full(ng, -1, dtype=np.int64)
    grot = np.full(ng, -1, dtype=np.int64)
    gcos, gsin = np.ones(ng), np.zeros(ng)
    n_loop_rows = 2 * c.loops.shape[0]
    angles = set(c.angle_var[c.angle_var >= 0].tolist())
    inputs = set(np.asarray(c.inputs).tolist())
    for b, g in enumerate(c.groups):
        gkind[b] = kinds.get(g.kind, 5)  # 5: a general group (not swept compiled)
        if gkind[b] == 0 and len(g.rows) == 1 and g.rows[0] >= n_loop_rows:
            gkind[b] = 4  # one constraint on one unknown: solved by itself
            r = g.rows[0] - n_loop_rows
            v0 = int(c.unknown[g.cols[0]])
            grow[b], gvar[b] = r, v0
            others = [int(v) for v in np.flatnonzero(c.con[r]) if v != v0]
            if (
                len(others) == 1
                and {v0, others[0]} <= angles
                and c.con[r, others[0]] == -c.con[r, v0]
            ):  # θ = θ_other + δ: cos/sin by rotation
                delta = -c.con0[r] / c.con[r, v0]
                grot[b], gcos[b], gsin[b] = others[0], np.cos(delta), np.sin(delta)
            elif any(v in angles and v not in inputs for v in others):
                # a gear ratio on an unknown angle: its whole turns matter, which the
                # kernel's closed forms (angles within a turn) do not know: NumPy
                gkind[b] = 5
        if gkind[b] in (0, 4, 5):
            continue
        gloop[b], ga[b], gb[b] = g.loop, g.angle, g.length
        gflip[b] = int(c.unknown[g.cols[0]]) != g.angle
        for t, (k, _) in enumerate(c.loop_terms[g.loop], start=int(starts[g.loop])):
            av, lv = int(c.angle_var[k]), int(c.length_var[k])
            if av == g.angle and lv != g.length:
                tcat[t] = 1
            elif (g.kind == DYAD_ANGLES and av == g.length) or (
                g.kind != DYAD_ANGLES and lv == g.length
            ):
                tcat[t] = 2
            else:
                tcat[t] = 0
    return gkind, gloop, ga, gb, gflip, tcat, grow, gvar, grot, gcos, gsin


#: Largest scaled input step between two samples the kernel takes at once: longer ones
#: are followed in sub-steps, so that every angle keeps its whole turn.
SUB_STEP = 0.25
#: The compiled sine and cosine are accurate for inputs up to this magnitude.
INPUT_LIMIT = 1e5
#: |cos| (or |sin|) of a dyad's closed form beyond 1 by at most this is a toggle, not a
#: gap (rounding at the exact limit), as in the four-bar's closed form.
CLOSE_TOL = 1e-12


def sweepable(c: Compiled) -> bool:
    """Whether the compiled sweep can follow ``c``: its groups all dyads or single constraints.

    (General groups and linear groups of loops go the NumPy way.)
    """
    kinds = c.kernel_dyads[0]
    return bool(len(c.unknown)) and not ((kinds == 0) | (kinds == 5)).any()


def sweep(
    c: Compiled,
    u: np.ndarray,
    guess: np.ndarray,
    want: np.ndarray | None,
    u_rates: list[np.ndarray] | None,
    *,
    sing_tol: float,
    tol: float,
    max_iter: int,
    cost: float = 1.0,
) -> tuple[Any, ...] | None:
    """Run the compiled sweep; None when the kernels should not serve, or leave the sweep.

    Only models whose groups are all dyads or single constraints are swept this
    way. Returns ``(X, rates, points, det, rcond, gdet, grc, resid, code, group,
    want)`` for every sample: every variable (n_var, N), their rates (orders,
    n_var, N), the named points and their rates (1 + orders, n_point, N).
    None also where the first sample gives no branch (the NumPy path handles
    sweeps that start in a gap or at a toggle). ``cost``:
    how many four-bar poses of NumPy time one pose of the NumPy continuation
    costs (for the ``auto`` rule of :mod:`machdyn.jit`).
    """
    n = u.shape[1]
    if not c.kernel_sweepable:
        return None
    if u.size and not (u.max() <= INPUT_LIMIT and u.min() >= -INPUT_LIMIT):  # False for NaN
        return None
    if jit.kernels(int(n * cost)) is None:
        return None
    try:
        from . import _kernels
    except Exception as exc:  # numba missing or broken: NumPy serves
        jit.fail(exc)
        return None
    ng = len(c.groups)
    orders = len(u_rates) if u_rates else 0
    # the rates of orders not asked for are never read: any array of u's shape stands in
    r1, r2, r3 = ((list(u_rates) if u_rates else []) + [u] * 3)[:3]
    branch = np.zeros(ng) if want is None else np.array(want, dtype=float)
    # every output is written at every sample when the kernel returns n (read only then)
    X = np.empty((len(c.names), n))
    rates = np.empty((orders, len(c.names), n))
    det, rcond, resid = np.empty(n), np.empty(n), np.empty(n)
    gdet, grc = np.empty((ng, n)), np.empty((ng, n))
    code = np.empty(n, dtype=np.int8)
    points = np.empty((orders + 1, c.points.shape[0], n), dtype=complex)
    group = np.empty(n, dtype=np.int16)
    try:
        done = _kernels.sweep(
            *c.kernel_arrays,
            *c.kernel_dyads,
            np.ascontiguousarray(u, dtype=float),
            np.ascontiguousarray(guess[:, 0], dtype=float),
            branch,
            np.ascontiguousarray(r1, dtype=float),
            np.ascontiguousarray(r2, dtype=float),
            np.ascontiguousarray(r3, dtype=float),
            orders,
            CLOSE_TOL,
            sing_tol,
            SUB_STEP,
            tol,
            POLISH_FROM,
            TINY_STEP,
            max_iter,
            X,
            rates,
            det,
            rcond,
            gdet,
            grc,
            resid,
            code,
            group,
            points,
        )
    except Exception as exc:  # anything from numba: NumPy is the reference path
        jit.fail(exc)
        return None
    if done < n:
        return None
    return X, rates, points, det, rcond, gdet, grc, resid, code, group, branch
