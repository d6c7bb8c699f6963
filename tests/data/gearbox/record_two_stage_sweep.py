"""Records tests/data/gearbox/two_stage_sweep_reference.json (tests/test_cli_sweep_forms.py):
the two-stage gearbox case file's coupled sweep by jaxgear.gearbox.gearbox_speed_sweep at main
before the gearbox became a dynamics model (its own Newmark loop and plan), at two input speeds
on an explicit plan. Run at that commit::

    PYTHONPATH=$PWD python tests/data/gearbox/record_two_stage_sweep.py . \
        tests/data/gearbox/two_stage_sweep_reference.json
"""
import json
import pathlib
import subprocess
import sys

import jax
import numpy as np

import jaxgear.io as jio
from jaxgear import gearbox as gb

jax.config.update("jax_enable_x64", True)

root = pathlib.Path(sys.argv[1])
case = jio.load_case(str(root / "tests/data/gearbox/two-stage-gearbox.toml"))
form = case.form
plan = {"steps_per_period": 32, "periods": 4, "keep_periods": 2, "mean_positions": 32}
speeds = [60.0, 120.0]
run = gb.GearboxRun(form.stages[0].input_torque, 5e5, **plan)
out = gb.gearbox_speed_sweep(form.coupled(), run, np.asarray(speeds))
commit = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True, text=True,
                        check=True).stdout.strip()
data = {"case": "tests/data/gearbox/two-stage-gearbox.toml", "commit": commit, "plan": plan,
        "input_torque_Nm": float(form.stages[0].input_torque), "output_hold_Nm_per_rad": 5e5,
        "input_speeds_rad_s": speeds,
        "mesh_names": list(gb.mesh_names(form.coupled())),
        "dynamic_factors": np.asarray(out.dynamic_factors).tolist(),
        "static_forces_N": np.asarray(out.static_forces).tolist(),
        "steps": np.asarray(out.steps).tolist(), "result": np.asarray(out.result).tolist()}
pathlib.Path(sys.argv[2]).write_text(json.dumps(data, indent=1) + "\n")
print("ok", data["dynamic_factors"])
