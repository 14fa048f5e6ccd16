"""Part kind ``cam``: a cam program (segments) and its follower.

The part's model is a :class:`Cam` when it has both, the
:class:`~machdyn.cams.CamProgram` alone when it has no follower, and the
follower alone when it has no segments (so ``CamProgram.to_spec()`` and a
follower's ``to_spec()`` read back as themselves). Running samples the program
(s, v, a, j; in time with the cam's speed) and, with a follower, the profile
and the design checks. No physics here.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._context import Context
from ._linkage import Raw
from ._machine import Machine, Part, PartKind
from ._run import PartResult, ResultTable, Summary
from ._types import (
    Choice,
    Integer,
    ListOf,
    Name,
    Number,
    Quantity,
    Table,
    Text,
    fields,
    optional,
    required,
)

__all__ = ["PART_KINDS", "Cam"]

FOLLOWER = Table(
    fields(
        type=required(Choice("roller", "flat", "oscillating")),
        prime_radius=optional(Quantity("length", positive=True), "roller, oscillating"),
        roller_radius=optional(Quantity("length", minimum=0.0), "roller, oscillating"),
        base_radius=optional(Quantity("length", positive=True), "flat"),
        eccentricity=optional(Quantity("length"), "roller, flat: offset of the follower axis"),
        pivot_distance=optional(Quantity("length", positive=True), "oscillating"),
        arm_length=optional(Quantity("length", positive=True), "oscillating"),
        pivot_side=optional(Choice("right", "left"), "oscillating"),
        face_width=optional(Quantity("length", positive=True), "flat: the width to check"),
    ),
    doc="the follower",
)
_LIFT = {"anyOf": [{"$ref": "#/$defs/length"}, {"$ref": "#/$defs/angle"}]}


@dataclass(frozen=True)
class Tagged:
    """A value with its kind, known only once the rest of the part is read."""

    value: float
    kind: str


class Lift(Raw):
    """A segment's lift: a length, or an angle for an oscillating follower."""

    def write(self, w: Any, value: Any) -> Any:
        return w.quantity(value.value, value.kind)


SEGMENT = Table(
    fields(
        motion=required(Choice("rise", "fall", "dwell")),
        beta=required(Quantity("angle", positive=True), "the segment's cam angle"),
        lift=optional(Lift(_LIFT), "h: a length, or an angle for an oscillating follower"),
        law=optional(Name(), "a law of machdyn.cams.LAW_NAMES (rise and fall)"),
        b=optional(Number(minimum=0.0), "scca"),
        c=optional(Number(minimum=0.0), "scca"),
        d=optional(Number(minimum=0.0), "scca"),
    ),
    doc="one segment, in order from the start of the turn",
)
CAM = Table(
    fields(
        segment=optional(ListOf(SEGMENT, minimum=1), "[[cam.NAME.segment]] in order"),
        follower=optional(FOLLOWER),
        speed=optional(Quantity("angular_velocity"), "the cam's speed: V, A, J in time"),
        points=optional(Integer(4, 1_000_000), "samples over the turn for the checks"),
        step=optional(Quantity("angle", positive=True), "spacing of the table (default 10 deg)"),
        max_pressure_angle=optional(Quantity("angle", positive=True), "default 30 deg"),
        notes=optional(Text()),
    ),
    doc="a cam program and its follower",
)


@dataclass(frozen=True)
class Cam:
    """A cam program with its follower (the model of a ``cam`` part with both).

    Examples
    --------
    >>> from machdyn import cams
    >>> cam = Cam(cams.CamProgram.double_dwell(1.0, math.pi / 3, math.pi / 3),
    ...           cams.TranslatingRoller(3.0, 0.5))
    >>> cam.profile().is_undercut
    False
    """

    program: Any
    follower: Any

    def __post_init__(self) -> None:
        from .. import cams
        from ..errors import InputError

        if not isinstance(self.program, cams.CamProgram):
            raise InputError("program", f"must be a machdyn.cams.CamProgram, got {self.program!r}")
        followers = (cams.TranslatingRoller, cams.TranslatingFlatFace, cams.OscillatingRoller)
        if not isinstance(self.follower, followers):
            raise InputError("follower", f"must be a machdyn.cams follower, got {self.follower!r}")

    def profile(self, n: int = 3600) -> Any:
        """The cam's :class:`~machdyn.cams.CamProfile` at ``n`` angles.

        With the cam's ``units`` (a machine file's) its ``to_pandas()`` says them.
        """
        from .._validate import integer

        profile = self.follower.profile(self.program, integer("n", n, minimum=4, maximum=10**7))
        return cam_units(profile, self)

    def motion(self, n: int = 360) -> Any:
        """The follower's :class:`~machdyn.cams.Motion` at ``n`` angles (per radian).

        ``motion(n).in_time(omega)`` gives it in time. With the cam's ``units``
        their ``to_pandas()`` columns say them (``s [mm]``, ``V [mm/s]``).

        Examples
        --------
        >>> import machdyn
        >>> cam = machdyn.load("docs/examples/cam.toml")  # doctest: +SKIP
        >>> list(cam.motion(4).in_time(10.0).to_pandas())[:4]  # doctest: +SKIP
        ['t [s]', 'theta [deg]', 's [mm]', 'V [mm/s]']
        """
        from .._validate import integer

        motion = self.program.sample(integer("n", n, minimum=4, maximum=10**7))
        return cam_units(motion, self)

    def to_spec(self, name: str = "cam") -> dict[str, Any]:
        """The cam as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from . import model_spec

        return model_spec(self, "cam", name)


def cam_units(result: Any, cam: Any) -> Any:
    """A cam's motion or profile with the cam's units (and its lift's kind) attached."""
    from .. import cams
    from ..units import with_units

    lift = "angle" if isinstance(cam.follower, cams.OscillatingRoller) else "length"
    object.__setattr__(result, "lift", lift)
    return with_units(result, getattr(cam, "units", None))


def _oscillating(v: dict) -> bool:
    return v.get("follower", {}).get("type") == "oscillating"


def _segment(ctx: Context, path: tuple, e: dict, oscillating: bool) -> Any:
    from ..cams import Segment, get_law

    motion = e["motion"]
    if motion == "dwell":
        for key in ("lift", "law", "b", "c", "d"):
            if key in e:
                raise ctx.error((*path, key), "a dwell has no lift or law")
        return Segment("dwell", e["beta"])
    for key in ("lift", "law"):
        if key not in e:
            raise ctx.error((*path, key), f"missing: a {motion} needs its lift and law")
    where, raw = e["lift"]
    lift = Quantity("angle" if oscillating else "length", minimum=0.0).read(ctx, where, raw)
    params = {k: e[k] for k in "bcd" if k in e}
    with ctx.at((*path, "law"), {"law": (*path, "law"), **{k: (*path, k) for k in "bcd"}}):
        law = get_law(e["law"], **params)
    with ctx.at(path, {"h": (*path, "lift"), "beta": (*path, "beta")}):
        return Segment(motion, e["beta"], lift, law)


def _follower(ctx: Context, path: tuple, f: dict) -> Any:
    from .. import cams

    kind = f["type"]
    needs = {
        "roller": ("prime_radius", "roller_radius"),
        "flat": ("base_radius",),
        "oscillating": ("prime_radius", "roller_radius", "pivot_distance", "arm_length"),
    }[kind]
    allowed = {
        "roller": ("eccentricity",),
        "flat": ("eccentricity", "face_width"),
        "oscillating": ("pivot_side",),
    }[kind]
    for key in f:
        if key != "type" and key not in needs and key not in allowed:
            raise ctx.error((*path, key), f"not a key of a {kind} follower")
    for key in needs:
        if key not in f:
            raise ctx.error((*path, key), f"missing: required for a {kind} follower")
    with ctx.at(path, {k: (*path, k) for k in f}):
        if kind == "roller":
            return cams.TranslatingRoller(
                f["prime_radius"], f["roller_radius"], f.get("eccentricity", 0.0)
            )
        if kind == "flat":
            return cams.TranslatingFlatFace(f["base_radius"], f.get("eccentricity", 0.0))
        return cams.OscillatingRoller(
            f["prime_radius"],
            f["roller_radius"],
            f["pivot_distance"],
            f["arm_length"],
            f.get("pivot_side", "right"),
        )


def _build(ctx: Context, path: tuple, v: dict) -> Any:
    from ..cams import CamProgram

    if "segment" not in v and "follower" not in v:
        raise ctx.error((*path, "segment"), "missing: a cam needs its [[segment]]s (and follower)")
    follower = _follower(ctx, (*path, "follower"), v["follower"]) if "follower" in v else None
    program = None
    if "segment" in v:
        osc = _oscillating(v)
        segments = [
            _segment(ctx, (*path, "segment", i), e, osc) for i, e in enumerate(v["segment"], 1)
        ]
        with ctx.at((*path, "segment"), {"segments": (*path, "segment")}):
            program = CamProgram(segments)
        for i, seg in enumerate(program.segments, start=1):  # the lifts, now of known kind
            if seg.motion != "dwell":
                v["segment"][i - 1]["lift"] = Tagged(seg.h, "angle" if osc else "length")
    if "max_pressure_angle" in v and v["max_pressure_angle"] >= math.pi / 2:
        raise ctx.error((*path, "max_pressure_angle"), "must be below 90 deg")
    model = Cam(program, follower) if program is not None and follower is not None else None
    model = model or program or follower
    object.__setattr__(model, "units", None if ctx.system.is_unit_free else ctx.system)
    return model


_SCCA = re.compile(r"scca\(b=([^,]+), c=([^,]+), d=([^)]+)\)")


def _law_keys(law: Any) -> dict[str, Any]:
    from ..errors import InputError

    found = _SCCA.fullmatch(law.name)
    if found:
        return {"law": "scca", **{k: float(x) for k, x in zip("bcd", found.groups(), strict=True)}}
    from ..cams import LAW_NAMES

    if law.name not in LAW_NAMES:
        raise InputError("law", f"the law {law.name!r} has no name in the file format")
    return {"law": law.name}


def _values_of(model: Any) -> dict[str, Any]:
    from ..cams import CamProgram

    program = model.program if isinstance(model, Cam) else model
    follower = model.follower if isinstance(model, Cam) else model
    out: dict[str, Any] = {}
    osc = type(follower).__name__ == "OscillatingRoller"
    if isinstance(program, CamProgram):
        segments = []
        for seg in program.segments:
            entry: dict[str, Any] = {"motion": seg.motion, "beta": seg.beta}
            if seg.motion != "dwell":
                entry |= {"lift": Tagged(seg.h, "angle" if osc else "length")}
                entry |= _law_keys(seg.law)
            segments.append(entry)
        out["segment"] = segments
    if not isinstance(follower, CamProgram):
        out["follower"] = _follower_values(follower)
    return out


def _follower_values(f: Any) -> dict[str, Any]:
    from .. import cams

    if isinstance(f, cams.TranslatingRoller):
        out = {"type": "roller", "prime_radius": f.prime_radius, "roller_radius": f.roller_radius}
        return out | ({"eccentricity": f.eccentricity} if f.eccentricity else {})
    if isinstance(f, cams.TranslatingFlatFace):
        out = {"type": "flat", "base_radius": f.base_radius}
        return out | ({"eccentricity": f.eccentricity} if f.eccentricity else {})
    return {
        "type": "oscillating",
        "prime_radius": f.prime_radius,
        "roller_radius": f.roller_radius,
        "pivot_distance": f.pivot_distance,
        "arm_length": f.arm_length,
        "pivot_side": f.pivot_side,
    }


def _run(part: Part, machine: Machine, results: dict) -> PartResult:
    from ..cams import CamProgram

    model, v = part.model, part.values
    program = model.program if isinstance(model, Cam) else model
    out = PartResult(part, objects={})
    if not isinstance(program, CamProgram):
        out.summary.append(Summary("follower", repr(model)))
        return out
    osc = _oscillating(v)
    lift_kind = "angle" if osc else "length"
    continuity = program.continuity()
    out.summary.append(Summary("continuity", "; ".join(continuity.lines())))
    step = v.get("step", math.radians(10.0))
    n = max(4, round(2 * math.pi / step))
    m = program.sample(n)
    out.objects["motion"] = m
    cols: dict[str, tuple[Any, str | None]] = {"theta": (m.theta, "angle"), "s": (m.s, lift_kind)}
    if "speed" in v:
        tm = m.in_time(abs(v["speed"]))
        kinds = (
            ("angular_velocity", "angular_acceleration", "angular_jerk")
            if osc
            else ("velocity", "acceleration", "jerk")
        )
        cols |= {"V": (tm.V, kinds[0]), "A": (tm.A, kinds[1]), "J": (tm.J, kinds[2])}
        out.summary.append(Summary("cycle time", 2 * math.pi / abs(v["speed"]), "time"))
        title = f"Follower motion of {part.name} at its speed"
    else:
        cols |= {"v_per_rad": (m.v, lift_kind), "a_per_rad2": (m.a, lift_kind)}
        cols |= {"j_per_rad3": (m.j, lift_kind)}
        title = f"Follower motion of {part.name} (derivatives per radian of cam angle)"
    out.tables.append(_table("motion", title, cols))
    if isinstance(model, Cam):
        profile = model.profile(v.get("points", 3600))
        out.objects["profile"] = profile
        limit = v.get("max_pressure_angle", math.radians(30.0))
        checks = profile.checks(limit, face_width=v.get("follower", {}).get("face_width"))
        out.summary += [
            Summary("base radius", profile.base_radius, "length"),
            Summary("prime radius", profile.prime_radius, "length"),
            Summary("largest |pressure angle|", abs(profile.pressure_angle_max), "angle"),
            Summary("least radius of curvature", profile.rho_min, "length"),
            Summary("undercut", "yes" if profile.is_undercut else "no"),
        ]
        out.summary += [Summary(f"check: {c.name}", c.line()) for c in checks]
        shown = profile_rows(profile, m.theta)
        out.tables.append(_table("profile", f"Profile of {part.name}", shown))
    return out


def profile_rows(profile: Any, theta: np.ndarray) -> dict[str, tuple[Any, str | None]]:
    """The profile at the table's angles (nearest samples of the profile)."""
    k = np.searchsorted(profile.theta, theta).clip(0, profile.theta.size - 1)
    cols: dict[str, tuple[Any, str | None]] = {
        "theta": (profile.theta[k], "angle"),
        "pressure_angle": (profile.pressure_angle[k], "angle"),
        "rho": (profile.rho_surface[k], "length"),
        "x": (profile.surface.real[k], "length"),
        "y": (profile.surface.imag[k], "length"),
    }
    return cols


def _table(name: str, title: str, cols: dict[str, tuple[Any, str | None]]) -> ResultTable:
    return ResultTable(
        name,
        title,
        {k: np.ravel(val) for k, (val, _) in cols.items()},
        {k: kind for k, (_, kind) in cols.items()},
    )


PART_KINDS = {"cam": PartKind("cam", CAM, _build, _values_of, _run)}
