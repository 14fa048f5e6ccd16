"""Which samples a drawn linkage reaches: the circuit of the drawing.

Every closed-form group keeps its drawn assembly sign at every sample, and the
vector-loop core keeps each general group's drawn branch (the sign of its
determinant); but a sign is not a circuit. Where a group stops closing (a
toggle) the mechanism stops; further on it may close again with the same sign
on its *other* circuit, which only taking the mechanism apart reaches. This
module tells which samples the drawing reaches without that
(docs/linkage.md, "Circuit selection"):

* **One driver** (:func:`_circuit`): the connected range of the driver around
  its drawn value on which every group closes — any motion of the driver from
  the drawing that stays in it; found once per model and then one comparison
  per sample. A general group closes where the core, following the driver
  from the drawing, assembles it.
* **Several drivers** (:func:`_path_lost`): what the drawing reaches is a
  region of the drivers' values, so reaching a sample depends on the path the
  drivers take to it. For a sweep that path is the motion itself: from the
  drawn pose straight to the first sample, then sample to sample, each
  straight in the drivers' values (an angle within π of the drawn one on the
  first stretch); a sample is reached when every group closes all along it to
  that sample, and once the path has left that region no later sample is.
  Samples solved independently (grids, ``continuation=False``) each take the
  straight path from the drawing (angles within π of the drawn ones). The
  path is scanned in steps of :data:`H` (scaled driver units: radians, or
  typical lengths) and where it leaves narrowed 64-fold seven times; between
  scanned points, where an RRR or RRP dyad's margin dips, it is scanned again
  (:meth:`_Scan.dips`): an excursion narrower than a step is found, and so is
  a change point on the path, which is flagged (not passed) with several drivers.
* **Change points** (:func:`change_points`, :func:`flips`): where a dyad's two
  forms cross (a parallelogram four-bar in line, an isosceles slider-crank's
  crank square to the slide), a sweep with one angle driver follows the drawn
  form by continuity, turning that dyad's assembly sign.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from . import kernel
from .program import NO_ASSEMBLY, Dyad, General, PArm, Program, RArm, Ref

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


def off_circuit(
    lk: Linkage, model: _Model, info: _Info, U0: np.ndarray, codes: np.ndarray, follow: bool
) -> tuple[np.ndarray, np.ndarray, Any] | None:
    """The samples assembled off the drawing's circuit: ``(mark, away, reason)``, or None.

    ``U0`` holds the drivers' values (one row each), ``codes`` each group's
    status per sample. ``away`` marks the samples, ``mark`` (groups × samples)
    the groups to flag there (their links and dependants become NaN) and
    ``reason`` is one text, or one per sample of ``away``.
    """
    n = codes.shape[1]
    if len(lk._drivers) == 1:
        arc = _circuit(lk, model, info)
        away = None if arc is None else _off_circuit(arc, U0[0], codes)
        if away is None:
            return None
        mark = np.zeros(codes.shape, bool)
        mark[np.ix_(arc[2], away)] = True
        return mark, away, _away_text(lk, model, info, arc)
    steps = model.program.steps
    if not n or not steps or any(isinstance(s, General) for s in steps):
        return None
    return _path_lost(lk, model, info, U0, codes, follow)


def _away_text(lk: Linkage, model: _Model, info: _Info, arc: tuple) -> str:
    """The reason of a sample outside the drawn range ``arc`` (see :func:`_circuit`)."""
    lo, hi, groups, period = arc
    span = (
        f"[{math.degrees(lo):.5g}°, {math.degrees(hi):.5g}°]"
        if period is not None
        else f"[{lo:.6g}, {hi:.6g}]"
    )
    if len(groups) == 1:
        who = f"{info.texts[groups[0]][2]} is"
    else:  # a different group stops closing at each end
        names = [model.groups[g].name for g in groups]
        who = f"{names[0]} (at {lk._drivers[0]}'s upper end) and {names[1]} (lower end) are"
    return (
        f"{who} on another circuit at this input: the drawn mechanism reaches "
        f"{lk._drivers[0]} in {span} only (it would have to be taken apart)"
    )


def _circuit(lk: Linkage, model: _Model, info: _Info) -> tuple | None:
    """The range of a lone driver that the drawn pose can reach, when it is not everything.

    Every closed-form group keeps its drawn assembly sign, but a driver value
    at which the groups close on a *separate* range (a Grashof four-bar whose
    coupler is the shortest link, driven at a rocker: two mirror arcs; a
    slider-crank driven at its slider: the block on the other side of the
    crank's pivot; the second loop of a Watt II six-bar closing on two arcs of
    the first loop's rocker swing) puts the linkage on its other circuit there,
    which no motion of the drawn mechanism reaches: moving the driver from the
    drawing, the mechanism stops where the first of its groups stops closing
    (a toggle), so what it reaches is the connected range around the drawn
    value on which *every* group closes. Returns ``(lo, hi, groups, period)``
    — that range (edges refined by :func:`_refine`; ±inf where a length driver's
    groups close beyond ±10 typical lengths), the first group (in solving
    order) that stops closing at its upper and at its lower end, and 2π for an
    angle (None for a length) — or None when the groups close everywhere. Not
    asked (None): several drivers (the reachable set is a region of the
    drivers' space, not a range: :func:`_path_lost`). A group the closed
    forms do not cover (the vector-loop core) closes where the core, following
    the driver from the drawing on the drawn branch, assembles it.
    """
    if "circuit" in model.cache:
        return model.cache["circuit"]  # type: ignore[return-value]
    arc = None
    driver = lk._drivers[0] if len(lk._drivers) == 1 else None
    steps = model.program.steps
    if driver is not None and steps:
        general = any(isinstance(s, General) for s in steps)
        t0 = float(info.start[0])
        lone = _Lone(model, driver in lk._actuators, t0, float(info.scale[0]), general)
        period = 2.0 * np.pi if driver in info.angle_drivers else None
        if period is not None:  # a turn from the drawn angle, the lower end reached below it
            n = 720
            up = t0 + np.linspace(0.0, period, n, endpoint=False)
            down = t0 - np.linspace(0.0, period, n, endpoint=False)
        else:  # ±10 typical lengths each way
            n = 721
            up = t0 + np.linspace(0.0, 10.0 * float(info.scale[0]), n)
            down = t0 - np.linspace(0.0, 10.0 * float(info.scale[0]), n)
        if general or period is None:  # (a general group: followed each way on its own)
            scans = [(x, lone(x), lone.solved) for x in (up, down)]
        else:  # down[k] is up[n - k] less a turn
            fail_up = _turn(model, info)[2]
            scans = [(up, fail_up, {}), (down, np.roll(fail_up[:, ::-1], 1, axis=1), {})]
        bad_up, bad_down = (fail.any(axis=0) for _, fail, _ in scans)
        if (bad_up.any() or bad_down.any()) and not bad_up[0]:
            arc = _ends(t0, period, scans, lone)
    model.cache["circuit"] = arc
    return arc


def _turn(model: _Model, info: _Info) -> tuple[np.ndarray, Any, np.ndarray]:
    """A lone angle driver's turn from its drawn value (720 values), the program run over it.

    Returns the values, the state and which groups do not close (groups × values);
    shared by :func:`_circuit` and :func:`change_points` (closed-form groups only).
    """
    if "turn" not in model.cache:
        x = float(info.start[0]) + np.linspace(0.0, 2.0 * np.pi, 720, endpoint=False)
        with np.errstate(all="ignore"):
            st, codes = model.program.run([[x, 0.0, 0.0, 0.0]], x.size, 0, False)
        model.cache["turn"] = (x, st, codes == NO_ASSEMBLY)
    return model.cache["turn"]  # type: ignore[return-value]


class _Lone:
    """Values of a lone driver → per group and value, whether it does not close.

    (A group after one that does not close is placed from NaN: it does not
    either.) ``wall``: the driver is an actuator, whose length stays > 0. With a
    ``general`` group (solved by the vector-loop core) the values are reached
    from the drawn value ``t0`` by continuation, as a sweep would: those above
    it in one march upwards, those below in one downwards (the core keeps the
    drawn branch, and does not close where that branch does not exist); each
    value's solution is kept (:attr:`solved`, per general step) so that values
    near one can be solved from it (:meth:`near`) instead of marching again.
    """

    def __init__(self, model: _Model, wall: bool, t0: float, scale: float, general: bool):
        self.program, self.wall, self.t0, self.scale = model.program, wall, t0, scale
        self.general = general
        self.solved: dict[int, dict[str, np.ndarray]] = {}
        # the compiled kernels follow every general group (:meth:`_FromLast.__call__`)
        steps = [s for s in self.program.steps if isinstance(s, General)]
        self.compiled = bool(steps) and all(s.compiled() for s in steps)

    def _run(self, x: np.ndarray, follow: bool, guess: Any = None) -> np.ndarray:
        with np.errstate(all="ignore"):
            st, codes = self.program.run([[x, 0.0, 0.0, 0.0]], x.size, 0, follow, guess)
        self.solved = st.solved
        out = codes == NO_ASSEMBLY
        if self.wall:
            out[0] |= x <= 0.0
        return out

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Per group and value of ``x``: it does not close (groups × values)."""
        if not self.general:
            return self._run(x, False)
        from .sweep import _path

        t0 = self.t0
        out = np.zeros((len(self.program.deps), x.size), bool)
        solved: dict[int, dict[str, np.ndarray]] = {}
        for side in (x >= t0, x < t0):
            idx = np.flatnonzero(side)
            if idx.size:
                idx = idx[np.argsort(np.abs(x[idx] - t0), kind="stable")]
                path, tags = _path(np.array([t0]), np.array([self.scale]), x[idx][None, :])
                take = np.flatnonzero(tags < 0)
                at = idx[-1 - tags[take]]
                out[:, at] = self._run(path[0], True)[:, take]
                for step, values in self.solved.items():
                    mine = solved.setdefault(step, {})
                    for var, v in values.items():
                        mine.setdefault(var, np.full(x.size, np.nan))[at] = v[take]
        self.solved = solved
        return out

    def near(self, x: np.ndarray, seeds: dict[int, dict[str, np.ndarray]]) -> np.ndarray:
        """As a call, each value of ``x`` solved alone from the solution ``seeds`` (per value).

        A general group's core starts from a nearby value's solution (where the
        drawn circuit closes) and must land on the drawn branch; closed-form
        groups are solved as always.
        """
        return self._run(x, False, seeds if self.general else None)

    def follow(self, x: np.ndarray, seeds: dict[int, dict[str, np.ndarray]]) -> np.ndarray:
        """As a call, the values of ``x`` followed from the first's solution ``seeds``."""
        return self._run(x, True, seeds)


def _pick(solved: dict[int, dict[str, np.ndarray]], idx: Any) -> dict[int, dict[str, np.ndarray]]:
    """The solutions of :attr:`_Lone.solved` at the values ``idx``."""
    return {s: {v: a[idx] for v, a in values.items()} for s, values in solved.items()}


def _ends(t0: float, period: float | None, scans: list, lone: _Lone) -> tuple | None:
    """Refine the first failing value of each scan (both at once) to the range's ends.

    ``scans``: the upward and the downward scan, each ``(values, failing, solved)``
    as :class:`_Lone` gives them. A general group's core starts each pass of
    :func:`_refine` from its solution at the last value known to close (the
    scan's, then each pass's): no pass marches from the drawing again.
    """
    a, b, there, seeds = [], [], [], []
    for x, fail, solved in scans:
        bad = fail.any(axis=0)
        k = int(np.argmax(bad)) if bad.any() else x.size  # a closes, b does not
        a.append(x[k - 1])
        b.append(x[min(k, x.size - 1)])
        there.append(fail[:, min(k, x.size - 1)])
        seeds.append(_pick(solved, k - 1))
    rows = {
        s: {v: np.array([sd[s][v] for sd in seeds]) for v in vs} for s, vs in scans[0][2].items()
    }
    closes = _FromLast(lone, np.array(a), rows)
    a, b = _refine(np.array(a), np.array(b), closes, True, closes.keep)
    # the first group (solving order) not closing just past each end (at the scanned
    # value, should a core's Newton still close one just past a toggle)
    closes(b)
    past, there = closes.failed, np.stack(there, axis=1)
    first = np.where(past.any(axis=0), past, there)
    ends, groups = [], []
    for i, (x, fail, _) in enumerate(scans):
        if fail.any():
            ends.append(float(a[i]))
            groups.append(int(np.argmax(first[:, i])))
        else:
            ends.append(math.copysign(math.inf, x[-1] - t0))
    hi, lo = ends
    if period is not None and hi - lo >= period - 1e-9:
        return None
    return lo, hi, tuple(dict.fromkeys(groups)), period


class _FromLast:
    """:func:`_refine`'s test for :func:`_ends`: which values close, each from where it last did.

    NumPy (:meth:`_Lone.near`): every value solved alone from the solution at its
    bracket's last value known to close, each pass's (:meth:`keep`). Where the
    compiled kernels follow every general group (dyads of the core, assembled on
    the drawn branch in closed form), each bracket's values are followed from the
    scan's last value that closed instead (its solution the start).
    """

    def __init__(self, lone: _Lone, start: np.ndarray, seeds: dict[int, dict[str, np.ndarray]]):
        self.lone, self.start, self.seeds = lone, start, seeds  # one value and seed per bracket
        self.solved = self.first = {s: dict(vs) for s, vs in seeds.items()}

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Per value of ``x`` (each bracket's in turn, as many each), whether all close."""
        rows = self.start.size
        per = x.size // rows
        if not self.lone.compiled:
            guess = {
                s: {v: np.repeat(a, per) for v, a in vs.items()} for s, vs in self.seeds.items()
            }
            self.failed = self.lone.near(x, guess)
            self.solved = self.lone.solved
            return ~self.failed.any(axis=0)
        fails, solved = [], []
        for r, part in enumerate(x.reshape(rows, per)):
            path = np.concatenate(([self.start[r]], part))
            guess = {s: {v: np.full(path.size, a[r]) for v, a in vs.items()}
                     for s, vs in self.first.items()}  # fmt: skip
            fails.append(self.lone.follow(path, guess)[:, 1:])
            solved.append(_pick(self.lone.solved, slice(1, None)))
        self.solved = {
            s: {v: np.concatenate([d[s][v] for d in solved]) for v in vs}
            for s, vs in self.first.items()
        }
        self.failed = np.concatenate(fails, axis=1)
        return ~self.failed.any(axis=0)

    def keep(self, j: np.ndarray) -> None:
        """Each bracket goes on from its value ``j`` (one that closed: a solution)."""
        flat = np.arange(j.size) * CUTS + j
        for s, vs in self.seeds.items():
            for v, old in vs.items():
                new = self.solved[s][v][flat]
                vs[v] = np.where(np.isfinite(new), new, old)  # (j = 0: the row's own start)


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


def _off_circuit(arc: tuple, theta: np.ndarray, codes: np.ndarray):
    """The samples assembled outside the drawn range, on the other circuit (None: none)."""
    lo, hi, _, period = arc
    if period is None:
        tol = 1e-9 * (1.0 + max(abs(v) for v in (lo, hi) if math.isfinite(v)))
        away = (theta < lo - tol) | (theta > hi + tol)
    else:
        away = np.remainder(theta - lo, period) > (hi - lo) + 1e-9 * (1.0 + abs(hi))
    if not away.any():
        return None
    away &= ~(codes == NO_ASSEMBLY).any(axis=0)  # in the gap between: "does not close" stays
    return away if away.any() else None


# ------------------------------------------------------------- several drivers
def _failing(lk: Linkage, model: _Model, info: _Info):
    """A function: driver values (drivers × m) → per group and point, it does not close.

    With ``margins`` it also returns the margin (:func:`_margin`) of each
    watched dyad (:func:`_watched`, in its order) at each point. One run of
    the program serves both, by whichever engine
    :func:`machdyn.linkage.kernel.run` picks (the compiled kernel when it
    serves): it reports only the points the margins are measured from
    (:func:`_gauges`).
    """
    program = model.program
    walls = [i for i, d in enumerate(lk._drivers) if d in lk._actuators]
    tables, sides = _gauges(model, info, _watched(program))

    def failing(x: np.ndarray, margins: bool = False) -> Any:
        out = np.zeros((len(program.deps), x.shape[1]), bool)
        M = np.empty((len(sides), x.shape[1])) if margins else None
        for k in range(0, x.shape[1], CHUNK):
            part = x[:, k : k + CHUNK]
            U = np.zeros((4 * part.shape[0], part.shape[1]))
            U[0::4] = part
            with np.errstate(all="ignore"):
                run = kernel.run(program, tables, U, 0, False)
                if M is not None:  # (each dyad's three points in turn)
                    P = run.pts
                    M[:, k : k + CHUNK] = _margin(P[0::3], P[1::3], P[2::3], sides)
            out[:, k : k + CHUNK] = run.codes == NO_ASSEMBLY
        for i in walls:  # an actuator's length stays > 0: its group does not close
            out[_group_of_driver(model, i)] |= x[i] <= 0.0
        return out if M is None else (out, M)

    return failing


def _gauges(model: _Model, info: _Info, dyads: list[tuple[int, Dyad]]) -> tuple[Any, np.ndarray]:
    """Run tables that report only the points the ``dyads``' margins are measured from.

    Returns ``(tables, sides)``: the tables' points are each dyad's three
    points of :func:`_gauge` in turn (rows ``3j`` to ``3j + 2`` for dyad ``j``),
    ``sides`` (dyads × 2) its two lengths. No link angles or lengths are
    reported, so a scan's run does little more than solve the groups.
    """
    if "gauges" not in model.cache:
        from .kernel import Tables

        gauges = [_gauge(s) for _, s in dyads]
        refs = [r for points, _ in gauges for r in points]
        none = np.zeros(0)
        tables = Tables(
            np.zeros(0, np.int64),
            np.array([i for i, _ in refs], np.int64),
            np.array([x for _, r in refs for x in (r.real, r.imag)], float),
            np.zeros(0, np.int64),
            none,
            np.zeros(0, np.int8),
            none,
            info.tables.start,
            info.tables.scale,
        )
        sides = np.array([lengths for _, lengths in gauges], float).reshape(-1, 2)
        model.cache["gauges"] = (tables, sides)
    return model.cache["gauges"]  # type: ignore[return-value]


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

    Returns as :func:`off_circuit`.
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

    RRR: its pivots (the second twice) and its arms' lengths ``e, f``. RRP: its
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
    gauges = [_gauge(s) for _, s in dyads]
    zero = np.zeros(st.n)
    P = [[st.pos(r) + zero for r in points] for points, _ in gauges]
    sides = np.array([lengths for _, lengths in gauges], float).reshape(-1, 2)
    return _margin(*(np.array([p[k] for p in P]).reshape(-1, st.n) for k in range(3)), sides)


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
    e, f = sides[:, :1], sides[:, 1:]
    with np.errstate(all="ignore"):
        D = np.abs(A - B)
        m = np.where(1e-6 * (e + f) < D, np.minimum(D - np.abs(e - f), e + f - D) / (e + f), np.nan)
        u = C - B
        h = ((A - B) * np.conj(u)).imag / np.abs(u)
        return np.where(np.isnan(f), (e - np.abs(h)) / e, m)


# -------------------------------------------------------------- change points
def change_points(lk: Linkage, model: _Model, info: _Info) -> tuple[tuple[int, float], ...]:
    """Where a dyad passes a change point, for a lone angle driver: ``(group, value)`` pairs.

    At a change point (a four-bar with ``s + l = p + q``: all its pivots in
    line) a dyad's two circles touch while it closes on both sides: its two
    forms (a parallelogram's and an antiparallelogram's) meet and cross there;
    so do an RRP dyad's where its rod's circle touches the slide line (an
    isosceles slider-crank, crank = rod, with the crank square to the slide).
    Holding the drawn assembly sign through it would go on along the *other*
    form; the drawn form goes on smoothly (the coupler angle and its rate
    continuous: a parallelogram's coupler stays parallel to the ground) with
    the other sign, and that is the one a sweep follows (:func:`flips`).
    Found once per model: each RRR and RRP dyad's margin (:func:`_margin`;
    an RRR dyad's ``min(D − |e − f|, e + f − D)``, ``D`` between its pivots,
    relative to ``e + f``) over a turn of the driver
    (720 values), every dip that closes on both sides narrowed 32-fold seven
    times; a change point where its least margin is within
    :data:`machdyn.classify.CHANGE_POINT_RTOL` of zero. Values in
    ``[drawn, drawn + 2π)``.
    """
    if "change points" in model.cache:
        return model.cache["change points"]  # type: ignore[return-value]
    from ..classify import CHANGE_POINT_RTOL

    program, found = model.program, []
    dyads = _watched(program)
    one = len(lk._drivers) == 1 and lk._drivers[0] in info.angle_drivers
    if one and dyads and not any(isinstance(s, General) for s in program.steps):

        def margins(x: np.ndarray, st: Any = None) -> np.ndarray:
            if st is None:
                with np.errstate(all="ignore"):
                    st, _ = program.run([[x, 0.0, 0.0, 0.0]], x.size, 0, False)
            return np.broadcast_to(_margins(dyads, st), (len(dyads), x.size))

        x, st, _ = _turn(model, info)
        step = x[1] - x[0]
        M = margins(x, st)
        for i, (g, _) in enumerate(dyads):
            m, before, after = M[i], np.roll(M[i], 1), np.roll(M[i], -1)
            dip = (m <= before) & (m <= after) & (before > 0) & (after > 0) & (m < 1e-3)
            for k in np.flatnonzero(dip):
                lo, hi = x[k] - step, x[k] + step
                for _ in range(7):
                    z = np.linspace(lo, hi, 65)
                    mz = margins(z)[i]
                    if np.isnan(mz).all():
                        break
                    j = int(np.nanargmin(mz))
                    lo, hi = z[max(j - 1, 0)], z[min(j + 1, 64)]
                if np.isfinite(mz).any() and abs(mz[j]) <= CHANGE_POINT_RTOL:
                    found.append((g, x[0] + float(np.remainder(z[j] - x[0], 2.0 * np.pi))))
    model.cache["change points"] = out = tuple(found)
    return out


def flips(
    lk: Linkage, model: _Model, info: _Info, x: np.ndarray, follow: bool
) -> list[tuple[Program, np.ndarray]]:
    """The samples past an odd number of a dyad's change points, and the program for them.

    A sample's path from the drawn value crosses the change points between the
    two (a sweep's values as given; samples solved independently take the
    value within π of the drawn one); past an odd number of a dyad's, the
    drawn form has the other assembly sign there. Returns ``(program, mask)``
    per combination of dyads to flip (the program with those signs turned).
    """
    points = change_points(lk, model, info)
    if not points:
        return []
    t0 = float(info.start[0])
    if not follow:
        x = x - 2.0 * np.pi * np.round((x - t0) / (2.0 * np.pi))
    odd: dict[int, np.ndarray] = {}
    for g, c in points:
        turns = (x - c) / (2.0 * np.pi)
        count = np.where(
            x >= t0, np.maximum(0.0, np.ceil(turns)), np.maximum(0.0, -1.0 - np.floor(turns))
        )
        odd[g] = odd.get(g, 0) + count.astype(np.int64)
    groups = sorted(odd)
    pattern = np.stack([odd[g] % 2 for g in groups])  # (groups, samples)
    out = []
    for combo in np.unique(pattern, axis=1).T:
        if not combo.any():
            continue
        mask = (pattern == combo[:, None]).all(axis=0)
        flip = frozenset(g for g, c in zip(groups, combo, strict=True) if c)
        key = ("flipped", flip)
        if key not in model.cache:
            from dataclasses import replace

            program = model.program
            steps = [
                replace(s, sign=-s.sign) if g in flip else s
                for g, s in zip(program.group_of_step, program.steps, strict=True)
            ]
            model.cache[key] = replace(program, steps=steps)
        out.append((model.cache[key], mask))
    return out
