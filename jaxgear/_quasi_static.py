"""Quasi-static transmission error, mesh stiffness and load distribution over mesh positions."""

from __future__ import annotations

import functools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Bool, Float, Int

from ._backlash import check_no_coast, flank_separation
from ._baseplane import (
    MeshModel,
    check_positions,
    mesh_positions,
    split_by_mesh,
)
from ._contact import (
    ContactLaw,
    ExactContact,
    contact_law,
)
from ._modifications import Modifications
from ._results import ContactResult, error_if_failed, raise_if_failed
from ._util import (
    check_instance,
    check_real,
    is_traced,
    of_the_one_mesh,
    only_one_mesh,
    rms_about_mean,
    safe_max,
)
from .scenes import RigidMesh, Scene

__all__ = ["MeshResult", "QuasiStaticResult", "mesh_positions", "quasi_static", "separation"]


class MeshResult(eqx.Module):
    """Quasi-static response of one gear mesh at P positions (cell arrays: (P, n_lines,
    n_slices) of this mesh).

    Attributes:
        transmission_error: transverse TE along the line of action (m), shape (P,), measured from
            the perfect rigid position, positive under load (the driven gear lags):
            TE = (u·X − max_M e) / cos β_b (docs/design.md, "Modifications, initial separation
            and TE").
        mesh_stiffness: K(θ) = Σ k_ij l_ij over loaded cells (N/m), flank-normal in the base plane
            (smooth mode: the tangent stiffness Σ k l φ'(Δ)), shape (P,).
        contact_length: loaded contact length (m), shape (P,) (smooth mode weighted by φ').
        line_load: load per unit contact length per cell (N/m), shape (P, L, N).
        cell_s, cell_z: cell coordinates in the base plane (m), shape (P, L, N).
        cell_mask: cells on the flanks, shape (P, L, N).
        mesh_stiffness_on_path: the part of ``mesh_stiffness`` from the loaded cells on the
            theoretical path of contact, 0 <= s <= g_α (N/m), shape (P,): all of it on a
            :class:`~jaxgear.TheoreticalPath` (``MeshModel.contact_geometry``); on a
            :class:`~jaxgear.BeyondPath` the tip corners' cells beyond the path are left out
            (docs/extended-contact.md, "Mesh stiffness on and beyond the path"). ``None`` in a
            result built by hand.
    """

    transmission_error: Float[Array, " P"]
    mesh_stiffness: Float[Array, " P"]
    contact_length: Float[Array, " P"]
    line_load: Float[Array, "P L N"]
    cell_s: Float[Array, "P L N"]
    cell_z: Float[Array, "P L N"]
    cell_mask: Bool[Array, "P L N"]
    mesh_stiffness_on_path: Float[Array, " P"] | None = None

    @property
    def te_mean(self):
        """Mean TE (m)."""
        return jnp.mean(self.transmission_error)

    @property
    def te_rms(self):
        """RMS of the TE about its mean (m)."""
        return rms_about_mean(self.transmission_error)

    @property
    def te_ptp(self):
        """Peak-to-peak TE (m). (safe_max: jnp.max's and jnp.min's values, with a derivative
        that never divides by a zero count of extrema.)"""
        return safe_max(self.transmission_error) + safe_max(-self.transmission_error)

    @property
    def max_line_load(self):
        """Largest load per unit contact length (N/m) (safe_max: jnp.max's value)."""
        return safe_max(self.line_load)


class QuasiStaticResult(eqx.Module):
    """Quasi-static response at P pinion positions: the structure's coordinates and, per gear
    mesh, a :class:`MeshResult`.

    A scene of one gear mesh reads that mesh's results directly on this object
    (``transmission_error``, ``mesh_stiffness``, ``mesh_stiffness_on_path``, ``contact_length``,
    ``line_load``, ``cell_s``, ``cell_z``, ``cell_mask``, ``te_mean``, ``te_rms``, ``te_ptp``, ``max_line_load``: see
    :class:`MeshResult`); a scene of several meshes reads them from ``meshes[k]``.

    Attributes:
        theta: pinion angle (rad), shape (P,).
        x: generalised coordinates of the scene, shape (P, n).
        iterations, result: contact-solver passes and result code per position, shape (P,).
        meshes: one :class:`MeshResult` per gear mesh, in the scene's mesh order.
    """

    theta: Float[Array, " P"]
    x: Float[Array, "P n"]
    iterations: Int[Array, " P"]
    result: Int[Array, " P"]
    meshes: tuple[MeshResult, ...]

    @property
    def mesh(self) -> MeshResult:
        """The results of the scene's one gear mesh."""
        return only_one_mesh(self.meshes, "results")

    transmission_error = of_the_one_mesh("transmission_error")
    mesh_stiffness = of_the_one_mesh("mesh_stiffness")
    mesh_stiffness_on_path = of_the_one_mesh("mesh_stiffness_on_path")
    contact_length = of_the_one_mesh("contact_length")
    line_load = of_the_one_mesh("line_load")
    cell_s = of_the_one_mesh("cell_s")
    cell_z = of_the_one_mesh("cell_z")
    cell_mask = of_the_one_mesh("cell_mask")
    te_mean = of_the_one_mesh("te_mean")
    te_rms = of_the_one_mesh("te_rms")
    te_ptp = of_the_one_mesh("te_ptp")
    max_line_load = of_the_one_mesh("max_line_load")


@functools.singledispatch
def per_mesh_modifications(mods, n_meshes: int) -> tuple[Modifications, ...]:
    """One :class:`Modifications` per mesh from ``mods``: None (perfect involutes), one for
    every mesh, or a tuple/list of one per mesh (dispatched on the type of ``mods``).

    Raises:
        ValueError: a tuple of another length than ``n_meshes``.
    """
    return (mods,) * n_meshes


@per_mesh_modifications.register(type(None))
def _no_modifications(mods, n_meshes: int) -> tuple[Modifications, ...]:
    return (Modifications(),) * n_meshes


@per_mesh_modifications.register(tuple)
@per_mesh_modifications.register(list)
def _modifications_per_mesh(mods, n_meshes: int) -> tuple[Modifications, ...]:
    if len(mods) != n_meshes:
        raise ValueError(
            f"modifications: {len(mods)} given for a scene of {n_meshes} gear meshes (allowed: "
            "one Modifications for every mesh, or one per mesh)"
        )
    return tuple(mods)


@functools.singledispatch
def _named_modifications(mods, name: str) -> tuple:
    """(argument name, value) of each modification ``mods`` holds, for the input checks: one
    object as ``name``, a tuple/list entry by entry as ``name[k]``, None none."""
    return ((name, mods),)


@_named_modifications.register(type(None))
def _no_named_modifications(mods, name: str) -> tuple:
    return ()


@_named_modifications.register(tuple)
@_named_modifications.register(list)
def _named_modifications_per_mesh(mods, name: str) -> tuple:
    return tuple((f"{name}[{k}]", m) for k, m in enumerate(mods))


def separation(mesh: MeshModel, mods: Modifications, theta):
    """Cells at pinion angle ``theta`` (rad), max_M e (m) and δ0 = max e − e per cell (m, (2.8)).

    Shared by the quasi-static and the dynamic solvers. δ0 is 0 outside the mask. The
    manufacturing deviations that ``mods`` carries (``mods.deviations``, per tooth, at the absolute
    angle ``theta``) add to e (docs/deviations.md, "Initial separation").
    """
    cells = mesh.cells(theta)
    # beyond the theoretical path (``mesh.contact_geometry``) the tip corner touches the mating
    # flank: the deviations are the path ends' and the corner's gap adds (docs/extended-contact.md)
    geometry = mesh.contact_geometry
    on_path = geometry.deviation_cells(mesh, cells)
    e = mods.deviation(on_path.s / mesh.path_of_contact, cells.z / mesh.face_width)
    deviations = mods.deviations
    if deviations is not None:
        check_no_coast(mesh, "deviations (per-tooth ISO 1328-1)")
        e = e + deviations.deviation(mesh, on_path)
    # with coast flanks (docs/backlash.md) their gap holds the backlash
    e_max, delta0 = flank_separation(mesh, cells, e)
    return cells, e_max, geometry.with_corner_gap(mesh, cells, delta0)


def mesh_separations(scene: Scene, mods: tuple, theta) -> list:
    """:func:`separation` of every mesh of ``scene`` at the scene angle θ (rad), each at its mesh
    angle (:meth:`jaxgear.scenes.Scene.mesh_angles`; θ for a pair's meshes) with its
    modifications (``mods``: one per mesh): a list of (cells, max e, δ0), one per mesh."""
    angles = scene.mesh_angles(theta)
    return [separation(p, m, a) for p, m, a in zip(scene.base_planes, mods, angles, strict=True)]


def _one_position(scene: Scene, mods: tuple, torque, speed, theta, law: ContactLaw):
    planes = scene.base_planes
    parts = mesh_separations(scene, mods, theta)
    cells = tuple(p[0] for p in parts)
    sol, x, u_x = scene.static_contact(cells, tuple(p[2] for p in parts), torque, speed, law)
    shapes = [c.mask.shape for c in cells]
    weights = split_by_mesh(sol.weight, shapes)
    loads = split_by_mesh(sol.force_density, shapes)
    meshes = []
    for k, (mesh, (c, e_max, _)) in enumerate(zip(planes, parts, strict=True)):
        kl = jnp.where(c.mask, c.stiffness * c.length, 0.0)
        on_path = (c.s >= 0.0) & (c.s <= mesh.path_of_contact)
        meshes.append(
            MeshResult(
                transmission_error=(u_x[k] - e_max) / jnp.cos(mesh.base_helix_angle),
                mesh_stiffness=jnp.sum(kl * weights[k]),
                contact_length=jnp.sum(c.length * weights[k]),
                line_load=loads[k],
                cell_s=c.s,
                cell_z=c.z,
                cell_mask=c.mask,
                mesh_stiffness_on_path=jnp.sum(jnp.where(on_path, kl * weights[k], 0.0)),
            )
        )
    # a cell approach that would close the corner gap at the far end of the cells beyond the
    # theoretical path fails loudly: the extension is too short (docs/extended-contact.md)
    gaps = split_by_mesh(sol.gap, shapes)
    over = [
        mesh.extension_overrun(c, gaps[k])
        for k, (mesh, c) in enumerate(zip(planes, cells, strict=True))
    ]
    result = jnp.where(
        (sol.result == ContactResult.successful) & jnp.any(jnp.stack(over)),
        ContactResult.beyond_extension,
        sol.result,
    )
    return QuasiStaticResult(
        theta=theta,
        x=x,
        iterations=sol.iterations,
        result=result,
        meshes=tuple(meshes),
    )


@functools.singledispatch
def _as_scene(scene: Scene) -> Scene:
    """The scene :func:`quasi_static` solves: a scene itself; a :class:`MeshModel`'s is its
    rigid pair (:class:`jaxgear.scenes.RigidMesh`, built under jit: cheaper than eagerly)."""
    return scene


@_as_scene.register
def _mesh_scene(scene: MeshModel) -> Scene:
    return RigidMesh(scene)


@eqx.filter_jit
def _quasi_static(scene, mods, torque, speed, theta, law, throw, positions, traced_checks=True):
    """:func:`quasi_static` under jit; ``positions``: (positions per pitch, periods) of the
    default angles."""
    # defaults are made here, under jit: building them eagerly costs more than the solve
    scene = _as_scene(scene)
    mods = per_mesh_modifications(mods, len(scene.base_planes))
    if theta is None:
        theta = mesh_positions(scene.base_planes[0], *positions)
    if traced_checks:  # traced inputs (concrete ones are checked eagerly: check_operating)
        coast = any(p.coast for p in scene.base_planes)  # a negative torque loads the coast
        torque = eqx.error_if(
            torque,
            ~(torque != 0) if coast else ~(torque > 0),
            "operating.torque_Nm must be != 0 (with coast flanks: > 0 drive, < 0 coast)"
            if coast
            else "operating.torque_Nm must be > 0 (the pinion drives on its working flank)",
        )
        speed = eqx.error_if(speed, ~(speed >= 0), "the pinion speed must be >= 0 (rad/s)")
        law = law.with_traced_checks()  # e.g. a traced smooth width
    res = scene.map_positions(lambda sc, th: _one_position(sc, mods, torque, speed, th, law), theta)
    if throw:  # the check rides on what a caller reads (each mesh's TE, the coordinates)

        def guarded(r):
            return [m.transmission_error for m in r.meshes] + [r.x]

        res = eqx.tree_at(
            guarded,
            res,
            [error_if_failed(v, res.result, ContactResult, "quasi_static") for v in guarded(res)],
        )
    return res


def check_operating(
    where: str,
    scene,
    modifications,
    torque,
    theta=None,
    speed=None,
    *,
    coast_torque: bool = True,
    mods_name: str = "modifications",
) -> None:
    """The public inputs of :func:`quasi_static` (and of the dynamic model's builder, ``where``
    naming the entry), before any tracing: types and shapes always, values where they are
    concrete (a traced torque, under ``jax.grad`` or ``jax.vmap``, is checked by
    ``eqx.error_if`` inside). ``coast_torque``: with coast flanks any torque != 0
    (quasi-statics), else > 0. ``mods_name``: the modifications' argument name. One-line
    ``ValueError`` naming the argument, its value and the allowed range."""
    check_instance(
        "scene", scene, (Scene, MeshModel), "a jaxgear Scene (RigidMesh, ...) or MeshModel", where
    )
    allowed = "None, a jaxgear.Modifications, or a tuple of one per gear mesh"
    for name, m in _named_modifications(modifications, mods_name):
        check_instance(name, m, Modifications, allowed, where)
    coast = coast_torque and any(p.coast for p in scene.base_planes)
    check_real(
        "torque", torque, "N·m", lo=None if coast else 0.0, lo_open=True, shape=(), where=where
    )
    if coast and not is_traced(torque) and float(torque) == 0.0:
        raise ValueError(
            f"{where}: torque = 0 N·m is out of range: allowed != 0 with coast flanks (> 0 "
            "drive, < 0 coast)"
        )
    if theta is not None:
        check_real("theta", theta, "rad", shape=(None,), shape_text="(n,)", where=where)
        if jnp.shape(theta)[0] < 1:
            raise ValueError(f"{where}: theta must have shape (n,) [rad] with n >= 1, got (0,)")
    if speed is not None:
        check_real("speed", speed, "rad/s", lo=0.0, shape=(), where=where)


def at_torques(
    scene: Scene | MeshModel,
    modifications: Modifications | None,
    torques,
    read,
    *,
    contact: ContactLaw = ExactContact(),
    positions_per_pitch: int = 64,
):
    """:func:`quasi_static` at rest over one mesh period at each of the pinion torques
    ``torques`` (N·m, (T,), concrete), side by side (``jax.vmap``), with ``throw=False``:
    (``read`` of each torque's :class:`QuasiStaticResult`, its arrays leading with T; the result
    codes, (T, P)), the caller reading the codes (:func:`raise_if_failed`). The
    torques are checked here, on the host (finite, > 0), as a concrete torque is, so that the
    vmapped solve holds no ``eqx.error_if`` of a traced torque (a Python callback: JAX's
    persistent compilation cache never stores such a program, and each run compiled it again).

    Raises:
        ValueError: torques not a non-empty 1-D array of finite values > 0 (N·m); the inputs
            :func:`quasi_static` refuses."""
    t = np.asarray(torques, dtype=float)
    if t.ndim != 1 or t.size < 1 or not np.all(np.isfinite(t)) or not np.all(t > 0):
        raise ValueError(
            f"torques = {torques!r}: allowed a non-empty 1-D array of finite pinion torques > 0 "
            "(N·m)"
        )
    check_positions(positions_per_pitch, 1)
    check_operating("quasi_static", scene, modifications, float(t[0]))
    planes = scene.base_planes
    modifications = per_mesh_modifications(modifications, len(planes))
    for plane, mods in zip(planes, modifications, strict=True):
        if mods.deviations is not None:
            mods.deviations.check(plane)
    dtype = planes[0].base_pitch.dtype
    speed = jnp.asarray(0.0, dtype=dtype)
    law = contact_law(contact, dtype)
    positions = (int(positions_per_pitch), 1)

    def one(torque):
        r = _quasi_static(scene, modifications, torque, speed, None, law, False, positions, False)
        return read(r), r.result

    return jax.vmap(one)(jnp.asarray(t, dtype=dtype))


def quasi_static(
    scene: Scene | MeshModel,
    modifications: Modifications | None,
    torque,
    theta: Float[Array, " P"] | None = None,
    *,
    speed=0.0,
    contact: ContactLaw = ExactContact(),
    positions_per_pitch: int = 64,
    periods: int = 1,
    throw: bool = True,
) -> QuasiStaticResult:
    """Quasi-static (no inertia) loaded contact of the gear pair at a series of pinion angles.

    Args:
        scene: a :class:`Scene` (e.g. :class:`RigidMesh`, :class:`TorsionalPair`), or a
            :class:`MeshModel` for the rigid 1-DOF mesh.
        modifications: flank modifications (``None``: perfect involutes): one
            :class:`Modifications` for every mesh of the scene, or a tuple of one per mesh; with
            ``deviations`` (per-tooth ISO 1328-1 deviations) the result depends on the absolute
            angle: cover whole revolutions with ``periods = z1 × revolutions``
            (:func:`~jaxgear.hunting_revolutions`; docs/deviations.md).
        torque: pinion torque T (N·m), > 0, scalar array (a traced value is fine: differentiable);
            with coast flanks (a mesh built with ``coast``: backlash) any T != 0, T < 0 loading
            the coast flanks (the TE then sits a backlash j_bn/cos β_b below the drive side).
        theta: scene angles θ (rad, the pinion's), shape (P,); default :func:`mesh_positions`
            of the first mesh over ``periods`` mesh periods with ``positions_per_pitch``
            positions each. Each mesh takes its cells at its own mesh angle
            (:meth:`~jaxgear.scenes.Scene.mesh_angles`: θ itself for the meshes of one pair,
            such as the two halves of a double-helical pair; ratio θ + phase in a train).
        speed: pinion speed Ω (rad/s) >= 0 of the centrifugal loads of condensed bodies
            (a hybrid scene: each body at its own speed, seed (2.37)); rigid gear bodies carry
            none, so other scenes do not depend on it. Default 0: at rest.
        contact: the contact law, :class:`~jaxgear.ExactContact` (active set, seed II-25;
            default) or :class:`~jaxgear.SmoothContact` (softplus ramp of its width;
            docs/design.md, "Contact laws"), with its cap on active-set passes / Newton steps
            per position.
        throw: raise ``eqx.EquinoxRuntimeError`` when a position fails (contact loop not
            converged, no contact, non-finite state); with ``False`` read ``result`` instead
            (0 = converged; :class:`~jaxgear.ContactResult`).

    Returns:
        :class:`QuasiStaticResult` (one :class:`MeshResult` per mesh; the contact of all meshes
        is solved at once, so that they share the structure's compliance).

    Raises:
        ValueError: ``contact`` not a contact law, bad position counts (at trace time),
            deviations whose per-tooth arrays do not have the mesh's tooth counts; before any
            tracing, one line naming the argument, its value and the allowed range: a
            ``scene`` that is neither a scene nor a :class:`MeshModel`, ``modifications`` that
            are not :class:`Modifications`, a torque that is not a scalar or (concrete) not
            finite and > 0 (!= 0 with coast flanks), ``theta`` not of shape (P,) or not
            finite, a speed not a finite scalar >= 0.
        eqx.EquinoxRuntimeError: a traced torque <= 0 (== 0 with coast flanks), width <= 0, a
            traced negative speed, solver failure (with ``throw``).
    """
    return _solve(
        scene, modifications, torque, theta, speed, contact, positions_per_pitch, periods, throw
    )


def _solve(
    scene,
    modifications,
    torque,
    theta,
    speed,
    contact,
    positions_per_pitch=64,
    periods=1,
    throw=True,
    host_checked=False,
):
    """:func:`quasi_static` (the same arguments); ``host_checked``: the torque and speed, traced
    here, were checked on the host before the caller's trace (a dynamic model's torque when
    it was built, the speeds of a run before its program): the solve then holds no
    ``eqx.error_if`` of them, whose Python callback would keep the caller's program out of
    JAX's persistent compilation cache."""
    check_positions(positions_per_pitch, periods)
    check_operating("quasi_static", scene, modifications, torque, theta, speed)
    planes = scene.base_planes  # a MeshModel's: itself
    # one per mesh before jit: None, one for every mesh and a tuple of the same meshes' (a CLI
    # run's unmodified and modified flanks of a train) then share one compiled program
    modifications = per_mesh_modifications(modifications, len(planes))
    for plane, mods in zip(planes, modifications, strict=True):
        if mods.deviations is not None:  # tooth counts, eagerly
            mods.deviations.check(plane)
    dtype = planes[0].base_pitch.dtype
    torque = jnp.asarray(torque, dtype=dtype)
    speed = jnp.asarray(speed, dtype=dtype)
    law = contact_law(contact, dtype)
    if theta is not None:
        theta = jnp.asarray(theta, dtype=dtype)
    # Concrete inputs (no outer jit, vmap or grad): checked eagerly above, and the result codes
    # read here, so that the compiled solve holds no eqx.error_if callback (JAX's persistent
    # compilation cache stores no program with one: a second CLI run reads the solve back).
    concrete = not is_traced((scene, modifications, torque, speed, theta, law))
    res = _quasi_static(
        scene,
        modifications,
        torque,
        speed,
        theta,
        law,
        bool(throw) and not concrete,
        (int(positions_per_pitch), int(periods)),
        not concrete and not host_checked,
    )
    if concrete and throw:
        raise_if_failed(res.result, ContactResult, "quasi_static")
    return res
