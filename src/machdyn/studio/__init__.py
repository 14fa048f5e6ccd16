"""The machdyn studio: design a mechanism in the browser (``machdyn studio [FILE]``).

A local web server (:mod:`machdyn.studio.server`, bound to 127.0.0.1) serves a
single page (``static/``: ES modules, no build step) that sketches and edits a
linkage document — a machine file of ``docs/spec.md`` — and shows what the
library computes of it, live: the motion over the driver's range, coupler
curves, plots of any quantity, instant centres, mobility, the Assur groups and
their assembly, unassemblable ranges; synthesis from points picked on the
canvas; save, load, share (the document in the URL) and export.

The server is a thin layer over the public Python API
(:mod:`~machdyn.studio.analysis`, :mod:`~machdyn.studio.exports`,
:mod:`~machdyn.studio.synthesis`); the page computes no physics.
"""

from __future__ import annotations

__all__: list[str] = []
