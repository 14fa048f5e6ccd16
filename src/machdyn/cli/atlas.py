"""``machdyn atlas ...``: build and inspect a coupler-curve atlas.

Registered by the application as ``app.add_typer(atlas_app, name="atlas")``.
Only parsing and presentation live here; the atlas is
:mod:`machdyn.synthesis.atlas_store`.
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from ._common import dumps, print_table

__all__ = ["DEFAULT_ATLAS", "atlas_app", "default_atlas"]

atlas_app = typer.Typer(
    name="atlas",
    help="Coupler-curve atlases for path synthesis: build (in chunks, on Dask), inspect.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

#: Where an atlas goes when no folder is named (``MACHDYN_ATLAS`` overrides it).
DEFAULT_ATLAS = Path("~/.cache/machdyn/fourbar.atlas")


def default_atlas() -> Path:
    """The atlas folder used when none is named: ``$MACHDYN_ATLAS`` or :data:`DEFAULT_ATLAS`."""
    return Path(os.environ.get("MACHDYN_ATLAS") or DEFAULT_ATLAS).expanduser()


@atlas_app.command("build")
def build_cmd(
    path: Annotated[
        Path | None,
        typer.Argument(
            help="Atlas folder (default $MACHDYN_ATLAS or ~/.cache/machdyn/fourbar.atlas)."
        ),
    ] = None,
    count: Annotated[
        int, typer.Option("--count", "-c", help="Entries (linkage, coupler point, circuit).")
    ] = 10_000_000,
    chunk_size: Annotated[
        int, typer.Option("--chunk-size", help="Entries per chunk (one task).")
    ] = 1 << 16,
    seed: Annotated[int, typer.Option("--seed", help="Seed of the sampler.")] = 0,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            help="'local' (a Dask LocalCluster) or tcp://HOST:PORT; default: this process.",
        ),
    ] = None,
    workers: Annotated[
        int | None, typer.Option("--workers", help="Workers of the local cluster.")
    ] = None,
    progress: Annotated[
        bool, typer.Option("--progress/--no-progress", help="Show a progress bar.")
    ] = True,
    kind: Annotated[
        str, typer.Option("--kind", help="fourbar, or sixbar (Watt and Stephenson).")
    ] = "fourbar",
) -> None:
    """Build a coupler-curve atlas, or finish one whose build was interrupted (same options)."""
    from ..synthesis.atlas_store import build_atlas

    if not 1 <= count <= 10**9:
        raise InputError("--count", f"must be between 1 and 10^9, got {count:,}")
    if workers is not None and workers < 1:
        raise InputError("--workers", f"must be at least 1, got {workers}")
    if not 1 <= chunk_size <= 1 << 24:
        raise InputError("--chunk-size", f"must be between 1 and {1 << 24:,}, got {chunk_size:,}")
    if seed < 0:
        raise InputError("--seed", f"must be zero or positive, got {seed}")
    if kind not in ("fourbar", "sixbar"):
        raise InputError("--kind", f"must be fourbar or sixbar, got {kind!r}")
    folder = path or default_atlas()
    if folder.exists() and not folder.is_dir():
        raise InputError("PATH", f"{folder} is a file; give a folder for the atlas")
    start = time.perf_counter()
    m = build_atlas(
        folder, count, chunk_size=chunk_size, seed=seed, scheduler=scheduler, workers=workers,
        progress=progress, kind=kind,
    )  # fmt: skip
    seconds = time.perf_counter() - start
    size = sum(f.stat().st_size for f in Path(folder).glob("chunk_*.npy"))
    print(f"atlas {folder}: {m.count:,} entries in {m.n_chunks} chunks, {size / 1e9:.2f} GB, "
          f"built in {seconds:.1f} s")  # fmt: skip


@atlas_app.command("info")
def info_cmd(
    path: Annotated[Path | None, typer.Argument(help="Atlas folder.")] = None,
    verify: Annotated[
        bool, typer.Option("--verify/--no-verify", help="Check every chunk's CRC-32.")
    ] = True,
    json: Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")] = False,
) -> None:
    """What an atlas holds; refuses (exit 1) one that is stale, unfinished or corrupted."""
    import numpy as np

    from ..synthesis.atlas_path import open_atlas
    from ..synthesis.atlas_store import BARKER_CODES

    folder = path or default_atlas()
    at = open_atlas(folder, verify=verify)
    m = at.manifest
    classes = np.bincount(np.concatenate([x["barker"] for x in at.meta]), minlength=9)
    kinds = {"kind": m.kind}
    counts = {BARKER_CODES[i]: int(classes[i]) for i in range(1, 9)}
    info = {
        "path": str(folder),
        **kinds,
        "entries": len(at),
        "chunks": m.n_chunks,
        "format_version": m.format_version,
        "built_by": m.machdyn_version,
        "harmonics": m.harmonics,
        "seed": m.seed,
        "barker_classes": counts,
        "verified": verify,
    }
    if json:
        print(dumps(info))
        return
    rows = [[k, v] for k, v in info.items() if k != "barker_classes"]
    rows += [[f"entries {k}", v] for k, v in counts.items()]
    print_table(f"Atlas {folder}", ["quantity", "value"], rows)
