"""Settings and operating point of a rating (:func:`jaxgear.rating.rate`): the material,
lubrication, accuracy, life, given load factors and the standard (:class:`RatingSettings`), and the operating
point (:class:`OperatingPoint`), an argument of the rating, never a field of its settings. SI
units; each constructor refuses bad input in one line naming the parameter, its value and the
allowed range."""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._deviations import iso1328_tolerances, iso1328_tolerances_array
from .._geometry import GearPair
from .._util import as_float, check_instance, check_real
from ._iso6336 import Edition2019
from ._material import AbstractTreatment, CaseHardened
from ._standard import AbstractRatingStandard

__all__ = [
    "RATING_RANGES",
    "GearAccuracy",
    "GivenFactors",
    "Lubrication",
    "OperatingPoint",
    "RatingMaterial",
    "RatingSettings",
    "ToothLoading",
]


#: the ranges a gear material's strength numbers and its surfaces' roughness can have (SI:
#: Pa, m), each with where it comes from: name → (lo, hi, source). :class:`RatingMaterial` and
#: :class:`Lubrication` refuse values outside them, the case file's keys too (in its units,
#: the source in the message and the reference: ``jaxgear.io``)
RATING_RANGES = {
    "sigma_h_lim": (
        200e6, 2000e6,
        "ISO 6336-5's material lines span about 270 N/mm², normalized cast steel ML, to "
        "1650 N/mm², case-hardened ME; with margin",
    ),
    "sigma_f_lim": (
        30e6, 800e6,
        "ISO 6336-5's material lines span about 46 N/mm², grey cast iron ML, to 525 N/mm², "
        "case-hardened ME; with margin; σ_Flim, not σ_FE = 2 σ_Flim",
    ),
    "roughness_flank": (
        0.1e-6, 50e-6,
        "finished flanks: superfinished below 1 µm, ground about 1 to 4 µm, hobbed or shaped "
        "about 8 to 25 µm; ISO 6336-2's Z_R = 1 at its test gears' R_z10 = 3 µm",
    ),
    "roughness_root": (
        0.1e-6, 100e-6,
        "root fillets: ground about 1 to 6 µm, hobbed or shaped about 10 to 40 µm; ISO "
        "6336-3's Y_RrelT ≈ 1 at its test gears' R_z = 10 µm",
    ),
}


def _check_range(name: str, value, unit: str, where: str) -> None:
    lo, hi, _ = RATING_RANGES[name]
    check_real(name, value, unit, lo=lo, hi=hi, where=where)


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
            6336-5), [200, 2000] N/mm² (:data:`RATING_RANGES`).
        sigma_f_lim: σ_Flim (Pa), (pinion, gear): the nominal bending stress number
            (σ_FE = Y_ST σ_Flim, Y_ST = 2), [30, 800] N/mm².
        youngs_modulus: Young's modulus (Pa), both gears.
        poisson_ratio: Poisson's ratio, both gears.
        density: density (kg/m³), both gears.
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
        _check_range("sigma_h_lim", sigma_h_lim, "Pa", w)  # as given (float32 flushes 1e-300)
        _check_range("sigma_f_lim", sigma_f_lim, "Pa", w)
        sh = jnp.broadcast_to(as_float(sigma_h_lim), (2,))
        sf = jnp.broadcast_to(as_float(sigma_f_lim), (2,))
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
    ``roughness_flank`` ([0.1, 50] µm) and ``roughness_root`` ([0.1, 100] µm) R_z (m),
    (pinion, gear) (:data:`RATING_RANGES`). A value out of range: one ``ValueError`` line."""

    viscosity_40: Float[Array, ""]
    roughness_flank: Float[Array, 2]
    roughness_root: Float[Array, 2]

    def __init__(self, viscosity_40, roughness_flank, roughness_root):
        w = "Lubrication"
        check_real("viscosity_40", viscosity_40, "m²/s", lo=0.0, lo_open=True, where=w)
        _check_range("roughness_flank", roughness_flank, "m", w)
        _check_range("roughness_root", roughness_root, "m", w)
        rf = jnp.broadcast_to(as_float(roughness_flank), (2,))
        rr = jnp.broadcast_to(as_float(roughness_root), (2,))
        self.viscosity_40, self.roughness_flank, self.roughness_root = (
            as_float(viscosity_40),
            rf,
            rr,
        )


class GearAccuracy(eqx.Module):
    """The deviations of the load factors (m): ``base_pitch`` f_pb, ``profile_form`` f_fα and
    ``helix_slope`` f_Hβ (each the larger of the two gears'), and the ISO 1328-1 flank
    tolerance class ``grade`` (static; Y_DT and the report). :meth:`from_grade` takes them from
    the tolerances of ISO 1328-1:2013 (f_pb = f_pT, f_fα = f_fαT, f_Hβ = f_HβT) of a pair;
    :meth:`from_dimensions` the same from the gears' dimensions as arrays (traceable)."""

    base_pitch: Float[Array, ""]
    profile_form: Float[Array, ""]
    helix_slope: Float[Array, ""]
    grade: int = eqx.field(static=True, default=6)

    @classmethod
    def from_grade(cls, pair: GearPair, grade: int) -> GearAccuracy:
        tol = [
            iso1328_tolerances(
                pair.normal_module,
                abs(m.teeth) * pair.normal_module / math.cos(pair.helix_angle),
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


    @classmethod
    def from_dimensions(cls, normal_module, reference_diameter, face_width,
                        grade: int) -> GearAccuracy:
        """:meth:`from_grade` from the gears' dimensions as ``jax.numpy`` values (traceable:
        one program for a batch of candidates under :func:`jax.vmap`):
        :func:`jaxgear.iso1328_tolerances_array`, the larger of the two gears' each.

        Args:
            normal_module: m_n (m), a scalar. reference_diameter: (d1, d2) (m), shape (2,).
            face_width: (b1, b2) (m), shape (2,). grade: the flank tolerance class, a Python
                integer 1-11 (static).

        Returns:
            The accuracy, equal to :meth:`from_grade`'s of the same pair (but where a
            tolerance lies within 1e-11 of a rounding step of ISO 1328-1 5.2.3 without being
            on it). The standard's scope (m_n, d, b) is not checked here (values may be
            traced).

        Raises:
            ValueError: a grade that is not an integer in [1, 11].
        """
        f_pt, f_fa, f_hb = iso1328_tolerances_array(
            normal_module, as_float(reference_diameter), as_float(face_width), grade
        )
        return cls(
            base_pitch=jnp.max(f_pt),
            profile_form=jnp.max(f_fa * jnp.ones(2)),
            helix_slope=jnp.max(f_hb),
            grade=int(grade),
        )


class GivenFactors(eqx.Module):
    """Load factors given by the user (``None``: computed by ISO 6336-1 method B). A given
    K_Hβ carries to K_Fβ (K_Fβ = K_Hβ^N_F, ISO 6336-1 clause 7) and a given K_Hα to K_Fα
    (K_Fα = K_Hα within K_Fα's upper limit, ISO 6336-1 8.3.4) unless those are given too.

    Raises:
        ValueError: a factor that is not a finite real number >= 1 (ISO 6336-1's load factors
            are each a peak load over its mean; NaN and ±inf included), in one line naming it
            and its value; a traced value (under ``jit``/``grad``) has its shape checked only.
            (The case file's given factors are also bounded above, [1, 10].)
    """

    K_v: float | None = None
    K_Hbeta: float | None = None
    K_Fbeta: float | None = None
    K_Halpha: float | None = None
    K_Falpha: float | None = None

    def __check_init__(self):
        for name in ("K_v", "K_Hbeta", "K_Fbeta", "K_Halpha", "K_Falpha"):
            value = getattr(self, name)
            if value is not None:
                check_real(name, value, "", lo=1.0, shape=(), shape_text="a scalar",
                           where="GivenFactors")


#: ISO 6336-3:2019's mean stress influence factor Y_M for a tooth loaded on both flanks in
#: turn (an idler: stress ratio R ≈ −1.2), its method C value; one-way bending (R = 0): 1
IDLER_MEAN_STRESS_FACTOR = 0.7


class ToothLoading(eqx.Module):
    """How each gear's teeth are loaded per turn, (pinion, gear) each.

    Attributes:
        cycles_per_turn: load cycles of the rated flank (and of its fillet in tension) per
            turn of the gear, >= 1: the number of meshes in which the gear has the same role
            (driving or driven); the life factors' N_L = life · turns · cycles_per_turn.
        mean_stress_factor: Y_M of ISO 6336-3:2019 (mean stress influence factor, in σ_FG),
            (0, 1]: 1 for one-way bending; :data:`IDLER_MEAN_STRESS_FACTOR` (0.7, the
            standard's method C value for R ≈ −1.2) for a gear loaded on alternate flanks in
            turn (driven in one mesh, driving in another: an idler).

    :meth:`idler` gives a gear of two meshes on alternate flanks; the default is a pair's
    (one cycle per turn, one-way bending). A pair or a train mesh's value comes from the
    train's layout (``jaxgear.io``).
    """

    cycles_per_turn: tuple[float, float] = eqx.field(static=True)
    mean_stress_factor: tuple[float, float] = eqx.field(static=True)

    def __init__(self, cycles_per_turn=(1.0, 1.0), mean_stress_factor=(1.0, 1.0)):
        w = "ToothLoading"
        check_real("cycles_per_turn", cycles_per_turn, "", lo=1.0, shape=(2,), where=w)
        check_real(
            "mean_stress_factor", mean_stress_factor, "", lo=0.0, lo_open=True, hi=1.0,
            shape=(2,), where=w,
        )
        self.cycles_per_turn = tuple(float(c) for c in cycles_per_turn)
        self.mean_stress_factor = tuple(float(y) for y in mean_stress_factor)

    @classmethod
    def of_roles(cls, driving: tuple[int, int], driven: tuple[int, int]) -> ToothLoading:
        """From the number of meshes each gear of the rated mesh drives in (``driving``) and is
        driven in (``driven``), (pinion, gear): a gear rated in the mesh where it drives (the
        pinion, member 0) has ``driving`` cycles per turn on that flank, one rated where it is
        driven (member 1) ``driven``; Y_M = 0.7 for a gear with both roles (its two flanks
        loaded in turn, fully reversed bending), 1 otherwise."""
        same = (driving[0], driven[1])
        both = [d > 0 and n > 0 for d, n in zip(driving, driven, strict=True)]
        ym = [IDLER_MEAN_STRESS_FACTOR if b else 1.0 for b in both]
        return cls([float(max(c, 1)) for c in same], ym)


class RatingSettings(eqx.Module):
    """Everything of a rating but the geometry and the operating point.

    Attributes:
        material: :class:`RatingMaterial`. lubrication: :class:`Lubrication`.
        accuracy: :class:`GearAccuracy`. life: required life (s). application_factor: K_A.
        given: :class:`GivenFactors`. tip_relief: C_a (m) of K_v; ``None``: the running-in
            value C_ay = (σ_Hlim/97 − 18.45)²/18 + 1.5 µm (σ_Hlim in N/mm², ISO 6336-1 clause 6).
        min_safety_pitting, min_safety_bending: S_Hmin, S_Fmin (σ_HP = σ_HG/S_Hmin; 1 default).
        standard: the rating standard and its edition, a kind passed as an object
            (:class:`jaxgear.rating.AbstractRatingStandard`): default
            :class:`jaxgear.rating.Edition2019` (ISO 6336:2019), or
            :class:`jaxgear.rating.Edition2006` to compare with ratings to it.
        loading: :class:`ToothLoading`, load cycles per turn and Y_M per gear (default: a
            pair's, one cycle per turn, one-way bending).
        crowning: C_β (m), the lead crowning of K_Hβ (ISO 6336-1 clause 7: F_βx = B₂ f_Hβ
            with B₂ = 0.5 for crowning, at least f_Hβ/2 deep, 1 without); ``None`` or 0: none.
            A case file derives ``tip_relief`` and ``crowning`` from its ``[modifications]``
            (:meth:`jaxgear.Modifications.rating_inputs`).
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
    standard: AbstractRatingStandard = Edition2019()
    loading: ToothLoading = ToothLoading()
    crowning: float | None = None

    def __check_init__(self):
        """One ``ValueError`` line naming the argument, its value and the allowed range: life
        > 0 s, application_factor >= 1 (ISO 6336-1's K_A), tip_relief and crowning None or >= 0 m,
        min_safety_* > 0, and each part of its kind (a traced number: its shape only)."""
        w = "RatingSettings"
        for name, kind, allowed in (
            ("material", RatingMaterial, "a jaxgear.rating.RatingMaterial"),
            ("lubrication", Lubrication, "a jaxgear.rating.Lubrication"),
            ("accuracy", GearAccuracy, "a jaxgear.rating.GearAccuracy (e.g. GearAccuracy.from_grade)"),
            ("given", GivenFactors, "a jaxgear.rating.GivenFactors"),
            ("standard", AbstractRatingStandard,
             "a jaxgear.rating.AbstractRatingStandard (jaxgear.rating.Edition2019(), ...)"),
            ("loading", ToothLoading, "a jaxgear.rating.ToothLoading"),
        ):
            check_instance(name, getattr(self, name), kind, allowed, w)
        scalar = {"shape": (), "shape_text": "a scalar", "where": w}
        check_real("life", self.life, "s", lo=0.0, lo_open=True, **scalar)
        check_real("application_factor", self.application_factor, "", lo=1.0, **scalar)
        for name in ("tip_relief", "crowning"):
            if getattr(self, name) is not None:
                check_real(name, getattr(self, name), "m", lo=0.0, **scalar)
        for name in ("min_safety_pitting", "min_safety_bending"):
            check_real(name, getattr(self, name), "", lo=0.0, lo_open=True, **scalar)

    def running_in_tip_relief(self) -> Float[Array, ""]:
        """The running-in tip relief C_ay (m) that K_v takes without a tip relief: (σ_Hlim/97 −
        18.45)²/18 + 1.5 µm, σ_Hlim (N/mm²) the smaller of the gears' (ISO 6336-1 clause 6)."""
        sh = jnp.min(self.material.sigma_h_lim)
        return ((sh * 1e-6 / 97.0 - 18.45) ** 2 / 18.0 + 1.5) * 1e-6

    def with_modifications(self, modifications) -> RatingSettings:
        """These settings with ISO 6336-1's modification inputs of a design: ``tip_relief`` C_a
        and ``crowning`` C_β of ``modifications`` (a :class:`jaxgear.Modifications`; the larger
        member's depths, :meth:`jaxgear.Modifications.rating_inputs`), C_a the running-in C_ay
        where the design has no tip relief. Differentiable in the depths (the load-capacity
        objective rates each design so: ``optimise.LeastSafetyFactor``)."""
        ca, cb = modifications.rating_inputs()
        relief = jnp.where(ca > 0, ca, self.running_in_tip_relief())
        return eqx.tree_at(
            lambda s: (s.tip_relief, s.crowning),
            self,
            (relief, cb),
            is_leaf=lambda x: x is None,
        )
