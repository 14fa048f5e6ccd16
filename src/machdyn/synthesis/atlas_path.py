"""Path synthesis from an atlas: retrieve similar coupler curves, refine them, check them.

1. **Retrieve.** A closed target is interpolated (a periodic spline through
   the points), resampled by arc length and reduced to its descriptor
   (:mod:`~machdyn.synthesis.descriptor`); the ``k`` nearest atlas entries in
   any of its four variants are found by one float32 matrix product per chunk
   (BLAS) and a partial sort. An open (or partial) target is instead matched
   arc by arc (:func:`~machdyn.synthesis.descriptor.align_partial`) against an
   evenly spread pool of atlas entries, since the descriptor of a whole curve
   says nothing about where a part of it lies.
2. **Place.** Each retrieved curve is rebuilt from its parameters and fitted
   onto the target by a rotation, scale and translation (closed form, all
   starting points at once by FFT): the atlas's unit-crank linkage becomes a
   linkage placed in the target's plane.
3. **Refine.** :func:`~machdyn.synthesis.refine.refine` minimises the real
   distances of the targets to the coupler curve (or to the timed points).
4. **Check.** Each result is checked by the four-bar's own code
   (:class:`~machdyn.synthesis.PlacedFourBar`): one circuit (by
   construction), branch (no toggle between targets), order, Grashof/crank
   requirement and minimum transmission angle; the survivors are ranked by
   their worst distance and thinned to distinct linkages.
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._parallel import one_blas_thread
from .._validate import boolean, finite_array, finite_scalar, integer, nonnegative, positive
from ..classify import classify
from ..errors import InputError
from ..fourbar import FourBar
from .atlas_store import (
    META_DTYPE,
    AtlasError,
    Manifest,
    chunk_is_good,
    chunk_name,
    even_curves,
    folder_path,
    read_manifest,
)
from .circuits import circuit_angles, circuit_points, circuit_range
from .descriptor import (
    align_closed,
    align_partial,
    curve_descriptor,
    descriptor_variants,
    interpolate_closed,
    interpolate_open,
    resample_closed,
)
from .geometry import as_points
from .path import PathSynthesis, _mu_min
from .placed import PlacedFourBar
from .refine import refine
from .sixbar import SIXBAR_DTYPE
from .valley import polish

# Internal to machdyn.synthesis, which re-exports the public names (Atlas, build_atlas,
# open_atlas, path_from_atlas, curve_descriptor, ...); the fuzz suite fuzzes those.
__all__: list[str] = []

#: Atlas entries retrieved per query, and how many of the best-placed are refined.
RETRIEVE = 160
REFINE = 10
#: Rows per BLAS call in a query (below OpenBLAS's threading threshold; see chunk_topk).
BLAS_ROWS = 2048
#: How many of the refined candidates are refined on to convergence.
POLISH = 3
#: Steps of every start's refinement, the share of them that goes on, and its steps in all.
SCREEN_NFEV = 12
SCREEN_KEEP = 0.25
REFINE_NFEV = 40
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
#: is polished longer instead; see sixbar_path.SIXBAR_ROUNDS).
SIXBAR_NEAR = 1e-8
#: Untimed targets: most fits polished while none meets the targets to this share of
#: their size (see _polished).
UNTIMED_POLISH_MAX = 4
UNTIMED_MET = 1e-9
#: Untimed targets: fits just past Grashof's change point re-refined before they land on it,
#: per linkage asked for (the rest, worse ranked, are landed as they are).
UNTIMED_BOUNDARY = 2
#: Untimed: refinement steps of each polished fit before its valley polish, in the first
#: round and in later ones (100 in the first lost the literature's case 5 its best SSE).
UNTIMED_NFEV = (400, 100)
#: Untimed targets: most rounds of retrieval (each a fresh pool) while none is met, and
#: only while the best fit's largest miss lies between UNTIMED_ENOUGH and UNTIMED_FAR of
#: the size (see _worth_a_round).
UNTIMED_ROUNDS = 3
UNTIMED_ENOUGH = 3e-7
UNTIMED_FAR = 1e-3
#: Untimed targets none of whose fits meets them: the best few distinct fits polished
#: on, most steps, and the stall window (see _long_polished; compiled kernels only).
UNTIMED_LONG = (3, 5000, 1000)
#: Size of the pool an open target is matched against (entries spread over the atlas).
OPEN_POOL = 4_000
#: Open targets: best arc fits re-scored on the target points, samples of each curve
#: for that, and rounds of the re-fit (see _fit_to_points); the arc fit takes every
#: ARC_STRIDE-th of a curve's samples.
RESCORE = 200
ARC_STRIDE = 2
DENSE = 720
ICP_ROUNDS = 3
#: A best result farther than this (over the target's size) means no entry came near.
NEAR = 0.05
#: Random four-bars beyond the atlas's proportions (link lengths from 1/50 to 50 crank
#: lengths) whose best-placed also start refinements: the literature's best linkages
#: often lie there (a 50-long ground and rocker on a 1.35 crank, at a length bound).
WIDE_POOL = 8_000
WIDE_RANGE = (0.02, 50.0)
WIDE_TIMED = 1_500  # of them, for timed targets whose starting angle is scanned too
#: Minimum number of target points: a closed or open path, with prescribed timing.
MIN_POINTS = {"closed": 5, "open": 5, "timed": 4}


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


@dataclass(frozen=True, eq=False)
class PathCandidates:
    """Linkages for a path, best first, from :func:`path_from_atlas`.

    Attributes
    ----------
    candidates : tuple of PathSynthesis or of SixBarPath
        Defect-free, distinct linkages, best (smallest worst distance) first
        (four-bars from a four-bar atlas, six-bars from a six-bar atlas).
    rejected : tuple of PathSynthesis
        Refined linkages that failed a check (with their ``defects``).
    targets : ndarray of complex
    near : bool
        False when even the best result misses a target by more than
        :data:`NEAR` of the target's size (no atlas entry came near).
    note : str
        What to know about the result (empty if nothing).
    seconds : dict
        Time spent retrieving and refining.
    """

    candidates: tuple[PathSynthesis, ...]
    rejected: tuple[PathSynthesis, ...]
    targets: np.ndarray
    near: bool
    note: str
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def best(self) -> PathSynthesis:
        """The best candidate (or the best rejected one if none passed)."""
        pool = self.candidates or self.rejected
        if not pool:
            raise InputError("targets", "no linkage was found for these targets")
        return pool[0]


def _targets(targets: Any, timing: Any, closed: bool) -> tuple[np.ndarray, np.ndarray | None]:
    try:
        pts = as_points("targets", targets)
    except (OverflowError, TypeError) as exc:
        raise InputError("targets", f"must be points (x, y) or x + jy, got {exc}") from None
    kind = "timed" if timing is not None else ("closed" if closed else "open")
    need = MIN_POINTS[kind]
    if pts.size < need:
        raise InputError(
            "targets",
            f"{pts.size} points are too few for a {kind} path: at least {need} are needed "
            "(a four-bar's coupler curve has 9 free parameters; fewer points fit countless "
            "linkages: use motion generation, synthesis.three_position, for 2 or 3 positions)",
        )
    centre = pts.mean()
    size = float(np.max(np.abs(pts - centre)))
    if size == 0.0:
        raise InputError("targets", "all target points coincide")
    if closed and timing is None and pts.size > need and abs(pts[-1] - pts[0]) <= 1e-9 * size:
        pts = pts[:-1]  # a closed path written back to its start: the first point ends it
    step = np.abs(np.diff(np.concatenate([pts, pts[:1]]) if closed else pts))
    same = np.flatnonzero(step <= 1e-9 * size)
    if same.size:
        i = int(same[0])
        raise InputError(
            "targets",
            f"points {i + 1} and {(i + 1) % pts.size + 1} coincide; give each point once",
        )
    if timing is not None:
        timing = np.ravel(finite_array("timing", timing, "radian"))
        if timing.size != pts.size:
            raise InputError(
                "timing", f"needs one angle per target ({pts.size}), got {timing.size}"
            )
    return pts, timing


@one_blas_thread
def path_from_atlas(
    targets: Any,
    atlas: Atlas | Any,
    *,
    closed: bool = True,
    timing: Any = None,
    n: int = 5,
    crank: bool = True,
    mu_min: float = np.radians(30.0),
    tolerance: float | None = None,
    retrieve: int = RETRIEVE,
    refine_count: int = REFINE,
    client: Any = None,
    O2: Any = None,
    theta1: float | None = None,
    absolute_timing: bool = False,
    max_length: float | None = None,
    pivot_box: Any = None,
    time_limit: float | None = None,
) -> PathCandidates:
    """Four-bars whose coupler curve passes through target points, from an atlas.

    Parameters
    ----------
    targets : sequence of complex or (x, y)
        Points along the wanted path, in order.
    atlas : Atlas or path-like
        An opened atlas (:func:`open_atlas`) or its folder.
    closed : bool
        True: the points go round a closed path. False: an open path (or a
        part of a closed one), matched against arcs of the coupler curves.
    timing : sequence of float, optional
        Input-angle increments (radians) at which the targets must be reached
        (prescribed timing); link 2 must then be a crank.
    n : int
        How many distinct linkages to return.
    crank : bool
        Require link 2 to turn fully (a motor drives it round).
    mu_min : float
        Smallest acceptable transmission angle, radians.
    tolerance : float, optional
        A target farther than this from the curve is a defect.
    retrieve, refine_count : int
        Entries taken from the atlas, and how many of the best-placed are refined
        (four times as many when ``O2``, ``theta1`` or the timing is held).
    client : distributed.Client, optional
        Score the atlas's chunks as tasks on this Dask cluster.
    O2, theta1 : complex or (x, y), float, optional
        Hold the crank's pivot ``O2`` and the ground line's direction ``θ1``
        (radians) at these values (four-bar atlases).
    absolute_timing : bool
        With ``timing``: the angles are link 2's angle from the ground line
        (θ2), not increments from the first target.
    max_length : float, optional
        No link (``r1 … r4``, and the coupler point's distance ``p`` from A)
        longer than this.
    pivot_box : (xmin, ymin, xmax, ymax), optional
        Keep the crank's pivot ``O2`` inside this rectangle.
    time_limit : float, optional
        Wall-clock seconds for the whole call. The synthesis then stops at the
        first stage boundary past the limit and returns the best linkages found
        so far, with a ``note`` that says so. The boundaries: between chunks of
        the atlas query (a closed target's nearest entries are then those of the
        chunks scored, a random share of the atlas), between slices of 1,000
        entries of an open target's pool, before the starts from random
        four-bars of wide proportions, between screened starts, polished fits
        and pool rounds. It returns within about the limit plus one stage (a
        few tens of milliseconds; an open target's first slice and its arc fits
        ~0.2 s; a six-bar round longer; in a fresh process, the first call also
        loads the compiled kernels). At least one retrieved start is refined, so
        even a limit of 0 returns the retrieval's best placed and checked. None
        (the default): no limit, the same steps and result on every run.

    Returns
    -------
    PathCandidates

    Raises
    ------
    InputError
        Too few points, NaN, coincident points, a timing list of the wrong length,
        a negative ``time_limit``.
    AtlasError
        The atlas is missing, from another version, unfinished or corrupted.

    Examples
    --------
    A tiny atlas (a thousand four-bars; ``machdyn atlas build`` makes 10^7), and
    twelve targets a known four-bar's coupler point passes through at crank steps
    of 30°, the timing prescribed:

    >>> import tempfile
    >>> from machdyn.fourbar import FourBar
    >>> from machdyn.synthesis import PlacedFourBar, build_atlas
    >>> folder = tempfile.mkdtemp()
    >>> _ = build_atlas(folder, 1000, chunk_size=500, progress=False)
    >>> known = PlacedFourBar(FourBar(3.0, 1.0, 3.5, 2.5, coupler=(1.8, 0.6)), 0.5 + 0.2j, 0.3, 1)
    >>> theta = np.radians(np.arange(0, 360, 30))
    >>> targets = known.pose(theta)[2]
    >>> found = path_from_atlas(targets, folder, timing=theta, n=1)
    >>> best = found.candidates[0]
    >>> bool(found.near), bool(np.max(best.distance) < 1e-9)
    (True, True)

    The linkage found (placed in the plane) passes through the targets at its
    crank angles ``best.theta2``, each ``theta`` apart:

    >>> bool(np.allclose(best.linkage.pose(best.theta2)[2], targets, atol=1e-9))
    True
    >>> bool(np.allclose(np.diff(best.theta2), np.diff(theta)))
    True
    """
    start = time.perf_counter()
    if time_limit is not None:
        time_limit = nonnegative("time_limit", time_limit, "second")
    deadline = _NEVER if time_limit is None else _Deadline(start + time_limit)
    if not isinstance(atlas, Atlas):
        atlas = open_atlas(atlas)
    closed = boolean("closed", closed)
    pts, timing = _targets(targets, timing, closed)
    n = integer("n", n, minimum=1, maximum=1000)
    mu_min = finite_scalar("mu_min", mu_min, "radian")
    if not 0.0 <= mu_min < np.pi / 2:
        raise InputError("mu_min", f"must be between 0 and 90 deg, got {np.degrees(mu_min):g} deg")
    if tolerance is not None:
        tolerance = positive("tolerance", tolerance)
    retrieve = integer("retrieve", retrieve, minimum=1, maximum=100_000)
    refine_count = integer("refine_count", refine_count, minimum=1, maximum=10_000)
    if client is not None and not callable(getattr(client, "submit", None)):
        raise InputError("client", "must be a distributed.Client (or None)")
    crank = boolean("crank", crank) or timing is not None
    size = float(np.max(np.abs(pts - pts.mean())))
    fixed, max_length, pivot_box = _constraints(O2, theta1, absolute_timing, max_length,
                                                pivot_box, timing, atlas)  # fmt: skip
    if timing is not None and not absolute_timing:
        timing = timing - timing[0]  # increments from the first target
    t0 = time.perf_counter()
    if atlas.manifest.kind == "sixbar":
        return _sixbar_path(atlas, pts, timing, closed, n, tolerance, mu_min, retrieve,
                            refine_count, client, start, deadline)  # fmt: skip
    if {6, 8, 9} & fixed.keys():  # held placement or timing: fewer good starts, refine more
        refine_count *= 4
    options = dict(timing=timing, crank=crank, mu_min=mu_min, fixed=fixed, max_length=max_length,
                   pivot_box=pivot_box)  # fmt: skip
    if timing is None:
        fits, t1 = _untimed_fits(atlas, pts, closed, crank, retrieve, refine_count, client,
                                 options, deadline)  # fmt: skip
    else:
        starts = _retrieve_timed(atlas, pts, timing, closed, retrieve, refine_count, client, fixed,
                                 deadline)  # fmt: skip
        t1 = time.perf_counter()
        # the few best go on until they converge (the rest rarely overtake them)
        fits, met = _polished(_screened(starts, pts, options, deadline), pts, options, POLISH,
                              deadline=deadline, tries=TIMED_TRIES)  # fmt: skip
        # an open arc met by no start but nearly met by one: fresh pools of the atlas (a
        # closed timed target's nearest entries by shape are already in; an arc's are not)
        for r in range(1, TIMED_ROUNDS if not closed else 1):
            if met or deadline.passed() or not fits or fits[0].rms > TIMED_NEAR_MISS * size:
                break
            rows = atlas.entries(atlas.pool(TIMED_POOL, crank=True, draw=r))
            more = _screened(_timed_starts(rows, pts, timing, refine_count, fixed), pts, options,
                             deadline)  # fmt: skip
            more, met = _polished(more, pts, options, POLISH, deadline=deadline, tries=TIMED_TRIES)
            fits = sorted(fits + more, key=lambda f: f.rms)
    results = []
    for i, fit in enumerate(_unique(fits, size)):
        # untimed: only the fits that can be among the n chosen are refined at the change
        # point; the others (a path no four-bar meets leaves dozens there) only land on it
        onto = options if timing is not None or i < UNTIMED_BOUNDARY * n else None
        onto = None if deadline.passed() else onto  # past the time limit: only land on it
        if crank and 0.0 < _grashof_excess(fit.x) <= 1e-4 * np.sum(fit.x[:4]):
            # just past the change point: hold the crank harder, then land on it
            if onto is not None:
                more = refine(fit.x, fit.theta, fit.branch, pts, max_nfev=200, weight=1e4,
                              **options)  # fmt: skip
                fit = more if more.rms <= 2 * fit.rms else fit
            fit = _onto_grashof(fit, pts, onto)
        res = _checked(fit, pts, timing, closed, crank, mu_min, tolerance)
        if res is not None:
            results.append(res)
    t2 = time.perf_counter()
    results.sort(key=_rank)
    good = [r for r in results if r.ok]
    chosen = _distinct(good, n, size)
    rejected = tuple(r for r in results if not r.ok)[: max(n, 5)]
    best = chosen[0] if chosen else (rejected[0] if rejected else None)
    worst = float(np.max(best.distance)) / size if best is not None else np.inf
    near = worst <= NEAR
    note = _far_note(best, size, "linkage", " (is the path one a four-bar can trace?)")
    if best is not None and near and not chosen:
        note = "every linkage found has a defect (see rejected)"
    seconds = {"retrieve": t1 - t0, "refine": t2 - t1, "total": time.perf_counter() - start}
    note = _limit_note(note, deadline, time_limit, seconds["total"])
    return PathCandidates(tuple(chosen), rejected, pts, near, note, seconds)


def _rank(result: PathSynthesis) -> tuple[int, float]:
    """Sort key of a checked result: targets it cannot be assembled at, then its worst miss."""
    distance = np.asarray(result.distance, float)
    finite = np.isfinite(distance)
    return int(np.count_nonzero(~finite)), float(np.max(distance, where=finite, initial=0.0))


def _far_note(best: PathSynthesis | None, size: float, linkage: str, hint: str = "") -> str:
    """Why no result comes near the targets ("" when the best does, within :data:`NEAR`)."""
    if best is None:
        return "no atlas entry could be placed on these targets"
    distance = np.asarray(best.distance, float)
    lost = int(np.count_nonzero(~np.isfinite(distance)))
    if lost:  # (a distance of inf: the linkage cannot be assembled there)
        return (f"no atlas entry comes near these targets: the best {linkage} found cannot be "
                f"assembled at {lost} of the {distance.size} targets{hint}")  # fmt: skip
    worst = float(np.max(distance)) / size
    if worst <= NEAR:
        return ""
    return (f"no atlas entry comes near these targets: the best {linkage} found misses by "
            f"{100 * worst:.1f} % of the targets' size{hint}")  # fmt: skip


def _limit_note(note: str, deadline: _Deadline, time_limit: float | None, total: float) -> str:
    """``note`` with, when the synthesis stopped at its time limit, a sentence saying so."""
    if not deadline.hit:
        return note
    stop = (f"stopped at the time limit ({time_limit:g} s) after {total:.2f} s: the best "
            "linkages found by then (without the limit the search goes on)")  # fmt: skip
    return f"{stop}; {note}" if note else stop


def _screened(starts, pts, options, deadline: _Deadline = _NEVER) -> list:
    """Refinements of ``starts``, best first: a few steps each, then more for the best.

    Every start takes :data:`SCREEN_NFEV` steps; the best :data:`SCREEN_KEEP` share (at
    least :data:`REFINE`) goes on to :data:`REFINE_NFEV` steps in all. A start that is
    far behind after a few steps rarely overtakes the leaders (and the few best are
    polished to convergence afterwards); this halves the refinement time of a query
    with many starts (prescribed timing or placement: four times :data:`REFINE`).
    Past the ``deadline``, the starts not yet screened are dropped (the first one is
    always screened) and none takes more steps.
    """
    solver = "lm" if options.get("timing") is not None else "trf"
    fits = []
    for first in starts:
        if first is None:
            continue
        if fits and deadline.passed():
            break
        fits.append(refine(*first, pts, max_nfev=SCREEN_NFEV, solver=solver, **options))
    fits.sort(key=lambda f: f.rms)
    keep = max(REFINE, int(np.ceil(SCREEN_KEEP * len(fits))))
    for i in range(min(keep, len(fits))):
        if deadline.passed():
            break
        f = fits[i]
        more = refine(f.x, f.theta, f.branch, pts, max_nfev=REFINE_NFEV - SCREEN_NFEV,
                      solver=solver, **options)  # fmt: skip
        fits[i] = more if more.rms <= f.rms else f
    fits.sort(key=lambda f: f.rms)
    return fits


def _untimed_fits(atlas, pts, closed, crank, retrieve, refine_count, client, options,
                  deadline: _Deadline = _NEVER):  # fmt: skip
    """Refined fits for untimed targets, best first, and the time retrieval ended.

    Round 0: the entries nearest the target (:func:`_retrieve`) and the wide
    rows (:func:`_retrieve_wide`). While no fit meets the targets to
    :data:`UNTIMED_MET` of their size, up to :data:`UNTIMED_ROUNDS` − 1 more
    rounds take a fresh pool of the atlas (:meth:`Atlas.pool`, ``round``) and
    match the targets as an arc (a closed target opened at its widest gap: a
    spline through unevenly spread points of a closed path can be far from the
    curve between them, so its descriptor misleads the retrieval). Past the
    ``deadline`` (:class:`_Deadline`), no more screening, polishing or rounds.
    """
    fixed = options["fixed"]
    count = max(1, refine_count // 4) if {6, 8} & fixed.keys() else refine_count
    entries, transforms = _retrieve(atlas, pts, closed, crank, retrieve, refine_count, client,
                                    deadline)  # fmt: skip
    if not deadline.passed():  # (past the deadline: the atlas's entries alone)
        wide, placed = _retrieve_wide(atlas, pts, closed, crank, count)
        entries, transforms = np.concatenate([entries, wide]), np.concatenate([transforms, placed])
    t1 = time.perf_counter()
    fits, met = _polished(_screened(_untimed_starts(entries, transforms, pts), pts,
                                            options, deadline), pts, options, UNTIMED_POLISH_MAX,
                          UNTIMED_NFEV[0], deadline)  # fmt: skip
    longer: list[np.ndarray] = []  # the keys of the fits polished longer
    fits, met = _long_polished(fits, pts, options, met, longer, deadline)
    man = atlas.manifest
    arc = pts
    if closed:  # the targets as an arc: from the far side of the widest gap round to its near side
        gap = int(np.argmax(np.abs(np.roll(pts, -1) - pts)))
        arc = np.roll(pts, -(gap + 1))
    for r in range(1, UNTIMED_ROUNDS):
        if met or deadline.passed() or not _worth_a_round(fits, pts, closed):
            break
        rows = atlas.entries(atlas.pool(OPEN_POOL, crank=crank, draw=r))
        curves = even_curves(rows, man.circuit_samples, man.samples)
        entries, transforms = _arc_starts(rows, curves, arc, refine_count)
        more, met = _polished(_screened(_untimed_starts(entries, transforms, pts), pts,
                                                options, deadline), pts, options, POLISH,
                              UNTIMED_NFEV[1], deadline)  # fmt: skip
        fits = sorted(fits + more, key=lambda f: f.rms)
        fits, met = _long_polished(fits, pts, options, met, longer, deadline)
    return fits, t1


def _long_polished(fits, pts, options, met, longer, deadline: _Deadline = _NEVER):
    """``fits`` with the best few not yet met polished longer (:data:`UNTIMED_LONG`).

    A near miss of a sloppy arc often still crawls down its valley when the polish's
    stall rule stops it (``bench_atlas.py --recovery 20 --seed 5``, open case 14: a
    fit at 1.1e-6 of the size reaches 1e-11 in ~3,000 more steps). Only with the
    compiled kernels (:mod:`~machdyn.synthesis._valley_kernels`: a long polish costs
    milliseconds there, a second in NumPy); only fits whose keys are not in
    ``longer`` (appended to), and not once one meets or past the ``deadline``. A
    longer-polished fit replaces its start only if its largest miss is within
    :data:`UNTIMED_ENOUGH` of the size: a fit that is not met by then crawls toward
    a worse answer as often as not (``--seed 11`` open case 13: to a parallelogram
    at Grashof's change point, 1.3e-6 at its own angles, 1e-4 of the size off its
    curve once landed on the change point, where the fit it started from was 2.3e-6).
    Returns the fits (best first) and whether one met.
    """
    from .refine import _compiled

    if met or not fits or not _compiled(None):
        return fits, met
    size = float(np.max(np.abs(pts - pts.mean())))
    count, iterations, stall = UNTIMED_LONG
    fits = list(fits)
    for i, f in enumerate(fits[: 4 * count]):
        if count == 0 or deadline.passed():
            break
        key = _design_key(f, size)
        if any(np.max(np.abs(key - k)) <= SAME for k in longer):
            continue
        longer.append(key)
        count -= 1
        g = polish(f, pts, **options, iterations=iterations, stall=stall)
        if _largest_miss(g, pts) <= UNTIMED_ENOUGH * size:
            fits[i] = g
            met = met or (g.rms <= UNTIMED_MET * size and np.ptp(g.branch) == 0)
    return sorted(fits, key=lambda f: f.rms), met


def _largest_miss(fit, pts) -> float:
    """A fit's largest distance to a target, at its own input angles."""
    from .refine import coupler_and_jacobian

    return float(np.max(np.abs(coupler_and_jacobian(fit.x, fit.theta, fit.branch)[0] - pts)))


#: An open target the nearest untimed fit traces this closely (as a share of its size), but
#: only out of order or across assemblies, takes no more pool rounds.
UNTIMED_TRACED = 1e-5


def _worth_a_round(fits, pts, closed) -> bool:
    """Whether another pool may still improve the best untimed fit.

    Judged on the best fit on one assembly with the targets in order along its
    curve (the nearest fit of all, for an open target that none of them comes
    near). Not when its largest miss (at its own input angles) is within
    :data:`UNTIMED_ENOUGH` of the size (the targets are met as
    far as an engineer can tell; sloppy valleys often stall there, short of
    :data:`UNTIMED_MET`), nor, for an open target, when it misses by more than
    :data:`UNTIMED_FAR` (no four-bar traces the path: the random crank-rocker
    arcs of ``bench_atlas.py --recovery 20 --seed 11`` that later rounds
    recovered missed by at most ~2e-5 after the first, and fresh pools do not
    bring a path no four-bar traces nearer; the query keeps to its time budget).
    A closed target's first round can be misled by its descriptor (unevenly
    spread points): its later rounds, arc by arc, stay.
    """
    if not fits:
        return True
    size = float(np.max(np.abs(pts - pts.mean())))

    def worst(f) -> float:
        return _largest_miss(f, pts) / size

    nearest = worst(fits[0])
    if not closed and nearest > UNTIMED_FAR:  # not even the nearest fit comes near
        return False
    # the best fit that can be an answer: one assembly, the targets in order along the curve
    # (a near fit through them out of order is rejected by the checks anyway)
    best = next((f for f in fits if np.ptp(f.branch) == 0 and _in_order(f.theta, closed, None)),
                None)  # fmt: skip
    if best is None:  # none can be an answer: an open target traced only out of order (or
        # across assemblies) by the nearest fit is traced so by fresh pools too (a zigzag)
        return closed or nearest > UNTIMED_TRACED
    miss = worst(best)
    return miss > UNTIMED_ENOUGH and (closed or miss <= UNTIMED_FAR)


def _untimed_starts(entries, transforms, pts) -> list:
    return [_start_untimed(row, tr, pts) for row, tr in zip(entries, transforms, strict=True)]


def _polished(fits, pts, options, most, nfev=400, deadline: _Deadline = _NEVER,
              tries: int | None = None) -> tuple[list, bool]:  # fmt: skip
    """The best fits polished down their valleys (:func:`~machdyn.synthesis.valley.polish`).

    Targets on a short arc (untimed above all) make a sloppy problem whose exact
    fits lie at the ends of long curved valleys. :data:`POLISH` fits are refined on (``nfev``
    steps of :func:`refine`, which keeps the bounds) and then polished, and more
    (up to ``most``) while none meets the targets to :data:`UNTIMED_MET` of
    their size on one assembly; none past the ``deadline``. With ``tries``, while
    the best fit is a near miss (RMS within :data:`TIMED_TRIES_NEAR` of the size), a
    fit that ends where one polished before ended (within :data:`COPY`: the same
    local minimum, reached from another start) does not count: up to ``tries`` fits
    are polished to find ``most`` distinct ones (timed targets, whose best-screened
    starts can all be copies of one wrong minimum). Returns the fits (best first)
    and whether one met.
    """
    size = float(np.max(np.abs(pts - pts.mean())))
    fits = list(fits)
    met = False
    done: list[np.ndarray] = []  # the polished fits' keys as they started...
    ends: list[np.ndarray] = []  # ... and as they ended (with tries)
    distinct, best = 0, np.inf

    def copy(f) -> bool:  # in a minimum polished already (with tries)
        return tries is not None and any(np.max(np.abs(_design_key(f, size) - k)) <= COPY
                                         for k in ends)  # fmt: skip

    for i in range(min(most if tries is None else tries, len(fits))):
        if (i >= POLISH and met) or deadline.passed():
            break
        near = best <= TIMED_TRIES_NEAR * size
        if tries is not None and (distinct >= most or (i >= most and not near)):
            break
        f = fits[i]
        key = _design_key(f, size)
        if any(np.max(np.abs(key - k)) <= SAME for k in done + ends):
            continue  # a copy of a fit polished already (see _unique)
        done.append(key)
        if (
            tries is not None
            and i >= most
            and copy(refine(f.x, f.theta, f.branch, pts, max_nfev=nfev, solver="lm", **options))
        ):
            continue  # an extra try: a look with the (compiled) LM first, a hundred times cheaper
        more = refine(f.x, f.theta, f.branch, pts, max_nfev=nfev, **options)  # bounds kept
        f = fits[i] = more if more.rms <= f.rms else f
        if copy(f):
            continue  # refined into a minimum polished already: no polish, not counted
        if f.rms > UNTIMED_MET * size:
            f = polish(f, pts, **options)
        fits[i] = f
        met = met or (f.rms <= UNTIMED_MET * size and np.ptp(f.branch) == 0)
        best = min(best, f.rms)
        if tries is not None:
            distinct += 1
            ends.append(_design_key(f, size))
    return sorted(fits, key=lambda f: f.rms), met


def _constraints(O2, theta1, absolute_timing, max_length, pivot_box, timing, atlas):
    """Refinement's fixed unknowns (index → value), the length bound and the pivot box."""
    from .._validate import point

    absolute_timing = boolean("absolute_timing", absolute_timing)
    fixed: dict[int, float] = {}
    if O2 is not None:
        O2 = point("O2", O2)
        fixed.update({6: O2.real, 7: O2.imag})
    if theta1 is not None:
        fixed[8] = finite_scalar("theta1", theta1, "radian")
    if absolute_timing:
        if timing is None:
            raise InputError("absolute_timing", "needs timing (the input angle at each target)")
        fixed[9] = 0.0
    if max_length is not None:
        max_length = positive("max_length", max_length)
    if pivot_box is not None:
        box = np.ravel(finite_array("pivot_box", pivot_box))
        if box.size != 4 or not (box[0] < box[2] and box[1] < box[3]):
            raise InputError("pivot_box", "must be (xmin, ymin, xmax, ymax) with min < max")
        pivot_box = tuple(float(v) for v in box)
    if (fixed or max_length is not None or pivot_box) and atlas.manifest.kind == "sixbar":
        raise InputError("O2", "placement and size limits are for four-bar atlases only")
    return fixed, max_length, pivot_box


def _sixbar_path(atlas, pts, timing, closed, n, tolerance, mu_min, retrieve, refine_count, client,
                 start, deadline=_NEVER):  # fmt: skip
    """:func:`path_from_atlas` on a six-bar atlas (:mod:`machdyn.synthesis.sixbar_path`)."""
    from .. import jit
    from .sixbar_path import (
        SIXBAR_LATER_TIMED,
        SIXBAR_ROUNDS,
        SIXBAR_TIMED_NUMPY,
        polished_sixbars,
        refine_sixbar,
        second_loop_fits,
        sixbar_result,
        sixbar_starts,
    )

    size = float(np.max(np.abs(pts - pts.mean())))
    compiled = jit.mode() != "off" and jit.load()  # one choice for the whole synthesis
    # six-bars: many atlas entries draw nearly the same curve, so many are screened; timed
    # targets many more (their fit is over-determined: real local minima near the truth)
    screen, most = (SIXBAR_SCREEN, SIXBAR_POLISH_MAX) if timing is None else SIXBAR_TIMED
    rounds, long = SIXBAR_ROUNDS[timing is not None], SIXBAR_LONG if compiled else (0, 0)
    if not compiled and timing is not None:  # MACHDYN_JIT=off: the NumPy loop's smaller budget
        (screen, most), rounds = SIXBAR_TIMED_NUMPY, 1
    options = dict(timing=timing, compiled=compiled)
    checked: dict[int, Any] = {}  # the Linkage's check of the fits met so far, by id

    def check(fit):
        if id(fit) not in checked:
            checked[id(fit)] = (fit, sixbar_result(fit[0], fit[1], fit[3], pts, timing, closed,
                                                   tolerance, mu_min))  # fmt: skip
        return checked[id(fit)][1]

    fits, loop, met, near, seen, scan = [], [], False, False, set(), 0.0
    t_begin = time.perf_counter()
    for round_ in range(rounds):  # rounds of fresh starts while none meets the targets
        if met or near or (round_ and deadline.passed()):
            break
        t0 = time.perf_counter()
        starts = sixbar_starts(atlas, pts, timing, closed, retrieve, screen * refine_count,
                               client, compiled, round_, fits)  # fmt: skip
        starts = [s for s in starts if s[0].tobytes() not in seen]
        seen.update(s[0].tobytes() for s in starts)
        scan += time.perf_counter() - t0
        steps = SIXBAR_POLISH // 2 if round_ else SIXBAR_POLISH  # later rounds: shorter
        later = SIXBAR_LATER_TIMED if round_ and timing is not None else (30, most)
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
        near = min((f[2] for f in fits), default=np.inf) <= SIXBAR_NEAR * size
    fits.sort(key=lambda f: f[2])
    if not met and long[0] and not deadline.passed():  # the best crawl along narrow valleys:
        order = list(range(min(long[0], len(fits))))  # polish longer (and the best loop fit)
        order += [i for i, f in enumerate(fits) if loop and f is loop[0] and i >= long[0]]
        for i in order:
            x, th, rms, fx = fits[i]
            more = refine_sixbar(x, th, fx, pts, iterations=long[1], **options)
            fits[i] = (*more, fx) if more[2] <= rms else fits[i]
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
    seconds = {"retrieve": scan, "refine": t2 - t_begin - scan,
               "total": time.perf_counter() - start}  # fmt: skip
    note = _limit_note(note, deadline, deadline.at - start, seconds["total"])
    return PathCandidates(tuple(chosen), tuple(rejected[: max(n, 5)]), pts, worst <= NEAR, note,
                          seconds)  # fmt: skip


#: Entries of an open target's pool whose curves are computed at once (a time limit is
#: looked at between slices).
POOL_SLICE = 1_000


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
        dense = interpolate_closed(pts, 8 * man.samples)
        even = resample_closed(dense, man.samples)
        q = curve_descriptor(even, man.harmonics, resampled=True)
        idx, _ = atlas._query(q, retrieve, crank, client, deadline)
        rows = atlas.entries(idx)
        curves = even_curves(rows, man.circuit_samples, man.samples)
        transforms, residual = align_closed(even, curves)
    else:
        rows = atlas.entries(atlas.pool(OPEN_POOL, crank=crank))
        curves: list = []
        step = rows.size if deadline is _NEVER else POOL_SLICE  # (no limit: one call, as ever)
        for lo in range(0, rows.size, step):
            if curves and deadline.passed():
                break
            curves.append(even_curves(rows[lo : lo + step], man.circuit_samples, man.samples))
        curves = np.concatenate(curves)
        return _arc_starts(rows[: len(curves)], curves, pts, refine_count)
    order = np.argsort(residual)[:refine_count]
    return rows[order], transforms[order]


def _arc_starts(rows, curves, pts, count):
    """The ``count`` rows whose curves pass nearest an open target, and their placements.

    Every curve is first fitted arc-wise (:func:`align_partial`), then the
    :data:`RESCORE` best are re-fitted to the points themselves
    (:func:`_fit_to_points`) and ranked by that.
    """
    # a coarse arc fit is enough to pick the curves to re-fit: every other sample (half
    # the work of all 128)
    target = interpolate_open(pts, 24)
    transforms, residual = align_partial(target, curves[:, ::ARC_STRIDE])
    order = np.argsort(residual)[:RESCORE]
    rows, transforms = rows[order], transforms[order]
    transforms, miss = _fit_to_points(rows, transforms, pts)
    order = np.argsort(miss)[:count]
    return rows[order], transforms[order]


def _fit_to_points(rows, transforms, pts, rounds: int = ICP_ROUNDS):
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

    Returns the new transforms (N, 2) and the RMS point-to-curve misses over
    the size (N,).
    """
    f = {k: rows[k].astype(float) for k in ("r1", "r3", "r4", "p", "delta")}
    Q, _ = circuit_points(f["r1"], 1.0, f["r3"], f["r4"], f["p"], f["delta"],
                          rows["circuit"].astype(float), DENSE)  # fmt: skip
    Q = np.where(np.isfinite(Q), Q, np.inf)
    size = float(np.max(np.abs(pts - pts.mean())))
    a0 = pts - pts.mean()
    h, t = transforms[:, 0].copy(), transforms[:, 1].copy()
    for _ in range(rounds):
        near = _nearest_on(Q, h, t, pts)  # (N, K) in the curves' own frames
        bm = near.mean(axis=1, keepdims=True)
        b0 = near - bm
        v = np.sum(np.abs(b0) ** 2, axis=1)
        hn = np.sum(np.conj(b0) * a0[None, :], axis=1) / np.where(v > 0, v, np.inf)
        good = np.isfinite(hn) & (hn != 0)
        h, t = np.where(good, hn, h), np.where(good, pts.mean() - hn * bm[:, 0], t)
    near, i = _nearest_on(Q, h, t, pts, index=True)
    miss = np.sqrt(np.mean(np.abs(t[:, None] + h[:, None] * near - pts[None, :]) ** 2, axis=1))
    miss = np.where(np.isfinite(miss), miss / size, np.inf)
    # a rocker's circuit runs on both assemblies (sign of sin u): targets met on both
    # need a pass through a toggle, a branch defect that no refinement mends: last
    side = np.sign(np.sin(2 * np.pi * i / DENSE))
    mixed = (rows["barker"] > 2) & (np.ptp(side, axis=1) > 0)
    return np.column_stack([h, t]), np.where(mixed, miss + 1.0, miss)


def _nearest_on(Q, h, t, pts, index=False):
    """Nearest point to each target of each polygon ``t + h·Q`` (N, M), in Q's frame (N, K).

    ``index``: also return the nearest sample of each (N, K).
    """
    w = (pts[None, :] - t[:, None]) / np.where(h != 0, h, 1.0)[:, None]  # (N, K)
    n = np.arange(Q.shape[0])[:, None]
    i = np.argmin(np.abs(Q[:, None, :] - w[:, :, None]), axis=2)  # nearest sample (N, K)
    m = Q.shape[1]
    best = Q[n, i]
    for a, b in ((Q[n, i], Q[n, (i + 1) % m]), (Q[n, (i - 1) % m], Q[n, i])):  # its two edges
        seg = b - a
        den = np.where(np.abs(seg) > 0, np.abs(seg) ** 2, np.inf)
        u = np.clip(np.real((w - a) * np.conj(seg)) / den, 0.0, 1.0)
        c = a + u * seg
        best = np.where(np.abs(w - c) < np.abs(w - best), c, best)
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
    even = resample_closed(interpolate_closed(pts, 8 * man.samples), man.samples)
    transforms, residual = align_closed(even, curves)
    order = np.argsort(residual)[:refine_count]
    return rows[order], transforms[order]


def _start_untimed(row, tr, pts):
    """Refinement start of an atlas entry placed by ``tr = (h, t)``: design, θ_k, assembly_k."""
    h, t = tr
    if not np.isfinite(h) or h == 0:
        return None
    r1, r3, r4, p, delta = (float(row[k]) for k in ("r1", "r3", "r4", "p", "delta"))
    circuit = float(row["circuit"])
    s, rot = abs(h), np.angle(h)
    # dense samples of the circuit, to start each target at its nearest point
    local, theta2 = circuit_points([r1], 1.0, [r3], [r4], [p], [delta], [circuit], 720)
    c, hw, ck = circuit_range(r1, 1.0, r3, r4, circuit)
    u = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    _, branch = circuit_angles(u, c, hw, ck, circuit)
    x0 = np.array([r1 * s, s, r3 * s, r4 * s, p * s, delta, t.real, t.imag, rot])
    near = np.argmin(np.abs((t + h * local[0])[None, :] - pts[:, None]), axis=1)
    return x0, theta2[0][near], branch[near]


#: Entries scanned for timed targets, and crank angles tried for the first target.
TIMED_POOL = 5_000
#: Timed open targets: most rounds of retrieval (each a fresh pool) while none is met but
#: the best fit is a near miss (RMS within this share of the size: a linkage through the
#: targets likely exists; the random open-timed targets a fresh pool met were missed by
#: 9e-6 and 7e-5 of their size in the first round, the literature's case 4, which no
#: four-bar meets, by 4e-2, and a second round did not lower its error).
TIMED_ROUNDS = 2
TIMED_NEAR_MISS = 1e-2
TIMED_GRID = 60
#: Timed targets: fits polished at most (per round) to reach POLISH distinct local minima
#: while the best is a near miss (RMS within TIMED_TRIES_NEAR of the size; see _polished).
#: Seed 11's open-timed case 8 (bench_atlas --recovery 20): the ten best-screened starts of
#: the first pool all ended in one minimum (RMS 2.9e-4 of the size; max miss 4.6e-4) and
#: the eleventh met the targets; the literature's cases 3 and 4, which no four-bar meets
#: (RMS 4e-2), keep their POLISH fits and time.
TIMED_TRIES = 12
TIMED_TRIES_NEAR = 1e-3


def _retrieve_timed(atlas: Atlas, pts, timing, closed, retrieve, refine_count, client=None,
                    fixed=None, deadline: _Deadline = _NEVER):  # fmt: skip
    """Refinement starts for timed targets: scan θ0 for every entry of a pool, fit each.

    For each crank entry (and its mirror image: δ → −δ on the other assembly,
    which runs the other way round for the same crank rotation) and each of
    ``TIMED_GRID`` starting angles θ0, the coupler points at ``θ0 + Δ_k`` are
    fitted onto the targets by a rotation, scale and offset (closed form); the
    best fits start the refinements. ``fixed`` (see :func:`refine`) holds the
    pivot, the ground line's direction or θ0 (absolute timing): the fit then
    keeps them (a scale only, or a scale and rotation). Past the ``deadline``, the
    query scores no more chunks (:meth:`Atlas._query`) and the wide rows are left out.
    """
    fixed = fixed or {}
    man = atlas.manifest
    idx = atlas.pool(TIMED_POOL, crank=True)
    if closed:
        dense = interpolate_closed(pts, 8 * man.samples)
        q = curve_descriptor(resample_closed(dense, man.samples), man.harmonics, resampled=True)
        idx = np.union1d(idx, atlas._query(q, retrieve, True, client, deadline)[0])
    wide = _wide_rows(True)[: None if 9 in fixed else WIDE_TIMED]  # θ0 scanned: fewer
    wide = wide[:0] if deadline.passed() else wide
    held = 6 in fixed or 8 in fixed  # (refine_count was quadrupled for them)
    groups = [(rows, count) for rows, count in (
        (atlas.entries(idx), refine_count),
        (wide, max(1, refine_count // 4) if held else refine_count)) if rows.size]  # fmt: skip
    # every row scored in one call (on threads), the best starts picked group by group
    scored = _timed_scored(np.concatenate([rows for rows, _ in groups]), pts, timing, fixed)
    starts, lo = [], 0
    for rows, count in groups:
        part = tuple(x[:, lo : lo + rows.size] for x in scored)
        starts += _timed_starts(rows, pts, timing, count, fixed, part)
        lo += rows.size
    return starts


def _timed_grid(fixed) -> np.ndarray:
    """Starting crank angles θ0 scanned for timed targets (θ0 itself when it is held)."""
    return np.zeros(1) if 9 in fixed else np.linspace(0.0, 2 * np.pi, TIMED_GRID, endpoint=False)


def _timed_scored(rows, pts, timing, fixed) -> tuple:
    """:func:`_timed_fits` of every row (score, θ0 index, h, t; each (2, rows)), on threads."""
    from .._parallel import for_slices

    table = _angle_table(_timed_grid(fixed)[:, None] + timing[None, :])  # (G, K) angles
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


def _timed_starts(rows, pts, timing, refine_count, fixed, scored=None):
    """The ``refine_count`` best timed starts among ``rows`` (both mirror images).

    ``scored``: :func:`_timed_scored` of these rows, when already computed.
    """
    score, g, hh, off = (x.ravel() for x in scored or _timed_scored(rows, pts, timing, fixed))
    # (2, rows) each, flattened: all entries as stored, then all mirrored
    mirror = np.repeat([1.0, -1.0], rows.size)
    order = np.argsort(-score)[:refine_count]
    rows2 = np.concatenate([rows, rows])
    grid = _timed_grid(fixed)
    starts = []
    for i in order:
        row, m, h = rows2[i], mirror[i], hh[i]
        r1, r3, r4, p, delta = (float(row[k]) for k in ("r1", "r3", "r4", "p", "delta"))
        s = abs(h)
        x0 = np.array([r1 * s, s, r3 * s, r4 * s, p * s, m * delta, off[i].real, off[i].imag,
                       np.angle(h)])  # fmt: skip
        theta = grid[g[i]] + timing
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


def _checked(fit, pts, timing, closed, crank, mu_min, tolerance) -> PathSynthesis | None:
    """The refined linkage as a PathSynthesis, checked by the four-bar's own code."""
    r1, r2, r3, r4, p, delta, ox, oy, theta1 = fit.x
    try:
        fb = FourBar(r1, r2, r3, r4, coupler=(p, delta))
    except InputError:
        return None
    except Exception:  # AssemblyError: lengths that cannot form a four-bar
        return None
    branches = np.unique(fit.branch)
    placed = PlacedFourBar(
        fb, complex(ox, oy), float(theta1), int(np.sign(np.sum(fit.branch)) or 1)
    )
    theta = np.mod(fit.theta, 2 * np.pi)
    P = np.empty(pts.size, dtype=complex)
    ok = np.ones(pts.size, dtype=bool)
    for b in branches:  # the four-bar's own solver, on each target's assembly
        sel = fit.branch == b
        other = PlacedFourBar(fb, placed.O2, placed.theta1, int(b))
        _, _, P[sel], ok[sel] = other.pose(theta[sel])
    distance = np.where(ok, np.abs(P - pts), np.inf)
    cls = classify(*fb.lengths)
    is_crank = 2 in cls.cranks
    dense = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
    okd = placed.pose(dense)[3] if is_crank else np.ones(dense.size, bool)
    lengths = {k: np.array([v]) for k, v in zip(("r1", "r2", "r3", "r4"), fb.lengths, strict=True)}
    mu = float(_mu_min(lengths, dense, okd[None, :])[0]) if is_crank else float("nan")
    in_order = _in_order(theta, closed, timing)
    defects = []
    if crank and not is_crank:
        defects.append(f"link 2 is not a full-turn crank ({cls.code})")
    if branches.size > 1:
        defects.append("branch defect: the linkage must pass a toggle between targets")
    if is_crank and mu < mu_min - np.radians(0.5):
        defects.append(f"transmission angle falls to {np.degrees(mu):.1f} deg")
    if not in_order:
        defects.append("order defect: the coupler point meets the targets out of order")
    if not np.all(ok):
        defects.append("the linkage cannot be assembled at some target")
    if tolerance is not None:
        far = np.flatnonzero(~(distance <= tolerance))
        if far.size:
            defects.append(f"targets {[int(i) + 1 for i in far]} are farther than {tolerance:g}")
    return PathSynthesis(
        linkage=placed,
        targets=pts,
        theta2=theta,
        distance=distance,
        barker_class=cls.code,
        is_crank=is_crank,
        mu_min=mu,
        in_order=in_order,
        objective=fit.rms,
        defects=tuple(defects),
    )


#: Steps of the refinement along a change point (see _onto_grashof).
GRASHOF_NFEV = 60


def _grashof_excess(x) -> float:
    """``s + l − p − q`` of the lengths ``x[:4]`` (positive: not Grashof)."""
    srt = np.sort(np.asarray(x[:4], float))
    return float(srt[0] + srt[3] - srt[1] - srt[2])


def _onto_grashof(fit, pts, options=None):
    """A fit that breaks Grashof's condition by a hair, moved onto the change point.

    The refinement holds link 2 a crank by a penalty, so an optimum on the
    boundary ``s + l = p + q`` (the literature's best linkages often sit there)
    ends a few millionths past it, where the four-bar check rightly finds no
    crank. The longest link is shortened by that excess (at most 1e-4 of the
    links' sum): the linkage lands on the change point, whose shortest link turns
    fully, and its coupler point moves little (near a change point, some ten times the
    excess). With the refinement's ``options``, it is then refined along the
    change point (``l = p + q − s`` held: :data:`GRASHOF_NFEV` steps of
    :func:`refine`'s Levenberg–Marquardt), kept if that lowers its misses.
    """
    from .refine import Refined, coupler_and_jacobian

    lengths = np.asarray(fit.x[:4], float)
    excess = _grashof_excess(lengths)
    near = abs(excess) <= 1e-4 * lengths.sum()
    if not near or (excess <= 0.0 and options is None):
        return fit
    x = fit.x.copy()
    onto = fit
    if excess > 0.0:
        x[int(np.argmax(lengths))] -= excess
        G = coupler_and_jacobian(x, fit.theta, fit.branch)[0]
        rms = float(np.sqrt(np.mean(np.abs(G - pts) ** 2)))
        onto = Refined(x, fit.theta, fit.branch, rms, fit.success)
    if options is None:
        return onto
    order = np.argsort(lengths)  # s, p, q, l: s + l − p − q = 0 held by one of them
    sign = np.array([1.0, -1.0, -1.0, 1.0])[np.argsort(order)]
    top = options.get("max_length")
    top = np.inf if top is None else top
    # the length solved for: the longest whose result keeps the length bound (the
    # others keep it by the refinement's bounds)
    for tied in (int(i) for i in order[::-1] if x[i] < top * (1 - 1e-9)):
        c = np.where(np.arange(4) == tied, 0.0, -sign / sign[tied])
        more = refine(x, fit.theta, fit.branch, pts, max_nfev=GRASHOF_NFEV, solver="lm",
                      tie=(tied, c), **options)  # fmt: skip
        if 0.0 < more.x[tied] <= top:
            good = _grashof_excess(more.x) <= max(_grashof_excess(x), 0.0)
            return more if good and more.rms < onto.rms else onto
    return onto


def _in_order(theta: np.ndarray, closed: bool, timing) -> bool:
    """True when the targets follow each other one way along the curve."""
    if timing is not None:
        return True
    steps = np.mod(np.diff(np.concatenate([theta, theta[:1]]) if closed else theta), 2 * np.pi)
    full = 2 * np.pi
    fwd = float(np.sum(steps))
    back = float(np.sum(np.mod(-steps, full)))
    limit = full + 1e-6
    return fwd <= limit or back <= limit


def _unique(fits: list, size: float) -> list:
    """``fits`` (best first) less the copies of one linkage (its best-converged copy stays).

    A copy is within :data:`SAME` of a better fit in every design number (lengths
    and pivot over the size, angles in radians) and on the same assemblies.
    """
    kept: list = []
    keys: list[np.ndarray] = []
    for f in fits:
        key = _design_key(f, size)
        if all(np.max(np.abs(key - k)) > SAME for k in keys):
            kept.append(f)
            keys.append(key)
    return kept


#: Refined fits closer than this (see _unique) are one linkage.
SAME = 1e-6
#: Polished fits closer than this (see _polished) ended in one local minimum.
COPY = 1e-4


def _design_key(f, size: float) -> np.ndarray:
    """A fit's design numbers (lengths and pivot over the size, angles) and assemblies.

    The angles δ and θ1 enter as their cosines and sines: a fit and its copy a turn
    further round (θ1 and θ1 + 2π) have one key.
    """
    angles = f.x[[5, 8]]
    return np.concatenate([f.x[[0, 1, 2, 3, 4, 6, 7]] / size, np.cos(angles), np.sin(angles),
                           f.branch])  # fmt: skip


def _distinct(results: list[PathSynthesis], n: int, size: float) -> list[PathSynthesis]:
    """Up to ``n`` results whose pivots and lengths differ by more than 2 % of the size."""
    chosen: list[PathSynthesis] = []
    keys: list[np.ndarray] = []
    for r in results:
        pl = r.linkage
        key = np.array([*pl.lengths, pl.O2.real, pl.O2.imag, pl.O4.real, pl.O4.imag]) / size
        if all(np.max(np.abs(key - k)) > 0.02 for k in keys):
            chosen.append(r)
            keys.append(key)
        if len(chosen) == n:
            break
    return chosen
