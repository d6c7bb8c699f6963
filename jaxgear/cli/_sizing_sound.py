"""The sound stage of ``jaxgear size`` (a spec with ``[sound]``, docs/sizing.md, "The sound
stage"): for the candidates of the first Pareto fronts (:func:`jaxgear.sizing.dynamics_selection`'s
rule, ``stage="sound"``), each candidate's housed case file (:func:`jaxgear.io.housed_case_text`:
the lumped 3D pair on the layout's shafts and bearings in a box housing round its tip circles,
with ``[whine]``) is written into the results store and run as ``jaxgear run`` runs it: the case
read by :func:`jaxgear.io.load_case` and its sound computed by :func:`jaxgear.io.case_sound` (its
whine, the housing meshed and condensed by fem_prep, cached, and its equivalent radiated power on
the housing's outer skin); with ``[sound] sound_power = true`` the case holds ``[acoustics]``
and its radiated sound power is computed as ``jaxgear run``'s ``[acoustics]`` computes it
(:meth:`jaxgear.io.CaseSound.with_sound_power`: the closed skin's normal velocity radiated by
:func:`jaxgear.io.surface_sound_power`, one BEM solve per grid frequency, cached). The columns
:data:`SOUND_COLUMNS` are that run's headline: the largest overall ERP over the speeds and its
speed, and the largest overall sound power L_W (not A-weighted: the ERP's weighting, so the two
compare) and its speed, so ``jaxgear run`` of the written case reports the same numbers. Each
finished candidate's result is kept in ``store/sound/`` (keyed by its case text and jaxgear's
version), which a rerun of the same spec into the same folder reads instead of running it
again."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
import time
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from .. import __version__, sizing
from ..io import (
    SchemaError,
    acoustics_of,
    atomic_open,
    case_sound,
    housed_case_text,
    load_case,
)

__all__ = ["SOUND_COLUMNS", "SoundCurves", "sound_stage"]

#: the columns the stage adds (NaN where a candidate was not run; beside them ``sound_stage``,
#: :func:`sound_stage`): the largest overall ERP over the speeds (dB re 1 pW), the speed where
#: it is largest (rad/s, the pinion's), the speeds with contact loss (where the whine's
#: linear result does not hold), and with ``[sound] sound_power = true`` the largest overall
#: radiated sound power L_W over the speeds (dB re 1 pW, not A-weighted; the orders in the
#: housing's band at every speed, as ``jaxgear run``'s acoustics/sound_power.json
#: overall_LW_dB) and its speed (rad/s)
SOUND_COLUMNS = ("erp_peak_dB", "erp_peak_speed_rad_s", "sound_contact_loss",
                 "sound_power_peak_dB", "sound_power_peak_speed_rad_s")


class SoundCurves(NamedTuple):
    """The stage's curves, one row per candidate run.

    Attributes:
        rows: the candidates' rows of the table, (k,).
        speeds: the pinion speeds (rad/s), (S,) ([sound]'s range; none where no candidate ran).
        overall_erp_db: the overall ERP over the orders in the housing's band (dB re 1 pW),
            (k, S); NaN where the candidate failed or no order lies in the band.
        contact_loss: whether each speed lost contact, (k, S).
        overall_sound_power_db: the overall radiated sound power L_W (dB re 1 pW), (k, S); NaN
            where not computed (``sound_power`` false, a failed candidate).
        flanks: "plain" or "modified" (the transmission-error stage's), (k,).
        seconds: each candidate's time (s; a result read back from the store: its first run's).
        failed: each candidate's one-line reason ("" where it ran).
    """

    rows: np.ndarray
    speeds: np.ndarray
    overall_erp_db: np.ndarray
    contact_loss: np.ndarray
    overall_sound_power_db: np.ndarray
    flanks: tuple[str, ...]
    seconds: np.ndarray
    failed: tuple[str, ...]


def _nullable(levels) -> list:
    """Levels (dB) as a JSON list, NaN (no power) as None."""
    return [None if math.isnan(v) else float(v) for v in np.asarray(levels, dtype=float)]


def _levels(values) -> np.ndarray:
    """A JSON list of levels (dB) back as an array, None (no power) as NaN: :func:`_nullable`'s
    inverse."""
    return np.asarray([math.nan if v is None else v for v in values], dtype=float)


def _peak(columns: dict, i: int, names: tuple[str, str], levels, speeds) -> None:
    """``jaxgear run``'s headline of a curve: its largest level (dB) and the speed where it is
    (rad/s) into ``columns[names[0]][i]``, ``columns[names[1]][i]``; nothing where every level
    is NaN."""
    if np.isfinite(levels).any():
        top = int(np.nanargmax(levels))
        columns[names[0]][i], columns[names[1]][i] = levels[top], speeds[top]


def _run_candidate(path: str) -> dict:
    """``jaxgear run``'s housed whine and ERP of the case file ``path``
    (:func:`jaxgear.io.case_sound`): the speeds, the overall ERP (NaN: no order in the band)
    and the contact loss per speed; with its ``[acoustics]`` the overall radiated sound power
    per speed, L_W and L_WA (``jaxgear run``'s computation), its own time recorded."""
    t0 = time.perf_counter()
    case = load_case(path)
    sound = case_sound(case, sound_power=False)
    table = acoustics_of(case)
    radiated = {}
    if table is not None:
        t1 = time.perf_counter()
        sound = sound.with_sound_power(table)
        p = sound.sound_power
        radiated = {"overall_sound_power_db": _nullable(p.overall),
                    "overall_sound_power_dba": _nullable(p.overall_a),
                    "radiation_frequencies": len(p.grid),
                    "skin_vertices": int(sound.radiation.surface.n_vertices),
                    "sound_power_seconds": time.perf_counter() - t1}
    w, erp, body = sound.whine, sound.erp, sound.housed.body
    return radiated | {"speeds": np.asarray(w.speed, dtype=float).tolist(),
                       "overall_erp_db": _nullable(erp.overall_db),
                       "contact_loss": np.asarray(w.contact_loss, dtype=bool).any(axis=1).tolist(),
                       "housing_modes": len(body.condensed.modes_hz),
                       "housing_dofs": int(body.mesh.n_dofs),
                       "seconds": time.perf_counter() - t0}


def sound_stage(spec, tables: dict, table: sizing.SizingTable, section, candidates: int,
                folder: str, *, restart: bool = False,
                progress: Callable[[int, int, str], None] | None = None
                ) -> tuple[sizing.SizingTable, SoundCurves]:
    """The sound stage (the module docstring).

    Args:
        spec, tables: the sizing spec and its checked tables (:func:`jaxgear.io.load_sizing_spec`).
        table: its table (after the transmission-error stage, if any: a row of ``stage`` "te"
            runs with that stage's flanks).
        section: the spec's ``[sound]`` (:func:`jaxgear.io.sizing_sound`). candidates: how many
            candidates of the first fronts (0: none).
        folder: the stage's results store (each candidate's housed case file
            ``candidate_K_housed.toml`` and result ``candidate_K.json``).
        restart: run every candidate again (the store's results ignored).
        progress: ``progress(done, total, what)`` before each candidate (``what``: its row and
            step) and after the last.

    Returns:
        (the table with :data:`SOUND_COLUMNS`, NaN where not run, and ``sound_stage``: "plain"
        or "modified" (the flanks it ran with), "failed" where its housed case did not run (a
        box that does not fit round the shafts, a housing over the machine's limits: the
        reason in :attr:`SoundCurves.failed`), else "none"; the :class:`SoundCurves`).
    """
    n = len(table)
    columns = {k: np.full(n, math.nan) for k in SOUND_COLUMNS}
    stage = np.full(n, "none", dtype=object)
    chosen = (sizing.dynamics_selection(spec, table, candidates, stage="sound") if candidates
              else np.zeros(0, dtype=int))
    k = len(chosen)
    results, flanks, failed = [], [], []
    for j, i in enumerate(chosen):
        i = int(i)
        row = {name: v[i] for name, v in table.columns.items()}
        flanks.append("modified" if row.get("stage") == "te" else "plain")
        if progress is not None:
            progress(j, k, f"row {i}: housing, whine" + (" and sound power (BEM)"
                                                         if section.sound_power else ""))
        text = housed_case_text(tables, spec, row, i, section)
        key = hashlib.sha256((__version__ + "\n" + text).encode()).hexdigest()
        os.makedirs(folder, exist_ok=True)
        case_path = os.path.join(folder, f"candidate_{i}_housed.toml")
        result_path = os.path.join(folder, f"candidate_{i}.json")
        got = None
        if not restart and os.path.isfile(result_path):
            with open(result_path) as f:
                stored = json.load(f)
            got = stored if stored.get("key") == key else None
        if got is None:
            with atomic_open(case_path, "w") as f:
                f.write(text)
            try:
                got = _run_candidate(case_path) | {"failed": ""}
            except (SchemaError, ValueError) as err:  # the case's one line
                got = {"failed": str(err).splitlines()[0]}
            with atomic_open(result_path, "w") as f:
                json.dump(got | {"key": key}, f)
        results.append(got)
        failed.append(got["failed"])
    if progress is not None:
        progress(k, k, "done")
    ran = [r for r in results if not r["failed"]]
    speeds = np.asarray(ran[0]["speeds"] if ran else [], dtype=float)
    level = np.full((k, speeds.size), math.nan)
    loss = np.zeros((k, speeds.size), dtype=bool)
    radiated = np.full((k, speeds.size), math.nan)
    for j, (i, r) in enumerate(zip(chosen, results, strict=True)):
        if r["failed"]:
            stage[i] = "failed"
            continue
        stage[i] = flanks[j]
        level[j] = _levels(r["overall_erp_db"])
        loss[j] = r["contact_loss"]
        columns["sound_contact_loss"][i] = float(loss[j].sum())
        _peak(columns, i, ("erp_peak_dB", "erp_peak_speed_rad_s"), level[j], speeds)
        if "overall_sound_power_db" in r:
            radiated[j] = _levels(r["overall_sound_power_db"])
        _peak(columns, i, ("sound_power_peak_dB", "sound_power_peak_speed_rad_s"), radiated[j],
              speeds)
    seconds = np.asarray([r.get("seconds", math.nan) for r in results], dtype=float)
    curves = SoundCurves(np.asarray(chosen, dtype=int), speeds, level, loss, radiated,
                         tuple(flanks), seconds, tuple(failed))
    table = dataclasses.replace(table, columns=table.columns | columns
                                | {"sound_stage": stage.astype(str)})
    return table, curves
