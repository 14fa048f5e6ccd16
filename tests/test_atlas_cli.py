"""``machdyn atlas build/info`` and ``machdyn synth path``, through the real entry point."""

from __future__ import annotations

import json

import numpy as np
import pytest

from machdyn.cli import main
from machdyn.fourbar import FourBar
from machdyn.synthesis import PlacedFourBar

KNOWN = PlacedFourBar(FourBar(5, 2, 5, 4, coupler=(3.0, 0.6)), 1 + 2j, 0.3, 1)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    path = tmp_path_factory.mktemp("cli") / "a.atlas"
    assert main(["atlas", "build", str(path), "--count", "20000", "--chunk-size", "10000",
                 "--seed", "11", "--no-progress"]) == 0  # fmt: skip
    return path


def _csv(tmp_path, timing=False):
    th = np.linspace(0, 2 * np.pi, 10, endpoint=False)
    P = KNOWN.pose(th)[2]
    lines = ["x,y,theta2"] + [
        f"{float(p.real)!r},{float(p.imag)!r},{float(np.degrees(t))!r}"
        for p, t in zip(P, th, strict=True)
    ]
    file = tmp_path / "points.csv"
    file.write_text("\n".join(lines) + "\n")
    return file, P


def test_atlas_info(folder, capsys):
    assert main(["atlas", "info", str(folder), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["entries"] == 20000 and info["chunks"] == 2
    assert all(v > 0 for v in info["barker_classes"].values())


@pytest.mark.parametrize("timing", [False, True])
def test_synth_path_prints_candidates_and_writes_specs(folder, tmp_path, capsys, timing):
    import tomllib

    file, P = _csv(tmp_path, timing)
    out = tmp_path / "cands"
    args = ["synth", "path", str(file), "--atlas", str(folder), "-n", "2", "--out", str(out)]
    assert main([*args, "--json"] + (["--timing"] if timing else [])) == 0
    res = json.loads(capsys.readouterr().out)
    best = res["candidates"][0]
    size = np.max(np.abs(P - P.mean()))
    assert best["max_distance"] <= 1e-6 * size and best["defects"] == []
    spec = tomllib.loads((out / "candidate_1.toml").read_text())
    part = spec["fourbar"]["candidate"]
    assert spec["machdyn"] == 1
    np.testing.assert_allclose(
        [part["r1"], part["r2"], part["r3"], part["r4"]],
        [best["r1"], best["r2"], best["r3"], best["r4"]],
    )
    # the spec's linkage, placed as its notes say, passes through the targets
    delta = np.radians(float(part["coupler"]["delta"].split()[0]))
    fb = FourBar(
        part["r1"], part["r2"], part["r3"], part["r4"], coupler=(part["coupler"]["p"], delta)
    )
    placed = PlacedFourBar(fb, best["O2"]["x"] + 1j * best["O2"]["y"],
                           np.radians(best["theta1_deg"]), best["branch"])  # fmt: skip
    got = placed.pose(np.radians(best["theta2_deg"]))[2]
    assert np.max(np.abs(got - P)) <= 1e-6 * size
    assert main(args) == 0  # the table
    text = capsys.readouterr().out
    assert "Path synthesis from the atlas" in text and "GCRR" in text
    # the geometry table: one value per column, the best candidate's lengths on its row 1
    geometry = text[text.index("Their geometry") :].splitlines()
    assert geometry[1].split() == ["#", "r1", "r2", "r3", "r4", "p", "delta(deg)", "O2", "x",
                                   "O2", "y", "theta1(deg)"]  # fmt: skip
    row = [float(v) for v in geometry[2].split()]
    assert row[0] == 1
    np.testing.assert_allclose(row[1:5], [best[k] for k in ("r1", "r2", "r3", "r4")], rtol=1e-4)
    np.testing.assert_allclose(row[7:9], [best["O2"]["x"], best["O2"]["y"]], rtol=1e-4, atol=1e-4)


def test_synth_path_shows_closer_linkages_whose_defects_stop_them(folder, tmp_path, capsys):
    from tests.test_atlas_timed_rocker import CASES, _coupler, _reach

    # a Grashof rocker-crank driven at its rocker, 7 timed points over most of its reach
    lengths, coupler, side, O2, theta1, scale = CASES["GRRC"]
    lo, hi = _reach(lengths)
    theta = lo + (hi - lo) * np.linspace(0.05, 0.95, 7)
    P = O2 + scale * np.exp(1j * theta1) * _coupler(lengths, coupler, 0j, 0.0, side, theta)
    # its smallest transmission angle over that travel, by the law of cosines: under 30°
    r1, r2, r3, r4 = lengths
    travel = np.linspace(theta[0], theta[-1], 20001)
    phi = np.arccos((r3**2 + r4**2 - np.abs(r2 * np.exp(1j * travel) - r1) ** 2) / (2 * r3 * r4))
    mu = float(np.degrees(np.min(np.minimum(phi, np.pi - phi))))
    assert mu < 25.0
    file = tmp_path / "rocker.csv"
    file.write_text(
        "x,y,theta2\n"
        + "".join(
            f"{float(p.real)!r},{float(p.imag)!r},{float(np.degrees(t))!r}\n"
            for p, t in zip(P, theta, strict=True)
        )
    )
    out = tmp_path / "cands"
    args = ["synth", "path", str(file), "--atlas", str(folder), "--open", "--timing",
            "--no-crank", "-n", "3", "--out", str(out)]  # fmt: skip
    main(args)  # (--mu-min 30 by default: the exact linkage has a defect)
    text = capsys.readouterr().out
    shown = "Closer linkages with defects" in text or "Best linkages found (with defects)" in text
    assert shown, text
    assert f"transmission angle falls to {mu:.1f} deg" in text, text


def test_synth_path_bad_input_is_one_line(folder, tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("0,0\n1,x\n")
    assert main(["synth", "path", str(bad), "--atlas", str(folder)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("machdyn: error:") and "line 2" in err and err.count("\n") == 1
    few = tmp_path / "few.csv"
    few.write_text("0,0\n1,0\n1,1\n")
    assert main(["synth", "path", str(few), "--atlas", str(folder)]) == 1
    assert "too few" in capsys.readouterr().err
    file, _ = _csv(tmp_path)
    assert main(["synth", "path", str(file), "--atlas", str(tmp_path / "none")]) == 1
    assert "not an atlas" in capsys.readouterr().err
    assert main(["synth", "path", str(file), "--atlas", str(folder), "-n", "0"]) == 1
    assert main(["atlas", "build", str(tmp_path / "x"), "--count", "0"]) == 1
