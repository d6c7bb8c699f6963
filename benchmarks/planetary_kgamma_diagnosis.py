"""The first diagnostic: which part of the dynamic K_γ and DF of ``nrel-5mw-planetary``
at quasi-static speeds is the engagement stiffness step's ringing and which is not.

At one low input speed (default 0.25 rad/s) :func:`jaxgear.planetary.planetary_dynamics` runs
the case's dynamic model (:func:`jaxgear.io.build_dynamic_model`: planar, ContactMeshes, the
20 µm pin error) at several step counts, and each planet's sun-mesh force history is compared
with :func:`jaxgear.planetary.planetary_quasi_static` at the same mesh travels: the per-instant
K_γ (max_t max_j F_j / mean_j F_j, the run's definition), the time-mean shares, each planet's
DF, the forces of the other planets at the peak, and the mesh stiffness ratio across the
engagement step (the force jump F k_after / k_before that an instantaneous stiffness step
gives at continuous deflection). Then the same with ConstantMeshes (no stiffness step) and
without the pin error.

Usage: python benchmarks/planetary_kgamma_diagnosis.py [speed_rad_s] [steps ...]
(default 0.25 rad/s, 768 3072 12288 steps per mesh period; 3 periods, the last 2 kept, as the
automatic plan of ``jaxgear run``). Each run ~10-60 s on one CPU core.
"""
import sys
import time

import jax

jax.config.update("jax_enable_x64", True)
import numpy as np

from jaxgear.io import build_dynamic_model, load_case
from jaxgear.planetary import (
    ConstantMeshes,
    PlanetaryRun,
    planetary_dynamics,
    planetary_quasi_static,
)

PERIODS, KEEP = 3, 2


def report(tag, m, meshes, speed, steps, pin=True):
    run = m.run
    zero = np.zeros_like(np.asarray(run.tangential_pin_errors))
    t_err = run.tangential_pin_errors if pin else zero
    r_err = run.radial_pin_errors if pin else zero
    r = PlanetaryRun(run.sun_torque, steps_per_period=steps, periods=PERIODS, keep_periods=KEEP,
                     damping_ratio=run.damping_ratio, tangential_pin_errors=t_err,
                     radial_pin_errors=r_err)
    t0 = time.perf_counter()
    d = planetary_dynamics(m.kind, m.stage, meshes, r, m.carrier_per_input * speed,
                           m._mesh_speed(speed), ring=m.ring)
    f = np.asarray(d.sun_mesh_forces)
    fs = float(d.static_force)
    q = planetary_quasi_static(m.kind, m.stage, meshes, run.sun_torque, d.travel, t_err, r_err,
                               ring=m.ring)
    fq = np.asarray(q.sun_mesh_forces)
    ratio = f.max(1) / f.mean(1)
    k = int(np.argmax(ratio))
    print(f"[{tag}] S={steps}: {time.perf_counter() - t0:.1f} s, result {int(d.result)}")
    print(f"  dynamic: K_γ per instant {ratio.max():.4f} | time-mean shares "
          f"{np.round(f.mean(0) / f.mean(), 4)} | max_j max_t F_j / max_t mean F "
          f"{f.max() / f.mean(1).max():.4f} | DF per planet {np.round(f.max(0) / fs, 4)} | "
          f"median/F0 {np.round(np.median(f, 0) / fs, 4)}")
    print(f"    at the K_γ instant: F/F0 = {np.round(f[k] / fs, 4)} (quasi-static there "
          f"{np.round(fq[k] / fs, 4)}); peak-based K_γ max_j DF_j / mean_j DF_j "
          f"{np.max(f.max(0)) / np.mean(f.max(0)):.4f}")
    # where each planet's peak falls: steps after its sun mesh's stiffness steps up
    k_s, _ = (np.asarray(a) for a in meshes.mesh_stiffness(m.kind, m.stage, d.travel))
    for j in range(f.shape[1]):
        ups = np.flatnonzero(k_s[1:, j] > k_s[:-1, j] * (1 + 1e-6)) + 1
        p = int(np.argmax(f[:, j]))
        lag = p - ups[ups <= p].max() if np.any(ups <= p) else None
        print(f"    planet {j}: peak at step {p}, {lag} steps after its sun mesh's stiffness "
              f"step up (x{k_s[p, j] / k_s[p - 1, j] if lag == 0 else float('nan'):.3f} there); "
              f"F/F0 one step before {f[p - 1, j] / fs:.4f}" if p > 0 else "")
    print(f"  quasi-static: K_γ per instant {np.max(fq.max(1) / fq.mean(1)):.4f} | shares "
          f"{np.round(fq.mean(0) / fq.mean(), 4)} | max/F0 {np.round(fq.max(0) / fs, 4)} | "
          f"max|dyn - qs|/F0 {np.abs(f - fq).max() / fs:.4f} | "
          f"|time-mean dyn - qs|/F0 {np.abs(f.mean(0) - fq.mean(0)).max() / fs:.2e}")
    return d, q


def stiffness_step(m, meshes, per_period=4096):
    """Each sun mesh's stiffness over a mesh period: the largest jump k_after / k_before."""
    x = meshes.positions(per_period, 1)
    k_s, k_r = (np.asarray(a) for a in meshes.mesh_stiffness(m.kind, m.stage, x))
    for name, k in (("sun", k_s), ("ring", k_r)):
        j = np.roll(k[:, 0], -1) / k[:, 0]
        print(f"  {name} mesh stiffness: min {k[:, 0].min():.4g} max {k[:, 0].max():.4g} N/m, "
              f"largest step up k_after/k_before {j.max():.4f}, down {j.min():.4f}")


def main():
    speed = float(sys.argv[1]) if len(sys.argv) > 1 else 0.25
    steps = [int(s) for s in sys.argv[2:]] or [768, 3072, 12288]
    case = load_case("nrel-5mw-planetary")
    m, _ = build_dynamic_model(case)
    print(f"{type(m.kind).__name__}, {type(m.meshes).__name__}, {type(m.ring).__name__}, "
          f"pin errors {np.asarray(m.run.tangential_pin_errors)} m, T_s {float(m.run.sun_torque):.6g} "
          f"N m, sun bearing {np.asarray(m.stage.sun.bearing_stiffness)} N/m, speed {speed} rad/s, "
          f"mesh period {float(m.mesh_period_angle()) / speed:.4g} s")
    stiffness_step(m, m.meshes)
    for s in steps:
        report("contact meshes, pin error", m, m.meshes, speed, s)
    s = steps[-1]
    report("contact meshes, no pin error", m, m.meshes, speed, s, pin=False)
    const = ConstantMeshes(m.meshes.mesh_period())
    report("constant meshes, pin error", m, const, speed, s)
    return m


if __name__ == "__main__":
    main()
