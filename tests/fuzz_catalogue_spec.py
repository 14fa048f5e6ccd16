"""Fuzz-catalogue entries of machine files and units (machdyn.spec, machdyn.units).

Kept apart from tests/fuzz_catalogue.py (which calls :func:`add_spec`) so the
format's owner edits its own entries.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"
SPEC = {"machdyn": 1, "fourbar": {"a": {"r1": 8.0, "r2": 4.0, "r3": 7.0, "r4": 6.0}}}


def _machine():
    from machdyn.spec import load_machine

    return load_machine(EXAMPLES / "hw6.toml")


def _units():
    from machdyn.units import UnitSystem

    return UnitSystem(length="mm", mass="kg", time="s", force="N")


def _lid():
    from machdyn.spec import load_machine

    return load_machine(EXAMPLES / "lid.toml")["lid"]


def _gear_pair():
    from machdyn.gears import Gear, GearPair

    return GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))


def _planetary():
    from machdyn.gears import PlanetaryTrain

    return PlanetaryTrain.simple(40, 20, 80)


def _program():
    import math

    from machdyn.cams import CamProgram

    return CamProgram.double_dwell(1.0, math.radians(60), math.radians(60))


def _cam():
    from machdyn.cams import TranslatingRoller
    from machdyn.spec import Cam

    return Cam(_program(), TranslatingRoller(3.0, 0.5))


def _flywheel():
    import numpy as np

    from machdyn.spec import FlywheelSizing

    theta = np.linspace(0.0, 2 * np.pi, 37)
    return FlywheelSizing(
        theta, 50 + 10 * np.sin(theta), 0.02, 100.0, density=7850.0, thickness=0.04
    )


def _rotor():
    from machdyn.spec import RotorBalance

    return RotorBalance(((1.0, 0.1, 0.3, 0.2), (2.0, 0.2, -1.0, 0.5)), (0.0, 1.0), (0.1,), 10.0)


C3 = ((0 + 5.086j), (2.019 + 3.181j), (3.933 + 4.051j))
D3 = ((0.741 + 2.703j), (4.428 + 2.529j), (6.304 + 4.83j))


def _motion_task():
    from machdyn.spec import MotionTask

    return MotionTask(C3, D3)


def _function_task():
    import math

    from machdyn.spec import FunctionTask

    return FunctionTask(
        "log10(x)",
        (1.0, 2.0),
        (math.radians(45), math.radians(105)),
        (math.radians(135), math.radians(225)),
    )


def _path_task():
    from machdyn.spec import PathTask

    return PathTask((0j, 1 + 0.5j, 2 + 0j, 1 - 0.5j), maxiter=2, popsize=5, polish=False)


def _model(module: str, name: str, *args: Any):
    def make():
        import importlib

        return getattr(importlib.import_module(module), name)(*args)

    return make


def add_spec(c: dict, fn, meth) -> None:
    """Valid calls of every public callable of machdyn.spec and machdyn.units."""
    from fuzz_catalogue import Call, _mod

    fn("machdyn.spec:from_spec", spec=SPEC)
    fn("machdyn.spec:read", doc=SPEC)
    fn("machdyn.spec:dumps", spec=SPEC)
    fn("machdyn.spec:schema")
    for name in ("load", "load_machine"):
        fn(f"machdyn.spec:{name}", path=str(EXAMPLES / "hw6.toml"))
        c[f"machdyn.spec:{name}"].accepts["path"] = {"text"}
    fn("machdyn.spec:loads", text=(EXAMPLES / "hw6.toml").read_text(), source="hw6.toml")
    meth("machdyn.spec:Machine.to_spec", _machine)
    meth("machdyn.spec:Machine.run", _machine, names=["hw6"])
    c["machdyn.spec:Machine.run"].accepts["names"] = {"none", "empty"}
    for key, factory in (
        ("machdyn.fourbar:FourBar.to_spec", _model("machdyn", "FourBar", 8.0, 4.0, 7.0, 6.0)),
        ("machdyn.slidercrank:SliderCrank.to_spec", _model("machdyn", "SliderCrank", 2.0, 6.0)),
        (
            "machdyn.slidercrank:InvertedSliderCrank.to_spec",
            _model("machdyn", "InvertedSliderCrank", 2.0, 4.0),
        ),
        ("machdyn.linkage:Linkage.to_spec", _lid),
        ("machdyn.gears:GearPair.to_spec", _gear_pair),
        ("machdyn.gears:GearTrain.to_spec", _model("machdyn.gears", "GearTrain", [(18, 54)])),
        ("machdyn.gears:PlanetaryTrain.to_spec", _planetary),
        ("machdyn.cams:CamProgram.to_spec", _program),
        (
            "machdyn.cams:TranslatingRoller.to_spec",
            _model("machdyn.cams", "TranslatingRoller", 3.0, 0.5),
        ),
        (
            "machdyn.cams:TranslatingFlatFace.to_spec",
            _model("machdyn.cams", "TranslatingFlatFace", 3.0),
        ),
        (
            "machdyn.cams:OscillatingRoller.to_spec",
            _model("machdyn.cams", "OscillatingRoller", 2.0, 0.3, 4.0, 3.5),
        ),
        ("machdyn.spec:Cam.to_spec", _cam),
        ("machdyn.spec:FlywheelSizing.to_spec", _flywheel),
        ("machdyn.spec:RotorBalance.to_spec", _rotor),
        ("machdyn.spec:MotionTask.to_spec", _motion_task),
        ("machdyn.spec:FunctionTask.to_spec", _function_task),
        ("machdyn.spec:PathTask.to_spec", _path_task),
    ):
        meth(key, factory, name="part")
        c[key].accepts["name"] = {"text"}
    import math

    import numpy as np

    meth(
        "machdyn.gears:GearTrain.speeds",
        _model("machdyn.gears", "GearTrain", [(18, 54)]),
        omega_in=100.0,
    )
    fn("machdyn.gears:GearTrain", stages=[(18, 54), (20, 60, "internal")])
    meth("machdyn.spec:Cam.profile", _cam, n=90)
    meth("machdyn.spec:Cam.motion", _cam, n=90)
    fn("machdyn.spec:Cam", program=_program(), follower=_cam().follower)
    theta = np.linspace(0.0, 2 * np.pi, 37)
    fn(
        "machdyn.spec:FlywheelSizing",
        theta=theta,
        torque=50 + 10 * np.sin(theta),
        k=0.02,
        omega_avg=100.0,
    )
    c["machdyn.spec:FlywheelSizing"].accepts.update(
        omega_avg={"none"},
        density={"none"},
        thickness={"none"},
        source={"none", "text"},
        csv={"none", "text"},
        units={"none"},
        theta={"none"},
        torque={"none"},
    )
    meth("machdyn.spec:FlywheelSizing.solve", _flywheel)
    meth("machdyn.spec:FlywheelSizing.disc", _flywheel, inertia=2.0)
    fn("machdyn.spec:RotorBalance", masses=((1.0, 0.1, 0.3, 0.2),))
    c["machdyn.spec:RotorBalance"].accepts.update(
        planes={"none"}, radii={"none"}, speed={"none"}, units={"none"}
    )
    meth("machdyn.spec:RotorBalance.solve", _rotor)
    fn("machdyn.spec:MotionTask", c=C3, d=D3)
    meth("machdyn.spec:MotionTask.solve", _motion_task)
    fn(
        "machdyn.spec:FunctionTask",
        function="log10(x)",
        x=(1.0, 2.0),
        theta2=(math.radians(45), math.radians(105)),
        theta4=(math.radians(135), math.radians(225)),
    )
    c["machdyn.spec:FunctionTask"].accepts["function"] = {"text"}
    meth("machdyn.spec:FunctionTask.solve", _function_task)
    fn("machdyn.spec:PathTask", targets=(0j, 1 + 0.5j, 2 + 0j), maxiter=2, popsize=5)
    meth("machdyn.spec:PathTask.solve", _path_task)
    fn("machdyn.spec:read_torque_csv", path=str(EXAMPLES / "torque.csv"))
    fn("machdyn.units:registry")
    fn(
        "machdyn.units:UnitSystem",
        Call(
            _mod("machdyn.units", "UnitSystem"),
            {"length": "mm", "mass": "kg", "time": "s", "angle": "deg", "force": "N"},
            accepts={
                k: {"none"}
                for k in ("length", "mass", "time", "force", "torque", "angular_velocity")
            },
        ),
    )
    for method in ("internal", "display", "factor"):
        meth(f"machdyn.units:UnitSystem.{method}", _units, kind="torque")
    meth("machdyn.units:UnitSystem.label", _units, name="T12", kind="torque")
    meth("machdyn.units:UnitSystem.to_spec", _units)
    call = meth("machdyn.units:UnitSystem.show", _units, kind="force", value=[1.0, 2.0])
    call.skip["value"] = "a unit conversion: NaN (a sample without a value) passes through"
