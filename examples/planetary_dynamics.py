"""A planetary stage from real pairs (19/17/-53, m 3 mm, three planets, ring held): its meshes'
stiffness over the mesh period, the quasi-static load sharing with a planet-pin error, the
carrier-frame dynamics over a speed range (dynamic factor and dynamic load sharing per mesh),
the net mesh force on the sun for sequentially phased and in-phase planets, and the spectrum
of a transducer fixed on the ring (docs/planetary.md, "Meshes from real contact", "Dynamics in
the carrier frame").

Writes docs/img/planetary-dynamics.png and docs/bench/planetary_dynamics.json. Run from the
repository root: ``python examples/planetary_dynamics.py`` (a few minutes on 2 loaded cores,
mostly compilation).
"""

from __future__ import annotations

import json
import pathlib

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import jaxgear as jg  # noqa: E402
import jaxgear.planetary as jp  # noqa: E402

ROOT = pathlib.Path(__file__).parents[1] / "docs"
MODULE, ALPHA, WIDTH, DENSITY = 3e-3, np.radians(20.0), 0.03, 7850.0
HELD = 1e10  # the ring held by its housing (N/m on x, y and on u = r theta): stiff, but
# resolved by the steps (a 1e13 support rings undamped under average acceleration)
TORQUE = 800.0  # N m on the sun


def stage_of(z_s, z_p, x_s, x_p, n):
    """The pairs (planetary_geometry), the lumped members (solid steel discs, a ring of 4
    modules of rim, a carrier plate), the stage and its contact meshes (ISO 6336 stiffness,
    a 10 um linear tip relief on each pair)."""
    z_r = z_s + 2 * z_p
    geo = jg.planetary_geometry(
        jg.Member(z_s, profile_shift=x_s, face_width=WIDTH),
        jg.Member(z_p, profile_shift=x_p, face_width=WIDTH),
        jg.Member(-z_r, profile_shift=-(x_s + 2 * x_p), face_width=WIDTH),
        MODULE,
        ALPHA,
    )
    r_s, r_p = geo.sun_planet.base_radii
    r_r, a = geo.planet_ring.base_radii[1], geo.center_distance

    def disc(r):
        m = DENSITY * np.pi * r**2 * WIDTH
        return m, 0.5 * m * r**2

    m_s, i_s = disc(geo.sun_planet.pitch_radii[0])
    m_p, i_p = disc(geo.sun_planet.pitch_radii[1])
    r_in, r_out = z_r * MODULE / 2, z_r * MODULE / 2 + 4 * MODULE
    m_r = DENSITY * np.pi * (r_out**2 - r_in**2) * WIDTH
    m_c, i_c = disc(a + 1.2 * r_p)
    member = jp.PlanetaryMember
    stage = jp.PlanetaryStage.equally_spaced(
        n,
        sun=member(m_s, i_s, r_s, 1e8, 0.0),  # a flexibly supported sun
        ring=member(m_r, 0.5 * m_r * (r_in**2 + r_out**2), r_r, HELD, HELD * r_r**2),
        carrier=member(m_c, i_c, a, 1e9, 1e9 * a**2),
        planet=member(m_p, i_p, r_p, 5e8, 0.0),
        sun_pressure_angle=geo.sun_pressure_angle,
        ring_pressure_angle=geo.ring_pressure_angle,
        sun_mesh_stiffness=4e8,
        ring_mesh_stiffness=4e8,
    )
    tip = jg.MemberModification(tip_relief_depth=10e-6, tip_relief_extent=0.3)
    mods = jg.Modifications(tip, tip)
    meshes = jp.ContactMeshes.from_geometry(
        geo, stage.planet_angles, jg.ISO6336(), n_slices=1, modifications=(mods, mods)
    )
    return geo, stage, meshes


def net_sun_force(forces, psi_s, harmonic, periods):
    """|net force| and |net torque| / r_bs on the sun at a mesh harmonic, from the sun-mesh
    forces (t, n) over ``periods`` whole mesh periods, each over N times one mesh's harmonic."""
    fx, fy = forces @ np.sin(psi_s), -(forces @ np.cos(psi_s))

    def h(y):
        return np.abs(np.fft.rfft(y, axis=0)[harmonic * periods]) / y.shape[0]

    one = h(forces[:, 0])
    n = forces.shape[1]
    return float(np.hypot(h(fx), h(fy)) / (n * one)), float(h(forces.sum(1)) / (n * one))


KEEP = 4  # recorded mesh periods


def main(out_dir: pathlib.Path = ROOT) -> dict:
    model = jp.PlanarPlanetary()
    geo, stage, meshes = stage_of(19, 17, 0.3, 0.3, 3)
    p_b = float(meshes.mesh_period())
    r_r = float(stage.ring.base_radius)
    out = {"stage": "19/17/-53, m 3 mm, b 30 mm, 3 planets, ring held", "torque_Nm": TORQUE}
    # 1. mesh stiffness over a mesh period, phased
    x = meshes.positions(48)
    k_s, k_r = jp.planetary_mesh_stiffness(model, stage, meshes, x)
    # 2. quasi-static load sharing with a 30 um tangential pin error on planet 1
    errors = np.array([-30e-6, 0.0, 0.0])
    qs = jp.planetary_quasi_static(model, stage, meshes, np.asarray(TORQUE), x, errors)
    qs0 = jp.planetary_quasi_static(model, stage, meshes, np.asarray(TORQUE), x, np.zeros(3))
    out["quasi_static"] = {
        "k_gamma_no_error": float(qs0.k_gamma_max),
        "k_gamma_pin_error_30um": float(qs.k_gamma_max),
        "sun_te_ptp_um": float(np.ptp(np.asarray(qs0.sun_te)[:, 0]) * 1e6),
    }
    # 3. speed sweep (mesh frequency over the first modes)
    modes = jp.planetary_modes(model, stage)
    f_mesh = np.linspace(300.0, 6000.0, 24)
    speeds = jnp.asarray(f_mesh * p_b / r_r)
    # steps per period a multiple of N: the planets' phases fall on steps, so that the discrete
    # system keeps the stage's cyclic symmetry (else Newmark's first-order error at the stiffness
    # jumps differs from planet to planet)
    run = jp.PlanetaryRun(TORQUE, steps_per_period=96, periods=80, keep_periods=KEEP,
                          damping_ratio=0.04, tangential_pin_errors=errors)
    sweep = jp.planetary_speed_sweep(model, stage, meshes, run, speeds)
    df_s, df_r = (np.asarray(d) for d in sweep.dynamic_factors)
    k_dyn = np.asarray(sweep.k_gamma)
    assert np.all(np.asarray(sweep.result) == 0)
    i_max = int(np.argmax(df_s.max(1)))
    out["sweep"] = {
        "mesh_frequency_Hz": f_mesh.tolist(),
        "sun_mesh_df_max": df_s.max(1).tolist(),
        "ring_mesh_df_max": df_r.max(1).tolist(),
        "k_gamma_dynamic": k_dyn.tolist(),
        "worst": {"mesh_frequency_Hz": float(f_mesh[i_max]),
                  "df": float(df_s[i_max].max()), "k_gamma": float(k_dyn[i_max])},
        "natural_frequencies_Hz_mean_stiffness_4e8": np.asarray(modes.frequencies)[:8].tolist(),
    }
    # 4. net mesh force on the sun, sequential (19/3) against in phase (20/16/-52, 4 planets),
    # at a mesh frequency where every mesh stays in contact
    cancel = {}
    f_demo = 1500.0
    run1 = jp.PlanetaryRun(TORQUE, steps_per_period=96, periods=200, keep_periods=KEEP,
                           damping_ratio=0.04)
    for name, (z_s, z_p, x_s, x_p, n) in {"sequential 19/17/-53 N=3": (19, 17, 0.3, 0.3, 3),
                                          "in phase 20/16/-52 N=4": (20, 16, 0.2, 0.2, 4)}.items():
        g, st, ms = stage_of(z_s, z_p, x_s, x_p, n)
        omega = f_demo * float(ms.mesh_period()) / float(st.ring.base_radius)
        d = jp.planetary_dynamics(model, st, ms, run1, jnp.asarray(omega))
        psi_s = np.asarray(st.planet_angles) - g.sun_pressure_angle
        f = np.asarray(d.sun_mesh_forces)
        rows = {}
        for ell in (1, 2, 3, 4):
            force, torque = net_sun_force(f, psi_s, ell, KEEP)
            rows[ell] = {"net_force": force, "net_torque": torque,
                         "rule": jp.phasing_excites(z_s, n, ell).value}
        cancel[name] = rows
        cancel[name]["min_mesh_force_N"] = float(min(f.min(), np.asarray(d.ring_mesh_forces).min()))
    out[f"net_sun_force_at_{f_demo:.0f}Hz"] = cancel
    # 5. the ring transducer over one carrier turn (z_r mesh periods)
    z_r, per = 53, 48
    run2 = jp.PlanetaryRun(TORQUE, steps_per_period=per, periods=z_r + 200, keep_periods=z_r,
                           damping_ratio=0.04)
    omega = f_demo * p_b / r_r
    d = jp.planetary_dynamics(model, stage, meshes, run2, jnp.asarray(omega))
    theta_c = np.asarray(d.time) * omega
    y = jp.ring_transducer_signal(d.ring_mesh_forces, jnp.asarray(theta_c), stage.planet_angles)
    orders, amp = jp.order_spectrum(y, per * z_r)
    band = (orders > z_r - 12) & (orders < z_r + 12)
    top = np.argsort(amp * band)[::-1][:6]
    out["transducer"] = {
        "mesh_frequency_Hz": f_demo,
        "largest_orders_near_mesh_order": [int(round(orders[i])) for i in top],
        "their_amplitudes_N": [float(amp[i]) for i in top],
        "amplitude_at_mesh_order_53_N": float(amp[z_r]),
        "largest_off_multiple_of_3_N": float(amp[(np.rint(orders) % 3 != 0) & band].max()),
    }

    fig, ax = plt.subplots(2, 2, figsize=(12, 8))
    xs = np.asarray(x) / p_b
    for n in range(3):
        ax[0, 0].plot(xs, np.asarray(k_s)[:, n] * 1e-6, label=f"k_s{n + 1}")
        ax[0, 0].plot(xs, np.asarray(k_r)[:, n] * 1e-6, "--", label=f"k_r{n + 1}")
    ax[0, 0].set(xlabel="mesh travel / base pitch", ylabel="mesh stiffness (N/um)",
                 title="mesh stiffness per planet (ISO 6336 cells, phased)")
    ax[0, 0].legend(fontsize=7, ncol=2)
    for n in range(3):
        ax[0, 1].plot(xs, np.asarray(qs.sun_mesh_forces)[:, n] * 1e-3, label=f"planet {n + 1}")
    ax[0, 1].set(xlabel="mesh travel / base pitch", ylabel="sun-mesh force (kN)",
                 title=f"quasi-static, 30 um pin error on planet 1: K_gamma "
                       f"{float(qs.k_gamma_max):.3f}")
    ax[0, 1].legend(fontsize=8)
    ax[1, 0].plot(f_mesh, df_s.max(1), "o-", label="sun meshes, max DF")
    ax[1, 0].plot(f_mesh, df_r.max(1), "s-", label="ring meshes, max DF")
    ax[1, 0].plot(f_mesh, k_dyn, "^-", label="dynamic K_gamma")
    ax[1, 0].set(xlabel="mesh frequency (Hz)", ylabel="factor (-)",
                 title="carrier-frame Newmark, planar model")
    ax[1, 0].legend(fontsize=8)
    sel = (orders > z_r - 25) & (orders < z_r + 25)
    ax[1, 1].stem(orders[sel], amp[sel], basefmt=" ")
    ax[1, 1].set_yscale("log")
    for k in range(z_r - 24, z_r + 25):
        if k % 3 == 0:
            ax[1, 1].axvline(k, color="0.85", lw=0.6, zorder=0)
    ax[1, 1].axvline(z_r, color="r", ls="--", lw=0.8, label="mesh order z_r = 53")
    ax[1, 1].set(xlabel="order (carrier turns)", ylabel="amplitude (N)",
                 title=f"ring transducer at {f_demo:.0f} Hz mesh: lines at multiples of N = 3")
    ax[1, 1].legend(fontsize=8)
    fig.tight_layout()
    (out_dir / "img").mkdir(parents=True, exist_ok=True)
    fig.savefig(out_dir / "img" / "planetary-dynamics.png", dpi=110)
    (out_dir / "bench").mkdir(parents=True, exist_ok=True)
    (out_dir / "bench" / "planetary_dynamics.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
