"""The radiation resistance matrix R of a surface per frequency, built once and cached.

The radiated power of a surface vibrating with complex vertex normal velocity amplitudes v
(m/s, peak) is W = ½ Re ∫ p v* dS = vᴴ R v (W), R Hermitian and positive semi-definite (kg/s).
For a closed surface (BEM, :func:`bem_impedance`: p = Z v, M the P1 mass matrix)
R = ¼ (M Z + Zᴴ M); for a baffled flat panel R is the Rayleigh resistance
(:func:`rayleigh_resistance`). R depends on the surface, the fluid and the frequency only, not on
the gear design: it is computed once and read from fem_prep's cache
(``fem_prep.cache_dir() / "radiation" / <key>.npz``, the same mechanism as the tooth tables
and the housing: the key hashes the vertices, triangles, frequencies, fluid, method, rank and
format version; atomic writes, a corrupt or stale entry is rebuilt).

The low-rank form keeps the r largest eigenpairs of each R: R ≈ L Lᴴ with L = U √Λ ``(n, r)``,
the surface's radiation modes (Elliott & Johnson, JASA 94 (1993) 2194; Cunefare, JASA 90 (1991)
2521): few modes radiate efficiently at low ka, so r ≪ n.

NumPy/SciPy, bempp-cl for the BEM; never JAX.
"""

from __future__ import annotations

import abc
import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from .._fe_cache import cache_key, load_entry, store_entry, table_dir
from .._kinds import Kind
from ._bem import BEMBackend, BurtonMiller, Formulation, bem_field_transfer, bem_impedance
from ._rayleigh import rayleigh_resistance, rayleigh_transfer
from ._surface import AIR, Fluid, RadiatingSurface

__all__ = [
    "BEM",
    "ERP",
    "RADIATION_FORMAT",
    "RadiationMethod",
    "RadiationResistance",
    "Rayleigh",
    "radiation_resistance",
]

#: bump when what a cached radiation resistance holds changes
RADIATION_FORMAT = 1


class RadiationMethod(Kind):
    """How R is computed (a kind: pass an instance; printed and compared by its name, which
    the cache key holds)."""

    @abc.abstractmethod
    def resistance(self, surface: RadiatingSurface, frequency_hz: float, fluid: Fluid):
        """``(n, n)`` Hermitian R (kg/s) at one frequency."""

    def operators(self, surface, frequency_hz, fluid, points=None):
        """R and, given field ``points`` ``(q, 3)`` (m), the transfer ``(q, n)`` from the
        vertex normal velocity to the pressure there (Pa s/m; ``None`` without points).

        Raises:
            ValueError: points given to a method that has no field pressure."""
        if points is not None:
            raise ValueError(f"radiation_resistance: method {self} gives no field pressure")
        return self.resistance(surface, frequency_hz, fluid), None


class BEM(RadiationMethod):
    """Exterior BEM on a closed surface (bempp-cl, :func:`bem_impedance`), ``formulation``
    :class:`BurtonMiller` (default) or :class:`Direct`; ``backend`` where bempp-cl assembles,
    :class:`Numba` or :class:`OpenCL` (``None``: :func:`default_backend`, chosen at the first
    solve; the same R to round-off, so not in the name nor the cache key); ``progress`` shows
    a bar over each solve's operator assemblies."""

    def __init__(
        self,
        formulation: Formulation | None = None,
        progress: bool = False,
        backend: BEMBackend | None = None,
    ):
        formulation = BurtonMiller() if formulation is None else formulation
        if not isinstance(formulation, Formulation):
            raise TypeError(
                f"BEM: formulation must be BurtonMiller() or Direct(), got {formulation!r}"
            )
        if backend is not None and not isinstance(backend, BEMBackend):
            raise TypeError(f"BEM: backend must be Numba() or OpenCL(), got {backend!r}")
        self.formulation = formulation
        self.backend = backend
        self.progress = bool(progress)

    @property
    def name(self) -> str:  # type: ignore[override]
        return f"bem/{self.formulation}"

    def __repr__(self):
        return f"BEM({self.formulation!r})"

    def resistance(self, surface, frequency_hz, fluid):
        return self.operators(surface, frequency_hz, fluid)[0]

    def operators(self, surface, frequency_hz, fluid, points=None):
        Z = bem_impedance(surface, frequency_hz, fluid, self.formulation,
                          progress=self.progress, backend=self.backend)
        MZ = surface.mass_matrix() @ Z
        T = None if points is None else bem_field_transfer(surface, frequency_hz, Z, points, fluid)
        return 0.25 * (MZ + MZ.conj().T), T


class Rayleigh(RadiationMethod):
    """The Rayleigh integral on a baffled flat panel (:func:`rayleigh_resistance`)."""

    name = "rayleigh"

    def resistance(self, surface, frequency_hz, fluid):
        return rayleigh_resistance(surface, frequency_hz, fluid).astype(complex)

    def operators(self, surface, frequency_hz, fluid, points=None):
        R = self.resistance(surface, frequency_hz, fluid)
        T = None if points is None else rayleigh_transfer(surface, frequency_hz, points, fluid)
        return R, T


class ERP(RadiationMethod):
    """The equivalent radiated power as a resistance: R = ½ ρc M (M the P1 mass matrix), every
    part of the surface radiating as a plane wave (radiation efficiency 1; close to the power
    above the coincidence frequency, an upper estimate below it: Fritze, Marburg & Hardtke,
    Acta Acust. united Ac. 95 (2009)). Any surface, open or closed; no field pressure."""

    name = "erp"

    def resistance(self, surface, frequency_hz, fluid):
        return (0.5 * fluid.impedance * surface.mass_matrix()).astype(complex)


@dataclass(frozen=True, eq=False)
class RadiationResistance:
    """R per frequency on a surface's vertices (what the cache holds).

    Attributes:
        frequencies_hz: ``(f,)`` (Hz).
        factors: ``(f, n, r)`` complex L with R ≈ L Lᴴ (kg/s)^½; r = n when no rank was
            asked for (then L Lᴴ = R up to round-off, clipped negative eigenvalues aside).
        eigenvalues: ``(f, n)`` the eigenvalues of each R, descending (kg/s): the radiation
            modes' resistances (their tail shows what a rank r drops).
        fluid_density, sound_speed: the fluid (kg/m³, m/s).
        method: the method's name (``"bem/burton-miller"``, ``"rayleigh"``, ``"erp"``).
        key: the cache key.
        points: ``(q, 3)`` the field points asked for (m), or ``None``.
        transfer: ``(f, q, n)`` complex: the pressure amplitude at each point per unit vertex
            normal velocity (Pa s/m; p = T v, e^{-iωt}), or ``None`` without points.
    """

    frequencies_hz: np.ndarray
    factors: np.ndarray
    eigenvalues: np.ndarray
    fluid_density: float
    sound_speed: float
    method: str
    key: str
    points: np.ndarray | None = None
    transfer: np.ndarray | None = None

    def matrix(self, i: int) -> np.ndarray:
        """``(n, n)`` R ≈ L Lᴴ at the ``i``-th frequency (kg/s)."""
        L = self.factors[i]
        return L @ L.conj().T

    def power(self, velocity: np.ndarray) -> np.ndarray:
        """``(f,)`` W = ‖Lᴴ v‖² (W) for vertex normal velocities ``(f, n)`` or ``(n,)`` (m/s)."""
        v = np.broadcast_to(np.asarray(velocity), self.factors.shape[:2])
        return np.sum(np.abs(np.einsum("fnr,fn->fr", self.factors.conj(), v)) ** 2, axis=1)


def _factor(R: np.ndarray, rank: int | None):
    lam, U = np.linalg.eigh(0.5 * (R + R.conj().T))
    lam, U = lam[::-1], U[:, ::-1]
    r = len(lam) if rank is None else min(rank, len(lam))
    return U[:, :r] * np.sqrt(np.clip(lam[:r], 0.0, None)), lam


def _inputs(surface, freqs, fluid, method, rank, points=None):
    geo = hashlib.sha256(
        surface.vertices.astype("<f8").tobytes() + surface.triangles.astype("<i8").tobytes()
    ).hexdigest()
    extra = {} if points is None else {"points": [[repr(float(c)) for c in p] for p in points]}
    return extra | {
        "format_version": RADIATION_FORMAT,
        "surface_sha256": geo,
        "frequencies_hz": [repr(float(f)) for f in freqs],
        "fluid": [repr(fluid.density), repr(fluid.sound_speed)],
        "method": str(method),
        "rank": rank,
    }


def radiation_resistance(
    surface: RadiatingSurface,
    frequencies_hz,
    fluid: Fluid = AIR,
    method: RadiationMethod | None = None,
    *,
    rank: int | None = None,
    cache: bool | str | Path = True,
    progress: bool = False,
    points=None,
) -> RadiationResistance:
    """R (or its rank-r factor) of ``surface`` at each frequency, built once and then read from
    fem_prep's cache.

    Args:
        surface: the :class:`RadiatingSurface` (closed for :class:`BEM`, a flat panel for
            :class:`Rayleigh`).
        frequencies_hz: ``(f,)`` frequencies > 0 (Hz).
        fluid: the medium.
        method: :class:`BEM` (default), :class:`Rayleigh` or :class:`ERP`.
        rank: keep the ``rank`` largest radiation modes (``None``: all).
        cache: ``True`` (fem_prep's cache folder), ``False`` (build, store nothing) or a folder.
        progress: a tqdm bar over the frequencies (each a BEM assembly and solve).
        points: ``(q, 3)`` field points (m; microphones): the result also holds the transfer
            from the velocity to the pressure there (BEM: from the same solve; Rayleigh).

    Returns:
        The :class:`RadiationResistance`.

    Raises:
        TypeError: a surface, fluid or method of another type.
        ValueError: no frequency, a frequency ≤ 0 or not finite, ``rank`` not an integer ≥ 1,
            points not finite ``(q, 3)`` or given to :class:`ERP`, a surface the method cannot
            take (see the method).
    """
    method = BEM() if method is None else method
    if not isinstance(surface, RadiatingSurface):
        raise TypeError(
            f"radiation_resistance: surface must be a RadiatingSurface, got {type(surface).__name__}"
        )
    if not isinstance(fluid, Fluid):
        raise TypeError(f"radiation_resistance: fluid must be a Fluid, got {type(fluid).__name__}")
    if not isinstance(method, RadiationMethod):
        raise TypeError(
            f"radiation_resistance: method must be BEM(), Rayleigh() or ERP(), got {method!r}"
        )
    freqs = np.atleast_1d(np.asarray(frequencies_hz, dtype=float))
    if freqs.ndim != 1 or len(freqs) == 0 or not np.all(np.isfinite(freqs)) or freqs.min() <= 0:
        raise ValueError(
            f"radiation_resistance: frequencies_hz must be finite values > 0, got {frequencies_hz!r}"
        )
    if rank is not None and (isinstance(rank, bool) or not isinstance(rank, int) or rank < 1):
        raise ValueError(
            f"radiation_resistance: rank must be an integer >= 1 or None, got {rank!r}"
        )
    if points is not None:
        points = np.asarray(points, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3 or not np.all(np.isfinite(points)):
            raise ValueError(
                f"radiation_resistance: points must be finite (q, 3) (m), got {points.shape}"
            )
        if isinstance(method, ERP):
            raise ValueError("radiation_resistance: points given to ERP(): it has no pressure")
    inputs = _inputs(surface, freqs, fluid, method, rank, points)
    key = cache_key(inputs)
    path = None
    if cache is not False:
        folder = table_dir("radiation") if cache is True else Path(cache)
        path = folder / f"{key}.npz"
        d = load_entry(path, key, RADIATION_FORMAT, inputs)
        if d is not None:
            return RadiationResistance(
                frequencies_hz=d["frequencies_hz"],
                factors=d["factors"],
                eigenvalues=d["eigenvalues"],
                fluid_density=float(d["fluid_density"]),
                sound_speed=float(d["sound_speed"]),
                method=str(d["method"]),
                key=key,
                points=points,
                transfer=d["transfer"] if points is not None else None,
            )
    factors, eigs, transfer = [], [], []
    for f in tqdm(freqs, desc=f"radiation ({method})", disable=not progress):
        R, T = method.operators(surface, float(f), fluid, points)
        L, lam = _factor(R, rank)
        factors.append(L)
        eigs.append(lam)
        transfer.append(T)
    out = RadiationResistance(
        frequencies_hz=freqs,
        factors=np.stack(factors),
        eigenvalues=np.stack(eigs),
        fluid_density=fluid.density,
        sound_speed=fluid.sound_speed,
        method=str(method),
        key=key,
        points=points,
        transfer=None if points is None else np.stack(transfer),
    )
    if path is not None:
        extra = {} if points is None else {"transfer": out.transfer}
        store_entry(
            path,
            extra | {
                "frequencies_hz": out.frequencies_hz,
                "factors": out.factors,
                "eigenvalues": out.eigenvalues,
                "fluid_density": out.fluid_density,
                "sound_speed": out.sound_speed,
                "method": out.method,
                "key": key,
                "format_version": RADIATION_FORMAT,
                "inputs": json.dumps(inputs, sort_keys=True),
            },
        )
    return out
