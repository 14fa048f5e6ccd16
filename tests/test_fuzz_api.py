"""Every public callable × a catalogue of bad values: a machdyn error or a checked answer.

The public API is walked from the modules' ``__all__`` (and the public methods of
its classes), so a new function is fuzzed as soon as it is exported: it needs a
valid call in tests/fuzz_catalogue.py, or this file fails. Each argument of each
call is replaced in turn by each value of ``fuzz_support.BAD`` (None, text, NaN,
±inf, 0, −1, 1e308, 5e-324, 10**400, a complex number, a bool, empty, ragged and
2-d arrays, a pint quantity in seconds, an arbitrary object). The call must then

* raise a :class:`machdyn.MachdynError` (an ``InputError`` naming the argument), or
* return a result that passes :func:`fuzz_support.verdict`: a value no numeric
  argument may take (None, text, complex, bool, ragged, seconds, …) was not
  accepted; NaN or ±inf was accepted only with samples flagged (``ok`` False, a
  ``status`` or ``reason``); no non-finite number hides in an unflagged result;
  and the entry's own independent check holds where it has one.

NumPy RuntimeWarnings count as failures (a warning is how garbage leaks out).
"""

from __future__ import annotations

import collections
import os

import pytest

from fuzz_catalogue import catalogue
from fuzz_support import BAD, parameters, public_callables, run_case

CATALOGUE = catalogue()


@pytest.fixture(autouse=True)
def _numpy_path():
    """Fuzz the validation on the NumPy path, as conftest sets it, before and after every
    test: fuzzing ``jit.set_mode`` itself (``None`` is a valid value: "read MACHDYN_JIT")
    would otherwise leave ``auto`` on, and a first kernel compile (a minute on a loaded
    machine) would run past a call's time limit. Both paths share the validation."""
    from machdyn import jit

    jit.set_mode("off")
    yield
    jit.set_mode("off")


@pytest.fixture(scope="module", autouse=True)
def _kernels_compiled():
    """``jit.load`` compiles numba's kernels the first time after a checkout (a minute on
    a loaded 2-core machine; CI once timed out ``machdyn.jit:load`` this way): load them
    here, outside the fuzzed calls' time limit, so that the catalogue's ``jit.load`` call
    times the call and not the compiler."""
    from machdyn import jit

    jit.load()


#: Callables whose bad-input cases are not all clean yet (issue #17 in progress).
PENDING: set[str] = set()


def test_every_public_callable_is_catalogued():
    public = public_callables()
    missing = sorted(set(public) - set(CATALOGUE))
    assert not missing, f"add a valid call of each to tests/fuzz_catalogue.py: {missing}"
    stale = sorted(set(CATALOGUE) - set(public))
    assert not stale, f"no longer public, drop from tests/fuzz_catalogue.py: {stale}"


@pytest.mark.parametrize("key", sorted(CATALOGUE))
def test_bad_inputs(key):
    call = CATALOGUE[key]
    outcome, detail = run_case(key, call, None, None)
    assert outcome == "accepted", f"the catalogue's valid call fails: {outcome} {detail}"
    if key in PENDING and not os.environ.get("HARDEN_NO_PENDING"):
        pytest.skip("bad-input handling not finished (issue #17)")
    problems = []
    counts: collections.Counter[str] = collections.Counter()
    for name, _ in parameters(key, call):
        for bad in BAD:
            outcome, detail = run_case(key, call, name, bad)
            counts[outcome] += 1
            if outcome in ("foreign", "silent"):
                problems.append(f"{name}={bad}: {outcome}: {detail}")
    assert not problems, "\n".join(problems)
