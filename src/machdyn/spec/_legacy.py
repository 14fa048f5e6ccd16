"""Old ``machdyn linkage`` files (before ``machdyn = 1``), read into the new format."""

from __future__ import annotations

from typing import Any

from ._context import Context

__all__ = ["is_legacy", "upgrade"]


def is_legacy(doc: Any) -> bool:
    """True for a linkage file of the old format (no ``machdyn`` key, top-level ``points``)."""
    return isinstance(doc, dict) and "machdyn" not in doc and "points" in doc


def upgrade(doc: dict, ctx: Context) -> dict:
    """The new-format document of an old linkage file."""
    raise ctx.error(("machdyn",), "old linkage files are not read yet")
