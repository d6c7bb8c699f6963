"""A gear-pair case in SI units: geometry, modifications, material, operating point, mesh model
settings, and optionally a dynamic scene and optimisation settings.

Cases are read from TOML files (units in key names) by :func:`jaxgear.io.load_case`, which
validates the whole file first; this module holds only the validated, SI-unit result.
"""

from __future__ import annotations

import dataclasses
import fractions
import math
from typing import Any, ClassVar

from .._baseplane import MeshModel
from .._contact import ContactLaw
from ._names import contact_law_from_name
from .._geometry import GearPair
from .._modifications import Modifications
from .._stiffness_models import FE2D, AbstractStiffness, stiffness_table
from ..scenes import (
    TrainSpec,
    Wrench,
    disc_inertia,
    grounded,
    hybrid_train,
    lumped_train,
    torsional_train,
    train_layout,
)

__all__ = ["Case", "MeshSettings", "TrainCase"]


@dataclasses.dataclass(frozen=True, kw_only=True)
class MeshSettings:
    """The material and mesh-model settings of a case, written once: a pair case
    (:class:`Case`) holds them for its mesh, a train case (:class:`TrainCase`) for every mesh
    (each mesh's pair case, :meth:`TrainCase.mesh_case`, takes the train's).

    Attributes:
        youngs_modulus: Young's modulus (Pa); ``poisson_ratio`` (-); ``density`` (kg/m³).
        stiffness: the mesh-stiffness model (:class:`~jaxgear.AbstractStiffness`:
            :class:`~jaxgear.Uniform`, :class:`~jaxgear.ISO6336`, :class:`~jaxgear.Weber`,
            :class:`~jaxgear.FE2D`, default ``FE2D()``; the case file's ``[mesh] stiffness``
            names it, :mod:`jaxgear.io` builds it).
        slices: slices per contact line; positions_per_pitch: positions per mesh period.
        smooth_width: smoothing width of the smooth contact law (m).
    """

    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.3
    density: float = 7800.0
    stiffness: AbstractStiffness = FE2D()
    slices: int = 40
    positions_per_pitch: int = 64
    smooth_width: float = 1e-7

    def mesh_settings(self) -> dict:
        """These settings as keywords (``{field: value}``), for another case that shares them."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(MeshSettings)}

    def contact_law(self, mode: str) -> ContactLaw:
        """The contact law a case file names: ``"exact"`` → :class:`~jaxgear.ExactContact`,
        ``"smooth"`` → :class:`~jaxgear.SmoothContact` of the case's ``smooth_width`` (m).

        Raises:
            ValueError: another name.
        """
        return contact_law_from_name(mode, self.smooth_width)

    @property
    def lumped(self) -> bool:
        """The scene is lumped 3D (``[scene] model = "lumped3d"``: shafts on bearings), as
        :attr:`TrainCase.lumped`."""
        return self.scene is not None and self.scene.lumped

    @property
    def stiffness_model(self) -> str:
        """The stiffness model's name (``"weber"``, ``"fe2d"``, ...), for summaries."""
        return self.stiffness.name

    def replace(self, **changes):
        """A copy with ``changes`` (field names as keywords)."""
        return dataclasses.replace(self, **changes)


@dataclasses.dataclass(frozen=True)
class Case(MeshSettings):
    """A validated gear-pair case (SI units).

    Attributes:
        name: case name. pair: :class:`~jaxgear.GearPair`.
        modifications: :class:`~jaxgear.Modifications`.
        torque: pinion torque (N·m). speed: pinion speed Ω (rad/s) of the quasi-static
            centrifugal load of condensed bodies (each body at its own speed); 0: at rest.
        youngs_modulus: with ``poisson_ratio``, ``density``, ``stiffness``, ``slices``,
            ``positions_per_pitch``, ``smooth_width``: the mesh settings
            (:class:`MeshSettings`; keywords only).
        scene: the validated ``[scene]`` table (:class:`jaxgear.io.SceneSpec`) or None.
        optimise: the validated ``[optimise]`` table (a dict in case-file units) or None.
        raw: the parsed TOML, as read (for reference; the fields above are what the code uses).
        deviations: manufacturing deviations per tooth (:class:`~jaxgear.Deviations`, ISO
            1328-1) or None; deviation_settings: the ``[deviations]`` run settings (grade, seed,
            revolutions, positions per pitch; docs/deviations.md) or None.
        coast: model the coast flanks with the pair's backlash (:meth:`mesh_model`; the case
            file sets it when a ``tooth_thickness_allowance_um`` is given; docs/backlash.md).
    """

    name: str
    pair: GearPair
    modifications: Modifications
    deviations: Any = None
    deviation_settings: dict | None = None
    torque: float = 100.0
    speed: float = 0.0
    scene: Any = None
    optimise: dict | None = None
    raw: dict = dataclasses.field(default_factory=dict, repr=False, compare=False)
    coast: bool = False

    # the views of a train (:class:`TrainCase`) on a pair: a pair is a train of two gears and
    # one mesh, named by the case, so that what reads a case's meshes reads both the same way

    gears: ClassVar[tuple] = ((0, 1),)
    shaft_of: ClassVar[tuple] = (0, 1)
    span_periods: ClassVar[int] = 1

    @property
    def gear_names(self) -> tuple:
        """("pinion", "gear")."""
        return ("pinion", "gear")

    @property
    def n_gears(self) -> int:
        return 2

    @property
    def pairs(self) -> tuple:
        """(pair,): its one mesh's :class:`~jaxgear.GearPair`."""
        return (self.pair,)

    def mesh_name(self, k: int) -> str:
        """Its one mesh's name: the case's."""
        return self.name

    def mesh_label(self, k: int) -> str:
        """"": a pair's one mesh needs no label in the outputs (:meth:`TrainCase.mesh_label`)."""
        return ""

    def mesh_case(self, k: int) -> Case:
        """Its one mesh as a pair case: itself."""
        return self

    @property
    def mesh_torques(self) -> tuple:
        """(torque,): the pinion torque (N·m)."""
        return (self.torque,)

    def mesh_modifications(self) -> tuple:
        """(modifications,)."""
        return (self.modifications,)

    def members(self) -> tuple:
        """(pinion, gear): each gear's :class:`~jaxgear.Member`."""
        return (self.pair.pinion, self.pair.gear)

    @property
    def normal_load(self) -> float:
        """Flank-normal mesh force F_n = T/(r_b1 cos β_b) (N)."""
        return self.torque / (self.pair.base_radii[0] * math.cos(self.pair.base_helix_angle))

    def nominal_line_load(self, torque: float | None = None) -> float:
        """Mean transverse load per unit face width, F_bt/(ε_α b) (N/m), for the Hertz term."""
        t = self.torque if torque is None else torque
        return (
            t
            / self.pair.base_radii[0]
            / (self.pair.transverse_contact_ratio * self.pair.face_width)
        )

    def specific_load(self, torque: float | None = None) -> float:
        """Nominal tangential load at the reference circle per unit face width, F_t / b =
        T / (r_1 b) (N/m), K_A = 1: the load of the ISO 6336-1 low-load factor (``iso6336``)."""
        t = self.torque if torque is None else torque
        return t / self.pair.pitch_radii[0] / self.pair.face_width

    def mesh_model(
        self,
        slices: int | None = None,
        torque: float | None = None,
        flexible: tuple[bool, bool] = (False, False),
    ) -> MeshModel:
        """Build the :class:`~jaxgear.MeshModel` (stiffness table evaluated at the nominal line
        load; the ``iso6336`` table at the case's E and :meth:`specific_load` of ``torque``).

        ``flexible``: members that are condensed FE bodies (pinion, gear): their tooth stiffness
        leaves out the foundation term, which the FE rim replaces (seed remark after (2.31)).
        With :attr:`coast` the model holds the coast flanks too (docs/backlash.md).
        """
        s, k = stiffness_table(
            self.pair,
            self.stiffness.without_body(flexible),
            youngs_modulus=self.youngs_modulus,
            poisson_ratio=self.poisson_ratio,
            line_load=self.nominal_line_load(torque),
            specific_load=self.specific_load(torque),
        )
        return MeshModel.from_pair(
            self.pair, s, k, self.slices if slices is None else slices, coast=self.coast
        )


@dataclasses.dataclass(frozen=True)
class TrainCase(MeshSettings):
    """A validated gear-train case (SI units): gears, the meshes between them and their layout,
    with the mesh settings, material and operating point of a pair case.

    Attributes:
        name: case name. gear_names: each gear's name, (n,), gear 0 the input.
        pairs: the :class:`~jaxgear.GearPair` of each mesh, (m,), its pinion the mesh's driving
            gear.
        gears: each mesh's (driving, driven) gear indices, listed from the input outwards.
        angles: each mesh's direction of the driven gear's centre seen from the driving one
            (rad, fixed frame).
        modifications: each gear's :class:`~jaxgear.MemberModification`, (n,) (every flank it
            loads).
        torque: the input gear's torque (N·m); the balancing output takes what the loads
            leave.
        loads: ((gear, torque (N·m)), ...): the torques of the loaded gears other than the
            balancing output, each in its gear's direction of motion (< 0: it takes power), at
            the case's input torque; the model keeps their shares of the input power
            (:meth:`shares`), so another input torque scales them all.
        speed: the input gear's speed (rad/s).
        youngs_modulus: with ``poisson_ratio``, ``density``, ``stiffness``, ``slices``,
            ``positions_per_pitch``, ``smooth_width``: the mesh settings
            (:class:`MeshSettings`; keywords only), every
            mesh's.
        inertias: each gear's polar inertia (kg·m²), (n,); None: a solid disc of its tip radius
            and face width.
        shafts: each gear's shaft (n,) (default: a shaft each, numbered in gear order): gears
            on one shaft turn together (a compound gear: the wheel of one stage and the pinion
            of the next), one rotation of the torsional train, shaft 0 the input's.
        clockings: each gear's tooth angle on its shaft less that of the shaft's first gear
            (rad, in the direction of motion; default 0).
        hands: each gear's given helix hand, +1 right, −1 left, 0 by default (n,)
            (:func:`jaxgear.scenes.train_hands`).
        masses: each gear body's mass (kg), (n,), the lumped 3D scene's; None: a solid disc of
            its tip radius and face width.
        wrenches: ((shaft, z (m), force (N) (3,), moment (N·m) (3,)), ...): forces and tilting
            moments on shaft nodes at the case's input torque (lumped 3D; fixed frame), scaled
            with the input torque as the loads are.
        shaft_names: each shaft's name (a gear's ``shaft`` in the case file; default the name of
            its first gear), (shafts,).
        scene: the validated ``[scene]`` (:class:`jaxgear.io.SceneSpec`: torsional, or
            lumped 3D with its ``shafts``) or None.
        raw: the parsed TOML, as read.
    """

    name: str
    gear_names: tuple
    pairs: tuple
    gears: tuple
    angles: tuple
    modifications: tuple
    torque: float = 100.0
    loads: tuple = ()
    speed: float = 0.0
    inertias: tuple = ()
    shafts: tuple = ()
    clockings: tuple = ()
    hands: tuple = ()
    masses: tuple = ()
    wrenches: tuple = ()
    shaft_names: tuple = ()
    scene: Any = None
    raw: dict = dataclasses.field(default_factory=dict, repr=False, compare=False)

    optimise = None  # a train case has no [optimise] table

    @property
    def n_gears(self) -> int:
        return len(self.gear_names)

    def mesh_name(self, k: int) -> str:
        """``"driving-driven"``, the names of mesh ``k``'s gears."""
        g, h = self.gears[k]
        return f"{self.gear_names[g]}-{self.gear_names[h]}"

    def mesh_label(self, k: int) -> str:
        """What tells mesh ``k`` apart in the outputs (file names, titles, per-mesh keys and
        warnings): its :meth:`mesh_name` (a pair case's one mesh has none, "")."""
        return self.mesh_name(k)

    @property
    def shaft_of(self) -> tuple:
        """Each gear's shaft index (n,): the rotation of the torsional train it turns with."""
        return tuple(self.shafts) if self.shafts else tuple(range(self.n_gears))

    @property
    def n_shafts(self) -> int:
        return max(self.shaft_of) + 1

    def shares(self) -> dict:
        """``{shaft: share}``: the share of the input power each loaded shaft takes, −T_j ω_j /
        (T ω_0) (:func:`jaxgear.scenes.torsional_train`); the balancing output takes the rest."""
        ratios = self.layout().ratios
        out = {}
        for g, t in self.loads:
            s = self.shaft_of[g]
            out[s] = out.get(s, 0.0) - t * ratios[g] / (self.torque * ratios[0])
        return out

    @property
    def span_periods(self) -> int:
        """Periods of the first mesh after which every mesh's cells repeat together (exact,
        from the tooth counts): 1 when every mesh passes teeth at the first's rate (an idler
        train); a two-stage train's span (:meth:`jaxgear.scenes.Scene.scene_periods`)."""
        shaft_ratio = {self.shaft_of[0]: fractions.Fraction(1)}
        q = 1
        z0 = self.pairs[0].pinion.teeth
        for pair, (g, h) in zip(self.pairs, self.gears, strict=True):
            rg = shaft_ratio[self.shaft_of[g]]
            shaft_ratio[self.shaft_of[h]] = rg * pair.pinion.teeth / pair.gear.teeth
            q = math.lcm(q, (z0 / (pair.pinion.teeth * rg)).numerator)
        return q

    @property
    def output(self) -> int:
        """The balancing output's shaft: the one shaft that drives no other and has no load."""
        drivers = {self.shaft_of[g] for g, _ in self.gears}
        shares = self.shares()
        free = [s for s in range(self.n_shafts) if s not in drivers and s not in shares]
        return free[0]

    @property
    def mesh_torques(self) -> tuple:
        """Each mesh's torque on its driving gear (N·m): the power the shafts beyond the mesh
        take (their shares; the balancing output the rest) over the driving gear's speed,
        T S_k ω_0 / ω_g (S_k: the shares of the driven gear's shaft and every shaft it drives,
        directly or not). In a chain with no load on its way the force is passed on: T_h =
        T_g r_b,h / r_b,g."""
        ratios = self.layout().ratios
        share = dict(self.shares())
        share[self.output] = 1.0 - sum(share.values())
        children = {}
        for g, h in self.gears:
            children.setdefault(self.shaft_of[g], []).append(self.shaft_of[h])

        def beyond(s):  # the share taken at shaft s and beyond it
            return share.get(s, 0.0) + sum(beyond(c) for c in children.get(s, ()))

        return tuple(
            self.torque * beyond(self.shaft_of[h]) * ratios[0] / ratios[g] for g, h in self.gears
        )

    def mesh_case(self, k: int) -> Case:
        """Mesh ``k`` as a pair case: its pair (the driving gear as pinion), its driving gear's
        torque (:attr:`mesh_torques`) and speed, and the train's mesh settings."""
        g, h = self.gears[k]
        pair = self.pairs[k]
        speed = self.speed * self.layout().ratios[g]
        return Case(
            name=f"{self.name}-{self.mesh_name(k)}",
            pair=pair,
            modifications=Modifications(self.modifications[g], self.modifications[h]),
            torque=self.mesh_torques[k],
            speed=speed,
            **self.mesh_settings(),
        )

    def mesh_modifications(self) -> tuple:
        """Each mesh's :class:`~jaxgear.Modifications` (its driving gear's, its driven gear's)."""
        return tuple(
            Modifications(self.modifications[g], self.modifications[h]) for g, h in self.gears
        )

    def layout(self):
        """The train laid out in the plane (:func:`jaxgear.scenes.train_layout`)."""
        return train_layout(
            self.pairs,
            self.gears,
            self.angles,
            self.n_gears,
            self.shaft_of,
            self.clockings or None,
            self.hands or None,
        )

    def members(self) -> tuple:
        """Each gear's :class:`~jaxgear.Member` (from the first mesh it takes part in)."""
        out = [None] * self.n_gears
        for pair, (g, h) in zip(self.pairs, self.gears, strict=True):
            out[g] = out[g] or pair.pinion
            out[h] = out[h] or pair.gear
        return tuple(out)

    def tip_radii(self) -> tuple:
        """Each gear's tip radius (m)."""
        out = [None] * self.n_gears
        for pair, (g, h) in zip(self.pairs, self.gears, strict=True):
            out[g] = out[g] or pair.tip_radii[0]
            out[h] = out[h] or pair.tip_radii[1]
        return tuple(out)

    def gear_inertias(self) -> tuple:
        """Each gear's polar inertia (kg·m²): the case's, or a solid disc of the tip radius and
        face width at the case's density."""
        members, radii = self.members(), self.tip_radii()
        return tuple(
            disc_inertia(self.density, radii[i], members[i].face_width) if j is None else j
            for i, j in enumerate(self.inertias or (None,) * self.n_gears)
        )

    def gear_masses(self) -> tuple:
        """Each gear body's mass (kg): the case's, or a solid disc ρ π r_a² b."""
        members, radii = self.members(), self.tip_radii()
        return tuple(
            self.density * math.pi * radii[i] ** 2 * members[i].face_width if m is None else m
            for i, m in enumerate(self.masses or (None,) * self.n_gears)
        )

    def mesh_models(self, slices: int | None = None, flexible: tuple = ()) -> tuple:
        """Each mesh's :class:`~jaxgear.MeshModel` (:meth:`Case.mesh_model` of :meth:`mesh_case`);
        ``flexible``: which gears are condensed FE bodies (their tooth stiffness leaves out the
        foundation term), (n,) (default none)."""
        flex = tuple(flexible) or (False,) * self.n_gears
        return tuple(
            self.mesh_case(k).mesh_model(slices, flexible=(flex[g], flex[h]))
            for k, (g, h) in enumerate(self.gears)
        )

    def torsional_train(self, slices: int | None = None):
        """The train's torsional scene (:func:`jaxgear.scenes.torsional_train`): one rotation
        per shaft (:attr:`shaft_of`) with the inertia of its gears (:meth:`gear_inertias`), each
        mesh at its layout's phase, the loads' :meth:`shares`."""
        planes = self.mesh_models(slices)
        inertias = [0.0] * self.n_shafts
        for g, j in enumerate(self.gear_inertias()):
            inertias[self.shaft_of[g]] += j
        links = tuple((self.shaft_of[g], self.shaft_of[h]) for g, h in self.gears)
        return torsional_train(
            tuple(zip(planes, links, strict=True)),
            inertias,
            tuple(float(p) for p in self.layout().phases),
            self.shares(),
        )

    @property
    def lumped(self) -> bool:
        """The scene is lumped 3D (``[scene] model = "lumped3d"``: shafts on bearings)."""
        return self.scene is not None and self.scene.lumped

    @property
    def flexible(self) -> bool:
        """The lumped 3D scene has condensed FE bodies (``[scene.bodies]``)."""
        return self.lumped and self.scene.hybrid

    def _lumped_args(self) -> dict:
        """The keyword arguments of :func:`~jaxgear.scenes.lumped_train` and
        :func:`~jaxgear.scenes.hybrid_train` from the case."""
        members = self.members()
        bodies = [
            (m, (j / 2 + m * members[i].face_width ** 2 / 12, j))
            for i, (m, j) in enumerate(zip(self.gear_masses(), self.gear_inertias(), strict=True))
        ]
        return dict(
            masses=[b[0] for b in bodies],
            inertias=[b[1] for b in bodies],
            shares=self.shares(),
            wrenches=tuple(
                Wrench(s, z, tuple(f / self.torque for f in F), tuple(m / self.torque for m in M))
                for s, z, F, M in self.wrenches
            ),
            shaft_names=self.shaft_names or None,
            youngs_modulus=self.youngs_modulus,
            poisson_ratio=self.poisson_ratio,
            density=self.density,
        )

    def lumped_train(self, slices: int | None = None):
        """The train's lumped 3D scene (:func:`jaxgear.scenes.lumped_train`): each shaft of
        ``[[scene.shafts]]`` on its bearings with its gears (rigid discs of
        :meth:`gear_masses` and :meth:`gear_inertias`, diametral inertia I_p/2 + m b²/12), each
        mesh on its line of action with the layout's hands and phase, the loads' shares and the
        wrenches per unit input torque.

        Raises:
            ValueError: the case has no lumped 3D scene.
        """
        if not self.lumped:
            raise ValueError("a lumped 3D train needs [scene] model = 'lumped3d'")
        return lumped_train(
            TrainSpec(
                tuple(zip(self.mesh_models(slices), self.gears, strict=True)),
                self.layout(),
                self.scene.shafts,
                self.shaft_of,
                **self._lumped_args(),
            )
        )

    def hybrid_train(self, bodies: tuple, slices: int | None = None, *, tooth_mass: bool = True):
        """The train's lumped 3D scene with its flexible gears as condensed FE bodies
        (:func:`jaxgear.scenes.hybrid_train`; ``[scene.bodies]``), the output held; its meshes'
        tooth stiffness leaves out a flexible gear's foundation term.

        Args:
            bodies: each gear's condensed body or ``None`` (rigid), (n,)
                (:func:`jaxgear.io.load_bodies` of the case's scene).
            tooth_mass: lump the teeth's mass on the rim masters (default).

        Raises:
            ValueError: the case has no lumped 3D scene, or what
                :func:`~jaxgear.scenes.hybrid_train` refuses.
        """
        if not self.lumped:
            raise ValueError("a hybrid train needs [scene] model = 'lumped3d'")
        flexible = tuple(b is not None for b in bodies)
        spec = TrainSpec(
            tuple(zip(self.mesh_models(slices, flexible), self.gears, strict=True)),
            self.layout(),
            self.scene.shafts,
            self.shaft_of,
            pairs=self.pairs,
            bodies=tuple(bodies),
            rims=self.scene.gear_rims or None,
            gear_names=self.gear_names,
            **self._lumped_args(),
        )
        return hybrid_train(spec, tooth_mass=tooth_mass)

    def dynamic_train(self, slices: int | None = None):
        """The train's rigid-gear scene: :meth:`lumped_train` for a lumped 3D scene, else
        :meth:`torsional_train` (a train with flexible gears: :meth:`hybrid_train`, which needs
        their bodies; :func:`jaxgear.io.build_dynamic_model` loads them).

        Raises:
            ValueError: a train with flexible gears.
        """
        if self.flexible:
            raise ValueError(
                "[scene.bodies]: a train with flexible gears is a hybrid scene: "
                "case.hybrid_train(bodies) or jaxgear.io.build_dynamic_model(case)"
            )
        return self.lumped_train(slices) if self.lumped else self.torsional_train(slices)

    def static_train(self, slices: int | None = None, bodies: tuple | None = None):
        """The scene of the train's quasi-static solve: :meth:`dynamic_train` with the output
        shaft's rotation held by a spring (the output torque's reaction; the meshes' TE and
        loads do not depend on it); with flexible gears, :meth:`hybrid_train` of ``bodies``
        (which holds the output itself).

        Raises:
            ValueError: flexible gears without their ``bodies``.
        """
        if self.flexible:
            if bodies is None:
                raise ValueError(
                    "static_train: the case has flexible gears ([scene.bodies]); pass their "
                    "condensed bodies (jaxgear.io.load_bodies(case.scene))"
                )
            return self.hybrid_train(bodies, slices)
        train = self.dynamic_train(slices)
        return grounded(train, (train.torque_dofs[1],), factor=1e9)
