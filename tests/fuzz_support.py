"""The machinery of the bad-input fuzzers: bad values, public callables, verdicts.

Used by tests/test_fuzz_api.py (and by hand: ``python -m tests.fuzz_support`` prints a
tally of every (callable, argument, bad value) case).
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import math
import signal
import warnings
from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np

from fuzz_catalogue import (
    METHODS_NOT_FUZZED,
    NOT_CALLED,
    NOT_FUZZED,
    Call,
    catalogue,
    public_modules,
)


def _seconds() -> Any:
    import pint

    return pint.UnitRegistry().Quantity(2.0, "second")


#: The bad values. Each is either refused with a machdyn error or, where the text says
#: "may", accepted with a result that passes the checks of :func:`verdict`.
BAD: dict[str, Any] = {
    "none": None,
    "text": "abc",
    "nan": math.nan,
    "inf": math.inf,
    "-inf": -math.inf,
    "zero": 0,
    "minus_one": -1,
    "huge": 1e308,
    "tiny": 5e-324,
    "bigint": 10**400,
    "complex": 1 + 1j,
    "bool": True,
    "empty": [],
    "ragged": [[1.0, 2.0], [3.0]],
    "matrix": np.ones((2, 2)),
    "seconds": _seconds(),
    "object": object(),
}

#: Values no numeric argument may accept (unless its annotation says so: a complex
#: argument takes 1 + 1j, an optional one None, a flag True, a name "abc").
STRICT = {"none", "text", "bigint", "complex", "bool", "ragged", "seconds", "object"}
#: Non-finite values: refused, or accepted only with samples flagged in the result.
NONFINITE = {"nan", "inf", "-inf"}

FLAG_NAMES = ("ok", "valid", "assembled", "status", "in_loop", "reason")


def public_callables() -> dict[str, Any]:
    """Every public function, class and public method, by ``"module:Qualname"``."""
    found: dict[int, str] = {}
    objects: dict[str, Any] = {}
    for module_name in public_modules():  # the shortest public path of each object wins
        module = importlib.import_module(module_name)
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.ismodule(obj) or not callable(obj) or id(obj) in found:
                continue
            if inspect.isclass(obj) and issubclass(obj, BaseException):
                continue
            key = f"{module_name}:{name}"
            found[id(obj)] = key
            objects[key] = obj
    out = {}
    for key, obj in objects.items():
        if key not in NOT_CALLED and key not in NOT_FUZZED:
            out[key] = obj
        if inspect.isclass(obj):
            own: dict[str, Any] = {}
            for base in reversed(obj.__mro__):  # methods of machdyn's own classes and mixins
                if base.__module__.startswith("machdyn"):
                    own.update(vars(base))
            for attr, raw in own.items():
                if attr.startswith("_") or attr in METHODS_NOT_FUZZED:
                    continue
                if isinstance(raw, property) or not (
                    callable(raw) or isinstance(raw, staticmethod | classmethod)
                ):
                    continue
                out[f"{key}.{attr}"] = getattr(obj, attr)
    return out


def parameters(key: str, call: Call) -> Iterator[tuple[str, inspect.Parameter | None]]:
    """The fuzzed arguments of a call: its named parameters (and ``*args`` items)."""
    target = call.target()
    try:
        sig = inspect.signature(target)
    except (TypeError, ValueError):
        return
    positional = list(call.args)
    for name, p in sig.parameters.items():
        if name in call.skip:
            continue
        if p.kind is p.VAR_KEYWORD:
            continue
        if p.kind is p.VAR_POSITIONAL:
            for i in range(len(positional)):
                yield f"*{i}", p
            continue
        if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD) and positional:
            positional.pop(0)
            yield f"#{name}", p  # passed positionally
            continue
        yield name, p


def arguments(call: Call, name: str | None, value: Any) -> tuple[tuple, dict]:
    """The call's arguments with one replaced (``name`` None: unchanged)."""
    args, kwargs = list(call.args), dict(call.kwargs)
    if name is None:
        return tuple(args), kwargs
    if name.startswith("*"):
        args[int(name[1:])] = value
    elif name.startswith("#"):
        target = call.target()
        names = [
            n
            for n, p in inspect.signature(target).parameters.items()
            if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)
        ]
        args[names.index(name[1:])] = value
    else:
        kwargs[name] = value
    return tuple(args), kwargs


def allowed(call: Call, name: str, p: inspect.Parameter | None) -> set[str]:
    """Bad-value names that this parameter may accept (its annotation or the catalogue)."""
    out = set(call.accepts.get(name.lstrip("#"), ()))
    if p is None:
        return out
    note = str(p.annotation).replace(" ", "")
    if p.default is None or "None" in note.split("|"):
        out.add("none")
    if "complex" in note:
        out.add("complex")
    if note == "bool" or note.startswith("bool|"):
        out.add("bool")
    if note.startswith("str") or "|str" in note:
        out.add("text")
    return out


class CallTimeout(BaseException):
    """A fuzzed call ran past its time limit (a BaseException, so that no ``except
    Exception`` in machdyn, such as the jit's fallback, takes it for its own failure)."""


def _alarm(signum, frame):  # pragma: no cover - signal handler
    raise CallTimeout


#: A fuzzed call's time limit: it catches a bad value that makes a call hang, and is far
#: above any call's time on a quiet machine (the slowest take a few seconds) because the
#: suite also runs on loaded 2-core machines, where 10 s timed out valid calls.
CALL_SECONDS = 30.0


def invoke(call: Call, name: str | None, value: Any, seconds: float = CALL_SECONDS) -> Any:
    """Call with one argument replaced; exceptions propagate."""
    args, kwargs = arguments(call, name, value)
    target = call.target()
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a warning is how garbage leaks out
            return target(*args, **kwargs)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _walk(value: Any, depth: int = 0) -> Iterator[tuple[str, Any]]:
    """(name, leaf) pairs of a result: arrays and numbers inside records and mappings."""
    if depth > 4:
        return
    if isinstance(value, np.ndarray | float | complex | np.number):
        yield "", value
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        for f in dataclasses.fields(value):
            for sub, leaf in _walk(getattr(value, f.name), depth + 1):
                yield f"{f.name}.{sub}".rstrip("."), leaf
    elif isinstance(value, Mapping):
        for k, v in list(value.items())[:200]:
            for sub, leaf in _walk(v, depth + 1):
                yield f"{k}.{sub}".rstrip("."), leaf
    elif isinstance(value, tuple | list):
        for i, v in enumerate(value[:200]):
            for sub, leaf in _walk(v, depth + 1):
                yield f"{i}.{sub}".rstrip("."), leaf


def _flagged(result: Any) -> bool:
    """Whether the result flags at least one sample (ok False, status nonzero, ...)."""
    if isinstance(result, tuple):  # (…, ok) as positions() returns
        for item in result:
            arr = np.asarray(item) if isinstance(item, np.ndarray | bool | np.bool_) else None
            if arr is not None and arr.dtype.kind == "b" and not np.all(arr):
                return True
    for name in FLAG_NAMES:
        flag = getattr(result, name, None)
        if flag is None or callable(flag):
            continue
        arr = np.asarray(flag)
        if name == "reason":
            if arr.dtype.kind in "US" and np.any(arr != ""):
                return True
            continue
        if name == "status" and arr.dtype.kind in "iu":
            if np.any(arr != 0):
                return True
        elif arr.dtype.kind == "b" and not np.all(arr):
            return True
    return False


def nonfinite(result: Any) -> str:
    """The name of a non-finite number in the result ('' if all are finite)."""
    for name, leaf in _walk(result):
        arr = np.asarray(leaf)
        if arr.dtype.kind in "fc" and not np.all(np.isfinite(arr)):
            return name or "result"
    return ""


def verdict(key: str, call: Call, name: str | None, bad: str | None, result: Any) -> str:
    """'' if an accepted call's result is right; otherwise what is wrong with it."""
    p = None
    if name is not None:
        p = dict(parameters(key, call)).get(name)
    valid_here = bad is not None and bad in allowed(call, name or "", p)
    if bad is not None and bad in STRICT and not valid_here:
        return f"accepted {bad}"
    flagged = _flagged(result)
    if bad in NONFINITE and not flagged and not valid_here:
        return f"accepted {bad} with no sample flagged"
    where = nonfinite(result)
    passed_on = bad in NONFINITE and valid_here  # NaN in, NaN out (documented)
    if where and not flagged and not call.nonfinite and not passed_on:
        return f"non-finite {where} with no sample flagged"
    if call.check is not None:
        try:
            call.check(result, arguments(call, name, BAD.get(bad))[1])
        except AssertionError as exc:
            return f"check failed: {exc}"
    return ""


def run_case(key: str, call: Call, name: str | None, bad: str | None) -> tuple[str, str]:
    """(outcome, detail): outcome is 'refused', 'accepted', 'foreign' or 'silent'."""
    from machdyn.errors import MachdynError

    value = BAD[bad] if bad is not None else None
    try:
        result = invoke(call, name, value)
    except MachdynError as exc:
        return "refused", str(exc)
    except CallTimeout:
        return "foreign", "timed out"
    except Exception as exc:
        return "foreign", f"{type(exc).__name__}: {exc}"[:300]
    problem = verdict(key, call, name, bad, result)
    return ("silent", problem) if problem else ("accepted", "")


def tally(keys: list[str] | None = None, verbose: bool = True) -> dict[str, int]:
    """Run every case; print the ones that fail."""
    import collections

    cat = catalogue()
    counts: collections.Counter[str] = collections.Counter()
    chosen = [k for k in sorted(cat) if not keys or any(k.startswith(p) for p in keys)]
    for key in chosen:
        call = cat[key]
        outcome, detail = run_case(key, call, None, None)
        if outcome != "accepted":
            print(f"BASELINE {key}: {outcome} {detail}")
            continue
        for name, _ in parameters(key, call):
            for bad in BAD:
                outcome, detail = run_case(key, call, name, bad)
                counts[outcome] += 1
                if verbose and outcome in ("foreign", "silent"):
                    print(f"{outcome:7} {key} {name}={bad}: {detail}")
    return dict(counts)


if __name__ == "__main__":  # pragma: no cover
    import sys

    print(tally(sys.argv[1:] or None))
