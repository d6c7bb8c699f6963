"""The sizing's sound stage with the radiated sound power: what a candidate costs. ``jaxgear
size`` of examples/sizing/helical.toml with ``[sound] sound_power = true`` (its
``[sound.acoustics]`` defaults: the BEM on the housing's closed skin at 6 frequencies
log-spaced over the orders' range, every radiation mode) and ``--te 0 --dynamics 0 --sound 1``
runs the stage's first candidate: its housed case read, the housing meshed and condensed, the
whine, the ERP, then the radiation operators (one BEM solve per grid frequency, into a fresh
fem_prep cache: solved, not read back) and the sound power. Recorded: the stage's time for the
candidate, the sound power's share of it, the skin's size, and the candidate again with
``--force`` (the condensation and the radiation operators read from fem_prep's cache).

Writes docs/bench/sizing_sound_power.json (or the file given) with the machine, dtype and JAX
version (benchmarks/_timing.py's ``environment()``) and the load average. From the repository
root: ``python -m benchmarks.sizing_sound_power [FILE]``.
"""

from __future__ import annotations

import csv
import json
import os
import pathlib
import sys
import tempfile

import jax

jax.config.update("jax_enable_x64", True)

from benchmarks._timing import environment, write_record
from benchmarks.sizing_sound import _size as sound_size

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "bench" / "sizing_sound_power.json"
SPEC = ROOT / "examples" / "sizing" / "helical.toml"


def _size(spec: str, out: str, *extra: str) -> dict:
    """The stage's first candidate (benchmarks/sizing_sound.py's run of ``spec``)."""
    return sound_size(out, *extra, spec=spec, candidates=1)


def main(path: pathlib.Path) -> None:
    machine = environment()
    load_start = list(os.getloadavg())
    text = SPEC.read_text(encoding="utf-8")
    assert text.count("\nsound_power = false") == 1  # [sound]'s
    text = text.replace("\nsound_power = false", "\nsound_power = true", 1)
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["FEM_PREP_CACHE"] = os.path.join(tmp, "cache")  # fresh housing and R
        spec = os.path.join(tmp, "helical-sound-power.toml")
        pathlib.Path(spec).write_text(text, encoding="utf-8")
        out = os.path.join(tmp, "size")
        first = _size(spec, out)["sound_stage"]
        k = first["candidates"][0]
        with open(os.path.join(out, "store", "sound", f"candidate_{k}.json"),
                  encoding="utf-8") as f:
            result = json.load(f)
        again = _size(spec, out, "--force")["sound_stage"]
        with open(os.path.join(out, "store", "sound", f"candidate_{k}.json"),
                  encoding="utf-8") as f:
            result_again = json.load(f)
        with open(os.path.join(out, "sizing.csv"), encoding="utf-8") as f:
            r = {int(r["candidate"]): r for r in csv.DictReader(f)}[k]
    record = {
        "what": "the sizing's sound stage with [sound] sound_power = true on the example spec: "
                "the first candidate's housed case, housing condensed, whine, ERP and the "
                "radiated sound power (BEM on the closed skin at the grid frequencies), timed "
                "by the stage itself; first (fresh fem_prep cache: condensed and solved) and "
                "again with --force (both read from fem_prep's cache, compiled)",
        "machine": machine,
        "spec": "examples/sizing/helical.toml with its [sound] (24 speeds 300-3000 1/min, 8 "
                "harmonics, cut-off 1.5 x the order-1 mesh frequency at 3000 1/min, 12 mm "
                "aluminium walls, 40 mm tet10 mesh) and sound_power = true ([sound.acoustics] "
                "defaults: bem, 6 frequencies, every mode), --te 0 --dynamics 0 --sound 1",
        "candidate": {
            "row": k, "normal_module_mm": round(float(r["normal_module_m"]) * 1e3, 4),
            "z1": int(r["z1"]), "z2": int(r["z2"]),
            "housing_dofs": result["housing_dofs"],
            "skin_vertices": result["skin_vertices"],
            "radiation_frequencies": result["radiation_frequencies"],
            "erp_peak_dB": float(r["erp_peak_dB"]),
            "sound_power_peak_dB": float(r["sound_power_peak_dB"]),
            "sound_power_peak_speed_rad_s": float(r["sound_power_peak_speed_rad_s"]),
            "first_s": first["candidate_seconds"][0],
            "first_sound_power_s": round(result["sound_power_seconds"], 3),
            "again_s": again["candidate_seconds"][0],
            "again_sound_power_s": round(result_again["sound_power_seconds"], 3),
        },
        "load_average_at_start": load_start,
        "load_average_at_end": list(os.getloadavg()),
    }
    write_record(path, record)


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)
