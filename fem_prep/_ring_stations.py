"""A condensed ring gear seen from its tooth stations, for the planetary dynamics and case files
(docs/planetary.md, "A flexible ring gear"): the static in-plane compliance at the Z stations
(:func:`~fem_prep.ring_master_compliance`), the stations' mass (the condensed ring reduced
statically onto the stations' in-plane displacements, Guyan 1965), the ring's lowest in-plane
nodal-diameter frequencies, built once per ring body and then read from the fem_prep cache; the
embedded ring bodies (``fem_prep/bodies/rings/*.toml``).
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
    "ring_nd_frequencies",
    "ring_station_mass",
    "ring_stations",
]

#: bump when what a cached ring holds changes
RING_FORMAT = 1
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
    """

    compliance: np.ndarray
    mass: np.ndarray
    nd_frequencies: dict
    body: RingBody


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


def ring_station_mass(prep: PreparedRing) -> np.ndarray:
    """M_u (kg, (Z, 2, Z, 2)): the condensed ring's mass reduced onto its stations' in-plane
    displacements by the static shapes Phi = K_c^-1 E F^-1 (unit station displacements, the
    other stations still): ``M_u = Phi^T M_c Phi`` (Guyan 1965). Exact for the ring's rigid
    translation; its nodal-diameter modes converge from above as they grow relative to Z.

    Raises:
        ValueError: a free ring (as :func:`~fem_prep.ring_master_compliance`).
    """
    F, _ = ring_master_compliance(prep)
    z = F.shape[0]
    c = prep.condensed
    phi = np.linalg.solve(c.K, _station_map(prep)) @ np.linalg.inv(F.reshape(2 * z, 2 * z))
    m = phi.T @ c.M @ phi
    return (0.5 * (m + m.T)).reshape(z, 2, z, 2)


def ring_nd_frequencies(prep: PreparedRing, n_modes: int = 16) -> dict[int, float]:
    """{n: f (Hz)}: the lowest frequency of each nodal diameter n among the condensed ring's
    lowest ``n_modes`` in-plane modes (in-plane share > :data:`IN_PLANE`;
    :func:`~fem_prep.mode_nodal_diameter`)."""
    c = prep.condensed
    lam, vec = sla.eigh(c.K, c.M, subset_by_index=[0, min(n_modes, c.K.shape[0]) - 1])
    out: dict[int, float] = {}
    for k in range(lam.size):
        nd, inplane = mode_nodal_diameter(prep, prep.full_field(c.basis @ vec[:, k]))
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
            return RingStations(d["compliance"], d["mass"], nd, body)
    prep = prepare_ring(body)
    F, _ = ring_master_compliance(prep)
    out = RingStations(F, ring_station_mass(prep), ring_nd_frequencies(prep), body)
    folder.mkdir(parents=True, exist_ok=True)
    with files.atomic_open(path, "wb") as fh:
        np.savez(fh, compliance=out.compliance, mass=out.mass,
                 nd=np.array(list(out.nd_frequencies), dtype=int),
                 nd_hz=np.array(list(out.nd_frequencies.values())))
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
