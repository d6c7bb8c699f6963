"""Records tests/data/gearbox/coupled_sweep_reference.json: the coupled NREL 5 MW gearbox's
sweep by jaxgear.gearbox.gearbox_speed_sweep as it was before the gearbox became a
jaxgear.dynamics model (run from that commit; tests/test_gearbox_model.py compares the model's
speed_sweep with it to 1e-9), re-recorded after deliberate changes of the physics (the test's
docstring says which). Explicit plan: a few speeds, few steps and blocks (cheap).

    PYTHONPATH=$PWD python tests/data/gearbox/record_coupled_sweep.py
"""

import json
import pathlib
import subprocess

import jax
import numpy as np

jax.config.update("jax_enable_x64", True)

import jaxgear.io as jio  # noqa: E402
from jaxgear import gearbox as gb  # noqa: E402

#: the plan of the record (GearboxRun's explicit steps and blocks) and the input speeds'
#: fractions of the first stage's rated input speed
PLAN = {"steps_per_period": 16, "periods": 4, "keep_periods": 2, "mean_positions": 16}
FRACTIONS = [0.4, 1.0]
#: the recorded steps kept in the file: every STRIDE-th
STRIDE = 32


def main():
    form = jio.load_case("nrel-5mw-gearbox").form
    chain, first = form.coupled(), form.stages[0]
    hold = form.stages[-1].shaft_stiffness
    run = gb.GearboxRun(first.input_torque, hold, **PLAN)
    speeds = first.input_speed * np.asarray(FRACTIONS)
    out = gb.gearbox_speed_sweep(chain, run, speeds)
    commit = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                            cwd=pathlib.Path(__file__).parent).stdout.strip()
    record = {
        "case": "nrel-5mw-gearbox",
        "commit": commit,
        "plan": PLAN,
        "input_torque_Nm": float(first.input_torque),
        "output_hold_Nm_per_rad": float(hold),
        "input_speeds_rad_s": speeds.tolist(),
        "dynamic_factors": np.asarray(out.dynamic_factors).tolist(),
        "static_forces_N": np.asarray(out.static_forces).tolist(),
        # every STRIDE-th recorded step (the record small)
        "record_stride": STRIDE,
        "mesh_forces_N": np.asarray(out.mesh_forces)[:, ::STRIDE].tolist(),
        "time_s": np.asarray(out.time)[:, ::STRIDE].tolist(),
        "mesh_speeds_m_s": np.asarray(out.mesh_speeds).tolist(),
        "steps": np.asarray(out.steps).tolist(),
        "result": np.asarray(out.result).tolist(),
    }
    path = pathlib.Path(__file__).parent / "coupled_sweep_reference.json"
    path.write_text(json.dumps(record) + "\n", encoding="utf-8")
    print(path, np.asarray(out.dynamic_factors), np.asarray(out.mesh_forces).shape)


if __name__ == "__main__":
    main()
