"""Refinement starts for a path synthesis from a four-bar atlas: retrieve and place.

A closed target's nearest atlas entries by descriptor, an open target's best
arcs of an evenly spread pool (re-fitted to the points themselves), random
four-bars of wide proportions, and for timed targets a scan of every pool
entry's starting crank angle; each start is an atlas linkage placed on the
target by a rotation, scale and offset. Used by
:mod:`~machdyn.synthesis.atlas_path` (and :mod:`~machdyn.synthesis._sixbar_starts`).
"""

from __future__ import annotations

import functools
import weakref

import numpy as np

from ._atlas_index import _NEVER, OPEN_POOL, Atlas, _Deadline
from .atlas_store import even_curves
from .circuits import circuit_angles, circuit_points, circuit_range
from .descriptor import (
    align_closed,
    align_partial,
    curve_descriptor,
    interpolate_closed,
    interpolate_open,
    resample_closed,
)

__all__: list[str] = []

#: Open targets: best arc fits re-scored on the target points, samples of each curve
#: for that, and rounds of the re-fit (see _fit_to_points); the arc fit takes every
#: ARC_STRIDE-th of a curve's samples.
RESCORE = 200
ARC_STRIDE = 2
DENSE = 720
ICP_ROUNDS = 3
#: The fine arc fit of an open target's first extra pool round (see _arc_starts): arcs of 24
#: lengths from a tenth of the curve to all of it, each 10.5 % longer than the last, on all of
#: a curve's samples; then :data:`ICP_LINE` point-to-line rounds of the re-fit.
FINE_FRACTIONS = np.geomspace(0.1, 1.0, 24)
ICP_LINE = 3
#: Most target points the re-fit matches (a 40-point line's nearest points on 200 curves of
#: 720 samples, four times, took a third of its synthesis; the benchmarks' other targets
#: have at most 18).
ICP_POINTS = 20
#: Random four-bars beyond the atlas's proportions (link lengths from 1/50 to 50 crank
#: lengths) whose best-placed also start refinements: the literature's best linkages
#: often lie there (a 50-long ground and rocker on a 1.35 crank, at a length bound).
WIDE_POOL = 8_000
WIDE_RANGE = (0.02, 50.0)
WIDE_TIMED = 1_500  # of them, for timed targets whose starting angle is scanned too

#: Entries of an open target's pool whose curves are computed at once (a time limit is
#: looked at between slices).
POOL_SLICE = 1_000
#: Entries scanned for timed targets, and crank angles tried for the first target.
TIMED_POOL = 5_000
TIMED_GRID = 60
#: Timed targets: the pool's next-best starts kept for a second round on a small atlas
#: (ranked just below the ``refine_count`` best; see atlas_path.TIMED_ROUNDS). On an atlas
#: of 10^4 entries (5,034 crank rows: a fresh pool of 5,000 shares 4,966 with the first)
#: the open-timed targets bench_atlas --recovery 20 missed (1 in 20 on seeds 3, 7 and 11,
#: by 1e-5 to 5e-4 of their size) were met by starts ranked 11-20, 11-20 and 41-80.
TIMED_SPARE = 70


def _retrieve(atlas: Atlas, pts, closed, crank, retrieve, refine_count, client=None,
              deadline: _Deadline = _NEVER):  # fmt: skip
    """Atlas rows and the similarity transforms (h, t) that place their curves on the target.

    Past the ``deadline``, the query of a closed target's nearest entries scores no
    more chunks (:meth:`Atlas._query`). With a limit, an open target's pool is taken in
    slices of :data:`POOL_SLICE` entries and none after the deadline (the first always):
    the entries placed are then those of the slices taken, a smaller random sample of
    the atlas.
    """
    man = atlas.manifest
    if closed:
        rows, transforms, residual = _nearest_placed(atlas, pts, retrieve, crank, client,
                                                     deadline)  # fmt: skip
        order = np.argsort(residual)[:refine_count]
        return rows[order], transforms[order]
    rows = atlas.entries(atlas.pool(OPEN_POOL, crank=crank))
    curves: list = []
    step = rows.size if deadline is _NEVER else POOL_SLICE  # (no limit: one call, as ever)
    for lo in range(0, rows.size, step):
        if curves and deadline.passed():
            break
        curves.append(even_curves(rows[lo : lo + step], man.circuit_samples, man.samples))
    curves = np.concatenate(curves)
    return _arc_starts(rows[: len(curves)], curves, pts, refine_count)


def _even_target(man, pts) -> np.ndarray:
    """A closed target resampled as the atlas holds its curves (``man.samples`` points).

    Evenly spaced along the periodic spline through the targets.
    """
    return resample_closed(interpolate_closed(pts, 8 * man.samples), man.samples)


def _nearest_placed(atlas: Atlas, pts, k, crank, client=None, deadline: _Deadline = _NEVER):
    """The ``k`` entries nearest a closed target by descriptor (best first), placed on it.

    Returns the rows, their placements ``(h, t)`` (:func:`align_closed`) and misfits.
    """
    man = atlas.manifest
    even = _even_target(man, pts)
    q = curve_descriptor(even, man.harmonics, resampled=True)
    idx, _ = atlas._query(q, k, crank, client, deadline)
    rows = atlas.entries(idx)
    transforms, residual = align_closed(even, even_curves(rows, man.circuit_samples, man.samples))
    return rows, transforms, residual


#: Closed untimed targets: the nearest entries by descriptor taken for spare starts, as a
#: multiple of ``retrieve`` (see _retrieve_closed).
CLOSED_SPARE = 2


def _retrieve_closed(atlas: Atlas, pts, crank, retrieve, refine_count, client=None,
                     deadline: _Deadline = _NEVER):  # fmt: skip
    """A closed untimed target's nearest entries, placed: the first round's and spare ones.

    One query of the :data:`CLOSED_SPARE` · ``retrieve`` nearest entries by
    descriptor. Returns the rows and placements of :func:`_retrieve` (the
    ``refine_count`` best-placed of the ``retrieve`` nearest: the same), and the
    ``refine_count`` best-placed entries whose link 2 turns fully (Barker's GCCC and
    GCRR) among the others: a closed path is traced in order on one assembly only by
    such a linkage, and a second round starts from them.
    """
    # (best first: the first `retrieve` are _retrieve's)
    rows, transforms, residual = _nearest_placed(atlas, pts, CLOSED_SPARE * retrieve, crank,
                                                 client, deadline)  # fmt: skip
    first = np.argsort(residual[:retrieve])[:refine_count]
    rest = np.full(rows.size, np.inf)
    rest[retrieve:] = residual[retrieve:]
    rest[rows["barker"] > 2] = np.inf
    spare = np.argsort(rest)[:refine_count]
    spare = spare[np.isfinite(rest[spare])]
    return (rows[first], transforms[first]), (rows[spare], transforms[spare])


def _arc_starts(rows, curves, pts, count, fine: bool = False):
    """The ``count`` rows whose curves pass nearest an open target, and their placements.

    Every curve is first fitted arc-wise (:func:`align_partial`), then the
    :data:`RESCORE` best are re-fitted to the points themselves
    (:func:`_fit_to_points`) and ranked by that.

    The coarse arc fit (the default) takes every :data:`ARC_STRIDE`-th sample of a
    curve and arcs of eight lengths (1/8 … 1 of the curve). On a short arc that is too
    coarse to see the right curves: an arc of 17.6 % of its curve (``bench_atlas.py
    --recovery 20 --seed 11``, open case 13) spans 11 of the 64 samples, each of its 24
    spline samples is paired with the nearest of them, and the nearest lengths are 29 %
    short or 42 % long; the true linkage's *own* curve then misfits by 5.8 % and ranks
    past 2,000 of 4,000 entries, and after three rounds of the point-to-point re-fit
    it still misses by 2.9 % (that re-fit crawls along a gently curved arc). ``fine``:
    all the samples and :data:`FINE_FRACTIONS` (the same curve: 0.6 %, and the entries
    within 3 % of the truth rank among the first 60), then :data:`ICP_LINE`
    point-to-line rounds of the re-fit (the truth's curve: 2.4e-6, the polygon's sag).
    It costs six times the coarse fit, so one pool round takes it (see
    :func:`~machdyn.synthesis.atlas_path._untimed_fits`).
    """
    target = interpolate_open(pts, 24)
    if fine:
        transforms, residual = align_partial(target, curves, FINE_FRACTIONS, single=True)
    else:  # every other sample: half the work of all 128
        transforms, residual = align_partial(target, curves[:, ::ARC_STRIDE], single=True)
    order = np.argsort(residual)[:RESCORE]
    rows, transforms = rows[order], transforms[order]
    transforms, miss = _fit_to_points(rows, transforms, pts, line=ICP_LINE if fine else 0)
    order = np.argsort(miss)[:count]
    return rows[order], transforms[order]


def _fit_to_points(rows, transforms, pts, rounds: int = ICP_ROUNDS, line: int = 0):
    """Placements ``(h, t)`` of atlas curves re-fitted to the target points themselves.

    :func:`~machdyn.synthesis.descriptor.align_partial` matches evenly spaced
    samples of the target's spline to evenly spaced samples of an arc whose
    extent is one of a few fractions of the curve: its misfit has a floor of
    about 1.5 % of the size, below which it cannot rank entries (measured on
    open arcs: the entries nearest the exact linkage score no better than
    hundreds of others). Here each target is matched to its nearest point of
    the placed curve (on the segment between two of :data:`DENSE` samples), the
    rotation, scale and offset are re-fitted to those pairs (closed form), and
    this is repeated ``rounds`` times (iterative closest point).

    ``line`` more rounds then fit each point to the *line* along the curve at its
    nearest point (Gauss–Newton on the four numbers of ``h`` and ``t``, with 1 % of
    the along-the-line misses to stay defined on a straight arc), each kept for a
    curve only where it lowers that curve's RMS miss: on a short, gently curved arc
    the point-to-point rounds slide along the curve by ever smaller steps (the
    true linkage's own curve from a 0.41 % misfit: 0.37 % after 3 rounds, 0.20 %
    after 100), where the line rounds reach the polygon's sag (2.4e-6) in 2 or 3.

    Returns the new transforms (N, 2) and the RMS point-to-curve misses over
    the size (N,). Of a target of more than :data:`ICP_POINTS` points, that many
    spread evenly along it are re-fitted (the misses are of all the points).
    """
    Q = _dense_curves(rows)
    size = float(np.max(np.abs(pts - pts.mean())))
    few = pts
    if pts.size > ICP_POINTS:
        few = pts[np.unique(np.round(np.linspace(0, pts.size - 1, ICP_POINTS)).astype(int))]
    a0 = few - few.mean()
    h, t = transforms[:, 0].copy(), transforms[:, 1].copy()
    for _ in range(rounds):
        near = _nearest_on(Q, h, t, few)  # (N, K) in the curves' own frames
        bm = near.mean(axis=1, keepdims=True)
        b0 = near - bm
        v = np.sum(np.abs(b0) ** 2, axis=1)
        hn = np.sum(np.conj(b0) * a0[None, :], axis=1) / np.where(v > 0, v, np.inf)
        good = np.isfinite(hn) & (hn != 0)
        h, t = np.where(good, hn, h), np.where(good, few.mean() - hn * bm[:, 0], t)
    if line:
        h, t = _line_rounds(Q, h, t, few, line)
    near, i = _nearest_on(Q, h, t, pts, index=True)
    miss = _rms_miss(h, t, near, pts) / size
    # a rocker's circuit runs on both assemblies (sign of sin u): targets met on both
    # need a pass through a toggle, a branch defect that no refinement mends: last
    side = np.sign(np.sin(2 * np.pi * i / DENSE))
    mixed = (rows["barker"] > 2) & (np.ptp(side, axis=1) > 0)
    return np.column_stack([h, t]), np.where(mixed, miss + 1.0, miss)


def _dense_curves(rows) -> np.ndarray:
    """Atlas entries' curves at :data:`DENSE` samples in their own frames (inf where apart).

    A four-bar's round its circuit (:func:`~machdyn.synthesis.circuits.circuit_points`);
    a six-bar's (crank-driven) round a turn of its crank
    (:func:`~machdyn.synthesis.sixbar.sixbar_points`), as
    :func:`~machdyn.synthesis.atlas_store.even_curves` draws each kind.
    """
    if "topology" in rows.dtype.names:
        from .sixbar import sixbar_points

        Q = sixbar_points(rows, np.linspace(0.0, 2 * np.pi, DENSE, endpoint=False))[0]
    else:
        f = {k: rows[k].astype(float) for k in ("r1", "r3", "r4", "p", "delta")}
        Q, _ = circuit_points(f["r1"], 1.0, f["r3"], f["r4"], f["p"], f["delta"],
                              rows["circuit"].astype(float), DENSE)  # fmt: skip
    return np.where(np.isfinite(Q), Q, np.inf)


def _line_rounds(Q, h, t, pts, rounds: int, along: float = 0.01):
    """``rounds`` point-to-line Gauss–Newton steps of the placements ``t + h·Q`` (N curves).

    Each target ``p_k`` is paired with its nearest point ``c_k`` of the polygon ``Q``
    (in the curve's frame) and that edge's direction ``τ_k``; the step ``(δh, δt)``
    minimises ``Σ [n_k·(t + δt + (h + δh) c_k − p_k)]² + along² Σ [e_k·(…)]²`` with
    ``e_k = h τ_k/|h τ_k|`` and ``n_k = j e_k`` (linear least squares in the four
    real numbers). A curve keeps a step only if its RMS miss falls.
    """

    def miss(h, t):
        return _rms_miss(h, t, _nearest_on(Q, h, t, pts), pts)

    current = miss(h, t)
    eye = np.eye(4)
    for _ in range(rounds):
        c, tau = _nearest_on(Q, h, t, pts, tangent=True)
        e = h[:, None] * tau
        e = e / np.where(np.abs(e) > 0, np.abs(e), 1.0)
        res = t[:, None] + h[:, None] * c - pts[None, :]
        blocks, rhs = [], []
        for u, weight in ((1j * e, 1.0), (e, along)):
            g = np.conj(u) * c
            blocks.append(weight * np.stack([u.real, u.imag, g.real, -g.imag], axis=2))
            rhs.append(-weight * np.real(np.conj(u) * res))
        A, b = np.concatenate(blocks, axis=1), np.concatenate(rhs, axis=1)
        with np.errstate(all="ignore"):
            AtA = np.einsum("nki,nkj->nij", A, A)
            Atb = np.einsum("nki,nk->ni", A, b)
            ok = np.all(np.isfinite(AtA), axis=(1, 2)) & np.all(np.isfinite(Atb), axis=1)
            AtA = np.where(ok[:, None, None], AtA, eye)
            AtA = AtA + 1e-12 * np.trace(AtA, axis1=1, axis2=2)[:, None, None] * eye
            du = np.linalg.solve(AtA, np.where(ok[:, None], Atb, 0.0)[..., None])[..., 0]
            t2, h2 = t + du[:, 0] + 1j * du[:, 1], h + du[:, 2] + 1j * du[:, 3]
            new = miss(h2, t2)
        better = ok & (new < current) & (h2 != 0)
        h, t, current = (
            np.where(better, h2, h),
            np.where(better, t2, t),
            np.where(better, new, current),
        )
    return h, t


def _rms_miss(h, t, near, pts) -> np.ndarray:
    """Per curve, the RMS distance of the targets from their placed nearest points.

    ``near`` (N, K) in the curves' frames, placed by ``t + h·near``; ``inf`` where the
    RMS is not finite.
    """
    rms = np.sqrt(np.mean(np.abs(t[:, None] + h[:, None] * near - pts[None, :]) ** 2, axis=1))
    return np.where(np.isfinite(rms), rms, np.inf)


def _nearest_on(Q, h, t, pts, index=False, tangent=False):
    """Nearest point to each target of each polygon ``t + h·Q`` (N, M), in Q's frame (N, K).

    ``index``: also return the nearest sample of each (N, K); ``tangent``: instead,
    the unit direction of the edge the nearest point lies on (N, K), in Q's frame.
    """
    w = (pts[None, :] - t[:, None]) / np.where(h != 0, h, 1.0)[:, None]  # (N, K)
    n = np.arange(Q.shape[0])[:, None]
    i = np.argmin(np.abs(Q[:, None, :] - w[:, :, None]), axis=2)  # nearest sample (N, K)
    m = Q.shape[1]
    best = Q[n, i]
    # (at a sample itself: the chord across it)
    edge = Q[n, (i + 1) % m] - Q[n, (i - 1) % m] if tangent else None
    for a, b in ((Q[n, i], Q[n, (i + 1) % m]), (Q[n, (i - 1) % m], Q[n, i])):  # its two edges
        seg = b - a
        den = np.where(np.abs(seg) > 0, np.abs(seg) ** 2, np.inf)
        u = np.clip(np.real((w - a) * np.conj(seg)) / den, 0.0, 1.0)
        c = a + u * seg
        closer = np.abs(w - c) < np.abs(w - best)
        best = np.where(closer, c, best)
        edge = np.where(closer, seg, edge) if tangent else None
    if tangent:
        with np.errstate(invalid="ignore"):
            return best, edge / np.where(np.abs(edge) > 0, np.abs(edge), 1.0)
    return (best, i) if index else best


@functools.lru_cache(maxsize=2)
def _wide_rows(crank: bool) -> np.ndarray:
    """:data:`WIDE_POOL` random four-bars over :data:`WIDE_RANGE` (the same every call)."""
    from .atlas_store import sample_fourbars

    rows = sample_fourbars(np.random.default_rng(14), WIDE_POOL, WIDE_RANGE)
    rows = rows[rows["barker"] <= 2] if crank else rows
    rows.flags.writeable = False
    return rows


@functools.lru_cache(maxsize=2)
def _wide_curves(crank: bool, circuit_samples: int, samples: int) -> np.ndarray:
    """Even samples of the curves of :func:`_wide_rows` (computed once)."""
    curves = even_curves(_wide_rows(crank), circuit_samples, samples)
    curves.flags.writeable = False
    return curves


def _retrieve_wide(atlas: Atlas, pts, closed, crank, refine_count):
    """The ``refine_count`` best-placed of :func:`_wide_rows` and their placements (untimed)."""
    man = atlas.manifest
    rows = _wide_rows(crank)
    curves = _wide_curves(crank, man.circuit_samples, man.samples)
    if not closed:
        return _arc_starts(rows, curves, pts, refine_count)
    transforms, residual = align_closed(_even_target(man, pts), curves)
    order = np.argsort(residual)[:refine_count]
    return rows[order], transforms[order]


#: Entries whose starts are computed at once (see _untimed_starts).
STARTS_BLOCK = 64


def _start_untimed(row, tr, pts):
    """Refinement start of an atlas entry placed by ``tr = (h, t)``: design, θ_k, assembly_k."""
    return _untimed_starts(np.asarray(row).reshape(1), np.reshape(tr, (1, 2)), pts)[0]


def _untimed_starts(entries, transforms, pts) -> list:
    """Refinement starts of atlas entries placed by ``transforms`` (rows ``(h, t)``).

    Each a design ``x0`` (the entry scaled, turned and moved by its placement), the
    input angle and assembly of each target's nearest of 720 samples round the
    entry's circuit; None where the placement is not finite or zero. All the entries'
    circuits at once (one entry at a time, the 240 starts of a neighbour round took
    0.2 s); the same numbers as entry by entry (elementwise operations).
    """
    entries = np.asarray(entries)
    transforms = np.asarray(transforms, dtype=complex).reshape(-1, 2)
    if entries.size > STARTS_BLOCK:  # (a block's samples stay in cache: a third of the time)
        return [s for lo in range(0, entries.size, STARTS_BLOCK)
                for s in _untimed_starts(entries[lo : lo + STARTS_BLOCK],
                                         transforms[lo : lo + STARTS_BLOCK], pts)]  # fmt: skip
    if entries.size == 0:
        return []
    f = {k: entries[k].astype(float) for k in ("r1", "r3", "r4", "p", "delta")}
    circuit = entries["circuit"].astype(float)
    h, t = transforms[:, 0], transforms[:, 1]
    ok = np.isfinite(h) & (h != 0)
    # (element by element, as numpy's scalars do it: its array abs rounds otherwise)
    s = np.array([abs(v) for v in h], dtype=float)
    rot = np.array([np.angle(v) for v in h], dtype=float)
    # dense samples of each circuit, to start each target at its nearest point
    local, theta2 = circuit_points(f["r1"], 1.0, f["r3"], f["r4"], f["p"], f["delta"], circuit,
                                   720)  # fmt: skip
    c, hw, ck = circuit_range(f["r1"], 1.0, f["r3"], f["r4"], circuit)
    u = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    _, branch = circuit_angles(u[None, :], c[:, None], hw[:, None], ck[:, None], circuit[:, None])
    x0 = np.column_stack([f["r1"] * s, s, f["r3"] * s, f["r4"] * s, f["p"] * s, f["delta"],
                          t.real, t.imag, rot])  # fmt: skip
    with np.errstate(invalid="ignore", over="ignore"):
        placed = t[:, None] + h[:, None] * local  # (N, 720)
        near = np.argmin(np.abs(placed[:, None, :] - pts[None, :, None]), axis=2)  # (N, K)
    n = np.arange(entries.size)[:, None]
    return [(x0[i], theta2[n[i], near[i]], branch[n[i], near[i]]) if ok[i] else None
            for i in range(entries.size)]  # fmt: skip


#: The neighbour round of an open untimed target (see _neighbour_starts): the distinct best
#: fits taken (at least NEIGHBOUR_APART apart in design numbers) and the atlas entries nearest
#: to each, among the first NEIGHBOUR_ROWS of the atlas (a random sample of it, as every chunk
#: is: a tenth of the 10^7).
NEIGHBOURS = (4, 40)
NEIGHBOUR_APART = 0.05
NEIGHBOUR_ROWS = 1_000_000
NEIGHBOUR_ICP = 3


def _design_numbers(r1, r2, r3, r4, p, delta) -> np.ndarray:
    """Four-bars' design numbers (N, 5): ``ln`` of r1, r3, r4 over r2, the coupler point over r3.

    The coupler point as ``(p/r3) e^{jδ}`` in the coupler's own frame (A at 0, B at 1),
    its real and imaginary parts: the numbers in which the session-11 study measured
    how far a fit lies from a target's drawing linkage (its basin about 0.3 across).
    """
    values = (np.asarray(v, dtype=float) for v in (r1, r2, r3, r4, p, delta))
    r1, r2, r3, r4, p, delta = np.broadcast_arrays(*values)
    c = p / r3 * np.exp(1j * delta)
    return np.stack([np.log(r1 / r2), np.log(r3 / r2), np.log(r4 / r2), c.real, c.imag], axis=-1)


def _neighbour_table(atlas: Atlas, crank: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Flat indices, design numbers (float32, (5, rows)) and squared norms of the rows searched.

    The first :data:`NEIGHBOUR_ROWS` of the atlas (crank entries only with ``crank``),
    kept per opened atlas: computing them takes ~0.1 s, once (20 MB).
    """
    cache = _NEIGHBOUR_TABLES.setdefault(atlas, {})
    if crank not in cache:
        idx, numbers, left = [], [], NEIGHBOUR_ROWS
        for c, m in enumerate(atlas.meta):
            if left <= 0:
                break
            m = m[:left]
            left -= m.size
            sel = np.flatnonzero(m["barker"] <= 2) if crank else np.arange(m.size)
            m = m[sel]
            idx.append(sel + atlas.offsets[c])
            numbers.append(_design_numbers(m["r1"], 1.0, m["r3"], m["r4"], m["p"], m["delta"]))
        # (one row per number: the fits' distances are then a (fits, 5) x (5, rows) product,
        # 0.02 s over 10^6 rows, where rows x numbers took 0.17 s)
        table = np.ascontiguousarray(np.concatenate(numbers).T, dtype=np.float32)
        cache[crank] = (np.concatenate(idx), table, np.einsum("ij,ij->j", table, table))
    return cache[crank]


#: :func:`_neighbour_table`'s tables, per opened atlas.
_NEIGHBOUR_TABLES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _neighbour_starts(atlas: Atlas, fits, pts, crank: bool) -> list:
    """Starts of an open untimed target's neighbour round: entries near its best fits.

    For each of the ``NEIGHBOURS[0]`` best fits (by RMS, whether or not an answer)
    whose design numbers (:func:`_design_numbers`) lie :data:`NEIGHBOUR_APART` from
    those taken already, the ``NEIGHBOURS[1]`` entries nearest to it among
    :func:`_neighbour_table`'s, placed as the fit is (its crank length, ground line
    and pivot), re-placed by the point-to-point re-fit (:func:`_fit_to_points`) and
    started at their nearest points to the targets (:func:`_untimed_starts`).

    An open target's fits can stall in local minima while the pools' 4,000 entries
    hold none of the few tens to hundreds of the 10^7 that refine to an exact answer
    (``bench_atlas_random.py --kinds open``: seed 1's cases 13 and 14, seed 3's case 13,
    non-Grashof rockers' arcs). Their best fits lie 0.4–4 in these numbers from the
    drawing linkage and its twin driven by link 4 (a basin is about 0.3 across), so the
    round seldom reaches the drawing linkage itself; what it reaches is another exact
    answer, by chance: from the first round's fits of seed 1's case 13, the 40 entries
    nearest to its third fit hold one in each of five disjoint 10^6-entry tenths of the
    atlas; seed 3's case 13 is met from the first tenth's only, seed 1's case 14 from none
    (see docs/synthesis.md, session 12). The search is a (fits, 5) x (5, rows) product
    and a partial sort (~0.05 s); the round's screening and polish about as much again.
    """
    most, count = NEIGHBOURS
    idx, table, norms = _neighbour_table(atlas, crank)
    if table.shape[1] <= count:
        return []
    keys, places = [], []
    for f in sorted(fits, key=lambda f: f.rms):
        if len(keys) == most:
            break
        x = f.x
        with np.errstate(all="ignore"):
            key = _design_numbers(abs(x[0]), abs(x[1]), abs(x[2]), abs(x[3]), x[4], x[5])
        if not np.all(np.isfinite(key)) or any(np.max(np.abs(key - k)) <= NEIGHBOUR_APART
                                               for k in keys):  # fmt: skip
            continue
        keys.append(key)
        places.append((abs(x[1]) * np.exp(1j * x[8]), complex(x[6], x[7])))
    if not keys:
        return []
    # squared distances less the fits' own norms: one matrix product over the rows
    d = np.asarray(keys, dtype=np.float32) @ table
    d *= np.float32(-2.0)
    d += norms
    near = np.argpartition(d, count, axis=1)[:, :count]  # (fits, count)
    rows = atlas.entries(idx[near.ravel()])
    transforms = np.repeat(np.array(places, dtype=complex), count, axis=0)
    transforms, _ = _fit_to_points(rows, transforms, pts, rounds=NEIGHBOUR_ICP)
    return _untimed_starts(rows, transforms, pts)


def _retrieve_timed(atlas: Atlas, pts, timing, closed, retrieve, refine_count, client=None,
                    fixed=None, deadline: _Deadline = _NEVER):  # fmt: skip
    """Refinement starts for timed targets, and the pool's next-best ones.

    Scans θ0 for every entry of a pool and fits each.

    For each crank entry (and its mirror image: δ → −δ on the other assembly,
    which runs the other way round for the same crank rotation) and each of
    ``TIMED_GRID`` starting angles θ0, the coupler points at ``θ0 + Δ_k`` are
    fitted onto the targets by a rotation, scale and offset (closed form); the
    best fits start the refinements. ``fixed`` (see :func:`refine`) holds the
    pivot, the ground line's direction or θ0 (absolute timing): the fit then
    keeps them (a scale only, or a scale and rotation). Past the ``deadline``, the
    query scores no more chunks (:meth:`Atlas._query`) and the wide rows are left out.
    Returns the starts (the ``refine_count`` best of the pool's rows and of the wide
    rows) and the pool's :data:`TIMED_SPARE` next best (for a later round on a small
    atlas, see ``atlas_path.TIMED_ROUNDS``).
    """
    fixed = fixed or {}
    man = atlas.manifest
    idx = atlas.pool(TIMED_POOL, crank=True)
    if closed:
        q = curve_descriptor(_even_target(man, pts), man.harmonics, resampled=True)
        idx = np.union1d(idx, atlas._query(q, retrieve, True, client, deadline)[0])
    wide = _wide_rows(True)[: None if 9 in fixed else WIDE_TIMED]  # θ0 scanned: fewer
    wide = wide[:0] if deadline.passed() else wide
    held = 6 in fixed or 8 in fixed  # (refine_count was quadrupled for them)
    groups = [(rows, count) for rows, count in (
        (atlas.entries(idx), refine_count),
        (wide, max(1, refine_count // 4) if held else refine_count)) if rows.size]  # fmt: skip
    # every row scored in one call (on threads), the best starts picked group by group
    scored = _timed_scored(np.concatenate([rows for rows, _ in groups]), pts, timing, fixed)
    starts, next_best, lo = [], [], 0
    for i, (rows, count) in enumerate(groups):
        part = tuple(x[:, lo : lo + rows.size] for x in scored)
        ranked = _timed_starts(rows, pts, timing, count + (TIMED_SPARE if i == 0 else 0), fixed,
                               part)  # fmt: skip
        starts += ranked[:count]
        next_best += ranked[count:]
        lo += rows.size
    return starts, next_best


def _timed_grid(fixed, count: int = TIMED_GRID) -> np.ndarray:
    """``count`` starting crank angles θ0 scanned for timed targets (θ0 itself when held)."""
    return np.zeros(1) if 9 in fixed else np.linspace(0.0, 2 * np.pi, count, endpoint=False)


def _timed_scored(rows, pts, timing, fixed, grid: int = TIMED_GRID) -> tuple:
    """:func:`_timed_fits` of every row (score, θ0 index, h, t; each (2, rows)), on threads.

    ``grid``: the number of starting angles scanned (:func:`_timed_grid`).
    """
    from .._parallel import for_slices

    table = _angle_table(_timed_grid(fixed, grid)[:, None] + timing[None, :])  # (G, K) angles
    O2 = complex(fixed[6], fixed[7]) if 6 in fixed else None
    out = (np.empty((2, rows.size)), np.empty((2, rows.size), np.int64),
           np.empty((2, rows.size), complex), np.empty((2, rows.size), complex))  # fmt: skip

    def run(sl: slice) -> None:  # each thread a run of rows (the fit kernels release the GIL)
        for lo in range(sl.start, sl.stop, TIMED_BLOCK):
            part = slice(lo, min(lo + TIMED_BLOCK, sl.stop))
            for x, y in zip(out, _timed_fits(rows[part], table, pts, O2, fixed.get(8)),
                            strict=True):  # fmt: skip
                x[:, part] = y

    for_slices(run, rows.size, minimum=TIMED_THREADS)
    return out


def _timed_starts(rows, pts, timing, refine_count, fixed, scored=None, grid: int = TIMED_GRID):
    """The ``refine_count`` best timed starts among ``rows`` (both mirror images).

    ``scored``: :func:`_timed_scored` of these rows, when already computed.
    ``grid``: the number of starting angles scanned (:func:`_timed_grid`).
    """
    scored = scored or _timed_scored(rows, pts, timing, fixed, grid)
    score, g, hh, off = (x.ravel() for x in scored)
    # (2, rows) each, flattened: all entries as stored, then all mirrored
    mirror = np.repeat([1.0, -1.0], rows.size)
    order = np.argsort(-score)[:refine_count]
    rows2 = np.concatenate([rows, rows])
    angles = _timed_grid(fixed, grid)
    starts = []
    for i in order:
        row, m, h = rows2[i], mirror[i], hh[i]
        r1, r3, r4, p, delta = (float(row[k]) for k in ("r1", "r3", "r4", "p", "delta"))
        s = abs(h)
        x0 = np.array([r1 * s, s, r3 * s, r4 * s, p * s, m * delta, off[i].real, off[i].imag,
                       np.angle(h)])  # fmt: skip
        theta = angles[g[i]] + timing
        starts.append((x0, theta, np.full(pts.size, m * float(row["circuit"]))))
    return starts


#: Entries scored by one call of the timed fits (NumPy: their coupler points at once), and
#: the fewest worth threads (the compiled fits of a thousand entries take ~3 ms).
TIMED_BLOCK = 2048
TIMED_THREADS = 1024


def _angle_table(th: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Distinct crank angles of ``θ0_g + Δ_k`` and of their negatives, and where each lies.

    Returns the angles (in [0, 2π], to 1e-12 rad) and the index of each
    ``th[g, k]`` and of each ``−th[g, k]`` in them: the coupler points are
    computed once per distinct angle (steps of 20° from a grid of 6° meet only
    180 angles, not 2 × 60 × 18), and a mirror image's point at θ is the
    conjugate of the stored linkage's point at −θ.
    """
    both = np.concatenate([th.ravel(), -th.ravel()])
    angles, where = np.unique(np.round(np.mod(both, 2 * np.pi), 12), return_inverse=True)
    where = where.reshape(2, *th.shape)
    return angles, where[0], where[1]


def _timed_fits(rows, table, pts, O2=None, theta1=None):
    """Best θ0 (index), fit score and placement ``h, t`` of each entry for timed targets.

    For the entries as stored and mirrored (δ → −δ on the other assembly), each
    shaped (2, rows). The placement ``t + h·Q`` minimising ``Σ |a_k − t − h Q_k|²``
    in closed form: ``t`` the offset (``O2`` when held) and ``h`` a rotation and
    scale (a scale ``s ≥ 0`` times ``e^{jθ1}`` when ``θ1`` is held). The score is
    the share of the targets' spread the fit explains. ``table``: see
    :func:`_angle_table`. Compiled, the coupler points and the fits are one kernel
    (:func:`~machdyn.synthesis._atlas_kernels.timed_scores`: the points of a few
    entries at a time stay in cache); NumPy computes the points of all the rows
    (:func:`~machdyn.synthesis.atlas.coupler_points`), then the fits.
    """
    from .. import jit
    from ..fourbar import _CLOSE_TOL
    from .atlas import _kernel, _kernel_inputs

    angles, ip, im = table
    f = {k: rows[k].astype(float) for k in ("r1", "r3", "r4", "p", "delta")}
    circuit = rows["circuit"].astype(float)
    centre = pts.mean() if O2 is None else O2
    a = pts - centre
    held = np.nan if theta1 is None else float(theta1)
    out = (np.empty((2, rows.size)), np.empty((2, rows.size), np.int64),
           np.empty((2, rows.size), complex), np.empty((2, rows.size), complex))  # fmt: skip
    if jit.kernels(rows.size * angles.size) is not None:
        from ._atlas_kernels import timed_scores

        lengths, offsets = _kernel_inputs(f["r1"], np.ones(rows.size), f["r3"], f["r4"], f["p"],
                                         f["delta"], circuit)  # fmt: skip
        timed_scores(lengths, offsets, np.cos(angles), np.sin(angles), _CLOSE_TOL, ip, im, a,
                     O2 is None, held, *out)  # fmt: skip
    else:
        Q, _ = _kernel(f["r1"], np.ones(rows.size), f["r3"], f["r4"], f["p"], f["delta"], angles,
                       circuit)  # fmt: skip
        _timed_scores_numpy(Q, ip, im, a, O2 is None, held, *out)
    score, g, h, qm = out
    return score, g, h, centre - h * qm


def _timed_scores_numpy(Q, ip, im, a, centred, theta1, score, best, h, qm):
    """NumPy reference of :func:`machdyn.synthesis._atlas_kernels.timed_scores` (same outputs)."""
    for m, q in enumerate((Q[:, ip], np.conj(Q[:, im]))):  # (R, G, K)
        mean = q.mean(axis=2, keepdims=True) if centred else np.zeros_like(q[..., :1])
        q = q - mean
        c = np.sum(np.conj(q) * a, axis=2)  # (R, G)
        v = np.sum(q.real**2 + q.imag**2, axis=2)
        v = np.where(v > 0, v, np.inf)
        if np.isnan(theta1):
            hh = c / v
            gain = np.abs(c) ** 2 / v
        else:
            along = np.maximum(np.real(c * np.exp(-1j * theta1)), 0.0)
            hh = along / v * np.exp(1j * theta1)
            gain = along**2 / v
        s = np.nan_to_num(gain / max(float(np.sum(np.abs(a) ** 2)), 1e-300), nan=-1.0)
        g = np.argmax(s, axis=1)
        r = np.arange(q.shape[0])
        score[m], best[m], h[m], qm[m] = s[r, g], g, hh[r, g], mean[r, g, 0]
