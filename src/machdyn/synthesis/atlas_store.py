"""A coupler-curve atlas on disk: sampled four-bars, their descriptors, built in chunks.

An atlas is a folder::

    manifest.json            format version, sampling, descriptor settings, per-chunk CRCs
    chunk_00000.desc.npy     float32 (rows, 4K): curve descriptors (unit vectors)
    chunk_00000.meta.npy     structured (rows,): r1 r3 r4 p delta (float32), circuit, barker (int8)
    ...

Why ``.npy``: the two arrays per chunk are dense numbers that a query reads
whole, once, at memory speed (``np.load(mmap_mode="r")``, no decoding), with
no dependency beyond NumPy; compression buys little on float descriptors
(they are near-random bits), and Zarr or Parquet would add a package for what
a file per chunk and a JSON manifest already give: chunks written
independently (by any Dask worker), atomically (``os.replace``), checked by a
CRC-32 each, and a build that resumes by skipping the chunks the manifest lists.

Linkages are sampled with ``r2 = 1`` (the atlas is scale-free) by a generator
seeded with ``(seed, chunk)``, so a chunk is the same wherever and whenever it
is built. Their parameters are rounded to float32 *before* the curve is
computed: an entry rebuilds to exactly the curve its descriptor came from.
"""

from __future__ import annotations

import json
import mmap
import os
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import jit
from .._validate import boolean, choice, integer
from ..errors import InputError
from .circuits import circuit_points, circuit_range
from .descriptor import HARMONICS, SAMPLES, curve_descriptor, resample_closed

# Internal to machdyn.synthesis, which re-exports the public names (Atlas, build_atlas,
# open_atlas, path_from_atlas, curve_descriptor, ...); the fuzz suite fuzzes those.
__all__: list[str] = []

#: Bumped whenever sampling, circuits or descriptors change: older atlases are refused.
FORMAT_VERSION = 1
#: Circuit samples per curve before the arc-length resampling.
CIRCUIT_SAMPLES = 256
#: Entries per chunk (one Dask task each).
CHUNK_SIZE = 1 << 16
#: Rows computed at once inside a chunk (keeps temporaries near 50 MB).
_BLOCK = 4096
#: Range of r1, r3, r4 over r2 (log-uniform) and radius of the coupler-point disc (over r3).
LENGTH_RANGE = (0.2, 5.0)
COUPLER_RADIUS = 2.0
#: Fraction of drawn linkages whose link 2 is not a crank that are kept (about half the atlas
#: then has a crank input; every class stays present).
NON_CRANK_SHARE = 0.2

META_DTYPE = np.dtype(
    [
        ("r1", "<f4"),
        ("r3", "<f4"),
        ("r4", "<f4"),
        ("p", "<f4"),
        ("delta", "<f4"),
        ("circuit", "i1"),
        ("barker", "i1"),
    ]
)
#: Barker numbers (1–8) of the classes the sampler produces, as in ``classify.BARKER_CLASSES``.
BARKER_CODES = ("", "GCCC", "GCRR", "GRCR", "GRRC", "RRR1", "RRR2", "RRR3", "RRR4")


class AtlasError(InputError):
    """An atlas folder that cannot be used: missing, from another version, or corrupted."""

    def __init__(self, path: Any, message: str) -> None:
        super().__init__("atlas", f"{path}: {message}")


@dataclass
class Manifest:
    """What an atlas holds and how it was made (``manifest.json``)."""

    count: int
    chunk_size: int = CHUNK_SIZE
    seed: int = 0
    harmonics: int = HARMONICS
    samples: int = SAMPLES
    circuit_samples: int = CIRCUIT_SAMPLES
    format_version: int = FORMAT_VERSION
    machdyn_version: str = ""
    kind: str = "fourbar"
    chunks: dict[str, dict[str, Any]] = field(default_factory=dict)

    @property
    def n_chunks(self) -> int:
        """Number of chunks the complete atlas has."""
        return -(-self.count // self.chunk_size)

    def rows(self, index: int) -> int:
        """Entries in chunk ``index``."""
        return min(self.chunk_size, self.count - index * self.chunk_size)

    @property
    def complete(self) -> bool:
        """True when every chunk has been built."""
        return len(self.chunks) == self.n_chunks

    def same_recipe(self, other: Manifest) -> bool:
        """True if ``other`` describes the same atlas (everything but the chunks built)."""
        keys = ("count", "chunk_size", "seed", "harmonics", "samples", "circuit_samples", "kind")
        return all(getattr(self, k) == getattr(other, k) for k in keys)

    def to_json(self) -> str:
        """The manifest as JSON text."""
        d = {k: getattr(self, k) for k in self.__dataclass_fields__}
        d["format"] = "machdyn-atlas"
        return json.dumps(d, indent=1, sort_keys=True)


def folder_path(field: str, value: Any) -> Path:
    """A folder argument as a Path (a str or path-like, not empty), else :class:`InputError`."""
    if not isinstance(value, str | os.PathLike) or not str(os.fspath(value)).strip():
        raise InputError(field, f"must be a folder path, got {value!r:.60}")
    return Path(os.fspath(value))


def chunk_name(index: int) -> str:
    """File stem of chunk ``index``."""
    return f"chunk_{index:05d}"


def read_manifest(path: Path) -> Manifest:
    """Read and check ``manifest.json`` (format and version); raises :class:`AtlasError`."""
    file = Path(path) / "manifest.json"
    if not file.is_file():
        raise AtlasError(
            path, "no manifest.json here: not an atlas (build one with 'machdyn atlas build')"
        )
    try:
        d = json.loads(file.read_text())
    except (OSError, ValueError) as exc:
        raise AtlasError(path, f"manifest.json cannot be read ({exc}); rebuild the atlas") from None
    if not isinstance(d, dict) or d.get("format") != "machdyn-atlas":
        raise AtlasError(path, "manifest.json is not a machdyn atlas manifest")
    version = d.get("format_version")
    if type(version) is not int or version != FORMAT_VERSION:
        raise AtlasError(
            path,
            f"atlas format {version!r} (built by machdyn {d.get('machdyn_version', '?')}) is not "
            f"this machdyn's format {FORMAT_VERSION}: its descriptors would be compared wrongly; "
            "rebuild it with 'machdyn atlas build'",
        )
    fields = Manifest.__dataclass_fields__
    try:
        manifest = Manifest(**{k: d[k] for k in fields if k in d})
    except TypeError as exc:
        raise AtlasError(path, f"manifest.json is incomplete ({exc})") from None
    why = _manifest_problem(manifest)
    if why:
        raise AtlasError(
            path, f"manifest.json {why}: edited, damaged or from another machdyn; rebuild the atlas"
        )
    return manifest


#: The sampling and descriptor settings this machdyn builds and queries with: a manifest
#: that says otherwise describes descriptors a query would compare wrongly.
_RECIPE = {"harmonics": HARMONICS, "samples": SAMPLES, "circuit_samples": CIRCUIT_SAMPLES}
#: Keys of a chunk's record (CRC-32s and byte sizes of its two files, its rows).
_CHUNK_KEYS = ("desc", "desc_bytes", "meta", "meta_bytes", "rows")


def _manifest_problem(m: Manifest) -> str:
    """Empty if ``m``'s fields have the types and values a build writes, else what is wrong.

    A manifest read from disk is checked before its numbers are used: a hand-edited or
    damaged one (a count as text, a chunk without its rows) is refused with the field,
    never an internal error or a query over rows that are not there.

    Examples
    --------
    >>> _manifest_problem(Manifest(count=10))
    ''
    >>> _manifest_problem(Manifest(count="10"))
    "has count '10', expected a whole number of entries >= 1"
    """

    def whole(v: Any, least: int) -> bool:
        return type(v) is int and v >= least

    if not whole(m.count, 1):
        return f"has count {m.count!r}, expected a whole number of entries >= 1"
    if not whole(m.chunk_size, 1):
        return f"has chunk_size {m.chunk_size!r}, expected a whole number >= 1"
    if not whole(m.seed, 0):
        return f"has seed {m.seed!r}, expected a whole number >= 0"
    if m.kind not in ("fourbar", "sixbar"):
        return f"has kind {m.kind!r}, expected 'fourbar' or 'sixbar'"
    for key, want in _RECIPE.items():
        if getattr(m, key) != want or type(getattr(m, key)) is not int:
            return f"has {key} {getattr(m, key)!r}, expected {want} (this machdyn's recipe)"
    if not isinstance(m.chunks, dict):
        return f"has chunks {type(m.chunks).__name__}, expected a mapping of chunk records"
    for key, info in m.chunks.items():
        if not (len(key) == 5 and key.isdigit() and int(key) < m.n_chunks):
            return f"lists chunk {key!r}, expected '00000' to '{m.n_chunks - 1:05d}'"
        if not isinstance(info, dict):
            return f"has chunk {key}'s record {info!r:.40}, expected a mapping"
        for k in _CHUNK_KEYS:
            if not whole(info.get(k), 0):
                return f"has chunk {key}'s {k} {info.get(k)!r:.40}, expected a whole number >= 0"
        if info["rows"] != m.rows(int(key)):
            return f"gives chunk {key} {info['rows']} rows, expected {m.rows(int(key))}"
    return ""


def _write_atomic(file: Path, data: bytes) -> None:
    tmp = file.with_name(file.name + f".tmp{os.getpid()}")
    tmp.write_bytes(data)
    os.replace(tmp, file)


def _npy_bytes(array: np.ndarray) -> bytes:
    import io

    buf = io.BytesIO()
    np.save(buf, array, allow_pickle=False)
    return buf.getvalue()


def crc_of(file: Path) -> int:
    """CRC-32 of a file's bytes, read through a memory map.

    Mapped, the bytes are the operating system's cached pages themselves:
    ``read`` would copy each piece into a fresh buffer, which costs more than
    the CRC (on the project's machine 1.9 s instead of 0.75 s of CPU for the
    10^7 atlas's 1.5 GB, most of it the kernel's copying and page faults).
    """
    with open(file, "rb") as fh:
        if os.fstat(fh.fileno()).st_size == 0:  # (an empty file cannot be mapped)
            return zlib.crc32(b"")
        with mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ) as data:
            return zlib.crc32(data)


# --------------------------------------------------------------------------------------
# sampling and one chunk


def sample_fourbars(
    rng: np.random.Generator, n: int, length_range: tuple[float, float] = LENGTH_RANGE
) -> np.ndarray:
    """``n`` random assemblable four-bars with a coupler point and a circuit (META_DTYPE rows).

    ``r2 = 1``; ``r1, r3, r4`` log-uniform over ``length_range`` (the atlas's:
    :data:`LENGTH_RANGE`); the
    coupler point uniform over a disc of radius ``COUPLER_RADIUS·r3`` about A;
    the circuit ±1 at random. Linkages within 1e-3 of a change point, or not
    assemblable, are drawn again; so are all but :data:`NON_CRANK_SHARE` of
    those whose link 2 is not a crank (about half the atlas has a crank input).
    Every Barker class except the change-point ones occurs.
    """
    out = np.empty(n, dtype=META_DTYPE)
    filled = 0
    lo, hi = np.log(length_range[0]), np.log(length_range[1])
    while filled < n:
        want = int(2.5 * (n - filled)) + 16
        r1, r3, r4 = np.exp(rng.uniform(lo, hi, size=(3, want))).astype(np.float32)
        rad = COUPLER_RADIUS * np.sqrt(rng.uniform(0.0, 1.0, want))
        ang = rng.uniform(-np.pi, np.pi, want)
        circuit = rng.choice(np.array([-1, 1], dtype=np.int8), want)
        lengths = np.stack([r1, np.ones_like(r1), r3, r4]).astype(float)
        srt = np.sort(lengths, axis=0)
        total = srt.sum(axis=0)
        excess = srt[0] + srt[3] - srt[1] - srt[2]
        good = (srt[3] < total - srt[3] - 1e-3 * total) & (np.abs(excess) > 1e-3 * total)
        # path synthesis mostly wants link 2 to be a crank: keep only a share of the rest
        crank = (excess < 0) & (np.argmin(lengths, axis=0) <= 1)  # GCCC, GCRR
        good &= crank | (rng.uniform(0.0, 1.0, want) < NON_CRANK_SHARE)
        k = min(int(good.sum()), n - filled)
        idx = np.flatnonzero(good)[:k]
        rows = out[filled : filled + k]
        rows["r1"], rows["r3"], rows["r4"] = r1[idx], r3[idx], r4[idx]
        rows["p"] = (rad[idx] * r3[idx]).astype(np.float32)
        rows["delta"] = ang[idx].astype(np.float32)
        rows["circuit"] = circuit[idx]
        rows["barker"] = barker_numbers(lengths[:, idx])
        filled += k
    return out


def barker_numbers(lengths: np.ndarray) -> np.ndarray:
    """Barker class numbers (1–8; 0 for a change point) of lengths (4, N), vectorised.

    Grashof (``s + l < p + q``): 1 + which link is shortest (1 → GCCC …
    4 → GRRC); otherwise 4 + which link is longest (RRR1 … RRR4); the notes'
    Table 2 (Norton Table 2-4).
    """
    lengths = np.asarray(lengths, dtype=float)
    srt = np.sort(lengths, axis=0)
    excess = srt[0] + srt[3] - srt[1] - srt[2]
    grashof = 1 + np.argmin(lengths, axis=0)
    non = 5 + np.argmax(lengths, axis=0)
    tol = 1e-12 * srt.sum(axis=0)
    return np.where(excess < -tol, grashof, np.where(excess > tol, non, 0)).astype(np.int8)


def fourbar_curves(meta: np.ndarray, m: int = CIRCUIT_SAMPLES) -> np.ndarray:
    """Circuit curves (rows, m) of atlas entries, from their float32 parameters."""
    f = {k: meta[k].astype(float) for k in ("r1", "r3", "r4", "p", "delta")}
    return circuit_points(
        f["r1"], 1.0, f["r3"], f["r4"], f["p"], f["delta"], meta["circuit"].astype(float), m
    )[0]


def even_curves(meta: np.ndarray, m: int, samples: int, compiled: bool | None = None) -> np.ndarray:
    """Circuit curves of atlas entries (``m`` samples) resampled evenly by arc length.

    ``compiled``: True/False to choose; None lets :mod:`machdyn.jit` decide.
    """
    if "topology" in meta.dtype.names:  # six-bars: the engine's dyads, NumPy
        from .sixbar import sixbar_points

        P = sixbar_points(meta, np.linspace(0.0, 2 * np.pi, m, endpoint=False))[0]
        return resample_closed(np.where(np.isfinite(P), P, 0.0), samples)
    f = {k: meta[k].astype(float) for k in ("r1", "r3", "r4", "p", "delta")}
    circuit = meta["circuit"].astype(float)
    if compiled is None:
        compiled = jit.kernels(meta.size * m) is not None
    if compiled:
        from . import _atlas_kernels

        centre, half, crank = circuit_range(f["r1"], 1.0, f["r3"], f["r4"], circuit)
        params = np.column_stack(
            [
                f["r1"], np.ones_like(f["r1"]), f["r3"], f["r4"],
                f["p"] * np.cos(f["delta"]), f["p"] * np.sin(f["delta"]),
                centre, half, crank.astype(float), circuit,
            ]
        )  # fmt: skip
        out = np.empty((meta.size, samples), dtype=complex)
        _atlas_kernels.even_circuit_curves(params, m, out)
        return out
    return resample_closed(fourbar_curves(meta, m), samples)


def describe_entries(meta: np.ndarray, manifest: Manifest, compiled: bool = False) -> np.ndarray:
    """Descriptors (rows, 4K) of atlas entries, computed in blocks."""
    out = np.empty((meta.size, 4 * manifest.harmonics), dtype=np.float32)
    for i in range(0, meta.size, _BLOCK):
        sl = slice(i, min(meta.size, i + _BLOCK))
        even = even_curves(meta[sl], manifest.circuit_samples, manifest.samples, compiled)
        out[sl] = curve_descriptor(even, manifest.harmonics, resampled=True)
    return out


def build_chunk(
    path: str, manifest_json: str, index: int, compiled: bool = False
) -> tuple[int, dict[str, Any]]:
    """Build chunk ``index`` of the atlas at ``path``, write its two files; return their CRCs.

    A plain function of picklable arguments: the unit of work of a Dask task.
    ``compiled`` picks the kernels for the whole chunk (the caller decides once,
    so that every worker computes the same numbers).
    """
    compiled = compiled and jit.load()
    manifest = Manifest(**{k: v for k, v in json.loads(manifest_json).items() if k != "format"})
    folder = Path(path)
    rng = np.random.default_rng([manifest.seed, index])
    if manifest.kind == "sixbar":
        from .sixbar import sample_sixbars

        meta = sample_sixbars(rng, manifest.rows(index), manifest.circuit_samples)
    else:
        meta = sample_fourbars(rng, manifest.rows(index))
    desc = describe_entries(meta, manifest, compiled)
    info: dict[str, Any] = {"rows": int(meta.size)}
    for suffix, array in (("desc", desc), ("meta", meta)):
        data = _npy_bytes(array)
        _write_atomic(folder / f"{chunk_name(index)}.{suffix}.npy", data)
        info[suffix] = zlib.crc32(data)
        info[f"{suffix}_bytes"] = len(data)
    return index, info


def chunk_is_good(folder: Path, index: int, info: dict[str, Any]) -> str:
    """Empty if chunk ``index``'s files exist with their recorded sizes and CRCs, else why not."""
    for suffix in ("desc", "meta"):
        file = folder / f"{chunk_name(index)}.{suffix}.npy"
        if not file.is_file():
            return f"{file.name} is missing"
        if file.stat().st_size != info.get(f"{suffix}_bytes"):
            size, want = file.stat().st_size, info.get(f"{suffix}_bytes")
            return f"{file.name} has {size} bytes, the manifest says {want}"
        if crc_of(file) != info.get(suffix):
            return f"{file.name} fails its CRC-32 check (corrupted)"
    return ""


# --------------------------------------------------------------------------------------
# the build


def build_atlas(
    path: Any,
    count: int,
    *,
    chunk_size: int = CHUNK_SIZE,
    seed: int = 0,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = True,
    kind: str = "fourbar",
) -> Manifest:
    """Build (or finish building) a four-bar coupler-curve atlas of ``count`` entries.

    Parameters
    ----------
    path : path-like
        Folder of the atlas (created if needed). If it holds a manifest of the
        same recipe, the chunks already built and intact are kept: a build that
        was interrupted resumes where it stopped.
    count : int
        Entries (linkage, coupler point, circuit).
    chunk_size : int
        Entries per chunk (one task).
    seed : int
        Seed of the sampler (chunk ``i`` uses ``(seed, i)``).
    scheduler : str, optional
        ``None``: build in this process. ``"local"``: on a Dask ``LocalCluster``
        of ``workers`` processes. ``"tcp://host:port"``: on that Dask scheduler
        (its workers must see ``path``: a shared file system).
    workers : int, optional
        Worker processes of the local cluster (default: the CPU count).
    progress : bool
        Show a progress bar (on stderr).
    kind : {"fourbar", "sixbar"}
        Four-bars over every Barker class and circuit, or crank-driven Watt and
        Stephenson six-bars (:mod:`machdyn.synthesis.sixbar`).

    Returns
    -------
    Manifest

    Examples
    --------
    >>> import tempfile
    >>> folder = tempfile.mkdtemp()
    >>> m = build_atlas(folder, 1000, chunk_size=400, progress=False)
    >>> m.n_chunks, m.complete, sorted(m.chunks)
    (3, True, ['00000', '00001', '00002'])
    """
    folder = folder_path("path", path)
    count = integer("count", count, minimum=1, maximum=10**10)
    chunk_size = integer("chunk_size", chunk_size, minimum=1, maximum=1 << 24)
    seed = integer("seed", seed, minimum=0, maximum=2**63)
    kind = choice("kind", kind, ("fourbar", "sixbar"))
    progress = boolean("progress", progress)
    if workers is not None:
        workers = integer("workers", workers, minimum=1, maximum=4096)
    if scheduler is not None and not isinstance(scheduler, str):
        raise InputError("scheduler", f"must be 'local' or an address, got {scheduler!r:.60}")
    from .. import __version__

    folder.mkdir(parents=True, exist_ok=True)
    manifest = Manifest(
        count=count, chunk_size=chunk_size, seed=seed, machdyn_version=__version__, kind=kind
    )
    manifest = _resume(folder, manifest)
    todo = [i for i in range(manifest.n_chunks) if f"{i:05d}" not in manifest.chunks]
    _save_manifest(folder, manifest)
    recipe = manifest.to_json()
    compiled = jit.mode() != "off" and jit.load()  # one choice for every chunk and worker
    with _Progress(progress, manifest.n_chunks, len(manifest.chunks)) as bar:
        if scheduler is None:
            for index in todo:
                _record(folder, manifest, *build_chunk(str(folder), recipe, index, compiled))
                bar.advance()
        else:
            from .atlas_dask import map_chunks

            for index, info in map_chunks(
                build_chunk,
                [(str(folder.resolve()), recipe, i, compiled) for i in todo],
                scheduler,
                workers,
            ):
                _record(folder, manifest, index, info)
                bar.advance()
    return manifest


def _resume(folder: Path, manifest: Manifest) -> Manifest:
    """Keep the intact chunks of an earlier build of the same recipe."""
    if not (folder / "manifest.json").exists():
        return manifest
    try:
        old = read_manifest(folder)
    except AtlasError:
        return manifest  # another version or unreadable: start again
    if not old.same_recipe(manifest):
        raise AtlasError(
            folder,
            f"holds another atlas ({old.count} entries, chunk size {old.chunk_size}, "
            f"seed {old.seed}); choose another folder or delete this one",
        )
    for key, info in old.chunks.items():
        if not chunk_is_good(folder, int(key), info):
            manifest.chunks[key] = info
    return manifest


def _record(folder: Path, manifest: Manifest, index: int, info: dict[str, Any]) -> None:
    manifest.chunks[f"{index:05d}"] = info
    _save_manifest(folder, manifest)


def _save_manifest(folder: Path, manifest: Manifest) -> None:
    _write_atomic(folder / "manifest.json", manifest.to_json().encode())


class _Progress:
    """A rich progress bar on stderr (or nothing)."""

    def __init__(self, show: bool, total: int, done: int) -> None:
        self.show, self.total, self.done = show, total, done
        self._bar = None

    def __enter__(self) -> _Progress:
        if self.show:
            from rich.console import Console
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeRemainingColumn

            self._bar = Progress(
                "[progress.description]{task.description}",
                BarColumn(),
                MofNCompleteColumn(),
                TimeRemainingColumn(),
                console=Console(stderr=True),
            )
            self._bar.start()
            self._task = self._bar.add_task("atlas chunks", total=self.total, completed=self.done)
        return self

    def advance(self) -> None:
        if self._bar is not None:
            self._bar.advance(self._task)

    def __exit__(self, *exc: object) -> None:
        if self._bar is not None:
            self._bar.stop()
