"""Meshing of a pinion and a gear: centre distance, length of action, contact ratio.

The notes (review lecture 3, Figure 9-7; Norton eq. 9.2):

* length of action, from first contact to final separation along the line of
  action, ``Z = √((r_p + a_p)² − (r_p cos φ)²) + √((r_g + a_g)² − (r_g cos φ)²) − C sin φ``;
* contact ratio ``m_p = Z / p_b`` — the average number of tooth pairs in
  contact; below 1.2 is unacceptable, 1.4 or more is the target;
* a changed centre distance ``C'`` changes the pressure angle,
  ``cos φ' = (C / C') cos φ``, and the pitch radii ``r' = r_b / cos φ'``, but not
  the velocity ratio ``ω_g / ω_p = r_bp / r_bg`` (Figure 9-8).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validate import broadcast, choice, positive
from ..errors import InputError
from ._checks import finite, pressure_angle_array
from .geometry import Gear, inverse_involute, involute

__all__ = [
    "CONTACT_RATIO_MINIMUM",
    "CONTACT_RATIO_TARGET",
    "DRIVERS",
    "GearPair",
    "backlash_from_center_distance",
    "contact_ratio",
    "contact_ratio_rating",
    "length_of_action",
    "operating_pressure_angle",
]

#: The notes' minimum acceptable contact ratio.
CONTACT_RATIO_MINIMUM = 1.2
#: The notes' standard target: ``m_p >= 1.4``.
CONTACT_RATIO_TARGET = 1.4
#: Which member of a :class:`GearPair` drives.
DRIVERS = ("pinion", "gear")


def operating_pressure_angle(
    standard_center_distance: ArrayLike,
    center_distance: ArrayLike,
    pressure_angle: ArrayLike,
) -> NDArray[np.float64]:
    """Operating pressure angle ``φ'`` from ``cos φ' = (C / C') cos φ`` (Figure 9-8).

    Parameters
    ----------
    standard_center_distance : array_like
        Centre distance ``C`` at which the pressure angle is ``φ``.
    center_distance : array_like
        Operating centre distance ``C'``.
    pressure_angle : array_like
        Pressure angle ``φ`` (radians) at ``C``.

    Returns
    -------
    ndarray
        ``φ'`` in radians.

    Raises
    ------
    InputError
        If ``C'`` is not above ``C cos φ`` (the sum of the base radii of an
        external pair, their difference for an internal one), if a value is
        not finite, or if the shapes do not broadcast.

    Examples
    --------
    Pulling a 20° pair 2 % apart raises the pressure angle to about 22.9°:

    >>> round(float(np.degrees(operating_pressure_angle(10.0, 10.2, np.radians(20)))), 2)
    22.89
    """
    c = finite("standard_center_distance", standard_center_distance, "must be a finite length")
    c_op = finite("center_distance", center_distance, "must be a finite length")
    phi = pressure_angle_array(pressure_angle)
    broadcast(standard_center_distance=c, center_distance=c_op, pressure_angle=phi)
    if np.any(c <= 0):
        raise InputError("standard_center_distance", "must be a positive length")
    cos_op = c * np.cos(phi) / np.where(c_op > 0, c_op, np.inf)
    if np.any(c_op <= 0) or np.any(cos_op > 1.0):
        raise InputError(
            "center_distance",
            "must exceed C cos φ (the sum of the base radii of an external pair, their"
            " difference for an internal one): the line of action would not exist",
        )
    return np.arccos(cos_op)


def length_of_action(
    r_gear: ArrayLike,
    a_gear: ArrayLike,
    r_pinion: ArrayLike,
    a_pinion: ArrayLike,
    pressure_angle: ArrayLike,
    center_distance: ArrayLike | None = None,
) -> Any:
    """Length of action ``Z`` of an external pair (the notes, Figure 9-7; Norton eq. 9.2).

    ``Z = √((r_p + a_p)² − (r_p cos φ)²) + √((r_g + a_g)² − (r_g cos φ)²) − C sin φ``

    Parameters
    ----------
    r_gear, a_gear : array_like
        Gear pitch radius and addendum.
    r_pinion, a_pinion : array_like
        Pinion pitch radius and addendum.
    pressure_angle : array_like
        Pressure angle ``φ`` in radians, at the standard centre distance
        ``C = r_g + r_p``.
    center_distance : array_like, optional
        Operating centre distance ``C'``. When given, ``φ`` is replaced by the
        operating pressure angle ``cos φ' = (C / C') cos φ`` and ``C`` by ``C'``
        (the base and addendum circles do not move with the centres).

    Returns
    -------
    ndarray or float
        ``Z``, in the unit of the radii (a float for scalar input), always > 0.

    Raises
    ------
    InputError
        If a value is not finite or out of range, if the shapes do not
        broadcast, or if ``C'`` is so large that the addendum circles no longer
        cross on the line of action (``Z <= 0``, the teeth lose contact); the
        message gives the largest centre distance with contact,
        ``C'_max = √((z_p + z_g)² + (r_bp + r_bg)²)`` where
        ``z = √(r_a² − r_b²)``.

    Examples
    --------
    The notes' final exam, problem 10 (φ = 20°, r_g = 3.75, a_g = 0.125,
    r_p = 1.5, a_p = 0.125 in):

    >>> round(float(length_of_action(3.75, 0.125, 1.5, 0.125, np.radians(20))), 4)
    0.6249

    Pulled apart to 6 in, the addendum circles no longer cross on the line of
    action:

    >>> length_of_action(3.75, 0.125, 1.5, 0.125, np.radians(20), 6.0)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: center_distance: 6 is too large: the teeth lose contact ...
    """
    rg = finite("r_gear", r_gear, "must be a positive, finite pitch radius")
    rp = finite("r_pinion", r_pinion, "must be a positive, finite pitch radius")
    ag = finite("a_gear", a_gear, "must be a finite addendum >= 0")
    ap = finite("a_pinion", a_pinion, "must be a finite addendum >= 0")
    phi = pressure_angle_array(pressure_angle)
    for name, value in (("r_gear", rg), ("r_pinion", rp)):
        if np.any(value <= 0) or not np.all(np.isfinite(value)):
            raise InputError(name, "must be a positive, finite pitch radius")
    for name, value in (("a_gear", ag), ("a_pinion", ap)):
        if np.any(value < 0) or not np.all(np.isfinite(value)):
            raise InputError(name, "must be a finite addendum >= 0")
    given = {"r_gear": rg, "a_gear": ag, "r_pinion": rp, "a_pinion": ap, "pressure_angle": phi}
    if center_distance is None:
        broadcast(**given)
        c_op, phi_op = rg + rp, phi
    else:
        c_op = finite("center_distance", center_distance, "must be a finite length")
        broadcast(**given, center_distance=c_op)
        phi_op = operating_pressure_angle(rg + rp, c_op, phi)
    rbg, rbp = rg * np.cos(phi), rp * np.cos(phi)
    # Distances along the line of action from each base-circle tangent point to the tip circle.
    zp, zg = np.sqrt((rp + ap) ** 2 - rbp**2), np.sqrt((rg + ag) ** 2 - rbg**2)
    z = zp + zg - c_op * np.sin(phi_op)
    lost = z <= 0
    if np.any(lost):
        i = int(np.flatnonzero(lost.ravel())[0])
        at = np.broadcast_arrays(c_op, z, np.hypot(zp + zg, rbp + rbg))
        c_bad, z_bad, c_max = (float(a.ravel()[i]) for a in at)
        if center_distance is None:  # only zero addenda do this at the standard distance
            raise InputError("a_pinion", "the teeth have no contact with zero addenda (Z = 0)")
        raise InputError(
            "center_distance",
            f"{c_bad:g} is too large: the teeth lose contact (Z = {z_bad:.4g}); contact"
            f" needs a centre distance below {c_max:.6g}",
        )
    return z if np.ndim(z) else float(z)


def contact_ratio(length_of_action: ArrayLike, base_pitch: ArrayLike) -> Any:
    """Contact ratio ``m_p = Z / p_b`` (the notes, review lecture 3).

    Parameters
    ----------
    length_of_action : array_like
        Length of action ``Z``.
    base_pitch : array_like
        Base pitch ``p_b``.

    Returns
    -------
    ndarray or float
        The average number of tooth pairs in contact.

    Raises
    ------
    InputError
        If ``Z`` is negative or not finite (teeth that do not reach each
        other have no contact ratio), if ``p_b`` is not a positive length, or
        if the shapes do not broadcast.

    Examples
    --------
    The notes' final exam, problem 10 (p_b = 0.3689 in):

    >>> z = length_of_action(3.75, 0.125, 1.5, 0.125, np.radians(20))
    >>> round(float(contact_ratio(z, 0.3689)), 3)
    1.694
    """
    z = finite("length_of_action", length_of_action, "must be a finite length")
    pb = finite("base_pitch", base_pitch, "must be a positive, finite length")
    if np.any(pb <= 0):
        raise InputError("base_pitch", "must be a positive, finite length")
    broadcast(length_of_action=z, base_pitch=pb)
    if np.any(z < 0):
        raise InputError(
            "length_of_action",
            f"must be >= 0, got {float(z.min()):g}: a negative Z means the tip circles no"
            " longer cross on the line of action (the centre distance is too large)",
        )
    out = z / pb
    return out if np.ndim(out) else float(out)


def contact_ratio_rating(contact_ratio: ArrayLike) -> Any:
    """Rate a contact ratio by the notes' thresholds.

    ``"no contact"`` (``m_p < 1``: the mesh loses contact between teeth),
    ``"unacceptable"`` (``< 1.2``), ``"acceptable"`` (``1.2 <= m_p < 1.4``),
    ``"good"`` (``>= 1.4``, the standard target range).

    Examples
    --------
    >>> contact_ratio_rating([0.9, 1.1, 1.3, 1.7]).tolist()
    ['no contact', 'unacceptable', 'acceptable', 'good']
    """
    mp = finite("contact_ratio", contact_ratio, "must be a finite number >= 0")
    if np.any(mp < 0):
        raise InputError("contact_ratio", f"must be >= 0, got {float(mp.min()):g}")
    out = np.select(
        [mp < 1.0, mp < CONTACT_RATIO_MINIMUM, mp < CONTACT_RATIO_TARGET],
        ["no contact", "unacceptable", "acceptable"],
        "good",
    )
    return out if np.ndim(out) else str(out)


def backlash_from_center_distance(
    center_distance_increase: ArrayLike, pressure_angle: ArrayLike
) -> Any:
    """Approximate circular backlash from a centre-distance increase, ``B ≈ 2 ΔC tan φ``.

    The first-order estimate (Norton Ch. 9, "Backlash"); :attr:`GearPair.backlash`
    gives the exact value from the involute tooth thicknesses.

    Parameters
    ----------
    center_distance_increase : array_like
        ``ΔC = C' − C`` (negative: the centres moved closer, the estimate is
        the loss of backlash).
    pressure_angle : array_like
        Pressure angle ``φ`` in radians (a pint quantity is converted).

    Returns
    -------
    ndarray or float
        ``B``, in the unit of ``ΔC``.

    Raises
    ------
    InputError
        A value that is not finite, a pressure angle outside ``0 < φ < π/2``
        (for example degrees passed as radians), or shapes that do not
        broadcast.

    Examples
    --------
    >>> round(float(backlash_from_center_distance(0.01, np.radians(20))), 6)
    0.00728
    """
    dc = finite("center_distance_increase", center_distance_increase, "must be a finite length")
    phi = pressure_angle_array(pressure_angle)
    broadcast(center_distance_increase=dc, pressure_angle=phi)
    out = 2.0 * dc * np.tan(phi)
    return out if np.ndim(out) else float(out)


def _half_angle(gear: Gear, thinned: bool) -> float:
    """``s / (2 r) + inv φ`` of a tooth (external) or of a space (internal)."""
    s = gear.tooth_thickness if thinned else gear.thickness_standard
    width = gear.circular_pitch - s if gear.internal else s
    return width / (2.0 * gear.pitch_radius) + float(involute(gear.pressure_angle))


#: Summary keys of a gear pair that are not lengths (the rest of the numbers are).
_NOT_LENGTHS = ("teeth", "profile_shift", "velocity_ratio", "gear_ratio", "contact_ratio")


def _kind_of_key(key: str, value: Any) -> str | None:
    """The kind of a gear-pair summary entry (None: a count, flag, text or ratio)."""
    name = key.rpartition(".")[2]
    if isinstance(value, bool | str) or not isinstance(value, int | float) or name in _NOT_LENGTHS:
        return None
    if name.endswith("_deg"):
        return None  # already labelled
    return "inverse_length" if name == "diametral_pitch" else "length"


def _shown(system: Any, key: str, value: Any) -> Any:
    kind = _kind_of_key(key, value)
    return value if kind is None or value is None else system.show(kind, float(value))


@dataclass(frozen=True, init=False)
class GearPair:
    """A pinion meshing with a gear (external pair, or pinion inside a ring gear).

    Parameters
    ----------
    pinion : Gear
        The smaller, external gear.
    gear : Gear
        The mating gear, external or internal, with the same module and
        pressure angle.
    center_distance : float, optional
        Operating centre distance ``C'``. Default: the tight-mesh centre
        distance of the (unthinned) teeth, which is the standard
        ``C = (N_g ± N_p) m / 2`` when the profile shifts add to zero.
    driver : {"pinion", "gear"}, default "pinion"
        The member that drives. It decides which end of the path of contact
        is the first contact, so it splits the length of action into approach
        and recess (:attr:`path_of_approach`, :attr:`angles_of_approach`);
        nothing else depends on it.

    Raises
    ------
    InputError
        Mismatched module or pressure angle, two internal gears, an internal
        gear that is not larger than the pinion, or a centre distance at which
        the teeth jam (negative backlash), a tip hits the other root, or the
        teeth lose contact (the tip circles no longer cross on the line of
        action, ``Z <= 0``: too far apart for an external pair, too close
        together for an internal one).

    Examples
    --------
    >>> import math
    >>> pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
    >>> pair.center_distance, round(pair.contact_ratio, 3), pair.contact_ratio_rating
    (5.25, 1.693, 'good')
    >>> wide = pair.with_center_distance(5.30)
    >>> wide.velocity_ratio == pair.velocity_ratio == -0.4
    True
    >>> round(math.degrees(wide.operating_pressure_angle), 3)
    21.436

    Whichever member drives, approach and recess share the same length of
    action; they swap ends:

    >>> up = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8), driver="gear")
    >>> round(pair.path_of_approach, 4), round(up.path_of_approach, 4)
    (0.3293, 0.2956)
    """

    pinion: Gear
    gear: Gear
    center_distance: float
    driver: str = "pinion"

    def __init__(
        self,
        pinion: Gear,
        gear: Gear,
        center_distance: float | None = None,
        *,
        driver: str = "pinion",
    ) -> None:
        if not isinstance(pinion, Gear) or not isinstance(gear, Gear):
            raise InputError("pinion", "pinion and gear must be machdyn.gears.Gear objects")
        if pinion.internal:
            raise InputError("pinion", "the pinion must be an external gear")
        if not math.isclose(pinion.module, gear.module, rel_tol=1e-9):
            raise InputError(
                "gear",
                f"module/pitch mismatch: pinion m={pinion.module:g} (P_d={1 / pinion.module:g}),"
                f" gear m={gear.module:g} (P_d={1 / gear.module:g}); mating gears need the"
                " same pitch",
            )
        if not math.isclose(pinion.pressure_angle, gear.pressure_angle, rel_tol=1e-9):
            raise InputError(
                "gear",
                f"pressure-angle mismatch: pinion {math.degrees(pinion.pressure_angle):g}°,"
                f" gear {math.degrees(gear.pressure_angle):g}°; mating gears need the same one",
            )
        if gear.internal and gear.teeth <= pinion.teeth:
            raise InputError("gear", "an internal gear must have more teeth than its pinion")
        object.__setattr__(self, "pinion", pinion)
        object.__setattr__(self, "gear", gear)
        object.__setattr__(self, "driver", choice("driver", driver, DRIVERS))
        if center_distance is None:
            c_op = self.tight_center_distance
        else:
            c_op = positive("center_distance", center_distance)
        object.__setattr__(self, "center_distance", c_op)
        self._check_center_distance(given=center_distance is not None)

    def with_center_distance(self, center_distance: float) -> GearPair:
        """Return the same gears at another operating centre distance.

        Examples
        --------
        >>> pair = GearPair(Gear(20, module=2.0), Gear(40, module=2.0))
        >>> round(pair.with_center_distance(60.2).backlash, 4)  # ≈ 2 ΔC tan φ = 0.1456
        0.1479
        """
        return GearPair(self.pinion, self.gear, center_distance, driver=self.driver)

    def with_driver(self, driver: str) -> GearPair:
        """Return the same pair with ``driver`` ("pinion" or "gear") driving.

        Examples
        --------
        >>> pair = GearPair(Gear(20, module=2.0), Gear(40, module=2.0))
        >>> back = pair.with_driver("gear")
        >>> back.driver, back.path_of_approach == pair.path_of_recess
        ('gear', True)
        """
        return GearPair(self.pinion, self.gear, self.center_distance, driver=driver)

    # -- centre distance and pressure angle ---------------------------------
    @property
    def internal(self) -> bool:
        """True for a pinion inside a ring gear."""
        return self.gear.internal

    @property
    def _sign(self) -> float:
        return -1.0 if self.internal else 1.0

    @property
    def standard_center_distance(self) -> float:
        """``C = r_g + r_p`` (external) or ``r_g − r_p`` (internal), reference pitch radii."""
        return self.gear.pitch_radius + self._sign * self.pinion.pitch_radius

    def _operating_angle_for_zero_backlash(self, thinned: bool) -> float:
        bp, bg = _half_angle(self.pinion, thinned), _half_angle(self.gear, thinned)
        n_p, n_g = self.pinion.teeth, self.gear.teeth
        if self.internal:
            inv = (n_g * bg - n_p * bp) / (n_g - n_p)
        else:
            inv = (n_p * bp + n_g * bg - math.pi) / (n_p + n_g)
        if inv <= 0:
            raise InputError(
                "profile_shift", "the profile shifts are too negative for the teeth to mesh"
            )
        return float(inverse_involute(inv))

    @property
    def tight_center_distance(self) -> float:
        """Centre distance at zero backlash for unthinned teeth (standard if Σx = 0)."""
        phi_op = self._operating_angle_for_zero_backlash(thinned=False)
        return self.standard_center_distance * math.cos(self.pressure_angle) / math.cos(phi_op)

    @property
    def pressure_angle(self) -> float:
        """Reference (cutting) pressure angle ``φ``."""
        return self.pinion.pressure_angle

    @cached_property
    def operating_pressure_angle(self) -> float:
        """``φ'`` from ``cos φ' = (C / C') cos φ`` (Figure 9-8).

        Computed once per pair (the pair is immutable); every contact
        property uses it.
        """
        return float(
            operating_pressure_angle(
                self.standard_center_distance, self.center_distance, self.pressure_angle
            )
        )

    @property
    def operating_pitch_radii(self) -> tuple[float, float]:
        """Operating pitch radii ``(r_p', r_g') = r_b / cos φ'`` of pinion and gear."""
        c = math.cos(self.operating_pressure_angle)
        return self.pinion.base_radius / c, self.gear.base_radius / c

    @property
    def velocity_ratio(self) -> float:
        """Signed ``ω_g / ω_p = ∓ r_p' / r_g'`` (negative for an external pair).

        Computed from the operating pitch radii, it equals ``∓ N_p / N_g`` at any
        centre distance: the velocity ratio does not change (Figure 9-8).
        """
        rp, rg = self.operating_pitch_radii
        return -self._sign * rp / rg

    @property
    def gear_ratio(self) -> float:
        """``m_G = N_g / N_p`` (>= 1)."""
        return self.gear.teeth / self.pinion.teeth

    # -- contact -------------------------------------------------------------
    def _tip_paths(self) -> tuple[float, float, float]:
        """Return ``(√(r_ap² − r_bp²), √(r_ag² − r_bg²), C' sin φ')``.

        The first two are the distances along the line of action from each
        base-circle tangent point to that gear's tip circle; the last is the
        distance between the two tangent points (external pair) — for an
        internal pair it is the same expression, the tangent points lying on
        the same side of the pitch point.
        """
        p, g = self.pinion, self.gear
        zp = math.sqrt(p.addendum_radius**2 - p.base_radius**2)
        zg = math.sqrt(g.addendum_radius**2 - g.base_radius**2)
        return zp, zg, self.center_distance * math.sin(self.operating_pressure_angle)

    @property
    def length_of_action(self) -> float:
        """Length of action ``Z`` at the operating centre distance (Figure 9-7).

        The notes' formula assumes involute action from tip to tip; when a tip
        interferes (:attr:`interference`), real contact would run below the
        mate's base circle and ``Z`` (hence ``m_p``) is optimistic.
        """
        zp, zg, c_sin = self._tip_paths()
        if self.internal:
            return zp - zg + c_sin
        return zp + zg - c_sin

    @property
    def base_pitch(self) -> float:
        """Base pitch ``p_b`` (the same for both gears)."""
        return self.pinion.base_pitch

    @property
    def contact_ratio(self) -> float:
        """Contact ratio ``m_p = Z / p_b``."""
        return float(contact_ratio(self.length_of_action, self.base_pitch))

    @property
    def contact_ratio_rating(self) -> str:
        """The notes' verdict: "no contact", "unacceptable", "acceptable" or "good".

        When the pair interferes the length of action (and so the contact ratio)
        is overstated, and the verdict says so.
        """
        rating = str(contact_ratio_rating(self.contact_ratio))
        if self.interferes:
            rating += " (but the teeth interfere: the contact ratio is overstated)"
        return rating

    def _tip_paths_from_pitch_point(self) -> tuple[float, float]:
        """Distances from the pitch point to where the (pinion, gear) tip circles cut the line.

        The pinion's tip point lies on the far side of the pitch point from
        the pinion's base-circle tangent point, ``√(r_ap² − r_bp²) − r_p' sin φ'``;
        the gear's tip point lies on the far side from the gear's tangent point
        (external pair), ``√(r_ag² − r_bg²) − r_g' sin φ'``, or between the pitch
        point and that tangent point (internal pair: the ring's tip circle is
        inside its pitch circle), ``r_g' sin φ' − √(r_ag² − r_bg²)``. The two
        add up to the length of action.
        """
        zp, zg, _ = self._tip_paths()
        rp_op, rg_op = self.operating_pitch_radii
        s = math.sin(self.operating_pressure_angle)
        gear_side = rg_op * s - zg if self.internal else zg - rg_op * s
        return zp - rp_op * s, gear_side

    @property
    def path_of_approach(self) -> float:
        """Length of the line of action from first contact to the pitch point.

        Contact begins where the *driven* member's tip circle crosses the line
        of action (the notes' Figure 9-7; Norton Ch. 9): the driver's flank first touches the
        driven tooth's tip, low on its own flank. With the pinion driving (the
        default) that is the gear's tip circle; with the gear driving, the
        pinion's — approach and recess swap ends.

        Examples
        --------
        The notes' final-exam set (24/60 teeth, P_d = 8, 20°): the gear's tip
        circle cuts the line of action 1.6119 in from the gear's tangent point,
        ``r_g sin φ = 1.2826`` in from the pitch point:

        >>> pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
        >>> round(pair.path_of_approach, 4)
        0.3293
        """
        pinion_tip, gear_tip = self._tip_paths_from_pitch_point()
        return gear_tip if self.driver == "pinion" else pinion_tip

    @property
    def path_of_recess(self) -> float:
        """Length of the line of action from the pitch point to the last contact.

        Contact ends where the *driver's* tip circle crosses the line of action.

        Examples
        --------
        >>> pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
        >>> round(pair.path_of_recess, 4), round(pair.with_driver("gear").path_of_recess, 4)
        (0.2956, 0.3293)
        """
        pinion_tip, gear_tip = self._tip_paths_from_pitch_point()
        return pinion_tip if self.driver == "pinion" else gear_tip

    @property
    def arc_of_approach(self) -> float:
        """Arc of approach on the operating pitch circles, ``path of approach / cos φ'``.

        The pitch circles roll on each other, so the arc is the same on both
        (Norton Figure 9-7); over each pitch radius it is that member's angle.

        Examples
        --------
        >>> pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
        >>> round(pair.arc_of_approach, 4)  # 0.3293 / cos 20°
        0.3504
        """
        return self.path_of_approach / math.cos(self.operating_pressure_angle)

    @property
    def arc_of_recess(self) -> float:
        """Arc of recess on the operating pitch circles, ``path of recess / cos φ'``.

        Examples
        --------
        >>> pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
        >>> round(pair.arc_of_recess, 4)  # 0.2956 / cos 20°
        0.3146
        """
        return self.path_of_recess / math.cos(self.operating_pressure_angle)

    @property
    def angles_of_approach(self) -> tuple[float, float]:
        """Angles (rad) turned by ``(pinion, gear)`` during approach, by :attr:`driver`.

        The arc of approach on an operating pitch circle over its radius,
        which is the path of approach over the base radius (the line of action
        unwinds from each base circle like a taut string). Both members turn
        through their angles in the same time, in the ratio ``N_p / N_g``.

        Examples
        --------
        >>> pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
        >>> [round(math.degrees(a), 2) for a in pair.angles_of_approach]
        [13.39, 5.35]
        """
        z = self.path_of_approach
        return z / self.pinion.base_radius, z / self.gear.base_radius

    @property
    def angles_of_recess(self) -> tuple[float, float]:
        """Angles (rad) turned by ``(pinion, gear)`` during recess, by :attr:`driver`.

        Examples
        --------
        >>> pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
        >>> [round(math.degrees(a), 2) for a in pair.with_driver("gear").angles_of_recess]
        [13.39, 5.35]
        """
        z = self.path_of_recess
        return z / self.pinion.base_radius, z / self.gear.base_radius

    # -- backlash and interference --------------------------------------------
    @property
    def backlash(self) -> float:
        """Circular backlash on the operating pitch circles (exact involute relation).

        From the centre-distance increase over the tight mesh and from any
        tooth-thickness reduction; ``≈ 2 ΔC tan φ + Δs_p + Δs_g``.
        """
        inv_op = float(involute(self.operating_pressure_angle))
        rp_op, rg_op = self.operating_pitch_radii
        bp, bg = _half_angle(self.pinion, True), _half_angle(self.gear, True)
        s_p = 2 * rp_op * (bp - inv_op)
        if self.internal:
            return 2 * rg_op * (bg - inv_op) - s_p
        return 2 * math.pi * rp_op / self.pinion.teeth - s_p - 2 * rg_op * (bg - inv_op)

    @property
    def radial_clearances(self) -> tuple[float, float]:
        """Radial gaps (gear tip to pinion root, pinion tip to gear root)."""
        p, g, c = self.pinion, self.gear, self.center_distance
        if self.internal:
            return g.addendum_radius - c - p.root_radius, g.root_radius - c - p.addendum_radius
        return c - g.addendum_radius - p.root_radius, c - p.addendum_radius - g.root_radius

    @property
    def contact_limit(self) -> float:
        """Centre distance at which the teeth lose contact (``Z = 0``).

        With ``z = √(r_a² − r_b²)`` for each gear and ``C' sin φ' = √(C'² − (r_bg ± r_bp)²)``,
        ``Z = 0`` gives ``C' = √((z_p + z_g)² + (r_bp + r_bg)²)`` for an
        external pair (an upper limit) and ``C' = √((z_g − z_p)² + (r_bg − r_bp)²)``
        for an internal one (a lower limit; ``r_bg − r_bp`` when ``z_g <= z_p``,
        where the line of action itself vanishes).

        Examples
        --------
        >>> pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
        >>> round(pair.contact_limit, 4)
        5.4952
        """
        p, g = self.pinion, self.gear
        zp = math.sqrt(p.addendum_radius**2 - p.base_radius**2)
        zg = math.sqrt(g.addendum_radius**2 - g.base_radius**2)
        if self.internal:
            return math.hypot(max(zg - zp, 0.0), g.base_radius - p.base_radius)
        return math.hypot(zp + zg, p.base_radius + g.base_radius)

    def _check_center_distance(self, given: bool = True) -> None:
        c = self.center_distance
        # An external pair moves out of mesh as C' grows; a pinion inside a ring as C' shrinks.
        too_deep, too_shallow = ("large", "small") if self.internal else ("small", "large")
        bound = "at most" if self.internal else "at least"
        clear = self.radial_clearances
        if min(clear) < -1e-12 * self.pinion.module:
            limit = c + min(clear) if self.internal else c - min(clear)
            if not given:  # the tight mesh of these shifts itself: the shifts are to blame
                shift = self.pinion.profile_shift + self.gear.profile_shift
                raise InputError(
                    "profile_shift",
                    f"the shifts (x_p + x_g = {shift:g}) leave no tip clearance at the "
                    f"tight-mesh centre distance {c:g}: a tip reaches {-min(clear):.4g} into the "
                    "mating root; shorten the addenda (give addendum= and dedendum=) by at least "
                    f"that, use smaller shifts, or give a centre distance of {bound} {limit:g} "
                    "(with backlash)",
                )
            raise InputError(
                "center_distance",
                f"{c:g} is too {too_deep}: a tooth tip hits the mating root (the clearance allows"
                f" a centre distance of {bound} {limit:g}; standard is"
                f" {self.standard_center_distance:g})",
            )
        limit = self.contact_limit
        if (c <= limit) if self.internal else (c >= limit):
            z = self.length_of_action if c > self._base_line() else float("nan")
            z_text = f" (Z = {z:.4g})" if math.isfinite(z) else ""
            need = "above" if self.internal else "below"
            raise InputError(
                "center_distance",
                f"{c:g} is too {too_shallow}: the teeth lose contact{z_text}; contact needs a"
                f" centre distance {need} {limit:.6g} (standard is"
                f" {self.standard_center_distance:g})",
            )
        if self.backlash < -1e-9 * self.pinion.module:
            raise InputError(
                "center_distance",
                f"{c:g} is too {too_deep}: the teeth jam (backlash {self.backlash:.4g}); the"
                f" tight-mesh centre distance of these teeth is"
                f" {self._zero_backlash_distance():g}",
            )

    def _base_line(self) -> float:
        """``C' cos φ'``: the sum (external) or difference (internal) of the base radii."""
        return self.gear.base_radius + self._sign * self.pinion.base_radius

    def _zero_backlash_distance(self) -> float:
        phi_op = self._operating_angle_for_zero_backlash(thinned=True)
        return self.standard_center_distance * math.cos(self.pressure_angle) / math.cos(phi_op)

    @property
    def interference(self) -> tuple[bool, bool]:
        """Whether (the gear tip, the pinion tip) reaches past the mate's interference point.

        Interference (Figure 9-12): contact below a base circle, where the
        profile cannot be involute. An external tip interferes when its
        intersection with the line of action lies beyond the tangent point of
        the mate's base circle, ``√(r_a² − r_b²) > C' sin φ'``.
        """
        zp, zg, c_sin = self._tip_paths()
        tol = 1e-12 * self.pinion.module
        if self.internal:
            # The ring's inner tip must stay beyond the pinion's tangent point.
            return zg < c_sin - tol, False
        return zg > c_sin + tol, zp > c_sin + tol

    @property
    def interferes(self) -> bool:
        """True if either tip interferes (see :attr:`interference`)."""
        return any(self.interference)

    def plot(
        self,
        pinion_angle: float = 0.0,
        ax: Any = None,
        points: int = 40,
        cutter_teeth: int | None = None,
    ) -> Any:
        """Draw the pair in mesh (see :func:`machdyn.gears.profile.plot_mesh`).

        Examples
        --------
        >>> import matplotlib.pyplot as plt
        >>> ax = GearPair(Gear(18, module=1.0), Gear(40, module=1.0)).plot()
        >>> plt.close("all")
        """
        from .profile import plot_mesh

        return plot_mesh(self, pinion_angle, ax, points, cutter_teeth)

    def to_pandas(self) -> Any:
        """Return :meth:`summary` flattened into a pandas Series (``pinion.*``, ``gear.*``).

        Examples
        --------
        >>> s = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8)).to_pandas()
        >>> float(s["pinion.pitch_radius"]), s["contact_ratio_rating"]
        (1.5, 'good')
        """
        import pandas as pd

        from ..units import units_of

        flat: dict[str, Any] = {}
        for key, value in self.summary().items():
            if isinstance(value, dict):
                flat |= {f"{key}.{k}": v for k, v in value.items()}
            else:
                flat[key] = value
        system = units_of(self)  # a machine file's pair: "pinion.pitch_radius [in]", ...
        if system is not None:
            flat = {
                (k if _kind_of_key(k, v) is None else system.label(k, _kind_of_key(k, v))): (
                    _shown(system, k, v)
                )
                for k, v in flat.items()
            }
        return pd.Series(flat, dtype=object)

    def to_spec(self, name: str = "gear_pair") -> dict[str, Any]:
        """The pair as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from ..spec import model_spec

        return model_spec(self, "gear_pair", name)

    def summary(self) -> dict[str, Any]:
        """Return geometry, contact and interference as a plain dict (angles in degrees).

        Examples
        --------
        >>> pair = GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8))
        >>> pair.summary()["interferes"]
        False
        """
        a_app, a_rec = self.angles_of_approach, self.angles_of_recess
        gear_tip, pinion_tip = self.interference
        return {
            "pinion": self.pinion.summary(),
            "gear": self.gear.summary(),
            "internal": self.internal,
            "driver": self.driver,
            "standard_center_distance": self.standard_center_distance,
            "center_distance": self.center_distance,
            "operating_pressure_angle_deg": math.degrees(self.operating_pressure_angle),
            "operating_pitch_radius_pinion": self.operating_pitch_radii[0],
            "operating_pitch_radius_gear": self.operating_pitch_radii[1],
            "velocity_ratio": self.velocity_ratio,
            "gear_ratio": self.gear_ratio,
            "length_of_action": self.length_of_action,
            "path_of_approach": self.path_of_approach,
            "path_of_recess": self.path_of_recess,
            "arc_of_approach": self.arc_of_approach,
            "arc_of_recess": self.arc_of_recess,
            "base_pitch": self.base_pitch,
            "contact_ratio": self.contact_ratio,
            "contact_ratio_rating": self.contact_ratio_rating,
            "angle_of_approach_pinion_deg": math.degrees(a_app[0]),
            "angle_of_approach_gear_deg": math.degrees(a_app[1]),
            "angle_of_recess_pinion_deg": math.degrees(a_rec[0]),
            "angle_of_recess_gear_deg": math.degrees(a_rec[1]),
            "backlash": self.backlash,
            "interference_gear_tip": gear_tip,
            "interference_pinion_tip": pinion_tip,
            "interferes": self.interferes,
        }
