"""The planetary rating's measured K_Halpha and root-stress maps (jaxgear.cli.planetary:
stage_loads, rating_section): the stage's quasi-static solve on the gears' contact cells, each
planet's mesh measured as a pair's (jaxgear.rating.transverse_load_factor), the most loaded planet's cell
loads mapped with the plane FE fillet stress (jaxgear.rating.root_stress_map).

References, independent of the stage code:
- the same GearPair run as a pair (jaxgear.quasi_static on the mesh's rigid mesh) at the mesh's
  load: on nrel-5mw-stage2 (z 18/36/-93, 3 equally spaced planets: every planet's meshes in
  phase, gamma = 0; no pin errors) the stage is cyclically symmetric, each sun mesh carries
  T_s/(3 r_bs) at every position, and all cells of one mesh of the planar model close by one
  approach, so the cells' line loads are the pair's at that torque (Parker & Lin's phases and the
  sun/ring offset written here from docs/planetary.md's formula);
- the closed form of a spur mesh of uniform stiffness k per unit length with a linear tip relief
  e(s) on the sun: in double contact the relieved pair carries k e less per unit length, so
  K_Halpha = 1 + k b max e / F_n over the positions of double contact (tests/
  test_rating_measured.py's pair form, here on the stage's mesh);
- ISO 6336-3's sigma_F0 against the FE maximum on the NREL stage 1 (docs/rating.md, FE root
  stress: the FE is below ISO's by 1 to 18 % on spur teeth under ISO's own load).
"""

import functools
import math
import tomllib
import warnings

import jax
import numpy as np
import pytest
from _rating_cases import stub_table

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.io import CaseWarning

jax.config.update("jax_enable_x64", True)


def _stage2(slices=2, positions=16, relief_um=None, stiffness=None, use=None, extended=None):
    """nrel-5mw-stage2 at a coarse resolution, its given K_Hbeta kept, with a linear tip relief
    of ``relief_um`` on the sun (extent 0.3 of the path), ``stiffness`` the [mesh] table's
    model keys, ``use`` the rating's use_measured, ``extended`` its extended_contact (None: the
    case file's default)."""
    d = tomllib.loads(jio.embedded_case_text("nrel-5mw-stage2"))
    d["mesh"].update(slices=slices, positions_per_pitch=positions)
    if extended is not None:
        d["mesh"]["extended_contact"] = extended
    if stiffness:
        d["mesh"].update(stiffness)
    if relief_um is not None:
        d["modifications"] = {"sun2": {"tip_relief": {"depth_um": relief_um, "extent": 0.3}}}
    if use:
        d["rating"]["use_measured"] = use
        for mesh in ("sun2-planet2", "planet2-ring2"):  # the report's given factors: not those
            for key in use:
                d["rating"][mesh].pop(key, None)
    return jio.parse_train(d)


def _loads(case):
    from jaxgear.cli.planetary import sharing_models, stage_loads

    spec = case.form.spec
    stage = spec.stage(case)
    return stage_loads(case, spec, stage, sharing_models(spec, stage))


@functools.cache
def _in_phase_loads():
    """The stage loads of stage 2 with the 60 µm sun relief on the theoretical path, computed
    once for the tests that read them (the rating keys do not enter the loads)."""
    return _loads(_stage2(relief_um=60.0, extended=False))


def _pair_result(case, k, positions):
    """Mesh k's pair run alone (its rigid mesh, exact contact, its gears' modifications, the
    mean planet load), at the stage's positions: the sun mesh's pinion angles x/r_bs, the ring
    mesh's (x + Delta_rs - gamma_r p_b)/r_bp (docs/planetary.md)."""
    one = case.mesh_case(k)
    spec = case.form.spec
    meshes = spec.dynamic_meshes(case, case.slices)
    x = np.asarray(meshes.positions(positions))
    pair = case.pairs[k]
    if k == 0:
        theta = x / float(pair.base_radii[0])
    else:
        p_b = float(pair.base_pitch)
        shift = float(meshes.ring_offset) - float(meshes.ring_phases[0]) * p_b
        theta = (x + shift) / float(pair.base_radii[0])
    return jg.quasi_static(one.mesh_model(), one.modifications, one.torque, theta=theta)


def test_in_phase_stage_meshes_equal_the_pairs_run_alone(tmp_path):
    """Every planet's sun mesh and ring mesh of the in-phase stage 2 (a 60 µm tip relief on the
    sun, iso6336 stiffness): cell line loads equal to the pair's run alone at the mean planet
    load (1e-9 of the largest), so the measured K_Halpha of both meshes equals the pair's
    jaxgear.rating.transverse_load_factor (1e-9) and exceeds 1 on the relieved sun mesh; the
    sun/planet root-stress map's maximum equals the pair's map at the same loads (stub FE table,
    1e-9), both members."""
    from jaxgear.cli.planetary import measured_k_h_alpha, stage_root_stress

    # on the theoretical path: the stage's rows and the pair alone agree there cell by cell;
    # beyond it a corner cell's broken torque ratio is shared by the stage's members (the tip
    # owner's rotation times λ, translations turned) but carried by the pinion alone with the
    # gear held in the pair's rigid mesh (13 % apart at one position with the default)
    case = _stage2(relief_um=60.0, extended=False)
    loads = _in_phase_loads()
    want = []
    for k in (0, 1):
        pair_res = _pair_result(case, k, case.positions_per_pitch)
        w = np.asarray(pair_res.line_load)
        for planet in loads.meshes[k]:
            np.testing.assert_allclose(planet.line_load, w, rtol=0, atol=1e-9 * w.max())
            np.testing.assert_array_equal(planet.cell_mask, np.asarray(pair_res.cell_mask))
        g = float(case.pairs[k].path_of_contact)  # the pairs on the theoretical path
        want.append(float(jg.rating.transverse_load_factor(pair_res, path_of_contact=g)))
    got = [m["value"] for m in measured_k_h_alpha(loads)]
    np.testing.assert_allclose(got, want, rtol=1e-9)
    assert got[0] > 1.05  # the relief shifts load between the sun mesh's pairs
    sec = {"bending": {"sigma_F0_Pa": [1.0, 1.0]}}  # the FE/ISO ratio: tests below
    stage_root_stress(case, str(tmp_path), 0, sec, loads, table=stub_table)
    sun = _pair_result(case, 0, case.positions_per_pitch)
    pair = case.pairs[0]
    by_pair = []
    for i in (0, 1):  # the stub is linear in the roll: exact at any radius of the active profile
        ends = [float(pair.roll_distance(x, i)) for x in (0.0, float(pair.path_of_contact))]
        radii = np.hypot(np.linspace(min(ends), max(ends), 5), float(pair.base_radii[i]))
        t = stub_table(jg.tooth_geometry(pair, i), radii)
        by_pair.append(float(jg.rating.root_stress_map(pair, sun, i, t.roll, t.peak).max))
    np.testing.assert_allclose(sec["root_stress"]["max_Pa"], by_pair, rtol=1e-9)
    assert sec["root_stress"]["planet"] == 1  # equal shares: the first planet


def test_planet_mesh_loads_place_each_planets_cells():
    """:func:`jaxgear.planetary.planet_mesh_loads` on the stage's quasi-static solve (the spur
    nrel-5mw-stage2, 3 planets, the sun's 60 µm relief, on the path): each planet's sun-mesh and ring-mesh cells, placed on its own
    mesh, carry the solve's own mesh force of that planet at every position (Σ line load ×
    length = the transverse mesh force, spur: 1e-9 of it; the forces are the solver's, not the
    cells'); the cells' forces given back with ``per_length`` give the line loads."""
    import jaxgear.planetary as jp

    case = _stage2(relief_um=60.0, extended=False)  # the in-phase loads' stage: their programs
    spec = case.form.spec
    meshes = spec.dynamic_meshes(case, case.slices)
    x = meshes.positions(case.positions_per_pitch)
    q = jp.planetary_quasi_static(jp.PlanarPlanetary(), spec.sharing_stage(spec.stage(case)),
                                  meshes, np.asarray(abs(spec.torques(case.torque)["sun"])), x)
    kinds = jp.planet_mesh_loads(meshes, x, q.cell_line_load)
    assert [len(k) for k in kinds] == [3, 3]
    for kind, forces in zip(kinds, (q.sun_mesh_forces, q.ring_mesh_forces), strict=True):
        for i, m in enumerate(kind):
            cell = np.where(m.cell_mask, m.line_load * m.cell_length, 0.0).sum(axis=(1, 2))
            np.testing.assert_allclose(cell, np.asarray(forces)[:, i],
                                       rtol=1e-9, atol=1e-9 * float(np.max(forces)))
    rows = [np.stack([np.where(m.cell_mask, m.line_load * m.cell_length, 0.0) for m in kind],
                     axis=1).reshape(len(x), -1) for kind in kinds]  # the cell rows' order
    back = jp.planet_mesh_loads(meshes, x, np.concatenate(rows, axis=1), per_length=True)
    for k0, k1 in zip(kinds, back, strict=True):
        for a, b in zip(k0, k1, strict=True):
            np.testing.assert_allclose(np.where(a.cell_mask, a.line_load, 0.0), b.line_load,
                                       rtol=1e-12, atol=1e-6)


def test_k_h_alpha_of_a_uniform_stage_mesh_against_the_closed_form():
    """Uniform stiffness k0 on the in-phase stage 2, tip relief depth e0 on the sun: the sun
    mesh's measured K_Halpha is 1 + k0 b max e / F_n (F_n = T_s/(3 r_bs), the planet's share,
    e(s) the relief at the relieved pair's cells in double contact), 1e-9; no relief: 1; a
    deeper relief gives more."""
    from jaxgear.cli.planetary import measured_k_h_alpha

    k0 = 1.5e10  # N/m per m of contact line
    # theoretical path: the closed form takes the path's cells (two lines in double contact)
    stiff = {"stiffness": "uniform", "stiffness_per_length_N_per_mm_per_um": k0 * 1e-9,
             "extended_contact": False}
    values = {}
    for depth in (0.0, 10.0, 20.0):
        case = _stage2(relief_um=depth, stiffness=stiff)
        loads = _loads(case)
        values[depth] = measured_k_h_alpha(loads)[0]["value"]
    assert values[0.0] == pytest.approx(1.0, abs=1e-12)
    assert 1.0 < values[10.0] < values[20.0]
    pair = case.pairs[0]
    spec = case.form.spec
    f_n = abs(spec.torques(case.torque)["sun"]) / (3 * float(pair.base_radii[0]))
    b = float(pair.face_width)
    g = float(pair.path_of_contact)
    planet = loads.meshes[0][0]
    s, m = planet.cell_s[:, :, 0], planet.cell_mask[:, :, 0]
    e = 20e-6 * np.clip((s - 0.7 * g) / (0.3 * g), 0.0, None)  # the sun's tip: the end of the path
    double = m.sum(axis=1) == 2
    assert k0 * 20e-6 < f_n / b  # the relieved pair stays loaded
    want = 1 + k0 * b * np.max(np.where(m & double[:, None], e, 0.0)) / f_n
    assert values[20.0] == pytest.approx(want, rel=1e-9)


def test_use_measured_k_h_alpha_rates_each_mesh_with_the_stages(tmp_path):
    """`use_measured = ["K_Halpha"]`: each mesh rated with its measured K_Halpha (within ISO's
    limits, jg.rating.transverse_factor_limits) in place of ISO's, K_Falpha with it; no warning (the
    stage measures it). K_v named too (in the same rating): the one-line warning names K_v
    only."""
    from jaxgear.cli.planetary import rating_section

    # one rating with K_v named too (not measured here): its one use_measured warning names K_v
    # alone (K_Halpha is measured: no warning of it)
    # the in-phase stage's loads on the theoretical path (the test above's): the contact
    # geometry does not enter what is rated with them
    case = _stage2(relief_um=60.0, use=["K_Halpha", "K_v"], extended=False)
    loads = _in_phase_loads()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sec = rating_section(case, str(tmp_path), 1.0, loads=loads, table=stub_table)
    said = [str(w.message) for w in caught if issubclass(w.category, CaseWarning)
            and "use_measured" in str(w.message)]
    assert len(said) == 1, said
    assert said[0].startswith("[rating] use_measured: K_v not measured on this planetary"), said
    measured = sec["measured"]["K_Halpha"]["value"]
    caps = [float(jg.rating.transverse_factor_limits(rc.geometry)[0]) for rc in jio.ratings_of(case)]
    for key in ("K_Halpha", "K_Falpha"):
        f = sec["factors"][key]
        assert all(s.startswith("measured (rating.measured") for s in f["source"])
    np.testing.assert_allclose(sec["factors"]["K_Halpha"]["value"],
                               np.minimum(measured, caps), rtol=1e-12)
    md = (tmp_path / "rating.md").read_text()
    assert md.count("| K_Hα measured |") == 2
    assert md.count("| σ_F,FE max | ") == 2 and "not computed" not in md  # the ring: its cutter


# default tier: tests/test_rating_examples.py::
# test_root_stress_map_example_with_five_load_radii_is_below_iso (a pair's FE map below ISO's
# sigma_F0), tests/test_ring_root_stress.py::test_nrel_ring_fe_over_iso (stage 1's ring on its
# cutter's form, in the band) and test_in_phase_stage_meshes_equal_the_pairs_run_alone above
# (the stage's map is the pair's at the same loads)
@pytest.mark.slow
@pytest.mark.parametrize("resolution", [
    (2, 16),
    pytest.param(None, marks=pytest.mark.slow),  # the run's: 40 slices, 32 positions, ~13 s
])
def test_nrel_stage1_fe_root_stress_against_iso(tmp_path, resolution):
    """nrel-5mw-planetary (2 slices and 16 positions, and (slow) the run's resolution: 40
    slices, 32 positions; the real FE tables):
    the sun's and the planet's largest FE root stress in the sun/planet mesh, the planet's in the
    planet/ring mesh, FE/ISO sigma_F0 in (0.8, 1): the band docs/rating.md gives and
    tests/test_rating_examples.py asserts for a pair's map (the FE below ISO's by 1 to 18 % on
    spur teeth; here 3 planets and a floating sun share equally, K_gamma 1, and the unmodified
    spur meshes share evenly between pairs, K_Halpha 1, so the map is at ISO's load); the
    ring's on the form its cutter generates (z0 = 36) over σ_F0 with the same cutter, in the
    same band (0.845 measured at the coarse resolution; tests/test_ring_root_stress.py);
    root_stress_map_<mesh>.png written."""
    from jaxgear.cli.planetary import measured_k_h_alpha, rating_section

    # theoretical path: the even split between the pairs (K_Halpha 1) that puts the map at
    # ISO's load is the path's (beyond it the corners' contact loads the fillets' other points:
    # test_nrel_stage1_k_h_alpha_beyond_the_path_against_a_reference below)
    case = jio.load_case("nrel-5mw-planetary").replace(contact_geometry=jg.TheoreticalPath())
    if resolution is not None:
        case = case.replace(slices=resolution[0], positions_per_pitch=resolution[1])
    loads = _loads(case)
    assert [m["value"] for m in measured_k_h_alpha(loads)] == pytest.approx([1.0, 1.0], abs=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CaseWarning)
        sec = rating_section(case, str(tmp_path), 1.0, loads=loads)
    rs = sec["root_stress"]
    ratios = [rs["fe_over_iso"][0][0], rs["fe_over_iso"][0][1], rs["fe_over_iso"][1][0],
              rs["fe_over_iso"][1][1]]
    assert all(0.8 < r < 1.0 for r in ratios), ratios
    for k, name in enumerate(sec["meshes"]):
        assert rs["file"][k] == f"root_stress_map_{name}.png"
        assert (tmp_path / rs["file"][k]).stat().st_size > 10_000
    iso = np.asarray(rs["iso_sigma_F0_Pa"])
    np.testing.assert_allclose(iso, np.asarray(sec["bending"]["sigma_F0_Pa"]), rtol=0)
    assert math.isclose(rs["max_Pa"][0][0] / iso[0][0], ratios[0], rel_tol=1e-12)


def _k_h_alpha_reference(w, s, mask, g, loaded=1e-2):
    """K_Halpha written again from its definition (docs/rating.md): at each position the pairs
    are the contact lines' cells on the theoretical path [0, g] loaded above ``loaded`` of the
    largest line load; the largest pair's mean line load over (all the load, on the path and
    beyond, over all the pairs' loaded cells); the largest over the positions, at least 1."""
    w = np.where(mask, np.maximum(w, 0.0), 0.0)
    cut = loaded * w.max()
    best = 1.0
    for p in range(w.shape[0]):
        count, means = 0, []
        for line in range(w.shape[1]):
            cells = [j for j in range(w.shape[2])
                     if w[p, line, j] > cut and 0.0 <= s[p, line, j] <= g]
            count += len(cells)
            if cells:
                means.append(sum(w[p, line, j] for j in range(w.shape[2])
                                 if 0.0 <= s[p, line, j] <= g) / len(cells))
        if means:
            best = max(best, max(means) / (w[p].sum() / count))
    return best


# default tier: tests/test_rating_measured.py::test_transverse_load_factor_beyond_the_path_by_hand
# (corner cells beyond the path relieve a pair, by hand) and
# tests/test_rating_planetary_loads.py::test_in_phase_stage_meshes_equal_the_pairs_run_alone
# (the stage's measured K_Halpha per mesh against the pair's)
@pytest.mark.slow
def test_nrel_stage1_k_h_alpha_beyond_the_path_against_a_reference():
    """nrel-5mw-planetary as the case file has it (contact beyond the path), 2 slices and 16
    positions: the unmodified spur meshes share evenly between their pairs on the path, and the
    tip corners' light contact beyond it (up to a quarter of the load where one pair alone is
    on the path) relieves that pair rather than counting as a second pair: K_Halpha 1 on both
    meshes, equal to the reference written from the definition for every planet (1e-12); read
    with every cell as a pair's (path_of_contact None) the same loads would give above 1.5."""
    from jaxgear.cli.planetary import measured_k_h_alpha

    case = jio.load_case("nrel-5mw-planetary").replace(slices=2, positions_per_pitch=16)
    assert case.contact_geometry == jg.BeyondPath()
    loads = _loads(case)
    got = [m["value"] for m in measured_k_h_alpha(loads)]
    assert got == pytest.approx([1.0, 1.0], abs=1e-9)
    beyond = False
    for k, kind in enumerate(loads.meshes):
        g = float(case.pairs[k].path_of_contact)
        assert loads.paths[k] == pytest.approx(g, rel=1e-12)
        for planet in kind:
            w, s, m = (np.asarray(a) for a in (planet.line_load, planet.cell_s, planet.cell_mask))
            beyond |= bool(np.any(m & (w > 0) & ((s < 0) | (s > g))))
            ref = _k_h_alpha_reference(w, s, m, g)
            assert float(jg.rating.transverse_load_factor(planet, path_of_contact=g)) == (
                pytest.approx(ref, rel=1e-12))
        assert float(jg.rating.transverse_load_factor(kind[0])) > 1.5  # every cell a pair's
    assert beyond  # the corners do touch
