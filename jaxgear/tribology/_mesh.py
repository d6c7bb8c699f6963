"""Film, friction and sliding loss along the path of contact of one mesh, from the line loads of
a contact solve (:func:`jaxgear.quasi_static`), at an operating point (torque, speed).

Kinematics at a cell of base-plane coordinate s (transverse section, pinion speed ω₁ > 0, gear
speed ω₂ = ω₁/|u|): roll distances ρ₁ = ρ_A + s and ρ₂ (:meth:`jaxgear.GearPair.roll_distance`),
the flanks' surface speeds v₁ = ω₁ ρ₁, v₂ = ω₂ ρ₂, the entrainment speed u = (v₁ + v₂)/2 and the
sliding speed v_g = |v₁ − v₂| (zero at the pitch point). The relative radius R in the normal
section is :func:`jaxgear.relative_radius`; the Hertz pressure p₀ = √(w E*/(π R)) is
:func:`jaxgear.contact_pressure`'s.

The local sliding loss per unit contact length is q = μ w v_g (W/m); the mesh's loss at a
position is P(θ) = Σ q l over the cells (l the cell's length along its contact line,
b/(N cos β_b)); its mean over the positions is P_VZP (the positions must sample whole mesh
periods evenly, as :func:`jaxgear.mesh_positions` does). With the input power P_in = T ω₁ the
mesh efficiency is η_Z = 1 − P_VZP/P_in and the integrated tooth loss factor
H_V = P_VZP/(μ P_in) (Wimmer's numerical H_V, with jaxgear's load sharing in place of the
rigid one), beside Ohlendorf's closed form (:func:`ohlendorf_loss_factor`).
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float

from .._geometry import AbstractGearPair
from .._pressure import contact_modulus, relative_radius
from .._quasi_static import MeshResult, QuasiStaticResult
from .._util import check_instance, check_real, safe_max
from ._film import AbstractFilmFormula, DowsonHigginson, film_thickness
from ._loss import AbstractFriction, Schlenk, ohlendorf_loss_factor
from ._lubricant import Lubricant

__all__ = ["MeshTribology", "mesh_tribology"]


class MeshTribology(eqx.Module):
    """Film and sliding loss of one mesh along its path of contact. Cell arrays have the shape
    of the result's ``line_load``, (P, L, N); 0 where a cell carries no load (``loaded``).

    Attributes:
        loaded: cells on the flanks with a positive line load, (P, L, N).
        cell_s: the cells' base-plane coordinates s (m), the result's.
        line_load: w (N/m), the result's (0 off the flanks).
        entrainment_speed: u = (v₁ + v₂)/2 (m/s). sliding_speed: v_g = |v₁ − v₂| (m/s).
        radius: R, relative radius of curvature in the normal section (m).
        max_pressure: Hertz p₀ (Pa).
        central_film, minimum_film: h_c, h_min (m) by the film formula.
        specific_film: λ = h_min / R_a, R_a = (R_a1 + R_a2)/2 (ISO/TS 6336-22:2018's λ_GF,Y uses
            the arithmetic mean of the flanks' R_a), (-).
        local_loss: q = μ w v_g (W/m).
        power_loss: P(θ) = Σ q l (W), shape (P,).
        friction_coefficient: μ (-). input_power: P_in = T ω₁ (W).
        mean_power_loss: P_VZP (W). efficiency: η_Z = 1 − P_VZP/P_in (-).
        loss_factor: H_V = P_VZP/(μ P_in) (-), the integrated one.
        ohlendorf_loss_factor: Ohlendorf's H_V (-), closed form.
    """

    loaded: Bool[Array, "P L N"]
    cell_s: Float[Array, "P L N"]
    line_load: Float[Array, "P L N"]
    entrainment_speed: Float[Array, "P L N"]
    sliding_speed: Float[Array, "P L N"]
    radius: Float[Array, "P L N"]
    max_pressure: Float[Array, "P L N"]
    central_film: Float[Array, "P L N"]
    minimum_film: Float[Array, "P L N"]
    specific_film: Float[Array, "P L N"]
    local_loss: Float[Array, "P L N"]
    power_loss: Float[Array, " P"]
    friction_coefficient: Float[Array, ""]
    input_power: Float[Array, ""]
    mean_power_loss: Float[Array, ""]
    efficiency: Float[Array, ""]
    loss_factor: Float[Array, ""]
    ohlendorf_loss_factor: float

    @property
    def min_specific_film(self) -> Float[Array, ""]:
        """The smallest λ over the loaded cells (-) (differentiable: :func:`safe_max`'s rule)."""
        return -safe_max(jnp.where(self.loaded, -self.specific_film, -jnp.inf))

    @property
    def min_film(self) -> Float[Array, ""]:
        """The smallest h_min over the loaded cells (m)."""
        return -safe_max(jnp.where(self.loaded, -self.minimum_film, -jnp.inf))

    def summary(self) -> dict:
        """Scalars as a JSON-ready dict (SI units)."""
        return {
            "friction_coefficient": float(self.friction_coefficient),
            "input_power_W": float(self.input_power),
            "mean_power_loss_W": float(self.mean_power_loss),
            "efficiency": float(self.efficiency),
            "loss_factor_integrated": float(self.loss_factor),
            "loss_factor_ohlendorf": float(self.ohlendorf_loss_factor),
            "min_specific_film": float(self.min_specific_film),
            "min_film_m": float(self.min_film),
            "max_central_film_m": float(jnp.max(jnp.where(self.loaded, self.central_film, 0.0))),
            "max_pressure_Pa": float(jnp.max(self.max_pressure)),
            "max_local_loss_W_m": float(jnp.max(self.local_loss)),
        }


def mesh_tribology(
    pair: AbstractGearPair,
    result,
    lubricant: Lubricant,
    torque,
    speed,
    roughness,
    youngs_modulus,
    poisson_ratio,
    *,
    film: AbstractFilmFormula | None = None,
    friction: AbstractFriction | None = None,
) -> MeshTribology:
    """Film thickness, λ and sliding loss of one mesh along its path of contact (the module
    docstring), from a contact solve's line loads. Differentiable (jit, grad) in the result's
    line loads, the lubricant's and friction law's leaves, torque and speed.

    Args:
        pair: the mesh's gear pair (its pinion driving).
        result: a result with ``line_load`` (N/m), ``cell_s`` (m), ``cell_mask`` of shape
            (P, L, N) at P positions sampling whole mesh periods evenly:
            :class:`~jaxgear.MeshResult` (``res.meshes[k]``) or a
            :class:`~jaxgear.QuasiStaticResult` of one mesh.
        lubricant: :class:`Lubricant`.
        torque: pinion torque T (N·m) > 0, the one the result was solved at.
        speed: pinion speed ω₁ (rad/s) > 0.
        roughness: (R_a1, R_a2), the flanks' arithmetic mean roughness (m), each in (0, 1e-5].
        youngs_modulus, poisson_ratio: the material of both gears (Pa, -).
        film: the film formula (None: :class:`DowsonHigginson`).
        friction: the friction law (None: :class:`Schlenk` with X_L = 1).

    Returns:
        :class:`MeshTribology`.

    Raises:
        ValueError: one line naming the argument, its value and the allowed range: a pair that
            is not a gear pair, a lubricant or formula of the wrong type, torque or speed not
            > 0, a roughness not two values in (0, 1e-5] m, a modulus not > 0, a Poisson ratio
            outside [0, 0.5).
    """
    w_ = "mesh_tribology"
    check_instance("pair", pair, AbstractGearPair, "a GearPair or InternalGearPair", w_)
    check_instance("lubricant", lubricant, Lubricant, "a jaxgear.tribology.Lubricant", w_)
    film = DowsonHigginson() if film is None else film
    check_instance("film", film, AbstractFilmFormula, "a film formula kind", w_)
    friction = Schlenk() if friction is None else friction
    check_instance("friction", friction, AbstractFriction, "a friction kind", w_)
    check_real("torque", torque, "N·m", lo=0.0, lo_open=True, shape=(), where=w_)
    check_real("speed", speed, "rad/s", lo=0.0, lo_open=True, shape=(), where=w_)
    check_real("roughness", roughness, "m", lo=0.0, hi=1e-5, lo_open=True, shape=(2,), where=w_)
    check_real("youngs_modulus", youngs_modulus, "Pa", lo=0.0, lo_open=True, where=w_)
    check_real("poisson_ratio", poisson_ratio, lo=0.0, hi=0.5, hi_open=True, where=w_)
    check_instance("result", result, (MeshResult, QuasiStaticResult),
                   "a jaxgear.MeshResult or a one-mesh jaxgear.QuasiStaticResult", w_)
    return _tribology(
        pair,
        result.line_load,
        result.cell_s,
        result.cell_mask,
        lubricant,
        jnp.asarray(torque),
        jnp.asarray(speed),
        jnp.asarray(roughness),
        youngs_modulus,
        poisson_ratio,
        film,
        friction,
    )


@eqx.filter_jit
def _tribology(pair, line_load, s, mask, lub, torque, speed, ra, E, nu, film, friction):
    """:func:`mesh_tribology` on the result's arrays: one compiled program."""
    dtype = line_load.dtype
    loaded = mask & (line_load > 0.0)
    w = jnp.where(loaded, line_load, 1.0)  # a safe value where masked (no NaN tangents)
    s_safe = jnp.where(mask, s, 0.5 * pair.path_of_contact)
    omega2 = speed / abs(pair.gear_ratio)
    v1 = speed * pair.roll_distance(s_safe, 0)
    v2 = omega2 * pair.roll_distance(s_safe, 1)
    u = 0.5 * (v1 + v2)
    vg = jnp.abs(v1 - v2)
    R = jnp.maximum(relative_radius(pair, s_safe), 1e-9)
    e_star = contact_modulus(E, nu)
    eta = lub.dynamic_viscosity
    h = film_thickness(film, R, u, w, eta, lub.pressure_viscosity, e_star)
    ra_mean = 0.5 * (ra[0] + ra[1])
    mu = jnp.asarray(friction.coefficient(pair, lub, torque, speed, ra), dtype)
    zero = jnp.zeros((), dtype)
    q = jnp.where(loaded, mu * w * vg, zero)
    n_slices = line_load.shape[-1]
    length = pair.face_width / (n_slices * jnp.cos(pair.base_helix_angle))
    power = jnp.sum(q, axis=(-2, -1)) * length
    p_in = torque * speed
    p_vzp = jnp.mean(power)
    return MeshTribology(
        loaded=loaded,
        cell_s=s,
        line_load=jnp.where(loaded, line_load, zero),
        entrainment_speed=jnp.where(mask, u, zero),
        sliding_speed=jnp.where(mask, vg, zero),
        radius=jnp.where(mask, R, zero),
        max_pressure=jnp.where(loaded, jnp.sqrt(w * e_star / (jnp.pi * R)), zero),
        central_film=jnp.where(loaded, h.central, zero),
        minimum_film=jnp.where(loaded, h.minimum, zero),
        specific_film=jnp.where(loaded, h.minimum / ra_mean, zero),
        local_loss=q,
        power_loss=power,
        friction_coefficient=mu,
        input_power=p_in,
        mean_power_loss=p_vzp,
        efficiency=1.0 - p_vzp / p_in,
        loss_factor=p_vzp / (mu * p_in),
        ohlendorf_loss_factor=ohlendorf_loss_factor(pair),
    )
