"""Forces and torques of gears: tooth loads of a mesh, torques of trains by power balance.

Ideal gearing (no friction loss): power is conserved through every mesh, so a
shaft turning at ω carries the torque ``P / ω`` (Norton, *Design of
Machinery*, Ch. 9 and §12.x on gear forces). Signs: a torque is the external
torque applied *to* a member, positive in the sense of positive ω; its power
``T ω`` is positive where power enters the train (a driver) and negative where
it leaves (a load), and the powers of all external torques add to zero.

* :func:`mesh_forces` — the tooth load of a pair along the line of action:
  tangential ``W_t = T_p / r_p'``, radial ``W_r = W_t tan φ'``, total
  ``W = W_t / cos φ'`` (``r_p'`` the operating pitch radius, ``φ'`` the
  operating pressure angle).
* :func:`train_power` — every shaft of a simple or compound train: speed, the
  torque it transmits, the power; the load torque on the output shaft.
* :func:`planetary_power` — the external torques on the three central members
  of an epicyclic train (first gear, last gear, arm) from one of them. With
  Willis' ``ω_L − ω_A = R (ω_F − ω_A)``, ``Σ T ω = 0`` for every motion gives
  ``T_F = −R T_L`` and ``T_A = −(1 − R) T_L`` (and so ``Σ T = 0``: the train's
  moment balance).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._summary import Summarized
from .._validate import choice, finite_scalar, mapping
from ..errors import InputError

__all__ = [
    "MeshForces",
    "PlanetaryPower",
    "TrainPower",
    "mesh_forces",
    "planetary_power",
    "train_power",
]


@dataclass(frozen=True)
class MeshForces(Summarized):
    """The tooth load of a gear pair transmitting a torque (ideal: no friction).

    Attributes
    ----------
    torque_pinion, torque_gear : float
        Magnitudes of the torques on the pinion and on the gear (``W_t r'``).
    tangential, radial, total : float
        ``W_t`` (along the pitch-circle tangent), ``W_r`` (towards each centre)
        and ``W`` (along the line of action).
    pressure_angle : float
        The operating pressure angle ``φ'`` (rad) the load acts at.
    """

    torque_pinion: float
    torque_gear: float
    tangential: float
    radial: float
    total: float
    pressure_angle: float


def mesh_forces(pair: Any, torque: float, member: str = "pinion") -> MeshForces:
    """Tangential, radial and total tooth load of a pair transmitting ``torque``.

    Parameters
    ----------
    pair : GearPair
    torque : float
        The torque on ``member`` (its magnitude is used).
    member : {"pinion", "gear"}
        Which member's torque is given.

    Examples
    --------
    The final exam's pair (24/60 teeth, P_d = 8, 20°) with 300 lbf·in on the pinion:
    ``W_t = 300 / 1.5 = 200`` lbf, ``W_r = 200 tan 20° = 72.8`` lbf.

    >>> from machdyn.gears import Gear, GearPair
    >>> f = mesh_forces(GearPair(Gear(24, diametral_pitch=8), Gear(60, diametral_pitch=8)), 300.0)
    >>> round(f.tangential, 6), round(f.radial, 2), round(f.torque_gear, 6)
    (200.0, 72.79, 750.0)
    """
    from .mesh import GearPair

    if not isinstance(pair, GearPair):
        raise InputError("pair", f"expected a machdyn.gears.GearPair, got {type(pair).__name__}")
    t = abs(finite_scalar("torque", torque))
    member = choice("member", member, ("pinion", "gear"))
    rp, rg = pair.operating_pitch_radii
    phi = pair.operating_pressure_angle
    wt = t / (rp if member == "pinion" else rg)
    return MeshForces(wt * rp, wt * rg, wt, wt * math.tan(phi), wt / math.cos(phi), phi)


@dataclass(frozen=True)
class TrainPower(Summarized):
    """Speeds, torques and power of every shaft of a simple or compound train.

    Attributes
    ----------
    speeds : ndarray
        Shaft speeds, the input first (``GearTrain.speeds``).
    torques : ndarray
        The torque each shaft transmits, ``P / ω`` (the input torque on the
        input shaft; on the output shaft the torque it delivers to the load).
    power : float
        ``P = T_in ω_in``, the power through every stage.
    load_torque : float
        The external torque on the output shaft, ``−P / ω_out`` (the load).
    """

    speeds: np.ndarray
    torques: np.ndarray
    power: float
    load_torque: float


def train_power(train: Any, omega_in: float, torque_in: float) -> TrainPower:
    """Every shaft's speed and torque of a :class:`GearTrain` by power balance (ideal train).

    Examples
    --------
    Norton's compound train 18:54 then 20:60 at 1800 rpm (188.5 rad/s) with 10 N·m in:
    the output turns 200 rpm and must be held by −90 N·m (``m_V = 1/9``).

    >>> from machdyn.gears import GearTrain
    >>> p = train_power(GearTrain([(18, 54), (20, 60)]), 188.5, 10.0)
    >>> p.torques.round(6).tolist(), round(p.load_torque, 6)
    ([10.0, -30.0, 90.0], -90.0)
    """
    from .trains import GearTrain

    if not isinstance(train, GearTrain):
        raise InputError("train", f"expected a machdyn.gears.GearTrain, got {type(train).__name__}")
    w_in = finite_scalar("omega_in", omega_in)
    if w_in == 0.0:
        raise InputError("omega_in", "a train at rest transmits no power: give a non-zero speed")
    t_in = finite_scalar("torque_in", torque_in)
    speeds = np.asarray(train.speeds(w_in))
    if np.any(speeds == 0.0):
        raise InputError("omega_in", f"{w_in:g} is too small: a shaft's speed rounds to 0")
    power = t_in * w_in
    torques = power / speeds
    return TrainPower(speeds, torques, float(power), float(-torques[-1]))


@dataclass(frozen=True)
class PlanetaryPower(Summarized):
    """External torques and powers of an epicyclic train's central members.

    Attributes
    ----------
    members : tuple of str
        Every member, the arm last (``PlanetaryTrain.members``).
    speeds : ndarray
        Every member's speed (the tabular method).
    torques : ndarray
        The external torque on each member; 0 on the planets (they carry none).
    power : ndarray
        ``T ω`` of each member (positive: power enters the train there).
    """

    members: tuple[str, ...]
    speeds: np.ndarray
    torques: np.ndarray
    power: np.ndarray

    def __getitem__(self, member: str) -> float:
        """The external torque on ``member``."""
        return float(self.torques[self.members.index(choice("member", member, self.members))])


def planetary_power(
    train: Any, speeds: Mapping[str, float], torque: Mapping[str, float]
) -> PlanetaryPower:
    """The torques on the first gear, the last gear and the arm from one of them.

    Parameters
    ----------
    train : PlanetaryTrain
    speeds : mapping
        Two known member speeds (as :meth:`PlanetaryTrain.table` takes them).
    torque : mapping
        One entry: the external torque on the first gear, the last gear or the arm.

    Examples
    --------
    Norton Example 9-6 (sun 40, planet 20, ring 80; arm −200 rpm, sun +100 rpm)
    with 10 units of torque driving the sun: ``R = −1/2``, so the ring takes
    ``T_L = −T_F / R = 20`` and the arm ``−(1 − R) T_L = −30``.

    >>> from machdyn.gears import PlanetaryTrain
    >>> train = PlanetaryTrain.simple(sun=40, planet=20, ring=80)
    >>> p = planetary_power(train, {"arm": -200.0, "sun": 100.0}, {"sun": 10.0})
    >>> p["ring"], p["arm"], p["planet"], float(p.power.sum())
    (20.0, -30.0, 0.0, 0.0)
    """
    from .trains import PlanetaryTrain

    if not isinstance(train, PlanetaryTrain):
        raise InputError(
            "train", f"expected a machdyn.gears.PlanetaryTrain, got {type(train).__name__}"
        )
    speeds = mapping("speeds", speeds, "speeds (two of them)")
    torque = mapping("torque", torque, "torques (one of them)")
    if len(torque) != 1:
        raise InputError("torque", f"give the torque on one member, got {len(torque)}")
    ((member, value),) = torque.items()
    central = (train.first, train.last, "arm")
    member = choice("torque", member, central)
    value = finite_scalar(f"torque[{member}]", value)
    table = train.table(**speeds)
    r = train.train_value
    if member == train.last:
        t_last = value
    elif member == train.first:
        t_last = -value / r
    else:
        if math.isclose(r, 1.0, rel_tol=0.0, abs_tol=1e-15):
            raise InputError("torque", "R = 1: the arm carries no torque; give the first or last")
        t_last = -value / (1.0 - r)
    by_member = {train.first: -r * t_last, train.last: t_last, "arm": -(1.0 - r) * t_last}
    torques = np.array([by_member.get(m, 0.0) for m in train.members]) + 0.0
    return PlanetaryPower(train.members, table.total, torques, torques * table.total)
