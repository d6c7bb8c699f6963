"""Outputs: versioned ``.npz`` (+ validating loader), ``.vtu`` (meshio), ``summary.json``, cache.

This is the only fem_prep module that imports meshio.  Every file is written atomically (a
temporary file in the same directory, then ``os.replace``).
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import platform
import shutil
import zipfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import scipy
import skfem

from ._body import Body
from ._modal import critical_speeds
from ._prepare import prepare
from .files import atomic_write, fem_prep_cache_dir, write_json
from .schema import load_body, parse_body

__all__ = [
    "FORMAT_VERSION",
    "CondensedBody",
    "build",
    "cache_dir",
    "cache_key",
    "condensed",
    "load_condensed",
    "output_names",
    "save_condensed",
    "summary_dict",
    "write_vtu",
]

FORMAT = "fem_prep.condensed"
# 2: rim master planes exactly at linspace(-b/2, b/2, n) (grid lines).
# 3: the rotating-frame matrices gyroscopic, spin_softening and stress_stiffening are required
#    keys (always written; spin_softening was optional before): a version-2 file lacks what the
#    rotating-frame dynamics needs, so it is rejected and rebuilt (the cache key holds the version).
FORMAT_VERSION = 4


# ------------------------------------------------------------------------------------------
# atomic writes


def _atomic(path: Path, write: Callable[[Path], None]) -> None:
    atomic_write(path, write)  # one implementation for jaxgear and fem_prep (fem_prep.schema)


def _atomic_text(path: Path, text: str) -> None:
    _atomic(path, lambda p: p.write_text(text, encoding="utf-8"))


def _atomic_copy(src: Path, dst: Path) -> None:
    _atomic(dst, lambda p: shutil.copyfile(src, p))


# ------------------------------------------------------------------------------------------
# the condensed body file


@dataclass(frozen=True)
class CondensedBody:
    """A condensed gear body loaded from ``.npz`` (all arrays NumPy, SI units).

    Condensed DOF order: rim master nodes (tooth ``k``, axial ``j``, component x/y/z), then the
    bearing nodes (u_x, u_y, u_z, theta_x, theta_y, theta_z each), then ``n_modes`` modal
    coordinates.  Everything here is a constant for jaxgear (no gradient through the FE mesh).

    Rotating frame: for the body spinning at the signed speed ``Omega`` (rad/s) about +z, the
    condensed coordinates ``q`` measured in the body frame (x, y, z turn with the body) obey,
    linearised about the centrifugal prestress,

        M q'' + 2 Omega gyroscopic q' + (K + Omega**2 (spin_softening + stress_stiffening)) q
            = Omega**2 f_centrifugal + f.

    All three rotating-frame matrices are ``basis^T T^T A T basis`` of the full-model operator
    ``A`` (``q_full = T basis q``), so they share the DOF order above.

    Attributes:
        K: condensed stiffness ``(n_c, n_c)``.
        M: condensed mass ``(n_c, n_c)``.
        f_centrifugal: centrifugal load per unit speed squared ``(n_c,)`` (N/(rad/s)^2,
            seed (2.37)); the load at wheel speed Omega is ``Omega**2 * f_centrifugal``.
        spin_softening: ``(n_c, n_c)`` symmetric, negative semi-definite, per unit speed squared
            (kg): ``-integral rho (u_x v_x + u_y v_y) dV``, the centripetal force of the
            displacement itself; the stiffness at speed gains ``Omega**2 * spin_softening``.
        gyroscopic: ``(n_c, n_c)`` skew-symmetric, per unit spin speed (kg):
            ``integral rho v . (e_z x u) dV`` (full model ``kron(M_scalar, J)``,
            ``J = [[0, -1, 0], [1, 0, 0], [0, 0, 0]]``); the Coriolis force is
            ``2 Omega gyroscopic q'`` on the left-hand side: a rigid velocity ``v e_x`` of
            the body of mass m gives the term ``2 Omega m v e_y`` there (the Coriolis inertia
            ``m 2 Omega e_z x v``; the fictitious Coriolis force is its opposite).
        stress_stiffening: ``(n_c, n_c)`` symmetric, per unit speed squared (N/m/(rad/s)^2):
            the geometric stiffness ``integral sigma0_ij d_i u_k d_j v_k dV`` of the
            linear-elastic centrifugal stress ``sigma0`` at 1 rad/s with the bearing nodes held
            (positive for the tensile hoop/radial prestress of a spinning wheel).
        master_coords: master-node coordinates ``(n_masters, 3)`` (m), rim nodes then bearings.
        master_kind: ``(n_masters,)`` 0 = rim node (3 DOFs), 1 = bearing node (6 DOFs).
        rim_grid: ``(teeth, n_axial)`` master-node index of each rim station (the wheel's rim).
        rim_shapes: ``(n_rims, 2)`` (stations, axial masters) of each rim, or ``None``: one
            rim. A body with a ``[pinion_rim]`` has two, whose masters follow each other (the
            wheel's, then the pinion's); :attr:`rim_grids` gives each rim's grid.
        dof_map: ``(n_c, 2)``: master-node index and component (0-5) per DOF; ``(-1, m)`` for
            modal coordinate ``m``.
        modes_hz: frequencies of the retained component modes ``(n_modes,)`` (Hz).
        recovery_coords: ``(n_rec, 3)`` coordinates (m) of the recovery nodes (mesh corners).
        recovery_cells: ``(n_cells, 8)`` hexahedra on the recovery nodes (VTK order).
        recovery: ``(3 n_rec, n_c)`` float32: ``u_nodes.ravel() = recovery @ q_c`` (node-major,
            x/y/z interleaved).
        metadata: dict (body name, method, sizes, frequencies, versions...).
        input_toml: the body file text.
        input_sha256: its sha256.
    """

    K: np.ndarray
    M: np.ndarray
    f_centrifugal: np.ndarray
    spin_softening: np.ndarray
    gyroscopic: np.ndarray
    stress_stiffening: np.ndarray
    master_coords: np.ndarray
    master_kind: np.ndarray
    rim_grid: np.ndarray
    dof_map: np.ndarray
    modes_hz: np.ndarray
    recovery_coords: np.ndarray
    recovery_cells: np.ndarray
    recovery: np.ndarray
    metadata: dict[str, Any]
    input_toml: str
    input_sha256: str
    rim_shapes: np.ndarray | None = None

    @property
    def rim_grids(self) -> tuple[np.ndarray, ...]:
        """Each rim's ``(stations, n_axial)`` master-node indices, the wheel's rim first."""
        if self.rim_shapes is None:
            return (self.rim_grid,)
        out, start = [], 0
        for z, nax in np.asarray(self.rim_shapes):
            out.append(start + np.arange(z * nax).reshape(z, nax))
            start += z * nax
        return tuple(out)

    @property
    def n_dofs(self) -> int:
        """Number of condensed DOFs."""
        return self.K.shape[0]

    @property
    def body(self) -> Body:
        """The body that made this file (parsed again from ``input_toml``)."""
        return parse_body(self.input_toml, default_name=self.metadata.get("name", "body"))


_REQUIRED = (
    "format",
    "format_version",
    "K",
    "M",
    "f_centrifugal",
    "spin_softening",
    "gyroscopic",
    "stress_stiffening",
    "master_coords",
    "master_kind",
    "rim_grid",
    "dof_map",
    "modes_hz",
    "recovery_coords",
    "recovery_cells",
    "recovery",
    "metadata",
    "input_toml",
    "input_sha256",
)


def _arrays(prep: Any) -> dict[str, np.ndarray]:
    """Arrays of the condensed file from a :class:`~fem_prep._prepare.Prepared`."""
    body, bm, ms, cp, cond = prep.body, prep.mesh, prep.masters, prep.coupled, prep.condensed
    teeth, nax = ms.rim_nodes.shape
    nb = len(ms.bearing_rings)
    shapes = [r.nodes.shape for r in ms.rims]
    n_rim = sum(a * b for a, b in shapes)
    coords = np.concatenate(
        [
            cp.rim_positions.reshape(-1, 3),
            *(pos.reshape(-1, 3) for _, pos in cp.more_rims),
            ms.bearing_positions,
        ]
    )
    kind = np.concatenate([np.zeros(n_rim, np.int8), np.ones(nb, np.int8)])
    dof_map = np.concatenate(
        [
            np.stack([np.repeat(np.arange(n_rim), 3), np.tile(np.arange(3), n_rim)], 1),
            np.stack([np.repeat(n_rim + np.arange(nb), 6), np.tile(np.arange(6), nb)], 1),
            np.stack([-np.ones(cond.n_modes, int), np.arange(cond.n_modes)], 1),
        ]
    ).astype(np.int64)
    nv = bm.n_vertices
    vdofs = np.arange(3 * nv)
    rec = (cp.T[vdofs] @ cond.basis).astype(np.float32)
    meta = {
        "name": body.name,
        "method": str(cond.method),
        "element": str(bm.element),
        "n_nodes": bm.n_nodes,
        "n_dofs": bm.n_dofs,
        "n_elements": int(bm.mesh.nelements),
        "n_theta": bm.n_theta,
        "teeth": teeth,
        "axial_master_nodes": nax,
        "bearing_couplings": [str(c) for c in ms.couplings],
        "rim_coupling": str(ms.rim_coupling),
        "mass_kg": prep.operators.mass,
        "speed_rad_s": body.speed,
        "support": str(body.support),
        "frequencies_full_hz": [float(x) for x in prep.frequencies_full_hz],
        "frequencies_condensed_hz": [float(x) for x in prep.frequencies_condensed_hz],
        "body_sha256": body.sha256,
        "versions": _versions(),
    }
    out = {
        "format": np.array(FORMAT),
        "format_version": np.array(FORMAT_VERSION),
        "K": cond.K,
        "M": cond.M,
        "f_centrifugal": cond.f_centrifugal,
        "spin_softening": cond.spin_softening,
        "gyroscopic": cond.gyroscopic,
        "stress_stiffening": cond.stress_stiffening,
        "master_coords": coords,
        "master_kind": kind,
        "rim_grid": np.arange(teeth * nax).reshape(teeth, nax),
        "dof_map": dof_map,
        "modes_hz": np.asarray(cond.modes_hz, dtype=float),
        "recovery_coords": bm.nodes[:nv],
        "recovery_cells": bm.cells.astype(np.int64),
        "recovery": rec,
        "metadata": np.array(json.dumps(meta)),
        "input_toml": np.array(body.source_text),
        "input_sha256": np.array(body.text_sha256),
    }
    if len(shapes) > 1:  # a body with a pinion rim: each rim's (stations, axial masters)
        out["rim_shapes"] = np.array(shapes, dtype=np.int64)
        meta["rim_teeth"] = [int(a) for a, _ in shapes]
        out["metadata"] = np.array(json.dumps(meta))
    missing = [k for k in ("spin_softening", "gyroscopic", "stress_stiffening") if out[k] is None]
    if missing:
        raise ValueError(f"the condensed model lacks {', '.join(missing)} (condense without them?)")
    return out


def save_condensed(prep: Any, path: str | Path) -> Path:
    """Write the condensed body of a :class:`~fem_prep._prepare.Prepared` to ``.npz``.

    Args:
        prep: the pipeline result.
        path: output file (written atomically).

    Returns:
        The path.
    """
    arrays = _arrays(prep)

    def write(p: Path) -> None:
        with open(p, "wb") as fh:
            np.savez(fh, **arrays)

    _atomic(Path(path), write)
    return Path(path)


def load_condensed(path: str | Path) -> CondensedBody:
    """Load and validate a condensed body file.

    Args:
        path: ``.npz`` written by :func:`save_condensed` / ``fem-prep build``.

    Returns:
        The :class:`CondensedBody`.

    Raises:
        FileNotFoundError: no such file.
        ValueError: truncated/corrupt file, wrong format or version, a missing key, an array
            of the wrong shape, or an input hash that does not match the stored input.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"condensed body file {str(path)!r} not found")
    try:
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
    except (zipfile.BadZipFile, EOFError, OSError, ValueError, KeyError) as exc:
        raise ValueError(f"{path}: not a readable .npz (truncated or corrupt file): {exc}") from exc
    missing = [k for k in _REQUIRED if k not in data]
    if missing:
        raise ValueError(f"{path}: missing key(s) {', '.join(missing)}; rebuild with fem-prep")
    if str(data["format"]) != FORMAT:
        raise ValueError(f"{path}: format {str(data['format'])!r}, expected {FORMAT!r}")
    ver = int(data["format_version"])
    if ver != FORMAT_VERSION:
        raise ValueError(
            f"{path}: format_version {ver} is not supported (this fem_prep reads "
            f"{FORMAT_VERSION}); rebuild with fem-prep"
        )
    text = str(data["input_toml"])
    sha = str(data["input_sha256"])
    if hashlib.sha256(text.encode()).hexdigest() != sha:
        raise ValueError(f"{path}: input_sha256 does not match the stored input (hash mismatch)")

    def shape_err(key: str, expected: str) -> ValueError:
        return ValueError(f"{path}: {key} has shape {data[key].shape}, expected {expected}")

    K, M = data["K"], data["M"]
    if K.ndim != 2 or K.shape[0] != K.shape[1]:
        raise shape_err("K", "(n_c, n_c)")
    n = K.shape[0]
    for key in ("M", "spin_softening", "gyroscopic", "stress_stiffening"):
        if data[key].shape != (n, n):
            raise shape_err(key, f"({n}, {n})")
    if data["f_centrifugal"].shape != (n,):
        raise shape_err("f_centrifugal", f"({n},)")
    if data["dof_map"].shape != (n, 2):
        raise shape_err("dof_map", f"({n}, 2)")
    mc = data["master_coords"]
    if mc.ndim != 2 or mc.shape[1] != 3:
        raise shape_err("master_coords", "(n_masters, 3)")
    if data["master_kind"].shape != (mc.shape[0],):
        raise shape_err("master_kind", f"({mc.shape[0]},)")
    kind = data["master_kind"]
    n_b = int(3 * np.sum(kind == 0) + 6 * np.sum(kind == 1))
    n_modes = n - n_b
    if n_modes < 0 or data["modes_hz"].shape != (n_modes,):
        raise shape_err("modes_hz", f"({n_modes},) (n_c minus master DOFs)")
    shapes = data.get("rim_shapes")
    n_rim = int(np.sum(kind == 0))
    if shapes is not None and (
        shapes.ndim != 2 or shapes.shape[1] != 2 or int(np.sum(np.prod(shapes, 1))) != n_rim
    ):
        raise shape_err("rim_shapes", f"(n_rims, 2) of stations x axial masters summing to {n_rim}")
    first = n_rim if shapes is None else int(np.prod(shapes[0]))
    if data["rim_grid"].ndim != 2 or data["rim_grid"].size != first:
        raise shape_err("rim_grid", "(teeth, n_axial)")
    rc = data["recovery_coords"]
    if rc.ndim != 2 or rc.shape[1] != 3:
        raise shape_err("recovery_coords", "(n_rec, 3)")
    if data["recovery"].shape != (3 * rc.shape[0], n):
        raise shape_err("recovery", f"({3 * rc.shape[0]}, {n})")
    cells = data["recovery_cells"]
    if cells.ndim != 2 or cells.shape[1] != 8 or (cells.size and cells.max() >= rc.shape[0]):
        raise shape_err("recovery_cells", f"(n_cells, 8) with indices < {rc.shape[0]}")
    for key in ("K", "M", "spin_softening", "gyroscopic", "stress_stiffening"):
        if not np.all(np.isfinite(data[key])):
            raise ValueError(f"{path}: {key} contains non-finite values")
    try:
        meta = json.loads(str(data["metadata"]))
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path}: metadata is not valid JSON: {exc}") from exc
    return CondensedBody(
        K=K,
        M=M,
        f_centrifugal=data["f_centrifugal"],
        spin_softening=data["spin_softening"],
        gyroscopic=data["gyroscopic"],
        stress_stiffening=data["stress_stiffening"],
        master_coords=mc,
        master_kind=kind,
        rim_grid=data["rim_grid"],
        dof_map=data["dof_map"],
        modes_hz=data["modes_hz"],
        recovery_coords=rc,
        recovery_cells=cells,
        recovery=data["recovery"],
        metadata=meta,
        input_toml=text,
        input_sha256=sha,
        rim_shapes=shapes,
    )


# ------------------------------------------------------------------------------------------
# VTU and summary


def write_vtu(prep: Any, path: str | Path) -> Path:
    """Write the mesh (corner nodes, linear hexahedra) with mode shapes and the centrifugal
    deflection as point data (meshio ``.vtu`` for ParaView).

    Point data: ``centrifugal_displacement`` (m, at ``[centrifugal] speed_rad_s``, bearings
    held) and ``mode_XX_<f>Hz_ND<n>`` (mass-normalised shapes) for the first ``vtu_modes``
    modes; cell data: ``region`` (0 hub/stub, 1 web, 2 rim).
    """
    import meshio  # lazy: the one module that imports meshio, only when a .vtu is written

    bm = prep.mesh
    nv = bm.n_vertices
    pdata = {"centrifugal_displacement": prep.centrifugal_displacement.reshape(-1, 3)[:nv]}
    for k in range(min(prep.body.vtu_modes, prep.mode_shapes.shape[1])):
        fam = prep.families[k]
        name = f"mode_{k + 1:02d}_{fam.frequency_hz:.0f}Hz_ND{fam.nodal_diameters}"
        pdata[name] = prep.mode_shapes[:, k].reshape(-1, 3)[:nv]
    mesh = meshio.Mesh(
        bm.nodes[:nv],
        [("hexahedron", bm.cells)],
        point_data=pdata,
        cell_data={"region": [bm.region.astype(np.int32)]},
    )
    _atomic(Path(path), lambda p: meshio.write(str(p), mesh, file_format="vtu"))
    return Path(path)


def _versions() -> dict[str, str]:
    return {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "scikit-fem": skfem.__version__,
        "machine": f"{platform.machine()} {platform.processor() or ''}".strip(),
        "cpus": str(os.cpu_count()),
    }


def summary_dict(prep: Any) -> dict[str, Any]:
    """The ``summary.json`` content of a pipeline result (see ``docs/fem_prep.md``)."""
    body = prep.body
    return {
        "name": body.name,
        "n_nodes": prep.mesh.n_nodes,
        "n_dofs": prep.mesh.n_dofs,
        "n_elements": int(prep.mesh.mesh.nelements),
        "element": str(prep.mesh.element),
        "mass_kg": prep.operators.mass,
        "method": str(prep.condensed.method),
        "n_master_dofs": int(len(prep.master_dofs)),
        "rim_coupling": str(prep.masters.rim_coupling),
        "n_modes": int(prep.condensed.n_modes),
        "n_condensed_dofs": int(prep.condensed.K.shape[0]),
        "support": str(body.support),
        "frequencies_full_hz": [float(x) for x in prep.frequencies_full_hz],
        "frequencies_condensed_hz": [float(x) for x in prep.frequencies_condensed_hz],
        "speed_rad_s": body.speed,
        "centrifugal_rim_radial_displacement_m": prep.rim_radial_displacement,
        "centrifugal_rim_radial_displacement_condensed_m": prep.rim_radial_displacement_condensed,
        "modes": critical_speeds(body.condensation.teeth, prep.families),
        "timings_s": {k: round(v, 3) for k, v in prep.timings.items()},
        "solver": prep.solver,
        "body_sha256": body.sha256,
        "input_sha256": body.text_sha256,
        "format_version": FORMAT_VERSION,
        "versions": _versions(),
    }


# ------------------------------------------------------------------------------------------
# cache and build


def cache_dir() -> Path:
    """Cache directory: ``$FEM_PREP_CACHE`` or ``~/.cache/jaxgear/fem_prep``."""
    return fem_prep_cache_dir()


def cache_key(body: Body) -> str:
    """The cache entry name of a body: hash of the parsed body, the file-format version and,
    for distributing rim masters, the coupling's revision (``cache_dir() / cache_key(body)`` holds its ``.npz``, ``.vtu`` and ``summary.json``)."""
    return _cache_key(body)


def _cache_key(body: Body) -> str:
    rev = body.condensation.rim_coupling.cache_revision()
    return hashlib.sha256(f"{body.sha256}:v{FORMAT_VERSION}{rev}".encode()).hexdigest()[:32]


def _cached(body: Body, *, use_cache: bool, progress: bool, out: Path) -> tuple[Path, bool]:
    """Directory holding the body's three output files (the cache entry, or ``out`` without the
    cache) and whether they came from the cache."""
    names = output_names(body)
    cdir = cache_dir() / _cache_key(body)
    if use_cache and all((cdir / n).is_file() for n in names.values()):
        try:
            load_condensed(cdir / names["npz"])
            json.loads((cdir / names["summary"]).read_text())
            return cdir, True
        except (ValueError, json.JSONDecodeError):
            pass
    prep = prepare(body, progress=progress)
    summary = summary_dict(prep)
    target = cdir if use_cache else out
    save_condensed(prep, target / names["npz"])
    write_vtu(prep, target / names["vtu"])
    write_json(target / names["summary"], summary)
    return target, False


def output_names(body: Body) -> dict[str, str]:
    """The names of the files :func:`build` writes into its folder for ``body``:
    ``{"npz": <name>.npz, "vtu": <name>.vtu, "summary": summary.json}``."""
    return {"npz": f"{body.name}.npz", "vtu": f"{body.name}.vtu", "summary": "summary.json"}


def condensed(source: str | Path | Body, *, progress: bool = False) -> CondensedBody:
    """The condensed body of a body file, an embedded body name, a :class:`Body` or a condensed
    ``.npz`` path, built once and then read from the cache (:func:`build`'s cache).

    Raises:
        FileNotFoundError, SchemaError, ValueError: as :func:`load_body` / :func:`load_condensed`.
    """
    return _condensed(source, progress)


@functools.singledispatch
def _condensed(source: str | Path, progress: bool) -> CondensedBody:
    """:func:`condensed` of a path or a name: a ``.npz`` read as is, else a body file."""
    if str(source).endswith(".npz"):
        return load_condensed(source)
    return _condensed(load_body(source), progress)


@_condensed.register
def _(source: Body, progress: bool) -> CondensedBody:
    where, _ = _cached(source, use_cache=True, progress=progress, out=cache_dir())
    return load_condensed(where / output_names(source)["npz"])


@functools.singledispatch
def _as_body(source: str | Path) -> Body:
    """A body: the one given, or the one a body file or an embedded body's name describes."""
    return load_body(source)


@_as_body.register
def _(source: Body) -> Body:
    return source


def build(
    source: str | Path | Body,
    out_dir: str | Path | None = None,
    *,
    use_cache: bool = True,
    progress: bool = False,
) -> dict[str, Any]:
    """Build (or fetch from the cache) a condensed body and write its outputs.

    Writes ``<out_dir>/<name>.npz``, ``<out_dir>/<name>.vtu`` and ``<out_dir>/summary.json``.
    The cache (``cache_dir()/<key>/``, key = hash of the parsed body and the format version)
    keeps the three files, so the same body is never condensed twice.

    Args:
        source: body file path, embedded body name or a :class:`Body`.
        out_dir: output directory; default ``fem-prep-out/<name>``.
        use_cache: read/write the cache.
        progress: show progress bars.

    Returns:
        The summary dict, plus ``"cache_hit"`` and ``"files"`` (paths written).
    """
    body = _as_body(source)
    out = Path(out_dir) if out_dir is not None else Path("fem-prep-out") / body.name
    names = output_names(body)
    where, hit = _cached(body, use_cache=use_cache, progress=progress, out=out)
    summary = json.loads((where / names["summary"]).read_text())
    if where != out:
        for n in names.values():
            _atomic_copy(where / n, out / n)
    summary = dict(summary)
    summary["cache_hit"] = hit
    summary["files"] = {k: str(out / n) for k, n in names.items()}
    return summary
