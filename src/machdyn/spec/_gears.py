"""Part kinds ``gear_pair``, ``gear_train`` and ``planetary``.

A gear pair or train may drive another part: its output speed (``input_speed``
through the pair's or train's signed ratio) is what a mechanism's
``driven_by`` takes. No physics here: the ratios are the library's.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._context import Context, _show
from ._machine import Machine, Part, PartKind
from ._run import PartResult, ResultTable, Summary, rounded
from ._types import (
    Boolean,
    Choice,
    Integer,
    MapOf,
    Name,
    Number,
    Quantity,
    Table,
    Text,
    Type,
    fields,
    optional,
    required,
)

__all__ = ["PART_KINDS"]

GEAR = Table(
    fields(
        teeth=required(Integer(3), "number of teeth"),
        profile_shift=optional(Number(), "profile-shift coefficient x"),
        internal=optional(Boolean(), "an internal (ring) gear"),
        thickness_reduction=optional(Quantity("length", minimum=0.0), "thinning for backlash"),
        addendum=optional(Quantity("length", positive=True)),
        dedendum=optional(Quantity("length", positive=True)),
    ),
    doc="one gear of the pair",
)

GEAR_PAIR = Table(
    fields(
        pinion=required(GEAR),
        gear=required(GEAR),
        module=optional(Quantity("length", positive=True), "pitch diameter per tooth"),
        diametral_pitch=optional(Quantity("inverse_length", positive=True), "teeth per length"),
        pressure_angle=optional(Quantity("angle", positive=True), "default 20 deg"),
        system=optional(Choice("full_depth", "stub")),
        center_distance=optional(Quantity("length", positive=True), "default: tight mesh"),
        driver=optional(Choice("pinion", "gear")),
        input_speed=optional(Quantity("angular_velocity"), "the driving member's speed"),
        torque=optional(Quantity("torque"), "the driving member's torque (tooth loads)"),
        notes=optional(Text()),
    ),
    doc="a pinion meshing with a gear",
)


class Stage(Type):
    """``[driver, driven]`` or ``[driver, driven, kind]`` of a gear train."""

    what = "[driver teeth, driven teeth] or [driver, driven, kind]"

    def read(self, ctx: Context, path: tuple, value: Any) -> tuple:
        from ..gears import MESH_KINDS

        if not isinstance(value, list) or len(value) not in (2, 3):
            raise ctx.error(path, f"expected {self.what}, e.g. [18, 54], got {_show(value)}")
        driver = Number(positive=True).read(ctx, (*path, 1), value[0])
        driven = Number(positive=True).read(ctx, (*path, 2), value[1])
        kind = "external"
        if len(value) == 3:
            kind = Choice(*MESH_KINDS).read(ctx, (*path, 3), value[2])
        return (driver, driven, kind)

    def write(self, w: Any, value: Any) -> Any:
        a, b, kind = value
        out = [int(x) if float(x).is_integer() else x for x in (a, b)]
        return out if kind == "external" else [*out, kind]

    def schema(self) -> dict:
        from ..gears import MESH_KINDS

        number = {"type": "number", "exclusiveMinimum": 0}
        return {
            "type": "array",
            "prefixItems": [number, number, {"enum": list(MESH_KINDS)}],
            "minItems": 2,
            "maxItems": 3,
        }


class Stages(Type):
    """An array of :class:`Stage`."""

    what = "an array of stages [[18, 54], [20, 60]]"

    def read(self, ctx: Context, path: tuple, value: Any) -> list:
        if not isinstance(value, list) or not value:
            raise ctx.error(path, f"expected {self.what}, got {_show(value)}")
        return [Stage().read(ctx, (*path, i), v) for i, v in enumerate(value, start=1)]

    def write(self, w: Any, value: Any) -> Any:
        return [Stage().write(w, s) for s in value]

    def schema(self) -> dict:
        return {"type": "array", "items": Stage().schema(), "minItems": 1}


GEAR_TRAIN = Table(
    fields(
        stages=required(Stages(), "[driver, driven(, kind)] from the input shaft"),
        input_speed=optional(Quantity("angular_velocity")),
        torque=optional(Quantity("torque"), "the input shaft's torque"),
        notes=optional(Text()),
    ),
    doc="a simple or compound train",
)


class Chain(Type):
    """``[["sun", 40], ["planet", 20, "external"], ["ring", 80, "internal"]]``."""

    what = 'a chain [["sun", 40], ["planet", 20, "external"], ...]'

    def read(self, ctx: Context, path: tuple, value: Any) -> list:
        if not isinstance(value, list) or len(value) < 2:
            raise ctx.error(path, f"expected {self.what} (at least two gears), got {_show(value)}")
        out = []
        for i, link in enumerate(value, start=1):
            where = (*path, i)
            size = 2 if i == 1 else 3
            if not isinstance(link, list) or len(link) != size:
                shape = '["sun", 40]' if i == 1 else '["planet", 20, "external"]'
                raise ctx.error(where, f"expected {shape}, got {_show(link)}")
            name = Name().read(ctx, (*where, 1), link[0])
            teeth = Integer(3).read(ctx, (*where, 2), link[1])
            tail = ()
            if i > 1:
                tail = (Choice("external", "internal", "shaft").read(ctx, (*where, 3), link[2]),)
            out.append((name, teeth, *tail))
        return out

    def write(self, w: Any, value: Any) -> Any:
        return [list(link) for link in value]

    def schema(self) -> dict:
        return {
            "type": "array",
            "minItems": 2,
            "items": {
                "type": "array",
                "prefixItems": [
                    {"type": "string", "minLength": 1},
                    {"type": "integer", "minimum": 3},
                    {"enum": ["external", "internal", "shaft"]},
                ],
                "minItems": 2,
                "maxItems": 3,
            },
        }


PLANETARY = Table(
    fields(
        sun=optional(Integer(3)),
        planet=optional(Integer(3)),
        ring=optional(Integer(3)),
        chain=optional(Chain(), "instead of sun, planet, ring"),
        speeds=optional(
            MapOf(Quantity("angular_velocity"), "a table of member = speed (two of them)"),
            "two known member speeds (0 for a fixed member)",
        ),
        torques=optional(
            MapOf(Quantity("torque"), "a table of member = torque (one of them)"),
            "the external torque on one member (first gear, last gear or arm)",
        ),
        notes=optional(Text()),
    ),
    doc="an epicyclic train",
)


# ------------------------------------------------------------------- building
def _gear(ctx: Context, path: tuple, e: dict, v: dict) -> Any:
    from ..gears import Gear

    size = {}
    if "module" in v:
        size["module"] = v["module"]
    if "diametral_pitch" in v:
        size["diametral_pitch"] = v["diametral_pitch"]
    fields_ = {k: (*path, k) for k in e} | {"teeth": (*path, "teeth")}
    with ctx.at(path, fields_ | {"module": (*path[:-1], "module")}):
        return Gear(
            e["teeth"],
            **size,
            pressure_angle=v.get("pressure_angle", math.radians(20.0)),
            system=v.get("system", "full_depth"),
            addendum=e.get("addendum"),
            dedendum=e.get("dedendum"),
            profile_shift=e.get("profile_shift", 0.0),
            internal=e.get("internal", False),
            thickness_reduction=e.get("thickness_reduction", 0.0),
        )


def _build_pair(ctx: Context, path: tuple, v: dict) -> Any:
    from ..gears import GearPair

    if ("module" in v) == ("diametral_pitch" in v):
        raise ctx.error((*path, "module"), "give module or diametral_pitch (one of them)")
    pinion = _gear(ctx, (*path, "pinion"), v["pinion"], v)
    gear = _gear(ctx, (*path, "gear"), v["gear"], v)
    with ctx.at(path, {"center_distance": (*path, "center_distance")}):
        pair = GearPair(pinion, gear, v.get("center_distance"), driver=v.get("driver", "pinion"))
    pair_units(pair, ctx)
    return pair


def pair_units(model: Any, ctx: Context) -> None:
    """Give a frozen model its unit system (``units`` is not one of its fields)."""
    object.__setattr__(model, "units", None if ctx.system.is_unit_free else ctx.system)


def _gear_values(g: Any) -> dict:
    out: dict[str, Any] = {"teeth": g.teeth}
    if g.profile_shift:
        out["profile_shift"] = g.profile_shift
    if g.internal:
        out["internal"] = True
    if g.thickness_reduction:
        out["thickness_reduction"] = g.thickness_reduction
    if g.given_addendum is not None:
        out["addendum"] = g.given_addendum
    if g.given_dedendum is not None:
        out["dedendum"] = g.given_dedendum
    return out


def _pair_values(pair: Any) -> dict:
    p = pair.pinion
    out: dict[str, Any] = {"pinion": _gear_values(p), "gear": _gear_values(pair.gear)}
    if p.diametral_pitch is not None:
        out["diametral_pitch"] = p.diametral_pitch
    else:
        out["module"] = p.module
    out["pressure_angle"] = p.pressure_angle
    if p.system != "full_depth":
        out["system"] = p.system
    if pair.center_distance != pair.tight_center_distance:
        out["center_distance"] = pair.center_distance
    if pair.driver != "pinion":
        out["driver"] = pair.driver
    return out


def _build_train(ctx: Context, path: tuple, v: dict) -> Any:
    from ..gears import GearTrain

    with ctx.at((*path, "stages")):
        train = GearTrain(v["stages"])
    train.units = None if ctx.system.is_unit_free else ctx.system
    return train


def _build_planetary(ctx: Context, path: tuple, v: dict) -> Any:
    from ..gears import PlanetaryTrain

    simple = [k for k in ("sun", "planet", "ring") if k in v]
    if "chain" in v and simple:
        raise ctx.error((*path, simple[0]), "give sun, planet and ring, or chain, not both")
    with ctx.at(path, {k: (*path, k) for k in ("sun", "planet", "ring")}):
        if "chain" in v:
            train = PlanetaryTrain(v["chain"])
        else:
            missing = [k for k in ("sun", "planet", "ring") if k not in v]
            if missing:
                raise ctx.error((*path, missing[0]), "missing: give sun, planet, ring (or chain)")
            train = PlanetaryTrain.simple(v["sun"], v["planet"], v["ring"])
    speeds = v.get("speeds", {})
    if speeds:
        if len(speeds) != 2:
            raise ctx.error((*path, "speeds"), f"give exactly two member speeds, got {len(speeds)}")
        for name in speeds:
            if name not in train.members:
                listed = ", ".join(train.members)
                raise ctx.error((*path, "speeds", name), f"not a member; members: {listed}")
        with ctx.at((*path, "speeds")):
            train.table(**speeds)
    torques = v.get("torques", {})
    if torques:
        if len(torques) != 1 or not speeds:
            raise ctx.error((*path, "torques"), "give one member's torque, with two speeds")
        for name in torques:
            if name not in train.members:
                listed = ", ".join(train.members)
                raise ctx.error((*path, "torques", name), f"not a member; members: {listed}")
        from ..gears import planetary_power

        with ctx.at((*path, "torques")):
            planetary_power(train, speeds, torques)
    train.units = None if ctx.system.is_unit_free else ctx.system
    return train


# ------------------------------------------------------------------- running
def _run_pair(part: Part, machine: Machine, results: dict) -> PartResult:
    pair, v = part.model, part.values
    out = PartResult(part, objects={"pair": pair})
    app_p, app_g = pair.angles_of_approach
    rec_p, rec_g = pair.angles_of_recess
    gear_tip, pinion_tip = pair.interference
    out.summary += [
        Summary("centre distance", pair.center_distance, "length"),
        Summary("standard centre distance", pair.standard_center_distance, "length"),
        Summary("operating pressure angle", pair.operating_pressure_angle, "angle"),
        Summary("velocity ratio (gear/pinion)", pair.velocity_ratio),
        Summary("contact ratio", f"{pair.contact_ratio:.4f} ({pair.contact_ratio_rating})"),
        Summary("length of action", pair.length_of_action, "length"),
        Summary("path of approach, recess", [pair.path_of_approach, pair.path_of_recess], "length"),
        Summary("angles of approach (pinion, gear)", [app_p, app_g], "angle"),
        Summary("angles of recess (pinion, gear)", [rec_p, rec_g], "angle"),
        Summary("base pitch", pair.base_pitch, "length"),
        Summary("backlash", rounded(pair.backlash, pair.center_distance), "length"),
        Summary(
            "interference",
            "none"
            if not pair.interferes
            else ", ".join(
                n for n, hit in (("gear tip", gear_tip), ("pinion tip", pinion_tip)) if hit
            ),
        ),
    ]
    names = ("teeth", "pitch_radius", "base_radius", "addendum_radius", "root_radius")
    gears = (pair.pinion, pair.gear)
    cols: dict[str, np.ndarray] = {"member": np.array(["pinion", "gear"], dtype=object)}
    kinds: dict[str, str | None] = {"member": None}
    cols["teeth"] = np.array([g.teeth for g in gears])
    kinds["teeth"] = "dimensionless"
    for name in names[1:]:
        cols[name] = np.array([float(getattr(g, name)) for g in gears])
        kinds[name] = "length"
    cols["tooth_thickness"] = np.array([g.tooth_thickness for g in gears])
    kinds["tooth_thickness"] = "length"
    if "input_speed" in v:
        w_in = v["input_speed"]
        w_out = (
            w_in * pair.velocity_ratio if pair.driver == "pinion" else w_in / pair.velocity_ratio
        )
        speeds = (w_in, w_out) if pair.driver == "pinion" else (w_out, w_in)
        cols["speed"] = np.array(speeds)
        kinds["speed"] = "angular_velocity"
        out.speed = float(w_out)
        out.summary.append(Summary("output speed", w_out, "angular_velocity"))
    if "torque" in v:
        from ..gears import mesh_forces

        f = mesh_forces(pair, v["torque"], pair.driver)
        cols["torque"] = np.array([f.torque_pinion, f.torque_gear])
        kinds["torque"] = "torque"
        out.summary += [
            Summary("tangential tooth load W_t", f.tangential, "force"),
            Summary("radial tooth load W_r", f.radial, "force"),
            Summary("total tooth load W", f.total, "force"),
        ]
    out.tables.append(ResultTable("gears", f"Gears of {part.name}", cols, kinds))
    return out


def _run_train(part: Part, machine: Machine, results: dict) -> PartResult:
    train, v = part.model, part.values
    out = PartResult(part, objects={"train": train})
    out.summary.append(Summary("train value (output/input)", train.train_value))
    stages = train.stages
    cols: dict[str, np.ndarray] = {
        "stage": np.arange(1, len(stages) + 1),
        "driver": np.array([s[0] for s in stages]),
        "driven": np.array([s[1] for s in stages]),
        "kind": np.array([s[2] for s in stages], dtype=object),
    }
    kinds: dict[str, str | None] = {
        "stage": "dimensionless",
        "driver": "dimensionless",
        "driven": "dimensionless",
        "kind": None,
    }
    if "input_speed" in v:
        speeds = train.speeds(v["input_speed"])
        cols["driven_speed"] = np.array(speeds[1:])
        kinds["driven_speed"] = "angular_velocity"
        out.speed = speeds[-1]
        out.summary.append(Summary("output speed", speeds[-1], "angular_velocity"))
    if "torque" in v:
        from ..gears import train_power

        power = train_power(train, v.get("input_speed", 1.0), v["torque"])
        cols["driven_torque"] = np.array(power.torques[1:])
        kinds["driven_torque"] = "torque"
        out.summary.append(Summary("load torque on the output shaft", power.load_torque, "torque"))
    out.tables.append(ResultTable("stages", f"Stages of {part.name}", cols, kinds))
    return out


def _run_planetary(part: Part, machine: Machine, results: dict) -> PartResult:
    train, v = part.model, part.values
    out = PartResult(part, objects={"train": train})
    out.summary.append(Summary("train value (Willis, arm fixed)", train.train_value))
    if v.get("speeds"):
        table = train.table(**v["speeds"])
        cols = {
            "member": np.array(table.members, dtype=object),
            "with_arm": table.with_arm,
            "relative_to_arm": table.relative,
            "speed": table.total,
        }
        kinds = {
            "member": None,
            "with_arm": "angular_velocity",
            "relative_to_arm": "angular_velocity",
            "speed": "angular_velocity",
        }
        if v.get("torques"):
            from ..gears import planetary_power

            power = planetary_power(train, v["speeds"], v["torques"])
            by = dict(zip(power.members, power.torques, strict=True))
            cols["torque"] = np.array([by.get(m, 0.0) for m in table.members])
            kinds["torque"] = "torque"
        out.tables.append(ResultTable("speeds", f"Tabular method for {part.name}", cols, kinds))
    return out


PART_KINDS = {
    "gear_pair": PartKind(
        "gear_pair", GEAR_PAIR, _build_pair, _pair_values, _run_pair, role="speed"
    ),
    "gear_train": PartKind(
        "gear_train",
        GEAR_TRAIN,
        _build_train,
        lambda train: {"stages": list(train.stages)},
        _run_train,
        role="speed",
    ),
    "planetary": PartKind(
        "planetary",
        PLANETARY,
        _build_planetary,
        lambda train: {"chain": [list(link) for link in train.chain]},
        _run_planetary,
    ),
}
