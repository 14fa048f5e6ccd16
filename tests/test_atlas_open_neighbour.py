"""Open untimed targets: the neighbour round (atlas entries nearest to the best fits).

The targets are ``bench_atlas_random.py --kinds open --seed 1``'s case 13: nine points over
5–95 % of the input's range of a non-Grashof four-bar whose input is its longest link
(Barker's RRR2), on one assembly. On the 10^7 atlas the three pools' fits all stall at one
curve 3.5e-5 of the size (RMS) off the targets (its cognates and twins: four distinct fits in
design numbers), and none of the pools' entries lies in an exact answer's basin; of the
atlas's first 10^6 entries, the 40 nearest to the third of those fits in design numbers
hold some that refine to an exact answer (in each of five disjoint 10^6-entry tenths of the
atlas). Here the first round is faked to start from that fit alone, and a small atlas holds
4,000 random four-bars within ±0.5 of it in each design number: about the atlas's own
density there (its first 10^6 entries hold 4,356 in that box; the 40 nearest lie within 0.28
of the fit there, within 0.28–0.31 here). Which entries those are is a lottery: of eight such
random neighbourhoods (seeds 1–8), six held one that refines to an answer; seed 1 is one of
them. The round's answer is checked by the independent point-to-curve distance of
tests/test_synthesis_path_atlas.py (circle intersections and a scalar minimisation; no
machdyn solver), against the drawing linkage's own targets.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from tests.test_synthesis_path_atlas import _curve_distance

from machdyn.fourbar import FourBar
from machdyn.synthesis import PlacedFourBar
from machdyn.synthesis import atlas_path as AP
from machdyn.synthesis.atlas_store import META_DTYPE, barker_numbers

OPTIONS = dict(timing=None, crank=False, mu_min=0.0, fixed={}, max_length=None, pivot_box=None)
#: The drawing linkage (lengths r1..r4, coupler point (p, δ), form 2 as FourBar.solve's), its
#: placement and the crank angles of the targets (as the benchmark drew them).
TRUTH = FourBar(0.9378054260113694, 2.2255385772090635, 1.1738806796829289, 1.2225824691000338,
                coupler=(1.1907301988437746, -0.2589264525291637))  # fmt: skip
PLACE, TURN = 3.3313976268088616 - 4.4220940566626705j, -0.5707672749948023 - 1.210213476266248j
THETA = np.radians(np.array([280.0, 300.0, 320.0, 340.0, 0.0, 19.5, 39.5, 59.5, 79.5]))
#: The stalled fit the neighbour round starts from: design (r1, r2, r3, r4, p, δ, O2, θ1).
FIT = np.array([2.103763121530126, 2.0482712784651778, 2.4933530761280296, 2.3787767569438136,
                0.6531645884616116, 0.21231741788754635, 2.215121776787453, -5.643666002525211,
                0.12071300122877467])  # fmt: skip


def _targets() -> np.ndarray:
    """The drawing linkage's coupler points at THETA, placed (by its own solver, form 2)."""
    return PLACE + TURN * np.asarray(TRUTH.solve(THETA, 1.0, form=2).coupler)


TARGETS = _targets()
SIZE = float(np.max(np.abs(TARGETS - TARGETS.mean())))


class _SmallAtlas:
    """What the neighbour round reads of an atlas: its rows (one chunk), placed entries."""

    def __init__(self, rows: np.ndarray) -> None:
        self.meta = [rows]
        self.offsets = np.array([0, rows.size])
        self.manifest = SimpleNamespace(circuit_samples=256, samples=128)

    def entries(self, index) -> np.ndarray:
        return self.meta[0][np.asarray(index)]


def _rows_around(x: np.ndarray, count: int, spread: float, seed: int) -> np.ndarray:
    """``count`` random four-bars within ±``spread`` of a design's numbers (ln r1/r2, ln r3/r2,
    ln r4/r2, the coupler point over r3), the first being the design itself (as an atlas
    row: lengths over r2); assemblable ones only."""
    rng = np.random.default_rng(seed)
    r1, r2, r3, r4, p, delta = x[:6]
    c = p / r3 * np.exp(1j * delta)
    base = np.array([np.log(r1 / r2), np.log(r3 / r2), np.log(r4 / r2), c.real, c.imag])
    v = base + rng.uniform(-spread, spread, (4 * count, 5))
    v[0] = base
    lengths = np.vstack([np.exp(v[:, 0]), np.ones(len(v)), np.exp(v[:, 1]), np.exp(v[:, 2])])
    srt = np.sort(lengths, axis=0)
    ok = srt[3] < srt[0] + srt[1] + srt[2]
    v, lengths = v[ok][:count], lengths[:, ok][:, :count]
    rows = np.zeros(len(v), META_DTYPE)
    rows["r1"], rows["r3"], rows["r4"] = lengths[0], lengths[2], lengths[3]
    cp = (v[:, 3] + 1j * v[:, 4]) * lengths[2]
    rows["p"], rows["delta"] = np.abs(cp), np.angle(cp)
    rows["circuit"] = rng.choice(np.array([-1, 1], np.int8), len(v))
    rows["barker"] = barker_numbers(lengths)
    return rows


def _faked_first_round(monkeypatch, rows):
    """atlas_path's first round starts from the stalled fit alone (the atlas row of its
    design, placed as it is); no wide four-bars, no pool rounds."""
    place = np.array([[FIT[1] * np.exp(1j * FIT[8]), complex(FIT[6], FIT[7])]])
    monkeypatch.setattr(AP, "_retrieve", lambda *a, **k: (rows[:1], place))
    monkeypatch.setattr(AP, "_retrieve_wide", lambda *a, **k: (rows[:0], place[:0]))
    monkeypatch.setattr(AP, "UNTIMED_ROUNDS", 1)


def _worst_answer(fits, most: int = 3) -> float:
    """Least largest independent distance to the targets (over their size) among the ``most``
    best fits (by RMS) that are answers (one assembly, the targets in order along the
    curve); inf if none is."""
    answers = [f for f in fits if np.ptp(f.branch) == 0 and AP._in_order(f.theta, False, None)]
    best = np.inf
    for f in sorted(answers, key=lambda f: f.rms)[:most]:
        x = f.x
        placed = PlacedFourBar(FourBar(*x[:4], coupler=(x[4], x[5])), complex(x[6], x[7]),
                               float(x[8]), int(f.branch[0]))  # fmt: skip
        with np.errstate(invalid="ignore"):
            d = _curve_distance(SimpleNamespace(linkage=placed, theta2=f.theta), TARGETS)
        best = min(best, float(np.max(d)) / SIZE)
    return best


def test_targets_are_the_drawing_linkages():
    # the drawing linkage scaled by |TURN| and placed: the targets lie on its curve, by the
    # tests' own circle intersections (on the assembly whose pose gives the first target)
    scaled = FourBar(*(abs(TURN) * np.array(TRUTH.lengths)),
                     coupler=(abs(TURN) * TRUTH.coupler[0], TRUTH.coupler[1]))  # fmt: skip
    placed = [PlacedFourBar(scaled, PLACE, float(np.angle(TURN)), b) for b in (1, -1)]
    placed = min(placed, key=lambda pl: abs(pl.pose(THETA[0])[2] - TARGETS[0]))
    d = _curve_distance(SimpleNamespace(linkage=placed, theta2=THETA), TARGETS)
    assert np.max(d) <= 1e-9 * SIZE


def test_neighbour_round_meets_an_arc_the_first_round_misses(compiled, monkeypatch):
    rows = _rows_around(FIT, 4000, 0.5, seed=1)
    atlas = _SmallAtlas(rows)
    _faked_first_round(monkeypatch, rows)
    # without the neighbour round: the fit stays where it stalled, 6e-5 of the size off
    monkeypatch.setattr(AP, "OPEN_NEIGHBOURS", False)
    fits, _ = AP._untimed_fits(atlas, TARGETS, False, False, 160, 10, None, OPTIONS)
    assert AP._worth_a_round(fits, TARGETS, False)  # (near, but met by none)
    assert _worst_answer(fits) > 1e-5
    # with it: an exact answer from the entries around the fit
    monkeypatch.setattr(AP, "OPEN_NEIGHBOURS", True)
    fits, _ = AP._untimed_fits(atlas, TARGETS, False, False, 160, 10, None, OPTIONS)
    assert _worst_answer(fits) <= 1e-6
