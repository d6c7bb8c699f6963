"""A pair's own dynamic model as a gearbox stage (jaxgear.dynamics.DynamicModel given its input
side, an AbstractStage; docs/architecture.md, "One stage contract"): two torsional pairs in
series, each the DynamicModel of its TorsionalDynamics scene, give the coupled run of a
torsional pair stage written apart here (the gearbox's meshed pair stage as it was its own
class: the torsional pair's vectors with the wheel's sign flipped, the mesh's separations, the
kinematics from the base radii) to 1e-12, and the chain's torsional natural frequencies against
an eigen-solution assembled here from the inertias, base radii, the cells' mean stiffness and
the shaft, to 1e-10. A model without its side runs alone and is refused in a gearbox; one built
for a gearbox only is refused alone."""

from __future__ import annotations

import itertools
import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg

import jaxgear as jg
from jaxgear import dynamics as jd, gearbox as gb
from jaxgear.scenes import TorsionalDynamics, TorsionalPair

jax.config.update("jax_enable_x64", True)

MODULE, ALPHA, K_U = 3e-3, math.radians(20.0), 1.4e10
BETA = math.radians(15.0)  # helical: cos(beta_b) enters the vectors
# the two pairs: (z1, z2, face width (m), polar inertias (kg m^2), the driven side)
PAIRS = ((21, 43, 0.030, (2.1e-3, 3.6e-2), 0), (19, 37, 0.040, (6.0e-3, 8.5e-2), 0))
SHAFT = 2.0e6  # N m/rad, the first pair's wheel to the second's pinion
TORQUE = 150.0  # N m on the first pinion
MODS = jg.Modifications.symmetric(jg.MemberModification(tip_relief_depth=8e-6,
                                                        tip_relief_extent=0.25))
PLAN = {"steps_per_period": 16, "periods": 4, "keep_periods": 1, "mean_positions": 16}


class _ReferenceStage(jd.AbstractStage):
    """The torsional pair on its cells, written apart: rotations (theta_pinion, theta_wheel) in
    one sense, V = TorsionalPair's vectors times (1, -1), the cells at pinion angle x / r_b1
    with the modifications' separations (jaxgear.separation), K_bar their k l V V^T over the
    period's mid-points on the theoretical path, the kinematics of two gears in mesh."""

    inertias: tuple
    radii: tuple
    side: int
    mesh: jg.MeshModel
    mods: jg.Modifications

    def dof_names(self):
        return ("theta_pinion", "theta_wheel")

    def matrices(self):
        return jnp.diag(jnp.asarray(self.inertias)), jnp.zeros((2, 2))

    def ends(self):
        return self.side, 1 - self.side

    def dynamic_parts(self, positions):
        x = self.mesh_period() * (jnp.arange(positions) + 0.5) / positions
        path = self.mesh.contact_geometry.on_path(self.mesh)
        k = jnp.zeros((2, 2))
        for xi in x:
            r = _ReferenceStage(self.inertias, self.radii, self.side, path, self.mods).cell_row(xi)
            kl = jnp.where(r.mask, r.k * r.length, 0.0)
            k = k + (r.V * kl[:, None]).T @ r.V
        m = jnp.diag(jnp.asarray(self.inertias))
        return m, jnp.zeros((2, 2)), k / positions, jnp.zeros(2)

    def cell_row(self, x):
        cells, _, d0 = jg.separation(self.mesh, self.mods, x / self.mesh.base_radius_pinion)
        V = TorsionalPair(self.mesh).cell_vectors(cells) * jnp.asarray([[[1.0, -1.0]]])
        return jg.CellRow.of(cells, V, d0)

    def mesh_forces(self, forces):
        return jnp.cos(self.mesh.base_helix_angle) * jnp.sum(forces, axis=-1, keepdims=True)

    def mesh_names(self):
        return ("pair",)

    def mesh_period(self):
        return self.mesh.base_pitch

    def kinematics(self, input_speed, input_torque):
        r_in, r_out = self.radii[self.side], self.radii[1 - self.side]
        t = jnp.abs(jnp.asarray(input_torque, float))
        w = jnp.asarray(input_speed, float)
        return -w * r_in / r_out, t * r_out / r_in, r_in * jnp.abs(w), jnp.reshape(t / r_in, (1,))


# a mesh's cells by one compiled program (evaluated op by op: many small ones)
_cells = eqx.filter_jit(lambda mesh, theta: mesh.cells(theta))


def _mesh(z1, z2, b):
    pair = jg.GearPair(jg.Member(z1, face_width=b), jg.Member(z2, face_width=b), MODULE, ALPHA,
                       helix_angle=BETA)
    return pair, jg.MeshModel.from_pair(pair, *jg.stiffness_table(pair, jg.Uniform(K_U)), 2)


@pytest.fixture(scope="module")
def stages():
    """Per pair: (the reference stage written apart, the pair's DynamicModel with its side: the
    first built to run alone too, the second for a gearbox only)."""
    out = []
    for k, (z1, z2, b, inertias, side) in enumerate(PAIRS):
        pair, mesh = _mesh(z1, z2, b)
        radii = tuple(float(r) for r in pair.base_radii)
        old = _ReferenceStage(inertias, radii, side, mesh, MODS)
        scene = TorsionalDynamics(mesh, *inertias)
        if k == 0:
            new = jd.dynamic_model(scene, MODS, TORQUE, input=side)
        else:
            new = jd.stage_model(scene, MODS, input=side)
        out.append((old, new, mesh, pair))
    return out


def test_the_pair_model_answers_the_stage_contract_as_the_reference_stage(stages):
    """What the coupled run reads of a stage (jaxgear.dynamics.AbstractStage): each pair's
    DynamicModel answers as the reference stage written apart: the coordinate names, ends,
    mesh-averaged parts (16 positions), cells' rows at three places in the mesh
    period on both flanks (vectors, stiffness x length, separations; one compiled program per
    stage), mesh forces, names, period, kinematics and speed terms, to 1e-12; the first runs
    alone too."""
    old = gb.GearboxTorsional(tuple(s[0] for s in stages), (SHAFT,))
    new = gb.GearboxTorsional(tuple(s[1] for s in stages), (SHAFT,))
    assert isinstance(new.stages[0], jd.DynamicModel) and new.stages[0].runs_alone
    assert not new.stages[1].runs_alone
    assert gb.coordinate_names(new) == gb.coordinate_names(old)

    def close(x, y, what):
        x, y = np.asarray(x), np.asarray(y)
        np.testing.assert_allclose(y, x, rtol=1e-12, atol=1e-12 * max(np.max(np.abs(x)), 1e-300),
                                   err_msg=what)

    rows = eqx.filter_jit(lambda stage, x: stage.cell_row(x))
    parts = eqx.filter_jit(lambda stage: stage.dynamic_parts(PLAN["mean_positions"]))
    for a, b in zip(old.stages, new.stages, strict=True):
        assert tuple(b.coordinates()) == tuple(a.coordinates())
        assert tuple(b.coordinate_ends()) == tuple(a.coordinate_ends())
        assert tuple(b.mesh_names()) == tuple(a.mesh_names())
        close(a.mesh_period(), b.mesh_period(), "mesh_period")
        assert b.excited() == a.excited() and b.mount() is None and a.mount() is None
        close(a.carrier_speed(180.0), b.carrier_speed(180.0), "carrier_speed")
        for x, y in zip(a.speed_terms(180.0), b.speed_terms(180.0), strict=True):
            close(x, y, "speed_terms")
        for x, y, what in zip(parts(a), parts(b), ("M", "C", "K_bar", "f"), strict=True):
            close(x, y, what)
        for x, y in zip(a.kinematics(180.0, TORQUE), b.kinematics(180.0, TORQUE), strict=True):
            close(x, y, "kinematics")
        flanks = ((a, b), (a.on_flanks(jnp.asarray(-1.0)), b.on_flanks(jnp.asarray(-1.0))))
        for (sa, sb), frac in itertools.product(flanks, (0.1, 0.45, 0.8)):
            x = jnp.asarray(frac * float(a.mesh_period()))
            ra, rb = rows(sa, x), rows(sb, x)
            np.testing.assert_array_equal(np.asarray(ra.mask), np.asarray(rb.mask))
            on = np.asarray(ra.mask)
            close(np.asarray(ra.V)[on], np.asarray(rb.V)[on], "V")
            close(np.asarray(ra.k * ra.length)[on], np.asarray(rb.k * rb.length)[on], "k l")
            close(np.asarray(ra.delta0)[on], np.asarray(rb.delta0)[on], "separation")
            forces = np.where(on, 1.0 + np.arange(on.size).reshape(on.shape), 0.0)
            close(sa.mesh_forces(jnp.asarray(forces)), sb.mesh_forces(jnp.asarray(forces)),
                  "mesh_forces")
    # the same object runs alone (its own pair dynamics, cheap plan)
    alone = jd.simulate(new.stages[0], 180.0, integrator=jd.Newmark(16),
                        window=jd.SteadyState(4, 2))
    assert int(alone.result) == 0


# default tier: tests/test_gearbox_pair_model.py::test_the_pair_model_answers_the_stage_contract_as_the_reference_stage (what the coupled run reads of each stage, to 1e-12)
@pytest.mark.slow
def test_the_pair_model_gives_the_reference_stage_coupled_run(stages):
    old = gb.GearboxTorsional(tuple(s[0] for s in stages), (SHAFT,))
    new = gb.GearboxTorsional(tuple(s[1] for s in stages), (SHAFT,))
    assert isinstance(new.stages[0], jd.DynamicModel) and new.stages[0].runs_alone
    assert not new.stages[1].runs_alone
    assert gb.coordinate_names(new) == gb.coordinate_names(old)
    run = gb.GearboxRun(TORQUE, 5e5, **PLAN)
    a, b = gb.gearbox_dynamics(old, run, 180.0), gb.gearbox_dynamics(new, run, 180.0)
    assert int(a.result) == 0 and int(b.result) == 0
    for name in ("mesh_forces", "displacement", "dynamic_factors", "static_forces",
                 "mesh_speeds", "time"):
        x, y = np.asarray(getattr(a, name)), np.asarray(getattr(b, name))
        np.testing.assert_allclose(y, x, rtol=1e-12, atol=1e-12 * np.max(np.abs(x)),
                                   err_msg=name)
    # the same object runs alone (its own pair dynamics, cheap plan)
    alone = jd.simulate(new.stages[0], 180.0, integrator=jd.Newmark(16),
                        window=jd.SteadyState(4, 2))
    assert int(alone.result) == 0


def test_chain_frequencies_against_a_hand_assembled_eigh(stages):
    """gearbox_modes of the chain of the two pair models: each pair's torsional view is its
    inertias and its cells' stiffness averaged over 64 mid-points of a mesh period (the drive
    flanks on the path), k_bar cos^2(beta_b) [r1^2, r1 r2; r1 r2, r2^2] with both rotations
    in one sense, the shaft joining wheel 1 to pinion 2; the eigen-solution of that M, K."""
    M = np.zeros((4, 4))
    K = np.zeros((4, 4))
    for k, (_, _, mesh, pair) in enumerate(stages):
        inertias = PAIRS[k][3]
        z1 = PAIRS[k][0]
        theta = (np.arange(64) + 0.5) * 2 * math.pi / z1 / 64
        kl = []
        for th in theta:
            c = _cells(mesh, jnp.asarray(th))
            on = np.asarray(c.mask) & (np.asarray(c.s) >= 0.0) & (
                np.asarray(c.s) <= float(mesh.path_of_contact))
            kl.append(np.sum(np.where(on, np.asarray(c.stiffness) * np.asarray(c.length), 0.0)))
        k_bar = float(np.mean(kl))
        cb = math.cos(float(mesh.base_helix_angle))
        r = np.asarray(pair.base_radii, dtype=float)
        i = slice(2 * k, 2 * k + 2)
        M[i, i] = np.diag(inertias)
        K[i, i] = k_bar * cb**2 * np.outer(r, r)
    e = np.zeros(4)
    e[1], e[2] = 1.0, -1.0
    K += SHAFT * np.outer(e, e)
    w2 = scipy.linalg.eigh(K, M, eigvals_only=True)
    f_ref = np.sqrt(np.clip(w2, 0.0, None)) / (2 * math.pi)
    chain = gb.GearboxTorsional(tuple(s[1] for s in stages), (SHAFT,))
    f = np.asarray(gb.gearbox_modes(chain).frequencies)
    assert f[0] < 1e-6 * f[1]  # the free chain's rigid rotation
    np.testing.assert_allclose(f[1:], f_ref[1:], rtol=1e-10)


def test_refusals_one_line(stages):
    _, model, mesh, _ = stages[0]
    alone = jd.dynamic_model(TorsionalDynamics(mesh, 1e-3, 2e-3), None, TORQUE)
    with pytest.raises(ValueError, match=r"stages\[0\]: a DynamicModel without its input side"):
        gb.GearboxTorsional((alone,), ())
    only = stages[1][1]
    with pytest.raises(ValueError, match="built for a gearbox only"):
        jd.simulate(only, 100.0)
    with pytest.raises(ValueError, match="input = 2"):
        jd.stage_model(TorsionalDynamics(mesh, 1e-3, 2e-3), None, input=2)
    assert model.input == 0 and jd.dynamic_model(
        TorsionalDynamics(mesh, 1e-3, 2e-3), None, TORQUE, input=1).input == 1


def test_the_meshed_pair_gearbox_stage_form_is_deprecated():
    """``PairGearboxStage(..., mesh=)`` (the meshed pair's old constructor) warns, naming
    :class:`jaxgear.gearbox.TorsionalPairGearboxStage`, and builds that model: the same parts
    as the class built directly (bitwise); without a mesh it is the constant-spring stage,
    with no warning."""
    import warnings

    z1, z2, b, inertias, side = PAIRS[0]
    pair, mesh = _mesh(z1, z2, b)
    radii = tuple(float(r) for r in pair.base_radii)
    with pytest.warns(DeprecationWarning, match=r"jaxgear\.gearbox\.TorsionalPairGearboxStage"):
        old = gb.PairGearboxStage(inertias, radii, 5e8, input=side, mesh=mesh, modifications=MODS)
    new = gb.TorsionalPairGearboxStage(inertias, radii, 5e8, input=side, mesh=mesh,
                                       modifications=MODS)
    assert type(old) is gb.TorsionalPairGearboxStage
    # the same fields, static and array (bitwise): so the same parts, cells and kinematics
    assert bool(eqx.tree_equal(old, new))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        springs = gb.PairGearboxStage(inertias, radii, 5e8, input=side)
    assert type(springs) is gb.PairGearboxStage
