"""Parsing and printing helpers shared by the CLI modules (no physics here)."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["dumps", "parse_range_deg", "print_table"]


def parse_range_deg(text: str, field: str = "--theta2") -> np.ndarray:
    """Parse ``START:STOP:STEP`` (degrees, STOP included when on the grid) or one value.

    Examples
    --------
    >>> parse_range_deg("0:90:15").tolist()
    [0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0]
    >>> parse_range_deg("30").tolist()
    [30.0]
    """
    parts = text.split(":")
    try:
        numbers = [float(p) for p in parts]
    except ValueError:
        raise InputError(
            field, f"expected START:STOP:STEP in degrees or one angle, got {text!r}"
        ) from None
    if len(numbers) == 1:
        return np.array(numbers)
    if len(numbers) != 3:
        raise InputError(field, f"expected START:STOP:STEP in degrees or one angle, got {text!r}")
    start, stop, step = numbers
    if not all(math.isfinite(v) for v in numbers):
        raise InputError(field, f"values must be finite, got {text!r}")
    if step == 0 or (stop - start) / step < 0:
        raise InputError(field, f"STEP must be non-zero and point from START to STOP, got {text!r}")
    count = math.floor((stop - start) / step + 1e-9) + 1
    if count > 1_000_000:
        raise InputError(field, f"{count} samples requested; at most 1,000,000 are printed")
    return start + step * np.arange(count)


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return [_jsonable(v) for v in value.tolist()]
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    if isinstance(value, complex):
        return {"x": _jsonable(value.real), "y": _jsonable(value.imag)}
    if isinstance(value, float | np.floating):
        value = float(value)
        return value if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    return value


def dumps(payload: Any) -> str:
    """Serialise results to JSON: arrays as lists, complex as {x, y}, non-finite as null."""
    return json.dumps(_jsonable(payload), indent=2, allow_nan=False)


#: Longer tables are printed as plain aligned text: rich lays a table out at about a
#: millisecond per row (a 3,600-row sweep took seconds), plain text at microseconds.
RICH_ROWS = 200


def print_table(
    title: str, columns: Sequence[str], rows: Sequence[Sequence[Any]], plain: bool = False
) -> None:
    """Print a right-aligned table with rich (plain text when not a terminal, or long).

    Examples
    --------
    >>> print_table("t", ["a", "b"], [[1.0, "x"]] * 201)  # doctest: +ELLIPSIS
    t
         a  b
    1.0000  x
    ...
    """
    if plain or len(rows) > RICH_ROWS:
        cells = [[_cell(v) for v in row] for row in rows]
        widths = [max([len(c), *(len(r[k]) for r in cells)]) for k, c in enumerate(columns)]
        lines = [title, "  ".join(c.rjust(w) for c, w in zip(columns, widths, strict=True))]
        lines += ["  ".join(v.rjust(w) for v, w in zip(r, widths, strict=True)) for r in cells]
        print("\n".join(lines))
        return
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    # escape: a unit in brackets ("theta3 [deg]") is not rich markup
    table = Table(title=escape(title), title_justify="left", box=None, pad_edge=False)
    for name in columns:
        table.add_column(escape(name), justify="right")
    for row in rows:
        table.add_row(*(escape(_cell(v)) for v in row))
    Console(width=max(100, 12 * len(columns))).print(table)


def _cell(value: Any) -> str:
    if isinstance(value, str):
        return value
    if value is None:
        return "-"
    if isinstance(value, float | np.floating):
        if not math.isfinite(value):
            return "-"
        return f"{round(float(value), 4) + 0.0:.4f}"  # + 0.0: never print "-0.0000"
    return str(value)
