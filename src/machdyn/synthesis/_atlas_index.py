"""An opened atlas and its query: the ``k`` entries nearest a descriptor, chunk by chunk.

:func:`open_atlas` checks an atlas folder (its manifest, version and every
chunk's CRC-32) and memory-maps its chunks; :class:`Atlas` answers the nearest
entries to a descriptor in any of its four variants by one float32 matrix
product per block of rows (BLAS) and a partial sort, on threads or as Dask
tasks (:func:`chunk_topk_file`), and spreads pools of entries over the atlas
for open targets. From an atlas's second query on (compiled), a compact table
derived from a chunk (int16 head columns, uint16 norms of the others, sorted by a
key column; built once, in memory, a budget of chunks per query) bounds every
score, and only the rows whose bound beats the k-th best so far are scored
(:func:`bounded_topk`); the chunks without one are scored by BLAS. Either way, the
candidates (every row that may be among the best k, and a few more) are ranked by
their exact scores in float64, best first and equal scores by index
(:meth:`Atlas._exact_scores`): every path gives the same top k for the same atlas
and target. Used by :mod:`~machdyn.synthesis.atlas_path`.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import boolean, finite_array, integer
from ..errors import InputError
from .atlas_store import (
    META_DTYPE,
    AtlasError,
    Manifest,
    chunk_is_good,
    chunk_name,
    folder_path,
    read_manifest,
)
from .descriptor import descriptor_variants
from .sixbar import SIXBAR_DTYPE

__all__: list[str] = []  # (machdyn.synthesis re-exports Atlas and open_atlas)

#: Atlas entries retrieved per query.
RETRIEVE = 160
#: Rows per BLAS call in a query (below OpenBLAS's threading threshold; see chunk_topk).
BLAS_ROWS = 2048
#: Size of the pool an open target is matched against (entries spread over the atlas).
OPEN_POOL = 4_000


class _Deadline:
    """When a synthesis must stop (:func:`time.perf_counter` seconds) and whether it did.

    ``passed()`` is asked between stages (a pool round, a batch of polished fits,
    one start's screening); once it answers True, ``hit`` records that the result
    is the best found by the time limit. ``at = inf`` (no limit) never passes, so
    a synthesis without a limit takes exactly the steps it took before.
    """

    __slots__ = ("at", "hit")

    def __init__(self, at: float = np.inf) -> None:
        self.at, self.hit = at, False

    def passed(self) -> bool:
        if not self.hit and time.perf_counter() >= self.at:
            self.hit = True
        return self.hit


_NEVER = _Deadline()  # (never passes: shared by the calls without a limit)


class Atlas:
    """An opened atlas: descriptors and parameters of its entries, chunk by chunk.

    Use :func:`open_atlas`. The arrays are memory-mapped: the operating
    system keeps them in memory after the first query.
    """

    def __init__(self, path: Path, manifest: Manifest, desc: list, meta: list) -> None:
        self.path = path
        self.manifest = manifest
        self.desc = desc
        self.meta = meta
        self.offsets = np.concatenate([[0], np.cumsum([m.size for m in meta])])
        self._crank = [np.ascontiguousarray(m["barker"] <= 2) for m in meta]  # GCCC, GCRR
        self._pools: dict[tuple[int, bool], np.ndarray] = {}
        self._plan: tuple | None = None  # the compact tables' columns (see _query_plan)
        self._compact: dict[tuple[int, bool], tuple] = {}  # (see _tables)
        self._queries = 0
        self._plain: list | None = None  # (see _exact_scores)

    def __len__(self) -> int:
        return int(self.offsets[-1])

    def __repr__(self) -> str:
        return f"Atlas({str(self.path)!r}, {len(self):,} entries)"

    def entries(self, index: Any) -> np.ndarray:
        """Parameter rows of the entries at flat indices."""
        index = np.atleast_1d(finite_array("index", index)).ravel()
        if index.size and (
            np.any(index != np.round(index)) or index.min() < 0 or index.max() >= len(self)
        ):
            raise InputError("index", f"must be whole numbers from 0 to {len(self) - 1}")
        index = index.astype(np.int64)
        chunk = np.searchsorted(self.offsets, index, side="right") - 1
        out = np.empty(index.size, dtype=self.meta[0].dtype)
        for c in np.unique(chunk):
            sel = chunk == c
            out[sel] = self.meta[c][index[sel] - self.offsets[c]]
        return out

    def nearest(self, descriptor: Any, k: int = RETRIEVE, *, crank: bool = True, client=None):
        """The ``k`` entries nearest to a descriptor in any of its variants.

        ``client``: a ``distributed.Client``: each chunk is then scored by a
        task on the cluster (whose workers must see the atlas folder).
        Returns flat indices and squared distances (best first: by the exact
        float64 score, equal scores by index), the same on every path.
        """
        width = 4 * self.manifest.harmonics
        descriptor = np.ravel(finite_array("descriptor", descriptor))
        if descriptor.size != width:
            raise InputError("descriptor", f"must have {width} numbers, got {descriptor.size}")
        k = integer("k", k, minimum=1, maximum=1_000_000)
        crank = boolean("crank", crank)
        if client is not None and not callable(getattr(client, "submit", None)):
            raise InputError("client", "must be a distributed.Client (or None)")
        return self._query(descriptor, k, crank, client, _NEVER)

    def _query(self, descriptor, k: int, crank: bool, client, deadline: _Deadline):
        """:meth:`nearest` on checked inputs; past the ``deadline``, no more chunks.

        Each thread stops after the chunk it is scoring when the deadline passes
        (it scores one at least): the entries returned are then the nearest of the
        chunks scored, a random share of the atlas (its chunks are independent
        samples). The chunks given to a Dask cluster are all scored.
        """
        variants = np.ascontiguousarray(descriptor_variants(descriptor).reshape(4, -1))  # (4, D)
        if client is None:
            parts = self._local_topk(variants, k, crank, deadline)
        else:
            futures = [
                client.submit(chunk_topk_file, str(self.path), c, variants, k, crank, pure=False)
                for c in range(len(self.desc))
            ]
            parts = list(enumerate(client.gather(futures)))
        idx = np.concatenate([top + self.offsets[c] for c, (top, _) in parts]).astype(np.int64)
        near = np.concatenate([s for _, (_, s) in parts]).astype(np.float64)
        if near.size > k:  # the candidates that can be among the best k (float64 scores)
            kth = np.partition(near, near.size - k)[near.size - k]
            idx = idx[near >= kth - SCORE_SLACK]
        score = self._exact_scores(idx, variants)
        order = np.lexsort((idx, -score))[:k]  # best first; equal scores by index
        return idx[order], 2.0 - 2.0 * score[order]

    def _exact_scores(self, idx: np.ndarray, variants: np.ndarray) -> np.ndarray:
        """The scores (cosine, best of the variants) of the entries at flat ``idx``, in float64.

        The ranking's scores: computed from the stored descriptors alone, in one
        fixed order of operations (a column at a time, the same for every row and
        every batch), so that an entry's score does not depend on the path that
        found it (first or later query, NumPy or compiled, local or Dask) nor on the
        other candidates.
        """
        idx = np.asarray(idx, dtype=np.int64)
        if self._plain is None:  # (the chunks' arrays: a row's view is cheaper than a memmap's)
            self._plain = [np.asarray(d) for d in self.desc]
        chunk = np.searchsorted(self.offsets, idx, side="right") - 1
        d = np.empty((idx.size, variants.shape[1]), dtype=np.float64)
        order = np.argsort(chunk, kind="stable")  # (each chunk's rows in one read)
        cuts = np.searchsorted(chunk[order], np.arange(len(self.desc) + 1))
        for c in np.flatnonzero(np.diff(cuts)):
            at = order[cuts[c] : cuts[c + 1]]
            d[at] = self._plain[c][idx[at] - self.offsets[c]]  # (float32 -> float64 exactly)
        return exact_scores(d, variants)

    def _local_topk(self, variants: np.ndarray, k: int, crank: bool,
                    deadline: _Deadline = _NEVER) -> list:  # fmt: skip
        """The best ``k`` of every chunk, on the threads of :mod:`machdyn._parallel`.

        Each thread scores a run of chunks (the BLAS products, the comparisons, the
        partial sort and the compiled kernels release the GIL) and keeps a heap of the
        best ``k`` float64 scores it met, its root the floor that later chunks must
        beat. From an atlas's second query on (compiled), a chunk whose
        compact tables exist (:meth:`_tables`) goes through :func:`bounded_topk`: a
        bound of every row's score from the table, the exact score of the rows whose
        bound beats the floor. The others are scored by :func:`chunk_topk` (every row,
        BLAS), and each query builds the tables of at most :data:`TABLE_BUDGET` of them
        (:meth:`_to_build`), so that no query pays for the whole atlas's tables: the
        first query (often the only one of a process) builds none. A thread whose
        bound passes more than :data:`BOUND_FALLBACK` of a chunk's rows (a target in a
        dense cluster of near-equal curves, where the bound's resolution cannot tell
        them apart) scores the rest of its chunks by BLAS, which is cheaper then. The
        union holds the exact top k whichever way each chunk went. Returns ``(chunk,
        (rows, scores))`` for the chunks scored: past the ``deadline``, each thread
        stops after its current chunk.
        """
        from .. import jit
        from .._parallel import for_slices

        parts: list = [None] * len(self.desc)
        starts = self.offsets[:-1]
        two = jit.active() and self._queries > 0
        self._queries += 1
        build: frozenset = frozenset()
        if two:
            stage = _FirstStage(variants, *self._query_plan())
            build = self._to_build(crank)

        def run(sl: slice) -> None:
            best = np.full(k, -np.inf)  # (a min-heap of the thread's best scores)
            bounded = two
            for c in np.flatnonzero((starts >= sl.start) & (starts < sl.stop)):
                if bounded and (c in build or self._has_tables(c, crank)):
                    rows, score, scored = bounded_topk(self.desc[c], self._tables(c, crank),
                                                       stage, best)  # fmt: skip
                    parts[c] = rows, score
                    bounded = scored <= BOUND_FALLBACK * self.desc[c].shape[0]
                else:
                    ok = self._crank[c] if crank else None
                    parts[c] = chunk_topk(self.desc[c], ok, variants, k, float(best[0]))
                    _raise_floor(best, parts[c][1])
                if deadline.passed():
                    break

        for_slices(run, len(self))
        return [(c, p) for c, p in enumerate(parts) if p is not None]

    def _has_tables(self, c: int, crank: bool) -> bool:
        """Whether chunk ``c``'s compact tables for a query with (or without) ``crank`` exist."""
        return (c, True) in self._compact and (crank or (c, False) in self._compact)

    def _to_build(self, crank: bool) -> frozenset:
        """The chunks whose compact tables this query builds: :data:`TABLE_BUDGET` tables at most.

        Of the chunks lacking some (the crank rows' table; unless ``crank``, the
        others' too), evenly spread over the atlas: each thread of :meth:`_local_topk`
        scores a run of chunks, and builds its share.
        """
        need = [(c, 2 - ((c, True) in self._compact) - ((c, False) in self._compact or crank))
                for c in range(len(self.desc))]  # fmt: skip
        todo = [(c, n) for c, n in need if n > 0]
        if sum(n for _, n in todo) <= TABLE_BUDGET:
            return frozenset(c for c, _ in todo)
        picks, spent = [], 0
        step = len(todo) * np.mean([n for _, n in todo]) / TABLE_BUDGET
        for i in np.unique((np.arange(len(todo) / step) * step).astype(int)):
            c, n = todo[i]
            if spent + n <= TABLE_BUDGET:
                picks.append(c)
                spent += n
        return frozenset(picks)

    def _query_plan(self) -> tuple[np.ndarray, np.ndarray, int]:
        """The compact tables' columns: the :data:`HEAD` of most energy, the groups, the key.

        The energy is the mean square in the first chunk; the other columns, in
        order of energy, are split into :data:`TAIL_GROUPS` groups (``groups[j]``:
        column ``j``'s group, −1 for a head column). The tables are sorted by the
        head column of second most energy (its position in the head: ``kcol``): a
        query's windows on it (:func:`~machdyn.synthesis._atlas_kernels.key_ranges`)
        hold the fewest rows (measured on the 10^7 atlas for the literature's closed
        targets and atlas curves: 5–33 % of the rows, the first column 6–61 %).
        """
        if self._plan is None:
            first = np.asarray(self.desc[0], dtype=np.float64)
            order = np.argsort(-np.mean(first**2, axis=0), kind="stable")
            groups = np.full(first.shape[1], -1, np.int64)
            for g, part in enumerate(np.array_split(order[HEAD:], TAIL_GROUPS)):
                groups[part] = g
            cols = np.sort(order[:HEAD]).astype(np.int64)
            self._plan = (cols, groups, int(np.flatnonzero(cols == order[1])[0]))
        return self._plan

    def _tables(self, c: int, crank: bool) -> tuple:
        """Chunk ``c``'s compact tables: of its crank rows, and (unless ``crank``) the others.

        Each ``(head, tail, rows, hs, ts, longest2)`` (see
        :func:`~machdyn.synthesis._atlas_kernels.compact_rows`), sorted by the key
        column (:meth:`_query_plan`) and built by the query that picks the chunk
        (:meth:`_to_build`): the :data:`HEAD` columns as int16 and the norms of the
        :data:`TAIL_GROUPS` groups of the others as uint16 (rounded up), ``2 (HEAD +
        TAIL_GROUPS)`` bytes a row, and the rows (int32): 110 MB for the 5·10^6 crank
        rows of 10^7 entries (the queries with ``crank``; timed targets always), 220 MB
        for all of them.
        """
        from ._atlas_kernels import compact_rows

        parts = (True,) if crank else (True, False)
        for part in parts:
            if (c, part) not in self._compact:
                cols, groups, kcol = self._query_plan()
                rows = np.flatnonzero(self._crank[c] == part).astype(np.int32)
                head = np.empty((cols.size, rows.size), np.int16)
                tail = np.empty((TAIL_GROUPS, rows.size), np.uint16)
                hs, ts, longest2 = compact_rows(np.asarray(self.desc[c]), rows, cols, groups,
                                                head, tail)  # fmt: skip
                # sorted by the key afterwards (compacted in the rows' order, the reads are
                # sequential: in the key's order, 2.7 times slower)
                order = np.argsort(head[kcol], kind="stable")  # (the copies are contiguous)
                table = (head[:, order], tail[:, order], rows[order], hs, ts, longest2)
                self._compact[c, part] = table
        return tuple(self._compact[c, part] for part in parts)

    def pool(self, size: int = OPEN_POOL, *, crank: bool = True, draw: int = 0) -> np.ndarray:
        """Flat indices of up to ``size`` entries spread evenly over the atlas.

        ``draw`` 1, 2, … shifts the pool along the atlas by a golden-ratio share
        of its step (mod 1): each a different pool, spread as evenly.
        """
        size = integer("size", size, minimum=1, maximum=10**9)
        crank = boolean("crank", crank)
        draw = integer("draw", draw, minimum=0, maximum=10**6)
        key = (size, crank, draw)
        if key not in self._pools:  # the same pool every time: computed once
            allowed = np.flatnonzero(np.concatenate(self._crank)) if crank else np.arange(len(self))
            if allowed.size > size:
                if draw == 0:
                    at = np.linspace(0, allowed.size - 1, size)
                else:
                    step = (allowed.size - 1) / max(size - 1, 1)
                    at = np.arange(size) * step + (draw * 0.6180339887498949) % 1.0 * step
                allowed = allowed[np.minimum(at, allowed.size - 1).astype(np.int64)]
            self._pools[key] = allowed
        return self._pools[key].copy()


def chunk_topk(
    desc: np.ndarray,
    allowed: np.ndarray | None,
    variants: np.ndarray,
    k: int,
    floor: float = -np.inf,
) -> tuple[np.ndarray, np.ndarray]:
    """Rows and scores (cosine) of the ``k`` best allowed entries of one chunk (BLAS products).

    Every row is scored in float32 (within :func:`score_band` of the exact score):
    the rows within the band of the chunk's k-th best, less any more than the band
    below ``floor`` (the k-th best of the chunks seen so far), hold every row of
    the exact top k. Those are scored again in float64 (:func:`exact_scores`), and
    the rows within :data:`SCORE_SLACK` of the k-th best of those scores (and of
    ``floor``) are returned, with their float64 scores (:meth:`Atlas._query` ranks
    them): a target among many near-equal curves, whose float32 band holds
    thousands of rows a chunk, hands on only the few that may tie. The product
    runs in blocks of :data:`BLAS_ROWS` rows: below that size OpenBLAS computes on
    the calling thread, above it wakes its thread pool, which on a busy 2-core
    machine costs ~20 ms per call (measured: 65,536 rows in one call 29 ms, in
    blocks of 2,048 0.7 ms). Scale-out is the chunks' job.
    """
    n = desc.shape[0]
    prod = np.empty((n, variants.shape[0]), dtype=np.float32)
    right = variants.T
    for lo in range(0, n, BLAS_ROWS):
        np.matmul(desc[lo : lo + BLAS_ROWS], right, out=prod[lo : lo + BLAS_ROWS])
    score = prod[:, 0]
    for j in range(1, prod.shape[1]):  # max over the variants (faster than .max(axis=1))
        score = np.maximum(score, prod[:, j])
    band = score_band(variants)
    keep = score >= floor - band
    if allowed is not None:
        keep &= allowed
    rows = np.flatnonzero(keep)
    if rows.size > k:  # the k best, and every row whose exact score may tie them
        best = score[rows]
        rows = rows[best >= np.partition(best, best.size - k)[best.size - k] - band]
    exact = exact_scores(np.asarray(desc[rows], dtype=np.float64), variants)
    least = floor
    if rows.size > k:
        least = max(least, float(np.partition(exact, exact.size - k)[exact.size - k]))
    keep = exact >= least - SCORE_SLACK
    return rows[keep], exact[keep]


def exact_scores(d: np.ndarray, variants: np.ndarray) -> np.ndarray:
    """The scores (cosine, best of the variants) of the descriptor rows ``d`` (n, D), in float64.

    One fixed order of operations (a column at a time, the same for every row and
    every batch): a row's score does not depend on the other rows given.
    """
    v = np.asarray(variants, dtype=np.float64)
    acc = d[:, :1] * v[:, 0]  # (n, 4)
    for j in range(1, v.shape[1]):
        acc += d[:, j : j + 1] * v[:, j]
    return acc.max(axis=1) if acc.size else np.empty(0)


def score_band(variants: np.ndarray) -> float:
    """How far below the k-th best float32 score a row of the exact top k may score.

    A float32 product of two ``D``-vectors is within ``e = γ Σ|q_j d_j| ≤ γ |q| |d|``
    of the exact one, ``γ = (D + 1) u / (1 − (D + 1) u)``, ``u = 2⁻²⁴`` (the final
    rounding included; Higham, *Accuracy and Stability of Numerical Algorithms*,
    §3.1); the atlas's descriptors are unit vectors
    (:func:`~machdyn.synthesis.descriptor.curve_descriptor`, stored in float32:
    ``|d| < 1 + D u``). ``k`` rows score at least the k-th best ``F`` in float32, so
    the exact k-th best is above ``F − e`` and a row of the exact top k scores above
    ``F − 2e`` in float32: the band is ``2e``, doubled again as a margin (the
    compiled stage's float64 scores are far closer).
    """
    width = variants.shape[1]
    u = 2.0**-24
    gamma = (width + 1) * u / (1.0 - (width + 1) * u)
    return 4.0 * gamma * float(np.max(np.linalg.norm(variants, axis=1))) * (1.0 + width * u)


#: The query's first stage (see Atlas._local_topk): the descriptor columns kept per row
#: (the HEAD of most energy), and the groups of the others whose norms are kept; the
#: compiled kernel is written for these counts. Its slack over the float32 bound (the
#: rounding of ten float32 products is below 1e-6), and the float64 scores' margin (a
#: row scored within it of the k-th best so far is kept: its ranking score, perhaps
#: summed in another order by Atlas._exact_scores, may tie the k-th best's; two float64
#: sums of the same 32 products differ by less than 1e-14).
HEAD = 6
TAIL_GROUPS = 3
BOUND_SLACK = 1e-4
SCORE_SLACK = 1e-9
#: Compact tables (a chunk's crank rows, or its others) a query builds at most (see
#: Atlas._local_topk); and the share of a chunk's rows scored exactly past which a
#: thread scores its other chunks by BLAS. 80: the 153 crank tables of 10^7 entries are
#: complete after a process's third query (24: its eighth, and the literature's case 3,
#: whose queries come early in bench_atlas_literature's process, took 0.25 s wall, not
#: 0.07 s: its swarm ratio at machdyn's wall time fell to 10.1x median); the longest of
#: bench_atlas.py's 20 queries 0.39 s (24: 0.28 s), quiet, 2026-11-25.
TABLE_BUDGET = 80
BOUND_FALLBACK = 0.2


class _FirstStage:
    """One query's numbers for :func:`bounded_topk`: its four variants, and split.

    ``head``: the variants' head columns (4, HEAD); ``norms``: each group's norm
    per variant (4, TAIL_GROUPS); ``squares``: each variant's squared norm; ``kcol``:
    the key column's place in the head.
    """

    __slots__ = ("head", "kcol", "norms", "squares", "variants")

    def __init__(self, variants: np.ndarray, cols: np.ndarray, groups: np.ndarray,
                 kcol: int) -> None:  # fmt: skip
        # the compiled bound (_atlas_kernels.bound_topk) unrolls exactly these counts: with
        # others it would drop a group's term (a bound below the exact score prunes true
        # top-k rows) or read past the head, unchecked
        if (len(cols), int(groups.max()) + 1, variants.shape[0]) != (HEAD, TAIL_GROUPS, 4):
            raise AssertionError("the compiled first stage is written for 6 head columns, "
                                 "3 groups and 4 variants")  # fmt: skip
        self.variants = np.ascontiguousarray(variants, dtype=np.float64)
        self.head = np.ascontiguousarray(self.variants[:, cols])
        self.norms = np.stack(
            [np.linalg.norm(self.variants[:, groups == g], axis=1) for g in range(TAIL_GROUPS)],
            axis=1,
        )
        self.squares = np.sum(self.variants**2, axis=1)
        self.kcol = kcol


def bounded_topk(desc, tables, stage: _FirstStage, best: np.ndarray):
    """:func:`chunk_topk` of one chunk in two stages (the chunk's rows among the best k).

    Each row's score with a variant is ``q·d = q_h·d_h + Σ_g q_g·d_g ≤ q_h·d_h +
    Σ_g |q_g| |d_g|`` (Cauchy–Schwarz over each group of the other columns): the
    bound is computed from the compact ``tables`` (:meth:`Atlas._tables`: the head
    rounded to ``1/hs``, hence an allowance, and the groups' norms rounded up) alone,
    for the rows in the windows of the key column that can hold a row near enough
    (:func:`~machdyn.synthesis._atlas_kernels.key_ranges`), and only the rows whose
    bound beats the k-th best so far (the root of the heap ``best``, less
    :data:`BOUND_SLACK`) are scored exactly (float64), in one compiled pass
    (:func:`~machdyn.synthesis._atlas_kernels.bound_topk`) that updates ``best``.
    Returns the rows and (float64) scores of those scored within
    :data:`SCORE_SLACK` of the floor after the chunk (its best ``k`` and any that
    may tie them), and how many rows were scored exactly.
    """
    from ._atlas_kernels import bound_topk

    desc = np.asarray(desc)  # (a memory map: the array it maps)
    found, scores, scored = [], [], 0
    for head, tail, rows, hs, ts, longest2 in tables:
        out, score = np.empty(rows.size, np.int64), np.empty(rows.size, np.float64)
        n, m = bound_topk(head, tail, rows, stage.kcol, desc, stage.head, stage.norms,
                       stage.squares, hs, ts, longest2, stage.variants, BOUND_SLACK,
                       SCORE_SLACK, best, out, score)  # fmt: skip
        found.append(out[:n])
        scores.append(score[:n])
        scored += m
    rows, score = np.concatenate(found), np.concatenate(scores)
    keep = score >= best[0] - SCORE_SLACK  # (best[0]: the k-th best of the thread so far)
    return rows[keep], score[keep], scored


def _raise_floor(best: np.ndarray, scores: np.ndarray) -> None:
    """Put ``scores`` into the heap ``best`` (in place): its ``k`` highest values, ascending.

    Every value a float64 score of a row of its own (no row twice), as the compiled
    stage puts in: the root is then at most the exact k-th best score, give or take
    the rounding that :data:`SCORE_SLACK` covers (an ascending array is a min-heap,
    as :func:`~machdyn.synthesis._atlas_kernels.bound_topk` reads it).
    """
    k = best.size
    merged = np.concatenate([best, np.asarray(scores, dtype=np.float64)])
    best[:] = np.sort(np.partition(merged, merged.size - k)[merged.size - k :])


def chunk_topk_file(path: str, index: int, variants: np.ndarray, k: int, crank: bool):
    """:func:`chunk_topk` on a chunk read from the atlas folder (a Dask task)."""
    folder = Path(path)
    desc = np.load(folder / f"{chunk_name(index)}.desc.npy", mmap_mode="r")
    meta = np.load(folder / f"{chunk_name(index)}.meta.npy", mmap_mode="r")
    return chunk_topk(desc, np.asarray(meta["barker"]) <= 2 if crank else None, variants, k)


def open_atlas(path: Any, *, verify: bool = True) -> Atlas:
    """Open an atlas folder built by :func:`~machdyn.synthesis.build_atlas`.

    Parameters
    ----------
    path : path-like
    verify : bool
        Check every chunk's CRC-32 (reads the whole atlas once).

    Raises
    ------
    AtlasError
        No manifest, another format version, an unfinished build, a missing,
        truncated or corrupted chunk: never a wrong answer from a stale atlas.
    """
    folder = folder_path("path", path)
    verify = boolean("verify", verify)
    manifest = read_manifest(folder)
    if not manifest.complete:
        raise AtlasError(
            folder,
            f"unfinished build ({len(manifest.chunks)} of {manifest.n_chunks} chunks); "
            "run the same 'machdyn atlas build' again to finish it",
        )
    if verify:
        _verify_chunks(folder, manifest)
    desc, meta = [], []
    width = 4 * manifest.harmonics
    for i in range(manifest.n_chunks):
        info = manifest.chunks[f"{i:05d}"]
        try:
            d = np.load(folder / f"{chunk_name(i)}.desc.npy", mmap_mode="r")
            m = np.load(folder / f"{chunk_name(i)}.meta.npy", mmap_mode="r")
        except Exception as exc:  # (np.load of a damaged header raises many kinds)
            # (an empty file: EOFError, which click would turn into "aborted"; a flipped
            # byte in the header: tokenize's TokenError or a SyntaxError; with verify=False)
            raise AtlasError(
                folder, f"chunk {i} cannot be read ({type(exc).__name__}: {exc}); rebuild the atlas"
            ) from None
        want = SIXBAR_DTYPE if manifest.kind == "sixbar" else META_DTYPE
        if (
            d.shape != (info["rows"], width)
            or d.dtype != np.float32
            or m.shape != (info["rows"],)
            or m.dtype != want
        ):
            raise AtlasError(folder, f"chunk {i} does not have the shape its manifest says")
        desc.append(d)
        meta.append(np.asarray(m))
    return Atlas(folder, manifest, desc, meta)


def _verify_chunks(folder: Path, manifest: Manifest) -> None:
    """Raise AtlasError for the first chunk (in order) whose files fail their sizes or CRCs.

    The chunks are checked on the threads of :mod:`machdyn._parallel`: zlib's CRC
    releases the GIL over a buffer, so the atlas is read by every core at once (the
    10^7 atlas's 1.5 GB in about half the wall time of one thread).
    """
    from .._parallel import for_slices

    whys = [""] * manifest.n_chunks

    def run(sl: slice) -> None:
        for i in range(sl.start, sl.stop):
            whys[i] = chunk_is_good(folder, i, manifest.chunks[f"{i:05d}"])
            if whys[i]:
                return

    for_slices(run, manifest.n_chunks, minimum=2)
    why = next((w for w in whys if w), "")
    if why:
        raise AtlasError(folder, f"{why}; rebuild the atlas")
