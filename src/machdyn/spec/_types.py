"""The value types of the machine-file format: how each key is read, and its schema.

One description serves the reader (types, required and unknown keys, units)
and the JSON Schema (:mod:`machdyn.spec.schema`), so the two cannot drift.
Each type's :meth:`~Type.read` takes the context, the key path and the raw
TOML/JSON value and returns the value in the model's internal units.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import units as u
from ._context import Context, _show

__all__ = [
    "Boolean",
    "Choice",
    "Field",
    "Grid",
    "Integer",
    "ListOf",
    "MapOf",
    "Name",
    "Names",
    "Number",
    "OneOf",
    "Position",
    "Positions",
    "Quantities",
    "Quantity",
    "Sweep",
    "Table",
    "Text",
    "Type",
]

#: At most this many samples in a sweep.
MAX_SAMPLES = 1_000_000


class Type:
    """A value type: :meth:`read` it, describe it (``what``), give its JSON Schema."""

    what = "a value"

    def read(self, ctx: Context, path: tuple, value: Any) -> Any:
        raise NotImplementedError

    def accepts(self, value: Any) -> bool:
        """Whether ``value`` has the Python type this reads (for :class:`OneOf`)."""
        return True

    def schema(self) -> dict:
        raise NotImplementedError

    def write(self, w: Any, value: Any) -> Any:
        """``value`` as the file holds it (``w`` a :class:`~._context.Writer`)."""
        return value

    def owns(self, value: Any) -> bool:
        """Whether a value read by this type looks like ``value`` (for :class:`OneOf`)."""
        return True


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _looks_numeric(value: Any) -> bool:
    if _is_number(value):
        return True
    if isinstance(value, str):
        try:
            u.parse(value)
        except ValueError:
            return False
        return True
    return False


class Quantity(Type):
    """A number of a kind: bare (in ``[units]``) or ``"<number> <unit>"``."""

    def __init__(self, kind: str, minimum: float | None = None, positive: bool = False) -> None:
        self.kind = kind
        self.minimum = minimum
        self.positive = positive
        self.what = u.KINDS[kind].article

    def accepts(self, value: Any) -> bool:
        return _looks_numeric(value)

    def read(self, ctx: Context, path: tuple, value: Any) -> float:
        out = ctx.quantity(path, value, self.kind)
        if self.positive and not out > 0.0:
            raise ctx.error(path, f"must be positive, got {value!r}")
        if self.minimum is not None and out < self.minimum:
            raise ctx.error(path, f"must be at least {self.minimum:g}, got {value!r}")
        return out

    def schema(self) -> dict:
        ref = {"$ref": f"#/$defs/{self.kind}"}
        if not self.positive and (self.minimum is None or self.minimum < 0):
            return ref
        bound = {"exclusiveMinimum": 0} if self.positive else {"minimum": self.minimum}
        sign = {"if": {"type": "number"}, "then": bound, "else": {"not": {"pattern": r"^\s*-"}}}
        return {"allOf": [ref, sign]}

    def write(self, w: Any, value: Any) -> Any:
        return w.quantity(value, self.kind)

    def owns(self, value: Any) -> bool:
        return _is_number(value) or isinstance(value, np.floating)


class Number(Quantity):
    """A plain (dimensionless) number."""

    def __init__(
        self,
        minimum: float | None = None,
        positive: bool = False,
        below: float | None = None,
    ) -> None:
        super().__init__("dimensionless", minimum, positive)
        self.below = below
        self.what = "a number"

    def accepts(self, value: Any) -> bool:
        return _is_number(value)

    def read(self, ctx: Context, path: tuple, value: Any) -> float:
        if not _is_number(value):
            raise ctx.error(path, f"expected a plain number, got {_show(value)}")
        out = super().read(ctx, path, value)
        if self.below is not None and not out < self.below:
            raise ctx.error(path, f"must be less than {self.below:g}, got {value!r}")
        return out

    def schema(self) -> dict:
        out: dict[str, Any] = {"$ref": "#/$defs/number"}
        if self.minimum is not None or self.positive:
            key = "exclusiveMinimum" if self.positive else "minimum"
            out = {"allOf": [out, {key: self.minimum or 0}]}
        return out


class Integer(Type):
    """A whole number within bounds."""

    what = "a whole number"

    def __init__(self, minimum: int | None = None, maximum: int | None = None) -> None:
        self.minimum, self.maximum = minimum, maximum

    def accepts(self, value: Any) -> bool:
        return isinstance(value, int) and not isinstance(value, bool)

    def read(self, ctx: Context, path: tuple, value: Any) -> int:
        if not self.accepts(value):
            raise ctx.error(path, f"expected a whole number, got {_show(value)}")
        if self.minimum is not None and value < self.minimum:
            raise ctx.error(path, f"must be at least {self.minimum}, got {value}")
        if self.maximum is not None and value > self.maximum:
            raise ctx.error(path, f"must be at most {self.maximum}, got {value}")
        return int(value)

    def schema(self) -> dict:
        out: dict[str, Any] = {"type": "integer"}
        if self.minimum is not None:
            out["minimum"] = self.minimum
        if self.maximum is not None:
            out["maximum"] = self.maximum
        return out

    def owns(self, value: Any) -> bool:
        return self.accepts(value)


class Boolean(Type):
    """``true`` or ``false``."""

    what = "true or false"

    def accepts(self, value: Any) -> bool:
        return isinstance(value, bool)

    def read(self, ctx: Context, path: tuple, value: Any) -> bool:
        if not isinstance(value, bool):
            raise ctx.error(path, f"expected true or false, got {_show(value)}")
        return value

    def schema(self) -> dict:
        return {"type": "boolean"}

    def owns(self, value: Any) -> bool:
        return isinstance(value, bool)


class Text(Type):
    """Free text."""

    what = "text"

    def accepts(self, value: Any) -> bool:
        return isinstance(value, str)

    def read(self, ctx: Context, path: tuple, value: Any) -> str:
        if not isinstance(value, str):
            raise ctx.error(path, f"expected text in quotes, got {_show(value)}")
        return value

    def schema(self) -> dict:
        return {"type": "string"}

    def owns(self, value: Any) -> bool:
        return isinstance(value, str)


class Name(Text):
    """The name of something else in the document (a point, a link, a part)."""

    what = "a name"

    def accepts(self, value: Any) -> bool:
        return isinstance(value, str) and not _looks_numeric(value)

    def read(self, ctx: Context, path: tuple, value: Any) -> str:
        if not isinstance(value, str) or not value.strip():
            raise ctx.error(path, f'expected a name in quotes, e.g. "A", got {_show(value)}')
        return value

    def schema(self) -> dict:
        return {"type": "string", "minLength": 1}


class Choice(Type):
    """One of a few values (strings or numbers)."""

    def __init__(self, *options: Any) -> None:
        self.options = options
        self.what = "one of " + ", ".join(map(repr, options))

    def accepts(self, value: Any) -> bool:
        return value in self.options and not isinstance(value, bool)

    def read(self, ctx: Context, path: tuple, value: Any) -> Any:
        if isinstance(value, bool) or value not in self.options:
            listed = ", ".join(f'"{o}"' if isinstance(o, str) else str(o) for o in self.options)
            raise ctx.error(path, f"must be one of {listed}; got {_show(value)}")
        return value

    def schema(self) -> dict:
        return {"enum": list(self.options)}


class Names(Type):
    """An array of names (``["O2", "O4"]``)."""

    what = "an array of names"

    def __init__(self, count: int | None = None, minimum: int = 0) -> None:
        self.count, self.minimum = count, minimum

    def accepts(self, value: Any) -> bool:
        return isinstance(value, list)

    def read(self, ctx: Context, path: tuple, value: Any) -> list[str]:
        if not isinstance(value, list):
            raise ctx.error(
                path, f'expected an array of names like ["O2", "A"], got {_show(value)}'
            )
        names = [Name().read(ctx, (*path, i), v) for i, v in enumerate(value, start=1)]
        if self.count is not None and len(names) != self.count:
            raise ctx.error(path, f"must name {self.count} items, got {len(names)}")
        if len(names) < self.minimum:
            raise ctx.error(path, f"must name at least {self.minimum}, got {len(names)}")
        seen = set()
        for i, name in enumerate(names, start=1):
            if name in seen:
                raise ctx.error((*path, i), f"{name!r} is named twice")
            seen.add(name)
        return names

    def schema(self) -> dict:
        out: dict[str, Any] = {
            "type": "array",
            "items": {"type": "string", "minLength": 1},
            "uniqueItems": True,
        }
        if self.count is not None:
            out["minItems"] = out["maxItems"] = self.count
        elif self.minimum:
            out["minItems"] = self.minimum
        return out

    def write(self, w: Any, value: Any) -> Any:
        return list(value)


class Quantities(Type):
    """An array of numbers of one kind."""

    def __init__(self, kind: str, count: int | None = None, minimum: int = 0) -> None:
        self.kind, self.count, self.minimum = kind, count, minimum
        self.what = f"an array of {u.KINDS[kind].name.replace('_', ' ')}s"

    def accepts(self, value: Any) -> bool:
        return isinstance(value, list)

    def read(self, ctx: Context, path: tuple, value: Any) -> np.ndarray:
        if not isinstance(value, list):
            k = u.KINDS[self.kind]
            raise ctx.error(
                path, f"expected an array like [{k.example!r}, ...], got {_show(value)}"
            )
        if self.count is not None and len(value) != self.count:
            raise ctx.error(path, f"must hold {self.count} values, got {len(value)}")
        if len(value) < self.minimum:
            raise ctx.error(path, f"must hold at least {self.minimum} values, got {len(value)}")
        item = Quantity(self.kind)
        if value and all(_is_number(v) for v in value) and self.kind != "dimensionless":
            return _bare_array(ctx, path, value, self.kind)
        return np.array([item.read(ctx, (*path, i), v) for i, v in enumerate(value, start=1)])

    def schema(self) -> dict:
        out: dict[str, Any] = {"type": "array", "items": Quantity(self.kind).schema()}
        if self.count is not None:
            out["minItems"] = out["maxItems"] = self.count
        elif self.minimum:
            out["minItems"] = self.minimum
        return out

    def write(self, w: Any, value: Any) -> Any:
        return [w.quantity(v, self.kind) for v in np.asarray(value, dtype=float)]

    def owns(self, value: Any) -> bool:
        return isinstance(value, np.ndarray) and value.dtype.kind == "f"


def _bare_array(ctx: Context, path: tuple, value: list, kind: str) -> np.ndarray:
    """Many bare numbers at once (a torque curve of 3,600 samples): one check, one factor."""
    array = np.asarray(value, dtype=float)
    bad = ~np.isfinite(array) | (np.abs(array) > 1e15)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        ctx.quantity((*path, i + 1), value[i], kind)  # raises, naming the item
    ctx.quantity((*path, 1), value[0], kind)  # bare numbers allowed here at all?
    return array * ctx.bare_factor(kind)


class Position(Type):
    """A vector ``[x, y]`` of two quantities (a point by default) → a complex number."""

    def __init__(self, kind: str = "length") -> None:
        self.kind = kind
        self.what = "a position [x, y]" if kind == "length" else f"a vector [x, y] of {kind}s"

    def accepts(self, value: Any) -> bool:
        return isinstance(value, list)

    def read(self, ctx: Context, path: tuple, value: Any) -> complex:
        if not isinstance(value, list) or len(value) != 2:
            example = u.KINDS[self.kind].example
            raise ctx.error(path, f"expected {self.what} like [{example!r}, 0], got {_show(value)}")
        x, y = (ctx.quantity((*path, i), v, self.kind) for i, v in enumerate(value, start=1))
        return complex(x, y)

    def write(self, w: Any, value: Any) -> Any:
        z = complex(value)
        return [w.quantity(z.real, self.kind), w.quantity(z.imag, self.kind)]

    def owns(self, value: Any) -> bool:
        return isinstance(value, complex | np.complexfloating)

    def schema(self) -> dict:
        item = {"$ref": f"#/$defs/{self.kind}"}
        return {"type": "array", "items": item, "minItems": 2, "maxItems": 2}


class Positions(Type):
    """An array of positions → a complex array."""

    def __init__(self, count: int | None = None, minimum: int = 0, kind: str = "length") -> None:
        self.count, self.minimum, self.kind = count, minimum, kind
        self.what = "an array of positions [x, y]"

    def accepts(self, value: Any) -> bool:
        return isinstance(value, list)

    def read(self, ctx: Context, path: tuple, value: Any) -> np.ndarray:
        if not isinstance(value, list):
            raise ctx.error(
                path, f"expected an array of positions [[x, y], ...], got {_show(value)}"
            )
        if self.count is not None and len(value) != self.count:
            raise ctx.error(path, f"must hold {self.count} positions, got {len(value)}")
        if len(value) < self.minimum:
            raise ctx.error(path, f"must hold at least {self.minimum} positions, got {len(value)}")
        return np.array([Position().read(ctx, (*path, i), v) for i, v in enumerate(value, 1)])

    def schema(self) -> dict:
        out: dict[str, Any] = {"type": "array", "items": Position().schema()}
        if self.count is not None:
            out["minItems"] = out["maxItems"] = self.count
        elif self.minimum:
            out["minItems"] = self.minimum
        return out

    def write(self, w: Any, value: Any) -> Any:
        return [Position().write(w, z) for z in np.asarray(value, dtype=complex)]

    def owns(self, value: Any) -> bool:
        return isinstance(value, np.ndarray) and value.dtype.kind == "c"


@dataclass(frozen=True)
class Grid:
    """The values of a :class:`Sweep`: ``start, stop, step`` or explicit ``values``."""

    start: float = 0.0
    stop: float = 0.0
    step: float = 0.0
    explicit: tuple[float, ...] | None = None

    @property
    def values(self) -> np.ndarray:
        """The samples (stop included when it falls on the grid)."""
        if self.explicit is not None:
            return np.array(self.explicit, dtype=float)
        count = math.floor((self.stop - self.start) / self.step + 1e-9) + 1
        return self.start + self.step * np.arange(count)

    @classmethod
    def of(cls, values: Any) -> Grid:
        """A grid holding these values (explicitly; one value is ``start = stop``)."""
        array = np.atleast_1d(np.asarray(values, dtype=float)).ravel()
        return cls(explicit=tuple(float(v) for v in array))


class Sweep(Type):
    """One value, ``[start, stop, step]`` (stop included on the grid), or ``{values = [...]}``."""

    def __init__(self, kind: str) -> None:
        self.kind = kind
        self.what = f"{u.KINDS[kind].article}, [start, stop, step] or {{values = [...]}}"

    def accepts(self, value: Any) -> bool:
        return _looks_numeric(value) or isinstance(value, list | dict)

    def read(self, ctx: Context, path: tuple, value: Any) -> Grid:
        if isinstance(value, dict):
            table = Table(fields(values=required(Quantities(self.kind, minimum=1))))
            return Grid.of(table.read(ctx, path, value)["values"])
        if not isinstance(value, list):
            return Grid.of([ctx.quantity(path, value, self.kind)])
        if len(value) != 3:
            k = u.KINDS[self.kind]
            raise ctx.error(
                path,
                f"expected one value, [start, stop, step] like {k.example!r}, or "
                f"{{values = [...]}} for a list; got an array of {len(value)}",
            )
        start, stop, step = (
            ctx.quantity((*path, i), v, self.kind) for i, v in enumerate(value, start=1)
        )
        span = stop - start
        if step == 0.0 or span * step < 0.0:
            raise ctx.error(
                path, f"step must be non-zero and point from start to stop, got {value!r}"
            )
        count = math.floor(span / step + 1e-9) + 1
        if count > MAX_SAMPLES:
            raise ctx.error(path, f"{count:,} samples; at most {MAX_SAMPLES:,}")
        return Grid(start, stop, step)

    def write(self, w: Any, value: Any) -> Any:
        q = Quantity(self.kind)
        if value.explicit is None:
            return [q.write(w, value.start), q.write(w, value.stop), q.write(w, value.step)]
        if len(value.explicit) == 1:
            return q.write(w, value.explicit[0])
        return {"values": [q.write(w, v) for v in value.explicit]}

    def owns(self, value: Any) -> bool:
        return isinstance(value, Grid)

    def schema(self) -> dict:
        one = Quantity(self.kind).schema()
        return {
            "anyOf": [
                one,
                {"type": "array", "items": one, "minItems": 3, "maxItems": 3},
                {
                    "type": "object",
                    "properties": {"values": {"type": "array", "items": one, "minItems": 1}},
                    "required": ["values"],
                    "additionalProperties": False,
                },
            ]
        }


class OneOf(Type):
    """The first of several types that accepts the value's form."""

    def __init__(self, *types: Type, what: str | None = None) -> None:
        self.types = types
        self.what = what or " or ".join(t.what for t in types)

    def accepts(self, value: Any) -> bool:
        return any(t.accepts(value) for t in self.types)

    def read(self, ctx: Context, path: tuple, value: Any) -> Any:
        for t in self.types:
            if t.accepts(value):
                return t.read(ctx, path, value)
        raise ctx.error(path, f"expected {self.what}, got {_show(value)}")

    def schema(self) -> dict:
        return {"anyOf": [t.schema() for t in self.types]}

    def write(self, w: Any, value: Any) -> Any:
        for t in self.types:
            if t.owns(value):
                return t.write(w, value)
        raise TypeError(f"cannot write {value!r} as {self.what}")  # pragma: no cover

    def owns(self, value: Any) -> bool:
        return any(t.owns(value) for t in self.types)


@dataclass(frozen=True)
class Field:
    """A key of a table: its type, whether it is required, and a line of documentation."""

    type: Type
    required: bool = False
    doc: str = ""


class Table(Type):
    """A table with known keys: unknown keys and missing required keys are errors."""

    what = "a table"

    def __init__(
        self, fields: dict[str, Field], doc: str = "", check: Callable | None = None
    ) -> None:
        self.fields = fields
        self.doc = doc
        self.check = check

    def accepts(self, value: Any) -> bool:
        return isinstance(value, dict)

    def read(self, ctx: Context, path: tuple, value: Any) -> dict[str, Any]:
        if not isinstance(value, dict):
            raise ctx.error(path, f"expected a table of keys {self._list()}, got {_show(value)}")
        for key in value:
            if key not in self.fields:
                raise ctx.error((*path, key), f"unknown key; valid keys: {self._list()}")
        for key, f in self.fields.items():
            if f.required and key not in value:
                what = f.type.what
                raise ctx.error((*path, key), f"missing: required ({what})")
        out = {
            k: f.type.read(ctx, (*path, k), value[k]) for k, f in self.fields.items() if k in value
        }
        if self.check is not None:
            self.check(ctx, path, out)
        return out

    def _list(self) -> str:
        return ", ".join(self.fields)

    def schema(self) -> dict:
        out: dict[str, Any] = {
            "type": "object",
            "properties": {
                k: {**f.type.schema(), **({"description": f.doc} if f.doc else {})}
                for k, f in self.fields.items()
            },
            "additionalProperties": False,
        }
        required = [k for k, f in self.fields.items() if f.required]
        if required:
            out["required"] = required
        if self.doc:
            out["description"] = self.doc
        return out

    def write(self, w: Any, value: Any) -> Any:
        return {
            k: f.type.write(w, value[k])
            for k, f in self.fields.items()
            if k in value and value[k] is not None
        }

    def owns(self, value: Any) -> bool:
        return isinstance(value, dict)


class MapOf(Type):
    """A table of ``name = value`` (points, per-link torques, parts of one kind)."""

    def __init__(self, item: Type, what: str = "a table of names", minimum: int = 0) -> None:
        self.item, self.what, self.minimum = item, what, minimum

    def accepts(self, value: Any) -> bool:
        return isinstance(value, dict)

    def read(self, ctx: Context, path: tuple, value: Any) -> dict[str, Any]:
        if not isinstance(value, dict):
            raise ctx.error(path, f"expected {self.what}, got {_show(value)}")
        if len(value) < self.minimum:
            raise ctx.error(path, f"expected {self.what}, at least {self.minimum}")
        out = {}
        for name, item in value.items():
            if not str(name).strip():
                raise ctx.error((*path, name), "a name must not be empty")
            out[name] = self.item.read(ctx, (*path, name), item)
        return out

    def schema(self) -> dict:
        out: dict[str, Any] = {
            "type": "object",
            "additionalProperties": self.item.schema(),
            "propertyNames": {"minLength": 1, "pattern": r"\S"},
        }
        if self.minimum:
            out["minProperties"] = self.minimum
        return out

    def write(self, w: Any, value: Any) -> Any:
        return {name: self.item.write(w, v) for name, v in value.items()}

    def owns(self, value: Any) -> bool:
        return isinstance(value, dict)


class ListOf(Type):
    """An array of tables (``[[cam.c.segment]]``), counted from 1 in messages."""

    def __init__(self, item: Type, minimum: int = 0) -> None:
        self.item, self.minimum = item, minimum
        self.what = f"an array of tables (write [[...]] for each), at least {minimum}"

    def accepts(self, value: Any) -> bool:
        return isinstance(value, list)

    def read(self, ctx: Context, path: tuple, value: Any) -> list[Any]:
        if not isinstance(value, list):
            raise ctx.error(path, f"expected {self.what}, got {_show(value)}")
        if len(value) < self.minimum:
            raise ctx.error(path, f"expected at least {self.minimum} entries, got {len(value)}")
        return [self.item.read(ctx, (*path, i), v) for i, v in enumerate(value, start=1)]

    def schema(self) -> dict:
        out: dict[str, Any] = {"type": "array", "items": self.item.schema()}
        if self.minimum:
            out["minItems"] = self.minimum
        return out

    def write(self, w: Any, value: Any) -> Any:
        return [self.item.write(w, v) for v in value]

    def owns(self, value: Any) -> bool:
        return isinstance(value, list)


def fields(**spec: Field | Type) -> dict[str, Field]:
    """``fields(r1=Field(...), notes=Text())``: plain types become optional fields."""
    return {k: (v if isinstance(v, Field) else Field(v)) for k, v in spec.items()}


def required(type_: Type, doc: str = "") -> Field:
    """A required field."""
    return Field(type_, True, doc)


def optional(type_: Type, doc: str = "") -> Field:
    """An optional field."""
    return Field(type_, False, doc)


def check_all(*checks: Callable) -> Callable:
    """Run several table checks in turn."""

    def run(ctx: Context, path: tuple, out: dict) -> None:
        for check in checks:
            check(ctx, path, out)

    return run


def names_in(values: Sequence[str]) -> str:
    """``'a, b, c'`` for messages."""
    return ", ".join(values)
