"""Keys ``[<part>.simulate]`` and ``[<part>.tolerance]`` of four-bars and slider-cranks.

They describe what ``machdyn simulate FILE`` and ``machdyn tolerance FILE`` do
with the part (the motor, the flywheel, how long to run; the dimension
tolerances and the number of samples); ``machdyn run`` ignores them. The
physics is :mod:`machdyn.simulate` and :mod:`machdyn.tolerance`.
"""

from __future__ import annotations

from typing import Any

from ._types import (
    Choice,
    Integer,
    MapOf,
    Names,
    Quantity,
    Table,
    fields,
    optional,
    required,
)

__all__: list[str] = []


def dynamics_options(part: Any, machine: Any) -> dict[str, Any] | None:
    """A fourbar or slider_crank part's masses, loads and gravity, as the force analysis takes them.

    The keyword arguments of ``dynamics`` and :func:`machdyn.simulate`; None without masses.
    """
    from ._fourbar import _external, _in_own_frame, _masses

    v = part.values
    masses = _masses(v, (2, 3, 4))
    if masses is None:
        return None
    out: dict[str, Any] = {"gravity": machine.gravity or 0.0, "form": v.get("form", 1)}
    loads = v.get("loads", {})
    if part.kind == "fourbar":
        out |= {"load_torque4": loads.get("torque4", 0.0), "branch": v.get("branch")}
    else:
        masses["inertia"], masses["cg"] = masses["inertia"][:2], masses["cg"][:2]
        out |= {
            "load_force4": loads.get("force4", 0.0),
            "friction": loads.get("friction", "smooth"),
            "mu": loads.get("mu", 0.0),
            "beta": loads.get("beta", 0.0),
        }
    external = _external(loads, (2, 3, 4))
    if part.kind == "fourbar":
        external, out["gravity"] = _in_own_frame(v, masses, external, out["gravity"])
    return out | masses | external


def simulated_k(machine: Any, source: str, result: Any) -> float | str:
    """The flywheel's fluctuation with the linkage's own varying inertia, or why not.

    ``result`` is the sizing (:class:`~machdyn.flywheel.FlywheelResult`) of the
    torque of part ``source``; its :meth:`~machdyn.flywheel.FlywheelResult.simulate`
    solves that part's equation of motion with the flywheel, at the same
    average speed under a constant torque.
    """
    from ..errors import MachdynError

    part = machine.parts[source]
    if part.kind not in ("fourbar", "slider_crank"):
        return f"not simulated: {source!r} is a {part.kind}"
    options = dynamics_options(part, machine)
    if options is None:
        return f"not simulated: {source!r} has no masses"
    try:
        return float(result.simulate(part.model, **options).k)
    except MachdynError as exc:
        return f"not simulated: {exc}"


def _motor_check(ctx: Any, path: tuple, v: dict) -> None:
    needs = {
        "dc": ("stall_torque", "no_load_speed"),
        "induction": ("rated_torque", "rated_speed", "synchronous_speed"),
        "constant": ("torque",),
    }[v["kind"]]
    for key in needs:
        if key not in v:
            raise ctx.error((*path, key), f"missing: a {v['kind']} motor needs {', '.join(needs)}")


MOTOR = Table(
    fields(
        kind=required(Choice("dc", "induction", "constant")),
        torque=optional(Quantity("torque"), "constant: the torque on the input"),
        stall_torque=optional(Quantity("torque", positive=True), "dc: torque at standstill"),
        no_load_speed=optional(
            Quantity("angular_velocity", positive=True), "dc: speed at zero torque"
        ),
        rated_torque=optional(Quantity("torque", positive=True), "induction: nameplate torque"),
        rated_speed=optional(Quantity("angular_velocity", positive=True), "induction: nameplate"),
        synchronous_speed=optional(Quantity("angular_velocity", positive=True), "induction"),
        breakdown_factor=optional(
            Quantity("dimensionless", positive=True), "induction: breakdown / rated torque (2.5)"
        ),
        ratio=optional(Quantity("dimensionless", positive=True), "motor turns per input turn"),
        inertia=optional(Quantity("inertia", minimum=0.0), "the motor's rotor"),
        off_at=optional(Quantity("time", minimum=0.0), "switched off at this time (coast-down)"),
    ),
    doc="the motor on the input: dc (straight line), induction (Kloss) or constant",
    check=_motor_check,
)

SIMULATE = Table(
    fields(
        motor=optional(MOTOR, "absent: no motor (a coast-down from omega0, a free swing)"),
        flywheel=optional(Quantity("inertia", minimum=0.0), "flywheel and drive line on the input"),
        t_end=optional(Quantity("time", positive=True), "run this long"),
        turns=optional(Quantity("dimensionless", positive=True), "or this many input turns"),
        until=optional(Choice("steady"), "or until the periodic steady state"),
        theta0=optional(Quantity("angle"), "start angle (default: the drawn/first pose)"),
        omega0=optional(Quantity("angular_velocity"), "start speed (default 0: from rest)"),
        samples=optional(Integer(2, 1_000_000), "time samples in the output (2001)"),
        max_evaluations=optional(
            Integer(100, 10**10),
            "budget of the run: evaluations of the equation of motion (2,000,000 tabulated; "
            "50,000 for several drivers, solved at every evaluation); a run that needs more "
            "is refused",
        ),
    ),
    doc="forward dynamics for `machdyn simulate`: the motor, flywheel and when to stop",
)


def _tolerance_table(dimensions: dict[str, str]) -> Table:
    return Table(
        fields(
            **{
                name: optional(Quantity(kind, minimum=0.0), f"± tolerance of {name}")
                for name, kind in dimensions.items()
            },
            distribution=optional(Choice("normal", "uniform"), "normal (default) or uniform"),
            sigmas=optional(
                Quantity("dimensionless", positive=True), "a normal tolerance is this many σ (3)"
            ),
            samples=optional(Integer(1, 10**9), "Monte Carlo samples (100000)"),
            seed=optional(Integer(0, 2**63), "random seed (0)"),
        ),
        doc="dimension tolerances for `machdyn tolerance`",
    )


FOURBAR_TOLERANCE = _tolerance_table(
    {"r1": "length", "r2": "length", "r3": "length", "r4": "length", "p": "length",
     "delta": "angle"}
)  # fmt: skip
SLIDER_TOLERANCE = _tolerance_table(
    {"crank": "length", "coupler": "length", "offset": "length", "p": "length", "delta": "angle"}
)


class _Dimensions(MapOf):
    """``"name" = ± tolerance`` of a linkage: ``"….delta"`` an angle, the others lengths."""

    def __init__(self) -> None:
        super().__init__(Quantity("length", minimum=0.0), "a table of dimension = ± tolerance", 1)
        self.angle = Quantity("angle", minimum=0.0)

    def read(self, ctx: Any, path: tuple, value: Any) -> dict[str, Any]:
        if not isinstance(value, dict) or len(value) < 1:
            raise ctx.error(path, f"expected {self.what} (at least one)")
        return {
            name: (self.angle if str(name).endswith(".delta") else self.item).read(
                ctx, (*path, name), item
            )
            for name, item in value.items()
        }

    def write(self, w: Any, value: Any) -> Any:
        return {
            name: (self.angle if str(name).endswith(".delta") else self.item).write(w, v)
            for name, v in value.items()
        }

    def schema(self) -> dict:
        out = super().schema()
        out["additionalProperties"] = {"anyOf": [self.item.schema(), self.angle.schema()]}
        return out


LINKAGE_TOLERANCE = Table(
    fields(
        dimensions=required(
            _Dimensions(),
            '"P.x"/"P.y" (a drawn point), "F-S" (a link\'s length), "Q.p"/"Q.delta" '
            "(a further point's polar parameters): ± tolerance",
        ),
        outputs=optional(Names(minimum=1), "theta.<link>, point.<P>, torque.<driver>"),
        distribution=optional(Choice("normal", "uniform"), "normal (default) or uniform"),
        sigmas=optional(
            Quantity("dimensionless", positive=True), "a normal tolerance is this many σ (3)"
        ),
        samples=optional(Integer(1, 10**9), "Monte Carlo samples (100000)"),
        seed=optional(Integer(0, 2**63), "random seed (0)"),
    ),
    doc="dimension tolerances of a drawn linkage for `machdyn tolerance`",
)
