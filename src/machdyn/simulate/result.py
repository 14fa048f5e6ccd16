"""The result of :func:`machdyn.simulate`: the motion in time, its events and energies."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._summary import Summarized

__all__ = ["Energy", "Event", "Simulation", "SteadyState"]


@dataclass(frozen=True)
class Event:
    """Something that happened during a simulation.

    Attributes
    ----------
    kind : str
        ``"stall"`` (the motor could not keep it moving: it stopped and would
        roll back), ``"reversal"`` (the speed passed through zero), ``"rest"``
        (it stopped in equilibrium), ``"toggle"`` (it reached a toggle or the end
        of the input's range), ``"steady"`` (periodic steady state reached),
        ``"breakpoint"`` (a motor or load switched).
    t, theta, omega : float
        Time, input coordinate and speed at the event.
    message : str
        What happened, in words (with the torque deficit of a stall).
    deficit : float
        For a stall: the effort the load needs minus what the motor gives
        at zero speed (> 0); otherwise 0.
    given, need : float
        For a stall: the motor's effort at zero speed and the effort that
        would hold the load there; otherwise 0.
    """

    kind: str
    t: float
    theta: float
    omega: float
    message: str
    deficit: float = 0.0
    given: float = 0.0
    need: float = 0.0

    def __str__(self) -> str:
        return f"t = {self.t:.6g}: {self.kind}: {self.message}"


@dataclass(frozen=True)
class SteadyState:
    """The last full cycle of a crank's motion.

    Attributes
    ----------
    cycle_time : float
        Time of the last cycle (one period of the input).
    omega_avg : float
        ``period / cycle_time``: the time average of ω over the cycle.
    omega_max, omega_min : float
        Extremes of ω over the cycle.
    theta_omega_max, theta_omega_min : float
        Input angles (within the cycle) where they occur.
    k : float
        Coefficient of speed fluctuation ``(ω_max − ω_min) / ω_avg``.
    converged : float
        Relative change of the cycle time from the cycle before (small in a
        steady state).
    """

    cycle_time: float
    omega_avg: float
    omega_max: float
    omega_min: float
    theta_omega_max: float
    theta_omega_min: float
    k: float
    converged: float


@dataclass(frozen=True)
class Energy(Summarized):
    """Energies and works along the simulation, from ``t = 0`` (arrays at the samples).

    The balance ``kinetic − kinetic[0] = motor + loads + model + damping``
    holds to the integrator's tolerance (``residual``): ``model`` is the work
    of the model's own position-dependent loads (gravity, springs, constant
    loads: minus their potential energy change), ``damping`` that of its
    dampers and viscous friction (≤ 0), ``loads`` that of the simulation's loads.
    """

    kinetic: np.ndarray
    motor: np.ndarray
    loads: np.ndarray
    model: np.ndarray
    damping: np.ndarray

    @property
    def residual(self) -> np.ndarray:
        """``ΔKE − (motor + loads + model + damping)``."""
        return (self.kinetic - self.kinetic[0]) - (
            self.motor + self.loads + self.model + self.damping
        )


@dataclass(frozen=True, eq=False)
class Simulation(Summarized):
    """The motion a motor and loads give a one-degree-of-freedom model, in time.

    Attributes
    ----------
    t : ndarray
        Sample times (uniform, from 0 to the end).
    theta, omega, alpha : ndarray
        Input coordinate (``theta2`` or the driver's value; not wrapped), its
        speed and acceleration at the samples.
    motor_torque : ndarray
        The motor's effort on the input at the samples (after the gearbox).
    inertia : ndarray
        Generalised inertia ``I(θ)`` of the model alone at the samples (add
        ``added_inertia`` for the shaft's total).
    added_inertia : float
        Flywheel, drive line and reflected rotor inertia on the input.
    energy : Energy
        Kinetic energy and the works, for the balance.
    events : tuple of Event
        Everything that happened, in order.
    status : str
        Why it ended: ``"t_end"``, ``"turns"``, ``"steady"``, or an event kind.
    message : str
        The same, in words.
    cycles : ndarray
        Times at which a crank completed each turn (from the start angle).
    steady : SteadyState or None
        The last full cycle (None before a crank's first two turns).
    coordinate : str
        Name of the input coordinate (``"theta2"`` or the driver).
    angular : bool
        True when it is an angle (radians; its effort a torque).
    table : str
        How the coefficients were evaluated (cells and measured interpolation
        error, or exact).
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    motor_torque: np.ndarray
    inertia: np.ndarray
    added_inertia: float
    energy: Energy
    events: tuple[Event, ...]
    status: str
    message: str
    cycles: np.ndarray
    steady: SteadyState | None
    coordinate: str
    angular: bool
    table: str
    _runner: Any = field(repr=False, default=None)

    def __len__(self) -> int:
        return int(self.t.size)

    def at(self, t: Any) -> tuple[np.ndarray, np.ndarray]:
        """``(theta, omega)`` at any times within the simulation (dense output).

        Times outside ``[0, t[-1]]`` are refused.
        """
        from .._validate import finite_array
        from ..errors import InputError

        t = finite_array("t", t, "second")
        if t.size and (t.min() < self.t[0] or t.max() > self.t[-1]):
            raise InputError("t", f"must lie within the simulated [0, {self.t[-1]:.6g}] s")
        if not self._runner.segments:  # it never moved
            return np.full(t.shape, self.theta[0]), np.full(t.shape, self.omega[0])
        return self._runner.state(t)

    def forces(self) -> Any:
        """The model's force analysis along the simulated motion (pin forces, ``T12``).

        The model's own force result (``FourBarForces``, ``SliderCrankForces``
        or ``LinkageForces``) at every sample, with the simulation's loads
        included. Its driver effort is what the shaft delivers to the input
        link: the motor's torque less the added inertia's ``I_add α``.
        """
        return self._runner.forces(self.t, self.theta, self.omega, self.alpha)

    def to_pandas(self) -> Any:
        """One row per sample: ``t``, θ, ω, α, motor torque, energies (pandas lazily)."""
        import pandas as pd

        from ..units import columns, units_of

        name = self.coordinate
        system = units_of(self)  # a model with units: "t [s]", "theta2_dot [rpm]", ...
        if system is not None:
            kinds = ("angle", "angular_velocity", "angular_acceleration", "torque")
            if not self.angular:
                kinds = ("length", "velocity", "acceleration", "force")
            spec = [("t", "time", self.t), (name, kinds[0], self.theta)]
            spec += [(f"{name}_dot", kinds[1], self.omega), (f"{name}_ddot", kinds[2], self.alpha)]
            spec += [("motor", kinds[3], self.motor_torque)]
            spec += [("kinetic_energy", "energy", self.energy.kinetic)]
            spec += [("motor_work", "energy", self.energy.motor)]
            return pd.DataFrame(columns(system, spec))
        return pd.DataFrame(
            {
                "t": self.t,
                name: self.theta,
                f"{name}_dot": self.omega,
                f"{name}_ddot": self.alpha,
                "motor": self.motor_torque,
                "kinetic_energy": self.energy.kinetic,
                "motor_work": self.energy.motor,
            }
        )

    def plot(self, fig: Any = None, units: Any = None, title: str | None = None) -> Any:
        """Angle, speed and motor effort against time (:mod:`machdyn.draw.simulation`).

        ``units``: a machine file's :class:`~machdyn.units.UnitSystem`, to show its output units.
        """
        from ..draw.simulation import plot_simulation

        return plot_simulation(self, fig=fig, units=units, title=title)

    def __str__(self) -> str:
        lines = [f"simulated {self.t[-1]:.6g} s: {self.message}"]
        lines += [f"  {e}" for e in self.events]
        if self.steady is not None:
            s = self.steady
            lines.append(
                f"  last cycle: {s.cycle_time:.6g} s, omega avg {s.omega_avg:.6g}, "
                f"min {s.omega_min:.6g}, max {s.omega_max:.6g}, k = {s.k:.4g}"
            )
        lines.append(f"  coefficients: {self.table}")
        return "\n".join(lines)
