"""The flexible ring gear in the carrier-frame dynamics (jaxgear.planetary.planetary_dynamics with
ring=jaxgear.planetary.CondensedRing): the ring's station displacements as coordinates, the contacts moving
around it with the carrier.

References: the zero-speed limit is the quasi-static solution of
jaxgear.planetary.planetary_quasi_static with the same ring (written on the planets' N ring-mesh
displacements with the compliance C^-1, not on the stations: another formulation), to 1e-8; the FE
ring made 10^3 stiffer gives the rigid ring's dynamic factors per mesh within 0.5 %.
"""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import fem_prep as fp
import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.planetary as jp
from _planetary_stage import K0, RING_PIN_ERRORS, RING_TORQUE, SEQ, geometry, stage

jax.config.update("jax_enable_x64", True)

TORQUE = 1000.0  # N m on the sun
ZETA = 0.05
PIN_ERRORS = np.array([15e-6, 0.0, 0.0])  # m, tangential, planet 1
RIM = 0.009  # m: the SEQ ring's rim under its root circle


@pytest.fixture(scope="module")
def seq():
    geo = geometry(**SEQ)
    return geo, stage(geo, 3, pin=3e8, sun_bearing=1e8)


# the constant-mesh runs' settings: those of tests/_planetary_stage.py's ring_run (24 steps per
# mesh period, 6 periods, 3 kept; its torque and pin error are this file's), so that the rigid
# ring's run is tests/test_planetary_ring_cb.py's compiled program and the flexible rings' one
# program for both tests here
RUN = jp.PlanetaryRun(TORQUE, steps_per_period=24, periods=6, keep_periods=3,
                      damping_ratio=ZETA, tangential_pin_errors=PIN_ERRORS)
assert TORQUE == RING_TORQUE and np.array_equal(PIN_ERRORS, RING_PIN_ERRORS)


def coupled_compliance(z, c=3e-9, share=0.5):
    """An SPD station compliance (m/N) that couples every station: c (delta_kk' + share
    cos(theta_k - theta_k')) on each in-plane direction (a PSD cosine kernel on the identity)."""
    t = 2 * math.pi * np.arange(z) / z
    s = c * (np.eye(z) + share * np.cos(t[:, None] - t[None, :]))
    return np.einsum("kl,ab->kalb", s, np.eye(2))


def test_zero_speed_limit_is_the_flexible_quasi_static_solution(seq):
    """At 1e-6 rad/s, over six mesh periods (the planets move 6/53 of a turn around the
    ring), the recorded mesh forces and ring deflections of the last three are
    planetary_quasi_static's with the same ring at the same travels, to 1e-8."""
    _, st = seq
    ring = jp.CondensedRing(coupled_compliance(53))
    run = RUN
    model = jp.PlanarPlanetary()
    meshes = jp.ConstantMeshes()
    got = jp.planetary_dynamics(model, st, meshes, run, jnp.asarray(1e-6), ring=ring)
    assert int(got.result) == 0
    static = jp.planetary_quasi_static(model, st, meshes, np.asarray(TORQUE), got.travel,
                                       PIN_ERRORS, ring=ring)
    np.testing.assert_allclose(got.sun_mesh_forces, static.sun_mesh_forces, rtol=1e-8)
    np.testing.assert_allclose(got.ring_mesh_forces, static.ring_mesh_forces, rtol=1e-8)
    np.testing.assert_allclose(got.ring_deflection, static.ring_deflection, rtol=1e-7,
                               atol=1e-12)
    assert got.displacement.shape[1] == len(model.dof_names(st)) + 2 * 53


@pytest.fixture(scope="module")
def fe_compliance(seq):
    """The SEQ ring (53 teeth, a 9 mm rim, on a uniform elastic housing of 1e11 Pa/m), condensed
    on its 53 root-patch stations: its station compliance F (m/N)."""
    geo, _ = seq
    pr = geo.planet_ring
    r_f = float(pr.root_radii[1])
    body = fp.RingBody(
        "seq-ring", r_f, r_f + RIM, float(pr.gear.face_width), fp.Material(),
        fp.MeshSettings(fp.Hex20(), size=RIM, circumferential_size=0.012),
        fp.Condensation(fp.CraigBampton(), fp.Distributing(), modes=4, teeth=53,
                        axial_master_nodes=2),
        fp.ElasticFoundation(1e11, 1e11, 1e11),
    )
    return fp.ring_master_compliance(fp.prepare_ring(body))[0]


def test_stiff_fe_ring_equals_the_rigid_ring_constant_meshes(seq, fe_compliance):
    """The fast form of the next test: one spring per mesh (ConstantMeshes), a pin error, at a
    carrier speed of 60 rad/s: the FE ring 10^3 stiffer gives the rigid ring's mesh forces at
    every recorded step within 0.5 %; the real ring relieves the overloaded planet (lower
    dynamic load sharing K_gamma; sun and pins held, as the quasi-static test of
    tests/test_planetary_ring.py), its deflections positive (relieving)."""
    st = stage(seq[0], 3)
    run = RUN  # the zero-speed test's run: one compiled program for the flexible rings
    model = jp.PlanarPlanetary()
    meshes = jp.ConstantMeshes()
    rigid, stiff, soft = _three_rings(model, st, meshes, run, fe_compliance)
    np.testing.assert_allclose(stiff.sun_mesh_forces, rigid.sun_mesh_forces, rtol=5e-3)
    np.testing.assert_allclose(stiff.ring_mesh_forces, rigid.ring_mesh_forces, rtol=5e-3)
    assert float(soft.k_gamma) < float(rigid.k_gamma) - 0.02
    assert np.all(np.asarray(soft.ring_deflection) > 0.0)


def _three_rings(model, st, meshes, run, fe_compliance, omega=60.0):
    """The stage's dynamics at carrier speed ``omega`` (rad/s) with the rigid ring, the FE ring
    made 10^3 stiffer and the FE ring itself (massless, compliance ``fe_compliance``)."""
    omega = jnp.asarray(omega)
    return tuple(
        jp.planetary_dynamics(model, st, meshes, run, omega, **ring)
        for ring in ({"ring": jp.RigidRing()}, {"ring": jp.CondensedRing(fe_compliance / 1e3)},
                     {"ring": jp.CondensedRing(fe_compliance)})
    )


@pytest.mark.slow
def test_stiff_fe_ring_dynamics_equals_the_rigid_ring(seq, fe_compliance):
    """Real contact (53/17/19 teeth, 3 planets, a pin error) at a carrier speed of 60 rad/s:
    the FE ring made 10^3 stiffer (massless, its compliance / 10^3) gives the rigid ring's
    dynamic factor of every mesh within 0.5 %, while the real ring changes them by more."""
    geo, st = seq
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    run = jp.PlanetaryRun(TORQUE, steps_per_period=24, periods=12, keep_periods=3,
                          damping_ratio=ZETA, tangential_pin_errors=PIN_ERRORS)
    model = jp.PlanarPlanetary()
    rigid, stiff, soft = _three_rings(model, st, meshes, run, fe_compliance)
    for r in (rigid, stiff, soft):
        assert int(r.result) == 0
    for a, b, c in zip(rigid.dynamic_factors, stiff.dynamic_factors, soft.dynamic_factors,
                       strict=True):
        print("DF rigid", np.asarray(a), "stiff", np.asarray(b), "FE ring", np.asarray(c))
        np.testing.assert_allclose(b, a, rtol=5e-3)
        assert np.max(np.abs(np.asarray(c) / np.asarray(a) - 1)) > 5e-3
