"""Rim and web stresses of a condensed body: its full displacement field recovered from the
condensed coordinates and the linear-elastic stresses of that field, per element.

Recovery (seed (2.3)-(2.5)): the condensed coordinates ``q_c`` (master displacements, then
modal coordinates) give the reduced coordinates ``q_red = H q_c`` (``Condensed.basis``, the
transfer matrix: for Craig–Bampton ``[I 0; G_ib Φ_i]``, the static constraint modes and the
fixed-interface modes) and the full field ``u = T q_red`` (``Coupled.T``, the bearing and rim
couplings). A static load on the master DOFs alone has no modal part and an interior response
``G_ib u_b`` exactly: the recovered field is then the full model's static solution.

Stresses: σ = λ tr(ε) I + 2 μ ε, ε = sym ∇u, at the quadrature points of the body's own basis
(the quadrature of its stiffness), averaged over each element with the quadrature weights; von
Mises σ_vM = √(3/2 s:s) (s the deviator), and the cylindrical components about the body's axis
(+z): hoop σ_θθ = e_θ·σ·e_θ with e_θ = (−y, x, 0)/r, radial σ_rr = e_r·σ·e_r. Regions as the
mesh's (0 hub/stub, 1 web, 2 rim, 3 pinion rim). NumPy/SciPy/scikit-fem only.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import skfem

from ._body import Material
from ._io import CondensedBody
from ._prepare import Prepared
from .files import atomic_write

__all__ = [
    "REGIONS",
    "BodyStress",
    "body_stress",
    "condensed_body_stress",
    "element_stresses",
    "full_displacement",
    "write_stress_vtu",
]

#: the mesh's element regions by name (``BodyMesh.region``)
REGIONS = {"hub": 0, "web": 1, "rim": 2, "pinion_rim": 3}


@dataclass(frozen=True)
class BodyStress:
    """Element stresses of a body's displacement field (Pa), each ``(n_elements,)``: the
    element means over its quadrature points.

    Attributes:
        von_mises: σ_vM (Pa), >= 0.
        hoop: σ_θθ about the body's axis +z (Pa), tension > 0.
        radial: σ_rr (Pa). axial: σ_zz (Pa).
        radius: the element's mean radius (m).
        region: the element's region (:data:`REGIONS`).
    """

    von_mises: np.ndarray
    hoop: np.ndarray
    radial: np.ndarray
    axial: np.ndarray
    radius: np.ndarray
    region: np.ndarray

    def max_in(self, region: str) -> dict[str, float]:
        """``{"von_mises_Pa", "hoop_Pa"}``: the largest von Mises stress and the largest
        |hoop| stress (signed) over the elements of ``region`` ("hub", "web", "rim",
        "pinion_rim").

        Raises:
            ValueError: an unknown region, or one without elements.
        """
        if region not in REGIONS:
            raise ValueError(f"region = {region!r}: allowed {', '.join(REGIONS)}")
        sel = self.region == REGIONS[region]
        if not sel.any():
            raise ValueError(f"region = {region!r}: the body has no {region} elements")
        hoop = self.hoop[sel]
        return {
            "von_mises_Pa": float(self.von_mises[sel].max()),
            "hoop_Pa": float(hoop[np.argmax(np.abs(hoop))]),
        }


def full_displacement(prep: Any, q_c: np.ndarray) -> np.ndarray:
    """The full displacement field ``u = T H q_c`` (m), ``(n_dofs,)`` interleaved x/y/z per
    node, of condensed coordinates ``q_c`` (``(n_c,)``, the condensed DOF order of
    :class:`~fem_prep.CondensedBody`) of a :class:`~fem_prep.Prepared` body (``T``:
    ``prep.coupled.T``; ``H``: ``prep.condensed.basis``; float64 throughout).

    Raises:
        ValueError: ``q_c`` not of shape ``(n_c,)``.
    """
    basis = prep.condensed.basis
    q = np.asarray(q_c, dtype=float)
    if q.shape != (basis.shape[1],):
        raise ValueError(
            f"q_c of shape {q.shape}: the condensed body has {basis.shape[1]} coordinates"
        )
    return np.asarray(prep.coupled.T @ (basis @ q)).ravel()


def element_stresses(
    basis: skfem.Basis, material: Material, u: np.ndarray, region: np.ndarray
) -> BodyStress:
    """The element stresses (module docstring) of the displacement ``u`` (m, ``(n_dofs,)`` on
    the vector ``basis``) of an isotropic ``material``; ``region``: each element's region.

    Raises:
        ValueError: ``u`` of the wrong length.
    """
    u = np.asarray(u, dtype=float)
    if u.shape != (basis.N,):
        raise ValueError(f"u of shape {u.shape}: the basis has {basis.N} DOFs")
    lam, mu = material.lame
    g = basis.interpolate(u).grad  # (3, 3, n_el, n_q): d_j u_i
    eps = 0.5 * (g + g.transpose(1, 0, 2, 3))
    tr = eps[0, 0] + eps[1, 1] + eps[2, 2]
    sig = 2.0 * mu * eps
    for a in range(3):
        sig[a, a] += lam * tr
    x = np.asarray(basis.global_coordinates())  # (3, n_el, n_q)
    r = np.hypot(x[0], x[1])
    c, s = x[0] / r, x[1] / r
    hoop = s * s * sig[0, 0] + c * c * sig[1, 1] - 2 * s * c * sig[0, 1]
    radial = c * c * sig[0, 0] + s * s * sig[1, 1] + 2 * s * c * sig[0, 1]
    dev = sig - np.eye(3)[:, :, None, None] * (tr * (lam + 2 * mu / 3))[None, None]
    vm = np.sqrt(1.5 * np.einsum("ijeq,ijeq->eq", dev, dev))
    w = basis.dx / basis.dx.sum(axis=1, keepdims=True)  # quadrature weights per element

    def mean(v):
        return np.sum(w * v, axis=1)

    return BodyStress(
        von_mises=mean(vm),
        hoop=mean(hoop),
        radial=mean(radial),
        axial=mean(sig[2, 2]),
        radius=mean(r),
        region=np.asarray(region),
    )


def body_stress(prep: Any, q_c: np.ndarray) -> tuple[np.ndarray, BodyStress]:
    """The full field (:func:`full_displacement`) and its element stresses
    (:func:`element_stresses`) of condensed coordinates ``q_c`` of a
    :class:`~fem_prep.Prepared` body. Returns ``(u, stress)``."""
    u = full_displacement(prep, q_c)
    return u, element_stresses(prep.mesh.basis, prep.body.material, u, prep.mesh.region)


#: skfem's MeshHex corner order from the VTK hexahedron order of ``BodyMesh.cells`` (its inverse)
_VTK_ORDER = np.array([0, 3, 6, 2, 1, 5, 7, 4])


def _regions_by_radius(body: Any, coords: np.ndarray) -> np.ndarray:
    """Each element's region from its mean corner position ``coords`` ``(n_el, 3)`` (m) and
    the body's geometry, as the mesher sets them: rim at ``r >= rim_inner_radius``, web at
    ``hub_outer_radius <= r < rim_inner_radius``, hub below; a pinion rim's elements (radius
    under its outer radius, axially in its band outside the hub's width) are region 3."""
    g = body.geometry
    r = np.hypot(coords[:, 0], coords[:, 1])
    reg = np.where(r >= g.rim_inner_radius, 2, np.where(r >= g.hub_outer_radius, 1, 0))
    pin = body.pinion_rim
    if pin is not None:
        lo, hi = pin.band
        z = coords[:, 2]
        hub = np.abs(z - g.web_offset) <= g.hub_width / 2
        reg = np.where((r < pin.outer_radius) & (z > lo) & (z < hi) & ~hub, 3, reg)
    return reg


def condensed_body_stress(body: Any, q_c: np.ndarray) -> tuple[np.ndarray, BodyStress]:
    """Element stresses of a loaded :class:`~fem_prep.CondensedBody` (the ``.npz`` a run reads;
    no mesh or operator is rebuilt): the corner displacements ``u = recovery @ q_c``
    (``(n_rec, 3)``, m) on the linear hexahedra ``recovery_cells``, stresses as
    :func:`element_stresses` with trilinear interpolation of the corners (the quadratic
    elements' mid-edge values are not in the file: a coarser stress than :func:`body_stress`,
    see ``docs/rating.md``), regions from the radius (:func:`_regions_by_radius`); the material
    is the body file's.

    Returns ``(u (n_rec, 3), stress)``.

    Raises:
        ValueError: ``q_c`` not of shape ``(n_c,)``.
    """
    q = np.asarray(q_c, dtype=float)
    if q.shape != (body.n_dofs,):
        raise ValueError(
            f"q_c of shape {q.shape}: the condensed body has {body.n_dofs} coordinates"
        )
    u = np.asarray(body.recovery, dtype=float) @ q
    coords = np.asarray(body.recovery_coords, dtype=float)
    cells = np.asarray(body.recovery_cells)
    t = np.empty((8, cells.shape[0]), dtype=np.int64)
    t[_VTK_ORDER] = cells.T
    mesh = skfem.MeshHex(coords.T.copy(), t)
    basis = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementHex1()), intorder=2)
    b = body.body
    region = _regions_by_radius(b, coords[cells].mean(axis=1))
    return u.reshape(-1, 3), element_stresses(basis, b.material, u, region)


@functools.singledispatch
def _corners(source: Prepared) -> tuple[np.ndarray, np.ndarray]:
    """(corner nodes (n, 3) m, hexahedra (n_el, 8) VTK order) of a prepared body's mesh."""
    return source.mesh.nodes[: source.mesh.n_vertices], source.mesh.cells


@_corners.register
def _(source: CondensedBody) -> tuple[np.ndarray, np.ndarray]:
    return np.asarray(source.recovery_coords), np.asarray(source.recovery_cells)


def write_stress_vtu(prep: Any, u: np.ndarray, stress: BodyStress, path: str | Path) -> Path:
    """Write the body mesh (corner nodes, linear hexahedra) with the displacement ``u`` (point
    data ``displacement``, m) and the element stresses (cell data ``von_mises_Pa``,
    ``hoop_Pa``, ``radial_Pa``, ``axial_Pa``, ``region``) as a meshio ``.vtu`` (written
    atomically). ``prep``: a :class:`~fem_prep.Prepared` body (``u`` its full field,
    ``(n_dofs,)``) or a :class:`~fem_prep.CondensedBody` (``u`` its corner displacements,
    ``(n_rec, 3)``, as :func:`condensed_body_stress` returns them). Returns the path."""
    import meshio  # lazy, as fem_prep's other .vtu writer: only when a file is written

    points, cells = _corners(prep)
    mesh = meshio.Mesh(
        points,
        [("hexahedron", cells)],
        point_data={"displacement": np.asarray(u).reshape(-1, 3)[: len(points)]},
        cell_data={
            "von_mises_Pa": [stress.von_mises],
            "hoop_Pa": [stress.hoop],
            "radial_Pa": [stress.radial],
            "axial_Pa": [stress.axial],
            "region": [np.asarray(stress.region, dtype=np.int32)],
        },
    )
    return atomic_write(Path(path), lambda p: meshio.write(str(p), mesh, file_format="vtu"))
