"""Forward dynamics of a Linkage with several drivers (two degrees of freedom and more).

With the driver coordinates ``q = (q1, …, qn)`` every velocity is linear in
``q̇`` and every acceleration linear in ``q̈``, so the efforts the force
analysis needs at the drivers for a motion ``(q, q̇, q̈)`` are (Lagrange,
equivalently virtual work with d'Alembert's inertia loads)::

    E(q, q̇, q̈) = M(q) q̈ + c(q, q̇) + D(q) q̇ − Q(q)

with the generalised mass matrix ``M``, the velocity terms ``c`` (quadratic in
``q̇``), viscous damping ``D`` and the generalised forces ``Q`` of gravity,
springs and constant loads. The motors supply ``τ(t, q, q̇)``; the motion is
``M q̈ = τ − E(q, q̇, 0)``. Nothing is coded a second time: at each step the
linkage is solved once for a batch of five motions and :meth:`Linkage.forces`
(its one Newton–Euler assembler) gives ``E`` for each —

* ``(q̇, 0)``: ``E0 = c + D q̇ − Q``;
* ``(q̇, e_i)``: column ``i`` of ``M`` is ``E − E0``;
* ``(0, 0)`` and ``(−q̇, 0)``: ``−Q`` and ``c − D q̇ − Q``, for the energy.

The work integrals ride along under the integrator's error control:
``W_motor = ∫ q̇·τ``, ``W_model = ∫ q̇·Q`` (gravity, springs, constant loads)
and ``W_damping = −∫ q̇·D q̇``, so that ``ΔKE = W_motor + W_model + W_damping``
with ``KE = ½ q̇ᵀ M q̇`` (the tests write KE from the links' own velocities).

A sample the linkage cannot solve (a toggle, a dyad that no longer closes)
stops the run with an event naming the reason.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from .._summary import Summarized
from ..errors import InputError
from ._integrate import OverBudget

__all__ = ["MultiSimulation", "simulate_drivers"]


@dataclass(frozen=True, eq=False)
class MultiSimulation(Summarized):
    """The motion of a several-driver linkage in time (see :func:`simulate_drivers`).

    Attributes
    ----------
    t : ndarray
        Uniform time samples.
    q, qdot, qddot : mapping of driver name to ndarray
        Each driver's coordinate, rate and acceleration (radians for angles).
    effort : mapping of driver name to ndarray
        The motors' efforts on the drivers (torques, or forces for sliders).
    kinetic, w_motor, w_model, w_damping : ndarray
        Kinetic energy ``½ q̇ᵀ M q̇`` and the work integrals since ``t = 0``.
    status, message : str
        ``"done"`` (reached ``t_end``) or ``"unsolved"`` (stopped at a pose the
        linkage cannot take), and why.
    """

    t: np.ndarray
    q: Mapping[str, np.ndarray]
    qdot: Mapping[str, np.ndarray]
    qddot: Mapping[str, np.ndarray]
    effort: Mapping[str, np.ndarray]
    kinetic: np.ndarray
    w_motor: np.ndarray
    w_model: np.ndarray
    w_damping: np.ndarray
    status: str
    message: str

    @property
    def residual(self) -> np.ndarray:
        """``ΔKE − (W_motor + W_model + W_damping)``: zero to the integrator's tolerance."""
        return self.kinetic - self.kinetic[0] - (self.w_motor + self.w_model + self.w_damping)


class _Drivers:
    """The efforts of a linkage's force analysis at a pose, for a batch of motions."""

    def __init__(self, lk: Any, options: dict[str, Any]) -> None:
        self.lk, self.options = lk, options
        self.names = tuple(lk.drivers)

    def efforts(self, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, ...] | str:
        """``E0``, ``M``, ``−Q``, ``E(−q̇)`` at poses ``q`` (k, n) with rates ``qd`` (k, n).

        Shapes (k, n), (k, n, n), (k, n), (k, n); or the reason a pose is not solved.
        """
        k, n = q.shape
        rates = np.zeros((k, n + 3, n))
        rates[:, : n + 1] = qd[:, None, :]
        rates[:, n + 2] = -qd
        accels = np.zeros((k, n + 3, n))
        accels[:, 1 : n + 1] = np.eye(n)
        values = np.repeat(q[:, None, :], n + 3, axis=1)
        m = self.lk.solve(
            {d: values[..., i].ravel() for i, d in enumerate(self.names)},
            velocity={d: rates[..., i].ravel() for i, d in enumerate(self.names)},
            acceleration={d: accels[..., i].ravel() for i, d in enumerate(self.names)},
        )
        if not np.all(m.ok):
            return str(np.asarray(m.reason)[np.argmin(m.ok)])
        f = self.lk.forces(m, **self.options)
        if not np.all(f.ok):
            return str(np.asarray(f.reason)[np.argmin(f.ok)])
        E = np.stack([np.asarray(f.driver[d], dtype=float) for d in self.names], axis=-1)
        E = E.reshape(k, n + 3, n)
        M = np.swapaxes(E[:, 1 : n + 1] - E[:, :1], 1, 2)  # column i: E(q̇, e_i) − E0
        return E[:, 0], M, E[:, n + 1], E[:, n + 2]


def _solvers() -> dict[str, Any]:
    from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, Radau

    return {"DOP853": DOP853, "RK45": RK45, "RK23": RK23, "Radau": Radau, "BDF": BDF,
            "LSODA": LSODA}  # fmt: skip


class _Unsolved(Exception):
    """A pose the linkage cannot take, met while integrating."""


def simulate_drivers(
    lk: Any,
    motors: Mapping[str, Any],
    *,
    t_end: float,
    q0: Mapping[str, float] | None = None,
    qdot0: Mapping[str, float] | None = None,
    samples: int = 2001,
    rtol: float = 1e-9,
    atol: float = 1e-10,
    method: str = "DOP853",
    max_evaluations: int | None = None,
    **options: Any,
) -> MultiSimulation:
    """Integrate the motion of a Linkage with several drivers under their motors.

    Parameters
    ----------
    lk : Linkage
        A linkage with two or more drivers (link angles, motors between links,
        sliders, actuators), with its links' mass properties.
    motors : mapping of driver name to motor
        Each driver's motor (:class:`DCMotor`, a constant, ``f(t, q, q̇)``, ...;
        a driver left out is free: zero effort). A motor's rotor inertia,
        reflected through its ratio, adds to that driver's diagonal of ``M``.
    t_end : float
        Duration.
    q0, qdot0 : mapping, optional
        Start values (default: the drawing) and rates (default: at rest).
    samples, rtol, atol, method, max_evaluations : optional
        As for :func:`machdyn.simulate` (a run needing more evaluations of the
        equation of motion than ``max_evaluations`` is refused, naming ``t_end``;
        default 50,000, the budget of a model solved at every evaluation: each
        takes some 4 ms here, so a few minutes at most).
    **options
        The linkage's own loads, as :meth:`Linkage.forces` takes them
        (``gravity``, ``external_forces``, ``external_torques``, ``viscous``).

    Returns
    -------
    MultiSimulation

    Examples
    --------
    Two cranks of a five-bar, one motor each, against gravity:

    >>> import numpy as np
    >>> from machdyn.linkage import Linkage
    >>> pts = {"O2": 0j, "O5": 6 + 0j, "A": 2j, "D": 6 + 2j, "C": 3 + 5j}
    >>> lk = (Linkage(pts).ground("O2", "O5").link("2", "O2", "A", mass=1.0, inertia=0.3)
    ...       .link("3", "A", "C", mass=1.0, inertia=2.0).link("4", "D", "C", mass=1.0, inertia=2.0)
    ...       .link("5", "O5", "D", mass=1.0, inertia=0.3).drive("2", "5"))
    >>> run = simulate_drivers(lk, {"2": 10.0, "5": -10.0}, t_end=0.5, gravity=9.81, samples=11)
    >>> run.status, bool(np.abs(run.residual).max() < 1e-7 * run.kinetic.max())
    ('done', True)
    """
    from .._validate import positive
    from ..linkage import Linkage
    from .motors import as_motor

    if not isinstance(lk, Linkage):
        raise InputError("model", f"several drivers need a Linkage; got {type(lk).__name__}")
    drivers = _Drivers(lk, options)
    names, n = drivers.names, len(drivers.names)
    if n < 2:
        raise InputError("model", "simulate_drivers integrates several drivers; use simulate")
    if not isinstance(motors, Mapping):
        raise InputError("motor", f"give a mapping {{driver: motor}} for the drivers {names}")
    for key in motors:
        if key not in names:
            raise InputError("motor", f"unknown driver {key!r:.40}; drivers: {', '.join(names)}")
    motor = [as_motor(motors.get(d)) for d in names]
    added = np.array([m.reflected_inertia if m is not None else 0.0 for m in motor])
    t_end = positive("t_end", t_end, "second")
    drawn = lk.drawn_inputs
    q = np.array([_start("q0", q0, d, drawn[d]) for d in names])
    qd = np.array([_start("qdot0", qdot0, d, 0.0) for d in names])
    from ._setup import solver_options

    opts = solver_options(samples=samples, rtol=rtol, atol=atol, method=method, max_step=None,
                          table=False, table_tol=1e-9,
                          max_evaluations=max_evaluations)  # fmt: skip
    evaluations = [0]

    def torque(t: float, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        return np.array([float(m(t, q[i], qd[i])) if m is not None else 0.0
                         for i, m in enumerate(motor)])  # fmt: skip

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        evaluations[0] += 1
        if evaluations[0] > opts["max_evaluations"]:
            raise OverBudget(float(t), opts["max_evaluations"])
        q, qd = y[:n], y[n : 2 * n]
        got = drivers.efforts(q[None], qd[None])
        if isinstance(got, str):
            raise _Unsolved(f"t = {t:.6g}: {got}")
        e0, M, minus_q, e_back = (a[0] for a in got)
        tau = torque(t, q, qd)
        qdd = np.linalg.solve(M + np.diag(added), tau - e0)
        damping = 0.5 * (e0 - e_back)  # D q̇
        power = (qd @ tau, -(qd @ minus_q), -(qd @ damping))
        return np.concatenate([qd, qdd, power])

    y0 = np.concatenate([q, qd, np.zeros(3)])
    status, message, (ts, pieces) = "done", f"reached t_end = {t_end:g}", ([0.0], [])
    solver = _solvers()[opts["method"]](rhs, 0.0, y0, t_end, rtol=opts["rtol"], atol=opts["atol"])
    while solver.status == "running":
        try:
            failure = solver.step()
            piece = solver.dense_output() if failure is None else None  # DOP853's calls f
        except OverBudget as over:
            raise over.refusal("t_end", f"{t_end:.6g} s") from None
        except _Unsolved as exc:
            status, message = "unsolved", f"stopped before a pose it cannot take, at {exc}"
            break
        if failure is not None:
            status, message = "failed", str(failure)
            break
        ts.append(solver.t)
        pieces.append(piece)
    end = ts[-1]
    t = np.linspace(0.0, end, opts["samples"])
    if pieces:
        from scipy.integrate import OdeSolution

        y = OdeSolution(ts, pieces)(t)
    else:
        y = np.repeat(y0[:, None], t.size, axis=1)
    return _result(t, y, drivers, torque, added, status, message)


def _start(field: str, values: Any, driver: str, default: float) -> float:
    from .._validate import finite_scalar

    if values is None:
        return float(default)
    if not isinstance(values, Mapping):
        raise InputError(field, "give a mapping {driver: value}")
    return finite_scalar(f"{field}[{driver}]", values.get(driver, default))


def _result(t, y, drivers, torque, added, status, message) -> MultiSimulation:
    names, n = drivers.names, len(drivers.names)
    q, qd = y[:n].T, y[n : 2 * n].T
    got = drivers.efforts(q, qd)  # the output samples, all at once
    if isinstance(got, str):  # pragma: no cover - every sample lies on an accepted step
        raise InputError("model", got)
    e0, M, _, _ = got
    tau = np.array([torque(t[k], q[k], qd[k]) for k in range(t.size)])
    M = M + np.diag(added)
    qdd = np.linalg.solve(M, (tau - e0)[..., None])[..., 0].T
    kinetic = 0.5 * np.einsum("ki,kij,kj->k", qd, M, qd)
    tau = tau.T
    by = lambda a: MappingProxyType({d: a[i] for i, d in enumerate(names)})  # noqa: E731
    return MultiSimulation(
        t=t, q=by(y[:n]), qdot=by(y[n : 2 * n]), qddot=by(qdd), effort=by(tau), kinetic=kinetic,
        w_motor=y[2 * n], w_model=y[2 * n + 1], w_damping=y[2 * n + 2], status=status,
        message=message,
    )  # fmt: skip
