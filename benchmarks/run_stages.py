"""Where the time of one ``jaxgear run CASE`` goes: the run in this process under ``cProfile``
(wall clock), its stages read from the profile's cumulative times of the functions that do
them: the quasi-static passes, the first-look time-domain sweep (of which the settled windows),
the whine with its model build, its balance (``whine_response``) and its housing outputs (the
full-field recovery, the VTU), and the figures (every ``savefig`` of the run). CPU seconds and
the load average at start and end beside them (the machine is shared: compare stages within one
record, not across records).

From the repository root::

    python -m benchmarks.run_stages two-stage-housed [--out docs/bench/run_stages_two-stage-housed.json]

The case's files go to a temporary folder. The CLI's persistent compilation cache is used as a
``jaxgear run`` uses it (a warm cache: execution; a cold one: compilation too; the record says
how many programs were compiled). Benchmarks are not tests: timings are measured, never
asserted."""

from __future__ import annotations

import argparse
import cProfile
import json
import os
import pathlib
import pstats
import tempfile
import time

from ._timing import environment

__all__ = ["run_stages"]

ROOT = pathlib.Path(__file__).resolve().parents[1]

# stage: (module path suffix, function name); the cumulative wall seconds of each
STAGES = {
    "run_total": ("jaxgear/cli/run.py", "run_kind"),
    "quasi_static_passes": ("jaxgear/_quasi_static.py", "quasi_static"),
    "time_domain_sweep": ("jaxgear/cli/run.py", "_sweep_section"),
    "time_domain_sweep_windows": ("jaxgear/dynamics/_settle.py", "settled_sweep"),
    "whine_outputs": ("jaxgear/cli/_whine_run.py", "whine_outputs"),
    "whine_balance": ("jaxgear/dynamics/_whine.py", "whine_response"),
    "housing_outputs": ("jaxgear/cli/_housing_run.py", "housing_outputs"),
    "housing_recovery": ("jaxgear/acoustics/_erp.py", "housing_vibration"),
    "housing_ods_vtu": ("fem_prep/housing/_surface.py", "write_housing_ods_vtu"),
    "figures": ("jaxgear/cli/_plots/_figure.py", "savefig"),
}
# (stage, function called from the stage's function): the callee's seconds from that caller
NESTED = {
    "whine_model_build": (("jaxgear/io/_case_sound.py", "case_whine"),
                          ("jaxgear/io/_case_model.py", "build_dynamic_model")),
}


def _find(stats: dict, where: tuple) -> list:
    path, name = where
    return [k for k in stats if k[2] == name and k[0].replace(os.sep, "/").endswith(path)]


def run_stages(case: str) -> dict:
    """Run ``jaxgear run case`` under cProfile here; the stages' wall seconds (see the module)."""
    from jaxgear.cli import main

    env = environment()
    prof = cProfile.Profile()
    with tempfile.TemporaryDirectory() as tmp:
        wall, cpu = time.perf_counter(), time.process_time()
        prof.enable()
        try:
            main(["run", case, "--out", os.path.join(tmp, "out"), "--quiet"])
        except SystemExit:
            pass
        prof.disable()
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    stats = pstats.Stats(prof).stats  # (file, line, name) -> (cc, nc, tt, ct, callers)
    out = {}
    for stage, where in STAGES.items():
        keys = _find(stats, where)
        out[stage] = round(sum(stats[k][3] for k in keys), 2) if keys else None
        if stage == "whine_balance" and keys:
            out["whine_balance_calls"] = int(sum(stats[k][1] for k in keys))
        if stage == "figures" and keys:
            out["figures_written"] = int(sum(stats[k][1] for k in keys))
    for stage, (caller, callee) in NESTED.items():
        callers = set(_find(stats, caller))
        out[stage] = round(sum(ct for k in _find(stats, callee)
                               for c, (_, _, _, ct) in stats[k][4].items() if c in callers), 2)
    return {
        "case": case,
        "wall_s": round(wall, 2),
        "cpu_s": round(cpu, 2),
        "stages_wall_s": out,
        "how": "cProfile cumulative wall seconds of each stage's function (module docstring)",
        "load_average_at_end": list(os.getloadavg()),
        "environment": env,
    }


if __name__ == "__main__":
    import jax

    jax.config.update("jax_enable_x64", True)
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("case")
    p.add_argument("--out", default=None, help="the JSON record (default: print only)")
    a = p.parse_args()
    rec = run_stages(a.case)
    print(json.dumps({k: v for k, v in rec.items() if k != "environment"}, indent=1))
    if a.out:
        pathlib.Path(a.out).write_text(json.dumps(rec, indent=1) + "\n")
