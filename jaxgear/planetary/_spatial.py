"""The 3D lumped model of a helical planetary stage: six coordinates per member (three
translations, three rotations), helical meshes whose normal has an axial component, bearings
with translational, axial, tilting and torsional stiffnesses, in the carrier frame
(docs/planetary.md, "The 3D lumped model").

Sources: T. Eritenel and R. G. Parker, "Modal properties of three-dimensional helical planetary
gears", J. Sound Vib. 325 (2009) 397-420 (the model and its three mode types); T. Eritenel and
R. G. Parker, "Three-dimensional nonlinear vibration of gear pairs", J. Sound Vib. 331 (2012)
3628-3648 (the mesh as a stiffness spread over the face: its translational and tilting parts);
J. Lin and R. G. Parker (1999) for the planar part, which this model holds exactly at beta_b = 0.

Conventions (those of :mod:`jaxgear.planetary._stage`, with z along the stage axis, right-handed with
the carrier frame's x, y). Each member's six coordinates, in this order:
``(x, y, z, theta_x, theta_y, u)`` for a central member (translations in m along the carrier
frame's axes, tilts in rad about x and y, u = r_b theta_z in m) and
``(zeta, eta, z, theta_zeta, theta_eta, u)`` for a planet (along and about its radial and
tangential directions e_zeta = (cos psi_n, sin psi_n), e_eta = (-sin psi_n, cos psi_n)). Members
in the order carrier, ring, sun, planets; every member's centre (and bearing) in the mesh
mid-plane z = 0.

A rigid member's material point at the lever arm rho (from its centre) moves by
``d + theta x rho`` with ``theta = (tilts, u / r_b)``. A mesh's deflection (compression
positive) at the point ``rho + s e_z`` (s across the face) is the projection on the tooth
normal n of the central member's motion less the planet's:

    n_sn = cos beta_b (-sin(psi_n - a_s), cos(psi_n - a_s), 0) + sin beta_b e_z
    n_rn = cos beta_b (-sin(psi_n + a_r), cos(psi_n + a_r), 0) - sin beta_b e_z

(the transverse parts are Lin & Parker's lines of action; beta_b > 0 a right-hand planet, its
normal's axial part of opposite signs at the sun and the ring side, as a helicoid's normal
n_z = -(moment of n about the axis) / lead requires). The mesh point is the transverse pitch
point seen by each member: rho = (r_b / cos a) e_zeta for the sun and the ring, -(r_bp / cos a_s)
e_zeta and +(r_bp / cos a_r) e_zeta for the planet's sun and ring sides (they coincide for a
stage whose radii fit; with them the u terms are Lin & Parker's exactly). The mesh stiffness k
acts along n, spread uniformly over the face width b: two Gauss points s = +-b / (2 sqrt 3),
k/2 each (exact for the linear deflection across the face). A relative tilt theta_perp about
e_perp = d x e_z (d the line of action's transverse direction) moves the point s by -s cos
beta_b theta_perp along n (n's transverse part is cos beta_b d): the mesh's tilting stiffness
is k b^2 cos^2(beta_b) / 12, not k b^2 / 12 (23 % less at beta_b = 28.5 deg). A stage may give
each mesh's tilting stiffness instead (``sun_mesh_tilt_stiffness``,
``ring_mesh_tilt_stiffness``): the points then sit at +-b_kappa / (2 sqrt 3) with that
stiffness (:meth:`~jaxgear.planetary.PlanetaryStage.mesh_face_widths`).

The planet pin joins the carrier's material point at r_c e_zeta to the planet centre: stiffness
(k_zeta, k_eta) = the planet's ``bearing_stiffness``, k_z its ``axial_stiffness``, and the
relative tilts about e_zeta, e_eta its ``tilt_stiffness``. The central members' bearings act on
their own coordinates (``bearing_stiffness`` on x, y; ``axial_stiffness`` on z;
``tilt_stiffness`` on the tilts; ``torsional_stiffness`` on theta_z).

Rotating frame (``M q'' + Omega G q' + (K - Omega^2 K_Omega) q = f``), every member taken as
turning with the carrier, as the lumped models of the literature do (Lin & Parker 1999 for the
translations; Eritenel & Parker 2009 for the tilts): the Coriolis and centripetal terms of the
in-plane translations are the planar model's (per member ``G = [[0, -2m], [2m, 0]]`` on x, y,
``K_Omega = diag(m, m)``; the axial translation has none); the tilts of an axisymmetric body
(diametral inertia I_d, polar J) turning at Omega obey Euler's equations in the turning frame,
``I_d theta_x'' - (2 I_d - J) Omega theta_y' + (J - I_d) Omega^2 theta_x = M_x`` and
``I_d theta_y'' + (2 I_d - J) Omega theta_x' + (J - I_d) Omega^2 theta_y = M_y``: ``G = [[0,
-(2 I_d - J)], [2 I_d - J, 0]]``, ``K_Omega = (I_d - J) I`` on the tilts (a planet's about
e_zeta, e_eta, which turn with the carrier too). The gyroscopic moments of a member's spin
relative to the carrier, omega_r = omega - Omega, add ``-J omega_r`` to the tilts' gyroscopic
coefficient and ``J omega_r Omega`` to their stiffness (:meth:`SpatialPlanetary.spin_matrices`;
omega_r is set by the mesh travel speed v: v / r_bs for the sun, -v / r_br for the ring, -v /
r_bp for the planets, 0 for the carrier).

In the contact solve and the dynamics (``planetary_quasi_static``, ``planetary_dynamics``) each
cell of a mesh acts at its own contact point: P = C + sigma t + z e_z, C the transverse pitch
point, z the cell's axial position from the mesh mid-plane, sigma = s - s_C its place on the
path of contact (s, from the pair's engagement point) less the pitch point's, t the sense the
contact travels (the sun's push on the planet for a sun mesh, the planet's on the ring for a
ring mesh). Its normal deflection is linear in (sigma, z): ``(V + z W + sigma X) q`` on the
transverse-equivalent rows (:meth:`SpatialPlanetary.face_rows`, :meth:`SpatialPlanetary.
line_rows`). With e_perp = d x e_z (d the line of action's transverse direction) the relative
tilt theta_perp = (theta_central - theta_planet) . e_perp moves it by (sigma sin beta_b - z cos
beta_b) theta_perp: the coordinate along the contact lines, whose moment arms across the face
and along the line of action the tilts see (the translations and the spin do not: every point
of the line of action is at r_b from the axis). Summed over the cells this is Eritenel &
Parker's (2009) mesh: the resultant at the centre of stiffness with the tilting stiffness of the
lines' spread. The lumped :meth:`SpatialPlanetary.stiffness_matrix` (and
:class:`~jaxgear.planetary.ConstantMeshes`) keeps the mesh at the pitch point, spread over the face.
"""

from __future__ import annotations

from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp

from ._stage import CENTRAL, AbstractPlanetaryModel, PlanetaryStage, _members
from .._util import as_float

__all__ = ["SpatialPlanetary"]

DOF = 6  # per member


def _size(stage: PlanetaryStage) -> int:
    return DOF * (CENTRAL + stage.n_planets)


def _skew(r):
    """[r]x, so that ``_skew(r) @ w = r x w``; r (..., 3) -> (..., 3, 3)."""
    z = jnp.zeros_like(r[..., 0])
    return jnp.stack(
        [
            jnp.stack([z, -r[..., 2], r[..., 1]], -1),
            jnp.stack([r[..., 2], z, -r[..., 0]], -1),
            jnp.stack([-r[..., 1], r[..., 0], z], -1),
        ],
        -2,
    )


def _frames(stage: PlanetaryStage):
    """(e_zeta, e_eta, e_z) of each planet, each (n, 3), in the carrier frame."""
    psi = stage.planet_angles
    zero, one = jnp.zeros_like(psi), jnp.ones_like(psi)
    e_zeta = jnp.stack([jnp.cos(psi), jnp.sin(psi), zero], -1)
    e_eta = jnp.stack([-jnp.sin(psi), jnp.cos(psi), zero], -1)
    e_z = jnp.stack([zero, zero, one], -1)
    return e_zeta, e_eta, e_z


def _point_map(axes, rho, base_radius):
    """(..., 3, 6): the displacement of the material point at the lever arm rho (..., 3) of a
    member whose coordinates' axes are ``axes`` (..., 3, 3, broadcasting: columns the two
    in-plane axes and e_z): ``d + theta x rho = E d - [rho]x theta``."""
    rot = -_skew(rho)
    tilt = rot @ axes[..., :2]
    spin = rot[..., 2:3] / base_radius
    return jnp.concatenate([jnp.broadcast_to(axes, rot.shape), tilt, spin], -1)


def _per_member(stage: PlanetaryStage, value):
    """(3 + N,): ``value(member)`` of each member, in the coordinates' order."""
    return jnp.stack([jnp.asarray(value(m)) for m in _members(stage)])


def _blocks(*parts):
    """(n_dof, n_dof): the block-diagonal matrix whose member j's 6 x 6 block holds, for each
    pair (values, (row, col)) of ``parts``, values[j] at (row, col)."""
    values = parts[0::2]
    n = values[0].shape[0]
    block = jnp.zeros((n, DOF, DOF), dtype=values[0].dtype)
    for v, (r, c) in zip(values, parts[1::2], strict=True):
        unit = jnp.zeros((1, DOF, DOF), dtype=v.dtype).at[0, r, c].set(1.0)
        block = block + v[:, None, None] * unit
    eye = jnp.eye(n, dtype=block.dtype)
    return jnp.einsum("ab,aij->aibj", eye, block).reshape(n * DOF, n * DOF)


def _on_member(stage: PlanetaryStage, member: int, block):
    """(n, k, n_dof) rows with ``block`` (n, k, 6) on the coordinates of member ``member``."""
    n, k = block.shape[:2]
    before = jnp.zeros((n, k, DOF * member), dtype=block.dtype)
    after = jnp.zeros((n, k, _size(stage) - DOF * (member + 1)), dtype=block.dtype)
    return jnp.concatenate([before, block, after], -1)


def _on_planets(stage: PlanetaryStage, block):
    """(n, k, n_dof) rows with ``block`` (n, k, 6) on row n's planet's coordinates."""
    n, k = block.shape[:2]
    eye = jnp.eye(n, dtype=block.dtype)
    planets = (eye[:, None, :, None] * block[:, :, None, :]).reshape(n, k, n * DOF)
    return jnp.concatenate([jnp.zeros((n, k, DOF * CENTRAL), dtype=block.dtype), planets], -1)


def _mesh_rows(stage: PlanetaryStage, central: int, line, sign_z, angle, side, points):
    """(n, k, n_dof): the deflection rows (along the tooth normal, m) of the mesh of each
    planet with the central member ``central`` (1 ring, 2 sun) at the points ``points`` (k
    pairs (sigma, z), m) of its plane of action: sigma along the line of action from the
    transverse pitch point, in the sense the contact travels (``sign_z`` times the line's
    direction: the sun's push for the sun mesh, the planet's on the ring for the ring mesh),
    z along e_z from the mid-plane. Its line of action at the angle ``line`` (n,), ``sign_z``
    the sign of the normal's axial part, ``angle`` the pressure angle, ``side`` -1 (sun side of
    the planet) or +1 (ring side)."""
    psi = stage.planet_angles
    beta = stage.helix_angle
    central_member = _members(stage)[central]
    e_zeta, e_eta, e_z = _frames(stage)
    direction = jnp.stack([-jnp.sin(line), jnp.cos(line), jnp.zeros_like(psi)], -1)
    normal = jnp.cos(beta) * direction + sign_z * jnp.sin(beta) * e_z
    n, k = psi.shape[0], len(points)
    # each of sigma, z: one value per point (k,), or one per planet and point ((n,) each)
    sigma, z = (jnp.broadcast_to(jnp.asarray(v, dtype=psi.dtype).T, (n, k))
                for v in zip(*points, strict=True))
    shift = (sigma[:, :, None] * (sign_z * direction)[:, None, :]
             + z[:, :, None] * e_z[:, None, :])  # (n, k, 3)
    rho_c = (central_member.base_radius / jnp.cos(angle) * e_zeta)[:, None, :] + shift
    rho_p = (side * stage.planet.base_radius / jnp.cos(angle) * e_zeta)[:, None, :] + shift
    eye = jnp.eye(3, dtype=psi.dtype)
    planet_axes = jnp.stack([e_zeta, e_eta, e_z], -1)[:, None]  # (n, 1, 3, 3)
    a = jnp.einsum("ni,nkij->nkj", normal, _point_map(eye, rho_c, central_member.base_radius))
    b = jnp.einsum("ni,nkij->nkj", normal,
                   _point_map(planet_axes, rho_p, stage.planet.base_radius))
    return _on_member(stage, central, a) - _on_planets(stage, b)


def _both_meshes(stage: PlanetaryStage, points):
    """(V_s, V_r), each (n, k, n_dof): both meshes' normal rows at the points (sigma, z)."""
    psi, a_s, a_r = stage.planet_angles, stage.sun_pressure_angle, stage.ring_pressure_angle
    return (
        _mesh_rows(stage, 2, psi - a_s, 1.0, a_s, -1.0, points),
        _mesh_rows(stage, 1, psi + a_r, -1.0, a_r, 1.0, points),
    )


def _transverse_slopes(stage: PlanetaryStage, point):
    """((V_s, D_s), (V_r, D_r)), each (n_planets, n_dof): the transverse-equivalent rows (the
    normal ones over cos beta_b) at the pitch point and their change per metre towards
    ``point`` ((sigma, z) = (1, 0) or (0, 1))."""
    c = jnp.cos(stage.helix_angle)
    return tuple((r[:, 0] / c, (r[:, 1] - r[:, 0]) / c)
                 for r in _both_meshes(stage, ((0.0, 0.0), point)))


def _pin_rows(stage: PlanetaryStage):
    """(n, 5, n_dof): the pin's deflections (carrier less planet): translations along e_zeta,
    e_eta, e_z (m), then the relative tilts about e_zeta, e_eta (rad)."""
    n = stage.n_planets
    e_zeta, e_eta, e_z = _frames(stage)
    axes = jnp.stack([e_zeta, e_eta, e_z], -1)  # (n, 3, 3)
    eye = jnp.eye(3, dtype=e_z.dtype)
    r_c = stage.carrier.base_radius
    carrier = jnp.einsum("nji,njk->nik", axes, _point_map(eye, r_c * e_zeta, r_c))
    zeros = jnp.zeros((n, 2, 3), dtype=e_z.dtype)
    # the carrier's tilts about e_zeta, e_eta: their x, y components on theta_x, theta_y
    carrier_tilt = jnp.concatenate(
        [zeros, jnp.swapaxes(axes[..., :2], 1, 2)[..., :2], zeros[..., :1]], -1
    )
    planet = jnp.broadcast_to(jnp.eye(5, DOF, dtype=e_z.dtype), (n, 5, DOF))
    central = jnp.concatenate([carrier, carrier_tilt], 1)
    return _on_member(stage, 0, central) - _on_planets(stage, planet)


def _pin_stiffness(stage: PlanetaryStage):
    p = stage.planet
    return jnp.concatenate([p.bearing_stiffness, p.axial_stiffness[None], p.tilt_stiffness])


class SpatialPlanetary(AbstractPlanetaryModel):
    """The 3D lumped model of a helical planetary stage (Eritenel & Parker 2009): six
    coordinates per member, 6 (3 + N) in all, in the carrier frame (module docstring of
    :mod:`jaxgear.planetary._spatial` for the coordinates, the mesh normals and points, the
    pins and bearings). It uses the stage's ``helix_angle`` and ``face_width`` and the
    members' ``axial_stiffness``, ``tilt_stiffness`` and ``tilt_inertia``; at
    ``helix_angle = 0`` the in-plane coordinates (x, y, u) are Lin & Parker's planar model
    exactly and the axial-tilting ones decouple from them.

    Mode types (:func:`~jaxgear.planetary.classify_modes`; Eritenel & Parker 2009, equally spaced
    planets): ROTATIONAL_AXIAL (multiplicity 1: the central members rotate and move axially
    only), TRANSLATIONAL_TILTING (multiplicity 2: they translate in the plane and tilt only),
    PLANET (multiplicity N - 3: they stay still). :meth:`central_rotations` are therefore the
    central members' z and u, :meth:`central_translations` their x, y and tilts.

    In the contact solve and the dynamics (:func:`~jaxgear.planetary.planetary_quasi_static`,
    :func:`~jaxgear.planetary.planetary_dynamics`) each cell of a helical mesh sees the
    deflection along the tooth normal at its own contact point, its axial position across the
    face and its place along the line of action (:meth:`face_rows`, :meth:`line_rows`), so
    that a member's tilt moves the load along the contact lines; a
    :class:`~jaxgear.planetary.ConstantMeshes` spring is spread over the face by its ``face_points``
    (2: the Gauss points of :meth:`stiffness_matrix`). The members' spin relative to the
    carrier adds its gyroscopic moments (:meth:`spin_matrices`).
    """

    face_points: ClassVar[int] = 2  # the Gauss points of stiffness_matrix's mesh springs

    def reduction(self, stage):
        """T (3 (3 + N), 6 (3 + N)): the planar coordinates (x, y, u of each member) of q."""
        members = jnp.arange(CENTRAL + stage.n_planets)
        rows = 3 * members[:, None] + jnp.arange(3)[None, :]
        cols = DOF * members[:, None] + jnp.array([0, 1, 5])[None, :]
        t = jnp.zeros((3 * members.shape[0], _size(stage)), dtype=stage.planet_angles.dtype)
        return t.at[rows.ravel(), cols.ravel()].set(1.0)

    def dof_names(self, stage):
        central = tuple(
            f"{c}_{m}" for m in "crs" for c in ("x", "y", "z", "theta_x", "theta_y", "u")
        )
        planet = ("zeta", "eta", "z", "theta_zeta", "theta_eta", "u")
        return central + tuple(f"{c}_{i + 1}" for i in range(stage.n_planets) for c in planet)

    def central_translations(self, stage):
        return tuple(DOF * m + k for m in range(CENTRAL) for k in (0, 1, 3, 4))

    def central_rotations(self, stage):
        return tuple(DOF * m + k for m in range(CENTRAL) for k in (2, 5))

    def mode_types(self):
        return ("rotational-axial", "translational-tilting")

    @eqx.filter_jit
    def mass_matrix(self, stage):
        """M (kg, kg m^2 on the tilts): diag(m, m, m, I_d, I_d, I / r_b^2) per member."""
        return jnp.diag(
            jnp.concatenate(
                [
                    jnp.stack(
                        [m.mass, m.mass, m.mass, m.tilt_inertia, m.tilt_inertia, m.inertia_over_r2]
                    )
                    for m in _members(stage)
                ]
            )
        )

    @eqx.filter_jit
    def mesh_rows_across(self, stage: PlanetaryStage):
        """(V_s, V_r), each (n_planets, 2, n_dof): the mesh deflections (m, compression
        positive) at the two Gauss points across the face, ``delta = V q``: z = +-b / (2
        sqrt 3), b each mesh's :meth:`~jaxgear.planetary.PlanetaryStage.mesh_face_widths` (the face
        width, or the width giving its tilting stiffness)."""
        psi, a_s, a_r = stage.planet_angles, stage.sun_pressure_angle, stage.ring_pressure_angle
        g_s, g_r = (b / (2.0 * jnp.sqrt(3.0)) for b in stage.mesh_face_widths())
        return (
            _mesh_rows(stage, 2, psi - a_s, 1.0, a_s, -1.0, ((0.0, -g_s), (0.0, g_s))),
            _mesh_rows(stage, 1, psi + a_r, -1.0, a_r, 1.0, ((0.0, -g_r), (0.0, g_r))),
        )

    @eqx.filter_jit
    def face_rows(self, stage):
        """((V_s, W_s), (V_r, W_r)), each (n_planets, n_dof): the transverse-equivalent mesh
        deflection at the axial position z (m from the mid-plane, along e_z) is ``(V + z W) q``:
        the deflection along the tooth normal (at the transverse pitch point, module docstring)
        divided by cos beta_b, so that a cell's normal approach is cos beta_b times it, as for
        the planar model's transverse rows (``spring_cos``: cos beta_b)."""
        return _transverse_slopes(stage, (0.0, 1.0))

    @eqx.filter_jit
    def line_rows(self, stage):
        """(X_s, X_r), each (n_planets, n_dof): the change of :meth:`face_rows`' transverse-
        equivalent deflection per metre of a point's offset sigma along the line of action from
        the transverse pitch point, in the sense the contact travels (the sun's push on the
        planet for a sun mesh, the planet's on the ring for a ring mesh): a cell at (sigma, z)
        sees ``(V + z W + sigma X) q``. Only the normal's axial part gives it a moment arm
        (sin beta_b sigma about the axis normal to the plane of action): zero for a spur stage,
        and the u columns are those of the pitch point (the line of action is at r_b from the
        axis wherever the point sits on it). Source: the contact lines in the plane of action
        of Eritenel & Parker 2009 (their mesh force at the centre of stiffness on the line of
        action; docs/planetary.md, "The 3D lumped model")."""
        return tuple(x for _, x in _transverse_slopes(stage, (1.0, 0.0)))

    def spring_cos(self, stage):
        """cos beta_b: the stage's mesh stiffnesses act along the tooth normal."""
        return jnp.cos(stage.helix_angle)

    def spin_matrices(self, stage):
        """(G_v, K_v): the gyroscopic moments of each member's spin relative to the carrier,
        omega_r = s v (per unit mesh speed v: s = 0 for the carrier, 1 / r_bs for the sun,
        -1 / r_br for the ring and -1 / r_bp for each planet, the senses of the mesh travel):
        per member ``G_v = [[0, J s], [-J s, 0]]`` and ``K_v = J s I`` on the two tilts. With
        them the tilts of a member spinning at Omega + omega_r obey, in the frame turning at
        Omega, ``I_d psi'' + i (2 I_d Omega - J (Omega + omega_r)) psi' + (k - I_d Omega^2 +
        J (Omega + omega_r) Omega) psi = 0`` (psi = theta_x + i theta_y): the spinning disc's
        forward and backward whirl seen from the carrier (module docstring)."""
        spins = jnp.stack([jnp.zeros_like(stage.ring.base_radius), -1.0 / stage.ring.base_radius,
                           1.0 / stage.sun.base_radius]
                          + [-1.0 / stage.planet.base_radius] * stage.n_planets)
        j = _per_member(stage, lambda m: m.polar_inertia) * spins
        return _blocks(j, (3, 4), -j, (4, 3)), _blocks(j, (3, 3), j, (4, 4))

    def mesh_deflection_rows(self, stage):
        """(V_s, V_r), each (n_planets, n_dof): the mesh deflections at mid-face (m)."""
        v_s, v_r = self.mesh_rows_across(stage)
        return 0.5 * (v_s[:, 0] + v_s[:, 1]), 0.5 * (v_r[:, 0] + v_r[:, 1])

    @eqx.filter_jit
    def stiffness_matrix(self, stage):
        """K (N/m on translations and u; N m/rad on the tilts): bearings, pins and meshes."""
        diag = jnp.concatenate(
            [
                jnp.concatenate(
                    [
                        m.bearing_stiffness,
                        m.axial_stiffness[None],
                        m.tilt_stiffness,
                        m.torsional_u[None],
                    ]
                )
                for m in _members(stage)[:CENTRAL]
            ]
        )
        diag = jnp.concatenate([diag, jnp.zeros(DOF * stage.n_planets, dtype=diag.dtype)])
        diag = diag.at[DOF * CENTRAL + 5 :: DOF].set(stage.planet.torsional_u)
        pins = _pin_rows(stage)
        k = jnp.diag(diag) + jnp.einsum("nki,k,nkj->ij", pins, _pin_stiffness(stage), pins)
        v_s, v_r = self.mesh_rows_across(stage)
        k_s, k_r = stage.mesh_stiffnesses()
        k = k + 0.5 * jnp.einsum("nki,n,nkj->ij", v_s, k_s, v_s)
        return k + 0.5 * jnp.einsum("nki,n,nkj->ij", v_r, k_r, v_r)

    def gyroscopic_matrix(self, stage):
        """G: per member ``[[0, -2m], [2m, 0]]`` on the in-plane translations and
        ``[[0, -(2 I_d - J)], [2 I_d - J, 0]]`` on the tilts (module docstring)."""
        mass = _per_member(stage, lambda m: m.mass)
        g = _per_member(stage, lambda m: 2.0 * m.tilt_inertia - m.polar_inertia)
        return _blocks(-2.0 * mass, (0, 1), 2.0 * mass, (1, 0), -g, (3, 4), g, (4, 3))

    def centripetal_matrix(self, stage):
        """K_Omega: per member ``diag(m, m, 0, I_d - J, I_d - J, 0)`` (module docstring)."""
        zero = 0.0 * stage.planet.mass
        return jnp.diag(
            jnp.concatenate(
                [
                    jnp.stack(
                        [
                            m.mass,
                            m.mass,
                            zero,
                            m.tilt_inertia - m.polar_inertia,
                            m.tilt_inertia - m.polar_inertia,
                            zero,
                        ]
                    )
                    for m in _members(stage)
                ]
            )
        )

    def pin_error_terms(self, stage, tangential_errors, radial_errors):
        # the pin stands e further along eta (eps along zeta): its deflection is P q + e
        e = jnp.broadcast_to(as_float(tangential_errors), (stage.n_planets,))
        eps = jnp.broadcast_to(as_float(radial_errors), (stage.n_planets,))
        pins = _pin_rows(stage)
        k_pin = stage.planet.bearing_stiffness
        f = -k_pin[1] * (e @ pins[:, 1]) - k_pin[0] * (eps @ pins[:, 0])
        zero = jnp.zeros_like(e)
        return f, zero, zero
