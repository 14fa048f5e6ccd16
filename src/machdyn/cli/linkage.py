"""``machdyn linkage FILE.toml``: a drawn linkage from a TOML file, solved and tabulated.

The file maps one-to-one onto the :class:`machdyn.linkage.Linkage` builder
(see ``docs/linkage.md``, *From the command line*, and ``docs/examples/``).
Angles are in degrees in the file and on the command line (labelled in every
output), angular rates in rad/s and rad/s^2; lengths, masses and forces are in
the file's own consistent units, whose names ``[units]`` gives for the labels.

This module only parses, calls the library and presents: no physics here.
"""

from __future__ import annotations

import csv
import math
import tomllib
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from ..errors import InputError, MachdynError
from ..linkage import Linkage, LinkageForces, LinkageMotion
from ._common import dumps, parse_range_deg, print_table

__all__ = [
    "DriverMotion",
    "LinkageFile",
    "Table",
    "analyse",
    "driver_values",
    "linkage",
    "load",
    "parse",
    "write_csv",
]

_TOP = ("title", "units", "points", "ground", "drive", "report", "gravity", "motion")
_UNITS = ("length", "mass", "force", "time")
#: Each array of tables: (required keys, optional keys), in the builder's order.
_ELEMENTS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "link": (("name", "points"), ("mass", "inertia", "cg")),
    "slider": (("block", "on", "at"), ("direction", "through", "name")),
    "slot": (("pin", "link", "on"), ("direction", "through", "name")),
    "actuator": (("name", "start", "end"), ("links",)),
    "roll": (
        ("link_a", "centre_a", "radius_a", "link_b", "centre_b", "radius_b"),
        ("internal", "name"),
    ),
    "motor": (("name", "at"), ("links",)),
    "spring": (
        ("name", "start", "end", "stiffness", "free_length"),
        ("damping", "preload", "links"),
    ),
    "torsion_spring": (
        ("name", "at", "stiffness", "free_angle"),
        ("damping", "preload", "links"),
    ),
}
_MOTION = ("sweep", "value", "velocity", "acceleration")
#: The example files of docs/linkage.md (in a source checkout).
EXAMPLES = Path(__file__).resolve().parents[3] / "docs" / "examples"


# ---------------------------------------------------------------- reading the file
def _type_name(value: Any) -> str:
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int | float):
        return "a number"
    return {str: "a string", list: "an array", dict: "a table"}.get(
        type(value), f"a {type(value).__name__}"
    )


def _keys(field: str, table: Any, required: Sequence[str], optional: Sequence[str]) -> dict:
    if not isinstance(table, dict):
        raise InputError(field, f"must be a table, got {_type_name(table)}")
    valid = tuple(dict.fromkeys((*required, *optional)))
    unknown = [k for k in table if k not in valid]
    if unknown:
        raise InputError(
            f"{field}.{unknown[0]}" if field else unknown[0],
            f"unknown key; valid keys: {', '.join(valid)}",
        )
    missing = [k for k in required if k not in table]
    if missing:
        raise InputError(f"{field}.{missing[0]}" if field else missing[0], "missing (required)")
    return table


def _number(field: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(field, f"must be a number, got {_type_name(value)} {value!r}")
    return float(value)


def _text(field: str, value: Any) -> str:
    if not isinstance(value, str) or not value:
        raise InputError(field, f"must be a non-empty string (a name), got {value!r}")
    return value


def _texts(field: str, value: Any, count: int | None = None) -> list[str]:
    if not isinstance(value, list):
        raise InputError(field, f'must be an array of names, e.g. ["O2", "A"], got {value!r}')
    names = [_text(f"{field}[{i}]", v) for i, v in enumerate(value, start=1)]
    if count is not None and len(names) != count:
        raise InputError(field, f"must name {count} items, got {len(names)}")
    return names


def _xy(field: str, value: Any) -> complex:
    if not isinstance(value, list) or len(value) != 2:
        raise InputError(field, f"must be [x, y], got {value!r}")
    x, y = (_number(f"{field}[{i}]", v) for i, v in enumerate(value, start=1))
    return complex(x, y)


def _direction(field: str, value: Any) -> float | complex | str:
    """A slide direction: an angle in degrees, a vector [dx, dy] or a point name."""
    if isinstance(value, str):
        return value
    if isinstance(value, list):
        return _xy(field, value)
    return math.radians(_number(field, value))


def _cg(field: str, value: Any) -> float | complex | str:
    if isinstance(value, str):
        return value
    if isinstance(value, list):
        return _xy(field, value)
    return _number(field, value)


@contextmanager
def _at(field: str) -> Iterator[None]:
    """Prefix an error of the builder with the TOML key that caused it."""
    try:
        yield
    except InputError as exc:
        if exc.field.startswith(field):  # already names the TOML key
            raise
        raise InputError(field, str(exc)) from exc
    except MachdynError as exc:
        raise type(exc)(f"{field}: {exc}") from exc


@dataclass(frozen=True)
class DriverMotion:
    """The file's default values and rates of one driver (angles in degrees)."""

    sweep: np.ndarray | None = None
    value: float | None = None
    velocity: float = 1.0
    acceleration: float = 0.0


@dataclass(frozen=True)
class LinkageFile:
    """A linkage read from a TOML file, with its defaults for the command line.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> text = '''
    ... ground = ["O2"]
    ... drive = ["crank"]
    ... [points]
    ... O2 = [0, 0]
    ... A = [2, 0]
    ... [[link]]
    ... name = "crank"
    ... points = ["O2", "A"]
    ... '''
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "crank.toml"
    >>> _ = path.write_text(text)
    >>> spec = load(path)
    >>> spec.drivers, spec.angle_drivers
    (('crank',), frozenset({'crank'}))
    """

    linkage: Linkage
    drivers: tuple[str, ...]
    angle_drivers: frozenset[str]
    title: str = ""
    units: Mapping[str, str] = field(default_factory=dict)
    report: tuple[str, ...] = ()
    gravity: float = 0.0
    motion: Mapping[str, DriverMotion] = field(default_factory=dict)
    torsion_springs: frozenset[str] = frozenset()
    motors: frozenset[str] = frozenset()


def load(path: str | Path) -> LinkageFile:
    """Read a linkage TOML file; errors name the TOML key (``link[2].mass``).

    Arrays and arrays of tables are counted from 1 in the error messages:
    ``link[2].points[1]`` is the first point of the second ``[[link]]``.


    Examples
    --------
    >>> load("no/such/file.toml")
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: no/such/file.toml: no such file
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(str(path), "no such file" if not path.exists() else "not a file")
    try:
        doc = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise InputError(str(path), f"TOML syntax error: {exc}") from None
    return parse(doc)


def parse(doc: Mapping[str, Any]) -> LinkageFile:
    """Build the :class:`LinkageFile` of a parsed TOML document (see :func:`load`).

    Examples
    --------
    >>> parse({"points": {"O2": [0, 0]}, "lnk": []})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: lnk: unknown key; valid keys: points, ground, drive, title, ...
    """
    doc = _keys("", dict(doc), ("points", "ground", "drive"), (*_TOP, *_ELEMENTS))
    title = "" if "title" not in doc else _text("title", doc["title"])
    units = {
        k: _text(f"units.{k}", v)
        for k, v in _keys("units", doc.get("units", {}), (), _UNITS).items()
    }
    points = doc["points"]
    if not isinstance(points, dict) or not points:
        raise InputError("points", "must be a table of name = [x, y], e.g. O2 = [0, 0]")
    lk = Linkage({name: _xy(f"points.{name}", xy) for name, xy in points.items()})
    with _at("ground"):
        lk.ground(*_texts("ground", doc["ground"]))
    for kind in _ELEMENTS:
        entries = doc.get(kind, [])
        if not isinstance(entries, list):
            raise InputError(kind, f"must be an array of tables: write [[{kind}]] for each")
        for i, entry in enumerate(entries, start=1):
            key = f"{kind}[{i}]"
            required, optional = _ELEMENTS[kind]
            _keys(key, entry, required, optional)
            with _at(key):
                _BUILD[kind](lk, key, entry)
    drivers = _texts("drive", doc["drive"])
    with _at("drive"):
        lk.drive(*drivers)
    angle_drivers = frozenset(
        d
        for d in drivers
        if d in {e["name"] for e in (*doc.get("link", []), *doc.get("motor", []))}
    )
    report = tuple(_texts("report", doc.get("report", [])))
    for i, p in enumerate(report, start=1):
        with _at(f"report[{i}]"):
            lk.position(p)
    gravity = _number("gravity", doc.get("gravity", 0.0))
    if gravity < 0 or not math.isfinite(gravity):
        raise InputError("gravity", f"must be >= 0 (it acts along -y), got {gravity:g}")
    motion_doc = doc.get("motion", {})
    if not isinstance(motion_doc, dict):
        raise InputError("motion", "must be a table of [motion.<driver>] tables")
    motion = {}
    for d, entry in motion_doc.items():
        if d not in drivers:
            raise InputError(f"motion.{d}", f"is not a driver; drivers: {', '.join(drivers)}")
        motion[d] = _driver_motion(f"motion.{d}", _keys(f"motion.{d}", entry, (), _MOTION))
    torsions = frozenset(e["name"] for e in doc.get("torsion_spring", []))
    motors = frozenset(e["name"] for e in doc.get("motor", []))
    return LinkageFile(
        lk, tuple(drivers), angle_drivers, title, units, report, gravity, motion, torsions, motors
    )


def _driver_motion(key: str, entry: dict) -> DriverMotion:
    sweep = value = None
    if "sweep" in entry and "value" in entry:
        raise InputError(
            f"{key}.value", "give either sweep = [start, stop, step] or value, not both"
        )
    if "sweep" in entry:
        raw = entry["sweep"]
        if not isinstance(raw, list) or len(raw) != 3:
            raise InputError(f"{key}.sweep", f"must be [start, stop, step], got {raw!r}")
        numbers = [_number(f"{key}.sweep[{i}]", v) for i, v in enumerate(raw, start=1)]
        sweep = parse_range_deg(":".join(repr(v) for v in numbers), f"{key}.sweep")
    if "value" in entry:
        value = _number(f"{key}.value", entry["value"])
    rates = {k: _number(f"{key}.{k}", entry[k]) for k in ("velocity", "acceleration") if k in entry}
    return DriverMotion(sweep, value, **rates)


def _names_or_empty(key: str, entry: dict) -> tuple[str, ...]:
    return tuple(_texts(f"{key}.links", entry["links"], 2)) if "links" in entry else ()


def _link(lk: Linkage, key: str, e: dict) -> None:
    mass = {k: _number(f"{key}.{k}", e[k]) for k in ("mass", "inertia") if k in e}
    cg = _cg(f"{key}.cg", e["cg"]) if "cg" in e else None
    lk.link(_text(f"{key}.name", e["name"]), *_texts(f"{key}.points", e["points"]), cg=cg, **mass)


def _slider(lk: Linkage, key: str, e: dict, method: str = "slider") -> None:
    first = ("block", "on", "at") if method == "slider" else ("pin", "link", "on")
    getattr(lk, method)(
        *(_text(f"{key}.{k}", e[k]) for k in first),
        _direction(f"{key}.direction", e.get("direction", 0.0)),
        through=_text(f"{key}.through", e["through"]) if "through" in e else None,
        name=_text(f"{key}.name", e["name"]) if "name" in e else None,
    )


def _roll(lk: Linkage, key: str, e: dict) -> None:
    internal = e.get("internal", False)
    if not isinstance(internal, bool):
        raise InputError(f"{key}.internal", f"must be true or false, got {internal!r}")
    lk.roll(
        _text(f"{key}.link_a", e["link_a"]),
        _text(f"{key}.centre_a", e["centre_a"]),
        _number(f"{key}.radius_a", e["radius_a"]),
        _text(f"{key}.link_b", e["link_b"]),
        _text(f"{key}.centre_b", e["centre_b"]),
        _number(f"{key}.radius_b", e["radius_b"]),
        internal=internal,
        name=_text(f"{key}.name", e["name"]) if "name" in e else None,
    )


def _spring(lk: Linkage, key: str, e: dict, torsion: bool = False) -> None:
    loads = {k: _number(f"{key}.{k}", e[k]) for k in ("stiffness", "damping", "preload") if k in e}
    name = _text(f"{key}.name", e["name"])
    if torsion:
        free = math.radians(_number(f"{key}.free_angle", e["free_angle"]))
        links = _names_or_empty(key, e) or None
        lk.torsion_spring(name, _text(f"{key}.at", e["at"]), free_angle=free, links=links, **loads)
    else:
        ends = (_text(f"{key}.start", e["start"]), _text(f"{key}.end", e["end"]))
        free = _number(f"{key}.free_length", e["free_length"])
        lk.spring(name, *ends, free_length=free, links=_names_or_empty(key, e), **loads)


_BUILD: dict[str, Callable[[Linkage, str, dict], None]] = {
    "link": _link,
    "slider": _slider,
    "slot": lambda lk, key, e: _slider(lk, key, e, "slot"),
    "actuator": lambda lk, key, e: lk.actuator(
        _text(f"{key}.name", e["name"]),
        _text(f"{key}.start", e["start"]),
        _text(f"{key}.end", e["end"]),
        links=_names_or_empty(key, e),
    ),
    "roll": _roll,
    "motor": lambda lk, key, e: lk.motor(
        _text(f"{key}.name", e["name"]),
        _text(f"{key}.at", e["at"]),
        links=_names_or_empty(key, e) or None,
    ),
    "spring": _spring,
    "torsion_spring": lambda lk, key, e: _spring(lk, key, e, torsion=True),
}


# ---------------------------------------------------------------- solving and tabulating
@dataclass(frozen=True)
class Table:
    """The command's output: named columns (one value per sample) and their units.

    Column names are plain identifiers (``theta_coupler_deg``, ``omega_coupler``,
    ``P_x``, ``T_crank``, ``F_ground_crank_x``, ``ok``, ``reason``) so that the
    JSON and CSV outputs can be read by programs; ``units`` labels each.
    """

    title: str
    columns: Mapping[str, np.ndarray]
    units: Mapping[str, str]

    def rows(self) -> list[dict[str, Any]]:
        """One dict per sample (the ``--json`` rows)."""
        n = len(self.columns["ok"])
        return [{k: v[i] for k, v in self.columns.items()} for i in range(n)]


def driver_values(
    spec: LinkageFile, sweep: str | None = None, at: Sequence[str] = ()
) -> dict[str, np.ndarray]:
    """Each driver's values in file units (degrees for angles), from the CLI and the file.

    ``--sweep D=START:STOP:STEP`` and ``--at D=VALUE`` override the file's
    ``[motion.D]``; only one driver may be swept.

    Examples
    --------
    >>> spec = load(EXAMPLES / "fourbar.toml")
    >>> driver_values(spec)["crank"][:3].tolist()  # the file's sweep = [0, 360, 30]
    [0.0, 30.0, 60.0]
    >>> driver_values(spec, at=["crank=45"])["crank"].tolist()
    [45.0]
    """
    chosen: dict[str, np.ndarray] = {}
    for d, m in spec.motion.items():
        if m.sweep is not None:
            chosen[d] = m.sweep
        elif m.value is not None:
            chosen[d] = np.array([m.value])
    if sweep is not None:
        d, text = _driver_assignment("--sweep", sweep, spec.drivers)
        chosen[d] = parse_range_deg(text, f"--sweep {d}")
    for item in at:
        d, text = _driver_assignment("--at", item, spec.drivers)
        try:
            chosen[d] = np.array([float(text)])
        except ValueError:
            raise InputError(f"--at {d}", f"expected one number, got {text!r}") from None
        if not math.isfinite(chosen[d][0]):
            raise InputError(f"--at {d}", f"must be finite, got {text!r}")
    missing = [d for d in spec.drivers if d not in chosen]
    if missing:
        raise InputError(
            f"motion.{missing[0]}",
            f"driver {missing[0]!r} has no value: give --sweep {missing[0]}=START:STOP:STEP, "
            f"--at {missing[0]}=VALUE, or sweep/value under [motion.{missing[0]}] in the file",
        )
    swept = [d for d in spec.drivers if chosen[d].size > 1]
    if len(swept) > 1:
        raise InputError(
            "--sweep",
            f"sweep one driver at a time; {', '.join(swept)} are all swept "
            f"(hold the others with --at DRIVER=VALUE)",
        )
    return {d: chosen[d] for d in spec.drivers}


def _driver_assignment(option: str, text: str, drivers: Sequence[str]) -> tuple[str, str]:
    name, sep, value = text.partition("=")
    if not sep:
        raise InputError(
            option, f"expected DRIVER=..., got {text!r}; drivers: {', '.join(drivers)}"
        )
    if name not in drivers:
        raise InputError(option, f"{name!r} is not a driver; drivers: {', '.join(drivers)}")
    return name, value


def analyse(
    spec: LinkageFile, values: Mapping[str, np.ndarray], with_forces: bool = False
) -> Table:
    """Solve ``spec`` at ``values`` (file units, degrees for angles) and tabulate it.

    Rates come from the file's ``[motion.<driver>]`` (velocity 1, acceleration 0
    by default); with ``with_forces`` the driver efforts, pin forces and spring
    loads are added (gravity from the file).

    Examples
    --------
    The notes' HW 6 four-bar at θ2 = 0: θ3 = 58.8114°, θ4 = 93.5833°.

    >>> spec = load(EXAMPLES / "fourbar.toml")
    >>> t = analyse(spec, {"crank": np.array([0.0])}, with_forces=True)
    >>> round(float(t.columns["theta_coupler_deg"][0]), 4), t.units["T_crank"]
    (58.8114, 'lbf*in')
    """
    lk, angles = spec.linkage, spec.angle_drivers
    rad = {d: np.radians(v) if d in angles else np.asarray(v, float) for d, v in values.items()}
    n = max(v.size for v in rad.values())
    rad = {d: np.broadcast_to(v, (n,)) for d, v in rad.items()}
    rates = {d: spec.motion.get(d, DriverMotion()) for d in spec.drivers}
    m = lk.solve(
        rad,
        velocity={d: r.velocity for d, r in rates.items()},
        acceleration={d: r.acceleration for d, r in rates.items()},
    )
    f = lk.forces(m, gravity=spec.gravity) if with_forces else None
    u = {"length": "L", "force": "F", "time": "s", **spec.units}
    length, force, time = u["length"], u["force"], u["time"]
    cols: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}

    def put(name: str, value: np.ndarray, unit: str) -> None:
        if name not in cols:  # a driver's column comes first, under its kinematic name
            cols[name] = np.broadcast_to(value, (n,))
            units[name] = unit

    for d in spec.drivers:
        put(_driver_column(spec, d), values[d], "deg" if d in angles else length)
    _kinematics(m, put, length, time)
    for p in spec.report:
        put(f"{p}_x", m.points[p].real, length)
        put(f"{p}_y", m.points[p].imag, length)
    if f is not None:
        _forces(f, angles, spec.torsion_springs, put, length, force)
    ok = m.ok if f is None else f.ok
    reason = m.reason if f is None else f.reason
    put("ok", ok, "")
    put("reason", reason, "")
    rate_text = ", ".join(
        f"{d}: velocity {r.velocity:g} {'rad' if d in angles else length}/{time}, "
        f"acceleration {r.acceleration:g} {'rad' if d in angles else length}/{time}^2"
        for d, r in rates.items()
    )
    title = f"{spec.title or 'Linkage'} ({rate_text})"
    return Table(title, cols, units)


def _driver_column(spec: LinkageFile, driver: str) -> str:
    if driver in spec.angle_drivers:
        return f"{'phi' if driver in spec.motors else 'theta'}_{driver}_deg"
    return f"d_{driver}"


def _kinematics(m: LinkageMotion, put: Callable, length: str, time: str) -> None:
    for link, theta in m.theta.items():
        put(f"theta_{link}_deg", np.degrees(theta), "deg")
        put(f"omega_{link}", m.omega[link], f"rad/{time}")
        put(f"alpha_{link}", m.alpha[link], f"rad/{time}^2")
    for joint, d in m.lengths.items():
        put(f"d_{joint}", d, length)
        put(f"ddot_{joint}", m.length_rate[joint], f"{length}/{time}")


def _forces(
    f: LinkageForces,
    angles: frozenset[str],
    torsions: frozenset[str],
    put: Callable,
    length: str,
    force: str,
) -> None:
    for d, effort in f.driver.items():
        if d in angles:
            put(f"T_{d}", effort, f"{force}*{length}")
        else:
            put(f"F_{d}", effort, force)
    for (a, p), value in f.pins.items():
        put(f"F_{a}_{p}_x", value.real, force)
        put(f"F_{a}_{p}_y", value.imag, force)
    for name, effort in f.elements.items():
        if name in torsions:
            put(f"tau_{name}", effort, f"{force}*{length}")
        else:
            put(f"T_{name}", effort, force)


# ---------------------------------------------------------------- presenting
def write_csv(table: Table, path: str | Path) -> None:
    """Write every column of ``table`` (unrounded) to ``path`` with the csv module.

    The header row holds the column names (units are in ``table.units``);
    ``ok`` is written ``true``/``false``, a sample without a value an empty cell.

    Examples
    --------
    >>> import tempfile
    >>> spec = load(EXAMPLES / "lid.toml")
    >>> out = Path(tempfile.mkdtemp()) / "lid.csv"
    >>> write_csv(analyse(spec, driver_values(spec)), out)
    >>> out.read_text().splitlines()[0]
    'theta_lid_deg,omega_lid,alpha_lid,A_x,A_y,Q_x,Q_y,ok,reason'
    """
    with open(path, "w", newline="", encoding="utf-8") as out:
        writer = csv.writer(out)
        names = list(table.columns)
        writer.writerow(names)
        for row in table.rows():
            writer.writerow(_csv_cell(row[k]) for k in names)


def _csv_cell(value: Any) -> Any:
    if isinstance(value, np.bool_ | bool):
        return str(bool(value)).lower()
    if isinstance(value, float | np.floating):
        return "" if not math.isfinite(value) else repr(float(value))
    return value


def _print(table: Table, drivers: int, forces_from: str | None) -> None:
    """The kinematics table, then (with --forces) the forces table, then the flagged rows."""
    names = list(table.columns)
    leading, end = names[:drivers], names.index("ok")
    cut = names.index(forces_from) if forces_from else end
    parts = [("Kinematics", names[drivers:cut])]
    if forces_from:
        parts.append(("Forces", names[cut:end]))
    rows = table.rows()
    for heading, part in parts:
        shown = [*leading, *part, "ok"]
        headers = [_header(k, table.units[k]) for k in shown]
        body = [[("yes" if r["ok"] else "NO") if k == "ok" else r[k] for k in shown] for r in rows]
        print_table(f"{heading}: {table.title}", headers, body)
        print()
    first = names[0]
    for r in rows:
        if not r["ok"]:
            print(f"  {first} = {r[first]:g}: {r['reason']}")


def _header(name: str, unit: str) -> str:
    # spaces let rich wrap a long header instead of cutting it; the unit in brackets
    label = name.removesuffix("_deg").replace("_", " ")
    return f"{label} [{unit}]" if unit else label


def linkage(
    file: Annotated[Path, typer.Argument(help="The linkage's TOML file (see docs/linkage.md).")],
    sweep: Annotated[
        str | None,
        typer.Option(help="Sweep one driver: DRIVER=START:STOP:STEP (degrees for angles)."),
    ] = None,
    at: Annotated[
        list[str] | None,
        typer.Option(help="Hold a driver: DRIVER=VALUE (degrees for angles); repeatable."),
    ] = None,
    forces: Annotated[
        bool, typer.Option("--forces", help="Add driver efforts, pin forces and spring loads.")
    ] = False,
    json: Annotated[bool, typer.Option("--json", help="Print machine-readable JSON.")] = False,
    csv_out: Annotated[
        Path | None, typer.Option("--csv", help="Also write the full table to this CSV file.")
    ] = None,
) -> None:
    """Solve a linkage described in a TOML file and print its kinematics (and forces)."""
    spec = load(file)
    table = analyse(spec, driver_values(spec, sweep, at or ()), with_forces=forces)
    if csv_out is not None:
        write_csv(table, csv_out)
    if json:
        print(dumps({"title": table.title, "units": table.units, "rows": table.rows()}))
    else:
        efforts = [k for k in table.columns if k.startswith(("T_", "F_"))]
        _print(table, len(spec.drivers), efforts[0] if forces else None)
        if csv_out is not None:
            print(f"\nwrote {csv_out}")
