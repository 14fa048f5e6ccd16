"""The periodic steady state of a crank-driven machine, found directly (shooting).

Over one turn of the input the equation of motion is integrated in the angle
rather than in time, ``dω/dθ = α(θ, ω)/ω`` and ``dt/dθ = 1/ω`` (valid while
the crank keeps turning one way), and the start speed ``ω0`` is chosen so the
turn ends at the speed it began: ``ω(θ0 + 2π) = ω0``. With a motor whose torque
falls with speed that fixes the motion; with no motor law (``motor=None``) a
constant torque ``T`` and ``ω0`` are found together so that the time average
of ω over the turn is ``omega_avg`` — the flywheel-sizing situation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._summary import Summarized
from ..errors import InputError, ModelError
from ._integrate import parabola_peak

__all__ = ["PeriodicMotion", "steady_state"]


@dataclass(frozen=True, eq=False)
class PeriodicMotion(Summarized):
    """One turn of a crank's periodic steady state.

    Attributes
    ----------
    theta : ndarray
        Input angles over one period from the start angle (``samples`` of them,
        the last one a period after the first).
    omega, t : ndarray
        Speed at those angles, and the time at which they are reached.
    alpha : ndarray
        Acceleration there.
    motor_torque : ndarray
        The motor's torque on the input there (constant ``torque`` when none was given).
    torque : float or None
        The constant motor torque found (``motor=None``), else None.
    cycle_time, omega_avg : float
        Time of one turn and ``2π / cycle_time``.
    omega_max, omega_min, theta_omega_max, theta_omega_min : float
        Extremes of ω and where they occur (within the turn).
    k : float
        Coefficient of speed fluctuation ``(ω_max − ω_min)/ω_avg``.
    inertia : ndarray
        The machine's generalised inertia ``I(θ)`` (without the added inertia).
    added_inertia : float
        Flywheel, drive line and reflected rotor.
    """

    theta: np.ndarray
    omega: np.ndarray
    t: np.ndarray
    alpha: np.ndarray
    motor_torque: np.ndarray
    torque: float | None
    cycle_time: float
    omega_avg: float
    omega_max: float
    omega_min: float
    theta_omega_max: float
    theta_omega_min: float
    k: float
    inertia: np.ndarray
    added_inertia: float
    _solution: Any = field(repr=False, default=None)

    def at(self, theta: Any) -> np.ndarray:
        """ω at any angles (periodic continuation of the dense solution).

        Examples
        --------
        >>> import machdyn
        >>> p = steady_state(machdyn.FourBar(8, 4, 7, 6), omega_avg=10.0, flywheel=1.0,
        ...                  mass=(1, 2, 1.5), inertia=(0.1, 0.5, 0.3), cg=(2, 3.5, 3))
        >>> bool(np.isclose(p.at(p.theta[3] + 2 * np.pi), p.omega[3]))
        True
        """
        from .._validate import finite_array

        theta = finite_array("theta", theta, "radian")
        if theta.size == 0:
            return np.empty(theta.shape)
        local = self.theta[0] + np.mod(theta - self.theta[0], self.theta[-1] - self.theta[0])
        return self._solution(local.ravel())[0].reshape(theta.shape)

    def __str__(self) -> str:
        what = "" if self.torque is None else f" with a constant torque {self.torque:.6g}"
        return (
            f"periodic steady state{what}: one turn in {self.cycle_time:.6g} s, "
            f"omega avg {self.omega_avg:.6g}, min {self.omega_min:.6g}, "
            f"max {self.omega_max:.6g}, k = {self.k:.4g}"
        )


def steady_state(
    model: Any,
    motor: Any = None,
    *,
    omega_avg: float | None = None,
    flywheel: float = 0.0,
    loads: Any = (),
    theta0: float | None = None,
    form: int = 1,
    branch: int | None = None,
    driver: str | None = None,
    samples: int = 721,
    rtol: float = 1e-10,
    table_tol: float = 1e-9,
    **dynamics: Any,
) -> PeriodicMotion:
    """The periodic motion of a crank under a motor law, or at a given average speed.

    Parameters
    ----------
    model, motor, flywheel, loads, theta0, form, branch, driver, **dynamics
        As for :func:`machdyn.simulate`. The loads must not depend on time.
    omega_avg : float, optional
        Without ``motor``: the time-average speed to run at; a constant motor
        torque is found with the motion (how :func:`machdyn.flywheel.size_flywheel`
        assumes a machine is driven). With a motor: not given (the motor fixes it).
    samples : int
        Angles over the turn in the result.
    rtol : float
        Relative tolerance of the integration over the turn.

    Returns
    -------
    PeriodicMotion

    Raises
    ------
    InputError
        A model whose input does not turn fully, ``omega_avg`` given with a
        motor or missing without one.
    ModelError
        No periodic motion in one direction (the motor's torque does not fall
        with speed, or the machine stalls within the turn).

    Examples
    --------
    The HW 6 crank-rocker at 30 rad/s on average with a 0.02 kg·m² flywheel and
    a constant driving torque:

    >>> import machdyn
    >>> fb = machdyn.FourBar(0.08, 0.04, 0.07, 0.06)
    >>> p = steady_state(fb, omega_avg=30.0, flywheel=0.02, mass=(0.2, 0.3, 0.25),
    ...                  inertia=(3e-5, 1.2e-4, 7.5e-5), cg=(0.02, 0.035, 0.03))
    >>> round(p.omega_avg, 9), round(p.k, 4), abs(p.torque) < 1e-9
    (30.0, 0.023, True)
    """
    from .._validate import in_range, integer, positive
    from ._integrate import Runner
    from ._setup import prepare
    from ._table import Table

    setup = prepare(model, motor, loads, dynamics, form=form, branch=branch, driver=driver,
                    theta0=theta0, flywheel=flywheel)  # fmt: skip
    plant, motor, q0 = setup.plant, setup.motor, setup.q0
    span = plant.span(q0)
    if span.period is None:
        raise InputError("model", "a periodic steady state needs an input that turns fully")
    if (motor is None) == (omega_avg is None):
        raise InputError(
            "omega_avg",
            "give either a motor (its law fixes the speed) or omega_avg (a constant torque is "
            "found that runs at it), not both",
        )
    rtol = in_range("rtol", rtol, 1e-13, 1e-3)
    samples = integer("samples", samples, minimum=3, maximum=10**7)
    table = Table(plant, setup.loads, q0, span, in_range("table_tol", table_tol, 1e-14, 1e-2))
    runner = Runner(plant, table, span, motor, setup.loads, setup.added,
                    rtol=rtol, atol=1e-12, method="DOP853", max_step=math.inf)  # fmt: skip
    turn = _Turn(runner, q0, span.period, rtol)
    if motor is None:
        target = positive("omega_avg", omega_avg, "radian / second")
        torque, w0 = turn.solve_average(target)
    else:
        torque, w0 = None, turn.solve_motor()
    return turn.result(w0, torque, samples, setup.added)


class _Turn:
    """One turn in the angle domain: ``y = (ω, t)`` as functions of θ."""

    def __init__(self, runner: Any, q0: float, period: float, rtol: float) -> None:
        self.runner, self.q0, self.period, self.rtol = runner, q0, period, rtol
        self.torque = 0.0  # the constant torque when there is no motor law

    def _rhs(self, q: float, y: np.ndarray) -> list[float]:
        w = float(y[0])
        if w <= 0.0:
            raise _Stalled(q)
        _, alpha, _, _, _, _ = self.runner.terms(0.0, q, w)
        if self.runner.motor is None:
            alpha += self.torque / (self.runner.coef(q)[0] + self.runner.added)
        return [alpha / w, 1.0 / w]

    def integrate(self, w0: float, dense: bool = False) -> Any:
        from scipy.integrate import solve_ivp

        return solve_ivp(
            self._rhs,
            (self.q0, self.q0 + self.period),
            [w0, 0.0],
            method="DOP853",
            rtol=self.rtol,
            atol=1e-12 * max(w0, 1.0),
            dense_output=dense,
        )

    def end(self, w0: float) -> tuple[float, float]:
        """Speed and time at the end of a turn started at ``w0``."""
        try:
            sol = self.integrate(w0)
        except _Stalled as exc:
            raise ModelError(
                f"the machine stops within the turn (at q = {exc.q:.6g}) from a start speed "
                f"of {w0:.6g}: there is no periodic motion at this speed"
            ) from None
        return float(sol.y[0, -1]), float(sol.y[1, -1])

    def solve_motor(self) -> float:
        """``ω0`` of the periodic turn under the motor's law (secant on ω(2π) − ω0)."""
        from scipy.optimize import brentq

        runner = self.runner
        # a first guess: the speed at which the motor's torque balances the loads on average
        q = self.q0 + np.linspace(0.0, self.period, 64, endpoint=False)
        c = runner.coef.many(q)
        need, damp = -float(np.mean(c[3])), float(np.mean(c[2]))

        def balance(w: float) -> float:
            return float(np.mean(runner.motor(0.0, q, w))) - need - damp * w

        hi = 1.0
        while balance(hi) > 0.0 and hi < 1e9:
            hi *= 2.0
        if balance(hi) > 0.0 or balance(1e-9 * hi) <= 0.0:
            raise ModelError(
                "no steady speed: the motor's torque does not fall below the load's as the speed "
                "grows (or it cannot turn the machine at all); give omega_avg instead"
            )
        guess = brentq(balance, 1e-9 * hi, hi, xtol=1e-12 * hi)
        return self._fixed_point(guess)

    def _fixed_point(self, guess: float) -> float:
        from scipy.optimize import root_scalar

        sol = root_scalar(
            lambda w: self.end(w)[0] - w, x0=guess, x1=1.01 * guess, method="secant",
            xtol=1e-13 * guess, rtol=1e-13,
        )  # fmt: skip
        if not sol.converged or not sol.root > 0.0:
            raise ModelError(f"the periodic turn was not found ({sol.flag})")
        return float(sol.root)

    def solve_average(self, target: float) -> tuple[float, float]:
        """Constant torque and ``ω0`` of the periodic turn whose average speed is ``target``.

        Nested one-dimensional solves, each monotonic and nearly linear (secant
        steps, bracketed if they stall): for a start speed, the torque that
        closes the turn (``Δ(½ I ω²) = ∮ (T + Q) dθ``: more torque, a faster
        end); then the start speed that gives the average.
        """
        c = self.runner.coef.many(self.q0 + np.linspace(0.0, self.period, 256, endpoint=False))
        inertia = float(np.mean(c[0])) + self.runner.added
        mean_q, mean_c = float(np.mean(c[3])), float(np.mean(c[2]))

        def closing_torque(w0: float) -> float:
            def gap(torque: float) -> float:
                self.torque = torque
                return self.end(w0)[0] - w0

            # a torque step dT changes the end speed by about period dT / (I ω0)
            step = 1e-3 * inertia * w0 * w0 / self.period
            return _root(gap, -mean_q + mean_c * w0, step)

        def speed_gap(w0: float) -> float:
            self.torque = closing_torque(w0)
            return self.period / self.end(w0)[1] - target

        w0 = _root(speed_gap, target, 1e-3 * target, low=0.0)
        return closing_torque(w0), w0

    def result(self, w0: float, torque: float | None, samples: int, added: float) -> PeriodicMotion:
        sol = self.integrate(w0, dense=True)
        theta = np.linspace(self.q0, self.q0 + self.period, samples)
        fine = np.linspace(self.q0, self.q0 + self.period, 50001)
        w_fine = sol.sol(fine)[0]
        omega, t = sol.sol(theta)
        cycle = float(sol.y[1, -1])
        omega_avg = self.period / cycle
        terms = self.runner.terms_many(t, theta, omega)
        motor = terms["torque"] + (torque or 0.0)
        alpha = terms["alpha"] + (torque or 0.0) / terms["inertia"]
        q_max, w_max = parabola_peak(fine, w_fine, int(np.argmax(w_fine)))
        q_min, w_min = parabola_peak(fine, w_fine, int(np.argmin(w_fine)))
        return PeriodicMotion(
            theta=theta,
            omega=omega,
            t=t,
            alpha=alpha,
            motor_torque=np.broadcast_to(motor, theta.shape).copy(),
            torque=torque,
            cycle_time=cycle,
            omega_avg=omega_avg,
            omega_max=w_max,
            omega_min=w_min,
            theta_omega_max=float(np.mod(q_max - self.q0, self.period)),
            theta_omega_min=float(np.mod(q_min - self.q0, self.period)),
            k=(w_max - w_min) / omega_avg,
            inertia=terms["inertia"] - added,
            added_inertia=added,
            _solution=sol.sol,
        )


def _root(f: Any, guess: float, step: float, *, low: float | None = None) -> float:
    """The root of an increasing, nearly linear ``f`` near ``guess``.

    Secant steps from ``guess`` and ``guess + step``; if they do not converge in
    a few steps, the root is bracketed by growing steps and found by Brent's method.
    """
    from scipy.optimize import brentq

    x0, x1 = guess, guess + step
    f0, f1 = f(x0), f(x1)
    for _ in range(8):
        if f1 == f0:
            break
        x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
        if low is not None and x2 <= low:
            break
        x0, f0, x1 = x1, f1, x2
        f1 = f(x1)
        if abs(x1 - x0) <= max(1e-13 * abs(x1), 1e-7 * abs(step)) or f1 == 0.0:
            return x1
    a, fa = (x1, f1)
    direction = -1.0 if fa > 0.0 else 1.0
    for _ in range(60):
        b = a + direction * step
        if low is not None and b <= low:
            b = 0.5 * (a + low)
        fb = f(b)
        if (fa > 0.0) != (fb > 0.0) or fb == 0.0:
            lo, hi = (a, b) if a < b else (b, a)
            xtol = max(1e-14 * max(abs(lo), abs(hi)), 1e-8 * abs(step))
            return float(brentq(f, lo, hi, xtol=xtol, rtol=1e-14))
        a, fa = b, fb
        step *= 2.0
    raise ModelError("no periodic turn was found near the expected speed and torque")


class _Stalled(ArithmeticError):
    def __init__(self, q: float) -> None:
        super().__init__(q)
        self.q = q
