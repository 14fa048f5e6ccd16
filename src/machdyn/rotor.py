"""A rigid rotor in three dimensions: angular momentum, bearing reactions, balance.

The rotor turns about the fixed z axis with angular velocity ``ω k̂`` (and
angular acceleration ``α k̂``). Its mass properties are given in its own axes
``O xyz`` — O a point of the axis, x its zero reference line — either as point
masses or as a mass, a centre of mass and an inertia tensor with its products
of inertia. The notes (Ch. 12, "Machine balancing") write, for ``ω = ω k̂``,

``H_O = −I_xz ω î − I_yz ω ĵ + I_zz ω k̂``,  ``ω × H_O = I_yz ω² î − I_xz ω² ĵ``,

with the products of inertia ``I_xz = ∫ x z dm`` and ``I_yz = ∫ y z dm`` (the
tensor carries them with a minus sign: ``H = [I] ω``). The two imbalance
issues of the notes follow: a centre of mass off the axis (forces ∝ ω²), and
an axis that is not a principal axis (``I_xz``, ``I_yz`` ≠ 0: a rotating couple
∝ ω²).

Bearings
--------
Two bearings at ``z_A`` and ``z_B`` on the axis hold the rotor. Newton–Euler
about O (Norton, *Design of Machinery*, sec. 12.2; Beer & Johnston's rotation
about a fixed axis), with planar vectors normal to the axis written as complex
numbers in the fixed frame (``k̂ × F = jF``, so a force F at height z has the
moment ``j z F`` about O):

``F_A + F_B + m g = m a_G = (jα − ω²) U e^{jθ}``,
``j (z_A F_A + z_B F_B) + j z_G m g = dH_O/dt = (jα − ω²) (−j) P e^{jθ}``,

where θ is the rotor's angle, ``U = m (x_G + j y_G)`` its unbalance and
``P = I_xz + j I_yz`` its couple unbalance (in rotor axes), so
``z_A F_A + z_B F_B = (jα − ω²) P e^{jθ} − z_G m g``. ``F_A``, ``F_B`` are the
forces of the bearings on the rotor; the rotor loads the bearings with the
opposite forces. The drive torque about the axis is ``T = I_zz α`` plus what
gravity needs.

Balance
-------
Both reactions vanish for every ω and α exactly when ``U = 0`` and ``P = 0``:
the centre of mass on the axis and the axis a principal axis of inertia (the
notes' "if any pair of these three conditions are true, the third is also
true"). Two correction masses in planes A and B with ``Σ mR = −U`` and
``Σ mR z = −P`` achieve it (:meth:`Rotor.two_plane_correction`, the same
formula as :func:`machdyn.balancing.two_plane`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ._summary import Summarized
from ._validate import choice, complex_array, finite_array, finite_scalar, nonnegative
from .balancing import StaticBalance, TwoPlaneBalance, two_plane
from .errors import InputError

__all__ = ["BearingReactions", "Rotor"]

#: Relative tolerance of the inertia tensor's symmetry and triangle inequalities.
_TENSOR_RTOL = 1e-9


@dataclass(frozen=True)
class BearingReactions(Summarized):
    """Forces of two bearings on a rotor, over the samples given.

    Attributes
    ----------
    theta, omega, alpha : ndarray
        Rotor angle, angular velocity and acceleration (broadcast shape).
    reaction_a, reaction_b : ndarray of complex
        Forces of bearings A and B on the rotor, fixed frame, ``Fx + j Fy``.
    torque : ndarray
        Drive torque about the axis the rotor needs (``I_zz α``, plus gravity's
        moment when the centre of mass is off the axis).
    z_a, z_b : float
        Axial positions of the bearings.
    """

    theta: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    reaction_a: np.ndarray
    reaction_b: np.ndarray
    torque: np.ndarray
    z_a: float
    z_b: float

    @property
    def load_a(self) -> np.ndarray:
        """Force of the rotor on bearing A (what the bearing carries), ``−reaction_a``."""
        return -self.reaction_a

    @property
    def load_b(self) -> np.ndarray:
        """Force of the rotor on bearing B, ``−reaction_b``."""
        return -self.reaction_b

    def to_pandas(self) -> Any:
        """One row per sample: θ (deg), ω, α, the reactions' components and the torque."""
        import pandas as pd

        shape = np.broadcast_shapes(self.theta.shape, self.reaction_a.shape)
        columns = {
            "theta_deg": np.degrees(np.broadcast_to(self.theta, shape)),
            "omega": np.broadcast_to(self.omega, shape),
            "alpha": np.broadcast_to(self.alpha, shape),
            "FA_x": self.reaction_a.real,
            "FA_y": self.reaction_a.imag,
            "FB_x": self.reaction_b.real,
            "FB_y": self.reaction_b.imag,
            "torque": np.broadcast_to(self.torque, shape),
        }
        return pd.DataFrame({k: np.ravel(v) for k, v in columns.items()})


class Rotor:
    """A rigid rotor turning about the z axis of its own frame ``O xyz``.

    Parameters
    ----------
    mass : float
        Total mass (> 0).
    cg : (x, y, z)
        Centre of mass in rotor axes.
    inertia : (3, 3) array_like, optional
        Inertia tensor in rotor axes, ``[[I_xx, −I_xy, −I_xz], [−I_xy, I_yy,
        −I_yz], [−I_xz, −I_yz, I_zz]]`` with the products ``I_xz = ∫ xz dm`` etc.
        Default: that of a point mass at ``cg``.
    about : {"origin", "cg"}
        Whether ``inertia`` is taken about O or about the centre of mass
        (moved to O by the parallel-axis theorem ``I_O = I_G + m(|d|²E − d dᵀ)``).

    Raises
    ------
    InputError
        A non-positive mass, a tensor that is not 3×3, symmetric and physical
        (principal moments ≥ 0 obeying the triangle inequality about the
        centre of mass), or a bad ``about``.

    Examples
    --------
    A disc of 10 kg on the axis, tilted so that ``I_xz = 0.05 kg·m²``:

    >>> tensor = [[0.5, 0, -0.05], [0, 0.5, 0], [-0.05, 0, 0.9]]
    >>> rotor = Rotor(10.0, (0.0, 0.0, 0.2), tensor, about="cg")
    >>> rotor.angular_momentum(100.0)       # H_O = (−I_xz ω, −I_yz ω, I_zz ω)
    array([-5.,  0., 90.])
    >>> rotor.gyroscopic_moment(100.0)      # ω × H_O = (I_yz ω², −I_xz ω², 0)
    array([   0., -500.,    0.])
    """

    def __init__(
        self, mass: Any, cg: Any = (0.0, 0.0, 0.0), inertia: Any = None, *, about: str = "origin"
    ) -> None:
        self.mass = finite_scalar("mass", mass)
        if self.mass <= 0.0:
            raise InputError(
                "mass", f"a rotor needs a positive mass, got {self.mass:g} (no mass, no unbalance)"
            )
        d = finite_array("cg", cg)
        if d.shape != (3,):
            raise InputError("cg", f"must be the centre of mass (x, y, z), got shape {d.shape}")
        self.cg = d
        point = self.mass * (float(d @ d) * np.eye(3) - np.outer(d, d))
        if inertia is None:
            self.inertia = point
            return
        tensor = finite_array("inertia", inertia)
        if tensor.shape != (3, 3):
            raise InputError("inertia", f"must be a 3×3 inertia tensor, got shape {tensor.shape}")
        about = choice("about", about, ("origin", "cg"))
        scale = max(float(np.max(np.abs(tensor))), float(np.max(np.abs(point))), 1e-300)
        if np.max(np.abs(tensor - tensor.T)) > _TENSOR_RTOL * scale:
            raise InputError("inertia", "must be symmetric (the products appear twice, as −I_xz)")
        tensor = 0.5 * (tensor + tensor.T)
        i_g = tensor if about == "cg" else tensor - point
        _check_physical(i_g, scale)
        self.inertia = i_g + point

    # -- constructors -----------------------------------------------------------
    @classmethod
    def from_masses(cls, masses: Any, R: Any, z: Any) -> Rotor:
        """A rotor made of point masses ``mᵢ`` at ``Rᵢ = xᵢ + j yᵢ`` and heights ``zᵢ``.

        The same description as :mod:`machdyn.balancing` (``R`` complex, in
        the rotor's frame). Combine with a shaft or disc with ``+``.

        Examples
        --------
        Two equal masses opposite each other in different planes: the centre of
        mass is on the axis, but ``I_xz`` ≠ 0 — a couple unbalance.

        >>> rotor = Rotor.from_masses([1.0, 1.0], [0.1, -0.1], [0.0, 0.5])
        >>> rotor.unbalance, rotor.couple_unbalance
        (0j, (-0.05+0j))
        """
        m = finite_array("masses", masses).reshape(-1)
        if m.size == 0:
            raise InputError("masses", "a rotor needs at least one mass")
        if np.any(m < 0.0):
            raise InputError("masses", f"must be zero or positive, got {m.tolist()}")
        r = complex_array("R", R).reshape(-1)
        zz = finite_array("z", z).reshape(-1)
        for field, values in (("R", r), ("z", zz)):
            if values.size != m.size:
                raise InputError(field, f"needs one value per mass ({m.size}), got {values.size}")
        total = float(m.sum())
        if total <= 0.0:
            raise InputError("masses", "a rotor needs mass: every mass given is zero")
        xyz = np.stack([r.real, r.imag, zz], axis=-1)
        cg = (m @ xyz) / total
        tensor = np.einsum("i,ij->ij", m, xyz)
        inertia = float(np.sum(m * np.sum(xyz * xyz, axis=1))) * np.eye(3) - xyz.T @ tensor
        return cls(total, cg, inertia, about="origin")

    def __add__(self, other: Rotor) -> Rotor:
        """Two rigidly joined rotors on one axis (masses, moments and tensors add)."""
        if not isinstance(other, Rotor):
            return NotImplemented
        mass = self.mass + other.mass
        cg = (self.mass * self.cg + other.mass * other.cg) / mass
        return Rotor(mass, cg, self.inertia + other.inertia, about="origin")

    def __repr__(self) -> str:
        x, y, z = self.cg
        return (
            f"Rotor(mass={self.mass:g}, cg=({x:g}, {y:g}, {z:g}), "
            f"I_xz={self.I_xz:g}, I_yz={self.I_yz:g})"
        )

    # -- mass properties --------------------------------------------------------
    @property
    def I_xz(self) -> float:
        """Product of inertia ``∫ x z dm`` about O."""
        return float(-self.inertia[0, 2]) + 0.0  # never -0.0

    @property
    def I_yz(self) -> float:
        """Product of inertia ``∫ y z dm`` about O."""
        return float(-self.inertia[1, 2]) + 0.0

    @property
    def I_zz(self) -> float:
        """Moment of inertia about the axis."""
        return float(self.inertia[2, 2])

    @property
    def unbalance(self) -> complex:
        """Static unbalance ``U = m (x_G + j y_G)`` (rotor frame)."""
        return complex(self.mass * self.cg[0], self.mass * self.cg[1])

    @property
    def couple_unbalance(self) -> complex:
        """Couple unbalance ``P = I_xz + j I_yz`` (``Σ mᵢ zᵢ Rᵢ`` for point masses)."""
        return complex(self.I_xz, self.I_yz)

    def is_balanced(self, rtol: float = 1e-12) -> bool:
        """True when ``U`` and ``P`` vanish (to ``rtol``): no bearing reaction at any speed.

        ``U`` is compared with ``m k`` and ``P`` with ``m k²``, ``k`` the radius of
        gyration ``√(trace I_O / m)``.
        """
        rtol = nonnegative("rtol", rtol)
        k = float(np.sqrt(np.trace(self.inertia) / self.mass))
        return bool(
            abs(self.unbalance) <= rtol * self.mass * k
            and abs(self.couple_unbalance) <= rtol * self.mass * k * k
        )

    # -- kinetics -----------------------------------------------------------------
    def angular_momentum(self, omega: Any) -> np.ndarray:
        """``H_O = [I] ω k̂`` in rotor axes: ``(−I_xz ω, −I_yz ω, I_zz ω)``, shape (..., 3)."""
        w = finite_array("omega", omega, "rad/s")
        return np.asarray(w)[..., None] * self.inertia[:, 2]

    def gyroscopic_moment(self, omega: Any) -> np.ndarray:
        """``ω × H_O = (I_yz ω², −I_xz ω², 0)`` in rotor axes, shape (..., 3).

        The moment the bearings must apply at constant ω (the notes' ω × H₀).
        """
        w = finite_array("omega", omega, "rad/s")[..., None]
        return np.cross(
            np.concatenate([0 * w, 0 * w, w], axis=-1), self.angular_momentum(w[..., 0])
        )

    def bearing_reactions(
        self,
        omega: Any,
        z_a: float,
        z_b: float,
        *,
        alpha: Any = 0.0,
        theta: Any = 0.0,
        gravity: float = 0.0,
    ) -> BearingReactions:
        """Forces of two bearings on the rotor (fixed frame, complex ``Fx + j Fy``).

        Parameters
        ----------
        omega, alpha : array_like
            Angular velocity and acceleration about +z (broadcast together).
        z_a, z_b : float
            Axial positions of the bearings (distinct).
        theta : array_like
            Rotor angle: its x axis (zero reference line) from the fixed x axis.
        gravity : float
            Acceleration of gravity along −y of the fixed frame (0: none).

        Returns
        -------
        BearingReactions

        Examples
        --------
        Two masses forming a couple between bearings 1 apart: equal and
        opposite reactions, each ``P ω² / 1``.

        >>> rotor = Rotor.from_masses([1.0, 1.0], [0.1, -0.1], [0.25, 0.75])
        >>> r = rotor.bearing_reactions(10.0, 0.0, 1.0)
        >>> complex(r.reaction_a), complex(r.reaction_b)
        ((-5+0j), (5+0j))
        """
        w = finite_array("omega", omega, "rad/s")
        a = finite_array("alpha", alpha, "rad/s**2")
        th = finite_array("theta", theta, "radian")
        z_a = finite_scalar("z_a", z_a)
        z_b = finite_scalar("z_b", z_b)
        g = finite_scalar("gravity", gravity)
        span = z_b - z_a
        scale = max(abs(z_a), abs(z_b), abs(float(self.cg[2])), 1e-300)
        if abs(span) <= 1e-12 * scale:
            raise InputError("z_b", f"must differ from z_a={z_a:g}: two distinct bearings")
        turn = np.exp(1j * th)
        rate = 1j * a - w * w  # (jα − ω²)
        weight = -1j * self.mass * g  # m g as a complex force (along −y)
        total = rate * self.unbalance * turn - weight  # F_A + F_B
        moment = rate * self.couple_unbalance * turn - float(self.cg[2]) * weight
        reaction_b = (moment - z_a * total) / span
        reaction_a = total - reaction_b
        # about the axis: T + (moment of gravity) = I_zz α; r_G × m g has z part x_G' (−m g)
        x_g = (complex(self.cg[0], self.cg[1]) * turn).real
        torque = self.I_zz * a + self.mass * g * x_g
        shape = np.broadcast_shapes(w.shape, a.shape, th.shape)
        return BearingReactions(
            theta=np.broadcast_to(th, shape),
            omega=np.broadcast_to(w, shape),
            alpha=np.broadcast_to(a, shape),
            reaction_a=np.broadcast_to(reaction_a, shape),
            reaction_b=np.broadcast_to(reaction_b, shape),
            torque=np.broadcast_to(torque, shape),
            z_a=z_a,
            z_b=z_b,
        )

    # -- balance --------------------------------------------------------------------
    def static_correction(self) -> StaticBalance:
        """Single-plane correction ``m_b R_b = −U`` (centre of mass onto the axis)."""
        return StaticBalance(-self.unbalance)

    def two_plane_correction(self, plane_a: float, plane_b: float) -> TwoPlaneBalance:
        """Masses in planes A and B that cancel both ``U`` and ``P`` (dynamic balance).

        Examples
        --------
        >>> rotor = Rotor.from_masses([1.0, 1.0], [0.1, -0.1], [0.25, 0.75])
        >>> fix = rotor.two_plane_correction(0.0, 1.0)
        >>> complex(fix.mR_a), complex(fix.mR_b)
        ((-0.05+0j), (0.05+0j))
        """
        # (U, P) as two equivalent point unbalances: U − P at z = 0 and P at z = 1
        # (Σ mR = U, Σ mR z = P), balanced by the one two-plane formula.
        u, p = self.unbalance, self.couple_unbalance
        return two_plane([u - p, p], [0.0, 1.0], plane_a, plane_b)

    def with_masses(self, masses: Any, R: Any, z: Any) -> Rotor:
        """The rotor with point masses added (e.g. the correction masses)."""
        return self + Rotor.from_masses(masses, R, z)


def _check_physical(i_g: np.ndarray, scale: float) -> None:
    """Principal moments about the centre of mass: ≥ 0, each ≤ the sum of the others."""
    moments = np.linalg.eigvalsh(i_g)
    tol = _TENSOR_RTOL * scale
    if moments[0] < -tol:
        raise InputError(
            "inertia",
            f"has a negative principal moment about the centre of mass ({moments[0]:g}); "
            "check the signs of the products of inertia (the tensor holds −I_xz)",
        )
    if moments[2] > moments[0] + moments[1] + tol:
        raise InputError(
            "inertia",
            "principal moments about the centre of mass break the triangle inequality "
            f"({moments[2]:g} > {moments[0]:g} + {moments[1]:g}): no body has them",
        )
