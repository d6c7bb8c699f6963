"""Hybrid dynamics, first part: Newmark with the contact loop in the cell space
on the small test body. References: the same Newmark scheme on all coordinates (each step the
contact problem K_eff X = F_eff − Σ P V solved with jaxgear.solve_contact), and the quasi-static
limit at low speed."""

from __future__ import annotations

import functools
import json
import logging
import pathlib
import textwrap

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg
from _devices import run_on_cpu_devices
from _examples import load_example
from _hybrid_util import drive_rotations, rigidified_pair, rigidified_runs
from _scene_solve import half_face_meshes

import fem_prep
import jaxgear as jg
from jaxgear import io as jio
from jaxgear.dynamics import (
    Batching,
    DiffraxIntegrator,
    HertzPressure,
    Newmark,
    Outputs,
    SteadyState,
    Up,
    auto_steps_per_period,
    dynamic_model,
    excited_omega,
    mean_mesh_stiffness,
    mesh_averaged_modes,
    simulate,
    speed_sweep,
)
from jaxgear.io import Damping, static_scene

DATA = pathlib.Path(__file__).parent / "data"
STATIC_TE_ATOL = 1e-2  # of the mean quasi-static TE, at 5 rad/s


def _model(scene, mods, torque, damping=None, rotating_frame=False):
    return dynamic_model(scene, mods, torque, damping, rotating_frame=rotating_frame)


def _simulate(scene, mods, torque, speed, *, damping=None, rotating_frame=False, **settings):
    """:func:`jaxgear.dynamics.simulate` on the hybrid model of ``scene``."""
    return simulate(_model(scene, mods, torque, damping, rotating_frame), speed, **settings)


def _sweep(scene, mods, torque, speeds, *, damping=None, rotating_frame=False, **settings):
    """:func:`jaxgear.dynamics.speed_sweep` on the hybrid model of ``scene``: its results."""
    model = _model(scene, mods, torque, damping, rotating_frame)
    return speed_sweep(model, speeds, **settings).results


@pytest.fixture(scope="module")
def setup(fem_prep_cache):
    # theoretical path: the all-coordinate references written here (_newmark_all_coordinates)
    # take the flank gaps of the path, not the corner gaps beyond it
    case = jio.load_case(DATA / "hybrid-test-case.toml").replace(
        contact_geometry=jg.TheoreticalPath()
    )
    body = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
    return case, static_scene(case, bodies=(None, body))[0]


# the settings of the module's runs of the test scene (Newmark 16, 3 periods with 1 kept, the
# states recorded): one compiled sweep program for every speed and test that takes them
RUN = {"integrator": Newmark(16), "window": SteadyState(3, 1), "outputs": Outputs(states=True)}


@pytest.fixture(scope="module")
def low_speed(setup):
    """The run at 5 rad/s (mesh frequency 16 Hz, far below the modes), read by two tests."""
    case, scene = setup
    return _simulate(scene, case.modifications, case.torque, 5.0, **RUN)


def _period_mesh_stiffness(scene, mods, torque, speed, spp):
    """k ↦ K̄_m(k) (n, n): the mesh stiffness of mesh period k averaged over the period's
    quasi-static positions θ_p + k T on the full cell vectors (the loaded cells of the
    quasi-static solution at θ_p, centrifugal load on)."""
    mesh = scene.mesh
    n = scene.structure.K.shape[0]
    T = float(mesh.mesh_period_angle)
    positions = (np.arange(spp) + 0.5) * T / spp
    loaded = np.asarray(
        jg.quasi_static(scene, mods, torque, jnp.asarray(positions), speed=speed).line_load
    )

    @jax.jit
    @jax.vmap
    def parts(th):  # a position's cells: V (c, n) and k l (c,), 0 off the flanks
        cells = mesh.cells(th)
        mask = cells.mask.reshape(-1)
        V = jnp.where(mask[:, None], scene.cell_vectors(cells).reshape(-1, n), 0.0)
        return V, jnp.where(mask, (cells.stiffness * cells.length).reshape(-1), 0.0)

    on = np.asarray(loaded > 0).reshape(spp, -1)

    @functools.cache
    def mesh_stiffness(k):  # Σ_p Σ_c w_c k_c l_c V_c V_cᵀ / spp over the period's positions
        V, kl = (np.asarray(a) for a in parts(jnp.asarray(positions + k * T)))
        W = V * np.where(on, kl, 0.0)[..., None]
        return W.reshape(-1, n).T @ V.reshape(-1, n) / spp

    return mesh_stiffness


def _exact_contact_numpy(Keff, F, V, kl, d0, mask, max_iterations=100):
    """The exact contact problem K_eff X + Σ_c k_c l_c max(V_c·X − δ0_c, 0) V_c = F (seed (2.9))
    by the seed's active-set iteration (II-25) from every cell on the flanks, in NumPy/SciPy
    (LAPACK's LU: K_eff is not symmetric in a turning frame): X (n,) and the mesh force
    Σ_c k_c l_c max(Δ_c, 0) (N)."""
    active = mask.copy()
    for _ in range(max_iterations):
        w = np.where(active, kl, 0.0)
        X = scipy.linalg.solve(Keff + (V.T * w) @ V, F + V.T @ (w * d0))
        gap = V @ X - d0
        new = mask & (gap > 0)
        if np.array_equal(new, active):
            return X, float(np.sum(np.where(mask, kl * np.maximum(gap, 0.0), 0.0)))
        active = new
    raise AssertionError("the reference's active set did not settle")


def _newmark_all_coordinates(scene, mods, torque, speed, spp, runs):
    """Newmark average acceleration on all coordinates, written out here, with the damping
    C_of(k) in mesh period k (K_eff refactored each period) and each step's contact problem
    K_eff X = F_eff − Σ P V solved by the active set in NumPy (:func:`_exact_contact_numpy`; the
    cells' vectors, stiffness and flank gaps of every step from the model's mesh in one call);
    the flank gaps from one time-constant reference (the largest flank deviation over the
    period's step positions), the start moved along the drive rotation to match. ``runs``:
    (C_of, rotating (the turning frame's Ω Gy and Ω² S), steps) each; the mesh force per step
    of each."""
    mesh = scene.mesh
    n = scene.structure.K.shape[0]
    T = float(mesh.mesh_period_angle)
    dt = T / speed / spp
    a0, a1 = 4.0 / dt**2, 2.0 / dt
    F = torque * np.asarray(scene.f_torque) + speed**2 * np.asarray(scene.structure.f_centrifugal)
    th0 = 0.5 * T / spp
    # the start: the quasi-static solution at θ0, the first of a period's step positions (the
    # program of the module's other quasi-static solves at spp positions)
    positions = (np.arange(spp) + 0.5) * T / spp
    qs = jg.quasi_static(scene, mods, torque, jnp.asarray(positions), speed=speed)

    @jax.jit
    @jax.vmap
    def cells_at(th):  # each position's cells: V (c, n), k l (c,), deviation e (c,), mask (c,)
        cells = mesh.cells(th)
        e = mods.deviation(cells.s / mesh.path_of_contact, cells.z / mesh.face_width)
        mask = cells.mask.reshape(-1)
        V = jnp.where(mask[:, None], scene.cell_vectors(cells).reshape(-1, n), 0.0)
        kl = jnp.where(mask, (cells.stiffness * cells.length).reshape(-1), 0.0)
        return V, kl, e.reshape(-1), mask

    steps = max(r[2] for r in runs)
    V, kl, e, mask = (np.asarray(a) for a in cells_at(th0 + np.arange(steps + 1) * T / spp))
    e = np.where(mask, e, -np.inf)
    # flank gaps from one time-constant reference, the start moved along the drive rotation
    e_ref = float(np.max(e[:spp]))
    start = np.asarray(qs.x[0]) + (e_ref - float(np.max(e[0]))) * np.asarray(scene.N[:, 0])
    d0 = np.where(mask, e_ref - e, 0.0)

    out = []
    for C_of, rotating, n_steps in runs:
        M, K, Cr = np.asarray(scene.structure.M), np.asarray(scene.structure.K), 0.0
        if rotating:
            K = K + speed**2 * np.asarray(scene.structure.spin_stiffness)
            Cr = speed * np.asarray(scene.structure.gyroscopic)
        X, Xd, Xdd = start, np.zeros(M.shape[0]), np.zeros(M.shape[0])
        forces = []
        for i in range(n_steps):
            if i % spp == 0:
                C = C_of(i // spp) + Cr
                Keff = K + a0 * M + a1 * C
            Feff = F + M @ (a0 * X + 4.0 / dt * Xd + Xdd) + C @ (a1 * X + Xd)
            Xn, fm = _exact_contact_numpy(Keff, Feff, V[i + 1], kl[i + 1], d0[i + 1], mask[i + 1])
            Xddn = a0 * (Xn - X - dt * Xd - dt * dt * 0.25 * Xdd)
            Xd = Xd + dt * 0.5 * (Xdd + Xddn)
            X, Xdd = Xn, Xddn
            forces.append(fm)
        out.append(np.array(forces))
    return out


def _reference_newmark(scene, mods, torque, speed, spp, n_steps, alpha, beta, rotating=False):
    """The all-coordinate Newmark with Rayleigh damping C(k) = α M + β (K + K̄_m(k)), K̄_m(k)
    the mesh stiffness of period k (:func:`_period_mesh_stiffness`): mesh force per step."""
    Km = _period_mesh_stiffness(scene, mods, torque, speed, spp)
    M, K = np.asarray(scene.structure.M), np.asarray(scene.structure.K)

    def C_of(k):
        return alpha * M + beta * (K + Km(k))

    return _newmark_all_coordinates(scene, mods, torque, speed, spp, [(C_of, rotating, n_steps)])[0]


@pytest.mark.parametrize(
    "rotating", [False, pytest.param(True, marks=pytest.mark.slow)], ids=["fixed", "rotating"]
)
def test_cell_space_newmark_equals_newmark_on_all_coordinates(setup, rotating):
    """The cell-space Newmark (window compliance, the mesh damping's window update once per
    period by Woodbury, the turning frame's Coriolis and spin stiffness) against the same
    scheme on all coordinates, over 3 mesh periods (the mesh damping moves on twice): the third
    period's mesh force, which carries the first two's errors in its start state. The run
    takes the module's settings ``RUN`` (Newmark 16, 3 periods with the last kept; one
    compiled program with the module's other runs). The turning frame's case is slow: the
    composite test (tests/test_hybrid_composite.py) runs it in the default suite."""
    case, scene = setup
    spp, periods, speed, ray = 16, 3, 800.0, (25.0, 2.5e-6)  # seed D1
    assert RUN["integrator"] == Newmark(spp) and RUN["window"] == SteadyState(periods, 1)
    r = _simulate(
        scene,
        case.modifications,
        case.torque,
        speed,
        damping=Damping("rayleigh", alpha=ray[0], beta=ray[1]),
        rotating_frame=rotating,
        **RUN,
    )
    assert int(r.result) == 0
    ref = _reference_newmark(
        scene, case.modifications, case.torque, speed, spp, spp * periods, *ray, rotating
    )
    np.testing.assert_allclose(
        np.asarray(r.mesh_force), ref[-spp:], rtol=1e-8, atol=1e-8 * ref.max()
    )


def test_low_speed_is_the_quasi_static_response(setup, low_speed):
    """At 5 rad/s (mesh frequency 16 Hz, far below the modes) the dynamic mesh force follows the
    quasi-static one at speed (centrifugal load included) within 0.5 % of the static force."""
    case, scene = setup
    speed, r = 5.0, low_speed
    qs = jg.quasi_static(scene, case.modifications, case.torque, r.theta, speed=speed)
    f_qs = np.sum(
        np.asarray(qs.line_load) * np.asarray(scene.mesh.cells(0.0).length)[None], axis=(1, 2)
    )
    np.testing.assert_allclose(np.asarray(r.mesh_force), f_qs, atol=5e-3 * float(r.static_force))
    # the static TE (the quasi-static one at the same place in the first mesh period, whose
    # stations differ from those under the mesh now) and the dynamic TE follow the quasi-static
    te_qs = np.asarray(qs.transmission_error)
    for te in (r.static_te, r.transmission_error):
        np.testing.assert_allclose(np.asarray(te), te_qs, atol=STATIC_TE_ATOL * te_qs.mean())


def test_automatic_step_of_a_hybrid_model(setup):
    """``Newmark(None)`` on a hybrid model: the automatic step of the lumped models (the smallest
    power of two >= max(64, 40 f_max / f_mesh), docs/dynamics.md "Time step and accuracy") from
    the highest mode with >= 5 % of its strain energy in the mesh, here by SciPy's generalised
    eigensolver on (K + K̄_m, M); the run reports N_s f_mesh / f_max."""
    case, scene = setup
    model = _model(scene, case.modifications, case.torque)
    Km = np.asarray(mean_mesh_stiffness(scene, case.modifications, jnp.asarray(case.torque), 64))
    lam, Phi = scipy.linalg.eigh(np.asarray(scene.structure.K) + Km, np.asarray(scene.structure.M))
    elastic = lam > 1e-9 * lam.max()
    share = np.einsum("ij,ik,kj->j", Phi, Km, Phi) / np.where(elastic, lam, 1.0)
    w_max = np.sqrt(lam[elastic & (share >= 0.05)].max())
    theta_m = float(scene.mesh.mesh_period_angle)
    speeds = np.array([300.0, 3000.0])
    need = np.maximum(64, np.ceil(40 * w_max * theta_m / (2 * np.pi * speeds)))
    expected = 2 ** np.ceil(np.log2(need))
    np.testing.assert_array_equal(auto_steps_per_period(model, speeds), expected)


@pytest.mark.slow
def test_a_hybrid_run_with_the_automatic_step_reports_it(setup):
    """``simulate`` with ``Newmark(None)`` on a hybrid model runs the automatic N_s and reports
    N_s f_mesh / f_max with the f_max of :func:`jaxgear.dynamics.mesh_averaged_modes` (whose rule
    the test above checks against SciPy)."""
    case, scene = setup
    model = _model(scene, case.modifications, case.torque)
    w_max = float(excited_omega(mesh_averaged_modes(model)))
    n = int(auto_steps_per_period(model, [3000.0])[0])
    r = simulate(model, 3000.0, integrator=Newmark(), window=SteadyState(2, 1))
    assert int(r.result) == 0 and int(r.steps_per_period) == n
    per_mode = n * 3000.0 / float(scene.mesh.mesh_period_angle) / (w_max / (2 * np.pi))
    assert float(r.steps_per_mode_period) == pytest.approx(per_mode, rel=1e-12)


def test_speed_sweep_maps_single_speeds(setup):
    """A hybrid sweep's speed k is the single run at that speed (one speed per call, as
    ``jaxgear sweep`` runs a hybrid case: the compiled program of the single runs serves the
    sweep too); bad settings are one-line errors."""
    case, scene = setup
    kw = RUN
    sw = _sweep(
        scene,
        case.modifications,
        case.torque,
        [300.0, 900.0],
        batching=Batching(chunk_size=1),
        **kw,
    )
    one = _simulate(scene, case.modifications, case.torque, 900.0, **kw)
    np.testing.assert_allclose(sw.mesh_force[1], one.mesh_force, rtol=1e-10)
    with pytest.raises(ValueError, match="steps_per_period"):
        _simulate(scene, None, case.torque, 900.0, integrator=Newmark(2))
    with pytest.raises(ValueError, match="integrator"):  # no diffrax form in the cell space
        _simulate(scene, None, case.torque, 900.0, integrator=DiffraxIntegrator())
    with pytest.raises(ValueError, match="direction"):  # no continuation
        speed_sweep(_model(scene, None, case.torque), [900.0], direction=Up())


# default tier: tests/test_hybrid_train.py::test_rigidified_idler_train_dynamics_equal_the_rigid_node_train (two meshes on one condensed body in the hybrid Newmark) and tests/test_hybrid.py::test_a_pair_cut_into_two_half_face_meshes_gives_the_pair_result (the split pair, quasi-static)
@pytest.mark.slow
def test_dynamics_of_a_pair_cut_into_two_half_face_meshes_give_the_pair_response(setup):
    """The hybrid dynamics over every mesh of a scene: the spur pair cut across the face into
    two half-face meshes on the same members (the wheel condensed) is the same Newmark run in
    the cell space (the meshes' windows joined, their mesh damping summed on the shared rim
    stations). Reference: the one-mesh run at 900 rad/s (Newmark 16, Rayleigh damping that
    follows the mesh): each half's TE equals the pair's, the halves' mesh forces, line forces
    and static forces sum to the pair's (so their summed dynamic factor is the pair's), the
    bearing forces and rim records agree, to 1e-9."""
    case, scene = setup
    two = eqx.tree_at(lambda s: s.meshes, scene, half_face_meshes(scene.meshes[0]))
    run = RUN
    whole = _simulate(scene, case.modifications, case.torque, 900.0, **run)
    parts = _simulate(two, case.modifications, case.torque, 900.0, **run)
    assert int(whole.result) == 0 and int(parts.result) == 0
    a, b = parts.meshes
    fm = np.asarray(whole.mesh_force)
    scale = float(np.max(fm))
    np.testing.assert_allclose(
        np.asarray(a.mesh_force + b.mesh_force), fm, rtol=0, atol=1e-9 * scale
    )
    np.testing.assert_allclose(
        np.asarray(a.line_force + b.line_force),
        np.asarray(whole.line_force),
        rtol=0,
        atol=1e-9 * scale,
    )
    np.testing.assert_allclose(
        float(a.static_force + b.static_force), float(whole.static_force), rtol=1e-9
    )
    np.testing.assert_allclose(
        float(np.max(a.mesh_force + b.mesh_force) / (a.static_force + b.static_force)),
        float(whole.dynamic_factor),
        rtol=1e-9,
    )
    te = np.asarray(whole.transmission_error)
    for half in (a, b):
        np.testing.assert_allclose(
            np.asarray(half.transmission_error), te, rtol=0, atol=1e-9 * np.max(np.abs(te))
        )
        np.testing.assert_allclose(
            np.asarray(half.static_te),
            np.asarray(whole.static_te),
            rtol=0,
            atol=1e-9 * np.max(np.abs(te)),
        )
    # the rims to 1e-9 of the rim's motion (a spur wheel's axial motion is round-off, 1e-17 m)
    rim = np.max(np.abs(np.asarray(whole.rim_radial)))
    for name, rim_scale in (("bearing_force", None), ("rim_radial", rim), ("rim_axial", rim)):
        ref = np.asarray(getattr(whole, name))
        scale = np.max(np.abs(ref)) if rim_scale is None else rim_scale
        np.testing.assert_allclose(
            np.asarray(getattr(parts, name)), ref, rtol=0, atol=1e-9 * scale, err_msg=name
        )


# default tier: tests/test_dynamics_sweep.py::test_sharded_sweep_matches_unsharded_on_four_cpu_devices (a sweep sharded over 4 CPU devices) and test_speed_sweep_maps_single_speeds (the hybrid sweep)
@pytest.mark.slow
def test_hybrid_sweep_sharded_over_four_cpu_devices_matches_one_device(setup):
    """With several devices a hybrid sweep runs one row of speeds per device (each row one
    speed after the other): on 4 CPU devices (a separate process), 6 speeds (padded to 8) give
    the one-device sweep's dynamic factors, TE RMS and result codes to 1e-10. The one-device
    sweep is this process's (the module's settings ``RUN``, one speed per call: the program of
    the module's other runs), so that the other process compiles only the sharded program."""
    script = textwrap.dedent(f"""
        import json
        import jax, numpy as np
        jax.config.update("jax_enable_x64", True)
        import fem_prep
        import jaxgear as jg
        from jaxgear import io as jio
        from jaxgear.dynamics import Newmark, SteadyState, dynamic_model, speed_sweep
        from jaxgear.dynamics import Batching
        from jaxgear.io import static_scene
        case = jio.load_case({str(DATA / "hybrid-test-case.toml")!r}).replace(
            contact_geometry=jg.TheoreticalPath())  # as the module's setup: the theoretical path
        body = fem_prep.condensed({str(DATA / "hybrid-test-wheel.toml")!r})
        model = dynamic_model(static_scene(case, bodies=(None, body))[0], case.modifications,
                              case.torque)
        kw = dict(integrator=Newmark(16), window=SteadyState(3, 1))
        speeds = np.linspace(300.0, 1800.0, 6)
        a = speed_sweep(model, speeds, batching=Batching(shard=True), **kw).results
        assert len(jax.local_devices()) == 4
        print(json.dumps({{k: np.asarray(getattr(a, k)).tolist()
                          for k in ("dynamic_factor", "te_rms", "result")}}))
    """)
    a = json.loads(run_on_cpu_devices(script, timeout=900).strip().splitlines()[-1])
    case, scene = setup
    speeds = np.linspace(300.0, 1800.0, 6)
    b = _sweep(
        scene, case.modifications, case.torque, speeds, batching=Batching(chunk_size=1), **RUN
    )
    np.testing.assert_allclose(a["dynamic_factor"], np.asarray(b.dynamic_factor), rtol=1e-10)
    np.testing.assert_allclose(a["te_rms"], np.asarray(b.te_rms), rtol=1e-10)
    assert a["result"] == list(np.asarray(b.result)) == [0] * 6


def test_rotating_frame_leaves_the_drive_rotations_neutral(setup):
    """A rigid turn of a member about its axis must cost nothing in its turning frame: the
    scene's spin stiffness (the body's spin softening and stress stiffening with the shaft's
    share of the bore-band reactions, the teeth's spin softening on the radial direction, the
    shaft's) maps the null space of K (the two drive rotations) to zero. fem_prep's K_sigma
    alone gives the rigid turn of this wheel a stiffness of several % of its spin softening
    (tests/test_fem_prep_rotating.py), and the teeth's spin softening on both in-plane
    directions would add −Σ m r² per unit speed²."""
    scene = setup[1]
    S = np.asarray(scene.structure.spin_stiffness)
    null = drive_rotations(scene)
    assert np.linalg.norm(S @ null) <= 1e-10 * np.linalg.norm(S, 2)
    # the null space holds the wheel's turn: its rim nodes' Coriolis force (centripetal) is there
    gy, M = np.asarray(scene.structure.gyroscopic), np.asarray(scene.structure.M)
    ratio = np.linalg.norm(gy @ null, axis=0) / np.linalg.norm(M @ null, axis=0)
    assert ratio.max() > 0.1


def _rigidified_pair(case):
    """The test wheel 1000× stiffer on the same shafts as a hybrid scene, and the rigid-node
    lumped scene given its mass and inertias (uniform mesh stiffness in both)."""
    return rigidified_pair(case, 1, DATA / "hybrid-test-wheel.toml", 1000.0)


def _rigidified_vs_lumped(case, speeds, rotating_frame=False):
    """Dynamic factors of the two with Rayleigh damping (seed D1), and the lumped model's
    minimum mesh force / F_s per speed."""
    d1 = Damping("rayleigh", alpha=25.0, beta=2.5e-6)
    sw, refs, model = rigidified_runs(
        _rigidified_pair(case), speeds, d1, rotating_frame=rotating_frame
    )
    lumped_df = np.array([float(r.dynamic_factor) for r in refs])
    lumped_min = np.array([float(r.mesh_force.min() / model.static_force) for r in refs])
    return np.asarray(sw.dynamic_factor), lumped_df, lumped_min


# default tier: tests/test_hybrid_train.py::test_rigidified_idler_train_dynamics_equal_the_rigid_node_train (a rigidified body's hybrid Newmark against the rigid-node lumped one, at 1000 rad/s)
@pytest.mark.slow
def test_rigidified_body_reproduces_the_lumped_dynamic_factor(setup):
    """A body 1000× stiffer on the same shafts, against the rigid-node lumped
    model given its mass and inertias: the dynamic factor after 60 mesh periods agrees within
    1 % at 150, 800 and 2100 rad/s (measured 0.01 %, 0.04 %, 0.07 %; with tooth separation down
    to 0.52 F_s at 2100). The flank gaps are measured from one time-constant reference in both.
    With the turning frames' inertia (Coriolis, spin softening, stress stiffening) the body is
    a rigid rotor seen from its own frame, exactly the lumped model: within 0.2 % at 2100
    rad/s (measured 0.04 %; 2.9 % before the bore-band reactions' load stiffness went to the
    shaft, when the drive rotation had a spurious spin stiffness)."""
    speeds = [150.0, 800.0, 2100.0]
    hyb, lum, _ = _rigidified_vs_lumped(setup[0], speeds)
    np.testing.assert_allclose(hyb, lum, rtol=1e-2)
    hyb_r, lum_r, _ = _rigidified_vs_lumped(setup[0], speeds[2:], rotating_frame=True)
    np.testing.assert_allclose(hyb_r, lum_r, rtol=2e-3)


@pytest.mark.slow
@pytest.mark.parametrize("rotating_frame", [False, True])
def test_rigidified_body_reproduces_the_lumped_sweep(setup, rotating_frame):
    """The same over 18 speeds from 150 to 3000 rad/s: all within 1 % (measured ≤ 0.54 %, at
    1200 rad/s) and, with the turning frames' inertia, all within 0.2 % (measured ≤ 0.094 %):
    the hybrid model turns the body frame under the mesh, and only with the rotating frame's
    Coriolis and spin terms is a rigid body in its own frame the lumped model's rigid body."""
    speeds = np.r_[150.0, np.linspace(600.0, 3000.0, 17)]
    hyb, lum, _ = _rigidified_vs_lumped(setup[0], speeds, rotating_frame=rotating_frame)
    err = np.abs(hyb / lum - 1.0)
    assert np.all(err < (2e-3 if rotating_frame else 1e-2)), (speeds, err)


# default tier: tests/test_optimise_speed.py::test_load_centroid_optimum_matches_a_grid_scan_at_speed (the optimiser on the small hybrid case at 3000 rad/s against a grid scan in exact contact)
@pytest.mark.slow
def test_crowning_optimisation_on_the_hybrid_scene_at_speed(setup):
    """the optimiser runs on the hybrid scene at 3000 rad/s
    (centrifugal loads): with a 10 µm helix-slope deviation on the pinion, the crowning that
    minimises the maximum line load (gradient-based, smooth contact, then evaluated in exact
    contact) matches a 0.25 µm grid scan in exact contact within 1 %."""
    import optimise

    case, _ = setup
    mods = eqx.tree_at(
        lambda m: m.pinion.helix_slope_deviation, case.modifications, jnp.asarray(10e-6)
    )
    case = case.replace(modifications=mods)
    scene = static_scene(case)[0]
    problem = jio.case_problem(
        case, "crowning.depth", "max_line_load", scene=scene, speed=3000.0, positions_per_pitch=16
    )
    res = optimise.minimise(problem, np.array([0.5]), max_iterations=60, progress=False)
    sharp = eqx.tree_at(
        lambda p: (p.base.pinion.relief_blend, p.base.gear.relief_blend),
        problem,
        (jnp.asarray(0.0), jnp.asarray(0.0)),
    )
    best = float(sharp.value(jnp.asarray(res.x), jg.ExactContact()))
    depths = np.arange(0.0, 6.01, 0.25)
    grid = [
        float(
            sharp.value(
                jnp.asarray(problem.from_physical({"crowning.depth": d})), jg.ExactContact()
            )
        )
        for d in depths
    ]
    assert best <= min(grid) * 1.01
    assert 0.5 < problem.to_physical(res.x)["crowning.depth"] < 4.0  # interior optimum (≈ 2 µm)


def test_rim_waves_identify_nodal_diameters_and_direction():
    """A synthetic rim field of two travelling waves, 1 µm ND 3 towards +φ at 500 Hz and 0.3 µm
    ND 5 towards −φ at 1000 Hz: amplitudes, frequencies and directions recovered (forward =
    the body's rotation sense)."""
    from jaxgear.dynamics import rim_waves

    Z, S, dt = 30, 200, 1e-4
    phi = 2 * np.pi * np.arange(Z) / Z
    t = np.arange(S)[:, None] * dt
    u = 1e-6 * np.cos(3 * phi - 2 * np.pi * 500 * t) + 0.3e-6 * np.cos(
        5 * phi + 2 * np.pi * 1000 * t
    )
    # the band keeps only the 1000 Hz wave: diameter 3 then shows nothing above round-off
    wb = rim_waves(u, dt, band=(800.0, 2000.0))
    assert wb["amplitude"][5] == pytest.approx(0.3e-6, rel=1e-9) and wb["amplitude"][3] < 1e-20
    with pytest.raises(ValueError, match="band"):
        rim_waves(u, dt, band=(1e6, 2e6))
    for spin in (1.0, -1.0):
        w = rim_waves(u, dt, spin=spin)
        np.testing.assert_allclose(w["amplitude"][[3, 5]], [1e-6, 0.3e-6], rtol=1e-9)
        np.testing.assert_allclose(w["frequency_hz"][[3, 5]], [500.0, 1000.0])
        assert list(w["direction"][[3, 5]]) == [spin, -spin]
        assert np.all(w["amplitude"][[1, 2, 4, 6]] < 1e-20)


def test_modal_analysis_of_the_hybrid_scene_against_scipy(setup):
    """The one modal analysis (:func:`jaxgear.dynamics.modal_analysis`, Cholesky and a dense
    symmetric eigenproblem) on the condensed test wheel with a rank-one mesh stiffness k u uᵀ
    (u the TE vector): the 20 lowest frequencies and mesh-energy shares equal SciPy's
    generalized eigensolver (the CLI's former eigen-analysis) to 1e-9, and
    :func:`jaxgear.dynamics.nodal_diameter_modes` reads the same elastic frequencies."""
    import scipy.linalg as sla

    from jaxgear.dynamics import modal_analysis, nodal_diameter_modes

    _, scene = setup
    u = np.asarray(scene.te_vector(), dtype=float)
    Km = 1e8 * np.outer(u, u)
    K, M = np.asarray(scene.structure.K), np.asarray(scene.structure.M)
    lam, phi = sla.eigh(K + Km, M, subset_by_index=[0, 19])
    share = 1e8 * (u @ phi) ** 2 / np.maximum(lam, 1e-300)
    elastic = lam > 1e-9 * lam.max()  # the drive rotation
    modes = modal_analysis(scene, jnp.asarray(Km))
    assert list(np.asarray(modes.rigid)[:20]) == list(~elastic)
    f = np.asarray(modes.omega)[:20]
    np.testing.assert_allclose(f[elastic], np.sqrt(lam[elastic]), rtol=1e-9)
    np.testing.assert_allclose(
        np.asarray(modes.mesh_energy)[:20][elastic], share[elastic], atol=1e-9
    )
    nd = nodal_diameter_modes(scene, modes, n_modes=10)
    np.testing.assert_allclose(
        2 * np.pi * nd["frequency_hz"], np.sqrt(lam[elastic][:10]), rtol=1e-9
    )


def test_campbell_coincidences_by_hand():
    """Ω = ω/(h z) for the modes the mesh excites (share >= 5 %), up to 1.05 × the top speed,
    the largest shares first when ``n_modes`` is given; rigid modes (ω = 0) never count."""
    from jaxgear.dynamics import campbell_coincidences

    omega = [0.0, 100.0, 200.0, 300.0]
    share = [0.0, 0.5, 0.01, 0.2]
    got = campbell_coincidences(omega, share, 10, 15.0)
    assert [(c["mode"], c["harmonic"]) for c in got] == [(1, 1), (1, 2), (1, 3), (3, 2), (3, 3)]
    np.testing.assert_allclose(
        [c["speed_rad_s"] for c in got], [10.0, 5.0, 100 / 30, 15.0, 10.0], rtol=1e-15
    )
    assert got[3]["frequency_Hz"] == pytest.approx(300 / (2 * np.pi), rel=1e-15)
    assert got[3]["mesh_energy_share"] == 0.2
    one = campbell_coincidences(omega, share, 10, 15.0, n_modes=1)
    assert {c["mode"] for c in one} == {1}
    assert len(campbell_coincidences(omega, share, 10, harmonics=(1,), min_share=0.0)) == 3


def test_simulation_records_the_wheel_rim(setup):
    """A hybrid run records the wheel rim's radial and axial motion at every station and kept
    step (the settings of the module's other runs at 900 rad/s: one compiled program)."""
    case, scene = setup
    r = _simulate(scene, case.modifications, case.torque, 900.0, **RUN)
    Z = scene.members[1].rim_dofs.shape[0]
    assert r.rim_radial.shape == (16, Z) and r.rim_axial.shape == (16, Z)
    assert np.all(np.isfinite(np.asarray(r.rim_radial)))
    assert float(jnp.max(jnp.abs(r.rim_radial))) > 0  # the rim moves under the mesh load


def test_jaxgear_sweep_on_a_hybrid_case(tmp_path, fem_prep_cache):
    """`jaxgear sweep` on a case with a condensed wheel: the hybrid Newmark per speed (the
    case's composite damping), sweep.json with the dynamic factors (global and per tooth), the
    modes of the mesh-averaged system, the (3.9) nodal-diameter resonances of the wheel and its
    rim waves per speed, both plots, and a VTU time series at one speed."""
    import xml.etree.ElementTree as ET

    import meshio

    from jaxgear.cli import main

    out = tmp_path / "sweep"
    argv = "sweep CASE --speeds 300:900:3 --periods 4 --keep-periods 2 --steps-per-period 16"
    argv = argv.split() + ["--out", str(out), "--quiet", "--vtu-speed", "600"]
    code = main([str(DATA / "hybrid-test-case.toml") if a == "CASE" else a for a in argv])
    assert code == 0
    s = json.loads((out / "sweep.json").read_text())
    assert s["model"] == "hybrid" and len(s["dynamic_factor"]) == 3
    assert s["damping"] == "composite"
    assert all(1.0 < v < 5.0 for v in s["dynamic_factor"]) and s["result"] == [0, 0, 0]
    assert all(0.9 < v < 5.0 for v in s["dynamic_factor_tooth"]) and s["contact_loss"] == [0] * 3
    f = [v for v in s["natural_frequencies_Hz"] if v]  # the drive rotation is reported as 0
    assert 1000 < f[0] < 1e5 and s["critical_speeds"] is not None
    # the modes at speed are reported (the run leaves the rotating-frame terms out, so the
    # critical speeds use the modes at rest)
    assert s["campbell_at_speed"] is False and s["modes_at_speed_error"] < 1e-3
    assert len(s["natural_frequencies_at_speed_Hz"]) == len(s["campbell_speeds_rad_s"])
    assert s["natural_frequencies_at_speed_Hz"][0] == pytest.approx(
        s["natural_frequencies_Hz"], rel=1e-9
    )
    # (3.9): every listed resonance is the wheel speed 2π f/(Z ± n) in pinion terms
    for r in s["nodal_diameter_resonances"]:
        sign = 1 if r["direction"] == "backward" else -1
        order = r["harmonic"] * 30 + sign * r["nodal_diameter"]
        assert r["order"] == order
        w2 = 2 * np.pi * r["frequency_hz"] / order
        assert r["pinion_speed_rad_s"] == pytest.approx(w2 * 30 / 20, rel=1e-12)
    assert s["flexible_gears"] == ["gear"] and list(s["rim_waves"]) == ["gear"]
    assert all(w["axial"]["nodal_diameter"] >= 1 for w in s["rim_waves"]["gear"])
    assert (out / "dynamic_factor.png").stat().st_size > 0 and (
        out / "campbell.png"
    ).stat().st_size > 0
    files = s["vtu_series"]["files"]
    assert len(files) == 2 * 16 + 1  # 2 kept periods of 16 steps, and the collection
    pvd = ET.parse(out / "vtu" / "body_gear.pvd").getroot()
    frames = [d.get("file") for d in pvd.iter("DataSet")]
    assert len(frames) == 32
    m = meshio.read(out / "vtu" / frames[-1])
    assert np.abs(m.point_data["displacement_m"]).max() > 0


def test_rotating_frame_needs_a_condensed_body(tmp_path):
    """On a rigid case ``[scene.integration] rotating_frame = true`` is a one-line error naming
    it."""
    rigid = (DATA / "hybrid-test-case.toml").read_text().split("[scene]")[0]
    bad = tmp_path / "rigid.toml"
    bad.write_text(rigid + "[scene]\n[scene.integration]\nrotating_frame = true\n")
    with pytest.raises(ValueError, match=r"rotating_frame.*condensed body"):
        jio.load_case(bad)


@pytest.mark.slow
def test_jaxgear_sweep_rotating_frame_from_the_case_file(tmp_path, setup, no_figures):
    """``[scene.integration] rotating_frame = true`` reaches the hybrid Newmark: `jaxgear sweep`
    gives the dynamic factors of ``_sweep(..., rotating_frame=True)`` with the same
    settings (and not those without it), and records the flag."""

    from jaxgear.cli import main
    from jaxgear.io import spec_damping

    text = (DATA / "hybrid-test-case.toml").read_text()
    case_file = tmp_path / "hybrid-test-case.toml"
    case_file.write_text(
        text.replace(
            "[scene.gear_body]",
            "[scene.integration]\nrotating_frame = true\n\n[scene.gear_body]",
            1,
        )
    )
    (tmp_path / "hybrid-test-wheel.toml").write_text((DATA / "hybrid-test-wheel.toml").read_text())
    out = tmp_path / "sweep"
    # 4 periods, 2 kept: the window of test_jaxgear_sweep_on_a_hybrid_case's sweep, whose
    # compiled program the run without the flag below is
    argv = ["sweep", str(case_file), "--speeds", "1500:2100:2", "--periods", "4"]
    argv += ["--keep-periods", "2", "--steps-per-period", "16", "--out", str(out), "--quiet"]
    assert main(argv) == 0
    s = json.loads((out / "sweep.json").read_text())
    assert s["rotating_frame"] is True and s["result"] == [0, 0]
    # the critical speeds follow the modes at speed: each lies on its mode's curve
    assert s["campbell_at_speed"] is True
    grid = np.asarray(s["campbell_speeds_rad_s"])
    curves = np.asarray(s["natural_frequencies_at_speed_Hz"])
    for c in s["critical_speeds"]:
        f = np.interp(c["speed_rad_s"], grid, curves[:, c["mode"]])
        assert c["frequency_Hz"] == pytest.approx(f, rel=1e-9)
    case = jio.load_case(case_file)
    scene = static_scene(case)[0]
    kw = dict(integrator=Newmark(16), window=SteadyState(4, 2), damping=spec_damping(case.scene))
    kw.update(contact=case.contact_law(case.scene.contact))
    # the command's other settings too (a hybrid sweep: one speed per call, the Hertzian
    # pressure tracked): the rotating run below is the command's compiled sweep program
    hertz = HertzPressure(tuple(case.pairs), case.youngs_modulus, case.poisson_ratio)
    kw.update(batching=Batching(chunk_size=1), outputs=Outputs(pressure=hertz))
    speeds = [1500.0, 2100.0]
    on = _sweep(scene, case.modifications, case.torque, speeds, rotating_frame=True, **kw)
    off = _sweep(scene, case.modifications, case.torque, speeds, **kw)
    fm = [
        np.asarray(r.mesh_force).max() / float(np.asarray(r.static_force).reshape(-1)[0])
        for r in (on, off)
    ]
    np.testing.assert_allclose(
        s["dynamic_factor"],
        np.asarray(on.mesh_force).max(axis=1) / float(np.asarray(on.static_force).reshape(-1)[0]),
        rtol=1e-9,
    )
    assert abs(fm[0] / fm[1] - 1.0) > 1e-6  # the flag changes the response


def test_free_vibration_conserves_energy(setup):
    """undamped, the mesh held at one position and the contact held (an
    initial velocity about the loaded equilibrium carrying 1 % of the static mesh strain
    energy), the cell-space Newmark conserves the vibration energy ½ẊᵀMẊ + ½ΔXᵀ(K + K_c)ΔX:
    its drift per mesh period stays below 1e-10 (measured 7e-13) over 20 periods of the
    800 rad/s time step, while the mesh force swings by 2 % of its static value."""
    from jaxgear.dynamics import hybrid_free_vibration

    case, scene = setup
    n = scene.structure.K.shape[0]
    v = np.random.default_rng(0).standard_normal(n)
    M = np.asarray(scene.structure.M)
    theta = 0.3 * float(scene.mesh.mesh_period_angle)
    spp, speed, periods = 16, 800.0, 20
    dt = float(scene.mesh.mesh_period_angle) / speed / spp
    fs = float(scene.mesh.normal_load(case.torque))
    e_static = fs**2 / (2 * 2e8)  # F_n²/(2 k̄), k̄ ≈ 2e8 N/m for this pair
    v *= np.sqrt(2e-2 * e_static / (v @ M @ v))
    fv = hybrid_free_vibration(scene, case.modifications, case.torque, theta, v, dt, spp * periods)
    assert int(fv.result) == 0 and bool(fv.contact_held)
    E = np.asarray(fv.energy)
    per_period = np.abs(np.diff(E[::spp])) / E[0]
    assert per_period.max() < 1e-10
    assert np.ptp(np.asarray(fv.mesh_force)) > 1e-2 * fs


def test_free_vibration_flags_contact_loss(setup):
    """The check knows when it does not apply: the rim set moving at 50 m/s loses contact
    (contact_held False), where the system is no longer the linear one. The run's step count
    is the conservation test's (its compiled program: the step count fixes the program)."""
    from jaxgear.dynamics import hybrid_free_vibration

    case, scene = setup
    n = scene.structure.K.shape[0]
    v = np.zeros(n)
    v[np.asarray(scene.members[1].rim_dofs)[:, :, 0].ravel()] = 50.0  # rim stations, 50 m/s in x
    dt = float(scene.mesh.mesh_period_angle) / 800.0 / 16
    theta = 0.3 * float(scene.mesh.mesh_period_angle)
    fv = hybrid_free_vibration(scene, case.modifications, case.torque, theta, v, dt, 16 * 20)
    assert not bool(fv.contact_held)


# default tier: tests/test_hybrid_train.py::test_rigidified_idler_train_dynamics_equal_the_rigid_node_train (a rigidified body's hybrid Newmark against the rigid-node lumped one), tests/test_hybrid_composite.py::test_composite_equals_the_mesh_following_reference (the composite damping in the hybrid Newmark) and test_low_speed_tooth_factor_states_and_bearing_forces (the per-tooth dynamic factor)
@pytest.mark.slow
def test_rigidified_body_composite_damping_and_tooth_factor(setup):
    """Composite modal damping (seed (2.36): ξ_i = 0.07 e_i + 0.01 (1 − e_i)) in the hybrid
    Newmark against the lumped model's, on the rigidified body at 800 and 2100 rad/s over one
    wheel revolution (30 mesh periods, the last 2 kept): dynamic factor within 1 % (measured
    −0.40 %, +0.71 %; over 60 periods −0.43 %, +0.89 %) and per-tooth dynamic factor within
    2.5 % (measured −1.99 %, −0.55 %; over 60 periods −1.97 %, −0.50 %). The two composites
    are not the same model: the lumped one takes the modes with the mesh spring in its fixed
    direction; the hybrid one, whose gear shaft sits in the turning body frame, the modes with
    the mesh stiffness averaged round the revolution (isotropic there: the gear's mesh modes
    move, 3070 → 3229 Hz, 10238 → 9518 Hz), so that its mesh share can follow the mesh
    (tests/test_hybrid_composite.py). On the modes of the first period the two agreed within
    0.25 %, but the damping then turned with the wheel (the dynamic factor of the flexible
    wheel at 900 rad/s swung by 6 % per revolution)."""
    pair = _rigidified_pair(setup[0])
    sw, refs, _ = rigidified_runs(pair, [800.0, 2100.0], Damping(), periods=30)
    for i, ref in enumerate(refs):
        assert float(sw.dynamic_factor[i]) == pytest.approx(float(ref.dynamic_factor), rel=1e-2)
        assert float(sw.dynamic_factor_tooth[i]) == pytest.approx(
            float(ref.dynamic_factor_tooth), rel=2.5e-2
        )


def test_low_speed_tooth_factor_states_and_bearing_forces(setup, low_speed):
    """At 5 rad/s the largest tooth-pair force is the quasi-static one (per-tooth dynamic factor
    1 within 0.5 %), no contact is lost, the recorded states end at the final state, and the
    bearing forces balance the mesh force on each shaft (their maxima the static ones)."""
    scene, r = setup[1], low_speed
    assert float(r.dynamic_factor_tooth) == pytest.approx(1.0, abs=5e-3)
    assert float(r.contact_loss) == 0.0
    assert r.states.shape == (16, scene.structure.K.shape[0])
    # each shaft's bearings carry the mesh force: the driving pinion pushes the gear along the
    # line of action, the force on the gear is P n (n_xy = cos β_b t in the plane), and the
    # bearing forces k u of a shaft sum to the in-plane load it carries (the centrifugal loads of
    # the full ring of rim stations cancel); quasi-static at 5 rad/s, so within 0.5 % of F_s
    n_xy = np.asarray(scene.meshes[0].normal)[:2]
    names = scene.reaction_names
    for shaft, sign in (("pinion", -1.0), ("gear", 1.0)):
        xy = [
            [i for i, nm in enumerate(names) if nm.startswith(shaft) and nm.endswith(c)]
            for c in ("Fx", "Fy")
        ]
        for forces, mesh_force in (
            (np.asarray(r.bearing_force), np.asarray(r.mesh_force)),
            (np.asarray(scene.bearing_forces(r.theta, r.states)), np.asarray(r.mesh_force)),
        ):
            total = np.stack([forces[:, xy[0]].sum(axis=1), forces[:, xy[1]].sum(axis=1)], 1)
            np.testing.assert_allclose(
                total,
                sign * mesh_force[:, None] * n_xy[None, :],
                atol=5e-3 * float(r.static_force),
            )
    assert r.bearing_force_static.shape == r.bearing_force_max.shape == (len(names),)
    np.testing.assert_allclose(
        np.asarray(r.bearing_force_max),
        np.asarray(r.bearing_force_static),
        atol=5e-3 * float(r.static_force),
    )
    np.testing.assert_array_equal(np.asarray(r.states[-1]), np.asarray(r.final_state[0]))
    np.testing.assert_allclose(
        np.asarray(r.line_force).sum(axis=1), np.asarray(r.mesh_force), rtol=1e-12
    )


@pytest.mark.slow
def test_nodal_diameter_resonances_appear_at_the_predicted_speeds(fem_prep_cache):
    """(seed (3.9), Tab. III-11): on the helical test pair the wheel's
    2-nodal-diameter web modes of the assembled structure (6685 and 7033 Hz, split by the
    mesh) predict a backward resonance at order Z + 2 = 32 (pinion 1969–2072 rad/s) and a
    forward one at Z − 2 = 28 (2250–2367 rad/s). The hybrid sweep (25 rad/s steps, one wheel
    turn kept) finds the ND-2 axial rim wave of order 32 peaking at 2000 rad/s and travelling
    backward, and that of order 28 peaking at 2300 rad/s travelling forward, each within the
    predicted span ± one step and at least 3 times its level at 1850 rad/s (measured 5.0×,
    17×). docs/bench/nd_resonance.json (examples/nodal_diameter_resonance.py) holds the same."""

    ex = load_example("nodal_diameter_resonance")
    res = ex.compute()
    assert all(r == 0 for r in res["result"])
    sp = np.asarray(res["speeds_rad_s"])
    step = sp[1] - sp[0]
    for name, sign in (("backward", -1), ("forward", +1)):
        pred = [p["pinion_speed_rad_s"] for p in res["predicted"] if p["direction"] == name]
        assert len(pred) == 2
        amp = np.array([r["amplitude_m"] for r in res["response"][name]])
        k = int(np.argmax(amp))
        assert min(pred) - step <= sp[k] <= max(pred) + step, (name, sp[k], pred)
        assert res["response"][name][k]["direction"] == sign
        assert amp[k] > 3 * amp[0]
    docs = json.loads(
        (pathlib.Path(__file__).parents[1] / "docs" / "bench" / "nd_resonance.json").read_text()
    )
    np.testing.assert_allclose(
        [r["amplitude_m"] for r in docs["response"]["forward"]],
        [r["amplitude_m"] for r in res["response"]["forward"]],
        rtol=1e-3,
    )


def test_failures_use_the_one_result_enumeration(setup, caplog):
    """The hybrid path reports with the lumped path's :class:`jaxgear.DynamicsResult` codes and,
    as the lumped one, raises with ``throw`` (a sweep reports; one simulation raises by
    default). One Newton step from the exact solution does not solve a smooth contact whose
    ramp (50 µm) is wider than the deflection, and does solve one of a 10 nm ramp (the width is
    data: one compiled program for both). The energy check (code 3) bounds the mesh force by
    ``blowup`` F_s: a bound of half the static force stops a converged run (the bound is data:
    the converged run's program, nothing compiled again)."""
    case, scene = setup
    kw = {
        "integrator": Newmark(16),
        "window": SteadyState(2, 1),
        "contact": jg.SmoothContact(5e-5, max_iterations=1),
    }
    sw = _sweep(scene, case.modifications, case.torque, [900.0], **kw)
    assert int(sw.result[0]) == jg.DynamicsResult.contact_not_converged == 1
    # the same program (one Newton step) on a narrow ramp: the contact loop converges
    ok_kw = {**kw, "contact": jg.SmoothContact(1e-8, max_iterations=1)}
    ok = _sweep(scene, case.modifications, case.torque, [900.0], **ok_kw)
    assert int(ok.result[0]) == jg.DynamicsResult.successful
    message = "contact loop did not converge"
    with pytest.raises(eqx.EquinoxRuntimeError, match=message):
        _sweep(scene, case.modifications, case.torque, [900.0], throw=True, **kw)
    with pytest.raises(eqx.EquinoxRuntimeError, match=message):
        _simulate(scene, case.modifications, case.torque, 900.0, **kw)
    r = _simulate(scene, case.modifications, case.torque, 900.0, throw=False, **kw)
    assert int(r.result) == 1
    # the energy check (code 3) of the lumped models: a bound below the static mesh force
    # (blowup 0.5: mesh force > F_s / 2 at the first step) stops a converged run; the bound is
    # an argument of the program of ``r`` above (JAX logs no new compilation of the sweep)
    caplog.clear()
    with jax.log_compiles(True), caplog.at_level(logging.WARNING):
        low = _simulate(
            scene,
            case.modifications,
            case.torque,
            900.0,
            throw=False,
            outputs=Outputs(blowup=0.5),
            **ok_kw,
        )
    assert int(low.result) == jg.DynamicsResult.blow_up == 3
    assert not [m for m in caplog.messages if m.startswith("Compiling jit(sweep)")]
    with pytest.raises(ValueError, match=r"blowup = 0\.0: allowed > 0"):
        _simulate(
            scene, case.modifications, case.torque, 900.0, outputs=Outputs(blowup=0.0), **ok_kw
        )
    # the window-overflow code no longer shares 3 (energy blow-up) with the lumped path
    codes = {c.name: int(c) for c in jg.DynamicsResult}
    assert codes["window_overflow"] not in (codes["blow_up"], codes["non_finite"])
    assert len(set(codes.values())) == len(codes)


def test_a_run_that_blows_up_away_from_the_mesh_is_flagged_by_the_energy_check(setup):
    """Negative mass-proportional damping (Rayleigh α = −20000 /s) makes every mode of the
    hybrid scene grow: the gears separate (no mesh force in the kept period: the mesh-force
    bound never trips), while the kinetic energy, checked once per mesh period in the cell space,
    leaves its bound: the loud blow-up code, not a silent result. (Measured when the check was
    moved to the period ends: with the energy check switched off the same run returns 0.)"""
    case, scene = setup
    r = _sweep(
        scene,
        case.modifications,
        case.torque,
        [900.0],
        damping=Damping("rayleigh", alpha=-2e4, beta=0.0),
        batching=Batching(chunk_size=1),
        **RUN,  # the damping is data: the program of the module's other runs
    )
    assert int(r.result[0]) == jg.DynamicsResult.blow_up
    assert float(r.dynamic_factor[0]) == 0.0  # the mesh force did not flag it
