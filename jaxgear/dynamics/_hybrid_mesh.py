"""The hybrid scene's mesh over time (condensed FE bodies on the cells; docs/hybrid.md,
"Dynamics"): the flank gaps' time-constant references, the mesh stiffness averaged over a mesh
period on the rim stations under the mesh (:func:`mean_mesh_stiffness`, round a revolution for
the damping and the modal basis), and the Newmark loop in the cell space on the scene's cells
(:func:`_newmark_cells`, shared by the hybrid engine and the free vibration)."""

from __future__ import annotations

import math
from typing import NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._baseplane import CellRow
from .._contact import ContactLaw, ExactContact, contact_law
from .._quasi_static import _solve, mesh_separations, per_mesh_modifications
from .._util import compiled_when_eager, safe_max
from ..scenes import HybridPair, HybridScene
from ._model import cell_stiffness, cells_from_reference, mesh_te
from ._newmark import LinearSystem, MeshDamping, ModalSystem, newmark, newmark_modal

__all__ = ["mean_mesh_stiffness"]


class SceneCells(NamedTuple):
    """The cells of a hybrid scene at any pinion angle, with their flank gaps from each mesh's
    time-constant reference (δ0 = e_ref,k − e; :class:`~jaxgear.dynamics.MeshTable`), on the
    meshes' windows of master DOFs under the contact
    (:meth:`~jaxgear.scenes.HybridPair.window_row`), and the contact law that loads them.

    Attributes:
        scene: the :class:`~jaxgear.scenes.HybridPair`. mods: one
            :class:`~jaxgear.Modifications` per mesh. e_ref: each mesh's reference (m), (m,).
        law: the contact law.
    """

    scene: HybridPair
    mods: tuple
    e_ref: Float[Array, " m"]
    law: ContactLaw

    def at(self, theta) -> CellRow:
        """Every mesh's cells at the scene angle ``theta`` (rad) on the window."""
        return self.scene.window_row(
            *cells_from_reference(self.scene, self.mods, theta, self.e_ref)
        )


class CellSystem(NamedTuple):
    """The linear structure a hybrid Newmark run integrates, M Ẍ + C Ẋ + K X = F − Vᵀ P, on
    its coordinates (n, n) and (n,), or (``modal``) in a modal basis
    (:class:`~jaxgear.dynamics._newmark.ModalSystem`, with its own mesh damping;
    :func:`~jaxgear.dynamics._newmark.newmark_modal`); ``mesh_damping``: the mesh share of C
    that follows the mesh (:class:`~jaxgear.dynamics._newmark.MeshDamping`), or None."""

    K: Float[Array, "n n"]
    M: Float[Array, "n n"]
    C: Float[Array, "n n"]
    F: Float[Array, " n"]
    mesh_damping: MeshDamping | None = None
    modal: ModalSystem | None = None


def _newmark_cells(
    cells: SceneCells,
    system: CellSystem,
    dt,
    state,
    thetas,
    record,
    *,
    checks=(None, None),
    keep_blocks: int | None = None,
):
    """The Newmark loop (:func:`~jaxgear.dynamics._newmark.newmark`, the contact in the cell
    space) of ``system`` on the hybrid scene's ``cells``, one step of ``dt`` (s) per pinion
    angle of ``thetas`` (P, S) (P blocks of S steps: the mesh periods of the mesh damping),
    from ``state`` = (X, Ẋ, Ẍ); ``checks``: (the divergence check of each step, the one at the
    end of each block) (:func:`~jaxgear.dynamics._newmark.newmark`), each or None;
    ``keep_blocks``: record only the last blocks (None: all).

    In a modal basis (``system.modal``; :func:`~jaxgear.dynamics._newmark.newmark_modal`)
    ``state`` is (q, q̇, q̈, r, ṙ, r̈), the step check gets (q, q̇, P); the final state is
    returned on the coordinates.

    Returns the final state (X, Ẋ, Ẍ, result code, most contact passes), θ of every step, and
    per recorded step (flattened over the recorded blocks): the cell forces P (c,) of all
    meshes, each mesh's TE (m,) and ``record(X, Ẋ)``."""
    te_of = mesh_te(cells.scene, cells.e_ref)

    def kept(X, Xd, P, _theta):
        return P, te_of(X), record(X, Xd)

    init = (*state, jnp.array(0), jnp.array(0))
    steps = (dt, init, thetas, cells, kept)
    if system.modal is None:
        linear = LinearSystem(system.K, system.M, system.C, system.F, system.mesh_damping)
        carry, (P, te, rec) = newmark(linear, *steps, checks=checks, keep_blocks=keep_blocks)
    else:
        carry, (P, te, rec) = newmark_modal(
            system.modal, *steps, checks=checks, keep_blocks=keep_blocks
        )
        q, qd, qdd, r, rd, rdd, code, it = carry  # the state on the coordinates
        D = system.modal.space.D
        carry = (D @ q + r, D @ qd + rd, D @ qdd + rdd, code, it)
    return carry, (thetas.reshape(-1), P, te, rec)


def _revolution_periods(scene: HybridPair) -> int:
    """Mesh periods after which every flexible member's stations are again where they were:
    the least common multiple of their tooth counts (the wheel's teeth for H1; 1 if none)."""
    Z = [z for z in (m.rim_stations().count for m in scene.members) if z]
    return math.lcm(*Z) if Z else 1


def _revolution_mesh_stiffness(scene: HybridPair, block, periods: int):
    """K̄ (n, n): the mean of the mesh stiffness ``block(p)`` (:func:`_mesh_block`) over the mesh
    periods p = 0 … ``periods`` − 1 (a revolution, :func:`_revolution_periods`)."""
    n = scene.structure.K.shape[0]

    def add(Km, p):
        U, B, _ = block(p)
        return Km.at[U[:, None], U[None, :]].add(B), None

    Km, _ = jax.lax.scan(add, jnp.zeros((n, n), scene.structure.K.dtype), jnp.arange(periods))
    return Km / periods


def _references(scene: HybridPair, mods, theta):
    """e_ref (m,): each mesh's time-constant reference of the flank gaps over the positions
    ``theta`` (S,) of a mesh period (the largest max_M e), and max_M e at each position (S, m).

    The quasi-static δ0 = max_M e(θ) − e moves its reference with the position: in dynamics that
    would be a spurious kinematic excitation of the drive rotation wherever max_M e varies (a
    tip relief), so the dynamics use δ0 = e_ref − e, as the lumped model's mesh table."""
    planes = scene.base_planes
    mods = per_mesh_modifications(mods, len(planes))

    def at(th):
        return jnp.stack([part[1] for part in mesh_separations(scene, mods, th)])

    e_max = jax.vmap(at)(theta)
    return safe_max(e_max, axis=0), e_max  # jnp.max's value; its derivative never 0/0


def _joined(qs, name: str):
    """The per-cell field ``name`` of every mesh of a quasi-static result, joined mesh after
    mesh as the contact row joins the cells: (P, c)."""
    P = qs.theta.shape[0]
    return jnp.concatenate([getattr(m, name).reshape(P, -1) for m in qs.meshes], axis=-1)


def _reference_shift(scene: HybridScene, d):
    """The move N α of the free rotations that brings each mesh's flank-normal approach u_k·X
    forward by d_k (m), (meshes,): the start state's move from the quasi-static gaps (reference
    max_M e at the position) to the dynamics' time-constant reference e_ref. α solves
    (U N) α = d in the least-squares sense (U the meshes' TE vectors): one rotation per free
    shaft; a pair's meshes all move with its one drive rotation (u·N = cos β_b)."""
    A = scene.te_vectors() @ scene.N
    alpha = jnp.linalg.lstsq(A, d)[0]
    return scene.N @ alpha


@compiled_when_eager
def _loaded(qs):
    """The loaded cells (line load > 0) of every mesh at each position, joined: (P, c) (one
    compiled program when called eagerly)."""
    return _joined(qs, "line_load") > 0


def mean_mesh_stiffness(
    scene: HybridPair,
    mods,
    torque,
    spp: int,
    contact: ContactLaw = ExactContact(),
    *,
    speed=0.0,
):
    """K̄_m = ⟨Σ_c w_c k_c l_c V_c V_cᵀ⟩ over the ``spp`` quasi-static positions of one mesh
    period of the first mesh, θ_j = (j + ½) Δθ (n, n), w_c = 1 on the loaded cells (line load
    > 0), 0 elsewhere: the mesh part of K̄ in Rayleigh damping (2.34) and of the modal
    analysis; at pinion torque T (N·m) and speed Ω (rad/s, the centrifugal loads; default at
    rest), with the ``contact`` law of the quasi-static solve.

    ``scene``: any assembled scene, condensed (:class:`~jaxgear.scenes.HybridScene`) or lumped
    (:class:`~jaxgear.scenes.LumpedPair`, a train); the sum is :func:`cell_stiffness` on the
    cells' windows, as the lumped model's over its table: for a pair (whose span is one
    period) the two agree to rounding. The lumped model of a train averages over its whole
    span (:attr:`~jaxgear.dynamics.MeshTable.span`), this one over the first mesh's period."""
    law = contact_law(contact, scene.structure.K.dtype)
    return _period_statics(scene, mods, torque, speed, spp, law)[1]


@eqx.filter_jit
def _mesh_block(scene: HybridPair, theta, loaded, pad: int = 1):
    """The mesh stiffness of every mesh averaged over the positions ``theta`` (S,) with the
    cells ``loaded`` (S, c) (weights 0/1, joined mesh after mesh) on the window U of the first
    position widened by ``pad`` stations each side: (U (w,), B (w, w), whether every position's
    window lies inside U). A coordinate that two meshes see appears in U once per mesh; B holds
    its stiffness at one of them (the others' rows and columns are zero)."""
    n = scene.structure.size

    def row(th, pad=0):
        cells = scene.mesh_cells(th)
        return scene.window_row(cells, tuple(jnp.zeros_like(c.s) for c in cells), pad)

    U = row(theta[0], pad).idx
    w = U.shape[0]
    pos = jnp.full((n,), w, jnp.int32).at[U].set(jnp.arange(w, dtype=jnp.int32))

    def add(B, p):
        r = row(theta[p])
        kl = jnp.where(r.mask, r.k * r.length, 0.0) * loaded[p].astype(B.dtype)
        j = pos[r.idx]
        B = B.at[j[:, None], j[None, :]].add(cell_stiffness(r.V, kl), mode="drop")
        return B, jnp.all(j < w)

    B, ok = jax.lax.scan(
        add, jnp.zeros((w, w), scene.structure.K.dtype), jnp.arange(theta.shape[0])
    )
    return U, B / theta.shape[0], jnp.all(ok)


def _period_statics(
    scene: HybridPair, mods, torque, speed, spp, law: ContactLaw, host_checked: bool = False
):
    """Quasi-static result at pinion speed Ω (centrifugal loads) at the ``spp`` step positions
    of one mesh period, and K̄_m there (all meshes). ``host_checked``: the torque, speed and
    law were checked on the host before the caller's trace (no ``eqx.error_if`` of them)."""
    theta = (jnp.arange(spp) + 0.5) * scene.base_planes[0].mesh_period_angle / spp
    qs = _solve(scene, mods, torque, theta, speed, law, throw=False, host_checked=host_checked)
    U, B, _ = _mesh_block(scene, theta, _loaded(qs))
    return qs, _scattered(U, B, scene.structure.size)


@compiled_when_eager
def _scattered(U, B, n: int):
    """The block ``B`` (w, w) on the coordinates ``U`` (w,) as an (n, n) matrix (the entries
    of a coordinate that ``U`` holds twice added; one compiled program when called eagerly)."""
    return jnp.zeros((n, n), B.dtype).at[U[:, None], U[None, :]].add(B)
