"""Pictures of solved mechanisms: poses, kinematic curves, coupler curves, animations.

This is a front-end: it draws what the models computed (:meth:`FourBar.solve`,
:meth:`FourBar.coupler_curve`, :meth:`SliderCrank.solve`, the instant centres)
and computes no kinematics itself. matplotlib is imported lazily inside each
function, so ``import machdyn.plot`` is cheap and works without it; every
function takes an optional ``ax`` (or ``fig``) and returns what it drew on, and
works with the non-interactive Agg backend.

Drawing conventions: O2 at the origin, the ground line along +x, equal axis
scales; ground pivots are hatched, links are thick lines (input C0, coupler C1,
output C2), pin joints are white circles, the coupler triangle ``A B P`` is
shaded. Every artist that carries data has a ``gid`` (``"link2"``,
``"coupler_curve"``, ...) so that it can be found again (and tested).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ._validate import choice, finite_scalar, integer, positive
from .errors import AssemblyError, InputError
from .fourbar import FourBar, FourBarMotion
from .slidercrank import SliderCrank, SliderCrankMotion

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.animation import FuncAnimation
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "Sweep",
    "animate",
    "draw_fourbar",
    "plot_coupler_curve",
    "plot_kinematics",
    "plot_slider_crank",
    "plot_slider_motion",
    "sweep",
]

#: Colours of the moving links (matplotlib's default cycle), by link number.
_LINK_COLOURS = {2: "C0", 3: "C1", 4: "C2"}
_JOINT_STYLE = {
    "marker": "o",
    "markersize": 7,
    "markerfacecolor": "white",
    "markeredgecolor": "black",
    "linestyle": "none",
    "zorder": 6,
}


# --------------------------------------------------------------------------------------
# Sweeps: which poses an animation or a viewer shows (ordering only; the model solves).


@dataclass(frozen=True)
class Sweep:
    """Poses of a four-bar in the order of an animation, joined from one or more solves.

    Every array has one entry per frame. ``omega2`` changes sign on a rocker's
    return stroke, so the rates are those of the motion actually shown.
    """

    theta2: np.ndarray
    theta3: np.ndarray
    theta4: np.ndarray
    omega2: np.ndarray
    omega3: np.ndarray
    omega4: np.ndarray
    mu: np.ndarray
    A: np.ndarray
    B: np.ndarray
    coupler: np.ndarray | None
    assembled: np.ndarray
    ok: np.ndarray
    reason: np.ndarray

    def __len__(self) -> int:
        return int(self.theta2.size)


def sweep(
    fourbar: FourBar,
    form: int = 1,
    n: int = 120,
    theta2: Any = None,
    omega2: float = 1.0,
) -> Sweep:
    """The poses an animation of ``fourbar`` shows, solved by :meth:`FourBar.solve`.

    Parameters
    ----------
    fourbar : FourBar
    form : {1, 2}
    n : int
        Samples per stroke when ``theta2`` is not given: a crank makes one turn
        in ``n`` frames; a rocker input goes from one limit to the other and
        back, and a GRCR/GRRC form runs along one branch and back along the
        other, so the motion closes (``2n − 2`` frames in both cases).
    theta2 : array_like, optional
        Explicit input angles (radians), solved with ``omega2`` as given.
    omega2 : float
        Input speed on the forward stroke (rad/s); the readouts ω3, ω4 are for it.

    Examples
    --------
    >>> s = sweep(FourBar(8, 4, 7, 6), n=36)
    >>> len(s), bool(s.ok.all())
    (36, True)
    """
    if not isinstance(fourbar, FourBar):
        raise InputError("fourbar", f"expected a FourBar, got {type(fourbar).__name__}")
    choice("form", form, (1, 2))
    omega2 = finite_scalar("omega2", omega2, "radian / second")
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        # A rocker's grid ends exactly at its toggles: the model flags them (status and
        # NaN rates), but its jerk arithmetic there can still raise numpy's inf − inf warning.
        motions = _sweep_motions(fourbar, form, n, theta2, omega2)

    def join(name: str) -> np.ndarray:
        return np.concatenate([np.ravel(getattr(m, name)) for m in motions])

    has_p = motions[0].coupler is not None
    return Sweep(
        theta2=join("theta2"),
        theta3=join("theta3"),
        theta4=join("theta4"),
        omega2=join("omega2"),
        omega3=join("omega3"),
        omega4=join("omega4"),
        mu=join("mu"),
        A=join("A"),
        B=join("B"),
        coupler=join("coupler") if has_p else None,
        assembled=join("assembled"),
        ok=join("ok"),
        reason=join("reason"),
    )


def _sweep_motions(
    fourbar: FourBar, form: int, n: int, theta2: Any, omega2: float
) -> list[FourBarMotion]:
    """The solves that make up a sweep, in the order they are shown."""
    if theta2 is not None:
        return [fourbar.solve(np.ravel(np.asarray(theta2, dtype=float)), omega2, form=form)]
    n = integer("n", n, minimum=2)
    rng = fourbar.input_range(form)
    grid = rng.grid(n)
    back = grid[-2:0:-1]  # the return stroke, without repeating either end
    if rng.full_turn:
        return [fourbar.solve(grid, omega2, form=form)]
    if fourbar.form_rule == "phi34":
        # GRCR/GRRC: the two branches meet at the toggles of links 3 and 4 (the grid's
        # ends), so one branch out and the other back make the closed motion of a form
        return [
            fourbar.solve(grid, omega2, form=form, branch=1),
            fourbar.solve(back, -omega2, form=form, branch=-1),
        ]
    # any other rocker input: there and back on the same form
    return [fourbar.solve(grid, omega2, form=form), fourbar.solve(back, -omega2, form=form)]


# --------------------------------------------------------------------------------------
# Small drawing helpers


def _new_axes(ax: Any) -> Axes:
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    _, ax = plt.subplots()
    return ax


def _ground_pivot(ax: Axes, at: complex, size: float, gid: str) -> list[Any]:
    """A hatched ground symbol under a pivot: a triangle on a hatched strip."""
    from matplotlib.patches import Polygon, Rectangle

    x, y = at.real, at.imag
    tri = Polygon(
        [(x, y), (x - 0.6 * size, y - size), (x + 0.6 * size, y - size)],
        closed=True,
        facecolor="0.9",
        edgecolor="black",
        lw=1.0,
        zorder=2,
    )
    strip = Rectangle(
        (x - 0.9 * size, y - 1.35 * size),
        1.8 * size,
        0.35 * size,
        facecolor="none",
        edgecolor="black",
        hatch="////",
        lw=0.0,
        zorder=2,
    )
    tri.set_gid(f"{gid}_support")
    strip.set_gid(gid)
    ax.add_patch(tri)
    ax.add_patch(strip)
    return [tri, strip]


def _xy(z: complex) -> tuple[float, float]:
    return float(np.real(z)), float(np.imag(z))


def _check_index(index: Any, size: int) -> int:
    index = integer("index", index)
    if not -size <= index < size:
        raise InputError("index", f"must select one of the {size} solved samples, got {index}")
    return index % size


# --------------------------------------------------------------------------------------
# Four-bar pose


class _FourBarArtists:
    """The artists of one four-bar pose, updatable frame by frame (used by animate)."""

    def __init__(self, ax: Axes, fourbar: FourBar, labels: bool = True) -> None:
        self.ax = ax
        self.r1 = fourbar.r1
        size = 0.07 * max(fourbar.lengths)
        self.ground = [
            *_ground_pivot(ax, 0j, size, "ground_O2"),
            *_ground_pivot(ax, complex(fourbar.r1), size, "ground_O4"),
        ]
        (self.link1,) = ax.plot([0.0, fourbar.r1], [0.0, 0.0], color="0.5", lw=1.0, ls="--")
        self.link1.set_gid("link1")
        self.links = {}
        for k, colour in _LINK_COLOURS.items():
            (line,) = ax.plot([], [], color=colour, lw=4, solid_capstyle="round", zorder=4)
            line.set_gid(f"link{k}")
            self.links[k] = line
        self.has_p = fourbar.coupler is not None
        if self.has_p:
            from matplotlib.patches import Polygon

            self.triangle = Polygon(
                np.zeros((3, 2)), closed=True, facecolor="C1", alpha=0.25, edgecolor="C1", zorder=3
            )
            self.triangle.set_gid("coupler_triangle")
            ax.add_patch(self.triangle)
            (self.point,) = ax.plot([], [], marker="o", ms=6, color="C3", ls="none", zorder=7)
            self.point.set_gid("coupler_point")
        (self.joints,) = ax.plot([], [], **_JOINT_STYLE)
        self.joints.set_gid("joints")
        self.labels = {}
        if labels:
            for name in ("O2", "O4", "A", "B", *(("P",) if self.has_p else ())):
                self.labels[name] = ax.annotate(
                    name, (0.0, 0.0), xytext=(5, 5), textcoords="offset points", fontsize=9
                )
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x")
        ax.set_ylabel("y")

    @property
    def artists(self) -> list[Any]:
        out = [self.link1, *self.links.values(), self.joints, *self.labels.values()]
        if self.has_p:
            out += [self.triangle, self.point]
        return out

    def set_pose(self, A: complex, B: complex, P: complex | None, visible: bool = True) -> None:
        """Move the moving links to joints ``A``, ``B`` (and coupler point ``P``)."""
        O2, O4 = 0j, complex(self.r1)
        ends = {2: (O2, A), 3: (A, B), 4: (O4, B)}
        for k, (p, q) in ends.items():
            self.links[k].set_data([p.real, q.real], [p.imag, q.imag])
            self.links[k].set_visible(visible)
        pins = [O2, A, B, O4]
        self.joints.set_data([z.real for z in pins], [z.imag for z in pins])
        if self.has_p:
            assert P is not None
            self.triangle.set_xy([_xy(A), _xy(B), _xy(P)])
            self.point.set_data([P.real], [P.imag])
            self.triangle.set_visible(visible)
            self.point.set_visible(visible)
        where = {"O2": O2, "O4": O4, "A": A, "B": B, "P": P}
        for name, text in self.labels.items():
            z = where[name]
            text.xy = _xy(z)
            text.set_visible(visible or name in ("O2", "O4"))


def _pose_of(
    fourbar: FourBar, motion_or_theta2: Any, index: Any, form: int
) -> tuple[FourBarMotion, int]:
    """The solved motion and the flat index of the pose to draw."""
    if isinstance(motion_or_theta2, FourBarMotion):
        motion = motion_or_theta2
        if motion.lengths != fourbar.lengths:
            raise InputError(
                "motion",
                f"was solved for lengths {motion.lengths}, not for {fourbar!r}; "
                "pass the motion of this FourBar or an input angle",
            )
    else:
        motion = fourbar.solve(motion_or_theta2, form=form)
    k = _check_index(index, len(motion))
    if not np.ravel(motion.assembled)[k]:
        raise AssemblyError(
            f"{fourbar!r}, theta2 = {np.degrees(np.ravel(motion.theta2)[k]):.6g} deg: "
            f"{np.ravel(motion.reason)[k]}; there is no pose to draw"
        )
    return motion, k


def draw_fourbar(
    fourbar: FourBar,
    motion_or_theta2: FourBarMotion | Any,
    index: int = 0,
    ax: Axes | None = None,
    *,
    form: int = 1,
    instant_centres: bool = False,
    labels: bool = True,
) -> Axes:
    """Draw a four-bar in one pose.

    Parameters
    ----------
    fourbar : FourBar
        The linkage (its ground pivots are at O2 = 0 and O4 = r1).
    motion_or_theta2 : FourBarMotion or array_like
        A motion solved by ``fourbar.solve``, or input angles θ2 (radians) to
        solve in ``form``.
    index : int
        Which sample of the motion to draw (flat index; negative counts from the end).
    ax : matplotlib Axes, optional
        Where to draw; a new figure is made if omitted.
    form : {1, 2}
        The form, used only when input angles are given.
    instant_centres : bool
        Also mark the six instant centres (from :mod:`machdyn.centres`);
        centres at infinity are listed in a corner note.
    labels : bool
        Label O2, O4, A, B (and P).

    Returns
    -------
    matplotlib.axes.Axes

    Raises
    ------
    AssemblyError
        If the selected sample could not be assembled.

    Examples
    --------
    >>> fb = FourBar(8, 4, 7, 6, coupler=(5, np.radians(30)))
    >>> ax = draw_fourbar(fb, np.radians(60))
    >>> [line.get_gid() for line in ax.lines][:4]
    ['link1', 'link2', 'link3', 'link4']
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    motion, k = _pose_of(fourbar, motion_or_theta2, index, form)
    ax = _new_axes(ax)
    A = complex(np.ravel(motion.A)[k])
    B = complex(np.ravel(motion.B)[k])
    P = None if motion.coupler is None else complex(np.ravel(motion.coupler)[k])
    art = _FourBarArtists(ax, fourbar, labels=labels)
    art.set_pose(A, B, P)
    pose = [0j, complex(fourbar.r1), A, B, *(() if P is None else (P,))]
    ax.update_datalim([_xy(z) for z in pose])
    if instant_centres:
        _draw_instant_centres(ax, fourbar.r1, A, B)
    ax.autoscale_view()
    ax.set_title(f"θ2 = {np.degrees(np.ravel(motion.theta2)[k]):.4g}°, form {motion.form}")
    return ax


def _draw_instant_centres(ax: Axes, r1: float, A: complex, B: complex) -> None:
    """Mark the six instant centres; they do not change the axis limits."""
    from matplotlib.lines import Line2D

    from .centres import fourbar_centres

    ics = fourbar_centres(r1, np.array(A), np.array(B), np.array(True))
    at_infinity = []
    xs, ys = [], []
    for i, j in ics:
        centre = ics[i, j]
        if bool(centre.at_infinity):
            at_infinity.append(f"I{i}{j}")
            continue
        z = complex(centre.point)
        xs.append(z.real)
        ys.append(z.imag)
        ax.annotate(
            f"I{i}{j}", (z.real, z.imag), xytext=(4, -10), textcoords="offset points", fontsize=8
        )
    # added as a plain artist: far-away centres must not blow up the axis limits
    marks = Line2D(xs, ys, marker="x", ms=7, color="C4", ls="none", zorder=7)
    marks.set_gid("instant_centres")
    ax.add_artist(marks)
    if at_infinity:
        ax.text(
            0.02,
            0.02,
            ", ".join(at_infinity) + " at infinity",
            transform=ax.transAxes,
            fontsize=8,
        )


# --------------------------------------------------------------------------------------
# Kinematic curves


def _masked(values: np.ndarray, valid: np.ndarray) -> np.ma.MaskedArray:
    """Values hidden where a sample is flagged (drawn as a gap, never joined across)."""
    values = np.ravel(values)
    return np.ma.masked_array(values, mask=~np.ravel(valid) | ~np.isfinite(values))


def _break_wraps(x: np.ndarray, y: np.ma.MaskedArray) -> tuple[np.ndarray, np.ma.MaskedArray]:
    """Insert a masked point where an angle in [0, 360) wraps, so no vertical line is drawn."""
    filled = y.filled(np.nan)
    jumps = np.flatnonzero(np.abs(np.diff(filled)) > 180.0) + 1
    if jumps.size == 0:
        return x, y
    x = np.insert(np.asarray(x, dtype=float), jumps, np.nan)
    data = np.insert(filled, jumps, np.nan)
    mask = np.insert(np.ma.getmaskarray(y), jumps, True)
    return x, np.ma.masked_array(data, mask=mask)


def plot_kinematics(
    motion: FourBarMotion, *, jerk: bool = False, mu: bool = False, fig: Figure | None = None
) -> Figure:
    """θ3, θ4, ω3, ω4, α3, α4 (and optionally the jerks) of a four-bar against θ2.

    Angles are drawn in degrees, rates in rad/s, rad/s², rad/s³ (the time unit
    of the ``omega2`` given to the solver). Flagged samples (``motion.ok``
    False; positions also at toggles, where only the rates are undefined) are
    left as gaps, and an angle's wrap from 360° to 0° is not joined.

    Parameters
    ----------
    motion : FourBarMotion
        From :meth:`FourBar.solve`, ideally over a sorted grid of θ2.
    jerk : bool
        Add a panel with the angular jerks.
    mu : bool
        Also draw the transmission angle μ on the angle panel.
    fig : matplotlib Figure, optional
        An empty figure to draw in.

    Returns
    -------
    matplotlib.figure.Figure
        With one row of axes per quantity, sharing the θ2 axis.

    Examples
    --------
    >>> m = FourBar(8, 4, 7, 6).solve(np.radians(np.arange(0, 361, 5)), omega2=10.0)
    >>> fig = plot_kinematics(m)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['angle (deg)', 'ω (rad/s)', 'α (rad/s²)']
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    if not isinstance(motion, FourBarMotion):
        raise InputError(
            "motion", f"expected a FourBarMotion from FourBar.solve, got {type(motion).__name__}"
        )
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(7, 7 if jerk else 5.5), layout="constrained")
    panels: list[tuple[str, list[tuple[str, str, bool, bool]]]] = [
        (
            "angle (deg)",
            [("theta3", "θ3", True, True), ("theta4", "θ4", True, True)]
            + ([("mu", "μ", True, False)] if mu else []),
        ),
        ("ω (rad/s)", [("omega3", "ω3", False, False), ("omega4", "ω4", False, False)]),
        ("α (rad/s²)", [("alpha3", "α3", False, False), ("alpha4", "α4", False, False)]),
    ]
    if jerk:
        panels.append(
            ("jerk (rad/s³)", [("jerk3", "jerk3", False, False), ("jerk4", "jerk4", False, False)])
        )
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    x = np.degrees(np.ravel(motion.theta2))
    for ax, (ylabel, curves) in zip(axes, panels, strict=True):
        for name, label, is_angle, wraps in curves:
            valid = motion.assembled if is_angle else motion.ok
            values = np.ravel(getattr(motion, name))
            y = _masked(np.degrees(values) if is_angle else values, valid)
            xs, ys = _break_wraps(x, y) if wraps else (x, y)
            (line,) = ax.plot(xs, ys, label=label)
            line.set_gid(name)
        ax.set_ylabel(ylabel)
        ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
        ax.grid(True, lw=0.3)
        ax.legend(loc="best", fontsize=8)
    axes[-1].set_xlabel("θ2 (deg)")
    flagged = int(np.count_nonzero(~np.ravel(motion.ok)))
    title = f"Four-bar {motion.lengths}, form {motion.form}"
    if flagged:
        title += f" ({flagged} flagged samples left blank)"
    axes[0].set_title(title, fontsize=10)
    return fig


# --------------------------------------------------------------------------------------
# Coupler curve


def plot_coupler_curve(
    fourbar: FourBar,
    form: int = 1,
    ax: Axes | None = None,
    *,
    theta2: float | None = None,
    n: int = 721,
    labels: bool = True,
) -> Axes:
    """The coupler curve of a form, with the linkage drawn in one pose.

    Parameters
    ----------
    fourbar : FourBar
        A linkage built with a coupler point.
    form : {1, 2}
    ax : matplotlib Axes, optional
    theta2 : float, optional
        Input angle (radians) of the pose drawn; by default the first point of
        the curve (θ2 = 0 for a crank, the lower limit for a rocker).
    n : int
        Samples per branch of :meth:`FourBar.coupler_curve`.

    Raises
    ------
    InputError
        If the linkage has no coupler point.

    Examples
    --------
    >>> fb = FourBar(8, 4, 7, 6, coupler=(5, np.radians(30)))
    >>> ax = plot_coupler_curve(fb, n=181)
    >>> curve = [l for l in ax.lines if l.get_gid() == "coupler_curve"][0]
    >>> len(curve.get_xdata())          # closed: the first point repeated
    182
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    curve = fourbar.coupler_curve(form, integer("n", n, minimum=2))
    ax = _new_axes(ax)
    pts = curve.points
    if fourbar.input_range(form).full_turn or fourbar.form_rule == "phi34":
        pts = np.append(pts, pts[:1])  # the motion of the form is a closed cycle
    (line,) = ax.plot(pts.real, pts.imag, color="C3", lw=1.2, label="coupler curve")
    line.set_gid("coupler_curve")
    branch = None
    if theta2 is None:
        theta2 = float(curve.theta2[0])
        if fourbar.form_rule == "phi34":
            branch = int(curve.branch[0])
    motion = fourbar.solve(theta2, form=form, branch=branch)
    draw_fourbar(fourbar, motion, ax=ax, labels=labels)
    ax.set_title(f"Coupler curve, {fourbar!r}, form {form}", fontsize=10)
    return ax


# --------------------------------------------------------------------------------------
# Slider-crank


def plot_slider_crank(
    slidercrank: SliderCrank,
    motion_or_theta2: SliderCrankMotion | Any,
    index: int = 0,
    ax: Axes | None = None,
    *,
    form: int = 1,
    labels: bool = True,
) -> Axes:
    """Draw a slider-crank in one pose: crank, connecting rod, slider block and its guide.

    Parameters
    ----------
    slidercrank : SliderCrank
    motion_or_theta2 : SliderCrankMotion or array_like
        A motion from ``slidercrank.solve``, or crank angles (radians) to solve in ``form``.
    index : int
        Which sample to draw.
    ax : matplotlib Axes, optional
    form : {1, 2}
        Used only when crank angles are given.

    Examples
    --------
    >>> sc = SliderCrank(crank=2.0, coupler=6.0, offset=0.5)
    >>> ax = plot_slider_crank(sc, np.radians(45))
    >>> sorted(a.get_gid() for a in ax.patches if a.get_gid())[:2]
    ['ground_O2', 'ground_O2_support']
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    from matplotlib.patches import Polygon, Rectangle

    if not isinstance(slidercrank, SliderCrank):
        raise InputError("slidercrank", f"expected a SliderCrank, got {type(slidercrank).__name__}")
    if isinstance(motion_or_theta2, SliderCrankMotion):
        motion = motion_or_theta2
    else:
        motion = slidercrank.solve(motion_or_theta2, form=form)
    k = _check_index(index, int(np.size(motion.theta2)))
    if not np.ravel(motion.assembled)[k]:
        raise AssemblyError(
            f"{slidercrank!r}, theta2 = {np.degrees(np.ravel(motion.theta2)[k]):.6g} deg: "
            f"{np.ravel(motion.reason)[k]}; there is no pose to draw"
        )
    ax = _new_axes(ax)
    a, b, c = slidercrank.a, slidercrank.b, slidercrank.c
    A = complex(np.ravel(motion.A)[k])
    B = complex(np.ravel(motion.B)[k])
    size = 0.07 * (a + b)
    _ground_pivot(ax, 0j, size, "ground_O2")
    # the block and its guide
    w, h = 0.22 * b, 0.12 * b
    if slidercrank.crank_rotates:
        lo, hi = slidercrank.stroke(motion.form)
    else:  # a rocking crank: the slider stays within a crank length of this pose
        lo, hi = B.real - a, B.real + a
    guide_y = c - 0.5 * h
    (guide,) = ax.plot(
        [lo - 0.8 * w, hi + 0.8 * w], [guide_y, guide_y], color="black", lw=1.0, zorder=2
    )
    guide.set_gid("slide_guide")
    hatch = Polygon(
        [
            (lo - 0.8 * w, guide_y),
            (hi + 0.8 * w, guide_y),
            (hi + 0.8 * w, guide_y - 0.3 * h),
            (lo - 0.8 * w, guide_y - 0.3 * h),
        ],
        closed=True,
        facecolor="none",
        hatch="////",
        lw=0.0,
        zorder=2,
    )
    hatch.set_gid("slide_ground")
    ax.add_patch(hatch)
    block = Rectangle(
        (B.real - 0.5 * w, B.imag - 0.5 * h), w, h, facecolor="C2", alpha=0.6, edgecolor="black"
    )
    block.set_gid("slider")
    ax.add_patch(block)
    for gid, (p, q), colour in (("link2", (0j, A), "C0"), ("link3", (A, B), "C1")):
        (line,) = ax.plot(
            [p.real, q.real], [p.imag, q.imag], color=colour, lw=4, solid_capstyle="round", zorder=4
        )
        line.set_gid(gid)
    (joints,) = ax.plot([0.0, A.real, B.real], [0.0, A.imag, B.imag], **_JOINT_STYLE)
    joints.set_gid("joints")
    names = {"O2": 0j, "A": A, "B": B}
    if motion.coupler is not None:
        P = complex(np.ravel(motion.coupler)[k])
        triangle = Polygon(
            [_xy(A), _xy(B), _xy(P)], closed=True, facecolor="C1", alpha=0.25, edgecolor="C1"
        )
        triangle.set_gid("coupler_triangle")
        ax.add_patch(triangle)
        (point,) = ax.plot([P.real], [P.imag], marker="o", ms=6, color="C3", ls="none", zorder=7)
        point.set_gid("coupler_point")
        names["P"] = P
    if labels:
        for name, z in names.items():
            ax.annotate(name, (z.real, z.imag), xytext=(5, 5), textcoords="offset points")
    ax.set_aspect("equal", adjustable="datalim")
    ax.autoscale_view()
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_title(
        f"θ2 = {np.degrees(np.ravel(motion.theta2)[k]):.4g}°, "
        f"d = {np.ravel(motion.d)[k]:.4g}, form {motion.form}"
    )
    return ax


def plot_slider_motion(
    motion: SliderCrankMotion, *, jerk: bool = True, fig: Figure | None = None
) -> Figure:
    """Slider position d and its derivatives against the crank angle (an "svaj" plot).

    Flagged samples are left as gaps (positions are kept at toggles).

    Examples
    --------
    >>> m = SliderCrank(2.0, 6.0).solve(np.radians(np.arange(0, 361, 5)), omega2=10.0)
    >>> fig = plot_slider_motion(m)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['d', 'ḋ (per s)', 'd̈ (per s²)', 'jerk (per s³)']
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    if not isinstance(motion, SliderCrankMotion):
        raise InputError(
            "motion",
            f"expected a SliderCrankMotion from SliderCrank.solve, got {type(motion).__name__}",
        )
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(7, 7 if jerk else 5.5), layout="constrained")
    rows = [("d", "d", True), ("d_dot", "ḋ (per s)", False), ("d_ddot", "d̈ (per s²)", False)]
    if jerk:
        rows.append(("d_dddot", "jerk (per s³)", False))
    axes = fig.subplots(len(rows), 1, sharex=True, squeeze=False)[:, 0]
    x = np.degrees(np.ravel(motion.theta2))
    for ax, (name, ylabel, is_position) in zip(axes, rows, strict=True):
        valid = motion.assembled if is_position else motion.ok
        (line,) = ax.plot(x, _masked(getattr(motion, name), valid), color="C2")
        line.set_gid(name)
        ax.set_ylabel(ylabel)
        ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
        ax.grid(True, lw=0.3)
    axes[-1].set_xlabel("θ2 (deg)")
    axes[0].set_title(f"Slider motion, form {motion.form}", fontsize=10)
    return fig


# --------------------------------------------------------------------------------------
# Animation


def animate(
    fourbar: FourBar,
    theta2: Any = None,
    form: int = 1,
    path: str | Path | None = None,
    fps: float = 30,
    *,
    n: int = 120,
    coupler_curve: bool = True,
    dpi: float = 80,
    figsize: Sequence[float] = (6.0, 4.5),
) -> FuncAnimation:
    """Animate a four-bar through its motion (matplotlib ``FuncAnimation``).

    Parameters
    ----------
    fourbar : FourBar
    theta2 : array_like, optional
        Input angles of the frames (radians). By default one cycle of the form
        (see :func:`sweep`: a crank turns once, a rocker goes there and back).
    form : {1, 2}
    path : str or Path, optional
        Save a GIF there (the name must end in ``.gif``). Without it, nothing
        is written: show the returned animation in a notebook with
        ``HTML(anim.to_jshtml())``.
    fps : float
        Frames per second.
    n : int
        Samples per stroke when ``theta2`` is not given.
    coupler_curve : bool
        Trace the coupler curve behind the linkage (when it has a coupler point).
    dpi, figsize
        Size of the frames.

    Returns
    -------
    matplotlib.animation.FuncAnimation
        One frame per pose. Frames whose pose cannot be assembled show the
        ground and the reason instead of the moving links.

    Examples
    --------
    >>> anim = animate(FourBar(8, 4, 7, 6, coupler=(5, 0.5)), n=6, dpi=40)
    >>> len(list(anim.new_frame_seq()))
    6
    >>> html = anim.to_jshtml()          # in a notebook: IPython.display.HTML(html)
    """
    from matplotlib.animation import FuncAnimation
    from matplotlib.figure import Figure

    fps = positive("fps", fps)
    if path is not None:
        path = Path(path)
        if path.suffix.lower() != ".gif":
            raise InputError(
                "path",
                f"animations are saved as GIF; the name must end in .gif, got {path.name!r} "
                "(for a browser page use machdyn.viewer.to_html)",
            )
    frames = sweep(fourbar, form, n, theta2)
    # A bare Figure (not pyplot's): nothing is shown twice in a notebook.
    fig = Figure(figsize=tuple(figsize), dpi=dpi, layout="constrained")
    ax = fig.add_subplot()
    if coupler_curve and frames.coupler is not None:
        path_pts = frames.coupler[frames.assembled]
        if theta2 is None:  # a default sweep is a cycle: close the trace
            path_pts = np.append(path_pts, path_pts[:1])
        (trace,) = ax.plot(path_pts.real, path_pts.imag, color="C3", lw=1.0, alpha=0.7)
        trace.set_gid("coupler_curve")
    art = _FourBarArtists(ax, fourbar)
    # fixed limits: the union of every pose
    pts = np.concatenate(
        [
            [0j, complex(fourbar.r1)],
            frames.A[frames.assembled],
            frames.B[frames.assembled],
            *([frames.coupler[frames.assembled]] if frames.coupler is not None else []),
        ]
    )
    span = max(np.ptp(pts.real), np.ptp(pts.imag), 1e-12)
    pad = 0.12 * span
    ax.set_xlim(pts.real.min() - pad, pts.real.max() + pad)
    ax.set_ylim(pts.imag.min() - pad, pts.imag.max() + pad)
    ax.set_aspect("equal", adjustable="box")
    status = ax.text(0.02, 0.96, "", transform=ax.transAxes, va="top", fontsize=9)
    status.set_gid("status")
    status.set_in_layout(False)  # a long reason must not squeeze the drawing
    ax.set_title(f"{fourbar!r}, form {form}", fontsize=10)

    def update(i: int) -> list[Any]:
        if frames.assembled[i]:
            P = None if frames.coupler is None else frames.coupler[i]
            art.set_pose(frames.A[i], frames.B[i], P)
            status.set_text(
                f"θ2 = {np.degrees(frames.theta2[i]):7.2f}°   θ3 = "
                f"{np.degrees(frames.theta3[i]):7.2f}°   θ4 = {np.degrees(frames.theta4[i]):7.2f}°"
            )
        else:
            art.set_pose(0j, complex(fourbar.r1), 0j if art.has_p else None, visible=False)
            status.set_text(f"θ2 = {np.degrees(frames.theta2[i]):7.2f}°:\n{frames.reason[i]}")
        return [*art.artists, status]

    # Lay the figure out once for the widest status text; frames then skip the layout pass.
    update(int(np.argmin(frames.assembled)) if not frames.assembled.all() else 0)
    fig.draw_without_rendering()
    fig.set_layout_engine("none")
    anim = FuncAnimation(
        fig,
        update,
        frames=len(frames),
        interval=1000.0 / fps,
        blit=False,
        cache_frame_data=False,
    )
    if path is not None:
        anim.save(path, writer=_gif_writer([*art.artists, status], fps), dpi=fig.dpi)
    return anim


def _gif_writer(moving: list[Any], fps: float) -> Any:
    """A GIF writer that draws the still parts once and then only the ``moving`` artists.

    matplotlib's ``PillowWriter`` re-renders the whole figure (tick labels,
    hatching, the coupler curve) for every frame; here the background is
    rendered once and restored before each frame, as interactive blitting
    does. The frames are written by Pillow, as ``PillowWriter`` writes them.
    """
    from matplotlib.animation import AbstractMovieWriter
    from matplotlib.backends.backend_agg import RendererAgg
    from PIL import Image

    class GifWriter(AbstractMovieWriter):
        def setup(self, fig: Any, outfile: Any, dpi: float | None = None) -> None:
            super().setup(fig, outfile, dpi)
            self._images: list[Any] = []
            self._renderer: Any = None
            self._background: Any = None

        def grab_frame(self, **savefig_kwargs: Any) -> None:
            if self._renderer is None:  # the background, without the moving artists
                width, height = self.frame_size
                self._renderer = RendererAgg(width, height, self.fig.dpi)
                shown = [artist.get_visible() for artist in moving]
                for artist in moving:
                    artist.set_visible(False)
                self.fig.draw(self._renderer)
                for artist, visible in zip(moving, shown, strict=True):
                    artist.set_visible(visible)
                self._background = self._renderer.copy_from_bbox(self.fig.bbox)
            renderer = self._renderer
            renderer.restore_region(self._background)
            for artist in sorted(moving, key=lambda a: a.get_zorder()):
                artist.draw(renderer)
            rgba = np.array(renderer.buffer_rgba(), copy=True)
            self._images.append(Image.fromarray(rgba, "RGBA"))

        def finish(self) -> None:
            if self._images:
                self._images[0].save(
                    self.outfile,
                    save_all=True,
                    append_images=self._images[1:],
                    duration=int(1000 / self.fps),
                    loop=0,
                )

    return GifWriter(fps=fps)
