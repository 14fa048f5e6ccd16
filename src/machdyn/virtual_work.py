"""Kinetostatics by virtual work (power), and mechanical advantage.

The second notes' "Simple kinetostatic force analysis": for a mechanism with
ideal (frictionless, time-independent) constraints the joint forces do no work,
so the power of all *external* forces and torques vanishes,

    Σ F_i · v_i + Σ T_j ω_j = 0,

and the one unknown input effort follows from the velocity solution alone,
without assembling the force matrix. Inertia enters as d'Alembert loads
``−m aG`` at each centre of mass and ``−IG α`` on each link ("dynamic forces can
be inserted into the virtual work equation"), which gives the dynamic input
torque; it equals the Newton–Euler ``T12`` of :mod:`machdyn.dynamics`.

Planar vectors are complex numbers ``x + j y``; a torque and an angular
velocity, or a force and a speed along one line, are real numbers. One formula
covers both: the power of an effort ``F`` at a rate ``v`` is ``Re(conj(F) v)``.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._flags import Flagged
from ._validate import TINY, choice, complex_array, finite_array, instance, items, nonnegative
from ._validate import broadcast as _broadcast
from .dynamics import (
    FORCE_REASONS,
    _check_input_shapes,
    _check_sample_shapes,
    _complex_scalar,
    _point_loads,
    _torques,
    link_properties,
    unit_system,
)
from .errors import InputError, SingularityError
from .fourbar import OK, TOGGLE, FourBar, FourBarMotion, velocities

__all__ = [
    "InputTorque",
    "fourbar_input_torque",
    "fourbar_mechanical_advantage",
    "mechanical_advantage",
    "power",
    "virtual_work",
]


#: What a pint quantity may measure, by the kind of argument.
_RATES = ("1 / [time]", "[length] / [time]")  # angular or linear velocity
_EFFORTS = ("[force]", "[force] * [length]")  # force or torque


def _as_complex(field: str, value: Any, dims: tuple[str, ...] = ()) -> np.ndarray:
    if hasattr(value, "magnitude") and hasattr(value, "to_base_units"):
        if dims and not any(value.check(d) for d in dims):
            raise InputError(
                field, f"must be a {' or '.join(dims)} quantity, got one in {value.units}"
            )
        value = value.to_base_units().magnitude  # pint: SI base units, so powers add up
    return complex_array(field, value)


def power(effort: Any, rate: Any) -> np.ndarray:
    """Power of a force at a velocity (complex ``F·v``) or of a torque at ``ω`` (real ``T ω``).

    Examples
    --------
    >>> float(power(3 + 4j, 2 - 1j))      # 3·2 + 4·(−1)
    2.0
    >>> float(power(-100.0, 2.0))          # a resisting torque
    -200.0
    """
    return _power(_as_complex("effort", effort, _EFFORTS), _as_complex("rate", rate, _RATES))


def _power(f: Any, v: Any) -> np.ndarray:
    """``Re(conj(f) v)`` without checks: NaN at flagged samples stays NaN (masked later)."""
    f, v = np.asarray(f), np.asarray(v)
    return f.real * v.real + f.imag * v.imag


def _effective_rate(input_rate: Any, direction: Any) -> np.ndarray:
    rate = _as_complex("input_rate", input_rate, _RATES)
    if direction is None:
        if np.any(rate.imag != 0.0):
            raise InputError(
                "direction",
                "the input rate is a planar velocity (complex); give the direction of "
                "the unknown input force as a complex number, e.g. direction=1j for +y",
            )
        return rate.real
    d = _as_complex("direction", direction, ("[]", "[length]"))
    size = np.abs(d)
    if np.any(size < TINY):
        raise InputError("direction", "must be a non-zero complex number (the force's line)")
    return power(d / size, rate)


def virtual_work(
    input_rate: Any,
    loads: Iterable[tuple[Any, Any]] = (),
    *,
    direction: Any = None,
) -> np.ndarray:
    """The input effort that balances external loads: ``E·v_in + Σ F·v + Σ T·ω = 0``.

    Parameters
    ----------
    input_rate : array_like
        The rate of the input: ``θ̇`` of an input link (the effort is a torque),
        ``ṙ`` of an actuator (a force along its axis), or the complex velocity
        of the input point together with ``direction``.
    loads : iterable of (effort, rate)
        External loads acting *on* the mechanism and the rates of their points
        or links: ``(F, v)`` with complex force and velocity, or ``(T, ω)``.
        Add inertia as d'Alembert loads ``(−m aG, vG)`` and ``(−IG α, ω)``.
    direction : complex, optional
        Line of action of the unknown input force when ``input_rate`` is a
        planar velocity; the result is the force component along it.

    Returns
    -------
    ndarray
        The input torque or force (along ``direction``) acting on the mechanism.

    Raises
    ------
    SingularityError
        Where the input does not move (``v_in* = 0``): a dead point, where no
        finite input effort balances a working load.

    Examples
    --------
    The second notes' loader (kinetostatics, example 1): 1000 kg at P with
    ``V_P = (8.896, 108.6)`` cm/s at ``θ̇2 = 0.5`` rad/s (velocities in m/s):

    >>> T12 = virtual_work(0.5, [(-1000 * 9.81j, 0.08896 + 1.086j)])
    >>> print(f"{float(T12):.0f} N·m")
    21307 N·m
    """
    rate = _effective_rate(input_rate, direction)
    named: dict[str, Any] = {"input_rate": rate}
    total: Any = 0.0
    for n, item in enumerate(items("loads", loads, what="(effort, rate) pairs")):
        try:
            effort, load_rate = item
        except (TypeError, ValueError):
            raise InputError(f"loads[{n}]", f"expected (effort, rate), got {item!r}") from None
        effort = _as_complex(f"loads[{n}] effort", effort, _EFFORTS)
        load_rate = _as_complex(f"loads[{n}] rate", load_rate, _RATES)
        named |= {f"loads[{n}] effort": effort, f"loads[{n}] rate": load_rate}
        _broadcast(**named)
        total = total + _power(effort, load_rate)
    total = np.broadcast_to(total, _broadcast(**named))
    dead = np.broadcast_to(np.abs(rate) < TINY, total.shape)  # below 1e-50: at rest
    if dead.any():
        index = int(np.flatnonzero(dead.ravel())[0])
        raise SingularityError(
            f"input_rate: the input does not move at sample {index} (v_in = 0, a dead point); "
            "the loads cannot be balanced by a finite input effort"
        )
    return -total / rate


def mechanical_advantage(input_rate: Any, output_rate: Any) -> np.ndarray:
    """Ideal mechanical advantage ``F_out / F_in = v_in* / v_out*`` (the notes, kinetostatics).

    ``v*`` are the velocity components along the input and output forces (or
    the angular velocities, for ``T_out / T_in = ω_in / ω_out``). Signed; ``inf``
    where the output is at a toggle (``v_out* = 0``).

    Examples
    --------
    The bike suspension: shock ``ṙ2 = 75`` cm/s, axle ``V_Py = 125`` cm/s: the
    axle force is 0.6 of the shock force.

    >>> float(mechanical_advantage(75.0, 125.0))
    0.6
    """
    v_in = _as_complex("input_rate", input_rate, _RATES)
    v_out = _as_complex("output_rate", output_rate, _RATES)
    _broadcast(input_rate=v_in, output_rate=v_out)
    if np.any(v_in.imag) or np.any(v_out.imag):
        raise InputError(
            "input_rate",
            "give the velocity components along the forces (real numbers), e.g. "
            "power(direction, velocity) for a unit direction",
        )
    v_in, v_out = v_in.real, v_out.real
    if np.any((v_in == 0.0) & (v_out == 0.0)):
        raise SingularityError("input_rate: input and output both at rest; the ratio is undefined")
    with np.errstate(divide="ignore", over="ignore"):  # a stopped output: ±inf (documented)
        return np.divide(v_in, v_out)


# --------------------------------------------------------------------------------------
# The four-bar's dynamic input torque by virtual work


class _Coefficients:
    """Kinematic coefficients of a four-bar pose: rates per unit input rate ``θ̇2``."""

    def __init__(self, fourbar: FourBar, motion: FourBarMotion) -> None:
        r1, r2, r3, r4 = fourbar.lengths
        A, B = motion.A, motion.B
        # ∂θ3/∂θ2, ∂θ4/∂θ2: the velocity solution at unit input speed
        h3, h4 = velocities(r2, r3, r4, motion.theta2, motion.theta3, motion.theta4, 1.0)
        self.e = {2: A / r2, 3: (B - A) / r3, 4: (B - r1) / r4}  # link directions
        self.h = {2: 1.0, 3: h3, 4: h4}
        self.finite = np.isfinite(h3) & np.isfinite(h4)
        self._origin_rate = {2: 0.0, 3: 1j * A, 4: 0.0}  # ∂(first joint)/∂θ2
        self._length = unit_system(fourbar.length_unit)["length"]

    def point_rate(self, link: int, point: complex) -> np.ndarray:
        """∂rP/∂θ2 of a point fixed in a link (given in the link's frame)."""
        return self._origin_rate[link] + 1j * self.h[link] * (point * self.e[link])

    def rate(self, spec: Any, field: str) -> np.ndarray:
        """Rate per unit θ̇2 of an input/output: a link (torque) or (link, point, direction)."""
        if isinstance(spec, (int, np.integer)):
            return np.asarray(self.h[choice(field, int(spec), (2, 3, 4))], dtype=float)
        try:
            link, point, direction = spec
        except (TypeError, ValueError):
            raise InputError(
                field, f"expected a link number or (link, point, direction), got {spec!r}"
            ) from None
        link = choice(f"{field} link", link, (2, 3, 4))
        point = _complex_scalar(f"{field} point", point, self._length)
        d = complex(_as_complex(f"{field} direction", direction))
        if d == 0:
            raise InputError(f"{field} direction", "must be a non-zero complex number")
        return _power(d / abs(d), self.point_rate(link, point))


def fourbar_mechanical_advantage(
    fourbar: FourBar,
    theta2: Any,
    input: Any = 2,
    output: Any = 4,
    form: int = 1,
    *,
    branch: int | None = None,
) -> np.ndarray:
    """Mechanical advantage of a four-bar between any input and output, by power.

    ``input`` and ``output`` are a link number (a torque on that link) or
    ``(link, point, direction)``: a force along the complex ``direction`` at a
    ``point`` given in the link's frame (origin at O2, A, O4; x toward A, B, B).
    The result is ``output effort / input effort = v_in* / v_out*`` (signed;
    ``inf`` where the output is stationary, e.g. at a toggle of links 2 and 3).

    Examples
    --------
    Torque on link 2 to torque on link 4 equals ``ω2/ω4``, the FourBar method:

    >>> fb = FourBar(8, 4, 7, 6)
    >>> ma = fourbar_mechanical_advantage(fb, np.radians(60))
    >>> bool(np.isclose(ma, fb.mechanical_advantage(np.radians(60))))
    True

    A torque on link 2 against a horizontal force at the coupler's mid-point
    (per unit torque, the force it can hold; negative: it pushes toward −x):

    >>> ma = fourbar_mechanical_advantage(fb, np.radians(90), 2, (3, 3.5, 1.0))
    >>> print(f"{float(ma):.4f}")
    -0.2572
    """
    instance("fourbar", fourbar, FourBar)
    motion = fourbar.solve(theta2, 1.0, 0.0, form, branch=branch)
    coef = _Coefficients(fourbar, motion)
    v_in = coef.rate(input, "input")
    v_out = coef.rate(output, "output")
    valid = motion.ok & coef.finite
    with np.errstate(divide="ignore", invalid="ignore"):
        ma = np.divide(v_in, v_out)
    return np.where(valid, ma, np.nan)


@dataclass(frozen=True, eq=False)
class InputTorque(Flagged):
    """The input torque of a four-bar found by virtual work.

    Attributes
    ----------
    T12 : ndarray
        Torque of the ground on link 2 (CCW positive).
    motion : FourBarMotion
        The kinematics used.
    status : ndarray of uint8
        0 where solved; otherwise an index into
        :data:`machdyn.dynamics.FORCE_REASONS`.
    """

    REASONS = FORCE_REASONS

    T12: np.ndarray
    motion: FourBarMotion
    status: np.ndarray

    def to_pandas(self):
        """A :class:`pandas.DataFrame` with ``theta2, T12, ok, reason`` (pandas lazily)."""
        import pandas as pd

        return pd.DataFrame(
            {
                "theta2": np.ravel(self.motion.theta2),
                "T12": np.ravel(self.T12),
                "ok": np.ravel(self.ok),
                "reason": np.ravel(self.reason),
            }
        )


def fourbar_input_torque(
    fourbar: FourBar,
    theta2: Any,
    omega2: Any = 0.0,
    alpha2: Any = 0.0,
    *,
    mass: Sequence[float] = (0.0, 0.0, 0.0),
    inertia: Sequence[float] = (0.0, 0.0, 0.0),
    cg: Sequence[complex] = (0.0, 0.0, 0.0),
    form: int = 1,
    gravity: float = 0.0,
    load_torque4: Any = 0.0,
    external_forces: Iterable[Any] = (),
    external_torques: Any = (),
    branch: int | None = None,
) -> InputTorque:
    """Input torque ``T12`` of a four-bar by virtual work, with d'Alembert inertia loads.

    Uses the *kinematic coefficients* (velocities per unit ``θ̇2``), so it also
    works at rest (``omega2 = 0``, pure statics with gravity and loads)::

        T12 = Σ (m aG − F_ext − m g)·∂rG/∂θ2 + Σ (IG α − T_ext) ∂θ/∂θ2
              − Σ F_P·∂rP/∂θ2,

    the sums over the links and their loads. Arguments as
    :func:`machdyn.dynamics.fourbar_dynamics` (masses default to zero: the
    kinetostatic torque).

    Examples
    --------
    A resisting torque of 10 on the output of the notes' HW 6 crank-rocker at
    θ2 = 60° (ω4/ω2 there is about −0.11):

    >>> fb = FourBar(8, 4, 7, 6)
    >>> vw = fourbar_input_torque(fb, np.radians(60), load_torque4=-10.0)
    >>> m = fb.solve(np.radians(60), omega2=1.0)
    >>> bool(np.isclose(vw.T12, 10.0 * m.omega4))
    True
    """
    instance("fourbar", fourbar, FourBar)
    units = unit_system(fourbar.length_unit)
    props = link_properties(mass, inertia, cg, fourbar.length_unit)
    g = nonnegative("gravity", gravity, units["acceleration"])
    loads = _point_loads(external_forces, units)
    torques = list(_torques(external_torques, units))
    load4 = finite_array("load_torque4", load_torque4, units["torque"])
    _check_input_shapes(theta2, omega2, alpha2)
    motion = fourbar.solve(theta2, omega2, alpha2, form, branch=branch)
    _check_sample_shapes(np.shape(motion.status), loads, torques, ("load_torque4", load4))
    coef = _Coefficients(fourbar, motion)
    e, h, point_rate = coef.e, coef.h, coef.point_rate
    A = motion.A
    omega = {2: motion.omega2, 3: motion.omega3, 4: motion.omega4}
    alpha = {2: motion.alpha2, 3: motion.alpha3, 4: motion.alpha4}
    accel_origin = {2: 0.0, 3: A * (1j * motion.alpha2 - motion.omega2**2), 4: 0.0}

    # Σ of (applied + inertia) loads · coefficients; T12 balances it. The coefficients are
    # NaN at flagged samples (unassemblable, toggle): unchecked _power, masked below.
    generalized = 0.0
    for link, m, i_g, c in zip((2, 3, 4), props.mass, props.inertia, props.cg, strict=True):
        if m:
            a_g = accel_origin[link] + (1j * alpha[link] - omega[link] ** 2) * (c * e[link])
            generalized = generalized + _power(-m * a_g - 1j * m * g, point_rate(link, c))
        if i_g:
            generalized = generalized - i_g * alpha[link] * h[link]
    for load in loads:
        generalized = generalized + _power(load.force, point_rate(load.link, load.point))
    for link, torque in torques:
        generalized = generalized + torque * h[link]
    generalized = generalized + load4 * h[4]

    status = np.array(motion.status, dtype=np.uint8, copy=True)
    status[(status == OK) & ~coef.finite] = TOGGLE
    T12 = np.broadcast_to(-generalized, status.shape)
    T12 = np.where(status == OK, T12, np.nan)
    return InputTorque(T12=T12, motion=motion, status=status)
