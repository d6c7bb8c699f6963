"""Load capacity of an external spur or helical pair: ISO 6336-2 (pitting) and ISO 6336-3 (tooth
bending), method B, with the load factors of ISO 6336-1 method B; pure, jit-able and
differentiable ``jax.numpy`` functions of the pair's macro geometry
(:class:`jaxgear.RatingGeometry`), an operating point (:class:`OperatingPoint`: torque and speed,
an argument, never a field of the settings) and the settings (:class:`RatingSettings`: material,
lubrication, accuracy, life, application factor and any given load factors).

Pitting (ISO 6336-2:2019)::

    σ_H0 = Z_H Z_E Z_ε Z_β √(F_t (u + 1) / (d₁ b u))            F_t = 2 T₁ / d₁
    σ_H  = Z_B,D σ_H0 √(K_A K_v K_Hβ K_Hα)                       (pinion Z_B, gear Z_D)
    σ_HG = σ_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X,  σ_HP = σ_HG / S_Hmin,  S_H = σ_HG / σ_H

Bending (ISO 6336-3:2019; Y_F, Y_S: :func:`jaxgear.rating.tooth_form_factors`)::

    σ_F0 = F_t / (b m_n) Y_F Y_S Y_β Y_B Y_DT,   σ_F = σ_F0 K_A K_v K_Fβ K_Fα
    σ_FG = σ_Flim Y_ST Y_NT Y_δrelT Y_RrelT Y_X Y_M,  σ_FP = σ_FG / S_Fmin,  S_F = σ_FG / σ_F

Load factors (ISO 6336-1:2019): K_v method B (clause 6, the resonance ratio N from c_γα and the
reduced mass of solid blanks), K_Hβ from the helix slope deviation (clause 7, F_βx = f_Hβ: no shaft
deflection, no helix correction, no adjustment), K_Fβ = K_Hβ^N_F (clause 7), K_Hα = K_Fα
method B (clause 8); a factor given in :class:`GivenFactors` replaces the computed one (and the
factors computed after it use the given value). Each factor reports its source.
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array

from ._bending import ToothFormFactors
from ._factors import (
    LoadFactors,
    _contact_ratio_factor,
    _tangential_load,
    check_rating_arguments,
    load_factors,
)
from ._geometry import RatingGeometry
from ._settings import OperatingPoint, RatingSettings, factor_clause
from .._util import as_float

__all__ = ["BendingRating", "PittingRating", "Rating", "bending_rating", "pitting_rating", "rate"]

METHOD = "ISO 6336:2019 method B"
Y_ST = 2.0  # ISO 6336-3: stress correction factor of the reference test gears


class PittingRating(eqx.Module):
    """ISO 6336-2 results: scalars Z_H, Z_E (√Pa), Z_epsilon, Z_beta, Z_L, Z_v, Z_R, Z_X,
    sigma_H0 (Pa); per gear (2,) Z_BD (Z_B, Z_D), Z_NT, Z_W (work hardening, ISO 6336-2 clause
    13: 1 but for a through-hardened gear against a surface-hardened one), sigma_H, sigma_HG, sigma_HP (Pa), S_H,
    cycles N_L."""

    Z_H: Array
    Z_E: Array
    Z_epsilon: Array
    Z_beta: Array
    Z_BD: Array
    Z_NT: Array
    Z_L: Array
    Z_v: Array
    Z_R: Array
    Z_W: Array
    Z_X: Array
    sigma_H0: Array
    sigma_H: Array
    sigma_HG: Array
    sigma_HP: Array
    S_H: Array
    cycles: Array


class BendingRating(eqx.Module):
    """ISO 6336-3 results, per gear (2,): Y_F, Y_S, Y_B, Y_NT, Y_delta_rel_T, Y_R_rel_T, Y_X,
    Y_M (mean stress influence factor, :class:`jaxgear.ToothLoading`), sigma_F0, sigma_F,
    sigma_FG, sigma_FP (Pa), S_F; scalars Y_beta, Y_DT, Y_ST; ``form`` the
    :class:`jaxgear.rating.ToothFormFactors`."""

    Y_F: Array
    Y_S: Array
    Y_beta: Array
    Y_B: Array
    Y_DT: Array
    Y_ST: Array
    Y_NT: Array
    Y_delta_rel_T: Array
    Y_R_rel_T: Array
    Y_X: Array
    Y_M: Array
    sigma_F0: Array
    sigma_F: Array
    sigma_FG: Array
    sigma_FP: Array
    S_F: Array
    form: ToothFormFactors


class Rating(eqx.Module):
    """A whole rating: ``factors`` (:class:`LoadFactors`), ``pitting`` (:class:`PittingRating`),
    ``bending`` (:class:`BendingRating`), ``method`` (the edition's label, e.g. "ISO 6336:2019
    method B"); :meth:`summary` gives the JSON section."""

    factors: LoadFactors
    pitting: PittingRating
    bending: BendingRating
    method: str = eqx.field(static=True, default=METHOD)
    #: the factors whose formula in this edition (:attr:`method`) no published worked example
    #: confirms (:attr:`jaxgear.rating.AbstractEdition.unconfirmed`: ``("Y_beta",)`` for
    #: :class:`jaxgear.rating.Edition2019`, ``()`` for :class:`jaxgear.rating.Edition2006`), attribute names
    #: of :attr:`pitting`, :attr:`bending` and :attr:`factors`, for the report to state
    unconfirmed: tuple[str, ...] = eqx.field(static=True, default=())

    def scope_notes(self) -> list[str]:
        """Where the inputs leave the standard's scope, one line each naming the part, edition and
        (where checked, :func:`jaxgear.rating.factor_clause`) clause, e.g. "ISO 6336-3:2006 9.2 rim
        thickness factor Y_B: ..." (empty when none): Y_S's 1 <= q_s < 8 (ISO 6336-3, stress
        correction factor), K_v's main
        resonance range 0.85 < N < 1.15 (ISO 6336-1, dynamic factor; noted whether K_v is
        given or computed), Y_B's rim 0.5 < s_R/h_t (ISO 6336-3, rim thickness factor; read back
        from Y_B = 1.6 ln(2.242 h_t/s_R)). Concrete values only (not under ``jit``)."""
        notes = []
        where = {k: factor_clause(k, self.method) for k in ("Y_B", "Y_S", "K_v")}
        for tag, y_b in zip(("pinion", "gear"), self.bending.Y_B.tolist(), strict=True):
            ratio = 2.242 * math.exp(-y_b / 1.6)
            if y_b > 1.0 and ratio <= 0.5:
                notes.append(
                    f"{where['Y_B']} rim thickness factor Y_B: {tag} rim s_R/h_t = {ratio:.4g} "
                    "is outside the method's scope 0.5 < s_R/h_t (thinner rims should be avoided)"
                )
        for tag, q in zip(("pinion", "gear"), self.bending.form.q_s.tolist(), strict=True):
            if not 1.0 <= q < 8.0:
                notes.append(
                    f"{where['Y_S']} stress correction factor Y_S: {tag} notch parameter q_s = "
                    f"{q:.4g} is outside the method's scope 1 <= q_s < 8"
                )
        n = float(self.factors.details["resonance_ratio_N"])
        if 0.85 < n < 1.15:
            notes.append(
                f"{where['K_v']} dynamic factor K_v: resonance ratio N = {n:.4g} in the main "
                "resonance range (0.85, 1.15), where the gears should not run (method B's K_v "
                "is not meant for it)"
            )
        return notes

    def summary(self) -> dict:
        """The ``rating`` section of ``summary.json``: SI units (stresses in Pa), per-gear values
        as [pinion, gear] lists, each load factor with its source."""

        def v(a):
            a = jnp.asarray(a)
            return [float(t) for t in a] if a.ndim else float(a)

        f, p, b = self.factors, self.pitting, self.bending
        return {
            "method": self.method,
            "factors": {
                k: {"value": v(getattr(f, k)), "source": f.sources[k]}
                for k in ("K_A", "K_v", "K_Hbeta", "K_Fbeta", "K_Halpha", "K_Falpha")
            },
            "pitting": {
                "Z_H": v(p.Z_H),
                "Z_E_sqrt_Pa": v(p.Z_E),
                "Z_epsilon": v(p.Z_epsilon),
                "Z_beta": v(p.Z_beta),
                "Z_BD": v(p.Z_BD),
                "Z_NT": v(p.Z_NT),
                "Z_L": v(p.Z_L),
                "Z_v": v(p.Z_v),
                "Z_R": v(p.Z_R),
                "sigma_H0_Pa": v(p.sigma_H0),
                "sigma_H_Pa": v(p.sigma_H),
                "sigma_HP_Pa": v(p.sigma_HP),
                "S_H": v(p.S_H),
            },
            "bending": {
                "Y_F": v(b.Y_F),
                "Y_S": v(b.Y_S),
                "Y_beta": v(b.Y_beta),
                "Y_B": v(b.Y_B),
                "Y_DT": v(b.Y_DT),
                "Y_NT": v(b.Y_NT),
                "Y_delta_rel_T": v(b.Y_delta_rel_T),
                "Y_R_rel_T": v(b.Y_R_rel_T),
                "Y_X": v(b.Y_X),
                "Y_M": v(b.Y_M),
                "sigma_F0_Pa": v(b.sigma_F0),
                "sigma_F_Pa": v(b.sigma_F),
                "sigma_FP_Pa": v(b.sigma_FP),
                "S_F": v(b.S_F),
            },
        }


# ------------------------------------------------------------------------------------------
# pitting (ISO 6336-2:2019)


def _c_zl(sigma_h_lim):
    """C_ZL of the lubricant factor Z_L (σ_Hlim of the softer gear)."""
    s = sigma_h_lim * 1e-6
    return jnp.clip(0.08 * (s - 850.0) / 350.0 + 0.83, 0.83, 0.91)


def pitting_rating(
    geometry: RatingGeometry,
    operating: OperatingPoint,
    settings: RatingSettings,
    factors: LoadFactors | None = None,
) -> PittingRating:
    """ISO 6336-2:2019 method B at the operating point (module docstring).

    Args:
        geometry: :class:`jaxgear.RatingGeometry`. operating: :class:`OperatingPoint`.
        settings: :class:`RatingSettings`. factors: the load factors (default
            :func:`load_factors` of the same arguments).

    Returns:
        :class:`PittingRating` (stresses in Pa, Z_E in √Pa).
    """
    check_rating_arguments("pitting_rating", geometry, operating, settings)
    if factors is None:
        factors = load_factors(geometry, operating, settings)
    g = geometry.derived()
    mat, lub = settings.material, settings.lubrication
    u = g.gear_ratio
    ft = _tangential_load(g, operating)
    d1, b = g.reference_diameter[0], g.face_width
    z_h = jnp.sqrt(
        2
        * jnp.cos(g.base_helix_angle)
        * jnp.cos(g.operating_pressure_angle)
        / (jnp.cos(g.transverse_pressure_angle) ** 2 * jnp.sin(g.operating_pressure_angle))
    )
    z_e = jnp.sqrt(mat.youngs_modulus / (2 * jnp.pi * (1 - mat.poisson_ratio**2)))
    z_eps = _contact_ratio_factor(g.transverse_contact_ratio, g.overlap_ratio, geometry)
    z_beta = 1 / jnp.sqrt(jnp.cos(geometry.helix_angle))
    s_h0 = z_h * z_e * z_eps * z_beta * jnp.sqrt(ft * (u + 1) / (d1 * b * u))
    k = factors.K_A * factors.K_v * factors.K_Hbeta * factors.K_Halpha
    z_bd = geometry.single_pair_factors(g)
    s_h = z_bd * s_h0 * jnp.sqrt(k)
    # permissible stress
    cycles = _cycles(settings, operating, u)
    z_nt = mat.treatment.z_nt(cycles)
    s_min = jnp.min(mat.sigma_h_lim)
    czl = _c_zl(s_min)
    nu40 = lub.viscosity_40 * 1e6  # mm²/s
    z_l = czl + 4 * (1 - czl) / (1.2 + 134.0 / nu40) ** 2
    v = operating.speed * d1 / 2
    czv = czl + 0.02
    z_v = czv + 2 * (1 - czv) / jnp.sqrt(0.8 + 32.0 / v)
    rho = g.base_diameter / 2 * jnp.tan(g.operating_pressure_angle)
    rho_red = rho[0] * rho[1] / (rho[0] + rho[1])
    rz10 = jnp.mean(lub.roughness_flank) * (10e-3 / rho_red) ** (1 / 3)
    s = s_min * 1e-6
    czr = jnp.clip(0.32 - 0.0002 * s, 0.08, 0.15)
    z_r = (3e-6 / rz10) ** czr
    z_w, z_x = mat.treatment.work_hardening_factors(), as_float(1.0)
    s_hg = mat.sigma_h_lim * z_nt * z_l * z_v * z_r * z_w * z_x
    return PittingRating(
        Z_H=z_h,
        Z_E=z_e,
        Z_epsilon=z_eps,
        Z_beta=z_beta,
        Z_BD=z_bd,
        Z_NT=z_nt,
        Z_L=z_l,
        Z_v=z_v,
        Z_R=z_r,
        Z_W=z_w,
        Z_X=z_x,
        sigma_H0=s_h0,
        sigma_H=s_h,
        sigma_HG=s_hg,
        sigma_HP=s_hg / settings.min_safety_pitting,
        S_H=s_hg / s_h,
        cycles=cycles,
    )


# ------------------------------------------------------------------------------------------
# bending (ISO 6336-3:2019)


def _cycles(settings: RatingSettings, operating: OperatingPoint, u):
    """Load cycles N_L (pinion, gear) over the life: turns × the rated flank's cycles per turn
    (:class:`jaxgear.ToothLoading`)."""
    turns = jnp.stack([jnp.ones_like(u), 1 / jnp.abs(u)])  # u < 0: an internal pair
    per_turn = jnp.asarray(settings.loading.cycles_per_turn, dtype=turns.dtype) * turns
    return settings.life * operating.speed / (2 * jnp.pi) * per_turn


def _rim_factor(geometry: RatingGeometry, g):
    """Y_B (rim thickness factor): 1.6 ln(2.242 h_t/s_R) for s_R/h_t < 1.2, 1 above (solid blank: 1)."""
    h_t = (g.tip_diameter - g.root_diameter) / 2
    out = []
    for i, s_r in enumerate(geometry.rim_thickness):
        if s_r is None:
            out.append(jnp.ones_like(h_t[i]))
        else:
            out.append(jnp.maximum(1.0, 1.6 * jnp.log(2.242 * h_t[i] / s_r)))
    return jnp.stack(out)


def bending_rating(
    geometry: RatingGeometry,
    operating: OperatingPoint,
    settings: RatingSettings,
    factors: LoadFactors | None = None,
) -> BendingRating:
    """ISO 6336-3:2019 method B at the operating point (module docstring).

    Y_β of the settings' edition (:class:`jaxgear.rating.Edition2019`: (1 − ε_β β/120°)/cos³ β,
    :class:`jaxgear.rating.Edition2006`: 1 − ε_β β/120°; ε_β <= 1, β <= 30°);
    Y_DT = 1 but for flank tolerance classes <= 4 with ε_αn > 2.05 (deep tooth factor);
    Y_δrelT = (1 + √(ρ' χ*))/(1 + √(ρ' χ*_T)), χ* = (1 + 2 q_s)/5 mm⁻¹, χ*_T = 1.2 mm⁻¹
    (method B); Y_RrelT, Y_X and Y_NT from the material's treatment; the face width
    of each gear is at most the other's plus one module each side.

    Returns:
        :class:`BendingRating` (stresses in Pa).
    """
    check_rating_arguments("bending_rating", geometry, operating, settings)
    if factors is None:
        factors = load_factors(geometry, operating, settings)
    g = geometry.derived()
    mat, lub = settings.material, settings.lubrication
    mn = geometry.normal_module
    form = geometry.form_factors()
    ft = _tangential_load(g, operating)
    bw = geometry.face_width
    b = jnp.minimum(bw, bw[::-1] + 2 * mn)
    y_beta = settings.edition.helix_angle_factor(g.overlap_ratio, geometry.helix_angle)
    y_b = _rim_factor(geometry, g)
    ean = form.eps_alpha_n
    if settings.accuracy.grade <= 4:
        y_dt = jnp.where(ean <= 2.05, 1.0, jnp.where(ean < 2.5, -0.666 * ean + 2.366, 0.7))
    else:
        y_dt = jnp.ones_like(ean)
    s_f0 = ft / (b * mn) * form.Y_F * form.Y_S * y_beta * y_b * y_dt
    s_f = s_f0 * factors.K_A * factors.K_v * factors.K_Fbeta * factors.K_Falpha
    cycles = _cycles(settings, operating, g.gear_ratio)
    tr = mat.treatment
    y_nt = tr.y_nt(cycles)
    chi = 200.0 * (1 + 2 * form.q_s)  # 1/m
    rho_p = tr.slip_layer
    y_d = (1 + jnp.sqrt(rho_p * chi)) / (1 + jnp.sqrt(rho_p * 1200.0))
    y_r = tr.y_r_rel(lub.roughness_root)
    y_x = tr.y_x(mn) * jnp.ones(2)
    y_m = jnp.asarray(settings.loading.mean_stress_factor, dtype=s_f.dtype)
    s_fg = mat.sigma_f_lim * Y_ST * y_nt * y_d * y_r * y_x * y_m
    return BendingRating(
        Y_F=form.Y_F,
        Y_S=form.Y_S,
        Y_beta=y_beta,
        Y_B=y_b,
        Y_DT=y_dt,
        Y_ST=as_float(Y_ST),
        Y_NT=y_nt,
        Y_delta_rel_T=y_d,
        Y_R_rel_T=y_r,
        Y_X=y_x,
        Y_M=y_m,
        sigma_F0=s_f0,
        sigma_F=s_f,
        sigma_FG=s_fg,
        sigma_FP=s_fg / settings.min_safety_bending,
        S_F=s_fg / s_f,
        form=form,
    )


def rate(geometry: RatingGeometry, operating: OperatingPoint, settings: RatingSettings) -> Rating:
    """The whole rating: :func:`load_factors`, :func:`pitting_rating`, :func:`bending_rating`
    at one operating point (a pair's geometry: ``RatingGeometry.of(pair)``; an internal pair's
    ``InternalRatingGeometry.of(pair)``, member 0 the pinion, member 1 the internal gear, with
    the standard's internal-gear rules, :class:`jaxgear.rating.InternalRatingGeometry`). Pure and jit-able
    (``eqx.filter_jit``); differentiable with respect to the array fields of the geometry, the
    operating point and the settings."""
    check_rating_arguments("rate", geometry, operating, settings)
    factors = load_factors(geometry, operating, settings)
    return Rating(
        factors,
        pitting_rating(geometry, operating, settings, factors),
        bending_rating(geometry, operating, settings, factors),
        settings.edition.label,
        tuple(settings.edition.unconfirmed),
    )
