"""The load-capacity rating of an internal pair (an external pinion, e.g. a planet, in an
internal gear, a ring): ISO 6336-2:2006/2019 and ISO 6336-3:2006/2019 method B with the
standard's internal-gear rules, as a geometry object the rating functions of
:func:`jaxgear.rate` ask the same questions as :class:`jaxgear.RatingGeometry`.

Sign conventions (ISO 21771, ISO 6336): the internal gear's tooth count z2 < 0, and in the
derived geometry its reference, base, tip and root diameters are negative too, so that the
external formulas hold unchanged where the standard writes them with signs: the gear ratio
u = z2/z1 < 0 (σ_H0 ∝ √((u + 1)/u)), the radius of curvature ρ2 = d_b2/2 tan α_wt < 0 (the
concave flank: ρ_red = ρ1 ρ2/(ρ1 + ρ2) = ρ1 |ρ2|/(|ρ2| − ρ1), the relative curvature
1/ρ1 − 1/|ρ2|, of Z_R and of the Hertzian pressure), the tip and root diameters d_a2 = d2 +
2 m_n (h_a* + x2), d_f2 = d2 − 2 m_n (h_f* − x2) (positive x2 thickens the ring's teeth). The
centre distance is positive. Z_H = √(2 cos β_b cos α_wt/(cos² α_t sin α_wt)) as for external
pairs, with the internal pair's α_wt (inv α_wt = inv α_t + 2 tan α_n (x1 + x2)/(z1 + z2)).

Internal-gear rules:

* ε_α = (√(r_a1² − r_b1²) − √(r_a2² − r_b2²) + a_w sin α_wt)/p_bt (ISO 21771, magnitudes).
* Z_B of the pinion from M₁ = √(ρ_C1 ρ_C2/(ρ_B1 ρ_B2)) at its inner point of single contact B
  (one base pitch below its tip), the same relative-curvature ratio as the external M₁, here
  with ρ2 = ρ1 + a_w sin α_wt; Z_D = 1 for the internal gear (ISO 6336-2, single pair tooth
  contact factors: "for internal gears Z_D = 1").
* The pinion's Y_F, Y_S: the external method B (:func:`jaxgear.member_form`) with the internal
  pair's ε_α (the load at the pinion's outer point of single contact of this mesh).
* The internal gear's Y_F, Y_S (ISO 6336-3, method B, internal gears): the critical section
  where the fillet's tangent makes 60° with the tooth centre line (30° for external teeth); its
  chord s_Fn, fillet radius ρ_F and diameter d_sFn come from a root-section object
  (:class:`SubstituteRack`: ISO's substitute rack; :class:`GivenRootSection`: from a tooth
  form program, e.g. a pinion-type cutter simulation); the load at the internal gear's outer
  point of single contact (nearest its tip), d_en2 = 2 √((√(d_an2²/4 − d_bn2²/4) + π m_n
  cos α_n (ε_αn − 1))² + d_bn2²/4) in magnitudes, α_Fen = α_en − γ_e with γ_e = (π/2 + 2 x2
  tan α_n)/z_n2 + inv α_n − inv α_en (z_n2 < 0), and the bending moment arm h_Fe = √(r_s² −
  s_Fn²/4) − (d_en/2)(cos γ_e − sin γ_e tan α_Fen) from the chord at r_s = d_sFn/2 to where the
  load's line crosses the centre line (the geometry the external h_Fe formula writes, for a
  tooth whose root lies outside its tip). These reproduce the KISSsoft reports' printed h_F and
  α_Fen of the NREL 5 MW ring gears from their s_Fn, ρ_F and d_sFn within their rounding.
* Y_B of the ring's rim as for external gears, s_R (the rim below the root circle, outside it
  for a ring) over the tooth height h_t.
* ISO 6336-1 method B: the ring's virtual tooth count in c' taken as infinite, and the ring
  infinitely heavy in the reduced mass of K_v (m_red = m*₁: a ring is fixed to, or part of,
  the housing; the standard's pair formula with a ring blank would count a rim of the ring's
  pitch diameter as solid).

Sources: ISO 6336-1, -2, -3 (2006 and 2019; the clauses named above), ISO 21771:2007; the
KISSsoft reports of the NREL 5 MW planetary stages (docs/rating.md, "Internal meshes and
planetary stages").
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from ._internal import InternalGearPair
from ._rating_bending import ToothFormFactors, member_form, section_factors
from ._rating_geometry import Derived, inverse_involute_jnp, pair_fields, replace_fields
from ._util import as_float, check_instance, check_real

__all__ = [
    "AbstractRootSection",
    "GivenRootSection",
    "InternalRatingGeometry",
    "SubstituteRack",
]


def _inv(a):
    return jnp.tan(a) - a


class AbstractRootSection(eqx.Module):
    """How the internal gear's critical root section (ISO 6336-3, 60° tangent) is found: a
    method object of :class:`InternalRatingGeometry`."""

    @abc.abstractmethod
    def section(self, geometry: InternalRatingGeometry, g: Derived) -> tuple:
        """(s_Fn, ρ_F, d_sFn) of the internal gear (m, magnitudes): the chord at the 60°
        tangent points, the fillet's radius of curvature there and the diameter of the chord's
        ends."""


class SubstituteRack(AbstractRootSection):
    """ISO 6336-3 method B's substitute rack for an internal gear: its tooth is taken as the
    basic rack's (h_fP, ρ_fP, α_n; z → ∞), whose fillet is the rack's tip rounding itself. At
    the point where the fillet's tangent makes 60° with the centre line (30° with the root
    line): s_Fn = 2 m_n (π/4 + (h_fP − ρ_fP)/m_n tan α_n + ρ_fP/(m_n cos α_n) − ρ_fP/(2 m_n)),
    ρ_F = ρ_fP, and the chord ρ_fP (1 − cos 30°) inside the root circle (the profile shift
    moves the tooth and the root alike and drops out). The concave internal tooth widens toward
    its root faster than a rack's: against the KISSsoft reports' pinion-type cutter sections of
    the NREL 5 MW rings (z2 = −93 and −56) this chord is 3.8 % and 9.6 % thinner and ρ_F 28 %
    and 39 % smaller, so Y_F (+9 %, +23 %) and Y_S (+10 %, +11 %) come out higher: σ_F0 of the
    rings 20 % and 37 % over the report's (conservative); give the section from a tooth form
    program with :class:`GivenRootSection` to rate like the report."""

    def section(self, geometry, g):
        mn, an = geometry.normal_module, geometry.normal_pressure_angle
        hfp = geometry.dedendum_coeff[1] * mn
        rfp = geometry.fillet_radius_coeff[1] * mn
        s_fn = 2 * (jnp.pi / 4 * mn + (hfp - rfp) * jnp.tan(an) + rfp / jnp.cos(an) - rfp / 2)
        d_s = jnp.abs(g.root_diameter[1]) - 2 * rfp * (1 - jnp.cos(jnp.pi / 6))
        return s_fn, rfp, d_s


class GivenRootSection(AbstractRootSection):
    """The internal gear's root section given (m): ``s_Fn`` the chord at the 60° tangent
    points, ``rho_F`` the fillet radius there, ``d_sFn`` the diameter of the chord's ends, e.g.
    from a tooth form program's pinion-type cutter simulation (KISSsoft prints them as s_Fn,
    ρ_F and dsFn)."""

    s_Fn: Float[Array, ""]
    rho_F: Float[Array, ""]
    d_sFn: Float[Array, ""]

    def __init__(self, s_Fn, rho_F, d_sFn):
        w = "GivenRootSection"
        for name, v in (("s_Fn", s_Fn), ("rho_F", rho_F), ("d_sFn", d_sFn)):
            check_real(name, v, "m", lo=0.0, lo_open=True, where=w)
        self.s_Fn, self.rho_F, self.d_sFn = as_float(s_Fn), as_float(rho_F), as_float(d_sFn)

    def section(self, geometry, g):
        return self.s_Fn, self.rho_F, self.d_sFn


class InternalRatingGeometry(eqx.Module):
    """The continuous macro parameters of an internal pair, as arrays (differentiable): member 0
    the external pinion (planet), member 1 the internal gear (ring).

    Attributes:
        teeth: (z1, z2), z2 < 0 (ISO 21771), static.
        normal_module: m_n (m); the other macro parameters (normal_pressure_angle,
            helix_angle, profile_shift (x1, x2; x2 in ISO 21771's sign), addendum_coeff,
            dedendum_coeff, fillet_radius_coeff, face_width, rim_thickness, center_distance)
            as :class:`jaxgear.RatingGeometry`.
        root_section: the internal gear's root section (:class:`AbstractRootSection`; default
            :class:`SubstituteRack`).

    Build it from a :class:`jaxgear.InternalGearPair` with :meth:`of`; :func:`jaxgear.rate`
    rates it (module docstring for the internal-gear rules).
    """

    teeth: tuple[int, int] = eqx.field(static=True)
    normal_module: Float[Array, ""]
    normal_pressure_angle: Float[Array, ""]
    helix_angle: Float[Array, ""]
    profile_shift: Float[Array, 2]
    addendum_coeff: Float[Array, 2]
    dedendum_coeff: Float[Array, 2]
    fillet_radius_coeff: Float[Array, 2]
    face_width: Float[Array, 2]
    rim_thickness: tuple = eqx.field(static=True)
    center_distance: Float[Array, ""] | None
    root_section: AbstractRootSection

    @classmethod
    def of(
        cls, pair: InternalGearPair, root_section: AbstractRootSection | None = None
    ) -> InternalRatingGeometry:
        """The parameters of ``pair`` (its centre distance kept only when it differs from the
        zero-backlash distance); ``root_section`` default :class:`SubstituteRack`."""
        w = "InternalRatingGeometry.of"
        check_instance("pair", pair, InternalGearPair, "a jaxgear.InternalGearPair", w)
        root_section = SubstituteRack() if root_section is None else root_section
        check_instance(
            "root_section", root_section, AbstractRootSection, "a jaxgear root section", w
        )
        return cls(**pair_fields(pair), root_section=root_section)

    def replace(self, **changes) -> InternalRatingGeometry:
        """A copy with some array fields replaced (as :meth:`jaxgear.RatingGeometry.replace`)."""
        return replace_fields(self, changes)

    def derived(self) -> Derived:
        """ISO 21771 geometry of the internal pair (jnp; the ring's diameters negative, the
        centre distance positive; module docstring)."""
        z = jnp.asarray(self.teeth, dtype=self.normal_module.dtype)
        mn, an, beta = self.normal_module, self.normal_pressure_angle, self.helix_angle
        x = self.profile_shift
        mt = mn / jnp.cos(beta)
        at = jnp.arctan(jnp.tan(an) / jnp.cos(beta))
        d = z * mt
        db = d * jnp.cos(at)
        da = d + 2 * mn * (self.addendum_coeff + x)
        df = d - 2 * mn * (self.dedendum_coeff - x)
        if self.center_distance is None:
            inv_awt = _inv(at) + 2 * jnp.tan(an) * (x[0] + x[1]) / (z[0] + z[1])
            awt = inverse_involute_jnp(inv_awt)
            a = -(d[0] + d[1]) / 2 * jnp.cos(at) / jnp.cos(awt)
        else:
            a = self.center_distance
            awt = jnp.arccos(-(db[0] + db[1]) / (2 * a))
        roll_tip = jnp.sqrt(da**2 / 4 - db**2 / 4)
        g_alpha = roll_tip[0] - roll_tip[1] + a * jnp.sin(awt)
        eps_a = g_alpha / (jnp.pi * mt * jnp.cos(at))
        b = jnp.minimum(self.face_width[0], self.face_width[1])
        return Derived(
            transverse_module=mt,
            transverse_pressure_angle=at,
            operating_pressure_angle=awt,
            base_helix_angle=jnp.arctan(jnp.tan(beta) * jnp.cos(at)),
            center_distance=a,
            reference_diameter=d,
            base_diameter=db,
            tip_diameter=da,
            root_diameter=df,
            transverse_contact_ratio=eps_a,
            overlap_ratio=b * jnp.sin(beta) / (jnp.pi * mn),
            face_width=b,
            gear_ratio=self.teeth[1] / self.teeth[0],
        )

    # -- what the rating asks of a pair (as jaxgear.RatingGeometry) --------------------------

    def single_pair_factors(self, g: Derived) -> Array:
        """(Z_B, Z_D): Z_B of the pinion from M₁ at its inner point of single contact (spur
        max(1, M₁), helical as external pairs), Z_D = 1 (module docstring)."""
        rb1 = g.base_diameter[0] / 2
        t1t2 = g.center_distance * jnp.sin(g.operating_pressure_angle)
        pbt = jnp.pi * g.transverse_module * jnp.cos(g.transverse_pressure_angle)
        rho_c1 = rb1 * jnp.tan(g.operating_pressure_angle)
        rho_b1 = jnp.sqrt(g.tip_diameter[0] ** 2 / 4 - rb1**2) - pbt
        m1 = jnp.sqrt(rho_c1 * (rho_c1 + t1t2) / (rho_b1 * (rho_b1 + t1t2)))
        eb = jnp.minimum(g.overlap_ratio, 1.0)
        z_b = jnp.maximum(1.0, m1 - eb * (m1 - 1))
        return jnp.stack([z_b, jnp.ones_like(z_b)])

    def form_factors(self) -> ToothFormFactors:
        """Y_F, Y_S and the root sections of the pinion and the internal gear (module
        docstring). The internal gear's ``theta`` is its tangent angle π/3 (60°)."""
        g = self.derived()
        mn, an, beta = self.normal_module, self.normal_pressure_angle, self.helix_angle
        z1 = jnp.asarray(self.teeth[0], dtype=mn.dtype)
        ea = g.transverse_contact_ratio
        p = member_form(
            mn, an, beta, g.base_helix_angle, z1, self.profile_shift[0],
            (self.dedendum_coeff[0] * mn, self.fillet_radius_coeff[0] * mn),
            (g.reference_diameter[0], g.tip_diameter[0]), ea,
        )
        # the internal gear (member 1) on its virtual gear (z_n2 < 0), magnitudes where named
        cb = jnp.cos(g.base_helix_angle)
        zn2 = self.teeth[1] / (cb**2 * jnp.cos(beta))
        dn = jnp.abs(mn * zn2)
        dbn = dn * jnp.cos(an)
        dan = dn - (jnp.abs(g.reference_diameter[1]) - jnp.abs(g.tip_diameter[1]))
        eps_an = ea / cb**2
        reach = jnp.sqrt(dan**2 / 4 - dbn**2 / 4) + jnp.pi * mn * jnp.cos(an) * (eps_an - 1)
        den = 2 * jnp.sqrt(reach**2 + dbn**2 / 4)
        aen = jnp.arccos(dbn / den)
        x2 = self.profile_shift[1]
        gamma_e = (jnp.pi / 2 + 2 * x2 * jnp.tan(an)) / zn2 + _inv(an) - _inv(aen)
        afen = aen - gamma_e
        s_fn, rho_f, d_s = self.root_section.section(self, g)
        r_s = (dn + d_s - jnp.abs(g.reference_diameter[1])) / 2  # the chord on the virtual gear
        r_load = den / 2 * (jnp.cos(gamma_e) - jnp.sin(gamma_e) * jnp.tan(afen))
        h_fe = jnp.sqrt(r_s**2 - s_fn**2 / 4) - r_load
        y_f, y_s, q_s = section_factors(mn, an, s_fn, h_fe, rho_f, afen)

        def both(a, b):
            return jnp.stack([jnp.asarray(a, dtype=mn.dtype), jnp.asarray(b, dtype=mn.dtype)])

        return ToothFormFactors(
            Y_F=both(p.Y_F, y_f),
            Y_S=both(p.Y_S, y_s),
            s_Fn=both(p.s_Fn, s_fn),
            rho_F=both(p.rho_F, rho_f),
            h_Fe=both(p.h_Fe, h_fe),
            alpha_Fen=both(p.alpha_Fen, afen),
            theta=both(p.theta, jnp.pi / 3),
            q_s=both(p.q_s, q_s),
            virtual_teeth=both(p.virtual_teeth, zn2),
            eps_alpha_n=p.eps_alpha_n,
        )

    def stiffness_teeth(self, g: Derived) -> Array:
        """(z_n1, ∞): the internal gear's virtual teeth taken as infinite in c' (ISO 6336-1
        method B for internal gears; as :class:`jaxgear.ISO6336` for internal pairs)."""
        zn1 = self.teeth[0] / (jnp.cos(g.base_helix_angle) ** 2 * jnp.cos(self.helix_angle))
        return jnp.stack([zn1, jnp.full_like(zn1, jnp.inf)])

    def reduced_mass(self, m_star: Array) -> Array:
        """m*₁: the internal gear infinitely heavy (module docstring)."""
        return m_star[0]
