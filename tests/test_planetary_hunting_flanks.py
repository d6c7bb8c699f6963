"""A planet's two flanks with their own deviations (jaxgear.planetary.PlanetFlanks in
jaxgear.planetary.PlanetaryDeviations): a deviation on one planet tooth's ring-side flank seen in that
planet's ring mesh only, at the travels where that tooth is on the ring line (counted by the
enumeration of tests/test_planetary_hunting.py), and nowhere in the sun meshes; an indexing
error (one flank +f, the other -f) loading the planet on the sun line and unloading it on the
ring line; a tooth-thickness error given equally on both flanks equal to the single-table form;
K_gamma with a pin error and one-flank pitch errors against the series-spring model of
tests/_planetary_stage.py; the case file's flank tables."""

import copy

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.planetary as jp
from _planetary_stage import SEQ, geometry
from test_planetary_hunting import (
    N_POS,
    TORQUE,
    Z_P,
    Z_R,
    Z_S,
    _contact_windows,
    _example,
    _one_tooth,
    assert_spring_model,
    drawn_sun_ring_travel,
    seq_stage,
)

jax.config.update("jax_enable_x64", True)

F = 4e-6  # m: the tooth's deviation


@pytest.fixture(scope="module")
def seq():
    return seq_stage()


@pytest.fixture(scope="module")
def drawn_d(seq):
    return drawn_sun_ring_travel(seq[0])


def _gear(z, pitch=None, profile=0.0):
    return jg.GearDeviations(np.zeros(z) if pitch is None else pitch, profile_slope=profile)


def _flanks(sun_flank=None, ring_flank=None, sun_profile=0.0, ring_profile=0.0):
    """Every planet a PlanetFlanks of two GearDeviations (zeros where not given), sun and ring
    given: one pytree structure for the file's solves. ``sun_flank``, ``ring_flank``: per
    planet single pitch deviations or None."""
    sun_flank = sun_flank or [None] * 3
    ring_flank = ring_flank or [None] * 3
    planets = tuple(jp.PlanetFlanks(_gear(Z_P, s), _gear(Z_P, r))
                    for s, r in zip(sun_flank, ring_flank, strict=True))
    return jp.PlanetaryDeviations(_gear(Z_S, profile=sun_profile), planets,
                                  _gear(Z_R, profile=ring_profile))


def _solve(model, st, meshes, x, errors=None):
    assert len(x) == N_POS
    errors = np.zeros(3) if errors is None else errors
    r = jp.planetary_quasi_static(model, st, meshes, np.asarray(TORQUE), np.asarray(x), errors)
    assert np.all(np.asarray(r.result) == 0)
    return r


@pytest.fixture(scope="module")
def nominal(seq):
    """The contact meshes' solve (torsional, no deviation) over 20 mesh periods."""
    _, st, contact, _ = seq
    x = np.asarray(contact.positions(3, 20))
    return x, _solve(jp.TorsionalPlanetary(), st, contact, x)


def _changes(got, nominal):
    """(sun-mesh force change (p, N), TE changes (p, 2N): sun meshes then ring meshes)."""
    d_f = np.asarray(got.sun_mesh_forces) - np.asarray(nominal.sun_mesh_forces)
    d_te = np.concatenate([np.asarray(got.sun_te) - np.asarray(nominal.sun_te),
                           np.asarray(got.ring_te) - np.asarray(nominal.ring_te)], axis=1)
    return d_f, d_te


def test_a_ring_flank_deviation_is_seen_in_that_planets_ring_mesh_only(seq, drawn_d, nominal):
    """Planet 2's tooth 5 moved 4 um on its ring-side flank only: the deviations' material of
    the meshes (te_offsets) is 4 um in planet 2's ring mesh exactly at the travels where that
    tooth is on the ring line (counted here) and 0 in every other mesh and elsewhere; every sun
    mesh's cell separations are the contact meshes' (1e-12); the solve changes at those
    travels only (not where the tooth is on the sun line: there every force and TE is the
    contact meshes' to 1e-12), its ring mesh's TE drops most, planet 2 takes load."""
    geo, st, contact, teeth = seq
    model = jp.TorsionalPlanetary()
    devs = _flanks(ring_flank=[None, _one_tooth(Z_P, 5, F), None])
    meshes = jp.DeviationMeshes(contact, teeth, devs)
    x, nominal = nominal
    on_sun, on_ring = _contact_windows(geo, np.asarray(st.planet_angles), drawn_d, x, 1, 5)
    assert on_sun.sum() >= 3 and on_ring.sum() >= 3 and not np.any(on_sun & on_ring)
    zero = jnp.zeros(3)

    @jax.jit
    @jax.vmap
    def material(x):
        o_s, o_r = meshes.te_offsets(st, x)
        d0 = meshes.cell_row(model, st, x, (zero, zero)).delta0
        d0_contact = contact.cell_row(model, st, x, (zero, zero)).delta0
        return o_s, o_r, d0, d0_contact

    o_s, o_r, d0, d0_c = (np.asarray(a) for a in material(jnp.asarray(x)))
    want = np.zeros((len(x), 3))
    want[on_ring, 1] = F
    np.testing.assert_allclose(o_r, want, rtol=0, atol=1e-12 * F)
    np.testing.assert_array_equal(o_s, 0.0)
    (sun_d0, ring_d0), (sun_c, ring_c) = contact.split_cells(d0), contact.split_cells(d0_c)
    np.testing.assert_allclose(sun_d0, sun_c, rtol=0, atol=1e-12 * F)
    assert np.abs(ring_d0 - ring_c)[on_ring][:, 1].max() == pytest.approx(F, rel=1e-12)
    np.testing.assert_allclose(np.delete(ring_d0, 1, axis=1), np.delete(ring_c, 1, axis=1),
                               rtol=0, atol=1e-12 * F)

    got = _solve(model, st, meshes, x)
    d_f, d_te = _changes(got, nominal)
    event = np.abs(d_f).max(axis=1) > 1e-6 * TORQUE
    np.testing.assert_array_equal(event, on_ring)
    quiet = ~on_ring  # including every travel with the tooth on the sun line
    np.testing.assert_allclose(np.asarray(got.sun_mesh_forces)[quiet],
                               np.asarray(nominal.sun_mesh_forces)[quiet], rtol=1e-12)
    assert np.abs(d_te[quiet]).max() < 1e-12 * F
    assert np.all(np.argmin(d_te[on_ring], axis=1) == 3 + 1)
    assert np.all(d_f[on_ring, 1] > 0) and np.all(d_f[on_ring][:, [0, 2]] < 0)


def test_an_indexing_error_loads_on_one_line_and_unloads_on_the_other(seq, drawn_d, nominal):
    """Planet 2's tooth 5 moved 4 um towards its sun-side flank (+4 um on that flank, -4 um on
    the ring-side one): planet 2 takes more load while the tooth is on the sun line and less
    while it is on the ring line (counted here); unchanged elsewhere (1e-12)."""
    geo, st, contact, teeth = seq
    tooth = _one_tooth(Z_P, 5, F)
    devs = _flanks(sun_flank=[None, tooth, None], ring_flank=[None, -tooth, None])
    x, nominal = nominal
    got = _solve(jp.TorsionalPlanetary(), st, jp.DeviationMeshes(contact, teeth, devs), x)
    d_f, _ = _changes(got, nominal)
    on_sun, on_ring = _contact_windows(geo, np.asarray(st.planet_angles), drawn_d, x, 1, 5)
    assert np.all(d_f[on_sun, 1] > 1e-3 * TORQUE) and np.all(d_f[on_ring, 1] < -1e-3 * TORQUE)
    quiet = ~(on_sun | on_ring)
    np.testing.assert_allclose(np.asarray(got.sun_mesh_forces)[quiet],
                               np.asarray(nominal.sun_mesh_forces)[quiet], rtol=1e-12)


def test_a_thickness_error_on_both_flanks_is_the_single_table_form(seq, nominal):
    """Planet 2's tooth 5 thicker by 4 um and a profile slope on every tooth of planet 3, given
    as equal values on both flanks (PlanetFlanks and PlanetFlanks.both), give the single
    GearDeviations form's forces, TE and K_gamma (1e-12); the thickness is seen on both
    lines."""
    _, st, contact, teeth = seq
    x, nominal = nominal
    thick = _one_tooth(Z_P, 5, F)
    slope = np.linspace(-2e-6, 3e-6, Z_P)
    # every member given (zeros where perfect): the structure of tests/test_planetary_hunting.py's
    # solves, whose compiled program this one is
    single = jp.PlanetaryDeviations(_gear(Z_S), (_gear(Z_P), _gear(Z_P, thick),
                                                 _gear(Z_P, profile=slope)), _gear(Z_R))
    # the file's structure (one compiled program with the other tests' solves)
    flanks = jp.PlanetaryDeviations(_gear(Z_S), (
        jp.PlanetFlanks(_gear(Z_P), _gear(Z_P)),
        jp.PlanetFlanks(_gear(Z_P, thick), _gear(Z_P, thick)),
        jp.PlanetFlanks.both(_gear(Z_P, profile=slope))), _gear(Z_R))
    assert jp.PlanetaryDeviations(planets=(None,) * 3).planet_flanks(0) == (None, None)
    model = jp.TorsionalPlanetary()
    want = _solve(model, st, jp.DeviationMeshes(contact, teeth, single), x)
    got = _solve(model, st, jp.DeviationMeshes(contact, teeth, flanks), x)
    for name in ("sun_mesh_forces", "ring_mesh_forces", "sun_te", "ring_te", "k_gamma"):
        w, g = np.asarray(getattr(want, name)), np.asarray(getattr(got, name))
        np.testing.assert_allclose(g, w, rtol=1e-12, atol=1e-12 * np.abs(w).max())
    d_f, _ = _changes(want, nominal)
    assert (d_f[:, 1] > 1e-3 * TORQUE).sum() >= 6  # on the sun line and on the ring line


def _class6(rng, z):
    sp = geometry(**SEQ).sun_planet
    tol = jg.iso1328_tolerances(sp.normal_module, z * sp.normal_module, 0.03, 6)
    return np.asarray(jg.sample_gear_deviations(rng, z, tol).single_pitch)


# default tier: tests/test_planetary_hunting.py::test_k_gamma_with_a_pin_error_and_deviations_against_a_spring_model (the same spring model) and tests/test_planetary_hunting_flanks.py::test_a_ring_flank_deviation_is_seen_in_that_planets_ring_mesh_only (flank tables)
@pytest.mark.slow
def test_k_gamma_with_one_flank_pitch_errors_against_a_spring_model(seq, drawn_d):
    """A 6 um tangential error on planet 1's pin, every planet's ring-side flanks drawn at
    ISO 1328-1 class 6 (the sun-side flanks perfect) and a profile slope on every sun and ring
    tooth: at each travel, the series-spring model of tests/_planetary_stage.py with each mesh's
    offset the mean material of its lines in contact (uniform k0 b per line; the sun mesh sees
    no planet deviation, the ring mesh the ring-side flank's cumulative pitch, the teeth and
    rolls counted here): forces and K_gamma within 1e-6 (torsional), K_gamma within 1 %
    (planar, stiff pins)."""
    geo, st, contact, teeth = seq
    sp, pr = geo.sun_planet, geo.planet_ring
    rng = np.random.default_rng(23)
    ring_flanks = [_class6(rng, Z_P) for _ in range(3)]
    s_slope, r_slope = np.linspace(-3e-6, 3e-6, Z_S), np.linspace(2e-6, -2e-6, Z_R)
    devs = _flanks(ring_flank=ring_flanks, sun_profile=s_slope, ring_profile=r_slope)
    meshes = jp.DeviationMeshes(contact, teeth, devs)
    errors = np.array([6e-6, 0.0, 0.0])
    cum = [np.cumsum(p) - p[0] for p in ring_flanks]
    g_s, g_r = sp.path_of_contact, pr.path_of_contact

    def sun_material(n, s, t, k):  # the sun-side flanks perfect
        return s_slope[t] * (s / g_s - 0.5)

    def ring_material(n, s, k, u):
        return cum[n][k] + r_slope[u] * (1 - s / g_r - 0.5)

    assert_spring_model(seq, drawn_d, meshes, errors, sun_material, ring_material)


def test_bad_flanks_are_one_line(seq):
    _, _, contact, teeth = seq
    cases = [
        (lambda: jp.PlanetFlanks(sun_flank=np.zeros(Z_P)), "sun_flank"),
        (lambda: jp.PlanetaryDeviations(planets=(None, jp.PlanetFlanks(
            ring_flank=jg.GearDeviations(np.zeros(Z_P), runout=1e-6)), None)),
         "planets[1].ring_flank.runout"),
        (lambda: jp.DeviationMeshes(contact, teeth, jp.PlanetaryDeviations(planets=(
            None, None, jp.PlanetFlanks(None, _gear(16))))), "planets[2].ring_flank has 16"),
        (lambda: jp.PlanetaryDeviations(planets=(np.zeros(Z_P),)), "PlanetFlanks or None"),
    ]
    for make, words in cases:
        with pytest.raises(ValueError) as err:
            make()
        msg = str(err.value)
        assert words in msg and "\n" not in msg, msg


def test_case_flank_tables_draw_each_flank_and_refuse_in_one_line():
    """examples/planetary-hunting.toml with flank tables: with the grade each planet's two flanks
    are drawn independently, in the order sun, the planets' sun-side flanks, ring, the
    planets' ring-side flanks (default_rng(seed), redrawn here); a flank table replaces that
    flank's drawn values only, the planet's table both; without a grade, equal flank tables
    are the planet's table (a GearDeviations); mixed forms, unknown keys, wrong lengths and
    runout are one line naming them."""
    import jaxgear.io as jio

    data, _ = _example()
    pitch = [0.0] * Z_P
    pitch[2], pitch[3] = 2.0, -2.0
    d = copy.deepcopy(data)
    d["deviations"]["planet_2"] = {"ring_flank": {"pitch_um": pitch}}
    devs = jio.parse_train(d).deviations
    rng = np.random.default_rng(1)
    sp = jio.parse_train(copy.deepcopy(data)).pairs[0]
    alpha = float(sp.transverse_pressure_angle)

    def draw(z):
        return jg.sample_gear_deviations(rng, z, jg.iso1328_tolerances(3e-3, z * 3e-3, 0.03, 6),
                                         alpha)

    order = [("sun", devs.sun, Z_S)]
    order += [(f"planet {i + 1} sun flank", devs.planet(i).sun_flank, Z_P) for i in range(3)]
    order += [("ring", devs.ring, Z_R)]
    order += [(f"planet {i + 1} ring flank", devs.planet(i).ring_flank, Z_P) for i in range(3)]
    for name, got, z in order:
        want = draw(z)
        fields = ["profile_slope", "profile_form", "helix_slope", "helix_form"]
        if name != "planet 2 ring flank":
            fields.append("single_pitch")
        for f in fields:
            np.testing.assert_allclose(getattr(got, f), getattr(want, f), rtol=1e-12,
                                       err_msg=f"{name} {f}")
    np.testing.assert_allclose(devs.planet(1).ring_flank.single_pitch, np.array(pitch) * 1e-6,
                               atol=1e-18)
    assert not np.allclose(devs.planet(0).sun_flank.profile_slope,
                           devs.planet(0).ring_flank.profile_slope)
    # the example's planet-2 table: the given pitch deviations on both flanks
    both = jio.parse_train(copy.deepcopy(data)).deviations.planet(1)
    np.testing.assert_array_equal(both.sun_flank.single_pitch, both.ring_flank.single_pitch)

    # without a grade: equal flank tables = the planet's table
    flat = copy.deepcopy(data)
    del flat["deviations"]["grade"]
    split = copy.deepcopy(flat)
    split["deviations"]["planet_2"] = {f: {"pitch_um": pitch, "helix_slope_um": 1.5}
                                      for f in ("sun_flank", "ring_flank")}
    flat["deviations"]["planet_2"] = {"pitch_um": pitch, "helix_slope_um": 1.5}
    g_flat = jio.parse_train(flat).deviations.planet(1)
    g_split = jio.parse_train(split).deviations.planet(1)
    assert isinstance(g_flat, jg.GearDeviations) and isinstance(g_split, jp.PlanetFlanks)
    for g in (g_split.sun_flank, g_split.ring_flank):
        for f in ("single_pitch", "helix_slope", "profile_slope"):
            np.testing.assert_array_equal(getattr(g, f), getattr(g_flat, f))
    one = copy.deepcopy(flat)
    one["deviations"]["planet_2"] = {"sun_flank": {"pitch_um": pitch}}
    g_one = jio.parse_train(one).deviations.planet(1)
    assert g_one.ring_flank is None and g_one.sun_flank.teeth == Z_P

    def bad(planet_2, words):
        d = copy.deepcopy(data)
        d["deviations"]["planet_2"] = planet_2
        with pytest.raises(ValueError) as err:
            jio.parse_train(d)
        msg = str(err.value)
        assert all(w in msg for w in words) and "\n" not in msg, msg

    bad({"pitch_um": pitch, "ring_flank": {"pitch_um": pitch}},
        ["[deviations.planet_2] pitch_um", "not beside its flank tables"])
    bad({"sun_flank": {"pitch_um": pitch, "lead_um": 1.0}},
        ["deviations.planet_2.sun_flank", "lead_um"])
    bad({"left_flank": {}}, ["left_flank", "ring_flank"])
    bad({"ring_flank": {"pitch_um": pitch[:-1]}},
        ["[deviations.planet_2.ring_flank] pitch_um", str(Z_P)])
    bad({"ring_flank": {"profile_slope_um": [1.0] * 3}},
        ["[deviations.planet_2.ring_flank] profile_slope_um"])
    bad({"sun_flank": {"runout_um": 3.0}},
        ["[deviations.planet_2.sun_flank] runout_um", "planet_runout_um"])
    bad({"sun_flank": 3.0}, ["sun_flank", "table"])
