"""``rating.md``: one mesh's load capacity written as a rating report a reviewer signs (the way
KISSsoft and MASTA print theirs): the edition and the factors no published worked example
confirms, the input data, material, lubrication and roughness, accuracy, life and load cycles,
the operating point, the load factors with the intermediate values behind K_v and K_Hβ, the
pitting and bending factors and stresses, S_H and S_F against S_Hmin and S_Fmin with a
pass/fail verdict, every row with its ISO 6336 part, edition and clause; the factors jaxgear
measured, each with where it comes from, the contact model that produced it
(:class:`jaxgear.rating.MeasuredFactor`) and whether it is comparable with ISO's; where the case
cites a published report (:func:`jaxgear.io.published_rating`), its printed values beside ours.
One number format (:func:`number`: four significant digits), one notation (the symbols as ISO
6336 writes them: K_Hβ, not K_Hbeta)."""

from __future__ import annotations

import math
from typing import NamedTuple

import equinox as eqx
import numpy as np

from ..io import RatingCase, published_rating, tribology_of
from ..rating import (
    EXTENDED_CONTACT,
    FACTOR_CLAUSES,
    Edition2006,
    Edition2019,
    GivenFactors,
    MeasuredFactor,
    PairTreatment,
    factor_clause,
    rate,
)
from ._rating_inputs import modification_line

__all__ = [
    "RATE",
    "ReportInputs",
    "inputs_of",
    "k_v_note",
    "measured_note",
    "number",
    "rating_lines",
    "reference",
    "standard_lines",
    "sweep_excitation",
    "unconfirmed_factors",
    "verdict",
]

#: jaxgear.rating.rate compiled once (not ~300 eager dispatches), shared by every rating of a run
RATE = eqx.filter_jit(rate)

ISO_SOURCE = "ISO 6336-1 method B"
#: the symbols of the summary's keys as ISO 6336 writes them
SYMBOLS = {
    "K_A": "K_A", "K_v": "K_v", "K_Hbeta": "K_Hβ", "K_Fbeta": "K_Fβ", "K_Halpha": "K_Hα",
    "K_Falpha": "K_Fα", "K_Hbeta_rigid_mesh": "K_Hβ", "K_Halpha_rigid_mesh": "K_Hα",
}


def number(x) -> str:
    """A value as every row of ``rating.md`` prints it: four significant digits, fixed point
    between 10⁻³ and 10⁶ (1.500, 861.0, 1500), else d.ddde±x; ``None``: "not computed"."""
    if x is None:
        return "not computed"
    x = float(x)
    if x == 0.0 or not math.isfinite(x):
        return f"{x:g}"
    r = float(f"{x:.4g}")  # rounded first: 0.99999 prints 1.000, not 1.0000
    if 1e-3 <= abs(r) < 1e6:
        return f"{r:.{max(0, 3 - math.floor(math.log10(abs(r))))}f}"
    return f"{x:.3e}"


def _values(v, scale: float = 1.0) -> str:
    """A scalar or a [pinion, gear] pair, scaled, as "a / b"."""
    if isinstance(v, np.ndarray) and v.ndim == 0:
        v = float(v)
    if isinstance(v, list | tuple | np.ndarray):
        return " / ".join(number(None if x is None else float(x) * scale) for x in v)
    return number(None if v is None else float(v) * scale)


def _source(src: str) -> str:
    """A factor's source as ``rating.md`` prints it: "given", ISO's, or "measured" (the
    summary's long words of a measured factor rated with, ``[rating] use_measured``)."""
    return "measured, [rating] use_measured" if src.startswith("measured") else src


def _printed(v) -> str:
    """A published value as the report printed it (its own rounding: 0.827, not 0.8270)."""
    if isinstance(v, list):
        return " / ".join(_printed(x) for x in v)
    return f"{float(v):.10g}" if abs(float(v)) < 1e6 else f"{float(v):.4g}"


# ------------------------------------------------------------------------------------------
# the edition

#: what each factor an edition leaves unconfirmed (:attr:`jaxgear.rating.AbstractEdition.unconfirmed`)
#: stands for, as the report prints it
_UNCONFIRMED_WHY = {
    "Y_beta": "Y_β (ISO 6336-3:2019, helix angle factor): the 1/cos³β term of the 2019 edition "
              "(no printed worked example of the 2019 edition was found; its 1 − ε_β β/120° "
              "term is the 2006 edition's, checked against a KISSsoft report)",
}


def unconfirmed_factors(method: str) -> list[str]:
    """The factors of the edition ``method`` (:attr:`jaxgear.rating.Rating.method`) whose formula no
    published worked example confirms (the edition's :attr:`~jaxgear.rating.AbstractEdition.unconfirmed`,
    the same tuple :attr:`jaxgear.rating.Rating.unconfirmed` carries), one line each (empty: all
    confirmed)."""
    edition = next((e for e in (Edition2006, Edition2019) if e.label == method), None)
    names = edition.unconfirmed if edition is not None else ()
    return [_UNCONFIRMED_WHY.get(name, name) for name in names]


def _year(method: str) -> str:
    return method.split(":")[1].split()[0]


#: rows whose quantity is defined inside another's clause (its formula): that clause
_WITHIN = {"sigma_H0": "sigma_H", "sigma_HG": "sigma_HP", "sigma_F0": "sigma_F",
           "sigma_FG": "sigma_FP", "Y_M": "sigma_FP"}


def reference(key: str, method: str) -> str:
    """The ISO 6336 reference of a row: part, edition and clause of ``key`` in the edition
    ``method`` (:func:`jaxgear.rating.factor_clause`); where this edition's clause was not checked,
    the other edition's clause labelled with its year ("ISO 6336-2:2019 (2006 ed. 6.1)"); a
    quantity defined in another's formula ("σ_H0" in σ_H's) names that clause ("in 5.3")."""
    key = key.removesuffix("_sqrt_Pa").removesuffix("_Pa")
    own = factor_clause(key, method)
    if len(own.split()) > 2:
        return own
    other = Edition2006.label if method == Edition2019.label else Edition2019.label
    for k, within in ((key, ""), (_WITHIN.get(key), "in ")):
        if k is None:
            continue
        for label in (method, other):
            ref = factor_clause(k, label)
            if len(ref.split()) > 2:
                clause = ref.split()[-1]
                if label == method:
                    return f"{own} {within}{clause}"
                return f"{own} ({within}{_year(label)} ed. {clause})"
    return own


def oil_warning(rating_viscosity_40, oil) -> str | None:
    """A warning line where the pitting rating's oil (``[rating] viscosity_40C_mm2_s``, its Z_L)
    is not the ``[lubricant]`` oil ``oil`` (the film, loss and scuffing), else None (no
    ``[lubricant]``, or the same ν₄₀ within 1e-6)."""
    if oil is None:
        return None
    nu_r, nu_l = float(rating_viscosity_40) * 1e6, float(oil.viscosity_40) * 1e6
    if abs(nu_r - nu_l) <= 1e-6 * nu_l:
        return None
    return (f"**Warning: two oils.** The pitting rating's Z_L uses ν₄₀ = {number(nu_r)} mm²/s "
            f"([rating] viscosity_40C_mm2_s); the film, the loss and the scuffing use the "
            f"[lubricant] oil's ν₄₀ = {number(nu_l)} mm²/s. Give one oil to both.")


#: where the default S_Hmin = S_Fmin = 1 come from and what practice asks (rating.md)
MINIMUM_SAFETY_NOTE = (
    "S_Hmin and S_Fmin are `[rating] min_safety_pitting` and `min_safety_bending`; without them "
    "jaxgear takes 1.0, the limit itself: ISO 6336 rates σ_HG and σ_FG at the 1 % failure "
    "probability of ISO 6336-5's strength numbers and leaves the minimum safety factors to "
    "agreement between purchaser and manufacturer. Practice asks more: the NREL 5 MW KISSsoft "
    "reports (jaxgear/cases/published/kisssoft-nrel-5mw.toml; wind-turbine gearboxes) use "
    "S_Hmin = 1.25 and S_Fmin = 1.56, with bending kept further from its limit than pitting "
    "(a broken tooth ends the gear's life, pitting progresses)."
)


def verdict(s, s_min: float) -> str:
    """"pass" per gear where the safety factor ``s`` is at least ``s_min``, else "FAIL"."""
    return " / ".join("pass" if float(x) >= s_min else "FAIL" for x in np.atleast_1d(s))


# ------------------------------------------------------------------------------------------
# what the report reads beside the summary section

class ReportInputs(NamedTuple):
    """What ``rating.md`` prints beside one mesh's summary section.

    Attributes:
        rc: the mesh's :class:`jaxgear.io.RatingCase` (geometry, operating point, settings).
        gears: the names of the mesh's gears (pinion, gear).
        settings: the settings it is rated with (a planetary mesh's: K_A K_γ as its
            application factor); None: ``rc.settings``.
        published: the values the case's published report prints for this mesh
            (:func:`jaxgear.io.published_rating`'s mesh table) or None; ``report``: its
            citation.
        rating: the :class:`jaxgear.rating.Rating` whose summary the section is (its given and
            measured factors in it), for the intermediate values of K_v and K_Hβ; None: rated
            again from the section (a report written from ``summary.json``'s section alone).
        oil: the case's ``[lubricant]`` oil (:class:`jaxgear.tribology.Lubricant`: the film,
            loss and scuffing of ``jaxgear run``), or None without the table.
    """

    rc: RatingCase
    gears: tuple[str, str]
    settings: object = None
    published: dict | None = None
    report: str | None = None
    rating: object = None
    oil: object = None


def _treatments(t) -> list:
    return [t.pinion, t.gear] if isinstance(t, PairTreatment) else [t, t]


def _treatment_name(t) -> str:
    return {"CaseHardened": "case hardened", "ThroughHardened": "through hardened",
            "Nitrided": "nitrided"}.get(type(t).__name__, type(t).__name__)


def _rated(inputs: ReportInputs, section: dict):
    """The rating the section is the summary of, for the intermediate values of K_v and K_Hβ
    (:attr:`jaxgear.rating.LoadFactors.details`): ``inputs.rating`` where the caller has it,
    else the section rated again (its given and measured factors given)."""
    if inputs.rating is not None:
        return inputs.rating
    settings = inputs.rc.settings if inputs.settings is None else inputs.settings
    given = {k: float(f["value"]) for k, f in section["factors"].items()
             if k != "K_A" and f["source"] != ISO_SOURCE}
    settings = eqx.tree_at(lambda s: s.given, settings, GivenFactors(**given))
    return RATE(inputs.rc.geometry, inputs.rc.operating, settings)


# ------------------------------------------------------------------------------------------
# the tables

class _Table:
    """A table of rows (quantity, symbol, value, unit[, published], reference)."""

    def __init__(self, published: dict | None):
        self.published = published
        self.rows: list[str] = []

    def head(self) -> list[str]:
        if self.published is None:
            return ["| quantity | symbol | value | unit | ISO 6336 (part:edition clause) |",
                    "|---|---|---|---|---|"]
        return ["| quantity | symbol | value | published | unit | ISO 6336 (part:edition "
                "clause) |", "|---|---|---|---|---|---|"]

    def row(self, what: str, symbol: str, value: str, unit: str, ref: str,
            key: str | None = None, scale: float = 1.0) -> None:
        if self.published is None:
            self.rows.append(f"| {what} | {symbol} | {value} | {unit} | {ref} |")
            return
        pub = self.published.get(key) if key else None
        shown = "" if pub is None else _printed(pub)
        self.rows.append(f"| {what} | {symbol} | {value} | {shown} | {unit} | {ref} |")

    def lines(self, title: str, heading: str, note: str | None = None) -> list[str]:
        return [f"{heading}# {title}", "", *([note, ""] if note else []), *self.head(),
                *self.rows, ""]


# summary key, quantity, symbol, scale, unit, published key (N/mm²: 1 from MPa)
_PITTING = [
    ("Z_H", "zone factor", "Z_H", 1, "", "Z_H"),
    ("Z_E_sqrt_Pa", "elasticity factor", "Z_E", 1e-3, "√(N/mm²)", "Z_E_sqrt_MPa"),
    ("Z_epsilon", "contact ratio factor", "Z_ε", 1, "", "Z_epsilon"),
    ("Z_beta", "helix angle factor", "Z_β", 1, "", "Z_beta"),
    ("Z_BD", "single pair tooth contact factors", "Z_B / Z_D", 1, "", "Z_BD"),
    ("sigma_H0_Pa", "nominal contact stress", "σ_H0", 1e-6, "N/mm²", "sigma_H0_MPa"),
    ("sigma_H_Pa", "contact stress", "σ_H", 1e-6, "N/mm²", "sigma_H_MPa"),
    ("Z_NT", "life factor", "Z_NT", 1, "", "Z_NT"),
    ("Z_L", "lubricant factor", "Z_L", 1, "", "Z_L"),
    ("Z_v", "velocity factor", "Z_v", 1, "", "Z_v"),
    ("Z_R", "roughness factor", "Z_R", 1, "", "Z_R"),
]
_BENDING = [
    ("Y_F", "tooth form factor (method B)", "Y_F", 1, "", "Y_F"),
    ("Y_S", "stress correction factor (method B)", "Y_S", 1, "", "Y_S"),
    ("Y_beta", "helix angle factor", "Y_β", 1, "", "Y_beta"),
    ("Y_B", "rim thickness factor", "Y_B", 1, "", "Y_B"),
    ("Y_DT", "deep tooth factor", "Y_DT", 1, "", "Y_DT"),
    ("sigma_F0_Pa", "nominal tooth root stress", "σ_F0", 1e-6, "N/mm²", "sigma_F0_MPa"),
    ("sigma_F_Pa", "tooth root stress", "σ_F", 1e-6, "N/mm²", "sigma_F_MPa"),
    ("Y_NT", "life factor", "Y_NT", 1, "", "Y_NT"),
    ("Y_delta_rel_T", "relative notch sensitivity factor", "Y_δrelT", 1, "", "Y_delta_rel_T"),
    ("Y_R_rel_T", "relative surface factor", "Y_RrelT", 1, "", "Y_R_rel_T"),
    ("Y_X", "size factor", "Y_X", 1, "", "Y_X"),
    ("Y_M", "mean stress influence factor", "Y_M", 1, "", "Y_M"),
]
_FACTORS = [
    ("K_A", "application factor"), ("K_v", "dynamic factor"),
    ("K_Hbeta", "face load factor (contact)"), ("K_Fbeta", "face load factor (root)"),
    ("K_Halpha", "transverse load factor (contact)"),
    ("K_Falpha", "transverse load factor (root)"),
]


def _inputs_tables(inputs: ReportInputs, section: dict, rating, heading: str) -> list[str]:
    """Input data, material, lubrication and roughness, accuracy, life and load cycles, the
    operating point."""
    rc, method, pub = inputs.rc, section["method"], inputs.published
    g, s = rc.geometry, inputs.rc.settings
    d = g.derived()
    ref = lambda k: reference(k, method)
    geo = "ISO 21771 (input)"
    out = []
    t = _Table(pub)
    t.row("gears (pinion / gear)", "", " / ".join(inputs.gears), "", geo)
    t.row("normal module", "m_n", number(float(g.normal_module) * 1e3), "mm", geo)
    t.row("number of teeth", "z", " / ".join(str(z) for z in g.teeth), "", geo)
    t.row("face width", "b", _values(np.asarray(g.face_width), 1e3), "mm", geo)
    t.row("profile shift coefficient", "x", _values(np.asarray(g.profile_shift)), "", geo)
    t.row("helix angle", "β", number(math.degrees(float(g.helix_angle))), "°", geo)
    t.row("normal pressure angle", "α_n", number(math.degrees(float(g.normal_pressure_angle))),
          "°", geo)
    t.row("centre distance", "a", number(float(d.center_distance) * 1e3), "mm", geo)
    t.row("gear ratio z₂/z₁", "u", number(float(d.gear_ratio)), "", geo)
    rack = "ISO 21771 (input; the basic rack of ISO 53)"
    t.row("basic rack (tool): pressure angle", "α_P",
          number(math.degrees(float(g.normal_pressure_angle))), "°", rack)
    t.row("basic rack (tool): dedendum h_fP/m_n (the tool's addendum)", "h_fP*",
          _values(np.asarray(g.dedendum_coeff)), "", rack)
    t.row("basic rack (tool): root radius ρ_fP/m_n (the tool's tip radius)", "ρ_fP*",
          _values(np.asarray(g.fillet_radius_coeff)), "", rack)
    t.row("addendum coefficient (after any tip shortening)", "h_a*",
          _values(np.asarray(g.addendum_coeff)), "", rack)
    t.row("tip diameter", "d_a", _values(np.abs(np.asarray(d.tip_diameter)), 1e3), "mm",
          "ISO 21771 (d_a = d + 2 m_n (h_a* + x))")
    t.row("root diameter", "d_f", _values(np.abs(np.asarray(d.root_diameter)), 1e3), "mm",
          "ISO 21771 (d_f = d − 2 m_n (h_fP* − x))")
    t.row("transverse contact ratio", "ε_α", number(float(d.transverse_contact_ratio)), "",
          f"{ref('Z_epsilon')}, Z_ε", "eps_alpha")
    t.row("overlap ratio", "ε_β", number(float(d.overlap_ratio)), "",
          f"{ref('Z_epsilon')}, Z_ε", "eps_beta")
    out += t.lines("Input data", heading)

    mat, lub, acc = s.material, s.lubrication, s.accuracy
    t = _Table(None)
    tr = _treatments(mat.treatment)
    t.row("material designation ([material] designation)", "",
          "— (not given)" if rc.designation is None else " / ".join(rc.designation), "",
          "reported only (σ_Hlim, σ_Flim carry the material)")
    t.row("heat treatment", "", " / ".join(_treatment_name(x) for x in tr), "",
          f"ISO 6336-5; its life curves: {ref('Z_NT')}, {ref('Y_NT')}")
    t.row("surface hardness ([material] surface_hardness_HV)", "HV",
          "— (not given)" if rc.surface_hardness is None else _values(
              np.asarray(rc.surface_hardness)), "", "reported only (ISO 6336-5 grades it in HV)")
    hb = [getattr(x, "brinell_hardness", None) for x in tr]
    t.row("Brinell hardness (through hardened)", "HB",
          " / ".join("—" if h is None else number(h) for h in hb), "", f"{ref('Z_W')}, Z_W")
    t.row("allowable contact stress number", "σ_Hlim", _values(np.asarray(mat.sigma_h_lim), 1e-6),
          "N/mm²", f"{ref('sigma_H_lim')}; {ref('sigma_HP')}, σ_HP")
    t.row("nominal bending stress number", "σ_Flim", _values(np.asarray(mat.sigma_f_lim), 1e-6),
          "N/mm²", f"{ref('sigma_F_lim')}; {ref('Y_ST')}, σ_FE = Y_ST σ_Flim")
    t.row("Young's modulus", "E", number(float(mat.youngs_modulus) * 1e-6), "N/mm²",
          f"{ref('Z_E')}, Z_E")
    t.row("Poisson's ratio", "ν", number(float(mat.poisson_ratio)), "", f"{ref('Z_E')}, Z_E")
    t.row("density", "ρ", number(float(mat.density)), "kg/m³", f"{ref('K_v')}, m_red of K_v")
    out += t.lines("Material", heading)

    t = _Table(None)
    t.row("kinematic viscosity at 40 °C ([rating])", "ν₄₀", number(float(lub.viscosity_40) * 1e6),
          "mm²/s", f"{ref('Z_L')}, Z_L")
    oil = inputs.oil
    if oil is not None:
        lub_ref = "[lubricant]: film, loss, scuffing (docs/tribology.md)"
        t.row("oil ([lubricant]): kinematic viscosity at 40 °C", "ν₄₀",
              number(float(oil.viscosity_40) * 1e6), "mm²/s", lub_ref)
        t.row("oil ([lubricant]): kinematic viscosity at 100 °C", "ν₁₀₀",
              number(float(oil.viscosity_100) * 1e6), "mm²/s", lub_ref)
        t.row("oil temperature", "θ_oil", number(float(oil.oil_temperature)), "°C", lub_ref)
    t.row("flank roughness", "R_z", _values(np.asarray(lub.roughness_flank), 1e6), "µm",
          f"{ref('Z_R')}, Z_R")
    t.row("root roughness", "R_z", _values(np.asarray(lub.roughness_root), 1e6), "µm",
          f"{ref('Y_R_rel_T')}, Y_RrelT")
    out += t.lines("Lubrication and roughness", heading)
    warning = oil_warning(lub.viscosity_40, oil)
    if warning:
        out += [warning, ""]

    t = _Table(None)
    iso1328 = "ISO 1328-1:2013 tolerance"
    t.row("flank tolerance class", "A", str(acc.grade), "", f"{iso1328}; {ref('Y_DT')}, Y_DT")
    t.row("single pitch deviation", "f_pb", number(float(acc.base_pitch) * 1e6), "µm",
          f"{iso1328}; {ref('K_v')}, {ref('K_Halpha')}")
    t.row("profile form deviation", "f_fα", number(float(acc.profile_form) * 1e6), "µm",
          f"{iso1328}; {ref('K_v')}")
    t.row("helix slope deviation", "f_Hβ", number(float(acc.helix_slope) * 1e6), "µm",
          f"{iso1328}; {ref('K_Hbeta')}")
    ca = rating.factors.details["C_a_m"]
    t.row("tip relief" + (" (running-in C_ay: none given)" if s.tip_relief is None else ""),
          "C_a", number(float(ca) * 1e6), "µm", f"{ref('K_v')}, B_k")
    out += t.lines("Accuracy", heading)

    t = _Table(pub)
    life_h = float(s.life) / 3600.0
    t.row("required life", "L_h", number(life_h), "h", f"{ref('Z_NT')}, {ref('Y_NT')}")
    t.row("load cycles per turn (rated flank)", "", _values(s.loading.cycles_per_turn), "",
          f"{ref('Z_NT')}")
    t.row("load cycles", "N_L", _values(np.asarray(rating.pitting.cycles)), "",
          f"{ref('Z_NT')}, {ref('Y_NT')}", "N_L")
    out += t.lines("Life and load cycles", heading)

    t = _Table(pub)
    torque, speed = float(rc.operating.torque), float(rc.operating.speed)
    d1 = float(d.reference_diameter[0])
    f_t, v = 2 * torque / d1, speed * d1 / 2
    p41 = "ISO 6336-1:2019 4.2 (tangential load, torque and power)"
    t.row("pinion torque", "T₁", number(torque), "N·m", p41)
    t.row("pinion speed", "n₁", number(speed * 30 / math.pi), "1/min", p41)
    t.row("power", "P", number(torque * speed * 1e-3), "kW", p41)
    t.row("nominal tangential load at d₁", "F_t", number(f_t), "N", p41, "F_t_N")
    t.row("pitch line velocity", "v", number(v), "m/s", f"{ref('Z_v')}, Z_v", "v_m_s")
    out += t.lines("Operating point", heading)
    return out


def _k_gamma_row(t: _Table, section: dict, method: str) -> None:
    """A planetary mesh's load sharing factor K_γ (the mesh load factor), a factor of the load as
    K_A (in σ_H's and σ_F's formulas); one computed by jaxgear (not "given") states the contact
    model that produced it (:class:`jaxgear.rating.MeasuredFactor`: it cannot be shown
    without)."""
    kg = section.get("K_gamma")
    if kg is None:
        return
    words = kg["source"]
    if words != "given":
        words += f"; contact model: {MeasuredFactor.of_entry(kg, 'K_gamma').contact_model}"
    t.row("mesh load factor (load sharing), a factor of the load as K_A", "K_γ",
          f"{number(kg['value'])} ({words})", "",
          f"ISO 6336-1:{_year(method)} (mesh load factor; in σ_H: {reference('sigma_H', method)}, "
          f"σ_F: {reference('sigma_F', method)})", "K_gamma")


#: the intermediate values of ISO 6336-1 method B printed (rows marked ↳) after a load factor's
#: row: (symbol, what, key in :attr:`jaxgear.RatingFactors.details`, scale to the unit, unit)
_INTERMEDIATES = {
    "K_v": (
        ("N", "resonance ratio n₁/n_E1", "resonance_ratio_N", 1, ""),
        ("N_S", "lower limit of the main resonance range", "resonance_ratio_N_S", 1, ""),
        ("m_red", "reduced mass per face width", "reduced_mass_kg_per_m", 1, "kg/m"),
        ("c'", "single stiffness", "c_prime_N_per_m2", 1e-9, "N/(mm·µm)"),
        ("c_γα", "mesh stiffness", "c_gamma_alpha_N_per_m2", 1e-9, "N/(mm·µm)"),
        ("f_pb,eff", "f_pb less running-in y_p", "f_pb_eff_m", 1e6, "µm"),
        ("f_fα,eff", "f_fα less running-in y_f", "f_falpha_eff_m", 1e6, "µm"),
        ("B_p", "non-dimensional pitch deviation", "B_p", 1, ""),
        ("B_f", "non-dimensional profile deviation", "B_f", 1, ""),
        ("B_k", "non-dimensional tip relief", "B_k", 1, ""),
    ),
    "K_Hbeta": (
        ("F_m/b", "mean transverse load per face width F_t K_A K_v/b", "F_m_per_b_N_per_m",
         1e-3, "N/mm"),
        ("F_βx", "initial equivalent misalignment (B₂ f_Hβ; f_sh = 0)", "F_betax_m", 1e6, "µm"),
        ("F_βy", "effective equivalent misalignment (F_βx − y_β)", "F_betay_m", 1e6, "µm"),
        ("c_γβ", "mesh stiffness 0.85 c_γα", "c_gamma_beta_N_per_m2", 1e-9, "N/(mm·µm)"),
    ),
    "K_Fbeta": (("N_F", "exponent of K_Fβ = K_Hβ^N_F", "N_F", 1, ""),),
}


#: the measured factor a factor rated with in its place follows (ISO ties K_Fβ to K_Hβ,
#: K_Fα to K_Hα): whose contact model its row states
_MEASURED_OF = {"K_Fbeta": "K_Hbeta", "K_Falpha": "K_Halpha"}


def _factor_rows(t: _Table, section: dict, rating, method: str) -> None:
    """The load factors, K_γ after K_A (a planetary mesh's), and with a ``rating`` (None: the
    factors only) the intermediate values behind K_v, K_Hβ and K_Fβ (ISO's, computed whether
    or not the factor is given) after their rows (:data:`_INTERMEDIATES`). A factor rated with
    a measured one in its place states the contact model of that measurement."""
    det = {} if rating is None else {
        k: float(np.asarray(v)) for k, v in rating.factors.details.items()
        if np.asarray(v).ndim == 0}
    measured = section.get("measured") or {}
    for key, what in _FACTORS:
        f = section["factors"][key]
        words = _source(f["source"])
        if f["source"].startswith("measured"):
            of = _MEASURED_OF.get(key, key)
            row = MeasuredFactor.of_entry(measured.get(of, {}), of)
            words += f"; contact model: {row.contact_model}"
        value = f"{number(f['value'])} ({words})"
        t.row(what, SYMBOLS[key], value, "", reference(key, method), key)
        if key == "K_A":
            _k_gamma_row(t, section, method)
        for sym, name, k, scale, unit in _INTERMEDIATES.get(key, ()) if det else ():
            t.row(f"↳ {name}", sym, number(det[k] * scale), unit, reference(key, method))


#: a mesh frequency below this share of the first mode is far below resonance: there ISO 6336-1's
#: K_v (the subcritical range, N <= N_S) is about 1 plus its deviation terms
FAR_BELOW = 0.5
#: why a dynamic factor measured far below the first mode is not ISO's K_v (the theoretical path
#: of contact)
ENTERING_PAIR = (
    "the measured factor there is the transient of each tooth pair entering contact (teeth "
    "without tip relief, under exact contact on the theoretical path, take their load at the "
    "theoretical start of contact and ring the mesh), not the resonance amplification ISO's "
    "K_v bounds"
)
#: what a dynamic factor measured far below the first mode is with contact beyond the path
GRADUAL_ENTRY = (
    "with contact beyond the theoretical path each entering pair takes its load gradually "
    "(docs/extended-contact.md): the measured factor is the mesh's dynamic overload from the "
    "varying mesh stiffness, as ISO's K_v is below resonance"
)


def _extended(contact: str | None) -> bool:
    """Whether the contact-model words ``contact`` (:func:`jaxgear.rating.contact_model`) are
    the extended path's on every mesh."""
    return contact == EXTENDED_CONTACT


def k_v_note(
    mesh_hz: float, mode_hz: float, mode: str, contact: str | None = None
) -> tuple[bool, str]:
    """Whether a K_v measured at the mesh frequency ``mesh_hz`` (Hz) is comparable with ISO's,
    from its ratio to the first mode ``mode_hz`` (Hz; ``mode`` says which) and the contact model
    ``contact`` (its words), and why: (comparable, words). On the theoretical path not
    comparable below :data:`FAR_BELOW` of the mode (:data:`ENTERING_PAIR`); with contact beyond
    it comparable there too (:data:`GRADUAL_ENTRY`)."""
    r = mesh_hz / mode_hz
    where = (f"mesh frequency {number(mesh_hz)} Hz = {number(r)} × {mode} "
             f"({number(mode_hz)} Hz)")
    if r < FAR_BELOW and not _extended(contact):
        return False, (f"not comparable with ISO's: {where}, far below resonance, where ISO's "
                       f"K_v is about 1 plus its deviation terms (B_p, B_f, B_k); {ENTERING_PAIR}")
    if r < FAR_BELOW:
        return True, f"comparable: {where}, far below resonance; {GRADUAL_ENTRY}"
    return True, (f"comparable: both the largest dynamic mesh load over the static one; "
                  f"{where}")


def sweep_excitation(mesh_hz, first_hz: float, contact: str | None = None) -> str | None:
    """What a sweep's dynamic factors are where every swept mesh frequency (``mesh_hz``, Hz)
    lies below :data:`FAR_BELOW` of the model's first mode ``first_hz`` (Hz): on the
    theoretical path not resonances but the entering-pair transient (:data:`ENTERING_PAIR`),
    which the peak-based dynamic K_γ (:func:`jaxgear.planetary.dynamic_load_sharing`) does not
    count again; with contact beyond the path (``contact``, the contact-model words) the
    gradual entry's overload (:data:`GRADUAL_ENTRY`); None otherwise."""
    hi = float(np.max(mesh_hz))
    if hi >= FAR_BELOW * first_hz:
        return None
    where = (f"mesh frequencies {number(float(np.min(mesh_hz)))}–{number(hi)} Hz, at most "
             f"{number(hi / first_hz)} × the first mode ({number(first_hz)} Hz): far below "
             "resonance, where ISO 6336-1's K_v is about 1")
    if _extended(contact):
        return f"{where}; {GRADUAL_ENTRY}"
    return (f"{where}; the dynamic factors here are the transient of each tooth pair entering "
            "contact (teeth without tip relief, under exact contact on the theoretical path, "
            "take their load at the theoretical start of contact and ring the mesh), not "
            "comparable with ISO's K_v; the dynamic K_γ (peak-based: each planet path's peak "
            "over the mean path's) does not count that transient again")


#: the standing words on a measured factor's cause and comparability, by the factor it measures
_MEASURED_CAUSE = {
    "K_Hbeta": ("comparable in kind (the largest load per face width over the mean), not in "
                "cause: ISO's comes from the misalignment F_βy of the accuracy grade's f_Hβ "
                "(no shaft deflection); the measured one from the model's deflections and the "
                "case's lead modifications, with no helix deviation (a crowning raises it on an "
                "aligned mesh)"),
    "K_Halpha": ("comparable in kind (load sharing between the pairs in contact), not in cause: "
                 "ISO's comes from the pitch deviation f_pb; the measured one from the case's "
                 "profile modifications under exact contact, with no pitch deviation (a tip "
                 "relief the load does not close raises it); rated within ISO's limits"),
}


def measured_note(key: str, measured: dict) -> str:
    """Where a measured factor comes from and whether it is comparable with ISO's: its
    ``note`` where the run gave one (a K_v's, from the mesh frequency against the first mode),
    else the standing words for its kind (:data:`_MEASURED_CAUSE`)."""
    return measured.get("note") or _MEASURED_CAUSE.get(key.removesuffix("_rigid_mesh"), "")


def _measured_lines(section: dict, heading: str) -> list[str]:
    measured = section.get("measured") or {}
    if not measured:
        return []
    out = [f"{heading}# Factors measured by jaxgear (where each comes from)", "",
           "| symbol | measured | ISO / given (rated) | used in the rating | source | "
           "contact model | comparable with ISO's? |", "|---|---|---|---|---|---|---|"]
    for key, m in measured.items():
        row = MeasuredFactor.of_entry(m, key)  # no row without its contact model
        base = key.removesuffix("_rigid_mesh")
        factor = section["factors"].get(key)  # K_Hbeta_rigid_mesh: reported only
        used = factor is not None and factor["source"] != ISO_SOURCE and factor["source"] != \
            "given"
        name = SYMBOLS.get(key, key) + (" measured, rigid mesh" if key != base else " measured")
        rated = section["factors"][base]
        used_words = "yes: [rating] use_measured" if used else "no (reported only)"
        out.append(f"| {name} | {number(m['value'])} | {number(rated['value'])} "
                   f"({'measured' if used else rated['source']}) | {used_words} | "
                   f"{row.source} | {row.contact_model} | {measured_note(key, m)} |")
    return out + [""]


def _root_stress_lines(section: dict, heading: str) -> list[str]:
    rs = section.get("root_stress")
    if rs is None:
        return []
    out = [f"{heading}# Tooth root stress by FE (reported only, not used in the rating)", "",
           "| quantity | value | unit | source |", "|---|---|---|---|",
           f"| σ_F,FE max | {_values(rs['max_Pa'], 1e-6)} | N/mm² | {rs['source']} |",
           f"| σ_F,FE max / σ_F0 | {_values(rs['fe_over_iso'])} |  | FE over ISO 6336-3's σ_F0 "
           "(no load factor) |"]
    fast = rs.get("at_speed")
    if fast is not None:
        speed_of = fast.get("speed_of", "the sweep's speed of its largest dynamic factor")
        out.append(
            f"| σ_F,FE max at speed | {_values(fast['max_Pa'], 1e-6)} | N/mm² | at "
            f"{number(fast['speed_rad_s'])} rad/s ({speed_of}; this mesh's dynamic factor there "
            f"{number(fast['dynamic_factor'])}, tooth {number(fast['dynamic_factor_tooth'])}) |")
        static_of = fast.get("static_of", f"the same {fast['slices']} slices, quasi-static "
                             "rigid mesh")
        out.append(f"| σ_F,FE at speed / static | {_values(fast['ratio'])} |  | {static_of} |")
    return out + [""]


def rating_lines(section: dict, case_name: str, heading: str = "#",
                 inputs: ReportInputs | None = None) -> list[str]:
    """``rating.md`` of one mesh's summary ``section`` (``heading`` the title's Markdown level):
    the edition and its unconfirmed factors (:func:`unconfirmed_factors`), with ``inputs`` (a
    :class:`ReportInputs`) the input data, material, lubrication and roughness, accuracy, life
    and load cycles, the operating point and the intermediate values of K_v and K_Hβ; the load
    factors, pitting and bending, S_H and S_F against S_Hmin and S_Fmin with their verdicts, the
    measured factors with their causes, the FE root stress; the published report's values in a
    column where ``inputs.published`` has them. Every row of the rating's tables names its ISO
    6336 part, edition and clause (:func:`reference`). A section of another standard than
    ISO 6336's editions (:class:`jaxgear.rating.AbstractRatingStandard`): its values as its
    summary gives them (:func:`standard_lines`)."""
    method = section["method"]
    if method not in FACTOR_CLAUSES:
        settings = None if inputs is None else (
            inputs.rc.settings if inputs.settings is None else inputs.settings)
        return standard_lines(section, case_name, heading, settings)
    h = heading  # each table's heading one level below the title's
    out = [f"{heading} {case_name}: load capacity, {method}", ""]
    out.append(f"Edition: ISO 6336-1, -2 and -3:{_year(method)}, method B (strength numbers of "
               "ISO 6336-5). Per-gear values as pinion / gear; stresses in N/mm² (summary.json: "
               "Pa); four significant digits. Each row names the part, edition and clause it "
               "comes from; where this edition's clause numbering was not checked, the other "
               "edition's, labelled with its year.")
    out.append("")
    unconfirmed = unconfirmed_factors(method)
    out.append("Factors whose formula no published worked example confirms: "
               + ("; ".join(unconfirmed) if unconfirmed else "none") + ".")
    out.append("")
    out += modification_line(section)[1:]  # ISO's tip relief and crowning inputs, their source
    pub = inputs.published if inputs is not None else None
    if pub is not None:
        out += [f"Published values: {inputs.report}, as printed (its rounding). Where this "
                "case's inputs differ from the report's (the case file's comments say which, "
                "e.g. a K_γ or a load factor the report was given), so do the values.", ""]
    rating = None
    if inputs is not None:
        rating = _rated(inputs, section)
        out += _inputs_tables(inputs, section, rating, h)
    t = _Table(pub)
    _factor_rows(t, section, rating, method)
    out += t.lines("Load factors", h, None if rating is None else (
        "Rows marked ↳ are the intermediate values of ISO 6336-1 method B behind the factor "
        "above them (computed from the inputs even where the factor is given or measured)."))

    settings = None if inputs is None else (
        inputs.rc.settings if inputs.settings is None else inputs.settings)
    p, b = section["pitting"], section["bending"]
    t = _Table(pub)
    for key, what, sym, scale, unit, pk in _PITTING:
        t.row(what, sym, _values(p[key], scale), unit, reference(key, method), pk)
    if rating is not None:
        r = rating.pitting
        t.row("work hardening factor", "Z_W", _values(np.asarray(r.Z_W)), "",
              reference("Z_W", method), "Z_W")
        t.row("size factor", "Z_X", _values(np.asarray(r.Z_X)), "", reference("Z_X", method),
              "Z_X")
        t.row("pitting stress limit", "σ_HG", _values(np.asarray(r.sigma_HG), 1e-6), "N/mm²",
              reference("sigma_HG", method), "sigma_HG_MPa")
    t.row("permissible contact stress σ_HG/S_Hmin", "σ_HP", _values(p["sigma_HP_Pa"], 1e-6),
          "N/mm²", reference("sigma_HP", method), "sigma_HP_MPa")
    t.row("safety factor for pitting σ_HG/σ_H", "S_H", _values(p["S_H"]), "",
          reference("S_H", method), "S_H")
    out += t.lines("Pitting (ISO 6336-2)", h)

    t = _Table(pub)
    for key, what, sym, scale, unit, pk in _BENDING:
        t.row(what, sym, _values(b[key], scale), unit, reference(key, method), pk)
    if rating is not None:
        r = rating.bending
        t.row("stress correction factor of the test gears", "Y_ST", number(float(r.Y_ST)), "",
              reference("Y_ST", method), "Y_ST")
        t.row("tooth root stress limit", "σ_FG", _values(np.asarray(r.sigma_FG), 1e-6), "N/mm²",
              reference("sigma_FG", method), "sigma_FG_MPa")
    t.row("permissible bending stress σ_FG/S_Fmin", "σ_FP", _values(b["sigma_FP_Pa"], 1e-6),
          "N/mm²", reference("sigma_FP", method), "sigma_FP_MPa")
    t.row("safety factor for bending σ_FG/σ_F", "S_F", _values(b["S_F"]), "",
          reference("S_F", method), "S_F")
    out += t.lines("Bending (ISO 6336-3)", h)

    if settings is not None:
        s_h, s_f = float(settings.min_safety_pitting), float(settings.min_safety_bending)
        out += [f"{h}# Safety against the required minimum", "",
                "| safety factor | value | required minimum | verdict | ISO 6336 |",
                "|---|---|---|---|---|",
                f"| S_H | {_values(p['S_H'])} | S_Hmin = {number(s_h)} | "
                f"{verdict(p['S_H'], s_h)} | {reference('S_H', method)} |",
                f"| S_F | {_values(b['S_F'])} | S_Fmin = {number(s_f)} | "
                f"{verdict(b['S_F'], s_f)} | {reference('S_F', method)} |", "",
                MINIMUM_SAFETY_NOTE, ""]
    out += _measured_lines(section, h)
    out += _root_stress_lines(section, h)
    return out


def _generic_rows(values: dict) -> list[str]:
    """A summary table's rows as they are: its key (a stress's ``_Pa`` in N/mm²), its values."""
    out = []
    for key, v in values.items():
        if key.endswith("_Pa"):
            out.append(f"| {key.removesuffix('_Pa')} | {_values(v, 1e-6)} | N/mm² |")
        else:
            out.append(f"| {key} | {_values(v)} |  |")
    return out


def standard_lines(section: dict, case_name: str, heading: str = "#",
                   settings=None) -> list[str]:
    """``rating.md`` of one mesh's ``section`` rated to a standard other than ISO 6336's
    editions (:class:`jaxgear.rating.AbstractRatingStandard`, its
    :meth:`~jaxgear.rating.AbstractRatingStandard.summary`): the load factors with their
    sources, the pitting and bending values as the standard names them (stresses in N/mm²),
    S_H and S_F against the settings' minimums with their verdicts (with ``settings``), the
    measured factors and the FE root stress."""
    h = heading
    out = [f"{heading} {case_name}: load capacity, {section['method']}", "",
           "Per-gear values as pinion / gear; stresses in N/mm² (summary.json: Pa); four "
           "significant digits; each value as the standard's summary names it.", ""]
    out += [f"{h}# Load factors", "", "| symbol | value | source |", "|---|---|---|"]
    out += [f"| {SYMBOLS.get(k, k)} | {number(f['value'])} | {_source(f['source'])} |"
            for k, f in section["factors"].items()] + [""]
    for title, key in (("Pitting", "pitting"), ("Bending", "bending")):
        out += [f"{h}# {title}", "", "| quantity | value | unit |", "|---|---|---|"]
        out += _generic_rows(section[key]) + [""]
    if settings is not None:
        p, b = section["pitting"], section["bending"]
        s_h, s_f = float(settings.min_safety_pitting), float(settings.min_safety_bending)
        out += [f"{h}# Safety against the required minimum", "",
                "| safety factor | value | required minimum | verdict |", "|---|---|---|---|",
                f"| S_H | {_values(p['S_H'])} | S_Hmin = {number(s_h)} | "
                f"{verdict(p['S_H'], s_h)} |",
                f"| S_F | {_values(b['S_F'])} | S_Fmin = {number(s_f)} | "
                f"{verdict(b['S_F'], s_f)} |", ""]
    out += _measured_lines(section, h)
    out += _root_stress_lines(section, h)
    return out


def inputs_of(case, k: int, rc: RatingCase, settings=None, rating=None) -> ReportInputs:
    """Mesh ``k``'s :class:`ReportInputs` of ``case`` (a pair's one mesh: ``"mesh"`` in the
    published tables); ``rating``: the :class:`jaxgear.rating.Rating` of its section, if at hand."""
    pub = published_rating(case.name)
    mesh = None if pub is None else pub.get(case.mesh_name(k), pub.get("mesh"))
    gears = tuple(case.gear_names[g] for g in case.gears[k])
    tribology = tribology_of(case)
    return ReportInputs(rc, gears, settings, mesh, None if mesh is None else pub["report"],
                        rating, None if tribology is None else tribology.lubricant)
