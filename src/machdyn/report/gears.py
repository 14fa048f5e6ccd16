"""Design reports of gearing: a gear pair, a simple or compound train, a planetary train.

Every number printed is the library's (``GearPair`` properties, the
interference functions, ``GearTrain.speeds``, ``PlanetaryTrain.table``,
:func:`machdyn.willis`, :mod:`machdyn.gears.power`); the self-check section
tests identities on the *printed* numbers that do not share their code path:

* gear pair — the base radii against the operating pitch radii and pressure
  angle (``r_b = r' cos φ'``), the length of action rebuilt from the tip and
  base circles, the contact ratio ``Z / p_b``; with a torque, the moment of the
  tooth load about each centre (``W r_b = T``) and the power through the mesh;
* train — the pitch-line speed of both wheels of every mesh (``|ω_a| N_a =
  |ω_b| N_b``, senses by the kind of mesh), the train value by the sign rule
  ``(−1)^externals Π N_driver / Π N_driven``, the tooth force of every mesh
  from both shafts' torques (``T_a / N_a = T_b / N_b``), and power in = power out;
* planetary — the tabular method against Willis' formula (``machdyn.willis``,
  member by member), the pitch-line speeds *relative to the arm* at every mesh,
  the moment balance ``Σ T = 0`` and the power balance ``Σ T ω = 0``.

A check fed wrong numbers fails (tests/test_report_gears.py).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from .._validate import finite_scalar, mapping
from ..draw.gears import mesh_chart, planetary_scene, train_scene
from ..draw.html import widget
from ..draw.units import Units
from ..errors import ModelError
from .checks import Check
from .page import Page, esc, fmt

__all__ = [
    "gear_pair_checks",
    "gear_report",
    "planetary_checks",
    "planetary_report",
    "train_checks",
    "train_report",
]

#: Relative tolerance of the gearing self-checks (the numbers are printed to 6+ digits).
TOL = 1e-9


def _rel(a: Any, b: Any) -> float:
    """Largest relative difference of two arrays (scaled by the larger magnitude)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    scale = max(float(np.max(np.abs(a), initial=0.0)), float(np.max(np.abs(b), initial=0.0)))
    return float(np.max(np.abs(a - b), initial=0.0)) / (scale or 1.0)


def _one(u: Units, kind: str) -> float:
    """One unit as shown (1 rpm, 1 N·m), in the model's internal units."""
    return 1.0 / float(u.show(kind, 1.0))


def _power(u: Units, value: float) -> str:
    """A power ``T ω`` (internal units) as shown: the energy unit per second."""
    return fmt(float(u.show("energy", value)), 6)


def _sense(w: float, scale: float) -> str:
    if abs(w) <= 1e-12 * scale:
        return "at rest"
    return "counter-clockwise (+)" if w > 0 else "clockwise (−)"


# ----------------------------------------------------------------------------- gear pair
def gear_pair_checks(pair: Any, shown: Mapping[str, Any]) -> list[Check]:
    """Self-checks of a gear pair on the numbers shown (``shown``: as :func:`gear_report` prints).

    ``shown`` holds ``base_radii``, ``operating_pitch_radii``, ``operating_pressure_angle``,
    ``addendum_radii``, ``center_distance``, ``length_of_action``, ``base_pitch``,
    ``contact_ratio`` and, with a torque, ``torques`` (pinion, gear), ``total_force``
    and ``speeds`` (pinion, gear).
    """
    rb = np.asarray(shown["base_radii"], float)
    rop = np.asarray(shown["operating_pitch_radii"], float)
    phi = float(shown["operating_pressure_angle"])
    ra = np.asarray(shown["addendum_radii"], float)
    c = float(shown["center_distance"])
    checks = [
        Check(
            "base circles",
            _rel(rb, rop * math.cos(phi)),
            TOL,
            "r_b = r' cos φ' for both gears (operating pitch radii and pressure angle)",
            2,
        )
    ]
    tips = np.sqrt(np.maximum(ra**2 - rb**2, 0.0))
    if pair.internal:  # the ring's tip path is measured from the other side
        z = tips[0] - tips[1] + c * math.sin(phi)
    else:
        z = tips[0] + tips[1] - c * math.sin(phi)
    checks.append(
        Check(
            "length of action",
            _rel(z, shown["length_of_action"]),
            TOL,
            "Z = √(r_ap² − r_bp²) ± √(r_ag² − r_bg²) ∓ C' sin φ' from the tip and base circles",
            1,
        )
    )
    pb = 2 * math.pi * rb[0] / pair.pinion.teeth
    checks.append(
        Check(
            "contact ratio",
            _rel(shown["length_of_action"] / pb, shown["contact_ratio"]),
            TOL,
            "m_p = Z / p_b with p_b = 2π r_bp / N_p",
            1,
        )
    )
    if "torques" in shown:
        t = np.asarray(shown["torques"], float)
        w = float(shown["total_force"])
        checks.append(
            Check(
                "moment of the tooth load",
                _rel(w * rb, t),
                TOL,
                "the load W along the line of action has the moment W r_b = T about each centre",
                2,
            )
        )
        if "speeds" in shown:
            s = np.abs(np.asarray(shown["speeds"], float))
            checks.append(
                Check(
                    "power through the mesh",
                    _rel(t[0] * s[0], t[1] * s[1]),
                    TOL,
                    "T_p |ω_p| = T_g |ω_g| (no loss in an ideal mesh)",
                    1,
                )
            )
    return checks


def _pair_numbers(pair: Any, input_speed: float | None, torque: float | None) -> dict[str, Any]:
    """The numbers the gear pair's page prints, from the API."""
    from ..gears import mesh_forces

    p, g = pair.pinion, pair.gear
    shown: dict[str, Any] = {
        "base_radii": (p.base_radius, g.base_radius),
        "operating_pitch_radii": pair.operating_pitch_radii,
        "operating_pressure_angle": pair.operating_pressure_angle,
        "addendum_radii": (p.addendum_radius, g.addendum_radius),
        "center_distance": pair.center_distance,
        "length_of_action": pair.length_of_action,
        "base_pitch": pair.base_pitch,
        "contact_ratio": pair.contact_ratio,
    }
    if input_speed is not None:
        w_in = finite_scalar("input_speed", input_speed)
        r = pair.velocity_ratio
        shown["speeds"] = (w_in, w_in * r) if pair.driver == "pinion" else (w_in / r, w_in)
    if torque is not None:
        f = mesh_forces(pair, torque, pair.driver)
        shown["forces"] = f
        shown["torques"] = (f.torque_pinion, f.torque_gear)
        shown["total_force"] = f.total
    return shown


def _pair_tables(page: Page, pair: Any, u: Units, deg: Any) -> None:
    p, g = pair.pinion, pair.gear
    rows = []
    for label, attr, kind in (
        ("teeth N", "teeth", None),
        ("pitch radius r", "pitch_radius", "length"),
        ("base radius r_b", "base_radius", "length"),
        ("addendum radius r_a", "addendum_radius", "length"),
        ("root radius", "root_radius", "length"),
        ("addendum a", "addendum", "length"),
        ("dedendum b", "dedendum", "length"),
        ("profile shift x", "profile_shift", None),
        ("tooth thickness (pitch circle)", "tooth_thickness", "length"),
    ):
        cells = [esc(label)]
        for who, gear in (("pinion", p), ("gear", g)):
            v = getattr(gear, attr)
            text = str(v) if attr == "teeth" else (u.text(kind, v, 6) if kind else fmt(v, 6))
            cells.append(page.span(f"{who}_{attr}", esc(text)))
        rows.append(cells)
    ring = " (internal)" if pair.internal else ""
    page.section(
        "geometry",
        "The two gears",
        page.grid(("", "pinion", f"gear{ring}"), rows)
        + f'<p class="remark">Module m = {esc(u.text("length", p.module, 6))}'
        + (f", diametral pitch P_d = {fmt(p.diametral_pitch, 6)}" if p.diametral_pitch else "")
        + f", pressure angle φ = {deg(p.pressure_angle)}, {esc(p.system.replace('_', ' '))}.</p>",
    )


def _pair_mesh_rows(pair: Any, u: Units, deg: Any) -> list[tuple[str, str, str]]:
    app, rec = pair.angles_of_approach, pair.angles_of_recess
    ln = lambda v: esc(u.text("length", v, 6))  # noqa: E731
    return [
        ("centre distance C'", ln(pair.center_distance), "center_distance"),
        ("standard centre distance C", ln(pair.standard_center_distance), "standard_cd"),
        ("pressure angle φ", deg(pair.pressure_angle), "pressure_angle"),
        ("operating pressure angle φ'", deg(pair.operating_pressure_angle), "operating_phi"),
        ("velocity ratio m_V = ω_g / ω_p", fmt(pair.velocity_ratio, 6), "velocity_ratio"),
        ("gear ratio m_G = N_g / N_p", fmt(pair.gear_ratio, 6), "gear_ratio"),
        ("length of action Z", ln(pair.length_of_action), "length_of_action"),
        (
            "path of approach, recess",
            f"{ln(pair.path_of_approach)}, {ln(pair.path_of_recess)}",
            "paths",
        ),
        ("base pitch p_b", ln(pair.base_pitch), "base_pitch"),
        (
            "contact ratio m_p = Z / p_b",
            f"{fmt(pair.contact_ratio, 6)} ({esc(pair.contact_ratio_rating)})",
            "contact_ratio",
        ),
        ("angles of approach (pinion, gear)", f"{deg(app[0])}, {deg(app[1])}", "approach"),
        ("angles of recess (pinion, gear)", f"{deg(rec[0])}, {deg(rec[1])}", "recess"),
        ("backlash", ln(_zero(pair.backlash, pair.pinion.module)), "backlash"),
    ]


def _zero(value: float, scale: float) -> float:
    """``value``, or 0 where it is rounding noise of a quantity of size ``scale``."""
    return 0.0 if abs(value) <= 1e-12 * scale else value


def _interference_rows(pair: Any, deg: Any) -> tuple[list[tuple[str, str, str]], list[str]]:
    """Interference, undercut and minimum teeth (the notes' relations), and the problems found."""
    from ..gears import min_pinion_teeth, min_profile_shift, min_teeth_equal_gears, undercut

    p, g = pair.pinion, pair.gear
    phi, k = p.pressure_angle, p.addendum_constant
    gear_tip, pinion_tip = pair.interference
    cut = [bool(undercut(x.teeth, phi, x.profile_shift, k)) for x in (p, g) if not x.internal]
    problems = [
        n
        for n, hit in (("gear tip interferes", gear_tip), ("pinion tip interferes", pinion_tip))
        if hit
    ]
    problems += [f"{n} undercut" for n, hit in zip(("pinion", "gear"), cut, strict=False) if hit]
    yes = lambda hit: "<b>YES</b>" if hit else "no"  # noqa: E731
    rows = [
        ("gear tip beyond the pinion's interference point", yes(gear_tip), "interference_gear_tip"),
        (
            "pinion tip beyond the gear's interference point",
            yes(pinion_tip),
            "interference_pinion_tip",
        ),
        ("pinion undercut by a rack cutter", yes(cut[0]), "undercut_pinion"),
    ]
    if not g.internal:
        rows.append(("gear undercut by a rack cutter", yes(cut[1]), "undercut_gear"))
        try:
            fewest = str(min_pinion_teeth(g.teeth, phi, k))
        except ModelError:  # the gear is below the equal-gear minimum: no pinion fits
            fewest = "none: no pinion meshes without interference"
        rows.append(
            (f"fewest pinion teeth with this {g.teeth}-tooth gear", fewest, "min_pinion_teeth")
        )
        rows.append(
            (
                "fewest teeth of two equal gears",
                str(min_teeth_equal_gears(phi, k)),
                "min_teeth_equal",
            )
        )
    rows.append(
        (
            "fewest pinion teeth against a rack",
            str(min_pinion_teeth(np.inf, phi, k)),
            "min_teeth_rack",
        )
    )
    rows.append(
        (
            "profile shift the pinion needs against undercut",
            fmt(max(float(min_profile_shift(p.teeth, phi, k)), 0.0), 6),
            "min_shift_pinion",
        )
    )
    return rows, problems


def gear_report(
    pair: Any,
    *,
    n: int = 120,
    title: str | None = None,
    input_speed: float | None = None,
    torque: float | None = None,
    units: Any = None,
) -> Page:
    """The report page of a gear pair (see :func:`machdyn.report.report`).

    ``input_speed`` is the driver's speed (the pair's ``driver``), ``torque``
    the driver's torque (tooth loads); both in the model's units.
    """
    u = Units.of(units if units is not None else pair)
    deg = lambda a: esc(u.text("angle", a, 6))  # noqa: E731
    title = title or f"gear pair {pair.pinion.teeth}/{pair.gear.teeth}"
    shown = _pair_numbers(pair, input_speed, torque)
    irows, problems = _interference_rows(pair, deg)
    if pair.contact_ratio < 1.2:
        problems.append(f"contact ratio {pair.contact_ratio:.3f} < 1.2")
    state = "; ".join(problems) if problems else "no interference, no undercut"
    page = Page(
        title,
        f"{title}: contact ratio {pair.contact_ratio:.4g} ({pair.contact_ratio_rating}), "
        f"m_V = {pair.velocity_ratio:.6g}, φ' = {math.degrees(pair.operating_pressure_angle):.4g}°"
        f"; {'FAILS: ' if problems else ''}{state}.",
    )
    page.failed = bool(problems)
    page.section(
        "model",
        "The pair in mesh, with the line of action",
        widget(_gear_scene(pair, n))
        + f'<div class="charts">{mesh_chart(pair, u).to_svg(width=460)}</div>'
        + '<p class="remark">The line of action runs between the base-circle tangent points '
        "T_p and T_g (the interference points); contact runs along it from the first to the "
        "last contact, where the tip circles cut it.</p>",
    )
    _pair_tables(page, pair, u, deg)
    page.section(
        "mesh", "Mesh: centre distance, ratios, contact", page.table(_pair_mesh_rows(pair, u, deg))
    )
    page.section("interference", "Interference, undercut and minimum teeth", page.table(irows))
    _pair_loads(page, pair, shown, u)
    page.section(
        "selfcheck",
        "Self-check: independent checks on this pair",
        page.checks(gear_pair_checks(pair, shown)),
    )
    return page


def _gear_scene(pair: Any, n: int) -> Any:
    from ..draw.elements import gear_scene

    return gear_scene(pair, n=n)


def _pair_loads(page: Page, pair: Any, shown: Mapping[str, Any], u: Units) -> None:
    rows = []
    if "speeds" in shown:
        wp, wg = shown["speeds"]
        rows += [
            ("pinion speed ω_p", esc(u.text("angular_velocity", wp, 6)), "omega_pinion"),
            ("gear speed ω_g", esc(u.text("angular_velocity", wg, 6)), "omega_gear"),
        ]
    if "forces" in shown:
        f = shown["forces"]
        force = lambda v: esc(u.text("force", v, 6))  # noqa: E731
        rows += [
            ("torque on the pinion T_p", esc(u.text("torque", f.torque_pinion, 6)), "T_pinion"),
            ("torque on the gear T_g", esc(u.text("torque", f.torque_gear, 6)), "T_gear"),
            ("tangential load W_t = T_p / r_p'", force(f.tangential), "W_t"),
            ("radial load W_r = W_t tan φ'", force(f.radial), "W_r"),
            ("total load W = W_t / cos φ' (along the line of action)", force(f.total), "W"),
        ]
    body = (
        page.table(rows)
        if rows
        else (
            '<p class="remark">No speed or torque given: report(pair, input_speed=…, torque=…) '
            "adds the speeds and the tooth loads.</p>"
        )
    )
    page.section("loads", "Speeds and tooth loads", body)


# ----------------------------------------------------------------------------- trains
def train_checks(
    train: Any, speeds: Any, torques: Any, train_value: float, load_torque: float
) -> list[Check]:
    """Self-checks of a simple or compound train on the printed speeds and torques."""
    from ..gears import MESH_KINDS

    w = np.asarray(speeds, float)
    t = np.asarray(torques, float)
    pitch, sense, force = [], [], []
    reverses = 0
    num = den = 1.0
    for k, (a, b, kind) in enumerate(train.stages):
        pitch.append(_rel(abs(w[k]) * a, abs(w[k + 1]) * b))
        flips = MESH_KINDS[kind] < 0
        reverses += flips
        same = np.sign(w[k]) == np.sign(w[k + 1])
        sense.append(0.0 if same != flips or w[k] == 0 else 1.0)
        force.append(_rel(abs(t[k]) / a, abs(t[k + 1]) / b))
        num, den = num * a, den * b
    rule = (-1.0) ** reverses * num / den
    p_in, p_out = t[0] * w[0], -load_torque * w[-1]
    return [
        Check(
            "pitch-line speed at every mesh",
            max(pitch + sense),
            TOL,
            "|ω_a| N_a = |ω_b| N_b at each mesh, and the sense flips at external meshes "
            "and crossed belts only",
            len(train.stages),
        ),
        Check(
            "train value by the sign rule",
            max(_rel(rule, train_value), _rel(w[-1] / w[0], train_value)),
            TOL,
            "m_V = (−1)^(reversing meshes) Π N_driver / Π N_driven = ω_out / ω_in",
            1,
        ),
        Check(
            "tooth force at every mesh",
            max(force),
            TOL,
            "the tooth force from the driving shaft's torque, T_a / r_a, equals the one from "
            "the driven shaft's, T_b / r_b (r ∝ N)",
            len(train.stages),
        ),
        Check(
            "power in = power out",
            _rel(p_in, p_out),
            TOL,
            "T_in ω_in = −T_load ω_out (ideal train)",
            1,
        ),
    ]


def train_report(
    train: Any,
    *,
    input_speed: float | None = None,
    torque: float | None = None,
    n: int = 72,
    title: str | None = None,
    units: Any = None,
) -> Page:
    """The report page of a simple or compound :class:`~machdyn.gears.GearTrain`.

    ``input_speed`` and ``torque`` (the input shaft's) in the model's units;
    without them the page gives speeds per unit input speed and torques per
    unit input torque.
    """
    from ..gears import stage_ratio, train_power

    u = Units.of(units if units is not None else train)
    w_in = (
        _one(u, "angular_velocity")
        if input_speed is None
        else finite_scalar("input_speed", input_speed)
    )
    t_in = _one(u, "torque") if torque is None else finite_scalar("torque", torque)
    power = train_power(train, w_in, t_in)
    m_v = train.train_value
    stages = len(train.stages)
    title = title or f"gear train of {stages} stage{'s' if stages > 1 else ''}"
    sense = "the same way as" if m_v > 0 else "against"
    page = Page(
        title,
        f"{title}: train value m_V = {m_v:+.6g} (the output turns {sense} the input, "
        f"{'reduction' if abs(m_v) < 1 else 'step-up'} {max(abs(1 / m_v), abs(m_v)):.6g}:1).",
    )
    page.section(
        "model",
        "Schematic: pitch circles at their centres",
        widget(train_scene(train, w_in, n=n, units=u)) + '<p class="remark">Radii ∝ tooth numbers '
        "(or the diameters given); every wheel's spoke turns at its shaft's speed, the "
        "fastest one turn per cycle.</p>",
    )
    rows = []
    for k, (a, b, kind) in enumerate(train.stages, start=1):
        rows.append(
            [
                str(k),
                fmt(a, 6),
                fmt(b, 6),
                esc(kind.replace("_", " ")),
                page.span(f"stage{k}_ratio", fmt(stage_ratio(a, b, kind), 6)),
            ]
        )
    page.section(
        "stages",
        "Stages and train value",
        page.grid(("stage", "driver N", "driven N", "kind", "ω_driven / ω_driver"), rows)
        + page.table(
            [
                ("train value m_V = ω_out / ω_in", fmt(m_v, 6), "train_value"),
                ("speed ratio ω_in / ω_out", fmt(1 / m_v, 6), "speed_ratio"),
            ]
        ),
    )
    _train_shafts(page, train, power, u, input_speed is None, torque is None)
    checks = train_checks(train, power.speeds, power.torques, m_v, power.load_torque)
    page.section("selfcheck", "Self-check: independent checks on this train", page.checks(checks))
    return page.finished()


def _train_shafts(page: Page, train: Any, power: Any, u: Units, unit_w: bool, unit_t: bool) -> None:
    speeds, torques = power.speeds, power.torques
    scale = float(np.max(np.abs(speeds)))
    wheels = [[] for _ in speeds]
    for k, (a, b, _) in enumerate(train.stages):
        wheels[k].append(fmt(a, 6))
        wheels[k + 1].append(fmt(b, 6))
    rows = []
    for k, w in enumerate(speeds):
        name = "input" if k == 0 else ("output" if k == len(speeds) - 1 else str(k + 1))
        rows.append(
            [
                esc(name),
                " + ".join(wheels[k]),
                page.span(f"omega{k + 1}", esc(u.text("angular_velocity", w, 6))),
                esc(_sense(w, scale)),
                page.span(f"T{k + 1}", esc(u.text("torque", torques[k], 6))),
            ]
        )
    per = []
    if unit_w:
        per.append("speeds per unit input speed (no input speed given)")
    if unit_t:
        per.append("torques per unit input torque (no torque given)")
    p_in, p_out = torques[0] * speeds[0], -power.load_torque * speeds[-1]
    energy = u.unit("energy")
    body = page.grid(("shaft", "wheels", "speed ω", "sense", "torque T = P / ω"), rows)
    body += page.table(
        [
            (
                "load torque on the output shaft",
                esc(u.text("torque", power.load_torque, 6)),
                "load_torque",
            ),
            (f"power in T_in ω_in ({energy}/s)", _power(u, p_in), "power_in"),
            (f"power out −T_load ω_out ({energy}/s)", _power(u, p_out), "power_out"),
        ]
    )
    if per:
        body += f'<p class="remark">{esc("; ".join(per))}.</p>'
    page.section("shafts", "Every shaft: speed, sense, torque (power balance)", body)


# ----------------------------------------------------------------------------- planetary
def planetary_checks(
    train: Any, speeds: Mapping[str, float], torques: Mapping[str, float] | None = None
) -> list[Check]:
    """Self-checks of a planetary train on the printed member speeds (and torques)."""
    from ..gears import willis

    w_a, w_f = speeds["arm"], speeds[train.first]
    formula = [float(willis(train.ratios[m], first=w_f, arm=w_a)) for m in train.members[:-1]]
    table = [speeds[m] for m in train.members[:-1]]
    scale = max(abs(v) for v in speeds.values()) or 1.0
    mesh = []
    for prev, link in zip(train.chain, train.chain[1:], strict=False):
        if link[2] == "shaft":
            mesh.append(abs(speeds[prev[0]] - speeds[link[0]]) / scale)
            continue
        va = (speeds[prev[0]] - w_a) * prev[1]
        vb = (speeds[link[0]] - w_a) * link[1]
        mesh.append(
            abs(va + vb if link[2] == "external" else va - vb) / (scale * max(prev[1], link[1]))
        )
    checks = [
        Check(
            "tabular vs formula method",
            _rel(table, formula),
            TOL,
            "every gear's speed from the table against Willis' formula "
            "(ω − ω_A) = R_i (ω_F − ω_A), machdyn.willis",
            len(formula),
        ),
        Check(
            "pitch-line speed relative to the arm",
            max(mesh),
            TOL,
            "at each mesh (ω_a − ω_A) N_a = ∓(ω_b − ω_A) N_b (− external, + internal); "
            "a shaft turns its two gears together",
            len(mesh),
        ),
    ]
    if torques is not None:
        t = np.array([torques[m] for m in train.members])
        w = np.array([speeds[m] for m in train.members])
        tscale = float(np.max(np.abs(t))) or 1.0
        pw = t * w
        p_in, p_out = float(pw[pw > 0].sum()), float(-pw[pw < 0].sum())
        checks += [
            Check(
                "moment balance",
                abs(float(t.sum())) / tscale,
                TOL,
                "Σ T = 0: the external torques on the coaxial members hold the train",
                3,
            ),
            Check(
                "power in = power out",
                _rel(p_in, p_out),
                TOL,
                "Σ T ω over the drivers = −Σ T ω over the loads (ideal train)",
                3,
            ),
        ]
    return checks


def planetary_report(
    train: Any,
    *,
    speeds: Mapping[str, float] | None = None,
    torque: Mapping[str, float] | None = None,
    n: int = 90,
    title: str | None = None,
    units: Any = None,
) -> Page:
    """The report page of a :class:`~machdyn.gears.PlanetaryTrain`.

    ``speeds``: two known member speeds (default: the last gear fixed, the
    first at 1); ``torque``: ``{member: T}`` on the first gear, the last gear
    or the arm (default: 1 on the first gear). Model units.
    """
    from ..gears import planetary_power

    u = Units.of(units if units is not None else train)
    given = (
        mapping("speeds", speeds, "speeds (two of them)")
        if speeds is not None
        else {train.last: 0.0, train.first: _one(u, "angular_velocity")}
    )
    load = (
        mapping("torque", torque, "torques (one of them)")
        if torque is not None
        else {train.first: _one(u, "torque")}
    )
    table = train.table(**given)
    omega = dict(zip(table.members, (float(x) for x in table.total), strict=True))
    power = planetary_power(train, given, load)
    teeth = "/".join(f"{link[0]} {link[1]}" for link in train.chain)
    title = title or f"planetary train {teeth}"
    known = ", ".join(f"{m} {u.text('angular_velocity', w, 6)}" for m, w in given.items())
    others = ", ".join(
        f"{m} {u.text('angular_velocity', omega[m], 6)}" for m in train.members if m not in given
    )
    page = Page(title, f"{title}: R = {train.train_value:.6g} (arm fixed); with {known}: {others}.")
    page.section(
        "model",
        "Schematic: the arm and the gears turning",
        widget(planetary_scene(train, given, n=n, units=u)) + '<p class="remark">Radii ∝ tooth '
        "numbers; one planet drawn; the fastest member makes one turn per cycle.</p>",
    )
    _planetary_tables(page, train, table, given, u)
    _planetary_torques(page, train, power, load, u, torque is None)
    checks = planetary_checks(train, omega, dict(zip(power.members, power.torques, strict=True)))
    page.section("selfcheck", "Self-check: independent checks on this train", page.checks(checks))
    return page.finished()


def _planetary_tables(page: Page, train: Any, table: Any, given: Mapping, u: Units) -> None:
    from ..gears import willis

    w = lambda v: esc(u.text("angular_velocity", v, 6))  # noqa: E731
    rows = []
    for i, link in enumerate(train.chain):
        rows.append(
            [
                esc(link[0]),
                str(link[1]),
                esc(link[2] if i else "first (central)"),
                page.span(f"R_{i + 1}", fmt(train.ratios[link[0]], 6)),
            ]
        )
    members = page.grid(("gear", "teeth", "meshes with the one before", "R_i (arm fixed)"), rows)
    scale = float(np.max(np.abs(table.total))) or 1.0
    trows = []
    for i, m in enumerate(table.members):
        mark = " (given)" if m in given else ""
        trows.append(
            [
                esc(m) + mark,
                w(table.with_arm[i]),
                w(table.relative[i]),
                page.span(f"omega_{i + 1}", w(table.total[i])),
                esc(_sense(table.total[i], scale)),
            ]
        )
    tab = page.grid(
        ("member", "with the arm ω_A", "relative to the arm R_i (ω_F − ω_A)", "total ω", "sense"),
        trows,
    )
    w_f, w_a = table[train.first], table["arm"]
    w_l = float(willis(train.train_value, first=w_f, arm=w_a))
    formula = (
        f"<p>Formula method (Willis): (ω_L − ω_A) / (ω_F − ω_A) = R, so ω_{esc(train.last)} = "
        f"ω_A + R (ω_F − ω_A) = {w(w_a)} + {fmt(train.train_value, 6)} × ({w(w_f)} − {w(w_a)}) "
        f'= <span data-key="willis_last">{w(w_l)}</span>.</p>'
    )
    fixed = []
    for hold, a, b in (
        (train.last, train.first, "arm"),
        (train.first, train.last, "arm"),
        ("arm", train.first, train.last),
    ):
        r = train.ratio(a, b, fixed=hold)
        fixed.append((f"{hold} fixed: ω_{b} / ω_{a}", fmt(r, 6), f"ratio_{hold}_fixed"))
    page.section(
        "members", "Members and their ratios relative to the arm", members + page.table(fixed)
    )
    page.section("tabular", "Speeds: tabular method and formula method", tab + formula)


def _planetary_torques(
    page: Page, train: Any, power: Any, load: Mapping, u: Units, per_unit: bool
) -> None:
    rows = []
    energy = u.unit("energy")
    for i, m in enumerate(power.members):
        if power.torques[i] == 0 and m not in (train.first, train.last, "arm"):
            continue
        rows.append(
            [
                esc(m) + (" (given)" if m in load else ""),
                page.span(f"T_{m}", esc(u.text("torque", power.torques[i], 6))),
                page.span(f"P_{m}", _power(u, power.power[i])),
            ]
        )
    pw = power.power
    body = page.grid(("member", "external torque T", f"power T ω ({energy}/s)"), rows)
    body += page.table(
        [
            (f"Σ power in ({energy}/s)", _power(u, pw[pw > 0].sum()), "power_in"),
            (f"Σ power out ({energy}/s)", _power(u, -pw[pw < 0].sum()), "power_out"),
            ("Σ T", esc(u.text("torque", power.torques.sum(), 3)), "torque_sum"),
        ]
    )
    body += (
        '<p class="remark">From Σ T ω = 0 for every motion the train allows: T_F = −R T_L, '
        "T_A = −(1 − R) T_L (planets carry no external torque)"
        + ("; per unit torque on the first gear (none given)" if per_unit else "")
        + ".</p>"
    )
    page.section("torques", "Torques by power balance", body)
