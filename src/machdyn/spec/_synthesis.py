"""Part kinds ``motion_synthesis``, ``function_synthesis`` and ``path_synthesis``.

Each is a task object holding what :mod:`machdyn.synthesis` takes, with
``solve()`` calling it and ``to_spec()`` writing it back; running prints the
four-bar found (lengths, pivots, its class and defects). No physics here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validate import (
    boolean,
    choice,
    finite_array,
    finite_scalar,
    integer,
    point,
    positive,
    text,
)
from ..errors import InputError
from ._context import Context, check_units
from ._machine import Machine, Part, PartKind
from ._run import PartResult, ResultTable, Summary, flagged_rows
from ._types import (
    Boolean,
    Choice,
    Integer,
    Position,
    Positions,
    Quantities,
    Quantity,
    Table,
    Text,
    fields,
    optional,
    required,
)

__all__ = ["PART_KINDS", "FunctionTask", "MotionTask", "PathTask"]


@dataclass(frozen=True, eq=False)
class MotionTask:
    """Two- or three-position motion generation: the coupler line CD in each position.

    ``a``, ``b``: moving pivots on the coupler in position 1 (three positions;
    default C1, D1); ``o2``, ``o4``: fixed pivots (the inverted problem);
    ``s2``, ``s4``: two positions only, where the fixed pivots sit on the
    bisectors.

    Examples
    --------
    >>> c = [0 + 5.086j, 2.019 + 3.181j, 3.933 + 4.051j]
    >>> d = [0.741 + 2.703j, 4.428 + 2.529j, 6.304 + 4.83j]
    >>> from machdyn.synthesis import three_position
    >>> MotionTask(tuple(c), tuple(d)).solve().r1 == three_position(c, d).r1
    True
    """

    c: tuple[complex, ...]
    d: tuple[complex, ...]
    a: complex | None = None
    b: complex | None = None
    o2: complex | None = None
    o4: complex | None = None
    s2: float | None = None
    s4: float | None = None
    units: Any = field(default=None, compare=False)

    def __post_init__(self) -> None:
        s = object.__setattr__
        c = _points("c", self.c)
        d = _points("d", self.d, len(c))
        if len(c) not in (2, 3):
            raise InputError("c", f"give 2 or 3 positions, got {len(c)}")
        s(self, "c", tuple(complex(z) for z in c))
        s(self, "d", tuple(complex(z) for z in d))
        for key in ("a", "b", "o2", "o4"):
            if getattr(self, key) is not None:
                s(self, key, point(key, getattr(self, key)))
        for key in ("s2", "s4"):
            if getattr(self, key) is not None:
                s(self, key, finite_scalar(key, getattr(self, key)))
        check_units(self.units)

    def solve(self) -> Any:
        """The :class:`~machdyn.synthesis.MotionSynthesis`."""
        from .. import synthesis as sy
        from ..units import with_units

        if len(self.c) == 2:
            result = sy.two_position(self.c, self.d, s2=self.s2, s4=self.s4, A=self.a, B=self.b)
        elif self.o2 is not None:
            result = sy.three_position_fixed_pivots(self.c, self.d, self.o2, self.o4)
        else:
            result = sy.three_position(self.c, self.d, A=self.a, B=self.b)
        return with_units(result, self.units)  # to_pandas(): "A_x [mm]"

    def to_spec(self, name: str = "motion_synthesis") -> dict[str, Any]:
        """The task as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from . import model_spec

        return model_spec(self, "motion_synthesis", name)


@dataclass(frozen=True, eq=False)
class FunctionTask:
    """Freudenstein function generation of ``y = function(x)``.

    Examples
    --------
    >>> task = FunctionTask("log10(x)", (1.0, 2.0), (math.radians(45), math.radians(105)),
    ...                     (math.radians(135), math.radians(225)))
    >>> task.solve().defects
    ()
    """

    function: str
    x: tuple[float, float]
    theta2: tuple[float, float]
    theta4: tuple[float, float]
    points: int = 3
    spacing: str = "chebyshev"
    r1: float = 1.0
    units: Any = field(default=None, compare=False)

    def __post_init__(self) -> None:
        s = object.__setattr__
        s(self, "function", text("function", self.function))
        for key in ("x", "theta2", "theta4"):
            pair = finite_array(key, getattr(self, key))
            if pair.shape != (2,):
                raise InputError(key, f"expected (start, end), got {getattr(self, key)!r}")
            s(self, key, (float(pair[0]), float(pair[1])))
        s(self, "points", integer("points", self.points, minimum=3, maximum=1000))
        s(self, "spacing", choice("spacing", self.spacing, ("chebyshev", "uniform")))
        s(self, "r1", positive("r1", self.r1))
        check_units(self.units)

    def solve(self) -> Any:
        """The :class:`~machdyn.synthesis.FunctionGenerator`."""
        from .._expression import parse_function
        from ..synthesis import function_generator
        from ..units import with_units

        func = parse_function(self.function)
        result = function_generator(
            func, self.x, self.theta2, self.theta4, n=self.points, spacing=self.spacing, r1=self.r1
        )
        return with_units(result, self.units)  # its structural error says its angles' unit

    def to_spec(self, name: str = "function_synthesis") -> dict[str, Any]:
        """The task as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from . import model_spec

        return model_spec(self, "function_synthesis", name)


@dataclass(frozen=True, eq=False)
class PathTask:
    """Path generation: a crank-driven four-bar whose coupler point passes the targets.

    Examples
    --------
    >>> t = PathTask((0j, 1 + 0.5j, 2 + 0j, 1 - 0.5j), maxiter=3, popsize=5, polish=False)
    >>> len(t.targets)
    4
    """

    targets: tuple[complex, ...]
    timing: tuple[float, ...] | None = None
    mu_min: float = math.radians(30.0)
    tolerance: float | None = None
    seed: int = 0
    maxiter: int = 400
    popsize: int = 30
    polish: bool = True
    units: Any = field(default=None, compare=False)

    def __post_init__(self) -> None:
        s = object.__setattr__
        targets = _points("targets", self.targets)
        if len(targets) < 3:
            raise InputError("targets", f"give at least 3 targets, got {len(targets)}")
        s(self, "targets", tuple(complex(z) for z in targets))
        if self.timing is not None:
            timing = finite_array("timing", self.timing)
            if timing.shape != (len(targets),):
                raise InputError("timing", "one input angle per target")
            s(self, "timing", tuple(float(v) for v in timing))
        s(self, "mu_min", positive("mu_min", self.mu_min))
        if self.tolerance is not None:
            s(self, "tolerance", positive("tolerance", self.tolerance))
        s(self, "seed", integer("seed", self.seed, minimum=0, maximum=2**32 - 1))
        s(self, "maxiter", integer("maxiter", self.maxiter, minimum=1, maximum=100_000))
        s(self, "popsize", integer("popsize", self.popsize, minimum=4, maximum=10_000))
        s(self, "polish", boolean("polish", self.polish))
        check_units(self.units)

    def solve(self) -> Any:
        """The :class:`~machdyn.synthesis.PathSynthesis` (a search: seconds, not milliseconds)."""
        from ..synthesis import synthesize_path

        return synthesize_path(
            np.array(self.targets),
            timing=None if self.timing is None else np.array(self.timing),
            mu_min=self.mu_min,
            tolerance=self.tolerance,
            seed=self.seed,
            maxiter=self.maxiter,
            popsize=self.popsize,
            polish=self.polish,
        )

    def to_spec(self, name: str = "path_synthesis") -> dict[str, Any]:
        """The task as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from . import model_spec

        return model_spec(self, "path_synthesis", name)


MOTION = Table(
    fields(
        c=required(Positions(minimum=2), "C in each position (2 or 3)"),
        d=required(Positions(minimum=2), "D in each position"),
        a=optional(Position(), "moving pivot A on the coupler, position 1"),
        b=optional(Position(), "moving pivot B on the coupler, position 1"),
        o2=optional(Position(), "fixed pivot O2 (inverted problem)"),
        o4=optional(Position(), "fixed pivot O4 (inverted problem)"),
        s2=optional(Quantity("length"), "two positions: O2 along the bisector of A1A2"),
        s4=optional(Quantity("length"), "two positions: O4 along the bisector of B1B2"),
        notes=optional(Text()),
    ),
    doc="two- or three-position motion generation",
)
FUNCTION = Table(
    fields(
        function=required(Text(), "y = f(x), e.g. 'log10(x)'"),
        x=required(Quantities("dimensionless", count=2), "[x0, xf]"),
        theta2=required(Quantities("angle", count=2), "input angles [start, end]"),
        theta4=required(Quantities("angle", count=2), "output angles [start, end]"),
        points=optional(Integer(3, 1000), "precision points (3 exact, more least squares)"),
        spacing=optional(Choice("chebyshev", "uniform")),
        r1=optional(Quantity("length", positive=True), "ground length (the scale)"),
        notes=optional(Text()),
    ),
    doc="Freudenstein function generation",
)
PATH = Table(
    fields(
        targets=required(Positions(minimum=3), "points the coupler point passes"),
        timing=optional(Quantities("angle", minimum=2), "input-angle increments (prescribed)"),
        mu_min=optional(Quantity("angle", positive=True), "default 30 deg"),
        tolerance=optional(Quantity("length", positive=True)),
        seed=optional(Integer(0)),
        maxiter=optional(Integer(1, 100_000)),
        popsize=optional(Integer(4, 10_000)),
        polish=optional(Boolean(), "refine the best candidate locally (default true)"),
        notes=optional(Text()),
    ),
    doc="path generation by search",
)


def _points(field: str, value: Any, count: int | None = None) -> Any:
    """Finite points (``as_points``), with a number too large for a float refused too."""
    from ..synthesis.geometry import as_points

    try:
        return as_points(field, value, count)
    except (OverflowError, TypeError, ValueError) as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError(
            field, f"expected points (x, y) or complex numbers, got {value!r}"
        ) from None


def _units(ctx: Context) -> Any:
    return None if ctx.system.is_unit_free else ctx.system


def _build_motion(ctx: Context, path: tuple, v: dict) -> MotionTask:
    c, d = v["c"], v["d"]
    if len(c) not in (2, 3) or len(d) != len(c):
        raise ctx.error(
            (*path, "d"), f"give C and D in 2 or 3 positions each; got {len(c)}, {len(d)}"
        )
    if ("o2" in v) != ("o4" in v):
        raise ctx.error((*path, "o4" if "o2" in v else "o2"), "give both fixed pivots o2, o4")
    if len(c) == 2 and ("s2" not in v or "s4" not in v):
        raise ctx.error((*path, "s2"), "two positions need s2 and s4 (where on the bisectors)")
    opt = {k: v.get(k) for k in ("a", "b", "o2", "o4", "s2", "s4")}
    task = MotionTask(tuple(c), tuple(d), **opt, units=_units(ctx))
    with ctx.at(path, {k: (*path, k) for k in ("c", "d", "A", "B", "O2", "O4", "s2", "s4")}):
        task.solve()
    return task


def _build_function(ctx: Context, path: tuple, v: dict) -> FunctionTask:
    task = FunctionTask(
        v["function"],
        tuple(v["x"]),
        tuple(v["theta2"]),
        tuple(v["theta4"]),
        v.get("points", 3),
        v.get("spacing", "chebyshev"),
        v.get("r1", 1.0),
        units=_units(ctx),
    )
    keys = {"--f": (*path, "function"), "x_range": (*path, "x"), "n": (*path, "points")}
    keys |= {"theta2_range": (*path, "theta2"), "theta4_range": (*path, "theta4")}
    with ctx.at(path, keys):
        task.solve()
    return task


def _build_path(ctx: Context, path: tuple, v: dict) -> PathTask:
    timing = v.get("timing")
    if timing is not None and len(timing) != len(v["targets"]):
        raise ctx.error((*path, "timing"), "give one angle per target")
    return PathTask(
        tuple(v["targets"]),
        None if timing is None else tuple(timing),
        v.get("mu_min", math.radians(30.0)),
        v.get("tolerance"),
        v.get("seed", 0),
        v.get("maxiter", 400),
        v.get("popsize", 30),
        v.get("polish", True),
        units=_units(ctx),
    )


def _motion_values(t: MotionTask) -> dict:
    out: dict[str, Any] = {"c": np.array(t.c), "d": np.array(t.d)}
    for key in ("a", "b", "o2", "o4", "s2", "s4"):
        if getattr(t, key) is not None:
            out[key] = getattr(t, key)
    return out


def _function_values(t: FunctionTask) -> dict:
    out = {"function": t.function, "x": np.array(t.x), "theta2": np.array(t.theta2)}
    out |= {"theta4": np.array(t.theta4), "points": t.points, "spacing": t.spacing}
    return out | ({"r1": t.r1} if t.r1 != 1.0 else {})


def _path_values(t: PathTask) -> dict:
    out: dict[str, Any] = {"targets": np.array(t.targets), "mu_min": t.mu_min}
    if t.timing is not None:
        out["timing"] = np.array(t.timing)
    if t.tolerance is not None:
        out["tolerance"] = t.tolerance
    out |= {"seed": t.seed, "maxiter": t.maxiter, "popsize": t.popsize}
    return out if t.polish else out | {"polish": False}


def _fourbar_summary(out: PartResult, result: Any) -> None:
    fb = result.fourbar
    out.summary += [
        Summary("r1, r2, r3, r4", list(fb.lengths), "length"),
        Summary("class", fb.barker_class),
    ]
    if fb.coupler is not None:
        out.summary.append(Summary("coupler point p", float(fb.coupler[0]), "length"))
        out.summary.append(Summary("coupler point delta", float(fb.coupler[1]), "angle"))
    placed = getattr(result, "linkage", result)  # path synthesis: a PlacedFourBar
    if hasattr(placed, "O2"):
        out.summary.append(Summary("O2", [placed.O2.real, placed.O2.imag], "length"))
        out.summary.append(Summary("O4", [placed.O4.real, placed.O4.imag], "length"))
    if hasattr(placed, "theta1"):
        out.summary.append(Summary("theta1 (ground line)", float(placed.theta1), "angle"))
    out.summary.append(Summary("defects", "; ".join(result.defects) or "none"))


def _run_motion(part: Part, machine: Machine, results: dict) -> PartResult:
    from ..synthesis.placed import form_of

    result = part.model.solve()
    out = PartResult(part, objects={"synthesis": result})
    _fourbar_summary(out, result)
    out.summary.append(Summary("form (FourBar, as in the notes)", form_of(result.branch)))
    cols = {
        "position": np.arange(1, result.A.size + 1),
        "A_x": result.A.real,
        "A_y": result.A.imag,
        "B_x": result.B.real,
        "B_y": result.B.imag,
        "theta2": np.asarray(result.theta2, dtype=float),
    }
    kinds = dict.fromkeys(cols, "length") | {"position": "dimensionless", "theta2": "angle"}
    out.tables.append(ResultTable("positions", f"Positions of {part.name}", cols, kinds))
    return out


#: Samples of a function generator's structural error (``machdyn synth function``'s default).
ERROR_SAMPLES = 11


def _run_function(part: Part, machine: Machine, results: dict) -> PartResult:
    result = part.model.solve()
    se = result.structural_error(n=ERROR_SAMPLES)
    out = PartResult(part, objects={"synthesis": result, "structural_error": se})
    _fourbar_summary(out, result)
    out.summary += [
        Summary("K1, K2, K3", [float(k) for k in result.k]),
        Summary("input, output link offsets", [result.input_offset, result.output_offset], "angle"),
        Summary("precision points x", [float(v) for v in result.x_precision]),
        Summary("max |structural error|", float(se.max_abs)),
    ]
    cols = {
        "x": np.asarray(se.x, dtype=float),
        "f(x)": np.asarray(se.y_desired, dtype=float),
        "generated": np.asarray(se.y_generated, dtype=float),
        "error": np.asarray(se.error, dtype=float),
        "ok": np.asarray(se.ok, dtype=bool),
        "reason": np.asarray(se.reason, dtype=object),
    }
    kinds: dict[str, str | None] = dict.fromkeys(cols, "dimensionless")
    kinds |= {"ok": None, "reason": None}
    title = f"Structural error of {part.name} (y = {part.model.function})"
    out.tables.append(ResultTable("structural_error", title, cols, kinds))
    out.flagged += flagged_rows("x", cols["x"], cols["ok"], cols["reason"])
    return out


def _run_path(part: Part, machine: Machine, results: dict) -> PartResult:
    result = part.model.solve()
    out = PartResult(part, objects={"synthesis": result})
    _fourbar_summary(out, result)
    out.summary.append(Summary("mu_min", result.mu_min, "angle"))
    cols = {
        "target_x": result.targets.real,
        "target_y": result.targets.imag,
        "theta2": result.theta2,
        "distance": result.distance,
    }
    kinds = {"target_x": "length", "target_y": "length", "theta2": "angle", "distance": "length"}
    out.tables.append(ResultTable("targets", f"Targets of {part.name}", cols, kinds))
    return out


PART_KINDS = {
    "motion_synthesis": PartKind(
        "motion_synthesis", MOTION, _build_motion, _motion_values, _run_motion
    ),
    "function_synthesis": PartKind(
        "function_synthesis", FUNCTION, _build_function, _function_values, _run_function
    ),
    "path_synthesis": PartKind("path_synthesis", PATH, _build_path, _path_values, _run_path),
}
