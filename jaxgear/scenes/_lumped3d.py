"""3D lumped-parameter scene: rigid gear nodes on Timoshenko shafts with bearings (seed I-3, (2.9)).

Frame: z along the (parallel) axes, pinion axis through the origin, gear axis through (a_w, 0);
the line of action and the contact points are those of :mod:`._gear_mesh`. Each shaft node has 6
DOF (u_x, u_y, u_z, φ_x, φ_y, φ_z). The approach of cell M is (d1(M) − d2(M))·n with
d_i(M) = u_i + φ_i × (M − O_i) at the gear nodes, i.e. the structure vector

    V(M) = [n, (M − O1) × n, −n, −(M − O2) × n]      (seed (2.9), at the two gear nodes:
                                                      :class:`~jaxgear.scenes.RigidMember`),

and for a pure rotation it reduces to the torsional V = cos β_b (r_b1, −r_b2) with θ1 = φ_z1 and
θ2 = −φ_z2.

The shafts and bearings are :mod:`._shaft`'s; a pair's two shafts (:func:`lumped_pair`) or a
train's (:class:`LumpedTrain`, built from its :class:`~jaxgear.scenes.TrainSpec`) are assembled
block-diagonally with a rigid gear body at each gear node.
"""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._baseplane import MeshModel
from .._geometry import GearPair
from ._gear_mesh import GearMesh, line_of_action, mesh_line, pair_mesh
from ._housing import Housing, bearing_positions
from ._mount import check_housing_position, couple_housing, housing_nodes
from ._interface import RigidMember
from ._scene import DynamicScene
from ._shaft import ShaftSpec, _add_gear_body, _shaft_arrays, _shaft_structure
from ._structure import AssembledScene
from ._train import (
    GearTrain,
    TrainSpec,
    mesh_period_ratios,
    mesh_teeth,
    scene_span,
    shaft_torques,
)

__all__ = [
    "LumpedPair",
    "LumpedTrain",
    "Wrench",
    "lumped_pair",
    "lumped_train",
    "mesh_wrench",
]


class LumpedPair(AssembledScene, DynamicScene):
    """Two shafts with rigid gear nodes and bearings (build with :func:`lumped_pair`).

    Attributes:
        structure: the assembled shafts, bearings and gear bodies
            (:class:`~jaxgear.scenes.Structure`; its parts ``pinion_shaft``, ``gear_shaft``,
            ``bearings``).
        meshes: the gear meshes (:class:`~jaxgear.scenes.GearMesh`).
        members: the gear members (pinion, gear), :class:`~jaxgear.scenes.RigidMember`.
        rigid: the rigid-body rotation mode (n,) (V·r = 0, F·r = 0).
    """

    rigid: Float[Array, " n"]
    #: its bearings sit in a housing (``lumped_pair(..., housing=)``)
    takes_housing: ClassVar[bool] = True

    def rigid_modes(self):
        return self.rigid[:, None]



def _lumped_arrays(
    pair: GearPair,
    pinion_shaft: ShaftSpec,
    gear_shaft: ShaftSpec,
    masses,
    inertias,
    E: float,
    nu: float,
    rho: float,
    extra_z=((), ()),
) -> dict:
    """NumPy parts of the lumped pair (shared by :func:`lumped_pair` and the hybrid scene):
    :func:`_shaft_arrays` of the two shafts ``pinion`` and ``gear``, the gear bodies and the
    pair's rigid rotation.

    ``extra_z``: additional shaft node positions per shaft (m from the shaft start), e.g. where a
    condensed body's bearing nodes attach. A member whose mass is ``None`` gets no rigid gear
    body at its gear node (a condensed body replaces it).
    """
    d = _shaft_arrays((pinion_shaft, gear_shaft), ("pinion", "gear"), E, nu, rho, extra_z)
    s1, s2 = d["mats"]
    n1 = d["shaft_offsets"][1]
    n = d["M"].shape[0]
    g1, g2 = 6 * s1.gear_node, n1 + 6 * s2.gear_node
    for g, m, inertia in ((g1, masses[0], inertias[0]), (g2, masses[1], inertias[1])):
        if m is not None:
            _add_gear_body(d["M"], g, m, inertia)
    rigid = np.zeros(n)
    rigid[5:n1:6] = 1.0 / pair.base_radii[0]
    rigid[n1 + 5 :: 6] = -1.0 / pair.base_radii[1]
    return dict(
        d,
        rigid=rigid,
        gear_dofs=(g1, g2),  # first DOF of each gear node
        nodes=(
            ("pinion", g1),
            ("gear", g2),
            ("input", 6 * s1.torque_node),
            ("output", n1 + 6 * s2.torque_node),
        ),
    )


def lumped_pair(
    pair: GearPair,
    mesh: MeshModel,
    pinion_shaft: ShaftSpec,
    gear_shaft: ShaftSpec,
    *,
    masses: tuple[float, float],
    inertias: tuple[tuple[float, float], ...],
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
    density: float = 7800.0,
    housing: Housing | None = None,
    seats=None,
    housing_position=None,
) -> LumpedPair:
    """Assemble the 3D lumped scene.

    Args:
        pair, mesh: the gear pair and its mesh model.
        pinion_shaft, gear_shaft: :class:`ShaftSpec` of each shaft (z from the shaft start).
        masses: gear body masses (kg), added at the gear nodes.
        inertias: ((I_diametral, I_polar) pinion, (…) gear) (kg·m²) of the gear bodies.
        youngs_modulus, poisson_ratio, density: shaft material.
        housing: a flexible :class:`~jaxgear.scenes.Housing` the bearings join the shafts to
            (its coordinates after the shafts'; the structure's part ``housing`` and nodes
            ``housing <seat>``), or None: the bearings hold the shafts to the ground. Scene
            frame: the pinion's axis is the z axis, the gear's through (a_w, 0), both gears'
            centres at z = 0 (a shaft position s lies at z = s − its ``gear_z``).
        seats: with ``housing``, each bearing's seat index (pinion's bearings, then the
            gear's), an entry None keeping that bearing on the ground; None: the seat nearest
            each bearing.
        housing_position: with ``housing``, t (3,) (m): this scene's origin in the frame the
            housing is placed in, the scene axes parallel to it (a gearbox frame whose one
            housing several stages share, docs/gearbox.md, "One housing for several
            stages"); the bearings' joints sit at their scene points plus t. None: the
            housing is placed in this scene's frame (t = 0).

    Raises:
        ValueError: what :func:`~jaxgear.scenes._mount.couple_housing` refuses (a seat index
            out of range, ``seats`` of another length), a ``housing_position`` without a
            ``housing`` or not 3 finite numbers (one line, before any work).
    """
    check_housing_position(housing, housing_position, "lumped_pair")
    d = _lumped_arrays(
        pair, pinion_shaft, gear_shaft, masses, inertias, youngs_modulus, poisson_ratio, density
    )
    line = line_of_action(pair)
    d = _housed(
        d,
        (pinion_shaft, gear_shaft),
        line["centres"],
        (pinion_shaft.gear_positions[0], gear_shaft.gear_positions[0]),
        housing,
        seats,
        position=housing_position,
    )
    members = tuple(
        RigidMember(line["centres"][m], tuple(range(g, g + 6)))
        for m, g in enumerate(d["gear_dofs"])
    )
    n = d["M"].shape[0]
    # angular TE at the gear bodies, cos β_b (r_b1 φ_z1 + r_b2 φ_z2) (the gear turns about −z)
    te = np.zeros(n)
    cb = math.cos(pair.base_helix_angle)
    te[members[0].dofs[5]], te[members[1].dofs[5]] = (
        cb * pair.base_radii[0],
        cb * pair.base_radii[1],
    )
    # input torque about +z on the pinion shaft; the load resists the gear's −z rotation
    t_in, t_out = (dict(d["nodes"])[k] + 5 for k in ("input", "output"))
    f_torque = np.zeros(n)
    f_torque[t_in] += 1.0
    f_torque[t_out] += pair.base_radii[1] / pair.base_radii[0]
    structure = _shaft_structure(
        d,
        ("pinion_shaft", "gear_shaft", "bearings") + (("housing",) if housing is not None else ()),
        d["nodes"],
    )
    return LumpedPair(
        structure=structure,
        meshes=(pair_mesh(mesh, line, te),),
        members=members,
        f_torque=jnp.asarray(f_torque),
        rigid=jnp.asarray(d["rigid"]),
    )


def _housed(d: dict, shafts, centres, gear_z, housing, seats, frames=None,
            position=None) -> dict:
    """``d`` with ``housing`` coupled (:func:`couple_housing`, each shaft's frame angle
    ``frames``, the scene origin at ``position`` in the housing's frame): the rigid rotation
    padded, the seats' nodes named."""
    if housing is None:
        return d
    n = d["M"].shape[0]
    out = couple_housing(
        d, shafts, bearing_positions(shafts, centres, gear_z), housing, seats, frames,
        position,
    )
    out["nodes"] = (*d["nodes"], *housing_nodes(housing, n))
    if "rigid" in d:
        out["rigid"] = np.concatenate([d["rigid"], np.zeros(housing.size)])
    return out


@dataclasses.dataclass(frozen=True)
class Wrench:
    """An external force and moment on a shaft node, per unit input torque (the loads of a
    train scale with its input torque, as its output torques do).

    Attributes:
        shaft: the shaft's index. z: the node's position along the shaft (m from its start).
        force: (F_x, F_y, F_z) per unit input torque (N per N·m), fixed frame.
        moment: (M_x, M_y, 0) per unit input torque (N·m per N·m), fixed frame. A torque about
            the shaft axis is an output torque (a share of the input power), not a wrench.

    Raises:
        ValueError: a moment about the shaft axis, or a non-finite component.
    """

    shaft: int
    z: float
    force: tuple = (0.0, 0.0, 0.0)
    moment: tuple = (0.0, 0.0, 0.0)

    def __post_init__(self):
        f, m = (tuple(float(v) for v in x) for x in (self.force, self.moment))
        if len(f) != 3 or len(m) != 3 or not all(math.isfinite(v) for v in f + m):
            raise ValueError(f"Wrench: force {f} and moment {m} must be 3 finite numbers each")
        if m[2] != 0.0:
            raise ValueError(
                f"Wrench: moment z = {m[2]:.6g} must be 0 (a torque about the shaft axis is an "
                "output torque: a share of the input power)"
            )
        object.__setattr__(self, "force", f)
        object.__setattr__(self, "moment", m)


def mesh_wrench(line: dict, base_plane: MeshModel, normal_force: float, centre) -> tuple:
    """The mean mesh force on a mesh's driving gear as a wrench at its centre (NumPy): the force
    −F_n n acting at the centre of the contact zone (:func:`~jaxgear.scenes.mesh_line`), which
    an engineer puts in place of a stage left out of a model (the seed, III-3.1: the low-speed
    stage as external forces and couples on the intermediate shaft).

    Args:
        line: the mesh's :func:`line_of_action` (as placed). base_plane: its mesh model.
        normal_force: F_n (N). centre: the driving gear's centre (m), (3,).

    Returns:
        (force (3,) in N, moment (3,) in N·m about ``centre``, its z component the torque
        −F_n cos β_b r_b1 (the driving gear's input torque reacted), fixed frame).
    """
    zone = np.asarray(
        mesh_line(
            line["tangent_point"],
            line["direction"],
            line["normal"],
            line["roll_start"],
            base_plane,
        )["zone"]
    )
    force = -normal_force * np.asarray(line["normal"], float)
    return force, np.cross(zone - np.asarray(centre, float), force)


class LumpedTrain(GearTrain):
    """A lumped 3D gear train: parallel shafts on bearings carrying rigid gear nodes, one mesh
    per pair of gears in contact (seed I-3 and (2.9) with several meshes), 6 DOFs per shaft
    node. Build with :meth:`of` from the train's :class:`~jaxgear.scenes.TrainSpec`."""

    #: its bearings sit in a housing (``LumpedTrain.of(..., housing=)``)
    takes_housing: ClassVar[bool] = True

    @classmethod
    def of(cls, spec: TrainSpec, housing: Housing | None = None, seats=None, *,
           housing_position=None) -> LumpedTrain:
        """The lumped 3D scene of the train ``spec`` (its layout, shafts, gear bodies, loads
        and material).

        Each shaft is a Timoshenko beam (:func:`shaft_matrices`) on its bearings, along +z
        through its gears' centre in the layout; its gears sit at their positions along it
        (:attr:`ShaftSpec.gear_positions`) and each mesh's cells act on the two gear nodes
        through V = [n, (M − O) × n] (:class:`~jaxgear.scenes.RigidMember`) on the mesh's line
        of action with its helix hands (:func:`~jaxgear.scenes.train_layout`). The input torque
        acts at the input shaft's torque node, each loaded shaft's and the balancing output's
        at theirs (:func:`~jaxgear.scenes.shaft_torques`), each about the shaft's sense of
        rotation; wrenches add forces and tilting moments at shaft nodes.

        With ``housing`` (a :class:`~jaxgear.scenes.Housing`) the bearings join the shafts to
        its seats (``seats``: each bearing's seat index, shaft after shaft, an entry None
        keeping that bearing on the ground; None: the nearest seat) instead of the ground,
        its coordinates after the shafts' (:func:`lumped_pair`'s ``housing``); shaft i's axis
        runs through its first gear's layout centre, a shaft position s at z = centre_z + s −
        that gear's position along the shaft. ``housing_position``: t (3,) (m), the scene
        origin's place in the frame the housing is placed in, as :func:`lumped_pair`'s (each
        bearing's joint at its scene point plus t, its nearest seat the one nearest that
        point); None: the housing placed in the scene's frame.

        Raises:
            ValueError: gears and shafts that do not match (a shaft's ``gear_z`` count against
                its gears), a wrench on no shaft, what :func:`shaft_speeds`,
                :func:`shaft_torques` and :func:`scene_span` refuse, or what
                :func:`lumped_pair` refuses of ``seats`` and ``housing_position``.
        """
        check_housing_position(housing, housing_position, "LumpedTrain.of")
        t = _train_arrays(spec, spec.masses)
        n0 = t["d"]["M"].shape[0]
        on = spec.shaft_gears
        t["d"] = _housed(
            dict(t["d"], nodes=t["nodes"]),
            spec.shafts,
            [spec.layout.centres[on[i][0]] for i in range(spec.n_shafts)],
            [s.gear_positions[0] for s in spec.shafts],
            housing,
            seats,
            position=housing_position,
        )
        t["nodes"] = t["d"].pop("nodes")
        t["f_torque"] = np.concatenate([t["f_torque"], np.zeros(t["d"]["M"].shape[0] - n0)])
        d, first, n = t["d"], t["first"], t["d"]["M"].shape[0]
        offsets, mats = d["shaft_offsets"], d["mats"]
        rb0 = float(spec.meshes[0][0].base_radius_pinion)
        rigid = np.zeros(n)
        for i in range(spec.n_shafts):
            rigid[offsets[i] + 5 : offsets[i] + 6 * mats[i].nodes.size : 6] = (
                t["spins"][i] * t["omega"][i] / rb0
            )
        members = tuple(
            RigidMember(spec.layout.centres[g], tuple(range(first[g], first[g] + 6)))
            for g in range(spec.n_gears)
        )
        structure = _shaft_structure(
            d,
            (
                *(f"{name}_shaft" for name in spec.names),
                "bearings",
                *(("housing",) if housing is not None else ()),
            ),
            t["nodes"],
        )
        return cls(
            structure=structure,
            meshes=train_meshes(spec.meshes, spec.layout, first, n),
            members=members,
            f_torque=jnp.asarray(t["f_torque"]),
            rigid=jnp.asarray(rigid),
            periods=t["periods"],
            period_ratios=t["period_ratios"],
        )


def lumped_train(spec: TrainSpec, housing: Housing | None = None, seats=None, *,
                 housing_position=None) -> LumpedTrain:
    """The lumped 3D scene of the train ``spec`` (with ``housing``: its bearings on the
    housing's seats, the scene origin at ``housing_position`` in the housing's frame):
    :meth:`LumpedTrain.of`.

    Raises:
        ValueError: what :meth:`LumpedTrain.of` refuses.
    """
    return LumpedTrain.of(spec, housing, seats, housing_position=housing_position)


def _train_arrays(spec: TrainSpec, masses, bodies_z=None) -> dict:
    """The NumPy parts of a lumped 3D train shared by :meth:`LumpedTrain.of` and the hybrid
    train (:meth:`~jaxgear.scenes.HybridScene.train`): the shafts with a node at each wrench
    and each condensed body's bearing node (``bodies_z``: more positions per shaft), a rigid
    disc at each gear whose mass (``masses``, (n,)) is not ``None``, each gear node's first
    DOF, the loads per unit input torque (shaft torques and wrenches), the structure's named
    nodes and the scene span.

    Returns:
        dict of ``d`` (:func:`_shaft_arrays`), ``first``, ``f_torque`` (shaft DOFs), ``out``
        (the balancing output's shaft), ``spins`` and ``omega`` (each shaft's sense and speed
        per unit input speed), ``nodes``, ``periods``, ``period_ratios``.

    Raises:
        ValueError: gears and shafts that do not match, a wrench on no shaft, or what
            :func:`shaft_torques` and :func:`scene_span` refuse.
    """
    shafts, layout, inertias = spec.shafts, spec.layout, spec.inertias
    n_shafts, names, on = len(shafts), spec.names, spec.shaft_gears
    for i, shaft in enumerate(shafts):
        if len(shaft.gear_positions) != len(on[i]):
            raise ValueError(
                f"shaft {names[i]!r}: {len(shaft.gear_positions)} gear positions for its "
                f"{len(on[i])} gears {on[i]}"
            )
    for w in spec.wrenches:
        if not 0 <= w.shaft < n_shafts:
            raise ValueError(f"Wrench: shaft {w.shaft} does not exist (0 to {n_shafts - 1})")
    bodies_z = bodies_z or ((),) * n_shafts
    extra = tuple((*z, *b) for z, b in zip(spec.wrench_z, bodies_z, strict=True))
    d = _shaft_arrays(shafts, names, *spec.material, extra)
    offsets, mats = d["shaft_offsets"], d["mats"]
    first = [None] * spec.n_gears  # each gear node's first DOF
    for i, gears in enumerate(on):
        for g, node in zip(gears, mats[i].gear_nodes, strict=True):
            first[g] = offsets[i] + 6 * node
            if masses[g] is not None:
                _add_gear_body(d["M"], first[g], masses[g], inertias[g])
    omega = [float(layout.ratios[on[i][0]]) for i in range(n_shafts)]
    spins = [float(layout.spins[on[i][0]]) for i in range(n_shafts)]
    torques, out = shaft_torques(spec.links, omega, spec.shares)
    n = d["M"].shape[0]
    f_torque = np.zeros(n)
    for i, t in torques.items():
        f_torque[offsets[i] + 6 * mats[i].torque_node + 5] += spins[i] * t
    for w in spec.wrenches:
        node = offsets[w.shaft] + 6 * int(np.argmin(np.abs(mats[w.shaft].nodes - w.z)))
        f_torque[node : node + 3] += w.force
        f_torque[node + 3 : node + 6] += w.moment
    # from the tooth counts (layout.ratios are ratios of them): exact in float32 too
    periods = [
        2.0 * math.pi / mesh_teeth(plane)[0] / float(layout.ratios[g])
        for plane, (g, _) in spec.meshes
    ]
    nodes = (
        ("input", offsets[0] + 6 * mats[0].torque_node),
        ("output", offsets[out] + 6 * mats[out].torque_node),
        *((f"gear{g}", first[g]) for g in range(spec.n_gears)),
    )
    return dict(
        d=d,
        first=first,
        f_torque=f_torque,
        out=out,
        spins=spins,
        omega=omega,
        nodes=nodes,
        periods=scene_span(periods),
        period_ratios=mesh_period_ratios(periods),
    )


def train_meshes(meshes, layout, first, n: int) -> tuple:
    """Each mesh of a train as a :class:`~jaxgear.scenes.GearMesh` on its line of action, with
    its phase, speed ratio, axial sense and TE vector cos β_b (r_b1 θ_g − r_b2 θ_h) (n,) at the
    gear nodes (``first``: each gear node's first DOF; θ = spin φ_z)."""
    out = []
    for k, (plane, (g, h)) in enumerate(meshes):
        line = layout.lines[k]
        cb = math.cos(float(plane.base_helix_angle))
        te = np.zeros(n)
        te[first[g] + 5] = cb * float(plane.base_radius_pinion) * layout.spins[g]
        te[first[h] + 5] = -cb * float(plane.base_radius_gear) * layout.spins[h]
        out.append(
            GearMesh(
                plane,
                line["tangent_point"],
                line["direction"],
                line["normal"],
                line["roll_start"],
                te,
                gears=(g, h),
                ratio=float(layout.ratios[g]),
                phase=float(layout.phases[k]),
                axial=line["axial"],
            )
        )
    return tuple(out)
