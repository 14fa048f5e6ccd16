"""Audit (session 13) of path synthesis from an atlas: bad input through the API and the CLI.

Issue #14's rule: bad input gets a machdyn error naming the field and what would be
right; the CLI prints one line and exits non-zero; nothing silently wrong. Each test
below failed before the fix it names (an empty CSV cell read as the next column, a
third column dropped without ``--timing``, semicolon files' first row taken for a
header, real numbers taken for points on the x axis, manifests whose fields were
edited giving internal errors or being used as they were, an empty or damaged chunk
with ``--no-verify`` ending in "aborted" or an internal error), or guards what the
audit found right (scale and offset invariance, reversed and multi-turn timings,
the written spec files reproducing the printed error).

Every expected distance is measured here: the coupler point by circle intersection
(``coupler_point`` below, not machdyn's code) and the distance of a target to a
curve by a dense scan refined by golden-section search over the input angle.
"""

from __future__ import annotations

import json
import shutil
import tomllib

import numpy as np
import pytest

from machdyn.cli import main
from machdyn.errors import InputError
from machdyn.synthesis import AtlasError, build_atlas, open_atlas, path_from_atlas

#: The drawing four-bar: r1 r2 r3 r4, coupler point (p, delta), O2, theta1, sign of phi12.
LINKAGE = (3.0, 1.0, 3.5, 2.5, 1.8, 0.6)
PLACE = (0.5 + 0.2j, 0.3, 1)


def coupler_point(r1, r2, r3, r4, p, delta, theta2, O2=0j, theta1=0.0, sign=1):
    """P by circle intersection: B on circle (A, r3) and circle (O4, r4), on the side
    where phi12 = theta4 - theta3 has the sign ``sign``; P = A + p e^{j(theta3 + delta)}."""
    th = np.asarray(theta2, dtype=float)
    A = O2 + r2 * np.exp(1j * (theta1 + th))
    O4 = O2 + r1 * np.exp(1j * theta1)
    d = O4 - A
    L = np.abs(d)
    a = (r3**2 - r4**2 + L**2) / (2 * L)
    with np.errstate(invalid="ignore"):
        h = np.sqrt(r3**2 - a**2)
    B = [A + a * d / L + s * 1j * h * d / L for s in (1, -1)]
    # phi12 = theta4 - theta3, theta4 the angle of O4 -> B, theta3 of A -> B
    phi12 = [np.angle((b - O4) / (b - A)) for b in B]
    B = np.where(np.sign(phi12[0]) == sign, B[0], B[1])
    return A + p * np.exp(1j * (np.angle(B - A) + delta))


def distance_to_curve(points, *args, **kwargs):
    """Each point's distance to the coupler curve: a scan of 7,200 input angles, then
    golden-section search on the two intervals next to the nearest sample."""
    grid = np.linspace(0, 2 * np.pi, 7201)
    curve = coupler_point(*args, grid, **kwargs)
    out = []
    for q in np.atleast_1d(points):
        k = int(np.nanargmin(np.abs(curve - q)))
        lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
        g = (np.sqrt(5) - 1) / 2
        for _ in range(80):
            a, b = hi - g * (hi - lo), lo + g * (hi - lo)
            fa = abs(coupler_point(*args, a, **kwargs) - q)
            fb = abs(coupler_point(*args, b, **kwargs) - q)
            lo, hi = (lo, b) if fa <= fb else (a, hi)
        out.append(abs(coupler_point(*args, (lo + hi) / 2, **kwargs) - q))
    return np.array(out)


def size_of(points):
    return float(np.max(np.abs(points - points.mean())))


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    folder = tmp_path_factory.mktemp("audit13") / "a.atlas"
    build_atlas(folder, 10_000, progress=False)
    return open_atlas(folder)


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """A two-chunk atlas to damage copies of."""
    folder = tmp_path_factory.mktemp("audit13t") / "t.atlas"
    build_atlas(folder, 300, chunk_size=150, progress=False)
    return folder


def _copy(tiny, tmp_path):
    dst = tmp_path / "copy.atlas"
    shutil.copytree(tiny, dst)
    return dst


def _cli(args, capsys):
    status = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return status, out, err


def _one_line_error(status, err):
    assert status == 1, err
    assert err.startswith("machdyn: error:") and err.count("\n") == 1, err
    assert "internal error" not in err and "Traceback" not in err
    return err


# --------------------------------------------------------------------------------------
# the targets (API)

THETA = np.radians(np.arange(0, 360, 30))
TARGETS = coupler_point(*LINKAGE, THETA, *PLACE)


@pytest.mark.parametrize(
    "targets",
    [TARGETS.real, list(TARGETS.real), np.c_[TARGETS.real, TARGETS.imag].ravel(), [1, 2, 3, 4, 5]],
    ids=["x only", "x only list", "x y flattened", "ints"],
)
def test_real_numbers_are_not_taken_for_points_on_the_x_axis(atlas, targets):
    # (was: a 1-D real array ran as points on the x axis and returned "near" linkages)
    with pytest.raises(InputError, match=r"targets: got \d+ real numbers, not points.*\(N, 2\)"):
        path_from_atlas(targets, atlas, n=1)


@pytest.mark.parametrize(
    ("targets", "kwargs", "match"),
    [
        (TARGETS[:3], {}, r"targets: 3 points are too few for a closed path: at least 5"),
        (TARGETS[:4], {"closed": False}, r"too few for an open path: at least 5"),
        (TARGETS[:3], {"timing": THETA[:3]}, r"too few for a timed path: at least 4"),
        (np.r_[TARGETS[:5], np.nan], {}, r"targets: must be finite"),
        (np.r_[TARGETS[:5], np.inf * 1j], {}, r"targets: must be finite"),
        (TARGETS, {"timing": np.r_[THETA[:-1], np.nan]}, r"timing: must be finite"),
        (np.full(8, 1 + 1j), {}, r"targets: all target points coincide"),
        (
            np.r_[TARGETS[:6], TARGETS[5]],
            {},
            r"points 6 and 7 coincide \(targets\[5\] and targets\[6\]\)",
        ),
        (np.c_[TARGETS.real, TARGETS.imag, TARGETS.real], {}, r"targets: .*shape \(12, 3\)"),
        (TARGETS, {"timing": THETA[:5]}, r"timing: needs one angle per target \(12\), got 5"),
        (TARGETS, {"n": 0}, r"n: must be at least 1"),
        (TARGETS, {"n": 10**9}, r"n: must be at most"),
    ],
)
def test_bad_targets_are_refused_with_the_field(atlas, targets, kwargs, match):
    with pytest.raises(InputError, match=match):
        path_from_atlas(targets, atlas, **kwargs)


def test_timed_targets_at_one_crank_angle_are_refused(atlas):
    # two different points at one input angle (mod a turn): no linkage passes them
    # (was: a search, then "no atlas entry comes near ... 33 %")
    theta = np.r_[THETA[:-1], THETA[0] + 2 * np.pi]
    with pytest.raises(InputError, match=r"timing\[0\] and timing\[11\] are one input angle"):
        path_from_atlas(TARGETS, atlas, timing=theta)
    # the same targets twice round (two turns): consistent, and met as once round
    twice = np.r_[TARGETS, TARGETS]
    res = path_from_atlas(twice, atlas, timing=np.r_[THETA, THETA + 2 * np.pi], n=1)
    assert np.max(res.candidates[0].distance) <= 1e-9 * size_of(TARGETS)


def test_a_timed_closed_path_written_back_to_its_start_is_read_as_closed(atlas):
    # (was: "points 13 and 1 coincide", while the untimed path so written was accepted)
    theta = np.r_[THETA, 2 * np.pi]
    res = path_from_atlas(np.r_[TARGETS, TARGETS[0]], atlas, timing=theta, n=1)
    assert res.targets.size == 12
    best = res.candidates[0]
    lk = best.linkage
    r1, r2, r3, r4 = lk.lengths
    p, delta = lk.fourbar.coupler
    got = coupler_point(r1, r2, r3, r4, p, delta, best.theta2, lk.O2, lk.theta1, lk.branch)
    assert np.max(np.abs(got - TARGETS)) <= 1e-9 * size_of(TARGETS)


# --------------------------------------------------------------------------------------
# scale, offset, order and timing: the recovery is the same


@pytest.mark.parametrize(
    ("scale", "offset", "timed", "closed"),
    [
        (1e-6, 0.0, True, True),
        (1e6, 1e6 + 1e6j, True, True),
        (1.0, 1e6, False, True),
        (1e-6, 0.0, False, False),
    ],
)
def test_recovery_is_scale_and_offset_invariant(atlas, scale, offset, timed, closed):
    targets = TARGETS * scale + offset
    theta = THETA
    if not closed:
        targets, theta = targets[:8], theta[:8]
    res = path_from_atlas(targets, atlas, closed=closed, timing=theta if timed else None, n=1)
    assert res.near and res.note == ""
    best = res.candidates[0]
    lk = best.linkage
    r1, r2, r3, r4 = lk.lengths
    p, delta = lk.fourbar.coupler
    size = size_of(targets)
    assert size == pytest.approx(size_of((targets - offset) / scale) * scale)
    # the points the linkage reaches at its crank angles, by circle intersection
    got = coupler_point(r1, r2, r3, r4, p, delta, best.theta2, lk.O2, lk.theta1, lk.branch)
    # offset 1e6 at scale 1: the targets themselves are rounded to ~1e-10 (3e-11 of the size)
    assert np.max(np.abs(got - targets)) <= 1e-9 * size
    assert np.max(best.distance) <= 1e-9 * size


def test_reversed_and_multi_turn_timings_are_recovered(atlas):
    rng = np.random.default_rng(5)
    theta = np.sort(rng.uniform(0, 2 * np.pi, 9))  # uneven steps
    targets = coupler_point(*LINKAGE, theta, *PLACE)
    size = size_of(targets)
    for name, th in {
        "reversed": theta[::-1] - 3 * np.pi,  # clockwise, negative, beyond a turn
        "plus two turns": theta + 4 * np.pi,
    }.items():
        pts = targets[::-1] if name == "reversed" else targets
        res = path_from_atlas(pts, atlas, timing=th, n=1)
        best = res.candidates[0]
        lk = best.linkage
        r1, r2, r3, r4 = lk.lengths
        p, delta = lk.fourbar.coupler
        got = coupler_point(r1, r2, r3, r4, p, delta, best.theta2, lk.O2, lk.theta1, lk.branch)
        assert np.max(np.abs(got - pts)) <= 1e-9 * size, name
        # the crank angles found keep the given steps (mod a turn)
        step = np.angle(np.exp(1j * (np.diff(best.theta2) - np.diff(th))))
        assert np.max(np.abs(step)) <= 1e-9, name


# --------------------------------------------------------------------------------------
# the CSV file (CLI)


def _csv_lines(points, theta=None, sep=","):
    xy = [f"{float(z.real)!r}{sep}{float(z.imag)!r}" for z in points]
    if theta is None:
        return xy
    return [f"{c}{sep}{float(t)!r}" for c, t in zip(xy, theta, strict=True)]


def _with(points, *extra, theta=None):
    return "\n".join([*_csv_lines(points, theta), *extra])


IDS = ["empty cell", "4 columns", "4 columns timed", "nan", "inf", "word", "decimal comma",
       "empty file", "header only", "3 points", "timing missing"]  # fmt: skip


@pytest.mark.parametrize(
    ("text", "timing", "match"),
    [
        # an empty cell (was: the row read as (x, the third value))
        (_with(TARGETS[:5], "1.0,,2.0"), False, r"line 6: cell 2 is empty"),
        # a fourth column without --timing (was: dropped)
        (_with(TARGETS, "1,2,3,4"), False, r"line 13: expected x, y, got 4 values"),
        # four columns with --timing (was: the fourth dropped)
        ("\n".join(f"{s},0" for s in _csv_lines(TARGETS, THETA)), True, r"line 1: .*got 4 values"),
        (_with(TARGETS[:5], "nan,1"), False, r"line 6: 'nan' is not a finite"),
        (_with(TARGETS[:5], "1e400,1"), False, r"line 6: '1e400' is not a finite"),
        (_with(TARGETS[:5], "1.0,abc"), False, r"line 6: expected numbers"),
        ("1,5;2,5\n3,5;4,5\n", False, r"line 1: .*'1,5' \(decimal commas are not read"),
        ("", False, r"holds no points"),
        ("x,y\n\n", False, r"holds no points"),
        ("\n".join(_csv_lines(TARGETS[:3])), False, r"3 points are too few"),
        ("\n".join(_csv_lines(TARGETS)), True, r"line 1: expected x, y, theta2 \(deg\), got 2"),
    ],
    ids=IDS,
)
def test_bad_csv_is_one_line_naming_the_line(atlas, tmp_path, capsys, text, timing, match):
    file = tmp_path / "points.csv"
    file.write_text(text)
    args = ["synth", "path", file, "--atlas", atlas.path, "-n", "1", "--out", tmp_path / "o"]
    status, _, err = _cli([*args, *(["--timing"] if timing else [])], capsys)
    assert _one_line_error(status, err)
    import re

    assert re.search(match, err), err


@pytest.mark.parametrize(
    "form", ["semicolons", "tabs", "spaces", "bom", "blank lines and header", "crlf"]
)
def test_csv_separators_and_layouts_give_the_same_points(tmp_path, form):
    from machdyn.cli.synth import read_points_csv

    sep = {"semicolons": ";", "tabs": "\t", "spaces": "  "}.get(form, ",")
    lines = _csv_lines(TARGETS, np.degrees(THETA), sep)
    if form == "blank lines and header":
        lines = ["", "x, y, theta2 (deg)", ""] + [x for line in lines for x in (line, "")]
    file = tmp_path / "p.csv"
    newline = "\r\n" if form == "crlf" else "\n"
    data = newline.join(lines).encode()
    file.write_bytes(b"\xef\xbb\xbf" + data if form == "bom" else data)
    pts, theta = read_points_csv(file, timing=True)
    # (was: a semicolon file's first row dropped as a header; a BOM made the first x a word)
    np.testing.assert_array_equal(pts, TARGETS)
    np.testing.assert_allclose(theta, THETA, rtol=1e-15, atol=1e-15)


def test_spec_files_reload_and_reproduce_the_printed_error(atlas, tmp_path, capsys):
    # targets at scale 1e6, offset 1e6 from the origin: the candidate's file, read back
    # with tomllib and measured by circle intersection, passes the targets as printed
    targets = TARGETS * 1e6 + (1e6 - 2e6j)
    file = tmp_path / "big.csv"
    file.write_text("x,y\n" + "\n".join(_csv_lines(targets)) + "\n")
    out = tmp_path / "cands"
    args = ["synth", "path", file, "--atlas", atlas.path, "-n", "2", "--out", out, "--json"]
    status, text, err = _cli(args, capsys)
    assert status == 0, err
    res = json.loads(text)
    size = size_of(targets)
    assert res["near"] and res["defect_free"]
    for k, c in enumerate(res["candidates"], 1):
        part = tomllib.loads((out / f"candidate_{k}.toml").read_text())["fourbar"]["candidate"]
        delta = np.radians(float(part["coupler"]["delta"].removesuffix(" deg")))
        theta1 = np.radians(float(part["theta1"].removesuffix(" deg")))
        sign = part.get("branch", 1 if part.get("form") == 1 else -1)
        lengths = [part[f"r{i}"] for i in (1, 2, 3, 4)]
        O2 = complex(*part["O2"])
        d = distance_to_curve(targets, *lengths, part["coupler"]["p"], delta, O2=O2,
                              theta1=theta1, sign=sign)  # fmt: skip
        # the file's linkage passes every target at least as near as printed (the printed
        # distance is to the point at the target's crank angle, the curve's nearest may be
        # nearer), and the first, the drawing linkage, as printed (to 1e-9 of the size)
        assert np.max(d) <= c["max_distance"] + 1e-9 * size
        assert c["max_distance_over_size"] == pytest.approx(c["max_distance"] / size)
        if k == 1:
            assert np.max(d) <= 1e-9 * size and c["max_distance"] <= 1e-9 * size


# --------------------------------------------------------------------------------------
# the atlas folder


def _edit_manifest(folder, **changes):
    file = folder / "manifest.json"
    d = json.loads(file.read_text())
    for key, value in changes.items():
        if key == "rows":
            del d["chunks"]["00000"]["rows"]
        else:
            d[key] = value
    file.write_text(json.dumps(d))


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"format_version": 2}, r"atlas format 2 .* is not this machdyn's format 1"),
        ({"format_version": "1"}, r"atlas format '1'"),
        ({"count": "300"}, r"count '300', expected a whole number"),  # (was: internal error)
        ({"count": -3}, r"count -3"),  # (was: "unfinished build (1 of 0 chunks)")
        ({"count": 200}, r"gives chunk 00001 150 rows, expected 50"),
        ({"chunk_size": 0}, r"chunk_size 0"),  # (was: ZeroDivisionError)
        ({"chunks": [1, 2]}, r"has chunks list"),  # (was: TypeError)
        ({"rows": None}, r"chunk 00000's rows None"),  # (was: KeyError)
        ({"samples": 64}, r"samples 64, expected 128"),  # (was: used as it was)
        ({"circuit_samples": 64}, r"circuit_samples 64, expected 256"),  # (was: used)
        ({"harmonics": 4}, r"harmonics 4, expected 8"),
        ({"kind": "ninebar"}, r"kind 'ninebar'"),  # (was: read as a four-bar atlas)
    ],
)
def test_an_edited_manifest_is_refused_with_the_field(tiny, tmp_path, capsys, changes, match):
    folder = _copy(tiny, tmp_path)
    _edit_manifest(folder, **changes)
    with pytest.raises(AtlasError, match=match):
        open_atlas(folder, verify=False)
    for verify in ("--verify", "--no-verify"):
        status, _, err = _cli(["atlas", "info", folder, verify], capsys)
        assert "atlas:" in _one_line_error(status, err)


def _flip(file, at):
    data = bytearray(file.read_bytes())
    data[at] ^= 0x01
    file.write_bytes(bytes(data))


@pytest.mark.parametrize(
    ("damage", "verified", "unverified"),
    [
        ("truncate", r"has \d+ bytes, the manifest says", r"chunk 1 cannot be read"),
        ("flip data", r"fails its CRC-32 check", None),
        # (was, unverified: tokenize's TokenError, an internal error, exit 70)
        ("flip header", r"fails its CRC-32 check", r"chunk 0 cannot be read"),
        # (was, unverified: EOFError, which click turned into "aborted")
        ("empty", r"has 0 bytes", r"chunk 0 cannot be read \(EOFError"),
        ("missing", r"is missing", r"chunk 1 cannot be read"),
    ],
)
def test_a_damaged_chunk_is_refused(tiny, tmp_path, capsys, damage, verified, unverified):
    folder = _copy(tiny, tmp_path)
    if damage == "truncate":
        file = folder / "chunk_00001.desc.npy"
        file.write_bytes(file.read_bytes()[:-64])
    elif damage == "flip data":
        _flip(folder / "chunk_00000.desc.npy", -100)
    elif damage == "flip header":
        _flip(folder / "chunk_00000.meta.npy", 20)
    elif damage == "empty":
        (folder / "chunk_00000.meta.npy").write_bytes(b"")
    else:
        (folder / "chunk_00001.meta.npy").unlink()
    with pytest.raises(AtlasError, match=verified):
        open_atlas(folder)
    csv = tmp_path / "p.csv"
    csv.write_text("\n".join(_csv_lines(TARGETS)) + "\n")
    status, out, err = _cli(["synth", "path", csv, "--atlas", folder, "--out", tmp_path / "o"],
                            capsys)  # fmt: skip
    assert "atlas:" in _one_line_error(status, err) and out == ""
    if unverified is not None:
        with pytest.raises(AtlasError, match=unverified):
            open_atlas(folder, verify=False)
        status, _, err = _cli(["atlas", "info", folder, "--no-verify"], capsys)
        assert "rebuild the atlas" in _one_line_error(status, err)


def test_atlas_build_names_its_options(tmp_path, capsys):
    folder = tmp_path / "b"
    for args, match in [
        (["--chunk-size", "0"], "--chunk-size: must be between 1"),  # (was: "chunk_size:")
        (["--kind", "ninebar"], "--kind: must be fourbar or sixbar"),  # (was: "kind:")
        (["--seed", "-1"], "--seed: must be zero or positive"),
        (["--count", "0"], "--count: must be between 1"),
    ]:
        status, _, err = _cli(["atlas", "build", folder, "--count", "10", *args], capsys)
        assert match in _one_line_error(status, err)
    assert not folder.exists()
    file = tmp_path / "f.csv"
    file.write_text("1,2\n")
    status, _, err = _cli(["atlas", "build", file, "--count", "10"], capsys)
    assert "is a file; give a folder" in _one_line_error(status, err)  # (was: "File exists")


def test_out_that_is_a_file_is_refused_before_the_synthesis(atlas, tmp_path, capsys):
    # (was: "File exists", after the whole synthesis had run)
    file = tmp_path / "p.csv"
    file.write_text("\n".join(_csv_lines(TARGETS)) + "\n")
    taken = tmp_path / "taken"
    taken.write_text("")
    status, out, err = _cli(["synth", "path", file, "--atlas", atlas.path, "--out", taken], capsys)
    assert "--out:" in _one_line_error(status, err) and "is a file" in err and out == ""


def test_a_rockers_transmission_angle_is_not_printed_as_nan(atlas, tmp_path, capsys):
    # an open arc of a non-Grashof rocker (s + l = 4 > p + q = 3.8), any input allowed:
    # the table printed "nan" in its "mu min" column for the rocker candidates (whose mu
    # was not measured; since ee24cd5 it is, over the travel between the targets)
    theta = np.radians(np.linspace(40, 100, 9))
    points = coupler_point(2.0, 1.5, 2.5, 1.8, 1.2, 0.5, theta)
    file = tmp_path / "rocker.csv"
    file.write_text("\n".join(_csv_lines(points)) + "\n")
    args = ["synth", "path", file, "--open", "--no-crank", "--atlas", atlas.path, "-n", "3",
            "--out", tmp_path / "o"]  # fmt: skip
    status, out, err = _cli(args, capsys)
    assert status == 0, err
    table = out[: out.index("Their geometry")]
    assert "nan" not in table.lower()
    rows = [line.split() for line in table.splitlines()[2:] if line.strip()]
    assert any(r[3].startswith("RRR") for r in rows), table
    assert all(r[4] == "-" or 0 <= float(r[4]) <= 90 for r in rows), table


def test_a_third_column_without_timing_is_ignored_with_a_warning(tmp_path):
    from machdyn.cli.synth import read_points_csv

    # (was: dropped without a word; the timed file of an untimed run is still read)
    file = tmp_path / "timed.csv"
    file.write_text("x,y,theta2\n" + "\n".join(_csv_lines(TARGETS, np.degrees(THETA))) + "\n")
    with pytest.warns(UserWarning, match="third column .* ignored; add --timing"):
        pts, theta = read_points_csv(file, timing=False)
    np.testing.assert_array_equal(pts, TARGETS)
    assert theta is None
