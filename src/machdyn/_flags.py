"""The per-sample result contract shared by every solved motion and force result.

A result holds ``status``: 0 where the sample was solved, otherwise an index
into the class's ``REASONS`` table; ``ok`` and ``reason`` are derived from it.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from ._summary import Summarized

__all__ = ["Flagged"]


class Flagged(Summarized):
    """Mixin for result dataclasses with a ``status`` array (0 = solved)."""

    #: Reason text for each status code (code 0 is the empty string).
    REASONS: ClassVar[tuple[str, ...]]

    @property
    def ok(self) -> np.ndarray:
        """True where the sample was solved."""
        return self.status == 0  # type: ignore[attr-defined]

    @property
    def reason(self) -> np.ndarray:
        """Why each sample was not solved (empty string where it was)."""
        return np.asarray(self.REASONS, dtype=object)[self.status]  # type: ignore[attr-defined]
