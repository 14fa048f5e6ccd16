"""The index form of a loop system and its groups (block-triangular decomposition).

:class:`Compiled` is what :class:`machdyn.loops.LoopSystem` hands to the numeric
core: plain index arrays, no names to look up. :func:`groups` splits the
unknowns into the diagonal blocks of the Jacobian's block-triangular form
(Dulmage–Mendelsohn; Duff & Reid, *ACM TOMS* 4, 1978): a perfect matching of
equations to unknowns, then the strongly connected components of the
"needs the unknown solved by" graph, in an order where every group only needs
groups before it. For a linkage these are its Assur groups as the loops see
them: a four-bar's dyad, then the next dyad of a six-bar, a constant-angle
constraint on its own, a triad as one larger group. The sign of each group's
determinant is the group's branch (assembly mode): :mod:`machdyn.loops.solve`
keeps it per group along a sweep.
"""

from __future__ import annotations

import graphlib
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ._linalg import BlockFactor, BlockPlan, block_factor, block_plan

__all__ = ["Compiled", "Group"]

#: Group kinds. A "dyad" is one loop with two unknowns and two roots of opposite
#: determinant sign (circle–circle, circle–line or a vector's own angle and length),
#: so the sign alone says which root; :mod:`machdyn.loops._branches` maps one root
#: to the other in closed form. "linear" groups have one root. "general" groups
#: (triads, groups joined by rolling constraints) may have more roots of one sign.
DYAD_ANGLES, DYAD_SLIDE, DYAD_SAME, LINEAR, GENERAL = (
    "dyad (two angles)",
    "dyad (angle and slide)",
    "dyad (angle and length of one vector)",
    "linear",
    "general",
)


@dataclass(frozen=True)
class Group:
    """One diagonal block of the block-triangular Jacobian (internal).

    ``rows`` are equation indices, ``cols`` positions in ``q`` (the unknowns in
    ``Compiled.unknown`` order), ``names`` the unknowns' names. For dyads,
    ``loop`` is the loop index and ``angle``/``length`` the variable indices of
    the two unknowns (``length`` is the second angle for two-angle dyads).
    """

    rows: tuple[int, ...]
    cols: tuple[int, ...]
    names: tuple[str, ...]
    kind: str
    loop: int = -1
    angle: int = -1
    length: int = -1

    @property
    def identified_by_sign(self) -> bool:
        """Whether the determinant's sign alone tells this group's roots apart."""
        return self.kind != GENERAL

    @property
    def label(self) -> str:
        """``"theta5, theta6"``: how messages name the group."""
        return ", ".join(self.names)


@dataclass(frozen=True)
class Compiled:
    """Index form of a loop system (built by ``LoopSystem``; not user facing).

    Attributes
    ----------
    names : tuple of str
        All variables; rows of the state array ``X``.
    unknown, inputs : ndarray of int
        Indices of unknown and input variables in ``names``.
    length_const, angle_const : ndarray, shape (n_vec,)
        Constant length / angle of each vector (ignored where a variable).
    length_var, angle_var : ndarray of int, shape (n_vec,)
        Variable index of each vector's length / angle, or -1 when constant.
    loops : ndarray, shape (n_loop, n_vec)
        Signed coefficients of the vectors in each loop.
    con : ndarray, shape (n_con, n_var); con0 : ndarray, shape (n_con,)
        Linear constraints ``con @ X + con0 = 0``.
    points : ndarray, shape (n_point, n_vec)
        Signed coefficients of the vector chain of each point.
    scale : float
        Characteristic length (mean constant length) for relative tolerances.
    var_scale : ndarray, shape (n_var,)
        1 for angle variables, ``scale`` for length variables.
    """

    names: tuple[str, ...]
    unknown: np.ndarray
    inputs: np.ndarray
    length_const: np.ndarray
    angle_const: np.ndarray
    length_var: np.ndarray
    angle_var: np.ndarray
    loops: np.ndarray
    con: np.ndarray
    con0: np.ndarray
    points: np.ndarray
    scale: float
    var_scale: np.ndarray

    @property
    def n_eq(self) -> int:
        """Number of scalar equations."""
        return 2 * self.loops.shape[0] + self.con.shape[0]

    @cached_property
    def loop_terms(self) -> tuple[tuple[tuple[int, float], ...], ...]:
        """Per loop, the (vector index, sign) pairs with a non-zero sign."""
        return tuple(
            tuple((int(k), float(row[k])) for k in np.flatnonzero(row)) for row in self.loops
        )

    @cached_property
    def jq_scales(self) -> tuple[np.ndarray, np.ndarray]:
        """Static row and column multipliers that make ``J_q``'s entries O(1)."""
        return self.row_weight, self.var_scale[self.unknown]

    @cached_property
    def row_weight(self) -> np.ndarray:
        """Weights that make every residual row dimensionless (loop rows / scale)."""
        con_w = 1.0 / np.maximum.reduce(
            [np.ones(len(self.con0)), np.abs(self.con0), np.abs(self.con) @ self.var_scale]
        )
        return np.concatenate([np.full(2 * self.loops.shape[0], 1.0 / self.scale), con_w])

    @cached_property
    def jq_pattern(self) -> np.ndarray:
        """Which unknowns each equation may touch, shape (n_eq, n_q), bool."""
        col = self.unknown_row
        pattern = np.zeros((self.n_eq, len(col)), dtype=bool)
        for l_idx, terms in enumerate(self.loop_terms):
            for k, _ in terms:
                for v in (int(self.angle_var[k]), int(self.length_var[k])):
                    if v in col:
                        pattern[2 * l_idx : 2 * l_idx + 2, col[v]] = True
        if self.con.shape[0]:
            pattern[2 * self.loops.shape[0] :] = self.con[:, self.unknown] != 0
        return pattern

    @cached_property
    def unknown_row(self) -> dict[int, int]:
        """Row of each unknown (by variable index) in ``q``."""
        return {int(v): i for i, v in enumerate(self.unknown)}

    @cached_property
    def angle_names(self) -> tuple[str, ...]:
        """The variables that are angles (plotted in degrees), in variable order."""
        return tuple(self.names[i] for i in np.unique(self.angle_var[self.angle_var >= 0]))

    @cached_property
    def angle_rows(self) -> np.ndarray:
        """Rows of ``q`` that hold angles (defined up to whole turns)."""
        angles = set(self.angle_var[self.angle_var >= 0].tolist())
        return np.array([i for i, v in enumerate(self.unknown) if int(v) in angles], dtype=int)

    @cached_property
    def groups(self) -> tuple[Group, ...]:
        """The Jacobian's diagonal blocks in solving order (see :func:`groups`)."""
        return groups(self)

    @cached_property
    def group_parity(self) -> float:
        """``det J_q = parity · Π det(group block)`` (the sign of the two permutations)."""
        rows = [r for g in self.groups for r in g.rows]
        cols = [q for g in self.groups for q in g.cols]
        return float(_parity(rows) * _parity(cols))

    @cached_property
    def plan(self) -> BlockPlan:
        """How :meth:`factor` factors ``J_q`` group by group."""
        blocks = [(g.rows, g.cols) for g in self.groups]
        return block_plan(blocks, self.jq_pattern, *self.jq_scales, self.group_parity)

    def factor(self, jac_q: np.ndarray) -> BlockFactor:
        """``J_q`` (n_eq, n_q, N) factored along the groups (:func:`block_factor`)."""
        return block_factor(jac_q, self.plan)

    @cached_property
    def scalar(self) -> Any:
        """The plain-float twin of the equations for one pose (``_newton.Scalar``)."""
        from ._newton import Scalar

        return Scalar(self)

    @cached_property
    def kernel_arrays(self) -> tuple:
        """The model as plain arrays for the compiled sweep (``_jit_sweep.arrays``)."""
        from ._jit_sweep import arrays

        return arrays(self)

    @cached_property
    def kernel_dyads(self) -> tuple:
        """The groups' closed-form data for the compiled sweep (``_jit_sweep.dyad_arrays``)."""
        from ._jit_sweep import dyad_arrays

        return dyad_arrays(self)

    @cached_property
    def kernel_sweepable(self) -> bool:
        """Whether the compiled sweep can follow the model (``_jit_sweep.sweepable``)."""
        from ._jit_sweep import sweepable

        return sweepable(self)

    @cached_property
    def input_names(self) -> tuple[str, ...]:
        """The inputs' names, in the order of ``inputs``."""
        return tuple(self.names[i] for i in self.inputs)

    @cached_property
    def unknown_names(self) -> tuple[str, ...]:
        """The unknowns' names, in the order of ``unknown`` (the rows of ``q``)."""
        return tuple(self.names[i] for i in self.unknown)

    @cached_property
    def group_names(self) -> tuple[tuple[str, ...], ...]:
        """Each group's unknowns (``Group.names``), in solving order."""
        return tuple(g.names for g in self.groups)

    @cached_property
    def sign_identified(self) -> bool:
        """True when every group's determinant sign identifies its root."""
        return all(g.identified_by_sign for g in self.groups)


def _parity(perm: list[int]) -> int:
    """Sign of a permutation (by counting inversions; the lists are short)."""
    inversions = sum(1 for i, a in enumerate(perm) for b in perm[i + 1 :] if a > b)
    return -1 if inversions % 2 else 1


def groups(c: Compiled) -> tuple[Group, ...]:
    """Block-triangular decomposition of ``J_q``'s sparsity into groups, in solving order.

    A maximum matching of equations to unknowns (``scipy.sparse.csgraph``), the
    strongly connected components of the graph "equation i uses the unknown
    matched to equation j", and a topological order of those components
    (``graphlib``): each group's equations involve only its own unknowns and
    those of earlier groups. A structurally singular pattern (no perfect
    matching; ``LoopSystem.check`` refuses such models first) gives one group.
    """
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components, maximum_bipartite_matching

    pattern = c.jq_pattern
    n = pattern.shape[1]
    if n == 0:
        return ()
    names = [c.names[int(v)] for v in c.unknown]
    match = maximum_bipartite_matching(csr_matrix(pattern.astype(np.int8)), perm_type="column")
    if pattern.shape[0] != n or (match < 0).any():
        rows, cols = tuple(range(pattern.shape[0])), tuple(range(n))
        return (Group(rows, cols, tuple(names), GENERAL),)
    needs = pattern[:, match]  # needs[i, j]: equation i uses the unknown matched to j
    np.fill_diagonal(needs, False)
    n_comp, label = connected_components(csr_matrix(needs), directed=True, connection="strong")
    deps: dict[int, set[int]] = {k: set() for k in range(n_comp)}
    for i, j in zip(*np.nonzero(needs), strict=True):
        if label[i] != label[j]:
            deps[int(label[i])].add(int(label[j]))
    order = list(graphlib.TopologicalSorter(deps).static_order())
    out = []
    for comp in order:
        rows = tuple(int(r) for r in np.flatnonzero(label == comp))
        cols = tuple(sorted(int(match[r]) for r in rows))
        out.append(_classify(c, rows, cols, tuple(names[q] for q in cols)))
    return tuple(out)


def _classify(
    c: Compiled, rows: tuple[int, ...], cols: tuple[int, ...], names: tuple[str, ...]
) -> Group:
    """Tell dyads (and which kind), linear and general groups apart."""
    block_vars = {int(c.unknown[q]) for q in cols}
    n_loop_rows = 2 * c.loops.shape[0]
    loops = sorted({r // 2 for r in rows if r < n_loop_rows})
    angle_unknowns = {
        int(c.angle_var[k])
        for l_idx in loops
        for k, _ in c.loop_terms[l_idx]
        if int(c.angle_var[k]) in block_vars
    }
    if not angle_unknowns:
        return Group(rows, cols, names, LINEAR)
    if len(rows) != 2 or len(loops) != 1:
        return Group(rows, cols, names, GENERAL)
    l_idx = loops[0]
    terms = c.loop_terms[l_idx]
    v1, v2 = (int(c.unknown[q]) for q in cols)
    if angle_unknowns == {v1, v2}:  # two angles: both must sit on vectors of known length
        if any(int(c.length_var[k]) in block_vars for k, _ in terms):
            return Group(rows, cols, names, GENERAL)
        return Group(rows, cols, names, DYAD_ANGLES, l_idx, v1, v2)
    (a,) = angle_unknowns
    d = v2 if a == v1 else v1
    with_d = [k for k, _ in terms if int(c.length_var[k]) == d]
    if any(int(c.length_var[k]) == a for k, _ in terms) or not with_d:
        return Group(rows, cols, names, GENERAL)
    if all(int(c.angle_var[k]) == a for k in with_d):
        if sum(s for k, s in terms if int(c.length_var[k]) == d) == 0.0:
            return Group(rows, cols, names, GENERAL)
        return Group(rows, cols, names, DYAD_SAME, l_idx, a, d)
    if all(int(c.angle_var[k]) not in block_vars for k in with_d) and not any(
        int(c.length_var[k]) == d for k, _ in terms if int(c.angle_var[k]) == a
    ):
        return Group(rows, cols, names, DYAD_SLIDE, l_idx, a, d)
    return Group(rows, cols, names, GENERAL)
