"""Old ``machdyn linkage`` files (before ``machdyn = 1``), read as machine files.

The old format had the linkage's keys at the top level and arrays of tables
(``[[link]]``, ``[[slider]]``, ...) with a ``name`` key; angles in degrees and
rates in rad/s, as now; ``[units]`` were labels, now real units. :func:`upgrade`
rewrites such a document into a one-part machine (part ``linkage``), so the one
reader checks it; errors keep the old file's line numbers (:attr:`Context.alias`).
``machdyn spec upgrade OLD.toml`` prints the new form.
"""

from __future__ import annotations

from typing import Any

from ._context import Context

__all__ = ["NOTE", "is_legacy", "upgrade"]

NOTE = (
    "note: {file} is an old linkage file (no machdyn = 1); it is read as a machine file. "
    "`machdyn spec upgrade {file}` prints it in the new format"
)

#: old array of tables → (new table, how its default name is made)
_ARRAYS = {
    "link": ("links", None),
    "slider": ("sliders", lambda e: f"{e.get('block')}/{e.get('on')}"),
    "slot": ("slots", lambda e: f"{e.get('pin')}@{e.get('on')}"),
    "actuator": ("actuators", None),
    "roll": ("rolls", lambda e: f"{e.get('link_a')}~{e.get('link_b')}"),
    "motor": ("motors", None),
    "spring": ("springs", None),
    "torsion_spring": ("torsion_springs", None),
}
_TOP = ("points", "ground", "drive", "report", "motion")
PART = "linkage"


def is_legacy(doc: Any) -> bool:
    """True for a linkage file of the old format (no ``machdyn`` key, top-level ``points``)."""
    return isinstance(doc, dict) and "machdyn" not in doc and "points" in doc


def upgrade(doc: dict, ctx: Context | None = None) -> dict:
    """The machine-file document of an old linkage file (one part, ``linkage``).

    Examples
    --------
    >>> old = {"ground": ["O2"], "drive": ["crank"], "points": {"O2": [0, 0], "A": [1, 0]},
    ...        "link": [{"name": "crank", "points": ["O2", "A"]}]}
    >>> upgrade(old)["linkage"]["linkage"]["links"]
    {'crank': {'points': ['O2', 'A']}}
    """
    ctx = ctx or Context()
    new: dict[str, Any] = {"machdyn": 1}
    part: dict[str, Any] = {}
    alias: dict[tuple, tuple] = {}
    for key, value in doc.items():
        if key == "title":
            new["title"] = value
        elif key == "units":
            new["units"] = value
        elif key == "gravity":
            if value not in (0, 0.0):
                new["gravity"] = value
        elif key in _TOP:
            part[key] = value
            alias[("linkage", PART, key)] = (key,)
        elif key in _ARRAYS:
            table, default = _ARRAYS[key]
            if not isinstance(value, list):
                raise ctx.error((key,), f"must be an array of tables: write [[{key}]] for each")
            named: dict[str, Any] = {}
            for i, entry in enumerate(value, start=1):
                if not isinstance(entry, dict):
                    raise ctx.error((key, i), "must be a table")
                entry = dict(entry)
                name = entry.pop("name", None)
                if name is None:
                    if default is None:
                        raise ctx.error((key, i, "name"), "missing (required)")
                    name = default(entry)
                if not isinstance(name, str) or not name:
                    raise ctx.error((key, i, "name"), f"must be a non-empty name, got {name!r}")
                if name in named:
                    raise ctx.error((key, i, "name"), f"{name!r} is named twice")
                if key == "roll" and entry.get("radius_b") == float("inf"):
                    entry["radius_b"] = "straight"
                named[name] = entry
                alias[("linkage", PART, table, name)] = (key, i)
            part[table] = named
        else:
            valid = ("title", "units", "gravity", *_TOP, *_ARRAYS)
            raise ctx.error((key,), f"unknown key; valid keys: {', '.join(valid)}")
    new["linkage"] = {PART: part}
    ctx.alias = alias
    return new
