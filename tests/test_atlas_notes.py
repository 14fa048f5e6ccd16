"""The atlas synthesis's note when nothing comes near, and the order of rejected results."""

from types import SimpleNamespace

import numpy as np

from machdyn.synthesis._atlas_result import NEAR, _far_note, _rank


def result(*distance):
    return SimpleNamespace(distance=np.array(distance, float))


def test_a_best_that_comes_apart_at_a_target_says_so_not_inf_percent():
    note = _far_note(result(0.1, np.inf, 0.2, np.inf), 1.0, "six-bar")
    assert "cannot be assembled at 2 of the 4 targets" in note
    assert "inf" not in note and "%" not in note


def test_a_far_best_gives_its_worst_miss_as_a_share_of_the_size():
    size = 8.0
    note = _far_note(result(0.1, 0.8, 0.2), size, "linkage", " (hint)")
    assert note.endswith("misses by 10.0 % of the targets' size (hint)")  # 0.8 / 8
    assert _far_note(result(0.1, NEAR * size, 0.2), size, "linkage") == ""
    assert _far_note(None, size, "linkage") == "no atlas entry could be placed on these targets"


def test_results_rank_by_targets_lost_then_by_worst_finite_miss():
    rows = [result(0.5, np.inf), result(0.3, 0.4), result(0.1, np.inf), result(np.inf, np.inf),
            result(0.2, 0.1)]  # fmt: skip
    ranked = sorted(rows, key=_rank)
    worst = [(int(np.isinf(r.distance).sum()), r.distance[np.isfinite(r.distance)].max(initial=0))
             for r in ranked]  # fmt: skip
    assert worst == [(0, 0.2), (0, 0.4), (1, 0.1), (1, 0.5), (2, 0.0)]
