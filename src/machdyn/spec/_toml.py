"""Writing a spec dict as TOML (machdyn writes the small subset its files use).

Scalars and arrays of scalars are written as ``key = value``; a table of
scalars only as an inline table when short; other tables as ``[a.b]``
sections and arrays of tables as ``[[a.b]]``.
"""

from __future__ import annotations

import json
import math
from typing import Any

from ._context import toml_key

__all__ = ["dumps"]

_INLINE_WIDTH = 80


def _scalar(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        if abs(value) >= 2**63:
            raise ValueError(f"{value} is too large for a TOML integer")
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"cannot write the non-finite number {value!r}")
        text = repr(value)
        return text if any(c in text for c in ".en") else text + ".0"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(_scalar(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{toml_key(k)} = {_scalar(v)}" for k, v in value.items()) + " }"
    raise TypeError(f"cannot write {type(value).__name__} {value!r} as TOML")


def _is_table_list(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def _nested(value: dict) -> bool:
    return any(isinstance(v, dict) or _is_table_list(v) for v in value.values())


def _inline(key: str, value: Any) -> bool:
    """A small table of scalars goes on one line."""
    if not isinstance(value, dict) or _nested(value) or not value:
        return False
    return len(_scalar(value)) + len(key) < _INLINE_WIDTH


def _section(out: list[str], path: list[str], table: dict) -> None:
    tables = [k for k, v in table.items() if isinstance(v, dict)]
    # Inline tables only when every sub-table of this one fits on a line: a
    # section written after the body would otherwise come out of order.
    inline = bool(path) and all(_inline(toml_key(k), table[k]) for k in tables)
    body = []
    for key, value in table.items():
        if (isinstance(value, dict) and not inline) or _is_table_list(value):
            continue
        body.append(f"{toml_key(key)} = {_scalar(value)}")
    if body or not tables:
        if path:
            out.append(f"\n[{'.'.join(toml_key(p) for p in path)}]")
        out.extend(body)
    for key, value in table.items():
        if isinstance(value, dict) and not inline:
            _section(out, [*path, key], value)
        elif _is_table_list(value):
            for item in value:
                out.append(f"\n[[{'.'.join(toml_key(p) for p in [*path, key])}]]")
                for k, v in item.items():
                    if isinstance(v, dict | list) and (_nested({0: v}) or _is_table_list(v)):
                        raise ValueError(f"nested tables in [[{key}]] are not written")
                    out.append(f"{toml_key(k)} = {_scalar(v)}")


def dumps(spec: dict) -> str:
    """A spec dict as TOML text (``machdyn = 1`` first).

    Examples
    --------
    >>> print(dumps({"machdyn": 1, "fourbar": {"hw6": {"r1": 8.0, "coupler": {"p": 5.0}}}}))
    machdyn = 1
    <BLANKLINE>
    [fourbar.hw6]
    r1 = 8.0
    coupler = { p = 5.0 }
    <BLANKLINE>
    """
    from ..errors import InputError

    if not isinstance(spec, dict):
        raise InputError("spec", f"expected a spec dict (a model's to_spec()), got {spec!r}")
    out: list[str] = []
    try:
        _section(out, [], spec)
    except (TypeError, ValueError) as exc:
        raise InputError("spec", str(exc)) from None
    return "\n".join(out).lstrip("\n") + "\n"
