"""The Rayleigh integral: a flat panel in an infinite rigid baffle radiating into the half-space
on its normal's side.

With the time dependence e^{-iωt} and the normal velocity v on the panel (m/s, positive into the
fluid), the pressure at x is (Rayleigh's first integral; Kinsler et al., *Fundamentals of
Acoustics*, 4th ed., §7.4; Williams, *Fourier Acoustics*, eq. 2.75)

    p(x) = -iωρ/(2π) ∫ v(y) e^{ik|x-y|}/|x-y| dS(y)

and the radiated power W = ½ Re ∫ p v* dS = vᴴ R v with the radiation resistance matrix
(Elliott & Johnson, JASA 94 (1993) 2194, eq. 12, there per element; here through the P1
quadrature of :meth:`RadiatingSurface.quadrature`)

    R = ωρk/(4π) · Φᵀ W_q S W_q Φ,   S_pq = sin(k r_pq)/(k r_pq)

which is regular (the real part of the kernel has no singularity), real and symmetric.

NumPy and SciPy.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.distance import cdist

from ._surface import AIR, Fluid, RadiatingSurface

__all__ = ["rayleigh_pressure", "rayleigh_resistance", "rayleigh_transfer"]


def _planar(surface: RadiatingSurface, fn: str) -> tuple[np.ndarray, float]:
    if not isinstance(surface, RadiatingSurface):
        raise TypeError(f"{fn}: surface must be a RadiatingSurface, got {type(surface).__name__}")
    n = surface.normals
    if surface.closed or not np.allclose(n, n[0], atol=1e-9):
        raise ValueError(f"{fn}: the Rayleigh integral needs a flat open panel (one normal)")
    return n[0], float(np.mean(surface.centroids @ n[0]))


def rayleigh_resistance(
    surface: RadiatingSurface, frequency_hz: float, fluid: Fluid = AIR
) -> np.ndarray:
    """The radiation resistance matrix of a baffled flat panel by the Rayleigh integral.

    Args:
        surface: a flat, open :class:`RadiatingSurface` (one normal, into the fluid).
        frequency_hz: f > 0 (Hz).
        fluid: the medium (:data:`AIR` by default).

    Returns:
        ``(n, n)`` real symmetric R (kg/s) on the vertices: W = vᴴ R v (W) for complex
        vertex amplitudes v (m/s, peak).

    Raises:
        TypeError: ``surface`` not a RadiatingSurface.
        ValueError: a closed or curved surface, ``frequency_hz`` ≤ 0.
    """
    _planar(surface, "rayleigh_resistance")
    k = fluid.wavenumber(frequency_hz)
    omega = 2 * np.pi * frequency_hz
    pts, w, interp = surface.quadrature()
    r = cdist(pts, pts)
    s = np.sinc(k * r / np.pi)  # numpy's sinc is sin(πx)/(πx)
    a = interp * w[:, None]
    return omega * fluid.density * k / (4 * np.pi) * (a.T @ s @ a)


def rayleigh_transfer(
    surface: RadiatingSurface,
    frequency_hz: float,
    points: np.ndarray,
    fluid: Fluid = AIR,
) -> np.ndarray:
    """The matrix T with p(x) = T v: the complex pressure amplitudes (Pa, peak; e^{-iωt}) at
    field ``points`` ``(q, 3)`` (m) in front of a baffled flat panel per unit vertex normal
    velocity (m/s), the Rayleigh integral p = −iωρ/(2π) ∫ v e^{ikr}/r dS on the panel's 3-point
    quadrature (points at least a few triangle sizes off the panel).

    Returns:
        ``(q, n)`` complex T (Pa s/m).

    Raises:
        TypeError: ``surface`` not a RadiatingSurface.
        ValueError: a closed or curved surface, ``frequency_hz`` ≤ 0, points not ``(q, 3)``,
            a point behind or on the baffle.
    """
    normal, offset = _planar(surface, "rayleigh_transfer")
    x = np.asarray(points, dtype=float)
    if x.ndim != 2 or x.shape[1] != 3 or not np.all(np.isfinite(x)):
        raise ValueError(f"rayleigh_transfer: points must be finite (q, 3), got {x.shape}")
    if np.any(x @ normal - offset <= 0):
        raise ValueError("rayleigh_transfer: every point must lie in front of the baffle")
    k = fluid.wavenumber(frequency_hz)
    omega = 2 * np.pi * frequency_hz
    pts, w, interp = surface.quadrature()
    r = cdist(x, pts)
    g = np.exp(1j * k * r) / r
    return -1j * omega * fluid.density / (2 * np.pi) * (g @ (interp * w[:, None]))


def rayleigh_pressure(
    surface: RadiatingSurface,
    frequency_hz: float,
    velocity: np.ndarray,
    points: np.ndarray,
    fluid: Fluid = AIR,
) -> np.ndarray:
    """The complex pressure amplitude (Pa, peak; e^{-iωt}) at field ``points`` ``(q, 3)`` (m)
    in front of a baffled flat panel with vertex normal velocity ``velocity`` ``(n,)`` (m/s), by
    the Rayleigh integral on the panel's 3-point quadrature (points at least a few triangle
    sizes off the panel): :func:`rayleigh_transfer` times ``velocity``.

    Raises:
        TypeError: ``surface`` not a RadiatingSurface.
        ValueError: a closed or curved surface, ``frequency_hz`` ≤ 0, shapes that do not fit,
            a point behind or on the baffle.
    """
    _planar(surface, "rayleigh_pressure")
    v = np.asarray(velocity)
    if v.shape != (surface.n_vertices,):
        raise ValueError(
            f"rayleigh_pressure: velocity must be ({surface.n_vertices},), got {v.shape}"
        )
    x = np.asarray(points, dtype=float)
    if x.ndim != 2 or x.shape[1] != 3:
        raise ValueError(f"rayleigh_pressure: points must be (q, 3), got {x.shape}")
    return rayleigh_transfer(surface, frequency_hz, x, fluid) @ v
