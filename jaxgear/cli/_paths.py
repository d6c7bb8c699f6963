"""Output paths of the commands: checked before anything is computed, stale files cleared.

Imports nothing heavy (no JAX), so the CLI can check ``--out``/``--json`` before it loads the
model.
"""

from __future__ import annotations

import contextlib
import os
import tempfile

__all__ = ["OUTPUT_FILES", "check_output_dir", "check_output_file", "clear_outputs"]

# The files each command writes into its folder (subfolder/name for the nested ones). Only these
# names are ever deleted by :func:`clear_outputs`, and only when the folder's manifest says that
# jaxgear wrote them: a user's own files in the folder stay.
OUTPUT_FILES: dict[str, tuple[str, ...]] = {
    "run": (
        "summary.json",
        "te.csv",
        "mesh_stiffness.csv",
        "transmission_error.png",
        "mesh_stiffness.png",
        "load_map.png",
        "harris_map.png",
    ),
    # jaxgear run on a case whose scene has condensed bodies (subfolder scene/)
    "scene": (
        "load_map.png",
        "load_map_speed.png",
        "body_pinion.vtu",
        "body_gear.vtu",
        "contact.vtu",
    ),
    "sweep": ("sweep.json", "dynamic_factor.png", "campbell.png"),
    "optimise": ("optimum.json", "convergence.png", "harris.png", "path.png"),
    "master-curve": ("master_curve.json", "master_curve.png"),
    "bench quasi-static": ("bench_quasi_static.json", "speed_accuracy_quasi_static.png"),
    "bench optimise": ("bench_optimise.json",),
    "bench dynamics": ("bench_dynamics.json", "stability_map.json", "stability_map.png"),
    "bench hybrid": ("bench_hybrid.json", "bench_hybrid.png"),
    "bench hybrid-sweep": ("bench_hybrid_sweep.json", "bench_hybrid_sweep.png"),
    "bench stiffness": ("bench_stiffness.json", "speed_accuracy_stiffness.png"),
}
# ``jaxgear run`` also owns the sweep/, optimise/ and scene/ subfolders of its folder
OUTPUT_FILES["run"] += tuple(
    f"{sub}/{n}" for sub in ("sweep", "optimise", "scene") for n in OUTPUT_FILES[sub]
)


def check_output_dir(path, option: str = "--out") -> str:
    """Check that ``path`` can be the output folder of a command, without creating anything
    (the writers create it when the first file is written: bad input leaves no folder behind).

    Raises:
        ValueError: one-line message ``{option} PATH: why`` when ``path`` is a file, lies under
            a file, or its nearest existing folder is not writable.
    """
    path = os.fspath(path)
    if os.path.exists(path) and not os.path.isdir(path):
        raise ValueError(f"{option} {path}: is a file, not a folder")
    existing = os.path.abspath(path)
    while not os.path.exists(existing):
        existing = os.path.dirname(existing)
    if not os.path.isdir(existing):
        raise ValueError(f"{option} {path}: {existing} is a file, not a folder")
    try:  # os.access alone misses read-only mounts (and root passes it everywhere)
        fd, probe = tempfile.mkstemp(prefix=".tmp-probe-", dir=existing)
        os.close(fd)
        os.unlink(probe)
    except OSError:
        where = "folder" if existing == os.path.abspath(path) else f"parent folder {existing}"
        raise ValueError(f"{option} {path}: {where} is not writable") from None
    return path


def check_output_file(path, option: str = "--json") -> str:
    """Check that a file can be written at ``path`` (a missing folder is created on writing).

    Raises:
        ValueError: ``path`` is a folder, or its folder cannot be created or written.
    """
    path = os.fspath(path)
    if path.endswith(os.sep) or os.path.isdir(path):
        raise ValueError(f"{option} {path}: is a folder, expected a file name")
    folder = os.path.dirname(os.path.abspath(path))
    try:
        check_output_dir(folder, option)
    except ValueError as err:
        raise ValueError(f"{option} {path}: {str(err).split(': ', 1)[1]}") from None
    if os.path.exists(path) and not os.access(path, os.W_OK):
        raise ValueError(f"{option} {path}: file is not writable")
    return path


def clear_outputs(folder, command: str) -> list[str]:
    """Delete the files that an earlier run wrote into ``folder`` and start recording this run's.

    Only files that the folder's manifest (``.jaxgear-outputs``, written as the files are
    written: :func:`fem_prep.schema.record_outputs`) lists AND that bear one of ``command``'s
    output names are deleted, with their leftover temporary files: a user's own files in the
    folder stay, even those with an output name (a run overwrites those it writes itself).
    Returns the paths removed."""
    from fem_prep import schema as sc  # fem_prep imports scipy: not at this module's import

    removed = []
    listed = set(sc.recorded_outputs(folder))
    for name in OUTPUT_FILES[command]:
        p = os.path.join(folder, name)
        if name in listed and (os.path.isfile(p) or os.path.islink(p)):
            with contextlib.suppress(FileNotFoundError):
                os.unlink(p)
                removed.append(p)
        d, base = os.path.split(p)
        if os.path.isdir(d):
            for other in os.listdir(d):
                if other.startswith(f".tmp-{base}-") and other.endswith(".tmp"):
                    with contextlib.suppress(OSError):
                        os.unlink(os.path.join(d, other))
    with contextlib.suppress(FileNotFoundError):  # this run starts a new list
        os.unlink(os.path.join(folder, sc.OUTPUT_MANIFEST))
    sc.record_outputs(folder)
    return removed
