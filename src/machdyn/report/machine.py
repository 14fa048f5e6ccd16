"""The report of a machine file: every part on one page, each with its own sections.

A :class:`machdyn.spec.Machine` is run once (so that ``driven_by`` speeds and
torques flow between parts as in ``machdyn run``); each part that has a report
(four-bar, slider-crank, inverted slider-crank, linkage, cam, gear pair, gear
train, planetary train, rotor) gets
its sections, numbered under the part and with data keys prefixed by the part's
name (``press:peak_F32``); any other part (flywheel,
synthesis task) is reported by the summary its run gives — with the
flywheel's torque curve and energy lobes, and a synthesised linkage drawn in its
precision positions over its targets. A machine of one
reportable part gets that part's page as it is.
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np

from ..errors import MachdynError
from .page import Page, esc, fmt

__all__ = ["machine_report", "part_options"]

#: Part kinds with a report of their own.
REPORTED = (
    "fourbar",
    "slider_crank",
    "inverted_slider_crank",
    "linkage",
    "cam",
    "gear_pair",
    "gear_train",
    "planetary",
    "rotor",
)


def part_options(part: Any, machine: Any, results: dict[str, Any] | None = None) -> dict[str, Any]:
    """The report options a machine file's part implies (speed, masses, loads, gravity, units).

    Examples
    --------
    >>> from machdyn.spec import load_machine
    >>> m = load_machine("docs/examples/hw6.toml")  # doctest: +SKIP
    >>> sorted(part_options(m.parts["hw6"], m))  # doctest: +SKIP
    ['cg', 'gravity', 'inertia', 'mass', 'omega2', 'units']
    """
    from ..spec._fourbar import _external, _in_own_frame, _masses, input_motion, placement

    v, kind = part.values, part.kind
    options: dict[str, Any] = {"units": machine.units}
    gravity = float(machine.gravity or 0.0)
    if kind in ("fourbar", "slider_crank", "inverted_slider_crank"):
        _, omega2, _ = input_motion(part, machine, results or {})
        options["omega2"] = omega2
        options["form"] = v.get("form", 1)
        if v.get("branch") is not None:  # a GRCR/GRRC four-bar's half of its circuit
            options["branch"] = v["branch"]
    if kind == "fourbar":
        if placement(v) is not None:
            options["placement"] = placement(v)
        masses = _masses(v, (2, 3, 4))
        if masses is not None:
            loads = v.get("loads", {})
            external, g = _in_own_frame(v, masses, _external(loads, (2, 3, 4)), gravity)
            options |= masses | external | {"gravity": g}
            options["load_torque4"] = loads.get("torque4", 0.0)
    elif kind == "slider_crank":
        masses = _masses(v, (2, 3, 4))
        if masses is not None:
            loads = v.get("loads", {})
            masses["inertia"], masses["cg"] = masses["inertia"][:2], masses["cg"][:2]
            options |= masses | {"gravity": gravity} | _external(loads, (2, 3))
            options["load_force4"] = loads.get("force4", 0.0)
            for key in ("friction", "mu", "beta"):
                if key in loads:
                    options[key] = loads[key]
    elif kind == "inverted_slider_crank":
        masses = _masses(v, (2, 3, 4))
        if masses is not None:
            loads = v.get("loads", {})
            options |= masses | {"gravity": gravity} | _external(loads, (2, 3, 4))
            options["load_torque4"] = loads.get("torque4", 0.0)
            for key in ("friction", "mu", "beta"):
                if key in loads:
                    options[key] = loads[key]
    elif kind == "linkage":
        from ..spec._linkage import loads as linkage_loads

        options["gravity"] = gravity
        options |= linkage_loads(part)
        lk = part.model
        first = v.get("motion", {}).get(lk.drivers[0]) if lk.drivers else None
        if first is not None:  # a DriverSetting, in the model's units (radians)
            if first.velocity is not None:
                options["velocity"] = first.velocity
            values = first.values.values if first.values is not None else ()
            if len(values) > 1:
                options["values"] = (float(values[0]), float(values[-1]))
    return options


def _page_of(part: Any, machine: Any, results: dict[str, Any], **common: Any) -> Page | None:
    """The report page of one part (None for a kind without a report of its own).

    A mechanism is reported over a cycle at its constant input speed: a file's input
    acceleration (``alpha2``, a driver's ``acceleration``), which ``machdyn run`` uses,
    is named in a section saying so.
    """
    page = _page_of_part(part, machine, results, **common)
    if page is not None:
        note = _unsteady(part, machine)
        if note:
            body = f'<p class="remark">{note}</p>'
            page.sections.insert(1, ("steady", "Steady speed", body, 2))
    return page


def _unsteady(part: Any, machine: Any) -> str:
    """Why the report's numbers differ from ``machdyn run``'s: a file's input acceleration."""
    units = machine.units
    if part.kind in ("fourbar", "slider_crank", "inverted_slider_crank"):
        alpha = float(part.values.get("motion", {}).get("alpha2", 0.0))  # (as input_motion's)
        name = "alpha2"
    elif part.kind == "linkage" and part.model.drivers:
        first = part.values.get("motion", {}).get(part.model.drivers[0])
        alpha = float(first.acceleration or 0.0) if first is not None else 0.0
        name = f"the acceleration of {part.model.drivers[0]}"
        if part.model.drivers[0] not in part.model.links:
            return ""  # a length driver's acceleration: not an angle's
    else:
        return ""
    if not alpha:
        return ""
    shown = (
        f"{units.show('angular_acceleration', alpha):.6g} {units.display('angular_acceleration')}"
    )
    return (
        f"This report analyses a cycle at the constant input speed; the file's {esc(name)} = "
        f"{esc(shown)} (used by machdyn run) is not used here."
    )


def _page_of_part(part: Any, machine: Any, results: dict[str, Any], **common: Any) -> Page | None:
    kind, model = part.kind, part.model
    options = part_options(part, machine, results)
    n, k, speed = common.get("n", 360), common.get("k"), common.get("speed")
    title = f"{part.name} ({kind.replace('_', ' ')})"
    if kind in ("fourbar", "slider_crank", "inverted_slider_crank"):
        from .fourbar import fourbar_report
        from .slidercrank import inverted_report, slidercrank_report

        report = {
            "fourbar": fourbar_report,
            "slider_crank": slidercrank_report,
            "inverted_slider_crank": inverted_report,
        }[kind]
        if speed is not None:
            options["omega2"] = speed
        if kind == "fourbar" and "mass" not in options:
            options.pop("gravity", None)
        return report(model, title=title, n=n, k=k, **options)
    if kind == "linkage":
        from .linkage import linkage_report

        if "values" in options:
            lo, hi = options.pop("values")
            options["values"] = np.linspace(lo, hi, n)
        if speed is not None:
            options["velocity"] = speed
        return linkage_report(model, title=title, n=n, k=k, **options)
    if kind == "cam":
        from .elements import cam_report

        profile = results[part.name].objects.get("profile")
        return None if profile is None else cam_report(profile, title=title, units=machine.units)
    if kind in ("gear_pair", "gear_train", "planetary", "rotor"):
        return _element_page(part, machine, title)
    return None


def _element_page(part: Any, machine: Any, title: str) -> Page:
    """The page of a gear pair, a train or a rotor part (its speeds from the file)."""
    from .gears import gear_report, planetary_report, train_report
    from .rotor import rotor_report

    v, model, units = part.values, part.model, machine.units
    if part.kind == "gear_pair":
        return gear_report(
            model,
            title=title,
            input_speed=v.get("input_speed"),
            torque=v.get("torque"),
            units=units,
        )
    if part.kind == "gear_train":
        return train_report(
            model,
            title=title,
            input_speed=v.get("input_speed"),
            torque=v.get("torque"),
            units=units,
        )
    if part.kind == "planetary":
        return planetary_report(
            model,
            title=title,
            speeds=v.get("speeds") or None,
            torque=v.get("torques") or None,
            units=units,
        )
    return rotor_report(model, title=title, bearings=model.bearings, units=units)


def _summary(page: Page, result: Any, machine: Any) -> str:
    rows = []
    for line in result.summary:
        label, value = line.shown(machine.units)
        if isinstance(value, float | int | np.floating):
            text = fmt(float(value), 6)
        elif isinstance(value, list | tuple | np.ndarray) and np.size(value) <= 8:
            text = ", ".join(fmt(float(x), 6) if _num(x) else esc(x) for x in np.ravel(value))
        else:
            text = esc(value)
        rows.append((label, text, re.sub(r"[^a-z0-9]+", "_", line.label.lower()).strip("_")))
    return page.table(rows) if rows else '<p class="remark">No summary.</p>'


def _extras(part: Any, result: Any, machine: Any) -> str:
    """What a part without a report of its own can still show: its drawing or its curve."""
    from ..draw import scene
    from ..draw.html import widget
    from ..draw.units import Units

    objects = result.objects
    try:
        if part.kind == "flywheel" and "flywheel" in objects:
            from ..draw.engineering import torque_chart

            fly = objects["flywheel"]
            u = Units.of(machine.units)
            return torque_chart(fly.theta, fly.torque, flywheel=fly, units=u).to_svg()
        if part.kind in ("motion_synthesis", "path_synthesis") and "synthesis" in objects:
            return widget(scene(objects["synthesis"]))
        if part.kind == "function_synthesis" and "synthesis" in objects:
            return widget(scene(objects["synthesis"].fourbar))
    except MachdynError as err:  # a result that cannot be drawn says why
        return f'<p class="remark">Not drawn: {esc(str(err))}</p>'
    return ""


def _num(x: Any) -> bool:
    return isinstance(x, int | float | np.number) and math.isfinite(float(x))


def _absorb(page: Page, index: int, name: str, sub: Page) -> None:
    """Add the sections of a part's page under the part, ids and keys prefixed."""
    prefix = esc(name) + ":"
    for key, title, body, _ in sub.sections:
        body = body.replace('data-key="', f'data-key="{prefix}').replace(
            'data-check="', f'data-check="{prefix}'
        )
        page.sections.append((f"part{index}-{key}", title, body, 3))
    page.failed |= sub.failed


def machine_report(
    machine: Any, *, n: int = 360, k: float | None = None, speed: float | None = None
) -> Page:
    """The report page of a machine file (a :class:`machdyn.spec.Machine`).

    ``n`` poses per mechanism, ``k`` sizes a flywheel on every full-turning
    mechanism, ``speed`` (rad per time unit) overrides every mechanism's input
    speed.
    """
    results = machine.run()
    parts = list(machine.parts.values())
    pages = {p.name: _page_of(p, machine, results, n=n, k=k, speed=speed) for p in parts}
    reported = [p for p in parts if pages[p.name] is not None]
    if len(parts) == 1 and reported:
        return pages[parts[0].name]
    title = machine.title or "machine"
    firsts = []
    for p in parts:
        sub = pages[p.name]
        name = f"{p.name} ({p.kind.replace('_', ' ')})"
        first = sub.headline if sub is not None else "see its summary"
        firsts.append(first if first.startswith(name) else f"{name}: {first}")
    count = f"{len(parts)} part" + ("s" if len(parts) != 1 else "")
    page = Page(title, f"{title}: {count}. " + " · ".join(firsts))
    for i, p in enumerate(parts, 1):
        sub = pages[p.name]
        head = f"{i}. {p.name} ({p.kind.replace('_', ' ')})"
        if sub is None:
            page.sections.append(
                (
                    f"part{i}",
                    head,
                    _summary(page, results[p.name], machine).replace(
                        'data-key="', f'data-key="{esc(p.name)}:'
                    )
                    + _extras(p, results[p.name], machine),
                    2,
                )
            )
            continue
        lead = f'<p class="part-headline" data-key="{esc(p.name)}:headline">{esc(sub.headline)}</p>'
        page.sections.append((f"part{i}", head, lead, 2))
        _absorb(page, i, p.name, sub)
    return page.finished()
