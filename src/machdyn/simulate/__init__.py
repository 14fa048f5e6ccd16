"""Forward dynamics: the motion a motor and loads give a mechanism, in time.

:func:`simulate` integrates the equation of motion of a one-degree-of-freedom
:class:`~machdyn.fourbar.FourBar`, :class:`~machdyn.slidercrank.SliderCrank`
or :class:`~machdyn.linkage.Linkage` (driven at a ground pivot, at a slider or
actuator, or by a motor between two moving links)::

    (I(q) + I_add) q̈ + ½ I'(q) q̇² = T_motor(t, q, q̇) + Q(q) − C(q) q̇ + Σ Q_load

``I(q)`` is the generalised inertia (Σ m |∂r_G/∂q|² + I_G (∂θ/∂q)²), ``Q`` the
generalised force of gravity, springs and the model's constant loads, ``C``
its viscous damping, all taken from the model's own force analysis (see
:mod:`machdyn.simulate._table`); ``I_add`` is the flywheel and drive line.
Motors (:mod:`machdyn.simulate.motors`): constant, DC, induction, any
function of time, angle and speed. Loads (:mod:`machdyn.simulate.loads`):
torques and forces as functions of time and of their own link's or point's
motion, and steps.

Examples
--------
The notes' HW 6 crank-rocker started from rest by a small DC motor through a
10:1 gearbox, with a flywheel, run until its speed is periodic:

>>> import machdyn
>>> from machdyn.simulate import DCMotor
>>> fb = machdyn.FourBar(0.08, 0.04, 0.07, 0.06)        # metres
>>> run = machdyn.simulate(
...     fb, DCMotor(stall_torque=0.5, no_load_speed=300.0, ratio=10.0),
...     mass=(0.2, 0.3, 0.25), inertia=(3e-5, 1.2e-4, 7.5e-5), cg=(0.02, 0.035, 0.03),
...     flywheel=0.02, until="steady")
>>> run.status, round(run.steady.omega_avg, 2), round(run.steady.k, 3)
('steady', 30.0, 0.024)
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import finite_scalar, in_range
from ..errors import InputError

if TYPE_CHECKING:
    from .loads import Load
    from .motors import Motor
    from .result import Simulation

__all__ = [
    "ConstantTorque",
    "DCMotor",
    "Energy",
    "Event",
    "InductionMotor",
    "Load",
    "Motor",
    "MultiSimulation",
    "PeriodicMotion",
    "Simulation",
    "SteadyState",
    "Step",
    "TorqueFunction",
    "force",
    "simulate",
    "simulate_drivers",
    "steady_state",
    "step",
    "torque",
]

# The classes load on first use, so that ``import machdyn`` (which imports this
# package for the ``machdyn.simulate`` function) stays fast.
_HOMES = {
    "Load": "loads",
    "Step": "loads",
    "force": "loads",
    "step": "loads",
    "torque": "loads",
    "ConstantTorque": "motors",
    "DCMotor": "motors",
    "InductionMotor": "motors",
    "Motor": "motors",
    "TorqueFunction": "motors",
    "Energy": "result",
    "Event": "result",
    "Simulation": "result",
    "SteadyState": "result",
    "PeriodicMotion": "periodic",
    "steady_state": "periodic",
    "MultiSimulation": "multi",
    "simulate_drivers": "multi",
}


def __getattr__(name: str) -> Any:
    if name in _HOMES:
        return getattr(importlib.import_module(f".{_HOMES[name]}", __name__), name)
    raise AttributeError(f"module 'machdyn.simulate' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(__all__) | set(globals()))


def simulate(
    model: Any,
    motor: Any = None,
    *,
    t_end: float | None = None,
    turns: float | None = None,
    until: str | None = None,
    theta0: float | None = None,
    omega0: float = 0.0,
    flywheel: float = 0.0,
    loads: Iterable[Load] = (),
    form: int = 1,
    branch: int | None = None,
    driver: str | None = None,
    stop_on: Iterable[str] = ("stall",),
    samples: int = 2001,
    rtol: float = 1e-9,
    atol: float = 1e-10,
    method: str = "DOP853",
    max_step: float | None = None,
    max_evaluations: int | None = None,
    table: bool = True,
    table_tol: float = 1e-9,
    steady_tol: float = 1e-7,
    **dynamics: Any,
) -> Simulation:
    """Integrate a one-degree-of-freedom model's motion under a motor and loads.

    Parameters
    ----------
    model : FourBar, SliderCrank or Linkage
        A FourBar or SliderCrank is driven at link 2 (coordinate ``theta2``);
        a Linkage at its one driver (a link's angle, a motor's relative angle,
        a slider's or actuator's travel: then efforts are forces).
    motor : Motor, float or callable, optional
        :class:`DCMotor`, :class:`InductionMotor`, :class:`ConstantTorque`,
        :class:`TorqueFunction`, a constant torque, or ``f(t, theta, omega)``.
        None: no motor (a coast-down, a free swing). A Linkage with several
        drivers (two degrees of freedom or more) takes a mapping
        ``{driver: motor}``, ``t_end``, and ``theta0``/``omega0`` as mappings;
        it is integrated by :func:`simulate_drivers` (a :class:`MultiSimulation`).
    t_end : float, optional
        Simulated time. At least one of ``t_end``, ``turns``, ``until``.
    turns : float, optional
        Stop when the input has turned this many times (2π each) from ``theta0``.
    until : {"steady"}, optional
        Stop at the periodic steady state of a crank: two consecutive turns
        whose durations and start speeds agree within ``steady_tol``.
    theta0, omega0 : float
        Initial coordinate (default 0 for a crank, the middle of a rocker's
        range, the drawn pose of a Linkage) and speed (default at rest).
    flywheel : float
        Inertia added on the input shaft (flywheel, couplings, drive line),
        besides the motor's reflected rotor inertia.
    loads : iterable of Load
        :func:`torque` and :func:`force` loads (constants, laws of time and of
        their link's or point's motion, :func:`step`).
    form, branch : optional
        The assembly of a FourBar or SliderCrank (as in their ``solve``).
    driver : str, optional
        A Linkage's driver (checked; it must have exactly one).
    stop_on : iterable of {"stall", "reversal"}
        Events that end the run. Toggles, rest and integration failures
        always end it.
    samples : int
        Number of uniform time samples in the result.
    rtol, atol, method, max_step
        Passed to :func:`scipy.integrate.solve_ivp` (``atol`` is for θ and ω;
        the work integrals get it scaled to the energies; ``max_step`` None: no
        limit).
    max_evaluations : int, optional
        Budget of the run: evaluations of the equation of motion. A run that
        needs more is refused, naming ``t_end`` (or ``turns``, ``until``) and the
        time it had reached, instead of running for as long as a huge ``t_end``
        asks. Default: 2,000,000 when tabulated (about a minute, thousands of
        turns of a four-bar; a steady state usually takes a few thousand);
        50,000 when the model is solved at every evaluation (``table=False``
        or several drivers, 1–5 ms each: a few minutes at most).
    table : bool
        Tabulate the coefficients once (default, fast) or solve the model at
        every step (``False``: slow, for checking).
    table_tol : float
        Largest interpolation error of the table, relative (measured).
    steady_tol : float
        Relative tolerance of ``until="steady"``.
    **dynamics
        The model's force-analysis options: ``mass``, ``inertia``, ``cg``,
        ``gravity``, ``load_torque4``, ``external_forces``, ``external_torques``
        (FourBar, see :func:`machdyn.dynamics.fourbar_dynamics`); ``load_force4``,
        ``friction="viscous"``, ``beta`` (SliderCrank); ``gravity``,
        ``external_forces``, ``external_torques``, ``viscous`` (Linkage, see
        :meth:`machdyn.linkage.Linkage.forces`). Constant values only; loads
        that vary go in ``loads``.

    Returns
    -------
    Simulation
        ``t, theta, omega, alpha``, the motor's torque, energies, events,
        ``steady`` (the last cycle's speed fluctuation) and ``forces()``.

    Raises
    ------
    InputError
        A bad option, time span, tolerance, load or motor.
    ModelError
        A model that is not one degree of freedom, or whose driver effort is
        not quadratic in its speed (Coulomb friction is not simulated).

    Examples
    --------
    A slider-crank coasting down from 100 rad/s against viscous piston
    friction: the damper takes its kinetic energy, and the energies balance:

    >>> import machdyn
    >>> sc = machdyn.SliderCrank(0.05, 0.2)
    >>> run = machdyn.simulate(sc, None, omega0=100.0, t_end=2.0, mass=(0.5, 1.0, 1.5),
    ...                        inertia=(2e-4, 4e-3), cg=(0.0, 0.06), friction="viscous",
    ...                        beta=20.0, flywheel=0.01)
    >>> bool(run.omega[-1] < 0.1 * run.omega[0]), bool(run.energy.damping[-1] < 0)
    (True, True)
    >>> bool(abs(run.energy.residual).max() < 1e-8 * run.energy.kinetic[0])
    True
    """
    from ..linkage import Linkage

    if isinstance(model, Linkage) and len(model.drivers) > 1:
        return _several(model, motor, t_end, turns, until, theta0, omega0, flywheel, loads,
                        samples=samples, rtol=rtol, atol=atol, method=method,
                        max_evaluations=max_evaluations, **dynamics)  # fmt: skip
    from ._integrate import OverBudget, Runner
    from ._setup import prepare, solver_options, stops, time_limit
    from ._table import Exact, Table
    from .result import Simulation

    setup = prepare(model, motor, loads, dynamics, form=form, branch=branch, driver=driver,
                    theta0=theta0, flywheel=flywheel)  # fmt: skip
    plant, motor, loads, q0 = setup.plant, setup.motor, setup.loads, setup.q0
    w0 = finite_scalar("omega0", omega0, "radian / second" if plant.angular else None)
    t_end_given = t_end
    t_end, turns = time_limit(t_end, turns, until)
    stop_set = stops(stop_on)
    opts = solver_options(samples=samples, rtol=rtol, atol=atol, method=method,
                          max_step=max_step, table=table, table_tol=table_tol,
                          max_evaluations=max_evaluations)  # fmt: skip
    steady = in_range("steady_tol", steady_tol, 1e-14, 0.1)

    span = plant.span(q0)
    if span.period is None and turns is not None:
        raise InputError("turns", "the input does not turn fully (it is a rocker): give t_end")
    if span.period is None and until is not None:
        raise InputError("until", "a steady state needs an input that turns fully (a crank)")
    if opts["table"]:
        coef = Table(plant, loads, q0, span, opts["table_tol"])
    else:
        coef = Exact(plant, loads, span)
    if coef.period is None and not coef.lo <= q0 <= coef.hi:
        raise InputError(
            "theta0", f"{q0:.6g} is too close to the end of the input's range ({span.hi_reason})"
        )
    runner = Runner(
        plant, coef, span, motor, loads, setup.added,
        rtol=opts["rtol"], atol=opts["atol"], method=opts["method"], max_step=opts["max_step"],
        max_evaluations=opts["max_evaluations"],
    )  # fmt: skip
    runner.check_start(q0, w0)
    q_stop = None
    if turns is not None:
        q_stop = q0 + math.copysign(2.0 * math.pi * turns, w0 if w0 else _push(motor, q0))
    breaks = (motor.breakpoints if motor else ()) + tuple(b for ld in loads for b in ld.breakpoints)
    try:
        status, message = runner.run(
            q0,
            w0,
            t_end,
            q_stop=q_stop,
            steady_tol=steady if until else None,
            stop_on=stop_set,
            breakpoints=breaks,
        )
    except OverBudget as over:
        asked = t_end if t_end_given is not None else None
        raise over.refusal(*_length_asked(asked, turns, until)) from None
    from ..units import with_units

    result = _result(Simulation, runner, plant, coef, status, message, opts["samples"], q0, w0,
                     setup.added)  # fmt: skip
    return with_units(result, getattr(model, "units", None))  # to_pandas(): "t [s]", ...


def _length_asked(t_end: Any, turns: Any, until: Any) -> tuple[str, str]:
    """The option that set how long the run goes on, and what it asked (for a refusal)."""
    if t_end is not None:
        return "t_end", f"{float(t_end):.6g} s"
    if turns is not None:
        return "turns", f"{float(turns):.6g} turns"
    return "until", "the steady state"


def _push(motor: Any, q0: float) -> float:
    """The direction a motor pushes at rest (for ``turns`` from rest)."""
    if motor is None:
        return 1.0
    return 1.0 if float(motor(0.0, q0, 0.0)) >= 0.0 else -1.0


def _result(cls, runner, plant, coef, status, message, samples, q0, w0, added) -> Simulation:
    end = runner.segments[-1][1] if runner.segments else 0.0
    if end > 0.0:
        t = np.linspace(0.0, end, samples)
        y = runner.dense(t)
    else:  # it never moved
        t = np.zeros(1)
        y = np.array([[q0], [w0], [0.0], [0.0], [0.0], [0.0]])
    q, w = y[0], y[1]
    terms = runner.terms_many(t, q, w)
    return cls(
        t=t,
        theta=q,
        omega=w,
        alpha=terms["alpha"],
        motor_torque=terms["torque"],
        inertia=terms["inertia"] - added,
        added_inertia=added,
        energy=runner.energy(terms["inertia"], w, y),
        events=tuple(runner.events),
        status=status,
        message=message,
        cycles=np.array(runner.cycle_times),
        steady=runner.steady_state(),
        coordinate=plant.label,
        angular=plant.angular,
        table=coef.describe(),
        _runner=runner,
    )


def _several(lk, motor, t_end, turns, until, theta0, omega0, flywheel, loads, **options):
    """A several-driver Linkage: :func:`~machdyn.simulate.multi.simulate_drivers`."""
    from .multi import simulate_drivers

    given = {"turns": turns, "until": until, "flywheel": flywheel or None, "loads": loads or None}
    for name, value in given.items():
        if value is not None:
            raise InputError(
                name, "is an option of one-driver models; a several-driver linkage takes t_end"
            )
    if t_end is None:
        raise InputError("t_end", "a several-driver linkage runs for a given time: give t_end")
    qdot0 = None if isinstance(omega0, int | float) and omega0 == 0.0 else omega0
    return simulate_drivers(lk, motor, t_end=t_end, q0=theta0, qdot0=qdot0, **options)
