"""Torsional scenes: rotations of the pinion and gear (and of a motor and a load), quasi-static
and dynamic, and the 1-DOF relative-approach reduction (seed (2.31); docs/design.md, "Structure
and dynamics").
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._backlash import cell_flank
from .._baseplane import CellRow, MeshModel
from .._contact_geometry import rolling_lever
from .._util import as_float, check_instance, check_real
from ._gear_mesh import GearMesh, pair_mesh
from ._interface import TorsionalMember
from ._rigid import RigidMesh
from ._scene import DynamicScene, Scene, _check_meshes
from ._structure import AssembledScene, Structure
from ._train import (
    GearTrain,
    TrainSpec,
    mesh_period_ratios,
    mesh_teeth,
    scene_span,
    shaft_speeds,
    shaft_torques,
)

__all__ = [
    "RelativeApproach",
    "TorsionalDynamics",
    "TorsionalPair",
    "TorsionalTrain",
    "disc_inertia",
    "torsional_train",
]


class TorsionalPair(Scene):
    """Two rotations X = (θ1, θ2) (rad, each positive in its direction of motion).

    The pinion carries the input torque T; the gear is held by an output shaft of torsional
    stiffness ``output_stiffness`` (N·m/rad) to a fixed load. Approach: V = cos β_b (r_b1, −r_b2)
    on the drive flanks, its negative on the coast flanks; beyond the theoretical path
    (``mesh.contact_geometry``) :meth:`cell_vectors` (the exact gap derivative) has the tip
    owner's entry λ(s) times its own (its lever arm, :meth:`jaxgear.MeshModel.corner`), and
    :meth:`cell_row`, what the solves take, the pinion's own lever on both entries: the exact
    derivative less its part along the pair's rolling, the gear held
    (:func:`~jaxgear._contact_geometry.rolling_lever`; docs/extended-contact.md, "The pair's
    rolling"). The output shaft's twist rolls the pair; that rolling closes no corner, and the
    result is :class:`RigidMesh`'s (the pinion's advance with the gear held) whatever the
    shaft.
    The transmission error is independent of the shaft stiffness (statically determinate chain),
    beyond the path too, which the tests use as a check of the structure-vector plumbing.
    """

    mesh: MeshModel
    output_stiffness: Float[Array, ""] = eqx.field(converter=as_float, default=1e5)

    def __check_init__(self):
        where = "TorsionalPair"
        check_instance("mesh", self.mesh, MeshModel, "a jaxgear.MeshModel", where)
        check_real(
            "output_stiffness", self.output_stiffness, "N·m/rad", lo=0.0, lo_open=True, where=where
        )

    def _v(self):
        cb = jnp.cos(self.mesh.base_helix_angle)
        return jnp.stack([cb * self.mesh.base_radius_pinion, -cb * self.mesh.base_radius_gear])

    def stiffness(self):
        z = jnp.zeros_like(self.output_stiffness)
        return jnp.stack([jnp.stack([z, z]), jnp.stack([z, self.output_stiffness])])

    def external_load(self, torque):
        return jnp.stack([torque, jnp.zeros_like(torque)])

    def cell_vectors(self, cells):
        v = cell_flank(cells)[..., None] * self._v()[None, None, :]
        # beyond the path the tip owner's lever arm is λ r_bT (docs/extended-contact.md)
        levers = self.mesh.contact_geometry.lever_ratios(self.mesh, cells.s)
        return v * jnp.stack([jnp.broadcast_to(lv, cells.s.shape) for lv in levers], axis=-1)

    def cell_row(self, cells, delta0):
        """The cells in one row (:meth:`~jaxgear.scenes.Scene.cell_row`), beyond the path with
        the pinion's lever ratio on both rotations (the gear held: weights (1, 0) of
        :func:`~jaxgear._contact_geometry.rolling_lever`); on the path :meth:`cell_vectors`'
        rows."""
        _check_meshes(self, cells)
        c = cells[0]
        mesh = self.mesh
        lever = rolling_lever(*mesh.contact_geometry.lever_ratios(mesh, c.s), (1.0, 0.0))
        lever = jnp.broadcast_to(lever, c.s.shape)
        V = cell_flank(c)[..., None] * self._v()[None, None, :] * lever[..., None]
        return CellRow.of(c, V, delta0[0])

    def te_vector(self):
        return self._v()


def disc_inertia(density: float, radius: float, width: float) -> float:
    """Polar moment of inertia ρ π b r⁴ / 2 of a solid disc (kg·m²): a gear blank of tip radius
    ``radius`` (m) and face width ``width`` (m)."""
    return density * math.pi * width * radius**4 / 2.0


class TorsionalDynamics(AssembledScene, DynamicScene):
    """Torsional model: (motor,) pinion, gear (, load) rotations (rad, each positive in its
    direction of motion), seed I-3; docs/dynamics.md, "Scenes". A structure of one-rotation
    nodes (:class:`~jaxgear.scenes.Structure` with ``node_dofs = 1``) with one gear mesh between
    two :class:`~jaxgear.scenes.TorsionalMember` (V = cos β_b (r_b1, −r_b2) on the pinion and
    gear rotations).

    Args:
        mesh: the gear mesh (:class:`jaxgear.MeshModel`).
        inertia_pinion, inertia_gear: polar inertias I1, I2 (kg·m²).
        inertia_motor, inertia_load: motor and load inertias (kg·m²), used with ``has_motor`` /
            ``has_load``.
        shaft_motor, shaft_load: torsional stiffnesses of the motor-pinion and gear-load shafts
            (N·m/rad), used likewise.
        has_motor, has_load: static flags (DOF count 2 + has_motor + has_load; the input torque
            acts on the first rotation, the balancing output torque on the last).

    The structure's stiffness parts are ``motor_shaft`` and ``load_shaft`` (those present); it
    has no bearing.
    """

    def __init__(
        self,
        mesh: MeshModel,
        inertia_pinion,
        inertia_gear,
        inertia_motor=1.0,
        inertia_load=1.0,
        shaft_motor=1e5,
        shaft_load=1e5,
        *,
        has_motor: bool = False,
        has_load: bool = False,
    ):
        where = "TorsionalDynamics"
        check_instance("mesh", mesh, MeshModel, "a jaxgear.MeshModel", where)
        for name, v in (
            ("inertia_pinion", inertia_pinion),
            ("inertia_gear", inertia_gear),
            ("inertia_motor", inertia_motor),
            ("inertia_load", inertia_load),
        ):
            check_real(name, v, "kg·m²", lo=0.0, lo_open=True, where=where)
        for name, v in (("shaft_motor", shaft_motor), ("shaft_load", shaft_load)):
            check_real(name, v, "N·m/rad", lo=0.0, lo_open=True, where=where)
        n = 2 + int(has_motor) + int(has_load)
        p, g = int(has_motor), int(has_motor) + 1
        dtype = jnp.result_type(float)
        eye = jnp.eye(n, dtype=dtype)
        inertias = [as_float(inertia_pinion), as_float(inertia_gear)]
        if has_motor:
            inertias = [as_float(inertia_motor)] + inertias
        if has_load:
            inertias = inertias + [as_float(inertia_load)]
        names, parts = [], []
        if has_motor:
            e = eye[0] - eye[p]
            names.append("motor_shaft")
            parts.append(as_float(shaft_motor) * jnp.outer(e, e))
        if has_load:
            e = eye[g] - eye[g + 1]
            names.append("load_shaft")
            parts.append(as_float(shaft_load) * jnp.outer(e, e))
        parts_K = jnp.stack(parts) if parts else jnp.zeros((0, n, n), dtype)
        zeros = jnp.zeros((n, n), dtype)
        self.structure = Structure(
            K=jnp.sum(parts_K, axis=0),
            M=jnp.diag(jnp.stack(inertias)),
            parts_K=parts_K,
            C_bearing=jnp.zeros((0, 0), dtype),
            reaction=jnp.zeros((0, n), dtype),
            gyroscopic=zeros,
            spin_stiffness=zeros,
            f_centrifugal=jnp.zeros((n,), dtype),
            part_names=tuple(names),
            reaction_names=(),
            reaction_member=(),
            nodes=(("pinion", p), ("gear", g), ("input", 0), ("output", n - 1)),
            node_dofs=1,
        )
        cb = jnp.cos(mesh.base_helix_angle)
        te = cb * mesh.base_radius_pinion * eye[p] - cb * mesh.base_radius_gear * eye[g]
        origin = jnp.zeros((3,), dtype)
        # a torsional mesh has no place in space: its line of action stays at the origin (the
        # members' vectors do not depend on it)
        line = {"tangent_point": origin, "direction": origin, "normal": origin, "roll_start": 0.0}
        line.update(coast_tangent_point=origin, coast_direction=origin, coast_normal=origin)
        self.members = (TorsionalMember(p), TorsionalMember(g))
        self.meshes = (pair_mesh(mesh, line, te),)
        ratio = mesh.base_radius_gear / mesh.base_radius_pinion
        self.f_torque = eye[0] - ratio * eye[n - 1]

    @property
    def n_dof(self) -> int:
        return self.structure.size

    @property
    def has_motor(self) -> bool:
        """A motor rotation drives the pinion through the motor shaft."""
        return "motor_shaft" in self.structure.part_names

    @property
    def has_load(self) -> bool:
        """The gear drives a load rotation through the load shaft."""
        return "load_shaft" in self.structure.part_names

    @property
    def pinion_index(self) -> int:
        return self.structure.node("pinion")

    @property
    def gear_index(self) -> int:
        return self.structure.node("gear")

    @property
    def inertia_pinion(self) -> Float[Array, ""]:
        """I1 (kg·m²)."""
        return self.structure.M[self.pinion_index, self.pinion_index]

    @property
    def inertia_gear(self) -> Float[Array, ""]:
        """I2 (kg·m²)."""
        return self.structure.M[self.gear_index, self.gear_index]

    def stage_senses(self):
        """+1 for the rotations on the pinion's side (motor, pinion), −1 on the gear's (gear,
        load): each rotation counted positive in the pinion's direction of motion, the common
        sense of a gearbox stage."""
        n = self.n_dof
        return jnp.where(jnp.arange(n) <= self.pinion_index, 1.0, -1.0).astype(
            self.structure.M.dtype
        )

    def stage_coordinates(self):
        """``theta_motor``, ``theta_pinion``, ``theta_wheel``, ``theta_load`` (those present)."""
        names = ("theta_pinion", "theta_wheel")
        return (("theta_motor",) if self.has_motor else ()) + names + (
            ("theta_load",) if self.has_load else ()
        )

    def rigid_modes(self):
        # the pair's rigid rotation: its gear ratio (every mesh of the pair's structure, such as
        # the halves of a split face, has the same base radii)
        pair = self.meshes[0].base_plane
        rp, rg = 1.0 / pair.base_radius_pinion, 1.0 / pair.base_radius_gear
        r = jnp.where(jnp.arange(self.n_dof) <= self.pinion_index, rp, rg)
        return r[:, None]

    def reduced(self) -> RelativeApproach:
        """The 1-DOF relative-approach reduction (only for a rigid pinion-gear chain)."""
        if self.has_motor or self.has_load:
            raise ValueError(
                "the relative-approach reduction needs a pinion-gear pair without "
                "motor/load shafts: drop them or use the full torsional model"
            )
        cb = jnp.cos(self.mesh.base_helix_angle)
        m_eq = 1.0 / (
            cb**2
            * (
                self.mesh.base_radius_pinion**2 / self.inertia_pinion
                + self.mesh.base_radius_gear**2 / self.inertia_gear
            )
        )
        return RelativeApproach(self.mesh, m_eq)


class TorsionalTrain(GearTrain):
    """A torsional gear train (seed I-3 with several meshes): one rotation per shaft (rad, each
    positive in its shaft's direction of motion), no place in space. Build with :meth:`of` from
    the train's :class:`~jaxgear.scenes.TrainSpec` (or :func:`torsional_train`)."""

    @classmethod
    def of(cls, spec: TrainSpec) -> TorsionalTrain:
        """The torsional scene of the train ``spec``: one rotation per shaft (a compound gear's
        gears turn together) with the polar inertias of its gears, each mesh between the
        rotations of its gears' shafts at the spec's phase (:attr:`TrainSpec.mesh_phases`), the
        input torque on rotation 0 and the loads' shares (:func:`shaft_torques`).

        Mesh k takes its cells at θ_k = ω_g θ + phase_k, ω_g the driving shaft's angle per unit
        input angle (r_b,0 / r_b,g through the train, from the tooth counts).

        Raises:
            ValueError: a mesh whose driving shaft is not yet turning, a shaft driven twice, an
                output shaft with no share but the balancing one (or none left for it), shares
                out of range, or meshes that repeat together only after more than
                ``MAX_SCENE_PERIODS`` periods of the first.
        """
        n = spec.n_shafts
        inertias = [None] * n
        for g, (_, j) in enumerate(spec.inertias):
            s = spec.shaft_of[g]
            inertias[s] = j if inertias[s] is None else inertias[s] + j
        links = spec.links
        # speed ratios and periods from the tooth counts: exact in float32 too
        teeth = [mesh_teeth(p) for p, _ in spec.meshes]
        omega = shaft_speeds(links, teeth, n)
        dtype = jnp.result_type(float)
        eye = jnp.eye(n, dtype=dtype)
        phases = spec.mesh_phases
        out, periods = [], []
        for k, ((plane, _), (g, h)) in enumerate(zip(spec.meshes, links, strict=True)):
            periods.append(2.0 * math.pi / teeth[k][0] / omega[g])  # the period T_k (input rad)
            cb = jnp.cos(plane.base_helix_angle)
            te = cb * plane.base_radius_pinion * eye[g] - cb * plane.base_radius_gear * eye[h]
            origin = jnp.zeros((3,), dtype)
            out.append(
                GearMesh(
                    plane,
                    origin,
                    origin,
                    origin,
                    0.0,
                    te,
                    gears=(g, h),
                    ratio=omega[g],
                    phase=phases[k],
                )
            )
        torques, o = shaft_torques(links, omega, spec.shares)
        zeros = jnp.zeros((n, n), dtype)
        structure = Structure(
            K=zeros,
            M=jnp.diag(jnp.stack([as_float(i) for i in inertias])),
            parts_K=jnp.zeros((0, n, n), dtype),
            C_bearing=jnp.zeros((0, 0), dtype),
            reaction=jnp.zeros((0, n), dtype),
            gyroscopic=zeros,
            spin_stiffness=zeros,
            f_centrifugal=jnp.zeros((n,), dtype),
            part_names=(),
            reaction_names=(),
            reaction_member=(),
            nodes=(("input", 0), ("output", o), *((f"gear{i}", i) for i in range(n))),
            node_dofs=1,
        )
        rb0 = float(spec.meshes[0][0].base_radius_pinion)
        return cls(
            structure=structure,
            meshes=tuple(out),
            members=tuple(TorsionalMember(i) for i in range(n)),
            f_torque=sum((t * eye[g] for g, t in torques.items()), jnp.zeros((n,), dtype)),
            rigid=jnp.asarray([w / rb0 for w in omega], dtype),
            periods=scene_span(periods),
            period_ratios=mesh_period_ratios(periods),
        )


def torsional_train(meshes, inertias, phases=None, shares=None) -> TorsionalTrain:
    """A torsional gear train from its meshes (seed I-3 with several meshes): one rotation per
    gear (rad, each positive in its gear's direction of motion), no shaft;
    :meth:`TorsionalTrain.of` of the :class:`~jaxgear.scenes.TrainSpec` of these arguments.

    Args:
        meshes: ((mesh model, (driving, driven)), ...), the gears numbered 0 … n−1, gear 0 the
            input, each mesh's model with the driving gear as its pinion, listed from the input
            outwards (a mesh's driving gear is the input or driven by an earlier mesh).
        inertias: polar inertias (kg·m²) of the gears, (n,).
        phases: each mesh's phase (rad, :attr:`GearMesh.phase`; default 0; from the layout:
            :func:`train_phases`).
        shares: ``{gear: share}``, the share of the input power each loaded gear takes (0 <
            share, their sum < 1), every gear but the input and one output, the balancing
            output, which takes the rest (default: none; then the train has one output).
            The load pattern per unit input torque: gear j's torque is −share_j T ω_0/ω_j
            (:func:`shaft_torques`).

    Returns:
        the :class:`TorsionalTrain` (:meth:`TorsionalTrain.of`).

    Raises:
        ValueError: what :meth:`TorsionalTrain.of` refuses.

    A gear index is a rotation: a compound gear (two gears on one rigid shaft, the wheel of one
    stage and the pinion of the next) is one index, driven in one mesh and driving the next,
    with the inertia of both; its meshes' phases then depend on how the two are clocked on the
    shaft, which the caller gives.
    """
    spec = TrainSpec(
        tuple(meshes),
        inertias=tuple((None, j) for j in inertias),
        phases=None if phases is None else tuple(phases),
        shares=shares,
    )
    return TorsionalTrain.of(spec)


class RelativeApproach(DynamicScene):
    """1-DOF relative approach x (m, flank-normal) with equivalent mass m_eq (kg); V = 1.

    The external load is the static normal mesh force F_n = T/(r_b1 cos β_b) (N). Beyond the
    theoretical path (``mesh.contact_geometry``) V stays 1: the corner cells act along the line
    of action with the base radii (the approach of the two gears' rotations together cannot
    carry the tip owner's shorter lever arm; docs/extended-contact.md)."""

    mesh: MeshModel
    equivalent_mass: Float[Array, ""] = eqx.field(converter=as_float)

    def mass(self):
        return jnp.reshape(self.equivalent_mass, (1, 1))

    def stiffness_parts(self):
        return {}

    # the structure is the rigid mesh's; only the mass is added
    def stiffness(self):
        return RigidMesh(self.mesh).stiffness()

    def external_load(self, torque):
        return RigidMesh(self.mesh).external_load(torque)

    def cell_vectors(self, cells):
        return cell_flank(cells)[..., None]

    def te_vector(self):
        return RigidMesh(self.mesh).te_vector()

    def rigid_modes(self):
        return jnp.zeros((1, 0), dtype=self.mesh.face_width.dtype)
