"""Part kinds ``flywheel`` (sizing from a torque curve) and ``rotor`` (balancing).

These are tasks, not mechanisms: :class:`FlywheelSizing` and
:class:`RotorBalance` hold what the library's :func:`~machdyn.flywheel.size_flywheel`
and :mod:`~machdyn.balancing` functions take, with ``solve()`` calling them
and ``to_spec()`` writing them back. A flywheel's torque curve is an array in
the file, a CSV file (``machdyn linkage --csv`` or ``machdyn run --csv``
output, or a spreadsheet's), or another part of the machine (its driving
torque over one turn). No physics here.
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import units as u
from .._validate import finite_array, finite_scalar, nonnegative, positive, text
from ..errors import InputError
from ._context import Context, _show, check_units
from ._machine import Machine, Part, PartKind
from ._run import PartResult, ResultTable, Summary, rounded
from ._types import (
    ListOf,
    Number,
    OneOf,
    Quantities,
    Quantity,
    Table,
    Text,
    Type,
    fields,
    optional,
    required,
)

__all__ = ["PART_KINDS", "FlywheelSizing", "RotorBalance", "read_torque_csv"]

_HEADER_UNIT = re.compile(r"^\s*(.*?)\s*\[(.*)\]\s*$")


# ------------------------------------------------------------------- CSV torque curves
def read_torque_csv(path: str | Path, system: u.UnitSystem | None = None) -> tuple[Any, Any]:
    r"""θ (radians) and the torque of a CSV file of one cycle, in ``system``'s units.

    The first column is the angle (degrees unless its header says ``[rad]``);
    the torque is the column named ``T12`` or ``T_<driver>`` (the tables of
    ``machdyn run`` and ``machdyn linkage``), else the second column. A header
    unit (``T12 [N*m]``) is converted into ``system``'s torque unit; without a
    system the numbers are taken as they are. ``#`` lines are comments. A row
    whose torque is empty (a pose that could not be solved) is an error: a
    flywheel needs the whole cycle.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     file = pathlib.Path(tmp) / "t.csv"
    ...     _ = file.write_text("theta_crank [deg],omega [rad/s],T_crank [N*m]\n0,1,2\n90,1,3\n")
    ...     theta, torque = read_torque_csv(file)
    >>> theta.round(4).tolist(), torque.tolist()
    ([0.0, 1.5708], [2.0, 3.0])
    """
    if not isinstance(path, str | Path) or not str(path).strip():
        raise InputError("path", f"expected a file name, got {path!r}")
    system = check_units(system)
    path = Path(path)
    try:
        content = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(str(path), f"cannot read it: {exc.strerror or exc}") from None
    except UnicodeDecodeError as exc:
        raise InputError(str(path), f"not UTF-8 text (byte {exc.start})") from None
    rows = [
        (n, [c.strip() for c in row])
        for n, row in enumerate(csv.reader(content.splitlines()), start=1)
        if row and any(c.strip() for c in row) and not row[0].lstrip().startswith("#")
    ]
    if not rows:
        raise InputError(str(path), "holds no rows of angle and torque")
    header: list[str] | None = None
    if not _numeric(rows[0][1][0]):
        header = rows[0][1]
        rows = rows[1:]
    angle_col, torque_col, angle_unit, torque_unit = _columns(path, header)
    thetas, torques = [], []
    for n, cells in rows:
        where = f"{path}:{n}"
        if len(cells) <= max(angle_col, torque_col):
            raise InputError(where, f"has {len(cells)} values; expected angle and torque columns")
        if not cells[torque_col]:
            message = "has no torque (a pose that was not solved): a flywheel needs the cycle"
            raise InputError(where, message)
        try:
            theta, torque = float(cells[angle_col]), float(cells[torque_col])
        except ValueError:
            raise InputError(where, f"is not numbers: {','.join(cells)!r}") from None
        if not (math.isfinite(theta) and math.isfinite(torque)):
            raise InputError(where, "holds a value that is not finite")
        thetas.append(theta)
        torques.append(torque)
    if not thetas:
        raise InputError(str(path), "holds no rows of angle and torque")
    theta = np.array(thetas) * u._factor(angle_unit, "rad") if angle_unit != "deg" else None
    if theta is None:
        theta = np.radians(thetas)
    torque = np.array(torques)
    if system is not None and not system.is_unit_free and torque_unit:
        try:
            u.check_unit(torque_unit, "torque")
        except ValueError as exc:
            raise InputError(f"{path}: torque column", str(exc)) from None
        torque = torque * u._factor(torque_unit, system.internal("torque"))
    return theta, torque


def _numeric(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True


def _columns(path: Path, header: list[str] | None) -> tuple[int, int, str, str]:
    if header is None:
        return 0, 1, "deg", ""
    names, unit = [], []
    for cell in header:
        found = _HEADER_UNIT.match(cell)
        names.append(found[1] if found else cell.strip())
        unit.append(found[2].strip() if found else "")
    torque_col = next(
        (i for i, name in enumerate(names) if name == "T12" or name.startswith("T_")), 1
    )
    if len(names) < 2:
        raise InputError(str(path), "needs an angle column and a torque column")
    angle_unit = unit[0] or ("rad" if names[0].endswith("_rad") else "deg")
    if angle_unit not in ("deg", "rad"):
        try:
            u.check_unit(angle_unit, "angle")
        except ValueError as exc:
            raise InputError(f"{path}: first column", str(exc)) from None
    return 0, torque_col, angle_unit, unit[torque_col]


# ------------------------------------------------------------------- flywheel
@dataclass(frozen=True, eq=False)
class FlywheelSizing:
    """A flywheel to size: a torque curve over one cycle, a mean speed and a fluctuation.

    ``theta`` and ``torque`` are the curve (None when it comes from another
    part, named by ``source``); ``csv`` names the file it was read from.

    Examples
    --------
    >>> theta = np.linspace(0, 2 * np.pi, 361)
    >>> task = FlywheelSizing(theta, 50 + 10 * np.sin(theta), k=0.02, omega_avg=100.0)
    >>> round(task.solve().inertia, 6)
    0.1
    """

    theta: Any
    torque: Any
    k: float
    omega_avg: float | None = None
    period: float = 2 * math.pi
    density: float | None = None
    thickness: float | None = None
    inner_radius: float = 0.0
    source: str | None = None
    csv: str | None = None
    units: Any = field(default=None, compare=False)

    def __post_init__(self) -> None:
        s = object.__setattr__
        if (self.theta is None) != (self.torque is None):
            raise InputError("torque", "give theta and torque together (or neither: a source)")
        if self.theta is not None:
            theta = finite_array("theta", self.theta)
            torque = finite_array("torque", self.torque)
            if theta.ndim != 1 or theta.shape != torque.shape or theta.size < 3:
                raise InputError("torque", "theta and torque: one value each, at least 3")
            s(self, "theta", theta)
            s(self, "torque", torque)
        k = finite_scalar("k", self.k)
        if not 0.0 < k < 0.5:
            raise InputError("k", f"coefficient of fluctuation must be in (0, 0.5); got {k}")
        s(self, "k", k)
        if self.omega_avg is not None:
            s(self, "omega_avg", finite_scalar("omega_avg", self.omega_avg))
        s(self, "period", positive("period", self.period))
        for key in ("density", "thickness"):
            if getattr(self, key) is not None:
                s(self, key, positive(key, getattr(self, key)))
        s(self, "inner_radius", nonnegative("inner_radius", self.inner_radius))
        for key in ("source", "csv"):
            if getattr(self, key) is not None:
                s(self, key, text(key, getattr(self, key)))
        check_units(self.units)

    def solve(self, theta: Any = None, torque: Any = None, omega_avg: float | None = None) -> Any:
        """The :class:`~machdyn.flywheel.FlywheelResult` (the curve and speed may be given)."""
        from ..flywheel import size_flywheel

        theta = self.theta if theta is None else finite_array("theta", theta)
        torque = self.torque if torque is None else finite_array("torque", torque)
        if omega_avg is not None:
            omega_avg = finite_scalar("omega_avg", omega_avg)
        omega = self.omega_avg if self.omega_avg is not None else omega_avg
        if theta is None or omega is None:
            raise InputError("flywheel", "needs its torque curve and omega_avg")
        from ..units import with_units

        result = size_flywheel(theta, torque, abs(omega), self.k, period=self.period)
        with_units(result.lobes, self.units)
        return with_units(result, self.units)  # to_pandas() columns with units

    def disc(self, inertia: float) -> Any:
        """The disc of ``inertia`` (:func:`~machdyn.flywheel.disc_flywheel`), if sized."""
        from ..flywheel import disc_flywheel

        inertia = nonnegative("inertia", inertia)
        if self.density is None or self.thickness is None or inertia == 0:
            return None
        return disc_flywheel(inertia, self.density, self.thickness, self.inner_radius)

    def to_spec(self, name: str = "flywheel") -> dict[str, Any]:
        """The task as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from . import model_spec

        return model_spec(self, "flywheel", name)


class TorqueSource(Type):
    """A flywheel's ``torque``: a part name, a CSV file name, or an array of torques."""

    what = "a part name, a CSV file name, or an array of torques"

    def read(self, ctx: Context, path: tuple, value: Any) -> Any:
        if isinstance(value, list):
            return ("array", Quantities("torque", minimum=3).read(ctx, path, value))
        if isinstance(value, str) and value.strip():
            if value.lower().endswith(".csv"):
                return ("csv", value)
            return ("part", value)
        raise ctx.error(path, f"expected {self.what}, got {_show(value)}")

    def write(self, w: Any, value: Any) -> Any:
        kind, content = value
        if kind == "array":
            return Quantities("torque").write(w, content)
        return content

    def schema(self) -> dict:
        return {
            "anyOf": [
                {"type": "string", "minLength": 1},
                {"type": "array", "items": {"$ref": "#/$defs/torque"}, "minItems": 3},
            ]
        }


FLYWHEEL = Table(
    fields(
        torque=required(TorqueSource(), "a part, a CSV file, or an array of torques"),
        theta=optional(Quantities("angle", minimum=3), "the angles of an array of torques"),
        k=required(Number(positive=True, below=0.5), "coefficient of fluctuation"),
        omega_avg=optional(Quantity("angular_velocity"), "default: the source part's speed"),
        period=optional(Quantity("angle", positive=True), "default 360 deg"),
        density=optional(Quantity("density", positive=True), "to size a disc"),
        thickness=optional(Quantity("length", positive=True), "to size a disc"),
        inner_radius=optional(Quantity("length", minimum=0.0)),
        notes=optional(Text()),
    ),
    doc="a flywheel sized from a torque curve (Table 11-1 method)",
)


def _build_flywheel(ctx: Context, path: tuple, v: dict) -> FlywheelSizing:
    kind, content = v["torque"]
    theta = torque = source = csv_name = None
    if kind == "array":
        if "theta" not in v:
            raise ctx.error((*path, "theta"), "missing: the angles of the torque array")
        theta, torque = v["theta"], content
        if theta.size != torque.size:
            raise ctx.error((*path, "theta"), f"{theta.size} angles for {torque.size} torques")
    elif kind == "csv":
        if "theta" in v:
            raise ctx.error((*path, "theta"), "the angles come from the CSV file")
        csv_name = content
        file = (ctx.folder or Path(".")) / content
        try:
            theta, torque = read_torque_csv(file, ctx.system)
        except InputError as exc:
            raise ctx.error((*path, "torque"), str(exc)) from None
    else:
        source = content
        if "theta" in v:
            raise ctx.error((*path, "theta"), f"the angles come from the part {source!r}")
    task = FlywheelSizing(
        theta,
        torque,
        v["k"],
        v.get("omega_avg"),
        v.get("period", 2 * math.pi),
        v.get("density"),
        v.get("thickness"),
        v.get("inner_radius", 0.0),
        source,
        csv_name,
        None if ctx.system.is_unit_free else ctx.system,
    )
    if (task.density is None) != (task.thickness is None):
        key = "thickness" if task.thickness is None else "density"
        raise ctx.error((*path, key), "give density and thickness to size a disc (both)")
    if task.source is None:
        keys = {"omega_avg": (*path, "omega_avg"), "k": (*path, "k"), "theta": (*path, "theta")}
        with ctx.at(path, keys):
            if task.omega_avg is None:
                raise ctx.error((*path, "omega_avg"), "missing: the mean speed of the shaft")
            task.solve()  # the curve and its cycle are checked now, not at run time
    return task


def _flywheel_values(task: FlywheelSizing) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if task.source is not None:
        out["torque"] = ("part", task.source)
    elif task.csv is not None:
        out["torque"] = ("csv", task.csv)
    else:
        out["torque"] = ("array", np.asarray(task.torque, dtype=float))
        out["theta"] = np.asarray(task.theta, dtype=float)
    out["k"] = task.k
    for key in ("omega_avg", "density", "thickness"):
        if getattr(task, key) is not None:
            out[key] = getattr(task, key)
    if task.period != 2 * math.pi:
        out["period"] = task.period
    if task.inner_radius:
        out["inner_radius"] = task.inner_radius
    return out


def _run_flywheel(part: Part, machine: Machine, results: dict) -> PartResult:
    task = part.model
    theta = torque = omega = None
    if task.source is not None:
        source = results[task.source]
        if source.torque is None:
            raise machine._error(
                (*part.path, "torque"),
                f"{task.source!r} gives no driving torque: it needs masses (or loads) and one "
                "angle driver turning a full cycle",
            )
        theta, torque = source.torque.over_turn()
        omega = source.torque.omega
    try:
        result = task.solve(theta, torque, omega)
    except InputError as exc:
        where = f"the torque of {task.source!r}: " if task.source else ""
        raise machine._error((*part.path, "torque"), where + str(exc)) from None
    out = PartResult(part, objects={"flywheel": result})
    out.summary += [
        Summary("T_avg", rounded(result.torque_avg, np.abs(result.torque).max()), "torque"),
        Summary("delta_E", result.delta_e, "energy"),
        Summary("omega_avg", result.omega_avg, "angular_velocity"),
        Summary("k (asked, achieved)", [result.k, result.k_achieved]),
        Summary("I (flywheel inertia)", result.inertia, "inertia"),
        Summary("omega min, max", [result.omega_min, result.omega_max], "angular_velocity"),
    ]
    out.summary.append(Summary("the estimate neglects", "; ".join(result.neglects)))
    if task.source is not None:  # the honest number: the source's own varying inertia
        from ._simulate import simulated_k

        k = simulated_k(machine, task.source, result)
        out.summary.append(Summary("k with the linkage's own inertia (simulated)", k))
    disc = task.disc(result.inertia)
    if disc is not None:
        out.objects["disc"] = disc
        out.summary += [
            Summary("disc outer radius", disc.outer_radius, "length"),
            Summary("disc mass", disc.mass, "mass"),
        ]
    lobes = result.lobes
    out.tables.append(
        ResultTable(
            "lobes",
            f"Lobes of T - T_avg for {part.name} (Table 11-1)",
            {
                "theta_from": lobes.theta_from,
                "theta_to": lobes.theta_to,
                "delta_E": lobes.area,
                "E": lobes.energy,
                "omega_at_end": np.asarray(lobes.omega_at_end, dtype=object),
            },
            {
                "theta_from": "angle",
                "theta_to": "angle",
                "delta_E": "energy",
                "E": "energy",
                "omega_at_end": None,
            },
        )
    )
    return out


def _flywheel_refs(values: dict) -> dict[tuple, str]:
    kind, content = values["torque"]
    return {("torque",): content} if kind == "part" else {}


# ------------------------------------------------------------------- rotor
@dataclass(frozen=True, eq=False)
class RotorBalance:
    """Point masses on a rotor and where to correct them (one plane, or two).

    ``masses`` holds ``(m, R, angle, z)`` for each mass (angle from the rotor's
    reference line, z along its axis); ``planes`` the correction planes' z (None:
    single-plane, static balance); ``radii`` the radius of each correction mass;
    ``bearings`` the bearings' z (their loads at ``speed``, before and after).

    Examples
    --------
    The notes' two-mass static case, m₁R₁ = 3∠0°, m₂R₂ = 2∠90°:

    >>> fix = RotorBalance(((3.0, 1.0, 0.0, 0.0), (2.0, 1.0, math.pi / 2, 0.0))).solve()
    >>> round(abs(fix.mR), 4), round(fix.angle_deg, 2)
    (3.6056, 213.69)
    """

    masses: tuple[tuple[float, float, float, float], ...]
    planes: tuple[float, float] | None = None
    radii: tuple[float, ...] | None = None
    speed: float | None = None
    units: Any = field(default=None, compare=False)
    bearings: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        s = object.__setattr__
        if isinstance(self.masses, str) or not isinstance(self.masses, tuple | list):
            raise InputError("masses", "expected ((m, R, angle, z), ...)")
        masses = []
        for i, entry in enumerate(self.masses):
            if isinstance(entry, str) or not isinstance(entry, tuple | list) or len(entry) != 4:
                raise InputError(f"masses[{i}]", f"expected (m, R, angle, z), got {entry!r}")
            m, r, a, z = entry
            masses.append(
                (
                    positive(f"masses[{i}] m", m),
                    nonnegative(f"masses[{i}] R", r),
                    finite_scalar(f"masses[{i}] angle", a),
                    finite_scalar(f"masses[{i}] z", z),
                )
            )
        if not masses:
            raise InputError("masses", "give at least one mass")
        s(self, "masses", tuple(masses))
        if self.planes is not None:
            planes = finite_array("planes", self.planes)
            if planes.shape != (2,) or planes[0] == planes[1]:
                raise InputError("planes", "two different axial positions (z_A, z_B)")
            s(self, "planes", (float(planes[0]), float(planes[1])))
        if self.radii is not None:
            radii = finite_array("radii", self.radii)
            if radii.ndim != 1 or radii.size not in (1, 2) or (radii <= 0).any():
                raise InputError("radii", "one or two positive radii")
            s(self, "radii", tuple(float(r) for r in radii))
        if self.speed is not None:
            s(self, "speed", finite_scalar("speed", self.speed))
        if self.bearings is not None:
            zb = finite_array("bearings", self.bearings)
            if zb.shape != (2,) or zb[0] == zb[1]:
                raise InputError("bearings", "two different axial positions (z_A, z_B)")
            s(self, "bearings", (float(zb[0]), float(zb[1])))
        check_units(self.units)

    @property
    def unbalance(self) -> np.ndarray:
        """``m R e^{jθ}`` of each mass."""
        return np.array([m * r * np.exp(1j * a) for m, r, a, _ in self.masses])

    def solve(self) -> Any:
        """The correction: a :class:`~machdyn.balancing.StaticBalance` or ``TwoPlaneBalance``."""
        from ..balancing import static_balance, two_plane
        from ..units import with_units

        if self.planes is None:
            return with_units(static_balance(self.unbalance), self.units)
        z = np.array([m[3] for m in self.masses])
        return with_units(two_plane(self.unbalance, z, *self.planes), self.units)

    def to_spec(self, name: str = "rotor") -> dict[str, Any]:
        """The task as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from . import model_spec

        return model_spec(self, "rotor", name)


MASS = Table(
    fields(
        mass=required(Quantity("mass", positive=True)),
        radius=required(Quantity("length", minimum=0.0)),
        angle=required(Quantity("angle")),
        z=optional(Quantity("length"), "axial position (two-plane balance)"),
    )
)
ROTOR = Table(
    fields(
        mass=required(ListOf(MASS, minimum=1), "[[rotor.NAME.mass]]: the rotating masses"),
        planes=optional(Quantities("length", count=2), "z of correction planes A, B"),
        radii=optional(
            OneOf(Quantities("length", minimum=1, count=None), Quantity("length")),
            "radius of the correction mass(es)",
        ),
        speed=optional(Quantity("angular_velocity"), "for the shaking force before balance"),
        bearings=optional(Quantities("length", count=2), "z of bearings A, B (loads at speed)"),
        notes=optional(Text()),
    ),
    doc="rotating masses to balance",
)


def _build_rotor(ctx: Context, path: tuple, v: dict) -> RotorBalance:
    planes = tuple(float(z) for z in v["planes"]) if "planes" in v else None
    masses = []
    for i, e in enumerate(v["mass"], start=1):
        if planes is not None and "z" not in e:
            raise ctx.error((*path, "mass", i, "z"), "missing: two-plane balance needs each z")
        masses.append((e["mass"], e["radius"], e["angle"], e.get("z", 0.0)))
    radii = v.get("radii")
    if radii is not None:
        radii = (float(radii),) if np.ndim(radii) == 0 else tuple(float(r) for r in radii)
        wanted = 1 if planes is None else 2
        if len(radii) not in (1, wanted) or any(r <= 0 for r in radii):
            raise ctx.error((*path, "radii"), f"give {wanted} positive radius(es)")
    bearings = tuple(float(z) for z in v["bearings"]) if "bearings" in v else None
    if bearings is not None and "speed" not in v:
        raise ctx.error((*path, "bearings"), "bearing loads need the rotor's speed: give speed")
    with ctx.at(path, {"bearings": (*path, "bearings")}):
        task = RotorBalance(
            tuple(masses),
            planes,
            radii,
            v.get("speed"),
            None if ctx.system.is_unit_free else ctx.system,
            bearings,
        )
    with ctx.at(path, {"plane_a": (*path, "planes"), "plane_b": (*path, "planes")}):
        task.solve()
    return task


def _rotor_values(task: RotorBalance) -> dict[str, Any]:
    out: dict[str, Any] = {
        "mass": [
            {"mass": m, "radius": r, "angle": a, **({"z": z} if task.planes or z else {})}
            for m, r, a, z in task.masses
        ]
    }
    if task.planes is not None:
        out["planes"] = np.array(task.planes)
    if task.radii is not None:
        out["radii"] = np.array(task.radii)
    if task.speed is not None:
        out["speed"] = task.speed
    if task.bearings is not None:
        out["bearings"] = np.array(task.bearings)
    return out


def _run_rotor(part: Part, machine: Machine, results: dict) -> PartResult:
    task = part.model
    fix = task.solve()
    out = PartResult(part, objects={"balance": fix})
    total = complex(task.unbalance.sum())
    out.summary.append(Summary("unbalance |sum m R|", abs(total), "unbalance"))
    if task.speed is not None:
        out.summary.append(Summary("shaking force before", abs(total) * task.speed**2, "force"))
    if task.bearings is not None:
        out.summary += _bearing_loads(task, fix)
    if task.planes is None:
        cols = {"plane": np.array(["static"], dtype=object), "mR": np.array([abs(fix.mR)])}
        cols["angle"] = np.array([float(fix.theta)]) % (2 * math.pi)  # as `balance static`
        mrs = [abs(fix.mR)]
    else:
        cols = {"plane": np.array(["A", "B"], dtype=object)}
        cols["z"] = np.array(task.planes)
        mrs = [abs(fix.mR_a), abs(fix.mR_b)]
        cols["mR"] = np.array(mrs)
        cols["angle"] = np.array([float(fix.theta_a), float(fix.theta_b)]) % (2 * math.pi)
    kinds: dict[str, str | None] = {"plane": None, "z": "length", "mR": "unbalance"}
    kinds["angle"] = "angle"
    if task.radii is not None:
        radii = task.radii * (len(mrs) // len(task.radii) or 1)
        cols["mass"] = np.array([mr / r for mr, r in zip(mrs, radii, strict=False)])
        kinds["mass"] = "mass"
    out.tables.append(ResultTable("corrections", f"Corrections for {part.name}", cols, kinds))
    return out


def _bearing_loads(task: RotorBalance, fix: Any) -> list[Summary]:
    """|F_A|, |F_B| at the task's speed, before and after its corrections."""
    from ..rotor import Rotor

    m = np.array([e[0] for e in task.masses])
    z = np.array([e[3] for e in task.masses])
    before = Rotor.from_masses(m, task.unbalance / m, z)
    if task.planes is None:
        after = before + Rotor.from_masses([1.0], [fix.mR], [float(before.cg[2])])
    else:
        after = before + Rotor.from_masses([1.0, 1.0], [fix.mR_a, fix.mR_b], list(task.planes))
    loads = []
    for label, rotor in (("before", before), ("after", after)):
        r = rotor.bearing_reactions(task.speed, *task.bearings)
        loads.append(
            Summary(f"bearing loads A, B {label}", [abs(r.load_a), abs(r.load_b)], "force")
        )
    return loads


PART_KINDS = {
    "flywheel": PartKind(
        "flywheel", FLYWHEEL, _build_flywheel, _flywheel_values, _run_flywheel, _flywheel_refs
    ),
    "rotor": PartKind("rotor", ROTOR, _build_rotor, _rotor_values, _run_rotor),
}
