"""The bearing kinds behind one contract (:class:`AbstractRollingBearing`).

A kind is a class passed as an object: a deep groove ball bearing, an angular contact ball
bearing, a cylindrical and a tapered roller bearing, a spherical roller bearing, a pair of tapered
roller bearings facing both ways (one bearing node: :class:`TaperedRollerPair`), each built from its catalogue geometry in
SI (m, rad, N), and the linear spring the scenes use today (:class:`LinearSpring`: ``radial``,
``axial``, ``tilt`` stiffnesses, the names of :class:`jaxgear.scenes.Bearing`). What a kind
supports is declared on the contract as class variables (rolling elements, the Hertz exponent,
which way it carries an axial load, the ISO 281 life exponent), never probed.

Coordinates: the shaft axis is z; the inner ring's displacement relative to the outer ring is
d = (δ_x, δ_y, δ_z, γ_x, γ_y) (m, m, m, rad, rad), γ_x and γ_y right-handed rotations about x and
y (the scenes' φ_x, φ_y: du_y/dz = −φ_x, du_x/dz = φ_y). Element j sits at the azimuth
ψ_j = 2π j / Z from +x towards +y. The bearing's load vector f = (F_x, F_y, F_z, M_x, M_y) (N,
N·m) is the force and moment the inner ring passes to the outer ring, equal to the external load
on the shaft at equilibrium: positive along d, so that K = ∂f/∂d is positive semi-definite.
"""

from __future__ import annotations

import abc
import dataclasses
import math
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._util import as_float, check_integer, check_real
from ._hertz import line_contact_constant, line_pressure, point_contact, point_contact_constant

__all__ = [
    "AbstractRollingBearing",
    "AngularContactBall",
    "CylindricalRoller",
    "DeepGrooveBall",
    "LinearSpring",
    "SphericalRoller",
    "TaperedRoller",
    "TaperedRollerPair",
]

#: steel (Harris & Kotzalas's bearing steel): Young's modulus (Pa) and Poisson's ratio
STEEL_E, STEEL_NU = 2.075e11, 0.3


@eqx.filter_jit
def _jacobian(bearing, d):
    """∂f/∂d of ``bearing.load`` at d, compiled once per kind and element count."""
    return jax.jacfwd(bearing.load)(d)


@eqx.filter_jit
def _stiffness6(bearing, d):
    """:meth:`AbstractRollingBearing.stiffness6` at d, compiled once per kind and count."""
    k = jax.jacfwd(bearing.load)(d)
    k = 0.5 * (k + k.T)
    return jnp.zeros((6, 6), k.dtype).at[:5, :5].set(k)


def _contact_power(delta, n):
    """max(δ, 0)^n with every derivative finite (0 where δ <= 0: an element out of contact
    has no load, stiffness or derivative of them; the double ``where`` keeps δ^(n − k) of a
    negative δ out of the derivatives)."""
    touching = delta > 0
    return jnp.where(touching, jnp.where(touching, delta, 1.0) ** n, 0.0)


def _optional(value):
    """A rating: ``None`` kept, a number as an array leaf."""
    return None if value is None else as_float(value)


def _real(default=None):
    """A real field stored as an array leaf (traced by ``jit``, not a static value that would
    compile a program per bearing); ``default`` if given."""
    if default is None:
        return eqx.field(converter=as_float)
    return eqx.field(converter=as_float, default=default)


class AbstractRollingBearing(eqx.Module):
    """A bearing kind: the load its rings pass for a displacement, and what it supports.

    Class variables (the contract's declarations):

    - ``rolling_elements``: the kind has rolling elements (element loads, Hertz contact,
      tones, ISO 281 life); :class:`LinearSpring` does not.
    - ``contact_exponent``: n of Q = K_n δ^n (3/2 point contact, 10/9 line contact, 1 a spring).
    - ``axial_load``: which axial load it carries: ``"both"`` ways, ``"positive"`` (single-row
      angular contact and tapered: +z pushes the inner ring onto its raceway) or ``"none"``
      (a cylindrical roller bearing without ribs, NU).
    - ``life_exponent``: p of ISO 281's L10 = (C/P)^p (3 balls, 10/3 rollers), ``None`` where
      the kind has no rating life.
    - ``self_aligning``: the outer raceway is a sphere about the bearing's centre (a spherical
      roller bearing): the rings tilt freely, no moment and no tilt stiffness (γ_x, γ_y not
      carried).
    - ``clearance_field``: the name of the kind's own field (m) that a bearing's clearance
      variable sets (``optimise``'s ``<shaft>.bearings[<k>].clearance``, written back as
      ``<field>_um`` in a case file; :meth:`with_clearance` sets it): ``"clearance"``, the
      diametral clearance P_d (negative: a radial preload), for the kinds with rolling
      elements; ``"end_play"`` for :class:`TaperedRollerPair` (its axial end play e stands in
      for the rows' clearance, P_d = e tan α; negative: an axial preload); ``None`` for
      :class:`LinearSpring` (no clearance).
    - ``rows``: the rows of rolling elements i (ISO 281's i): 2 for :class:`SphericalRoller`
      and :class:`TaperedRollerPair`, 1 otherwise.
    - ``crown_field``: the name of the kind's own field that holds its rollers' logarithmic
      crown, ``"crown"`` (m, 0 <= c <= D_w/100, or None: straight), or None where the kind
      takes none (as ``clearance_field`` names the clearance's field; the roller kinds sliced along their length:
      :class:`CylindricalRoller`, :class:`TaperedRoller`, :class:`TaperedRollerPair`); not the
      ball kinds, nor :class:`SphericalRoller` (one line per roller: no slice to unload).
    - ``carries_moment``: the kind holds a shaft against tilting on its own (one bearing node
      that carries a moment from the start: :class:`TaperedRollerPair`, its rows' pressure
      centres apart; :class:`LinearSpring`, its ``tilt`` spring where > 0), so that a shaft
      may stand on it alone. Not the single-row kinds, whose tilt stiffness comes from their
      load only (a shaft needs two of them apart), nor a self-aligning one (no moment).

    Methods: :meth:`load` (abstract; f(d), shape (5,)), :meth:`potential` (U(d), J, with
    f = ∇U), :meth:`stiffness` (K = ∂f/∂d by ``jax.jacfwd``, (5, 5)), :meth:`stiffness6` (the
    6×6 of a :class:`jaxgear.scenes.Bearing` ``stiffness``), :meth:`carried` (the DOFs it
    resists), :meth:`element_loads`, :meth:`contact_pressure` and :meth:`equivalent_load`
    (refused where not declared).
    """

    rolling_elements: ClassVar[bool] = True
    contact_exponent: ClassVar[float] = 1.5
    axial_load: ClassVar[str] = "both"
    life_exponent: ClassVar[float | None] = None
    self_aligning: ClassVar[bool] = False
    clearance_field: ClassVar[str | None] = "clearance"
    rows: ClassVar[int] = 1
    crown_field: ClassVar[str | None] = None
    carries_moment: ClassVar[bool] = False

    @abc.abstractmethod
    def load(self, displacement) -> Float[Array, " 5"]:
        """f = (F_x, F_y, F_z, M_x, M_y) (N, N·m) at the ring displacement d, shape (5,)."""

    @abc.abstractmethod
    def potential(self, displacement) -> Float[Array, ""]:
        """The elastic energy U(d) (J) stored in the contacts; :meth:`load` is its gradient."""

    def stiffness(self, displacement) -> Float[Array, "5 5"]:
        """K = ∂f/∂d (N/m, N/rad, N·m/rad) at the operating point d (``jax.jacfwd`` of
        :meth:`load`), shape (5, 5), symmetric (f is the gradient of :meth:`potential`)."""
        return _jacobian(self, jnp.asarray(displacement, dtype=float))

    def stiffness6(self, displacement) -> Float[Array, "6 6"]:
        """The stiffness at d as the 6×6 matrix a :class:`jaxgear.scenes.Bearing` takes
        (DOFs u_x, u_y, u_z, φ_x, φ_y, φ_z; row and column φ_z zero), symmetrised."""
        return _stiffness6(self, jnp.asarray(displacement, dtype=float))

    def with_clearance(self, value) -> AbstractRollingBearing:
        """The kind with its :attr:`clearance_field` set to ``value`` (m) and checked as its
        constructor checks it.

        Raises:
            ValueError: ``value`` outside the kind's range (its constructor's line), a kind
                without a clearance field (:class:`LinearSpring`)."""
        if self.clearance_field is None:
            raise ValueError(f"{type(self).__name__} has no clearance: allowed a rolling bearing "
                             "kind with rolling elements")
        return dataclasses.replace(self, **{self.clearance_field: value})

    def carried(self) -> tuple[bool, ...]:
        """Which of the five DOFs the bearing resists (a DOF it does not is left at 0 by
        :func:`~jaxgear.bearings.solve_displacement`): all but u_z where ``axial_load``
        is ``"none"`` and but the tilts where the kind is ``self_aligning``."""
        tilt = not self.self_aligning
        return (True, True, self.axial_load != "none", tilt, tilt)

    def element_loads(self, displacement) -> Array:
        """Each rolling element's normal load Q_j (N) at d: (Z,) for balls, (Z, slices) for
        the slices of rollers. Refused by a kind without rolling elements."""
        raise ValueError(
            f"{type(self).__name__} has no rolling elements: allowed a rolling bearing kind "
            "(DeepGrooveBall, AngularContactBall, CylindricalRoller, TaperedRoller, "
            "SphericalRoller, TaperedRollerPair)"
        )

    def contact_pressure(self, displacement) -> Array:
        """The largest Hertz contact pressure p_max (Pa) of each element's inner and outer
        contact at d: (Z, 2) for balls, (Z, slices, 2) for the slices of rollers. Refused by a
        kind without rolling elements."""
        raise ValueError(
            f"{type(self).__name__} has no rolling elements: allowed a rolling bearing kind "
            "(DeepGrooveBall, AngularContactBall, CylindricalRoller, TaperedRoller, "
            "SphericalRoller, TaperedRollerPair)"
        )

    def equivalent_load(self, radial, axial) -> Array:
        """ISO 281's equivalent dynamic load P (N) for a radial load F_r and an axial load F_a
        (N). Refused by a kind without a rating life."""
        raise ValueError(
            f"{type(self).__name__} has no ISO 281 rating life: allowed a rolling bearing kind"
        )


class LinearSpring(AbstractRollingBearing):
    """The linear spring bearing (the scenes' bearing today): f = diag(k_r, k_r, k_a, k_t,
    k_t) d.

    Attributes:
        radial: stiffness on δ_x and δ_y (N/m, >= 0); default 2e8.
        axial: stiffness on δ_z (N/m, >= 0); default 1e8.
        tilt: stiffness on γ_x and γ_y (N·m/rad, >= 0); default 0.

    Raises:
        ValueError: a stiffness negative or not finite (one line naming it).
    """

    radial: float = 2e8
    axial: float = 1e8
    tilt: float = 0.0

    rolling_elements: ClassVar[bool] = False
    clearance_field: ClassVar[str | None] = None
    contact_exponent: ClassVar[float] = 1.0
    axial_load: ClassVar[str] = "both"
    life_exponent: ClassVar[float | None] = None
    carries_moment: ClassVar[bool] = True

    def __init__(self, radial=2e8, axial=1e8, tilt=0.0):
        for name, value, unit in (("radial", radial, "N/m"), ("axial", axial, "N/m"),
                                  ("tilt", tilt, "N·m/rad")):
            check_real(name, value, unit, lo=0.0, where="LinearSpring")
        self.radial, self.axial, self.tilt = as_float(radial), as_float(axial), as_float(tilt)

    def _diagonal(self):
        k_r, k_a, k_t = self.radial, self.axial, self.tilt
        return jnp.stack(jnp.broadcast_arrays(*map(jnp.asarray, (k_r, k_r, k_a, k_t, k_t))))

    def load(self, displacement):
        return self._diagonal() * jnp.asarray(displacement)

    def potential(self, displacement):
        d = jnp.asarray(displacement)
        return 0.5 * jnp.sum(self._diagonal() * d**2)

    def carried(self):
        k = np.asarray([self.radial, self.radial, self.axial, self.tilt, self.tilt])
        return tuple(bool(x > 0) for x in k)


def _check_rating(where, dynamic_rating, static_rating, fatigue_limit=None):
    for name, value in (("dynamic_rating", dynamic_rating), ("static_rating", static_rating)):
        if value is not None:
            check_real(name, value, "N", lo=0.0, lo_open=True, where=where)
    if fatigue_limit is not None:  # C_u: the load of ISO 281's fatigue stress, below C₀'s
        top = None if static_rating is None else float(static_rating)
        check_real("fatigue_limit", fatigue_limit, "N", lo=0.0, lo_open=True, hi=top,
                   hi_open=True, where=where if top is None else
                   f"{where} (the fatigue load limit C_u, below static_rating C0)")


def _check_ring(where, bore, outer_diameter, width, elements, element_diameter, pitch_diameter,
                word):
    """The boundary and element geometry common to every rolling kind (one line each)."""
    check_real("bore", bore, "m", lo=0.0, lo_open=True, where=where)
    check_real("outer_diameter", outer_diameter, "m", lo=float(bore), lo_open=True,
               where=where)
    check_real("width", width, "m", lo=0.0, lo_open=True, where=where)
    section = 0.5 * (float(outer_diameter) - float(bore))
    check_real("element_diameter", element_diameter, "m", lo=0.0, hi=section, lo_open=True,
               hi_open=True, where=f"{where} ({word} inside the ring section "
               f"(outer_diameter - bore)/2 = {section:.6g} m)")
    D = float(element_diameter)
    check_real("pitch_diameter", pitch_diameter, "m", lo=float(bore) + D,
               hi=float(outer_diameter) - D, lo_open=True, hi_open=True,
               where=f"{where} (the {word}s between bore + element_diameter and "
               "outer_diameter - element_diameter)")
    check_integer(f"{where}: elements", elements, 3)
    most = int(math.pi * float(pitch_diameter) / D)
    if elements > most:
        raise ValueError(
            f"{where}: elements = {elements} do not fit on the pitch circle: allowed <= "
            f"pi pitch_diameter / element_diameter = {most}"
        )


class _RollingElements(AbstractRollingBearing):
    """The kinds with rolling elements (balls and rollers): ``elements`` of them, element j at
    the azimuth ψ_j = 2π j / Z (:attr:`azimuths`), at a contact angle :attr:`nominal_angle`."""

    elements: eqx.AbstractVar[int]

    @property
    @abc.abstractmethod
    def nominal_angle(self):
        """The contact angle (rad) the Hertz constant, pressures and tones take: a ball's α₀
        at which it first touches both raceways, a roller's fixed α."""

    @property
    def azimuths(self):
        """ψ_j = 2π j / Z (rad), (Z,)."""
        return 2.0 * jnp.pi * jnp.arange(self.elements) / self.elements


class _Ball(_RollingElements):
    """Ball kinds: point contact, the contact angle following the load (Jones; Harris &
    Kotzalas ch. 7): the inner and outer groove curvature centres are A = (f_i + f_o − 1) D
    apart when a ball just touches, at the free contact angle α₀ with the rings centred less
    half the diametral clearance P_d radially::

        a_r,j = A cos α₀ − P_d/2 + δ_x cos ψ_j + δ_y sin ψ_j
        a_z,j = A sin α₀ + δ_z + r_p (γ_x sin ψ_j − γ_y cos ψ_j)        (r_p = d_m / 2)
        δ_j = |a_j| − A,   Q_j = K_n max(δ_j, 0)^(3/2),   (cos α_j, sin α_j) = a_j / |a_j|

    and f = Σ Q_j (cos α_j cos ψ_j, cos α_j sin ψ_j, sin α_j, r_p sin α_j sin ψ_j,
    −r_p sin α_j cos ψ_j) (Lim & Singh, J. Sound Vib. 139 (1990) 179–199, Part I, with the
    ball's contact angle of Jones and Harris).
    """

    bore: float = _real()
    outer_diameter: float = _real()
    width: float = _real()
    elements: int = eqx.field(static=True)
    element_diameter: float = _real()
    pitch_diameter: float = _real()
    clearance: float = _real(0.0)
    inner_conformity: float = _real(0.52)
    outer_conformity: float = _real(0.52)
    youngs_modulus: float = _real(STEEL_E)
    poisson_ratio: float = _real(STEEL_NU)
    dynamic_rating: float | None = eqx.field(default=None, converter=_optional)
    static_rating: float | None = eqx.field(default=None, converter=_optional)
    fatigue_limit: float | None = eqx.field(default=None, converter=_optional)

    contact_exponent: ClassVar[float] = 1.5
    life_exponent: ClassVar[float | None] = 3.0

    def _check_ball(self, where):
        _check_ring(where, self.bore, self.outer_diameter, self.width, self.elements,
                    self.element_diameter, self.pitch_diameter, "ball")
        for name in ("inner_conformity", "outer_conformity"):
            check_real(name, getattr(self, name), "", lo=0.5, hi=0.6, lo_open=True,
                       where=f"{where} (groove radius / ball diameter)")
        check_real("youngs_modulus", self.youngs_modulus, "Pa", lo=0.0, lo_open=True,
                   where=where)
        check_real("poisson_ratio", self.poisson_ratio, "", lo=0.0, hi=0.5, hi_open=True,
                   where=where)
        _check_rating(where, self.dynamic_rating, self.static_rating, self.fatigue_limit)

    @property
    def curvature_distance(self):
        """A = (f_i + f_o − 1) D (m): the groove curvature centres' distance at first touch."""
        return (self.inner_conformity + self.outer_conformity - 1.0) * self.element_diameter

    @property
    def hertz_constant(self):
        """K_n (N/m^1.5) of one ball between its raceways at the nominal contact angle
        (:func:`~jaxgear.bearings.point_contact_constant`)."""
        return point_contact_constant(
            self.element_diameter, self.pitch_diameter, self.nominal_angle,
            self.inner_conformity, self.outer_conformity, self.youngs_modulus,
            self.poisson_ratio,
        )

    def _contacts(self, displacement):
        """(δ_j, cos α_j, sin α_j), each (Z,)."""
        d = jnp.asarray(displacement)
        psi = self.azimuths
        c, s = jnp.cos(psi), jnp.sin(psi)
        A, a0, rp = self.curvature_distance, self.nominal_angle, 0.5 * self.pitch_diameter
        ar = A * jnp.cos(a0) - 0.5 * self.clearance + d[0] * c + d[1] * s
        az = A * jnp.sin(a0) + d[2] + rp * (d[3] * s - d[4] * c)
        length = jnp.sqrt(ar**2 + az**2)
        return length - A, ar / length, az / length

    def element_loads(self, displacement):
        delta = self._contacts(displacement)[0]
        return self.hertz_constant * _contact_power(delta, 1.5)

    def contact_pressure(self, displacement):
        """p_max = 3Q / (2π a b) of each ball's inner and outer contact (Pa), (Z, 2), with
        a = (6 κ² ℰ Q R / (π E'))^(1/3), b = (6 ℰ Q R / (π κ E'))^(1/3) (Harris & Kotzalas;
        Brewe & Hamrock's κ, ℰ) at the nominal contact angle."""
        Q = self.element_loads(displacement)
        Ep = self.youngs_modulus / (1.0 - self.poisson_ratio**2)
        out = []
        for f, inner in ((self.inner_conformity, True), (self.outer_conformity, False)):
            _, kappa, E2, _, R = point_contact(self.element_diameter, self.pitch_diameter,
                                               self.nominal_angle, f, self.youngs_modulus,
                                               self.poisson_ratio, inner)
            a = (6.0 * kappa**2 * E2 * Q * R / (jnp.pi * Ep)) ** (1.0 / 3.0)
            b = (6.0 * E2 * Q * R / (jnp.pi * kappa * Ep)) ** (1.0 / 3.0)
            out.append(jnp.where(Q > 0, 1.5 * Q / (jnp.pi * jnp.where(Q > 0, a * b, 1.0)), 0.0))
        return jnp.stack(out, axis=-1)

    def load(self, displacement):
        delta, ca, sa = self._contacts(displacement)
        Q = self.hertz_constant * _contact_power(delta, 1.5)
        psi = self.azimuths
        c, s, rp = jnp.cos(psi), jnp.sin(psi), 0.5 * self.pitch_diameter
        rows = jnp.stack([ca * c, ca * s, sa, rp * sa * s, -rp * sa * c])
        return rows @ Q

    def potential(self, displacement):
        delta = self._contacts(displacement)[0]
        return self.hertz_constant / 2.5 * jnp.sum(_contact_power(delta, 2.5))


class DeepGrooveBall(_Ball):
    """A single-row deep groove ball bearing: nominal contact angle 0, an axial load taken up
    at the free contact angle of its clearance, cos α₀ = 1 − P_d / (2A) (Harris & Kotzalas),
    and beyond as the load turns the contact.

    Attributes:
        bore, outer_diameter, width: boundary dimensions d, D, B (m).
        elements: the number of balls Z (int >= 3, Z D < π d_m).
        element_diameter: the ball diameter D_w (m), inside the ring section (D − d)/2.
        pitch_diameter: d_m (m), between d + D_w and D − D_w.
        clearance: the diametral (radial internal) clearance P_d (m), 0 <= P_d < 2A (above, a
            ball could never touch both grooves); a negative value down to −D_w/100 is a
            radial preload (interference).
        inner_conformity, outer_conformity: f_i, f_o = groove radius / D_w, in (0.5, 0.6]
            (default 0.52: typical, catalogues do not state them; Harris & Kotzalas).
        youngs_modulus, poisson_ratio: the balls' and rings' material (Pa, -); steel default.
        dynamic_rating, static_rating: C and C₀ (N), for the ISO 281 life; ``None`` if not given.
        fatigue_limit: the maker's fatigue load limit C_u (N, 0 < C_u < C₀) for ISO 281's a_ISO;
            ``None``: ISO 281's estimate from C₀ (:func:`~jaxgear.bearings.fatigue_load_limit`).
        iso281_f0: ISO 281's factor f₀ (catalogue) for the table of X and Y; ``None``: not given.

    Raises:
        ValueError: any argument out of its range, in one line naming it, its value and the
            allowed range (a ball larger than the ring section, a clearance larger than the
            ball, too many balls for the pitch circle, ...).
    """

    iso281_f0: float | None = eqx.field(default=None, converter=_optional)

    axial_load: ClassVar[str] = "both"

    def __check_init__(self):
        w = "DeepGrooveBall"
        self._check_ball(w)
        A = float(self.curvature_distance)
        check_real("clearance", self.clearance, "m", lo=-0.01 * float(self.element_diameter),
                   hi=min(float(self.element_diameter), 2.0 * A), hi_open=True,
                   where=f"{w} (diametral clearance; below the ball diameter and 2A = "
                   f"2 (f_i + f_o - 1) D_w)")
        if self.iso281_f0 is not None:
            check_real("iso281_f0", self.iso281_f0, "", lo=0.0, lo_open=True, where=w)

    @property
    def nominal_angle(self):
        """0: a deep groove bearing's contact angle under a radial load (its Hertz constant,
        pressures and tones are taken there)."""
        return 0.0

    @property
    def free_contact_angle(self):
        """α₀ = arccos(1 − P_d / (2A)) (rad): the contact angle at which an axial shift takes up
        the clearance (Harris & Kotzalas), 0 without clearance."""
        A = self.curvature_distance
        return jnp.arccos(1.0 - jnp.maximum(self.clearance, 0.0) / (2.0 * A))

    def _contacts(self, displacement):
        # the clearance is already in the free angle's geometry: A cos α₀ = A − P_d/2
        d = jnp.asarray(displacement)
        psi = self.azimuths
        c, s = jnp.cos(psi), jnp.sin(psi)
        A, rp = self.curvature_distance, 0.5 * self.pitch_diameter
        ar = A - 0.5 * self.clearance + d[0] * c + d[1] * s
        az = d[2] + rp * (d[3] * s - d[4] * c)
        length = jnp.sqrt(ar**2 + az**2)
        return length - A, ar / length, az / length

    @property
    def hertz_constant(self):
        return point_contact_constant(
            self.element_diameter, self.pitch_diameter, 0.0, self.inner_conformity,
            self.outer_conformity, self.youngs_modulus, self.poisson_ratio,
        )

    def equivalent_load(self, radial, axial):
        """ISO 281:2007 Table 3, single-row radial ball bearing (normal clearance): e and Y
        interpolated linearly in f₀ F_a / C₀; P = F_r for F_a/F_r <= e, else 0.56 F_r + Y F_a.

        Raises:
            ValueError: ``static_rating`` or ``iso281_f0`` not given (one line)."""
        if self.static_rating is None or self.iso281_f0 is None:
            raise ValueError(
                "DeepGrooveBall.equivalent_load: static_rating and iso281_f0 = None: allowed "
                "both given (C0 in N and f0 from the catalogue: ISO 281's X, Y table)"
            )
        Fr, Fa = jnp.asarray(radial, float), jnp.asarray(axial, float)
        x = self.iso281_f0 * jnp.abs(Fa) / self.static_rating
        xp, ep, yp = (jnp.asarray(v) for v in ISO281_BALL)
        e = jnp.interp(x, xp, ep)
        Y = jnp.interp(x, xp, yp)
        heavy = jnp.abs(Fa) > e * Fr
        return jnp.where(heavy, 0.56 * Fr + Y * jnp.abs(Fa), Fr)


#: ISO 281:2007 Table 3, single-row radial ball bearings, normal clearance: f₀ F_a / C₀, e, Y
#: (X = 0.56 where F_a / F_r > e); beyond the ends the end values
ISO281_BALL = (
    (0.172, 0.345, 0.689, 1.03, 1.38, 2.07, 3.45, 5.17, 6.89),
    (0.19, 0.22, 0.26, 0.28, 0.30, 0.34, 0.38, 0.42, 0.44),
    (2.30, 1.99, 1.71, 1.55, 1.45, 1.31, 1.15, 1.04, 1.00),
)
#: ISO 281:2007 Table 3, single-row angular contact ball bearings: α (deg) -> (e, X, Y) for
#: F_a / F_r > e (X = 1, Y = 0 below)
ISO281_ANGULAR = {
    25: (0.68, 0.41, 0.87),
    30: (0.80, 0.39, 0.76),
    35: (0.95, 0.37, 0.66),
    40: (1.14, 0.35, 0.57),
    45: (1.34, 0.33, 0.50),
}


class AngularContactBall(_Ball):
    """A single-row angular contact ball bearing: carries an axial load one way (+z, the
    inner ring pressed onto its raceway's high shoulder). Fields as :class:`DeepGrooveBall`
    (its ``clearance``: 0 <= P_d < D_w, an axial preload enters as the operating point's δ_z)
    and:

    Attributes:
        contact_angle: the nominal (free) contact angle α₀ (rad), 0 < α₀ < π/2.

    Raises:
        ValueError: as :class:`DeepGrooveBall`; α₀ = 0 or >= 90° (a thrust bearing is not a
            kind here).
    """

    contact_angle: float = _real(0.6981317007977318)  # 40°, the "B" series

    axial_load: ClassVar[str] = "positive"

    def __check_init__(self):
        w = "AngularContactBall"
        self._check_ball(w)
        check_real("contact_angle", self.contact_angle, "rad", lo=0.0, hi=0.5 * math.pi,
                   lo_open=True, hi_open=True, where=w)
        check_real("clearance", self.clearance, "m", lo=-0.01 * float(self.element_diameter),
                   hi=float(self.element_diameter), hi_open=True,
                   where=f"{w} (diametral clearance, below the ball diameter)")

    @property
    def nominal_angle(self):
        return self.contact_angle

    def equivalent_load(self, radial, axial):
        """ISO 281:2007 Table 3, single-row angular contact ball bearing at α = 25, 30, 35, 40
        or 45°: P = F_r for F_a/F_r <= e, else X F_r + Y F_a.

        Raises:
            ValueError: a contact angle not one of the table's (one line)."""
        deg = math.degrees(float(self.contact_angle))
        row = ISO281_ANGULAR.get(round(deg))
        if row is None or abs(deg - round(deg)) > 1e-6:
            raise ValueError(
                f"AngularContactBall.equivalent_load: contact_angle = {deg:.6g} deg: allowed "
                "25, 30, 35, 40 or 45 deg (ISO 281's table of X and Y)"
            )
        e, X, Y = row
        Fr, Fa = jnp.asarray(radial, float), jnp.abs(jnp.asarray(axial, float))
        return jnp.where(Fa > e * Fr, X * Fr + Y * Fa, Fr)


class _Roller(_RollingElements):
    """Roller kinds: line contact, the contact angle fixed (Lim & Singh, Part I), each roller
    cut into ``slices`` slices along its effective length l (slice k at t_k from its centre,
    axial offset x_k = t_k cos α) so that a tilt loads a roller unevenly::

        δ_jk = (δ_r,j + x_k θ_j − P_d/2) cos α + (δ_z − r_p θ_j) sin α
        δ_r,j = δ_x cos ψ_j + δ_y sin ψ_j,   θ_j = γ_y cos ψ_j − γ_x sin ψ_j
        q_jk = (K_n / slices) max(δ_jk − 2 p(t_k), 0)^(10/9)

    (K_n the whole roller's constant, :func:`~jaxgear.bearings.line_contact_constant`: a
    uniform approach gives Q = K_n δ^(10/9)), f = Σ q_jk ∂δ_jk/∂d. Rollers are steel (the
    line-contact constant is Palmgren's steel relation).

    The roller's profile (``crown``, optional; default ``None``: a straight roller, the
    approach δ_jk unchanged): a logarithmic crown, the roller's radius dropping by

        p(t) = c ln(1 / (1 − (2t/l)²))        (m; c = ``crown``, m)

    at t from its centre (:meth:`crown_drop`), so that each slice's approach loses 2 p(t_k)
    (the roller's two contacts, inner and outer) before the line-contact law: a tilt moves the
    load towards the middle of the roller instead of spiking it at the edge. ISO/TS 16281:2008
    (eqs. (42)–(44)) gives c = 0.00035 D_w for cylindrical rollers with l <= 2.5 D_w and
    c = 0.00045 D_w for tapered rollers (as transcribed in github.com/minzhun/ISO16281@220b2feb,
    ``RollerBearing.py``, ``__roller_profile``); the slices' centres keep |2t/l| <= 1 − 1/S, so
    the drop is finite.
    """

    bore: float = _real()
    outer_diameter: float = _real()
    width: float = _real()
    elements: int = eqx.field(static=True)
    element_diameter: float = _real()
    pitch_diameter: float = _real()
    effective_length: float = _real()
    clearance: float = _real(0.0)
    slices: int = eqx.field(static=True, default=10)
    dynamic_rating: float | None = eqx.field(default=None, converter=_optional)
    static_rating: float | None = eqx.field(default=None, converter=_optional)
    fatigue_limit: float | None = eqx.field(default=None, converter=_optional)
    crown: float | None = eqx.field(default=None, converter=_optional)

    contact_exponent: ClassVar[float] = 10.0 / 9.0
    life_exponent: ClassVar[float | None] = 10.0 / 3.0
    crown_field: ClassVar[str | None] = "crown"

    def _check_roller(self, where):
        _check_ring(where, self.bore, self.outer_diameter, self.width, self.elements,
                    self.element_diameter, self.pitch_diameter, "roller")
        check_real("effective_length", self.effective_length, "m", lo=0.0,
                   hi=float(self.width), lo_open=True, where=f"{where} (at most the width)")
        check_real("clearance", self.clearance, "m", lo=-0.01 * float(self.element_diameter),
                   hi=float(self.element_diameter), hi_open=True,
                   where=f"{where} (diametral clearance, below the roller diameter)")
        check_integer(f"{where}: slices", self.slices, 1)
        _check_rating(where, self.dynamic_rating, self.static_rating, self.fatigue_limit)
        if self.crown is not None:
            check_real("crown", self.crown, "m", lo=0.0, hi=0.01 * float(self.element_diameter),
                       where=f"{where} (the logarithmic crown's scale c, at most "
                       "element_diameter/100; ISO/TS 16281: 0.00035 to 0.00045 element_diameter)")

    def crown_drop(self, position):
        """p(t) = c ln(1 / (1 − (2t/l)²)) (m), the drop of the roller's radius at ``position``
        t (m, |t| < l/2, any shape) from its centre (class docstring); 0 for ``crown=None``."""
        t = jnp.asarray(position, float)
        if self.crown is None:
            return jnp.zeros_like(t)
        return -self.crown * jnp.log1p(-(2.0 * t / self.effective_length) ** 2)

    @property
    def hertz_constant(self):
        """K_n (N/m^(10/9)) of a whole roller between its raceways (Palmgren)."""
        return line_contact_constant(self.effective_length)

    def _geometry(self, displacement):
        """(δ_jk (Z, S), the rows ∂δ_jk/∂d (5, Z, S))."""
        d = jnp.asarray(displacement)
        psi = self.azimuths
        c, s = jnp.cos(psi)[:, None], jnp.sin(psi)[:, None]
        S = self.slices
        t = ((jnp.arange(S) + 0.5) / S - 0.5) * self.effective_length
        ca, sa = jnp.cos(self.nominal_angle), jnp.sin(self.nominal_angle)
        x = (t * ca)[None, :]
        rp = 0.5 * self.pitch_diameter
        dr = d[0] * c + d[1] * s
        theta = d[4] * c - d[3] * s
        delta = (dr + x * theta - 0.5 * self.clearance) * ca + (d[2] - rp * theta) * sa
        if self.crown is not None:  # None: the straight roller's δ_jk, unchanged
            delta = delta - 2.0 * self.crown_drop(t)[None, :]
        one = jnp.ones_like(x)
        rows = jnp.stack([
            ca * c * one, ca * s * one, sa * jnp.ones_like(delta),
            (-x * ca + rp * sa) * s, (x * ca - rp * sa) * c,
        ])
        return delta, rows

    def element_loads(self, displacement):
        delta = self._geometry(displacement)[0]
        return self.hertz_constant / self.slices * _contact_power(delta, 10.0 / 9.0)

    def contact_pressure(self, displacement):
        """p_max = √(w E' / (2π R)) of each slice's inner and outer line contact (Pa), (Z,
        slices, 2): w = q / (l / slices) the slice's load per length, R = D(1 ∓ γ)/2 the
        contact's radius in the rolling direction, γ = D cos α / d_m, E' of steel (Hertz line
        contact; Harris & Kotzalas)."""
        w = self.element_loads(displacement) / (self.effective_length / self.slices)
        g = self.element_diameter * jnp.cos(self.nominal_angle) / self.pitch_diameter
        return jnp.stack([line_pressure(w, 0.5 * self.element_diameter * (1.0 - g)),
                          line_pressure(w, 0.5 * self.element_diameter * (1.0 + g))], axis=-1)

    def load(self, displacement):
        delta, rows = self._geometry(displacement)
        q = self.hertz_constant / self.slices * _contact_power(delta, 10.0 / 9.0)
        return jnp.einsum("ijk,jk->i", rows, q)

    def potential(self, displacement):
        delta = self._geometry(displacement)[0]
        return (self.hertz_constant / self.slices / (19.0 / 9.0)
                * jnp.sum(_contact_power(delta, 19.0 / 9.0)))


class CylindricalRoller(_Roller):
    """A single-row cylindrical roller bearing without ribs to locate it axially (NU, N): α = 0,
    no axial load (``axial_load = "none"``).

    Attributes:
        bore, outer_diameter, width: boundary dimensions (m).
        elements: the number of rollers Z. element_diameter: the roller diameter D_w (m).
        pitch_diameter: d_m (m). effective_length: the roller's effective length l (m),
            0 < l <= width. clearance: diametral clearance P_d (m), −D_w/100 <= P_d < D_w.
        slices: slices per roller (int >= 1; default 10).
        dynamic_rating, static_rating: C and C₀ (N) or ``None``.
        fatigue_limit: the maker's fatigue load limit C_u (N, 0 < C_u < C₀) or ``None`` (ISO
            281's estimate from C₀).
        crown: the roller's logarithmic crown c (m, 0 <= c <= D_w/100) or ``None`` (a straight
            roller; default): each slice's approach less 2 c ln(1/(1 − (2t_k/l)²))
            (the roller kinds' profile; ISO/TS 16281: c = 0.00035 D_w for l <= 2.5 D_w).

    Raises:
        ValueError: any argument out of its range (one line naming it).
    """

    axial_load: ClassVar[str] = "none"

    def __check_init__(self):
        self._check_roller("CylindricalRoller")

    @property
    def nominal_angle(self):
        return 0.0

    def equivalent_load(self, radial, axial):
        """P = F_r (ISO 281, a radial roller bearing at α = 0 carries no axial load).

        Raises:
            ValueError: a non-zero axial load (one line)."""
        if not isinstance(axial, jax.core.Tracer) and np.any(np.asarray(axial) != 0):
            raise ValueError(
                f"CylindricalRoller.equivalent_load: axial = {np.asarray(axial)} N: allowed 0 "
                "(an NU bearing has no ribs to take an axial load)"
            )
        return jnp.asarray(radial, float)


class TaperedRoller(_Roller):
    """A single-row tapered roller bearing: the outer raceway's contact angle α fixed, an axial
    load carried one way (+z). Fields as :class:`CylindricalRoller` (``element_diameter``: the
    rollers' mean diameter) and:

    Attributes:
        contact_angle: α (rad), 0 < α < π/2 (catalogues give e = 1.5 tan α).

    Raises:
        ValueError: as :class:`CylindricalRoller`; α = 0 or >= 90°.
    """

    contact_angle: float = _real(0.25)  # rad

    axial_load: ClassVar[str] = "positive"

    def __check_init__(self):
        w = "TaperedRoller"
        self._check_roller(w)
        check_real("contact_angle", self.contact_angle, "rad", lo=0.0, hi=0.5 * math.pi,
                   lo_open=True, hi_open=True, where=w)

    @property
    def nominal_angle(self):
        return self.contact_angle

    def equivalent_load(self, radial, axial):
        """ISO 281:2007 Table 4, single-row roller bearing, α ≠ 0: e = 1.5 tan α; P = F_r for
        F_a/F_r <= e, else 0.4 F_r + 0.4 cot α F_a."""
        Fr, Fa = jnp.asarray(radial, float), jnp.abs(jnp.asarray(axial, float))
        e = 1.5 * jnp.tan(self.contact_angle)
        return jnp.where(Fa > e * Fr, 0.4 * Fr + 0.4 / jnp.tan(self.contact_angle) * Fa, Fr)


class SphericalRoller(_Roller):
    """A double-row spherical roller bearing: two rows of ``elements`` rollers each, at the
    contact angles +α and −α, rolling on one spherical outer raceway, so that it is
    self-aligning (``self_aligning``): it carries a radial load and an axial load both ways
    and no moment (its tilt rows and columns of the stiffness are zero). Line contact per
    roller: the barrel roller on its nearly conforming raceways is modelled as a straight
    roller of the effective length l (Palmgren's line contact,
    :func:`~jaxgear.bearings.line_contact_constant`), one line per roller (a tilt does not
    load it unevenly: ``slices`` is 1). Roller j of row r (r = +1 for the row at +α, which
    carries +z; −1 for the other), both rows at the azimuths ψ_j (Harris & Kotzalas)::

        δ_jr = (δ_x cos ψ_j + δ_y sin ψ_j − P_d/2) cos α + r δ_z sin α
        Q_jr = K_n max(δ_jr, 0)^(10/9),   f = Σ Q_jr (cos α cos ψ_j, cos α sin ψ_j, r sin α, 0, 0)

    Attributes:
        bore, outer_diameter, width: boundary dimensions d, D, B (m).
        elements: the rollers per row Z (int >= 3; the bearing has 2Z). element_diameter: the
            rollers' largest diameter D_w (m). pitch_diameter: d_m (m).
        effective_length: l (m), the two rows side by side within the width: 2 l cos α <= B.
        contact_angle: α (rad), 0 < α < π/4 (catalogues give e = 1.5 tan α, 0.15 to 0.45).
        clearance: the radial internal clearance P_d (m), −D_w/100 <= P_d < D_w.
        dynamic_rating, static_rating: C and C₀ (N) or ``None``.

    Raises:
        ValueError: any argument out of its range (one line naming it); ``slices`` not 1.
    """

    contact_angle: float = _real(0.17453292519943295)  # 10°
    slices: int = eqx.field(static=True, default=1)

    axial_load: ClassVar[str] = "both"
    self_aligning: ClassVar[bool] = True
    rows: ClassVar[int] = 2
    crown_field: ClassVar[str | None] = None

    def __check_init__(self):
        w = "SphericalRoller"
        if self.slices != 1:
            raise ValueError(f"{w}: slices = {self.slices!r} is out of range: allowed 1 (a "
                             "self-aligning roller is loaded evenly along its length)")
        if self.crown is not None:
            raise ValueError(f"{w}: crown = {float(self.crown)!r} is out of range: allowed None "
                             "(one slice per roller: a crown has no slice to unload)")
        self._check_roller(w)
        check_real("contact_angle", self.contact_angle, "rad", lo=0.0, hi=0.25 * math.pi,
                   lo_open=True, hi_open=True, where=f"{w} (0 to 45 deg)")
        room = float(self.width) / (2.0 * math.cos(float(self.contact_angle)))
        check_real("effective_length", self.effective_length, "m", lo=0.0, hi=room,
                   lo_open=True, where=f"{w} (two rows side by side: at most width / (2 cos "
                   "contact_angle))")

    @property
    def nominal_angle(self):
        return self.contact_angle

    def _geometry(self, displacement):
        """(δ_jr (Z, 2), the rows ∂δ_jr/∂d (5, Z, 2)): column r = 0 the row at +α, 1 at −α."""
        d = jnp.asarray(displacement)
        psi = self.azimuths
        c, s = jnp.cos(psi)[:, None], jnp.sin(psi)[:, None]
        side = jnp.asarray([1.0, -1.0])[None, :]
        ca, sa = jnp.cos(self.contact_angle), jnp.sin(self.contact_angle)
        delta = (d[0] * c + d[1] * s - 0.5 * self.clearance) * ca + side * d[2] * sa
        one = jnp.ones_like(delta)
        rows = jnp.stack([ca * c * one, ca * s * one, side * sa * one, 0.0 * one, 0.0 * one])
        return delta, rows

    def element_loads(self, displacement):
        """Each roller's load Q_jr (N), (Z, 2): column 0 the row at +α, 1 the row at −α."""
        return super().element_loads(displacement)

    def equivalent_load(self, radial, axial):
        """ISO 281:2007, double-row roller bearing, α ≠ 0 (spherical): e = 1.5 tan α;
        P = F_r + 0.45 cot α F_a for F_a/F_r <= e, else 0.67 F_r + 0.67 cot α F_a."""
        return _double_row_equivalent_load(radial, axial, self.contact_angle)


def _double_row_equivalent_load(radial, axial, alpha):
    """ISO 281:2007's equivalent dynamic load of a double-row radial roller bearing at α ≠ 0
    (a spherical one; a pair of single-row ones side by side, which it rates as one double-row
    bearing): e = 1.5 tan α, P = F_r + 0.45 cot α F_a for F_a/F_r <= e, else
    0.67 F_r + 0.67 cot α F_a (N)."""
    Fr, Fa = jnp.asarray(radial, float), jnp.abs(jnp.asarray(axial, float))
    t = jnp.tan(alpha)
    return jnp.where(Fa > 1.5 * t * Fr, 0.67 * Fr + 0.67 / t * Fa, Fr + 0.45 / t * Fa)


def _of_row(name: str, doc: str) -> property:
    """A read-only property of a :class:`TaperedRollerPair` that is its row's ``name``."""
    return property(lambda self: getattr(self.row, name), doc=doc)


#: a tapered roller pair's arrangements: the row at +z carries −z ("O", back-to-back, DB: the
#: pressure centres outside the rows) or +z ("X", face-to-face, DF: between them)
ARRANGEMENTS = ("O", "X")
#: ISO 281's basic dynamic rating of two single-row roller bearings side by side as a unit
PAIR_DYNAMIC_FACTOR = 2.0 ** (7.0 / 9.0)


class TaperedRollerPair(AbstractRollingBearing):
    """Two single-row tapered roller bearings of one geometry side by side, facing both ways,
    as ONE bearing node at the pair's centre: a radial load, an axial load both ways and a
    moment (``axial_load = "both"``, not self-aligning, ``carries_moment``: a shaft may stand
    on the pair alone, an overhung pinion).

    Geometry: the rows' roller mid-planes sit at z = ∓s/2 (``spacing`` s: one row's ``width``
    for two rows side by side, more with a spacer). Each row is a :class:`TaperedRoller`
    (:attr:`row`, its sliced line contact unchanged); the row whose inner ring carries +z has
    its pressure centre (where the contact normal through the roller's mid-length meets the
    axis) a = (d_m/2) tan α on its −z side, the other row is its mirror image (z → −z). In the
    O arrangement the row at −z carries +z and the row at +z carries −z, the pressure centres
    ±(s/2 + a) (the :attr:`spread` s + 2a); in the X arrangement the other way round, ±(s/2 − a)
    (spread s − 2a, negative where the centres cross).

    The pair's axial end play e (m; negative: a preload) stands in place of the rows' clearance:
    each row takes the diametral clearance P_d = e tan α, so that with no radial load the inner
    ring moves axially by e between the two rows' first contacts.

    The load for the node's displacement d (the rigid inner ring): row i at z_i takes
    A_i d, A_i = S_i T_i, with the lever T_i (δ_x + z_i γ_y, δ_y − z_i γ_x, δ_z, γ_x, γ_y) and
    S_i = diag(1, 1, −1, −1, −1) for the mirrored row (identity for the other), and
    f(d) = Σ_i A_iᵀ f_row(A_i d): each row's force, and its moment carried to the node
    (M_x − z_i F_y, M_y + z_i F_x); U(d) = Σ_i U_row(A_i d). K = ∂f/∂d (``jax.jacfwd``).

    Life (ISO 281:2007): the pair rated as one double-row bearing, C = 2^(7/9) C_row
    (:data:`PAIR_DYNAMIC_FACTOR`, 1.715: two single-row roller bearings side by side operating
    as a unit), C₀ = 2 C₀_row (ISO 76), a maker's C_u doubled like C₀; P as a double-row
    roller bearing's (e = 1.5 tan α, Y₁ = 0.45 cot α, Y₂ = 0.67 cot α). Tones: the row's.

    Args:
        bore, outer_diameter, width: one row's boundary dimensions d, D, T (m).
        elements: the rollers per row Z (the tones' count). element_diameter: their mean
            diameter D_w (m). pitch_diameter: d_m (m). effective_length: l (m), <= width.
        contact_angle: α (rad), 0 < α < π/2 (the outer raceway's; e = 1.5 tan α).
        arrangement: ``"O"`` (back-to-back, DB) or ``"X"`` (face-to-face, DF).
        end_play: the pair's axial end play e (m), −D_w/(100 tan α) <= e < D_w / tan α (the
            row's clearance range); negative a preload.
        spacing: the rows' mid-plane distance s (m), >= width; default width.
        slices: slices per roller (int >= 1; default 10).
        dynamic_rating, static_rating, fatigue_limit: ONE ROW's C, C₀, C_u (N) or ``None``
            (the catalogue's single bearing's; the pair's are :attr:`dynamic_rating`, ...).
        crown: the rollers' logarithmic crown c (m) or ``None`` (:class:`TaperedRoller`'s).

    Raises:
        ValueError: any argument out of its range (one line naming it; the row's own lines).
    """

    row: TaperedRoller
    arrangement: str = eqx.field(static=True)
    end_play: float = _real(0.0)
    spacing: float = _real(0.0)

    contact_exponent: ClassVar[float] = 10.0 / 9.0
    axial_load: ClassVar[str] = "both"
    life_exponent: ClassVar[float | None] = 10.0 / 3.0
    self_aligning: ClassVar[bool] = False
    clearance_field: ClassVar[str | None] = "end_play"
    rows: ClassVar[int] = 2
    crown_field: ClassVar[str | None] = "crown"
    carries_moment: ClassVar[bool] = True

    def __init__(self, bore, outer_diameter, width, elements, element_diameter, pitch_diameter,
                 effective_length, contact_angle, arrangement="O", end_play=0.0, spacing=None,
                 slices=10, dynamic_rating=None, static_rating=None, fatigue_limit=None,
                 crown=None):
        w = "TaperedRollerPair"
        self.row = TaperedRoller(
            bore=bore, outer_diameter=outer_diameter, width=width, elements=elements,
            element_diameter=element_diameter, pitch_diameter=pitch_diameter,
            effective_length=effective_length, contact_angle=contact_angle, slices=slices,
            dynamic_rating=dynamic_rating, static_rating=static_rating,
            fatigue_limit=fatigue_limit, crown=crown)
        if arrangement not in ARRANGEMENTS:
            raise ValueError(f"{w}: arrangement = {arrangement!r} is out of range: allowed "
                             "'O' (back-to-back, DB) or 'X' (face-to-face, DF)")
        self.arrangement = arrangement
        t = math.tan(float(contact_angle))
        D = float(element_diameter)
        check_real("end_play", end_play, "m", lo=-0.01 * D / t, hi=D / t, hi_open=True,
                   where=f"{w} (axial; the rows' clearance end_play tan(contact_angle) in "
                   "[-element_diameter/100, element_diameter); negative: a preload)")
        self.end_play = as_float(end_play)
        spacing = width if spacing is None else spacing
        check_real("spacing", spacing, "m", lo=float(width), where=f"{w} (the rows' mid-plane "
                   "distance: at least one row's width, side by side)")
        self.spacing = as_float(spacing)

    @classmethod
    def of(cls, row: TaperedRoller, arrangement="O", end_play=0.0, spacing=None
           ) -> TaperedRollerPair:
        """The pair of two rows ``row`` (a :class:`TaperedRoller`, e.g. a catalogue entry; its
        clearance replaced by the pair's ``end_play``), in ``arrangement``, ``spacing`` apart.

        Raises:
            ValueError: ``row`` not a TaperedRoller; an argument out of range (one line)."""
        if type(row) is not TaperedRoller:
            raise ValueError(f"TaperedRollerPair.of: row = {type(row).__name__}: allowed a "
                             "TaperedRoller (one row of the pair)")
        return cls(bore=row.bore, outer_diameter=row.outer_diameter, width=row.width,
                   elements=row.elements, element_diameter=row.element_diameter,
                   pitch_diameter=row.pitch_diameter, effective_length=row.effective_length,
                   contact_angle=row.contact_angle, arrangement=arrangement,
                   end_play=end_play, spacing=spacing, slices=row.slices,
                   dynamic_rating=row.dynamic_rating, static_rating=row.static_rating,
                   fatigue_limit=row.fatigue_limit, crown=row.crown)

    def with_clearance(self, value) -> TaperedRollerPair:
        """The pair with end play ``value`` (m; its :attr:`clearance_field`), checked as the
        constructor checks it (ValueError, one line)."""
        return type(self).of(self.row, self.arrangement, value, self.spacing)

    # ---- the row's geometry, which the tones, the solve's scales and the life read
    bore = _of_row("bore", "d (m), the rows' bore: the seat's diameter.")
    outer_diameter = _of_row("outer_diameter", "D (m), the rows' outer diameter.")
    elements = _of_row("elements", "Z, the rollers of one row (the tones' count).")
    element_diameter = _of_row("element_diameter", "D_w (m), the rollers' mean diameter.")
    pitch_diameter = _of_row("pitch_diameter", "d_m (m).")
    effective_length = _of_row("effective_length", "l (m), a roller's effective length.")
    slices = _of_row("slices", "The slices per roller (the row's).")
    crown = _of_row("crown", "The rollers' logarithmic crown c (m) or None (the row's).")
    contact_angle = _of_row("contact_angle", "α (rad), the outer raceway's contact angle.")
    nominal_angle = _of_row("contact_angle", "α (rad): the tones' and the Hertz constant's.")
    hertz_constant = _of_row("hertz_constant", "K_n (N/m^(10/9)) of one roller (the row's).")

    @property
    def clearance(self):
        """The rows' diametral clearance P_d = e tan α (m) of the end play e."""
        return self.end_play * jnp.tan(self.row.contact_angle)

    # ---- the pair's ratings (ISO 281, ISO 76: two single-row bearings as a unit)
    @property
    def dynamic_rating(self):
        """C = 2^(7/9) C_row (N), or None."""
        c = self.row.dynamic_rating
        return None if c is None else PAIR_DYNAMIC_FACTOR * c

    @property
    def static_rating(self):
        """C₀ = 2 C₀_row (N), or None."""
        c = self.row.static_rating
        return None if c is None else 2.0 * c

    @property
    def fatigue_limit(self):
        """C_u = 2 C_u,row (N) where the maker's row value is given, else None."""
        c = self.row.fatigue_limit
        return None if c is None else 2.0 * c

    # ---- the pair's layout
    @property
    def pressure_offset(self):
        """a = (d_m/2) tan α (m): a row's pressure centre from its roller mid-plane."""
        return 0.5 * self.row.pitch_diameter * jnp.tan(self.row.contact_angle)

    @property
    def positions(self):
        """The rows' roller mid-planes z_i = (−s/2, +s/2) (m) from the node, (2,)."""
        return jnp.stack([-0.5 * self.spacing, 0.5 * self.spacing])

    @property
    def mirrored(self):
        """Which row carries −z (its inner ring pushed −z onto its raceway): the one at +z in
        the O arrangement, at −z in the X arrangement, (2,) of bool."""
        return (False, True) if self.arrangement == "O" else (True, False)

    @property
    def centres(self):
        """The rows' pressure centres (m) from the node, (2,): z_i + a for the row carrying −z,
        z_i − a for the other."""
        a = self.pressure_offset
        return self.positions + jnp.asarray([a if m else -a for m in self.mirrored])

    @property
    def spread(self):
        """The pressure centres' distance (m): s + 2a (O) or s − 2a (X, negative where they
        cross)."""
        c = self.centres
        return c[1] - c[0]

    def row_maps(self):
        """A_i = S_i T_i (5, 5) for the two rows, (2, 5, 5): the node's displacement to the
        row's (its lever, then its mirror)."""
        maps = []
        for z, m in zip(self.positions, self.mirrored, strict=True):
            T = (jnp.eye(5).at[0, 4].set(z).at[1, 3].set(-z))
            S = jnp.diag(jnp.asarray([1.0, 1.0, -1.0, -1.0, -1.0] if m else [1.0] * 5))
            maps.append(S @ T)
        return jnp.stack(maps)

    def _rows(self):
        """The row with the end play's clearance (its field replaced, not rebuilt)."""
        return eqx.tree_at(lambda r: r.clearance, self.row, self.clearance)

    def load(self, displacement):
        d = jnp.asarray(displacement)
        row = self._rows()
        return sum(A.T @ row.load(A @ d) for A in self.row_maps())

    def potential(self, displacement):
        d = jnp.asarray(displacement)
        row = self._rows()
        return sum(row.potential(A @ d) for A in self.row_maps())

    def row_loads(self, displacement):
        """Each row's load (F_x, F_y, F_z, M_x, M_y) (N, N·m) about its own mid-plane in its
        own frame (:class:`TaperedRoller`'s: its F_z > 0 the axial load it carries; the
        mirrored row's F_z, M_x, M_y of the reflected axes), (2, 5): row 0 at −z, 1 at +z."""
        d = jnp.asarray(displacement)
        row = self._rows()
        return jnp.stack([row.load(A @ d) for A in self.row_maps()])

    def element_loads(self, displacement):
        """Each slice's load q_jk (N) of each row, (2, Z, slices): row 0 at −z, 1 at +z."""
        d = jnp.asarray(displacement)
        row = self._rows()
        return jnp.stack([row.element_loads(A @ d) for A in self.row_maps()])

    def contact_pressure(self, displacement):
        """Each slice's inner and outer p_max (Pa) of each row, (2, Z, slices, 2)."""
        d = jnp.asarray(displacement)
        row = self._rows()
        return jnp.stack([row.contact_pressure(A @ d) for A in self.row_maps()])

    def equivalent_load(self, radial, axial):
        """ISO 281:2007: the pair as one double-row roller bearing at α (module function
        ``_double_row_equivalent_load``): e = 1.5 tan α; P = F_r + 0.45 cot α F_a for
        F_a/F_r <= e, else 0.67 F_r + 0.67 cot α F_a."""
        return _double_row_equivalent_load(radial, axial, self.row.contact_angle)
