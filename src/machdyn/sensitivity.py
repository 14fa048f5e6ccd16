"""How much the dimensions matter: first-order sensitivities of a linkage's outputs.

For a four-bar the loop ``F = a e^{jθ2} + b e^{jθ3} − c e^{jθ4} − d = 0`` fixes
``θ3, θ4`` given θ2 and the dimensions ``p`` (the notes' loop; a slider-crank's
is ``a e^{jθ2} − b e^{jθ3} − jc − d = 0`` for ``θ3`` and the slider's ``d``).
Differentiating it at constant θ2 (implicit differentiation)::

    J ∂x/∂p = −∂F/∂p,      J = [∂F/∂θ3, ∂F/∂θ4]

with the position Jacobian ``J`` — the matrix every derivative order of the
kinematics solves with (DESIGN.md). The velocity and acceleration equations are
linear in their unknowns with the same ``J``; differentiating them with respect
to ``p``, with the position derivatives above in their coefficients, gives the
derivatives of ω and α. The arithmetic is carried by dual numbers
(:mod:`machdyn._dual`), so each equation is written once and its exact first
derivatives follow; a whole sweep of input angles is one set of array
operations. Points (a coupler point, the pins) and the input torque ``T12``
(by virtual work: ``T12 = Σ (m a_G + j m g)·∂r_G/∂θ2 + Σ I_G α ∂θ/∂θ2 − T_load ∂θ4/∂θ2``,
the kinematic coefficients of :mod:`machdyn.virtual_work`) follow the same way.
A drawn Linkage of a crank and RRR dyads is differentiated forward through its
closed-form dyads instead (:mod:`machdyn._linkage_sensitivity`).

:func:`sensitivity` returns a :class:`Sensitivity`: every output's nominal
value and its derivatives with respect to every dimension over the sweep, and
the worst-case and root-sum-square stack-up of given tolerances.

Examples
--------
How the HW 6 crank-rocker's output angle θ4 moves with each length at θ2 = 60°:

>>> import numpy as np
>>> from machdyn import FourBar
>>> s = sensitivity(FourBar(8, 4, 7, 6), np.radians([60.0]))
>>> s.dimensions
('r1', 'r2', 'r3', 'r4')
>>> np.round(s.derivative["theta4"][0], 4).tolist()   # rad per unit length
[0.1733, -0.1443, -0.1856, 0.0818]
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from ._dual import Dual, expj, lift, solve_pair
from ._flags import Flagged
from .errors import InputError

__all__ = ["Sensitivity", "sensitivity"]


@dataclass(frozen=True, eq=False)
class Sensitivity(Flagged):
    """Outputs of a linkage over a sweep, and their derivatives with respect to its dimensions.

    Attributes
    ----------
    theta : ndarray
        The input values of the sweep (N,).
    dimensions : tuple of str
        The dimensions differentiated (``"r1"`` … ``"r4"``, ``"p"``, ``"delta"``
        for a four-bar; ``"crank"``, ``"coupler"``, ``"offset"``, ``"p"``,
        ``"delta"`` for a slider-crank).
    nominal : mapping of str to ndarray
        Each output at the sweep (N,): angles (rad), rates, points (complex
        ``x + jy``), ``T12``.
    derivative : mapping of str to ndarray
        ``∂output/∂dimension`` (N, len(dimensions)); complex for points.
    status : ndarray of uint8
        0 where solved; otherwise an index into ``reasons`` (the model's:
        unassembled, toggle), NaN in the values and derivatives there.
    reasons : tuple of str
        Why a sample is not solved, by status code.
    """

    theta: np.ndarray
    dimensions: tuple[str, ...]
    nominal: Mapping[str, np.ndarray]
    derivative: Mapping[str, np.ndarray]
    status: np.ndarray
    reasons: tuple[str, ...] = ()
    #: The quantity of ``theta``: ``"angle"``, or ``"length"`` for a linkage driven by a slide.
    input_kind: str = "angle"

    @property
    def REASONS(self) -> tuple[str, ...]:
        """The reasons by status code (as :class:`machdyn._flags.Flagged` expects)."""
        return self.reasons

    def of(self, output: str, dimension: str) -> np.ndarray:
        """``∂output/∂dimension`` over the sweep.

        Examples
        --------
        >>> from machdyn import FourBar
        >>> s = sensitivity(FourBar(8, 4, 7, 6), [0.5, 1.0])
        >>> s.of("theta3", "r2").shape
        (2,)
        """
        output = _name("output", output, self.derivative)
        dimension = _name("dimension", dimension, self.dimensions)
        return self.derivative[output][:, self.dimensions.index(dimension)]

    def stack_up(self, tolerances: Mapping[str, Any], output: str) -> np.ndarray:
        """Worst-case deviation of ``output`` for dimensions within ``±tolerance`` (first order).

        ``Σ |∂y/∂p| t_p`` at every sample; for a point, ``Σ |∂P/∂p| t_p`` bounds
        the distance it can move (the triangle inequality; its components are
        ``stack_up`` of ``output.real``... use :meth:`components`).

        Examples
        --------
        >>> from machdyn import FourBar
        >>> s = sensitivity(FourBar(8, 4, 7, 6), [1.0])
        >>> t = {"r1": 0.01, "r2": 0.01, "r3": 0.01, "r4": 0.01}
        >>> bool(s.stack_up(t, "theta4")[0] > s.rss(t, "theta4")[0] > 0)
        True
        """
        return np.sum(np.abs(self._scaled(tolerances, output)), axis=-1)

    def rss(self, tolerances: Mapping[str, Any], output: str) -> np.ndarray:
        """Root-sum-square deviation ``√Σ (∂y/∂p · t_p)²`` (for a point, its distance)."""
        return np.sqrt(np.sum(np.abs(self._scaled(tolerances, output)) ** 2, axis=-1))

    def _scaled(self, tolerances: Mapping[str, Any], output: str) -> np.ndarray:
        from ._validate import nonnegative

        if not isinstance(tolerances, Mapping):
            raise InputError("tolerances", "give a mapping {dimension: tolerance}")
        t = np.zeros(len(self.dimensions))
        for name, value in tolerances.items():
            name = _name("tolerances", name, self.dimensions)
            t[self.dimensions.index(name)] = nonnegative(f"tolerances[{name}]", value)
        return self.derivative[_name("output", output, self.derivative)] * t

    def to_pandas(self) -> Any:
        """One row per sample: ``theta`` and ``d<output>/d<dimension>`` columns (pandas lazily).

        A model given units (a machine file's) names each column with the quotient
        of its output's and its dimension's display units, ``dtheta.output/dO2.x
        [deg/mm]``, and converts the values to them; a unit-free model's columns
        are bare and in its own units (angles in radians).
        """
        import pandas as pd

        from .units import units_of

        system = units_of(self)

        def scaled(name: str, kind: str | None, values: np.ndarray, dim: str) -> dict:
            if system is None or kind is None:
                return {name: values}
            dim_kind = _dimension_kind(dim)
            out = system.display(kind)
            out = f"({out})" if "/" in out else out
            unit = f"{out}/{system.display(dim_kind)}"
            return {f"{name} [{unit}]": values * system.factor(kind) / system.factor(dim_kind)}

        if system is None:
            cols: dict[str, np.ndarray] = {"theta": self.theta}
        else:
            theta = self.input_kind
            cols = {system.label("theta", theta): system.show(theta, self.theta)}
        for name, d in self.derivative.items():
            kind = _output_kind(name, np.iscomplexobj(d))
            for k, dim in enumerate(self.dimensions):
                if np.iscomplexobj(d):
                    cols |= scaled(f"d{name}_x/d{dim}", kind, d[:, k].real, dim)
                    cols |= scaled(f"d{name}_y/d{dim}", kind, d[:, k].imag, dim)
                else:
                    cols |= scaled(f"d{name}/d{dim}", kind, d[:, k], dim)
        cols["ok"] = self.ok
        return pd.DataFrame(cols)


#: The quantity of an output by its name's head (four-bar, slider-crank and Linkage names).
_OUTPUT_KINDS = {
    "theta": "angle",
    "omega": "angular_velocity",
    "alpha": "angular_acceleration",
    "point": "length",
    "velocity": "velocity",
    "acceleration": "acceleration",
    "length": "length",
    "torque": "torque",
    "T12": "torque",
    "d": "length",
    "d_dot": "velocity",
    "d_ddot": "acceleration",
}


def _output_kind(name: str, is_point: bool) -> str | None:
    """The quantity of output ``name`` (None: unknown, left unlabelled)."""
    if is_point:  # A, B, coupler, their _velocity/_acceleration
        for suffix in ("velocity", "acceleration"):
            if name.endswith(f"_{suffix}"):
                return suffix
    head = name.split(".", 1)[0] if "." in name else name.rstrip("0123456789")
    kind = _OUTPUT_KINDS.get(head) or _OUTPUT_KINDS.get(name)
    return kind if kind is not None else ("length" if is_point else None)


def _dimension_kind(name: str) -> str:
    """An angle for ``delta`` and a guide's ``.angle``; every other dimension is a length."""
    return "angle" if name == "delta" or name.endswith((".delta", ".angle")) else "length"


def sensitivity(
    model: Any,
    theta2: Any,
    *,
    omega2: float = 1.0,
    alpha2: float = 0.0,
    form: int = 1,
    branch: int | None = None,
    dimensions: Sequence[str] | None = None,
    mass: Sequence[float] | None = None,
    inertia: Sequence[float] | None = None,
    cg: Sequence[complex] | None = None,
    gravity: float = 0.0,
    load: float = 0.0,
) -> Sensitivity:
    """Derivatives of a linkage's outputs with respect to its dimensions, over a sweep.

    Parameters
    ----------
    model : FourBar or SliderCrank
        The linkage (its lengths and coupler point are the dimensions).
    theta2 : array_like
        Input angles of the sweep, radians.
    omega2, alpha2 : float
        Input speed and acceleration (for the rates and ``T12``).
    form, branch : optional
        The assembly, as in the model's ``solve``.
    dimensions : sequence of str, optional
        The dimensions to differentiate with respect to (default all).
    mass, inertia, cg : sequences, optional
        Mass properties as for the model's ``dynamics``; with them ``T12`` is
        an output (by virtual work), with ``gravity`` and ``load`` (the
        external torque on link 4 of a four-bar, or force on a slider along x).
        ``gravity``: ``g`` along −y, or (a four-bar) a complex vector in its frame
        (placed at θ1 in a plane: ``−1j * g * exp(−1j * θ1)``).

    Returns
    -------
    Sensitivity
        Outputs: ``theta3``, ``theta4`` (four-bar) or ``d`` (slider-crank), their
        rates ``omega…``/``alpha…`` (``d_dot``, ``d_ddot``), the pins ``A``, ``B``
        and their velocities, the coupler point (``coupler``,
        ``coupler_velocity``, ``coupler_acceleration``) when the model has one,
        and ``T12`` with mass properties.

    Raises
    ------
    InputError
        A model that is not a FourBar or SliderCrank, an unknown dimension, bad angles.

    Examples
    --------
    A slider-crank's stroke grows with its crank: at θ2 = 0, ∂d/∂crank = 1:

    >>> from machdyn import SliderCrank
    >>> s = sensitivity(SliderCrank(2.0, 6.0), [0.0])
    >>> round(float(s.of("d", "crank")[0]), 12)
    1.0
    """
    from .fourbar import FourBar
    from .linkage import Linkage
    from .slidercrank import SliderCrank
    from .units import with_units

    if isinstance(model, Linkage):
        result = _linkage(model, theta2, omega2, alpha2, dimensions)
        return with_units(result, getattr(model, "units", None))
    if isinstance(model, FourBar):
        names, values, motion, status, reasons = _fourbar(
            model, theta2, omega2, alpha2, form, branch, mass, inertia, cg, gravity, load
        )
    elif isinstance(model, SliderCrank):
        names, values, motion, status, reasons = _slidercrank(
            model, theta2, omega2, alpha2, form, mass, inertia, cg, gravity, load
        )
    else:
        raise InputError(
            "model", f"sensitivity takes a FourBar or SliderCrank; got {type(model).__name__}"
        )
    keep = _chosen(dimensions, names)
    bad = status != 0
    nominal, derivative = {}, {}
    for name, value in values.items():
        v = np.array(value.v, copy=True)
        d = np.array(value.d[..., keep], copy=True)
        if bad.any():
            v[bad] = np.nan
            d[bad] = np.nan
        nominal[name], derivative[name] = v, d
    result = Sensitivity(
        theta=np.asarray(motion.theta2, dtype=float).ravel(),
        dimensions=tuple(names[k] for k in keep),
        nominal=MappingProxyType(nominal),
        derivative=MappingProxyType(derivative),
        status=status,
        reasons=reasons,
    )
    return with_units(result, getattr(model, "units", None))


def _linkage(
    lk: Any, values: Any, velocity: Any, acceleration: Any, dimensions: Any
) -> Sensitivity:
    from ._linkage_sensitivity import linkage_sensitivity
    from ._validate import finite_array

    values = finite_array("theta2", values).ravel()
    if values.size == 0:
        raise InputError("theta2", "give at least one driver value")
    names, nominal, derivative, motion = linkage_sensitivity(lk, values, velocity, acceleration)
    keep = _chosen(dimensions, names)
    finite = np.all([np.isfinite(d).all(axis=-1) for d in derivative.values()], axis=0)
    ok = np.asarray(motion.ok).ravel() & finite  # a new array: the motion's flags stay as solved
    status = (~ok).astype(np.uint8)
    for name in nominal:
        derivative[name] = derivative[name][:, keep]
        nominal[name][~ok] = np.nan
        derivative[name][~ok] = np.nan
    reasons = (
        "",
        "not solved: unassembled, or a singular pose (toggle) where the derivatives are undefined",
    )
    angular = set(getattr(motion, "angle_drivers", ())) >= set(lk.drivers)
    return Sensitivity(
        theta=values,
        dimensions=tuple(names[k] for k in keep),
        nominal=MappingProxyType(nominal),
        derivative=MappingProxyType(derivative),
        status=status,
        reasons=reasons,
        input_kind="angle" if angular else "length",
    )


def _name(field: str, value: Any, known: Any) -> str:
    """``value`` if it is one of the ``known`` names, else :class:`InputError` listing them."""
    if not isinstance(value, str) or value not in known:
        raise InputError(field, f"unknown name {value!r:.60}; known: {', '.join(known)}")
    return value


def _chosen(dimensions: Any, names: tuple[str, ...]) -> list[int]:
    if dimensions is None:
        return list(range(len(names)))
    if isinstance(dimensions, str):
        dimensions = (dimensions,)
    try:
        chosen = list(dimensions)
    except TypeError:
        raise InputError("dimensions", f"must be a list of names, got {dimensions!r:.60}") from None
    return [names.index(_name("dimensions", d, names)) for d in chosen]


def _sweep(theta2: Any, omega2: Any, alpha2: Any) -> tuple[np.ndarray, float, float]:
    from ._validate import finite_array, finite_scalar

    theta = finite_array("theta2", theta2, "radian").ravel()
    if theta.size == 0:
        raise InputError("theta2", "give at least one input angle")
    w2 = finite_scalar("omega2", omega2, "radian / second")
    a2 = finite_scalar("alpha2", alpha2, "radian / second ** 2")
    return theta, w2, a2


def _fourbar(fb, theta2, omega2, alpha2, form, branch, mass, inertia, cg, gravity, load):
    from .fourbar import STATUS_REASONS

    theta, w2, a2 = _sweep(theta2, omega2, alpha2)
    motion = fb.solve(theta, w2, a2, form, branch=branch, order=2)
    names = ("r1", "r2", "r3", "r4") + (("p", "delta") if fb.coupler is not None else ())
    m = len(names)
    lengths = tuple(Dual.seed(np.full(theta.shape, r), k, m) for k, r in enumerate(fb.lengths))
    coupler = None
    if fb.coupler is not None:
        coupler = tuple(
            Dual.seed(np.full(theta.shape, v), 4 + k, m) for k, v in enumerate(fb.coupler)
        )
    torque = None
    if mass is not None:
        torque = (mass, inertia, cg, gravity, load, fb.length_unit)
    values = fourbar_outputs(lengths, coupler, theta, motion.theta3, motion.theta4, w2, a2, torque)
    return names, values, motion, np.asarray(motion.status).ravel(), STATUS_REASONS


def fourbar_outputs(
    lengths, coupler, theta, theta3, theta4, w2, a2, torque=None
) -> dict[str, Dual]:
    """A four-bar's outputs as duals, given its solved angles θ3, θ4 (any broadcast shapes).

    ``lengths`` (r1, r2, r3, r4) and ``coupler`` (p, δ) are duals: seeded for
    sensitivities, or constants with no directions for a batch of linkages
    (:mod:`machdyn.tolerance`). The position derivatives follow from the loop
    ``F = 0`` by implicit differentiation; ω, α and the points from the same
    Jacobian's systems with their right-hand sides as in :mod:`machdyn.fourbar`.
    """
    d, a, b, c = lengths
    m = a.d.shape[-1]
    e2 = expj(
        lift(np.broadcast_to(theta, np.broadcast_shapes(np.shape(theta), np.shape(theta3))), m)
    )
    th3, th4 = lift(theta3, m), lift(theta4, m)
    if m:  # positions: J ∂θ/∂p = −∂F/∂p, with θ3, θ4 held (F's own derivative)
        F = a * e2 + b * expj(th3) - c * expj(th4) - d
        c1, c2 = (1j * b * expj(th3)), (-1j * c * expj(th4))
        dth3, dth4 = solve_pair(lift(c1.v, m), lift(c2.v, m), -F)
        th3, th4 = Dual(th3.v, dth3.d), Dual(th4.v, dth4.d)
    e3, e4 = expj(th3), expj(th4)
    c1, c2 = 1j * b * e3, -1j * c * e4  # the Jacobian's columns, with their derivatives
    A = a * e2
    w3, w4 = solve_pair(c1, c2, -1j * w2 * A)
    h3, h4 = solve_pair(c1, c2, -1j * A)  # kinematic coefficients (unit input speed)
    k_acc = -(1j * a2 - w2 * w2) * A + b * w3 * w3 * e3 - c * w4 * w4 * e4
    al3, al4 = solve_pair(c1, c2, k_acc)
    B = A + b * e3
    values = {
        "theta3": th3, "theta4": th4, "omega3": w3, "omega4": w4, "alpha3": al3, "alpha4": al4,
        "A": A, "B": B, "B_velocity": 1j * w4 * c * e4,
    }  # fmt: skip
    if coupler is not None:
        p, delta = coupler
        arm = p * expj(th3 + delta)
        values["coupler"] = A + arm
        values["coupler_velocity"] = 1j * w2 * A + 1j * w3 * arm
        values["coupler_acceleration"] = (1j * a2 - w2 * w2) * A + (1j * al3 - w3 * w3) * arm
    if torque is not None:
        values["T12"] = _fourbar_torque(
            (e2, e3, e4), A, (w3, w4, al3, al4, h3, h4), w2, a2, *torque, m
        )
    return values


def _fourbar_torque(e, A, rates, w2, a2, mass, inertia, cg, gravity, load, unit, m):
    """``T12`` by virtual work, as duals (the kinematic coefficients of ``virtual_work``)."""
    from ._validate import finite_scalar
    from .dynamics import link_properties

    props = link_properties(mass, inertia, cg, unit)
    g = _gravity_vector(gravity)
    load = finite_scalar("load", load)
    e2, e3, e4 = e
    w3, w4, al3, al4, h3, h4 = rates
    omega = (w2, w3, w4)
    alpha = (a2, al3, al4)
    coef = (1.0, h3, h4)
    origin_acc = (0.0, (1j * a2 - w2 * w2) * A, 0.0)
    origin_rate = (0.0, 1j * A, 0.0)
    frames = (e2, e3, e4)
    torque = lift(np.zeros(np.shape(e2.v)), m)
    for k in range(3):
        mk, ik, ck = props.mass[k], props.inertia[k], props.cg[k]
        arm = ck * frames[k]
        if mk:
            acc = origin_acc[k] + (1j * alpha[k] - omega[k] * omega[k]) * arm
            rate = origin_rate[k] + 1j * coef[k] * arm
            force = mk * acc - mk * g
            torque = torque + (force.conj() * rate).real
        if ik:
            torque = torque + ik * alpha[k] * coef[k]
    return torque - load * h4


def _gravity_vector(gravity: Any) -> complex:
    """The acceleration of gravity as a vector in the model's frame.

    A number ``g ≥ 0`` acts along −y (``−j g``); a complex number is the vector itself
    (a four-bar placed at θ1 in the plane, gravity along the plane's −y:
    ``−j g e^{−jθ1}``).

    Examples
    --------
    >>> _gravity_vector(9.81)
    -9.81j
    """
    from ._validate import complex_scalar, nonnegative

    if isinstance(gravity, complex | np.complexfloating):
        return complex_scalar("gravity", gravity)
    return -1j * nonnegative("gravity", gravity)


def _slidercrank(sc, theta2, omega2, alpha2, form, mass, inertia, cg, gravity, load):
    from .slidercrank import STATUS_REASONS

    theta, w2, a2 = _sweep(theta2, omega2, alpha2)
    motion = sc.solve(theta, w2, a2, form)
    names = ("crank", "coupler", "offset") + (("p", "delta") if sc.point is not None else ())
    m = len(names)
    a, b, c = (Dual.seed(np.full(theta.shape, v), k, m) for k, v in enumerate((sc.a, sc.b, sc.c)))
    e2 = expj(Dual.constant(theta, m))
    th3 = Dual.constant(motion.theta3, m)
    d = Dual.constant(motion.d, m)
    one = lift(np.full(theta.shape, -1.0 + 0j), m)
    F = a * e2 - b * expj(th3) - 1j * c - d
    c1 = -1j * b * expj(th3)
    dth3, dd = solve_pair(lift(c1.v, m), one, -F)
    th3, d = Dual(motion.theta3, dth3.d), Dual(motion.d, dd.d)
    e3 = expj(th3)
    c1 = -1j * b * e3
    A = a * e2
    w3, d_dot = solve_pair(c1, one, -1j * w2 * A)
    h3, h_d = solve_pair(c1, one, -1j * A)
    al3, d_ddot = solve_pair(c1, one, -(1j * a2 - w2 * w2) * A - b * w3 * w3 * e3)
    values = {
        "theta3": th3, "d": d, "omega3": w3, "d_dot": d_dot, "alpha3": al3, "d_ddot": d_ddot,
        "A": A, "B": d + 1j * c,
    }  # fmt: skip
    if sc.point is not None:
        p = Dual.seed(np.full(theta.shape, sc.point[0]), 3, m)
        delta = Dual.seed(np.full(theta.shape, sc.point[1]), 4, m)
        arm = -p * e3 * expj(delta)
        values["coupler"] = A + arm
        values["coupler_velocity"] = 1j * w2 * A + 1j * w3 * arm
        values["coupler_acceleration"] = (1j * a2 - w2 * w2) * A + (1j * al3 - w3 * w3) * arm
    if mass is not None:
        values["T12"] = _slider_torque(
            sc, (e2, e3), A, (w3, al3, h3, d_ddot, h_d), w2, a2, mass, inertia, cg, gravity, load, m
        )
    return names, values, motion, np.asarray(motion.status).ravel(), STATUS_REASONS


def _slider_torque(sc, e, A, rates, w2, a2, mass, inertia, cg, gravity, load, m):
    """A slider-crank's ``T12`` by virtual work, as duals."""
    from ._validate import finite_scalar, nonnegative
    from .dynamics import link_properties

    masses = tuple(mass)
    if len(masses) != 3:
        raise InputError("mass", "give (m2, m3, m4): crank, rod, slider")
    inertias = tuple(inertia)
    cgs = tuple(cg)
    props = link_properties(masses, (*inertias, 0.0), (*cgs, 0.0), sc.length_unit)
    g = nonnegative("gravity", gravity)
    load = finite_scalar("load", load)
    e2, e3 = e
    w3, al3, h3, d_ddot, h_d = rates
    rod = -e3  # the rod's frame: origin A, x toward B
    (m2, m3, m4), (i2, i3, _), (c2, c3, _) = props.mass, props.inertia, props.cg
    torque = lift(np.zeros(np.shape(e2.v)), m)
    if m2:
        arm = c2 * e2
        force = m2 * (1j * a2 - w2 * w2) * arm + 1j * (m2 * g)
        torque = torque + (force.conj() * (1j * arm)).real
    if m3:
        arm = c3 * rod
        acc = (1j * a2 - w2 * w2) * A + (1j * al3 - w3 * w3) * arm
        force = m3 * acc + 1j * (m3 * g)
        torque = torque + (force.conj() * (1j * A + 1j * h3 * arm)).real
    torque = torque + i2 * a2 + i3 * al3 * h3
    return torque + (m4 * d_ddot - load) * h_d
