"""Several drivers: the drivers' paths scanned for where the drawn groups stop closing.

With several drivers what the drawing reaches is a region of the drivers'
values (docs/linkage.md, "Circuit selection"; :mod:`machdyn.linkage.circuit`
says which paths a sweep takes): :func:`_path_lost` scans each path, straight
in the drivers' values, in steps of :data:`H` (:class:`_Scan`; a sweep's
stretches joined into one polyline, :class:`_Polyline`), narrows where it
leaves (:func:`_refine`), and between scanned points watches each RRR and RRP
dyad's margin (:func:`_margin`): a dip is scanned again, so an excursion
narrower than a step is found, and so is a change point on the path (flagged,
not passed). The margins serve the change points of a lone driver too
(:func:`machdyn.linkage.circuit.change_points`).
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import jit
from . import kernel
from .program import NO_ASSEMBLY, Dyad, PArm, Program, RArm, Ref

if TYPE_CHECKING:
    from .builder import Linkage
    from .sweep import _Info
    from .topology import _Model

#: Largest step of a path scan: half a degree, or 1/115 of a typical length.
H = 2.0 * np.pi / 720
#: Path points per program run of a scan (memory: a few MB per group).
CHUNK = 200_000
#: Values a bracket is cut at in each pass of :func:`_refine` (64 cells).
CUTS = 65
#: A dyad's relative margin below which a dip between two scanned points is looked at
#: closely (:meth:`_Scan.dips`): the parabola through three points may miss its least.
DIP = 1e-4


def _refine(
    a: np.ndarray, b: np.ndarray, state, at_a: Any, kept=None
) -> tuple[np.ndarray, np.ndarray]:
    """Narrow brackets ``[a, b]`` (arrays) where ``state`` changes from ``at_a`` to not.

    Each pass cuts every bracket in 64 and keeps the first cell where the state
    changes, all brackets in one call of ``state`` (:data:`CUTS` values a
    bracket): seven passes narrow them 64⁷ ≈ 4·10¹² times (a bisection needs 42
    calls for that). ``kept``, if given, hears which of its values each bracket
    starts the next pass from.
    """
    k = np.linspace(0.0, 1.0, CUTS)
    for _ in range(7):
        x = a[:, None] + (b - a)[:, None] * k
        same = state(x.ravel()).reshape(x.shape) == np.reshape(at_a, (-1, 1))
        j = np.maximum(np.argmin(same, axis=1), 1)  # the first cell past the change
        j = np.where(same.all(axis=1), CUTS - 1, j)  # (rounding: no change seen, keep the end)
        rows = np.arange(x.shape[0])
        a, b = x[rows, j - 1], x[rows, j]
        if kept is not None:
            kept(j - 1)
    return a, b


def _failing(lk: Linkage, model: _Model, info: _Info):
    """A function: driver values (drivers × m) → per group and point, it does not close.

    With ``margins`` it also returns the margin (:func:`_margin`) of each
    watched dyad (:func:`_watched`, in its order) at each point, from the same
    run of the program: the compiled kernel's when :mod:`machdyn.jit` serves
    it (or the plain-Python twin's for a pose or two; :func:`machdyn.linkage.kernel.run`,
    reporting only the points the margins are measured from, :class:`_Gauges`),
    else NumPy's, the margins read off its state.
    """
    program = model.program
    walls = [i for i, d in enumerate(lk._drivers) if d in lk._actuators]
    gauges = _gauges(model, info)

    def failing(x: np.ndarray, margins: bool = False) -> Any:
        out = np.zeros((len(program.deps), x.shape[1]), bool)
        M = np.empty((len(gauges.sides), x.shape[1])) if margins else None
        for k in range(0, x.shape[1], CHUNK):
            part = x[:, k : k + CHUNK]
            n = part.shape[1]
            with np.errstate(all="ignore"):
                if n > kernel.SCALAR_MAX and kernel.compiled_kernel(n) is None:  # NumPy
                    t = time.perf_counter()
                    st, codes = program.run([[row, 0.0, 0.0, 0.0] for row in part], n, 0, False)
                    if M is not None:
                        M[:, k : k + CHUNK] = gauges.of_state(st)
                    jit.charge(time.perf_counter() - t)
                else:
                    U = np.zeros((4 * part.shape[0], n))
                    U[0::4] = part
                    run = kernel.run(program, gauges.tables, U, 0, False)
                    codes = run.codes
                    if M is not None:
                        M[:, k : k + CHUNK] = gauges.margins(run.pts)
            out[:, k : k + CHUNK] = codes == NO_ASSEMBLY
        for i in walls:  # an actuator's length stays > 0: its group does not close
            out[_group_of_driver(model, i)] |= x[i] <= 0.0
        return out if M is None else (out, M)

    return failing


def _gauges(model: _Model, info: _Info) -> _Gauges:
    """The model's :class:`_Gauges` (of :func:`_watched`), built once."""
    if "gauges" not in model.cache:
        model.cache["gauges"] = _Gauges(_watched(model.program), info)
    return model.cache["gauges"]  # type: ignore[return-value]


class _Gauges:
    """The points the ``dyads``' margins are measured from (:func:`_gauge`), and the margins.

    ``refs``: the distinct material points; ``rows`` (dyads × 3): each dyad's
    three of them; ``sides`` (dyads × 2): its two lengths. ``tables`` report
    those points only (no link angles, no lengths), so that a run of the
    compiled kernel does little more than solve the groups.
    """

    def __init__(self, dyads: list[tuple[int, Dyad]], info: _Info | None = None) -> None:
        self.refs: list[Ref] = []
        seen: dict[Ref, int] = {}
        rows, sides = [], []
        for _, s in dyads:
            points, lengths = _gauge(s)
            rows.append([seen.setdefault(r, len(seen)) for r in points])
            sides.append(lengths)
        self.refs = list(seen)
        self.rows = np.array(rows, np.int64).reshape(-1, 3)
        self.sides = np.array(sides, float).reshape(-1, 2)
        if info is not None:
            from .kernel import Tables

            none = np.zeros(0)
            self.tables = Tables(
                np.zeros(0, np.int64),
                np.array([i for i, _ in self.refs], np.int64),
                np.array([x for _, r in self.refs for x in (r.real, r.imag)], float),
                np.zeros(0, np.int64),
                none,
                np.zeros(0, np.int8),
                none,
                info.tables.start,
                info.tables.scale,
            )

    def margins(self, P: np.ndarray) -> np.ndarray:
        """The margins (dyads × samples) given the points ``P`` (:attr:`refs` × samples)."""
        A, B, C = (P[self.rows[:, k]] for k in range(3))
        return _margin(A, B, C, self.sides)

    def of_state(self, st: Any) -> np.ndarray:
        """The margins at the samples of the program's state ``st``."""
        zero = np.zeros(st.n)
        return self.margins(np.array([st.pos(r) + zero for r in self.refs]).reshape(-1, st.n))


def _group_of_driver(model: _Model, d: int) -> int:
    """The group whose step reads driver ``d`` (an actuator: the dyad with its bar)."""
    for g, step in zip(model.program.group_of_step, model.program.steps, strict=True):
        arms = [getattr(step, a, None) for a in ("arm1", "arm2")]
        if getattr(step, "driver", -1) == d or any(getattr(a, "driver", -1) == d for a in arms):
            return g
    return 0


def _path_lost(
    lk: Linkage, model: _Model, info: _Info, U0: np.ndarray, codes: np.ndarray, follow: bool
) -> tuple[np.ndarray, np.ndarray, Any] | None:
    """Several drivers: the samples no path of the module's reaches inside where groups close.

    Returns as :func:`machdyn.linkage.circuit.off_circuit`.
    """
    n, start = U0.shape[1], info.start[:, None]
    follow = follow and n > 1  # one pose: its path is the straight one
    angle = np.array([d in info.angle_drivers for d in lk._drivers])[:, None]
    turns = np.where(angle, 2.0 * np.pi * np.round((U0 - start) / (2.0 * np.pi)), 0.0)
    ends = U0 - turns  # each sample, its angles within π of the drawn ones
    scan = _Scan(lk, model, info)
    at_end = (codes == NO_ASSEMBLY).any(axis=0)
    for i, d in enumerate(lk._drivers):
        if d in lk._actuators:
            at_end |= ends[i] <= 0.0
    k = np.arange(n)
    if follow:  # the sweep's legs: drawing → sample 0 → sample 1 ...
        along = U0 - turns[:, :1]
        prev = np.concatenate((start, along[:, :-1]), axis=1)
        leg_out, leg_who = scan.first_out(prev, along, at_end)
        broken = leg_out <= 1.0
        if not broken.any():
            return None
        todo = np.flatnonzero(~at_end & (k >= np.argmax(broken)))
    else:
        todo = np.flatnonzero(~at_end)
    straight, who = np.full(n, 2.0), np.full(n, -1)
    straight[todo], who[todo] = scan.first_out(start, ends[:, todo], at_end[todo])
    reached = ~at_end & (straight > 1.0)
    if follow:  # or reached along the sweep from the last sample reached
        last_break = np.maximum.accumulate(np.where(broken, k, -1))
        last_seed = np.maximum.accumulate(np.where(reached, k, -1))
        reached = ~at_end & (last_seed >= last_break)
    away = ~at_end & ~reached
    if not away.any():
        return None
    idx = np.flatnonzero(away)
    group, where, change = scan.exit(np.broadcast_to(start, ends[:, idx].shape), ends[:, idx],
                                     straight[idx], who[idx])  # fmt: skip
    texts = [
        scan.text(g, w, "straight path from the drawing to this input", c)
        for g, w, c in zip(group, where.T, change, strict=True)
    ]
    if follow:  # and where the sweep left after the last sample it reached
        after = np.minimum.accumulate(np.where(broken, k, n)[::-1])[::-1]  # next break from k
        legs, inverse = np.unique(after[last_seed[idx] + 1], return_inverse=True)
        g_leg, w_leg, c_leg = scan.exit(prev[:, legs], along[:, legs], leg_out[legs],
                                        leg_who[legs])  # fmt: skip
        w_leg += turns[:, :1]
        sweep = [scan.text(g, w, f"path along the sweep (before sample {j})", c)
                 for g, w, j, c in zip(g_leg, w_leg.T, legs, c_leg, strict=True)]  # fmt: skip
        texts = [f"{sweep[i]}; {t}" for i, t in zip(inverse.ravel(), texts, strict=True)]
        change = change | c_leg[inverse.ravel()]
    mark = np.zeros(codes.shape, bool)
    mark[group, idx] = True
    reason = np.empty(idx.size, object)
    word = "along them" if follow else "along it"
    reason[:] = [
        f"{t}: the mechanism cannot reach this input {word} "
        + ("on its drawn form" if c else "without being taken apart")
        for t, c in zip(texts, change, strict=True)
    ]
    return mark, away, reason


class _Scan:
    """Straight stretches of the drivers' values scanned for where a group stops closing."""

    def __init__(self, lk: Linkage, model: _Model, info: _Info) -> None:
        self.lk, self.model, self.info = lk, model, info
        self.failing = _failing(lk, model, info)
        self.scale = info.scale[:, None]
        self.dyads = _watched(model.program) or None
        self.dyad_group = np.array([g for g, _ in self.dyads or ()], np.int64)

    def steps(self, p0: np.ndarray, p1: np.ndarray) -> np.ndarray:
        """The number of steps of :data:`H` (at least one) scanning each stretch ``p0 → p1``."""
        count = np.ceil(np.max(np.abs(p1 - p0) / self.scale, axis=0) / H).astype(np.int64)
        return np.maximum(count, 1)

    def first_out(
        self, p0: np.ndarray, p1: np.ndarray, at_end: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Per stretch ``p0 → p1`` (columns): where the first group stops closing.

        Returns ``(out, who)``: the fraction of the stretch at its first point
        (steps of :data:`H`) where a group does not close, or where a watched
        dyad passes a change point (:meth:`dips`; ``who``: its group, else -1);
        1: only at its end (``at_end``); 2: nowhere. With watched dyads, stretches
        that join (one starting where the one before ends: a sweep's) are
        scanned as one polyline (:class:`_Polyline`).
        """
        p0 = np.broadcast_to(p0, p1.shape)
        out, who = np.where(at_end, 1.0, 2.0), np.full(p1.shape[1], -1)
        if not p1.shape[1]:
            return out, who
        count = self.steps(p0, p1)
        if self.dyads is not None:  # every point, margins too
            line = _Polyline(p0, p1, count)
            fail, M = self.failing(line.points(line.leg, line.frac), True)
            inner = (line.idx > 0) & (line.idx < count[line.leg])
            bad = np.flatnonzero(fail.any(axis=0) & inner)
            np.minimum.at(out, line.leg[bad], line.frac[bad])
            self.dips(line, M, ~fail.any(axis=0), out, who)
            return out, who
        # count − 1 points inside each, then its end
        leg = np.repeat(np.arange(p1.shape[1]), count - 1)
        first = np.concatenate(([0], np.cumsum(count - 1)[:-1]))
        inner = np.arange(leg.size) - np.repeat(first, count - 1) + 1
        frac = inner / np.repeat(count, count - 1)
        if leg.size:
            bad = np.flatnonzero(self.failing(p0[:, leg] + frac * (p1 - p0)[:, leg]).any(axis=0))
            np.minimum.at(out, leg[bad], frac[bad])
        return out, who

    def dips(self, line: _Polyline, M: np.ndarray, closes: np.ndarray, out, who) -> None:
        """Lower ``out`` where a dyad stops closing between two scanned points.

        A path can leave where the dyads close, and come back, between two
        points :data:`H` apart; or pass a change point of a dyad (its margin
        touching 0, closing on both sides: its two forms cross). Along the
        scanned polyline ``line`` each watched dyad's margin ``M`` (:func:`_margin`,
        at every point; ``closes`` there) is smooth but for kinks at joints:
        where the parabola through three neighbouring points of the polyline
        (all closing; across a joint too, so a sweep whose samples are one step
        apart or closer is watched between them) has its least within two
        steps of the middle one and below :data:`DIP`, those four steps are
        scanned again in 64 cells, then around that dyad's least margin (seven
        passes; each later one keeps two of the 64 cells, about 32-fold; each
        dyad that dips on its own, whatever the others' margins), until a point
        is found where a group does not close; or, failing that, that dyad's
        margin within :data:`machdyn.classify.CHANGE_POINT_RTOL` of 0 (a change
        point: ``who`` takes its group where it lowers ``out``).
        """
        idx = line.idx
        i = np.flatnonzero((idx[:-1] > 0) & (idx[1:] > 0))  # neighbours on both sides
        lo, mid, hi = M[:, i - 1], M[:, i], M[:, i + 1]
        with np.errstate(all="ignore"):
            curve = hi - 2.0 * mid + lo
            at = (lo - hi) / (2.0 * curve)  # the parabola's least, from the middle point
            least = mid - (hi - lo) ** 2 / (8.0 * curve)
            dip = (curve > 0) & (np.abs(at) <= 2.0) & (least < DIP)
        d, c = np.nonzero(dip & closes[i - 1] & closes[i] & closes[i + 1])  # which dyad, where
        k = i[c]
        first, last = line.ends(k)  # (a margin is not quite a parabola: two steps each way)
        t0, t1 = np.maximum(k - 2, first).astype(float), np.minimum(k + 2, last).astype(float)
        cut = np.linspace(0.0, 1.0, CUTS)
        at = least = np.zeros(k.size)
        for _ in range(7):
            g0, f0 = line.at(t0, last)
            keep = (f0 < out[g0]) | (line.at(t1, last)[0] != g0)  # (not past where it left)
            t0, t1, last, d, at = t0[keep], t1[keep], last[keep], d[keep], at[keep]
            least = least[keep]
            if not t0.size:
                return
            t = t0[:, None] + (t1 - t0)[:, None] * cut  # cells × CUTS
            g, f = line.at(t, last[:, None])
            fail, M = self.failing(line.points(g.ravel(), f.ravel()), True)
            bad = fail.any(axis=0).reshape(t.shape)
            hit = bad.any(axis=1)
            j = np.argmax(bad[hit], axis=1)
            _lower(out, who, g[hit, j], f[hit, j], np.full(j.size, -1))
            rows = np.arange(t0.size)
            mine = M.reshape(-1, *t.shape)[d, rows]  # the margin of the dyad that dipped
            j = np.argmin(np.where(np.isnan(mine), np.inf, mine), axis=1)
            at, least = t[rows, j], mine[rows, j]
            t0 = t[rows, np.maximum(j - 1, 0)]
            t1 = t[rows, np.minimum(j + 1, CUTS - 1)]
            t0, t1, last, d, at, least = (a[~hit] for a in (t0, t1, last, d, at, least))
            # neighbouring middle points of one dip share the cuts' lattice: once they narrow
            # to the same cells, one goes on
            one = np.unique(np.stack([d, t0, t1]), axis=1, return_index=True)[1]
            t0, t1, last, d, at, least = (a[one] for a in (t0, t1, last, d, at, least))
        # closing on both sides of a margin of 0: a change point (the dyad's forms cross)
        from ..classify import CHANGE_POINT_RTOL

        cross = np.abs(least) <= CHANGE_POINT_RTOL
        g, f = line.at(at[cross], last[cross])
        _lower(out, who, g, f, self.dyad_group[d[cross]])

    def exit(self, p0: np.ndarray, p1: np.ndarray, out: np.ndarray, who: np.ndarray):
        """Where each stretch leaves, from its first failing fraction ``out`` (as scanned).

        The first group not closing just past it (or ``who``, the dyad whose
        change point :meth:`first_out` found there), the last values where all
        close, and whether it is a change point.
        """
        a, b = np.maximum(out - 1.0 / self.steps(p0, p1), 0.0), out
        m = len(self.lk._drivers)

        def closes(x: np.ndarray) -> np.ndarray:
            f = x.reshape(p1.shape[1], -1)
            z = p0[:, :, None] + f[None] * (p1 - p0)[:, :, None]
            return ~self.failing(z.reshape(m, -1)).any(axis=0)

        a, b = _refine(a, b, closes, True)
        # the first group not closing just past the edge (at the scanned point, should
        # rounding put the edge's far side back inside)
        both = self.failing(np.concatenate((p0 + b * (p1 - p0), p0 + out * (p1 - p0)), axis=1))
        past, scanned = both[:, : out.size], both[:, out.size :]
        group = np.where(past.any(axis=0), np.argmax(past, axis=0), np.argmax(scanned, axis=0))
        # every group closes: a change point found by :meth:`dips` (never at a leg's end,
        # where ``out`` is 1 because the solve itself failed there, nor without watched dyads)
        change = ~past.any(axis=0) & ~scanned.any(axis=0) & (out < 1.0)
        if self.dyads is None:
            change[:] = False
        if change.any():  # the dyad that passed it (else, should rounding have made a point
            # found not closing close when scanned again: the dyad of the least margin there)
            _, M = self.failing(p0[:, change] + b[change] * (p1 - p0)[:, change], True)
            pick = self.dyad_group[np.argmin(np.where(np.isnan(M), np.inf, np.abs(M)), axis=0)]
            group[change] = np.where(who[change] >= 0, who[change], pick)
        return group, p0 + a * (p1 - p0), change

    def text(self, g: int, at: np.ndarray, path: str, change: bool = False) -> str:
        """``group`` and where ``path`` leaves it (or passes a change point of it)."""
        values = [
            f"{d} = {math.degrees(x):.5g}°" if d in self.info.angle_drivers else f"{d} = {x:.6g}"
            for d, x in zip(self.lk._drivers, at, strict=True)
        ]
        name = self.model.groups[g].name
        if change:
            return (
                f"the drivers' {path} passes a change point of {name} at {', '.join(values)} "
                "(its two forms cross there; with several drivers machdyn does not follow "
                "the drawn form through one)"
            )
        return f"the drivers' {path} leaves where {name} closes at {', '.join(values)}"


def _lower(out: np.ndarray, who: np.ndarray, g: np.ndarray, f: np.ndarray, by: np.ndarray):
    """``out[g] = min(out[g], f)`` (rows may repeat a ``g``), and ``who[g] = by`` where lowered."""
    order = np.lexsort((f, g))
    g, f, by = g[order], f[order], by[order]
    first = np.ones(g.size, bool)
    first[1:] = g[1:] != g[:-1]  # each stretch's least
    g, f, by = g[first], f[first], by[first]
    low = f < out[g]
    out[g[low]], who[g[low]] = f[low], by[low]


class _Polyline:
    """The points of a scan: stretches ``p0 → p1`` (columns) cut in ``count`` steps each.

    A stretch that starts where the one before it ends (a sweep's legs: drawing
    → sample 0 → sample 1 …) goes on from it: its first point is the last of
    the one before, and together they make one polyline. Each point (a row) is
    the step ``idx`` of the stretch ``leg``, at its fraction ``frac``; ``idx``
    is 0 only where a polyline begins. A position ``t`` along the polyline is a
    row where whole, and between two rows on the segment that joins them.
    """

    def __init__(self, p0: np.ndarray, p1: np.ndarray, count: np.ndarray) -> None:
        self.p0, self.d, self.count = p0, p1 - p0, count
        joined = np.zeros(count.size, np.int64)
        joined[1:] = (p0[:, 1:] == p1[:, :-1]).all(axis=0)
        size = count + 1 - joined
        self.leg = np.repeat(np.arange(count.size), size)
        self.base = np.cumsum(size) - size - joined  # each stretch's step 0 (a row)
        self.idx = np.arange(self.leg.size) - self.base[self.leg]
        self.frac = self.idx / count[self.leg]

    def ends(self, k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The first and the last row of the polyline of each row ``k``."""
        starts = np.flatnonzero(self.idx == 0)
        n = np.searchsorted(starts, k, side="right")
        last = np.append(starts[1:] - 1, self.idx.size - 1)
        return starts[n - 1], last[n - 1]

    def at(self, t: np.ndarray, last: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The stretch and fraction of each position ``t`` (its polyline ends at row ``last``)."""
        j = np.minimum(np.floor(t).astype(np.int64) + 1, last)  # the segment ending at row j
        g = self.leg[j]
        return g, np.clip((self.idx[j] - (j - t)) / self.count[g], 0.0, 1.0)

    def points(self, g: np.ndarray, f: np.ndarray) -> np.ndarray:
        """The drivers' values at the fractions ``f`` of the stretches ``g``."""
        return self.p0[:, g] + f * self.d[:, g]


def _rrr_dyads(program: Program) -> list[tuple[int, Dyad]]:
    """The RRR dyads of ``program`` (pinned to known bodies, no driven arm), with their groups."""
    return [
        (g, s)
        for g, s in zip(program.group_of_step, program.steps, strict=True)
        if isinstance(s, Dyad)
        and all(isinstance(a, RArm) and a.driver < 0 for a in (s.arm1, s.arm2))
    ]


def _watched(program: Program) -> list[tuple[int, Dyad]]:
    """The dyads whose margins a scan watches: the RRR dyads, then the RRP (and PRR) ones.

    (Pinned or guided on known bodies, no driven arm; with their groups.)
    """
    rrp = [
        (g, s)
        for g, s in zip(program.group_of_step, program.steps, strict=True)
        if isinstance(s, Dyad)
        and isinstance(s.arm1, RArm) != isinstance(s.arm2, RArm)
        and all(a.driver < 0 for a in (s.arm1, s.arm2) if isinstance(a, RArm))
    ]
    return _rrr_dyads(program) + rrp


def _gauge(s: Dyad) -> tuple[tuple[Ref, Ref, Ref], tuple[float, float]]:
    """Three material points and two lengths giving the dyad's margin (:func:`_margin`).

    RRR: its pivots (the second twice: not used) and its arms' lengths ``e, f``. RRP: its
    R arm's pivot ``A``, the line's point ``G`` and the point a unit along the
    line from it (on the same link), and ``(a, NaN)``, ``a`` the R arm's length.
    """
    a1, a2 = s.arm1, s.arm2
    if isinstance(a1, RArm) and isinstance(a2, RArm):
        return (a1.centre, a2.centre, a2.centre), (a1.length, a2.length)
    r, p = (a1, a2) if isinstance(a1, RArm) else (a2, a1)
    assert isinstance(r, RArm) and isinstance(p, PArm)
    link, G = p.G
    return (r.centre, p.G, (link, G + p.u0 / abs(p.u0))), (r.length, math.nan)


def _margins(dyads: list[tuple[int, Dyad]], st: Any) -> np.ndarray:
    """Per dyad and sample of the state ``st``: its margin (:func:`_margin`)."""
    return _Gauges(dyads).of_state(st)


def _margin(A: np.ndarray, B: np.ndarray, C: np.ndarray, sides: np.ndarray) -> np.ndarray:
    """Per dyad (rows), its relative margin from its points of :func:`_gauge`.

    Negative where it does not close, 0 at a toggle. RRR (``sides``: ``e, f``):
    ``min(D − |e − f|, e + f − D) / (e + f)``, ``D = |A − B|`` between its
    pivots; NaN where they meet (a kite's crank over the far pivot, where the
    dyad turns freely: not a crossing of its forms). RRP (``sides``: ``a``,
    NaN): ``(a − |h|) / a``, ``h`` the distance of the R arm's pivot ``A`` from
    the line through ``B`` along ``C − B`` (0 where the arm stands square to
    the line: two forms meet; a change point where that touches 0 and the
    dyad closes on both sides, as an isosceles slider-crank's).
    """
    slide = np.isnan(sides[:, 1])
    if slide.any():  # each kind's rows apart (the other formula would be wasted on them)
        m = np.empty(np.shape(A))
        for rows, fn in ((~slide, _margin_rrr), (slide, _margin_rrp)):
            if rows.any():
                m[rows] = fn(A[rows], B[rows], C[rows], sides[rows])
        return m
    return _margin_rrr(A, B, C, sides)


def _margin_rrr(A: np.ndarray, B: np.ndarray, _: np.ndarray, sides: np.ndarray) -> np.ndarray:
    e, f = sides[:, :1], sides[:, 1:]
    with np.errstate(all="ignore"):
        D = np.abs(A - B)
        m = np.minimum(D - np.abs(e - f), e + f - D) / (e + f)
        return np.where(1e-6 * (e + f) < D, m, np.nan)


def _margin_rrp(A: np.ndarray, B: np.ndarray, C: np.ndarray, sides: np.ndarray) -> np.ndarray:
    a, u = sides[:, :1], C - B
    with np.errstate(all="ignore"):
        return (a - np.abs(((A - B) * np.conj(u)).imag / np.abs(u))) / a
