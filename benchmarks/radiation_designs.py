"""Radiated sound power per design (docs/acoustics.md, "Precompute, then differentiate" and
"Outputs"): the radiation resistance R of a box housing's closed outer skin by the exterior BEM
(bempp-cl, Burton–Miller) at a grid of frequencies, built once (its cost per frequency, the
numba compile apart), then the sound power W and its gradient with respect to a design (here
the housing's seat loads, the input the gear chain feeds it) in JAX: jit, vmap over designs,
at one speed, against re-solving the BEM for every design (the ratio, both measured in this
run). Then ``jaxgear run``'s acoustic outputs (acoustic_outputs) on the same housing over a
speed sweep with the R just cached: the figures copied to docs/img.

The housing: whine_erp's aluminium box (360 × 200 × 220 mm, 8 mm walls, four bores, two feet),
structured Tet10 mesh of 40 mm, Craig–Bampton to 4.5 kHz; its closed skin
(fem_prep.housing.closed_outer_surface: the bores capped) has 826 vertices (the 2-core machine, shared, sets the size).
From the repository root: ``python -m benchmarks.radiation_designs``; JSON to
docs/bench/radiation_designs.json.
"""

from __future__ import annotations

import json
import pathlib
import shutil
import sys
import tempfile
import time

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp
import numpy as np

import fem_prep
import fem_prep.acoustics as fa
from fem_prep.housing import closed_outer_surface, condensed_housing, mesh_box
from jaxgear.acoustics import housing_acoustics, housing_response, radiated_power_low_rank
from jaxgear.cli.run import acoustic_outputs

from ._timing import environment
from .whine_erp import housing_box

ROOT = pathlib.Path(__file__).resolve().parents[1]
ALUMINIUM = fem_prep.Material(70e9, 0.33, 2700.0)
MESH_SIZE = 0.04
CUTOFF_HZ = 4500.0
#: R's grid (Hz): the band the speed sweep's orders 1 and 2 cover
GRID = np.geomspace(200.0, 1600.0, 5)
#: the design frequency (a grid frequency: "one speed")
F_DESIGN = float(GRID[3])
BATCHES = (1, 100, 1000, 10000)
MICS = (("front", (0.18, -1.0, 0.11)), ("top", (0.18, 0.1, 1.22)))


def _timed(fn, repeats=5):
    jax.block_until_ready(fn())  # compile
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        jax.block_until_ready(fn())
        best = min(best, time.perf_counter() - t)
    return best


def main(argv=()) -> None:
    quick = "--quick" in argv
    dry = "--dry" in argv  # the ERP's R in place of the BEM's: the script's own check, no timing
    env = environment()
    t = time.perf_counter()
    mesh = mesh_box(housing_box(), MESH_SIZE)
    ch = condensed_housing(mesh, ALUMINIUM, CUTOFF_HZ, cache=False)
    skin = closed_outer_surface(mesh)
    surf = skin.surface
    t_housing = time.perf_counter() - t
    n = surf.n_vertices
    print(f"housing: {mesh.n_dofs} DOFs, {len(ch.modes_hz)} modes, skin {n} vertices "
          f"({len(skin.cap_vertices)} caps), {t_housing:.1f} s", flush=True)
    # the numba compile of bempp's kernels: the first solve of the process
    t = time.perf_counter()
    if not dry:
        fa.bem_impedance(fa.sphere_surface(1.0, 1), 100.0)
    t_compile = time.perf_counter() - t
    # one BEM solve (build and solve) at the design frequency, and R from it
    t = time.perf_counter()
    Z = (0.5 * fa.AIR.impedance * np.eye(n) if dry else fa.bem_impedance(surf, F_DESIGN))
    t_solve = time.perf_counter() - t
    t = time.perf_counter()
    MZ = surf.mass_matrix() @ Z
    R_direct = 0.25 * (MZ + MZ.conj().T)
    t_form = time.perf_counter() - t
    # R per frequency over the grid, the microphones' transfer with it (cached for the outputs)
    grid = GRID[:3] if quick else GRID
    points = np.array([p for _, p in MICS])
    t = time.perf_counter()
    rr = fa.radiation_resistance(surf, grid, method=fa.ERP() if dry else fa.BEM(),
                                 progress=True, points=None if dry else points)
    t_grid = time.perf_counter() - t
    k = int(np.argmin(np.abs(grid - F_DESIGN)))
    f = float(grid[k])
    lam = rr.eigenvalues[k]
    rank = int(np.searchsorted(-lam, -1e-6 * lam[0]))  # modes above 1e-6 of the first
    # the design → W map in JAX: seat loads θ → housing response → skin velocity → W
    ac = housing_acoustics(ch, skin.skin, loss_factor=0.02)
    Nv = jnp.asarray(skin.normal_operator @ ch.recovery)  # (n, n_c)
    nb = 6 * len(ch.seat_names)

    def velocity(theta):
        r = housing_response(ac, theta.astype(complex), f)
        return jnp.conj(2j * jnp.pi * f * (r.coordinates @ Nv.T))  # e^{iωt} → e^{-iωt}

    def make(L):
        def power(theta):
            return radiated_power_low_rank(velocity(theta), L)

        return jax.jit(jax.vmap(jax.value_and_grad(power)))

    L_full = jnp.asarray(rr.factors[k])
    L_r = jnp.asarray(rr.factors[k][:, :rank])
    # the radiation modes of the condensed coordinates: P = L^H Nv (r × n_c), design-free
    P = jnp.asarray(rr.factors[k][:, :rank].conj().T @ (skin.normal_operator @ ch.recovery))

    def power_projected(theta):
        r = housing_response(ac, theta.astype(complex), f)
        a = P @ jnp.conj(2j * jnp.pi * f * r.coordinates)
        return jnp.sum(jnp.abs(a) ** 2)

    variants = {"full_rank": make(L_full), f"rank_{rank}": make(L_r),
                f"rank_{rank}_projected": jax.jit(jax.vmap(jax.value_and_grad(power_projected)))}
    rng = np.random.default_rng(0)
    per_design = {}
    for name, fn in variants.items():
        per_design[name] = {}
        for B in BATCHES[:2] if quick else BATCHES[: 3 if name == "full_rank" else 4]:
            theta = jnp.asarray(100.0 * rng.normal(size=(B, nb)))
            s = _timed(lambda fn=fn, theta=theta: fn(theta), repeats=3)
            per_design[name][str(B)] = {"seconds": s, "designs_per_s": B / s}
        print(name, {b: round(v["designs_per_s"]) for b, v in per_design[name].items()},
              flush=True)
    # checks: the three forms agree; W by the direct R; the gradient by central differences
    theta = jnp.asarray(100.0 * rng.normal(size=(4, nb)))
    w_full, g_full = variants["full_rank"](theta)
    w_proj, _ = variants[f"rank_{rank}_projected"](theta)
    v0 = np.asarray(velocity(theta[0]))
    w_direct = float(np.real(v0.conj() @ R_direct @ v0)) if np.isclose(f, F_DESIGN) else None
    e = np.zeros(nb)
    e[2] = 1.0
    h = 1e-3
    fd = (variants["full_rank"](theta[:1] + h * e)[0] - variants["full_rank"](theta[:1] - h * e)[0])
    fd = float(fd[0]) / (2 * h)
    # the BEM route per design: one solve (build + solve) and the quadratic form
    t_bem_design = t_solve + t_form
    best = max(v["designs_per_s"] for d in per_design.values() for v in d.values())
    out = {
        "environment": env,
        "housing": {"dofs": int(mesh.n_dofs), "modes": int(len(ch.modes_hz)),
                    "condensed_coordinates": int(ch.K.shape[0]), "cutoff_Hz": CUTOFF_HZ,
                    "mesh_size_m": MESH_SIZE, "seconds_mesh_condense_skin": t_housing},
        "skin": {"vertices": n, "triangles": int(len(surf.triangles)),
                 "caps": int(len(skin.cap_vertices)), "area_m2": float(surf.areas.sum())},
        "bem": {"numba_compile_s": t_compile,
                "one_frequency_build_and_solve_s": t_solve,
                "frequencies": int(len(grid)), "grid_Hz": grid.tolist(),
                "grid_total_s": t_grid, "per_frequency_s": t_grid / len(grid),
                "note": "per frequency: the five operator assemblies (dense, numba), the "
                        "solve, R = (MZ + Z^H M)/4, its eigendecomposition and the "
                        "microphones' transfer"},
        "design_frequency_Hz": f,
        "radiation_modes_kept": rank,
        "designs": {"parameters": nb, "what": "W and dW/dθ per design (θ: the seat loads), "
                    "jit(vmap(value_and_grad))", "per_design": per_design},
        "bem_per_design_s": t_bem_design,
        "ratio_bem_per_design_over_jax_per_design": t_bem_design * best,
        "best_designs_per_s": best,
        "checks": {"W_full_over_projected": (np.asarray(w_full) / np.asarray(w_proj)).tolist(),
                   "W_full_over_direct_R": (None if w_direct is None
                                            else float(w_full[0]) / w_direct),
                   "dW_dtheta2_jax": float(g_full[0, 2]), "dW_dtheta2_central": fd},
    }
    # jaxgear run's acoustic outputs on the sweep: a 200 N radial force at seat 0 (order 1)
    # and 80 N (order 2), speeds putting the orders inside the grid
    if not quick:
        speeds = np.linspace(2 * np.pi * 220.0, 2 * np.pi * 780.0, 40)
        orders = np.array([1.0, 2.0])
        freq = orders[None, :] * speeds[:, None] / (2 * np.pi)
        loads = np.zeros((len(speeds), 2, nb), complex)
        loads[:, 0, 2], loads[:, 1, 2] = 200.0, 80.0
        r = housing_response(ac, jnp.asarray(loads), jnp.asarray(freq))
        vel = 2j * np.pi * freq[..., None] * (np.asarray(r.coordinates) @ np.asarray(Nv).T)
        table = {"method": "erp-only" if dry else "bem", "band_Hz": [float(grid[0]), float(grid[-1])],
                 "frequencies": len(grid),
                 "microphones": [] if dry else [
                     {"name": m, "position_mm": [1e3 * x for x in p]} for m, p in MICS]}
        with tempfile.TemporaryDirectory() as tmp:
            t = time.perf_counter()
            sec = acoustic_outputs(surf, vel, speeds, orders, tmp, table,
                                   name="box housing, seat 0 loaded", progress=True)
            out["acoustic_outputs_s_with_R_cached"] = time.perf_counter() - t
            for src in () if dry else ("sound_power.png", "microphones.png", "intensity.png"):
                shutil.copy(pathlib.Path(tmp) / "acoustics" / src,
                            ROOT / "docs" / "img" / f"acoustics_housing_{src}")
        out["acoustic_outputs"] = {"overall_LWA_dBA_max": float(np.nanmax(
            sec["overall_LWA_dBA"])), "map_speed_rad_s": sec["map_speed_rad_s"]}
    path = (pathlib.Path(tempfile.gettempdir()) / "radiation_designs_dry.json" if dry
            else ROOT / "docs" / "bench" / ("radiation_designs_quick.json" if quick
                                            else "radiation_designs.json"))
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(json.dumps({k: out[k] for k in ("bem", "best_designs_per_s",
                                          "ratio_bem_per_design_over_jax_per_design",
                                          "checks")}, indent=1))


if __name__ == "__main__":
    main(sys.argv[1:])
