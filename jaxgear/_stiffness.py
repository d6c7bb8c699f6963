"""Mesh stiffness per unit contact length along the line of action (NumPy, evaluated once): the
tooth compliances and the foundation terms; the models built on them, passed as objects, are in
:mod:`jaxgear._stiffness_models` (docs/stiffness.md):

* ``uniform``: a given constant k0 (N/m per m of contact line).
* ``iso6336``: ISO 6336-1 method B single stiffness c' and mesh stiffness c_γα (virtual teeth
  z/(cos² β_b cos β), gear blank factor C_R, modulus scaling E/206 GPa, low-load factor below
  F_t/b = 100 N/mm), turned into a constant per unit contact length ``k0 = c_γα / (ε_α cos β_b)``,
  so that the mean mesh stiffness (normal to the flanks, in the base plane) times cos² β_b equals
  c_γα b.
* ``weber``: Weber–Banaschek thin-slice model, seed (1.1)–(1.3): Hertzian approach, tooth bending
  and shear of a cantilever on the real tooth-thickness profile (the exact rack-generated tooth of
  :mod:`fem_prep.tooth_form`: involute and trochoidal fillet down to the root circle), elastic
  foundation, pinion and gear compliances in series. The foundation (gear-body) term is an object:
  Weber's half-plane one (:class:`WeberFoundation`, L, M, P, Q = 5.2, 1.0, 1.4, 0.3), Sainsot et
  al.'s fit that depends on the bore (:class:`SainsotFoundation`), or left out
  (:class:`NoFoundation`), chosen per member (:class:`MemberFoundations`: a rigid pinion keeps
  its term, a flexible FE wheel, whose condensed body supplies the body compliance, has none). It varies along the profile; it is tabulated on a
  grid of the base-plane coordinate s ∈ [0, g_α] and interpolated linearly in the JAX kernels.

The profile is computed in the transverse section. A slice of width dz loaded along the transverse
line of action with f_t per unit width deflects δ_t = f_t / k_t; the flank-normal force is
f_t dz / cos β_b and the normal approach δ_t cos β_b, so the stiffness per unit *contact-line
length* (l = dz / cos β_b) is ``k = k_t / cos β_b``.

Everything here is a constant for JAX (no gradient through stiffness tables).
"""

from __future__ import annotations

import abc
import functools
import math
from typing import ClassVar

import equinox as eqx
import numpy as np

from ._geometry import GearPair, involute
from ._util import check_instance

__all__ = [
    "E_STEEL_ISO",
    "AbstractFoundation",
    "MemberFoundations",
    "NoFoundation",
    "SainsotFoundation",
    "WeberFoundation",
    "bore_radius",
    "iso6336_blank_factor",
    "iso6336_mesh_stiffness",
    "iso6336_pair_blank_factor",
    "iso6336_single_stiffness",
    "iso6336_virtual_teeth",
    "member_compliance",
    "sainsot_coefficients",
    "sainsot_fit_check",
    "tooth_geometry",
    "tooth_mass",
    "weber_profile",
]

_ISO_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
# Weber (1949) foundation constants for ν = 0.3 quoted by the seed under (1.3); M = 1.0 (Weber).
_WEBER_FOUNDATION = {"L": 5.2, "M": 1.0, "P": 1.4, "Q": 0.3}

# Sainsot, Velex & Duverger (2004), "Contribution of gear body to tooth deflections - a new
# bidimensional analytical formula", J. Mech. Des. 126(4) 748-752, doi:10.1115/1.1758252: fillet-
# foundation deflection δ_f = F cos²α_m / (E b) [L* (u_f/S_f)² + M* (u_f/S_f) + P* (1 + Q* tan²α_m)]
# with X*(h_f, θ_f) = A/θ_f² + B h_f² + C h_f/θ_f + D/θ_f + E h_f + F, h_f = r_f / r_int, θ_f (rad).
# Coefficients A..F as carried by ROSS (petrobras/ross, ross/multi_rotor/gear_element.py,
# GearElementTVMS._inv_kf), which also lists the span of each coefficient over the fit's data
# (_SAINSOT_SPAN); a gear whose L*, M*, P*, Q* fall outside it lies outside the fitted range.
_SAINSOT_FIT = {  # (A, B, C, D, E, F)
    "L": (-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045),
    "M": (60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086),
    "P": (-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236),
    "Q": (-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904),
}
_SAINSOT_SPAN = {"L": (6.82, 6.94), "M": (1.08, 3.29), "P": (2.56, 13.47), "Q": (0.141, 0.62)}
BORE_DEFAULT_FRACTION = 0.5  # default bore radius = 0.5 × root radius (solid blank on a shaft)


def sainsot_coefficients(h_f, theta_f) -> dict:
    """Sainsot et al. (2004) L*, M*, P*, Q* at h_f = r_f / r_int and θ_f (rad)."""
    return {
        k: a / theta_f**2 + b * h_f**2 + c * h_f / theta_f + d / theta_f + e * h_f + f
        for k, (a, b, c, d, e, f) in _SAINSOT_FIT.items()
    }


def bore_radius(pair: GearPair, member: int) -> float:
    """Bore radius r_int (m) of a member: ``Member.bore_radius``, else 0.5 × root radius."""
    m = (pair.pinion, pair.gear)[member]
    if m.bore_radius is not None:
        return float(m.bore_radius)
    return BORE_DEFAULT_FRACTION * pair.root_radii[member]


# Fillet points per flank of the tooth form used by the Weber integrals: the half thickness is
# interpolated between them with an O(n⁻²) error (≈ 1e-7 relative on the mean mesh stiffness).
_N_FILLET = 200


@functools.lru_cache(maxsize=64)
def _generated_tooth(geometry):
    from fem_prep.tooth_form import generate_tooth  # lazy: fem_prep's __init__ imports SciPy

    return generate_tooth(geometry, n_fillet=_N_FILLET, n_involute=2, n_tip=0)


def tooth_geometry(pair: GearPair, member: int):
    """The :class:`fem_prep.ToothGeometry` of member 0 (pinion) or 1 (gear) of ``pair``: the one
    object the tooth form, the FE tooth and the condensed bodies take.

    Raises:
        ValueError: a parameter out of range, named ``pinion.<name>`` or ``gear.<name>``.
    """
    from fem_prep.tooth_form import ToothGeometry  # lazy: fem_prep's __init__ imports SciPy

    return member_tooth_geometry(ToothGeometry, pair, member)


def member_tooth_geometry(cls, pair, member: int, *extra):
    """``cls(teeth, m_n, α_n, β, x, h_a*, h_f*, ρ_fP*, *extra)`` of member 0 (pinion) or 1
    (gear) of ``pair`` (a :class:`fem_prep.ToothGeometry`, or an internal gear's
    :class:`fem_prep.InternalToothGeometry` with its cutter in ``extra``), its errors prefixed
    ``pinion.`` or ``gear.``."""
    m = (pair.pinion, pair.gear)[member]
    try:
        return cls(
            int(m.teeth),
            float(pair.normal_module),
            float(pair.normal_pressure_angle),
            float(pair.helix_angle),
            float(m.profile_shift),
            float(m.addendum_coeff),
            float(m.dedendum_coeff),
            float(m.fillet_radius_coeff),
            *extra,
        )
    except ValueError as err:
        raise ValueError(f"{('pinion', 'gear')[member]}.{err}") from None


def _tooth_form(pair: GearPair, member: int):
    """The rack-generated tooth of a member (:class:`fem_prep.tooth_form.ToothForm`, cached).

    Its outline carries only the fillet at full resolution (200 points per flank) and the two
    ends of the involute; call :func:`fem_prep.tooth_form.generate_tooth` for a drawing/mesh.
    """
    geometry = tooth_geometry(pair, member)  # its errors name pinion./gear. already
    try:
        return _generated_tooth(geometry)
    except ValueError as err:
        raise ValueError(f"{('pinion', 'gear')[member]}.{err}") from None


def _root_angle(pair: GearPair, member: int) -> float:
    """θ_f (rad): angle from the tooth centre line to the point where the generated fillet meets
    the root circle (half the angular tooth thickness at the root circle, fillets included)."""
    return float(_tooth_form(pair, member).root_half_angle)


def sainsot_fit_check(pair: GearPair) -> list[dict]:
    """Per member: h_f, θ_f, the Sainsot coefficients and the names of those outside the span
    of the fit (``outside``; empty when the gear lies within the fitted range)."""
    out = []
    for i in (0, 1):
        h = pair.root_radii[i] / bore_radius(pair, i)
        th = _root_angle(pair, i)
        coeffs = sainsot_coefficients(h, th)
        outside = [
            k for k, v in coeffs.items() if not _SAINSOT_SPAN[k][0] <= v <= _SAINSOT_SPAN[k][1]
        ]
        out.append({"h_f": h, "theta_f": th, "coefficients": coeffs, "outside": outside})
    return out


def _foundation_term(f: dict, ratio: np.ndarray, cos2_over_e, tan2) -> np.ndarray:
    """Seed (1.3): cos²α/E [L (u/S)² + M (u/S) + P (1 + Q tan²α)], (m/N)·m."""
    return cos2_over_e * (f["L"] * ratio**2 + f["M"] * ratio + f["P"] * (1 + f["Q"] * tan2))


class AbstractFoundation(eqx.Module):
    """The foundation (gear-body) term of a tooth's compliance, seed (1.3): what the gear body
    adds to the deflection of a tooth loaded at distance u from the root circle.

    Subclasses implement :meth:`add_compliance`; ``name`` is the word summaries print (the case
    file's ``[mesh] foundation``, mapped to these objects by :mod:`jaxgear.io`), ``fe_body``
    whether the ``fe2d`` model meshes the gear body down to the bore with it (``False``: the
    tooth only, the body being supplied elsewhere, e.g. by a condensed FE body).
    """

    name: ClassVar[str]  # a property of MemberFoundations
    fe_body: ClassVar[bool]

    @abc.abstractmethod
    def add_compliance(
        self,
        c: np.ndarray,
        pair: GearPair,
        member: int,
        u: np.ndarray,
        cos2_over_e: np.ndarray,
        tan2: np.ndarray,
    ) -> np.ndarray:
        """The tooth compliance ``c`` with this foundation's term added.

        Args:
            c: the tooth's bending + shear + compression compliance, (m/N)·m, shape (n,).
            pair: the gear pair; member: 0 pinion, 1 gear.
            u: cantilever length (m) from the root circle to the load, shape (n,).
            cos2_over_e: cos²α / E (1/Pa) of the load angle α to the centre-line normal, (n,).
            tan2: tan²α, shape (n,).

        Returns:
            compliance per unit face width, (m/N)·m, shape (n,).
        """

    def member(self, member: int) -> AbstractFoundation:
        """The foundation of ``member`` (0 pinion, 1 gear): this one for both."""
        return self

    def ring_compliance(self, c, s_root: float, u, cos2_over_e, tan2) -> np.ndarray:
        """The compliance ``c`` of an internal gear's tooth (a ring's) with this foundation's
        term added; arguments as :meth:`add_compliance`, ``s_root`` the chordal tooth thickness
        at the root circle (m).

        Raises:
            ValueError: a foundation derived for external gear bodies (this default).
        """
        raise ValueError(
            f"foundation = {self.name!r} is out of range for an internal gear's teeth: allowed "
            "WeberFoundation() (Weber's half-plane) or NoFoundation() (Sainsot et al.'s fit is "
            "derived for external gear bodies on a bore)"
        )

    def without_body(self, flexible: tuple[bool, bool]) -> AbstractFoundation:
        """The foundations with a flexible member's (a condensed FE body, whose rim supplies the
        body compliance, seed remark after (2.31)) replaced by :class:`NoFoundation`."""
        pinion, gear = (
            NoFoundation() if flex else self.member(i) for i, flex in enumerate(flexible)
        )
        return MemberFoundations(pinion, gear)


class WeberFoundation(AbstractFoundation):
    """Weber's (1949) half-plane foundation, seed (1.3), L, M, P, Q = 5.2, 1.0, 1.4, 0.3 (ν = 0.3),
    S = the chordal tooth thickness at the root circle; it does not depend on the bore."""

    name: ClassVar[str] = "weber"
    fe_body: ClassVar[bool] = True

    def add_compliance(self, c, pair, member, u, cos2_over_e, tan2):
        s_fd = float(_chordal_thickness(pair, member, np.array([pair.root_radii[member]]))[0])
        return c + _foundation_term(_WEBER_FOUNDATION, u / s_fd, cos2_over_e, tan2)

    def ring_compliance(self, c, s_root, u, cos2_over_e, tan2):
        """Weber's half-plane term for a ring's tooth, S = its root chord (a ring's rim is the
        body below its root circle; Weber's half plane, as for external teeth)."""
        return c + _foundation_term(_WEBER_FOUNDATION, u / s_root, cos2_over_e, tan2)


class SainsotFoundation(AbstractFoundation):
    """Sainsot, Velex & Duverger's (2004) fit of the foundation term, which depends on the bore:
    L*, M*, P*, Q* at h_f = r_f / r_int (:func:`bore_radius`), θ_f the root half angle
    (:func:`sainsot_coefficients`, :func:`sainsot_fit_check`), S_f = 2 r_f θ_f."""

    name: ClassVar[str] = "sainsot"
    fe_body: ClassVar[bool] = True

    def add_compliance(self, c, pair, member, u, cos2_over_e, tan2):
        rf = pair.root_radii[member]
        theta_f = _root_angle(pair, member)
        f = sainsot_coefficients(rf / bore_radius(pair, member), theta_f)
        return c + _foundation_term(f, u / (2 * rf * theta_f), cos2_over_e, tan2)


class NoFoundation(AbstractFoundation):
    """No foundation term: the tooth alone (a condensed FE body supplies the body compliance)."""

    name: ClassVar[str] = "none"
    fe_body: ClassVar[bool] = False

    def add_compliance(self, c, pair, member, u, cos2_over_e, tan2):
        return c

    def ring_compliance(self, c, s_root, u, cos2_over_e, tan2):
        return c


class MemberFoundations(AbstractFoundation):
    """One foundation per member, e.g. ``MemberFoundations(WeberFoundation(), NoFoundation())``
    for a rigid pinion against a wheel that is a condensed FE body.

    Attributes:
        pinion, gear: each member's :class:`AbstractFoundation`.

    Raises:
        ValueError: a member's foundation that is not an :class:`AbstractFoundation`.
    """

    pinion: AbstractFoundation
    gear: AbstractFoundation
    fe_body: ClassVar[bool] = True  # per member: :meth:`member`

    def __check_init__(self):
        for tag in ("pinion", "gear"):
            check_instance(
                tag,
                getattr(self, tag),
                AbstractFoundation,
                "a jaxgear foundation (WeberFoundation(), SainsotFoundation(), NoFoundation())",
                "MemberFoundations",
            )

    @property
    def name(self) -> str:
        return f"({self.pinion.name}, {self.gear.name})"

    def member(self, member: int) -> AbstractFoundation:
        return (self.pinion, self.gear)[member]

    def add_compliance(self, c, pair, member, u, cos2_over_e, tan2):
        return self.member(member).add_compliance(c, pair, member, u, cos2_over_e, tan2)

    def ring_compliance(self, c, s_root, u, cos2_over_e, tan2):
        return self.gear.ring_compliance(c, s_root, u, cos2_over_e, tan2)


@functools.singledispatch
def iso6336_virtual_teeth(pair: GearPair) -> tuple[float, float]:
    """Virtual numbers of teeth (z_n1, z_n2) of ISO 6336-1 method B (§9.3, the q' equation):
    ``z_n = z / (cos² β_b cos β)`` (not the older z / cos³ β; the two differ by ≈ 1 % at
    β = 15°, ≈ 0.16 % on c'_th of ISO/TR 6336-30 example 1). Dispatched on the pair's type: an
    :class:`~jaxgear.InternalGearPair` takes the internal gear's z_n2 as infinite
    (``jaxgear/_internal.py``)."""
    beta, beta_b = pair.helix_angle, pair.base_helix_angle
    f = math.cos(beta_b) ** 2 * math.cos(beta)
    return pair.pinion.teeth / f, pair.gear.teeth / f


def iso6336_blank_factor(member, normal_module: float) -> float:
    """Gear blank factor C_R of one member, ISO 6336-1 method B (§9.3, "gear blank factor"):
    ``C_R = 1 + ln(b_s/b) / (5 exp(s_R / (5 m_n)))``.

    Args:
        member: a :class:`Member`; its ``web_thickness`` b_s (m), ``rim_thickness`` s_R (m) and
            ``face_width`` b (m). A solid blank (``web_thickness`` or ``rim_thickness`` None)
            gives C_R = 1.
        normal_module: m_n (m).

    Returns:
        C_R (-). As the standard prescribes, b_s/b is clamped to [0.2, 1.2] and s_R/m_n to >= 1
        (b_s/b > 1 gives C_R slightly above 1, at most 1.0299).
    """
    bs, sr = member.web_thickness, member.rim_thickness
    if bs is None or sr is None:
        return 1.0
    ratio = min(max(bs / member.face_width, 0.2), 1.2)
    rim = max(sr / normal_module, 1.0)
    return 1.0 + math.log(ratio) / (5.0 * math.exp(rim / 5.0))


def iso6336_pair_blank_factor(pair: GearPair) -> float:
    """C_R of the pair: the mean of the members' C_R (:func:`iso6336_blank_factor`).

    The standard's curve holds for mating gears of similar blanks, where the mean is the curve's
    value. For dissimilar blanks (a solid pinion against a webbed wheel) jaxgear takes the mean,
    i.e. half the correction: the blank's extra compliance acts on one of the two teeth in series
    (the formula's C_R < 1 is a compliance shared by both members).
    """
    return 0.5 * (
        iso6336_blank_factor(pair.pinion, pair.normal_module)
        + iso6336_blank_factor(pair.gear, pair.normal_module)
    )


E_STEEL_ISO = 206e9  # Pa: ISO 6336-1 steel modulus, the reference of c'_th (method B)
LOW_LOAD_LIMIT = 1e5  # N/m = 100 N/mm: below it c' is reduced (ISO 6336-1 §9.3.1)


def iso6336_single_stiffness(
    pair: GearPair,
    youngs_modulus: float = E_STEEL_ISO,
    specific_load: float | None = None,
) -> float:
    """ISO 6336-1 method B single stiffness c' (N/m per m of face width), §9.3.

    ``c' = c'_th C_M C_R C_B cos β · E/E_st [· (F_t K_A/b / 100 N/mm)^0.25 below 100 N/mm]`` with

    * ``c'_th = 1/q'``, q' (mm·µm/N) = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2
      + C7 x2/z_n2 + C8 x1² + C9 x2², z_n = z/(cos² β_b cos β) (:func:`iso6336_virtual_teeth`);
    * C_M = 0.8 (theoretical to measured);
    * C_R gear blank factor, :func:`iso6336_pair_blank_factor` (1 for solid blanks);
    * ``C_B = 0.5 Σ [1 + 0.5 (1.2 − h_fP/m_n)][1 − 0.02 (20° − α_n)]``, h_fP/m_n = the member's
      dedendum coefficient (the basic rack dedendum);
    * E/E_st: other materials scale with E (for two materials E = 2E1E2/(E1+E2)), E_st = 206 GPa;
    * the low-load factor (F_t K_A/b / 100)^0.25 when F_t K_A/b < 100 N/mm (1 above).

    Args:
        pair: the gear pair (member blanks: ``Member.web_thickness``/``rim_thickness``).
        youngs_modulus: E (Pa), default steel (206 GPa, the standard's reference).
        specific_load: F_t K_A / b (N/m): nominal tangential load at the reference circle per
            unit face width; ``None``: at or above 100 N/mm (no low-load reduction).

    Valid (ISO) for x1 >= x2, −0.5 <= x1 + x2 <= 2, β <= 30°; not checked.
    """
    zn1, zn2 = iso6336_virtual_teeth(pair)
    x1, x2 = pair.pinion.profile_shift, pair.gear.profile_shift
    c = _ISO_C
    q = (
        c[0]
        + c[1] / zn1
        + c[2] / zn2
        + c[3] * x1
        + c[4] * x1 / zn1
        + c[5] * x2
        + c[6] * x2 / zn2
        + c[7] * x1**2
        + c[8] * x2**2
    )
    cth = 1.0 / q  # N/(mm·µm)
    an_deg = math.degrees(pair.normal_pressure_angle)
    cb = 0.5 * sum(
        (1 + 0.5 * (1.2 - m.dedendum_coeff)) * (1 - 0.02 * (20.0 - an_deg))
        for m in (pair.pinion, pair.gear)
    )
    cr = iso6336_pair_blank_factor(pair)
    c_single = cth * 0.8 * cr * cb * math.cos(pair.helix_angle) * youngs_modulus / E_STEEL_ISO
    if specific_load is not None and specific_load < LOW_LOAD_LIMIT:
        c_single *= (specific_load / LOW_LOAD_LIMIT) ** 0.25
    return c_single * 1e9  # N/(mm·µm) -> N/m²


def iso6336_mesh_stiffness(
    pair: GearPair,
    youngs_modulus: float = E_STEEL_ISO,
    specific_load: float | None = None,
) -> float:
    """ISO 6336-1 mesh stiffness c_γα = c' (0.75 ε_α + 0.25) (N/m per m of face width), §9.3;
    arguments as :func:`iso6336_single_stiffness`. (The standard's optional reduction of up to
    10 % for spur gears with ε_α < 1.2 is not applied.)"""
    c_single = iso6336_single_stiffness(pair, youngs_modulus, specific_load)
    return c_single * (0.75 * pair.transverse_contact_ratio + 0.25)


def _half_thickness_angle(pair: GearPair, member: int, r: np.ndarray) -> np.ndarray:
    """Half angular tooth thickness ψ(r) (rad) of the involute at radius r (transverse)."""
    rb = pair.base_radii[member]
    rp = pair.pitch_radii[member]
    st = pair.reference_thickness[member]
    ar = np.arccos(np.clip(rb / r, -1.0, 1.0))
    return st / (2 * rp) + involute(pair.transverse_pressure_angle) - involute(ar)


def _chordal_thickness(pair: GearPair, member: int, r: np.ndarray) -> np.ndarray:
    """Tooth thickness d(r) (m) across the tooth centre line at radius r (transverse).

    Twice the distance from the centre line to the flank point at radius r: the involute
    ``2 r sin ψ(r)`` above the form circle (continued beyond the tip), the rack-generated
    trochoidal fillet below it, down to the root circle (:meth:`ToothForm.half_thickness`, exact
    up to an O(200⁻²) interpolation); radii below the root circle get the root value.
    """
    form = _tooth_form(pair, member)
    r = np.asarray(r, dtype=float)
    r_inv = np.maximum(r, form.form_radius)
    half = r_inv * np.sin(_half_thickness_angle(pair, member, r_inv))
    below = np.clip(r, form.root_radius, form.form_radius)
    return 2 * np.where(r >= form.form_radius, half, form.half_thickness(below))


@functools.lru_cache(maxsize=8)
def _gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [-1, 1] (cached: NumPy's eigenvalue solve for 400
    points takes about 0.5 s)."""
    return np.polynomial.legendre.leggauss(n)


@functools.singledispatch
def member_compliance(
    pair: GearPair,
    member: int,
    rho: np.ndarray,
    E: float,
    nu: float,
    foundation: AbstractFoundation,
    n_quad: int = 400,
    *,
    ring_cutter=None,
) -> np.ndarray:
    """Bending + shear + compression (seed (1.2)) and foundation (seed (1.3)) compliance of one
    tooth of the pair (``member`` 0 pinion, 1 gear), Hertz not included (the pair's Weber
    profile :func:`weber_profile` adds it).

    Args:
        pair: the gear pair.
        member: 0 pinion, 1 gear.
        rho: roll distances (m) of the contact points on this member, shape (n,).
        E: Young's modulus (Pa); nu: Poisson's ratio.
        foundation: the gear-body term (:class:`WeberFoundation`, :class:`SainsotFoundation`,
            :class:`NoFoundation`, or a :class:`MemberFoundations`).
        n_quad: Gauss-Legendre points of the cantilever integrals.
        ring_cutter: the :class:`fem_prep.ShaperCutter` that generated the internal gear of an
            :class:`~jaxgear.InternalGearPair` (its ``member`` 1; required there, ignored for
            external teeth). The ring's tooth (``jaxgear/_weber_internal.py``): the cantilever
            from its root circle r_f inwards to where the line of action crosses its centre
            line, r_b/cos(α_r + ψ(r)) (ψ the internal tooth's half angle, ISO 21771), on the
            half thickness of :func:`fem_prep.generate_internal_tooth`; the same (1.2)
            integrals; the foundation's :meth:`AbstractFoundation.ring_compliance`.

    Returns:
        compliance per unit face width, (m/N)·m, shape (n,), along the transverse line of action.

    Raises:
        ValueError: (internal pairs) ``ring_cutter`` None, a cutter that cannot cut the ring,
            or a foundation without an internal form (:class:`SainsotFoundation`).
    """
    rb = pair.base_radii[member]
    rf = pair.root_radii[member]
    rc = np.hypot(rho, rb)
    alpha_r = np.arctan2(rho, rb)
    alpha_p = alpha_r - _half_thickness_angle(
        pair, member, rc
    )  # load angle to the centre-line normal
    r_load = rb / np.cos(alpha_p)  # where the line of action crosses the tooth centre line
    u = r_load - rf  # cantilever length from the root circle
    c = beam_compliance(u, lambda y: _chordal_thickness(pair, member, rf + y), alpha_p, E, nu,
                        n_quad)
    cos2, tan2 = np.cos(alpha_p) ** 2, np.tan(alpha_p) ** 2
    return foundation.add_compliance(c, pair, member, u, cos2 / E, tan2)


def beam_compliance(u, thickness, alpha_p, E, nu, n_quad: int = 400) -> np.ndarray:
    """Weber's cantilever, seed (1.2): bending, shear and compression of a tooth slice of unit
    width loaded at distance u from its root circle at angle α_p to the centre line's normal,
    ``cos²α_p/E [12 (1 − ν²) ∫ (u − y)²/d³ dy + (2.4 (1 + ν) + (1 − ν²) tan²α_p) ∫ dy/d]``
    over y ∈ [0, u] (Gauss–Legendre, ``n_quad`` points), d(y) = ``thickness(y)`` (m, the
    chordal thickness at distance y from the root circle along the centre line; any shape).
    Returns (m/N)·m, the shape of ``u``."""
    xg, wg = _gauss_legendre(n_quad)
    y = 0.5 * (xg[None, :] + 1.0) * u[:, None]
    w = 0.5 * wg[None, :] * u[:, None]
    d = thickness(y)
    i_bend = np.sum(w * (u[:, None] - y) ** 2 / d**3, axis=1)
    i_shear = np.sum(w / d, axis=1)
    cos2 = np.cos(alpha_p) ** 2
    tan2 = np.tan(alpha_p) ** 2
    # (1.2): 10.92 = 12(1-ν²) and 3.1(1 + 0.294 tan²) = 2.4(1+ν) + (1-ν²) tan² for ν = 0.3
    return cos2 / E * (12 * (1 - nu**2) * i_bend + (2.4 * (1 + nu) + (1 - nu**2) * tan2) * i_shear)


@functools.singledispatch
def weber_profile(
    pair: GearPair,
    s: np.ndarray,
    youngs_modulus: float,
    poisson_ratio: float,
    line_load: float,
    foundation: AbstractFoundation = WeberFoundation(),  # noqa: B008 (an immutable module)
    *,
    ring_cutter=None,
) -> np.ndarray:
    """Weber–Banaschek stiffness per unit contact-line length along the line of action.

    Args:
        pair: the gear pair.
        s: base-plane coordinates (m), shape (n,), in [0, g_α].
        youngs_modulus: E (Pa); poisson_ratio: ν.
        line_load: transverse load per unit face width (N/m) used in the Hertzian term (1.1);
            the Hertzian approach depends on it logarithmically.
        foundation: the foundation (gear-body) term of both members: :class:`WeberFoundation`
            (1.3), :class:`SainsotFoundation` (Sainsot et al. 2004, depends on
            ``Member.bore_radius``) or :class:`NoFoundation` (drop it when a condensed FE body
            supplies the body compliance, (2.31) remark), or a :class:`MemberFoundations` of
            one per member.
        ring_cutter: an :class:`~jaxgear.InternalGearPair`'s ring cutter
            (:func:`member_compliance`; ignored for external pairs). The internal pair's
            Hertzian term (1.1) takes the concave ring flank, ρ_eq = ρ1 ρ2/(ρ2 − ρ1), and the
            ring's distance d_2 = r sin ψ(r) from the contact point to its tooth centre line.

    Returns:
        k(s) (N/m per m of contact line), shape (n,), flank-normal.
    """
    s = np.asarray(s, dtype=float)
    rho1 = pair.roll_distance(s, 0)
    rho2 = pair.roll_distance(s, 1)
    E, nu = youngs_modulus, poisson_ratio
    c = member_compliance(pair, 0, rho1, E, nu, foundation.member(0)) + member_compliance(
        pair, 1, rho2, E, nu, foundation.member(1)
    )
    # Hertzian approach (1.1): d_i = distance from the contact point to the tooth centre line
    d_i = [
        np.hypot(rho, rb) * np.sin(_half_thickness_angle(pair, i, np.hypot(rho, rb)))
        for i, (rho, rb) in enumerate(((rho1, pair.base_radii[0]), (rho2, pair.base_radii[1])))
    ]
    rho_eq = rho1 * rho2 / (rho1 + rho2)
    k_transverse = 1.0 / (c + hertz_compliance(rho_eq, d_i[0], d_i[1], line_load, E, nu))
    return k_transverse / math.cos(pair.base_helix_angle)


def hertz_compliance(rho_eq, d1, d2, line_load, E, nu) -> np.ndarray:
    """Weber's Hertzian approach, seed (1.1): 4 (1 − ν²)/(π E) (ln(2 √(d1 d2)/a_H) −
    ν/(2 (1 − ν))), a_H = √(8 w ρ_eq (1 − ν²)/(π E)) the half width of the contact at line load
    w (N/m), ρ_eq (m) the equivalent radius, d1, d2 (m) the contact point's distances to the
    two teeth's centre lines. Returns (m/N)·m."""
    a_h = np.sqrt(8 * line_load * rho_eq * (1 - nu**2) / (math.pi * E))
    return (
        4
        * (1 - nu**2)
        / (math.pi * E)
        * (np.log(2 * np.sqrt(d1 * d2) / a_h) - nu / (2 * (1 - nu)))
    )


def tooth_mass(pair: GearPair, member: int, density: float, width: float) -> tuple[float, float]:
    """Mass (kg) and centroid radius (m) of one tooth of ``member`` (0 pinion, 1 gear) above the
    root circle, over the face width ``width`` (m) at density ``density`` (kg/m³): the chordal
    thickness of the tooth form integrated from r_f to r_a (64-point Gauss–Legendre). It is the
    part of the gear that a condensed FE body meshed up to the root circle does not have."""
    rf, ra = pair.root_radii[member], pair.tip_radii[member]
    x, w = np.polynomial.legendre.leggauss(64)
    r = rf + 0.5 * (x + 1) * (ra - rf)
    w = 0.5 * w * (ra - rf)
    d = _chordal_thickness(pair, member, r)
    area = float(np.sum(w * d))
    return density * area * width, float(np.sum(w * d * r)) / area
