"""numba's on-disk cache, safe when several processes compile machdyn's kernels at once.

Every compiled kernel module imports :func:`njit` from here instead of from
numba. With ``cache=True`` numba keeps each kernel's compiled signatures in an
index file beside numbered data files, and it updates the index by
read-modify-write without a lock between processes (numba issues #4807 and
#10128). Two processes compiling two signatures of one kernel at the same time,
as pytest-xdist workers or a Dask ``LocalCluster``'s worker processes do on a
fresh install, can each give their signature the same data file: the index then
sends one signature to the other's machine code, and numba loads it without a
check. For a kernel with an optional argument that is a silently wrong answer
(``point=None``'s code run for a coupler point), not a crash; the same race once
failed machdyn's CI with numba's "no compiled object yet".

:func:`njit` therefore returns numba's own dispatcher with two changes to its
cache, nothing else:

- loading and saving an entry hold an exclusive lock on a file in the cache's
  directory (``filelock``: ``fcntl`` on POSIX, ``msvcrt`` on Windows), so that
  the index and the data file one process reads are the pair another wrote;
- a loaded entry whose argument types are not the ones asked for is refused
  (compiled afresh and saved again), so that an index written before the lock,
  or by hand, can cost time but never give a wrong kernel.

A cache that cannot be locked (a read-only directory) is used without the lock,
as numba itself would; a failed write only means the next process compiles
again.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

import numba
from filelock import FileLock, Timeout
from numba.core import sigutils

__all__ = ["LOCK_NAME", "LOCK_SECONDS", "njit"]

#: The lock file's name in each cache directory.
LOCK_NAME = "machdyn-numba-cache.lock"
#: Longest wait for another process's cache read or write (they take milliseconds);
#: past it the cache is skipped for that call (compiled, not loaded or saved).
LOCK_SECONDS = 60.0


def njit(**options: Any) -> Callable[[Callable[..., Any]], Any]:
    """``numba.njit(**options)``, with the cache guarded as the module says when ``cache=True``.

    Examples
    --------
    >>> from machdyn._numba_cache import njit
    >>> @njit(nogil=True)
    ... def twice(x):
    ...     return 2.0 * x
    >>> twice(1.5)
    3.0
    """
    decorate = numba.njit(**options)
    if not options.get("cache"):
        return decorate

    def guarded(function: Callable[..., Any]) -> Any:
        dispatcher = decorate(function)
        _guard(dispatcher._cache)
        return dispatcher

    return guarded


def _guard(cache: Any) -> None:
    """Put the lock and the signature check around ``cache``'s load and save."""
    load, save = cache.load_overload, cache.save_overload
    lock = FileLock(os.path.join(cache.cache_path, LOCK_NAME), timeout=LOCK_SECONDS)

    def load_overload(sig: Any, target_context: Any) -> Any:
        with _held(lock) as held:
            if not held:
                return None
            result = load(sig, target_context)
        if result is not None and tuple(result.signature.args) != _arguments(sig):
            return None  # another signature's code under this one's key: compile afresh
        return result

    def save_overload(sig: Any, data: Any) -> None:
        with _held(lock) as held:
            if held:
                save(sig, data)

    cache.load_overload, cache.save_overload = load_overload, save_overload


def _arguments(sig: Any) -> tuple[Any, ...]:
    """The argument types of a signature as numba's dispatcher passes it to the cache."""
    args, _ = sigutils.normalize_signature(sig)
    return tuple(args)


class _held:
    """Hold ``lock`` for a ``with`` block; ``as`` gives whether it is held.

    Not held when the lock file cannot be created (a read-only cache directory: the
    cache is then used unlocked, as numba would) — True — or when another process
    holds it past :data:`LOCK_SECONDS` (the cache is skipped) — False.
    """

    def __init__(self, lock: FileLock) -> None:
        self._lock = lock
        self._acquired = False

    def __enter__(self) -> bool:
        try:
            os.makedirs(os.path.dirname(self._lock.lock_file), exist_ok=True)
            self._lock.acquire()
        except Timeout:
            return False
        except OSError:  # cannot create the lock file: numba's own behaviour, unlocked
            return True
        self._acquired = True
        return True

    def __exit__(self, *exc: object) -> None:
        if self._acquired:
            self._lock.release()
