"""The document: version, units, gravity, and the named parts of one machine.

:func:`read` turns a parsed document (TOML or JSON) into a :class:`Machine`;
nothing is returned from a document that did not read completely. Each kind of
part (``fourbar``, ``linkage``, ``cam``, ...) is a :class:`PartKind` in its own
module, imported only when a document holds such a part.
"""

from __future__ import annotations

import importlib
import math
import os
import re
import tomllib
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .. import units as u
from ..errors import InputError
from . import _types as t
from ._context import Context, SpecError, Writer

__all__ = [
    "KINDS",
    "VERSION",
    "Machine",
    "Part",
    "PartKind",
    "from_spec",
    "load",
    "loads",
    "read",
    "read_doc",
]

#: The format version this machdyn reads and writes.
VERSION = 1

#: Part kinds and the module (in this package) that defines each.
KINDS: dict[str, str] = {
    "fourbar": "_fourbar",
    "slider_crank": "_fourbar",
    "inverted_slider_crank": "_fourbar",
    "linkage": "_linkage",
    "cam": "_cam",
    "gear_pair": "_gears",
    "gear_train": "_gears",
    "planetary": "_gears",
    "flywheel": "_tasks",
    "rotor": "_tasks",
    "motion_synthesis": "_synthesis",
    "function_synthesis": "_synthesis",
    "path_synthesis": "_synthesis",
}

UNIT_KEYS = {
    "length": "length",
    "mass": "mass",
    "time": "time",
    "angle": "angle",
    "force": "force",
    "torque": "torque",
    "angular_velocity": "angular_velocity",
}


@dataclass(frozen=True)
class PartKind:
    """How one kind of part is read, built, written back and analysed.

    ``table`` describes its keys; ``build(ctx, path, values)`` makes the model
    (or task object); ``values_of(model)`` gives the model's own keys back (for
    ``model.to_spec()``); ``run(part, machine)`` analyses it; ``refs(values)``
    names the parts it refers to, by key.
    """

    name: str
    table: t.Table
    build: Callable[[Context, tuple, dict], Any]
    values_of: Callable[[Any], dict]
    run: Callable[[Part, Machine], Any]
    refs: Callable[[dict], dict[tuple, str]] = lambda values: {}
    role: str = ""  # what it can be referred to for: "speed" (gears), "torque" (mechanisms)


def kind(name: str) -> PartKind:
    """The :class:`PartKind` of ``name`` (its module imported on first use)."""
    module = importlib.import_module(f".{KINDS[name]}", __package__)
    return module.PART_KINDS[name]


@dataclass
class Part:
    """One named part of a machine: its kind, the values read, and the model built."""

    kind: str
    name: str
    values: dict[str, Any]
    model: Any

    @property
    def path(self) -> tuple:
        """``(kind, name)``, the part's key path in the document."""
        return (self.kind, self.name)


@dataclass
class Machine(Mapping[str, Any]):
    """Every part of one machine file, by name (``machine["press"]`` is its model).

    Attributes
    ----------
    title : str
    units : UnitSystem
        The unit system the models compute in, and show their results in.
    gravity : float or None
        ``g`` in the models' units (None: no gravity).
    parts : dict of str to Part
        In file order.
    """

    title: str = ""
    units: u.UnitSystem = field(default_factory=u.UnitSystem)
    gravity: float | None = None
    parts: dict[str, Part] = field(default_factory=dict)
    source: str | None = None
    folder: Path | None = None
    #: The reading context (file, key lines) for errors found while running.
    context: Context | None = field(default=None, repr=False, compare=False)
    #: True when read from an old linkage file (upgraded on reading).
    legacy: bool = False

    def _error(self, path: tuple, message: str) -> SpecError:
        """A :class:`SpecError` at ``path`` of the machine's file (its line when known)."""
        return (self.context or Context(self.source)).error(path, message, table=True)

    def __getitem__(self, name: str) -> Any:
        return self.parts[name].model

    def __iter__(self) -> Iterator[str]:
        return iter(self.parts)

    def __len__(self) -> int:
        return len(self.parts)

    def __repr__(self) -> str:
        listed = ", ".join(f"{p.kind} {p.name!r}" for p in self.parts.values())
        title = f"{self.title!r}: " if self.title else ""
        return f"<Machine {title}{listed or 'no parts'}>"

    def to_spec(self) -> dict[str, Any]:
        """The machine as a plain spec dict (units included; reads back equal)."""
        w = Writer(self.units)
        out: dict[str, Any] = {"machdyn": VERSION}
        if self.title:
            out["title"] = self.title
        if self.gravity is not None:
            out["gravity"] = _write_gravity(w, self.gravity)
        units = self.units.to_spec()
        if units:
            out["units"] = units
        for part in self.parts.values():
            k = kind(part.kind)
            out.setdefault(part.kind, {})[part.name] = k.table.write(w, part.values)
        return out

    def run(self, names: list[str] | None = None) -> dict[str, Any]:
        """Analyse the parts (all, or ``names`` and what they refer to), in dependency order."""
        from ._run import run_machine

        if names is not None:
            if isinstance(names, str) or not isinstance(names, list | tuple):
                raise InputError("names", f"expected a list of part names, got {names!r}")
            for name in names:
                if not isinstance(name, str) or name not in self.parts:
                    listed = ", ".join(self.parts)
                    raise InputError("names", f"{name!r} is not a part; parts: {listed}")
        return run_machine(self, names)


def _write_gravity(w: Writer, g: float) -> Any:
    if w.system.is_unit_free:
        return g
    if g == u.standard_gravity(w.system):
        return True
    # with its unit: a bare gravity far from standard gravity is refused on reading
    return f"{g!r} {w.system.internal('acceleration')}"


# ------------------------------------------------------------------- reading
def _prescan(doc: Any, found: dict[str, str]) -> None:
    """The first unit met of each base kind, for a file without [units]."""
    if isinstance(doc, dict):
        for value in doc.values():
            _prescan(value, found)
    elif isinstance(doc, list):
        for value in doc:
            _prescan(value, found)
    elif isinstance(doc, str):
        try:
            _, unit = u.parse(doc)
        except ValueError:
            return
        if not unit or _is_angle(unit):
            return
        for key in ("length", "mass", "time", "force", "torque", "angular_velocity"):
            if key in found:
                continue
            try:
                u.check_unit(unit, key)
            except ValueError:
                continue
            found[key] = unit
            return
        try:  # '3 A', '3 furlongz': refused at their key, not as the file's units
            mechanical = not u.describe(unit).startswith("not a mechanical")
        except ValueError:
            return
        if mechanical:
            found.setdefault("any", unit)


def _is_angle(unit: str) -> bool:
    try:
        u.check_unit(unit, "angle")
    except ValueError:
        return False
    return True


def _units(ctx: Context, doc: dict) -> None:
    table = doc.get("units")
    if table is None:
        found: dict[str, str] = {}
        _prescan({k: v for k, v in doc.items() if k not in ("title", "units")}, found)
        if found:
            keys = ("length", "mass", "time", "force", "torque", "angular_velocity")
            given = {k: found[k] for k in keys if k in found}
            if not any(k in found for k in ("length", "mass", "time")):
                given["length"] = "m"
            ctx.system = u.UnitSystem(**given)
        return
    if not isinstance(table, dict):
        raise ctx.error(("units",), 'expected a table like [units] length = "mm"')
    given: dict[str, str] = {}
    for key, value in table.items():
        path = ("units", key)
        if key not in UNIT_KEYS:
            raise ctx.error(path, f"unknown key; valid keys: {', '.join(UNIT_KEYS)}")
        example = u.KINDS[UNIT_KEYS[key]].example.split(" ", 1)[1]
        if not isinstance(value, str) or not value.strip():
            raise ctx.error(path, f'expected a unit in quotes, e.g. "{example}"')
        try:
            u.check_unit(value.strip(), UNIT_KEYS[key])
        except ValueError as exc:
            raise ctx.error(path, str(exc).replace(" got a unit of", " got")) from None
        given[key] = value.strip()
    ctx.system = u.UnitSystem(**given)
    ctx.declared = True


def _gravity(ctx: Context, value: Any) -> float | None:
    path = ("gravity",)
    if value is False:
        return None
    if value is True:
        if ctx.system.is_unit_free:
            raise ctx.error(
                path,
                "standard gravity needs units: declare a [units] table, or give the value "
                "with its unit, e.g. '9.81 m/s^2'",
            )
        return u.standard_gravity(ctx.system)
    g = ctx.quantity(path, value, "acceleration")
    if g < 0.0:
        raise ctx.error(path, f"must be >= 0 (gravity acts along -y), got {value!r}")
    bare = not (isinstance(value, str) and u.parse(value)[1])
    if bare and g and not ctx.system.is_unit_free:
        standard = u.standard_gravity(ctx.system)
        if not 0.95 < g / standard < 1.05:
            unit = ctx.system.display("acceleration")
            raise ctx.error(
                path,
                f"{value!r} means {value} {unit}, {g / standard:.3g} times standard gravity "
                f"({standard:.6g} {unit}); write the value with its unit (e.g. '9.81 m/s^2') "
                "or gravity = true",
            )
    return g or None


def _version(ctx: Context, doc: dict) -> None:
    if "machdyn" not in doc:
        raise ctx.error(
            ("machdyn",), f"missing: a machine file starts with machdyn = {VERSION} (the format)"
        )
    version = doc["machdyn"]
    if version != VERSION or isinstance(version, bool):
        shown = version if isinstance(version, int) else repr(version)
        raise ctx.error(
            ("machdyn",),
            f"this file is format {shown}; this machdyn reads format {VERSION} (machdyn = 1)",
        )


def read(doc: Mapping[str, Any]) -> Machine:
    """A :class:`Machine` from a spec dict, whatever it holds (:func:`from_spec` gives a model).

    Examples
    --------
    >>> m = read({"machdyn": 1, "gravity": "9.81 m/s^2",
    ...           "fourbar": {"a": {"r1": "8 m", "r2": "4 m", "r3": "7 m", "r4": "6 m"}}})
    >>> m.gravity, list(m)
    (9.81, ['a'])
    """
    return read_doc(_plain(doc))


def read_doc(doc: Any, ctx: Context | None = None) -> Machine:
    """Read a parsed document into a :class:`Machine` (see :func:`load`)."""
    ctx = ctx or Context()
    if not isinstance(doc, dict):
        raise ctx.error((), "a machine file is a table (a TOML file, or a JSON object)")
    _version(ctx, doc)
    valid = ("machdyn", "title", "gravity", "units", *KINDS)
    for key in doc:
        if key not in valid:
            raise ctx.error((key,), f"unknown key; valid keys: {', '.join(valid)}")
    _units(ctx, doc)
    title = t.Text().read(ctx, ("title",), doc["title"]) if "title" in doc else ""
    gravity = _gravity(ctx, doc["gravity"]) if "gravity" in doc else None
    if "gravity" in doc and not isinstance(doc["gravity"], bool | int | float | str):
        raise ctx.error(("gravity",), "expected true, false or an acceleration like '9.81 m/s^2'")
    machine = Machine(title, ctx.system, gravity, source=ctx.source, folder=ctx.folder)
    machine.context = ctx
    read_parts(ctx, doc, machine)
    if not machine.parts:
        raise ctx.error((), f"describes no part: add one, e.g. [fourbar.NAME] ({_kinds()})")
    return machine


def _kinds() -> str:
    return "kinds: " + ", ".join(KINDS)


def read_parts(ctx: Context, doc: dict, machine: Machine) -> None:
    """Read, build and cross-check every part of ``doc`` into ``machine``."""
    seen: dict[str, str] = {}
    for name in (k for k in doc if k in KINDS):
        k = kind(name)
        parts = doc[name]
        if not isinstance(parts, dict) or not parts:
            raise ctx.error(
                (name,), f"expected named parts: write [{name}.NAME] and its keys under it"
            )
        for part_name, table in parts.items():
            path = (name, part_name)
            if not str(part_name).strip():
                raise ctx.error(path, "a part's name must not be empty", table=True)
            if part_name in seen:
                raise ctx.error(
                    path,
                    f"the name {part_name!r} is already a {seen[part_name]}: names are unique",
                    table=True,
                )
            seen[part_name] = name
            values = k.table.read(ctx, path, table)
            model = k.build(ctx, path, values)
            machine.parts[part_name] = Part(name, part_name, values, model)
    _check_refs(ctx, machine)


def _check_refs(ctx: Context, machine: Machine) -> None:
    for part in machine.parts.values():
        k = kind(part.kind)
        for key, target in k.refs(part.values).items():
            where = (*part.path, *key)
            if target not in machine.parts:
                listed = ", ".join(n for n in machine.parts if n != part.name) or "none"
                raise ctx.error(where, f"{target!r} is not a part; parts: {listed}")
            other = machine.parts[target]
            role = key[-1]
            wanted = {"driven_by": "speed", "torque": "torque"}.get(role, "")
            if wanted and kind(other.kind).role != wanted:
                raise ctx.error(
                    where,
                    f"{target!r} is a {other.kind}; {role} names a "
                    + ("gear_pair or gear_train" if wanted == "speed" else "mechanism with masses"),
                )
    order(machine, ctx)


def order(machine: Machine, ctx: Context | None = None) -> list[str]:
    """Part names in dependency order (a part after those it refers to); cycles are errors."""
    done: list[str] = []
    state: dict[str, int] = {}

    def visit(name: str, trail: tuple) -> None:
        if state.get(name) == 2:
            return
        if state.get(name) == 1:
            loop = " -> ".join((*trail, name))
            path = machine.parts[name].path
            message = f"parts refer to each other in a circle: {loop}"
            raise (ctx.error(path, message) if ctx else InputError(str(path), message))
        state[name] = 1
        part = machine.parts[name]
        for target in kind(part.kind).refs(part.values).values():
            visit(target, (*trail, name))
        state[name] = 2
        done.append(name)

    for name in machine.parts:
        visit(name, ())
    return done


def from_spec(spec: Mapping[str, Any]) -> Any:
    """Build the model a spec dict describes (a :class:`Machine` when it holds several parts).

    The dict is checked exactly as a file is (same messages, without line
    numbers). Of a one-part document the model is returned; its gravity,
    motion and loads are in :func:`read`'s :class:`Machine`.

    Examples
    --------
    >>> fb = from_spec({"machdyn": 1, "units": {"length": "mm"},
    ...                 "fourbar": {"hw6": {"r1": 8, "r2": 4, "r3": 7, "r4": "6 mm"}}})
    >>> fb.lengths, fb.units.length
    ((8.0, 4.0, 7.0, 6.0), 'mm')
    """
    return _single(read_doc(_plain(spec)))


def _plain(spec: Any) -> Any:
    if isinstance(spec, Mapping):
        return {k: _plain(v) for k, v in spec.items()}
    if isinstance(spec, tuple | list):
        return [_plain(v) for v in spec]
    return spec


def _single(machine: Machine) -> Any:
    """The lone part's model (the machine's gravity and settings stay in the Machine)."""
    if len(machine.parts) == 1:
        return next(iter(machine.parts.values())).model
    return machine


def parse_text(text: str, source: str, folder: Path | None = None) -> Machine:
    """Read TOML (or JSON, when ``source`` ends in .json) text into a :class:`Machine`."""
    ctx = Context(source, None)
    ctx.folder = folder
    if source.lower().endswith(".json"):
        import json

        try:
            doc = json.loads(text)
        except json.JSONDecodeError as exc:
            where = f"{source}:{exc.lineno}"
            raise InputError(where, f"JSON syntax error: {exc.msg} (column {exc.colno})") from None
    else:
        try:
            doc = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            found = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
            message = str(exc).split(" (at line")[0]
            if found:
                where, message = f"{source}:{found[1]}", f"{message} (column {found[2]})"
            else:
                where = source
            raise InputError(where, f"TOML syntax error: {message}") from None
        ctx = Context(source, text)
        ctx.folder = folder
    from ._legacy import is_legacy, upgrade

    legacy = is_legacy(doc)
    if legacy:
        doc = upgrade(doc, ctx)
    machine = read_doc(doc, ctx)
    machine.legacy = legacy
    return machine


def loads(text: str, source: str = "<text>.toml") -> Machine:
    r"""Read machine-file text (TOML, or JSON when ``source`` ends in ``.json``) into a Machine.

    What :func:`load_machine` does for a file, for text held in memory (a file
    dropped on a web page, an editor's buffer): errors start with
    ``source:line:`` and name the key; old linkage files are upgraded.
    ``source`` names the text in messages and picks the syntax; file names in
    the text (a torque CSV) are found relative to the working directory.

    Parameters
    ----------
    text : str
        The whole file.
    source : str
        A name for messages, ending in ``.toml`` or ``.json``.

    Returns
    -------
    Machine

    Examples
    --------
    >>> m = loads('machdyn = 1\n[units]\nlength = "mm"\n[fourbar.a]\nr1 = 80\nr2 = 40\n'
    ...           'r3 = 70\nr4 = 60\n', "a.toml")
    >>> m["a"].lengths, m.units.length
    ((80.0, 40.0, 70.0, 60.0), 'mm')
    >>> loads('{"machdyn": 1,\n "fourbar": }', "a.json")
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: a.json:2: JSON syntax error: Expecting value (column 13)
    """
    if not isinstance(text, str):
        raise InputError("text", f"expected the file's text (a str), got {type(text).__name__}")
    if not isinstance(source, str) or not source.strip():
        raise InputError("source", f"expected a name like 'press.toml', got {source!r}")
    if not source.lower().endswith((".toml", ".json")):
        raise InputError("source", f"expected a name ending in .toml or .json, got {source!r}")
    return parse_text(text, source)


def load_machine(path: str | Path) -> Machine:
    """Read a machine file (TOML or JSON) into a :class:`Machine`, whatever it holds."""
    if not isinstance(path, str | os.PathLike) or not str(path).strip():
        raise InputError("path", f"expected a file name, got {path!r}")
    path = Path(path)
    if not path.is_file():
        raise InputError(str(path), "no such file" if not path.exists() else "not a file")
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(
            str(path), f"not UTF-8 text (byte {exc.start}); save it as UTF-8"
        ) from None
    return parse_text(text, str(path), path.parent)


def load(path: str | Path) -> Any:
    """Read a machine file: the model when it holds one part, else a :class:`Machine`.

    :func:`load_machine` gives the :class:`Machine` in every case (with the
    file's gravity, each part's motion and loads, and ``run()``).

    Examples
    --------
    >>> load("no/such.toml")
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: no/such.toml: no such file
    """
    return _single(load_machine(path))


def finite(value: float) -> bool:
    """``math.isfinite`` for part modules."""
    return math.isfinite(value)
