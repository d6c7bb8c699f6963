"""A sizing spec's objectives (``[pareto]``) and the oil of its mesh loss (``[lubricant]``),
checked at load and mapped to :class:`jaxgear.sizing.SizingSpec`'s ``objectives``, ``chosen``
and ``mesh_loss``::

    [pareto]
    minimise = ["mass_kg", "mesh_loss_W"]   # columns of the table, each with its sense;
    maximise = ["least_margin"]             # 2 to 6 in all (jaxgear.sizing.OBJECTIVES)
    choose = "knee"                         # the chosen design: "knee" or an objective's column

    [lubricant]                             # a case file's [lubricant]: the oil, the flanks'
                                            # R_a and the friction law of the mesh loss

Without ``[pareto]`` the front is the mass (minimised) and the least margin (maximised) with the
knee chosen; ``mesh_loss_W`` and ``efficiency`` need ``[lubricant]``. Of ``[lubricant]`` a sizing
reads the oil, the roughness and the friction (Schlenk's X_L or a given μ); its film, scuffing
and micropitting keys are refused (no film, flash or micropitting stage here).
"""

from __future__ import annotations

from fem_prep import schema as sc

from ..sizing import CHOICES, DEFAULT_OBJECTIVES, MOST_OBJECTIVES, OBJECTIVES, MeshLossInputs
from ._lubricant_table import LubricantSection

__all__ = ["PARETO_KEYS", "SIZING_LUBRICANT_KEYS", "parse_pareto", "parse_sizing_lubricant"]

#: the keys of a sizing spec's ``[pareto]``
PARETO_KEYS = ("minimise", "maximise", "choose")
#: the keys of ``[lubricant]`` a sizing reads (the mesh loss's)
SIZING_LUBRICANT_KEYS = frozenset({
    "viscosity_40C_mm2_s", "viscosity_100C_mm2_s", "density_kg_m3", "thermal_expansion_per_K",
    "pressure_viscosity_per_GPa", "oil_temperature_C", "roughness_Ra_um", "lubricant_factor",
    "friction_coefficient"})


def parse_sizing_lubricant(table: dict, operating: dict) -> MeshLossInputs:
    """``[lubricant]`` of a sizing spec (the case file's reader, :class:`LubricantSection`, and
    only the keys of :data:`SIZING_LUBRICANT_KEYS`) as the mesh loss's inputs.

    Raises:
        SchemaError (a ``ValueError``): one line naming the key.
    """
    section = LubricantSection.read(table)
    unread = sorted(section.given - SIZING_LUBRICANT_KEYS)
    if unread:
        raise sc.fail("lubricant", unread[0], "not read by a sizing (its mesh loss reads the "
                      "oil, roughness_Ra_um and the friction: " + ", ".join(
                          sorted(SIZING_LUBRICANT_KEYS)) + ")")
    inputs = section.inputs(operating)
    return MeshLossInputs(inputs.lubricant, inputs.roughness, inputs.friction)


def parse_pareto(table: dict | None, has_lubricant: bool) -> tuple[tuple, str]:
    """``[pareto]`` (or None: the defaults) as (objectives, chosen) for
    :class:`jaxgear.sizing.SizingSpec` (the module docstring).

    Raises:
        SchemaError (a ``ValueError``): one line naming the key, its value and what is allowed.
    """
    if table is None:
        return DEFAULT_OBJECTIVES, "knee"
    sc.check_keys(table, set(PARETO_KEYS), "pareto")
    allowed = ", ".join(OBJECTIVES)
    objectives = []
    for key, sense in (("minimise", "min"), ("maximise", "max")):
        names = table.get(key, [])
        if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
            raise sc.fail("pareto", key, "allowed a list of column names: " + allowed, names)
        for name in names:
            if name not in OBJECTIVES:
                raise sc.fail("pareto", key, f"{name!r} is not an objective: allowed {allowed}",
                              names)
            if name in (o[0] for o in objectives):
                raise sc.fail("pareto", key, f"{name!r} is named twice", names)
            if name in ("mesh_loss_W", "efficiency") and not has_lubricant:
                raise sc.fail("pareto", key, f"{name!r} needs a [lubricant] table (the oil, "
                              "roughness and friction of the mesh loss)", names)
            objectives.append((name, sense))
    if "minimise" not in table and "maximise" not in table:
        objectives = list(DEFAULT_OBJECTIVES)
    if not 2 <= len(objectives) <= MOST_OBJECTIVES:
        raise sc.fail("pareto", "minimise", f"{len(objectives)} objectives with maximise: "
                      f"allowed 2 to {MOST_OBJECTIVES}", table.get("minimise", []))
    chosen = table.get("choose", "knee")
    names = [o[0] for o in objectives]
    if chosen not in (*CHOICES, *names):
        raise sc.fail("pareto", "choose", "allowed " + ", ".join(map(repr, (*CHOICES, *names))),
                      chosen)
    return tuple(objectives), chosen
