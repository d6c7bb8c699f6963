"""Plane-strain 2-D finite-element tooth compliance (``stiffness = "fe2d"``; docs/stiffness.md).

A transverse section of one gear member, per unit face width, plane strain: ``n_teeth`` teeth
(default 5) of the exact tooth form on the complete rim ring down to the bore (or a given rim
inner radius), clamped there.  The teeth outside the modelled sector are left off (they carry no
load and add little to the ring's stiffness; the result is independent of ``n_teeth`` within
0.3 % from 3 teeth on, see the tests).  Quadratic triangles (scikit-fem ``ElementTriP2`` on a
mapped, straight-edged ``MeshTri``), sparse Cholesky (:func:`fem_prep._solver.factorize`).

Loads and the compliance measure.  A unit force per unit face width acts on the middle tooth's
right flank at the contact point of roll distance ρ, along the transverse line of action
(normal to the involute, pushing into the tooth).  A point load on a 2-D continuum gives a
logarithmically infinite displacement under the load, so the displacement *at the load point*
does not converge under refinement.  As in Weber's (1949) decomposition used by ``weber``, the
tooth deflection is measured where the line of action crosses the tooth centre line (radius
``r_b / cos α_p``), projected on the load direction; that point is a regular point of the field
(its distance to the load is the depth d_i of the Hertzian formula), so the value converges,
and Weber's Hertzian approach (1.1) between the contact point and the two centre lines is added
analytically by jaxgear.  ``compliance`` is therefore bending + shear + compression of the tooth
+ the body (foundation, rim, ring torsion between bore and rim), per unit face width.

``compliance_tooth`` (the hybrid model's tooth-only compliance, the gear body being supplied by
a condensed FE body whose outer surface is the root circle) subtracts the rigid motion of the
tooth's root section: a least-squares translation + rotation of the displacements along the
root chord between the two fillet/root-circle tangency points (Sainsot's S_f), evaluated at the
measuring point and projected on the load direction.

The tooth form comes from :func:`fem_prep.tooth_form.generate_tooth` (the rack-generated
trochoidal fillet, :class:`~fem_prep.TrochoidFillet`); ``SectorModel(form=CircularFillet())``
selects the circular-arc fillet approximation that ``weber`` used before the rack-generated form
(kept for comparison: 1.6 % more compliant on ROSS's gear; :mod:`fem_prep._tooth_profile`). Results are cached (``cache_dir()/tooth_fe``, key = sha256 of the inputs and
:data:`TOOTH_FE_VERSION`), normalised by E (the compliance of a linear body clamped on part of its
boundary is exactly proportional to 1/E).

Internal teeth (a ring's): :mod:`fem_prep._internal_fe` registers their mesh, load geometry and
compliance on :func:`mesh_sector` and :func:`tooth_compliance`.  NumPy/SciPy/scikit-fem only.
"""

from __future__ import annotations

import functools
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp
import skfem
from scipy.spatial import cKDTree
from skfem.models.elasticity import lame_parameters, linear_elasticity
from tqdm import tqdm

from ._fe_cache import cache_key as _key, load_entry, store_entry, table_dir
from ._solver import factorize
from ._tooth_profile import FilletForm, ToothProfile, tooth_profile
from .tooth_form import ToothGeometry

__all__ = [
    "TOOTH_FE_VERSION",
    "SectorMesh",
    "SectorModel",
    "ToothCompliance",
    "mesh_sector",
    "plane_strain_point_loads",
    "tooth_compliance",
]

TOOTH_FE_VERSION = 2  # 2: equal diagonals split one way (the mesh no longer flips with rounding)
DEFAULT_ELEMENTS_PER_MODULE = 6.0  # default element size m_n / 6 at the teeth
DEFAULT_N_TEETH = 5
DEFAULT_N_ROLL = 33


# ------------------------------------------------------------------------------------------
# the mapped mesh


@dataclass(frozen=True)
class SectorMesh:
    """Straight-edged triangle mesh of ``n_teeth`` teeth on the full rim ring.

    Attributes:
        mesh: scikit-fem ``MeshTri`` (coordinates in m, ``(2, n)``); tooth 0 (the loaded one)
            has its centre line on +y; teeth at ±k·2π/z.
        profile: the :class:`ToothProfile`.
        rim_radius: r_int (m), the clamped inner boundary.
        size: target element size at the teeth (m).
        n_teeth: modelled teeth.
        split_radius: r_P (m), where the tooth block meets the rim block (the fillet point
            whose tangent is at 45° to the radius).
        flank: ``(n_rows + 1, 2)`` vertex coordinates (m) of the loaded tooth's right flank,
            from r_P to the tip corner.
    """

    mesh: Any
    profile: ToothProfile
    rim_radius: float
    size: float
    n_teeth: int
    split_radius: float
    flank: np.ndarray


def _graded(first: float, total: float, q: float, cap: float, *, min_count: int = 1) -> np.ndarray:
    """Cumulative fractions (0..1) of layers of ``first`` growing by ``q`` up to ``cap``."""
    sizes = [first]
    while sum(sizes) < total:
        sizes.append(min(sizes[-1] * q, cap))
    while len(sizes) < min_count:
        sizes.append(sizes[-1])
    sizes = np.array(sizes) * total / sum(sizes)
    return np.concatenate([[0.0], np.cumsum(sizes)]) / total


def _split_radius(prof: ToothProfile) -> float:
    """r_P: above it the flank is steeper than 45° to the radius (r |dψ/dr| < 1)."""
    r, psi = prof.r_tab, prof.psi_tab
    g = r[:-1] * np.abs(np.diff(psi) / np.diff(r))
    flat = np.nonzero(g >= 1.0)[0]
    if len(flat) == 0:
        return float(r[0])
    return float(r[flat[-1] + 1])


def _space_angles(prof: ToothProfile, psi_p: float, h: float) -> tuple[np.ndarray, int]:
    """Angles of the column boundaries on the right half space of a tooth, from ψ(r_P) to π/z
    (excluded), equally spaced in arc length along the lower fillet + root land."""
    half_pitch = math.pi / prof.teeth
    phi = np.linspace(psi_p, half_pitch, 400)
    rr = _top_radius_local(prof, psi_p, phi)
    ds = np.hypot(np.diff(rr), 0.5 * (rr[1:] + rr[:-1]) * np.diff(phi))
    s = np.concatenate([[0.0], np.cumsum(ds)])
    n = max(1, math.ceil(s[-1] / h))
    targets = np.linspace(0.0, s[-1], n + 1)[:-1]
    return np.interp(targets, s, phi), n


def _top_radius_local(prof: ToothProfile, psi_p: float, phi):
    """Top radius R(φ) (m) of the rim block at the local angle φ (rad) from a tooth centre."""
    a = np.abs(phi)
    lower = prof.r_of_psi(np.clip(a, psi_p, prof.root_half_angle))
    r_p = prof.r_of_psi(psi_p)
    return np.where(a <= psi_p, r_p, np.where(a >= prof.root_half_angle, prof.root_radius, lower))


@functools.singledispatch
def mesh_sector(
    prof: ToothProfile,
    rim_radius: float,
    size: float,
    *,
    n_teeth: int = DEFAULT_N_TEETH,
    growth: float = 1.3,
    max_ratio: float = 10.0,
) -> SectorMesh:
    """Mesh ``n_teeth`` teeth on the rim ring ``rim_radius <= r <= r_f`` (full circle).

    Two mapped blocks: the rim ring (polar grid: radial lines, rows at fixed fractions of the
    depth from the bore to the top curve R(φ), which follows the root circle, the lower fillets
    and the arc r = r_P under each tooth; rows graded from ``size`` at the top by ``growth``
    towards the bore; circumferential spacing ``size`` in the toothed sector, growing by
    ``growth`` away from it), and one block per tooth above r_P (rows uniform in r, columns at
    fixed fractions of the local tooth width, φ = ψ(r)(2ξ − 1)).  Quadrilaterals are split
    along their shorter diagonal.

    Args:
        prof: the tooth form. rim_radius: r_int (m), < r_f. size: element size h (m).
        n_teeth: number of teeth meshed (odd is symmetric about the loaded tooth; clipped to z).
        growth: geometric growth factor of the rim layers and of the circumferential spacing.
        max_ratio: the rim layers and the circumferential spacing grow up to ``max_ratio`` ×
            ``size`` (and half the rim depth), so that every element shrinks with ``size``.

    Returns:
        The :class:`SectorMesh`.

    Raises:
        ValueError: ``rim_radius`` not in (0, r_f), non-positive ``size`` or ``n_teeth``.

    An :class:`~fem_prep.InternalToothProfile` (a ring's teeth, pointing inwards) is meshed on
    the ring ``r_f <= r <= rim_radius`` (its outer face; :mod:`fem_prep._internal_fe`).
    """
    rf, ra, z = prof.root_radius, prof.tip_radius, prof.teeth
    if not 0 < rim_radius < rf:
        raise ValueError(f"rim_radius = {rim_radius!r} m must lie in (0, {rf:.6g}) (root radius)")
    if not size > 0:
        raise ValueError(f"size = {size!r} m must be > 0")
    if n_teeth < 1:
        raise ValueError(f"n_teeth = {n_teeth!r} must be >= 1")
    n_teeth = min(int(n_teeth), z)
    tau = 2 * math.pi / z
    r_p = _split_radius(prof)
    psi_p = float(prof.psi(r_p))
    n_tc = max(2, math.ceil(2 * r_p * psi_p / size))
    space, _ = _space_angles(prof, psi_p, size)
    # column boundary angles of one pitch, local to the tooth centre, from -τ/2 (incl.)
    tooth_cols = psi_p * (2 * np.arange(n_tc + 1) / n_tc - 1)
    # left half space: mirror of the right one (angles -π/z .. -ψ_P, exclusive of -ψ_P)
    left = -np.concatenate([[tau / 2], space[1:][::-1]])
    right = space[1:]
    pitch_cols = np.concatenate([left, tooth_cols, right])  # from -τ/2 to just below +τ/2
    centres = (np.arange(n_teeth) - (n_teeth - 1) // 2) * tau
    cols = [c + pitch_cols for c in centres]
    phi = np.concatenate(cols)
    one = np.concatenate([np.zeros(len(left)), np.ones(n_tc + 1), np.zeros(len(right))])
    is_tooth_col = np.tile(one, n_teeth)
    tooth_of = np.concatenate([np.full(len(pitch_cols), j) for j in range(n_teeth)])
    # the ring outside the toothed sector: from φ_end to φ_start + 2π, widths growing
    phi_end = centres[-1] + tau / 2
    gap = 2 * math.pi - n_teeth * tau
    if gap > 1e-12:
        w0 = size / rf
        wmax = min(0.5 * (rf - rim_radius), max_ratio * size) / rf
        half = [w0]
        while sum(half) < gap / 2:
            half.append(min(half[-1] * growth, wmax))
        half = np.array(half) * (gap / 2) / sum(half)
        widths = np.concatenate([half, half[::-1]])
        extra = phi_end + np.concatenate([[0.0], np.cumsum(widths)[:-1]])
        phi = np.concatenate([phi, extra])
        is_tooth_col = np.concatenate([is_tooth_col, np.zeros(len(extra))])
        tooth_of = np.concatenate([tooth_of, np.full(len(extra), -1)])
    n_cols = len(phi)
    # top radius of every column line
    top = np.full(n_cols, rf)
    for j, c in enumerate(centres):
        sel = tooth_of == j
        top[sel] = _top_radius_local(prof, psi_p, phi[sel] - c)
    top[is_tooth_col == 1] = r_p
    # rim rows: fractions from the bore (0) to the top (1), graded from the top
    depth = rf - rim_radius
    g_top = _graded(size, depth, growth, max_ratio * size, min_count=2)  # top downwards
    g = 1.0 - g_top[::-1]  # increasing from 0 (bore) to 1 (top)
    n_rows = len(g) - 1
    rr = rim_radius + (top[None, :] - rim_radius) * g[:, None]
    ang = np.broadcast_to(phi[None, :], rr.shape)
    pts = [np.stack([rr * np.sin(ang), rr * np.cos(ang)], -1).reshape(-1, 2)]
    rim_id = np.arange((n_rows + 1) * n_cols).reshape(n_rows + 1, n_cols)
    quads = []
    c0 = np.arange(n_cols)
    c1 = (c0 + 1) % n_cols
    for k in range(n_rows):
        quads.append(
            np.stack([rim_id[k, c0], rim_id[k, c1], rim_id[k + 1, c1], rim_id[k + 1, c0]], 1)
        )
    # tooth blocks
    n_tr = max(3, math.ceil((ra - r_p) / size))
    rows_r = r_p + (ra - r_p) * np.arange(n_tr + 1) / n_tr
    xi = 2 * np.arange(n_tc + 1) / n_tc - 1
    offset = (n_rows + 1) * n_cols
    flank_ids = None
    for j, c in enumerate(centres):
        bottom = np.nonzero((tooth_of == j) & (is_tooth_col == 1))[0]
        ids = np.empty((n_tr + 1, n_tc + 1), dtype=np.int64)
        ids[0] = rim_id[n_rows, bottom]
        ids[1:] = offset + np.arange(n_tr * (n_tc + 1)).reshape(n_tr, n_tc + 1)
        offset += n_tr * (n_tc + 1)
        r2 = rows_r[1:, None] * np.ones((1, n_tc + 1))
        a2 = c + prof.psi(rows_r[1:])[:, None] * xi[None, :]
        pts.append(np.stack([r2 * np.sin(a2), r2 * np.cos(a2)], -1).reshape(-1, 2))
        for k in range(n_tr):
            b0 = np.arange(n_tc)
            quads.append(
                np.stack([ids[k, b0], ids[k, b0 + 1], ids[k + 1, b0 + 1], ids[k + 1, b0]], 1)
            )
        if abs(c) < 1e-12:
            flank_ids = ids[:, -1]
    p = np.concatenate(pts)
    q = np.concatenate(quads)
    # split along the shorter diagonal, counter-clockwise triangles
    d02 = np.linalg.norm(p[q[:, 0]] - p[q[:, 2]], axis=1)
    d13 = np.linalg.norm(p[q[:, 1]] - p[q[:, 3]], axis=1)
    use02 = d02 <= d13 * (1 + 1e-9)  # equal diagonals (polar cells): 02, whatever the rounding
    t = np.concatenate(
        [
            np.where(use02[:, None], q[:, [0, 1, 2]], q[:, [0, 1, 3]]),
            np.where(use02[:, None], q[:, [0, 2, 3]], q[:, [1, 2, 3]]),
        ]
    )
    e1, e2 = p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]]
    area = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    t[area < 0] = t[area < 0][:, [0, 2, 1]]
    if np.any(np.abs(area) < 1e-14 * size**2):
        raise ValueError("mesh_sector: degenerate triangles (check the tooth form)")
    mesh = skfem.MeshTri(p.T.copy(), t.T.copy())
    flank = p[flank_ids]
    return SectorMesh(
        mesh=mesh,
        profile=prof,
        rim_radius=float(rim_radius),
        size=float(size),
        n_teeth=n_teeth,
        split_radius=r_p,
        flank=flank,
    )


# ------------------------------------------------------------------------------------------
# plane-strain solve


def plane_strain_point_loads(
    mesh,
    youngs_modulus: float,
    poisson_ratio: float,
    clamped,
    load_points: np.ndarray,
    load_dirs: np.ndarray,
    probe_points: np.ndarray,
    *,
    method: str = "auto",
) -> tuple[np.ndarray, dict]:
    """Displacements at probe points under unit point loads, plane strain, unit thickness.

    Quadratic triangles (``ElementTriP2``) on ``mesh``; each load is a separate load case, the
    stiffness matrix is factorised once.  A point force is the consistent nodal load
    ``f_i = φ_i(x_c) n``.

    Args:
        mesh: scikit-fem ``MeshTri`` (m).
        youngs_modulus: E (Pa). poisson_ratio: ν (plane strain: E' = E / (1 − ν²)).
        clamped: predicate on facet midpoints ``x`` (shape (2, n)) returning a boolean mask of
            the boundary facets where u = 0.
        load_points: (n_loads, 2) points (m), on or inside the mesh.
        load_dirs: (n_loads, 2) unit load directions (the force is 1 N per m of thickness).
        probe_points: (n_probes, 2) or (n_loads, n_probes, 2) points (m) inside the mesh.

    Returns:
        ``(U, info)``: ``U`` of shape (n_loads, n_probes, 2), displacement (m) per unit load
        (N/m), i.e. compliance per unit thickness; ``info`` with ``n_dofs``, ``n_elements``,
        ``solver`` and timings (s).
    """
    t0 = time.perf_counter()
    ib = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTriP2()))
    sb = skfem.Basis(mesh, skfem.ElementTriP2())
    K = skfem.asm(linear_elasticity(*lame_parameters(youngs_modulus, poisson_ratio)), ib)
    fixed = ib.get_dofs(clamped).all()
    free = np.setdiff1d(np.arange(ib.N), fixed)
    t1 = time.perf_counter()
    fac = factorize(K[free][:, free].tocsc())
    t2 = time.perf_counter()
    load_points = np.asarray(load_points, dtype=float)
    load_dirs = np.asarray(load_dirs, dtype=float)
    n_loads = len(load_points)
    Pl = sp.csr_matrix(sb.probes(load_points.T))  # (n_loads, n_scalar)
    F = np.zeros((ib.N, n_loads))
    coo = Pl.tocoo()
    for c in (0, 1):
        np.add.at(F, (2 * coo.col + c, coo.row), coo.data * load_dirs[coo.row, c])
    u = np.zeros((ib.N, n_loads))
    u[free] = fac.solve(F[free])
    probe_points = np.asarray(probe_points, dtype=float)
    if probe_points.ndim == 2:
        probe_points = np.broadcast_to(probe_points, (n_loads, *probe_points.shape))
    n_probes = probe_points.shape[1]
    Pm = sp.csr_matrix(sb.probes(probe_points.reshape(-1, 2).T))  # (n_loads n_probes, n_scalar)
    ux = (Pm @ u[0::2]).reshape(n_loads, n_probes, n_loads)
    uy = (Pm @ u[1::2]).reshape(n_loads, n_probes, n_loads)
    idx = np.arange(n_loads)
    U = np.stack([ux[idx, :, idx], uy[idx, :, idx]], -1)
    t3 = time.perf_counter()
    info = {
        "n_dofs": int(ib.N),
        "n_elements": int(mesh.nelements),
        "solver": fac.method,
        "assembly_s": t1 - t0,
        "factorisation_s": t2 - t1,
        "solve_s": t3 - t2,
    }
    return U, info


# ------------------------------------------------------------------------------------------
# tooth compliance along the involute


@functools.singledispatch
def _load_geometry(prof: ToothProfile, rho: np.ndarray):
    """Contact point C, load direction n (into the tooth, along the line of action) and the
    measuring point M (line of action ∩ tooth centre line) on the right flank of tooth 0."""
    rb = prof.base_radius
    r_c = np.hypot(rho, rb)
    psi_c = prof.psi(r_c)
    alpha = np.arctan2(rho, rb)
    phi_t = psi_c - alpha  # polar angle of the base tangent point T
    C = np.stack([r_c * np.sin(psi_c), r_c * np.cos(psi_c)], -1)
    n = np.stack([-np.cos(phi_t), np.sin(phi_t)], -1)
    s = -C[:, 0] / n[:, 0]
    M = C + s[:, None] * n
    return C, n, M


def _on_flank(flank: np.ndarray, r_c: np.ndarray, inset: float) -> np.ndarray:
    """Points of the polyline ``flank`` (vertices at increasing radii) at radii ``r_c``, moved
    ``inset`` (m) towards the middle of the tooth's centre line (the tooth's inside, for an
    external and an internal tooth alike) so that they lie inside a triangle."""
    rv = np.hypot(flank[:, 0], flank[:, 1])
    k = np.clip(np.searchsorted(rv, r_c) - 1, 0, len(rv) - 2)
    p0, d = flank[k], flank[k + 1] - flank[k]
    a = np.sum(d * d, 1)
    b = 2 * np.sum(p0 * d, 1)
    c = np.sum(p0 * p0, 1) - r_c**2
    t = np.clip((-b + np.sqrt(np.maximum(b * b - 4 * a * c, 0.0))) / (2 * a), 0.0, 1.0)
    pts = p0 + t[:, None] * d
    inward = np.array([0.0, 0.5 * (rv[0] + rv[-1])]) - pts
    return pts + inset * inward / np.linalg.norm(inward, axis=1)[:, None]


@functools.singledispatch
def _root_chord(prof: ToothProfile, size: float, n: int = 16):
    """Gauss points (n, 2) and weights (n,) on the root chord of tooth 0 (between the fillet/
    root-circle tangency points), pulled slightly inwards so that they lie in the mesh."""
    rf, psi_f = prof.root_radius, prof.root_half_angle
    xg, wg = np.polynomial.legendre.leggauss(n)
    shrink = 1 - 0.25 * (size / rf) ** 2
    x = rf * math.sin(psi_f) * xg * shrink
    y = np.full(n, rf * math.cos(psi_f) * shrink)
    return np.stack([x, y], -1), wg


def _rigid_fit(Q: np.ndarray, w: np.ndarray, U: np.ndarray, M: np.ndarray) -> np.ndarray:
    """Weighted least-squares rigid motion (translation + small rotation about the chord centre)
    of displacements U (n_loads, n_q, 2) at points Q (n_q, 2), evaluated at M (n_loads, 2)."""
    q0 = np.average(Q, axis=0, weights=w)
    d = Q - q0
    A = np.zeros((2 * len(Q), 3))
    A[0::2, 0] = 1.0
    A[1::2, 1] = 1.0
    A[0::2, 2] = -d[:, 1]
    A[1::2, 2] = d[:, 0]
    W = np.repeat(np.sqrt(w), 2)
    coef, *_ = np.linalg.lstsq(A * W[:, None], (U.reshape(len(U), -1) * W).T, rcond=None)
    tx, ty, om = coef  # each (n_loads,)
    dm = M - q0
    return np.stack([tx - om * dm[:, 1], ty + om * dm[:, 0]], -1)


def rim_face(sm: SectorMesh):
    """The clamp predicate of the rim's far face (the bore of an external member, the outer
    face of a ring): the facets whose two vertices lie on the circle ``sm.rim_radius``, found
    by their midpoints (a predicate on facet midpoints (2, n), as scikit-fem calls it)."""
    m, tol = sm.mesh, 1e-9 * sm.rim_radius
    on = np.abs(np.hypot(m.p[0], m.p[1]) - sm.rim_radius) < tol
    f = m.facets[:, on[m.facets[0]] & on[m.facets[1]]]
    tree = cKDTree((0.5 * (m.p[:, f[0]] + m.p[:, f[1]])).T)
    return lambda x: tree.query(np.asarray(x).T)[0] < tol


def _compute(prof: ToothProfile, rim_radius, nu, size, n_teeth, n_roll, progress, hold=None):
    """E-normalised compliances E·c (dimensionless per unit width) at n_roll roll distances;
    ``hold(sm) -> (mesh, clamped)`` a rim support's (None: the rim's far face clamped)."""
    off = None if progress is None else not progress  # None: shown on a terminal only
    steps = tqdm(total=3, desc=f"fe2d z={prof.teeth}", disable=off, unit="step")
    t0 = time.perf_counter()
    sm = mesh_sector(prof, rim_radius, size, n_teeth=n_teeth)
    mesh, clamped = (sm.mesh, rim_face(sm)) if hold is None else hold(sm)
    steps.update()
    rho = np.linspace(*sorted((prof.form_roll, prof.tip_roll)), n_roll)
    _C, n, M = _load_geometry(prof, rho)
    loads = _on_flank(sm.flank, np.hypot(rho, prof.base_radius), 1e-9 * size)
    Q, wq = _root_chord(prof, size)
    probes = np.concatenate([M[:, None, :], np.broadcast_to(Q, (n_roll, *Q.shape))], axis=1)
    U, info = plane_strain_point_loads(
        mesh,
        1.0,
        nu,
        clamped,
        loads,
        n,
        probes,
    )
    steps.update()
    cE = np.sum(U[:, 0, :] * n, axis=1)
    rigid = _rigid_fit(Q, wq, U[:, 1:, :], M)
    cE_tooth = cE - np.sum(rigid * n, axis=1)
    steps.update()
    steps.close()
    info = dict(info)
    info["split_radius"] = sm.split_radius
    info["seconds"] = time.perf_counter() - t0
    return rho, M[:, 1], cE, cE_tooth, info


@dataclass(frozen=True)
class ToothCompliance:
    """FE compliance of one member's tooth along its involute (per unit face width).

    Attributes:
        roll: roll distances ρ (m), shape (n,), from the form circle to the tip; the contact
            point's radius is √(ρ² + r_b²).
        load_radius: radius (m) where the line of action crosses the tooth centre line (the
            measuring point), shape (n,).
        compliance: tooth + body compliance (m/N)·m per unit face width, shape (n,), along the
            transverse line of action, at ``youngs_modulus`` (without the Hertzian approach).
        compliance_tooth: the same without the rigid motion of the root section (tooth clamped
            at the root circle), shape (n,).
        youngs_modulus, poisson_ratio: E (Pa), ν. rim_radius: clamped inner radius (m).
        size: element size (m). n_teeth: teeth modelled. form: tooth-form source.
        info: mesh size (``n_dofs``, ``n_elements``), solver, timings (s) of the computation.
        cache_hit: whether the table came from the cache. key: the cache key.
    """

    roll: np.ndarray
    load_radius: np.ndarray
    compliance: np.ndarray
    compliance_tooth: np.ndarray
    youngs_modulus: float
    poisson_ratio: float
    rim_radius: float
    size: float
    n_teeth: int
    form: str
    info: dict = field(default_factory=dict)
    cache_hit: bool = False
    key: str = ""

    def __call__(self, rho, *, tooth_only: bool = False) -> np.ndarray:
        """Compliance (m/N)·m at roll distances ``rho`` (m, any shape), cubic spline in ρ.

        Raises:
            ValueError: ``rho`` outside [form roll, tip roll] (beyond 1e-9 relative).
        """
        rho = np.asarray(rho, dtype=float)
        lo, hi = self.roll[0], self.roll[-1]
        tol = 1e-9 * hi
        if np.any(rho < lo - tol) or np.any(rho > hi + tol):
            raise ValueError(
                f"roll distance outside the involute [{lo * 1e3:.6g}, {hi * 1e3:.6g}] mm of "
                "the FE table (active profile below the form circle?)"
            )
        from scipy.interpolate import CubicSpline  # lazy: 0.13 s and 200 modules at every start

        c = self.compliance_tooth if tooth_only else self.compliance
        return CubicSpline(self.roll, c)(np.clip(rho, lo, hi))


def cache_dir() -> Path:
    """``fem_prep.cache_dir() / "tooth_fe"``."""
    return table_dir("tooth_fe")


@dataclass(frozen=True)
class SectorModel:
    """What the plane-strain model of :func:`tooth_compliance` holds besides the element size.

    Attributes:
        n_teeth: teeth modelled on the rim ring (the middle one is loaded; clipped to z).
        n_roll: number of load positions, equally spaced in roll distance (>= 4).
        form: the fillet (:class:`~fem_prep.TrochoidFillet`, or
            :class:`~fem_prep.CircularFillet`; ``None``: the member's default, see
            :func:`~fem_prep.tooth_profile`).
    """

    n_teeth: int = DEFAULT_N_TEETH
    n_roll: int = DEFAULT_N_ROLL
    form: FilletForm | None = None


@functools.singledispatch
def tooth_compliance(
    geometry: ToothGeometry,
    *,
    rim_radius: float | None = None,
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
    size: float | None = None,
    model: SectorModel | None = None,
    use_cache: bool = True,
    progress: bool | None = False,
) -> ToothCompliance:
    """Plane-strain FE compliance of one member's tooth + body along the involute (cached).

    See the module docstring for the model and the compliance measure (deflection of the tooth
    centre line where the line of action crosses it, along the line of action).

    Args:
        geometry: the member (:class:`fem_prep.ToothGeometry`); the model is the transverse
            section.
        rim_radius: clamped inner radius r_int (m): the bore of a solid gear or the rim inner
            radius; default 0.5 × root radius.
        youngs_modulus: E (Pa). poisson_ratio: ν.
        size: element size at the teeth (m); default m_n / 6.
        model: the teeth modelled, the load positions and the fillet (:class:`SectorModel`;
            ``None``: its defaults).
        use_cache: read/write ``cache_dir()``.
        progress: tqdm progress bar (``None``: only on a terminal).

    Returns:
        The :class:`ToothCompliance` (compliances at ``youngs_modulus``).

    Raises:
        ValueError: a rim radius outside (0, r_f), a non-positive size, fewer than 4 roll
            positions.
    """
    model = SectorModel() if model is None else model
    prof = tooth_profile(geometry, form=model.form)
    rim = 0.5 * prof.root_radius if rim_radius is None else float(rim_radius)
    if not 0 < rim < prof.root_radius:
        raise ValueError(
            f"rim_radius = {rim!r} m must lie in (0, {prof.root_radius:.6g}) (the root radius)"
        )
    material = (youngs_modulus, poisson_ratio)
    return tabulate(geometry, prof, rim, material, size, model, (use_cache, progress, None), {})


def tabulate(g, prof, rim, material, size, model, options, key_extra) -> ToothCompliance:
    """:func:`tooth_compliance` of the profile ``prof`` of the member ``g`` on the rim whose far
    face is at ``rim`` (m, checked by the caller): ``material`` = (E, ν), ``options`` =
    (use_cache, progress, hold) (``hold``: a rim support's, None: the far face clamped),
    ``key_extra`` more inputs of the cache key (the support's among them)."""
    use_cache, progress, hold = options
    youngs_modulus, poisson_ratio = material
    n_teeth, n_roll = model.n_teeth, model.n_roll
    h = g.normal_module / DEFAULT_ELEMENTS_PER_MODULE if size is None else float(size)
    if not h > 0 or not math.isfinite(h):
        raise ValueError(f"size = {h!r} m must be > 0")
    if n_roll < 4:
        raise ValueError(f"n_roll = {n_roll!r} must be >= 4")
    inputs = {
        "version": TOOTH_FE_VERSION,
        "teeth": g.teeth,
        "normal_module": g.normal_module,
        "normal_pressure_angle": g.normal_pressure_angle,
        "helix_angle": g.helix_angle,
        "profile_shift": g.profile_shift,
        "addendum_coeff": g.addendum_coeff,
        "dedendum_coeff": g.dedendum_coeff,
        "fillet_radius_coeff": g.fillet_radius_coeff,
        "rim_radius": rim,
        "poisson_ratio": float(poisson_ratio),
        "size": h,
        "n_teeth": int(min(n_teeth, prof.teeth)),
        "n_roll": int(n_roll),
        "form": prof.source,
        **key_extra,
    }
    key = _key(inputs)
    path = cache_dir() / f"{key}.npz"
    data = load_entry(path, key, TOOTH_FE_VERSION, inputs) if use_cache else None
    hit = data is not None
    if not hit:
        rho, r_load, cE, cE_tooth, info = _compute(
            prof, rim, poisson_ratio, h, inputs["n_teeth"], n_roll, progress, hold
        )
        data = {
            "format_version": np.array(TOOTH_FE_VERSION),
            "key": np.array(key),
            "inputs": np.array(json.dumps(inputs, sort_keys=True)),
            "info": np.array(json.dumps(info)),
            "roll": rho,
            "load_radius": r_load,
            "compliance_E": cE,
            "compliance_tooth_E": cE_tooth,
        }
        if use_cache:
            store_entry(path, data)
    E = float(youngs_modulus)
    return ToothCompliance(
        roll=np.asarray(data["roll"], dtype=float),
        load_radius=np.asarray(data["load_radius"], dtype=float),
        compliance=np.asarray(data["compliance_E"], dtype=float) / E,
        compliance_tooth=np.asarray(data["compliance_tooth_E"], dtype=float) / E,
        youngs_modulus=E,
        poisson_ratio=float(poisson_ratio),
        rim_radius=rim,
        size=h,
        n_teeth=inputs["n_teeth"],
        form=prof.source,
        info=json.loads(str(data["info"])),
        cache_hit=hit,
        key=key,
    )
