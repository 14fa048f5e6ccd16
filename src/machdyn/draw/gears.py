"""Schematics of gear trains: mesh circles at their centres, every shaft turning at its speed.

A simple or compound :class:`~machdyn.gears.GearTrain` is drawn in front view:
each stage's pitch circles touching at the pitch point (external meshes side by
side, an internal pinion inside its ring, belts and chains as their two
straight runs, crossed for a crossed belt); a compound shaft carries its two
wheels as concentric circles, and the next stage leaves at an angle so the
stages do not lie on top of each other. A :class:`~machdyn.gears.PlanetaryTrain`
is drawn with its first gear on the central axis, the planets on the arm and
the last gear around them; the arm turns. Radii are the tooth numbers (or the
diameters given) halved: module 1.

Every wheel's spoke turns at the speed the train's own API gives
(``GearTrain.speeds``, ``PlanetaryTrain.table``), scaled so that the fastest
member makes one turn over the frames. Nothing is solved here.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from .._validate import integer
from .build import PALETTE
from .chart import Chart, Series
from .scene import Curve, Item, Readout, Scene
from .units import Units

__all__ = ["mesh_chart", "planetary_scene", "train_scene"]

#: Direction of each stage's line of centres (radians), turning so that stages do not overlap.
_TURN = np.radians(-50.0)


def _times(speeds: np.ndarray, n: int) -> np.ndarray:
    """Angles per frame of each member: the fastest makes one turn over ``n`` frames."""
    top = float(np.max(np.abs(speeds))) or 1.0
    t = np.arange(n) / n
    return 2 * np.pi * np.outer(t, speeds / top)


def train_scene(train: Any, omega_in: float = 1.0, n: int = 72, units: Any = None) -> Scene:
    """A simple or compound train in front view, every shaft turning at its speed.

    Examples
    --------
    >>> from machdyn.gears import GearTrain
    >>> s = train_scene(GearTrain([(18, 54), (20, 60)]), 1800.0, n=12)
    >>> [i.gid for i in s.items if i.kind == "wheel"]
    ['wheel_1a', 'wheel_2a', 'wheel_2b', 'wheel_3a']
    >>> round(float(abs(s.point("P1")[0] - s.point("S1 in")[0])), 6)  # r = 18/2
    9.0
    """
    n = integer("n", n, minimum=1)
    u = Units.of(units)
    speeds = np.asarray(train.speeds(omega_in))
    shafts = len(speeds)
    names = [f"S{k + 1}" for k in range(shafts)]
    names[0] += " in"
    names[-1] += " out"
    centre = [0j]
    pitch: list[complex] = []
    heading = 0.0
    wheels: list[tuple[int, float, str]] = []  # (shaft, radius, kind of its mesh)
    lines = []
    for k, (a, b, kind) in enumerate(train.stages):
        ra, rb = a / 2, b / 2
        d = np.exp(1j * heading)
        if kind == "external":
            centre.append(centre[k] + (ra + rb) * d)
            pitch.append(centre[k] + ra * d)
        elif kind == "internal":  # the driven ring around its pinion (or a pinion in a ring)
            centre.append(centre[k] + (ra - rb) * d)
            pitch.append(centre[k] + ra * d if ra < rb else centre[k] - ra * d)
        else:  # belts and chains: the runs between the wheels, one diameter's gap
            gap = 1.2 * (ra + rb) + max(ra, rb)
            centre.append(centre[k] + gap * d)
            pitch.append(centre[k] + 0.5 * gap * d)
            lines.append((k, ra, rb, d, kind))
        wheels += [(k, ra, kind), (k + 1, rb, kind)]
        heading += _TURN if k % 2 == 0 else -_TURN
    angles = _times(speeds, n)
    point_names = names + [f"P{k + 1}" for k in range(len(pitch))]
    xy = [np.full(n, z) for z in centre + pitch]
    items = []
    letters: dict[int, int] = {}
    for shaft, radius, kind in wheels:
        letters[shaft] = letters.get(shaft, 0) + 1
        gid = f"wheel_{shaft + 1}{'abc'[letters[shaft] - 1]}"
        ring = kind == "internal" and radius == max(
            r for s, r, kd in wheels if kd == "internal" and abs(s - shaft) <= 1
        )
        items.append(
            Item(
                "wheel",
                gid,
                (names[shaft],),
                body=f"{names[shaft]}: {radius * 2:g}",
                colour=PALETTE[shaft % len(PALETTE)],
                angle=f"shaft{shaft + 1}",
                size=radius,
                closed=not ring,
            )
        )
    for k, ra, rb, d, kind in lines:  # the belt's or chain's two runs (straight lines)
        names_k = (f"run{k + 1}a", f"run{k + 1}b", f"run{k + 1}c", f"run{k + 1}d")
        sign = -1.0 if kind == "crossed_belt" else 1.0
        n_ = 1j * d
        ends = (
            centre[k] + ra * n_,
            centre[k + 1] + sign * rb * n_,
            centre[k] - ra * n_,
            centre[k + 1] - sign * rb * n_,
        )
        point_names += list(names_k)
        xy += [np.full(n, z) for z in ends]
        body = kind.replace("_", " ")
        items.append(Item("line", f"run_{k + 1}_a", names_k[:2], body=body, colour="#555555"))
        items.append(Item("line", f"run_{k + 1}_b", names_k[2:], body=body, colour="#555555"))
    items.append(Item("pin", "shafts", tuple(names)))
    readout = tuple(
        Readout(
            f"ω {name}", u.unit("angular_velocity"), np.full(n, u.show("angular_velocity", w)), 2
        )
        for name, w in zip(names, speeds, strict=True)
    )
    return Scene(
        title=f"gear train, train value m_V = {train.train_value:.6g} (radii ∝ teeth)",
        names=tuple(point_names),
        xy=np.stack(xy, axis=1),
        items=tuple(items),
        angles={f"shaft{k + 1}": angles[:, k] for k in range(shafts)},
        readout=readout,
        closed=False,
    )


def _chain_layout(train: Any) -> tuple[dict[str, float], dict[str, float]]:
    """Each gear's distance from the central axis along the arm, and its pitch radius."""
    x: dict[str, float] = {}
    radius: dict[str, float] = {}
    prev = None
    for link in train.chain:
        name, teeth = link[0], link[1]
        r = teeth / 2
        if prev is None:
            x[name] = 0.0
        else:
            kind, xp, rp = link[2], x[prev], radius[prev]
            if kind == "shaft":
                x[name] = xp
            elif kind == "external":
                x[name] = xp + (rp + r)
            else:  # internal: a planet inside the previous ring, or a ring around the planet
                x[name] = xp + (rp - r) if r < rp else xp - (r - rp)
        radius[name] = r
        prev = name
    return x, radius


def planetary_scene(
    train: Any, speeds: Mapping[str, float] | None = None, n: int = 90, units: Any = None
) -> Scene:
    """An epicyclic train in front view: the arm turning, each gear at its absolute speed.

    ``speeds`` are two known member speeds (default: the last gear fixed and the
    first turning at 1).

    Examples
    --------
    >>> from machdyn.gears import PlanetaryTrain
    >>> t = PlanetaryTrain.simple(sun=40, planet=20, ring=80)
    >>> s = planetary_scene(t, {"arm": -200.0, "sun": 100.0}, n=8)
    >>> float(abs(s.point("planet")[0])), float(abs(s.point("ring")[0]))  # r_s + r_p; coaxial
    (30.0, 0.0)
    """
    n = integer("n", n, minimum=1)
    u = Units.of(units)
    speeds = dict(speeds) if speeds else {train.last: 0.0, train.first: 1.0}
    table = train.table(**speeds)
    omega = dict(zip(table.members, table.total, strict=True))
    members = table.members
    angles = _times(np.array([omega[m] for m in members]), n)
    theta = {m: angles[:, i] for i, m in enumerate(members)}
    x, radius = _chain_layout(train)
    arm = np.exp(1j * theta["arm"])
    names = ["axis"]
    cols = [np.zeros(n, complex)]
    items = []
    gears = [link[0] for link in train.chain]
    rings = {  # the larger gear of each internal mesh is a ring: drawn open
        max(train.chain[k - 1][:2], link[:2], key=lambda g: g[1])[0]
        for k, link in enumerate(train.chain)
        if k and link[2] == "internal"
    }
    for i, name in enumerate(gears):
        names.append(name)
        cols.append(x[name] * arm)
        internal = name in rings
        items.append(
            Item(
                "wheel",
                f"gear_{i + 1}",
                (name,),
                body=f"{name}: {int(radius[name] * 2)} teeth",
                colour=PALETTE[i % len(PALETTE)],
                angle=f"g{i + 1}",
                size=radius[name],
                closed=not internal,
            )
        )
    reach = max((abs(x[g]) for g in gears), default=0.0)
    outer = max(gears, key=lambda g: abs(x[g]))
    items.append(Item("bar", "arm", ("axis", outer), body="arm", colour="#444444"))
    fixed = [m for m in members if abs(omega[m]) <= 1e-12 * max(abs(w) for w in omega.values())]
    for m in fixed:  # a member held still: the ground symbol under it
        at = x.get(m, 0.0) * arm - 1j * (radius.get(m, 0.0) if m != "arm" else 0.0)
        names.append(f"{m} (fixed)")
        cols.append(at if m != "arm" else np.zeros(n, complex))
        items.append(Item("ground", f"fixed_{len(names)}", (names[-1],), body="ground"))
    seen = {0.0}  # one pin (and one name) per centre: a compound planet's second gear shares it
    placed = [g for g in gears if x[g] not in seen and not seen.add(x[g])]
    items.append(Item("pin", "centres", ("axis", *placed)))
    readout = tuple(
        Readout(
            f"ω {m}",
            u.unit("angular_velocity"),
            np.full(n, u.show("angular_velocity", omega[m])),
            2,
        )
        for m in members
    )
    arm_circle = reach * np.exp(1j * np.linspace(0, 2 * np.pi, 121))
    return Scene(
        title=f"planetary train, R = {train.train_value:.6g} (arm fixed; radii ∝ teeth)",
        names=tuple(names),
        xy=np.stack(cols, axis=1),
        items=tuple(items),
        angles={"arm": theta["arm"]} | {f"g{i + 1}": theta[g] for i, g in enumerate(gears)},
        curves=(Curve("arm_path", arm_circle, "#bbbbbb", "path of the planet centres", "dashed"),),
        readout=readout,
        closed=False,
    )


def mesh_chart(pair: Any, units: Any = None) -> Chart:
    """The mesh region of a gear pair: the line of action between the base-circle tangent points.

    Norton's figure of the contact geometry (Figs. 9-6, 9-12): the pinion's
    centre at the origin and the gear's on the x axis (left of it for an
    internal gear), the pitch point P at ``r_p'``; the line of action through P
    at the operating pressure angle, from the pinion's tangent point T_p to the
    gear's T_g (the interference points); the tip (addendum), pitch and base
    circles near P; the path of contact from the first to the last contact,
    which must lie between T_p and T_g (else the tips interfere).

    Examples
    --------
    >>> from machdyn.gears import Gear, GearPair
    >>> c = mesh_chart(GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8)))
    >>> path = next(s for s in c.series if s.gid == "path_of_contact")
    >>> round(float(np.hypot(np.diff(path.x), np.diff(path.y))[0]), 6)  # the length of action
    0.624859
    """
    u = Units.of(units if units is not None else pair)
    p, g = pair.pinion, pair.gear
    phi = pair.operating_pressure_angle
    rp_op, rg_op = pair.operating_pitch_radii
    c = -pair.center_distance if pair.internal else pair.center_distance
    pitch = complex(rp_op, 0.0)
    d = complex(np.sin(phi), np.cos(phi))
    toward_first = -1.0 if pair.driver == "pinion" else 1.0
    first = pitch + toward_first * pair.path_of_approach * d
    last = pitch - toward_first * pair.path_of_recess * d
    foot = lambda centre: pitch + ((centre - pitch) * d.conjugate()).real * d  # noqa: E731
    tp, tg = foot(0j), foot(complex(c))
    half = 1.15 * max(abs(tp - pitch), abs(tg - pitch), abs(first - pitch), abs(last - pitch))
    scale = float(u.show("length", 1.0))

    def shown(z: Any) -> tuple[np.ndarray, np.ndarray]:
        z = np.asarray(z, complex)
        z = np.where(np.abs(z - pitch) <= half, z, np.nan)  # only the region of the mesh
        return z.real * scale, z.imag * scale

    t = np.linspace(0, 2 * np.pi, 4001)
    series = []
    for label, centre, radii, colour in (
        ("pinion", 0j, (p.addendum_radius, rp_op, p.base_radius), PALETTE[0]),
        ("gear", complex(c), (g.addendum_radius, rg_op, g.base_radius), PALETTE[3]),
    ):
        for kind, radius, dashed in zip(
            ("tip", "pitch", "base"), radii, (False, True, True), strict=True
        ):
            x, y = shown(centre + radius * np.exp(1j * t))
            series.append(
                Series(
                    x,
                    y,
                    f"{label} {kind} circle",
                    colour,
                    dashed=dashed,
                    width=1.4 if kind == "tip" else 1.0,
                    gid=f"{label}_{kind}",
                )
            )
    x, y = shown([tp, tg])
    series.append(Series(x, y, "line of action T_p T_g", "#000000", gid="line_of_action"))
    x, y = shown([first, last])
    series.append(Series(x, y, "path of contact Z", "#d62728", width=4.0, gid="path_of_contact"))
    pts = {"P": pitch, "T_p": tp, "T_g": tg, "first contact": first, "last contact": last}
    x, y = shown(list(pts.values()))
    series.append(Series(x, y, "", "#000000", marker=True, gid="points"))
    notes = [(float(a), float(b), n) for (n, _), a, b in zip(pts.items(), x, y, strict=True)]
    unit = u.unit("length")
    return Chart(
        f"line of action at φ' = {np.degrees(phi):.4g}°, "
        f"Z = {u.text('length', pair.length_of_action, 4)}",
        f"x ({unit})",
        f"y ({unit})",
        series=series,
        notes=notes,
        equal=True,
    )
