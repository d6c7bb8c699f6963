"""A gear train as a scene: several meshes on one structure, each at its own mesh angle.

An idler train (input → idler → output) on a torsional structure is statically determinate: each
mesh carries the same normal force and its transmission error is that of its pair alone at the
same force and at the mesh's own angle θ_k = ratio_k θ + phase_k (the idler turns at z_in/z_idler
of the input). The reference solves each pair on its own (:class:`jaxgear.scenes.TorsionalPair`).
"""

import functools
import itertools
import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.scenes as js
from fem_prep.tooth_form import generate_tooth
from jaxgear.scenes import (
    AssembledScene,
    GearMesh,
    Structure,
    TorsionalMember,
    disc_inertia,
    line_of_action,
    pair_mesh,
    torsional_train,
    train_phases,
)

jax.config.update("jax_enable_x64", True)

MODULE = 2e-3
ALPHA = math.radians(20.0)
TEETH = (23, 37, 29)  # input, idler, output
FACE = 15e-3
SLICES = 4
TORQUE = 120.0  # N·m on the input
K_OUT = 1e5  # N·m/rad: the output shaft to the fixed load


def _pair(z_driving: int, z_driven: int) -> jg.GearPair:
    return jg.GearPair(
        jg.Member(z_driving, face_width=FACE), jg.Member(z_driven, face_width=FACE), MODULE, ALPHA
    )


@functools.cache
def _mesh(z_driving: int, z_driven: int) -> jg.MeshModel:
    pair = _pair(z_driving, z_driven)
    s, k = jg.stiffness_table(pair, jg.Weber())
    return jg.MeshModel.from_pair(pair, s, k, SLICES)


def _te_vector(mesh: jg.MeshModel, driving: int, driven: int, n: int):
    """u·X = cos β_b (r_b1 φ_driving − r_b2 φ_driven), each rotation positive in its gear's
    direction of motion."""
    cb = jnp.cos(mesh.base_helix_angle)
    eye = jnp.eye(n)
    return cb * mesh.base_radius_pinion * eye[driving] - cb * mesh.base_radius_gear * eye[driven]


def _idler_train(mesh_a, mesh_b, phase_b):
    """Three rotations (input, idler, output), the output held by a shaft to a fixed load; mesh A
    input → idler at the input angle, mesh B idler → output at the idler's angle
    (z_in/z_idler) θ + ``phase_b``."""
    n = 3
    zeros = jnp.zeros((n, n))
    K = zeros.at[2, 2].set(K_OUT)
    structure = Structure(
        K=K,
        M=jnp.eye(n),
        parts_K=None,
        C_bearing=jnp.zeros((0, 0)),
        reaction=jnp.zeros((0, n)),
        gyroscopic=zeros,
        spin_stiffness=zeros,
        f_centrifugal=jnp.zeros(n),
        part_names=("load_shaft",),
        reaction_names=(),
        reaction_member=(),
        nodes=(("pinion", 0), ("idler", 1), ("gear", 2), ("input", 0), ("output", 2)),
        node_dofs=1,
    )
    origin = jnp.zeros(3)  # a torsional mesh has no place in space
    meshes = tuple(
        GearMesh(
            plane,
            origin,
            origin,
            origin,
            0.0,
            _te_vector(plane, a, b, n),
            gears=(a, b),
            ratio=ratio,
            phase=phase,
        )
        for plane, (a, b), ratio, phase in (
            (mesh_a, (0, 1), 1.0, 0.0),
            (mesh_b, (1, 2), TEETH[0] / TEETH[1], phase_b),
        )
    )
    members = tuple(TorsionalMember(d) for d in range(n))
    return AssembledScene(structure, meshes, members, jnp.eye(n)[0])


# default tier: tests/test_train.py::test_idler_train_meshes_equal_their_pairs_at_their_own_angles[exact] (same claim with the exact law; [smooth] is slow)
@pytest.mark.parametrize("contact", ["exact", pytest.param("smooth", marks=pytest.mark.slow)])
def test_idler_train_meshes_equal_their_pairs_at_their_own_angles(contact):
    """Each mesh of the idler train has its pair's TE, mesh stiffness and line loads at the
    mesh's own angle and the force the train passes on (the idler's torque T r_b,idler/r_b,in),
    to 1e-9; the output shaft carries T z_out/z_in."""
    mesh_a, mesh_b = _mesh(TEETH[0], TEETH[1]), _mesh(TEETH[1], TEETH[2])
    phase_b = 0.37 * float(mesh_b.mesh_period_angle)
    train = _idler_train(mesh_a, mesh_b, phase_b)
    tip = jg.MemberModification(tip_relief_depth=12e-6, tip_relief_extent=0.3)
    mods = jg.Modifications.symmetric(tip)
    law = jg.ExactContact() if contact == "exact" else jg.SmoothContact(2e-7)
    theta = jg.mesh_positions(mesh_a, 12)
    res = jg.quasi_static(train, mods, TORQUE, theta, contact=law)
    assert len(res.meshes) == 2

    t_idler = TORQUE * float(mesh_a.base_radius_gear) / float(mesh_a.base_radius_pinion)
    ratio = TEETH[0] / TEETH[1]
    refs = (
        jg.quasi_static(js.TorsionalPair(mesh_a, K_OUT), mods, TORQUE, theta, contact=law),
        jg.quasi_static(
            js.TorsionalPair(mesh_b, K_OUT), mods, t_idler, ratio * theta + phase_b, contact=law
        ),
    )
    for got, ref in zip(res.meshes, refs, strict=True):
        te = np.asarray(ref.transmission_error)
        assert np.ptp(te) > 0.05 * np.mean(np.abs(te))  # the TE varies: the angles matter
        np.testing.assert_allclose(got.transmission_error, te, rtol=1e-9)
        np.testing.assert_allclose(got.mesh_stiffness, ref.mesh_stiffness, rtol=1e-9)
        scale = float(np.max(np.asarray(ref.line_load)))
        np.testing.assert_allclose(got.line_load, ref.line_load, rtol=0, atol=1e-9 * scale)
    # the output shaft carries the output torque T z_out/z_in
    np.testing.assert_allclose(
        np.asarray(res.x[:, 2]) * K_OUT,
        TORQUE * float(mesh_b.base_radius_gear) / float(mesh_a.base_radius_pinion),
        rtol=1e-9,
    )


def _flank_offset(point, centre, spin, tooth_angle, teeth, form):
    """(signed angular offset δ of ``point`` from the nearest tooth centre line, in the gear's
    direction of motion; the generated tooth's half-width at the point's radius, from its
    involute), both in rad."""
    d = np.asarray(point[:2]) - np.asarray(centre[:2])
    r = math.hypot(d[0], d[1])
    a = spin * math.atan2(d[1], d[0])
    pitch = 2 * math.pi / teeth
    delta = (a - tooth_angle + 0.5 * pitch) % pitch - 0.5 * pitch
    right = (form.segments == 2) & (form.outline[:, 0] > 0)
    xy = form.outline[right]
    radius = np.hypot(xy[:, 0], xy[:, 1])
    order = np.argsort(radius)
    half = np.arctan2(xy[order, 0], xy[order, 1])
    return delta, float(np.interp(r, radius[order], half)), r


def test_train_phases_put_every_contact_point_on_the_generated_flanks():
    """Mesh phasing (train_phases) checked by geometry: an idler train laid out in the plane
    (input at the origin turning about +z, the idler at 0°, the output at 150° from the idler),
    each gear's teeth placed by the phases; at several scene angles every contact point of both
    meshes lies on the flanks of the teeth generated by the rack (fem_prep.generate_tooth), on
    the driving gear's leading flank and the driven gear's trailing flank, to 1e-9 m; the idler
    is driven on one flank and drives on the other. A phase off by a tenth of a pitch misses."""
    pairs = (_pair(TEETH[0], TEETH[1]), _pair(TEETH[1], TEETH[2]))
    spins = (1.0, -1.0, 1.0)
    gears = ((0, 1), (1, 2))
    line_a = line_of_action(pairs[0])
    line_b = line_of_action(
        pairs[1], driving_centre=line_a["centres"][1], angle=math.radians(150.0), spin=-1.0
    )
    phases, tooth = train_phases(pairs, (line_a, line_b), gears, spins, 3)
    ratios = (1.0, TEETH[0] / TEETH[1])  # each mesh's driving gear per unit input angle
    gear_ratio = (1.0, TEETH[0] / TEETH[1], TEETH[0] / TEETH[2])
    centres = (line_a["centres"][0], line_a["centres"][1], line_b["centres"][1])
    forms = [
        generate_tooth(jg.tooth_geometry(pairs[0], 0), n_involute=1600),
        generate_tooth(jg.tooth_geometry(pairs[0], 1), n_involute=1600),
        generate_tooth(jg.tooth_geometry(pairs[1], 1), n_involute=1600),
    ]

    @eqx.filter_jit
    def contact_points(plane, mesh, angle):  # one compiled program per mesh, not op by op
        cells = plane.cells(angle)
        return cells.mask, mesh.points(cells)

    def misses(phase_error):
        worst = 0.0
        for k, (line, (g, h)) in enumerate(zip((line_a, line_b), gears, strict=True)):
            plane = _mesh(*(TEETH[i] for i in (g, h)))
            mesh = pair_mesh(plane, line, jnp.zeros(3))
            for theta in (0.0, 0.031, 0.117, 0.25):
                angle = ratios[k] * theta + phases[k] + (phase_error if k else 0.0)
                mask, points = contact_points(plane, mesh, jnp.asarray(angle))
                points = np.asarray(points)[np.asarray(mask)]
                assert points.shape[0] > 0
                for gear, side in ((g, 1.0), (h, -1.0)):
                    c = tooth[gear] + gear_ratio[gear] * theta
                    for p in points:
                        delta, half, r = _flank_offset(
                            p, centres[gear], spins[gear], c, TEETH[gear], forms[gear]
                        )
                        # the leading flank (driving, side +1) ahead of the centre line
                        worst = max(worst, abs(delta - side * half) * r)
        return worst

    assert misses(0.0) < 1e-9
    assert misses(0.1 * 2 * math.pi / TEETH[1]) > 1e-5


def _rk4_reference(train, planes, model, torque, speed, periods, steps):
    """The train written out independently: rotations X (n,), linear mesh springs (no contact
    loss: every cell on the flanks is loaded), M Ẍ + C Ẋ + Σ_k k_k(θ_k) u_k u_kᵀ X = T f, with
    k_k the mesh stiffness Σ k l of mesh k's cells at its own angle θ_k = ratio_k Ω t + phase_k
    and C the model's damping matrix; classical RK4 from rest, ``steps`` per mesh period. The
    system is affine in z = (X, Ẋ), ż = L(t) z + g, so each RK4 step (stages at t, t + h/2,
    t + h) is an affine map z ↦ S_i z + s_i: the maps are built for every step at once (the
    stage formulas below, on matrices) and applied in turn."""
    M = np.asarray(train.structure.M)
    minv = 1.0 / np.diag(M)
    C = np.asarray(model.damping)
    F = torque * np.asarray(train.f_torque)
    U = np.asarray(train.te_vectors())
    period = float(planes[0].mesh_period_angle) / speed
    h = period / steps
    t = np.arange(periods * steps) * h

    def stiffness(times):  # (len, n, n)
        out = 0.0
        for mesh, u in zip(train.meshes, U, strict=True):
            angles = jnp.asarray(float(mesh.ratio) * speed * times + float(mesh.phase))
            c = jax.jit(jax.vmap(mesh.base_plane.cells))(angles)  # one program, not op by op
            k = np.asarray(jnp.sum(jnp.where(c.mask, c.stiffness * c.length, 0.0), axis=(1, 2)))
            out = out + k[:, None, None] * np.outer(u, u)[None]
        return out

    n = M.shape[0]
    K = stiffness(np.concatenate([t, t + h / 2, t + h])).reshape(3, t.size, n, n)

    def affine(Kt):  # (len, 2n + 1, 2n + 1): [[0, I, 0], [-M⁻¹K, -M⁻¹C, M⁻¹F], [0, 0, 0]]
        A = np.zeros((Kt.shape[0], 2 * n + 1, 2 * n + 1))
        A[:, :n, n : 2 * n] = np.eye(n)
        A[:, n : 2 * n, :n] = -minv[:, None] * Kt
        A[:, n : 2 * n, n : 2 * n] = -minv[:, None] * C
        A[:, n : 2 * n, 2 * n] = minv * F
        return A

    eye = np.eye(2 * n + 1)
    A0, A1, A2 = (affine(k) for k in K)
    k1 = A0  # the stages as maps of (z, 1)
    k2 = A1 @ (eye + h / 2 * k1)
    k3 = A1 @ (eye + h / 2 * k2)
    k4 = A2 @ (eye + h * k3)
    S = eye + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    z = np.zeros(2 * n + 1)
    z[-1] = 1.0
    xs = [z[:n]]
    for Si in S:
        z = Si @ z
        xs.append(z[:n])
    return np.arange(t.size + 1) * h, np.array(xs)


# default tier: tests/test_train.py::test_two_stage_dynamic_factor_per_mesh_against_a_segmented_reference (same claim, a torsional train's Newmark response per mesh against a reference written apart, on the two-stage train)
@pytest.mark.slow
def test_idler_train_dynamics_converge_to_an_independent_reference():
    """torsional_train + the one dynamics stack on the idler train (disc inertias, 120 N·m,
    mesh frequency at 0.6 of the first elastic mode, composite damping, no contact loss): each
    mesh's dynamic TE over the last two mesh periods agrees with the train written out and
    integrated by RK4 (2048 steps per period, exact mesh stiffness at each stage) within 1.5 % of
    its peak-to-peak at 256 Newmark steps per period, and closer at 512 (Newmark samples the
    stiffness at a table row, first order through its jumps). The records are read at their
    time, on the nominal motion's clock θ = Ω t (``theta`` = Ω ``time``: the table row whose
    cells the step used; docs/design.md)."""
    planes = (_mesh(TEETH[0], TEETH[1]), _mesh(TEETH[1], TEETH[2]))
    pairs = (_pair(TEETH[0], TEETH[1]), _pair(TEETH[1], TEETH[2]))
    radii = (pairs[0].tip_radii[0], pairs[0].tip_radii[1], pairs[1].tip_radii[1])
    inertias = [disc_inertia(7800.0, r, FACE) for r in radii]
    phase_b = 0.37 * float(planes[1].mesh_period_angle)
    train = torsional_train(((planes[0], (0, 1)), (planes[1], (1, 2))), inertias, (0.0, phase_b))
    # built at the first run's N_s: the model and that run share one table program
    model = jd.dynamic_model(train, jg.Modifications(), TORQUE, positions_per_pitch=256)
    speed = 0.6 * float(model.modes.omega[1]) / TEETH[0]
    periods = 30
    t_ref, x_ref = _rk4_reference(train, planes, model, TORQUE, speed, periods, 2048)
    errors = {}
    for n_steps in (256, 512):
        r = jd.simulate(
            model, speed, integrator=jd.Newmark(n_steps), window=jd.SteadyState(periods, 2)
        )
        t = np.asarray(r.time)  # θ = Ω t
        X = np.stack([np.interp(t, t_ref, x_ref[:, i]) for i in range(x_ref.shape[1])], -1)
        for k, mesh in enumerate(r.meshes):
            assert float(mesh.contact_loss) == 0.0
            te_ref = (
                X @ np.asarray(train.te_vectors()[k]) / math.cos(float(pairs[k].base_helix_angle))
            )
            te = np.asarray(mesh.transmission_error)
            errors[n_steps, k] = float(np.max(np.abs(te - te_ref)) / np.ptp(te_ref))
    for k in range(2):
        assert errors[256, k] < 0.015, errors
        assert errors[512, k] < errors[256, k], errors


def test_torsional_train_refuses_what_it_cannot_run():
    """One-line errors before any computation: a mesh listed before its driving gear turns, a
    gear driven twice, two outputs, and a second stage whose tooth-passing period differs."""
    a, b = _mesh(TEETH[0], TEETH[1]), _mesh(TEETH[1], TEETH[2])
    inertias = (1e-3, 1e-3, 1e-3)
    with pytest.raises(ValueError, match=r"^meshes\[0\]: driving gear 1 does not turn yet"):
        torsional_train(((b, (1, 2)), (a, (0, 1))), inertias)
    with pytest.raises(ValueError, match=r"^meshes\[1\]: gear 1 is driven twice"):
        torsional_train(((a, (0, 1)), (a, (0, 1))), inertias)
    with pytest.raises(ValueError, match=r"^the train has output gears \[1, 2\]"):
        torsional_train(((a, (0, 1)), (a, (0, 2))), inertias)
    # a driving gear of 23 teeth on gear 1's rotation (a compound gear: two gears on one
    # shaft): another tooth-passing rate; the meshes repeat together every 37 periods of the
    # first (one turn of the 37-tooth gear's shaft), and a window shorter than that is refused
    two_stage = torsional_train(((a, (0, 1)), (_mesh(TEETH[0], TEETH[2]), (1, 2))), inertias)
    assert two_stage.scene_periods() == 37
    model = jd.dynamic_model(two_stage, jg.Modifications(), TORQUE, positions_per_pitch=8)
    with pytest.raises(ValueError, match=r"^window keep_periods = 4: the meshes repeat together"):
        jd.simulate(model, 500.0, integrator=jd.Newmark(8), window=jd.SteadyState(40, 4))


def two_stage_train(planes=None):
    """The two-stage torsional train of these tests: 20 → 40 teeth, then a 30-tooth pinion on the
    40's shaft (a compound gear: one rotation, both gears' inertia) → 45 teeth, solid steel discs
    of the tip radii, the second mesh clocked by 0.3 of its period; ``planes`` (the two meshes'
    :class:`jaxgear.MeshModel`) default to :func:`_mesh`'s. Returns (planes, pairs, train)."""
    pairs = (_pair(20, 40), _pair(30, 45))
    planes = (_mesh(20, 40), _mesh(30, 45)) if planes is None else planes
    disc = lambda r: disc_inertia(7800.0, r, FACE)  # noqa: E731
    inertias = [
        disc(pairs[0].tip_radii[0]),
        disc(pairs[0].tip_radii[1]) + disc(pairs[1].tip_radii[0]),
        disc(pairs[1].tip_radii[1]),
    ]
    clocking = 0.3 * float(planes[1].mesh_period_angle)
    train = torsional_train(((planes[0], (0, 1)), (planes[1], (1, 2))), inertias, (0.0, clocking))
    return planes, pairs, train


# default tier: tests/test_train.py::test_two_stage_dynamic_factor_per_mesh_against_a_segmented_reference (same claims on the same train: each mesh's response against a reference written apart, at 256 steps, and the forces repeating over the 4-period span)
@pytest.mark.slow
def test_two_stage_train_dynamics_converge_to_an_independent_reference():
    """A two-stage torsional train: 20 → 40 teeth, then a 30-tooth pinion on the 40's shaft (a
    compound gear: one rotation, both gears' inertia) → 45 teeth. Its meshes pass teeth at 20 Ω
    and 15 Ω: they repeat together every 4 periods of the first (the table spans them). At a
    first-mesh frequency of 0.3 of the first elastic mode, no contact loss, each mesh's dynamic
    TE over two spans (8 periods) agrees with the train written out and integrated by RK4 (2048
    steps per period, each mesh's exact stiffness at its own angle) within 2.5 % of its
    peak-to-peak at 256 Newmark steps per period and closer at 512 (measured 2.0/1.4 % and
    0.6/0.6 %), and each mesh's dynamic factor within 2 % at 512."""
    planes, _, train = two_stage_train()
    assert train.scene_periods() == 4
    # built at the first run's N_s: the model and that run share one table program
    model = jd.dynamic_model(train, jg.Modifications(), TORQUE, positions_per_pitch=256)
    speed = 0.3 * float(model.modes.omega[1]) / 20
    periods, keep = 24, 8
    t_ref, x_ref = _rk4_reference(train, planes, model, TORQUE, speed, periods, 2048)
    U = np.asarray(train.te_vectors())
    errors = {}
    for n_steps in (256, 512):
        r = jd.simulate(
            model, speed, integrator=jd.Newmark(n_steps), window=jd.SteadyState(periods, keep)
        )
        assert int(r.result) == 0
        t = np.asarray(r.time)  # θ = Ω t: the records' angle (docs/design.md)
        X = np.stack([np.interp(t, t_ref, x_ref[:, i]) for i in range(x_ref.shape[1])], -1)
        for k, mesh in enumerate(r.meshes):
            assert float(mesh.contact_loss) == 0.0
            te_ref = X @ U[k]  # spur: cos β_b = 1
            te = np.asarray(mesh.transmission_error)
            errors[n_steps, k] = float(np.max(np.abs(te - te_ref)) / np.ptp(te_ref))
            if n_steps == 512:  # the reference's mesh force: every flank cell loaded, k_k u_k·X
                angles = float(train.meshes[k].ratio) * speed * t + float(train.meshes[k].phase)
                c = jax.vmap(planes[k].cells)(jnp.asarray(angles))
                kk = np.asarray(jnp.sum(jnp.where(c.mask, c.stiffness * c.length, 0.0), (1, 2)))
                df_ref = np.max(kk * te_ref) / float(mesh.static_force)
                assert float(mesh.dynamic_factor) == pytest.approx(df_ref, rel=0.02), (k, df_ref)
    for k in range(2):
        assert errors[256, k] < 0.025, errors
        assert errors[512, k] < errors[256, k], errors
    # the forces repeat over the span of four first-mesh periods, not over one
    fm = np.asarray(r.meshes[1].mesh_force)
    one, span = 512, 4 * 512
    repeat = np.max(np.abs(fm[-span:] - fm[-2 * span : -span]))
    assert np.max(np.abs(fm[-one:] - fm[-2 * one : -one])) > 10 * repeat


def _segmented_reference(model, train, planes, speed, t_end, k0):
    """The two-stage train with uniform mesh stiffness written out apart from the model: mesh k
    carries k0 b per tooth pair in contact, n_k = 2 while its mesh angle θ_k = ratio_k Ω t +
    phase_k is within (ε_k − 1) of a period after a whole period (a pair entered at the
    engagement point), 1 otherwise; between the jumps the system M ẍ + C ẋ + K x = F is linear
    with constant coefficients and is advanced exactly by the exponential of its augmented
    matrix (C the model's damping matrix), from rest. Returns x(t) as a function of t."""
    M = np.asarray(train.structure.M)
    C = np.asarray(model.damping)
    F = TORQUE * np.asarray(train.f_torque)
    U = np.asarray(train.te_vectors())
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    meshes = []
    for mesh, plane in zip(train.meshes, planes, strict=True):
        period = float(plane.mesh_period_angle)
        eps = float(plane.path_of_contact) / float(plane.base_pitch)
        meshes.append(
            (float(mesh.ratio), float(mesh.phase), period, eps, k0 * float(plane.face_width))
        )

    def pairs_in_contact(k, t):
        ratio, phase, period, eps, _ = meshes[k]
        frac = ((ratio * speed * t + phase) / period) % 1.0
        return 2 if frac < eps - 1.0 else 1

    def events(t_end):
        out = {0.0, t_end}
        for ratio, phase, period, eps, _ in meshes:
            for edge in (0.0, eps - 1.0):  # θ_k = (j + edge) period
                j0 = math.ceil((phase / period - edge) - 1)
                t = ((j0 + edge) * period - phase) / (ratio * speed)
                while t < t_end:
                    if t > 0:
                        out.add(t)
                    t += period / (ratio * speed)
        return np.array(sorted(out))

    def contact(mid):  # the pairs in contact per mesh between two jumps (4 combinations)
        return tuple(pairs_in_contact(k, mid) for k in range(2))

    @functools.cache
    def augmented(pairs):  # the linear system between two jumps, [x, ẋ, 1]' = A [x, ẋ, 1]
        K = sum(meshes[k][4] * pairs[k] * np.outer(U[k], U[k]) for k in range(2))
        A = np.zeros((2 * n + 1, 2 * n + 1))
        A[:n, n : 2 * n] = np.eye(n)
        A[n : 2 * n, :n] = -Minv @ K
        A[n : 2 * n, n : 2 * n] = -Minv @ C
        A[n : 2 * n, 2 * n] = Minv @ F
        return A

    times = events(t_end)
    states = [np.zeros(2 * n)]
    for a, b in itertools.pairwise(times):
        y = scipy.linalg.expm(augmented(contact(0.5 * (a + b))) * (b - a)) @ np.append(
            states[-1], 1.0
        )
        states.append(y[: 2 * n])
    states = np.array(states)

    def x_at(t):
        """Exact within a segment: advanced from its start to its first record by the
        exponential, then record to record by the exponential of the records' step (the
        records are evenly spaced: t_j = t_0 + j h to rounding; the step's exponential once
        per linear system)."""
        t = np.atleast_1d(t)
        h = (t[-1] - t[0]) / max(t.size - 1, 1)
        np.testing.assert_allclose(np.diff(t), h, rtol=1e-9)  # evenly spaced
        step = functools.cache(lambda pairs: scipy.linalg.expm(augmented(pairs) * h))
        seg = np.clip(np.searchsorted(times, t, side="right") - 1, 0, times.size - 2)
        out = np.empty((t.size, n))
        for ii in np.unique(seg):
            at = np.nonzero(seg == ii)[0]
            a, b = times[ii], times[ii + 1]
            pairs = contact(0.5 * (a + b))
            y = scipy.linalg.expm(augmented(pairs) * (t[at[0]] - a)) @ np.append(states[ii], 1.0)
            out[at[0]] = y[:n]
            for j in at[1:]:
                y = step(pairs) @ y
                out[j] = y[:n]
        return out

    return x_at, pairs_in_contact, meshes


def test_two_stage_dynamic_factor_per_mesh_against_a_segmented_reference():
    """The two-stage train (20 → 40, 30 → 45 on the 40's shaft) with uniform mesh stiffness
    (k0 per unit length: the mesh stiffness jumps between one and two tooth pairs), modal
    damping 20 %, at seven speeds from 0.15 to 1.05 of the first elastic mode's first-mesh
    coincidence (dynamic factors 1.8 to 2.6), no contact loss: each
    mesh's dynamic factor within 2 % of the reference written apart from the model (exact
    between the stiffness jumps, :func:`_segmented_reference`), read at the records' angles
    (measured: at most 0.60 % over the speeds and meshes at 256 steps per period, 0.19 % at
    512). The meshes repeat together every 4 first-mesh periods: the mesh forces over the last
    two spans repeat over a span, not over one period."""
    k0 = 1.4e10  # N/m per m of contact line
    pairs = (_pair(20, 40), _pair(30, 45))
    planes = tuple(
        jg.MeshModel.from_pair(p, *jg.stiffness_table(p, jg.Uniform(k0)), SLICES)
        for p in pairs
    )
    train = two_stage_train(planes)[2]
    # modal damping of 20 %: the stiffness jumps of uniform spur meshes excite strongly, and the
    # reference is linear (no contact loss at any of these speeds)
    model = jd.dynamic_model(train, jg.Modifications(), TORQUE, jio.Damping("modal", ratio=0.2))
    first = float(model.modes.omega[1]) / 20  # mode 1 × H1 of the first mesh (input rad/s)
    rb_in, rb_wheel = pairs[0].base_radii
    static = (TORQUE / rb_in, TORQUE * rb_wheel / rb_in / pairs[1].base_radii[0])
    periods, keep, steps = 24, 8, 256
    worst = 0.0
    for fraction in (0.15, 0.3, 0.45, 0.6, 0.75, 0.9, 1.05):
        speed = fraction * first
        r = jd.simulate(
            model, speed, integrator=jd.Newmark(steps), window=jd.SteadyState(periods, keep)
        )
        assert int(r.result) == 0
        t_end = periods * float(planes[0].mesh_period_angle) / speed
        x_at, n_pairs, meshes = _segmented_reference(model, train, planes, speed, t_end, k0)
        t = np.asarray(r.time)  # θ = Ω t: the records' angle (design.md)
        X = x_at(t)
        U = np.asarray(train.te_vectors())
        for k, mesh in enumerate(r.meshes):
            assert float(mesh.contact_loss) == 0.0, (fraction, k)
            # the forces repeat over the span of four first-mesh periods, not over one
            fm = np.asarray(mesh.mesh_force)
            one, span = steps, 4 * steps
            repeat = np.max(np.abs(fm[-span:] - fm[-2 * span : -span]))
            assert np.max(np.abs(fm[-one:] - fm[-2 * one : -one])) > 10 * repeat, (fraction, k)
            force = np.array([meshes[k][4] * n_pairs(k, ti) for ti in t]) * (X @ U[k])
            df_ref = force.max() / static[k]
            assert float(mesh.static_force) == pytest.approx(static[k], rel=1e-6)
            worst = max(worst, abs(float(mesh.dynamic_factor) / df_ref - 1))
            assert float(mesh.dynamic_factor) == pytest.approx(df_ref, rel=0.02), (
                fraction,
                k,
                df_ref,
            )
    assert worst < 0.02  # measured 0.60 % (256 steps per period; 0.19 % at 512)


def test_automatic_steps_resolve_the_fastest_mesh():
    """A speed-increasing two-stage train (40 → 24, then 36 → 20 on the 24's shaft): the second
    mesh passes teeth 1.5 times as fast as the first (60 Ω against 40 Ω), so the automatic step
    gives at least 64 steps per period of that mesh at a speed where the modes alone ask for
    fewer; the two meshes repeat together every 2 periods of the first, the second's period is
    2/3 of the first's, so the step count is a multiple of 3 (3 × 2^j: 96, which gives the
    second mesh exactly 64 steps per period and the table each mesh's own period: 96 and 64
    rows, not the span's 192)."""
    planes = (_mesh(40, 24), _mesh(36, 20))
    train = torsional_train(((planes[0], (0, 1)), (planes[1], (1, 2))), (1e-3, 1e-3, 1e-3))
    assert train.scene_periods() == 2
    model = jd.dynamic_model(train, jg.Modifications(), TORQUE)
    f_max = float(jd.excited_omega(model.modes))
    speed = 4.0 * f_max / 40  # the first mesh at 4 times the highest excited mode: 64 would do
    assert int(jd.auto_steps_per_period(model, [speed])[0]) == 96
    assert jd.mesh_table(train, None, 96).rows == (96, 64)
