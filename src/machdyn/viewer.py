"""The browser viewer (moved to :mod:`machdyn.draw.viewer`; these names stay here)."""

from __future__ import annotations

from .draw.viewer import DATA_ID, page_data, to_html

__all__ = ["DATA_ID", "page_data", "to_html"]
