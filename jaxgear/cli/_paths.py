"""Output paths of the commands: checked before anything is computed, stale files cleared.

Imports no JAX, so the CLI can check ``--out``/``--json`` before it loads the model; the folder
and file checks are fem_prep's (:mod:`fem_prep.schema`), shared with ``fem-prep``.
"""

from __future__ import annotations

import contextlib
import fnmatch
import os

from fem_prep import schema as sc
from fem_prep.schema import check_output_dir, check_output_file

__all__ = ["OUTPUT_FILES", "TRAIN_FILES", "check_output_dir", "check_output_file", "clear_outputs"]

# The files each command writes into its folder (subfolder/name for the nested ones; a name may
# hold a * wildcard, as fnmatch reads it). Only these names are ever deleted by :func:`clear_outputs`, and only when the folder's manifest says that
# jaxgear wrote them: a user's own files in the folder stay.
OUTPUT_FILES: dict[str, tuple[str, ...]] = {
    "run": (
        "summary.json",
        "te.csv",
        "mesh_stiffness.csv",
        "transmission_error.png",
        "mesh_stiffness.png",
        "load_map.png",
        "pressure_map.png",
        "harris_map.png",
    ),
    # jaxgear run on a case whose scene has condensed bodies (subfolder scene/)
    "scene": (
        "load_map.png",
        "load_map_speed.png",
        "pressure_map.png",
        "pressure_map_speed.png",
        "load_map_speed_minus_rest.png",
        "pressure_map_speed_minus_rest.png",
        "body_pinion.vtu",
        "body_gear.vtu",
        "contact.vtu",
    ),
    "sweep": (
        "sweep.json",
        "sweep.csv",
        "dynamic_factor.png",
        "campbell.png",
        "contact_pressure.png",
        "pressure_map_dynamic.png",
        # a train's, one per mesh (named after its gears)
        "pressure_map_dynamic_*.png",
    ),
    "optimise": ("optimum.json", "convergence.png", "harris.png", "path.png"),
    # jaxgear run on a case with [deviations] (subfolder deviations/)
    "deviations": ("te_span.csv", "spectrum.csv", "spectrum.json", "te_spectrum.png"),
    "master-curve": ("master_curve.json", "master_curve.png"),
    "bench quasi-static": ("bench_quasi_static.json", "speed_accuracy_quasi_static.png"),
    "bench optimise": ("bench_optimise.json",),
    "bench dynamics": ("bench_dynamics.json", "stability_map.json", "stability_map.png"),
    "bench hybrid": ("bench_hybrid.json", "bench_hybrid.png"),
    "bench hybrid-sweep": ("bench_hybrid_sweep.json", "bench_hybrid_sweep.png"),
    "bench modal-basis": ("modal_basis.json", "modal_basis.png"),
    "bench stiffness": ("bench_stiffness.json", "speed_accuracy_stiffness.png"),
    "bench trains": ("bench_trains.json", "bench_trains.png"),
    "bench robust": ("bench_robust.json",),
}
# what ``jaxgear run`` writes for a train case besides a pair's names: a load map and a pressure
# map per mesh (named after its gears) and the layout with its phasing
TRAIN_FILES = ("load_map_*.png", "pressure_map_*.png", "phasing.png")
OUTPUT_FILES["run"] += TRAIN_FILES
# ``jaxgear run`` also owns the sweep/, optimise/, scene/ and deviations/ subfolders of its folder
OUTPUT_FILES["run"] += tuple(
    f"{sub}/{n}" for sub in ("sweep", "optimise", "scene", "deviations") for n in OUTPUT_FILES[sub]
)


def clear_outputs(folder, command: str) -> list[str]:
    """Delete the files that an earlier run wrote into ``folder`` and start recording this run's.

    Only files that the folder's manifest (``.jaxgear-outputs``, written as the files are
    written: :func:`fem_prep.schema.record_outputs`) lists AND that bear one of ``command``'s
    output names are deleted, with their leftover temporary files: a user's own files in the
    folder stay, even those with an output name (a run overwrites those it writes itself).
    Returns the paths removed."""
    removed = []
    listed = set(sc.recorded_outputs(folder))
    for pattern in OUTPUT_FILES[command]:
        for name in sorted(n for n in listed if fnmatch.fnmatchcase(n, pattern)):
            p = os.path.join(folder, name)
            if os.path.isfile(p) or os.path.islink(p):
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(p)
                    removed.append(p)
        d, base = os.path.split(os.path.join(folder, pattern))
        if os.path.isdir(d):
            for other in os.listdir(d):
                if fnmatch.fnmatchcase(other, f".tmp-{base}-*.tmp"):
                    with contextlib.suppress(OSError):
                        os.unlink(os.path.join(d, other))
    with contextlib.suppress(FileNotFoundError):  # this run starts a new list
        os.unlink(os.path.join(folder, sc.OUTPUT_MANIFEST))
    sc.record_outputs(folder)
    return removed
