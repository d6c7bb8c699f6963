"""Hybrid scene: condensed FE gear bodies coupled to the contact cells (seed II-2).

A gear member of the lumped 3D scene (:mod:`._lumped3d`) is either a rigid gear node (seed (2.9))
or a *flexible body* condensed by :mod:`fem_prep` on its rim master nodes (the outer rim face under
the teeth, r = root radius, one station per tooth), its bearing nodes and modal coordinates; the
interface of a cell with either is :mod:`._interface` (docs/hybrid.md, "The interface"). The
body's bearing master nodes are merged with the shaft nodes at the gear position plus their
axial offset; its rigid gear node and inertia go.

The body turns under the fixed mesh: its frame is at angle φ_rot = φ_0 ∓ θ_member from the
fixed frame, and the cells' coefficients c_k are rotated into it, so the stations under each
contact line follow the rotation. K, M and the centrifugal load are constant in the body frame.
The shaft that carries a body is taken in the same rotating frame (shafts and bearings are
axisymmetric: their stiffness does not change), so the structure is factored once.

Statics in the space of the cells (:func:`jaxgear.solve_contact_cells`): the structure is
factored once (the compliance G on the complement of the drive rotation, the output torque
rotation held), and a position only needs the compliance of the window of master DOFs under the
contact, C = V_W G_WW V_Wᵀ: an active-set pass costs cells², not masters³. That cache is
:mod:`._window_compliance`'s; placing the bodies on their shafts is :mod:`._bodies`'s; a
hybrid train is built from the train's one description (:meth:`HybridScene.train` of a
:class:`~jaxgear.scenes.TrainSpec`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._baseplane import CellRow, Cells, MeshModel, mesh_positions
from .._cell_factor import solve_factored_cells
from .._contact import ContactLaw, solve_contact_cells
from .._geometry import GearPair
from ._bodies import (
    _body_bearing_z,
    _body_structure,
    _BodyPlace,
    _check_rim_widths,
    _common_offset,
    _drive_compliance,
    _gear_roles,
    _place_bodies,
    _shaft_bodies,
    _shaft_rotation,
)
from ._gear_mesh import line_of_action, mesh_line, only_mesh, pair_mesh
from ._interface import GearPlace, RigidMember, body_rims, flexible_member, rim_window
from ._housing import Housing
from ._lumped3d import _housed, _lumped_arrays, _train_arrays, train_meshes
from ._mount import check_housing_position
from ._shaft import Material, ShaftSpec
from ._structure import AssembledScene
from ._train import TrainSpec
from ._window_compliance import WindowCompliance, _flat, window_compliance

__all__ = [
    "HybridPair",
    "HybridScene",
    "cache_window_compliance",
    "fit_members",
    "fit_windows",
    "hybrid_pair",
    "hybrid_train",
]


class HybridScene(AssembledScene):
    """The lumped 3D scene with condensed FE bodies: a pair (H1: flexible wheel; H2: both
    flexible) or a gear train with flexible gears (a flexible idler meshing twice).

    Build with :func:`hybrid_pair` or, from a train's :class:`~jaxgear.scenes.TrainSpec`,
    :meth:`train`. Generalised coordinates: the shafts
    (6 per node), a flexible housing's if the bearings sit in one (``housing=``:
    docs/housing.md, "Hybrid scenes"), then each body's rim master and modal DOFs (its bearing
    nodes are shaft nodes). The scene speed Ω is the pinion's (a train's input's).

    Attributes:
        structure: the assembled shafts, bearings, rigid gear nodes and condensed bodies with
            their teeth lumped on the rim nodes (:class:`~jaxgear.scenes.Structure`, one stiffness
            part ``structure``). Its bearing damping acts on a flexible member's shaft in the
            body frame (the bearings there are axisymmetric, checked by :func:`hybrid_pair`; the
            rotating-frame term Ω C J of a fixed damper is neglected, as the seed neglects
            gyroscopic terms). Its rotating-frame matrices are those of the members whose frames
            turn (a flexible body and its shaft): the dynamics add Ω·gyroscopic·Ẋ (Coriolis, skew)
            and Ω²·spin_stiffness·X at pinion speed Ω.
        meshes: the gear meshes (:class:`~jaxgear.scenes.GearMesh`).
        members: the gear members (pinion, gear), each a
            :class:`~jaxgear.scenes.RigidMember` or a :class:`~jaxgear.scenes.FlexibleMember`.
        G: compliance on the complement of the free rotations with the output rotation held
            (n, n). N: the free rotations (n, r): a pair's drive rotation (the pinion chain),
            scaled to a unit base-plane approach (r = 1); a train's every shaft but the output
            (per unit base-plane advance of the input).
        member_shafts: static, each member's shaft (its bearings turn with a flexible body).
        periods: static, first-mesh periods after which every mesh's cells repeat
            (:meth:`scene_periods`; 1 for a pair or an idler train).
        compliance: the window compliance at a set of positions
            (:func:`cache_window_compliance`), or None: formed at each position.
        f_torque: load per unit pinion torque (n,) (:class:`AssembledScene`).
        x_torque, x_centrifugal: G f_torque,
            G f_centrifugal (the pinion speed Ω is an argument of the methods and solvers that
            load the scene, never a field of it). Each mesh's TE vector u is its
            :attr:`GearMesh.te` (at the gear positions of the shafts).
    """

    G: Float[Array, "n n"]
    N: Float[Array, "n r"]
    x_torque: Float[Array, " n"]
    x_centrifugal: Float[Array, " n"]
    member_shafts: tuple = eqx.field(static=True, default=(0, 1))
    periods: int = eqx.field(static=True, default=1)
    compliance: WindowCompliance | None = None
    rigid: Float[Array, "n 1"] | None = None
    #: its shafts' bearings sit in a housing (``hybrid_pair(..., housing=)``,
    #: :meth:`train`)
    takes_housing: ClassVar[bool] = True

    def rigid_modes(self) -> Float[Array, "n r"]:
        """The free drive rotation of the dynamics (n, 1) (every shaft and body turning at its
        ratio, the output's too: u·r = 0 for every mesh's TE vector u, K r = 0), :attr:`rigid`;
        (n, 0) for a scene built without it. The rows of corner cells beyond the theoretical
        path drop their part along it (:meth:`~jaxgear.scenes.AssembledScene._free_drive`)."""
        if self.rigid is None:
            return jnp.zeros((self.structure.K.shape[0], 0), self.structure.K.dtype)
        return self.rigid

    @classmethod
    def train(
        cls,
        spec: TrainSpec,
        *,
        tooth_mass: bool = True,
        housing: Housing | None = None,
        seats=None,
        housing_position=None,
    ) -> HybridScene:
        """A lumped 3D gear train (:class:`~jaxgear.scenes.LumpedTrain`) whose flexible gears are
        condensed FE bodies: a flexible idler meshes twice, its two contact zones on one rim, both
        through the interface of :mod:`._interface`; a body with two rims (a fem_prep
        ``[pinion_rim]``) carries the two gears of its shaft, each mesh on its gear's rim
        (docs/trains.md, "Flexible gears in a train", "A body carrying two gears").

        Each body is placed on its shaft as in :func:`hybrid_pair` (bearing masters merged with the
        shaft nodes at the body origin's position plus their axial positions; the origin is the
        mid-face of its wheel rim, rim 0, at that gear's position); its frame turns at the shaft's
        speed ratio and sense (the layout's), and a tooth centre of each of its gears sits on a
        station of that gear's rim (the gear's first mesh's phase). The statics run in the cell
        space with one free rotation per shaft but the output's, which is held
        (:class:`HybridScene`).

        Args:
            spec: the train (:class:`~jaxgear.scenes.TrainSpec`) with its ``pairs`` and
                ``bodies`` (its masses and inertias are ignored for a flexible gear). The gears of
                one shaft are all rigid or all on one body (the same object), on distinct rims,
                every rim one; the mesh models must leave out the foundation term of a flexible
                gear (as :func:`hybrid_pair`).
            tooth_mass: add the teeth's mass and centrifugal load on the rim masters.
            housing, seats: a flexible :class:`~jaxgear.scenes.Housing` and each bearing's
                seat (shaft after shaft), as :meth:`~jaxgear.scenes.LumpedTrain.of`'s, its
                coordinates after the shafts' (before the bodies'); a shaft carrying a
                flexible body meets its seats as in :func:`hybrid_pair`.
            housing_position: with ``housing``, t (3,) (m): the scene origin's place in the
                frame the housing is placed in, as :func:`~jaxgear.scenes.lumped_pair`'s;
                None: the housing placed in the scene's frame.

        Raises:
            ValueError (one line, lengths in mm): a shaft carrying a flexible gear and a rigid one or
                two bodies (the shaft turns with the body frame); a body's rims not matching its
                gears (count, rim taken twice), a gear position that is not where the body puts its
                rim, a rim width that is not the face width of the gear's meshes; what
                :func:`hybrid_pair` and
                :meth:`~jaxgear.scenes.LumpedTrain.of` refuse (``seats``,
                ``housing_position``).
        """
        return _hybrid_train(cls, spec, tooth_mass, housing, seats, housing_position)

    def with_window_compliance(self, theta) -> HybridScene:
        """The scene holding its :func:`window_compliance` at the scene angles ``theta`` (rad,
        (P,)) (:func:`cache_window_compliance`); itself when it holds them already."""
        theta = jnp.asarray(theta, self.structure.K.dtype)
        held = self.compliance
        if (
            held is not None
            and held.theta.shape == theta.shape
            and bool(jnp.all(held.theta == theta))
        ):
            return self
        bare = dataclasses.replace(self, compliance=None)
        return dataclasses.replace(self, compliance=window_compliance(bare, theta))

    def scene_periods(self) -> int:
        """:attr:`periods`."""
        return self.periods

    def external_load(self, torque, speed=0.0):
        """Generalised external forces (n,) at pinion torque T (N·m) and pinion speed Ω (rad/s):
        T f_torque + Ω² f_centrifugal (each body at its own speed, (2.37))."""
        return torque * self.f_torque + speed**2 * self.structure.f_centrifugal

    def points(self, cells: Cells):
        """Fixed-frame contact points M of the cells (m), shape (L, N, 3)."""
        return only_mesh(self.meshes).points(cells)

    def window(self, cells: Cells, pad: int = 0):
        """Window DOFs (w,) and structure vectors on them (L, N, w), masked cells zeroed;
        ``pad`` rim stations more on each side of a flexible member's window (corner cells
        beyond the path less their part along the free drive rotation:
        :meth:`~jaxgear.scenes.AssembledScene._free_drive`)."""
        mesh = only_mesh(self.meshes)
        idx, Vw = mesh.window(self.members, cells, pad)
        return idx, self._free_drive(mesh, idx, Vw, cells)

    def window_overflow(self, cells: Cells):
        """True if a cell on the flanks reaches a rim station beyond its member's window."""
        return only_mesh(self.meshes).window_overflow(self.members, cells)

    # -- the cell space -----------------------------------------------------------------------
    def cell_space(self, row: CellRow, torque, speed=0.0):
        """C = V_W G_WW V_Wᵀ, a0 = V_W x0_W, E = V_W N_W, b = Nᵀ F and x0 = G F on the window
        of ``row`` (:meth:`window_row`; the cells of all meshes), F the external load at pinion
        torque T (N·m) and speed Ω (rad/s)."""
        idx, Vw = row.idx, row.V
        Gw = self.G[idx[:, None], idx[None, :]]
        x0 = torque * self.x_torque + speed**2 * self.x_centrifugal
        C = Vw @ Gw @ Vw.T
        a0 = Vw @ x0[idx]
        E = Vw @ self.N[idx]
        b = self.N.T @ self.external_load(torque, speed)
        return C, a0, E, b, x0

    def static_contact(self, cells: tuple, delta0: tuple, torque, speed, law: ContactLaw):
        """The static contact of all meshes at one position in the space of the cells
        (:func:`jaxgear.solve_contact_cells` on :meth:`cell_space`, the centrifugal load at
        pinion speed ``speed``): (the contact solution, X (n,), u·X of each mesh (m),
        (meshes,)); the arguments are those of :meth:`jaxgear.scenes.Scene.static_contact`.
        With :attr:`compliance` the position's cached slice is read instead, and the exact law
        is solved on its factor (:mod:`jaxgear._cell_factor`); the smooth law starts its
        Newton iteration from that exact answer."""
        if self.compliance is None:
            r = self.window_row(cells, delta0)
            C, a0, E, b, x0 = self.cell_space(r, torque, speed)
            sol, force, alpha = solve_contact_cells(
                C, a0 - r.delta0, E, b, r.k, r.length, r.mask, law
            )
            return sol, self.recover(r, x0, force, alpha), self.te_recover(r, x0, force, alpha)
        cs = self._position_slice(cells)
        r = CellRow(
            cs.idx,
            cs.V,
            *(_flat(x) for x in ([c.stiffness for c in cells], [c.length for c in cells])),
            _flat(delta0),
            cs.mask,
        )
        x0 = torque * self.x_torque + speed**2 * self.x_centrifugal
        a = torque * cs.a_torque + speed**2 * cs.a_centrifugal - r.delta0
        b = self.N.T @ self.external_load(torque, speed)

        def factored_exact(a, b):
            return solve_factored_cells(cs, a, b, r.k, law.max_iterations)

        def newton(start):
            return solve_contact_cells(cs.C, a, cs.E, b, r.k, r.length, r.mask, law, start)

        sol, force, alpha = law.factored_cells_answer(factored_exact, newton, a, b)
        u = self.te_vectors()
        te = u @ x0 - cs.te_rows @ force + (u @ self.N) @ alpha
        return sol, self.recover(r, x0, force, alpha), te

    def map_positions(self, fn, theta):
        """``fn(scene, θ)`` vmapped over the positions θ (P,); with :attr:`compliance` at P
        positions, each call gets the scene holding its position's slice (no gather)."""
        cache = self.compliance
        if cache is None or cache.theta.shape != theta.shape:
            return super().map_positions(fn, theta)

        def one(th, cs):
            return fn(dataclasses.replace(self, compliance=cs), th)

        return jax.vmap(one)(theta, cache)

    def _position_slice(self, cells: tuple) -> WindowCompliance:
        """The slice of :attr:`compliance` at the cells' scene angle: the slice itself (checked)
        or the nearest cached position (gathered); an error if it is not within 1e-9 of a mesh
        period."""
        cache = self.compliance
        mesh = self.meshes[0]
        theta = (cells[0].theta - mesh.phase) / mesh.ratio
        tol = 1e-9 * mesh.base_plane.mesh_period_angle / mesh.ratio
        msg = (
            "HybridScene.compliance: the position is not one of the cached positions (cache "
            "the positions the solve takes: cache_window_compliance(scene, theta))"
        )
        if cache.theta.ndim == 0:
            # the check rides on k l, which every solve reads
            return dataclasses.replace(
                cache, kl=eqx.error_if(cache.kl, jnp.abs(cache.theta - theta) > tol, msg)
            )
        i = jnp.argmin(jnp.abs(cache.theta - theta))
        i = eqx.error_if(i, jnp.abs(cache.theta[i] - theta) > tol, msg)
        return jax.tree_util.tree_map(lambda x: x[i], cache)

    def bearing_forces_fixed_frame(self, theta, F):
        """The bearing force components R X (N), shape (P, r), at pinion angles θ (P,) in the
        fixed frame: a flexible member's shaft turns with its body, so the in-plane pair of a
        bearing on it (taken in the turning body frame) is rotated back by the body frame
        angle; the others are unchanged."""
        names = self.reaction_names
        turned = set()  # a body carrying two gears turns its shaft once
        for m, member in enumerate(self.members):
            if not member.turns_frame or self.member_shafts[m] in turned:
                continue
            turned.add(self.member_shafts[m])
            ang = member.frame_angle(theta)
            for i, name in enumerate(names):
                if self.structure.reaction_member[i] != self.member_shafts[m] or not name.endswith(
                    "Fx"
                ):
                    continue
                j = names.index(name[:-1] + "y") if name[:-1] + "y" in names else None
                if j is None:
                    continue
                fx, fy = F[:, i], F[:, j]
                c, s_ = jnp.cos(ang), jnp.sin(ang)
                F = F.at[:, i].set(c * fx - s_ * fy).at[:, j].set(s_ * fx + c * fy)
        return F

    def rim_radial_growth(self, speed):
        """Mean radial displacement (m) of each flexible member's rim master nodes under the
        centrifugal load alone at pinion speed ``speed`` (rad/s); 0 for a rigid member.
        Returns a tuple, one per member."""
        x = speed**2 * self.x_centrifugal
        return tuple(member.rim_radial_growth(x) for member in self.members)

    def recover(self, row: CellRow, x0, P, alpha):
        """X = G (F − V_Wᵀ P) + N α from the cell forces P (c,) on the window of ``row`` and the
        rigid amplitudes α (x0 = G F)."""
        z = jnp.zeros_like(x0).at[row.idx].add(row.V.T @ P)
        return x0 - self.G @ z + self.N @ alpha

    def te_recover(self, row: CellRow, x0, P, alpha):
        """u·X (m) of each mesh, (meshes,), without recovering X:
        u·x0 − (G u)_W·(V_Wᵀ P) + (u·N) α."""
        u = self.te_vectors()
        # (G u)ᵀ from the scene alone (G symmetric): under a vmap over positions it is not
        # batched, so it is formed once per call; only its window is gathered per position
        Gu = u @ self.G
        return u @ x0 - Gu[:, row.idx] @ (row.V.T @ P) + (u @ self.N) @ alpha


# ------------------------------------------------------------------------------------------
# builders (NumPy, once per scene)


def _hybrid_train(cls, spec: TrainSpec, tooth_mass: bool, housing=None, seats=None,
                  position=None) -> HybridScene:
    """:meth:`HybridScene.train`."""
    check_housing_position(housing, position, "HybridScene.train")
    bodies, layout, on = spec.gear_bodies, spec.layout, spec.shaft_gears
    shaft_body, bodies_z = _shaft_bodies(spec)
    masses = [None if b is not None else m for b, m in zip(bodies, spec.masses, strict=True)]
    t = _train_arrays(spec, masses, tuple(map(tuple, bodies_z)))
    n0 = t["d"]["M"].shape[0]
    role = _gear_roles(spec.meshes)
    frames = None
    if housing is not None:  # a turning shaft meets its seats at its frame's angle at θ = 0
        _check_rim_widths(spec)
        stand_in = {s_: _no_dofs(body) for s_, (body, _) in shaft_body.items()}
        built = _train_members(
            spec, train_meshes(spec.meshes, layout, t["first"], n0), t["first"], stand_in, role
        )
        frames = [0.0] * spec.n_shafts
        for g, body in enumerate(bodies):
            if body is not None:
                frames[spec.shaft_of[g]] = float(built[g].frame_angle(0.0))
    t["d"] = _housed(
        dict(t["d"], nodes=t["nodes"]),
        spec.shafts,
        [layout.centres[on[i][0]] for i in range(spec.n_shafts)],
        [sh.gear_positions[0] for sh in spec.shafts],
        housing,
        seats,
        frames,
        position,
    )
    t["nodes"] = t["d"].pop("nodes")
    t["f_torque"] = np.concatenate([t["f_torque"], np.zeros(t["d"]["M"].shape[0] - n0)])
    d, first = t["d"], t["first"]
    n_sh = d["M"].shape[0]
    spin = np.asarray(layout.spins, float)
    ratio = np.asarray(layout.ratios, float)
    _check_rim_widths(spec)
    places, body_shafts = [], []
    for s_, (body, origin) in shaft_body.items():
        per_rim = [None] * len(body_rims(body))
        for g in on[s_]:
            k, member = role[g]
            per_rim[spec.gear_rims[g]] = (spec.pairs[k], member)
        g0 = on[s_][0]
        places.append(_BodyPlace(body, s_, origin, spin[g0] * ratio[g0], tuple(per_rim)))
        body_shafts.append(s_)
    placed = _place_bodies(d, places, spec.density if tooth_mass else None)
    n = placed["n"]
    gidx_of = dict(zip(body_shafts, placed["gidx"], strict=True))  # shaft -> body DOFs
    f_t = np.concatenate([t["f_torque"], np.zeros(n - n_sh)])
    rb0 = float(spec.meshes[0][0].base_radius_pinion)
    Nv = np.stack(
        [
            _shaft_rotation(
                d,
                i,
                n,
                shaft_body[i][0] if i in shaft_body else None,
                gidx_of.get(i),
            )
            / rb0
            for i in range(spec.n_shafts)
            if i != t["out"]
        ],
        axis=1,
    )
    G = _drive_compliance(placed["K"], Nv, dict(t["nodes"])["output"] + 5)
    out_meshes = train_meshes(spec.meshes, layout, first, n)
    members = _train_members(spec, out_meshes, first, gidx_of, role)
    return cls(
        structure=_body_structure(d, placed, t["nodes"]),
        meshes=out_meshes,
        members=fit_members(out_meshes, members),
        G=jnp.asarray(G),
        N=jnp.asarray(Nv),
        f_torque=jnp.asarray(f_t),
        x_torque=jnp.asarray(G @ f_t),
        x_centrifugal=jnp.asarray(G @ placed["fc"]),
        member_shafts=tuple(int(s_) for s_ in spec.shaft_of),
        periods=t["periods"],
        rigid=jnp.asarray(_free_rotation(
            [
                _shaft_rotation(
                    d, i, n, shaft_body[i][0] if i in shaft_body else None, gidx_of.get(i)
                )
                for i in range(spec.n_shafts)
            ],
            [np.asarray(m.te) for m in out_meshes],
        )),
    )


def _train_members(spec: TrainSpec, meshes: tuple, first, gidx_of: dict, role: dict) -> tuple:
    """Each gear's member of the hybrid train ``spec``: a rigid gear node at its first DOF
    ``first[g]``, or its condensed body's interface (:func:`flexible_member`, its body DOFs
    ``gidx_of[shaft]``) in the frame of its body, one frame angle for a body's gears
    (:func:`_common_offset`)."""
    layout, bodies = spec.layout, spec.gear_bodies
    members, made = [], {}  # made: each flexible gear's (arguments, place)
    for g, body in enumerate(bodies):
        centre = jnp.asarray(layout.centres[g])
        if body is None:
            members.append(RigidMember(centre, tuple(range(first[g], first[g] + 6))))
            continue
        k, member = role[g]
        zone = {key: np.asarray(v) for key, v in meshes[k].line().items()}
        window = max(  # the widest window of the meshes it is in
            rim_window(spec.pairs[j], 0 if g == a else 1)
            for j, (_, (a, b)) in enumerate(spec.meshes)
            if g in (a, b)
        )
        place = GearPlace(
            centre,
            spin=float(layout.spins[g]),
            ratio=float(layout.ratios[g]),
            mesh_angle=float(layout.phases[k]),
            rim=spec.gear_rims[g],
            n_window=window,
        )
        args = (spec.pairs[k], member, body, gidx_of[spec.shaft_of[g]], zone, spec.meshes[k][0])
        made[g] = (args, place)
        members.append(flexible_member(*args, place))
    for gears in spec.shaft_gears:  # a body carrying two gears has one frame
        flex = [g for g in gears if g in made]
        if len(flex) > 1:
            offset = _common_offset([members[g] for g in flex], [spec.gear_labels[g] for g in flex])
            for g in flex:
                args, place = made[g]
                members[g] = flexible_member(*args, place._replace(offset=offset))
    return tuple(members)


def hybrid_pair(
    pair: GearPair,
    mesh: MeshModel,
    pinion_shaft: ShaftSpec,
    gear_shaft: ShaftSpec,
    *,
    bodies: tuple,
    masses: tuple,
    inertias: tuple,
    material: Material = Material(),
    tooth_mass: bool = True,
    housing: Housing | None = None,
    seats=None,
    housing_position=None,
) -> HybridScene:
    """Assemble the hybrid scene: the lumped 3D scene with condensed bodies (H1, H2).

    Args:
        pair, mesh: the gear pair and its mesh model (its stiffness table must leave out the
            foundation term of a flexible member: the FE rim replaces it, seed after (2.31)).
        pinion_shaft, gear_shaft: the shafts (:class:`ShaftSpec`).
        bodies: (pinion, gear): ``None`` (rigid gear node) or a condensed body
            (:class:`fem_prep.CondensedBody`: SI, body frame: axis z, z = 0 at mid-rim, rim
            station k at angle 2πk/Z). Each bearing node of a body is merged with the shaft
            node at ``gear_z`` + its axial position.
        masses, inertias: rigid gear bodies (as :func:`lumped_pair`); ignored for a flexible one.
        material: the shafts' :class:`~jaxgear.scenes.Material` (its density also for the
            teeth).
        tooth_mass: add the mass and centrifugal load of the teeth (not in the FE body, which
            ends at the root circle) on the rim master nodes [R].
        housing: a flexible :class:`~jaxgear.scenes.Housing` the bearings join the shafts to,
            as :func:`~jaxgear.scenes.lumped_pair`'s (its coordinates after the shafts', before
            the bodies'; the structure's nodes ``housing <seat>``; the same scene frame), or
            None: the bearings hold the shafts to the ground.
        seats: with ``housing``, each bearing's seat index (pinion's bearings, then the
            gear's), None for a bearing that stays on the ground; None: the nearest seat. A
            flexible member's shaft turns with its body frame, a seat does not: its bearings
            meet their seats at the body frame's angle at θ = 0 (:func:`couple_housing`'s
            ``frames``; docs/housing.md, "Hybrid scenes").
        housing_position: with ``housing``, t (3,) (m): the scene origin's place in the frame
            the housing is placed in, as :func:`~jaxgear.scenes.lumped_pair`'s (each bearing's
            joint at its scene point plus t, its nearest seat the one nearest that point);
            None: the housing placed in the scene's frame.

    Raises:
        ValueError: body/gear mismatch (teeth, root radius), a bearing node off the axis or
            outside its shaft, a structure with a rigid-body mode other than the drive rotation,
            a bearing stiffness or damping matrix on a flexible body's shaft that is not
            axisymmetric about z (that shaft turns with the body frame); what
            :func:`~jaxgear.scenes.lumped_pair` refuses of ``seats`` and ``housing_position``
            (the latter before any work).
    """
    check_housing_position(housing, housing_position, "hybrid_pair")
    shafts = (pinion_shaft, gear_shaft)
    where = ("scene.pinion_shaft", "scene.gear_shaft")
    for m, body in enumerate(bodies):
        if body is not None and len(body_rims(body)) > 1:
            raise ValueError(
                f"scene.{('pinion', 'gear')[m]}_body: the body has {len(body_rims(body))} rims "
                "(a [pinion_rim]): a body carrying two gears belongs in a train case "
                "([scene.bodies.<shaft>])"
            )
    extra = tuple(
        () if body is None else _body_bearing_z(body, shafts[m], where[m])
        for m, body in enumerate(bodies)
    )
    masses = tuple(None if b is not None else ms for b, ms in zip(bodies, masses, strict=True))
    d = _lumped_arrays(pair, pinion_shaft, gear_shaft, masses, inertias, *material, extra_z=extra)
    line = line_of_action(pair)
    zone = mesh_line(
        line["tangent_point"], line["direction"], line["normal"], line["roll_start"], mesh
    )
    zone = {k: np.asarray(v) for k, v in zone.items()}

    def member(m, gidx):
        body, centre = bodies[m], jnp.asarray(line["centres"][m])
        if body is None:
            g = d["gear_dofs"][m]
            return RigidMember(centre, tuple(range(g, g + 6)))
        return flexible_member(pair, m, body, gidx, zone, mesh, GearPlace(centre))

    if housing is not None:  # a turning shaft meets its seats at its frame's angle at θ = 0
        frames = [
            0.0 if body is None else float(member(m, _no_dofs(body)).frame_angle(0.0))
            for m, body in enumerate(bodies)
        ]
        d = _housed(
            d,
            shafts,
            line["centres"],
            (pinion_shaft.gear_positions[0], gear_shaft.gear_positions[0]),
            housing,
            seats,
            frames,
            housing_position,
        )
    ratio = pair.pinion.teeth / pair.gear.teeth
    placed = _place_bodies(
        d,
        [
            None if body is None else _BodyPlace(body, m, shafts[m].gear_z, w, ((pair, m),))
            for m, (body, w) in enumerate(zip(bodies, (1.0, -ratio), strict=True))
        ],
        material.density if tooth_mass else None,
    )
    n, gidxs = placed["n"], placed["gidx"]
    rb1, rb2 = pair.base_radii
    cb = math.cos(pair.base_helix_angle)
    g1, g2 = d["gear_dofs"]
    t_in, t_out = (dict(d["nodes"])[k] + 5 for k in ("input", "output"))
    f_t = np.zeros(n)
    f_t[t_in] += 1.0
    f_t[t_out] += rb2 / rb1
    te = np.zeros(n)
    te[g1 + 5], te[g2 + 5] = cb * rb1, cb * rb2
    # the drive rotation (pinion chain), scaled to a unit base-plane approach
    Nv = _shaft_rotation(d, 0, n, bodies[0], gidxs[0]) / rb1
    G = _drive_compliance(placed["K"], Nv[:, None], t_out)
    members = [member(m, gidxs[m]) for m in range(2)]
    meshes = (pair_mesh(mesh, line, te),)
    return HybridScene(
        structure=_body_structure(d, placed, d["nodes"]),
        meshes=meshes,
        members=fit_members(meshes, tuple(members)),
        G=jnp.asarray(G),
        N=jnp.asarray(Nv[:, None]),
        f_torque=jnp.asarray(f_t),
        x_torque=jnp.asarray(G @ f_t),
        x_centrifugal=jnp.asarray(G @ placed["fc"]),
        rigid=jnp.asarray(_free_rotation(
            [_shaft_rotation(d, m, n, bodies[m], gidxs[m]) for m in (0, 1)], [te]
        )),
    )


def _no_dofs(body) -> np.ndarray:
    """Stand-in global DOFs of a condensed body's DOFs (its own order), for a member built only
    to read its frame angle before the body is placed."""
    return np.arange(np.asarray(body.dof_map).shape[0])


def _free_rotation(rotations: list, te_rows: list) -> np.ndarray:
    """The scene's free drive rotation (n, 1): the combination of the shafts' rigid rotations
    ``rotations`` (each (n,), :func:`_shaft_rotation`) that moves no mesh's TE vector
    (``te_rows``, each (n,)): the null vector of their (meshes × shafts) products, scaled to a
    unit rotation of the first shaft."""
    Nr = np.stack(rotations, axis=1)
    A = np.stack(te_rows) @ Nr
    c = np.linalg.svd(A)[2][-1]
    return (Nr @ (c / c[0]))[:, None]


def hybrid_train(
    spec: TrainSpec,
    *,
    tooth_mass: bool = True,
    housing: Housing | None = None,
    seats=None,
    housing_position=None,
) -> HybridScene:
    """The hybrid scene of the train ``spec`` (with ``housing``: its shafts' bearings on the
    housing's seats, the scene origin at ``housing_position`` in the housing's frame):
    :meth:`HybridScene.train`.

    Raises:
        ValueError: what :meth:`HybridScene.train` refuses.
    """
    return HybridScene.train(spec, tooth_mass=tooth_mass, housing=housing, seats=seats,
                             housing_position=housing_position)


HybridPair = HybridScene  # the name of the pair's scene (a hybrid train is the same class)


@functools.singledispatch
def cache_window_compliance(scene, theta=None, *, positions_per_pitch: int = 64, periods: int = 1):
    """``scene`` holding its :func:`window_compliance` at the positions ``theta`` (rad, (P,);
    default the positions :func:`jaxgear.quasi_static` takes for ``positions_per_pitch`` and
    ``periods``), built once per scene and reused by every solve at those positions: a relief
    map, a torque sweep (:func:`jaxgear.harris_map`), an optimisation (``optimise``)
    (:meth:`HybridScene.with_window_compliance`).

    A solve then reads the windows and their compliance instead of forming them, and in exact
    contact it solves the first active-set pass as a product with the cached inverse of the full
    contact set and a later pass by a Schur complement (docs/hybrid.md, "Statics in the cell
    space"): the same result as the uncached scene (tested to 1e-12), the same gradients with
    respect to the modifications, the torque and the speed (none flows into the cache itself).
    A solve at another position raises (:class:`equinox.EquinoxRuntimeError`).

    Any other scene (and a :class:`jaxgear.MeshModel`), and a hybrid scene already cached at
    these positions, is returned as it is, so callers may apply it to whatever they are given
    (dispatch on the scene's type). Cost: one contact solve's linear algebra per position,
    once; memory P (2 c² + c w + (c + meshes + 4) c) floats (6 + 3 MiB for
    accessory-spur-flexible at 64 positions).
    """
    return scene


@cache_window_compliance.register(HybridScene)
def _(scene, theta=None, *, positions_per_pitch: int = 64, periods: int = 1):
    if theta is None:
        theta = mesh_positions(scene.base_planes[0], positions_per_pitch, periods)
    return scene.with_window_compliance(theta)


def fit_members(meshes: tuple, members: tuple, tries: int = 4) -> tuple:
    """``members`` with rim windows that hold the contact zones of ``meshes``: each condensed
    member's window (``n_window`` rim stations spanned by a contact zone and the root points)
    is checked over two periods of every mesh (96 positions each) and widened by one station
    (:meth:`~jaxgear.scenes.GearMember.widened`) while a cell reaches beyond it.
    :func:`hybrid_pair` and :meth:`HybridScene.train` build their members with it.

    Raises:
        ValueError: the zones do not fit after ``tries`` widenings.
    """
    for _ in range(tries):
        if not _windows_overflow(meshes, members):
            return members
        members = tuple(m.widened() for m in members)
    raise ValueError("hybrid scene: the contact zone does not fit a rim window (internal error)")


def fit_windows(scene: HybridScene, tries: int = 4) -> HybridScene:
    """``scene`` with rim windows that hold its contact zones (:func:`fit_members`): call it
    after changing a member by hand.

    Raises:
        ValueError: the zones do not fit after ``tries`` widenings.
    """
    return dataclasses.replace(scene, members=fit_members(scene.meshes, scene.members, tries))


def _windows_overflow(meshes: tuple, members: tuple, samples: int = 48) -> bool:
    """Whether a cell on the flanks of any mesh reaches beyond its member's window over two of
    that mesh's periods."""
    dtype = jnp.result_type(float)
    for mesh in meshes:
        plane = mesh.base_plane
        angles = (np.arange(2 * samples) + 0.5) * float(plane.mesh_period_angle) / samples
        over = _overflow_at(mesh, members, jnp.asarray(angles + float(mesh.phase), dtype))
        if bool(np.any(np.asarray(over))):
            return True
    return False


@eqx.filter_jit
def _overflow_at(mesh, members: tuple, angles):
    """Whether a flank cell of ``mesh`` reaches beyond its member's window at each angle (one
    compiled program per mesh layout, shared by every scene built with it)."""
    return jax.vmap(lambda a: mesh.window_overflow(members, mesh.base_plane.cells(a)))(angles)
