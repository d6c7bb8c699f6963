"""Shared by the scene tests: the case's dynamic model and its quasi-static solve with the load
rotation grounded (16 positions per mesh period, 6 slices), and a pair cut into two half-face
meshes (a scene of two meshes whose result is known: the pair's)."""

from __future__ import annotations

import dataclasses

import jax.numpy as jnp
import numpy as np

import jaxgear as jg
import jaxgear.scenes as js
from jaxgear.io import build_dynamic_model


def solve_grounded(scene, case, positions_per_pitch: int = 16):
    """The quasi-static solve of a 3D ``scene`` at ``case``'s modifications and torque, its
    load rotation grounded."""
    return jg.quasi_static(
        js.grounded(scene, (scene.torque_dofs[1],)),
        case.modifications,
        case.torque,
        positions_per_pitch=positions_per_pitch,
    )


def grounded_solve(case, spec=None):
    """(DynamicModel, QuasiStaticResult) of ``case`` with scene ``spec`` (default the case's)."""
    model, _ = build_dynamic_model(case, spec, slices=6)
    return model, solve_grounded(model.scene, case)


def half_face_meshes(mesh):
    """The gear mesh ``mesh`` (a spur pair) cut across the face into two meshes of half the face
    width on the same two members, each keeping its cells' place along the axes: the first
    covers z ∈ [0, b/2], the second z ∈ [b/2, b] (contact points M = T1 + (ρ_A + s) t +
    (z − b'/2) e_z with b' = b/2, so the tangent points move by ∓b/4 along z)."""
    plane = mesh.base_plane
    if plane.n_slices % 2:
        raise ValueError("half_face_meshes needs an even number of slices")
    half = dataclasses.replace(
        plane, face_width=0.5 * plane.face_width, n_slices=plane.n_slices // 2
    )
    ez = jnp.array([0.0, 0.0, 1.0], plane.face_width.dtype)
    return tuple(
        dataclasses.replace(
            mesh,
            base_plane=half,
            tangent_point=mesh.tangent_point + side * 0.25 * plane.face_width * ez,
        )
        for side in (-1.0, 1.0)
    )


def assert_split_equals_whole(whole, split, rtol):
    """The quasi-static results of a pair (``whole``, one mesh) and of the same pair as two
    half-face meshes (``split``) agree: coordinates, each half's TE equal to the pair's, the
    halves' mesh stiffness and contact length summing to the pair's, and their line loads side
    by side equal to the pair's."""
    a, b = split.meshes
    scale = float(np.max(np.abs(np.asarray(whole.x))))
    np.testing.assert_allclose(np.asarray(split.x), np.asarray(whole.x), rtol=0, atol=rtol * scale)
    for half in (a, b):
        np.testing.assert_allclose(
            np.asarray(half.transmission_error), np.asarray(whole.transmission_error), rtol=rtol
        )
    for name in ("mesh_stiffness", "contact_length"):
        np.testing.assert_allclose(
            np.asarray(getattr(a, name)) + np.asarray(getattr(b, name)),
            np.asarray(getattr(whole, name)),
            rtol=rtol,
        )
    joined = np.concatenate([np.asarray(a.line_load), np.asarray(b.line_load)], axis=-1)
    q = np.asarray(whole.line_load)
    np.testing.assert_allclose(joined, q, rtol=0, atol=rtol * float(np.max(q)))
