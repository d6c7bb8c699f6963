"""Helpers of the hybrid (condensed FE body) tests: a train case's module fixtures, the tooth
geometry of contact points, a body made stiffer, the rigid-body mass properties of a condensed
body, and the rigidified pair against the rigid-node lumped pair (the reference of the hybrid
dynamics: the same Newmark sweep on both)."""

from __future__ import annotations

import pathlib

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

import fem_prep
from jaxgear import Uniform, io as jio
from jaxgear.dynamics import Newmark, SteadyState, dynamic_model, simulate, speed_sweep
from jaxgear.io import load_bodies, static_scene
from jaxgear.scenes import FlexibleMember, disc_inertia, lumped_pair, mesh_zone_load

__all__ = [
    "drive_rotations",
    "rigid_mass_matrix",
    "rigid_properties",
    "rigidified_pair",
    "rigidified_runs",
    "stiffened_body",
    "tooth_offsets",
    "train_fixtures",
    "zone_compliance",
]

STEEL_E = "youngs_modulus_GPa = 210.0"


def train_fixtures(path: pathlib.Path) -> tuple:
    """Module-scoped fixtures ``case`` (the train case at ``path``), ``bodies`` (its condensed
    bodies, built in the session's fem_prep cache) and ``scene`` (its quasi-static train with
    them): assign them in a test module, ``case, bodies, scene = train_fixtures(CASE)``."""

    @pytest.fixture(scope="module", name="case")
    def case(fem_prep_cache):
        return jio.load_case(path)

    @pytest.fixture(scope="module", name="bodies")
    def bodies(case):
        return load_bodies(case.scene)

    @pytest.fixture(scope="module", name="scene")
    def scene(case, bodies):
        return case.static_train(bodies=bodies)

    return case, bodies, scene


def drive_rotations(scene, count: int = 2) -> np.ndarray:
    """The null space of the scene's stiffness K (n, count), unit columns: its ``count`` free
    drive rotations, asserted to be exactly ``count`` (the diagonally scaled K's lowest
    eigenvalues below 1e-12 of its largest, the next above 1e-6)."""
    K = np.asarray(scene.structure.K)
    d = np.sqrt(np.diag(K))
    w, v = np.linalg.eigh(K / np.outer(d, d))
    assert np.all(np.abs(w[:count]) < 1e-12 * w.max()) and w[count] > 1e-6 * w.max()
    null = v[:, :count] / d[:, None]
    return null / np.linalg.norm(null, axis=0)


def stiffened_body(path: pathlib.Path, factor: float, name: str | None = None):
    """The condensed body of the fem_prep file ``path`` with its steel's Young's modulus
    (210 GPa) times ``factor`` (cached under ``name``, default the file's own name)."""
    text = path.read_text()
    stiff = text.replace(STEEL_E, f"youngs_modulus_GPa = {210.0 * factor!r}")
    assert stiff != text, f"{path.name} has no {STEEL_E!r}"
    if name is None:
        return fem_prep.condensed(fem_prep.parse_body(stiff))
    return fem_prep.condensed(fem_prep.parse_body(stiff, default_name=name))


def tooth_offsets(member: FlexibleMember, mesh, side: float, theta: float) -> np.ndarray:
    """(φ_c − φ_station)/pitch of every cell on the flanks at scene angle θ, in (−½, ½]: the
    tooth centre line of each contact point by the involute (ψ(r) = ψ_b − inv α(r)) against
    the nearest station of the member's rim in the turning body frame. ``side``: +1 where the
    member drives the mesh, −1 where it is driven (the tooth lies on the side −side·n of its
    flank)."""
    points, mask, frame = (np.asarray(a) for a in _flank_points(member, mesh, jnp.asarray(theta)))
    p = points[mask]
    rel = p - np.asarray(member.centre)
    r = np.hypot(rel[:, 0], rel[:, 1])
    rb = float(member.base_radius)
    a = np.arccos(rb / r)
    psi = float(member.base_half_angle) - (np.tan(a) - a)
    n = np.asarray(mesh.normal)[:2]
    e_phi = np.stack([-rel[:, 1], rel[:, 0]], -1) / r[:, None]
    flank = np.sign(-side * (e_phi @ n))
    phi_c = np.arctan2(rel[:, 1], rel[:, 0]) + flank * psi
    t = (phi_c - float(frame) - float(member.station0)) / float(member.pitch_angle)
    return (t + 0.5) % 1.0 - 0.5


@eqx.filter_jit
def _flank_points(member: FlexibleMember, mesh, theta):
    """The cells' points and mask of ``mesh`` at scene angle θ and the member's body-frame
    angle there, in one compiled program per mesh (the angle traced)."""
    cells = mesh.base_plane.cells(mesh.angle(theta))
    return mesh.points(cells), cells.mask, member.frame_angle(theta)


def rigid_mass_matrix(body) -> np.ndarray:
    """The 6 × 6 mass matrix of a condensed body moved as one rigid body about its frame's
    origin (translations x, y, z, then rotations about x, y, z: w × x at a rim master, the
    rotation itself at a bearing master on the axis), its modal coordinates still (exact for
    Craig–Bampton: the constraint modes carry the interior rigidly)."""
    coords = np.asarray(body.master_coords)
    kind = np.asarray(body.master_kind)
    R = np.zeros((body.M.shape[0], 6))
    for i, (m, c) in enumerate(np.asarray(body.dof_map)):
        if m < 0:
            continue
        for a in range(3):
            w = np.eye(3)[a]
            R[i, a] = float(c == a)
            R[i, 3 + a] = w[c - 3] if (kind[m] == 1 and c >= 3) else np.cross(w, coords[m])[c]
    return R.T @ np.asarray(body.M) @ R


def rigid_properties(scene, body, member: int) -> list[float]:
    """Mass, diametral and polar inertia (about the body's centre) of the condensed body of
    ``scene.members[member]`` with its teeth: the rigid motions of its master DOFs through its
    condensed mass, the teeth the scene lumps on its rim DOFs added."""
    gear = scene.members[member]
    bd = np.asarray(gear.body_dofs)
    xyz = np.asarray(body.master_coords)
    M = np.array(body.M, dtype=float)
    rim = np.flatnonzero(np.isin(bd, np.asarray(gear.rim_dofs).ravel()))
    M[rim, rim] = np.asarray(scene.structure.M)[bd[rim], bd[rim]]
    out = []
    for mode in ("tx", "rx", "rz"):
        r = np.zeros(bd.size)
        for i, (m, c) in enumerate(np.asarray(body.dof_map)):
            if m < 0:
                continue
            if body.master_kind[m] == 1 and c >= 3:  # bearing node rotations
                r[i] = {"tx": 0.0, "rx": float(c == 3), "rz": float(c == 5)}[mode]
                continue
            x, y, z = xyz[m]
            r[i] = {"tx": (1.0, 0.0, 0.0), "rx": (0.0, -z, y), "rz": (-y, x, 0.0)}[mode][c]
        out.append(float(r @ M @ r))
    return out


def rigidified_pair(case, member: int, body: pathlib.Path, factor: float) -> tuple:
    """The pair ``case`` with the body file ``body`` ``factor`` times stiffer as its condensed
    ``member`` (0 the pinion, 1 the wheel; the other a rigid node), and the rigid-node lumped
    pair given that body's mass and inertias (:func:`rigid_properties`) and the other gear a
    disc of its tip radius and face width; uniform mesh stiffness in both: (case, hybrid scene,
    lumped scene)."""
    stiff = stiffened_body(body, factor)
    uni = case.replace(stiffness=Uniform(1.4e10))
    bodies = (stiff, None) if member == 0 else (None, stiff)
    hyb = static_scene(uni, bodies=bodies)[0]
    pair, rho = uni.pair, uni.density
    other = 1 - member
    r, b = pair.tip_radii[other], (pair.pinion, pair.gear)[other].face_width
    m_disc, i_polar = rho * np.pi * r**2 * b, disc_inertia(rho, r, b)
    m_body, i_dia, i_pol = rigid_properties(hyb, stiff, member)
    masses, inertias = [0.0, 0.0], [None, None]
    masses[member], inertias[member] = m_body, (i_dia, i_pol)
    masses[other], inertias[other] = m_disc, (i_polar / 2 + m_disc * b**2 / 12, i_polar)
    spec = uni.scene
    lumped = lumped_pair(
        pair,
        hyb.mesh,
        spec.pinion_shaft,
        spec.gear_shaft,
        masses=tuple(masses),
        inertias=tuple(inertias),
        youngs_modulus=uni.youngs_modulus,
        poisson_ratio=uni.poisson_ratio,
        density=rho,
    )
    return uni, hyb, lumped


def rigidified_runs(pair: tuple, speeds, damping, spp=32, periods=60, rotating_frame=False):
    """The rigidified hybrid sweep and the lumped model's runs (``pair``:
    :func:`rigidified_pair`) at ``speeds`` with the same damping model (on the period-averaged
    mesh stiffness), Newmark with ``spp`` steps per period, ``periods`` periods with 2 kept:
    (the hybrid sweep's results, the lumped runs, the lumped model)."""
    uni, hyb, lumped = pair
    kw = {"integrator": Newmark(spp), "window": SteadyState(periods, 2)}
    hybrid = dynamic_model(
        hyb, uni.modifications, uni.torque, damping, rotating_frame=rotating_frame
    )
    sw = speed_sweep(hybrid, speeds, **kw).results
    assert np.all(np.asarray(sw.result) == 0)
    model = dynamic_model(lumped, uni.modifications, uni.torque, damping, positions_per_pitch=spp)
    refs = [simulate(model, s, **kw) for s in speeds]
    return sw, refs, model


def zone_compliance(scene, theta: float) -> np.ndarray:
    """The 2 × 2 compliance (m/N) between the contact zones of a hybrid train's two meshes on
    its condensed bodies alone, their shaft coordinates (which come first) held: Fᵀ K⁻¹ F with
    F the two zones' unit loads (:func:`jaxgear.scenes.mesh_zone_load`) at scene angle θ."""
    first = scene.structure.C_bearing.shape[0]
    K = np.asarray(scene.structure.K)[first:, first:]
    F = np.asarray(_zone_loads(scene, jnp.asarray(theta, dtype=float)))
    return F.T @ np.linalg.solve(K, F)


@eqx.filter_jit
def _zone_loads(scene, theta):
    """The two zones' loads of :func:`zone_compliance` (n − first, 2) in one compiled program
    (the scene angle traced: one program for every angle; eagerly, mesh_zone_load's operations
    compile one by one, 170 small programs)."""
    first = scene.structure.C_bearing.shape[0]
    return jnp.stack([mesh_zone_load(scene, k, theta, first) for k in range(2)], 1)
