"""The rating's ``[material]`` keys as a typed section (:class:`MaterialRatingKeys`): the
strength numbers σ_Hlim, σ_Flim (:data:`MATERIAL_RANGES`: ISO 6336-5's material lines with
margin), the treatment of each gear (``treatment``, ``brinell_hardness_HB``,
``proof_stress_MPa``, mapped to :class:`jaxgear.rating.CaseHardened`,
:class:`jaxgear.rating.ThroughHardened`, :class:`jaxgear.rating.Nitrided`,
:class:`jaxgear.rating.PairTreatment`) and the report-only ``designation`` and
``surface_hardness_HV``; each per gear (:func:`per_gear`: a number for both, a [pinion, gear]
list, or a train's table by gear name); the per-gear type of ``[rating]``'s flank and root
roughness R_z; the refusal of a ``[material]`` key that no rated gear reads
(:func:`refuse_unread_material`). :mod:`jaxgear.io._rating_table` reads the rest of a rating."""

from __future__ import annotations

from typing import Annotated, Any, ClassVar, Literal

import pydantic
from pydantic import BeforeValidator

from fem_prep import schema as sc

from ..rating import (
    RATING_RANGES,
    CaseHardened,
    Nitrided,
    PairTreatment,
    ThroughHardened,
)
from ._sections import NEEDED, Section, number, number_list, one_of

__all__ = [
    "MATERIAL_RANGES",
    "TREATMENTS",
    "MaterialRatingKeys",
    "per_gear",
    "per_gear_pair",
    "refuse_unread_material",
]

#: ``[material] treatment`` names → the model's treatment objects
TREATMENTS = {
    "case_hardened": CaseHardened,
    "through_hardened": ThroughHardened,
    "nitrided": Nitrided,
}

#: the ranges of a material's and a surface's per-gear keys in file units, with where they
#: come from (σ_Hlim, σ_Flim, R_z: :data:`jaxgear.rating.RATING_RANGES`, SI), the note each
#: range message and the case-file reference print: key → (range, note)
MATERIAL_RANGES = {
    **{
        key: (f"[{RATING_RANGES[name][0] * scale:g}, {RATING_RANGES[name][1] * scale:g}]",
              f" ({RATING_RANGES[name][2]})")
        for key, name, scale in (
            ("sigma_H_lim_MPa", "sigma_h_lim", 1e-6),
            ("sigma_F_lim_MPa", "sigma_f_lim", 1e-6),
            ("roughness_Rz_flank_um", "roughness_flank", 1e6),
            ("roughness_Rz_root_um", "roughness_root", 1e6),
        )
    },
    "brinell_hardness_HB": ("[100, 700]", ""),
    "proof_stress_MPa": ("[500, 1000]", ""),
    "surface_hardness_HV": ("[100, 1000]", " (Vickers: ISO 6336-5's surface hardness)"),
}


def per_gear(key: str):
    """The type of a per-gear number key (``sigma_H_lim_MPa``, ``roughness_Rz_flank_um``, ...)
    in its :data:`MATERIAL_RANGES` range: a number for both gears, a [pinion, gear] list of two,
    or a table by gear name (a train's; its names are the train's gears:
    :func:`jaxgear.io._rating_table._mesh_value`)."""
    allowed, note = MATERIAL_RANGES[key]
    return one_of(number=number(allowed, note=note),
                  array=number_list(allowed, length=2, note=note),
                  table=dict[str, number(allowed, note=note)])


def per_gear_pair(value, key: str, where: str) -> list:
    """The [pinion, gear] values of a per-gear key's checked ``value`` (a number: for both); a
    table by gear name, a train's only, refused in one line."""
    if isinstance(value, dict):
        raise sc.fail(where, key, "must be a number, not a table", value)
    return list(value) if isinstance(value, list) else [value, value]


#: the type of a ``[material] treatment`` name
Treatment = Literal[tuple(TREATMENTS)]
_TWO_NAMES = ("a name or a [pinion, gear] list of two names of "
              + ", ".join(repr(c) for c in TREATMENTS))
_ALLOWED = "allowed " + ", ".join(repr(c) for c in TREATMENTS)
_NAME_WORDS = ("must be a material name (1 to 60 characters, e.g. '18CrNiMo7-6') or a "
               "[pinion, gear] list of two")


def _names(value: Any, info: pydantic.ValidationInfo) -> Any:
    """Treatment names per gear (a [pinion, gear] list of two, or a train's table by gear
    name): a wrong one named as it is, as a single name's."""
    where = (info.context or {}).get("where", "material")
    if isinstance(value, list) and len(value) != 2:
        raise sc.fail(where, "treatment", _TWO_NAMES, value)
    for v in value.values() if isinstance(value, dict) else value:
        if not isinstance(v, str) or v not in TREATMENTS:
            raise sc.fail(where, "treatment", _ALLOWED, v)
    return value


def _material_name(value: Any, info: pydantic.ValidationInfo) -> Any:
    """``designation``: a name of 1 to 60 characters, a [pinion, gear] list of two, or a
    train's table of one per gear name."""
    items = (value if isinstance(value, list) else
             list(value.values()) if isinstance(value, dict) else [value])
    ok = (len(items) == 2 or not isinstance(value, list)) and all(
        isinstance(v, str) and v.strip() and len(v) <= 60 for v in items)
    if not ok:
        raise sc.fail((info.context or {}).get("where", "material"), "designation", _NAME_WORDS,
                      value)
    return value


class MaterialRatingKeys(Section):
    """The keys a rating adds to ``[material]`` (module docstring; each per gear): σ_Hlim and
    σ_Flim (MPa; required where a mesh is rated), the treatment (default case-hardened), the
    Brinell hardness HB (a through-hardened gear's work hardening factor Z_W against a
    surface-hardened one), the proof stress (MPa; a through-hardened gear's slip-layer thickness
    ρ'), and the report-only material name and Vickers surface hardness. Read a mesh's with
    :meth:`of_mesh`."""

    WHERE: ClassVar[str] = "material"
    sigma_H_lim_MPa: Annotated[per_gear("sigma_H_lim_MPa") | None, NEEDED] = None
    sigma_F_lim_MPa: Annotated[per_gear("sigma_F_lim_MPa") | None, NEEDED] = None
    treatment: one_of(
        number=Treatment,
        array=Annotated[list[Treatment], BeforeValidator(_names)],
        table=Annotated[dict[str, Treatment], BeforeValidator(_names)],
    ) | None = pydantic.Field(None, json_schema_extra={"default": "'case_hardened'"})
    brinell_hardness_HB: per_gear("brinell_hardness_HB") | None = None
    proof_stress_MPa: per_gear("proof_stress_MPa") | None = None
    designation: Annotated[Any, BeforeValidator(_material_name)] = None  # a name per gear
    surface_hardness_HV: per_gear("surface_hardness_HV") | None = None

    @classmethod
    def of_mesh(cls, mat: dict):
        """The rating keys of one mesh's ``[material]`` (``mat``: a pair's table, or a train's
        with its per-gear values resolved to [driving, driven]); its other keys left to
        ``[material]``'s section."""
        return cls.read({k: v for k, v in mat.items() if k in cls.model_fields})

    def pair(self, key: str) -> list | None:
        """The [pinion, gear] values of a per-gear key, None where not given."""
        v = getattr(self, key)
        return None if v is None else per_gear_pair(v, key, self.WHERE)

    def treatment_names(self) -> list[str]:
        """The [pinion, gear] treatment names (default case-hardened)."""
        if self.treatment is None:
            return ["case_hardened"] * 2
        if isinstance(self.treatment, dict):  # a train's table, in a pair's case
            raise sc.fail(self.WHERE, "treatment", _TWO_NAMES, self.treatment)
        return per_gear_pair(self.treatment, "treatment", self.WHERE)

    def treatment_of(self):
        """The pair's treatment object of ``treatment``, ``brinell_hardness_HB`` and
        ``proof_stress_MPa`` (the last two read for a through-hardened gear only: its Z_W and
        its slip-layer thickness ρ'): one treatment for both gears, or
        :class:`jaxgear.rating.PairTreatment` when the gears differ."""
        hb = self.pair("brinell_hardness_HB") or [None, None]
        ps = self.pair("proof_stress_MPa") or [None, None]
        each = [TREATMENTS[name].of_material(h, None if p is None else p * 1e6)
                for name, h, p in zip(self.treatment_names(), hb, ps, strict=True)]
        return each[0] if each[0] == each[1] else PairTreatment(*each)

    def identity(self) -> tuple:
        """The report-only keys: ``(designations, hardnesses)``, each a (pinion, gear) tuple
        or None where the key is absent (names stripped). The rating does not read them (the
        strength numbers σ_Hlim, σ_Flim carry the material); ``rating.md`` prints them."""
        names = None
        if self.designation is not None:
            if isinstance(self.designation, dict):  # a train's table, in a pair's case
                raise sc.fail(self.WHERE, "designation", _NAME_WORDS, self.designation)
            items = per_gear_pair(self.designation, "designation", self.WHERE)
            names = (items[0].strip(), items[1].strip())
        hv = self.pair("surface_hardness_HV")
        return names, None if hv is None else tuple(hv)


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
