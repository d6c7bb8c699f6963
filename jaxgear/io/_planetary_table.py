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

import numpy as np

from fem_prep import schema as sc

from .._geometry import GearPair
from .._internal import InternalGearPair, planetary_geometry
from ..planetary import Central, PlanetaryMember, check_assembly, closest_planets, max_planets
from .._stiffness_models import ISO6336
from ._case import Case
from ._planetary_ring_spec import RING_MODEL_KEYS, parse_ring_model
from ._planetary_spec import (
    GivenMeshStiffness,
    ISO6336MeshStiffness,
    MeanMeshStiffness,
    PlanetaryForm,
    PlanetarySpec,
)
from ._plausibility import MIN_LINE_LOAD_N_PER_MM

__all__ = [
    "MESH_STIFFNESS",
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
#: keys of [planetary] (both forms; a key of the other form is refused in one line)
PLANETARY_KEYS = {
    *GEAR_FORM_KEYS,
    *LUMPED_FORM_KEYS,
    "sun",
    "planet",
    "ring",
    "carrier",
    "planets",
    "planet_angles_deg",
    "fixed",
    "input",
    "sun_mesh_stiffness_N_per_um",
    "ring_mesh_stiffness_N_per_um",
    *MESH_TILT_KEYS,
    "tangential_pin_errors_um",
    "radial_pin_errors_um",
    *(f"{m}_eccentricity{q}" for m in ("sun", "ring", "carrier") for q in ("_um", "_phase_deg")),
    "planet_runout_um",
    "planet_runout_phase_deg",
    "housing_seat",
    *(f"{m}_unbalance{q}" for m in (*MEMBERS, "planet") for q in ("_g_mm", "_phase_deg")),
}
_BODY_KEYS = {
    "mass_kg",
    "inertia_kg_m2",
    "inertia_over_r2_kg",
    "base_radius_mm",
    "diametral_inertia_kg_m2",
}
CENTRAL_KEYS = _BODY_KEYS | {
    "bearing_N_per_um",
    "torsional_stiffness_Nm_per_rad",
    "torsional_stiffness_N_per_um",
    "axial_N_per_um",
    "tilt_Nm_per_rad",
}
PLANET_KEYS = _BODY_KEYS | {
    "pin_radial_N_per_um",
    "pin_tangential_N_per_um",
    "pin_axial_N_per_um",
    "pin_tilt_Nm_per_rad",
}
#: each member table's keys (the others: CENTRAL_KEYS)
MEMBER_KEYS = {"planet": PLANET_KEYS, "ring": CENTRAL_KEYS | RING_MODEL_KEYS}


def is_planetary(data) -> bool:
    """Whether a parsed case file is a planetary stage (a ``[planetary]`` table)."""
    return isinstance(data, dict) and "planetary" in data


# -- parsing -----------------------------------------------------------------------------------


def _central(table: dict, name: str, base_radius: float | None) -> PlanetaryMember:
    where = f"planetary.{name}"
    r = _base_radius(table, where, base_radius)
    mass, inertia = _body(table, where, r)
    bearing = sc.number(table, "bearing_N_per_um", where, 0.0, allowed="[0, 1e+09]") * 1e6
    torsional = _either(
        table,
        where,
        ("torsional_stiffness_Nm_per_rad", "[0, 1e+20]", 1.0),
        ("torsional_stiffness_N_per_um", "[0, 1e+09]", 1e6 * r**2),
        0.0,
    )
    return PlanetaryMember(
        mass=mass,
        polar_inertia=inertia,
        base_radius=r,
        bearing_stiffness=bearing,
        torsional_stiffness=torsional,
        **_spatial(table, where, ""),
    )


def _spatial(table: dict, where: str, prefix: str) -> dict:
    """The 3D model's keys of a member (:class:`~jaxgear.planetary.SpatialPlanetary`): the axial and
    tilting stiffnesses (``axial_N_per_um``, ``tilt_Nm_per_rad``; a planet's ``pin_``-named)
    and the diametral inertia (``diametral_inertia_kg_m2``; half the polar one if absent)."""
    out = {
        "axial_stiffness": sc.number(
            table, f"{prefix}axial_N_per_um", where, 0.0, allowed="[0, 1e+09]"
        )
        * 1e6,
        "tilt_stiffness": sc.number(
            table, f"{prefix}tilt_Nm_per_rad", where, 0.0, allowed="[0, 1e+15]"
        ),
    }
    if "diametral_inertia_kg_m2" in table:
        out["diametral_inertia"] = sc.number(
            table, "diametral_inertia_kg_m2", where, allowed="[1e-12, 1e+09]"
        )
    return out


def _planet(table: dict, base_radius: float | None) -> PlanetaryMember:
    where = "planetary.planet"
    r = _base_radius(table, where, base_radius)
    mass, inertia = _body(table, where, r)
    pin = [
        sc.number(table, key, where, allowed=f"[{MIN_SUPPORT_N_PER_UM:g}, 1e+09]") * 1e6
        for key in ("pin_radial_N_per_um", "pin_tangential_N_per_um")
    ]
    return PlanetaryMember(
        mass=mass,
        polar_inertia=inertia,
        base_radius=r,
        bearing_stiffness=pin,
        **_spatial(table, where, "pin_"),
    )


def _base_radius(table: dict, where: str, from_gears: float | None) -> float:
    if from_gears is None:
        return sc.number(table, "base_radius_mm", where, allowed="[0.001, 1e+05]") * 1e-3
    if "base_radius_mm" in table:
        raise sc.fail(
            where,
            "base_radius_mm",
            "allowed only in the lumped form (no [[gears]]): with gears the base radii come "
            "from their geometry",
            table["base_radius_mm"],
        )
    return from_gears


def _body(table: dict, where: str, r: float) -> tuple[float, float]:
    # lower ends far below any gear's (a gram, 1e-12 kg m²) and above the float range's
    # underflow: I = (I/r²) r² stays a positive number
    mass = sc.number(table, "mass_kg", where, allowed="[1e-06, 1e+07]")
    inertia = _either(
        table,
        where,
        ("inertia_kg_m2", "[1e-12, 1e+09]", 1.0),
        ("inertia_over_r2_kg", "[1e-06, 1e+09]", r**2),
    )
    return mass, inertia


def _either(table: dict, where: str, first: tuple, second: tuple, default=sc.MISSING) -> float:
    """One of two keys (key, allowed, SI factor) of one quantity, or ``default``."""
    values = [
        sc.number(table, key, where, None, allowed=allowed) for key, allowed, _ in (first, second)
    ]
    if None not in values:
        raise sc.fail(
            where, second[0], f"give {first[0]} or {second[0]}, not both", table[second[0]]
        )
    for v, (_, _, factor) in zip(values, (first, second), strict=True):
        if v is not None:
            return v * factor
    if default is sc.MISSING:
        raise sc.fail(where, first[0], f"missing required key (or {second[0]})")
    return default


def _angles(t: dict, z_s: int, z_r: int) -> tuple:
    """``planets`` (equally spaced) or ``planet_angles_deg``, the assembly condition checked."""
    if ("planets" in t) == ("planet_angles_deg" in t):
        raise sc.fail(
            "planetary",
            "planets",
            "give planets (equally spaced) or planet_angles_deg, one of them"
            + (", not both" if "planets" in t else ""),
        )
    if "planets" in t:
        n = sc.number(t, "planets", "planetary", allowed="[1, 64]", integer=True)
        psi = 2 * math.pi * np.arange(n) / n
        key, shown = "planets", t["planets"]
    else:
        deg = sc.number_list(
            t, "planet_angles_deg", "planetary", min_length=1, allowed="[-360, 360]"
        )
        psi = np.radians(deg)
        key, shown = "planet_angles_deg", t["planet_angles_deg"]
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


def _roles(t: dict) -> tuple:
    names = [m.lower() for m in Central.__members__]
    fixed = sc.choice(t, "fixed", "planetary", names)
    driver = sc.choice(t, "input", "planetary", names)
    if driver == fixed:
        raise sc.fail(
            "planetary",
            "input",
            f"is the fixed member (allowed: another of {', '.join(names)})",
            driver,
        )
    out = next(n for n in names if n not in (fixed, driver))
    return tuple(Central[n.upper()] for n in (fixed, driver, out))


def _pin_errors(t: dict, key: str, n: int) -> tuple:
    v = sc.number_list(t, key, "planetary", [0.0] * n, allowed="[-1e+04, 1e+04]")
    if len(v) != n:
        raise sc.fail("planetary", key, f"must hold one value per planet ({n})", t[key])
    return tuple(x * 1e-6 for x in v)


def _eccentricities(t: dict) -> tuple:
    """``<member>_eccentricity_um`` and ``<member>_eccentricity_phase_deg`` of the sun, ring and
    carrier, in SI as :class:`jaxgear.planetary.Eccentricities` takes them (sun, sun_phase, ring,
    ring_phase, carrier, carrier_phase); a phase without its amplitude is refused."""
    out = []
    for m in ("sun", "ring", "carrier"):
        amp = sc.number(t, f"{m}_eccentricity_um", "planetary", 0.0, allowed="[0, 1e+04]")
        key = f"{m}_eccentricity_phase_deg"
        phase = sc.number(t, key, "planetary", 0.0, allowed="[-360, 360]")
        if key in t and f"{m}_eccentricity_um" not in t:
            raise sc.fail("planetary", key, f"given without {m}_eccentricity_um (its amplitude)",
                          t[key])
        out += [amp * 1e-6, math.radians(phase)]
    return tuple(out)


def _per_planet(t: dict, key: str, n: int, scale: float, allowed: str) -> tuple:
    """A list of one value per planet (0 by default), times ``scale`` (to SI)."""
    v = sc.number_list(t, key, "planetary", [0.0] * n, length=n, allowed=allowed)
    return tuple(x * scale for x in v)


def _with_amplitude(t: dict, amp_key: str, phase_key: str) -> None:
    if phase_key in t and amp_key not in t:
        raise sc.fail("planetary", phase_key, f"given without {amp_key} (its amplitude)",
                      t[phase_key])


def _planet_runout(t: dict, n: int) -> tuple:
    """``planet_runout_um`` and ``planet_runout_phase_deg``, one per planet, in SI (m, rad)."""
    _with_amplitude(t, "planet_runout_um", "planet_runout_phase_deg")
    return (_per_planet(t, "planet_runout_um", n, 1e-6, "[0, 1e+04]"),
            _per_planet(t, "planet_runout_phase_deg", n, math.pi / 180, "[-360, 360]"))


def _unbalances(t: dict, n: int) -> tuple:
    """``<member>_unbalance_g_mm`` and ``<member>_unbalance_phase_deg`` of the sun, ring,
    carrier (one value each) and the planets (one per planet), in SI as
    :class:`jaxgear.planetary.Unbalances` takes them (kg m, rad)."""
    out = []
    for m in MEMBERS:
        amp_key, phase_key = f"{m}_unbalance_g_mm", f"{m}_unbalance_phase_deg"
        _with_amplitude(t, amp_key, phase_key)
        out += [sc.number(t, amp_key, "planetary", 0.0, allowed="[0, 1e+09]") * 1e-6,
                math.radians(sc.number(t, phase_key, "planetary", 0.0, allowed="[-360, 360]"))]
    _with_amplitude(t, "planet_unbalance_g_mm", "planet_unbalance_phase_deg")
    out += [_per_planet(t, "planet_unbalance_g_mm", n, 1e-6, "[0, 1e+09]"),
            _per_planet(t, "planet_unbalance_phase_deg", n, math.pi / 180, "[-360, 360]")]
    return tuple(out)


def _refuse(t: dict, keys, why: str) -> None:
    for key in keys:
        if key in t:
            raise sc.fail("planetary", key, why, t[key])


def _given_stiffness(t: dict, required: bool) -> GivenMeshStiffness | None:
    keys = ("sun_mesh_stiffness_N_per_um", "ring_mesh_stiffness_N_per_um")
    if not required and not any(k in t for k in keys):
        return None
    vals = [sc.number(t, k, "planetary", allowed=MESH_STIFFNESS_N_PER_UM) * 1e6 for k in keys]
    return GivenMeshStiffness(*vals)


def parse_planetary(data: dict, base: dict, gears: dict, index: dict) -> Case:
    """Validate ``[planetary]`` and build the stage's :class:`Case` (:class:`PlanetaryForm`).

    Args:
        data: the parsed file; ``base``: the train fields already parsed (``name``, material,
            mesh settings, modifications, operating torque and speed: :class:`Case` keywords);
        gears: the ``[[gears]]`` (name → parsed gear, as :func:`jaxgear.io._train_file._gear`
            gives it), ``{}`` in the lumped form; index: name → position.

    Raises:
        SchemaError: one line, in the file's units (module docstring).
    """
    t = sc.subtable(data, "planetary", "", PLANETARY_KEYS, required=True)
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
    tables = {
        m: sc.subtable(
            t, m, "planetary", MEMBER_KEYS.get(m, CENTRAL_KEYS), required=True
        )
        for m in (*MEMBERS, "planet")
    }
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
        if given is not None and "mesh_stiffness" in t:
            raise sc.fail(
                "planetary",
                "mesh_stiffness",
                "give mesh_stiffness or the two *_mesh_stiffness_N_per_um, not both",
                t["mesh_stiffness"],
            )
        mesh_k = (
            given
            or MESH_STIFFNESS[
                sc.choice(t, "mesh_stiffness", "planetary", tuple(MESH_STIFFNESS), "iso6336")
            ]()
        )
        a_w = geometry.center_distance
        pairs = (geometry.sun_planet, geometry.planet_ring)
        # the gears' helix_angle_deg has no hand: the planets are taken right-hand
        helix = abs(float(geometry.sun_planet.base_helix_angle))
        width = float(gears[names[1]]["member"].face_width)
    else:
        _refuse(t, GEAR_FORM_KEYS, "allowed only with [[gears]] (the gear form)")
        z_s = sc.number(t, "sun_teeth", "planetary", allowed="[3, 10000]", integer=True)
        z_r = sc.number(
            t,
            "ring_teeth",
            "planetary",
            allowed=f"[{z_s + 2 * MIN_PLANET_TEETH}, 10000]",
            integer=True,
            note=f" (sun_teeth + 2 × {MIN_PLANET_TEETH}: planets of (ring_teeth − sun_teeth)/2 "
            f">= {MIN_PLANET_TEETH} teeth)",
        )
        z_p = None
        radii = dict.fromkeys((*MEMBERS, "planet"))
        alphas = tuple(
            math.radians(sc.number(t, k, "planetary", allowed=PRESSURE_ANGLE_DEG,
                                   note=" (deg, operating transverse)"))
            for k in ("sun_pressure_angle_deg", "ring_pressure_angle_deg")
        )
        mesh_k = _given_stiffness(t, required=True)
        names, pairs, a_w, ring_root = (), (), None, None
        helix = math.radians(
            sc.number(t, "helix_angle_deg", "planetary", 0.0, allowed="(-90, 90)")
        )
        width = sc.number(t, "face_width_mm", "planetary", 0.0, allowed="[0, 1e+05]") * 1e-3
    psi = _angles(t, z_s, z_r)
    ring_model = parse_ring_model(tables["ring"], z_r, ring_root)
    members = {m: _central(tables[m], m, radii[m]) for m in MEMBERS}
    members["planet"] = _planet(tables["planet"], radii["planet"])
    if a_w is None:
        a_w = float(members["carrier"].base_radius)
    _check_held(tables[fixed.name.lower()], members[fixed.name.lower()], fixed.name.lower())
    if not gears:
        _check_lumped_radii(members, alphas)
    _check_spacing(t, psi, a_w, float(geometry.sun_planet.tip_radii[1]) if gears
                   else float(members["planet"].base_radius), "tip" if gears else "base")
    n = len(psi)
    spec = PlanetarySpec(
        teeth=(z_s, z_p, z_r),
        planet_angles=psi,
        fixed=fixed,
        input=driver,
        output=output,
        members=members,
        pressure_angles=alphas,
        mesh_stiffness=mesh_k,
        tangential_pin_errors=_pin_errors(t, "tangential_pin_errors_um", n),
        radial_pin_errors=_pin_errors(t, "radial_pin_errors_um", n),
        eccentricities=_eccentricities(t),
        planet_runout=_planet_runout(t, n),
        unbalances=_unbalances(t, n),
        center_distance=a_w,
        ring_model=ring_model,
        helix_angle=helix,
        face_width=width,
        mesh_tilt_stiffness=tuple(
            sc.number(t, k, "planetary", None, allowed="[0, 1e+15]") for k in MESH_TILT_KEYS
        ),
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


def _housing_seat(data: dict, t: dict) -> int:
    """``[planetary] housing_seat``: the seat of ``[housing]`` the held member is bolted to
    (default 0); refused without a ``[housing]``, or past its seats (a box: two, its end walls'
    bores round the axis; a mesh file: its ``[[housing.seats]]``)."""
    if "housing" not in data:
        if "housing_seat" in t:
            raise sc.fail("planetary", "housing_seat", "allowed only with a [housing]",
                          t["housing_seat"])
        return 0
    h = data["housing"]
    n = len(h.get("seats", [])) if isinstance(h, dict) and "mesh_file" in h else 2
    return int(sc.number(t, "housing_seat", "planetary", 0, allowed=f"[0, {max(n - 1, 0)}]",
                         integer=True, note=" (a box: 0 its x- wall's bore, 1 its x+ wall's)"))


def _check_held(table: dict, member: PlanetaryMember, name: str) -> None:
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
    given = [k for k in ranges if k in table]
    if not given:
        raise sc.fail(where, "torsional_stiffness_Nm_per_rad", "missing: the fixed member needs "
                      "a torsional stiffness (its support), allowed >= "
                      f"{ranges['torsional_stiffness_Nm_per_rad'][0]} (or "
                      f"torsional_stiffness_N_per_um >= {MIN_SUPPORT_N_PER_UM:g})")
    lo, hi = ranges[given[0]]
    sc.number(table, given[0], where, allowed=f"[{lo}, {hi}]", note=note)


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


def _check_spacing(t: dict, psi: tuple, a: float, radius: float, which: str) -> None:
    """No two planets overlap: adjacent centres 2 a sin(Δψ/2) apart on the planet circle of
    radius a (m) at least twice the planets' ``which`` radius (m): their tip circles (the gear
    form) or base circles (the lumped form, which has no tip) must not intersect (one line
    naming ``planets`` or ``planet_angles_deg``, mm)."""
    if len(psi) < 2:
        return
    i, j, d = closest_planets(psi, a)
    if d >= 2.0 * radius:
        return
    key = "planets" if "planets" in t else "planet_angles_deg"
    most = max_planets(a, radius)
    hint = f"; allowed planets <= {most}" if most is not None else ""
    raise sc.fail(
        "planetary", key,
        f"planets {i + 1} and {j + 1} (at {math.degrees(psi[i]):.6g}° and "
        f"{math.degrees(psi[j]):.6g}°) overlap: their centres are {d * 1e3:.6g} mm apart on the "
        f"planet circle of radius {a * 1e3:.6g} mm, allowed >= 2 × the planet's {which} radius "
        f"= {2 * radius * 1e3:.6g} mm (their {which} circles must not intersect{hint})",
        t[key])


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


def _geometry(t: dict, gears: dict):
    """The stage's pairs from the gears ``[planetary]`` names (sun, planet external, ring
    internal; one module, pressure and helix angle), at ``center_distance_mm``."""
    names = []
    for role in ("sun", "planet", "ring"):
        key = f"{role}_gear"
        name = sc.string(t, key, "planetary")
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
    cd = sc.number(t, "center_distance_mm", "planetary", None, allowed="(0, 1e+06]")
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


def _check_center_distance(t: dict, g: list, cd: float) -> None:
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
            "ring's teeth jam)", t["center_distance_mm"])


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
