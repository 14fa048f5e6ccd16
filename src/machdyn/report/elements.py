"""Design reports of machine elements: a cam with its checks (gear pairs: :mod:`.gears`)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..draw.elements import cam_scene
from ..draw.engineering import cam_charts
from ..draw.html import widget
from ..draw.units import Units
from .gears import gear_report
from .page import Page, esc, fmt

__all__ = ["cam_report", "gear_report"]


def cam_report(
    profile: Any,
    *,
    max_pressure_angle_deg: float = 30.0,
    n: int = 120,
    length_unit: str | None = None,
    title: str | None = None,
    units: Any = None,
) -> Page:
    """The report page of a cam (see :func:`machdyn.report.report`).

    ``units`` (a machine file's unit system) labels the lengths and the SVAJ
    axes; else ``length_unit`` names the unit of a unit-free profile.
    """
    checks = profile.checks(max_pressure_angle=np.radians(max_pressure_angle_deg))
    failed = [c for c in checks if not c.passed]
    if units is not None and not Units.of(units).free:
        u = Units.of(units)
        length_unit = length_unit or u.system.internal("length")

        def length(v: float, digits: int = 4) -> str:
            return esc(u.text("length", v, digits))
    else:

        def length(v: float, digits: int = 4) -> str:
            return fmt(v, digits) + (f" {esc(length_unit)}" if length_unit else "")

    title = title or f"cam with a {profile.follower} follower"
    state = (
        "passes every design check"
        if not failed
        else ("FAILS " + ", ".join(c.name for c in failed))
    )
    page = Page(
        title,
        f"{title}: base radius {length(profile.base_radius)}, prime radius "
        f"{length(profile.prime_radius)}; {state}.",
    )
    page.failed = bool(failed)
    rows = [
        ("follower", esc(profile.follower), "follower"),
        ("base radius", length(profile.base_radius, 6), "base_radius"),
        ("prime radius", length(profile.prime_radius, 6), "prime_radius"),
        ("roller radius", length(profile.roller_radius, 6), "roller_radius"),
        (
            "lift",
            f"{np.degrees(np.ptp(profile.s)):.6g}° (arm swing)"
            if profile.follower == "oscillating roller"
            else length(float(np.ptp(profile.s)), 6),
            "lift",
        ),
    ]
    page.section(
        "model",
        "The cam and its follower",
        page.table(rows) + widget(cam_scene(profile, n=n, length_unit=length_unit or "")),
    )
    crow = [[esc(c.name), "pass" if c.passed else "<b>FAIL</b>", esc(c.detail)] for c in checks]
    page.section("checks", "Cam checks", page.grid(("check", "result", "detail"), crow))
    charts = cam_charts(
        profile,
        max_pressure_angle_deg=max_pressure_angle_deg,
        length_unit=length_unit,
        units=units,
    )
    page.section(
        "svaj",
        "SVAJ, pressure angle and radius of curvature",
        "".join(c.to_svg(height=220) for c in charts),
    )
    return page
