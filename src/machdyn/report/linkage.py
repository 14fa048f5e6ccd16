"""The design report of a :class:`~machdyn.linkage.Linkage`, read through its topology view."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from itertools import combinations
from typing import Any

import numpy as np

from ..draw.chart import Chart, Series
from ..draw.engineering import pin_force_charts, shaking_charts, torque_chart
from ..draw.html import widget
from ..draw.kinematics import length_label
from ..draw.linkage import default_values, linkage_scene
from ..draw.scene import Scene
from .checks import (
    Check,
    RigidMotion,
    finite_differences,
    kennedy,
    kinetic_energy_rate,
    loop_closure,
    power_balance,
)
from .fourbar import _force_labels, _model_length_unit
from .page import Page, esc, fmt

__all__ = ["linkage_checks", "linkage_report"]

_GROUND = "ground"


def _title(lk: Any) -> str:
    count = len(lk.links)
    return f"linkage of {count} moving link{'s' if count != 1 else ''} ({', '.join(lk.links)})"


def linkage_checks(
    lk: Any, motion: Any, x: np.ndarray, xdot: float, forces: Any = None, gravity: float = 0.0
) -> list[Check]:
    """Self-checks of a linkage motion (and forces), computed apart from the solver.

    Velocities of the centres of mass are written here from each link's first
    point and ω (``v_G = v_p + jω(G − p)``), so the power balance tests the
    driver efforts against a kinetic energy not taken from the force assembler.
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
        checks.append(
            power_balance(p_ext, kinetic_energy_rate(bodies), ok & np.ravel(forces.ok), scale=p_abs)
        )
    return checks


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
) -> Page:
    """Build the report page of a linkage (see :func:`machdyn.report.report`)."""
    title = title or _title(lk)
    length_unit = length_unit or _model_length_unit(lk)
    unit = length_label(length_unit)
    fu, tu = _force_labels(lk, length_unit)
    try:
        mobility = lk.mobility()
    except Exception as err:  # a model error is the answer here
        mobility = f"not countable: {err}"
    if not lk.drivers:
        page = Page(title, f"{title}: has no driver, so it cannot be moved (mobility {mobility}).")
        page.section(
            "model",
            "The model as drawn",
            _model_tables(page, lk, unit) + widget(_drawing_as_given(lk, title)),
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
            _model_tables(page, lk, unit) + widget(_drawing_as_given(lk, title)),
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
            _model_tables(page, lk, unit) + widget(_drawing_as_given(lk, title)),
        )
        return page
    xs = np.degrees(x) if is_angle else x
    xunit = "deg" if is_angle else unit
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
        linkage_scene(lk, frames, title=title, closed=closed), length_unit=length_unit or ""
    )
    page.section("model", "The model and its drawing", _model_tables(page, lk, unit) + widget(s))
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
    angle_series = [
        Series(xs, np.where(assembled, np.degrees(np.ravel(m.theta[n_])), np.nan), f"θ {n_}")
        for n_, link in lk.links.items()
        if len(link.points) >= 2 and n_ != driver
    ]
    charts = [Chart("link angles", xlabel, "angle (deg)", angle_series)] if angle_series else []
    charts.append(
        Chart(
            "angular velocities",
            xlabel,
            "ω (rad/s)",
            [
                Series(xs, np.where(assembled, np.ravel(m.omega[n_]), np.nan), f"ω {n_}")
                for n_ in lk.links
                if n_ != driver
            ],
        )
    )
    charts.append(
        Chart(
            "angular accelerations",
            xlabel,
            "α (rad/s²)",
            [
                Series(xs, np.where(assembled, np.ravel(m.alpha[n_]), np.nan), f"α {n_}")
                for n_ in lk.links
                if n_ != driver
            ],
        )
    )
    page.section("kinematics", "Kinematics", "".join(c.to_svg(height=240) for c in charts))
    forces = None
    if any(link.mass > 0 or link.inertia > 0 for link in lk.links.values()):
        forces = lk.forces(m, gravity=gravity)
        _force_sections(page, lk, m, forces, xs, xlabel, driver, fu, tu, full, velocity, k)
    else:
        page.section(
            "forces",
            "Forces",
            '<p class="remark">No link has mass: give link masses '
            "(link(..., mass=, inertia=, cg=)) for pin forces and driver effort.</p>",
        )
    checks = linkage_checks(lk, m, x, velocity, forces, gravity)
    page.section(
        "selfcheck",
        "Self-check: independent checks on this machine",
        page.checks(checks) + '<p class="remark">Rigid-body fields of every link (the '
        "loops and their derivatives), five-point differences along the sweep, Kennedy's "
        "rule on centres found from the velocity fields, and the power balance of the "
        "driver efforts and springs against the kinetic energy.</p>",
    )
    if page.failed:
        page.headline = "SELF-CHECK FAILED — " + page.headline
    return page


def _model_tables(page: Page, lk: Any, unit: str) -> str:
    pts = page.grid(
        ("point", f"x ({unit})", f"y ({unit})", "on"),
        [
            [
                esc(p),
                fmt(z.real, 6),
                fmt(z.imag, 6),
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
        ("link", "points", "mass", "I_G"),
        [
            [esc(n), esc(", ".join(link.points)), fmt(link.mass), fmt(link.inertia)]
            for n, link in lk.links.items()
        ],
    )
    return f'<div class="charts">{pts}{links}{joints}</div>'


def _force_sections(
    page: Page,
    lk: Any,
    m: Any,
    f: Any,
    xs: np.ndarray,
    xlabel: str,
    driver: str,
    fu: str,
    tu: str,
    full: bool,
    velocity: float,
    k: float | None,
) -> None:
    ok = np.ravel(f.ok)
    rows = []
    where = xlabel.split(" (")[0]
    for (a, b), F in f.pins.items():
        mag = np.where(ok, np.abs(np.ravel(F)), np.nan)
        if np.isfinite(mag).any():
            j = int(np.nanargmax(mag))
            rows.append(
                (
                    f"peak |F {a}→{b}|",
                    f"{fmt(mag[j])} {esc(fu)} at {esc(where)} = {xs[j]:.4g}",
                    f"peak_F_{a}_{b}",
                )
            )
    for d, effort in f.driver.items():
        e = np.where(ok, np.ravel(effort), np.nan)
        kind = "torque" if d in m.angle_drivers else "force"
        uu = tu if kind == "torque" else fu
        jmax, jmin = int(np.nanargmax(e)), int(np.nanargmin(e))
        rows.append(
            (
                f"driver {d} {kind}, largest",
                f"{fmt(e[jmax])} {esc(uu)} at {esc(where)} = {xs[jmax]:.4g}",
                f"driver_{d}_max",
            )
        )
        rows.append(
            (
                f"driver {d} {kind}, smallest",
                f"{fmt(e[jmin])} {esc(uu)} at {esc(where)} = {xs[jmin]:.4g}",
                f"driver_{d}_min",
            )
        )
    Fs = np.where(ok, np.abs(np.ravel(f.shaking_force)), np.nan)
    Ms = np.where(ok, np.abs(np.ravel(f.shaking_moment)), np.nan)
    rows.append(("peak |shaking force|", f"{fmt(np.nanmax(Fs))} {esc(fu)}", "shaking_force_max"))
    rows.append(("peak |shaking moment|", f"{fmt(np.nanmax(Ms))} {esc(tu)}", "shaking_moment_max"))
    pins = {f"F {a}→{b}": F for (a, b), F in f.pins.items()}
    polars = "".join(
        c.to_svg(width=330, height=330) for c in pin_force_charts(pins, ok=ok, unit=fu)
    )
    page.section(
        "forces",
        "Pin forces and driver effort",
        page.table(rows) + f'<div class="charts">{polars}</div>',
    )
    effort = np.ravel(f.driver[driver])
    fly = None
    if k is not None and full and ok.all():
        from ..flywheel import size_flywheel

        fly = size_flywheel(np.radians(xs), effort, velocity, k)
        body = page.table(
            [
                ("coefficient of fluctuation k", fmt(k), "k"),
                ("average torque", f"{fmt(fly.torque_avg)} {esc(tu)}", "torque_avg"),
                ("energy to swing ΔE", fmt(fly.delta_e), "delta_e"),
                ("flywheel inertia I = ΔE/(k ω²)", fmt(fly.inertia), "flywheel_inertia"),
            ]
        )
    else:
        body = (
            '<p class="remark">A flywheel is sized (give k) over a full turn of an angle '
            "driver.</p>"
        )
    chart = torque_chart(np.radians(xs), effort, flywheel=fly, ok=ok, unit=tu)
    chart = Chart(
        chart.title.replace("input torque", f"driver {driver}"),
        xlabel,
        chart.ylabel.replace("input torque T12", f"driver {driver} effort"),
        chart.series,
        chart.bands,
        chart.hlines,
        chart.notes,
    )
    page.section("flywheel", "Driver effort and flywheel", body + chart.to_svg())
    shaking = shaking_charts(np.ravel(f.shaking_force), force_unit=fu, torque_unit=tu)
    page.section("shaking", "Shaking force", shaking[0].to_svg(width=380, height=380))
