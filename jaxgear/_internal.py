"""Internal involute gear pairs (ISO 21771): an external pinion (a planet) inside an internal
gear (a ring), their geometry and the checks particular to internal pairs, computed once in
NumPy/Python floats like :class:`~jaxgear.GearPair` (docs/planetary.md, "Internal gears").

Representation: the internal gear is a :class:`~jaxgear.Member` whose tooth count is negative,
as ISO 21771 writes it (z2 < 0), in its own pair class :class:`InternalGearPair`. The external
:class:`~jaxgear.GearPair` keeps refusing z < 5, so an internal gear never enters an external
pair's formulas by mistake, and no external result changes. Diameters, radii and the centre
distance are positive (ISO 21771's convention; DIN 3960 wrote them negative). The profile shift
x2 of the ring follows ISO 21771 too: positive x2 adds material to the ring's teeth (its tip
circle moves inwards, |d_a2| = |d2| − 2 m_n (h_a* + x2)), the opposite sign of the textbook
convention x2' = −x2 of e.g. the KHK tables (inv α_w = inv α + 2 tan α (x2' − x1)/(z2' − z1),
z2' = |z2|).

The pair exposes the attributes the base-plane layout (:meth:`jaxgear.MeshModel.from_pair`),
the mesh-stiffness tables (:class:`~jaxgear.Uniform`, :class:`~jaxgear.ISO6336`) and the
Hertzian pressure (:func:`~jaxgear.contact_pressure`: the concave ring flank) read, so that
:func:`~jaxgear.quasi_static` computes the TE and the loads of an internal mesh with the
external machinery unchanged: on the line of action both gears turn the same sense, the
contact runs from the ring's tip (s = 0, the pinion's start of active profile) to the pinion's
tip (s = g_α).

Sources: ISO 21771:2007 (geometry, negative z of internal gears, working pressure angle, path
of contact, form circle); KHK Kohara Gear Industry, *Gear Technical Reference*, §4 "Internal
gears" (the involute, trochoid and radial-assembly interference conditions and the worked
example z = 16/24, m = 3, x2' = 0.516); ISO 6336-2 (Z_H with u < 0 for internal pairs).
"""

from __future__ import annotations

import dataclasses
import math

import jax.numpy as jnp

from ._geometry import (
    _REAL_FIELDS,
    _UNITS,
    GearPair,
    Member,
    check_member_ranges,
    inverse_involute,
    involute,
)
from ._pressure import relative_radius
from ._stiffness import iso6336_virtual_teeth, member_tooth_geometry
from ._util import check_instance, check_integer, check_real

__all__ = [
    "InternalGearPair",
    "PlanetaryGeometry",
    "internal_tooth_geometry",
    "planetary_geometry",
]


def _require(name: str, value, ok: bool, allowed: str) -> None:
    if not ok:
        raise ValueError(f"InternalGearPair: {name} = {value!r} is out of range: allowed {allowed}")


def trochoid_margin(z1: int, z2: int, ra1, ra2, rb1, rb2, a, alpha_w) -> float:
    """The trochoid-interference margin (rad of ring rotation) of an internal pair, KHK's
    condition θ1 z1/|z2| + inv α_w − inv α_a2 − θ2' >= 0 written as θ1 z1/|z2| − θ2 with

        θ1 = acos((r_a2² − r_a1² − a²)/(2 a r_a1)) + inv α_a1 − inv α_w,
        θ2 = acos((r_a2² − r_a1² + a²)/(2 a r_a2)) + inv α_a2 − inv α_w,

    α_ai = acos(r_bi/r_ai): while the pinion's tip corner leaves the mesh (recess) along its
    trochoid relative to the ring, it must not reach the ring's tip corner. Negative: the tips
    collide (small tooth-count differences). All radii positive (m), ``z2`` < 0.
    Requires intersecting tip circles (a + r_a1 > r_a2 > a − r_a1)."""
    inv_w = involute(alpha_w)
    c1 = (ra2**2 - ra1**2 - a**2) / (2 * a * ra1)
    c2 = (ra2**2 - ra1**2 + a**2) / (2 * a * ra2)
    theta1 = math.acos(c1) + involute(math.acos(rb1 / ra1)) - inv_w
    theta2 = math.acos(c2) + involute(math.acos(rb2 / ra2)) - inv_w
    return theta1 * z1 / abs(z2) - theta2


def radial_assembly_margin(z1: int, z2: int, ra1, ra2, rb1, rb2, alpha_w) -> float:
    """The radial-assembly (trimming) margin (rad) of an internal pair, KHK's and SDP/SI's
    condition θ1 + inv α_a1 − inv α_w >= (|z2|/z1)(θ2 + inv α_a2 − inv α_w) written as
    left − right, with

        θ1 = asin √((1 − (cos α_a1/cos α_a2)²)/(1 − (z1/|z2|)²)),
        θ2 = asin √(((cos α_a2/cos α_a1)² − 1)/((|z2|/z1)² − 1)),

    α_ai = acos(r_bi/r_ai), α_w the operating pressure angle: >= 0 when the pinion can be moved
    into (or out of) mesh along the line of centres; negative when its tips would cut the
    ring's (trimming: the pair must be assembled axially, as planets usually are, and a pinion
    cutter cannot be withdrawn radially). All radii positive (m), ``z2`` < 0; -inf where the
    square roots leave [0, 1] (tip circles that do not allow the construction).
    Source: SDP/SI, *Elements of Metric Gear Technology* (D785), eqs. (5-9), (5-10) and
    Table 5-3a; KHK *Gear Technical Reference*, §4 "Internal gears"."""
    inv_w = involute(alpha_w)
    aa1, aa2 = math.acos(rb1 / ra1), math.acos(rb2 / ra2)
    k = z1 / abs(z2)
    s1 = (1 - (math.cos(aa1) / math.cos(aa2)) ** 2) / (1 - k**2)
    s2 = ((math.cos(aa2) / math.cos(aa1)) ** 2 - 1) / (1 / k**2 - 1)
    if not (0.0 <= s1 <= 1.0 and 0.0 <= s2 <= 1.0):
        return -math.inf
    theta1 = math.asin(math.sqrt(s1)) + involute(aa1) - inv_w
    theta2 = math.asin(math.sqrt(s2)) + involute(aa2) - inv_w
    return theta1 - theta2 / k


@dataclasses.dataclass(frozen=True)
class InternalGearPair:
    """Internal involute spur or helical gear pair (ISO 21771): an external pinion meshing
    inside an internal gear; the pinion (member 1) drives; both turn the same sense.

    Construct with the input data; every derived quantity is a read-only attribute computed in
    ``__post_init__`` (SI units, angles in rad, radii and centre distance positive). Every check
    raises one ``ValueError`` line naming the parameter, its value and the allowed range, before
    anything is computed downstream.

    Args:
        pinion: the external member (teeth z1 >= 5; a planet).
        gear: the internal gear (a ring): a :class:`~jaxgear.Member` with ``teeth`` z2 < 0 (ISO
            21771), |z2| > z1; its ``profile_shift`` x2 in ISO 21771's sign (positive thickens
            the ring's teeth, moving its tip circle inwards); ``bore_radius`` None (a ring has no bore); ``tooth_thickness_allowance`` A_sn
            (m, negative thins the ring's teeth) as for :class:`~jaxgear.GearPair`.
        normal_module: m_n (m). normal_pressure_angle: α_n (rad). helix_angle: β (rad), >= 0
            (both members of the same hand).
        center_distance: a_w (m), in (r_b2 − r_b1, ``backlash_center_distance``]: an internal
            pair has backlash *closer* than its zero-backlash distance and jams farther apart;
            ``None`` for the zero-backlash distance of the nominal teeth.

    Derived attributes: ``transverse_module`` m_t, ``transverse_pressure_angle`` α_t,
    ``operating_pressure_angle`` α_wt (inv α_wt = inv α_t + 2 tan α_n (x1 + x2)/(z1 + z2),
    z1 + z2 < 0), ``center_distance`` a_w = m_t (|z2| − z1)/2 · cos α_t/cos α_wt,
    ``zero_backlash_center_distance``, ``pitch_radii`` (r1, |r2|), ``base_radii``,
    ``tip_radii`` (r_a1 = r1 + m_n (h_a1* + x1); r_a2 = |r2| − m_n (h_a2* + x2), inside),
    ``root_radii`` (r_f1 = r1 − m_n (h_f1* − x1); r_f2 = |r2| + m_n (h_f2* − x2), outside),
    ``reference_thickness`` (s_t = m_t (π/2 + 2 x tan α_n), each member's tooth),
    ``tip_thickness``, ``pinion_form_roll`` (the pinion's form circle, roll distance from T1),
    ``line_length`` T1T2 = a_w sin α_wt (both tangent points on the same side of the pitch
    point), ``start_roll`` (the pinion's start of active profile, at the ring's tip:
    √(r_a2² − r_b2²) − T1T2), ``path_of_contact`` g_α = √(r_a1² − r_b1²) − √(r_a2² − r_b2²)
    + a_w sin α_wt, ``base_pitch`` p_bt, ``base_helix_angle`` β_b,
    ``transverse_contact_ratio`` ε_α = g_α/p_bt, ``overlap_ratio`` ε_β, ``face_width`` b,
    ``tip_root_clearances`` (c1 = r_f2 − a_w − r_a1: pinion tip to ring root; c2 = r_a2 −
    a_w − r_f1: ring tip to pinion root), ``trochoid_margin`` (:func:`trochoid_margin`, rad),
    ``radial_assembly_margin`` (:func:`radial_assembly_margin`, rad: reported, not refused;
    negative: the pinion goes in axially),
    ``mesh_period_angle`` 2π/z1; the backlash (ISO 21771 / DIN 3967 quantities, as
    :class:`~jaxgear.GearPair`'s): ``backlash_center_distance`` a_A, the zero-backlash distance
    of the thinned teeth (inv α_wtA = inv α_wt0 + (A_sn1 + A_sn2)/(m_n (z1 + z2))),
    ``transverse_backlash`` j_bt = 2 (r_b2 − r_b1)(inv α_wtA − inv α_wt) (the ring's space less
    the pinion's tooth along the line of action; 0 at a_A, > 0 for a_w < a_A), ``circumferential_backlash`` j_wt =
    j_bt/cos α_wt, ``normal_backlash`` j_bn = j_bt cos β_b; ``base_thickness`` (s_b1, s_b2),
    the members' tooth thicknesses on their base circles (the ring's: 2 r_b2 (s_t2/(2 r2) −
    inv α_t)). With ``coast=True`` :meth:`jaxgear.MeshModel.from_pair` lays out the coast
    flanks with this backlash.

    Checks (docs/planetary.md, "Internal gears"): sizes and coefficients as
    :class:`~jaxgear.GearPair`; |z2| > z1; inv α_wt > 0; a_w <= the zero-backlash distance;
    the pinion's root radius > 0 and tip radius > its base radius; the ring's tip circle
    outside its base circle (r_a2 > r_b2: the involute exists only outside the base circle);
    no pointed tips; no undercut of the pinion (form circle, ISO 21771); **involute
    interference**: the ring's tip meets the pinion on its involute above the form circle
    (start_roll >= pinion_form_roll; with a zero form roll this is KHK's z1/|z2| >= 1 − tan
    α_a2/tan α_wt); **tip-to-root clearance** c1, c2 >= 0; ε_α >= 1; **trochoid
    interference**: margin >= 0 (KHK), the condition that sets the minimum tooth-count
    difference (20° teeth, z1 = 20, unshifted, ring addendum 0.6 m_n: |z2| − z1 >= 7).

    Raises:
        ValueError: any check above, one line naming the parameter (``pinion.<field>``,
            ``gear.<field>`` or the pair's), its value and the allowed range.

    Example:
        >>> planet = Member(20, profile_shift=0.3, face_width=0.02)
        >>> ring = Member(-90, face_width=0.02)           # ISO 21771: internal teeth negative
        >>> pair = InternalGearPair(planet, ring, 3e-3, math.radians(20.0))
        >>> round(pair.transverse_contact_ratio, 4)
        1.7426
    """

    pinion: Member
    gear: Member
    normal_module: float
    normal_pressure_angle: float
    helix_angle: float = 0.0
    center_distance: float | None = None

    def __post_init__(self) -> None:
        where = "InternalGearPair"
        for tag in ("pinion", "gear"):
            check_instance(tag, getattr(self, tag), Member, "a jaxgear.Member", where)
            m = getattr(self, tag)
            for name in _REAL_FIELDS:
                v = getattr(m, name)
                if v is not None:
                    check_real(f"{tag}.{name}", v, _UNITS.get(name, ""), shape=(), where=where)
        check_integer("InternalGearPair: pinion.teeth", self.pinion.teeth, 5)
        z1, z2 = self.pinion.teeth, self.gear.teeth
        _require(
            "gear.teeth",
            z2,
            not isinstance(z2, bool) and int(z2) == z2 and z2 < -z1,
            f"an integer < {-z1} (an internal gear's tooth count is negative, ISO 21771, and "
            "larger in magnitude than the pinion's)",
        )
        for name in ("normal_module", "normal_pressure_angle", "helix_angle", "center_distance"):
            if getattr(self, name) is not None:
                check_real(name, getattr(self, name), _UNITS[name], shape=(), where=where)
        mn, an, beta = self.normal_module, self.normal_pressure_angle, self.helix_angle
        _require("normal_module", mn, mn > 0, "> 0")
        _require("normal_pressure_angle", an, 0 < an < math.radians(45), "(0, 45) deg")
        _require("helix_angle", beta, 0 <= beta < math.radians(45), "[0, 45) deg")
        members = (self.pinion, self.gear)
        for tag, m in zip(("pinion", "gear"), members):
            check_member_ranges(tag, m, mn, _require)
        _require(
            "gear.bore_radius",
            self.gear.bore_radius,
            self.gear.bore_radius is None,
            "None (an internal gear has no bore; its rim is given by rim_thickness)",
        )
        bore = self.pinion.bore_radius
        x1, x2 = self.pinion.profile_shift, self.gear.profile_shift
        mt = mn / math.cos(beta)
        at = math.atan(math.tan(an) / math.cos(beta))
        r = (z1 * mt / 2.0, -z2 * mt / 2.0)
        rb = (r[0] * math.cos(at), r[1] * math.cos(at))
        # ISO 21771 with z2 < 0: inv α_wt = inv α_t + 2 tan α_n (x1 + x2)/(z1 + z2)
        inv_awt0 = involute(at) + 2.0 * math.tan(an) * (x1 + x2) / (z1 + z2)
        _require(
            "profile_shift (x1 + x2)",
            x1 + x2,
            inv_awt0 > 0,
            f"< {-(z1 + z2) * involute(at) / (2 * math.tan(an)):.4f} (inv α_wt > 0)",
        )
        awt0 = inverse_involute(inv_awt0)
        a0 = (rb[1] - rb[0]) / math.cos(awt0)
        # zero backlash with the thinned teeth: 2 x tan α_n + A_sn/m_n per member (ISO 21771,
        # DIN 3967), inv α_wtA = inv α_wt0 + (A_sn1 + A_sn2)/(m_n (z1 + z2)), z1 + z2 < 0
        allowances = self.pinion.tooth_thickness_allowance + self.gear.tooth_thickness_allowance
        inv_awtA = inv_awt0 + allowances / mn / (z1 + z2)
        _require(
            "tooth_thickness_allowance (pinion + gear)",
            allowances,
            inv_awtA > 0,
            f"< {inv_awt0 * -(z1 + z2) * mn:.6g} m (inv α_wt > 0)",
        )
        aA = (rb[1] - rb[0]) / math.cos(inverse_involute(inv_awtA))
        if self.center_distance is None:
            a, awt = a0, awt0
            _require(
                "tooth_thickness_allowance (pinion + gear) without a center_distance",
                allowances,
                aA >= a0 * (1 - 1e-9),
                f"<= 0 m (the teeth jam at the zero-backlash distance {a0 * 1e3:.6f} mm of the "
                f"nominal teeth); or give center_distance <= {aA * 1e3:.6f} mm",
            )
        else:
            # an internal pair jams farther apart: the pinion's tooth enters the ring's space
            # deeper, where the space narrows (the ring's teeth thicken towards their roots)
            a = float(self.center_distance)
            _require(
                "center_distance",
                a,
                rb[1] - rb[0] < a <= aA * (1 + 1e-9),
                f"({(rb[1] - rb[0]) * 1e3:.6f}, {aA * 1e3:.6f}] mm (up to the zero-backlash "
                "distance of the thinned teeth; farther apart, the teeth of an internal pair jam)",
            )
            awt = math.acos((rb[1] - rb[0]) / a)
        ra = (
            r[0] + mn * (self.pinion.addendum_coeff + x1),
            r[1] - mn * (self.gear.addendum_coeff + x2),
        )
        rf = (
            r[0] - mn * (self.pinion.dedendum_coeff - x1),
            r[1] + mn * (self.gear.dedendum_coeff - x2),
        )
        _require(
            "pinion.root radius (from dedendum_coeff and profile_shift)", rf[0], rf[0] > 0, "> 0"
        )
        _require(
            "pinion.tip radius (from addendum_coeff and profile_shift)",
            ra[0],
            ra[0] > rb[0],
            f"> base radius {rb[0] * 1e3:.4f} mm",
        )
        _require(
            "gear.tip radius (from addendum_coeff and profile_shift: the ring's tip circle must "
            "stay outside its base circle)",
            ra[1],
            ra[1] > rb[1],
            f"> base radius {rb[1] * 1e3:.4f} mm (lower gear.addendum_coeff or gear.profile_shift)",
        )
        if bore is not None:
            _require(
                "pinion.bore_radius",
                bore,
                0 < bore < rf[0],
                f"(0, {rf[0]:.6g}) m (below the root radius)",
            )
        # tooth thicknesses (ISO 21771: s_t = m_t (π/2 + 2 x tan α_n) for both, z2 < 0); the
        # ring's tooth is thinnest at its tip (inside): half angle s_t2/(2 r2) − inv α_t + inv α
        st = tuple(mt * (math.pi / 2 + 2 * m.profile_shift * math.tan(an)) for m in members)
        aa = tuple(math.acos(rb[i] / ra[i]) for i in (0, 1))
        sa1 = 2 * ra[0] * (st[0] / (2 * r[0]) + involute(at) - involute(aa[0]))
        sa2 = 2 * ra[1] * (st[1] / (2 * r[1]) - involute(at) + involute(aa[1]))
        for tag, sa, m in (("pinion", sa1, self.pinion), ("gear", sa2, self.gear)):
            _require(
                f"{tag}.addendum_coeff (tip thickness {sa * 1e3:.4f} mm: pointed tooth)",
                m.addendum_coeff,
                sa > 0,
                "a tip tooth thickness > 0",
            )
        # the pinion's form circle (rack generation, ISO 21771 (88)-(90)), as GearPair's
        p = self.pinion
        h = mn * (p.dedendum_coeff - x1 - p.fillet_radius_coeff * (1 - math.sin(an)))
        rho_f = r[0] * math.sin(at) - h / math.sin(at)
        _require(
            f"pinion.profile_shift (undercut: form circle roll {rho_f * 1e3:.4f} mm)",
            x1,
            rho_f >= 0,
            "large enough that the involute starts above the base circle (no undercut)",
        )
        line = a * math.sin(awt)  # T1T2: both tangent points on the same side of the pitch point
        roll_tip = (math.sqrt(ra[0] ** 2 - rb[0] ** 2), math.sqrt(ra[1] ** 2 - rb[1] ** 2))
        start = roll_tip[1] - line  # the pinion's start of active profile (at the ring's tip)
        _require(
            f"gear.addendum_coeff (involute interference: the ring's tip meets the pinion "
            f"{start * 1e3:.4f} mm from its tangent point, below its form circle "
            f"{rho_f * 1e3:.4f} mm)",
            self.gear.addendum_coeff,
            start >= rho_f - 1e-12,
            "small enough that the ring's tip meets the pinion on its involute (or a smaller "
            "gear.profile_shift, a larger pinion.profile_shift)",
        )
        clear = (rf[1] - a - ra[0], ra[1] - a - rf[0])
        _require(
            "tip-to-root clearance c1 (pinion tip to ring root, r_f2 − a_w − r_a1, m)",
            clear[0],
            clear[0] >= 0,
            ">= 0 (lower pinion.addendum_coeff or raise gear.dedendum_coeff)",
        )
        _require(
            "tip-to-root clearance c2 (ring tip to pinion root, r_a2 − a_w − r_f1, m)",
            clear[1],
            clear[1] >= 0,
            ">= 0 (lower gear.addendum_coeff or raise pinion.dedendum_coeff)",
        )
        g_alpha = roll_tip[0] - start
        pbt = math.pi * mt * math.cos(at)
        eps_a = g_alpha / pbt
        _require("transverse contact ratio", eps_a, eps_a >= 1.0, ">= 1 (increase addenda)")
        margin = trochoid_margin(z1, z2, ra[0], ra[1], rb[0], rb[1], a, awt)
        _require(
            f"gear.teeth (trochoid interference: margin {margin:.5f} rad, tooth-count "
            f"difference {-z2 - z1})",
            z2,
            margin >= 0,
            "a larger tooth-count difference |z2| − z1, or a larger operating pressure angle "
            "(a smaller x1 + x2) or shorter addenda (KHK's trochoid condition >= 0)",
        )
        b = min(self.pinion.face_width, self.gear.face_width)
        set_ = lambda k, v: object.__setattr__(self, k, v)
        set_("transverse_module", mt)
        set_("transverse_pressure_angle", at)
        set_("operating_pressure_angle", awt)
        set_("center_distance", a)
        set_("zero_backlash_center_distance", a0)
        set_("pitch_radii", r)
        set_("base_radii", rb)
        set_("tip_radii", ra)
        set_("root_radii", rf)
        set_("reference_thickness", st)
        # backlash: the ring's space less the pinion's tooth on the operating pitch circles,
        # j_bt = 2 (r_b2 − r_b1)(inv α_wtA − inv α_wt) >= 0 (0 at the zero-backlash distance
        # of the thinned teeth; round-off clamped)
        jbt = max(2 * (rb[1] - rb[0]) * (inv_awtA - involute(awt)), 0.0)
        thinned = tuple(
            st[i] + mt * m.tooth_thickness_allowance / mn for i, m in enumerate(members)
        )
        set_(
            "base_thickness",
            (
                2 * rb[0] * (thinned[0] / (2 * r[0]) + involute(at)),
                2 * rb[1] * (thinned[1] / (2 * r[1]) - involute(at)),
            ),
        )
        set_("backlash_center_distance", aA)
        set_("transverse_backlash", jbt)
        set_("circumferential_backlash", jbt / math.cos(awt))
        set_("normal_backlash", jbt * math.cos(math.atan(math.tan(beta) * math.cos(at))))
        set_("tip_thickness", (sa1, sa2))
        set_("pinion_form_roll", rho_f)
        set_("line_length", line)
        set_("start_roll", start)
        set_("base_pitch", pbt)
        set_("base_helix_angle", math.atan(math.tan(beta) * math.cos(at)))
        set_("path_of_contact", g_alpha)
        set_("transverse_contact_ratio", eps_a)
        set_("face_width", b)
        set_("overlap_ratio", b * math.sin(beta) / (math.pi * mn))
        set_("tip_root_clearances", clear)
        set_("trochoid_margin", margin)
        radial = radial_assembly_margin(z1, z2, ra[0], ra[1], rb[0], rb[1], awt)
        set_("radial_assembly_margin", radial)
        set_("mesh_period_angle", 2 * math.pi / z1)

    @property
    def ring(self) -> Member:
        """The internal gear (``gear``)."""
        return self.gear

    @property
    def total_contact_ratio(self) -> float:
        return self.transverse_contact_ratio + self.overlap_ratio

    @property
    def gear_ratio(self) -> float:
        """u = z2/z1 < 0 (ISO 21771, ISO 6336: negative for an internal pair)."""
        return self.gear.teeth / self.pinion.teeth

    def roll_distance(self, s, member: int):
        """Roll distance ρ (m) of base-plane coordinate ``s`` on member 0 (pinion, convex
        flank) or 1 (ring, concave flank), from the member's tangent point; both positive,
        ρ2 = ρ1 + a_w sin α_wt (the ring's radius of curvature, centre on the same side)."""
        rho1 = self.start_roll + s
        if member == 0:
            return rho1
        return rho1 + self.line_length

    def summary(self) -> dict:
        """Derived geometry as a JSON-ready dict (SI units)."""
        return {
            "internal": True,
            "transverse_contact_ratio": self.transverse_contact_ratio,
            "overlap_ratio": self.overlap_ratio,
            "total_contact_ratio": self.total_contact_ratio,
            "base_pitch_m": self.base_pitch,
            "center_distance_m": self.center_distance,
            "path_of_contact_m": self.path_of_contact,
            "operating_pressure_angle_deg": math.degrees(self.operating_pressure_angle),
            "base_helix_angle_deg": math.degrees(self.base_helix_angle),
            "base_radii_m": list(self.base_radii),
            "tip_radii_m": list(self.tip_radii),
            "root_radii_m": list(self.root_radii),
            "tip_root_clearances_m": list(self.tip_root_clearances),
            "trochoid_margin_rad": self.trochoid_margin,
            "radial_assembly_margin_rad": (
                self.radial_assembly_margin if math.isfinite(self.radial_assembly_margin) else None
            ),
            "face_width_m": self.face_width,
        }


def internal_tooth_geometry(pair: InternalGearPair, cutter=None):
    """The ring's :class:`fem_prep.InternalToothGeometry` of ``pair`` (its gear member), with the
    generating ``cutter`` (a :class:`fem_prep.ShaperCutter` or ``None``): the one place that
    builds it from an :class:`InternalGearPair`, as :func:`jaxgear._stiffness.tooth_geometry`
    does for external members.

    Raises:
        ValueError: a parameter out of range, named ``gear.<name>`` (or ``gear.cutter...``).
    """
    from fem_prep.tooth_form import InternalToothGeometry  # lazy: fem_prep imports SciPy

    return member_tooth_geometry(InternalToothGeometry, pair, 1, cutter)


@relative_radius.register
def _internal_relative_radius(pair: InternalGearPair, s):
    """The concave ring flank: R = ρ1 ρ2/(ρ2 − ρ1) (relative curvature 1/ρ1 − 1/ρ2) in the
    normal plane, ρ1 = (ρ_A + s)/cos β_b, ρ2 = (ρ_A + s + a_w sin α_wt)/cos β_b."""
    s = jnp.asarray(s)
    cb = jnp.cos(pair.base_helix_angle)
    rho1 = (pair.start_roll + s) / cb
    rho2 = (pair.start_roll + s + pair.line_length) / cb
    return rho1 * rho2 / (rho2 - rho1)


@iso6336_virtual_teeth.register
def _internal_virtual_teeth(pair: InternalGearPair) -> tuple[float, float]:
    """ISO 6336-1 method B's virtual teeth of an internal pair: z_n1 = z1/(cos² β_b cos β) and
    the internal gear's z_n2 taken as infinite (its terms C3/z_n2 and C7 x2/z_n2 vanish, the
    basic rack's value), the rule jaxgear applies to internal gears (docs/planetary.md)."""
    f = math.cos(pair.base_helix_angle) ** 2 * math.cos(pair.helix_angle)
    return pair.pinion.teeth / f, math.inf


@dataclasses.dataclass(frozen=True)
class PlanetaryGeometry:
    """The two pairs of a planetary stage at one operating centre distance (the carrier's
    planet-circle radius): the sun–planet :class:`~jaxgear.GearPair` and the planet–ring
    :class:`InternalGearPair`, built by :func:`planetary_geometry`.

    Attributes:
        sun_planet: the external pair (the sun drives the planet).
        planet_ring: the internal pair (the planet meshes inside the ring).
        center_distance: a_w (m), shared by both pairs.
        mismatch: the internal pair's zero-backlash distance less the external pair's (m, of
            the thinned teeth: ``backlash_center_distance``), >= 0: 0 for a concentric tooth
            set without allowances (z_r = z_s + 2 z_p and x_r = −(x_s + 2 x_p)); the pairs have
            a common distance only in between (an external pair jams closer than its
            zero-backlash distance, an internal pair farther).
    """

    sun_planet: GearPair
    planet_ring: InternalGearPair
    center_distance: float
    mismatch: float

    @property
    def sun_pressure_angle(self) -> float:
        """α_s: the sun–planet operating transverse pressure angle (rad), a
        :class:`~jaxgear.PlanetaryStage`'s ``sun_pressure_angle``."""
        return self.sun_planet.operating_pressure_angle

    @property
    def ring_pressure_angle(self) -> float:
        """α_r: the ring–planet operating transverse pressure angle (rad), a
        :class:`~jaxgear.PlanetaryStage`'s ``ring_pressure_angle``."""
        return self.planet_ring.operating_pressure_angle


def planetary_geometry(
    sun: Member,
    planet: Member,
    ring: Member,
    normal_module: float,
    normal_pressure_angle: float,
    helix_angle: float = 0.0,
    center_distance: float | None = None,
) -> PlanetaryGeometry:
    """Sun–planet and planet–ring pairs of a planetary stage at one centre distance.

    Args:
        sun, planet: external members (teeth >= 5). ring: the internal gear (teeth < 0, ISO
            21771; see :class:`InternalGearPair`).
        normal_module: m_n (m). normal_pressure_angle: α_n (rad). helix_angle: β (rad).
        center_distance: a_w (m), between the sun pair's and the ring pair's zero-backlash
            distances of the thinned teeth; ``None``: the sun pair's nominal zero-backlash
            distance, or the ring pair's if smaller.

    Returns:
        :class:`PlanetaryGeometry`.

    Raises:
        ValueError: the ring pair's zero-backlash distance below the sun pair's (no common
            distance: the teeth jam in one of the meshes), or any check of
            :class:`~jaxgear.GearPair` or :class:`InternalGearPair` (one line each).
    """
    args = (normal_module, normal_pressure_angle, helix_angle)
    external = GearPair(sun, planet, *args)
    internal = InternalGearPair(planet, ring, *args)
    # with thinned teeth: the sun pair fits from its backlash distance outwards, the ring pair
    # up to its own
    low, high = external.backlash_center_distance, internal.backlash_center_distance
    mismatch = high - low
    if mismatch < -1e-12 * low:
        raise ValueError(
            f"planetary_geometry: ring.profile_shift = {ring.profile_shift!r} is out of range: "
            f"the ring pair's zero-backlash distance {high * 1e3:.6f} mm is below the sun "
            f"pair's {low * 1e3:.6f} mm (the teeth jam at any common distance); allowed a "
            "smaller ring.profile_shift (thinner ring teeth), smaller sun/planet profile shifts "
            "or thinner teeth (tooth_thickness_allowance < 0)"
        )
    a = min(external.center_distance, high) if center_distance is None else center_distance
    return PlanetaryGeometry(
        GearPair(sun, planet, *args, a), InternalGearPair(planet, ring, *args, a), a, mismatch
    )
