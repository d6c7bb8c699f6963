"""Output paths of the commands: checked before anything is computed, stale files cleared.

Imports no JAX, so the CLI can check ``--out``/``--json`` before it loads the model; the folder
and file checks are fem_prep's (:mod:`fem_prep.files`), shared with ``fem-prep``.

The rule of every command's outputs: a file option (``--json``, ``--write``) never names an
input of the run (the case file or a file it names: :attr:`jaxgear.io.Case.input_files`) nor,
without ``--force``, an existing file (:func:`fem_prep.files.check_output_file`); an output
folder (``--out``) never holds an input of the run where the command writes
(:func:`check_out_inputs`) nor, without ``--force``, a file jaxgear did not write under a name
it writes (:func:`check_foreign_files`), and is written only inside (:func:`check_no_link_out`). Each is
refused in one line naming the option and the path, before any work.
"""

from __future__ import annotations

import contextlib
import glob
import os
import re
import shutil
import tempfile

from fem_prep import schema as sc
from fem_prep.files import check_not_input, check_output_dir, check_output_file

__all__ = [
    "OUTPUT_FILES",
    "PLANETARY_FILES",
    "TRAIN_FILES",
    "case_inputs",
    "check_case_outputs",
    "check_foreign_files",
    "check_no_link_out",
    "check_not_input",
    "check_out_inputs",
    "check_output_dir",
    "check_output_file",
    "clear_outputs",
    "staged_outputs",
]

# The files each command writes into its folder (subfolder/name for the nested ones; a name may
# hold a * wildcard, which matches within one name, never across a "/": :func:`_matches`). Only
# these names are ever deleted by :func:`clear_outputs`, and only when the folder's manifest says
# that jaxgear wrote them and they lie inside the folder: a user's own files in the folder stay.
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
        "loaded_path.png",  # with [mesh] extended_contact
        "rating.md",  # with a [rating] table
        "root_stress_map.png",  # with a [rating] table (a train: root_stress_map_<mesh>.png)
        "tribology.json",  # with a [lubricant] table: film and sliding loss
        "tribology.csv",
        "tribology.png",
        "root_stress_map_*.png",
        "spectrum.csv",  # with a [rating.spectrum] table (ISO 6336-6)
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
        "body_pinion_stress.vtu",  # the condensed bodies' element stresses
        "body_gear_stress.vtu",
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
        # a planetary stage's: the ring transducer's order spectrum at the worst speed
        "ring_spectrum.png",
        # --vtu-speed: the deformed bodies' time series
        "vtu/body_*.vtu",
        "vtu/body_*.pvd",
    ),
    "optimise": ("optimum.json", "convergence.png", "harris.png", "path.png", "choice.json",
                 "choice.csv", "choice.png"),
    # jaxgear modes: the natural frequencies with their types
    "modes": ("modes.json",),
    # jaxgear run on a case with [deviations] (subfolder deviations/)
    "deviations": ("te_span.csv", "spectrum.csv", "spectrum.json", "te_spectrum.png"),
    # jaxgear run on a case with [whine] (subfolder whine/): the orders and waterfalls of the
    # TE and bearing forces over the speed range
    "whine": ("whine.json", "whine.csv", "te_orders.png", "bearing_orders.png",
              "te_waterfall.png", "bearing_waterfall.png",
              # with [housing]: its ERP, named points and operating deflection shapes
              "housing.json", "housing.csv", "erp_orders.png", "erp_waterfall.png",
              "point_*_orders.png", "point_*_waterfall.png", "housing_ods.vtu",
              # a planetary stage's: its supports' forces as a fixed seat receives them
              "support_fixed_frame_waterfall.png"),
    # jaxgear run on a housed case with [acoustics] (subfolder acoustics/): the radiated sound
    "acoustics": ("sound_power.json", "sound_power.csv", "sound_power.png", "microphones.csv",
                  "microphones.png", "intensity.vtu", "intensity.png"),
    "master-curve": ("master_curve.json", "master_curve.png"),
    "robust": ("robust.json", "samples.csv", "robust_distributions.png", "robust_speed_bands.png"),
    # jaxgear size: the table of every candidate, the summary, the --write case files
    "size": ("sizing.csv", "sizing.parquet", "sizing.json", "candidate_*.toml", "pareto_*.png",
             "contact_ratios.png"),
    "bench quasi-static": ("bench_quasi_static.json", "speed_accuracy_quasi_static.png"),
    "bench optimise": ("bench_optimise.json",),
    "bench dynamics": ("bench_dynamics.json", "stability_map.json", "stability_map.png"),
    "bench hybrid": ("bench_hybrid.json", "bench_hybrid.png"),
    "bench hybrid-sweep": ("bench_hybrid_sweep.json", "bench_hybrid_sweep.png"),
    "bench modal-basis": ("modal_basis.json", "modal_basis.png"),
    "bench stiffness": ("bench_stiffness.json", "speed_accuracy_stiffness.png"),
    "bench trains": ("bench_trains.json", "bench_trains.png"),
    "bench robust": ("bench_robust.json",),
    "bench xla-cache": ("bench_xla_cache.json", "bench_xla_cache.png"),
}
# what ``jaxgear run`` writes for a train case besides a pair's names: a load map and a pressure
# map per mesh (named after its gears), the layout with its phasing, its flexible gears' bodies;
# with [lubricant] each mesh's film and loss, with [rating.spectrum] each mesh's bins (a planetary
# stage's too)
TRAIN_FILES = ("load_map_*.png", "pressure_map_*.png", "phasing.png", "body_*.vtu",
               "tribology_*.csv", "tribology_*.png", "spectrum_*.csv")
OUTPUT_FILES["run"] += TRAIN_FILES
# what ``jaxgear run`` writes for a planetary stage ([planetary]) besides summary.json: the modes
# with their types, the Campbell diagram in the carrier frame, each mesh's quasi-static curves,
# a flexible ring's mode shapes, the span with every tooth's deviations ([deviations])
PLANETARY_FILES = ("modes.json", "campbell.png", "mesh_*.csv", "ring.vtu", "ring_campbell.png",
                   "hunting.csv", "hunting.png")
OUTPUT_FILES["run"] += PLANETARY_FILES
# what ``jaxgear run`` writes for a gearbox ([[stages]]) besides modes.json and its stages'
# folders: the coupled model's sweep and modes, its dynamic factors' figure, its Campbell diagram
# (campbell.png: a planetary stage's name, above) and the housing-point spectrum
GEARBOX_FILES = ("coupled.json", "coupled.png", "campbell.json", "housing_spectrum.json",
                 "housing_spectrum.png")
OUTPUT_FILES["run"] += GEARBOX_FILES
# ``jaxgear run`` also owns the sweep/, optimise/, scene/, deviations/, whine/ and acoustics/
# subfolders of its folder
OUTPUT_FILES["run"] += tuple(
    f"{sub}/{n}" for sub in ("sweep", "optimise", "scene", "deviations", "whine", "acoustics")
    for n in OUTPUT_FILES[sub]
)


def _matches(name: str, pattern: str) -> bool:
    """Whether the manifest ``name`` is the output name ``pattern``: the same "/"-separated
    parts, a ``*`` matching any characters of one part but "/"; never a name with an empty,
    "." or ".." part or a leading "/" (a manifest is input: ``load_map_/../../x.png`` is no
    output name)."""
    if not _plain(name):
        return False
    rx = "[^/]*".join(re.escape(piece) for piece in pattern.split("*"))
    return re.fullmatch(rx, name) is not None


def _plain(name: str) -> bool:
    """Whether the manifest ``name`` is a plain relative path: no empty, "." or ".." part, no
    leading "/", no NUL (a manifest is input)."""
    parts = name.split("/")
    return not (any(part in ("", ".", "..") for part in parts) or "\0" in name)


def _inside(folder: str, name: str) -> str | None:
    """``folder``/``name`` when the folder that holds it resolves (symbolic links followed)
    inside ``folder``; None otherwise. The file itself may be a link: unlinking removes the
    link, never its target."""
    root = os.path.realpath(folder)
    path = os.path.join(folder, name)
    parent = os.path.realpath(os.path.dirname(path))
    if parent != root and not parent.startswith(root.rstrip(os.sep) + os.sep):
        return None
    return path


def _listed_outputs(folder, patterns, keep=()) -> list[str]:
    """The names the manifest of ``folder`` lists under one of ``patterns`` (but those in
    ``keep``) whose file (or link) lies inside the folder (:func:`_inside`)."""
    listed = set(sc.recorded_outputs(folder)) - set(keep)
    names = []
    for pattern in patterns:
        for name in sorted(n for n in listed if _matches(n, pattern)):
            p = _inside(folder, name)
            if p is not None and (os.path.isfile(p) or os.path.islink(p)) and name not in names:
                names.append(name)
    return names


def _remove_temporary(folder, patterns) -> None:
    """Delete the leftover temporary files (``.tmp-<name>-*.tmp``) of ``patterns`` in ``folder``."""
    for pattern in patterns:
        sub, base = os.path.split(pattern)
        d = os.path.join(folder, sub)
        if os.path.isdir(d) and _inside(folder, os.path.join(sub, "x")) is not None:
            for other in os.listdir(d):
                if _matches(other, f".tmp-{base}-*.tmp"):
                    with contextlib.suppress(OSError):
                        os.unlink(os.path.join(d, other))


def _remove_outputs(folder, patterns, keep=()) -> list[str]:
    """Delete the files the manifest of ``folder`` lists under one of ``patterns`` (but the
    names in ``keep``), and their leftover temporary files; returns the paths removed."""
    removed = []
    for name in _listed_outputs(folder, patterns, keep):
        p = os.path.join(folder, name)
        with contextlib.suppress(FileNotFoundError):
            os.unlink(p)
            removed.append(p)
    _remove_temporary(folder, patterns)
    return removed


#: subfolders a command writes besides those its output names hold (:func:`subfolders`): a
#: gearbox's stages, ``stage<k>/`` (:meth:`jaxgear.io.GearboxForm.stage_name`), each with a
#: run's own subfolders
EXTRA_SUBFOLDERS: dict[str, tuple[str, ...]] = {"run": ("stage*",)}


def subfolders(command: str) -> list[str]:
    """The subfolders (relative, "/"-separated, ``*`` within one name) that ``command`` may
    write into: those of its output names (:data:`OUTPUT_FILES`), every level of them, and
    :data:`EXTRA_SUBFOLDERS` with theirs under each."""
    own = {os.path.dirname(p) for p in OUTPUT_FILES[command]} - {""}
    extra = EXTRA_SUBFOLDERS.get(command, ())
    subs = own | set(extra) | {f"{e}/{s}" for e in extra for s in own}
    levels = set()
    for sub in subs:
        parts = sub.split("/")
        levels |= {"/".join(parts[:i]) for i in range(1, len(parts) + 1)}
    return sorted(levels)


def _within(path: str, root: str) -> bool:
    """Whether the resolved ``path`` is the resolved ``root`` or lies under it."""
    return path == root or path.startswith(root.rstrip(os.sep) + os.sep)


def check_no_link_out(folder, command: str, option: str = "--out") -> None:
    """Refuse an output folder in which a subfolder that ``command`` writes (:func:`subfolders`:
    ``sweep/``, ``optimise/``, ``scene/``, ``vtu/``, a gearbox's ``stage<k>/``, ...) leads out
    of it through a symbolic link (``out/sweep -> ../elsewhere``): jaxgear writes and deletes
    only inside the output folder, never through a link out of it, so that the files behind
    the link stay the user's. Checked before any work (:func:`staged_outputs`,
    :func:`clear_outputs`); a link that stays inside the folder is followed; the output folder
    itself may be a link (the user named it).

    Raises:
        ValueError: one line ``{option} FOLDER: PATH is a symbolic link to TARGET, outside
            the output folder ...``.
    """
    folder = os.fspath(folder)
    root = os.path.realpath(folder)
    for sub in subfolders(command):
        for path in sorted(glob.glob(os.path.join(glob.escape(folder), *sub.split("/")))):
            real = os.path.realpath(path)
            if not _within(real, root):
                raise ValueError(
                    f"{option} {folder}: {path} is a symbolic link to {real}, outside the output "
                    "folder (jaxgear writes only inside it, never through a link): remove the "
                    f"link or choose another {option}"
                )


def case_inputs(case) -> dict[str, str]:
    """{path: what it is} of the files a loaded case was read from
    (:attr:`jaxgear.io.Case.input_files`: its case file first, then the files it names), as
    :func:`check_out_inputs` and :func:`fem_prep.files.check_output_file` take them."""
    files = case.input_files
    return {f: "the case file" if k == 0 else "a file the case names" for k, f in
            enumerate(files)}


def check_out_inputs(folder, command: str, inputs, option: str = "--out") -> None:
    """Refuse an output folder in which an input of the run (``inputs``: {path: what it is},
    :func:`case_inputs`) lies where ``command`` writes: a name of its outputs
    (:data:`OUTPUT_FILES`, in its subfolders too, and in a gearbox's ``stage<k>/``), which the
    run would replace. An input elsewhere in the folder is left alone (the run writes only its
    own names).

    Raises:
        ValueError: one line ``{option} FOLDER: INPUT is WHAT of this run, and jaxgear writes
            NAME there: choose another {option}``.
    """
    root = os.path.realpath(folder)
    patterns = OUTPUT_FILES[command]
    patterns += tuple(f"{e}/{p}" for e in EXTRA_SUBFOLDERS.get(command, ()) for p in patterns)
    for source, what in (inputs or {}).items():
        real = os.path.realpath(source)
        if not _within(real, root) or real == root:
            continue
        name = os.path.relpath(real, root).replace(os.sep, "/")
        if any(_matches(name, p) for p in patterns):
            raise ValueError(
                f"{option} {folder}: {source} is {what} of this run, and jaxgear {command} "
                f"writes {name} there: choose another {option}"
            )


def check_foreign_files(folder, command: str, *, force: bool = False,
                        option: str = "--out") -> None:
    """Refuse, unless ``force``, an output folder holding a file that jaxgear did not write
    there (not in the folder's manifest, :func:`clear_outputs`) under a name ``command`` writes
    (a name of :data:`OUTPUT_FILES` without a wildcard): the run would replace it. A file
    behind a link out of the folder is left to :func:`check_no_link_out`.

    Raises:
        ValueError: one line ``{option} FOLDER: PATH exists and jaxgear did not write it; jaxgear
            COMMAND writes that name (add --force to replace it, or choose another {option})``.
    """
    if force or not os.path.isdir(folder):
        return
    listed = set(sc.recorded_outputs(folder))
    for name in OUTPUT_FILES[command]:
        if "*" in name or name in listed or _inside(folder, name) is None:
            continue
        path = os.path.join(folder, name)
        if os.path.isfile(path) or os.path.islink(path):
            raise ValueError(
                f"{option} {folder}: {path} exists and jaxgear did not write it; jaxgear "
                f"{command} writes that name (add --force to replace it, or choose another "
                f"{option})"
            )


def check_case_outputs(case, command: str, folder, files=(), *, force: bool = False) -> str:
    """The outputs of ``command`` run on the loaded ``case``, checked before any work (the
    module's rule): the output folder (:func:`check_output_dir`, :func:`check_out_inputs`,
    :func:`check_foreign_files`) and each ``(option, path)`` of ``files`` whose path is not
    None (:func:`check_output_file`: no input of the run; an existing file only with
    ``force``; not at a name the command writes into the folder). Returns the folder,
    normalised.

    Raises:
        ValueError: one line naming the option and the path."""
    inputs = case_inputs(case)
    for option, path in files:
        if path is not None:
            check_output_file(path, option, inputs=inputs, force=force)
    folder = check_output_dir(folder)
    check_out_inputs(folder, command, inputs)
    # nor a file option at a name the command writes into its folder (one output over another)
    check_out_inputs(folder, command, {p: f"the {o} file" for o, p in files if p is not None})
    check_foreign_files(folder, command, force=force)
    return folder


def clear_outputs(folder, command: str) -> list[str]:
    """Delete the files that an earlier run wrote into ``folder`` and start recording this run's.

    Refuses first (:func:`check_no_link_out`) a folder whose subfolders that ``command`` writes
    lead out of it through a link. Only files that the folder's manifest (``.jaxgear-outputs``,
    written as the files are written: :func:`fem_prep.schema.record_outputs`) lists AND that
    bear one of ``command``'s output names (:func:`_matches`) AND that lie inside the folder
    (no link out of it followed) are deleted, with their leftover temporary files: a user's own
    files in the folder stay, even those with an output name (a run overwrites those it writes
    itself). Returns the paths removed."""
    check_no_link_out(folder, command)
    removed = _remove_outputs(folder, OUTPUT_FILES[command])
    with contextlib.suppress(FileNotFoundError):  # this run starts a new list
        os.unlink(os.path.join(folder, sc.OUTPUT_MANIFEST))
    sc.record_outputs(folder)
    return removed


STAGING_PREFIX = ".jaxgear-staging-"
#: the hidden folder, inside the output folder, that holds an earlier run's files while a
#: ``--keep-partial`` run writes in place (:func:`staged_outputs`)
EARLIER_PREFIX = ".jaxgear-earlier-"
#: the failures of a run that are a refusal of its input (the CLI's one line and exit status 2,
#: :mod:`jaxgear.cli._main`): a ``--keep-partial`` run refused so gives the earlier results back
REFUSALS = (ValueError, TypeError)


@contextlib.contextmanager
def staged_outputs(folder, command: str, *, keep_partial: bool = False):
    """The folder a command writes its files into: a hidden staging folder inside ``folder``,
    moved in place only when the block ends without an error (the earlier run's files of
    ``command`` then deleted, :func:`clear_outputs`' rules); a failed or interrupted run
    leaves the earlier results as they were and no file of its own (``folder`` removed again
    when this made it and it is empty).

    With ``keep_partial``, ``folder`` itself (``jaxgear run --keep-partial``): the earlier
    files are set aside (a hidden folder inside ``folder``) and the run writes in place; a run
    that completes, or fails otherwise than by a refusal of its input (an interruption, a
    solver's failure, a full disk), leaves what it wrote (with its incomplete ``summary.json``)
    and the earlier files are deleted; a run refused for its input (:data:`REFUSALS`, whenever
    the refusal comes) gets the earlier files back as they were, byte for byte, and leaves none
    of its own.

    Either way, a folder whose subfolders that ``command`` writes lead out of it through a
    symbolic link is refused before anything is written (:func:`check_no_link_out`).
    """
    folder = os.fspath(folder)
    check_no_link_out(folder, command)
    if keep_partial:
        yield from _in_place(folder, command)
        return
    made = not os.path.isdir(folder)
    os.makedirs(folder, exist_ok=True)
    work = tempfile.mkdtemp(prefix=STAGING_PREFIX, dir=folder)
    sc.record_outputs(work)  # its files listed in its own manifest, not in the folder's
    try:
        yield work
        _commit(work, folder, command)
    finally:
        shutil.rmtree(work, ignore_errors=True)
        if made:
            with contextlib.suppress(OSError):
                os.rmdir(folder)  # only when empty: the run failed before any file


def _in_place(folder: str, command: str):
    """:func:`staged_outputs` with ``keep_partial`` (a generator: its body)."""
    aside = _set_aside(folder, command)
    sc.record_outputs(folder)
    try:
        yield folder
    except REFUSALS:
        _remove_own(folder)
        if aside is not None:
            _move_tree(aside, folder)
        raise
    finally:
        if aside is not None:
            shutil.rmtree(aside, ignore_errors=True)


def _remove_own(folder: str) -> None:
    """Delete every file that this run's manifest of ``folder`` lists (inside the folder), and
    the manifest."""
    for name in filter(_plain, sc.recorded_outputs(folder)):
        p = _inside(folder, name)
        if p is not None and (os.path.isfile(p) or os.path.islink(p)):
            with contextlib.suppress(FileNotFoundError):
                os.unlink(p)
    with contextlib.suppress(FileNotFoundError):
        os.unlink(os.path.join(folder, sc.OUTPUT_MANIFEST))


def _set_aside(folder: str, command: str) -> str | None:
    """Move the earlier run's files of ``command`` in ``folder`` (:func:`clear_outputs`' rules)
    and its manifest into a new hidden folder inside it; returns that folder (None when there
    was nothing to move). Their leftover temporary files are deleted."""
    names = _listed_outputs(folder, OUTPUT_FILES[command])
    manifest = os.path.join(folder, sc.OUTPUT_MANIFEST)
    _remove_temporary(folder, OUTPUT_FILES[command])
    if not names and not os.path.lexists(manifest):
        return None
    aside = tempfile.mkdtemp(prefix=EARLIER_PREFIX, dir=folder)
    for name in [*names, sc.OUTPUT_MANIFEST]:
        src = os.path.join(folder, name)
        if os.path.lexists(src):
            dest = os.path.join(aside, name)
            os.makedirs(os.path.dirname(dest), exist_ok=True)
            os.replace(src, dest)
    return aside


def _move_tree(src: str, folder: str) -> None:
    """Move every file under ``src`` to the same relative path in ``folder``."""
    for root, dirs, files in os.walk(src):
        dirs.sort()
        for f in files:
            rel = os.path.relpath(os.path.join(root, f), src)
            dest = os.path.join(folder, rel)
            os.makedirs(os.path.dirname(dest), exist_ok=True)
            os.replace(os.path.join(root, f), dest)


def _commit(work: str, folder: str, command: str) -> None:
    """Move the files of the staging folder ``work`` into ``folder``, delete the earlier run's
    files of ``command`` that this run did not write again, and list this run's files in the
    folder's manifest. A file whose place in ``folder`` leads out of it through a symbolic
    link (one made while the run ran: :func:`check_no_link_out` refused those before) is
    refused before any file moves."""
    new = []
    for root, dirs, files in os.walk(work):
        dirs.sort()
        for f in sorted(files):
            if f == sc.OUTPUT_MANIFEST or f.startswith(".tmp-"):
                continue
            new.append(os.path.relpath(os.path.join(root, f), work).replace(os.sep, "/"))
    for name in new:
        if _inside(folder, name) is None:
            where = os.path.dirname(os.path.join(folder, name))
            raise ValueError(
                f"--out {folder}: {where} leads to {os.path.realpath(where)}, outside the output "
                "folder, through a symbolic link (jaxgear writes only inside it): remove the link"
            )
    manifest = os.path.join(folder, sc.OUTPUT_MANIFEST)
    old = sc.recorded_outputs(folder)
    # while the files move, the manifest lists both runs' (an interruption leaves none unlisted)
    _write_manifest(manifest, list(dict.fromkeys(old + new)))
    for name in new:
        dest = os.path.join(folder, name)
        os.makedirs(os.path.dirname(dest), exist_ok=True)
        os.replace(os.path.join(work, name), dest)
    _remove_outputs(folder, OUTPUT_FILES[command], keep=new)
    _write_manifest(manifest, new)


def _write_manifest(path: str, names: list[str]) -> None:
    """Replace the manifest at ``path`` (atomically; not itself listed in a manifest)."""
    fd, tmp = tempfile.mkstemp(prefix=".tmp-manifest-", suffix=".tmp", dir=os.path.dirname(path))
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write("# files written here by jaxgear (its next run deletes them)\n")
            f.write("".join(n + "\n" for n in names))
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
