"""Charts: one description of an engineering plot, rendered by matplotlib or as inline SVG.

A :class:`Chart` says what a plot shows — labelled axes with units, series
(NaN entries are gaps), shaded bands, reference lines, marked points and
notes — and :meth:`Chart.to_svg` writes it as a small inline ``<svg>`` (no
matplotlib: the report draws its figures in milliseconds) while
:meth:`Chart.to_mpl` draws the same chart on matplotlib Axes.
"""

from __future__ import annotations

import html
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Chart", "Series", "figure", "nice_ticks"]

COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2")


@dataclass(frozen=True)
class Series:
    """One curve (``x``, ``y``; NaN is a gap), or marked points with ``marker``.

    ``gid`` names the drawn line (matplotlib gid, ``data-series`` in SVG) so
    that it can be found again.
    """

    x: np.ndarray
    y: np.ndarray
    label: str = ""
    colour: str = ""
    dashed: bool = False
    marker: bool = False
    width: float = 1.5
    gid: str = ""


@dataclass(frozen=True)
class Chart:
    """An engineering plot: title, axis labels (quantity and unit), series, bands, lines, notes.

    Attributes
    ----------
    bands : list of (x, y_low, y_high, colour)
        Shaded areas between two curves.
    hlines : list of (y, label, colour)
        Horizontal reference lines (limits, averages).
    notes : list of (x, y, text)
        Text placed at data coordinates.
    equal : bool
        Same scale on both axes (polar force plots, paths).
    """

    title: str
    xlabel: str
    ylabel: str
    series: list[Series] = field(default_factory=list)
    bands: list[tuple[np.ndarray, np.ndarray, np.ndarray, str]] = field(default_factory=list)
    hlines: list[tuple[float, str, str]] = field(default_factory=list)
    notes: list[tuple[float, float, str]] = field(default_factory=list)
    equal: bool = False
    ylim: tuple[float, float] | None = None

    # -- limits -------------------------------------------------------------------
    def limits(self) -> tuple[float, float, float, float]:
        """``(xmin, xmax, ymin, ymax)`` of everything drawn, padded (squared when ``equal``)."""
        xs = [np.ravel(s.x) for s in self.series] + [np.ravel(b[0]) for b in self.bands]
        ys = [np.ravel(s.y) for s in self.series] + [np.ravel(b[1]) for b in self.bands]
        ys += [np.ravel(b[2]) for b in self.bands] + [np.array([h[0]]) for h in self.hlines]
        x = np.concatenate(xs) if xs else np.zeros(1)
        y = np.concatenate(ys) if ys else np.zeros(1)
        x, y = x[np.isfinite(x)], y[np.isfinite(y)]
        x0, x1 = (float(x.min()), float(x.max())) if x.size else (0.0, 1.0)
        y0, y1 = (float(y.min()), float(y.max())) if y.size else (0.0, 1.0)
        if self.ylim is not None:
            y0, y1 = self.ylim
        if x1 == x0:
            x0, x1 = x0 - 1, x1 + 1
        if y1 == y0:
            y0, y1 = y0 - 1, y1 + 1
        pad = 0.05 * (y1 - y0)
        if self.ylim is None:
            y0, y1 = y0 - pad, y1 + pad
        if self.equal:
            cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
            half = 0.55 * max(x1 - x0, y1 - y0)
            return cx - half, cx + half, cy - half, cy + half
        return x0, x1, y0, y1

    # -- matplotlib ---------------------------------------------------------------
    def to_mpl(self, ax: Any) -> Any:
        """Draw the chart on matplotlib Axes (returns them)."""
        for k, s in enumerate(self.series):
            colour = s.colour or COLOURS[k % len(COLOURS)]
            if s.marker:
                (line,) = ax.plot(
                    s.x, s.y, "o", color=colour, ms=5, label=s.label or None, zorder=5
                )
            else:
                (line,) = ax.plot(
                    s.x,
                    np.ma.masked_invalid(s.y),
                    color=colour,
                    lw=s.width,
                    ls="--" if s.dashed else "-",
                    label=s.label or None,
                )
            if s.gid:
                line.set_gid(s.gid)
        for x, lo, hi, colour in self.bands:
            ax.fill_between(x, lo, hi, color=colour, alpha=0.25, lw=0)
        for y, label, colour in self.hlines:
            ax.axhline(
                y,
                color=colour,
                ls="--" if label else "-",
                lw=1.0 if label else 0.6,
                label=label or None,
                zorder=0 if not label else 2,
            )
        for x, y, text in self.notes:
            t = ax.annotate(
                text,
                (x, y),
                fontsize=7.5,
                ha="center",
                va="center",
                bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8},
            )
            t.set_parse_math(False)
        if self.ylim is not None:
            ax.set_ylim(*self.ylim)
        if self.equal:
            ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(self.xlabel)
        ax.set_ylabel(self.ylabel)
        ax.set_title(self.title, fontsize=9)
        ax.grid(True, lw=0.3)
        if any(s.label for s in self.series) or any(label for _, label, _ in self.hlines):
            ax.legend(fontsize=7.5, loc="best")
        return ax

    # -- SVG ------------------------------------------------------------------------
    def to_svg(self, width: int = 640, height: int = 300) -> str:
        """The chart as an inline ``<svg>`` element (text as text, escaped)."""
        e = html.escape
        legend = [
            (s.label, s.colour or COLOURS[k % len(COLOURS)], s.dashed)
            for k, s in enumerate(self.series)
            if s.label
        ]
        legend += [(lab, col, True) for _, lab, col in self.hlines if lab]
        # the legend sits right of the plot, never over the curves
        extra = int(min(260, 36 + 6.8 * max(len(t) for t, _, _ in legend))) if legend else 0
        width += extra  # the plot keeps its size; the legend is added on the right
        # a title wider than the chart is wrapped (12 px bold: ~7 px a character), never cut off
        title = _wrap(self.title, max(12, int((width - 12) / 7.2)))
        left, right, top, bottom = 62, 14 + extra, 26 + 15 * (len(title) - 1), 44
        if self.equal:
            height = (width - left - right) + top + bottom  # a square plot
        w, h = width - left - right, height - top - bottom
        x0, x1, y0, y1 = self.limits()
        if self.equal:  # same units per pixel on both axes
            scale = min(w / (x1 - x0), h / (y1 - y0))
            cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
            x0, x1 = cx - 0.5 * w / scale, cx + 0.5 * w / scale
            y0, y1 = cy - 0.5 * h / scale, cy + 0.5 * h / scale

        def X(v: Any) -> Any:
            return left + (np.asarray(v, float) - x0) / (x1 - x0) * w

        def Y(v: Any) -> Any:
            return top + (y1 - np.asarray(v, float)) / (y1 - y0) * h

        out = [
            f'<svg class="chart" viewBox="0 0 {width} {height}" width="{width}" '
            f'height="{height}" role="img" aria-label="{e(self.title)}" '
            'font-family="system-ui, sans-serif" font-size="11">',
            f'<text class="title" x="{width / 2:.1f}" y="16" text-anchor="middle" '
            'font-size="12" font-weight="600">'
            + "".join(
                f'<tspan x="{width / 2:.1f}" dy="{15 if i else 0}">{e(t)}</tspan>'
                for i, t in enumerate(title)
            )
            + "</text>",
        ]
        clip = f"c{abs(hash((self.title, self.xlabel))) % 10**8}"
        out.append(
            f'<defs><clipPath id="{clip}"><rect x="{left}" y="{top}" width="{w}" '
            f'height="{h}"/></clipPath></defs>'
        )
        out.append(
            f'<rect x="{left}" y="{top}" width="{w}" height="{h}" fill="#fff" stroke="#999"/>'
        )
        for t in nice_ticks(x0, x1):
            px = float(X(t))
            out.append(
                f'<line x1="{px:.1f}" y1="{top}" x2="{px:.1f}" y2="{top + h}" stroke="#eee"/>'
                f'<text x="{px:.1f}" y="{top + h + 14}" text-anchor="middle">{_tick(t)}</text>'
            )
        for t in nice_ticks(y0, y1):
            py = float(Y(t))
            out.append(
                f'<line x1="{left}" y1="{py:.1f}" x2="{left + w}" y2="{py:.1f}" stroke="#eee"/>'
                f'<text x="{left - 5}" y="{py + 4:.1f}" text-anchor="end">{_tick(t)}</text>'
            )
        out.append(
            f'<text class="axis-label x" x="{left + w / 2:.1f}" y="{height - 8}" '
            f'text-anchor="middle">{e(self.xlabel)}</text>'
        )
        out.append(
            f'<text class="axis-label y" transform="translate(14 {top + h / 2:.1f}) rotate(-90)" '
            f'text-anchor="middle">{e(self.ylabel)}</text>'
        )
        out.append(f'<g clip-path="url(#{clip})">')
        for x, lo, hi, colour in self.bands:
            for run in _runs(np.isfinite(lo) & np.isfinite(hi)):
                pts = [
                    *zip(X(x[run]), Y(hi[run]), strict=True),
                    *zip(X(x[run])[::-1], Y(lo[run])[::-1], strict=True),
                ]
                out.append(
                    f'<polygon points="{_pts(pts)}" fill="{e(colour)}" fill-opacity="0.25"/>'
                )
        for y, _, colour in self.hlines:
            out.append(
                f'<line x1="{left}" x2="{left + w}" y1="{float(Y(y)):.1f}" '
                f'y2="{float(Y(y)):.1f}" stroke="{e(colour)}" stroke-dasharray="6 4"/>'
            )
        for k, s in enumerate(self.series):
            colour = e(s.colour or COLOURS[k % len(COLOURS)])
            x, y = np.ravel(np.asarray(s.x, float)), np.ravel(np.asarray(s.y, float))
            if s.marker:
                for a, b in zip(X(x), Y(y), strict=True):
                    if np.isfinite(a) and np.isfinite(b):
                        out.append(f'<circle cx="{a:.1f}" cy="{b:.1f}" r="3.5" fill="{colour}"/>')
                continue
            dash = ' stroke-dasharray="5 3"' if s.dashed else ""
            dash += f' data-series="{e(s.gid)}"' if s.gid else ""
            for run in _runs(np.isfinite(x) & np.isfinite(y)):
                if run.stop - run.start > 1:
                    pts = zip(X(x[run]), Y(y[run]), strict=True)
                    out.append(
                        f'<polyline points="{_pts(pts)}" fill="none" stroke="{colour}" '
                        f'stroke-width="{s.width}"{dash}/>'
                    )
                elif run.stop - run.start == 1:  # an isolated sample: a dot, not nothing
                    a, b = float(X(x[run.start])), float(Y(y[run.start]))
                    out.append(f'<circle cx="{a:.1f}" cy="{b:.1f}" r="1.5" fill="{colour}"/>')
        out.append("</g>")
        placed: list[tuple[float, float, float, float]] = []
        for x, y, text in self.notes:
            px = float(X(x))
            anchor = (
                "start" if px < left + 0.2 * w else ("end" if px > left + 0.8 * w else "middle")
            )
            px += 6 if anchor == "start" else (-6 if anchor == "end" else 0)
            # a note that would overlap one already drawn is left out (notes come most
            # important first), never drawn over it (10 px text: ≤ 6.2 px a character)
            tw = 6.2 * len(text) + 4
            bx = px - {"start": 0.0, "middle": 0.5, "end": 1.0}[anchor] * tw
            box = (bx, float(Y(y)) - 11, bx + tw, float(Y(y)) + 4)
            if any(_overlap(box, b) for b in placed):
                continue
            placed.append(box)
            out.append(
                f'<text x="{px:.1f}" y="{float(Y(y)):.1f}" text-anchor="{anchor}" '
                f'font-size="10" paint-order="stroke" stroke="#fff" stroke-width="3">'
                f"{e(text)}</text>"
            )
        for k, (label, colour, dashed) in enumerate(legend):
            yy = top + 12 + 14 * k
            dash = ' stroke-dasharray="5 3"' if dashed else ""
            out.append(
                f'<line x1="{left + w + 8}" x2="{left + w + 26}" y1="{yy - 4}" '
                f'y2="{yy - 4}" stroke="{e(colour)}" stroke-width="2"{dash}/>'
                f'<text x="{left + w + 30}" y="{yy}" paint-order="stroke" stroke="#fff" '
                f'stroke-width="3">{e(label)}</text>'
            )
        out.append("</svg>")
        return "".join(out)


def _wrap(text: str, chars: int) -> list[str]:
    """``text`` in lines of at most ``chars`` characters, broken at spaces where possible."""
    import textwrap

    return textwrap.wrap(text, chars, break_on_hyphens=False) or [text]


def _overlap(a: tuple[float, ...], b: tuple[float, ...]) -> bool:
    """Whether boxes ``(x0, y0, x1, y1)`` ``a`` and ``b`` intersect."""
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def _pts(pairs: Any) -> str:
    return " ".join(f"{a:.1f},{b:.1f}" for a, b in pairs)


def _runs(good: np.ndarray) -> list[slice]:
    """Slices of consecutive True entries."""
    good = np.asarray(good, bool)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], good.astype(int), [0]])))
    return [slice(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def _tick(v: float) -> str:
    return f"{v:.6g}" if abs(v) >= 1e-12 else "0"


def nice_ticks(lo: float, hi: float, target: int = 6) -> list[float]:
    """Round tick values covering ``[lo, hi]`` (steps of 1, 2, 2.5 or 5 × 10ⁿ).

    Examples
    --------
    >>> nice_ticks(0, 360)
    [0.0, 100.0, 200.0, 300.0]
    """
    span = hi - lo
    if not math.isfinite(span) or span <= 0:
        return []
    raw = span / target
    mag = 10 ** math.floor(math.log10(raw))
    step = next(m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw)
    first = math.ceil(lo / step) * step
    return [float(round(first + i * step, 12)) for i in range(int((hi - first) / step + 1e-9) + 1)]


def figure(
    charts: list[Chart],
    *,
    fig: Any = None,
    columns: int = 1,
    sharex: bool = False,
    panel: tuple[float, float] = (7.0, 1.9),
) -> Any:
    """Draw ``charts`` on one matplotlib Figure, a panel each (returns the Figure).

    The charts are the plots' descriptions; this is their one matplotlib
    renderer (the report writes the same charts as inline SVG). With
    ``sharex`` the panels of a column share the x axis and only the bottom one
    is labelled.

    Examples
    --------
    >>> c = Chart("a", "x (s)", "y (m)", [Series(np.arange(3.0), np.ones(3), gid="y")])
    >>> fig = figure([c, c], sharex=True)
    >>> [ax.get_ylabel() for ax in fig.axes], fig.axes[1].lines[0].get_gid()
    (['y (m)', 'y (m)'], 'y')
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    if not charts:
        from ..errors import InputError

        raise InputError("charts", "give at least one chart")
    cols = max(1, min(int(columns), len(charts)))
    rows = -(-len(charts) // cols)
    if fig is None:  # pyplot's, so that plt.show() and notebooks show it
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(panel[0] * cols, panel[1] * rows + 0.6), layout="constrained")
    axes = fig.subplots(rows, cols, sharex=sharex, squeeze=False)
    flat = axes.T.ravel() if sharex else axes.ravel()  # a shared column is read top to bottom
    for ax, chart in zip(flat, charts, strict=False):
        chart.to_mpl(ax)
    for ax in flat[len(charts) :]:
        ax.set_visible(False)
    if sharex:
        for ax in flat[: len(charts)]:
            if not ax.get_subplotspec().is_last_row():
                ax.set_xlabel("")
    return fig
