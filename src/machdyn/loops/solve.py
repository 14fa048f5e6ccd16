"""Positions along a sweep: continuation that keeps every group's branch.

The equations, their Newton solvers and the linear algebra live in
``_equations``, ``_newton`` and ``_linalg``; this module follows a sweep of
input values (:func:`solve_positions`). A sweep's branch is the sign of every
group's determinant at its start (``_compiled`` explains the groups,
``_branches`` how a group is moved back to its branch): every sample reported
ok has those signs, through assembly gaps and change points alike.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from .. import jit
from . import _jit_sweep
from ._branches import assemble, fix_branches, wrong_groups
from ._compiled import Compiled
from ._equations import _step_terms, _vector_terms, residual_and_jacobian
from ._linalg import lu_factor, lu_solve, solve
from ._newton import FLOOR, POLISH_FROM, NewtonResult, Scalar, newton, newton_one

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
    "cannot assemble on the starting branch: only the other sign of a group's determinant found",
)


# --------------------------------------------------------------------------- results
@dataclass(frozen=True)
class Positions:
    """Positions of the unknowns with per-sample codes (internal).

    ``gdet``/``grc`` are each group's determinant and reciprocal condition,
    ``group`` the group a flag names (-1: none), ``want`` the sweep's branch
    (the groups' determinant signs; None without continuation).
    """

    q: np.ndarray  # (n_q, N)
    code: np.ndarray  # (N,) int8 reason codes
    residual: np.ndarray  # (N,)
    det: np.ndarray  # (N,)
    rcond: np.ndarray  # (N,)
    gdet: np.ndarray  # (n_groups, N)
    grc: np.ndarray  # (n_groups, N)
    group: np.ndarray  # (N,) int16
    want: np.ndarray | None = None
    #: ``(terms, jac, factor)`` at these positions (to rounding) when every sample came
    #: from the fast path: the derivative stage reuses them instead of recomputing.
    reuse: tuple | None = None
    #: Velocity, acceleration, jerk of every variable (n_var, N) already computed (by
    #: the compiled sweep) at the samples ``rates_done``.
    rates: list[np.ndarray] | None = None
    rates_done: np.ndarray | None = None
    #: From the compiled sweep: every variable (n_var, N) and the named points with
    #: their rates, already masked (NaN where not assembled, rates NaN where not ok).
    x: np.ndarray | None = None
    points: np.ndarray | None = None

    _PER_SAMPLE = ("q", "code", "residual", "det", "rcond", "gdet", "grc", "group")

    def join(self, other: Positions, span: slice) -> Positions:
        """The samples ``span`` replaced by those of ``other`` (as long as the span)."""
        out = {}
        for name in self._PER_SAMPLE:
            arr = getattr(self, name).copy()
            arr[..., span] = getattr(other, name)
            out[name] = arr
        done = None
        if self.rates_done is not None:
            done = self.rates_done.copy()
            done[span] = False
        return Positions(**out, want=self.want, rates=self.rates, rates_done=done)

    def take(self, sl: slice) -> Positions:
        """The samples ``sl`` (a slice) alone."""
        out = {name: getattr(self, name)[..., sl] for name in self._PER_SAMPLE}
        return Positions(**out, want=self.want)


def _singular_code(res: NewtonResult, sing_tol: float) -> np.ndarray:
    """OK, or SINGULAR where converged at a toggle (NO_ASSEMBLY where not converged)."""
    code = np.where(res.converged, OK, NO_ASSEMBLY)
    return np.where(res.converged & (res.rcond < sing_tol), SINGULAR, code).astype(np.int8)


def _first_group(mask: np.ndarray) -> np.ndarray:
    """(N,) index of the first True row of a (n_groups, N) mask, -1 where none."""
    if mask.shape[0] == 0:
        return np.full(mask.shape[1], -1, dtype=np.int16)
    return np.where(mask.any(axis=0), mask.argmax(axis=0), -1).astype(np.int16)


def _accept(
    c: Compiled,
    res: NewtonResult,
    pred: np.ndarray,
    du: np.ndarray,
    want: np.ndarray,
    sing_tol: float,
    q_from: np.ndarray | None = None,
    strict: bool = False,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Continuation checks; returns (accepted, jump, lost, group) per sample.

    *lost*: converged, but a group (not at a toggle) has the other determinant
    sign than the sweep's branch ``want`` (call :func:`fix_branches` first).
    *jump*: a group whose roots the sign does not tell apart (a triad, say)
    lies farther from its prediction than half the (scaled) step, unless the
    pose sits at a toggle, where the branches meet: on one branch the
    prediction error is O(step²), a jump to another assembly mode is O(1). The
    step counts the input step and, when ``q_from`` (the pose predicted from)
    is given, the predicted motion of the unknowns: next to a rocker's limit
    ``dq/du`` is unbounded and a pose on the right branch lies many input steps
    from the prediction. Groups told apart by their sign (dyads, linear
    groups) need no such test: their sign is their root, and the angles found
    are moved by whole turns next to ``q_from`` (:func:`_unwrap`). With
    ``strict`` (the sequential march, which halves a step that fails) a step
    whose prediction moves an angle by :data:`MARCH_TURN` or more fails too, so
    that the whole turn is never in doubt. ``group`` names the group a flag is
    about (-1: none).
    """
    wrong = wrong_groups(c, res.gdet, res.grc, want, sing_tol)
    lost = res.converged & wrong.any(axis=0)
    group = _first_group(wrong)
    jump = np.zeros_like(lost)
    general = [g for g in c.groups if not g.identified_by_sign]
    far_any = np.zeros_like(lost)
    if general:
        scale = c.var_scale[c.unknown][:, None]
        step = du
        if q_from is not None:
            moved = np.abs((pred - q_from) / scale).max(axis=0)
            step = du + np.where(np.isfinite(moved), moved, 0.0)
        off = np.abs((res.q - pred) / scale)
        far = np.stack([off[list(g.cols)].max(axis=0) > 0.5 * step + 1e-9 for g in general])
        far_any = far.any(axis=0)
        index = np.array([c.groups.index(g) for g in general], dtype=np.int16)
        group = np.where(far_any & ~lost, index[far.argmax(axis=0)], group).astype(np.int16)
    if strict and q_from is not None and c.angle_rows.size:
        # A step that expects an angle to move by a radian or more cannot tell which
        # whole turn the pose it finds is on: shorter steps.
        rows = c.angle_rows
        with np.errstate(invalid="ignore"):
            big = ~(np.abs(pred[rows] - q_from[rows]).max(axis=0) < MARCH_TURN)
        far_any = far_any | big
    # At a singular pose (a toggle) the two branches meet, so it belongs to both: the
    # prediction's error is unbounded there, but the pose is no jump.
    jump = res.converged & far_any & ~(res.rcond < sing_tol) & ~lost
    return res.converged & ~jump & ~lost, jump, lost, group


class _Store:
    """Per-sample arrays filled by the continuation (internal)."""

    def __init__(self, n_q: int, n_u: int, n_g: int, n: int, sing_tol: float) -> None:
        self.q = np.full((n_q, n), np.nan)
        self.code = np.full(n, NO_ASSEMBLY, dtype=np.int8)
        self.resid = np.full(n, np.inf)
        self.tan = np.full((n_q, n_u, n), np.nan)
        self.det = np.zeros(n)
        self.rc = np.zeros(n)
        self.gdet = np.zeros((n_g, n))
        self.grc = np.zeros((n_g, n))
        self.group = np.full(n, -1, dtype=np.int16)
        self.sing_tol = sing_tol

    def put(self, idx, res: NewtonResult, sel=slice(None)) -> None:
        self.q[:, idx] = res.q[:, sel]
        self.tan[:, :, idx] = res.tan[:, :, sel]
        self.det[idx] = res.det[sel]
        self.rc[idx] = res.rcond[sel]
        self.gdet[:, idx] = res.gdet[:, sel]
        self.grc[:, idx] = res.grc[:, sel]
        self.resid[idx] = res.residual[sel]
        self.code[idx] = np.where(res.rcond[sel] < self.sing_tol, SINGULAR, OK)
        self.group[idx] = -1

    def flag(self, idx, code: int, group=-1) -> None:
        self.code[idx] = code
        self.group[idx] = group

    def good(self) -> np.ndarray:
        return (self.code == OK) | (self.code == SINGULAR)

    def one(self, i: int) -> NewtonResult:
        return NewtonResult(
            self.q[:, i : i + 1],
            np.ones(1, bool),
            self.resid[i : i + 1],
            self.tan[:, :, i : i + 1],
            self.det[i : i + 1],
            self.rc[i : i + 1],
            self.gdet[:, i : i + 1],
            self.grc[:, i : i + 1],
        )

    def result(self, want: np.ndarray | None) -> Positions:
        return Positions(
            self.q, self.code, self.resid, self.det, self.rc, self.gdet, self.grc, self.group, want
        )


def _unwrap(c: Compiled, q: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """``q`` with its angles moved by whole turns to lie within π of ``ref``."""
    rows = c.angle_rows
    if rows.size:
        with np.errstate(invalid="ignore"):
            turns = np.round((q[rows] - ref[rows]) / (2.0 * np.pi))
        q = q.copy()
        q[rows] -= 2.0 * np.pi * np.nan_to_num(turns)
    return q


def _branch_of(res: NewtonResult, i: int = 0) -> np.ndarray:
    """The groups' determinant signs of sample ``i``: a sweep's branch."""
    return np.sign(res.gdet[:, i])


# --------------------------------------------------------------------------- entry point
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
    want: np.ndarray | None = None,
    u_rates: list[np.ndarray] | None = None,
    compiled: bool = True,
) -> Positions:
    """Positions of the unknowns for inputs ``u`` (n_u, N).

    With ``continuation=False`` every sample starts from ``guess`` (shape
    (n_q, 1) or (n_q, N)) and no branch is imposed. With ``continuation=True``
    the samples are an ordered sweep whose branch ``want`` (each group's
    determinant sign) is that of the first sample solved from the guess, unless
    given: a coarse subsample (steps of at most ``max_step`` in input space,
    radians for angles, model scale for lengths) is marched sequentially from
    the guess with a tangent predictor and step halving; the samples in between
    are then filled in doubling waves, each a single batched Newton solve
    predicted from the already solved neighbours. Every solution is verified
    (:func:`_accept`, after :func:`fix_branches` moved groups found on their
    other root back); a failed verification is re-solved with smaller steps or
    flagged. Straight, evenly stepped sweeps first try :func:`_sweep_fast`
    (unless ``fast`` is False); if only some of its samples fail, the stretch
    holding them is re-solved this careful way (:func:`_patch`). When
    :mod:`machdyn.jit` lets the compiled kernels serve (and ``compiled``), the
    sweep is followed by :func:`_sweep_compiled` first, which also computes the
    derivatives for the inputs' rates ``u_rates``.
    """
    n_q, n_u, n_samples = guess.shape[0], u.shape[0], u.shape[1]
    if n_q == 0:  # every variable driven (an open chain): nothing to solve
        ones, zeros = np.ones(n_samples), np.zeros(n_samples)
        return Positions(
            np.empty((0, n_samples)),
            np.zeros(n_samples, np.int8),
            zeros,
            ones,
            ones,
            np.ones((0, n_samples)),
            np.ones((0, n_samples)),
            np.full(n_samples, -1, np.int16),
        )
    if not continuation or n_samples == 1:
        q0 = np.broadcast_to(guess, (n_q, n_samples))
        res = newton(c, q0, u, max_iter=max_iter, tol=tol)
        q = np.where(res.converged, res.q, np.nan)
        group = np.full(n_samples, -1, np.int16)
        code = _singular_code(res, sing_tol)
        pos = Positions(q, code, res.residual, res.det, res.rcond, res.gdet, res.grc, group)
        return _closure(c, u, pos)
    options = {"max_step": max_step, "tol": tol, "max_iter": max_iter, "sing_tol": sing_tol}
    if compiled and n_u:
        done = _sweep_compiled(
            c, u, guess, want, u_rates, sing_tol=sing_tol, tol=tol, max_iter=max_iter
        )
        if done is not None:
            return done
    start = time.perf_counter()
    pos = _whole_turns(c, _sweep_numpy(c, u, guess, want, fast=fast, **options), u)
    jit.charge(time.perf_counter() - start)
    return pos


def _whole_turns(c: Compiled, pos: Positions, u: np.ndarray) -> Positions:
    """Each angle's whole turns by the compiled sweep's rule (docs/loops.md).

    Across an assembly gap (samples with no pose) continuity does not define an
    angle's whole turn: the first pose after the gap lies within π of the last
    pose before it, and the stretch that follows moves with it. Between two
    solved samples whose inputs moved by at most ``SUB_STEP`` (scaled), no angle
    turns by π (the march halves a step that would move one by a radian), so a
    whole turn between them is a sample solved in another neighbour's turn (one
    filled from the far side of a stretch the march crossed): the rest of the
    sweep moves with it likewise. The compiled sweep keeps both rules sample by
    sample.
    """
    rows = c.angle_rows
    there = np.flatnonzero(np.isfinite(pos.q).all(axis=0))
    if not rows.size or there.size < 2:
        return pos
    jump = np.diff(pos.q[np.ix_(rows, there)], axis=1)
    whole = np.round(jump / (2.0 * np.pi))
    moved = np.flatnonzero((whole != 0).any(axis=0))  # pairs (there[k], there[k + 1]) a turn apart
    before, after = there[moved], there[moved + 1]
    step = np.abs((u[:, after] - u[:, before]) / c.var_scale[c.inputs][:, None]).max(axis=0)
    moved = moved[(after - before > 1) | (step <= _jit_sweep.SUB_STEP)]  # where the rule applies
    if not moved.size:
        return pos
    starts = moved + 1  # the runs that move, as positions in ``there``
    turns = np.cumsum(whole[:, moved], axis=1)
    if len(c.con0):  # no shift that a constraint would not follow (a gear's ratio, an input)
        full = np.zeros((len(c.names), starts.size))
        full[c.unknown[rows]] = turns
        for _ in range(len(c.con0)):
            broken = np.abs(c.con @ full) > 1e-9  # (constraint, run)
            if not broken.any():
                break
            full[((c.con != 0.0)[:, :, None] & broken[:, None, :]).any(axis=0)] = 0.0
        turns = full[c.unknown[rows]]
    run = np.zeros(there.size, dtype=np.int64)
    run[starts] = 1
    shift = np.concatenate([np.zeros((rows.size, 1)), turns], axis=1)[:, np.cumsum(run)]
    q = pos.q.copy()
    q[np.ix_(rows, there)] -= 2.0 * np.pi * shift
    return replace(pos, q=q)


def _sweep_numpy(
    c: Compiled,
    u: np.ndarray,
    guess: np.ndarray,
    want: np.ndarray | None,
    *,
    fast: bool,
    max_step: float,
    tol: float,
    max_iter: int,
    sing_tol: float,
) -> Positions:
    """The NumPy continuation: the fast path, else the careful one (see above)."""
    n_u, n_samples = u.shape
    options = {"max_step": max_step, "tol": tol, "max_iter": max_iter, "sing_tol": sing_tol}
    first = None
    if want is None:
        first = newton_one(c, guess[:, :1], u[:, :1], max_iter=max_iter, tol=tol)
        if first.converged[0] and first.rcond[0] < 10 * sing_tol and n_samples > 2:
            # The sweep starts at a toggle: no branch to keep there.
            split = _from_a_toggle(c, u, guess, fast=fast, **options)
            if split is not None:
                return split
        if first.converged[0] and first.rcond[0] >= sing_tol:
            want = _branch_of(first)
    if fast and want is not None and 3 <= n_samples <= FAST_MAX_SAMPLES and n_u:
        quick = _sweep_fast(c, u, guess, want, first, **options)
        if quick is not None and (quick.code == OK).all():
            return quick
        if quick is not None:  # the march held; only some samples of the fill failed
            patched = _patch(c, u, guess, quick, **options)
            if patched is not None:
                return patched
    pos = _sweep_careful(c, u, guess, want, **options)
    return _closure(c, u, _verify(c, u, pos, sing_tol))


#: The kernel's codes 0 ok, 1 no assembly, 2 singular as this module's (None: the same).
_KERNEL_CODES = (
    None
    if (OK, NO_ASSEMBLY, SINGULAR) == (0, 1, 2)
    else np.array([OK, NO_ASSEMBLY, SINGULAR], dtype=np.int8)
)

#: The NumPy continuation costs about this many four-bar closed-form poses per pose
#: (a few µs): the ``auto`` rule of :mod:`machdyn.jit` counts a sweep accordingly.
NUMPY_POSE_COST = 40


def _sweep_compiled(
    c: Compiled,
    u: np.ndarray,
    guess: np.ndarray,
    want: np.ndarray | None,
    u_rates: list[np.ndarray] | None,
    *,
    sing_tol: float,
    tol: float,
    max_iter: int,
) -> Positions | None:
    """The sweep by the compiled kernel (models of dyads and linear groups).

    None when the kernels do not serve, the model has larger groups, or the
    sweep's first sample gives no branch (a gap or a toggle there): the NumPy
    path then takes the whole sweep.
    """
    res = _jit_sweep.sweep(
        c,
        u,
        guess,
        want,
        u_rates,
        sing_tol=sing_tol,
        tol=tol,
        max_iter=max_iter,
        cost=NUMPY_POSE_COST,
    )
    if res is None:
        return None
    x, rates, points, det, rcond, gdet, grc, resid, code, group, want = res
    return Positions(
        x[c.unknown],
        code if _KERNEL_CODES is None else _KERNEL_CODES[code],
        resid,
        det,
        rcond,
        gdet,
        grc,
        group,
        want,
        rates=list(rates),
        rates_done=np.ones(code.size, dtype=bool),
        x=x,
        points=points,
    )


def _closure(c: Compiled, u: np.ndarray, pos: Positions) -> Positions:
    """``pos`` with the loop residual of the poses returned.

    (Newton's last residual was evaluated before its polishing step.)
    """
    done = np.flatnonzero((pos.code == OK) | (pos.code == SINGULAR))
    if done.size:
        x = np.empty((len(c.names), done.size))
        x[c.inputs] = u[:, done]
        x[c.unknown] = pos.q[:, done]
        f, _ = residual_and_jacobian(c, x, jacobian=False)
        pos.residual[done] = np.abs(f * c.row_weight[:, None]).max(axis=0) if f.size else 0.0
    return pos


def _verify(c: Compiled, u: np.ndarray, pos: Positions, sing_tol: float) -> Positions:
    """Every sample reported OK has the sweep's branch; compute what was skipped.

    Samples accepted at the rounding floor without a Jacobian (``lazy_first``)
    get their determinants here; any OK sample with a group on its other sign
    (which the continuation's checks should already have caught) is flagged.
    """
    if pos.want is None:
        return pos
    todo = np.flatnonzero(np.isnan(pos.rcond) & (pos.code == OK))
    if todo.size:
        x = np.empty((len(c.names), todo.size))
        x[c.inputs] = u[:, todo]
        x[c.unknown] = pos.q[:, todo]
        _, jac = residual_and_jacobian(c, x, c.unknown)
        fac = c.factor(jac)
        pos.det[todo], pos.rcond[todo] = fac.det, fac.rcond
        pos.gdet[:, todo], pos.grc[:, todo] = fac.block_det, fac.block_rcond
        pos.code[todo] = np.where(fac.rcond < sing_tol, SINGULAR, OK)
    wrong = wrong_groups(c, pos.gdet, pos.grc, pos.want, sing_tol) & (pos.code == OK)
    lost = wrong.any(axis=0)
    if lost.any():
        pos.code[lost] = LOST
        pos.group[lost] = _first_group(wrong)[lost]
        pos.q[:, lost] = np.nan
    return pos


#: Sweeps up to this many samples try :func:`_sweep_fast` first. It was measured
#: faster than the doubling waves at every size tried (3.6e3 to 1e6 samples: ~3x
#: at 3,600, ~1.5-2x at 10⁶), but when its fill fails a check the whole sweep is
#: redone by the careful path, so a hard sweep costs up to ~2x; the cap bounds
#: that waste (and the fill's memory) for huge sweeps.
FAST_MAX_SAMPLES = 2_000_000
#: The fast march stops Newton after a step this small (scaled): the pose is then
#: within ~1e-10 and is polished, and verified, with every other sample in the fill.
MARCH_STEP_TOL = 1e-5
#: A march step that predicts an angle to move this much (radians) or more is halved:
#: then the pose found is within π of the last one in the right whole turn.
MARCH_TURN = 1.0
#: Corrector steps of the fast fill (from a cubic Hermite prediction whose error
#: is O(h⁴) for a coarse step h ≤ max_step, 2–3 suffice).
FAST_ITER = 5


def _from_a_toggle(
    c: Compiled,
    u: np.ndarray,
    guess: np.ndarray,
    *,
    max_step: float,
    tol: float,
    max_iter: int,
    sing_tol: float,
    fast: bool,
) -> Positions | None:
    """A sweep whose first pose (from the guess) is at a toggle: march from elsewhere.

    At a toggle the branches meet, so a march that starts there may go on along
    either. The sweep is anchored instead at the sample whose well-conditioned
    pose lies nearest the guess, whose groups' signs become the sweep's branch,
    and marched from there to both ends. Returns None when nothing in the sweep
    is well conditioned.
    """
    every = newton(c, np.broadcast_to(guess[:, :1], (guess.shape[0], u.shape[1])), u, max_iter, tol)
    usable = every.converged & (every.rcond >= 10 * sing_tol)
    if not usable.any():
        return None
    scale = c.var_scale[c.unknown][:, None]
    distance = np.abs((every.q - guess[:, :1]) / scale).max(axis=0)
    k = int(np.argmin(np.where(usable, distance, np.inf)))
    want = _branch_of(every, k)
    options = {"max_step": max_step, "tol": tol, "max_iter": max_iter, "sing_tol": sing_tol}
    start = every.q[:, k : k + 1]
    ahead = solve_positions(c, u[:, k:], start, True, fast=fast, want=want, **options)
    back = solve_positions(c, u[:, k::-1], start, True, fast=fast, want=want, **options)

    def joined(name: str) -> np.ndarray:
        before = getattr(back, name)[..., :0:-1]  # samples k-1 … 0, put back in order
        return np.concatenate([before, getattr(ahead, name)], axis=-1)

    names = ("q", "code", "residual", "det", "rcond", "gdet", "grc", "group")
    return Positions(*(joined(name) for name in names), want=want)


# --------------------------------------------------------------------------- fast path
def _sweep_fast(
    c: Compiled,
    u: np.ndarray,
    guess: np.ndarray,
    want: np.ndarray,
    first: NewtonResult | None,
    *,
    max_step: float,
    tol: float,
    max_iter: int,
    sing_tol: float,
) -> Positions | None:
    """Continuation for a short, evenly stepped sweep with few numpy calls.

    A sequential march in plain floats over coarse samples at most ``max_step``
    apart (tangent predictor, Newton corrector, the checks of :func:`_accept`),
    then ONE batched fill of all samples: a cubic Hermite prediction from the
    coarse poses and tangents, a few Newton iterations over the whole batch, a
    polishing step, and a vectorised check of every sample (converged, well
    conditioned, every group on the sweep's branch ``want``, within a tenth of
    the input step of its prediction). Returns None, leaving the sweep to the
    careful path of :func:`solve_positions`, for an uneven sweep or a coarse
    step that fails; when only samples of the fill fail (near a toggle, a
    check), they are returned coded NO_ASSEMBLY for :func:`_patch` to re-solve
    carefully. "Evenly stepped" means equal steps along a straight line in
    input space (``np.linspace`` of every input), so that a sample's fraction
    of a coarse interval by index is its fraction by input.
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
    start = first.q[:, 0].tolist() if first is not None else guess[:, 0].tolist()
    march = _march_fast(c.scalar, start, u_c, tol, max_iter, well, want.tolist())
    if march is None:
        return None
    q_c, t_c = march

    # 2. One batched fill: cubic Hermite between the coarse neighbours, as a polynomial
    #    per coarse interval (Horner in the interval fraction t).
    q_c_arr = np.array(q_c).T  # (nq, n_coarse)
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
        fac = c.factor(jac[:, :nq])
        fresh = True
        r = np.abs(f * weight).max(axis=0)
        last = np.inf
        for _ in range(FAST_ITER):
            # Chord steps down to the rounding floor, or until they stop gaining once
            # converged (a sample whose floor lies a little higher).
            worst = r.max()
            if worst <= FLOOR or (worst <= min(tol, POLISH_FROM) and worst > 0.25 * last):
                break
            last = worst
            step = solve(fac, f)
            step *= -1.0
            x[c.unknown] += step
            terms = _step_terms(c, x, terms, step)
            f, _ = residual_and_jacobian(c, x, cols, jacobian=False, terms=terms)
            r = np.abs(f * weight).max(axis=0)
            fresh = False
        if not fresh:  # det, rcond and the derivative stage need J at the solution
            f, jac = residual_and_jacobian(c, x, cols, terms=terms)
            fac = c.factor(jac[:, :nq])
        if r.max() > FLOOR:
            # The polish: one Newton step with the factor at (within rounding of) the
            # solution takes every sample to the rounding floor.
            step = solve(fac, f)
            step *= -1.0
            step[:, ~np.isfinite(step).all(axis=0)] = 0.0
            x[c.unknown] += step
            terms = _step_terms(c, x, terms, step)
        q = x[c.unknown]
        du = span * np.maximum(t, 1.0 - t)
        far = np.abs((q - pred) / c.var_scale[c.unknown][:, None]).max(axis=0)
        good = (
            (r <= tol)
            & (fac.rcond >= well)
            & (np.sign(fac.block_det) == want[:, None]).all(axis=0)
            & (far <= 0.1 * du + 1e-7)  # (+: the march's poses are polished here)
        )
    code = np.where(good, OK, NO_ASSEMBLY).astype(np.int8)
    group = np.full(n, -1, np.int16)
    out = (q, code, r, fac.det, fac.rcond, fac.block_det, fac.block_rcond, group, want)
    if good.all():
        return Positions(*out, reuse=(terms, jac, fac))
    return Positions(*out)  # to be patched by the careful path


def _patch(
    c: Compiled, u: np.ndarray, guess: np.ndarray, fast: Positions, **careful
) -> Positions | None:
    """Re-solve the stretch of a fast sweep that holds its failed samples, carefully.

    The span runs from the last accepted sample before the first failure to the
    first accepted one after the last failure; the careful path marches it from
    the accepted pose (the guess if the sweep's first sample failed), on the
    sweep's branch. Its end must agree with the fast pose there, else None.
    """
    n = u.shape[1]
    bad = np.flatnonzero(fast.code != OK)
    lo, hi = max(int(bad[0]) - 1, 0), min(int(bad[-1]) + 1, n - 1)
    start = fast.q[:, lo : lo + 1] if fast.code[lo] == OK else guess[:, :1]
    sub = solve_positions(c, u[:, lo : hi + 1], start, True, fast=False, want=fast.want, **careful)
    if hi < n - 1 and not (
        sub.code[-1] == OK
        and np.abs((sub.q[:, -1] - fast.q[:, hi]) / c.var_scale[c.unknown]).max() <= 1e-8
    ):
        return None
    return fast.join(sub, slice(lo, hi + 1))


def _march_fast(
    ks: Scalar,
    start: list[float],
    u_c: list[list[float]],
    tol: float,
    max_iter: int,
    well: float,
    want: list[float],
) -> tuple[list, list] | None:
    """The coarse march of :func:`_sweep_fast`: poses and tangents, or None.

    The first pose from ``start``, then each from a prediction (the tangent for
    the first step, afterwards the cubic Hermite through the last two poses and
    tangents, extrapolated) and Newton. Any step that does not converge, comes
    near a toggle, has a group off the branch ``want`` or lands farther than
    half the input step from its prediction (the checks of :func:`_accept`)
    gives None.
    """

    def on_branch(fac: tuple) -> bool:
        return fac[2] >= well and all(
            (d > 0.0) == (w > 0.0) for d, w in zip(fac[3], want, strict=True)
        )

    q, ok, _, fac, jac = ks.newton(start, u_c[0], max_iter, tol, 0.5)
    if not ok or not on_branch(fac):
        return None
    tan = ks.tangent(fac, jac)
    q_c, t_c = [q], [tan]
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
        q, ok, _, fac, jac = ks.newton(pred, u_c[j], 20, tol, 0.5, MARCH_STEP_TOL)
        if not ok or not on_branch(fac):
            return None
        if max(abs(a - b) / sc for a, b, sc in zip(q, pred, ks.scale, strict=True)) > 0.5 * du:
            return None
        m0, du_prev = m1, du
        tan = ks.tangent(fac, jac)
        q_c.append(q)
        t_c.append(tan)
    return q_c, t_c


# --------------------------------------------------------------------------- careful path
def _sweep_careful(
    c: Compiled,
    u: np.ndarray,
    guess: np.ndarray,
    want: np.ndarray | None,
    *,
    max_step: float,
    tol: float,
    max_iter: int,
    sing_tol: float,
) -> Positions:
    """The general continuation: a coarse sequential march, then doubling waves."""
    n_q, n_u, n_samples = guess.shape[0], u.shape[0], u.shape[1]
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
    st = _Store(n_q, n_u, len(c.groups), n_samples, sing_tol)
    march = _March(c, tol, sing_tol, want)
    g0 = guess[:, :1]

    # 1. The first coarse sample from the guess, then a sequential march; past an
    #    assembly gap the coarse samples left are re-assembled in one batch.
    anchor, u_anchor = None, None
    i = 0
    while i < len(coarse):
        idx = int(coarse[i])
        u_b = u[:, idx : idx + 1]
        i += 1
        if anchor is None:
            trial = newton_one(c, g0, u_b, max_iter=max_iter, tol=tol)
            if not trial.converged[0]:
                continue
            if march.want is None:
                if trial.rcond[0] < sing_tol:
                    st.put(np.array([idx]), trial)  # a toggle: no branch to keep yet
                    continue
                march.want = _branch_of(trial)
            trial = fix_branches(c, trial, u_b, march.want, sing_tol, tol)
            ok, _, lost, group = _accept(c, trial, trial.q, np.zeros(1), march.want, sing_tol)
            if ok[0]:
                anchor, u_anchor = trial, u_b
                st.put(np.array([idx]), trial)
            elif lost[0]:
                st.flag(idx, LOST, group[0])
            continue
        reached = march.to(anchor, u_anchor, u_b)
        if reached is not None:
            anchor, u_anchor = reached, u_b
            st.put(np.array([idx]), reached)
            continue
        k = _reassemble(c, coarse[i - 1 :], u, anchor.q, g0, st, march, max_iter)
        if k < 0:
            break
        anchor, u_anchor = st.one(k), u[:, k : k + 1]
        i = int(np.searchsorted(coarse, k)) + 1

    # 2. Fill the rest in doubling waves; 3. look again at the samples that failed.
    if march.want is not None:
        half = stride // 2
        while half >= 1:
            new = np.arange(half, n_samples, 2 * half)
            if new.size:
                _fill(c, new, half, u, st, tol, march)
            half //= 2
        _failed_again(c, u, guess, st, march, max_iter)
    return st.result(march.want)


def _failed_again(
    c: Compiled, u: np.ndarray, guess: np.ndarray, st: _Store, march: _March, max_iter: int
) -> None:
    """Assemble the failed samples group by group: islands, and which group fails.

    :func:`assemble` puts every dyad at its root of the sweep's branch in closed
    form. Where every group is a dyad or linear, a sample it assembles is solved
    (Newton polishes it; its angles in the whole turn of the nearest good
    sample): an island of assemblability narrower than the coarse step, which
    the march stepped over. Elsewhere the first group that does not close is
    named in the sample's reason.
    """
    idx = np.flatnonzero((st.code == NO_ASSEMBLY) | (st.code == LOST))
    if idx.size == 0:
        return
    x = np.empty((len(c.names), idx.size))
    x[c.inputs] = u[:, idx]
    x[c.unknown] = guess[:, :1]
    x, failed = assemble(c, x, march.want)
    lost = st.code[idx] == LOST
    st.group[idx[~lost]] = np.where(failed[~lost] >= 0, failed[~lost], st.group[idx[~lost]])
    closed = np.isfinite(x[c.unknown]).all(axis=0)
    if not c.sign_identified or not closed.any():
        return
    idx, seed = idx[closed], x[c.unknown][:, closed]
    good = np.flatnonzero(st.good())
    if good.size:  # the whole turn of the nearest good sample
        pos = np.clip(np.searchsorted(good, idx), 1, good.size) - 1
        after = np.minimum(pos + 1, good.size - 1)
        near = np.where(np.abs(good[after] - idx) < np.abs(good[pos] - idx), good[after], good[pos])
        seed = _unwrap(c, seed, st.q[:, near])
    res = newton(c, seed, u[:, idx], max_iter=max_iter, tol=march.tol)
    ok, *_ = _accept(c, res, res.q, np.zeros(idx.size), march.want, march.sing_tol)
    st.put(idx[ok], res, ok)


def _reassemble(
    c: Compiled,
    rest: np.ndarray,
    u: np.ndarray,
    last: np.ndarray,
    guess: np.ndarray,
    st: _Store,
    march: _March,
    max_iter: int,
) -> int:
    """After an assembly gap: the first coarse sample of ``rest`` on the sweep's branch.

    Every sample of ``rest`` is assembled group by group on the sweep's branch
    (:func:`assemble`: dyads in closed form) from the last good pose, then solved
    by Newton in one batch, and those that fail again likewise from the guess;
    each pose found has its groups moved back to the branch (:func:`fix_branches`).
    The first sample so assembled is stored (its angles in the whole turn next to ``last``) and
    returned (-1: none); samples before it where only poses off the branch were
    found are flagged LOST, naming the group.
    """
    n = rest.size
    found = np.zeros(n, dtype=bool)
    off = np.full(n, -1, dtype=np.int16)
    best: dict[int, NewtonResult] = {}
    for start in (last, guess):
        todo = np.flatnonzero(~found)
        u_t = u[:, rest[todo]]
        x = np.empty((len(c.names), todo.size))
        x[c.inputs] = u_t
        x[c.unknown] = start
        seed = assemble(c, x, march.want)[0][c.unknown]
        if c.sign_identified:  # dyads and linear groups: assembled exactly, or not at all
            closed = np.isfinite(seed).all(axis=0)
            todo, seed, u_t = todo[closed], seed[:, closed], u_t[:, closed]
        seed = np.where(np.isfinite(seed), seed, start)
        res = newton(c, seed, u_t, max_iter=max_iter, tol=march.tol)
        res = fix_branches(c, res, u_t, march.want, march.sing_tol, march.tol)
        ok, _, lost, group = _accept(c, res, res.q, np.zeros(todo.size), march.want, march.sing_tol)
        if ok.any():
            k = int(np.flatnonzero(ok)[0])
            found[todo[k]] = True
            best[int(todo[k])] = res.take(slice(k, k + 1))
        off[todo[lost & (off[todo] < 0)]] = group[lost & (off[todo] < 0)]
        if (found.any() and found.argmax() == 0) or c.sign_identified:
            break  # (for dyads the guess would give the same poses)
    if not found.any():
        return -1
    k = int(found.argmax())
    for j in np.flatnonzero(off[:k] >= 0):
        st.flag(int(rest[j]), LOST, off[j])
    res = best[k]
    st.put(np.array([rest[k]]), replace(res, q=_unwrap(c, res.q, last)))
    return int(rest[k])


class _March:
    """Sequential predictor–corrector steps with step halving (size-1 batches)."""

    def __init__(self, c: Compiled, tol: float, sing_tol: float, want: np.ndarray | None) -> None:
        self.c, self.tol, self.sing_tol, self.want = c, tol, sing_tol, want

    def _step(self, a: NewtonResult, u_a: np.ndarray, u_b: np.ndarray) -> NewtonResult | None:
        c = self.c
        du_vec = u_b - u_a
        pred = a.q + np.einsum("qun,un->qn", a.tan, du_vec)
        pred = np.where(np.isfinite(pred), pred, a.q)
        res = newton_one(c, pred, u_b, max_iter=20, tol=self.tol)
        if not res.converged[0]:
            return None
        res = fix_branches(c, res, u_b, self.want, self.sing_tol, self.tol)
        res = replace(res, q=_unwrap(c, res.q, a.q))
        du = np.abs(du_vec / c.var_scale[c.inputs][:, None]).max(axis=0)
        ok, *_ = _accept(c, res, pred, du, self.want, self.sing_tol, q_from=a.q, strict=True)
        return res if ok[0] else None

    def to(self, a: NewtonResult, u_a: np.ndarray, u_b: np.ndarray) -> NewtonResult | None:
        """March from solution ``a`` (at inputs ``u_a``) to ``u_b``; None if not reached."""
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
    new = new[~good[new]]  # (the sweep's last sample is a coarse one, solved already)
    left = new - half
    right = np.minimum(new + half, n_samples - 1)  # the last sample is a coarse one
    has_left = good[left]
    has_right = good[right] & (right > new)
    if not (has_left.all() and has_right[:-1].all()):
        # A neighbour beyond failed samples (across a gap) predicts nothing useful, and
        # its angles may be whole turns away: a sample with one solved neighbour is
        # solved from that one alone; one between two failed samples is not tried (an
        # island of assemblability narrower than the coarse step may be missed) and
        # keeps their flag if they agree.
        skipped = ~has_left & ~has_right
        if skipped.any():
            lo, hi = left[skipped], right[skipped]
            same = (st.code[lo] == st.code[hi]) & (st.group[lo] == st.group[hi])
            st.flag(
                new[skipped],
                np.where(same, st.code[lo], NO_ASSEMBLY),
                np.where(same, st.group[lo], -1),
            )
        solvable = ~skipped
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
    # With no well-conditioned neighbour (or one accepted without a tangent), predict
    # its pose without the tangent.
    t_l = np.where(well_l & np.isfinite(t_l).all(axis=(0, 1)), t_l, 0.0)
    t_r = np.where(well_r & np.isfinite(t_r).all(axis=(0, 1)), t_r, 0.0)
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
    res = fix_branches(c, res, u_new, march.want, march.sing_tol, tol)
    res = replace(res, q=_unwrap(c, res.q, st.q[:, ref]))
    ok, jump, lost, group = _accept(
        c, res, pred, du, march.want, march.sing_tol, q_from=st.q[:, ref]
    )
    st.put(new[ok], res, ok)
    st.flag(new[~res.converged], NO_ASSEMBLY)
    # Suspected jumps, poses found only off the branch, and samples between two solved
    # neighbours that did not converge (a poor prediction next to a change point's
    # kink): retry a few with the sequential march, flag the rest.
    st.flag(new[jump], JUMP, group[jump])
    st.flag(new[lost], LOST, group[lost])
    stuck = ~res.converged & has_left & has_right
    for j in np.flatnonzero(jump | lost | stuck)[:64]:
        a_idx = int(ref[j])
        u_a, u_b = u[:, a_idx : a_idx + 1], u[:, new[j] : new[j] + 1]
        s = march.to(st.one(a_idx), u_a, u_b)
        if isinstance(s, NewtonResult):
            st.put(new[j : j + 1], s)
