"""The case file's typed sections (``jaxgear.io._sections``): ``[whine]``, ``[acoustics]``,
``[lubricant]``, ``[rating]``, ``[pair]``, ``[pinion]``/``[gear]``, ``[material]``,
``[operating]`` (a pair's, a train's, a planetary stage's), ``[modifications]``, ``[robust]``,
``[optimise]``, ``[rating.spectrum]``, a sizing spec's ``[pareto]``, ``[lubricant]``'s micropitting keys and the ``[[gears]]`` and ``[[meshes]]`` entries given mutated values (numbers where tables are,
strings where numbers are, negative, non-finite and huge values, unknown keys) are refused in the one line the
command line prints, never a ``TypeError``, ``KeyError`` or pydantic's report; a number key's
message is the one :func:`fem_prep.checks.number` (the hand-written check, a separate
implementation) writes for the same value; the case reader keeps the typed section on the case.
Load only: nothing runs."""

from __future__ import annotations

import copy
import pathlib
import typing
import warnings

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import jaxgear.io as jio
from fem_prep import checks as sc
from jaxgear.io import (
    AcousticsSection,
    LubricantSection,
    Range,
    RatingSection,
    WhineSection,
    range_of,
)
from jaxgear.io._case_file import (
    MaterialSection,
    MeshSection,
    OperatingSection,
    PairMemberSection,
    PairSection,
)
from jaxgear.io._gearbox_file import GearboxOperating, StageEntry
from jaxgear.io._housing_table import FootEntry, HousingSection, SeatEntry
from jaxgear.io._micropitting_table import MicropittingKeys
from jaxgear.io._modifications_table import ModificationsSection
from jaxgear.io._optimise_table import OptimiseSection
from jaxgear.io._pareto_table import ParetoSection, parse_pareto
from jaxgear.io._planetary_deviations_table import (
    MemberDeviations,
    PlanetDeviations,
    StageDeviationsSection,
)
from jaxgear.io._planetary_table import PlanetarySection
from jaxgear.io._robust_table import RobustSection
from jaxgear.io._scene_table import (
    BearingSection,
    BodySection,
    DampingSection,
    IntegrationSection,
    SceneSection,
    ShaftSection,
)
from jaxgear.io._spectrum_table import SpectrumSection
from jaxgear.io._train_file import GearSection, MeshEntry, PlanetaryOperating, TrainOperating
from jaxgear.io._train_scene import TrainBodySection, TrainSceneSection, TrainShaftSection

ROOT = pathlib.Path(__file__).resolve().parents[1]

#: a valid table of each section (the module docstrings' samples, trimmed)
BASES = {
    WhineSection: {"speed_min_rad_s": 50.0, "speed_max_rad_s": 1500.0, "speeds": 48,
                   "harmonics": 16},
    AcousticsSection: {"method": "bem", "band_Hz": [100.0, 4000.0], "frequencies": 24,
                       "microphones": [{"name": "front", "position_mm": [150.0, -1000.0, 80.0]}]},
    LubricantSection: {"viscosity_40C_mm2_s": 316.0, "viscosity_100C_mm2_s": 22.2,
                       "density_kg_m3": 902.0, "pressure_viscosity_per_GPa": 71.05,
                       "oil_temperature_C": 75.0, "roughness_Ra_um": [0.6, 0.6],
                       "fzg_load_stage": 10},
    RatingSection: {"life_h": 175200.0, "viscosity_40C_mm2_s": 220.0,
                    "roughness_Rz_flank_um": 4.8, "roughness_Rz_root_um": 20.0,
                    "accuracy_grade": 6, "K_v": 1.1},
    PairSection: {"normal_module_mm": 1.5, "normal_pressure_angle_deg": 25.0,
                  "helix_angle_deg": 12.0},
    PairMemberSection: {"teeth": 45, "profile_shift": 0.341, "face_width_mm": 11.5,
                        "web_thickness_mm": 4.0, "rim_thickness_mm": 5.0},
    MaterialSection: {"youngs_modulus_GPa": 206.0, "poisson_ratio": 0.3,
                      "density_kg_m3": 7830.0, "sigma_H_lim_MPa": 1500.0,
                      "sigma_F_lim_MPa": [430.0, 500.0], "treatment": "through_hardened",
                      "brinell_hardness_HB": {"input": 200.0, "output": 240.0},
                      "proof_stress_MPa": 800.0, "designation": ["42CrMo4", "34CrNiMo6"],
                      "surface_hardness_HV": 300.0},
    OperatingSection: {"torque_Nm": 80.0, "speed_rad_s": 100.0},
    DampingSection: {"model": "composite", "mesh_ratio": 0.07, "structure_ratio": 0.01},
    IntegrationSection: {"solver": "newmark", "contact": "exact", "steps_per_period": 64,
                         "periods": 40, "keep_periods": 4, "rtol": 1e-6, "atol": 1e-6,
                         "rotating_frame": False, "modal_basis": False},
    MeshSection: {"stiffness": "fe2d", "slices": 40, "positions_per_pitch": 64,
                  "smooth_width_um": 0.1, "fe2d_size_um": 500.0, "foundation": "sainsot",
                  "extended_contact": False},
    TrainOperating: {"torque_Nm": 80.0, "loads": [{"gear": "idler", "torque_Nm": -5.0}]},
    PlanetaryOperating: {"torque_Nm": 1e6, "speed_rad_s": 1.2},
    GearSection: {"name": "ring", "teeth": -99, "normal_module_mm": 10.0,
                  "normal_pressure_angle_deg": 20.0, "face_width_mm": 100.0, "hand": "left"},
    ModificationsSection: {"tip_relief": {"depth_um": 10.0, "shape": "parabolic"},
                           "crowning": {"depth_um": 5.0},
                           "gear": {"helix_slope": {"deviation_um": -3.0}}},
    MeshEntry: {"driving": "input", "driven": "idler", "angle_deg": 0.0},
    RobustSection: {"grade": 6, "samples": 100, "members": ["pinion"],
                    "speeds_rad_s": [100.0, 200.0], "revolutions": "hunting"},
    OptimiseSection: {"objective": "robust_te_rms", "vars": ["tip_relief.depth", "tip_relief.extent"],
                      "torques": [40.0, 120.0, 5], "reduce": "quantile", "quantile": 0.9,
                      "method": "adam", "max_iterations": 50,
                      "bounds": {"tip_relief.depth": [0.0, 2.5]}},
    SpectrumSection: {"torque_Nm": [80.0, 40.0], "speed_rpm": [3000.0, 3000.0],
                      "hours": [5e3, 1.5e4]},
    ParetoSection: {"minimise": ["mass_kg", "volume_m3"], "maximise": ["least_margin"],
                    "choose": "volume_m3"},
    MicropittingKeys: {"micropitting_load_stage": 8},
    # a planetary stage (Lin & Parker's lumped form), a gearbox's tables, a housing
    PlanetarySection: {
        "sun_teeth": 28, "ring_teeth": 62, "sun_pressure_angle_deg": 24.6,
        "ring_pressure_angle_deg": 24.6, "sun_mesh_stiffness_N_per_um": 500.0,
        "ring_mesh_stiffness_N_per_um": 500.0, "planets": 3, "fixed": "ring",
        "input": "carrier", "sun_eccentricity_um": 10.0, "tangential_pin_errors_um": [5.0, 0.0, 0.0],
        "sun": {"mass_kg": 0.4, "inertia_over_r2_kg": 0.39, "base_radius_mm": 24.0,
                "bearing_N_per_um": 100.0},
        "ring": {"mass_kg": 2.35, "inertia_over_r2_kg": 3.0, "base_radius_mm": 60.0,
                 "torsional_stiffness_Nm_per_rad": 1e9},
        "carrier": {"mass_kg": 5.43, "inertia_over_r2_kg": 6.29, "base_radius_mm": 45.0},
        "planet": {"mass_kg": 0.66, "inertia_over_r2_kg": 0.61, "base_radius_mm": 15.0,
                   "pin_radial_N_per_um": 100.0, "pin_tangential_N_per_um": 100.0}},
    GearboxOperating: {"torque_Nm": 5000.0, "speed_rad_s": 100.0},
    StageEntry: {"case": "two-stage-gearbox-pair.toml", "input": "gear",
                 "shaft_Nm_per_rad": 5e5, "pinion_inertia_kg_m2": 5.2e-3,
                 "gear_inertia_kg_m2": 0.0165, "mesh_stiffness_N_per_um": 1792.0},
    HousingSection: {"width_mm": 250.0, "height_mm": 160.0, "wall_thickness_mm": 10.0,
                     "layers": 2, "mesher": "structured", "element": "tet4",
                     "cutoff_Hz": 3000.0, "loss_factor": 0.02,
                     "points_mm": {"top": [100.0, 80.0, 0.0]}},
    SeatEntry: {"centre_mm": [0.0, 0.0, 100.0], "axis": [1.0, 0.0, 0.0], "diameter_mm": 50.0,
                "width_mm": 10.0, "name": "left"},
    FootEntry: {"x_mm": [0.0, 30.0], "y_mm": [0.0, 30.0]},
    StageDeviationsSection: {"grade": 6, "seed": 3, "revolutions": 2, "positions_per_pitch": 4,
                             "sun": {"profile_slope_um": 1.0}, "ring": {"helix_form_um": -0.5}},
    MemberDeviations: {"pitch_um": [1.0, -1.0, 0.0], "profile_slope_um": 1.0,
                       "helix_form_um": [0.5, 0.5, 0.5]},
    PlanetDeviations: {"sun_flank": {"pitch_um": [1.0, -1.0, 0.0]},
                       "ring_flank": {"profile_form_um": 1.0}},
}
#: a lumped 3D shaft of 100 mm, its gear at 0.5 mm, on two bearings 1 mm apart (1 % of its
#: length: a longer shaft refuses them in words that name its length_mm)
_SHAFT = {"length_mm": 100.0, "diameter_mm": 30.0, "gear_position_mm": 0.5, "elements": 4,
          "torque_position_mm": 0.0,
          "bearings": [{"position_mm": 0.0, "radial_N_per_um": 200.0, "axial_N_per_um": 100.0,
                        "tilt_Nm_per_rad": 0.0},
                       {"position_mm": 1.0, "radial_N_per_um": 200.0}]}
_TRAIN_SHAFT = {k: v for k, v in _SHAFT.items() if k != "gear_position_mm"} | {
    "shaft": "input", "gear_positions_mm": {"input": 0.5}}
BASES |= {  # the [scene] tables (a pair's, a train's)
    SceneSection: {"model": "lumped3d", "pinion_shaft": _SHAFT, "gear_shaft": _SHAFT,
                   "pinion_mass_kg": 1.5, "gear_mass_kg": 2.5, "pinion_inertia_kg_m2": 7e-4,
                   "gear_inertia_kg_m2": 5e-3, "gear_body": {"body": "accessory-wheel"},
                   "damping": {"model": "modal", "ratio": 0.05}, "integration": {"periods": 8}},
    ShaftSection: _SHAFT,
    BearingSection: {"position_mm": 0.0, "radial_N_per_um": 200.0, "axial_N_per_um": 100.0,
                     "tilt_Nm_per_rad": 0.0,
                     "damping_matrix_SI": [[300.0, 0, 0, 0, 0, 0], [0, 300.0, 0, 0, 0, 0]] + [
                         [0] * 6] * 4},
    BodySection: {"body": "accessory-wheel"},
    TrainSceneSection: {"model": "lumped3d", "inertias_kg_m2": {"input": 1e-3},
                        "masses_kg": {"input": 1.0}, "shafts": [_TRAIN_SHAFT],
                        "bodies": {"input": {"body": "accessory-wheel"}},
                        "damping": {"model": "none"}, "integration": {"steps_per_period": 32}},
    TrainShaftSection: _TRAIN_SHAFT,
    TrainBodySection: {"body": "intermediate-shaft", "gears": ["wheel", "pinion"]},
}
SECTIONS = tuple(BASES)

VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.sampled_from([0, -1, 10**400, -(10**400), 1e308, 5e-324]),
    st.booleans(),
    st.text(max_size=6),
    st.lists(st.one_of(st.floats(), st.integers(), st.text(max_size=3)), max_size=4),
    st.dictionaries(st.text(max_size=4), st.integers(), max_size=2),
)


def _one_line(section, table, key: str) -> str | None:
    """Read ``table`` as ``section``: None when it reads, else its error's one line (which must
    be a SchemaError naming ``key``)."""
    try:
        section.read(table)
    except sc.SchemaError as err:
        msg = str(err)
        assert "\n" not in msg and msg.strip() == msg, msg
        assert "validation error" not in msg and "pydantic" not in msg, msg
        assert key in msg, (key, msg)
        return msg
    return None


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(pick=st.integers(min_value=0), key=st.integers(min_value=0), value=VALUES,
       unknown=st.booleans())
def test_mutated_tables_are_refused_in_one_line(pick, key, value, unknown):
    """One key of a valid table (or an unknown key) given any TOML value: the table reads, or
    one SchemaError line names the key."""
    section = SECTIONS[pick % len(SECTIONS)]
    table = copy.deepcopy(BASES[section])
    names = sorted(section.model_fields)
    name = "speed_mm_s" if unknown else names[key % len(names)]
    table[name] = value  # (RatingSection's "meshes" holds its mesh tables: not a file key)
    msg = _one_line(section, table, name)
    if unknown or name == "meshes":
        assert msg is not None and "unknown key" in msg


@pytest.mark.parametrize("section", SECTIONS, ids=lambda s: s.WHERE)
@pytest.mark.parametrize("value", [0.0, False, "x", [1.0]])
def test_a_table_given_as_a_value_is_one_line(section, value):
    msg = _one_line(section, value, section.WHERE.rpartition(".")[2])
    head, _, last = section.WHERE.rpartition(".")
    named = sc.key_path(head, last)  # a sub-table (an array's entry): named in its table
    assert msg.startswith(f"{named} = {sc.fmt(value)}: must be a table "
                          f"([{section.WHERE}]), not "), msg


def _number_fields():
    """(section, key, Range) of every scalar number key of the four sections."""
    out = []
    for section in SECTIONS:
        for key, info in section.model_fields.items():
            rng = range_of(info)
            one_of = any(type(m).__name__ == "Discriminator" for m in info.metadata) or (
                "Discriminator" in repr(info.annotation))
            words = (section, key) in {(RobustSection, "revolutions"),  # or "hunting"
                                       (IntegrationSection, "steps_per_period"),  # or "auto"
                                       (IntegrationSection, "periods"),
                                       (IntegrationSection, "modal_basis"),  # or false
                                       (StageEntry, "housing_seat"),  # its own words
                                       (StageDeviationsSection, "revolutions"),  # "hunting"
                                       # a series' keys: the other form than the base's bins
                                       (SpectrumSection, "series_step_s"),
                                       (SpectrumSection, "levels")}
            by_name = typing.get_origin(info.annotation) is dict  # a table of numbers by name
            if isinstance(rng, Range) and not rng.array and not one_of and not words and (
                    not by_name):
                out.append((section, key, rng))
    return out


NUMBER_FIELDS = _number_fields()


def _read(section, table):
    """``table`` read as ``section`` (a rating as a planetary stage's: every key it takes)."""
    if section is RatingSection:
        return RatingSection.of(table, (), planetary=True)
    return section.read(table)


def test_the_number_keys_are_found():
    keys = {k for _, k, _ in NUMBER_FIELDS}
    assert {"speeds", "frequencies", "viscosity_40C_mm2_s", "life_h", "K_v",
            "fzg_load_stage", "normal_module_mm", "face_width_mm", "youngs_modulus_GPa",
            "speed_rad_s", "clocking_deg"} <= keys
    assert len(NUMBER_FIELDS) >= 50


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(pick=st.integers(min_value=0), value=st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(2**1100), max_value=2**1100),
    st.sampled_from([0.5, 2.0, -0.0, 1e5, 1e6, 10**400, 48.0, 4.5]),
    st.booleans(), st.text(max_size=4), st.lists(st.integers(), max_size=2)))
def test_a_number_key_says_what_the_hand_written_check_says(pick, value):
    """A number key's refusal is word for word :func:`fem_prep.checks.number`'s for the same
    value and range (the check the sections replace, kept for the other tables)."""
    section, key, rng = NUMBER_FIELDS[pick % len(NUMBER_FIELDS)]
    table = copy.deepcopy(BASES[section]) | {key: value}
    try:
        sc.number(table, key, section.WHERE, allowed=rng.interval, integer=rng.integer,
                  note=rng.note)
    except sc.SchemaError as err:
        with pytest.raises(sc.SchemaError) as mine:
            _read(section, table)
        assert str(mine.value) == str(err)
        return
    try:  # the value is in range: the table reads, or a check of two keys refuses it
        _read(section, table)
    except sc.SchemaError as err:
        assert "\n" not in str(err) and key in str(err) or "out of range" in str(err), str(err)


def _same_words(section, key, rng, value):
    table = copy.deepcopy(BASES[section]) | {key: value}
    try:
        sc.number(table, key, section.WHERE, allowed=rng.interval, integer=rng.integer,
                  note=rng.note)
    except sc.SchemaError as err:
        with pytest.raises(sc.SchemaError) as mine:
            _read(section, table)
        assert str(mine.value) == str(err)
        return True
    return False


def test_every_number_key_says_what_the_hand_written_check_says():
    """Every number key of the four sections, each given the same wrong values: word for word
    :func:`fem_prep.checks.number`'s line."""
    wrong = (True, "x", [1.0], {"a": 1}, float("nan"), float("inf"), -1e300, 1e300, 10**400,
             -(2**80), 4.5, -1.0, 0)
    refused = sum(_same_words(section, key, rng, v) for section, key, rng in NUMBER_FIELDS
                  for v in wrong)
    assert refused >= 10 * len(NUMBER_FIELDS)  # most of them are wrong for every key


@pytest.mark.parametrize(("section", "change", "words"), [
    (WhineSection, {"speeds": 1}, "[whine] speeds = 1: out of range, allowed [2, 2000]"),
    (WhineSection, {"speeds": 48.0}, None),
    (WhineSection, {"speeds": 4.5}, "[whine] speeds = 4.5: must be an integer"),
    (WhineSection, {"speed": 48},
     ("[whine] unknown key 'speed' (did you mean 'speeds'?), allowed: harmonics, method, "
     "positions_per_period, sidebands, speed_max_rad_s, speed_min_rad_s, speeds")),
    (WhineSection, {"method": "fft"},
     "[whine] method = 'fft': allowed 'harmonic-balance', 'te-source', 'quasi-periodic'"),
    (WhineSection, {"speed_max_rad_s": 10.0},
     "[whine] speed_max_rad_s = 10: out of range, allowed > speed_min_rad_s = 50"),
    (AcousticsSection, {"microphones": 3},
     ("[acoustics] microphones = 3: must be an array of tables ([[acoustics.microphones]]), "
     "not a number")),
    (AcousticsSection, {"microphones": [{"position_mm": [1.0, 2.0]}]},
     "[acoustics.microphones[0]] position_mm = [1, 2]: must be an array of 3 numbers"),
    (AcousticsSection, {"microphones": [{"position_mm": [1.0, 2.0, 3.0], "x": 1}]},
     "[acoustics.microphones[0]] unknown key 'x', allowed: name, position_mm"),
    (AcousticsSection, {"microphones": [1.0]},
     ("[acoustics] 'microphones[0]' = 1: must be a table ([[acoustics.microphones]] entry), "
     "not a number")),
    (AcousticsSection, {"band_Hz": [100.0, float("nan")]},
     "[acoustics] band_Hz = [100, nan]: must be an array of finite numbers"),
    (LubricantSection, {"roughness_Ra_um": [0.6, -1.0]},
     "[lubricant] roughness_Ra_um = [0.6, -1]: element -1 out of range, allowed (0, 10]"),
    (LubricantSection, {"viscosity_40C_mm2_s": 1.0},
     ("[lubricant] viscosity_40C_mm2_s = 1: out of range, allowed [2, 100000] (Walther's "
     "equation, ASTM D341, holds from 2 mm²/s)")),
    (LubricantSection, {"friction_coefficient": 0.05, "lubricant_factor": 0.85},
     "[lubricant] lubricant_factor = 0.85: not read: friction_coefficient is given"),
    (RatingSection, {"K_v": 0.5}, "[rating] K_v = 0.5: out of range, allowed [1, 10]"),
    (RatingSection, {"edition": 2010},
     "[rating] edition = 2010: out of range, allowed [2006, 2019], the years 2006 or 2019"),
    (RatingSection, {"K_gamma": 1.2}, "[rating] unknown key 'K_gamma'"),
    (RatingSection, {"roughness_Rz_flank_um": {"pinion": -4.8}},
     "[rating] roughness_Rz_flank_um = { pinion = -4.8 }: element -4.8 out of range"),
    (PairSection, {"normal_pressure_angle_deg": 45.123456789},
     "[pair] normal_pressure_angle_deg = 45.1235: out of range, allowed [10, 40]"),
    (PairMemberSection, {"teeth": True}, ("[pinion] teeth = true: must be an integer, not a "
     "boolean")),
    (PairMemberSection, {"dedendum_coeff": 0.2},
     ("[pinion] dedendum_coeff = 0.2: out of range, allowed > 0.25 (above the default "
     "fillet_radius_coeff; or give a smaller fillet_radius_coeff)")),
    (PairMemberSection, {"fillet_radius_coeff": 1.5},
     ("[pinion] fillet_radius_coeff = 1.5: out of range, allowed [0, 1.25) (below "
     "dedendum_coeff)")),
    (PairMemberSection, {"web_thickness_mm": None},
     ("[pinion] web_thickness_mm: required with rim_thickness_mm (the gear blank factor C_R "
     "needs both")),
    (MaterialSection, {"youngs_modulus_GPa": 5e-324},
     "[material] youngs_modulus_GPa = 4.94066e-324: out of range, allowed [0.1, 10000]"),
    (MaterialSection, {"sigma_H_lim_MPa": -1.0},
     ("[material] sigma_H_lim_MPa = -1: out of range, allowed [200, 2000] (ISO 6336-5's "
      "material lines")),
    (MaterialSection, {"sigma_F_lim_MPa": [430.0, 900.0]},
     "[material] sigma_F_lim_MPa = [430, 900]: element 900 out of range, allowed [30, 800]"),
    (MaterialSection, {"sigma_F_lim_MPa": [430.0]},
     "[material] sigma_F_lim_MPa = [430]: must be an array of 2 numbers"),
    (MaterialSection, {"sigma_H_lim_MPa": "1500"},
     "[material] sigma_H_lim_MPa = '1500': must be a number, not a string"),
    (MaterialSection, {"brinell_hardness_HB": {"input": 50.0}},
     "[material] brinell_hardness_HB = { input = 50 }: element 50 out of range, allowed [100, 700]"),
    (MaterialSection, {"proof_stress_MPa": 450.0},
     "[material] proof_stress_MPa = 450: out of range, allowed [500, 1000]"),
    (MaterialSection, {"surface_hardness_HV": 50.0},
     ("[material] surface_hardness_HV = 50: out of range, allowed [100, 1000] (Vickers: "
      "ISO 6336-5's surface hardness)")),
    (MaterialSection, {"treatment": "carburised"},
     "[material] treatment = 'carburised': allowed 'case_hardened', 'through_hardened', 'nitrided'"),
    (MaterialSection, {"treatment": 3},
     "[material] treatment = 3: allowed 'case_hardened', 'through_hardened', 'nitrided'"),
    (MaterialSection, {"treatment": ["nitrided", "glass"]},
     "[material] treatment = 'glass': allowed 'case_hardened', 'through_hardened', 'nitrided'"),
    (MaterialSection, {"treatment": {"input": "nitrided", "output": 1.0}},
     "[material] treatment = 1: allowed 'case_hardened', 'through_hardened', 'nitrided'"),
    (MaterialSection, {"treatment": ["nitrided"] * 3},
     ("[material] treatment = ['nitrided', 'nitrided', 'nitrided']: a name or a [pinion, gear] "
      "list of two names of 'case_hardened', 'through_hardened', 'nitrided'")),
    (MaterialSection, {"designation": ""},
     ("[material] designation = '': must be a material name (1 to 60 characters, e.g. "
      "'18CrNiMo7-6') or a [pinion, gear] list of two")),
    (MaterialSection, {"designation": ["16MnCr5"]},
     "[material] designation = ['16MnCr5']: must be a material name"),
    (MaterialSection, {"designation": "x" * 61}, "[material] designation = "),
    (MaterialSection, {"designation": {"input": "16MnCr5", "output": 3}},
     "[material] designation = { input = '16MnCr5', output = 3 }: must be a material name"),
    (MaterialSection, {"designation": {"input": "16MnCr5"}}, None),  # a train's: names checked
    (MaterialSection, {"treatment": {"input": "nitrided"}}, None),   # by the train's rating
    (MaterialSection, {"sigma_bogus_MPa": 1.0}, "[material] unknown key 'sigma_bogus_MPa'"),
    (MeshSection, {"stiffness": "weber2"},
     "[mesh] stiffness = 'weber2': allowed 'weber', 'uniform', 'iso6336', 'fe2d'"),
    (MeshSection, {"slices": 0}, "[mesh] slices = 0: out of range, allowed [1, 10000]"),
    (MeshSection, {"slices": "forty"}, "[mesh] slices = 'forty': must be an integer, not a string"),
    (MeshSection, {"positions_per_pitch": 64.5}, "[mesh] positions_per_pitch = 64.5: must be an integer"),
    (MeshSection, {"smooth_width_um": 0.0},
     ("[mesh] smooth_width_um = 0: out of range, allowed >= 0.0001 (µm; up to 1 % of the normal "
      "module)")),
    (MeshSection, {"foundation": "winkler"},
     "[mesh] foundation = 'winkler': allowed 'weber', 'sainsot', 'none' (or true = 'weber', false = 'none')"),

    (MeshSection, {"foundation": 1},
     "[mesh] foundation = 1: allowed 'weber', 'sainsot', 'none' (or true = 'weber', false = 'none')"),
    (MeshSection, {"extended_contact": 1}, "[mesh] extended_contact = 1: must be true or false"),
    (MeshSection, {"stiffness": "iso6336"},
     ("[mesh] fe2d_size_um = 500: belongs to stiffness = 'fe2d', not 'iso6336' (remove it or "
      "change the model)")),
    (MeshSection, {"stiffness": "uniform", "fe2d_size_um": None, "foundation": None},
     "[mesh] stiffness_per_length_N_per_mm_per_um: missing required key"),
    (MeshSection, {"stiffness": "uniform", "fe2d_size_um": None, "foundation": None,
                   "stiffness_per_length_N_per_mm_per_um": 1e7},
     "[mesh] stiffness_per_length_N_per_mm_per_um = 1e+07: out of range, allowed (0, 1e+06]"),
    (MeshSection, {"slice": 4}, "[mesh] unknown key 'slice' (did you mean 'slices'?)"),
    (DampingSection, {"model": "viscous"},
     "[scene.damping] model = 'viscous': allowed 'composite', 'modal', 'rayleigh', 'none'"),
    (DampingSection, {"mesh_ratio": 1.5}, "[scene.damping] mesh_ratio = 1.5: out of range, allowed [0, 1]"),
    (DampingSection, {"beta_s": -1e-5}, "[scene.damping] beta_s = -1e-05: out of range, allowed >= 0"),
    (DampingSection, {"ratios": 0.05}, "[scene.damping] unknown key 'ratios' (did you mean 'ratio'?)"),
    (IntegrationSection, {"periods": 1}, "[scene.integration] periods = 1: out of range, allowed [2, 1e+06]"),
    (IntegrationSection, {"periods": "auto", "steps_per_period": "auto"}, None),
    (IntegrationSection, {"periods": "all"},
     "[scene.integration] periods = 'all': allowed 'auto' or an integer in [2, 1e+06]"),
    (IntegrationSection, {"steps_per_period": "many"},
     "[scene.integration] steps_per_period = 'many': allowed 'auto' or an integer in [4, 1e+06]"),
    (IntegrationSection, {"steps_per_period": 3},
     "[scene.integration] steps_per_period = 3: out of range, allowed [4, 1e+06]"),
    (IntegrationSection, {"periods": 3},
     "[scene.integration] keep_periods = 4: out of range, allowed <= periods = 3"),
    (IntegrationSection, {"periods": 3, "keep_periods": None},
     "[scene.integration] keep_periods = 4: out of range, allowed <= periods = 3"),
    (IntegrationSection, {"rtol": 0.0}, "[scene.integration] rtol = 0: out of range, allowed (0, 1)"),
    (IntegrationSection, {"modal_basis": 12, "solver": "tsit5"},
     "[scene.integration] modal_basis = 12: allowed only with solver = 'newmark'"),
    (IntegrationSection, {"modal_basis": True},
     "[scene.integration] modal_basis = true: must be an integer, not a boolean"),
    (IntegrationSection, {"modal_basis": 0},
     "[scene.integration] modal_basis = 0: out of range, allowed [1, 1e+06] (modes), or false"),
    (IntegrationSection, {"contact": "soft"},
     "[scene.integration] contact = 'soft': allowed 'exact', 'smooth'"),
    (IntegrationSection, {"rotating_frame": "yes"},
     "[scene.integration] rotating_frame = 'yes': must be true or false"),
    (OperatingSection, {"torque_Nm": None}, "[operating] torque_Nm: missing required key"),
    (OperatingSection, {"loads": []}, "[operating] unknown key 'loads'"),
    (TrainOperating, {"loads": 3}, ("[operating] loads = 3: must be an array of tables "
     "([[operating.loads]]), not a number")),
    (TrainOperating, {"loads": [{"gear": "idler", "torque_Nm": 5.0}]},
     ("[operating.loads[0]] torque_Nm = 5: out of range, allowed < 0 (a load takes power: "
     "negative)")),
    (PlanetaryOperating, {"speed_rad_s": 0.0}, ("[operating] speed_rad_s = 0: out of range, "
     "allowed (0, 100000] (a planetary stage's run sweeps around it)")),
    (GearSection, {"teeth": -3}, ("[gears] teeth = -3: out of range, allowed [-10000, -5] (an "
     "internal gear, ISO 21771; external: [5, 10000])")),
    (GearSection, {"teeth": 3}, "[gears] teeth = 3: out of range, allowed [5, 10000]"),
    (GearSection, {"teeth": "x"}, "[gears] teeth = 'x': must be an integer, not a string"),
    (GearSection, {"teeth": 56}, None),
    (GearSection, {"hand": "up"}, "[gears] hand = 'up': allowed 'right', 'left'"),
    (ModificationsSection, {"crowning": 5.0},
     "[modifications] crowning = 5: must be a table, e.g. { depth_um = 10.0 }"),
    (ModificationsSection, {"crowning": {"depth_um": "3"}},
     "[modifications.crowning] depth_um = '3': must be a number, not a string"),
    (ModificationsSection, {"gear": {"tip_relief": {"extent": 0.0}}},
     ("[modifications.gear.tip_relief] extent = 0: out of range, allowed (0, 1] (fraction of "
     "the path of contact)")),
    (ModificationsSection, {"gear": {"tip_relief": {"depth": 1.0}}},
     ("[modifications.gear.tip_relief] unknown key 'depth' (did you mean 'depth_um'?), "
     "allowed: depth_um, extent, shape")),
    (ModificationsSection, {"end_relief": {"edge": "z2"}},
     "[modifications.end_relief] edge = 'z2': allowed 'both', 'z0', 'z1'"),
    (ModificationsSection, {"wheel": {}}, "[modifications] unknown key 'wheel'"),
    (PlanetarySection, {"planets": None}, ("[planetary] planets: give planets (equally "
     "spaced) or planet_angles_deg, one of them")),
    (PlanetarySection, {"planet_angles_deg": [0.0, 120.0, 240.0]},
     ("[planetary] planets: give planets (equally spaced) or planet_angles_deg, one of them, "
     "not both")),
    (PlanetarySection, {"input": "ring"},
     "[planetary] input = 'ring': is the fixed member (allowed: another of sun, ring, carrier)"),
    (PlanetarySection, {"fixed": "moon"},
     "[planetary] fixed = 'moon': allowed 'sun', 'ring', 'carrier'"),
    (PlanetarySection, {"ring_teeth": 33},
     ("[planetary] ring_teeth = 33: out of range, allowed [34, 10000] (sun_teeth + 2 × 3: "
      "planets of (ring_teeth − sun_teeth)/2 >= 3 teeth)")),
    (PlanetarySection, {"carrier_eccentricity_phase_deg": 30.0},
     ("[planetary] carrier_eccentricity_phase_deg = 30: given without carrier_eccentricity_um "
      "(its amplitude)")),
    (PlanetarySection, {"planet_unbalance_phase_deg": [0.0, 0.0, 0.0]},
     "[planetary] planet_unbalance_phase_deg = [0, 0, 0]: given without planet_unbalance_g_mm"),
    (PlanetarySection, {"sun_eccentricity_um": -5.0},
     "[planetary] sun_eccentricity_um = -5: out of range, allowed [0, 10000]"),
    (PlanetarySection, {"mesh_stiffness": "weber"},
     "[planetary] mesh_stiffness = 'weber': allowed 'iso6336', 'mean'"),
    (PlanetarySection, {"carrier": None}, "[planetary.carrier]: missing required table"),
    (PlanetarySection, {"sun": 3.0},
     "[planetary] sun = 3: must be a table ([planetary.sun]), not a number"),
    (PlanetarySection, {"sun": {"mass_kg": 0.4, "inertia_kg_m2": 1e-3, "inertia_over_r2_kg": 0.39}},
     ("[planetary.sun] inertia_over_r2_kg = 0.39: give inertia_kg_m2 or inertia_over_r2_kg, "
      "not both")),
    (PlanetarySection, {"sun": {"mass_kg": 0.4}},
     "[planetary.sun] inertia_kg_m2: missing required key (or inertia_over_r2_kg)"),
    (PlanetarySection, {"ring": {"mass_kg": 2.35, "inertia_kg_m2": 1.0,
                                 "torsional_stiffness_Nm_per_rad": 1e9,
                                 "torsional_stiffness_N_per_um": 1.0}},
     ("[planetary.ring] torsional_stiffness_N_per_um = 1: give torsional_stiffness_Nm_per_rad "
      "or torsional_stiffness_N_per_um, not both")),
    (PlanetarySection, {"ring": {"mass_kg": 2.35, "inertia_kg_m2": 1.0, "model": "elastic"}},
     "[planetary.ring] model = 'elastic': allowed 'rigid', 'condensed'"),
    (PlanetarySection, {"ring": {"mass_kg": 2.35, "inertia_kg_m2": 1.0, "modes": 8.5}},
     "[planetary.ring] modes = 8.5: must be an integer"),
    (PlanetarySection, {"planet": {"mass_kg": 0.66, "inertia_kg_m2": 1.0,
                                   "pin_radial_N_per_um": 5e-324, "pin_tangential_N_per_um": 1.0}},
     ("[planetary.planet] pin_radial_N_per_um = 4.94066e-324: out of range, allowed "
      "[0.001, 1e+09]")),
    (PlanetarySection, {"planet": {"mass_kg": 0.66, "inertia_kg_m2": 1.0,
                                   "pin_tangential_N_per_um": 1.0}},
     "[planetary.planet] pin_radial_N_per_um: missing required key"),
    (PlanetarySection, {"sun": {"mass_kg": 0.4, "inertia_kg_m2": 1.0, "spin": 1.0}},
     "[planetary.sun] unknown key 'spin', allowed: axial_N_per_um, base_radius_mm"),
    (PlanetarySection, {"sun_teth": 28}, ("[planetary] unknown key 'sun_teth' (did you mean "
     "'sun_teeth'?)")),
    (GearboxOperating, {"torque_Nm": 0.0},
     "[operating] torque_Nm = 0: out of range, allowed (0, 1e+09]"),
    (GearboxOperating, {"speed_rad_s": None}, "[operating] speed_rad_s: missing required key"),
    (StageEntry, {"case": ""}, "[stages[]] case = '': must be a non-empty string"),
    (StageEntry, {"case": None}, "[stages[]] case: missing required key"),
    (StageEntry, {"mesh_stiffness_N_per_um": 1e-300},
     "[stages[]] mesh_stiffness_N_per_um = 1e-300: out of range, allowed [0.001, 1e+06]"),
    (StageEntry, {"model": "rigid"},
     "[stages[]] model = 'rigid': allowed 'torsional', 'lumped3d', 'planar'"),
    (StageEntry, {"input": "ring"}, "[stages[]] input = 'ring': allowed 'pinion', 'gear'"),
    (StageEntry, {"housing_seat": -1},
     ("[stages[]] housing_seat = -1: allowed an integer >= 0 (the seat index of the gearbox's "
      "[housing] the held ring is bolted to)")),
    (StageEntry, {"housing_seat": 2.0}, None),
    (StageEntry, {"housing_seats": [0, -2]},
     "[stages[]] housing_seats = [0, -2]: element -2 out of range, allowed >= -1"),
    (StageEntry, {"shaft": 1.0}, "[stages[]] unknown key 'shaft'"),
    (HousingSection, {"cutoff_Hz": 10.0, "highest_mesh_frequency_Hz": 100.0},
     "[housing] cutoff_Hz: give exactly one of cutoff_Hz and highest_mesh_frequency_Hz"),
    (HousingSection, {"mesh_file": "box.msh"},
     "[housing] width_mm = 250: a box key: not with mesh_file"),
    (HousingSection, {"offset_mm": [0.0, 0.0, 0.0]},
     "[housing] offset_mm = [0, 0, 0]: a mesh file's key: allowed with mesh_file only"),
    (HousingSection, {"height_mm": None}, "[housing] height_mm: missing required key"),
    (HousingSection, {"wall_thickness_mm": -1.0},
     "[housing] wall_thickness_mm = -1: out of range, allowed [0.001, 100000]"),
    (HousingSection, {"element": "hex8"}, "[housing] element = 'hex8': allowed 'tet10', 'tet4'"),
    (HousingSection, {"loss_factor": 3.0}, "[housing] loss_factor = 3: out of range, allowed [0, 1]"),
    (HousingSection, {"layers": 9}, "[housing] layers = 9: out of range, allowed [1, 8]"),
    (HousingSection, {"points_mm": {"top": [1.0, 2.0]}},
     "[housing.points_mm] top = [1, 2]: must be an array of 3 numbers"),
    (HousingSection, {"points_mm": 3},
     "[housing] points_mm = 3: must be a table ([housing.points_mm]), not a number"),
    (HousingSection, {"seats": 5e-324},
     ("[housing] seats = 4.94066e-324: must be an array of tables ([[housing.seats]]), not a "
      "number")),
    (HousingSection, {"colour": 1}, "[housing] unknown key 'colour'"),
    (SeatEntry, {"diameter_mm": 0.0},
     "[housing.seats[]] diameter_mm = 0: out of range, allowed [0.001, 100000]"),
    (SeatEntry, {"centre_mm": [1.0, 2.0]},
     "[housing.seats[]] centre_mm = [1, 2]: must be an array of 3 numbers"),
    (FootEntry, {"x_mm": [0.0, float("inf")]},
     "[housing.feet[]] x_mm = [0, inf]: must be an array of finite numbers"),
    (StageDeviationsSection, {"revolutions": "all"},
     "[deviations] revolutions = 'all': allowed an integer >= 1 or \"hunting\""),
    (StageDeviationsSection, {"revolutions": "hunting"}, None),
    (StageDeviationsSection, {"revolutions": 0},
     "[deviations] revolutions = 0: out of range, allowed >= 1"),
    (StageDeviationsSection, {"grade": 12}, "[deviations] grade = 12: out of range, allowed [1, 11]"),
    (StageDeviationsSection, {"planet_1": {}}, "[deviations] unknown key 'planet_1'"),
    (StageDeviationsSection, {"sun": {"sun_flank": {}}},
     "[deviations.sun] unknown key 'sun_flank'"),
    (StageDeviationsSection, {"sun": {"profile_slope_um": "1"}},
     "[deviations.sun] profile_slope_um = '1': must be a number, not a string"),
    (MemberDeviations, {"pitch_um": [1.0, float("nan")]},
     "[deviations.sun] pitch_um = [1, nan]: must be an array of finite numbers"),
    (MemberDeviations, {"lead_um": 1.0}, "[deviations.sun] unknown key 'lead_um'"),
    (PlanetDeviations, {"sun_flank": 3.0},
     ("[deviations.planet_1] sun_flank = 3: must be a table ([deviations.planet_1.sun_flank]), "
     "not a number")),
    (PlanetDeviations, {"ring_flank": {"lead_um": 1.0}},
     "[deviations.planet_1.ring_flank] unknown key 'lead_um'"),
    (RobustSection, {"revolutions": "all"},
     "[robust] revolutions = 'all': allowed an integer >= 1 or \"hunting\""),
    (RobustSection, {"kinds": ["pitch", "pitch"]},
     ("[robust] kinds = ['pitch', 'pitch']: out of range, allowed distinct names among "
     "['pitch', 'runout', 'profile', 'helix']")),
    (RobustSection, {"percentiles": [50.0, 100.0]},
     "[robust] percentiles = [50, 100]: element 100 out of range, allowed (0, 100)"),
    (OptimiseSection, {"objective": "te_max"},
     "[optimise] objective = 'te_max': allowed 'te_rms', 'te_ptp', 'robust_te_rms', "),
    (OptimiseSection, {"reduce": "median"},
     "[optimise] reduce = 'median': allowed 'max', 'mean', 'quantile'"),
    (OptimiseSection, {"quantile": 1.0},
     "[optimise] quantile = 1: out of range, allowed (0, 1)"),
    (OptimiseSection, {"a_weighted": 1}, "[optimise] a_weighted = 1: must be true or false"),
    (OptimiseSection, {"method": "bfgs"}, "[optimise] method = 'bfgs': allowed 'lbfgs', 'adam'"),
    (OptimiseSection, {"max_iterations": 0},
     "[optimise] max_iterations = 0: out of range, allowed [1, 1e+06]"),
    (OptimiseSection, {"max_iterations": 7.5}, "[optimise] max_iterations = 7.5: must be an integer"),
    (OptimiseSection, {"lp_order": 65.0}, "[optimise] lp_order = 65: out of range, allowed [1, 64]"),
    (OptimiseSection, {"te_limit_um": "1"},
     "[optimise] te_limit_um = '1': must be a number, not a string"),
    (OptimiseSection, {"vars": "tip_relief.depth, crowning.dpeth"},
     ("[optimise] vars = ['tip_relief.depth', 'crowning.dpeth']: unknown variable "
      "'crowning.dpeth', allowed tip_relief.depth, ")),
    (OptimiseSection, {"vars": []},
     "[optimise] vars = []: must be a non-empty array of variable names"),
    (OptimiseSection, {"vars": ["crowning.depth", "crowning.depth"], "bounds": None},
     "[optimise] vars = ['crowning.depth', 'crowning.depth']: names a variable twice"),
    (OptimiseSection, {"torques": [120.0, 40.0, 5]},
     ("[optimise] torques = [120, 40, 5]: allowed [start, stop, n] in N·m with 0 < start < "
      "stop and an integer n in [2, 10000]")),
    (OptimiseSection, {"objective": "dynamic_factor", "torques": None, "speeds": [200.0, 100.0, 3]},
     "[optimise] speeds = [200, 100, 3]: allowed [start, stop, n]: pinion speeds in rad/s"),
    (OptimiseSection, {"bounds": 3},
     "[optimise] bounds = 3: must be a table ([optimise.bounds]), not a number"),
    (OptimiseSection, {"bounds": {"tip_relief.depth": [0.0]}},
     "[optimise.bounds] tip_relief.depth = [0]: must be an array of 2 numbers"),
    (OptimiseSection, {"bounds": {"tip_relief.extent": [0.5, 0.2]}},
     ("[optimise.bounds] tip_relief.extent = [0.5, 0.2]: out of range, allowed [lo, hi] with "
      "0 < lo < hi < 1 (Γ)")),
    (OptimiseSection, {"bounds": {"tip_relief.depth": [-1.0, 2.0]}},
     ("[optimise.bounds] tip_relief.depth = [-1, 2]: out of range, allowed [lo, hi] with "
      "0 <= lo < hi (E* = depth/δ_m)")),
    (OptimiseSection, {"bounds": {"crowning.depth": [0.0, 1.0]}},
     ("[optimise.bounds] crowning.depth = [0, 1]: is not a design variable (vars = "
      "['tip_relief.depth', 'tip_relief.extent'])")),
    (OptimiseSection, {"bounds": {"crowning.dpeth": [0.0, 1.0]}},
     "[optimise.bounds] crowning.dpeth = [0, 1]: unknown variable, allowed tip_relief.depth"),
    (OptimiseSection, {"step": 3},
     ("[optimise] unknown key 'step', allowed: a_weighted, bounds, choices, lp_order, "
      "max_iterations, method, objective, quantile, reduce, speeds, te_limit_um, torques, "
      "vars")),
    # the keys that relate: quantile and reduce, a key of some objectives only
    (OptimiseSection, {"reduce": "mean"},
     "[optimise] quantile = 0.9: applies to reduce = 'quantile' only, not 'mean'"),
    (OptimiseSection, {"quantile": None},
     "[optimise] reduce = 'quantile': 'quantile' needs its level: quantile = q in (0, 1)"),
    (OptimiseSection, {"objective": "te_rms"},
     ("[optimise] torques = [40, 120, 5]: applies to objective = 'robust_te_rms' or a tribology "
      "objective (power_loss, efficiency_loss, min_specific_film, max_flash_temperature) only, "
      "not 'te_rms'")),
    (OptimiseSection, {"objective": None}, None),  # torques with the default objective
    (OptimiseSection, {"lp_order": 4.0},
     "[optimise] lp_order = 4: applies to objective = 'line_load_lp' only, not 'robust_te_rms'"),
    (OptimiseSection, {"objective": "line_load_lp", "torques": None, "lp_order": 4.0}, None),
    (OptimiseSection, {"objective": None, "torques": None, "lp_order": 4.0}, None),  # default
    (OptimiseSection, {"objective": None, "torques": None, "te_limit_um": 1.0},
     "[optimise] te_limit_um = 1: applies to objective = 'least_safety' only, not 'te_rms'"),
    (OptimiseSection, {"te_limit_um": 1.0},
     ("[optimise] te_limit_um = 1: applies to objective = 'least_safety' only, not "
      "'robust_te_rms'")),
    (OptimiseSection, {"a_weighted": False},
     ("[optimise] a_weighted = false: applies to objective = 'erp' or 'sound_power' only, not "
      "'robust_te_rms'")),
    (OptimiseSection, {"objective": "erp", "torques": None, "a_weighted": False}, None),
    (OptimiseSection, {"speeds": [100.0, 200.0, 2]},
     ("[optimise] speeds = [100, 200, 2]: applies to objective = 'dynamic_factor' only, not "
      "'robust_te_rms'")),
    (OptimiseSection, {"objective": "dynamic_factor", "torques": None},
     ("[optimise] objective = 'dynamic_factor': 'dynamic_factor' needs speeds = [start, stop, "
      "n]")),
    (OptimiseSection, {"objective": "dynamic_factor", "torques": None,
                       "speeds": [100.0, 100.0, 1]}, None),
    (SpectrumSection, {"torque_Nm": [80.0, -1.0]},
     "[rating.spectrum] torque_Nm = [80, -1]: element -1 out of range, allowed [0, 1e+09]"),
    (SpectrumSection, {"torque_Nm": []},
     "[rating.spectrum] torque_Nm = []: must be an array of at least 1 numbers"),
    (SpectrumSection, {"speed_rpm": "fast"},
     "[rating.spectrum] speed_rpm = 'fast': must be a number, not a string"),
    (SpectrumSection, {"speed_rpm": 2e6},
     "[rating.spectrum] speed_rpm = 2e+06: out of range, allowed [0, 1e+06]"),
    (SpectrumSection, {"speed_rpm": [3000.0]},
     ("[rating.spectrum] speed_rpm = [3000]: must be an array of 2 numbers (one per bin of "
      "torque_Nm)")),
    (SpectrumSection, {"hours": [1.0]},
     "[rating.spectrum] hours = [1]: must be an array of 2 numbers (one per bin of torque_Nm)"),
    (SpectrumSection, {"hours": [-1.0, 1.0]},
     "[rating.spectrum] hours = [-1, 1]: element -1 out of range, allowed >= 0"),
    (SpectrumSection, {"hours": None, "cycles": [1e6, 2e6]}, None),
    (SpectrumSection, {"hours": None, "time_share": [0.0, 0.0]},
     "[rating.spectrum] time_share = [0, 0]: out of range: the shares must add up to > 0"),
    (SpectrumSection, {"hours": None},
     "[rating.spectrum] hours: missing: give one of hours, cycles, time_share"),
    (SpectrumSection, {"cycles": [1e6, 2e6]},
     ("[rating.spectrum] hours: hours and cycles both given: give one of hours, cycles, "
      "time_share")),
    (SpectrumSection, {"levels": 4},
     ("[rating.spectrum] torque_Nm: give bins (torque_Nm, speed_rpm, hours | cycles | "
      "time_share) or a series (series_torque_Nm, ...), not both (levels is given too)")),
    (SpectrumSection, {"speed_rpm": None}, "[rating.spectrum] speed_rpm: missing required key"),
    (SpectrumSection, {"hour": [1.0, 1.0]},
     "[rating.spectrum] unknown key 'hour' (did you mean 'hours'?), allowed: cycles, hours, "),
    (SpectrumSection, {"torque_Nm": None, "speed_rpm": None, "hours": None,
                       "series_torque_Nm": [80.0, 40.0, 60.0], "series_speed_rpm": 3000.0,
                       "series_step_s": 0.1}, None),
    (SpectrumSection, {"torque_Nm": None, "speed_rpm": None, "hours": None,
                       "series_torque_Nm": [80.0, 40.0], "series_speed_rpm": [3000.0] * 3,
                       "series_step_s": 0.1},
     ("[rating.spectrum] series_speed_rpm = [3000, 3000, 3000]: must be an array of 2 numbers "
      "(one per sample of series_torque_Nm)")),
    (SpectrumSection, {"torque_Nm": None, "speed_rpm": None, "hours": None,
                       "series_torque_Nm": [0.0, 0.0], "series_speed_rpm": 3000.0,
                       "series_step_s": 0.1},
     "[rating.spectrum] series_torque_Nm = [0, 0]: out of range: no sample above 0 N·m"),
    (SpectrumSection, {"torque_Nm": None, "speed_rpm": None, "hours": None,
                       "series_torque_Nm": [80.0, 40.0], "series_speed_rpm": 3000.0},
     "[rating.spectrum] series_step_s: missing required key"),
    (SpectrumSection, {"torque_Nm": None, "speed_rpm": None, "hours": None,
                       "series_torque_Nm": [80.0, 40.0], "series_speed_rpm": 3000.0,
                       "series_step_s": 0.1, "levels": 1001},
     "[rating.spectrum] levels = 1001: out of range, allowed [1, 1000]"),
    (ParetoSection, {"minimise": "mass_kg"},
     ("[pareto] minimise = 'mass_kg': allowed a list of column names: mass_kg, volume_m3, "
      "least_margin, mesh_loss_W, efficiency, ")),
    (ParetoSection, {"maximise": ["least_margin", 3]},
     "[pareto] maximise = ['least_margin', 3]: allowed a list of column names: mass_kg, "),
    (ParetoSection, {"maximise": ["margin"]},
     "[pareto] maximise = ['margin']: 'margin' is not an objective: allowed mass_kg, volume_m3"),
    (ParetoSection, {"maximise": ["mass_kg"]},
     "[pareto] maximise = ['mass_kg']: 'mass_kg' is named twice"),
    (ParetoSection, {"minimise": ["mass_kg", "mesh_loss_W"]},
     ("[pareto] minimise = ['mass_kg', 'mesh_loss_W']: 'mesh_loss_W' needs a [lubricant] table "
      "(the oil, roughness and friction of the mesh loss)")),
    (ParetoSection, {"minimise": ["volume_m3"], "choose": None}, None),
    (ParetoSection, {"minimise": [], "choose": None},
     "[pareto] minimise = []: 1 objectives with maximise: allowed 2 to 6"),
    (ParetoSection, {"minimise": ["mass_kg", "volume_m3", "te_ppk_m", "te_ppk_modified_m",
                                  "dynamic_factor_max", "whine_force_N"]},
     "[pareto] minimise = ['mass_kg', 'volume_m3', 'te_ppk_m', 'te_ppk_modified_m', "),
    (ParetoSection, {"choose": "mesh_loss_W"},
     "[pareto] choose = 'mesh_loss_W': allowed 'knee', 'mass_kg', 'volume_m3', 'least_margin'"),
    (ParetoSection, {"choose": 1}, "[pareto] choose = 1: allowed 'knee', 'mass_kg'"),
    (ParetoSection, {"minimise": None, "maximise": None, "choose": "least_margin"}, None),
    (ParetoSection, {"minimize": ["mass_kg"]},
     ("[pareto] unknown key 'minimize' (did you mean 'minimise'?), allowed: choose, maximise, "
      "minimise")),
    (MicropittingKeys, {"micropitting_load_stage": 4.5},
     "[lubricant] micropitting_load_stage = 4.5: out of range, allowed [5, 10]"),
    (MicropittingKeys, {"micropitting_load_stage": None, "permissible_specific_film": 0.0},
     "[lubricant] permissible_specific_film = 0: out of range, allowed (0, 10]"),
    (MicropittingKeys, {"permissible_specific_film": 0.25},
     ("[lubricant] permissible_specific_film = 0.25: not read: micropitting_load_stage is given "
      "(λ_GFP from the TS's Figure A.1); remove one")),
    (MicropittingKeys, {"micropitting_stage": 8},
     "[lubricant] unknown key 'micropitting_stage' (did you mean 'micropitting_load_stage'?)"),
    (LubricantSection, {"micropitting_load_stage": "8"},
     "[lubricant] micropitting_load_stage = '8': must be a number, not a string"),
    (LubricantSection, {"micropitting_load_stage": 8, "viscosity_40C_mm2_s": 500.0},
     ("[lubricant] viscosity_40C_mm2_s = 500: out of range with micropitting_load_stage, allowed "
      "[32, 460] (ISO VG 32 to 460, the curves of the TS's Figure A.1; or give "
      "permissible_specific_film)")),
    (LubricantSection, {"permissible_specific_film": 0.25, "viscosity_40C_mm2_s": 500.0}, None),
    (LubricantSection, {"micropitting_load_stage": 8, "fzg_load_stage": None,
                        "bulk_temperature_C": 95.0, "bulk_lubrication_factor": 1.2},
     ("[lubricant] bulk_lubrication_factor = 1.2: not read: bulk_temperature_C is given (X_S is "
      "the TS rule's); remove one")),
    (LubricantSection, {"micropitting_load_stage": 8, "fzg_load_stage": None,
                        "bulk_lubrication_factor": 1.2}, None),
])
def test_the_words(section, change, words):
    """The messages in the file's words (the hand-written checks' wording)."""
    table = {k: v for k, v in (copy.deepcopy(BASES[section]) | change).items() if v is not None}
    if words is None:
        section.read(table)
        return
    with pytest.raises(sc.SchemaError) as err:
        section.read(table)
    assert str(err.value).startswith(words), str(err.value)


def test_the_optimise_settings_are_the_keys_given_normalised():
    """``[optimise]`` read by its section gives ``jaxgear optimise`` the keys the file gave (the
    others are the command's), normalised: the names of a comma-separated text as a list, the
    spans as (float, float, int), an integral float count as an int, the bounds as pairs."""
    table = BASES[OptimiseSection] | {"vars": " tip_relief.depth ,tip_relief.extent",
                                      "torques": [40, 120, 5.0], "max_iterations": 50.0,
                                      "bounds": {"tip_relief.depth": [0, 2.5]}}
    out = jio.parse_optimise(table)
    assert out == {"objective": "robust_te_rms", "reduce": "quantile", "quantile": 0.9,
                   "method": "adam", "max_iterations": 50,
                   "vars": ["tip_relief.depth", "tip_relief.extent"],
                   "torques": [40.0, 120.0, 5], "bounds": {"tip_relief.depth": (0.0, 2.5)}}
    assert [type(v) for v in out["torques"]] == [float, float, int]
    assert type(out["max_iterations"]) is int
    assert jio.parse_optimise({}) == {}


def test_the_pareto_objectives_are_the_columns_given_with_their_sense():
    """A sizing spec's ``[pareto]``: the minimised columns then the maximised, ``choose`` as
    given; the mesh loss's columns read with a ``[lubricant]`` (refused without); no table or
    neither list, the sizing's defaults (mass minimised, least margin maximised, the knee)."""
    table = {"minimise": ["mass_kg", "mesh_loss_W"], "maximise": ["least_margin", "efficiency"],
             "choose": "efficiency"}
    assert parse_pareto(table, True) == (
        (("mass_kg", "min"), ("mesh_loss_W", "min"), ("least_margin", "max"),
         ("efficiency", "max")), "efficiency")
    with pytest.raises(sc.SchemaError, match=r"'mesh_loss_W' needs a \[lubricant\] table"):
        parse_pareto(table, False)
    defaults = ((("mass_kg", "min"), ("least_margin", "max")), "knee")
    assert parse_pareto(None, False) == defaults
    assert parse_pareto({"choose": "knee"}, False) == defaults


def test_a_planetary_rating_takes_its_mesh_tables_and_keys():
    """``[rating.<mesh>]`` tables of the case's meshes and ``K_gamma`` (a planetary stage's)
    read; another table name is an unknown key; a mesh table's value in its own words."""
    table = BASES[RatingSection] | {"K_gamma": 1.1, "sun-planet": {"K_v": 1.2}}
    s = RatingSection.of(table, ("sun-planet", "planet-ring"), planetary=True)
    assert s.K_gamma == 1.1 and s.meshes["sun-planet"].K_v == 1.2 and not s.meshes.get("x")
    with pytest.raises(sc.SchemaError, match=r"^\[rating\] unknown key 'sun-ring'"):
        RatingSection.of(BASES[RatingSection] | {"sun-ring": {}}, ("sun-planet",), True)
    with pytest.raises(sc.SchemaError,
                       match=r"^\[rating.sun-planet\] K_v = 20: out of range, allowed \[1, 10\]$"):
        RatingSection.of(BASES[RatingSection] | {"sun-planet": {"K_v": 20.0}}, ("sun-planet",))
    with pytest.raises(sc.SchemaError, match=r"^\[rating\] sun-planet = 3: must be a table"):
        RatingSection.of(BASES[RatingSection] | {"sun-planet": 3}, ("sun-planet",))


def _fzg():
    data = sc.load_toml((ROOT / "jaxgear/cases/fzg-h951.toml").read_bytes(), "fzg-h951")
    assert {"lubricant", "rating"} <= set(data)
    return data


def test_the_case_carries_its_typed_sections():
    """The case reader keeps ``[lubricant]`` and ``[rating]`` typed on the case (and no
    ``[whine]``/``[acoustics]`` where the file has none); the SI inputs come from them."""
    data = _fzg()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        case = jio.parse_case(data, "fzg")
    assert isinstance(case.lubricant, LubricantSection)
    assert isinstance(case.rating, RatingSection)
    assert case.whine is None and case.acoustics is None
    assert case.lubricant.viscosity_40C_mm2_s == data["lubricant"]["viscosity_40C_mm2_s"]
    inputs = jio.tribology_of(case)
    assert float(inputs.lubricant.viscosity_40) == pytest.approx(
        data["lubricant"]["viscosity_40C_mm2_s"] * 1e-6)
    rc = jio.rating_of(case)
    assert float(rc.settings.life) == pytest.approx(data["rating"]["life_h"] * 3600.0)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(table=st.sampled_from(["lubricant", "rating", "pair", "pinion", "gear", "material",
                              "operating", "modifications"]), key=st.integers(min_value=0),
       value=VALUES,
       whole=st.booleans())
def test_a_mutated_case_file_is_one_line(table, key, value, whole):
    """Through the case reader (``jaxgear run``'s load): a mutated key of ``[lubricant]``,
    ``[rating]``, ``[pair]``, ``[pinion]``, ``[gear]``, ``[material]``, ``[operating]`` or
    ``[modifications]`` (or the table given as a value) loads or is one SchemaError line, never
    another exception."""
    data = _fzg()
    data.setdefault("modifications", {"tip_relief": {"depth_um": 10.0}})
    keys = sorted(data[table])
    if whole and not isinstance(value, dict):
        data[table] = value
    else:
        data[table][keys[key % len(keys)]] = value
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            jio.parse_case(data, "fzg")
    except sc.SchemaError as err:
        assert "\n" not in str(err), str(err)


def test_a_subnormal_positive_value_is_one_line():
    """The fuzz test's find: ``[lubricant] pressure_viscosity_per_GPa = 5e-324`` lies in (0, 100]
    but underflows to 0 in the conversion to 1/Pa, where the library refused it with its own
    ValueError; a key whose range is open at 0 takes at least the smallest normal float (2.2e-308),
    so the reader refuses it in one line, and keeps a normal small value."""
    data = _fzg()
    data["lubricant"]["pressure_viscosity_per_GPa"] = 5e-324
    with pytest.raises(sc.SchemaError) as err:
        jio.parse_case(data, "fzg")
    assert str(err.value) == ("[lubricant] pressure_viscosity_per_GPa = 4.94066e-324: out of range "
                              "(subnormal: below 2.22507e-308), allowed (0, 100]")
    data["lubricant"]["pressure_viscosity_per_GPa"] = 1e-300
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        case = jio.parse_case(data, "fzg")
    assert float(jio.tribology_of(case).lubricant.pressure_viscosity) == pytest.approx(1e-309)


def _train(name: str):
    return sc.load_toml((ROOT / f"jaxgear/cases/{name}.toml").read_bytes(), name)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(where=st.sampled_from([("accessory-idler-train", "gears"),
                              ("accessory-idler-train", "meshes"),
                              ("accessory-idler-train", "operating"),
                              ("accessory-idler-train", "material"),
                              ("lin-parker-1999", "operating"), ("lin-parker-1999", "material")]),
       key=st.integers(min_value=0), value=VALUES)
def test_a_mutated_train_file_is_one_line(where, key, value):
    """Through the train and planetary reader: a mutated key of a ``[[gears]]`` or
    ``[[meshes]]`` entry, ``[operating]`` or ``[material]`` loads or is one SchemaError
    line."""
    case, table = where
    data = _train(case)
    t = (data[table][key % len(data[table])] if table in ("gears", "meshes")
         else data.setdefault(table, {}))
    keys = sorted(t) or ["youngs_modulus_GPa"]
    t[keys[key % len(keys)]] = value
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            jio.parse_train(data, case)
    except sc.SchemaError as err:
        assert "\n" not in str(err), str(err)


@pytest.mark.parametrize(("key", "value", "words"), [
    ("sigma_H_lim_MPa", {"pinion": 1500.0},
     "[material] sigma_H_lim_MPa = { pinion = 1500 }: must be a number, not a table"),
    ("treatment", {"pinion": "nitrided"},
     ("[material] treatment = { pinion = 'nitrided' }: a name or a [pinion, gear] list of two "
      "names of")),
    ("designation", {"pinion": "16MnCr5"},
     "[material] designation = { pinion = '16MnCr5' }: must be a material name"),
])
def test_a_pair_case_refuses_a_table_by_gear_name(key, value, words):
    """A table by gear name is a train's: a pair's case reads the typed key, then refuses it in
    one line where the mesh is rated."""
    data = _fzg()
    data["material"][key] = value
    with pytest.raises(sc.SchemaError) as err, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        jio.parse_case(data, "fzg")
    assert str(err.value).startswith(words), str(err.value)


def test_the_rating_reads_the_typed_material_keys():
    """The rated pair's material is the file's per-gear numbers (a list: [pinion, gear], MPa
    → Pa) and treatments (a through-hardened gear with its HB against a case-hardened pinion:
    Z_W = 1.2 − (HB − 130)/1700, ISO 6336-2)."""
    data = _fzg()
    data["material"].update(sigma_H_lim_MPa=[1500.0, 1400.0], sigma_F_lim_MPa=430.0,
                            treatment=["case_hardened", "through_hardened"],
                            brinell_hardness_HB=[600.0, 300.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = jio.rating_of(jio.parse_case(data, "fzg")).settings.material
    assert [float(v) for v in m.sigma_h_lim] == [1.5e9, 1.4e9]
    assert [float(v) for v in m.sigma_f_lim] == [4.3e8, 4.3e8]
    assert m.treatment.gear.work_hardening(m.treatment.pinion) == pytest.approx(
        1.2 - (300.0 - 130.0) / 1700.0, rel=1e-12)


@pytest.mark.parametrize(("value", "name"), [(True, "weber"), (False, "none"),
                                             ("sainsot", "sainsot")])
def test_the_old_boolean_foundation_is_its_name(value, name):
    assert MeshSection.read({"foundation": value}).foundation == name


@pytest.mark.parametrize(("key", "value", "module_mm", "words"), [
    ("smooth_width_um", 20.0, 1.5,
     ("[mesh] smooth_width_um = 20: out of range, allowed [0.0001, 15] (µm; up to 1 % of the "
      "normal module)")),
    ("smooth_width_um", 14.0, 1.5, None),
    ("smooth_width_um", 20.0, 4.5, None),
    ("smooth_width_um", -1.0, 1.5, "allowed [0.0001, 15] (µm; up to 1 % of the normal module)"),
    ("fe2d_size_um", 10.0, 1.5,
     "[mesh] fe2d_size_um = 10: out of range, allowed [15, 1500] (m_n/100 to m_n; default m_n/6)"),
    ("fe2d_size_um", 1600.0, 1.5, "allowed [15, 1500]"),
    ("fe2d_size_um", 15.0, 1.5, None),
    ("fe2d_size_um", "1", 1.5, "[mesh] fe2d_size_um = '1': must be a number, not a string"),
])
def test_mesh_widths_follow_the_module(key, value, module_mm, words):
    """``[mesh]``'s smooth width (up to 1 % of m_n) and fe2d's element size (m_n/100 to m_n)
    are checked against the normal module given as the context (a pair's; a train's smallest),
    in the range its message prints, the bounds inclusive."""
    table = {key: value}
    if words is None:
        MeshSection.read(table, context={"normal_module": module_mm * 1e-3})
        return
    with pytest.raises(sc.SchemaError) as err:
        MeshSection.read(table, context={"normal_module": module_mm * 1e-3})
    assert words in str(err.value) and "\n" not in str(err.value), str(err.value)


def test_the_case_mesh_settings_are_the_sections():
    """Through the case reader: ``[mesh]``'s keys reach the case in SI (µm → m, N/mm/µm →
    N/m²) and a width beyond the case's module is refused in its words."""
    data = _fzg()
    data["mesh"] = {"stiffness": "uniform", "stiffness_per_length_N_per_mm_per_um": 14.0,
                    "slices": 12, "positions_per_pitch": 20, "smooth_width_um": 0.5,
                    "extended_contact": False}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        case = jio.parse_case(data, "fzg")
    assert (case.slices, case.positions_per_pitch) == (12, 20)
    assert case.smooth_width == pytest.approx(0.5e-6, rel=1e-15)
    assert float(case.stiffness.k0) == pytest.approx(14e9, rel=1e-15)
    assert not case.contact_geometry.reaches_beyond_path
    module_um = data["pair"]["normal_module_mm"] * 1e3
    data["mesh"]["smooth_width_um"] = 0.011 * module_um
    with pytest.raises(sc.SchemaError, match=r"^\[mesh\] smooth_width_um = .*: out of range, "
                       rf"allowed \[0.0001, {0.01 * module_um:.6g}\]"):
        jio.parse_case(data, "fzg")


def test_the_scene_settings_are_the_sections():
    """``[scene.damping]`` and ``[scene.integration]`` reach the scene's settings as given:
    "auto" counts as None (the time-plan rule), false modal basis absent, the keys not given
    left to the scene's defaults."""
    import types

    from jaxgear.io._scene_table import dynamics_settings

    def parse_dynamics_settings(table):  # a scene section's two sub-tables
        return dynamics_settings(types.SimpleNamespace(
            damping=DampingSection.read(table.get("damping", {})),
            integration=IntegrationSection.read(table.get("integration", {}))))

    kw = parse_dynamics_settings({"damping": {"model": "modal", "ratio": 0.05},
                                  "integration": {"periods": "auto", "rtol": 1e-7,
                                                  "modal_basis": False}})
    assert kw == {"damping_model": "modal", "damping_ratio": 0.05, "solver": "newmark",
                  "contact": "exact", "steps_per_period": None, "periods": None, "rtol": 1e-7}
    kw = parse_dynamics_settings({"integration": {"steps_per_period": 128.0, "periods": 12,
                                                  "keep_periods": 3, "modal_basis": 20}})
    assert kw["steps_per_period"] == 128 and type(kw["steps_per_period"]) is int
    assert (kw["periods"], kw["keep_periods"], kw["modal_basis"]) == (12, 3, 20)
    assert kw["damping_model"] == "composite"


# --------------------------------------------------------------------------------------------
# [scene]: a pair's and a train's, their shafts, bearings and bodies


def _case(name: str):
    return sc.load_toml((ROOT / f"jaxgear/cases/{name}.toml").read_bytes(), name)


def _load(data, name: str):
    """The case of ``data`` read by its form's reader (a train's ``[[gears]]``)."""
    read = jio.parse_train if "gears" in data else jio.parse_case
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read(data, name)


def _paths(value, path=()):
    """The path (keys, array indices) of every value in a table, itself included."""
    yield path
    items = value.items() if isinstance(value, dict) else (
        enumerate(value) if isinstance(value, list) else ())
    for key, inner in items:
        yield from _paths(inner, (*path, key))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(name=st.sampled_from(["accessory-spur-flexible", "flexible-idler", "two-stage"]),
       pick=st.integers(min_value=0), value=VALUES)
def test_a_mutated_scene_is_one_line(name, pick, value):
    """Any value of a ``[scene]`` (a pair's lumped 3D one with a flexible gear, a train's with
    its shafts, bearings and a flexible idler), down to a bearing's key, given any TOML value
    through the case reader: the case loads or one SchemaError line, never another
    exception."""
    data = _case(name)
    paths = list(_paths(data["scene"]))
    path = ("scene", *paths[pick % len(paths)])
    table = data
    for part in path[:-1]:
        table = table[part]
    table[path[-1]] = value
    try:
        _load(data, name)
    except sc.SchemaError as err:
        assert "\n" not in str(err) and str(err).strip() == str(err), str(err)


@pytest.mark.parametrize(("name", "path", "value", "words"), [
    ("accessory-spur-flexible", ("scene",), 3,
     "scene = 3: must be a table ([scene]), not a number"),
    ("two-stage", ("scene",), "lumped", "scene = 'lumped': must be a table ([scene]), not a string"),
    ("accessory-spur-flexible", ("scene", "pinion_shaft"), 3,
     "[scene] pinion_shaft = 3: must be a table ([scene.pinion_shaft]), not a number"),
    ("accessory-spur-flexible", ("scene", "gear_body"), True,
     "[scene] gear_body = true: must be a table ([scene.gear_body]), not a boolean"),
    ("accessory-spur-flexible", ("scene", "pinion_shaft", "bearings"), 1,
     ("[scene.pinion_shaft] bearings = 1: must be a non-empty array of tables, e.g. "
      "[{ position_mm = 0.0, radial_N_per_um = 200.0 }]")),
    ("accessory-spur-flexible", ("scene", "pinion_shaft", "bearings", 1), 2.0,
     ("[scene.pinion_shaft] 'bearings[1]' = 2: must be a table "
      "([scene.pinion_shaft.bearings[1]]), not a number")),
    ("accessory-spur-flexible", ("scene", "damping"), 0.05,
     "[scene] damping = 0.05: must be a table ([scene.damping]), not a number"),
    ("two-stage", ("scene", "shafts"), 1,
     "[scene] shafts = 1: must be an array of tables ([[scene.shafts]]), not a number"),
    ("two-stage", ("scene", "shafts", 0), "input",
     "[scene] 'shafts[0]' = 'input': must be a table ([[scene.shafts]] entry), not a string"),
    ("two-stage", ("scene", "shafts", 1, "gear_positions_mm"), 50.0,
     ("[scene.shafts.intermediate] gear_positions_mm = 50: must be a table "
      "([scene.shafts.intermediate.gear_positions_mm]), not a number")),
    ("two-stage", ("scene", "shafts", 1, "bearings"), [],
     "[scene.shafts.intermediate] bearings = []: must be a non-empty array of tables"),
    ("two-stage", ("scene", "inertias_kg_m2"), 1e-3,
     "[scene] inertias_kg_m2 = 0.001: must be a table ([scene.inertias_kg_m2]), not a number"),
    ("two-stage", ("scene", "masses_kg"), [1.0],
     "[scene] masses_kg = [1]: must be a table ([scene.masses_kg]), not an array"),
    ("flexible-idler", ("scene", "bodies"), 3,
     "[scene] bodies = 3: must be a table ([scene.bodies]), not a number"),
    ("flexible-idler", ("scene", "bodies", "idler"), "accessory-idler",
     ("[scene.bodies] idler = 'accessory-idler': must be a table ([scene.bodies.idler]), not a "
      "string")),
])
def test_a_scene_table_given_as_a_value_is_one_line(name, path, value, words):
    """A ``[scene]`` table (or an array of tables, or an entry of one) given as a number, a
    string, a boolean or an array, through the case reader: the one line naming it."""
    data = _case(name)
    table = data
    for part in path[:-1]:
        table = table[part]
    table[path[-1]] = value
    with pytest.raises(sc.SchemaError) as err:
        _load(data, name)
    assert str(err.value).startswith(words), str(err.value)
    assert "\n" not in str(err.value)


def _set(path, value):
    def change(data):
        table = data["scene"]
        for part in path[:-1]:
            table = table[part]
        if value is None:
            del table[path[-1]]
        else:
            table[path[-1]] = value
    return change


@pytest.mark.parametrize(("name", "change", "words"), [
    ("accessory-spur-flexible", _set(("pinion_shaft", "gear_position_mm"), -1.0),
     ("[scene.pinion_shaft] gear_position_mm = -1: out of range, allowed [0, 100] (not beyond "
      "the shaft length)")),
    ("accessory-spur-flexible", _set(("gear_shaft", "torque_position_mm"), 101.0),
     ("[scene.gear_shaft] torque_position_mm = 101: out of range, allowed [0, 100] (not beyond "
      "the shaft length)")),
    ("accessory-spur-flexible", _set(("gear_shaft", "length_mm"), 40.0),  # the first beyond
     ("[scene.gear_shaft] gear_position_mm = 50: out of range, allowed [0, 40] (not beyond the "
      "shaft length)")),
    ("accessory-spur-flexible", _set(("pinion_shaft", "bearings", 1, "position_mm"), 100.5),
     ("[scene.pinion_shaft.bearings[1]] position_mm = 100.5: out of range, allowed [0, 100] "
      "(not beyond the shaft length)")),
    ("accessory-spur-flexible", _set(("pinion_shaft", "bearings", 1, "radial_N_per_um"), 1e-4),
     ("[scene.pinion_shaft.bearings[1]] radial_N_per_um = 0.0001: out of range, allowed 0 "
      "(free) or [0.001, 1e+09]")),
    ("accessory-spur-flexible", _set(("pinion_shaft", "bearings", 0, "tilt_Nm_per_rad"), 0.5),
     ("[scene.pinion_shaft.bearings[0]] tilt_Nm_per_rad = 0.5: out of range, allowed 0 (free) "
      "or [1, 1e+15]")),
    ("accessory-spur-flexible", _set(("pinion_shaft", "bearings", 0, "axial_N_per_um"), 0.0),
     ("[scene.pinion_shaft] bearings: needs an axial stiffness on at least one bearing "
      "(axial_N_per_um > 0 or stiffness_matrix_SI[2][2] > 0)")),
    ("accessory-spur-flexible", _set(("pinion_shaft", "bearings", 1, "position_mm"), 0.5),
     ("[scene.pinion_shaft] bearings: radial bearings at position_mm = 0 to 0.5, allowed at "
      "least 1 mm apart")),
    ("accessory-spur-flexible", _set(("pinion_shaft", "elements"), 0),
     "[scene.pinion_shaft] elements = 0: out of range, allowed [1, 1000]"),
    ("accessory-spur-flexible", _set(("pinion_shaft", "bore_mm"), 10.0),
     "[scene.pinion_shaft] unknown key 'bore_mm', allowed: bearings, diameter_mm, elements, "),
    ("accessory-spur-flexible", _set(("gear_shaft",), None),
     "[scene] model = 'lumped3d' needs a [scene.gear_shaft] table"),
    ("accessory-spur-flexible", _set(("model",), "torsional"),
     "[scene] pinion_shaft: is for model = 'lumped3d'"),
    ("accessory-spur-flexible", _set(("motor_inertia_kg_m2",), 1.0),
     "[scene] motor_inertia_kg_m2: is for model = 'torsional'"),
    ("accessory-spur-flexible", _set(("gear_body", "body"), 3),
     "[scene.gear_body] body = 3: must be a non-empty string"),
    ("accessory-spur-flexible", _set(("gear_body", "body"), "no-such-body"),
     "[scene.gear_body] body = 'no-such-body': allowed an embedded body ("),
    ("accessory-spur-flexible", _set(("pinion_mass_kg",), 0.0),
     "[scene] pinion_mass_kg = 0: out of range, allowed [1e-06, 1e+09]"),
    ("fzg-h951", lambda d: d.__setitem__("scene", {"motor_inertia_kg_m2": 0.01}),
     ("[scene] motor_inertia_kg_m2 and motor_shaft_stiffness_Nm_per_rad go together: give both "
      "or neither")),
    ("fzg-h951", lambda d: d.__setitem__("scene", {"gear_inertia_kg_m2": 0.0}),
     "[scene] gear_inertia_kg_m2 = 0: out of range, allowed [1e-09, 1e+15]"),
    ("fzg-h951", lambda d: d.__setitem__("scene", {"integration": {"modal_basis": 12}}),
     ("[scene.integration] modal_basis = 12: allowed only with a condensed body ([scene] "
      "pinion_body or gear_body)")),
    ("two-stage", _set(("inertias_kg_m2",), {"input": 1e-3, "idler": 1e-3}),
     "[scene.inertias_kg_m2] unknown key 'idler', allowed: hst-wheel, input, lst-pinion, output"),
    ("two-stage", _set(("inertias_kg_m2",), {"input": 1e16}),
     "[scene.inertias_kg_m2] input = 1e+16: out of range, allowed [1e-09, 1e+15]"),
    ("two-stage", _set(("masses_kg",), {"output": "heavy"}),
     "[scene.masses_kg] output = 'heavy': must be a number, not a string"),
    ("two-stage", _set(("shafts", 2, "shaft"), "spindle"),
     "[scene.shafts[2]] shaft = 'spindle': no such shaft, allowed input, intermediate, output"),
    ("two-stage", _set(("shafts", 2, "shaft"), "input"),
     "[scene.shafts[2]] shaft = 'input': has a [[scene.shafts]] entry already"),
    ("two-stage", _set(("shafts", 1, "gear_positions_mm", "input"), 10.0),
     ("[scene.shafts.intermediate.gear_positions_mm] unknown key 'input', allowed: hst-wheel, "
      "lst-pinion")),
    ("two-stage", _set(("shafts", 1, "gear_positions_mm", "lst-pinion"), None),
     "[scene.shafts.intermediate.gear_positions_mm] lst-pinion: missing required key"),
    ("two-stage", _set(("shafts", 1, "length_mm"), 1e6),
     "[scene.shafts.intermediate] length_mm = 1e+06: out of range, allowed [1, 100000]"),
    ("two-stage", _set(("shafts", 1, "bearings", 0, "stiff"), 1.0),
     "[scene.shafts.intermediate.bearings[0]] unknown key 'stiff', allowed: arrangement, "
     "axial_N_per_um, "),
    ("two-stage", _set(("shafts",), None),
     ("[scene] model = 'lumped3d' needs [[scene.shafts]], one per shaft: input, intermediate, "
      "output")),
    ("two-stage", _set(("model",), "torsional"), "[scene] masses_kg: is for model = 'lumped3d'"),
    ("flexible-idler", _set(("bodies", "idler", "gears"), 3),
     "[scene.bodies.idler] gears = 3: must list the gears of shaft 'idler' (idler), one per "),
    ("flexible-idler", _set(("bodies", "idler", "gears"), ["input"]),
     "[scene.bodies.idler] gears = ['input']: must list the gears of shaft 'idler' (idler)"),
    ("flexible-idler", _set(("bodies", "spindle"), {"body": "accessory-idler"}),
     "[scene.bodies] unknown key 'spindle', allowed: idler, input, output"),
    ("flexible-idler", _set(("bodies", "idler", "body"), None),
     "[scene.bodies.idler] body: missing required key"),
])
def test_the_scene_words(name, change, words):
    """``[scene]``'s refusals through the case reader, in the hand-written checks' words: the
    positions on a shaft within its length, a bearing's stiffness 0 or above its floor, the
    bearings that hold a shaft, the keys of one model, the tables by gear or shaft name."""
    data = _case(name)
    if name == "two-stage":
        assert "masses_kg" not in data["scene"]
        data["scene"]["masses_kg"] = {"input": 1.0}
    change(data)
    with pytest.raises(sc.SchemaError) as err:
        _load(data, name)
    assert str(err.value).startswith(words), str(err.value)
    assert "\n" not in str(err.value)


def test_the_scene_sections_give_the_scene():
    """The typed sections give the scene the file says, in SI: a pair's shafts (mm → m,
    N/µm → N/m, the diagonal bearing's defaults 200 N/µm radial, 0 axial and tilt), its body,
    inertias and masses; a train's shafts in shaft order (the file's in another), each gear's
    centre in gear order, its inertias and masses by gear (None where not given)."""
    spec = jio.parse_scene({"model": "lumped3d", "pinion_shaft": _SHAFT | {
        "bearings": [{"position_mm": 0.0, "axial_N_per_um": 50}, {"position_mm": 1.0}]},
        "gear_shaft": _SHAFT | {"torque_position_mm": 100.0, "elements": 6.0},
        "pinion_mass_kg": 1.5, "gear_inertia_kg_m2": 5e-3})
    b0, b1 = spec.pinion_shaft.bearings
    assert (b0.z, b0.radial, b0.axial, b0.tilt) == (0.0, 2e8, 5e7, 0.0)
    assert (b1.z, b1.radial, b1.axial) == (1e-3, 2e8, 0.0)
    g = spec.gear_shaft
    assert (g.length, g.diameter, g.gear_z, g.torque_z) == (0.1, 0.03, 0.5e-3, 0.1)
    assert g.elements == 6 and type(g.elements) is int
    assert (spec.pinion_mass, spec.gear_mass, spec.gear_inertia) == (1.5, None, 5e-3)
    data = _case("two-stage")
    data["scene"]["shafts"].reverse()
    data["scene"]["inertias_kg_m2"] = {"output": 2e-3}
    data["scene"]["masses_kg"] = {"lst-pinion": 0.7}
    case = _load(data, "two-stage")
    shafts = {s["shaft"]: s for s in data["scene"]["shafts"]}
    for spec, name in zip(case.scene.shafts, ("input", "intermediate", "output"), strict=True):
        want = shafts[name]["gear_positions_mm"]
        gears = [g for g, s in zip(case.gear_names, case.shaft_of, strict=True)
                 if case.shaft_names[s] == name]
        assert spec.gear_positions == pytest.approx([want[g] * 1e-3 for g in gears], rel=1e-15)
        assert spec.length == pytest.approx(shafts[name]["length_mm"] * 1e-3, rel=1e-15)
    inertia = dict(zip(case.gear_names, case.inertias, strict=True))
    assert inertia["output"] == 2e-3
    assert dict(zip(case.gear_names, case.masses, strict=True))["lst-pinion"] == 0.7
