"""Radial cam geometry: pitch curve, surface, pressure angle, curvature, undercut.

Conventions (fixed frame, notes Fig. 8-44 / Norton §8.7):

* the cam turns **counter-clockwise** about the origin, θ = ωt;
* a translating follower moves along the +y direction on the line
  ``x = ε`` (the eccentricity ε may be negative); its roller centre (the
  trace point) sits at ``(ε, d + s)`` with ``d = √(Rp² − ε²)``;
* an oscillating follower pivots at ``(C, 0)`` (or ``(−C, 0)``); its arm of
  length L carries the roller centre on the prime circle (upper half-plane)
  when s = 0, and s (an angle, radians) swings the roller away from the cam
  centre.

Cam points are given in the cam's own frame (the cam drawn at θ = 0) as
complex numbers ``x + jy``: a fixed-frame point ``P`` seen from the cam is
``P e^{−jθ}``.

With this convention the pressure angle is the notes' (Norton eq. 8.31)
``φ = arctan((v − ε)/(s + √(Rp² − ε²)))`` and the radius of curvature of the
pitch curve is

``ρ = [(d+s)² + (v−ε)²]^{3/2} / [(d+s)² + (v−ε)(2v−ε) − (d+s)a]``

which is the notes' ρ(θ) (review lecture 3, Fig. 8-45) with ε replaced by −ε:
the notes write the trace point as ``ε u_r + (d+s) u_θ``, i.e. they measure
the offset the other way round from their pressure-angle figure. Here one sign
of ε serves both formulas. ρ > 0 where the pitch curve is convex, < 0 where it
is concave, ±inf at an inflection.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from .._summary import Summarized
from .._validate import (
    broadcast,
    choice,
    complex_array,
    count,
    finite_array,
    finite_scalar,
    nonnegative,
    positive,
)
from ..errors import InputError, ModelError
from ._interference import loop_pieces, polyline_crossings
from .critical_path import CriticalPathMotion
from .program import CamProgram, Motion

#: What a follower's ``profile()`` accepts: a program, a table motion or a sampled motion.
MotionSource = Motion | CamProgram | CriticalPathMotion

__all__ = [
    "CamProfile",
    "DesignCheck",
    "OscillatingRoller",
    "SurfaceSelfIntersection",
    "TranslatingFlatFace",
    "TranslatingRoller",
    "cam_profile",
    "flat_face_radius_of_curvature",
    "pitch_curve",
    "pressure_angle",
    "radius_of_curvature",
    "roller_surface",
    "surface_self_intersection",
]

DEFAULT_MAX_PRESSURE_ANGLE = np.radians(30.0)  # notes: acceptable range 0 → 30°


# --------------------------------------------------------------------------
# Functional core: translating roller follower
# --------------------------------------------------------------------------


def _offset_distance(prime_radius: Any, eccentricity: Any) -> tuple[float, float, float]:
    rp = positive("prime_radius", prime_radius)
    eps = finite_scalar("eccentricity", eccentricity)
    if abs(eps) >= rp:
        raise InputError(
            "prime_radius",
            f"must exceed |eccentricity| = {abs(eps):g} (the follower axis must cut the "
            f"prime circle), got {rp:g}",
        )
    return rp, eps, float(np.sqrt(rp * rp - eps * eps))


def _broadcast(**arrays: np.ndarray) -> list[np.ndarray]:
    """Broadcast named arrays together, or say which one does not fit and why.

    >>> _broadcast(s=np.zeros(3), v=np.zeros(2))
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: v: shape (2,) does not broadcast with s (3,)
    """
    shape = broadcast(**arrays)
    return [np.broadcast_to(value, shape) for value in arrays.values()]


def _check_reach(s: np.ndarray, d: float) -> np.ndarray:
    reach = s + d
    if reach.size and reach.min() <= 0.0:
        raise InputError(
            "s", "the trace point would reach the cam centre: s + √(Rp² − ε²) must stay positive"
        )
    return reach


def pressure_angle(s: Any, v: Any, prime_radius: float, eccentricity: float = 0.0) -> np.ndarray:
    """Pressure angle φ of a translating roller follower (radians).

    ``φ = arctan((v − ε)/(s + √(Rp² − ε²)))`` (notes, review lecture 3;
    Norton eq. 8.31), with ``v = ds/dθ`` per radian.

    Parameters
    ----------
    s, v : array_like
        Follower displacement and velocity per radian (broadcast together).
    prime_radius : float
        Prime circle radius Rp (> |ε|).
    eccentricity : float
        Follower offset ε.

    Returns
    -------
    ndarray
        φ in radians, same shape as ``s`` and ``v`` broadcast.

    Examples
    --------
    Final exam problem 9: s = 0.4, v = 1.2, Rp = 2.1, ε = 0.1.

    >>> round(float(np.degrees(pressure_angle(0.4, 1.2, 2.1, 0.1))), 2)
    23.77
    """
    s = finite_array("s", s)
    v = finite_array("v", v)
    _, eps, d = _offset_distance(prime_radius, eccentricity)
    s, v = _broadcast(s=s, v=v)
    return np.arctan((v - eps) / _check_reach(s, d))


def radius_of_curvature(
    s: Any, v: Any, a: Any, prime_radius: float, eccentricity: float = 0.0
) -> np.ndarray:
    """Signed radius of curvature ρ of the pitch curve of a translating roller follower.

    ``ρ = [(d+s)² + (v−ε)²]^{3/2} / [(d+s)² + (v−ε)(2v−ε) − (d+s)a]``,
    ``d = √(Rp² − ε²)`` (the notes' ρ(θ), review lecture 3, with this module's
    sign of ε; Norton eq. 8.34 for ε = 0). Positive where convex, negative where
    concave, ±inf at an inflection. The surface's radius is ``ρ − Rf``.

    Examples
    --------
    A dwell at s = 0 traces the prime circle:

    >>> radius_of_curvature(0.0, 0.0, 0.0, 2.0).tolist()
    2.0
    """
    s = finite_array("s", s)
    v = finite_array("v", v)
    a = finite_array("a", a)
    _, eps, d = _offset_distance(prime_radius, eccentricity)
    s, v, a = _broadcast(s=s, v=v, a=a)
    reach = _check_reach(s, d)
    w = v - eps
    numerator = (reach * reach + w * w) ** 1.5
    denominator = reach * reach + w * (2.0 * v - eps) - reach * a
    return _safe_ratio(numerator, denominator)


def _safe_ratio(numerator: np.ndarray, denominator: np.ndarray) -> np.ndarray:
    """numerator/denominator with ±inf (sign of the numerator) where it is 0."""
    out = np.where(numerator >= 0.0, np.inf, -np.inf)
    np.divide(numerator, denominator, out=out, where=denominator != 0.0)
    return out[()] if out.ndim == 0 else out


def pitch_curve(theta: Any, s: Any, prime_radius: float, eccentricity: float = 0.0) -> np.ndarray:
    """Pitch curve of a translating roller follower in the cam frame (complex).

    Examples
    --------
    >>> z = pitch_curve(0.0, 0.0, 2.0)
    >>> (float(z.real), float(z.imag))
    (0.0, 2.0)
    """
    theta, s = _broadcast(theta=finite_array("theta", theta), s=finite_array("s", s))
    _, eps, d = _offset_distance(prime_radius, eccentricity)
    return (eps + 1j * (d + s)) * np.exp(-1j * theta)


def roller_surface(
    theta: Any,
    s: Any,
    v: Any,
    prime_radius: float,
    roller_radius: float,
    eccentricity: float = 0.0,
) -> np.ndarray:
    """Cam surface of a translating roller follower in the cam frame (complex).

    The contact point lies a roller radius inside the pitch curve along its
    normal, which is inclined at the pressure angle to the follower axis.

    Examples
    --------
    >>> z = roller_surface(0.0, 0.0, 0.0, 2.0, 0.5)
    >>> (float(z.real), float(z.imag))
    (0.0, 1.5)
    """
    theta = finite_array("theta", theta)
    theta, s, v = _broadcast(theta=theta, s=finite_array("s", s), v=finite_array("v", v))
    rf = nonnegative("roller_radius", roller_radius)
    phi = pressure_angle(s, v, prime_radius, eccentricity)
    pitch = pitch_curve(theta, s, prime_radius, eccentricity)
    # Outward normal in the fixed frame is j e^{jφ}; rotate into the cam frame.
    return pitch - rf * 1j * np.exp(1j * (phi - theta))


def flat_face_radius_of_curvature(s: Any, a: Any, base_radius: float) -> np.ndarray:
    """Radius of curvature of a cam for a flat-faced follower: ``ρ = Rb + s + a``.

    Norton eq. 8.27b. ρ ≤ 0 means a cusp: the cam is undercut there.

    Examples
    --------
    >>> flat_face_radius_of_curvature([0.0, 1.0], [0.0, -2.0], 3.0).tolist()
    [3.0, 2.0]
    """
    s, a = _broadcast(s=finite_array("s", s), a=finite_array("a", a))
    return positive("base_radius", base_radius) + s + a


# --------------------------------------------------------------------------
# General trace-point route (used by the oscillating follower)
# --------------------------------------------------------------------------


def _trace_point_geometry(
    theta: np.ndarray,
    p: np.ndarray,
    dp: np.ndarray,
    ddp: np.ndarray,
    direction: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Pitch point, outward normal (cam frame), pressure angle, signed ρ of a trace point.

    ``p, dp, ddp`` are the trace point and its θ-derivatives in the fixed
    frame; ``direction`` is the unit direction in which it moves for
    increasing s. In the cam frame ``q = p e^{−jθ}``, so
    ``q' = (p' − jp) e^{−jθ}`` and ``q'' = (p'' − 2jp' − p) e^{−jθ}``.
    """
    tangent = dp - 1j * p
    second = ddp - 2j * dp - p
    normal_vs_motion = 1j * tangent / direction
    phi = np.arctan2(normal_vs_motion.imag, normal_vs_motion.real)
    phi = np.mod(phi + np.pi / 2.0, np.pi) - np.pi / 2.0
    speed = np.abs(tangent)
    rho = _safe_ratio(speed**3, -(np.conj(tangent) * second).imag)
    to_cam = np.exp(-1j * theta)
    return p * to_cam, 1j * tangent / speed * to_cam, phi, rho


# --------------------------------------------------------------------------
# Global interference: the surface crossing itself
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class SurfaceSelfIntersection:
    """Where a sampled cam surface crosses itself, and what the loops cut away.

    Attributes
    ----------
    theta : ndarray
        The cam angles of the samples (radians).
    theta_crossing : ndarray, shape (m, 2)
        For each of the ``m`` crossings, the cam angles (radians) of the two
        passes of the surface through it, the earlier first.
    point : ndarray of complex, shape (m,)
        The crossing points in the cam frame.
    loop_start, loop_end : ndarray
        Cam angles (radians, in [0, 2π)) where each loop begins and ends; a loop
        that runs through θ = 0 has ``loop_start > loop_end``.
    in_loop : ndarray of bool
        Samples whose surface point lies on a loop: a cutter would remove it,
        so the follower does not follow its law there.

    Examples
    --------
    >>> steep = CamProgram.double_dwell(1.0, np.radians(30), np.radians(30))
    >>> loops = TranslatingRoller(1.5, 1.0).profile(steep, n=720).self_intersection
    >>> loops.found, loops.theta_crossing.shape, int(loops.in_loop.sum())
    (True, (2, 2), 142)
    """

    theta: np.ndarray
    theta_crossing: np.ndarray
    point: np.ndarray
    loop_start: np.ndarray
    loop_end: np.ndarray
    in_loop: np.ndarray

    @property
    def found(self) -> bool:
        """True if the sampled surface crosses itself anywhere.

        Two corners that only touch count as a crossing here but cut no loop away:
        whether material is lost is :attr:`CamProfile.has_surface_loop` (``loop_start``
        not empty).
        """
        return bool(self.point.size)

    def ranges(self) -> list[tuple[float, float]]:
        """Cam-angle ranges (radians, from crossing to crossing) lost to loops."""
        return [(float(a), float(b)) for a, b in zip(self.loop_start, self.loop_end, strict=True)]

    def to_pandas(self) -> Any:
        """Return a DataFrame, one row per crossing: both cam angles (rad and deg), x, y."""
        import pandas as pd

        first, second = self.theta_crossing.T
        return pd.DataFrame(
            {
                "theta_a": first,
                "theta_b": second,
                "theta_a_deg": np.degrees(first),
                "theta_b_deg": np.degrees(second),
                "x": self.point.real,
                "y": self.point.imag,
            }
        )


def surface_self_intersection(theta: Any, surface: Any) -> SurfaceSelfIntersection:
    """Find where a closed cam surface, sampled over one turn, crosses itself.

    The surface is taken as the closed polyline through its samples. Every
    proper crossing of two of its segments is found on a grid of cells (no
    test of all pairs), then the outline is cut at the crossings and each piece
    is kept or marked as a loop by the winding number just inside it: the
    solid cam is the region the outline encloses exactly once, and a piece
    without that region on its material side is cut away (the swallowtail of
    an undercut, Norton §8.7). This test uses the sampled points only, not the
    curvature formulas behind :attr:`CamProfile.undercut`.

    Parameters
    ----------
    theta : array_like
        Cam angles of the samples (radians), increasing over one turn.
    surface : array_like of complex
        Cam surface points ``x + jy`` in the cam frame, one per angle.

    Returns
    -------
    SurfaceSelfIntersection

    Examples
    --------
    A roller larger than the pitch curve's convex radius in a steep rise:

    >>> steep = CamProgram.double_dwell(1.0, np.radians(30), np.radians(30))
    >>> cam = TranslatingRoller(1.5, 1.0).profile(steep, n=3600)
    >>> loops = surface_self_intersection(cam.theta, cam.surface)
    >>> np.degrees(loops.ranges()).round(1).tolist()
    [[10.4, 45.8], [164.2, 199.6]]
    """
    theta = finite_array("theta", theta)
    z = complex_array("surface", surface)
    if theta.ndim != 1 or z.shape != theta.shape:
        raise InputError(
            "surface", f"needs one point per cam angle: theta {theta.shape}, surface {z.shape}"
        )
    if not np.isfinite(z).all():
        raise InputError("surface", "contains NaN or infinite points")
    if theta.size < 3:
        raise InputError("theta", f"a closed outline needs at least 3 samples, got {theta.size}")
    if not (np.all(np.diff(theta) > 0.0) and theta[-1] - theta[0] <= 2 * np.pi * (1 + 1e-12)):
        raise InputError("theta", "must increase over at most one turn (2π rad)")
    n = theta.size
    tau_a, tau_b, point = polyline_crossings(z)
    start, end, in_loop = loop_pieces(z, tau_a, tau_b)
    # Angle at a position along the polyline: linear between samples, the last
    # segment closing the turn back to θ₀ + 2π.
    turn = np.append(theta, theta[0] + 2.0 * np.pi)

    def angle(tau: np.ndarray) -> np.ndarray:
        return np.mod(np.interp(np.mod(tau, n), np.arange(n + 1.0), turn), 2.0 * np.pi)

    # Sample k lies on the piece that starts at the last cut at or before k.
    piece = np.searchsorted(start, np.arange(n), side="right") - 1
    mask = in_loop[piece] if tau_a.size else np.zeros(n, dtype=bool)
    return SurfaceSelfIntersection(
        theta=theta,
        theta_crossing=np.stack((angle(tau_a), angle(tau_b)), axis=-1),
        point=point,
        loop_start=angle(start[in_loop]),
        loop_end=angle(end[in_loop]),
        in_loop=mask,
    )


# --------------------------------------------------------------------------
# Results
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class DesignCheck:
    """One design rule applied to a cam: its name, verdict and a one-line detail."""

    name: str
    passed: bool
    detail: str

    def line(self) -> str:
        """``PASS name: detail`` or ``FAIL ...``."""
        return f"{'PASS' if self.passed else 'FAIL'} {self.name}: {self.detail}"


@dataclass(frozen=True)
class CamProfile(Summarized):
    """Geometry of a radial cam for one follower, sampled over a turn.

    Attributes
    ----------
    follower : str
        ``"translating roller"``, ``"translating flat-faced"`` or ``"oscillating roller"``.
    theta, s, v, a, j : ndarray
        Cam angle (radians) and follower motion per radian.
    pitch : ndarray of complex or None
        Pitch curve (trace-point path) in the cam frame; None for a flat face.
    surface : ndarray of complex
        Cam surface in the cam frame.
    pressure_angle : ndarray
        φ in radians (zero for a flat face perpendicular to its motion).
    rho_pitch : ndarray or None
        Signed radius of curvature of the pitch curve (roller followers).
    rho_surface : ndarray
        Signed radius of curvature of the cam surface.
    undercut : ndarray of bool
        Samples where the cam is undercut by the local test (ρ_pitch between 0
        and Rf, or a flat-face cam with ρ ≤ 0). The global test, the surface
        crossing itself, is :attr:`self_intersection` (mask :attr:`surface_loop`).
    base_radius, prime_radius, roller_radius : float
        Circles of the design (prime = base for a flat face; roller 0 there).
    face_position : ndarray or None
        Flat face: contact point position along the face from the follower
        axis (``v − ε``).
    """

    follower: str
    theta: np.ndarray
    s: np.ndarray
    v: np.ndarray
    a: np.ndarray
    j: np.ndarray
    pitch: np.ndarray | None
    surface: np.ndarray
    pressure_angle: np.ndarray
    rho_pitch: np.ndarray | None
    rho_surface: np.ndarray
    undercut: np.ndarray
    base_radius: float
    prime_radius: float
    roller_radius: float = 0.0
    face_position: np.ndarray | None = None

    # Summaries --------------------------------------------------------------

    @property
    def pressure_angle_max(self) -> float:
        """The pressure angle of largest magnitude (signed, radians)."""
        return float(self.pressure_angle[self.theta_pressure_angle_max_index])

    @property
    def theta_pressure_angle_max_index(self) -> int:
        """Sample index of :attr:`pressure_angle_max`."""
        return int(np.argmax(np.abs(self.pressure_angle)))

    @property
    def theta_pressure_angle_max(self) -> float:
        """Cam angle (radians) where |φ| is largest."""
        return float(self.theta[self.theta_pressure_angle_max_index])

    @property
    def _governing_rho(self) -> np.ndarray:
        # Roller: convex part of the pitch curve against Rf; flat face: the surface.
        if self.rho_pitch is not None:
            return np.where(self.rho_pitch > 0.0, self.rho_pitch, np.inf)
        return self.rho_surface

    @property
    def rho_min(self) -> float:
        """Smallest radius of curvature that governs undercut.

        Roller followers: smallest convex ρ of the pitch curve (undercut if
        below Rf). Flat face: smallest ρ of the surface (undercut if ≤ 0).
        """
        return float(np.min(self._governing_rho))

    @property
    def theta_rho_min(self) -> float:
        """Cam angle (radians) of :attr:`rho_min`."""
        return float(self.theta[int(np.argmin(self._governing_rho))])

    @property
    def is_undercut(self) -> bool:
        """True if any sample is undercut."""
        return bool(self.undercut.any())

    def undercut_ranges(self) -> list[tuple[float, float]]:
        """Cam-angle ranges (radians, start and end sample) where the cam is undercut."""
        return _mask_ranges(self.theta, self.undercut)

    @cached_property
    def self_intersection(self) -> SurfaceSelfIntersection:
        """Where the surface crosses itself (computed on first use, then kept).

        The global companion of the local :attr:`undercut` test: see
        :func:`surface_self_intersection`.

        Examples
        --------
        >>> steep = CamProgram.double_dwell(1.0, np.radians(30), np.radians(30))
        >>> cam = TranslatingRoller(1.5, 1.0).profile(steep, n=720)
        >>> cam.self_intersection.found, cam.has_surface_loop
        (True, True)
        """
        return surface_self_intersection(self.theta, self.surface)

    @property
    def surface_loop(self) -> np.ndarray:
        """Samples whose surface point lies on a loop of the self-intersecting surface."""
        return self.self_intersection.in_loop

    @property
    def has_surface_loop(self) -> bool:
        """True if the surface crosses itself into a loop that a cutter would remove."""
        return bool(self.self_intersection.loop_start.size)

    def surface_loop_ranges(self) -> list[tuple[float, float]]:
        """Cam-angle ranges (radians, crossing to crossing) lost to loops of the surface."""
        return self.self_intersection.ranges()

    @property
    def face_width(self) -> float | None:
        """Flat face: the least face width, ``max(v) − min(v)`` (Norton eq. 8.28).

        The contact point sits ``v − ε`` along the face from the follower axis
        (:attr:`face_position`), so the face must reach from the least to the
        greatest of those; :meth:`checks` tests a given symmetric face.
        """
        if self.face_position is None:
            return None
        return float(self.face_position.max() - self.face_position.min())

    def checks(
        self,
        max_pressure_angle: float = DEFAULT_MAX_PRESSURE_ANGLE,
        rho_ratio: float = 2.0,
        face_width: float | None = None,
    ) -> list[DesignCheck]:
        """Apply the notes' and Norton's design rules to this cam.

        Parameters
        ----------
        max_pressure_angle : float
            Limit on |φ| in radians (notes: 0 → 30°).
        rho_ratio : float
            Rule of thumb (Norton §8.7): the convex pitch-curve radius should be
            at least this many roller radii (2 to 3).
        face_width : float, optional
            Flat face: the width you have, checked against the least width.
        """
        rho_ratio = positive("rho_ratio", rho_ratio)
        if face_width is not None:
            face_width = positive("face_width", face_width)
        limit = positive("max_pressure_angle", max_pressure_angle, "radian")
        if limit >= np.pi / 2.0:
            raise InputError(
                "max_pressure_angle",
                f"must be below 90° (π/2 rad; the notes allow up to 30°), got {limit:g} rad",
            )
        out = []
        deg = np.degrees
        if self.rho_pitch is not None:
            phi = self.pressure_angle_max
            out.append(
                DesignCheck(
                    "pressure angle",
                    abs(phi) <= limit + 1e-12,
                    f"max |φ| = {abs(deg(phi)):.2f}° at "
                    f"θ = {deg(self.theta_pressure_angle_max):.1f}° (limit {deg(limit):.0f}°)",
                )
            )
        out.append(self._undercut_check())
        if self.rho_pitch is not None and self.roller_radius > 0.0:
            ratio = self.rho_min / self.roller_radius
            out.append(
                DesignCheck(
                    "curvature margin",
                    ratio >= rho_ratio,
                    f"min convex ρ_pitch = {self.rho_min:.4g} = {ratio:.2f} Rf at "
                    f"θ = {deg(self.theta_rho_min):.1f}° (rule of thumb ≥ {rho_ratio:g} Rf)",
                )
            )
        if self.face_position is not None:
            need = self.face_width
            lo, hi = float(self.face_position.min()), float(self.face_position.max())
            text = (
                f"contact runs from {lo:.4g} to {hi:.4g} about the follower axis; "
                f"width ≥ {need:.4g}"
            )
            passed = True
            if face_width is not None:
                passed = positive("face_width", face_width) >= 2.0 * max(abs(lo), abs(hi))
                text += f" (symmetric face {face_width:g} needs ≥ {2 * max(abs(lo), abs(hi)):.4g})"
            out.append(DesignCheck("face width", passed, text))
        return out

    def _undercut_check(self) -> DesignCheck:
        """The local ρ test and the global self-intersection test, in one verdict."""
        loops = self.surface_loop_ranges()
        if not self.is_undercut and not loops:
            return DesignCheck(
                "undercut", True, "none (local ρ test; surface does not cross itself)"
            )
        parts = []
        if self.is_undercut:
            parts.append(f"undercut at θ = {format_ranges(self.undercut_ranges())}")
        if loops:
            parts.append(f"surface self-intersection: loops cut away θ = {format_ranges(loops)}")
        if not self.is_undercut:
            parts.append(
                "no sample fails the local ρ test (the loop lies between samples, or is global)"
            )
        return DesignCheck("undercut", False, "; ".join(parts))

    # Presentation -----------------------------------------------------------

    def to_pandas(self) -> Any:
        """Return a DataFrame: θ (rad and deg), svaj, pitch/surface x, y, φ (deg), ρ, undercut.

        ``undercut`` is the local test, ``surface_loop`` the global one.
        """
        import pandas as pd

        from ..units import units_of

        if units_of(self) is not None:  # a machine file's cam: "theta [deg]", "s [mm]", ...
            return pd.DataFrame(self._columns())
        return pd.DataFrame({"theta": self.theta, **self._columns()})

    def _columns(self) -> dict[str, np.ndarray]:
        from ..units import columns, units_of

        nan = np.full_like(self.theta, np.nan)
        pitch = self.pitch if self.pitch is not None else nan + 0j
        system = units_of(self)
        if system is not None:
            lift = "angle" if "oscillating" in self.follower else "length"
            spec: list[tuple[str, str | None, Any]] = [("theta", "angle", self.theta)]
            spec += [("s", lift, self.s), ("v", f"{lift}/rad", self.v)]
            spec += [("a", f"{lift}/rad^2", self.a), ("j", f"{lift}/rad^3", self.j)]
            spec += [("pitch_x", "length", pitch.real), ("pitch_y", "length", pitch.imag)]
            spec += [("surface_x", "length", self.surface.real)]
            spec += [("surface_y", "length", self.surface.imag)]
            spec += [("pressure_angle", "angle", self.pressure_angle)]
            rho = self.rho_pitch if self.rho_pitch is not None else nan
            spec += [("rho_pitch", "length", rho), ("rho_surface", "length", self.rho_surface)]
            spec += [("undercut", None, self.undercut), ("surface_loop", None, self.surface_loop)]
            return columns(system, spec, degrees=True)
        return {
            "theta_deg": np.degrees(self.theta),
            "s": self.s,
            "v": self.v,
            "a": self.a,
            "j": self.j,
            "pitch_x": pitch.real,
            "pitch_y": pitch.imag,
            "surface_x": self.surface.real,
            "surface_y": self.surface.imag,
            "pressure_angle_deg": np.degrees(self.pressure_angle),
            "rho_pitch": self.rho_pitch if self.rho_pitch is not None else nan,
            "rho_surface": self.rho_surface,
            "undercut": self.undercut,
            "surface_loop": self.surface_loop,
        }

    def to_csv(self, path: Any) -> None:
        """Write the profile table as CSV (see :func:`machdyn.cams.write_csv`)."""
        from .io import write_csv

        write_csv(self, path)

    def to_dxf(self, path: Any, allow_undercut: bool = False, unit: str | None = None) -> None:
        """Write the cam outline as DXF in ``unit`` (see :func:`machdyn.cams.write_dxf`).

        ``unit`` defaults to the length unit of a cam given units (a machine file's).
        """
        from ..units import units_of
        from .io import write_dxf

        system = units_of(self)
        if unit is None and system is not None:
            unit = system.length
        write_dxf(self, path, allow_undercut=allow_undercut, unit=unit)

    def plot(self, **kwargs: Any) -> Any:
        """Draw the cam (see :func:`machdyn.cams.plot_profile`)."""
        from .plot import plot_profile

        return plot_profile(self, **kwargs)


def format_ranges(ranges: list[tuple[float, float]]) -> str:
    """Cam-angle ranges (radians) as text in degrees: ``"18.8°–29.2°, 180.8°–191.2°"``."""
    return ", ".join(f"{np.degrees(a):.1f}°–{np.degrees(b):.1f}°" for a, b in ranges)


def _mask_ranges(theta: np.ndarray, mask: np.ndarray) -> list[tuple[float, float]]:
    """Return runs of True in ``mask`` as (first θ, last θ), joined across 2π."""
    if not mask.any():
        return []
    flags = np.concatenate(([False], mask, [False])).astype(np.int8)
    edges = np.flatnonzero(np.diff(flags))
    runs = [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2], strict=True)]
    if len(runs) > 1 and runs[0][0] == 0 and runs[-1][1] == mask.size - 1:
        runs = [(runs[-1][0], runs[0][1]), *runs[1:-1]]
    return [(float(theta[a]), float(theta[b])) for a, b in runs]


# --------------------------------------------------------------------------
# Followers
# --------------------------------------------------------------------------


@dataclass(frozen=True)
class TranslatingRoller:
    """Translating roller follower, offset ε (notes Fig. 8-44).

    Parameters
    ----------
    prime_radius : float
        Rp, the smallest circle through the roller centre (> |ε|, > Rf).
    roller_radius : float
        Rf (0 for a knife edge).
    eccentricity : float
        ε, offset of the follower axis.

    Examples
    --------
    >>> program = CamProgram.double_dwell(1.0, np.radians(60), np.radians(60))
    >>> cam = TranslatingRoller(prime_radius=3.0, roller_radius=0.5).profile(program)
    >>> round(float(np.degrees(abs(cam.pressure_angle_max))), 2)
    28.82
    >>> cam.is_undercut
    False
    """

    prime_radius: float
    roller_radius: float
    eccentricity: float = 0.0

    def __post_init__(self) -> None:
        rp, eps, _ = _offset_distance(self.prime_radius, self.eccentricity)
        rf = nonnegative("roller_radius", self.roller_radius)
        if rf >= rp:
            raise InputError(
                "roller_radius", f"must be smaller than the prime radius {rp:g}, got {rf:g}"
            )
        object.__setattr__(self, "prime_radius", rp)
        object.__setattr__(self, "eccentricity", eps)
        object.__setattr__(self, "roller_radius", rf)

    @property
    def base_radius(self) -> float:
        """Rb = Rp − Rf."""
        return self.prime_radius - self.roller_radius

    def to_spec(self, name: str = "cam") -> dict[str, Any]:
        """The follower as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from ..spec import model_spec

        return model_spec(self, "cam", name)

    def profile(self, motion: MotionSource, n: int = 3600) -> CamProfile:
        """Cam geometry for a program (sampled at ``n`` points) or a sampled motion."""
        m = _as_motion(motion, n)
        rp, eps, rf = self.prime_radius, self.eccentricity, self.roller_radius
        phi = pressure_angle(m.s, m.v, rp, eps)
        rho = radius_of_curvature(m.s, m.v, m.a, rp, eps)
        pitch = pitch_curve(m.theta, m.s, rp, eps)
        surface = pitch - rf * 1j * np.exp(1j * (phi - m.theta))
        return _roller_result("translating roller", m, pitch, surface, phi, rho, rp, rf)


@dataclass(frozen=True)
class TranslatingFlatFace:
    """Translating flat-faced follower (face perpendicular to its motion).

    The eccentricity does not change the cam, only where the contact runs on
    the face (Norton §8.7). The pressure angle is zero.

    Examples
    --------
    >>> program = CamProgram.double_dwell(1.0, np.radians(60), np.radians(60))
    >>> cam = TranslatingFlatFace(base_radius=3.0).profile(program)
    >>> round(cam.face_width, 4)   # 2 * 2h/β
    3.8197
    """

    base_radius: float
    eccentricity: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "base_radius", positive("base_radius", self.base_radius))
        object.__setattr__(self, "eccentricity", finite_scalar("eccentricity", self.eccentricity))

    def to_spec(self, name: str = "cam") -> dict[str, Any]:
        """The follower as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from ..spec import model_spec

        return model_spec(self, "cam", name)

    def profile(self, motion: MotionSource, n: int = 3600) -> CamProfile:
        """Cam geometry for a program (sampled at ``n`` points) or a sampled motion."""
        m = _as_motion(motion, n)
        rb = self.base_radius
        reach = _check_reach(m.s, rb)
        # Envelope of the face lines y = Rb + s: contact at x = v (fixed frame).
        surface = (m.v + 1j * reach) * np.exp(-1j * m.theta)
        rho = flat_face_radius_of_curvature(m.s, m.a, rb)
        return CamProfile(
            follower="translating flat-faced",
            theta=m.theta,
            s=m.s,
            v=m.v,
            a=m.a,
            j=m.j,
            pitch=None,
            surface=surface,
            pressure_angle=np.zeros_like(m.theta),
            rho_pitch=None,
            rho_surface=rho,
            undercut=rho <= 0.0,
            base_radius=rb,
            prime_radius=rb,
            roller_radius=0.0,
            face_position=m.v - self.eccentricity,
        )


@dataclass(frozen=True)
class OscillatingRoller:
    """Oscillating (rocker) roller follower; s is the arm angle in radians.

    Parameters
    ----------
    prime_radius : float
        Rp, distance of the roller centre from the cam centre when s = 0.
    roller_radius : float
        Rf.
    pivot_distance : float
        C, distance from the cam centre to the arm pivot.
    arm_length : float
        L, pivot to roller centre; needs ``|C − L| < Rp < C + L``.
    pivot_side : {"right", "left"}
        Pivot at (C, 0) or (−C, 0). The roller sits above the x axis; with the
        cam turning counter-clockwise its surface runs from the roller towards
        a right-hand pivot, away from a left-hand one.

    Examples
    --------
    >>> program = CamProgram.double_dwell(np.radians(20), np.radians(90), np.radians(90))
    >>> cam = OscillatingRoller(2.0, 0.3, pivot_distance=4.0, arm_length=3.5).profile(program)
    >>> cam.is_undercut
    False
    """

    prime_radius: float
    roller_radius: float
    pivot_distance: float
    arm_length: float
    pivot_side: str = "right"

    def __post_init__(self) -> None:
        rp = positive("prime_radius", self.prime_radius)
        rf = nonnegative("roller_radius", self.roller_radius)
        c = positive("pivot_distance", self.pivot_distance)
        arm = positive("arm_length", self.arm_length)
        side = choice("pivot_side", str(self.pivot_side).lower(), ("right", "left"))
        if rf >= rp:
            raise InputError(
                "roller_radius", f"must be smaller than the prime radius {rp:g}, got {rf:g}"
            )
        if not abs(c - arm) < rp < c + arm:
            raise InputError(
                "prime_radius",
                f"an arm of {arm:g} pivoted {c:g} from the cam centre reaches radii between "
                f"{abs(c - arm):g} and {c + arm:g}; got {rp:g}",
            )
        for name, value in (
            ("prime_radius", rp),
            ("roller_radius", rf),
            ("pivot_distance", c),
            ("arm_length", arm),
            ("pivot_side", side),
        ):
            object.__setattr__(self, name, value)

    @property
    def base_radius(self) -> float:
        """Rb = Rp − Rf."""
        return self.prime_radius - self.roller_radius

    @property
    def _sigma(self) -> float:
        # Sense in which the arm angle grows with s (it must carry the roller outward).
        return -1.0 if self.pivot_side == "right" else 1.0

    @property
    def pivot(self) -> complex:
        """Pivot position (fixed frame) as x + jy."""
        return complex(-self._sigma * self.pivot_distance, 0.0)

    @property
    def gamma0(self) -> float:
        """Arm angle (radians, from +x) when s = 0 (law of cosines, roller above the x axis)."""
        c, arm, rp = self.pivot_distance, self.arm_length, self.prime_radius
        return float(np.arccos(-self._sigma * (rp * rp - c * c - arm * arm) / (2.0 * c * arm)))

    def to_spec(self, name: str = "cam") -> dict[str, Any]:
        """The follower as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from ..spec import model_spec

        return model_spec(self, "cam", name)

    def profile(self, motion: MotionSource, n: int = 3600) -> CamProfile:
        """Cam geometry for a program (sampled at ``n`` points) or a sampled motion."""
        m = _as_motion(motion, n)
        arm, sigma = self.arm_length, self._sigma
        gamma = self.gamma0 + sigma * m.s
        if gamma.min() <= 0.0 or gamma.max() >= np.pi:
            raise ModelError(
                "the arm swings through the line of centres; use a smaller swing or "
                "another pivot position"
            )
        e = np.exp(1j * gamma)
        # Trace point p = pivot + L e^{jγ} and its θ-derivatives (γ' = σv, γ'' = σa).
        p = self.pivot + arm * e
        dp = 1j * sigma * arm * m.v * e
        ddp = arm * e * (1j * sigma * m.a - m.v**2)
        pitch, normal, phi, rho = _trace_point_geometry(m.theta, p, dp, ddp, 1j * sigma * e)
        surface = pitch - self.roller_radius * normal
        return _roller_result(
            "oscillating roller", m, pitch, surface, phi, rho, self.prime_radius, self.roller_radius
        )


Follower = TranslatingRoller | TranslatingFlatFace | OscillatingRoller


#: Memory per sample of a profile with its checks (outline, curvature, crossings grid).
_BYTES_PER_SAMPLE = 800


def _as_motion(motion: MotionSource, n: int) -> Motion:
    if isinstance(motion, CamProgram | CriticalPathMotion):
        n = count("n", n, minimum=4, bytes_each=_BYTES_PER_SAMPLE, what="cam samples")
        return motion.sample(n)
    if isinstance(motion, Motion):
        return motion
    raise InputError(
        "motion",
        f"must be a CamProgram, a CriticalPathMotion or a Motion, got {type(motion).__name__}",
    )


def _roller_result(
    kind: str,
    m: Motion,
    pitch: np.ndarray,
    surface: np.ndarray,
    phi: np.ndarray,
    rho: np.ndarray,
    rp: float,
    rf: float,
) -> CamProfile:
    undercut = (rho > 0.0) & (rho <= rf)
    return CamProfile(
        follower=kind,
        theta=m.theta,
        s=m.s,
        v=m.v,
        a=m.a,
        j=m.j,
        pitch=pitch,
        surface=surface,
        pressure_angle=phi,
        rho_pitch=rho,
        rho_surface=rho - rf,
        undercut=undercut,
        base_radius=rp - rf,
        prime_radius=rp,
        roller_radius=rf,
    )


def cam_profile(program: CamProgram, follower: Follower, n: int = 3600) -> CamProfile:
    """Sample ``program`` at ``n`` angles and build the cam for ``follower``.

    Examples
    --------
    >>> program = CamProgram.double_dwell(1.0, np.radians(60), np.radians(60))
    >>> cam_profile(program, TranslatingRoller(3.0, 0.5), n=720).theta.size
    720
    """
    if not isinstance(follower, TranslatingRoller | TranslatingFlatFace | OscillatingRoller):
        raise InputError("follower", f"must be a follower object, got {follower!r}")
    return follower.profile(program, n)
