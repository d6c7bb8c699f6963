"""Tooth-root stress from the plane FE tooth model (fem_prep.fillet_stress): the stress recovery
against beam theory on a slender cantilever, convergence under refinement on three meshes, and
the tooth's peak fillet stress against ISO 6336-3's nominal root stress σ_F0 (method B: the beam
stress at the 30° tangent section times the stress correction factor Y_S, an empirical fit of
measured stress concentrations, independent of this FE model)."""

import math
from typing import NamedTuple

import equinox as eqx
import numpy as np
import pytest
import skfem

import fem_prep
import jaxgear as jg
import jaxgear.rating as jr
from fem_prep.tooth_form import ToothGeometry


def test_plane_strain_stress_of_a_cantilever_matches_beam_theory():
    """A plane-strain strip L = 10 h clamped at x = 0 under a transverse end force P (per unit
    thickness) at x = L: at mid-span, away from the clamp and the load (Saint-Venant), the
    bending stress is σ_xx = M y / I = 12 P (L − x) y / h³ (elasticity solution of the
    end-loaded cantilever, Timoshenko & Goodier §21), tension on top for a downward force;
    the shear stress τ_xy = 3P/(2h) (1 − 4y²/h²) at the centre line. Required: 0.5 % on the
    bending stress; 2 % on the shear peak (the parabola across 8 elements, linear in each and
    averaged at the vertex: +1.0 % measured)."""
    L, h = 0.1, 0.01
    mesh = skfem.MeshTri.init_tensor(np.linspace(0, L, 81), np.linspace(-h / 2, h / 2, 9))
    sol = fem_prep.plane_strain_stress(
        mesh, 210e9, 0.3, lambda x: x[0] < 1e-12, np.array([L, 0.0]), np.array([0.0, -1.0])
    )
    x = np.array([0.4, 0.5, 0.6]) * L
    top = sol.stress(np.stack([x, np.full(3, h / 2 * (1 - 1e-9))], -1))
    beam = 12 * (L - x) * (h / 2) / h**3  # P = 1 N/m
    np.testing.assert_allclose(top[:, 0, 0], beam, rtol=5e-3)
    bottom = sol.stress(np.stack([x, np.full(3, -h / 2 * (1 - 1e-9))], -1))
    np.testing.assert_allclose(bottom[:, 0, 0], -beam, rtol=5e-3)
    centre = sol.stress(np.stack([x, np.zeros(3)], -1))
    np.testing.assert_allclose(-centre[:, 0, 1], 1.5 / h, rtol=2e-2)


def _spur_20_40():
    m = {"addendum_coeff": 1.0, "dedendum_coeff": 1.25, "fillet_radius_coeff": 0.38}
    m["face_width"] = 0.04
    return jg.GearPair(jg.Member(20, 0.0, **m), jg.Member(40, 0.0, **m), 2e-3, math.radians(20))


def _outer_single_contact_radius(pair, i):
    rb = pair.base_radii[i]
    roll = math.sqrt(pair.tip_radii[i] ** 2 - rb**2)
    roll -= (pair.transverse_contact_ratio - 1) * pair.base_pitch
    return math.hypot(roll, rb)


def _tooth(pair, i):
    m = (pair.pinion, pair.gear)[i]
    return ToothGeometry(
        teeth=m.teeth,
        normal_module=pair.normal_module,
        normal_pressure_angle=pair.normal_pressure_angle,
        profile_shift=m.profile_shift,
        addendum_coeff=m.addendum_coeff,
        dedendum_coeff=m.dedendum_coeff,
        fillet_radius_coeff=m.fillet_radius_coeff,
    )


# default tier: tests/test_root_stress.py::test_fillet_stress_agrees_on_two_meshes (the same peak from below on m_n/9 and m_n/13.5)
@pytest.mark.slow
def test_fillet_stress_converges_under_refinement():
    """The pinion's peak fillet stress on meshes of m_n/9, m_n/13.5 and m_n/20.25 (one tooth
    on the rim ring): the change halves at least from one refinement to the next, and the last
    change is under 1 % (measured 2.0 % then 0.65 %; m_n/18, the default, is within 0.1 % of
    m_n/27 on the 20/40 pair)."""
    pair = _spur_20_40()
    tooth, r = _tooth(pair, 0), _outer_single_contact_radius(pair, 0)
    mn = pair.normal_module
    peaks = [fem_prep.fillet_stress(tooth, r, size=mn / d).peak for d in (9.0, 13.5, 20.25)]
    d1, d2 = abs(peaks[1] - peaks[0]), abs(peaks[2] - peaks[1])
    assert d2 < 0.5 * d1, peaks
    assert d2 < 0.01 * peaks[2], peaks



def test_fillet_stress_agrees_on_two_meshes():
    """The fast twin of the three-mesh study (slow): the pinion's peak fillet stress on m_n/9
    and m_n/13.5 rises under refinement by under 1.5 % (measured 0.79 %: 1328 to 1339 Pa per
    N/m)."""
    pair = _spur_20_40()
    tooth, r = _tooth(pair, 0), _outer_single_contact_radius(pair, 0)
    mn = pair.normal_module
    coarse, fine = (fem_prep.fillet_stress(tooth, r, size=mn / d).peak for d in (9.0, 13.5))
    assert coarse < fine < 1.015 * coarse, (coarse, fine)


def test_fillet_stress_of_a_standard_tooth_agrees_with_iso_method_b():
    """ISO 6336-3 method B per unit normal load at the outer point of single pair contact:
    σ_F0 = 6 cos α_Fen h_Fe / s_Fn² · Y_S (b = 1). For the ISO 53 profile A tooth (ρ_fP =
    0.38 m_n, x = 0, z 20 and 40), the FE peak (mesh m_n/13.5, 0.3 % below m_n/18) is within
    5 % of it (measured at m_n/18: −1.2 % and −3.7 %;
    on sharper fillets, ρ_fP = 0.25 m_n, FE is 9 to 18 % below ISO: docs/rating.md). The peak
    lies above the 30° tangent (41° and 45°), as photoelastic and FE studies find."""
    pair = _spur_20_40()
    form = eqx.filter_jit(jg.rating.tooth_form_factors)(jr.RatingGeometry.of(pair))  # 5 s op by op
    for i in (0, 1):
        iso = 6 * math.cos(float(form.alpha_Fen[i])) * float(form.h_Fe[i])
        iso *= float(form.Y_S[i]) / float(form.s_Fn[i]) ** 2
        r = _outer_single_contact_radius(pair, i)
        fs = fem_prep.fillet_stress(_tooth(pair, i), r, size=pair.normal_module / 13.5)
        assert fs.peak == pytest.approx(iso, rel=0.05), (i, fs.peak / iso)
        assert math.radians(30) < fs.peak_tangent_angle < math.radians(60)
        # the surface stress along the boundary and the field's principal stress agree
        k = int(np.argmax(fs.sigma_t))
        assert fs.sigma_1[k] == pytest.approx(fs.sigma_t[k], rel=0.03)


def test_fillet_stress_refuses_a_load_off_the_involute():
    pair = _spur_20_40()
    with pytest.raises(ValueError) as err:
        fem_prep.fillet_stress(_tooth(pair, 0), 0.5)
    assert "load_radius = 0.5 m is out of range, allowed [" in str(err.value)
    assert "\n" not in str(err.value)


class _Cells(NamedTuple):
    line_load: np.ndarray
    cell_s: np.ndarray
    cell_z: np.ndarray
    cell_mask: np.ndarray


def test_root_stress_map_is_each_cells_load_times_the_fe_fillet_stress_there():
    """The map of a load distribution (jaxgear.rating.root_stress_map) with the influence table of
    fem_prep.fillet_influence (9 load radii over the pinion's active profile, one factorisation)
    against a separate FE solve with the load at one cell's own radius (fem_prep.fillet_stress):
    the table interpolated between its radii is within 0.5 % there; cells off the flanks and
    unloaded cells carry no stress; the map is linear in the loads."""
    pair = _spur_20_40()
    tooth = _tooth(pair, 0)
    r_start = math.hypot(pair.start_roll, pair.base_radii[0])  # start of active profile
    radii = np.linspace(r_start, pair.tip_radii[0], 9)
    size = pair.normal_module / 13.5
    table = fem_prep.fillet_influence(tooth, radii, size=size)
    s0 = 0.3 * pair.path_of_contact  # between two of the table's radii
    s = np.array([[[s0, s0], [s0 + pair.base_pitch] * 2, [-0.5e-3] * 2]])
    cells = _Cells(
        line_load=np.array([[[2e5, 1e5], [5e4, 0.0], [3e5, 3e5]]]),
        cell_s=s,
        cell_z=np.zeros_like(s),
        cell_mask=np.array([[[True, True], [True, True], [False, False]]]),
    )
    rmap = jg.rating.root_stress_map(pair, cells, 0, table.roll, table.peak)
    rho = pair.start_roll + float(s[0, 0, 0])
    direct = fem_prep.fillet_stress(tooth, math.hypot(rho, pair.base_radii[0]), size=size)
    np.testing.assert_allclose(rmap.stress[0, 0], np.array([2e5, 1e5]) * direct.peak, rtol=5e-3)
    assert rmap.stress[0, 1, 1] == 0.0 and np.all(rmap.stress[0, 2] == 0.0)
    assert float(rmap.max) == pytest.approx(2e5 * direct.peak, rel=5e-3)
