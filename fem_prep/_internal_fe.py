"""Plane-strain FE model of an internal gear's teeth on their ring (``fe2d`` for internal
pairs; docs/planetary.md, "Internal gears").

The transverse section of a ring, per unit face width, plane strain: ``n_teeth`` internal teeth
(pointing inwards, tip circle r_a inside root circle r_f) of the ring's tooth form
(:class:`~fem_prep.InternalToothProfile`: the one its cutter generates where the geometry has
one, else the stand-in circular fillet) on the complete ring ``r_f <= r <= R``, its outer face
R (``rim_radius``) clamped (a ring held in a stiff housing), the teeth outside the modelled
sector left off, as the external model (:mod:`fem_prep._tooth_fe`) does with its bore.  With
:class:`~fem_prep.RingSegment` (root stress) a segment of the ring is kept, its radial sides
clamped and its outer face free: a thin ring between its supports.

Mesh.  The mapped mesh of the external model is built for the radial mirror of the tooth,
r' = R + r_a − r (the same half angles ψ at the mirrored radii: an external tooth of root r' =
R + r_a − r_f on a ring whose bore r' = r_a is the clamped face), and its vertices are mapped
back, r = R + r_a − r' at the same polar angle; the straight-edged quadratic triangles are those
of the actual geometry (only the vertices are mapped), and the element size at the teeth
differs from the requested one by the ratio r/r' (within a few per cent for a ring).

Load and measure (as the external model, Weber's decomposition).  A unit force per unit face
width acts on the middle tooth's concave right flank at the contact point of the ring's roll
distance ρ (from its base tangent point T, :meth:`jaxgear.InternalGearPair.roll_distance`),
along the line of action CT, into the tooth (direction C − T: towards the tooth centre line and
outwards).  The compliance is the displacement, along the load, of the point M where the line of
action crosses the tooth centre line; near the ring's root M lies in the rim, just outside the
root circle (about 0.4 m_n at the form circle of a standard 20° tooth).  ``compliance_tooth``
subtracts the rigid motion of the root section (least squares on a line just outside the root
circle between the fillet/root-circle tangency points) at M.

NumPy/SciPy/scikit-fem (never JAX); a constant for jaxgear.
"""

from __future__ import annotations

import math

import numpy as np
import skfem

from ._root_stress import ClampedBore, RimSupport
from ._tooth_fe import (
    DEFAULT_N_TEETH,
    SectorMesh,
    SectorModel,
    ToothCompliance,
    _load_geometry,
    _root_chord,
    mesh_sector,
    tabulate,
    tooth_compliance,
)
from ._internal_tooth import ShaperFillet
from ._tooth_profile import FilletForm, InternalCircularFillet, InternalToothProfile, tooth_profile
from .tooth_form import InternalToothGeometry

__all__ = ["DEFAULT_RING_DEPTH"]

#: default ring depth below the root circle, R − r_f, in normal modules (a ring that is solid in
#: ISO 6336-3's sense, s_R > 1.2 h_t, as the external root-stress model's 3.5 m_n rim)
DEFAULT_RING_DEPTH = 3.5


@tooth_profile.register
def _internal_tooth_profile(
    geometry: InternalToothGeometry, *, form: FilletForm | None = None
) -> InternalToothProfile:
    """The transverse tooth form of an internal gear: an :class:`InternalToothProfile` (``form``:
    a :class:`FilletForm` whose ``table`` takes an :class:`~fem_prep.InternalToothGeometry`;
    ``None``: the form the geometry's ``cutter`` generates, :class:`~fem_prep.ShaperFillet`,
    where it has one, else the stand-in :class:`~fem_prep.InternalCircularFillet`).

    Raises:
        ValueError: ``form`` not a :class:`FilletForm`; a cutter that cannot cut the ring
            (:func:`~fem_prep.generate_internal_tooth`'s one line).
    """
    if form is None:
        form = InternalCircularFillet() if geometry.cutter is None else ShaperFillet()
    if not isinstance(form, FilletForm):
        raise ValueError(f"form = {form!r}; use a fem_prep fillet form of an internal tooth")
    tab = form.table(geometry)
    return InternalToothProfile(
        teeth=abs(geometry.teeth),
        root_half_angle=float(tab["psi_tab"][-1]),
        source=str(form),
        **tab,
    )


def _map_back(p: np.ndarray, c: float) -> np.ndarray:
    """Points (n, 2) of the mirrored plane mapped to r = c − r' at the same polar angle."""
    r = np.hypot(p[:, 0], p[:, 1])
    return p * ((c - r) / r)[:, None]


@mesh_sector.register
def _mesh_internal(
    prof: InternalToothProfile,
    rim_radius: float,
    size: float,
    *,
    n_teeth: int = DEFAULT_N_TEETH,
    growth: float = 1.3,
    max_ratio: float = 10.0,
) -> SectorMesh:
    """Mesh ``n_teeth`` internal teeth on the ring ``r_f <= r <= rim_radius`` (full circle;
    module docstring).  ``flank``: the loaded tooth's right flank from the tip corner to r_P
    (increasing radii); ``split_radius`` r_P; ``rim_radius`` the outer face R.

    Raises:
        ValueError: ``rim_radius`` not above r_f, non-positive ``size`` or ``n_teeth``.
    """
    rf = prof.root_radius
    if not (math.isfinite(rim_radius) and rim_radius > rf):
        raise ValueError(
            f"rim_radius = {rim_radius!r} m is out of range: allowed > {rf:.6g} (the ring's root "
            "radius; its outer face)"
        )
    c = float(rim_radius) + prof.tip_radius
    sm = mesh_sector(
        prof.mirrored(c),
        c - rim_radius,
        size,
        n_teeth=n_teeth,
        growth=growth,
        max_ratio=max_ratio,
    )
    p = _map_back(sm.mesh.p.T, c)
    mesh = skfem.MeshTri(p.T.copy(), sm.mesh.t[[0, 2, 1]].copy())  # mirrored: reorient
    return SectorMesh(
        mesh=mesh,
        profile=prof,
        rim_radius=float(rim_radius),
        size=sm.size,
        n_teeth=sm.n_teeth,
        split_radius=c - sm.split_radius,
        flank=_map_back(sm.flank, c)[::-1],
    )


@_load_geometry.register
def _internal_load_geometry(prof: InternalToothProfile, rho: np.ndarray):
    """Contact point C on the concave right flank at roll distance ρ, the load direction n =
    (C − T)/ρ (into the tooth, along the line of action; T the base tangent point at polar
    angle ψ(r_c) + α_c) and the measuring point M (line of action ∩ tooth centre line)."""
    rb = prof.base_radius
    r_c = np.hypot(rho, rb)
    psi_c = prof.psi(r_c)
    phi_t = psi_c + np.arctan2(rho, rb)
    C = np.stack([r_c * np.sin(psi_c), r_c * np.cos(psi_c)], -1)
    T = rb * np.stack([np.sin(phi_t), np.cos(phi_t)], -1)
    n = (C - T) / np.asarray(rho, dtype=float)[..., None]
    s = -C[:, 0] / n[:, 0]
    return C, n, C + s[:, None] * n


@_root_chord.register
def _internal_root_chord(prof: InternalToothProfile, size: float, n: int = 16):
    """Gauss points and weights on the root section of the internal tooth 0: the external
    chord of the mirrored tooth, mapped back (a line just outside the root circle between the
    fillet/root-circle tangency points)."""
    c = prof.root_radius + 4 * size
    q, w = _root_chord(prof.mirrored(c), size, n)
    return _map_back(q, c), w


@tooth_compliance.register
def _internal_tooth_compliance(
    geometry: InternalToothGeometry,
    *,
    rim_radius: float | None = None,
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
    size: float | None = None,
    model: SectorModel | None = None,
    use_cache: bool = True,
    progress: bool | None = False,
    support: RimSupport | None = None,
) -> ToothCompliance:
    """Plane-strain FE compliance of a ring's tooth + ring along its concave involute (cached;
    module docstring), at roll distances from the tip circle to the form circle (increasing).

    Args:
        geometry: the ring (:class:`fem_prep.InternalToothGeometry`).
        rim_radius: the ring's outer radius R (m, > r_f), clamped; default r_f + 3.5 m_n
            (:data:`DEFAULT_RING_DEPTH`).
        youngs_modulus, poisson_ratio, size, use_cache, progress: as the external model's.
        model: :class:`SectorModel`; its ``form`` a fillet form of an internal tooth (``None``:
            the generated :class:`~fem_prep.ShaperFillet` where ``geometry`` has a cutter, else
            the stand-in :class:`~fem_prep.InternalCircularFillet`).
        support: how the ring is held: :class:`~fem_prep.ClampedBore` (``None``, the default:
            its outer face clamped, a ring in a stiff housing) or :class:`~fem_prep.RingSegment`
            (a segment of ``pitches`` pitches, its radial sides clamped, its outer face free: a
            ring that bends between supports ``pitches`` pitches apart, the loaded tooth in the
            middle; ``model.n_teeth`` is then ``pitches``).

    Returns:
        The :class:`ToothCompliance` (``rim_radius`` the outer face; ``roll`` increasing from
        the tip roll to the form roll).

    Raises:
        ValueError: ``rim_radius`` not above r_f, a non-positive size, fewer than 4 roll
            positions, a fillet form that does not take an internal tooth, a ``support`` that
            is not a :class:`~fem_prep.RimSupport` or a segment of ``pitches`` >= |z|.
    """
    support = ClampedBore() if support is None else support
    if not isinstance(support, RimSupport):
        raise ValueError(f"support = {support!r}; use fem_prep.ClampedBore() or RingSegment()")
    model = SectorModel() if model is None else model
    model = SectorModel(support.teeth(model.n_teeth), model.n_roll, model.form)
    prof = tooth_profile(geometry, form=model.form)
    mn = geometry.normal_module
    rim = prof.root_radius + DEFAULT_RING_DEPTH * mn if rim_radius is None else float(rim_radius)
    if not (math.isfinite(rim) and rim > prof.root_radius):
        raise ValueError(
            f"rim_radius = {rim!r} m is out of range: allowed > {prof.root_radius:.6g} (the "
            "ring's root radius; its outer face)"
        )
    extra = {"internal": True, "cutter": repr(geometry.cutter), "support": repr(support)}
    material = (youngs_modulus, poisson_ratio)
    options = (use_cache, progress, support.hold)
    return tabulate(geometry, prof, rim, material, size, model, options, extra)
