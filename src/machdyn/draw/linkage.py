"""Scenes of a :class:`~machdyn.linkage.Linkage`, read through its public topology view.

Links are drawn from the solved points of :meth:`Linkage.solve`: a binary link
as a bar, a link with three or more points as a plate (filled polygon);
ground pivots hatched; sliders as blocks on their guides (a hatched channel
for a ground guide), slots as slotted outlines, actuators as cylinders,
rolling contacts as wheels, motors and driven cranks with a motor symbol,
springs and dampers as zigzags and dashpots. A guide or slot on a moving link
turns with the solved points of that link; nothing is solved here.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from ..errors import InputError
from .build import GROUND, PALETTE, TRACE, _unit
from .scene import Curve, Item, Readout, Scene

__all__ = ["default_values", "drawn_value", "linkage_scene", "scene_of_linkage"]

_GROUND = "ground"


def _gid(kind: str, index: int) -> str:
    return f"{kind}{index}"


def _angle_of(lk: Any, link: str) -> float:
    """Drawn angle of ``link``: its first → second point (0 for the ground or one point)."""
    if link == _GROUND or link not in lk.links or len(lk.links[link].points) < 2:
        return 0.0
    p0, p1 = (lk.points[p] for p in lk.links[link].points[:2])
    return float(np.angle(p1 - p0))


def drawn_value(lk: Any, driver: str) -> float:
    """A driver's value in the drawn pose (radians for angles, lengths otherwise).

    Examples
    --------
    >>> from machdyn.linkage import Linkage
    >>> lk = (Linkage({"O2": 0, "A": 1j, "B": 3 + 0j}).ground("O2")
    ...       .link("crank", "O2", "A").link("rod", "A", "B").link("block", "B")
    ...       .slider("block", "ground", "B", 0.0).drive("crank"))
    >>> round(float(np.degrees(drawn_value(lk, "crank"))), 6)
    90.0
    """
    inputs = getattr(lk, "drawn_inputs", None)  # the linkage's own answer, where it has one
    if inputs is not None and driver in inputs:
        return float(inputs[driver])
    if driver in lk.links:
        return _angle_of(lk, driver)
    joint = next((j for j in lk.joints if j.name == driver and j.kind != "pin"), None)
    if joint is None:
        raise InputError("driver", f"{driver!r} is not a link or joint of this linkage")
    P = lk.points
    if joint.kind == "motor":
        a, b = joint.links
        return _angle_of(lk, b) - _angle_of(lk, a)
    if joint.kind == "actuator":
        return float(abs(P[joint.points[1]] - P[joint.points[0]]))
    if joint.kind in ("slider", "slot"):
        origin = P[joint.through] if joint.through else 0j
        return float(((P[joint.points[0]] - origin) * np.conj(joint.direction)).real)
    raise InputError("driver", f"cannot drive a {joint.kind} joint ({driver!r})")


def _ok_run(ok: np.ndarray, start: int) -> tuple[int, int] | None:
    """The run of consecutive ok samples containing ``start`` (inclusive ends)."""
    if not ok[start]:
        return None
    lo = start
    while lo > 0 and ok[lo - 1]:
        lo -= 1
    hi = start
    while hi < ok.size - 1 and ok[hi + 1]:
        hi += 1
    return lo, hi


def default_values(lk: Any, n: int = 120) -> tuple[dict[str, np.ndarray], bool]:
    """Driver values of a default animation: a full turn, or there and back over the reach.

    An angle driver turns once from its drawn value when every pose can be
    assembled; otherwise it swings from one end of the assemblable arc around
    the drawn pose to the other and back. A length driver (slider, actuator)
    goes there and back over the assemblable part of ±50 % of the drawing's
    size around its drawn value. Other drivers stay at their drawn values.
    Returns the values and whether they make a closed cycle.
    """
    drivers = lk.drivers
    if not drivers:
        raise InputError("drivers", "the linkage has no driver: call drive(...) before drawing it")
    first = drivers[0]
    rest = {d: drawn_value(lk, d) for d in drivers[1:]}
    v0 = drawn_value(lk, first)
    angle = first in lk.links or any(j.name == first and j.kind == "motor" for j in lk.joints)
    fine = max(4 * n, 360)
    if angle:
        trial = v0 + np.linspace(0.0, 2.0 * np.pi, fine + 1)
        start = 0
    else:
        pts = np.array(list(lk.points.values()))
        span = max(float(np.ptp(pts.real)), float(np.ptp(pts.imag)), 1e-9)
        trial = v0 + np.linspace(-0.5 * span, 0.5 * span, fine + 1)
        start = fine // 2
    with np.errstate(all="ignore"):
        m = lk.solve({first: trial, **{d: np.full(trial.size, v) for d, v in rest.items()}})
    ok = np.asarray(m.ok, bool)
    if angle and ok.all():
        values = v0 + np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
        closed = True
    else:
        run = _ok_run(ok, start) if ok[start] else None
        if run is None or run[0] == run[1]:
            values, closed = np.full(1, v0), False
        else:
            if angle:  # the arc may also continue below the drawn value
                back = v0 - np.linspace(0.0, 2.0 * np.pi, fine + 1)
                with np.errstate(all="ignore"):
                    mb = lk.solve(
                        {first: back, **{d: np.full(back.size, v) for d, v in rest.items()}}
                    )
                b_run = _ok_run(np.asarray(mb.ok, bool), 0)
                lo_v = back[b_run[1]] if b_run else v0
                hi_v = trial[run[1]]
            else:
                lo_v, hi_v = trial[run[0]], trial[run[1]]
            go = np.linspace(lo_v, hi_v, n)
            values = np.concatenate([go, go[-2:0:-1]])
            closed = True
    out = {first: values, **{d: np.full(values.size, v) for d, v in rest.items()}}
    return out, closed


def _plate_order(lk: Any, names: tuple[str, ...]) -> tuple[str, ...]:
    """A link's points in the order around their centre (a simple polygon)."""
    z = np.array([lk.points[p] for p in names])
    return tuple(names[i] for i in np.argsort(np.angle(z - z.mean())))


def _bar_ends(lk: Any, names: tuple[str, ...]) -> tuple[str, str] | None:
    """The two farthest points of a link whose points lie on one line (None otherwise)."""
    z = np.array([lk.points[p] for p in names])
    if z.size < 2:
        return None
    i, j = np.unravel_index(np.argmax(np.abs(z[:, None] - z[None, :])), (z.size, z.size))
    span = abs(z[j] - z[i])
    if span == 0:
        return None
    e = (z[j] - z[i]) / span
    off = np.abs(((z - z[i]) * np.conj(e)).imag)
    return (names[i], names[j]) if off.max() <= 1e-9 * span else None


def _rotation(lk: Any, motion: Any, link: str) -> np.ndarray:
    """How far ``link`` has turned from the drawing in each frame (radians), from its points."""
    n = len(motion)
    if link == _GROUND:
        return np.zeros(n)
    pts = lk.links[link].points
    if len(pts) >= 2:
        p0, p1 = (np.ravel(motion.points[p]) for p in pts[:2])
        d0, d1 = (lk.points[p] for p in pts[:2])
        return np.angle((p1 - p0) / (d1 - d0))
    # a one-point link (a block): its angle variable, from the frames themselves
    theta = np.ravel(motion.theta[link])
    return theta - theta[0]


def _line_points(
    lk: Any, motion: Any, joint: Any, on_turn: np.ndarray, margin: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ends of a slide line drawn under a block or a slot, and its direction angle.

    The line passes through the block's solved point along the joint's drawn
    direction turned with the link that carries it; it covers the travel of
    the point over the frames, measured from a point of that link.
    """
    at = np.ravel(motion.points[joint.points[0]])
    e = joint.direction * np.exp(1j * on_turn)
    on = joint.links[1]
    if joint.through:  # a point of `on` on the line
        ref = np.ravel(motion.points[joint.through]) if on != _GROUND else None
        if ref is None:
            ref = np.full(at.shape, lk.points[joint.through])
    elif on == _GROUND:  # the line through the drawn point
        ref = np.full(at.shape, lk.points[joint.points[0]])
    else:  # the drawn point, carried rigidly by `on`
        q = lk.links[on].points[0]
        ref = np.ravel(motion.points[q]) + (lk.points[joint.points[0]] - lk.points[q]) * np.exp(
            1j * on_turn
        )
    t = ((at - ref) * np.conj(e)).real
    good = np.isfinite(t)
    lo = float(t[good].min()) - margin if good.any() else -margin
    hi = float(t[good].max()) + margin if good.any() else margin
    return ref + lo * e, ref + hi * e, np.angle(e)


def linkage_scene(lk: Any, motion: Any, *, title: str | None = None, closed: bool = False) -> Scene:
    """The scene of a :class:`~machdyn.linkage.Linkage` over the samples of ``motion``.

    Parameters
    ----------
    lk : Linkage
    motion : LinkageMotion
        From ``lk.solve`` (one frame per sample, flattened).
    title : str, optional
    closed : bool
        Whether the frames make one cycle.

    Examples
    --------
    >>> from machdyn.linkage import Linkage
    >>> lk = (Linkage({"O2": 0, "O4": 8, "A": 2j, "B": 5 + 5j, "P": 3 + 6j})
    ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B", "P")
    ...       .link("rocker", "O4", "B").drive("crank"))
    >>> s = linkage_scene(lk, lk.solve(np.radians([90, 100])))
    >>> [i.kind for i in s.items if i.body == "coupler"]
    ['plate']
    """
    P = lk.points
    frames = len(motion)
    ok = np.ravel(np.asarray(motion.ok, bool))
    reason = np.ravel(np.asarray(motion.reason, dtype=object))
    # a pose is drawn where every point has a position (rates may be undefined at a toggle)
    names = list(P)
    cols = [np.ravel(motion.points[p]).astype(complex) for p in names]
    shown = np.all(np.isfinite(np.stack(cols, axis=1)), axis=1) if cols else ok
    cols = [np.where(shown, c, np.nan) for c in cols]
    pts = np.array(list(P.values()))
    size = max(float(np.ptp(pts.real)), float(np.ptp(pts.imag)), 1e-9)
    u = size / 100.0
    items: list[Item] = []
    extra: dict[str, np.ndarray] = {}
    angles: dict[str, np.ndarray] = {}
    colour = {name: PALETTE[i % len(PALETTE)] for i, name in enumerate(lk.links)}
    joints = lk.joints
    pins = [j for j in joints if j.kind == "pin"]
    grounded = [j.points[0] for j in pins if _GROUND in j.links]
    # pivots, and the anchors of actuators and springs (not slide-line references)
    used = set(grounded)
    for j in joints:
        if j.kind == "actuator":
            used.update(p for p in j.points if p in lk.ground_points)
    for e in lk.elements:
        used.update(p for p in e.points if p in lk.ground_points)
    for k, g in enumerate(p for p in lk.ground_points if p in used):
        items.append(Item("ground", _gid("ground", k), (g,), body="ground"))
    # guides and slots under the links
    for k, j in enumerate(jj for jj in joints if jj.kind in ("slider", "slot")):
        on = j.links[1]
        turn = _rotation(lk, motion, on)
        a, b, ang = _line_points(lk, motion, j, turn, 6 * u)
        ka, kb = f"{j.name} ·1", f"{j.name} ·2"
        extra[ka], extra[kb] = np.where(shown, a, np.nan), np.where(shown, b, np.nan)
        key = f"{j.kind}:{k}"
        angles[key] = np.where(np.isfinite(ang), ang, 0.0)
        body = "ground" if on == _GROUND else on
        if j.kind == "slot" and on != _GROUND and len(lk.links[on].points) == 1:
            # a one-point link carrying the slot (a yoke): a bar from its point to the slot
            km = f"{j.name} ·m"
            extra[km] = 0.5 * (extra[ka] + extra[kb])
            items.append(
                Item(
                    "bar", _gid("yoke", k), (lk.links[on].points[0], km), body=on, colour=colour[on]
                )
            )
        if j.kind == "slider":
            items.append(
                Item(
                    "guide",
                    _gid("guide", k),
                    (ka, kb),
                    body=body,
                    colour="#000000" if on == _GROUND else colour[on],
                    size=8 * u,
                    label=j.name,
                )
            )
        else:
            length = np.abs(b - a)
            length = float(np.nanmax(length)) if np.isfinite(length).any() else 1.0
            r = 1.6 * u
            t = np.linspace(-0.5 * np.pi, 0.5 * np.pi, 13)
            outline = np.concatenate([length + r * np.exp(1j * t), r * np.exp(1j * (t + np.pi))])
            items.append(
                Item(
                    "shape",
                    _gid("slot", k),
                    (ka,),
                    body=body,
                    angle=key,
                    outline=outline,
                    closed=True,
                    colour="#000000" if on == _GROUND else colour[on],
                    label=j.name,
                )
            )
    # links
    for name, link in lk.links.items():
        ends = _bar_ends(lk, link.points)
        if len(link.points) >= 3 and ends is None:
            order = _plate_order(lk, link.points)
            items.append(
                Item("plate", _gid("plate", len(items)), order, body=name, colour=colour[name])
            )
        elif len(link.points) >= 2:  # two points, or several on one line
            items.append(
                Item(
                    "bar",
                    _gid("bar", len(items)),
                    ends or link.points[:2],
                    body=name,
                    colour=colour[name],
                )
            )
    # joints and elements on top of the links
    for k, j in enumerate(joints):
        if j.kind == "slider":
            block = j.links[0]
            key = f"block:{k}"
            turn = _rotation(lk, motion, j.links[1])
            angles[key] = np.angle(j.direction) + np.where(np.isfinite(turn), turn, 0.0)
            items.append(
                Item(
                    "slider",
                    _gid("slider", k),
                    (j.points[0],),
                    body=block,
                    colour=colour.get(block, GROUND),
                    angle=key,
                    size=8 * u,
                    label=j.name,
                )
            )
        elif j.kind == "actuator":
            items.append(
                Item(
                    "actuator",
                    _gid("actuator", k),
                    j.points,
                    body=j.name,
                    colour=colour.get(j.links[0], GROUND),
                    label=j.name,
                )
            )
        elif j.kind == "roll":
            for side in (0, 1):
                r = j.radii[side]
                if not np.isfinite(r) or r <= 0:
                    continue  # a rack: its link is drawn as it is
                carrier = j.links[side]
                key = f"roll:{k}:{side}"
                angles[key] = _rotation(lk, motion, carrier)
                items.append(
                    Item(
                        "wheel",
                        _gid(f"wheel{side}_", k),
                        (j.points[side],),
                        body=carrier,
                        colour=colour.get(carrier, GROUND),
                        angle=key,
                        size=float(r),
                        label=j.name,
                        closed=not (j.internal and side == 1),  # a ring: outline only
                    )
                )
        elif j.kind == "motor":
            items.append(
                Item(
                    "motor", _gid("motor", k), j.points, body=j.name, colour="#d62728", label=j.name
                )
            )
    for d in lk.drivers:  # a crank driven from the ground: a motor at its ground pivot
        if d in lk.links:
            at = next((j.points[0] for j in pins if _GROUND in j.links and d in j.links), None)
            if at is not None:
                items.append(
                    Item(
                        "motor",
                        _gid("drive", len(items)),
                        (at,),
                        body=d,
                        colour="#d62728",
                        label=f"driver {d}",
                    )
                )
    for k, e in enumerate(lk.elements):
        if e.kind == "spring":
            kind = "damper" if e.stiffness == 0 and e.damping > 0 else "spring"
            items.append(
                Item(kind, _gid("spring", k), e.points, body=e.name, colour="#555555", label=e.name)
            )
        else:
            t = np.linspace(0, 3.2 * np.pi, 60)
            spiral = (0.6 + 0.35 * t / np.pi) * 1.2 * u * np.exp(1j * t)
            key = f"torsion:{k}"
            angles[key] = np.zeros(frames)
            items.append(
                Item(
                    "shape",
                    _gid("torsion", k),
                    e.points,
                    body=e.name,
                    colour="#555555",
                    angle=key,
                    outline=spiral,
                    closed=False,
                    label=e.name,
                )
            )
    pin_points = tuple(
        dict.fromkeys(
            [j.points[0] for j in pins]
            + [j.points[0] for j in joints if j.kind == "slot"]
            + [p for j in joints if j.kind == "actuator" for p in j.points]
        )
    )
    items.append(Item("pin", "pins", pin_points))
    loose = tuple(
        p
        for p in names
        if p not in pin_points
        and p not in lk.ground_points
        and not any(p in j.points for j in joints if j.kind != "pin")
    )
    if loose:
        items.append(Item("point", "points", loose, colour=TRACE))
    readout = []
    for d, values in motion.inputs.items():
        is_angle = d in motion.angle_drivers
        v = np.ravel(values).astype(float)
        label = f"θ {d} (driver)" if d in lk.links else f"{d} (driver)"
        unit = "deg" if is_angle else (_unit(lk) or "model units")
        shown_v = np.degrees(v) % 360.0 if is_angle else v  # the readout wraps; the data does not
        readout.append(Readout(label, unit, shown_v, 2 if is_angle else 4))
    for name, link in lk.links.items():
        if name not in motion.inputs and len(link.points) >= 2:
            theta = np.where(shown, np.degrees(np.ravel(motion.theta[name])), np.nan)
            readout.append(Readout(f"θ {name}", "deg", theta))
    for name, d in motion.lengths.items():
        if name not in motion.inputs:
            value = np.where(shown, np.ravel(d), np.nan)
            readout.append(Readout(f"d {name}", _unit(lk) or "model units", value, 4))
    all_names = (*names, *extra)
    xy = np.stack([*cols, *extra.values()], axis=1) if extra else np.stack(cols, axis=1)
    return Scene(
        title=title or "linkage: " + ", ".join(lk.links),
        names=tuple(all_names),
        xy=xy,
        items=tuple(items),
        shown=shown,
        reason=reason,
        angles=angles,
        readout=tuple(readout),
        length_unit=_unit(lk),
        closed=closed,
    )


def scene_of_linkage(
    lk: Any,
    values: Mapping[str, Any] | Any = None,
    *,
    n: int = 120,
    title: str | None = None,
    traces: tuple[str, ...] = (),
) -> Scene:
    """Solve ``lk`` over ``values`` (or :func:`default_values`) and build its scene.

    ``traces`` names points whose paths are drawn behind the linkage.
    """
    closed = False
    if values is None:
        values, closed = default_values(lk, n)
    with np.errstate(all="ignore"):
        motion = lk.solve(values)
    s = linkage_scene(lk, motion, title=title, closed=closed)
    if traces:
        curves = []
        for k, p in enumerate(traces):
            if p not in lk.points:
                raise InputError("traces", f"unknown point {p!r}; points: {', '.join(lk.points)}")
            z = np.where(s.shown, np.ravel(motion.points[p]), np.nan)
            if closed and z.size:
                z = np.append(z, z[:1])
            curves.append(
                Curve(f"trace{k}", z, TRACE if k == 0 else PALETTE[(k + 3) % 10], f"path of {p}")
            )
        s = replace(s, curves=tuple(curves))
    return s
