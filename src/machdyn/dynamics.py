"""Dynamic force analysis of the four-bar (Newton–Euler, the notes' matrix method).

For every sample of a motion this module finds the joint forces ``F12, F32,
F43, F14``, the driving torque ``T12`` and the shaking force and moment on the
ground, with the masses and inertias of links 2–4, gravity, external forces at
points on the links and external torques.

Nomenclature (the notes' "FORCE ANALYSIS" section; Norton, *Design of
Machinery*, sec. 11.4–11.8): ``F_ap`` is the force on link *p* from link *a*
(so ``F_pa = −F_ap``); ``R_ap`` runs from the centre of mass of *p* to the
joint between *a* and *p*; ``T12`` is the torque of the ground on link 2.
Forces are complex numbers ``Fx + j Fy``; torques are CCW positive.

Equations (Norton eq. 11.9, one link at a time)::

    link 2:  F12 + F32 + ΣF2 = m2 aG2       T12 + R12×F12 + R32×F32 + ΣM2 = IG2 α2
    link 3:  F43 − F32 + ΣF3 = m3 aG3       R43×F43 − R23×F32 + ΣM3 = IG3 α3
    link 4:  F14 − F43 + ΣF4 = m4 aG4       R14×F14 − R34×F43 + ΣM4 = IG4 α4

nine linear equations in ``F12x, F12y, F32x, F32y, F43x, F43y, F14x, F14y,
T12`` (Norton eq. 11.10). ``ΣF`` and ``ΣM`` are the external loads (gravity,
point forces, torques; ``load_torque4`` is the external torque on link 4).

Solution method
---------------
The 9×9 system is solved by elimination in closed form, so a million samples
cost a few array operations each. Taking moments of link 4 about ``O4`` and of
link 3 about ``A`` leaves only ``F43``::

    (B − A) × F43 = M3,     (B − O4) × F43 = −M4

with ``M3 = IG3 α3 + (G3 − A) × m3 aG3 − (external moment on 3 about A)`` and
``M4`` likewise about ``O4``. Writing ``u = B − A`` and ``w = B − O4``,
``F43 = (M4 u + M3 w) / (u × w)``; the determinant ``u × w = r3 r4 sin(θ4 − θ3)``
vanishes only at a toggle of links 3 and 4, which is flagged. The other forces
follow from the force equations of links 3, 4 and 2, and ``T12`` from the
moment of link 2 about ``O2``. The tests build the 9×9 matrix independently
and compare.

Shaking force and moment (Norton sec. 11.8, eq. 11.15): the shaking force is
the sum of the forces the moving links exert on the ground,
``Fs = F21 + F41 = −(F12 + F14)``; the shaking moment is their moment about
``O2`` plus the reaction of the driving torque, ``Ms = T21 + R1 × F41`` with
``T21 = −T12`` and ``R1 = O4 − O2``. Without gravity and external loads
``Fs = −Σ m_i aG_i``, which vanishes for a force-balanced linkage.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._flags import Flagged
from ._validate import broadcast as _broadcast
from ._validate import (
    choice,
    complex_scalar,
    finite_array,
    finite_scalar,
    instance,
    items,
    magnitude,
    nonnegative,
    text,
)
from .errors import InputError
from .fourbar import OK, STATUS_REASONS, TOGGLE, FourBar, FourBarMotion
from .slidercrank import SliderCrank, SliderCrankMotion

__all__ = [
    "FORCE_REASONS",
    "SLIDER_REASONS",
    "FourBarForces",
    "LinkEquations",
    "LinkProperties",
    "PointLoad",
    "SliderCrankForces",
    "fourbar_dynamics",
    "fourbar_forces",
    "from_bodies",
    "link_equations",
    "link_properties",
    "slidercrank_dynamics",
    "slidercrank_forces",
    "unit_system",
]

#: Why a sample has no force solution (indexed by the motion's status code).
FORCE_REASONS: tuple[str, ...] = tuple(
    (
        "toggle: links 3 and 4 are collinear; the velocity solution and the force "
        "system (Norton eq. 11.10) are singular"
    )
    if code == TOGGLE
    else text
    for code, text in enumerate(STATUS_REASONS)
)

_MOVING_LINKS = (2, 3, 4)


# --------------------------------------------------------------------------------------
# Inputs


@dataclass(frozen=True)
class LinkProperties:
    """Validated mass properties of links 2, 3 and 4 of a four-bar.

    Attributes
    ----------
    mass : tuple of float
        ``(m2, m3, m4)``, each ≥ 0.
    inertia : tuple of float
        ``(IG2, IG3, IG4)``: moments of inertia about each centre of mass.
    cg : tuple of complex
        ``(c2, c3, c4)``: centre of mass of each link in its own frame (origin at
        O2, A, O4; x axis toward A, B, B).
    """

    mass: tuple[float, float, float]
    inertia: tuple[float, float, float]
    cg: tuple[complex, complex, complex]


def _triple(field: str, value: Any) -> tuple[Any, Any, Any]:
    return items(field, value, 3, "values (links 2, 3, 4)")  # type: ignore[return-value]


def unit_system(length_unit: str | None) -> dict[str, str]:
    """Units that pint quantities are converted to, given the model's length unit.

    The numeric API works in any consistent system; quantities are converted
    once at the boundary to kilograms, seconds and the linkage's length unit
    (metres if its lengths were plain numbers), and results are in the same
    system (forces in kg·L/s², torques in kg·L²/s²).

    Examples
    --------
    >>> unit_system("mm")["force"]
    'kg * mm / s ** 2'
    """
    length = "m" if length_unit is None else text("length_unit", length_unit)
    return {
        "mass": "kg",
        "inertia": f"kg * {length} ** 2",
        "length": length,
        "acceleration": f"{length} / s ** 2",
        "force": f"kg * {length} / s ** 2",
        "torque": f"kg * {length} ** 2 / s ** 2",
        "damping": "kg / s",
    }


def _complex_scalar(field: str, value: Any, unit: str | None = None) -> complex:
    return complex_scalar(field, value, unit)


def link_properties(
    mass: Any, inertia: Any, cg: Any, length_unit: str | None = None
) -> LinkProperties:
    """Check the mass properties of links 2, 3, 4 and return them as plain numbers.

    Masses and inertias are ≥ 0: a link with zero mass and inertia is
    massless (kinetostatics); a positive mass with zero inertia is a point
    mass (Norton's lumped-mass models, :func:`machdyn.massprops.point_mass`).
    Negative or non-finite values, and an inertia without mass, are rejected.

    Examples
    --------
    >>> link_properties((1, 2, 3), (0.1, 0.2, 0.3), (0.5, 1 + 0.5j, 2)).cg
    ((0.5+0j), (1+0.5j), (2+0j))
    >>> link_properties((1, 2), (0.1, 0.2, 0.3), (0, 0, 0))
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: mass: must have exactly 3 values (links 2, 3, 4), got 2
    """
    masses = _triple("mass", mass)
    inertias = _triple("inertia", inertia)
    cgs = _triple("cg", cg)
    units = unit_system(length_unit)
    m = tuple(
        nonnegative(f"mass m{k}", v, units["mass"])
        for k, v in zip(_MOVING_LINKS, masses, strict=True)
    )
    i = tuple(
        nonnegative(f"inertia IG{k}", v, units["inertia"])
        for k, v in zip(_MOVING_LINKS, inertias, strict=True)
    )
    for k, mk, ik in zip(_MOVING_LINKS, m, i, strict=True):
        if mk == 0.0 and ik != 0.0:
            raise InputError(
                f"mass m{k}",
                f"link {k} has no mass but IG{k} = {ik:g}; give its mass (> 0), or "
                f"IG{k} = 0 for a massless link",
            )
    c = tuple(
        _complex_scalar(f"cg c{k}", v, units["length"])
        for k, v in zip(_MOVING_LINKS, cgs, strict=True)
    )
    return LinkProperties(m, i, c)  # type: ignore[arg-type]


def from_bodies(*bodies: Any) -> dict[str, tuple[Any, ...]]:
    """``mass=, inertia=, cg=`` keyword arguments from one body per moving link.

    Each body has ``.mass``, ``.cg`` (complex, in the link's frame) and
    ``.inertia`` (about the centre of mass), e.g. a
    :class:`machdyn.massprops.MassProperties`.

    Examples
    --------
    >>> from machdyn.massprops import rod
    >>> kw = from_bodies(rod(1.0, 4.0), rod(2.0, 7.0), rod(1.5, 6.0))
    >>> kw["cg"]
    ((2+0j), (3.5+0j), (3+0j))
    """
    try:
        return {
            "mass": tuple(b.mass for b in bodies),
            "inertia": tuple(b.inertia for b in bodies),
            "cg": tuple(complex(b.cg) for b in bodies),
        }
    except AttributeError:
        raise InputError(
            "bodies", "each body needs .mass, .cg and .inertia (e.g. massprops.rod(...))"
        ) from None


@dataclass(frozen=True)
class PointLoad:
    """An external force on a moving link at a point fixed in that link.

    Attributes
    ----------
    link : int
        2, 3 or 4.
    point : complex
        Where the force acts, in the link's own frame (origin at the link's
        first joint O2, A, O4; x axis toward its next joint A, B, B).
    force : complex or ndarray of complex
        The force ``Fx + j Fy`` in the ground frame, one value or one per sample.
    """

    link: int
    point: complex
    force: Any


def _point_loads(external_forces: Any, units: dict[str, str]) -> tuple[PointLoad, ...]:
    if isinstance(external_forces, PointLoad):
        external_forces = (external_forces,)
    out = []
    for n, item in enumerate(items("external_forces", external_forces, what="loads")):
        field = f"external_forces[{n}]"
        if isinstance(item, PointLoad):
            link, point, force = item.link, item.point, item.force
        else:
            try:
                link, point, force = item
            except (TypeError, ValueError):
                raise InputError(
                    field, f"expected (link, point, force) or a PointLoad, got {item!r}"
                ) from None
        link = choice(f"{field} link", link, _MOVING_LINKS)
        point = _complex_scalar(f"{field} point", point, units["length"])
        force = np.asarray(magnitude(force, units["force"], f"{field} force"))
        if not np.iscomplexobj(force):
            force = finite_array(f"{field} force", force)
        elif not np.isfinite(force).all():
            raise InputError(f"{field} force", "must be finite")
        out.append(PointLoad(link, point, force.astype(complex)))
    return tuple(out)


def _torques(external_torques: Any, units: dict[str, str]) -> tuple[tuple[int, np.ndarray], ...]:
    pairs = (
        external_torques.items()
        if isinstance(external_torques, Mapping)
        else items("external_torques", external_torques, what="(link, torque) pairs")
    )
    out = []
    for n, item in enumerate(pairs):
        field = f"external_torques[{n}]"
        try:
            link, torque = item
        except (TypeError, ValueError):
            raise InputError(field, f"expected (link, torque), got {item!r}") from None
        link = choice(f"{field} link", link, _MOVING_LINKS)
        out.append((link, finite_array(f"{field} torque", torque, units["torque"])))
    return tuple(out)


def _check_model(model: Any, motion: Any) -> None:
    lengths = getattr(model, "lengths", None)
    if lengths is not None and tuple(motion.lengths) != tuple(lengths):
        raise InputError(
            "motion",
            f"was solved for lengths {tuple(motion.lengths)}, not for {model!r}; "
            "pass the motion of this linkage",
        )


def _check_slidercrank(slidercrank: Any, motion: Any) -> None:
    """The motion must be this slider-crank's: its offset, ``|O2A| = a``, ``|AB| = b``."""
    a, b, c = slidercrank.a, slidercrank.b, slidercrank.c
    A, B = np.ravel(motion.A), np.ravel(motion.B)
    there = np.flatnonzero(np.isfinite(A) & np.isfinite(B))[:16]  # a few poses tell
    tol = 1e-9 * (a + b + abs(c))
    if (
        abs(float(motion.offset) - c) > tol
        or np.any(np.abs(np.abs(A[there]) - a) > tol)
        or np.any(np.abs(np.abs(B[there] - A[there]) - b) > tol)
    ):
        raise InputError(
            "motion",
            f"was not solved by {slidercrank!r} (its crank, rod or offset differ); "
            "pass the motion of this slider-crank",
        )


def _check_sample_shapes(
    shape: tuple[int, ...], loads: Any, torques: Any, load4: tuple[str, Any]
) -> None:
    """Per-sample loads must broadcast to the motion's samples, not enlarge them."""
    named = [(f"external_forces[{n}] force", ld.force) for n, ld in enumerate(loads)]
    named += [(f"external_torques[{n}] torque", t) for n, (_, t) in enumerate(torques)]
    named.append(load4)
    for field, value in named:
        try:
            ok = np.broadcast_shapes(np.shape(value), shape) == shape
        except ValueError:
            ok = False
        if not ok:
            raise InputError(
                field,
                f"has shape {np.shape(value)}; give one value or one per sample "
                f"(the motion has shape {shape})",
            )


def _check_input_shapes(theta2: Any, omega2: Any, alpha2: Any) -> None:
    """The input's angle, speed and acceleration must broadcast (InputError, not numpy's)."""
    _broadcast(theta2=theta2, omega2=omega2, alpha2=alpha2)  # shapes only (quantities too)


def _plot_forces(result: Any, ax: Any, degrees: bool) -> Any:
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots()
    x = np.ravel(result.motion.theta2)
    x = np.degrees(x) if degrees else x
    for name in ("F12", "F32", "F43", "F14"):
        ax.plot(x, np.abs(np.ravel(getattr(result, name))), label=f"|{name}|")
    ax.plot(x, np.ravel(result.T12), "k", label="T12")
    ax.set_xlabel("θ2 [deg]" if degrees else "θ2 [rad]")
    ax.set_ylabel("force, torque")
    ax.legend()
    return ax


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The z component of ``u × v`` for planar vectors given as complex numbers."""
    return u.real * v.imag - u.imag * v.real


# --------------------------------------------------------------------------------------
# Result


@dataclass(frozen=True, eq=False)
class FourBarForces(Flagged):
    """Joint forces, driving torque and shaking loads of a four-bar over a motion.

    Attributes
    ----------
    T12 : ndarray
        Driving torque of the ground on link 2 (CCW positive).
    F12, F32, F43, F14 : ndarray of complex
        Joint forces: ``F_ap`` acts on link *p* from link *a*.
    shaking_force : ndarray of complex
        ``Fs = F21 + F41``: the force of the moving links on the ground (Norton
        eq. 11.15a).
    shaking_moment : ndarray
        ``Ms = T21 + R1 × F41``: their moment on the ground about O2 (Norton
        eq. 11.15b).
    aG2, aG3, aG4 : ndarray of complex
        Accelerations of the centres of mass used in the equations.
    motion : FourBarMotion
        The kinematics the forces belong to.
    status : ndarray of uint8
        0 where solved; otherwise an index into :data:`FORCE_REASONS`.
    """

    REASONS = FORCE_REASONS

    T12: np.ndarray
    F12: np.ndarray
    F32: np.ndarray
    F43: np.ndarray
    F14: np.ndarray
    shaking_force: np.ndarray
    shaking_moment: np.ndarray
    aG2: np.ndarray
    aG3: np.ndarray
    aG4: np.ndarray
    motion: FourBarMotion
    status: np.ndarray

    @property
    def shaking_torque(self) -> np.ndarray:
        """Norton's shaking torque ``Ts = T21 = −T12``: the reaction of the drive on the ground."""
        return -self.T12

    @property
    def F21(self) -> np.ndarray:
        """Force of link 2 on the ground, ``−F12``."""
        return -self.F12

    @property
    def F41(self) -> np.ndarray:
        """Force of link 4 on the ground, ``−F14``."""
        return -self.F14

    def to_pandas(self):
        """A :class:`pandas.DataFrame`, one row per sample (pandas imported lazily).

        Columns: ``theta2`` (rad), ``T12``, each force as ``_x``/``_y`` and
        magnitude ``_mag``, the shaking force and moment, ``ok`` and ``reason``.
        """
        import pandas as pd

        columns: dict[str, np.ndarray] = {
            "theta2": np.ravel(self.motion.theta2),
            "T12": np.ravel(self.T12),
        }
        for name in ("F12", "F32", "F43", "F14", "shaking_force"):
            value = np.ravel(getattr(self, name))
            columns[f"{name}_x"] = value.real
            columns[f"{name}_y"] = value.imag
            columns[f"{name}_mag"] = np.abs(value)
        columns["shaking_moment"] = np.ravel(self.shaking_moment)
        columns["ok"] = np.ravel(self.ok)
        columns["reason"] = np.ravel(self.reason)
        return pd.DataFrame(_labelled(columns, self.motion))

    def plot(self, ax: Any = None, degrees: bool = True):
        """Plot ``T12`` and the joint-force magnitudes against θ2 (matplotlib, lazily)."""
        return _plot_forces(self, ax, degrees)

    def __len__(self) -> int:
        return int(np.size(self.T12))


# --------------------------------------------------------------------------------------
# The solver


#: Samples are processed in blocks of this size (keeps temporaries in cache).
_CHUNK = 1 << 14


def _fourbar_newton_euler(
    lengths: tuple[float, float, float, float],
    props: LinkProperties,
    g: float,
    loads: list[tuple[int, complex, np.ndarray]],
    torques: list[tuple[int, np.ndarray]],
    A: np.ndarray,
    B: np.ndarray,
    w2: np.ndarray,
    w3: np.ndarray,
    w4: np.ndarray,
    al2: np.ndarray,
    al3: np.ndarray,
    al4: np.ndarray,
) -> dict[str, np.ndarray]:
    """Norton eq. 11.10 eliminated in closed form, for flat arrays of samples."""
    from .linkage import newton_euler  # on first use: machdyn.linkage is heavy to import

    m2, m3, m4 = props.mass
    I2, I3, I4 = props.inertia
    c2, c3, c4 = props.cg
    r1, r2, r3, r4 = lengths
    e2 = A * (1.0 / r2)  # e^{jθ2}
    u = B - A  # r3 e^{jθ3}
    w = B - r1  # r4 e^{jθ4}
    e3 = u * (1.0 / r3)
    e4 = w * (1.0 / r4)

    # Centres of mass relative to each link's first joint, and their accelerations.
    g2 = c2 * e2
    g3 = c3 * e3
    g4 = c4 * e4
    k2 = 1j * al2 - w2 * w2
    aG2 = g2 * k2
    aG3 = A * k2 + g3 * (1j * al3 - w3 * w3)
    aG4 = g4 * (1j * al4 - w4 * w4)

    # External loads: net force on each link and moment about its first joint.
    frame = {2: e2, 3: e3, 4: e4}
    Fe: dict[int, Any] = {k: 0.0 for k in _MOVING_LINKS}
    Me: dict[int, Any] = {k: 0.0 for k in _MOVING_LINKS}
    if g:
        for k, mk, gk in ((2, m2, g2), (3, m3, g3), (4, m4, g4)):
            if mk:
                Fe[k] = Fe[k] - 1j * (mk * g)
                Me[k] = Me[k] - (mk * g) * gk.real  # (G − O) × (−m g j)
    for link, point, force in loads:
        arm = point * frame[link]  # P − (first joint), ground frame
        Fe[link] = Fe[link] + force
        Me[link] = Me[link] + _cross(arm, np.broadcast_to(force, np.shape(arm)))
    for link, torque in torques:
        if torque.ndim or torque:
            Me[link] = Me[link] + torque

    # Known loads of links 2, 3, 4 (external, gravity, reversed inertia) with their moments
    # about O2, A and O4; the Assur groups solved in closed form (machdyn.linkage.newton_euler):
    # the RRR dyad (3, 4) first, then the crank with the coupler's reaction.
    M2 = Me[2] - (I2 * al2 + m2 * _cross(g2, aG2))
    M3 = Me[3] - (I3 * al3 + m3 * _cross(g3, aG3))
    M4 = Me[4] - (I4 * al4 + m4 * _cross(g4, aG4))
    F23, F43, F14, det = newton_euler.rrr(u, w, Fe[3] - m3 * aG3, M3, Fe[4] - m4 * aG4, M4)
    F32 = -F23
    F12, T12 = newton_euler.crank(Fe[2] - m2 * aG2 + F32, M2 + _cross(A, F32))
    return {
        "T12": T12,
        "F12": F12,
        "F32": F32,
        "F43": F43,
        "F14": F14,
        "aG2": aG2,
        "aG3": aG3,
        "aG4": aG4,
        "det": det,
    }


def fourbar_forces(
    fourbar: FourBar,
    motion: FourBarMotion,
    *,
    mass: Sequence[float],
    inertia: Sequence[float],
    cg: Sequence[complex],
    gravity: float = 0.0,
    load_torque4: Any = 0.0,
    external_forces: Iterable[Any] = (),
    external_torques: Any = (),
) -> FourBarForces:
    """Newton–Euler forces for an already solved motion of ``fourbar``.

    Same as :func:`fourbar_dynamics` (see there for the parameters), for a
    :class:`~machdyn.fourbar.FourBarMotion` from :meth:`FourBar.solve`. Use it
    to reuse one kinematic solution with several mass distributions or loads.

    Examples
    --------
    >>> fb = FourBar(8, 4, 7, 6)
    >>> motion = fb.solve(np.radians([0, 90]), omega2=10.0)
    >>> f = fourbar_forces(fb, motion, mass=(1, 2, 3), inertia=(1, 1, 1), cg=(2, 3.5, 3))
    >>> f.T12.shape, bool(f.ok.all())
    ((2,), True)
    """
    instance("fourbar", fourbar, FourBar)
    instance("motion", motion, FourBarMotion, "a FourBarMotion (from FourBar.solve)")
    _check_model(fourbar, motion)
    units = unit_system(fourbar.length_unit)
    props = link_properties(mass, inertia, cg, fourbar.length_unit)
    g = nonnegative("gravity", gravity, units["acceleration"])
    loads = _point_loads(external_forces, units)
    torques = list(_torques(external_torques, units))
    load4 = finite_array("load_torque4", load_torque4, units["torque"])
    _check_sample_shapes(np.shape(motion.status), loads, torques, ("load_torque4", load4))
    torques.append((4, load4))

    r1 = fourbar.r1
    status = np.array(motion.status, dtype=np.uint8, copy=True)
    shape = status.shape
    n = status.size

    def flat(x: Any) -> np.ndarray:
        x = np.asarray(x)
        return x if x.ndim == 0 else np.broadcast_to(x, shape).ravel()

    kin = [flat(x) for x in (motion.A, motion.B, motion.omega2, motion.omega3, motion.omega4)]
    kin += [flat(x) for x in (motion.alpha2, motion.alpha3, motion.alpha4)]
    flat_loads = [(ld.link, ld.point, flat(ld.force)) for ld in loads]
    flat_torques = [(link, flat(t)) for link, t in torques]
    names = ("T12", "F12", "F32", "F43", "F14", "aG2", "aG3", "aG4", "det")
    out = {k: np.empty(n, dtype=float if k in ("T12", "det") else complex) for k in names}
    # Chunks keep the temporaries in cache (a loop over blocks, not over samples).
    for lo in range(0, n, _CHUNK):
        sl = slice(lo, min(lo + _CHUNK, n))

        def part(x: np.ndarray, sl: slice = sl) -> np.ndarray:
            return x if x.ndim == 0 else x[sl]

        chunk = _fourbar_newton_euler(
            fourbar.lengths,
            props,
            g,
            [(link, point, part(f)) for link, point, f in flat_loads],
            [(link, part(t)) for link, t in flat_torques],
            *(part(x) for x in kin),
        )
        for k in names:
            out[k][sl] = chunk[k]
    T12, F12, F32, F43, F14, aG2, aG3, aG4, det = (out[k].reshape(shape) for k in names)
    singular = np.abs(det) < 1e-9 * fourbar.r3 * fourbar.r4
    status[(status == OK) & singular] = TOGGLE
    bad = status != OK
    if bad.any():
        for arr in (T12, F12, F32, F43, F14, aG2, aG3, aG4):
            arr[bad] = np.nan
    return FourBarForces(
        T12=T12,
        F12=F12,
        F32=F32,
        F43=F43,
        F14=F14,
        shaking_force=-(F12 + F14),
        shaking_moment=-T12 - r1 * F14.imag,  # T21 + R1 × F41
        aG2=aG2,
        aG3=aG3,
        aG4=aG4,
        motion=motion,
        status=status,
    )


def fourbar_dynamics(
    fourbar: FourBar,
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
    external_forces: Iterable[Any] = (),
    external_torques: Any = (),
    branch: int | None = None,
) -> FourBarForces:
    """Joint forces and driving torque of a four-bar (Newton–Euler, Norton eq. 11.10).

    Parameters
    ----------
    fourbar : FourBar
        The linkage.
    theta2, omega2, alpha2 : array_like
        Input angle (rad), angular velocity and acceleration of link 2;
        broadcast against each other.
    mass : (m2, m3, m4)
        Link masses (≥ 0; a massless link has zero inertia too).
    inertia : (IG2, IG3, IG4)
        Moments of inertia about the centres of mass.
    cg : (c2, c3, c4)
        Centre of mass of each link as a complex position in the link's own
        frame: origin at its first joint (O2, A, O4), x axis toward its next
        joint (A, B, B). E.g. ``c3 = r3 / 2`` is the middle of the coupler.
    form : {1, 2}
        The assembly form, as in :meth:`FourBar.solve`.
    gravity : float
        Acceleration of gravity ``g ≥ 0``, acting along −y.
    load_torque4 : array_like
        External torque on link 4 (CCW positive), e.g. ``−T`` for a resisting load.
    external_forces : iterable of (link, point, force) or PointLoad
        Forces on links 2–4 at points given in the link's frame; ``force`` is
        complex, one value or one per sample.
    external_torques : iterable of (link, torque), or a mapping link → torque
        External torques on links 2–4.
    branch : {1, -1}, optional
        Only for GRCR and GRRC, as in :meth:`FourBar.solve`.

    Returns
    -------
    FourBarForces
        Arrays ``T12, F12, F32, F43, F14``, shaking force and moment, the motion,
        and per-sample ``ok``/``reason`` (toggles and unassemblable inputs are
        flagged and hold NaN).

    Examples
    --------
    A balanced crank (centre of mass at O2) turning steadily with no load
    needs no torque:

    >>> fb = FourBar(8, 4, 7, 6)
    >>> f = fourbar_dynamics(fb, np.radians(30), 10.0, mass=(1, 0, 0),
    ...                      inertia=(0.5, 0, 0), cg=(0, 0, 0))
    >>> float(f.T12), float(abs(f.F12))
    (0.0, 0.0)

    A static load torque on the output (no masses) is balanced by the input
    torque times the velocity ratio (virtual work):

    >>> f = fourbar_dynamics(fb, np.radians(30), 1.0, mass=(0, 0, 0),
    ...                      inertia=(0, 0, 0), cg=(0, 0, 0), load_torque4=-5.0)
    >>> bool(np.isclose(f.T12 * 1.0, 5.0 * f.motion.omega4))
    True
    """
    instance("fourbar", fourbar, FourBar)
    _check_input_shapes(theta2, omega2, alpha2)
    motion = fourbar.solve(theta2, omega2, alpha2, form, branch=branch)
    return fourbar_forces(
        fourbar,
        motion,
        mass=mass,
        inertia=inertia,
        cg=cg,
        gravity=gravity,
        load_torque4=load_torque4,
        external_forces=external_forces,
        external_torques=external_torques,
    )


# --------------------------------------------------------------------------------------
# One link's kinetic equations (the notes' final exam, problem 7)


@dataclass(frozen=True)
class LinkEquations:
    """The three kinetic equations of one link, ``matrix @ unknowns = rhs``.

    Rows: ΣFx, ΣFy, ΣM_G (about the centre of mass, CCW positive). Columns:
    ``unknowns`` (``"F32x", "F32y", ...``).
    """

    unknowns: tuple[str, ...]
    matrix: np.ndarray
    rhs: np.ndarray

    def residual(self, values: Sequence[float]) -> np.ndarray:
        """``matrix @ values − rhs`` for trial values of the unknowns."""
        x = finite_array("values", values)
        if x.shape != (len(self.unknowns),):
            raise InputError(
                "values",
                f"must hold one value per unknown ({', '.join(self.unknowns)}), got shape "
                f"{x.shape}",
            )
        return self.matrix @ x - self.rhs

    def __str__(self) -> str:
        lines = []
        for row, rhs in zip(self.matrix, self.rhs, strict=True):
            terms = [
                f"{'+' if c >= 0 else '-'} {abs(c):g}*{name}"
                for c, name in zip(row, self.unknowns, strict=True)
                if c != 0.0
            ]
            text = " ".join(terms)
            text = text[2:] if text.startswith("+ ") else "-" + text[2:]
            lines.append(f"{text} = {rhs:g}")
        return "\n".join(lines)


def link_equations(
    mass: float,
    inertia: float,
    a_g: complex,
    alpha: float,
    joints: Mapping[str, tuple[complex, int]],
    *,
    forces: Iterable[tuple[complex, complex]] = (),
    torque: float = 0.0,
    gravity: float = 0.0,
) -> LinkEquations:
    """Write the kinetic equations ``Σ F = m aG`` and ``Σ M_G = IG α`` of one link.

    Parameters
    ----------
    mass, inertia : float
        Mass and moment of inertia about the centre of mass G.
    a_g : complex
        Acceleration of G.
    alpha : float
        Angular acceleration (CCW positive).
    joints : mapping name → (R, sign)
        The unknown joint forces: ``R`` is the joint's position relative to G,
        and ``sign`` is +1 if the force named acts on this link, −1 if the link
        feels its opposite (the notes' ``F23 = −F32``).
    forces : iterable of (R, F)
        Known forces ``F`` at points ``R`` relative to G.
    torque : float
        Known couples on the link (sum, CCW positive).
    gravity : float
        ``g ≥ 0`` along −y (adds the weight at G).

    Examples
    --------
    The notes' final exam, problem 7 (α = 5 rad/s² clockwise):

    >>> eq = link_equations(8, 6, -4 - 5j, -5,
    ...                     {"F32": (-4 + 1j, -1), "F43": (1 - 6j, +1)},
    ...                     forces=[(-1 + 1.5j, 3 - 5j)], torque=12)
    >>> print(eq)
    -1*F32x + 1*F43x = -35
    -1*F32y + 1*F43y = -35
    1*F32x + 4*F32y + 6*F43x + 1*F43y = -42.5
    """
    m = nonnegative("mass", mass)
    i_g = nonnegative("inertia", inertia)
    a_g = _complex_scalar("a_g", a_g)
    alpha = finite_scalar("alpha", alpha)
    torque = finite_scalar("torque", torque)
    g = nonnegative("gravity", gravity)
    names: list[str] = []
    columns: list[list[float]] = []
    if not isinstance(joints, Mapping):
        raise InputError("joints", f"must map joint names to (R, sign), got {joints!r}"[:200])
    for name, spec in joints.items():
        try:
            r, sign = spec
        except (TypeError, ValueError):
            raise InputError(f"joints[{name!r}]", f"expected (R, sign), got {spec!r}") from None
        r = _complex_scalar(f"joints[{name!r}] R", r)
        sign = choice(f"joints[{name!r}] sign", sign, (1, -1))
        names += [f"{name}x", f"{name}y"]
        # ΣFx, ΣFy, ΣM (R × F = Rx Fy − Ry Fx)
        columns.append([sign, 0.0, -sign * r.imag])
        columns.append([0.0, sign, sign * r.real])
    fx = fy = 0.0
    moment = torque
    for n, item in enumerate(items("forces", forces, what="(R, F) pairs")):
        try:
            r, f = item
        except (TypeError, ValueError):
            raise InputError(f"forces[{n}]", f"expected (R, F), got {item!r}") from None
        r = _complex_scalar(f"forces[{n}] R", r)
        f = _complex_scalar(f"forces[{n}] F", f)
        fx += f.real
        fy += f.imag
        moment += r.real * f.imag - r.imag * f.real
    fy -= m * g
    matrix = np.array(columns, dtype=float).T.reshape(3, len(names))
    rhs = np.array([m * a_g.real - fx, m * a_g.imag - fy, i_g * alpha - moment])
    return LinkEquations(tuple(names), matrix, rhs)


# --------------------------------------------------------------------------------------
# The slider-crank (Norton sec. 11.6), with slider friction

#: Per-sample reasons of a slider-crank force solution (motion codes 0–2, then these).
SLIDER_REASONS: tuple[str, ...] = (
    "",
    "cannot be assembled at this input angle (outside the crank's range)",
    "toggle: the rod is perpendicular to the slide; the velocity solution and the "
    "force system are singular",
    "Coulomb friction: no unique normal force consistent with the sign of the "
    "friction (the slider wedges or jams)",
    "Coulomb friction indeterminate: the slider is at rest and not accelerating (stiction)",
)
_SC_JAM = 3
_SC_STICK = 4

_FRICTION_MODELS = ("smooth", "coulomb", "viscous")


@dataclass(frozen=True, eq=False)
class SliderCrankForces(Flagged):
    """Joint forces and driving torque of a slider-crank over a motion.

    Attributes
    ----------
    T12 : ndarray
        Driving torque of the ground on the crank (CCW positive).
    F12, F32, F43 : ndarray of complex
        Pin forces: ``F_ap`` acts on link *p* from link *a* (2 crank, 3 rod,
        4 slider).
    F14 : ndarray of complex
        Force of the guide (ground) on the slider: ``F14.imag`` is the normal
        force ``N``, ``F14.real`` the friction force along the slide.
    shaking_force : ndarray of complex
        ``F21 + F41``, the force of the moving links on the ground.
    shaking_moment : ndarray
        ``T21 + rB × F41`` about O2, with the guide force taken at the slider
        pin B (Norton's assumption that the slider's forces are concurrent).
    motion : SliderCrankMotion
        The kinematics used.
    status : ndarray of uint8
        0 where solved; otherwise an index into :data:`SLIDER_REASONS`.
    friction : str
        The friction model used.
    """

    REASONS = SLIDER_REASONS

    T12: np.ndarray
    F12: np.ndarray
    F32: np.ndarray
    F43: np.ndarray
    F14: np.ndarray
    shaking_force: np.ndarray
    shaking_moment: np.ndarray
    motion: SliderCrankMotion
    status: np.ndarray
    friction: str

    @property
    def shaking_torque(self) -> np.ndarray:
        """Norton's shaking torque ``Ts = T21 = −T12``: the reaction of the drive on the ground."""
        return -self.T12

    @property
    def N(self) -> np.ndarray:
        """Normal force of the guide on the slider (+y positive)."""
        return self.F14.imag

    def plot(self, ax: Any = None, degrees: bool = True):
        """Plot ``T12`` and the joint-force magnitudes against θ2 (matplotlib, lazily)."""
        return _plot_forces(self, ax, degrees)

    def normal_reversals(self) -> np.ndarray:
        """Indices ``i`` (of the flattened samples) where ``N`` changes sign between i and i+1.

        With Coulomb friction the friction force jumps there, and the slider
        knocks from one side of its guide to the other (piston slap).
        """
        n = np.ravel(self.N)
        s = np.sign(n)
        valid = np.isfinite(n[:-1]) & np.isfinite(n[1:])
        return np.flatnonzero(valid & (s[:-1] * s[1:] < 0))

    def to_pandas(self):
        """A :class:`pandas.DataFrame`, one row per sample (pandas imported lazily)."""
        import pandas as pd

        columns: dict[str, np.ndarray] = {
            "theta2": np.ravel(self.motion.theta2),
            "T12": np.ravel(self.T12),
        }
        for name in ("F12", "F32", "F43", "F14", "shaking_force"):
            value = np.ravel(getattr(self, name))
            columns[f"{name}_x"] = value.real
            columns[f"{name}_y"] = value.imag
            columns[f"{name}_mag"] = np.abs(value)
        columns["shaking_moment"] = np.ravel(self.shaking_moment)
        columns["ok"] = np.ravel(self.ok)
        columns["reason"] = np.ravel(self.reason)
        return pd.DataFrame(_labelled(columns, self.motion))

    def __len__(self) -> int:
        return int(np.size(self.T12))


def _labelled(columns: dict[str, np.ndarray], motion: Any) -> dict[str, np.ndarray]:
    """A forces table's columns named with units when the model has units (``T12 [N*m]``)."""
    from .units import columns as labelled

    system = getattr(motion, "units", None)
    if system is None or system.is_unit_free:
        return columns

    def kind(name: str) -> str | None:
        if name in ("ok", "reason"):
            return None
        if name.startswith("theta"):
            return "angle"
        if name in ("T12", "shaking_moment") or name.startswith("T"):
            return "torque"
        return "force"

    return labelled(system, [(k, kind(k), v) for k, v in columns.items()])


def slidercrank_forces(
    slidercrank: SliderCrank,
    motion: SliderCrankMotion,
    *,
    mass: Sequence[float],
    inertia: Sequence[float],
    cg: Sequence[complex],
    gravity: float = 0.0,
    load_force4: Any = 0.0,
    friction: str = "smooth",
    mu: float = 0.0,
    beta: float = 0.0,
    external_forces: Iterable[Any] = (),
    external_torques: Any = (),
) -> SliderCrankForces:
    """Newton–Euler forces for a solved motion of a slider-crank.

    See :func:`slidercrank_dynamics` for the parameters.

    Examples
    --------
    >>> from machdyn.slidercrank import SliderCrank
    >>> sc = SliderCrank(2.0, 6.0)
    >>> motion = sc.solve(np.radians([30, 60]), omega2=50.0)
    >>> f = slidercrank_forces(sc, motion, mass=(1, 1, 2), inertia=(0.1, 3), cg=(0, 3))
    >>> bool(f.ok.all())
    True
    """
    from .linkage import newton_euler  # on first use: machdyn.linkage is heavy to import

    instance("slidercrank", slidercrank, SliderCrank)
    instance("motion", motion, SliderCrankMotion, "a SliderCrankMotion (from SliderCrank.solve)")
    _check_slidercrank(slidercrank, motion)
    friction = choice("friction", friction, _FRICTION_MODELS)
    masses = _triple("mass", mass)
    inertias = tuple(_sequence("inertia", inertia, 2, "(IG2, IG3)"))
    cgs = tuple(_sequence("cg", cg, 2, "(c2, c3)"))
    units = unit_system(slidercrank.length_unit)
    m4 = nonnegative("mass m4", masses[2], units["mass"])
    props = link_properties(
        (*masses[:2], m4), (*inertias, 1.0 if m4 else 0.0), (*cgs, 0.0), slidercrank.length_unit
    )
    m2, m3, m4 = props.mass
    I2, I3, _ = props.inertia
    c2, c3, _ = props.cg
    g = nonnegative("gravity", gravity, units["acceleration"])
    mu = nonnegative("mu", mu, "")
    beta = nonnegative("beta", beta, units["damping"])
    loads = _point_loads(external_forces, units)
    torques = _torques(external_torques, units)
    load4 = finite_array("load_force4", load_force4, units["force"])
    _check_sample_shapes(np.shape(motion.status), loads, torques, ("load_force4", load4))
    a, b = slidercrank.a, slidercrank.b

    status = np.array(motion.status, dtype=np.uint8, copy=True)
    A, B = motion.A, motion.B
    e2 = A * (1.0 / a)
    u = B - A  # rod A → B
    e3 = u * (1.0 / b)  # the rod's frame: x from A toward B
    w2, w3 = motion.omega2, motion.omega3
    al2, al3 = motion.alpha2, motion.alpha3
    g2 = c2 * e2
    g3 = c3 * e3
    k2 = 1j * al2 - w2 * w2
    aG2 = g2 * k2
    aG3 = A * k2 + g3 * (1j * al3 - w3 * w3)
    d_dot, d_ddot = motion.d_dot, motion.d_ddot

    frame = {2: e2, 3: e3, 4: 1.0}
    Fe: dict[int, Any] = {2: 0.0, 3: 0.0, 4: load4 + 0j}
    Me: dict[int, Any] = {2: 0.0, 3: 0.0, 4: 0.0}
    if g:
        for k, mk, gk in ((2, m2, g2), (3, m3, g3)):
            if mk:
                Fe[k] = Fe[k] - 1j * (mk * g)
                Me[k] = Me[k] - (mk * g) * gk.real
        Fe[4] = Fe[4] - 1j * (m4 * g)
    for load in loads:
        arm = load.point * frame[load.link]
        Fe[load.link] = Fe[load.link] + load.force
        if load.link != 4:  # the slider does not turn: its moment goes to the guide
            Me[load.link] = Me[load.link] + _cross(arm, np.broadcast_to(load.force, np.shape(arm)))
    for link, torque in torques:
        if link != 4:
            Me[link] = Me[link] + torque

    # Known loads: the rod's (about A) and the block's (its own friction f0 of the viscous
    # model, load, weight, reversed inertia); the RRP dyad (rod, block) then the crank, in
    # closed form (machdyn.linkage.newton_euler), the guide along +x.
    f0 = -beta * d_dot if friction == "viscous" else 0.0 * d_dot
    P0 = (f0 - m4 * d_ddot) + Fe[4]
    M3 = Me[3] - (I3 * al3 + m3 * _cross(g3, aG3))
    F3 = Fe[3] - m3 * aG3
    if friction == "coulomb" and mu:
        slip = newton_euler._slip_sign(d_dot, d_ddot, (a + b) * (np.abs(w2) + np.abs(w3)))
        F23, F43, N, _, _, kappa, jammed = newton_euler.rrp_coulomb(
            u, 0.0, 1.0 + 0j, slip, mu, F3, M3, P0, 0.0
        )
        status[(status == OK) & jammed] = _SC_JAM
        status[(status == OK) & (slip == 0.0)] = _SC_STICK
    else:
        kappa = 0.0
        F23, F43, N, _, _ = newton_euler.rrp(u, 0.0, 1j + 0.0, F3, M3, P0, 0.0)
    F14 = (f0 + kappa * N) + 1j * N
    F32 = -F23
    F12, T12 = newton_euler.crank(
        Fe[2] - m2 * aG2 + F32, Me[2] - (I2 * al2 + m2 * _cross(g2, aG2)) + _cross(A, F32)
    )
    shape = np.shape(status)
    results = [np.broadcast_to(x, shape) for x in (T12, F12, F32, F43, F14)]
    bad = status != OK
    if bad.any():
        results = [np.where(bad, np.nan, x) for x in results]
    T12, F12, F32, F43, F14 = results
    return SliderCrankForces(
        T12=T12,
        F12=F12,
        F32=F32,
        F43=F43,
        F14=F14,
        shaking_force=-(F12 + F14),
        shaking_moment=-T12 - _cross(B, F14),
        motion=motion,
        status=status,
        friction=friction,
    )


def _sequence(field: str, value: Any, n: int, names: str) -> tuple[Any, ...]:
    return items(field, value, n, f"values {names}")


def slidercrank_dynamics(
    slidercrank: SliderCrank,
    theta2: Any,
    omega2: Any,
    alpha2: Any = 0.0,
    *,
    mass: Sequence[float],
    inertia: Sequence[float],
    cg: Sequence[complex],
    form: int = 1,
    gravity: float = 0.0,
    load_force4: Any = 0.0,
    friction: str = "smooth",
    mu: float = 0.0,
    beta: float = 0.0,
    external_forces: Iterable[Any] = (),
    external_torques: Any = (),
) -> SliderCrankForces:
    """Joint forces and driving torque of a slider-crank (Norton sec. 11.6).

    Links: 2 crank, 3 connecting rod, 4 slider on a guide along +x (the ground).
    Unknowns ``F12, F32, F43`` (2 components each), the guide's normal force
    ``N`` and ``T12``: the crank's and rod's three equations and the slider's
    two force equations (its moment equation only locates ``N`` along the
    guide and is not used: the slider's forces are taken concurrent at B).
    Torques on the slider, and the moments of point loads on it, are carried
    by the guide and do not change the other forces.

    Parameters
    ----------
    slidercrank : machdyn.slidercrank.SliderCrank
    theta2, omega2, alpha2 : array_like
        Crank angle (rad), angular velocity and acceleration.
    mass : (m2, m3, m4)
        Crank, rod and slider masses.
    inertia : (IG2, IG3)
        Crank and rod moments of inertia about their centres of mass.
    cg : (c2, c3)
        Centres of mass of crank (frame: origin O2, x toward A) and rod
        (origin A, x toward B), complex.
    form : {1, 2}
        As in :meth:`SliderCrank.solve`.
    gravity : float
        ``g ≥ 0`` along −y.
    load_force4 : array_like
        External force on the slider along the slide (+x), e.g. the gas force
        on a piston.
    friction : {"smooth", "coulomb", "viscous"}
        Friction of the guide on the slider: none; Coulomb ``F = −μ |N| sign(ḋ)``
        (the sign of ``N`` is found by solving both cases and keeping the
        consistent one; at rest the impending slip direction ``sign(d̈)`` is
        used); or viscous ``F = −β ḋ``.
    mu, beta : float
        Coulomb coefficient and viscous damping coefficient (≥ 0).
    external_forces, external_torques
        As in :func:`fourbar_dynamics`; links 2 (crank), 3 (rod), 4 (slider).

    Returns
    -------
    SliderCrankForces

    Examples
    --------
    A static piston load ``−F`` along x needs ``T12 ω2 = −F ḋ``:

    >>> from machdyn.slidercrank import SliderCrank
    >>> sc = SliderCrank(2.0, 6.0)
    >>> f = slidercrank_dynamics(sc, np.radians(60), 1.0, mass=(0, 0, 0),
    ...                          inertia=(0, 0), cg=(0, 0), load_force4=-100.0)
    >>> bool(np.isclose(f.T12, 100.0 * f.motion.d_dot))
    True
    """
    instance("slidercrank", slidercrank, SliderCrank)
    _check_input_shapes(theta2, omega2, alpha2)
    motion = slidercrank.solve(theta2, omega2, alpha2, form)
    return slidercrank_forces(
        slidercrank,
        motion,
        mass=mass,
        inertia=inertia,
        cg=cg,
        gravity=gravity,
        load_force4=load_force4,
        friction=friction,
        mu=mu,
        beta=beta,
        external_forces=external_forces,
        external_torques=external_torques,
    )
