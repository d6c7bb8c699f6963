"""The 3D lumped model (jaxgear.planetary.SpatialPlanetary) in the load sharing: a sun eccentricity
on a helical stage against a series-spring model written here (tests/_planetary_stage.py:
rigid_path_forces, each mesh's stiffness along the tooth normal seen on the line of action as
k cos^2 beta_b), and the rating's K_gamma taken from the 3D model where `jaxgear run` uses it."""

import dataclasses
import tomllib

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _planetary_stage import A_R, A_S, HELD, K_MESH, R_S, rigid_path_forces
from _planetary_stage import lin_parker_stage as stage

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.planetary as jp

TORQUE = 3000.0
E = 30e-6  # m
BETA = np.radians(30.0)


def helical(st, beta=BETA):
    """The stage made 3D: base helix angle beta, 30 mm faces, every member held axially and in
    tilt (HELD: the rigid centres and pins of the spring model)."""
    kw = {"axial_stiffness": HELD, "tilt_stiffness": HELD}
    rep = dataclasses.replace
    return rep(st, helix_angle=beta, face_width=0.03,
               **{m: rep(getattr(st, m), **kw) for m in ("sun", "ring", "carrier", "planet")})


def test_sun_eccentricity_on_the_3d_model_against_the_series_spring_model():
    """A 30 um sun eccentricity over a turn of the sun, beta_b = 30 deg, 4 planets: the sun's
    offset e moves each mesh's normal compression by n . e = cos beta_b (t . e), so each path is
    the spring model's with the meshes' transverse stiffness k cos^2 beta_b: transverse forces
    F_t (rigid_path_forces), normal ones F_t / cos beta_b. load_sharing on the 3D model (normal
    forces) within 1e-3 of the mean force, K_gamma within 1e-3 (asserted 1 %); the offsets
    taken transverse on the normal deflection (the spread cos beta_b times too small: a spring
    model with k cos beta_b) would be off by more than 1 % in K_gamma."""
    beta0 = 0.7
    st = helical(stage(4, jp.Eccentricities(sun=E, sun_phase=beta0)))
    x = np.arange(12) * 2 * np.pi * R_S / 12
    got = jax.vmap(lambda xi: jp.load_sharing(jp.SpatialPlanetary(), st, TORQUE, jnp.zeros(4),
                                              travel=xi))(jnp.asarray(x))
    c = np.cos(BETA)
    f_nom = TORQUE / (4 * R_S * c)
    for i, xi in enumerate(x):
        centre = E * np.array([np.cos(beta0 + xi / R_S), np.sin(beta0 + xi / R_S)])
        f_t, k_gamma = rigid_path_forces(TORQUE, R_S, st.planet_angles, A_S, A_R,
                                         K_MESH * c**2, K_MESH * c**2, sun_centre=centre)
        _, wrong = rigid_path_forces(TORQUE, R_S, st.planet_angles, A_S, A_R, K_MESH * c,
                                     K_MESH * c, sun_centre=centre)
        np.testing.assert_allclose(got.sun_mesh_forces[i], f_t / c, rtol=0, atol=1e-3 * f_nom)
        np.testing.assert_allclose(got.ring_mesh_forces[i], f_t / c, rtol=0, atol=1e-3 * f_nom)
        assert float(got.k_gamma[i]) == pytest.approx(k_gamma, rel=1e-2)
        assert abs(float(got.k_gamma[i]) - k_gamma) < 1e-3 * k_gamma
        if k_gamma > 1.1:
            assert abs(wrong - k_gamma) > 1e-2 * k_gamma
    assert np.max(np.asarray(got.k_gamma)) > 1.2  # a real spread


def test_the_contact_solve_with_eccentricities_is_unchanged_by_the_normal_offsets():
    """The contact solve takes the offsets transverse (pin_terms divides error_terms' normal
    ones by cos beta_b): with one constant spring per mesh at two Gauss points and every mesh
    loaded it is load_sharing on the same stage, its transverse forces cos beta_b times the
    normal ones (1e-6: the planets' rotation spring of the contact solve)."""
    st = helical(stage(4, jp.Eccentricities(sun=E, sun_phase=0.7, ring=20e-6, ring_phase=-1.0)))
    model = jp.SpatialPlanetary()
    x = np.array([0.0, 3e-3, 11e-3])
    qs = jp.planetary_quasi_static(model, st, jp.ConstantMeshes(face_points=2),
                                   jnp.asarray(TORQUE), jnp.asarray(x))
    for i, xi in enumerate(x):
        ls = jp.load_sharing(model, st, TORQUE, jnp.zeros(4), travel=xi)
        np.testing.assert_allclose(qs.sun_mesh_forces[i], np.cos(BETA) * ls.sun_mesh_forces,
                                   rtol=1e-6)


def _lumped_case(**planetary):
    data = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
    data["planetary"].update(planetary)
    return data


def _supported(data):
    for m in ("sun", "ring", "carrier"):
        data["planetary"][m].update(axial_N_per_um=100.0, tilt_Nm_per_rad=1e6)
    data["planetary"]["planet"].update(pin_axial_N_per_um=80.0, pin_tilt_Nm_per_rad=4e5)
    data["planetary"]["tangential_pin_errors_um"] = [10.0, 0.0, 0.0]
    return data


def test_the_rating_takes_k_gamma_from_the_3d_model_where_the_run_uses_it():
    """`jaxgear run`'s K_gamma for the rating (cli.planetary.rating_k_gamma, from the run's
    load-sharing section): a helical stage on its axial and tilting supports -> the 3D model's,
    load_sharing(SpatialPlanetary(), ...) on the load-sharing stage (1e-12), named as such;
    without the supports, or spur -> the planar model's."""
    from jaxgear.cli.planetary import (K_GAMMA_SOURCES, rating_k_gamma, sharing_models,
                                       sharing_summary)

    def chosen(data, names):
        case = jio.parse_train(data)
        spec = case.form.spec
        st = spec.stage(case)
        torques = spec.torques(case.torque)
        sharing = sharing_summary(spec, st, torques, sharing_models(spec, st))
        held = spec.sharing_stage(st)
        models = {"planar": jp.PlanarPlanetary(), "spatial": jp.SpatialPlanetary()}
        direct = {name: float(jp.load_sharing(models[name], held, abs(torques["sun"]),
                                              np.asarray(spec.tangential_pin_errors),
                                              np.asarray(spec.radial_pin_errors)).k_gamma)
                  for name in names}
        return rating_k_gamma(sharing), direct

    (k, source), direct = chosen(_supported(_lumped_case(helix_angle_deg=20.0,
                                                          face_width_mm=30.0)),
                                 ("planar", "spatial"))
    assert source == K_GAMMA_SOURCES["spatial"] and "3D" in source
    assert k == pytest.approx(direct["spatial"], rel=1e-12)
    assert abs(direct["spatial"] - direct["planar"]) > 1e-4  # the choice matters
    bare = _lumped_case(helix_angle_deg=20.0, face_width_mm=30.0)
    bare["planetary"]["tangential_pin_errors_um"] = [10.0, 0.0, 0.0]
    (k, source), direct = chosen(bare, ("planar",))
    assert source == K_GAMMA_SOURCES["planar"] and k == pytest.approx(direct["planar"], rel=1e-12)


def test_the_rating_report_names_the_k_gamma_source(tmp_path):
    """rating_section with the 3D model's K_gamma: summary's K_gamma source and rating.md's
    table row (value, source column) name it (the embedded nrel-5mw-planetary, K_gamma not
    given in its [rating])."""
    from jaxgear.cli.planetary import K_GAMMA_SOURCES, rating_section

    spatial = K_GAMMA_SOURCES["spatial"]
    sec = rating_section(jio.load_case("nrel-5mw-planetary"), str(tmp_path), 1.2,
                         spatial)
    # the load sharing's linear mesh springs: the contact model the computed K_γ states
    springs = jg.rating.MESH_SPRINGS
    assert sec["K_gamma"] == {"value": [1.2, 1.2], "source": [spatial] * 2,
                              "contact_model": [springs] * 2}
    md = (tmp_path / "rating.md").read_text()
    assert md.count(f"| K_γ | 1.200 ({spatial}; contact model: {springs}) |") == 2
