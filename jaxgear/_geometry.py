"""Involute gear-pair geometry (ISO 21771), computed once in NumPy.

Geometry fixes the shapes of everything downstream (number of contact lines, base-plane extent),
so it is evaluated eagerly in float64 NumPy and validated here, before anything is traced. The
results are plain Python floats in SI units.

Sources: ISO 21771:2007 (involute geometry, profile shift, form circle), the seed's Tab. III-1 /
III-5 for the reference pairs. Conventions: docs/design.md, "Base plane and sign conventions".
"""

from __future__ import annotations

import abc
import dataclasses
import math
from typing import ClassVar

from fem_prep.involute import inverse_involute, involute

from ._backlash import backlashes, base_thicknesses, thinned_involute
from ._util import check_instance, check_integer, check_real

__all__ = ["AbstractGearPair", "GearPair", "Member", "inverse_involute", "involute"]


@dataclasses.dataclass(frozen=True)
class Member:
    """One gear of the pair (input data, SI units).

    Attributes:
        teeth: number of teeth z (>= 5).
        profile_shift: profile shift coefficient x (multiplies the *normal* module).
        addendum_coeff: addendum coefficient h_a* (tip radius r_a = r + m_n (h_a* + x)).
        dedendum_coeff: dedendum coefficient h_f* (root radius r_f = r − m_n (h_f* − x)); it is
            also the addendum of the generating rack cutter.
        face_width: face width b (m).
        fillet_radius_coeff: tip radius of the generating rack ρ_fP / m_n (Tab. III-1: 0.25).
        bore_radius: radius r_int of the gear body's bore (m), used by the Sainsot foundation
            term; ``None`` for the default 0.5 × root radius (see ``_stiffness.bore_radius``).
        web_thickness, rim_thickness: web thickness b_s and rim thickness s_R (m) of a webbed
            blank, for the ISO 6336-1 gear blank factor C_R of the ``iso6336`` stiffness;
            ``None`` (either) for a solid blank (C_R = 1).
        tooth_thickness_allowance: A_sn, the normal tooth-thickness allowance (m) at the
            reference circle (ISO 21771 / DIN 3967 sign: negative thins the tooth, s_n = s_n,0 +
            A_sn). It gives the backlash (:class:`GearPair` ``normal_backlash``); the stiffness
            models keep the nominal tooth (tens of µm change a tooth's compliance by well
            under 1 %).
    """

    teeth: int
    profile_shift: float = 0.0
    addendum_coeff: float = 1.0
    dedendum_coeff: float = 1.25
    face_width: float = 0.01
    fillet_radius_coeff: float = 0.25
    bore_radius: float | None = None
    web_thickness: float | None = None
    rim_thickness: float | None = None
    tooth_thickness_allowance: float = 0.0


#: the name in :class:`GearPair`'s error when teeth thickened by positive allowances jam at the
#: default centre distance (the zero-backlash distance of the nominal teeth)
JAM = "tooth_thickness_allowance (pinion + gear) without a center_distance"

#: the real-valued fields of :class:`Member` (every field but ``teeth``), checked finite
_REAL_FIELDS = (
    "profile_shift",
    "addendum_coeff",
    "dedendum_coeff",
    "face_width",
    "fillet_radius_coeff",
    "bore_radius",
    "web_thickness",
    "rim_thickness",
    "tooth_thickness_allowance",
)

# units of the inputs, for the messages
_UNITS = {
    "face_width": "m",
    "bore_radius": "m",
    "web_thickness": "m",
    "rim_thickness": "m",
    "tooth_thickness_allowance": "m",
    "normal_module": "m",
    "normal_pressure_angle": "rad",
    "helix_angle": "rad",
    "center_distance": "m",
}


def _require(name: str, value: float, ok: bool, allowed: str) -> None:
    if not ok:
        raise ValueError(f"{name} = {value!r} is out of range: allowed {allowed}")


def check_member_ranges(tag: str, m: Member, mn: float, require=_require) -> None:
    """The range checks of one :class:`Member`'s fields but its tooth count (face width,
    addendum, dedendum, fillet radius, web and rim, tooth-thickness allowance against the normal
    module ``mn``, m), shared by :class:`GearPair` and :class:`~jaxgear.InternalGearPair`;
    ``require(name, value, ok, allowed)`` raises the pair's one-line ``ValueError``. The profile
    shift has no fixed range: what it makes impossible (a pointed tip, an undercut, interference,
    a root below the centre, too little contact) is checked on the pair's geometry."""
    require(f"{tag}.face_width", m.face_width, m.face_width > 0, "> 0")
    require(f"{tag}.addendum_coeff", m.addendum_coeff, m.addendum_coeff > 0, "> 0")
    require(f"{tag}.dedendum_coeff", m.dedendum_coeff, m.dedendum_coeff > 0, "> 0")
    require(
        f"{tag}.fillet_radius_coeff",
        m.fillet_radius_coeff,
        0 <= m.fillet_radius_coeff < m.dedendum_coeff,
        "[0, dedendum_coeff)",
    )
    for name in ("web_thickness", "rim_thickness"):
        v = getattr(m, name)
        require(f"{tag}.{name}", v, v is None or v > 0, "> 0 or None (solid blank)")
    A = m.tooth_thickness_allowance
    require(
        f"{tag}.tooth_thickness_allowance",
        A,
        math.isfinite(A) and -0.25 * mn <= A <= 0.25 * mn,
        f"[{-0.25 * mn:.6g}, {0.25 * mn:.6g}] m (a quarter of the normal module)",
    )


#: the members' names, in the pair's order (member 0 drives)
_TAGS = ("pinion", "gear")


@dataclasses.dataclass(frozen=True)
class AbstractGearPair(abc.ABC):
    """An involute spur or helical gear pair (ISO 21771); member 0 (the pinion, external) drives.
    The one home of the pair geometry both kinds share; a kind is a subclass:
    :class:`GearPair` (external) and :class:`~jaxgear.InternalGearPair` (the gear an internal
    gear, its ``teeth`` negative as ISO 21771 writes them). ``isinstance(p, AbstractGearPair)``
    accepts either; ``isinstance(p, GearPair)`` still means an external pair.

    Construct a kind with the input data; every derived quantity is a read-only attribute
    computed in ``__post_init__`` (SI units, angles in rad; radii and the centre distance
    positive, ISO 21771's convention). Every check raises one ``ValueError`` line naming the
    parameter, its value and the allowed range, before anything downstream is computed.

    Args:
        pinion, gear: the two :class:`Member` (the pinion the driving member 1).
        normal_module: m_n (m). normal_pressure_angle: α_n (rad), in (0, 45°).
        helix_angle: β (rad), in [0, 45°); 0 for spur gears.
        center_distance: operating centre distance a_w (m); ``None`` for the zero-backlash
            distance of the nominal teeth (ISO 21771 (40)); the allowed side is the kind's.

    Derived attributes, the same formulas for both kinds with σ = +1 (external) or −1
    (internal), the sign of the gear's tooth count (ISO 21771): ``transverse_module`` m_t =
    m_n/cos β, ``transverse_pressure_angle`` α_t, ``operating_pressure_angle`` α_wt (inv α_wt0
    = inv α_t + 2 tan α_n (x1 + x2)/(z1 + z2)), ``center_distance`` a_w,
    ``zero_backlash_center_distance``, ``backlash_center_distance`` (the zero-backlash distance
    of the thinned teeth: 2 x tan α_n + A_sn/m_n per member), ``pitch_radii`` r_i = |z_i| m_t/2,
    ``base_radii`` r_bi = r_i cos α_t, ``tip_radii`` r_ai = r_i + σ_i m_n (h_a* + x),
    ``root_radii`` r_fi = r_i − σ_i m_n (h_f* − x) (an internal gear's tip circle inside, its
    root circle outside), ``reference_thickness`` s_t = m_t (π/2 + 2 x tan α_n),
    ``tip_thickness``, ``form_roll`` (the roll distance of each rack-generated member's form
    circle from its tangent point, ISO 21771 (88)-(90); ``None`` for an internal gear),
    ``line_length`` T1T2 = a_w sin α_wt, ``start_roll`` (the pinion's start of active profile
    from T1: the line-of-action coordinate s = 0 of docs/design.md, "Base plane and sign
    conventions"), ``path_of_contact`` g_α, ``base_pitch`` p_bt = π m_t cos α_t,
    ``base_helix_angle`` β_b, ``transverse_contact_ratio`` ε_α = g_α/p_bt (>= 1),
    ``overlap_ratio`` ε_β = b sin β/(π m_n), ``face_width`` b (the overlap of the two),
    ``mesh_period_angle`` 2π/z1; the backlash (ISO 21771 / DIN 3967, docs/backlash.md):
    ``base_thickness`` (s_b1, s_b2), ``transverse_backlash`` j_bt (its formula the kind's),
    ``circumferential_backlash`` j_wt = j_bt/cos α_wt, ``normal_backlash`` j_bn = j_bt cos β_b.

    Shared checks: types and finite numbers; sizes and coefficients (:func:`check_member_ranges`);
    inv α_wt > 0; root radius > 0, tip radius > base radius (both members: an internal gear's
    involute exists only outside its base circle), a bore inside the root circle; no pointed
    tip (s_a > 0); no undercut of a rack-generated member; ε_α > 0 and the total contact ratio
    ε_γ = ε_α + ε_β >= 1 (a helical pair with ε_α < 1 transmits through its overlap). The
    profile shift has no fixed range: these are what it makes impossible. The kind adds
    involute interference and the tip-to-root clearances (each tip inside the mating root
    circle).

    What a kind supplies (the physics that differs): ``_gear_sign`` σ2; ``_check_member`` (the
    kind's tooth-count rules); ``_centre_lever`` a_w cos α_wt (r_b1 ± r_b2 in its rounding) and
    ``_operating`` (the side of the zero-backlash distance where the teeth have backlash);
    ``_contact`` (the start of active profile, g_α and the interference checks); ``_backlash``
    (s_b and j_bt); ``_finish`` (the kind's own checks after ε_α and its own attributes).
    """

    pinion: Member
    gear: Member
    normal_module: float
    normal_pressure_angle: float
    helix_angle: float = 0.0
    center_distance: float | None = None

    #: σ2, the sign of the gear's tooth count (ISO 21771): +1 external, −1 internal
    _gear_sign: ClassVar[int]
    #: the head of the pair's one-line messages ("" for none)
    _prefix: ClassVar[str] = ""

    def _require(self, name: str, value, ok: bool, allowed: str) -> None:
        if not ok:
            head = f"{self._prefix}: " * bool(self._prefix)
            raise ValueError(f"{head}{name} = {value!r} is out of range: allowed {allowed}")

    def _check_inputs(self) -> None:
        """Types and finite numbers first (a NaN, an infinity or a string would pass or break
        the range checks), then the ranges; one line naming the attribute."""
        for tag in _TAGS:
            check_instance(tag, getattr(self, tag), Member, "a jaxgear.Member", type(self).__name__)
            m = getattr(self, tag)
            self._check_member(tag, m)
            for name in _REAL_FIELDS:
                v = getattr(m, name)
                if v is not None:
                    check_real(
                        f"{tag}.{name}", v, _UNITS.get(name, ""), shape=(), where=self._prefix
                    )
        for name in ("normal_module", "normal_pressure_angle", "helix_angle", "center_distance"):
            if getattr(self, name) is not None:
                check_real(name, getattr(self, name), _UNITS[name], shape=(), where=self._prefix)
        mn, an, beta = self.normal_module, self.normal_pressure_angle, self.helix_angle
        self._require("normal_module", mn, mn > 0, "> 0")
        self._require("normal_pressure_angle", an, 0 < an < math.radians(45), "(0, 45) deg")
        self._require("helix_angle", beta, 0 <= beta < math.radians(45), "[0, 45) deg")
        for tag in _TAGS:
            check_member_ranges(tag, getattr(self, tag), mn, self._require)

    def __post_init__(self) -> None:
        self._check_inputs()
        mn, an, beta = self.normal_module, self.normal_pressure_angle, self.helix_angle
        members = (self.pinion, self.gear)
        sign = (1, self._gear_sign)
        z1, z2 = self.pinion.teeth, self.gear.teeth
        x1, x2 = self.pinion.profile_shift, self.gear.profile_shift
        mt = mn / math.cos(beta)
        at = math.atan(math.tan(an) / math.cos(beta))
        r = (z1 * mt / 2.0, abs(z2) * mt / 2.0)
        rb = (r[0] * math.cos(at), r[1] * math.cos(at))
        # ISO 21771 (40), z2 < 0 for an internal gear (then z1 + z2 < 0 turns the bounds)
        inv_awt0 = involute(at) + 2.0 * math.tan(an) * (x1 + x2) / (z1 + z2)
        rel = ">" if z1 + z2 > 0 else "<"
        self._require(
            "profile_shift (x1 + x2)",
            x1 + x2,
            inv_awt0 > 0,
            f"{rel} {-(z1 + z2) * involute(at) / (2 * math.tan(an)):.4f} (inv α_wt > 0)",
        )
        awt0 = inverse_involute(inv_awt0)
        lever = self._centre_lever(r, rb, at)
        a0 = lever / math.cos(awt0)
        # zero backlash with the thinned teeth: ISO 21771 (40) with 2 x tan α_n + A_sn / m_n
        allowances = self.pinion.tooth_thickness_allowance + self.gear.tooth_thickness_allowance
        inv_awtA = thinned_involute(inv_awt0, allowances, mn, z1 + z2)
        self._require(
            "tooth_thickness_allowance (pinion + gear)",
            allowances,
            inv_awtA > 0,
            f"{rel} {-(inv_awt0 * (z1 + z2) * mn):.6g} m (inv α_wt > 0)",
        )
        aA = lever / math.cos(inverse_involute(inv_awtA))
        a, awt = self._operating(a0, awt0, aA, allowances, rb)
        ra = tuple(
            r[i] + sign[i] * mn * (m.addendum_coeff + m.profile_shift)
            for i, m in enumerate(members)
        )
        rf = tuple(
            r[i] - sign[i] * mn * (m.dedendum_coeff - m.profile_shift)
            for i, m in enumerate(members)
        )
        for i, (tag, m) in enumerate(zip(_TAGS, members)):
            inside = sign[i] < 0  # an internal gear: its tip circle inside, its root outside
            self._require(
                f"{tag}.root radius (from dedendum_coeff and profile_shift)",
                rf[i],
                rf[i] > 0,
                "> 0",
            )
            self._require(
                f"{tag}.tip radius (from addendum_coeff and profile_shift"
                + ": the ring's tip circle must stay outside its base circle)" * inside
                + ")" * (not inside),
                ra[i],
                ra[i] > rb[i],
                f"> base radius {rb[i] * 1e3:.4f} mm"
                + f" (lower {tag}.addendum_coeff or {tag}.profile_shift)" * inside,
            )
            if m.bore_radius is not None:
                self._require(
                    f"{tag}.bore_radius",
                    m.bore_radius,
                    0 < m.bore_radius < rf[i],
                    f"(0, {rf[i]:.6g}) m (below the root radius)",
                )
        # transverse tooth thickness at the reference circle and at the tip (ISO 21771); an
        # internal gear's tooth is thinnest at its tip, inside: its involute terms turn sign
        st = tuple(mt * (math.pi / 2 + 2 * m.profile_shift * math.tan(an)) for m in members)
        tip_thickness = []
        for i, (tag, m) in enumerate(zip(_TAGS, members)):
            aa = math.acos(rb[i] / ra[i])
            sa = 2 * ra[i] * (st[i] / (2 * r[i]) + sign[i] * involute(at) - sign[i] * involute(aa))
            self._require(
                f"{tag}.addendum_coeff (tip thickness {sa * 1e3:.4f} mm: pointed tooth; lower "
                f"{tag}.addendum_coeff or {tag}.profile_shift)",
                m.addendum_coeff,
                sa > 0,
                "a tip tooth thickness > 0",
            )
            tip_thickness.append(sa)
        # form circle of the generating rack (ISO 21771 (88)-(90)): roll distance from T; an
        # internal gear is cut by a pinion cutter (its form: fem_prep.InternalToothGeometry)
        form_roll = []
        for i, (tag, m) in enumerate(zip(_TAGS, members)):
            if sign[i] < 0:
                form_roll.append(None)
                continue
            h = mn * (
                m.dedendum_coeff - m.profile_shift - m.fillet_radius_coeff * (1 - math.sin(an))
            )
            rho_f = r[i] * math.sin(at) - h / math.sin(at)
            self._require(
                f"{tag}.profile_shift (undercut: form circle roll {rho_f * 1e3:.4f} mm)",
                m.profile_shift,
                rho_f >= 0,
                "large enough that the involute starts above the base circle (no undercut)",
            )
            form_roll.append(rho_f)
        line = a * math.sin(awt)  # T1T2
        roll_tip = (math.sqrt(ra[0] ** 2 - rb[0] ** 2), math.sqrt(ra[1] ** 2 - rb[1] ** 2))
        start, g_alpha = self._contact(line, roll_tip, form_roll, a, ra, rf)
        pbt = math.pi * mt * math.cos(at)
        eps_a = g_alpha / pbt
        self._require("transverse contact ratio", eps_a, eps_a > 0.0, "> 0 (the tips must reach)")
        b = min(self.pinion.face_width, self.gear.face_width)
        # a helical pair transmits with ε_α < 1 when the overlap carries it: ε_γ = ε_α + ε_β >= 1
        eps_g = eps_a + b * math.sin(beta) / (math.pi * mn)
        self._require(
            "total contact ratio",
            eps_g,
            eps_g >= 1.0,
            f">= 1 (ε_α = {eps_a:.4f} + ε_β = {eps_g - eps_a:.4f}: increase the addenda, the face "
            "width or the helix angle)",
        )
        beta_b = math.atan(math.tan(beta) * math.cos(at))
        sb, jbt = self._backlash(r, rb, st, mt, at, awt, inv_awtA)
        set_ = lambda k, v: object.__setattr__(self, k, v)
        set_("transverse_module", mt)
        set_("transverse_pressure_angle", at)
        set_("operating_pressure_angle", awt)
        set_("center_distance", a)
        set_("zero_backlash_center_distance", a0)
        set_("backlash_center_distance", aA)
        set_("base_thickness", sb)
        set_("transverse_backlash", jbt)
        set_("circumferential_backlash", jbt / math.cos(awt))
        set_("normal_backlash", jbt * math.cos(beta_b))
        set_("pitch_radii", r)
        set_("base_radii", rb)
        set_("tip_radii", ra)
        set_("root_radii", rf)
        set_("reference_thickness", st)
        set_("tip_thickness", tuple(tip_thickness))
        set_("form_roll", tuple(form_roll))
        set_("line_length", line)
        set_("start_roll", start)
        set_("base_pitch", pbt)
        set_("base_helix_angle", beta_b)
        set_("path_of_contact", g_alpha)
        set_("transverse_contact_ratio", eps_a)
        set_("face_width", b)
        set_("overlap_ratio", b * math.sin(beta) / (math.pi * mn))
        set_("mesh_period_angle", 2 * math.pi / z1)
        self._finish()

    # -- what a kind supplies ------------------------------------------------------------------

    @abc.abstractmethod
    def _check_member(self, tag: str, member: Member) -> None:
        """The kind's rules for one member (its tooth count, ...), one line each."""

    @abc.abstractmethod
    def _centre_lever(self, r, rb, at: float) -> float:
        """a_w cos α_wt (m), the same for every centre distance: r_b1 + r_b2 (external),
        r_b2 − r_b1 (internal)."""

    @abc.abstractmethod
    def _operating(self, a0: float, awt0: float, aA: float, allowances: float, rb) -> tuple:
        """(a_w, α_wt): the given ``center_distance`` checked on the side where the teeth have
        backlash (``aA`` the zero-backlash distance of the thinned teeth), or ``a0``, ``awt0``."""

    @abc.abstractmethod
    def _contact(self, line: float, roll_tip, form_roll, a: float, ra, rf) -> tuple:
        """(start_roll, g_α) from T1T2 and the tips' roll distances from their tangent points,
        with the kind's interference checks (against ``form_roll``)."""

    @abc.abstractmethod
    def _backlash(self, r, rb, st, mt: float, at: float, awt: float, inv_awtA: float) -> tuple:
        """(s_b, j_bt): the base thicknesses (s_b1, s_b2) and the transverse backlash (m)."""

    def _finish(self) -> None:
        """The kind's checks after the contact ratio and its own attributes; none here."""

    # -- shared methods ------------------------------------------------------------------------

    @property
    def total_contact_ratio(self) -> float:
        """ε_γ = ε_α + ε_β."""
        return self.transverse_contact_ratio + self.overlap_ratio

    @property
    def gear_ratio(self) -> float:
        """u = z2/z1 (negative for an internal pair, ISO 21771 and ISO 6336)."""
        return self.gear.teeth / self.pinion.teeth

    def roll_distance(self, s, member: int):
        """Roll distance ρ (m) of base-plane coordinate ``s`` on member 0 (pinion) or 1 (gear).

        ρ is measured along the line of action from the member's base tangent point; the contact
        point's radius is √(ρ² + r_b²) and its radius of curvature is ρ: ρ1 = ρ_A + s and
        ρ2 = T1T2 − σ2 ρ1 (external: the tangent points on either side of the pitch point;
        internal: on the same side, ρ2 = ρ1 + T1T2, the ring's concave flank).
        """
        rho1 = self.start_roll + s
        if member == 0:
            return rho1
        return self.line_length - self._gear_sign * rho1

    def summary(self) -> dict:
        """Derived geometry as a JSON-ready dict (SI units)."""
        return {
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
            "face_width_m": self.face_width,
        }


@dataclasses.dataclass(frozen=True)
class GearPair(AbstractGearPair):
    """External involute spur or helical gear pair; member 1 (pinion) drives. The shared
    geometry, attributes and checks are :class:`AbstractGearPair`'s; here what is external.

    Args:
        pinion, gear: the two members (pinion = driving member 1), teeth >= 5 each.
        normal_module: m_n (m).
        normal_pressure_angle: α_n (rad).
        helix_angle: β (rad), >= 0; 0 for spur gears.
        center_distance: operating centre distance a_w (m), >= ``backlash_center_distance``
            (closer, the teeth jam); ``None`` for the zero-backlash distance from the profile
            shifts (ISO 21771 (40)).

    External: a_w = (r1 + r2) cos α_t/cos α_wt; the tangent points T1, T2 on either side of the
    pitch point, g_α = √(r_a1² − r_b1²) + √(r_a2² − r_b2²) − a_w sin α_wt and ``start_roll`` =
    T1T2 − √(r_a2² − r_b2²); interference checked both ways (each member's active profile
    starts above its form circle, ``form_roll`` (ρ_F1, ρ_F2)) and each tip inside the mating
    root circle, ``tip_root_clearances`` (c1, c2) = (a_w − r_a1 − r_f2, a_w − r_a2 − r_f1) >= 0
    (m).

    Backlash (ISO 21771 / DIN 3967; docs/backlash.md) from the operating centre distance and the
    members' ``tooth_thickness_allowance`` A_sn (m, negative thins): ``transverse_backlash``
    j_bt = p_bt − s_b1 − s_b2 + 2 (r_b1 + r_b2) inv α_wt, the gap between the coast flanks
    along the transverse line of action (s_bi = m_t cos α_t (π/2 + 2 x_i tan α_n + A_sni/m_n +
    z_i inv α_t), the base-circle tooth thicknesses), ``circumferential_backlash`` j_wt =
    j_bt / cos α_wt (on the operating pitch circle), ``normal_backlash`` j_bn = j_bt cos β_b
    (normal to the flanks, what a feeler gauge reads); all 0 for zero allowances at the
    zero-backlash centre distance. ``backlash_center_distance``: the zero-backlash distance of
    the thinned teeth (ISO 21771 (40) with 2 x tan α_n + A_sn/m_n per member).

    Raises:
        ValueError: non-positive sizes, tip below the base circle, pointed tips, undercut
            (involute form circle below the base circle), interference (active profile
            starting below the form circle), a tip cutting into the mating root (tip-to-root
            clearance below 0), a total contact ratio ε_γ below 1, a centre distance below the
            zero-backlash distance; one line naming the parameter, its
            value and the allowed range.
    """

    _gear_sign: ClassVar[int] = 1

    def _check_member(self, tag, member):
        check_integer(f"{tag}.teeth", member.teeth, 5)

    def _centre_lever(self, r, rb, at):
        return (r[0] + r[1]) * math.cos(at)

    def _operating(self, a0, awt0, aA, allowances, rb):
        if self.center_distance is None:
            # thickened teeth (A_sn1 + A_sn2 > 0) do not fit at a0: no backlash to clamp to 0
            self._require(
                JAM,
                allowances,
                aA <= a0 * (1 + 1e-9),
                f"<= 0 m (the teeth jam at the zero-backlash distance {a0 * 1e3:.6f} mm of the "
                f"nominal teeth); or give center_distance >= {aA * 1e3:.6f} mm",
            )
            return a0, awt0
        a = float(self.center_distance)
        self._require(
            "center_distance",
            a,
            a >= aA * (1 - 1e-9),
            f">= {aA * 1e3:.6f} mm (zero-backlash distance; closer, the teeth jam)",
        )
        return a, math.acos(min(1.0, (rb[0] + rb[1]) / a))

    def _contact(self, line, roll_tip, form_roll, a, ra, rf):
        start = (line - roll_tip[1], line - roll_tip[0])  # start of active profile, each member
        for i, tag in enumerate(_TAGS):
            other = _TAGS[1 - i]
            self._require(
                f"{other}.addendum_coeff (interference: {tag} active profile starts "
                f"{start[i] * 1e3:.4f} mm from its tangent point, below the form circle "
                f"{form_roll[i] * 1e3:.4f} mm)",
                (self.pinion, self.gear)[1 - i].addendum_coeff,
                start[i] >= form_roll[i] - 1e-12,
                "small enough to avoid interference",
            )
        # each tip inside the mating root circle: c = a_w − r_a − r_f (mating) >= 0
        clear = (a - ra[0] - rf[1], a - ra[1] - rf[0])
        for i, tag in enumerate(_TAGS):
            other = _TAGS[1 - i]
            self._require(
                f"tip-to-root clearance c{i + 1} ({tag} tip to {other} root, a_w − r_a{i + 1} − "
                f"r_f{2 - i}, m)",
                clear[i],
                clear[i] >= -1e-12,
                f">= 0 (the {tag} tip would cut into the {other} root: lower "
                f"{tag}.addendum_coeff or raise {other}.dedendum_coeff)",
            )
        object.__setattr__(self, "tip_root_clearances", clear)
        return start[0], roll_tip[0] + roll_tip[1] - line

    def _backlash(self, r, rb, st, mt, at, awt, inv_awtA):
        # the base pitch less the base-circle thicknesses, carried to the operating pressure
        # angle (docs/backlash.md)
        mn, an, beta = self.normal_module, self.normal_pressure_angle, self.helix_angle
        sb = base_thicknesses((self.pinion, self.gear), mt, at, an, mn, involute(at))
        jbt, _, _ = backlashes(sb, rb, mt, at, awt, involute(awt), beta)
        return sb, jbt
