"""Sizing (closed form / bisection checked at the answer), CSV, DXF and plots."""

import numpy as np
import pytest

from machdyn import InputError, ModelError
from machdyn.cams import (
    CamProgram,
    OscillatingRoller,
    TranslatingFlatFace,
    TranslatingRoller,
    pressure_angle,
    radius_of_curvature,
    size_flat_face,
    size_oscillating_roller,
    size_roller,
)

deg = np.radians


@pytest.fixture
def dd():
    return CamProgram.double_dwell(1.0, deg(60), deg(60), law="modified_sine")


@pytest.mark.parametrize("eps", [0.0, 0.3, -0.3])
def test_size_roller_pressure_angle_governed(dd, eps):
    m = dd.sample(3600)
    sized = size_roller(m, roller_radius=0.2, eccentricity=eps)
    assert sized.governed_by == "pressure angle"
    # At the size found, max |φ| is the limit; 0.1 % smaller exceeds it.
    phi = np.abs(pressure_angle(m.s, m.v, sized.prime_radius, eps))
    assert phi.max() == pytest.approx(deg(30), abs=1e-9)
    smaller = np.abs(pressure_angle(m.s, m.v, sized.prime_radius * 0.999, eps))
    assert smaller.max() > deg(30)
    assert sized.base_radius == pytest.approx(sized.prime_radius - 0.2)


def test_size_roller_curvature_governed(dd):
    m = dd.sample(3600)
    rf = 1.5
    sized = size_roller(m, roller_radius=rf, max_pressure_angle=deg(45))
    assert sized.governed_by == "curvature"
    rho = radius_of_curvature(m.s, m.v, m.a, sized.prime_radius)
    assert rho[rho > 0].min() >= rf * (1 - 1e-9)
    rho_small = radius_of_curvature(m.s, m.v, m.a, sized.prime_radius * (1 - 1e-6))
    assert rho_small[rho_small > 0].min() < rf
    assert not TranslatingRoller(sized.prime_radius, rf).profile(m).is_undercut


def test_size_flat_face(dd):
    m = dd.sample(3600)
    sized = size_flat_face(m, min_radius_of_curvature=0.5)
    assert (m.s + m.a + sized.base_radius).min() == pytest.approx(0.5)
    cam = TranslatingFlatFace(sized.base_radius * 0.99).profile(m)
    assert cam.rho_min < 0.5


def test_size_oscillating_roller():
    program = CamProgram.double_dwell(deg(10), deg(90), deg(90))
    sized = size_oscillating_roller(program, 0.2, pivot_distance=4.0, arm_length=3.5)
    cam = OscillatingRoller(sized.prime_radius, 0.2, 4.0, 3.5).profile(program)
    assert abs(cam.pressure_angle_max) <= deg(30) + 1e-9
    assert not cam.is_undercut
    slightly = OscillatingRoller(sized.prime_radius * (1 - 1e-6), 0.2, 4.0, 3.5).profile(program)
    assert abs(slightly.pressure_angle_max) > deg(30) or slightly.is_undercut
    with pytest.raises(ModelError, match="no prime radius"):
        size_oscillating_roller(CamProgram.double_dwell(deg(60), deg(40), deg(40)), 0.2, 4.0, 3.5)


def test_sizing_bad_input(dd):
    with pytest.raises(InputError, match="below 90"):
        size_roller(dd, 0.2, max_pressure_angle=deg(95))
    with pytest.raises(InputError, match="roller_radius"):
        size_roller(dd, -0.2)
    with pytest.raises(InputError, match="min_radius_of_curvature"):
        size_flat_face(dd, 0.0)


def test_csv_round_trip(dd, tmp_path):
    cam = TranslatingRoller(3.0, 0.5, 0.2).profile(dd, n=360)
    path = tmp_path / "cam.csv"
    cam.to_csv(path)
    table = np.genfromtxt(path, delimiter=",", names=True)
    assert table.size == 360
    np.testing.assert_allclose(table["theta_deg"], np.degrees(cam.theta))
    np.testing.assert_allclose(table["surface_x"], cam.surface.real)
    np.testing.assert_allclose(table["rho_pitch"], cam.rho_pitch)
    assert table["undercut"].sum() == 0


def test_csv_flat_face_has_empty_pitch_cells(dd, tmp_path):
    cam = TranslatingFlatFace(5.0).profile(dd, n=12)
    path = tmp_path / "flat.csv"
    cam.to_csv(path)
    second = path.read_text().splitlines()[1].split(",")
    header = path.read_text().splitlines()[0].split(",")
    assert second[header.index("pitch_x")] == ""


def test_dxf_round_trip(dd, tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    cam = TranslatingRoller(3.0, 0.5).profile(dd, n=360)
    path = tmp_path / "cam.dxf"
    cam.to_dxf(path)
    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    [outline] = msp.query('LWPOLYLINE[layer=="CAM"]')
    points = np.array([(x, y) for x, y, *_ in outline.get_points()])
    assert outline.closed
    np.testing.assert_allclose(points[:, 0] + 1j * points[:, 1], cam.surface, atol=1e-9)
    radii = sorted(c.dxf.radius for c in msp.query("CIRCLE"))
    assert radii == pytest.approx([2.5, 3.0])


def test_dxf_undercut_allowed_on_request(tmp_path):
    pytest.importorskip("ezdxf")
    steep = CamProgram.double_dwell(1.0, deg(30), deg(30))
    cam = TranslatingRoller(1.5, 1.0).profile(steep, n=360)
    path = tmp_path / "undercut.dxf"
    with pytest.raises(ModelError, match=r"undercut at θ = .*its outline crosses itself"):
        cam.to_dxf(path)
    assert not path.exists()
    cam.to_dxf(path, allow_undercut=True)
    assert path.exists()


def test_plots(dd):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = dd.sample(360).plot()
    assert len(fig.axes) == 4
    assert fig.axes[3].get_xlabel() == "cam angle θ (deg)"
    steep = CamProgram.double_dwell(1.0, deg(30), deg(30))
    ax = TranslatingRoller(1.5, 1.0).profile(steep, n=360).plot()
    labels = [line.get_label() for line in ax.get_lines()]
    assert "undercut" in labels
    assert "pitch curve" in labels
    ax2 = TranslatingFlatFace(5.0).profile(dd, n=90).plot()
    assert "pitch curve" not in [line.get_label() for line in ax2.get_lines()]
    plt.close("all")


def test_dxf_refusal_advice_fits_the_follower(tmp_path):
    # Review finding 13: a flat-faced cam was told to "enlarge the prime circle
    # (see size_roller)". Its cure is a larger base circle (Norton eq. 8.29).
    steep = CamProgram.double_dwell(1.0, deg(30), deg(30))
    flat = TranslatingFlatFace(0.5).profile(steep, n=360)
    assert flat.is_undercut
    with pytest.raises(ModelError) as info:
        flat.to_dxf(tmp_path / "flat.dxf")
    message = str(info.value)
    assert "base circle" in message and "size_flat_face" in message
    assert "size_roller" not in message
    roller = TranslatingRoller(1.5, 1.0).profile(steep, n=360)
    with pytest.raises(ModelError, match=r"prime circle.*size_roller"):
        roller.to_dxf(tmp_path / "roller.dxf")
    assert not (tmp_path / "flat.dxf").exists()


def test_export_into_a_missing_directory_names_the_path(dd, tmp_path):
    cam = TranslatingRoller(3.0, 0.5).profile(dd, n=36)
    missing = tmp_path / "nope" / "cam.csv"
    with pytest.raises(InputError, match="nope") as info:
        cam.to_csv(missing)
    assert info.value.field == "path"
