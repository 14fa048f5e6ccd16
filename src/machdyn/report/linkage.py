"""The design report of a :class:`~machdyn.linkage.Linkage`, read through its topology view."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from itertools import combinations
from typing import Any

import numpy as np

from ..draw.chart import Chart, Series
from ..draw.engineering import (
    pin_force_charts,
    shaking_charts,
    torque_chart,
    transmission_chart,
)
from ..draw.html import widget
from ..draw.linkage import default_values, linkage_scene
from ..draw.scene import Scene
from ..draw.units import Units
from .checks import (
    Body,
    Check,
    RigidMotion,
    equilibrium,
    finite_differences,
    kennedy,
    kinetic_energy_rate,
    loop_closure,
    momentum,
    momentum_differences,
    power_balance,
)
from .fourbar import _units
from .page import Page, esc, fmt

__all__ = ["linkage_bodies", "linkage_checks", "linkage_report"]

_GROUND = "ground"


def _title(lk: Any) -> str:
    count = len(lk.links)
    return f"linkage of {count} moving link{'s' if count != 1 else ''} ({', '.join(lk.links)})"


def linkage_checks(
    lk: Any,
    motion: Any,
    x: np.ndarray,
    xdot: float,
    forces: Any = None,
    gravity: float = 0.0,
    loads: Mapping[str, Any] | None = None,
) -> list[Check]:
    """Self-checks of a linkage motion (and forces), computed apart from the solver.

    Velocities of the centres of mass are written here from each link's first
    point and ω (``v_G = v_p + jω(G − p)``), so the power balance tests the
    driver efforts against a kinetic energy not taken from the force assembler.
    ``loads`` are the applied loads the forces were found with (``external_forces``,
    ``external_torques``, and the friction of ``viscous``/``coulomb`` sliders, as
    :meth:`Linkage.forces` takes them): their power enters the balance and they act
    on the free bodies.
    """
    ok = np.ravel(motion.ok)
    zero = np.zeros(ok.shape, complex)
    points = {}
    for p in lk.points:
        pos = np.ravel(motion.points[p])
        vel = np.ravel(motion.point_velocity[p]) if motion.point_velocity is not None else zero
        acc = (
            np.ravel(motion.point_acceleration[p])
            if motion.point_acceleration is not None
            else zero
        )
        points[p] = (pos, vel, acc)
    links: dict[str, tuple[tuple[str, ...], np.ndarray, np.ndarray]] = {}
    if lk.ground_points:
        links[_GROUND] = (tuple(lk.ground_points), zero.real, zero.real)
    for name, link in lk.links.items():
        links[name] = (link.points, np.ravel(motion.omega[name]), np.ravel(motion.alpha[name]))
    pins = {}
    for j in lk.joints:
        if j.kind == "pin":
            for a, b in combinations(j.links, 2):
                if a in links and b in links:
                    pins[a, b] = j.points[0]
    rigid = RigidMotion(np.asarray(x, float), float(xdot), points, links, ok, pins)
    checks = [*loop_closure(rigid), *finite_differences(rigid), kennedy(rigid)]
    if forces is not None:
        bodies, p_ext, p_abs = {}, np.zeros(ok.shape), np.zeros(ok.shape)
        for name, link in lk.links.items():
            if link.mass == 0 and link.inertia == 0:
                continue
            p0, v0, a0 = points[link.points[0]]
            w, al = links[name][1], links[name][2]
            G = np.ravel(motion.cg[name])
            vg = v0 + 1j * w * (G - p0)
            ag = a0 + (1j * al - w * w) * (G - p0)
            bodies[name] = (link.mass, link.inertia, vg, ag, w, al)
            term = link.mass * gravity * vg.imag
            p_ext, p_abs = (
                p_ext - term,
                p_abs
                + np.abs(term)
                + np.abs(link.mass * (np.conj(vg) * ag).real)
                + np.abs(link.inertia * w * al),
            )
        for d, effort in forces.driver.items():
            rate = np.ravel(motion.length_rate[d]) if d in motion.length_rate else None
            if d in lk.links:
                rate = np.ravel(motion.omega[d])
            elif rate is None:  # a motor: the rate of the relative angle
                a, b = next(j.links for j in lk.joints if j.name == d)
                wa = zero.real if a == _GROUND else np.ravel(motion.omega[a])
                rate = np.ravel(motion.omega[b]) - wa
            term = np.ravel(effort) * rate
            p_ext, p_abs = p_ext + term, p_abs + np.abs(term)
        for e, effort in forces.elements.items():
            term = np.ravel(effort) * np.ravel(forces.element_rate[e])
            p_ext, p_abs = p_ext - term, p_abs + np.abs(term)
        applied = _applied(lk, motion, points, links, forces, loads or {})
        for term in applied.power:
            p_ext, p_abs = p_ext + term, p_abs + np.abs(term)
        good = ok & np.ravel(forces.ok)
        checks.append(power_balance(p_ext, kinetic_energy_rate(bodies), good, scale=p_abs))
        free = linkage_bodies(lk, points, links, motion, forces, gravity)
        for b in free:
            for F, X in applied.forces.get(b.name, ()):
                b.load(F, X, "external")
            for T in applied.torques.get(b.name, ()):
                b.torque(T, "external")
        Fs, Ms = np.ravel(forces.shaking_force), np.ravel(forces.shaking_moment)
        checks.append(equilibrium(free, good, rigid.size))
        checks.append(momentum(free, Fs, Ms, good, rigid.size))
        checks.append(momentum_differences(free, Fs, Ms, x, xdot, good, rigid.size))
    return checks


@dataclass
class _Applied:
    """Applied loads per link (``forces``: (F, X), ``torques``: T) and their powers."""

    forces: dict[str, list[tuple[np.ndarray, np.ndarray]]]
    torques: dict[str, list[np.ndarray]]
    power: list[np.ndarray]


def _applied(
    lk: Any,
    motion: Any,
    points: Mapping[str, tuple[np.ndarray, np.ndarray, np.ndarray]],
    links: Mapping[str, tuple[tuple[str, ...], np.ndarray, np.ndarray]],
    forces: Any,
    loads: Mapping[str, Any],
) -> _Applied:
    """The loads of ``loads`` on each link, and the power of every one of them.

    A point given in a link's frame is placed here from the link's first point and
    angle (``X = p0 + z e^{jθ}``: the frame's x axis is the line to its second point);
    a material point's velocity is ``v_p0 + jω(X − p0)``. A slider's friction does
    work on the relative slip: the slider force times the difference of the two
    links' velocities at its point (the normal part does none).
    """
    from .._validate import point

    n = np.ravel(motion.ok).shape

    def velocity(link: str, X: np.ndarray) -> np.ndarray:
        if link not in links or link == _GROUND:
            return np.zeros(n, complex)
        p0, v0, _ = points[links[link][0][0]]
        return v0 + 1j * links[link][1] * (X - p0)

    out = _Applied({}, {}, [])
    for link, at, F in loads.get("external_forces", ()):
        p0 = points[lk.links[link].points[0]][0]
        X = (
            points[at][0]
            if isinstance(at, str)
            else p0 + point("external force point", at) * np.exp(1j * np.ravel(motion.theta[link]))
        )
        F = np.broadcast_to(np.ravel(np.asarray(F, complex)), n)
        out.forces.setdefault(link, []).append((F, X))
        out.power.append((np.conj(F) * velocity(link, X)).real)
    torques = loads.get("external_torques") or {}
    for link, T in torques.items() if isinstance(torques, Mapping) else torques:
        T = np.broadcast_to(np.ravel(np.asarray(T, float)), n)
        out.torques.setdefault(link, []).append(T)
        out.power.append(T * links[link][1])
    joints = {j.name: j for j in lk.joints}
    for name in {*(loads.get("viscous") or {}), *(loads.get("coulomb") or {})}:
        j, F = joints[name], np.ravel(forces.sliders[name])
        X = points[j.points[0]][0]
        slip = velocity(j.links[0], X) - velocity(j.links[1], X)
        out.power.append((np.conj(F) * slip).real)
    return out


def linkage_bodies(
    lk: Any,
    points: Mapping[str, tuple[np.ndarray, np.ndarray, np.ndarray]],
    links: Mapping[str, tuple[tuple[str, ...], np.ndarray, np.ndarray]],
    motion: Any,
    forces: Any,
    gravity: float = 0.0,
) -> list[Body]:
    """Every moving link as a free body with the loads ``forces`` puts on it.

    Pin forces at their pins, slider and slot forces (and couples) at their
    points, rolling contacts at their contact points, actuator pushes along
    their lines, spring tensions along theirs, driver and motor torques and
    gravity: each applied to the link it acts on and, reversed, to the other
    (``source`` ``"ground"`` when that other is the frame, ``"joint"`` when it
    moves, ``"external"`` for gravity). ``v_G`` and ``a_G`` are written from the
    link's first point and its ω, α (``points`` and ``links`` as given to
    :class:`RigidMotion`).
    """
    bodies: dict[str, Body] = {}
    for name, link in lk.links.items():
        p0, v0, a0 = points[link.points[0]]
        w, al = links[name][1], links[name][2]
        G = np.ravel(motion.cg[name]) if name in motion.cg else p0
        G = np.where(np.isfinite(G), G, p0)
        vG, aG = v0 + 1j * w * (G - p0), a0 + (1j * al - w * w) * (G - p0)
        b = Body(name, link.mass, link.inertia, G, vG, aG, w, al)
        if gravity and link.mass:
            b.load(np.full(G.shape, -1j * link.mass * gravity), G, "external")
        bodies[name] = b

    def pair(on: str, by: str, force: Any, at: Any) -> None:
        """``force`` on link ``on`` from link ``by`` at ``at``; the reaction on ``by``."""
        force = np.ravel(force) + 0j
        for link, other, sign in ((on, by, 1.0), (by, on, -1.0)):
            if link in bodies:
                source = "ground" if other not in bodies else "joint"
                bodies[link].load(sign * force, np.ravel(at), source)

    def couple(on: str, by: str, torque: Any) -> None:
        torque = np.ravel(torque).astype(float)
        for link, other, sign in ((on, by, 1.0), (by, on, -1.0)):
            if link in bodies:
                bodies[link].torque(sign * torque, "ground" if other not in bodies else "joint")

    joints = {j.name: j for j in lk.joints}
    for (a, b), F in forces.pins.items():
        j = next(j for j in joints.values() if j.kind == "pin" and {a, b} <= set(j.links))
        pair(b, a, F, points[j.points[0]][0])
    for name, F in forces.sliders.items():
        j = joints[name]
        pair(j.links[0], j.links[1], F, points[j.points[0]][0])
        if name in forces.couple:
            couple(j.links[0], j.links[1], forces.couple[name])
    for name, F in forces.rolling.items():
        j = joints[name]
        pair(j.links[1], j.links[0], F, forces.contact[name])
    for d, effort in forces.driver.items():
        j = joints.get(d)
        if d in lk.links:  # an angle driver: the ground turns the link
            couple(d, _GROUND, effort)
        elif j is not None and j.kind == "motor":  # T on link b, −T on link a
            couple(j.links[1], j.links[0], effort)
        elif j is not None and j.kind == "actuator":  # a push along start → end
            start, end = points[j.points[0]][0], points[j.points[1]][0]
            u = (end - start) / np.abs(end - start)
            pair(j.links[1], j.links[0], np.ravel(effort) * u, end)
    for e in lk.elements:
        T = np.ravel(forces.elements[e.name])
        a, b = e.links
        if len(e.points) == 2:  # a spring's tension pulls its ends together
            start, end = points[e.points[0]][0], points[e.points[1]][0]
            u = (end - start) / np.abs(end - start)
            pair(a, b, T * u, start)  # (on b at start or end alike: the same line)
        else:  # a torsion spring: +τ on link a, −τ on link b
            couple(a, b, T)
    return list(bodies.values())


def _drawing_as_given(lk: Any, title: str) -> Scene:
    """The linkage as drawn (one frame), for a model that cannot be moved."""
    motion_like = _Drawn(lk)
    s = linkage_scene(lk, motion_like, title=title)
    return s


class _Drawn:
    """The drawn pose in the shape of a one-sample motion (positions only)."""

    def __init__(self, lk: Any) -> None:
        self.points = {p: np.array([z]) for p, z in lk.points.items()}
        self.theta = {n: np.array([0.0]) for n in lk.links}
        self.ok = np.array([True])
        self.reason = np.array([""], dtype=object)
        self.inputs: Mapping[str, np.ndarray] = {}
        self.angle_drivers = frozenset()
        self.lengths: Mapping[str, np.ndarray] = {}

    def __len__(self) -> int:
        return 1


def linkage_report(
    lk: Any,
    *,
    values: Any = None,
    velocity: float = 1.0,
    n: int = 360,
    gravity: float = 0.0,
    k: float | None = None,
    title: str | None = None,
    length_unit: str | None = None,
    units: Any = None,
    mu_limit_deg: float = 40.0,
    external_forces: Any = (),
    external_torques: Any = (),
    viscous: Mapping[str, float] | None = None,
    coulomb: Mapping[str, float] | None = None,
) -> Page:
    """Build the report page of a linkage (see :func:`machdyn.report.report`).

    ``external_forces``, ``external_torques``, ``viscous`` and ``coulomb`` are the
    applied loads, as :meth:`Linkage.forces` takes them (a machine file's
    ``[[forces]]``, ``torques`` and ``friction``).
    """
    loads = {
        "external_forces": external_forces,
        "external_torques": external_torques,
        "viscous": viscous or {},
        "coulomb": coulomb or {},
    }
    title = title or _title(lk)
    u = _units(lk, units, length_unit)
    try:
        mobility = lk.mobility()
    except Exception as err:  # a model error is the answer here
        mobility = f"not countable: {err}"
    if not lk.drivers:
        page = Page(title, f"{title}: has no driver, so it cannot be moved (mobility {mobility}).")
        page.section(
            "model",
            "The model as drawn",
            _model_tables(page, lk, u) + widget(_drawing_as_given(lk, title)),
        )
        return page
    driver = lk.drivers[0]
    is_angle = driver in lk.links or any(j.name == driver and j.kind == "motor" for j in lk.joints)
    try:
        if values is None:
            values, closed = default_values(lk, n)
        else:
            values = values if isinstance(values, Mapping) else {driver: np.ravel(values)}
            closed = False
        rates = {
            d: np.full(np.size(values[d]), velocity if d == driver else 0.0) for d in lk.drivers
        }
        with np.errstate(all="ignore"):
            m = lk.solve(values, velocity=rates)
        assembled = np.ravel(m.ok)
    except Exception as err:  # cannot be assembled anywhere: say so, draw it as given
        page = Page(title, f"{title}: cannot be assembled at any driver value tried ({err}).")
        page.failed = True
        page.section(
            "model",
            "The model as drawn",
            _model_tables(page, lk, u) + widget(_drawing_as_given(lk, title)),
        )
        return page
    x = np.ravel(values[driver]).astype(float)
    if not assembled.any():
        reason = next((r for r in np.ravel(m.reason) if r), "no pose closes")
        page = Page(title, f"{title}: cannot be assembled at any driver value tried ({reason}).")
        page.failed = True
        page.section(
            "model",
            "The model as drawn",
            _model_tables(page, lk, u) + widget(_drawing_as_given(lk, title)),
        )
        return page
    xs = np.ravel(u.show("angle" if is_angle else "length", x))
    xunit = u.unit("angle" if is_angle else "length")
    lo, hi = float(np.nanmin(xs[assembled])), float(np.nanmax(xs[assembled]))
    full = closed and is_angle and assembled.all()
    reach = "a full turn" if full else f"{lo:.4g} to {hi:.4g} {xunit}"
    page = Page(
        title,
        f"{title}: mobility {mobility}; driver {driver!r} moves over {reach}; "
        f"{int(assembled.sum())} of {assembled.size} poses assembled.",
    )
    step = max(1, len(x) // 120)
    frames = lk.solve({d: np.ravel(v)[::step] for d, v in values.items()})
    s = replace(
        linkage_scene(lk, frames, title=title, closed=closed),
        length_unit="" if u.free else u.unit("length"),
    )
    page.section("model", "The model and its drawing", _model_tables(page, lk, u) + widget(s))
    page.section(
        "class",
        "Mobility and input range",
        page.table(
            [
                ("mobility (Kutzbach–Gruebler)", esc(mobility), "mobility"),
                ("drivers", esc(", ".join(lk.drivers)), "drivers"),
                (f"range of {driver}", esc(reach), "input_range"),
                ("poses not assembled", str(int((~assembled).sum())), "not_assembled"),
            ]
        ),
    )
    xlabel = f"θ {driver} ({xunit})" if driver in lk.links else f"{driver} ({xunit})"
    charts = _kinematics_charts(lk, m, xs, xlabel, driver, assembled, u)
    _transmission_section(page, lk, m, (x, xs), xlabel, is_angle, mu_limit_deg)
    page.section("kinematics", "Kinematics", "".join(c.to_svg(height=240) for c in charts))
    forces = None
    loaded = any(link.mass > 0 or link.inertia > 0 for link in lk.links.values())
    if loaded or lk.elements or any(loads.values()):
        forces = lk.forces(m, gravity=gravity, **loads)
        _force_sections(page, lk, m, forces, (x, xs), xlabel, driver, u, full, velocity, k)
        run = (values, rates, gravity, loads)
        _balancing_section(page, lk, forces, run, (x, xs), xlabel, u, full)
    else:
        page.section(
            "forces",
            "Forces",
            '<p class="remark">No link has mass: give link masses '
            "(link(..., mass=, inertia=, cg=)) for pin forces and driver effort.</p>",
        )
    checks = linkage_checks(lk, m, x, velocity, forces, gravity, loads)
    page.section(
        "selfcheck",
        "Self-check: independent checks on this machine",
        page.checks(checks) + '<p class="remark">Rigid-body fields of every link (the '
        "loops and their derivatives), five-point differences along the sweep, Kennedy's "
        "rule on centres found from the velocity fields; with forces, the power balance of "
        "the driver efforts and springs against the kinetic energy, each link's equilibrium "
        "under the forces printed, and the momentum balance of the whole machine (with a_G, "
        "and by differences of the momentum along the sweep).</p>",
    )
    return page.finished()


def _transmission_section(
    page: Page,
    lk: Any,
    m: Any,
    x: tuple[np.ndarray, np.ndarray],
    xlabel: str,
    is_angle: bool,
    limit_deg: float,
) -> None:
    """μ of every dyad with two assemblies over the sweep (``Linkage.transmission_angles``)."""
    raw, xs = x
    where = xlabel.split(" (")[0]
    mus = lk.transmission_angles(m)
    if not mus:
        return
    rows, charts = [], []
    for k, (group, mu) in enumerate(mus.items()):
        deg = np.degrees(np.ravel(mu))
        if np.isfinite(deg).any():
            j = int(np.nanargmin(deg))
            at = f"{xs[j]:.1f}°" if is_angle else f"{xs[j]:.4g} {xlabel.rsplit('(', 1)[-1][:-1]}"
            met = "met" if deg[j] >= limit_deg else "NOT met"
            rows.append(
                (
                    f"smallest μ of {group}",
                    f"{deg[j]:.3f}° at {esc(where)} = {esc(at)} (limit {limit_deg:g}°: {met})",
                    f"mu_min_{k}",
                )
            )
        charts.append(
            transmission_chart(
                raw,
                mu,
                x=None if is_angle else xs,
                xlabel=xlabel,
                where=where,
                title=f"transmission angle of the {group}",
            ).to_svg(height=220)
        )
    page.section(
        "angles",
        "Transmission angles",
        page.table(rows) + "".join(charts) + '<p class="remark">μ of every dyad with two '
        "assemblies (RRR: the angle at its middle pin; RRP: the rod against the slide's "
        "normal), 90° best, with the design limit (mu_limit_deg).</p>",
    )


def _kinematics_charts(
    lk: Any,
    m: Any,
    xs: np.ndarray,
    xlabel: str,
    driver: str,
    assembled: np.ndarray,
    u: Units,
) -> list[Chart]:
    """Link angles, angular velocities and accelerations against the driver (shown units)."""
    moving = [n for n in lk.links if n != driver]
    panels = (
        ("link angles", "θ", "angle", m.theta, assembled),
        ("angular velocities", "ω", "angular_velocity", m.omega, m.ok),
        ("angular accelerations", "α", "angular_acceleration", m.alpha, m.ok),
    )
    charts = []
    for title, sym, kind, field, valid in panels:
        series = [
            Series(
                xs,
                np.where(np.ravel(valid), np.ravel(u.show(kind, np.ravel(field[n]))), np.nan),
                f"{sym} {n}",
                gid=f"{sym}_{n}",
            )
            for n in moving
            if kind != "angle" or len(lk.links[n].points) >= 2
        ]
        if series:
            charts.append(Chart(title, xlabel, u.axis(sym, kind), series))
    return charts


def _model_tables(page: Page, lk: Any, u: Units) -> str:
    unit = u.unit("length")
    pts = page.grid(
        ("point", f"x ({unit})", f"y ({unit})", "on"),
        [
            [
                esc(p),
                fmt(float(u.show("length", z.real)), 6),
                fmt(float(u.show("length", z.imag)), 6),
                esc(
                    ", ".join(
                        ["ground"] * (p in lk.ground_points)
                        + [n for n, link in lk.links.items() if p in link.points]
                    )
                ),
            ]
            for p, z in lk.points.items()
        ],
    )
    joints = page.grid(
        ("joint", "kind", "links", "points"),
        [
            [esc(j.name), esc(j.kind), esc(" – ".join(j.links)), esc(", ".join(j.points))]
            for j in lk.joints
        ],
    )
    links = page.grid(
        ("link", "points", f"mass ({u.unit('mass')})", f"I_G ({u.unit('inertia')})"),
        [
            [
                esc(n),
                esc(", ".join(link.points)),
                fmt(float(u.show("mass", link.mass))),
                fmt(float(u.show("inertia", link.inertia))),
            ]
            for n, link in lk.links.items()
        ],
    )
    return f'<div class="charts">{pts}{links}{joints}</div>'


def _force_sections(
    page: Page,
    lk: Any,
    m: Any,
    f: Any,
    x: tuple[np.ndarray, np.ndarray],
    xlabel: str,
    driver: str,
    u: Units,
    full: bool,
    velocity: float,
    k: float | None,
) -> None:
    raw, xs = x
    ok = np.ravel(f.ok)
    rows = []
    where = xlabel.split(" (")[0]
    xunit = xlabel.rsplit("(", 1)[-1].rstrip(")")

    def at(j: int) -> str:
        if xunit == "deg":  # an angle is named within the turn
            return f"{esc(where)} = {xs[j] % 360.0:.4g}°"
        return f"{esc(where)} = {xs[j]:.4g} {esc(xunit)}"

    for (a, b), F in f.pins.items():
        mag = np.where(ok, np.abs(np.ravel(F)), np.nan)
        if np.isfinite(mag).any():
            j = int(np.nanargmax(mag))
            rows.append(
                (
                    f"peak |F {a}→{b}|",
                    f"{esc(u.text('force', mag[j]))} at {at(j)}",
                    f"peak_F_{a}_{b}",
                )
            )
    for d, effort in f.driver.items():
        e = np.where(ok, np.ravel(effort), np.nan)
        kind = "torque" if d in m.angle_drivers else "force"
        if not np.isfinite(e).any():
            continue
        jmax, jmin = int(np.nanargmax(e)), int(np.nanargmin(e))
        for label, j, key in (("largest", jmax, "max"), ("smallest", jmin, "min")):
            rows.append(
                (
                    f"driver {d} {kind}, {label}",
                    f"{esc(u.text(kind, e[j]))} at {at(j)}",
                    f"driver_{d}_{key}",
                )
            )
    Fs = np.where(ok, np.abs(np.ravel(f.shaking_force)), np.nan)
    Ms = np.where(ok, np.abs(np.ravel(f.shaking_moment)), np.nan)
    if np.isfinite(Fs).any():
        js, jm = int(np.nanargmax(Fs)), int(np.nanargmax(Ms))
        rows.append(
            (
                "peak |shaking force|",
                f"{esc(u.text('force', Fs[js]))} at {at(js)}",
                "shaking_force_max",
            )
        )
        rows.append(
            (
                "peak |shaking moment|",
                f"{esc(u.text('torque', Ms[jm]))} at {at(jm)}",
                "shaking_moment_max",
            )
        )
    pins = {f"F {a}→{b}": F for (a, b), F in f.pins.items()}
    polars = "".join(
        c.to_svg(width=330, height=330)
        for c in pin_force_charts(
            pins, ok=ok, theta2=raw if xunit == "deg" else None, units=u, where=where
        )
    )
    page.section(
        "forces",
        "Pin forces and driver effort",
        page.table(rows) + f'<div class="charts">{polars}</div>',
    )
    effort = np.ravel(f.driver[driver])
    kind = "torque" if driver in m.angle_drivers else "force"
    fly = None
    if k is not None and full and ok.all():
        from ..flywheel import size_flywheel

        fly = size_flywheel(raw, effort, abs(velocity), k)
        body = page.table(
            [
                ("coefficient of fluctuation k", fmt(k), "k"),
                ("average torque", esc(u.text("torque", fly.torque_avg)), "torque_avg"),
                ("energy to swing ΔE", esc(u.text("energy", fly.delta_e)), "delta_e"),
                (
                    "flywheel inertia I = ΔE/(k ω²)",
                    esc(u.text("inertia", fly.inertia)),
                    "flywheel_inertia",
                ),
            ]
        )
    else:
        body = (
            '<p class="remark">A flywheel is sized (give k) over a full turn of an angle '
            "driver.</p>"
        )
    if kind == "torque":
        chart = torque_chart(raw, effort, flywheel=fly, ok=ok, units=u, name=driver, xlabel=xlabel)
        chart = replace(chart, title=chart.title.replace("input torque", f"driver {driver} torque"))
    else:
        y = np.where(ok, np.ravel(u.show("force", effort)), np.nan)
        chart = Chart(
            f"driver {driver} force",
            xlabel,
            u.axis(f"driver {driver} force", "force"),
            [Series(xs, y, driver, colour="#000", gid=f"driver_{driver}")],
            hlines=[(0.0, "", "#999")],
        )
    page.section("flywheel", "Driver effort and flywheel", body + chart.to_svg())


def _balancing_section(
    page: Page,
    lk: Any,
    f: Any,
    run: tuple[Any, Any, float],
    x: tuple[np.ndarray, np.ndarray],
    xlabel: str,
    u: Units,
    full: bool,
) -> None:
    """Shaking force and moment before and after counterweights (:func:`linkage_counterweights`).

    The balanced linkage (point-mass counterweights at each link's reach) is
    solved and its forces found by the same solver, at the same driver values.
    """
    from ..shaking import linkage_counterweights

    raw, xs = x
    values, rates, gravity, loads = run
    bal = linkage_counterweights(lk)
    after = m_after = None
    ok = np.ravel(f.ok)
    rows = [
        ("method", esc(bal.method), "balance_method"),
        ("what it does", esc(bal.what), "balance_what"),
    ]
    if bal.counterweights:
        balanced = bal.apply(lk)
        with np.errstate(all="ignore"):
            fb = balanced.forces(balanced.solve(values, velocity=rates), gravity=gravity, **loads)
        ok = ok & np.ravel(fb.ok)
        after = np.where(ok, np.ravel(fb.shaking_force), np.nan)
        m_after = np.where(ok, np.ravel(fb.shaking_moment), np.nan)
        for c in bal.counterweights:
            link = balanced.links[c.link]
            added = link.mass - lk.links[c.link].mass
            rows.append(
                (
                    f"counterweight on {esc(c.link)} (pivot {esc(c.pivot)})",
                    f"m·R = {esc(u.text('unbalance', abs(c.mR)))} at {c.angle_deg:.2f}° in the "
                    f"drawing; {esc(u.text('mass', added))} at R = "
                    f"{esc(u.text('length', abs(c.mR) / added if added else 0.0))}",
                    f"cw_{c.link}",
                )
            )
    before = np.where(ok, np.ravel(f.shaking_force), np.nan)
    m_before = np.where(ok, np.ravel(f.shaking_moment), np.nan)
    where = xlabel.split(" (")[0]
    unit = xlabel.rsplit("(", 1)[-1].rstrip(")")
    for label, values_, kind, key in (
        ("peak |shaking force| before", before, "force", "shaking_force_before"),
        ("peak |shaking force| after", after, "force", "shaking_force_after"),
        ("peak |shaking moment| before", m_before, "torque", "shaking_moment_before"),
        ("peak |shaking moment| after", m_after, "torque", "shaking_moment_after"),
    ):
        if values_ is not None and np.isfinite(values_).any():
            j = int(np.nanargmax(np.abs(values_)))
            at = f"{xs[j] % 360.0:.4g}°" if unit == "deg" else f"{xs[j]:.4g} {unit}"
            text = f"{u.text(kind, abs(values_[j]))} at {where} = {at}"
            ref = np.nanmax(np.abs(before if kind == "force" else m_before))
            if abs(values_[j]) <= 1e-9 * ref:  # balanced to rounding: no place to name
                text = f"0 (to rounding: {abs(values_[j]):.1e})"
            rows.append((label, esc(text), key))
    angle = unit == "deg"
    shaking = shaking_charts(
        before,
        after,
        moment_before=m_before if angle else None,
        moment_after=m_after if angle else None,
        theta=raw if angle else None,
        units=u,
        xlabel=xlabel,
        about="the origin",
        closed=full,
    )
    svgs = [shaking[0].to_svg(width=380, height=380)] + [c.to_svg() for c in shaking[1:]]
    page.section(
        "shaking",
        "Shaking force and balancing",
        page.table(rows)
        + '<p class="remark">Counterweights are point masses at each link\'s reach from its '
        "pivot (the farthest of its points); the balanced linkage is solved again at the same "
        "driver values. The shaking moment is taken about the drawing's origin.</p>"
        + f'<div class="charts">{"".join(svgs)}</div>',
    )
