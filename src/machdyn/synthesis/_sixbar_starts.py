"""Refinement starts for a six-bar path synthesis: atlas entries placed on the targets.

The rounds of starts of :func:`machdyn.synthesis.sixbar_path._sixbar_path`
(:data:`~machdyn.synthesis.sixbar_path.SIXBAR_ROUNDS`): untimed targets' entries
retrieved by shape and placed on the targets in their order (:func:`_placed_start`),
timed targets' pools scanned at every starting crank angle (:func:`_timed_best`),
the neighbour round (:func:`_neighbour_starts`: entries nearest to the best fits in
their design numbers) and the kind rounds (:func:`_kind_round`: entries of the best
fits' kinds); and an untimed Watt II "1-4" fit refitted loop by loop
(:func:`second_loop_fits`). The constants here are the ones these read; the
synthesis's own (screening, polish, rounds, gates) are in
:mod:`~machdyn.synthesis.sixbar_path`, which re-imports these names. Uses
:mod:`~machdyn.synthesis._sixbar_refine` (the design, its refinement) and
:mod:`~machdyn.synthesis._atlas_retrieve`; imports no :mod:`sixbar_path`.
"""

from __future__ import annotations

import weakref
from typing import Any

import numpy as np
from numpy.lib.recfunctions import structured_to_unstructured

from ._sixbar_refine import _joints, coupler_function, refine_sixbar

# Internal to machdyn.synthesis (see machdyn.synthesis.sixbar_path).
__all__: list[str] = []

_FIXED = ("s4", "s6", "topology", "on")
#: Six-bar entries spread over the atlas that timed targets are scanned against.
SIXBAR_TIMED_POOL = 1_000
#: Timed targets: starting angles every entry is scanned at, and entries scanned again finely.
SIXBAR_COARSE = 20
SIXBAR_FINE = 96
#: Timed targets: the pools scanned, each ``(entries spread over the atlas, nearest entries by
#: shape in units of ``retrieve``)``; each pool gives its own best starts. Spread entries
#: start most Watt II fits, the nearest by shape most Watt I and Stephenson ones.
SIXBAR_TIMED_POOLS = ((SIXBAR_TIMED_POOL, 1), (4 * SIXBAR_TIMED_POOL, 4), (0, 25), (0, 60))
#: Untimed later rounds: entries retrieved ×5, placed starts ×3, each round again (the
#: third: 25 times the first's retrieval, 4,000 entries, 360 placed). Seed 13's untimed
#: Watt I 3-4 on 5 and on 6 (six-bars 10 and 11: 1.2e-2, 6.1e-3 of the size after two rounds)
#: are met by the third (2.8e-15); a fourth (125 times) cost 4 s more and met none. No third
#: round where the best fit is within :data:`SIXBAR_CRAWL` (seeds 13 and 17: three targets
#: at 1e-8–8e-8 took it for nothing, 1.2–1.6 s of CPU).
SIXBAR_WIDER = (5, 3)
#: A kind round scans this many entries spread over those of a kind (chain, dyad links, the
#: point's link: :func:`_kind_pool`). Where the best fits are of the generating kind but at
#: a local minimum, the starts in the generating six-bar's basin are few (0.25–1.2 % of
#: random entries of its kind, for seed 7's missed Watt I 3-4 on 5) and no score finds them
#: (they ranked 500th to 150,000th by shape and by the timed scan): more entries of that
#: kind are what helps. A round of its own, not a share of the second: that share lost a
#: target the whole rescan met (best fits of another kind).
SIXBAR_KIND_POOL = 1_000
#: Kind rounds (:func:`_kind_round`): the first scans every kind whose best fit is within
#: ``SIXBAR_KIND_BAND`` times the best kind's best fit, at most ``SIXBAR_KIND_MOST`` kinds,
#: and polishes ``SIXBAR_KIND_POLISH`` fits per kind scanned. Over the benchmark's timed
#: targets that reach a kind round (seeds 2026, 7, 13, 17), where the next kind's best fit
#: was within 10 times the leader's, the generating kind was second five times (2nd/1st
#: 1.0–6.7) and first four times (1.1–3.2); where the next was 29 times or more behind, the
#: leader was the generating kind in three of four. Which of two close kinds leads is chance,
#: decided by which starts the rounds happened to have (seed 2026's six-bar 29 lost its
#: second-round start with the atlas query's exact re-ranking). The met fits of kind rounds
#: ranked 0th–13th after their screening steps.
SIXBAR_KIND_BAND = 10.0
SIXBAR_KIND_MOST = 2
#: The third kind round (a timed target's sixth round, run while five leave it unmet): the
#: kinds it scans (the best by their best fits of those neither kind round before scanned),
#: the starts from each kind's pool, and the fits polished per kind. Seed 21's timed six-bar
#: 43 (Watt I 2-3 on 5, a wide basin) ranks fifth by its kind's best fit (7.3e-4 of the size
#: against 1e-5 for the best kind's), so the kind rounds, which scan the best two, never
#: reach it: of 160 starts from 1,000 entries spread over its kind, the one that converges
#: ranked 21st by the scan and first after 100 steps.
SIXBAR_UNTRIED = (3, 32, 2)
#: No third (or fourth) round where the best fit's RMS is within this share of the size: such
#: a fit is crawling along its valley (seed 2026's six-bars 52 and 59, 2e-8 and 4e-8 after the first
#: round), which the long polish follows (a third round cost them CPU, and six-bar 59's
#: best polished fit). The local minima the third round escapes were 8.8e-6 to 9e-4.
SIXBAR_CRAWL = 1e-7


#: Untimed Watt II six-bars with the dyad on links 1 and 4 (two four-bars in series): while
#: none meets the targets, their second loop is fitted alone (see :func:`second_loop_fits`):
#: the fits whose second loop is fitted (without the compiled kernels: the second number)
#: and its steps, the best loops a six-bar is rebuilt from, and the rebuilt six-bars' steps.
#: On the benchmark's missed six-bar the loops that converged came from fits ranked 13th
#: and 33rd.
SIXBAR_SECOND_LOOP = ((40, 8), 600, 4, 300)


def _design_of(row, h, t, mirror: float = 1.0) -> tuple[np.ndarray, dict[str, int]]:
    """The placed design of an atlas row under the similarity ``t + h·z`` (mirrored: z → z̄)."""
    s = abs(h)
    f = {k: float(row[k]) for k in ("r1", "r3", "r4", "cu", "cv", "du", "dv", "a", "b", "pu", "pv")}
    x = np.array([
        t.real, t.imag, np.angle(h), f["r1"] * s, s, f["r3"] * s, f["r4"] * s,
        f["cu"], mirror * f["cv"], f["du"], mirror * f["dv"], f["a"] * s, f["b"] * s,
        f["pu"], mirror * f["pv"],
    ])  # fmt: skip
    fixed = {k: int(row[k]) for k in _FIXED}
    fixed["s4"] *= int(mirror)
    fixed["s6"] *= int(mirror)
    return x, fixed


def sixbar_starts(atlas, pts, timing, closed, retrieve, refine_count, client=None,
                  compiled=False, round_=0, fits=(), memo=None):  # fmt: skip
    """Refinement starts ``(x0, θ0, fixed)`` for six-bars: placed atlas entries.

    ``compiled``: the timed scan computes its coupler points on the compiled
    kernel (:mod:`machdyn.synthesis._sixbar_kernels`) rather than in NumPy.
    ``round_``: the round of starts (see :data:`SIXBAR_ROUNDS`); a later round's
    starts may repeat an earlier round's (the caller drops those). ``fits``: the
    fits so far ``(x, θ, rms, fixed)``: a timed target's third and fourth rounds scan
    entries of the kinds of the best ones (:func:`_kind_round`). ``memo``: a dict
    kept by the caller across the rounds of one synthesis: the entries nearest to
    the targets by shape are retrieved once into it (the second round rescans the
    first pool, and the fourth takes entries of its kinds from them; a query on the
    10^6 six-bar atlas costs about 0.3 s of CPU), and the kinds scanned.
    """
    from ._atlas_retrieve import _even_target, _retrieve
    from .descriptor import curve_descriptor
    from .sixbar import sixbar_points

    starts = []
    if timing is None:
        if round_:
            retrieve *= SIXBAR_WIDER[0] ** round_
            refine_count *= SIXBAR_WIDER[1] ** round_
        rows, transforms = _retrieve(atlas, pts, closed, True, retrieve, refine_count, client)
        u = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
        local = sixbar_points(rows, u)[0]
        keep = [i for i, (h, _) in enumerate(transforms) if np.isfinite(h) and h != 0]
        if compiled:  # (all at once: the same placements, a tenth of the calls)
            placed = _placed_starts(local[keep], [transforms[i] for i in keep], pts)
        else:
            placed = [_placed_start(local[i], *transforms[i], pts) for i in keep]
        for i, (h, t, near) in zip(keep, placed, strict=True):
            x0, fixed = _design_of(rows[i], h, t)
            starts.append((x0, u[near], fixed))
        return starts
    memo = {} if memo is None else memo
    near = np.zeros(0, np.int64)
    if closed:  # the entries whose whole curve looks like the target's (retrieved once)
        wanted = min(max(k for _, k in SIXBAR_TIMED_POOLS) * retrieve, len(atlas))
        if memo.get("near", (None, 0))[1] != wanted:
            even = _even_target(atlas.manifest, pts)
            q = curve_descriptor(even, atlas.manifest.harmonics, resampled=True)
            memo["near"] = (atlas.nearest(q, wanted, client=client)[0], wanted)
        near = memo["near"][0]
    # pools, each with its own best starts (see SIXBAR_TIMED_POOLS). Their best-scoring
    # starts lie in different basins (the timed fit is over-determined: near the truth it
    # has real local minima), and a target missed from one pool is often met from another
    seen: set[tuple[int, float]] = set()
    if round_ == 2:  # the neighbour round: entries placed as the best fits are
        return _neighbour_starts(atlas, fits, pts)
    if round_ > 2:  # a kind round: entries of the kinds of the best fits (_kind_round)
        pools = _kind_round(atlas, fits, pts, near, memo)
    else:
        pools = [
            np.union1d(atlas.pool(size, crank=True), near[: k * retrieve]) if size else
            near[: k * retrieve] for size, k in SIXBAR_TIMED_POOLS[: 1 if round_ else None]
        ]  # fmt: skip
    pools = [idx for idx in pools if idx.size]
    chosen = []
    # (kind rounds: the first round's starting angles, the grid turned by one whole step)
    if round_ > 4:  # the third kind round: fewer starts of each of more kinds
        refine_count = SIXBAR_UNTRIED[1]
    for best in _timed_best(atlas, pools, timing, pts, refine_count, compiled,
                            shift=0.5 * min(round_, 2)):  # fmt: skip
        for i, h, t, g0, mirror in best:
            if (i, mirror) not in seen:
                seen.add((i, mirror))
                chosen.append((i, h, t, g0, mirror))
    rows = atlas.entries(np.array([c[0] for c in chosen], np.int64))  # (one read for all)
    for row, (_, h, t, g0, mirror) in zip(rows, chosen, strict=True):
        x0, fixed = _design_of(row, h, t, mirror)
        starts.append((x0, g0 + timing, fixed))
    return starts


def _ranked_kinds(fits, pts) -> list[tuple[tuple[int, int], float]]:
    """The kinds of the fits, ``((topology, on), rms)`` best first by each kind's best fit.

    A kind: the chain and the dyad's links (``topology``) and the link that carries
    the point (``on``). Fits that come apart (``inf``) rank no kind. Empty where the
    best fit is within :data:`SIXBAR_CRAWL` of the targets' size (the long polish's).
    """
    kinds: dict[tuple[int, int], float] = {}
    for f in fits:
        key = (int(f[3]["topology"]), int(f[3]["on"]))
        if np.isfinite(f[2]) and f[2] < kinds.get(key, np.inf):
            kinds[key] = float(f[2])
    ranked = sorted(kinds.items(), key=lambda kv: (kv[1], kv[0]))
    if ranked and ranked[0][1] <= SIXBAR_CRAWL * float(np.max(np.abs(pts - pts.mean()))):
        return []
    return ranked


def _kind_round(atlas, fits, pts, near, memo) -> list[np.ndarray]:
    """The pools of entries of a kind round (a timed target's fourth, fifth or sixth round).

    The first kind round: for each kind whose best fit is within
    :data:`SIXBAR_KIND_BAND` times the best kind's (at most :data:`SIXBAR_KIND_MOST`
    kinds, best first: :func:`_ranked_kinds`), entries spread over the kind. The
    second: for the same kinds, their entries among ``near`` (the entries nearest to
    the targets by shape, which the first round's pools held among all kinds); and
    where the first took one kind only, entries spread over the next kind. Each pool
    gives its own best starts. The third: entries spread over each of the best kinds
    (at most ``SIXBAR_UNTRIED[0]``) that neither of the first two scanned, fewer starts
    from each (:data:`SIXBAR_UNTRIED`). ``memo["kinds"]``: the first kind round's kinds;
    ``memo["tried"]``: the first two's; ``memo["round_kinds"]``: the kinds of the round
    (the caller polishes :data:`SIXBAR_KIND_POLISH` fits per kind, ``SIXBAR_UNTRIED[2]``
    in the third). No pools where the best fit is within :data:`SIXBAR_CRAWL` of the
    targets' size.
    """
    ranked = _ranked_kinds(fits, pts)
    if not ranked:
        memo["round_kinds"] = []
        return []
    first = memo.get("kinds")
    if "tried" in memo:  # the third kind round: the best kinds no round has scanned yet
        fresh = [k for k, _ in ranked if k not in memo["tried"]][: SIXBAR_UNTRIED[0]]
        memo["round_kinds"] = fresh
        return [_kind_pool(atlas, k) for k in fresh]
    if first is None:
        band = SIXBAR_KIND_BAND * ranked[0][1]
        kinds = [k for k, rms in ranked[:SIXBAR_KIND_MOST] if rms <= band]
        memo["kinds"] = memo["round_kinds"] = kinds
        return [_kind_pool(atlas, k) for k in kinds]
    near = np.asarray(near, dtype=np.int64)
    rows = atlas.entries(near) if near.size else None  # (one read for every kind; near
    # holds crank entries only, each kind's sorted as the spread pools are)
    pools = [np.zeros(0, np.int64) if rows is None else
             np.unique(near[(rows["topology"] == k[0]) & (rows["on"] == k[1])])
             for k in first]  # fmt: skip
    other = [k for k, _ in ranked if k not in first][: max(0, SIXBAR_KIND_MOST - len(first))]
    pools += [_kind_pool(atlas, k) for k in other]
    memo["round_kinds"] = memo["tried"] = first + other
    return pools


def _kind_pool(atlas, kind: tuple[int, int]) -> np.ndarray:
    """Flat indices of :data:`SIXBAR_KIND_POOL` crank entries of one kind ``(topology, on)``.

    Spread evenly over the atlas's entries of the kind.
    """
    sel = [crank & (np.asarray(m["topology"]) == kind[0]) & (np.asarray(m["on"]) == kind[1])
           for crank, m in zip(atlas._crank, atlas.meta, strict=True)]  # fmt: skip
    allowed = np.flatnonzero(np.concatenate(sel))
    if allowed.size > SIXBAR_KIND_POOL:
        allowed = allowed[np.linspace(0, allowed.size - 1, SIXBAR_KIND_POOL).astype(np.int64)]
    return allowed


#: The neighbour round (a timed target's third, :func:`_neighbour_starts`): the kinds whose
#: best fits are taken (at most; within :data:`SIXBAR_KIND_BAND` of the best kind's), the
#: distinct best fits of each, and the atlas entries nearest to each fit in its design
#: numbers. A timed fit is over-determined: near the truth it has real local minima,
#: and the entries nearest to the truth by shape or by the timed scan are seldom in its
#: basin. Seed 13's six-bar 39 (Stephenson 1-3 on 6): of the 300 entries of its kind
#: nearest to the known six-bar in design numbers, 72 converge placed as it is (its
#: similarity and crank angles) but 6 placed by the timed scan, none of whose scores rank
#: among a pool's best 160; its best fits of its kind stop at 1.7e-2 of the size, and of the
#: 200 entries nearest to each placed as it is, 39, 18 and 16 converge (300 steps).
SIXBAR_NEIGHBOURS = (3, 1, 40)


#: The atlas rows' design numbers, in :func:`_design_numbers`' order.
_NUMBERS = ("r1", "r3", "r4", "cu", "cv", "du", "dv", "a", "b", "pu", "pv")


def _design_numbers(values: np.ndarray, mirror: Any = 1.0) -> np.ndarray:
    """Atlas rows' design numbers in one metric (:func:`_neighbour_starts`').

    ``values``: the rows' :data:`_NUMBERS`, one row each. Logs of the lengths over the
    crank, the link-frame coordinates as they are (``v`` negated for a mirror image;
    ``mirror`` ±1, one for all rows or one each).
    """
    out = np.array(values, dtype=float, ndmin=2)
    out[:, [0, 1, 2, 7, 8]] = np.log(out[:, [0, 1, 2, 7, 8]])
    out[:, [4, 6, 10]] *= np.asarray(mirror, dtype=float).reshape(-1, 1)
    return out


def _fit_numbers(x: np.ndarray) -> np.ndarray:
    """A placed design's numbers in :func:`_design_numbers`' metric (positive lengths)."""
    r2 = abs(x[4])
    lengths = np.log(np.abs(x[[3, 5, 6, 11, 12]]) / r2)
    return np.array([lengths[0], lengths[1], lengths[2], *x[7:11], lengths[3], lengths[4],
                     x[13], x[14]])  # fmt: skip


def _kind_entries(atlas, fixed) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The crank entries a fit of ``fixed``'s kind and assembly signs can be placed from.

    An entry of the same signs as it is, or of both signs opposite as its mirror image
    (:func:`_design_of`). Returns flat indices, mirrors (±1) and design numbers
    (:func:`_design_numbers`, float32), kept per opened atlas: reading them costs about
    0.02 s a kind on the 10^6 six-bar atlas, and a benchmark's syntheses ask for the same
    few kinds again (at most 4 MB each).
    """
    cache = _ENTRIES.setdefault(atlas, {})
    if "codes" not in cache:  # each entry's kind and signs as one number; -1: no crank
        cache["codes"] = [
            np.where(crank, (m["topology"].astype(np.int16) * 8 + m["on"]) * 9
                     + (m["s4"] + 1) * 3 + m["s6"] + 1, -1)
            for crank, m in zip(atlas._crank, atlas.meta, strict=True)
        ]  # fmt: skip
    key = (fixed["topology"], fixed["on"], fixed["s4"], fixed["s6"])
    if key not in cache:
        base = (fixed["topology"] * 8 + fixed["on"]) * 9
        same = base + (fixed["s4"] + 1) * 3 + fixed["s6"] + 1
        mirrored = base + (1 - fixed["s4"]) * 3 + 1 - fixed["s6"]
        idx, values, mirrors = [], [], []
        for c, (code, m) in enumerate(zip(cache["codes"], atlas.meta, strict=True)):
            sel = np.flatnonzero((code == same) | (code == mirrored))
            idx.append(sel + atlas.offsets[c])
            # (the fields as columns of a view: gathering them costs a third of the rows')
            values.append(structured_to_unstructured(m[list(_NUMBERS)], copy=False)[sel])
            mirrors.append(np.where(code[sel] == same, 1.0, -1.0))
        mirrors = np.concatenate(mirrors)
        numbers = _design_numbers(np.concatenate(values), mirrors).astype(np.float32)
        cache[key] = (np.concatenate(idx), mirrors.astype(np.int8), numbers)
    return cache[key]


#: :func:`_kind_entries`' entries, per opened atlas.
_ENTRIES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _neighbour_starts(atlas, fits, pts) -> list:
    """Starts ``(x0, θ0, fixed)`` of the neighbour round (a timed target's third).

    For each of the best kinds (:func:`_ranked_kinds`; at most
    ``SIXBAR_NEIGHBOURS[0]``, within :data:`SIXBAR_KIND_BAND` of the best) its
    ``SIXBAR_NEIGHBOURS[1]`` best distinct fits; for each, the ``SIXBAR_NEIGHBOURS[2]``
    entries of its kind and signs nearest to it in design numbers
    (:func:`_kind_entries`), placed by the fit's own similarity (its ground pivot,
    ground line and crank) at the fit's crank angles. Where the fits stop at local
    minima near the truth, these starts lie around them, and some in the truth's basin.
    """
    kinds_most, per_kind, count = SIXBAR_NEIGHBOURS
    ranked = _ranked_kinds(fits, pts)
    band = SIXBAR_KIND_BAND * ranked[0][1] if ranked else 0.0
    kinds = [k for k, rms in ranked[:kinds_most] if rms <= band]
    starts = []
    for kind in kinds:
        taken: list[np.ndarray] = []
        for x, theta, rms, fixed in sorted(fits, key=lambda f: f[2]):
            if len(taken) == per_kind:
                break
            if (fixed["topology"], fixed["on"]) != kind or not np.isfinite(rms):
                continue
            v = _fit_numbers(x)
            if not np.all(np.isfinite(v)) or any(np.allclose(v, w, atol=1e-6) for w in taken):
                continue
            taken.append(v)
            idx, mirrors, numbers = _kind_entries(atlas, fixed)
            near = np.argsort(np.sum((numbers - v) ** 2, axis=1), kind="stable")[:count]
            h, t = abs(x[4]) * np.exp(1j * x[2]), complex(x[0], x[1])
            for row, mirror in zip(atlas.entries(idx[near]), mirrors[near], strict=True):
                x0, fx = _design_of(row, h, t, float(mirror))
                starts.append((x0, np.asarray(theta, float).copy(), fx))
    return starts


def second_loop_fits(fits, pts, compiled=False) -> list:
    """Untimed Watt II "1-4" six-bars fitted loop by loop: new fits ``(x, θ, rms, fixed)``.

    The dyad on the ground and the rocker makes such a six-bar two four-bars in
    series: the coupler point is the second four-bar's (ground pivots ``O4`` and
    ``C``, input link ``O4–D`` on the rocker) at the rocker's angle ``φ``, and the
    first four-bar only swings the rocker. Fitted as one, the crank angle of a
    target near a turn of the rocker is barely felt (``dφ/dθ ≈ 0``), and fits
    stall on a neighbouring second four-bar (1e-5 to 3e-3 of the size) that the
    first cannot swing to the truth. So (:data:`SIXBAR_SECOND_LOOP`): (1) the
    second four-bar of each of the best such fits is fitted to the targets alone,
    ``φ`` at each target free (:func:`_second_loop`); (2) for the best few of
    these a first four-bar is designed to swing it (:func:`_first_loop`) and the
    six-bar of the two refined. The loop fits themselves are returned too (Watt II
    1-2 six-bars: an answer where ``φ`` turns a whole turn in the targets' order),
    all best first; the caller checks them.
    """
    count, steps, best, rebuilt = SIXBAR_SECOND_LOOP
    wanted = sorted((f for f in fits if f[3]["topology"] == 1 and np.isfinite(f[2])),
                    key=lambda f: f[2])  # fmt: skip
    loops = [_second_loop(*f, pts, steps, compiled) for f in wanted[: count[not compiled]]]
    out = []
    for loop in sorted((lp for lp in loops if lp is not None), key=lambda lp: lp[2])[:best]:
        out.append(loop)
        fit = _first_loop(*loop[:2], loop[3], pts, rebuilt, compiled)
        out += [fit] if fit is not None else []
    return sorted(out, key=lambda f: f[2])


def _second_loop(x, theta, rms, fixed, pts, steps, compiled):
    """The second four-bar of a Watt II 1-4 fit refined alone: ``(x', φ, rms, fixed')``.

    Posed as a Watt II "1-2" six-bar whose crank is the input link ``O4–D``
    (``φ`` its crank angles; its own first four-bar, a dummy 1-4-4-4
    crank-rocker, does not move the point), so the same refinement serves.
    None where it comes apart.
    """
    j = _joints(x, theta, fixed)
    O4, C, D = j["O4"], j["C"], j["D"]
    rho = float(np.mean(np.abs(D - O4)))
    if not (np.all(np.isfinite(D)) and rho > 0):
        return None
    proxy = dict(s4=1, s6=fixed["s6"], topology=0, on=fixed["on"])
    c = (C - O4) / (4 * rho)
    x = np.array([O4.real, O4.imag, 0.0, 4 * rho, rho, 4 * rho, 4 * rho, c.real, c.imag,
                  1.0, 0.0, *x[11:]])  # fmt: skip
    x, theta, rms = refine_sixbar(x, np.angle(D - O4), proxy, pts, iterations=steps,
                                  compiled=compiled)  # fmt: skip
    return (x, theta, rms, proxy) if np.isfinite(rms) else None


def _first_loop(xp, phi, proxy, pts, steps, compiled):
    """A Watt II 1-4 six-bar from a fitted second loop (:func:`_second_loop`'s), refined.

    The first four-bar is a crank-rocker whose rocker (``0.6 ρ`` long) swings
    just past the fitted ``φ`` range: its crank on the line through the rocker's
    two end positions, half that chord long, so these are its limit positions
    (the two-position design of a crank-rocker, Norton §3.4); on either side, in
    either assembly. The six-bar starts at the samples of its curve nearest the
    targets in their order; the best refined one is returned (None if none assembles).
    """
    j = _joints(xp, phi, proxy)
    O4, C, D = j["O2"], j["C"], j["D"]
    rho = float(np.mean(np.abs(D - O4)))
    phi = np.sort(np.mod(np.angle(D - O4), 2 * np.pi))
    gaps = np.diff(np.concatenate([phi, phi[:1] + 2 * np.pi]))
    k = int(np.argmax(gaps))  # the swing: the circle less its widest gap between targets
    lo, hi = float(phi[(k + 1) % phi.size]), float(phi[k] + (2 * np.pi if k + 1 < phi.size else 0))
    if hi - lo > 0.8 * np.pi:  # no crank-rocker swings this far
        return None
    coupler = coupler_function(compiled)
    u = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    best = None
    for margin in (0.05, 0.01, 0.001):  # the second loop may close only just past the targets
        r4, swing = 0.6 * rho, margin * (hi - lo) + 1e-4
        B1, B2 = O4 + r4 * np.exp(1j * (lo - swing)), O4 + r4 * np.exp(1j * (hi + swing))
        r2 = abs(B2 - B1) / 2
        r3 = r2 + 1.5 * r4
        for side in (1.0, -1.0):
            O2 = (B1 + B2) / 2 + side * r3 * (B2 - B1) / (2 * r2)
            c = (C - O2) / (O4 - O2)
            x0 = np.array([O2.real, O2.imag, np.angle(O4 - O2), abs(O4 - O2), r2, r3, r4,
                           c.real, c.imag, rho / r4, 0.0, *xp[11:]])  # fmt: skip
            for s4 in (1, -1):
                fixed = dict(proxy, s4=s4, topology=1)
                P, _, _, ok = coupler(x0, u, fixed)
                if not ok.all():
                    continue
                near = _ordered_samples(P, pts, compiled=compiled)
                fit = refine_sixbar(x0, u[near], fixed, pts, iterations=steps, compiled=compiled)
                if best is None or fit[2] < best[2]:
                    best = (*fit, fixed)
        if best is not None:
            break
    return best


def _timed_best(atlas, pools, timing, pts, count, compiled=False, shift=0.0):
    """Per pool of entries, the ``count`` best timed placements: (index, h, t, θ0, mirror).

    Coarse to fine: every entry at :data:`SIXBAR_COARSE` starting angles, the best
    :data:`SIXBAR_FINE` of each direction again at every one of ``TIMED_GRID`` angles;
    both grids turned by ``shift`` of their step. An entry's coarse scan does not depend
    on its pool, so the entries that several pools share (the nearest by shape are
    nested) are scanned once.
    """
    from ._atlas_retrieve import TIMED_GRID

    if not pools:
        return []
    union = np.unique(np.concatenate(pools))
    rows = atlas.entries(union)
    at = [np.searchsorted(union, idx) for idx in pools]
    coarse = np.linspace(0.0, 2 * np.pi, SIXBAR_COARSE, endpoint=False)
    coarse = coarse + shift * coarse[1]
    grid = np.linspace(0.0, 2 * np.pi, TIMED_GRID, endpoint=False)
    grid = grid + shift * grid[1]
    found: list[list] = [[] for _ in pools]
    for mirror in (1.0, -1.0):  # the mirror image turns the other way for the same crank turn
        scores = _timed_scan(rows, coarse, timing, pts, mirror, compiled)[0]
        for p, idx in enumerate(pools):
            pick = np.argsort(-scores[at[p]])[:SIXBAR_FINE]
            fine = _timed_scan(rows[at[p][pick]], grid, timing, pts, mirror, compiled)
            score, hh, off, g = fine
            found[p] += [(score[j], int(idx[pick[j]]), hh[j], off[j], grid[g[j]], mirror)
                         for j in range(pick.size)]  # fmt: skip
    out = []
    for f in found:
        f.sort(key=lambda f: -f[0])
        out.append([f[1:] for f in f[:count]])
    return out


def _ordered_samples(curve: np.ndarray, pts: np.ndarray, rolls: int = 8,
                     compiled: bool = False) -> np.ndarray:  # fmt: skip
    """Indices of a placed curve's samples nearest the targets, in the targets' order.

    Not each target's nearest sample on its own: where the coupler point dwells
    (much of the turn on a short stretch of the curve) or the curve crosses
    itself, nearest samples jump back and forth and the refinement starts on the
    wrong arcs. Instead the samples are taken one way round, never going back
    (dynamic programming over the samples: the least sum of squared distances),
    from each of ``rolls`` starting samples in both directions at once; the best wins.
    ``compiled``: the same programme on the compiled kernel
    (:func:`machdyn.synthesis._sixbar_kernels.ordered_samples`; the same choices,
    about ten times faster), for finite distances.
    """
    n = curve.size
    c = np.abs(curve[None, :] - pts[:, None]) ** 2  # (K, N)
    if compiled and np.all(np.isfinite(c)):
        from ._sixbar_kernels import ordered_samples

        out = np.empty(pts.size, np.int64)
        ordered_samples(c, rolls, out)
        return out
    starts = np.arange(0, n, n // rolls)
    steps = np.concatenate([np.arange(n)[None, :], -np.arange(n)[None, :]])  # both ways
    order = (starts[:, None, None] + steps[None, :, :]).reshape(-1, n) % n  # (2R, N)
    c = c[:, order].transpose(1, 0, 2)  # (2R, K, N)
    total, back = c[:, 0], []
    cols = np.arange(n)
    for k in range(1, pts.size):  # target k at sample j: target k - 1 at a sample <= j
        run = np.minimum.accumulate(total, axis=1)
        better = np.concatenate([np.ones((total.shape[0], 1), bool),
                                 total[:, 1:] < run[:, :-1]], axis=1)  # fmt: skip
        back.append(np.maximum.accumulate(np.where(better, cols, 0), axis=1))
        total = c[:, k] + run
    end = np.argmin(total, axis=1)
    w = int(np.argmin(total[np.arange(end.size), end]))
    path = [int(end[w])]
    for b in reversed(back):
        path.append(int(b[w, path[-1]]))
    return order[w, np.array(path[::-1])]


def _placed_start(z: np.ndarray, h: complex, t: complex, pts: np.ndarray, rounds: int = 3,
                  compiled: bool = False):  # fmt: skip
    """Similarity ``t + h·z`` and sample indices for a curve ``z``, fitted in turns.

    The samples in the targets' order (:func:`_ordered_samples`), then the
    rotation, scale and offset that put those samples on the targets (least
    squares, closed form), a few times over: the descriptor's placement fits
    the spline through the targets, which misplaces curves that dwell.
    ``compiled``: :func:`_ordered_samples`'s.
    """
    a0 = pts - pts.mean()
    for _ in range(rounds):
        near = _ordered_samples(t + h * z, pts, compiled=compiled)
        q = z[near] - z[near].mean()
        v = float(np.sum(np.abs(q) ** 2))
        if v == 0.0:
            break
        h = complex(np.sum(np.conj(q) * a0) / v)
        t = complex(pts.mean() - h * z[near].mean())
    return h, t, _ordered_samples(t + h * z, pts, compiled=compiled)


def _placed_starts(z: np.ndarray, transforms, pts: np.ndarray, rounds: int = 3,
                   block: int = 64) -> list:  # fmt: skip
    """:func:`_placed_start` (compiled) for many curves ``z`` (E, N) at once: ``[(h, t, near)]``.

    The same steps on each curve, so the same placements to the bit; only the
    ordering of the samples (:func:`_ordered_samples`) is batched: the squared
    distances of a block of placed curves formed at once and ordered by one call of
    the compiled kernel (:func:`machdyn.synthesis._sixbar_kernels.ordered_samples_many`)
    instead of one call (and its NumPy around it) per curve and turn. A curve whose
    distances are not all finite is ordered alone, as there.
    """
    from ._sixbar_kernels import ordered_samples_many

    e = z.shape[0]
    placed = [(h, t) for h, t in transforms]
    live = [True] * e  # a curve whose ordered samples coincide stops, as in _placed_start
    near = np.empty((e, pts.size), np.int64)
    a0 = pts - pts.mean()

    def order(sel):  # near[i] for each i in sel, at its current placement
        for lo in range(0, len(sel), block):
            b = sel[lo : lo + block]
            curves = np.array([placed[i][1] + placed[i][0] * z[i] for i in b])
            c = np.abs(curves[:, None, :] - pts[None, :, None]) ** 2
            finite = np.isfinite(c).reshape(len(b), -1).all(axis=1)
            good = np.flatnonzero(finite)
            out = np.empty((good.size, pts.size), np.int64)
            ordered_samples_many(c[good], 8, out)
            near[np.asarray(b)[good]] = out
            for j in np.flatnonzero(~finite):
                near[b[j]] = _ordered_samples(curves[j], pts, compiled=True)

    for _ in range(rounds):
        sel = [i for i in range(e) if live[i]]
        order(sel)
        for i in sel:
            zi = z[i][near[i]]
            q = zi - zi.mean()
            v = float(np.sum(np.abs(q) ** 2))
            if v == 0.0:
                live[i] = False
                continue
            h = complex(np.sum(np.conj(q) * a0) / v)
            placed[i] = (h, complex(pts.mean() - h * zi.mean()))
    order(list(range(e)))
    return [(*placed[i], near[i].copy()) for i in range(e)]


def _timed_scan(rows, grid, timing, pts, mirror, compiled=False):
    """Each row's best starting angle on ``grid`` for timed targets: fit score, placement.

    The coupler points at ``θ0 + Δ_k`` placed on the targets by a rotation, scale and
    offset ``t + h·Q`` (closed form); the score is the share of the targets' spread the
    fit explains. Returns per row the score, ``h``, ``t`` and the index of θ0 in ``grid``.
    """
    if compiled:
        from ._sixbar_kernels import sixbar_points_compiled as points
    else:
        from .sixbar import sixbar_points

        def points(block, th):
            return sixbar_points(block, th)[0]

    a0 = pts - pts.mean()
    out = []
    for lo in range(0, rows.size, 1024):
        block = rows[lo : lo + 1024]
        th = mirror * (grid[:, None] + timing[None, :]).ravel()
        Q = points(block, th).reshape(block.size, grid.size, -1)
        if mirror < 0:
            np.conjugate(Q, out=Q)
        qm = np.nanmean(Q, axis=2, keepdims=True)
        Q -= qm
        c = np.sum(np.conj(Q) * a0, axis=2)
        v = np.sum(np.abs(Q) ** 2, axis=2)
        score = np.nan_to_num(np.abs(c) ** 2 / np.where(v > 0, v, np.inf), nan=-1.0)
        g = np.argmax(score, axis=1)
        r = np.arange(block.size)
        hh = c[r, g] / v[r, g]
        out.append((score[r, g], hh, pts.mean() - hh * qm[r, g, 0], g))
    return tuple(np.concatenate(x) for x in zip(*out, strict=True))
