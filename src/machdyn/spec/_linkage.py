"""Part kind ``linkage``: a drawn :class:`~machdyn.linkage.Linkage`, its motion and its loads.

Every argument of the builder has a key (points, links, sliders, slots,
actuators, rolling contacts, motors, springs, torsion springs, drivers), and so
has what ``Linkage.forces`` takes (external forces and torques, friction;
gravity is the machine's). Elements are named by their table keys. Writing back
reads the linkage's public view (``points``, ``links``, ``joints``,
``elements``, ``drivers``). No physics here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._context import Context, _show
from ._machine import Machine, Part, PartKind
from ._run import PartResult, ResultTable, Summary, TorqueCurve, flagged_rows
from ._simulate import LINKAGE_TOLERANCE
from ._types import (
    Boolean,
    Choice,
    Grid,
    ListOf,
    MapOf,
    Name,
    Names,
    OneOf,
    Position,
    Quantity,
    Sweep,
    Table,
    Text,
    Type,
    fields,
    optional,
    required,
)

__all__ = ["PART_KINDS", "DriverSetting"]


class Vector(Position):
    """A direction ``[dx, dy]`` of plain numbers (not both zero)."""

    def __init__(self) -> None:
        super().__init__("dimensionless")
        self.what = "a direction [dx, dy]"

    def read(self, ctx: Context, path: tuple, value: Any) -> complex:
        z = super().read(ctx, path, value)
        if z == 0:
            raise ctx.error(path, "a direction [dx, dy] must not be [0, 0]")
        return z


class Radius(Type):
    """A positive length, or ``"straight"`` (an infinite radius: a rack, a flat track)."""

    what = 'a length or "straight"'

    def accepts(self, value: Any) -> bool:
        return True

    def read(self, ctx: Context, path: tuple, value: Any) -> float:
        if value == "straight":
            return math.inf
        return Quantity("length", positive=True).read(ctx, path, value)

    def write(self, w: Any, value: Any) -> Any:
        return "straight" if math.isinf(value) else w.quantity(value, "length")

    def owns(self, value: Any) -> bool:
        return isinstance(value, float)

    def schema(self) -> dict:
        return {"anyOf": [Quantity("length", positive=True).schema(), {"const": "straight"}]}


class Raw(Type):
    """A value read later, once its kind is known (a driver's values: angle or length)."""

    what = "a value"

    def __init__(self, schema: dict) -> None:
        self._schema = schema

    def read(self, ctx: Context, path: tuple, value: Any) -> Any:
        return (path, value)

    def schema(self) -> dict:
        return self._schema


@dataclass(frozen=True)
class DriverSetting:
    """A driver's values and rates in internal units; ``kind`` is ``"angle"`` or ``"length"``."""

    kind: str
    values: Grid | None = None
    velocity: float | None = None
    acceleration: float | None = None
    driven_by: str | None = None


_EITHER = {"anyOf": [{"$ref": "#/$defs/angle"}, {"$ref": "#/$defs/length"}]}
_SWEEP = {"anyOf": [_EITHER, {"type": "array", "items": _EITHER, "minItems": 3, "maxItems": 3}]}
_RATE = {"anyOf": [{"$ref": "#/$defs/angular_velocity"}, {"$ref": "#/$defs/velocity"}]}
_ACC = {"anyOf": [{"$ref": "#/$defs/angular_acceleration"}, {"$ref": "#/$defs/acceleration"}]}


class DriverMotions(MapOf):
    """``[linkage.NAME.motion.<driver>]`` tables; their kinds come from the drivers."""

    def __init__(self) -> None:
        super().__init__(
            Table(
                fields(
                    value=optional(Raw(_EITHER), "one value (angle or length)"),
                    sweep=optional(Raw(_SWEEP), "[start, stop, step]"),
                    velocity=optional(Raw(_RATE), "its rate (default 1 rad/s or 1 length/s)"),
                    acceleration=optional(Raw(_ACC)),
                    driven_by=optional(Name(), "a gear_pair or gear_train turning this driver"),
                )
            ),
            "a table of [motion.<driver>] tables",
        )

    def write(self, w: Any, value: Any) -> Any:
        out = {}
        for name, s in value.items():
            rate = "angular_velocity" if s.kind == "angle" else "velocity"
            acc = "angular_acceleration" if s.kind == "angle" else "acceleration"
            entry: dict[str, Any] = {}
            if s.values is not None:
                written = Sweep(s.kind).write(w, s.values)
                entry["sweep" if isinstance(written, list | dict) else "value"] = written
            if s.velocity is not None:
                entry["velocity"] = w.quantity(s.velocity, rate)
            if s.acceleration is not None:
                entry["acceleration"] = w.quantity(s.acceleration, acc)
            if s.driven_by is not None:
                entry["driven_by"] = s.driven_by
            out[name] = entry
        return out


CG = OneOf(Name(), Position(), Quantity("length"))
SHAPE = Table(
    fields(
        rod=optional(Quantity("length", positive=True), "a rod of this length along x"),
        disc=optional(Quantity("length", positive=True), "a disc of this radius"),
        ring=optional(Quantity("length", positive=True), "a thin ring of this radius"),
        plate=optional(Position(), "a plate [width, height]"),
    ),
    doc="the link's shape, for its inertia (one key): rod, disc, ring or plate",
)
LINK = Table(
    fields(
        points=required(Names(minimum=1), "its points; the first two fix its frame"),
        mass=optional(Quantity("mass", minimum=0.0)),
        inertia=optional(Quantity("inertia", minimum=0.0), "about its centre of mass"),
        cg=optional(CG, "centre of mass: a point name, [x, y] or a length along x"),
        shape=optional(SHAPE),
    )
)
DIRECTION = OneOf(Name(), Vector(), Quantity("angle"), what="an angle, [dx, dy] or a point name")
SLIDER = Table(
    fields(
        block=required(Name()),
        on=required(Name()),
        at=required(Name()),
        direction=optional(DIRECTION),
        through=optional(Name()),
        centre=optional(Name(), "a curved guide: the point of `on` at its centre of curvature"),
        radius=optional(Quantity("length", positive=True), "a curved guide's radius (checked)"),
    )
)
SLOT = Table(
    fields(
        pin=required(Name()),
        link=required(Name()),
        on=required(Name()),
        direction=optional(DIRECTION),
        through=optional(Name()),
        centre=optional(Name(), "a curved guide: the point of `on` at its centre of curvature"),
        radius=optional(Quantity("length", positive=True), "a curved guide's radius (checked)"),
    )
)
ACTUATOR = Table(fields(start=required(Name()), end=required(Name()), links=optional(Names(2))))
ROLL = Table(
    fields(
        link_a=required(Name()),
        centre_a=required(Name()),
        radius_a=required(Quantity("length", positive=True)),
        link_b=required(Name()),
        centre_b=required(Name()),
        radius_b=required(Radius()),
        internal=optional(Boolean()),
    )
)
MOTOR = Table(fields(at=required(Name()), links=optional(Names(2))))
SPRING = Table(
    fields(
        start=required(Name()),
        end=required(Name()),
        stiffness=required(Quantity("stiffness")),
        free_length=required(Quantity("length", minimum=0.0)),
        damping=optional(Quantity("damping")),
        preload=optional(Quantity("force")),
        links=optional(Names(2)),
    )
)
TORSION = Table(
    fields(
        at=required(Name()),
        stiffness=required(Quantity("torsional_stiffness")),
        free_angle=required(Quantity("angle")),
        damping=optional(Quantity("torsional_damping")),
        preload=optional(Quantity("torque")),
        links=optional(Names(2)),
    )
)
FORCE = Table(
    fields(
        link=required(Name()),
        at=required(OneOf(Name(), Position()), "a point name, or [x, y] in the link frame"),
        force=required(Position("force"), "[Fx, Fy] in the ground frame"),
    )
)
FRICTION = Table(
    fields(
        coulomb=optional(Quantity("dimensionless", minimum=0.0), "Coulomb coefficient mu"),
        viscous=optional(Quantity("damping", minimum=0.0), "viscous coefficient"),
    )
)

LINKAGE = Table(
    fields(
        points=required(MapOf(Position(), "a table of name = [x, y]", minimum=1)),
        ground=required(Names(minimum=1), "points fixed to the frame"),
        drive=required(Names(minimum=1), "the drivers, in order"),
        report=optional(Names(), "points whose positions, velocities, accelerations are shown"),
        links=optional(MapOf(LINK, "a table of [links.<name>] tables")),
        sliders=optional(MapOf(SLIDER)),
        slots=optional(MapOf(SLOT)),
        actuators=optional(MapOf(ACTUATOR)),
        rolls=optional(MapOf(ROLL)),
        motors=optional(MapOf(MOTOR)),
        springs=optional(MapOf(SPRING)),
        torsion_springs=optional(MapOf(TORSION)),
        motion=optional(DriverMotions()),
        forces=optional(ListOf(FORCE), "external point forces: [[linkage.NAME.forces]]"),
        torques=optional(MapOf(Quantity("torque"), "a table of link = torque")),
        friction=optional(MapOf(FRICTION, "a table of [friction.<slider or slot>] tables")),
        tolerance=optional(LINKAGE_TOLERANCE, "for `machdyn tolerance`"),
        notes=optional(Text()),
    ),
    doc="a drawn linkage: points, links, joints, drivers, elements and loads",
)


# ------------------------------------------------------------------- building
def _body(ctx: Context, path: tuple, e: dict) -> dict[str, Any]:
    """The mass keywords of :meth:`Linkage.link` for a link table."""
    from ..massprops import MassProperties, disc, plate, ring, rod

    mass = e.get("mass", 0.0)
    if "shape" in e:
        shape = e["shape"]
        if len(shape) != 1:
            raise ctx.error((*path, "shape"), "give one shape: rod, disc, ring or plate")
        if "inertia" in e:
            raise ctx.error((*path, "inertia"), "give the inertia or a shape, not both")
        if not mass:
            raise ctx.error((*path, "mass"), "a link with a shape needs its mass")
        ((kind, size),) = shape.items()
        with ctx.at((*path, "shape")):
            if kind == "rod":
                body = rod(mass, size)
            elif kind == "plate":
                body = plate(mass, size.real, size.imag)
            else:
                body = (disc if kind == "disc" else ring)(mass, size)
        if "cg" in e:
            if not isinstance(e["cg"], complex | float):
                raise ctx.error(
                    (*path, "cg"), "with a shape, cg is [x, y] or a length (its centre)"
                )
            body = MassProperties(mass, complex(e["cg"]), body.inertia)
        return {"body": body}
    if not mass:
        if "inertia" in e or "cg" in e:
            raise ctx.error((*path, "mass"), "a link with an inertia or a cg needs its mass")
        return {}
    inertia = e.get("inertia", 0.0)
    cg = e.get("cg")
    if inertia == 0.0 and not isinstance(cg, str):  # a point mass
        return {"body": MassProperties(mass, complex(cg or 0.0), 0.0)}
    return {"mass": mass, "inertia": inertia, "cg": cg}


def _build(ctx: Context, path: tuple, v: dict) -> Any:
    from ..linkage import Linkage

    with ctx.at((*path, "points")):
        lk = Linkage(v["points"])
    with ctx.at((*path, "ground")):
        lk.ground(*v["ground"])
    for name, e in v.get("links", {}).items():
        where = (*path, "links", name)
        body = _body(ctx, where, e)
        with ctx.at(where, {"link": where, "points": (*where, "points")}):
            lk.link(name, *e["points"], **body)
    for name, e in v.get("sliders", {}).items():
        with ctx.at((*path, "sliders", name)):
            lk.slider(
                e["block"],
                e["on"],
                e["at"],
                e.get("direction", 0.0),
                through=e.get("through"),
                name=name,
                **_curve(ctx, (*path, "sliders", name), e),
            )
    for name, e in v.get("slots", {}).items():
        with ctx.at((*path, "slots", name)):
            lk.slot(
                e["pin"],
                e["link"],
                e["on"],
                e.get("direction", 0.0),
                through=e.get("through"),
                name=name,
                **_curve(ctx, (*path, "slots", name), e),
            )
    for name, e in v.get("actuators", {}).items():
        with ctx.at((*path, "actuators", name)):
            lk.actuator(name, e["start"], e["end"], links=tuple(e.get("links", ())))
    for name, e in v.get("rolls", {}).items():
        with ctx.at((*path, "rolls", name)):
            lk.roll(
                e["link_a"],
                e["centre_a"],
                e["radius_a"],
                e["link_b"],
                e["centre_b"],
                e["radius_b"],
                internal=e.get("internal", False),
                name=name,
            )
    for name, e in v.get("motors", {}).items():
        with ctx.at((*path, "motors", name)):
            lk.motor(name, e["at"], links=tuple(e["links"]) if "links" in e else None)
    with ctx.at((*path, "drive")):
        lk.drive(*v["drive"])
    for name, e in v.get("springs", {}).items():
        with ctx.at((*path, "springs", name)):
            lk.spring(
                name,
                e["start"],
                e["end"],
                stiffness=e["stiffness"],
                free_length=e["free_length"],
                damping=e.get("damping", 0.0),
                preload=e.get("preload", 0.0),
                links=tuple(e.get("links", ())),
            )
    for name, e in v.get("torsion_springs", {}).items():
        with ctx.at((*path, "torsion_springs", name)):
            lk.torsion_spring(
                name,
                e["at"],
                stiffness=e["stiffness"],
                free_angle=e["free_angle"],
                damping=e.get("damping", 0.0),
                preload=e.get("preload", 0.0),
                links=tuple(e["links"]) if "links" in e else None,
            )
    on_links = {q for ln in lk.links.values() for q in ln.points} | set(lk.ground_points)
    for i, p in enumerate(v.get("report", []), start=1):
        with ctx.at((*path, "report", i)):
            lk.position(p)
        if p not in on_links:  # a loose point moves with nothing: no motion to report
            raise ctx.error(
                (*path, "report", i), f"point {p!r} is on no link: add it to a link's points"
            )
    _check_loads(ctx, path, v, lk)
    v["motion"] = _motions(ctx, path, v.get("motion", {}), lk)
    lk.units = None if ctx.system.is_unit_free else ctx.system
    return lk


def _check_loads(ctx: Context, path: tuple, v: dict, lk: Any) -> None:
    for i, f in enumerate(v.get("forces", []), start=1):
        if f["link"] not in lk.links:
            raise ctx.error((*path, "forces", i, "link"), _not_a(f["link"], "link", lk.links))
        if isinstance(f["at"], str) and f["at"] not in lk.links[f["link"]].points:
            points = lk.links[f["link"]].points
            raise ctx.error((*path, "forces", i, "at"), _not_a(f["at"], "point of it", points))
    for name in v.get("torques", {}):
        if name not in lk.links:
            raise ctx.error((*path, "torques", name), _not_a(name, "link", lk.links))
    joints = {j.name for j in lk.joints if j.kind in ("slider", "slot")}
    for name, fr in v.get("friction", {}).items():
        if name not in joints:
            raise ctx.error((*path, "friction", name), _not_a(name, "slider or slot", joints))
        if not fr:
            raise ctx.error((*path, "friction", name), "give coulomb (mu) and/or viscous")


def _not_a(name: str, what: str, known: Any) -> str:
    return f"{name!r} is not a {what}; {what}s: {', '.join(known) or '(none)'}"


def angle_drivers(lk: Any) -> frozenset[str]:
    """Drivers that are angles (links and motors); the others are lengths."""
    motors = {j.name for j in lk.joints if j.kind == "motor"}
    return frozenset(d for d in lk.drivers if d in lk.links or d in motors)


def _motions(ctx: Context, path: tuple, raw: dict, lk: Any) -> dict[str, DriverSetting]:
    angles = angle_drivers(lk)
    out = {}
    for name, entry in raw.items():
        where = (*path, "motion", name)
        if name not in lk.drivers:
            raise ctx.error(where, _not_a(name, "driver", lk.drivers), table=True)
        kind = "angle" if name in angles else "length"
        rate, acc = (
            ("angular_velocity", "angular_acceleration")
            if kind == "angle"
            else ("velocity", "acceleration")
        )
        if "value" in entry and "sweep" in entry:
            raise ctx.error((*where, "value"), "give value or sweep, not both")
        values = None
        for key in ("value", "sweep"):
            if key in entry:
                p, value = entry[key]
                if key == "sweep" and not isinstance(value, list | dict):
                    raise ctx.error(p, f"expected [start, stop, step], got {_show(value)}")
                values = Sweep(kind).read(ctx, p, value)
        setting = DriverSetting(
            kind,
            values,
            Quantity(rate).read(ctx, *entry["velocity"]) if "velocity" in entry else None,
            Quantity(acc).read(ctx, *entry["acceleration"]) if "acceleration" in entry else None,
            entry.get("driven_by"),
        )
        out[name] = setting
    return out


def _curve(ctx: Context, path: tuple, e: dict) -> dict[str, Any]:
    """``centre``/``radius`` of a curved slider or slot (neither: a straight one)."""
    if "centre" not in e:
        if "radius" in e:
            raise ctx.error((*path, "radius"), "a curved guide needs centre = a point name")
        return {}
    for key in ("direction", "through"):
        if key in e:
            raise ctx.error((*path, key), "a curved guide (centre) takes no direction/through")
    return {"centre": e["centre"], "radius": e.get("radius")}


def _values_of(lk: Any) -> dict[str, Any]:
    out: dict[str, Any] = {
        "points": dict(lk.points),
        "ground": list(lk.ground_points),
        "drive": list(lk.drivers),
    }
    links = {}
    for ln in lk.links.values():
        entry: dict[str, Any] = {"points": list(ln.points)}
        if ln.mass:
            entry["mass"] = ln.mass
            if ln.inertia:
                entry["inertia"] = ln.inertia
            if ln.cg is not None:
                entry["cg"] = ln.cg
        links[ln.name] = entry
    if links:
        out["links"] = links
    by_kind: dict[str, dict] = {}
    for j in lk.joints:
        if j.kind == "slider":
            e = {"block": j.links[0], "on": j.links[1], "at": j.points[0], "direction": j.direction}
        elif j.kind == "slot":
            e = {"pin": j.points[0], "link": j.links[0], "on": j.links[1], "direction": j.direction}
        elif j.kind == "actuator":
            e = {"start": j.points[0], "end": j.points[1], "links": list(j.links)}
        elif j.kind == "roll":
            e = {
                "link_a": j.links[0],
                "centre_a": j.points[0],
                "radius_a": j.radii[0],
                "link_b": j.links[1],
                "centre_b": j.points[1],
                "radius_b": j.radii[1],
            }
            if j.internal:
                e["internal"] = True
        elif j.kind == "motor":
            e = {"at": j.points[0], "links": list(j.links)}
        else:
            continue
        if j.kind in ("slider", "slot") and j.centre is not None:  # a curved guide
            del e["direction"]
            e |= {"centre": j.centre, "radius": j.radius}
        if j.kind in ("slider", "slot") and j.through is not None:
            e["through"] = j.through
        by_kind.setdefault(j.kind + "s", {})[j.name] = e
    for e in lk.elements:
        entry = {"stiffness": e.stiffness, "links": list(e.links)}
        if e.kind == "spring":
            entry |= {"start": e.points[0], "end": e.points[1], "free_length": e.free_length}
        else:
            entry |= {"at": e.points[0], "free_angle": e.free_angle}
        entry |= {k: getattr(e, k) for k in ("damping", "preload") if getattr(e, k)}
        by_kind.setdefault("springs" if e.kind == "spring" else "torsion_springs", {})[e.name] = (
            entry
        )
    out |= {
        k: by_kind[k]
        for k in ("sliders", "slots", "actuators", "rolls", "motors", "springs", "torsion_springs")
        if k in by_kind
    }
    return out


# ------------------------------------------------------------------- running
def driver_inputs(part: Part, machine: Machine, results: dict) -> dict[str, DriverSetting]:
    """Each driver's setting, with ``driven_by`` resolved into a velocity."""
    lk = part.model
    settings = dict(part.values.get("motion", {}))
    missing = [d for d in lk.drivers if d not in settings or settings[d].values is None]
    if missing:
        d = missing[0]
        raise machine._error(
            (*part.path, "motion", d),
            f"driver {d!r} has no value: add value or sweep under [{part.kind}.{part.name}"
            f".motion.{d}] (or --at/--sweep on the command line)",
        )
    for d, s in settings.items():
        if s.driven_by is not None:
            speed = results[s.driven_by].speed
            settings[d] = DriverSetting(s.kind, s.values, speed, 0.0, s.driven_by)
    swept = [d for d in lk.drivers if len(settings[d].values.values) > 1]
    if len(swept) > 1:
        raise machine._error(
            (*part.path, "motion"),
            f"sweep one driver at a time; {', '.join(swept)} are all swept",
        )
    return settings


def _driver_torque(
    lk: Any, driver: str, velocity: dict, acceleration: dict, options: dict
) -> TorqueCurve:
    """The lone angle driver's torque at any of its angles, for a flywheel (same loads)."""

    def torque(theta: np.ndarray) -> np.ndarray:
        m = lk.solve({driver: theta}, velocity=velocity, acceleration=acceleration)
        return np.asarray(lk.forces(m, **options).driver[driver])

    return TorqueCurve(torque, velocity[driver])


def has_loads(part: Part) -> bool:
    """Whether the part's forces are worth computing (masses, springs or loads)."""
    lk, v = part.model, part.values
    return bool(
        any(ln.mass for ln in lk.links.values())
        or lk.elements
        or v.get("forces")
        or v.get("torques")
        or v.get("friction")
    )


def loads(part: Part) -> dict[str, Any]:
    """The part's applied loads as ``Linkage.forces`` takes them (for ``run`` and ``report``).

    ``external_forces``, ``external_torques``, ``viscous`` and ``coulomb``; gravity is the
    machine's.
    """
    v = part.values
    friction = v.get("friction", {})
    return {
        "external_forces": [(e["link"], e["at"], e["force"]) for e in v.get("forces", [])],
        "external_torques": dict(v.get("torques", {})),
        "viscous": {k: e["viscous"] for k, e in friction.items() if "viscous" in e},
        "coulomb": {k: e["coulomb"] for k, e in friction.items() if "coulomb" in e},
    }


def _run(part: Part, machine: Machine, results: dict, forces: bool | None = None) -> PartResult:
    lk, v = part.model, part.values
    settings = driver_inputs(part, machine, results)
    angles = angle_drivers(lk)
    n = max(len(s.values.values) for s in settings.values())
    values = {d: np.broadcast_to(s.values.values, (n,)) for d, s in settings.items()}
    one_rate = {d: (1.0 if d not in angles else _per_second(machine)) for d in lk.drivers}
    velocity = {
        d: s.velocity if s.velocity is not None else one_rate[d] for d, s in settings.items()
    }
    acceleration = {d: s.acceleration or 0.0 for d, s in settings.items()}
    m = lk.solve(values, velocity=velocity, acceleration=acceleration)
    out = PartResult(part, objects={"motion": m})
    out.summary += [
        Summary("links", ", ".join(lk.links) or "none"),
        Summary("drivers", ", ".join(lk.drivers)),
        Summary("mobility", lk.mobility()),
    ]
    cols: dict[str, tuple[Any, str | None]] = {}
    for d in lk.drivers:
        cols[_driver_column(d, angles, lk)] = (values[d], "angle" if d in angles else "length")
    for link, theta in m.theta.items():
        cols.setdefault(f"theta_{link}", (theta, "angle"))
        cols[f"omega_{link}"] = (m.omega[link], "angular_velocity")
        cols[f"alpha_{link}"] = (m.alpha[link], "angular_acceleration")
    for joint, d in m.lengths.items():
        cols.setdefault(f"d_{joint}", (d, "length"))
        cols[f"ddot_{joint}"] = (m.length_rate[joint], "velocity")
    cols |= {"ok": (m.ok, None), "reason": (m.reason, None)}
    title = f"Kinematics of {part.name}"
    out.tables.append(_table("kinematics", title, cols))
    report = v.get("report", [])
    if report:
        pts: dict[str, tuple[Any, str | None]] = {}
        for p in report:
            pts |= _xy(p, m.points[p], "length")
            pts |= _xy(f"V{p}", m.point_velocity[p], "velocity")
            pts |= _xy(f"A{p}", m.point_acceleration[p], "acceleration")
        pts |= {"ok": (m.ok, None), "reason": (m.reason, None)}
        out.tables.append(_table("points", f"Points of {part.name}", pts))
    if forces if forces is not None else has_loads(part):
        options = {"gravity": machine.gravity or 0.0, **loads(part)}
        f = lk.forces(m, **options)
        out.objects["forces"] = f
        out.tables.append(_forces_table(part, f, angles, values))
        angle_driven = [d for d in lk.drivers if d in angles]
        if len(angle_driven) == 1 and len(lk.drivers) == 1:
            d = angle_driven[0]
            out.torque = _driver_torque(lk, d, velocity, acceleration, options)
        ok, reason = f.ok, f.reason
    else:
        ok, reason = m.ok, m.reason
    first = lk.drivers[0]
    s = machine.units
    kind = "angle" if first in angles else "length"
    label = s.label(_driver_column(first, angles, lk), kind)
    out.flagged += flagged_rows(label, s.show(kind, np.asarray(values[first], float)), ok, reason)
    return out


def _per_second(machine: Machine) -> float:
    from .. import units as u

    if machine.units.is_unit_free:
        return 1.0
    return u._factor("rad/s", machine.units.internal("angular_velocity"))


def _driver_column(d: str, angles: frozenset[str], lk: Any) -> str:
    if d in angles:
        motors = {j.name for j in lk.joints if j.kind == "motor"}
        return f"{'phi' if d in motors else 'theta'}_{d}"
    return f"d_{d}"


def _xy(name: str, z: Any, kind: str) -> dict[str, tuple[Any, str]]:
    return {f"{name}_x": (np.real(z), kind), f"{name}_y": (np.imag(z), kind)}


def _table(name: str, title: str, cols: dict[str, tuple[Any, str | None]]) -> ResultTable:
    return ResultTable(
        name,
        title,
        {k: np.ravel(val) for k, (val, _) in cols.items()},
        {k: kind for k, (_, kind) in cols.items()},
    )


def _forces_table(part: Part, f: Any, angles: frozenset[str], values: dict) -> ResultTable:
    lk = part.model
    cols: dict[str, tuple[Any, str | None]] = {}
    for d in lk.drivers:
        cols[_driver_column(d, angles, lk)] = (values[d], "angle" if d in angles else "length")
    for d, effort in f.driver.items():
        cols[f"{'T' if d in angles else 'F'}_{d}"] = (effort, "torque" if d in angles else "force")
    for (a, p), value in f.pins.items():
        cols |= _xy(f"F_{a}_{p}", value, "force")
    torsion = {e.name for e in lk.elements if e.kind == "torsion"}
    for name, effort in f.elements.items():
        if name in torsion:
            cols[f"tau_{name}"] = (effort, "torque")
        else:
            cols[f"T_{name}"] = (effort, "force")
    cols |= {"ok": (f.ok, None), "reason": (f.reason, None)}
    return _table("forces", f"Forces on {part.name}", cols)


def _refs(values: dict) -> dict[tuple, str]:
    out = {}
    for name, s in values.get("motion", {}).items():
        driven = s.driven_by if isinstance(s, DriverSetting) else s.get("driven_by")
        if driven:
            out[("motion", name, "driven_by")] = driven
    return out


PART_KINDS = {
    "linkage": PartKind(
        "linkage",
        LINKAGE,
        _build,
        _values_of,
        lambda part, machine, results: _run(part, machine, results),
        _refs,
        "torque",
    ),
}

#: For the command line: run a linkage part with or without the forces table.
run_linkage = _run
#: Choice of the friction models, for documentation.
FRICTION_KEYS = Choice("coulomb", "viscous")
