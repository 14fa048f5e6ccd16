"""What the studio's page shows of a document: one call, only the public Python API.

:func:`analyse` reads a spec document (``machdyn.spec.read``), picks its
linkage part and asks the library for everything the page draws — the solved
poses over the driver's range (``Linkage.solve`` through ``Machine.run``, so
the columns carry the file's units), the forces when the part has loads, the
scene (``machdyn.draw.linkage.linkage_scene``), the instant centres
(``Linkage.instant_centres``), mobility and the Assur groups with their
assembly signs. Nothing is computed here that the library does not compute:
the module only chooses the samples, calls and packs the answers as JSON.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import InputError, MachdynError

__all__ = ["analyse", "linkage_part"]

#: Samples of the driver's range the page gets by default.
SAMPLES = 360


def _numbers(values: Any, digits: int = 7, places: int | None = None) -> list[float | None]:
    """A list for JSON: ``None`` where not finite, else rounded.

    To ``digits`` significant digits of the largest value, or to ``places`` decimals.
    """
    a = np.asarray(values, dtype=float).ravel()
    good = np.isfinite(a)
    if not good.any():
        return [None] * a.size
    top = float(np.max(np.abs(a[good])))
    if places is None:
        places = digits - 1 - (math.floor(math.log10(top)) if top > 0 else 0)
    rounded = np.round(np.where(good, a, 0.0), max(min(places, 15), -15)).tolist()
    if good.all():
        return rounded
    return [v if g else None for v, g in zip(rounded, good.tolist(), strict=True)]


def _number(value: Any, digits: int = 7) -> float | None:
    """One value for JSON, as :func:`_numbers` writes it (``None`` where not finite)."""
    v = float(value)
    if not math.isfinite(v):
        return None
    places = digits - 1 - (math.floor(math.log10(abs(v))) if v else 0)
    return round(v, max(min(places, 15), -15)) + 0.0


def linkage_part(machine: Any, name: str | None = None) -> Any:
    """The linkage part ``name`` of a :class:`~machdyn.spec.Machine` (default: the first)."""
    parts = [p for p in machine.parts.values() if p.kind == "linkage"]
    if name is not None:
        found = [p for p in parts if p.name == name]
        if not found:
            listed = ", ".join(p.name for p in parts) or "none"
            raise InputError("part", f"no linkage part {name!r}; linkage parts: {listed}")
        return found[0]
    if not parts:
        kinds = ", ".join(f"{p.kind} {p.name!r}" for p in machine.parts.values()) or "no parts"
        raise InputError(
            "document",
            f"the studio edits [linkage.NAME] parts (and opens [fourbar.NAME], "
            f"[slider_crank.NAME] and [inverted_slider_crank.NAME] parts as drawn linkages); "
            f"this document has {kinds}. "
            "Start from a template, or draw one.",
        )
    return parts[0]


def _is_angle(lk: Any, driver: str) -> bool:
    return driver in lk.links or any(j.name == driver and j.kind == "motor" for j in lk.joints)


def _grid(lk: Any, driver: str, n: int) -> tuple[np.ndarray, int, bool]:
    """Samples of the first driver: a turn from the drawn value, or ± half the drawing's size.

    Returns the values, the index of the drawn pose and whether they close a cycle.
    """
    v0 = float(lk.drawn_inputs[driver])
    if _is_angle(lk, driver):
        return v0 + np.linspace(0.0, 2.0 * np.pi, n, endpoint=False), 0, True
    pts = np.array(list(lk.points.values()))
    span = max(float(np.ptp(pts.real)), float(np.ptp(pts.imag)), 1e-9)
    half = n // 2
    x = v0 + np.linspace(-0.5 * span, 0.5 * span, 2 * half + 1)
    x[half] = v0
    return x, half, False


def _run_document(part: Any, machine: Any, x: np.ndarray) -> Any:
    """``Machine.run`` of the part with its first driver swept over ``x`` (all points reported).

    The part's driver settings are replaced as ``machdyn linkage --sweep/--at`` does
    (``machdyn.cli.linkage.driver_values``): values in the model's units, the file's
    velocity and acceleration kept; the other drivers stay at their drawn values.
    """
    from ..spec._linkage import DriverSetting
    from ..spec._types import Grid

    lk = part.model
    motion = dict(part.values.get("motion", {}))
    for d in lk.drivers:
        kind = "angle" if _is_angle(lk, d) else "length"
        values = x if d == lk.drivers[0] else np.array([float(lk.drawn_inputs[d])])
        old = motion.get(d) or DriverSetting(kind)
        motion[d] = DriverSetting(
            kind, Grid.of(values), old.velocity, old.acceleration, old.driven_by
        )
    part.values["motion"] = motion
    carried = {p for link in lk.links.values() for p in link.points}
    part.values["report"] = [p for p in lk.points if p in carried]  # a point on no link: no motion
    return machine.run([part.name])[part.name]


def _columns(result: Any, units: Any, wanted: Any) -> tuple[list[str], dict[str, list]]:
    """Every plottable column's label, and the values of those asked for."""
    names: list[str] = []
    out: dict[str, list] = {}
    pairs: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for table in result.tables:
        for label, values in table.labelled(units).items():
            if label in ("ok", "reason") or label in names:  # (the input is in every table)
                continue
            names.append(label)
            if wanted is None or label in wanted:
                out[label] = _numbers(values)
            base, _, unit = label.partition(" ")
            if base.endswith("_x"):
                pairs.setdefault(base[:-2] + unit, (None, None))
                pairs[base[:-2] + unit] = (np.asarray(values, float), pairs[base[:-2] + unit][1])
            elif base.endswith("_y"):
                pairs.setdefault(base[:-2] + unit, (None, None))
                pairs[base[:-2] + unit] = (pairs[base[:-2] + unit][0], np.asarray(values, float))
    for key, (vx, vy) in pairs.items():
        if vx is None or vy is None:
            continue
        base, unit = key.split("[", 1) if "[" in key else (key, "")
        label = f"|{base}|" + (f" [{unit}" if unit else "")
        names.append(label)
        if wanted is None or label in wanted:
            out[label] = _numbers(np.hypot(vx, vy))
    return names, out


def _runs(ok: np.ndarray) -> list[tuple[int, int]]:
    """Inclusive index ranges of consecutive True samples."""
    out, start = [], None
    for i, good in enumerate([*ok.tolist(), False]):
        if good and start is None:
            start = i
        elif not good and start is not None:
            out.append((start, i - 1))
            start = None
    return out


def _problems(x_shown: np.ndarray, ok: np.ndarray, reason: np.ndarray) -> list[dict]:
    """The flagged samples grouped by reason: where (input range) and why."""
    out: list[dict] = []
    bad = np.flatnonzero(~ok)
    by_reason: dict[str, list[int]] = {}
    for i in bad.tolist():
        by_reason.setdefault(str(reason[i]) or "not solved", []).append(i)
    for why, idx in by_reason.items():
        runs = _runs(np.isin(np.arange(ok.size), idx))
        out.append(
            {
                "reason": why,
                "count": len(idx),
                "ranges": [[_number(x_shown[a]), _number(x_shown[b])] for a, b in runs],
                "samples": idx,
            }
        )
    return out


def _transmission(lk: Any, m: Any, units: Any, wanted: Any) -> tuple[list[str], dict]:
    """The transmission angle of each dyad with two assemblies (``transmission_angles``)."""
    names, out = [], {}
    groups = {g.name: g for g in lk.groups}
    for name, mu in lk.transmission_angles(m).items():
        links = groups[name].links if name in groups else (name,)
        label = units.label("mu_" + "_".join(links), "angle")
        names.append(label)
        if wanted is None or label in wanted:
            out[label] = _numbers(units.show("angle", np.asarray(mu, float)))
    return names, out


def _classes(lk: Any, units: Any) -> list[dict[str, Any]]:
    """Grashof condition and Barker class of every four-bar loop (``classify.fourbar_loops``)."""
    from ..classify import fourbar_loops

    out = []
    for loop in fourbar_loops(lk):
        c = loop.classification
        shown = [_number(units.show("length", r)) for r in loop.lengths]
        out.append(
            {
                "links": list(loop.links),
                "lengths": shown,
                "code": c.code,
                "condition": c.condition,
                "text": f"{c.code} ({c.name}); {c.condition}: s + l = {c.s + c.l:.4g} vs "
                f"p + q = {sum(loop.lengths) - c.s - c.l:.4g}",
            }
        )
    return out


def _limits(lk: Any, m: Any, x_shown: np.ndarray, ok: np.ndarray, reason: np.ndarray) -> list:
    """Frames to mark: input range ends, toggles, and the reversals of grounded links.

    The reversals are the poses where a link pivoted on the ground changes the sign of its
    angular velocity (its limit positions), found in the solver's own samples.
    """
    out: list[dict[str, Any]] = []
    n = ok.size
    runs = _runs(ok)
    if not (len(runs) == 1 and runs[0] == (0, n - 1)):
        for a, b in runs:
            for k in {a, b}:
                where = _number(x_shown[k])
                out.append(
                    {"frame": k, "kind": "limit", "text": f"end of the input range at {where}"}
                )
    for k in np.flatnonzero(np.char.find(reason.astype(str), "singular") >= 0).tolist():
        out.append({"frame": k, "kind": "toggle", "text": f"toggle at {_number(x_shown[k])}"})
    if m.omega is not None:
        rockers = {n for n, ln in lk.links.items() if set(ln.points) & set(lk.ground_points)}
        for name, w in m.omega.items():
            if name in lk.drivers or name not in rockers:
                continue
            w = np.ravel(w)
            s = np.sign(np.where(ok, w, np.nan))
            flips = np.flatnonzero((s[:-1] * s[1:]) < 0)
            for k in flips.tolist():
                k = k if abs(w[k]) <= abs(w[k + 1]) else k + 1
                where = _number(x_shown[k])
                out.append(
                    {"frame": k, "kind": "extreme", "text": f"{name} reverses (ω = 0) at {where}"}
                )
    return out


def _coordinates(scene: Any) -> dict[str, Any]:
    """Per-point coordinates of every frame, rounded as :func:`machdyn.draw.html.decimals` says.

    A point that never moves is written once (a number instead of a list); a frame where a
    point has no position is ``null``.
    """
    from ..draw.html import decimals

    xmin, xmax, ymin, ymax = scene.extent()
    places = decimals(max(xmax - xmin, ymax - ymin))
    xy = np.round(scene.xy, places)
    good = np.isfinite(xy)
    static = good.all(axis=0) & (np.ptp(xy.real, axis=0) == 0) & (np.ptp(xy.imag, axis=0) == 0)
    xs: list[Any] = []
    ys: list[Any] = []
    for j in range(xy.shape[1]):
        col = xy[:, j]
        if static[j]:
            xs.append(float(col[0].real) + 0.0)
            ys.append(float(col[0].imag) + 0.0)
        elif good[:, j].all():
            xs.append(col.real.tolist())
            ys.append(col.imag.tolist())
        else:
            ok = good[:, j].tolist()
            xs.append([v if g else None for v, g in zip(col.real.tolist(), ok, strict=True)])
            ys.append([v if g else None for v, g in zip(col.imag.tolist(), ok, strict=True)])
    return {"decimals": places, "x": xs, "y": ys}


def _scene_json(scene: Any) -> dict[str, Any]:
    """A scene's items, names and per-frame coordinates for the page to draw."""
    data: dict[str, Any] = {
        "frames": len(scene),
        **_coordinates(scene),
        "angles": {k: _numbers(np.degrees(v), places=4) for k, v in scene.angles.items()},
        "shown": [bool(v) for v in scene.shown],
        "readout": [
            {
                "label": r.label,
                "unit": r.unit,
                "digits": r.digits,
                "v": _numbers(r.values, places=r.digits),
            }
            for r in scene.readout
        ],
        "closed": bool(scene.closed),
    }
    data["names"] = list(scene.names)
    data["items"] = [
        {
            "k": it.kind,
            "id": it.gid,
            "p": [scene.index(p) for p in it.points],
            "body": it.body,
            "colour": it.colour,
            "a": it.angle,
            "size": float(it.size),
            "label": it.label,
            "closed": bool(it.closed),
            "outline": None
            if it.outline is None
            else [[float(z.real), float(z.imag)] for z in np.ravel(it.outline)],
        }
        for it in scene.items
    ]
    data["curves"] = [
        {
            "id": c.gid,
            "label": c.label,
            "colour": c.colour,
            "style": c.style,
            "x": _numbers(np.real(c.points)),
            "y": _numbers(np.imag(c.points)),
        }
        for c in scene.curves
    ]
    data["size"] = float(scene.size)
    return data


def _centres(lk: Any, x: np.ndarray, velocity: Any, places: int) -> dict[str, Any]:
    ics = lk.instant_centres({lk.drivers[0]: x, **_rest(lk, x.size)}, velocity=velocity)
    out = []
    for i, j in ics:
        c = ics[i, j]
        p, d = c.point, c.direction
        out.append(
            {
                "pair": [str(i), str(j)],
                "method": ics.method(i, j),
                "x": _numbers(p.real, places=places),
                "y": _numbers(p.imag, places=places),
                "dx": _numbers(d.real),
                "dy": _numbers(d.imag),
            }
        )
    return {"centres": out, "ok": [bool(v) for v in np.ravel(ics.valid)]}


def _rest(lk: Any, n: int) -> dict[str, np.ndarray]:
    return {d: np.full(n, float(lk.drawn_inputs[d])) for d in lk.drivers[1:]}


def _summary(lk: Any, part: Any, machine: Any) -> dict[str, Any]:
    units = machine.units
    try:
        mobility: Any = lk.mobility()
    except MachdynError as err:
        mobility = str(err)
    groups = [
        {"kind": g.kind, "name": g.name, "links": list(g.links), "sign": int(g.sign)}
        for g in lk.groups
    ]
    lengths = {}
    for name, link in lk.links.items():
        pts = link.points
        sides = []
        for a in range(len(pts)):
            for b in range(a + 1, len(pts)):
                d = abs(lk.points[pts[b]] - lk.points[pts[a]])
                sides.append([pts[a], pts[b], _number(units.show("length", d))])
        lengths[name] = sides
    return {
        "part": part.name,
        "mobility": mobility,
        "drivers": list(lk.drivers),
        "angle_drivers": [d for d in lk.drivers if _is_angle(lk, d)],
        "groups": groups,
        "lengths": lengths,
        "classes": _classes(lk, units),
        "can_flip": True,
        "units": {
            k: units.display(k)
            for k in ("length", "angle", "mass", "inertia", "force", "torque", "angular_velocity")
        },
    }


def analyse(
    doc: Mapping[str, Any],
    *,
    part: str | None = None,
    samples: int = SAMPLES,
    quantities: Any = None,
    centres: bool = False,
) -> dict[str, Any]:
    """Everything the page shows of a linkage document, as plain JSON-ready data.

    Parameters
    ----------
    doc : mapping
        A spec document (``docs/spec.md``) holding at least one ``[linkage.NAME]`` part.
    part : str, optional
        The linkage part to analyse (default: the first).
    samples : int
        Poses over the first driver's range: a full turn from its drawn value
        for an angle, ± half the drawing's size for a length.
    quantities : list of str, optional
        Labelled columns (``"omega_3 [rad/s]"``) whose values are sent; all by default.
        Names the linkage has no column for (the page may still ask for a plot of a
        link it has since renamed) are listed in the answer's ``unknown``.
    centres : bool
        Also the instant centres of every pair of bodies at every pose.

    Returns
    -------
    dict
        ``summary`` (mobility, drivers, groups and their assembly signs, link
        side lengths, units), ``x`` (the driver's samples in output units,
        ``x_label``), ``drawn`` (index of the drawn pose), ``ok``/``reason``
        per sample, ``problems`` (flagged samples by reason with their input
        ranges), ``scene`` (items and per-frame coordinates), ``names`` and
        ``columns`` (the plottable quantities), ``unknown`` (asked-for names that
        are not columns, in the order asked), ``centres`` if asked.

    Raises
    ------
    InputError, ModelError, AssemblyError
        The document cannot be read or the linkage cannot be built (the
        message names the key or the links at fault).

    Examples
    --------
    >>> from machdyn.studio.templates import template
    >>> out = analyse(template("four-bar"), samples=36)
    >>> out["summary"]["mobility"], len(out["x"]), all(out["ok"])
    (1, 36, True)
    """
    from .._validate import count
    from ..draw.linkage import linkage_scene
    from ..spec import read

    samples = count("samples", samples, minimum=8)
    if samples > 20_000:
        raise InputError("samples", f"at most 20000 poses, got {samples}")
    if not isinstance(doc, Mapping):
        raise InputError("document", "a machine document is a JSON object")
    machine = read(doc)
    p = linkage_part(machine, part)
    lk = p.model
    carried = {q for link in lk.links.values() for q in link.points} | set(lk.ground_points)
    loose = [q for q in lk.points if q not in carried]
    if loose:
        raise InputError(
            f"linkage.{p.name}.points.{loose[0]}", "is on no link: add it to a link, or delete it"
        )
    first = lk.drivers[0]
    x, drawn, closed = _grid(lk, first, samples)
    result = _run_document(p, machine, x)  # (``p`` belongs to this call's ``machine``)
    units = machine.units
    m = result.objects["motion"]
    f = result.objects.get("forces")
    ok = np.ravel(f.ok if f is not None else m.ok).astype(bool)
    reason = np.ravel(f.reason if f is not None else m.reason)
    kind = "angle" if _is_angle(lk, first) else "length"
    x_shown = np.asarray(units.show(kind, x), float)
    wanted = None if quantities is None else set(quantities)
    names, columns = _columns(result, units, wanted)
    mu_names, mu_columns = _transmission(lk, m, units, wanted)
    names[1:1] = mu_names  # after the driver's column
    columns.update(mu_columns)
    scene = linkage_scene(lk, m, title=p.name, closed=closed and bool(ok.all()))
    out: dict[str, Any] = {
        "summary": _summary(lk, p, machine),
        "x": _numbers(x_shown),
        "x_label": names[0] if names else first,
        "drawn": drawn,
        "closed": closed,
        "ok": [bool(v) for v in ok],
        "motion_ok": [bool(v) for v in np.ravel(m.ok)],
        "reason": [str(r) for r in reason],
        "problems": _problems(x_shown, ok, reason),
        "scene": _scene_json(scene),
        "names": names,
        "columns": columns,
        "has_forces": f is not None,
        "limits": _limits(lk, m, x_shown, ok, reason),
        "unknown": [q for q in dict.fromkeys(quantities or ()) if q not in set(names)],
    }
    if centres:
        velocity = {d: 1.0 for d in lk.drivers}
        out["centres"] = _centres(lk, x, velocity, out["scene"]["decimals"] + 2)
    return out
