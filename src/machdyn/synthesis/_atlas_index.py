"""An opened atlas and its query: the ``k`` entries nearest a descriptor, chunk by chunk.

:func:`open_atlas` checks an atlas folder (its manifest, version and every
chunk's CRC-32) and memory-maps its chunks; :class:`Atlas` answers the nearest
entries to a descriptor in any of its four variants by one float32 matrix
product per block of rows (BLAS) and a partial sort, on threads or as Dask
tasks (:func:`chunk_topk_file`), and spreads pools of entries over the atlas
for open targets. Used by :mod:`~machdyn.synthesis.atlas_path`.
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
        self._heads: tuple | None = None  # the query's first stage (see _query_heads)
        self._queries = 0

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
        Returns flat indices and squared distances (best first).
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
        idx = np.concatenate([top + self.offsets[c] for c, (top, _) in parts])
        score = np.concatenate([s for _, (_, s) in parts])
        order = np.lexsort((idx, -score))[:k]  # best first; equal scores by index
        keep = np.isfinite(score[order])
        return idx[order][keep], (2.0 - 2.0 * score[order][keep]).astype(float)

    def _local_topk(self, variants: np.ndarray, k: int, crank: bool,
                    deadline: _Deadline = _NEVER) -> list:  # fmt: skip
        """:func:`chunk_topk` of every chunk, on the threads of :mod:`machdyn._parallel`.

        Each thread scores a run of chunks (BLAS products, comparisons and the
        partial sort release the GIL), keeping only what beats its own k-th best
        so far; the union holds the exact top k. Once a thread has a k-th best,
        its later chunks are scored in two stages (:func:`bounded_topk`): an
        upper bound of every score from :data:`HEAD` columns, then the exact
        score of the rows whose bound beats the k-th best. Returns ``(chunk, (rows,
        scores))`` for the chunks scored: past the ``deadline``, each thread stops
        after its current chunk.
        """
        from .. import jit
        from .._parallel import for_slices

        parts: list = [None] * len(self.desc)
        starts = self.offsets[:-1]
        # two stages from an atlas's second query on (the first stage is compiled; the
        # first query, often the only one of a process, scores every row)
        two = jit.active() and self._queries > 0
        self._queries += 1
        if two:
            cols = self._query_heads()[0]
            rest = np.setdiff1d(np.arange(variants.shape[1]), cols)
            qh = np.ascontiguousarray(variants[:, cols], dtype=np.float32)
            qt = np.sqrt(np.sum(variants[:, rest].astype(np.float64) ** 2, axis=1))
            qt = np.nextafter(qt.astype(np.float32), np.float32(np.inf))

        def run(sl: slice) -> None:
            floor, best = -np.inf, np.empty(0, np.float32)
            for c in np.flatnonzero((starts >= sl.start) & (starts < sl.stop)):
                ok = self._crank[c] if crank else None
                if two:
                    table = self._head_of(c, crank)
                if two and np.isfinite(floor):
                    parts[c] = bounded_topk(self.desc[c], table, ok, variants, qh, qt, k, floor)
                else:
                    parts[c] = chunk_topk(self.desc[c], ok, variants, k, floor)
                best = np.concatenate([best, parts[c][1]])
                if best.size >= k:  # the k-th best so far: later chunks must beat it
                    best = np.partition(best, best.size - k)[best.size - k :]
                    floor = float(best[0])
                if deadline.passed():
                    break

        for_slices(run, len(self))
        return [(c, p) for c, p in enumerate(parts) if p is not None]

    def _query_heads(self) -> tuple:
        """The query's first stage: its columns, and each chunk's tables built so far.

        The :data:`HEAD` descriptor columns of most energy (in the first chunk),
        copied for the rows of every chunk (``HEAD × 4`` bytes a row), with the norm
        of each row's other columns (float32): 200 MB for 10^7 entries, or 100 MB for
        their crank rows alone (queries with ``crank``: timed targets always), each
        built by the first such query that scores the chunk (:meth:`_head_of`).
        """
        if self._heads is None:
            first = np.asarray(self.desc[0], dtype=np.float64)
            cols = np.sort(np.argsort(-np.mean(first**2, axis=0), kind="stable")[:HEAD])
            self._heads = (cols, {})
        return self._heads

    def _head_of(self, c: int, crank: bool) -> tuple:
        """Chunk ``c``'s first-stage table: head, tail and its rows (None: all), compiled."""
        from ._atlas_kernels import head_rows

        cols, tables = self._query_heads()
        if (c, crank) not in tables:
            rows = np.flatnonzero(self._crank[c]) if crank else None
            desc = self.desc[c] if rows is None else np.asarray(self.desc[c])[rows]
            n = desc.shape[0]
            head, tail = np.empty((n, cols.size), np.float32), np.empty(n, np.float32)
            head_rows(desc, cols.astype(np.int64), head, tail)
            tables[c, crank] = (head, tail, rows)
        return tables[c, crank]

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

    Only scores above ``floor`` (the k-th best of the chunks seen so far) are
    kept. The product runs in blocks of :data:`BLAS_ROWS` rows: below that size
    OpenBLAS computes on the calling thread, above it wakes its thread pool,
    which on a busy 2-core machine costs ~20 ms per call (measured: 65,536 rows
    in one call 29 ms, in blocks of 2,048 0.7 ms). Scale-out is the chunks' job.
    """
    n = desc.shape[0]
    prod = np.empty((n, variants.shape[0]), dtype=np.float32)
    right = variants.T
    for lo in range(0, n, BLAS_ROWS):
        np.matmul(desc[lo : lo + BLAS_ROWS], right, out=prod[lo : lo + BLAS_ROWS])
    score = prod[:, 0]
    for j in range(1, prod.shape[1]):  # max over the variants (faster than .max(axis=1))
        score = np.maximum(score, prod[:, j])
    keep = score > floor
    if allowed is not None:
        keep &= allowed
    rows = np.flatnonzero(keep)
    if rows.size > k:
        rows = rows[np.argpartition(-score[rows], k - 1)[:k]]
    return rows, score[rows]


#: Descriptor columns of the query's first stage (see Atlas._local_topk; its compiled
#: kernel is written for 4), and the slack of its bound over a float32 score (the
#: rounding of a 32-term float32 product is below 1e-5).
HEAD = 4
BOUND_SLACK = 1e-4


def bounded_topk(desc, table, allowed, variants, qh, qt, k: int, floor: float):
    """:func:`chunk_topk` in two stages, for a ``floor`` already known (the same rows).

    Each row's score with a variant is ``q·d = q_h·d_h + q_t·d_t ≤ q_h·d_h + |q_t| |d_t|``
    (Cauchy–Schwarz over the other columns): the bound is computed from the ``table``
    (see :meth:`Atlas._query_heads`: head columns, tail norms, and its rows: all of
    them, or the ``allowed`` ones only) alone (compiled:
    :func:`~machdyn.synthesis._atlas_kernels.bound_rows`), and only the rows whose
    bound beats ``floor`` (less :data:`BOUND_SLACK`) are scored exactly. A loose
    bound (a quarter of the chunk passing) scores the whole chunk instead.
    """
    from ._atlas_kernels import bound_rows

    head, tail, index = table
    if head.shape[1] != 4 or qh.shape != (4, 4):
        raise ValueError("the first stage's kernel is written for 4 columns and 4 variants")
    n = desc.shape[0]
    rows = np.empty(head.shape[0], np.int64)
    check = allowed is not None and index is None
    ok = allowed if check else np.ones(0, bool)
    count = bound_rows(head, tail, ok, check, qh, qt, floor - BOUND_SLACK, rows)
    rows = rows[:count] if index is None else index[rows[:count]]
    if rows.size > n // 4:
        return chunk_topk(desc, allowed, variants, k, floor)
    if rows.size == 0:
        return rows, np.empty(0, np.float32)
    prod = np.asarray(desc[rows]) @ variants.T
    score = prod[:, 0]
    for j in range(1, prod.shape[1]):
        score = np.maximum(score, prod[:, j])
    keep = score > floor
    rows, score = rows[keep], score[keep]
    if rows.size > k:
        top = np.argpartition(-score, k - 1)[:k]
        rows, score = rows[top], score[top]
    return rows, score


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
    desc, meta = [], []
    width = 4 * manifest.harmonics
    for i in range(manifest.n_chunks):
        info = manifest.chunks[f"{i:05d}"]
        why = chunk_is_good(folder, i, info) if verify else ""
        if why:
            raise AtlasError(folder, f"{why}; rebuild the atlas")
        try:
            d = np.load(folder / f"{chunk_name(i)}.desc.npy", mmap_mode="r")
            m = np.load(folder / f"{chunk_name(i)}.meta.npy", mmap_mode="r")
        except (OSError, ValueError) as exc:
            raise AtlasError(
                folder, f"chunk {i} cannot be read ({exc}); rebuild the atlas"
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
