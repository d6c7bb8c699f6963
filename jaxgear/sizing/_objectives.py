"""What a designer ranks sizing candidates by, as columns of the table: the blanks' mass and the
least safety margin (the rating's), the envelope's volume and the mesh's power loss and
efficiency (:func:`objective_columns`); the objectives a Pareto front may take, each a column
with its natural sense (:data:`OBJECTIVES`).

The mesh loss is ISO/TR 14179-2:2001's closed form at the spec's operating point, per candidate,
on NumPy columns (no compiled program: a few array operations for the whole table):

    P_VZP = μ_mZ H_V P_in,    η_Z = 1 − P_VZP/P_in = 1 − μ_mZ H_V,

μ_mZ the friction law's mean coefficient at the pitch point (:class:`jaxgear.tribology.Schlenk`
or a given μ, :meth:`jaxgear.tribology.AbstractFriction.at_pitch_point`), H_V Ohlendorf's tooth
loss factor (:func:`jaxgear.tribology.ohlendorf_formula`), P_in = T₁ ω₁. It is the sliding loss
of the teeth only (no churning, bearing or seal losses) and assumes the load shared evenly by the
pairs in contact; ``jaxgear run`` with a ``[lubricant]`` integrates jaxgear's own load sharing
instead (docs/tribology.md), and reports the same μ_mZ and Ohlendorf's H_V of the pair.
"""

from __future__ import annotations

import dataclasses
import math

import equinox as eqx
import numpy as np
from jaxtyping import Array, Float

from .._util import as_float, check_instance, check_real
from ..tribology import (
    AbstractBulkTemperature,
    AbstractFriction,
    FlashBulkTemperature,
    Lubricant,
    ScuffingLimits,
    ohlendorf_formula,
)

__all__ = ["MESH_LOSS_COLUMNS", "OBJECTIVES", "SCUFFING_COLUMNS", "STAGE_OBJECTIVES",
           "MeshLossInputs", "ScuffingRequirement", "envelope_volume", "objective_columns"]

#: the objectives a sizing may rank by: column → (its natural sense, "min" or "max"; the words
#: and unit of a plot's axis; the factor from the column's SI unit to the axis's). A new column
#: of the table (a later stage's) becomes an objective by an entry here.
OBJECTIVES = {
    "mass_kg": ("min", "blanks' mass (kg)", 1.0),
    "volume_m3": ("min", "envelope volume (dm³)", 1e3),
    "least_margin": ("max", "least margin min(S/S_min)", 1.0),
    "mesh_loss_W": ("min", "mesh power loss P_VZP (W)", 1.0),
    "efficiency": ("max", "mesh efficiency η_Z (%)", 100.0),
    # the scuffing rating's (with the spec's scuffing keys: SCUFFING_COLUMNS)
    "S_B": ("max", "scuffing safety factor S_B (ISO/TS 6336-20)", 1.0),
    # the transmission-error stage's (jaxgear.sizing.te_stage): NaN, so off the front, for the
    # candidates it did not evaluate
    "te_ppk_m": ("min", "TE peak-to-peak, plain flanks (µm)", 1e6),
    "te_ppk_modified_m": ("min", "TE peak-to-peak, optimised flanks (µm)", 1e6),
    # the dynamics stage's (jaxgear.sizing.dynamics_stage): NaN, so off the front, for the
    # candidates it did not run
    "dynamic_factor_max": ("min", "largest dynamic factor K_v over the speed range", 1.0),
    "dynamic_factor_at_speed": ("min", "dynamic factor K_v at the spec's speed", 1.0),
    "whine_force_N": ("min", "whine: dynamic mesh force, orders 1-3, RMS (N)", 1.0),
    # the sound stage's (jaxgear size with [sound]): NaN, so off the front, for the candidates
    # it did not run
    "erp_peak_dB": ("min", "housing's overall ERP, largest over the speeds (dB re 1 pW)", 1.0),
    # with [sound] sound_power = true: the radiated sound power (BEM, jaxgear run's [acoustics])
    "sound_power_peak_dB": ("min", "housing's overall sound power L_W, largest over the speeds "
                            "(dB re 1 pW)", 1.0),
}

#: the objectives a later stage adds, by stage (``"te"``: :func:`jaxgear.sizing.te_stage`,
#: ``"dynamics"``: :func:`jaxgear.sizing.dynamics_stage`, ``"sound"``: ``jaxgear size``'s sound
#: stage of a spec with ``[sound]``, docs/sizing.md): only the candidates that stage runs
#: have them, so a front over one needs the stage on (the spec reader and ``jaxgear size``
#: refuse it with the stage's candidates 0)
STAGE_OBJECTIVES = {
    "te": ("te_ppk_m", "te_ppk_modified_m"),
    "dynamics": ("dynamic_factor_max", "dynamic_factor_at_speed", "whine_force_N"),
    "sound": ("erp_peak_dB", "sound_power_peak_dB"),
}

#: the columns of the mesh loss (with :attr:`SizingSpec.mesh_loss <jaxgear.sizing.SizingSpec>`):
#: μ_mZ, Ohlendorf's H_V, P_VZP (W), η_Z
MESH_LOSS_COLUMNS = ("friction_coefficient", "loss_factor", "mesh_loss_W", "efficiency")
#: the columns of the scuffing rating (with :attr:`SizingSpec.scuffing
#: <jaxgear.sizing.SizingSpec>`; :func:`jaxgear.tribology.ts_scuffing`): S_B, θ_B,max (°C),
#: θ_fl,max (K), θ_M (°C), μ_mC, S_intS (the integral method's, reported, not a check)
SCUFFING_COLUMNS = ("S_B", "theta_B_max_C", "theta_fl_max_K", "theta_M_C", "mu_mC", "S_intS")


@dataclasses.dataclass(frozen=True)
class MeshLossInputs:
    """What the mesh loss of a sizing needs beyond the candidate and the operating point.

    Attributes:
        lubricant: the oil at its temperature (:class:`jaxgear.tribology.Lubricant`).
        roughness: (R_a1, R_a2), the flanks' arithmetic mean roughness (m), each > 0.
        friction: the friction law (:class:`jaxgear.tribology.AbstractFriction`: Schlenk's
            μ_mZ, or a given μ).
    """

    lubricant: Lubricant
    roughness: tuple[float, float]
    friction: AbstractFriction

    def __post_init__(self):
        w = "MeshLossInputs"
        check_instance("lubricant", self.lubricant, Lubricant, "a jaxgear.tribology.Lubricant", w)
        check_instance("friction", self.friction, AbstractFriction,
                       "a jaxgear.tribology friction kind", w)
        r = self.roughness
        if not (len(r) == 2 and all(float(v) > 0 for v in r)):
            raise ValueError(f"{w}: roughness = {r!r} is out of range: allowed (R_a1, R_a2), "
                             "each > 0 (m)")


class ScuffingRequirement(eqx.Module):
    """What the scuffing check of a sizing needs beyond the candidate and the operating point
    (the closed form of ISO/TS 6336-20, :func:`jaxgear.tribology.ts_scuffing`).

    Attributes:
        lubricant: the oil at its temperature θ_oil (:class:`jaxgear.tribology.Lubricant`).
        roughness: (R_a1, R_a2) (m), each > 0 (μ_mC's X_R).
        limits: θ_S (from the oil's FZG load stage) and θ_intS
            (:class:`jaxgear.tribology.ScuffingLimits`).
        bulk: the bulk-temperature rule (:class:`jaxgear.tribology.AbstractBulkTemperature`;
            default ISO/TS 6336-20's, X_S = 1).
        min_safety: S_Bmin, the least S_B a candidate may have (> 0; default 1).
    """

    lubricant: Lubricant
    roughness: Float[Array, 2]
    limits: ScuffingLimits
    bulk: AbstractBulkTemperature
    min_safety: Float[Array, ""]

    def __init__(self, lubricant, roughness, limits, bulk=None, min_safety=1.0):
        w = "ScuffingRequirement"
        check_instance("lubricant", lubricant, Lubricant, "a jaxgear.tribology.Lubricant", w)
        check_instance("limits", limits, ScuffingLimits, "a jaxgear.tribology.ScuffingLimits", w)
        bulk = FlashBulkTemperature() if bulk is None else bulk
        check_instance("bulk", bulk, AbstractBulkTemperature, "a bulk-temperature kind", w)
        check_real("roughness", roughness, "m", lo=0.0, lo_open=True, shape=(2,), where=w)
        check_real("min_safety", min_safety, "", lo=0.0, lo_open=True, where=w)
        self.lubricant, self.limits, self.bulk = lubricant, limits, bulk
        self.roughness = as_float(roughness)
        self.min_safety = as_float(min_safety)


def envelope_volume(tip_diameter_1, tip_diameter_2, centre_distance, face_width):
    """The volume (m³) of the box that holds the pair's tip cylinders: (a + (d_a1 + d_a2)/2) ·
    max(d_a1, d_a2) · b; the space the stage takes, without housing or shafts. Arrays of one
    shape (m)."""
    length = centre_distance + (tip_diameter_1 + tip_diameter_2) / 2
    return length * np.maximum(tip_diameter_1, tip_diameter_2) * face_width


def objective_columns(spec, columns: dict, invalid: np.ndarray) -> dict:
    """The objective columns of a sizing table beyond the rating's: ``volume_m3``
    (:func:`envelope_volume`) and, where ``spec.mesh_loss`` is given, :data:`MESH_LOSS_COLUMNS`
    (the module docstring), NaN where ``invalid`` (no valid geometry).

    Args:
        spec: the :class:`jaxgear.sizing.SizingSpec` (its angles, operating point, mesh loss).
        columns: the table's columns (SI): teeth, face width, centre distance, reference and tip
            diameters, operating pressure angle, ε_α.
        invalid: (n,) True where the candidate's geometry is invalid.
    """
    c = columns
    out = {"volume_m3": envelope_volume(c["tip_diameter_1_m"], c["tip_diameter_2_m"],
                                        c["centre_distance_m"], c["face_width_m"])}
    if spec.mesh_loss is None:
        return out
    with np.errstate(invalid="ignore", divide="ignore"):
        values = _mesh_loss(spec, c)
    return out | {k: np.where(invalid, np.nan, v) for k, v in values.items()}


def _mesh_loss(spec, c: dict) -> dict:
    """μ_mZ, H_V, P_VZP, η_Z of every row (the module docstring), from the pitch point and the
    addendum contact ratios of the columns' geometry (ISO 21771)."""
    inputs = spec.mesh_loss
    an, beta = spec.normal_pressure_angle, c["helix_angle_rad"]  # each row's β (refined)
    at = np.arctan(math.tan(an) / np.cos(beta))
    z1, z2 = c["z1"].astype(float), c["z2"].astype(float)
    rb1 = c["reference_diameter_1_m"] / 2 * np.cos(at)
    rb2 = c["reference_diameter_2_m"] / 2 * np.cos(at)
    awt, a = c["operating_pressure_angle_rad"], c["centre_distance_m"]
    tip1 = np.sqrt((c["tip_diameter_1_m"] / 2) ** 2 - rb1**2)
    tip2 = np.sqrt((c["tip_diameter_2_m"] / 2) ** 2 - rb2**2)
    line = a * np.sin(awt)  # T1T2
    path = tip1 + tip2 - line  # g_α
    pitch = rb1 * np.tan(awt) - (line - tip2)  # s_C from the path's start (the gear's tip)
    p_bt = 2 * math.pi * rb1 / z1
    e1, e2 = (path - pitch) / p_bt, pitch / p_bt
    beta_b = np.arctan(np.tan(beta) * np.cos(at))
    h_v = ohlendorf_formula(z2 / z1, z1, np.cos(beta_b), c["eps_alpha"], e1, e2)
    torque, speed = float(spec.operating.torque), float(spec.operating.speed)
    rho1, rho2 = rb1 * np.tan(awt), rb2 * np.tan(awt)
    lub, ra = inputs.lubricant, inputs.roughness
    mu = np.asarray(inputs.friction.at_pitch_point(
        torque / rb1 / c["face_width_m"], 2.0 * speed * rho1, rho1 * rho2 / (rho2 + rho1),
        float(lub.dynamic_viscosity), 0.5 * (float(ra[0]) + float(ra[1]))), dtype=float)
    p_in = torque * speed
    loss = mu * h_v * p_in
    return {"friction_coefficient": mu, "loss_factor": h_v, "mesh_loss_W": loss,
            "efficiency": 1.0 - loss / p_in}
