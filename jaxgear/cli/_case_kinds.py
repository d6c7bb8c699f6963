"""What the command line writes about a case's meshes, for any case (:class:`jaxgear.io.Case`: a
gear pair is a train of two gears and one mesh), over its views (``pairs``, ``gears``,
``gear_names``, ``mesh_name``, ``span_periods``) and what its results hold: a case of several
meshes has per-mesh lists in its summaries (as the sweep's results,
:func:`jaxgear.cli._sweep_json.pressure_responses`), a case of one mesh (a pair, or a train of one
mesh) has its mesh's values as the summary's own; each mesh's files and titles carry its label,
:meth:`jaxgear.io.Case.mesh_label` (a pair's one mesh has none: its files and titles are the
case's)."""

from __future__ import annotations

__all__ = [
    "GEAR_NAME_GLOSSARY",
    "gear_glossary",
    "gear_meshes",
    "mesh_file_tag",
    "mesh_title",
    "pair_teeth",
    "per_mesh_keys",
    "pressure_curves",
    "refuse_stages",
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
    """The names of the meshes gear ``member`` is in (:meth:`jaxgear.io.Case.mesh_name`;
    a pair's one mesh is named by its case)."""
    return [case.mesh_name(k) for k, gears in enumerate(case.gears) if member in gears]


def pair_teeth(case) -> dict:
    """``sweep.json``'s teeth of the two gears of a case of one mesh (``pinion_teeth``,
    ``wheel_teeth``: the summary's own, as its other values); the gears of a case of several
    meshes are under ``flexible_gear_teeth`` only: {}."""
    pair = case.pairs[0]
    return one_mesh_keys(case, {"pinion_teeth": pair.pinion.teeth, "wheel_teeth": pair.gear.teeth})


def one_mesh_keys(case, keys: dict) -> dict:
    """``keys`` (a summary's keys of its one mesh) for a case of one mesh, {} for a case of
    several (their values are per mesh, :func:`per_mesh_keys`)."""
    return {} if len(case.pairs) > 1 else dict(keys)


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
    """``keys`` (per-mesh lists of a summary) for a case of several meshes, as the sweep's
    results hold them (:func:`jaxgear.cli._sweep_json.pressure_responses`); {} for a case of
    one mesh (its values are the summary's own)."""
    return dict(keys) if len(case.pairs) > 1 else {}


def pressure_curves(case, summary: dict) -> list[tuple]:
    """The contact pressure curves of a sweep ``summary`` of the case
    (:func:`jaxgear.cli.plots.pressure_speed_plot`): ``(mesh label, largest pressure per speed
    (Pa), the quasi-static one at rest (Pa) or None)`` of each mesh, as the summary holds them:
    per mesh (a case of several meshes, :func:`per_mesh_keys`), else the summary's own values,
    one curve, unlabelled."""
    per = summary.get("max_contact_pressure_mesh_Pa")  # (S, m)
    if per is None:
        return [("", summary["max_contact_pressure_Pa"], summary["max_contact_pressure_static_Pa"])]
    return [
        (name, [row[k] for row in per], summary["max_contact_pressure_static_mesh_Pa"][k])
        for k, name in enumerate(summary["mesh_names"])
    ]


def refuse_stages(case, command: str) -> None:
    """Refuse, in one line, a planetary stage or a gearbox given to a command of one gear
    pair (``jaxgear robust``, ``jaxgear optimise``): the command does not take them yet."""
    from ..io import GearboxForm, PlanetaryForm  # the command's own import time

    what = {PlanetaryForm: "planetary stages", GearboxForm: "gearboxes"}.get(type(case.form))
    if what is not None:
        planetary = what[0] == "p"
        kind = "a planetary stage ([planetary])" if planetary else "a gearbox ([[stages]])"
        how = "jaxgear run or jaxgear sweep" if planetary else "jaxgear run"
        raise ValueError(
            f"jaxgear {command} does not take {what} yet: case {case.name!r} is {kind}; run it "
            f"with {how} (allowed: a pair case)"
        )
