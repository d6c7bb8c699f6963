"""Cost of a carrier-frame Newmark step of a planetary stage against its number of planets
(3 to 6), the planar model (3 (3 + N) coordinates) with every mesh's contact cells
(jaxgear.planetary.planetary_dynamics), in one run so that the ratios share the machine's load.

Each N: one call to compile, then two runs of P1 and P2 mesh periods; the step cost is the
difference of their times (wall and process CPU) over the difference of their step counts, so
that compilation and the fixed costs drop out (benchmarks/_step_cost.py). Writes
docs/bench/planetary_step.json, the machine as benchmarks/_timing.py's ``environment()``. Run from
the repository root: ``python -m benchmarks.planetary_step``.
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

OUT = pathlib.Path(__file__).parents[1] / "docs" / "bench" / "planetary_step.json"
MODULE, ALPHA, WIDTH, HELD = 3e-3, np.radians(20.0), 0.03, 1e13
# z_s + z_p = 60: (z_s + z_r) = 120 planets assemble equally spaced for N = 3, 4, 5, 6, and six
# planets of 24 teeth still clear each other on the 90 mm planet circle
Z_S, Z_P = 36, 24
STEPS, P1, P2 = 64, 20, 420


def stage(n):
    geo = jg.planetary_geometry(
        jg.Member(Z_S, profile_shift=0.2, face_width=WIDTH),
        jg.Member(Z_P, profile_shift=0.2, face_width=WIDTH),
        jg.Member(-(Z_S + 2 * Z_P), profile_shift=-0.6, face_width=WIDTH),
        MODULE,
        ALPHA,
    )
    r_s, r_p = geo.sun_planet.base_radii
    r_r, a = geo.planet_ring.base_radii[1], geo.center_distance
    member = jp.PlanetaryMember
    st = jp.PlanetaryStage.equally_spaced(
        n,
        sun=member(2.0, 2.0 * r_s**2 / 2, r_s, 1e8, 0.0),
        ring=member(8.0, 8.0 * r_r**2, r_r, HELD, HELD * r_r**2),
        carrier=member(6.0, 3.0 * a**2, a, 1e9, 1e9 * a**2),
        planet=member(1.0, r_p**2 / 2, r_p, 5e8, 0.0),
        sun_pressure_angle=geo.sun_pressure_angle,
        ring_pressure_angle=geo.ring_pressure_angle,
        sun_mesh_stiffness=4e8,
        ring_mesh_stiffness=4e8,
    )
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.ISO6336(), n_slices=1)
    return st, meshes


def main(out: pathlib.Path = OUT) -> dict:
    machine = environment()
    model = jp.PlanarPlanetary()
    rows = []
    for n in (3, 4, 5, 6):
        st, meshes = stage(n)
        omega = jnp.asarray(2000.0 * float(meshes.mesh_period()) / float(st.ring.base_radius))
        cost = step_cost(model, st, meshes, omega, 800.0, STEPS, (P1, P2))
        rows.append({"planets": n, **cost})
        print(rows[-1], flush=True)
    base = rows[0]
    for r in rows:
        r["wall_ratio_to_3"] = r["step_wall_us"] / base["step_wall_us"]
        r["cpu_ratio_to_3"] = r["step_cpu_us"] / base["step_cpu_us"]
    result = {
        "what": "carrier-frame Newmark step of a planetary stage (planar model, contact cells "
                "of all 2N meshes, exact contact), cost per step from runs of "
                f"{P1} and {P2} mesh periods of {STEPS} steps",
        "stage": f"{Z_S}/{Z_P}/-{Z_S + 2 * Z_P}, m 3 mm, b 30 mm, ISO 6336 stiffness, 1 slice",
        "machine": machine,
        "rows": rows,
    }
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=1) + "\n")
    return result


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
