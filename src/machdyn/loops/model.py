"""The vector-loop model: vectors, loops, constraints, points — and :class:`LoopSystem`.

This is the notes' method written down as a library (review lecture 3,
"position analysis"; Norton, *Design of Machinery*, §4.5 and §4.13): each link
is a vector ``R = d·e^{jθ}`` whose length ``d`` and angle ``θ`` are constants
or named variables; each independent circuit of the mechanism gives a vector
loop ``Σ ±R = 0`` (two scalar equations); vectors of one link that sit in
different loops are tied by a constant-angle constraint such as
``theta3p = theta3 + alpha``; sliders add length variables, and linear
constraints like ``d3 + d4 = dbar`` or rolling ``r2*theta2 + r3*theta3 = c``
add one scalar equation each.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from .._validate import boolean, finite_array, finite_scalar, integer, mapping
from .._validate import names as name_list
from ..errors import InputError, ModelError
from . import solve as _solve
from ._equations import derivatives, point_motion, residual_and_jacobian
from ._parse import parse_linear, parse_signed_sum
from .result import Motion, SystemReport, blank

__all__ = ["LoopSystem", "Vector"]

_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


@dataclass(frozen=True)
class Vector:
    """A planar vector ``length · e^{j·angle}``; each part a float or a variable name."""

    name: str
    length: float | str
    angle: float | str

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _IDENT.match(self.name):
            raise InputError("name", f"a vector name is an identifier like 'R2', got {self.name!r}")
        for field in ("length", "angle"):
            value = getattr(self, field)
            if isinstance(value, str):
                if not _IDENT.match(value):
                    raise InputError(field, f"a variable name is an identifier, got {value!r}")
                continue
            number = finite_scalar(f"{self.name}.{field}", value)
            if field == "length" and number <= 0.0:
                raise InputError(f"{self.name}.length", f"must be a positive length, got {number}")


@dataclass(frozen=True)
class _Constraint:
    text: str
    coefs: dict[str, float]
    c0: float


def _names(items: list[str]) -> str:
    return ", ".join(items) if items else "(none)"


class LoopSystem:
    """A mechanism described by vector loops, linear constraints and named points.

    Build it step by step (each method returns the system, so calls chain), then
    :meth:`check` the counts and :meth:`solve` over arrays of input values.

    Examples
    --------
    The GCRR four-bar of the notes' HW 6 (R1 = 8, R2 = 4, R3 = 7, R4 = 6):

    >>> import numpy as np
    >>> s = LoopSystem()
    >>> s = s.vector("R1", length=8.0, angle=0.0)
    >>> s = s.vector("R2", length=4.0, angle="theta2")
    >>> s = s.vector("R3", length=7.0, angle="theta3")
    >>> s = s.vector("R4", length=6.0, angle="theta4")
    >>> s = s.loop("R2 + R3 - R4 - R1").point("B", "R2 + R3").inputs("theta2")
    >>> print(s.check())  # doctest: +ELLIPSIS
    3 variables, 2 equations: DOF 1
    variables: theta2, theta3, theta4
    inputs: theta2
    ...
    >>> m = s.solve({"theta2": np.radians([0.0, 45.0, 90.0])},
    ...             guess={"theta3": 0.5, "theta4": 1.5}, velocity={"theta2": 10.0})
    >>> np.degrees(m["theta3"]).round(2).tolist()
    [58.81, 25.98, 15.47]
    >>> bool(m.ok.all())
    True
    """

    def __init__(self) -> None:
        self._vectors: dict[str, Vector] = {}
        self._loops: list[tuple[str, dict[str, int]]] = []
        self._constraints: list[_Constraint] = []
        self._points: dict[str, tuple[str, dict[str, int]]] = {}
        self._inputs: tuple[str, ...] = ()
        self._cache: dict[tuple[str, ...], tuple[SystemReport, _solve.Compiled]] = {}

    # ------------------------------------------------------------------ building
    def vector(self, name: str, length: float | str, angle: float | str) -> LoopSystem:
        """Define vector ``name = length · e^{j·angle}``.

        Parameters
        ----------
        name : str
            A Python-style identifier such as ``"R3p"``.
        length : float or str
            A positive constant, or the name of a length variable (a slider).
        angle : float or str
            A constant angle in radians (CCW from +x), or a variable name.

        Examples
        --------
        >>> s = LoopSystem().vector("R6", length="d6", angle=0.0)  # a slider
        """
        if not isinstance(name, str) or not _IDENT.match(name):
            raise InputError("name", f"a vector name must be an identifier like 'R2', got {name!r}")
        if name in self._vectors:
            raise ModelError(f"vector {name} is defined twice")
        parts: list[float | str] = []
        for field, value in (("length", length), ("angle", angle)):
            if isinstance(value, str):
                if not _IDENT.match(value):
                    raise InputError(
                        f"{name}.{field}", f"a variable name must be an identifier, got {value!r}"
                    )
                parts.append(value)
            else:
                number = finite_scalar(f"{name}.{field}", value)
                if field == "length" and number <= 0.0:
                    raise InputError(f"{name}.length", f"must be a positive length, got {number}")
                parts.append(number)
        self._vectors[name] = Vector(name, parts[0], parts[1])
        self._cache.clear()
        return self

    def loop(self, text: str) -> LoopSystem:
        """Add a vector loop such as ``"R2 + R3 - R4 - R1"`` (optionally ``= 0``).

        Examples
        --------
        >>> s = LoopSystem().loop("-r1 + r2 + r3 = 0")
        """
        self._loops.append((text, parse_signed_sum(text, "loop")))
        self._cache.clear()
        return self

    def constraint(self, text: str, **constants: float) -> LoopSystem:
        """Add a linear constraint among variables, e.g. ``"theta3p = theta3 + alpha"``.

        Names given as keywords are constants; every other name is a variable.

        Examples
        --------
        >>> s = LoopSystem().constraint("r2*theta2 + r3*theta3 = c", r2=2.0, r3=3.0, c=0.0)
        """
        values = {k: finite_scalar(k, v) for k, v in constants.items()}
        coefs, c0 = parse_linear(text, values, "constraint")
        self._constraints.append(_Constraint(text, coefs, c0))
        self._cache.clear()
        return self

    def point(self, name: str, chain: str | None = None) -> LoopSystem:
        """Name a point reached from the origin by a vector chain.

        ``point("P", "R2 + R3p")`` or ``point("P = R2 + R3p")``.

        Examples
        --------
        >>> s = LoopSystem().point("P = R2 + R3p")
        """
        if chain is None:
            if not isinstance(name, str) or "=" not in name:
                raise InputError(
                    "point", f"write 'P = R2 + R3p' or point('P', 'R2 + R3p'), got {name!r}"
                )
            name, chain = (part.strip() for part in name.split("=", 1))
        if not isinstance(name, str) or not _IDENT.match(name):
            raise InputError("point", f"a point name must be an identifier, got {name!r}")
        self._points[name] = (chain, parse_signed_sum(chain, f"point {name}"))
        self._cache.clear()
        return self

    def inputs(self, *names: str) -> LoopSystem:
        """Name the input (driven) variables; several for a multi-DOF mechanism.

        Examples
        --------
        >>> s = LoopSystem().inputs("theta2", "theta5")  # a five-bar with two cranks
        """
        self._inputs = _identifiers("inputs", names)
        self._cache.clear()
        return self

    # ------------------------------------------------------------------ validation
    def _variables(self) -> list[str]:
        used = self._used_vectors()
        out: list[str] = []
        for v in self._vectors.values():
            if v.name not in used:
                continue
            for part in (v.length, v.angle):
                if isinstance(part, str) and part not in out:
                    out.append(part)
        return out

    def _used_vectors(self) -> set[str]:
        used: set[str] = set()
        for _, terms in self._loops:
            used.update(terms)
        for _, terms in self._points.values():
            used.update(terms)
        return used

    def _equation_labels(self) -> list[str]:
        labels = []
        for i, (text, _) in enumerate(self._loops, start=1):
            labels += [f"loop {i} x: {text}", f"loop {i} y: {text}"]
        labels += [f"constraint: {c.text}" for c in self._constraints]
        return labels

    def _structure(self) -> list[str]:
        defined = list(self._vectors)
        for kind, items in (("loop", self._loops), ("point", list(self._points.values()))):
            for text, terms in items:
                missing = [n for n in terms if n not in self._vectors]
                if missing:
                    raise ModelError(
                        f"{kind} {text!r} names unknown vector(s) {_names(missing)}; "
                        f"defined vectors: {_names(defined)}"
                    )
        unused = [n for n in defined if n not in self._used_vectors()]
        if unused:
            raise ModelError(
                f"vector(s) {_names(unused)} appear in no loop and no point; "
                "use them or remove them"
            )
        variables = self._variables()
        for c in self._constraints:
            stray = [n for n in c.coefs if n not in variables]
            if stray:
                raise ModelError(
                    f"constraint {c.text!r}: {_names(stray)} is no variable of any vector "
                    f"(variables: {_names(variables)}); pass constants as keywords"
                )
        return variables

    def _compile(self, inputs: tuple[str, ...]) -> _solve.Compiled:
        variables = self._variables()
        index = {n: i for i, n in enumerate(variables)}
        vec_names = list(self._vectors)
        vecs = [self._vectors[n] for n in vec_names]
        const_lengths = [v.length for v in vecs if not isinstance(v.length, str)]
        scale = float(np.mean(const_lengths)) if const_lengths else 1.0
        length_var = np.array(
            [index.get(v.length, -1) if isinstance(v.length, str) else -1 for v in vecs]
        )
        angle_var = np.array(
            [index.get(v.angle, -1) if isinstance(v.angle, str) else -1 for v in vecs]
        )
        length_const = np.array([0.0 if isinstance(v.length, str) else v.length for v in vecs])
        angle_const = np.array([0.0 if isinstance(v.angle, str) else v.angle for v in vecs])

        def rows(items: list[dict[str, int]]) -> np.ndarray:
            out = np.zeros((len(items), len(vecs)))
            for i, terms in enumerate(items):
                for n, s in terms.items():
                    out[i, vec_names.index(n)] = s
            return out

        con = np.zeros((len(self._constraints), len(variables)))
        for i, c in enumerate(self._constraints):
            for n, coef in c.coefs.items():
                con[i, index[n]] = coef
        var_scale = np.ones(len(variables))
        for i in length_var[length_var >= 0]:
            var_scale[i] = scale
        return _solve.Compiled(
            names=tuple(variables),
            unknown=np.array([index[n] for n in variables if n not in inputs], dtype=int),
            inputs=np.array([index[n] for n in inputs], dtype=int),
            length_const=length_const,
            angle_const=angle_const,
            length_var=length_var,
            angle_var=angle_var,
            loops=rows([t for _, t in self._loops]),
            con=con,
            con0=np.array([c.c0 for c in self._constraints]),
            points=rows([t for _, t in self._points.values()]),
            scale=scale,
            var_scale=var_scale,
        )

    def check(self, inputs: tuple[str, ...] | list[str] | None = None) -> SystemReport:
        """Count equations, variables and inputs; raise :class:`ModelError` on a bad model.

        Checks, in the user's terms: every loop/point names defined vectors, every
        vector is used, constraints mention only variables, the named inputs
        exist and match the degrees of freedom, and the equations are not
        structurally redundant (the Jacobian, evaluated at random poses, has full
        row rank) and determine the unknowns once the inputs are fixed.

        Parameters
        ----------
        inputs : sequence of str, optional
            Overrides the inputs named with :meth:`inputs`.

        Returns
        -------
        SystemReport

        Examples
        --------
        >>> s = (LoopSystem().vector("R1", 8.0, 0.0).vector("R2", 4.0, "theta2")
        ...      .vector("R3", 7.0, "theta3").vector("R4", 6.0, "theta4")
        ...      .loop("R2 + R3 - R4 - R1"))
        >>> s.check().dof
        1
        >>> s.check(inputs=("theta2", "theta3"))  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        machdyn.errors.ModelError: 3 variables, 2 equations: DOF 1, but 2 inputs were named: ...
        """
        inputs = self._inputs if inputs is None else _identifiers("inputs", inputs)
        variables = self._structure()
        labels = self._equation_labels()
        dof = len(variables) - len(labels)
        stray = [n for n in inputs if n not in variables]
        if stray:
            raise ModelError(
                f"input(s) {_names(stray)} appear in no vector; variables: {_names(variables)}"
            )
        if len(set(inputs)) != len(inputs):
            raise ModelError(f"an input is named twice: {', '.join(inputs)}")
        self._check_rank(variables, labels, ())
        if inputs and dof != len(inputs):
            raise ModelError(
                f"{len(variables)} variables, {len(labels)} equations: DOF {dof}, but "
                f"{len(inputs)} input{'s were' if len(inputs) != 1 else ' was'} named: "
                f"{', '.join(inputs)}"
                + (" (over-determined: remove an equation or add a variable)" if dof < 0 else "")
            )
        self._check_rank(variables, labels, inputs)
        groups = tuple(g.names for g in self._compile(inputs).groups) if inputs else ()
        return SystemReport(tuple(labels), tuple(variables), inputs, dof, groups)

    def _check_rank(self, variables: list[str], labels: list[str], inputs: tuple[str, ...]) -> None:
        """Structural rank test at random poses (a singular pose is not structural)."""
        if not labels:
            return
        c = self._compile(inputs)
        rng = np.random.default_rng(12345)
        n_try = 3
        x = rng.uniform(-np.pi, np.pi, (len(variables), n_try))
        is_len = c.var_scale != 1.0
        x[is_len] = rng.uniform(0.5, 1.5, (int(is_len.sum()), n_try)) * c.scale
        cols = np.arange(len(variables))
        _, jac = residual_and_jacobian(c, x, cols)
        jac = jac * c.row_weight[:, None, None] * c.var_scale[None, :, None]
        best_full, best_q = None, None
        for t in range(n_try):
            j_full = jac[:, :, t]
            u, s, _ = np.linalg.svd(j_full)
            rank = int((s > 1e-9 * max(s.max(initial=0.0), 1e-300)).sum())
            if best_full is None or rank > best_full[0]:
                best_full = (rank, u, s)
            if inputs:
                j_q = j_full[:, c.unknown]
                _, sq, vq = np.linalg.svd(j_q)
                rank_q = int((sq > 1e-9 * max(sq.max(initial=0.0), 1e-300)).sum())
                if best_q is None or rank_q > best_q[0]:
                    best_q = (rank_q, vq)
        rank, u, s = best_full
        if rank < len(labels):
            null = u[:, rank:]
            involved = [labels[i] for i in np.flatnonzero(np.abs(null).max(axis=1) > 1e-6)]
            raise ModelError(
                f"redundant formulation: the equations have rank {rank} < {len(labels)} at "
                "every pose, so some are dependent. Involved: "
                + "; ".join(involved)
                + ". (Three vectors of one link, or a constraint implied by the others?)"
            )
        if best_q is not None and best_q[0] < len(c.unknown):
            rank_q, vq = best_q
            null = vq[rank_q:].T
            names = [
                variables[c.unknown[i]] for i in np.flatnonzero(np.abs(null).max(axis=1) > 1e-6)
            ]
            raise ModelError(
                f"with inputs {', '.join(inputs)} the unknowns {_names(names)} are not determined "
                "(Jacobian rank-deficient at every pose): choose other inputs or add constraints"
            )

    def _checked(self, inputs: tuple[str, ...]) -> _solve.Compiled:
        """``check(inputs)`` and compile, cached until the model changes."""
        if inputs not in self._cache:
            report = self.check(inputs)
            self._cache[inputs] = (report, self._compile(inputs))
        return self._cache[inputs][1]

    # ------------------------------------------------------------------ solving
    def _input_arrays(
        self, values: Mapping[str, Any], inputs: tuple[str, ...]
    ) -> tuple[np.ndarray, tuple[int, ...]]:
        missing = [n for n in inputs if n not in values]
        extra = [n for n in values if n not in inputs]
        if missing or extra:
            raise ModelError(
                f"values must be given for exactly {', '.join(inputs)}"
                + (f"; missing: {', '.join(missing)}" if missing else "")
                + (f"; not inputs: {', '.join(extra)}" if extra else "")
            )
        arrays = [finite_array(n, values[n]) for n in inputs]
        try:
            shape = (
                arrays[0].shape
                if len(arrays) == 1
                else np.broadcast_shapes(*(a.shape for a in arrays))
            )
        except ValueError:
            raise InputError(
                "values", f"input arrays of shapes {[a.shape for a in arrays]} do not broadcast"
            ) from None
        n = math.prod(shape)
        u = np.empty((len(arrays), n))
        for i, a in enumerate(arrays):
            u[i] = a.reshape(n) if a.shape == shape else np.broadcast_to(a, shape).reshape(n)
        return u, shape

    @staticmethod
    def _rates(
        field: str, rates: Mapping[str, Any] | None, inputs: tuple[str, ...], shape, required: bool
    ) -> np.ndarray:
        rates = {} if rates is None else dict(rates)
        extra = [n for n in rates if n not in inputs]
        if extra:
            raise ModelError(
                f"{field} given for {', '.join(extra)}, which are not inputs ({', '.join(inputs)})"
            )
        missing = [n for n in inputs if n not in rates]
        if required and missing:
            raise ModelError(f"{field}: no value for input(s) {', '.join(missing)}")
        n = math.prod(shape)
        out = np.zeros((len(inputs), n))
        for i, name in enumerate(inputs):
            if name in rates:
                a = finite_array(f"{field}[{name}]", rates[name])
                try:
                    out[i] = a if a.ndim == 0 else np.broadcast_to(a, shape).reshape(n)
                except ValueError:
                    raise InputError(
                        f"{field}[{name}]", f"shape {a.shape} does not match inputs {shape}"
                    ) from None
        return out

    def solve(
        self,
        values: Mapping[str, Any],
        guess: Mapping[str, Any],
        velocity: Mapping[str, Any] | None = None,
        acceleration: Mapping[str, Any] | None = None,
        jerk: Mapping[str, Any] | None = None,
        *,
        order: int = 3,
        continuation: bool | None = None,
        max_step: float = 0.4,
        tol: float = 1e-12,
    ) -> Motion:
        """Positions (Newton–Raphson) and, optionally, velocity, acceleration and jerk.

        Parameters
        ----------
        values : mapping of str to array_like
            Values of every input variable (radians for angles); arrays broadcast.
            When no inputs were named with :meth:`inputs`, these keys are the inputs.
        guess : mapping of str to float or array_like
            Approximate values of every unknown: they pick the circuit/branch.
        velocity : mapping, optional
            First time derivative of every input (e.g. ``{"theta2": omega2}``).
            Without it no derivatives are computed (``m.velocity is None``).
        acceleration, jerk : mapping, optional
            Second and third time derivatives of inputs; missing ones are 0
            (constant speed).
        order : int
            Derivative orders computed when ``velocity`` is given: 1 velocity,
            2 also acceleration, 3 (default) also jerk.
        continuation : bool, optional
            Treat 1-D inputs as an ordered sweep and follow one branch (default
            for 1-D inputs with more than one sample); False solves every sample
            independently from ``guess``.
        max_step : float
            Largest continuation step between sequentially solved samples, in
            radians (lengths: in units of the mean constant length).
        tol : float
            Largest loop residual (relative to the mean constant length) at
            which a pose counts as closed, between 1e-15 and 1e-6; tighten it to
            refuse poses Newton cannot close that well (near toggles). Every
            pose accepted is polished to the rounding floor whatever ``tol``.

        Returns
        -------
        Motion
            Samples that cannot be assembled, sit at a toggle (singular
            Jacobian) or could not be followed safely have ``ok`` False and a
            ``reason``; their positions (or derivatives) are NaN.

        Examples
        --------
        A triple rocker (4-3-3-2.5) driven past its limit: it assembles only while
        ``|A − O4| ≤ R3 + R4``, i.e. ``cos θ2 ≥ −0.21875`` (θ2 ≤ 102.6°); the other
        inputs are flagged.

        >>> import numpy as np
        >>> s = (LoopSystem().vector("R1", 4.0, 0.0).vector("R2", 3.0, "theta2")
        ...      .vector("R3", 3.0, "theta3").vector("R4", 2.5, "theta4")
        ...      .loop("R2 + R3 - R4 - R1").inputs("theta2"))
        >>> m = s.solve({"theta2": np.radians([60.0, 90.0, 120.0, 150.0])},
        ...             guess={"theta3": 0.0, "theta4": 1.5})
        >>> m.ok.tolist()
        [True, True, False, False]
        >>> str(m.reason[3])
        'cannot assemble: Newton-Raphson did not converge at this input'
        """
        values = mapping("values", values, "input values")
        velocity, acceleration, jerk = _rate_maps(velocity, acceleration, jerk)
        inputs = self._inputs or tuple(values)
        c = self._checked(inputs)
        u, shape = self._input_arrays(values, inputs)
        unknowns = c.unknown_names
        guess = mapping("guess", guess, "approximate values of the unknowns")
        missing = [n for n in unknowns if n not in guess]
        if missing:
            raise ModelError(
                f"no guess for {', '.join(missing)}: a guess picks the branch (circuit) to "
                "follow; give approximate values"
            )
        extra = [n for n in guess if n not in unknowns]
        if extra:
            raise ModelError(
                f"guess given for {', '.join(extra)}, which are not unknowns ({_names(unknowns)})"
            )
        n = u.shape[1]
        q0 = np.empty((len(unknowns), n))
        for i, name in enumerate(unknowns):
            g = finite_array(f"guess[{name}]", guess[name])
            try:
                q0[i] = g if g.ndim == 0 else np.broadcast_to(g, shape).reshape(n)
            except ValueError:
                raise InputError(
                    f"guess[{name}]", f"shape {g.shape} does not match inputs {shape}"
                ) from None
        if continuation is None:
            continuation = len(shape) <= 1 and n > 1
        continuation = boolean("continuation", continuation)
        step = finite_scalar("max_step", max_step)
        if step <= 0:
            raise InputError("max_step", f"must be positive, got {step}")
        tol = _tolerance(tol)
        u_rates = self._input_rates(inputs, shape, velocity, acceleration, jerk, order)
        pos = _solve.solve_positions(
            c, u, q0, continuation, max_step=step, tol=tol, u_rates=u_rates
        )
        if pos.x is not None:  # the compiled sweep's every variable
            x0 = pos.x
        else:
            x0 = np.empty((len(c.names), n))
            x0[c.inputs] = u
            x0[c.unknown] = pos.q
        return self._finish(c, x0, pos.code, pos.residual, shape, u_rates, pos)

    def evaluate(
        self,
        values: Mapping[str, Any],
        velocity: Mapping[str, Any] | None = None,
        acceleration: Mapping[str, Any] | None = None,
        jerk: Mapping[str, Any] | None = None,
        *,
        order: int = 3,
    ) -> Motion:
        """Compute derivatives at a *given* configuration (no position solve).

        The notes' velocity examples give every angle and ask for rates; here
        ``values`` holds every variable, ``velocity`` etc. the inputs' rates. The
        loop-closure residual of the given configuration is reported in
        ``residual`` but not enforced.

        Examples
        --------
        The notes' floating-arm trebuchet (second notes, example 2):

        >>> import numpy as np
        >>> s = (LoopSystem().vector("r1", "d1", np.pi).vector("r2", "d2", -np.pi / 2)
        ...      .vector("r3", 200.0, "theta3").loop("-r1 + r2 + r3").inputs("d2"))
        >>> m = s.evaluate({"d1": 173.2, "d2": 100.0, "theta3": np.radians(150)},
        ...                velocity={"d2": 250.0})
        >>> round(float(m.velocity["d1"]), 1), round(float(m.velocity["theta3"]), 3)
        (-144.3, -1.443)
        """
        values = mapping("values", values, "values of every variable")
        velocity, acceleration, jerk = _rate_maps(velocity, acceleration, jerk)
        inputs = self._inputs
        if not inputs:
            raise ModelError("evaluate needs the inputs named first: call inputs(...)")
        c = self._checked(inputs)
        names = list(c.names)
        x0, shape = self._input_arrays(values, tuple(names))
        f, _ = residual_and_jacobian(c, x0, jacobian=False)
        resid = np.abs(f * c.row_weight[:, None]).max(axis=0) if f.size else np.zeros(x0.shape[1])
        code = np.zeros(x0.shape[1], dtype=np.int8)
        u_rates = self._input_rates(inputs, shape, velocity, acceleration, jerk, order)
        return self._finish(c, x0, code, resid, shape, u_rates)

    def _input_rates(
        self, inputs, shape, velocity, acceleration, jerk, order
    ) -> list[np.ndarray] | None:
        """The inputs' rates (checked), as many orders as asked; None without velocity."""
        order = integer("order", order, minimum=1)
        if order > 3:
            raise InputError(
                "order", f"must be 1, 2 or 3 (velocity, acceleration, jerk), got {order}"
            )
        if velocity is None:
            if acceleration is not None or jerk is not None:
                raise ModelError("acceleration/jerk need the input velocity too (velocity=...)")
            return None
        out = []
        given = (("velocity", velocity), ("acceleration", acceleration), ("jerk", jerk))
        for k, (field, rates) in enumerate(given):
            if k < order or rates is not None:  # rates given beyond ``order`` are checked too
                checked = self._rates(field, rates, inputs, shape, required=k == 0)
                if k < order:
                    out.append(checked)
        return out

    def _finish(self, c, x0, code, resid, shape, u_rates, pos=None) -> Motion:
        inputs = c.input_names
        states = [x0]
        if u_rates is not None:
            rates, det, rcond, gdet, grc = _derivatives(c, x0, u_rates, pos)
            states += rates
        else:
            det, rcond, gdet, grc = _determinants(c, x0, pos)
        group = pos.group.copy() if pos is not None else np.full(x0.shape[1], -1, np.int16)
        singular = ~(rcond >= _solve.SINGULAR_RCOND)  # True where rcond is NaN too
        singular &= code == _solve.OK
        if singular.any() and len(c.unknown):
            code = np.where(singular, _solve.SINGULAR, code)
            if len(c.groups) > 1:
                group[singular] = np.argmin(np.nan_to_num(grc[:, singular], nan=np.inf), axis=0)
        ok = code == _solve.OK
        bad_pos = (code != _solve.OK) & (code != _solve.SINGULAR)
        if pos is not None and pos.points is not None:  # the compiled sweep's: masked already
            pts = list(pos.points)
        else:  # NaN where not assembled (positions) or not ok (rates)
            terms = pos.reuse[0] if pos is not None and pos.reuse is not None else None
            pts = point_motion(c, states, terms)
            mask = [bad_pos] + [~ok] * (len(states) - 1)
            states = [np.where(m, np.nan, a) for a, m in zip(states, mask, strict=True)]
            pts = [np.where(m, np.nan, a) for a, m in zip(pts, mask, strict=True)]
        # read-only stacks: the rows below, views of them, are read-only too
        for a in (*states, *pts):
            a.flags.writeable = False
        per_var = [_by_name(c.names, a, shape) for a in states]
        per_pt = [_by_name(tuple(self._points), a, shape) for a in pts]
        for i, name in zip(c.inputs, inputs, strict=True):  # known even where the pose is not
            value = x0[i].reshape(shape).copy()
            value.flags.writeable = False
            per_var[0][name] = value
        frozen = [MappingProxyType(d) for d in per_var]
        frozen_pts = [MappingProxyType(d) for d in per_pt]
        extra = [None] * (4 - len(frozen))
        branch, signs = _sign(det), _sign(gdet)
        branch[bad_pos] = 0
        signs[:, bad_pos] = 0
        return Motion(
            positions=frozen[0],
            velocity=(frozen + extra)[1],
            acceleration=(frozen + extra)[2],
            jerk=(frozen + extra)[3],
            points=frozen_pts[0],
            point_velocity=(frozen_pts + extra)[1],
            point_acceleration=(frozen_pts + extra)[2],
            point_jerk=(frozen_pts + extra)[3],
            ok=ok.reshape(shape),
            reason=_reasons(c, code, group).reshape(shape),
            residual=np.where(bad_pos, np.nan, resid).reshape(shape),
            branch=branch.reshape(shape),
            inputs=inputs,
            angles=c.angle_names,
            groups=c.group_names,
            group_branch=signs.reshape((len(c.groups), *shape)),
        )


#: The range of ``tol``: below 1e-15 a loop residual cannot be told from rounding;
#: above 1e-6 a pose that does not close would pass as solved.
TOL_RANGE = (1e-15, 1e-6)


def _identifiers(field: str, value: Any) -> tuple[str, ...]:
    """Variable names (identifiers such as ``theta2``) as a tuple."""
    out = name_list(field, value, "variable names")
    bad = [n for n in out if not _IDENT.match(n)]
    if bad:
        raise InputError(field, f"a variable name is an identifier like 'theta2', got {bad[0]!r}")
    return out


def _rate_maps(*rates: Any) -> tuple[dict[str, Any] | None, ...]:
    """velocity, acceleration, jerk: each None or a mapping of input name to rate."""
    fields = ("velocity", "acceleration", "jerk")
    return tuple(
        None if r is None else mapping(f, r, "rates by input name")
        for f, r in zip(fields, rates, strict=True)
    )


def _tolerance(tol: Any) -> float:
    """``tol`` checked: a finite number in :data:`TOL_RANGE`.

    Examples
    --------
    >>> _tolerance(float("inf"))
    Traceback (most recent call last):
    ...
    machdyn.errors.InputError: tol: must be finite, got inf
    """
    value = finite_scalar("tol", tol)
    lo, hi = TOL_RANGE
    if not lo <= value <= hi:
        raise InputError(
            "tol",
            f"must lie between {lo:g} (rounding) and {hi:g} (poses that do not close), "
            f"got {value:g}",
        )
    return value


def _derivatives(c, x0: np.ndarray, u_rates: list[np.ndarray], pos) -> tuple:
    """Rates of every variable and det, rcond, group dets and rconds at ``x0``.

    What the compiled sweep computed already (``pos.rates`` at
    ``pos.rates_done``) is kept; the other samples go to the NumPy stage.
    """
    if pos is None or pos.rates is None:
        reuse = pos.reuse if pos is not None else None
        rates, fac = derivatives(c, x0, u_rates, reuse=reuse)
        return rates, fac.det, fac.rcond, fac.block_det, fac.block_rcond
    if pos.rates_done.all():
        return pos.rates, pos.det, pos.rcond, pos.gdet, pos.grc
    rates = [r.copy() for r in pos.rates]
    det, rcond, gdet, grc = (a.copy() for a in (pos.det, pos.rcond, pos.gdet, pos.grc))
    todo = np.flatnonzero(~pos.rates_done)
    if todo.size:
        sub, fac = derivatives(c, x0[:, todo], [r[:, todo] for r in u_rates])
        for full, part in zip(rates, sub, strict=True):
            full[:, todo] = part
        det[todo], rcond[todo] = fac.det, fac.rcond
        gdet[:, todo], grc[:, todo] = fac.block_det, fac.block_rcond
    return rates, det, rcond, gdet, grc


def _determinants(c, x0: np.ndarray, pos) -> tuple[np.ndarray, ...]:
    """det, rcond and the groups' det and rcond of ``J_q`` at ``x0`` (from ``pos`` if known)."""
    n = x0.shape[1]
    if pos is not None:
        det, rcond, gdet, grc = (a.copy() for a in (pos.det, pos.rcond, pos.gdet, pos.grc))
        todo = np.flatnonzero(np.isnan(rcond))  # accepted without a factorization
    else:
        det, rcond = np.zeros(n), np.zeros(n)
        gdet, grc = np.zeros((len(c.groups), n)), np.zeros((len(c.groups), n))
        todo = np.arange(n)
    if todo.size:
        x = np.nan_to_num(x0[:, todo])
        _, jac = residual_and_jacobian(c, x, c.unknown)
        fac = c.factor(jac)
        det[todo], rcond[todo] = fac.det, fac.rcond
        gdet[:, todo], grc[:, todo] = fac.block_det, fac.block_rcond
    return det, rcond, gdet, grc


def _by_name(names: tuple[str, ...], stack: np.ndarray, shape: tuple[int, ...]) -> dict:
    """``{name: row}`` of ``stack`` (one row per name), each row (a view) shaped ``shape``."""
    if len(shape) == 1:  # the rows have the shape already: iterating gives the views
        return dict(zip(names, stack, strict=True))
    return {name: stack[i].reshape(shape) for i, name in enumerate(names)}


def _sign(a: np.ndarray) -> np.ndarray:
    """The sign of ``a`` as int8 (-1, 0, 1), 0 where NaN.

    Examples
    --------
    >>> _sign(np.array([-2.0, -0.0, 3.0, np.nan])).tolist()
    [-1, 0, 1, 0]
    """
    return (a > 0).view(np.int8) - (a < 0).view(np.int8)


def _reasons(c, code: np.ndarray, group: np.ndarray) -> np.ndarray:
    """Per-sample reason texts; a flag about one group names it (when there are several)."""
    if not code.any():
        return blank(code.shape)
    reasons = np.array(_solve.REASONS, dtype=object)[code]
    named = (group >= 0) & ((code == _solve.LOST) | (len(c.groups) > 1)) & (code != _solve.OK)
    for gi, g in enumerate(c.groups):
        sel = named & (group == gi)
        if sel.any():
            reasons[sel] = [f"{r} (group {g.label})" for r in reasons[sel]]
        sel &= code == _solve.NO_ASSEMBLY
        if sel.any():
            reasons[sel] = f"cannot assemble: group {g.label} cannot close at this input"
    return reasons
