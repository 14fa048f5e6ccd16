"""Units out: labelled columns, DXF $INSUNITS and SVG sizes, the degrees warning, short reprs,
and the install hint of a missing optional package on the command line."""

from __future__ import annotations

import math
import re
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import machdyn
from machdyn import cams
from machdyn.cli import main
from machdyn.gears import Gear, gear_outline
from machdyn.linkage import Linkage
from machdyn.units import UnitSystem, dxf_units

ezdxf = pytest.importorskip("ezdxf")


def _program():
    return cams.CamProgram.double_dwell(10.0, math.radians(60), math.radians(60))


@pytest.mark.parametrize(("unit", "code"), [("mm", 4), ("in", 1), ("m", 6), ("cm", 5), (None, 0)])
def test_dxf_files_say_their_unit(tmp_path, unit, code):
    cam = cams.TranslatingRoller(40.0, 5.0).profile(_program(), n=360)
    cam.to_dxf(tmp_path / "cam.dxf", unit=unit)
    gear_outline(Gear(20, module=2.0)).to_dxf(tmp_path / "gear.dxf", unit=unit)
    for name in ("cam.dxf", "gear.dxf"):
        doc = ezdxf.readfile(tmp_path / name)
        assert doc.header["$INSUNITS"] == code
        assert doc.header["$MEASUREMENT"] == (0 if unit == "in" else 1)


def test_a_dxf_unit_must_be_a_length():
    with pytest.raises(machdyn.InputError, match="unit: expected a length"):
        dxf_units("kg")


def test_svg_width_and_height_are_the_true_size_in_mm():
    out = gear_outline(Gear(20, diametral_pitch=8.0), points=10)
    svg = out.to_svg(unit="in")
    _, _, w, h = (float(v) for v in re.search(r'viewBox="([^"]+)"', svg)[1].split())
    width = float(re.search(r'width="([0-9.e+-]+)mm"', svg)[1])
    height = float(re.search(r'height="([0-9.e+-]+)mm"', svg)[1])
    assert width == pytest.approx(25.4 * w, rel=1e-5) and height == pytest.approx(
        25.4 * h, rel=1e-5
    )
    assert " width=" not in out.to_svg()  # no unit given: no size claimed


def test_the_gear_and_cam_commands_write_their_units(tmp_path, capsys):
    assert main(["gear", "profile", "-N", "20", "--pd", "8", "-o", str(tmp_path / "p.dxf")]) == 0
    assert ezdxf.readfile(tmp_path / "p.dxf").header["$INSUNITS"] == 1  # P_d: inches
    assert main(["gear", "profile", "-N", "20", "-m", "2", "-o", str(tmp_path / "m.svg")]) == 0
    assert 'mm" height=' in (tmp_path / "m.svg").read_text()
    args = ["cam", "--segment", "rise:cycloidal:10:180", "--segment", "fall:cycloidal:10:180",
            "--follower", "roller", "--prime-radius", "40", "--roller-radius", "5"]  # fmt: skip
    assert main([*args, "--dxf", str(tmp_path / "c.dxf"), "--unit", "mm"]) == 0
    assert ezdxf.readfile(tmp_path / "c.dxf").header["$INSUNITS"] == 4
    capsys.readouterr()
    assert main([*args, "--dxf", str(tmp_path / "d.dxf"), "--unit", "kg"]) == 1
    assert "--unit: expected a length" in capsys.readouterr().err


def test_degrees_where_radians_are_due_warn_with_a_hint():
    fb = machdyn.FourBar(8, 4, 7, 6)
    with pytest.warns(UserWarning, match=r"theta2 reaches 359 rad .* did you pass degrees"):
        fb.solve(np.arange(0, 360), 1.0)
    lk = Linkage({"O": 0, "A": 1}).ground("O").link("arm", "O", "A").drive("arm")
    with pytest.warns(UserWarning, match="arm reaches 90 rad"):
        lk.solve(np.arange(0.0, 91.0))
    with pytest.warns(UserWarning, match="theta reaches"):
        _program().svaj(np.arange(0.0, 360.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fb.solve(np.radians(np.arange(0, 360)), 1.0)  # radians: no warning
        fb.solve(np.linspace(0, 20 * np.pi, 50), 1.0)  # ten turns are fine


def test_every_angle_array_taken_warns_on_degrees():
    """Function-generator ranges, path-synthesis timing and a simulation's start angle too."""
    from machdyn.synthesis import function_generator, synthesize_path

    with (
        pytest.warns(UserWarning, match="theta2_range reaches 105 rad"),
        pytest.warns(UserWarning, match="theta4_range reaches 225 rad"),
    ):
        function_generator(np.log10, (1, 2), (45.0, 105.0), (135.0, 225.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        function_generator(np.log10, (1, 2), np.radians((45, 105)), np.radians((135, 225)))
    targets = np.array([0, 2 + 1j, 4 + 1.2j, 6 + 1j, 8])
    with pytest.warns(UserWarning, match="timing reaches 120 rad"):
        synthesize_path(targets, timing=[0, 30, 60, 90, 120], maxiter=1, popsize=5, polish=False)
    fb = machdyn.FourBar(8, 4, 7, 6)
    load = {"mass": (1, 1, 1), "inertia": (1, 1, 1), "cg": (2, 3, 3)}
    with pytest.warns(UserWarning, match="theta0 reaches 90 rad"):
        machdyn.simulate(fb, None, theta0=90.0, omega0=1.0, t_end=0.01, samples=3, **load)


def test_a_cam_with_units_writes_its_dxf_in_them(tmp_path):
    cam = machdyn.load(Path(__file__).resolve().parents[1] / "docs" / "examples" / "cam.toml")
    cam.profile(360).to_dxf(tmp_path / "cam.dxf")
    lines = (tmp_path / "cam.dxf").read_text().splitlines()
    assert lines[lines.index("$INSUNITS") + 2].strip() == "4"  # the file's mm


def test_reprs_are_short_and_say_what_was_solved():
    fb = machdyn.FourBar(6, 9, 3, 8)  # a GRCR: most of a turn cannot be assembled
    m = fb.solve(np.linspace(0.0, 2 * np.pi, 1_000_000), omega2=1.0)
    text = repr(m)
    assert len(text) < 2500 and "1,000,000 samples" in text
    ok = int(m.ok.sum())
    assert f"{ok:,} ok" in text and "cannot be assembled" in text
    assert "<table>" in m._repr_html_()
    lk = (
        Linkage({"O2": 0, "A": 2, "B": 8})
        .ground("O2")
        .link("crank", "O2", "A")
        .link("rod", "A", "B")
        .link("block", "B")
        .slider("block", "ground", "B", 0.0, name="guide")
        .drive("crank")
    )
    assert repr(lk).startswith("Linkage(3 links, 4 joints, 1 driver; mobility 1)")
    assert "slider guide" in repr(lk) and "<table>" in lk._repr_html_()


def test_reprs_name_units_of_a_model_with_units():
    fb = machdyn.FourBar(8, 4, 7, 6)
    fb.units = UnitSystem(length="mm", angular_velocity="rpm")
    text = repr(fb.solve(np.radians([0.0, 10.0]), 1.0))
    assert re.search(r"A\s+4 mm", text) and "rad/s" in text


def test_a_missing_optional_package_gets_the_install_hint(monkeypatch, capsys, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    for args in (
        ["animate", "8", "4", "7", "6", "--out", str(tmp_path / "a.png")],
        ["gear", "plot", "--np", "24", "--ng", "60", "--pd", "8", "-o", str(tmp_path / "g.png")],
    ):
        assert main(args) == 1
        err = capsys.readouterr().err
        assert err.endswith("pip install 'machdyn[plot]'\n") and "internal error" not in err


def test_to_pandas_columns_carry_the_units_of_a_loaded_model():
    pytest.importorskip("pandas")
    from pathlib import Path

    from machdyn.spec import load_machine

    examples = Path(__file__).resolve().parents[1] / "docs" / "examples"
    lk = load_machine(examples / "lid.toml")["lid"]
    m = lk.solve(np.radians([0.0, 30.0]), velocity=1.0)
    cols = set(m.to_pandas().columns)
    assert {"theta_lid [rad]", "omega_lid [rad/s]", "A_x [m]", "A_vy [m/s]"} <= cols
    forces = set(lk.forces(m, gravity=9.81).to_pandas().columns)
    assert {"F_ground_lid_x [N]", "driver_lid [N*m]", "shaking_moment [N*m]"} <= forces
    plain = Linkage({"O": 0, "A": 1}).ground("O").link("arm", "O", "A").drive("arm")
    assert "theta_arm" in plain.solve([0.0, 0.1], velocity=1.0).to_pandas().columns
    sc = load_machine(examples / "slider_crank.toml")["engine"]
    assert "d_ddot [mm/s^2]" in sc.solve(np.radians([0.0, 1.0]), 1.0).to_pandas().columns
