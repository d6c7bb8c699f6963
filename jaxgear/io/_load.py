"""Loading a case: a file or an embedded case name, a pair case or a train case."""

from __future__ import annotations

import dataclasses
import functools
import importlib.resources
import os
import tomllib

from fem_prep import schema as sc

from ._case import Case
from ._case_file import parse_case
from ._case_model import check_case_whine
from ._gearbox_file import GearboxForm, is_gearbox, parse_gearbox
from ._housing_table import check_case_housing
from ._planetary_ring_spec import CondensedRingSpec
from ._planetary_spec import PlanetaryForm
from ._train_file import is_train, parse_train

__all__ = ["embedded_case_text", "list_cases", "load_case", "published_rating"]


def _embedded():
    return importlib.resources.files("jaxgear") / "cases"


def list_cases() -> list[str]:
    """Names of the embedded cases (``jaxgear cases``)."""
    return sc.embedded_names(_embedded())


def embedded_case_text(name: str) -> str:
    """The TOML text of the embedded case ``name`` (``jaxgear cases NAME``).

    Raises:
        FileNotFoundError: ``name`` is not an embedded case (the message lists them).
    """
    return sc.embedded_text(_embedded(), name, "case")


@functools.cache
def _published() -> dict:
    """Every table of the embedded published ratings (``cases/published/*.toml``), by case."""
    out = {}
    for f in sorted((_embedded() / "published").iterdir(), key=lambda f: f.name):
        if f.name.endswith(".toml"):
            out |= tomllib.loads(f.read_text(encoding="utf-8"))
    return out


def published_rating(case_name: str) -> dict | None:
    """The values a published rating report prints for the case named ``case_name`` (an
    embedded case whose ``[rating]`` inputs are that report's: the NREL 5 MW stages and their
    KISSsoft reports, ``jaxgear/cases/published/``), or None: ``{"report": its citation,
    <mesh name>: {symbol: value or [pinion, gear]}}`` (a pair's one mesh ``"mesh"``; stresses
    in N/mm², keys ending ``_MPa``; Z_E in √(N/mm²); N_L in cycles). ``jaxgear run`` prints them
    beside its own in ``rating.md``."""
    return _published().get(case_name)


def load_case(name_or_path: str | os.PathLike) -> Case:
    """Load a case (:class:`Case`) from a TOML path or an embedded case name: a pair case
    (:func:`parse_case`, :class:`PairForm`: one mesh) or, with ``[[gears]]`` and ``[[meshes]]``,
    a train case (:func:`parse_train`, :class:`TrainForm`).

    Raises:
        FileNotFoundError: neither a file nor an embedded case name.
        SchemaError (a ``ValueError``): non-UTF-8 bytes or TOML syntax errors (naming the
            file), schema/range errors (see :func:`parse_case`); one line each.
    """
    return _load(name_or_path, ())


def check_case(case: Case) -> None:
    """The checks :func:`load_case` makes of a pair, train or planetary case after its tables
    (:func:`parse_case`, :func:`parse_train`), against its geometry and before any meshing or
    solve: a box ``[housing]`` round its shafts and its named points on its skin, the
    housing's size for this machine, the ``[whine]`` method for the model kind, its groups and
    its size. Call it after parsing a case from a dict, to refuse what a file would refuse.

    Raises:
        SchemaError (a ``ValueError``): one line naming the key, its value and the allowed
            range, in the file's words.
    """
    check_case_housing(case)  # the box round its shafts and its points, before any meshing
    case.housing_size()  # a housing too large for this machine refused before any work
    check_case_whine(case)  # [whine]: its method for the model kind, its groups, its size


def _load(name_or_path: str | os.PathLike, chain: tuple) -> Case:
    """:func:`load_case`, ``chain`` the gearbox files (resolved paths, embedded names) that
    led here: a stage that is one of them (a gearbox whose stage is itself, or a cycle of
    gearbox files) is refused in one line before it recurses."""
    label = str(name_or_path)
    key = os.path.realpath(name_or_path) if os.path.isfile(name_or_path) else label
    if key in chain:
        names = [os.path.basename(c) for c in (*chain, key)]
        raise sc.SchemaError(
            f"[[stages]] case = {label!r}: a gearbox that contains itself (the stages "
            f"{' → '.join(names)} come back to it); allowed a stage that is a planetary stage "
            "or a pair case"
        )
    if os.path.isfile(name_or_path):
        with open(name_or_path, "rb") as f:
            raw = f.read()
        default = os.path.splitext(os.path.basename(label))[0]
        base = os.path.dirname(os.path.abspath(name_or_path))
    elif str(name_or_path) in list_cases():
        raw = embedded_case_text(str(name_or_path))
        default = str(name_or_path)
        base = None
    elif label.endswith(".toml") or os.sep in label or "/" in label:  # meant as a file
        raise FileNotFoundError(
            f"case file {label!r}: no such file (in {os.path.abspath(os.path.dirname(label))}; "
            "an embedded case is named without .toml: jaxgear cases lists them)"
        )
    else:
        raise FileNotFoundError(
            f"case {label!r} is neither a file nor an embedded case"
            f"{sc.did_you_mean(label, list_cases())} (embedded: {', '.join(list_cases())})"
        )
    data = sc.load_toml(raw, f"case file {label!r}")
    if is_gearbox(data):
        case = parse_gearbox(data, default, base, functools.partial(_load, chain=(*chain, key)))
    else:
        case = parse_train(data, default, base) if is_train(data) else parse_case(data, default, base)
        check_case(case)
    own = (os.path.abspath(name_or_path),) if base is not None else ()
    return dataclasses.replace(case, input_files=_input_files(case, own))


def _input_files(case: Case, own: tuple) -> tuple:
    """The files ``case`` was read from (:attr:`Case.input_files`): ``own`` (its case file, or
    none), the files its tables name (resolved as they were read: ``[scene]`` bodies against
    the case file's folder, ``[planetary.ring] body`` as given), a gearbox's stages' files."""
    named = list(case.scene.bodies) if case.scene is not None else []
    housings = [case.housing]
    stages = ()
    if isinstance(case.form, GearboxForm):
        housings.append(case.form.housing)
        stages = case.form.stages
    named += [h.mesh_file for h in housings if h is not None]
    if isinstance(case.form, PlanetaryForm) and isinstance(case.form.spec.ring_model,
                                                           CondensedRingSpec):
        named.append(case.form.spec.ring_model.source)
    files = [*own, *(os.path.abspath(f) for f in named if f is not None and os.path.isfile(f))]
    for stage in stages:
        files.extend(stage.case.input_files)
    return tuple(dict.fromkeys(files))
