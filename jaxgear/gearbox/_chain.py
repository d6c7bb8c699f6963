"""A gearbox of stages in series as one torsional lumped model: each stage's torsional model (a
planetary stage's :class:`~jaxgear.planetary.TorsionalPlanetary`, a parallel pair's two rotations
joined by its mesh) in absolute rotations, the stages joined by the torsional stiffnesses of the
shafts that carry one stage's output member to the next stage's input member.

Coordinates: one rotation theta (rad) per member, every rotation positive in the same sense
about the common axis direction (a parallel pair's wheel and pinion included); M in kg m^2,
K in N m/rad. A planetary stage's model is :class:`~jaxgear.planetary.TorsionalPlanetary`'s, whose
coordinates are u = r theta (m) with r the member's ``base_radius`` (the carrier's: the planet
circle), so that its blocks here are R M R and R K R, R = diag(r). A parallel pair's mesh
deflection along its line of action is r_b1 theta_1 + r_b2 theta_2 (the two gears turn in
opposite senses), its mesh stiffness k: K = k [r_b1 r_b1, r_b1 r_b2; r_b1 r_b2, r_b2 r_b2].
A shaft of torsional stiffness k_t between coordinates i and j adds k_t (theta_i - theta_j)^2 / 2
to the strain energy.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax
import jax.numpy as jnp
import jax.scipy.linalg
import numpy as np
from jaxtyping import Array, Float

from .._baseplane import CellRow, MeshModel, on_the_path
from .._modifications import Modifications
from .._quasi_static import separation
from .._util import as_float, check_instance
from ..dynamics import cell_stiffness, matrix_modal_analysis
from ..planetary import (
    AbstractPlanetaryMeshes,
    AbstractPlanetaryModel,
    Central,
    ConstantMeshes,
    HousedPlanetary,
    PlanetaryRun,
    PlanetaryStage,
    TorsionalPlanetary,
    planetary_cell_row,
    planetary_stage_system,
)
from ..scenes import Housing, TorsionalPair

__all__ = [
    "AbstractGearboxStage",
    "GearboxModes",
    "GearboxTorsional",
    "PairGearboxStage",
    "PlanetaryGearboxStage",
    "gearbox_modes",
]


def mean_cell_stiffness(cell_row, period, positions: int) -> Float[Array, "n n"]:
    """K̄_m of a mesh: its cells' stiffness Σ k l V Vᵀ (:func:`jaxgear.dynamics.cell_stiffness`)
    averaged over ``positions`` mid-points of its period ``period`` (m of mesh travel), the
    cells from ``cell_row`` (a function of the travel, on the theoretical path: beyond it a
    corner's cell carries load only under deflection)."""
    x = period * (jnp.arange(positions) + 0.5) / positions
    rows = jax.vmap(cell_row)(x)
    kl = jnp.where(rows.mask, rows.k * rows.length, 0.0)
    return cell_stiffness(rows.V, kl) / positions


class AbstractGearboxStage(eqx.Module):
    """One stage of a gearbox in the torsional chain: its members' rotations, its matrices, and
    which of them are its input and output members."""

    @abc.abstractmethod
    def dof_names(self) -> tuple[str, ...]:
        """One name per rotation of the stage, in order."""

    @abc.abstractmethod
    def matrices(self) -> tuple[Float[Array, "n n"], Float[Array, "n n"]]:
        """(M, K): kg m^2 and N m/rad, on the stage's rotations (rad)."""

    @abc.abstractmethod
    def ends(self) -> tuple[int, int]:
        """(input, output): the indices of the input and output members' rotations."""

    # -- the coupled dynamic model (:func:`~jaxgear.gearbox.gearbox_dynamics`) ----------------

    def coordinates(self) -> tuple[str, ...]:
        """The stage's coordinates in the coupled dynamic model (rad for a rotation, m for a
        translation); default: :meth:`dof_names` (a torsional stage)."""
        return self.dof_names()

    def coordinate_ends(self) -> tuple[int, int]:
        """:meth:`ends` in :meth:`coordinates` (the rotations the shafts join)."""
        return self.ends()

    @abc.abstractmethod
    def dynamic_parts(self, positions: int):
        """(M, K_s, K̄_m, F): mass, structure stiffness without the meshes, the meshes' cell
        stiffness averaged over ``positions`` mid-points of a mesh period, and the stage's own
        constant load (pin errors; N or N m), on :meth:`coordinates`."""

    @abc.abstractmethod
    def cell_row(self, x) -> CellRow:
        """The stage's contact cells at its mesh travel ``x`` (m) on :meth:`coordinates`
        (every mesh's, in :meth:`mesh_names`' order)."""

    def on_flanks(self, sign) -> AbstractGearboxStage:
        """The stage with its cells placed for the flanks the load is on: ``sign`` (traced,
        +1 or -1) the sign of its mesh deflections under the static load (-1: the other flanks
        than its cells' own). The default: the same cells (a pair's two flanks alike; the
        coupled model flips their rows' sign)."""
        return self

    @abc.abstractmethod
    def mesh_forces(self, forces) -> Float[Array, "... m"]:
        """Each mesh's transverse force (N, compression positive), (..., m), from the cell
        forces (N, (..., c))."""

    @abc.abstractmethod
    def mesh_names(self) -> tuple[str, ...]:
        """One name per mesh."""

    @abc.abstractmethod
    def mesh_period(self) -> Float[Array, ""]:
        """p_b (m): the mesh travel of one mesh period."""

    @abc.abstractmethod
    def kinematics(self, input_speed, input_torque):
        """(output speed (rad/s), output torque (N m), mesh travel speed v (m/s), each mesh's
        static transverse force (N, (m,))) at the input member's speed (rad/s) and torque
        (N m, its magnitude carried; the stage's drive flanks are the ones it loads)."""

    def excited(self) -> bool:
        """Whether the stage's meshes vary along the mesh travel (contact cells): a stage of
        constant springs sets no time scale of a run."""
        return True

    def carrier_speed(self, input_speed):
        """The speed (rad/s) of the frame the stage's coordinates are written in (a planetary
        stage: its carrier's) at its input member's ``input_speed``; default 0 (the fixed
        frame: a parallel pair)."""
        return 0.0 * as_float(input_speed)

    def speed_terms(self, carrier_speed):
        """(C_Omega, K_Omega): the rotating frame's damping and stiffness terms (Coriolis,
        centripetal) on :meth:`coordinates` at the stage's carrier speed (rad/s); zero for a
        torsional stage."""
        n = len(self.coordinates())
        z = jnp.zeros((n, n))
        return z, z

    def housing(self) -> tuple[Float[Array, "h h"], Float[Array, "h h"]] | None:
        """(K_h, M_h): the stiffness and mass of the flexible housing whose h coordinates end
        :meth:`coordinates` (its seats' 6 each, then its modal ones), which a gearbox-level
        :attr:`GearboxTorsional.housing` shares with the other stages; None (the default): the
        stage stands on the ground (a torsional stage, a planetary stage of an unhoused model
        kind)."""
        return None

    def housing_seats(self) -> tuple[int, ...]:
        """The seats (indices) of :meth:`housing` that the stage's bearings or members join, in
        ascending order; () (the default) for a stage on the ground."""
        return ()


class PlanetaryGearboxStage(AbstractGearboxStage):
    """A planetary stage in the chain (:class:`~jaxgear.planetary.TorsionalPlanetary`, Kahraman
    1994: rotations of carrier, ring, sun and the N planets); ``input``/``output``: which central
    members (:class:`~jaxgear.planetary.Central`) the shafts join. A fixed member is held by its
    ``torsional_stiffness`` in ``stage``.

    ``model`` a :class:`~jaxgear.planetary.HousedPlanetary` (of a torsional or planar kind):
    the stage on a condensed housing, its held member's torsional support (about the stage
    axis) joining a seat instead of the ground through the housing's seat coupling; the
    housing's coordinates end :meth:`coordinates` (:meth:`housing`), so that a gearbox-level
    :attr:`GearboxTorsional.housing` shares them with the other housed stages
    (docs/gearbox.md, "A planetary stage in the shared housing"). Its damping C_h rides in
    :meth:`speed_terms`, as a lumped stage's does.

    Raises:
        ValueError: ``input`` = ``output``; ``meshes`` or ``model`` of another kind, or a model
            without contact cells; a ``HousedPlanetary`` with ``carrier_held`` whose carrier is
            the input or output member (it turns) (one line each).
    """

    stage: PlanetaryStage
    input: Central = eqx.field(static=True)
    output: Central = eqx.field(static=True)
    meshes: AbstractPlanetaryMeshes | None = None
    model: AbstractPlanetaryModel = TorsionalPlanetary()
    run: PlanetaryRun | None = None  # jaxgear.planetary.PlanetaryRun: its pin errors

    def __check_init__(self):
        if self.input == self.output:
            raise ValueError(f"PlanetaryGearboxStage: input = output = {self.input!r}: allowed "
                             "two different central members")
        if self.meshes is not None:
            check_instance("meshes", self.meshes, AbstractPlanetaryMeshes,
                           "a planetary meshes kind (ContactMeshes, ConstantMeshes)",
                           "PlanetaryGearboxStage")
        check_instance("model", self.model, AbstractPlanetaryModel,
                       "a planetary model kind (TorsionalPlanetary, PlanarPlanetary)",
                       "PlanetaryGearboxStage")
        if not self.model.contact_solve:
            raise ValueError(f"PlanetaryGearboxStage: model {type(self.model).__name__} has no "
                             "contact cells: allowed TorsionalPlanetary, PlanarPlanetary (or "
                             "either in a HousedPlanetary)")
        if (isinstance(self.model, HousedPlanetary) and self.model.carrier_held
                and Central.CARRIER in (self.input, self.output)):
            role = "input" if self.input == Central.CARRIER else "output"
            raise ValueError("PlanetaryGearboxStage: model HousedPlanetary(carrier_held=True) "
                             f"with the carrier the {role} member: allowed a star stage (sun "
                             "and ring the shafts' members, the carrier held)")

    # -- the coupled model: the stage's model in its carrier frame, its rotations u = r theta
    # scaled to theta (rad) so that the shafts join rotations; translations stay in m
    def _meshes(self):
        return ConstantMeshes() if self.meshes is None else self.meshes

    def _run(self):

        return PlanetaryRun(0.0) if self.run is None else self.run

    def _scale(self):
        st = self.stage
        radius = {"c": st.carrier.base_radius, "r": st.ring.base_radius,
                  "s": st.sun.base_radius}
        r = [radius.get(n[2:], st.planet.base_radius) if n.startswith("u_") else 1.0
             for n in self.model.dof_names(st)]
        return jnp.stack([jnp.asarray(v, dtype=st.planet_angles.dtype) for v in r])

    def coordinates(self):
        return tuple(("theta_" + n[2:]) if n.startswith("u_") else n
                     for n in self.model.dof_names(self.stage))

    def coordinate_ends(self):
        names = self.model.dof_names(self.stage)
        key = {Central.CARRIER: "u_c", Central.RING: "u_r", Central.SUN: "u_s"}
        return names.index(key[self.input]), names.index(key[self.output])

    def dynamic_parts(self, positions):

        parts = planetary_stage_system(self.model, self.stage, self._meshes(), self._run(),
                                       positions)
        r = self._scale()
        rr = r[:, None] * r[None, :]
        return rr * parts.m, rr * parts.k_b, rr * parts.k_mean, r * parts.f

    def cell_row(self, x):

        row = planetary_cell_row(self.model, self.stage, self._meshes(), self._run(), x)
        return row._replace(V=row.V * self._scale()[None, :])

    def mesh_forces(self, forces):
        return self._meshes().mesh_forces(forces)

    def on_flanks(self, sign):
        """The stage on the flanks its static load takes: with ``sign`` < 0 (the planets drive
        the sun: carrier in and sun out) its meshes'
        :meth:`~jaxgear.planetary.ContactMeshes.other_flanks` (the sun-ring phase within a planet of
        the other flanks), chosen leaf by leaf so that ``sign`` may be traced."""
        if self.meshes is None:
            return self
        other = self.meshes.other_flanks()
        # only the leaves the other flanks change are selected (the rest are the same arrays:
        # the tables are not copied)
        meshes = jax.tree.map(
            lambda a, b: jnp.where(sign < 0, b, a) if eqx.is_array(a) and a is not b else a,
            self.meshes, other)
        return eqx.tree_at(lambda s: s.meshes, self, meshes)

    def mesh_names(self):
        n = self.stage.n_planets
        return (tuple(f"sun-planet {i + 1}" for i in range(n))
                + tuple(f"ring-planet {i + 1}" for i in range(n)))

    def mesh_period(self):
        return self._meshes().mesh_period()

    def excited(self):
        return not isinstance(self._meshes(), ConstantMeshes)

    def _speeds(self, input_speed):
        """(omega_c, omega_r, omega_s) from Willis on base radii (r_bs w_s + r_br w_r =
        (r_bs + r_br) w_c; the radii are in the tooth counts' ratio), the third member held."""
        st = self.stage
        r_s, r_r = st.sun.base_radius, st.ring.base_radius
        held = ({Central.CARRIER, Central.RING, Central.SUN} - {self.input, self.output}).pop()
        # w = (w_c, w_r, w_s): Willis, the held member at 0, the input member at input_speed
        a = jnp.array([[-(r_s + r_r), r_r, r_s], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
        idx = {Central.CARRIER: 0, Central.RING: 1, Central.SUN: 2}
        a = a.at[1, idx[held]].set(1.0).at[2, idx[self.input]].set(1.0)
        w = jnp.linalg.solve(a, jnp.stack([0.0 * input_speed, 0.0 * input_speed, input_speed]))
        return w, idx

    def kinematics(self, input_speed, input_torque):
        st = self.stage
        w, idx = self._speeds(as_float(input_speed))
        out_speed = w[idx[self.output]]
        # power: |T_out| = |T_in w_in / w_out|; the sun's torque T_s = r_bs (over the torque's
        # lever of the input member: r_bs, r_br or r_bs + r_br) T_in; each mesh N r_bs F = T_s
        r_s, r_r = st.sun.base_radius, st.ring.base_radius
        lever = {Central.SUN: r_s, Central.RING: r_r, Central.CARRIER: r_s + r_r}[self.input]
        torque = jnp.abs(as_float(input_torque))
        out_torque = torque * jnp.abs(as_float(input_speed) / out_speed)
        f = torque / (lever * st.n_planets)
        v = r_s * jnp.abs(w[2] - w[0])  # the mesh travel in the carrier frame
        return out_speed, out_torque, v, jnp.full((2 * st.n_planets,), f)

    def speed_terms(self, carrier_speed):
        """(C_Omega, K_Omega) of the model at ``carrier_speed`` (rad/s), with a housed model
        the housing's damping C_h on its coordinates added to C_Omega (the coupled model's
        constant damping term, which carries a lumped stage's housing damping as well)."""
        r = self._scale()
        rr = r[:, None] * r[None, :]
        st = self.stage
        c = carrier_speed * rr * self.model.gyroscopic_matrix(st)
        if isinstance(self.model, HousedPlanetary):
            h = self.model.housing.size
            c = c.at[-h:, -h:].add(jnp.asarray(self.model.housing.C, c.dtype))
        return c, -carrier_speed**2 * rr * self.model.centripetal_matrix(st)

    def housing(self):
        """(K_h, M_h) of a :class:`~jaxgear.planetary.HousedPlanetary` model's housing (its
        coordinates end :meth:`coordinates`), or None: the stage on the ground."""
        if not isinstance(self.model, HousedPlanetary):
            return None
        return self.model.housing.K, self.model.housing.M

    def housing_seats(self):
        """The seats the housed model's members join (indices, ascending), () unhoused."""
        if not isinstance(self.model, HousedPlanetary):
            return ()
        return tuple(sorted({seat for _, seat in self.model.seat_indices()}))

    def carrier_speed(self, input_speed):
        """The carrier's speed (rad/s) at the input member's ``input_speed``."""
        return self._speeds(as_float(input_speed))[0][0]

    def dof_names(self):
        return ("theta_c", "theta_r", "theta_s") + tuple(
            f"theta_{i + 1}" for i in range(self.stage.n_planets)
        )

    def matrices(self):
        model, st = TorsionalPlanetary(), self.stage
        r = jnp.concatenate(
            [
                jnp.stack([st.carrier.base_radius, st.ring.base_radius, st.sun.base_radius]),
                jnp.broadcast_to(st.planet.base_radius, (st.n_planets,)),
            ]
        )
        scale = r[:, None] * r[None, :]
        return scale * model.mass_matrix(st), scale * model.stiffness_matrix(st)

    def ends(self):
        # TorsionalPlanetary's order: u_c, u_r, u_s (Central's carrier, ring, sun)
        order = {Central.CARRIER: 0, Central.RING: 1, Central.SUN: 2}
        return order[self.input], order[self.output]


class PairGearboxStage(AbstractGearboxStage):
    """A parallel pair in the chain: pinion and wheel rotations (rad), their polar inertias
    (kg m^2, shape (2,)), base radii (m, shape (2,)) and the mean mesh stiffness along the line
    of action (N/m); ``input``: 0 when the pinion is driven by the previous stage, 1 the wheel
    (the other gear is the output). With a ``mesh`` (:class:`~jaxgear.MeshModel`, drive flanks
    only) its contact cells are the torsional pair's (:class:`jaxgear.scenes.TorsionalPair`'s
    structure vectors, on the mesh's base radii, the wheel's rotation counted in the chain's
    common sense)."""

    inertias: Float[Array, " 2"] = eqx.field(converter=as_float)
    base_radii: Float[Array, " 2"] = eqx.field(converter=as_float)
    mesh_stiffness: Float[Array, ""] = eqx.field(converter=as_float)
    input: int = eqx.field(static=True, default=1)
    mesh: MeshModel | None = None
    modifications: Modifications = eqx.field(default_factory=Modifications)

    def __check_init__(self):
        if self.input not in (0, 1):
            raise ValueError(f"input = {self.input!r}: out of range, allowed 0 (pinion), 1 (wheel)")
        if self.mesh is not None:
            check_instance("mesh", self.mesh, MeshModel, "a jaxgear.MeshModel",
                           "PairGearboxStage")
            if self.mesh.coast:
                raise ValueError("PairGearboxStage: mesh.coast = True: allowed False (the "
                                 "coupled model carries the loaded flanks)")

    # -- the coupled model: the pair's cells (or its constant spring ``mesh_stiffness``, one
    # cell of unit length) on the deflection cos(beta_b) (r_b1 theta_1 + r_b2 theta_2)
    def dynamic_parts(self, positions):
        m, _ = self.matrices()
        # the cells on the theoretical path (the mesh model's contact geometry)
        k_mean = mean_cell_stiffness(on_the_path(self).cell_row, self.mesh_period(), positions)
        z = jnp.zeros_like(m)
        return m, z, k_mean, jnp.zeros(2, m.dtype)

    def cell_row(self, x):
        r = self.base_radii
        if self.mesh is None:
            one = jnp.ones((1,), r.dtype)
            return CellRow(None, r[None, :], self.mesh_stiffness * one, one, 0.0 * one,
                           jnp.ones((1,), bool))
        cells, _, delta0 = separation(self.mesh, self.modifications,
                                      x / self.mesh.base_radius_pinion)
        # the torsional pair's structure vectors (jaxgear.scenes.TorsionalPair: each rotation
        # positive in its own direction of motion, the tip owner's lever ratio beyond the path)
        # on the chain's rotations, every one positive in one sense: the wheel's sign flipped
        V = TorsionalPair(self.mesh).cell_vectors(cells) * jnp.array([[[1.0, -1.0]]], r.dtype)
        return CellRow.of(cells, V, delta0)

    def mesh_forces(self, forces):
        c = 1.0 if self.mesh is None else jnp.cos(self.mesh.base_helix_angle)
        return c * jnp.sum(forces, axis=-1, keepdims=True)

    def mesh_names(self):
        return ("pair",)

    def mesh_period(self):
        if self.mesh is None:
            return jnp.asarray(0.01, self.base_radii.dtype)  # sets no time scale (no cells)
        return self.mesh.base_pitch

    def excited(self):
        return self.mesh is not None

    def kinematics(self, input_speed, input_torque):
        r_in, r_out = self.base_radii[self.input], self.base_radii[1 - self.input]
        w = as_float(input_speed)
        torque = jnp.abs(as_float(input_torque))
        return (-w * r_in / r_out, torque * r_out / r_in, r_in * jnp.abs(w),
                jnp.reshape(torque / r_in, (1,)))

    def dof_names(self):
        return ("theta_pinion", "theta_wheel")

    def matrices(self):
        r = self.base_radii
        return jnp.diag(self.inertias), self.mesh_stiffness * jnp.outer(r, r)

    def ends(self):
        return self.input, 1 - self.input


class GearboxTorsional(eqx.Module):
    """Stages in series (:class:`AbstractGearboxStage`), stage k's output member joined to stage
    k+1's input member by a shaft of torsional stiffness ``shaft_stiffnesses[k]`` (N m/rad,
    shape (n_stages - 1,)). The chain's coordinates are the stages' in order.

    ``housing``: one flexible :class:`~jaxgear.scenes.Housing` that the stages share
    (docs/gearbox.md, "One housing for several stages"), or None. Each stage that sits in it is
    a :class:`~jaxgear.gearbox.LumpedPairGearboxStage` whose scene was built with this same
    condensed housing (``lumped_pair(..., housing=, seats=)``, the housing placed in that
    scene's frame, with the same loss factor): its bearings are joined to its seats there, by
    the scenes' one seat coupling; or a :class:`PlanetaryGearboxStage` whose model is a
    :class:`~jaxgear.planetary.HousedPlanetary` on this same condensed housing (placed in the
    stage's frame, the stage axis its +z): its held member's torsional support joined to its
    seat by the same coupling. The coupled model (:func:`gearbox_coupled_modes`,
    :func:`gearbox_dynamics`, :func:`gearbox_whine`) then keeps the housing's coordinates
    once, after every stage's own, and its K_h, M_h and damping C_h once. Stages without a
    housing (torsional, an unhoused planetary model, a grounded lumped stage) stay on the
    ground. The torsional chain's view (:meth:`matrices`, :func:`gearbox_modes`) does not take
    a shared housing.

    Raises:
        ValueError: no stages; ``shaft_stiffnesses`` of another shape; ``housing`` not a
            :class:`~jaxgear.scenes.Housing`, carried by no stage, or another housing than a
            stage's (its size, stiffness or mass differ); a seat a planetary stage's member
            joins that another stage joins too (one line each).
    """

    stages: tuple[AbstractGearboxStage, ...]
    shaft_stiffnesses: Float[Array, " n_shafts"] = eqx.field(converter=as_float)
    housing: Housing | None = None

    def __check_init__(self):
        if len(self.stages) < 1:
            raise ValueError("stages: empty, allowed at least one stage")
        if self.shaft_stiffnesses.shape != (len(self.stages) - 1,):
            raise ValueError(
                f"shaft_stiffnesses: shape {self.shaft_stiffnesses.shape}, allowed "
                f"({len(self.stages) - 1},) (one per pair of consecutive stages)"
            )
        if self.housing is not None:
            _check_housing(self.stages, self.housing)

    def offsets(self) -> tuple[int, ...]:
        """Where each stage's rotations start in the chain's coordinates."""
        out, n = [], 0
        for s in self.stages:
            out.append(n)
            n += len(s.dof_names())
        return tuple(out)

    def dof_names(self) -> tuple[str, ...]:
        """``"<k>:<name>"`` per coordinate, k the stage's index from 1."""
        return tuple(f"{k + 1}:{n}" for k, s in enumerate(self.stages) for n in s.dof_names())

    def stage_of_dof(self) -> tuple[int, ...]:
        """Each coordinate's stage index (from 0)."""
        return tuple(k for k, s in enumerate(self.stages) for _ in s.dof_names())

    @eqx.filter_jit
    def matrices(self) -> tuple[Float[Array, "n n"], Float[Array, "n n"]]:
        """(M, K) of the chain: kg m^2, N m/rad."""
        blocks = [s.matrices() for s in self.stages]
        mass = jax.scipy.linalg.block_diag(*[m for m, _ in blocks])
        stiff = jax.scipy.linalg.block_diag(*[k for _, k in blocks])
        # the shafts: twist b theta, b = e_out(k) - e_in(k + 1), strain energy k_t (b theta)^2 / 2
        offsets = self.offsets()
        b = np.zeros((len(self.stages) - 1, mass.shape[0]))
        for j in range(len(self.stages) - 1):
            b[j, offsets[j] + self.stages[j].ends()[1]] = 1.0
            b[j, offsets[j + 1] + self.stages[j + 1].ends()[0]] = -1.0
        b = jnp.asarray(b, dtype=mass.dtype)
        stiff = stiff + b.T @ (self.shaft_stiffnesses[:, None] * b)
        return mass, stiff


def _check_housing(stages, housing):
    """Refuse a gearbox-level ``housing`` that no stage carries or that is not each carrying
    stage's own (its K_h and M_h, compared where the arrays are concrete)."""
    check_instance("housing", housing, Housing, "a jaxgear.scenes.Housing or None",
                   "GearboxTorsional")
    h = housing.size
    carried = 0
    for k, s in enumerate(stages):
        own = s.housing()
        if own is None:
            continue
        carried += 1
        if own[0].shape != (h, h):
            raise ValueError(f"GearboxTorsional: housing has {h} coordinates, stage {k + 1}'s "
                             f"scene's housing {own[0].shape[0]}: allowed the same housing")
        concrete = not any(isinstance(a, jax.core.Tracer)
                           for a in (*own, housing.K, housing.M))
        if concrete and not all(
                np.allclose(np.asarray(a), np.asarray(b), rtol=1e-12, atol=1e-12 * scale)
                for a, b, scale in ((own[0], housing.K, float(np.abs(housing.K).max())),
                                    (own[1], housing.M, float(np.abs(housing.M).max())))):
            raise ValueError(f"GearboxTorsional: housing's stiffness or mass differs from stage "
                             f"{k + 1}'s scene's housing: allowed the same condensed housing")
    if carried == 0:
        raise ValueError("GearboxTorsional: housing is given but no stage sits in it: allowed "
                         "None, or a LumpedPairGearboxStage whose scene is built with "
                         "housing=, or a PlanetaryGearboxStage whose model is a "
                         "HousedPlanetary (torsional stages stay on the ground)")
    # a seat a planetary stage's member is bolted to is that member's alone
    for k, s in enumerate(stages):
        if not isinstance(s, PlanetaryGearboxStage):
            continue
        for seat in s.housing_seats():
            for j, other in enumerate(stages):
                if j != k and seat in other.housing_seats():
                    raise ValueError(
                        f"GearboxTorsional: seat {housing.seat_names[seat]!r} ({seat}) is used "
                        f"twice, by stage {k + 1}'s planetary member and by stage {j + 1}: "
                        "allowed a seat of its own for each planetary member")


class GearboxModes(eqx.Module):
    """The chain's natural modes: ``frequencies`` (Hz, ascending, shape (n,)), ``shapes``
    (rad, (n, n), column j mass-normalised: phi^T M phi = I) and ``stage_energy`` ((n_stages, n):
    each mode's kinetic energy share per stage, columns summing to 1)."""

    frequencies: Float[Array, " n"]
    shapes: Float[Array, "n n"]
    stage_energy: Float[Array, "s n"]


@eqx.filter_jit
def gearbox_modes(chain: GearboxTorsional) -> GearboxModes:
    """The undamped natural modes of the chain, ``K phi = omega^2 M phi``, through
    :func:`jaxgear.dynamics.modal_analysis` (the one modal solve: Cholesky factor of M,
    ``jnp.linalg.eigh``); a free chain (no member held) has one rigid-body mode at 0 Hz.

    Raises:
        ValueError: ``chain`` not a :class:`GearboxTorsional` (one line)."""
    check_instance("chain", chain, GearboxTorsional, "a jaxgear.gearbox.GearboxTorsional",
                   "gearbox_modes")
    if chain.housing is not None:
        raise ValueError("gearbox_modes: chain.housing is set: the torsional chain's view "
                         "condenses each stage alone and cannot share a housing; allowed a "
                         "chain without one (the coupled modes: gearbox_coupled_modes)")

    m, k = chain.matrices()
    modes = matrix_modal_analysis(m, k, jnp.zeros_like(k))
    shapes = modes.shapes
    energy = shapes * (m @ shapes)  # each coordinate's share (M diagonal per stage block)
    owner = np.asarray(chain.stage_of_dof())  # static: the indicator of each stage's rotations
    belongs = jnp.asarray(owner[None, :] == np.arange(len(chain.stages))[:, None], energy.dtype)
    per_stage = belongs @ energy
    per_stage = per_stage / per_stage.sum(axis=0, keepdims=True)
    return GearboxModes(modes.frequency, shapes, per_stage)
