"""Units at the boundary: the kinds of quantity, unit systems, and pint conversion.

The numeric core of machdyn is unit-agnostic: it computes in any consistent
system. A model read from a machine file (or built from pint quantities)
carries a :class:`UnitSystem` — the length, mass and time units it computes in
(angles always in radians inside) and the units its results are shown in — so
that tables, ``to_pandas()`` columns, CSV headers and drawings say what their
numbers are.

pint is imported only when a unit has to be parsed or converted (it costs about
0.15 s), through one :func:`registry`; conversions are cached per unit text.

Examples
--------
>>> mm = UnitSystem(length="mm", mass="kg", time="s", force="N")
>>> mm.internal("force"), mm.display("force"), mm.display("torque")
('kg*mm/s^2', 'N', 'N*mm')
>>> round(mm.factor("force"), 12)   # a force in kg*mm/s^2 is shown in N
0.001
>>> mm.label("T12", "torque")
'T12 [N*mm]'
>>> to_internal("1500 rpm", "angular_velocity", mm)
157.07963267948966
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from functools import cache
from typing import Any

from .errors import InputError

__all__ = ["KINDS", "Kind", "UnitSystem", "registry"]


@dataclass(frozen=True)
class Kind:
    """A kind of quantity: its dimension in length, mass, time and angle.

    ``radian`` is the exponent of the angle (pint counts angles as dimensionless:
    the exponent is checked on the unit itself, so ``'10 Hz'`` is not taken for
    an angular velocity). ``loose_radian`` accepts the unit without its angle
    too (a torsional stiffness in ``N*m`` as well as ``N*m/rad``).
    """

    name: str
    length: int = 0
    mass: int = 0
    time: int = 0
    radian: int = 0
    example: str = ""
    loose_radian: bool = False

    @property
    def article(self) -> str:
        """``'a length'``, ``'an angle'``: the kind in a sentence."""
        words = self.name.replace("_", " ")
        return ("an " if words[0] in "aeiou" else "a ") + words


def _kinds(*kinds: Kind) -> dict[str, Kind]:
    return {k.name: k for k in kinds}


#: Every kind of quantity a machine file holds, with an example for messages.
KINDS: dict[str, Kind] = _kinds(
    Kind("length", length=1, example="120 mm"),
    Kind("mass", mass=1, example="2.5 kg"),
    Kind("time", time=1, example="0.5 s"),
    Kind("angle", radian=1, example="30 deg"),
    Kind("angular_velocity", time=-1, radian=1, example="1500 rpm"),
    Kind("angular_acceleration", time=-2, radian=1, example="20 rad/s^2"),
    Kind("angular_jerk", time=-3, radian=1, example="100 rad/s^3"),
    Kind("velocity", length=1, time=-1, example="2 m/s"),
    Kind("acceleration", length=1, time=-2, example="9.81 m/s^2"),
    Kind("jerk", length=1, time=-3, example="100 m/s^3"),
    Kind("force", mass=1, length=1, time=-2, example="10 N"),
    Kind("torque", mass=1, length=2, time=-2, example="20 N*m"),
    Kind("energy", mass=1, length=2, time=-2, example="50 J"),
    Kind("inertia", mass=1, length=2, example="0.01 kg*m^2"),
    Kind("stiffness", mass=1, time=-2, example="500 N/m"),
    Kind("damping", mass=1, time=-1, example="20 N*s/m"),
    Kind(
        "torsional_stiffness",
        mass=1,
        length=2,
        time=-2,
        radian=-1,
        example="2 N*m/rad",
        loose_radian=True,
    ),
    Kind(
        "torsional_damping",
        mass=1,
        length=2,
        time=-1,
        radian=-1,
        example="0.1 N*m*s/rad",
        loose_radian=True,
    ),
    Kind("density", mass=1, length=-3, example="7850 kg/m^3"),
    Kind("inverse_length", length=-1, example="8 1/in"),
    Kind("unbalance", mass=1, length=1, example="0.02 kg*m"),
    Kind("moment_of_unbalance", mass=1, length=2, example="0.004 kg*m^2"),
    Kind("dimensionless", example="0.3"),
)

_EXAMPLE_UNITS = {
    "length": "mm",
    "mass": "kg",
    "time": "s",
    "angle": "deg",
    "force": "N",
    "torque": "N*m",
    "angular_velocity": "rpm",
}

#: Base units of a declared system whose table leaves them out.
SI_BASE = {"length": "m", "mass": "kg", "time": "s"}
#: Labels of a unit-free system (numbers in any consistent units).
FREE = {"length": "L", "mass": "M", "time": "T", "force": "F"}
STANDARD_GRAVITY = 9.80665  # m/s^2

_NUMBER = re.compile(
    r"^\s*([+-]?(?:(?:\d[\d_]*)?\.?\d[\d_]*(?:[eE][+-]?\d+)?|nan|inf|infinity))\s*(.*?)\s*$",
    re.IGNORECASE,
)


# units machdyn adds to pint's; the on-disk memo (_Memo) is keyed by them too, so a memo
# written before a definition changed is not read
_DEFINITIONS = ("rev = revolution",)  # pint knows 'revolution' and 'rpm', not 'rev' (rev/s)


@cache
def registry() -> Any:
    """The one pint ``UnitRegistry`` of machdyn (created on first use, cached on disk).

    Examples
    --------
    >>> registry().Quantity("2 in").to("mm").magnitude
    50.8
    """
    import pint

    try:
        ureg = pint.UnitRegistry(cache_folder=":auto:")
    except Exception:  # pragma: no cover - a read-only or unusable cache folder
        ureg = pint.UnitRegistry()
    for line in _DEFINITIONS:
        ureg.define(line)
    return ureg


def _kind(kind: Any) -> Kind:
    if not isinstance(kind, str) or kind not in KINDS:
        raise InputError("kind", f"must be one of {', '.join(KINDS)}; got {kind!r}")
    return KINDS[kind]


@cache  # pure, and called for every column label of every table
def _compose(*parts: tuple[str, int]) -> str:
    """``'kg*mm/s^2'`` from ``(('kg', 1), ('mm', 1), ('s', -2))``; simple names stay bare."""

    def wrap(unit: str) -> str:
        return f"({unit})" if re.search(r"[*/^ ]", unit) else unit

    parts = tuple((u, n) for u, n in parts if n)
    several = len(parts) > 1

    def power(unit: str, n: int) -> str:
        if n == 1:
            return wrap(unit) if several else unit
        return f"{wrap(unit)}^{n}"

    top = [power(u, n) for u, n in parts if n > 0]
    bottom = [power(u, -n) for u, n in parts if n < 0]
    text = "*".join(top) or "1"
    for b in bottom:
        text += "/" + b
    return text


@dataclass(frozen=True)
class UnitSystem:
    """The units a model computes in (length, mass, time) and shows its results in.

    Parameters
    ----------
    length, mass, time : str or None
        Base units (pint names or symbols, e.g. ``"mm"``, ``"kg"``, ``"s"``).
        All None: a unit-free system (numbers in any consistent units, labelled
        ``L``, ``M``, ``T``, ``F``).
    angle : str
        Unit angles are shown in (``"deg"`` or ``"rad"``; inside they are radians).
    force, torque, angular_velocity : str, optional
        Units forces, torques and angular speeds are shown in (default ``N``,
        force × length, and rad per time unit).

    Examples
    --------
    >>> UnitSystem().is_unit_free, UnitSystem().label("P_x", "length")
    (True, 'P_x [L]')
    >>> UnitSystem(length="in", mass="lbf*s^2/in", force="lbf").display("inertia")
    '(lbf*s^2/in)*in^2'
    """

    length: str | None = None
    mass: str | None = None
    time: str | None = None
    angle: str = "deg"
    force: str | None = None
    torque: str | None = None
    angular_velocity: str | None = None
    _factors: dict = field(default_factory=dict, init=False, repr=False, compare=False, hash=False)

    def __post_init__(self) -> None:
        for key in ("length", "mass", "time", "angle", "force", "torque", "angular_velocity"):
            value = getattr(self, key)
            if value is None and key != "angle":
                continue
            if not isinstance(value, str) or not value.strip():
                example = _EXAMPLE_UNITS[key]
                raise InputError(key, f"expected a unit name like {example!r}, got {value!r}")
            try:
                check_unit(value, key)
            except ValueError as exc:
                raise InputError(key, str(exc)) from None
        given = [self.length, self.mass, self.time]
        if any(given) and not all(given):
            for key, default in SI_BASE.items():
                if getattr(self, key) is None:
                    object.__setattr__(self, key, default)
        if self.length is not None and self.force is None:
            object.__setattr__(self, "force", "N")

    @property
    def is_unit_free(self) -> bool:
        """True when numbers carry no units (any consistent system)."""
        return self.length is None

    def _base(self) -> dict[str, str]:
        if self.is_unit_free:
            return FREE
        return {"length": self.length, "mass": self.mass, "time": self.time}  # type: ignore[dict-item]

    def internal(self, kind: str) -> str:
        """The coherent unit a quantity of ``kind`` is held in (radians for angles)."""
        k = _kind(kind)
        b = self._base()
        return _compose(
            (b["mass"], k.mass), (b["length"], k.length), (b["time"], k.time), ("rad", k.radian)
        )

    def display(self, kind: str) -> str:
        """The unit a quantity of ``kind`` is shown in (labels, tables, files)."""
        if not isinstance(kind, str):
            _kind(kind)  # refused, naming the field
        shown = self._factors.get(("display", kind))  # the system is frozen: compose once
        if shown is None:
            shown = self._factors[("display", kind)] = self._display(kind)
        return shown

    def _display(self, kind: str) -> str:
        k = _kind(kind)
        b = self._base()
        force = self.force or FREE["force"]
        torque = self.torque or _compose((force, 1), (b["length"], 1))
        named = {
            "length": b["length"],
            "mass": b["mass"],
            "time": b["time"],
            "angle": self.angle,
            "force": force,
            "torque": torque,
            "energy": torque,
            "angular_velocity": self.angular_velocity or _compose(("rad", 1), (b["time"], -1)),
            "stiffness": _compose((force, 1), (b["length"], -1)),
            "damping": _compose((force, 1), (b["time"], 1), (b["length"], -1)),
            "torsional_stiffness": _compose((torque, 1), ("rad", -1)),
            "torsional_damping": _compose((torque, 1), (b["time"], 1), ("rad", -1)),
            "dimensionless": "",
        }
        if kind in named:
            return named[kind]
        return _compose(
            (b["mass"], k.mass), (b["length"], k.length), (b["time"], k.time), ("rad", k.radian)
        )

    def factor(self, kind: str) -> float:
        """Multiply a value held in :meth:`internal` units by this to show it in :meth:`display`."""
        _kind(kind)
        if kind not in self._factors:
            src, dst = self.internal(kind), self.display(kind)
            if src == dst:
                value = 1.0
            elif self.is_unit_free:
                # only angles change: rad -> deg in the rates' numerators
                value = 1.0
                if kind == "angle" and self.angle != "rad":
                    value = _factor("rad", self.angle)
            else:
                value = _factor(src, dst)
            self._factors[kind] = value
        return self._factors[kind]

    def show(self, kind: str, value: Any) -> Any:
        """``value`` (internal units, NaN where a sample has none) in display units."""
        import numpy as np

        f = self.factor(kind)
        if isinstance(value, list | tuple):
            value = np.asarray(value, dtype=float)
        return value if f == 1.0 else value * f

    def label(self, name: str, kind: str) -> str:
        """A column name with its display unit: ``'theta3 [deg]'`` (no brackets when unitless)."""
        if not isinstance(name, str):
            raise InputError("name", f"a column name is text, got {name!r}")
        unit = self.display(kind)
        return f"{name} [{unit}]" if unit else name

    def to_spec(self) -> dict[str, str]:
        """The ``[units]`` table of a machine file (empty for a unit-free system)."""
        if self.is_unit_free:
            return {} if self.angle == "deg" else {"angle": self.angle}
        out = {"length": self.length, "mass": self.mass, "time": self.time, "angle": self.angle}
        for key in ("force", "torque", "angular_velocity"):
            if getattr(self, key) is not None:
                out[key] = getattr(self, key)
        return out  # type: ignore[return-value]


@cache
def _unit(text: str) -> Any:
    """The pint unit of ``text``; :class:`ValueError` naming it if pint does not know it."""
    ureg = registry()
    try:
        return ureg.Unit(text.replace("^", "**"))
    except Exception as exc:
        bad = getattr(exc, "unit_names", None) or [text]
        raise ValueError(f"unknown unit {', '.join(map(repr, bad))}") from None


class _Memo:
    """pint's answers (conversion factors, dimensions of a unit) kept on disk between runs.

    Importing pint and building its registry costs about 0.15 s, a quarter of
    the cold-start budget of ``machdyn run``; a file's units are nearly always
    the same few, so their factors and dimensions are remembered in
    ``$XDG_CACHE_HOME/machdyn/units-*.json`` (keyed by pint's installed files and
    machdyn's own unit definitions) and
    pint is imported only for a unit not seen before. ``MACHDYN_UNIT_CACHE=off``
    disables the file.
    """

    def __init__(self) -> None:
        self.data: dict[str, dict] | None = None
        self.dirty = False

    def _path(self) -> Any:
        import os
        from pathlib import Path

        if os.environ.get("MACHDYN_UNIT_CACHE", "").lower() in ("off", "0", "no"):
            return None
        import importlib.util

        found = importlib.util.find_spec("pint")
        if found is None or not found.origin:
            return None
        import zlib

        stamp = int(os.stat(found.origin).st_mtime)
        ours = zlib.crc32("\n".join(_DEFINITIONS).encode())
        home = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        return Path(home) / "machdyn" / f"units-{stamp}-{ours:08x}.json"

    def table(self, name: str) -> dict:
        if self.data is None:
            self.data = {"factor": {}, "signature": {}}
            path = self._path()
            if path is not None:
                try:
                    import json

                    loaded = json.loads(path.read_text(encoding="utf-8"))
                    if isinstance(loaded, dict):
                        for key in self.data:
                            if isinstance(loaded.get(key), dict):
                                self.data[key] = loaded[key]
                except (OSError, ValueError):
                    pass
        return self.data[name]

    def put(self, name: str, key: str, value: Any) -> None:
        self.table(name)[key] = value
        if not self.dirty:
            import atexit

            self.dirty = True
            atexit.register(self.save)

    def save(self) -> None:
        path = self._path()
        if path is None or self.data is None:
            return
        try:
            import json
            import os

            path.parent.mkdir(parents=True, exist_ok=True)
            tmp = path.with_suffix(f".{os.getpid()}.tmp")
            tmp.write_text(json.dumps(self.data), encoding="utf-8")
            os.replace(tmp, path)
        except OSError:  # pragma: no cover - a read-only home: pint answers next time
            pass


_MEMO = _Memo()


@cache
def _factor(src: str, dst: str) -> float:
    key = f"{src}|{dst}"
    known = _MEMO.table("factor").get(key)
    if isinstance(known, float):
        return known
    ureg = registry()
    value = float(ureg.Quantity(1.0, _unit(src)).to(_unit(dst)).magnitude)
    _MEMO.put("factor", key, value)
    return value


@cache
def _signature(text: str) -> tuple[tuple[int, int, int], int, int]:
    """((length, mass, time), radian exponent, other dimensions) of a unit."""
    known = _MEMO.table("signature").get(text)
    if isinstance(known, list) and len(known) == 5:
        return (int(known[0]), int(known[1]), int(known[2])), int(known[3]), int(known[4])
    ureg = registry()
    unit = _unit(text)
    dims = ureg.get_dimensionality(unit)
    lmt = (int(dims.get("[length]", 0)), int(dims.get("[mass]", 0)), int(dims.get("[time]", 0)))
    other = sum(1 for d in dims if d not in ("[length]", "[mass]", "[time]"))
    _, root = ureg.get_root_units(unit)
    radian = int(dict(root._units).get("radian", 0))
    _MEMO.put("signature", text, [*lmt, radian, other])
    return lmt, radian, other


def describe(unit: str) -> str:
    """The kind a unit measures, for messages: ``'a length'``, ``'a frequency'``.

    Examples
    --------
    >>> describe("kg"), describe("Hz")
    ('a mass', 'a frequency; write a turning speed in rev/s, rad/s or rpm')
    """
    lmt, radian, other = _signature(unit)
    if other:
        return f"not a mechanical quantity ({registry().get_dimensionality(_unit(unit))})"
    for k in KINDS.values():
        if (k.length, k.mass, k.time) == lmt and k.radian == radian and k.name != "energy":
            return k.article
    if lmt == (0, 0, -1) and radian == 0:
        return "a frequency; write a turning speed in rev/s, rad/s or rpm"
    return f"a quantity in {unit}"


def check_unit(unit: str, kind: str) -> None:
    """Raise :class:`ValueError` unless ``unit`` measures a quantity of ``kind``.

    Examples
    --------
    >>> check_unit("rpm", "angular_velocity")
    >>> check_unit("m", "mass")
    Traceback (most recent call last):
    ...
    ValueError: expected a mass like '2.5 kg', got a unit of a length ('m')
    """
    k = KINDS[kind]
    lmt, radian, other = _signature(unit)
    radians_ok = radian == k.radian or (k.loose_radian and radian == 0)
    if other or lmt != (k.length, k.mass, k.time) or not radians_ok:
        raise ValueError(
            f"expected {k.article} like {k.example!r}, got a unit of {describe(unit)} ({unit!r})"
        )


def parse(text: str) -> tuple[float, str]:
    """Split ``'120 mm'`` into ``(120.0, 'mm')`` (unit ``''`` for a bare number).

    Examples
    --------
    >>> parse("120 mm"), parse("-1.5e3 N*m"), parse(" 7 ")
    ((120.0, 'mm'), (-1500.0, 'N*m'), (7.0, ''))
    """
    match = _NUMBER.match(text)
    if not match or match.group(1).lstrip("+-").startswith("_"):
        raise ValueError(f"expected a number and a unit like '120 mm', got {text!r}")
    return float(match.group(1).replace("_", "")), match.group(2)


def to_internal(text: str, kind: str, system: UnitSystem) -> float:
    """Convert a quantity written as text into ``system``'s internal unit for ``kind``.

    Raises :class:`ValueError` with the reason (unknown unit, wrong kind, not a
    number); the caller names the key.
    """
    value, unit = parse(text)
    if not unit:
        raise ValueError("no unit")
    check_unit(unit, kind)
    if system.is_unit_free:
        raise ValueError("a unit-free file cannot hold quantities with units")
    return value * _factor(unit, system.internal(kind))


def standard_gravity(system: UnitSystem) -> float:
    """9.80665 m/s² in ``system``'s acceleration unit.

    Examples
    --------
    >>> round(standard_gravity(UnitSystem(length="mm", mass="kg", time="s")), 6)
    9806.65
    """
    if system.is_unit_free:
        raise InputError("gravity", "standard gravity needs a unit system")
    return STANDARD_GRAVITY * _factor("m/s^2", system.internal("acceleration"))


def is_finite(value: float) -> bool:
    """``math.isfinite`` (re-exported for the spec reader)."""
    return math.isfinite(value)


#: Kind of each rate column of a motion result, by its first letters.
RATE_KINDS = {"omega": "angular_velocity", "alpha": "angular_acceleration", "jerk": "angular_jerk"}


def columns(
    system: UnitSystem | None,
    spec: list[tuple[str, str | None, Any]],
    degrees: bool = False,
) -> dict[str, Any]:
    """Table columns of a result: labelled with units when the model has a unit system.

    ``spec`` lists ``(name, kind, values)``; ``kind`` None leaves a column (flags,
    text) as it is. Angles are radians unless ``degrees``. Without a unit system
    (a unit-free model) the names stay bare (angles in degrees get ``_deg``).

    Examples
    --------
    >>> import numpy as np
    >>> cols = columns(UnitSystem(length="mm"), [("theta2", "angle", np.array([np.pi])),
    ...                                          ("P_x", "length", np.array([2.0]))], degrees=True)
    >>> {k: v.tolist() for k, v in cols.items()}
    {'theta2 [deg]': [180.0], 'P_x [mm]': [2.0]}
    >>> list(columns(None, [("theta2", "angle", np.array([0.0]))], degrees=True))
    ['theta2_deg']
    """
    import numpy as np

    out: dict[str, Any] = {}
    for name, kind, values in spec:
        values = np.ravel(values)
        base, per, over = (kind or "").partition("/")
        if per and system is not None:  # a derivative per radian of cam angle: "length/rad"
            shown = "deg" if base == "angle" and degrees else system.display(base)
            if base == "angle":
                values = np.degrees(values) if degrees else values
            else:
                values = system.show(base, values)
            out[f"{name} [{shown}/{over}]"] = values
        elif per:
            out[name] = values
        elif kind == "angle":
            if degrees:
                values = np.degrees(values)
            if system is None:
                out[f"{name}_deg" if degrees else name] = values
            else:
                out[f"{name} [{'deg' if degrees else 'rad'}]"] = values
        elif kind is None or system is None:
            out[name] = values
        else:
            out[system.label(name, kind)] = system.show(kind, values)
    return out


def with_units(result: Any, system: UnitSystem | None) -> Any:
    """``result`` with ``result.units = system`` (a frozen result too); unit-free: as is.

    A result's ``to_pandas()`` then names its columns with units (``s [mm]``).

    Examples
    --------
    >>> from machdyn.cams import CamProgram
    >>> m = with_units(CamProgram.double_dwell(25.0, 1.0, 1.0).sample(4), UnitSystem(length="mm"))
    >>> list(m.to_pandas())[:3]
    ['theta [deg]', 's [mm]', 'v [mm/rad]']
    """
    if system is not None and not system.is_unit_free:
        object.__setattr__(result, "units", system)
    return result


def units_of(result: Any) -> UnitSystem | None:
    """The unit system a result was given (:func:`with_units`), or None."""
    system = getattr(result, "units", None)
    return system if isinstance(system, UnitSystem) and not system.is_unit_free else None


def from_quantity_unit(length: str | None) -> UnitSystem | None:
    """The unit system of a model whose lengths were pint quantities in ``length`` (or None).

    Examples
    --------
    >>> from_quantity_unit("millimeter").length
    'mm'
    """
    if length is None:
        return None
    try:
        short = format(_unit(length), "~").replace(" ", "")
    except ValueError:  # pragma: no cover - pint gave the name, pint knows it
        short = length
    return UnitSystem(length=short)


#: Angles given in radians beyond this many turns were most likely meant as degrees.
DEGREE_TURNS = 10


def warn_if_degrees(field: str, values: Any, stacklevel: int = 3) -> None:
    """Warn when an angle in radians reaches beyond ten turns: degrees, most likely.

    ``solve(np.arange(0, 360))`` sweeps 57 turns: the hint says so and how to
    write it (the gear module refuses a pressure angle in degrees the same way).

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     warn_if_degrees("theta2", [0.0, 90.0, 359.0])
    >>> print(caught[0].message)
    theta2 reaches 359 rad (57 turns): did you pass degrees? use np.radians(...) or a pint quantity
    """
    import warnings

    import numpy as np

    a = np.abs(np.asarray(values, dtype=float))
    if a.size == 0:
        return
    top = float(np.nanmax(a)) if np.isfinite(a).any() else 0.0
    if top > DEGREE_TURNS * 2.0 * math.pi:
        warnings.warn(
            f"{field} reaches {top:g} rad ({top / (2 * math.pi):.0f} turns): did you pass "
            "degrees? use np.radians(...) or a pint quantity",
            UserWarning,
            stacklevel=stacklevel,
        )


#: AutoCAD's ``$INSUNITS`` code of each length unit (pint's name); 0 is "unitless".
DXF_INSUNITS = {
    "inch": 1,
    "foot": 2,
    "mile": 3,
    "millimeter": 4,
    "centimeter": 5,
    "meter": 6,
    "kilometer": 7,
    "microinch": 8,
    "thou": 9,
    "yard": 10,
    "angstrom": 11,
    "nanometer": 12,
    "micrometer": 13,
    "decimeter": 14,
}
_IMPERIAL = {1, 2, 3, 8, 9, 10}


def dxf_units(unit: str | None) -> tuple[int, int]:
    """``($INSUNITS, $MEASUREMENT)`` of a DXF file whose numbers are in ``unit``.

    ``None`` (numbers in no declared unit) gives 0, "unitless"; a length unit
    without an AutoCAD code is refused (convert the drawing to mm or in).

    Examples
    --------
    >>> dxf_units("mm"), dxf_units("in"), dxf_units(None)
    ((4, 1), (1, 0), (0, 1))
    """
    if unit is None:
        return 0, 1
    if not isinstance(unit, str):
        raise InputError("unit", f"expected a length unit like 'mm', got {unit!r}")
    try:
        check_unit(unit, "length")
        name = str(_unit(unit))
    except ValueError as exc:
        raise InputError("unit", str(exc)) from None
    if name not in DXF_INSUNITS:
        listed = ", ".join(DXF_INSUNITS)
        raise InputError("unit", f"DXF has no code for {unit!r}; use one of {listed}")
    code = DXF_INSUNITS[name]
    return code, 0 if code in _IMPERIAL else 1


def set_dxf_units(doc: Any, unit: str | None) -> None:
    """Write the true unit into an ezdxf document (``$INSUNITS``, ``$MEASUREMENT``)."""
    code, measurement = dxf_units(unit)
    doc.header["$INSUNITS"] = code
    doc.header["$MEASUREMENT"] = measurement


def svg_size(width: float, height: float, unit: str | None) -> str:
    """``width="..mm" height="..mm"`` for an SVG drawn in ``unit`` (empty without a unit).

    Examples
    --------
    >>> svg_size(2.0, 1.0, "in")
    'width="50.8mm" height="25.4mm" '
    """
    if unit is None:
        return ""
    dxf_units(unit)  # a length unit, or the error naming it
    mm = _factor(unit, "mm")
    return f'width="{width * mm:.6g}mm" height="{height * mm:.6g}mm" '
