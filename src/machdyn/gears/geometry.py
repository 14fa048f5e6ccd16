"""Involute spur-gear geometry: one gear from its teeth, pitch and proportions.

The functional core is a handful of plain functions over numpy arrays
(:func:`involute`, :func:`inverse_involute`, :func:`base_pitch`,
:func:`tooth_thickness_at`); :class:`Gear` holds the parameters of one gear and
calls them.

Sizes are unit-agnostic. The *module* ``m = d / N`` is the pitch diameter per
tooth (millimetres for metric gears); a diametral pitch ``P_d = N / d`` (teeth
per inch) is converted once with ``m = 1 / P_d``, so a gear given by diametral
pitch has all its lengths in inches. Angles are in radians.

Tooth proportions (Norton, *Design of Machinery*, Table 9-1, AGMA):

============  ============  ============
system        addendum      dedendum
============  ============  ============
full_depth    1.000 m       1.250 m
stub          0.800 m       1.000 m
============  ============  ============

A profile shift ``x`` (coefficient of the module) moves the generating rack
outward by ``x m``: the addendum becomes ``(k_a + x) m``, the dedendum
``(k_d − x) m`` and the pitch-circle tooth thickness ``π m / 2 + 2 x m tan φ``
(Norton Figure 9-13, "long and short addendum" teeth).

An internal gear follows the same sign rule — a positive ``x`` moves its
whole profile ``x m`` away from the axis (ISO 21771, the KHK and SDP/SI
tables) — and, its material lying outside, that thins its teeth: its tip
(inner) circle is ``r − (k_a − x) m``, its root circle ``r + (k_d + x) m``
and its pitch-circle tooth thickness ``π m / 2 − 2 x m tan φ``. The ring's
space is the tooth of the external gear of the same pitch and shift, which
is also the shaper cutter that generates it at the standard cutting
distance. With these, the tight mesh of a pinion ``x_p`` in a ring ``x_g``
runs at ``inv φ' = inv φ + 2 tan φ (x_g − x_p) / (N_g − N_p)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validate import (
    boolean,
    broadcast,
    choice,
    finite_array,
    finite_scalar,
    integer,
    magnitude,
    nonnegative,
    positive,
)
from ..errors import InputError
from ._checks import finite, pressure_angle_array

__all__ = [
    "SYSTEMS",
    "Gear",
    "base_pitch",
    "inverse_involute",
    "involute",
    "tooth_thickness_at",
]

#: Addendum and dedendum coefficients (multiples of the module) of the
#: standard tooth systems, Norton Table 9-1 (AGMA full depth and 20° stub).
SYSTEMS: dict[str, tuple[float, float]] = {
    "full_depth": (1.0, 1.25),
    "stub": (0.8, 1.0),
}

#: Fewest teeth accepted for any gear (the tip must also not be pointed).
MIN_TEETH = 3
#: Most teeth a Gear may have (more than any gear that is cut; keeps outlines finite).
MAX_TEETH = 1_000_000


def involute(phi: ArrayLike) -> NDArray[np.float64]:
    """Involute function ``inv φ = tan φ − φ``.

    The polar angle of the point of an involute at pressure angle ``φ``,
    measured from where the involute leaves the base circle.

    Parameters
    ----------
    phi : array_like
        Pressure angle(s) in radians, ``0 <= φ < π/2``.

    Returns
    -------
    ndarray
        ``tan φ − φ``, same shape as ``phi``.

    Examples
    --------
    >>> float(involute(np.radians(20.0)))
    0.014904383867336446
    """
    phi = finite_array("phi", phi, "radian")
    if np.any(np.abs(phi) >= 0.5 * math.pi):
        raise InputError("phi", "the involute function is defined for |φ| < π/2 (radians)")
    return np.tan(phi) - phi


def inverse_involute(value: ArrayLike) -> NDArray[np.float64]:
    """Pressure angle ``φ`` with ``inv φ = value`` (Newton's method, vectorised).

    Parameters
    ----------
    value : array_like
        Values of the involute function, ``>= 0``.

    Returns
    -------
    ndarray
        ``φ`` in radians, same shape as ``value``.

    Examples
    --------
    >>> round(float(np.degrees(inverse_involute(0.014904383867336446))), 10)
    20.0
    """
    value = finite("value", value, "the involute function is finite and >= 0")
    if np.any(value < 0) or np.any(value > 1e15):
        raise InputError("value", "the involute function is >= 0 (and below 1e15: φ < 90°)")
    # Starting guess from the series inv φ ≈ φ³/3, good to a few per cent up to 60°.
    phi = np.minimum(np.cbrt(3.0 * value), 1.5)
    for _ in range(50):
        step = (involute(phi) - value) / np.maximum(np.tan(phi) ** 2, 1e-300)
        phi = np.clip(phi - step, 0.0, math.pi / 2 - 1e-12)
        if np.all(np.abs(step) < 1e-15):
            break
    return phi


def base_pitch(pitch_radius: ArrayLike, teeth: ArrayLike, pressure_angle: ArrayLike) -> Any:
    """Return the base pitch ``p_b = 2π r cos φ / N`` (the notes, Figure 9-9).

    By the definition of the involute it is also the distance between
    successive teeth along the common normal (the line of action).

    Parameters
    ----------
    pitch_radius : array_like
        Pitch radius ``r``.
    teeth : array_like
        Number of teeth ``N``.
    pressure_angle : array_like
        Pressure angle ``φ`` in radians.

    Returns
    -------
    ndarray or float
        The base pitch, in the length unit of ``pitch_radius``.

    Examples
    --------
    A 24-tooth pinion of 1.5 in pitch radius at 20° (the notes' final exam):

    >>> round(float(base_pitch(1.5, 24, np.radians(20.0))), 4)
    0.369
    """
    r = finite("pitch_radius", pitch_radius, "must be a positive, finite length")
    n = finite("teeth", teeth, f"must be at least {MIN_TEETH}")
    if np.any(r <= 0) or not np.all(np.isfinite(r)):
        raise InputError("pitch_radius", f"must be a positive, finite length, got {pitch_radius!r}")
    if np.any(n < MIN_TEETH) or not np.all(np.isfinite(n)):
        raise InputError("teeth", f"must be at least {MIN_TEETH}, got {teeth!r}")
    phi = pressure_angle_array(pressure_angle)
    broadcast(pitch_radius=r, teeth=n, pressure_angle=phi)
    return 2.0 * np.pi * r * np.cos(phi) / n


def tooth_thickness_at(
    radius: ArrayLike,
    pitch_radius: float,
    thickness: float,
    pressure_angle: float,
) -> NDArray[np.float64]:
    """Circular tooth thickness at ``radius`` of an involute tooth.

    ``s_r = 2 r (s / (2 r_p) + inv φ − inv φ_r)`` with ``cos φ_r = r_b / r``
    (the standard involute relation, from ``inv φ = tan φ − φ``; the same expression gives
    the space width of an internal gear, whose spaces are shaped like external
    teeth).

    Parameters
    ----------
    radius : array_like
        Radii at which to evaluate, each ``>= r_b = r_p cos φ``.
    pitch_radius : float
        Reference pitch radius ``r_p``.
    thickness : float
        Circular thickness ``s`` on the reference pitch circle.
    pressure_angle : float
        Reference pressure angle ``φ`` in radians.

    Returns
    -------
    ndarray
        Circular thickness at each radius (negative means a pointed tooth).

    Examples
    --------
    On the pitch circle it returns the pitch-circle thickness:

    >>> float(tooth_thickness_at(10.0, 10.0, 1.5, np.radians(20.0)))
    1.5
    """
    radius = finite("radius", radius, "must be finite")
    pitch_radius = positive("pitch_radius", pitch_radius)
    thickness = finite_scalar("thickness", thickness)
    phi = pressure_angle_array(pressure_angle)
    if phi.ndim:
        raise InputError("pressure_angle", "must be one angle (radians), not an array")
    pressure_angle = float(phi)
    r_b = pitch_radius * math.cos(pressure_angle)
    if np.any(radius < r_b * (1 - 1e-12)):
        raise InputError("radius", f"the involute exists only outside the base circle r_b={r_b}")
    phi_r = np.arccos(np.clip(r_b / radius, -1.0, 1.0))
    half_angle = thickness / (2.0 * pitch_radius) + involute(pressure_angle) - involute(phi_r)
    return 2.0 * radius * half_angle


@dataclass(frozen=True)
class Gear:
    """One involute spur gear (external or internal).

    Give the size by ``module`` (pitch diameter per tooth) *or*
    ``diametral_pitch`` (teeth per unit of pitch diameter); the proportions by
    ``system`` or by explicit ``addendum`` and ``dedendum`` lengths.

    Parameters
    ----------
    teeth : int
        Number of teeth ``N`` (a whole number, at least 3, and the tip must not
        be pointed).
    module : float, optional
        Module ``m = d / N``.
    diametral_pitch : float, optional
        Diametral pitch ``P_d = N / d``; then ``m = 1 / P_d``.
    pressure_angle : float, default 20°
        Pressure angle ``φ`` in radians (a pint quantity in degrees is accepted).
    system : {"full_depth", "stub"}, default "full_depth"
        Standard proportions (Norton Table 9-1), unless ``addendum`` and
        ``dedendum`` are given.
    addendum, dedendum : float, optional
        Explicit addendum and dedendum lengths (before profile shift).
    profile_shift : float, default 0
        Profile-shift coefficient ``x``: positive moves the profile ``x m``
        away from the axis (thicker external teeth, thinner internal teeth;
        see the module notes).
    internal : bool, default False
        An internal (ring) gear: its addendum circle lies inside the pitch
        circle and its root circle outside.
    thickness_reduction : float, default 0
        Amount by which the pitch-circle tooth thickness is thinned to give
        backlash (a length).

    Examples
    --------
    The pinion of the notes' final-exam gear set (r_p = 1.5 in and a_p = 0.125 in
    are 24 teeth of P_d = 8, full depth, 20°; the exam rounds p_b to 0.3689):

    >>> p = Gear(24, diametral_pitch=8)
    >>> p.pitch_radius, p.addendum, round(p.base_pitch, 4)
    (1.5, 0.125, 0.369)
    >>> Gear(20, module=2.0, profile_shift=0.3).addendum_radius
    22.6
    """

    teeth: int
    module: float | None = None
    diametral_pitch: float | None = None
    pressure_angle: float = math.radians(20.0)
    system: str = "full_depth"
    given_addendum: float | None = field(default=None, repr=False)
    given_dedendum: float | None = field(default=None, repr=False)
    profile_shift: float = 0.0
    internal: bool = False
    thickness_reduction: float = 0.0

    def __init__(
        self,
        teeth: int,
        *,
        module: float | None = None,
        diametral_pitch: float | None = None,
        pressure_angle: float = math.radians(20.0),
        system: str = "full_depth",
        addendum: float | None = None,
        dedendum: float | None = None,
        profile_shift: float = 0.0,
        internal: bool = False,
        thickness_reduction: float = 0.0,
    ) -> None:
        s = object.__setattr__
        s(self, "teeth", integer("teeth", teeth, minimum=MIN_TEETH, maximum=MAX_TEETH))
        if (module is None) == (diametral_pitch is None):
            raise InputError("module", "give exactly one of module or diametral_pitch")
        if module is not None:
            m = positive("module", module)
            s(self, "module", m)
            s(self, "diametral_pitch", None)
        else:
            pd = positive("diametral_pitch", diametral_pitch)
            s(self, "module", 1.0 / pd)
            s(self, "diametral_pitch", pd)
        phi = finite_scalar("pressure_angle", magnitude(pressure_angle, "radian"))
        if not 0.0 < phi < math.radians(45.0):
            hint = f"; did you pass degrees? use math.radians({phi:g})" if phi >= 1.0 else ""
            raise InputError(
                "pressure_angle",
                f"must be in radians, between 0 and π/4 (45°); got {phi:g} rad"
                f" ({math.degrees(phi):.4g}°){hint}",
            )
        s(self, "pressure_angle", phi)
        s(self, "system", choice("system", system, SYSTEMS))
        if (addendum is None) != (dedendum is None):
            raise InputError("addendum", "give both addendum and dedendum, or neither")
        s(self, "given_addendum", None if addendum is None else positive("addendum", addendum))
        s(self, "given_dedendum", None if dedendum is None else positive("dedendum", dedendum))
        s(self, "profile_shift", finite_scalar("profile_shift", profile_shift))
        s(self, "internal", boolean("internal", internal))
        s(self, "thickness_reduction", nonnegative("thickness_reduction", thickness_reduction))
        self._check()

    def _check(self) -> None:
        if self.clearance <= 0.0:
            raise InputError(
                "dedendum", "must exceed the addendum so that there is tip-to-root clearance"
            )
        if self.root_radius <= 0.0:
            raise InputError(
                "teeth", f"{self.teeth} teeth leave no room for the root circle; use more teeth"
            )
        if self.thickness_reduction >= self.thickness_standard:
            raise InputError(
                "thickness_reduction",
                f"must be smaller than the tooth thickness {self.thickness_standard:.4g}",
            )
        if self.internal and self.addendum_radius <= self.base_radius:
            shift = " or a larger profile shift" if self.profile_shift <= 0 else ""
            raise InputError(
                "teeth",
                f"an internal gear of {self.teeth} teeth has its tip circle inside its base"
                f" circle; use more teeth, a shorter addendum{shift}",
            )
        if self.internal:
            space_at_root = tooth_thickness_at(
                self.root_radius, self.pitch_radius, self.space_width, self.pressure_angle
            )
            if space_at_root <= 0.0:
                raise InputError(
                    "profile_shift",
                    f"{self.profile_shift:g} closes the spaces of this internal gear before its"
                    " root circle (no cutter can cut them); use a smaller shift",
                )
        if self.tip_thickness <= 0.0:
            raise InputError(
                "teeth",
                f"{self.teeth} teeth give pointed teeth (tip thickness"
                f" {self.tip_thickness:.4g}); use more teeth, less profile shift, less thinning"
                " or a shorter addendum",
            )

    # -- sizes -------------------------------------------------------------
    @property
    def _shift(self) -> float:
        """``x m`` towards the tip: ``+x m`` outside, ``−x m`` for an internal gear."""
        return (-1.0 if self.internal else 1.0) * self.profile_shift * self.module

    @property
    def pitch_radius(self) -> float:
        """Reference pitch radius ``r = m N / 2``."""
        return self.module * self.teeth / 2.0

    @property
    def pitch_diameter(self) -> float:
        """Reference pitch diameter ``d = m N``."""
        return self.module * self.teeth

    @property
    def base_radius(self) -> float:
        """Base-circle radius ``r_b = r cos φ``."""
        return self.pitch_radius * math.cos(self.pressure_angle)

    @property
    def addendum(self) -> float:
        """Addendum after profile shift: ``(k_a + x) m``, internal ``(k_a − x) m``.

        With explicit proportions, the given addendum plus (internal: minus) ``x m``.
        """
        base = (
            SYSTEMS[self.system][0] * self.module
            if self.given_addendum is None
            else self.given_addendum
        )
        return base + self._shift

    @property
    def dedendum(self) -> float:
        """Dedendum after profile shift: ``(k_d − x) m``, internal ``(k_d + x) m``."""
        base = (
            SYSTEMS[self.system][1] * self.module
            if self.given_dedendum is None
            else self.given_dedendum
        )
        return base - self._shift

    @property
    def clearance(self) -> float:
        """Tip-to-root clearance ``c = b − a`` of the unshifted proportions."""
        return self.dedendum - self.addendum + 2 * self._shift

    @property
    def addendum_constant(self) -> float:
        """Addendum constant ``k = a / m = P_d a`` (the notes, unshifted)."""
        return (self.addendum - self._shift) / self.module

    @property
    def addendum_radius(self) -> float:
        """Tip (addendum) radius: ``r + a`` outside, ``r − a`` for an internal gear."""
        sign = -1.0 if self.internal else 1.0
        return self.pitch_radius + sign * self.addendum

    @property
    def root_radius(self) -> float:
        """Root (dedendum) radius: ``r − b`` outside, ``r + b`` for an internal gear."""
        sign = 1.0 if self.internal else -1.0
        return self.pitch_radius + sign * self.dedendum

    @property
    def circular_pitch(self) -> float:
        """Circular pitch ``p_c = π m = π d / N``."""
        return math.pi * self.module

    @property
    def base_pitch(self) -> float:
        """Base pitch ``p_b = 2π r cos φ / N = p_c cos φ``."""
        return float(base_pitch(self.pitch_radius, self.teeth, self.pressure_angle))

    # -- thicknesses -------------------------------------------------------
    @property
    def thickness_standard(self) -> float:
        """Pitch-circle tooth thickness before thinning: ``π m / 2 ± 2 x m tan φ``.

        ``+`` for an external gear, ``−`` for an internal one (its space is
        ``π m / 2 + 2 x m tan φ``, the tooth of an external gear of shift ``x``).

        Examples
        --------
        >>> ring = Gear(60, module=2.0, internal=True, profile_shift=0.25)
        >>> round(ring.thickness_standard, 6) == round(2.0 * (math.pi / 2 - 0.5 * math.tan(
        ...     math.radians(20))), 6)
        True
        """
        return math.pi * self.module / 2.0 + 2.0 * self._shift * math.tan(self.pressure_angle)

    @property
    def tooth_thickness(self) -> float:
        """Circular tooth thickness on the reference pitch circle (after thinning)."""
        return self.thickness_standard - self.thickness_reduction

    @property
    def space_width(self) -> float:
        """Circular space width on the reference pitch circle, ``p_c − s``."""
        return self.circular_pitch - self.tooth_thickness

    def thickness_at(self, radius: ArrayLike) -> NDArray[np.float64]:
        """Circular tooth thickness at ``radius`` (external gears; ``>= r_b``).

        For an internal gear it is the *space* width that follows the
        involute law; the tooth thickness is the angular pitch minus it.

        Examples
        --------
        >>> g = Gear(20, module=1.0)
        >>> round(float(g.thickness_at(g.pitch_radius)), 6) == round(math.pi / 2, 6)
        True
        """
        if self.internal:
            space = tooth_thickness_at(
                radius, self.pitch_radius, self.space_width, self.pressure_angle
            )
            return 2 * np.pi * np.asarray(radius, dtype=float) / self.teeth - space
        return tooth_thickness_at(
            radius, self.pitch_radius, self.tooth_thickness, self.pressure_angle
        )

    @property
    def tip_thickness(self) -> float:
        """Circular tooth thickness on the addendum circle (``<= 0``: pointed)."""
        return float(self.thickness_at(max(self.addendum_radius, self.base_radius)))

    def outline(self, points: int = 60, **kwargs: Any) -> Any:
        """Return the generated outline (see :func:`machdyn.gears.profile.gear_outline`).

        Examples
        --------
        >>> Gear(20, module=1.0).outline(points=10).fillet
        'trochoid'
        """
        from .profile import gear_outline

        return gear_outline(self, points, **kwargs)

    def summary(self) -> dict[str, Any]:
        """Return the gear's dimensions as a plain dict (angles in degrees, labelled).

        Examples
        --------
        >>> Gear(24, diametral_pitch=16).summary()["pitch_diameter"]
        1.5
        """
        return {
            "teeth": self.teeth,
            "internal": self.internal,
            "module": self.module,
            "diametral_pitch": self.diametral_pitch,
            "pressure_angle_deg": math.degrees(self.pressure_angle),
            "profile_shift": self.profile_shift,
            "pitch_diameter": self.pitch_diameter,
            "pitch_radius": self.pitch_radius,
            "base_radius": self.base_radius,
            "addendum": self.addendum,
            "dedendum": self.dedendum,
            "addendum_radius": self.addendum_radius,
            "root_radius": self.root_radius,
            "circular_pitch": self.circular_pitch,
            "base_pitch": self.base_pitch,
            "tooth_thickness": self.tooth_thickness,
            "tip_thickness": self.tip_thickness,
        }
