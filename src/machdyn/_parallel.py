"""Run a vectorised kernel over slices of a large array on a few threads; the memory budget.

NumPy releases the GIL inside its ufuncs, so contiguous slices of one array can
be processed concurrently in one process. Small arrays run inline: below
:data:`MIN_PARALLEL` samples the thread hand-off costs more than it saves.

The number of threads is ``os.cpu_count()`` unless the environment variable
``MACHDYN_THREADS`` says otherwise (``MACHDYN_THREADS=1`` disables threading).

A request whose arrays would not fit the memory budget is refused before any
work, with the size it needs (:func:`require_memory`): half the machine's
memory unless ``MACHDYN_MEMORY_LIMIT`` says otherwise (bytes, or with a unit:
``8G``, ``500M``; or a fraction of the machine's memory: ``0.25``).
"""

from __future__ import annotations

import os
import re
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


def for_slices(kernel: Callable[[slice], None], n: int, minimum: int = MIN_PARALLEL) -> None:
    """Call ``kernel(slice)`` over ``range(n)``, split across threads when ``n`` is large.

    ``kernel`` must write its results into preallocated arrays, each slice
    touching only its own elements. ``minimum``: the least ``n`` worth threads
    (for a kernel whose items each cost much more than a sample's).
    """
    global _pool, _pool_size
    workers = threads()
    if workers == 1 or n < minimum:
        kernel(slice(0, n))
        return
    if _pool is None or _pool_size != workers:
        _pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="machdyn")
        _pool_size = workers
    bounds = [n * k // workers for k in range(workers + 1)]
    futures = [_pool.submit(kernel, slice(lo, hi)) for lo, hi in pairwise(bounds)]
    for future in futures:
        future.result()


#: Default memory budget, as a fraction of the machine's physical memory.
MEMORY_FRACTION = 0.5
_UNITS = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}


_blas = None  # threadpoolctl's controller: the BLAS libraries loaded, found once


def one_blas_thread(fn: Callable) -> Callable:
    """``fn`` with the BLAS libraries (numpy's and scipy's OpenBLAS) on one thread while it runs.

    For code that solves many small dense problems (the atlas synthesis's
    least-squares refinements: an SVD of an 84 × 49 Jacobian per step for 40
    targets): OpenBLAS splits such a matrix over its threads, and the hand-off
    costs more than it saves — on this 2-core machine under load, 38 ms of CPU
    per SVD instead of 0.5 ms on one thread. The limit is process-wide
    (threadpoolctl) and restored when ``fn`` returns.
    """
    import functools

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        global _blas
        if _blas is None:
            import scipy.linalg  # noqa: F401  (scipy's own OpenBLAS loaded, so the controller finds it)
            from threadpoolctl import ThreadpoolController

            _blas = ThreadpoolController()
        with _blas.limit(limits=1, user_api="blas"):
            return fn(*args, **kwargs)

    return wrapper


def physical_memory() -> int:
    """The machine's physical memory in bytes (8 GiB if the system does not say)."""
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, OSError, ValueError):
        return 8 * 2**30


def memory_limit() -> int:
    """The memory budget of one request in bytes (``MACHDYN_MEMORY_LIMIT``, see above).

    Examples
    --------
    >>> import os
    >>> os.environ["MACHDYN_MEMORY_LIMIT"] = "2G"
    >>> memory_limit()
    2147483648
    >>> del os.environ["MACHDYN_MEMORY_LIMIT"]
    """
    raw = os.environ.get("MACHDYN_MEMORY_LIMIT", "").strip()
    match = re.fullmatch(r"(\d+(?:\.\d*)?|\.\d+)\s*([KMGT]?)i?B?", raw.upper()) if raw else None
    if match is None:
        return int(MEMORY_FRACTION * physical_memory())
    number, unit = float(match.group(1)), match.group(2)
    if not unit and number <= 1.0:
        return int(number * physical_memory())  # a fraction of the machine
    return int(number * _UNITS[unit])


def format_bytes(n: float) -> str:
    """``n`` bytes for people: ``'1.5 GB'``.

    Examples
    --------
    >>> format_bytes(1.5 * 2**30)
    '1.5 GB'
    """
    n = min(float(n), 1e300) if n < 1e300 else 1e300  # a Python int may exceed the float range
    for unit, size in (("TB", 2**40), ("GB", 2**30), ("MB", 2**20), ("kB", 2**10)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{int(n)} bytes"


def require_memory(field: str, nbytes: float, what: str) -> None:
    """Refuse (:class:`~machdyn.errors.InputError` naming ``field``) a request over budget.

    Examples
    --------
    >>> require_memory("theta2", 10**18, "10^17 poses")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: theta2: 10^17 poses need about 9.09e+05 TB of memory, more ...
    """
    limit = memory_limit()
    if nbytes > limit:
        from .errors import InputError

        raise InputError(
            field,
            f"{what} need about {format_bytes(nbytes)} of memory, more than the "
            f"{format_bytes(limit)} allowed (MACHDYN_MEMORY_LIMIT); split the request "
            f"into smaller pieces or raise the limit",
        )
