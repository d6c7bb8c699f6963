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
from typing import ClassVar

import jax.numpy as jnp

from ._geometry import JAM, AbstractGearPair, GearPair, Member, involute
from ._pressure import relative_radius
from ._stiffness import iso6336_virtual_teeth, member_tooth_geometry
from ._util import check_integer

__all__ = [
    "InternalGearPair",
    "PlanetaryGeometry",
    "internal_tooth_geometry",
    "planetary_geometry",
]


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
class InternalGearPair(AbstractGearPair):
    """Internal involute spur or helical gear pair (ISO 21771): an external pinion meshing
    inside an internal gear; the pinion (member 1) drives; both turn the same sense. The shared
    geometry, attributes and checks are :class:`~jaxgear.AbstractGearPair`'s (σ2 = −1); here
    what is internal.

    Args:
        pinion: the external member (teeth z1 >= 5; a planet).
        gear: the internal gear (a ring): a :class:`~jaxgear.Member` with ``teeth`` z2 < 0 (ISO
            21771), |z2| > z1; its ``profile_shift`` x2 in ISO 21771's sign (positive thickens
            the ring's teeth, moving its tip circle inwards); ``bore_radius`` None (a ring has
            no bore); ``tooth_thickness_allowance`` A_sn (m, negative thins the ring's teeth)
            as for :class:`~jaxgear.GearPair`.
        normal_module: m_n (m). normal_pressure_angle: α_n (rad). helix_angle: β (rad), >= 0
            (both members of the same hand).
        center_distance: a_w (m), in (r_b2 − r_b1, ``backlash_center_distance``]: an internal
            pair has backlash *closer* than its zero-backlash distance and jams farther apart;
            ``None`` for the zero-backlash distance of the nominal teeth.

    Internal: ``operating_pressure_angle`` α_wt (inv α_wt = inv α_t + 2 tan α_n (x1 + x2)/(z1 +
    z2), z1 + z2 < 0), ``center_distance`` a_w = m_t (|z2| − z1)/2 · cos α_t/cos α_wt,
    ``pitch_radii`` (r1, |r2|), ``tip_radii`` (r_a1 = r1 + m_n (h_a1* + x1); r_a2 = |r2| − m_n
    (h_a2* + x2), inside), ``root_radii`` (r_f1 = r1 − m_n (h_f1* − x1); r_f2 = |r2| + m_n (h_f2*
    − x2), outside), ``pinion_form_roll`` (the pinion's form circle, roll distance from T1;
    ``form_roll`` (ρ_F1, None)), ``line_length`` T1T2 = a_w sin α_wt (both tangent points on the
    same side of the pitch point), ``start_roll`` (the pinion's start of active profile, at the
    ring's tip: √(r_a2² − r_b2²) − T1T2), ``path_of_contact`` g_α = √(r_a1² − r_b1²) −
    √(r_a2² − r_b2²) + a_w sin α_wt, ``tip_root_clearances`` (c1 = r_f2 − a_w − r_a1: pinion
    tip to ring root; c2 = r_a2 − a_w − r_f1: ring tip to pinion root), ``trochoid_margin``
    (:func:`trochoid_margin`, rad), ``radial_assembly_margin`` (:func:`radial_assembly_margin`,
    rad: reported, not refused; negative: the pinion goes in axially); the backlash:
    ``backlash_center_distance`` a_A, the zero-backlash distance of the thinned teeth (inv α_wtA
    = inv α_wt0 + (A_sn1 + A_sn2)/(m_n (z1 + z2))), ``transverse_backlash`` j_bt = 2 (r_b2 −
    r_b1)(inv α_wtA − inv α_wt) (the ring's space less the pinion's tooth along the line of
    action; 0 at a_A, > 0 for a_w < a_A), ``base_thickness`` (s_b1, s_b2), the members' tooth
    thicknesses on their base circles (the ring's: 2 r_b2 (s_t2/(2 r2) − inv α_t)). With
    ``coast=True`` :meth:`jaxgear.MeshModel.from_pair` lays out the coast flanks with this
    backlash.

    Checks (docs/planetary.md, "Internal gears"), beside the shared ones: |z2| > z1; no bore;
    a_w <= the zero-backlash distance; the ring's tip circle outside its base circle (r_a2 >
    r_b2); **involute interference**: the ring's tip meets the pinion on its involute above the
    form circle (start_roll >= pinion_form_roll; with a zero form roll this is KHK's z1/|z2| >=
    1 − tan α_a2/tan α_wt); **tip-to-root clearance** c1, c2 >= 0; **trochoid interference**:
    margin >= 0 (KHK), the condition that sets the minimum tooth-count difference (20° teeth,
    z1 = 20, unshifted, ring addendum 0.6 m_n: |z2| − z1 >= 7).

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

    _gear_sign: ClassVar[int] = -1
    _prefix: ClassVar[str] = "InternalGearPair"

    def _check_member(self, tag, member):
        if tag == "pinion":
            check_integer("InternalGearPair: pinion.teeth", member.teeth, 5)
            return
        z1, z2 = self.pinion.teeth, member.teeth
        self._require(
            "gear.teeth",
            z2,
            not isinstance(z2, bool) and int(z2) == z2 and z2 < -z1,
            f"an integer < {-z1} (an internal gear's tooth count is negative, ISO 21771, and "
            "larger in magnitude than the pinion's)",
        )
        self._require(
            "gear.bore_radius",
            member.bore_radius,
            member.bore_radius is None,
            "None (an internal gear has no bore; its rim is given by rim_thickness)",
        )

    def _centre_lever(self, r, rb, at):
        return rb[1] - rb[0]

    def _operating(self, a0, awt0, aA, allowances, rb):
        if self.center_distance is None:
            self._require(
                JAM,
                allowances,
                aA >= a0 * (1 - 1e-9),
                f"<= 0 m (the teeth jam at the zero-backlash distance {a0 * 1e3:.6f} mm of the "
                f"nominal teeth); or give center_distance <= {aA * 1e3:.6f} mm",
            )
            return a0, awt0
        # an internal pair jams farther apart: the pinion's tooth enters the ring's space
        # deeper, where the space narrows (the ring's teeth thicken towards their roots)
        a = float(self.center_distance)
        self._require(
            "center_distance",
            a,
            rb[1] - rb[0] < a <= aA * (1 + 1e-9),
            f"({(rb[1] - rb[0]) * 1e3:.6f}, {aA * 1e3:.6f}] mm (up to the zero-backlash "
            "distance of the thinned teeth; farther apart, the teeth of an internal pair jam)",
        )
        return a, math.acos((rb[1] - rb[0]) / a)

    def _contact(self, line, roll_tip, form_roll, a, ra, rf):
        start = roll_tip[1] - line  # the pinion's start of active profile (at the ring's tip)
        rho_f = form_roll[0]
        self._require(
            f"gear.addendum_coeff (involute interference: the ring's tip meets the pinion "
            f"{start * 1e3:.4f} mm from its tangent point, below its form circle "
            f"{rho_f * 1e3:.4f} mm)",
            self.gear.addendum_coeff,
            start >= rho_f - 1e-12,
            "small enough that the ring's tip meets the pinion on its involute (or a smaller "
            "gear.profile_shift, a larger pinion.profile_shift)",
        )
        clear = (rf[1] - a - ra[0], ra[1] - a - rf[0])
        self._require(
            "tip-to-root clearance c1 (pinion tip to ring root, r_f2 − a_w − r_a1, m)",
            clear[0],
            clear[0] >= 0,
            ">= 0 (lower pinion.addendum_coeff or raise gear.dedendum_coeff)",
        )
        self._require(
            "tip-to-root clearance c2 (ring tip to pinion root, r_a2 − a_w − r_f1, m)",
            clear[1],
            clear[1] >= 0,
            ">= 0 (lower gear.addendum_coeff or raise pinion.dedendum_coeff)",
        )
        object.__setattr__(self, "tip_root_clearances", clear)
        return start, roll_tip[0] - start

    def _backlash(self, r, rb, st, mt, at, awt, inv_awtA):
        # the ring's space less the pinion's tooth on the operating pitch circles,
        # j_bt = 2 (r_b2 − r_b1)(inv α_wtA − inv α_wt) >= 0 (0 at the zero-backlash distance
        # of the thinned teeth; round-off clamped)
        mn = self.normal_module
        jbt = max(2 * (rb[1] - rb[0]) * (inv_awtA - involute(awt)), 0.0)
        members = (self.pinion, self.gear)
        thinned = tuple(
            st[i] + mt * m.tooth_thickness_allowance / mn for i, m in enumerate(members)
        )
        sb = (
            2 * rb[0] * (thinned[0] / (2 * r[0]) + involute(at)),
            2 * rb[1] * (thinned[1] / (2 * r[1]) - involute(at)),
        )
        return sb, jbt

    def _finish(self):
        z1, z2 = self.pinion.teeth, self.gear.teeth
        ra, rb = self.tip_radii, self.base_radii
        a, awt = self.center_distance, self.operating_pressure_angle
        margin = trochoid_margin(z1, z2, ra[0], ra[1], rb[0], rb[1], a, awt)
        self._require(
            f"gear.teeth (trochoid interference: margin {margin:.5f} rad, tooth-count "
            f"difference {-z2 - z1})",
            z2,
            margin >= 0,
            "a larger tooth-count difference |z2| − z1, or a larger operating pressure angle "
            "(a smaller x1 + x2) or shorter addenda (KHK's trochoid condition >= 0)",
        )
        set_ = lambda k, v: object.__setattr__(self, k, v)
        set_("pinion_form_roll", self.form_roll[0])
        set_("trochoid_margin", margin)
        set_(
            "radial_assembly_margin",
            radial_assembly_margin(z1, z2, ra[0], ra[1], rb[0], rb[1], awt),
        )

    @property
    def ring(self) -> Member:
        """The internal gear (``gear``)."""
        return self.gear

    def summary(self) -> dict:
        """Derived geometry as a JSON-ready dict (SI units): the shared keys, ``internal``, the
        clearances and the margins."""
        shared = super().summary()
        face = shared.pop("face_width_m")
        return {
            "internal": True,
            **shared,
            "tip_root_clearances_m": list(self.tip_root_clearances),
            "trochoid_margin_rad": self.trochoid_margin,
            "radial_assembly_margin_rad": (
                self.radial_assembly_margin if math.isfinite(self.radial_assembly_margin) else None
            ),
            "face_width_m": face,
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
        :class:`~jaxgear.planetary.PlanetaryStage`'s ``sun_pressure_angle``."""
        return self.sun_planet.operating_pressure_angle

    @property
    def ring_pressure_angle(self) -> float:
        """α_r: the ring–planet operating transverse pressure angle (rad), a
        :class:`~jaxgear.planetary.PlanetaryStage`'s ``ring_pressure_angle``."""
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
