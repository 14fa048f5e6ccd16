"""Motors for :func:`machdyn.simulate`: constant, DC, induction, or any torque function.

A motor gives the torque on its own shaft as a function of time ``t``, the
input's position ``theta`` and the *motor* speed. Between the motor and the
input link sits an ideal gearbox of ``ratio`` motor turns per input turn
(1 for a direct drive): the input sees ``ratio × T_motor(ratio × ω)`` and the
reflected rotor inertia ``ratio² × inertia`` (Norton, *Design of Machinery*,
§2.19 and §10.8: speed–torque curves of DC and AC motors).

Every motor takes ``off_at``: from that time on it gives no torque (a
coast-down after a run); the simulation splits its integration there, so the
switch is exact.

Examples
--------
A DC motor with a stall torque of 20 N·m and a no-load speed of 30 rad/s gives
half its stall torque at half its no-load speed:

>>> m = DCMotor(stall_torque=20.0, no_load_speed=30.0)
>>> float(m(0.0, 0.0, 15.0))
10.0
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from .._validate import (
    LIMIT,
    complex_array,
    finite_array,
    finite_scalar,
    in_range,
    nonnegative,
    positive,
)
from ..errors import InputError, ModelError

__all__ = ["ConstantTorque", "DCMotor", "InductionMotor", "Motor", "TorqueFunction"]


class Motor:
    """Base class: a torque source on the input shaft, through an ideal gearbox.

    Subclasses implement ``_law(t, theta, omega_motor)``, the torque on the
    motor's own shaft at the motor speed (:meth:`shaft_torque` is that law with
    its arguments checked). Calling the motor, ``motor(t, theta, omega)``, gives
    the torque on the *input* (``ratio × law(t, theta, ratio × omega)``, zero
    from ``off_at`` on); both broadcast over arrays.

    Parameters
    ----------
    inertia : float
        Rotor inertia (≥ 0), on the motor shaft.
    ratio : float
        Motor turns per input turn (> 0); 1 for a direct drive.
    off_at : float, optional
        Time from which the motor gives no torque (switched off).
    """

    def __init__(self, *, inertia: float = 0.0, ratio: float = 1.0, off_at: Any = None) -> None:
        self.inertia = nonnegative("inertia", inertia)
        self.ratio = in_range("ratio", ratio, 1e-6, 1e6)
        self.off_at = None if off_at is None else finite_scalar("off_at", off_at, "second")

    @property
    def reflected_inertia(self) -> float:
        """``ratio² × inertia``: the rotor's inertia seen on the input shaft."""
        return self.ratio**2 * self.inertia

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Times where the torque jumps (the integration is split there)."""
        return () if self.off_at is None else (self.off_at,)

    def _law(self, t: Any, theta: Any, omega_motor: Any) -> Any:
        raise ModelError(f"{type(self).__name__} gives no torque law: subclass Motor with _law()")

    def shaft_torque(self, t: Any, theta: Any, omega_motor: Any) -> Any:
        """Torque on the motor's own shaft at time ``t``, input angle ``theta``, motor speed.

        Examples
        --------
        >>> DCMotor(2.0, 100.0).shaft_torque(0.0, 0.0, [0.0, 50.0]).tolist()
        [2.0, 1.0]
        """
        t, theta, omega_motor = _checked(t, theta, omega_motor, "omega_motor")
        return self._law(t, theta, omega_motor)

    def __call__(self, t: Any, theta: Any, omega: Any) -> Any:
        """Torque on the input at time ``t``, input angle ``theta`` and input speed ``omega``."""
        if not (type(t) is float and type(theta) is float and type(omega) is float):
            t, theta, omega = _checked(t, theta, omega, "omega")
        elif not (abs(t) <= LIMIT and abs(theta) <= LIMIT and abs(omega) <= LIMIT):
            _checked(t, theta, omega, "omega")  # raises: NaN or beyond the range
        torque = self.ratio * self._law(t, theta, self.ratio * omega)
        if self.off_at is None:
            return torque
        if np.ndim(t) == 0 and np.ndim(torque) == 0:
            return 0.0 if t >= self.off_at else torque
        return np.where(np.asarray(t) >= self.off_at, 0.0, torque)

    def _suffix(self) -> str:
        parts = []
        if self.inertia:
            parts.append(f"inertia={self.inertia:g}")
        if self.ratio != 1.0:
            parts.append(f"ratio={self.ratio:g}")
        if self.off_at is not None:
            parts.append(f"off_at={self.off_at:g}")
        return "".join(", " + p for p in parts)


class ConstantTorque(Motor):
    """A constant torque ``T`` (a weight on a drum, an idealised motor).

    Examples
    --------
    >>> float(ConstantTorque(5.0, ratio=2.0)(0.0, 0.0, 100.0))   # 2 × 5 on the input
    10.0
    """

    def __init__(self, torque: float, **options: Any) -> None:
        super().__init__(**options)
        self.torque = finite_scalar("torque", torque)

    def _law(self, t: Any, theta: Any, omega_motor: Any) -> Any:
        return self.torque + 0.0 * omega_motor

    def __repr__(self) -> str:
        return f"ConstantTorque({self.torque:g}{self._suffix()})"


class DCMotor(Motor):
    """A permanent-magnet (shunt) DC motor: the straight speed–torque line.

    ``T = T_stall (1 − ω_m / ω_no_load)`` (Norton fig. 2-32): the stall torque at
    standstill, zero at the no-load speed, a brake beyond it.

    Parameters
    ----------
    stall_torque : float
        Torque at zero speed (> 0; give a negative ``no_load_speed`` and
        ``stall_torque`` for a motor turning the other way).
    no_load_speed : float
        Speed at zero torque, rad/s (pint rpm accepted), same sign as the torque.

    Examples
    --------
    >>> m = DCMotor.from_electrical(voltage=24.0, resistance=2.0, kt=0.5)
    >>> round(m.stall_torque, 6), round(m.no_load_speed, 6)
    (6.0, 48.0)
    """

    def __init__(self, stall_torque: float, no_load_speed: Any, **options: Any) -> None:
        super().__init__(**options)
        self.stall_torque = finite_scalar("stall_torque", stall_torque)
        self.no_load_speed = finite_scalar("no_load_speed", no_load_speed, "radian / second")
        if self.stall_torque == 0.0 or self.no_load_speed == 0.0:
            raise InputError("stall_torque", "stall torque and no-load speed must be non-zero")
        if (self.stall_torque > 0.0) != (self.no_load_speed > 0.0):
            raise InputError(
                "no_load_speed",
                "must have the sign of stall_torque (the motor runs the way it pushes)",
            )

    @classmethod
    def from_electrical(
        cls, voltage: float, resistance: float, kt: float, ke: float | None = None, **options: Any
    ) -> DCMotor:
        """From the supply voltage ``V``, armature resistance ``R`` and constants ``kt``, ``ke``.

        ``T = kt (V − ke ω) / R``: stall torque ``kt V / R``, no-load speed
        ``V / ke`` (``ke = kt`` in SI units, the default).
        """
        voltage = finite_scalar("voltage", voltage, "volt")
        if voltage == 0.0:
            raise InputError("voltage", "must be non-zero (the motor's supply)")
        resistance = positive("resistance", resistance, "ohm")
        kt = positive("kt", kt)
        ke = kt if ke is None else positive("ke", ke)
        return cls(kt * voltage / resistance, voltage / ke, **options)

    def _law(self, t: Any, theta: Any, omega_motor: Any) -> Any:
        return self.stall_torque * (1.0 - omega_motor / self.no_load_speed)

    def __repr__(self) -> str:
        return (
            f"DCMotor(stall_torque={self.stall_torque:g}, "
            f"no_load_speed={self.no_load_speed:g}{self._suffix()})"
        )


class InductionMotor(Motor):
    """A three-phase induction (AC) motor by Kloss's formula.

    With the slip ``s = 1 − ω_m / ω_sync``::

        T = 2 T_b s s_b / (s² + s_b²)

    the breakdown (pull-out) torque ``T_b`` at the breakdown slip ``s_b``; the
    starting torque is ``2 T_b s_b / (1 + s_b²)``; above synchronous speed it
    brakes (a generator). Norton fig. 2-32's curve, in the form of the standard
    steady-state equivalent circuit with the stator resistance neglected.

    Parameters
    ----------
    synchronous_speed : float
        ``ω_sync = 2π f / pole pairs`` in rad/s (pint rpm accepted), > 0.
    breakdown_torque : float
        ``T_b`` (> 0).
    breakdown_slip : float
        ``s_b`` in (0, 1]; typically 0.1–0.3.

    Examples
    --------
    A 4-pole 50 Hz motor (1500 rpm synchronous) rated 26.5 N·m at 1450 rpm
    with a breakdown torque 2.5 times the rated one:

    >>> m = InductionMotor.from_rating(26.5, rated_speed=151.84, synchronous_speed=157.08,
    ...                                breakdown_factor=2.5)
    >>> round(float(m(0.0, 0.0, 151.84)), 3), round(m.breakdown_slip, 4)
    (26.5, 0.1598)
    """

    def __init__(
        self, synchronous_speed: Any, breakdown_torque: float, breakdown_slip: float, **options: Any
    ) -> None:
        super().__init__(**options)
        self.synchronous_speed = positive("synchronous_speed", synchronous_speed, "radian / second")
        self.breakdown_torque = positive("breakdown_torque", breakdown_torque)
        s_b = positive("breakdown_slip", breakdown_slip)
        if s_b > 1.0:
            raise InputError("breakdown_slip", f"must be in (0, 1], typically 0.1-0.3; got {s_b}")
        self.breakdown_slip = s_b

    @classmethod
    def from_rating(
        cls,
        rated_torque: float,
        rated_speed: Any,
        synchronous_speed: Any,
        breakdown_factor: float = 2.5,
        **options: Any,
    ) -> InductionMotor:
        """From the nameplate: rated torque and speed, synchronous speed, ``T_b / T_rated``.

        Kloss's formula through the rated point gives the breakdown slip
        ``s_b = s_r (λ + √(λ² − 1))`` with ``λ = T_b / T_rated`` and the rated slip
        ``s_r = 1 − ω_rated / ω_sync``.
        """
        rated_torque = positive("rated_torque", rated_torque)
        w_s = positive("synchronous_speed", synchronous_speed, "radian / second")
        w_r = positive("rated_speed", rated_speed, "radian / second")
        if w_r >= w_s:
            raise InputError("rated_speed", f"must be below the synchronous speed {w_s:g} rad/s")
        lam = finite_scalar("breakdown_factor", breakdown_factor)
        if lam <= 1.0:
            raise InputError(
                "breakdown_factor", f"T_b / T_rated must exceed 1 (typically 2-3); got {lam}"
            )
        s_r = 1.0 - w_r / w_s
        s_b = min(1.0, s_r * (lam + math.sqrt(lam * lam - 1.0)))
        return cls(w_s, lam * rated_torque, s_b, **options)

    @property
    def starting_torque(self) -> float:
        """Torque at standstill, ``2 T_b s_b / (1 + s_b²)``."""
        s_b = self.breakdown_slip
        return 2.0 * self.breakdown_torque * s_b / (1.0 + s_b * s_b)

    def _law(self, t: Any, theta: Any, omega_motor: Any) -> Any:
        s = 1.0 - omega_motor / self.synchronous_speed
        s_b = self.breakdown_slip
        return 2.0 * self.breakdown_torque * s * s_b / (s * s + s_b * s_b)

    def __repr__(self) -> str:
        return (
            f"InductionMotor(synchronous_speed={self.synchronous_speed:g}, "
            f"breakdown_torque={self.breakdown_torque:g}, "
            f"breakdown_slip={self.breakdown_slip:g}{self._suffix()})"
        )


class TorqueFunction(Motor):
    """Any torque law ``func(t, theta, omega_motor)`` (time, input angle, motor speed).

    The function is called with floats during the integration and with arrays
    when the results are assembled; write it with NumPy (``np.where`` rather
    than ``if``) or it is called once per sample. If it jumps at known times,
    give them as ``breakpoints`` (the integration is split there).

    Examples
    --------
    A torque that ramps up over the first second:

    >>> m = TorqueFunction(lambda t, theta, omega: 10.0 * np.minimum(t, 1.0), breakpoints=[1.0])
    >>> float(m(0.5, 0.0, 0.0)), m.breakpoints
    (5.0, (1.0,))
    """

    def __init__(self, func: Callable[..., Any], *, breakpoints: Any = (), **options: Any) -> None:
        super().__init__(**options)
        if not callable(func):
            raise InputError("motor", f"a torque function must be callable, got {func!r}")
        self.func = func
        self._breaks = _times("breakpoints", breakpoints)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """The given jump times (and ``off_at``)."""
        return self._breaks + super().breakpoints

    def _law(self, t: Any, theta: Any, omega_motor: Any) -> Any:
        return call_law(self.func, t, theta, omega_motor, "motor")

    def __repr__(self) -> str:
        return f"TorqueFunction({getattr(self.func, '__name__', 'func')}{self._suffix()})"


def call_law(func: Callable[..., Any], t: Any, x: Any, v: Any, field: str) -> Any:
    """Call a user law ``func(t, x, v)``; with arrays, fall back to one call per sample.

    The result must be a finite number (real, or complex for a force), or an
    array of them that broadcasts with the inputs.
    """
    scalar = np.ndim(t) == 0 and np.ndim(x) == 0 and np.ndim(v) == 0
    try:
        out = func(t, x, v)
    except Exception as exc:
        if scalar:
            raise InputError(field, f"the function raised {type(exc).__name__}: {exc}") from exc
        out = None
    if scalar:
        if type(out) is float and abs(out) <= LIMIT:  # the integrator's fast path
            return out
        return _law_value(field, out, ())
    shape = np.broadcast_shapes(np.shape(t), np.shape(x), np.shape(v))
    if out is None or np.shape(out) not in (shape, ()):
        tb, xb, vb = (np.broadcast_to(a, shape) for a in (t, x, v))
        rows = zip(tb.ravel(), xb.ravel(), vb.ravel(), strict=True)
        out = [_law_value(field, func(ti, xi, vi), ()) for ti, xi, vi in rows]
    return _law_value(field, out, shape)


def _law_value(field: str, out: Any, shape: tuple[int, ...]) -> Any:
    """A law's value checked: finite, real unless complex, broadcast to ``shape``."""
    arr = complex_array(field, out)
    if np.shape(arr) not in (shape, ()):
        raise InputError(field, f"the function returned shape {np.shape(arr)}, not {shape}")
    if not np.any(arr.imag):
        arr = arr.real
    if not shape:
        return arr.item()
    return np.broadcast_to(arr, shape)


def as_motor(motor: Any) -> Motor | None:
    """A :class:`Motor` from ``None``, a number (constant torque), a callable or a Motor."""
    if motor is None or isinstance(motor, Motor):
        return motor
    if callable(motor) and not isinstance(motor, type):
        return TorqueFunction(motor)
    if isinstance(motor, int | float | np.floating | np.integer) and not isinstance(
        motor, bool | np.bool_
    ):
        return ConstantTorque(finite_scalar("motor", motor))
    raise InputError(
        "motor",
        f"give a Motor (DCMotor, InductionMotor, ConstantTorque, TorqueFunction), a constant "
        f"torque or a function f(t, theta, omega); got {type(motor).__name__}",
    )


def _checked(t: Any, theta: Any, omega: Any, name: str) -> tuple[Any, Any, Any]:
    """Time, angle and speed as finite floats or arrays (each as given: scalar or array)."""
    out = []
    for field, value, unit in (("t", t, "second"), ("theta", theta, "radian"), (name, omega, None)):
        arr = finite_array(field, value, unit)
        out.append(float(arr) if arr.ndim == 0 else arr)
    return out[0], out[1], out[2]


def _times(field: str, values: Any) -> tuple[float, ...]:
    """A sequence of finite times (a load's or motor's switching times)."""
    from ._setup import listed

    arr = finite_array(field, listed(field, values, "times"), "second")
    if arr.ndim != 1:
        raise InputError(field, f"must be a flat sequence of times, got shape {arr.shape}")
    return tuple(float(x) for x in arr)
