"""When the four-bar's closed form runs compiled (numba) instead of in NumPy.

The compiled kernels in :mod:`machdyn._kernels` are 2–5 times faster than the
NumPy path, but loading them costs about half a second per process (importing
numba and reading the compiled code from its on-disk cache; the very first
time after installation they are compiled, a few seconds once). So that a
short script or a single CLI call never pays for them, and a long sweep never
goes without them, the default (``auto``) is the ski-rental rule: NumPy serves
the calls until the time NumPy has spent, counting the call about to be made
(estimated at :data:`NUMPY_SECONDS_PER_POSE`), reaches what loading costs
(:data:`BUDGET`); then the compiled kernels are loaded and serve every later
call. Once numba's cache exists that is never much more than twice as slow as
knowing the future.

The environment variable ``MACHDYN_JIT`` chooses: ``auto`` (the default),
``on`` (load at the first call) or ``off`` (NumPy only); :func:`set_mode`
overrides it for the process. :func:`load` loads now, e.g. before timing
something. Both paths give the same numbers up to rounding, not the same bits:
the compiled kernels carry their own sin, cos and atan2 (polynomials within 2
ulp of libm's, so that the loops vectorise). The difference is bounded by the
pose's conditioning: with ``κ = (longest link / shortest link) / |sin(θ3 − θ4)|``,
angles and points agree to ``1e-14 κ`` (points relative to their size) and
rates to ``1e-14 κ²``; a few units in the last place away from toggles, more
only next to one, where the pose itself is ill-conditioned (tests/test_jit.py
checks this bound sample by sample, and runs every four-bar test on both paths).

Under ``auto`` the same call may therefore differ in its last bits before and
after the switch. For bit-for-bit reproducible results choose one path for the
whole process: ``MACHDYN_JIT=off`` (NumPy, identical on every machine with the
same NumPy and libm) or ``MACHDYN_JIT=on`` (compiled from the first call; NumPy
throughout if numba is unavailable).

Loading sets two of LLVM's process-wide options (how many run-time alias
checks the loop vectoriser may emit; see :mod:`machdyn._kernels`): other numba
code compiled later in the same process sees them too.

Examples
--------
>>> from machdyn import jit
>>> jit.mode() in ("auto", "on", "off")
True
"""

from __future__ import annotations

import os
import sys
import threading
import warnings
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

__all__ = ["BUDGET", "NUMPY_SECONDS_PER_POSE", "active", "load", "mode", "reason", "set_mode"]

#: Seconds of NumPy kernel time after which ``auto`` loads the compiled kernels
#: (about what loading them from numba's cache costs on the project's machine).
BUDGET = 0.5
#: A low estimate of the NumPy path's cost per pose (it runs at 6–16 M poses/s on
#: the project's machine), used to count a call before it is made.
NUMPY_SECONDS_PER_POSE = 5e-8

_MODES = ("auto", "on", "off")
_ALIASES = {"1": "on", "true": "on", "yes": "on", "0": "off", "false": "off", "no": "off"}
_PACKAGE = str(Path(__file__).resolve().parent)

_lock = threading.Lock()
_kernels: ModuleType | None = None
_failure = ""  # why the compiled kernels are unavailable, once they are
_spent = 0.0
_mode: str | None = None  # None: read MACHDYN_JIT
_warned_env = ""
_env = ("", "auto")  # the last MACHDYN_JIT read and what it means (parsed once per value)


def mode() -> str:
    """The current mode: ``"auto"``, ``"on"`` or ``"off"``."""
    global _warned_env, _env
    if _mode is not None:
        return _mode
    raw = os.environ.get("MACHDYN_JIT", "")
    if raw == _env[0]:
        return _env[1]
    value = raw.strip().lower() or "auto"
    value = _ALIASES.get(value, value)
    if value in _MODES:
        _env = (raw, value)
        return value
    if raw != _warned_env:  # once per distinct bad value
        _warned_env = raw
        _warn(f"MACHDYN_JIT={raw!r} is not one of auto, on, off (or 1, 0); using auto")
    return "auto"


def set_mode(value: str | None) -> None:
    """Override ``MACHDYN_JIT`` for this process; ``None`` goes back to the variable.

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
    _mode = None if value is None else choice("mode", value, _MODES)


def active() -> bool:
    """Whether the compiled kernels serve calls now (loaded and not switched off)."""
    return _kernels is not None and mode() != "off"


def reason() -> str:
    """Why the compiled kernels are unavailable (empty if they are, or were never tried)."""
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

            warm(module)
        except Exception as exc:  # any failure of an optional accelerator: stay on NumPy
            _failure = f"{type(exc).__name__}: {exc}"
            return False
        _kernels = module
        return True


def warm(module: ModuleType) -> None:
    """Call a compiled module's ``warm_up()``; once more if numba raised a RuntimeError.

    numba adds a freshly compiled kernel to its dispatcher before it writes the
    on-disk cache, so a failure of the write (CI once saw numba's "no compiled
    object yet" with two processes compiling into one fresh cache; see
    :mod:`machdyn._numba_cache`) leaves the kernel usable in this process: the
    second call finds it compiled. A real fault fails twice and is raised.
    """
    try:
        module.warm_up()
    except RuntimeError:
        module.warm_up()


def kernels(poses: int) -> ModuleType | None:
    """The compiled kernels if they should serve a call of ``poses`` poses, else None."""
    if _kernels is not None:
        return _kernels if mode() != "off" else None
    current = mode()
    if current == "off" or _failure:
        return None
    if current == "on" or _spent + poses * NUMPY_SECONDS_PER_POSE >= BUDGET:
        if not load() and current == "on":
            _warn(
                f"MACHDYN_JIT=on but the compiled kernels are unavailable ({_failure}); using NumPy"
            )
        return _kernels
    return None


def run(kernel: Callable[[slice], int | None], n: int) -> bool:
    """Run a compiled kernel over ``range(n)`` in slices (threads for large n).

    Returns False if NumPy must redo the call: a kernel returned a nonzero count
    (inputs beyond its range), or raised. A kernel that raises (it should not:
    the test suite runs the four-bar tests on both paths) switches the compiled
    path off with one warning, and NumPy serves this and every later call.
    """
    from ._parallel import for_slices

    results: list[int | None] = []
    try:
        for_slices(lambda sl: results.append(kernel(sl)), n)
    except Exception as exc:  # anything from numba: NumPy is the reference path
        fail(exc)
        return False
    return not any(results)


def charge(seconds: float) -> None:
    """Record time spent in the NumPy kernels (the ``auto`` rule's meter)."""
    global _spent
    _spent += seconds


def fail(exc: BaseException) -> None:
    """A compiled kernel raised: switch the compiled path off for the process and say so."""
    global _kernels, _failure
    with _lock:
        _kernels = None
        _failure = f"{type(exc).__name__}: {exc}"
    _warn(f"a compiled four-bar kernel failed ({_failure}); NumPy serves from now on")


def _warn(message: str) -> None:
    """Warn, attributed to the first caller outside machdyn (the user's line)."""
    frame, level = sys._getframe(1), 2  # stacklevel 2: _warn's caller
    while frame is not None and str(Path(frame.f_code.co_filename).resolve()).startswith(_PACKAGE):
        frame, level = frame.f_back, level + 1
    warnings.warn(message, RuntimeWarning, stacklevel=level)


def _after_fork_in_child() -> None:
    global _lock
    _lock = threading.Lock()  # a fork during load() must not leave it held


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork_in_child)
