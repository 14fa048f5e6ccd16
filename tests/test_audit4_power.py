"""Audit 4: power balance of a drawn linkage with every kind of known load.

A four-bar O2-A-B-O4 driven by a hydraulic cylinder (actuator C-E, its length the
input), a rod B-D and a block D sliding on an inclined ground guide with viscous
and Coulomb friction, a gas spring (stiffness, damping, preload) from the ground
to the coupler, a torsion spring-damper at O4, an external force on the coupler
and a torque on the rocker, gravity and masses.  With the input length driven
along ``L(t) = L0 + v t + a t²/2``:

    F_cyl L̇ + Σ P_ext − T_s L̇_s − τ φ̇ + P_friction = d/dt (KE + PE)

where KE, PE, the spring's length and rate, the torsion angle and rate and the
block's sliding speed are all computed here from *differenced positions* (five-
point central differences in time, h = 1e-4 s: truncation ~h⁴ ≈ 1e-16 of the
scale), the spring laws written here; only the driving force ``F_cyl`` and the
slider's normal force N (for μ|N| |v|) are taken from ``Linkage.forces``.
"""

from __future__ import annotations

import numpy as np
import pytest

from machdyn.linkage import Linkage

H = 1e-4
K = np.arange(-2, 3)
G = 9.81


def d_dt(z):
    d1 = (z[..., 0] - 8 * z[..., 1] + 8 * z[..., 3] - z[..., 4]) / (12 * H)
    return d1


PTS = {
    "O2": 0j,
    "O4": 6 + 0j,
    "A": 1.5 + 1.5j,
    "B": 5 + 4j,
    "P": 3 + 4j,
    "C": 3 - 3j,
    "E": 0.9 + 0.9j,
    "S": 4 - 2j,
    "D": 10 + 2j,
    "D2": 11 + 2.3j,
}
MASS = {"crank": (2.0, 0.3, (0.8, 0.1)), "coupler": (3.0, 1.2, "P"), "rocker": (2.5, 0.8, 2.0)}
MASS |= {"rod": (1.0, 0.4, 2.5), "block": (1.5, 0.05, (0.0, 0.0))}
K_S, L0_S, C_S, PRE_S = 40.0, 3.0, 6.0, -15.0  # gas spring S → P (on the coupler)
K_T, PHI0, C_T, PRE_T = 12.0, 0.3, 2.0, 1.5  # torsion spring at O4 (ground → rocker)
BETA, MU = 3.0, 0.2  # friction of the guide
F_EXT, T_EXT = 20 - 35j, -18.0


def build():
    lk = Linkage(PTS).ground("O2", "O4", "C", "S")
    links = {
        "crank": ("O2", "A", "E"),
        "coupler": ("A", "B", "P"),
        "rocker": ("O4", "B"),
        "rod": ("B", "D"),
        "block": ("D", "D2"),
    }
    for name, pts in links.items():
        m, i, cg = MASS[name]
        lk.link(name, *pts, mass=m, inertia=i, cg=cg)
    lk.slider("block", "ground", "D", "D2", name="guide")
    lk.actuator("cyl", "C", "E")
    lk.spring("gas", "S", "P", stiffness=K_S, free_length=L0_S, damping=C_S, preload=PRE_S)
    lk.torsion_spring(
        "hinge",
        "O4",
        stiffness=K_T,
        free_angle=PHI0,
        damping=C_T,
        preload=PRE_T,
        links=("ground", "rocker"),
    )
    return lk.drive("cyl")


@pytest.mark.parametrize("coulomb", [False, True])
def test_power_balance_with_actuator_springs_dampers_and_friction(coulomb):
    lk = build()
    L_drawn = abs(PTS["E"] - PTS["C"])
    L0 = L_drawn + np.linspace(-0.15, 0.15, 7)
    v, a = 0.8, -0.5
    t = H * K
    L = (L0[:, None] + v * t + a * t**2 / 2).ravel()
    pos = lk.solve(L)
    assert pos.ok.all()
    m = lk.solve(L0, velocity=v, acceleration=a)
    loads = dict(
        gravity=G,
        external_forces=[("coupler", "P", F_EXT)],
        external_torques={"rocker": T_EXT},
        viscous={"guide": BETA},
    )
    if coulomb:
        loads["coulomb"] = {"guide": MU}
    f = lk.forces(m, **loads)
    assert f.ok.all()

    def track(z):
        return np.asarray(z).reshape(-1, 5)

    # kinetic energy at each of the five stencil samples from a nine-sample stencil
    wide = H * np.arange(-4, 5)
    posw = lk.solve((L0[:, None] + v * wide + a * wide**2 / 2).ravel())
    assert posw.ok.all()
    ke = np.zeros((L0.size, 5))
    pe = np.zeros((L0.size, 5))
    for name, link in lk.links.items():
        Gz = np.asarray(posw.cg[name]).reshape(-1, 9)
        th = np.unwrap(np.asarray(posw.theta[name]).reshape(-1, 9), axis=1)
        for j in range(5):
            vG, w = d_dt(Gz[:, j : j + 5]), d_dt(th[:, j : j + 5])
            ke[:, j] += 0.5 * link.mass * np.abs(vG) ** 2 + 0.5 * link.inertia * w**2
        pe += link.mass * G * Gz[:, 2:7].imag
    dE = d_dt(ke) + d_dt(pe)
    # loads written here
    P = track(pos.points["P"])
    S = PTS["S"]
    ell = np.abs(P - S)
    ell_dot = d_dt(ell)
    T_spring = K_S * (ell[:, 2] - L0_S) + C_S * ell_dot + PRE_S
    phi = np.unwrap(track(pos.theta["rocker"]), axis=1)  # θ_rocker − θ_ground
    phi_dot = d_dt(phi)
    tau = K_T * (phi[:, 2] - PHI0) + C_T * phi_dot + PRE_T
    D = track(pos.points["D"])
    vD = d_dt(D)
    u = (PTS["D2"] - PTS["D"]) / abs(PTS["D2"] - PTS["D"])
    slide = (vD * np.conj(u)).real
    p_friction = -BETA * slide**2
    if coulomb:
        p_friction -= MU * np.abs(f.normal["guide"]) * np.abs(slide)
    vP = d_dt(P)
    p_ext = (np.conj(F_EXT) * vP).real + T_EXT * d_dt(np.unwrap(track(pos.theta["rocker"]), axis=1))
    p_in = f.driver["cyl"] * v
    balance = p_in + p_ext - T_spring * ell_dot - tau * phi_dot + p_friction - dE
    scale = np.abs(p_in).max() + np.abs(dE).max()
    assert np.abs(balance).max() < 1e-6 * scale, balance
    # the library's own spring efforts and rates agree with the laws written here
    np.testing.assert_allclose(f.elements["gas"], T_spring, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(f.elements["hinge"], tau, rtol=1e-7, atol=1e-9)


def test_an_actuator_driven_past_its_reach_is_flagged_without_a_warning():
    """The cylinder C-E and the crank O2-E close only for |E| − |C| ≤ L ≤ |E| + |C|;
    beyond, the sample is flagged — it divided NaN by NaN on the NumPy path and warned
    'invalid value encountered in divide' (an error under the suite's filterwarnings)."""
    lk = build()
    reach = abs(PTS["E"]) + abs(PTS["C"])
    m = lk.solve(np.array([abs(PTS["E"] - PTS["C"]), reach + 0.1]))
    assert list(m.ok) == [True, False] and "does not close" in m.reason[1]


def test_lid_example_driver_torque_by_moments_about_the_hinge(capsys):
    """docs/examples/lid.toml through ``machdyn linkage --at lid=45 --forces --json``:
    one link on a hinge, so ΣM_O2 = I_O α with I_O = I_G + m c² (parallel axes), the gas
    spring's tension k (L − L0) + c L̇ + preload pulling Q toward S, the torsion spring's
    −k_t (θ − θ0) on the lid and the weight at the centre of mass — all written here."""
    import json
    from pathlib import Path

    from machdyn.cli import main

    lid = Path(__file__).resolve().parents[1] / "docs" / "examples" / "lid.toml"
    assert main(["linkage", str(lid), "--at", "lid=45", "--forces", "--json"]) == 0
    table = json.loads(capsys.readouterr().out)["parts"]["lid"]["tables"]["forces"]
    row = dict(zip(table["columns"], table["rows"][0], strict=True))
    th, w, al = np.radians(45.0), 0.5, 0.2  # the file's velocity and acceleration
    m, i_g, c, g = 4.0, 0.2133, 0.4, 9.81
    e = np.exp(1j * th)
    G, Q, S = c * e, 0.2 * e, 0.15 - 0.3j
    L = abs(Q - S)
    L_dot = (1j * w * Q * np.conj((Q - S) / L)).real
    tension = 500 * (L - 0.5) + 20 * L_dot - 150
    m_gas = (np.conj(Q) * tension * (S - Q) / L).imag
    tau = 2 * (th - np.radians(10))
    m_weight = (np.conj(G) * (-1j * m * g)).imag
    T = (i_g + m * c * c) * al - m_weight - m_gas + tau
    assert row["T_lid [N*m]"] == pytest.approx(T, rel=1e-12)
    assert row["T_gas [N]"] == pytest.approx(tension, rel=1e-12)
    assert row["tau_hinge [N*m]"] == pytest.approx(tau, rel=1e-12)
    # the hinge carries the rest: F = m a_G − weight − spring force on Q
    a_G = (1j * al - w * w) * G
    F = m * a_G + 1j * m * g - tension * (S - Q) / L
    assert row["F_ground_lid_x [N]"] == pytest.approx(F.real, rel=1e-12)
    assert row["F_ground_lid_y [N]"] == pytest.approx(F.imag, rel=1e-12)
