"""Mass properties of planar links: mass, centre of mass and moment of inertia.

A link's mass properties are three numbers in its own frame: the mass ``m``, the
centre of mass ``G`` as a complex position (``x + jy``), and the mass moment of
inertia ``I_G`` about the axis through ``G`` normal to the plane. Everything else
follows from the notes' two formulas (Norton, *Design of Machinery*, ch. 10):

* ``I_G = ∫ (x² + y²) dm`` — tabulated below for the usual shapes;
* the parallel-axis theorem ``I_O = I_G + m d²``, with ``d = |O − G|``.

Composite links are sums: masses add, the centre of mass is the mass-weighted
mean, and each part's ``I_G`` is carried to the common centre of mass with the
parallel-axis theorem. A hole is a part with negative mass (``plate - disc``).
The notes' "lollipop" (a rod of length ``l`` with a disc of radius ``R`` at its
end) is ``rod(m_r, l) + disc(m_d, R, centre=l + R)``.

Examples
--------
>>> from machdyn.massprops import rod, disc
>>> lollipop = rod(2.0, 0.5) + disc(1.0, 0.1, centre=0.6)
>>> round(lollipop.inertia_about(0.0), 6)   # mL²/3 + MR²/2 + M(l+R)²
0.531667
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._validate import (
    TINY,
    complex_array,
    complex_scalar,
    finite_array,
    finite_scalar,
    magnitude,
    positive,
)
from ._validate import broadcast as _broadcast
from .errors import InputError

__all__ = [
    "MassProperties",
    "annulus",
    "cg_motion",
    "composite",
    "disc",
    "parallel_axis",
    "plate",
    "point_mass",
    "radius_of_gyration",
    "ring",
    "rod",
]


def parallel_axis(inertia_g: Any, mass: Any, d: Any) -> Any:
    """Moment of inertia about an axis at distance ``d`` from the centre of mass.

    ``I_O = I_G + m d²`` (the notes, ch. 10; Norton eq. 10.9). Broadcasts over
    arrays; ``d`` may be complex (an offset vector), in which case ``|d|`` is used.

    Parameters
    ----------
    inertia_g : float or array_like
        Moment of inertia about the centre of mass, ``I_G``.
    mass : float or array_like
        Mass ``m``.
    d : float, complex or array_like
        Distance (or offset vector) from the centre of mass to the new axis.

    Returns
    -------
    float or numpy.ndarray
        ``I_O``.

    Examples
    --------
    A slender rod about its end, ``mL²/12 + m(L/2)² = mL²/3``:

    >>> parallel_axis(3.0 * 2.0**2 / 12, 3.0, 1.0)
    4.0
    """
    inertia_g = _nonnegative_array("inertia_g", inertia_g)
    mass = _nonnegative_array("mass", mass)
    d = _complex_array("d", d)
    _broadcast(inertia_g=inertia_g, mass=mass, d=d)
    return _out(inertia_g + mass * np.abs(d) ** 2)


def radius_of_gyration(inertia: Any, mass: Any) -> Any:
    """Radius of gyration ``k = √(I/m)``: where the mass would sit as a point.

    Parameters
    ----------
    inertia : float or array_like
        Moment of inertia about the axis of interest (positive).
    mass : float or array_like
        Mass (positive).

    Returns
    -------
    float or numpy.ndarray
        ``k``, in length units.

    Examples
    --------
    A solid disc of radius 2: ``k = R/√2``.

    >>> round(float(radius_of_gyration(0.5 * 3.0 * 2.0**2, 3.0)), 6)
    1.414214
    """
    inertia = finite_array("inertia", magnitude(inertia))
    mass = finite_array("mass", magnitude(mass))
    _broadcast(inertia=inertia, mass=mass)
    if np.any(mass < TINY):
        raise InputError(
            "mass", f"must be positive (at least {TINY:g}) to define a radius of gyration"
        )
    if np.any(inertia < 0):
        raise InputError("inertia", "must be zero or positive to define a radius of gyration")
    return _out(np.sqrt(inertia / mass))


@dataclass(frozen=True)
class MassProperties:
    """Mass, centre of mass and centroidal moment of inertia of a planar body.

    Build one with the shape constructors (:func:`rod`, :func:`disc`, :func:`ring`,
    :func:`annulus`, :func:`plate`, :func:`point_mass`) and combine them with ``+``
    (composite body) and ``-`` (remove a hole). Constructing one directly
    validates the numbers: the mass must be positive and ``I_G`` non-negative
    (zero only for a point mass).

    Parameters
    ----------
    mass : float
        Mass ``m`` (> 0).
    cg : complex
        Centre of mass ``G`` in the link's own frame, ``x + jy``.
    inertia : float
        ``I_G``, about the axis through ``G`` normal to the plane (≥ 0).

    Examples
    --------
    >>> body = MassProperties(mass=2.0, cg=1 + 0j, inertia=0.5)
    >>> body.inertia_about(0)     # 0.5 + 2·1²
    2.5
    >>> MassProperties(mass=-1.0, cg=0j, inertia=1.0)
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: mass: must be positive, got -1.0
    """

    mass: float
    cg: complex
    inertia: float

    def __post_init__(self) -> None:
        mass = positive("mass", self.mass)
        inertia = finite_scalar("inertia", self.inertia)
        if inertia < 0:
            raise InputError("inertia", f"I_G must be zero or positive, got {inertia}")
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "cg", _complex("cg", self.cg))
        object.__setattr__(self, "inertia", inertia)

    # -- derived quantities -------------------------------------------------------

    @property
    def radius_of_gyration(self) -> float:
        """``k_G = √(I_G / m)``, about the centre of mass."""
        return math.sqrt(self.inertia / self.mass)

    @property
    def first_moment(self) -> complex:
        """``m·G``, the body's mass-radius product about the frame origin."""
        return self.mass * self.cg

    def inertia_about(self, point: complex = 0j) -> float:
        """Moment of inertia about the axis through ``point`` (parallel-axis theorem).

        Examples
        --------
        A slender rod about its end is ``mL²/3``:

        >>> rod(3.0, 2.0).inertia_about(0)
        4.0
        """
        d = _complex("point", point) - self.cg
        return self.inertia + self.mass * abs(d) ** 2

    def radius_of_gyration_about(self, point: complex = 0j) -> float:
        """``k_O = √(I_O / m)`` about the axis through ``point``."""
        return math.sqrt(self.inertia_about(point) / self.mass)

    def moved(self, offset: complex = 0j, angle: float = 0.0) -> MassProperties:
        """Return the same body in another frame: rotated by ``angle``, then shifted.

        ``G' = offset + G·e^{j·angle}``; ``I_G`` is unchanged by a rigid motion.

        Examples
        --------
        >>> rod(1.0, 2.0).moved(offset=1j, angle=math.pi / 2).cg
        2j
        """
        offset = _complex("offset", offset)
        angle = finite_scalar("angle", angle, "rad")
        cg = offset + self.cg * complex(math.cos(angle), math.sin(angle))
        return MassProperties(self.mass, _clean(cg), self.inertia)

    # -- composite bodies ---------------------------------------------------------

    def __add__(self, other: MassProperties) -> MassProperties:
        if not isinstance(other, MassProperties):
            return NotImplemented
        return _combine([(self, 1.0), (other, 1.0)])

    def __sub__(self, other: MassProperties) -> MassProperties:
        if not isinstance(other, MassProperties):
            return NotImplemented
        return _combine([(self, 1.0), (other, -1.0)])


def composite(*parts: MassProperties) -> MassProperties:
    """Combine parts into one body (the parallel-axis theorem about the common G).

    ``m = Σ mᵢ``, ``G = Σ mᵢ Gᵢ / m``, ``I_G = Σ (I_Gᵢ + mᵢ |Gᵢ − G|²)``.
    Use ``a - b`` to remove a hole ``b`` from ``a``.

    Examples
    --------
    Two equal point masses 2 apart: ``I_G = 2·m·1²``.

    >>> body = composite(point_mass(1.0, -1.0), point_mass(1.0, 1.0))
    >>> body.mass, body.cg, body.inertia
    (2.0, 0j, 2.0)
    """
    if not parts:
        raise InputError("parts", "give at least one MassProperties to combine")
    for index, part in enumerate(parts):
        if not isinstance(part, MassProperties):
            raise InputError(f"parts[{index}]", f"must be MassProperties, got {part!r}")
    return _combine([(p, 1.0) for p in parts])


def _combine(signed_parts: list[tuple[MassProperties, float]]) -> MassProperties:
    mass = sum(sign * p.mass for p, sign in signed_parts)
    if mass <= 1e-12 * max(p.mass for p, _ in signed_parts):
        raise InputError(
            "mass",
            f"the composite body has no positive mass ({mass:g}); "
            "a hole must weigh less than the body it is cut from",
        )
    cg = sum(sign * p.mass * p.cg for p, sign in signed_parts) / mass
    inertia = sum(sign * p.inertia_about(cg) for p, sign in signed_parts)
    scale = max(p.inertia_about(cg) for p, _ in signed_parts)
    if inertia < -1e-12 * scale:
        raise InputError(
            "inertia",
            f"the composite body has negative I_G ({inertia:g}); "
            "a hole cannot hold more inertia than the body it is cut from",
        )
    return MassProperties(mass, _clean(cg), max(inertia, 0.0))


# -- shapes -------------------------------------------------------------------------


def point_mass(mass: float, at: complex = 0j) -> MassProperties:
    """Make a concentrated mass (``I_G = 0``) at ``at``.

    Examples
    --------
    >>> point_mass(2.0, 3.0).inertia_about(0)
    18.0
    """
    return MassProperties(positive("mass", mass), _complex("at", at), 0.0)


def rod(mass: float, length: float, start: complex = 0j, angle: float = 0.0) -> MassProperties:
    """Make a slender rod (uniform bar) from ``start`` along direction ``angle``.

    ``I_G = mL²/12`` about its middle, so ``I = mL²/3`` about either end
    (the notes, ch. 10). By default the rod lies on the link's x axis from the
    origin, as a link from its first joint toward the next.

    Parameters
    ----------
    mass : float
        Mass (> 0).
    length : float
        Length ``L`` (> 0).
    start : complex, optional
        Position of one end in link coordinates.
    angle : float, optional
        Direction of the rod, radians counter-clockwise from the x axis.

    Examples
    --------
    >>> bar = rod(3.0, 2.0)
    >>> bar.cg, bar.inertia
    ((1+0j), 1.0)
    """
    mass = positive("mass", mass)
    length = positive("length", length)
    angle = finite_scalar("angle", angle, "rad")
    cg = _complex("start", start) + 0.5 * length * complex(math.cos(angle), math.sin(angle))
    return MassProperties(mass, _clean(cg), mass * length**2 / 12.0)


def disc(mass: float, radius: float, centre: complex = 0j) -> MassProperties:
    """Make a solid disc (or cylinder about its axis): ``I_G = ½ m R²``.

    Examples
    --------
    >>> disc(2.0, 3.0).inertia
    9.0
    """
    mass = positive("mass", mass)
    radius = positive("radius", radius)
    return MassProperties(mass, _complex("centre", centre), 0.5 * mass * radius**2)


def ring(mass: float, radius: float, centre: complex = 0j) -> MassProperties:
    """Make a thin ring (hoop) of mean radius ``R``: ``I_G = m R²``.

    Examples
    --------
    >>> ring(2.0, 3.0).inertia
    18.0
    """
    mass = positive("mass", mass)
    radius = positive("radius", radius)
    return MassProperties(mass, _complex("centre", centre), mass * radius**2)


def annulus(
    mass: float, outer_radius: float, inner_radius: float, centre: complex = 0j
) -> MassProperties:
    """Make a thick ring (a rim, a disc with a central hole): ``I_G = ½ m (R_o² + R_i²)``.

    Examples
    --------
    >>> annulus(2.0, 3.0, 1.0).inertia
    10.0
    """
    mass = positive("mass", mass)
    outer = positive("outer_radius", outer_radius)
    inner = finite_scalar("inner_radius", inner_radius)
    if not 0.0 <= inner < outer:
        raise InputError(
            "inner_radius", f"must satisfy 0 <= inner_radius < outer_radius={outer}, got {inner}"
        )
    return MassProperties(mass, _complex("centre", centre), 0.5 * mass * (outer**2 + inner**2))


def plate(mass: float, width: float, height: float, centre: complex = 0j) -> MassProperties:
    """Make a thin rectangular plate ``width × height``: ``I_G = m (w² + h²) / 12``.

    The in-plane inertia does not depend on how the plate is turned in its plane.

    Examples
    --------
    >>> plate(12.0, 3.0, 4.0).inertia
    25.0
    """
    mass = positive("mass", mass)
    width = positive("width", width)
    height = positive("height", height)
    return MassProperties(mass, _complex("centre", centre), mass * (width**2 + height**2) / 12.0)


# -- kinematics of a centre of mass -------------------------------------------------


def cg_motion(
    theta: Any,
    omega: Any,
    alpha: Any,
    cg: complex,
    origin: Any = 0j,
    origin_velocity: Any = 0j,
    origin_acceleration: Any = 0j,
) -> tuple[Any, Any, Any]:
    """Position, velocity and acceleration of a link's centre of mass.

    The link's frame has its origin at a joint ``O`` (position, velocity and
    acceleration given) and its x axis at angle ``θ``; the centre of mass sits at
    ``c`` in that frame. With ``R = c e^{jθ}`` (the notes' complex-number method):

    ``R_G = R_O + c e^{jθ}``,
    ``V_G = V_O + jω c e^{jθ}``,
    ``A_G = A_O + (jα − ω²) c e^{jθ}``.

    Everything broadcasts over arrays of samples.

    Parameters
    ----------
    theta, omega, alpha : float or array_like
        Angle (rad), angular velocity and angular acceleration of the link.
    cg : complex
        Centre of mass in the link's frame (e.g. ``MassProperties.cg``).
    origin, origin_velocity, origin_acceleration : complex or array_like, optional
        Motion of the frame's origin (zero for a link pivoted on the ground).

    Returns
    -------
    tuple of complex arrays
        ``(R_G, V_G, A_G)``.

    Examples
    --------
    A crank's centre of mass 1 from the pivot at θ = 0, ω = 2, α = 0: the
    velocity is tangential, the acceleration centripetal (``−ω² r``).

    >>> cg_motion(0.0, 2.0, 0.0, cg=1.0)
    ((1+0j), 2j, (-4+0j))
    """
    theta = finite_array("theta", theta, "rad")
    omega = finite_array("omega", omega, "rad/s")
    alpha = finite_array("alpha", alpha, "rad/s**2")
    origin = _complex_array("origin", origin)
    origin_velocity = _complex_array("origin_velocity", origin_velocity)
    origin_acceleration = _complex_array("origin_acceleration", origin_acceleration)
    _broadcast(
        theta=theta,
        omega=omega,
        alpha=alpha,
        origin=origin,
        origin_velocity=origin_velocity,
        origin_acceleration=origin_acceleration,
    )
    arm = _complex("cg", cg) * np.exp(1j * theta)
    position = origin + arm
    velocity = origin_velocity + 1j * omega * arm
    acceleration = origin_acceleration + (1j * alpha - omega**2) * arm
    return _out_complex(position), _out_complex(velocity), _out_complex(acceleration)


# -- helpers ------------------------------------------------------------------------


def _nonnegative_array(field: str, value: Any, unit: str | None = None) -> np.ndarray:
    out = finite_array(field, value, unit)
    if np.any(out < 0.0):
        index = int(np.flatnonzero(out.ravel() < 0.0)[0])
        raise InputError(field, f"must be zero or positive; entry {index} is {out.ravel()[index]}")
    return out


def _complex_array(field: str, value: Any) -> np.ndarray:
    return complex_array(field, value)


def _out_complex(value: np.ndarray) -> Any:
    """Return a 0-d complex result as a Python complex, an array as is."""
    return complex(value) if np.ndim(value) == 0 else value


def _out(value: np.ndarray) -> Any:
    """Return a 0-d result as a Python float, an array as is."""
    return float(value) if np.ndim(value) == 0 else value


def _complex(field: str, value: Any) -> complex:
    return complex_scalar(field, value)


def _clean(z: complex) -> complex:
    """Round away last-bit noise (1e-17 imaginary parts) so printed results read cleanly."""
    scale = max(abs(z.real), abs(z.imag), 1.0)
    re = 0.0 if abs(z.real) < 1e-15 * scale else z.real
    im = 0.0 if abs(z.imag) < 1e-15 * scale else z.imag
    return complex(re, im)
