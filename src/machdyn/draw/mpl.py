"""The matplotlib back end: a scene drawn on Axes, stills (PNG/SVG) and animations (GIF/MP4).

matplotlib is imported inside the functions. :class:`Painter` makes the artists
of a scene once and moves them frame by frame (an animation re-uses them);
every artist has the item's ``gid`` so it can be found again (and tested).
"""

from __future__ import annotations

import shutil
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import integer, positive
from ..errors import InputError
from . import symbols
from .scene import Item, Scene, is_static

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.animation import FuncAnimation
    from matplotlib.axes import Axes

__all__ = ["ANIMATION_KINDS", "Painter", "animate_scene", "draw_scene"]

#: File endings :func:`animate_scene` writes, and what each holds.
ANIMATION_KINDS = {
    ".gif": "animated GIF (Pillow)",
    ".mp4": "H.264 video (needs ffmpeg on the PATH)",
    ".html": "self-contained browser page (machdyn.draw.html)",
}

_PIN = {
    "marker": "o",
    "markersize": 7,
    "markerfacecolor": "white",
    "markeredgecolor": "black",
    "linestyle": "none",
    "zorder": 6,
}


def _xy(z: complex) -> tuple[float, float]:
    return float(np.real(z)), float(np.imag(z))


def _good(*zs: complex) -> bool:
    return all(np.isfinite(z) for z in zs)


def _zorder(kind: str) -> float:
    return {
        "line": 1.5,
        "guide": 2,
        "ground": 2,
        "shape": 2.5,
        "wheel": 2.5,
        "plate": 3,
        "spring": 3.5,
        "damper": 3.5,
        "actuator": 3.6,
        "slider": 3.8,
        "bar": 4,
        "motor": 5,
        "pin": 6,
        "point": 7,
    }[kind]


class Painter:
    """The artists of a scene on one Axes, movable to any frame.

    Parameters
    ----------
    scene : Scene
    ax : matplotlib Axes
    labels : bool
        Write the point names beside the points.
    status : bool
        Show the readout (or the reason a frame is not drawn) in a corner.
    """

    def __init__(
        self, scene: Scene, ax: Axes, *, labels: bool = True, status: bool = False
    ) -> None:
        self.scene, self.ax = scene, ax
        self.unit = scene.size / 100.0
        self.moving: list[Any] = []
        self._updates: list[Any] = []
        for c in scene.curves:
            self._curve(c)
        for item in scene.items:
            self._item(item)
        self.labels: dict[str, Any] = {}
        if labels:
            for item in scene.items:
                if item.kind in ("pin", "ground", "point"):
                    for p in item.points:
                        if p not in self.labels:
                            t = ax.annotate(
                                p,
                                (0.0, 0.0),
                                xytext=(5, 5),
                                textcoords="offset points",
                                fontsize=9,
                                annotation_clip=False,
                                zorder=8,
                            )
                            t.set_parse_math(False)  # a user's '$' is text, not TeX
                            self.labels[p] = t
                            self.moving.append(t)
        self.status = None
        if status:
            self.status = ax.text(
                0.01, 0.99, "", transform=ax.transAxes, va="top", fontsize=8, family="monospace"
            )
            self.status.set_gid("status")
            self.status.set_in_layout(False)
            self.status.set_parse_math(False)
            self.moving.append(self.status)
        ax.set_aspect("equal", adjustable="datalim")
        unit = f" ({scene.length_unit})" if scene.length_unit else ""
        ax.set_xlabel(f"x{unit}")
        ax.set_ylabel(f"y{unit}")

    # -- building -------------------------------------------------------------------
    def _curve(self, c: Any) -> None:
        pts = np.ravel(np.asarray(c.points, complex))
        if c.style == "markers":
            (line,) = self.ax.plot(
                pts.real,
                pts.imag,
                "o",
                mfc="none",
                mec=c.colour,
                ms=9,
                mew=1.5,
                zorder=8,
                label=c.label or None,
            )
            for i, z in enumerate(pts, start=1):
                if np.isfinite(z):
                    self.ax.annotate(
                        str(i),
                        _xy(z),
                        xytext=(6, -11),
                        textcoords="offset points",
                        fontsize=8,
                        color=c.colour,
                    )
        else:
            ls = "--" if c.style == "dashed" else "-"
            (line,) = self.ax.plot(
                pts.real, pts.imag, ls, color=c.colour, lw=1.2, label=c.label or None, zorder=1
            )
        line.set_gid(c.gid)

    def _item(self, item: Item) -> None:
        from matplotlib.patches import Polygon

        ax, s, u, k = self.ax, self.scene, self.unit, item.kind
        before = len(self.moving)
        col = item.colour
        idx = [s.index(p) for p in item.points]
        z = lambda i: s.xy[i][idx]  # noqa: E731 - the item's points in frame i
        ang = (lambda i: float(s.angles[item.angle][i])) if item.angle else (lambda i: 0.0)

        if k == "ground":
            tri, strip = symbols.ground_symbol(4.5 * u)
            at = s.resting(item.points[0])
            a = Polygon(
                np.c_[(at + tri).real, (at + tri).imag],
                closed=True,
                fc="0.9",
                ec="black",
                lw=1.0,
                zorder=2,
            )
            b = Polygon(
                np.c_[(at + strip).real, (at + strip).imag],
                closed=True,
                fc="none",
                ec="black",
                hatch="////",
                lw=0.0,
                zorder=2,
            )
            a.set_gid(f"{item.gid}_support")
            b.set_gid(item.gid)
            ax.add_patch(a)
            ax.add_patch(b)
            return
        if k in ("bar", "line"):
            ground = item.body.endswith("(ground)")
            kw = (
                {"lw": 4, "solid_capstyle": "round"}
                if k == "bar"
                else {"lw": 1.0, "ls": "--" if ground else "-"}
            )
            (art,) = ax.plot([], [], color=col, zorder=_zorder(k), **kw)

            def upd(i, art=art):
                p = z(i)
                art.set_data(p.real, p.imag)
                return _good(*p)

        elif k == "plate":
            art = Polygon(
                np.zeros((len(idx), 2)),
                closed=True,
                fc=col,
                alpha=0.3,
                ec=col,
                lw=1.5,
                zorder=_zorder(k),
            )
            ax.add_patch(art)

            def upd(i, art=art):
                p = z(i)
                if _good(*p):
                    art.set_xy(np.c_[p.real, p.imag])
                return _good(*p)

        elif k in ("pin", "point"):
            style = (
                dict(_PIN)
                if k == "pin"
                else {"marker": "o", "ms": 6, "color": col, "ls": "none", "zorder": 7}
            )
            (art,) = ax.plot([], [], **style)

            def upd(i, art=art):
                p = z(i)
                p = p[np.isfinite(p)]
                art.set_data(p.real, p.imag)
                return True

        elif k in ("slider", "shape", "wheel", "motor"):
            if k == "slider":
                length = item.size or 8 * u
                local, closed = symbols.block(length, 0.55 * length), True
                kw = {"fc": col, "alpha": 0.7, "ec": "black", "lw": 1.2}
            elif k == "shape":
                local, closed = np.asarray(item.outline, complex), item.closed
                kw = {
                    "fc": col if closed else "none",
                    "alpha": 0.35 if closed else 1.0,
                    "ec": col,
                    "lw": 1.2,
                }
            elif k == "wheel":
                t = np.linspace(0, 2 * np.pi, 73)
                local, closed = item.size * np.exp(1j * t), item.closed
                kw = {
                    "fc": col if closed else "none",
                    "alpha": 0.25 if closed else 1.0,
                    "ec": col,
                    "lw": 1.5,
                }
            else:
                local, closed = symbols.motor_arrow(3.2 * u), False
                kw = {"fc": "none", "ec": col, "lw": 1.5}
            art = Polygon(np.zeros((len(local), 2)), closed=closed, zorder=_zorder(k), **kw)
            ax.add_patch(art)
            spoke = None
            if k == "wheel" and item.body != "ground":
                (spoke,) = ax.plot([], [], color=col, lw=1.5, zorder=_zorder(k))
                spoke.set_gid(f"{item.gid}_spoke")
                self.moving.append(spoke)

            def upd(i, art=art, local=local, spoke=spoke):
                p = z(i)
                if not _good(*p):
                    if spoke is not None:
                        spoke.set_visible(False)
                    return False
                w = symbols.placed(local, p[0], ang(i))
                art.set_xy(np.c_[w.real, w.imag])
                if spoke is not None:
                    e = symbols.placed(np.array([0, item.size]), p[0], ang(i))
                    spoke.set_data(e.real, e.imag)
                    spoke.set_visible(True)
                return True

        elif k == "guide":
            h = 0.55 * (item.size or 8 * u)
            (art,) = ax.plot([], [], color=col, lw=1.0, zorder=_zorder(k))
            hatch = Polygon(
                np.zeros((4, 2)), closed=True, fc="none", hatch="////", lw=0.0, zorder=_zorder(k)
            )
            hatch.set_gid(f"{item.gid}_ground")
            ax.add_patch(hatch)
            self.moving.append(hatch)

            def upd(i, art=art, hatch=hatch, h=h):
                p, q = z(i)
                if not _good(p, q) or p == q:
                    hatch.set_visible(False)
                    return False
                e = (q - p) / abs(q - p)
                lo = np.array([p, q]) - 0.5j * h * e
                art.set_data(lo.real, lo.imag)
                strip = np.array([lo[0], lo[1], lo[1] - 1.6j * u * e, lo[0] - 1.6j * u * e])
                hatch.set_xy(np.c_[strip.real, strip.imag])
                hatch.set_visible(True)
                return True

        elif k in ("spring", "damper", "actuator"):
            pieces = []
            if k == "spring":
                pieces = [symbols.spring(1.8 * u)]
            elif k == "damper":
                pieces = symbols.damper(4.0 * u)
            lines = []
            n_lines = len(pieces) if pieces else 2
            for m in range(n_lines):
                lw = 1.5 if k != "actuator" else (9 if m == 0 else 2.5)
                alpha = 0.55 if (k == "actuator" and m == 0) else 1.0
                colour = col if not (k == "actuator" and m == 1) else "#333333"
                (line,) = ax.plot(
                    [],
                    [],
                    color=colour,
                    lw=lw,
                    alpha=alpha,
                    solid_capstyle="butt",
                    zorder=_zorder(k),
                )
                line.set_gid(item.gid if m == 0 else f"{item.gid}_{m}")
                lines.append(line)
            art = lines[0]
            self.moving.extend(lines[1:])
            barrel = None
            if k == "actuator":
                d = np.abs(s.point(item.points[1]) - s.point(item.points[0]))
                d = d[np.isfinite(d)]
                barrel = 0.62 * float(d.min()) if d.size else 1.0

            def upd(i, lines=lines, pieces=pieces, barrel=barrel):
                p, q = z(i)
                if not _good(p, q):
                    for line in lines:
                        line.set_visible(False)
                    return False
                L = abs(q - p)
                e = (q - p) / L if L > 0 else 1.0
                if barrel is not None:
                    ends = [(0.0, barrel), (0.4 * barrel, L)]
                    for line, (a, b) in zip(lines, ends, strict=True):
                        w = p + e * np.array([a, b])
                        line.set_data(w.real, w.imag)
                else:
                    for line, (xs, ys) in zip(lines, pieces, strict=True):
                        w = p + e * (xs * L + 1j * ys)
                        line.set_data(w.real, w.imag)
                for line in lines:
                    line.set_visible(True)
                return True

        else:  # pragma: no cover - KINDS is closed
            raise InputError("kind", f"no matplotlib drawing for {k!r}")
        art.set_gid(item.gid)
        self.moving.append(art)
        extras = [a for a in self.moving[before:] if a is not art]
        self._updates.append((art, upd, extras, is_static(s, item)))

    # -- moving ---------------------------------------------------------------------
    def set_frame(self, i: int) -> list[Any]:
        """Move every artist to frame ``i``; returns the artists that moved."""
        s = self.scene
        shown = bool(s.shown[i])
        for art, upd, extras, static in self._updates:
            visible = bool(upd(i)) and (shown or static)
            art.set_visible(visible)
            if not visible:
                for extra in extras:
                    extra.set_visible(False)
        for p, text in self.labels.items():
            z = s.xy[i, s.index(p)]
            good = shown and bool(np.isfinite(z))
            if good:
                text.xy = _xy(z)
            text.set_visible(good)
        if self.status is not None:
            if shown:
                parts = [
                    f"{r.label} = {_fmt(np.asarray(r.values)[i], r.digits)}"
                    + (
                        f" {r.unit}"
                        if r.unit and r.unit != "deg"
                        else ("°" if r.unit == "deg" else "")
                    )
                    for r in s.readout
                ]
                text = "   ".join(parts[:4]) + ("\n" + "   ".join(parts[4:]) if parts[4:] else "")
                if s.reason[i]:
                    text += f"\n{s.reason[i]}"
            else:
                first = s.readout[0] if s.readout else None
                head = (
                    f"{first.label} = {_fmt(np.asarray(first.values)[i], first.digits)}: "
                    if first
                    else ""
                )
                text = f"{head}\n{s.reason[i]}"
            self.status.set_text(text)
        return self.moving

    def fit(self) -> None:
        """Fixed limits that hold every frame."""
        xmin, xmax, ymin, ymax = self.scene.extent(pad=0.1)
        self.ax.set_xlim(xmin, xmax)
        self.ax.set_ylim(ymin, ymax)


def _fmt(v: Any, digits: int) -> str:
    v = float(v)
    return "–" if not np.isfinite(v) else f"{v:.{digits}f}"


def _new_axes(ax: Any) -> Axes:
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    _, ax = plt.subplots()
    return ax


def draw_scene(
    scene: Scene,
    frame: int | None = None,
    ax: Axes | None = None,
    *,
    labels: bool = True,
    status: bool = False,
    title: bool = True,
) -> Axes:
    """Draw one frame of ``scene`` on ``ax`` (a new figure if omitted).

    Examples
    --------
    >>> from machdyn import SliderCrank
    >>> from machdyn.draw import scene
    >>> ax = draw_scene(scene(SliderCrank(2.0, 6.0, 0.5), n=12), 3)
    >>> sorted(a.get_gid() for a in ax.lines if a.get_gid())[:3]
    ['joints', 'link2', 'link3']
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    ax = _new_axes(ax)
    k = scene.first_shown() if frame is None else frame
    if not -len(scene) <= k < len(scene):
        raise InputError("frame", f"must select one of the {len(scene)} frames, got {k}")
    k %= len(scene)
    painter = Painter(scene, ax, labels=labels, status=status)
    painter.set_frame(k)
    shown = scene.xy[k][np.isfinite(scene.xy[k])] if scene.shown[k] else scene.xy[0][:0]
    if shown.size:
        ax.update_datalim(np.c_[shown.real, shown.imag])
    for c in scene.curves:
        pts = np.ravel(c.points)
        pts = pts[np.isfinite(pts)]
        if pts.size:
            ax.update_datalim(np.c_[pts.real, pts.imag])
    ax.autoscale_view()
    if title:
        ax.set_title(scene.title + (f"\n{scene.note}" if scene.note else ""), fontsize=10)
    return ax


def animate_scene(
    scene: Scene,
    path: str | Path | None = None,
    *,
    fps: float = 30.0,
    dpi: float = 80,
    figsize: Sequence[float] = (6.0, 4.5),
    labels: bool = True,
) -> FuncAnimation:
    """A matplotlib animation of ``scene``; saved to ``path`` (``.gif``, ``.mp4``, ``.html``).

    Without ``path`` nothing is written: show the returned animation in a
    notebook with ``HTML(anim.to_jshtml())``. An ``.html`` path writes the
    browser page of :func:`machdyn.draw.html.to_html` as well.

    Examples
    --------
    >>> from machdyn import SliderCrank
    >>> from machdyn.draw import scene
    >>> anim = animate_scene(scene(SliderCrank(2.0, 6.0), n=3), dpi=30)
    >>> len(list(anim.new_frame_seq()))
    3
    >>> anim.to_jshtml().count("<img") > 0       # in a notebook: IPython.display.HTML(...)
    True
    """
    from matplotlib.animation import FuncAnimation
    from matplotlib.figure import Figure

    fps = positive("fps", fps)
    kind = None
    if path is not None:
        path = Path(path)
        kind = path.suffix.lower()
        if kind not in ANIMATION_KINDS:
            raise InputError(
                "path",
                f"an animation is saved as {', '.join(ANIMATION_KINDS)}; got {path.name!r}",
            )
        if kind == ".mp4" and shutil.which("ffmpeg") is None:
            raise InputError("path", "MP4 needs ffmpeg on the PATH; save a .gif or .html instead")
    integer("frames", len(scene), minimum=1)
    fig = Figure(figsize=tuple(figsize), dpi=dpi, layout="constrained")
    ax = fig.add_subplot()
    painter = Painter(scene, ax, labels=labels, status=True)
    painter.fit()
    ax.set_aspect("equal", adjustable="box")
    ax.set_title(scene.title, fontsize=10)
    # Lay the figure out once (with the longest status text) and freeze it.
    worst = int(np.argmin(scene.shown)) if not scene.shown.all() else 0
    painter.set_frame(worst)
    fig.draw_without_rendering()
    fig.set_layout_engine("none")

    def update(i: int) -> list[Any]:
        return painter.set_frame(i)

    anim = FuncAnimation(
        fig, update, frames=len(scene), interval=1000.0 / fps, blit=False, cache_frame_data=False
    )
    if kind == ".gif":
        anim.save(path, writer=gif_writer(painter.moving, fps), dpi=fig.dpi)
    elif kind == ".mp4":
        from matplotlib.animation import FFMpegWriter

        anim.save(
            path,
            writer=FFMpegWriter(fps=fps, codec="libx264", extra_args=["-pix_fmt", "yuv420p"]),
            dpi=fig.dpi,
        )
    elif kind == ".html":
        from .html import to_html

        to_html(scene, path, fps=fps, labels=labels)
    return anim


def gif_writer(moving: list[Any], fps: float) -> Any:
    """A GIF writer that draws the still parts once and then only the ``moving`` artists.

    matplotlib's ``PillowWriter`` re-renders the whole figure (tick labels,
    hatching, curves) for every frame; here the background is rendered once
    and restored before each frame, as interactive blitting does.
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
                if artist.get_visible():
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
