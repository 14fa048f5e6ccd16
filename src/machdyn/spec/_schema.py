"""The JSON Schema of the machine-file format, built from the reader's own key tables.

The schema is published in the package as ``machdyn.schema.json`` (editors use
it to check and complete files); :func:`schema` builds it from the same
:mod:`machdyn.spec._types` descriptions the reader uses, and a test keeps the
file equal to it. Regenerate the file with ``python -m machdyn.spec._schema``.

A quantity is a bare number (finite, at most 1e15 in size) or a string
``"<number> <unit>"`` whose unit is one of the common units of its kind
(mm, in, kg, lbf, rpm, N*m, ...; pint knows more, and machdyn reads them all).

Examples
--------
>>> s = build()
>>> s["properties"]["machdyn"], "fourbar" in s["properties"]
({'const': 1}, True)
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

from .. import units as u

__all__ = ["build", "write"]

FILE = Path(__file__).with_name("machdyn.schema.json")

# Units of each base kind, as files write them (longest first inside the regex).
_TOKENS = {
    "L": "mm cm dm m km um µm nm in inch inches ft foot feet yd mil millimeter millimeters "
    "millimetre millimetres centimeter centimeters meter meters metre metres",
    "M": "mg g kg t tonne lb lbm lbs oz slug slugs blob blobs slinch gram grams kilogram kilograms",
    "T": "s ms us min h hr second seconds millisecond milliseconds minute minutes hour hours",
    "A": "deg degree degrees rad radian radians mrad rev revolution revolutions turn turns "
    "arcmin arcsec grad",
    "F": "N kN mN MN lbf kip kipf ozf dyn kgf newton newtons",
    "E": "J kJ mJ joule joules",
}

# How a unit of each kind is written, in the tokens above.
_TEMPLATES: dict[str, tuple[str, ...]] = {
    "length": ("L",),
    "mass": ("M", "F*T^2/L"),
    "time": ("T",),
    "angle": ("A",),
    "angular_velocity": ("A/T", "rpm", "rps", "revolutions_per_minute"),
    "angular_acceleration": ("A/T^2", "A/T/T", "rpm/T"),
    "angular_jerk": ("A/T^3",),
    "velocity": ("L/T",),
    "acceleration": ("L/T^2", "L/T/T"),
    "jerk": ("L/T^3",),
    "force": ("F", "M*L/T^2"),
    "torque": ("F*L", "L*F", "E", "M*L^2/T^2"),
    "energy": ("E", "F*L", "L*F", "M*L^2/T^2"),
    "inertia": ("M*L^2", "L^2*M", "F*T^2*L", "F*L*T^2"),
    "stiffness": ("F/L",),
    "damping": ("F*T/L", "F/(L/T)"),
    "torsional_stiffness": ("F*L/A", "F*L", "L*F", "E/A", "F*L/A"),
    "torsional_damping": ("F*L*T/A", "F*L*T", "F*T*L"),
    "density": ("M/L^3",),
    "inverse_length": ("1/L", "/L"),
    "unbalance": ("M*L", "L*M"),
    "moment_of_unbalance": ("M*L^2", "M*L*L"),
}

_NUMBER = r"[+-]?(?:\d[\d_]*(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"


def _alternatives(tokens: str) -> str:
    words = sorted(tokens.split(), key=len, reverse=True)
    return "(?:" + "|".join(re.escape(w) for w in words) + ")"


def unit_pattern(kind: str) -> str:
    """A regular expression (no anchors) for the units of ``kind``."""
    forms = []
    for template in _TEMPLATES[kind]:
        out = ""
        for ch in template:
            if ch in _TOKENS:
                out += _alternatives(_TOKENS[ch])
            elif ch == "*":
                out += r"\s*(?:\*|\s)\s*"
            elif ch == "/":
                out += r"\s*/\s*"
            elif ch == "^":
                out += r"(?:\^|\*\*)"
            elif ch in "()":
                out += "\\" + ch + r"\s*" if ch == "(" else r"\s*\)"
            elif ch.isalnum() or ch == "_":
                out += ch
            else:  # pragma: no cover - templates hold only the characters above
                raise ValueError(template)
        forms.append(out)
    return "(?:" + "|".join(forms) + ")"


def _number() -> dict[str, Any]:
    # NaN passes every comparison keyword, so it is caught by a pair no number meets.
    return {
        "type": "number",
        "minimum": -1e15,
        "maximum": 1e15,
        "not": {"minimum": 1e308, "maximum": -1e308},
    }


def _quantity(kind: str) -> dict[str, Any]:
    k = u.KINDS[kind]
    if kind == "dimensionless":
        return {**_number(), "description": "a plain number"}
    return {
        "description": f"{k.article}: a number in [units], or a string like {k.example!r}",
        "anyOf": [
            _number(),
            {
                "type": "string",
                "pattern": rf"^\s*{_NUMBER}\s*{unit_pattern(kind)}\s*$",
            },
        ],
    }


def _units_table() -> dict[str, Any]:
    from ._machine import UNIT_KEYS

    return {
        "type": "object",
        "description": "units of bare numbers and of the outputs",
        "properties": {
            key: {"type": "string", "pattern": rf"^\s*{unit_pattern(kind)}\s*$"}
            for key, kind in UNIT_KEYS.items()
        },
        "additionalProperties": False,
    }


def build() -> dict[str, Any]:
    """The JSON Schema (draft 2020-12) of machine files, as a dict."""
    from ._machine import KINDS, VERSION, kind

    parts = {
        name: {
            "type": "object",
            "description": f"named {name} parts: [{name}.NAME]",
            "minProperties": 1,
            "propertyNames": {"minLength": 1, "pattern": r"\S"},
            "additionalProperties": kind(name).table.schema(),
        }
        for name in KINDS
    }
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": "urn:machdyn:machine-file:1",
        "title": f"machdyn machine file (format {VERSION})",
        "description": "A machine for machdyn: units, gravity and named parts (docs/spec.md).",
        "type": "object",
        "required": ["machdyn"],
        "properties": {
            "machdyn": {"const": VERSION},
            "title": {"type": "string"},
            "gravity": {"anyOf": [{"type": "boolean"}, {"$ref": "#/$defs/acceleration"}]},
            "units": _units_table(),
            **parts,
        },
        "additionalProperties": False,
        "$defs": {
            **{name: _quantity(name) for name in u.KINDS},
            "number": _number(),
        },
    }


def write(path: Path = FILE) -> None:
    """Write :func:`build` to ``path`` (the packaged file by default)."""
    path.write_text(json.dumps(build(), indent=1, ensure_ascii=False) + "\n", encoding="utf-8")


if __name__ == "__main__":  # pragma: no cover
    write()
    print(f"wrote {FILE}")
