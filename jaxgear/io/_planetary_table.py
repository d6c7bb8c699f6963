"""A planetary stage in a case file: the ``[planetary]`` table (docs/guide/planetary.md, "Case
files"), in one of two forms.

**Gear form**: the sun, planet and ring are ``[[gears]]`` entries (the ring internal: ``teeth``
negative, ISO 21771), named by ``[planetary] sun_gear``, ``planet_gear``, ``ring_gear``; the base radii, the
operating pressure angles and the planet-circle radius come from their geometry
(:func:`jaxgear.planetary_geometry` at ``center_distance_mm``), the mesh stiffness from the gears
(ISO 6336-1 c_γα b, or the mean of the ``[mesh]`` stiffness model) or given.

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

Validated whole before any work, one line per error in the file's units: the assembly condition
((z_s + z_r) ψ_n/360° integer), the three members distinct, the fixed member held in rotation
(a torsional stiffness > 0), one pin error per planet, keys of one form only.
"""

from __future__ import annotations

import abc
import dataclasses
import math

import numpy as np
from fem_prep import schema as sc

from .._internal import InternalGearPair, planetary_geometry
from .._planetary import Central, PlanetaryMember, PlanetaryStage, check_assembly, speed_ratio
from .._quasi_static import quasi_static
from .._stiffness import iso6336_mesh_stiffness
from .._stiffness_models import ISO6336
from ._case import Case, CaseForm, PairForm, TrainForm

__all__ = [
    "GivenMeshStiffness",
    "InternalMeshForm",
    "ISO6336MeshStiffness",
    "MeanMeshStiffness",
    "PlanetaryForm",
    "PlanetaryMeshStiffness",
    "PlanetarySpec",
    "is_planetary",
    "parse_planetary",
]

MEMBERS = ("sun", "ring", "carrier")
#: keys of [planetary] (both forms; a key of the other form is refused in one line)
PLANETARY_KEYS = {
    "sun_gear",
    "planet_gear",
    "ring_gear",
    "sun",
    "planet",
    "ring",
    "carrier",
    "planets",
    "planet_angles_deg",
    "fixed",
    "input",
    "center_distance_mm",
    "mesh_stiffness",
    "sun_mesh_stiffness_N_per_um",
    "ring_mesh_stiffness_N_per_um",
    "tangential_pin_errors_um",
    "radial_pin_errors_um",
    "sun_teeth",
    "ring_teeth",
    "sun_pressure_angle_deg",
    "ring_pressure_angle_deg",
}
GEAR_FORM_KEYS = ("sun_gear", "planet_gear", "ring_gear", "center_distance_mm", "mesh_stiffness")
LUMPED_FORM_KEYS = ("sun_teeth", "ring_teeth", "sun_pressure_angle_deg", "ring_pressure_angle_deg")
_BODY_KEYS = {
    "mass_kg",
    "inertia_kg_m2",
    "inertia_over_r2_kg",
    "base_radius_mm",
}
CENTRAL_KEYS = _BODY_KEYS | {
    "bearing_N_per_um",
    "torsional_stiffness_Nm_per_rad",
    "torsional_stiffness_N_per_um",
}
PLANET_KEYS = _BODY_KEYS | {"pin_radial_N_per_um", "pin_tangential_N_per_um"}
#: a stiffness that holds a member (N/m on u = r θ) relative to the stiffest mesh
HOLD_FACTOR = 1e3


def is_planetary(data) -> bool:
    """Whether a parsed case file is a planetary stage (a ``[planetary]`` table)."""
    return isinstance(data, dict) and "planetary" in data


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
    """Given in the case file (``sun_mesh_stiffness_N_per_um``, ``ring_mesh_stiffness_N_per_um``)."""

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
    stiffness, each mesh at its mean planet load (the rigid mesh, exact contact)."""

    def values(self, case):
        out = []
        for k in range(len(case.pairs)):
            one = case.mesh_case(k)
            r = quasi_static(
                one.mesh_model(), one.modifications, one.torque, positions_per_pitch=16
            )
            out.append(float(np.mean(np.asarray(r.mesh_stiffness))))
        return tuple(out)

    def summary(self):
        return "mean of the [mesh] stiffness model"


_MESH_STIFFNESS = {"iso6336": ISO6336MeshStiffness, "mean": MeanMeshStiffness}


# -- the stage as the file gives it --------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class PlanetarySpec:
    """A validated ``[planetary]`` table in SI units.

    Attributes:
        teeth: (z_s, z_p, z_r), the ring's positive (z_p None in the lumped form).
        planet_angles: ψ_n (rad), (N,), planet 1 first.
        fixed, input, output: the :class:`~jaxgear.Central` members.
        members: {"sun", "ring", "carrier", "planet": :class:`~jaxgear.PlanetaryMember`}, the
            base radii of the gear form from the gears.
        pressure_angles: (α_s, α_r) operating transverse pressure angles (rad).
        mesh_stiffness: a :class:`PlanetaryMeshStiffness`.
        tangential_pin_errors, radial_pin_errors: per planet (m), (N,).
        center_distance: a_w (m), the planet-circle radius.
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

    @property
    def n_planets(self) -> int:
        return len(self.planet_angles)

    def tooth_count(self, member: Central) -> float:
        """z of the Willis torque balance: z_s, z_r, −(z_s + z_r) for the carrier."""
        z_s, _, z_r = self.teeth
        return (z_s, z_r, -(z_s + z_r))[member]

    def speeds(self, input_speed: float) -> dict:
        """Each central member's speed (rad/s, fixed frame) and the planet's (absolute and
        relative to the carrier), the input at ``input_speed``, the fixed member at rest
        (Willis: z_s ω_s + z_r ω_r = (z_s + z_r) ω_c)."""
        z_s, z_p, z_r = self.teeth
        a = np.array([[z_s, z_r, -(z_s + z_r)], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
        a[1, self.fixed], a[2, self.input] = 1.0, 1.0
        w = np.linalg.solve(a, [0.0, 0.0, input_speed])
        w[self.fixed] = 0.0
        out = {m.name.lower(): float(w[m]) for m in Central}
        if z_p is not None:
            rel = -(w[Central.SUN] - w[Central.CARRIER]) * z_s / z_p
            out["planet_relative"] = float(rel)
            out["planet"] = float(w[Central.CARRIER] + rel)
        return out

    def torques(self, input_torque: float) -> dict:
        """Each central member's torque (N·m), the input's ``input_torque``: T_m = T_in z_m /
        z_in (lossless; their sum 0)."""
        z_in = self.tooth_count(self.input)
        return {m.name.lower(): input_torque * self.tooth_count(m) / z_in for m in Central}

    def ratio(self) -> float:
        """The Willis speed ratio ω_input/ω_output (:func:`jaxgear.speed_ratio`)."""
        z_s, _, z_r = self.teeth
        return speed_ratio(z_s, z_r, self.fixed, self.input, self.output)

    def mesh_frequency(self, input_speed: float) -> float:
        """The mesh frequency (Hz) in the carrier frame, z_s |ω_s − ω_c|/(2π)."""
        w = self.speeds(input_speed)
        return self.teeth[0] * abs(w["sun"] - w["carrier"]) / (2 * math.pi)

    def stage(self, case: Case) -> PlanetaryStage:
        """The lumped stage (:class:`~jaxgear.PlanetaryStage`) of the case: the members as
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
        """The stage of the load-sharing solve (:func:`jaxgear.load_sharing` loads the sun):
        the sun free in rotation, the ring and the carrier held (HOLD_FACTOR × the stiffest
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


@dataclasses.dataclass(frozen=True)
class PlanetaryForm(CaseForm):
    """A planetary case file (``[planetary]``): its stage (:class:`PlanetarySpec`); the gear
    form's two meshes, ``sun-planet`` (the external pair, the sun driving) and ``planet-ring``
    (the :class:`~jaxgear.InternalGearPair`, the planet driving), named by the gears; each as a
    one-mesh case at the mean planet load, at its speed relative to the carrier. ``jaxgear run``
    writes its stage outputs (``jaxgear/cli/_planetary_run.py``)."""

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
    )


def _planet(table: dict, base_radius: float | None) -> PlanetaryMember:
    where = "planetary.planet"
    r = _base_radius(table, where, base_radius)
    mass, inertia = _body(table, where, r)
    pin = [
        sc.number(table, key, where, allowed="(0, 1e+09]") * 1e6
        for key in ("pin_radial_N_per_um", "pin_tangential_N_per_um")
    ]
    return PlanetaryMember(mass=mass, polar_inertia=inertia, base_radius=r, bearing_stiffness=pin)


def _base_radius(table: dict, where: str, from_gears: float | None) -> float:
    if from_gears is None:
        return sc.number(table, "base_radius_mm", where, allowed="(0, 1e+05]") * 1e-3
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
    mass = sc.number(table, "mass_kg", where, allowed="(0, 1e+07]")
    inertia = _either(
        table,
        where,
        ("inertia_kg_m2", "(0, 1e+09]", 1.0),
        ("inertia_over_r2_kg", "(0, 1e+09]", r**2),
    )
    return mass, inertia


def _either(table: dict, where: str, first: tuple, second: tuple, default=sc.MISSING) -> float:
    """One of two keys (key, allowed, SI factor) of one quantity, or ``default``."""
    values = [sc.number(table, key, where, None, allowed=allowed) for key, allowed, _ in (first, second)]
    if None not in values:
        raise sc.fail(where, second[0], f"give {first[0]} or {second[0]}, not both", table[second[0]])
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
        raise sc.fail("planetary", "input", f"is the fixed member (allowed: another of {', '.join(names)})", driver)
    out = next(n for n in names if n not in (fixed, driver))
    return tuple(Central[n.upper()] for n in (fixed, driver, out))


def _pin_errors(t: dict, key: str, n: int) -> tuple:
    v = sc.number_list(t, key, "planetary", [0.0] * n, allowed="[-1e+04, 1e+04]")
    if len(v) != n:
        raise sc.fail("planetary", key, f"must hold one value per planet ({n})", t[key])
    return tuple(x * 1e-6 for x in v)


def _refuse(t: dict, keys, why: str) -> None:
    for key in keys:
        if key in t:
            raise sc.fail("planetary", key, why, t[key])


def _given_stiffness(t: dict, required: bool) -> GivenMeshStiffness | None:
    keys = ("sun_mesh_stiffness_N_per_um", "ring_mesh_stiffness_N_per_um")
    if not required and not any(k in t for k in keys):
        return None
    vals = [sc.number(t, k, "planetary", allowed="(0, 1e+09]") * 1e6 for k in keys]
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
            raise sc.fail("operating", key, "not in a planetary case (allowed: torque_Nm on the input member)", op[key])
    fixed, driver, output = _roles(t)
    tables = {
        m: sc.subtable(t, m, "planetary", PLANET_KEYS if m == "planet" else CENTRAL_KEYS, required=True)
        for m in (*MEMBERS, "planet")
    }
    if gears:
        _refuse(t, LUMPED_FORM_KEYS, "allowed only in the lumped form (no [[gears]]): the gears give it")
        geometry, names, z_p = _geometry(t, gears)
        z_s, z_r = geometry.sun_planet.pinion.teeth, -geometry.planet_ring.gear.teeth
        radii = {
            "sun": geometry.sun_planet.base_radii[0],
            "planet": geometry.sun_planet.base_radii[1],
            "ring": geometry.planet_ring.base_radii[1],
            "carrier": geometry.center_distance,
        }
        alphas = (geometry.sun_pressure_angle, geometry.ring_pressure_angle)
        given = _given_stiffness(t, required=False)
        if given is not None and "mesh_stiffness" in t:
            raise sc.fail("planetary", "mesh_stiffness", "give mesh_stiffness or the two *_mesh_stiffness_N_per_um, not both", t["mesh_stiffness"])
        mesh_k = given or _MESH_STIFFNESS[
            sc.choice(t, "mesh_stiffness", "planetary", tuple(_MESH_STIFFNESS), "iso6336")
        ]()
        a_w = geometry.center_distance
        pairs = (geometry.sun_planet, geometry.planet_ring)
    else:
        _refuse(t, GEAR_FORM_KEYS, "allowed only with [[gears]] (the gear form)")
        z_s = sc.number(t, "sun_teeth", "planetary", allowed="[3, 10000]", integer=True)
        z_r = sc.number(t, "ring_teeth", "planetary", allowed=f"[{z_s + 1}, 10000]", integer=True, note=" (above sun_teeth)")
        z_p = None
        radii = dict.fromkeys((*MEMBERS, "planet"))
        alphas = tuple(
            math.radians(sc.number(t, k, "planetary", allowed="(0, 90)"))
            for k in ("sun_pressure_angle_deg", "ring_pressure_angle_deg")
        )
        mesh_k = _given_stiffness(t, required=True)
        names, pairs, a_w = (), (), None
    psi = _angles(t, z_s, z_r)
    members = {m: _central(tables[m], m, radii[m]) for m in MEMBERS}
    members["planet"] = _planet(tables["planet"], radii["planet"])
    if a_w is None:
        a_w = float(members["carrier"].base_radius)
    held = members[fixed.name.lower()]
    if float(held.torsional_stiffness) <= 0:
        raise sc.fail(
            f"planetary.{fixed.name.lower()}",
            "torsional_stiffness_Nm_per_rad",
            "missing: the fixed member needs a torsional stiffness > 0 (its support; or "
            "torsional_stiffness_N_per_um)",
        )
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
        center_distance=a_w,
    )
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
            raise sc.fail("planetary", key, f"names the {('sun', 'planet')[names.index(name)]} already (allowed: three different gears)", name)
        internal = gears[name]["member"].teeth < 0
        if internal != (role == "ring"):
            what = "an internal gear (teeth < 0)" if role == "ring" else "an external gear (teeth > 0)"
            raise sc.fail("planetary", key, f"must name {what}: [gears.{name}] teeth = {gears[name]['member'].teeth}", name)
        names.append(name)
    g = [gears[n] for n in names]
    for key, label in (("module_mm", "normal_module_mm"), ("alpha_deg", "normal_pressure_angle_deg"), ("beta_deg", "helix_angle_deg")):
        if len({x[key] for x in g}) > 1:
            raise sc.SchemaError(
                f"[planetary]: [gears.{names[0]}], [gears.{names[1]}], [gears.{names[2]}] "
                f"{label} = {', '.join(sc.fmt(x[key]) for x in g)} differ (a stage's gears share it)"
            )
    cd = sc.number(t, "center_distance_mm", "planetary", None, allowed="(0, 1e+06]")
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


def check_internal_stiffness(case: Case, where: str) -> None:
    """The ``[mesh]`` stiffness model must have an internal-gear form when a mesh is internal
    (``uniform`` or ``iso6336``), refused in one line before any work."""
    if any(isinstance(p, InternalGearPair) for p in case.pairs) and not case.stiffness.internal_teeth:
        raise sc.fail(
            "mesh",
            "stiffness",
            f"{case.stiffness.name!r} has no internal-gear form ({where} has an internal gear); "
            "allowed 'uniform' or 'iso6336'",
            case.stiffness.name,
        )


def planetary_mesh_settings(data: dict, mesh: dict) -> dict:
    """A planetary case's mesh settings: ``[mesh]``'s, the stiffness model ISO 6336 unless the
    file names one (the default FE model has no internal-gear form)."""
    if "stiffness" not in data.get("mesh", {}):
        return {**mesh, "stiffness": ISO6336()}
    return mesh
