"""Coupler-curve atlas: descriptors, circuits, the chunked store, Dask, refusal of bad atlases."""

from __future__ import annotations

import json

import numpy as np
import pytest
from tests.closed_forms import circle_meet

from machdyn.classify import classify
from machdyn.errors import InputError
from machdyn.fourbar import FourBar
from machdyn.synthesis.atlas_path import open_atlas
from machdyn.synthesis.atlas_store import (
    AtlasError,
    barker_numbers,
    build_atlas,
    sample_fourbars,
)
from machdyn.synthesis.circuits import circuit_points
from machdyn.synthesis.descriptor import curve_descriptor, descriptor_variants

# --------------------------------------------------------------------------------------
# descriptors


def _dense_curve(lengths, coupler, n=2000):
    fb = FourBar(*lengths, coupler=coupler)
    m = fb.solve(np.linspace(0, 2 * np.pi, n, endpoint=False))
    assert m.assembled.all()
    return m.coupler


@pytest.mark.parametrize(
    "lengths, coupler",
    [((8, 4, 7, 6), (5.0, 0.5)), ((5, 2, 5, 4), (3.0, 0.6)), ((3, 1, 3.5, 2.5), (2.0, -1.2))],
)
def test_descriptor_is_invariant_to_placement_size_start_and_direction(lengths, coupler):
    z = _dense_curve(lengths, coupler)
    d = curve_descriptor(z)
    assert abs(float(d @ d) - 1.0) < 1e-6
    moved = [
        z + (3.0 - 7.0j),  # translated
        z * np.exp(1.1j),  # rotated
        z * 4.5,  # scaled
        np.roll(z, 613),  # started elsewhere
        z[::-1],  # run the other way round
        (2 + 1j) + 0.3 * np.exp(-2.0j) * np.roll(z[::-1], 77),  # all at once
    ]
    for w in moved:
        dw = curve_descriptor(w)
        gap = np.min(np.abs(descriptor_variants(d) - dw).max(axis=-1))
        assert gap < 2e-4
    # and a different curve is far away
    other = curve_descriptor(_dense_curve((8, 4, 7, 6), (2.0, 2.0)))
    assert np.min(np.abs(descriptor_variants(d) - other).max(axis=-1)) > 0.05


def test_barker_numbers_match_classify(rng):
    lengths = rng.uniform(0.2, 5.0, size=(4, 600))
    lengths = lengths[:, 2 * lengths.max(axis=0) < lengths.sum(axis=0)]  # assemblable
    numbers = barker_numbers(lengths)
    for col, num in zip(lengths.T, numbers, strict=True):
        assert classify(*col).number == num


def test_sampler_covers_every_non_change_point_class():
    meta = sample_fourbars(np.random.default_rng(1), 4000)
    assert set(np.unique(meta["barker"])) == set(range(1, 9))
    assert set(np.unique(meta["circuit"])) == {-1, 1}


# --------------------------------------------------------------------------------------
# circuits: every sample is an assembly of the linkage (checked by circle intersection)


@pytest.mark.parametrize(
    "lengths, code",
    [
        ((8, 4, 7, 6), "GCRR"),
        ((4, 3, 1, 3.5), "GRCR"),
        ((5, 4, 2, 2.5), "RRR1"),
        ((2, 4, 3, 4.5), "GCCC"),
    ],
)
@pytest.mark.parametrize("circuit", [1, -1])
def test_circuit_points_are_assemblies_and_close_up(lengths, code, circuit):
    r1, r2, r3, r4 = lengths
    assert classify(*lengths).code == code
    p, delta = 1.3, 0.7
    pts, theta2 = circuit_points([r1], [r2], [r3], [r4], [p], [delta], [circuit], m=400)
    pts, theta2 = pts[0], theta2[0]
    assert np.all(np.isfinite(pts))
    A = r2 * np.exp(1j * theta2)
    sides = set()
    for a, th, P in zip(A, theta2, pts, strict=True):
        best = np.inf
        for side in (1.0, -1.0):
            with np.errstate(invalid="ignore"):
                B = circle_meet(a, r3, complex(r1), r4, side)
            if not np.isfinite(B):  # at a limit: the circles touch
                B = a + r3 * (r1 - a) / abs(r1 - a) * np.sign(abs(r1 - a) - r3 + 1e-300)
            want = a + p * np.exp(1j * delta) * (B - a) / r3
            if abs(want - P) < best:
                best, pick = abs(want - P), side
        assert best < 1e-6 * r1, (th, best)
        sides.add(pick)
    steps = np.abs(np.diff(np.append(pts, pts[0])))
    assert steps.max() < 12 * np.median(steps)  # one continuous closed curve
    if code in ("GCRR", "GCCC"):
        assert len(sides) == 1  # a crank's circuit is one assembly
    else:
        assert sides == {1.0, -1.0}  # a rocker's circuit passes from one to the other


# --------------------------------------------------------------------------------------
# the store


@pytest.fixture(scope="module")
def small_atlas(tmp_path_factory):
    folder = tmp_path_factory.mktemp("atlas") / "a"
    build_atlas(folder, 3000, chunk_size=1200, seed=3, progress=False)
    return folder


def test_every_stored_entry_rebuilds_to_its_descriptor(small_atlas):
    at = open_atlas(small_atlas)
    assert len(at) == 3000
    idx = np.random.default_rng(0).choice(len(at), 60, replace=False)
    rows = at.entries(idx)
    for i, row in zip(idx, rows, strict=True):
        r1, r3, r4, p, delta = (float(row[k]) for k in ("r1", "r3", "r4", "p", "delta"))
        # rebuild independently: A on its circle, B by circle intersection, both circuits' sides
        curve = _rebuild(r1, 1.0, r3, r4, p, delta, int(row["circuit"]))
        chunk = np.searchsorted(at.offsets, i, side="right") - 1
        stored = at.desc[chunk][i - at.offsets[chunk]]
        gap = np.min(np.abs(descriptor_variants(curve_descriptor(curve)) - stored).max(axis=-1))
        assert gap < 2e-3, (row, gap)


def _rebuild(r1, r2, r3, r4, p, delta, circuit, n=4000):
    """A circuit's coupler curve by a dense sweep and circle intersections (no machdyn solver).

    A crank's circuit is the side of AO4 on which φ12 = arg((B − O4)/(B − A)) has the
    circuit's sign; a rocker's is its reachable interval (the upper one for circuit +1 if
    there are two), out on one side and back on the other.
    """
    th = np.linspace(0, 2 * np.pi, n, endpoint=False)
    d = np.abs(r2 * np.exp(1j * th) - r1)
    ok = (d < r3 + r4) & (d > abs(r3 - r4))
    if ok.all():
        a0 = complex(r2)

        def phi12(side):
            b = circle_meet(a0, r3, r1, r4, side)
            return np.angle((b - r1) / (b - a0))

        side = next(s for s in (1.0, -1.0) if np.sign(phi12(s)) == circuit)
        runs = [(th, side)]
    else:
        k = int(np.flatnonzero(~ok)[0])
        rolled, okr = np.roll(th, -k), np.roll(ok, -k)
        jumps = np.diff(np.concatenate([[0], okr.astype(int), [0]]))
        starts, ends = np.flatnonzero(jumps == 1), np.flatnonzero(jumps == -1)
        arcs = [rolled[a:b] for a, b in zip(starts, ends, strict=True)]
        if len(arcs) == 2:
            arcs = [a for a in arcs if np.sign(np.mean(np.sin(a))) == circuit]
        arc = np.unwrap(arcs[0])
        runs = [(arc, 1.0), (arc[::-1], -1.0)]
    pts = []
    for arc, side in runs:
        for a in r2 * np.exp(1j * arc):
            B = circle_meet(a, r3, complex(r1), r4, side)
            pts.append(a + p * np.exp(1j * delta) * (B - a) / r3)
    return np.array(pts)


def test_nearest_finds_an_entry_from_its_own_curve_moved_and_reversed(small_atlas):
    at = open_atlas(small_atlas)
    rows = at.entries(np.arange(len(at)))
    i = int(np.flatnonzero(rows["barker"] == 2)[5])  # a crank-rocker
    row = rows[i]
    r1, r3, r4, p, delta = (float(row[k]) for k in ("r1", "r3", "r4", "p", "delta"))
    curve = _rebuild(r1, 1.0, r3, r4, p, delta, int(row["circuit"]))
    query = curve_descriptor(5 - 2j + 0.2j * np.roll(curve[::-1], 333))
    idx, dist = at.nearest(query, 5)
    assert idx[0] == i
    assert dist[0] < 1e-5


def test_build_resumes_after_an_interruption(tmp_path, small_atlas):
    folder = tmp_path / "b"
    build_atlas(folder, 3000, chunk_size=1200, seed=3, progress=False)
    man = json.loads((folder / "manifest.json").read_text())
    del man["chunks"]["00001"]  # as if the build stopped before chunk 1 was recorded
    (folder / "manifest.json").write_text(json.dumps(man))
    (folder / "chunk_00001.desc.npy").unlink()
    before = (folder / "chunk_00000.desc.npy").stat().st_mtime_ns
    m = build_atlas(folder, 3000, chunk_size=1200, seed=3, progress=False)
    assert m.complete
    assert (folder / "chunk_00000.desc.npy").stat().st_mtime_ns == before  # not rebuilt
    for i in range(3):
        a = np.load(folder / f"chunk_{i:05d}.desc.npy")
        b = np.load(small_atlas / f"chunk_{i:05d}.desc.npy")
        np.testing.assert_array_equal(a, b)


def test_build_refuses_a_folder_holding_another_atlas(tmp_path):
    build_atlas(tmp_path, 100, chunk_size=100, seed=1, progress=False)
    with pytest.raises(AtlasError, match="holds another atlas"):
        build_atlas(tmp_path, 200, chunk_size=100, seed=1, progress=False)


def test_corrupted_stale_or_unfinished_atlases_are_refused(tmp_path):
    folder = tmp_path / "c"
    build_atlas(folder, 500, chunk_size=250, progress=False)
    open_atlas(folder)  # fine
    file = folder / "chunk_00001.desc.npy"
    data = bytearray(file.read_bytes())
    data[-7] ^= 0xFF
    file.write_bytes(bytes(data))
    with pytest.raises(AtlasError, match="CRC"):
        open_atlas(folder)
    man = json.loads((folder / "manifest.json").read_text())
    man["format_version"] = 0
    (folder / "manifest.json").write_text(json.dumps(man))
    with pytest.raises(AtlasError, match="format 0"):
        open_atlas(folder)
    man["format_version"] = 1
    del man["chunks"]["00000"]
    (folder / "manifest.json").write_text(json.dumps(man))
    with pytest.raises(AtlasError, match="unfinished"):
        open_atlas(folder)
    with pytest.raises(AtlasError, match="not an atlas"):
        open_atlas(tmp_path / "nothing")
    (folder / "manifest.json").write_text("{not json")
    with pytest.raises(AtlasError, match="cannot be read"):
        open_atlas(folder)
    assert issubclass(AtlasError, InputError)


def test_the_first_bad_chunk_is_named_whichever_thread_checks_it(tmp_path, monkeypatch):
    monkeypatch.setenv("MACHDYN_THREADS", "2")
    folder = tmp_path / "c"
    build_atlas(folder, 1000, chunk_size=250, progress=False)  # 4 chunks, 2 a thread
    late = folder / "chunk_00003.meta.npy"
    late.write_bytes(late.read_bytes()[:-5])  # truncated: found by the second thread
    with pytest.raises(AtlasError, match=r"chunk_00003\.meta\.npy has"):
        open_atlas(folder)
    early = folder / "chunk_00001.desc.npy"
    data = bytearray(early.read_bytes())
    data[100] ^= 0x01
    early.write_bytes(bytes(data))
    with pytest.raises(AtlasError, match=r"chunk_00001\.desc\.npy fails its CRC"):
        open_atlas(folder)


def test_dask_build_equals_serial_build(tmp_path, small_atlas):
    pytest.importorskip("distributed")
    folder = tmp_path / "d"
    build_atlas(folder, 3000, chunk_size=1200, seed=3, scheduler="local", workers=2, progress=False)
    for i in range(3):
        for suffix in ("desc", "meta"):
            a = np.load(folder / f"chunk_{i:05d}.{suffix}.npy")
            b = np.load(small_atlas / f"chunk_{i:05d}.{suffix}.npy")
            np.testing.assert_array_equal(a, b)
    assert open_atlas(folder).manifest.complete


def test_bad_scheduler_is_an_input_error(tmp_path):
    pytest.importorskip("distributed")
    with pytest.raises(InputError, match="scheduler"):
        build_atlas(tmp_path, 10, chunk_size=10, scheduler="nonsense", progress=False)


def test_dask_query_equals_local_query(small_atlas):
    distributed = pytest.importorskip("distributed")
    at = open_atlas(small_atlas)
    q = at.desc[1][17]
    local = at.nearest(q, 7)
    with distributed.Client(processes=False, n_workers=1, dashboard_address=None) as client:
        remote = at.nearest(q, 7, client=client)
    np.testing.assert_array_equal(local[0], remote[0])
    np.testing.assert_allclose(local[1], remote[1])
    assert local[0][0] == at.offsets[1] + 17


# --------------------------------------------------------------------------------------
# a placed four-bar that does not close, and a fit just past Grashof's boundary


def test_placed_pose_where_the_linkage_does_not_close_is_flagged_not_raised():
    from machdyn.synthesis import PlacedFourBar

    # a triple rocker (non-Grashof): link 2 reaches only |θ2| <= acos((r1²+r2²-(r3+r4)²)/(2 r1 r2))
    pl = PlacedFourBar(FourBar(5, 4, 2, 2.5), 1 + 2j, 0.3, 1)
    limit = np.arccos((25 + 16 - 4.5**2) / (2 * 5 * 4))
    A, B, P, ok = pl.pose(np.array([0.0, limit + 0.2, np.pi]))
    assert ok.tolist() == [True, False, False]
    assert np.isnan(P[1:]).all() and np.isnan(B[1:]).all() and np.isnan(A[1:]).all()
    assert np.isfinite(P[0]) and abs(A[0] - (1 + 2j + 4 * np.exp(0.3j))) < 1e-12


def test_a_fit_just_past_the_change_point_lands_on_it_with_its_crank():
    from machdyn.synthesis._atlas_checks import _grashof_excess, _onto_grashof
    from machdyn.synthesis.refine import Refined, coupler_and_jacobian

    # r1 + r2 = r3 + r4 + 3e-6: a hair past a change point, link 2 the shortest
    x = np.array([50.0, 1.35, 1.36, 50.0 - 0.01 - 3e-6, 12.0, 0.4, 10.0, -3.0, 0.1])
    theta = np.radians([30.0, 60.0, 90.0, 120.0])
    branch = np.ones(4)
    assert classify(*x[:4]).condition == "non-grashof"
    pts = coupler_and_jacobian(x, theta, branch)[0]
    fit = Refined(x, theta, branch, 0.0, True)
    moved = _onto_grashof(fit, pts)
    assert _grashof_excess(moved.x) <= 1e-12 * x[:4].sum()
    cls = classify(*moved.x[:4])
    assert cls.condition == "change point" and 2 in cls.cranks
    # only the longest link changed, by the excess
    assert np.count_nonzero(moved.x != x) == 1 and abs(moved.x[0] - 50.0) == pytest.approx(3e-6)
    assert 0 < moved.rms < 100 * 3e-6  # moved, but by little


def test_an_open_target_no_four_bar_meets_takes_one_round_and_reports_its_best(
    small_atlas, monkeypatch
):
    # 15 points on a full wave of a sine: no coupler curve follows it (its best misses by ~10 %),
    # so the best fit misses by more than UNTIMED_FAR after the first round: no fresh pool drawn
    from tests.test_synthesis_path_atlas import _curve_distance

    from machdyn.synthesis import atlas_path

    at = open_atlas(small_atlas)
    draws = []
    pool = atlas_path.Atlas.pool

    def counted(self, *args, **kw):
        draws.append(kw.get("draw", 0))
        return pool(self, *args, **kw)

    monkeypatch.setattr(atlas_path.Atlas, "pool", counted)
    x = np.linspace(-1.0, 1.0, 15)
    targets = 2 - 1j + x + 0.3j * np.sin(2 * np.pi * x)
    size = np.max(np.abs(targets - targets.mean()))
    res = atlas_path.path_from_atlas(targets, at, closed=False, n=1, mu_min=0.0)
    best = res.best if res.candidates else res.rejected[0]
    miss = _curve_distance(best, targets).max() / size  # measured apart from the synthesis
    assert miss > atlas_path.UNTIMED_FAR
    assert draws == [0]  # the first pool only: the query kept to its budget
    assert np.max(best.distance) / size == pytest.approx(miss, rel=1e-3)  # reported as measured


@pytest.mark.parametrize(
    ("miss", "closed", "another_round"),
    [(1e-8, False, False), (3e-6, False, True), (3e-5, False, True), (1e-2, False, False),
     (1e-2, True, True), (1e-8, True, False), (1e-1, True, False)],
)  # fmt: skip
def test_more_pool_rounds_only_between_met_and_far(miss, closed, another_round):
    # a fit whose points are a known four-bar's (by circle intersection, written in the
    # tests), and targets that are those points with one moved by `miss` of their size
    from tests.test_synthesis_path_atlas import _coupler

    from machdyn.synthesis.atlas_path import _worth_a_round
    from machdyn.synthesis.refine import Refined, coupler_and_jacobian

    x = np.array([5.0, 2.0, 5.0, 4.0, 3.0, 0.6, 1.0, 2.0, 0.3])
    th = np.linspace(0.5, 2.5, 9)
    branch = np.ones(9)
    own = coupler_and_jacobian(x, th, branch)[0]
    P = {s: _coupler(x[:4], x[4:6], complex(*x[6:8]), x[8], s, th) for s in (1.0, -1.0)}
    P = min(P.values(), key=lambda p: np.abs(p - own).max())  # the fit's assembly
    size = np.max(np.abs(P - P.mean()))
    assert np.abs(own - P).max() < 1e-9 * size  # the fit passes through P
    targets = P.copy()
    targets[4] += miss * size * np.exp(0.4j)
    rms = np.sqrt(np.mean(np.abs(P - targets) ** 2))
    assert _worth_a_round([Refined(x, th, branch, rms, True)], targets, closed) is another_round
    # the same fit through the targets out of their order along the curve cannot be an
    # answer (the checks reject it): more rounds only while this nearest fit misses by
    # between 1e-5 (traced, out of order: a zigzag that fresh pools trace out of order
    # too) and UNTIMED_FAR of its size, CLOSED_FAR for a closed target (no four-bar
    # traces it; a closed target's descriptor can mislead its first round, so more)
    from machdyn.synthesis.atlas_path import CLOSED_FAR, UNTIMED_FAR

    swap = [0, 1, 2, 3, 5, 4, 6, 7, 8]
    out_of_order = Refined(x, th[swap], branch, rms, True)
    expected = 1e-5 < miss <= (CLOSED_FAR if closed else UNTIMED_FAR)
    assert _worth_a_round([out_of_order], targets[swap], closed) is expected
