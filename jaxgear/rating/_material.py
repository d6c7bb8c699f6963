"""Material kinds of the ISO 6336 rating: the life curves, running-in allowances, slip-layer
thickness, roughness and size factors that depend on the heat treatment.

A kind of material is one concrete subclass of :class:`AbstractTreatment` (case hardened,
through hardened, nitrided), passed to :class:`jaxgear.rating.RatingMaterial` as an object; the case
file's names map to them in :mod:`jaxgear.io` only. Every method is a pure ``jax.numpy``
function of its arguments (SI units; cycles are counts).

Sources (cited by the factors' titles): ISO 6336-2:2019, life factor Z_NT; ISO 6336-3:2019,
life factor Y_NT, relative notch sensitivity factor Y_δrelT (slip-layer thickness ρ'),
relative surface factor Y_RrelT, size factor Y_X; ISO 6336-1:2019, running-in allowances y_α
(dynamic and transverse load factors) and y_β (face load factor).

ISO 6336-3's table of the slip-layer thickness ρ' (2006: 13.3, Y_δrelT method B) by
material: grey cast iron (GG) 0.3124 mm at σ_B = 150 N/mm² and 0.3095 mm at σ_B = 300 N/mm²
(with ferritic nodular iron); nitrided (NT, NV) 0.1005 mm; structural steel (St) 0.0833 mm at
σ_S = 300 N/mm², 0.0445 mm at 400 N/mm²; through-hardened wrought steel (V; also malleable and
perlitic or bainitic nodular iron) by its 0.2 % proof stress, 0.0281, 0.0194, 0.0064 and
0.0014 mm at σ_0.2 = 500, 600, 800 and 1000 N/mm² (:data:`THROUGH_HARDENED_SLIP_LAYER`);
case-hardened, induction or flame hardened (Eh, IF root) 0.0030 mm. The treatments here carry
the rows of Eh, NT/NV and V; grey iron and structural steel are not kinds of this module.
"""

from __future__ import annotations

import abc
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._util import check_instance, check_real

__all__ = [
    "THROUGH_HARDENED_SLIP_LAYER",
    "AbstractTreatment",
    "CaseHardened",
    "Nitrided",
    "PairTreatment",
    "ThroughHardened",
    "life_curve",
    "through_hardened_slip_layer",
]

#: the Brinell hardness a rated steel can have (HB; the case file's ``brinell_hardness_HB``):
#: ISO 6336-5's material lines span about 110 HB (normalized low-carbon steel) to 700 (a
#: case-hardened surface, 60 HRC, beyond the Brinell scale's own reach; Z_W clips HB to
#: [130, 470])
BRINELL_RANGE = (100.0, 700.0)

#: ISO 6336-3's slip-layer thickness ρ' of through-hardened wrought steel (V) by its 0.2 % proof
#: stress (the standard's table of ρ', 2006: 13.3): (σ_0.2 Pa, ρ' m), σ_0.2 increasing
THROUGH_HARDENED_SLIP_LAYER = (
    (500e6, 0.0281e-3),
    (600e6, 0.0194e-3),
    (800e6, 0.0064e-3),
    (1000e6, 0.0014e-3),
)


def through_hardened_slip_layer(proof_stress: float) -> float:
    """ρ' (m) of through-hardened steel at its 0.2 % proof stress σ_0.2 (Pa): the rows of ISO
    6336-3's table (:data:`THROUGH_HARDENED_SLIP_LAYER`) and linear between them (the standard
    tabulates the rows only).

    Raises:
        ValueError: σ_0.2 outside the table, [500, 1000] N/mm² (one line naming the value).
    """
    lo, hi = THROUGH_HARDENED_SLIP_LAYER[0][0], THROUGH_HARDENED_SLIP_LAYER[-1][0]
    v = float(proof_stress)
    if not lo <= v <= hi:
        raise ValueError(
            f"ThroughHardened: proof_stress = {v:g} Pa is out of range, allowed [{lo:g}, {hi:g}] "
            "Pa (the rows of ISO 6336-3's slip-layer table, σ_0.2 = 500 to 1000 N/mm²)"
        )
    s = [p[0] for p in THROUGH_HARDENED_SLIP_LAYER]
    rho = [p[1] for p in THROUGH_HARDENED_SLIP_LAYER]
    return float(np.interp(v, s, rho))


def life_curve(cycles, points):
    """A life factor that is a power law of the number of load cycles between the ``points``
    ((N, factor) pairs, N increasing) and constant below the first (static strength) and
    beyond the last (ISO's curves end at 10¹⁰ cycles): log(factor) is interpolated linearly in
    log N, so each segment is a power law ``factor = factor_b (N_b/N)^k`` through its two end
    points, the form of ISO 6336-2/-3's life factors (the long-life segments of case-hardened
    steel: Z_NT = (5·10⁷/N_L)^0.03067, Y_NT = (3·10⁶/N_L)^0.0200; checked against the Z_NT of
    ISO/TR 6336-30 example 1 and the Z_NT, Y_NT of a published KISSsoft report,
    docs/rating.md)."""
    n = jnp.log(jnp.maximum(cycles, 1.0))
    logs = jnp.log(jnp.asarray([p[0] for p in points], dtype=n.dtype))
    vals = jnp.log(jnp.asarray([p[1] for p in points], dtype=n.dtype))
    return jnp.exp(jnp.interp(n, logs, vals))


class AbstractTreatment(eqx.Module):
    """The heat treatment of a gear material: the factors of ISO 6336 that depend on it.

    Subclasses give :attr:`z_nt_points`, :attr:`y_nt_points` (the life curves
    :meth:`z_nt`, :meth:`y_nt` at ``cycles`` load cycles),
    :attr:`slip_layer` ρ' (m, ISO 6336-3), :meth:`y_r_rel` (relative roughness factor
    at the root's R_z, m), :meth:`y_x` (size factor at m_n, m) and :meth:`running_in`
    (the allowances y_α, y_β of ISO 6336-1 from a deviation, m)."""

    #: the pitting life curve's corners, ((N, Z_NT), ...) with N increasing: static strength
    #: at the first, the endurance reference at the second, the end of the curve (10¹⁰) at the
    #: last (ISO 6336-2's Z_NT; :meth:`z_nt`, and the S–N line of a load spectrum,
    #: :class:`jaxgear.rating.SNCurve`)
    z_nt_points: eqx.AbstractClassVar[tuple[tuple[float, float], ...]]
    #: the bending life curve's corners, as :attr:`z_nt_points` (ISO 6336-3's Y_NT)
    y_nt_points: eqx.AbstractClassVar[tuple[tuple[float, float], ...]]

    def z_nt(self, cycles):
        """Z_NT at ``cycles`` load cycles (:func:`life_curve` of :attr:`z_nt_points`)."""
        return life_curve(cycles, self.z_nt_points)

    def y_nt(self, cycles):
        """Y_NT at ``cycles`` load cycles (:func:`life_curve` of :attr:`y_nt_points`)."""
        return life_curve(cycles, self.y_nt_points)

    def per_gear(self) -> tuple[AbstractTreatment, AbstractTreatment]:
        """(pinion's, gear's) treatment: this one for both (:class:`PairTreatment`: each its
        own)."""
        return (self, self)

    @property
    @abc.abstractmethod
    def slip_layer(self) -> float: ...

    @abc.abstractmethod
    def y_r_rel(self, rz): ...

    @abc.abstractmethod
    def y_x(self, normal_module): ...

    @abc.abstractmethod
    def running_in_alpha(self, deviation, sigma_h_lim): ...

    @abc.abstractmethod
    def running_in_beta(self, deviation, sigma_h_lim): ...

    #: a surface-hardened flank (case hardened, nitrided): work-hardens a softer mating gear
    surface_hardened: ClassVar[bool] = True

    @classmethod
    def of_material(cls, brinell_hardness=None, proof_stress=None) -> AbstractTreatment:
        """This kind for a gear of surface hardness ``brinell_hardness`` (HB) and 0.2 % proof
        stress ``proof_stress`` (Pa), either ``None`` when unknown (the case file's ``[material]``
        keys): a surface-hardened kind has one ρ' for all hardnesses and no Z_W of its own, so
        both go unused here (:class:`ThroughHardened` reads them)."""
        return cls()

    def work_hardening(self, partner: AbstractTreatment):
        """Z_W of this gear meshing with ``partner`` (ISO 6336-2, work hardening factor): 1 but
        for a through-hardened gear with a given Brinell hardness against a surface-hardened
        one (:class:`ThroughHardened`)."""
        return 1.0

    def work_hardening_factors(self):
        """Z_W of (pinion, gear), both of this material: (2,)."""
        return jnp.ones(2) * self.work_hardening(self)


def _y_r_hardened(rz):
    """Y_RrelT of V, GGG (perl., bai.), Eh, IF: 1.12 below R_z = 1 µm, else 1.674 −
    0.529 (R_z + 1)^0.1 (R_z in µm; ISO 6336-3, relative surface factor, method B)."""
    um = rz * 1e6
    return jnp.where(um < 1.0, 1.120, 1.674 - 0.529 * (jnp.maximum(um, 1.0) + 1.0) ** 0.1)


class CaseHardened(AbstractTreatment):
    """Case-hardened wrought steel (Eh), pitting not permitted: Z_NT 1.6 at 10⁵, 1.0 at 5·10⁷,
    0.85 at 10¹⁰ cycles; Y_NT 2.5 at 10³, 1.0 at 3·10⁶, 0.85 at 10¹⁰; ρ' = 0.003 mm; y_α =
    0.075 f_pb ≤ 3 µm, y_β = 0.15 F_βx ≤ 6 µm; Y_X = 1.05 − 0.01 m_n (mm) in [0.8, 1]."""

    z_nt_points: ClassVar[tuple] = ((1e5, 1.6), (5e7, 1.0), (1e10, 0.85))
    y_nt_points: ClassVar[tuple] = ((1e3, 2.5), (3e6, 1.0), (1e10, 0.85))

    @property
    def slip_layer(self) -> float:
        return 0.003e-3

    def y_r_rel(self, rz):
        return _y_r_hardened(rz)

    def y_x(self, normal_module):
        return jnp.clip(1.05 - 0.01 * normal_module * 1e3, 0.8, 1.0)

    def running_in_alpha(self, deviation, sigma_h_lim):
        return jnp.minimum(0.075 * deviation, 3e-6)

    def running_in_beta(self, deviation, sigma_h_lim):
        return jnp.minimum(0.15 * deviation, 6e-6)


class ThroughHardened(AbstractTreatment):
    """Through-hardened wrought steel (V), pitting not permitted: Z_NT as :class:`CaseHardened`;
    Y_NT 2.5 at 10⁴, 1.0 at 3·10⁶, 0.85 at 10¹⁰; y_α = 160/σ_Hlim f_pb, y_β = 320/σ_Hlim F_βx
    (σ_Hlim in N/mm²); Y_X = 1.03 − 0.006 m_n (mm) in [0.85, 1].

    Args:
        slip_layer_m: ρ' (m) of Y_δrelT given directly; or
        proof_stress: σ_0.2 (Pa), ρ' from ISO 6336-3's table (:func:`through_hardened_slip_layer`,
            [500, 1000] N/mm²). Neither: ρ' = 0.0281 mm, the table's row σ_0.2 = 500 N/mm².
        brinell_hardness: HB (or None), for the work hardening factor Z_W against a
            surface-hardened mate (:meth:`work_hardening`).

    Raises:
        ValueError: both ``slip_layer_m`` and ``proof_stress``, a proof stress outside the
            table, ``slip_layer_m`` <= 0, a ``brinell_hardness`` outside [100, 700] HB
            (:data:`BRINELL_RANGE`), or any of them not a finite real number; one line naming
            the argument.
    """

    slip_layer_m: float
    brinell_hardness: float | None
    proof_stress: float | None
    surface_hardened: ClassVar[bool] = False

    def __init__(self, slip_layer_m=None, brinell_hardness=None, proof_stress=None):
        w = "ThroughHardened"
        if brinell_hardness is not None:
            lo, hi = BRINELL_RANGE
            check_real("brinell_hardness", brinell_hardness, "HB", lo=lo, hi=hi, shape=(),
                       shape_text="a scalar", where=w)
            brinell_hardness = float(brinell_hardness)
        if proof_stress is not None:
            if slip_layer_m is not None:
                raise ValueError(
                    "ThroughHardened: slip_layer_m and proof_stress both given: give one "
                    "(ρ' directly, or σ_0.2 for ISO 6336-3's table)"
                )
            check_real("proof_stress", proof_stress, "Pa", lo=THROUGH_HARDENED_SLIP_LAYER[0][0],
                       hi=THROUGH_HARDENED_SLIP_LAYER[-1][0], shape=(), shape_text="a scalar",
                       where=w)
            slip_layer_m = through_hardened_slip_layer(proof_stress)
            proof_stress = float(proof_stress)
        elif slip_layer_m is None:
            slip_layer_m = THROUGH_HARDENED_SLIP_LAYER[0][1]
        check_real("slip_layer_m", slip_layer_m, "m", lo=0.0, lo_open=True, shape=(),
                   shape_text="a scalar", where=w)
        self.slip_layer_m = float(slip_layer_m)
        self.brinell_hardness = brinell_hardness
        self.proof_stress = proof_stress

    @classmethod
    def of_material(cls, brinell_hardness=None, proof_stress=None) -> ThroughHardened:
        """Z_W from ``brinell_hardness`` and ρ' from ``proof_stress`` (the table; ``None``: the
        default ρ')."""
        return cls(brinell_hardness=brinell_hardness, proof_stress=proof_stress)

    def work_hardening(self, partner: AbstractTreatment):
        """Z_W = 1.2 − (HB − 130)/1700 (HB clipped to [130, 470]) against a surface-hardened
        ``partner``, else 1 (ISO 6336-2:2006 clause 13, the soft gear of a pair with a hardened
        pinion; the 2019 edition's roughness term (3/R_zH)^0.15 is not applied: the KISSsoft
        report rated to the 2006 edition prints 1.135 at HB 240, which is the bare formula)."""
        if self.brinell_hardness is None or not partner.surface_hardened:
            return 1.0
        hb = min(max(float(self.brinell_hardness), 130.0), 470.0)
        return 1.2 - (hb - 130.0) / 1700.0

    z_nt_points: ClassVar[tuple] = ((1e5, 1.6), (5e7, 1.0), (1e10, 0.85))
    y_nt_points: ClassVar[tuple] = ((1e4, 2.5), (3e6, 1.0), (1e10, 0.85))

    @property
    def slip_layer(self) -> float:
        return self.slip_layer_m

    def y_r_rel(self, rz):
        return _y_r_hardened(rz)

    def y_x(self, normal_module):
        return jnp.clip(1.03 - 0.006 * normal_module * 1e3, 0.85, 1.0)

    def running_in_alpha(self, deviation, sigma_h_lim):
        return 160.0 / (sigma_h_lim * 1e-6) * deviation

    def running_in_beta(self, deviation, sigma_h_lim):
        return 320.0 / (sigma_h_lim * 1e-6) * deviation


class Nitrided(AbstractTreatment):
    """Nitrided steel (NT, NV nitrided): Z_NT 1.3 at 10⁵, 1.0 at 2·10⁶, 0.85 at 10¹⁰;
    Y_NT 1.6 at 10³, 1.0 at 3·10⁶, 0.85 at 10¹⁰; ρ' = 0.1005 mm; Y_RrelT = 1.025 below
    R_z = 1 µm, else 4.299 − 3.259 (R_z + 1)^0.005; y_α, y_β and Y_X as :class:`CaseHardened`."""

    z_nt_points: ClassVar[tuple] = ((1e5, 1.3), (2e6, 1.0), (1e10, 0.85))
    y_nt_points: ClassVar[tuple] = ((1e3, 1.6), (3e6, 1.0), (1e10, 0.85))

    @property
    def slip_layer(self) -> float:
        return 0.1005e-3

    def y_r_rel(self, rz):
        um = rz * 1e6
        return jnp.where(um < 1.0, 1.025, 4.299 - 3.259 * (jnp.maximum(um, 1.0) + 1.0) ** 0.005)

    def y_x(self, normal_module):
        return jnp.clip(1.05 - 0.01 * normal_module * 1e3, 0.8, 1.0)

    def running_in_alpha(self, deviation, sigma_h_lim):
        return jnp.minimum(0.075 * deviation, 3e-6)

    def running_in_beta(self, deviation, sigma_h_lim):
        return jnp.minimum(0.15 * deviation, 6e-6)


class PairTreatment(AbstractTreatment):
    """Two treatments, (pinion, gear): each gear's factors from its own material (a
    case-hardened planet in a through-hardened ring, as in the NREL 5 MW stages). Life, size,
    slip-layer and roughness factors come per gear as (2,) arrays (``cycles``, ``rz`` of shape
    (2,) or scalars); the running-in allowances of the pair are the mean of the two gears'
    (ISO 6336-1: y_α = (y_α1 + y_α2)/2 for different materials); Z_W per gear against the
    other (:meth:`AbstractTreatment.work_hardening`)."""

    pinion: AbstractTreatment
    gear: AbstractTreatment

    def __check_init__(self):
        for name in ("pinion", "gear"):
            value = getattr(self, name)
            if isinstance(value, PairTreatment):
                raise ValueError(
                    f"PairTreatment: {name} = PairTreatment(...) is out of range: allowed one "
                    "gear's treatment (not a PairTreatment): CaseHardened(), ThroughHardened(...) "
                    "or Nitrided()"
                )
            check_instance(name, value, AbstractTreatment, "a jaxgear rating treatment: "
                           "CaseHardened(), ThroughHardened(...) or Nitrided()", "PairTreatment")

    def _each(self, name, value):
        v = jnp.broadcast_to(jnp.asarray(value), (2,))
        return jnp.stack(
            [getattr(self.pinion, name)(v[0]), getattr(self.gear, name)(v[1])]
        )

    # the pair has no one curve: its gears' own (per_gear)
    z_nt_points: ClassVar[tuple] = ()
    y_nt_points: ClassVar[tuple] = ()

    def per_gear(self) -> tuple[AbstractTreatment, AbstractTreatment]:
        """(pinion's, gear's) own treatments."""
        return (self.pinion, self.gear)

    def z_nt(self, cycles):
        return self._each("z_nt", cycles)

    def y_nt(self, cycles):
        return self._each("y_nt", cycles)

    @property
    def slip_layer(self):
        return jnp.asarray([self.pinion.slip_layer, self.gear.slip_layer])

    def y_r_rel(self, rz):
        return self._each("y_r_rel", rz)

    def y_x(self, normal_module):
        return self._each("y_x", normal_module)

    def running_in_alpha(self, deviation, sigma_h_lim):
        return (
            self.pinion.running_in_alpha(deviation, sigma_h_lim)
            + self.gear.running_in_alpha(deviation, sigma_h_lim)
        ) / 2

    def running_in_beta(self, deviation, sigma_h_lim):
        return (
            self.pinion.running_in_beta(deviation, sigma_h_lim)
            + self.gear.running_in_beta(deviation, sigma_h_lim)
        ) / 2

    def work_hardening_factors(self):
        return jnp.asarray(
            [self.pinion.work_hardening(self.gear), self.gear.work_hardening(self.pinion)]
        )
