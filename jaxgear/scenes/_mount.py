"""A housing mount: a condensed :class:`~jaxgear.scenes.Housing` and the joints that seat a
structure's or a model's nodes on it (docs/housing.md, "The coupling"; docs/architecture.md,
"One housing part").

A joint holds one node of its host (a shaft node under a bearing, a planetary stage's central
member): a 6-vector u = T x (u_x, u_y, u_z (m), θ_x, θ_y, θ_z (rad)) of the host's
coordinates x, in a frame turned by φ (the joint's ``frame``, rad) about +z from the scene
frame, at the point p (m, scene frame). Its spring K_b acts on the relative displacement

    d = u − G' q,   G' = Q(φ)ᵀ G,   G = [[R, −S(p − c) R], [0, R]]

(q the seat's six coordinates, c its centre, R the housing's rotation; p and c in the frame
the housing is placed in, a gearbox's where several hosts share it:
:meth:`~jaxgear.scenes.Housing.seat_transform`), restricted to the rows the joint takes
(P K_b P, P = diag of the joined rows: all six on a fixed frame; about and along the axis,
u_z and θ_z, for a frame that turns about it). Its energy ½ dᵀ P K_b P d is, on (x, q),

    ½ [x; q]ᵀ [[Tᵀ A T, Tᵀ B], [Bᵀ T, D]] [x; q],  (A, B, D) = (K', −K' G', G'ᵀ K' G'),

K' = P K_b P (:meth:`HousingMount.blocks`). :meth:`HousingMount.coupling` sums these blocks
over every joint, on the host's n coordinates followed by the housing's h: the one seat
coupling of the lumped and hybrid scenes (their bearings, the damping C_b taking the same
blocks) and of the planetary stages on a housing (their central members' supports).

Source: Craig & Bampton, AIAA J. 6 (1968) for the condensed housing; the seat lever is the
rigid-link (RBE2) relation of the condensed bodies' bearing masters
(:func:`fem_prep.couple_masters`).
"""

from __future__ import annotations

import dataclasses
import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._util import check_instance
from ._housing import Housing

__all__ = ["ALL_ROWS", "AXIS_ROWS", "HousingMount", "MountJoint", "check_housing_position",
           "couple_housing", "housing_nodes"]

#: the rows of a node's 6-vector (u_x, u_y, u_z, θ_x, θ_y, θ_z) a joint takes on a frame that
#: turns about the axis: along it (u_z) and about it (θ_z), the same in the turning and the
#: fixed frame
AXIS_ROWS = (2, 5)
#: every row: a joint in a fixed frame
ALL_ROWS = (0, 1, 2, 3, 4, 5)


def _point(value):
    try:
        return tuple(float(x) for x in value)
    except (TypeError, ValueError):
        return value


def _rows(value):
    try:
        return tuple(value)
    except TypeError:
        return value


@dataclasses.dataclass(frozen=True)
class MountJoint:
    """One node of a host seated on a housing seat (module docstring).

    Attributes:
        member: the host's name of the node (a bearing's ``"<shaft> bearing <k>"``, a
            planetary member's ``"ring"``, ``"carrier"``, ``"sun"``).
        seat: the seat it joins: its index (0 .. n_seats − 1) or its name (one of the
            housing's :attr:`~jaxgear.scenes.Housing.seat_names`).
        point: p (m), (3,): where the node sits, in the frame the mount's housing is placed
            in: the host's scene frame, or a frame several hosts share (a gearbox's, the
            host's axes parallel to it), where it is the host's own point plus t, the host
            origin's place in that frame.
        rows: the rows of the node's 6-vector the joint takes, ascending indices 0 .. 5
            (:data:`ALL_ROWS`: a fixed frame; :data:`AXIS_ROWS`: a frame turning about +z).
        frame: φ (rad), the angle about +z of the frame the node's coordinates are taken in
            (0: the scene frame).
        own_seat: whether the seat is this node's alone (a planetary member bolted to it:
            :meth:`HousingMount.on_axis`), so that a gearbox whose stages share the housing
            refuses another stage's joint on it; False: a bearing in a bore, which other
            bearings may share.

    Raises:
        ValueError: a point not 3 finite numbers, rows not distinct indices 0 .. 5 in
            ascending order, a frame not finite (one line).
        TypeError: ``own_seat`` not a bool (one line).
    """

    member: str
    seat: int | str
    point: tuple = (0.0, 0.0, 0.0)
    rows: tuple = ALL_ROWS
    frame: float = 0.0
    own_seat: bool = False

    def __post_init__(self):
        object.__setattr__(self, "point", _point(self.point))
        object.__setattr__(self, "rows", _rows(self.rows))
        p = self.point
        if not (isinstance(p, tuple) and len(p) == 3 and all(math.isfinite(x) for x in p)):
            raise ValueError(f"MountJoint {self.member!r}: point = {p!r}, allowed 3 finite "
                             "numbers (m, scene frame)")
        r = self.rows
        if not (isinstance(r, tuple) and r and all(
                isinstance(k, (int, np.integer)) and not isinstance(k, bool) for k in r)
                and list(r) == sorted(set(r)) and 0 <= r[0] and r[-1] <= 5):
            raise ValueError(f"MountJoint {self.member!r}: rows = {r!r}, allowed distinct "
                             "ascending indices 0 to 5 (u_x, u_y, u_z, theta_x, theta_y, "
                             "theta_z)")
        if (isinstance(self.frame, bool) or not isinstance(self.frame, (int, float))
                or not math.isfinite(self.frame)):
            raise ValueError(f"MountJoint {self.member!r}: frame = {self.frame!r}, allowed a "
                             "finite angle (rad)")
        if not isinstance(self.own_seat, bool):
            raise TypeError(f"MountJoint {self.member!r}: own_seat = {self.own_seat!r}, "
                             "allowed True or False")


def _xp(*arrays):
    """NumPy where every array is a NumPy array (a scene's host-side assembly), else jax.numpy
    (a model's matrices, possibly traced)."""
    return np if all(isinstance(a, np.ndarray) for a in arrays) else jnp


class HousingMount(eqx.Module):
    """A condensed housing and the joints that seat a host's nodes on it (module docstring):
    the one structure part through which a scene, a planetary stage and a gearbox take a
    housing.

    Attributes:
        housing: the :class:`~jaxgear.scenes.Housing`, placed in the frame of the joints'
            points (the host's scene frame, or a frame the hosts of one housing share: a
            gearbox's, whose stages' mounts hold this one object).
        joints: static, the :class:`MountJoint` s, in the host's order.

    The housing's h coordinates (:meth:`coordinate_names`) follow the host's n; its
    stiffness, mass and damping (:attr:`K`, :attr:`M`, :attr:`C`, (h, h)) act on them once.

    Raises:
        ValueError: a housing of another type, a joint not a :class:`MountJoint`, a seat
            out of range or a seat name the housing has not, one member joined twice (one
            line).
    """

    housing: Housing
    joints: tuple = eqx.field(static=True, default=())

    def __check_init__(self):
        check_instance("housing", self.housing, Housing, "a jaxgear.scenes.Housing",
                       "HousingMount")
        seen = set()
        n = self.housing.n_seats
        for k, j in enumerate(self.joints):
            check_instance(f"joints[{k}]", j, MountJoint, "a jaxgear.scenes.MountJoint",
                           "HousingMount")
            if j.member in seen:
                raise ValueError(f"HousingMount: joints[{k}] member {j.member!r} is joined "
                                 "twice, allowed one joint per member")
            seen.add(j.member)
            s = j.seat
            if isinstance(s, str):
                if s not in self.housing.seat_names:
                    raise ValueError(
                        f"HousingMount: seat of {j.member} = {s!r}, allowed a seat name of "
                        f"the housing ({', '.join(map(repr, self.housing.seat_names))}) or an "
                        f"index 0 to {n - 1}")
            elif (isinstance(s, bool) or not isinstance(s, (int, np.integer))
                    or not 0 <= s < n):
                raise ValueError(f"HousingMount: seat of {j.member} = {s!r}, allowed a seat "
                                 f"index 0 to {n - 1} or a seat name of the housing")

    @classmethod
    def on_axis(cls, housing: Housing, seats, centre=(0.0, 0.0, 0.0),
                fixed_frame: bool = False) -> HousingMount:
        """The mount of members on a stage axis (+z through ``centre``, m, in the frame the
        housing is placed in: the stage's own frame, where its centre is the origin, or a
        gearbox's, where it is the stage's place t):
        ``seats`` ``((member, seat), ...)`` (a seat's index or name), each member's node at
        ``centre``, joining the axis rows (u_z, θ_z: a frame turning about the axis, a
        planetary stage's carrier frame) or, with ``fixed_frame``, all six; each member bolted
        to its seat, the seat its own (:attr:`MountJoint.own_seat`).

        Raises:
            ValueError: what :class:`MountJoint` and the mount refuse (one line)."""
        rows = ALL_ROWS if fixed_frame else AXIS_ROWS
        return cls(housing, tuple(MountJoint(member, seat, centre, rows, own_seat=True)
                                  for member, seat in seats))

    # -- the housing, once -------------------------------------------------------------

    @property
    def size(self) -> int:
        """h, the housing's coordinates."""
        return self.housing.size

    @property
    def K(self):
        """K_h (h, h): the housing's condensed stiffness."""
        return self.housing.K

    @property
    def M(self):
        """M_h (h, h): the housing's condensed mass."""
        return self.housing.M

    @property
    def C(self):
        """C_h (h, h): the housing's damping."""
        return self.housing.C

    def coordinate_names(self) -> tuple[str, ...]:
        """The h names of the housing's coordinates
        (:meth:`~jaxgear.scenes.Housing.coordinate_names`)."""
        return self.housing.coordinate_names()

    def seat_index(self, k: int) -> int:
        """The seat index of joint ``k`` (a seat name resolved in the housing's
        :attr:`~jaxgear.scenes.Housing.seat_names`)."""
        s = self.joints[k].seat
        return self.housing.seat_names.index(s) if isinstance(s, str) else int(s)

    def seats(self) -> tuple[int, ...]:
        """The seats (indices) the joints use, ascending, each once."""
        return tuple(sorted({self.seat_index(k) for k in range(len(self.joints))}))

    def own_seats(self) -> tuple[tuple[str, int], ...]:
        """``((member, seat index), ...)`` of the joints whose seat is theirs alone
        (:attr:`MountJoint.own_seat`), in the joints' order."""
        return tuple((j.member, self.seat_index(k)) for k, j in enumerate(self.joints)
                     if j.own_seat)

    @property
    def fixed_frame(self) -> bool:
        """Whether every joint takes all six rows (its host's frame does not turn about the
        axis); False for a mount without joints."""
        return bool(self.joints) and all(j.rows == ALL_ROWS for j in self.joints)

    # -- the seat coupling ---------------------------------------------------------------

    def lever(self, k: int) -> np.ndarray:
        """G' (6, 6) of joint ``k``: its node's motion, in its frame, per unit coordinate of
        its seat (module docstring; :meth:`~jaxgear.scenes.Housing.seat_spring`'s G')."""
        j = self.joints[k]
        return self.housing.seat_spring(self.seat_index(k), j.point, np.zeros((6, 6)),
                                        j.frame)[3]

    def blocks(self, k: int, spring):
        """(A, B, D) (6, 6) each of joint ``k`` for the spring ``spring`` K_b (6, 6) (SI per
        coordinate pair; a NumPy or JAX array): (K', −K' G', G'ᵀ K' G'), K' = P K_b P on the
        joint's rows (module docstring)."""
        G = self.lever(k)
        rows = self.joints[k].rows
        xp = _xp(spring)
        a = xp.asarray(spring)
        if rows != ALL_ROWS:
            p = np.zeros(6)
            p[list(rows)] = 1.0
            a = (p[:, None] * a) * p[None, :]
        return a, -a @ G, G.T @ a @ G

    def coupling(self, nodes, springs, *, member: bool = True):
        """K_c (n + h, n + h): the joints' springs between their nodes and their seats, on the
        host's n coordinates then the housing's h:
        Σ_k [[T_kᵀ A_k T_k, T_kᵀ B_k S_k], [S_kᵀ B_kᵀ T_k, S_kᵀ D_k S_k]] (:meth:`blocks`;
        S_k (6, h) the seat's six coordinates).

        Args:
            nodes: per joint, T_k (6, n): its node's 6-vector from the host's coordinates.
            springs: per joint, K_b (6, 6) (a stiffness or a damping: the same blocks).
            member: False leaves the node's own block T_kᵀ A_k T_k out (a host that assembled
                the joint's spring on the ground already: the node's block is the same on the
                ground and on the seat).

        Returns a NumPy array where every input is one, else a JAX array.

        Raises:
            ValueError: not one node map and one spring per joint (one line).
        """
        if len(nodes) != len(self.joints) or len(springs) != len(self.joints):
            raise ValueError(f"HousingMount.coupling: {len(nodes)} node maps and "
                             f"{len(springs)} springs for {len(self.joints)} joints, allowed "
                             "one each")
        h = self.size
        xp = _xp(*nodes, *springs)
        n = nodes[0].shape[-1] if nodes else 0
        dtype = (xp.result_type(*nodes, *springs) if nodes else np.float64)
        top = xp.zeros((n, n), dtype)
        cross = xp.zeros((n, h), dtype)
        seat = xp.zeros((h, h), dtype)
        for k, (T, spring) in enumerate(zip(nodes, springs, strict=True)):
            A, B, D = self.blocks(k, spring)
            S = np.zeros((6, h))
            s = self.seat_index(k)
            S[:, 6 * s:6 * s + 6] = np.eye(6)
            if member:
                top = top + T.T @ A @ T
            cross = cross + T.T @ B @ S
            seat = seat + S.T @ D @ S
        return xp.block([[top, cross], [cross.T, seat]])


def check_housing_position(housing: Housing | None, position, where: str):
    """The one check of a scene builder's ``housing_position`` (:func:`couple_housing`'s
    ``position``; every kind that declares
    :attr:`~jaxgear.scenes.Scene.takes_housing` takes it with ``housing=`` and ``seats=``):
    t (3,) (m) as a NumPy array, or None for None (the housing placed in the scene's own
    frame, t = 0). ``where``: the builder's name, for the message.

    Raises:
        ValueError: a ``position`` without a ``housing``, or not 3 finite numbers (one line
            naming ``where``, the value and what is allowed).
    """
    if position is None:
        return None
    if housing is None:
        raise ValueError(f"{where}: housing_position = {position!r} without a housing, allowed "
                         "None (or give housing=)")
    try:
        t = np.asarray(position, dtype=float)
    except (TypeError, ValueError):
        t = np.full(1, np.nan)
    if t.shape != (3,) or not np.all(np.isfinite(t)):
        raise ValueError(f"{where}: housing_position = {position!r}, allowed 3 finite numbers "
                         "(m, the scene origin in the housing's frame)")
    return t


def couple_housing(
    d: dict, shafts, positions, housing: Housing | None, seats=None, frames=None,
    position=None,
) -> dict:
    """The shafts' NumPy parts (:func:`~jaxgear.scenes._shaft._shaft_arrays`) with ``housing``
    appended after the shaft coordinates and every bearing re-seated from the ground onto a
    seat (module docstring): M, the stiffness parts (a ``housing`` part appended; the
    ``bearings`` part holding the bearing couplings), the damping (n', n') and the bearing
    force rows, grown to n' = n + h. ``positions``: :func:`bearing_positions` (m, scene
    frame); ``seats``: the seat index of every bearing (shaft after shaft, as ``positions``;
    None: the nearest), an entry None leaving that bearing on the ground. ``housing`` None
    returns ``d`` unchanged.
    ``position``: t (3,) (m), the scene origin's place in the frame the housing is placed in
    (a gearbox frame that several scenes share, the scene axes parallel to it; None: the
    scene's own frame, t = 0): each bearing at p (scene frame) is the mount's joint at p + t
    and its nearest seat is the one nearest p + t. A seat's lever depends on p − c alone, so
    a housing placed in the scene's own frame (its seats at c − t) couples alike.
    ``frames``: per shaft, the angle φ (rad) about +z of the frame its coordinates are taken in
    (a hybrid scene's condensed body turns its shaft's frame, docs/housing.md, "Hybrid
    scenes"), or None: every shaft in the scene frame. A bearing of a shaft at φ acts on
    d = u_s − Q(φ)ᵀ G q (Q(φ) the rotation by φ about z on the translations and on the rotation
    vector): its relative motion in the shaft's frame, the bearing being axisymmetric there.

    Raises:
        ValueError: ``seats`` of another length than the bearings, a seat index out of range,
            what :func:`check_housing_position` refuses of ``position`` (one line).
    """
    t = check_housing_position(housing, position, "couple_housing")
    if housing is None:
        return d
    n = d["M"].shape[0]
    h = housing.size
    N = n + h
    flat = [
        (i, b, np.asarray(p) if t is None else np.asarray(p) + t)
        for i, s in enumerate(shafts)
        for b, p in zip(s.bearings, positions[i])
    ]
    if seats is None:
        seats = [housing.nearest_seat(p) for _, _, p in flat]
    seats = list(seats)
    if len(seats) != len(flat):
        raise ValueError(f"seats: {len(seats)} entries for {len(flat)} bearings, allowed one each")
    for k, s in enumerate(seats):
        if s is None:
            continue
        if (
            isinstance(s, bool)
            or not isinstance(s, (int, np.integer))
            or not 0 <= s < housing.n_seats
        ):
            raise ValueError(
                f"seats[{k}] = {s!r}, allowed a seat index 0 to {housing.n_seats - 1} "
                "(None: the ground)"
            )

    def grow(a):
        out = np.zeros(a.shape[:-2] + (N, N))
        out[..., :n, :n] = a
        return out

    offsets, mats = d["shaft_offsets"], d["mats"]
    joints, nodes, stiff, damp = [], [], [], []
    for k, ((i, b, p), s) in enumerate(zip(flat, seats, strict=True)):
        if s is None:  # None: the bearing stays on the ground
            continue
        node = int(np.argmin(np.abs(mats[i].nodes - b.z)))
        T = np.zeros((6, n))
        T[:, offsets[i] + 6 * node:offsets[i] + 6 * node + 6] = np.eye(6)
        phi = 0.0 if frames is None else float(frames[i] or 0.0)
        joints.append(MountJoint(f"bearing {k}", int(s), tuple(float(x) for x in p),
                                 frame=phi))
        nodes.append(T)
        stiff.append(np.asarray(b.stiffness_matrix(), float))
        damp.append(np.asarray(b.damping_matrix(), float))
    mount = HousingMount(housing, tuple(joints))
    M = grow(d["M"])
    M[n:, n:] = np.asarray(housing.M)
    parts = grow(d["parts"])
    housing_part = np.zeros((1, N, N))
    housing_part[0, n:, n:] = np.asarray(housing.K)
    parts = np.concatenate([parts, housing_part])
    C = grow(d["bearing_C"])
    C[n:, n:] += np.asarray(housing.C)
    if joints:  # the shaft node's own blocks are its grounded bearing's, there already
        parts[-2] += mount.coupling(nodes, stiff, member=False)
        C += mount.coupling(nodes, damp, member=False)
    reaction = np.zeros((d["reaction"].shape[0], N))
    reaction[:, :n] = d["reaction"]
    row, joint = 0, 0
    for (i, b, p), s in zip(flat, seats, strict=True):
        kb = b.stiffness_matrix()
        B = None if s is None else mount.blocks(joint, np.asarray(kb, float))[1]
        for k in range(3):  # the rows _shaft_arrays made, in its order: the bearing's K_b d
            if np.any(kb[k] != 0):
                if s is not None:
                    reaction[row, n + 6 * s : n + 6 * s + 6] = B[k]
                row += 1
        joint += s is not None
    return dict(d, M=M, parts=parts, bearing_C=C, reaction=reaction, housing_offset=n,
                mount=mount)


def housing_nodes(housing: Housing | None, offset: int) -> tuple:
    """The structure's named nodes of the housing's seats, ``("housing <seat>", first DOF)``
    (its modal coordinates follow the last seat's six): each seat's first coordinate's name
    (:meth:`Housing.coordinate_names`) without its DOF."""
    if housing is None:
        return ()
    names = housing.coordinate_names()
    return tuple((names[6 * k].rsplit(" ", 1)[0], offset + 6 * k)
                 for k in range(housing.n_seats))
