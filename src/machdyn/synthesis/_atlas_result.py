"""What a path synthesis from an atlas returns, and how its results are ranked and noted.

Shared by the four-bar (:mod:`~machdyn.synthesis.atlas_path`) and six-bar
(:mod:`~machdyn.synthesis.sixbar_path`) syntheses.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ._atlas_index import _Deadline
from .path import PathSynthesis

__all__: list[str] = []  # (machdyn.synthesis re-exports PathCandidates)

#: How many of the refined candidates are refined on to convergence.
POLISH = 3
#: A best result farther than this (over the target's size) means no entry came near.
NEAR = 0.05


@dataclass(frozen=True, eq=False)
class PathCandidates:
    """Linkages for a path, best first, from :func:`path_from_atlas`.

    Attributes
    ----------
    candidates : tuple of PathSynthesis or of SixBarPath
        Defect-free, distinct linkages, best (smallest worst distance) first
        (four-bars from a four-bar atlas, six-bars from a six-bar atlas).
    rejected : tuple of PathSynthesis
        Refined linkages that failed a check (with their ``defects``).
    targets : ndarray of complex
    near : bool
        False when even the best result misses a target by more than
        :data:`NEAR` of the target's size (no atlas entry came near).
    note : str
        What to know about the result (empty if nothing).
    seconds : dict
        Time spent retrieving and refining.
    """

    candidates: tuple[PathSynthesis, ...]
    rejected: tuple[PathSynthesis, ...]
    targets: np.ndarray
    near: bool
    note: str
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def best(self) -> PathSynthesis:
        """The best candidate (or the best rejected one if none passed)."""
        pool = self.candidates or self.rejected
        if not pool:
            raise InputError("targets", "no linkage was found for these targets")
        return pool[0]


def _rank(result: PathSynthesis) -> tuple[int, float]:
    """Sort key of a checked result: targets it cannot be assembled at, then its worst miss."""
    distance = np.asarray(result.distance, float)
    finite = np.isfinite(distance)
    return int(np.count_nonzero(~finite)), float(np.max(distance, where=finite, initial=0.0))


def _far_note(best: PathSynthesis | None, size: float, linkage: str, hint: str = "") -> str:
    """Why no result comes near the targets ("" when the best does, within :data:`NEAR`)."""
    if best is None:
        return "no atlas entry could be placed on these targets"
    distance = np.asarray(best.distance, float)
    lost = int(np.count_nonzero(~np.isfinite(distance)))
    if lost:  # (a distance of inf: the linkage cannot be assembled there)
        return (f"no atlas entry comes near these targets: the best {linkage} found cannot be "
                f"assembled at {lost} of the {distance.size} targets{hint}")  # fmt: skip
    worst = float(np.max(distance)) / size
    if worst <= NEAR:
        return ""
    return (f"no atlas entry comes near these targets: the best {linkage} found misses by "
            f"{100 * worst:.1f} % of the targets' size{hint}")  # fmt: skip


def _closer_note(best: PathSynthesis, closer: PathSynthesis, size: float) -> str:
    """The note when the defect-free results miss but one with defects comes near."""
    worst = float(np.max(best.distance)) / size
    near = float(np.max(closer.distance)) / size
    return (f"the linkages free of defects miss by {100 * worst:.1f} % of the targets' size; "
            f"one with defects comes within {100 * near:.1e} % ({'; '.join(closer.defects)}): "
            "see rejected")  # fmt: skip


def _limit_note(note: str, deadline: _Deadline, time_limit: float | None, total: float) -> str:
    """``note`` with, when the synthesis stopped at its time limit, a sentence saying so."""
    if not deadline.hit:
        return note
    stop = (f"stopped at the time limit ({time_limit:g} s) after {total:.2f} s: the best "
            "linkages found by then (without the limit the search goes on)")  # fmt: skip
    return f"{stop}; {note}" if note else stop
