"""``machdyn cam`` through typer's CliRunner on the cam sub-app."""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from machdyn import InputError, MachdynError
from machdyn.cli.cam import cam_app, parse_segment

runner = CliRunner()

DOUBLE_DWELL = [
    "--segment",
    "rise:cycloidal:1.0:60",
    "--segment",
    "dwell:120",
    "--segment",
    "fall:cycloidal:1.0:60",
    "--segment",
    "dwell:120",
]
ROLLER = ["--follower", "roller", "--prime-radius", "3", "--roller-radius", "0.5"]


def test_report_for_the_brief_example():
    result = runner.invoke(cam_app, [*DOUBLE_DWELL, *ROLLER, "--eccentricity", "0", "--rpm", "100"])
    assert result.exit_code == 0, result.output
    out = result.output
    assert "continuity: s, v, a continuous everywhere" in out
    assert "pressure angle: max |φ| = 28.82°" in out  # brute-force value, see geometry tests
    assert "undercut: none" in out
    assert "PASS pressure angle" in out
    # Cycloidal at 100 rpm: V = ω·2h/β = (10π/3)(6/π) = 20 length/s.
    assert "20.0000" in out
    assert "at 100 rpm" in out


def test_json_output():
    result = runner.invoke(cam_app, [*DOUBLE_DWELL, *ROLLER, "--rpm", "60", "--json", "--size"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    assert data["continuity"]["ok"] is True
    # 2h/β and 2πh/β² with h = 1, β = π/3.
    assert data["peaks_per_rad"]["v"] == pytest.approx(6 / np.pi, rel=1e-6)
    assert data["peaks_per_rad"]["a"] == pytest.approx(2 * np.pi * 9 / np.pi**2, rel=1e-5)
    assert data["peaks_time"]["V"] == pytest.approx(2 * np.pi * 6 / np.pi, rel=1e-6)
    assert data["undercut"] is False
    assert data["sizing"]["governed_by"] == "pressure angle"
    assert [s["beta_deg"] for s in data["segments"]] == pytest.approx([60, 120, 60, 120])


def test_constant_velocity_program_is_flagged_and_strict_fails():
    segs = ["-s", "rise:cv:1:90", "-s", "dwell:90", "-s", "fall:cv:1:90", "-s", "dwell:90"]
    result = runner.invoke(cam_app, [*segs, *ROLLER, "--strict"])
    assert result.exit_code == 1
    assert "FAILS the finite-jerk rule" in result.output
    assert "v jumps" in result.output
    assert "constant velocity" in result.output


def test_undercut_reported_with_angles(tmp_path):
    segs = [
        "-s",
        "rise:cycloidal:1:30",
        "-s",
        "dwell:150",
        "-s",
        "fall:cycloidal:1:30",
        "-s",
        "dwell:150",
    ]
    dxf = tmp_path / "cam.dxf"
    args = [*segs, "--prime-radius", "1.5", "--roller-radius", "1.0", "--dxf", str(dxf)]
    result = runner.invoke(cam_app, args)
    assert "undercut: YES at θ = " in result.output
    assert "surface loops: YES, cutting away θ = " in result.output
    assert "FAIL undercut" in result.output
    assert isinstance(result.exception, MachdynError)
    assert "its outline crosses itself" in str(result.exception)
    assert not dxf.exists()


def test_a_loop_only_the_global_test_sees_is_reported_and_refused(tmp_path):
    # 40° cycloidal rise and fall, Rp 1.5, Rf 0.525, sampled every 5°: no sample fails
    # the radius-of-curvature test, but the sampled outline folds over (the loops
    # test_cams_interference.py checks against a fine sampling)
    segs = ["-s", "rise:cycloidal:1:40", "-s", "dwell:140", "-s", "fall:cycloidal:1:40"]
    segs += ["-s", "dwell:140"]
    dxf = tmp_path / "cam.dxf"
    args = [*segs, "--prime-radius", "1.5", "--roller-radius", "0.525", "--points", "72"]
    result = runner.invoke(cam_app, [*args, "--dxf", str(dxf)])
    assert "undercut: none by the radius of curvature" in result.output
    assert "surface loops: YES" in result.output
    assert "its outline crosses itself" in str(result.exception)
    assert not dxf.exists()
    report = json.loads(runner.invoke(cam_app, [*args, "--json"]).output)
    assert report["undercut"] is False and report["surface_loop"] is True
    assert len(report["surface_loop_ranges_deg"]) == 2


def test_flat_and_oscillating_followers():
    flat = runner.invoke(cam_app, [*DOUBLE_DWELL, "--follower", "flat", "--base-radius", "8"])
    assert flat.exit_code == 0, flat.output
    assert "face width ≥ 3.82" in flat.output  # 2 · 2h/β = 12/π
    sized = runner.invoke(
        cam_app,
        [*DOUBLE_DWELL, "--follower", "flat", "--base-radius", "8", "--size", "--min-rho", "1"],
    )
    # Norton eq. 8.29: Rb = ρmin - min(s + a) is a curvature-governed size.
    assert "governed by curvature" in sized.output
    unsized = runner.invoke(
        cam_app, [*DOUBLE_DWELL, "--follower", "flat", "--base-radius", "8", "--size"]
    )
    assert isinstance(unsized.exception, InputError)
    assert unsized.exception.field == "--min-rho"
    segs = [
        "-s",
        "rise:modified_sine:15:90",
        "-s",
        "dwell:90",
        "-s",
        "fall:modified_sine:15:90",
        "-s",
        "dwell:90",
    ]
    osc = runner.invoke(
        cam_app,
        [
            *segs,
            "--follower",
            "oscillating",
            "--prime-radius",
            "2",
            "--roller-radius",
            "0.3",
            "--pivot-distance",
            "4",
            "--arm-length",
            "3.5",
            "--json",
        ],
    )
    assert osc.exit_code == 0, osc.output
    data = json.loads(osc.output)
    assert data["segments"][0]["h"] == pytest.approx(15.0)
    assert data["peaks_per_rad"]["s"] == pytest.approx(np.radians(15))
    left = runner.invoke(
        cam_app,
        [
            *segs,
            "--follower",
            "oscillating",
            "--prime-radius",
            "2",
            "--roller-radius",
            "0.3",
            "--pivot-distance",
            "4",
            "--arm-length",
            "3.5",
            "--pivot-side",
            "left",
            "--size",
        ],
    )
    assert left.exit_code == 0, left.output
    assert "smallest cam: prime radius" in left.output
    wrong = runner.invoke(
        cam_app,
        [
            *segs,
            "--follower",
            "oscillating",
            "--prime-radius",
            "2",
            "--roller-radius",
            "0.3",
            "--pivot-distance",
            "4",
            "--arm-length",
            "3.5",
            "--pivot-side",
            "up",
        ],
    )
    assert wrong.exception.field == "--pivot-side"
    assert "right, left" in str(wrong.exception)


def test_program_file_and_exports(tmp_path):
    toml = tmp_path / "cam.toml"
    toml.write_text(
        """
rpm = 120  # rev/min
[follower]
type = "roller"
prime_radius = 3.0   # length
roller_radius = 0.5
[[segments]]
motion = "rise"
law = "scca"
b = 0.25
c = 0.0
d = 0.75
h = 1.0
beta_deg = 60
[[segments]]
motion = "dwell"
beta_deg = 120
[[segments]]
motion = "fall"
law = "4-5-6-7"
h = 1.0
beta_deg = 60
[[segments]]
motion = "dwell"
beta_deg = 120
""",
        encoding="utf-8",
    )
    csv = tmp_path / "cam.csv"
    dxf = tmp_path / "cam.dxf"
    svaj = tmp_path / "svaj.png"
    drawing = tmp_path / "cam.png"
    result = runner.invoke(
        cam_app,
        [
            "--program",
            str(toml),
            "--csv",
            str(csv),
            "--dxf",
            str(dxf),
            "--svaj-plot",
            str(svaj),
            "--profile-plot",
            str(drawing),
            "--points",
            "720",
        ],
    )
    assert result.exit_code == 0, result.output
    assert "scca(b=0.25, c=0, d=0.75)" in result.output
    assert "at 120 rpm" in result.output
    assert len(csv.read_text().splitlines()) == 721
    assert dxf.stat().st_size > 0
    assert svaj.stat().st_size > 0 and drawing.stat().st_size > 0


def test_laws_subcommand():
    result = runner.invoke(cam_app, ["laws"])
    assert result.exit_code == 0
    assert "modified_sine" in result.output
    assert "5.5280" in result.output  # Norton Table 8-3


@pytest.mark.parametrize(
    ("args", "field", "text"),
    [
        (["-s", "rise:cycloidal:1:60", "-s", "dwell:120", *ROLLER], "--segment", "sum to 360"),
        (
            ["-s", "rise:parabolic:1:180", "-s", "fall:cycloidal:1:180", *ROLLER],
            "--segment",
            "valid: dwell",
        ),
        (["-s", "rise:cycloidal:1:-60", *ROLLER], "--segment", "positive"),
        (["-s", "rise:cycloidal:-1:180", "-s", "dwell:180", *ROLLER], "--segment", "rise:"),
        (["-s", "rise:cycloidal:1", *ROLLER], "--segment", "rise:LAW:H:BETA_DEG"),
        (
            [*DOUBLE_DWELL, "--prime-radius", "3", "--roller-radius", "-0.5"],
            "--roller-radius",
            "zero or positive",
        ),
        (
            [
                *DOUBLE_DWELL,
                "--prime-radius",
                "0.2",
                "--roller-radius",
                "0.1",
                "--eccentricity",
                "0.5",
            ],
            "--prime-radius",
            "eccentricity",
        ),
        (
            [*DOUBLE_DWELL, "--follower", "knife", *ROLLER[2:]],
            "--follower",
            "roller, flat, oscillating",
        ),
        ([*DOUBLE_DWELL, "--prime-radius", "3"], "--roller-radius", "required"),
        ([*ROLLER], "--segment", "--program"),
        ([*DOUBLE_DWELL, *ROLLER, "--rpm", "0"], "--rpm", "positive"),
        ([*DOUBLE_DWELL, *ROLLER, "--points", "2"], "--points", "4"),
        ([*DOUBLE_DWELL, *ROLLER, "--max-pressure-angle", "100"], "--max-pressure-angle", "90"),
        ([*DOUBLE_DWELL, *ROLLER, "--max-pressure-angle", "0"], "--max-pressure-angle", "0"),
        (
            [
                *DOUBLE_DWELL,
                "--follower",
                "flat",
                "--base-radius",
                "8",
                "--size",
                "--min-rho",
                "-1",
            ],
            "--min-rho",
            "positive",
        ),
    ],
)
def test_bad_input_is_one_clear_error(args, field, text):
    result = runner.invoke(cam_app, args)
    assert result.exit_code != 0
    assert isinstance(result.exception, InputError)
    assert result.exception.field == field
    assert text in str(result.exception)
    # main() prints str(exc) as one line: no newline inside the message.
    assert "\n" not in str(result.exception)


def test_bad_program_files(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(
        "[[segments]]\nmotion = 'rise'\nlaw = 'cycloidal'\nbeta_deg = 360\n", encoding="utf-8"
    )
    result = runner.invoke(cam_app, ["--program", str(bad), *ROLLER])
    assert isinstance(result.exception, InputError)
    assert "needs h" in str(result.exception)
    broken = tmp_path / "broken.toml"
    broken.write_text("segments = [", encoding="utf-8")
    result = runner.invoke(cam_app, ["--program", str(broken), *ROLLER])
    assert "not valid TOML" in str(result.exception)
    result = runner.invoke(cam_app, ["--program", str(tmp_path / "missing.toml"), *ROLLER])
    assert "cannot read" in str(result.exception)


def test_parse_segment_scca_and_oscillating():
    seg = parse_segment("fall:scca(0.5, 0, 0.5):2:90")
    assert seg.law.name == "scca(b=0.5, c=0, d=0.5)"
    assert seg.motion == "fall"
    assert parse_segment("rise:cycloidal:30:90", oscillating=True).h == pytest.approx(np.pi / 6)
    with pytest.raises(InputError, match="three fractions"):
        parse_segment("rise:scca(0.5,0.5):1:90")


def test_open_program_is_refused_before_any_output(tmp_path):
    # Review finding 4, the reviewer's command: rise 1, fall 2. The outline would
    # have a step and dip 1 below the prime circle; no report, no DXF, an error.
    dxf = tmp_path / "x.dxf"
    segs = ["-s", "rise:cycloidal:1:60", "-s", "fall:cycloidal:2:60", "-s", "dwell:240"]
    args = [*segs, "--prime-radius", "3", "--roller-radius", "0.5", "--dxf", str(dxf)]
    result = runner.invoke(cam_app, args)
    assert result.exit_code != 0
    assert isinstance(result.exception, InputError)
    assert result.exception.field == "--segment"
    message = str(result.exception)
    assert "rises total 1, falls total 2" in message
    assert "net rise -1" in message
    assert "\n" not in message
    assert "design rules" not in result.output
    assert not dxf.exists()


def test_open_oscillating_program_is_reported_in_degrees():
    segs = ["-s", "rise:cycloidal:20:90", "-s", "fall:cycloidal:15:90", "-s", "dwell:180"]
    osc = ["--follower", "oscillating", "--prime-radius", "2", "--roller-radius", "0.3"]
    osc += ["--pivot-distance", "4", "--arm-length", "3.5"]
    result = runner.invoke(cam_app, [*segs, *osc])
    assert isinstance(result.exception, InputError)
    assert "rises total 20°, falls total 15° (net rise +5°)" in str(result.exception)


def test_undercut_dxf_refusal_names_the_flag(tmp_path):
    # Review finding 13: the CLI user cannot pass allow_undercut=True.
    segs = ["-s", "rise:cycloidal:1:30", "-s", "dwell:150", "-s", "fall:cycloidal:1:30"]
    segs += ["-s", "dwell:150"]
    dxf = tmp_path / "cam.dxf"
    args = [*segs, "--prime-radius", "1.5", "--roller-radius", "1.0", "--dxf", str(dxf)]
    result = runner.invoke(cam_app, args)
    assert isinstance(result.exception, MachdynError)
    message = str(result.exception)
    assert "--allow-undercut" in message
    assert "allow_undercut=True" not in message
    assert not dxf.exists()
    allowed = runner.invoke(cam_app, [*args, "--allow-undercut"])
    assert allowed.exit_code == 0, allowed.output
    assert dxf.exists()


@pytest.mark.parametrize("option", ["--csv", "--dxf", "--svaj-plot", "--profile-plot"])
def test_output_into_a_missing_directory_names_the_option(tmp_path, option):
    # Review finding 5: --svaj-plot / --profile-plot gave a FileNotFoundError traceback.
    target = tmp_path / "missing" / ("out.png" if "plot" in option else "out.dat")
    result = runner.invoke(cam_app, [*DOUBLE_DWELL, *ROLLER, option, str(target)])
    assert result.exit_code != 0
    assert isinstance(result.exception, InputError), result.exception
    assert result.exception.field == option
    assert "missing" in str(result.exception)
    assert "\n" not in str(result.exception)


def test_unknown_plot_format_names_the_option(tmp_path):
    result = runner.invoke(
        cam_app, [*DOUBLE_DWELL, *ROLLER, "--svaj-plot", str(tmp_path / "a.xyz")]
    )
    assert isinstance(result.exception, InputError), result.exception
    assert result.exception.field == "--svaj-plot"
    assert "png" in str(result.exception)


def _toml(tmp_path, text):
    path = tmp_path / "cam.toml"
    path.write_text(text, encoding="utf-8")
    return path


SEGMENTS_TOML = """
[[segments]]
motion = "rise"
law = "cycloidal"
h = 1.0
beta_deg = 180
[[segments]]
motion = "fall"
law = "cycloidal"
h = 1.0
beta_deg = 180
"""


def test_program_file_segments_must_be_tables(tmp_path):
    # Review finding 5: `segments = [5]` raised TypeError: 'int' object is not iterable.
    path = _toml(tmp_path, "segments = [5]\n")
    result = runner.invoke(cam_app, ["--program", str(path), *ROLLER])
    assert isinstance(result.exception, InputError), result.exception
    assert result.exception.field == "segments[0]"
    assert "[[segments]]" in str(result.exception)


def test_program_file_that_is_not_utf8_names_the_file(tmp_path):
    path = tmp_path / "cam.toml"
    path.write_bytes(b"\xff\xfe")
    result = runner.invoke(cam_app, ["--program", str(path), *ROLLER])
    assert isinstance(result.exception, InputError), result.exception
    assert result.exception.field == "--program"
    assert "cam.toml" in str(result.exception) and "UTF-8" in str(result.exception)


@pytest.mark.parametrize(
    ("follower", "unknown"),
    [
        ('typ = "flat"\nbase_radius = 3.0', "typ"),
        ("prime_radius = 3.0\nroller_radus = 0.5", "roller_radus"),
    ],
)
def test_program_file_follower_typos_are_rejected(tmp_path, follower, unknown):
    # Review finding 6: `typ = "flat"` silently analysed a roller follower.
    path = _toml(tmp_path, f"[follower]\n{follower}\n{SEGMENTS_TOML}")
    result = runner.invoke(cam_app, ["--program", str(path)])
    assert isinstance(result.exception, InputError), result.exception
    assert result.exception.field == "[follower]"
    message = str(result.exception)
    assert repr(unknown) in message
    assert "roller_radius" in message and "type" in message and "pivot_side" in message


def test_program_file_follower_values_are_named_by_key(tmp_path):
    path = _toml(tmp_path, f"[follower]\nprime_radius = 3.0\nroller_radius = -1\n{SEGMENTS_TOML}")
    result = runner.invoke(cam_app, ["--program", str(path)])
    assert isinstance(result.exception, InputError), result.exception
    assert result.exception.field == "[follower] roller_radius"


def test_program_file_open_program_names_the_file(tmp_path):
    path = _toml(
        tmp_path, SEGMENTS_TOML.replace("h = 1.0\nbeta_deg = 180\n", "h = 0.5\nbeta_deg = 180\n", 1)
    )
    result = runner.invoke(cam_app, ["--program", str(path), *ROLLER])
    assert isinstance(result.exception, InputError), result.exception
    assert result.exception.field == "--program"
    assert "net rise -0.5" in str(result.exception)


def test_program_file_bad_segment_values_name_the_entry(tmp_path):
    text = SEGMENTS_TOML.replace('motion = "fall"', 'motion = "drop"')
    result = runner.invoke(cam_app, ["--program", str(_toml(tmp_path, text)), *ROLLER])
    assert isinstance(result.exception, InputError), result.exception
    assert result.exception.field == "segments[1].motion"
    assert "rise, fall, dwell" in str(result.exception)


def test_program_file_booleans_and_rpm_are_checked(tmp_path):
    text = SEGMENTS_TOML.replace("beta_deg = 180", "beta_deg = true", 1)
    result = runner.invoke(cam_app, ["--program", str(_toml(tmp_path, text)), *ROLLER])
    assert isinstance(result.exception, InputError), result.exception
    assert result.exception.field == "segments[0].beta_deg"
    path = _toml(tmp_path, "rpm = -5\n" + SEGMENTS_TOML)
    result = runner.invoke(cam_app, ["--program", str(path), *ROLLER])
    assert isinstance(result.exception, InputError), result.exception
    assert result.exception.field.endswith("cam.toml: rpm")
