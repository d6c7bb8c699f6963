"""3D lumped-parameter scene: rigid gear nodes on Timoshenko shafts with bearings (seed I-3, (2.9)).

Frame: z along the (parallel) axes, pinion axis through the origin, gear axis through (a_w, 0).
The line of action is t = (sin α_wt, cos α_wt, 0), tangent to the pinion base circle at
T1 = r_b1 (cos α_wt, −sin α_wt, 0) (the pinion turns about +z and drives, the gear turns about
−z). A cell at base-plane coordinates (s, z) sits at M = T1 + (ρ_A + s) t + (z − b/2) e_z, ρ_A
the pinion roll distance of the engagement point, and its flank normal is
n = cos β_b t + sin β_b e_z (the helix-hand convention: a positive β gives a +z axial force on the
gear). Each shaft node has 6 DOF (u_x, u_y, u_z, φ_x, φ_y, φ_z). The approach of cell M is
(d1(M) − d2(M))·n with d_i(M) = u_i + φ_i × (M − O_i) at the gear nodes, i.e. the structure vector

    V(M) = [n, (M − O1) × n, −n, −(M − O2) × n]      (seed (2.9), at the two gear nodes),

and for a pure rotation it reduces to the torsional V = cos β_b (r_b1, −r_b2) with θ1 = φ_z1 and
θ2 = −φ_z2.

Shaft element: 2-node Timoshenko beam (Przemieniecki; shear parameter Φ = 12 E I/(κ G A L²)),
consistent Euler-Bernoulli translational mass plus rotary inertia, axial and torsional bars. The
seed's annex (1.9) has typos; this follows the textbook (Przemieniecki, *Theory of Matrix
Structural Analysis*, 1968, §5.6; Friedman & Kosmatka, Comput. Struct. 47, 1993 for the
shear-deformable stiffness).
"""

from __future__ import annotations

import dataclasses
import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._baseplane import MeshModel
from .._geometry import GearPair
from ._scene import DynamicScene

__all__ = ["Bearing", "LumpedPair", "ShaftSpec", "lumped_pair", "timoshenko_element"]


def contact_points(tangent_point, direction, roll_start, mesh: MeshModel, cells) -> Array:
    """Fixed-frame contact points M = T1 + (ρ_A + s) t + (z − b/2) e_z of the cells (m),
    shape (L, N, 3) (the frame of the module docstring)."""
    lead = (1,) * cells.s.ndim
    ez = jnp.array([0.0, 0.0, 1.0], cells.s.dtype).reshape(lead + (3,))
    return (
        tangent_point.reshape(lead + (3,))
        + (roll_start + cells.s)[..., None] * direction.reshape(lead + (3,))
        + (cells.z - 0.5 * mesh.face_width)[..., None] * ez
    )


def rigid_node_vector(points, centre, normal) -> Array:
    """Structure vector of a rigid gear body at a 6-DOF node O: [n_m, (M − O) × n_m] (seed
    (2.9)), shape (..., 6), for contact points M (..., 3) and the member's outward normal n_m
    (n for the pinion, −n for the gear)."""
    nm = jnp.broadcast_to(normal, points.shape)
    arm = points - centre.reshape((1,) * (points.ndim - 1) + (3,))
    return jnp.concatenate([nm, jnp.cross(arm, nm)], axis=-1)


def timoshenko_element(
    E: float, G: float, rho: float, diameter: float, length: float, kappa: float = 0.9
) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and mass (12, 12) of a solid circular shaft element along z.

    DOF order per node: u_x, u_y, u_z, φ_x, φ_y, φ_z (m, rad); node 1 then node 2.
    Bending in the x–z plane uses (u_x, φ_y) with du_x/dz = φ_y, in the y–z plane (u_y, φ_x)
    with du_y/dz = −φ_x.

    Args:
        E, G: Young's and shear moduli (Pa). rho: density (kg/m³). diameter, length: (m).
        kappa: shear coefficient (0.9 for a solid circle, Cowper 6(1+ν)/(7+6ν)).
    """
    L = length
    A = math.pi * diameter**2 / 4
    I = math.pi * diameter**4 / 64
    J = 2 * I
    phi = 12 * E * I / (kappa * G * A * L**2)
    c = E * I / ((1 + phi) * L**3)
    kb = c * np.array(
        [
            [12, 6 * L, -12, 6 * L],
            [6 * L, (4 + phi) * L**2, -6 * L, (2 - phi) * L**2],
            [-12, -6 * L, 12, -6 * L],
            [6 * L, (2 - phi) * L**2, -6 * L, (4 + phi) * L**2],
        ]
    )
    mt = (
        rho
        * A
        * L
        / 420
        * np.array(
            [
                [156, 22 * L, 54, -13 * L],
                [22 * L, 4 * L**2, 13 * L, -3 * L**2],
                [54, 13 * L, 156, -22 * L],
                [-13 * L, -3 * L**2, -22 * L, 4 * L**2],
            ]
        )
    )
    mr = (
        rho
        * I
        / (30 * L)
        * np.array(
            [
                [36, 3 * L, -36, 3 * L],
                [3 * L, 4 * L**2, -3 * L, -(L**2)],
                [-36, -3 * L, 36, -3 * L],
                [3 * L, -(L**2), -3 * L, 4 * L**2],
            ]
        )
    )
    mb = mt + mr
    K = np.zeros((12, 12))
    M = np.zeros((12, 12))
    # bending x–z: (u_x, φ_y) = DOF (0, 4), (6, 10), slope +φ_y
    # bending y–z: (u_y, φ_x) = DOF (1, 3), (7, 9), slope −φ_x
    for idx, sign in (((0, 4, 6, 10), 1.0), ((1, 3, 7, 9), -1.0)):
        s = np.diag([1.0, sign, 1.0, sign])
        K[np.ix_(idx, idx)] += s @ kb @ s
        M[np.ix_(idx, idx)] += s @ mb @ s
    bar = np.array([[1.0, -1.0], [-1.0, 1.0]])
    bar_m = np.array([[2.0, 1.0], [1.0, 2.0]]) / 6
    for idx, k, m in (((2, 8), E * A / L, rho * A * L), ((5, 11), G * J / L, rho * J * L)):
        K[np.ix_(idx, idx)] += k * bar
        M[np.ix_(idx, idx)] += m * bar_m
    return K, M


@dataclasses.dataclass(frozen=True)
class Bearing:
    """A bearing at axial position ``z`` (m): diagonal stiffness to the ground (N/m, N·m/rad)."""

    z: float
    radial: float = 2e8
    axial: float = 1e8
    tilt: float = 0.0


@dataclasses.dataclass(frozen=True)
class ShaftSpec:
    """A solid shaft along z from 0 to ``length`` (m), diameter (m), gear centre at ``gear_z``,
    bearings, and the torque node (input for the pinion, output for the gear) at ``torque_z``."""

    length: float
    diameter: float
    gear_z: float
    bearings: tuple[Bearing, ...]
    torque_z: float = 0.0
    elements: int = 4


class LumpedPair(DynamicScene):
    """Two shafts with rigid gear nodes and bearings (build with :func:`lumped_pair`).

    Attributes:
        mesh: the gear mesh. M, K: assembled mass and structure stiffness (n, n).
        parts_K: the stiffness split by part, shape (n_parts, n, n) (names in ``part_names``).
        centres: O1, O2 (m), shape (2, 3). tangent_point: T1 (m). direction: t. normal: n.
        roll_start: ρ_A (m). rigid: the rigid-body rotation mode (n,).
        gear_dofs: first DOF index of the pinion and gear nodes (static).
        torque_dofs: φ_z DOF of the input and output torque nodes (static).
        part_names: static names of ``parts_K``.
    """

    mesh: MeshModel
    M: Float[Array, "n n"]
    K: Float[Array, "n n"]
    parts_K: Float[Array, "p n n"]
    centres: Float[Array, "2 3"]
    tangent_point: Float[Array, " 3"]
    direction: Float[Array, " 3"]
    normal: Float[Array, " 3"]
    roll_start: Float[Array, ""]
    rigid: Float[Array, " n"]
    reaction: Float[Array, "r n"]
    gear_dofs: tuple = eqx.field(static=True)
    torque_dofs: tuple = eqx.field(static=True)
    part_names: tuple = eqx.field(static=True)
    reaction_names: tuple = eqx.field(static=True, default=())

    def mass(self):
        return self.M

    def stiffness(self):
        return self.K

    def stiffness_parts(self):
        return {name: self.parts_K[i] for i, name in enumerate(self.part_names)}

    def rigid_modes(self):
        return self.rigid[:, None]

    def reaction_matrix(self):
        """Bearing force components k u (N) (x, y, z at each bearing), names in ``reaction_names``."""
        return self.reaction

    def external_load(self, torque):
        n = self.M.shape[0]
        ratio = self.mesh.base_radius_gear / self.mesh.base_radius_pinion
        F = jnp.zeros(n, dtype=self.M.dtype)
        # input torque about +z on the pinion shaft; the load resists the gear's −z rotation
        return F.at[self.torque_dofs[0]].add(torque).at[self.torque_dofs[1]].add(torque * ratio)

    def cell_vectors(self, cells):
        P = contact_points(self.tangent_point, self.direction, self.roll_start, self.mesh, cells)
        v1 = rigid_node_vector(P, self.centres[0], self.normal)
        v2 = rigid_node_vector(P, self.centres[1], -self.normal)
        V = jnp.zeros(cells.s.shape + (self.M.shape[0],), self.M.dtype)
        i, j = self.gear_dofs
        return V.at[..., i : i + 6].set(v1).at[..., j : j + 6].set(v2)

    def te_vector(self):
        """Angular transmission error at the gear bodies, cos β_b (r_b1 φ_z1 + r_b2 φ_z2)."""
        cb = jnp.cos(self.mesh.base_helix_angle)
        u = jnp.zeros(self.M.shape[0], self.M.dtype)
        i, j = self.gear_dofs
        return (
            u.at[i + 5]
            .set(cb * self.mesh.base_radius_pinion)
            .at[j + 5]
            .set(cb * self.mesh.base_radius_gear)
        )


def _shaft(spec: ShaftSpec, E, G, rho, extra_z=()):
    zs = {0.0, spec.length, spec.gear_z, spec.torque_z, *(b.z for b in spec.bearings), *extra_z}
    for z in zs:
        if not -1e-12 <= z <= spec.length + 1e-12:
            raise ValueError(
                f"shaft position {z * 1e3:.6g} mm is outside the shaft [0, {spec.length * 1e3:.6g}] mm"
            )
    # refine every segment into about `elements` elements over the whole length; positions that
    # differ by rounding only (60 + 10 mm vs 70 mm) are one node
    base = []
    for z in sorted(zs):
        if not base or z - base[-1] > 1e-9 * max(spec.length, 1.0):
            base.append(z)
    nodes = []
    for a, b in zip(base[:-1], base[1:], strict=True):
        k = max(1, round(spec.elements * (b - a) / spec.length))
        nodes.extend(np.linspace(a, b, k + 1)[:-1].tolist())
    nodes.append(base[-1])
    nodes = np.array(nodes)
    n = 6 * nodes.size
    K = np.zeros((n, n))
    M = np.zeros((n, n))
    for e in range(nodes.size - 1):
        ke, me = timoshenko_element(E, G, rho, spec.diameter, nodes[e + 1] - nodes[e])
        sl = slice(6 * e, 6 * e + 12)
        K[sl, sl] += ke
        M[sl, sl] += me
    Kb = np.zeros((n, n))
    for b in spec.bearings:
        i = int(np.argmin(np.abs(nodes - b.z)))
        for d, k in zip(range(5), (b.radial, b.radial, b.axial, b.tilt, b.tilt), strict=True):
            Kb[6 * i + d, 6 * i + d] += k
    idx = lambda z: int(np.argmin(np.abs(nodes - z)))
    rows = []
    for b in spec.bearings:
        i = idx(b.z)
        for d, k in zip(range(3), (b.radial, b.radial, b.axial), strict=True):
            if k > 0:
                r = np.zeros(n)
                r[6 * i + d] = k
                rows.append((f"z={b.z * 1e3:g}mm F{'xyz'[d]}", r))
    return nodes, K, M, Kb, idx(spec.gear_z), idx(spec.torque_z), rows


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
    """NumPy parts of the lumped scene (shared by :func:`lumped_pair` and the hybrid scene).

    ``extra_z``: additional shaft node positions per shaft (m from the shaft start), e.g. where a
    condensed body's bearing nodes attach. A member whose mass is ``None`` gets no rigid gear
    body at its gear node (a condensed body replaces it).
    """
    G = E / (2 * (1 + nu))
    s1 = _shaft(pinion_shaft, E, G, rho, extra_z[0])
    s2 = _shaft(gear_shaft, E, G, rho, extra_z[1])
    n1, n2 = 6 * s1[0].size, 6 * s2[0].size
    n = n1 + n2
    M = np.zeros((n, n))
    Ksh1 = np.zeros((n, n))
    Ksh2 = np.zeros((n, n))
    Kb = np.zeros((n, n))
    M[:n1, :n1], M[n1:, n1:] = s1[2], s2[2]
    Ksh1[:n1, :n1], Ksh2[n1:, n1:] = s1[1], s2[1]
    Kb[:n1, :n1], Kb[n1:, n1:] = s1[3], s2[3]
    g1, g2 = 6 * s1[4], n1 + 6 * s2[4]
    for g, m, inertia in ((g1, masses[0], inertias[0]), (g2, masses[1], inertias[1])):
        if m is None:
            continue
        idia, ipol = inertia
        M[g : g + 3, g : g + 3] += m * np.eye(3)
        M[g + 3, g + 3] += idia
        M[g + 4, g + 4] += idia
        M[g + 5, g + 5] += ipol
    a = pair.center_distance
    alpha = pair.operating_pressure_angle
    rb1 = pair.base_radii[0]
    bb = pair.base_helix_angle
    t = np.array([math.sin(alpha), math.cos(alpha), 0.0])
    T1 = rb1 * np.array([math.cos(alpha), -math.sin(alpha), 0.0])
    normal = math.cos(bb) * t + math.sin(bb) * np.array([0.0, 0.0, 1.0])
    rigid = np.zeros(n)
    rigid[5:n1:6] = 1.0 / rb1
    rigid[n1 + 5 :: 6] = -1.0 / pair.base_radii[1]
    names, reaction = [], []
    for tag, rows, offset in (("pinion", s1[6], 0), ("gear", s2[6], n1)):
        for name, r in rows:
            full = np.zeros(n)
            full[offset : offset + r.size] = r
            names.append(f"{tag} {name}")
            reaction.append(full)
    return dict(
        M=M,
        parts=np.stack([Ksh1, Ksh2, Kb]),
        centres=np.array([[0.0, 0.0, 0.0], [a, 0.0, 0.0]]),
        tangent_point=T1,
        direction=t,
        normal=normal,
        rigid=rigid,
        reaction=np.array(reaction).reshape(-1, n),
        reaction_names=tuple(names),
        gear_dofs=(g1, g2),
        torque_dofs=(6 * s1[5] + 5, n1 + 6 * s2[5] + 5),
        shaft_z=(s1[0], s2[0]),  # node positions (m) along each shaft
        shaft_offsets=(0, n1),  # first DOF of each shaft
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
) -> LumpedPair:
    """Assemble the 3D lumped scene.

    Args:
        pair, mesh: the gear pair and its mesh model.
        pinion_shaft, gear_shaft: :class:`ShaftSpec` of each shaft (z from the shaft start).
        masses: gear body masses (kg), added at the gear nodes.
        inertias: ((I_diametral, I_polar) pinion, (…) gear) (kg·m²) of the gear bodies.
        youngs_modulus, poisson_ratio, density: shaft material.
    """
    d = _lumped_arrays(
        pair, pinion_shaft, gear_shaft, masses, inertias, youngs_modulus, poisson_ratio, density
    )
    return LumpedPair(
        mesh=mesh,
        M=jnp.asarray(d["M"]),
        K=jnp.asarray(d["parts"].sum(axis=0)),
        parts_K=jnp.asarray(d["parts"]),
        centres=jnp.asarray(d["centres"]),
        tangent_point=jnp.asarray(d["tangent_point"]),
        direction=jnp.asarray(d["direction"]),
        normal=jnp.asarray(d["normal"]),
        roll_start=jnp.asarray(pair.start_roll),
        rigid=jnp.asarray(d["rigid"]),
        reaction=jnp.asarray(d["reaction"]),
        reaction_names=d["reaction_names"],
        gear_dofs=d["gear_dofs"],
        torque_dofs=d["torque_dofs"],
        part_names=("pinion_shaft", "gear_shaft", "bearings"),
    )
