"""What the command line reads from a case, by the case's type: a gear pair (:class:`jaxgear.io.Case`)
or a gear train (:class:`jaxgear.io.TrainCase`). Each is a :func:`functools.singledispatch` function
with one implementation per case type, so that a command asks the case instead of testing its
kind; a new kind of case registers its own."""

from __future__ import annotations

import functools

from ..io import Case, TrainCase

__all__ = [
    "GEAR_NAME_GLOSSARY",
    "case_pairs",
    "gear_glossary",
    "gear_meshes",
    "gear_names",
    "mesh_file_tag",
    "mesh_title",
    "pair_teeth",
    "per_mesh_keys",
    "pressure_curves",
    "span_periods",
]


#: what the short gear names of the embedded trains stand for (in titles)
GEAR_NAME_GLOSSARY = {"hst": "high-speed train, stage 1", "lst": "low-speed train, stage 2"}


def gear_glossary(gear_names) -> str:
    """What the abbreviations in the gear names mean, "hst = ..., lst = ..." ("" if none)."""
    used = [
        f"{k} = {v}"
        for k, v in GEAR_NAME_GLOSSARY.items()
        if any(n == k or n.startswith(k + "-") for n in gear_names)
    ]
    return ", ".join(used)


def _unknown(what: str, case) -> TypeError:
    return TypeError(f"{what}: not defined for a {type(case).__name__} (a Case or a TrainCase)")


@functools.singledispatch
def case_pairs(case) -> tuple:
    """Each mesh's :class:`~jaxgear.GearPair`, in mesh order."""
    raise _unknown("case_pairs", case)


@case_pairs.register
def _(case: Case) -> tuple:
    return (case.pair,)


@case_pairs.register
def _(case: TrainCase) -> tuple:
    return tuple(case.pairs)


@functools.singledispatch
def gear_names(case) -> tuple:
    """Each gear's name in member order: a pair's "pinion" and "gear", a train's own."""
    raise _unknown("gear_names", case)


@gear_names.register
def _(case: Case) -> tuple:
    return ("pinion", "gear")


@gear_names.register
def _(case: TrainCase) -> tuple:
    return tuple(case.gear_names)


@functools.singledispatch
def gear_meshes(case, member: int) -> list:
    """The names of the meshes gear ``member`` is in: a pair's one mesh is named by its case, a
    train's by their gears (:meth:`jaxgear.io.TrainCase.mesh_name`)."""
    raise _unknown("gear_meshes", case)


@gear_meshes.register
def _(case: Case, member: int) -> list:
    return [case.name]


@gear_meshes.register
def _(case: TrainCase, member: int) -> list:
    return [case.mesh_name(k) for k, gears in enumerate(case.gears) if member in gears]


@functools.singledispatch
def pair_teeth(case) -> dict:
    """``sweep.json``'s teeth of a pair's two gears (``pinion_teeth``, ``wheel_teeth``); a
    train's are under ``flexible_gear_teeth`` only: {}."""
    raise _unknown("pair_teeth", case)


@pair_teeth.register
def _(case: Case) -> dict:
    return {"pinion_teeth": case.pair.pinion.teeth, "wheel_teeth": case.pair.gear.teeth}


@pair_teeth.register
def _(case: TrainCase) -> dict:
    return {}


@functools.singledispatch
def mesh_file_tag(case, k: int) -> str:
    """What names mesh ``k``'s file among the case's: "" for a pair's one mesh, ``_<mesh>``
    for a train's (``pressure_map_dynamic_<mesh>.png``)."""
    raise _unknown("mesh_file_tag", case)


@mesh_file_tag.register
def _(case: Case, k: int) -> str:
    return ""


@mesh_file_tag.register
def _(case: TrainCase, k: int) -> str:
    return f"_{case.mesh_name(k)}"


@functools.singledispatch
def mesh_title(case, k: int) -> str:
    """Mesh ``k`` in a title: a pair's case name, a train's ``<case>'s <mesh>``."""
    raise _unknown("mesh_title", case)


@mesh_title.register
def _(case: Case, k: int) -> str:
    return case.name


@mesh_title.register
def _(case: TrainCase, k: int) -> str:
    return f"{case.name}'s {case.mesh_name(k)}"


@functools.singledispatch
def per_mesh_keys(case, keys: dict) -> dict:
    """``keys`` (per-mesh lists of a summary) where the case has several meshes to tell apart:
    a train's; {} for a pair (its one mesh's values are the summary's own)."""
    raise _unknown("per_mesh_keys", case)


@per_mesh_keys.register
def _(case: Case, keys: dict) -> dict:
    return {}


@per_mesh_keys.register
def _(case: TrainCase, keys: dict) -> dict:
    return dict(keys)


@functools.singledispatch
def span_periods(case) -> int:
    """Periods of the first mesh after which every mesh of the case repeats: a pair's 1, a
    train's :attr:`jaxgear.io.TrainCase.span_periods` (its kept periods must hold them)."""
    raise _unknown("span_periods", case)


@span_periods.register
def _(case: Case) -> int:
    return 1


@span_periods.register
def _(case: TrainCase) -> int:
    return case.span_periods


@functools.singledispatch
def pressure_curves(case, summary: dict) -> list[tuple]:
    """The contact pressure curves of a sweep ``summary`` of the case
    (:func:`jaxgear.cli.plots.pressure_speed_plot`): ``(mesh name, largest pressure per speed
    (Pa), the quasi-static one at rest (Pa) or None)`` of each mesh, a pair's one unnamed."""
    raise _unknown("pressure_curves", case)


@pressure_curves.register
def _(case: Case, summary: dict) -> list[tuple]:
    return [
        ("", summary["max_contact_pressure_Pa"], summary["max_contact_pressure_static_Pa"])
    ]


@pressure_curves.register
def _(case: TrainCase, summary: dict) -> list[tuple]:
    per = summary["max_contact_pressure_mesh_Pa"]  # (S, m)
    return [
        (name, [row[k] for row in per], summary["max_contact_pressure_static_mesh_Pa"][k])
        for k, name in enumerate(summary["mesh_names"])
    ]
