"""Dynamic force analysis of the inverted slider-crank (Newton–Euler, Norton §11.7).

Links (:class:`~machdyn.slidercrank.InvertedSliderCrank`): 1 the ground, 2 the
crank ``O2A``, 3 the block pinned to the crank at ``A``, 4 the slotted link
pinned to the ground at ``O4 = d``; the block slides in link 4's slot and turns
with it (``θ3 = θ4``, ``û = e^{jθ4}`` the slot's direction).

Nomenclature as :mod:`machdyn.dynamics` (the notes' "FORCE ANALYSIS"; Norton
§11.4–11.8): ``F_ap`` is the force on link *p* from link *a*, forces complex
``Fx + j Fy``, torques CCW positive, ``T12`` the ground's torque on the crank.
The slot is a prismatic joint: the force of link 4 on the block is
``F43 = N j û + f û`` (normal force ``N``, friction ``f``) acting at ``A``,
with a couple ``C43`` (the block turns with link 4, so the slot carries the
block's moment too).

Equations (Norton eq. 11.9, one link at a time)::

    link 2:  F12 + F32 + ΣF2 = m2 aG2       T12 + R12×F12 + R32×F32 + ΣM2 = IG2 α2
    link 3:  F43 − F32 + ΣF3 = m3 aG3       C43 + R43×F43 − R23×F32 + ΣM3 = IG3 α4
    link 4:  F14 − F43 + ΣF4 = m4 aG4       −C43 + R14×F14 − R34×F43 + ΣM4 = IG4 α4

nine equations in ``F12, F32, F14`` (two components each), ``N``, ``C43`` and
``T12``. They are solved as the Assur groups they are: the RPR dyad (block,
slotted link) by :func:`machdyn.linkage.newton_euler.rpr` — link 3's moment
about ``A`` gives ``C43``, the sum of link 3's moment about ``A`` and link 4's
about ``O4`` gives ``N``, whose coefficient ``(A − O4) × (j û + κ û) = b − κ c``
vanishes only where the block passes the foot of the perpendicular from
``O4`` (``b = 0``, the crank's limit: flagged) — then the crank by
:func:`~machdyn.linkage.newton_euler.crank`, from the one module of closed
forms ``FourBar.dynamics``, ``SliderCrank.dynamics`` and ``Linkage.forces`` use
(``Linkage.forces`` solves an RPR group by its LU; the tests compare the two).

Friction at the slot: Coulomb ``f = −μ |N| sign(ḃ)`` (the net normal force;
the pair of contact forces that makes the couple ``C43`` is not resolved, as
in the slider-crank) or viscous ``f = −β ḃ``.

Shaking force and moment (Norton §11.8): ``Fs = F21 + F41 = −(F12 + F14)``,
``Ms = T21 + R1 × F41`` about O2 with ``R1 = O4 − O2 = d``.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._flags import Flagged
from ._validate import choice, finite_array, instance, nonnegative
from .dynamics import (
    _check_input_shapes,
    _check_sample_shapes,
    _cross,
    _plot_forces,
    _point_loads,
    _torques,
    link_properties,
    unit_system,
)
from .errors import InputError
from .slidercrank import OK, TOGGLE, InvertedSliderCrank, InvertedSliderCrankMotion

__all__ = [
    "INVERTED_REASONS",
    "InvertedSliderCrankForces",
    "inverted_slidercrank_dynamics",
    "inverted_slidercrank_forces",
]

#: Why a sample has no force solution (motion codes 0–2, then the friction's).
INVERTED_REASONS: tuple[str, ...] = (
    "",
    "cannot be assembled at this input angle (A comes closer to O4 than the slot offset)",
    "toggle: the block is at the foot of the perpendicular from O4 to the slot (b = 0); "
    "the velocity solution and the force system are singular",
    "Coulomb friction: no unique normal force consistent with the sign of the friction "
    "(the block wedges or jams in the slot)",
    "Coulomb friction indeterminate: the block is at rest in the slot and not "
    "accelerating along it (stiction)",
)
_JAM, _STICK = 3, 4
_FRICTION_MODELS = ("smooth", "coulomb", "viscous")
#: Relative tolerance of the motion's consistency check with the model.
_SAME_MODEL_TOL = 1e-9


@dataclass(frozen=True, eq=False)
class InvertedSliderCrankForces(Flagged):
    """Joint forces, driving torque and shaking loads of an inverted slider-crank.

    Attributes
    ----------
    T12 : ndarray
        Driving torque of the ground on the crank (CCW positive).
    F12, F32, F14 : ndarray of complex
        Pin forces: ``F_ap`` acts on link *p* from link *a* (1 ground, 2 crank,
        3 block, 4 slotted link); ``F32`` at A, ``F14`` at O4.
    F43 : ndarray of complex
        Force of the slotted link on the block at A: ``normal · j û`` plus the
        friction along the slot ``û = e^{jθ4}``.
    normal : ndarray
        The normal force ``N`` of the slot on the block, along ``j û``.
    couple : ndarray
        The couple ``C43`` of the slotted link on the block (CCW positive).
    shaking_force : ndarray of complex
        ``Fs = F21 + F41``, the force of the moving links on the ground.
    shaking_moment : ndarray
        ``Ms = T21 + R1 × F41`` about O2 (``R1 = O4 − O2``).
    aG2, aG3, aG4 : ndarray of complex
        Accelerations of the centres of mass used in the equations.
    motion : InvertedSliderCrankMotion
    status : ndarray of uint8
        0 where solved; otherwise an index into :data:`INVERTED_REASONS`.
    friction : str
        The friction model at the slot.
    """

    REASONS = INVERTED_REASONS

    T12: np.ndarray
    F12: np.ndarray
    F32: np.ndarray
    F43: np.ndarray
    F14: np.ndarray
    normal: np.ndarray
    couple: np.ndarray
    shaking_force: np.ndarray
    shaking_moment: np.ndarray
    aG2: np.ndarray
    aG3: np.ndarray
    aG4: np.ndarray
    motion: InvertedSliderCrankMotion
    status: np.ndarray
    friction: str

    @property
    def N(self) -> np.ndarray:
        """The slot's normal force on the block (along ``j e^{jθ4}``)."""
        return self.normal

    @property
    def friction_force(self) -> np.ndarray:
        """The friction force of the slot on the block along ``e^{jθ4}``."""
        return (self.F43 * np.exp(-1j * self.motion.theta4)).real

    @property
    def shaking_torque(self) -> np.ndarray:
        """Norton's shaking torque ``Ts = T21 = −T12``: the reaction of the drive on the ground."""
        return -self.T12

    @property
    def F21(self) -> np.ndarray:
        """Force of the crank on the ground, ``−F12``."""
        return -self.F12

    @property
    def F41(self) -> np.ndarray:
        """Force of the slotted link on the ground, ``−F14``."""
        return -self.F14

    def to_pandas(self) -> Any:
        """A :class:`pandas.DataFrame`, one row per sample (pandas imported lazily).

        Columns ``theta2``, ``T12``, each force as ``_x``/``_y``, ``N``,
        ``C43``, the shaking force and moment, ``ok`` and ``reason``; named with
        their units (``'T12 [N*m]'``) when the model has a unit system.
        """
        import pandas as pd

        from .units import columns

        spec: list[tuple[str, str | None, Any]] = [
            ("theta2", "angle", self.motion.theta2),
            ("T12", "torque", self.T12),
        ]
        for name in ("F12", "F32", "F43", "F14", "shaking_force"):
            value = np.ravel(getattr(self, name))
            spec += [(f"{name}_x", "force", value.real), (f"{name}_y", "force", value.imag)]
        spec += [
            ("N", "force", self.normal),
            ("C43", "torque", self.couple),
            ("shaking_moment", "torque", self.shaking_moment),
            ("ok", None, self.ok),
            ("reason", None, self.reason),
        ]
        n = int(np.size(self.status))
        cols = columns(self.motion.units, spec)
        return pd.DataFrame({k: np.broadcast_to(v, (n,)) for k, v in cols.items()})

    def plot(self, ax: Any = None, degrees: bool = True) -> Any:
        """Plot ``T12`` and the joint-force magnitudes against θ2 (matplotlib, lazily)."""
        return _plot_forces(self, ax, degrees)

    def __len__(self) -> int:
        return int(np.size(self.T12))


def _check_motion(isc: InvertedSliderCrank, motion: InvertedSliderCrankMotion) -> None:
    """The motion must be this model's: the crank pin on the crank circle and in the slot."""
    A, b, th4 = (np.asarray(x) for x in (motion.A, motion.b, motion.theta4))
    good = np.isfinite(b) & np.isfinite(A)
    scale = isc.a + isc.d + abs(isc.c)
    crank = np.abs(np.abs(A) - isc.a)
    slot = np.abs(isc.d + (b + 1j * isc.c) * np.exp(1j * th4) - A)
    if good.any() and max(crank[good].max(), slot[good].max()) > _SAME_MODEL_TOL * scale:
        raise InputError(
            "motion",
            f"was not solved by {isc!r} (its crank pin is off this crank circle or slot); "
            "pass the motion of this inverted slider-crank",
        )


def _known_loads(
    isc: InvertedSliderCrank, m: InvertedSliderCrankMotion, props: Any, g: float, loads, torques
) -> dict[str, Any]:
    """Centre-of-mass accelerations and each link's known load (``F``, moment about its pin)."""
    m2, m3, m4 = props.mass
    I2, I3, I4 = props.inertia
    c2, c3, c4 = props.cg
    A = m.A
    e2 = A * (1.0 / isc.a)
    e4 = np.exp(1j * m.theta4)
    w2, w4, al2, al4 = m.omega2, m.omega4, m.alpha2, m.alpha4
    k2 = 1j * al2 - w2 * w2
    k4 = 1j * al4 - w4 * w4
    g2, g3, g4 = c2 * e2, c3 * e4, c4 * e4  # G − (O2, A, O4)
    aG2 = g2 * k2
    aG3 = A * k2 + g3 * k4
    aG4 = g4 * k4
    frame = {2: e2, 3: e4, 4: e4}
    Fe: dict[int, Any] = {2: 0.0, 3: 0.0, 4: 0.0}
    Me: dict[int, Any] = {2: 0.0, 3: 0.0, 4: 0.0}
    if g:
        for k, mk, gk in ((2, m2, g2), (3, m3, g3), (4, m4, g4)):
            if mk:
                Fe[k] = Fe[k] - 1j * (mk * g)
                Me[k] = Me[k] - (mk * g) * gk.real  # (G − pin) × (−m g j)
    for load in loads:
        arm = load.point * frame[load.link]
        Fe[load.link] = Fe[load.link] + load.force
        Me[load.link] = Me[load.link] + _cross(arm, np.broadcast_to(load.force, np.shape(arm)))
    for link, torque in torques:
        Me[link] = Me[link] + torque
    return {
        "aG": (aG2, aG3, aG4),
        "F": (Fe[2] - m2 * aG2, Fe[3] - m3 * aG3, Fe[4] - m4 * aG4),
        "M": (
            Me[2] - (I2 * al2 + m2 * _cross(g2, aG2)),
            Me[3] - (I3 * al4 + m3 * _cross(g3, aG3)),
            Me[4] - (I4 * al4 + m4 * _cross(g4, aG4)),
        ),
        "e4": e4,
    }


def inverted_slidercrank_forces(
    isc: InvertedSliderCrank,
    motion: InvertedSliderCrankMotion,
    *,
    mass: Sequence[float],
    inertia: Sequence[float],
    cg: Sequence[complex],
    gravity: float = 0.0,
    load_torque4: Any = 0.0,
    friction: str = "smooth",
    mu: float = 0.0,
    beta: float = 0.0,
    external_forces: Iterable[Any] = (),
    external_torques: Any = (),
) -> InvertedSliderCrankForces:
    """Newton–Euler forces for a solved motion of an inverted slider-crank.

    See :func:`inverted_slidercrank_dynamics` for the parameters; use this one
    to reuse one kinematic solution with several masses or loads.

    Examples
    --------
    >>> from machdyn import InvertedSliderCrank
    >>> isc = InvertedSliderCrank(2.0, 4.0)
    >>> motion = isc.solve(np.radians([30, 60]), omega2=10.0)
    >>> f = inverted_slidercrank_forces(isc, motion, mass=(1, 0.5, 3), inertia=(0.1, 0.01, 2),
    ...                                 cg=(1, 0, 2))
    >>> f.T12.shape, bool(f.ok.all())
    ((2,), True)
    """
    from .linkage import newton_euler  # on first use: machdyn.linkage is heavy to import

    instance("isc", isc, InvertedSliderCrank)
    instance(
        "motion",
        motion,
        InvertedSliderCrankMotion,
        "an InvertedSliderCrankMotion (from InvertedSliderCrank.solve)",
    )
    _check_motion(isc, motion)
    friction = choice("friction", friction, _FRICTION_MODELS)
    units = unit_system(isc.length_unit)
    props = link_properties(mass, inertia, cg, isc.length_unit)
    g = nonnegative("gravity", gravity, units["acceleration"])
    mu = nonnegative("mu", mu, "")
    beta = nonnegative("beta", beta, units["damping"])
    loads = _point_loads(external_forces, units)
    torques = list(_torques(external_torques, units))
    load4 = finite_array("load_torque4", load_torque4, units["torque"])
    _check_sample_shapes(np.shape(motion.status), loads, torques, ("load_torque4", load4))
    torques.append((4, load4))

    status = np.array(motion.status, dtype=np.uint8, copy=True)
    known = _known_loads(isc, motion, props, g, loads, torques)
    (F2, F3, F4), (M2, M3, M4), e4 = known["F"], known["M"], known["e4"]
    A, b_dot = motion.A, motion.b_dot
    r = A - isc.d  # O4 → A
    # viscous friction −β ḃ û on the block at A, its reaction on link 4
    f0 = -beta * b_dot * e4 if friction == "viscous" else 0.0 * e4
    F3 = F3 + f0
    F4 = F4 - f0
    M4 = M4 - _cross(r, f0)
    if friction == "coulomb" and mu:
        speed = (isc.a + isc.d) * np.abs(motion.omega2)  # ḃ below REST_TOL × this: a dead point
        slip = newton_euler._slip_sign(b_dot, motion.b_ddot, speed)
        F23, N, C43, F14, den, kappa, jammed = newton_euler.rpr_coulomb(
            r, e4, slip, mu, F3, M3, F4, M4
        )
        status[(status == OK) & jammed] = _JAM
        status[(status == OK) & (slip == 0.0)] = _STICK
    else:
        kappa = 0.0
        F23, N, C43, F14, den = newton_euler.rpr(r, 1j * e4, F3, M3, F4, M4)
    singular = np.abs(den) <= 1e-9 * (isc.a + isc.d)
    status[(status == OK) & singular] = TOGGLE if friction != "coulomb" else _JAM
    F43 = N * (1j + kappa) * e4 + f0
    F32 = -F23
    F12, T12 = newton_euler.crank(F2 + F32, M2 + _cross(A, F32))
    shape = np.shape(status)
    aG2, aG3, aG4 = known["aG"]
    out = [np.broadcast_to(x, shape) for x in (T12, F12, F32, F43, F14, N, C43, aG2, aG3, aG4)]
    bad = status != OK
    out = [np.where(bad, np.nan, x) for x in out]  # copies (never views of the inputs)
    T12, F12, F32, F43, F14, N, C43, aG2, aG3, aG4 = out
    return InvertedSliderCrankForces(
        T12=T12,
        F12=F12,
        F32=F32,
        F43=F43,
        F14=F14,
        normal=N,
        couple=C43,
        shaking_force=-(F12 + F14),
        shaking_moment=-T12 - isc.d * F14.imag,  # T21 + R1 × F41
        aG2=aG2,
        aG3=aG3,
        aG4=aG4,
        motion=motion,
        status=status,
        friction=friction,
    )


def inverted_slidercrank_dynamics(
    isc: InvertedSliderCrank,
    theta2: Any,
    omega2: Any,
    alpha2: Any = 0.0,
    *,
    mass: Sequence[float],
    inertia: Sequence[float],
    cg: Sequence[complex],
    form: int = 1,
    gravity: float = 0.0,
    load_torque4: Any = 0.0,
    friction: str = "smooth",
    mu: float = 0.0,
    beta: float = 0.0,
    external_forces: Iterable[Any] = (),
    external_torques: Any = (),
) -> InvertedSliderCrankForces:
    """Joint forces and crank torque of an inverted slider-crank (Norton §11.7).

    Parameters
    ----------
    isc : InvertedSliderCrank
    theta2, omega2, alpha2 : array_like
        Crank angle (rad), angular velocity and acceleration; broadcast.
    mass : (m2, m3, m4)
        Crank, block and slotted-link masses (≥ 0).
    inertia : (IG2, IG3, IG4)
        Moments of inertia about the centres of mass (the block turns with
        link 4, so IG3 counts).
    cg : (c2, c3, c4)
        Centres of mass, complex, each in its link's frame: the crank's origin
        O2, x toward A; the block's origin A, x along the slot (``e^{jθ4}``);
        the slotted link's origin O4, x along the slot (its line is then
        ``y = c``).
    form : {1, 2}
        As in :meth:`InvertedSliderCrank.solve`.
    gravity : float
        ``g ≥ 0`` along −y.
    load_torque4 : array_like
        External torque on the slotted link (the output; CCW positive), e.g.
        ``−T`` for a resisting load.
    friction : {"smooth", "coulomb", "viscous"}
        Friction of the slot on the block: none; Coulomb ``−μ |N| sign(ḃ)``
        (both signs of ``N`` are solved and the consistent one kept; where
        both or neither fit the block wedges: flagged); viscous ``−β ḃ``.
    mu, beta : float
        Coulomb coefficient and viscous damping coefficient (≥ 0).
    external_forces : iterable of (link, point, force) or PointLoad
        Forces on links 2–4 at points in the link's frame (see ``cg``).
    external_torques : iterable of (link, torque), or a mapping link → torque

    Returns
    -------
    InvertedSliderCrankForces
        ``T12, F12, F32, F43, F14``, the slot's ``normal`` force and
        ``couple``, shaking force and moment, per-sample ``ok``/``reason``
        (unassemblable, toggle and wedged samples hold NaN).

    Examples
    --------
    A static torque −5 on the slotted link of a massless shaper needs
    ``T12 ω2 = 5 ω4`` (virtual work):

    >>> from machdyn import InvertedSliderCrank
    >>> isc = InvertedSliderCrank(2.0, 4.0)
    >>> f = inverted_slidercrank_dynamics(isc, np.radians(60), 1.0, mass=(0, 0, 0),
    ...                                   inertia=(0, 0, 0), cg=(0, 0, 0), load_torque4=-5.0)
    >>> bool(np.isclose(f.T12, 5.0 * f.motion.omega4))
    True
    """
    instance("isc", isc, InvertedSliderCrank)
    _check_input_shapes(theta2, omega2, alpha2)
    motion = isc.solve(theta2, omega2, alpha2, form)
    return inverted_slidercrank_forces(
        isc,
        motion,
        mass=mass,
        inertia=inertia,
        cg=cg,
        gravity=gravity,
        load_torque4=load_torque4,
        friction=friction,
        mu=mu,
        beta=beta,
        external_forces=external_forces,
        external_torques=external_torques,
    )
