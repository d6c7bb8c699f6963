"""The sizing's sound stage on the example spec: what a candidate costs. ``jaxgear size
examples/sizing/helical.toml --sound 2`` (the transmission-error and dynamics stages off: plain
flanks) runs the stage's two candidates of the first Pareto fronts, each its housed case
(:func:`jaxgear.io.housed_case_text`, the spec's ``[sound]``) read, its model built with the
housing meshed and condensed (fem_prep, into a fresh cache folder: the condensations timed, not
read back), the whine over the ``[sound]`` speeds and the ERP on the housing's skin; the
stage's own time per candidate (``sizing.json``'s ``sound_stage.candidate_seconds``) is
recorded. Then ``REPEATS`` times again with ``--force`` in the same process (the stage's store
ignored, the condensations read from fem_prep's cache, the programs compiled): the fastest of
each candidate kept, every run's recorded. Beside them, each housing's size and the case
reader's estimate of its condensation's CPU seconds (:meth:`jaxgear.io.Case.housing_size`).

Writes docs/bench/sizing_sound.json (or the file given) with the machine, dtype and JAX version
(benchmarks/_timing.py's ``environment()``) and the load average. From the repository root:
``python -m benchmarks.sizing_sound [FILE]``.
"""

from __future__ import annotations

import csv
import json
import os
import pathlib
import sys
import tempfile

import jax

jax.config.update("jax_enable_x64", True)

import jaxgear.io as jio
from benchmarks._timing import environment, write_record
from jaxgear.cli import main as jaxgear

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "bench" / "sizing_sound.json"
SPEC = ROOT / "examples" / "sizing" / "helical.toml"
CANDIDATES = 2
REPEATS = 3


def _size(out: str, *extra: str, spec=SPEC, candidates: int = CANDIDATES) -> dict:
    """``jaxgear size`` of the example (or ``spec``) with the sound stage's ``candidates``, the
    transmission-error and dynamics stages off; its sizing.json."""
    argv = ["size", str(spec), "--out", out, "--quiet", "--te", "0", "--dynamics", "0",
            "--sound", str(candidates), *extra]
    if jaxgear(argv) != 0:
        raise RuntimeError(f"jaxgear {' '.join(argv)} failed")
    with open(os.path.join(out, "sizing.json"), encoding="utf-8") as f:
        return json.load(f)


def main(path: pathlib.Path) -> None:
    machine = environment()
    load_start = list(os.getloadavg())
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["FEM_PREP_CACHE"] = os.path.join(tmp, "cache")  # fresh condensations
        out = os.path.join(tmp, "size")
        first = _size(out)["sound_stage"]
        runs = [_size(out, "--force")["sound_stage"]["candidate_seconds"]
                for _ in range(REPEATS)]
        rows = first["candidates"]
        with open(os.path.join(out, "sizing.csv"), encoding="utf-8") as f:
            table = {int(r["candidate"]): r for r in csv.DictReader(f)}
        candidates = []
        for j, k in enumerate(rows):
            case = jio.load_case(os.path.join(out, "store", "sound", f"candidate_{k}_housed.toml"))
            est = case.housing_size()
            r = table[k]
            candidates.append({
                "row": k, "normal_module_mm": round(float(r["normal_module_m"]) * 1e3, 4),
                "z1": int(r["z1"]), "z2": int(r["z2"]),
                "centre_distance_mm": round(float(r["centre_distance_m"]) * 1e3, 2),
                "face_width_mm": round(float(r["face_width_m"]) * 1e3, 2),
                "housing_dofs": int(est.dofs),
                "housing_modes_estimated": round(float(est.modes), 1),
                "condensation_cpu_s_estimated": round(float(est.seconds), 2),
                "cutoff_Hz": float(case.housing.cutoff),
                "erp_peak_dB": float(r["erp_peak_dB"]),
                "erp_peak_speed_rad_s": float(r["erp_peak_speed_rad_s"]),
                "first_s": first["candidate_seconds"][j],
                "again_s": min(run[j] for run in runs),
                "again_runs_s": [run[j] for run in runs],
            })
    record = {
        "what": "the sizing's sound stage on the example spec: each candidate's housed case "
                "read, its model built with the housing meshed and condensed, the whine over "
                "the [sound] speeds and the housing's ERP, timed by the stage itself; first "
                "(fresh condensations, compiling: the second candidate after the first) and "
                "again with --force (the condensations from fem_prep's cache, compiled)",
        "machine": machine,
        "spec": "examples/sizing/helical.toml with its [sound] (24 speeds 300-3000 1/min, 8 "
                "harmonics, cut-off 1.5 x the order-1 mesh frequency at 3000 1/min, 12 mm "
                "aluminium walls, 40 mm tet10 mesh), --te 0 --dynamics 0 --sound 2",
        "candidates": candidates,
        "stage_first_s": first["seconds"],
        "load_average_at_start": load_start,
        "load_average_at_end": list(os.getloadavg()),
    }
    write_record(path, record)


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)
