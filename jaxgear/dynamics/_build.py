"""The dynamic model of a scene at an operating torque (:func:`dynamic_model`): the engine of
its kind (a lumped :class:`~jaxgear.dynamics.DynamicModel`, a hybrid
:class:`~jaxgear.dynamics.HybridModel`), dispatched on the scene's type; and the lumped
model's time-averaged mesh stiffness, modes and damping, with their per-mesh splits
(:func:`mesh_stiffness_means`, :func:`mesh_energy_shares`)."""

from __future__ import annotations

import dataclasses
import functools
import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._contact import ContactLaw, ExactContact, contact_law
from .._modifications import Modifications
from .._quasi_static import check_operating, per_mesh_modifications
from .._util import check_instance, check_integer, is_traced
from ..scenes import DynamicScene, HybridPair, HybridScene
from ._hybrid import HybridModel
from ._lumped import DynamicModel
from ._damping import AbstractDamping, CompositeDamping, RayleighDamping, damping_matrix
from ._modal import modal_analysis
from ._model import (
    AbstractDynamicModel,
    _held_or_prepare,
    _HeldTable,
    _mean_mesh_matrix,
    _prepare,
    _Prepared,
    deviations_in,
)

__all__ = ["dynamic_model", "mesh_energy_shares", "mesh_stiffness_means", "stage_model"]


def dynamic_model(
    scene: DynamicScene | HybridPair,
    mods: Modifications | tuple | None,
    torque,
    damping: AbstractDamping | None = None,
    *,
    positions_per_pitch: int = 64,
    contact: ContactLaw = ExactContact(),
    rotating_frame: bool = False,
    revolutions: int | None = None,
    input: int | None = None,
) -> DynamicModel | HybridModel:
    """The dynamic model of a scene at an operating torque: what :func:`simulate` and
    :func:`speed_sweep` integrate.

    A lumped scene (torsional or 3D, :class:`DynamicScene`) gives a :class:`DynamicModel`: the
    time-averaged mesh stiffness matrix K̄_m = ⟨Σ_c w_c k_c l_c V_c V_cᵀ⟩ over one mesh period,
    w_c the static contact weights at ``torque`` (loaded cells only, so a tip relief that is not
    in contact does not count); the modal analysis of (M, K_s + K̄_m) gives the damping
    (2.34)-(2.36). A hybrid scene (:class:`jaxgear.scenes.HybridPair`) gives a
    :class:`HybridModel`, whose damping the sweeps build at each speed.

    Args:
        scene: dynamic scene. mods: modifications (``None``: none; one for every mesh, or a
            tuple of one per mesh). torque: pinion torque (N·m).
        damping: a damping model (:class:`AbstractDamping`). Default: composite (2.36), 0.07
            mesh / 0.01 structure, for a lumped scene; the seed's D1, Rayleigh (α, β) =
            (25 1/s, 2.5e-6 s), for a hybrid one.
        positions_per_pitch: positions per mesh period for the averages (lumped scenes).
        contact: the contact law of the static solve (:class:`~jaxgear.ExactContact` by
            default; lumped scenes).
        rotating_frame: hybrid scenes only: add the turning frames' inertia
            (:class:`HybridModel`).
        revolutions: lumped scenes with manufacturing deviations (``mods.deviations``): pinion
            revolutions of the span the runs cover (an integer >= 1; the table of δ0 over
            ``revolutions`` × z1 mesh periods repeats after it). Default None: the period of
            the deviations (:func:`deviation_periods`: z1 periods for the pinion's alone,
            lcm(z1, z2) for both, the hunting period). A span shorter than that period joins
            its end to its start (the gear's teeth jump): the steady state of a gear pair that
            repeats after the span, an approximation stated in docs/robust.md.
        input: lumped scenes: the side a gearbox drives, 0 the pinion's torque node, 1 the
            gear's (:attr:`DynamicModel.input`): the model then also stands in a
            :class:`jaxgear.gearbox.GearboxTorsional` (a pair's scene); None (default): it runs
            alone only.

    Raises:
        ValueError: a ``damping`` that is not a damping model; ``rotating_frame`` on a
            lumped scene; a concrete torque <= 0 for a hybrid scene; a tuple of modifications of
            another length than the meshes; ``input`` not None, 0 or 1, or given for a hybrid
            scene.
        eqx.EquinoxRuntimeError: lumped scene: torque <= 0, or the static contact solve failed
            (jit/vmap-safe).
    """
    check_instance(
        "scene",
        scene,
        (DynamicScene, HybridPair),
        "a jaxgear dynamic scene (TorsionalDynamics, a lumped or hybrid scene)",
        "dynamic_model",
    )
    check_operating("dynamic_model", scene, mods, torque, coast_torque=False, mods_name="mods")
    if mods is None:
        mods = Modifications()
    per_mesh_modifications(mods, len(scene.base_planes))  # one per mesh: the count, first
    if damping is not None and not isinstance(damping, AbstractDamping):
        raise ValueError(
            f"damping = {damping!r}: allowed a jaxgear.dynamics damping model "
            "(RayleighDamping, ModalDamping, CompositeDamping, NoDamping, or Damping(name, ...))"
        )
    _check_input(input, "dynamic_model")
    dtype = scene.base_planes[0].base_pitch.dtype
    torque = jnp.asarray(torque, dtype=dtype)
    model = _engine(
        scene,
        mods,
        torque,
        damping,
        positions_per_pitch=positions_per_pitch,
        contact=contact,
        rotating_frame=rotating_frame,
        revolutions=revolutions,
    )
    if input is None:
        return model
    if not isinstance(model, DynamicModel):
        raise ValueError(
            f"input = {input!r}: a gearbox stage's side is for a lumped scene's model (allowed "
            f"None for a {type(scene).__name__})"
        )
    return dataclasses.replace(model, input=int(input))


def _check_input(input, where: str) -> None:
    if input is not None and (isinstance(input, bool) or input not in (0, 1)):
        raise ValueError(
            f"{where}: input = {input!r}: out of range, allowed 0 (the pinion's torque node "
            "driven), 1 (the gear's) or None"
        )


def stage_model(scene: DynamicScene, mods: Modifications | None = None, *,
                input: int) -> DynamicModel:
    """A pair's :class:`DynamicModel` as a gearbox stage only: its scene, modifications and
    input side, without an operating torque, the static contact solve, the modes or the damping
    that a run alone needs (a gearbox's coupled run carries its torque and builds its own modal
    damping, :class:`jaxgear.gearbox.GearboxTorsional`). Its runs alone are refused in one line
    (:attr:`DynamicModel.runs_alone`); :func:`dynamic_model` with ``input`` builds a model that
    does both.

    Args:
        scene: a pair's lumped scene with torque nodes (a lumped 3D pair,
            :func:`~jaxgear.scenes.lumped_pair`; :class:`~jaxgear.scenes.TorsionalDynamics`).
        mods: its flank modifications (the cells' initial separations); None: none.
        input: 0 when the gearbox drives the pinion's torque node, 1 the gear's.

    Raises:
        ValueError: ``scene`` not a dynamic scene, ``mods`` not one
            :class:`~jaxgear.Modifications`, ``input`` not 0 or 1, a scene that cannot stand
            in a gearbox (:meth:`DynamicModel.check_stage`) (one line each).
    """
    where = "stage_model"
    check_instance("scene", scene, DynamicScene,
                   "a pair's lumped dynamic scene (lumped_pair(...), TorsionalDynamics)", where)
    mods = Modifications() if mods is None else mods
    check_instance("mods", mods, Modifications, "a jaxgear.Modifications or None", where)
    _check_input(input, where)
    if input is None:
        raise ValueError(f"{where}: input = None: allowed 0 (the pinion's torque node driven) "
                         "or 1 (the gear's)")
    model = DynamicModel(scene, mods, None, None, None, None, input=int(input))
    model.check_stage(where)
    return model


@functools.singledispatch
def _engine(scene, mods, torque, damping, **options) -> AbstractDynamicModel:
    """The dynamics engine of a scene (dispatched on its type: a new kind of scene registers
    its engine here). ``options``: :func:`dynamic_model`'s keywords."""
    raise ValueError(f"scene = {type(scene).__name__}: no dynamics engine for this scene kind")


@_engine.register
def _(scene: HybridScene, mods, torque, damping, *, rotating_frame=False, **_) -> HybridModel:
    if not isinstance(torque, jax.core.Tracer) and not bool(torque > 0):
        raise ValueError(f"torque = {float(torque)!r} N·m: allowed > 0 (the pinion drives)")
    if damping is None:  # the seed's D1 (built here: its arrays take the caller's dtype)
        damping = RayleighDamping(alpha=25.0, beta=2.5e-6)
    return HybridModel(scene, mods, torque, damping, bool(rotating_frame))


@_engine.register
def _(
    scene: DynamicScene,
    mods,
    torque,
    damping,
    *,
    positions_per_pitch=64,
    contact=ExactContact(),
    rotating_frame=False,
    revolutions=None,
) -> DynamicModel:
    if rotating_frame:
        raise ValueError(
            "rotating_frame = True: only a hybrid scene (condensed bodies) has turning body "
            "frames; a lumped scene's gears are rigid"
        )
    if damping is None:
        damping = CompositeDamping()
    span = None
    if revolutions is not None:
        check_integer("revolutions", revolutions, 1)
        z1 = [d.pinion.teeth for d in deviations_in(mods) if d.pinion is not None]
        if not z1:
            z1 = [
                round(2 * math.pi * float(p.base_radius_pinion) / float(p.base_pitch))
                for p in scene.base_planes[:1]
            ]
        span = int(revolutions) * z1[0]
    law = contact_law(contact, torque.dtype)
    return _build(scene, mods, torque, damping, law, positions_per_pitch, span)


def _build(scene, mods, torque, damping, law, positions_per_pitch, span=None):
    failed = (
        "dynamic_model: the static contact solve failed at some mesh positions "
        "(no contact or no convergence): check the load and the deviations"
    )
    # Concrete inputs (no outer jit, vmap or grad): the torque was checked by check_operating
    # and the static solve's result codes are read here, on the host: an eqx.error_if on a
    # concrete value compiles a program of its own that holds a Python callback, which JAX's
    # persistent compilation cache does not store (a second CLI run compiled it again).
    if not is_traced((scene, mods, torque)):
        prep = _prepare_rows(scene, mods, torque, law, positions_per_pitch)
        if np.any(np.asarray(prep.static_result) != 0):
            raise eqx.EquinoxRuntimeError(failed)
        model = _averaged(scene, mods, torque, damping, prep, span)
        # the model holds these rows: its runs at this law and N_s reuse them (DynamicModel.held)
        inputs = (model.scene, model.mods, model.torque)
        periods = scene.scene_periods()
        held = _HeldTable(prep, law, inputs, int(positions_per_pitch), periods)
        return dataclasses.replace(model, held=held)
    # traced values (jit/vmap/grad): eqx.error_if raises EquinoxRuntimeError
    torque = eqx.error_if(
        torque, ~(torque > 0), "dynamic_model: torque must be > 0 N·m (the pinion drives)"
    )
    prep = _prepare_rows(scene, mods, torque, law, positions_per_pitch)
    model = _averaged(scene, mods, torque, damping, prep, span)
    kbar = eqx.error_if(model.mesh_stiffness_mean, jnp.any(prep.static_result != 0), failed)
    return eqx.tree_at(lambda m: m.mesh_stiffness_mean, model, kbar)


def _prepare_rows(scene, mods, torque, law, positions_per_pitch) -> _Prepared:
    """:func:`_prepare` over the scene's period, called as a run's table is
    (:meth:`DynamicModel.prepare`: every argument given, the scene's period written out), so
    that a model built at ``positions_per_pitch`` and run at as many steps per period without
    deviations compiles the table and static rows once, not twice (filter_jit keys on the
    arguments as given)."""
    return _prepare(
        scene, mods, torque, law, int(positions_per_pitch), scene.scene_periods(), True, True, None
    )


@eqx.filter_jit
def _averaged(scene, mods, torque, damping, prep, span=None):
    kl = _loaded_kl(prep)
    Km = _mean_mesh_matrix(prep.table, kl)
    kbar = jnp.mean(jnp.sum(kl, axis=1))
    modes = modal_analysis(scene, Km)
    C = damping_matrix(scene, modes, damping)
    return DynamicModel(
        scene=scene,
        mods=mods,
        torque=torque,
        damping=C,
        modes=modes,
        mesh_stiffness_mean=kbar,
        deviation_span=span,
    )


def _loaded_kl(prep: _Prepared) -> Float[Array, "S c"]:
    """The loaded cells' k l w (N/m) at every step of the span, (S, c)."""
    t, steps = prep.table, jnp.arange(prep.static_weight.shape[0])
    kl = jnp.where(t.take(t.mask, steps), t.take(t.k, steps) * t.take(t.length, steps), 0.0)
    return kl * prep.static_weight


def _mesh_parts(model: DynamicModel, positions_per_pitch: int, contact: ContactLaw):
    """The table and static rows over ``positions_per_pitch`` positions of a mesh period at the
    model's torque (the model's own when it holds them, :attr:`DynamicModel.held`), and each
    cell's mesh index (c,), a tuple (static)."""
    check_integer("positions_per_pitch", positions_per_pitch, 4)
    model._check_runs()
    law = contact_law(contact, model.dtype)
    prep = _held_or_prepare(
        model.held,
        model.scene,
        model.mods,
        model.torque,
        law,
        int(positions_per_pitch),
        model.scene.scene_periods(),
    )
    sizes = np.array([L * N for L, N in prep.table.sizes])
    return prep, tuple(int(k) for k in np.repeat(np.arange(sizes.size), sizes))


# one compiled program each (their steps eager were some 30 small programs of a first run)
@eqx.filter_jit
def _stiffness_means(prep: _Prepared, of_mesh: tuple) -> Float[Array, " m"]:
    kl, of_mesh = _loaded_kl(prep), np.asarray(of_mesh)
    # the barrier: each mesh's sum over its cells, then its mean over the steps (XLA would
    # merge the two reductions into one, summing in another order)
    return jnp.stack(
        [
            jnp.mean(
                jax.lax.optimization_barrier(
                    jnp.sum(jnp.where(jnp.asarray(of_mesh == k), kl, 0.0), axis=1)
                )
            )
            for k in range(int(of_mesh.max()) + 1)
        ]
    )


@eqx.filter_jit
def _energy_shares(prep: _Prepared, modes, of_mesh: tuple) -> Float[Array, "m n"]:
    kl, table, of_mesh = _loaded_kl(prep), prep.table, np.asarray(of_mesh)
    w2 = jnp.where(modes.rigid, 1.0, modes.omega**2)
    out = []
    for k in range(int(of_mesh.max()) + 1):
        kk = jnp.where(jnp.asarray(of_mesh == k)[None, :], kl, 0.0)
        Kk = _mean_mesh_matrix(table, kk)
        strain = jnp.sum(modes.shapes * (Kk @ modes.shapes), axis=0)
        out.append(jnp.where(modes.rigid, 0.0, strain / w2))
    return jnp.stack(out)


def mesh_stiffness_means(
    model: DynamicModel, *, positions_per_pitch: int = 64, contact: ContactLaw = ExactContact()
) -> Float[Array, " m"]:
    """Each mesh's time-averaged loaded stiffness k̄_k = ⟨Σ w k l⟩ over its cells (N/m), shape
    (meshes,), over ``positions_per_pitch`` positions of a mesh period at the model's torque
    (the split of :attr:`DynamicModel.mesh_stiffness_mean`)."""
    return _stiffness_means(*_mesh_parts(model, positions_per_pitch, contact))


def mesh_energy_shares(
    model: DynamicModel, *, positions_per_pitch: int = 64, contact: ContactLaw = ExactContact()
) -> Float[Array, "m n"]:
    """Each mesh's share of each mode's strain energy, e_ik = φ_iᵀ K̄_k φ_i / ω_i² (-), shape
    (meshes, modes): K̄_k the loaded stiffness of mesh k averaged over ``positions_per_pitch``
    positions of a mesh period at the model's torque (the split of the model's K̄_m, which its
    modes diagonalise); the meshes' rows sum to the mode's mesh share (:attr:`ModalAnalysis.
    mesh_energy`, (2.36)) up to the averaging grid. 0 for the rigid modes."""
    prep, of_mesh = _mesh_parts(model, positions_per_pitch, contact)
    return _energy_shares(prep, model.modes, of_mesh)


# --------------------------------------------------------------------------------------------
# results
