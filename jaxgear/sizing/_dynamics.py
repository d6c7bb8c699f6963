"""The dynamics stage of a sizing: for the candidates of the first Pareto fronts, the dynamic
factor K_v against speed and the gear whine of each candidate's lumped torsional model
(:func:`dynamics_stage`).

A candidate's model is the one ``jaxgear sweep`` builds from its case file (``jaxgear size
--write``; a case without ``[scene]``): the pair (:func:`candidate_pair`) and its rigid mesh
(:func:`candidate_mesh`) between two rotations, each gear a solid disc of its tip radius, face
width and the spec's density, composite modal damping (7 % in the mesh, 1 % elsewhere), at the
spec's pinion torque, with the transmission-error stage's optimised tip relief and crowning
where that stage evaluated the candidate (its ``candidate_K_modified.toml``), else the plain
flanks (:func:`candidate_dynamic_model`). Each speed of the range is run by
:func:`jaxgear.dynamics.settled_sweep` until it settles, the sweep ``jaxgear sweep`` runs on
that case (independent speeds, periods automatic); the whine is the harmonic balance of the
same model linearised about its quasi-static solution (:func:`jaxgear.dynamics.whine_response`,
:class:`jaxgear.dynamics.HarmonicBalance`, docs/whine.md) at the same speeds."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np

from .._contact import ExactContact
from .._modifications import Modifications
from .._util import check_instance
from ..dynamics import (
    CompositeDamping,
    HarmonicBalance,
    dynamic_model,
    settled_sweep,
    whine_response,
)
from ..scenes import TorsionalDynamics, disc_inertia
from ._objectives import STAGE_OBJECTIVES
from ._pareto import DEFAULT_OBJECTIVES, pareto_front
from ._size import SizingTable
from ._spec import SizingSpec
from ._te import candidate_mesh, candidate_modifications, candidate_pair

__all__ = ["DYNAMICS_COLUMNS", "WHINE_ORDERS", "DynamicsCurves", "DynamicsSettings",
           "candidate_dynamic_model", "dynamics_selection", "dynamics_speeds",
           "dynamics_stage"]

#: the columns the stage adds (NaN where a candidate was not run; beside them
#: ``dynamics_stage``, :func:`dynamics_stage`): the largest dynamic factor K_v over the speed
#: range, K_v at the spec's speed, the mesh resonance speed (rad/s: where the first mesh
#: order's dynamic mesh force is largest over the range), the whine level (the largest over the
#: range of the dynamic mesh force's RMS over the mesh orders 1 to :data:`WHINE_ORDERS`, N) and
#: the speeds that reached their cap unsettled
DYNAMICS_COLUMNS = ("dynamic_factor_max", "dynamic_factor_at_speed", "resonance_speed_rad_s",
                    "whine_force_N", "dynamics_unsettled")

#: the mesh orders the whine level sums (1 to this)
WHINE_ORDERS = 3

#: the time averages of a candidate's model (its modes, damping, mean mesh stiffness): positions
#: per mesh period, as ``jaxgear sweep`` builds a case's lumped model
AVERAGE_POSITIONS = 64

#: the default speed range (:func:`dynamics_speeds`): from this fraction of the lower of the
#: spec's speed and the lowest mesh resonance speed ...
RANGE_BELOW = 0.5
#: ... to this multiple of the higher of the spec's speed and the highest one
RANGE_ABOVE = 1.5


@dataclasses.dataclass(frozen=True)
class DynamicsSettings:
    """What the dynamics stage runs.

    Attributes:
        candidates: how many candidates, from the first Pareto fronts
            (:func:`dynamics_selection`), >= 0 (0: no stage).
        speed_range: (lo, hi), the pinion speeds (rad/s) swept, 0 < lo < hi; None: the
            default (:func:`dynamics_speeds`: through every candidate's mesh resonance).
        speeds: the speeds equally spaced over the range, >= 2 (the spec's speed is added
            where it is not one of them).

    Raises:
        ValueError: a value out of range (one line naming it).
    """

    candidates: int = 3
    speed_range: tuple[float, float] | None = None
    speeds: int = 40

    def __post_init__(self):
        w = "DynamicsSettings"
        if isinstance(self.candidates, bool) or not isinstance(self.candidates, int) \
                or self.candidates < 0:
            raise ValueError(f"{w}: candidates = {self.candidates!r} is out of range: allowed "
                             "an integer >= 0")
        r = self.speed_range
        if r is not None and not (len(r) == 2 and all(math.isfinite(float(v)) for v in r)
                                  and 0 < float(r[0]) < float(r[1])):
            raise ValueError(f"{w}: speed_range = {r!r} is out of range: allowed (lo, hi) with "
                             "0 < lo < hi (rad/s), or None")
        if isinstance(self.speeds, bool) or not isinstance(self.speeds, int) or self.speeds < 2:
            raise ValueError(f"{w}: speeds = {self.speeds!r} is out of range: allowed an "
                             "integer >= 2")


@dataclasses.dataclass(frozen=True)
class DynamicsCurves:
    """The stage's curves, one row per candidate run.

    Attributes:
        rows: the candidates' rows of the table, (k,).
        speeds: the pinion speeds (rad/s), ascending, (S,), the spec's speed among them (none
            where no candidate ran).
        dynamic_factor: K_v, the largest mesh force over the kept periods over the static
            one, (k, S); NaN where a speed failed.
        whine_force: the dynamic mesh force's RMS over the mesh orders 1 to
            :data:`WHINE_ORDERS` (N), (k, S).
        first_order: the amplitude of the dynamic mesh force's first mesh order (N), (k, S).
        settled: whether each speed settled within the settled sweep's tolerance, (k, S).
        flanks: "plain" or "modified" (the transmission-error stage's), (k,).
    """

    rows: np.ndarray
    speeds: np.ndarray
    dynamic_factor: np.ndarray
    whine_force: np.ndarray
    first_order: np.ndarray
    settled: np.ndarray
    flanks: tuple[str, ...]


def candidate_dynamic_model(spec: SizingSpec, row: dict, modified: bool | None = None):
    """The lumped torsional :class:`jaxgear.dynamics.DynamicModel` of one candidate (the
    module docstring): the model ``jaxgear sweep`` builds from its written case file.

    Args:
        spec: the sizing spec (its torque, material, rack).
        row: the candidate's columns (one value each; :func:`candidate_pair`'s).
        modified: the transmission-error stage's tip relief and crowning
            (:func:`candidate_modifications`) or the plain flanks; None: modified where the
            row's ``stage`` is ``"te"``.

    Returns:
        The :class:`jaxgear.dynamics.DynamicModel` (SI; coordinates the pinion's and the
        wheel's rotations, rad, each positive in its direction of motion).

    Raises:
        ValueError: an invalid geometry (:func:`candidate_pair`'s).
    """
    if modified is None:
        modified = row.get("stage") == "te"
    pair = candidate_pair(spec, row)
    density = float(spec.settings.material.density)
    i1, i2 = (disc_inertia(density, float(r), float(m.face_width))
              for r, m in zip(pair.tip_radii, (pair.pinion, pair.gear), strict=True))
    scene = TorsionalDynamics(candidate_mesh(spec, pair), i1, i2)
    mods = candidate_modifications(row) if modified else Modifications()
    return dynamic_model(scene, mods, float(spec.operating.torque), CompositeDamping(),
                         positions_per_pitch=AVERAGE_POSITIONS)


def dynamics_selection(spec: SizingSpec, table: SizingTable, n: int,
                       stage: str = "dynamics") -> np.ndarray:
    """The rows a stage runs (this one's; ``stage``, a key of
    :data:`jaxgear.sizing.STAGE_OBJECTIVES`: ``"sound"`` the sound stage's, the same rule):
    the first ``n`` of the feasible candidates front by front, the
    fronts over the spec's objectives that the stage does not add (completed to two by
    :data:`jaxgear.sizing.DEFAULT_OBJECTIVES`, the mass and the least margin); of a front
    larger than the places left, those evenly spaced along its first objective (both ends,
    one place: the best in it), on the first front after its chosen design (the knee or the
    spec's choice), which comes first."""
    ours = set(STAGE_OBJECTIVES[stage])
    objectives = [o for o in spec.objectives if o[0] not in ours]
    for o in DEFAULT_OBJECTIVES:
        if len(objectives) < 2 and o[0] not in (name for name, _ in objectives):
            objectives.append(o)
    chosen = spec.chosen if spec.chosen in [name for name, _ in objectives] else "knee"
    front = pareto_front(table, tuple(objectives), chosen)
    name, sense = objectives[0]
    first = np.asarray(table.columns[name], dtype=float) * (1.0 if sense == "min" else -1.0)
    out: list[int] = []
    for r in range(1, int(front.rank.max(initial=0)) + 1):
        left = n - len(out)
        if left <= 0:
            break
        rows = np.flatnonzero(front.rank == r)
        if rows.size <= left:
            out += rows.tolist()
            continue
        if r == 1:  # the chosen design first
            out.append(int(front.chosen))
            rows, left = rows[rows != front.chosen], left - 1
        if left:
            rows = rows[np.argsort(first[rows], kind="stable")]
            out += rows[np.round(np.linspace(0, rows.size - 1, left)).astype(int)].tolist()
    return np.asarray(out, dtype=int)


def _resonance_speed(model) -> float:
    """The pinion speed (rad/s) whose mesh frequency is the natural frequency of the mode with
    the largest share of its strain energy in the mesh (the model's time-averaged modes)."""
    modes = model.averaged_modes()
    i = int(np.argmax(np.asarray(modes.mesh_energy)))
    return float(modes.omega[i]) * float(model.mesh_period_angle()) / (2 * math.pi)


def dynamics_speeds(spec: SizingSpec, settings: DynamicsSettings, models) -> np.ndarray:
    """The pinion speeds (rad/s) of the stage, ascending: ``settings.speeds`` equally spaced
    over ``settings.speed_range`` or, without one, from :data:`RANGE_BELOW` times the lower of
    the spec's speed and the lowest mesh resonance speed of the ``models`` (the speed whose
    mesh frequency is the natural frequency of the mode with the largest mesh energy share)
    to :data:`RANGE_ABOVE` times the higher of the spec's speed and the highest one; the
    spec's speed added where it is not one of them (to 1e-12)."""
    speed = float(spec.operating.speed)
    if settings.speed_range is not None:
        lo, hi = (float(v) for v in settings.speed_range)
    else:
        res = [_resonance_speed(m) for m in models] or [speed]
        lo, hi = RANGE_BELOW * min(speed, *res), RANGE_ABOVE * max(speed, *res)
    grid = np.linspace(lo, hi, settings.speeds)
    if not np.any(np.abs(grid - speed) <= 1e-12 * speed):
        grid = np.sort(np.append(grid, speed))
    return grid


def _whine_force(model, speeds) -> tuple[np.ndarray, np.ndarray]:
    """(the dynamic mesh force's RMS over the mesh orders 1 to :data:`WHINE_ORDERS`, sqrt(Σ_h
    |F_h|²/2), the amplitude |F_1| of its first order) (N) at each speed, of the one-sided
    amplitudes of the harmonic balance."""
    w = whine_response(model, speeds, HarmonicBalance())
    f = np.abs(np.asarray(w.mesh_force)[:, 1 : WHINE_ORDERS + 1, 0])
    return np.sqrt(0.5 * np.sum(f**2, axis=1)), f[:, 0]


def dynamics_stage(spec: SizingSpec, table: SizingTable,
                   settings: DynamicsSettings | None = None, *,
                   progress: Callable[[int, int], None] | None = None
                   ) -> tuple[SizingTable, DynamicsCurves]:
    """The dynamics stage (the module docstring): the candidates of
    :func:`dynamics_selection`, each its lumped torsional model
    (:func:`candidate_dynamic_model`) swept over :func:`dynamics_speeds` by
    :func:`jaxgear.dynamics.settled_sweep` (Newmark, automatic steps, exact contact, 4 kept
    periods) and its whine by :func:`jaxgear.dynamics.whine_response` at the same speeds (the
    mesh resonance speed: where its first mesh order is largest; the speed of the largest K_v
    may be a higher order's resonance, z1 h Ω = ω_n, h > 1, where the flanks' TE is rich in
    that order).
    The candidates' models share the compiled programs where their mesh layouts match.

    Args:
        spec, table: the sizing spec and its table (after the transmission-error stage, if
            any: a row of ``stage`` "te" runs with that stage's flanks).
        settings: :class:`DynamicsSettings` (default: its defaults).
        progress: ``progress(done, total)`` after each speed of each candidate.

    Returns:
        (the table with :data:`DYNAMICS_COLUMNS`, NaN where not run, and ``dynamics_stage``:
        "plain" or "modified" (the flanks it ran with), "failed" where a speed failed (a
        contact solve, a diverged step: its columns NaN), else "none"; the
        :class:`DynamicsCurves` of the candidates run).

    Raises:
        ValueError: a settings object that is not a :class:`DynamicsSettings`.
    """
    settings = DynamicsSettings() if settings is None else settings
    check_instance("settings", settings, DynamicsSettings, "a jaxgear.sizing.DynamicsSettings",
                   "dynamics_stage")
    n = len(table)
    columns = {k: np.full(n, math.nan) for k in DYNAMICS_COLUMNS}
    stage = np.full(n, "none", dtype=object)
    chosen = dynamics_selection(spec, table, settings.candidates) if settings.candidates \
        else np.zeros(0, dtype=int)
    rows = [{k: v[i] for k, v in table.columns.items()} for i in chosen]
    flanks = tuple("modified" if r.get("stage") == "te" else "plain" for r in rows)
    models = [candidate_dynamic_model(spec, r, f == "modified") for r, f in zip(rows, flanks,
                                                                                 strict=True)]
    # no candidate run: no speeds
    speeds = dynamics_speeds(spec, settings, models) if models else np.zeros(0)
    k, s = len(models), speeds.size
    kv, whine, first = (np.full((k, s), math.nan) for _ in range(3))
    settled = np.zeros((k, s), dtype=bool)
    at = int(np.argmin(np.abs(speeds - float(spec.operating.speed)))) if s else 0
    for j, (i, model) in enumerate(zip(chosen, models, strict=True)):
        def step(done, base=j * s):
            if progress is not None:
                progress(base + done, k * s)

        run = settled_sweep(model, speeds, integrator=None, contact=ExactContact(),
                            progress=step)
        r = run.sweep.results
        ok = np.asarray(r.result) == 0
        kv[j] = np.where(ok, np.asarray(r.dynamic_factor, dtype=float), math.nan)
        settled[j] = np.asarray(run.settled) & ok
        whine[j], first[j] = _whine_force(model, speeds)
        if not np.all(ok):
            stage[i] = "failed"
            continue
        stage[i] = flanks[j]
        top = int(np.argmax(kv[j]))
        columns["dynamic_factor_max"][i] = kv[j, top]
        columns["dynamic_factor_at_speed"][i] = kv[j, at]
        columns["resonance_speed_rad_s"][i] = speeds[int(np.argmax(first[j]))]
        columns["whine_force_N"][i] = np.max(whine[j])
        columns["dynamics_unsettled"][i] = float(np.sum(~settled[j]))
    curves = DynamicsCurves(chosen, speeds, kv, whine, first, settled, flanks)
    table = dataclasses.replace(table, columns=table.columns | columns
                                | {"dynamics_stage": stage.astype(str)})
    return table, curves
