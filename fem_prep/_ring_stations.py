"""A condensed ring gear seen from its tooth stations, for the planetary dynamics and case files
(docs/planetary.md, "A flexible ring gear"): the static in-plane compliance at the Z stations
(:func:`~fem_prep.ring_master_compliance`), the stations' mass (the condensed ring reduced
statically onto the stations' in-plane displacements, Guyan 1965), the ring's fixed-interface
modes (the stations held) that complete it to a Craig–Bampton model on the stations
(:func:`ring_craig_bampton`), the ring's lowest in-plane nodal-diameter frequencies, built once
per ring body and then read from the fem_prep cache; the embedded ring bodies
(``fem_prep/bodies/rings/*.toml``).

Craig–Bampton on the stations (R. R. Craig & M. C. C. Bampton, AIAA J. 6 (1968) 1313; the
thesis's (2.3)-(2.5) with the stations as the interface): the condensed ring's coordinates x
(``prep.condensed``: K_c, M_c) are written ``x = Phi u + Psi eta`` with u the 2Z station
displacements (``u = E^T x``, E the stations' map of :func:`_station_map`), Phi = K_c^-1 E F^-1
the static constraint shapes (a unit station displacement, the other stations still; F = E^T
K_c^-1 E the station compliance) and Psi the fixed-interface modes: the modes of (K_c, M_c) on
the subspace E^T x = 0 (the stations held), mass-normalised, eigenvalues Lambda. Then Phi^T K_c
Psi = F^-1 E^T Psi = 0 and

    K_cb = [[F^-1, 0], [0, Lambda]],    M_cb = [[M_u, M_ue], [M_ue^T, I]],

M_u = Phi^T M_c Phi (the Guyan station mass), M_ue = Phi^T M_c Psi. With every fixed-interface
mode the basis spans the condensed ring exactly; a mode whose M_ue column vanishes (by the
ring's symmetry about its mid-plane: the out-of-plane and axially antisymmetric motion of the
masters) never moves under loads at the stations and is left out (:data:`COUPLED`).
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np
import scipy.linalg as sla

from . import files
from ._ring import PreparedRing, RingBody, mode_nodal_diameter, prepare_ring, ring_master_compliance
from .schema import parse_ring_body

__all__ = [
    "RingStations",
    "embedded_ring_text",
    "embedded_rings",
    "load_ring_body",
    "ring_craig_bampton",
    "ring_interior_modes",
    "ring_nd_frequencies",
    "ring_station_mass",
    "ring_stations",
]

#: bump when what a cached ring holds changes (2: the fixed-interface modes)
RING_FORMAT = 2
#: a fixed-interface mode is kept when its inertial coupling to the stations (the norm of its
#: column of M_ue) exceeds this share of the largest (module docstring)
COUPLED = 1e-6
#: in-plane share of a mode's squared displacement above which it is an in-plane ND mode
IN_PLANE = 0.5


@dataclass(frozen=True)
class RingStations:
    """A ring at its Z tooth stations (SI units).

    Attributes:
        compliance: F (m/N), (Z, 2, Z, 2) (:func:`~fem_prep.ring_master_compliance`).
        mass: M_u (kg), (Z, 2, Z, 2) (:func:`ring_station_mass`).
        nd_frequencies: {n: f (Hz)} the lowest in-plane mode of each nodal diameter n among
            the condensed ring's lowest modes (:func:`ring_nd_frequencies`).
        body: the :class:`~fem_prep.RingBody`.
        interior_eigenvalues: Lambda ((rad/s)^2, (m,)), ascending: the ring's fixed-interface
            modes that couple to the stations (:func:`ring_interior_modes`); None: not built.
        coupling: M_ue (kg^(1/2), (Z, 2, m)): their mass coupling to the stations' in-plane
            displacements (module docstring; the modes mass-normalised); None with them.
    """

    compliance: np.ndarray
    mass: np.ndarray
    nd_frequencies: dict
    body: RingBody
    interior_eigenvalues: np.ndarray | None = None
    coupling: np.ndarray | None = None

    def craig_bampton(self, modes: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``(K_cb (N/m), M_cb (kg))``, each ``(2Z + m, 2Z + m)``: the Craig–Bampton ring on the
        stations with its ``modes`` lowest coupled fixed-interface modes (None: all; module
        docstring), the station block of K_cb F^-1.

        Raises:
            ValueError: ``modes`` outside 0..m, or the modes not built (one line).
        """
        if self.interior_eigenvalues is None or self.coupling is None:
            raise ValueError("RingStations.craig_bampton: no fixed-interface modes (allowed: "
                             "RingStations from fem_prep.ring_stations)")
        lam, cpl = self.interior_eigenvalues, self.coupling
        z2 = 2 * self.compliance.shape[0]
        m = lam.size if modes is None else modes
        if isinstance(m, bool) or not isinstance(m, (int, np.integer)) or not 0 <= m <= lam.size:
            raise ValueError(f"RingStations.craig_bampton: modes = {modes!r} is out of range: "
                             f"allowed an integer 0..{lam.size} (the coupled fixed-interface "
                             "modes)")
        return _cb_matrices(self.compliance.reshape(z2, z2), self.mass.reshape(z2, z2),
                            lam[:m], cpl.reshape(z2, -1)[:, :m])


def _station_map(prep: PreparedRing) -> np.ndarray:
    """E (n_condensed, 2Z): the condensed forces of unit in-plane station forces (trapezoid
    weights over the axial masters, as :func:`~fem_prep.ring_master_compliance`)."""
    c = prep.condensed
    teeth, nax, _ = prep.master_dofs.shape
    w = np.ones(nax) if nax == 1 else np.r_[0.5, np.ones(nax - 2), 0.5]
    w = w / w.sum()
    E = np.zeros((teeth, nax, 3, teeth, 2))
    for a in range(2):
        E[np.arange(teeth), :, a, np.arange(teeth), a] = w
    out = np.zeros((c.K.shape[0], 2 * teeth))
    out[: c.master_dofs.size] = E.reshape(-1, 2 * teeth)
    return out


def _station_shapes(prep: PreparedRing) -> tuple[np.ndarray, np.ndarray]:
    """``(Phi (n_condensed, 2Z), F (m/N, (2Z, 2Z)))``: the static constraint shapes Phi = K_c^-1
    E F^-1 (a unit station displacement, the other stations still) and the station compliance."""
    F, _ = ring_master_compliance(prep)
    z2 = 2 * F.shape[0]
    F = F.reshape(z2, z2)
    return np.linalg.solve(prep.condensed.K, _station_map(prep)) @ np.linalg.inv(F), F


def ring_station_mass(prep: PreparedRing) -> np.ndarray:
    """M_u (kg, (Z, 2, Z, 2)): the condensed ring's mass reduced onto its stations' in-plane
    displacements by the static shapes Phi = K_c^-1 E F^-1 (unit station displacements, the
    other stations still): ``M_u = Phi^T M_c Phi`` (Guyan 1965). Exact for the ring's rigid
    translation; its nodal-diameter modes converge from above as they grow relative to Z.

    Raises:
        ValueError: a free ring (as :func:`~fem_prep.ring_master_compliance`).
    """
    phi, F = _station_shapes(prep)
    m = phi.T @ prep.condensed.M @ phi
    z = F.shape[0] // 2
    return (0.5 * (m + m.T)).reshape(z, 2, z, 2)


def ring_interior_modes(prep: PreparedRing) -> tuple[np.ndarray, np.ndarray]:
    """``(Lambda ((rad/s)^2, (m,)), Psi (n_condensed, m))``: the condensed ring's fixed-interface
    modes, the stations held (the modes of (K_c, M_c) on E^T x = 0, solved with scipy on an
    orthonormal basis of that subspace), mass-normalised, ascending, those that couple to the
    stations (:data:`COUPLED`; module docstring).

    Raises:
        ValueError: a free ring (as :func:`~fem_prep.ring_master_compliance`).
    """
    c = prep.condensed
    phi, _ = _station_shapes(prep)
    null = sla.null_space(_station_map(prep).T)
    k, m = null.T @ c.K @ null, null.T @ c.M @ null
    lam, vec = sla.eigh(0.5 * (k + k.T), 0.5 * (m + m.T))
    psi = null @ vec
    share = np.linalg.norm(phi.T @ c.M @ psi, axis=0)
    keep = share > COUPLED * share.max()
    return lam[keep], psi[:, keep]


def _cb_matrices(F, M_u, lam, coupling) -> tuple[np.ndarray, np.ndarray]:
    z2, m = F.shape[0], lam.size
    K = np.zeros((z2 + m, z2 + m))
    K[:z2, :z2] = np.linalg.inv(F)
    K[:z2, :z2] = 0.5 * (K[:z2, :z2] + K[:z2, :z2].T)
    K[z2:, z2:] = np.diag(lam)
    M = np.block([[0.5 * (M_u + M_u.T), coupling], [coupling.T, np.eye(m)]])
    return K, M


def ring_craig_bampton(prep: PreparedRing, modes: int | None = None
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(K_cb (N/m), M_cb (kg), T)``: the condensed ring reduced Craig–Bampton style onto its
    Z stations' in-plane displacements and its ``modes`` lowest coupled fixed-interface modes
    (None: all of them; :func:`ring_interior_modes`), each matrix ``(2Z + m, 2Z + m)``, the
    coordinates (u, eta) (module docstring): K_cb = diag(F^-1, Lambda) assembled (its station
    block F^-1 exactly), M_cb = T^T M_c T; T = [Phi, Psi_m] ``(n_condensed, 2Z + m)`` the
    basis (``x = T (u, eta)``).

    Raises:
        ValueError: a free ring; ``modes`` outside 0..m (one line).
    """
    lam, psi = ring_interior_modes(prep)
    if modes is not None and not 0 <= modes <= lam.size:
        raise ValueError(f"ring_craig_bampton: modes = {modes!r} is out of range: allowed "
                         f"0..{lam.size} (the coupled fixed-interface modes)")
    lam, psi = lam[:modes], psi[:, :modes]
    phi, F = _station_shapes(prep)
    M_u = phi.T @ prep.condensed.M @ phi
    K, M = _cb_matrices(F, M_u, lam, phi.T @ prep.condensed.M @ psi)
    return K, M, np.hstack([phi, psi])


def ring_nd_frequencies(prep: PreparedRing, n_modes: int = 16,
                        basis: np.ndarray | None = None) -> dict[int, float]:
    """{n: f (Hz)}: the lowest frequency of each nodal diameter n among the condensed ring's
    lowest ``n_modes`` in-plane modes (in-plane share > :data:`IN_PLANE`;
    :func:`~fem_prep.mode_nodal_diameter`); with ``basis`` T ``(n_condensed, r)``: of the ring
    reduced on it, (T^T K_c T, T^T M_c T) (Rayleigh–Ritz: from above), e.g. the station shapes
    (the Guyan station model) or the Craig–Bampton basis of :func:`ring_craig_bampton`."""
    c = prep.condensed
    T = np.eye(c.K.shape[0]) if basis is None else np.asarray(basis)
    kr, mr = T.T @ c.K @ T, T.T @ c.M @ T
    lam, vec = sla.eigh(0.5 * (kr + kr.T), 0.5 * (mr + mr.T),
                        subset_by_index=[0, min(n_modes, kr.shape[0]) - 1])
    out: dict[int, float] = {}
    for k in range(lam.size):
        nd, inplane = mode_nodal_diameter(prep, prep.full_field(c.basis @ (T @ vec[:, k])))
        if inplane > IN_PLANE and nd not in out:
            out[nd] = float(np.sqrt(max(lam[k], 0.0)) / (2 * math.pi))
    return dict(sorted(out.items()))


def _key(body: RingBody) -> str:
    return hashlib.sha256(f"{body!r}:ring-v{RING_FORMAT}".encode()).hexdigest()[:32]


def ring_stations(body: RingBody, cache: Path | None = None) -> RingStations:
    """The :class:`RingStations` of ``body``, built once (:func:`~fem_prep.prepare_ring`) and
    then read from ``cache`` (a folder; None: :func:`~fem_prep.cache_dir`, the bodies' cache) as
    ``ring-<hash of the body>.npz``."""
    folder = Path(cache) if cache is not None else files.fem_prep_cache_dir()
    path = folder / f"ring-{_key(body)}.npz"
    if path.is_file():
        with np.load(path) as d:
            nd = dict(zip(d["nd"].tolist(), d["nd_hz"].tolist(), strict=True))
            return RingStations(d["compliance"], d["mass"], nd, body, d["interior"],
                                d["coupling"])
    prep = prepare_ring(body)
    F, _ = ring_master_compliance(prep)
    z = F.shape[0]
    lam, psi = ring_interior_modes(prep)
    phi, _ = _station_shapes(prep)
    coupling = (phi.T @ prep.condensed.M @ psi).reshape(z, 2, lam.size)
    out = RingStations(F, ring_station_mass(prep), ring_nd_frequencies(prep), body, lam,
                       coupling)
    folder.mkdir(parents=True, exist_ok=True)
    with files.atomic_open(path, "wb") as fh:
        np.savez(fh, compliance=out.compliance, mass=out.mass,
                 nd=np.array(list(out.nd_frequencies), dtype=int),
                 nd_hz=np.array(list(out.nd_frequencies.values())), interior=lam,
                 coupling=coupling)
    return out


def _folder():
    return resources.files("fem_prep") / "bodies" / "rings"


def embedded_rings() -> list[str]:
    """Names of the ring bodies shipped with fem_prep (``fem_prep/bodies/rings/*.toml``)."""
    return files.embedded_names(_folder())


def embedded_ring_text(name: str) -> str:
    """The TOML text of the embedded ring ``name``.

    Raises:
        FileNotFoundError: not an embedded ring (the message lists them).
    """
    return files.embedded_text(_folder(), name, "ring")


def load_ring_body(source: str | Path) -> RingBody:
    """A ring body from a file path or an embedded ring's name (:func:`embedded_rings`).

    Raises:
        FileNotFoundError: neither (the message lists the embedded rings).
        SchemaError: an invalid file (:func:`~fem_prep.schema.parse_ring_body`).
    """
    path = Path(source)
    if path.is_file():
        return parse_ring_body(path.read_text(encoding="utf-8"), default_name=path.stem,
                               label=f"ring file {str(source)!r}")
    name = str(source)
    if name in embedded_rings():
        return parse_ring_body(embedded_ring_text(name), default_name=name,
                               label=f"embedded ring {name!r}")
    raise FileNotFoundError(
        f"ring body {str(source)!r} not found (not a file, nor an embedded ring; embedded "
        f"rings: {', '.join(embedded_rings())})"
    )
