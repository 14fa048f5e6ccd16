"""Flywheel sizing from a driving-torque curve (the notes' Table 11-1; Norton §11.11).

A machine whose linkage needs a fluctuating torque ``T12(θ)`` is driven by a
motor that supplies the average torque ``T_avg``; a flywheel on the input shaft
stores the difference. Over one cycle:

1. ``T_avg = (1/period) ∮ T12 dθ``.
2. The cycle splits into *lobes* where ``T12 − T_avg`` keeps one sign; each lobe's
   area ``ΔE = ∫ (T12 − T_avg) dθ`` is energy taken from the flywheel (positive
   lobe: ω falls) or given back to it (negative lobe: ω rises).
3. The accumulated sum ``E`` of the lobe areas is the energy drawn from the
   flywheel since the start of the table, so ω is smallest where ``E`` is
   largest and largest where ``E`` is smallest; ``ΔE = E_max − E_min``.
4. With the coefficient of fluctuation ``k = (ω_max − ω_min)/ω_avg`` and
   ``ω_avg ≈ (ω_max + ω_min)/2``, ``½ I (ω_max² − ω_min²) = ΔE`` gives the
   size estimate ``I = ΔE / (k ω_avg²)``.

Beyond the estimate, :func:`size_flywheel` solves the machine's equation of motion
with that flywheel, ``I ω dω/dθ = T_avg − T12(θ)`` (the motor torque is the
constant ``T_avg``; the linkage's own, varying inertia is neglected as in the
estimate), in its energy-integral form ``½ I ω² = ½ I ω₀² − E(θ)``, and picks
``ω₀`` so the *time* average of ω over the cycle (cycle angle / cycle time, what
a tachometer reads) equals ``omega_avg``. The achieved ``k`` is then close to the
requested one, with an error of order ``k²``.

The torque curve is taken as piecewise linear between the samples, so the lobe
areas, the zero crossings and ``E(θ)`` are exact for that curve: sampling may be
non-uniform, and a lobe that straddles the start of the cycle is one lobe.

What the estimate neglects
--------------------------
The sizing is the notes' (and Norton's) estimate, and it says so
(:attr:`FlywheelResult.neglects`):

* the linkage's own, *varying* inertia ``I(θ)``: its inertia torque is part of
  ``T12``, computed at the constant speed ``ω_avg``, and the flywheel alone is
  the energy store. A linkage that stores energy itself (a heavy coupler)
  changes the fluctuation, usually lowering it;
* the change of that inertia torque with the speed fluctuation it causes;
* the motor's speed–torque curve: the motor is taken to give exactly
  ``T_avg`` at every instant;
* ``ω_avg ≈ (ω_max + ω_min)/2`` in ``I = ΔE/(k ω_avg²)`` (an error of order
  ``k²``, which the ω(θ) above already removes).

:meth:`FlywheelResult.simulate` offers the honest number: the periodic steady
state of the *model itself* with the chosen flywheel (its ``I(θ)``, gravity,
springs and loads, by :func:`machdyn.simulate.steady_state`), driven by a
constant torque at the same average speed or by a motor's law, and its
simulated coefficient of fluctuation.

Examples
--------
The closed form ``T = T0 + A sin θ`` has two lobes of area ``±2A``:

>>> import numpy as np
>>> theta = np.linspace(0.0, 2 * np.pi, 3601)
>>> fw = size_flywheel(theta, 50.0 + 10.0 * np.sin(theta), omega_avg=100.0, k=0.02)
>>> round(fw.torque_avg, 6), round(fw.delta_e, 4), round(fw.inertia, 6)
(50.0, 20.0, 0.1)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._summary import Summarized
from ._validate import finite_array, finite_scalar, positive
from .errors import InputError

__all__ = ["DiscFlywheel", "FlywheelResult", "LobeTable", "disc_flywheel", "size_flywheel"]

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class LobeTable:
    """The notes' Table 11-1: lobes of ``T12 − T_avg`` in order over one cycle.

    Attributes
    ----------
    theta_from, theta_to : numpy.ndarray
        Start and end angle of each lobe, radians within the cycle (a lobe that
        straddles the start of the cycle ends at a smaller angle than it starts).
    area : numpy.ndarray
        ``ΔArea = ΔE = ∫ (T12 − T_avg) dθ`` over each lobe. Positive: energy lost
        by the flywheel (ω falls); negative: energy gained by the flywheel.
    energy : numpy.ndarray
        Accumulated sum ``E`` at the end of each lobe, from the start of the first.
        The last entry closes the cycle and is zero up to round-off.
    """

    theta_from: np.ndarray
    theta_to: np.ndarray
    area: np.ndarray
    energy: np.ndarray

    def __len__(self) -> int:
        return int(self.area.size)

    @property
    def omega_at_end(self) -> np.ndarray:
        """``"min"``, ``"max"`` or ``""`` per lobe: where ω has its extremes."""
        marks = np.full(len(self), "", dtype=object)
        if len(self):
            marks[int(np.argmax(self.energy))] = "min"
            marks[int(np.argmin(self.energy))] = "max"
        return marks

    def to_pandas(self) -> Any:
        """Return the table as a :class:`pandas.DataFrame` (angles in degrees).

        Sized from a machine file with units, the columns say them
        (``theta_from [deg]``, ``delta_E [N*m]``).
        """
        import pandas as pd

        from .units import columns, units_of

        system = units_of(self)
        if system is not None:
            spec = [("theta_from", "angle", self.theta_from), ("theta_to", "angle", self.theta_to)]
            spec += [("delta_E", "energy", self.area), ("E", "energy", self.energy)]
            spec += [("omega_at_end", None, self.omega_at_end)]
            return pd.DataFrame(
                columns(system, spec, degrees=True),
                index=pd.RangeIndex(1, len(self) + 1, name="lobe"),
            )
        return pd.DataFrame(
            {
                "theta_from_deg": np.degrees(self.theta_from),
                "theta_to_deg": np.degrees(self.theta_to),
                "delta_E": self.area,
                "E": self.energy,
                "omega_at_end": self.omega_at_end,
            },
            index=pd.RangeIndex(1, len(self) + 1, name="lobe"),
        )

    def __str__(self) -> str:
        header = (
            f"{'lobe':>4}  {'from (deg)':>10}  {'to (deg)':>10}  "
            f"{'ΔArea = ΔE':>14}  {'Accum. sum E':>14}  ω at end"
        )
        lines = [header]
        rows = zip(
            np.degrees(self.theta_from),
            np.degrees(self.theta_to),
            self.area,
            self.energy,
            self.omega_at_end,
            strict=True,
        )
        for number, (start, stop, area, energy, mark) in enumerate(rows, 1):
            mark = f"ω_{mark}" if mark else ""
            angles = f"{start:>10.2f}  {stop:>10.2f}"
            lines.append(f"{number:>4}  {angles}  {area:>+14.6g}  {energy:>+14.6g}  {mark}")
        return "\n".join(lines)


@dataclass(frozen=True)
class FlywheelResult(Summarized):
    """Result of :func:`size_flywheel`.

    Attributes
    ----------
    theta, torque : numpy.ndarray
        The cycle as analysed: the input samples, closed by ``θ₀ + period`` if
        the input did not include it.
    torque_avg : float
        ``T_avg``, the constant motor torque.
    lobes : LobeTable
        The table of lobe areas and accumulated energy (the notes' Table 11-1).
    delta_e : float
        ``ΔE = E_max − E_min`` (≥ 0), the energy the flywheel must swing.
    theta_omega_max, theta_omega_min : float
        Angles (radians) where ω is largest and smallest.
    omega_avg, k : float
        The requested average speed (rad per time unit) and coefficient of fluctuation.
    inertia : float
        The estimate ``I = ΔE / (k ω_avg²)`` (in torque units × time²).
    omega : numpy.ndarray
        ω(θ) at :attr:`theta` of the machine with that flywheel (steady periodic
        solution whose time average is ``omega_avg``).
    omega_max, omega_min : float
        Extremes of that ω(θ).
    k_achieved : float
        ``(ω_max − ω_min) / ω_avg`` of that solution.
    neglects : tuple of str
        What the estimate leaves out (see the module's notes); use
        :meth:`simulate` for the fluctuation with the linkage's own inertia.
    """

    theta: np.ndarray
    torque: np.ndarray
    torque_avg: float
    lobes: LobeTable
    delta_e: float
    theta_omega_max: float
    theta_omega_min: float
    omega_avg: float
    k: float
    inertia: float
    omega: np.ndarray
    omega_max: float
    omega_min: float
    k_achieved: float
    neglects: tuple[str, ...] = (
        "the linkage's own varying inertia I(θ): its inertia torque is taken at constant "
        "ω_avg as part of T12, and the flywheel alone stores the energy",
        "the change of the linkage's inertia torque with the speed fluctuation",
        "the motor's speed-torque curve: it gives exactly T_avg at every instant",
    )

    def simulate(self, model: Any, motor: Any = None, **options: Any) -> Any:
        """The periodic motion of ``model`` with this flywheel: the simulated fluctuation.

        The estimate neglects the linkage's own varying inertia (see
        :attr:`neglects`); this solves the model's equation of motion with it,
        the flywheel :attr:`inertia` on the input shaft, and either a constant
        torque at the same average speed ``omega_avg`` (``motor=None``: the
        sizing's own assumption) or a motor's law. Its ``.k`` is the honest
        coefficient of fluctuation to compare with :attr:`k`.

        Parameters
        ----------
        model : FourBar, SliderCrank or Linkage
            The machine whose ``T12`` was sized (its input must turn fully).
        motor : Motor, optional
            A motor law (:mod:`machdyn.simulate.motors`); then the speed is the
            motor's, not ``omega_avg``.
        **options
            The model's mass properties and loads (``mass=``, ``inertia=``,
            ``cg=``, ``gravity=`` …) as for :func:`machdyn.simulate`; ``flywheel=``
            adds drive-line inertia to this flywheel's.

        Returns
        -------
        machdyn.simulate.PeriodicMotion

        Examples
        --------
        Size a flywheel for the HW 6 crank-rocker at 30 rad/s and k = 0.05 from
        its inverse-dynamics torque, then simulate it:

        >>> import numpy as np
        >>> from machdyn import FourBar
        >>> fb = FourBar(0.08, 0.04, 0.07, 0.06)
        >>> m = dict(mass=(0.2, 0.3, 0.25), inertia=(3e-5, 1.2e-4, 7.5e-5),
        ...          cg=(0.02, 0.035, 0.03), gravity=9.81)
        >>> theta = np.radians(np.arange(0.0, 360.0, 0.5))
        >>> fw = size_flywheel(theta, fb.dynamics(theta, 30.0, **m).T12, omega_avg=30.0, k=0.05)
        >>> honest = fw.simulate(fb, **m)
        >>> round(fw.k_achieved, 4), round(honest.k, 4)     # the linkage's inertia helps
        (0.0501, 0.0473)
        """
        from .simulate.periodic import steady_state

        extra = options.pop("flywheel", 0.0)
        average = self.omega_avg if motor is None else None
        return steady_state(
            model, motor, omega_avg=average, flywheel=self.inertia + extra, **options
        )

    def to_pandas(self) -> Any:
        """Per-sample table: θ (deg), T12, T12 − T_avg and ω.

        Sized from a machine file with units, the columns say them
        (``theta [deg]``, ``T12 [N*m]``, ``omega [rpm]``).
        """
        import pandas as pd

        from .units import columns, units_of

        system = units_of(self)
        if system is not None:
            spec = [("theta", "angle", self.theta), ("T12", "torque", self.torque)]
            spec += [("T12_minus_T_avg", "torque", self.torque - self.torque_avg)]
            spec += [("omega", "angular_velocity", self.omega)]
            return pd.DataFrame(columns(system, spec, degrees=True))
        return pd.DataFrame(
            {
                "theta_deg": np.degrees(self.theta),
                "T12": self.torque,
                "T12_minus_T_avg": self.torque - self.torque_avg,
                "omega": self.omega,
            }
        )

    def plot(self, ax: Any = None) -> Any:
        """Plot T12 with T_avg and its lobes, and ω(θ) on a twin axis; return the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        deg = np.degrees(self.theta)
        ax.plot(deg, self.torque, label="T12")
        ax.axhline(self.torque_avg, color="k", lw=0.8, ls="--", label="T_avg")
        ax.fill_between(deg, self.torque, self.torque_avg, alpha=0.2)
        ax.set_xlabel("θ (deg)")
        ax.set_ylabel("torque")
        twin = ax.twinx()
        twin.plot(deg, self.omega, color="C3", label="ω with flywheel")
        twin.set_ylabel("ω")
        ax.legend(loc="upper left")
        twin.legend(loc="upper right")
        return ax


def size_flywheel(
    theta: Any, torque: Any, omega_avg: Any, k: float, *, period: float = TWO_PI
) -> FlywheelResult:
    """Size a flywheel from the driving torque over one cycle (Table 11-1 method).

    Parameters
    ----------
    theta : array_like
        Input angle samples over one cycle, radians, strictly increasing (any
        start, any spacing). Either ``[θ₀, θ₀ + period)`` or ``[θ₀, θ₀ + period]``
        with the last sample closing the cycle.
    torque : array_like
        ``T12`` at those angles: the torque the linkage requires on its input
        shaft (the load the flywheel and motor drive).
    omega_avg : float
        Average speed of the input shaft, rad per time unit (> 0). A pint
        quantity (e.g. rpm) is converted to rad/s.
    k : float
        Coefficient of fluctuation ``(ω_max − ω_min)/ω_avg``, in ``(0, 0.5)``;
        typical machinery uses 0.01–0.05.
    period : float, optional
        Angle of one cycle, radians (``4π`` for a four-stroke engine).

    Returns
    -------
    FlywheelResult
        ``.inertia``, ``.delta_e``, ``.lobes`` and the simulated ``.omega``.

    Raises
    ------
    InputError
        Shapes that differ, fewer than three samples, non-finite values, angles
        not increasing, spanning more than one period or too little of it (the
        gap to ``θ₀ + period`` may be at most twice the largest step: the curve
        is closed there by one straight segment), ``k`` out of range.

    Notes
    -----
    ``I`` is the total inertia on the input shaft; subtract what the motor
    and the crank already provide. The estimate neglects the linkage's own
    varying inertia and the motor's speed–torque curve (:attr:`FlywheelResult.neglects`);
    :meth:`FlywheelResult.simulate` solves the model's own equation of motion
    with the flywheel for the fluctuation it really gets. The notes' printed Table 11-1 closes at
    +1.54 instead of 0 from rounding of its areas; here ``T_avg`` is the exact
    mean of the given curve, so the lobes always close to round-off.

    Examples
    --------
    >>> import numpy as np
    >>> theta = np.radians(np.arange(0.0, 360.0, 1.0))
    >>> torque = 20.0 + 5.0 * np.sin(2 * theta)      # two load pulses per turn
    >>> fw = size_flywheel(theta, torque, omega_avg=50.0, k=0.05)
    >>> len(fw.lobes), round(fw.delta_e, 3)           # four lobes of ±5
    (4, 5.0)
    >>> abs(fw.k_achieved - 0.05) < 1e-3
    True
    """
    omega_avg = positive("omega_avg", omega_avg, "rad/s")
    k = finite_scalar("k", k)
    if not 1e-12 <= k < 0.5:  # below 1e-12 the flywheel (I ~ 1/k) outgrows double precision
        raise InputError(
            "k", f"coefficient of fluctuation must be in [1e-12, 0.5), typically 0.01-0.05; got {k}"
        )
    theta, torque, period = _closed_cycle(theta, torque, period)

    torque_avg = float(_integrate(theta, torque)[-1] / period)
    fine_theta, deviation, original = _split_at_crossings(theta, torque - torque_avg)
    energy = _integrate(fine_theta, deviation)  # E(θ) from θ₀, exact for the polyline
    lobes = _lobe_table(fine_theta, deviation, energy, period)

    if len(lobes):
        delta_e = float(np.max(lobes.energy) - np.min(lobes.energy))
        theta_omega_min = float(lobes.theta_to[np.argmax(lobes.energy)])
        theta_omega_max = float(lobes.theta_to[np.argmin(lobes.energy)])
    else:  # constant torque: nothing to smooth
        delta_e, theta_omega_min, theta_omega_max = 0.0, float(theta[0]), float(theta[0])
    inertia = delta_e / (k * omega_avg**2)

    if delta_e > 0.0:
        omega_fine = _periodic_speed(fine_theta, energy, inertia, omega_avg, period)
    else:
        omega_fine = np.full(fine_theta.shape, omega_avg)
    omega_max, omega_min = float(omega_fine.max()), float(omega_fine.min())

    return FlywheelResult(
        theta=theta,
        torque=torque,
        torque_avg=torque_avg,
        lobes=lobes,
        delta_e=delta_e,
        theta_omega_max=theta_omega_max,
        theta_omega_min=theta_omega_min,
        omega_avg=omega_avg,
        k=k,
        inertia=inertia,
        omega=omega_fine[original],
        omega_max=omega_max,
        omega_min=omega_min,
        k_achieved=(omega_max - omega_min) / omega_avg,
    )


# -- the cycle and its lobes ------------------------------------------------------


def _closed_cycle(theta: Any, torque: Any, period: Any) -> tuple[np.ndarray, np.ndarray, float]:
    """Validate the samples and return them closed by ``θ₀ + period``."""
    theta = finite_array("theta", theta, "rad")
    torque = finite_array("torque", torque)
    period = positive("period", period, "rad")
    if theta.ndim != 1 or torque.ndim != 1 or theta.shape != torque.shape:
        raise InputError(
            "torque",
            f"theta and torque must be 1-D of equal length; got shapes {theta.shape} "
            f"and {torque.shape}",
        )
    if theta.size < 3:
        raise InputError("theta", f"need at least 3 samples over the cycle, got {theta.size}")
    steps = np.diff(theta)
    if np.any(steps <= 0.0):
        index = int(np.flatnonzero(steps <= 0.0)[0]) + 1
        raise InputError("theta", f"must be strictly increasing; sample {index} is not")
    span = theta[-1] - theta[0]
    tolerance = 1e-9 * period
    if span > period + tolerance:
        raise InputError(
            "theta",
            f"spans {math.degrees(span):.6g} deg, more than one cycle "
            f"({math.degrees(period):.6g} deg); pass exactly one cycle "
            "(θ in radians here, in degrees in the CLI's CSV)",
        )
    if span >= period - tolerance:  # the last sample closes the cycle
        theta = theta.copy()
        theta[-1] = theta[0] + period
        return theta, torque, period
    gap = period - span  # closed below by one straight segment back to T(θ₀)
    if gap > 2.0 * float(steps.max()) * (1.0 + 1e-9):
        raise InputError(
            "theta",
            f"covers only {math.degrees(span):.4g}° of a {math.degrees(period):.4g}° cycle; "
            "pass one full cycle (θ in radians here, in degrees in the CLI's CSV)",
        )
    return np.append(theta, theta[0] + period), np.append(torque, torque[0]), period


def _integrate(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Cumulative trapezoid integral from ``x[0]`` (exact for a polyline)."""
    return np.concatenate(([0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(x))))


def _split_at_crossings(
    theta: np.ndarray, deviation: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Insert the zero crossings of the polyline as nodes.

    Returns the refined angles and deviations, and the indices of the original
    samples in the refined arrays. Deviations within round-off of zero are zero.
    """
    scale = max(float(np.max(np.abs(deviation))), np.finfo(float).tiny)
    deviation = np.where(np.abs(deviation) <= 1e-12 * scale, 0.0, deviation)
    left, right = deviation[:-1], deviation[1:]
    crossing = np.flatnonzero(left * right < 0.0)
    fraction = left[crossing] / (left[crossing] - right[crossing])
    theta_c = theta[crossing] + fraction * (theta[crossing + 1] - theta[crossing])
    fine_theta = np.insert(theta, crossing + 1, theta_c)
    fine_dev = np.insert(deviation, crossing + 1, 0.0)
    original = np.arange(theta.size) + np.searchsorted(crossing + 1, np.arange(theta.size), "right")
    return fine_theta, fine_dev, original


def _lobe_table(
    theta: np.ndarray, deviation: np.ndarray, energy: np.ndarray, period: float
) -> LobeTable:
    """Group the segments of one sign into lobes, merging across the cycle's start."""
    sign = np.sign(deviation[:-1] + deviation[1:])  # one sign per segment (no crossings left)
    signed = np.flatnonzero(sign)
    if signed.size == 0:
        empty = np.empty(0)
        return LobeTable(empty, empty, empty, empty)
    run_sign = sign[signed]
    # A lobe starts where the sign of the next non-flat segment differs from the previous one.
    starts = signed[1:][run_sign[1:] != run_sign[:-1]]
    if run_sign[0] != run_sign[-1]:
        starts = np.concatenate(([0], starts))  # the cycle's start is itself a boundary
    if starts.size == 0:  # cannot happen for a zero-mean curve beyond round-off
        empty = np.empty(0)
        return LobeTable(empty, empty, empty, empty)
    level = energy[starts]
    closing = energy[-1]  # the whole-cycle integral, zero up to round-off
    ends_level = np.append(level[1:], level[0] + closing)
    area = ends_level - level
    accumulated = np.cumsum(area)
    scale = float(np.max(np.abs(area)))
    accumulated[np.abs(accumulated) <= 1e-12 * scale] = 0.0  # the closing round-off
    theta_from = theta[starts]
    return LobeTable(
        theta_from=theta_from,
        theta_to=np.append(theta_from[1:], theta_from[0]),
        area=area,
        energy=accumulated,
    )


def _periodic_speed(
    theta: np.ndarray, energy: np.ndarray, inertia: float, omega_avg: float, period: float
) -> np.ndarray:
    """ω(θ) = √(ω₀² − 2E(θ)/I) with ω₀ chosen so the time average is ``omega_avg``."""
    from scipy.optimize import brentq

    drop = 2.0 * energy / inertia  # ω₀² − ω(θ)²
    steps = np.diff(theta)

    def mean_speed(c: float) -> float:
        omega = np.sqrt(np.maximum(c - drop, 0.0))
        with np.errstate(divide="ignore"):
            slowness = 1.0 / omega
        cycle_time = float(np.sum(0.5 * (slowness[1:] + slowness[:-1]) * steps))
        return period / cycle_time if math.isfinite(cycle_time) else 0.0

    # At c_low the fastest point runs at omega_avg, at c_high the slowest one does,
    # so the time average is bracketed (k < 0.5 keeps ω > 0 at c_low).
    c_low = omega_avg**2 + float(drop.min())
    c_high = omega_avg**2 + float(drop.max())
    c = brentq(lambda c: mean_speed(c) - omega_avg, c_low, c_high, xtol=1e-15 * c_high, rtol=1e-14)
    return np.sqrt(c - drop)


# -- geometry -----------------------------------------------------------------------


@dataclass(frozen=True)
class DiscFlywheel:
    """A flat disc (or rim with a central hole) flywheel of a given inertia.

    Attributes
    ----------
    outer_radius, inner_radius, thickness, density : float
        Geometry and material.
    mass, inertia : float
        ``m = ρ π t (r_o² − r_i²)`` and ``I = ½ m (r_o² + r_i²)``.
    """

    outer_radius: float
    inner_radius: float
    thickness: float
    density: float
    mass: float
    inertia: float


def disc_flywheel(
    inertia: float, density: float, thickness: float, inner_radius: float = 0.0
) -> DiscFlywheel:
    """Outer radius of a disc flywheel of given inertia, material and thickness.

    ``I = (π/2) ρ t (r_o⁴ − r_i⁴)`` (Norton eq. 11.20), solved for ``r_o``.
    Use consistent units (e.g. kg/m³, m → kg·m²).

    Parameters
    ----------
    inertia : float
        Required moment of inertia (> 0), e.g. :attr:`FlywheelResult.inertia`.
    density : float
        Material density ρ (> 0).
    thickness : float
        Axial thickness t (> 0).
    inner_radius : float, optional
        Radius of a central hole (≥ 0).

    Returns
    -------
    DiscFlywheel

    Examples
    --------
    A steel disc (7850 kg/m³) 40 mm thick holding 2 kg·m²:

    >>> fw = disc_flywheel(2.0, 7850.0, 0.04)
    >>> round(fw.outer_radius, 4), round(fw.mass, 2)
    (0.2523, 62.82)
    """
    inertia = positive("inertia", inertia)
    density = positive("density", density)
    thickness = positive("thickness", thickness)
    inner = finite_scalar("inner_radius", inner_radius)
    if inner < 0.0:
        raise InputError("inner_radius", f"must be zero or positive, got {inner}")
    outer = (inner**4 + 2.0 * inertia / (math.pi * density * thickness)) ** 0.25
    mass = density * math.pi * thickness * (outer**2 - inner**2)
    return DiscFlywheel(outer, inner, thickness, density, mass, inertia)
