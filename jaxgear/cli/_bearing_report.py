"""What ``jaxgear run`` reports of a case's rolling bearings: each bearing's operating load,
its lives (ISO 281's L10 and L_nm, ISO/TS 16281's L10r) and its tones, in ``summary.json``'s
``bearings`` section, ``rating.md`` and the lines the run prints (docs/bearings.md, "In the report"); the
tones as orders of the pinion speed for the Campbell diagram and the whine spectra. The
numbers are :func:`jaxgear.io.case_bearings`' (the model's); this module only presents them.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..bearings import bearing_tones
from ..io import GearboxForm, PairForm, TrainForm, bearing_spectrum_lives, case_bearings

__all__ = ["TONE_NAMES", "bearing_outputs", "bearing_rating_lines", "bearing_run_lines",
           "bearing_tone_lines", "bearing_tone_orders", "gearbox_bearing_outputs"]

#: the tones' keys and their names on the plots
TONE_NAMES = {"ftf": "FTF", "bpfo": "BPFO", "bpfi": "BPFI", "bsf": "BSF"}
_HOUR = 3600.0


def _tones(kind) -> dict:
    t = bearing_tones(kind)
    return {k: float(getattr(t, k)) for k in TONE_NAMES}


def _life(life) -> dict | None:
    """An :class:`~jaxgear.bearings.OperatingLife` as summary keys (None: not rated)."""
    if life is None:
        return None

    def hours(seconds):
        return None if seconds is None else float(seconds) / _HOUR

    out = {"equivalent_load_N": life.equivalent_load, "L10_revolutions": life.revolutions,
           "L10_hours": hours(life.duration)}
    ref = life.reference
    if ref is not None:
        rev = float(ref.revolutions)
        out |= {"L10r_revolutions": rev, "reference_load_N": float(ref.equivalent_load),
                "L10r_hours": None if life.duration is None
                else rev / life.revolutions * life.duration / _HOUR}
    m = life.modified
    if m is not None:
        out |= {"Lnm_revolutions": float(m.revolutions), "Lnm_hours": hours(m.duration),
                "a1": float(m.reliability_factor), "a_ISO": float(m.life_factor),
                "viscosity_ratio": float(m.viscosity_ratio),
                "fatigue_limit_N": float(m.fatigue_limit)}
    return out


def _spectrum_life(life) -> dict | None:
    """A :class:`~jaxgear.dynamics.SpectrumLife` as summary keys (None: not rated)."""
    if life is None:
        return None
    sp, basic, m, ref = life
    out = {"bins_radial_load_N": np.asarray(sp.radial).tolist(),
           "bins_axial_load_N": np.asarray(sp.axial).tolist(),
           "equivalent_load_N": float(basic.equivalent_load),
           "L10_revolutions": float(basic.revolutions),
           "L10_hours": float(basic.duration) / _HOUR}
    if ref is not None:
        out |= {"L10r_revolutions": float(ref.revolutions),
                "L10r_hours": float(ref.duration) / _HOUR,
                "reference_load_N": float(ref.equivalent_load)}
    if m is not None:
        out |= {"Lnm_revolutions": float(m.revolutions), "Lnm_hours": float(m.duration) / _HOUR}
    return out


@functools.singledispatch
def bearing_outputs(form, case) -> dict | None:
    """``summary.json``'s ``bearings`` section of a case of ``form``: None (a form whose
    shafts take no bearings from geometry)."""
    return None


@bearing_outputs.register(PairForm)
@bearing_outputs.register(TrainForm)
def _(form, case) -> dict | None:
    """A ``lumped3d`` pair's or train's rolling bearings (None without): per bearing its name
    (the case file's table, ``pinion_shaft.bearings[0]``, ``shafts.idler.bearings[1]``), kind,
    position, shaft speed, load f = (F_x, F_y, F_z, M_x, M_y) (N, N·m), F_r and F_a, tones (orders of its shaft's speed, and Hz at it), and, where it has its
    ratings, its lives (revolutions, and hours at the case's speed) and, under the case's
    rating spectrum, ``spectrum_life`` (each bin's loads, P_eq, L10, L10r and L_nm
    by Palmgren–Miner)."""
    found = case_bearings(case)
    if found is None:
        return None
    point, speeds, lives, settings, spectrum, names = found
    rows = []
    for k, shaft in enumerate(point.shafts):
        for i, b in enumerate(shaft.bearings):
            if b.rolling is None:
                continue
            f = np.asarray(point.loads[k][i], float)
            orders = _tones(b.rolling)
            speed = None if speeds is None else float(speeds[k])
            rows.append({
                "name": f"{_shaft_name(names[k])}.bearings[{i}]",
                "kind": type(b.rolling).__name__,
                "position_m": float(b.z),
                "shaft_speed_rad_s": speed,
                "load_N_Nm": f.tolist(),
                "radial_load_N": float(math.hypot(f[0], f[1])),
                "axial_load_N": float(f[2]),
                "tones_orders": orders,
                "tones_Hz": None if speed is None
                else {t: v * speed / (2 * math.pi) for t, v in orders.items()},
                "life": _life(lives[k][i]),
            })
            if spectrum is not None:
                rows[-1]["spectrum_life"] = _spectrum_life(spectrum[k][i])
    return {
        "speed_rad_s": None if speeds is None else float(speeds[0]),
        "life_settings": None if settings is None else {
            "reliability": settings.reliability,
            "viscosity_mm2_per_s": settings.viscosity * 1e6,
            "contamination_factor": settings.contamination,
        },
        "operating_point_iterations": int(point.iterations),
        "bearings": rows,
    }


def _e(v) -> str:
    return f"{v:.3g}"


def bearing_run_lines(section: dict | None) -> list[str]:
    """What ``jaxgear run`` prints of the ``bearings`` section: one line per rolling bearing
    (loads, lives, tones); nothing without the section."""
    if not section:
        return []
    whose = "gearbox's load spectrum" if "load_spectrum" in section else "rating spectrum"
    lines = []
    for b in section["bearings"]:
        text = (f"bearing {b['name']} ({b['kind']}): F_r {b['radial_load_N']:.4g} N, "
                f"F_a {b['axial_load_N']:.3g} N")
        life = b["life"]
        if life is None:
            text += "; life: no dynamic_rating_kN"
        else:
            for key, name in (("L10", "L10"), ("L10r", "L10r"), ("Lnm", "L_nm")):
                rev = life.get(f"{key}_revolutions")
                if rev is None:
                    continue
                h = life.get(f"{key}_hours")
                text += f"; {name} {_e(rev / 1e6)} M rev" + (f" ({_e(h)} h)" if h else "")
        sp = b.get("spectrum_life")
        if sp:
            text += f"; under the {whose} L10 {_e(sp['L10_hours'])} h" + (
                f", L10r {_e(sp['L10r_hours'])} h" if "L10r_hours" in sp else "") + (
                f", L_nm {_e(sp['Lnm_hours'])} h" if "Lnm_hours" in sp else "")
        tones = ", ".join(f"{TONE_NAMES[t]} {v:.4g}" for t, v in b["tones_orders"].items())
        lines.append(f"{text}; tones (orders of its shaft) {tones}")
    return lines


def _shaft_name(table: str) -> str:
    """A shaft's table in the report: the case file's without ``scene.``
    (``pinion_shaft``, ``shafts.idler``)."""
    return table.removeprefix("scene.")


def bearing_tone_orders(case) -> list[dict]:
    """Each rolling bearing's tones as orders of the pinion (input) speed (its own order times
    its shaft's turns per pinion turn: a pair's 1, z1/z2; a train's shaft's speed ratio; a
    gearbox's lumped 3D stage's, times the stage's pinion turns per turn of the gearbox's
    input member, each bearing named ``stage<k>.<its table>``), for the Campbell diagram and
    the spectra: ``[{bearing, tone, order}]``; [] for a case without rolling bearings (a
    lumped 3D pair's, train's or gearbox stage's shafts take them; a planetary stage's do
    not)."""
    return _tone_orders(case.form, case)


@functools.singledispatch
def _tone_orders(form, case) -> list[dict]:
    found = form.bearing_shafts(case)
    if found is None:
        return []
    out = []
    for shaft, name, ratio in zip(*found, strict=True):
        for i, b in enumerate(shaft.bearings):
            if b.rolling is None:
                continue
            for tone, order in _tones(b.rolling).items():
                out.append({"bearing": f"{_shaft_name(name)}.bearings[{i}]", "tone": tone,
                            "order": order * ratio})
    return out


@_tone_orders.register
def _(form: GearboxForm, case) -> list[dict]:
    """Each stage's tones (its case at the carried point) over its pinion's speed per the
    gearbox's input speed (the first stage's input member's)."""
    w = form.stages[0].input_speed
    out = []
    for k, s in enumerate(form.stages):
        for t in _tone_orders(s.case.form, s.case):
            out.append({"bearing": f"{form.stage_name(k)}.{t['bearing']}", "tone": t["tone"],
                        "order": t["order"] * s.case.speed / w})
    return out


def bearing_tone_lines(case) -> list[tuple[str, float]]:
    """The tones of :func:`bearing_tone_orders` as (name, order of the pinion speed) lines, one
    per shaft and tone (a shaft's bearings that share an order named once): the spectra's."""
    out = {}
    for t in bearing_tone_orders(case):
        shaft = t["bearing"].rsplit(".bearings[", 1)[0]
        key = (shaft, t["tone"], round(t["order"], 6))
        stage, _, table = shaft.rpartition(".") if shaft.startswith("stage") else ("", "", shaft)
        label = table.removeprefix("shafts.").replace("_", " ")
        if table.startswith("shafts."):
            label += " shaft"
        label = f"{stage} {label}" if stage else label
        name = f"{label} {TONE_NAMES[t['tone']]} ({t['order']:.3g}×)"
        out.setdefault(key, (name, t["order"]))
    return list(out.values())


def _cell(v, fmt="{:.4g}") -> str:
    return "–" if v is None else fmt.format(v)


def bearing_rating_lines(section: dict | None) -> list[str]:
    """The lines of ``rating.md`` for the ``bearings`` section, after the gears' safety factors:
    a table of each rolling bearing's loads and lives (nothing without the section or without
    a rated bearing)."""
    if not section or not any(b["life"] for b in section["bearings"]):
        return []
    speed = section["speed_rad_s"]
    settings = section["life_settings"]
    modified = (f", and ISO 281's modified life L_nm = a1 a_ISO L10 (reliability "
                f"{settings['reliability']:.4g}, viscosity {settings['viscosity_mm2_per_s']:.4g}"
                f" mm²/s, e_C {settings['contamination_factor']:.4g})" if settings else
                " (L_nm: with a [bearings] table)")
    hours = (f"; hours at {speed:g} rad/s (pinion)." if speed else
             "; in revolutions ([operating] speed_rad_s gives hours).")
    intro = ("Each bearing's load at the operating point of the case's quasi-static solve (its "
             "shaft's push on it), its basic rating life L10 = (C/P)^p, ISO/TS 16281's "
             "reference rating life L10r of its balls' or its rollers' laminae's loads"
             + modified + hours)
    lines = ["", "## Rolling bearings (ISO 281, ISO/TS 16281)", "", intro, "",
             ("| bearing | kind | F_r (N) | F_a (N) | P (N) | L10 (10⁶ rev) | L10h (h) "
              "| L10r (10⁶ rev) | L_nm (10⁶ rev) | L_nmh (h) | a_ISO |"),
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for b in section["bearings"]:
        life = b["life"] or {}

        def mega(key, life=life):
            v = life.get(key)
            return None if v is None else v / 1e6

        lines.append(
            f"| {b['name']} | {b['kind']} | {b['radial_load_N']:.4g} | {b['axial_load_N']:.3g} "
            f"| {_cell(life.get('equivalent_load_N'))} | {_cell(mega('L10_revolutions'))} "
            f"| {_cell(life.get('L10_hours'))} | {_cell(mega('L10r_revolutions'))} "
            f"| {_cell(mega('Lnm_revolutions'))} | {_cell(life.get('Lnm_hours'))} "
            f"| {_cell(life.get('a_ISO'))} |")
    spectra = [(b["name"], b.get("spectrum_life")) for b in section["bearings"]
               if b.get("spectrum_life")]
    if spectra:
        lines += ["", ("Under the rating's load spectrum ([rating.spectrum]: each bin's loads "
                       "at its own operating point, the bins' damage by Palmgren–Miner):"), "",
                  "| bearing | F_r per bin (N) | P_eq (N) | L10h (h) | L10rh (h) | L_nmh (h) |",
                  "|---|---|---|---|---|---|"]
        for name, sp in spectra:
            bins = " / ".join(f"{v:.4g}" for v in sp["bins_radial_load_N"])
            lines.append(f"| {name} | {bins} | {sp['equivalent_load_N']:.4g} "
                         f"| {sp['L10_hours']:.4g} | {_cell(sp.get('L10r_hours'))} "
                         f"| {_cell(sp.get('Lnm_hours'))} |")
    return lines


def gearbox_bearing_outputs(form, case, stages: list[dict]) -> dict | None:
    """A gearbox's ``summary.json`` ``bearings`` section: each lumped 3D stage's rolling
    bearings as its own run reports them (``stages``: the gearbox summary's rows, each with its
    stage's ``summary``; the stage case at the carried operating point: its loads there, its
    lives at the stage's shaft speeds), each named ``stage<k>.<its table>`` with its
    ``stage`` and ``tones_input_orders`` (its tones as orders of the gearbox's input speed,
    :func:`bearing_tone_orders`, the coupled Campbell diagram's and the whine's axis); per
    stage its pinion speed, life settings and fixed-point iterations (``stages``). With the
    gearbox's ``[load_spectrum]``: the section's ``load_spectrum`` (its input bins: torque
    N·m, speed rad/s, time s), each stage's carried bins (``spectrum_pinion_torque_Nm``,
    ``spectrum_pinion_speed_rad_s``: :meth:`~jaxgear.io.GearboxForm.stage_spectrum`) and each
    bearing's ``spectrum_life`` (each bin's loads, P_eq, L10, L10r and L_nm by Palmgren–Miner,
    :func:`jaxgear.io.bearing_spectrum_lives`, as a pair's under its ``[rating.spectrum]``).
    None for a gearbox without a rolling bearing."""
    tones: dict = {}
    for t in bearing_tone_orders(case):
        tones.setdefault(t["bearing"], {})[t["tone"]] = t["order"]
    index = {form.stage_name(k): k for k in range(len(form.stages))}
    rows, per = [], []
    for s in stages:
        section = (s.get("summary") or {}).get("bearings")
        if not section:
            continue
        label = s["stage"]
        per.append({"stage": label} | {k: v for k, v in section.items() if k != "bearings"})
        spectra = {}
        if form.spectrum is not None:
            spectra = _stage_spectrum(form, index[label], per[-1])
        for b in section["bearings"]:
            name = f"{label}.{b['name']}"
            rows.append(b | {"name": name, "stage": label, "tones_input_orders": tones[name]})
            if spectra:
                rows[-1]["spectrum_life"] = spectra[b["name"]]
    if not rows:
        return None
    out = {"input_speed_rad_s": float(form.stages[0].input_speed), "stages": per,
           "bearings": rows}
    if form.spectrum is not None:
        sp = form.spectrum
        out["load_spectrum"] = {"input_torque_Nm": np.asarray(sp.torque).tolist(),
                                "input_speed_rad_s": np.asarray(sp.speed).tolist(),
                                "duration_s": np.asarray(sp.duration).tolist()}
    return out


def _stage_spectrum(form, k: int, row: dict) -> dict:
    """Stage ``k``'s rolling bearings' lives under the gearbox's ``[load_spectrum]`` carried
    to it, by the bearing's name in the stage's report (``pinion_shaft.bearings[0]``); the
    carried bins added to the stage's ``row``."""
    case = form.stages[k].case
    bins = form.stage_spectrum(k)
    row["spectrum_pinion_torque_Nm"] = np.asarray(bins.torque).tolist()
    row["spectrum_pinion_speed_rad_s"] = np.asarray(bins.speed).tolist()
    lives = bearing_spectrum_lives(case, bins)
    names = case.form.bearing_shafts(case).names
    return {f"{_shaft_name(names[j])}.bearings[{i}]": _spectrum_life(life)
            for j, shaft in enumerate(lives) for i, life in enumerate(shaft)}
