"""A planetary stage whose central members' supports about and along the stage axis are joined
to a condensed housing's seat instead of the ground (docs/planetary.md, "On a housing";
docs/housing.md, "Planetary stages").

:class:`HousedPlanetary` is a model kind: it takes another kind (torsional, planar or 3D) and a
:class:`~jaxgear.scenes.Housing`, and appends the housing's h coordinates (its seats' 6-DOF
masters and interior modal coordinates, fixed frame) after the stage's. Every matrix the
engines read is the base kind's, grown by h zero columns (meshes, pins, Coriolis and
centripetal terms act on the stage only), except

- M: the housing's M_h on its coordinates;
- K: the housing's K_h, and each joined support's spring taken off the ground and put between
  the member and its seat through the seat's rigid lever G
  (:meth:`~jaxgear.scenes.Housing.seat_spring`, the lumped scenes' coupling
  d = u − G q restricted to the joined rows).

Why only the axis. The stage's coordinates are taken in the frame turning with the carrier;
the seat stands still. A member's rotation about the stage axis (θ_z = u / r_b) and its motion
along it (z) are the same in both frames, so those springs join the seat with constant blocks.
An in-plane translation or tilt seen from the seat is R(Ωt) times its carrier-frame one: its
blocks would carry cos Ωt and sin Ωt, which the engines' constant structure matrices
(:func:`~jaxgear.planetary.planetary_dynamics`, :func:`~jaxgear.planetary.planetary_whine`)
cannot hold; they stay on their grounded springs. A stage whose carrier does not turn (a star
stage, Ω = 0) has its carrier frame fixed: there ``carrier_held=True`` joins every support of
the joined members (x, y, z, tilts, θ_z) and the dynamics must run at Ω = 0.

The stage axis is the scene's +z through ``centre`` (m, scene frame), the frame
:meth:`~jaxgear.scenes.Housing.of` places the housing in; the carrier frame's x axis is the
scene's x (at Ω = 0, or for the axis rows, which do not depend on it).

Source: Craig & Bampton, AIAA J. 6 (1968) for the condensed housing; the rigid seat lever is
the lumped scenes' (docs/housing.md, "The coupling").
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._util import check_instance, is_traced
from ..scenes import Housing, HousingMount
from ._stage import AbstractPlanetaryModel, PlanetaryStage

__all__ = ["HousedPlanetary", "check_carrier_speed"]

#: the central members' coordinate suffixes (their names in ``dof_names``)
_SUFFIX = {"carrier": "c", "ring": "r", "sun": "s"}
#: a member's 6-vector (u_x, u_y, u_z, θ_x, θ_y, θ_z) from its coordinates: name prefix per row
_NODE = ("x", "y", "z", "theta_x", "theta_y", "u")


def _pad(a, h: int, rows: bool = False):
    """``a`` (..., n) with h zero columns appended (and h zero rows where ``rows``)."""
    a = jnp.asarray(a)
    out = jnp.concatenate([a, jnp.zeros(a.shape[:-1] + (h,), a.dtype)], axis=-1)
    if rows:
        out = jnp.concatenate([out, jnp.zeros((h,) + out.shape[1:], a.dtype)], axis=0)
    return out


def _entries(value):
    """``seats`` as a tuple of tuples (hashable: a static field); anything else as given, for
    the check to name."""
    try:
        return tuple(tuple(e) if isinstance(e, (list, tuple)) else e for e in value)
    except TypeError:
        return value


def _point(value):
    try:
        return tuple(float(x) for x in value)
    except (TypeError, ValueError):
        return value


class HousedPlanetary(AbstractPlanetaryModel):
    """A planetary model kind on a condensed housing (module docstring): ``model``'s
    coordinates (n) then the housing's (h), the joined supports of ``seats``' members between
    the member and its seat.

    Attributes:
        model: the base kind (:class:`~jaxgear.planetary.TorsionalPlanetary`,
            :class:`~jaxgear.planetary.PlanarPlanetary`,
            :class:`~jaxgear.planetary.SpatialPlanetary`).
        housing: the :class:`~jaxgear.scenes.Housing` (placed in the stage's scene frame: the
            stage axis is +z through ``centre``).
        seats: static, ``((member, seat), ...)``: ``member`` "ring", "carrier" or "sun", ``seat``
            the housing's seat its supports join: its index (0 .. n_seats − 1) or its name
            (one of :attr:`~jaxgear.scenes.Housing.seat_names`; :meth:`seat_indices`).
        centre: static, the stage centre (m, scene frame), (3,).
        carrier_held: static, the stage's carrier does not turn (a star stage; the dynamics at
            Ω = 0): every support of the joined members joins its seat. False (default): only
            the torsional support (θ_z) and, in the 3D model, the axial one (z).

    Coordinates: ``model.dof_names`` then the housing's
    (:meth:`~jaxgear.scenes.Housing.coordinate_names`: ``"housing <seat> u_x" .. "housing
    <seat> phi_z"`` per seat and ``"housing mode <k>"`` per kept interior mode). The joined springs'
    reactions (:func:`~jaxgear.planetary.support_reactions`) are what the member puts on its
    seat: the ring's reaction torque k_θ (θ_r − θ_seat) about the axis.

    Raises:
        ValueError: a base kind or housing of another type, a member or seat out of range (a
            seat name the housing has not), a member twice, ``carrier_held`` not a bool (one
            line).
    """

    model: AbstractPlanetaryModel
    housing: Housing
    seats: tuple = eqx.field(static=True, default=(("ring", 0),), converter=_entries)
    centre: tuple = eqx.field(static=True, default=(0.0, 0.0, 0.0), converter=_point)
    carrier_held: bool = eqx.field(static=True, default=False)

    def __check_init__(self):
        where = "HousedPlanetary"
        check_instance("model", self.model, AbstractPlanetaryModel,
                       "a planetary model kind (TorsionalPlanetary, PlanarPlanetary, "
                       "SpatialPlanetary)", where)
        if isinstance(self.model, HousedPlanetary):
            raise ValueError(f"{where}: model = {self.model!r}, allowed an unhoused kind")
        check_instance("housing", self.housing, Housing, "a jaxgear.scenes.Housing", where)
        if not isinstance(self.carrier_held, bool):
            raise ValueError(f"{where}: carrier_held = {self.carrier_held!r}, allowed a bool")
        c = np.asarray(self.centre, dtype=float)
        if c.shape != (3,) or not np.all(np.isfinite(c)):
            raise ValueError(f"{where}: centre = {self.centre!r}, allowed 3 finite numbers (m)")
        members = []
        for entry in self.seats:
            if not (isinstance(entry, tuple) and len(entry) == 2):
                raise ValueError(f"{where}: seats entry {entry!r}, allowed (member, seat index)")
            member, seat = entry
            if member not in _SUFFIX or member in members:
                raise ValueError(
                    f"{where}: seats member {member!r}, allowed one each of 'ring', 'carrier', "
                    "'sun'"
                )
            members.append(member)
            if isinstance(seat, str):
                if seat not in self.housing.seat_names:
                    raise ValueError(
                        f"{where}: seat of {member} = {seat!r}, allowed a seat name of the "
                        f"housing ({', '.join(map(repr, self.housing.seat_names))}) or an index "
                        f"0 to {self.housing.n_seats - 1}"
                    )
            elif (isinstance(seat, bool) or not isinstance(seat, (int, np.integer))
                    or not 0 <= seat < self.housing.n_seats):
                raise ValueError(
                    f"{where}: seat of {member} = {seat!r}, allowed a seat index 0 to "
                    f"{self.housing.n_seats - 1} or a seat name of the housing"
                )

    def seat_indices(self) -> tuple:
        """``((member, seat index), ...)``: :attr:`seats` with each seat name replaced by its
        index in the housing's :attr:`~jaxgear.scenes.Housing.seat_names`."""
        mount = self.mount
        return tuple((j.member, mount.seat_index(k)) for k, j in enumerate(mount.joints))

    # -- the coupling ----------------------------------------------------------------------

    def _unjoined(self, stage: PlanetaryStage) -> PlanetaryStage:
        """The stage with the joined supports taken off the ground (set to 0)."""
        for member, _ in self.seats:
            m = getattr(stage, member)
            zero = jnp.zeros_like(m.torsional_stiffness)
            if self.carrier_held:
                m = eqx.tree_at(
                    lambda m: (m.bearing_stiffness, m.axial_stiffness, m.tilt_stiffness,
                               m.torsional_stiffness),
                    m, (jnp.zeros_like(m.bearing_stiffness), zero,
                        jnp.zeros_like(m.tilt_stiffness), zero))
            else:
                m = eqx.tree_at(lambda m: (m.axial_stiffness, m.torsional_stiffness), m,
                                (zero, zero))
            stage = eqx.tree_at(lambda s, member=member: getattr(s, member), stage, m)
        return stage

    def _joint(self, stage: PlanetaryStage, member: str, rows: tuple):
        """(T, K_b): T (6, n) the member's node (u_x, u_y, u_z, θ_x, θ_y, θ_z) from the base
        coordinates (θ_z = u / r_b), zero on rows the base kind has not or the joint does not
        take (``rows``, its mount joint's); K_b (6, 6) the member's support springs on those
        rows (N/m, N m/rad)."""
        m = getattr(stage, member)
        names = self.model.dof_names(stage)
        n = len(names)
        dtype = stage.planet_angles.dtype
        k_all = jnp.concatenate([m.bearing_stiffness, m.axial_stiffness[None], m.tilt_stiffness,
                                 m.torsional_stiffness[None]]).astype(dtype)
        T = jnp.zeros((6, n), dtype)
        keep = jnp.zeros(6, dtype)
        for row in rows:
            name = f"{_NODE[row]}_{_SUFFIX[member]}"
            if name not in names:
                continue
            scale = 1.0 / m.base_radius if row == 5 else 1.0
            T = T.at[row, names.index(name)].set(scale)
            keep = keep.at[row].set(1.0)
        return T, jnp.diag(k_all * keep)

    @property
    def mount(self) -> HousingMount:
        """The :class:`~jaxgear.scenes.HousingMount` of its joints: each of ``seats``' members
        at ``centre`` on its seat, taking the axis rows (u_z, θ_z) or, with
        ``carrier_held``, all six."""
        return HousingMount.on_axis(self.housing, self.seats, self.centre, self.carrier_held)

    def coupling(self, stage: PlanetaryStage):
        """K_c (n + h, n + h): the joined springs between the members and their seats, the
        mount's seat coupling (:meth:`~jaxgear.scenes.HousingMount.coupling`) of each joined
        member's node T q (:meth:`_joint`) and its support springs K_b on the joined rows:
        K_c = Σ [[Tᵀ A T, Tᵀ B], [Bᵀ T, D]], (A, B, D) the blocks of
        :meth:`~jaxgear.scenes.Housing.seat_spring` (the lumped scenes' seat coupling)."""
        mount = self.mount
        if not mount.joints:
            n = len(self.model.dof_names(stage)) + mount.size
            return jnp.zeros((n, n), stage.planet_angles.dtype)
        joints = [self._joint(stage, j.member, j.rows) for j in mount.joints]
        return mount.coupling([T for T, _ in joints], [k for _, k in joints])

    # -- the model kind --------------------------------------------------------------------

    @property
    def contact_solve(self) -> bool:
        return self.model.contact_solve

    @property
    def face_points(self) -> int:
        return self.model.face_points

    def reduction(self, stage):
        return _pad(self.model.reduction(stage), self.housing.size)

    def dof_names(self, stage):
        return tuple(self.model.dof_names(stage)) + self.housing.coordinate_names()

    def central_translations(self, stage):
        return self.model.central_translations(stage)

    def central_rotations(self, stage):
        return self.model.central_rotations(stage)

    def mode_types(self):
        return self.model.mode_types()

    def gyroscopic_matrix(self, stage):
        return _pad(self.model.gyroscopic_matrix(stage), self.housing.size, rows=True)

    def centripetal_matrix(self, stage):
        return _pad(self.model.centripetal_matrix(stage), self.housing.size, rows=True)

    def spin_matrices(self, stage):
        return tuple(_pad(a, self.housing.size, rows=True)
                     for a in self.model.spin_matrices(stage))

    def pin_error_terms(self, stage, tangential_errors, radial_errors):
        f, d_s, d_r = self.model.pin_error_terms(stage, tangential_errors, radial_errors)
        return _pad(f, self.housing.size), d_s, d_r

    def error_terms(self, stage, tangential_errors, radial_errors, travel=0.0):
        f, d_s, d_r = self.model.error_terms(stage, tangential_errors, radial_errors, travel)
        return _pad(f, self.housing.size), d_s, d_r

    def mass_matrix(self, stage):
        m = _pad(self.model.mass_matrix(stage), self.housing.size, rows=True)
        n = m.shape[0] - self.housing.size
        return m.at[n:, n:].set(jnp.asarray(self.housing.M, m.dtype))

    def stiffness_matrix(self, stage):
        k = _pad(self.model.stiffness_matrix(self._unjoined(stage)), self.housing.size, rows=True)
        n = k.shape[0] - self.housing.size
        return k.at[n:, n:].add(jnp.asarray(self.housing.K, k.dtype)) + self.coupling(stage)

    def mesh_deflection_rows(self, stage):
        return tuple(_pad(v, self.housing.size) for v in self.model.mesh_deflection_rows(stage))

    def face_rows(self, stage):
        return tuple(tuple(_pad(v, self.housing.size) for v in mesh)
                     for mesh in self.model.face_rows(stage))

    def corner_rows(self, stage):
        return tuple(tuple(_pad(v, self.housing.size) for v in mesh)
                     for mesh in self.model.corner_rows(stage))

    def line_rows(self, stage):
        return tuple(_pad(v, self.housing.size) for v in self.model.line_rows(stage))

    def spring_cos(self, stage):
        return self.model.spring_cos(stage)


def check_carrier_speed(model, carrier_speed, where: str) -> None:
    """Refuse (one line) a turning carrier (``carrier_speed`` (rad/s) != 0, where concrete; a
    traced speed passes) for a :class:`HousedPlanetary` with ``carrier_held``: its in-plane
    supports join a seat fixed in space, which the turning carrier frame would see through
    cos Ωt and sin Ωt blocks; any other model kind passes."""
    if not (isinstance(model, HousedPlanetary) and model.carrier_held):
        return
    if carrier_speed is None or is_traced(carrier_speed):
        return
    speed = np.asarray(carrier_speed, dtype=float)
    if np.any(speed != 0.0):
        raise ValueError(
            f"{where}: carrier speed = {speed.tolist()!r} rad/s with HousedPlanetary("
            "carrier_held=True), allowed 0 (a star stage): its in-plane supports join a seat "
            "fixed in space, and a turning carrier frame would join them through blocks "
            "carrying cos Ωt and sin Ωt, which the constant structure matrices cannot hold"
        )
