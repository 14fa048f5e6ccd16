"""Sizing: the smallest cam that keeps the pressure angle and curvature in bounds.

Norton §8.7: a larger prime circle lowers the pressure angle (φ falls as
``s + √(Rp² − ε²)`` grows) and straightens the pitch curve, at the price of
a bigger cam. The roller follower is sized for both rules; the flat-faced
follower only for positive curvature (its pressure angle is zero).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import choice, finite_scalar, nonnegative, positive
from ..errors import InputError, ModelError
from .critical_path import CriticalPathMotion
from .geometry import (
    DEFAULT_MAX_PRESSURE_ANGLE,
    OscillatingRoller,
    TranslatingFlatFace,
    TranslatingRoller,
    _as_motion,
    radius_of_curvature,
)
from .program import CamProgram, Motion

__all__ = ["Sizing", "size_flat_face", "size_oscillating_roller", "size_roller"]


@dataclass(frozen=True)
class Sizing:
    """Result of a sizing: the circles found and which rule set them.

    Attributes
    ----------
    prime_radius, base_radius : float
        The smallest radii meeting every rule (prime = base for a flat face).
    governed_by : str
        ``"pressure angle"``, ``"curvature"`` or ``"minimum size"``.
    pressure_angle_max : float
        max |φ| in radians at that size.
    rho_min : float
        Governing minimum radius of curvature at that size.
    """

    prime_radius: float
    base_radius: float
    governed_by: str
    pressure_angle_max: float
    rho_min: float


def _smallest(ok: Callable[[float], bool], lo: float, hi: float, rtol: float = 1e-10) -> float:
    """Smallest x in (lo, hi] with ok(x), by bisection (ok assumed monotone)."""
    if not ok(hi):
        raise ModelError(f"no size up to {hi:g} meets the rules")
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        if ok(mid):
            hi = mid
        else:
            lo = mid
    return hi


def size_roller(
    motion: CamProgram | CriticalPathMotion | Motion,
    roller_radius: float,
    eccentricity: float = 0.0,
    max_pressure_angle: float = DEFAULT_MAX_PRESSURE_ANGLE,
    rho_ratio: float = 1.0,
    n: int = 3600,
) -> Sizing:
    """Smallest prime circle for a translating roller follower.

    The pressure-angle rule has a closed form: ``|v − ε| ≤ (s + d) tan φmax``
    for every θ gives ``d ≥ max(|v − ε|/tan φmax − s)`` and ``Rp = √(d² + ε²)``.
    The curvature rule (convex ρ_pitch ≥ ``rho_ratio``·Rf, no undercut when
    ``rho_ratio`` = 1) is met by bisection on Rp.

    Examples
    --------
    >>> program = CamProgram.double_dwell(1.0, np.radians(60), np.radians(60))
    >>> sized = size_roller(program, roller_radius=0.5)
    >>> sized.governed_by, round(float(np.degrees(sized.pressure_angle_max)), 6)
    ('pressure angle', 30.0)
    """
    m = _as_motion(motion, n)
    rf = nonnegative("roller_radius", roller_radius)
    eps = finite_scalar("eccentricity", eccentricity)
    limit = positive("max_pressure_angle", max_pressure_angle, "radian")
    if limit >= np.pi / 2:
        raise InputError("max_pressure_angle", "must be below 90°")
    ratio = positive("rho_ratio", rho_ratio)
    d_phi = float(np.max(np.abs(m.v - eps) / np.tan(limit) - m.s))
    d_floor = max(d_phi, float(-m.s.min()) + 1e-12, 0.0)
    rp_phi = float(np.hypot(d_floor, eps))
    rp_min = max(rp_phi, abs(eps) * (1 + 1e-12), rf * (1 + 1e-12))

    def curvature_ok(rp: float) -> bool:
        rho = radius_of_curvature(m.s, m.v, m.a, rp, eps)
        return not np.any((rho > 0.0) & (rho < ratio * rf))

    governed = "pressure angle" if rp_min == rp_phi else "minimum size"
    rp = rp_min
    if rf > 0.0 and not curvature_ok(rp_min):
        hi = 2.0 * rp_min
        while not curvature_ok(hi):
            hi *= 2.0
            if hi > 1e9 * rp_min:
                raise ModelError("no prime circle removes the undercut")
        rp = _smallest(curvature_ok, rp_min, hi)
        governed = "curvature"
    cam = TranslatingRoller(rp, rf, eps).profile(m)
    return Sizing(rp, rp - rf, governed, abs(cam.pressure_angle_max), cam.rho_min)


def size_flat_face(
    motion: CamProgram | CriticalPathMotion | Motion, min_radius_of_curvature: float, n: int = 3600
) -> Sizing:
    """Smallest base circle for a flat-faced follower: ``Rb + s + a ≥ ρmin`` everywhere.

    Norton eq. 8.29: ``Rb ≥ ρmin − min(s + a)``.

    Examples
    --------
    >>> program = CamProgram.double_dwell(1.0, np.radians(60), np.radians(60))
    >>> sized = size_flat_face(program, min_radius_of_curvature=0.25)
    >>> round(sized.rho_min, 9)
    0.25
    """
    m = _as_motion(motion, n)
    rho_min = positive("min_radius_of_curvature", min_radius_of_curvature)
    rb = float(rho_min - np.min(m.s + m.a))
    if rb <= 0.0:
        raise ModelError("the curvature rule leaves the base circle free; choose it by size")
    cam = TranslatingFlatFace(rb).profile(m)
    return Sizing(rb, rb, "curvature", 0.0, cam.rho_min)


def size_oscillating_roller(
    motion: CamProgram | CriticalPathMotion | Motion,
    roller_radius: float,
    pivot_distance: float,
    arm_length: float,
    max_pressure_angle: float = DEFAULT_MAX_PRESSURE_ANGLE,
    rho_ratio: float = 1.0,
    n: int = 3600,
    pivot_side: str = "right",
) -> Sizing:
    """Smallest prime circle for an oscillating roller follower (bisection).

    The pivot and arm are kept; Rp is scanned over ``(|C − L|, C + L)`` (the
    pressure angle is not monotone in Rp for a rocker) and refined by bisection.

    Examples
    --------
    >>> program = CamProgram.double_dwell(np.radians(10), np.radians(90), np.radians(90))
    >>> sized = size_oscillating_roller(program, 0.2, pivot_distance=4.0, arm_length=3.5)
    >>> bool(np.degrees(sized.pressure_angle_max) <= 30.0 + 1e-6)
    True
    """
    m = _as_motion(motion, n)
    rf = nonnegative("roller_radius", roller_radius)
    c = positive("pivot_distance", pivot_distance)
    arm = positive("arm_length", arm_length)
    limit = positive("max_pressure_angle", max_pressure_angle, "radian")
    ratio = positive("rho_ratio", rho_ratio)
    pivot_side = choice("pivot_side", str(pivot_side).lower(), ("right", "left"))
    lo, hi = max(abs(c - arm), rf), c + arm

    def cam_at(rp: float) -> Any:
        try:
            return OscillatingRoller(rp, rf, c, arm, pivot_side).profile(m)
        except (InputError, ModelError):
            return None

    def pressure_ok(rp: float) -> bool:
        cam = cam_at(rp)
        return cam is not None and abs(cam.pressure_angle_max) <= limit

    def curvature_ok(rp: float) -> bool:
        cam = cam_at(rp)
        return cam is not None and not np.any((cam.rho_pitch > 0.0) & (cam.rho_pitch < ratio * rf))

    def both_ok(rp: float) -> bool:
        return pressure_ok(rp) and (rf == 0.0 or curvature_ok(rp))

    # The pressure angle is not monotone in Rp here (it vanishes at dwell only
    # when the arm is square to the radius), so scan, then refine by bisection.
    grid = np.linspace(lo, hi, 202)[1:-1]
    feasible = [rp for rp in grid if both_ok(rp)]
    if not feasible:
        raise ModelError(
            f"no prime radius between {lo:g} and {hi:g} keeps |φ| ≤ "
            f"{np.degrees(limit):g}° without undercut for this pivot and arm"
        )
    first = int(np.searchsorted(grid, feasible[0]))
    rp = feasible[0] if first == 0 else _smallest(both_ok, float(grid[first - 1]), feasible[0])
    governed = "pressure angle" if not pressure_ok(rp * (1 - 1e-6)) else "curvature"
    cam = cam_at(rp)
    return Sizing(rp, rp - rf, governed, abs(cam.pressure_angle_max), cam.rho_min)
