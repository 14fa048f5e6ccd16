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
    ):
        meth(key, factory, name="part")
        c[key].accepts["name"] = {"text"}
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
