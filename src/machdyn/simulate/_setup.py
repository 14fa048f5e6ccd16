"""The arguments :func:`machdyn.simulate` and :func:`steady_state` share, checked once."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from .._validate import boolean, choice, finite_scalar, in_range, integer, nonnegative, positive
from ..errors import InputError
from ._integrate import MAX_EVALUATIONS, SOLVED_EVALUATIONS
from ._plant import make_plant
from .loads import Load
from .motors import Motor, as_motor

__all__: list[str] = []

METHODS = ("RK45", "DOP853", "Radau", "BDF", "LSODA", "RK23")
STOPS = ("stall", "reversal")


@dataclass(frozen=True)
class Setup:
    """A model adapter with its motor, loads, start and added inertia."""

    plant: Any
    motor: Motor | None
    loads: tuple[Load, ...]
    q0: float
    added: float


def prepare(
    model: Any,
    motor: Any,
    loads: Any,
    dynamics: dict[str, Any],
    *,
    form: Any,
    branch: Any,
    driver: Any,
    theta0: Any,
    flywheel: Any,
) -> Setup:
    """Check the model, motor, loads and start; build the model's adapter."""
    from ..fourbar import FourBar
    from ..linkage import Linkage

    motor = as_motor(motor)
    loads = _loads(loads)
    if branch is not None and not isinstance(model, FourBar):
        raise InputError("branch", "is an option of a FourBar (GRCR, GRRC) only; omit it")
    if driver is not None and not isinstance(model, Linkage):
        raise InputError("driver", "names a Linkage's driver; omit it for this model")
    if driver is not None and not isinstance(driver, str):
        raise InputError("driver", f"must be a driver's name, got {driver!r:.60}")
    plant = make_plant(model, dynamics, form=form, branch=branch, driver=driver)
    for load in loads:
        plant.check(load)
    unit = "radian" if plant.angular else None
    q0 = plant.default_q0() if theta0 is None else finite_scalar("theta0", theta0, unit)
    if theta0 is not None and plant.angular:
        from ..units import warn_if_degrees

        warn_if_degrees("theta0", q0, stacklevel=4)  # theta0=90 meant in degrees
    added = nonnegative("flywheel", flywheel) + (motor.reflected_inertia if motor else 0.0)
    return Setup(plant, motor, loads, q0, added)


def listed(field: str, values: Any, what: str) -> list[Any]:
    """``values`` as a list, or :class:`InputError` if it is not a sequence (or is text)."""
    if isinstance(values, str | bytes | dict):
        raise InputError(field, f"must be a list of {what}, got {values!r:.60}")
    try:
        return list(values)
    except TypeError:
        raise InputError(field, f"must be a list of {what}, got {values!r:.60}") from None


def _loads(loads: Any) -> tuple[Load, ...]:
    if isinstance(loads, Load):
        return (loads,)
    out = tuple(listed("loads", loads, "loads (torque(), force())"))
    for n, load in enumerate(out):
        if not isinstance(load, Load):
            raise InputError(
                f"loads[{n}]", f"build loads with torque() or force(); got {load!r:.60}"
            )
    return out


def stops(stop_on: Any) -> frozenset[str]:
    """The events that end a run, checked."""
    if isinstance(stop_on, str):
        stop_on = (stop_on,)
    return frozenset(choice("stop_on", s, STOPS) for s in listed("stop_on", stop_on, "events"))


def solver_options(
    *,
    samples: Any,
    rtol: Any,
    atol: Any,
    method: Any,
    max_step: Any,
    table: Any,
    table_tol: Any,
    max_evaluations: Any = None,
) -> dict[str, Any]:
    """The integration's options, checked (``max_evaluations`` None: the default of the path)."""
    if max_evaluations is None:
        max_evaluations = MAX_EVALUATIONS if boolean("table", table) else SOLVED_EVALUATIONS
    return {
        "max_evaluations": integer("max_evaluations", max_evaluations, minimum=100, maximum=10**10),
        "samples": integer("samples", samples, minimum=2, maximum=10**7),
        "rtol": in_range("rtol", rtol, 1e-13, 0.1),  # solve_ivp takes 100 eps at least
        "atol": in_range("atol", atol, 1e-200, 1e10),
        "method": choice("method", method, METHODS),
        "max_step": math.inf if max_step is None else positive("max_step", max_step, "second"),
        "table": boolean("table", table),
        "table_tol": in_range("table_tol", table_tol, 1e-14, 1e-2),
    }


def time_limit(t_end: Any, turns: Any, until: Any) -> tuple[float, float | None]:
    """The simulated time (bounded by the turns or the steady state when not given) and turns."""
    if until is not None:
        choice("until", until, ("steady",))
    if t_end is None and turns is None and until is None:
        raise InputError("t_end", "say how long to simulate: t_end=, turns= or until='steady'")
    turns = None if turns is None else in_range("turns", turns, 1e-9, 1e9)
    if t_end is None:
        return 1e9, turns
    return positive("t_end", t_end, "second"), turns
