"""Keys ``[<part>.simulate]`` and ``[<part>.tolerance]`` of four-bars and slider-cranks.

They describe what ``machdyn simulate FILE`` and ``machdyn tolerance FILE`` do
with the part (the motor, the flywheel, how long to run; the dimension
tolerances and the number of samples); ``machdyn run`` ignores them. The
physics is :mod:`machdyn.simulate` and :mod:`machdyn.tolerance`.
"""

from __future__ import annotations

from typing import Any

from ._types import Choice, Integer, Quantity, Table, fields, optional, required

__all__: list[str] = []


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
