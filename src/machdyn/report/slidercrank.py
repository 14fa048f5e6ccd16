"""The design report of a slider-crank and of the inverted slider-crank.

Every number comes from the :class:`~machdyn.slidercrank.SliderCrank` /
:class:`~machdyn.slidercrank.InvertedSliderCrank` API (``solve``,
``dynamics``, ``stroke``, ``input_range``, ``mechanical_advantage``), shown in
the model's units; the self-checks are the same independent identities as the
four-bar's (:mod:`machdyn.report.checks`), written here from the solved motion.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..draw.build import inverted_scene, slidercrank_scene
from ..draw.engineering import (
    pin_force_charts,
    shaking_charts,
    torque_chart,
    transmission_chart,
)
from ..draw.html import widget
from ..draw.kinematics import slider_charts
from ..slidercrank import InvertedSliderCrank, SliderCrank
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
from .fourbar import _along, _applied, _rigid, _units, flywheel_table
from .page import Page, esc, fmt

__all__ = [
    "inverted_checks",
    "inverted_report",
    "slidercrank_checks",
    "slidercrank_report",
    "slidercrank_sweep",
]


def slidercrank_sweep(model: SliderCrank | InvertedSliderCrank, n: int) -> np.ndarray:
    """``n`` crank angles: a full turn (uniform, open), or the rocking range inside its ends."""
    rng = model.input_range() if isinstance(model, SliderCrank) else None
    if rng is None:
        return np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    margin = 1e-6 * (rng[1] - rng[0])
    return np.linspace(rng[0] + margin, rng[1] - margin, n)


def _at(th: np.ndarray, j: int) -> str:
    return f"θ2 = {np.degrees(th[j]):.1f}°"


def _peak_row(label: str, values: Any, th: np.ndarray, key: str, text: Any) -> tuple[str, str, str]:
    v = np.ravel(values)
    if not np.isfinite(v).any():
        return (label, "–", key)
    j = int(np.nanargmax(np.abs(v)))
    return (label, f"{esc(text(abs(v[j])))} at {_at(th, j)}", key)


# --------------------------------------------------------------------------------------
# slider-crank


def slidercrank_checks(
    sc: SliderCrank,
    motion: Any,
    omega2: float,
    forces: Any = None,
    mass: Any = None,
    inertia: Any = None,
    cg: Any = None,
    gravity: float = 0.0,
    load_force4: Any = 0.0,
    external_forces: Any = (),
    external_torques: Any = (),
) -> list[Check]:
    """Self-checks of a slider-crank motion (and forces), computed apart from the solver.

    ``v_A = jω2·A`` is written from the crank's rate and ``v_B = ḋ`` from the
    slider's, so the rod's rigidity tests ω3 and ḋ together; with forces,
    each link's equilibrium, the power balance and the momentum balance test
    the pin forces, ``T12`` and the shaking force.
    """
    th2 = np.ravel(motion.theta2)
    ok = np.ravel(motion.ok)
    one = np.ones_like(th2)
    w2, a2 = np.ravel(motion.omega2) * one, np.ravel(motion.alpha2) * one
    w3, a3 = np.ravel(motion.omega3), np.ravel(motion.alpha3)
    A, B = np.ravel(motion.A), np.ravel(motion.B)
    zero = np.zeros_like(A)
    vA, aA = 1j * w2 * A, (1j * a2 - w2 * w2) * A
    vB, aB = np.ravel(motion.d_dot) + 0j, np.ravel(motion.d_ddot) + 0j
    points = {"O2": (zero, zero, zero), "A": (A, vA, aA), "B": (B, vB, aB)}
    links = {
        "1": (("O2",), zero.real, zero.real),
        "2": (("O2", "A"), w2, a2),
        "3": (("A", "B"), w3, a3),
        "4": (("B",), zero.real, zero.real),
    }
    pins = {("1", "2"): "O2", ("2", "3"): "A", ("3", "4"): "B"}
    rigid = RigidMotion(th2, float(omega2), points, links, ok, pins)
    checks = [*loop_closure(rigid), *finite_differences(rigid), kennedy(rigid)]
    assembled = np.ravel(motion.assembled)
    checks.append(
        angles(
            [
                (motion.theta3, np.angle(A - B)),
                (motion.d, B.real),  # the slider's position is B's x (B = d + jc)
            ],
            assembled,
            what="max |θ3 − arg(A − B)| (rad, wrapped) and |d − Re B|",
        )
    )
    if forces is None:
        return checks
    f = forces
    c2, c3 = (complex(x) for x in cg)
    bodies = {}
    for k, (p, vp, ap, w, al, G) in {
        2: (zero, zero, zero, w2, a2, _along(zero, A, c2)),
        3: (A, vA, aA, w3, a3, _along(A, B, c3)),
        4: (B, vB, aB, zero.real, zero.real, B),
    }.items():
        vG, aG = _rigid(p, vp, ap, w, al, G)
        inert = float(inertia[k - 2]) if k < 4 else 0.0
        b = Body(str(k), float(mass[k - 2]), inert, G, vG, aG, w, al)
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
    bodies[4].load(F14, B, "ground")
    bodies[4].load(np.ravel(load_force4) * one + 0j, B, "external")
    # the block is a particle on its slide line (a load's moment about B goes to the guide,
    # which the model does not print): its loads act at B
    frames = {2: lambda z: _along(zero, A, z), 3: lambda z: _along(A, B, z), 4: lambda z: B}
    _applied(bodies, frames, external_forces, external_torques, one, sc.length_unit, (4,))
    good = ok & np.ravel(f.ok)
    power, dke, scale = power_of_loads(list(bodies.values()))
    checks.append(power_balance(power, dke, good, scale=scale))
    checks.append(equilibrium(list(bodies.values()), good, rigid.size))
    checks.append(
        momentum(list(bodies.values()), f.shaking_force, f.shaking_moment, good, rigid.size)
    )
    checks.append(
        momentum_differences(
            list(bodies.values()), f.shaking_force, f.shaking_moment, th2, omega2, good, rigid.size
        )
    )
    return checks


def slidercrank_report(sc: SliderCrank, *, title: str | None = None, **options: Any) -> Page:
    """Build the report page of a slider-crank (see :func:`machdyn.report.report`)."""
    page = Page(title or _name(sc), "")
    page.headline = slidercrank_sections(page, sc, **options)
    return page.finished()


def _name(model: Any, u: Any = None) -> str:
    unit = "" if u is None or u.free else f" {u.unit('length')}"
    if isinstance(model, SliderCrank):
        return f"slider-crank {model.a:g}-{model.b:g}{unit}, offset {model.c:g}{unit}"
    return (
        f"inverted slider-crank, crank {model.a:g}{unit}, ground {model.d:g}{unit}, "
        f"offset {model.c:g}{unit}"
    )


def slidercrank_sections(
    page: Page,
    sc: SliderCrank,
    *,
    form: int = 1,
    omega2: float = 1.0,
    n: int = 360,
    mass: Any = None,
    inertia: Any = None,
    cg: Any = None,
    gravity: float = 0.0,
    load_force4: Any = 0.0,
    friction: str = "smooth",
    mu: float = 0.0,
    beta: float = 0.0,
    k: float | None = None,
    mu_limit_deg: float = 40.0,
    units: Any = None,
    length_unit: str | None = None,
    balance_fraction: float = 0.0,
    external_forces: Any = (),
    external_torques: Any = (),
) -> str:
    """Add a slider-crank's sections to ``page``; returns its first line.

    ``balance_fraction`` is the part of the reciprocating mass the crank
    counterweight overbalances (0: the rotating masses only); ``external_forces``
    and ``external_torques`` as :meth:`SliderCrank.dynamics` takes them.
    """
    u = _units(sc, units, length_unit)
    th = slidercrank_sweep(sc, n)
    m = sc.solve(th, omega2, form=form)
    rng = sc.input_range()
    span = (
        "the full turn"
        if rng is None
        else f"θ2 from {np.degrees(rng[0]):.2f}° to {np.degrees(rng[1]):.2f}°"
    )
    kind = "crank" if rng is None else "rocker"
    headline = (
        f"{_name(sc, u)}: assembles over {span} of link 2 (a {kind}) in form {form}; mobility 1."
    )
    rows = [
        ("crank a", u.text("length", sc.a, 6), "a"),
        ("connecting rod b", u.text("length", sc.b, 6), "b"),
        ("offset c", u.text("length", sc.c, 6), "c"),
        ("form (circuit)", str(form), "form"),
        ("input speed ω2", u.text("angular_velocity", omega2), "omega2"),
    ]
    frames = sc.solve(th[:: max(1, th.size // 120)], omega2, form=form)
    page.section(
        "model",
        "The model and its drawing",
        page.table(rows)
        + widget(slidercrank_scene(sc, frames), fps=30)
        + f'<p class="remark">Lengths in {esc(u.unit("length"))}, y up.</p>',
    )
    facts = [
        ("mobility (Kutzbach–Gruebler)", "M = 3(4 − 1) − 2·4 = 1", "mobility"),
        ("input link", f"a {kind}", "input_kind"),
        ("input range", esc(span), "input_range"),
    ]
    if sc.crank_rotates:
        lo, hi = sc.stroke(form)
        facts.append(
            ("stroke (d min … d max)", f"{u.text('length', lo)} … {u.text('length', hi)}", "stroke")
        )
    mu_rod = acute(np.ravel(m.A - m.B), np.ones(th.size, complex) * 1j)  # rod vs the slide normal
    good = np.ravel(m.assembled)
    if good.any():
        mu_g = np.where(good, np.degrees(mu_rod), np.nan)
        j = int(np.nanargmin(mu_g))
        facts.append(
            ("smallest transmission angle μ", f"{mu_g[j]:.3f}° at {_at(th, j)}", "mu_min_deg")
        )
    ma = sc.mechanical_advantage(th, form=form)
    mag = np.abs(np.where(np.isfinite(ma), ma, np.nan))
    if np.isfinite(mag).any():
        j = int(np.nanargmin(mag))
        facts.append(("|MA| smallest (r_in = 1)", f"{fmt(mag[j])} at {_at(th, j)}", "ma_min"))
    chart = transmission_chart(th, mu_rod, ok=good, limit_deg=mu_limit_deg)
    page.section(
        "class",
        "Mobility, range and transmission",
        page.table(facts)
        + '<p class="remark">μ: the acute angle between the rod and the normal to the slide '
        "(90° best; the design limit is drawn).</p>" + chart.to_svg(),
    )
    krows = [
        _peak_row(
            "peak |ω3|",
            np.where(m.ok, m.omega3, np.nan),
            th,
            "peak_omega3",
            _t(u, "angular_velocity"),
        ),
        _peak_row(
            "peak |α3|",
            np.where(m.ok, m.alpha3, np.nan),
            th,
            "peak_alpha3",
            _t(u, "angular_acceleration"),
        ),
        _peak_row("peak |ḋ|", np.where(m.ok, m.d_dot, np.nan), th, "peak_d_dot", _t(u, "velocity")),
        _peak_row(
            "peak |d̈|", np.where(m.ok, m.d_ddot, np.nan), th, "peak_d_ddot", _t(u, "acceleration")
        ),
    ]
    charts = "".join(c.to_svg(height=220) for c in slider_charts(m, rod=True, units=u))
    page.section("kinematics", "Kinematics", page.table(krows) + charts)
    forces = fly = None
    if mass is not None:
        inertia = (0.0, 0.0) if inertia is None else tuple(inertia)[:2]
        cg = (0.0, 0.0) if cg is None else tuple(cg)[:2]
        forces = sc.dynamics(
            th,
            omega2,
            mass=mass,
            inertia=inertia,
            cg=cg,
            form=form,
            gravity=gravity,
            load_force4=load_force4,
            friction=friction,
            mu=mu,
            beta=beta,
            external_forces=external_forces,
            external_torques=external_torques,
        )
        fly = _slider_forces(page, sc, th, forces, u, omega2, k, rng is None)
        _slider_balancing(
            page,
            sc,
            th,
            forces,
            u,
            {
                "omega2": omega2,
                "mass": mass,
                "inertia": inertia,
                "cg": cg,
                "form": form,
                "gravity": gravity,
                "load_force4": load_force4,
                "friction": friction,
                "mu": mu,
                "beta": beta,
                "balance_fraction": balance_fraction,
                "external_forces": external_forces,
                "external_torques": external_torques,
            },
        )
    else:
        page.section(
            "forces",
            "Forces",
            '<p class="remark">No mass properties were given: pass mass=(m2, m3, m4), '
            "inertia=(IG2, IG3), cg=(c2, c3) for pin forces, crank torque, shaking and "
            "flywheel.</p>",
        )
    checks = slidercrank_checks(
        sc, m, omega2, forces, mass, inertia, cg, gravity, load_force4,
        external_forces, external_torques,
    )  # fmt: skip
    if fly is not None:
        checks.append(flywheel_energy(fly.theta, fly.torque, fly))
    page.section(
        "selfcheck",
        "Self-check: independent checks on this machine",
        page.checks(checks) + '<p class="remark">Rigid-body fields (the vector loop and '
        "its derivatives), five-point differences along the sweep, Kennedy's rule, the rod "
        "angle against its pins; with forces, each link's equilibrium, the power balance and "
        "the momentum balance.</p>",
    )
    return headline


def _t(u: Any, kind: str) -> Any:
    return lambda v: u.text(kind, v)


def _slider_forces(
    page: Page,
    sc: SliderCrank | InvertedSliderCrank,
    th: np.ndarray,
    f: Any,
    u: Any,
    omega2: float,
    k: Any,
    full: bool,
) -> Any:
    ok = np.ravel(f.ok)
    pins = {"F12": f.F12, "F32": f.F32, "F43": f.F43, "F14": f.F14}
    rows = [
        _peak_row(f"peak |{n}|", np.where(ok, np.abs(F), np.nan), th, f"peak_{n}", _t(u, "force"))
        for n, F in pins.items()
    ]
    T = np.where(ok, f.T12, np.nan)
    if np.isfinite(T).any():
        jmax, jmin = int(np.nanargmax(T)), int(np.nanargmin(T))
        rows.append(
            ("T12 largest", f"{esc(u.text('torque', T[jmax]))} at {_at(th, jmax)}", "T12_max")
        )
        rows.append(
            ("T12 smallest", f"{esc(u.text('torque', T[jmin]))} at {_at(th, jmin)}", "T12_min")
        )
    rows.append(
        _peak_row(
            "peak |shaking force|",
            np.where(ok, np.abs(f.shaking_force), np.nan),
            th,
            "shaking_force_max",
            _t(u, "force"),
        )
    )
    rows.append(
        _peak_row(
            "peak |shaking moment|",
            np.where(ok, f.shaking_moment, np.nan),
            th,
            "shaking_moment_max",
            _t(u, "torque"),
        )
    )
    polars = "".join(
        c.to_svg(width=330, height=330) for c in pin_force_charts(pins, ok=ok, theta2=th, units=u)
    )
    page.section(
        "forces",
        "Pin forces and crank torque",
        page.table(rows) + f'<div class="charts">{polars}</div>',
    )
    fly = None
    if k is not None and full and ok.all():
        from ..flywheel import size_flywheel

        fly = size_flywheel(th, f.T12, abs(omega2), k)
    body = (
        flywheel_table(page, fly, u)
        if fly is not None
        else ('<p class="remark">A flywheel is sized (give k) over a full turn of the crank.</p>')
    )
    chart = torque_chart(th, f.T12, flywheel=fly, ok=ok, units=u)
    page.section("flywheel", "Crank torque and flywheel", body + chart.to_svg())
    return fly


def _slider_balancing(
    page: Page, sc: SliderCrank, th: np.ndarray, f: Any, u: Any, props: dict[str, Any]
) -> None:
    """Shaking force before and after the crank counterweight (rotating masses balanced)."""
    from ..shaking import slidercrank_counterweight

    fraction = props.pop("balance_fraction")
    mass, inertia, cg = props.pop("mass"), props.pop("inertia"), props.pop("cg")
    bal = slidercrank_counterweight(sc, mass, cg, fraction=fraction)
    mass_b, inertia_b, cg_b = bal.apply(mass, inertia, cg, radius=sc.a)
    fb = sc.dynamics(th, mass=mass_b, inertia=inertia_b, cg=cg_b, **props)
    ok = np.ravel(f.ok) & np.ravel(fb.ok)
    before, after = (np.where(ok, x.shaking_force, np.nan) for x in (f, fb))
    m_before, m_after = (np.where(ok, x.shaking_moment, np.nan) for x in (f, fb))
    shaking = shaking_charts(
        before,
        after,
        moment_before=m_before,
        moment_after=m_after,
        theta=th,
        units=u,
        closed=sc.crank_rotates,
    )
    w2 = abs(props["omega2"])
    m_b = abs(bal.reciprocating)
    primary = m_b * sc.a * w2**2
    rows = [
        (
            "crank counterweight m·R",
            f"{esc(u.text('unbalance', abs(bal.mR)))} at {bal.angle_deg:.2f}° from the crank "
            "line O2→A",
            "mR_crank",
        ),
        (
            "its mass at R = a",
            esc(u.text("mass", bal.mass(sc.a))) if abs(bal.mR) else "none needed",
            "counterweight_mass",
        ),
        ("overbalanced fraction f of m_B", fmt(fraction), "balance_fraction"),
        ("reciprocating mass m_B = m4 + m3·c3/b", esc(u.text("mass", m_b)), "m_B"),
        _peak_row(
            "peak |shaking force| after", np.abs(after), th, "shaking_force_after", _t(u, "force")
        ),
        _peak_row(
            "peak |shaking moment| after", m_after, th, "shaking_moment_after", _t(u, "torque")
        ),
        (
            "primary m_B·a·ω2² (f = 0)",
            esc(u.text("force", primary)),
            "primary",
        ),
        (
            "secondary ≈ m_B·a·ω2²·(a/b) (Norton)",
            esc(u.text("force", primary * sc.a / sc.b)),
            "secondary",
        ),
    ]
    remark = (
        '<p class="remark">The counterweight (a point mass at R = a opposite the crank pin) '
        "balances the rotating masses exactly — the crank and the part m3(1 − c3/b) of the rod "
        "at the crank pin — so without external loads the shaking force after is "
        "−m_B(B̈ − f·Ä): along the slide, the piston's primary and secondary harmonics "
        "(f = 0); overbalancing (balance_fraction f) turns a part f of the primary into a "
        "force across the slide. No crank counterweight removes the reciprocating force "
        "(Norton, ch. 13, balancing the single-cylinder engine).</p>"
    )
    charts = shaking[0].to_svg(width=380, height=380) + "".join(c.to_svg() for c in shaking[1:])
    page.section(
        "shaking",
        "Shaking force and balancing",
        page.table(rows) + remark + f'<div class="charts">{charts}</div>',
    )


# --------------------------------------------------------------------------------------
# inverted slider-crank


def inverted_checks(
    isc: InvertedSliderCrank,
    motion: Any,
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
    """Self-checks of an inverted slider-crank motion (and forces), computed apart from the solver.

    The block's pin A is written twice: from the crank (``A = a e^{jθ2}``,
    ``v = jω2 A``) and from the slotted link (``A₄ = O4 + (b + jc) e^{jθ4}``
    with its velocity ``(ḃ + jω4 (b + jc)) e^{jθ4}`` and acceleration — the
    Coriolis term ``2jω4 ḃ`` included — from the solved b, θ4 and their
    rates); the two must coincide (the loop), follow the differences of their
    positions and satisfy Kennedy's rule. With forces, each link's
    equilibrium, the power balance (the slot's friction pair does work on the
    block's sliding, its normal force and couple none) and the momentum
    balance test the pin forces, ``T12`` and the shaking force and moment.
    """
    th2 = np.ravel(motion.theta2)
    ok = np.ravel(motion.ok)
    one = np.ones_like(th2)
    w2, a2 = np.ravel(motion.omega2) * one, np.ravel(motion.alpha2) * one
    w4, a4 = np.ravel(motion.omega4), np.ravel(motion.alpha4)
    th4 = np.ravel(motion.theta4)
    b, bd, bdd = (np.ravel(x) for x in (motion.b, motion.b_dot, motion.b_ddot))
    A = np.ravel(motion.A)
    zero = np.zeros_like(A)
    O4 = zero + isc.d
    e = np.exp(1j * th4)
    Z = b + 1j * isc.c
    A4 = O4 + Z * e
    vA4 = (bd + 1j * w4 * Z) * e
    aA4 = (bdd + 2j * w4 * bd + (1j * a4 - w4 * w4) * Z) * e
    points = {
        "O2": (zero, zero, zero),
        "O4": (O4, zero, zero),
        "A": (A, 1j * w2 * A, (1j * a2 - w2 * w2) * A),
        "A4": (A4, vA4, aA4),
    }
    links = {
        "1": (("O2", "O4"), zero.real, zero.real),
        "2": (("O2", "A"), w2, a2),
        "3": (("A", "A4"), w4, a4),  # the block: the crank's pin, and the slot's point under it
        "4": (("O4",), w4, a4),
    }
    pins = {("1", "2"): "O2", ("2", "3"): "A", ("1", "4"): "O4"}
    rigid = RigidMotion(th2, float(omega2), points, links, ok, pins)
    checks = [*loop_closure(rigid), *finite_differences(rigid), kennedy(rigid)]
    gap = np.where(ok, np.abs(A4 - A) / rigid.size, np.nan)
    checks.append(
        Check(
            "slot passes through the block",
            float(np.nanmax(gap)) if np.isfinite(gap).any() else float("nan"),
            1e-9,
            "max |O4 + (b + jc)e^{jθ4} − a e^{jθ2}| / drawing size",
            int(np.isfinite(gap).sum()),
        )
    )
    if forces is None:
        return checks
    w = (w2, a2, w4, a4)
    bodies = _inverted_bodies(points, w, e, forces, mass, inertia, cg, gravity, load_torque4)
    frames = {2: lambda z: _along(zero, A, z), 3: lambda z: A + z * e, 4: lambda z: O4 + z * e}
    _applied(dict(zip((2, 3, 4), bodies, strict=True)), frames, external_forces,
             external_torques, one, isc.length_unit)  # fmt: skip
    good = ok & np.ravel(forces.ok)
    power, dke, scale = power_of_loads(bodies)
    checks.append(power_balance(power, dke, good, scale=scale))
    checks.append(equilibrium(bodies, good, rigid.size))
    Fs, Ms = forces.shaking_force, forces.shaking_moment
    checks.append(momentum(bodies, Fs, Ms, good, rigid.size))
    checks.append(momentum_differences(bodies, Fs, Ms, th2, omega2, good, rigid.size))
    return checks


def _inverted_shaking(page: Page, th: np.ndarray, f: Any, u: Any, full: bool) -> None:
    """The shaking force (polar) and moment about O2 of an inverted slider-crank."""
    ok = np.ravel(f.ok)
    shaking = shaking_charts(
        np.where(ok, f.shaking_force, np.nan),
        moment_before=np.where(ok, f.shaking_moment, np.nan),
        theta=th,
        units=u,
        closed=full,
    )
    charts = shaking[0].to_svg(width=380, height=380) + "".join(c.to_svg() for c in shaking[1:])
    page.section(
        "shaking",
        "Shaking force and moment",
        '<p class="remark">The force and moment of the moving links on the frame (Norton '
        "§11.8): Fs = F21 + F41, Ms = T21 + R1 × F41 about O2; their peaks are under Pin "
        f'forces.</p><div class="charts">{charts}</div>',
    )


def _inverted_bodies(
    points: dict[str, Any],
    rates: tuple[Any, ...],
    e4: Any,
    f: Any,
    mass: Any,
    inertia: Any,
    cg: Any,
    gravity: float,
    load_torque4: Any,
) -> list[Body]:
    """Crank, block and slotted link with the printed forces on them (D'Alembert data)."""
    w2, a2, w4, a4 = rates
    (O2, _, _), (O4, _, _), (A, vA, aA) = points["O2"], points["O4"], points["A"]
    c2, c3, c4 = (complex(x) for x in cg)
    frames = {
        2: (O2, O2 * 0, O2 * 0, w2, a2, _along(O2, A, c2)),
        3: (A, vA, aA, w4, a4, A + c3 * e4),
        4: (O4, O4 * 0, O4 * 0, w4, a4, O4 + c4 * e4),
    }
    bodies = {}
    for k, (p, vp, ap, om, al, G) in frames.items():
        vG, aG = _rigid(p, vp, ap, om, al, G)
        b = Body(str(k), float(mass[k - 2]), float(inertia[k - 2]), G, vG, aG, om, al)
        if gravity and b.mass:
            b.load(np.full(G.shape, -1j * b.mass * gravity), G, "external")
        bodies[k] = b
    F12, F32, F43, F14 = (np.ravel(x) for x in (f.F12, f.F32, f.F43, f.F14))
    normal = np.ravel(f.normal) * 1j * e4  # the slot's normal force; the rest is friction
    C43 = np.ravel(f.couple)
    bodies[2].load(F12, O2, "ground")
    bodies[2].load(F32, A, "joint")
    bodies[2].torque(np.ravel(f.T12), "ground")
    bodies[3].load(-F32, A, "joint")
    bodies[3].load(normal, A, "joint")
    bodies[3].load(F43 - normal, A, "friction")  # works on the block's sliding in the slot
    bodies[3].torque(C43, "joint")
    bodies[4].load(-normal, A, "joint")
    bodies[4].load(normal - F43, A, "friction")
    bodies[4].torque(-C43, "joint")
    bodies[4].load(F14, O4, "ground")
    bodies[4].torque(np.ravel(load_torque4) * np.ones(A.shape), "external")
    return list(bodies.values())


def inverted_report(isc: InvertedSliderCrank, *, title: str | None = None, **options: Any) -> Page:
    """Build the report page of an inverted slider-crank (see :func:`machdyn.report.report`)."""
    page = Page(title or _name(isc), "")
    page.headline = inverted_sections(page, isc, **options)
    return page.finished()


def inverted_sections(
    page: Page,
    isc: InvertedSliderCrank,
    *,
    form: int = 1,
    omega2: float = 1.0,
    n: int = 360,
    mass: Any = None,
    inertia: Any = None,
    cg: Any = None,
    gravity: float = 0.0,
    load_torque4: Any = 0.0,
    friction: str = "smooth",
    mu: float = 0.0,
    beta: float = 0.0,
    k: float | None = None,
    units: Any = None,
    length_unit: str | None = None,
    external_forces: Any = (),
    external_torques: Any = (),
    **ignored: Any,
) -> str:
    """Add an inverted slider-crank's sections to ``page``; returns its first line.

    ``external_forces`` and ``external_torques`` as :meth:`InvertedSliderCrank.dynamics`
    takes them.
    """
    u = _units(isc, units, length_unit)
    th = slidercrank_sweep(isc, n)
    m = isc.solve(th, omega2, form=form)
    assembled = np.ravel(np.isfinite(m.b))  # positions exist (toggles included)
    reach = (
        "the full turn"
        if assembled.all()
        else f"{int(assembled.sum())} of {assembled.size} crank angles of a turn"
    )
    headline = f"{_name(isc, u)}: assembles over {reach} of link 2 in form {form}; mobility 1."
    rows = [
        ("crank a", u.text("length", isc.a, 6), "a"),
        ("ground d = O2O4", u.text("length", isc.d, 6), "d"),
        ("slot offset c", u.text("length", isc.c, 6), "c"),
        ("form (circuit)", str(form), "form"),
        ("input speed ω2", u.text("angular_velocity", omega2), "omega2"),
    ]
    frames = isc.solve(th[:: max(1, th.size // 120)], omega2, form=form)
    page.section(
        "model",
        "The model and its drawing",
        page.table(rows) + widget(inverted_scene(isc, frames), fps=30),
    )
    th4 = np.where(assembled, np.degrees(np.ravel(m.theta4)), np.nan)
    facts = [
        ("mobility (Kutzbach–Gruebler)", "M = 3(4 − 1) − 2·4 = 1", "mobility"),
        ("input range", esc(reach), "input_range"),
    ]
    if np.isfinite(th4).any():
        facts.append(
            ("swing of link 4 (θ4 max − min)", f"{np.nanmax(th4) - np.nanmin(th4):.3f}°", "swing4")
        )
    w4 = np.where(np.ravel(m.ok), np.ravel(m.omega4), np.nan)
    if assembled.all() and np.isfinite(w4).all():  # quick return: the two swings' times
        one_way = float(np.mean(w4 > 0))  # uniform θ2 at constant ω2: samples are time
        if 0.0 < one_way < 1.0:
            ratio = max(one_way, 1 - one_way) / min(one_way, 1 - one_way)
            facts.append(("time ratio (slow swing / quick swing)", fmt(ratio), "time_ratio"))
    page.section("class", "Mobility and range", page.table(facts))
    charts = "".join(c.to_svg(height=220) for c in slider_charts(m, rod=True, units=u))
    page.section("kinematics", "Kinematics", charts)
    forces = fly = None
    if mass is not None:
        inertia = (0.0, 0.0, 0.0) if inertia is None else tuple(inertia)
        cg = (0.0, 0.0, 0.0) if cg is None else tuple(cg)
        forces = isc.dynamics(
            th,
            omega2,
            mass=mass,
            inertia=inertia,
            cg=cg,
            form=form,
            gravity=gravity,
            load_torque4=load_torque4,
            friction=friction,
            mu=mu,
            beta=beta,
            external_forces=external_forces,
            external_torques=external_torques,
        )
        fly = _slider_forces(page, isc, th, forces, u, omega2, k, assembled.all())
        _inverted_shaking(page, th, forces, u, bool(assembled.all()))
    else:
        page.section(
            "forces",
            "Forces",
            '<p class="remark">No mass properties were given: pass mass=(m2, m3, m4), '
            "inertia=(IG2, IG3, IG4), cg=(c2, c3, c4) (block and slotted link: x along the "
            "slot) for pin forces, crank torque, shaking and flywheel.</p>",
        )
    checks = inverted_checks(
        isc, m, omega2, forces, mass, inertia, cg, gravity, load_torque4,
        external_forces, external_torques,
    )  # fmt: skip
    if fly is not None:
        checks.append(flywheel_energy(fly.theta, fly.torque, fly))
    page.section(
        "selfcheck",
        "Self-check: independent checks on this machine",
        page.checks(checks) + '<p class="remark">The block\'s pin written from the crank and '
        "from the slotted link must agree at position, velocity and acceleration (Coriolis "
        "included); five-point differences and Kennedy's rule as for the four-bar; with "
        "forces, each link's equilibrium, the power balance and the momentum balance.</p>",
    )
    return headline
