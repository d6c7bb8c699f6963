"""The pre-processing pipeline: mesh -> assemble -> couple -> full modal -> condense."""

from __future__ import annotations

import math
import time
import tracemalloc
from dataclasses import dataclass, field, replace
from typing import ClassVar, final

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from tqdm import tqdm

from ._assemble import Operators, assemble_operators, stress_stiffening_matrix
from ._body import Body
from ._condense import Condensed, RotatingOperators, condense
from ._couplings import (
    Coupled,
    MasterSet,
    band_reaction_stiffness,
    couple_masters,
    select_masters,
)
from ._kinds import Support
from ._mesh import BodyMesh, mesh_body
from ._modal import ModeFamily, identify_modes
from ._solver import blas_threads, factorize, phase_bar, shift_invert_modes, solve_bar

__all__ = ["Bearings", "Free", "Prepared", "prepare"]


@final
class Bearings(Support):
    """The reported frequencies with the bearing nodes held (``[modal] support = "bearings"``,
    the default)."""

    name: ClassVar[str] = "bearings"

    def full_modes(self, cp, Kff, free, factor, n, progress):
        with solve_bar(f"modes of the full model ({n})", progress) as bar:
            lam, phi_f = shift_invert_modes(
                Kff, cp.M[free][:, free], n, sigma=0.0, factor=factor, on_solve=bar.update
            )
        phi = np.zeros((cp.K.shape[0], n))
        phi[free] = phi_f
        return lam, phi

    def held(self, bearing_dofs):
        return bearing_dofs


@final
class Free(Support):
    """The reported frequencies of the free body (``[modal] support = "free"``): six rigid-body
    modes first."""

    name: ClassVar[str] = "free"

    def full_modes(self, cp, Kff, free, factor, n, progress):
        shift = -float(np.median(cp.K.diagonal() / cp.M.diagonal())) * 1e-4
        with phase_bar(f"factorisation of K - s M (n = {cp.K.shape[0]})", progress):
            F_shift = factorize((cp.K - shift * cp.M).tocsr())
        with solve_bar(f"modes of the full model ({n}, free)", progress) as bar:
            lam, phi = shift_invert_modes(
                cp.K, cp.M, n, sigma=shift, factor=F_shift, on_solve=bar.update
            )
        del F_shift
        return lam, phi

    def held(self, bearing_dofs):
        return bearing_dofs[:0]


@dataclass
class Prepared:
    """Everything the pre-processing produced (in memory).

    Attributes:
        body: the input body.
        mesh: the :class:`BodyMesh`.
        operators: full operators (K, M, centrifugal vector, gyroscopic, spin softening).
        masters: master nodes.
        coupled: operators after the bearing couplings (``u_full = T q``), with the stress
            stiffening (``coupled.Ksigma``: ``T^T K_sigma T`` plus the shaft's load stiffness of
            the bore-band reactions, :func:`~fem_prep._couplings.band_reaction_stiffness`).
        condensed: the condensed model.
        master_dofs: reduced indices of the boundary DOFs: rim grid ``(teeth, n_axial, 3)``
            flattened (then a pinion rim's likewise), then bearings ``(n_bearings, 6)``
            flattened.
        frequencies_full_hz: first ``body.n_frequencies`` frequencies of the full model (Hz).
        mode_shapes: full-DOF mode shapes ``(n_dofs, n_frequencies)`` (mass-normalised).
        frequencies_condensed_hz: same modes from the condensed model (Hz).
        families: nodal diameters/circles of the full-model modes.
        centrifugal_displacement: full-DOF static displacement ``(n_dofs,)`` (m) under the
            centrifugal load at ``body.speed`` with the bearings held.
        prestress_displacement: the same at 1 rad/s ``(n_dofs,)`` (m/(rad/s)^2): the
            prestress of the stress stiffening.
        stress_stiffening: full-DOF stress-stiffening matrix ``(n_dofs, n_dofs)`` CSR per unit
            speed squared, the geometric stiffness of ``prestress_displacement``'s stress
            (:func:`~fem_prep._assemble.stress_stiffening_matrix`).
        rim_radial_displacement: mean radial displacement (m) at the rim outer radius, mid-face.
        rim_radial_displacement_condensed: the same from the condensed model (m).
        timings: wall time per step (s).
        solver: the sparse factorisation library that ran (``"cholmod"``, ``"pardiso"`` or
            ``"superlu"``).
        peak_memory_bytes: peak traced Python/NumPy allocation (bytes).
    """

    body: Body
    mesh: BodyMesh
    operators: Operators
    masters: MasterSet
    coupled: Coupled
    condensed: Condensed
    master_dofs: np.ndarray
    frequencies_full_hz: np.ndarray
    mode_shapes: np.ndarray
    frequencies_condensed_hz: np.ndarray
    families: list[ModeFamily]
    centrifugal_displacement: np.ndarray
    prestress_displacement: np.ndarray
    stress_stiffening: sp.csr_matrix
    rim_radial_displacement: float
    rim_radial_displacement_condensed: float
    timings: dict[str, float] = field(default_factory=dict)
    solver: str = ""
    peak_memory_bytes: int = 0


def _hz(lam: np.ndarray) -> np.ndarray:
    return np.sqrt(np.maximum(lam, 0.0)) / (2 * math.pi)


def prepare(body: Body, *, progress: bool = False, trace_memory: bool = False) -> Prepared:
    """Run the whole pre-processing of a body (see :func:`_prepare`)."""
    with blas_threads():
        return _prepare(body, progress=progress, trace_memory=trace_memory)


def _prepare(body: Body, *, progress: bool = False, trace_memory: bool = False) -> Prepared:
    """Run the whole pre-processing of a body.

    Args:
        body: the validated body.
        progress: show tqdm progress bars (meshing, assembly, factorisation, eigen-solves).
        trace_memory: measure the peak allocation with ``tracemalloc`` (slower).

    Returns:
        The :class:`Prepared` results.
    """
    if trace_memory:
        tracemalloc.start()
    timings: dict[str, float] = {}
    # six steps; the bar names the running one, its inner bars count the long calls
    # (factorisations, the solves of each eigen-solve, column blocks) and vanish when done
    steps = tqdm(total=6, desc=f"fem-prep {body.name}", disable=not progress, unit="step")

    def begin(what: str) -> None:
        steps.set_postfix_str(f"{what}...")

    def tick(name: str | None, t0: float) -> None:
        dt = time.perf_counter() - t0
        if name is not None:
            timings[name] = dt
        steps.set_postfix_str(f"{(name or 'condensed model').removesuffix('_s')} {dt:.1f}s")
        steps.update()

    begin("mesh")
    t0 = time.perf_counter()
    bm = mesh_body(body)
    tick("mesh_s", t0)

    begin(f"assembly ({bm.n_dofs} DOFs)")
    t0 = time.perf_counter()
    ops = assemble_operators(bm.basis, body.material)
    tick("assembly_s", t0)

    begin("bearing couplings")
    t0 = time.perf_counter()
    ms = select_masters(bm, body)
    cp = couple_masters(bm, ops, ms)
    rim_dofs = cp.all_rim_dofs
    master_dofs = np.concatenate([rim_dofs, cp.bearing_dofs.ravel()])
    bearing_c = len(rim_dofs) + np.arange(cp.bearing_dofs.size)
    n_red = cp.K.shape[0]
    tick("coupling_s", t0)

    # ---- full model: modes (support as the body says) and centrifugal deflection
    begin("full model: factorisation, modes, prestress")
    t0 = time.perf_counter()
    nf = body.n_frequencies
    held = np.zeros(n_red, dtype=bool)
    held[cp.bearing_dofs.ravel()] = True
    free = np.nonzero(~held)[0]
    Kff = cp.K[free][:, free]
    with phase_bar(f"factorisation of the full model (n = {len(free)})", progress):
        Fff = factorize(Kff)
    solver = Fff.method
    t_fact = time.perf_counter() - t0
    # centrifugal prestress at 1 rad/s, bearings held (it scales with speed^2)
    u_red = np.zeros(n_red)
    u_red[free] = Fff.solve(cp.f[free])
    u_unit = cp.T @ u_red
    u_cf = body.speed**2 * u_unit
    lam, phi = body.support.full_modes(cp, Kff, free, Fff, nf, progress)
    del Fff
    shapes = cp.T @ phi
    f_full = _hz(lam)
    timings["full_factorisation_s"] = t_fact
    t1 = time.perf_counter()
    with phase_bar("stress stiffening of the prestress", progress):
        k_sigma = stress_stiffening_matrix(bm.basis, body.material, u_unit)
        # the bore bands' reactions turn with the shaft that carries them: their load
        # stiffness goes with the body's so that a rigid turn about the axis stays neutral
        k_react = band_reaction_stiffness(cp, ms, bm.nodes, ops.K @ u_unit - ops.f_centrifugal)
        cp = replace(cp, Ksigma=cp.reduce(k_sigma) + k_react)
    timings["stress_stiffening_s"] = time.perf_counter() - t1
    tick("full_modal_s", t0)

    # ---- condensation
    begin(f"condensation ({body.condensation.method}, {len(master_dofs)} master DOFs)")
    t0 = time.perf_counter()
    cond = condense(
        cp.K,
        cp.M,
        master_dofs,
        method=body.condensation.method,
        n_modes=body.condensation.modes,
        rotating=RotatingOperators(f=cp.f, S=cp.S, G=cp.G, Ksigma=cp.Ksigma),
        progress=progress,
    )
    for k, v in cond.timings.items():
        timings[f"condense_{k}"] = v
    tick("condensation_s", t0)

    # ---- condensed model: same support, frequencies and centrifugal deflection
    begin("condensed model: frequencies, deflection, mode identification")
    t_step = t0 = time.perf_counter()
    n_c = cond.K.shape[0]
    keep = np.ones(n_c, dtype=bool)
    keep[body.support.held(bearing_c)] = False
    lam_c = sla.eigh(cond.K[np.ix_(keep, keep)], cond.M[np.ix_(keep, keep)], eigvals_only=True)
    f_cond = _hz(lam_c[:nf])
    kc = np.ones(n_c, dtype=bool)
    kc[bearing_c] = False
    qc = np.zeros(n_c)
    qc[kc] = np.linalg.solve(cond.K[np.ix_(kc, kc)], body.speed**2 * cond.f_centrifugal[kc])
    timings["condensed_modal_s"] = time.perf_counter() - t0

    # ---- rim radial displacement at the rim outer radius, mid-face
    g = body.geometry
    x = bm.nodes
    rho = np.hypot(x[:, 0], x[:, 1])
    on = np.abs(rho - g.rim_outer_radius) < 1e-7 * g.rim_outer_radius
    zmid = x[on, 2][np.argmin(np.abs(x[on, 2]))]
    sel = np.nonzero(on & (np.abs(x[:, 2] - zmid) < 1e-9))[0]
    u = u_cf.reshape(-1, 3)[sel]
    ur = (u[:, 0] * x[sel, 0] + u[:, 1] * x[sel, 1]) / rho[sel]
    rim_ur = float(np.mean(ur))
    # condensed: rim master column nearest mid-face
    rim_nodes = ms.rim_nodes
    jmid = int(np.argmin(np.abs(x[rim_nodes[0], 2])))
    qr = qc[: rim_nodes.size * 3].reshape(rim_nodes.shape[0], rim_nodes.shape[1], 3)[:, jmid]
    xr = cp.rim_positions[:, jmid]
    ur_c = float(
        np.mean((qr[:, 0] * xr[:, 0] + qr[:, 1] * xr[:, 1]) / np.hypot(xr[:, 0], xr[:, 1]))
    )

    t0 = time.perf_counter()
    web_z = g.web_offset
    fam = identify_modes(bm, shapes, f_full, web_z=web_z)
    timings["identification_s"] = time.perf_counter() - t0
    tick(None, t_step)
    steps.close()
    peak = 0
    if trace_memory:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return Prepared(
        body=body,
        mesh=bm,
        operators=ops,
        masters=ms,
        coupled=cp,
        condensed=cond,
        master_dofs=master_dofs,
        frequencies_full_hz=f_full,
        mode_shapes=shapes,
        frequencies_condensed_hz=f_cond,
        families=fam,
        centrifugal_displacement=u_cf,
        prestress_displacement=u_unit,
        stress_stiffening=k_sigma,
        rim_radial_displacement=rim_ur,
        rim_radial_displacement_condensed=ur_c,
        timings=timings,
        solver=solver,
        peak_memory_bytes=int(peak),
    )
