"""A planetary stage in a case file: the ``[planetary]`` table (docs/guide/planetary.md, "Case
files"), in one of two forms.

**Gear form**: the sun, planet and ring are ``[[gears]]`` entries (the ring internal: ``teeth``
negative, ISO 21771), named by ``[planetary] sun_gear``, ``planet_gear``, ``ring_gear``; the
base radii, the operating pressure angles and the planet-circle radius come from their geometry
(:func:`jaxgear.planetary_geometry` at ``center_distance_mm``), the mesh stiffness from the
gears (ISO 6336-1 c_γα b, or the mean of the ``[mesh]`` stiffness model) or given.

.. code-block:: toml

    [[gears]]                          # sun, planet, ring: keys as a train's gears
    name = "ring"
    teeth = -56                        # internal: negative (ISO 21771)
    ...
    [operating]
    torque_Nm = 3.946e6                # on the input member, in its direction of motion
    speed_rad_s = 1.2671               # of the input member
    [planetary]
    sun_gear = "sun"                   # [[gears]] names
    planet_gear = "planet"
    ring_gear = "ring"
    planets = 3                        # equally spaced; or planet_angles_deg = [0, 120, 240]
    fixed = "ring"                     # "sun", "ring" or "carrier"
    input = "carrier"                  # the output is the third
    center_distance_mm = 863.0         # optional: the sun pair's zero-backlash distance
    mesh_stiffness = "iso6336"         # or "mean", or sun_/ring_mesh_stiffness_N_per_um
    tangential_pin_errors_um = [20.0, 0.0, 0.0]   # optional, one per planet
    sun_eccentricity_um = 10.0         # optional: sun, ring, carrier (radial runout)
    sun_eccentricity_phase_deg = 0.0   # its direction at the start, from planet 1's
    planet_runout_um = [12.0, 0.0, 0.0]          # optional, one per planet (radial runout)
    planet_runout_phase_deg = [0.0, 0.0, 0.0]    # from each planet's radial direction
    housing_seat = 0                   # with [housing]: the seat the held member is bolted to
    sun_unbalance_g_mm = 50.0          # optional: sun, ring, carrier (m e; the dynamics)
    sun_unbalance_phase_deg = 0.0      # planet_unbalance_g_mm = [...]: one per planet
    [planetary.sun]                    # and ring, carrier, planet
    mass_kg = 1.0e3
    inertia_kg_m2 = 100.0              # or inertia_over_r2_kg (I/r_b², Lin & Parker's)
    bearing_N_per_um = 100.0           # radial, both directions (0: floating)
    [planetary.ring]
    torsional_stiffness_Nm_per_rad = 1e12   # or torsional_stiffness_N_per_um (on u = r_b θ)
    [planetary.planet]
    pin_radial_N_per_um = 1.0e4        # the pin on the carrier (radial, tangential)
    pin_tangential_N_per_um = 1.0e4

**Lumped form** (the literature's: Lin & Parker 1999's Table 1 is written so): no ``[[gears]]``;
each member gives ``base_radius_mm`` (the carrier's: the planet-circle radius),
``[planetary]`` the tooth counts ``sun_teeth``, ``ring_teeth`` (positive; for the speed ratios,
the assembly condition and the mesh phases only), ``sun_pressure_angle_deg``,
``ring_pressure_angle_deg`` and both mesh stiffnesses.

**3D lumped model** (:class:`~jaxgear.planetary.SpatialPlanetary`; optional keys, 0 by default): in
``[planetary]`` of the lumped form ``helix_angle_deg`` (the planets' base helix angle, positive
for right-hand planets, in (-90, 90)) and ``face_width_mm`` (the meshes'); the gear form takes
the base helix angle from the sun-planet geometry (right-hand planets: the gears'
``helix_angle_deg`` has no hand) and the planet gear's face width. Each member table: ``axial_N_per_um`` (axial bearing),
``tilt_Nm_per_rad`` (tilting, both axes), ``diametral_inertia_kg_m2`` (half the polar inertia if
absent); the planet's pin: ``pin_axial_N_per_um``, ``pin_tilt_Nm_per_rad``. The meshes' tilting
stiffness is k b² cos²β_b/12 from the face width unless ``[planetary]``
``sun_mesh_tilt_stiffness_Nm_per_rad`` / ``ring_mesh_tilt_stiffness_Nm_per_rad`` give it (as
published models do; :class:`~jaxgear.planetary.PlanetaryStage`).

Validated whole before any work, one line per error in the file's units: the assembly condition
((z_s + z_r) ψ_n/360° integer), planets that do not overlap (adjacent centres 2 a sin(Δψ/2)
at least twice the planet's tip radius, in the lumped form its base radius), the lumped form's
radii (the ring's operating pitch radius r_b/cos α_r beyond the sun's and the planet's
r_b/cos α_s, the planet circle between them; ring_teeth >= sun_teeth + 6), the gear form's
ring with more teeth than its sun and ``center_distance_mm`` between the two pairs'
zero-backlash distances, the three members distinct, the fixed member held in rotation (at
least 0.001 N/µm on u = r_b θ), plausible mesh and pin stiffnesses ([0.001, 1e6] N/µm,
[0.001, 1e9] N/µm), operating pressure angles ([10, 50]°) and a torque floor (the pairs' line
load of 1e-6 N/mm on each sun mesh; in the lumped form a sun-mesh deflection of 1e-7 µm), one
pin error per planet, keys of one form only.
"""

from __future__ import annotations

import math
from typing import Annotated, ClassVar, Literal

import numpy as np
import pydantic

from fem_prep import schema as sc

from .._geometry import GearPair
from .._internal import InternalGearPair, planetary_geometry
from ..planetary import Central, PlanetaryMember, check_assembly, closest_planets, max_planets
from .._stiffness_models import ISO6336
from ._case import Case
from ._planetary_ring_spec import RING_DYNAMICS, RING_MODELS, parse_ring_model
from ._planetary_spec import (
    GivenMeshStiffness,
    ISO6336MeshStiffness,
    MeanMeshStiffness,
    PlanetaryForm,
    PlanetarySpec,
)
from ._plausibility import MIN_LINE_LOAD_N_PER_MM
from ._sections import NEEDED, Section, Text, in_range, number, number_list

__all__ = [
    "MESH_STIFFNESS",
    "PlanetarySection",
    "check_internal_stiffness",
    "check_ring_teeth",
    "is_planetary",
    "parse_planetary",
    "planetary_mesh_settings",
    "torque_floor",
]

#: the lumped models' given mesh stiffnesses (N/µm on the line of action): a plastic gear of a
#: millimetre's face width (~0.2 N/µm) down by two hundred, up to c' ~ 20 N/mm/µm over 50 m
#: of face (the gearbox file's mesh_stiffness_N_per_um); the planet pins' and a held member's
#: torsional support (on u = r_b θ) take the same lower end
MESH_STIFFNESS_N_PER_UM = "[0.001, 1e+06]"
MIN_SUPPORT_N_PER_UM = 1e-3
#: the lumped form's operating transverse pressure angles (deg): the pairs' normal pressure
#: angle [10, 40] (PRESSURE_ANGLE_RANGE_DEG) turned transverse at helix angles up to 45°
#: (atan(tan 40° / cos 45°) = 49.97°)
PRESSURE_ANGLE_DEG = "[10, 50]"
#: the fewest planet teeth of the lumped form, z_p ≈ (z_r − z_s)/2 (the sun's lower end)
MIN_PLANET_TEETH = 3
#: the lumped form's torque floor: the nominal sun-mesh deflection F/k_s at least 1e-7 µm (the
#: pairs' line-load floor MIN_LINE_LOAD_N_PER_MM gives about that; below, round-off)
MIN_DEFLECTION_M = 1e-13

#: ``[planetary] mesh_stiffness``: the name → where the lumped models' mesh stiffness comes from
MESH_STIFFNESS = {"iso6336": ISO6336MeshStiffness, "mean": MeanMeshStiffness}
MEMBERS = ("sun", "ring", "carrier")
GEAR_FORM_KEYS = ("sun_gear", "planet_gear", "ring_gear", "center_distance_mm", "mesh_stiffness")
LUMPED_FORM_KEYS = (
    "sun_teeth",
    "ring_teeth",
    "sun_pressure_angle_deg",
    "ring_pressure_angle_deg",
    "helix_angle_deg",
    "face_width_mm",
)
#: the meshes' optional tilting stiffnesses (N·m/rad; the 3D model's, both forms)
MESH_TILT_KEYS = ("sun_mesh_tilt_stiffness_Nm_per_rad", "ring_mesh_tilt_stiffness_Nm_per_rad")
#: the given mesh stiffnesses (N/µm; the lumped form's, or the gear form's instead of a model)
GIVEN_KEYS = ("sun_mesh_stiffness_N_per_um", "ring_mesh_stiffness_N_per_um")
#: a phase (deg) of an eccentricity, a runout or an unbalance
_PHASE = "[-360, 360]"
_OPERATING = " (deg, operating transverse)"


class BodySection(Section):
    """A member's body in ``[planetary.<member>]`` (module docstring): its mass (kg), polar
    inertia (``inertia_kg_m2`` or ``inertia_over_r2_kg``: I/r_b², Lin & Parker's; one of them,
    :meth:`PlanetarySection.members`), base radius (mm; the lumped form's only) and diametral
    inertia (kg m²; the 3D model's). The lower ends lie far below any gear's (a gram,
    1e-12 kg m²) and above the float range's underflow: I = (I/r²) r² stays positive."""

    mass_kg: number("[1e-06, 1e+07]")
    inertia_kg_m2: number("[1e-12, 1e+09]") | None = None
    inertia_over_r2_kg: number("[1e-06, 1e+09]") | None = None
    base_radius_mm: Annotated[number("[0.001, 1e+05]") | None, NEEDED] = None  # lumped form
    diametral_inertia_kg_m2: number("[1e-12, 1e+09]") | None = None

    def inertia(self, r: float) -> float:
        """The polar inertia (kg m²) at base radius ``r`` (m)."""
        if self.inertia_kg_m2 is not None:
            return self.inertia_kg_m2
        return self.inertia_over_r2_kg * r**2

    def diametral(self) -> dict:
        """:class:`~jaxgear.planetary.PlanetaryMember`'s ``diametral_inertia`` where given."""
        if self.diametral_inertia_kg_m2 is None:
            return {}
        return {"diametral_inertia": self.diametral_inertia_kg_m2}


class CentralSection(BodySection):
    """``[planetary.sun]``, ``[planetary.carrier]`` (and the ring's, :class:`RingSection`): the
    body, its radial bearing (N/µm, both directions; 0: floating), its torsional support
    (``torsional_stiffness_Nm_per_rad``, or ``torsional_stiffness_N_per_um`` on u = r_b θ;
    0 by default: free to turn) and the 3D model's axial (N/µm) and tilting (N·m/rad)
    bearings."""

    bearing_N_per_um: number("[0, 1e+09]") = 0.0
    torsional_stiffness_Nm_per_rad: number("[0, 1e+20]") | None = None
    torsional_stiffness_N_per_um: number("[0, 1e+09]") | None = None
    axial_N_per_um: number("[0, 1e+09]") = 0.0
    tilt_Nm_per_rad: number("[0, 1e+15]") = 0.0

    def torsional(self, r: float) -> float:
        """The torsional stiffness (N·m/rad) at base radius ``r`` (m); 0 when not given."""
        if self.torsional_stiffness_Nm_per_rad is not None:
            return self.torsional_stiffness_Nm_per_rad
        if self.torsional_stiffness_N_per_um is not None:
            return self.torsional_stiffness_N_per_um * 1e6 * r**2
        return 0.0


class RingSection(CentralSection):
    """``[planetary.ring]``: a central member's keys and the ring's model
    (:mod:`jaxgear.io._planetary_ring_spec`: ``model``, ``body``, ``dynamics``, ``modes``,
    ``integration_modes``; the counts' ranges follow the ring body, checked where it is
    read)."""

    model: Literal[tuple(RING_MODELS)] = "rigid"
    body: Text | None = None
    dynamics: Literal[RING_DYNAMICS] | None = None
    modes: number(integer=True) | None = None
    integration_modes: number(integer=True) | None = None


class PlanetSection(BodySection):
    """``[planetary.planet]``: the body and the pin on the carrier (N/µm, radial and
    tangential, at least :data:`MIN_SUPPORT_N_PER_UM`; the 3D model's axial (N/µm) and tilting
    (N·m/rad))."""

    pin_radial_N_per_um: number(f"[{MIN_SUPPORT_N_PER_UM:g}, 1e+09]")
    pin_tangential_N_per_um: number(f"[{MIN_SUPPORT_N_PER_UM:g}, 1e+09]")
    pin_axial_N_per_um: number("[0, 1e+09]") = 0.0
    pin_tilt_Nm_per_rad: number("[0, 1e+15]") = 0.0


class PlanetarySection(Section):
    """``[planetary]`` (module docstring), both forms' keys: which key belongs to which form,
    what the gears or the ``[housing]`` bound, the assembly and the spacing are checked by
    :func:`parse_planetary`; this section checks each key's type and range, the member tables,
    and what relates keys of the table (one of ``planets``/``planet_angles_deg``, the input not
    the fixed member, one value per planet, a phase with its amplitude, a member's inertia
    given once, the lumped ring's teeth beyond the sun's)."""

    WHERE: ClassVar[str] = "planetary"
    # the gear form (its names required there: NEEDED)
    sun_gear: Annotated[Text | None, NEEDED] = None
    planet_gear: Annotated[Text | None, NEEDED] = None
    ring_gear: Annotated[Text | None, NEEDED] = None
    center_distance_mm: number("(0, 1e+06]") | None = None
    mesh_stiffness: Literal[tuple(MESH_STIFFNESS)] = "iso6336"
    # the lumped form (its teeth and angles required there)
    sun_teeth: Annotated[number("[3, 10000]", integer=True) | None, NEEDED] = None
    ring_teeth: Annotated[number(integer=True) | None, NEEDED] = None  # _related: its range
    sun_pressure_angle_deg: Annotated[number(PRESSURE_ANGLE_DEG, note=_OPERATING) | None,
                                      NEEDED] = None
    ring_pressure_angle_deg: Annotated[number(PRESSURE_ANGLE_DEG, note=_OPERATING) | None,
                                       NEEDED] = None
    helix_angle_deg: number("(-90, 90)") = 0.0
    face_width_mm: number("[0, 1e+05]") = 0.0
    # both forms (a member's table required: _related)
    sun: Annotated[CentralSection | None, NEEDED] = None
    planet: Annotated[PlanetSection | None, NEEDED] = None
    ring: Annotated[RingSection | None, NEEDED] = None
    carrier: Annotated[CentralSection | None, NEEDED] = None
    planets: number("[1, 64]", integer=True) | None = None  # or planet_angles_deg: _related
    planet_angles_deg: number_list("[-360, 360]", min_length=1) | None = None
    fixed: Literal[MEMBERS]
    input: Literal[MEMBERS]
    # the lumped form's (or the gear form's instead of mesh_stiffness)
    sun_mesh_stiffness_N_per_um: Annotated[number(MESH_STIFFNESS_N_PER_UM) | None, NEEDED] = None
    ring_mesh_stiffness_N_per_um: Annotated[number(MESH_STIFFNESS_N_PER_UM) | None,
                                            NEEDED] = None
    sun_mesh_tilt_stiffness_Nm_per_rad: number("[0, 1e+15]") | None = None
    ring_mesh_tilt_stiffness_Nm_per_rad: number("[0, 1e+15]") | None = None
    tangential_pin_errors_um: number_list("[-1e+04, 1e+04]") | None = None
    radial_pin_errors_um: number_list("[-1e+04, 1e+04]") | None = None
    sun_eccentricity_um: number("[0, 1e+04]") = 0.0
    sun_eccentricity_phase_deg: number(_PHASE) = 0.0
    ring_eccentricity_um: number("[0, 1e+04]") = 0.0
    ring_eccentricity_phase_deg: number(_PHASE) = 0.0
    carrier_eccentricity_um: number("[0, 1e+04]") = 0.0
    carrier_eccentricity_phase_deg: number(_PHASE) = 0.0
    planet_runout_um: number_list("[0, 1e+04]") | None = None
    planet_runout_phase_deg: number_list(_PHASE) | None = None
    housing_seat: number(integer=True) = 0  # its range follows [housing]: _housing_seat
    sun_unbalance_g_mm: number("[0, 1e+09]") = 0.0
    sun_unbalance_phase_deg: number(_PHASE) = 0.0
    ring_unbalance_g_mm: number("[0, 1e+09]") = 0.0
    ring_unbalance_phase_deg: number(_PHASE) = 0.0
    carrier_unbalance_g_mm: number("[0, 1e+09]") = 0.0
    carrier_unbalance_phase_deg: number(_PHASE) = 0.0
    planet_unbalance_g_mm: number_list("[0, 1e+09]") | None = None
    planet_unbalance_phase_deg: number_list(_PHASE) | None = None

    @pydantic.model_validator(mode="after")
    def _related(self):
        w = self.WHERE
        if (self.planets is None) == (self.planet_angles_deg is None):
            raise sc.fail(w, "planets", "give planets (equally spaced) or planet_angles_deg, "
                          "one of them" + (", not both" if self.planets is not None else ""))
        if self.input == self.fixed:
            raise sc.fail(w, "input", f"is the fixed member (allowed: another of "
                          f"{', '.join(MEMBERS)})", self.input)
        if self.ring_teeth is not None and self.sun_teeth is not None:
            in_range(w, "ring_teeth", self.ring_teeth,
                     f"[{self.sun_teeth + 2 * MIN_PLANET_TEETH}, 10000]",
                     f" (sun_teeth + 2 × {MIN_PLANET_TEETH}: planets of (ring_teeth − sun_teeth)"
                     f"/2 >= {MIN_PLANET_TEETH} teeth)")
        for m in MEMBERS:
            self._with_amplitude(f"{m}_eccentricity_um", f"{m}_eccentricity_phase_deg")
        self._with_amplitude("planet_runout_um", "planet_runout_phase_deg")
        for m in (*MEMBERS, "planet"):
            self._with_amplitude(f"{m}_unbalance_g_mm", f"{m}_unbalance_phase_deg")
        for m in (*MEMBERS, "planet"):
            section = getattr(self, m)
            if section is None:
                raise sc.SchemaError(f"[{w}.{m}]: missing required table", f"[{w}.{m}]")
            _one_of(section, f"{w}.{m}", "inertia_kg_m2", "inertia_over_r2_kg", required=True)
            if isinstance(section, CentralSection):
                _one_of(section, f"{w}.{m}", "torsional_stiffness_Nm_per_rad",
                        "torsional_stiffness_N_per_um")
        return self

    def check_planets(self) -> None:
        """One value per planet in each list of them (checked once the planets can be
        assembled and do not overlap: :func:`parse_planetary`)."""
        n = self.n_planets
        for key in ("tangential_pin_errors_um", "radial_pin_errors_um"):
            v = getattr(self, key)
            if v is not None and len(v) != n:
                raise sc.fail(self.WHERE, key, f"must hold one value per planet ({n})", v)
        for key in ("planet_runout_um", "planet_runout_phase_deg", "planet_unbalance_g_mm",
                    "planet_unbalance_phase_deg"):
            v = getattr(self, key)
            if v is not None and len(v) != n:
                raise sc.fail(self.WHERE, key, f"must be an array of {n} numbers", v)

    def _with_amplitude(self, amp: str, phase: str) -> None:
        if phase in self.given and amp not in self.given:
            raise sc.fail(self.WHERE, phase, f"given without {amp} (its amplitude)",
                          getattr(self, phase))

    @property
    def n_planets(self) -> int:
        """The planets (``planets``, or the angles given)."""
        return self.planets if self.planets is not None else len(self.planet_angles_deg)

    def planet_angles(self) -> np.ndarray:
        """ψ_n (rad), (N,): equally spaced, or as given."""
        if self.planets is not None:
            return 2 * math.pi * np.arange(self.planets) / self.planets
        return np.radians(self.planet_angles_deg)

    def per_planet(self, key: str, scale: float) -> tuple:
        """A list of one value per planet (0 where not given), times ``scale`` (to SI)."""
        v = getattr(self, key)
        return tuple(x * scale for x in ([0.0] * self.n_planets if v is None else v))


def _one_of(section: Section, where: str, first: str, second: str, required: bool = False):
    """One of two keys of one quantity (``first`` or ``second``, not both; ``required``: one
    of them)."""
    given = [k for k in (first, second) if k in section.given]
    if len(given) == 2:
        raise sc.fail(where, second, f"give {first} or {second}, not both",
                      getattr(section, second))
    if required and not given:
        raise sc.fail(where, first, f"missing required key (or {second})")


def is_planetary(data) -> bool:
    """Whether a parsed case file is a planetary stage (a ``[planetary]`` table)."""
    return isinstance(data, dict) and "planetary" in data


# -- parsing -----------------------------------------------------------------------------------


def _central(t: CentralSection, name: str, base_radius: float | None) -> PlanetaryMember:
    where = f"planetary.{name}"
    r = _base_radius(t, where, base_radius)
    return PlanetaryMember(
        mass=t.mass_kg,
        polar_inertia=t.inertia(r),
        base_radius=r,
        bearing_stiffness=t.bearing_N_per_um * 1e6,
        torsional_stiffness=t.torsional(r),
        axial_stiffness=t.axial_N_per_um * 1e6,
        tilt_stiffness=t.tilt_Nm_per_rad,
        **t.diametral(),
    )


def _planet(t: PlanetSection, base_radius: float | None) -> PlanetaryMember:
    r = _base_radius(t, "planetary.planet", base_radius)
    return PlanetaryMember(
        mass=t.mass_kg,
        polar_inertia=t.inertia(r),
        base_radius=r,
        bearing_stiffness=[t.pin_radial_N_per_um * 1e6, t.pin_tangential_N_per_um * 1e6],
        axial_stiffness=t.pin_axial_N_per_um * 1e6,
        tilt_stiffness=t.pin_tilt_Nm_per_rad,
        **t.diametral(),
    )


def _base_radius(t: BodySection, where: str, from_gears: float | None) -> float:
    if from_gears is None:
        if t.base_radius_mm is None:
            raise sc.fail(where, "base_radius_mm", "missing required key")
        return t.base_radius_mm * 1e-3
    if t.base_radius_mm is not None:
        raise sc.fail(
            where,
            "base_radius_mm",
            "allowed only in the lumped form (no [[gears]]): with gears the base radii come "
            "from their geometry",
            t.base_radius_mm,
        )
    return from_gears


def _angles(t: PlanetarySection, z_s: int, z_r: int) -> tuple:
    """The planets' angles (:meth:`PlanetarySection.planet_angles`), the assembly condition
    checked."""
    psi = t.planet_angles()
    key = "planets" if t.planets is not None else "planet_angles_deg"
    shown = getattr(t, key)
    turns = (z_s + z_r) * (psi - psi[0]) / (2 * math.pi)
    bad = np.abs(turns - np.round(turns)) > 1e-6
    if np.any(bad):
        i = int(np.argmax(bad))
        raise sc.fail(
            "planetary",
            key,
            f"planet {i + 1} at {math.degrees(psi[i] - psi[0]):.6g}° cannot be assembled: "
            f"(z_sun + z_ring) × angle/360° = {turns[i]:.6g} must be an integer (z_sun = {z_s}, "
            f"z_ring = {z_r}; equally spaced planets need (z_sun + z_ring)/planets integer)",
            shown,
        )
    check_assembly(z_s, z_r, psi)  # the library's own condition, the same
    return tuple(float(p) for p in psi)


def _roles(t: PlanetarySection) -> tuple:
    out = next(n for n in MEMBERS if n not in (t.fixed, t.input))
    return tuple(Central[n.upper()] for n in (t.fixed, t.input, out))


def _eccentricities(t: PlanetarySection) -> tuple:
    """The sun's, ring's and carrier's eccentricities and phases in SI as
    :class:`jaxgear.planetary.Eccentricities` takes them (sun, sun_phase, ring, ring_phase,
    carrier, carrier_phase)."""
    out = []
    for m in MEMBERS:
        out += [getattr(t, f"{m}_eccentricity_um") * 1e-6,
                math.radians(getattr(t, f"{m}_eccentricity_phase_deg"))]
    return tuple(out)


def _unbalances(t: PlanetarySection) -> tuple:
    """The sun's, ring's, carrier's (one value each) and the planets' (one per planet) mass
    unbalances and phases in SI as :class:`jaxgear.planetary.Unbalances` takes them (kg m,
    rad)."""
    out = []
    for m in MEMBERS:
        out += [getattr(t, f"{m}_unbalance_g_mm") * 1e-6,
                math.radians(getattr(t, f"{m}_unbalance_phase_deg"))]
    out += [t.per_planet("planet_unbalance_g_mm", 1e-6),
            t.per_planet("planet_unbalance_phase_deg", math.pi / 180)]
    return tuple(out)


def _refuse(t: PlanetarySection, keys, why: str) -> None:
    for key in keys:
        if key in t.given:
            raise sc.fail("planetary", key, why, getattr(t, key))


def _required(t: PlanetarySection, key: str):
    """A key of one form that the form requires."""
    if key not in t.given:
        raise sc.fail("planetary", key, "missing required key")
    return getattr(t, key)


def _given_stiffness(t: PlanetarySection, required: bool) -> GivenMeshStiffness | None:
    if not required and not any(k in t.given for k in GIVEN_KEYS):
        return None
    return GivenMeshStiffness(*(_required(t, k) * 1e6 for k in GIVEN_KEYS))


def parse_planetary(data: dict, base: dict, gears: dict, index: dict) -> Case:
    """Validate ``[planetary]`` (:class:`PlanetarySection`) and build the stage's
    :class:`Case` (:class:`PlanetaryForm`).

    Args:
        data: the parsed file; ``base``: the train fields already parsed (``name``, material,
            mesh settings, modifications, operating torque and speed: :class:`Case` keywords);
        gears: the ``[[gears]]`` (name → parsed gear, as :func:`jaxgear.io._train_file._gear`
            gives it), ``{}`` in the lumped form; index: name → position.

    Raises:
        SchemaError: one line, in the file's units (module docstring).
    """
    t = PlanetarySection.of_file(data, required=True)
    for key in ("meshes", "scene"):
        if key in data:
            raise sc.SchemaError(
                f"[{key}]: not in a planetary case (allowed: [planetary] names the stage's "
                "gears and meshes; its models are the lumped ones of [planetary])"
            )
    op = data.get("operating", {})
    for key in ("loads", "wrenches"):
        if key in op:
            raise sc.fail(
                "operating",
                key,
                "not in a planetary case (allowed: torque_Nm on the input member)",
                op[key],
            )
    fixed, driver, output = _roles(t)
    if gears:
        _refuse(
            t, LUMPED_FORM_KEYS, "allowed only in the lumped form (no [[gears]]): the gears give it"
        )
        geometry, names, z_p = _geometry(t, gears)
        z_s, z_r = geometry.sun_planet.pinion.teeth, -geometry.planet_ring.gear.teeth
        ring_root = float(geometry.planet_ring.root_radii[1])
        radii = {
            "sun": geometry.sun_planet.base_radii[0],
            "planet": geometry.sun_planet.base_radii[1],
            "ring": geometry.planet_ring.base_radii[1],
            "carrier": geometry.center_distance,
        }
        alphas = (geometry.sun_pressure_angle, geometry.ring_pressure_angle)
        given = _given_stiffness(t, required=False)
        if given is not None and "mesh_stiffness" in t.given:
            raise sc.fail(
                "planetary",
                "mesh_stiffness",
                "give mesh_stiffness or the two *_mesh_stiffness_N_per_um, not both",
                t.mesh_stiffness,
            )
        mesh_k = given or MESH_STIFFNESS[t.mesh_stiffness]()
        a_w = geometry.center_distance
        pairs = (geometry.sun_planet, geometry.planet_ring)
        # the gears' helix_angle_deg has no hand: the planets are taken right-hand
        helix = abs(float(geometry.sun_planet.base_helix_angle))
        width = float(gears[names[1]]["member"].face_width)
    else:
        _refuse(t, GEAR_FORM_KEYS, "allowed only with [[gears]] (the gear form)")
        z_s = _required(t, "sun_teeth")
        z_r = _required(t, "ring_teeth")
        z_p = None
        radii = dict.fromkeys((*MEMBERS, "planet"))
        alphas = tuple(math.radians(_required(t, k))
                       for k in ("sun_pressure_angle_deg", "ring_pressure_angle_deg"))
        mesh_k = _given_stiffness(t, required=True)
        names, pairs, a_w, ring_root = (), (), None, None
        helix = math.radians(t.helix_angle_deg)
        width = t.face_width_mm * 1e-3
    psi = _angles(t, z_s, z_r)
    ring_model = parse_ring_model(t.ring, z_r, ring_root)
    members = {m: _central(getattr(t, m), m, radii[m]) for m in MEMBERS}
    members["planet"] = _planet(t.planet, radii["planet"])
    if a_w is None:
        a_w = float(members["carrier"].base_radius)
    _check_held(getattr(t, fixed.name.lower()), members[fixed.name.lower()], fixed.name.lower())
    if not gears:
        _check_lumped_radii(members, alphas)
    _check_spacing(t, psi, a_w, float(geometry.sun_planet.tip_radii[1]) if gears
                   else float(members["planet"].base_radius), "tip" if gears else "base")
    t.check_planets()
    spec = PlanetarySpec(
        teeth=(z_s, z_p, z_r),
        planet_angles=psi,
        fixed=fixed,
        input=driver,
        output=output,
        members=members,
        pressure_angles=alphas,
        mesh_stiffness=mesh_k,
        tangential_pin_errors=t.per_planet("tangential_pin_errors_um", 1e-6),
        radial_pin_errors=t.per_planet("radial_pin_errors_um", 1e-6),
        eccentricities=_eccentricities(t),
        planet_runout=(t.per_planet("planet_runout_um", 1e-6),
                       t.per_planet("planet_runout_phase_deg", math.pi / 180)),
        unbalances=_unbalances(t),
        center_distance=a_w,
        ring_model=ring_model,
        helix_angle=helix,
        face_width=width,
        mesh_tilt_stiffness=tuple(getattr(t, k) for k in MESH_TILT_KEYS),
        housing_seat=_housing_seat(data, t),
    )
    _check_torque(data["operating"], spec, pairs)
    mods = base.pop("gear_modifications", ())
    idx = [index[nm] for nm in names]
    return Case(
        pairs=pairs,
        gear_names=tuple(names),
        gears=((0, 1), (1, 2)) if pairs else (),
        angles=(0.0, 0.0) if pairs else (),
        gear_modifications=tuple(mods[i] for i in idx),
        form=PlanetaryForm(spec),
        **base,
    )


def _housing_seat(data: dict, t: PlanetarySection) -> int:
    """``[planetary] housing_seat``: the seat of ``[housing]`` the held member is bolted to
    (default 0); refused without a ``[housing]``, or past its seats (a box: two, its end walls'
    bores round the axis; a mesh file: its ``[[housing.seats]]``)."""
    if "housing" not in data:
        if "housing_seat" in t.given:
            raise sc.fail("planetary", "housing_seat", "allowed only with a [housing]",
                          t.housing_seat)
        return 0
    h = data["housing"]
    n = len(h.get("seats", [])) if isinstance(h, dict) and "mesh_file" in h else 2
    return in_range("planetary", "housing_seat", t.housing_seat, f"[0, {max(n - 1, 0)}]",
                    " (a box: 0 its x- wall's bore, 1 its x+ wall's)")


def _check_held(t: CentralSection, member: PlanetaryMember, name: str) -> None:
    """The fixed member held in rotation: a torsional stiffness of at least
    :data:`MIN_SUPPORT_N_PER_UM` on u = r_b θ (k_θ >= 1e3 N/m × r_b²), in the units of the key
    given (one line)."""
    where = f"planetary.{name}"
    r = float(member.base_radius)
    note = (f" (the fixed member is held: at least {MIN_SUPPORT_N_PER_UM:g} N/µm on u = r_b θ, "
            f"r_b = {r * 1e3:.6g} mm)")
    ranges = {"torsional_stiffness_N_per_um": (f"{MIN_SUPPORT_N_PER_UM:g}", "1e+09"),
              "torsional_stiffness_Nm_per_rad": (f"{MIN_SUPPORT_N_PER_UM * 1e6 * r**2:.6g}",
                                                 "1e+20")}
    given = [k for k in ranges if k in t.given]
    if not given:
        raise sc.fail(where, "torsional_stiffness_Nm_per_rad", "missing: the fixed member needs "
                      "a torsional stiffness (its support), allowed >= "
                      f"{ranges['torsional_stiffness_Nm_per_rad'][0]} (or "
                      f"torsional_stiffness_N_per_um >= {MIN_SUPPORT_N_PER_UM:g})")
    in_range(where, given[0], getattr(t, given[0]), "[{}, {}]".format(*ranges[given[0]]), note)


def _check_lumped_radii(members: dict, alphas: tuple) -> None:
    """The lumped form's base radii of a stage that can exist (one line, mm): the ring's
    operating pitch radius r_br/cos α_r beyond the sun's and the planet's r_b/cos α_s (the
    ring surrounds them), the planet circle a (the carrier's base_radius_mm) between them
    (a = r_s' + r_p' exceeds r_s' and r_p'; the planets' centres inside the ring)."""
    r = {m: float(members[m].base_radius) for m in members}
    cs, cr = math.cos(alphas[0]), math.cos(alphas[1])
    inner = max(r["sun"], r["planet"]) / cs  # m: the sun's or the planet's pitch radius
    ring = r["ring"] / cr
    if not ring > inner:
        which = "sun" if r["sun"] >= r["planet"] else "planet"
        raise sc.fail(
            "planetary.ring", "base_radius_mm",
            f"out of range, allowed > {inner * cr * 1e3:.6g} (the ring surrounds the sun and "
            f"the planets: its operating pitch radius r_b/cos α_r beyond the {which}'s "
            f"r_b/cos α_s = {inner * 1e3:.6g} mm)", r["ring"] * 1e3)
    if not inner < r["carrier"] < ring:
        raise sc.fail(
            "planetary.carrier", "base_radius_mm",
            f"out of range, allowed ({inner * 1e3:.6g}, {ring * 1e3:.6g}) (the planet circle: "
            "beyond the sun's and the planet's operating pitch radii r_b/cos α_s, inside the "
            "ring's r_b/cos α_r)", r["carrier"] * 1e3)


def _check_spacing(t: PlanetarySection, psi: tuple, a: float, radius: float, which: str) -> None:
    """No two planets overlap: adjacent centres 2 a sin(Δψ/2) apart on the planet circle of
    radius a (m) at least twice the planets' ``which`` radius (m): their tip circles (the gear
    form) or base circles (the lumped form, which has no tip) must not intersect (one line
    naming ``planets`` or ``planet_angles_deg``, mm)."""
    if len(psi) < 2:
        return
    i, j, d = closest_planets(psi, a)
    if d >= 2.0 * radius:
        return
    key = "planets" if t.planets is not None else "planet_angles_deg"
    most = max_planets(a, radius)
    hint = f"; allowed planets <= {most}" if most is not None else ""
    raise sc.fail(
        "planetary", key,
        f"planets {i + 1} and {j + 1} (at {math.degrees(psi[i]):.6g}° and "
        f"{math.degrees(psi[j]):.6g}°) overlap: their centres are {d * 1e3:.6g} mm apart on the "
        f"planet circle of radius {a * 1e3:.6g} mm, allowed >= 2 × the planet's {which} radius "
        f"= {2 * radius * 1e3:.6g} mm (their {which} circles must not intersect{hint})",
        getattr(t, key))


def torque_floor(spec: PlanetarySpec, pairs: tuple) -> tuple[float, str]:
    """(the least input torque (N·m), why) that strains the stage's sun meshes measurably: with
    gears, the pairs' floor, a line load F_n/b = ``MIN_LINE_LOAD_N_PER_MM`` on each sun mesh
    (F_n = |T_s| / (N r_bs cos β_b)); in the lumped form, a nominal sun-mesh deflection
    |T_s| / (N r_bs k_s) of :data:`MIN_DEFLECTION_M`; |T_s| = |T_in z_s / z_in| (Willis)."""
    per_sun = abs(1.0 / spec.torques(1.0)["sun"])  # |T_in / T_s|
    r_bs, n = float(spec.members["sun"].base_radius), spec.n_planets
    if pairs:
        sp = pairs[0]
        floor = MIN_LINE_LOAD_N_PER_MM
        t_min = floor * 1e3 * sp.face_width * n * r_bs * math.cos(sp.base_helix_angle) * per_sun
        return t_min, f"a line load F_n/b of {floor:g} N/mm on each sun mesh"
    t_min = MIN_DEFLECTION_M * spec.mesh_stiffness.sun * n * r_bs * per_sun
    return t_min, (f"a sun-mesh deflection of {MIN_DEFLECTION_M * 1e6:g} µm at "
                   "sun_mesh_stiffness_N_per_um")


def _check_torque(op: dict, spec: PlanetarySpec, pairs: tuple) -> None:
    """``[operating] torque_Nm`` at least :func:`torque_floor` (one line)."""
    t_min, why = torque_floor(spec, pairs)
    sc.number(op, "torque_Nm", "operating", allowed=f"[{float(f'{t_min:.3g}'):.3g}, 1e+12]",
              note=f" ({why})")


def check_ring_teeth(data: dict) -> None:
    """The gear form's ring larger than its sun, refused in one line on the ring's ``teeth``
    before its ``[[gears]]`` entry (its cutter keys, whose range follows |z|) is read: a ring
    of no more teeth than the sun cannot surround it. Reads the raw file; anything malformed
    is left to the parser."""
    t = data.get("planetary")
    gears = data.get("gears")
    if not isinstance(t, dict) or not isinstance(gears, list):
        return
    by_name = {g.get("name"): (i, g) for i, g in enumerate(gears)
               if isinstance(g, dict) and isinstance(g.get("name"), str)}
    try:
        (_, sun), (_, ring) = by_name[t["sun_gear"]], by_name[t["ring_gear"]]
    except (KeyError, TypeError):
        return
    z_s, z_r = sun.get("teeth"), ring.get("teeth")
    if not all(isinstance(z, int) and not isinstance(z, bool) for z in (z_s, z_r)):
        return
    if z_r < 0 < z_s and -z_r <= z_s:
        raise sc.fail(
            f"gears.{t['ring_gear']}", "teeth",
            f"a ring of {-z_r} teeth cannot surround the sun {t['sun_gear']!r} of {z_s}: "
            f"allowed <= {-(z_s + 1)} (more teeth than the sun's; internal: negative)", z_r)


def _geometry(t: PlanetarySection, gears: dict):
    """The stage's pairs from the gears ``[planetary]`` names (sun, planet external, ring
    internal; one module, pressure and helix angle), at ``center_distance_mm``."""
    names = []
    for role in ("sun", "planet", "ring"):
        key = f"{role}_gear"
        name = _required(t, key)
        if name not in gears:
            raise sc.fail("planetary", key, f"no such gear, allowed {', '.join(gears)}", name)
        if name in names:
            raise sc.fail(
                "planetary",
                key,
                f"names the {('sun', 'planet')[names.index(name)]} already (allowed: three "
                "different gears)",
                name,
            )
        internal = gears[name]["member"].teeth < 0
        if internal != (role == "ring"):
            what = (
                "an internal gear (teeth < 0)" if role == "ring" else "an external gear (teeth > 0)"
            )
            raise sc.fail(
                "planetary",
                key,
                f"must name {what}: [gears.{name}] teeth = {gears[name]['member'].teeth}",
                name,
            )
        names.append(name)
    g = [gears[n] for n in names]
    for key, label in (
        ("module_mm", "normal_module_mm"),
        ("alpha_deg", "normal_pressure_angle_deg"),
        ("beta_deg", "helix_angle_deg"),
    ):
        if len({x[key] for x in g}) > 1:
            raise sc.SchemaError(
                f"[planetary]: [gears.{names[0]}], [gears.{names[1]}], [gears.{names[2]}] "
                f"{label} = {', '.join(sc.fmt(x[key]) for x in g)} differ (a stage's gears share "
                "it)"
            )
    cd = t.center_distance_mm
    if cd is not None:
        _check_center_distance(t, g, cd)
    try:
        geometry = planetary_geometry(
            g[0]["member"],
            g[1]["member"],
            g[2]["member"],
            g[0]["module_mm"] * 1e-3,
            math.radians(g[0]["alpha_deg"]),
            math.radians(g[0]["beta_deg"]),
            None if cd is None else cd * 1e-3,
        )
    except (ValueError, ArithmeticError) as err:
        raise sc.SchemaError(f"[planetary] {' / '.join(names)}: {sc.g6(str(err))}") from None
    return geometry, tuple(names), g[1]["member"].teeth


def _check_center_distance(t: PlanetarySection, g: list, cd: float) -> None:
    """``center_distance_mm`` between the sun pair's zero-backlash distance (closer, its teeth
    jam) and the ring pair's (farther, the ring's jam; :func:`jaxgear.planetary_geometry`), in
    mm (the range rounded inwards to the µm); the pairs' own checks otherwise."""
    args = (g[0]["module_mm"] * 1e-3, math.radians(g[0]["alpha_deg"]),
            math.radians(g[0]["beta_deg"]))
    try:
        low = GearPair(g[0]["member"], g[1]["member"], *args).backlash_center_distance
        high = InternalGearPair(g[1]["member"], g[2]["member"], *args).backlash_center_distance
    except (ValueError, ArithmeticError):
        return  # the geometry's own message (planetary_geometry)
    lo_mm, hi_mm = math.ceil(low * 1e6) / 1e3, math.floor(high * 1e6) / 1e3
    if low <= high and not low <= cd * 1e-3 <= high:
        raise sc.fail(
            "planetary", "center_distance_mm",
            f"out of range, allowed [{lo_mm:.3f}, {hi_mm:.3f}] (from the sun pair's "
            "zero-backlash distance, closer its teeth jam, to the ring pair's, farther the "
            "ring's teeth jam)", cd)


def check_internal_stiffness(case: Case, where: str) -> None:
    """The ``[mesh]`` stiffness model must have an internal-gear form when a mesh is internal
    (``uniform``, ``iso6336``, ``fe2d``, or ``weber`` with the internal gear's cutter, its
    ``[[gears]]`` ``cutter_*`` keys: :meth:`jaxgear.AbstractStiffness.check_pair`), refused in one line
    before any work."""
    internal = [p for p in case.pairs if isinstance(p, InternalGearPair)]
    if not internal:
        return
    problem = f"{case.stiffness.name!r} has no internal-gear form"
    try:
        ok = case.stiffness.internal_teeth and all(
            case.stiffness.check_pair(p) is None for p in internal
        )
    except ValueError as err:
        ok, problem = False, f"{case.stiffness.name!r} cannot take it: {err}"
    if not ok:
        raise sc.fail(
            "mesh",
            "stiffness",
            f"{problem} ({where} has an internal gear); allowed 'uniform', 'iso6336', 'fe2d', "
            "or 'weber' with the internal gear's cutter_teeth ([[gears]])",
            case.stiffness.name,
        )


def planetary_mesh_settings(data: dict, mesh: dict, gears: dict) -> dict:
    """A planetary case's (or an internal mesh's) mesh settings: ``[mesh]``'s, the stiffness
    model ISO 6336 unless the file names one (the default FE model has no internal-gear form),
    given the internal gear's cutter (its ``[[gears]]`` entry's ``cutter_*`` keys,
    :func:`gear_cutter`; :meth:`jaxgear.AbstractStiffness.with_ring_cutter`)."""
    if "stiffness" not in data.get("mesh", {}):
        return {**mesh, "stiffness": ISO6336()}
    cutters = [g["cutter"] for g in gears.values() if g.get("cutter") is not None]
    if cutters:  # one internal gear per case (a planetary stage's ring, an internal mesh's)
        return {**mesh, "stiffness": mesh["stiffness"].with_ring_cutter(cutters[0])}
    return mesh


#: an internal gear's ``[[gears]]`` keys of its pinion-type cutter (:func:`gear_cutter`)
CUTTER_KEYS = ("cutter_teeth", "cutter_profile_shift", "cutter_tip_radius_coeff")


def cutter_values(table: dict, where: str, teeth: int) -> tuple | None:
    """(z0, x0, ρ_a0/m_n or ``None``) of the cutter keys of an internal gear's ``[[gears]]``
    entry (``table``, named ``where``; ``teeth`` its |z|), ``None`` without them: the ranges of
    :func:`gear_cutter`, which also tries the cutter; the rating reads the same values
    (:func:`jaxgear.io._rating_table.ring_cutter`).

    Raises:
        SchemaError: ``cutter_profile_shift`` or ``cutter_tip_radius_coeff`` without
            ``cutter_teeth``, a value out of range (one line naming the key).
    """
    given = [k for k in CUTTER_KEYS if k in table]
    if not given:
        return None
    if "cutter_teeth" not in table:
        raise sc.fail(
            where, given[0], "describes the internal gear's cutter: give cutter_teeth too",
            table[given[0]],
        )
    if teeth - 10 < 11:
        raise sc.fail(where, "cutter_teeth", f"the internal gear's {teeth} teeth are too few "
                      "for a pinion-type cutter of at least 11 teeth (allowed: cutter_teeth in "
                      "[11, |teeth| − 10], a gear of at least 21 teeth; or leave the cutter "
                      "keys out)", table["cutter_teeth"])
    z0 = sc.number(table, "cutter_teeth", where, allowed=f"[11, {teeth - 10}]", integer=True)
    x0 = sc.number(table, "cutter_profile_shift", where, 0.0, allowed="[-1, 1.5]")
    rho = sc.number(
        table, "cutter_tip_radius_coeff", where, None, allowed="(0, 0.6]",
        note=" (default: the gear's fillet_radius_coeff)",
    )
    return int(z0), x0, rho


def gear_cutter(table: dict, where: str, member, module_mm, alpha_deg, beta_deg):
    """The pinion-type cutter of an internal gear's ``[[gears]]`` entry, a
    :class:`fem_prep.ShaperCutter` (``None`` without the keys): ``cutter_teeth`` z0 (integer,
    [11, |z| − 10]), ``cutter_profile_shift`` x0 ([−1, 1.5], default 0),
    ``cutter_tip_radius_coeff`` ρ_a0/m_n ((0, 0.6], default the gear's ``fillet_radius_coeff``),
    the one place of the ring's cutter in a case file (``[rating] ring_cutter_*``, same
    ranges, the older spelling). The Weber stiffness model generates the ring's teeth with it
    (:func:`fem_prep.generate_internal_tooth`), which is tried here: a cutter that cannot cut
    the ring is refused in one line, before any work; a planetary stage's rating takes its
    root section from it (:func:`jaxgear.io._rating_table.ring_cutter`).

    Raises:
        SchemaError: the keys on an external gear, ``cutter_profile_shift`` or
            ``cutter_tip_radius_coeff`` without ``cutter_teeth``, a value out of range, a
            cutter that cannot cut the ring (naming the key and the values that work).
    """
    given = [k for k in CUTTER_KEYS if k in table]
    if not given:
        return None
    # the gear's own table accepts them (as _member's for the member keys)
    sc.check_keys({k: table[k] for k in given}, set(CUTTER_KEYS), where)
    if member.teeth > 0:
        raise sc.fail(
            where, given[0], "belongs to an internal gear (teeth < 0): its pinion-type cutter",
            table[given[0]],
        )
    import fem_prep  # lazy: SciPy

    cutter = fem_prep.ShaperCutter(*cutter_values(table, where, -member.teeth))
    try:
        fem_prep.generate_internal_tooth(
            fem_prep.InternalToothGeometry(
                member.teeth, module_mm * 1e-3, math.radians(alpha_deg), math.radians(beta_deg),
                member.profile_shift, member.addendum_coeff, member.dedendum_coeff,
                member.fillet_radius_coeff, cutter,
            ),
            n_fillet=8, n_involute=2, n_tip=0,
        )
    except ValueError as err:
        raise sc.SchemaError(f"[{where}] {str(err).replace('cutter.', 'cutter_')}") from None
    return cutter
