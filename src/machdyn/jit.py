"""When the four-bar's closed form runs compiled (numba) instead of in NumPy.

The compiled kernels in :mod:`machdyn._kernels` are 2–5 times faster than the
NumPy path, but loading them costs about half a second per process (importing
numba and reading the compiled code from its on-disk cache; the very first
time after installation they are compiled, a few seconds once). So a short
script or a single CLI call never pays for them, and a long sweep never goes
without them, the default (``auto``) is the ski-rental rule: NumPy serves every
call until the NumPy kernels have spent as much time as loading would cost
(:data:`BUDGET`), then the compiled kernels are loaded and serve every later
call. That is never more than twice as slow as knowing the future.

The environment variable ``MACHDYN_JIT`` chooses: ``auto`` (the default),
``on`` (load at the first call) or ``off`` (NumPy only). :func:`load` loads
now, e.g. before timing something. Both paths give the same numbers to a few
units in the last place (the tests compare them sample by sample).

Examples
--------
>>> from machdyn import jit
>>> jit.mode() in ("auto", "on", "off")
True
"""

from __future__ import annotations

import os
import threading
import warnings
from types import ModuleType

__all__ = ["BUDGET", "active", "kernels", "load", "mode", "reason", "set_mode"]

#: Seconds of NumPy kernel time after which ``auto`` loads the compiled kernels
#: (about what loading them costs on the project's machine).
BUDGET = 0.5

_MODES = ("auto", "on", "off")
_ALIASES = {"1": "on", "true": "on", "yes": "on", "0": "off", "false": "off", "no": "off"}

_lock = threading.Lock()
_kernels: ModuleType | None = None
_failure = ""  # why loading failed, once it has
_spent = 0.0
_mode: str | None = None  # None: read MACHDYN_JIT


def mode() -> str:
    """The current mode: ``"auto"``, ``"on"`` or ``"off"``."""
    if _mode is not None:
        return _mode
    value = os.environ.get("MACHDYN_JIT", "auto").strip().lower()
    value = _ALIASES.get(value, value)
    return value if value in _MODES else "auto"


def set_mode(value: str) -> None:
    """Override ``MACHDYN_JIT`` for this process (``"auto"``, ``"on"`` or ``"off"``).

    Examples
    --------
    >>> from machdyn import jit
    >>> jit.set_mode("fast")
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: mode: must be one of auto, on, off; got 'fast'
    """
    from ._validate import choice

    global _mode
    _mode = choice("mode", value, _MODES)


def active() -> bool:
    """Whether the compiled kernels serve calls now (loaded and not switched off)."""
    return _kernels is not None and mode() != "off"


def reason() -> str:
    """Why the compiled kernels are not available (empty if they are or were never tried)."""
    return _failure


def load() -> bool:
    """Load (compiling the first time) the compiled kernels now; True if they are available.

    Never raises: if numba cannot be imported or compiled, the NumPy path
    stays in use and :func:`reason` says why.
    """
    global _kernels, _failure
    with _lock:
        if _kernels is not None:
            return True
        if _failure:
            return False
        try:
            from . import _kernels as module

            module.warm_up()
        except Exception as exc:  # any failure of an optional accelerator: stay on NumPy
            _failure = f"{type(exc).__name__}: {exc}"
            return False
        _kernels = module
        return True


def kernels() -> ModuleType | None:
    """The compiled kernels if they should serve the next call, else None (use NumPy)."""
    if _kernels is not None:
        return _kernels if mode() != "off" else None
    current = mode()
    if current == "off" or _failure:
        return None
    if current == "on" or _spent >= BUDGET:
        if not load() and current == "on":
            warnings.warn(
                f"MACHDYN_JIT=on but the compiled kernels are unavailable ({_failure}); "
                "using NumPy",
                RuntimeWarning,
                stacklevel=3,
            )
        return _kernels
    return None


def charge(seconds: float) -> None:
    """Record time spent in the NumPy kernels (the ``auto`` rule's meter)."""
    global _spent
    _spent += seconds
