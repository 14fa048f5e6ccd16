"""Valid calls of machdyn.simulate's public API, for the bad-input fuzzer (tests/fuzz_catalogue.py).

Kept short: a slider-crank run of a few milliseconds of simulated time, so every bad value of
every argument can be tried within the suite's budget.
"""

from __future__ import annotations

from functools import cache
from typing import Any

import numpy as np

SC_MASS = dict(mass=(0.5, 1.0, 1.5), inertia=(2e-4, 4e-3), cg=(0.0, 0.06))
FAST = dict(rtol=1e-7, table_tol=1e-6)  # coarse: a fuzzed call is about its arguments


def _sc():
    from machdyn import SliderCrank

    return SliderCrank(0.05, 0.2)


def _motor():
    from machdyn.simulate import DCMotor

    return DCMotor(2.0, 100.0)


def _load():
    from machdyn.simulate import torque

    return torque(2, 1.0)


@cache  # results are immutable: one run serves every case of their methods
def _run():
    import machdyn

    return machdyn.simulate(
        _sc(), _motor(), t_end=0.05, flywheel=0.01, samples=5, table_tol=1e-6, **SC_MASS
    )


@cache
def _periodic():
    from machdyn.simulate import steady_state

    return steady_state(_sc(), omega_avg=20.0, flywheel=0.05, samples=5, **FAST, **SC_MASS)


def _flywheel():
    from machdyn.flywheel import size_flywheel

    theta = np.radians(np.arange(0.0, 360.0, 5.0))
    needed = _sc().dynamics(theta, 20.0, **SC_MASS).T12
    return size_flywheel(theta, needed, 20.0, 0.05)


def add_simulate(c: dict[str, Any], fn, meth) -> None:
    """Entries for machdyn.simulate (motors, loads, runs) and FlywheelResult.simulate."""
    s = "machdyn.simulate"
    fn("machdyn.simulate:simulate", model=_sc(), motor=_motor(), t_end=0.05, flywheel=0.01,
       samples=5, table_tol=1e-6, **SC_MASS)  # fmt: skip
    run = c["machdyn.simulate:simulate"]
    run.accepts.update(
        motor={"none", "zero", "minus_one", "tiny"},  # no motor; constant torques
        t_end={"seconds"},
        max_step={"seconds"},
        turns={"none"},
        until={"none"},
        theta0={"none"},
        branch={"none"},
        driver={"none"},
        stop_on={"empty"},
        loads={"empty"},
    )
    fn(f"{s}:steady_state", model=_sc(), omega_avg=20.0, flywheel=0.05, samples=5, **FAST,
       **SC_MASS)  # fmt: skip
    c[f"{s}:steady_state"].accepts.update(
        motor={"none"}, omega_avg={"none"}, theta0={"none"}, branch={"none"}, driver={"none"},
        loads={"empty"},
    )  # fmt: skip
    fn(f"{s}:ConstantTorque", torque=2.0, inertia=1e-3, ratio=2.0, off_at=1.0)
    fn(f"{s}:DCMotor", stall_torque=2.0, no_load_speed=100.0, inertia=1e-3, ratio=2.0)
    fn(f"{s}:DCMotor.from_electrical", voltage=24.0, resistance=2.0, kt=0.05, ke=0.05)
    fn(
        f"{s}:InductionMotor",
        synchronous_speed=157.08,
        breakdown_torque=60.0,
        breakdown_slip=0.2,
    )
    fn(
        f"{s}:InductionMotor.from_rating",
        rated_torque=20.0,
        rated_speed=150.0,
        synchronous_speed=157.08,
        breakdown_factor=2.5,
    )
    fn(f"{s}:TorqueFunction", func=lambda t, theta, omega: 1.0 + 0.0 * t, breakpoints=[0.5])
    for cls in ("ConstantTorque", "DCMotor", "InductionMotor"):
        c[f"{s}:{cls}"].accepts["off_at"] = {"none"}
    c[f"{s}:DCMotor.from_electrical"].accepts["ke"] = {"none"}
    c[f"{s}:TorqueFunction"].accepts["breakpoints"] = {"empty"}
    for key in ("Motor", "ConstantTorque", "DCMotor", "InductionMotor", "TorqueFunction"):
        call = meth(f"{s}:{key}.shaft_torque", _motor, t=0.1, theta=0.3,
                    omega_motor=np.array([0.0, 50.0]))  # fmt: skip
        call.accepts["t"] = {"seconds"}
    fn(f"{s}:torque", link=2, value=-1.0)
    fn(f"{s}:force", link=4, point=0.0, value=-10.0 + 0j)
    fn(f"{s}:step", at=0.5, before=0.0, after=-10.0)
    for key, name in (("torque", "value"), ("force", "point"), ("force", "value")):
        c[f"{s}:{key}"].accepts.setdefault(name, set()).add("complex")
    c[f"{s}:step"].accepts.update(at={"seconds"}, before={"complex"}, after={"complex"})
    meth(f"{s}:Load.describe", _load)
    meth(f"{s}:Simulation.at", _run, t=np.array([0.0, 0.02]))
    meth(f"{s}:Simulation.forces", _run)
    meth(f"{s}:Simulation.to_pandas", _run)
    meth(f"{s}:PeriodicMotion.at", _periodic, theta=np.array([0.0, 1.0]))
    meth("machdyn.flywheel:FlywheelResult.simulate", _flywheel, model=_sc(), **FAST, **SC_MASS)
    add_sensitivity(c, fn, meth)
    add_tolerance(c, fn)
    add_drivers(c, fn)


@cache
def _sensitivity():
    import machdyn

    return machdyn.sensitivity(_fb(), np.radians([10.0, 50.0, 90.0]))


def _fb():
    from machdyn import FourBar

    return FourBar(8.0, 4.0, 7.0, 6.0, coupler=(3.0, 0.5))


def add_sensitivity(c: dict[str, Any], fn, meth) -> None:
    """Entries for machdyn.sensitivity."""
    k = "machdyn.sensitivity"
    fn(f"{k}:sensitivity", model=_fb(), theta2=np.radians([10.0, 50.0]), omega2=10.0,
       alpha2=1.0, mass=(1.0, 2.0, 1.5), inertia=(0.1, 0.5, 0.3), cg=(2.0, 3.0, 3.0),
       gravity=9.81, load=-1.0)  # fmt: skip
    c[f"{k}:sensitivity"].accepts.update(
        branch={"none"}, dimensions={"none"}, mass={"none"}, inertia={"none"}, cg={"none"}
    )
    c[f"{k}:sensitivity"].accepts["gravity"] = {"complex"}  # a vector in the four-bar's frame
    meth(f"{k}:Sensitivity.of", _sensitivity, output="theta4", dimension="r2")
    meth(f"{k}:Sensitivity.stack_up", _sensitivity, tolerances={"r1": 0.01}, output="coupler")
    meth(f"{k}:Sensitivity.rss", _sensitivity, tolerances={"r1": 0.01}, output="theta4")
    meth(f"{k}:Sensitivity.to_pandas", _sensitivity)
    for name in ("of", "stack_up", "rss"):
        c[f"{k}:Sensitivity.{name}"].accepts.update(output={"text"}, dimension={"text"})
    c["machdyn.flywheel:FlywheelResult.simulate"].accepts["motor"] = {"none"}


def add_tolerance(c: dict[str, Any], fn) -> None:
    """Entries for machdyn.tolerance (a small run: the fuzzer calls it many times)."""
    k = "machdyn.tolerance:tolerance"
    fn(k, model=_fb(), tolerances={"r2": 0.01, "p": (0.01, "uniform")},
       theta2=np.radians([10.0, 50.0]), samples=20, chunk=8, seed=1, sigmas=3.0,
       outputs=["theta4", "coupler", "T12"], omega2=10.0, alpha2=1.0, mass=(1.0, 2.0, 1.5),
       inertia=(0.1, 0.5, 0.3), cg=(2.0, 3.0, 3.0), gravity=9.81, load=-1.0)  # fmt: skip
    c[k].accepts.update(
        theta2={"none"}, branch={"none"}, outputs={"none"}, scheduler={"none"}, workers={"none"},
        seed={"zero"}, alpha2={"zero"}, gravity={"zero", "complex"}, load={"zero"},
        omega2={"zero"},
    )  # fmt: skip


def _pendulums():
    from machdyn.linkage import Linkage

    lk = Linkage({"O1": 0j, "P1": 0.3 + 0j, "O2": 1 + 0j, "P2": 1.0 + 0.25j}).ground("O1", "O2")
    lk.link("a", "O1", "P1", mass=2.0, inertia=0.02, cg=(0.1, 0.0))
    lk.link("b", "O2", "P2", mass=1.0, inertia=0.01, cg=(0.1, 0.0))
    return lk.drive("a", "b")


def add_drivers(c: dict[str, Any], fn) -> None:
    """Entries for machdyn.simulate.simulate_drivers (a short run: a few steps)."""
    k = "machdyn.simulate:simulate_drivers"
    # at rest, no motor torque, no gravity: the integrator's steps grow at once (a 2 s run
    # of the fuzzer's pint "2 second" stays quick)
    fn(k, lk=_pendulums(), motors={"a": 0.0, "b": 0.0}, t_end=1e-3, q0={"a": 0.1},
       qdot0={"b": 0.0}, samples=3, rtol=1e-6, atol=1e-8, gravity=0.0)  # fmt: skip
    c[k].accepts.update(q0={"none", "empty"}, qdot0={"none", "empty"}, gravity={"zero"},
                        motors={"empty"}, t_end={"seconds"})  # fmt: skip
