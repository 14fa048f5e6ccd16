"""Run a vectorised kernel over slices of a large array on a few threads.

NumPy releases the GIL inside its ufuncs, so contiguous slices of one array can
be processed concurrently in one process. Small arrays run inline: below
:data:`MIN_PARALLEL` samples the thread hand-off costs more than it saves.

The number of threads is ``os.cpu_count()`` unless the environment variable
``MACHDYN_THREADS`` says otherwise (``MACHDYN_THREADS=1`` disables threading).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from itertools import pairwise

#: Arrays shorter than this are processed in the calling thread.
MIN_PARALLEL = 1 << 16

_CPUS = os.cpu_count() or 1
_pool: ThreadPoolExecutor | None = None
_pool_size = 0


def _forget_pool() -> None:
    """In a forked child the pool's threads do not exist: start a new pool when needed."""
    global _pool, _pool_size
    _pool, _pool_size = None, 0


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pool)


def threads() -> int:
    """Number of threads used for large arrays (``MACHDYN_THREADS`` or the CPU count)."""
    value = os.environ.get("MACHDYN_THREADS")
    if value:
        try:
            return max(1, int(value))
        except ValueError:
            return 1
    return _CPUS


def for_slices(kernel: Callable[[slice], None], n: int) -> None:
    """Call ``kernel(slice)`` over ``range(n)``, split across threads when ``n`` is large.

    ``kernel`` must write its results into preallocated arrays, each slice
    touching only its own elements.
    """
    global _pool, _pool_size
    workers = threads()
    if workers == 1 or n < MIN_PARALLEL:
        kernel(slice(0, n))
        return
    if _pool is None or _pool_size != workers:
        _pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="machdyn")
        _pool_size = workers
    bounds = [n * k // workers for k in range(workers + 1)]
    futures = [_pool.submit(kernel, slice(lo, hi)) for lo, hi in pairwise(bounds)]
    for future in futures:
        future.result()
