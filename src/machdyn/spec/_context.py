"""Reading state shared by every part reader: the source, its lines, the unit system.

Errors are :class:`SpecError` (an :class:`~machdyn.errors.InputError`) whose
field says where: ``press.toml:14: [fourbar.press] r3``.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from .. import units as u
from ..errors import InputError, MachdynError
from ._lines import KeyLines

__all__ = ["Context", "SpecError", "field_name", "toml_key"]

#: Largest magnitude accepted for a number in a file's own units.
HUGE = 1e15
_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


class SpecError(InputError):
    """A machine file (or spec dict) that cannot be read: names file, line and key.

    Attributes
    ----------
    path : tuple
        The key path in the document (``("fourbar", "hw6", "r1")``).
    line : int or None
        The line of that key in the TOML file, when known.

    Examples
    --------
    >>> str(SpecError("hw6.toml", 12, ("fourbar", "hw6", "r1"), "must be positive"))
    'hw6.toml:12: [fourbar.hw6] r1: must be positive'
    """

    def __init__(
        self, source: str | None, line: int | None, path: tuple, message: str, table: bool = False
    ) -> None:
        self.path = tuple(path)
        self.line = line
        self.source = source
        where = "" if source is None else (f"{source}:{line}: " if line else f"{source}: ")
        name = f"[{_join(self.path)}]" if table and self.path else field_name(self.path)
        if not self.path:  # the document as a whole
            super().__init__(where.rstrip(": ") or "machine file", message)
            return
        super().__init__(where + name, message)


def toml_key(key: Any) -> str:
    """A key as TOML writes it: bare when it can be, else quoted.

    Examples
    --------
    >>> toml_key("hw6"), toml_key("crank rocker")
    ('hw6', '"crank rocker"')
    """
    key = str(key)
    return key if _BARE.match(key) else json.dumps(key, ensure_ascii=False)


def _join(path: tuple) -> str:
    out = ""
    for part in path:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + toml_key(part)
    return out


def field_name(path: tuple) -> str:
    """``[fourbar.hw6] r1`` for a key path; ``machdyn`` for a top-level key.

    Examples
    --------
    >>> field_name(("cam", "c", "segment", 2, "beta")), field_name(("machdyn",))
    ('[cam.c.segment[2]] beta', 'machdyn')
    >>> field_name(("path_synthesis", "p", "targets", 3)), field_name(())
    ('[path_synthesis.p] targets[3]', '(the document)')
    """
    path = tuple(path)
    if not path:
        return "(the document)"
    j = len(path) - 1
    while j > 0 and isinstance(path[j], int):
        j -= 1
    key = _join(path[j:])
    table = path[:j]
    return f"[{_join(table)}] {key}" if table else key


class Context:
    """Where the document came from and how to convert its numbers.

    Parameters
    ----------
    source : str, optional
        The file name for messages (None for a dict).
    text : str, optional
        The TOML text, for line numbers.
    """

    def __init__(self, source: str | None = None, text: str | None = None) -> None:
        self.source = source
        self.lines = KeyLines(text) if text is not None else None
        self.system = u.UnitSystem()
        #: True when [units] is declared: bare numbers are in its units.
        self.declared = False
        #: The folder of the file, for files it names (CSV torque curves).
        self.folder: Path | None = None
        #: Key paths of an upgraded old file → its own paths (for line numbers).
        self.alias: dict[tuple, tuple] = {}

    # -- errors -------------------------------------------------------------------
    def line(self, path: tuple) -> int | None:
        """The file line of ``path`` (None for a dict)."""
        if self.lines is None:
            return None
        path = tuple(path)
        for k in range(len(path), 0, -1):
            if path[:k] in self.alias:
                return self.lines.line(self.alias[path[:k]] + path[k:])
        return self.lines.line(path)

    def error(self, path: tuple, message: str, table: bool = False) -> SpecError:
        """A :class:`SpecError` at ``path`` (a key, or with ``table`` a whole table)."""
        return SpecError(self.source, self.line(path), path, message, table)

    @contextmanager
    def at(self, path: tuple, fields: Mapping[str, tuple] | None = None) -> Iterator[None]:
        """Name ``path`` (or the key a library field maps to) in errors of the library.

        ``fields`` maps the library's field names (``"r2"``, ``"coupler p"``) to
        key paths of the file; other errors are placed at ``path`` itself.
        """
        try:
            yield
        except SpecError:
            raise
        except InputError as exc:
            where = (fields or {}).get(exc.field)
            if where is not None:
                raise self.error(where, exc.message) from None
            raise self.error(path, str(exc), table=True) from None
        except MachdynError as exc:
            raise self.error(path, str(exc), table=True) from None

    # -- numbers ------------------------------------------------------------------
    def quantity(self, path: tuple, value: Any, kind: str) -> float:
        """A number of ``kind`` in the model's internal units (bare or with a unit)."""
        k = u.KINDS[kind]
        if isinstance(value, bool) or not isinstance(value, int | float | str):
            raise self.error(path, f"expected {k.article} like {k.example!r}, got {_show(value)}")
        if isinstance(value, str):
            try:
                number, unit = u.parse(value)
            except ValueError:
                raise self.error(
                    path, f"expected {k.article} like {k.example!r}, got {value!r}"
                ) from None
            if unit:
                return self._with_unit(path, value, number, unit, kind)
        else:
            number = value
        return self._bare(path, float(number), kind, value)

    def _finite(self, path: tuple, number: float, text: Any) -> None:
        if not math.isfinite(number):
            raise self.error(path, f"must be finite, got {text!r}")
        if abs(number) > HUGE:
            raise self.error(path, f"{text!r} is too large (at most 1e15 in the file's units)")

    def _with_unit(self, path: tuple, text: str, number: float, unit: str, kind: str) -> float:
        self._finite(path, number, text)
        k = u.KINDS[kind]
        if kind == "dimensionless":
            raise self.error(path, f"is a plain number, got {text!r}")
        if self.system.is_unit_free and kind != "angle":
            raise self.error(
                path,
                f"{text!r} has a unit but the file has none (bare numbers, any consistent "
                "units): declare a [units] table, or give every number its unit",
            )
        try:
            u.check_unit(unit, kind)
        except ValueError as exc:
            message = str(exc)
            if message.startswith("unknown unit"):
                message = f"{message} in {text!r}; write it like {k.example!r}"
            else:
                message = f"expected {k.article} like {k.example!r}, got {text!r} " + (
                    f"({u.describe(unit)})"
                )
            raise self.error(path, message) from None
        return number * u._factor(unit, "rad" if kind == "angle" else self.system.internal(kind))

    def _bare(self, path: tuple, number: float, kind: str, text: Any) -> float:
        self._finite(path, number, text)
        if kind == "dimensionless":
            return number
        system = self.system
        if system.is_unit_free:
            if kind == "angle":
                return number * self.angle_factor()
            return number
        if not self.declared and kind != "angle":
            k = u.KINDS[kind]
            raise self.error(
                path,
                f"a bare number ({text!r}) in a file whose numbers carry units: give it a unit "
                f"like {k.example!r}, or declare the units of bare numbers in a [units] table",
            )
        return number * self.bare_factor(kind)

    def angle_factor(self) -> float:
        """Bare angles (in ``[units] angle``) to radians."""
        angle = self.system.angle
        if angle in ("deg", "degree", "degrees"):
            return math.pi / 180.0
        if angle in ("rad", "radian", "radians"):
            return 1.0
        return u._factor(angle, "rad")

    def bare_factor(self, kind: str) -> float:
        """Bare numbers of ``kind`` (in display units) to internal units."""
        if kind == "angle":
            return self.angle_factor()
        if self.system.is_unit_free:
            return 1.0
        src, dst = self.system.display(kind), self.system.internal(kind)
        return 1.0 if src == dst else u._factor(src, dst)


def _show(value: Any) -> str:
    if isinstance(value, bool):
        return f"a boolean ({str(value).lower()})"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, dict):
        return "a table"
    return repr(value)


class Writer:
    """Writes values held in a unit system's internal units back as file values.

    A value is written bare, in the ``[units]`` the written file declares, when
    reading it back gives the same float; otherwise with its internal unit
    (``"0.5235987755982988 rad"``), which reads back exactly.

    Examples
    --------
    >>> w = Writer(u.UnitSystem(length="mm", mass="kg", time="s"))
    >>> w.quantity(8.0, "length"), w.quantity(math.radians(30), "angle")
    (8.0, 30.0)
    >>> w.quantity(0.1, "angle")  # 0.1 rad: the decimal degrees that read back exactly
    5.729577951308232
    """

    def __init__(self, system: u.UnitSystem) -> None:
        self.system = system
        self.ctx = Context()
        self.ctx.system = system
        self.ctx.declared = True

    def quantity(self, value: float, kind: str) -> float | str:
        """``value`` (internal units) as a bare number or a quantity string."""
        value = float(value)
        if kind == "dimensionless":
            return value
        factor = self.ctx.bare_factor(kind)
        shown = value / factor
        if math.isfinite(shown):
            for digits in (6, 9, 12, 15, 17):  # the shortest decimal that reads back exactly
                short = float(f"{shown:.{digits}g}")
                if short * factor == value:
                    return short + 0.0
        unit = "rad" if kind == "angle" else self.system.internal(kind)
        return f"{value!r} {unit}"


def check_units(value: Any) -> Any:
    """``units`` of a part object: None or a :class:`~machdyn.units.UnitSystem`."""
    if value is not None and not isinstance(value, u.UnitSystem):
        raise InputError("units", f"must be a machdyn.units.UnitSystem or None, got {value!r}")
    return value
