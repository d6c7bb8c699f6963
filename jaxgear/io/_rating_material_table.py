"""The rating's ``[material]`` keys and the ranges a material and a surface can have: the
treatment of each gear (``treatment``, ``brinell_hardness_HB``, ``proof_stress_MPa``, mapped to
:class:`jaxgear.rating.CaseHardened`, :class:`jaxgear.rating.ThroughHardened`,
:class:`jaxgear.rating.Nitrided`, :class:`jaxgear.rating.PairTreatment`), the per-gear numbers of
``[material]`` and ``[rating]`` in their :data:`MATERIAL_RANGES` (σ_Hlim, σ_Flim: ISO 6336-5's
material lines with margin; the flanks' and root fillets' R_z: finished surfaces), and the refusal
of a ``[material]`` key that no rated gear reads (:func:`refuse_unread_material`).
:mod:`jaxgear.io._rating_table` reads the rest of a rating."""

from __future__ import annotations

import functools

from fem_prep import schema as sc

from ..rating import (
    RATING_RANGES,
    CaseHardened,
    Nitrided,
    PairTreatment,
    ThroughHardened,
)

__all__ = [
    "MATERIAL_RANGES",
    "TREATMENTS",
    "material_identity",
    "pair_of",
    "refuse_unread_material",
    "treatment_names",
    "treatment_of",
]

#: ``[material] treatment`` names → the model's treatment objects
TREATMENTS = {
    "case_hardened": CaseHardened,
    "through_hardened": ThroughHardened,
    "nitrided": Nitrided,
}

#: the ranges of a material's and a surface's keys in file units, with where they come from
#: (:data:`jaxgear.rating.RATING_RANGES`, SI), the note each range message and the case-file reference
#: print: key → (range, note)
MATERIAL_RANGES = {
    key: (f"[{RATING_RANGES[name][0] * scale:g}, {RATING_RANGES[name][1] * scale:g}]",
          f" ({RATING_RANGES[name][2]})")
    for key, name, scale in (
        ("sigma_H_lim_MPa", "sigma_h_lim", 1e-6),
        ("sigma_F_lim_MPa", "sigma_f_lim", 1e-6),
        ("roughness_Rz_flank_um", "roughness_flank", 1e6),
        ("roughness_Rz_root_um", "roughness_root", 1e6),
    )
}


@functools.singledispatch
def _per_gear(value, table: dict, key: str, where: str, allowed: str, note: str) -> list[float]:
    """A number for both gears (any other type: :func:`fem_prep.schema.number` names it)."""
    v = sc.number(table, key, where, allowed=allowed, note=note)
    return [v, v]


@_per_gear.register(list)
def _(value, table: dict, key: str, where: str, allowed: str, note: str) -> list[float]:
    """[pinion, gear]."""
    return sc.number_list(table, key, where, length=2, allowed=allowed, note=note)


def pair_of(table: dict, key: str, where: str) -> list[float]:
    """A number or a [pinion, gear] list of two numbers (file units) in its
    :data:`MATERIAL_RANGES` range; the key required."""
    allowed, note = MATERIAL_RANGES[key]
    return _per_gear(table.get(key), table, key, where, allowed, note)



def material_identity(mat: dict, where: str = "material") -> tuple:
    """The report-only keys of ``[material]``: ``designation`` (a non-empty string of at most
    60 characters, e.g. "18CrNiMo7-6", or a [pinion, gear] list of two) and
    ``surface_hardness_HV`` (Vickers, [100, 1000], as ISO 6336-5 grades surface-hardened steels;
    or [pinion, gear]). Returns ``(designations, hardnesses)``, each a (pinion, gear) tuple or
    None where the key is absent. The rating does not read them (the strength numbers σ_Hlim,
    σ_Flim carry the material); ``rating.md`` prints them."""
    names = None
    if "designation" in mat:
        value = mat["designation"]
        items = value if isinstance(value, list) else [value, value]
        ok = len(items) == 2 and all(
            isinstance(v, str) and v.strip() and len(v) <= 60 for v in items
        )
        if not ok:
            raise sc.fail(where, "designation", "must be a material name (1 to 60 characters, e.g. "
                          "'18CrNiMo7-6') or a [pinion, gear] list of two", value)
        names = (items[0].strip(), items[1].strip())
    hv = None
    if "surface_hardness_HV" in mat:
        hv = tuple(_per_gear(mat["surface_hardness_HV"], mat, "surface_hardness_HV", where,
                             "[100, 1000]", " (Vickers: ISO 6336-5's surface hardness)"))
    return names, hv


def refuse_unread_material(mat: dict, meshes: list) -> None:
    """Refuse, in one line, a ``[material]`` key that no gear of the rated ``meshes`` (each its
    [pinion, gear] treatment names, :data:`TREATMENTS`) reads: ``proof_stress_MPa`` without a
    through-hardened gear (only its slip-layer thickness ρ' reads it; a surface-hardened
    treatment has one ρ' for all), ``brinell_hardness_HB`` without a mesh of a through-hardened
    gear and a surface-hardened one (only that gear's work hardening factor Z_W reads it)."""
    kinds = [tuple(TREATMENTS[n] for n in names) for names in meshes]
    used = sorted({n for names in meshes for n in names})
    told = f"([material] treatment: {', '.join(used)})"
    if "proof_stress_MPa" in mat and all(k.surface_hardened for pair in kinds for k in pair):
        raise sc.fail(
            "material", "proof_stress_MPa", "not read: it selects a through-hardened gear's "
            f"slip-layer thickness ρ' (ISO 6336-3), and no gear is through_hardened {told}; "
            "remove it, or give the gear treatment = 'through_hardened'", mat["proof_stress_MPa"],
        )
    if "brinell_hardness_HB" in mat and not any(
        a.surface_hardened != b.surface_hardened for a, b in kinds
    ):
        raise sc.fail(
            "material", "brinell_hardness_HB", "not read: it gives the work hardening factor "
            "Z_W of a through-hardened gear meshing with a surface-hardened one (ISO 6336-2), "
            f"and no mesh has one {told}; remove it", mat["brinell_hardness_HB"],
        )



@functools.singledispatch
def treatment_names(value, mat: dict) -> list[str]:
    """``[material] treatment``: one name for both gears (default case-hardened)."""
    return [sc.choice(mat, "treatment", "material", TREATMENTS, "case_hardened")] * 2


@treatment_names.register(list)
def _(value, mat: dict) -> list[str]:
    """[pinion, gear] names."""
    if len(value) != 2:
        raise sc.fail(
            "material", "treatment", f"a name or a [pinion, gear] list of two names of "
            f"{', '.join(repr(c) for c in TREATMENTS)}", value,
        )
    return [sc.choice({"treatment": v}, "treatment", "material", TREATMENTS) for v in value]


@functools.singledispatch
def _optional_pair(value, mat: dict, key: str, allowed: str) -> list:
    """An optional ``[material]`` number for both gears; absent: ``[None, None]``."""
    v = sc.number(mat, key, "material", None, allowed=allowed)
    return [v, v]


@_optional_pair.register(list)
def _(value, mat: dict, key: str, allowed: str) -> list:
    """[pinion, gear]."""
    return sc.number_list(mat, key, "material", None, length=2, allowed=allowed)


def treatment_of(mat: dict):
    """The pair's treatment object of ``[material] treatment``, ``brinell_hardness_HB`` and
    ``proof_stress_MPa`` (the last two read for a through-hardened gear only: its Z_W and its
    slip-layer thickness ρ'): one treatment for both gears, or :class:`jaxgear.rating.PairTreatment`
    when the gears differ."""
    names = treatment_names(mat.get("treatment"), mat)
    hb = _optional_pair(mat.get("brinell_hardness_HB"), mat, "brinell_hardness_HB", "[100, 700]")
    ps = _optional_pair(mat.get("proof_stress_MPa"), mat, "proof_stress_MPa", "[500, 1000]")
    each = []
    for name, h, p in zip(names, hb, ps, strict=True):
        each.append(TREATMENTS[name].of_material(h, None if p is None else p * 1e6))
    return each[0] if each[0] == each[1] else PairTreatment(*each)


