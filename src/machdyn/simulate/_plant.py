"""Model adapters for the simulation: one per model kind, over the model's own analyses.

Each adapter answers four questions about a one-degree-of-freedom model, all
through the model's public kinematics and its one force assembler:

* ``efforts_at(q, pairs)``: the driver effort the force analysis needs for the
  motions ``(q, q̇, q̈)`` (``pairs`` of ``(q̇, q̈)``), with the model's own loads;
* ``geometry(load, q)``: a load's coordinate (link angle or point) and its
  kinematic coefficient (rate per unit ``q̇``);
* ``span(q0)``: a crank's period, or the input's limits (toggles) and why;
* ``forces(q, q̇, q̈, loads)``: the full force result along a motion (pin forces).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import InputError, ModelError
from ..fourbar import FourBar
from ..slidercrank import SliderCrank
from ._table import Span
from .loads import Load

__all__ = ["make_plant"]

TWO_PI = 2.0 * math.pi

_FOURBAR_OPTIONS = (
    "mass",
    "inertia",
    "cg",
    "gravity",
    "load_torque4",
    "external_forces",
    "external_torques",
)
_SLIDER_OPTIONS = (
    "mass",
    "inertia",
    "cg",
    "gravity",
    "load_force4",
    "friction",
    "mu",
    "beta",
    "external_forces",
    "external_torques",
)
_LINKAGE_OPTIONS = ("gravity", "external_forces", "external_torques", "viscous", "coulomb")


def make_plant(model: Any, options: dict[str, Any], *, form: int, branch: int | None, driver: Any):
    """The adapter for ``model`` with its force-analysis ``options`` checked."""
    from ..linkage import Linkage

    if isinstance(model, FourBar):
        return _FourBarPlant(model, _options(options, _FOURBAR_OPTIONS, "FourBar"), form, branch)
    if isinstance(model, SliderCrank):
        opts = _options(options, _SLIDER_OPTIONS, "SliderCrank")
        if opts.get("friction") == "coulomb" and opts.get("mu", 0.0):
            raise InputError(
                "friction",
                "Coulomb friction is not simulated (its normal force depends on the "
                "acceleration); use friction='viscous' with beta",
            )
        return _SliderCrankPlant(model, opts, form)
    if isinstance(model, Linkage):
        opts = _options(options, _LINKAGE_OPTIONS, "Linkage")
        if opts.get("coulomb"):
            raise InputError(
                "coulomb",
                "Coulomb friction is not simulated (its normal force depends on the "
                "acceleration); use viscous friction",
            )
        return _LinkagePlant(model, opts, driver)
    raise InputError(
        "model", f"simulate takes a FourBar, SliderCrank or Linkage; got {type(model).__name__}"
    )


def _options(options: dict[str, Any], allowed: Sequence[str], kind: str) -> dict[str, Any]:
    extra = [k for k in options if k not in allowed]
    if extra:
        raise InputError(
            extra[0], f"not an option of a {kind}'s force analysis; options: {', '.join(allowed)}"
        )
    return dict(options)


def _with_loads(options: dict[str, Any], extra: Sequence[tuple[Load, Any]]) -> dict[str, Any]:
    """The force options plus the simulation's loads (values per sample)."""
    if not extra:
        return options
    opts = dict(options)
    forces = list(opts.get("external_forces", ()))
    torques = opts.get("external_torques", ())
    torques = list(torques.items()) if isinstance(torques, dict) else list(torques)
    for load, value in extra:
        if load.is_torque:
            torques.append((load.link, value))
        else:
            forces.append((load.link, load.point, value))
    opts["external_forces"], opts["external_torques"] = forces, torques
    return opts


def _pairs_grid(q: np.ndarray, pairs: Sequence[tuple[float, float]]):
    qd = np.array([p[0] for p in pairs])[:, None]
    qdd = np.array([p[1] for p in pairs])[:, None]
    return np.broadcast_to(q[None, :], (len(pairs), q.size)), qd, qdd


class _FourBarPlant:
    """A :class:`FourBar` driven at link 2 (coordinate θ2, effort T12)."""

    label = "theta2"
    effort = "T12"
    angular = True

    def __init__(self, fb: FourBar, options: dict[str, Any], form: int, branch: int | None) -> None:
        for key in ("mass", "inertia", "cg"):
            if key not in options:
                raise InputError(
                    key, "a FourBar simulation needs mass=, inertia= and cg= (links 2, 3, 4)"
                )
        self.model, self.options, self.form, self.branch = fb, options, form, branch
        self.range = fb.input_range(form)

    def default_q0(self) -> float:
        return 0.0 if self.range.full_turn else 0.5 * (self.range.lo + self.range.hi)

    def span(self, q0: float) -> Span:
        if self.range.full_turn:
            return Span(TWO_PI)
        lo, hi = self.range.lo, self.range.hi
        shift = TWO_PI * math.floor((q0 - lo) / TWO_PI)
        lo, hi = lo + shift, hi + shift
        if not lo <= q0 <= hi:
            raise InputError(
                "theta0",
                f"{math.degrees(q0):.6g} deg is outside link 2's range "
                f"[{math.degrees(lo):.6g}, {math.degrees(hi):.6g}] deg for form {self.form}",
            )
        why = (
            "toggle: links 3 and 4 are collinear at theta2 = {:.6g} deg (the end of link 2's range)"
        )
        return Span(None, lo, hi, why.format(math.degrees(lo)), why.format(math.degrees(hi)))

    def _solve_forces(self, q, qd, qdd, extra=()):
        from ..dynamics import fourbar_dynamics

        return fourbar_dynamics(
            self.model,
            _turn(q),
            qd,
            qdd,
            form=self.form,
            branch=self.branch,
            **_with_loads(self.options, extra),
        )

    def efforts_at(self, q: np.ndarray, pairs) -> tuple[np.ndarray, np.ndarray]:
        f = self._solve_forces(*_pairs_grid(q, pairs))
        return np.asarray(f.T12), np.asarray(f.ok).all(axis=0)

    def forces(self, q, qd, qdd, extra=()):
        return self._solve_forces(q, qd, qdd, extra)

    def is_complex(self, load: Load) -> bool:
        return not load.is_torque

    def check(self, load: Load) -> None:
        if load.link not in (2, 3, 4):
            raise InputError("loads", f"a FourBar load acts on link 2, 3 or 4; got {load.link!r}")
        if isinstance(load.point, str):
            raise InputError("loads", "a FourBar load's point is x + yj in the link's frame")

    def geometry(self, load: Load, q: np.ndarray):
        m = self.model.solve(_turn(q), 1.0, 0.0, self.form, branch=self.branch, order=1)
        ok = np.asarray(m.ok)
        rate = {2: np.ones_like(q), 3: m.omega3, 4: m.omega4}[load.link]
        if load.is_torque:
            return {2: q, 3: m.theta3, 4: m.theta4}[load.link], rate, ok
        r1, r2, r3, r4 = self.model.lengths
        origin = {2: 0.0 * m.A, 3: m.A, 4: r1 + 0.0 * m.A}[load.link]
        origin_rate = {2: 0.0, 3: 1j * m.A, 4: 0.0}[load.link]
        e = {2: m.A / r2, 3: (m.B - m.A) / r3, 4: (m.B - r1) / r4}[load.link]
        arm = load.point * e
        return origin + arm, origin_rate + 1j * rate * arm, ok


class _SliderCrankPlant:
    """A :class:`SliderCrank` driven at its crank (coordinate θ2, effort T12)."""

    label = "theta2"
    effort = "T12"
    angular = True

    def __init__(self, sc: SliderCrank, options: dict[str, Any], form: int) -> None:
        for key in ("mass", "inertia", "cg"):
            if key not in options:
                raise InputError(
                    key,
                    "a SliderCrank simulation needs mass=(m2, m3, m4), inertia=(I2, I3), "
                    "cg=(c2, c3)",
                )
        self.model, self.options, self.form = sc, options, form
        self.range = sc.input_range()

    def default_q0(self) -> float:
        return 0.0 if self.range is None else 0.5 * (self.range[0] + self.range[1])

    def span(self, q0: float) -> Span:
        if self.range is None:
            return Span(TWO_PI)
        for lo, hi in (self.range, (math.pi - self.range[1], math.pi - self.range[0])):
            shift = TWO_PI * math.floor((q0 - lo) / TWO_PI)
            if lo + shift <= q0 <= hi + shift:
                why = "toggle: the rod is perpendicular to the slide at theta2 = {:.6g} deg"
                lo, hi = lo + shift, hi + shift
                return Span(
                    None, lo, hi, why.format(math.degrees(lo)), why.format(math.degrees(hi))
                )
        raise InputError(
            "theta0",
            f"{math.degrees(q0):.6g} deg is outside the crank's range (it cannot be assembled)",
        )

    def _solve_forces(self, q, qd, qdd, extra=()):
        from ..dynamics import slidercrank_dynamics

        return slidercrank_dynamics(
            self.model, _turn(q), qd, qdd, form=self.form, **_with_loads(self.options, extra)
        )

    def efforts_at(self, q: np.ndarray, pairs) -> tuple[np.ndarray, np.ndarray]:
        f = self._solve_forces(*_pairs_grid(q, pairs))
        return np.asarray(f.T12), np.asarray(f.ok).all(axis=0)

    def forces(self, q, qd, qdd, extra=()):
        return self._solve_forces(q, qd, qdd, extra)

    def is_complex(self, load: Load) -> bool:
        return not load.is_torque

    def check(self, load: Load) -> None:
        if load.link not in (2, 3, 4):
            raise InputError(
                "loads", f"a SliderCrank load acts on link 2, 3 or 4; got {load.link!r}"
            )
        if load.is_torque and load.link == 4:
            raise InputError(
                "loads", "the slider (link 4) does not turn: a torque on it does no work"
            )
        if isinstance(load.point, str):
            raise InputError("loads", "a SliderCrank load's point is x + yj in the link's frame")

    def geometry(self, load: Load, q: np.ndarray):
        m = self.model.solve(_turn(q), 1.0, 0.0, self.form)
        ok = np.asarray(m.ok)
        if load.is_torque:
            if load.link == 2:
                return q, np.ones_like(q), ok
            return m.theta3, m.omega3, ok
        a, b = self.model.a, self.model.b
        if load.link == 2:
            arm = load.point * (m.A / a)
            return arm, 1j * arm, ok
        if load.link == 3:
            arm = load.point * ((m.B - m.A) / b)
            return m.A + arm, 1j * m.A + 1j * m.omega3 * arm, ok
        return m.B + load.point, m.d_dot + 0j, ok


class _LinkagePlant:
    """A one-driver :class:`~machdyn.linkage.Linkage` (coordinate and effort of its driver)."""

    def __init__(self, lk: Any, options: dict[str, Any], driver: Any) -> None:
        drivers = tuple(lk.drivers)
        if len(drivers) != 1:
            raise ModelError(
                f"simulate integrates one degree of freedom; this linkage has {len(drivers)} "
                f"drivers ({', '.join(drivers)})"
            )
        if driver is not None and driver != drivers[0]:
            raise InputError("driver", f"the linkage's driver is {drivers[0]!r}, not {driver!r}")
        self.model, self.options = lk, options
        self.driver = drivers[0]
        kinds = {j.name: j.kind for j in lk.joints}
        self.angular = self.driver in lk.links or kinds.get(self.driver) == "motor"
        self.label = self.driver
        self.effort = self.driver

    def default_q0(self) -> float:
        return _drawn_value(self.model, self.driver)

    def _solve(self, q, qd=None, qdd=0.0):
        return self.model.solve(q, velocity=qd, acceleration=qdd)

    def efforts_at(self, q: np.ndarray, pairs) -> tuple[np.ndarray, np.ndarray]:
        rows, ok = [], np.ones(q.shape, dtype=bool)
        for qd, qdd in pairs:
            f = self.model.forces(self._solve(q, qd, qdd), **self.options)
            rows.append(np.asarray(f.driver[self.driver], dtype=float))
            ok &= np.asarray(f.ok)
        return np.array(rows), ok

    def forces(self, q, qd, qdd, extra=()):
        return self.model.forces(self._solve(q, qd, qdd), **_with_loads(self.options, extra))

    def is_complex(self, load: Load) -> bool:
        return not load.is_torque

    def check(self, load: Load) -> None:
        links = self.model.links
        if load.link not in links:
            raise InputError("loads", f"unknown link {load.link!r}; links: {', '.join(links)}")
        if isinstance(load.point, str) and load.point not in links[load.link].points:
            on = ", ".join(links[load.link].points)
            raise InputError("loads", f"point {load.point!r} is not on link {load.link!r} ({on})")

    def geometry(self, load: Load, q: np.ndarray):
        m = self._solve(q, 1.0, 0.0)
        ok = np.asarray(m.ok)
        theta, omega = m.theta[load.link], m.omega[load.link]
        if load.is_torque:
            return theta, omega, ok
        if isinstance(load.point, str):
            return m.points[load.point], m.point_velocity[load.point], ok
        first = self.model.links[load.link].points[0]
        arm = load.point * np.exp(1j * theta)
        return m.points[first] + arm, m.point_velocity[first] + 1j * omega * arm, ok

    def span(self, q0: float) -> Span:
        """A full turn that closes on itself (a crank), or the limits found by sweeping."""
        if self.angular:
            sweep = np.linspace(q0, q0 + TWO_PI, 721)
            m = self._solve(sweep)
            if bool(np.all(m.ok)) and _closes(m):
                return Span(TWO_PI)
            reach = TWO_PI
        else:
            pts = np.array(list(self._solve(np.array([q0])).points.values())).ravel()
            reach = 4.0 * float(np.max(np.abs(pts - pts.mean())) + 1e-300)
        lo, lo_why = self._limit(q0, -reach)
        hi, hi_why = self._limit(q0, reach)
        return Span(None, lo, hi, lo_why, hi_why)

    def _limit(self, q0: float, reach: float) -> tuple[float, str]:
        """Sweep from ``q0`` by up to ``reach`` to the first pose the model cannot solve."""
        good, end, why = q0, q0 + reach, ""
        for _ in range(4):
            sweep = np.linspace(good, end, 181)
            m = self._solve(sweep)
            bad = np.flatnonzero(~np.asarray(m.ok))
            if bad.size == 0:
                return (
                    (end, why)
                    if why
                    else (end, f"end of the range searched ({self.driver} = {end:.6g})")
                )
            if bad[0] == 0:
                break
            good, end = float(sweep[bad[0] - 1]), float(sweep[bad[0]])
            why = str(m.reason[bad[0]])
        unit = "deg" if self.angular else ""
        where = math.degrees(end) if self.angular else end
        return end, f"{why} (at {self.driver} = {where:.6g} {unit})".replace(" )", ")")


def _turn(q: Any) -> Any:
    """An input angle of a closed-form model brought within one turn of zero (same pose)."""
    return np.asarray(q) - TWO_PI * np.round(np.asarray(q) / TWO_PI)


def _closes(m: Any) -> bool:
    """Whether the last pose of a full-turn sweep repeats the first (a crank)."""
    size = max(float(np.max(np.abs(p))) for p in m.points.values()) + 1e-300
    return all(abs(z[-1] - z[0]) <= 1e-7 * size for z in m.points.values())


def _drawn_value(lk: Any, driver: str) -> float:
    """The driver's value in the drawn pose."""
    return float(lk.drawn_inputs[driver])
