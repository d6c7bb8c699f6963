"""A planetary stage as a case holds it (SI units): :class:`PlanetarySpec` (the validated
``[planetary]`` table, jaxgear/io/_planetary_table.py), the case's form :class:`PlanetaryForm`,
the lumped models' mesh stiffness by where it comes from (:class:`PlanetaryMeshStiffness`), and
the form of a train of one internal mesh (:class:`InternalMeshForm`).

Sign conventions: speeds and torques in the fixed frame, positive in the input's direction of
motion; the Willis relation z_s ω_s + z_r ω_r = (z_s + z_r) ω_c (z_r the ring's tooth count,
positive here) and the torques T_s : T_r : T_c = z_s : z_r : −(z_s + z_r) (lossless) are the
model's (:func:`jaxgear.planetary.central_speeds`, :func:`jaxgear.planetary.central_torques`).
"""

from __future__ import annotations

import abc
import dataclasses
import math

import numpy as np

from .._internal import PlanetaryGeometry
from ..planetary import (
    AbstractPlanetaryMeshes,
    Central,
    ConstantMeshes,
    ContactMeshes,
    Eccentricities,
    PlanetaryStage,
    Unbalances,
    central_speeds,
    central_torques,
    lumped_mesh_stiffness,
    speed_ratio,
)
from .._stiffness import iso6336_mesh_stiffness
from ._case import Case, CaseForm, PairForm, TrainForm
from ._planetary_ring_spec import RigidRingSpec, RingModelSpec

__all__ = [
    "HOLD_FACTOR",
    "GivenMeshStiffness",
    "ISO6336MeshStiffness",
    "InternalMeshForm",
    "MeanMeshStiffness",
    "PlanetaryForm",
    "PlanetaryMeshStiffness",
    "PlanetarySpec",
]

#: a stiffness that holds a member (N/m on u = r θ) relative to the stiffest mesh
HOLD_FACTOR = 1e3


# -- mesh stiffness of the lumped models: objects named by `mesh_stiffness` --------------------


class PlanetaryMeshStiffness(abc.ABC):
    """Where the lumped models' constant sun–planet and ring–planet mesh stiffnesses come from
    (``[planetary] mesh_stiffness`` names it; given values are :class:`GivenMeshStiffness`)."""

    @abc.abstractmethod
    def values(self, case: Case) -> tuple[float, float]:
        """(k_s, k_r) (N/m) on the line of action."""

    @abc.abstractmethod
    def summary(self) -> str:
        """What the summary says the stiffness is."""


@dataclasses.dataclass(frozen=True)
class GivenMeshStiffness(PlanetaryMeshStiffness):
    """Given in the case file (``sun_mesh_stiffness_N_per_um``,
    ``ring_mesh_stiffness_N_per_um``)."""

    sun: float
    ring: float

    def values(self, case):
        return self.sun, self.ring

    def summary(self):
        return "given"


@dataclasses.dataclass(frozen=True)
class ISO6336MeshStiffness(PlanetaryMeshStiffness):
    """ISO 6336-1 §9.3: c_γα b (c_γα = c' (0.75 ε_α + 0.25) at the case's Young's modulus; an
    internal pair with the standard's internal-gear rule)."""

    def values(self, case):
        return tuple(
            iso6336_mesh_stiffness(p, case.youngs_modulus) * p.face_width for p in case.pairs
        )

    def summary(self):
        return "iso6336 (ISO 6336-1 c_gamma_alpha b)"


@dataclasses.dataclass(frozen=True)
class MeanMeshStiffness(PlanetaryMeshStiffness):
    """The mean over a mesh period of the ``[mesh]`` stiffness model's quasi-static mesh
    stiffness, each mesh at its mean planet load (the rigid mesh, exact contact:
    :func:`jaxgear.planetary.lumped_mesh_stiffness`)."""

    def values(self, case):
        return tuple(
            lumped_mesh_stiffness(one.mesh_model(), one.modifications, one.torque)
            for one in (case.mesh_case(k) for k in range(len(case.pairs)))
        )

    def summary(self):
        return "mean of the [mesh] stiffness model"


# -- the stage as the file gives it --------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class PlanetarySpec:
    """A validated ``[planetary]`` table in SI units.

    Attributes:
        teeth: (z_s, z_p, z_r), the ring's positive (z_p None in the lumped form).
        planet_angles: ψ_n (rad), (N,), planet 1 first.
        fixed, input, output: the :class:`~jaxgear.planetary.Central` members.
        members: {"sun", "ring", "carrier", "planet": :class:`~jaxgear.planetary.PlanetaryMember`},
            the base radii of the gear form from the gears.
        pressure_angles: (α_s, α_r) operating transverse pressure angles (rad).
        mesh_stiffness: a :class:`PlanetaryMeshStiffness`.
        tangential_pin_errors, radial_pin_errors: per planet (m), (N,).
        center_distance: a_w (m), the planet-circle radius.
        ring_model: the ring's model (``[planetary.ring] model``,
            :class:`~jaxgear.io._planetary_ring_spec.RingModelSpec`); rigid by default.
        eccentricities: the sun's, ring's and carrier's eccentricities (m) and phases (rad),
            in the order of :class:`~jaxgear.planetary.Eccentricities`' fields; none by default.
        planet_runout: (runouts (m), phases (rad)), one per planet (or empty: none), the
            :class:`~jaxgear.planetary.Eccentricities`' ``planet`` and ``planet_phase``.
        unbalances: the sun's, ring's, carrier's and planets' mass unbalances (kg m) and
            phases (rad), in the order of :class:`~jaxgear.planetary.Unbalances`' fields; none by default.
        helix_angle: the planets' base helix angle beta_b (rad; positive: right-hand planets),
            for :class:`~jaxgear.planetary.SpatialPlanetary`; 0 (spur) by default.
        face_width: the meshes' face width (m), for :class:`~jaxgear.planetary.SpatialPlanetary`.
        mesh_tilt_stiffness: (sun mesh, ring mesh) tilting stiffness (N m/rad) or None each
            (k b² cos²β_b/12 from the face width), :class:`~jaxgear.planetary.PlanetaryStage`'s
            ``sun_mesh_tilt_stiffness``, ``ring_mesh_tilt_stiffness``.
        housing_seat: the seat of the case's ``[housing]`` the held member is bolted to
            (``[planetary] housing_seat``; its supports about and along the axis there, every
            support of a held carrier: the dynamic model's ``mount()``).
    """

    teeth: tuple
    planet_angles: tuple
    fixed: Central
    input: Central
    output: Central
    members: dict
    pressure_angles: tuple
    mesh_stiffness: PlanetaryMeshStiffness
    tangential_pin_errors: tuple
    radial_pin_errors: tuple
    center_distance: float
    ring_model: RingModelSpec = dataclasses.field(default_factory=RigidRingSpec)
    eccentricities: tuple = (0.0,) * 6
    planet_runout: tuple = ()
    unbalances: tuple = (0.0,) * 8
    helix_angle: float = 0.0
    face_width: float = 0.0
    mesh_tilt_stiffness: tuple = (None, None)
    housing_seat: int = 0

    @property
    def eccentric(self) -> bool:
        """Whether a member has an eccentricity (a planet: its runout)."""
        return any(self.eccentricities[::2]) or any(self.planet_runout[0] if self.planet_runout else ())

    @property
    def unbalanced(self) -> bool:
        """Whether a member has a mass unbalance."""
        return any(np.any(np.asarray(u) != 0) for u in self.unbalances[::2])

    @property
    def n_planets(self) -> int:
        return len(self.planet_angles)

    def speeds(self, input_speed: float) -> dict:
        """Each central member's speed (rad/s, fixed frame) and the planet's (absolute and
        relative to the carrier), the input at ``input_speed``, the fixed member at rest
        (Willis, :func:`jaxgear.planetary.central_speeds`)."""
        z_s, z_p, z_r = self.teeth
        w = central_speeds(z_s, z_r, self.fixed, self.input, input_speed)
        out = {m.name.lower(): float(w[m]) for m in Central}
        if z_p is not None:
            rel = -(w[Central.SUN] - w[Central.CARRIER]) * z_s / z_p
            out["planet_relative"] = float(rel)
            out["planet"] = float(w[Central.CARRIER] + rel)
        return out

    def torques(self, input_torque: float) -> dict:
        """Each central member's torque (N·m), the input's ``input_torque`` (lossless:
        :func:`jaxgear.planetary.central_torques`; their sum 0)."""
        z_s, _, z_r = self.teeth
        t = central_torques(z_s, z_r, self.input, input_torque)
        return {m.name.lower(): float(t[m]) for m in Central}

    def ratio(self) -> float:
        """The Willis speed ratio ω_input/ω_output (:func:`jaxgear.planetary.speed_ratio`)."""
        z_s, _, z_r = self.teeth
        return speed_ratio(z_s, z_r, self.fixed, self.input, self.output)

    def mesh_frequency(self, input_speed: float) -> float:
        """The mesh frequency (Hz) in the carrier frame, z_s |ω_s − ω_c|/(2π)."""
        w = self.speeds(input_speed)
        return self.teeth[0] * abs(w["sun"] - w["carrier"]) / (2 * math.pi)

    def stage(self, case: Case) -> PlanetaryStage:
        """The lumped stage (:class:`~jaxgear.planetary.PlanetaryStage`) of the case: the members as
        given (a member without torsional stiffness free to turn), the mesh stiffnesses of
        :attr:`mesh_stiffness`."""
        k_s, k_r = self.mesh_stiffness.values(case)
        m = self.members
        return PlanetaryStage(
            sun=m["sun"],
            ring=m["ring"],
            carrier=m["carrier"],
            planet=m["planet"],
            planet_angles=np.asarray(self.planet_angles),
            sun_pressure_angle=self.pressure_angles[0],
            ring_pressure_angle=self.pressure_angles[1],
            sun_mesh_stiffness=k_s,
            ring_mesh_stiffness=k_r,
            eccentricities=Eccentricities(*self.eccentricities, *self.planet_runout),
            unbalances=Unbalances(*self.unbalances) if self.unbalanced else None,
            helix_angle=self.helix_angle,
            face_width=self.face_width,
            sun_mesh_tilt_stiffness=self.mesh_tilt_stiffness[0],
            ring_mesh_tilt_stiffness=self.mesh_tilt_stiffness[1],
        )

    def held_stage(self, stage: PlanetaryStage) -> PlanetaryStage:
        """The stage with its output held in rotation too (HOLD_FACTOR × the stiffest mesh on
        u = r θ, as a load of large inertia): no rigid mechanism mode is left, which the
        centripetal term of the carrier frame would make diverge at any carrier speed (the
        Campbell diagram's stage)."""
        member = self.output.name.lower()
        m = getattr(stage, member)
        held = dataclasses.replace(
            m, torsional_stiffness=m.torsional_stiffness + self._hold(stage) * m.base_radius**2
        )
        return dataclasses.replace(stage, **{member: held})

    @staticmethod
    def _hold(stage: PlanetaryStage) -> float:
        return HOLD_FACTOR * float(
            max(np.max(stage.sun_mesh_stiffness), np.max(stage.ring_mesh_stiffness))
        )

    def sharing_stage(self, stage: PlanetaryStage) -> PlanetaryStage:
        """The stage of the load-sharing solve (:func:`jaxgear.planetary.load_sharing` loads the
        sun): the sun free in rotation, the ring and the carrier held (HOLD_FACTOR × the stiffest
        mesh on u = r θ). Which two members take the reactions does not change the mesh loads:
        with the sun's torque the statics set every member's torque (Willis), and holding
        another pair of members differs by a rigid motion of the mechanism, which strains no
        mesh."""
        hold = self._hold(stage)

        def held(m, k_u):
            return dataclasses.replace(m, torsional_stiffness=k_u * m.base_radius**2)

        return dataclasses.replace(
            stage,
            sun=held(stage.sun, 0.0),
            ring=held(stage.ring, hold),
            carrier=held(stage.carrier, hold),
        )


    def dynamic_meshes(self, case: Case, n_slices: int = 1) -> AbstractPlanetaryMeshes:
        """The 2N meshes of the stage's dynamics (:func:`jaxgear.planetary.planetary_dynamics`)
        and of its quasi-static solves on contact cells: with gears,
        :class:`~jaxgear.planetary.ContactMeshes` of the two pairs' own models
        (:meth:`~jaxgear.io.Case.mesh_model` of each :meth:`~jaxgear.io.Case.mesh_case`: the
        case's ``[mesh]`` stiffness model at the case's E and ν, each mesh's table at its own
        mean planet load, with the ISO 6336-1 low-load factor of ``iso6336``; the same models as
        the pair outputs and the rating), ``n_slices`` slices per contact line, each pair's
        modifications, phased per planet; in the lumped form,
        :class:`~jaxgear.planetary.ConstantMeshes` at the base pitch p_b = 2π r_bs / z_s (so that
        the mesh frequency is z_s |ω_s − ω_c| / 2π)."""
        if not case.pairs:
            sun = self.members["sun"]
            return ConstantMeshes(2.0 * math.pi * float(sun.base_radius) / self.teeth[0])
        geometry = PlanetaryGeometry(case.pairs[0], case.pairs[1], self.center_distance, 0.0)
        ones = [case.mesh_case(k) for k in (0, 1)]
        return ContactMeshes.from_models(
            geometry,
            np.asarray(self.planet_angles),
            tuple(one.mesh_model(n_slices) for one in ones),
            tuple(one.modifications for one in ones),
        )

    def mesh_speed(self, input_speed: float) -> float:
        """The mesh travel speed v = r_bs |ω_s − ω_c| (m/s) at the input's ``input_speed``
        (rad/s): the contact lines' speed along every line of action, in the carrier frame."""
        w = self.speeds(input_speed)
        return float(self.members["sun"].base_radius) * abs(w["sun"] - w["carrier"])


@dataclasses.dataclass(frozen=True)
class PlanetaryForm(CaseForm):
    """A planetary case file (``[planetary]``): its stage (:class:`PlanetarySpec`); the gear
    form's two meshes, ``sun-planet`` (the external pair, the sun driving) and ``planet-ring``
    (the :class:`~jaxgear.InternalGearPair`, the planet driving), named by the gears; each as a
    one-mesh case at the mean planet load, at its speed relative to the carrier. ``jaxgear run``
    writes its stage outputs (``jaxgear/cli/planetary.py``)."""

    spec: PlanetarySpec

    def mesh_name(self, case: Case, k: int) -> str:
        g, h = case.gears[k]
        return f"{case.gear_names[g]}-{case.gear_names[h]}"

    def mesh_label(self, case: Case, k: int) -> str:
        return self.mesh_name(case, k)

    def mesh_case(self, case: Case, k: int) -> Case:
        if not case.pairs:
            raise ValueError(
                f"case {case.name!r}: a lumped planetary stage ([planetary] without [[gears]]) "
                "has no gear meshes"
            )
        spec = self.spec
        torque_sun = abs(spec.torques(case.torque)["sun"])
        force = torque_sun / (spec.n_planets * case.pairs[0].base_radii[0])  # on the line of action
        speeds = spec.speeds(case.speed)
        pair = case.pairs[k]
        g, h = case.gears[k]
        driving_speed = (
            abs(speeds["sun"] - speeds["carrier"]) if k == 0 else abs(speeds["planet_relative"])
        )
        return Case(
            name=f"{case.name}-{self.mesh_name(case, k)}",
            pairs=(pair,),
            gear_modifications=(case.gear_modifications[g], case.gear_modifications[h]),
            torque=force * pair.base_radii[0],
            speed=driving_speed,
            form=PairForm(),
            **case.mesh_settings(),
        )


@dataclasses.dataclass(frozen=True)
class InternalMeshForm(TrainForm):
    """A train file of one mesh whose driven gear is internal (``teeth`` < 0: an
    :class:`~jaxgear.InternalGearPair`): named and labelled as a train's mesh; the mesh is the
    case itself as a one-mesh case, and ``jaxgear run`` writes a pair's quasi-static files for it
    (the rigid mesh: TE, stiffness, pressure); no ``[scene]`` takes it yet."""

    def mesh_case(self, case: Case, k: int) -> Case:
        return dataclasses.replace(case, form=PairForm())
