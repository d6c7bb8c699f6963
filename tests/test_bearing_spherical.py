"""The double-row spherical roller bearing (:class:`jaxgear.bearings.SphericalRoller`) against
references written here.

- Self-aligning: no moment and zero tilt rows and columns of the stiffness, its load blind to a
  tilt; the DOFs it carries declared on the kind.
- Stribeck's line-contact distribution per row: zero clearance and a radial load, each row
  carries F_r / 2 = Σ_j Q_j cos α cos ψ_j, so that each row's Q_max = F_r / (2 Z J_r cos α)
  with Z the rollers of one row and 1/J_r(ε = 0.5) = 4.08 for Q ∝ δ^(10/9) (the Sjövall
  integral by quadrature here; NSK's published 4.08): Q_max · 2Z cos α / F_r = 4.08, 2Z the
  rollers of both rows.
- An axial load carried by one row: Σ Q sin α = F_a, each roller's Q = K_n (δ_z sin α)^(10/9)
  by hand, the other row unloaded.
- The stiffness: central differences of the load and the closed form
  Σ (10/9) K_n δ^(1/9) b bᵀ, b = (cos α cos ψ, cos α sin ψ, ±sin α, 0, 0), written here.
- ISO 281's P for a double-row roller bearing by hand, and its Y against the NREL 5 MW
  gearbox table's rounded e, Y (Nejad et al. 2016 via gfsReboucas/Drivetrain); the tones per
  row by hand; the refusals (the kind's and the case file's), one line each.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import jax.numpy as jnp
import numpy as np
import pytest
from test_bearings import _element_loads, _load, refused_in_one_line, sjovall

import jaxgear.bearings as jb
import jaxgear.io as jio

ROOT = Path(__file__).resolve().parents[1]
ALPHA = math.radians(12.0)


def many(**kw):
    """72 small rollers per row on a 100 mm pitch circle (the continuous limit), α = 12°."""
    args = dict(bore=0.09, outer_diameter=0.11, width=0.01, elements=72, element_diameter=0.002,
                pitch_diameter=0.1, effective_length=0.004, contact_angle=ALPHA)
    return jb.SphericalRoller(**{**args, **kw})


def test_self_aligning_no_moment_and_zero_tilt_stiffness():
    """At a displacement with tilts: the moments are 0, the tilt rows and columns of K are 0,
    the load is that of the same displacement without the tilts; the kind declares it."""
    b = jb.catalogue("240/710 ECA", clearance=50e-6)
    assert jb.SphericalRoller.self_aligning and b.axial_load == "both"
    assert b.carried() == (True, True, True, False, False)
    d = jnp.array([80e-6, -20e-6, 30e-6, 3e-4, -5e-4])
    f = np.asarray(_load(b, d))
    assert f[3] == 0.0 and f[4] == 0.0
    np.testing.assert_array_equal(f, np.asarray(_load(b, d.at[3:].set(0.0))))
    K = np.asarray(b.stiffness(d))
    assert np.all(K[3:, :] == 0.0) and np.all(K[:, 3:] == 0.0)
    assert K[0, 0] > 0 and K[1, 1] > 0 and K[2, 2] > 0


def test_radial_load_rows_share_equally_and_stribeck_line_contact():
    """Zero clearance, a radial shift: the rows carry equal loads (1e-12), each row's largest
    roller Q_max · 2Z cos α / F_r = 1/J_r(0.5) for n = 10/9 (quadrature) within 5e-4, and the
    published 4.08 within 2e-3; no axial load."""
    Jr, _ = sjovall(10 / 9)
    b = many()
    d = jnp.array([5e-6, 0, 0, 0, 0])
    Q = np.asarray(_element_loads(b, d))
    f = np.asarray(_load(b, d))
    assert Q.shape == (72, 2)
    np.testing.assert_allclose(Q[:, 0], Q[:, 1], rtol=1e-12)
    psi = 2 * np.pi * np.arange(72) / 72
    row = np.sum(Q[:, 0] * math.cos(ALPHA) * np.cos(psi))
    assert row == pytest.approx(f[0] / 2, rel=1e-12)
    factor = Q[:, 0].max() * 2 * 72 * math.cos(ALPHA) / f[0]
    assert factor == pytest.approx(1 / Jr, rel=5e-4)
    assert factor == pytest.approx(4.08, rel=2e-3)
    assert abs(f[2]) < 1e-9 * f[0]


def test_axial_load_carried_by_one_row():
    """A pure axial shift δ_z: the +α row's rollers each carry K_n (δ_z sin α)^(10/9) (hand),
    Σ Q sin α = F_z, the −α row nothing; reversed, the other row. Combined with a radial
    shift: F_z = sin α (Σ Q₊ − Σ Q₋), F_x = cos α Σ Q cos ψ over both rows."""
    b = many()
    dz = 4e-6
    K = float(b.hertz_constant)
    for sign, loaded in ((1.0, 0), (-1.0, 1)):
        Q = np.asarray(_element_loads(b, jnp.array([0, 0, sign * dz, 0, 0])))
        f = np.asarray(_load(b, jnp.array([0, 0, sign * dz, 0, 0])))
        np.testing.assert_allclose(Q[:, loaded], K * (dz * math.sin(ALPHA)) ** (10 / 9),
                                   rtol=1e-12)
        assert np.all(Q[:, 1 - loaded] == 0.0)
        assert sign * f[2] == pytest.approx(Q[:, loaded].sum() * math.sin(ALPHA), rel=1e-12)
    d = jnp.array([3e-6, 0, 1e-6, 0, 0])
    Q = np.asarray(_element_loads(b, d))
    f = np.asarray(_load(b, d))
    psi = 2 * np.pi * np.arange(72) / 72
    assert f[2] == pytest.approx(math.sin(ALPHA) * (Q[:, 0].sum() - Q[:, 1].sum()), rel=1e-12)
    assert f[0] == pytest.approx(math.cos(ALPHA) * np.sum(Q * np.cos(psi)[:, None]), rel=1e-12)


def closed_form(b, d):
    """K = Σ_j Σ_rows (10/9) K_n δ^(1/9) b bᵀ, written here with numpy."""
    K, Z, a = float(b.hertz_constant), b.elements, float(b.contact_angle)
    ca, sa, P = math.cos(a), math.sin(a), float(b.clearance)
    out = np.zeros((5, 5))
    for j in range(Z):
        psi = 2 * math.pi * j / Z
        c, s = math.cos(psi), math.sin(psi)
        for side in (1.0, -1.0):
            delta = (d[0] * c + d[1] * s - P / 2) * ca + side * d[2] * sa
            if delta > 0:
                v = np.array([ca * c, ca * s, side * sa, 0.0, 0.0])
                out += 10 / 9 * K * delta ** (1 / 9) * np.outer(v, v)
    return out


def test_stiffness_is_the_jacobian_and_the_closed_form():
    """The 240/710 ECA with 50 µm clearance at a combined displacement (some rollers out of
    contact): jacfwd against central differences (1e-5 of each row's largest entry) and the
    closed form (1e-9)."""
    b = jb.catalogue("240/710 ECA", clearance=50e-6)
    d = jnp.array([60e-6, 15e-6, 20e-6, 1e-4, 0.0])
    assert float(_element_loads(b, d).min()) == 0.0
    K = np.asarray(b.stiffness(d))
    h = 1e-9
    fd = np.zeros((5, 5))
    for j in range(5):
        e = np.zeros(5)
        e[j] = h
        fd[:, j] = (np.asarray(_load(b, d + e)) - np.asarray(_load(b, d - e))) / (2 * h)
    row = np.abs(K).max(axis=1, keepdims=True)
    assert np.all(np.abs(K - fd) <= 1e-5 * row + 1e-9)
    np.testing.assert_allclose(K, closed_form(b, np.asarray(d)), rtol=1e-9,
                               atol=1e-9 * np.abs(K).max())


def test_iso281_equivalent_load_and_life_by_hand():
    """The 231/750 CA (α = atan(0.28/1.5)): e = 0.28, Y1 = 0.45 · 1.5/0.28 = 2.41071,
    Y2 = 0.67 · 1.5/0.28 = 3.58929 (the NREL table's rounded 2.4 / 3.6, X 1 / 0.67); at
    F_r 1 MN: F_a 0.2 MN gives P = 1 + 0.482143 = 1.482143 MN, F_a 0.5 MN (and −0.5 MN) gives
    0.67 + 1.794643 = 2.464643 MN; L10 = (16518 / 1482.143)^(10/3) = 3091.89 million
    revolutions."""
    b = jb.catalogue("231/750 CA")
    Y1, Y2 = 0.45 * 1.5 / 0.28, 0.67 * 1.5 / 0.28
    assert (round(Y1, 1), round(Y2, 1)) == (2.4, 3.6)
    assert float(b.equivalent_load(1e6, 0.2e6)) == pytest.approx(1e6 + Y1 * 0.2e6, rel=1e-12)
    assert float(b.equivalent_load(1e6, 0.2e6)) == pytest.approx(1.482143e6, rel=1e-6)
    for fa in (0.5e6, -0.5e6):
        assert float(b.equivalent_load(1e6, fa)) == pytest.approx(2.464643e6, rel=1e-6)
    # the two branches meet within 1 % at F_a/F_r = e (ISO 281's rounded X, Y)
    e = 0.28
    below, above = 1 + Y1 * e, 0.67 + Y2 * e
    assert below == pytest.approx(above, rel=0.01)
    life = jb.rating_life(b, 1e6, 0.2e6, 10.0)
    assert float(life.revolutions) == pytest.approx((16518 / 1482.143) ** (10 / 3) * 1e6,
                                                    rel=1e-6)
    assert float(life.revolutions) / 1e6 == pytest.approx(3091.89, rel=1e-5)


def test_tones_per_row_by_hand():
    """Z the rollers of one row: BPFO = Z/2 (1 − γ), BPFI = Z/2 (1 + γ), γ = D cos α / d_m."""
    b = jb.catalogue("231/750 CA")
    g = 0.1175 * math.cos(math.atan(0.28 / 1.5)) / 0.985
    t = jb.bearing_tones(b)
    assert b.elements == 21
    assert float(t.bpfo) == pytest.approx(21 / 2 * (1 - g), rel=1e-12)
    assert float(t.bpfi) == pytest.approx(21 / 2 * (1 + g), rel=1e-12)


def test_catalogue_entries_transcribe_the_nrel_table():
    """The embedded 231/750 CA and 240/710 ECA: d, D, B, C and α = atan(e/1.5) as the NREL 5 MW
    table gives them (INP-B: 1220/750/365, 16518 kN, e 0.28; PLC-A: 1030/710/315, 11164 kN,
    e 0.27), the rollers by the stated estimate."""
    for name, (D, d, B, C, e) in {"231/750 CA": (1220, 750, 365, 16518, 0.28),
                                  "240/710 ECA": (1030, 710, 315, 11164, 0.27)}.items():
        b = jb.catalogue(name)
        got = [float(x) for x in (b.outer_diameter, b.bore, b.width, b.dynamic_rating)]
        np.testing.assert_allclose(got, [D * 1e-3, d * 1e-3, B * 1e-3, C * 1e3], rtol=1e-12)
        assert 1.5 * math.tan(float(b.contact_angle)) == pytest.approx(e, rel=1e-12)
        assert b.static_rating is None
        assert float(b.element_diameter) == pytest.approx((D - d) / 4 * 1e-3, rel=1e-12)
        assert float(b.effective_length) == pytest.approx(0.35 * B * 1e-3, rel=1e-12)
        assert b.elements == int(0.8 * math.pi * (D + d) / 2 / ((D - d) / 4))


GEOM = dict(bore=0.025, outer_diameter=0.052, width=0.018, elements=12, element_diameter=0.007,
            pitch_diameter=0.0385, effective_length=0.007)


@pytest.mark.parametrize("build,words", [
    (lambda: jb.SphericalRoller(**GEOM, contact_angle=math.pi / 4), "contact_angle = 0.785398"),
    (lambda: jb.SphericalRoller(**GEOM, contact_angle=0.0), "contact_angle = 0 rad"),
    (lambda: jb.SphericalRoller(**{**GEOM, "effective_length": 0.0095}),
     "effective_length = 0.0095 m is out of range"),
    (lambda: jb.SphericalRoller(**{**GEOM, "element_diameter": 0.014}),
     "element_diameter = 0.014 m is out of range"),
    (lambda: jb.SphericalRoller(**GEOM, slices=10), "slices = 10 is out of range: allowed 1"),
    (lambda: jb.SphericalRoller(**GEOM, clearance=0.007), "clearance = 0.007 m"),
    (lambda: jb.solve_displacement(jb.SphericalRoller(**GEOM), [1000.0, 0, 0, 5.0, 0]),
     "load[3] (M_x) = 5 on a DOF SphericalRoller does not carry"),
])
def test_bad_spherical_data_is_refused_in_one_line(build, words):
    refused_in_one_line(build, words)


def _spherical_case(**change):
    """examples/accessory-lumped3d-rolling.toml with its first pinion bearing a 22206-sized
    spherical roller bearing (d 30, D 62, B 20 mm; rollers estimated)."""
    data = tomllib.loads((ROOT / "examples" / "accessory-lumped3d-rolling.toml").read_text())
    bearing = {"position_mm": data["scene"]["pinion_shaft"]["bearings"][0]["position_mm"],
               "kind": "spherical_roller", "bore_mm": 30.0, "outer_diameter_mm": 62.0,
               "width_mm": 20.0, "rollers": 14, "roller_diameter_mm": 8.0,
               "roller_length_mm": 7.0, "pitch_diameter_mm": 46.0, "contact_angle_deg": 10.0,
               "clearance_um": 20.0}
    data["scene"]["pinion_shaft"]["bearings"][0] = {**bearing, **change}
    return data


def test_case_file_spherical_roller_keys():
    """``kind = "spherical_roller"`` builds the kind (rollers per row, SI); an angle of 45° or a
    roller too long for two rows, a roller larger than the ring section, too many rollers for
    a row's pitch circle refused in one line naming the key, in the file's units; the angle
    missing named with the keys the kind needs."""
    case = jio.parse_case(_spherical_case())
    b = case.scene.pinion_shaft.bearings[0].rolling
    assert isinstance(b, jb.SphericalRoller) and b.elements == 14
    assert float(b.contact_angle) == pytest.approx(math.radians(10.0), rel=1e-12)
    assert float(b.clearance) == pytest.approx(20e-6, rel=1e-12)
    where = "[scene.pinion_shaft.bearings[0]] "
    for change, start in (
        ({"contact_angle_deg": 45.0}, "contact_angle_deg = 45: out of range, allowed (0, 45)"),
        ({"roller_length_mm": 10.5}, ("roller_length_mm = 10.5: out of range, allowed <= "
                                      "width_mm / (2 cos contact_angle_deg) = 10.1543")),
        ({"balls": 14}, "balls: not a key of kind = 'spherical_roller'"),
        ({"roller_diameter_mm": 16.0}, ("roller_diameter_mm = 16: out of range, allowed < "
                                        "(outer_diameter_mm - bore_mm)/2 = 16")),
        ({"rollers": 20}, "rollers = 20: out of range, allowed <= pi pitch_diameter_mm"),
    ):
        with pytest.raises(ValueError) as err:
            jio.parse_case(_spherical_case(**change))
        text = str(err.value)
        assert text.startswith(where + start) and "\n" not in text, text
    data = _spherical_case()
    del data["scene"]["pinion_shaft"]["bearings"][0]["contact_angle_deg"]
    with pytest.raises(ValueError) as err:
        jio.parse_case(data)
    assert str(err.value).startswith(
        where + "contact_angle_deg: missing: kind = 'spherical_roller' needs"), str(err.value)


def test_solve_carries_a_combined_load_with_the_tilts_free():
    """solve_displacement: load(solve(F)) = F (1e-9) for F_r and F_a both ways, the tilts
    left at 0 (not carried), the state's stiffness the Jacobian there."""
    b = jb.catalogue("240/710 ECA", clearance=50e-6)
    for F in ([4e5, -1e5, 1.5e5, 0, 0], [3e5, 0, -2e5, 0, 0]):
        s = jb.solve_displacement(b, jnp.array(F))
        assert float(s.residual) < 1e-9
        np.testing.assert_allclose(_load(b, s.displacement), F, rtol=0, atol=1e-9 * 4e5)
        assert float(s.displacement[3]) == 0.0 and float(s.displacement[4]) == 0.0


def test_spherical_bearing_in_a_lumped_pair_at_its_operating_point():
    """The example pair with its pinion's first bearing spherical (20 µm clearance): the fixed
    point settles, the bearing carries no moment and has zero tilt stiffness there, and its
    radial load is half the normal force F_n = T / r_b1 (the pinion at mid-span; 1 %, the
    other bearing's small tilt stiffness)."""
    case = jio.parse_case(_spherical_case())
    point = jio.operating_point(case)
    f = np.asarray(point.loads[0][0])
    assert point.iterations <= 10
    assert f[3] == 0.0 and f[4] == 0.0
    K = point.shafts[0].bearings[0].stiffness_matrix()
    assert np.all(K[3:5, :] == 0.0) and np.all(K[:, 3:5] == 0.0)
    data = _spherical_case()
    m = data["pair"]["normal_module_mm"] * 1e-3
    r_b1 = 0.5 * m * data["pinion"]["teeth"] * math.cos(
        math.radians(data["pair"]["normal_pressure_angle_deg"]))
    F_n = data["operating"]["torque_Nm"] / r_b1
    assert math.hypot(f[0], f[1]) == pytest.approx(F_n / 2, rel=1e-2)
