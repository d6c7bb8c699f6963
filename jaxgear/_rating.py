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

Bending (ISO 6336-3:2019; Y_F, Y_S: :func:`jaxgear.tooth_form_factors`)::

    σ_F0 = F_t / (b m_n) Y_F Y_S Y_β Y_B Y_DT,   σ_F = σ_F0 K_A K_v K_Fβ K_Fα
    σ_FG = σ_Flim Y_ST Y_NT Y_δrelT Y_RrelT Y_X,  σ_FP = σ_FG / S_Fmin,  S_F = σ_FG / σ_F

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
from jaxtyping import Array, Float

from ._deviations import iso1328_tolerances
from ._geometry import GearPair
from ._rating_bending import ToothFormFactors, tooth_form_factors
from ._rating_geometry import RatingGeometry
from ._rating_material import AbstractTreatment, CaseHardened
from ._util import as_float, check_instance, check_real

__all__ = [
    "BendingRating",
    "GearAccuracy",
    "GivenFactors",
    "LoadFactors",
    "Lubrication",
    "OperatingPoint",
    "PittingRating",
    "Rating",
    "RatingMaterial",
    "RatingSettings",
    "bending_rating",
    "load_factors",
    "pitting_rating",
    "rate",
]

METHOD = "ISO 6336:2019 method B"
E_STEEL = 206e9  # Pa: ISO 6336-1's reference modulus of c'_th
ISO_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
LOW_LOAD = 1e5  # N/m = 100 N/mm
Y_ST = 2.0  # ISO 6336-3: stress correction factor of the reference test gears


class OperatingPoint(eqx.Module):
    """The operating point of a rating: ``torque`` T₁ on the pinion (N·m, > 0) and the pinion's
    ``speed`` ω₁ (rad/s, > 0)."""

    torque: Float[Array, ""]
    speed: Float[Array, ""]

    def __init__(self, torque, speed):
        check_real("torque", torque, "N·m", lo=0.0, lo_open=True, where="OperatingPoint")
        check_real("speed", speed, "rad/s", lo=0.0, lo_open=True, where="OperatingPoint")
        self.torque = as_float(torque)
        self.speed = as_float(speed)


class RatingMaterial(eqx.Module):
    """The gears' material (one modulus, Poisson ratio and density for both; strength per gear).

    Attributes:
        sigma_h_lim: σ_Hlim (Pa), (pinion, gear): the allowable contact stress number (ISO
            6336-5). sigma_f_lim: σ_Flim (Pa), the nominal bending stress number (σ_FE =
            Y_ST σ_Flim, Y_ST = 2).
        youngs_modulus (Pa), poisson_ratio, density (kg/m³).
        treatment: the heat treatment, an :class:`AbstractTreatment` (life curves, running-in,
            slip layer, size factor); default :class:`CaseHardened`.
    """

    sigma_h_lim: Float[Array, 2]
    sigma_f_lim: Float[Array, 2]
    youngs_modulus: Float[Array, ""]
    poisson_ratio: Float[Array, ""]
    density: Float[Array, ""]
    treatment: AbstractTreatment

    def __init__(
        self,
        sigma_h_lim,
        sigma_f_lim,
        youngs_modulus=206e9,
        poisson_ratio=0.3,
        density=7830.0,
        treatment: AbstractTreatment | None = None,
    ):
        w = "RatingMaterial"
        sh = jnp.broadcast_to(as_float(sigma_h_lim), (2,))
        sf = jnp.broadcast_to(as_float(sigma_f_lim), (2,))
        check_real("sigma_h_lim", sh, "Pa", lo=0.0, lo_open=True, where=w)
        check_real("sigma_f_lim", sf, "Pa", lo=0.0, lo_open=True, where=w)
        check_real("youngs_modulus", youngs_modulus, "Pa", lo=0.0, lo_open=True, where=w)
        check_real("poisson_ratio", poisson_ratio, "", lo=0.0, hi=0.5, hi_open=True, where=w)
        check_real("density", density, "kg/m³", lo=0.0, lo_open=True, where=w)
        treatment = CaseHardened() if treatment is None else treatment
        check_instance("treatment", treatment, AbstractTreatment, "a jaxgear rating treatment", w)
        self.sigma_h_lim, self.sigma_f_lim = sh, sf
        self.youngs_modulus = as_float(youngs_modulus)
        self.poisson_ratio = as_float(poisson_ratio)
        self.density = as_float(density)
        self.treatment = treatment


class Lubrication(eqx.Module):
    """Lubricant and surfaces: ``viscosity_40`` ν₄₀ (m²/s; ISO VG 220 is 220e-6),
    ``roughness_flank`` and ``roughness_root`` R_z (m), (pinion, gear)."""

    viscosity_40: Float[Array, ""]
    roughness_flank: Float[Array, 2]
    roughness_root: Float[Array, 2]

    def __init__(self, viscosity_40, roughness_flank, roughness_root):
        w = "Lubrication"
        check_real("viscosity_40", viscosity_40, "m²/s", lo=0.0, lo_open=True, where=w)
        rf = jnp.broadcast_to(as_float(roughness_flank), (2,))
        rr = jnp.broadcast_to(as_float(roughness_root), (2,))
        check_real("roughness_flank", rf, "m", lo=0.0, lo_open=True, where=w)
        check_real("roughness_root", rr, "m", lo=0.0, lo_open=True, where=w)
        self.viscosity_40, self.roughness_flank, self.roughness_root = (
            as_float(viscosity_40),
            rf,
            rr,
        )


class GearAccuracy(eqx.Module):
    """The deviations of the load factors (m): ``base_pitch`` f_pb, ``profile_form`` f_fα and
    ``helix_slope`` f_Hβ (each the larger of the two gears'), and the ISO 1328-1 flank
    tolerance class ``grade`` (static; Y_DT and the report). :meth:`from_grade` takes them from
    the tolerances of ISO 1328-1:2013 (f_pb = f_pT, f_fα = f_fαT, f_Hβ = f_HβT)."""

    base_pitch: Float[Array, ""]
    profile_form: Float[Array, ""]
    helix_slope: Float[Array, ""]
    grade: int = eqx.field(static=True, default=6)

    @classmethod
    def from_grade(cls, pair: GearPair, grade: int) -> GearAccuracy:
        tol = [
            iso1328_tolerances(
                pair.normal_module,
                m.teeth * pair.normal_module / math.cos(pair.helix_angle),
                m.face_width,
                grade,
            )
            for m in (pair.pinion, pair.gear)
        ]
        return cls(
            base_pitch=as_float(max(t.single_pitch for t in tol)),
            profile_form=as_float(max(t.profile_form for t in tol)),
            helix_slope=as_float(max(t.helix_slope for t in tol)),
            grade=int(grade),
        )


class GivenFactors(eqx.Module):
    """Load factors given by the user (``None``: computed by ISO 6336-1 method B)."""

    K_v: float | None = None
    K_Hbeta: float | None = None
    K_Fbeta: float | None = None
    K_Halpha: float | None = None
    K_Falpha: float | None = None


class RatingSettings(eqx.Module):
    """Everything of a rating but the geometry and the operating point.

    Attributes:
        material: :class:`RatingMaterial`. lubrication: :class:`Lubrication`.
        accuracy: :class:`GearAccuracy`. life: required life (s). application_factor: K_A.
        given: :class:`GivenFactors`. tip_relief: C_a (m) of K_v; ``None``: the running-in
            value C_ay = (σ_Hlim/97 − 18.45)²/18 + 1.5 µm (σ_Hlim in N/mm², ISO 6336-1 clause 6).
        min_safety_pitting, min_safety_bending: S_Hmin, S_Fmin (σ_HP = σ_HG/S_Hmin; 1 default).
    """

    material: RatingMaterial
    lubrication: Lubrication
    accuracy: GearAccuracy
    life: float
    application_factor: float = 1.0
    given: GivenFactors = GivenFactors()
    tip_relief: float | None = None
    min_safety_pitting: float = 1.0
    min_safety_bending: float = 1.0


class LoadFactors(eqx.Module):
    """K_A, K_v, K_Hβ, K_Fβ, K_Hα, K_Fα (scalars) and ``sources`` (static: symbol → "given" or
    "ISO 6336-1 method B"), with the intermediate values of their clauses (``details``)."""

    K_A: Array
    K_v: Array
    K_Hbeta: Array
    K_Fbeta: Array
    K_Halpha: Array
    K_Falpha: Array
    details: dict
    sources: dict = eqx.field(static=True)


class PittingRating(eqx.Module):
    """ISO 6336-2 results: scalars Z_H, Z_E (√Pa), Z_epsilon, Z_beta, Z_L, Z_v, Z_R, Z_W, Z_X,
    sigma_H0 (Pa); per gear (2,) Z_BD (Z_B, Z_D), Z_NT, sigma_H, sigma_HG, sigma_HP (Pa), S_H,
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
    sigma_F0, sigma_F, sigma_FG, sigma_FP (Pa), S_F; scalars Y_beta, Y_DT, Y_ST; ``form`` the
    :class:`jaxgear.ToothFormFactors`."""

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
    sigma_F0: Array
    sigma_F: Array
    sigma_FG: Array
    sigma_FP: Array
    S_F: Array
    form: ToothFormFactors


class Rating(eqx.Module):
    """A whole rating: ``factors`` (:class:`LoadFactors`), ``pitting`` (:class:`PittingRating`),
    ``bending`` (:class:`BendingRating`); :meth:`summary` gives the JSON section."""

    factors: LoadFactors
    pitting: PittingRating
    bending: BendingRating

    def scope_notes(self) -> list[str]:
        """Where the inputs leave the standard's scope, one line each naming the clause (empty
        when none): Y_S's 1 <= q_s < 8 (ISO 6336-3, stress correction factor), K_v's main
        resonance range 0.85 < N < 1.15 (ISO 6336-1, dynamic factor: method B is not to be
        used there). Concrete values only (not under ``jit``)."""
        notes = []
        for tag, q in zip(("pinion", "gear"), self.bending.form.q_s.tolist(), strict=True):
            if not 1.0 <= q < 8.0:
                notes.append(
                    f"ISO 6336-3 stress correction factor Y_S: {tag} notch parameter q_s = "
                    f"{q:.4g} is outside the method's scope 1 <= q_s < 8"
                )
        n = float(self.factors.details["resonance_ratio_N"])
        if self.factors.sources["K_v"] != "given" and 0.85 < n < 1.15:
            notes.append(
                f"ISO 6336-1 dynamic factor K_v: resonance ratio N = {n:.4g} in the main "
                "resonance range (0.85, 1.15), where the gears should not run: give K_v"
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
            "method": METHOD,
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
                "sigma_F0_Pa": v(b.sigma_F0),
                "sigma_F_Pa": v(b.sigma_F),
                "sigma_FP_Pa": v(b.sigma_FP),
                "S_F": v(b.S_F),
            },
        }


# ------------------------------------------------------------------------------------------
# load factors (ISO 6336-1:2019)


def _tangential_load(g, operating: OperatingPoint):
    """F_t = 2 T₁/d₁ (N) at the reference circle; ``g`` the derived geometry."""
    return 2 * operating.torque / g.reference_diameter[0]


def _stiffness(geometry: RatingGeometry, g, settings: RatingSettings, specific_load):
    """c' and c_γα (N/m per m of face width), ISO 6336-1 method B (9.3), C_R = 1 (solid)."""
    beta = geometry.helix_angle
    zn = jnp.asarray(geometry.teeth, dtype=beta.dtype) / (
        jnp.cos(g.base_helix_angle) ** 2 * jnp.cos(beta)
    )
    x1, x2 = geometry.profile_shift[0], geometry.profile_shift[1]
    c = ISO_C
    q = (
        c[0]
        + c[1] / zn[0]
        + c[2] / zn[1]
        + c[3] * x1
        + c[4] * x1 / zn[0]
        + c[5] * x2
        + c[6] * x2 / zn[1]
        + c[7] * x1**2
        + c[8] * x2**2
    )
    an_deg = geometry.normal_pressure_angle * 180 / jnp.pi
    cb = jnp.mean((1 + 0.5 * (1.2 - geometry.dedendum_coeff)) * (1 - 0.02 * (20.0 - an_deg)))
    e = settings.material.youngs_modulus
    low = jnp.minimum(specific_load / LOW_LOAD, 1.0) ** 0.25
    c1 = 1e9 / q * 0.8 * cb * jnp.cos(beta) * e / E_STEEL * low
    return c1, c1 * (0.75 * g.transverse_contact_ratio + 0.25)


def _dynamic_factor(geometry, g, operating, settings, stiffness, line_load):
    """K_v, ISO 6336-1 clause 6 (method B): the resonance ratio N = ω₁/ω_E1 with ω_E1 =
    √(c_γα/m_red)/z₁ and m_red of two solid blanks, and the regions of N."""
    c1, cga = stiffness
    mat, acc, tr = settings.material, settings.accuracy, settings.material.treatment
    dm = (g.tip_diameter + g.root_diameter) / 2
    m_star = jnp.pi / 8 * mat.density * dm**4 / g.base_diameter**2
    m_red = m_star[0] * m_star[1] / (m_star[0] + m_star[1])
    n_ratio = operating.speed / (jnp.sqrt(cga / m_red) / geometry.teeth[0])
    sh = jnp.min(mat.sigma_h_lim)
    f_pb = acc.base_pitch - tr.running_in_alpha(acc.base_pitch, sh)
    f_fa = acc.profile_form - tr.running_in_alpha(acc.profile_form, sh)
    if settings.tip_relief is None:
        ca = ((sh * 1e-6 / 97.0 - 18.45) ** 2 / 18.0 + 1.5) * 1e-6
    else:
        ca = settings.tip_relief
    bp, bf = c1 * f_pb / line_load, c1 * f_fa / line_load
    bk = jnp.abs(1 - c1 * ca / line_load)
    eg = g.transverse_contact_ratio + g.overlap_ratio
    big = eg > 2
    cv1, cv5 = 0.32, 0.47
    cv2 = jnp.where(big, 0.57 / (eg - 0.3), 0.34)
    cv3 = jnp.where(big, 0.096 / (eg - 1.56), 0.23)
    cv4 = jnp.where(big, (0.57 - 0.05 * eg) / (eg - 1.44), 0.90)
    cv6 = jnp.where(big, 0.12 / (eg - 1.74), 0.47)
    cv7 = jnp.where(
        eg <= 1.5, 0.75, jnp.where(eg <= 2.5, 0.125 * jnp.sin(jnp.pi * (eg - 2)) + 0.875, 1.0)
    )
    n_s = jnp.where(line_load < LOW_LOAD, 0.5 + 0.35 * jnp.sqrt(line_load / LOW_LOAD), 0.85)
    sub = n_ratio * (cv1 * bp + cv2 * bf + cv3 * bk) + 1
    main = cv1 * bp + cv2 * bf + cv4 * bk + 1
    super_ = cv5 * bp + cv6 * bf + cv7
    inter = super_ + (main - super_) * (1.5 - n_ratio) / 0.35
    kv = jnp.where(
        n_ratio <= n_s,
        sub,
        jnp.where(n_ratio <= 1.15, main, jnp.where(n_ratio < 1.5, inter, super_)),
    )
    return kv, {"resonance_ratio_N": n_ratio, "reduced_mass_kg_per_m": m_red, "C_a_m": ca}


def _face_factor(settings, cga, f_m_per_b):
    """K_Hβ (ISO 6336-1 clause 7): F_βx = f_Hβ, at least 0.005 µm per N/mm of F_m/b (5e-12 m²/N); F_βy =
    F_βx − y_β (running-in); c_γβ = 0.85 c_γα; K_Hβ = 1 + F_βy c_γβ/(2 F_m/b) up to 2, else
    √(2 F_βy c_γβ/(F_m/b)) (F_m = F_t K_A K_v)."""
    acc, tr = settings.accuracy, settings.material.treatment
    f_bx = jnp.maximum(acc.helix_slope, 5e-12 * f_m_per_b)
    f_by = f_bx - tr.running_in_beta(f_bx, jnp.min(settings.material.sigma_h_lim))
    t = f_by * 0.85 * cga / f_m_per_b
    return jnp.where(t <= 2.0, 1 + t / 2, jnp.sqrt(2 * jnp.maximum(t, 2.0)))


def _transverse_factors(geometry, g, settings, cga, f_th_per_b):
    """K_Hα and K_Fα (ISO 6336-1 clause 8, method B), limited to [1, ε_γ/(ε_α Z_ε²)] and [1, ε_γ/(0.25 ε_α +
    0.75)]."""
    acc, tr = settings.accuracy, settings.material.treatment
    ea, eb = g.transverse_contact_ratio, g.overlap_ratio
    eg = ea + eb
    f_eff = acc.base_pitch - tr.running_in_alpha(
        acc.base_pitch, jnp.min(settings.material.sigma_h_lim)
    )
    term = cga * f_eff / f_th_per_b
    k = jnp.where(
        eg <= 2,
        eg / 2 * (0.9 + 0.4 * term),
        0.9 + 0.4 * jnp.sqrt(2 * (eg - 1) / eg) * term,
    )
    z_eps = _contact_ratio_factor(ea, eb, geometry)
    kh = jnp.clip(k, 1.0, eg / (ea * z_eps**2))
    kf = jnp.clip(k, 1.0, eg / (0.25 * ea + 0.75))
    return kh, kf


def load_factors(
    geometry: RatingGeometry, operating: OperatingPoint, settings: RatingSettings
) -> LoadFactors:
    """K_A, K_v, K_Hβ, K_Fβ, K_Hα, K_Fα at the operating point (module docstring; ISO 6336-1:2019
    clauses 6, 7, 8, method B); given factors replace computed ones."""
    given = settings.given
    g = geometry.derived()
    ka = as_float(settings.application_factor)
    ft = _tangential_load(g, operating)
    line = ft * ka / g.face_width  # N/m
    c1, cga = _stiffness(geometry, g, settings, line)
    kv_iso, details = _dynamic_factor(geometry, g, operating, settings, (c1, cga), line)
    kv = kv_iso if given.K_v is None else as_float(given.K_v)
    khb = (
        _face_factor(settings, cga, line * kv) if given.K_Hbeta is None else as_float(given.K_Hbeta)
    )
    h = (g.tip_diameter - g.root_diameter) / 2
    bh = jnp.maximum(jnp.min(geometry.face_width / h), 3.0)
    n_f = bh**2 / (1 + bh + bh**2)
    kfb = khb**n_f if given.K_Fbeta is None else as_float(given.K_Fbeta)
    kha, kfa = _transverse_factors(geometry, g, settings, cga, line * kv * khb)
    kha = kha if given.K_Halpha is None else as_float(given.K_Halpha)
    kfa = kfa if given.K_Falpha is None else as_float(given.K_Falpha)
    iso = "ISO 6336-1 method B"
    sources = {"K_A": "given"} | {
        k: ("given" if getattr(given, k) is not None else iso)
        for k in ("K_v", "K_Hbeta", "K_Fbeta", "K_Halpha", "K_Falpha")
    }
    details = details | {"c_prime_N_per_m2": c1, "c_gamma_alpha_N_per_m2": cga, "N_F": n_f}
    return LoadFactors(ka, kv, khb, kfb, kha, kfa, details, sources)


# ------------------------------------------------------------------------------------------
# pitting (ISO 6336-2:2019)


def _contact_ratio_factor(ea, eb, geometry):
    """Z_ε (contact ratio factor): spur √((4 − ε_α)/3); helical √((4 − ε_α)/3 (1 − ε_β) + ε_β/ε_α) for
    ε_β < 1, √(1/ε_α) from ε_β = 1."""
    eb1 = jnp.minimum(eb, 1.0)
    return jnp.sqrt((4 - ea) / 3 * (1 - eb1) + eb1 / ea)


def _single_pair_factors(g, geometry):
    """Z_B, Z_D (single pair tooth contact factors): M₁, M₂ at the inner points of single pair contact; spur max(1, M),
    helical ε_β < 1 max(1, M − ε_β (M − 1)), ε_β >= 1: 1."""
    z = jnp.asarray(geometry.teeth, dtype=g.center_distance.dtype)
    ea, eb = g.transverse_contact_ratio, jnp.minimum(g.overlap_ratio, 1.0)
    t = jnp.sqrt((g.tip_diameter / g.base_diameter) ** 2 - 1)
    m1 = jnp.tan(g.operating_pressure_angle) / jnp.sqrt(
        (t[0] - 2 * jnp.pi / z[0]) * (t[1] - (ea - 1) * 2 * jnp.pi / z[1])
    )
    m2 = jnp.tan(g.operating_pressure_angle) / jnp.sqrt(
        (t[1] - 2 * jnp.pi / z[1]) * (t[0] - (ea - 1) * 2 * jnp.pi / z[0])
    )
    m = jnp.stack([m1, m2])
    return jnp.maximum(1.0, m - eb * (m - 1))


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
    z_bd = _single_pair_factors(g, geometry)
    s_h = z_bd * s_h0 * jnp.sqrt(k)
    # permissible stress
    cycles = settings.life * operating.speed / (2 * jnp.pi) * jnp.asarray([1.0, 1.0 / u])
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
    z_w, z_x = as_float(1.0), as_float(1.0)
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

    Y_β = (1 − ε_β β/120°)/cos³ β with ε_β <= 1, β <= 30° (the 2006 edition had no 1/cos³ β);
    Y_DT = 1 but for flank tolerance classes <= 4 with ε_αn > 2.05 (deep tooth factor);
    Y_δrelT = (1 + √(ρ' χ*))/(1 + √(ρ' χ*_T)), χ* = (1 + 2 q_s)/5 mm⁻¹, χ*_T = 1.2 mm⁻¹
    (method B); Y_RrelT, Y_X and Y_NT from the material's treatment; the face width
    of each gear is at most the other's plus one module each side.

    Returns:
        :class:`BendingRating` (stresses in Pa).
    """
    if factors is None:
        factors = load_factors(geometry, operating, settings)
    g = geometry.derived()
    mat, lub = settings.material, settings.lubrication
    mn = geometry.normal_module
    form = tooth_form_factors(geometry)
    ft = _tangential_load(g, operating)
    bw = geometry.face_width
    b = jnp.minimum(bw, bw[::-1] + 2 * mn)
    beta_deg = jnp.minimum(geometry.helix_angle * 180 / jnp.pi, 30.0)
    y_beta = (1 - jnp.minimum(g.overlap_ratio, 1.0) * beta_deg / 120.0) / jnp.cos(
        geometry.helix_angle
    ) ** 3
    y_b = _rim_factor(geometry, g)
    ean = form.eps_alpha_n
    if settings.accuracy.grade <= 4:
        y_dt = jnp.where(ean <= 2.05, 1.0, jnp.where(ean < 2.5, -0.666 * ean + 2.366, 0.9))
    else:
        y_dt = jnp.ones_like(ean)
    s_f0 = ft / (b * mn) * form.Y_F * form.Y_S * y_beta * y_b * y_dt
    s_f = s_f0 * factors.K_A * factors.K_v * factors.K_Fbeta * factors.K_Falpha
    u = g.gear_ratio
    cycles = settings.life * operating.speed / (2 * jnp.pi) * jnp.asarray([1.0, 1.0 / u])
    tr = mat.treatment
    y_nt = tr.y_nt(cycles)
    chi = 200.0 * (1 + 2 * form.q_s)  # 1/m
    rho_p = tr.slip_layer
    y_d = (1 + jnp.sqrt(rho_p * chi)) / (1 + jnp.sqrt(rho_p * 1200.0))
    y_r = tr.y_r_rel(lub.roughness_root)
    y_x = tr.y_x(mn) * jnp.ones(2)
    s_fg = mat.sigma_f_lim * Y_ST * y_nt * y_d * y_r * y_x
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
        sigma_F0=s_f0,
        sigma_F=s_f,
        sigma_FG=s_fg,
        sigma_FP=s_fg / settings.min_safety_bending,
        S_F=s_fg / s_f,
        form=form,
    )


def rate(geometry: RatingGeometry, operating: OperatingPoint, settings: RatingSettings) -> Rating:
    """The whole rating: :func:`load_factors`, :func:`pitting_rating`, :func:`bending_rating`
    at one operating point (a pair's geometry: ``RatingGeometry.of(pair)``). Pure and jit-able
    (``eqx.filter_jit``); differentiable with respect to the array fields of the geometry, the
    operating point and the settings."""
    check_instance("geometry", geometry, RatingGeometry, "a jaxgear.RatingGeometry", "rate")
    factors = load_factors(geometry, operating, settings)
    return Rating(
        factors,
        pitting_rating(geometry, operating, settings, factors),
        bending_rating(geometry, operating, settings, factors),
    )
