"""An assembled linear structure: the shafts, bearings, rigid gear bodies and condensed FE bodies
that a scene's gear meshes act on (docs/design.md, "Structure and dynamics").

The members are assembled once, in NumPy, into n generalised coordinates: 6 per shaft node
(u_x, u_y, u_z, φ_x, φ_y, φ_z; :mod:`._lumped3d`), then each condensed body's rim master and modal
coordinates (:mod:`._hybrid`). A :class:`Structure` holds the assembled matrices and the names of
its nodes; the scene holds its gear members (the gear bodies on those nodes) and the meshes
(:mod:`._gear_mesh`) act between two of them each, and the operating point (torques, speed) stays an argument of the methods that load it.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._baseplane import CellRow, Cells, MeshModel
from ._gear_mesh import only_mesh
from ._mount import HousingMount
from ._scene import Scene, _check_meshes

__all__ = ["AssembledScene", "Structure"]


class Structure(eqx.Module):
    """Assembled stiffness, mass, bearing damping and rotating-frame matrices of a structure.

    Attributes:
        K: stiffness (n, n) (N/m, N/rad, N·m/rad per coordinate pair).
        M: mass (n, n) (kg, kg·m²).
        parts_K: K split by part, (p, n, n) summing to K (names in ``part_names``), or None for
            one part named ``part_names[0]``.
        C_bearing: bearing damping (units of K·s) on the first s coordinates (the shafts, and
            with a flexible housing its coordinates and damping too), (s, s).
        reaction: bearing force rows (r, n): R X the elastic force components k u (N), names in
            ``reaction_names``, each on shaft ``reaction_member`` (the shaft's index: 0 pinion,
            1 gear for a pair); on a flexible housing k d, d the shaft node's displacement
            relative to its seat (:class:`~jaxgear.scenes.Housing`).
        gyroscopic: Coriolis matrix per unit pinion speed (n, n) of the members whose frames turn
            (zeros for a structure in the fixed frame).
        spin_stiffness: spin softening plus centrifugal stress stiffening per unit pinion speed²
            (n, n) (zeros likewise).
        f_centrifugal: centrifugal load per unit pinion speed² (n,) (zeros likewise).
        nodes: static ((name, first DOF), ...): the torque nodes ``input`` and ``output`` and
            the gear nodes (``pinion`` and ``gear`` for a pair, ``gear<i>`` for a train).
        node_dofs: static, the DOFs of each node: 6 for shaft nodes (u_x, u_y, u_z, φ_x, φ_y,
            φ_z), 1 for a torsional structure (the rotation φ_z alone).
        mount: the :class:`~jaxgear.scenes.HousingMount` its bearings sit in (its joints the
            seated bearings; its housing's K_h, M_h, C_h are in the ``housing`` part, M and
            C_bearing), or None: a structure on the ground.
        mount_offset: static, the first of the mount's housing coordinates (its h follow).
    """

    K: Float[Array, "n n"]
    M: Float[Array, "n n"]
    parts_K: Float[Array, "p n n"] | None
    C_bearing: Float[Array, "s s"]
    reaction: Float[Array, "r n"]
    gyroscopic: Float[Array, "n n"]
    spin_stiffness: Float[Array, "n n"]
    f_centrifugal: Float[Array, " n"]
    part_names: tuple = eqx.field(static=True)
    reaction_names: tuple = eqx.field(static=True)
    reaction_member: tuple = eqx.field(static=True)
    nodes: tuple = eqx.field(static=True)
    node_dofs: int = eqx.field(static=True, default=6)
    mount: HousingMount | None = None
    mount_offset: int = eqx.field(static=True, default=0)

    @property
    def size(self) -> int:
        """The number n of generalised coordinates."""
        return self.K.shape[0]

    def node(self, name: str) -> int:
        """First DOF of the node ``name`` (its :attr:`node_dofs` follow).

        Raises:
            ValueError: no node of that name (the message lists the names).
        """
        for key, first in self.nodes:
            if key == name:
                return first
        names = ", ".join(k for k, _ in self.nodes)
        raise ValueError(f"structure node {name!r} does not exist: allowed {names}")

    def stiffness_parts(self) -> dict[str, Float[Array, "n n"]]:
        """The named parts of K (the modal analysis's strain-energy shares, seed (2.36))."""
        if self.parts_K is None:
            return {self.part_names[0]: self.K}
        return {name: self.parts_K[i] for i, name in enumerate(self.part_names)}

    def bearing_damping(self) -> Float[Array, "n n"]:
        """The bearing damping padded to (n, n) (zeros without bearing damping)."""
        n, s = self.size, self.C_bearing.shape[0]
        if s == n:
            return self.C_bearing
        return jnp.zeros((n, n), self.K.dtype).at[:s, :s].set(self.C_bearing)


class AssembledScene(Scene):
    """A scene made of an assembled :class:`Structure`, its gear members and a tuple of gear
    meshes (:class:`~jaxgear.scenes.GearMesh`) between them.

    Attributes:
        structure: the assembled structure (n coordinates).
        meshes: the gear meshes, each naming its (driving, driven) gears among ``members``.
        members: the gear members of the structure (each a
            :class:`~jaxgear.scenes.GearMember`: :class:`~jaxgear.scenes.RigidMember`,
            :class:`~jaxgear.scenes.TorsionalMember`, :class:`~jaxgear.scenes.FlexibleMember`),
            for a pair (pinion, gear). A gear that meshes twice (an idler) is one member.
        f_torque: the external load per unit pinion torque (n,): +1 on the input node's φ_z,
            and the output torque that balances it through the gear ratio (the load resists the
            driven gear's rotation).
    """

    structure: Structure
    meshes: tuple
    members: tuple
    f_torque: Float[Array, " n"]

    def __check_init__(self):
        for k, mesh in enumerate(self.meshes):
            a, b = mesh.gears
            if a == b or not (0 <= a < len(self.members) and 0 <= b < len(self.members)):
                raise ValueError(
                    f"mesh {k}: gears = {mesh.gears} must be two different indices of the "
                    f"scene's {len(self.members)} gear members (0 to {len(self.members) - 1})"
                )

    def gear_members(self) -> tuple:
        """Its ``members``."""
        return self.members

    def external_load(self, torque) -> Float[Array, " n"]:
        """Generalised external forces T f_torque (n,) at pinion torque T (N·m)."""
        return torque * self.f_torque

    def rigid_modes(self) -> Float[Array, "n r"]:
        """The scene's free drive rotations R (n, r), columns with V·r = 0 and F·r = 0 (its
        structure turning freely at the gear ratios): none, (n, 0), for a scene assembled for
        quasi-static solves; a dynamic scene gives its own
        (:meth:`~jaxgear.scenes.DynamicScene.rigid_modes`)."""
        K = self.structure.K
        return jnp.zeros((K.shape[0], 0), K.dtype)

    @property
    def mesh(self) -> MeshModel:
        """The base-plane model of the scene's one mesh."""
        return only_mesh(self.meshes).base_plane

    @property
    def torque_dofs(self) -> tuple[int, int]:
        """φ_z DOF of the input and output torque nodes (the last DOF of each node)."""
        last = self.structure.node_dofs - 1
        return self.structure.node("input") + last, self.structure.node("output") + last

    # -- the scene's part of a gearbox stage (jaxgear.dynamics.AbstractStage, written once on
    # the dynamic model): its coordinates' names and senses, its cells as the stage takes them

    def stage_senses(self) -> Float[Array, " n"]:
        """±1 per coordinate (n,): the sign that counts it as a gearbox stage counts its
        coordinates, every rotation positive about one common axis direction (the chain's sense,
        :class:`jaxgear.dynamics.AbstractStage`): all +1 here (the shafts' φ_z of a lumped
        scene are all about +z); a torsional scene, whose rotations are each positive in their
        own direction of motion, flips the driven side's."""
        return jnp.ones((self.structure.size,), self.structure.K.dtype)

    def stage_coordinates(self) -> tuple[str, ...]:
        """One name per coordinate (n,): ``"<node> <dof>"`` on the structure's named nodes of
        6 coordinates (``pinion``, ``gear``, ``input``, ``output``, a housing's seats;
        coincident nodes joined by "/"; dof u_x, u_y, u_z in m, phi_x, phi_y, phi_z in rad),
        ``"q<i>"`` elsewhere."""
        dofs = ("u_x", "u_y", "u_z", "phi_x", "phi_y", "phi_z")
        width = self.structure.node_dofs
        names: dict[int, list[str]] = {}
        for key, first in self.structure.nodes:
            names.setdefault(first, []).append(key)
        out = []
        for i in range(self.structure.size):
            first = i - i % width if width == 6 else i
            keys = names.get(first)
            out.append(f"{'/'.join(keys)} {dofs[i - first]}" if keys and width == 6 else f"q{i}")
        return tuple(out)

    @property
    def reaction_names(self) -> tuple:
        """Names of the bearing force components of :meth:`reaction_matrix`."""
        return self.structure.reaction_names

    def stiffness(self):
        return self.structure.K

    def mass(self) -> Float[Array, "n n"]:
        """Mass matrix M (n, n) (kg, kg·m²) of the assembled structure."""
        return self.structure.M

    def stiffness_parts(self) -> dict[str, Float[Array, "n n"]]:
        """The named parts of the structure stiffness (:meth:`Structure.stiffness_parts`)."""
        return self.structure.stiffness_parts()

    def bearing_damping(self) -> Float[Array, "n n"]:
        """Assembled bearing damping matrix (units of K·s), shape (n, n), zeros without bearing
        damping; the dynamic model adds it to its damping matrix C."""
        return self.structure.bearing_damping()

    def reaction_matrix(self) -> Float[Array, "r n"]:
        """Bearing force components k u (N) (x, y, z at each bearing: the translational rows of
        its stiffness, elastic force only), names in :attr:`reaction_names`."""
        return self.structure.reaction

    def bearing_forces_fixed_frame(self, theta, F) -> Float[Array, "P r"]:
        """The bearing force components R X (N), shape (P, r), at pinion angles θ (P,) in the
        fixed frame: unchanged here (every bearing in the fixed frame); a scene whose members
        turn their shafts' frames rotates them back."""
        return F

    def bearing_forces(self, theta, x) -> Float[Array, "P r"]:
        """Bearing force components k u (N), fixed frame, shape (P, r), at pinion angles θ (P,)
        and coordinates x (P, n); names in :attr:`reaction_names`."""
        return self.bearing_forces_fixed_frame(theta, x @ self.structure.reaction.T)

    def cell_vectors(self, cells: Cells) -> Float[Array, "L N n"]:
        return only_mesh(self.meshes).cell_vectors(self.members, cells, self.structure.size)

    @property
    def base_planes(self) -> tuple[MeshModel, ...]:
        """The base-plane model of each gear mesh."""
        return tuple(m.base_plane for m in self.meshes)

    def mesh_angles(self, theta) -> tuple:
        """Each mesh's angle θ_k = ratio_k θ + phase_k at the scene angle θ (rad)
        (:meth:`GearMesh.angle`)."""
        return tuple(m.angle(theta) for m in self.meshes)

    def _free_drive(self, mesh, idx, Vw, cells: Cells):
        """The window vectors ``Vw`` (..., w) of ``mesh``'s ``cells`` on the DOFs ``idx`` (w,),
        each corner cell's beyond the theoretical path (``contact_geometry``) less its part
        along the scene's free drive rotations R (:meth:`~jaxgear.scenes.DynamicScene.
        rigid_modes`): Vw − (Vw R_w)(G_wᵀ R_w)⁻¹ G_wᵀ, G = M R, both on the window, so that
        V·R = 0 (the rigid modes' contract). A corner cell's gap changes as the mesh position
        moves, so its exact vector has a part along the drive rotation (docs/extended-contact.md,
        "Where it acts"); the scene's nominal motion sets the mesh position, and the cell sees
        the elastic deviation, the torque ratio that the corner breaks shared by the window's
        inertias. Unchanged on the path, for a scene without rigid modes, or on a
        :class:`~jaxgear.TheoreticalPath`."""

        def free(V):
            R = self.rigid_modes()
            if R.shape[1] == 0:
                return V
            G = (self.structure.M @ R)[idx]
            R = R[idx]
            return V - (V @ R) @ jnp.linalg.solve(G.T @ R, G.T)

        plane = mesh.base_plane
        return plane.contact_geometry.beyond_path_vectors(plane, cells.s, Vw, free)

    def cell_row(self, cells: tuple[Cells, ...], delta0: tuple) -> CellRow:
        """The cells of every mesh in one row on all n coordinates, mesh after mesh (with a
        free drive rotation, corner cells beyond the path less their part along it:
        :meth:`_free_drive`)."""
        _check_meshes(self, cells)
        n = self.structure.size
        rows = []
        for m, c, d in zip(self.meshes, cells, delta0, strict=True):
            idx, Vw = m.window(self.members, c)
            Vw = self._free_drive(m, idx, Vw, c)
            V = jnp.zeros(c.s.shape + (n,), Vw.dtype).at[..., idx].add(Vw)
            rows.append(CellRow.of(c, V, d))
        return CellRow.concat(rows)

    def window_row(self, cells: tuple[Cells, ...], delta0: tuple, pad: int = 0) -> CellRow:
        """The cells of every mesh in one row on the meshes' windows (:meth:`GearMesh.window`,
        ``pad`` rim stations more on each side of a flexible member's window), mesh after
        mesh: the window is the meshes' windows joined, V block diagonal
        (:meth:`CellRow.concat`)."""
        _check_meshes(self, cells)
        rows = []
        for m, c, d in zip(self.meshes, cells, delta0, strict=True):
            idx, Vw = m.window(self.members, c, pad)
            rows.append(CellRow.of(c, self._free_drive(m, idx, Vw, c), d, idx))
        return CellRow.concat(rows)

    def contact_dofs(self) -> tuple[int, ...] | None:
        """The coordinates of the members in a mesh, sorted (static: each rigid member's 6 node
        DOFs, each torsional member's rotation), or None if a member's window follows the
        contact (a condensed body's rim stations)."""
        out = set()
        for mesh in self.meshes:
            for g in mesh.gears:
                dofs = self.members[g].contact_dofs
                if dofs is None:
                    return None
                out.update(dofs)
        return tuple(sorted(out))

    def te_vector(self) -> Float[Array, " n"]:
        """The TE vector u of the scene's one mesh (:attr:`GearMesh.te`)."""
        return only_mesh(self.meshes).te

    def te_vectors(self) -> Float[Array, "m n"]:
        """The TE vector of each mesh, shape (meshes, n)."""
        return jnp.stack([m.te for m in self.meshes])
