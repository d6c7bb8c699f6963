"""What the command line writes about a case's meshes, for a gear pair (:class:`jaxgear.io.Case`)
and a gear train (:class:`jaxgear.io.TrainCase`) alike: both give a train's views (``pairs``,
``gears``, ``gear_names``, ``mesh_name``, ``span_periods``; a pair is a train of two gears and one
mesh), and each mesh's label in the outputs, :meth:`jaxgear.io.TrainCase.mesh_label` (a pair's one
mesh has none: its values are the summary's own, its files and titles the case's)."""

from __future__ import annotations

__all__ = [
    "GEAR_NAME_GLOSSARY",
    "gear_glossary",
    "gear_meshes",
    "labelled_meshes",
    "mesh_file_tag",
    "mesh_title",
    "pair_teeth",
    "per_mesh_keys",
    "pressure_curves",
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


def gear_meshes(case, member: int) -> list:
    """The names of the meshes gear ``member`` is in (:meth:`jaxgear.io.TrainCase.mesh_name`;
    a pair's one mesh is named by its case)."""
    return [case.mesh_name(k) for k, gears in enumerate(case.gears) if member in gears]


def labelled_meshes(case) -> bool:
    """The case's meshes carry labels in the outputs (a train's); a pair's one mesh does not."""
    return any(case.mesh_label(k) for k in range(len(case.pairs)))


def pair_teeth(case) -> dict:
    """``sweep.json``'s teeth of the two gears of an unlabelled mesh (a pair's: ``pinion_teeth``,
    ``wheel_teeth``); labelled meshes' gears are under ``flexible_gear_teeth`` only: {}."""
    if labelled_meshes(case):
        return {}
    (pair,) = case.pairs
    return {"pinion_teeth": pair.pinion.teeth, "wheel_teeth": pair.gear.teeth}


def mesh_file_tag(case, k: int) -> str:
    """What names mesh ``k``'s file among the case's: ``_<label>`` (a train's
    ``pressure_map_dynamic_<mesh>.png``), "" for a pair's one mesh."""
    label = case.mesh_label(k)
    return f"_{label}" if label else ""


def mesh_title(case, k: int) -> str:
    """Mesh ``k`` in a title: ``<case>'s <label>`` (a train's mesh), the case name for a pair's
    one mesh."""
    label = case.mesh_label(k)
    return f"{case.name}'s {label}" if label else case.name


def per_mesh_keys(case, keys: dict) -> dict:
    """``keys`` (per-mesh lists of a summary) where the case's meshes are labelled (a train's);
    {} for a pair (its one mesh's values are the summary's own)."""
    return dict(keys) if labelled_meshes(case) else {}


def pressure_curves(case, summary: dict) -> list[tuple]:
    """The contact pressure curves of a sweep ``summary`` of the case
    (:func:`jaxgear.cli.plots.pressure_speed_plot`): ``(mesh label, largest pressure per speed
    (Pa), the quasi-static one at rest (Pa) or None)`` of each mesh, a pair's one unlabelled (the
    summary's own values, :func:`per_mesh_keys`)."""
    if not labelled_meshes(case):
        return [
            ("", summary["max_contact_pressure_Pa"], summary["max_contact_pressure_static_Pa"])
        ]
    per = summary["max_contact_pressure_mesh_Pa"]  # (S, m)
    return [
        (name, [row[k] for row in per], summary["max_contact_pressure_static_mesh_Pa"][k])
        for k, name in enumerate(summary["mesh_names"])
    ]
