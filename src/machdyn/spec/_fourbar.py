"""Part kinds ``fourbar``, ``slider_crank`` and ``inverted_slider_crank``.

Reading builds :class:`~machdyn.fourbar.FourBar`, :class:`~machdyn.slidercrank.SliderCrank`
and :class:`~machdyn.slidercrank.InvertedSliderCrank`; running solves the motion
the part's ``[motion]`` asks for and, with masses, the forces (the library's
``dynamics``), and tabulates them. No physics here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._context import Context
from ._machine import Machine, Part, PartKind
from ._run import PartResult, ResultTable, Summary, TorqueCurve, flagged_rows
from ._simulate import FOURBAR_TOLERANCE, SIMULATE, SLIDER_TOLERANCE
from ._types import (
    Choice,
    Grid,
    ListOf,
    Name,
    OneOf,
    Position,
    Quantity,
    Sweep,
    Table,
    Text,
    fields,
    optional,
    required,
)

__all__ = ["PART_KINDS"]

#: A full turn of a crank, sampled for `run`'s tables (a flywheel takes finer steps:
#: :data:`~machdyn.spec._run.FLYWHEEL_SAMPLES`).
FULL_TURN = Grid(0.0, 2.0 * np.pi, np.radians(10.0))


def _length(doc: str = "", minimum: float | None = None, positive: bool = False) -> Any:
    return Quantity("length", minimum=minimum, positive=positive)


POINT_ON_LINK = Table(
    fields(
        p=required(Quantity("length", minimum=0.0), "distance from the link's first joint"),
        delta=required(Quantity("angle"), "angle from the link's line, counter-clockwise"),
    ),
    doc="a point on a link: p from its first joint, delta from its line",
)

MOTION = Table(
    fields(
        theta2=optional(Sweep("angle"), "input angles: one, [start, stop, step] or {values}"),
        omega2=optional(Quantity("angular_velocity"), "input angular velocity (default 1 rad/s)"),
        alpha2=optional(Quantity("angular_acceleration"), "input angular acceleration"),
        driven_by=optional(Name(), "a gear_pair or gear_train whose output turns the input"),
    ),
    doc="what to analyse: the input's angles and rates",
)

MASS = Table(
    fields(
        mass=required(Quantity("mass", minimum=0.0)),
        inertia=optional(Quantity("inertia", minimum=0.0), "about the centre of mass"),
        cg=optional(
            OneOf(Position(), Quantity("length")),
            "centre of mass in the link frame: [x, y] or a length along x",
        ),
    ),
    doc="mass properties of a link, in its own frame",
)

FORCE = Table(
    fields(
        link=required(Choice(2, 3, 4)),
        at=required(Position(), "point of application in the link frame"),
        force=required(Position("force"), "[Fx, Fy] in the ground frame"),
    ),
    doc="a point load on a moving link",
)


def _torques(links: tuple[int, ...]) -> Table:
    return Table(fields(**{f"link{n}": optional(Quantity("torque")) for n in links}))


FOURBAR_LOADS = Table(
    fields(
        torque4=optional(Quantity("torque"), "external torque on the output link (CCW +)"),
        torques=optional(_torques((2, 3, 4)), "external torques on links 2-4"),
        force=optional(ListOf(FORCE), "point loads: [[...loads.force]]"),
    )
)

SLIDER_LOADS = Table(
    fields(
        force4=optional(Quantity("force"), "external force on the slider along +x"),
        friction=optional(Choice("smooth", "coulomb", "viscous")),
        mu=optional(Quantity("dimensionless", minimum=0.0), "Coulomb coefficient"),
        beta=optional(Quantity("damping", minimum=0.0), "viscous coefficient"),
        torques=optional(_torques((2, 3))),
        force=optional(ListOf(FORCE)),
    )
)

FOURBAR = Table(
    fields(
        r1=required(_length(positive=True), "ground O2O4"),
        r2=required(_length(positive=True), "input O2A"),
        r3=required(_length(positive=True), "coupler AB"),
        r4=required(_length(positive=True), "output O4B"),
        coupler=optional(POINT_ON_LINK, "coupler point P: p from A, delta from AB"),
        form=optional(Choice(1, 2)),
        branch=optional(Choice(1, -1), "GRCR/GRRC only: the sign of phi12"),
        O2=optional(Position(), "placed in the plane: where O2 is (with theta1)"),
        theta1=optional(Quantity("angle"), "placed: the angle of O2 -> O4 from +x"),
        motion=optional(MOTION),
        link2=optional(MASS),
        link3=optional(MASS),
        link4=optional(MASS),
        loads=optional(FOURBAR_LOADS),
        simulate=optional(SIMULATE, "for `machdyn simulate`"),
        tolerance=optional(FOURBAR_TOLERANCE, "for `machdyn tolerance`"),
        notes=optional(Text()),
    ),
    doc="a four-bar: ground r1, input r2, coupler r3, output r4",
)

SLIDER_CRANK = Table(
    fields(
        crank=required(_length(positive=True), "a = O2A"),
        coupler=required(_length(positive=True), "b = AB"),
        offset=optional(_length(), "slide line above O2"),
        point=optional(POINT_ON_LINK, "a point on the rod: p from A, delta from AB"),
        form=optional(Choice(1, 2)),
        motion=optional(MOTION),
        link2=optional(MASS),
        link3=optional(MASS),
        link4=optional(MASS),
        loads=optional(SLIDER_LOADS),
        simulate=optional(SIMULATE, "for `machdyn simulate`"),
        tolerance=optional(SLIDER_TOLERANCE, "for `machdyn tolerance`"),
        notes=optional(Text()),
    ),
    doc="an offset slider-crank",
)

INVERTED_LOADS = Table(
    fields(
        torque4=optional(Quantity("torque"), "external torque on the slotted link (CCW +)"),
        friction=optional(Choice("smooth", "coulomb", "viscous"), "of the slot on the block"),
        mu=optional(Quantity("dimensionless", minimum=0.0), "Coulomb coefficient"),
        beta=optional(Quantity("damping", minimum=0.0), "viscous coefficient"),
        torques=optional(_torques((2, 3, 4)), "external torques on links 2-4"),
        force=optional(ListOf(FORCE), "point loads: [[...loads.force]]"),
    )
)

INVERTED = Table(
    fields(
        crank=required(_length(positive=True), "a = O2A"),
        ground=required(_length(positive=True), "d = O2O4"),
        offset=optional(_length(), "slot offset from O4"),
        form=optional(Choice(1, 2)),
        motion=optional(MOTION),
        link2=optional(MASS, "the crank (frame: O2, x toward A)"),
        link3=optional(MASS, "the block (frame: A, x along the slot)"),
        link4=optional(MASS, "the slotted link (frame: O4, x along the slot)"),
        loads=optional(INVERTED_LOADS),
        notes=optional(Text()),
    ),
    doc="Norton's inverted slider-crank (inversion #3)",
)

_MODEL_KEYS = {
    "fourbar": ("r1", "r2", "r3", "r4", "coupler"),
    "slider_crank": ("crank", "coupler", "offset", "point"),
    "inverted_slider_crank": ("crank", "ground", "offset"),
}


# ------------------------------------------------------------------- building
def _fields(path: tuple, keys: tuple[str, ...], point: str = "coupler") -> dict[str, tuple]:
    out = {k: (*path, k) for k in keys}
    out |= {f"{point} p": (*path, point, "p"), f"{point} delta": (*path, point, "delta")}
    return out


def _build_fourbar(ctx: Context, path: tuple, v: dict) -> Any:
    from ..fourbar import FourBar

    coupler = (v["coupler"]["p"], v["coupler"]["delta"]) if "coupler" in v else None
    with ctx.at(path, _fields(path, ("r1", "r2", "r3", "r4"))):
        fb = FourBar(v["r1"], v["r2"], v["r3"], v["r4"], coupler=coupler)
        if "branch" in v:
            fb._branch_and_side(v.get("form", 1), v["branch"])
    fb.units = None if ctx.system.is_unit_free else ctx.system
    return fb


def _build_slider(ctx: Context, path: tuple, v: dict) -> Any:
    from ..slidercrank import SliderCrank

    point = (v["point"]["p"], v["point"]["delta"]) if "point" in v else None
    with ctx.at(path, _fields(path, ("crank", "coupler", "offset"), "point")):
        sc = SliderCrank(v["crank"], v["coupler"], v.get("offset", 0.0), point=point)
    sc.units = None if ctx.system.is_unit_free else ctx.system
    return sc


def _build_inverted(ctx: Context, path: tuple, v: dict) -> Any:
    from ..slidercrank import InvertedSliderCrank

    with ctx.at(path, _fields(path, ("crank", "ground", "offset"))):
        isc = InvertedSliderCrank(v["crank"], v["ground"], v.get("offset", 0.0))
    isc.units = None if ctx.system.is_unit_free else ctx.system
    return isc


def _fourbar_values(fb: Any) -> dict:
    out: dict[str, Any] = {"r1": fb.r1, "r2": fb.r2, "r3": fb.r3, "r4": fb.r4}
    if fb.coupler is not None:
        out["coupler"] = {"p": fb.coupler[0], "delta": fb.coupler[1]}
    return out


def _slider_values(sc: Any) -> dict:
    out: dict[str, Any] = {"crank": sc.a, "coupler": sc.b}
    if sc.c:
        out["offset"] = sc.c
    if sc.point is not None:
        out["point"] = {"p": sc.point[0], "delta": sc.point[1]}
    return out


def _inverted_values(isc: Any) -> dict:
    out: dict[str, Any] = {"crank": isc.a, "ground": isc.d}
    if isc.c:
        out["offset"] = isc.c
    return out


# ------------------------------------------------------------------- running
def input_angles(part: Part) -> np.ndarray:
    """The θ2 samples a part is analysed at.

    Its ``[motion] theta2``; else a turn, or, for a four-bar whose input rocks, 37
    values over the input's range.
    """
    motion = part.values.get("motion", {})
    model = part.model
    if "theta2" in motion:
        return motion["theta2"].values
    if part.kind == "fourbar" and not model.input_range(part.values.get("form", 1)).full_turn:
        return model.input_range(part.values.get("form", 1)).grid(37)
    return FULL_TURN.values


def input_motion(part: Part, machine: Machine, results: dict) -> tuple[np.ndarray, float, float]:
    """θ2 samples, ω2 and α2 of a part's ``[motion]`` (ω2 from ``driven_by`` if given)."""
    motion = part.values.get("motion", {})
    omega2 = motion.get("omega2", 1.0 if machine.units.is_unit_free else _rad_per_s(machine))
    if "driven_by" in motion:
        omega2 = results[motion["driven_by"]].speed
    return input_angles(part), float(omega2), float(motion.get("alpha2", 0.0))


def _rad_per_s(machine: Machine) -> float:
    """1 rad/s in the machine's angular-velocity unit (its internal rad per time unit)."""
    from .. import units as u

    return u._factor("rad/s", machine.units.internal("angular_velocity"))


def _masses(v: dict, links: tuple[int, ...]) -> dict[str, Any] | None:
    if not any(f"link{n}" in v for n in links):
        return None
    tables = [v.get(f"link{n}", {"mass": 0.0}) for n in links]
    return {
        "mass": tuple(t["mass"] for t in tables),
        "inertia": tuple(t.get("inertia", 0.0) for t in tables),
        "cg": tuple(complex(t.get("cg", 0.0)) for t in tables),
    }


def _external(loads: dict, links: tuple[int, ...]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if "force" in loads:
        out["external_forces"] = [(f["link"], f["at"], f["force"]) for f in loads["force"]]
    torques = loads.get("torques", {})
    if torques:
        out["external_torques"] = {int(k.removeprefix("link")): val for k, val in torques.items()}
    return out


def placement(v: dict) -> tuple[complex, float] | None:
    """``(O2, theta1)`` of a four-bar placed in the plane (a synthesis result), else None.

    Global = O2 + e^{jθ1}·local; either key alone places it (the other 0).
    """
    if "O2" not in v and "theta1" not in v:
        return None
    return complex(v.get("O2", 0j)), float(v.get("theta1", 0.0))


def _in_own_frame(
    v: dict, masses: dict, external: dict, gravity: float | None
) -> tuple[dict[str, Any], float]:
    """A four-bar's loads in its own frame (x along O2 → O4) and the gravity to pass.

    Unplaced: as given. Placed (``O2``/``theta1``, a synthesis result): the file's
    force vectors are in the plane, and gravity acts along the plane's −y — turned by
    e^{−jθ1} it becomes a point load ``m g`` at each centre of mass (gravity then 0).
    """
    g = float(gravity or 0.0)
    if "theta1" not in v:
        return external, g  # O2 alone only translates: directions are the plane's
    back = complex(np.exp(-1j * v["theta1"]))
    forces = [(k, at, back * F) for k, at, F in external.get("external_forces", [])]
    if g:
        weights = zip((2, 3, 4), masses["mass"], masses["cg"], strict=True)
        forces += [(k, cg, -1j * g * mass * back) for k, mass, cg in weights if mass]
    out = dict(external)
    if forces:
        out["external_forces"] = forces
    return out, 0.0


def _kin_table(name: str, title: str, cols: dict[str, tuple[Any, str | None]]) -> ResultTable:
    return ResultTable(
        name,
        title,
        {k: np.ravel(v) for k, (v, _) in cols.items()},
        {k: kind for k, (_, kind) in cols.items()},
    )


def _flags(m: Any) -> dict[str, tuple[Any, str | None]]:
    return {"ok": (m.ok, None), "reason": (m.reason, None)}


def _xy(name: str, z: Any, kind: str) -> dict[str, tuple[Any, str]]:
    return {f"{name}_x": (np.real(z), kind), f"{name}_y": (np.imag(z), kind)}


def _rates_title(machine: Machine, omega2: float, alpha2: float) -> str:
    s = machine.units
    w = s.show("angular_velocity", omega2)
    a = s.show("angular_acceleration", alpha2)
    return (
        f"omega2 = {w:.6g} {s.display('angular_velocity')}, "
        f"alpha2 = {a:.6g} {s.display('angular_acceleration')}"
    )


def _run_fourbar(part: Part, machine: Machine, results: dict) -> PartResult:
    fb, v = part.model, part.values
    form = v.get("form", 1)
    theta2, omega2, alpha2 = input_motion(part, machine, results)
    m = fb.solve(theta2, omega2, alpha2, form, branch=v.get("branch"))
    out = PartResult(part, objects={"motion": m})
    c = fb.classification
    rng = fb.input_range(form)
    out.summary += [
        Summary("class", f"{c.code} (Barker #{c.number}: {c.name})"),
        Summary("condition", c.condition),
        Summary("cranks", ", ".join(f"link {n}" for n in c.cranks) or "none"),
        Summary("form", f"{form} ({fb.form_rule} {'> 0' if form == 1 else '< 0'})"),
        Summary("input range", "full turn" if rng.full_turn else [rng.lo, rng.hi], "angle"),
    ]
    for tg in fb.toggles():
        side = f", branch {tg.branch:+d}" if tg.branch else ""
        out.summary.append(
            Summary(
                f"toggle: links {tg.links[0]}-{tg.links[1]} {tg.kind}{side}", tg.theta2, "angle"
            )
        )
    # placed (a synthesis result): the model works in its own frame (x along O2 → O4);
    # positions and forces are shown in the plane's (global = O2 + e^{jθ1}·local), the
    # file's loads are read in it and gravity acts along the plane's −y
    placed = placement(v)
    o2, theta1 = placed or (0j, 0.0)
    turn = complex(np.exp(1j * theta1))
    if placed:
        out.summary.append(Summary("placed: O2", [o2.real, o2.imag], "length"))
        out.summary.append(Summary("placed: theta1", theta1, "angle"))
    good = m.ok & np.isfinite(m.mu)
    if good.any():
        out.summary.append(
            Summary("mu over the sweep (min, max)", [m.mu[good].min(), m.mu[good].max()], "angle")
        )
    cols: dict[str, tuple[Any, str | None]] = {
        "theta2": (m.theta2, "angle"),
        "theta3": (m.theta3, "angle"),
        "theta4": (m.theta4, "angle"),
        "omega3": (m.omega3, "angular_velocity"),
        "omega4": (m.omega4, "angular_velocity"),
        "alpha3": (m.alpha3, "angular_acceleration"),
        "alpha4": (m.alpha4, "angular_acceleration"),
        "mu": (m.mu, "angle"),
        **_flags(m),
    }
    title = f"Kinematics of {part.name}, {_rates_title(machine, omega2, alpha2)}"
    out.tables.append(_kin_table("kinematics", title, cols))
    if m.coupler is not None:
        cols = {
            "theta2": (m.theta2, "angle"),
            **_xy("P", o2 + turn * m.coupler, "length"),
            **_xy("VP", turn * m.coupler_velocity, "velocity"),
            **_xy("AP", turn * m.coupler_acceleration, "acceleration"),
            **_flags(m),
        }
        out.tables.append(_kin_table("coupler", f"Coupler point P of {part.name}", cols))
    masses = _masses(v, (2, 3, 4))
    if masses is not None:
        loads = v.get("loads", {})
        external, g = _in_own_frame(v, masses, _external(loads, (2, 3, 4)), machine.gravity)
        options = dict(form=form, branch=v.get("branch"), gravity=g,
                       load_torque4=loads.get("torque4", 0.0), **masses, **external)  # fmt: skip
        f = fb.dynamics(theta2, omega2, alpha2, **options)
        out.objects["forces"] = f
        cols = {"theta2": (m.theta2, "angle"), "T12": (f.T12, "torque")}
        for name in ("F12", "F32", "F43", "F14"):
            cols |= _xy(name, turn * getattr(f, name), "force")
        cols |= {"M_shaking": (f.shaking_moment, "torque"), **_flags(f)}
        out.tables.append(_kin_table("forces", f"Forces on {part.name}", cols))
        out.torque = _torque_curve(fb.dynamics, omega2, alpha2, options)
    _flag_lines(out, machine, m.theta2, m.ok, m.reason)
    return out


def _flag_lines(out: PartResult, machine: Machine, theta2: Any, ok: Any, reason: Any) -> None:
    s = machine.units
    label = f"theta2 [{s.display('angle')}]"
    out.flagged += flagged_rows(label, s.show("angle", np.asarray(theta2)), ok, reason)


def _run_slider(part: Part, machine: Machine, results: dict) -> PartResult:
    sc, v = part.model, part.values
    form = v.get("form", 1)
    theta2, omega2, alpha2 = input_motion(part, machine, results)
    m = sc.solve(theta2, omega2, alpha2, form)
    out = PartResult(part, objects={"motion": m})
    lo, hi = sc.stroke(form)
    rng = sc.input_range()
    out.summary += [
        Summary("crank", "turns fully" if sc.crank_rotates else "rocks"),
        Summary("stroke (d min, d max)", [lo, hi], "length"),
    ]
    if rng is not None:
        out.summary.append(Summary("input range", list(rng), "angle"))
    cols: dict[str, tuple[Any, str | None]] = {
        "theta2": (m.theta2, "angle"),
        "theta3": (m.theta3, "angle"),
        "omega3": (m.omega3, "angular_velocity"),
        "alpha3": (m.alpha3, "angular_acceleration"),
        "d": (m.d, "length"),
        "d_dot": (m.d_dot, "velocity"),
        "d_ddot": (m.d_ddot, "acceleration"),
        **_flags(m),
    }
    title = f"Kinematics of {part.name}, {_rates_title(machine, omega2, alpha2)}"
    out.tables.append(_kin_table("kinematics", title, cols))
    if m.coupler is not None:
        cols = {
            "theta2": (m.theta2, "angle"),
            **_xy("P", m.coupler, "length"),
            **_xy("VP", m.coupler_velocity, "velocity"),
            **_xy("AP", m.coupler_acceleration, "acceleration"),
            **_flags(m),
        }
        out.tables.append(_kin_table("point", f"Point P on the rod of {part.name}", cols))
    masses = _masses(v, (2, 3, 4))
    if masses is not None:
        loads = v.get("loads", {})
        masses["inertia"] = masses["inertia"][:2]
        masses["cg"] = masses["cg"][:2]
        options = dict(form=form, gravity=machine.gravity or 0.0,
                       load_force4=loads.get("force4", 0.0), **_friction(loads), **masses,
                       **_external(loads, (2, 3)))  # fmt: skip
        f = sc.dynamics(theta2, omega2, alpha2, **options)
        out.objects["forces"] = f
        cols = {"theta2": (m.theta2, "angle"), "T12": (f.T12, "torque")}
        for name in ("F12", "F32", "F43", "F14"):
            cols |= _xy(name, getattr(f, name), "force")
        cols |= {"M_shaking": (f.shaking_moment, "torque"), **_flags(f)}
        out.tables.append(_kin_table("forces", f"Forces on {part.name}", cols))
        out.torque = _torque_curve(sc.dynamics, omega2, alpha2, options)
    _flag_lines(out, machine, m.theta2, m.ok, m.reason)
    return out


def _run_inverted(part: Part, machine: Machine, results: dict) -> PartResult:
    isc, v = part.model, part.values
    theta2, omega2, alpha2 = input_motion(part, machine, results)
    m = isc.solve(theta2, omega2, alpha2, v.get("form", 1))
    out = PartResult(part, objects={"motion": m})
    cols: dict[str, tuple[Any, str | None]] = {
        "theta2": (m.theta2, "angle"),
        "theta4": (m.theta4, "angle"),
        "omega4": (m.omega4, "angular_velocity"),
        "alpha4": (m.alpha4, "angular_acceleration"),
        "b": (m.b, "length"),
        "b_dot": (m.b_dot, "velocity"),
        "b_ddot": (m.b_ddot, "acceleration"),
        **_flags(m),
    }
    title = f"Kinematics of {part.name}, {_rates_title(machine, omega2, alpha2)}"
    out.tables.append(_kin_table("kinematics", title, cols))
    masses = _masses(v, (2, 3, 4))
    if masses is not None:
        loads = v.get("loads", {})
        options = dict(form=v.get("form", 1), gravity=machine.gravity or 0.0,
                       load_torque4=loads.get("torque4", 0.0), **_friction(loads), **masses,
                       **_external(loads, (2, 3, 4)))  # fmt: skip
        f = isc.dynamics(theta2, omega2, alpha2, **options)
        out.objects["forces"] = f
        cols = {"theta2": (m.theta2, "angle"), "T12": (f.T12, "torque")}
        for name in ("F12", "F32", "F43", "F14"):
            cols |= _xy(name, getattr(f, name), "force")
        cols |= {"N": (f.normal, "force"), "C43": (f.couple, "torque")}
        cols |= {"M_shaking": (f.shaking_moment, "torque"), **_flags(f)}
        out.tables.append(_kin_table("forces", f"Forces on {part.name}", cols))
        out.torque = _torque_curve(isc.dynamics, omega2, alpha2, options)
    _flag_lines(out, machine, m.theta2, m.ok, m.reason)
    return out


def _friction(loads: dict) -> dict[str, Any]:
    """A slider's friction options of a part's ``[loads]``."""
    return {"friction": loads.get("friction", "smooth"), "mu": loads.get("mu", 0.0),
            "beta": loads.get("beta", 0.0)}  # fmt: skip


def _torque_curve(dynamics: Any, omega2: float, alpha2: float, options: dict) -> TorqueCurve:
    """The driving torque T12 at any crank angles, for a flywheel (same speed, loads)."""
    return TorqueCurve(lambda theta2: dynamics(theta2, omega2, alpha2, **options).T12, omega2)


def _refs(values: dict) -> dict[tuple, str]:
    motion = values.get("motion", {})
    return {("motion", "driven_by"): motion["driven_by"]} if "driven_by" in motion else {}


PART_KINDS = {
    "fourbar": PartKind(
        "fourbar", FOURBAR, _build_fourbar, _fourbar_values, _run_fourbar, _refs, "torque"
    ),
    "slider_crank": PartKind(
        "slider_crank", SLIDER_CRANK, _build_slider, _slider_values, _run_slider, _refs, "torque"
    ),
    "inverted_slider_crank": PartKind(
        "inverted_slider_crank",
        INVERTED,
        _build_inverted,
        _inverted_values,
        _run_inverted,
        _refs,
        "torque",
    ),
}
