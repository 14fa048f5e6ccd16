"""The scene: what a drawing of a mechanism shows, frame by frame, with no renderer in it.

A :class:`Scene` is built from a *solved* motion (never from geometry recomputed
here): per frame, the coordinates of every named point the solver returned,
the angles of the bodies that carry drawn outlines (a cam, a gear, a slider
block on a turning guide), and a readout of the quantities worth showing. Its
:class:`Item` list says how to draw them: links as bars or plates, sliders as
blocks on their guides, pins, hatched ground pivots, springs, actuators,
motors, rolling wheels, rigid outlines (cams, gear teeth), static curves
(a coupler curve, a target path) and marked targets.

Two back ends render a scene: :mod:`machdyn.draw.mpl` (matplotlib: PNG, SVG,
GIF, MP4) and :mod:`machdyn.draw.html` (an inline SVG and a self-contained
page). Every model draws through this one description.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["KINDS", "Curve", "Item", "Readout", "Scene", "drawing_size", "is_static"]

#: What an :class:`Item` can be, and which fields it uses.
KINDS = {
    "ground": "a hatched ground pivot at points[0]",
    "guide": "a slide line through points[0] and points[1] (ground hatching if body is 'ground')",
    "bar": "a link drawn as a thick line from points[0] to points[1]",
    "plate": "a link with three or more joints: a filled polygon through points",
    "pin": "pin joints at every one of points (white circles)",
    "point": "marked points (coupler points, tracer points)",
    "slider": "a block centred on points[0], along the direction angle[frame]",
    "shape": "a rigid outline (complex, body frame) placed at points[0], turned by angle",
    "spring": "a zigzag from points[0] to points[1]",
    "damper": "a dashpot from points[0] to points[1]",
    "actuator": "a cylinder from points[0] with its rod reaching points[1]",
    "motor": "a motor symbol at points[0]",
    "wheel": "a circle of radius size on points[0], with a spoke turned by angle",
    "line": "a thin line from points[0] to points[1] (line of action, offset arm)",
}


@dataclass(frozen=True)
class Item:
    """One drawn thing of a :class:`Scene`.

    Attributes
    ----------
    kind : str
        One of :data:`KINDS`.
    gid : str
        Identifier of the drawn element (matplotlib gid, SVG id): letters,
        digits, ``_`` and ``-`` only.
    points : tuple of str
        Names of the scene's points it is drawn through.
    body : str
        Name of the body it belongs to (the user's; escaped when rendered).
    colour : str
        A CSS/matplotlib colour.
    angle : str, optional
        Key of :attr:`Scene.angles` (radians per frame) for sliders, shapes, wheels.
    outline : ndarray of complex, optional
        A shape's outline in its body frame (placed at ``points[0]``, turned by ``angle``).
    size : float
        A slider block's length, a wheel's radius (drawing units); 0 for a default.
    label : str
        Text shown with it (the user's; escaped when rendered).
    closed : bool
        Whether a shape's outline is closed (filled).
    """

    kind: str
    gid: str
    points: tuple[str, ...] = ()
    body: str = ""
    colour: str = "#444444"
    angle: str | None = None
    outline: np.ndarray | None = field(default=None, repr=False)
    size: float = 0.0
    label: str = ""
    closed: bool = True

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise InputError("kind", f"must be one of {', '.join(KINDS)}, got {self.kind!r}")


@dataclass(frozen=True)
class Curve:
    """A static polyline (coupler curve, target path): NaN entries are gaps."""

    gid: str
    points: np.ndarray = field(repr=False)
    colour: str = "#d62728"
    label: str = ""
    style: str = "line"  # "line", "dashed" or "markers" (numbered target points)


@dataclass(frozen=True)
class Readout:
    """A quantity shown for every frame: ``label`` (``unit``) = ``values[frame]``."""

    label: str
    unit: str
    values: np.ndarray = field(repr=False)
    digits: int = 2


@dataclass(frozen=True)
class Scene:
    """A mechanism drawn over frames: solved point coordinates and how to draw them.

    Attributes
    ----------
    title : str
    names : tuple of str
        Point names (the user's), one column of :attr:`xy` each.
    xy : ndarray of complex, shape (frames, points)
        Solved coordinates; NaN where a point has no position in a frame.
    shown : ndarray of bool, shape (frames,)
        Frames whose pose was assembled (others show the reason).
    reason : ndarray of str, shape (frames,)
        Why a frame is not shown, or why its rates are undefined ('' where fine).
    items : tuple of Item
        Drawn in this order (later on top).
    angles : mapping of str to ndarray
        Angles (radians, per frame) used by sliders, shapes and wheels.
    curves : tuple of Curve
        Static curves drawn behind the mechanism.
    readout : tuple of Readout
        Quantities listed beside the drawing.
    length_unit : str
        Unit of the coordinates ('' when the model has none).
    closed : bool
        Whether the frames make a cycle (playback wraps without a jump).
    note : str
        A line shown under the title (e.g. why nothing can be assembled).

    Examples
    --------
    >>> import numpy as np
    >>> s = Scene(title="a crank", names=("O", "A"),
    ...           xy=np.array([[0, 1], [0, 1j]], dtype=complex),
    ...           items=(Item("bar", "crank", ("O", "A")), Item("ground", "O_ground", ("O",))))
    >>> len(s), complex(s.point("A")[1])
    (2, 1j)
    """

    title: str
    names: tuple[str, ...]
    xy: np.ndarray = field(repr=False)
    items: tuple[Item, ...] = ()
    shown: np.ndarray | None = field(default=None, repr=False)
    reason: np.ndarray | None = field(default=None, repr=False)
    angles: Mapping[str, np.ndarray] = field(default_factory=dict, repr=False)
    curves: tuple[Curve, ...] = ()
    readout: tuple[Readout, ...] = ()
    length_unit: str = ""
    closed: bool = True
    note: str = ""

    def __post_init__(self) -> None:
        xy = np.atleast_2d(np.asarray(self.xy, dtype=complex))
        if xy.ndim != 2 or xy.shape[1] != len(self.names):
            raise InputError(
                "xy", f"must have one column per point name ({len(self.names)}), got {xy.shape}"
            )
        if len(set(self.names)) != len(self.names):
            raise InputError("names", "point names must be distinct")
        object.__setattr__(self, "xy", xy)
        frames = xy.shape[0]
        shown = np.ones(frames, bool) if self.shown is None else np.asarray(self.shown, bool)
        reason = np.full(frames, "", object) if self.reason is None else np.asarray(self.reason)
        if shown.shape != (frames,) or reason.shape != (frames,):
            raise InputError("shown", f"shown and reason need one entry per frame ({frames})")
        object.__setattr__(self, "shown", shown)
        object.__setattr__(self, "reason", reason.astype(object))
        angles = {
            k: np.broadcast_to(np.asarray(v, float), (frames,)) for k, v in self.angles.items()
        }
        object.__setattr__(self, "angles", angles)
        known = set(self.names)
        for item in self.items:
            missing = [p for p in item.points if p not in known]
            if missing:
                raise InputError("items", f"{item.gid!r} names unknown point(s) {missing}")
            if item.angle is not None and item.angle not in angles:
                raise InputError("items", f"{item.gid!r} needs angle {item.angle!r}")

    def __len__(self) -> int:
        return int(self.xy.shape[0])

    def index(self, name: str) -> int:
        """Column of point ``name`` in :attr:`xy`."""
        return self.names.index(name)

    def point(self, name: str) -> np.ndarray:
        """Coordinates of point ``name`` in every frame (complex)."""
        return self.xy[:, self.index(name)]

    @property
    def size(self) -> float:
        """The drawing's typical size: the larger span of everything drawn."""
        return drawing_size(self)

    def extent(self, pad: float = 0.08) -> tuple[float, float, float, float]:
        """``(xmin, xmax, ymin, ymax)`` enclosing every frame, curve and outline, padded."""
        pts = _all_points(self)
        if pts.size == 0:
            return (-1.0, 1.0, -1.0, 1.0)
        span = max(float(np.ptp(pts.real)), float(np.ptp(pts.imag)), 1e-9)
        # room for the ground symbols hanging under their pivots (6 % of the drawing)
        grounds = [self.resting(i.points[0]) for i in self.items if i.kind == "ground"]
        grounds = [z for z in grounds if np.isfinite(z)]
        if grounds:
            below = min(z.imag for z in grounds) - 0.065 * span
            pts = np.append(pts, complex(pts.real.min(), min(below, pts.imag.min())))
        p = pad * span
        return (
            float(pts.real.min() - p),
            float(pts.real.max() + p),
            float(pts.imag.min() - p),
            float(pts.imag.max() + p),
        )

    def first_shown(self) -> int:
        """The first frame with a pose (0 if none)."""
        hits = np.flatnonzero(self.shown)
        return int(hits[0]) if hits.size else 0

    def resting(self, name: str) -> complex:
        """A point's coordinates in the first frame where it has them (static items)."""
        z = self.point(name)
        good = np.flatnonzero(np.isfinite(z))
        return complex(z[good[0]]) if good.size else complex(np.nan, np.nan)

    def frames(self, index: Sequence[int] | np.ndarray) -> Scene:
        """The same scene restricted to some frames (e.g. one pose for a still)."""
        idx = np.asarray(index, dtype=int)
        return Scene(
            title=self.title,
            names=self.names,
            xy=self.xy[idx],
            items=self.items,
            shown=self.shown[idx],
            reason=self.reason[idx],
            angles={k: v[idx] for k, v in self.angles.items()},
            curves=self.curves,
            readout=tuple(
                Readout(r.label, r.unit, np.asarray(r.values)[idx], r.digits) for r in self.readout
            ),
            length_unit=self.length_unit,
            closed=self.closed and idx.size == len(self),
            note=self.note,
        )


def _outline_reach(item: Item) -> float:
    if item.kind == "shape" and item.outline is not None and item.outline.size:
        return float(np.nanmax(np.abs(item.outline)))
    if item.kind == "wheel":
        return float(item.size)
    return 0.0


def _all_points(scene: Scene) -> np.ndarray:
    shown = scene.xy[scene.shown] if scene.shown.any() else scene.xy
    pts = [shown.ravel()]
    for c in scene.curves:
        pts.append(np.ravel(c.points))
    for item in scene.items:
        reach = _outline_reach(item)
        if reach > 0 and item.points:
            centre = scene.point(item.points[0])
            centre = centre[np.isfinite(centre)]
            if centre.size:
                lo = complex(centre.real.min(), centre.imag.min())
                hi = complex(centre.real.max(), centre.imag.max())
                pts.append(np.array([lo - reach * (1 + 1j), hi + reach * (1 + 1j)]))
    allp = np.concatenate(pts) if pts else np.zeros(0, complex)
    return allp[np.isfinite(allp)]


def is_static(scene: Scene, item: Item) -> bool:
    """An item that does not move: its points and angle are the same in every frame."""
    if item.angle is not None and np.ptp(np.nan_to_num(scene.angles[item.angle])) > 0:
        return False
    for p in item.points:
        z = scene.point(p)
        if not np.all(np.isfinite(z)) or np.ptp(z.real) > 0 or np.ptp(z.imag) > 0:
            return False
    return True


def drawing_size(scene: Scene) -> float:
    """The larger span (x or y) of everything a scene draws, for symbol sizes.

    Examples
    --------
    >>> import numpy as np
    >>> s = Scene("t", ("O", "A"), np.array([[0, 4 + 1j]]))
    >>> drawing_size(s)
    4.0
    """
    pts = _all_points(scene)
    if pts.size == 0:
        return 1.0
    return max(float(np.ptp(pts.real)), float(np.ptp(pts.imag)), 1e-9)


def as_frames(values: Any, frames: int) -> np.ndarray:
    """A per-frame float array (broadcast from a scalar)."""
    return np.broadcast_to(np.asarray(values, dtype=float), (frames,)).copy()
