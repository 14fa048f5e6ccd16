"""Balancing of rotating masses: single-plane (static) and two-plane (dynamic).

A rotor turning at ω carries point masses ``mᵢ`` at radius vectors ``Rᵢ``
(complex, in the rotor's frame, angle from its zero reference line) and axial
positions ``zᵢ``. Each throws a rotating centrifugal force ``mᵢ ω² Rᵢ`` on the
bearings, so only the products ``mᵢRᵢ`` — the *unbalance* — matter.

* **Static balance** (notes, "STATIC BALANCING"; Norton §12.1): one mass
  ``m_b R_b = −Σ mᵢRᵢ`` puts the centre of mass on the axis. Enough for a
  thin disc, not for a long rotor.
* **Dynamic balance** (notes, "DYNAMIC BALANCING", Fig. 12-3; Norton §12.2): two
  masses in correction planes A and B cancel the total force *and* the moment,
  ``Σ mᵢRᵢ + m_A R_A + m_B R_B = 0`` and
  ``Σ mᵢRᵢ (zᵢ − z_A) + m_B R_B (z_B − z_A) = 0`` (moments about plane A), so

  ``m_B R_B = −Σ mᵢRᵢ (zᵢ − z_A) / (z_B − z_A)``,
  ``m_A R_A = −Σ mᵢRᵢ (z_B − zᵢ) / (z_B − z_A)``.

* **Balancing machine** (notes, Problem 12-6; Norton §12.4): the peak bearing
  forces ``F`` measured at ω, with their phases relative to the rotor's zero
  line, are statically equivalent to unbalances ``F/ω²`` at the bearing planes;
  correcting those is a two-plane balance.

Everything broadcasts: ``unbalance`` may carry leading batch axes, the masses are
summed over the last axis. The numbers are unit-agnostic (any consistent system).

Examples
--------
Two equal masses opposite each other in different planes: statically balanced,
dynamically not (they form a couple).

>>> import numpy as np
>>> unbalance = np.array([2.0 + 0j, -2.0 + 0j])      # m·R, e.g. kg·m
>>> static_balance(unbalance).mR
0j
>>> mR_a, mR_b = two_plane(unbalance, z=[1.0, 3.0], plane_a=0.0, plane_b=4.0)
>>> complex(mR_a), complex(mR_b)
((-1+0j), (1+0j))
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._validate import complex_array, finite_array, finite_scalar, positive
from .errors import InputError

__all__ = [
    "StaticBalance",
    "TwoPlaneBalance",
    "bearing_balance",
    "shaking_force",
    "shaking_moment",
    "static_balance",
    "two_plane",
]


@dataclass(frozen=True)
class StaticBalance:
    """Correction of a single-plane balance.

    Attributes
    ----------
    mR : complex or numpy.ndarray
        The balancing mass-radius product ``m_b R_b`` (complex, rotor frame).

    Examples
    --------
    >>> fix = static_balance([1j])
    >>> fix.mR, fix.angle_deg, fix.mass(radius=0.5)
    (-1j, 270.0, 2.0)
    """

    mR: Any

    @property
    def theta(self) -> Any:
        """Angle of the balance mass, radians in (−π, π]."""
        return _out(np.angle(self.mR))

    @property
    def angle_deg(self) -> Any:
        """Angle of the balance mass, degrees in [0, 360) for reports."""
        return _degrees(self.mR)

    def mass(self, radius: float) -> Any:
        """Balance mass ``m_b = |m_b R_b| / R_b`` at the given radius."""
        return _out(np.abs(self.mR) / positive("radius", radius))


def static_balance(unbalance: Any) -> StaticBalance:
    """Single-plane balance: the correction ``m_b R_b = −Σ mᵢRᵢ``.

    Parameters
    ----------
    unbalance : array_like of complex
        ``mᵢRᵢ`` of each mass (last axis), ``R`` in the rotor's frame.

    Returns
    -------
    StaticBalance
        ``.mR`` is the balancing ``m_b R_b``; ``.angle_deg`` says where to put
        it, ``.mass(radius)`` how heavy it is at that radius.

    Examples
    --------
    The notes' two-mass case: ``m_b R_b = −(m₁R₁ + m₂R₂)``.

    >>> fix = static_balance([3.0 + 0j, 2j])
    >>> fix.mR, round(abs(fix.mR), 4), round(fix.angle_deg, 2)
    ((-3-2j), 3.6056, 213.69)
    """
    unbalance = _complex_array("unbalance", unbalance)
    return StaticBalance(_out(-np.sum(unbalance, axis=-1)))


def shaking_force(unbalance: Any, omega: Any) -> Any:
    """Total rotating force on the bearings, ``ω² Σ mᵢRᵢ`` (in the rotor's frame).

    Examples
    --------
    >>> shaking_force([0.5 + 0j, 0.5j], omega=2.0)
    (2+2j)
    """
    unbalance = _complex_array("unbalance", unbalance)
    omega = finite_scalar("omega", omega, "rad/s")
    return _out(omega**2 * np.sum(unbalance, axis=-1))


def shaking_moment(unbalance: Any, z: Any, omega: Any, about: float = 0.0) -> Any:
    """Total moment of the rotating forces about the point of the axis at ``about``.

    ``M = Σ (zᵢ − about) k̂ × mᵢ ω² Rᵢ``; with planar vectors as complex numbers
    ``k̂ × F = jF``, so ``M = j ω² Σ (zᵢ − about) mᵢRᵢ`` (a vector normal to the axis).

    Examples
    --------
    A couple: equal and opposite forces 2 apart.

    >>> shaking_moment([1.0 + 0j, -1.0 + 0j], z=[0.0, 2.0], omega=1.0)
    -2j
    """
    unbalance = _complex_array("unbalance", unbalance)
    z = _axial("z", z, unbalance)
    omega = finite_scalar("omega", omega, "rad/s")
    about = finite_scalar("about", about)
    return _out(1j * omega**2 * np.sum((z - about) * unbalance, axis=-1))


@dataclass(frozen=True)
class TwoPlaneBalance:
    """Corrections of a two-plane balance; unpacks as ``mR_a, mR_b``.

    Attributes
    ----------
    mR_a, mR_b : complex or numpy.ndarray
        Mass-radius products to add in planes A and B (``m R e^{jθ}``).
    plane_a, plane_b : float
        Axial positions of the correction planes.

    Examples
    --------
    >>> result = two_plane([1.0 + 0j], z=[1.0], plane_a=0.0, plane_b=4.0)
    >>> mR_a, mR_b = result
    >>> complex(mR_a), complex(mR_b)
    ((-0.75+0j), (-0.25+0j))
    >>> result.angle_a_deg, result.masses(radius_a=0.5)
    (180.0, (1.5, 0.5))
    """

    mR_a: Any
    mR_b: Any
    plane_a: float
    plane_b: float

    def __iter__(self) -> Iterator[Any]:
        yield self.mR_a
        yield self.mR_b

    def __len__(self) -> int:
        return 2

    @property
    def theta_a(self) -> Any:
        """Angle of the correction in plane A, radians in (−π, π]."""
        return _out(np.angle(self.mR_a))

    @property
    def theta_b(self) -> Any:
        """Angle of the correction in plane B, radians in (−π, π]."""
        return _out(np.angle(self.mR_b))

    @property
    def angle_a_deg(self) -> Any:
        """Angle of the correction in plane A, degrees in [0, 360) for reports."""
        return _degrees(self.mR_a)

    @property
    def angle_b_deg(self) -> Any:
        """Angle of the correction in plane B, degrees in [0, 360) for reports."""
        return _degrees(self.mR_b)

    def masses(self, radius_a: float, radius_b: float | None = None) -> tuple[Any, Any]:
        """Correction masses ``(m_A, m_B)`` when placed at the given radii.

        ``radius_b`` defaults to ``radius_a`` (both on one rim).
        """
        radius_a = positive("radius_a", radius_a)
        radius_b = radius_a if radius_b is None else positive("radius_b", radius_b)
        return _out(np.abs(self.mR_a) / radius_a), _out(np.abs(self.mR_b) / radius_b)

    def to_pandas(self, radius_a: float | None = None, radius_b: float | None = None) -> Any:
        """One row per plane: z, m·R (magnitude), angle (deg) and, given radii, the mass."""
        import pandas as pd

        from .units import columns, units_of

        data: dict[str, Any] = {
            "z": [self.plane_a, self.plane_b],
            "mR": [np.abs(self.mR_a), np.abs(self.mR_b)],
            "angle_deg": [self.angle_a_deg, self.angle_b_deg],
        }
        if radius_a is not None:
            data["mass"] = list(self.masses(radius_a, radius_b))
        system = units_of(self)  # a machine file's rotor: "z [mm]", "mR [kg*mm]", ...
        if system is not None:
            kinds = {"z": "length", "mR": "unbalance", "mass": "mass"}
            angles = np.radians(data.pop("angle_deg"))
            spec = [(k, kinds[k], v) for k, v in data.items()]
            spec.insert(2, ("angle", "angle", angles))
            data = columns(system, spec, degrees=True)
        return pd.DataFrame(data, index=pd.Index(["A", "B"], name="plane"))


def two_plane(unbalance: Any, z: Any, plane_a: float, plane_b: float) -> TwoPlaneBalance:
    """Two-plane dynamic balance: corrections so total force and moment vanish.

    Parameters
    ----------
    unbalance : array_like of complex
        ``mᵢRᵢ`` of each mass (last axis; leading axes are a batch).
    z : array_like
        Axial position of each mass: the same length as the last axis of
        ``unbalance`` (broadcasts only over the batch axes).
    plane_a, plane_b : float
        Axial positions of the two correction planes (distinct; the masses may
        lie between, outside, or on them).

    Returns
    -------
    TwoPlaneBalance
        Unpacks as ``mR_a, mR_b``.

    Examples
    --------
    One mass in the middle of two planes is split equally:

    >>> mR_a, mR_b = two_plane([2j], z=[5.0], plane_a=0.0, plane_b=10.0)
    >>> complex(mR_a), complex(mR_b)
    (-1j, -1j)
    """
    unbalance = _complex_array("unbalance", unbalance)
    z = _axial("z", z, unbalance)
    plane_a = finite_scalar("plane_a", plane_a)
    plane_b = finite_scalar("plane_b", plane_b)
    span = plane_b - plane_a
    scale = max(float(np.max(np.abs(z), initial=0.0)), abs(plane_a), abs(plane_b), 1e-300)
    if abs(span) <= 1e-12 * scale:
        raise InputError("plane_b", f"must differ from plane_a={plane_a}; two distinct planes")
    # Moments about plane A give plane B; moments about plane B give plane A.
    mR_b = -np.sum(unbalance * (z - plane_a), axis=-1) / span
    mR_a = -np.sum(unbalance * (plane_b - z), axis=-1) / span
    return TwoPlaneBalance(_out(mR_a), _out(mR_b), plane_a, plane_b)


def bearing_balance(
    bearing_forces: Any, z_bearings: Any, omega: Any, plane_a: float, plane_b: float
) -> TwoPlaneBalance:
    """Corrections from the bearing forces measured on a balancing machine.

    Parameters
    ----------
    bearing_forces : array_like of complex
        Peak force the rotor exerts on each bearing, ``F e^{jφ}``, the phase φ
        measured from the rotor's zero reference line (as the notes' Problem 12-6:
        ``F_L = 5∠45°``, ``F_R = 2∠−120°``).
    z_bearings : array_like
        Axial position of each bearing.
    omega : float
        Speed of the test run, rad per time unit (> 0; a pint rpm is converted).
    plane_a, plane_b : float
        Axial positions of the correction planes (e.g. the rim edges).

    Returns
    -------
    TwoPlaneBalance
        ``m_A R_A``, ``m_B R_B``; ``.masses(rim_radius)`` gives the masses.

    Notes
    -----
    Rotating at ω, an unbalance ``U`` loads the bearings like a force ``ω² U``,
    so the bearing forces are equivalent to unbalances ``F/ω²`` at the bearing
    planes, and the correction is :func:`two_plane` of those. The corrected
    rotor exerts no force on either bearing.

    Examples
    --------
    The notes' Problem 12-6: bearings 14 in and 4 in to the left of rim plane A,
    plane B 7 in to its right, rim radius 7.5 in, and the notes' ω = 10π/3 rad/s
    (they write "200π/60"; 200 rpm is really 20π/3 rad/s, which makes every
    mass four times smaller and leaves the angles as they are):

    >>> import numpy as np
    >>> forces = [5 * np.exp(1j * np.radians(45)), 2 * np.exp(-1j * np.radians(120))]
    >>> fix = bearing_balance(forces, [-14.0, -4.0], 10 * np.pi / 3, 0.0, 7.0)
    >>> m_a, m_b = fix.masses(7.5)
    >>> round(m_b, 4), round(fix.angle_b_deg, 2), round(m_a, 4), round(fix.angle_a_deg, 2)
    (0.0108, 43.1, 0.0146, 221.11)
    """
    forces = _complex_array("bearing_forces", bearing_forces)
    omega = positive("omega", omega, "rad/s")
    if forces.shape[-1] < 2:
        raise InputError(
            "bearing_forces",
            "needs the forces of (at least) two bearings: one bearing cannot carry the "
            "rotor's moment, so its force alone does not locate the unbalance",
        )
    z = _axial("z_bearings", z_bearings, forces, "bearing")
    return two_plane(forces / omega**2, z, plane_a, plane_b)


# -- helpers ------------------------------------------------------------------------


def _complex_array(field: str, value: Any) -> np.ndarray:
    out = complex_array(field, value)
    if out.ndim == 0:
        out = out.reshape(1)
    if out.shape[-1] == 0:
        raise InputError(field, "needs at least one mass")
    return out


def _axial(field: str, value: Any, unbalance: np.ndarray, what: str = "mass") -> np.ndarray:
    """Axial positions: one per mass (last axis), broadcasting only over the batch axes."""
    z = finite_array(field, value)
    count = unbalance.shape[-1]
    try:
        matches = z.ndim >= 1 and z.shape[-1] == count
        np.broadcast_shapes(z.shape, unbalance.shape)
    except ValueError:
        matches = False
    if not matches:
        raise InputError(
            field,
            f"needs one axial position per {what} ({count}, the last axis of shape "
            f"{unbalance.shape}); got shape {z.shape}",
        )
    return z


def _degrees(value: Any) -> Any:
    deg = np.mod(np.degrees(np.angle(value)), 360.0)
    return _out(np.where(deg >= 360.0, 0.0, deg))  # -0.0 → 360 round-off guard


def _out(value: Any) -> Any:
    """Return a 0-d result as a Python scalar, an array as is."""
    value = np.asarray(value) + 0.0  # also turns -0.0 into 0.0 for clean printing
    return value.item() if value.ndim == 0 else value
