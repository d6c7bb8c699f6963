"""Cost of a carrier-frame Newmark step of a helical planetary stage, the 3D lumped model
(jaxgear.planetary.SpatialPlanetary: 6 (3 + N) coordinates, cells at their contact points, the
spin's gyroscopic moments) against the planar model (3 (3 + N)) on the same cells, in one run so
that the ratio shares the machine's load.

Each model: one call to compile, then two runs of P1 and P2 mesh periods (best of three); the
step cost is the difference of their times (wall and process CPU) over the difference of their
step counts, so that compilation drops out (benchmarks/_step_cost.py). Writes
docs/bench/planetary_spatial_step.json, the machine as benchmarks/_timing.py's ``environment()``.
Run from the repository root: ``python -m benchmarks.planetary_spatial_step``.
"""

from __future__ import annotations

import json
import pathlib

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

import jaxgear as jg  # noqa: E402
import jaxgear.planetary as jp
from benchmarks._step_cost import step_cost  # noqa: E402
from benchmarks._timing import environment  # noqa: E402

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
    member = jp.PlanetaryMember
    kw = {"axial_stiffness": 3e8, "tilt_stiffness": 4e5}
    st = jp.PlanetaryStage.equally_spaced(
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
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(1.4e10),
                                            n_slices=SLICES)
    return st, meshes


def main(out: pathlib.Path = OUT) -> dict:
    machine = environment()
    st, meshes = stage()
    omega = jnp.asarray(600.0)
    rows = []
    for model in (jp.PlanarPlanetary(), jp.SpatialPlanetary()):
        rows.append({"model": type(model).__name__,
                     **step_cost(model, st, meshes, omega, 1000.0, STEPS, (P1, P2))})
        print(rows[-1], flush=True)
    result = {
        "what": "carrier-frame Newmark step of a helical planetary stage, 3D lumped model "
                "against the planar one on the same contact cells (exact contact), cost per "
                f"step from runs of {P1} and {P2} mesh periods of {STEPS} steps, one speed",
        "stage": f"19/17/-53, m 3 mm, b 30 mm, beta 15 deg, Uniform k0, {SLICES} slices, "
                 "3 planets, 600 rad/s",
        "cpu_ratio_3d_to_planar": rows[1]["step_cpu_us"] / rows[0]["step_cpu_us"],
        "wall_ratio_3d_to_planar": rows[1]["step_wall_us"] / rows[0]["step_wall_us"],
        "machine": machine,
        "rows": rows,
    }
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=2) + "\n")
    return result


if __name__ == "__main__":
    main()
