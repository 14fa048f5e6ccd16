"""Atlas chunks as Dask tasks: a ``LocalCluster`` by default, any scheduler by address.

Dask (``dask.distributed``) is imported only here, and only when a build or a
query asks for a cluster: ``import machdyn`` never pays for it.

On several machines: start a scheduler (``dask scheduler``) on one, a worker
(``dask worker tcp://HOST:8786 --nthreads 1 --nworkers auto``) on each, with
machdyn installed everywhere and the atlas folder on a file system they all
see (NFS, a cluster's shared disk), then pass ``scheduler="tcp://HOST:8786"``
(``--scheduler`` on the command line). Each chunk is one task: a worker
samples its linkages, computes their curves and descriptors and writes the
chunk's files; the client only records the checksums in the manifest.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any

from ..errors import InputError

# Internal to machdyn.synthesis, which re-exports the public names (Atlas, build_atlas,
# open_atlas, path_from_atlas, curve_descriptor, ...); the fuzz suite fuzzes those.
__all__: list[str] = []

#: Environment of local worker processes: one thread each (the worker *is* the parallelism).
WORKER_ENV = {
    "MACHDYN_THREADS": "1",
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
}


@contextmanager
def client_for(scheduler: str, workers: int | None = None) -> Iterator[Any]:
    """A ``distributed.Client`` on a new ``LocalCluster`` (``"local"``) or on an address."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:  # pragma: no cover - dask is a dependency
        raise InputError(
            "scheduler", "needs dask.distributed: pip install 'dask[distributed]'"
        ) from None
    if scheduler == "local":
        import os

        n = workers or os.cpu_count() or 1
        cluster = LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            env=WORKER_ENV,
        )
        try:
            with Client(cluster) as client:
                yield client
        finally:
            cluster.close()
    elif scheduler.startswith(("tcp://", "tls://", "inproc://", "ucx://")):
        try:
            client = Client(scheduler, timeout="20s")
        except OSError as exc:
            raise InputError("scheduler", f"cannot reach {scheduler}: {exc}") from None
        with client:
            yield client
    else:
        raise InputError(
            "scheduler", f"must be 'local' or an address such as tcp://host:8786, got {scheduler!r}"
        )


def map_chunks(
    func: Callable[..., Any], args: Sequence[tuple], scheduler: str, workers: int | None = None
) -> Iterator[Any]:
    """Run ``func(*a)`` for every ``a`` in ``args`` as Dask tasks; yield results as they finish."""
    from distributed import as_completed

    with client_for(scheduler, workers) as client:
        futures = [client.submit(func, *a, pure=False) for a in args]
        for future in as_completed(futures):
            yield future.result()
