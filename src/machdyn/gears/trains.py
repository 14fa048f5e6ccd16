"""Gear trains: simple, compound, reverted, planetary; belts and chains as rolling pairs.

Sign convention (Norton Ch. 9, gear trains): the *train value* is ``m_V = ω_out / ω_in``,
the product of the stage ratios, each ``−N_driver / N_driven`` for an
external mesh and ``+N_driver / N_driven`` for an internal mesh. Belts and
chains are rolling pairs of the same kind: an open belt or a chain keeps the
sense of rotation (``+d_1 / d_2``), a crossed belt reverses it.

Planetary (epicyclic) trains are solved two independent ways:

* Willis' formula (Norton Ch. 9, "formula method"): with the arm's speed ``ω_A``,
  ``(ω_L − ω_A) / (ω_F − ω_A) = R``, ``R`` the train value from the first to
  the last gear with the arm held fixed;
* the tabular method (Norton Ch. 9): every member's motion is the sum of a
  rotation of the whole train with the arm and a rotation relative to the arm;
  two known speeds (any members, the arm included, a fixed member has speed 0)
  fix both columns.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validate import (
    TINY,
    boolean,
    broadcast,
    choice,
    finite_array,
    finite_scalar,
    integer,
    items,
    positive,
)
from ..errors import InputError
from .interference import max_gear_teeth

__all__ = [
    "MESH_KINDS",
    "GearTrain",
    "PlanetaryTable",
    "PlanetaryTrain",
    "RevertedTrain",
    "belt_ratio",
    "chain_ratio",
    "reverted_compound",
    "simple_train_value",
    "sprocket_pitch_diameter",
    "stage_ratio",
    "train_value",
    "willis",
]

#: Kinds of rolling pairs and the sign of their velocity ratio.
MESH_KINDS: dict[str, float] = {
    "external": -1.0,
    "internal": 1.0,
    "open_belt": 1.0,
    "crossed_belt": -1.0,
    "chain": 1.0,
}


def stage_ratio(driver: ArrayLike, driven: ArrayLike, kind: str = "external") -> Any:
    """Signed velocity ratio ``ω_driven / ω_driver`` of one rolling pair.

    ``driver`` and ``driven`` are tooth numbers (gears, sprockets) or pitch
    diameters/radii (friction wheels, pulleys).

    Examples
    --------
    >>> stage_ratio(20, 60), stage_ratio(20, 60, "internal")
    (-0.3333333333333333, 0.3333333333333333)
    """
    sign = MESH_KINDS[choice("kind", kind, MESH_KINDS)]
    a, b = finite_array("driver", driver), finite_array("driven", driven)
    for name, value in (("driver", a), ("driven", b)):
        if np.any(value < TINY):
            raise InputError(name, "tooth numbers and diameters must be positive")
    broadcast(driver=a, driven=b)
    out = sign * a / b
    return out if np.ndim(out) else float(out)


def train_value(stages: Sequence[Sequence[Any]]) -> float:
    """Train value ``m_V = ω_out / ω_in`` of a compound train, sign included.

    Parameters
    ----------
    stages : sequence of (driver, driven) or (driver, driven, kind)
        Each stage's driver and driven teeth (or diameters), in order from the
        input; ``kind`` is one of :data:`MESH_KINDS` (default ``"external"``).
        Consecutive stages are joined by a shaft (a compound gear).

    Examples
    --------
    Norton's two-stage compound train, 14:54 then 14:56 (both external):

    >>> round(train_value([(14, 54), (14, 56)]), 6)
    0.064815
    >>> train_value([(20, 40), (30, 90, "internal"), (1, 2, "crossed_belt")])
    0.08333333333333333
    """
    stages = items("stages", stages, what="(driver, driven) stages")
    if len(stages) == 0:
        raise InputError("stages", "give at least one (driver, driven) stage")
    value = 1.0
    for i, stage in enumerate(stages):
        if len(stage) not in (2, 3):
            raise InputError(f"stages[{i}]", "expected (driver, driven) or (driver, driven, kind)")
        kind = stage[2] if len(stage) == 3 else "external"
        value *= stage_ratio(stage[0], stage[1], kind)
    return float(value)


def simple_train_value(teeth: Sequence[int]) -> float:
    """Train value of a simple train of external gears in a row.

    Only the first and last gears count; each idler flips the sign:
    ``m_V = (−1)^(n−1) N_first / N_last``.

    Examples
    --------
    >>> simple_train_value([20, 35, 17, 40])
    -0.5
    """
    n = [integer(f"teeth[{i}]", t, minimum=1) for i, t in enumerate(items("teeth", teeth))]
    if len(n) < 2:
        raise InputError("teeth", "a train needs at least two gears")
    return train_value(list(itertools.pairwise(n)))


def belt_ratio(
    driver_diameter: ArrayLike, driven_diameter: ArrayLike, crossed: bool = False
) -> Any:
    """``ω_driven / ω_driver = ± d_1 / d_2`` of a belt drive without slip (rolling pair).

    Examples
    --------
    >>> belt_ratio(100, 250), belt_ratio(100, 250, crossed=True)
    (0.4, -0.4)
    """
    kind = "crossed_belt" if boolean("crossed", crossed) else "open_belt"
    return stage_ratio(driver_diameter, driven_diameter, kind)


def chain_ratio(driver_teeth: ArrayLike, driven_teeth: ArrayLike) -> Any:
    """``ω_driven / ω_driver = N_1 / N_2`` of a chain drive (same sense of rotation).

    Examples
    --------
    >>> chain_ratio(17, 51)
    0.3333333333333333
    """
    _whole("driver_teeth", driver_teeth)
    _whole("driven_teeth", driven_teeth)
    return stage_ratio(driver_teeth, driven_teeth, "chain")


def _whole(field: str, teeth: ArrayLike) -> None:
    """Tooth numbers are whole: 17.5 teeth is a typo (or a diameter), not a sprocket."""
    n = finite_array(field, teeth)
    if np.any(n != np.round(n)):
        raise InputError(field, f"tooth numbers must be whole numbers, got {teeth!r}")


def sprocket_pitch_diameter(pitch: ArrayLike, teeth: ArrayLike) -> Any:
    """Pitch diameter of a chain sprocket, ``d = p / sin(180° / N)``.

    Examples
    --------
    A 17-tooth sprocket for 1/2-in roller chain:

    >>> round(sprocket_pitch_diameter(0.5, 17), 4)
    2.7211
    """
    p, n = finite_array("pitch", pitch), finite_array("teeth", teeth)
    _whole("teeth", n)
    if np.any(p <= 0):
        raise InputError("pitch", "a sprocket needs a positive chain pitch")
    if np.any(n < 3):
        raise InputError("teeth", "a sprocket needs at least 3 teeth")
    broadcast(pitch=p, teeth=n)
    out = p / np.sin(np.pi / n)
    return out if np.ndim(out) else float(out)


# --------------------------------------------------------------------------
# Reverted compound trains
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class RevertedTrain:
    """A two-stage reverted compound train (input and output shafts coaxial).

    Attributes
    ----------
    teeth : tuple of int
        ``(N2, N3, N4, N5)``: pinion 2 drives gear 3, which shares a shaft
        with pinion 4, which drives gear 5. ``N2 + N3 = N4 + N5`` (equal
        centre distances with one module).
    ratio : float
        Achieved ``ω_in / ω_out = (N3 N5) / (N2 N4)`` (positive: two external
        meshes).
    target : float
        Requested ratio.
    error : float
        Relative error ``ratio / target − 1``.

    Examples
    --------
    >>> t = RevertedTrain((18, 84, 21, 81), 18.0, 18.0, 0.0)
    >>> t.tooth_sum, t.center_distance(2.5)
    (102, 127.5)
    """

    teeth: tuple[int, int, int, int]
    ratio: float
    target: float
    error: float

    @property
    def train_value(self) -> float:
        """``m_V = ω_out / ω_in = 1 / ratio``."""
        return 1.0 / self.ratio

    @property
    def tooth_sum(self) -> int:
        """``N2 + N3 = N4 + N5``, proportional to the centre distance."""
        return self.teeth[0] + self.teeth[1]

    def to_pandas(self) -> Any:
        """Return the train as a pandas Series (teeth, ratio, target, error, tooth sum).

        Examples
        --------
        >>> s = RevertedTrain((18, 84, 21, 81), 18.0, 18.0, 0.0).to_pandas()
        >>> int(s["N3"]), float(s["ratio"]), int(s["tooth_sum"])
        (84, 18.0, 102)
        """
        import pandas as pd

        n2, n3, n4, n5 = self.teeth
        return pd.Series(
            {
                "N2": n2,
                "N3": n3,
                "N4": n4,
                "N5": n5,
                "tooth_sum": self.tooth_sum,
                "ratio": self.ratio,
                "train_value": self.train_value,
                "target": self.target,
                "error": self.error,
            },
            dtype=object,
        )

    def center_distance(self, module: float) -> float:
        """Return the common centre distance ``m (N2 + N3) / 2`` for a module.

        Examples
        --------
        >>> RevertedTrain((18, 84, 21, 81), 18.0, 18.0, 0.0).center_distance(2.0)
        102.0
        """
        return positive("module", module) * self.tooth_sum / 2


def reverted_compound(
    ratio: float,
    *,
    min_teeth: int = 12,
    max_teeth: int = 100,
    tolerance: float = 1e-3,
    pressure_angle: float = math.radians(20.0),
    k: float = 1.0,
) -> RevertedTrain:
    """Search tooth numbers of a two-stage reverted compound train for a ratio.

    All ``(N2, N3, N4, N5)`` with ``min_teeth <= N <= max_teeth``,
    ``N2 + N3 = N4 + N5`` and no interference in either mesh (the notes'
    onset relation with addendum constant ``k`` at ``pressure_angle``) are
    scanned at once (vectorised). The closest ratio wins; among equally close
    ones, the smallest tooth sum (the most compact train).

    Parameters
    ----------
    ratio : float
        Target ``ω_in / ω_out`` (> 1 reduces speed; < 1 steps it up).
    min_teeth, max_teeth : int
        Tooth-number limits of every gear.
    tolerance : float, default 1e-3
        Largest acceptable relative ratio error.
    pressure_angle : float, default 20°
        Pressure angle (rad) for the interference check.
    k : float, default 1
        Addendum constant for the interference check.

    Raises
    ------
    InputError
        If no train within the limits reaches the target within ``tolerance``.

    Examples
    --------
    An 18:1 reverted train (the kind of design problem Norton sets in Ch. 9):

    >>> t = reverted_compound(18)
    >>> t.teeth, t.ratio
    ((18, 84, 21, 81), 18.0)
    """
    target = positive("ratio", ratio)
    lo = integer("min_teeth", min_teeth, minimum=3)
    hi = integer("max_teeth", max_teeth, minimum=lo)
    tol = positive("tolerance", tolerance)
    if hi - lo > 400:
        raise InputError("max_teeth", "search at most 400 tooth numbers (max - min)")
    reach = (hi / lo) ** 2
    if not 1 / reach * (1 - tol) <= target <= reach * (1 + tol):
        raise InputError(
            "ratio",
            f"{target:g} is impossible with {lo}..{hi} teeth: two stages reach at most"
            f" {reach:g}:1 (and at least 1:{reach:g}); allow more teeth or add a stage",
        )
    pinion = np.arange(lo, hi + 1, dtype=float)  # driver of a stage
    total = np.arange(2 * lo, 2 * hi + 1, dtype=float)  # N_driver + N_driven
    driven = total[:, None] - pinion[None, :]
    small, large = np.minimum(pinion, driven), np.maximum(pinion, driven)
    ok = (driven >= lo) & (driven <= hi)
    ok &= np.asarray(max_gear_teeth(small.clip(lo), pressure_angle, k)) >= large
    stage = np.where(ok, driven / pinion, np.nan)  # ω_in/ω_out of a stage, per (sum, pinion)
    product = stage[:, :, None] * stage[:, None, :]
    err = np.abs(product / target - 1.0)
    err = np.where(np.isnan(err), np.inf, err)
    best = float(err.min())
    if not best <= tol:
        raise InputError(
            "ratio",
            f"{target:g} cannot be reached within {tol:g} with {lo}..{hi} teeth free of"
            " interference; widen the limits or the tolerance",
        )
    # Smallest tooth sum among the best (errors equal to round-off).
    candidates = np.argwhere(err <= best + 1e-12)
    s_i, a_i, b_i = candidates[np.lexsort((candidates[:, 1], candidates[:, 0]))[0]]
    n2, n4 = int(pinion[a_i]), int(pinion[b_i])
    s = int(total[s_i])
    n3, n5 = s - n2, s - n4
    achieved = n3 * n5 / (n2 * n4)
    return RevertedTrain((n2, n3, n4, n5), achieved, target, achieved / target - 1.0)


# --------------------------------------------------------------------------
# Planetary trains
# --------------------------------------------------------------------------
def willis(
    train_value: ArrayLike,
    *,
    first: ArrayLike | None = None,
    last: ArrayLike | None = None,
    arm: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """Solve Willis' formula ``(ω_L − ω_A) / (ω_F − ω_A) = R`` for the missing speed.

    Give exactly two of ``first``, ``last``, ``arm`` (a fixed member has
    speed 0); arrays broadcast.

    Parameters
    ----------
    train_value : array_like
        ``R``, the train value from the first to the last gear with the arm
        fixed (sign included).
    first, last, arm : array_like, optional
        Angular velocities ``ω_F``, ``ω_L``, ``ω_A``.

    Returns
    -------
    ndarray
        The missing angular velocity.

    Examples
    --------
    Norton Example 9-7: sun 40 T, planet 20 T, ring 80 T, so ``R = (−40/20)(20/80)
    = −0.5``; arm −200 rpm, sun +100 rpm:

    >>> float(willis(-0.5, first=100, arm=-200))
    -350.0
    """
    r = finite_array("train_value", train_value)
    given = {k: v for k, v in (("first", first), ("last", last), ("arm", arm)) if v is not None}
    if len(given) != 2:
        raise InputError("first", "give exactly two of first, last and arm")
    speeds = {k: finite_array(k, v) for k, v in given.items()}
    broadcast(train_value=r, **speeds)
    if "arm" not in given:
        f, lst = speeds["first"], speeds["last"]
        if np.any(r == 1.0):
            raise InputError("train_value", "R = 1 locks the train: the arm speed is undefined")
        return (lst - r * f) / (1.0 - r)
    a = speeds["arm"]
    if "last" not in given:
        return a + r * (speeds["first"] - a)
    if np.any(r == 0.0):
        raise InputError("train_value", "R = 0 cannot be inverted")
    return a + (speeds["last"] - a) / r


@dataclass(frozen=True)
class PlanetaryTable:
    """The tabular method's table: motion with the arm plus motion relative to the arm.

    Attributes
    ----------
    members : tuple of str
        Member names (the arm included, as ``"arm"``).
    with_arm : ndarray
        Column 1: every member turns with the arm, ``ω_A``.
    relative : ndarray
        Column 2: arm fixed, ``R_i (ω_F − ω_A)``.
    total : ndarray
        ``ω_i = ω_A + R_i (ω_F − ω_A)``.

    Examples
    --------
    >>> t = PlanetaryTrain.simple(sun=40, planet=20, ring=80).table(ring=0, sun=30)
    >>> t["arm"]
    10.0
    """

    members: tuple[str, ...]
    with_arm: NDArray[np.float64]
    relative: NDArray[np.float64]
    total: NDArray[np.float64]

    def __getitem__(self, member: str) -> float:
        """Total speed of ``member``."""
        return float(self.total[self.members.index(choice("member", member, self.members))])

    def to_pandas(self) -> Any:
        """Return the table as a DataFrame indexed by member.

        Examples
        --------
        >>> t = PlanetaryTrain.simple(sun=40, planet=20, ring=80).table(ring=0, sun=30)
        >>> float(t.to_pandas().loc["arm", "total"])
        10.0
        """
        import pandas as pd

        from ..units import columns, units_of

        data = {"with_arm": self.with_arm, "relative_to_arm": self.relative, "total": self.total}
        system = units_of(self)  # a machine file's train: "total [rpm]"
        if system is not None:
            data = columns(system, [(k, "angular_velocity", v) for k, v in data.items()])
        return pd.DataFrame(data, index=pd.Index(self.members, name="member"))


class PlanetaryTrain:
    """An epicyclic train: a chain of gears carried by an arm.

    Parameters
    ----------
    chain : sequence of (name, teeth) then (name, teeth, connection)
        The gears from the first (a sun or ring on the central axis) to the
        last, each connected to the previous one by ``"external"`` or
        ``"internal"`` mesh, or ``"shaft"`` (a compound planet: same speed).
        Names must be unique and not ``"arm"``.

    Examples
    --------
    Norton Examples 9-6 (tabular) and 9-7 (formula): sun 40, planet 20,
    ring 80; arm −200 rpm, sun +100 rpm:

    >>> train = PlanetaryTrain.simple(sun=40, planet=20, ring=80)
    >>> train.train_value
    -0.5
    >>> train.speeds(arm=-200, sun=100)["ring"]
    -350.0
    >>> train.speeds(ring=0, sun=1)["arm"]  # ring fixed: N_s / (N_s + N_r)
    0.3333333333333333
    """

    def __init__(self, chain: Sequence[Sequence[Any]]) -> None:
        chain = items("chain", chain, what="(name, teeth[, connection]) entries")
        if len(chain) < 2:
            raise InputError("chain", "a planetary train needs at least two gears")
        names: list[str] = []
        ratios: list[float] = []
        teeth_prev = None
        for i, link in enumerate(chain):
            link = items(f"chain[{i}]", link, what="values (name, teeth[, connection])")
            if len(link) not in (2, 3) or (i == 0) != (len(link) == 2):
                raise InputError(
                    f"chain[{i}]",
                    "the first entry is (name, teeth); the others (name, teeth, connection)",
                )
            name = str(link[0])
            if name == "arm" or name in names:
                raise InputError(f"chain[{i}]", f"member name {name!r} is reserved or repeated")
            n = integer(f"chain[{i}].teeth", link[1], minimum=3)
            if i == 0:
                ratio = 1.0
            else:
                kind = choice(f"chain[{i}].connection", link[2], ("external", "internal", "shaft"))
                ratio = ratios[-1] * (1.0 if kind == "shaft" else stage_ratio(teeth_prev, n, kind))
            names.append(name)
            ratios.append(ratio)
            teeth_prev = n
        #: The chain as given: ``(name, teeth)`` then ``(name, teeth, connection)``.
        self.chain: tuple[tuple[Any, ...], ...] = tuple(
            (str(link[0]), int(link[1]), *(() if i == 0 else (str(link[2]),)))
            for i, link in enumerate(chain)
        )
        self.members: tuple[str, ...] = (*names, "arm")
        #: ``R_i``: speed of each member relative to the arm per unit of the first's (arm fixed).
        self.ratios: dict[str, float] = dict(zip(names, ratios, strict=True)) | {"arm": 0.0}
        self.first, self.last = names[0], names[-1]

    @classmethod
    def simple(cls, sun: int, planet: int, ring: int) -> PlanetaryTrain:
        """Sun, planet and ring gear (members ``sun``, ``planet``, ``ring``, ``arm``).

        The ring must satisfy ``N_r = N_s + 2 N_p`` for the gears to fit with
        one module.
        """
        s, p, r = (
            integer(k, v, minimum=3) for k, v in (("sun", sun), ("planet", planet), ("ring", ring))
        )
        if r != s + 2 * p:
            raise InputError("ring", f"must have N_s + 2 N_p = {s + 2 * p} teeth to fit, got {r}")
        return cls([("sun", s), ("planet", p, "external"), ("ring", r, "internal")])

    @property
    def train_value(self) -> float:
        """``R`` from the first to the last gear with the arm fixed (Willis)."""
        return self.ratios[self.last]

    def table(self, **known: float) -> PlanetaryTable:
        """Tabular method: the table from two known member speeds (a fixed member is 0).

        Examples
        --------
        >>> t = PlanetaryTrain.simple(sun=40, planet=20, ring=80).table(arm=-200, sun=100)
        >>> t["ring"], t["planet"]
        (-350.0, -800.0)
        """
        if len(known) != 2:
            raise InputError(
                "known", f"give exactly two speeds among {', '.join(self.members)}; got {known}"
            )
        (m1, w1), (m2, w2) = known.items()
        r1 = self.ratios[choice("member", m1, self.members)]
        r2 = self.ratios[choice("member", m2, self.members)]
        w1, w2 = finite_scalar(m1, w1), finite_scalar(m2, w2)
        if math.isclose(r1, r2, rel_tol=1e-12, abs_tol=1e-15):
            raise InputError(
                m2,
                f"{m1} and {m2} always turn together relative to the arm; give another member",
            )
        # Columns: with-arm a = ω_A and relative b = ω_F − ω_A; ω_i = a + R_i b.
        a, b = np.linalg.solve(np.array([[1.0, r1], [1.0, r2]]), np.array([w1, w2]))
        ratios = np.array([self.ratios[m] for m in self.members])
        relative = ratios * b
        from ..units import with_units

        table = PlanetaryTable(self.members, np.full(ratios.size, a), relative, a + relative)
        return with_units(table, getattr(self, "units", None))  # a machine file's: [rpm]

    def speeds(self, **known: float) -> dict[str, float]:
        """Return all member speeds (the arm included) from two known ones.

        Examples
        --------
        >>> PlanetaryTrain.simple(sun=40, planet=20, ring=80).speeds(arm=1, ring=1)["sun"]
        1.0
        """
        table = self.table(**known)
        return {m: float(w) for m, w in zip(table.members, table.total, strict=True)}

    def ratio(self, driver: str, driven: str, fixed: str) -> float:
        """``ω_driven / ω_driver`` with member ``fixed`` held still.

        Examples
        --------
        >>> PlanetaryTrain.simple(sun=40, planet=20, ring=80).ratio("sun", "arm", fixed="ring")
        0.3333333333333333
        """
        driver, driven, fixed = (
            choice(name, value, self.members)
            for name, value in (("driver", driver), ("driven", driven), ("fixed", fixed))
        )
        if len({driver, driven, fixed}) != 3:
            raise InputError("fixed", "driver, driven and fixed must be three different members")
        return self.speeds(**{fixed: 0.0, driver: 1.0})[choice("driven", driven, self.members)]

    def to_spec(self, name: str = "planetary") -> dict[str, Any]:
        """The train as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from ..spec import model_spec

        return model_spec(self, "planetary", name)

    def __repr__(self) -> str:
        return f"PlanetaryTrain(members={self.members}, train_value={self.train_value:g})"


class GearTrain:
    """A simple or compound train: stages of rolling pairs from the input shaft to the output.

    Parameters
    ----------
    stages : sequence of (driver, driven) or (driver, driven, kind)
        Each stage: the tooth numbers (or pitch diameters) of the driving and
        the driven member, and the kind of pair (a key of :data:`MESH_KINDS`:
        ``"external"`` by default, ``"internal"``, belts, chain). The driven
        member of a stage shares its shaft with the driver of the next.

    Examples
    --------
    Two external stages 18:54 and 20:60 (Norton's compound train): ``m_V = (18/54)(20/60)``.

    >>> train = GearTrain([(18, 54), (20, 60)])
    >>> round(train.train_value, 12), train.speeds(1800.0)
    (0.111111111111, (1800.0, -600.0, 200.0))
    """

    def __init__(self, stages: Sequence[Sequence[Any]]) -> None:
        if isinstance(stages, str) or not isinstance(stages, Sequence) or not stages:
            raise InputError("stages", "give at least one stage (driver, driven[, kind])")
        out = []
        for i, stage in enumerate(stages):
            field = f"stages[{i}]"
            if (
                isinstance(stage, str)
                or not isinstance(stage, Sequence)
                or len(stage) not in (2, 3)
            ):
                raise InputError(
                    field, f"expected (driver, driven) or (driver, driven, kind), got {stage!r}"
                )
            kind = choice(f"{field}.kind", stage[2] if len(stage) == 3 else "external", MESH_KINDS)
            a = positive(f"{field}.driver", stage[0])
            b = positive(f"{field}.driven", stage[1])
            out.append((a, b, kind))
        self.stages: tuple[tuple[float, float, str], ...] = tuple(out)

    @property
    def train_value(self) -> float:
        """``m_V = ω_out / ω_in``: the product of the stages' signed ratios."""
        return float(np.prod([stage_ratio(a, b, kind) for a, b, kind in self.stages]))

    def speeds(self, omega_in: float) -> tuple[float, ...]:
        """The speed of every shaft, the input first, for an input speed ``omega_in``."""
        omega = finite_scalar("omega_in", omega_in)
        out = [omega]
        for a, b, kind in self.stages:
            out.append(out[-1] * stage_ratio(a, b, kind))
        return tuple(float(w) for w in out)

    def to_spec(self, name: str = "gear_train") -> dict[str, Any]:
        """The train as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from ..spec import model_spec

        return model_spec(self, "gear_train", name)

    def __repr__(self) -> str:
        stages = ", ".join(
            f"{a:g}:{b:g}" + ("" if k == "external" else f" {k}") for a, b, k in self.stages
        )
        return f"GearTrain({stages}; m_V = {self.train_value:.6g})"
