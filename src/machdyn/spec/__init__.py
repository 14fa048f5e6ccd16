"""Machine files: one description of a machine, with real units (see ``docs/spec.md``).

A machine file (TOML, or the same structure as JSON) starts with ``machdyn =
1``, may set ``[units]`` and ``gravity``, and holds named parts
``[<kind>.<name>]``: four-bars, slider-cranks, drawn linkages, cams, gears,
flywheels, rotors and synthesis tasks, which may refer to each other by name.

* :func:`load` reads a file: the model when it holds one part, else a
  :class:`Machine`; :func:`load_machine` always gives the :class:`Machine`,
  and :func:`loads` the same from text.
* :func:`from_spec` builds the same from a plain dict; every model's
  ``to_spec()`` gives such a dict back.
* :func:`dumps` writes a spec dict as TOML; :func:`schema` is the format's
  JSON Schema.

Examples
--------
>>> import machdyn
>>> fb = machdyn.from_spec({"machdyn": 1, "units": {"length": "mm"},
...                         "fourbar": {"hw6": {"r1": 8, "r2": 4, "r3": 7, "r4": 6}}})
>>> fb.barker_class, fb.units.length
('GCRR', 'mm')
>>> machdyn.from_spec(fb.to_spec()).lengths == fb.lengths
True
"""

from __future__ import annotations

from typing import Any

from ._context import SpecError
from ._machine import VERSION, Machine, Part, from_spec, load, load_machine, loads, read
from ._toml import dumps

__all__ = [
    "VERSION",
    "Cam",
    "FlywheelSizing",
    "FunctionTask",
    "Machine",
    "MotionTask",
    "Part",
    "PathTask",
    "RotorBalance",
    "SpecError",
    "dumps",
    "from_spec",
    "load",
    "load_machine",
    "loads",
    "read",
    "read_torque_csv",
    "schema",
]


def __getattr__(name: str) -> Any:
    # the part objects of the task kinds, loaded with their modules
    places = {
        "Cam": "_cam",
        "FlywheelSizing": "_tasks",
        "RotorBalance": "_tasks",
        "read_torque_csv": "_tasks",
        "MotionTask": "_synthesis",
        "FunctionTask": "_synthesis",
        "PathTask": "_synthesis",
    }
    if name in places:
        import importlib

        return getattr(importlib.import_module(f".{places[name]}", __name__), name)
    raise AttributeError(f"module 'machdyn.spec' has no attribute {name!r}")


def model_spec(model: Any, kind: str, name: str) -> dict[str, Any]:
    """The spec dict of one model object (what its ``to_spec()`` returns).

    ``kind`` is the part kind (``"fourbar"``); the part is called ``name``.
    The model's ``units`` (if any) become ``[units]``.
    """
    from .. import units as u
    from ..errors import InputError
    from . import _machine as mc

    if not isinstance(name, str) or not name.strip():
        raise InputError("name", f"a part's name is text, e.g. 'hw6', got {name!r}")
    k = mc.kind(kind)
    system = getattr(model, "units", None) or u.UnitSystem()
    part = mc.Part(kind, name, k.values_of(model), model)
    return mc.Machine(units=system, parts={part.name: part}).to_spec()


def schema() -> dict[str, Any]:
    """The JSON Schema of the machine-file format (draft 2020-12), as a dict.

    It is the file ``machdyn/spec/machdyn.schema.json`` of the package, which
    editors can use to check machine files.

    Examples
    --------
    >>> schema()["title"]
    'machdyn machine file (format 1)'
    """
    import json
    from pathlib import Path

    path = Path(__file__).with_name("machdyn.schema.json")
    return json.loads(path.read_text(encoding="utf-8"))
