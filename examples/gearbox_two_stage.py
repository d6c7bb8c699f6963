"""The two-stage coupled gearbox of docs/gearbox.md: a planetary stage (ring held, carrier in,
sun out) whose sun drives a parallel spur pair through a shaft, both on their contact cells in one
Newmark run (jaxgear.gearbox.gearbox_dynamics, each speed with the automatic time plan: at
least 40 steps per period of the highest mode the meshes excite, the settling time of the
slowest decaying excited mode), every mesh's dynamic factor against the carrier speed, and the coupled modes with the
mesh holding most strain energy (a few minutes on a laptop).

Writes docs/img/gearbox-two-stage.png. Run from the repository root:

    python examples/gearbox_two_stage.py
"""

import pathlib

import jax
import matplotlib
import numpy as np

import jaxgear as jg
import jaxgear.planetary as jp
from jaxgear import gearbox as gb

jax.config.update("jax_enable_x64", True)

MODULE, ALPHA = 4e-3, np.radians(20.0)
K_U = 1.4e10  # N/m per m of contact line, every mesh


def two_stage(shaft=5e5, output=5e5, torque=5000.0, slices=1, **run):
    """(chain, run): stage 1 planetary 20/30/-80, 4 planets, b 50 mm; shaft; stage 2 pair
    32 (in) / 24 (out), b 80 mm; ``run``: GearboxRun's integration keywords."""
    b1, b2 = 0.05, 0.08
    # the planet cut by a deeper rack (h_f* 1.3): its involute reaches low enough for the
    # ring's standard tip (jaxgear refuses the interference at 1.25); the tips, so the contact
    # ratios (1.605, 1.938), are the standard ones
    geo = jg.planetary_geometry(jg.Member(20, face_width=b1), jg.Member(30, face_width=b1, dedendum_coeff=1.3),
                                jg.Member(-80, face_width=b1), MODULE, ALPHA)
    psi = 2 * np.pi * np.arange(4) / 4
    meshes = jp.ContactMeshes.from_geometry(geo, psi, jg.Uniform(K_U), slices)
    r_s, r_p = (float(r) for r in geo.sun_planet.base_radii)
    r_r = float(geo.planet_ring.base_radii[1])
    member = jp.PlanetaryMember
    k_mesh = K_U * b1 * 1.5  # a nominal constant stiffness (the chain's torsional modes only)
    stage = jp.PlanetaryStage(
        sun=member(1.0, 1.6e-3, r_s), ring=member(10.0, 2.0, r_r, torsional_stiffness=1e9),
        carrier=member(10.0, 0.5, 0.1), planet=member(4.44, 8.0e-3, r_p),
        planet_angles=psi, sun_pressure_angle=geo.sun_pressure_angle,
        ring_pressure_angle=geo.ring_pressure_angle, sun_mesh_stiffness=k_mesh,
        ring_mesh_stiffness=k_mesh)
    planetary = gb.PlanetaryGearboxStage(stage, jp.Central.CARRIER, jp.Central.SUN, meshes)
    pair = jg.GearPair(jg.Member(24, face_width=b2), jg.Member(32, face_width=b2), MODULE, ALPHA)
    mesh = jg.MeshModel.from_pair(pair, *jg.stiffness_table(pair, jg.Uniform(K_U)), slices)
    parallel = gb.TorsionalPairGearboxStage((5.2e-3, 0.0165), pair.base_radii, K_U * b2 * 1.6,
                                            input=1, mesh=mesh)
    chain = gb.GearboxTorsional((planetary, parallel), [shaft])
    return chain, gb.GearboxRun(torque, output, **run)


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    matplotlib.use("Agg")
    chain, run = two_stage(steps_per_period=None, periods=None, keep_periods=1)
    speeds = np.linspace(20.0, 160.0, 15)  # carrier, rad/s
    df = np.array([gb.gearbox_dynamics(chain, run, w).dynamic_factors for w in speeds])
    for w, row in zip(speeds, df, strict=True):
        print(f"{w:6.1f} rad/s: DF sun-planet {row[0]:.4f}, ring-planet {row[4]:.4f}, "
              f"pair {row[8]:.4f}")
    names = gb.mesh_names(chain)
    modes = gb.coupled_mode_table(chain, gb.gearbox_coupled_modes(chain, run))
    for row in modes:
        print(f"{row['frequency_Hz']:9.1f} Hz  {row['type']:<12} {row['mesh']}")
    fig, ax = plt.subplots(figsize=(7, 4))
    for j, style in ((0, "o-"), (4, "s--"), (8, "^-")):  # the planets' meshes coincide
        ax.plot(speeds, df[:, j], style, ms=3, label=names[j] + (" (every planet)" if j < 8
                                                                  else ""))
    ax.set_xlabel("carrier speed (rad/s)")
    ax.set_ylabel("dynamic factor (max / static)")
    ax.set_title("two-stage gearbox, coupled: planetary stage + spur pair")
    ax.legend()
    path = pathlib.Path(__file__).resolve().parents[1] / "docs" / "img" / "gearbox-two-stage.png"
    fig.savefig(path, dpi=110, bbox_inches="tight")
    print(f"wrote {path}")
