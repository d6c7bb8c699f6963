"""Linear structures that the contact law acts on, through structure vectors (seed (2.9)).

A scene has n generalised coordinates X. The approach of cell c (flank-normal, m) is V_c·X, and
the contact force p_c l_c on the cell acts on the structure as −p_c l_c V_c. Each scene provides:

* ``stiffness()``: the structure's own stiffness K_s, shape (n, n);
* ``external_load(torque)``: generalised external forces F, shape (n,), for pinion torque T;
* ``cell_vectors(cells)``: V for every cell of its one mesh, shape (n_lines, n_slices, n);
* ``te_vector()``: u with u·X the flank-normal rigid-body approach of the mesh (the transmission
  error before the ``− max e`` and 1/cos β_b of docs/design.md, "Modifications, initial
  separation and TE");
* ``static_contact(cells, delta0, torque, speed, law)``: the static contact at one position,
  ``cells`` and ``delta0`` tuples of one entry per mesh. Scenes of a few coordinates solve it in
  coordinates (the default here); a scene of condensed bodies overrides it with the cell space
  (:class:`jaxgear.scenes.HybridPair`).

A scene may hold several gear meshes (:class:`jaxgear.scenes.AssembledScene`). The entries that
serve every scene take the cells of all meshes as tuples, one entry per mesh in the order of
``base_planes``: ``cell_row`` joins them into one row of cells (:meth:`CellRow.concat`),
``te_vectors()`` gives one TE vector per mesh, and ``static_contact`` solves the contact of all
meshes at once. The scenes of one mesh below give these from their one mesh.
"""

from __future__ import annotations

import abc
import fractions
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._backlash import cell_flank
from .._baseplane import CellRow, Cells, MeshModel
from .._contact import ContactLaw, ContactSolution, solve_contact
from .._util import as_float

__all__ = ["DynamicScene", "Grounded", "Scene", "grounded", "rigid_mode_penalty"]


class Scene(eqx.Module):
    """Abstract linear structure seen by the contact law.

    ``takes_housing`` (a class attribute): whether the kind's bearings can sit in a flexible
    :class:`~jaxgear.scenes.Housing` (its :class:`HousingMount` seating them); False here,
    True on the kinds with shafts on bearings (:class:`~jaxgear.scenes.LumpedPair`,
    :class:`~jaxgear.scenes.LumpedTrain`, :class:`~jaxgear.scenes.HybridScene`), whose every
    builder takes the housing alike: ``housing=`` (the object, placed in some frame),
    ``seats=`` (each bearing's seat; None: the nearest) and ``housing_position=`` (t (3,) (m),
    the scene origin's place in that frame, the axes parallel; None: t = 0), with the same
    refusals (:func:`~jaxgear.scenes.lumped_pair`). A case's ``[housing]`` is refused at load
    for a kind that does not declare it."""

    takes_housing: ClassVar[bool] = False

    @abc.abstractmethod
    def stiffness(self) -> Float[Array, "n n"]:
        """See the module docstring."""

    @abc.abstractmethod
    def external_load(self, torque: Float[Array, ""]) -> Float[Array, " n"]:
        """See the module docstring."""

    @abc.abstractmethod
    def cell_vectors(self, cells: Cells) -> Float[Array, "n_lines n_slices n"]:
        """See the module docstring."""

    @abc.abstractmethod
    def te_vector(self) -> Float[Array, " n"]:
        """See the module docstring."""

    def contact_dofs(self) -> tuple[int, ...] | None:
        """The coordinates the structure vectors of every cell can reach, sorted (static), or
        None: not known before the cells (every coordinate). A static solve over many
        positions condenses the structure onto them once (:mod:`jaxgear.dynamics`)."""
        return None

    @property
    def base_planes(self) -> tuple[MeshModel, ...]:
        """The base-plane model of each gear mesh (a scene of one mesh: its ``mesh``)."""
        return (self.mesh,)

    def gear_members(self) -> tuple:
        """The gear members of the structure (:class:`~jaxgear.scenes.GearMember`, a pair's
        (pinion, gear)): none for a scene that does not model its gears as members (a torsional
        pair of two rotations, the relative approach); an assembled scene's ``members``."""
        return ()

    def mesh_angles(self, theta) -> tuple:
        """The angle at which each mesh takes its cells at the scene angle θ (rad): θ itself for
        every mesh of a pair (a train's meshes: :meth:`GearMesh.angle`)."""
        return (theta,) * len(self.base_planes)

    def mesh_cells(self, theta) -> tuple:
        """Every mesh's cells at the scene angle θ (rad), each at its mesh angle
        (:meth:`mesh_angles`), unmodified (layout, stiffness, mask): one :class:`Cells` per
        mesh."""
        angles = self.mesh_angles(theta)
        return tuple(p.cells(a) for p, a in zip(self.base_planes, angles, strict=True))

    def scene_periods(self) -> int:
        """Periods of the first mesh after which the cells of every mesh repeat together: 1 for
        a pair or an idler train; a two-stage train's span (:func:`torsional_train`)."""
        return 1

    def mesh_periods(self) -> tuple[fractions.Fraction, ...]:
        """Each mesh's period in periods of the first mesh, exact (static): 1 for every mesh of
        a pair; a train's from its tooth counts (:func:`~jaxgear.scenes.mesh_period_ratios`).
        The dynamics tabulate each mesh over its own period (docs/trains.md, "Long spans")."""
        return (fractions.Fraction(1),) * len(self.base_planes)

    def cell_row(self, cells: tuple[Cells, ...], delta0: tuple) -> CellRow:
        """The cells of every mesh (one :class:`Cells` per mesh, with their initial separations
        δ0 (m)) in one row on all coordinates (:meth:`CellRow.concat`)."""
        _check_meshes(self, cells)
        return CellRow.of(cells[0], self.cell_vectors(cells[0]), delta0[0])

    def te_vectors(self) -> Float[Array, "m n"]:
        """The TE vector of each mesh, shape (meshes, n)."""
        return self.te_vector()[None, :]

    def map_positions(self, fn, theta):
        """``fn(scene, θ)`` vmapped over the scene angles θ (rad), (P,) (a scene that caches
        per-position data hands each call its position's slice:
        :meth:`jaxgear.scenes.HybridScene.map_positions`)."""
        return jax.vmap(lambda th: fn(self, th))(theta)

    def pinned_stiffness(self, K: Float[Array, "n n"], row: CellRow) -> Float[Array, "n n"]:
        """The structure stiffness K of a static solve with the scene's rigid-body modes pinned
        (:meth:`static_contact`): K itself for a scene without them (grounded, or a rigid pair);
        a :class:`DynamicScene` adds :func:`rigid_mode_penalty`."""
        del row
        return K

    def static_contact(
        self, cells: tuple[Cells, ...], delta0: tuple, torque, speed, law: ContactLaw
    ) -> tuple[ContactSolution, Float[Array, " n"], Float[Array, " m"]]:
        """The static contact of all meshes at one position, in coordinates
        (:func:`jaxgear.solve_contact` on K_s X + Σ P V = F).

        Args:
            cells: the cells of each mesh at the position, a tuple (one :class:`Cells` of
                shape (n_lines, n_slices) per mesh). delta0: their initial separations δ0 (m),
                a tuple of the same shapes. torque: pinion torque (N·m). speed: pinion speed
                (rad/s), unused here (no member of this scene carries a centrifugal load).
                law: the contact law.

        Returns:
            (the contact solution over the cells of all meshes in mesh order, X (n,), u·X of
            each mesh (m), shape (meshes,)). A scene with rigid-body modes r (a
            :class:`DynamicScene` that turns freely, such as an ungrounded gear train) has them
            pinned (:func:`rigid_mode_penalty`): X is the solution with rᵀ M X = 0.
        """
        r = self.cell_row(cells, delta0)
        K, F = self.stiffness(), self.external_load(torque)
        K = self.pinned_stiffness(K, r)
        sol = solve_contact(
            K, F, r.V, r.k, r.length, r.delta0, r.mask, law, loaded_flank(cells, torque)
        )
        return sol, sol.x, self.te_vectors() @ sol.x


class DynamicScene(Scene):
    """Abstract scene with inertia: adds :meth:`mass`, :meth:`rigid_modes` and the named parts of
    the structure stiffness (for the strain-energy shares of the modal analysis)."""

    @abc.abstractmethod
    def mass(self) -> Float[Array, "n n"]:
        """Mass matrix M, shape (n, n) (kg, kg·m², per coordinate)."""

    def reaction_matrix(self) -> Float[Array, "r n"]:
        """Rows R with R X the support (bearing) force components (N); none by default."""
        M = self.mass()
        return jnp.zeros((0, M.shape[0]), M.dtype)

    def bearing_damping(self) -> Float[Array, "n n"]:
        """The bearings' viscous damping matrix (units of K·s), shape (n, n), that the dynamic
        model adds to its damping matrix: zeros for a scene without bearing damping (an
        assembled scene's, :meth:`~jaxgear.scenes.AssembledScene.bearing_damping`)."""
        return jnp.zeros_like(self.mass())

    @abc.abstractmethod
    def rigid_modes(self) -> Float[Array, "n r"]:
        """Rigid-body modes r (columns, r may be 0) with V·r = 0 and F·r = 0."""

    @abc.abstractmethod
    def stiffness_parts(self) -> dict[str, Float[Array, "n n"]]:
        """Named structure stiffness matrices summing to :meth:`stiffness`."""

    def pinned_stiffness(self, K, row):
        """K plus :func:`rigid_mode_penalty`: a free chain's rigid-body modes pinned, so that
        the static solution has rᵀ M X = 0 (zeros added when the scene has no such mode)."""
        return K + rigid_mode_penalty(self, K, row)


class Grounded(Scene):
    """A scene with some coordinates tied to the ground by a stiff spring (for statics).

    Dynamic scenes keep rigid-body modes (the torsional chain turns freely) that make their
    stiffness singular in a quasi-static solve. Grounding the output rotation (the load) removes
    the mode; in a statically determinate torsional chain it changes neither the transmission error
    nor the bearing loads.

    Attributes:
        base: the scene. dofs: grounded coordinate indices (static).
        stiffness_value: spring stiffness in the units of those coordinates (default 1e3 times
            the largest diagonal term of the base stiffness).
    """

    base: Scene
    stiffness_value: Float[Array, ""] = eqx.field(converter=as_float)
    dofs: tuple = eqx.field(static=True)

    @property
    def mesh(self):
        return self.base.mesh

    @property
    def base_planes(self):
        return self.base.base_planes

    def mesh_angles(self, theta):
        return self.base.mesh_angles(theta)

    def gear_members(self):
        return self.base.gear_members()

    def scene_periods(self):
        return self.base.scene_periods()

    def mesh_periods(self):
        return self.base.mesh_periods()

    def cell_row(self, cells, delta0):
        return self.base.cell_row(cells, delta0)

    def te_vectors(self):
        return self.base.te_vectors()

    def stiffness(self):
        K = self.base.stiffness()
        idx = jnp.asarray(self.dofs)
        return K.at[idx, idx].add(self.stiffness_value)

    def external_load(self, torque):
        return self.base.external_load(torque)

    def cell_vectors(self, cells):
        return self.base.cell_vectors(cells)

    def te_vector(self):
        return self.base.te_vector()


def loaded_flank(cells: tuple, torque):
    """The cells of the flank that the pinion torque T loads, (c,) over the cells of every mesh
    (drive for T > 0, coast for T < 0): the active set's start of a static solve with coast
    flanks (:func:`jaxgear.solve_contact` ``start``); None (every cell) without coast cells."""
    if all(c.flank is None for c in cells):
        return None
    flank = jnp.concatenate([cell_flank(c).reshape(-1) for c in cells])
    return flank * jnp.sign(torque) > 0


def rigid_mode_penalty(scene: DynamicScene, K, row: CellRow) -> Float[Array, "n n"]:
    """The stiffness Σ_j k_j m̂_j m̂_jᵀ that pins the rigid-body modes r_j of ``scene`` in a
    static solve, m̂_j = M r_j / |M r_j| (r_j itself where M r_j = 0), so that the solution X
    has rᵀ M X = 0 (as the dynamics' static reference) and is otherwise unchanged (V·r = F·r = 0).

    Without it the tangent stiffness K_s + Σ k l V Vᵀ of a free chain (a torsional train has
    K_s = 0) is singular: its LU factorisation's last pivot is rounding noise (float32,
    ``two-stage``: 4e-12 … 2e-8 of the largest entry over 20 000 positions, X then carrying a
    rigid rotation up to 2.6 rad beside elastic ones of 5e-4 rad), and exactly 0 where the
    rounding cancels: a non-finite X. Which positions cancel depends on the elimination and
    summation order, so on the CPU's kernels: ``two-stage`` in float32 failed on one CPU and
    not on another, and with its shafts numbered in another order at 4 of 8 positions on
    any, in float64 too; an idler train of equal gears cancels exactly.
    Each k_j is the stiffness of the coordinates the mode moves, Σ_i D_ii m̂_ji² with D the
    diagonal of K plus the contact stiffness of every cell on the flanks (N/m or N·m/rad as the
    coordinates are): the pinned system is as well conditioned as the contact's own (no
    gradient flows through this scale; the solution does not depend on it).

    Args:
        scene: the scene (its :meth:`~DynamicScene.mass` and
            :meth:`~DynamicScene.rigid_modes`, (n, r), r may be 0).
        K: its structure stiffness, (n, n). row: the position's cells (:class:`CellRow`).

    Returns:
        the penalty stiffness, (n, n) (zeros without rigid-body modes).
    """
    R = scene.rigid_modes()
    n = K.shape[0]
    if R.shape[1] == 0:
        return jnp.zeros((n, n), K.dtype)
    sg = jax.lax.stop_gradient
    R, M = sg(R).astype(K.dtype), sg(scene.mass()).astype(K.dtype)
    kl = sg(jnp.where(row.mask, row.k * row.length, 0.0))
    D = jnp.abs(jnp.diag(sg(K))) + jnp.einsum("c,ci->i", kl, sg(row.V) ** 2)
    MR = M @ R
    W = jnp.where(jnp.sum(MR**2, axis=0, keepdims=True) > 0, MR, R)
    W = W / jnp.sqrt(jnp.sum(W**2, axis=0, keepdims=True))
    k = jnp.einsum("i,ir->r", D, W**2)
    return (W * k[None, :]) @ W.T


def _check_meshes(scene: Scene, cells: tuple) -> None:
    """One :class:`Cells` per mesh of ``scene`` (a one-line error otherwise)."""
    n = len(scene.base_planes)
    if not isinstance(cells, tuple):
        raise ValueError(
            f"the scene has {n} gear meshes; cells given for {type(cells).__name__} (one per mesh)"
        )
    if len(cells) != n:
        raise ValueError(
            f"the scene has {n} gear meshes; cells given for {len(cells)} meshes (one per mesh)"
        )


def grounded(scene: Scene, dofs, factor: float = 1e3) -> Grounded:
    """Ground ``dofs`` of ``scene`` with springs ``factor`` × the largest diagonal stiffness."""
    k = float(jnp.max(jnp.abs(jnp.diag(scene.stiffness()))))
    return Grounded(scene, factor * max(k, 1.0), tuple(int(d) for d in dofs))
