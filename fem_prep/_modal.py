"""Modal analysis of a gear body: nodal diameters/circles (seed (3.2)) and resonance orders (3.9).

Nodal diameters: each mode shape is sampled on the complete circumferential rings of corner
nodes of the structured mesh, its cylindrical components (u_r, u_theta, u_z) are Fourier
analysed along the angle (3.2), ``delta = sum_n delta_c^n cos(n theta) + delta_s^n sin(n
theta)``, and the harmonic ``n`` carrying the largest share of the energy is the nodal-diameter
number.  Nodal circles: the n-th harmonic of the axial displacement is followed along the radius
on the web mid-surface (hub to rim) and its sign changes are counted.

Rotating-frame resonance orders (3.9): a mode of frequency ``omega_0`` with ``n`` nodal
diameters is excited by the mesh (``Z`` teeth) when ``omega_0 = (Z +- n) Omega``: backward order
``Z + n``, forward order ``Z - n`` (Tab. III-11).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._mesh import BodyMesh

__all__ = ["ModeFamily", "identify_modes", "nodal_diameter_spectrum", "resonance_orders"]


def resonance_orders(teeth: int, n: int | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotating-frame resonance orders of an n-nodal-diameter mode, seed (3.9).

    Args:
        teeth: tooth count ``Z`` of the wheel.
        n: nodal-diameter number(s).

    Returns:
        ``(backward, forward)`` orders ``Z + n`` and ``Z - n``: the wheel speed at resonance is
        ``omega_0 / order`` (rad/s for omega_0 in rad/s).
    """
    n = np.asarray(n)
    return teeth + n, teeth - n


@dataclass(frozen=True)
class ModeFamily:
    """Identification of one mode.

    Attributes:
        frequency_hz: natural frequency (Hz).
        nodal_diameters: dominant circumferential harmonic ``n``.
        nodal_circles: sign changes of the n-th harmonic of u_z along the web radius.
        harmonic_share: share of the mode's ring energy in harmonic ``n`` (0..1).
    """

    frequency_hz: float
    nodal_diameters: int
    nodal_circles: int
    harmonic_share: float


def _rings(bm: BodyMesh) -> tuple[np.ndarray, np.ndarray]:
    """Complete corner-node rings: node ids ``(n_rings, n_theta)`` and their (i, j) indices."""
    ijk = bm.vertex_ijk
    nt = bm.n_theta
    key = ijk[:, 0] * (ijk[:, 1].max() + 1) + ijk[:, 1]
    order = np.lexsort((ijk[:, 2], key))
    ks = key[order]
    uniq, start, count = np.unique(ks, return_index=True, return_counts=True)
    full = count == nt
    rings = np.stack([order[s : s + nt] for s in start[full]]) if full.any() else np.zeros((0, nt))
    ij = ijk[rings[:, 0], :2] if len(rings) else np.zeros((0, 2), dtype=int)
    return rings.astype(np.int64), ij


def _cylindrical(bm: BodyMesh, nodes: np.ndarray, shape: np.ndarray) -> np.ndarray:
    """Cylindrical components ``(..., 3)`` (u_r, u_theta, u_z) of a full-DOF shape at nodes."""
    x = bm.nodes[nodes]
    th = np.arctan2(x[..., 1], x[..., 0])
    u = shape.reshape(-1, 3)[nodes]
    c, s = np.cos(th), np.sin(th)
    return np.stack([c * u[..., 0] + s * u[..., 1], -s * u[..., 0] + c * u[..., 1], u[..., 2]], -1)


def nodal_diameter_spectrum(bm: BodyMesh, shape: np.ndarray) -> np.ndarray:
    """Energy of each circumferential harmonic of a mode shape, seed (3.2).

    Args:
        bm: the mesh.
        shape: full-DOF mode shape ``(n_dofs,)``.

    Returns:
        ``(n_theta // 2 + 1,)`` energies (sum over rings and cylindrical components of
        ``|delta_c^n|^2 + |delta_s^n|^2``), normalised to sum 1.
    """
    rings, _ = _rings(bm)
    ucyl = _cylindrical(bm, rings, shape)  # (n_rings, n_theta, 3)
    F = np.fft.rfft(ucyl, axis=1)
    e = np.sum(np.abs(F) ** 2, axis=(0, 2))
    return e / e.sum()


def identify_modes(
    bm: BodyMesh, shapes: np.ndarray, frequencies_hz: np.ndarray, *, web_z: float | None = None
) -> list[ModeFamily]:
    """Nodal diameters and nodal circles of mode shapes.

    Args:
        bm: the mesh.
        shapes: full-DOF mode shapes ``(n_dofs, n_modes)``.
        frequencies_hz: ``(n_modes,)`` (Hz).
        web_z: axial grid position (unsheared frame, m) of the web mid-surface; default the
            grid line nearest the middle of the axial grid.

    Returns:
        One :class:`ModeFamily` per mode.
    """
    rings, ij = _rings(bm)
    if web_z is None:
        web_z = 0.5 * (bm.z_grid[0] + bm.z_grid[-1])
    jw = int(np.argmin(np.abs(bm.z_grid - web_z)))
    # per radial index, the ring whose axial index is closest to jw
    radial_line = []
    for i in np.unique(ij[:, 0]):
        cand = np.nonzero(ij[:, 0] == i)[0]
        radial_line.append(cand[np.argmin(np.abs(ij[cand, 1] - jw))])
    radial_line = np.array(radial_line, dtype=int)
    out = []
    for m in range(shapes.shape[1]):
        ucyl = _cylindrical(bm, rings, shapes[:, m])
        F = np.fft.rfft(ucyl, axis=1)
        e = np.sum(np.abs(F) ** 2, axis=(0, 2))
        n = int(np.argmax(e))
        share = float(e[n] / e.sum())
        c = F[radial_line, n, 2]  # n-th harmonic of u_z along the radius
        phase = 0.5 * np.angle(np.sum(c**2))
        a = np.real(c * np.exp(-1j * phase))
        big = np.abs(a) > 0.05 * np.abs(a).max() if np.abs(a).max() > 0 else np.zeros_like(a, bool)
        sgn = np.sign(a[big])
        nc = int(np.sum(sgn[1:] != sgn[:-1]))
        out.append(ModeFamily(float(frequencies_hz[m]), n, nc, share))
    return out


def critical_speeds(teeth: int, families: list[ModeFamily]) -> list[dict[str, float]]:
    """Wheel speeds (rad/s) at which the mesh excites each mode, seed (3.9)."""
    rows = []
    for f in families:
        back, fwd = resonance_orders(teeth, f.nodal_diameters)
        w0 = 2 * math.pi * f.frequency_hz
        rows.append(
            {
                "frequency_hz": f.frequency_hz,
                "nodal_diameters": f.nodal_diameters,
                "nodal_circles": f.nodal_circles,
                "backward_order": int(back),
                "forward_order": int(fwd),
                "backward_speed_rad_s": w0 / back if back > 0 else math.inf,
                "forward_speed_rad_s": w0 / fwd if fwd > 0 else math.inf,
            }
        )
    return rows
