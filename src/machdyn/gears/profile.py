"""Tooth profiles: involute flanks, tip, and the root fillet cut by a rack.

An external gear's outline is *generated* the way a hob or rack cutter cuts
it: the cutter — the basic rack of the gear's proportions, its tip corners
rounded to radius ``ρ`` — rolls with its rolling line on the pitch circle,
offset outward by the profile shift ``x m``. Its straight flanks envelop the
involute; its rounded tips envelop the root fillet, a curve parallel (at
``ρ``) to the trochoid of the tip-round centre. When the cutter's flank
reaches past the interference point, the fillet cuts into the involute:
that is undercut (Norton Figure 9-12), reported by :attr:`GearOutline.undercut`.

The envelope point of the tip round is found from the law of gearing: its
normal passes through the pitch point ``I``, so it is ``C + ρ (C − I)/|C − I|``
with ``C`` the tip-round centre in the gear frame.

An internal gear is generated the same way by a pinion-type shaper cutter
(a small external gear with rounded tips) rolling inside it; its fillet is
the envelope of the cutter's tip rounds. A profile-shifted ring (shift ``x``)
is cut by a cutter carrying the same shift — tooth ``π m / 2 + 2 x m tan φ``,
addendum ``(k_d + x) m`` — at the standard cutting distance ``R − r_c``; the
ring's involute is the same as from an unshifted cutter fed to the
corresponding distance, and its root circle is the ring's nominal
``R + (k_d + x) m``. :func:`cutter_teeth_range` says which cutters can cut a
ring. (Undercut of internal gears is not checked.)

Everything is vectorised: one tooth is built from arrays of parameters, the
gear by broadcasting the tooth over the ``N`` angular positions.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._validate import (
    boolean,
    count,
    finite_scalar,
    instance,
    integer,
    nonnegative,
    point,
)
from ..errors import InputError, MachdynError
from .geometry import Gear, involute

__all__ = [
    "GearOutline",
    "cutter_teeth_range",
    "default_cutter_teeth",
    "default_tip_radius",
    "gear_outline",
    "plot_mesh",
]

#: Fewest teeth between a ring and its shaper cutter (a shop rule of thumb against the
#: cutter's tips fouling the ring's tips as it is fed in and withdrawn, not derived here).
CUTTER_TEETH_DIFFERENCE = 8


def cutter_teeth_range(gear: Gear) -> tuple[int, int]:
    """Fewest and most teeth of a pinion-type shaper cutter that can cut an internal gear.

    The cutter has the ring's module and pressure angle, a tooth as thick as
    the ring's space and an addendum equal to the ring's dedendum; it meshes
    with the ring at the cutting centre distance ``R − r_c``. It generates the
    ring's involute only where the contact lies on its own involute, outside
    its base circle. The ring's tip circle cuts the line of action
    ``R sin φ − √(r_a² − r_b²)`` from the pitch point, towards the cutter's
    tangent point, which is ``r_c sin φ`` from it; so the whole flank, up to
    the ring's tip, is generated (no involute interference, the same
    condition as :attr:`GearPair.interference` for a pinion in a ring) if

    ``N_c >= (2 / m) (R − √(r_a² − r_b²) / sin φ)``.

    For a very large ring this tends to the minimum pinion against a rack
    (Norton Table 9-4: 32, 18, 12 teeth at 14.5°, 20°, 25° full depth). The
    cutter's own teeth must also not be pointed at its tip circle. The upper
    limit ``N − 8`` is a shop rule of thumb against the cutter's tips fouling
    the ring's tips when it is fed in and withdrawn, not a derivation.

    Parameters
    ----------
    gear : Gear
        An internal gear.

    Returns
    -------
    (int, int)
        Fewest and most cutter teeth, inclusive.

    Raises
    ------
    InputError
        If the gear is not internal, or no cutter fits (the fewest exceed the
        most: use a shorter addendum, a larger pressure angle or more teeth).

    Examples
    --------
    >>> cutter_teeth_range(Gear(40, module=1.0, internal=True))
    (24, 32)
    >>> cutter_teeth_range(Gear(2000, module=1.0, internal=True))[0]  # a rack: Table 9-4
    18
    """
    instance("gear", gear, Gear)
    if not isinstance(gear, Gear) or not gear.internal:
        raise InputError("gear", "only an internal gear is cut by a shaper cutter here")
    m, phi, n = gear.module, gear.pressure_angle, gear.teeth
    z_tip = math.sqrt(gear.addendum_radius**2 - gear.base_radius**2)
    by_interference = math.ceil(2.0 / m * (gear.pitch_radius - z_tip / math.sin(phi)) - 1e-9)
    # Pointed cutter teeth: the half-angle of the tooth at the cutter's tip circle, for every
    # candidate at once (the tip of a cutter of N_c teeth is at m N_c / 2 + b).
    n_c = np.arange(3, n)
    r_c = m * n_c / 2.0
    phi_tip = np.arccos(r_c * math.cos(phi) / (r_c + gear.dedendum))
    half = gear.space_width / (2.0 * r_c) + float(involute(phi)) - involute(phi_tip)
    sharp = n_c[half <= 0.0]
    by_point = int(sharp.max()) + 1 if sharp.size else 3
    low, high = max(by_interference, by_point, 3), n - CUTTER_TEETH_DIFFERENCE
    if low > high:
        raise InputError(
            "teeth",
            f"no shaper cutter can cut this {n}-tooth ring: it needs at least {low} teeth"
            f" (fewer are pointed or cannot generate the flanks up to the ring's tip) and at"
            f" most {high}; use more teeth, a shorter addendum, a larger pressure angle or"
            " a smaller profile shift",
        )
    return low, high


def default_cutter_teeth(gear: Gear) -> int:
    """Shaper-cutter teeth used for an internal gear unless told otherwise.

    ``max(12, min(25, N // 2))``, raised or lowered into
    :func:`cutter_teeth_range`.

    Examples
    --------
    >>> default_cutter_teeth(Gear(120, module=1.0, internal=True))
    25
    >>> default_cutter_teeth(Gear(40, module=1.0, internal=True))  # 20 would interfere
    24
    """
    instance("gear", gear, Gear)
    low, high = cutter_teeth_range(gear)
    return min(max(max(12, min(25, gear.teeth // 2)), low), high)


def default_tip_radius(gear: Gear) -> float:
    """Largest cutter tip round that fits: ``ρ = c / (1 − sin φ)`` if the tooth tip allows.

    With this radius the straight part of the cutter flank ends exactly at
    the addendum line of the basic rack (``k m`` below the datum), which is
    what the minimum-teeth and undercut relations assume. For full depth at
    20° it is ``0.38 m`` (ISO 53 profile A). Where the cutter's tip is too
    narrow for that (25° full depth), the full round of the tip is used:
    ``ρ = (π m / 4 + Δs / 2 − h tan φ) cos φ / (1 − sin φ)``.

    Examples
    --------
    >>> round(default_tip_radius(Gear(20, module=1.0)), 3)
    0.38
    >>> round(default_tip_radius(Gear(20, module=1.0, pressure_angle=math.radians(25))), 3)
    0.3
    """
    instance("gear", gear, Gear)
    phi = gear.pressure_angle
    h_f = gear.dedendum + gear.profile_shift * gear.module
    by_clearance = gear.clearance / (1.0 - math.sin(phi))
    half_tip = math.pi * gear.module / 4 + gear.thickness_reduction / 2 - h_f * math.tan(phi)
    by_tip = half_tip * math.cos(phi) / (1.0 - math.sin(phi))
    return min(by_clearance, by_tip)


@dataclass(frozen=True)
class GearOutline:
    """Closed outline of a whole gear (or one tooth), with export and plotting.

    Attributes
    ----------
    x, y : ndarray
        Outline points, counter-clockwise, not repeating the first point.
    segment : ndarray of str
        What each point lies on: ``"root"``, ``"fillet"``, ``"involute"``,
        ``"tip"``.
    teeth : int
        Number of teeth of the gear.
    internal : bool
        True for an internal (ring) gear.
    fillet : str
        ``"trochoid"``: the envelope of the generating cutter's tip round (a
        rack for external gears, a shaper cutter for internal ones).
    undercut : bool
        True if the generating cutter undercuts the involute.
    form_radius : float
        Radius where the involute begins (its lowest point actually cut).

    Examples
    --------
    >>> out = gear_outline(Gear(12, module=1.0))
    >>> out.undercut, round(out.form_radius, 3)  # undercut: the involute starts above r_b
    (True, 5.651)
    >>> out.to_pandas()["segment"].unique().tolist()
    ['root', 'fillet', 'involute', 'tip']
    """

    x: NDArray[np.float64]
    y: NDArray[np.float64]
    segment: NDArray[np.str_]
    teeth: int
    internal: bool
    fillet: str
    undercut: bool
    form_radius: float

    def to_pandas(self) -> Any:
        """Return the points as a DataFrame with columns ``x, y, segment``.

        Examples
        --------
        >>> gear_outline(Gear(20, module=1.0), points=10).to_pandas().shape
        (880, 3)
        """
        import pandas as pd

        return pd.DataFrame({"x": self.x, "y": self.y, "segment": self.segment})

    def to_csv(self, path: str | Path) -> Path:
        """Write ``x,y,segment`` rows (with a header) to ``path``.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> out = gear_outline(Gear(12, module=1.0, profile_shift=0.3), points=8)
        >>> with tempfile.TemporaryDirectory() as d:
        ...     p = out.to_csv(pathlib.Path(d) / "g.csv")
        ...     p.read_text().splitlines()[0]
        'x,y,segment'
        """
        path = Path(path)
        with path.open("w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(["x", "y", "segment"])
            writer.writerows(zip(self.x.tolist(), self.y.tolist(), self.segment, strict=True))
        return path

    def to_svg(
        self,
        path: str | Path | None = None,
        stroke_width: float | None = None,
        unit: str | None = None,
    ) -> str:
        """Return (and optionally write) an SVG document of the closed outline.

        The y axis is flipped so that the drawing appears as in the x–y plane.
        One drawing unit is one length unit of the gear; with ``unit`` (the
        length unit of the gear's numbers, ``"mm"``, ``"in"``) the document's
        width and height say its true size in millimetres.

        Examples
        --------
        >>> svg = gear_outline(Gear(20, module=1.0), points=10).to_svg()
        >>> svg.startswith("<svg") and "<polygon" in svg
        True
        """
        x, y = self.x, -self.y
        pad = 0.05 * float(np.ptp(x) + np.ptp(y)) / 2
        x0, y0 = float(x.min()) - pad, float(y.min()) - pad
        w, h = float(np.ptp(x)) + 2 * pad, float(np.ptp(y)) + 2 * pad
        sw = stroke_width if stroke_width is not None else w / 500
        pts = " ".join(f"{a:.6g},{b:.6g}" for a, b in zip(x.tolist(), y.tolist(), strict=True))
        from ..units import svg_size

        svg = (
            f'<svg xmlns="http://www.w3.org/2000/svg" {svg_size(w, h, unit)}'
            f'viewBox="{x0:.6g} {y0:.6g} {w:.6g} {h:.6g}">\n'
            f'  <polygon points="{pts}" fill="none" stroke="black" stroke-width="{sw:.3g}"/>\n'
            "</svg>\n"
        )
        if path is not None:
            Path(path).write_text(svg)
        return svg

    def to_dxf(self, path: str | Path, unit: str | None = None) -> Path:
        """Write the outline as one closed LWPOLYLINE to a DXF file (needs ezdxf).

        ``unit`` is the length unit of the gear's numbers: the file's
        ``$INSUNITS`` says so (without it, 0: unitless).

        Examples
        --------
        >>> import tempfile, pathlib
        >>> with tempfile.TemporaryDirectory() as d:
        ...     path = gear_outline(Gear(20, module=1.0)).to_dxf(pathlib.Path(d) / "g.dxf")
        ...     path.stat().st_size > 0
        True
        """
        try:
            import ezdxf
        except ImportError:  # pragma: no cover - ezdxf is in the test extras
            raise MachdynError("DXF export needs ezdxf: pip install 'machdyn[dxf]'") from None
        from ..units import set_dxf_units

        doc = ezdxf.new()
        set_dxf_units(doc, unit)
        doc.modelspace().add_lwpolyline(
            np.column_stack([self.x, self.y]).tolist(), format="xy", close=True
        )
        path = Path(path)
        doc.saveas(path)
        return path

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Draw the closed outline on matplotlib axes (created if not given).

        Examples
        --------
        >>> import matplotlib.pyplot as plt
        >>> ax = gear_outline(Gear(20, module=1.0)).plot()
        >>> len(ax.patches)
        1
        >>> plt.close("all")
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        ax.fill(self.x, self.y, **({"fill": False, "lw": 0.8} | kwargs))
        ax.set_aspect("equal")
        return ax


def _flank_polar(gear: Gear, points: int, tip_radius: float | None) -> tuple[Any, ...]:
    """Upper half of an external tooth in polar form, from the tip down to the root.

    Returns ``(r, psi, segment, undercut, form_radius)`` with ``psi`` the
    polar angle from the tooth's centre line.
    """
    m, phi, x = gear.module, gear.pressure_angle, gear.profile_shift
    rp, rb, ra, rf = gear.pitch_radius, gear.base_radius, gear.addendum_radius, gear.root_radius
    tan_phi = math.tan(phi)
    rho = default_tip_radius(gear) if tip_radius is None else tip_radius
    h_f = gear.dedendum + x * m  # cutter addendum below its datum line (unshifted dedendum)
    if not 0.0 <= rho < h_f:
        raise InputError("tip_radius", f"must be between 0 and the dedendum {h_f:g}")

    # Cutter (rack) coordinates: u along the datum line, v depth towards the gear centre.
    # Flank of the cutter tooth next to the gear tooth centred at u = 0:
    #   u_f(v) = π m / 4 − Δs / 2 + v tan φ.
    u0 = math.pi * m / 4 - gear.thickness_reduction / 2
    v_c = h_f - rho  # tip-round centre depth
    u_c = u0 + v_c * tan_phi + rho / math.cos(phi)
    if u_c > math.pi * m / 2 + 1e-12 * m:
        raise InputError("tip_radius", f"{rho:g} is too large for the cutter tooth tip")
    if v_c - x * m <= 0.0:
        raise InputError(
            "profile_shift",
            f"{x:g} lifts the cutter's tip round above the pitch circle; the rack cannot"
            " generate this gear (use a smaller shift or tip radius)",
        )

    # The rack point (u, v) sits at (r_p + x m − v) e_r(θ) + (u − r_p θ) e_t(θ) in the gear
    # frame, and the pitch point at r_p e_r(θ). Root contact at θ_0, flank tangency at θ_1.
    theta0 = u_c / rp
    theta1 = (u_c + (v_c - x * m) / tan_phi) / rp

    def fillet(theta: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        # Relative to e_r(θ), e_t(θ): tip-round centre C = (radial, tangential), I = (r_p, 0);
        # the envelope point is C + ρ (C − I) / |C − I|.
        radial = rp + x * m - v_c
        tangential = u_c - rp * theta
        norm = np.hypot(radial - rp, tangential)
        er = radial + rho * (radial - rp) / norm
        et = tangential + rho * tangential / norm
        return np.hypot(er, et), theta + np.arctan2(et, er)

    # Involute half-angle at radius r: s/(2 r_p) + inv φ − inv φ_r.
    half0 = gear.tooth_thickness / (2 * rp) + float(involute(phi))

    def psi_inv(r: NDArray[np.float64]) -> NDArray[np.float64]:
        return half0 - involute(np.arccos(np.clip(rb / r, -1.0, 1.0)))

    # Undercut: the fillet crosses into the tooth above the base circle. The gap is measured
    # against the involute continued radially below the base circle (positive: the fillet
    # lies inside the tooth there); the last inside→outside crossing ends the cut fillet.
    # A dense sampling finds the crossing, which can sit very close to the base circle.
    dense = np.linspace(theta0, theta1, max(8192, points))
    r_dense, psi_dense = fillet(dense)
    gap = psi_inv(np.maximum(r_dense, rb)) - psi_dense
    tol = 1e-12
    crossing = np.flatnonzero((gap[:-1] > tol) & (gap[1:] <= tol))
    undercut = False
    theta_end = theta1
    if crossing.size:
        i = int(crossing[-1])
        w = gap[i] / (gap[i] - gap[i + 1])
        r_cross = float(r_dense[i] + w * (r_dense[i + 1] - r_dense[i]))
        if r_cross > rb * (1 + 1e-12) and i < dense.size - 2:
            undercut = True
            theta_end = float(dense[i] + w * (dense[i + 1] - dense[i]))
    r_fil, psi_fil = fillet(np.linspace(theta0, theta_end, points))
    if undercut:
        psi_fil[-1] = psi_inv(np.array(r_fil[-1]))  # close exactly on the involute
    r_form = float(r_fil[-1])
    if r_form >= ra:
        raise InputError("teeth", "the cutter removes the whole involute: the tooth is cut away")

    r_inv = np.linspace(ra, r_form, points)
    psi_tip_edge = float(psi_inv(np.array(ra)))
    n_tip = max(2, points // 4)
    psi_tip = np.linspace(0.0, psi_tip_edge, n_tip, endpoint=False)
    root_end = math.pi / gear.teeth
    # No root arc when the cutter's full tip round meets the space centre.
    n_root = max(2, points // 4) if root_end - theta0 > 1e-9 * root_end else 0
    psi_root = np.linspace(theta0, root_end, n_root + 1)[1:]

    # Tip (centre line → edge), involute (tip → form), fillet (form → root), root arc.
    fil_r, fil_psi = r_fil[::-1][1:], psi_fil[::-1][1:]
    r = np.concatenate([np.full(n_tip, ra), r_inv, fil_r, np.full(n_root, rf)])
    psi = np.concatenate([psi_tip, psi_inv(r_inv), fil_psi, psi_root])
    segment = np.concatenate(
        [
            np.full(n_tip, "tip"),
            np.full(points, "involute"),
            np.full(fil_r.size, "fillet"),
            np.full(n_root, "root"),
        ]
    )
    return r, psi, segment, bool(undercut), r_form


def _shaper_tip_centre(
    r_base: float, half0: float, r_tip: float, rho: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Centre of a cutter's tip round of radius ``rho`` and the flank's inward normal there.

    The round touches the cutter's tip circle ``r_tip`` (centre at ``r_tip − ρ``)
    and its upper involute flank (half-angle ``half0 − inv φ_r``). The normal
    of an involute runs to its base-circle tangent point.
    """
    from scipy.optimize import brentq

    def flank(f: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        psi = half0 - float(involute(f))
        p = r_base / math.cos(f) * np.array([math.cos(psi), math.sin(psi)])
        roll = half0 - math.tan(f)
        t = r_base * np.array([math.cos(roll), math.sin(roll)])
        return p, (t - p) / np.linalg.norm(t - p)

    def miss(f: float) -> float:
        p, n = flank(f)
        return float(np.linalg.norm(p + rho * n)) - (r_tip - rho)

    f_tip = math.acos(r_base / r_tip)
    if miss(1e-9) > 0:
        raise InputError("tip_radius", f"{rho:g} is too large for the shaper cutter's teeth")
    p, n = flank(brentq(miss, 1e-9, f_tip, xtol=1e-15))
    return p + rho * n, n


def _shaper_fillet(
    gear: Gear, points: int, cutter_teeth: int, tip_radius: float | None
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Root fillet of an internal gear cut by a pinion-type shaper cutter.

    The cutter (``cutter_teeth`` teeth, same module and pressure angle, tooth
    thickness equal to the ring's space width, addendum equal to the ring's
    dedendum, tip rounds of radius ``ρ``) rolls inside the ring: its centre
    orbits at ``a = R − r_c`` and it turns ``−γ a / r_c`` while the line of
    centres turns ``γ``. The envelope point of the tip round is
    ``C + ρ (C − I) / |C − I|`` with ``I`` the pitch point, as for the rack.

    Returns ``(r, psi)`` from the root circle to the start of the involute,
    ``psi`` measured from the centre of the ring's space.
    """
    from scipy.optimize import brentq

    m, phi = gear.module, gear.pressure_angle
    big_r = gear.pitch_radius
    r_c = m * cutter_teeth / 2
    r_bc, a = r_c * math.cos(phi), big_r - r_c
    r_tip = r_c + gear.dedendum
    half0 = gear.space_width / (2 * r_c) + float(involute(phi))

    def centre_angle(rho: float) -> float:
        c, _ = _shaper_tip_centre(r_bc, half0, r_tip, rho)
        return math.atan2(c[1], c[0])

    if tip_radius is None:
        # As for the rack, c / (1 − sin φ), but no more than a full round of the tip.
        rho = gear.clearance / (1.0 - math.sin(phi))
        if centre_angle(rho) < 0:
            rho = brentq(centre_angle, 1e-6 * m, rho, xtol=1e-12 * m)
    else:
        rho = tip_radius
        if not 0.0 <= rho < gear.dedendum or centre_angle(rho) < -1e-12:
            raise InputError("tip_radius", f"{rho:g} does not fit the shaper cutter's tooth tip")
    c, n = _shaper_tip_centre(r_bc, half0, r_tip, rho)
    r_cc, psi_cc = float(np.hypot(*c)), math.atan2(c[1], c[0])
    alpha_flank = math.atan2(-n[1], -n[0])  # contact direction at the flank tangency

    def envelope(gamma: NDArray[np.float64]) -> tuple[Any, Any, Any]:
        turn = -gamma * a / r_c
        cx = a * np.cos(gamma) + r_cc * np.cos(turn + psi_cc)
        cy = a * np.sin(gamma) + r_cc * np.sin(turn + psi_cc)
        dx, dy = cx - big_r * np.cos(gamma), cy - big_r * np.sin(gamma)
        norm = np.hypot(dx, dy)
        # Contact direction on the tip round, in the cutter's frame.
        alpha = np.unwrap(np.arctan2(dy, dx) - turn)
        return cx + rho * dx / norm, cy + rho * dy / norm, alpha

    # Contact runs from the tip land (α = ψ_C, on the root circle) to the flank (α_flank).
    gamma = np.linspace(-4 * math.pi / cutter_teeth * r_c / a, 0.5 * math.pi * m / a, 40001)
    _, _, alpha = envelope(gamma)
    d_tip = alpha - psi_cc
    tips = np.flatnonzero((d_tip[:-1] > 0) & (d_tip[1:] <= 0))
    if tips.size == 0:  # pragma: no cover - geometry guarantees a crossing
        raise InputError("cutter_teeth", "the shaper cutter does not reach the root")
    i = int(tips[-1])
    g_tip = gamma[i] - d_tip[i] * (gamma[i + 1] - gamma[i]) / (d_tip[i + 1] - d_tip[i])
    d_flank = alpha[: i + 1] - alpha_flank
    flanks = np.flatnonzero((d_flank[:-1] >= 0) & (d_flank[1:] < 0))
    if flanks.size == 0:  # pragma: no cover
        raise InputError("cutter_teeth", "the shaper cutter's tip round never meets its flank")
    j = int(flanks[-1])
    g_flank = gamma[j] - d_flank[j] * (gamma[j + 1] - gamma[j]) / (d_flank[j + 1] - d_flank[j])
    ex, ey, _ = envelope(np.linspace(g_tip, g_flank, points))
    return np.hypot(ex, ey), np.arctan2(ey, ex)


def _internal_flank_polar(
    gear: Gear, points: int, cutter_teeth: int, tip_radius: float | None
) -> tuple[Any, ...]:
    """Upper half of an internal gear's tooth: tip (inner), involute, fillet, root (outer)."""
    rb, ra, rf, n = gear.base_radius, gear.addendum_radius, gear.root_radius, gear.teeth
    r_fil, space_fil = _shaper_fillet(gear, points, cutter_teeth, tip_radius)
    r_form = float(r_fil[-1])
    space0 = gear.space_width / (2 * gear.pitch_radius) + float(involute(gear.pressure_angle))
    r_inv = np.linspace(ra, r_form, points)
    # Tooth half-angle = half the angular pitch minus the space half-angle.
    psi_inv = math.pi / n - (space0 - involute(np.arccos(rb / r_inv)))
    n_arc = max(2, points // 4)
    psi_tip = np.linspace(0.0, psi_inv[0], n_arc, endpoint=False)
    fil_r, fil_psi = r_fil[::-1][1:], math.pi / n - space_fil[::-1][1:]
    root_start = float(fil_psi[-1])
    n_root = n_arc if math.pi / n - root_start > 1e-9 / n else 0
    psi_root = np.linspace(root_start, math.pi / n, n_root + 1)[1:]
    r = np.concatenate([np.full(n_arc, ra), r_inv, fil_r, np.full(n_root, rf)])
    psi = np.concatenate([psi_tip, psi_inv, fil_psi, psi_root])
    segment = np.concatenate(
        [
            np.full(n_arc, "tip"),
            np.full(points, "involute"),
            np.full(fil_r.size, "fillet"),
            np.full(n_root, "root"),
        ]
    )
    return r, psi, segment, False, r_form


def gear_outline(
    gear: Gear,
    points: int = 60,
    *,
    rotation: float = 0.0,
    center: tuple[float, float] = (0.0, 0.0),
    tip_radius: float | None = None,
    single_tooth: bool = False,
    cutter_teeth: int | None = None,
) -> GearOutline:
    """Outline of a gear: every tooth with involute flanks, tip and root fillet.

    Parameters
    ----------
    gear : Gear
        The gear.
    points : int, default 60
        Points per involute flank and per fillet (tip and root arcs get a
        quarter of that).
    rotation : float, default 0
        Angle (rad) of the centre line of the first tooth from +x.
    center : (float, float), default (0, 0)
        Position of the gear centre.
    tip_radius : float, optional
        Tip-round radius ``ρ`` of the generating cutter; default
        :func:`default_tip_radius` for the rack (``c / (1 − sin φ)``, capped
        to what fits the cutter's tooth tip, also for a shaper cutter). ``0``
        gives a sharp cutter corner (a pure trochoid).
    single_tooth : bool, default False
        Only the tooth centred on ``rotation`` (from space centre to space
        centre) instead of the whole gear.
    cutter_teeth : int, optional
        Teeth of the pinion-type shaper cutter that cuts an internal gear,
        within :func:`cutter_teeth_range` (default
        :func:`default_cutter_teeth`). An external gear is generated by a
        rack: giving it a cutter count is an error.

    Returns
    -------
    GearOutline
        Points counter-clockwise (an open polyline for one tooth, a closed
        polygon for the gear).

    Examples
    --------
    >>> out = gear_outline(Gear(20, module=2.0), points=20)
    >>> out.fillet, out.undercut, out.x.size
    ('trochoid', False, 1920)
    >>> r = np.hypot(out.x, out.y)
    >>> round(float(r.min()), 9), round(float(r.max()), 9)
    (17.5, 22.0)
    >>> gear_outline(Gear(10, module=2.0), points=20).undercut
    True
    """
    if not isinstance(gear, Gear):
        raise InputError("gear", "must be a machdyn.gears.Gear")
    teeth = 1 if single_tooth is True else gear.teeth
    points = count("points", points, minimum=4, bytes_each=256 * teeth, what="outline points")
    rotation = finite_scalar("rotation", rotation, "radian")
    center = point("center", center)
    single_tooth = boolean("single_tooth", single_tooth)
    if tip_radius is not None:
        tip_radius = nonnegative("tip_radius", tip_radius)
    if cutter_teeth is not None and not gear.internal:
        raise InputError(
            "cutter_teeth",
            "only an internal gear is cut by a shaper cutter here; an external gear is "
            "generated by a rack (leave cutter_teeth out)",
        )
    if gear.internal:
        n_c = _cutter_teeth(gear, cutter_teeth)
        r, psi, seg, undercut, r_form = _internal_flank_polar(gear, points, n_c, tip_radius)
    else:
        r, psi, seg, undercut, r_form = _flank_polar(gear, points, tip_radius)
    fillet = "trochoid"
    # Whole tooth, counter-clockwise from the lower space centre: mirrored half reversed,
    # then the upper half (drop the duplicated centre-line point and the last root point).
    r_tooth = np.concatenate([r[::-1], r[1:-1]])
    psi_tooth = np.concatenate([-psi[::-1], psi[1:-1]])
    seg_tooth = np.concatenate([seg[::-1], seg[1:-1]])
    teeth = gear.teeth
    if single_tooth:
        r_tooth = np.append(r_tooth, r[-1])
        psi_tooth = np.append(psi_tooth, psi[-1])
        seg_tooth = np.append(seg_tooth, seg[-1])
        offsets = np.zeros(1)
    else:
        offsets = 2 * np.pi * np.arange(teeth) / teeth
    angle = (psi_tooth[None, :] + offsets[:, None] + rotation).ravel()
    radius = np.broadcast_to(r_tooth, (offsets.size, r_tooth.size)).ravel()
    return GearOutline(
        x=center.real + radius * np.cos(angle),
        y=center.imag + radius * np.sin(angle),
        segment=np.tile(seg_tooth, offsets.size),
        teeth=teeth,
        internal=gear.internal,
        fillet=fillet,
        undercut=undercut,
        form_radius=r_form,
    )


def _cutter_teeth(gear: Gear, cutter_teeth: int | None) -> int:
    """Check a shaper cutter's tooth count for ``gear`` (internal), or choose the default."""
    if cutter_teeth is None:
        return default_cutter_teeth(gear)
    n_c = integer("cutter_teeth", cutter_teeth)
    low, high = cutter_teeth_range(gear)
    if not low <= n_c <= high:
        why = (
            "a smaller cutter has pointed teeth or cannot generate the ring's flanks up to its tip"
            if n_c < low
            else f"a cutter needs at least {CUTTER_TEETH_DIFFERENCE} teeth fewer than the ring"
        )
        raise InputError(
            "cutter_teeth",
            f"must be from {low} to {high} to cut this {gear.teeth}-tooth ring, got {n_c}: {why}",
        )
    return n_c


def mesh_outlines(
    pair: Any, pinion_angle: float = 0.0, points: int = 40, cutter_teeth: int | None = None
) -> tuple[Any, Any]:
    """Place the pinion and the gear of a :class:`GearPair` in mesh.

    The pinion is centred at the origin, the gear on the x axis at ``+C'``
    (external) or ``−C'`` (internal), so that the pitch point is at
    ``(r_p', 0)``. With ``pinion_angle = 0`` a pinion tooth points at the
    pitch point; the gear turns ``∓ N_p / N_g`` as far.

    ``cutter_teeth`` is passed to :func:`gear_outline` for an internal gear.

    Returns
    -------
    (GearOutline, GearOutline)
        Pinion and gear outlines.

    Examples
    --------
    >>> from machdyn.gears import GearPair
    >>> pin, gear = mesh_outlines(GearPair(Gear(18, module=1.0), Gear(40, module=1.0)))
    >>> round(float(np.mean(gear.x)), 9)  # the gear is centred at C' = 29
    29.0
    """
    from .mesh import GearPair

    instance("pair", pair, GearPair)
    pinion_angle = finite_scalar("pinion_angle", pinion_angle, "radian")
    p, g, c = pair.pinion, pair.gear, pair.center_distance
    ratio = p.teeth / g.teeth
    if pair.internal:
        gear_rot = math.pi / g.teeth + pinion_angle * ratio
        center = (-c, 0.0)
    else:
        gear_rot = math.pi + math.pi / g.teeth - pinion_angle * ratio
        center = (c, 0.0)
    return (
        gear_outline(p, points, rotation=pinion_angle),
        gear_outline(g, points, rotation=gear_rot, center=center, cutter_teeth=cutter_teeth),
    )


def plot_mesh(
    pair: Any,
    pinion_angle: float = 0.0,
    ax: Any = None,
    points: int = 40,
    cutter_teeth: int | None = None,
) -> Any:
    """Plot a meshing pair with pitch and base circles and the path of contact.

    The path of contact is drawn in two parts, approach (solid, from the
    first contact, marked) and recess (dashed), according to ``pair.driver``.

    Parameters
    ----------
    pair : GearPair
        The pair (at its operating centre distance).
    pinion_angle : float, default 0
        Pinion rotation (rad); the gear follows at the velocity ratio.
    ax : matplotlib Axes, optional
        Axes to draw on (new figure if omitted).
    points : int, default 40
        Points per flank.
    cutter_teeth : int, optional
        Shaper-cutter teeth of an internal gear (see :func:`gear_outline`).

    Returns
    -------
    matplotlib Axes

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from machdyn.gears import GearPair
    >>> ax = plot_mesh(GearPair(Gear(18, module=1.0), Gear(40, module=1.0)))
    >>> ax.get_title()
    "m_p = 1.622 (good), φ' = 20.00°"
    >>> plt.close("all")
    """
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle

    if ax is None:
        _, ax = plt.subplots(figsize=(8, 5))
    pin, gear = mesh_outlines(pair, pinion_angle, points, cutter_teeth)
    pin.plot(ax, color="tab:blue", label=f"pinion N={pair.pinion.teeth}")
    gear.plot(ax, color="tab:red", label=f"gear N={pair.gear.teeth}")
    c = -pair.center_distance if pair.internal else pair.center_distance
    rp_op, rg_op = pair.operating_pitch_radii
    for xc, r_pitch, r_base in (
        (0.0, rp_op, pair.pinion.base_radius),
        (c, rg_op, pair.gear.base_radius),
    ):
        ax.add_patch(Circle((xc, 0.0), r_pitch, fill=False, ls="--", lw=0.6, color="gray"))
        ax.add_patch(Circle((xc, 0.0), r_base, fill=False, ls=":", lw=0.6, color="gray"))
    phi = pair.operating_pressure_angle
    # The line of action through the pitch point, tangent to both base circles: the pinion's
    # tangent point is at -r_p' sin φ' along d, so its tip point is beyond the pitch point
    # (+d) and the gear's tip point short of it (-d), external or internal. Contact starts at
    # the driven member's tip point.
    d = np.array([math.sin(phi), math.cos(phi)])
    pitch = np.array([rp_op, 0.0])
    toward_first = -1.0 if pair.driver == "pinion" else 1.0
    first = pitch + toward_first * pair.path_of_approach * d
    last = pitch - toward_first * pair.path_of_recess * d
    for (a, b), style, label in (
        ((first, pitch), "-", f"approach ({pair.driver} drives)"),
        ((pitch, last), "--", "recess"),
    ):
        ax.plot([a[0], b[0]], [a[1], b[1]], color="k", ls=style, lw=1.0, label=label)
    ax.plot(*first, "o", color="k", ms=3, label="first contact")
    span = pair.pinion.addendum_radius * 1.6
    ax.set_xlim(-span * 0.6, rp_op + span)
    ax.set_ylim(-span, span)
    ax.set_aspect("equal")
    ax.set_title(
        f"m_p = {pair.contact_ratio:.3f} ({pair.contact_ratio_rating}),"
        f" φ' = {math.degrees(phi):.2f}°"
    )
    ax.legend(loc="upper right", fontsize="small")
    return ax
