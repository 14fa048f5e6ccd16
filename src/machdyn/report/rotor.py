"""The design report of a rotor: its masses and planes, the balance, the bearing forces.

A :class:`machdyn.spec.RotorBalance` (a machine file's ``[rotor.NAME]``: point
masses, correction planes and radii, a speed) or a :class:`machdyn.rotor.Rotor`
(mass, centre of mass, inertia tensor) with ``planes=``. The corrections are
the library's (:func:`machdyn.balancing.two_plane` / ``static_balance``,
``Rotor.two_plane_correction``); the bearing forces before and after are
:meth:`machdyn.rotor.Rotor.bearing_reactions` of the rotor without and with the
correction masses, at the speed given (Norton §12.1–12.2; the notes' Ch. 12).

Self-checks on the printed numbers, apart from the correction formula:

* **residual bearing forces** — the rotor *with* the printed corrections, put
  together as a new :class:`~machdyn.rotor.Rotor` (its products of inertia from
  the point masses), loads its bearings with ~0;
* **force and moment sums** — ``Σ mR`` and ``Σ mR z`` over the masses and the
  corrections, summed here, vanish (the moment only for a two-plane balance);
* **bearing forces by statics** — the printed loads before correction obey
  ``L_A + L_B = ω² Σ mR`` and ``z_A L_A + z_B L_B = ω² Σ mR z`` (the rotating
  forces ``m R ω²`` and their moments).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import finite_array, finite_scalar
from ..draw.rotor import rotor_side_chart, unbalance_chart
from ..draw.units import Units
from ..errors import InputError
from .checks import Check
from .page import Page, esc, fmt

__all__ = ["rotor_checks", "rotor_report"]

TOL = 1e-9


@dataclass(frozen=True)
class _Balance:
    """A rotor, its correction and where the numbers come from (all in model units)."""

    rotor: Any  # machdyn.rotor.Rotor before correction
    masses: tuple[tuple[float, float, float, float], ...] | None  # (m, R, angle, z)
    unbalance: complex  # Σ m R e^{jθ}
    couple: complex  # Σ m R z e^{jθ}
    corrections: tuple[complex, ...]
    correction_z: tuple[float, ...]
    radii: tuple[float, ...] | None
    speed: float
    speed_given: bool
    bearings: tuple[float, float] | None
    bearings_given: bool


def _balance(model: Any, planes: Any, speed: Any, bearings: Any, radii: Any) -> _Balance:
    from ..rotor import Rotor
    from ..spec import RotorBalance

    if isinstance(model, RotorBalance):
        m = np.array([e[0] for e in model.masses])
        mr = model.unbalance
        z = np.array([e[3] for e in model.masses])
        rotor = Rotor.from_masses(m, mr / m, z)
        planes = model.planes if planes is None else planes
        radii = model.radii if radii is None else radii
        masses, u, p = model.masses, complex(mr.sum()), complex((mr * z).sum())
        speed = model.speed if speed is None else speed
    elif isinstance(model, Rotor):
        rotor, masses, u, p = model, None, model.unbalance, model.couple_unbalance
    else:
        raise InputError("model", f"expected a Rotor or RotorBalance, got {type(model).__name__}")
    planes = _two("planes", planes)
    bearings = _two("bearings", bearings)
    if speed is not None:
        speed = finite_scalar("speed", speed)
        if speed == 0.0:
            raise InputError("speed", "a rotor at rest loads its bearings with nothing: give ω ≠ 0")
    if planes is not None:
        za, zb = planes
        fix = rotor.two_plane_correction(za, zb)
        corrections, cz = (complex(fix.mR_a), complex(fix.mR_b)), (za, zb)
    else:
        fix = rotor.static_correction()
        corrections, cz = (complex(fix.mR),), (float(rotor.cg[2]),)
    given = bearings is not None
    if bearings is None and planes is not None:
        bearings = planes
    w = 1.0 if speed is None else speed
    if radii is not None:
        radii = tuple(float(r) for r in np.ravel(finite_array("radii", radii)))
        if not radii or min(radii) <= 0:
            raise InputError("radii", "one or two positive radii of the correction masses")
    return _Balance(
        rotor, masses, u, p, corrections, cz, radii, w, speed is not None, bearings, given
    )


def _two(field: str, value: Any) -> tuple[float, float] | None:
    """Two distinct axial positions ``(z_A, z_B)`` (or None)."""
    if value is None:
        return None
    z = finite_array(field, value)
    if z.shape != (2,) or z[0] == z[1]:
        raise InputError(field, f"two different axial positions (z_A, z_B), got {value!r}")
    return float(z[0]), float(z[1])


def _corrected(b: _Balance) -> Any:
    """The rotor with the correction masses added (unit radius: only m R counts)."""
    keep = [i for i, c in enumerate(b.corrections) if abs(c) > 0]
    if not keep:
        return b.rotor
    c = np.array([b.corrections[i] for i in keep])
    return b.rotor.with_masses(np.abs(c), c / np.abs(c), [b.correction_z[i] for i in keep])


def _loads(rotor: Any, b: _Balance) -> tuple[complex, complex] | None:
    if b.bearings is None:
        return None
    r = rotor.bearing_reactions(b.speed, *b.bearings)
    return complex(r.load_a), complex(r.load_b)


def rotor_checks(
    unbalance: complex,
    couple: complex,
    corrections: Sequence[complex],
    correction_z: Sequence[float],
    *,
    omega: float,
    scale: float,
    residual: float,
    bearings: tuple[float, float] | None = None,
    loads_before: tuple[complex, complex] | None = None,
) -> list[Check]:
    """The rotor's self-checks on the printed numbers.

    ``unbalance``/``couple``: ``Σ mR``, ``Σ mR z`` of the masses; ``scale`` the
    sum of their magnitudes ``Σ |mR|``; ``residual`` the largest bearing load
    (or shaking force) after correction, from the corrected rotor.
    """
    c = np.asarray(corrections, complex)
    cz = np.asarray(correction_z, float)
    w2 = omega * omega
    checks = [
        Check(
            "residual bearing forces",
            residual / (w2 * scale),
            TOL,
            "largest bearing load of the rotor with the printed corrections added "
            "(machdyn.rotor.Rotor from the point masses) over ω² Σ|mR|",
            1,
        ),
        Check(
            "force sum with the corrections",
            abs(unbalance + c.sum()) / scale,
            TOL,
            "|Σ mR (masses) + Σ mR (corrections)| / Σ|mR|",
            1,
        ),
    ]
    if c.size == 2:
        span = max(abs(cz[1] - cz[0]), 1e-300)
        checks.append(
            Check(
                "moment sum with the corrections",
                abs(couple + (c * cz).sum()) / (scale * span),
                TOL,
                "|Σ mR z (masses) + Σ mR z (corrections)| / (Σ|mR| |z_B − z_A|)",
                1,
            )
        )
    if bearings is not None and loads_before is not None:
        la, lb = loads_before
        za, zb = bearings
        force = abs(la + lb - w2 * unbalance) / (w2 * scale)
        reach = max(abs(za), abs(zb), abs(zb - za))
        moment = abs(za * la + zb * lb - w2 * couple) / (w2 * scale * reach)
        checks.append(
            Check(
                "bearing forces by statics",
                max(force, moment),
                TOL,
                "the printed loads before correction: L_A + L_B = ω² Σ mR and "
                "z_A L_A + z_B L_B = ω² Σ mR z",
                2,
            )
        )
    return checks


def rotor_report(
    model: Any,
    *,
    planes: Sequence[float] | None = None,
    bearings: Sequence[float] | None = None,
    speed: float | None = None,
    radii: Sequence[float] | None = None,
    title: str | None = None,
    units: Any = None,
) -> Page:
    """The report page of a rotor (see :func:`machdyn.report.report`).

    ``planes``: z of the correction planes (a RotorBalance has its own; none:
    a single-plane, static balance); ``bearings``: z of the two bearings
    (default: the correction planes); ``speed``: ω (default: the model's, else
    1, forces per unit ω²); ``radii``: where the correction masses go.
    """
    b = _balance(model, planes, speed, bearings, radii)
    u = Units.of(units if units is not None else getattr(model, "units", None))
    after = _corrected(b)
    before_loads, after_loads = _loads(b.rotor, b), _loads(after, b)
    scale = (sum(e[0] * e[1] for e in b.masses) if b.masses else 0.0) or (
        abs(b.unbalance) + abs(b.couple) / max(abs(z) for z in (*b.correction_z, 1e-300))
    )
    scale = scale or 1e-300  # a rotor balanced already: every residual is 0
    w2 = b.speed**2
    residual = max(abs(v) for v in after_loads) if after_loads else w2 * abs(after.unbalance)
    kind = "two-plane (dynamic)" if len(b.corrections) == 2 else "single-plane (static)"
    title = title or "rotor"
    head = f"{title}: {kind} balance, "
    head += ", ".join(
        f"{u.text('unbalance', abs(c), 4)} at {math.degrees(np.angle(c)) % 360:.4g}°"
        for c in b.corrections
    )
    if before_loads:
        head += (
            f"; bearing loads {u.text('force', abs(before_loads[0]), 4)}, "
            f"{u.text('force', abs(before_loads[1]), 4)} before, "
            f"{u.text('force', residual, 2)} after"
        )
    page = Page(title, head + ".")
    _masses_section(page, b, u)
    _correction_section(page, b, u)
    _bearing_section(page, b, u, before_loads, after_loads, after)
    checks = rotor_checks(
        b.unbalance,
        b.couple,
        b.corrections,
        b.correction_z,
        omega=b.speed,
        scale=scale,
        residual=residual,
        bearings=b.bearings,
        loads_before=before_loads,
    )
    page.section("selfcheck", "Self-check: independent checks on this rotor", page.checks(checks))
    return page.finished()


def _masses_section(page: Page, b: _Balance, u: Units) -> None:
    L = lambda v: esc(u.text("length", v, 6))  # noqa: E731
    if b.masses is not None:
        rows = []
        for i, (m, r, a, z) in enumerate(b.masses, start=1):
            mr = m * r
            rows.append(
                [
                    f"m{i}",
                    page.span(f"m{i}", esc(u.text("mass", m, 6))),
                    L(r),
                    esc(u.text("angle", a, 6)),
                    L(z),
                    page.span(f"mR{i}", esc(u.text("unbalance", mr, 6))),
                    page.span(f"mRz{i}", esc(u.text("moment_of_unbalance", mr * z, 6))),
                ]
            )
        body = page.grid(("mass", "m", "R", "angle θ", "z", "m R", "m R z"), rows)
    else:
        r = b.rotor
        x, y, z = r.cg
        body = page.table(
            [
                ("mass", esc(u.text("mass", r.mass, 6)), "mass"),
                ("centre of mass (x, y, z)", f"{L(x)}, {L(y)}, {L(z)}", "cg"),
                (
                    "products of inertia I_xz, I_yz",
                    f"{esc(u.text('inertia', r.I_xz, 6))}, {esc(u.text('inertia', r.I_yz, 6))}",
                    "products",
                ),
            ]
        )
    sums = page.table(
        [
            (
                "static unbalance Σ m R",
                esc(u.text("unbalance", abs(b.unbalance), 6))
                + f" at {fmt(math.degrees(np.angle(b.unbalance)) % 360, 6)}°",
                "unbalance",
            ),
            (
                "couple unbalance Σ m R z",
                esc(u.text("moment_of_unbalance", abs(b.couple), 6))
                + f" at {fmt(math.degrees(np.angle(b.couple)) % 360, 6)}°",
                "couple",
            ),
        ]
    )
    planes = ", ".join(f"z = {L(z)}" for z in b.correction_z)
    side = ""
    if b.masses is not None:
        two = len(b.corrections) == 2
        side = rotor_side_chart(
            b.masses,
            b.correction_z if two else (),
            b.corrections if two else (),
            b.radii,
            b.bearings,
            units=u,
        ).to_svg(width=560, height=260)
    page.section(
        "masses",
        "Masses and planes",
        side + body + sums + f'<p class="remark">Correction plane(s): {planes}.</p>',
    )


def _correction_section(page: Page, b: _Balance, u: Units) -> None:
    names = ("A", "B") if len(b.corrections) == 2 else ("static",)
    rows = []
    for i, (name, c, z) in enumerate(zip(names, b.corrections, b.correction_z, strict=True)):
        row = [
            esc(name),
            esc(u.text("length", z, 6)),
            page.span(f"mR_{name}", esc(u.text("unbalance", abs(c), 6))),
            page.span(f"angle_{name}", f"{fmt(math.degrees(np.angle(c)) % 360, 6)}°"),
        ]
        if b.radii:
            radius = b.radii[min(i, len(b.radii) - 1)]
            row += [
                esc(u.text("length", radius, 6)),
                page.span(f"mass_{name}", esc(u.text("mass", abs(c) / radius, 6))),
            ]
        rows.append(row)
    head = ("plane", "z", "m R", "angle θ")
    if b.radii:
        head += ("at radius", "correction mass")
    chart = unbalance_chart(
        [e[0] * e[1] * np.exp(1j * e[2]) for e in b.masses] if b.masses else [b.unbalance],
        b.corrections,
        names=None if b.masses else ["Σ m R"],
        correction_names=[f"correction {n}" for n in names],
        units=u,
    )
    charts = chart.to_svg(width=330)
    if len(b.corrections) == 2 and b.masses:  # the moment polygon about plane A
        za = b.correction_z[0]
        moments = [e[0] * e[1] * np.exp(1j * e[2]) * (e[3] - za) for e in b.masses]
        charts += unbalance_chart(
            moments,
            [b.corrections[1] * (b.correction_z[1] - za)],
            correction_names=["correction B"],
            kind="moment_of_unbalance",
            title="moments m R (z − z_A) about plane A",
            units=u,
        ).to_svg(width=330)
    page.section(
        "balance",
        "Correction masses and the unbalance polar plot",
        page.grid(head, rows) + f'<div class="charts">{charts}</div>',
    )


def _bearing_section(
    page: Page, b: _Balance, u: Units, before: Any, after: Any, rotor: Any
) -> None:
    note = "" if b.speed_given else " (no speed given: per unit ω², ω = 1 rad/s)"
    w = esc(u.text("angular_velocity", b.speed, 6))
    if before is None:
        rows = [
            (
                "shaking force before: ω² |Σ m R|",
                esc(u.text("force", b.speed**2 * abs(b.unbalance), 6)),
                "shaking_before",
            ),
            (
                "shaking force after",
                esc(u.text("force", b.speed**2 * abs(rotor.unbalance), 3)),
                "shaking_after",
            ),
        ]
        page.section(
            "bearings",
            f"Shaking force at ω = {w}{note}",
            page.table(rows) + '<p class="remark">No bearing positions: report(..., bearings=(z_A, '
            "z_B)) adds the bearing loads.</p>",
        )
        return
    where = "given" if b.bearings_given else "at the correction planes (none given)"
    za, zb = b.bearings
    rows = []
    for label, loads, key in (
        ("before correction", before, "before"),
        ("after correction", after, "after"),
    ):
        cells = [esc(label)]
        for name, f in zip(("A", "B"), loads, strict=True):
            digits = 6 if key == "before" else 3
            angle = f"{math.degrees(np.angle(f)) % 360:.4g}°" if key == "before" else ""
            cells.append(
                page.span(f"load_{name}_{key}", esc(u.text("force", abs(f), digits)))
                + (f" at {angle}" if angle else "")
            )
        rows.append(cells)
    body = page.grid(
        (
            "",
            f"bearing A (z = {u.text('length', za, 6)})",
            f"bearing B (z = {u.text('length', zb, 6)})",
        ),
        rows,
    )
    page.section(
        "bearings",
        f"Bearing loads at ω = {w}{note}",
        body + f'<p class="remark">Bearings {esc(where)}; the loads rotate with the rotor '
        "(angles in its frame, at θ = 0); machdyn.rotor.Rotor.bearing_reactions.</p>",
    )
