"""Mesh-stiffness models as objects: the abstract :class:`AbstractStiffness` and its concrete
:class:`Uniform`, :class:`ISO6336`, :class:`Weber` and :class:`FE2D`, and
:func:`stiffness_table`, which tabulates any of them on the path of contact (docs/stiffness.md).

A new model is one subclass with a ``name`` and a :meth:`~AbstractStiffness.profile` (the
stiffness per unit contact-line length at base-plane coordinates s); the case file's names
("uniform", "iso6336", "weber", "fe2d") map to these objects in :mod:`jaxgear.io` only.
Everything here is NumPy, evaluated once: a constant for JAX (no gradient through the tables).
"""

from __future__ import annotations

import abc
import functools
import math
from typing import ClassVar

import equinox as eqx
import numpy as np

from ._geometry import AbstractGearPair, GearPair
from ._internal import InternalGearPair, internal_tooth_geometry
from ._stiffness import (
    AbstractFoundation,
    NoFoundation,
    WeberFoundation,
    _half_thickness_angle as half_thickness_angle,
    bore_radius,
    iso6336_mesh_stiffness,
    member_compliance,
    tooth_geometry,
    weber_profile,
)
from ._util import check_instance, check_integer, check_real
from ._weber_internal import ring_form

__all__ = [
    "FE2D",
    "ISO6336",
    "AbstractStiffness",
    "MeshConditions",
    "Uniform",
    "Weber",
    "stiffness_table",
]

_E_REFERENCE = 210e9  # Pa: the modulus the plausibility estimate of Weber/FE2D scales from


class MeshConditions(eqx.Module):
    """The material and load a stiffness profile is evaluated at (NumPy floats, SI).

    Attributes:
        youngs_modulus: E (Pa). poisson_ratio: ν (-).
        line_load: transverse load per unit face width (N/m), the Hertzian term's (1.1).
        specific_load: F_t K_A / b (N/m) of the ISO 6336-1 low-load factor; ``None``: at or
            above 100 N/mm (no reduction).
    """

    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.3
    line_load: float = 2e5
    specific_load: float | None = None


class AbstractStiffness(eqx.Module):
    """A mesh-stiffness model: k(s), the stiffness per unit contact-line length (N/m per m,
    flank-normal, in the base plane) along the path of contact.

    Subclasses set ``name`` (the word summaries print) and implement :meth:`profile`; ``hertz``
    says the profile depends on the line load through a Hertzian approach (an error then points
    at the load). :meth:`without_body`, :meth:`mean_estimate` and :meth:`summary` have defaults.
    """

    name: eqx.AbstractClassVar[str]
    hertz: ClassVar[bool] = False
    #: the model has an internal-gear form (an :class:`~jaxgear.InternalGearPair` accepted)
    internal_teeth: ClassVar[bool] = False

    @abc.abstractmethod
    def profile(
        self, pair: AbstractGearPair, s: np.ndarray, conditions: MeshConditions
    ) -> np.ndarray:
        """k(s) (N/m per m of contact line) at base-plane coordinates ``s`` (m), shape (n,),
        s ∈ [0, g_α]; returns shape (n,)."""

    def without_body(self, flexible: tuple[bool, bool]) -> AbstractStiffness:
        """The model for a pair whose ``flexible`` members (pinion, gear) are condensed FE bodies
        that supply their body compliance (seed remark after (2.31)): the same model unless it
        has a foundation term."""
        return self

    def check_pair(self, pair) -> None:
        """Refuse, in one ``ValueError`` line before any work, an internal ``pair`` this model
        cannot tabulate (nothing here)."""

    def with_ring_cutter(self, cutter) -> AbstractStiffness:
        """The model with the internal gear's pinion-type cutter (a :class:`fem_prep.ShaperCutter`)
        for a model that generates the ring's teeth (:class:`Weber`); this one unchanged."""
        return self

    def mean_estimate(self, pair: AbstractGearPair, youngs_modulus: float) -> float:
        """A cheap estimate of the mean mesh stiffness (N/m) without the table, for plausibility
        checks: ISO 6336-1 c_γα b scaled by E / 210 GPa (the Weber profile of the embedded cases
        agrees with it within about 25 %)."""
        return iso6336_mesh_stiffness(pair) * pair.face_width * youngs_modulus / _E_REFERENCE

    def summary_at(self, pair: AbstractGearPair, conditions: MeshConditions) -> dict:
        """``summary.json``'s mesh-stiffness entries that depend on the pair and the conditions
        (SI): none for a model whose k(s) follows from the tooth geometry."""
        return {}

    def summary(self) -> dict:
        """``summary.json``'s mesh-stiffness entries: ``stiffness`` (:attr:`name`),
        ``foundation`` (the case file's default, "weber", for a model without one, as summaries
        have always carried it) and ``fe2d_size_m`` (None)."""
        return {"stiffness": self.name, "foundation": WeberFoundation.name, "fe2d_size_m": None}


def _check_foundation(foundation, where: str) -> None:
    check_instance(
        "foundation",
        foundation,
        AbstractFoundation,
        "a jaxgear foundation (WeberFoundation(), SainsotFoundation(), NoFoundation(), "
        "MemberFoundations(pinion, gear))",
        where,
    )


class Uniform(AbstractStiffness):
    """A given constant stiffness per unit contact-line length.

    Attributes:
        k0: k (N/m per m of contact line, i.e. N/m²) > 0.

    Raises:
        ValueError: ``k0`` not a finite number > 0.
    """

    k0: float
    name: ClassVar[str] = "uniform"
    internal_teeth: ClassVar[bool] = True

    def __check_init__(self):
        try:
            ok = 0 < float(self.k0) < math.inf
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ValueError(
                f"Uniform: k0 = {self.k0!r} N/m² is out of range: allowed a finite value > 0 "
                "(the case file's [mesh] stiffness_per_length_N_per_mm_per_um, required with "
                "stiffness = 'uniform')"
            )

    def profile(self, pair, s, conditions):
        return np.full_like(s, self.k0)

    def mean_estimate(self, pair, youngs_modulus):
        """k0 ε_α b / cos β_b (N/m)."""
        eps = pair.transverse_contact_ratio
        return self.k0 * eps * pair.face_width / math.cos(pair.base_helix_angle)


class ISO6336(AbstractStiffness):
    """ISO 6336-1 method B: c_γα (:func:`~jaxgear.iso6336_mesh_stiffness`, at the conditions'
    E and specific load) as a constant per unit contact length ``k0 = c_γα / (ε_α cos β_b)``, so
    that the mean mesh stiffness on the theoretical path of contact times cos² β_b equals
    c_γα b (the standard's c_γα = c′ (0.75 ε_α + 0.25) is that path's mean).

    With contact beyond the path (``MeshModel.extended_contact``) the cells there take the
    path end's k0 like every model's, and the tip corners they hold add the load-dependent
    contact that ISO 6336 does not model: the loaded mean mesh stiffness then exceeds
    c_γα b / cos² β_b while its part on the path
    (:attr:`~jaxgear.MeshResult.mesh_stiffness_on_path`) keeps it (docs/stiffness.md)."""

    name: ClassVar[str] = "iso6336"
    internal_teeth: ClassVar[bool] = True

    def profile(self, pair, s, conditions):
        k0 = iso6336_mesh_stiffness(pair, conditions.youngs_modulus, conditions.specific_load) / (
            pair.transverse_contact_ratio * math.cos(pair.base_helix_angle)
        )
        return np.full_like(s, k0)

    def summary_at(self, pair, conditions):
        """``c_gamma_alpha_N_per_m2``: c_γα at the conditions' E and specific load (N/m²,
        i.e. N/(m·m) per unit face width), and ``mesh_stiffness_on_path_iso_N_per_m``: the mean
        mesh stiffness on the theoretical path it prescribes, c_γα b / cos² β_b (N/m,
        flank-normal, as ``MeshResult.mesh_stiffness_on_path``)."""
        c = iso6336_mesh_stiffness(pair, conditions.youngs_modulus, conditions.specific_load)
        cb = math.cos(pair.base_helix_angle)
        return {
            "c_gamma_alpha_N_per_m2": float(c),
            "mesh_stiffness_on_path_iso_N_per_m": float(c * pair.face_width / cb**2),
        }

    def mean_estimate(self, pair, youngs_modulus):
        """c_γα b (N/m) at the standard's steel modulus."""
        return iso6336_mesh_stiffness(pair) * pair.face_width


class Weber(AbstractStiffness):
    """The Weber–Banaschek thin-slice model, seed (1.1)–(1.3) (:func:`~jaxgear.weber_profile`),
    for external pairs and internal pairs (:class:`~jaxgear.InternalGearPair`: the ring's tooth
    generated by ``ring_cutter``, :func:`~jaxgear.member_compliance`).

    Attributes:
        foundation: the gear-body term (:class:`~jaxgear.WeberFoundation` by default,
            :class:`~jaxgear.SainsotFoundation`, :class:`~jaxgear.NoFoundation`, or a
            :class:`~jaxgear.MemberFoundations` of one per member; an internal gear takes
            Weber's or none).
        ring_cutter: the :class:`fem_prep.ShaperCutter` (teeth z0, profile_shift x0,
            tip_radius_coeff ρ_a0/m_n) that generates an internal gear's teeth; ``None``
            (default): an internal pair is refused in one line; external pairs ignore it (one
            ``Weber`` serves the sun–planet and ring–planet meshes of a stage).

    Raises:
        ValueError: ``foundation`` not a foundation object, ``ring_cutter`` neither None nor a
            :class:`fem_prep.ShaperCutter`.
    """

    foundation: AbstractFoundation = WeberFoundation()
    ring_cutter: object = None
    name: ClassVar[str] = "weber"
    hertz: ClassVar[bool] = True
    internal_teeth: ClassVar[bool] = True

    def __check_init__(self):
        _check_foundation(self.foundation, "Weber")
        if self.ring_cutter is not None:
            from fem_prep import ShaperCutter  # lazy: fem_prep imports SciPy

            check_instance(
                "ring_cutter", self.ring_cutter, ShaperCutter,
                "None or a fem_prep.ShaperCutter(teeth, profile_shift, tip_radius_coeff)", "Weber",
            )

    def profile(self, pair, s, conditions):
        c = conditions
        return weber_profile(
            pair, s, c.youngs_modulus, c.poisson_ratio, c.line_load, self.foundation,
            ring_cutter=self.ring_cutter,
        )

    def check_pair(self, pair):
        """An internal ``pair`` needs the ring's cutter, one that cuts it, and a foundation
        with a ring form (its :meth:`~jaxgear.AbstractFoundation.ring_compliance` refuses at
        once otherwise): one ``ValueError`` line, before any work."""
        ring_form(pair, self.ring_cutter)
        self.foundation.member(1).ring_compliance(np.zeros(1), 1.0, np.ones(1), 1.0, 0.0)

    def without_body(self, flexible):
        return Weber(self.foundation.without_body(flexible), self.ring_cutter)

    def with_ring_cutter(self, cutter):
        return Weber(self.foundation, cutter)

    def summary(self):
        return {**super().summary(), "foundation": self.foundation.name}


class FE2D(AbstractStiffness):
    """Plane-strain FE compliance of each member's tooth + body (:func:`fem_prep.tooth_compliance`,
    cached by input hash) plus Weber's Hertzian approach (1.1), exactly as
    :func:`~jaxgear.weber_profile`'s.

    An :class:`~jaxgear.InternalGearPair` is accepted: the pinion (planet) as above, the ring's
    internal tooth on its ring (:func:`fem_prep.tooth_compliance` of
    :func:`~jaxgear.internal_tooth_geometry`, the ring's outer face clamped at r_f2 + s_R with
    the ring's ``Member.rim_thickness`` s_R, default r_f2 + 3.5 m_n), and Weber's Hertzian
    approach (1.1) with the concave flank's relative radius ρ1 ρ2/(ρ2 − ρ1) and the ring's depth
    d2 = r sin ψ(r) to its tooth centre line (docs/planetary.md, "Internal gears"). The ring's
    tooth form, in the FE model and the Hertzian term alike, is the one its ``ring_cutter``
    generates (:class:`fem_prep.ShaperFillet`); without a cutter, the stand-in
    :class:`fem_prep.InternalCircularFillet` (the involute and a circle of ρ_fP tangent to the
    root circle: mean compliance 0.04 % from the generated form's for the NREL 5 MW stage-1
    ring and its z0 = 36 cutter, 1.4-3 % below it for small cutters, z0 = 15-30).

    Attributes:
        size: FE element size (m) > 0; ``None``: m_n / 6.
        foundation: a member whose foundation is :class:`~jaxgear.NoFoundation` gets its
            tooth-only FE compliance (a condensed FE body supplies the rest); any other gives the
            FE tooth + body down to the bore (:func:`~jaxgear.bore_radius`).
        ring_support: how an internal pair's ring is held (``fem_prep.tooth_compliance``'s
            ``support``): ``None`` (its outer face clamped) or ``fem_prep.RingSegment(p)`` (a
            segment of p pitches held at its radial sides, its outer face free: the ring's
            bending between supports p pitches apart); unused for external pairs.
        ring_cutter: the :class:`fem_prep.ShaperCutter` that generates an internal pair's ring
            teeth (as :class:`Weber`'s; :meth:`with_ring_cutter`); ``None`` (default): the
            stand-in fillet above; external pairs ignore it.

    Raises:
        ValueError: ``size`` not a finite number > 0, ``foundation`` not a foundation object,
            ``ring_cutter`` neither None nor a :class:`fem_prep.ShaperCutter`; an internal pair
            the cutter cannot cut (:meth:`check_pair`, one line naming ``gear.cutter...``).
    """

    size: float | None = None
    foundation: AbstractFoundation = WeberFoundation()
    ring_support: object = eqx.field(default=None, static=True)
    ring_cutter: object = eqx.field(default=None, static=True)
    name: ClassVar[str] = "fe2d"
    hertz: ClassVar[bool] = True
    internal_teeth: ClassVar[bool] = True

    def __check_init__(self):
        if self.size is not None:
            check_real("size", self.size, "m", lo=0.0, lo_open=True, shape=(), where="FE2D")
        _check_foundation(self.foundation, "FE2D")
        if self.ring_cutter is not None:
            from fem_prep import ShaperCutter  # lazy: fem_prep imports SciPy

            check_instance(
                "ring_cutter", self.ring_cutter, ShaperCutter,
                "None or a fem_prep.ShaperCutter(teeth, profile_shift, tip_radius_coeff)", "FE2D",
            )

    def profile(self, pair, s, conditions):
        import fem_prep  # lazy: SciPy and scikit-fem only when the FE model runs

        E, nu, cb = (
            conditions.youngs_modulus,
            conditions.poisson_ratio,
            math.cos(pair.base_helix_angle),
        )
        rho = [pair.roll_distance(s, i) for i in (0, 1)]
        c = np.zeros_like(s)
        for i in (0, 1):
            geometry, held = _fe_member(pair, i, self.ring_support, self.ring_cutter)
            fe = fem_prep.tooth_compliance(
                geometry,
                **held,
                youngs_modulus=E,
                poisson_ratio=nu,
                size=self.size,
                progress=None,
            )
            c = c + fe(rho[i], tooth_only=not self.foundation.member(i).fe_body)
        c_hertz = _hertz_compliance(pair, s, E, nu, conditions.line_load, self.ring_cutter)
        return 1.0 / (c + c_hertz) / cb

    def check_pair(self, pair):
        """An internal ``pair`` whose ring the ``ring_cutter`` cannot cut: one ``ValueError``
        line (``gear.cutter...``), before any work; without a cutter nothing to check."""
        if self.ring_cutter is not None:
            ring_form(pair, self.ring_cutter)

    def without_body(self, flexible):
        return FE2D(
            self.size, self.foundation.without_body(flexible), self.ring_support, self.ring_cutter
        )

    def with_ring_cutter(self, cutter):
        return FE2D(self.size, self.foundation, self.ring_support, cutter)

    def summary(self):
        return {
            "stiffness": self.name,
            "foundation": self.foundation.name,
            "fe2d_size_m": self.size,
        }


@functools.singledispatch
def _fe_member(pair: AbstractGearPair, member: int, ring_support=None, ring_cutter=None):
    """The FE tooth of member 0 (pinion) or 1 (gear) and how it is held (the keywords of
    ``fem_prep.tooth_compliance``: its clamped rim radius, m): an external member's, of either
    kind of pair."""
    return tooth_geometry(pair, member), {"rim_radius": bore_radius(pair, member)}


@_fe_member.register
def _fe_internal_member(pair: InternalGearPair, member: int, ring_support=None, ring_cutter=None):
    """The planet as an external member; the ring's internal tooth on its ring (generated by
    ``ring_cutter``: fem_prep's default form of a geometry with a cutter), its outer face at
    r_f2 + ``rim_thickness`` (``None``: the FE model's default, r_f2 + 3.5 m_n), held by
    ``ring_support``."""
    if member == 0:  # the planet: an external member
        return _fe_member.dispatch(AbstractGearPair)(pair, 0)
    s_r = pair.gear.rim_thickness
    rim = None if s_r is None else pair.root_radii[1] + float(s_r)
    geometry = internal_tooth_geometry(pair, ring_cutter)
    return geometry, {"rim_radius": rim, "support": ring_support}


@functools.singledispatch
def _hertz_compliance(pair: GearPair, s, E, nu, line_load, ring_cutter=None):
    """Weber's Hertzian approach (1.1) (m/N per m, transverse), from weber_profile's own code
    path: 1/k_t − (tooth terms)."""
    cb = math.cos(pair.base_helix_angle)
    none = NoFoundation()
    c_none = sum(member_compliance(pair, i, pair.roll_distance(s, i), E, nu, none) for i in (0, 1))
    return 1.0 / (cb * weber_profile(pair, s, E, nu, line_load, none)) - c_none


@_hertz_compliance.register
def _internal_hertz_compliance(pair: InternalGearPair, s, E, nu, line_load, ring_cutter=None):
    """Weber's (1.1) on the concave ring flank: 4(1 − ν²)/(π E) [ln(2 √(d1 d2)/a_H) −
    ν/(2(1 − ν))], a_H = √(8 w R (1 − ν²)/(π E)), R = ρ1 ρ2/(ρ2 − ρ1) (transverse), d_i = r
    sin ψ(r) the contact point's distance to each tooth's centre line (the ring's ψ from its
    FE tooth form: the one ``ring_cutter`` generates, else the stand-in)."""
    import fem_prep  # lazy: SciPy only when the FE model runs

    rho1, rho2 = (pair.roll_distance(s, i) for i in (0, 1))
    r1, r2 = np.hypot(rho1, pair.base_radii[0]), np.hypot(rho2, pair.base_radii[1])
    d1 = r1 * np.sin(half_thickness_angle(pair, 0, r1))
    ring = fem_prep.tooth_profile(internal_tooth_geometry(pair, ring_cutter))
    d2 = r2 * np.sin(ring.psi(r2))
    a_h = np.sqrt(8 * line_load * rho1 * rho2 / (rho2 - rho1) * (1 - nu**2) / (math.pi * E))
    log = np.log(2 * np.sqrt(d1 * d2) / a_h) - nu / (2 * (1 - nu))
    return 4 * (1 - nu**2) / (math.pi * E) * log


@functools.singledispatch
def _check_model_for_pair(pair, model: AbstractStiffness) -> None:
    """Every model takes an external pair."""


@_check_model_for_pair.register
def _internal_pair_model(pair: InternalGearPair, model: AbstractStiffness) -> None:
    if not model.internal_teeth:
        raise ValueError(
            f"stiffness_table: model = {model.name!r} is out of range for an InternalGearPair: "
            "allowed 'uniform', 'iso6336', 'weber' (with the ring's cutter) or 'fe2d'"
        )
    model.check_pair(pair)


def stiffness_table(
    pair: AbstractGearPair,
    model: AbstractStiffness,
    *,
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
    line_load: float = 2e5,
    n_points: int = 129,
    specific_load: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Tabulate k(s) (N/m²) of ``model`` on ``n_points`` equally spaced s ∈ [0, g_α].

    Args:
        pair: the gear pair, of either kind (:class:`~jaxgear.GearPair`,
            :class:`~jaxgear.InternalGearPair`).
        model: the stiffness model, e.g. ``jaxgear.Weber(jaxgear.SainsotFoundation())``.
        youngs_modulus: E (Pa); poisson_ratio: ν.
        line_load: transverse load per unit face width (N/m) of the Hertzian term (``Weber``,
            ``FE2D``).
        n_points: table points (an integer >= 2).
        specific_load: F_t K_A / b (N/m) of the ISO 6336-1 low-load factor below 100 N/mm
            (``ISO6336``; ``None``: no reduction); :meth:`jaxgear.io.Case.mesh_model` passes the
            case's nominal F_t / b (K_A = 1).

    Returns:
        ``(s, k)``: s (m), shape (n_points,); k(s) (N/m per m of contact line), (n_points,).

    Raises:
        ValueError: a ``model`` that is not an :class:`AbstractStiffness`, a ``pair`` that is not
            a :class:`~jaxgear.AbstractGearPair` (a GearPair or InternalGearPair), a material,
            load or size that is not a finite number in range, ``n_points`` not an integer >= 2
            (one line naming the argument); a model that gives
            non-positive or non-finite values (pointed or undercut teeth, or a load whose
            Hertzian contact is wider than the teeth).
    """
    where = "stiffness_table"
    check_instance("pair", pair, AbstractGearPair, "a jaxgear.GearPair or InternalGearPair", where)
    check_instance(
        "model",
        model,
        AbstractStiffness,
        "a jaxgear stiffness model (Uniform(k0), ISO6336(), Weber(foundation), FE2D(size))",
        where,
    )
    check_real("youngs_modulus", youngs_modulus, "Pa", lo=0.0, lo_open=True, shape=(), where=where)
    check_real("poisson_ratio", poisson_ratio, lo=0.0, hi=0.5, hi_open=True, shape=(), where=where)
    check_real("line_load", line_load, "N/m", lo=0.0, lo_open=True, shape=(), where=where)
    check_integer("n_points", n_points, 2)
    _check_model_for_pair(pair, model)
    if specific_load is not None:
        check_real(
            "specific_load", specific_load, "N/m", lo=0.0, lo_open=True, shape=(), where=where
        )
    s = np.linspace(0.0, pair.path_of_contact, n_points)
    conditions = MeshConditions(youngs_modulus, poisson_ratio, line_load, specific_load)
    k = model.profile(pair, s, conditions)
    if not np.all(np.isfinite(k)) or np.any(k <= 0):
        load = (
            f" or the load (line load {line_load * 1e-3:.6g} N/mm: a Hertzian contact wider "
            "than the teeth)"
        )
        raise ValueError(
            f"mesh stiffness model {model.name!r} gave non-positive or non-finite values; "
            "check the tooth geometry (pointed or undercut teeth)" + load * model.hertz
        )
    return s, k
