"""The transmission-error stage of a sizing: for the best feasible candidates, the quasi-static
transmission error over a torque range, first of the plain flanks, then with the tip relief and
crowning that the optimiser (:mod:`optimise`, :class:`optimise.TePeakToPeak`) finds at the rated
torque (:func:`te_stage`). A candidate becomes the library's pair (:func:`candidate_pair`) and
its rigid mesh model (:func:`candidate_mesh`), the pair and mesh of the case file that
``jaxgear size --write`` writes of it; the candidates whose meshes share one static layout of
their cells are solved by one compiled ``vmap`` program (:func:`te_curves`)."""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._baseplane import MeshModel
from .._contact_geometry import BeyondPath, TheoreticalPath
from .._geometry import GearPair, Member
from .._modifications import Modifications
from .._quasi_static import at_torques
from .._spectrum import te_spectrum
from .._stiffness import WeberFoundation
from .._stiffness_models import Weber, stiffness_table
from .._util import check_instance, padded_batch
from ._size import SizingTable
from ._spec import SizingSpec

__all__ = ["CANDIDATE_MESH", "TE_COLUMNS", "TE_VARIABLES", "TeSettings", "candidate_mesh",
           "candidate_modifications", "candidate_pair", "te_curves", "te_stage"]

#: the mesh model of a candidate, as its case file's ``[mesh]`` names it (``jaxgear size
#: --write``): Weber's tooth stiffness with Weber's foundation, slices per contact line, mesh
#: positions per base pitch, contact beyond the theoretical path too (the tip corners:
#: :class:`jaxgear.BeyondPath`); exact contact, drive flanks only
CANDIDATE_MESH = {"stiffness": "weber", "slices": 20, "positions_per_pitch": 16,
                  "extended_contact": True}


#: the design variables of the modified flanks (both members alike), the optimiser's names
TE_VARIABLES = ("tip_relief.depth", "tip_relief.extent", "crowning.depth")

#: the columns the stage adds to the table (NaN where a candidate was not evaluated; beside
#: them ``stage``: "te", "te_failed" or "rating", :func:`te_stage`): plain and modified flanks, the rated torque's TE
#: peak-to-peak and its first two mesh-order amplitudes, the largest peak-to-peak over the
#: torque range, the modification's amounts (both members), the optimiser's iterations
TE_COLUMNS = (
    "te_ppk_m", "te_ppk_max_m", "te_h1_m", "te_h2_m",
    "te_ppk_modified_m", "te_ppk_max_modified_m", "te_h1_modified_m", "te_h2_modified_m",
    "tip_relief_depth_m", "tip_relief_extent", "crowning_depth_m", "te_iterations",
)


@dataclasses.dataclass(frozen=True)
class TeSettings:
    """What the transmission-error stage evaluates.

    Attributes:
        candidates: how many of the feasible candidates, the best ranked first
            (:meth:`SizingTable.ranked`), >= 0 (0: no stage).
        torque_fractions: the torques of the range as fractions of the rated pinion torque,
            increasing, each in (0, 1], the last 1 (the rated torque, where the modifications
            are optimised).
        max_iterations: the optimiser's cap on accepted iterations, >= 1.

    Raises:
        ValueError: a value out of range (one line naming it).
    """

    candidates: int = 3
    torque_fractions: tuple[float, ...] = (0.25, 0.5, 0.75, 1.0)
    max_iterations: int = 50

    def __post_init__(self):
        w = "TeSettings"
        if isinstance(self.candidates, bool) or not isinstance(self.candidates, int) \
                or self.candidates < 0:
            raise ValueError(f"{w}: candidates = {self.candidates!r} is out of range: allowed "
                             "an integer >= 0")
        f = np.asarray(self.torque_fractions, dtype=float)
        if f.ndim != 1 or f.size < 1 or not np.all(np.isfinite(f)) or np.any(f <= 0) \
                or np.any(np.diff(f) <= 0) or f[-1] != 1.0:
            raise ValueError(f"{w}: torque_fractions = {self.torque_fractions!r} is out of "
                             "range: allowed increasing fractions in (0, 1] ending at 1")
        if isinstance(self.max_iterations, bool) or not isinstance(self.max_iterations, int) \
                or self.max_iterations < 1:
            raise ValueError(f"{w}: max_iterations = {self.max_iterations!r} is out of range: "
                             "allowed an integer >= 1")


def candidate_pair(spec: SizingSpec, row: dict) -> GearPair:
    """The :class:`jaxgear.GearPair` of one candidate: ``row`` its table columns (one value
    each: ``normal_module_m``, ``z1``, ``z2``, ``x1``, ``x2``, ``face_width_m``,
    ``helix_angle_rad``), ``spec``'s pressure angle and basic rack; both gears of the candidate's face width, no allowances, at the
    zero-backlash centre distance. The numbers a candidate's case file writes
    (:func:`jaxgear.io.candidate_case_text` reads them here).

    Raises:
        ValueError: an invalid geometry (the pair's own checks, a candidate failing one of
            :data:`jaxgear.sizing.GEOMETRIC`).
    """
    members = [Member(int(row[z]), float(row[x]), float(spec.addendum_coeff),
                      float(spec.dedendum_coeff), float(row["face_width_m"]),
                      float(spec.fillet_radius_coeff))
               for z, x in (("z1", "x1"), ("z2", "x2"))]
    return GearPair(*members, normal_module=float(row["normal_module_m"]),
                    normal_pressure_angle=float(spec.normal_pressure_angle),
                    helix_angle=float(row.get("helix_angle_rad", spec.helix_angle)))


def candidate_mesh(spec: SizingSpec, pair: GearPair) -> MeshModel:
    """The rigid mesh model of a candidate's ``pair`` (:data:`CANDIDATE_MESH`): Weber's
    stiffness table at the spec's modulus and Poisson ratio and at the rated torque's nominal
    line load F_bt/(ε_α b), cells beyond the theoretical path (:data:`CANDIDATE_MESH`), as
    ``jaxgear run`` builds it from the candidate's case file."""
    t = float(spec.operating.torque)
    material = spec.settings.material
    s, k = stiffness_table(
        pair, Weber(WeberFoundation()), youngs_modulus=float(material.youngs_modulus),
        poisson_ratio=float(material.poisson_ratio),
        line_load=t / pair.base_radii[0] / (pair.transverse_contact_ratio * pair.face_width),
        specific_load=t / pair.pitch_radii[0] / pair.face_width)
    geometry = BeyondPath() if CANDIDATE_MESH["extended_contact"] else TheoreticalPath()
    return MeshModel.from_pair(pair, s, k, CANDIDATE_MESH["slices"], contact_geometry=geometry)


def candidate_modifications(row: dict) -> Modifications:
    """The modified flanks of a candidate's row (``tip_relief_depth_m``, ``tip_relief_extent``,
    ``crowning_depth_m``; linear relief, sharp relief start), both members alike."""
    d, g, c = (float(row[k]) for k in ("tip_relief_depth_m", "tip_relief_extent",
                                        "crowning_depth_m"))
    mods = Modifications()
    member = dataclasses.replace(mods.pinion, tip_relief_depth=d, tip_relief_extent=g,
                                 crowning_depth=c)
    return dataclasses.replace(mods, pinion=member, gear=member)


def _stack(trees):
    return jax.tree.map(lambda *xs: jnp.stack(xs), *trees)


def te_curves(meshes, modifications, torques, *, positions_per_pitch: int | None = None,
              batched: bool = True) -> np.ndarray:
    """The quasi-static TE (m) of each mesh with its modifications at each torque over one mesh
    period (:func:`jaxgear.quasi_static` at rest, exact contact): shape (n, T, P); NaN for a
    mesh whose contact solve failed at some position and torque (:class:`jaxgear.ContactResult`
    not converged: no contact, the cells beyond the path overrun, ...).

    The meshes of one static layout (the cell arrays' shapes, ``MeshModel``'s static fields)
    go through one compiled ``jax.vmap`` program, a group padded with copies of its last mesh
    to a power of two up to 8, then to a multiple of 8 (``jaxgear.padded_batch``: one
    program per layout and padded size); ``batched=False`` solves them one at a time (the program of one
    mesh; the benchmark's loop).

    Args:
        meshes: :class:`jaxgear.MeshModel` s, (n,). modifications: one
            :class:`jaxgear.Modifications` per mesh (None: plain flanks). torques: pinion
            torques (N·m), (T,), > 0, the same for every mesh. positions_per_pitch: P
            (default :data:`CANDIDATE_MESH`'s).

    Raises:
        ValueError: torques not > 0 (:func:`jaxgear.quasi_static`'s one-line refusals).
    """
    ppp = CANDIDATE_MESH["positions_per_pitch"] if positions_per_pitch is None \
        else int(positions_per_pitch)
    n = len(meshes)
    mods = [Modifications() if m is None else m for m in
            (modifications if modifications is not None else [None] * n)]
    torques = np.asarray(torques, dtype=float)
    read = lambda r: r.meshes[0].transmission_error
    out = np.zeros((n, torques.size, ppp))
    if not batched:
        for i in range(n):
            te, codes = at_torques(meshes[i], mods[i], torques, read, positions_per_pitch=ppp)
            out[i] = np.where(np.any(np.asarray(codes) != 0), np.nan, np.asarray(te))
        return out
    groups: dict = {}
    for i, mesh in enumerate(meshes):
        leaves, tree = jax.tree.flatten((mesh, mods[i]))
        groups.setdefault((tree, tuple(np.shape(v) for v in leaves)), []).append(i)
    for idx in groups.values():
        size = padded_batch(len(idx))
        padded = idx + [idx[-1]] * (size - len(idx))
        te, codes = _batched(_stack([meshes[i] for i in padded]),
                             _stack([mods[i] for i in padded]), torques, ppp)
        failed = np.any(np.asarray(codes)[: len(idx)] != 0, axis=(1, 2))
        out[idx] = np.where(failed[:, None, None], np.nan, np.asarray(te)[: len(idx)])
    return out


def _batched(meshes, mods, torques, ppp):
    read = lambda r: r.meshes[0].transmission_error
    return jax.vmap(lambda m, d: at_torques(m, d, torques, read, positions_per_pitch=ppp))(
        meshes, mods)


#: the coarse grid of the optimiser's start: tip relief depths E* = E/δ_m and extents Γ (the
#: crowning starts 5 % inside its bounds, as ``jaxgear optimise`` starts an unmodified case)
START_DEPTHS = (0.5, 1.0, 1.5, 2.0, 2.5)
START_EXTENTS = (0.1, 0.25, 0.4, 0.55, 0.7, 0.85)


@eqx.filter_jit
def _grid_values(problem, xs):
    return jax.vmap(problem.value)(xs)


def _start(problem) -> np.ndarray:
    """The optimiser's start: the point of the coarse (E*, Γ) grid (:data:`START_DEPTHS`,
    :data:`START_EXTENTS`) where the problem's smooth objective is least. The TE
    peak-to-peak has several local minima in a relief's depth and extent (a start at the
    plain flanks ends in the nearest, a short relief of little effect)."""
    lo, hi = np.asarray(problem.lower), np.asarray(problem.upper)
    base = lo + 0.05 * (hi - lo)
    depth, extent = (problem.names.index(n) for n in TE_VARIABLES[:2])
    xs = np.repeat(base[None], len(START_DEPTHS) * len(START_EXTENTS), axis=0)
    xs[:, depth] = np.repeat(START_DEPTHS, len(START_EXTENTS))
    xs[:, extent] = np.tile(START_EXTENTS, len(START_DEPTHS))
    xs = np.clip(xs, lo + 0.05 * (hi - lo), hi - 0.05 * (hi - lo))
    values = np.asarray(_grid_values(problem, jnp.asarray(xs)))
    return xs[int(np.nanargmin(values))]


def _te_numbers(te, teeth, ppp):
    """(ppk at the rated torque, largest ppk over the range, mesh orders 1 and 2 at the rated
    torque) of a candidate's curves ``te`` (T, P)."""
    ppk = np.ptp(te, axis=1)
    spectrum = te_spectrum(te[-1], ppp, teeth)
    z1 = teeth[0]
    return ppk[-1], ppk.max(), spectrum.at(z1), spectrum.at(2 * z1)


def _optimised(problems: dict, max_iterations: int, batched: bool,
               done: Callable[[int], None]) -> dict:
    """Each problem's :func:`optimise.minimise` result from its :func:`_start` (index →
    result; a problem whose solve failed on the way is absent or has a non-finite value):
    ``batched``, the problems of one mesh layout solved together
    (:func:`optimise.minimise_batch`; a batch whose solve fails a runtime check is solved one
    problem at a time, to find which); else one at a time. ``done(k)`` after each k solved."""
    import optimise

    keys = list(problems)
    out = {}
    with warnings.catch_warnings():  # the cap: the iterations are a column
        warnings.simplefilter("ignore", UserWarning)
        if batched and keys:
            try:
                found = optimise.minimise_batch([problems[j] for j in keys],
                                                [_start(problems[j]) for j in keys],
                                                max_iterations=max_iterations)
                done(len(keys))
                return dict(zip(keys, found, strict=True))
            except eqx.EquinoxRuntimeError:
                pass
        for j in keys:
            try:
                out[j] = optimise.minimise(problems[j], _start(problems[j]),
                                           max_iterations=max_iterations, progress=False)
            except (FloatingPointError, eqx.EquinoxRuntimeError):
                pass  # a solve that failed on the way: the stage names the candidate
            done(1)
    return out


def te_stage(spec: SizingSpec, table: SizingTable, settings: TeSettings | None = None, *,
             progress: Callable[[int, int], None] | None = None,
             batched: bool = False) -> SizingTable:
    """The transmission-error stage: the first ``settings.candidates`` feasible candidates of
    ``table`` (:meth:`SizingTable.ranked`), each its pair's rigid mesh (:func:`candidate_mesh`)
    at the torques ``settings.torque_fractions`` × the rated pinion torque; the plain flanks
    (batched, :func:`te_curves`), then the tip relief (depth, extent) and crowning (depth),
    both members alike, that :func:`optimise.minimise` finds minimising
    :class:`optimise.TePeakToPeak` at the rated torque (smooth contact; from the best point of
    a coarse grid of relief depths and extents, :func:`_start`), evaluated as written (exact
    contact, sharp relief starts) over the range (batched). ``batched``: the candidates whose
    meshes share one layout optimised together (:func:`optimise.minimise_batch`, one compiled
    ``vmap`` of the solve; each candidate's result the one-at-a-time solve's to the optimiser's
    rounding); else (the default) one at a time (:func:`optimise.minimise`), which is the
    faster on a CPU: each solve is already vectorised over cells, positions and torques, and
    a batch steps in lock-step until its slowest member stops (measured: docs/sizing.md, "The
    transmission-error stage").

    Returns:
        A :class:`SizingTable` of ``table``'s columns and :data:`TE_COLUMNS` (NaN where not
        evaluated) and ``stage``: "te" where evaluated, "te_failed" where a contact solve or
        the optimiser failed on the way (no contact, the tip corners' cells overrun, a
        non-finite objective; the columns of what failed NaN), else "rating"; ``failed``
        unchanged.

    Raises:
        ValueError: a settings object that is not a :class:`TeSettings`.
    """
    import optimise  # the optimiser package (a top-level sibling of jaxgear)

    settings = TeSettings() if settings is None else settings
    check_instance("settings", settings, TeSettings, "a jaxgear.sizing.TeSettings", "te_stage")
    chosen = table.ranked()[: settings.candidates]
    n = len(table)
    columns = {k: np.full(n, math.nan) for k in TE_COLUMNS}
    stage = np.full(n, "rating", dtype=object)
    rated = float(spec.operating.torque)
    torques = rated * np.asarray(settings.torque_fractions, dtype=float)
    ppp = CANDIDATE_MESH["positions_per_pitch"]
    rows = [{k: v[i] for k, v in table.columns.items()} for i in chosen]
    pairs = [candidate_pair(spec, r) for r in rows]
    meshes = [candidate_mesh(spec, p) for p in pairs]
    plain = te_curves(meshes, None, torques)
    nan = {"tip_relief_depth_m": math.nan, "tip_relief_extent": math.nan,
           "crowning_depth_m": math.nan}
    problems = {}
    for j, mesh in enumerate(meshes):
        if np.all(np.isfinite(plain[j])):
            try:
                problems[j] = optimise.make_problem(mesh, None, rated, ",".join(TE_VARIABLES),
                                                    optimise.TePeakToPeak(),
                                                    positions_per_pitch=ppp)
            except (FloatingPointError, eqx.EquinoxRuntimeError):
                pass  # a solve that failed on the way: the stage names the candidate
    finished = len(meshes) - len(problems)  # those with no problem to solve

    def done(k):
        nonlocal finished
        finished += k
        if progress is not None:
            progress(finished, len(meshes))

    results = _optimised(problems, settings.max_iterations, batched, done)
    designs, iterations = [], []
    for j in range(len(meshes)):
        design, its = nan, math.nan
        res = results.get(j)
        if res is not None and np.isfinite(res.value):
            values = problems[j].to_physical(res.x)
            design = {"tip_relief_depth_m": values["tip_relief.depth"] * 1e-6,
                      "tip_relief_extent": values["tip_relief.extent"],
                      "crowning_depth_m": values["crowning.depth"] * 1e-6}
            its = res.iterations
        designs.append(design)
        iterations.append(its)
    ok = [j for j, d in enumerate(designs) if np.isfinite(d["tip_relief_depth_m"])]
    modified = np.full_like(plain, math.nan)
    if ok:
        modified[ok] = te_curves([meshes[j] for j in ok],
                                 [candidate_modifications(designs[j]) for j in ok], torques)
    for j, i in enumerate(chosen):
        teeth = (int(rows[j]["z1"]), int(rows[j]["z2"]))
        for suffix, curves in (("", plain[j]), ("_modified", modified[j])):
            if not np.all(np.isfinite(curves)):
                continue
            ppk, ppk_max, h1, h2 = _te_numbers(curves, teeth, ppp)
            columns[f"te_ppk{suffix}_m"][i] = ppk
            columns[f"te_ppk_max{suffix}_m"][i] = ppk_max
            columns[f"te_h1{suffix}_m"][i] = h1
            columns[f"te_h2{suffix}_m"][i] = h2
        for k, v in designs[j].items():
            columns[k][i] = v
        columns["te_iterations"][i] = iterations[j]
        stage[i] = "te" if np.all(np.isfinite(modified[j])) else "te_failed"
    return dataclasses.replace(table, columns=table.columns | {"stage": stage.astype(str)}
                               | columns)
