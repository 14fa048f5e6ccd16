"""The report page: sections of tables, inline figures and the animated drawing, one HTML file.

Nothing is loaded from the network: figures are inline SVG charts
(:meth:`machdyn.draw.chart.Chart.to_svg`), the drawing is the inline-SVG widget
of :mod:`machdyn.draw.html` with its small script, and the style sheet is
inline. Every number a test or a reader may look up carries ``data-key``; on
the page of a machine of several parts, the keys of a part start with its
name (``press:peak_F32``) and its sections are numbered under it.
"""

from __future__ import annotations

import html
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..draw.html import SCRIPT, STYLE
from .checks import Check, describe

__all__ = ["Page", "fmt"]


def esc(text: Any) -> str:
    """HTML-escaped text (quotes too)."""
    return html.escape(str(text), quote=True)


def fmt(value: Any, digits: int = 4) -> str:
    """A number as printed in the report (``digits`` significant digits; '–' if undefined).

    Examples
    --------
    >>> fmt(3.14159265), fmt(float("nan")), fmt(12345678.0)
    ('3.142', '–', '1.235e+07')
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        return esc(value)
    if not np.isfinite(v):
        return "–"
    return f"{v:.{digits}g}"


@dataclass
class Page:
    """A report being written: a title, a first line, then sections.

    A section is ``(id, title, body, level)``: level 2, or 3 for the sections
    of a part on a machine's page (:mod:`machdyn.report.machine`, which also
    prefixes the part's data keys with its name).
    """

    title: str
    headline: str
    sections: list[tuple[str, str, str, int]] = field(default_factory=list)
    failed: bool = False

    def finished(self) -> Page:
        """The page, its first line marked when a self-check failed (the end of every report)."""
        if self.failed:
            self.headline = "SELF-CHECK FAILED — " + self.headline
        return self

    def key(self, name: str) -> str:
        """A data key of the part being written."""
        return name

    def section(self, key: str, title: str, body: str) -> None:
        """Add a section (``key`` becomes its id)."""
        self.sections.append((key, title, body, 2))

    def span(self, key: str, text: str) -> str:
        """``text`` (HTML) marked with a data key."""
        return f'<span data-key="{esc(self.key(key))}">{text}</span>'

    def table(self, rows: list[tuple[str, str, str]], head: tuple[str, ...] = ()) -> str:
        """Rows of (label, value HTML, data-key or '') as a two-column table."""
        out = ['<table class="facts">']
        if head:
            out.append("<tr>" + "".join(f"<th>{esc(h)}</th>" for h in head) + "</tr>")
        for label, value, key in rows:
            attr = f' data-key="{esc(self.key(key))}"' if key else ""
            out.append(f"<tr><td>{esc(label)}</td><td{attr}>{value}</td></tr>")
        out.append("</table>")
        return "".join(out)

    def grid(self, head: tuple[str, ...], rows: list[list[str]], cls: str = "grid") -> str:
        """A table of already-formatted cells (escaped here)."""
        out = [f'<table class="{cls}"><tr>' + "".join(f"<th>{esc(h)}</th>" for h in head) + "</tr>"]
        for row in rows:
            out.append("<tr>" + "".join(f"<td>{c}</td>" for c in row) + "</tr>")
        out.append("</table>")
        return "".join(out)

    def checks(self, checks: list[Check]) -> str:
        """The self-check table; a failed check makes the headline say so."""
        rows = []
        for c in checks:
            state = "pass" if c.passed else ("not measured" if c.samples == 0 else "FAIL")
            if state == "FAIL":
                self.failed = True
            key = re.sub(r"[^a-z0-9]+", "_", c.name.lower()).strip("_")
            rows.append(
                f'<tr class="{state.split()[0].lower()}" data-check="{esc(self.key(key))}">'
                f'<td>{esc(c.name)}</td><td data-key="{esc(self.key("check_" + key))}">'
                f"{describe(c.value)}</td>"
                f'<td>{c.tolerance:.0e}</td><td>{c.samples}</td><td class="state">{state}</td>'
                f"<td>{esc(c.what)}</td></tr>"
            )
        return (
            '<table class="checks"><tr><th>check</th><th>value</th><th>tolerance</th>'
            "<th>samples</th><th>result</th><th>what is compared</th></tr>"
            + "".join(rows)
            + "</table>"
        )

    def html(self) -> str:
        """The whole page."""
        toc = "".join(
            f'<li class="l{level}"><a href="#{esc(k)}">{esc(t)}</a></li>'
            for k, t, _, level in self.sections
        )
        body = "".join(
            f'<section id="{esc(k)}" class="l{level}"><h{level}>{esc(t)}</h{level}>{b}</section>'
            for k, t, b, level in self.sections
        )
        cls = "headline bad" if self.failed else "headline"
        return (
            '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
            '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
            f"<title>machdyn report: {esc(self.title)}</title>\n"
            f"<style>{STYLE}{REPORT_STYLE}</style>\n</head>\n<body>\n"
            f'<p class="{cls}" id="headline">{esc(self.headline)}</p>\n'
            f"<h1>machdyn report: {esc(self.title)}</h1>\n"
            f"<nav><ol>{toc}</ol></nav>\n{body}\n<script>{SCRIPT}</script>\n</body>\n</html>\n"
        )


REPORT_STYLE = """
body { max-width: 1000px; margin: 1em auto; padding: 0 1em; line-height: 1.4; }
h1 { font-size: 1.35em; margin: 0.3em 0; }
h2 { font-size: 1.1em; border-bottom: 1px solid #ccc; margin-top: 1.6em; }
.headline { font-size: 1.05em; font-weight: 600; background: #eef6ee;
            border-left: 4px solid #2ca02c;
            padding: 0.4em 0.7em; margin: 0; }
.headline.bad { background: #fbeaea; border-left-color: #d62728; }
nav ol { columns: 2; font-size: 0.9em; color: #555; }
nav li.l3 { margin-left: 1.2em; list-style: circle; }
nav ol:has(li.l3) { list-style: none; }
h3 { font-size: 1.0em; margin-top: 1.2em; color: #333; }
section.l2.part { border-top: 3px solid #888; }
table.facts, table.grid, table.checks { border-collapse: collapse; margin: 0.5em 0;
  font-variant-numeric: tabular-nums; font-size: 0.92em; }
table.facts td, table.grid td, table.grid th, table.checks td, table.checks th {
  border-bottom: 1px solid #e4e4e4; padding: 0.2em 0.7em; text-align: left; vertical-align: top; }
table.facts td:first-child { color: #444; }
table.checks tr.pass td.state { color: #2a7d2a; font-weight: 600; }
table.checks tr.fail td.state { color: #c00; font-weight: 700; }
table.checks tr.not td.state { color: #888; }
svg.chart { max-width: 100%; height: auto; display: block; margin: 0.4em 0; }
.charts { display: flex; flex-wrap: wrap; gap: 0.5em; }
.charts svg.chart { display: inline-block; }
.remark { color: #555; font-size: 0.9em; }
@media print { nav { display: none; } .controls { display: none; }
  section { break-inside: avoid; } }
"""
