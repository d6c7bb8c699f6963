"""Cost of a carrier-frame Newmark step of a helical planetary stage, the 3D lumped model
(jaxgear.SpatialPlanetary: 6 (3 + N) coordinates, cells at their contact points, the spin's
gyroscopic moments) against the planar model (3 (3 + N)) on the same cells, in one run so that
the ratio shares the machine's load.

Each model: one call to compile, then two runs of P1 and P2 mesh periods (best of three); the
step cost is the difference of their times (wall and process CPU) over the difference of their
step counts, so that compilation drops out. Writes docs/bench/planetary_spatial_step.json. Run
from the repository root: ``python benchmarks/planetary_spatial_step.py``.
"""

from __future__ import annotations

import json
import os
import pathlib
import platform
import subprocess
import time

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

import jaxgear as jg  # noqa: E402
import jaxgear.dynamics as jd  # noqa: E402

OUT = pathlib.Path(__file__).parents[1] / "docs" / "bench" / "planetary_spatial_step.json"
MODULE, ALPHA, WIDTH, HELD = 3e-3, np.radians(20.0), 0.03, 1e13
HELIX, SLICES = np.radians(15.0), 4
STEPS, P1, P2 = 64, 20, 220


def stage():
    """19/17/-53, 3 planets, beta 15 deg, Uniform stiffness, every support given."""
    geo = jg.planetary_geometry(
        jg.Member(19, profile_shift=0.3, face_width=WIDTH),
        jg.Member(17, profile_shift=0.3, face_width=WIDTH),
        jg.Member(-53, profile_shift=-0.9, face_width=WIDTH),
        MODULE, ALPHA, HELIX,
    )
    r_s, r_p = geo.sun_planet.base_radii
    r_r, a = geo.planet_ring.base_radii[1], geo.center_distance
    member = jg.PlanetaryMember
    kw = {"axial_stiffness": 3e8, "tilt_stiffness": 4e5}
    st = jg.PlanetaryStage.equally_spaced(
        3,
        sun=member(1.2, 0.4 * 1.2 * r_s**2, r_s, 1e9, 0.0, **kw),
        ring=member(6.0, 6.0 * r_r**2, r_r, 1e9, HELD * r_r**2, **kw),
        carrier=member(5.0, 2.5 * a**2, a, 1e9, HELD * a**2, **kw),
        planet=member(0.8, 0.4 * r_p**2, r_p, 5e8, 0.0, **kw),
        sun_pressure_angle=geo.sun_pressure_angle,
        ring_pressure_angle=geo.ring_pressure_angle,
        sun_mesh_stiffness=5e8,
        ring_mesh_stiffness=5e8,
        helix_angle=abs(float(geo.sun_planet.base_helix_angle)),
        face_width=WIDTH,
    )
    meshes = jg.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(1.4e10),
                                            n_slices=SLICES)
    return st, meshes


def timed(fn):
    t0, c0 = time.perf_counter(), time.process_time()
    jax.block_until_ready(fn())
    return time.perf_counter() - t0, time.process_time() - c0


def main(out: pathlib.Path = OUT) -> dict:
    st, meshes = stage()
    omega = jnp.asarray(600.0)
    rows = []
    for model in (jg.PlanarPlanetary(), jg.SpatialPlanetary()):
        runs = {p: jd.PlanetaryRun(1000.0, steps_per_period=STEPS, periods=p, keep_periods=1)
                for p in (P1, P2)}
        first = timed(lambda r=runs[P1]: jd.planetary_dynamics(model, st, meshes, r, omega))
        timed(lambda r=runs[P2]: jd.planetary_dynamics(model, st, meshes, r, omega))
        best = {p: min(timed(lambda r=r: jd.planetary_dynamics(model, st, meshes, r, omega))
                       for _ in range(3)) for p, r in runs.items()}
        steps = (P2 - P1) * STEPS
        rows.append({
            "model": type(model).__name__,
            "coordinates": int(model.mass_matrix(st).shape[0]),
            "cells": int(meshes.cell_row(model, st, jnp.asarray(0.0),
                                         (jnp.zeros(3), jnp.zeros(3))).k.shape[0]),
            "step_wall_us": (best[P2][0] - best[P1][0]) / steps * 1e6,
            "step_cpu_us": (best[P2][1] - best[P1][1]) / steps * 1e6,
            "first_call_wall_s": first[0],
            "first_call_cpu_s": first[1],
        })
        print(rows[-1], flush=True)
    lscpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    result = {
        "what": "carrier-frame Newmark step of a helical planetary stage, 3D lumped model "
                "against the planar one on the same contact cells (exact contact), cost per "
                f"step from runs of {P1} and {P2} mesh periods of {STEPS} steps, one speed",
        "stage": f"19/17/-53, m 3 mm, b 30 mm, beta 15 deg, Uniform k0, {SLICES} slices, "
                 "3 planets, 600 rad/s",
        "cpu_ratio_3d_to_planar": rows[1]["step_cpu_us"] / rows[0]["step_cpu_us"],
        "wall_ratio_3d_to_planar": rows[1]["step_wall_us"] / rows[0]["step_wall_us"],
        "machine": {
            "platform": platform.platform(),
            "cpu_count": os.cpu_count(),
            "lscpu_model": next((ln.split(":", 1)[1].strip() for ln in lscpu.splitlines()
                                 if ln.startswith("Model name")), None),
            "load_average_1_5_15": list(os.getloadavg()),
            "device": str(jax.devices()[0]),
        },
        "dtype": "float64",
        "jax": jax.__version__,
        "rows": rows,
    }
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=2) + "\n")
    return result


if __name__ == "__main__":
    main()
