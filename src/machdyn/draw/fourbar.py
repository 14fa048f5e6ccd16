"""Four-bar and slider-crank pictures with the calls documented since the first release.

``draw_fourbar``, ``plot_coupler_curve``, ``plot_slider_crank`` and ``animate``
draw through the one scene path (:mod:`machdyn.draw.build` →
:mod:`machdyn.draw.mpl`), like every other model; :func:`sweep` gives the poses
of an animation in the order they are shown. matplotlib is imported inside the
functions, and each takes an optional ``ax`` and returns what it drew on.

Every artist that carries data has a ``gid`` (``"link2"``, ``"coupler_curve"``,
``"instant_centres"``, ...) so that it can be found again (and tested).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import choice, finite_scalar, integer
from ..errors import AssemblyError, InputError
from ..fourbar import FourBar, FourBarMotion
from ..slidercrank import SliderCrank, SliderCrankMotion
from .build import describe, fourbar_scene, scene, slidercrank_scene
from .mpl import animate_scene, draw_scene

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.animation import FuncAnimation
    from matplotlib.axes import Axes

__all__ = [
    "Sweep",
    "animate",
    "draw_fourbar",
    "plot_coupler_curve",
    "plot_slider_crank",
    "sweep",
]


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
# Poses


def _check_index(index: Any, size: int) -> int:
    index = integer("index", index)
    if not -size <= index < size:
        raise InputError("index", f"must select one of the {size} solved samples, got {index}")
    return index % size


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
        Also mark the six instant centres (from :mod:`machdyn.centres`). A
        centre outside the view is shown by an arrow at the border labelled
        with its coordinates; a centre at infinity by an arrow along its
        direction.
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
    s = fourbar_scene(fourbar, motion)
    ax = draw_scene(s, k, ax, labels=labels, title=False)
    if instant_centres:
        A = complex(np.ravel(motion.A)[k])
        B = complex(np.ravel(motion.B)[k])
        draw_centres(
            ax,
            fourbar.instant_centres(
                np.ravel(motion.theta2)[k], motion.form, branch=_branch(fourbar, motion, k)
            ),
            (A, B),
        )
    ax.set_title(
        f"{describe(fourbar)}\nθ2 = {np.degrees(np.ravel(motion.theta2)[k]):.4g}°, "
        f"form {motion.form}",
        fontsize=10,
    )
    return ax


def _branch(fourbar: FourBar, motion: FourBarMotion, k: int) -> int | None:
    if fourbar.form_rule != "phi34":
        return None
    return 1 if float(np.ravel(motion.phi12)[k]) >= 0 else -1


def draw_centres(ax: Axes, centres: Any, keep: Sequence[complex] = ()) -> None:
    """Mark instant centres on ``ax``; those off the view get an arrow at the border.

    The view is fixed first (the drawing and ``keep``); a centre inside it is
    a cross labelled ``Iij``; one outside is an arrow at the border pointing
    to it, labelled with its coordinates; one at infinity an arrow along its
    direction, labelled ``at ∞``. Nothing changes the axis limits.
    """
    from matplotlib.lines import Line2D

    ax.autoscale_view()
    ax.apply_aspect()  # the view as it will be shown (equal aspect applied)
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    ax.set_adjustable("box")  # keep this view: the box, not the limits, keeps the aspect
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    centre = complex(0.5 * (x0 + x1), 0.5 * (y0 + y1))
    half = complex(0.5 * (x1 - x0), 0.5 * (y1 - y0))
    xs, ys = [], []
    for i, j in centres:
        c = centres[i, j]
        name = f"I{i}{j}" if isinstance(i, int | np.integer) else f"I({i}, {j})"
        if bool(np.ravel(c.at_infinity)[0]):
            d = complex(np.ravel(c.direction)[0])
            _border_arrow(
                ax, centre, half, d, f"{name} at ∞ ({np.degrees(np.angle(d)) % 180:.1f}°)", name
            )
            continue
        z = complex(np.ravel(c.point)[0])
        if x0 <= z.real <= x1 and y0 <= z.imag <= y1:
            xs.append(z.real)
            ys.append(z.imag)
            ax.annotate(
                name,
                (z.real, z.imag),
                xytext=(4, -10),
                textcoords="offset points",
                fontsize=8,
                color="C4",
            )
        else:
            _border_arrow(
                ax, centre, half, z - centre, f"{name} ({z.real:.4g}, {z.imag:.4g})", name
            )
    marks = Line2D(xs, ys, marker="x", ms=7, color="C4", ls="none", zorder=7)
    marks.set_gid("instant_centres")
    ax.add_artist(marks)


def _border_arrow(
    ax: Axes, centre: complex, half: complex, direction: complex, text: str, name: str
) -> None:
    """An arrow from inside the view to its border, along ``direction``, with a label."""
    if direction == 0:
        return
    e = direction / abs(direction)
    # the ray centre + t e meets the box |x| <= half.real, |y| <= half.imag at t
    ts = [
        abs(half.real / e.real) if e.real else np.inf,
        abs(half.imag / e.imag) if e.imag else np.inf,
    ]
    t = 0.97 * min(ts)
    tip = centre + t * e
    tail = centre + 0.78 * t * e
    art = ax.annotate(
        text,
        xy=(tip.real, tip.imag),
        xytext=(tail.real, tail.imag),
        fontsize=7.5,
        color="C4",
        ha="center",
        va="center",
        arrowprops={"arrowstyle": "->", "color": "C4", "lw": 1.2},
        annotation_clip=False,
        bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8},
    )
    art.set_gid(f"centre_arrow_{name}")


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
    pts = curve.points
    if fourbar.input_range(form).full_turn or fourbar.form_rule == "phi34":
        pts = np.append(pts, pts[:1])  # the motion of the form is a closed cycle
    branch = None
    if theta2 is None:
        theta2 = float(curve.theta2[0])
        if fourbar.form_rule == "phi34":
            branch = int(curve.branch[0])
    motion = fourbar.solve(theta2, form=form, branch=branch)
    s = fourbar_scene(fourbar, motion, coupler_curve=pts)
    ax = draw_scene(s, 0, ax, labels=labels, title=False)
    ax.set_title(f"Coupler curve, {describe(fourbar)}, form {form}", fontsize=10)
    return ax


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
    s = slidercrank_scene(slidercrank, motion)
    # the guide spans the stroke (or a crank length either side of a rocking crank's pose)
    if slidercrank.crank_rotates:
        lo, hi = slidercrank.stroke(motion.form)
    else:
        B = complex(np.ravel(motion.B)[k])
        lo, hi = B.real - slidercrank.a, B.real + slidercrank.a
    margin = 0.22 * slidercrank.b
    xy = s.xy.copy()
    xy[:, s.index("G1")] = complex(lo - margin, slidercrank.c)
    xy[:, s.index("G2")] = complex(hi + margin, slidercrank.c)
    s = replace(s, xy=xy)
    ax = draw_scene(s, k, ax, labels=labels, title=False)
    ax.set_title(
        f"θ2 = {np.degrees(np.ravel(motion.theta2)[k]):.4g}°, "
        f"d = {np.ravel(motion.d)[k]:.4g}, form {motion.form}"
    )
    return ax


# --------------------------------------------------------------------------------------
# Animation


def animate(
    model: Any,
    theta2: Any = None,
    form: int = 1,
    path: str | Path | None = None,
    fps: float = 30,
    *,
    n: int = 120,
    coupler_curve: bool = True,
    dpi: float = 80,
    figsize: Sequence[float] = (6.0, 4.5),
    **options: Any,
) -> FuncAnimation:
    """Animate a mechanism through its motion (matplotlib ``FuncAnimation``).

    Parameters
    ----------
    model : FourBar, SliderCrank, InvertedSliderCrank, Linkage, cam, gear pair, ...
        Anything :func:`machdyn.draw.scene` draws (or a ``Scene``).
    theta2 : array_like, optional
        Input angles of the frames (radians). By default one cycle of the form
        (see :func:`sweep`: a crank turns once, a rocker goes there and back).
    form : {1, 2}
    path : str or Path, optional
        Save the animation there: ``.gif``, ``.mp4`` (needs ffmpeg) or
        ``.html`` (the browser page). Without it, nothing is written: show
        the returned animation in a notebook with ``HTML(anim.to_jshtml())``.
    fps : float
        Frames per second.
    n : int
        Samples per stroke when ``theta2`` is not given.
    coupler_curve : bool
        Trace the coupler curve behind a four-bar (when it has a coupler point).
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
    if path is not None and Path(path).suffix.lower() not in (".gif", ".mp4", ".html"):
        raise InputError(
            "path",
            f"animations are saved as .gif, .mp4 or .html; got {Path(path).name!r} "
            "(for a still picture use draw())",
        )
    s = scene(model, n=n, form=form, theta2=theta2, **options)
    if not coupler_curve and s.curves:
        s = replace(s, curves=())
    return animate_scene(s, path, fps=fps, dpi=dpi, figsize=figsize)
