"""The design report of a four-bar: every number from the FourBar API, and the self-checks."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..draw.build import describe, fourbar_scene
from ..draw.engineering import (
    force_units,
    pin_force_charts,
    shaking_charts,
    torque_chart,
    transmission_chart,
)
from ..draw.html import widget
from ..draw.kinematics import kinematics_charts, length_label
from ..fourbar import FourBar, FourBarMotion
from .checks import (
    Check,
    RigidMotion,
    finite_differences,
    kennedy,
    kinetic_energy_rate,
    loop_closure,
    power_balance,
)
from .page import Page, esc, fmt

__all__ = ["fourbar_checks", "fourbar_report", "fourbar_sweep"]

_NAMES = {2: "input", 3: "coupler", 4: "output"}


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


def _cg_world(origin: np.ndarray, toward: np.ndarray, c: complex) -> np.ndarray:
    e = (toward - origin) / np.abs(toward - origin)
    return origin + c * e


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
) -> list[Check]:
    """Self-checks of a four-bar motion (and forces), computed apart from the solver.

    Point velocities and accelerations are written here from the link rates
    (``v_A = jω2·A``, ``v_B = jω4·(B − O4)``, ...), so the rigid-body, finite
    difference and Kennedy checks test the solver's ω and α against the
    positions; the power balance tests ``T12`` against the kinetic energy
    written from the same motion.
    """
    th2 = np.ravel(motion.theta2)
    ok = np.ravel(motion.ok)
    w2, a2 = (
        np.ravel(motion.omega2) * np.ones_like(th2),
        np.ravel(motion.alpha2) * np.ones_like(th2),
    )
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
    checks = [*loop_closure(rigid), *finite_differences(rigid), kennedy(rigid)]
    if forces is not None:
        G = [
            _cg_world(zero, A, complex(cg[0])),
            _cg_world(A, B, complex(cg[1])),
            _cg_world(zero + O4, B, complex(cg[2])),
        ]
        origin = [
            (zero, zero, zero, w2, a2),
            (A, vA, aA, w3, a3),
            (zero + O4, zero, zero, w4, a4),
        ]
        bodies, p_grav = {}, 0.0
        for k, (g, (p, vp, ap, w, al)) in enumerate(zip(G, origin, strict=True)):
            vg = vp + 1j * w * (g - p)
            ag = ap + (1j * al - w * w) * (g - p)
            bodies[str(k + 2)] = (float(mass[k]), float(inertia[k]), vg, ag, w, al)
            p_grav = p_grav - float(mass[k]) * gravity * vg.imag
        dke = kinetic_energy_rate(bodies)
        p_in = np.ravel(forces.T12) * w2 + np.ravel(load_torque4) * w4 + p_grav
        checks.append(power_balance(p_in, dke, ok & np.ravel(forces.ok)))
    return checks


def _model_length_unit(model: Any) -> str | None:
    """The model's length unit: its unit system's (machine files), else its quantities'."""
    system = getattr(model, "units", None)
    return getattr(system, "length", None) or getattr(model, "length_unit", None)


def _force_labels(model: Any, length_unit: str | None) -> tuple[str, str]:
    """Force and torque units: the model's unit system's where it has one."""
    system = getattr(model, "units", None)
    force, torque = getattr(system, "force", None), getattr(system, "torque", None)
    if force and torque:
        return str(force), str(torque)
    return force_units(length_unit)


def _where(th: np.ndarray, k: int) -> str:
    return f"{np.degrees(th[k]):.1f}°"


def fourbar_report(
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
    k: float | None = None,
    mu_limit_deg: float = 40.0,
    title: str | None = None,
    motion: FourBarMotion | None = None,
    length_unit: str | None = None,
) -> Page:
    """Build the report page of a four-bar (see :func:`machdyn.report.report`)."""
    th = fourbar_sweep(fb, form, n)
    m = motion if motion is not None else fb.solve(th, omega2, form=form)
    th = np.ravel(m.theta2)
    rng = fb.input_range(form)
    length_unit = length_unit or _model_length_unit(fb)
    unit = length_label(length_unit)
    fu, tu = _force_labels(fb, length_unit)
    kind = {True: "crank", False: "rocker"}[rng.full_turn]
    span = (
        "the full turn"
        if rng.full_turn
        else (f"θ2 from {np.degrees(rng.lo):.2f}° to {np.degrees(rng.hi):.2f}°")
    )
    page = Page(
        title or describe(fb),
        f"{describe(fb)}: assembles over {span} of link 2 (a {kind}) in form {form}; "
        f"mobility 1; Barker class {fb.barker_class}.",
    )
    # -- the model and its drawing
    rows = [(f"r{i}", fmt(v, 6) + f" {esc(unit)}", f"r{i}") for i, v in enumerate(fb.lengths, 1)]
    if fb.coupler is not None:
        rows.append(("coupler point p", fmt(fb.coupler[0], 6) + f" {esc(unit)}", "p"))
        rows.append(("coupler point δ", fmt(np.degrees(fb.coupler[1]), 6) + " deg", "delta_deg"))
    rows.append(("form (circuit)", str(form), "form"))
    rows.append(("input speed ω2", fmt(omega2) + " rad/s", "omega2"))
    curve = None
    if fb.coupler is not None:
        c = fb.coupler_curve(form, 360).points
        curve = np.append(c, c[:1]) if (rng.full_turn or fb.form_rule == "phi34") else c
    frames = fb.solve(
        np.linspace(th[0], th[-1], 120) if not rng.full_turn else th[:: max(1, n // 120)],
        omega2,
        form=form,
    )
    s = fourbar_scene(fb, frames, coupler_curve=curve, closed=rng.full_turn)
    page.section(
        "model",
        "The model and its drawing",
        page.table(rows)
        + widget(s, fps=30)
        + '<p class="remark">The drawing plays the solved poses (lengths in '
        f"{esc(unit)}, y up); the slider picks a pose.</p>",
    )
    # -- classification
    L = sorted(fb.lengths)
    s_l, p_q = L[0] + L[3], L[1] + L[2]
    grashof = (
        "Grashof"
        if s_l < p_q
        else ("special Grashof (change point)" if s_l == p_q else "non-Grashof")
    )
    cranks = ", ".join(f"link {c}" for c in fb.cranks) or "none"
    page.section(
        "class",
        "Mobility and class",
        page.table(
            [
                ("mobility (Kutzbach–Gruebler)", "M = 3(4 − 1) − 2·4 = 1", "mobility"),
                (
                    "Grashof condition",
                    f"s + l = {fmt(s_l)} vs p + q = {fmt(p_q)}: {grashof}",
                    "grashof",
                ),
                ("Barker class", esc(fb.barker_class), "barker_class"),
                ("links that turn fully", esc(cranks), "cranks"),
            ]
        ),
    )
    # -- circuits, toggles, range
    trows = [
        [
            f"{np.degrees(t.theta2):.3f}",
            f"{t.links[0]} and {t.links[1]}",
            esc(t.kind),
            str(t.branch),
        ]
        for t in fb.toggles()
    ]
    body = page.table(
        [
            ("input link", f"a {kind}", "input_kind"),
            ("input range", esc(span), "input_range"),
            (
                "circuits (forms)",
                "2 (form 1 and form 2; the form is the sign of "
                + ("φ34 = θ2, GRCR/GRRC" if fb.form_rule == "phi34" else "φ12")
                + ")",
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
    # -- φ and μ extremes
    ex = fb.extrema(form)
    erows = []
    for name, e in ex.items():
        if e.full_turn:
            erows.append([esc(name), "full turn", "–", "–", "–"])
        else:
            erows.append(
                [
                    esc(name),
                    f'<span data-key="{name}_min_deg">{np.degrees(e.min):.3f}</span>',
                    f"{np.degrees(e.theta2_at_min):.2f}",
                    f'<span data-key="{name}_max_deg">{np.degrees(e.max):.3f}</span>',
                    f"{np.degrees(e.theta2_at_max):.2f}",
                ]
            )
    ta = fb.transmission_angle(form)
    body = page.table(
        [
            (
                "minimum transmission angle μ",
                f"{np.degrees(ta.min):.3f}° at θ2 = {np.degrees(ta.theta2_at_min):.2f}°",
                "mu_min_deg",
            ),
            (
                "design limit",
                f"{mu_limit_deg:g}° ("
                + ("met" if np.degrees(ta.min) >= mu_limit_deg else "NOT met")
                + ")",
                "mu_limit",
            ),
        ]
    )
    body += page.grid(("angle", "min (deg)", "at θ2 (deg)", "max (deg)", "at θ2 (deg)"), erows)
    body += transmission_chart(m.theta2, m.mu, ok=m.assembled, limit_deg=mu_limit_deg).to_svg()
    page.section("angles", "Fundamental angles φij and transmission angle μ", body)
    # -- mechanical advantage
    ma = fb.mechanical_advantage(th, form=form)
    finite = np.isfinite(ma)
    mag = np.abs(np.where(finite, ma, np.nan))
    if finite.any():
        kmin, kmax = int(np.nanargmin(mag)), int(np.nanargmax(mag))
        body = (
            page.table(
                [
                    (
                        "|MA| smallest (r_in = r_out)",
                        f"{fmt(mag[kmin])} at θ2 = {_where(th, kmin)}",
                        "ma_min",
                    ),
                    ("|MA| largest", f"{fmt(mag[kmax])} at θ2 = {_where(th, kmax)}", "ma_max"),
                ]
            )
            + '<p class="remark">MA = (r_in ω2)/(r_out ω4), by the power identity; infinite at '
            "a toggle of links 2 and 3.</p>"
        )
    else:
        body = '<p class="remark">No finite mechanical advantage in the sweep.</p>'
    page.section("ma", "Mechanical advantage", body)
    # -- kinematics
    krows = []
    for name in ("omega3", "omega4", "alpha3", "alpha4"):
        v = np.where(m.ok, getattr(m, name), np.nan)
        if np.isfinite(v).any():
            j = int(np.nanargmax(np.abs(v)))
            unit_r = "rad/s" if name.startswith("omega") else "rad/s²"
            krows.append(
                (
                    f"peak |{name}|",
                    f"{fmt(abs(v[j]))} {unit_r} at θ2 = {_where(th, j)}",
                    f"peak_{name}",
                )
            )
    charts = "".join(c.to_svg(height=240) for c in kinematics_charts(m))
    page.section("kinematics", "Kinematics", page.table(krows) + charts)
    # -- forces, flywheel, balancing
    forces = None
    if mass is not None:
        forces = fb.dynamics(
            th,
            omega2,
            mass=mass,
            inertia=inertia,
            cg=cg,
            form=form,
            gravity=gravity,
            load_torque4=load_torque4,
        )
        _force_sections(
            page, fb, th, forces, fu, tu, omega2, k, mass, inertia, cg, form, gravity, load_torque4
        )
    else:
        page.section(
            "forces",
            "Forces",
            '<p class="remark">No mass properties were given: '
            "pass mass=(m2, m3, m4), inertia=(IG2, IG3, IG4), cg=(c2, c3, c4) for "
            "pin forces, input torque, shaking, flywheel and balancing.</p>",
        )
    checks = fourbar_checks(fb, m, omega2, forces, mass, inertia, cg, gravity, load_torque4)
    page.section(
        "selfcheck",
        "Self-check: independent checks on this machine",
        page.checks(checks) + '<p class="remark">Each check recomputes an identity '
        "from the solved numbers without the solver's code: rigid-body fields (the vector "
        "loop and its derivatives), five-point differences along the sweep, the power "
        "balance against the kinetic energy, and Kennedy's rule on centres found from "
        "the velocity fields.</p>",
    )
    if page.failed:
        page.headline = "SELF-CHECK FAILED — " + page.headline
    return page


def _force_sections(
    page: Page,
    fb: FourBar,
    th: np.ndarray,
    f: Any,
    fu: str,
    tu: str,
    omega2: float,
    k: float | None,
    mass: Any,
    inertia: Any,
    cg: Any,
    form: int,
    gravity: float,
    load_torque4: Any,
) -> None:
    ok = np.ravel(f.ok)
    rows = []
    pins = {"F12": f.F12, "F32": f.F32, "F43": f.F43, "F14": f.F14}
    for name, F in pins.items():
        mag = np.where(ok, np.abs(F), np.nan)
        j = int(np.nanargmax(mag))
        rows.append(
            (f"peak |{name}|", f"{fmt(mag[j])} {esc(fu)} at θ2 = {_where(th, j)}", f"peak_{name}")
        )
    T = np.where(ok, f.T12, np.nan)
    jmax, jmin = int(np.nanargmax(T)), int(np.nanargmin(T))
    rows.append(("T12 largest", f"{fmt(T[jmax])} {esc(tu)} at θ2 = {_where(th, jmax)}", "T12_max"))
    rows.append(("T12 smallest", f"{fmt(T[jmin])} {esc(tu)} at θ2 = {_where(th, jmin)}", "T12_min"))
    Fs = np.where(ok, np.abs(f.shaking_force), np.nan)
    Ms = np.where(ok, np.abs(f.shaking_moment), np.nan)
    js, jm = int(np.nanargmax(Fs)), int(np.nanargmax(Ms))
    rows.append(
        (
            "peak |shaking force|",
            f"{fmt(Fs[js])} {esc(fu)} at θ2 = {_where(th, js)}",
            "shaking_force_max",
        )
    )
    rows.append(
        (
            "peak |shaking moment|",
            f"{fmt(Ms[jm])} {esc(tu)} at θ2 = {_where(th, jm)}",
            "shaking_moment_max",
        )
    )
    props = page.grid(
        ("link", "mass", "I_G", "centre of mass (link frame)"),
        [[str(i + 2), fmt(mass[i]), fmt(inertia[i]), esc(complex(cg[i]))] for i in range(3)],
    )
    polars = "".join(
        c.to_svg(width=330, height=330) for c in pin_force_charts(pins, ok=ok, theta2=th, unit=fu)
    )
    page.section(
        "forces",
        "Pin forces and input torque",
        props + page.table(rows) + f'<div class="charts">{polars}</div>',
    )
    fly = None
    if k is not None and np.all(ok):
        from ..flywheel import size_flywheel

        theta = th if fb.input_range(form).full_turn else None
        if theta is not None:
            fly = size_flywheel(theta, f.T12, omega2, k)
    torque = torque_chart(th, f.T12, flywheel=fly, ok=ok, unit=tu).to_svg()
    if fly is not None:
        body = page.table(
            [
                ("coefficient of fluctuation k", fmt(k), "k"),
                ("average torque", f"{fmt(fly.torque_avg)} {esc(tu)}", "torque_avg"),
                ("energy to swing ΔE", fmt(fly.delta_e), "delta_e"),
                ("flywheel inertia I = ΔE/(k ω²)", fmt(fly.inertia), "flywheel_inertia"),
            ]
        )
    elif k is None:
        body = '<p class="remark">Give k (coefficient of fluctuation) to size a flywheel.</p>'
    else:
        body = '<p class="remark">A flywheel is sized over a crank\'s full turn.</p>'
    page.section("flywheel", "Input torque and flywheel", body + torque)
    from ..shaking import fourbar_counterweights

    cw = fourbar_counterweights(fb, mass, cg)
    mc = (max(mass[0], 1e-12), max(mass[2], 1e-12))
    mass_b, inertia_b, cg_b = cw.apply(mass, inertia, cg, mc)
    fb_bal = fb.dynamics(
        th,
        omega2,
        mass=mass_b,
        inertia=inertia_b,
        cg=cg_b,
        form=form,
        gravity=gravity,
        load_torque4=load_torque4,
    )
    shaking = shaking_charts(
        f.shaking_force,
        fb_bal.shaking_force,
        moment_before=f.shaking_moment,
        moment_after=fb_bal.shaking_moment,
        theta=th,
        force_unit=fu,
        torque_unit=tu,
    )
    body = (
        page.table(
            [
                (
                    "counterweight m·R on link 2",
                    f"{fmt(abs(cw.mR2))} at {np.degrees(np.angle(cw.mR2)):.2f}° (link frame)",
                    "mR2",
                ),
                (
                    "counterweight m·R on link 4",
                    f"{fmt(abs(cw.mR4))} at {np.degrees(np.angle(cw.mR4)):.2f}° (link frame)",
                    "mR4",
                ),
                (
                    "peak |shaking force| after",
                    f"{fmt(np.nanmax(np.abs(fb_bal.shaking_force)))} {esc(fu)}",
                    "shaking_force_after",
                ),
            ]
        )
        + '<p class="remark">Counterweights of the links\' own masses (m2, m4) at R = mR/m; the '
        "coupler is unchanged (Norton §12.2).</p>"
    )
    charts = shaking[0].to_svg(width=380, height=380) + "".join(c.to_svg() for c in shaking[1:])
    page.section(
        "balancing", "Shaking force and balancing", body + f'<div class="charts">{charts}</div>'
    )
