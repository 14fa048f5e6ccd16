"""Engineering plots: pin-force polars, torque with flywheel lobes, shaking force, μ over the cycle.

Each plot is first a :class:`~machdyn.draw.chart.Chart` (``*_chart`` functions:
what is shown, every axis labelled with quantity and unit) and then drawn by
matplotlib (``plot_*`` functions, returning the Figure or Axes) or written as
inline SVG by the report. Lengths are in the model's unit (or "model units"),
forces and torques in the units the model's numbers imply (:func:`force_units`),
angles in degrees. Unsolved samples are gaps, never zeros.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from .chart import Chart, Series, figure
from .units import Units

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "cam_charts",
    "force_units",
    "pin_force_charts",
    "plot_cam_design",
    "plot_pin_forces",
    "plot_shaking",
    "plot_torque",
    "plot_transmission_angle",
    "shaking_charts",
    "torque_chart",
    "transmission_chart",
]


def force_units(length_unit: str | None) -> tuple[str, str]:
    """Labels of force and torque for a model with ``length_unit`` (masses in kg, time in s).

    Examples
    --------
    >>> force_units("m")
    ('N', 'N·m')
    >>> force_units("mm")
    ('kg·mm/s²', 'kg·mm²/s²')
    >>> force_units(None)
    ('force units', 'torque units')
    """
    if not length_unit:
        return "force units", "torque units"
    if length_unit in ("m", "meter", "metre"):
        return "N", "N·m"
    return f"kg·{length_unit}/s²", f"kg·{length_unit}²/s²"


def _shown(units: Any, kind: str, unit: str) -> tuple[Any, str]:
    """``(convert, label)``: the model's units when given, else the label ``unit`` as it is."""
    if units is None:
        return (lambda v: v), unit
    u = Units.of(units)
    return (lambda v: u.show(kind, v)), u.unit(kind)


def _gaps(values: Any, ok: Any = None) -> np.ndarray:
    v = np.array(np.ravel(np.asarray(values)), dtype=complex if np.iscomplexobj(values) else float)
    if ok is not None:
        v[~np.ravel(np.asarray(ok, bool))] = np.nan
    return v


def _axes(ax: Any, figsize: tuple[float, float]) -> Axes:
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt  # pyplot's figure: plt.show() and notebooks show it

    return plt.figure(figsize=figsize, layout="constrained").add_subplot()


# --------------------------------------------------------------------------------------
# Transmission angle


def transmission_chart(
    theta2: Any,
    mu: Any,
    *,
    ok: Any = None,
    limit_deg: float = 40.0,
    x: Any = None,
    xlabel: str = "θ2 (deg)",
    where: str = "θ2",
    title: str = "transmission angle over the cycle",
) -> Chart:
    """μ (deg) over the cycle, the design limit, and the minimum marked.

    ``theta2`` are the input angles (radians); ``x`` the input as shown when
    it is not an angle in degrees (a slider's travel), labelled ``xlabel`` and
    named ``where`` in the note of the minimum.

    Examples
    --------
    >>> c = transmission_chart(np.radians([0, 90, 180]), np.radians([50, 30, 60]))
    >>> c.ylabel, c.notes[0][2]
    ('transmission angle μ (deg)', 'μ min = 30.00° at θ2 = 90.0°')
    >>> transmission_chart(None, np.radians([50, 30]), x=[1.0, 2.0], xlabel="s (mm)",
    ...                    where="s").notes[0][2]
    'μ min = 30.00° at s = 2 mm'
    """
    if x is None:
        x = np.degrees(np.ravel(theta2).astype(float))
        at = "{:.1f}°"
    else:
        x = np.ravel(np.asarray(x, float))
        at = "{:.4g} " + xlabel.rsplit("(", 1)[-1].rstrip(")") if "(" in xlabel else "{:.4g}"
        at = "{:.1f}°" if xlabel.endswith("(deg)") else at
    y = np.degrees(_gaps(mu, ok).astype(float))
    chart = Chart(
        title,
        xlabel,
        "transmission angle μ (deg)",
        [Series(x, y, "μ")],
        hlines=[(limit_deg, f"limit {limit_deg:g}°", "#d62728")],
        ylim=(0.0, 95.0),
    )
    if np.isfinite(y).any():
        k = int(np.nanargmin(y))
        chart.series.append(Series(x[k : k + 1], y[k : k + 1], colour="#d62728", marker=True))
        note = f"μ min = {y[k]:.2f}° at {where} = " + at.format(x[k])
        chart.notes.append((x[k], max(y[k] - 8.0, 4.0), note))
    chart.bands.append((x, np.zeros_like(x), np.full_like(x, limit_deg), "#ff9896"))
    return chart


def plot_transmission_angle(
    theta2: Any, mu: Any, *, ok: Any = None, limit_deg: float = 40.0, ax: Axes | None = None
) -> Axes:
    """The transmission angle μ over the cycle, with its limit (see :func:`transmission_chart`).

    Examples
    --------
    >>> from machdyn import FourBar
    >>> m = FourBar(8, 4, 7, 6).solve(np.radians(np.arange(0, 360.0)))
    >>> ax = plot_transmission_angle(m.theta2, m.mu)
    >>> ax.get_ylabel(), ax.get_xlabel()
    ('transmission angle μ (deg)', 'θ2 (deg)')
    """
    return transmission_chart(theta2, mu, ok=ok, limit_deg=limit_deg).to_mpl(_axes(ax, (7, 3.2)))


# --------------------------------------------------------------------------------------
# Pin forces


def pin_force_charts(
    forces: Mapping[str, Any],
    *,
    ok: Any = None,
    theta2: Any = None,
    unit: str = "force units",
    units: Any = None,
    where: str = "θ2",
) -> list[Chart]:
    """One polar chart per pin force, as Norton's programs draw them: the locus of the force's tip.

    The pin is at the origin, both axes at the same scale; the largest force
    is drawn as a point and named with its magnitude, direction and input angle.
    ``units`` (a model's :class:`~machdyn.units.UnitSystem`, or
    :class:`~machdyn.draw.units.Units`) converts the forces to its force unit
    and labels them; otherwise they are drawn as given and labelled ``unit``.
    ``theta2`` (radians) are the input angles named ``where`` in the titles.

    Examples
    --------
    >>> from machdyn.units import UnitSystem
    >>> c = pin_force_charts({"F32": [1000.0 + 0j, 2000j]}, units=UnitSystem(length="mm"))[0]
    >>> c.xlabel, c.title
    ('Fx (N)', 'F32: max |F| = 2 N, 90.0°')
    """
    if not forces:
        raise InputError("forces", "give at least one pin force")
    show, unit = _shown(units, "force", unit)
    charts = []
    for name, F in forces.items():
        F = show(_gaps(np.asarray(F, complex), ok))
        title = f"{name} (polar)"
        chart = Chart(
            title, f"Fx ({unit})", f"Fy ({unit})", [Series(F.real, F.imag, "")], equal=True
        )
        chart.series.append(Series(np.array([0.0]), np.array([0.0]), colour="#000", marker=True))
        if np.isfinite(F).any():
            k = int(np.nanargmax(np.abs(F)))
            z = F[k]
            at = "" if theta2 is None else f" at {where} = {np.degrees(np.ravel(theta2)[k]):.1f}°"
            chart = Chart(
                f"{name}: max |F| = {abs(z):.4g} {unit}, {np.degrees(np.angle(z)):.1f}°{at}",
                chart.xlabel,
                chart.ylabel,
                [
                    *chart.series,
                    Series(np.array([0, z.real]), np.array([0, z.imag]), colour="#d62728"),
                ],
                equal=True,
            )
        charts.append(chart)
    return charts


def plot_pin_forces(
    forces: Mapping[str, Any],
    *,
    ok: Any = None,
    theta2: Any = None,
    unit: str = "force units",
    units: Any = None,
    fig: Figure | None = None,
    columns: int = 2,
) -> Figure:
    """Polar plots of pin forces (see :func:`pin_force_charts`), one panel each.

    Examples
    --------
    >>> from machdyn import FourBar
    >>> th = np.radians(np.arange(0, 360.0, 5))
    >>> f = FourBar(8, 4, 7, 6).dynamics(th, 10.0, mass=(1, 2, 1.5), inertia=(.1, .5, .3),
    ...                                  cg=(2, 3.5, 3))
    >>> fig = plot_pin_forces({"F12": f.F12, "F32": f.F32}, theta2=th, unit="N")
    >>> fig.axes[0].get_xlabel()
    'Fx (N)'
    """
    charts = pin_force_charts(forces, ok=ok, theta2=theta2, unit=unit, units=units)
    return figure(charts, fig=fig, columns=columns, panel=(3.6, 3.4))


# --------------------------------------------------------------------------------------
# Torque and flywheel


def torque_chart(
    theta: Any,
    torque: Any,
    *,
    flywheel: Any = None,
    ok: Any = None,
    unit: str = "torque units",
    units: Any = None,
    name: str = "T12",
    xlabel: str = "θ2 (deg)",
) -> Chart:
    """The input torque over the cycle; with a flywheel, its lobes shaded and their areas labelled.

    ``flywheel`` is a :class:`~machdyn.flywheel.FlywheelResult` of the same
    curve: the mean torque is drawn, each lobe between the curve and it is
    shaded (red: energy taken from the flywheel, blue: given back) and labelled
    with its area ``ΔE`` (the notes' Table 11-1). ``units`` converts torques
    and energies to the model's units (else they are labelled ``unit``);
    ``name`` and ``xlabel`` name the effort and the input (``θ2 (deg)``).

    Examples
    --------
    >>> from machdyn.flywheel import size_flywheel
    >>> th = np.radians(np.arange(0, 360.0))
    >>> T = 20 + 5 * np.sin(2 * th)
    >>> c = torque_chart(th, T, flywheel=size_flywheel(th, T, 50.0, 0.05), unit="N·m")
    >>> sorted(t for _, _, t in c.notes)
    ['ΔE = -4.999', 'ΔE = -4.999', 'ΔE = 4.999', 'ΔE = 4.999']
    """
    show, unit = _shown(units, "torque", unit)
    energy, energy_unit = _shown(units, "energy", "")
    x = np.degrees(np.ravel(theta).astype(float))
    T = show(_gaps(torque, ok).astype(float))
    chart = Chart(
        "input torque",
        xlabel,
        f"input torque {name} ({unit})",
        [Series(x, T, name, colour="#000")],
        hlines=[(0.0, "", "#999")],
    )
    if flywheel is None:
        if np.isfinite(T).any():
            k = int(np.nanargmax(np.abs(T)))
            chart.series.append(Series(x[k : k + 1], T[k : k + 1], colour="#d62728", marker=True))
            chart.notes.append((x[k], T[k], f"{T[k]:.4g} {unit} at {x[k]:.1f}°"))
        return chart
    avg = float(show(float(flywheel.torque_avg)))
    th = np.degrees(np.asarray(flywheel.theta, float))
    Tf = show(np.asarray(flywheel.torque, float))
    eu = f" {energy_unit}" if energy_unit else ""
    above = np.where(Tf >= avg, Tf, avg)
    below = np.where(Tf < avg, Tf, avg)
    chart.bands.append((th, np.full_like(th, avg), above, "#d62728"))
    chart.bands.append((th, below, np.full_like(th, avg), "#1f77b4"))
    chart.hlines.append((avg, f"T avg = {avg:.4g} {unit}", "#2ca02c"))
    lobes = flywheel.lobes
    t0 = float(th[0])
    for a, b, area in zip(
        np.degrees(lobes.theta_from), np.degrees(lobes.theta_to), lobes.area, strict=True
    ):
        if b < a:
            b += 360.0
        mid = t0 + (0.5 * (a + b) - t0) % 360.0
        y = float(np.interp(mid, th, Tf))
        chart.notes.append((mid, 0.5 * (y + avg), f"ΔE = {float(energy(area)):.4g}{eu}"))
    # the largest lobes first: where labels would collide, the chart drops the later
    # (smaller) ones; every lobe's ΔE stays in the report's lobe table
    order = np.argsort(-np.abs(np.asarray(lobes.area, float)), kind="stable")
    chart.notes[:] = [chart.notes[int(i)] for i in order]
    inertia, inertia_unit = _shown(units, "inertia", "")
    iu = f" {inertia_unit}" if inertia_unit else ""
    return Chart(
        f"input torque and flywheel lobes: ΔE = {float(energy(flywheel.delta_e)):.4g}{eu}, "
        f"I = {float(inertia(flywheel.inertia)):.4g}{iu} for k = {flywheel.k:g}",
        chart.xlabel,
        chart.ylabel,
        chart.series,
        chart.bands,
        chart.hlines,
        chart.notes,
    )


def plot_torque(
    theta: Any,
    torque: Any,
    *,
    flywheel: Any = None,
    ok: Any = None,
    unit: str = "torque units",
    units: Any = None,
    ax: Axes | None = None,
) -> Axes:
    """The input torque over the cycle with the flywheel's lobes (see :func:`torque_chart`).

    Examples
    --------
    >>> from machdyn.flywheel import size_flywheel
    >>> th = np.radians(np.arange(0, 360.0))
    >>> T = 20 + 5 * np.sin(2 * th)
    >>> ax = plot_torque(th, T, flywheel=size_flywheel(th, T, 50.0, 0.05), unit="N·m")
    >>> len([t for t in ax.texts if t.get_text().startswith("ΔE")])
    4
    """
    chart = torque_chart(theta, torque, flywheel=flywheel, ok=ok, unit=unit, units=units)
    return chart.to_mpl(_axes(ax, (7, 3.4)))


# --------------------------------------------------------------------------------------
# Shaking


def shaking_charts(
    before: Any,
    after: Any = None,
    *,
    moment_before: Any = None,
    moment_after: Any = None,
    theta: Any = None,
    force_unit: str = "force units",
    torque_unit: str = "torque units",
    units: Any = None,
    xlabel: str = "θ2 (deg)",
    about: str = "O2",
    closed: bool = False,
) -> list[Chart]:
    """The shaking force as a polar chart before/after balancing, and the shaking moment.

    ``units`` converts forces and moments to a model's units (else they are
    labelled ``force_unit`` and ``torque_unit``); ``about`` names the point the
    moment is taken about (in the moment chart's title); ``closed``: the samples
    are one whole cycle, so each polar trace returns to its first point.
    """
    force, force_unit = _shown(units, "force", force_unit)
    torque, torque_unit = _shown(units, "torque", torque_unit)
    # the origin first, so a balanced trace (a dot there) is drawn over it
    series = [Series(np.array([0.0]), np.array([0.0]), colour="#000", marker=True)]
    peak = 0.0
    # "before"/"after" only when there is an after: unbalanced alone is just the shaking force
    both = after is not None
    for z, label, colour in (
        (before, "before balancing" if both else "shaking force", "#d62728"),
        (after, "after balancing", "#2ca02c"),
    ):
        if z is not None:
            z = force(np.ravel(np.asarray(z, complex)))
            if closed and z.size:
                z = np.append(z, z[0])
            good = z[np.isfinite(z)]
            top = float(np.abs(good).max()) if good.size else 0.0
            extent = max(np.ptp(good.real), np.ptp(good.imag)) if good.size else 0.0
            dot = extent <= 1e-6 * peak  # a constant force: a line of no length shows nothing
            series.append(
                Series(z.real, z.imag, f"{label}: max {top:.4g}", colour=colour, marker=dot)
            )
            peak = max(peak, top)
    charts = [
        Chart(
            f"shaking force (polar), {force_unit}",
            f"Fs x ({force_unit})",
            f"Fs y ({force_unit})",
            series,
            equal=True,
        )
    ]
    if moment_before is not None and theta is not None:
        x = np.degrees(np.ravel(theta).astype(float))
        before_m = torque(np.ravel(moment_before).astype(float))
        ms = [Series(x, before_m, "before" if moment_after is not None else "", colour="#d62728")]
        if moment_after is not None:
            after_m = torque(np.ravel(moment_after).astype(float))
            ms.append(Series(x, after_m, "after", colour="#2ca02c", dashed=True))
        charts.append(
            Chart(f"shaking moment about {about}", xlabel, f"shaking moment Ms ({torque_unit})", ms)
        )
    return charts


def plot_shaking(
    before: Any,
    after: Any = None,
    *,
    moment_before: Any = None,
    moment_after: Any = None,
    theta: Any = None,
    force_unit: str = "force units",
    torque_unit: str = "torque units",
    units: Any = None,
    fig: Figure | None = None,
) -> Figure:
    """Shaking force polar plot before/after balancing, and the moment (:func:`shaking_charts`).

    Examples
    --------
    >>> th = np.radians(np.arange(0, 360.0, 5))
    >>> fig = plot_shaking(3 * np.exp(1j * th), 0.1 * np.exp(2j * th), theta=th, force_unit="N")
    >>> fig.axes[0].get_xlabel()
    'Fs x (N)'
    """
    charts = shaking_charts(
        before,
        after,
        moment_before=moment_before,
        moment_after=moment_after,
        theta=theta,
        force_unit=force_unit,
        torque_unit=torque_unit,
        units=units,
    )
    return figure(charts, fig=fig, columns=len(charts), panel=(4.2, 3.8))


# --------------------------------------------------------------------------------------
# Cams


def cam_charts(
    profile: Any,
    *,
    max_pressure_angle_deg: float = 30.0,
    length_unit: str | None = None,
    units: Any = None,
) -> list[Chart]:
    """SVAJ of a cam with its pressure angle and radius of curvature beside it.

    Six charts against the cam angle θ (deg): s, v (per rad), a (per rad²),
    j (per rad³) — the notes' svaj diagrams — then the pressure angle φ with its
    limit (shaded beyond ±limit) and the radii of curvature of the pitch curve
    and of the surface, with the roller radius drawn (a convex pitch radius
    below it undercuts, Norton §8.7; negative ρ is concave). Values beyond
    ±10 × the base radius (near inflections ρ → ∞) are left out as gaps.
    Lengths are in ``units``' length unit (a model's unit system), or
    ``length_unit``, or "model units"; an oscillating follower's s is its arm
    angle, drawn in degrees (v, a, j in rad per radian of cam angle).

    Examples
    --------
    >>> from machdyn import cams
    >>> prog = cams.CamProgram([cams.Segment("rise", np.pi / 2, 1.0, "cycloidal"),
    ...                         cams.Segment("fall", np.pi / 2, 1.0, "cycloidal"),
    ...                         cams.Segment("dwell", np.pi)])
    >>> cam = cams.TranslatingRoller(prime_radius=3.0, roller_radius=0.5).profile(prog)
    >>> [c.ylabel for c in cam_charts(cam)]  # doctest: +NORMALIZE_WHITESPACE
    ['s (model units)', 'v (model units/rad)', 'a (model units/rad²)', 'j (model units/rad³)',
     'pressure angle φ (deg)', 'radius of curvature ρ (model units)']
    """
    length, u = _shown(units, "length", length_unit or "model units")
    x = np.degrees(np.asarray(profile.theta, float))
    xlabel = "cam angle θ (deg)"
    if profile.follower == "oscillating roller":  # s is the arm's angle (radians)
        svaj = [np.degrees(np.asarray(profile.s, float))] + [
            np.asarray(getattr(profile, q), float) for q in "vaj"
        ]
        units_of = ("deg", "rad/rad", "rad/rad²", "rad/rad³")
        names = ("arm angle s", "v", "a", "j")
    else:
        svaj = [np.asarray(length(np.asarray(getattr(profile, q), float))) for q in "svaj"]
        units_of = (u, f"{u}/rad", f"{u}/rad²", f"{u}/rad³")
        names = ("s", "v", "a", "j")
    titles = ("follower displacement", "velocity", "acceleration", "jerk")
    charts = [
        Chart(
            title,
            xlabel,
            f"{name} ({unit})",
            [Series(x, y, name.split()[-1], gid="svaj"[k])],
            hlines=[(0.0, "", "#999")] if k else [],
        )
        for k, (title, name, unit, y) in enumerate(zip(titles, names, units_of, svaj, strict=True))
    ]
    phi = np.degrees(np.asarray(profile.pressure_angle, float))
    lim = float(max_pressure_angle_deg)
    top = max(lim * 1.3, float(np.nanmax(np.abs(phi))) * 1.1 if phi.size else lim)
    pa = Chart(
        "pressure angle",
        "cam angle θ (deg)",
        "pressure angle φ (deg)",
        [Series(x, phi, "φ")],
        hlines=[(lim, f"limit ±{lim:g}°", "#d62728"), (-lim, "", "#d62728")],
        ylim=(-top, top),
    )
    pa.bands.append((x, np.full_like(x, lim), np.full_like(x, top), "#ff9896"))
    pa.bands.append((x, np.full_like(x, -top), np.full_like(x, -lim), "#ff9896"))
    if phi.size:
        k = int(np.nanargmax(np.abs(phi)))
        pa.series.append(Series(x[k : k + 1], phi[k : k + 1], colour="#d62728", marker=True))
        pa.notes.append((x[k], phi[k] * 0.8, f"|φ| max = {abs(phi[k]):.2f}° at {x[k]:.1f}°"))
    charts.append(pa)
    cap = 10.0 * max(float(profile.base_radius), 1e-12)
    clip = lambda r: length(np.where(np.abs(r) <= cap, r, np.nan))  # noqa: E731
    rho = [Series(x, clip(np.asarray(profile.rho_surface, float)), "ρ surface")]
    if profile.rho_pitch is not None:
        rho.insert(0, Series(x, clip(np.asarray(profile.rho_pitch, float)), "ρ pitch curve"))
    rc = Chart(
        "radius of curvature",
        xlabel,
        f"radius of curvature ρ ({u})",
        rho,
        hlines=[(0.0, "", "#999")],
    )
    if profile.roller_radius > 0:
        rf = float(length(float(profile.roller_radius)))
        rc.hlines.append((rf, f"roller radius {rf:g}", "#d62728"))
    under = np.asarray(profile.undercut, bool)
    if under.any():
        y = np.where(under, 0.0, np.nan)
        rc.series.append(Series(x, y, "undercut", colour="#d62728", width=5.0))
    charts.append(rc)
    return charts


def plot_cam_design(
    profile: Any,
    *,
    max_pressure_angle_deg: float = 30.0,
    units: Any = None,
    fig: Figure | None = None,
) -> Figure:
    """SVAJ with the pressure angle and radius of curvature beside it (see :func:`cam_charts`).

    Examples
    --------
    >>> from machdyn import cams
    >>> prog = cams.CamProgram([cams.Segment("rise", np.pi / 2, 1.0, "cycloidal"),
    ...                         cams.Segment("fall", np.pi / 2, 1.0, "cycloidal"),
    ...                         cams.Segment("dwell", np.pi)])
    >>> cam = cams.TranslatingRoller(prime_radius=3.0, roller_radius=0.5).profile(prog)
    >>> fig = plot_cam_design(cam)
    >>> len(fig.axes)
    6
    """
    charts = cam_charts(profile, max_pressure_angle_deg=max_pressure_angle_deg, units=units)
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(11, 8), layout="constrained")
    axes = fig.subplots(4, 2, squeeze=False)
    order = [axes[0, 0], axes[1, 0], axes[2, 0], axes[3, 0], axes[0, 1], axes[1, 1]]
    for ax, chart in zip(order, charts, strict=True):
        chart.to_mpl(ax)
    for ax in (axes[2, 1], axes[3, 1]):
        ax.remove()
    return fig
