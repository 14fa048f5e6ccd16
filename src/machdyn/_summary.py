"""Short summaries of results: ``repr`` and notebook tables instead of pages of arrays.

A result (a solved motion, forces, a cam profile, a flywheel) may hold arrays of
a million samples; printing it should say what it is: how many samples, how
many were solved (and why not), and the range of each quantity with its unit.
:class:`Summarized` gives a dataclass that summary as ``repr`` and as an HTML
table (``_repr_html_``, shown by Jupyter); :func:`linkage_repr` describes a
:class:`~machdyn.linkage.Linkage`.

Units: a result that carries ``units`` (a :class:`~machdyn.units.UnitSystem`)
names the unit of each quantity (its internal unit; angles in radians); the
kind of a quantity is read from its textbook name (``theta``, ``omega``,
``alpha``, ``T12``, ``F32``, ``A``, ``coupler``, ...).
"""

from __future__ import annotations

import dataclasses
import html
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["Summarized", "kind_of", "linkage_repr", "summary_rows"]

#: Name prefixes and the kind of quantity they hold (longest match first).
_PREFIXES = (
    ("shaking_moment", "torque"),
    ("shaking_force", "force"),
    ("shaking_torque", "torque"),
    ("coupler_velocity", "velocity"),
    ("coupler_acceleration", "acceleration"),
    ("coupler_jerk", "jerk"),
    ("point_velocity", "velocity"),
    ("point_acceleration", "acceleration"),
    ("cg_velocity", "velocity"),
    ("cg_acceleration", "acceleration"),
    ("length_rate", "velocity"),
    ("length_acceleration", "acceleration"),
    ("torque_avg", "torque"),
    ("omega", "angular_velocity"),
    ("alpha", "angular_acceleration"),
    ("jerk", "angular_jerk"),
    ("theta", "angle"),
    ("phi", "angle"),
    ("mu", "angle"),
    ("pressure_angle", "angle"),
    ("d_dddot", "jerk"),
    ("d_ddot", "acceleration"),
    ("d_dot", "velocity"),
    ("b_dddot", "jerk"),
    ("b_ddot", "acceleration"),
    ("b_dot", "velocity"),
    ("delta_e", "energy"),
    ("energy", "energy"),
    ("area", "energy"),
    ("inertia", "inertia"),
    ("torque", "torque"),
    ("driver", None),
    ("coupler", "length"),
    ("points", "length"),
    ("lengths", "length"),
    ("pitch", "length"),
    ("surface", "length"),
    ("rho", "length"),
    ("cg", "length"),
)
_EXACT = {
    "T12": "torque",
    "A": "length",
    "B": "length",
    "d": "length",
    "b": "length",
    "s": None,
    "pins": "force",
    "sliders": "force",
    "normal": "force",
    "couple": "torque",
    "rolling": "force",
    "contact": "force",
    "aG2": "acceleration",
    "aG3": "acceleration",
    "aG4": "acceleration",
}


def kind_of(name: str) -> str | None:
    """The kind of quantity a result field holds, from its name (None: unknown).

    Examples
    --------
    >>> kind_of("omega3"), kind_of("F32"), kind_of("coupler_velocity"), kind_of("status")
    ('angular_velocity', 'force', 'velocity', None)
    """
    if name in _EXACT:
        return _EXACT[name]
    if len(name) >= 2 and name[0] == "F" and name[1:].isdigit():
        return "force"
    for prefix, kind in _PREFIXES:
        if name.startswith(prefix):
            return kind
    return None


def _unit(units: Any, kind: str | None) -> str:
    if kind is None:
        return ""
    if kind == "angle":
        return "rad"
    if units is None:
        return {"angular_velocity": "rad/T", "angular_acceleration": "rad/T^2"}.get(kind, "")
    return units.internal(kind)


def _range(values: np.ndarray) -> str | None:
    """``'min … max'`` of the finite values (magnitudes of complex ones)."""
    if values.dtype.kind == "c":
        values = np.abs(values)
    elif values.dtype.kind not in "fiu":
        return None
    finite = values[np.isfinite(values)] if values.dtype.kind == "f" else values
    if finite.size == 0:
        return "no finite values"
    lo, hi = float(finite.min()), float(finite.max())
    same = hi - lo <= 1e-12 * max(abs(lo), abs(hi))
    return f"{lo:.6g}" if same else f"{lo:.6g} … {hi:.6g}"


def _units_of(obj: Any) -> Any:
    """The unit system of a result, or of the motion it was computed from."""
    units = getattr(obj, "units", None)
    return units if units is not None else getattr(getattr(obj, "motion", None), "units", None)


def summary_rows(obj: Any, limit: int = 40) -> list[tuple[str, str, str]]:
    """``(quantity, range, unit)`` for each array (or mapping of arrays) of a dataclass."""
    units = _units_of(obj)
    rows: list[tuple[str, str, str]] = []
    for f in dataclasses.fields(obj):
        if f.name in ("status", "units", "motion", "lobes", "linkage") or not f.repr:
            continue
        value = getattr(obj, f.name)
        items = (
            [(f"{f.name}[{k}]", v) for k, v in value.items()]
            if isinstance(value, Mapping)
            else [(f.name, value)]
        )
        for label, v in items:
            if isinstance(v, np.ndarray) and v.size > 1:
                shown = _range(v)
            elif isinstance(v, float | int | complex | np.floating) and not isinstance(v, bool):
                shown = f"{v:.6g}"
            else:
                continue
            if shown is None:
                continue
            name = label.split("[")[0]
            rows.append((label, shown, _unit(units, kind_of(name))))
            if len(rows) >= limit:
                return rows
    return rows


def _headline(obj: Any) -> str:
    name = type(obj).__name__
    parts = []
    ok = getattr(obj, "ok", None)
    if isinstance(ok, np.ndarray):
        n = int(ok.size)
        good = int(np.count_nonzero(ok))
        parts.append(f"{n:,} sample{'s' if n != 1 else ''}, {good:,} ok")
        if good < n:
            reasons = getattr(obj, "reason", None)
            if isinstance(reasons, np.ndarray):
                found, counts = np.unique(reasons[~ok].astype(str), return_counts=True)
                order = np.argsort(-counts)[:3]
                parts.append("; ".join(f"{counts[i]} {found[i]}" for i in order))
    form = getattr(obj, "form", None)
    if isinstance(form, int):
        parts.append(f"form {form}")
    units = _units_of(obj)
    if units is not None and getattr(units, "length", None):
        parts.append(f"units {units.length}, {units.mass}, {units.time}")
    return f"{name}({', '.join(parts)})" if parts else name


def summary_text(obj: Any) -> str:
    """The ``repr`` of a :class:`Summarized` result."""
    rows = summary_rows(obj)
    if not rows:
        return _headline(obj)
    width = max(len(r[0]) for r in rows)
    lines = [_headline(obj)]
    lines += [f"  {q.ljust(width)}  {rng}{' ' + u if u else ''}" for q, rng, u in rows]
    return "\n".join(lines)


def summary_html(obj: Any) -> str:
    """The notebook table of a :class:`Summarized` result."""
    esc = html.escape
    body = "".join(
        f"<tr><td>{esc(q)}</td><td style='text-align:right'>{esc(r)}</td><td>{esc(u)}</td></tr>"
        for q, r, u in summary_rows(obj)
    )
    head = "<tr><th>quantity</th><th>range</th><th>unit</th></tr>"
    return f"<p><b>{esc(_headline(obj))}</b></p><table>{head}{body}</table>"


class Summarized:
    """Mixin for result dataclasses: a short ``repr`` and a notebook table.

    Examples
    --------
    >>> from machdyn import FourBar
    >>> m = FourBar(8, 4, 7, 6).solve(np.radians(np.arange(0, 360)), omega2=10.0)
    >>> print(repr(m).splitlines()[0])
    FourBarMotion(360 samples, 360 ok, form 1)
    >>> len(repr(m)) < 2000 and "<table>" in m._repr_html_()
    True
    """

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        # Put the summary in the class itself, so @dataclass does not write its
        # field-by-field repr over it (it leaves a __repr__ defined in the class).
        if "__repr__" not in cls.__dict__:
            cls.__repr__ = summary_text  # type: ignore[method-assign]
        if "_repr_html_" not in cls.__dict__:
            cls._repr_html_ = summary_html  # type: ignore[attr-defined]


def linkage_repr(lk: Any) -> str:
    """``Linkage(links ..., joints ..., drivers ..., mobility M)`` in a few lines.

    Examples
    --------
    >>> from machdyn.linkage import Linkage
    >>> lk = (Linkage({"O2": 0, "A": 2, "B": 8}).ground("O2").link("crank", "O2", "A")
    ...       .link("rod", "A", "B").link("block", "B")
    ...       .slider("block", "ground", "B", 0.0, name="guide").drive("crank"))
    >>> print(repr(lk))
    Linkage(3 links, 4 joints, 1 driver; mobility 1)
      links    crank (O2, A), rod (A, B), block (B)
      joints   pin O2, pin A, pin B, slider guide
      drivers  crank
    """
    try:
        mobility: Any = lk.mobility()
    except Exception:  # an unfinished linkage still prints
        mobility = "?"
    links = [f"{ln.name} ({', '.join(ln.points)})" for ln in lk.links.values()]
    joints = [j.name if j.kind == "pin" else f"{j.kind} {j.name}" for j in lk.joints]
    drivers = list(lk.drivers)
    head = (
        f"Linkage({len(links)} link{'s' * (len(links) != 1)}, {len(joints)} joint"
        f"{'s' * (len(joints) != 1)}, {len(drivers)} driver{'s' * (len(drivers) != 1)}; "
        f"mobility {mobility})"
    )
    lines = [head]
    for label, items in (("links", links), ("joints", joints), ("drivers", drivers)):
        if items:
            shown = ", ".join(items[:20]) + (
                f", … ({len(items)} in all)" if len(items) > 20 else ""
            )
            lines.append(f"  {label:<7}  {shown}")
    elements = [e.name for e in lk.elements]
    if elements:
        lines.append(f"  {'springs':<7}  {', '.join(elements)}")
    return "\n".join(lines)


def linkage_html(lk: Any) -> str:
    """The notebook table of a linkage."""
    esc = html.escape
    lines = linkage_repr(lk).splitlines()
    rows = "".join(
        f"<tr><td>{esc(line.split(None, 1)[0])}</td><td>{esc(line.split(None, 1)[1])}</td></tr>"
        for line in lines[1:]
    )
    return f"<p><b>{esc(lines[0])}</b></p><table>{rows}</table>"
