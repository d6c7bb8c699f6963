"""The ring's FE tooth on the form its pinion-type cutter generates (fem_prep.ShaperFillet, the
default form of an InternalToothGeometry with a cutter): FE2D(ring_cutter=...) and the ring's
root-stress map in the planetary rating.

References, independent of the code under test:
- ISO 6336-3 method B's sigma_F0 of the internal gear with its root section from the same
  cutter (jaxgear.rating.ShaperCutterSection: the 60-degree section of the cutter's envelope, written
  in JAX separately from fem_prep's NumPy generation), against the FE fillet peak under the load
  at ISO's outer point of single pair contact; the external teeth give FE/ISO 0.8-1.0
  (docs/rating.md);
- the involute's closed form (ISO 21771, InternalToothForm.half_thickness) for the Hertzian term;
- convergence of the FE compliance and fillet stress under mesh refinement;
- jaxgear.rating.root_stress_map of the ring pair run alone at the same cell loads (the planetary map).
"""

from __future__ import annotations

import math
import tomllib
import warnings

import jax
import numpy as np
import pytest
from _convergence import assert_monotone_richardson
from _rating_cases import stub_table

import fem_prep
import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
from jaxgear.io import CaseWarning

jax.config.update("jax_enable_x64", True)

ALPHA = math.radians(20.0)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("FEM_PREP_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache" / "tooth_fe"


def _ring(cutter=None, z=-60, rho=0.25):
    return fem_prep.InternalToothGeometry(z, 1e-3, ALPHA, fillet_radius_coeff=rho, cutter=cutter)


def test_the_cutter_selects_the_generated_form():
    """With a cutter fem_prep's internal tooth is the generated one (its form circle and fillet
    those of generate_internal_tooth), without one the stand-in circular fillet; on the involute
    both are ISO 21771's closed form."""
    cutter = fem_prep.ShaperCutter(18, 0.0, 0.25)
    gen, stand = fem_prep.tooth_profile(_ring(cutter)), fem_prep.tooth_profile(_ring())
    assert gen.source == "shaper_cutter" and stand.source == "internal_circular_fillet"
    form = fem_prep.generate_internal_tooth(_ring(cutter), n_fillet=200)
    assert gen.form_radius == pytest.approx(form.form_radius, rel=1e-12)
    assert gen.form_radius < stand.form_radius  # the small cutter's fillet reaches further
    r = np.linspace(gen.tip_radius, gen.form_radius, 7)
    # the profile's ψ is its table's linear interpolation (400 involute points): 6e-7 measured
    np.testing.assert_allclose(r * np.sin(gen.psi(r)), form.half_thickness(r), rtol=2e-6)
    np.testing.assert_allclose(gen.psi(r), stand.psi(r), rtol=2e-6)
    fil = form.fillet[1:-1]  # the envelope's points lie on the profile's table
    rr = np.hypot(fil[:, 0], fil[:, 1])
    np.testing.assert_allclose(gen.psi(rr), np.arctan2(fil[:, 0], fil[:, 1]), rtol=1e-6)


def _fe_over_iso(pair, cutter, size=None, stand_in=False):
    """The ring's FE fillet peak (per N/m) under the load at ISO 6336-3's outer point of single
    pair contact of the internal gear (ρ2 = its tip roll + (ε_α − 1) p_bt), over σ_F0/w of
    method B with the root section of the same cutter (σ_F0 = F_t/(b m_n) Y_F Y_S, F_t = F_bt cos
    α_t: σ_FE/σ_F0 = g m_n/(cos α_t Y_F Y_S)); ``stand_in``: also the stand-in fillet's FE over
    the same σ_F0 (else None)."""
    section = jg.rating.ShaperCutterSection(
        cutter.teeth, cutter.profile_shift, cutter.tip_radius_coeff
    )
    ff = jr.InternalRatingGeometry.of(pair, section).form_factors()
    rb2 = float(pair.base_radii[1])
    rho2 = math.sqrt(float(pair.tip_radii[1]) ** 2 - rb2**2)
    rho2 += (float(pair.transverse_contact_ratio) - 1) * float(pair.base_pitch)
    iso = math.cos(pair.transverse_pressure_angle) * float(ff.Y_F[1]) * float(ff.Y_S[1])
    out = []
    for cut in (cutter, None)[: 1 + stand_in]:
        geometry = jg.internal_tooth_geometry(pair, cut)
        peak = fem_prep.fillet_stress(geometry, math.hypot(rho2, rb2), size=size).peak
        out.append(peak * float(pair.normal_module) / iso)
    return out[0], (out[1] if stand_in else None)


def _pair(z2=-70, rho=0.25):
    planet = jg.Member(20, profile_shift=0.5, face_width=0.02)
    ring = jg.Member(z2, face_width=0.02, fillet_radius_coeff=rho)
    return jg.InternalGearPair(planet, ring, 3e-3, ALPHA)


@pytest.mark.parametrize(("z0", "above"), [
    # default tier: tests/test_ring_root_stress.py::test_ring_fe_on_its_generated_form_against_iso_with_the_same_cutter[40-1.04]
    pytest.param(18, 1.15, marks=pytest.mark.slow), (40, 1.04)])
def test_ring_fe_on_its_generated_form_against_iso_with_the_same_cutter(z0, above):
    """Ring z2 = −70, m 3 mm, ρ_a0 = 0.25 m_n, cut by z0 = 18 and z0 = 40: the FE fillet peak on
    the generated form over ISO's σ_F0 with the same cutter's section is 0.856 and 0.855
    (measured; −140 with z0 = 40: 0.859; the slow test: the two within 0.02 at three meshes):
    below 1 by the margin of the external teeth (FE 1-18 % below ISO, docs/rating.md). The
    stand-in fillet's FE over the same σ_F0 gives 1.054 and 0.923 (its peak 23 % and 8 % above
    the generated form's): the stand-in misses the cutter's fillet. Asserted: the generated
    form's ratio in (0.8, 0.95); the stand-in's peak above it by more than 15 % (z0 = 18) and
    4 % (z0 = 40)."""
    gen, stand = _fe_over_iso(_pair(), fem_prep.ShaperCutter(z0, 0.0, 0.25), stand_in=True)
    assert 0.8 < gen < 0.95, gen
    assert stand / gen > above, (gen, stand)


@pytest.mark.parametrize("case", [
    "nrel-5mw-planetary",  # stage 1: ring z -56, cutter z0 = 36, ρ_a0 = 0.3 m_n
    pytest.param("nrel-5mw-stage2", marks=pytest.mark.slow),  # z -93, z0 = 30, 0.3 m_n
])
def test_nrel_ring_fe_over_iso(case):
    """The NREL 5 MW rings with their reports' cutters ([rating] ring_cutter_*): FE/ISO 0.863
    (stage 1) and 0.878 (stage 2), measured at m_n/18; in (0.8, 0.95) as above. The slow tier
    adds the stand-in: within 0.5 % of the generated form on stage 1 (the cutter's fillet is
    close to the stand-in circle there), 14 % above it on stage 2."""
    c = jio.load_case(case)
    section = jio.ratings_of(c)[1].geometry.root_section
    cutter = fem_prep.ShaperCutter(
        section.teeth, float(section.profile_shift), float(section.tip_radius_coeff)
    )
    slow = case != "nrel-5mw-planetary"
    gen, stand = _fe_over_iso(c.pairs[1], cutter, stand_in=slow)
    assert 0.8 < gen < 0.95, gen
    if slow:
        assert 1.1 < stand / gen < 1.2, (gen, stand)


@pytest.mark.slow
def test_ring_fillet_stress_on_the_generated_form_converges():
    """The generated form's fillet peak at m/18, m/27, m/40 for both cutters (z0 = 18, 40):
    m/27 within 0.5 % of m/40 and the default m/18 within 2.5 %; FE/ISO stays in the band and
    the two cutters' ratios within 0.02 of each other at every mesh (ISO's σ_F0 follows the
    generated fillet as the FE does)."""
    pair = _pair()
    both = []
    for z0 in (18, 40):
        cutter = fem_prep.ShaperCutter(z0, 0.0, 0.25)
        ratios = [_fe_over_iso(pair, cutter, size=3e-3 / k)[0] for k in (18, 27, 40)]
        assert abs(ratios[1] / ratios[2] - 1) < 0.005, ratios
        assert abs(ratios[0] / ratios[2] - 1) < 0.025, ratios
        assert all(0.8 < r < 0.95 for r in ratios), ratios
        both.append(ratios)
    assert np.all(np.abs(np.subtract(*both)) < 0.02), both


# default tier: tests/test_ring_root_stress.py::test_generated_ring_compliance_agrees_on_two_meshes (the same convergence from below and the same band over the stand-in, m/3 and m/6)
@pytest.mark.slow
def test_generated_ring_compliance_converges_under_refinement():
    """|z| = 60, m 1 mm, cut by z0 = 18 (ρ_a0 0.25 m_n), ring 3.5 m_n deep clamped outside:
    sizes m/3, m/6, m/12 (the stand-in's test, tests/test_internal_tooth_fe.py): monotone from
    below at about first order, the default m/6 within 1 % of the Richardson limit; the
    generated tooth more compliant than the stand-in's (its fillet deeper into the tooth: +3 %
    measured), by less than 6 %."""
    model = fem_prep.SectorModel(n_roll=9)
    g = _ring(fem_prep.ShaperCutter(18, 0.0, 0.25))
    runs = [
        fem_prep.tooth_compliance(g, size=1e-3 / k, use_cache=False, model=model)
        for k in (3, 6, 12)
    ]
    full = np.array([t.compliance.mean() for t in runs])
    assert_monotone_richardson(full, min_rate=0.8, tol=0.01)
    stand = fem_prep.tooth_compliance(_ring(), size=1e-3 / 6, use_cache=False, model=model)
    assert 1.0 < full[1] / stand.compliance.mean() < 1.06



def test_generated_ring_compliance_agrees_on_two_meshes():
    """The fast twin of the three-mesh study (slow): the ring cut by z0 = 18 at m/3 and m/6
    (|z| = 60, m 1 mm, 3.5 m_n deep, clamped outside): the compliance grows under refinement
    by under 1 % (measured 0.75 %); at m/6 the generated tooth is more compliant than the
    stand-in's by less than 6 % (measured 2.9 %)."""
    model = fem_prep.SectorModel(n_roll=9)
    g = _ring(fem_prep.ShaperCutter(18, 0.0, 0.25))
    coarse, fine = (
        fem_prep.tooth_compliance(g, size=1e-3 / k, use_cache=False, model=model).compliance.mean()
        for k in (3, 6)
    )
    assert coarse < fine < 1.01 * coarse, (coarse, fine)
    stand = fem_prep.tooth_compliance(_ring(), size=1e-3 / 6, use_cache=False, model=model)
    assert 1.0 < fine / stand.compliance.mean() < 1.06


def test_fe2d_takes_the_ring_cutter(cache):
    """FE2D(ring_cutter=...) as Weber's: with_ring_cutter and without_body keep it; the ring's
    FE table is the generated form's (its own cache entry: the key holds the form and the
    cutter), its stiffness a little different from the stand-in's; the Hertzian term reads
    the generated form, on the involute equal to the closed form of the contact point's depth;
    a cutter that cannot cut the ring, or not a cutter, refused in one line."""
    pair = _pair(-60)
    cutter = fem_prep.ShaperCutter(18, 0.0, 0.25)
    model = jg.FE2D(size=1e-3, ring_cutter=cutter)
    assert jg.FE2D(size=1e-3).with_ring_cutter(cutter) == model
    assert model.without_body((False, True)).ring_cutter == cutter
    _, k_gen = jg.stiffness_table(pair, model, n_points=9)
    n_files = len(list(cache.glob("*.npz")))
    _, k_stand = jg.stiffness_table(pair, jg.FE2D(size=1e-3), n_points=9)
    assert len(list(cache.glob("*.npz"))) == n_files + 1  # the stand-in ring: a new entry
    # at this coarse size (m/3) the two forms' meshes differ by less than 1 % (the fine
    # comparison: test_generated_ring_compliance_converges_under_refinement)
    assert 1e-3 < np.max(np.abs(k_gen / k_stand - 1)) < 0.05
    # the Hertzian term: 1/(k cos β_b) less the two members' FE compliances (the cached tables
    # FE2D read: the same inputs, the same cache entries)
    s, k = jg.stiffness_table(pair, model, n_points=5, line_load=2e5)
    rho1, rho2 = (np.asarray(pair.roll_distance(s, i)) for i in (0, 1))
    ring = jg.internal_tooth_geometry(pair, cutter)
    planet_fe = fem_prep.tooth_compliance(
        jg.tooth_geometry(pair, 0), rim_radius=0.5 * float(pair.root_radii[0]), size=1e-3
    )
    ring_fe = fem_prep.tooth_compliance(ring, size=1e-3)
    got = 1 / k - planet_fe(rho1) - ring_fe(rho2)
    assert len(list(cache.glob("*.npz"))) == n_files + 1  # no new entry: FE2D's own
    form = fem_prep.generate_internal_tooth(ring)
    r1 = np.hypot(rho1, float(pair.base_radii[0]))
    r2 = np.hypot(rho2, float(pair.base_radii[1]))
    planet = fem_prep.tooth_profile(jg.tooth_geometry(pair, 0))
    d1, d2 = r1 * np.sin(planet.psi(r1)), form.half_thickness(r2)
    a_h = np.sqrt(8 * 2e5 * rho1 * rho2 / (rho2 - rho1) * (1 - 0.09) / (math.pi * 210e9))
    want = 4 * 0.91 / (math.pi * 210e9) * (np.log(2 * np.sqrt(d1 * d2) / a_h) - 0.3 / 1.4)
    np.testing.assert_allclose(got, want, rtol=1e-6)
    bad = jg.FE2D(ring_cutter=fem_prep.ShaperCutter(25, 0.0, 0.38))
    with pytest.raises(ValueError, match=r"^gear\.cutter\.profile_shift = 0 cannot cut the ring"):
        jg.stiffness_table(_pair(-90, rho=0.38), bad)
    with pytest.raises(ValueError, match="ring_cutter"):
        jg.FE2D(ring_cutter="z0 = 18")


def _stage2(cutter=True, extended=None):
    """nrel-5mw-stage2 at 2 slices, 8 positions; ``cutter`` False: the ring's cutter removed
    (its ``[[gears]]`` ``cutter_*``, or the older ``[rating] ring_cutter_*``: ISO's substitute
    rack, no cutter); ``extended`` its extended_contact (None: the case file's default)."""
    d = tomllib.loads(jio.embedded_case_text("nrel-5mw-stage2"))
    d["mesh"].update(slices=2, positions_per_pitch=8)
    if extended is not None:
        d["mesh"]["extended_contact"] = extended
    if not cutter:
        for table in (d["rating"], *d["gears"]):
            for key in [k for k in table if k.startswith(("ring_cutter", "cutter_"))]:
                del table[key]
    return jio.parse_train(d)


def _loads(case):
    from jaxgear.cli.planetary import sharing_models, stage_loads

    spec = case.form.spec
    stage = spec.stage(case)
    return stage_loads(case, spec, stage, sharing_models(spec, stage))


def test_planetary_ring_map_equals_the_pairs(tmp_path):
    """nrel-5mw-stage2 (in phase, no pin errors: every ring mesh carries the pair's loads, as
    tests/test_rating_planetary_loads.py shows): the planet/ring mesh's ring map maximum equals
    jaxgear.rating.root_stress_map of the InternalGearPair run alone (its rigid mesh, the mean planet
    load) at the same positions, with the same FE table (a stub, linear in the roll: exact at
    any radius), 1e-9; the table is asked for the ring cut by the rating's cutter (z0 = 30,
    ρ_a0 = 0.3 m_n) over radii on its active profile (r_a up). Without a cutter: the ring's
    entries None and its panel and rating.md say so."""
    from jaxgear.cli.planetary import stage_root_stress

    # on the theoretical path, where the stage's ring rows and the pair's rigid mesh agree cell
    # by cell: beyond it the stage shares a corner cell's broken torque ratio among its members
    # and the pair alone holds the ring (the map's maximum 3.6 % apart with the default;
    # tests/test_rating_planetary_loads.py)
    case = _stage2(extended=False)
    loads = _loads(case)
    asked = []

    def table(tooth, radii):
        asked.append((tooth, radii))
        return stub_table(tooth, radii)

    sec = {"bending": {"sigma_F0_Pa": [1.0, 1.0]}}
    stage_root_stress(case, str(tmp_path), 1, sec, loads, table=table)
    ring, radii = asked[1]
    assert isinstance(ring, fem_prep.InternalToothGeometry)
    assert ring.cutter == fem_prep.ShaperCutter(30, 0.0, 0.3)
    pair = case.pairs[1]
    assert min(radii) == pytest.approx(float(pair.tip_radii[1]), rel=1e-12)
    assert max(radii) < fem_prep.tooth_profile(ring).form_radius
    one = case.mesh_case(1)
    spec = case.form.spec
    meshes = spec.dynamic_meshes(case, case.slices)
    x = np.asarray(meshes.positions(case.positions_per_pitch))
    shift = float(meshes.ring_offset) - float(meshes.ring_phases[0]) * float(pair.base_pitch)
    alone = jg.quasi_static(one.mesh_model(), one.modifications, one.torque,
                            theta=(x + shift) / float(pair.base_radii[0]))
    t = stub_table(ring, radii)
    want = float(jg.rating.root_stress_map(pair, alone, 1, t.roll, t.peak).max)
    assert sec["root_stress"]["max_Pa"][1] == pytest.approx(want, rel=1e-9)
    assert sec["root_stress"]["fe_over_iso"][1] == pytest.approx(want, rel=1e-9)
    bare = _stage2(cutter=False)
    sec = {"bending": {"sigma_F0_Pa": [1.0, 1.0]}}
    stage_root_stress(bare, str(tmp_path), 1, sec, loads, table=stub_table)
    assert sec["root_stress"]["max_Pa"][1] is None and sec["root_stress"]["max_Pa"][0] > 0
    from jaxgear.cli.planetary import rating_section

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CaseWarning)
        rating_section(bare, str(tmp_path), 1.0, loads=loads, table=stub_table)
    assert "not computed" in (tmp_path / "rating.md").read_text()
