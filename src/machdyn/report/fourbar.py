"""The design report of a four-bar: every number from the FourBar API, and the self-checks.

Numbers are shown in the model's units (:class:`machdyn.draw.units.Units`:
``FourBar.units`` of a machine file, or labels that say "model units").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..draw.build import describe, fourbar_scene
from ..draw.engineering import pin_force_charts, shaking_charts, torque_chart, transmission_chart
from ..draw.html import widget
from ..draw.kinematics import kinematics_charts
from ..draw.units import Units
from ..fourbar import FourBar, FourBarMotion
from .checks import (
    Body,
    Check,
    RigidMotion,
    acute,
    angles,
    equilibrium,
    finite_differences,
    flywheel_energy,
    kennedy,
    loop_closure,
    momentum,
    momentum_differences,
    power_balance,
    power_of_loads,
)
from .page import Page, esc, fmt

__all__ = ["fourbar_checks", "fourbar_report", "fourbar_sections", "fourbar_sweep"]


def fourbar_sweep(fb: FourBar, form: int, n: int) -> np.ndarray:
    """The report's input angles: a uniform full turn, or the rocker's range less 2 % at each end.

    (Five-point differences need uniform steps; next to a rocker's toggle the
    rates grow without bound and no difference formula converges, so the
    last 2 % are left out of the sweep, not out of the answers.)
    """
    rng = fb.input_range(form)
    if rng.full_turn:
        return np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    margin = 0.02 * (rng.hi - rng.lo)
    return np.linspace(rng.lo + margin, rng.hi - margin, n)


def _along(origin: np.ndarray, toward: np.ndarray, c: complex) -> np.ndarray:
    """A point given in a link frame (origin, x toward ``toward``) in the world."""
    e = (toward - origin) / np.abs(toward - origin)
    return origin + complex(c) * e


def _applied(
    bodies: dict[int, Body],
    place: dict[int, Any],
    forces: Any,
    torques: Any,
    one: np.ndarray,
    length_unit: str | None = None,
    guided: tuple[int, ...] = (),
) -> None:
    """The applied point loads (at points in their link's frame, ``place``) and torques.

    Read as the dynamics read them (triples or ``PointLoad``, quantities converted);
    torques on a ``guided`` link (a slider-crank's block) are carried by its guide.
    """
    from ..dynamics import _point_loads, _torques, unit_system

    units = unit_system(length_unit)
    for load in _point_loads(forces, units):
        at = place[load.link](load.point) * one
        bodies[load.link].load(np.ravel(load.force) * one + 0j, at, "external")
    for link, torque in _torques(torques, units):
        if link not in guided:
            bodies[link].torque(np.ravel(torque) * one, "external")


def _rigid(p: Any, vp: Any, ap: Any, w: Any, al: Any, q: Any) -> tuple[Any, Any]:
    """Velocity and acceleration of point ``q`` of a body through ``p`` (ω, α)."""
    return vp + 1j * w * (q - p), ap + (1j * al - w * w) * (q - p)


def fourbar_checks(
    fb: FourBar,
    motion: FourBarMotion,
    omega2: float,
    forces: Any = None,
    mass: Any = None,
    inertia: Any = None,
    cg: Any = None,
    gravity: float = 0.0,
    load_torque4: Any = 0.0,
    external_forces: Any = (),
    external_torques: Any = (),
) -> list[Check]:
    """Self-checks of a four-bar motion (and forces), computed apart from the solver.

    Point velocities and accelerations are written here from the link rates
    (``v_A = jω2·A``, ``v_B = jω4·(B − O4)``, ...), so the rigid-body, finite
    difference and Kennedy checks test the solver's ω and α against the
    positions; the link angles are tested against the pin positions; with
    forces, each link's equilibrium tests the pin forces and ``T12``, the power
    balance ``T12`` against the kinetic energy written from the same motion,
    and the momentum balance the shaking force and moment.
    """
    th2 = np.ravel(motion.theta2)
    ok = np.ravel(motion.ok)
    w2 = np.ravel(motion.omega2) * np.ones_like(th2)
    a2 = np.ravel(motion.alpha2) * np.ones_like(th2)
    w3, w4 = np.ravel(motion.omega3), np.ravel(motion.omega4)
    a3, a4 = np.ravel(motion.alpha3), np.ravel(motion.alpha4)
    A, B = np.ravel(motion.A), np.ravel(motion.B)
    O4 = complex(fb.r1)
    zero = np.zeros_like(A)
    vA, aA = 1j * w2 * A, (1j * a2 - w2 * w2) * A
    vB, aB = 1j * w4 * (B - O4), (1j * a4 - w4 * w4) * (B - O4)
    points = {
        "O2": (zero, zero, zero),
        "O4": (zero + O4, zero, zero),
        "A": (A, vA, aA),
        "B": (B, vB, aB),
    }
    link3 = ("A", "B")
    if motion.coupler is not None:
        points["P"] = (
            np.ravel(motion.coupler),
            np.ravel(motion.coupler_velocity),
            np.ravel(motion.coupler_acceleration),
        )
        link3 = ("A", "B", "P")
    zeros = np.zeros(th2.shape)
    links = {
        "1": (("O2", "O4"), zeros, zeros),
        "2": (("O2", "A"), w2, a2),
        "3": (link3, w3, a3),
        "4": (("O4", "B"), w4, a4),
    }
    pins = {("1", "2"): "O2", ("2", "3"): "A", ("3", "4"): "B", ("1", "4"): "O4"}
    rigid = RigidMotion(th2, float(omega2), points, links, ok, pins)
    assembled = np.ravel(motion.assembled)
    checks = [*loop_closure(rigid), *finite_differences(rigid), kennedy(rigid)]
    checks.append(
        angles(
            [
                (motion.theta3, np.angle(B - A)),
                (motion.theta4, np.angle(B - O4)),
                (motion.mu, acute(B - A, B - O4)),
            ],
            assembled,
        )
    )
    if forces is None:
        return checks
    frames = {2: (zero, A), 3: (A, B), 4: (zero + O4, B)}
    origin = {
        2: (zero, zero, zero, w2, a2),
        3: (A, vA, aA, w3, a3),
        4: (zero + O4, zero, zero, w4, a4),
    }
    f = forces
    bodies = {}
    for k in (2, 3, 4):
        p, vp, ap, w, al = origin[k]
        G = _along(*frames[k], cg[k - 2])
        vG, aG = _rigid(p, vp, ap, w, al, G)
        b = Body(str(k), float(mass[k - 2]), float(inertia[k - 2]), G, vG, aG, w, al)
        if gravity and b.mass:
            b.load(np.full(G.shape, -1j * b.mass * gravity), G, "external")
        bodies[k] = b
    F12, F32, F43, F14 = (np.ravel(x) for x in (f.F12, f.F32, f.F43, f.F14))
    bodies[2].load(F12, zero, "ground")
    bodies[2].load(F32, A, "joint")
    bodies[2].torque(np.ravel(f.T12), "ground")
    bodies[3].load(-F32, A, "joint")
    bodies[3].load(F43, B, "joint")
    bodies[4].load(-F43, B, "joint")
    bodies[4].load(F14, zero + O4, "ground")
    bodies[4].torque(np.ravel(load_torque4) * np.ones(th2.shape), "external")
    place = {k: (lambda z, k=k: _along(*frames[k], z)) for k in (2, 3, 4)}
    _applied(bodies, place, external_forces, external_torques, np.ones(th2.shape), fb.length_unit)
    good = ok & np.ravel(f.ok)
    power, dke, scale = power_of_loads(list(bodies.values()))
    size = rigid.size
    checks.append(power_balance(power, dke, good, scale=scale))
    checks.append(equilibrium(list(bodies.values()), good, size))
    checks.append(momentum(list(bodies.values()), f.shaking_force, f.shaking_moment, good, size))
    checks.append(
        momentum_differences(
            list(bodies.values()), f.shaking_force, f.shaking_moment, th2, omega2, good, size
        )
    )
    return checks


@dataclass
class _Case:
    """One four-bar being reported: the model, its motion and what it was given."""

    fb: FourBar
    form: int
    omega2: float
    th: np.ndarray
    m: FourBarMotion
    u: Units
    mass: Any
    inertia: Any
    cg: Any
    gravity: float
    load_torque4: Any
    external_forces: Any
    external_torques: Any
    k: float | None
    where: str = "θ2"
    placement: tuple[complex, float] | None = None
    branch: int | None = None

    def at(self, j: int) -> str:
        return f"{self.where} = {np.degrees(self.th[j]):.1f}°"

    @property
    def turn(self) -> complex:
        """e^{jθ1}: the four-bar's own frame (x along O2 → O4) turned into the plane's."""
        return 1.0 + 0j if self.placement is None else complex(np.exp(1j * self.placement[1]))


def fourbar_report(fb: FourBar, *, title: str | None = None, **options: Any) -> Page:
    """Build the report page of a four-bar (see :func:`machdyn.report.report`)."""
    page = Page(title or describe(fb), "")
    page.headline = fourbar_sections(page, fb, **options)
    return page.finished()


def fourbar_sections(
    page: Page,
    fb: FourBar,
    *,
    form: int = 1,
    omega2: float = 1.0,
    n: int = 360,
    mass: Any = None,
    inertia: Any = None,
    cg: Any = None,
    gravity: float = 0.0,
    load_torque4: Any = 0.0,
    external_forces: Any = (),
    external_torques: Any = (),
    k: float | None = None,
    mu_limit_deg: float = 40.0,
    motion: FourBarMotion | None = None,
    units: Any = None,
    length_unit: str | None = None,
    placement: tuple[complex, float] | None = None,
    branch: int | None = None,
) -> str:
    """Add a four-bar's sections to ``page``; returns its first line.

    ``placement`` ``(O2, theta1)`` places the four-bar in the plane (a synthesis
    result: global = O2 + e^{jθ1}·local): the drawing and the force directions are
    the plane's; θ2–θ4 stay measured from O2 → O4 and the loads are given as
    :meth:`FourBar.dynamics` takes them (its own frame). ``branch`` (a GRCR or
    GRRC, as :meth:`FourBar.solve` takes it) picks the half of the form's circuit.
    """
    th = fourbar_sweep(fb, form, n)
    m = motion if motion is not None else fb.solve(th, omega2, form=form, branch=branch)
    th = np.ravel(m.theta2)
    u = _units(fb, units, length_unit)
    if mass is not None:
        inertia = (0.0, 0.0, 0.0) if inertia is None else inertia
        cg = (0.0, 0.0, 0.0) if cg is None else cg
    case = _Case(
        fb,
        form,
        float(omega2),
        th,
        m,
        u,
        mass,
        inertia,
        cg,
        float(gravity or 0.0),
        load_torque4,
        external_forces,
        external_torques,
        k,
        placement=None if placement is None else (complex(placement[0]), float(placement[1])),
        branch=branch,
    )
    rng = fb.input_range(form)
    kind = "crank" if rng.full_turn else "rocker"
    span = (
        "the full turn"
        if rng.full_turn
        else f"θ2 from {np.degrees(rng.lo):.2f}° to {np.degrees(rng.hi):.2f}°"
    )
    name = _name(fb, u)
    headline = (
        f"{name}: assembles over {span} of link 2 (a {kind}) in form {form}; "
        f"mobility 1; Barker class {fb.barker_class}."
    )
    _model_section(page, case, rng)
    _class_sections(page, case, kind, span, mu_limit_deg)
    _kinematics_section(page, case)
    forces = None
    if mass is not None:
        forces = fb.dynamics(
            th,
            omega2,
            mass=mass,
            inertia=inertia,
            cg=cg,
            form=form,
            branch=branch,
            gravity=case.gravity,
            load_torque4=load_torque4,
            external_forces=external_forces,
            external_torques=external_torques,
        )
        fly = _force_sections(page, case, forces)
    else:
        fly = None
        page.section(
            "forces",
            "Forces",
            '<p class="remark">No mass properties were given: '
            "pass mass=(m2, m3, m4), inertia=(IG2, IG3, IG4), cg=(c2, c3, c4) for "
            "pin forces, input torque, shaking, flywheel and balancing.</p>",
        )
    checks = fourbar_checks(
        fb,
        m,
        omega2,
        forces,
        mass,
        inertia,
        cg,
        case.gravity,
        load_torque4,
        external_forces,
        external_torques,
    )
    if fly is not None:
        checks.append(flywheel_energy(fly.theta, fly.torque, fly))
    page.section(
        "selfcheck",
        "Self-check: independent checks on this machine",
        page.checks(checks) + '<p class="remark">Each check recomputes an identity '
        "from the solved numbers without the solver's code: rigid-body fields (the vector "
        "loop and its derivatives), five-point differences along the sweep, Kennedy's rule "
        "on centres found from the velocity fields, the link angles against the pins; with "
        "forces, each link's equilibrium, the power balance against the kinetic energy and "
        "the momentum balance of the whole machine.</p>",
    )
    return headline


def _units(model: Any, units: Any, length_unit: str | None) -> Units:
    """The report's units: given, the model's, or a length unit named for a unit-free model."""
    if units is not None:
        return Units.of(units)
    u = Units.of(model)
    if u.free and length_unit:
        from ..units import UnitSystem

        return Units(UnitSystem(length=length_unit))
    return u


def _name(fb: FourBar, u: Units) -> str:
    name = describe(fb)
    if not u.free and not fb.length_unit:
        lengths = "-".join(f"{v:g}" for v in fb.lengths)
        name = name.replace(lengths, f"{lengths} {u.unit('length')}", 1)
    return name


def _model_section(page: Page, c: _Case, rng: Any) -> None:
    fb, u = c.fb, c.u
    rows = [(f"r{i}", u.text("length", v, 6), f"r{i}") for i, v in enumerate(fb.lengths, 1)]
    if fb.coupler is not None:
        rows.append(("coupler point p", u.text("length", fb.coupler[0], 6), "p"))
        rows.append(("coupler point δ", fmt(np.degrees(fb.coupler[1]), 6) + "°", "delta_deg"))
    rows.append(("form (circuit)", str(c.form), "form"))
    if c.placement is not None:
        rows.append(("placed: O2", _xy(u, c.placement[0]), "placed_O2"))
        rows.append(("placed: θ1", fmt(np.degrees(c.placement[1]), 6) + "°", "placed_theta1"))
    rows.append(("input speed ω2", u.text("angular_velocity", c.omega2), "omega2"))
    curve = None
    if fb.coupler is not None:
        pts = fb.coupler_curve(c.form, 360).points
        curve = np.append(pts, pts[:1]) if (rng.full_turn or fb.form_rule == "phi34") else pts
    n = c.th.size
    frames = fb.solve(
        np.linspace(c.th[0], c.th[-1], 120) if not rng.full_turn else c.th[:: max(1, n // 120)],
        c.omega2,
        form=c.form,
        branch=c.branch,
    )
    s = fourbar_scene(fb, frames, coupler_curve=curve, closed=rng.full_turn)
    placed = ""
    if c.placement is not None:
        s = _in_plane(s, *c.placement)
        placed = (
            " Placed in the plane: global = O2 + e^(jθ1)·local, forces in the plane's x, y;"
            " θ2–θ4 from O2 → O4."
        )
    page.section(
        "model",
        "The model and its drawing",
        page.table(rows)
        + widget(s, fps=30)
        + '<p class="remark">The drawing plays the solved poses (lengths in '
        f"{esc(u.unit('length'))}, y up); the slider picks a pose.{placed}</p>",
    )


def _in_plane(s: Any, O2: complex, theta1: float) -> Any:
    """A four-bar scene (own frame) moved to its place: z → O2 + e^{jθ1} z."""
    from dataclasses import replace

    turn = complex(np.exp(1j * theta1))
    curves = tuple(replace(cv, points=O2 + turn * np.asarray(cv.points)) for cv in s.curves)
    angles = {k: v + theta1 for k, v in s.angles.items()}
    return replace(s, xy=O2 + turn * s.xy, curves=curves, angles=angles)


def _class_sections(page: Page, c: _Case, kind: str, span: str, mu_limit_deg: float) -> None:
    fb = c.fb
    L = sorted(fb.lengths)
    s_l, p_q = L[0] + L[3], L[1] + L[2]
    grashof = {  # classify's condition: s + l = p + q to its tolerance, as Barker's table
        "grashof": "Grashof",
        "change point": "special Grashof (change point)",
        "non-grashof": "non-Grashof",
    }[fb.classification.condition]
    cranks = ", ".join(f"link {n}" for n in fb.cranks) or "none"
    page.section(
        "class",
        "Mobility and class",
        page.table(
            [
                ("mobility (Kutzbach–Gruebler)", "M = 3(4 − 1) − 2·4 = 1", "mobility"),
                (
                    "Grashof condition",
                    f"s + l = {c.u.text('length', s_l)} vs p + q = {c.u.text('length', p_q)}: "
                    f"{grashof}",
                    "grashof",
                ),
                ("Barker class", esc(fb.barker_class), "barker_class"),
                ("links that turn fully", esc(cranks), "cranks"),
            ]
        ),
    )
    trows = [
        [
            f"{np.degrees(t.theta2):.3f}",
            f"{t.links[0]} and {t.links[1]}",
            esc(t.kind),
            str(t.branch),
        ]
        for t in fb.toggles()
    ]
    rule = "φ34 = θ2, GRCR/GRRC" if fb.form_rule == "phi34" else "φ12"
    body = page.table(
        [
            ("input link", f"a {kind}", "input_kind"),
            ("input range", esc(span), "input_range"),
            (
                "circuits (forms)",
                f"2 (form 1 and form 2; the form is the sign of {rule})",
                "circuits",
            ),
        ]
    )
    body += (
        page.grid(("θ2 (deg)", "links aligned", "kind", "branch"), trows)
        if trows
        else '<p class="remark">No toggle positions.</p>'
    )
    page.section("toggles", "Circuits, toggles and input range", body)
    erows = []
    for name, e in fb.extrema(c.form).items():
        if e.full_turn:
            erows.append([esc(name), "full turn", "–", "–", "–"])
        else:
            erows.append(
                [
                    esc(name),
                    page.span(f"{name}_min_deg", f"{np.degrees(e.min):.3f}"),
                    f"{np.degrees(e.theta2_at_min):.2f}",
                    page.span(f"{name}_max_deg", f"{np.degrees(e.max):.3f}"),
                    f"{np.degrees(e.theta2_at_max):.2f}",
                ]
            )
    ta = fb.transmission_angle(c.form)
    met = "met" if np.degrees(ta.min) >= mu_limit_deg else "NOT met"
    body = page.table(
        [
            (
                "minimum transmission angle μ",
                f"{np.degrees(ta.min):.3f}° at θ2 = {np.degrees(ta.theta2_at_min):.2f}°",
                "mu_min_deg",
            ),
            ("design limit", f"{mu_limit_deg:g}° ({met})", "mu_limit"),
        ]
    )
    body += page.grid(("angle", "min (deg)", "at θ2 (deg)", "max (deg)", "at θ2 (deg)"), erows)
    body += transmission_chart(
        c.m.theta2, c.m.mu, ok=c.m.assembled, limit_deg=mu_limit_deg
    ).to_svg()
    page.section("angles", "Fundamental angles φij and transmission angle μ", body)
    ma = fb.mechanical_advantage(c.th, form=c.form, branch=c.branch)
    finite = np.isfinite(ma)
    mag = np.abs(np.where(finite, ma, np.nan))
    if finite.any():
        kmin, kmax = int(np.nanargmin(mag)), int(np.nanargmax(mag))
        body = page.table(
            [
                ("|MA| smallest (r_in = r_out)", f"{fmt(mag[kmin])} at {c.at(kmin)}", "ma_min"),
                ("|MA| largest", f"{fmt(mag[kmax])} at {c.at(kmax)}", "ma_max"),
            ]
        ) + (
            '<p class="remark">MA = (r_in ω2)/(r_out ω4), by the power identity; infinite at '
            "a toggle of links 2 and 3.</p>"
        )
    else:
        body = '<p class="remark">No finite mechanical advantage in the sweep.</p>'
    page.section("ma", "Mechanical advantage", body)


def _kinematics_section(page: Page, c: _Case) -> None:
    rows = []
    for name, kind in (
        ("omega3", "angular_velocity"),
        ("omega4", "angular_velocity"),
        ("alpha3", "angular_acceleration"),
        ("alpha4", "angular_acceleration"),
    ):
        v = np.where(c.m.ok, getattr(c.m, name), np.nan)
        if np.isfinite(v).any():
            j = int(np.nanargmax(np.abs(v)))
            rows.append(
                (f"peak |{name}|", f"{c.u.text(kind, abs(v[j]))} at {c.at(j)}", f"peak_{name}")
            )
    charts = "".join(ch.to_svg(height=240) for ch in kinematics_charts(c.m, units=c.u))
    page.section("kinematics", "Kinematics", page.table(rows) + charts)


def _force_sections(page: Page, c: _Case, f: Any) -> Any:
    """Pin forces, torque, flywheel and balancing; returns the flywheel (or None)."""
    u, th = c.u, c.th
    ok = np.ravel(f.ok)
    rows = []
    pins = {k: c.turn * getattr(f, k) for k in ("F12", "F32", "F43", "F14")}  # the plane's
    for name, F in pins.items():
        mag = np.where(ok, np.abs(F), np.nan)
        j = int(np.nanargmax(mag))
        rows.append((f"peak |{name}|", f"{u.text('force', mag[j])} at {c.at(j)}", f"peak_{name}"))
    T = np.where(ok, f.T12, np.nan)
    jmax, jmin = int(np.nanargmax(T)), int(np.nanargmin(T))
    rows.append(("T12 largest", f"{u.text('torque', T[jmax])} at {c.at(jmax)}", "T12_max"))
    rows.append(("T12 smallest", f"{u.text('torque', T[jmin])} at {c.at(jmin)}", "T12_min"))
    Fs = np.where(ok, np.abs(f.shaking_force), np.nan)
    Ms = np.where(ok, np.abs(f.shaking_moment), np.nan)
    js, jm = int(np.nanargmax(Fs)), int(np.nanargmax(Ms))
    rows.append(
        ("peak |shaking force|", f"{u.text('force', Fs[js])} at {c.at(js)}", "shaking_force_max")
    )
    rows.append(
        ("peak |shaking moment|", f"{u.text('torque', Ms[jm])} at {c.at(jm)}", "shaking_moment_max")
    )
    props = page.grid(
        ("link", "mass", "I_G", "centre of mass (link frame)"),
        [
            [
                str(i + 2),
                u.text("mass", c.mass[i]),
                u.text("inertia", c.inertia[i]),
                _xy(u, complex(c.cg[i])),
            ]
            for i in range(3)
        ],
    )
    polars = "".join(
        ch.to_svg(width=330, height=330) for ch in pin_force_charts(pins, ok=ok, theta2=th, units=u)
    )
    page.section(
        "forces",
        "Pin forces and input torque",
        props + page.table(rows) + f'<div class="charts">{polars}</div>',
    )
    fly = None
    if c.k is not None and np.all(ok) and c.fb.input_range(c.form).full_turn:
        from ..flywheel import size_flywheel

        fly = size_flywheel(th, f.T12, abs(c.omega2), c.k)
    torque = torque_chart(th, f.T12, flywheel=fly, ok=ok, units=u).to_svg()
    if fly is not None:
        body = flywheel_table(page, fly, u)
    elif c.k is None:
        body = '<p class="remark">Give k (coefficient of fluctuation) to size a flywheel.</p>'
    else:
        body = '<p class="remark">A flywheel is sized over a crank\'s full turn.</p>'
    page.section("flywheel", "Input torque and flywheel", body + torque)
    _balancing_section(page, c, f)
    return fly


def flywheel_table(page: Page, fly: Any, u: Units) -> str:
    """The flywheel's numbers: k, T_avg, ΔE, I (in the model's units)."""
    return page.table(
        [
            ("coefficient of fluctuation k", fmt(fly.k), "k"),
            ("average torque", u.text("torque", fly.torque_avg), "torque_avg"),
            ("energy to swing ΔE", u.text("energy", fly.delta_e), "delta_e"),
            ("flywheel inertia I = ΔE/(k ω²)", u.text("inertia", fly.inertia), "flywheel_inertia"),
        ]
    )


def _xy(u: Units, z: complex) -> str:
    x, y = (float(u.show("length", v)) for v in (z.real, z.imag))
    unit = u.unit("length")
    return f"({fmt(x)}, {fmt(y)}) {esc(unit)}"


def _balancing_section(page: Page, c: _Case, f: Any) -> None:
    from ..shaking import fourbar_counterweights

    u = c.u
    cw = fourbar_counterweights(c.fb, c.mass, c.cg)
    mc = (max(c.mass[0], 1e-12), max(c.mass[2], 1e-12))
    mass_b, inertia_b, cg_b = cw.apply(c.mass, c.inertia, c.cg, mc)
    fb_bal = c.fb.dynamics(
        c.th,
        c.omega2,
        mass=mass_b,
        inertia=inertia_b,
        cg=cg_b,
        form=c.form,
        branch=c.branch,
        gravity=c.gravity,
        load_torque4=c.load_torque4,
        external_forces=c.external_forces,
        external_torques=c.external_torques,
    )
    shaking = shaking_charts(
        c.turn * f.shaking_force,
        c.turn * fb_bal.shaking_force,
        moment_before=f.shaking_moment,
        moment_after=fb_bal.shaking_moment,
        theta=c.th,
        units=u,
        closed=bool(c.fb.input_range(c.form).full_turn),
    )
    after = np.nanmax(np.abs(fb_bal.shaking_force))
    body = page.table(
        [
            (
                "counterweight m·R on link 2",
                f"{u.text('unbalance', abs(cw.mR2))} at {np.degrees(np.angle(cw.mR2)):.2f}° "
                "(link frame)",
                "mR2",
            ),
            (
                "counterweight m·R on link 4",
                f"{u.text('unbalance', abs(cw.mR4))} at {np.degrees(np.angle(cw.mR4)):.2f}° "
                "(link frame)",
                "mR4",
            ),
            ("peak |shaking force| after", u.text("force", after), "shaking_force_after"),
        ]
    ) + (
        '<p class="remark">Counterweights of the links\' own masses (m2, m4) at R = mR/m; the '
        "coupler is unchanged (Norton §12.2).</p>"
    )
    charts = shaking[0].to_svg(width=380, height=380) + "".join(ch.to_svg() for ch in shaking[1:])
    page.section(
        "balancing", "Shaking force and balancing", body + f'<div class="charts">{charts}</div>'
    )
