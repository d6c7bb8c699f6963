"""ISO 6336 (method B) as a rating standard (:class:`jaxgear.rating.AbstractRatingStandard`):
its editions :class:`Edition2006` and :class:`Edition2019`, the standard's clauses of each
factor (:func:`factor_clause`), and the formulas of ISO 6336-2 (pitting) and ISO 6336-3 (tooth
bending) with the load factors of ISO 6336-1 method B; pure, jit-able and differentiable
``jax.numpy`` functions of the pair's macro geometry (:class:`jaxgear.rating.RatingGeometry`), an
operating point (:class:`jaxgear.rating.OperatingPoint`) and the settings
(:class:`jaxgear.rating.RatingSettings`).

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

import abc
import dataclasses
import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array

from .._util import as_float
from ._bending import ToothFormFactors
from ._factors import (
    LoadFactors,
    _contact_ratio_factor,
    _tangential_load,
    iso6336_load_factors,
    transverse_factor_limits,
)
from ._standard import FACTOR_NAMES, AbstractRatingStandard

__all__ = [
    "FACTOR_CLAUSES",
    "AbstractEdition",
    "BendingRating",
    "Edition2006",
    "Edition2019",
    "PittingRating",
    "factor_clause",
]

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
    Y_M (mean stress influence factor, :class:`jaxgear.rating.ToothLoading`), sigma_F0, sigma_F,
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


# ------------------------------------------------------------------------------------------
# pitting (ISO 6336-2:2019)


def _c_zl(sigma_h_lim):
    """C_ZL of the lubricant factor Z_L (σ_Hlim of the softer gear)."""
    s = sigma_h_lim * 1e-6
    return jnp.clip(0.08 * (s - 850.0) / 350.0 + 0.83, 0.83, 0.91)


def iso6336_pitting(geometry, operating, settings, factors: LoadFactors) -> PittingRating:
    """ISO 6336-2:2019 method B at the operating point (module docstring), under the load
    ``factors``; the editions' :meth:`AbstractEdition.pitting` (arguments checked by the
    caller, :func:`jaxgear.rating.pitting_rating`).

    Returns:
        :class:`PittingRating` (stresses in Pa, Z_E in √Pa).
    """
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


def _cycles(settings, operating, u):
    """Load cycles N_L (pinion, gear) over the life: turns × the rated flank's cycles per turn
    (:class:`jaxgear.rating.ToothLoading`)."""
    turns = jnp.stack([jnp.ones_like(u), 1 / jnp.abs(u)])  # u < 0: an internal pair
    per_turn = jnp.asarray(settings.loading.cycles_per_turn, dtype=turns.dtype) * turns
    return settings.life * operating.speed / (2 * jnp.pi) * per_turn


def _rim_factor(geometry, g):
    """Y_B (rim thickness factor): 1.6 ln(2.242 h_t/s_R) for s_R/h_t < 1.2, 1 above (solid blank: 1)."""
    h_t = (g.tip_diameter - g.root_diameter) / 2
    out = []
    for i, s_r in enumerate(geometry.rim_thickness):
        if s_r is None:
            out.append(jnp.ones_like(h_t[i]))
        else:
            out.append(jnp.maximum(1.0, 1.6 * jnp.log(2.242 * h_t[i] / s_r)))
    return jnp.stack(out)


def iso6336_bending(geometry, operating, settings, factors: LoadFactors) -> BendingRating:
    """ISO 6336-3:2019 method B at the operating point (module docstring), under the load
    ``factors``; the editions' :meth:`AbstractEdition.bending` (arguments checked by the caller,
    :func:`jaxgear.rating.bending_rating`).

    Y_β of the settings' edition (:class:`jaxgear.rating.Edition2019`: (1 − ε_β β/120°)/cos³ β,
    :class:`jaxgear.rating.Edition2006`: 1 − ε_β β/120°; ε_β <= 1, β <= 30°);
    Y_DT = 1 but for flank tolerance classes <= 4 with ε_αn > 2.05 (deep tooth factor);
    Y_δrelT = (1 + √(ρ' χ*))/(1 + √(ρ' χ*_T)), χ* = (1 + 2 q_s)/5 mm⁻¹, χ*_T = 1.2 mm⁻¹
    (method B); Y_RrelT, Y_X and Y_NT from the material's treatment; the face width
    of each gear is at most the other's plus one module each side.

    Returns:
        :class:`BendingRating` (stresses in Pa).
    """
    g = geometry.derived()
    mat, lub = settings.material, settings.lubrication
    mn = geometry.normal_module
    form = geometry.form_factors()
    ft = _tangential_load(g, operating)
    bw = geometry.face_width
    b = jnp.minimum(bw, bw[::-1] + 2 * mn)
    y_beta = settings.standard.helix_angle_factor(g.overlap_ratio, geometry.helix_angle)
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


#: the given factors a measured one stands for (ISO 6336-1 method B: K_Fα = K_Hα; K_Fβ follows
#: from K_Hβ as ISO's, K_Hβ^N_F)
STANDS_FOR = {"K_Hbeta": ("K_Hbeta",), "K_Halpha": ("K_Halpha", "K_Falpha"), "K_v": ("K_v",)}


class AbstractEdition(AbstractRatingStandard):
    """ISO 6336 method B as a rating standard, in one of its editions, which differ in what
    jaxgear computes only in the helix angle factor Y_β of ISO 6336-3 (:meth:`helix_angle_factor`;
    every other factor is the same in both). A kind, passed as an object
    (:attr:`jaxgear.rating.RatingSettings.standard`): the load factors of ISO 6336-1
    (:meth:`load_factors`), pitting (:meth:`pitting`, ISO 6336-2), bending (:meth:`bending`,
    ISO 6336-3), the scope notes and the ``summary.json`` section of a rating."""

    label: eqx.AbstractClassVar[str]
    # each edition sets ``unconfirmed`` (:attr:`AbstractRatingStandard.unconfirmed`): the
    # attribute names of PittingRating, BendingRating and LoadFactors whose formula in it no
    # published worked example confirms
    #: where each factor and stress of the rating is defined in this edition: symbol (the
    #: attribute names of :class:`jaxgear.rating.LoadFactors`, :class:`jaxgear.rating.PittingRating`,
    #: :class:`jaxgear.rating.BendingRating`, and ``sigma_H_lim``, ``sigma_F_lim``) → "ISO
    #: 6336-3:2006 6.2", or the part alone where the clause could not be checked
    #: (:func:`factor_clause`)
    clauses: eqx.AbstractClassVar[dict[str, str]]

    @abc.abstractmethod
    def helix_angle_factor(self, overlap_ratio, helix_angle):
        """Y_β (-) from ε_β and β (rad)."""

    def load_factors(self, geometry, operating, settings) -> LoadFactors:
        """ISO 6336-1:2019 method B (:func:`jaxgear.rating.load_factors`)."""
        return iso6336_load_factors(geometry, operating, settings)

    def pitting(self, geometry, operating, settings, factors) -> PittingRating:
        """ISO 6336-2 method B (:func:`jaxgear.rating.pitting_rating`)."""
        return iso6336_pitting(geometry, operating, settings, factors)

    def bending(self, geometry, operating, settings, factors) -> BendingRating:
        """ISO 6336-3 method B with this edition's Y_β (:func:`jaxgear.rating.bending_rating`)."""
        return iso6336_bending(geometry, operating, settings, factors)

    def measured_factors(self, name: str) -> tuple[str, ...]:
        """A measured K_Hα gives K_Fα too (K_Fα = K_Hα, ISO 6336-1 method B); a measured K_Hβ
        gives K_Hβ alone (K_Fβ follows from it as ISO's, K_Hβ^N_F); K_v itself."""
        return STANDS_FOR[name]

    def with_measured(self, geometry, settings, measured: dict):
        """``settings`` with the measured factors given in place of ISO's
        (:meth:`measured_factors`), each at least 1 (ISO's factors are); a measured K_Hα and
        the K_Fα it gives within clause 8's limits
        (:func:`jaxgear.rating.transverse_factor_limits`). ``measured``: name → value, of K_v,
        K_Hbeta, K_Halpha."""
        settings = super().with_measured(geometry, settings, measured)
        if "K_Halpha" not in measured:
            return settings
        given = settings.given
        limits = transverse_factor_limits(geometry)
        bounded = {key: min(getattr(given, key), float(limit))
                   for key, limit in zip(("K_Halpha", "K_Falpha"), limits, strict=True)}
        return eqx.tree_at(lambda s: s.given, settings, dataclasses.replace(given, **bounded))

    def scope_notes(self, rating) -> list[str]:
        """Where the inputs leave the standard's scope, one line each naming the part, edition and
        (where checked, :func:`jaxgear.rating.factor_clause`) clause, e.g. "ISO 6336-3:2006 9.2 rim
        thickness factor Y_B: ..." (empty when none): Y_S's 1 <= q_s < 8 (ISO 6336-3, stress
        correction factor), K_v's main
        resonance range 0.85 < N < 1.15 (ISO 6336-1, dynamic factor; noted whether K_v is
        given or computed), Y_B's rim 0.5 < s_R/h_t (ISO 6336-3, rim thickness factor; read back
        from Y_B = 1.6 ln(2.242 h_t/s_R)). Concrete values only (not under ``jit``)."""
        notes = []
        where = {k: factor_clause(k, self.label) for k in ("Y_B", "Y_S", "K_v")}
        for tag, y_b in zip(("pinion", "gear"), rating.bending.Y_B.tolist(), strict=True):
            ratio = 2.242 * math.exp(-y_b / 1.6)
            if y_b > 1.0 and ratio <= 0.5:
                notes.append(
                    f"{where['Y_B']} rim thickness factor Y_B: {tag} rim s_R/h_t = {ratio:.4g} "
                    "is outside the method's scope 0.5 < s_R/h_t (thinner rims should be avoided)"
                )
        for tag, q in zip(("pinion", "gear"), rating.bending.form.q_s.tolist(), strict=True):
            if not 1.0 <= q < 8.0:
                notes.append(
                    f"{where['Y_S']} stress correction factor Y_S: {tag} notch parameter q_s = "
                    f"{q:.4g} is outside the method's scope 1 <= q_s < 8"
                )
        n = float(rating.factors.details["resonance_ratio_N"])
        if 0.85 < n < 1.15:
            notes.append(
                f"{where['K_v']} dynamic factor K_v: resonance ratio N = {n:.4g} in the main "
                "resonance range (0.85, 1.15), where the gears should not run (method B's K_v "
                "is not meant for it)"
            )
        return notes

    def summary(self, rating) -> dict:
        """The ``rating`` section of ``summary.json``: SI units (stresses in Pa), per-gear values
        as [pinion, gear] lists, each load factor with its source."""

        def v(a):
            a = jnp.asarray(a)
            return [float(t) for t in a] if a.ndim else float(a)

        f, p, b = rating.factors, rating.pitting, rating.bending
        return {
            "method": self.label,
            "factors": {
                k: {"value": v(getattr(f, k)), "source": f.sources[k]}
                for k in FACTOR_NAMES
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


# The part of ISO 6336 that defines each factor (1: load factors, 2: pitting, 3: bending, 5:
# the strength numbers); the material's σ_Hlim and σ_Flim are ISO 6336-5's.
_PART = dict.fromkeys(("K_A", "K_v", "K_Hbeta", "K_Fbeta", "K_Halpha", "K_Falpha"), 1)
_PART |= dict.fromkeys(
    ("Z_H", "Z_E", "Z_epsilon", "Z_beta", "Z_BD", "Z_NT", "Z_L", "Z_v", "Z_R", "Z_W", "Z_X",
     "sigma_H0", "sigma_H", "sigma_HG", "sigma_HP", "S_H"),
    2,
)
_PART |= dict.fromkeys(
    ("Y_F", "Y_S", "Y_beta", "Y_B", "Y_DT", "Y_ST", "Y_NT", "Y_delta_rel_T", "Y_R_rel_T", "Y_X",
     "Y_M", "sigma_F0", "sigma_F", "sigma_FG", "sigma_FP", "S_F"),
    3,
)
_PART |= {"sigma_H_lim": 5, "sigma_F_lim": 5}

# ISO 6336-3:2006's clauses, as its table of contents numbers them (BS ISO 6336-3:2006, the
# BSI's listing of its contents: "5.1 Safety factor for bending strength S_F, 5.2 Tooth root
# stress σ_F, 5.3 Permissible bending stress σ_FP, 6.2 Calculation of the form factor Y_F:
# Method B, 7.2 Stress correction factor Y_S: Method B, 7.4 ... Y_ST ..., 8 Helix angle factor
# Y_β, 8.2 Determination by calculation, 9.2 (Y_B), 10.2 (Y_DT), 11.2 Reference stress, with
# values σ_Flim and σ_FE for Method B, 12.2 Life factor Y_NT: Method B, 13.3 Relative notch
# sensitivity factor Y_δrelT: Method B, 14.3 Relative surface factor Y_RrelT: Method B,
# 15 Size factor Y_X"; the BSI shop's page of BS ISO 6336-3:2006, e.g.
# https://shop.standards.ie/en-ie/standards/bs-iso-6336-3-2006-226269_saig_bsi_bsi_531028).
# No table of contents of parts 1 and 5 of 2006, nor of parts 2 and 3 of 2019, was found to
# check against: those name the part alone (the σ_F0 and σ_FG that 5.2 and 5.3 hold are not
# named in the contents, so they too name the part alone; rating.md gives such a row the other
# edition's clause, labelled so: jaxgear.cli's report).
_CLAUSES_3_2006 = {
    "S_F": "5.1", "sigma_F": "5.2", "sigma_FP": "5.3", "Y_F": "6.2", "Y_S": "7.2",
    "Y_ST": "7.4", "Y_beta": "8.2", "Y_B": "9.2", "Y_DT": "10.2", "sigma_F_lim": "11.2",
    "Y_NT": "12.2", "Y_delta_rel_T": "13.3", "Y_R_rel_T": "14.3", "Y_X": "15",
}


# ISO 6336-2:2006's clauses, as the BSI lists the contents of BS ISO 6336-2:2006 (the same shop
# as part 3's, https://shop.standards.ie/en-ie/standards/bs-iso-6336-2-2006-226264_saig_bsi_bsi_531017:
# "5.2 Safety factor for surface durability S_H, 5.3 Contact stress σ_H, 5.4 Permissible contact
# stress σ_HP, 6.1 Zone factor Z_H, 6.2 Single pair tooth contact factors Z_B and Z_D for
# ε_α <= 2, 7 Elasticity factor Z_E, 8.1 Determination of contact ratio factor Z_ε, 9 Helix
# angle factor Z_β, 10.1 Allowable stress numbers σ_Hlim for Method B, 11.2 Life factor Z_NT:
# Method B, 12.3 factors Z_L, Z_v and Z_R: Method B, 13.2 Work hardening factor Z_W: Method B,
# 14 Size factor Z_X").
_CLAUSES_2_2006 = {
    "S_H": "5.2", "sigma_H": "5.3", "sigma_HP": "5.4", "Z_H": "6.1", "Z_BD": "6.2", "Z_E": "7",
    "Z_epsilon": "8.1", "Z_beta": "9", "Z_NT": "11.2", "Z_L": "12.3", "Z_v": "12.3",
    "Z_R": "12.3", "Z_W": "13.2", "Z_X": "14",
}
# ISO 6336-1:2019's clauses of the load factors: "5 Application factor K_A" and "6 Internal
# dynamic factor K_v" as its text numbers them, 7 (face load factors K_Hβ, K_Fβ) and 8
# (transverse load factors K_Hα, K_Fα) as the clauses jaxgear's formulas are written from
# (jaxgear.rating's load factors).
_CLAUSES_1_2019 = {
    "K_A": "5", "K_v": "6", "K_Hbeta": "7", "K_Fbeta": "7", "K_Halpha": "8", "K_Falpha": "8",
}


def _clauses(year: int, checked: dict[str, str]) -> dict[str, str]:
    """symbol → "ISO 6336-<part>:<year>[ <clause>]" (σ_Hlim, σ_Flim: ISO 6336-5, no year);
    ``checked`` the clauses of the edition's parts 1-3 that were checked (symbols are unique
    across the parts)."""
    out = {}
    for symbol, part in _PART.items():
        head = "ISO 6336-5" if part == 5 else f"ISO 6336-{part}:{year}"
        clause = checked.get(symbol) if part != 5 else None
        out[symbol] = f"{head} {clause}" if clause else head
    return out


def _y_beta_2006(overlap_ratio, helix_angle):
    """1 − ε_β β/120° with ε_β ≤ 1 and β ≤ 30°."""
    beta_deg = jnp.minimum(helix_angle * 180 / jnp.pi, 30.0)
    return 1 - jnp.minimum(overlap_ratio, 1.0) * beta_deg / 120.0


class Edition2006(AbstractEdition):
    """ISO 6336-3:2006: Y_β = 1 − ε_β β/120° (ε_β ≤ 1, β ≤ 30°). Checked against the printed
    Y_β and σ_F0 of a KISSsoft report to ISO 6336:2006 (docs/rating.md)."""

    label: ClassVar[str] = "ISO 6336:2006 method B"
    unconfirmed: ClassVar[tuple[str, ...]] = ()
    clauses: ClassVar[dict[str, str]] = _clauses(2006, _CLAUSES_2_2006 | _CLAUSES_3_2006)

    def helix_angle_factor(self, overlap_ratio, helix_angle):
        return _y_beta_2006(overlap_ratio, helix_angle)


class Edition2019(AbstractEdition):
    """ISO 6336-3:2019: Y_β = (1 − ε_β β/120°)/cos³ β, with ε_β ≤ 1 and β ≤ 30° in both terms
    (above 30° the factor is that of 30°). No printed worked example of the 2019 edition was
    found to check it against (docs/rating.md); two independent public implementations of the
    2019 edition write the same formula, the limits included. The 2006 term is checked
    (:class:`Edition2006`)."""

    label: ClassVar[str] = "ISO 6336:2019 method B"
    #: Y_β's 1/cos³β term: no printed worked example of the 2019 edition was found
    unconfirmed: ClassVar[tuple[str, ...]] = ("Y_beta",)
    clauses: ClassVar[dict[str, str]] = _clauses(2019, _CLAUSES_1_2019)

    def helix_angle_factor(self, overlap_ratio, helix_angle):
        beta = jnp.minimum(helix_angle, jnp.pi / 6)
        return _y_beta_2006(overlap_ratio, helix_angle) / jnp.cos(beta) ** 3


#: The clauses of each edition by its label (:attr:`jaxgear.rating.Rating.method`): label → symbol →
#: "ISO 6336-3:2006 6.2" (:attr:`AbstractEdition.clauses`)
FACTOR_CLAUSES: dict[str, dict[str, str]] = {
    e.label: e.clauses for e in (Edition2006, Edition2019)
}


def factor_clause(symbol: str, edition: str) -> str:
    """Where ISO 6336 defines a factor or stress of the rating: "ISO 6336-3:2006 6.2" (part,
    edition and clause), or "ISO 6336-2:2019" (the part alone, where the clause was not checked
    against the standard's contents; :attr:`AbstractEdition.clauses`).

    Args:
        symbol: an attribute name of :class:`jaxgear.rating.LoadFactors`,
            :class:`jaxgear.rating.PittingRating` or :class:`jaxgear.rating.BendingRating`
            (``"Y_F"``, ``"K_Hbeta"``, ``"sigma_H0"``; a ``summary()`` key's ``_Pa``/``_sqrt_Pa``
            suffix is dropped), or ``"sigma_H_lim"``, ``"sigma_F_lim"``.
        edition: the edition's label (:attr:`AbstractEdition.label`,
            :attr:`jaxgear.rating.Rating.method`: ``"ISO 6336:2019 method B"``).

    Raises:
        ValueError: an unknown symbol or edition, in one line naming the known ones.
    """
    label = edition
    if label not in FACTOR_CLAUSES:
        raise ValueError(
            f"factor_clause: edition = {label!r} is out of range: one of {sorted(FACTOR_CLAUSES)}"
        )
    clauses = FACTOR_CLAUSES[label]
    key = symbol.removesuffix("_sqrt_Pa").removesuffix("_Pa")
    if key not in clauses:
        raise ValueError(
            f"factor_clause: symbol = {symbol!r} is out of range: one of {sorted(clauses)}"
        )
    return clauses[key]
