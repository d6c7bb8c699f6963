"""The load-capacity rating of an internal pair (an external pinion, e.g. a planet, in an
internal gear, a ring): ISO 6336-2:2006/2019 and ISO 6336-3:2006/2019 method B with the
standard's internal-gear rules, as a geometry object the rating functions of
:func:`jaxgear.rating.rate` ask the same questions as :class:`jaxgear.rating.RatingGeometry`.

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
* The pinion's Y_F, Y_S: the external method B (:func:`jaxgear.rating.member_form`) with the internal
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
import itertools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._internal import InternalGearPair
from .._results import CutterResult
from .._util import as_float, check_instance, check_integer, check_real, is_traced
from ._bending import ToothFormFactors, _inv, member_form, section_factors
from ._geometry import (
    AbstractRatingGeometry,
    Derived,
    inverse_involute_jnp,
    pair_derived,
    pair_fields,
)

__all__ = [
    "AbstractRootSection",
    "GivenRootSection",
    "InternalRatingGeometry",
    "ShaperCutterSection",
    "SubstituteRack",
]


class AbstractRootSection(eqx.Module):
    """How the internal gear's critical root section (ISO 6336-3, 60° tangent) is found: a
    method object of :class:`InternalRatingGeometry`."""

    @abc.abstractmethod
    def section(self, geometry: InternalRatingGeometry, g: Derived) -> tuple:
        """(s_Fn, ρ_F, d_sFn) of the internal gear (m, magnitudes): the chord at the 60°
        tangent points, the fillet's radius of curvature there and the diameter of the chord's
        ends."""

    def check(self, geometry) -> None:
        """Refuse, in one ``ValueError`` line, a section this method cannot give for
        ``geometry`` (concrete values; nothing here: every geometry has one)."""


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


def _e(phi):
    """The unit vector at polar angle ``phi`` measured from +y toward +x (stacked last)."""
    return jnp.stack([jnp.sin(phi), jnp.cos(phi)], axis=-1)


def _e_prime(phi):
    """d/dφ of :func:`_e`."""
    return jnp.stack([jnp.cos(phi), -jnp.sin(phi)], axis=-1)


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _cutter(mn, an, z0, x0, rho_a0, zr, x2, r_f):
    """The cutting mesh and the cutter's tip (:func:`shaper_cut_section`): (a0, r_c, η_c, the
    result code). The code (:class:`jaxgear.CutterResult`) is nonzero where the cutter cannot
    generate the fillet up to its 60° section: no cutting mesh (inv α_w0 <= 0); the tip
    rounding's centre at r_c <= r_b0 (no involute above the rounding); a pointed tooth (η_c <
    0: the two tip roundings overlap, ISO 21771's tip thickness below zero); the rounding's
    centre inside the cutting pitch circle r_w0 = a0 z0/(|z2| − z0) (r_c <= r_w0: its path
    in the ring's frame turns back before the fillet's tangent reaches 60°, the internal
    analogue of ISO 6336-3's condition G < 0 on the generating rack, whose rounding centre
    lies beyond the rolling line)."""
    inv = _inv
    inv_w = inv(an) + 2 * jnp.tan(an) * (x0 + x2) / (z0 - zr)
    aw = inverse_involute_jnp(jnp.where(inv_w > 0, inv_w, inv(an)))
    a0 = mn * (zr - z0) / 2 * jnp.cos(an) / jnp.cos(aw)
    ra0 = r_f - a0
    rb0 = mn * z0 / 2 * jnp.cos(an)
    rc = ra0 - rho_a0
    tan_p = (jnp.sqrt(jnp.maximum(rc**2 - rb0**2, 0.0)) + rho_a0) / rb0
    psi_b = (jnp.pi / 2 + 2 * x0 * jnp.tan(an)) / z0 + inv(an)
    p = rb0 / jnp.cos(jnp.arctan(tan_p)) * _e(psi_b - (tan_p - jnp.arctan(tan_p)))
    t = rb0 * _e(psi_b - tan_p)
    q0 = p + rho_a0 * (t - p) / (rb0 * tan_p)
    eta = jnp.arctan2(q0[0], q0[1])
    code = jnp.select(  # the first that holds (jaxgear.CutterResult)
        [inv_w <= 0, rc <= rb0, eta < 0, rc <= a0 * z0 / (zr - z0)], [1, 2, 3, 4], 0
    )
    return a0, rc, eta, code


def shaper_cut_section(mn, an, z0, x0, rho_a0, zr, x2, r_f):
    """The 60° (``theta``) root section of an internal gear generated by a pinion-type (shaper)
    cutter, in the plane of the gears (normal section of a helical pair; magnitudes, m).

    The cutter (z0 teeth, profile shift x0, tip rounding ρ_a0, module m_n, pressure angle α_n)
    cuts at the zero-backlash distance of the cutting mesh (inv α_w0 = inv α_n + 2 tan α_n (x0
    + x2)/(z0 − |z2|), a0 = m_n (|z2| − z0)/2 cos α_n/cos α_w0), its tip circle r_a0 = r_f2 − a0
    (the cutter's addendum chosen so that it cuts the ring's root circle ``r_f``; this
    reproduces the KISSsoft reports' root form diameters d_Ff of the NREL rings to 0.001 mm).
    The centre of the tip rounding (tangent to the tip circle and to the cutter's involute, at
    polar angle η_c from the cutter tooth's centre line) moves in the ring's frame on q(ψ) = a0
    e(ψ) + R_c e(η_c + (1 − |z2|/z0) ψ) (ψ the carrier angle of the cutting mesh, the ring
    fixed); the fillet is the envelope of the rounding, q + ρ_a0 n on the side away from the
    cutter's centre. The rounding touches the root circle (its normal along the line of
    centres) at ψ_a = η_c z0/|z2| and generates the fillet toward the flank as ψ decreases
    from there. The section is the point where the fillet's tangent (that of q) makes 60° with
    the centre line of the tooth beside the space (ISO 6336-3, internal gears: 60°): the root
    of that condition nearest below ψ_a, found on a grid of ψ over one cutter pitch below ψ_a
    and refined by bisection, then one Newton step whose derivative is the implicit one
    (differentiable in every argument but the tooth counts).

    Where the cutter cannot generate the fillet up to that section (:func:`_cutter`'s code,
    :class:`jaxgear.CutterResult`) the three values are NaN.

    Returns:
        (s_Fn, ρ_F, r_s): the chord between the two fillets' section points, the fillet's
        radius of curvature there (ρ_a0 plus the radius of curvature of the trochoid q), and
        the radius of the chord's ends (m).
    """
    a0, rc, eta, code = _cutter(mn, an, z0, x0, rho_a0, zr, x2, r_f)
    k = 1 - zr / z0
    u = _e(jnp.pi / zr)  # the centre line of the tooth beside the space centred on +y

    def d1(psi):
        return a0 * _e_prime(psi) + k * rc * _e_prime(eta + k * psi)

    def g(psi):  # cos of the tangent's angle to the centre line, less cos θ
        v = d1(psi)
        return (v @ u) / jnp.linalg.norm(v, axis=-1) - 0.5  # cos 60°

    # the root nearest below ψ_a, where the rounding leaves the root circle
    psi_a = jax.lax.stop_gradient(eta / (1 - k))
    grid = 129
    ps = psi_a - jnp.linspace(2 * jnp.pi / z0, 0.0, grid)
    gs = jax.vmap(g)(ps)
    change = jnp.sign(gs[:-1]) != jnp.sign(gs[1:])
    i = jnp.max(jnp.where(change, jnp.arange(grid - 1), 0))
    lo, hi = jax.lax.stop_gradient(ps[i]), jax.lax.stop_gradient(ps[i + 1])

    def bisect(_, bracket):
        lo, hi, g_lo = bracket
        mid = (lo + hi) / 2
        g_mid = g(mid)
        same = jnp.sign(g_mid) == jnp.sign(g_lo)
        return jnp.where(same, mid, lo), jnp.where(same, hi, mid), jnp.where(same, g_mid, g_lo)

    lo, hi, _ = jax.lax.fori_loop(0, 48, bisect, (lo, hi, jax.lax.stop_gradient(g(lo))))
    psi0 = jax.lax.stop_gradient((lo + hi) / 2)
    psi = psi0 - g(psi0) / jax.grad(g)(psi0)  # value psi0, derivative the implicit one
    q = a0 * _e(psi) + rc * _e(eta + k * psi)
    v1 = d1(psi)
    v2 = -a0 * _e(psi) - k**2 * rc * _e(eta + k * psi)
    tang = v1 / jnp.linalg.norm(v1)
    n = jnp.stack([tang[1], -tang[0]])
    n = n * jnp.sign(n @ (q - a0 * _e(psi)))  # away from the cutter's centre
    pt = q + rho_a0 * n
    r_q = jnp.linalg.norm(v1) ** 3 / jnp.abs(_cross(v1, v2))
    rho_f = jnp.abs(r_q - rho_a0 * jnp.sign(n @ v2))
    s_fn = 2 * jnp.abs(_cross(pt, u))
    bad = (code != 0) | ~jnp.any(change)
    return tuple(jnp.where(bad, jnp.nan, v) for v in (s_fn, rho_f, jnp.linalg.norm(pt)))


class ShaperCutterSection(AbstractRootSection):
    """The internal gear's root section from its generation by a pinion-type (shaper) cutter:
    the fillet as the envelope of the cutter's tip rounding, the critical section where its
    tangent makes 60° with the tooth centre line (ISO 6336-3, internal gears), s_Fn, ρ_F (the
    generated fillet's radius of curvature there) and d_sFn (:func:`shaper_cut_section`; a
    helical ring on its virtual gear in the normal section, the cutter's on z0/(cos² β_b cos
    β)).

    Attributes:
        teeth: z0, the cutter's tooth count (static; 10 < z0 < |z2| − 10).
        profile_shift: x0 of the cutter (default 0).
        tip_radius_coeff: ρ_a0/m_n of the cutter's tip rounding; ``None`` (default) takes the
            ring's basic rack fillet ρ_fP/m_n (the rack the cutter is made to).

    Against the KISSsoft reports of the NREL 5 MW rings (cutter z0 = 30 and 36, x0 = 0, ρ_a0 =
    0.3 m_n): the root form diameters d_Ff of the same cutter within 0.001 mm; s_Fn 1.3 % and
    2.0 % over the printed, d_sFn within 0.01 % and ρ_F 11 % and 39 % under it: KISSsoft's
    printed ρ_F (0.418 and 0.494 m_n) is not the generated fillet's curvature (which is ρ_a0
    plus the trochoid's, 0.371 and 0.302 m_n), nor the rack's ρ_fP; σ_F0 of the rings comes out
    3.6 % and 18 % over the report's (the rack: 20 % and 37 %; docs/rating.md).

    A cutter that cannot generate the ring's fillet up to its 60° section (no cutting mesh, a
    pointed tooth at the tip circle that cuts the root, its rounding's centre below its base
    circle or inside the cutting pitch circle: :func:`shaper_cut_section`) is refused by
    :meth:`check` (called by :meth:`InternalRatingGeometry.of`) in one line; traced, its
    section is NaN and :meth:`result` gives the :class:`jaxgear.CutterResult` code.
    """

    teeth: int = eqx.field(static=True)
    profile_shift: Float[Array, ""]
    tip_radius_coeff: Float[Array, ""] | None

    def __init__(self, teeth: int, profile_shift=0.0, tip_radius_coeff=None):
        w = "ShaperCutterSection"
        check_integer(f"{w}: teeth", teeth, 11)
        check_real("profile_shift", profile_shift, lo=-1.0, hi=1.5, where=w)
        if tip_radius_coeff is not None:
            check_real("tip_radius_coeff", tip_radius_coeff, lo=0.0, hi=0.6, lo_open=True, where=w)
            tip_radius_coeff = as_float(tip_radius_coeff)
        self.teeth = int(teeth)
        self.profile_shift = as_float(profile_shift)
        self.tip_radius_coeff = tip_radius_coeff

    def _arguments(self, geometry, g) -> tuple:
        """The arguments of :func:`shaper_cut_section` for ``geometry`` (the virtual gears)."""
        if abs(geometry.teeth[1]) - self.teeth < 10:
            raise ValueError(
                f"ShaperCutterSection: teeth = {self.teeth} is out of range for the internal "
                f"gear's {abs(geometry.teeth[1])} teeth: allowed 11 <= z0 <= |z2| - 10"
            )
        mn, an, beta = geometry.normal_module, geometry.normal_pressure_angle, geometry.helix_angle
        virtual = jnp.cos(g.base_helix_angle) ** 2 * jnp.cos(beta)
        zr = abs(geometry.teeth[1]) / virtual
        z0 = self.teeth / virtual
        rho = geometry.fillet_radius_coeff[1] if self.tip_radius_coeff is None else (
            self.tip_radius_coeff
        )
        dn = mn * zr
        r_f = (dn + jnp.abs(g.root_diameter[1]) - jnp.abs(g.reference_diameter[1])) / 2
        return (mn, an, z0, self.profile_shift, rho * mn, zr, geometry.profile_shift[1], r_f), dn

    def result(self, geometry) -> Array:
        """Whether this cutter generates ``geometry``'s ring fillet up to its 60° section: an
        integer :class:`jaxgear.CutterResult` code (0: it does; traceable; the limits are
        :func:`shaper_cut_section`'s)."""
        args, _ = self._arguments(geometry, geometry.derived())
        return _cutter(*args)[3]

    def limit(self, geometry) -> tuple | None:
        """``None`` where this cutter generates ``geometry``'s ring fillet up to its 60° section
        (:meth:`result` 0, or ``geometry`` traced); otherwise (name, value, problem, allowed):
        the cutter's parameter to change (``"profile_shift"``; ``"tip_radius_coeff"`` where no
        profile shift in [−1, 1.5] helps; ``"teeth"`` where no tip radius does either), its
        value, the :class:`jaxgear.CutterResult` message, and the range of it that generates
        the fillet with the cutter's other two parameters (sampled: x0 by 0.01, ρ_a0/m_n by
        0.01, z0 by 1)."""
        code = self.result(geometry)
        if is_traced(code) or int(code) == 0:
            return None
        args, _ = self._arguments(geometry, geometry.derived())
        virtual = self.teeth / args[2]  # the real tooth count over the virtual one
        x0, rho = float(args[3]), float(args[4] / args[0])

        def passing(index, values, scale=1.0):
            def code(v):
                return _cutter(*args[:index], v * scale, *args[index + 1:])[3]

            codes = np.asarray(jax.vmap(code)(jnp.asarray(values, dtype=args[0].dtype)))
            return [v for v, c in zip(values, codes) if c == 0]

        name, value, allowed = "profile_shift", x0, _interval(
            passing(3, list(np.round(np.linspace(-1.0, 1.5, 251), 2))), 2)
        if allowed is None:
            name, value, allowed = "tip_radius_coeff", rho, _interval(
                passing(4, list(np.round(np.linspace(0.01, 0.6, 60), 2)), args[0]), 2)
        if allowed is None:
            teeth = [float(z) for z in range(11, abs(geometry.teeth[1]) - 9)]
            zs = passing(2, teeth, 1 / virtual)
            name, value, allowed = "teeth", self.teeth, _interval([round(z) for z in zs], 0)
        allowed = "none for this ring" if allowed is None else allowed
        return name, value, CutterResult(int(code)).message, allowed

    def check(self, geometry) -> None:
        """Refuse, in one ``ValueError`` line, a cutter that cannot generate ``geometry``'s ring
        fillet up to its 60° section (:meth:`limit`): ``ShaperCutterSection: profile_shift =
        -0.1 cannot generate the ring's fillet (z0 = 41, x0 = -0.1, rho_a0/m_n = 0.1): the
        centre of the cutter's tip rounding lies inside ...; allowed [-0.02, 0.80]``. Nothing is
        checked where ``geometry`` is traced."""
        found = self.limit(geometry)
        if found is None:
            return
        name, value, problem, allowed = found
        rho = self.tip_radius_coeff
        rho = float(geometry.fillet_radius_coeff[1] if rho is None else rho)
        raise ValueError(
            f"ShaperCutterSection: {name} = {value:g} cannot generate the ring's fillet "
            f"(z0 = {self.teeth}, x0 = {float(self.profile_shift):g}, rho_a0/m_n = {rho:g}): "
            f"{problem}; allowed {allowed}"
        )

    def section(self, geometry, g):
        args, dn = self._arguments(geometry, g)
        s_fn, rho_f, r_s = shaper_cut_section(*args)
        if not is_traced(s_fn) and not bool(jnp.isfinite(s_fn)):
            self.check(geometry)
        return s_fn, rho_f, 2 * r_s - dn + jnp.abs(g.reference_diameter[1])


def _interval(values, digits) -> str | None:
    """``[lo, hi]`` of the values that pass (rounded inward to ``digits``), ``None`` if none;
    a set with gaps is written as its pieces."""
    if not values:
        return None
    values = sorted(values)
    pieces, start = [], values[0]
    step = min((b - a for a, b in itertools.pairwise(values)), default=1.0)
    for a, b in zip(values, values[1:] + [None]):
        if b is None or b - a > 1.5 * step:
            pieces.append(f"[{start:.{digits}f}, {a:.{digits}f}]")
            start = b
    return " or ".join(pieces)


class InternalRatingGeometry(AbstractRatingGeometry):
    """The continuous macro parameters of an internal pair, as arrays (differentiable): member 0
    the external pinion (planet), member 1 the internal gear (ring); the fields of
    :class:`jaxgear.rating.AbstractRatingGeometry` (``teeth`` (z1, z2) with z2 < 0, x2 in
    ISO 21771's sign) and its root section.

    Attributes:
        root_section: the internal gear's root section (:class:`AbstractRootSection`; default
            :class:`SubstituteRack`).

    Build it from a :class:`jaxgear.InternalGearPair` with :meth:`of`; :func:`jaxgear.rating.rate`
    rates it (module docstring for the internal-gear rules).
    """

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
        geometry = cls(**pair_fields(pair), root_section=root_section)
        root_section.check(geometry)
        return geometry

    def derived(self) -> Derived:
        """ISO 21771 geometry of the internal pair (jnp; the ring's diameters negative, the
        centre distance positive; module docstring)."""
        return pair_derived(self, -1.0)

    # -- what the rating asks of a pair (as jaxgear.rating.RatingGeometry) -------------------------

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
