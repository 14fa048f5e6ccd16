"""Path synthesis of six-bars from a six-bar atlas: place, refine, check, build the Linkage.

Rounds of starts (placed atlas entries) are screened and the best polished until one
meets the targets and the Linkage's check finds no defect (:func:`_sixbar_path`,
called by :func:`machdyn.synthesis.path_from_atlas` on a six-bar atlas). The six-bar's
design (15 numbers), its coupler point with derivatives (forward mode), its refinement
and its Linkage live in :mod:`~machdyn.synthesis._sixbar_refine`; the starts of each
round (retrieval, the timed scan, the neighbour and kind rounds, the loop-by-loop fits
of Watt II "1-4" six-bars) in :mod:`~machdyn.synthesis._sixbar_starts`. This module
holds the rounds, the polish, the Linkage's check (:func:`sixbar_result`), the result
(:class:`SixBarPath`) and the constants they read; it re-imports the names tests and
docs take from here. A test that patches a name patches the module that reads it
(``sixbar_starts`` and ``polished_sixbars`` are read here).
The results are :class:`~machdyn.linkage.Linkage` objects drawn in the plane;
their distances to the targets are measured by the Linkage's own solver.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ModelError
from ._atlas_index import _NEVER
from ._atlas_result import NEAR, PathCandidates, _far_note, _limit_note, _rank
from ._sixbar_refine import (  # noqa: F401  (re-imported: tests and docs take them from here)
    DAMPING_FLOOR,
    _joints,
    coupler_function,
    refine_sixbar,
    sixbar_coupler,
    sixbar_linkage,
)
from ._sixbar_starts import (  # noqa: F401  (re-imported: tests and docs take them from here)
    SIXBAR_CRAWL,
    SIXBAR_KIND_BAND,
    SIXBAR_KIND_POOL,
    SIXBAR_NEIGHBOURS,
    SIXBAR_UNTRIED,
    _design_of,
    _kind_pool,
    _kind_round,
    _neighbour_starts,
    _ordered_samples,
    second_loop_fits,
    sixbar_starts,
)
from .sixbar import TOPOLOGIES

# Internal to machdyn.synthesis, which re-exports the public names (Atlas, build_atlas,
# open_atlas, path_from_atlas, curve_descriptor, ...); the fuzz suite fuzzes those.
__all__: list[str] = []


@dataclass(frozen=True, eq=False)
class SixBarPath:
    """A six-bar found by path synthesis, checked by the Linkage solver.

    Attributes
    ----------
    linkage : machdyn.linkage.Linkage
        Drawn in the plane at the first target's crank angle; driver ``crank``.
    chain : str
        ``"Watt I"``, ``"Watt II"`` or ``"Stephenson"`` and the dyad's links.
    design : ndarray, shape (15,)
        ``O2x O2y θ1 r1 r2 r3 r4 cu cv du dv a b pu pv``.
    targets, theta2, distance : ndarray
        Targets, crank angle (from the ground line) at each, distance to the curve.
    defects : tuple of str
    """

    linkage: Any
    chain: str
    design: np.ndarray
    fixed: dict
    targets: np.ndarray
    theta2: np.ndarray
    distance: np.ndarray
    defects: tuple[str, ...]
    barker_class: str = ""
    is_crank: bool = True
    mu_min: float = float("nan")
    in_order: bool = True

    @property
    def ok(self) -> bool:
        """True when no defect was found."""
        return not self.defects


#: Six-bars: starts screened per refined candidate, and steps of each polished one.
SIXBAR_SCREEN = 4
SIXBAR_POLISH = 600
#: Six-bars: most fits polished while none meets the targets (of 20 random timed six-bars
#: of the benchmark, none was met from a fit screened below the 23rd; a miss polished all).
SIXBAR_POLISH_MAX = 24
#: Six-bars with prescribed timing: starts screened per refined candidate, most fits polished.
SIXBAR_TIMED = (16, 96)
#: Six-bars: when none meets the targets, the best few fits polished this many steps more
#: (compiled kernels only; untimed too since a Watt II 1-4 fit at 3.8e-6 crawled to 3e-14).
SIXBAR_LONG = (2, 6000)
#: A six-bar whose RMS distance is below this share of the size meets the targets.
SIXBAR_MET = 1e-12
#: Six-bars: a fit this near (RMS over the size) takes no more rounds of starts (its valley
#: is polished longer instead; see sixbar_path.SIXBAR_ROUNDS). Not a fit the Linkage's check
#: rejected: 8 timed open points (16 equations, 16 unknowns) have exact fits that cannot turn
#: their crank (seed 2026's open timed six-bar 21 stopped at 9.1e-6 behind two such).
SIXBAR_NEAR = 1e-8
#: An untimed target whose best fit after its first two rounds and their long polish is
#: within this share of the size at every target (the Linkage's distances) and without
#: defect takes no third round (the wider retrieval, SIXBAR_WIDER): the target is met to
#: the tolerance a recovery asks for, and the third round's starts (1.0-1.7 s of CPU) only
#: escape local minima far from it. Over seeds 2026, 7, 13 and 17 (240 untimed targets of
#: the benchmark) six reached a third round: with the best fit before it at 1.5e-4–3.3e-3
#: (RMS over the size) the third round met three, and one stays missed (8.2e-4); seed
#: 2026's six-bar 6 (5.4e-7, largest distance 9.4e-7) gained nothing from it in 1.25 s, and
#: seed 7's six-bar 59 (1.1e-7) ends at 2.0e-7 without it instead of 2.8e-13.
SIXBAR_WITHIN = 1e-6
#: Rounds of starts while no fit meets the targets (untimed, timed). The second round of a
#: timed target scans the first pool again on grids of starting angles turned by half a
#: step (the best-scoring entries and angles change, and with them the basins the starts
#: lie in); its third is a neighbour round (:func:`_neighbour_starts`: entries nearest to
#: its best fits in their design numbers, placed as those fits are), its fourth and fifth
#: are kind rounds (:func:`_kind_round`): entries of the kinds of its best fits. A later
#: round of an untimed target takes the next-best-placed entries of a retrieval
#: :data:`SIXBAR_WIDER` times wider than the round before. An untimed third round and a
#: timed fifth run only when the rounds before leave a target unmet, and their best fits
#: polished long too (:data:`SIXBAR_GATE`).
SIXBAR_ROUNDS = (3, 6)  # untimed, timed
#: From this round of starts on (0 the first; untimed, timed), a round runs only when the
#: best fits so far, polished long (:data:`SIXBAR_LONG`, as after the rounds; each fit
#: once), still leave the targets unmet. Seed 2026's timed six-bar 43: its best fit after
#: three rounds (3.1e-7 of the size, from the first) polished to 9e-16, and the fourth round
#: it had run for nothing; of the untimed targets two rounds leave unmet, most are met by
#: that polish.
SIXBAR_GATE = (2, 4)
#: Kind rounds: fits polished per kind scanned (the kinds:
#: :data:`~machdyn.synthesis._sixbar_starts.SIXBAR_KIND_BAND`, whose note gives the measurements).
SIXBAR_KIND_POLISH = 16
#: A later round of a timed target: steps every start is refined before the fits are ranked
#: (the first round: 30), and most fits polished. Thirty steps rank poorly among six-bars'
#: many near-fits: the one start of a missed timed Watt I 3-4 on 6 that converged ranked
#: 452nd of 539 after 30 steps (112th of 160 in the second round), 40th (8th) after 100 and
#: first after 300. A later round has only the first pool's starts: it can afford to screen
#: them longer, and polishes half as many (the time of a miss stays as it was).
SIXBAR_LATER_TIMED = (100, 48)
#: Timed targets without the compiled kernels (``MACHDYN_JIT=off``, whose NumPy refinement
#: costs ~6 times more a step): starts screened per refined candidate and most fits
#: polished, one round, no long polish (docs/synthesis.md gives the times and rates).
SIXBAR_TIMED_NUMPY = (4, 24)
#: The neighbour round's screening steps and most fits polished (as :data:`SIXBAR_LATER_TIMED`):
#: its starts lie around a fit, and those in the truth's basin lead after few steps (six-bar
#: 39's three met starts of 40 ranked first to third after 30, 60 or 100 steps).
SIXBAR_NEIGHBOUR_POLISH = (30, 16)


def polished_sixbars(starts, pts, most, check, steps, *, timing=None, compiled=False,
                     screen=30):  # fmt: skip
    """Fits ``(x, θ, rms, fixed)`` from ``starts``, screened and polished; whether one is met.

    Every start is refined ``screen`` steps; then the fits are polished (``steps`` more)
    best first — up to
    ``most`` of them — until one meets the targets to rounding and ``check(fit)``
    (the Linkage's) finds no defect: the screen's order is a poor guide among
    six-bars, whose near-fits abound, and an exact fit may be a six-bar that
    cannot turn its crank (the untimed fits form a family).
    """
    from ._atlas_result import POLISH

    size = float(np.max(np.abs(pts - pts.mean())))
    options = dict(timing=timing, compiled=compiled)
    fits = [(*refine_sixbar(x0, th0, fx, pts, iterations=screen, **options), fx)
            for x0, th0, fx in starts]  # fmt: skip
    fits.sort(key=lambda f: f[2])
    met = False
    for i, (x, th, rms, fx) in enumerate(fits[: max(POLISH, most)]):
        if i >= POLISH and met:
            break
        more = refine_sixbar(x, th, fx, pts, iterations=steps, **options)
        fits[i] = (*more, fx) if more[2] <= rms else fits[i]
        if fits[i][2] <= SIXBAR_MET * size:
            res = check(fits[i])
            met = met or (res is not None and res.ok)
    return fits, met


def sixbar_result(x, theta, fixed, pts, timing, closed, tolerance, mu_min=0.0) -> SixBarPath | None:
    """Check a refined six-bar with the Linkage solver; None if it cannot be built.

    Defects: the crank cannot turn fully, the targets are met out of order, a
    target where the six-bar comes apart (its distance is then ``inf``) or stands
    at a toggle (its distance measured), a target farther than ``tolerance``,
    and a transmission angle (of either dyad, over the whole turn, by
    :meth:`machdyn.linkage.Linkage.transmission_angles`) below ``mu_min``.
    """
    from ._atlas_checks import _in_order

    theta = np.mod(theta, 2 * np.pi)
    try:
        lk = sixbar_linkage(x, fixed, float(theta[0]))
    except Exception:  # a drawing the Linkage refuses (coincident joints …)
        return None
    try:
        m = lk.solve(x[2] + theta, continuation=False)
        turn = lk.solve(x[2] + theta[0] + np.linspace(0, 2 * np.pi, 361))
    except ModelError:  # drawn at a toggle: its branches meet there, neither can be followed
        return None
    # at a toggle (a dyad's two links in line) the Linkage places the joints but takes no
    # derivatives (not ok): the coupler point is there, so is its distance
    P = np.asarray(m.points["P"])
    placed = m.ok | np.isfinite(P)
    distance = np.where(placed, np.abs(P - pts), np.inf)
    defects = []
    mu = float("nan")
    if not np.all(turn.ok):
        defects.append("the six-bar cannot be driven round a whole turn of the crank")
    else:
        angles = [np.asarray(a, float) for a in lk.transmission_angles(turn).values()]
        if angles:
            mu = float(np.nanmin(np.concatenate(angles)))
        if mu < mu_min - np.radians(0.5):
            defects.append(f"transmission angle falls to {np.degrees(mu):.1f} deg")
    in_order = _in_order(theta, closed, timing)
    if not in_order:
        defects.append("order defect: the coupler point meets the targets out of order")
    if not np.all(placed):
        apart = [int(i) + 1 for i in np.flatnonzero(~placed)]
        defects.append(f"the linkage cannot be assembled at targets {apart}")
    if not np.all(m.ok[placed]):
        dead = [int(i) + 1 for i in np.flatnonzero(placed & ~m.ok)]
        defects.append(f"at targets {dead} the six-bar stands at a toggle (a dyad's two links "
                       "in line: a dead point, where its derivatives are undefined)")  # fmt: skip
    if tolerance is not None:
        far = np.flatnonzero(~(distance <= tolerance))
        if far.size:
            defects.append(f"targets {[int(i) + 1 for i in far]} are farther than {tolerance:g}")
    (l1, l2), chain = TOPOLOGIES[fixed["topology"]]
    name = f"{chain} (dyad on links {l1} and {l2}, point on link {fixed['on']})"
    return SixBarPath(lk, name, x, fixed, pts, theta, distance, tuple(defects), mu_min=mu,
                      in_order=in_order)  # fmt: skip


def _sixbar_path(atlas, pts, timing, closed, n, tolerance, mu_min, retrieve, refine_count, client,
                 start, deadline=_NEVER):  # fmt: skip
    """:func:`path_from_atlas` on a six-bar atlas (:mod:`machdyn.synthesis.sixbar_path`)."""
    from .. import jit

    size = float(np.max(np.abs(pts - pts.mean())))
    compiled = jit.active()  # (path_from_atlas loaded the kernels unless they are off)
    # six-bars: many atlas entries draw nearly the same curve, so many are screened; timed
    # targets many more (their fit is over-determined: real local minima near the truth)
    screen, most = (SIXBAR_SCREEN, SIXBAR_POLISH_MAX) if timing is None else SIXBAR_TIMED
    rounds, long = SIXBAR_ROUNDS[timing is not None], SIXBAR_LONG if compiled else (0, 0)
    if not compiled and timing is not None:  # MACHDYN_JIT=off: the NumPy loop's smaller budget
        (screen, most), rounds = SIXBAR_TIMED_NUMPY, 1
    elif not compiled:  # (untimed: no third round, whose placements cost seconds in NumPy)
        rounds = min(rounds, 2)
    options = dict(timing=timing, compiled=compiled)
    checked: dict[int, Any] = {}  # the Linkage's check of the fits met so far, by id

    def check(fit):
        if id(fit) not in checked:
            checked[id(fit)] = (fit, sixbar_result(fit[0], fit[1], fit[3], pts, timing, closed,
                                                   tolerance, mu_min))  # fmt: skip
        return checked[id(fit)][1]

    def alive(fit) -> bool:
        """Whether a fit is unchecked, or checked and found without defect.

        A fit the check rejected (an exact one that cannot turn its crank, say) is no lead:
        it neither ends the rounds (as near) nor picks their kinds, nor is polished long.
        """
        return id(fit) not in checked or getattr(checked[id(fit)][1], "ok", False)

    def live(fits):
        return [f for f in fits if alive(f)]

    def recovered(fit) -> bool:
        """Whether ``fit`` is without defect and within :data:`SIXBAR_WITHIN` (the Linkage's)."""
        res = check(fit)
        return bool(getattr(res, "ok", False) and np.max(res.distance) <= SIXBAR_WITHIN * size)

    polished: dict[int, Any] = {}  # the fits polished long so far, by id

    def polish_long(order):
        """Polish ``fits[i]`` for ``i`` in ``order`` :data:`SIXBAR_LONG` steps (once each)."""
        met = False
        for i in order:
            if id(fits[i]) in polished:
                continue
            x, th, rms, fx = fits[i]
            more = refine_sixbar(x, th, fx, pts, iterations=long[1], **options)
            fits[i] = (*more, fx) if more[2] <= rms else fits[i]
            polished[id(fits[i])] = fits[i]
            if fits[i][2] <= SIXBAR_MET * size:
                met = met or getattr(check(fits[i]), "ok", False)
        return met

    fits, loop, met, near, seen, scan, memo = [], [], False, False, set(), 0.0, {}
    t_begin = time.perf_counter()
    for round_ in range(rounds):  # rounds of fresh starts while none meets the targets
        gate = SIXBAR_GATE[timing is not None]
        crawl = min((f[2] for f in live(fits)), default=np.inf) <= SIXBAR_CRAWL * size
        if timing is None and round_ >= gate and crawl:
            break  # an untimed fit crawling to the targets: the long polish's, not a wider round
        if round_ >= gate and long[0] and not (met or near or deadline.passed()):
            # a late round only while the best fits, polished long, leave the targets unmet
            fits.sort(key=lambda f: f[2])
            met = polish_long([i for i, f in enumerate(fits) if alive(f)][: long[0]])
        if met or near or (round_ and deadline.passed()):
            break
        best = min(live(fits), key=lambda f: f[2], default=None)
        if timing is None and round_ >= gate and best is not None and recovered(best):
            break  # an untimed fit already within SIXBAR_WITHIN at every target: no wider round
        t0 = time.perf_counter()
        starts = sixbar_starts(atlas, pts, timing, closed, retrieve, screen * refine_count,
                               client, compiled, round_, live(fits), memo=memo)  # fmt: skip
        starts = [s for s in starts if s[0].tobytes() not in seen]
        seen.update(s[0].tobytes() for s in starts)
        scan += time.perf_counter() - t0
        steps = SIXBAR_POLISH // 2 if round_ else SIXBAR_POLISH  # later rounds: shorter
        later = SIXBAR_LATER_TIMED if round_ and timing is not None else (30, most)
        if round_ == 2 and timing is not None:  # the neighbour round
            later = SIXBAR_NEIGHBOUR_POLISH
        if round_ > 2 and timing is not None:  # a kind round: polished per kind scanned
            per_kind = SIXBAR_KIND_POLISH if round_ < 5 else SIXBAR_UNTRIED[2]
            later = (later[0], per_kind * max(1, len(memo.get("round_kinds", ()))))
        more, met = polished_sixbars(starts, pts, later[1], check, steps, screen=later[0],
                                     **options)  # fmt: skip
        fits += more
        best = min(fits, key=lambda f: f[2], default=None)
        if (
            timing is None
            and not (met or loop or deadline.passed())
            and best
            and best[3]["topology"] == 1
        ):
            # untimed Watt II 1-4 (two four-bars in series) unmet: fitted loop by loop, once
            loop = second_loop_fits(fits, pts, compiled)
            fits += loop
            met = any(f[2] <= SIXBAR_MET * size and getattr(check(f), "ok", False) for f in loop)
        near = min((f[2] for f in live(fits)), default=np.inf) <= SIXBAR_NEAR * size
    fits.sort(key=lambda f: f[2])
    if not met and long[0] and not deadline.passed():  # the best crawl along narrow valleys:
        order = [i for i, f in enumerate(fits) if alive(f)][: long[0]]  # polish longer
        order += [i for i, f in enumerate(fits) if loop and f is loop[0] and i not in order]
        polish_long(order)
    for fit in fits[:refine_count]:
        check(fit)
    results = [r for _, r in checked.values() if r is not None]
    results.sort(key=_rank)
    t2 = time.perf_counter()
    chosen, rejected = [], []
    for r in results:
        if not r.ok:
            rejected.append(r)
        elif all(np.max(np.abs(r.design[3:] - c.design[3:])) > 0.02 * size for c in chosen):
            chosen.append(r)
    chosen = chosen[:n]
    best = chosen[0] if chosen else (rejected[0] if rejected else None)
    worst = float(np.max(best.distance)) / size if best is not None else np.inf
    note = _far_note(best, size, "six-bar")
    if best is not None and worst <= NEAR and not chosen:  # near, but every one has a defect
        defects = "; ".join(best.defects)
        note = (f"every six-bar found has a defect (see rejected); the best, {worst:.1e} of the "
                f"targets' size from them at worst: {defects}")  # fmt: skip
    seconds = {"retrieve": scan, "refine": t2 - t_begin - scan,
               "total": time.perf_counter() - start}  # fmt: skip
    note = _limit_note(note, deadline, deadline.at - start, seconds["total"])
    return PathCandidates(tuple(chosen), tuple(rejected[: max(n, 5)]), pts, worst <= NEAR, note,
                          seconds)  # fmt: skip
