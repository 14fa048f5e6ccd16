"""Sensitivities of a drawn :class:`~machdyn.linkage.Linkage` to its drawn coordinates.

The linkage's constraints are written in natural coordinates, independent of
how the solver places it: every moving link ``L`` has a pose ``(z_L, φ_L)`` —
its first point and the angle of its first → second line — and a point ``P``
of it is at ``w(L, P) = z_L + (P₀ − F₀) e^{j(φ_L − ψ_L)}`` (``P₀``, ``F₀`` drawn,
``ψ_L`` the drawn angle of the link). Joints and drivers are equations:

* a pin: the carriers' points coincide, ``w(L₁, P) = w(L₂, P)``;
* a slider: the block turns with its guide, and its point stays on the guide's
  line ``Im(conj(û) (w(block, P) − w(on, P₀))) = 0``; a slot: the line only;
* drivers: a link's angle, a motor's relative angle, a slider's or slot's
  travel along the line, an actuator's length.

With the solved pose ``x`` at each sample, ``C(x, u; p) = 0`` differentiates
implicitly: ``J ∂x/∂p = −∂C/∂p`` (``J = ∂C/∂x``, the Jacobian of the velocity
analysis). Written with jets (:class:`machdyn._dual.Jet`), the same
constraints give the velocity and acceleration equations, each linear in its
unknown rates with the same ``J``; their derivatives follow level by level.
"""

from __future__ import annotations

import contextlib
from typing import Any

import numpy as np

from ._dual import Dual, Jet
from .errors import InputError

__all__: list[str] = []

GROUND = "ground"


class _Constraints:
    """A linkage's joints and drivers as natural-coordinate equations."""

    def __init__(self, lk: Any) -> None:
        self.lk = lk
        self.links = list(lk.links)
        self.points = list(lk.points)
        self.owner: dict[str, str] = {}
        for name, link in lk.links.items():
            for p in link.points:
                self.owner.setdefault(p, name)
        for p in lk.ground_points:
            self.owner[p] = GROUND
        self.joints = []
        for joint in lk.joints:
            curved = getattr(joint, "radius", None) is not None
            if joint.kind == "roll" or curved:
                raise InputError(
                    "model",
                    f"sensitivity: joint {joint.name!r} "
                    f"({'curved ' if curved else ''}{joint.kind}) "
                    "is not differentiated yet; pins, straight sliders and slots, actuators and "
                    "motors are",
                )
            self.joints.append(joint)
        self.drivers = tuple(lk.drivers)
        self.kinds = {j.name: j for j in self.joints}
        self.dimensions = tuple(f"{p}.{axis}" for p in self.points for axis in ("x", "y"))

    # ------------------------------------------------------------------ geometry
    def drawn(self, m: int, seeded: bool) -> dict[str, Dual]:
        """The drawn points, seeded as the dimensions (or constants)."""
        out = {}
        for k, name in enumerate(self.points):
            z = complex(self.lk.points[name])
            d = np.zeros(m, dtype=complex)
            if seeded:
                d[2 * k], d[2 * k + 1] = 1.0, 1j
            out[name] = Dual(np.asarray(z), d)
        return out

    def frame(self, link: str, drawn: dict[str, Dual]) -> tuple[Dual, Dual]:
        """A link's drawn first point ``F₀`` and angle ``ψ`` (0 for a one-point link)."""
        pts = self.lk.links[link].points
        first = drawn[pts[0]]
        if len(pts) < 2:
            return first, first.real * 0.0
        vec = drawn[pts[1]] - first
        psi_v = np.angle(vec.v)
        # d(arg z) = Im(dz / z)
        return first, Dual(psi_v, (vec.d / vec.v[..., None]).imag)

    # ------------------------------------------------------------------ the equations
    def placer(self, poses: dict[str, tuple[Jet, Jet]], drawn: dict[str, Dual], zero: Jet):
        """Functions ``angle(link)``, ``turn(link)`` (``e^{j(φ − ψ)}``), ``world(link, point)``."""
        frames = {name: self.frame(name, drawn) for name in self.links}
        rot: dict[str, Jet] = {}
        placed: dict[tuple[str, str], Jet] = {}

        def angle(link: str) -> Jet:
            return zero if link == GROUND else poses[link][1]

        def turn(link: str) -> Jet:
            if link not in rot:
                rot[link] = (poses[link][1] - frames[link][1]).expj()
            return rot[link]

        def world(link: str, point: str) -> Jet:
            key = (link, point)
            if key not in placed:
                if link == GROUND:
                    placed[key] = zero + drawn[point]
                else:
                    first, _ = frames[link]
                    placed[key] = poses[link][0] + turn(link) * (drawn[point] - first)
            return placed[key]

        return frames, angle, turn, world

    def equations(self, poses: dict[str, tuple[Jet, Jet]], drawn: dict[str, Dual], u: Jet,
                  zero: Jet) -> list[Jet]:  # fmt: skip
        """Every constraint as a real jet (``poses``: link → (z, φ) jets; ``u``: the driver)."""
        frames, angle, turn, world = self.placer(poses, drawn, zero)
        eqs: list[Jet] = []
        for j in self.joints:
            if j.kind == "pin":
                p = j.points[0]
                for other in j.links[1:]:
                    gap = world(j.links[0], p) - world(other, p)
                    eqs += [gap.real, gap.imag]
            elif j.kind in ("slider", "slot"):
                moving, on = j.links
                p = j.points[0]
                along = world(moving, p) - world(on, p)
                eqs.append((self._axis(on, j.direction, turn, zero).conj() * along).imag)
                if j.kind == "slider":
                    psi_m = frames[moving][1] if moving != GROUND else 0.0
                    psi_o = frames[on][1] if on != GROUND else 0.0
                    eqs.append(angle(moving) - angle(on) - (psi_m - psi_o))
        eqs.append(self._driver(self.drivers[0], angle, turn, world, zero) - u)
        return eqs

    def _axis(self, on: str, direction: complex, turn: Any, zero: Jet) -> Jet:
        """The guide's unit vector, turning with it."""
        if on == GROUND:
            return zero + complex(direction)
        return turn(on) * complex(direction)

    def _driver(self, name: str, angle: Any, turn: Any, world: Any, zero: Jet) -> Jet:
        if name in self.lk.links:
            return angle(name)
        j = self.kinds[name]
        if j.kind == "motor":
            return angle(j.links[1]) - angle(j.links[0])
        if j.kind == "actuator":
            a, b = j.links
            gap = world(b, j.points[1]) - world(a, j.points[0])
            return (gap.conj() * gap).real  # the length squared (u is squared too)
        moving, on = j.links
        if j.through is not None:
            ref = j.through
        elif on == GROUND:
            ref = self.lk.ground_points[0]
        else:
            ref = self.lk.links[on].points[0]
        axis = self._axis(on, j.direction, turn, zero)
        return (axis.conj() * (world(moving, j.points[0]) - world(on, ref))).real

    def outputs(self, poses: dict[str, tuple[Jet, Jet]], drawn: dict[str, Dual], zero: Jet):
        """Link angles and points with their rates, as jets: ``{name: Jet}``."""
        _, angle, _, world = self.placer(poses, drawn, zero)
        out: dict[str, tuple[Jet, bool]] = {}
        for name in self.links:
            out[f"theta.{name}"] = (angle(name), False)
        for point in self.points:
            out[f"point.{point}"] = (world(self.owner[point], point), True)
        return out


def _jet_const(value: Any, m: int, order: int = 2) -> Jet:
    v = np.asarray(value)
    zero = Dual(np.zeros_like(v), np.zeros((*v.shape, m), dtype=v.dtype))
    return Jet(Dual(v, np.zeros((*v.shape, m), dtype=v.dtype)), *[zero] * order)


def linkage_sensitivity(lk: Any, values: Any, velocity: Any, acceleration: Any) -> dict[str, Any]:
    """Outputs of ``lk`` over a sweep of its driver, and their derivatives to its drawing.

    A linkage of a driven crank and RRR dyads is differentiated through its
    closed forms (:func:`closed_form_sensitivity`); any other by implicit
    differentiation of its natural-coordinate constraints (:func:`implicit_sensitivity`).
    """
    from ._linkage_family import Family

    try:
        family = Family(lk)
    except InputError:
        return implicit_sensitivity(lk, values, velocity, acceleration)
    if family.sliders:  # the closed-form route differentiates cranks and RRR dyads only
        return implicit_sensitivity(lk, values, velocity, acceleration)
    return closed_form_sensitivity(lk, family, values, velocity, acceleration)


def closed_form_sensitivity(lk: Any, family: Any, values: Any, velocity: Any,
                            acceleration: Any) -> tuple:  # fmt: skip
    """Derivatives by forward differentiation of the closed-form dyads (duals over the drawing).

    The family solver (:mod:`machdyn._linkage_family`) runs once with the drawn
    points as duals seeded along ``P.x``, ``P.y``: every pose, rate and point
    carries its exact first derivatives — no Jacobian to invert. A pose where a
    dyad is singular (its links aligned: a toggle) is left to NaN.
    """
    driver = family.driver
    motion = lk.solve(values, velocity=velocity, acceleration=acceleration)
    n = int(np.size(motion.ok))
    u = [np.asarray(motion.inputs[driver], dtype=float).reshape(n)]
    u += [_rate(velocity, driver, n), _rate(acceleration, driver, n)]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        st, _ = family.solve(family.seeded(), u, 2)
        singular = _singular(family, st, n)
        m = 2 * len(family.points)
        nominal, derivative = {}, {}
        for link in family.links:
            D = st.direction(link)
            turn = Dual(D.v, (D.d / D.v[..., None]).imag)
            for key, value, jet in (
                ("theta", motion.theta[link], turn),
                ("omega", motion.omega[link], st.w[link]),
                ("alpha", motion.alpha[link], st.al[link]),
            ):
                nominal[f"{key}.{link}"] = np.array(value, dtype=float).reshape(n)
                derivative[f"{key}.{link}"] = _along(jet, n, m, float)
        for p in family.points:
            owner = GROUND if p in family.carriers[GROUND] else family.owner(p)
            rates = (
                ("point", motion.points[p], st.pos(owner, p)),
                ("velocity", motion.point_velocity[p], st.vel(owner, p)),
                ("acceleration", motion.point_acceleration[p], st.acc(owner, p)),
            )
            for key, value, jet in rates:
                nominal[f"{key}.{p}"] = np.array(value, dtype=complex).reshape(n)
                derivative[f"{key}.{p}"] = _along(jet, n, m, complex)
    for d in derivative.values():
        d[singular] = np.nan
    dims = tuple(f"{p}.{axis}" for p in family.points for axis in ("x", "y"))
    return dims, nominal, derivative, motion


def _along(x: Any, n: int, m: int, dtype: type) -> np.ndarray:
    """The derivatives of ``x`` as an (n, m) array (zeros for a value that has none)."""
    if not isinstance(x, Dual):
        return np.zeros((n, m), dtype=dtype)
    return np.array(np.broadcast_to(x.d, (1, n, m))[0], dtype=dtype)


def _singular(family: Any, st: Any, n: int) -> np.ndarray:
    """Poses where a dyad's two links are aligned (sine below 1e-10: derivatives undefined)."""
    out = np.zeros(n, dtype=bool)
    for step in family.steps:
        if step[0] == "rrr":
            _, L1, _, p1, L2, _, p2, B, _ = step
            r1 = (st.pos(L1, B) - st.pos(L1, p1)).v
            r2 = (st.pos(L2, B) - st.pos(L2, p2)).v
            sine = np.abs(_cross_c(r1, r2)) / (np.abs(r1) * np.abs(r2))
            out |= ~(np.broadcast_to(sine, (1, n))[0] > 1e-10)
    return out


def _cross_c(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a.real * b.imag - a.imag * b.real


def implicit_sensitivity(lk: Any, values: Any, velocity: Any, acceleration: Any) -> tuple:
    """Derivatives by implicit differentiation of the natural-coordinate constraints."""
    model = _Constraints(lk)
    if len(model.drivers) != 1:
        raise InputError("model", f"sensitivity takes one driver; this linkage has {model.drivers}")
    driver = model.drivers[0]
    motion = lk.solve(values, velocity=velocity, acceleration=acceleration)
    n = int(np.size(motion.ok))
    rates = [motion.points, motion.point_velocity, motion.point_acceleration]
    turns = [motion.theta, motion.omega, motion.alpha]
    first = {name: lk.links[name].points[0] for name in model.links}
    given = (motion.inputs[driver], _rate(velocity, driver, n), _rate(acceleration, driver, n))
    u_vals = [np.broadcast_to(np.asarray(x, dtype=float), (n,)) for x in given]
    kinds = model.kinds.get(driver)
    if kinds is not None and kinds.kind == "actuator":  # the constraint uses the length squared
        u0, u1, u2 = u_vals
        u_vals = [u0 * u0, 2 * u0 * u1, 2 * (u1 * u1 + u0 * u2)]

    # J = ∂C/∂x from the position equations with the poses seeded
    nx = 3 * len(model.links)
    poses = {}
    for k, name in enumerate(model.links):
        z0 = np.asarray(rates[0][first[name]], dtype=complex)
        dz = np.zeros((n, nx), dtype=complex)
        dz[:, 3 * k], dz[:, 3 * k + 1] = 1.0, 1j
        dphi = np.zeros((n, nx))
        dphi[:, 3 * k + 2] = 1.0
        poses[name] = (Jet(Dual(z0, dz)), Jet(Dual(np.asarray(turns[0][name], float), dphi)))
    eqs = model.equations(poses, model.drawn(nx, False), _jet_const(np.zeros(n), nx, 0),
                          _jet_const(np.zeros(n), nx, 0))  # fmt: skip
    if len(eqs) != nx:
        raise InputError(
            "model",
            f"sensitivity: {len(eqs)} constraint equations for {nx} pose unknowns (redundant or "
            "missing joints)",
        )
    jac = np.stack([e.c[0].d for e in eqs], axis=1)  # (n, eqs, nx)
    m = len(model.dimensions)
    drawn = model.drawn(m, True)
    known = [np.zeros((n, nx, m)) for _ in range(3)]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        inverse = _inverse(jac, motion.ok)
        for level in range(3):  # each level needs the jets up to its own order
            state = _poses(model, rates, turns, first, known, n, m, level)
            eqs = model.equations(
                state, drawn, _driver_jet(u_vals[: level + 1], m), _jet_const(np.zeros(n), m, level)
            )
            rhs = np.stack([e.c[level].d for e in eqs], axis=1)  # (n, eqs, m)
            known[level] = -(inverse @ rhs)
    state = _poses(model, rates, turns, first, known, n, m)
    jets = model.outputs(state, drawn, _jet_const(np.zeros(n), m))
    nominal, derivative = {}, {}
    for name, (jet, is_point) in jets.items():
        base = name.split(".", 1)[1]
        for level, (angle_name, point_name) in enumerate(
            (("theta", "point"), ("omega", "velocity"), ("alpha", "acceleration"))
        ):
            key = f"{point_name if is_point else angle_name}.{base}"
            nominal[key] = np.broadcast_to(jet.c[level].v, (n,)).copy()
            derivative[key] = np.broadcast_to(jet.c[level].d, (n, m)).copy()
    return model.dimensions, nominal, derivative, motion


def _rate(value: Any, driver: str, n: int) -> np.ndarray:
    if isinstance(value, dict):
        value = value.get(driver, 0.0)
    return np.broadcast_to(np.asarray(value, dtype=float), (n,))


def _driver_jet(u: list[np.ndarray], m: int) -> Jet:
    return Jet(*(Dual(x, np.zeros((*x.shape, m))) for x in u))


def _poses(model, rates, turns, first, known, n, m, order=2) -> dict[str, tuple[Jet, Jet]]:
    """Every link's pose jets up to ``order``, with the derivative parts solved so far."""
    out = {}
    for k, name in enumerate(model.links):
        z, phi = [], []
        for level in range(order + 1):
            d = known[level]
            z.append(
                Dual(
                    np.asarray(rates[level][first[name]], complex),
                    d[:, 3 * k] + 1j * d[:, 3 * k + 1],
                )
            )
            phi.append(Dual(np.asarray(turns[level][name], float), d[:, 3 * k + 2]))
        out[name] = (Jet(*z), Jet(*phi))
    return out


def _inverse(jac: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """``J⁻¹`` per sample; NaN where the sample is not solved or ``J`` is singular (a toggle).

    Singular: the 1-norm condition number ``‖J‖ ‖J⁻¹‖`` beyond 1e12.
    """
    out = np.full(jac.shape, np.nan)
    good = np.asarray(ok).ravel() & np.isfinite(jac).all(axis=(1, 2))
    idx = np.flatnonzero(good)
    if idx.size == 0:
        return out
    try:
        inv = np.linalg.inv(jac[idx])
    except np.linalg.LinAlgError:  # some exactly singular: one at a time
        inv = np.full((idx.size, *jac.shape[1:]), np.nan)
        for k, i in enumerate(idx):
            with contextlib.suppress(np.linalg.LinAlgError):
                inv[k] = np.linalg.inv(jac[i])
    norm = np.abs(jac[idx]).sum(axis=1).max(axis=1) * np.abs(inv).sum(axis=1).max(axis=1)
    inv[~(norm < 1e12)] = np.nan
    out[idx] = inv
    return out
