"""The pair's macro geometry as JAX values, for the load-capacity rating (ISO 6336).

:class:`jaxgear.GearPair` is evaluated once, eagerly, in Python floats (it fixes the shapes of
the mesh model). The rating needs the same quantities as differentiable functions of the
continuous macro parameters (profile shifts, face widths, module, angles), so that S_H and S_F
have gradients: :class:`RatingGeometry` holds those parameters as arrays and recomputes the
ISO 21771 geometry from them with ``jax.numpy`` (:meth:`RatingGeometry.derived`).

Sources: ISO 21771:2007 (involute geometry, profile shift, operating pressure angle (40)), ISO
6336-1:2019 (symbols). SI units; angles in rad.
"""

from __future__ import annotations

import abc
import dataclasses
from typing import NamedTuple

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._geometry import GearPair, inverse_involute, involute
from .._util import as_float, check_instance
from ._bending import ToothFormFactors, member_form

__all__ = ["AbstractRatingGeometry", "RatingGeometry", "TracedTeethRatingGeometry"]


class Derived(NamedTuple):
    """The derived geometry of :meth:`RatingGeometry.derived` (SI, rad; per member (2,))."""

    transverse_module: Array
    transverse_pressure_angle: Array
    operating_pressure_angle: Array
    base_helix_angle: Array
    center_distance: Array
    reference_diameter: Array  # d (2,)
    base_diameter: Array  # d_b (2,)
    tip_diameter: Array  # d_a (2,)
    root_diameter: Array  # d_f (2,)
    transverse_contact_ratio: Array  # ε_α
    overlap_ratio: Array  # ε_β (on the common face width)
    face_width: Array  # b, the common (smaller) face width
    gear_ratio: float  # u = z2 / z1


def pair_fields(pair) -> dict:
    """The rating geometry's parameters of a pair (external or internal: ``pinion``, ``gear``,
    module, angles, centre distance), per-gear values as ``(2,)`` arrays; the centre distance
    kept only when it differs from the zero-backlash distance of the nominal teeth."""
    members = (pair.pinion, pair.gear)
    a0 = pair.zero_backlash_center_distance
    fixed = abs(pair.center_distance - a0) > 1e-12 * a0

    def two(name):
        return as_float([getattr(m, name) for m in members])

    return dict(
        teeth=(int(pair.pinion.teeth), int(pair.gear.teeth)),
        normal_module=as_float(pair.normal_module),
        normal_pressure_angle=as_float(pair.normal_pressure_angle),
        helix_angle=as_float(pair.helix_angle),
        profile_shift=two("profile_shift"),
        addendum_coeff=two("addendum_coeff"),
        dedendum_coeff=two("dedendum_coeff"),
        fillet_radius_coeff=two("fillet_radius_coeff"),
        face_width=two("face_width"),
        rim_thickness=tuple(m.rim_thickness for m in members),
        center_distance=as_float(pair.center_distance) if fixed else None,
    )


def replace_fields(geometry, changes: dict):
    """``geometry`` (an equinox module) with the array fields ``changes`` replaced."""
    out = geometry
    for name, value in changes.items():
        out = eqx.tree_at(lambda g, n=name: getattr(g, n), out, as_float(value))
    return out


class AbstractRatingGeometry(eqx.Module):
    """The continuous macro parameters of a pair as the rating reads them, as arrays
    (differentiable): one geometry whose kinds are the external pair
    (:class:`RatingGeometry`) and the internal pair (:class:`jaxgear.rating.InternalRatingGeometry`:
    member 1 the internal gear). The fields and the ISO 21771 geometry are the kinds' common
    part (:func:`pair_derived`, which each kind's :meth:`derived` calls with its sign: +1
    external, -1 internal, the ring's tooth count and diameters negative); each kind answers
    what the rating asks of a pair by its own rules (:meth:`form_factors`, :meth:`single_pair_factors`,
    :meth:`stiffness_teeth`, :meth:`reduced_mass`).

    Attributes:
        teeth: (z1, z2), static (an internal gear's z2 < 0, ISO 21771).
        normal_module: m_n (m). normal_pressure_angle: α_n (rad). helix_angle: β (rad).
        profile_shift: (x1, x2). addendum_coeff, dedendum_coeff: (h_a*, h_f*) per member (the
            dedendum coefficient is the generating rack's addendum h_fP/m_n).
        fillet_radius_coeff: ρ_fP/m_n per member (the rack's tip radius).
        face_width: (b1, b2) (m).
        rim_thickness: (s_R1, s_R2) (m) below the root circle, or ``None`` per member (solid
            blank; static).
        center_distance: a_w (m), or ``None``: the zero-backlash distance of the profile shifts
            (ISO 21771 (40)), which then moves with them.
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

    def replace(self, **changes):
        """A copy with some array fields replaced (``profile_shift=...``, ``face_width=...``).
        Nothing is checked here (values may be traced): keep them a valid pair (no undercut,
        no jam at a fixed centre distance), as :class:`jaxgear.GearPair` would check."""
        return replace_fields(self, changes)

    # -- what the rating asks of a pair, by the kind's rules ------------------------------

    @abc.abstractmethod
    def derived(self) -> Derived:
        """ISO 21771 geometry of the pair from the parameters (jnp; :func:`pair_derived`)."""

    @abc.abstractmethod
    def form_factors(self) -> ToothFormFactors:
        """Y_F, Y_S and the root sections of both members (ISO 6336-3 method B)."""

    @abc.abstractmethod
    def single_pair_factors(self, g: Derived) -> Array:
        """Z_B, Z_D (ISO 6336-2, single pair tooth contact factors), (2,)."""

    @abc.abstractmethod
    def stiffness_teeth(self, g: Derived) -> Array:
        """The virtual teeth (z_n1, z_n2) of ISO 6336-1 method B's single stiffness c'."""

    @abc.abstractmethod
    def reduced_mass(self, m_star: Array) -> Array:
        """ISO 6336-1 method B's reduced mass per face width (kg/m) from the members'
        m* = π/8 ρ d_m⁴/d_b²."""


class RatingGeometry(AbstractRatingGeometry):
    """The continuous macro parameters of an external pair, as arrays (differentiable): the
    fields of :class:`AbstractRatingGeometry`.

    Build it from a :class:`jaxgear.GearPair` with :meth:`of` (a pair built without a centre
    distance gives ``None`` here); :func:`eqx.tree_at` or :meth:`replace` change a parameter,
    e.g. for a gradient with respect to x1.
    """

    @classmethod
    def of(cls, pair: GearPair) -> RatingGeometry:
        """The parameters of ``pair`` (its centre distance kept only when it differs from the
        zero-backlash distance of the nominal teeth)."""
        check_instance("pair", pair, GearPair, "a jaxgear.GearPair", "RatingGeometry.of")
        return cls(**pair_fields(pair))

    def derived(self) -> Derived:
        """ISO 21771 geometry of the pair from the parameters (jnp; module docstring)."""
        return pair_derived(self, 1.0)

    def form_factors(self) -> ToothFormFactors:
        """Y_F, Y_S and the root sections of both members (:func:`jaxgear.rating.tooth_form_factors`)."""
        g = self.derived()
        z = jnp.asarray(self.teeth, dtype=self.normal_module.dtype)
        mn = self.normal_module
        return member_form(
            mn,
            self.normal_pressure_angle,
            self.helix_angle,
            g.base_helix_angle,
            z,
            self.profile_shift,
            (self.dedendum_coeff * mn, self.fillet_radius_coeff * mn),
            (g.reference_diameter, g.tip_diameter),
            g.transverse_contact_ratio,
        )

    def single_pair_factors(self, g: Derived) -> Array:
        """Z_B, Z_D (ISO 6336-2, single pair tooth contact factors): M₁, M₂ at the inner points
        of single pair contact; spur max(1, M), helical ε_β < 1 max(1, M − ε_β (M − 1)),
        ε_β >= 1: 1."""
        z = jnp.asarray(self.teeth, dtype=g.center_distance.dtype)
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

    def stiffness_teeth(self, g: Derived) -> Array:
        """The virtual teeth (z_n1, z_n2) of ISO 6336-1 method B's single stiffness c'."""
        z = jnp.asarray(self.teeth, dtype=g.center_distance.dtype)
        return z / (jnp.cos(g.base_helix_angle) ** 2 * jnp.cos(self.helix_angle))

    def reduced_mass(self, m_star: Array) -> Array:
        """ISO 6336-1 method B's reduced mass per face width of the pair from the members'
        m* = π/8 ρ d_m⁴/d_b² (kg/m): m*₁ m*₂/(m*₁ + m*₂)."""
        return m_star[0] * m_star[1] / (m_star[0] + m_star[1])


class TracedTeethRatingGeometry(RatingGeometry):
    """An external pair's rating geometry whose tooth counts are an array leaf, ``teeth``
    (z1, z2) as floats of shape (2,), instead of :class:`RatingGeometry`'s static integers: the
    same fields and formulas otherwise, so that :func:`jax.vmap` maps :func:`jaxgear.rating.rate`
    over candidates of different tooth counts and one compiled program rates them all (the
    static counts compile one program per pair). The counts are whole numbers still (the
    formulas are ISO's for integer teeth); nothing here checks them (they may be traced): build
    each candidate from a valid pair, as :class:`jaxgear.GearPair` would check it. Its rating
    equals :class:`RatingGeometry`'s of the same pair to round-off (XLA folds the static counts
    into constants, which may move the last bits).

    :meth:`of` builds it from a :class:`jaxgear.GearPair`; :meth:`of_geometry` from a
    :class:`RatingGeometry`. A gradient of the rating with respect to the geometry then has a
    (meaningless) component for ``teeth``: differentiate with respect to the other fields.
    """

    teeth: Float[Array, 2]

    def __check_init__(self):
        """``teeth`` of shape (2,) (one line naming it); its values are not checked."""
        shape = jnp.shape(self.teeth)
        if shape != (2,):
            raise ValueError(
                f"TracedTeethRatingGeometry: teeth of shape {shape} is out of range: allowed "
                "(2,), the tooth counts (z1, z2)"
            )

    @classmethod
    def of(cls, pair: GearPair) -> TracedTeethRatingGeometry:
        """The parameters of ``pair`` (as :meth:`RatingGeometry.of`), its teeth an array."""
        check_instance("pair", pair, GearPair, "a jaxgear.GearPair", "TracedTeethRatingGeometry.of")
        return cls.of_geometry(RatingGeometry.of(pair))

    @classmethod
    def of_geometry(cls, geometry: RatingGeometry) -> TracedTeethRatingGeometry:
        """``geometry``'s fields with its tooth counts as a float array (2,)."""
        check_instance("geometry", geometry, RatingGeometry, "a jaxgear.rating.RatingGeometry",
                       "TracedTeethRatingGeometry.of_geometry")
        fields = {f.name: getattr(geometry, f.name) for f in dataclasses.fields(geometry)}
        return cls(**(fields | {"teeth": as_float(fields["teeth"])}))


def pair_derived(p, sign: float) -> Derived:
    """ISO 21771 geometry of a pair of :class:`RatingGeometry`'s fields (jnp): ``sign`` +1 for
    an external pair, -1 for an internal one (the ring's tooth count and diameters negative,
    the centre distance positive: a_w = s (d₁ + d₂) cos α_t / (2 cos α_wt),
    g_α = ρ_a1 + s ρ_a2 − s a_w sin α_wt)."""
    z = jnp.asarray(p.teeth, dtype=p.normal_module.dtype)
    mn, an, beta = p.normal_module, p.normal_pressure_angle, p.helix_angle
    x = p.profile_shift
    mt = mn / jnp.cos(beta)
    at = jnp.arctan(jnp.tan(an) / jnp.cos(beta))
    d = z * mt
    db = d * jnp.cos(at)
    da = d + 2 * mn * (p.addendum_coeff + x)
    df = d - 2 * mn * (p.dedendum_coeff - x)
    if p.center_distance is None:
        inv_awt = involute(at) + 2 * jnp.tan(an) * (x[0] + x[1]) / (z[0] + z[1])
        awt = inverse_involute(inv_awt)
        a = sign * (d[0] + d[1]) / 2 * jnp.cos(at) / jnp.cos(awt)
    else:
        a = p.center_distance
        awt = jnp.arccos(sign * (db[0] + db[1]) / (2 * a))
    roll_tip = jnp.sqrt(da**2 / 4 - db**2 / 4)
    g_alpha = roll_tip[0] + sign * roll_tip[1] - sign * a * jnp.sin(awt)
    eps_a = g_alpha / (jnp.pi * mt * jnp.cos(at))
    b = jnp.minimum(p.face_width[0], p.face_width[1])
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
        gear_ratio=p.teeth[1] / p.teeth[0],
    )
