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
* **Several drivers** (:func:`machdyn.linkage.paths._path_lost`): what the drawing reaches is a
  region of the drivers' values, so reaching a sample depends on the path the
  drivers take to it. For a sweep that path is the motion itself: from the
  drawn pose straight to the first sample, then sample to sample, each
  straight in the drivers' values (an angle within π of the drawn one on the
  first stretch); a sample is reached when every group closes all along it to
  that sample, and once the path has left that region no later sample is.
  Samples solved independently (grids, ``continuation=False``) each take the
  straight path from the drawing (angles within π of the drawn ones). The
  path is scanned in steps of :data:`~machdyn.linkage.paths.H` (scaled driver units: radians, or
  typical lengths) and where it leaves narrowed 64-fold seven times; between
  scanned points, where an RRR or RRP dyad's margin dips, it is scanned again
  (:mod:`machdyn.linkage.paths`): an excursion narrower than a step is found, and so is
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

from .paths import CUTS, _margins, _path_lost, _refine, _watched
from .program import NO_ASSEMBLY, General, Program

if TYPE_CHECKING:
    from .builder import Linkage
    from .sweep import _Info
    from .topology import _Model


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
    — that range (edges refined by :func:`~.paths._refine`; ±inf where a length driver's
    groups close beyond ±10 typical lengths), the first group (in solving
    order) that stops closing at its upper and at its lower end, and 2π for an
    angle (None for a length) — or None when the groups close everywhere. Not
    asked (None): several drivers (the reachable set is a region of the
    drivers' space, not a range: :func:`~machdyn.linkage.paths._path_lost`). A group the closed
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
    :func:`~.paths._refine` from its solution at the last value known to close (the
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
    """The test :func:`_ends` gives :func:`~.paths._refine`: which values close (from the last).

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
    Found once per model: each RRR and RRP dyad's margin (:func:`~.paths._margin`;
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
