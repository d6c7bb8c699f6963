"""Tooth-root stress along the fillet from the plane FE tooth model (docs/rating.md, "FE root
stress").

The transverse section of one member, per unit face width, in plane strain: the mesh of the FE
tooth compliance (:func:`fem_prep.mesh_sector`: ``n_teeth`` teeth of the exact rack-generated
tooth form on the rim ring, clamped at the rim's inner radius; quadratic triangles). A force of
1 N per m of face width acts on the middle tooth's right flank at a given radius, along the
transverse line of action (normal to the involute, into the tooth): the tooth bends towards its
left, so the right (loaded-side) fillet is the tensile one, the fillet ISO 6336-3 rates.

Stress: σ = λ tr(ε) I + 2 μ ε of the quadratic solution, linear in each triangle, averaged at
the mesh vertices over the triangles that share them (area-weighted; the raw element stress
spikes where the mesh's rim and tooth blocks meet in the fillet, the averaged one converges
monotonically from below) and interpolated linearly in the triangle holding each point of the
right fillet (the ψ(r) table of the tooth form, from the root circle
to the form circle). At a traction-free surface the stress is uniaxial along the surface: the
tangential normal stress σ_t = tᵀσt and the largest principal stress σ₁ coincide there up to the
recovery error (both are returned; their difference is a measure of it).

The section (:class:`RootSection`): :class:`TransverseSection` (the member's own) or
:class:`NormalSection` (ISO 6336-3's virtual spur gear of a helical member, z_n = z/(cos² β_b
cos β), loaded at the same height on the tooth, per unit length along the helix). The rim
(:class:`RimSupport`): :class:`ClampedBore` (the ring clamped at its inner radius, a solid
blank) or :class:`RingSegment` (a segment of the ring of a few pitches, its sides clamped, its
bore free: a thin rim that bends; docs/rating.md, "Root stress of a thin rim").

Plane strain and plane stress give the same in-plane stresses for a body loaded by tractions
alone; the clamp makes a small difference (Poisson's ratio enters), so ``poisson_ratio`` is an
argument. Stresses are linear in the load: multiply by the load per unit face width (N/m).

An :class:`~fem_prep.InternalToothGeometry` (a ring's tooth) is modelled the same way on its ring
(:mod:`fem_prep._internal_fe`): the rim lies outside the root circle, :class:`ClampedBore` clamps
the ring's outer face, :class:`RingSegment` holds a segment by its sides (transverse section only).

Everything here is NumPy/SciPy/scikit-fem (fem_prep never imports JAX).

Source of the comparison: ISO 6336-3:2019, method B (σ_F0 = F_t/(b m_n) Y_F Y_S at the 30°
tangent section, load at the outer point of single pair tooth contact).
"""

from __future__ import annotations

import abc
import math
from dataclasses import dataclass

import numpy as np
import skfem
from skfem.helpers import ddot, eye, sym_grad, trace
from skfem.models.elasticity import lame_parameters, linear_elasticity

from ._solver import factorize
from ._tooth_fe import _load_geometry, _on_flank, mesh_sector, rim_face
from ._tooth_profile import FilletForm, ToothProfile, tooth_profile
from .tooth_form import ToothGeometry

__all__ = [
    "ClampedBore",
    "FilletInfluence",
    "FilletStress",
    "NormalSection",
    "PlaneStrainStress",
    "RimSupport",
    "RingSegment",
    "RootSection",
    "TransverseSection",
    "WebbedRim",
    "fillet_influence",
    "fillet_stress",
    "plane_strain_stress",
]

DEFAULT_ELEMENTS_PER_MODULE = 18.0  # element size m_n/18 at the teeth: peak within 0.1 % of m_n/27
DEFAULT_RIM_DEPTH = 3.5  # rim depth below the root circle, in modules (s_R/h_t ≈ 1.5: solid)
FILLET_FE_VERSION = 1  # of cached_fillet_influence's tables: bump when their values change


class PlaneStrainStress:
    """A plane-strain solution under a point load and its stress field.

    Build with :func:`plane_strain_stress`; :meth:`stress` reads the stress tensor at points:
    the quadratic solution's stress at the vertices of each (straight-edged) triangle, averaged
    at every mesh vertex over its triangles weighted by their areas (``smooth``; else the
    element's own), interpolated linearly in the triangle holding the point.

    Attributes:
        n_dofs: degrees of freedom of the quadratic solution.
    """

    def __init__(
        self,
        mesh,
        vertex_stress: np.ndarray,
        n_dofs: int,
        smooth: bool = True,
        *,
        basis=None,
        displacement=None,
    ):
        self._mesh = mesh
        self.basis = basis  # the vector P2 basis of the solution
        self.displacement = displacement  # its dof vector (m per N/m of load)
        self._vertex_stress = vertex_stress  # (3 components, 3 vertices, n_elements)
        self.n_dofs = n_dofs
        if smooth:
            t = mesh.t
            p = mesh.p
            area = 0.5 * np.abs(
                (p[0, t[1]] - p[0, t[0]]) * (p[1, t[2]] - p[1, t[0]])
                - (p[0, t[2]] - p[0, t[0]]) * (p[1, t[1]] - p[1, t[0]])
            )
            num = np.zeros((3, p.shape[1]))
            den = np.zeros(p.shape[1])
            for v in range(3):
                np.add.at(num.T, t[v], (vertex_stress[:, v, :] * area).T)
                np.add.at(den, t[v], area)
            nodal = num / den
            self._vertex_stress = nodal[:, t]

    def stress(self, points: np.ndarray) -> np.ndarray:
        """The stress tensor (Pa, per unit load) at ``points`` (n, 2) inside the mesh, shape
        (n, 2, 2)."""
        pts = np.asarray(points, dtype=float)
        cells = self._mesh.element_finder()(pts[:, 0], pts[:, 1])
        v = self._mesh.p[:, self._mesh.t[:, cells]]  # (2, 3, n)
        a, b, c = v[:, 0], v[:, 1], v[:, 2]
        det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        l1 = ((pts[:, 0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (pts[:, 1] - a[1])) / det
        l2 = ((b[0] - a[0]) * (pts[:, 1] - a[1]) - (pts[:, 0] - a[0]) * (b[1] - a[1])) / det
        lam = np.stack([1 - l1 - l2, l1, l2])  # (3, n) barycentric
        sxx, syy, sxy = np.einsum("vn,kvn->kn", lam, self._vertex_stress[:, :, cells])
        return np.stack([np.stack([sxx, sxy], -1), np.stack([sxy, syy], -1)], -2)


def _solve(mesh, lam, mu, clamped, load_points, load_dirs, thickness=None):
    """Quadratic plane-strain displacements (dof vectors, (n_dofs, n_loads)) under unit point
    forces (one load case each, one factorisation). ``thickness``: None (uniform), or the
    thickness ratio as a function of the radius (m) at the quadrature points."""
    if thickness is None:
        ib = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTriP2()))
        K = skfem.asm(linear_elasticity(lam, mu), ib)
    else:
        ib = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTriP2()), intorder=6)

        @skfem.BilinearForm
        def form(u, v, w):
            c = thickness(np.hypot(w.x[0], w.x[1]))
            e = sym_grad(u)
            return c * ddot(2 * mu * e + lam * eye(trace(e), 2), sym_grad(v))

        K = form.assemble(ib)
    sb = skfem.Basis(mesh, skfem.ElementTriP2())
    fixed = ib.get_dofs(clamped).all()
    free = np.setdiff1d(np.arange(ib.N), fixed)
    pl = sb.probes(np.asarray(load_points, dtype=float).T).tocoo()  # (n_loads, n_scalar)
    F = np.zeros((ib.N, len(load_points)))
    for c in (0, 1):
        np.add.at(F, (2 * pl.col + c, pl.row), pl.data * load_dirs[pl.row, c])
    U = np.zeros_like(F)
    U[free] = factorize(K[free][:, free].tocsc()).solve(F[free])
    return ib, U


def plane_strain_stress(
    mesh,
    youngs_modulus: float,
    poisson_ratio: float,
    clamped,
    load_point: np.ndarray,
    load_dir: np.ndarray,
) -> PlaneStrainStress:
    """Solve a plane-strain body under one point force (1 N per m of thickness) and recover
    its stress field (module docstring).

    Args:
        mesh: scikit-fem ``MeshTri`` (m). youngs_modulus: E (Pa). poisson_ratio: ν.
        clamped: predicate on facet midpoints ``x`` (shape (2, n)) → mask of the clamped facets.
        load_point: (2,) point of the force (m), in the mesh. load_dir: (2,) unit direction.

    Returns:
        The :class:`PlaneStrainStress` (stresses in Pa per N/m of load).
    """
    lam, mu = lame_parameters(youngs_modulus, poisson_ratio)
    ib, U = _solve(
        mesh, lam, mu, clamped, np.reshape(load_point, (1, 2)), np.reshape(load_dir, (1, 2))
    )
    u = U[:, 0]
    return PlaneStrainStress(
        mesh, _vertex_stress(mesh, u, lam, mu), int(ib.N), basis=ib, displacement=u
    )


def _vertex_stress(mesh, u, lam, mu):
    """The stress (3 components, 3 vertices, n_elements) of the quadratic field ``u`` at the
    vertices of every triangle (reference points (0,0), (1,0), (0,1))."""
    at_vertices = skfem.Basis(
        mesh,
        skfem.ElementVector(skfem.ElementTriP2()),
        quadrature=(np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]), np.full(3, 1 / 6)),
    )
    grad = at_vertices.interpolate(u).grad  # (2, 2, n_elements, 3): ∂u_i/∂x_j
    exx, eyy = grad[0, 0], grad[1, 1]
    exy = 0.5 * (grad[0, 1] + grad[1, 0])
    tr = exx + eyy
    comps = np.stack([lam * tr + 2 * mu * exx, lam * tr + 2 * mu * eyy, 2 * mu * exy])
    return np.transpose(comps, (0, 2, 1))


@dataclass(frozen=True)
class FilletStress:
    """The stress along the right (tensile) fillet of the loaded tooth, per unit load, at the
    midpoints of the mesh's boundary edges from the middle of the tooth space (root land) to
    the form circle.

    Attributes:
        radius: (n,) radii of the points (m).
        points: (n, 2) the points (m; tooth centre line on +y, gear centre at the origin).
        tangent_angle: (n,) angle between the boundary's tangent and the tooth centre line
            (rad): π/2 on the root land, falling towards the flank; ISO's critical section is
            where it is 30° (π/6).
        sigma_t: (n,) the surface stress along the boundary (Pa per N/m of load, tension > 0),
            from the quadratic solution's tangential strain at the edge midpoint (the chord
            strain between the edge's end nodes: a central difference, O(h²)). At the
            traction-free surface it is the largest principal stress wherever it is tensile.
        sigma_1: (n,) largest principal stress of the vertex-averaged stress field just inside
            the edge (Pa per N/m; a cross-check of the recovery: it converges from below).
        load_radius: r (m) of the load point. load_point: (2,) (m). load_dir: (2,) unit.
        size: element size at the teeth (m). n_dofs: degrees of freedom.
    """

    radius: np.ndarray
    points: np.ndarray
    tangent_angle: np.ndarray
    sigma_t: np.ndarray
    sigma_1: np.ndarray
    load_radius: float
    load_point: np.ndarray
    load_dir: np.ndarray
    size: float
    n_dofs: int

    def _vertex(self):
        """Index of the largest σ_t and the parabola through it and its two neighbours (in arc
        length): the peak's value and its position's fraction between the neighbours."""
        k = int(np.clip(np.argmax(self.sigma_t), 1, len(self.sigma_t) - 2))
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(self.points, axis=0), axis=1))])
        c = np.polyfit(s[k - 1 : k + 2] - s[k], self.sigma_t[k - 1 : k + 2], 2)
        x = -c[1] / (2 * c[0]) if c[0] < 0 else 0.0
        x = float(np.clip(x, s[k - 1] - s[k], s[k + 1] - s[k]))
        return k, float(np.polyval(c, x)), x

    @property
    def peak(self) -> float:
        """The largest tensile surface stress on the fillet (Pa per N/m of load): the maximum
        of :attr:`sigma_t`, refined by a parabola through it and its neighbours."""
        return self._vertex()[1]

    @property
    def peak_tangent_angle(self) -> float:
        """The tangent angle (rad) at the largest :attr:`sigma_t`."""
        return float(self.tangent_angle[self._vertex()[0]])


def _fillet_edges(m, sm, prof: ToothProfile):
    """The boundary edges of the loaded tooth's right fillet and root land (from the middle of
    the space to the form circle) of the mesh ``m``, ordered from the space towards the flank:
    their end vertex indices (2, n), midpoints (n, 2) and the centroids (n, 2) of their
    triangles."""
    bf = m.boundary_facets()
    ends = m.facets[:, bf]
    mid = 0.5 * (m.p[:, ends[0]] + m.p[:, ends[1]])
    r = np.hypot(mid[0], mid[1])
    psi = np.arctan2(mid[0], mid[1])
    rf = prof.root_radius  # between the root and the form circle (external or internal)
    sel = (psi > 0) & (psi < math.pi / prof.teeth) & (np.abs(r - rf) < abs(prof.form_radius - rf))
    order = np.argsort(-psi[sel])
    cells = m.f2t[0, bf[sel][order]]
    centroid = m.p[:, m.t[:, cells]].mean(axis=1)
    return ends[:, sel][:, order], mid[:, sel][:, order].T, centroid.T


def _surface_stress(m, ib, U, ends, poisson_ratio):
    """σ_t (Pa per N/m) at the midpoints of the boundary edges ``ends`` for the displacement
    columns ``U``: the chord strain of the quadratic field is its tangential strain at the edge
    midpoint (a central difference, O(h²)); at the free surface σ_n = τ = 0 and ε_z = 0, so
    σ_t = E ε_t/(1 − ν²), E = 1 here (the stresses do not depend on E). Shape (n_loads, n)."""
    a, b = m.p[:, ends[0]].T, m.p[:, ends[1]].T
    length = np.linalg.norm(b - a, axis=1)
    t = (b - a) / length[:, None]
    ud = U[ib.nodal_dofs]  # (2, n_vertices, n_loads)
    du = ud[:, ends[1]] - ud[:, ends[0]]  # (2, n, n_loads)
    strain = np.einsum("cnl,nc->ln", du, t) / length
    return strain / (1 - poisson_ratio**2), t


# ------------------------------------------------------------------------------------------
# the section of the tooth that is modelled, and how its rim is held


class RootSection(abc.ABC):
    """Which plane section of a member's tooth the plane FE model takes for a root-stress map:
    the tooth it meshes, where a load at a transverse radius sits on it, and the model's load per
    unit thickness for a unit transverse line load (docs/rating.md, "Helical teeth")."""

    name: str

    @abc.abstractmethod
    def tooth(self, geometry: ToothGeometry) -> ToothGeometry:
        """The tooth the plane model meshes."""

    @abc.abstractmethod
    def radius(self, geometry: ToothGeometry, radius):
        """The radius (m) on :meth:`tooth` of a load at the transverse ``radius`` (m)."""

    @abc.abstractmethod
    def load_scale(self, geometry: ToothGeometry) -> float:
        """The model's load per unit thickness (N/m) for a transverse line load of 1 N/m."""

    def __repr__(self) -> str:
        return f"{type(self).__name__}()"


class TransverseSection(RootSection):
    """The member's own transverse section (its tooth, its radii, the load as it is)."""

    name = "transverse"

    def tooth(self, geometry):
        return geometry

    def radius(self, geometry, radius):
        return np.asarray(radius, dtype=float)

    def load_scale(self, geometry):
        return 1.0


class NormalSection(RootSection):
    """ISO 6336-3's normal section: the virtual spur gear (:meth:`ToothGeometry.virtual_spur`,
    z_n = z/(cos² β_b cos β)), a load at its height on the tooth (the virtual radii are the
    transverse ones shifted by r_n − r, ISO's d_an = d_n + d_a − d), and per unit length of the
    tooth along its helix: a transverse line load w per unit face width is a normal load
    w/cos β_b per unit face width, w cos β/cos β_b per unit length along the helix (a face
    width b is b/cos β of tooth). A spur gear's is its transverse section exactly."""

    name = "normal"

    def tooth(self, geometry):
        if not isinstance(geometry, ToothGeometry):
            raise ValueError(
                f"section = NormalSection() is out of range for {type(geometry).__name__}: "
                "allowed TransverseSection() (an internal tooth's normal section is not built)"
            )
        return geometry.virtual_spur()

    def radius(self, geometry, radius):
        v = geometry.virtual_spur()
        shift = v.teeth * v.normal_module / 2
        shift -= geometry.teeth * geometry.normal_module / (2 * math.cos(geometry.helix_angle))
        return np.asarray(radius, dtype=float) + shift

    def load_scale(self, geometry):
        beta = geometry.helix_angle
        beta_b = math.asin(math.sin(beta) * math.cos(geometry.normal_pressure_angle))
        return math.cos(beta) / math.cos(beta_b)


class RimSupport(abc.ABC):
    """How the plane model holds its rim: :class:`ClampedBore` (a solid blank),
    :class:`RingSegment` (a thin rim that bends between clamped cuts) or :class:`WebbedRim`
    (a thin rim on a web)."""

    def inner_radius(self, rim_radius: float) -> float:
        """The radius (m) the mesh reaches down to, for a rim whose inner radius is
        ``rim_radius``."""
        return rim_radius

    def thickness(self, rim_radius: float):
        """None (a uniform thickness), or the thickness over the face width's as a function
        of the radius (m)."""
        return None

    @abc.abstractmethod
    def teeth(self, n_teeth: int) -> int:
        """The teeth to mesh, given the caller's ``n_teeth``."""

    @abc.abstractmethod
    def hold(self, sm):
        """The meshed model from the full-ring :class:`SectorMesh` ``sm``: ``(mesh,
        clamped)``, ``clamped`` a predicate on facet midpoints (2, n)."""


@dataclass(frozen=True)
class ClampedBore(RimSupport):
    """The complete rim ring clamped at its inner radius (the default: a solid blank in ISO's
    sense when the rim is deep, s_R/h_t > 1.2)."""

    def teeth(self, n_teeth):
        return n_teeth

    def hold(self, sm):
        return sm.mesh, rim_face(sm)


@dataclass(frozen=True)
class RingSegment(RimSupport):
    """A segment of the rim ring of ``pitches`` pitches (odd, >= 3: the loaded tooth in the
    middle, the segment's radial sides through the middles of tooth spaces), its two sides
    clamped and its bore free: the rim of thickness s_R = r_f − ``rim_radius`` bends between
    the sides as a curved beam on the supports of a web or spokes ``pitches`` pitches apart
    (the tooth-on-rim model of thin-rimmed gears; docs/rating.md, "Root stress of a thin rim").

    Raises:
        ValueError: ``pitches`` not an odd integer >= 3.
    """

    pitches: int = 5

    def __post_init__(self):
        n = self.pitches
        if not (isinstance(n, int) and n >= 3 and n % 2 == 1):
            raise ValueError(f"RingSegment: pitches = {n!r} is out of range, allowed odd >= 3")

    def teeth(self, n_teeth):
        return self.pitches

    def hold(self, sm):
        z = sm.profile.teeth
        if self.pitches >= z:
            raise ValueError(
                f"RingSegment: pitches = {self.pitches!r} is out of range, allowed < z = {z:g}"
            )
        half = math.pi * self.pitches / z
        m = sm.mesh
        centre = m.p[:, m.t].mean(axis=1)
        outside = np.nonzero(np.abs(np.arctan2(centre[0], centre[1])) > half)[0]
        mesh = m.remove_elements(outside)
        tol = 1e-9 * half
        return mesh, lambda x: np.abs(np.abs(np.arctan2(x[0], x[1])) - half) < tol


@dataclass(frozen=True)
class WebbedRim(RimSupport):
    """The whole rim ring on a web: below the rim's inner radius a web of ``web`` times the
    face width (plane stiffness scaled by it) reaches down to ``bore`` times that radius,
    where it is clamped (a central web seen in the transverse plane, in-plane: it holds the
    rim's bore radially and tangentially all round, with a stiffness that falls with its
    thickness). The web's edge is smeared over the elements that straddle the rim's inner
    radius (each quadrature point takes the thickness of its radius).

    Raises:
        ValueError: ``web`` outside (0, 1] or ``bore`` outside (0.1, 1).
    """

    web: float = 0.25
    bore: float = 0.5

    def __post_init__(self):
        if not 0 < self.web <= 1:
            raise ValueError(f"WebbedRim: web = {self.web!r} is out of range, allowed (0, 1]")
        if not 0.1 < self.bore < 1:
            raise ValueError(f"WebbedRim: bore = {self.bore!r} is out of range, allowed (0.1, 1)")

    def teeth(self, n_teeth):
        return n_teeth

    def inner_radius(self, rim_radius):
        return self.bore * rim_radius

    def hold(self, sm):
        return ClampedBore().hold(sm)

    def thickness(self, rim_radius):
        web = self.web
        return lambda r: np.where(r < rim_radius, web, 1.0)


def _sector(geometry, size, rim_radius, n_teeth, form, support=None):
    """The tooth profile, the meshed model ``(mesh, clamped, sm, thickness)`` and the element
    size."""
    support = ClampedBore() if support is None else support
    if not isinstance(support, RimSupport):
        raise ValueError(
            f"support = {support!r}; use fem_prep.ClampedBore(), RingSegment() or WebbedRim()"
        )
    prof = tooth_profile(geometry, form=form)
    mn = geometry.normal_module
    size = mn / DEFAULT_ELEMENTS_PER_MODULE if size is None else float(size)
    if rim_radius is None:  # the rim below an external tooth's root, above an internal one's
        depth = math.copysign(DEFAULT_RIM_DEPTH * mn, prof.root_radius - prof.tip_radius)
        rim_radius = max(prof.root_radius + depth, 0.2 * prof.root_radius)
    inner = support.inner_radius(rim_radius)
    sm = mesh_sector(prof, inner, size, n_teeth=support.teeth(n_teeth))
    mesh, clamped = support.hold(sm)
    return prof, (mesh, clamped, sm, support.thickness(rim_radius)), size


def _check_radii(prof, radii, where):
    lo, hi = sorted((prof.form_radius, prof.tip_radius))
    bad = radii[(radii < lo) | (radii > hi)]
    if len(bad):
        raise ValueError(
            f"{where}: load_radius = {float(bad[0])!r} m is out of range, allowed "
            f"[{lo:.6g}, {hi:.6g}] (the involute, between the form and the tip circle)"
        )


@dataclass(frozen=True)
class FilletInfluence:
    """The fillet surface stress of one tooth for unit loads at several flank radii: the
    influence of a load's position on the root stress (per unit face width).

    Attributes:
        load_radius: (n_loads,) radii of the loads on the member's transverse flank (m),
            increasing.
        roll: (n_loads,) their roll distances from the base tangent point (m), transverse.
        sigma_t: (n_loads, n) the surface stress at the fillet points (Pa per N/m of transverse
            line load, the load map's w), as :attr:`FilletStress.sigma_t`; in the normal section
            the virtual tooth's stress times :meth:`RootSection.load_scale`.
        points: (n, 2) the fillet points of the modelled tooth (m). tangent_angle: (n,) (rad).
        size: element size (m). n_dofs: degrees of freedom.
        model_radius: (n_loads,) the loads' radii on the modelled tooth (m; the virtual spur
            tooth's in the normal section). section: the :class:`RootSection`'s name.
        cache_hit: whether the table came from the disk cache. key: its cache key (""
            uncached); both set by :func:`fem_prep.cached_fillet_influence`.
    """

    load_radius: np.ndarray
    roll: np.ndarray
    sigma_t: np.ndarray
    points: np.ndarray
    tangent_angle: np.ndarray
    size: float
    n_dofs: int
    model_radius: np.ndarray | None = None
    section: str = "transverse"
    cache_hit: bool = False
    key: str = ""

    @property
    def peak(self) -> np.ndarray:
        """(n_loads,) the largest fillet stress of each unit load (Pa per N/m)."""
        return np.max(self.sigma_t, axis=1)


def _unit_loads(prof, model, radii, poisson_ratio):
    """σ_t (n_loads, n) of unit loads at ``radii`` on the modelled tooth, the fillet edges'
    midpoints, tangents and the solve (one factorisation)."""
    rho = np.sqrt(radii**2 - prof.base_radius**2)
    _c, n, _m = _load_geometry(prof, rho)
    mesh, clamped, sm, thickness = model
    loads = _on_flank(sm.flank, radii, 1e-9 * sm.size)
    lam, mu = lame_parameters(1.0, poisson_ratio)
    ib, U = _solve(mesh, lam, mu, clamped, loads, n, thickness)
    ends, mid, centroid = _fillet_edges(mesh, sm, prof)
    sigma_t, t = _surface_stress(mesh, ib, U, ends, poisson_ratio)
    return sigma_t, mid, t, ib, U, (ends, centroid, loads, n)


def fillet_influence(
    geometry: ToothGeometry,
    load_radii,
    *,
    size: float | None = None,
    rim_radius: float | None = None,
    n_teeth: int = 1,
    poisson_ratio: float = 0.3,
    form: FilletForm | None = None,
    section: RootSection | None = None,
    support: RimSupport | None = None,
) -> FilletInfluence:
    """The tensile fillet's surface stress for a unit load at each of ``load_radii`` (m, on
    the member's transverse involute flank, [r_F, r_a]): one factorisation, one load case per
    radius; the model and the other arguments as :func:`fillet_stress`. A load history on the
    tooth (one contact point per transverse slice) gives the slice's fillet stress as the load
    per unit face width times the row of its position (interpolated between the radii): the
    root-stress map (docs/rating.md).

    ``section``: :class:`TransverseSection` (the default: the member's transverse section) or
    :class:`NormalSection` (ISO's virtual spur gear of a helical member, loaded at the same
    height on the tooth, the load per unit length along the helix; the same as the transverse
    section for a spur gear). The mapped radii are held within the virtual tooth's [r_Fn, r_an]
    (its form circle differs from the shifted transverse one by less than 1e-3 m_n)."""
    section = TransverseSection() if section is None else section
    if not isinstance(section, RootSection):
        raise ValueError(
            f"section = {section!r}; use fem_prep.TransverseSection() or NormalSection()"
        )
    radii = np.sort(np.atleast_1d(np.asarray(load_radii, dtype=float)))
    _check_radii(tooth_profile(geometry, form=form), radii, "fillet_influence")
    model = section.tooth(geometry)
    prof, fe, size = _sector(model, size, rim_radius, n_teeth, form, support)
    on_model = np.clip(
        section.radius(geometry, radii), *sorted((prof.form_radius, prof.tip_radius))
    )
    sigma_t, mid, t, ib, _u, _rest = _unit_loads(prof, fe, on_model, poisson_ratio)
    base = tooth_profile(geometry, form=form).base_radius
    return FilletInfluence(
        load_radius=radii,
        roll=np.sqrt(radii**2 - base**2),
        sigma_t=sigma_t * section.load_scale(geometry),
        points=mid,
        tangent_angle=np.arccos(np.clip(np.abs(t[:, 1]), 0.0, 1.0)),
        size=size,
        n_dofs=int(ib.N),
        model_radius=on_model,
        section=section.name,
    )


def fillet_stress(
    geometry: ToothGeometry,
    load_radius: float,
    *,
    size: float | None = None,
    rim_radius: float | None = None,
    n_teeth: int = 1,
    poisson_ratio: float = 0.3,
    form: FilletForm | None = None,
    support: RimSupport | None = None,
) -> FilletStress:
    """Stress along the tensile fillet of a tooth loaded on its flank (module docstring).

    Args:
        geometry: the member's :class:`fem_prep.ToothGeometry` (its transverse section is
            modelled; for ISO's method B use the virtual spur gear of a helical one,
            ``geometry.virtual_spur()``).
        load_radius: radius (m) of the load point on the involute flank, in [r_F, r_a] (the
            outer point of single pair tooth contact for ISO's σ_F0).
        size: element size at the teeth (m); default m_n/18.
        rim_radius: the rim's inner radius (m); default r_f − 3.5 m_n (a solid blank in
            ISO's sense, s_R > 1.2 h_t).
        n_teeth: teeth modelled (odd: symmetric about the loaded one; the peak stress of 3
            teeth is within 0.05 % of 1 tooth's on the rim ring). poisson_ratio: ν.
        form: the fillet (:class:`fem_prep.TrochoidFillet`,
            the default, or :class:`fem_prep.CircularFillet`).
        support: how the rim is held: :class:`ClampedBore` (the default: the ring clamped at
            ``rim_radius``), :class:`RingSegment` (a segment of the ring, its sides clamped,
            its bore free: a thin rim that bends; ``n_teeth`` is then its ``pitches``) or
            :class:`WebbedRim` (the ring on a web below ``rim_radius``, clamped at its bore).

    Returns:
        :class:`FilletStress`, stresses in Pa per N/m of normal load (per unit face width):
        multiply by the load per unit face width (the stresses do not depend on E).

    Raises:
        ValueError: ``load_radius`` outside the involute [r_F, r_a], or a bad ``size``,
            ``rim_radius``, ``n_teeth``, ``support`` (named, with the allowed range).
    """
    prof, fe, size = _sector(geometry, size, rim_radius, n_teeth, form, support)
    _check_radii(prof, np.array([load_radius]), "fillet_stress")
    sigma_t, mid, t, ib, U, (_ends, centroid, loads, n) = _unit_loads(
        prof, fe, np.array([float(load_radius)]), poisson_ratio
    )
    mesh = fe[0]
    sigma_t = sigma_t[0]
    lam, mu = lame_parameters(1.0, poisson_ratio)
    vertex = _vertex_stress(mesh, U[:, 0], lam, mu)
    sol = PlaneStrainStress(mesh, vertex, int(ib.N), basis=ib, displacement=U[:, 0])
    sig = sol.stress(mid + 1e-3 * (centroid - mid))  # just inside the edge's triangle
    mean = 0.5 * (sig[:, 0, 0] + sig[:, 1, 1])
    rad = np.hypot(0.5 * (sig[:, 0, 0] - sig[:, 1, 1]), sig[:, 0, 1])
    angle = np.arccos(np.clip(np.abs(t[:, 1]), 0.0, 1.0))
    return FilletStress(
        radius=np.hypot(mid[:, 0], mid[:, 1]),
        points=mid,
        tangent_angle=angle,
        sigma_t=sigma_t,
        sigma_1=mean + rad,
        load_radius=float(load_radius),
        load_point=loads[0],
        load_dir=n[0],
        size=size,
        n_dofs=sol.n_dofs,
    )
