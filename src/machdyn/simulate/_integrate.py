"""Integrating the equation of motion with ``scipy.integrate.solve_ivp``, segment by segment.

The state is ``y = (q, q̇, W_motor, W_loads, W_damping, W_model)``: the motion
and four work integrals, integrated with the same error control so the
energy balance can be checked to the integrator's tolerance. The run is cut
into segments at every event that changes what happens next:

* a crank's completed turn (``q`` one period from the cycle's start): the
  cycle's time and speed are recorded and the steady state is checked;
* a motor's or load's switching time (``breakpoints``): the jump is exact;
* the speed passing through zero: a stall (the motor pushed on but the load
  won), a reversal (no motor pushing: a swing), or rest (equilibrium);
* the end of the input's range (a toggle), or of the tabulated range.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import InputError
from ._table import _Unsolved, load_layout
from .loads import Load
from .result import Energy, Event, SteadyState

__all__ = ["OverBudget", "Runner"]

#: Default budget of a tabulated run: evaluations of the equation of motion
#: (``max_evaluations``). About a minute of a tabulated four-bar (30 µs each), some 4,000
#: turns; a steady state usually takes a few thousand.
MAX_EVALUATIONS = 2_000_000
#: Default budget of a run that solves the model at every evaluation (``table=False``, or a
#: linkage with several drivers): 1–5 ms each, so a few minutes at most instead of hours.
SOLVED_EVALUATIONS = 50_000


class Runner:
    """One simulation: the right-hand side, the segment loop and the recorded solution."""

    def __init__(
        self,
        plant: Any,
        coefficients: Any,
        span: Any,
        motor: Any,
        loads: tuple[Load, ...],
        added_inertia: float,
        *,
        rtol: float,
        atol: float,
        method: str,
        max_step: float,
        max_evaluations: int = MAX_EVALUATIONS,
    ) -> None:
        self.plant, self.coef, self.motor, self.loads = plant, coefficients, motor, loads
        self.coef_span = span
        self.q0 = 0.0
        self._base = 0.0  # a segment integrates q − base (small): its tolerance is absolute
        self.added = added_inertia
        self.layout = load_layout(loads, plant)
        self.rtol, self.atol, self.method, self.max_step = rtol, atol, method, max_step
        self.max_evaluations, self.evaluations = max_evaluations, 0
        self.segments: list[tuple[float, float, Any]] = []
        self.events: list[Event] = []
        self.cycle_times: list[float] = []
        self.cycle_speeds: list[float] = []

    # ------------------------------------------------------------------ the equation
    def terms(
        self, t: float, q: float, w: float
    ) -> tuple[float, float, float, float, float, float]:
        """``(I_total, α, T_motor, Q_loads, C, Q_model)`` at one state."""
        c = self.coef(q)
        inertia = c[0] + self.added
        torque = self.motor(t, q, w) if self.motor is not None else 0.0
        q_loads = 0.0
        for load, (row, complex_) in zip(self.loads, self.layout, strict=True):
            if complex_:
                x = complex(c[row], c[row + 1])
                rate = complex(c[row + 2], c[row + 3])
                f = complex(load(t, x, rate * w))
                q_loads += f.real * rate.real + f.imag * rate.imag
            else:
                rate = c[row + 1]
                q_loads += float(load(t, c[row], rate * w)) * rate
        damping, q_model = c[2], c[3]
        alpha = (torque + q_loads + q_model - damping * w - c[1] * w * w) / inertia
        return inertia, alpha, torque, q_loads, damping, q_model

    def terms_many(self, t: np.ndarray, q: np.ndarray, w: np.ndarray) -> dict[str, np.ndarray]:
        """:meth:`terms` over arrays of samples (for the results): a dict of arrays."""
        c = self.coef.many(q)
        inertia = c[0] + self.added
        torque = np.broadcast_to(self.motor(t, q, w), q.shape) if self.motor else np.zeros(q.shape)
        q_loads = np.zeros(q.shape)
        for load, (row, complex_) in zip(self.loads, self.layout, strict=True):
            if complex_:
                x = c[row] + 1j * c[row + 1]
                rate = c[row + 2] + 1j * c[row + 3]
                f = np.asarray(load(t, x, rate * w), dtype=complex)
                q_loads = q_loads + (f.real * rate.real + f.imag * rate.imag)
            else:
                rate = c[row + 1]
                q_loads = q_loads + np.real(load(t, c[row], rate * w)) * rate
        alpha = (torque + q_loads + c[3] - c[2] * w - c[1] * w * w) / inertia
        return {"inertia": inertia, "alpha": alpha, "torque": torque, "loads": q_loads}

    def rhs(self, t: float, y: np.ndarray) -> list[float]:
        """``dy/dt`` for ``solve_ivp``: q̇, q̈ and the four powers."""
        self.evaluations += 1
        if self.evaluations > self.max_evaluations:
            raise OverBudget(float(t), self.max_evaluations)
        t, q, w = float(t), self._base + float(y[0]), float(y[1])
        _, alpha, torque, q_loads, damping, q_model = self.terms(t, q, w)
        out = [w, alpha, torque * w, q_loads * w, -damping * w * w, q_model * w]
        size = abs(w) + abs(alpha) + abs(out[2]) + abs(out[3]) + abs(out[4]) + abs(out[5])
        if not size <= _HUGE:  # NaN fails too
            raise _Diverged(t, q, w)
        return out

    def check_start(self, q0: float, w0: float) -> None:
        """Refuse a start whose energy or acceleration is out of floating-point range."""
        self._base = 0.0
        try:
            self.rhs(0.0, np.array([q0, w0, 0.0, 0.0, 0.0, 0.0]))
        except _Diverged:
            raise InputError(
                "omega0", f"{w0:g} is too fast for this machine: its energy overflows"
            ) from None

    # ------------------------------------------------------------------ the run
    def run(
        self,
        q0: float,
        w0: float,
        t_end: float,
        *,
        q_stop: float | None,
        steady_tol: float | None,
        stop_on: frozenset[str],
        breakpoints: tuple[float, ...],
    ) -> tuple[str, str]:
        """Integrate from ``(q0, w0)`` at t = 0; return the status and its message."""
        y = np.array([q0, w0, 0.0, 0.0, 0.0, 0.0])
        self.q0 = q0
        t = 0.0
        period = self.coef.period
        cycle_start = q0
        direction = self._start_direction(0.0, q0, w0)
        if isinstance(direction, tuple):  # it cannot start
            return direction
        breaks = sorted(b for b in set(breakpoints) if 0.0 < b < t_end)
        while True:
            t_stop = next((b for b in breaks if b > t), t_end)
            events, names = self._events(y, direction, cycle_start, period, q_stop)
            sol = self._segment(t, t_stop, y, events)
            t, y = float(sol.t[-1]), sol.y[:, -1].copy()
            y[0] += self._base
            if sol.status == -1:
                return self._failed(t, y, sol.message)
            fired = {names[i] for i, te in enumerate(sol.t_events) if te.size}
            if "cycle" in fired:  # may coincide with any other event: record it first
                self.cycle_times.append(t)
                self.cycle_speeds.append(float(y[1]))
                cycle_start += period if y[0] > cycle_start else -period
                if steady_tol is not None and self._is_steady(steady_tol):
                    self.events.append(Event("steady", t, y[0], y[1], "periodic steady state"))
                    return "steady", f"steady state after {len(self.cycle_times)} turns"
            if "stop" in fired or _reached(y[0], q_stop, self.q0):
                return "turns", f"the input turned to {y[0]:.6g}"
            if fired & {"hi", "lo"}:
                why = self._limit_reason("hi" if "hi" in fired else "lo")
                self.events.append(Event("toggle", t, y[0], y[1], why))
                return "toggle", why
            if "zero" in fired:
                y[1] = 0.0
                outcome = self._at_zero_speed(t, y, direction)
                if not isinstance(outcome, tuple):
                    direction = outcome
                elif self.events[-1].kind in stop_on or self.events[-1].kind == "rest":
                    return outcome
                else:
                    direction = -direction
            elif not fired:  # reached t_stop
                if t >= t_end:
                    return "t_end", f"reached t_end = {t_end:.6g} s"
                self.events.append(Event("breakpoint", t, y[0], y[1], "a motor or load switched"))

    def _segment(self, t0: float, t1: float, y: np.ndarray, events: list) -> Any:
        from scipy.integrate import solve_ivp

        self._base = base = float(y[0])
        local = y.copy()
        local[0] = 0.0
        for event in events:
            event.base = base
        try:
            sol = solve_ivp(
                self.rhs,
                (t0, t1),
                local,
                method=self.method,
                rtol=self.rtol,
                atol=self._atol(y),
                events=events,
                dense_output=True,
                max_step=self.max_step,
            )
        except (_Unsolved, _Diverged) as exc:  # the model failed, or the motion ran away
            sol = _Failed(t0, local, str(exc))
        if sol.status != -1 and sol.t.size > 1:
            self.segments.append((float(sol.t[0]), float(sol.t[-1]), sol.sol, base))
        return sol

    def _atol(self, y: np.ndarray) -> np.ndarray:
        """Absolute tolerances: ``atol`` for q and q̇, scaled to the energies for the works."""
        c = self.coef(float(y[0]))
        energy = 0.5 * (c[0] + self.added) * max(float(y[1]) ** 2, 1.0) + abs(c[3]) + 1e-300
        return np.array([self.atol, self.atol] + [self.atol * energy] * 4)

    def _events(self, y, direction, cycle_start, period, q_stop):
        """Terminal events of the next segment, and their names (``y[0]`` is ``q − base``)."""
        events, names = [], []

        def add(name: str, level: float | None, sense: float) -> None:
            fun = _SpeedEvent() if level is None else _LevelEvent(level)
            fun.terminal, fun.direction = True, sense
            events.append(fun)
            names.append(name)

        if period is not None:
            add("cycle", cycle_start + period, 1.0)
            add("cycle", cycle_start - period, -1.0)
        if q_stop is not None:
            add("stop", q_stop, 1.0 if q_stop > self.q0 else -1.0)
        if math.isfinite(self.coef.hi):
            add("hi", self.coef.hi, 1.0)
        if math.isfinite(self.coef.lo):
            add("lo", self.coef.lo, -1.0)
        add("zero", None, -direction)
        return events, names

    def _start_direction(self, t: float, q: float, w: float) -> Any:
        """Direction of motion at the start, or (status, message) if it cannot start."""
        if w:
            return 1.0 if w > 0 else -1.0
        outcome = self._at_zero_speed(t, np.array([q, 0.0]), 0.0)
        if isinstance(outcome, tuple):
            return outcome
        return outcome

    def _at_zero_speed(self, t: float, y: np.ndarray, moving: float) -> Any:
        """Classify a moment of zero speed: the new direction, or (status, message) after an event.

        ``moving`` is the direction it had (0 at a start from rest).
        """
        q = float(y[0])
        _, alpha, torque, q_loads, _, q_model = self.terms(t, q, 0.0)
        need = -(q_loads + q_model)  # effort that holds it at rest here
        # the model's generalised force over its range sets the scale: at an equilibrium
        # of gravity (a pendulum hanging down) q_model is itself zero but for round-off
        scale = abs(torque) + abs(q_loads) + abs(q_model) + self.coef.force_scale + 1e-300
        pushes = self.motor is not None and torque != 0.0
        if abs(alpha) * (self.coef(q)[0] + self.added) <= 1e-12 * scale:
            what = f"at rest in equilibrium at {self.plant.label} = {_show(q, self.plant)}"
            self.events.append(Event("rest", t, q, 0.0, what))
            return "rest", what
        new = 1.0 if alpha > 0 else -1.0
        if pushes and (math.copysign(1.0, torque) != new):
            deficit = abs(need - torque)
            verb = "cannot start" if moving == 0.0 else "stalls"
            where = f"{self.plant.label} = {_show(q, self.plant)}"
            what = stall_words(verb, where, f"{torque:.6g}", f"{need:.6g}", f"{deficit:.6g}")
            self.events.append(Event("stall", t, q, 0.0, what, deficit, torque, need))
            return "stall", what
        if moving:
            what = f"the speed reversed at {self.plant.label} = {_show(q, self.plant)}"
            self.events.append(Event("reversal", t, q, 0.0, what))
            if new == moving:  # touched zero and went on
                return new
            return "reversal", what
        return new

    def _limit_reason(self, kind: str) -> str:
        span = self.coef_span
        exact = span.hi if kind == "hi" else span.lo
        reached = self.coef.hi if kind == "hi" else self.coef.lo
        why = span.hi_reason if kind == "hi" else span.lo_reason
        gap = abs(exact - reached)
        if gap > 1e-12 * max(1.0, abs(exact)):
            unit = " rad" if self.plant.angular else ""
            return (
                f"{why}; stopped {gap:.3g}{unit} short of it, where the generalised inertia "
                "grows without bound"
            )
        return why

    def _is_steady(self, tol: float) -> bool:
        times = [0.0, *self.cycle_times]
        if len(times) < 4:
            return False
        d1, d2 = times[-1] - times[-2], times[-2] - times[-3]
        w1, w2 = self.cycle_speeds[-1], self.cycle_speeds[-2]
        return abs(d1 - d2) <= tol * d1 and abs(w1 - w2) <= tol * max(abs(w1), 1e-300)

    def _failed(self, t: float, y: np.ndarray, message: str) -> tuple[str, str]:
        what = f"the integration failed at t = {t:.6g}: {message}"
        self.events.append(Event("failed", t, float(y[0]), float(y[1]), what))
        return "failed", what

    # ------------------------------------------------------------------ results
    def state(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(q, q̇)`` at times within the run (dense output of the segments)."""
        y = self.dense(t)
        return y[0], y[1]

    def dense(self, t: np.ndarray) -> np.ndarray:
        """The whole state vector at times ``t`` (6, ...)."""
        t = np.asarray(t, dtype=float)
        flat = t.ravel()
        out = np.empty((6, flat.size))
        if not self.segments:
            out[:] = np.nan
            return out.reshape(6, *t.shape)
        starts = np.array([s[0] for s in self.segments])
        index = np.clip(np.searchsorted(starts, flat, side="right") - 1, 0, len(self.segments) - 1)
        for k in np.unique(index):
            sel = index == k
            _, _, dense, base = self.segments[k]
            out[:, sel] = dense(flat[sel])
            out[0, sel] += base
        return out.reshape(6, *t.shape)

    def energy(self, inertia: np.ndarray, w: np.ndarray, y: np.ndarray) -> Energy:
        """Kinetic energy from the total inertia, and the integrated works."""
        return Energy(
            kinetic=0.5 * inertia * w * w,
            motor=y[2],
            loads=y[3],
            damping=y[4],
            model=y[5],
        )

    def steady_state(self) -> SteadyState | None:
        """The last full cycle's speed statistics (None before two full turns)."""
        period = self.coef.period
        if period is None or len(self.cycle_times) < 2:
            return None
        t0, t1 = self.cycle_times[-2], self.cycle_times[-1]
        ts = np.linspace(t0, t1, 20001)
        _, w = self.state(ts)
        t_max, w_max = parabola_peak(ts, w, int(np.argmax(w)))
        t_min, w_min = parabola_peak(ts, w, int(np.argmin(w)))
        q_max, q_min = (float(v) for v in self.state(np.array([t_max, t_min]))[0])
        omega_avg = period / (t1 - t0)
        times = [0.0, *self.cycle_times]
        previous = times[-2] - times[-3] if len(times) >= 3 else math.nan
        return SteadyState(
            cycle_time=t1 - t0,
            omega_avg=omega_avg,
            omega_max=w_max,
            omega_min=w_min,
            theta_omega_max=float(np.mod(q_max - self.q0, period)),
            theta_omega_min=float(np.mod(q_min - self.q0, period)),
            k=(w_max - w_min) / omega_avg,
            converged=abs((t1 - t0) - previous) / (t1 - t0),
        )

    def forces(self, t, q, w, alpha) -> Any:
        """The model's force result along the samples, with the loads' values at them."""
        extra = []
        if self.loads:
            c = self.coef.many(q)
            for load, (row, complex_) in zip(self.loads, self.layout, strict=True):
                if complex_:
                    x = c[row] + 1j * c[row + 1]
                    rate = c[row + 2] + 1j * c[row + 3]
                else:
                    x, rate = c[row], c[row + 1]
                extra.append((load, np.broadcast_to(load(t, x, rate * w), np.shape(t))))
        return self.plant.forces(q, w, alpha, extra)


#: Largest state derivative the integration accepts (beyond it the motion has run away).
_HUGE = 1e150


class OverBudget(Exception):
    """A run that needs more evaluations of its equation of motion than it may take."""

    def __init__(self, t: float, limit: int) -> None:
        super().__init__(t, limit)
        self.t, self.limit = t, limit

    def refusal(self, field: str, asked: str) -> InputError:
        """The one-line refusal naming ``field`` (the option that set the run's length)."""
        return InputError(
            field,
            f"{asked} needs more than the {self.limit:,} evaluations of the equation of motion a "
            f"run may take (max_evaluations; it had reached t = {self.t:.6g} s); simulate a "
            'shorter time, use until = "steady" for the periodic state, or raise '
            "max_evaluations",
        )


class _Diverged(ArithmeticError):
    """The motion ran out of floating-point range (raised inside the integration)."""

    def __init__(self, t: float, q: float, w: float) -> None:
        super().__init__(f"the motion ran away at t = {t:.6g} (q = {q:.6g}, speed {w:.6g})")


class _LevelEvent:
    """``q`` reaching ``level`` (``base`` is set by the segment that uses it)."""

    def __init__(self, level: float) -> None:
        self.level = level
        self.base = 0.0

    def __call__(self, t: float, y: np.ndarray) -> float:
        return (self.base - self.level) + y[0]


class _SpeedEvent:
    """The speed passing through zero."""

    base = 0.0

    def __call__(self, t: float, y: np.ndarray) -> float:
        return y[1]


class _Failed:
    """A stand-in for a solve_ivp result when the model failed inside the integration."""

    def __init__(self, t: float, y: np.ndarray, message: str) -> None:
        self.t = np.array([t])
        self.y = y[:, None]
        self.status = -1
        self.message = message
        self.t_events: list[np.ndarray] = []


def _reached(q: float, q_stop: float | None, q0: float) -> bool:
    """Whether ``q`` reached ``q_stop`` (from ``q0``) up to rounding: events may coincide."""
    if q_stop is None:
        return False
    slack = 1e-12 * max(1.0, abs(q_stop))
    return (q - q_stop) * (1.0 if q_stop > q0 else -1.0) >= -slack


def parabola_peak(x: np.ndarray, y: np.ndarray, i: int) -> tuple[float, float]:
    """The extremum of the parabola through samples ``i − 1, i, i + 1`` of a uniform grid.

    Returns ``(x, y)`` at the vertex; the sample itself at an end of the grid.
    """
    if 0 < i < x.size - 1:
        y0, y1, y2 = y[i - 1], y[i], y[i + 1]
        curvature = y0 - 2.0 * y1 + y2
        if curvature:
            s = 0.5 * (y0 - y2) / curvature
            if abs(s) <= 1.0:
                return float(x[i] + s * (x[1] - x[0])), float(y1 - 0.25 * (y0 - y2) * s)
    return float(x[i]), float(y[i])


def stall_words(verb: str, where: str, given: str, need: str, deficit: str) -> str:
    """A stall's message from its parts, already worded (numbers with their units, if any)."""
    return (
        f"the motor {verb} at {where}: it gives {given} at zero speed where the load needs "
        f"{need} (a deficit of {deficit})"
    )


def _show(q: float, plant: Any) -> str:
    return f"{math.degrees(q):.6g} deg" if plant.angular else f"{q:.6g}"
