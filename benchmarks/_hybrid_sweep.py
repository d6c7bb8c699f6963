"""Benchmark of the hybrid speed sweep: Newmark in the cell space on the
accessory pair with its flexible wheel, against Newmark on all coordinates.

``bench_hybrid_sweep(out_dir)`` is the body of ``jaxgear bench hybrid-sweep``. In one run, on the
``accessory-spur-flexible`` case (the wheel the embedded ``accessory-wheel`` body: Craig–Bampton
with the 50 fixed-interface modes its body file asks for, condensed by fem_prep once and then
read from its cache), float64, exact contact, it measures:

(1) the sweep: ``n_speeds`` pinion speeds over the seed's range (100–3000 rad/s) with
    :func:`jaxgear.dynamics.speed_sweep` in chunks of speeds (the chunking of
    ``jaxgear sweep``, one progress step per chunk): total wall time (compile included) against
    the < 10 min target, compile time (first chunk − the same chunk again), per speed and per
    step;
(2) convergence of the dynamic factor in the number of integrated mesh periods: one run of two
    wheel revolutions per check speed with every step kept; DF(P) = the max mesh force over the
    ``keep_periods`` periods before period P, which is exactly what a run of P periods returns;
(3) the baseline at equal accuracy: the same equations (the same start state, K̄_m, damping,
    time step, contact law and active-set algorithm) written without the cell space, on all n
    coordinates, compiled (``jax.jit`` + ``lax.scan``, ``lax.map`` over speeds):
    "woodbury": K_eff Cholesky-factored once per speed, each step one ``cho_solve`` with the
    c + 1 right-hand sides [F_eff, Vᵀ] (the structure vectors of all c cells on all n
    coordinates), the active-set passes on the c×c matrix V K_eff⁻¹ Vᵀ, X = x* − K_eff⁻¹Vᵀ P;
    "refactor": the textbook form of the tests' reference, :func:`jaxgear.solve_contact` on
    K_eff (K_eff + Vᵀ diag(k l) V factored at every contact pass). The woodbury DF against the
    sweep's at a subset of its speeds, the first steps of both against the model's; the per-step
    cost of the three measured in one run at one speed (difference of two run lengths: the
    per-speed set-up cancels);
(4) per-step cost against the master-DOF count n at equal cells and equal window (the test
    wheel of ``tests/data/hybrid-test-wheel.toml`` condensed with more and more modes, and the
    case's own wheel; each window widened to one common width, as ``jaxgear bench hybrid``
    compares bodies), and against the cells (slices) at fixed n, for the model and the
    baselines, with least-squares fits t = t₀ + a xᵖ.

Writes ``bench_hybrid_sweep.json`` and ``bench_hybrid_sweep.png``. Benchmarks are not tests:
compile separated, warm-up, ``block_until_ready``, min of repeats; machine, dtype and versions
and the load average before and after recorded.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
import pathlib
import time

import numpy as np

from jaxgear.dynamics import Batching, ModalBasis, Newmark, SteadyState
from jaxgear.io import contact_law_from_name

from ._charts import thin_tick_labels
from ._hybrid import _cells, _flex_index, _window_dofs, _with_window, hybrid_cases
from ._timing import environment, min_time

__all__ = ["bench_hybrid_sweep"]

_TARGET_S = 600.0  # target: 100 speeds on the 2-core CPU in < 10 min
_SPEED_RANGE = (100.0, 3000.0)  # the seed's pinion speed range (rad/s)
_RAYLEIGH = (25.0, 2.5e-6)  # the seed's D1, dynamic_model's default for a hybrid scene
_TEST_CASE = (
    pathlib.Path(__file__).resolve().parents[1] / "tests" / "data" / "hybrid-test-case.toml"
)
_METHODS = ("model", "woodbury", "refactor")
_MODAL_MODES = 160  # the modal-basis sweep's modes (docs/bench/modal_basis.png: DF within 0.06 %)
_MODAL_TARGET_S = 60.0  # the aim: 100 speeds below 60 s, DF within 1 % of the cell space


# ------------------------------------------------------------------------------------------
# the baseline: Newmark on all coordinates


def _baseline_run(
    scene, mods, torque, speed, alpha, beta, width, spp, n_steps, mode, max_it, variant
):
    """Newmark (average acceleration) of the hybrid scene on all n coordinates: the equations of
    :func:`jaxgear.dynamics.speed_sweep` without the cell space. Returns the mesh force
    per step (N), the worst result code and the most contact passes in a step."""
    import jax
    import jax.numpy as jnp
    from jax.scipy.linalg import solve_triangular

    from jaxgear import quasi_static, separation, solve_contact, solve_contact_cells

    law = contact_law_from_name(mode, width, max_it)

    mesh = scene.mesh
    n = scene.structure.K.shape[0]
    dtype = scene.structure.K.dtype
    dth = mesh.mesh_period_angle / spp
    dt = dth / speed
    a0, a1 = 4.0 / (dt * dt), 2.0 / dt
    M, K = scene.structure.M, scene.structure.K
    # start state and period-averaged mesh stiffness: the quasi-static states at the step
    # positions of one mesh period (centrifugal load at this speed), K̄_m on all coordinates
    theta = (jnp.arange(spp) + 0.5) * dth
    qs = quasi_static(
        scene,
        mods,
        torque,
        theta,
        speed=speed,
        contact=law,
        throw=False,
    )

    def _vectors(cells):  # the model's cell vectors on all n coordinates, (c, n): beyond the
        # path each corner cell's less its part along the free drive rotation (the scene's
        # cell_row; on the theoretical path its cell_vectors)
        return scene.cell_row((cells,), (jnp.zeros_like(cells.s),)).V

    def mean_mesh(k):  # K̄_m of mesh period k: the wheel has turned k pitches under the mesh
        def add(Km, p):
            cells = mesh.cells(theta[p] + k * mesh.mesh_period_angle)
            V = _vectors(cells)
            kl = jnp.where(cells.mask, cells.stiffness * cells.length, 0.0).reshape(-1)
            w = (qs.line_load[p].reshape(-1) > 0).astype(dtype)
            return Km + V.T @ ((kl * w)[:, None] * V), None

        return jax.lax.scan(add, jnp.zeros((n, n), dtype), jnp.arange(spp))[0] / spp

    C0 = alpha * M + beta * K  # Rayleigh (2.34), plus the bearings' damping
    if hasattr(scene, "bearing_damping"):
        C0 = C0 + scene.bearing_damping()
    F = torque * scene.f_torque + speed**2 * scene.structure.f_centrifugal

    # one time-constant flank reference δ0 = e_ref − e, the start state moved along the drive
    # rotation N to match (as the model)
    e_max = jax.vmap(lambda th: separation(mesh, mods, th)[1])(theta)
    e_ref = jnp.max(e_max)
    X0 = qs.x[0] + scene.N[:, 0] * (e_ref - e_max[0])

    def body(carry, i, C, Keff, L):
        X, Xd, Xdd, code, it = carry

        def cho_solve(b):  # K_eff⁻¹ b = L⁻ᵀ L⁻¹ b: two LAPACK triangular solves (trsm) with L
            return solve_triangular(L, solve_triangular(L, b, lower=True), trans="T", lower=True)

        cells, e_th, d0 = separation(mesh, mods, theta[0] + (i + 1) * dth)
        d0 = jnp.where(cells.mask, d0 + (e_ref - e_th), 0.0)
        V = _vectors(cells)  # all c cells on all n coordinates
        k = cells.stiffness.reshape(-1)
        ln = cells.length.reshape(-1)
        m = cells.mask.reshape(-1)
        Feff = F + M @ (a0 * X + 4.0 / dt * Xd + Xdd) + C @ (a1 * X + Xd)
        if variant == "woodbury":
            R = cho_solve(jnp.concatenate([Feff[:, None], V.T], axis=1))
            xs, Z = R[:, 0], R[:, 1:]
            c = V.shape[0]
            sol, P, _ = solve_contact_cells(
                V @ Z,
                V @ xs - d0.reshape(-1),
                jnp.zeros((c, 0), dtype),
                jnp.zeros((0,), dtype),
                k,
                ln,
                m,
                law,
            )
            Xn = xs - Z @ P
        else:
            sol = solve_contact(Keff, Feff, V, k, ln, d0.reshape(-1), m, law)
            Xn, P = sol.x, sol.force_density * ln
        Xddn = a0 * (Xn - X - dt * Xd - 0.25 * dt * dt * Xdd)
        Xdn = Xd + 0.5 * dt * (Xdd + Xddn)
        new = jnp.where(sol.result != 0, 1, 0)
        new = jnp.where(jnp.all(jnp.isfinite(Xn)), new, 2)
        carry = (Xn, Xdn, Xddn, jnp.maximum(code, new), jnp.maximum(it, sol.iterations))
        return carry, jnp.sum(P)

    def period(carry, k):  # K_eff changes once per mesh period (the mesh damping's stations)
        C = C0 + beta * mean_mesh(k)
        Keff = K + a0 * M + a1 * C
        L = jnp.linalg.cholesky(Keff) if variant == "woodbury" else None
        steps = k * spp + jnp.arange(spp)
        return jax.lax.scan(lambda c, i: body(c, i, C, Keff, L), carry, steps)

    zero = jnp.zeros((n,), dtype)
    init = (X0, zero, zero, jnp.array(0), jnp.array(0))
    n_periods = -(-n_steps // spp)
    (_, _, _, code, it), fm = jax.lax.scan(period, init, jnp.arange(n_periods))
    fm = fm.reshape(-1)[:n_steps]
    code = jnp.where(qs.result[0] != 0, jnp.maximum(code, 1), code)
    return fm, code, it


@functools.cache
def _baseline_jit():
    import equinox as eqx
    import jax

    @eqx.filter_jit
    def sweep(scene, mods, torque, speeds, alpha, beta, width, spp, n_steps, mode, max_it, variant):
        fm, code, it = jax.lax.map(
            lambda w: _baseline_run(
                scene, mods, torque, w, alpha, beta, width, spp, n_steps, mode, max_it, variant
            ),
            speeds,
        )
        return fm, scene.mesh.normal_load(torque), code, it

    return sweep


def baseline_sweep(
    scene,
    mods,
    torque,
    speeds,
    *,
    steps_per_period,
    n_steps,
    variant,
    rayleigh=_RAYLEIGH,
    contact="exact",
    width=1e-7,
    max_iterations=50,
):
    """The full-coordinate baseline at each speed (``jax.lax.map``: one n×n factor in memory at
    a time), from the same start state as :func:`jaxgear.dynamics.speed_sweep`.

    Args:
        scene: a hybrid scene. mods: flank modifications. torque: pinion torque (N·m).
        speeds: pinion speeds (rad/s), shape (S,). steps_per_period: time steps per mesh
            period. n_steps: steps integrated (all returned). variant: "woodbury" or
            "refactor" (see the module docstring). rayleigh, contact, width, max_iterations: as
            ``speed_sweep``.

    Returns:
        (mesh force (S, n_steps) N, static mesh force N, result (S,), most passes (S,)).
    """
    import jax.numpy as jnp

    if variant not in ("woodbury", "refactor"):
        raise ValueError(f"variant = {variant!r}: allowed 'woodbury', 'refactor'")
    dtype = scene.structure.K.dtype
    return _baseline_jit()(
        scene,
        mods,
        jnp.asarray(torque, dtype),
        jnp.asarray(speeds, dtype),
        jnp.asarray(rayleigh[0], dtype),
        jnp.asarray(rayleigh[1], dtype),
        jnp.asarray(width, dtype),
        int(steps_per_period),
        int(n_steps),
        contact,
        int(max_iterations),
        variant,
    )


# ------------------------------------------------------------------------------------------
# helpers


def _body_build(source) -> tuple[dict, object]:
    """Load (or, if not cached, build) a condensed body through fem_prep's cache — a body file,
    an embedded body name or a :class:`fem_prep.Body` — and report its sizes and whether it came
    from the cache (fem_prep caches each parsed body once: a changed mode count is a new
    entry)."""
    import fem_prep

    body = source if isinstance(source, fem_prep.Body) else fem_prep.load_body(source)
    hit = (fem_prep.cache_dir() / fem_prep.cache_key(body) / "summary.json").is_file()
    t0 = time.perf_counter()
    cond = fem_prep.condensed(body)
    t = time.perf_counter() - t0
    kind = np.asarray(cond.dof_map)[:, 0]
    n_modes = int(np.sum(kind < 0))
    n_rim = int(np.asarray(cond.rim_grid).size * 3)
    return {
        "body": body.name,
        "modes_in_body_file": int(body.condensation.modes),
        "condensed_dofs": int(cond.K.shape[0]),
        "rim_master_dofs": n_rim,
        "bearing_dofs": int(cond.K.shape[0]) - n_rim - n_modes,
        "modes": n_modes,
        "cache_hit": bool(hit),
        "load_or_build_s": t,
    }, cond


def _load() -> list | None:
    return list(os.getloadavg()) if hasattr(os, "getloadavg") else None


def _step_costs(scene, mods, torque, speed, spp, lengths, repeats, compare=False) -> dict:
    """Per-step cost (s) of the model and the baselines at one speed, from two run lengths each
    (steps; the per-speed set-up cancels in the difference): compile = first call − steady,
    min of ``repeats`` steady calls of each length, all methods and lengths interleaved (a change
    of load hits them all). ``lengths[method]`` = (steps 1, steps 2) or None (skipped); the
    model's lengths are whole periods. With ``compare``: the mesh force of the first steps of
    each baseline against the model's (max |Δ| / static force)."""
    import jax
    import jax.numpy as jnp

    from jaxgear.dynamics import dynamic_model, speed_sweep

    block = jax.block_until_ready

    def run(method, steps):
        if method == "model":
            p = steps // spp
            r = speed_sweep(
                dynamic_model(scene, mods, torque),
                jnp.asarray([speed]),
                integrator=Newmark(spp),
                window=SteadyState(p, p),
            ).results
            return r.mesh_force[0], r.static_force[0]
        fm, fs, _, _ = baseline_sweep(
            scene, mods, torque, [speed], steps_per_period=spp, n_steps=steps, variant=method
        )
        return fm[0], fs

    methods = [m for m in _METHODS if lengths.get(m) is not None]
    runs = [(m, int(n)) for m in methods for n in lengths[m]]
    first, forces = {}, {}
    for m, n in runs:  # compile (and the forces of the first run of each method)
        t0 = time.perf_counter()
        fm, fs = block(run(m, n))
        first[m, n] = time.perf_counter() - t0
        forces.setdefault(m, (np.asarray(fm), float(fs)))
    best = dict.fromkeys(runs, math.inf)
    for _ in range(max(1, int(repeats))):  # interleaved: a change of load hits every method
        for m, n in runs:
            t0 = time.perf_counter()
            block(run(m, n))
            best[m, n] = min(best[m, n], time.perf_counter() - t0)
    out = {}
    for m in methods:
        s1, s2 = (int(n) for n in lengths[m])
        t1, t2 = best[m, s1], best[m, s2]
        per = max(t2 - t1, 0.0) / (s2 - s1)
        out[m] = {
            "per_step_s": per,
            "per_speed_setup_s": max(t1 - s1 * per, 0.0),
            "runs": [
                {
                    "steps": n,
                    "first_call_s": first[m, n],
                    "steady_s": best[m, n],
                    "compile_s": max(first[m, n] - best[m, n], 0.0),
                }
                for n in (s1, s2)
            ],
        }
    if "model" in out:
        t_model = out["model"]["per_step_s"]
        out["ratios_to_model"] = {
            m: out[m]["per_step_s"] / t_model if t_model > 0 else None for m in out if m != "model"
        }
    if compare and "model" in forces:
        fm_m, fs = forces["model"]
        out["first_steps_agreement"] = {
            m: {
                "steps": int(min(forces[m][0].size, fm_m.size)),
                "max_abs_diff_over_static_force": float(
                    np.max(np.abs(forces[m][0][: fm_m.size] - fm_m[: forces[m][0].size])) / fs
                ),
            }
            for m in forces
            if m != "model"
        }
    return out


def _fits(rows, x, powers) -> dict:
    """Least-squares t = t₀ + a xᵖ per method over ``rows`` (x = ``rows[i][x]``), and the
    log-log slope between the two extreme points."""
    out = {}
    xs = np.array([r[x] for r in rows], float)
    for m, p in powers.items():
        key = f"{m}_per_step_s"
        if any(r.get(key) is None for r in rows) or len(rows) < 2:
            continue
        t = np.array([r[key] for r in rows], float)
        A = np.stack([np.ones_like(xs), xs**p], 1)
        (t0, a), *_ = np.linalg.lstsq(A, t, rcond=None)
        resid = t - A @ np.array([t0, a])
        lo, hi = np.argmin(xs), np.argmax(xs)
        out[m] = {
            "power": p,
            "t0_s": float(t0),
            "a_s": float(a),
            "max_rel_residual": float(np.max(np.abs(resid) / t)) if np.all(t > 0) else None,
            "loglog_slope_extremes": float(np.log(t[hi] / t[lo]) / np.log(xs[hi] / xs[lo]))
            if t[lo] > 0 and t[hi] > 0
            else None,
        }
    return out


# ------------------------------------------------------------------------------------------
# the benchmark


def bench_hybrid_sweep(
    out_dir,
    quick: bool = False,
    case: str = "accessory-spur-flexible",
    compare_case: str | os.PathLike | None = _TEST_CASE,
    *,
    periods: int = 20,
    keep_periods: int = 4,
    progress: bool = True,
    verbose: bool = True,
) -> dict:
    """Run the hybrid speed-sweep benchmark and write ``bench_hybrid_sweep.json`` and
    ``bench_hybrid_sweep.png`` into ``out_dir`` (atomically).

    Args:
        out_dir: output folder (created if missing).
        quick: a smoke run: 4 speeds, 16 steps per period, 4 periods, short runs, the case's own
            body only in the master-DOF scaling, its own slices only.
        case: embedded case name or TOML path of a case with a condensed body (default the
            accessory pair with its flexible wheel, 50 modes).
        compare_case: the case whose (small) body is condensed with more and more modes for the
            per-step cost against the master-DOF count (default
            ``tests/data/hybrid-test-case.toml`` of a source checkout; skipped when missing,
            ``None`` or the same file as ``case``).
        periods, keep_periods: mesh periods integrated per speed and kept for the dynamic factor
            (the sweep's settings; (2) reports how far they are converged). Ignored by ``quick``.
        progress: show a tqdm progress bar. verbose: print the summary table.

    Returns:
        the JSON-ready dict that was written.
    """
    import jax

    jax.config.update("jax_enable_x64", True)  # entry point: float64
    import jax.numpy as jnp
    from tqdm.auto import tqdm

    import fem_prep
    from jaxgear.dynamics import dynamic_model, speed_sweep
    from jaxgear.io import load_case, static_scene, write_json

    block = jax.block_until_ready
    env = environment()
    c = load_case(case)
    compare_case = hybrid_cases(c, case, compare_case, "bench hybrid-sweep")
    if quick:
        n_speeds, spp, periods, keep, chunk, n_base, rep = 4, 16, 4, 2, 2, 1, 1
        # the model's second length is the convergence run's, the woodbury's the DF check's (the
        # same compiled functions: two compiles fewer)
        lengths = {"model": (4 * spp, 8 * spp), "woodbury": (2 * spp, 4 * spp), "refactor": (2, 4)}
        slice_factors, scaling_modes = (1,), ()
    else:
        n_speeds, spp, chunk, n_base, rep = 100, 64, 5, 5, 5
        periods, keep = int(periods), int(keep_periods)
        lengths = {
            "model": (2 * spp, 20 * spp),
            "woodbury": (2 * spp, 10 * spp),
            "refactor": (4, 20),
        }
        slice_factors, scaling_modes = (1, 2, 5, 10), (10, 100, 250, 500, 1000)
    if compare_case is None:
        scaling_modes = ()
    torque = c.torque
    mods = c.modifications
    speeds = np.linspace(*_SPEED_RANGE, n_speeds)
    conv_speeds = sorted(
        {float(speeds[np.argmin(np.abs(speeds - f * _SPEED_RANGE[1]))]) for f in (1, 1 / 3, 1 / 6)}
    )
    rev = int(c.pair.gear.teeth)  # mesh periods per wheel revolution
    long_periods = 2 * rev if not quick else 2 * periods
    n_chunks = math.ceil(n_speeds / chunk)
    bar = tqdm(
        total=1 + len(conv_speeds) + n_chunks + 2 + 2 + 1 + len(scaling_modes) + len(slice_factors),
        desc="bench hybrid-sweep",
        disable=not progress,
        leave=False,
    )
    wall: dict = {}
    t_last = [time.perf_counter()]

    def step(msg):
        now = time.perf_counter()
        wall[msg] = wall.get(msg, 0.0) + now - t_last[0]
        t_last[0] = now
        bar.set_postfix_str(msg)
        bar.update(1)

    out: dict = {
        "case": c.name,
        "quick": bool(quick),
        "machine": env,
        "dtype": env["dtype"],
        "jax": env["jax"],
        "settings": {
            "speeds_rad_s": {
                "first": float(speeds[0]),
                "last": float(speeds[-1]),
                "count": int(n_speeds),
            },
            "steps_per_period": spp,
            "periods": periods,
            "keep_periods": keep,
            "steps_per_speed": spp * periods,
            "torque_Nm": torque,
            "contact": "exact",
            "rayleigh_alpha_beta": list(_RAYLEIGH),
            "chunk_speeds": chunk,
            "repeats": rep,
            "timing": "min of repeats after a warm-up call, jax.block_until_ready on the whole "
            "result; compile = first call (after jax.clear_caches()) minus the steady time; "
            "per step = difference of two run lengths at one speed (the per-speed set-up "
            "cancels)",
        },
    }

    # (0) the body and the scene -------------------------------------------------------------
    bodies_info, bodies = [], []
    for ref in c.scene.bodies:
        if ref is None:
            bodies.append(None)
            continue
        info, cond = _body_build(ref)
        bodies_info.append(info)
        bodies.append(cond)
    bodies = tuple(bodies)
    t0 = time.perf_counter()
    sc, _ = static_scene(c, bodies=bodies)
    t_scene = time.perf_counter() - t0
    fi = _flex_index(sc)
    slices = int(sc.mesh.n_slices)
    out["setup"] = {
        "bodies": bodies_info,
        "static_scene_s": t_scene,
        "structure_dofs": int(sc.structure.K.shape[0]),
        "slices": slices,
        "cells_per_position": _cells(sc.mesh),
        "window_stations": int(sc.members[fi].n_window),
        "window_dofs": _window_dofs(sc),
        "mesh_periods_per_wheel_revolution": rev,
    }
    step("setup")

    hybrid = dynamic_model(sc, mods, torque)  # the seed's D1 damping

    def model(w, p, k):
        return speed_sweep(
            hybrid, jnp.asarray(w), integrator=Newmark(spp), window=SteadyState(p, k)
        ).results

    # (1) the sweep --------------------------------------------------------------------------
    jax.clear_caches()
    chunks = [speeds[k : k + chunk] for k in range(0, n_speeds, chunk)]
    dfs, results, passes, te_rms, chunk_s = [], [], [], [], []
    t_sweep = time.perf_counter()
    for part in chunks:
        padded = np.concatenate([part, np.full(chunk - part.size, part[-1])])
        t0 = time.perf_counter()
        r = block(model(padded, periods, keep))
        chunk_s.append(time.perf_counter() - t0)
        dfs += np.asarray(r.dynamic_factor)[: part.size].tolist()
        results += [int(v) for v in np.asarray(r.result)[: part.size]]
        passes += [int(v) for v in np.asarray(r.iterations)[: part.size]]
        te_rms += np.asarray(r.te_rms)[: part.size].tolist()
        step("sweep")
    total_wall = time.perf_counter() - t_sweep
    t0 = time.perf_counter()
    block(model(chunks[0], periods, keep))  # the first chunk again, compiled
    first_again = time.perf_counter() - t0
    step("sweep")
    compile_s = max(chunk_s[0] - first_again, 0.0)
    run_s = total_wall - compile_s
    out["sweep"] = {
        "what": f"jaxgear.dynamics.speed_sweep in chunks of {chunk} speeds (the chunking "
        "of `jaxgear sweep`); compile = first chunk − the same chunk again",
        "speeds_rad_s": speeds.tolist(),
        "dynamic_factor": dfs,
        "te_rms_m": te_rms,
        "result": results,
        "max_contact_passes": passes,
        "chunk_s": chunk_s,
        "first_chunk_again_s": first_again,
        "total_wall_s": total_wall,
        "compile_s": compile_s,
        "run_after_compile_s": run_s,
        "per_speed_s": run_s / n_speeds,
        "per_step_s": run_s / (n_speeds * spp * periods),
        "per_step_note": "run after compile / (speeds × steps per speed), the per-speed set-up "
        "(period statics, K̄_m, K_eff⁻¹) included; the step alone: baseline.per_step.model",
        "target_s": _TARGET_S,
        "meets_target": total_wall < _TARGET_S,
        "load_average_after": _load(),
    }

    # (1b) the same sweep in the modal basis (docs/hybrid.md, "Modal basis") ----------------------
    # one speed_sweep call chunked inside (the way `jaxgear sweep` runs: the basis once per call)
    def modal(w, p, k, chunk_size=None, progress=None):
        basis = ModalBasis(_MODAL_MODES)
        return speed_sweep(
            hybrid,
            jnp.asarray(w),
            integrator=Newmark(spp, basis=basis),
            window=SteadyState(p, k),
            batching=Batching(chunk_size, progress),
        ).results

    jax.clear_caches()
    ticks = []
    t_sweep = time.perf_counter()
    r = block(modal(speeds, periods, keep, chunk, lambda k: ticks.append(time.perf_counter())))
    m_total = time.perf_counter() - t_sweep
    mdfs = np.asarray(r.dynamic_factor).tolist()
    mresults = [int(v) for v in np.asarray(r.result)]
    mchunk_s = np.diff([t_sweep, *ticks]).tolist()
    t0 = time.perf_counter()
    block(modal(chunks[0], periods, keep))  # the first chunk again (basis included), compiled
    m_again = time.perf_counter() - t0
    step("sweep: modal basis")
    m_compile = max(mchunk_s[0] - m_again, 0.0)
    m_err = np.abs(np.asarray(mdfs) / np.asarray(dfs) - 1)
    out["sweep_modal_basis"] = {
        "what": f"the sweep (1) with Newmark({spp}, basis=ModalBasis({_MODAL_MODES})): the "
        f"{_MODAL_MODES} lowest modes of (M, K + K̄) plus the members' free rotations and the "
        "static correction of the cells; one speed_sweep call with chunk_size (as `jaxgear "
        "sweep`: the basis computed once); compile = first chunk − the first chunk again "
        "(basis included in both); ratios against (1) measured in this run",
        "modes": _MODAL_MODES,
        "dynamic_factor": mdfs,
        "result": mresults,
        "chunk_s": mchunk_s,
        "total_wall_s": m_total,
        "compile_s": m_compile,
        "run_after_compile_s": m_total - m_compile,
        "per_speed_s": (m_total - m_compile) / n_speeds,
        "ratio_total_wall_vs_cell_space": m_total / total_wall,
        "ratio_run_vs_cell_space": (m_total - m_compile) / run_s,
        "max_abs_df_error_vs_cell_space": float(m_err.max()),
        "speed_of_max_df_error_rad_s": float(speeds[int(np.argmax(m_err))]),
        "target_s": _MODAL_TARGET_S,
        "meets_target": m_total < _MODAL_TARGET_S and float(m_err.max()) < 0.01,
        "load_average_after": _load(),
    }

    # (2) convergence in the number of periods ------------------------------------------------
    conv = []
    for s in conv_speeds:
        r = block(model([s], long_periods, long_periods))
        fm = np.asarray(r.mesh_force)[0].reshape(long_periods, spp)
        per_period = fm.max(axis=1) / float(np.asarray(r.static_force)[0])
        df = {P: float(per_period[P - keep : P].max()) for P in range(keep, long_periods + 1)}
        within_rev = [df[P] for P in range(periods, min(rev, long_periods + 1))]
        conv.append(
            {
                "speed_rad_s": s,
                "df_at_sweep_periods": df[periods],
                "df_at_2x_periods": df.get(2 * periods),
                "df_at_4x_periods": df.get(4 * periods),
                "df_range_periods_to_first_revolution": [min(within_rev), max(within_rev)],
                "max_rel_dev_of_sweep_df_in_first_revolution": max(
                    abs(v - df[periods]) for v in within_rev
                )
                / df[periods],
                "df_max_over_second_revolution": float(per_period[rev:].max())
                if long_periods > rev
                else None,
                "df_per_period": per_period.tolist(),
                "result": int(np.asarray(r.result)[0]),
            }
        )
        step("convergence")
    out["convergence"] = {
        "what": "one run of long_periods mesh periods per speed with every step kept; "
        "df_per_period[p] = max mesh force / static force in period p; DF(P) = max over periods "
        "P − keep_periods … P − 1 (exactly the DF of a run of P periods); the range of DF(P) for "
        "P from the sweep's periods to one wheel revolution; the max over the whole second "
        "wheel revolution",
        "keep_periods": keep,
        "long_periods": long_periods,
        "rows": conv,
    }

    # (3) baseline at equal accuracy; per-step costs in one run --------------------------------
    idx_b = np.unique(np.linspace(0, n_speeds - 1, n_base).round().astype(int))
    sp_b = speeds[idx_b]
    kw = {"steps_per_period": spp, "n_steps": spp * periods, "variant": "woodbury"}
    t0 = time.perf_counter()
    fm_b, fs_b, code_b, it_b = block(baseline_sweep(sc, mods, torque, sp_b, **kw))
    t_first = time.perf_counter() - t0
    t_base = min_time(lambda: baseline_sweep(sc, mods, torque, sp_b, **kw), 1, block, warmup=False)
    df_b = np.asarray(fm_b)[:, -spp * keep :].max(axis=1) / float(fs_b)
    df_m = np.asarray(dfs)[idx_b]
    step("baseline")
    s_mid = float(speeds[n_speeds // 2])
    per = _step_costs(sc, mods, torque, s_mid, spp, lengths, rep, compare=True)
    step("baseline")
    out["baseline"] = {
        "what": "the same equations on all n coordinates (module docstring): 'woodbury' = "
        "K_eff Cholesky once per speed, each step one cho_solve with [F_eff, Vᵀ] (c + 1 "
        "right-hand sides) and the active set on V K_eff⁻¹ Vᵀ; 'refactor' = "
        "jaxgear.solve_contact on K_eff (K_eff + Vᵀ diag(k l) V factored at every pass, the "
        "tests' reference); per_step at one speed, all three in one run",
        "speeds_rad_s": sp_b.tolist(),
        "dynamic_factor_woodbury": df_b.tolist(),
        "dynamic_factor_model": df_m.tolist(),
        "df_max_abs_diff": float(np.max(np.abs(df_b - df_m))),
        "result_woodbury": [int(v) for v in np.asarray(code_b)],
        "max_contact_passes_woodbury": [int(v) for v in np.asarray(it_b)],
        "woodbury_sweep_s": t_base,
        "woodbury_compile_s": max(t_first - t_base, 0.0),
        "woodbury_per_speed_s": t_base / sp_b.size,
        "model_per_speed_s": out["sweep"]["per_speed_s"],
        "per_speed_ratio_woodbury_over_model": (t_base / sp_b.size) / out["sweep"]["per_speed_s"],
        "woodbury_all_speeds_extrapolated_s": t_base / sp_b.size * n_speeds,
        "per_step_speed_rad_s": s_mid,
        "per_step": per,
    }
    if "refactor" in per:
        r = per["refactor"]
        out["baseline"]["refactor_all_speeds_extrapolated_s"] = n_speeds * (
            r["per_speed_setup_s"] + spp * periods * r["per_step_s"]
        )

    # (4a) per-step cost vs master DOFs at equal cells and window ------------------------------
    variants = [(c, bodies, f"{bodies_info[0]['body']} (the case's)", bodies_info[0])]
    if compare_case is not None:
        c2 = load_case(compare_case)
        body2 = fem_prep.load_body(next(b for b in c2.scene.bodies if b is not None))
        for m in scaling_modes:
            b = dataclasses.replace(
                body2, condensation=dataclasses.replace(body2.condensation, modes=int(m))
            )
            info, cond = _body_build(b)
            bb = tuple(None if x is None else cond for x in c2.scene.bodies)
            variants.append((c2, bb, f"{body2.name}, {m} modes", info))
    scenes = [static_scene(cc, slices=slices, bodies=bb)[0] for cc, bb, _, _ in variants]
    per_station = [
        s.members[_flex_index(s)].width // s.members[_flex_index(s)].n_window for s in scenes
    ]
    lcm = math.lcm(*per_station)
    need = max(s.members[_flex_index(s)].width for s in scenes)
    width = lcm * math.ceil(need / lcm)  # a common window width that holds every default
    rows_n = []
    for (cc, _, label, info), s, ps in zip(variants, scenes, per_station):
        if len(variants) == 1:
            costs = per
        else:
            s = _with_window(s, _flex_index(s), width // ps)
            costs = _step_costs(s, cc.modifications, cc.torque, s_mid, spp, lengths, rep)
        rows_n.append(
            {
                "case": cc.name,
                "body": label,
                "condensed_body_dofs": info["condensed_dofs"],
                "modes": info["modes"],
                "modes_in_body_file": info["modes_in_body_file"],
                "body_cache_hit": info["cache_hit"],
                "structure_dofs": int(s.structure.size),
                "cells_per_position": _cells(s.mesh),
                "window_dofs": _window_dofs(s),
                **{f"{m}_per_step_s": costs[m]["per_step_s"] for m in _METHODS if m in costs},
                **{
                    f"{m}_per_speed_setup_s": costs[m]["per_speed_setup_s"]
                    for m in _METHODS
                    if m in costs
                },
            }
        )
        step("scaling: master DOFs")
    rows_n.sort(key=lambda r: r["structure_dofs"])
    out["scaling"] = {
        "master_dofs": {
            "what": "per step at one speed, equal cells and equal window DOFs (each window "
            "widened to a common width), n varied: the test wheel condensed with more modes and "
            "the case's own wheel; fits t = t0 + a n^p",
            "rows": rows_n,
            "fits": _fits(rows_n, "structure_dofs", {"model": 2, "woodbury": 2, "refactor": 3}),
        }
    }

    # (4b) per-step cost vs cells at fixed n ----------------------------------------------------
    rows_c = []
    # no refactor, and a shorter woodbury difference (its step grows with the cells)
    no_refactor = dict(
        lengths, refactor=None, woodbury=(lengths["woodbury"][0], 3 * lengths["woodbury"][0])
    )
    for f in slice_factors:
        ns = slices * f
        s = sc if f == 1 else static_scene(c, slices=ns, bodies=bodies)[0]
        costs = per if f == 1 else _step_costs(s, mods, torque, s_mid, spp, no_refactor, rep)
        rows_c.append(
            {
                "slices": int(ns),
                "cells_per_position": _cells(s.mesh),
                "window_dofs": _window_dofs(s),
                "structure_dofs": int(s.structure.size),
                **{
                    f"{m}_per_step_s": costs[m]["per_step_s"]
                    for m in ("model", "woodbury")
                    if m in costs
                },
            }
        )
        step("scaling: cells")
    out["scaling"]["cells"] = {
        "what": "per step at one speed, the case's body at its default window, slices varied "
        "(cells = contact lines × slices); fits t = t0 + a c",
        "rows": rows_c,
        "fits": _fits(rows_c, "cells_per_position", {"model": 1, "woodbury": 1}),
    }
    bar.close()
    out["wall_s"] = {"total": sum(wall.values()), "steps": wall}
    out["load_average_end"] = _load()

    os.makedirs(out_dir, exist_ok=True)
    write_json(os.path.join(out_dir, "bench_hybrid_sweep.json"), out)
    hybrid_sweep_chart(out, os.path.join(out_dir, "bench_hybrid_sweep.png"))
    if verbose:
        print(_table(out))
    return out


# ------------------------------------------------------------------------------------------
# report

_STYLE = {
    "model": ("C3", "o-", "cell space (jaxgear)"),
    "woodbury": ("C0", "s-", "all coordinates, K_eff factored once (Woodbury)"),
    "refactor": ("C7", "^-", "all coordinates, refactored per contact pass"),
}


def hybrid_sweep_chart(out: dict, path: str) -> None:
    """Draw the chart of the hybrid sweep benchmark (bench_hybrid_sweep.json) from its JSON record ``out`` into
    the PNG ``path`` (written atomically); ``jaxgear bench`` calls it after a run."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import NullFormatter

    from jaxgear.io import atomic_open

    fig = Figure(figsize=(16, 9.5), layout="constrained")
    FigureCanvasAgg(fig)
    (ax1, ax2, ax3), (ax4, ax5, ax6) = fig.subplots(2, 3)
    sw, bl, cv, st = out["sweep"], out["baseline"], out["convergence"], out["settings"]

    # (a) the sweep's dynamic factor, and the baseline's at its speeds
    ax1.plot(
        sw["speeds_rad_s"],
        sw["dynamic_factor"],
        ".-",
        color="C3",
        ms=4,
        label=f"cell space, {len(sw['speeds_rad_s'])} speeds",
    )
    ax1.plot(
        bl["speeds_rad_s"],
        bl["dynamic_factor_woodbury"],
        "s",
        mfc="none",
        color="C0",
        ms=9,
        label=f"all coordinates (max |ΔDF| {bl['df_max_abs_diff']:.1e})",
    )
    ax1.set_xlabel("pinion speed (rad/s)")
    ax1.set_ylabel(f"dynamic factor (last {st['keep_periods']} of {st['periods']} periods)")
    ax1.set_title(
        f"{out['case']}: {st['steps_per_period']} steps/period, {st['periods']} periods; "
        f"{sw['total_wall_s']:.0f} s wall for {len(sw['speeds_rad_s'])} speeds",
        fontsize=9,
    )
    ax1.legend(fontsize=7)
    ax1.grid(True, alpha=0.3)

    # (b) convergence in periods
    keep = cv["keep_periods"]
    for i, row in enumerate(cv["rows"]):
        pp = np.asarray(row["df_per_period"])
        P = np.arange(keep, pp.size + 1)
        dfP = np.array([pp[p - keep : p].max() for p in P])
        ax2.plot(P, dfP, "-", color=f"C{i}", lw=1.2, label=f"{row['speed_rad_s']:.0f} rad/s")
        ax2.plot([st["periods"]], [row["df_at_sweep_periods"]], "o", color=f"C{i}")
    ax2.axvline(st["periods"], color="k", ls="--", lw=0.8, label=f"sweep: {st['periods']} periods")
    rev = out["setup"]["mesh_periods_per_wheel_revolution"]
    for k in range(1, cv["long_periods"] // rev + 1):
        ax2.axvline(k * rev, color="0.6", ls=":", lw=0.8)
    ax2.set_xscale("log")
    ax2.set_xlabel(f"mesh periods integrated P (dotted: wheel revolutions, {rev} periods)")
    ax2.set_ylabel(f"DF over the last {keep} periods")
    ax2.set_title("convergence of the dynamic factor in the number of periods", fontsize=9)
    ax2.legend(fontsize=7)
    ax2.grid(True, which="both", alpha=0.3)

    # (c) wall time for the speeds
    n = len(sw["speeds_rad_s"])
    labels = ["cell space\n(measured)", "all coords, Woodbury\n(extrapolated)"]
    run = [sw["run_after_compile_s"], bl["woodbury_all_speeds_extrapolated_s"]]
    comp = [sw["compile_s"], bl["woodbury_compile_s"]]
    if "refactor_all_speeds_extrapolated_s" in bl:
        labels.append("all coords, refactored\n(extrapolated)")
        run.append(bl["refactor_all_speeds_extrapolated_s"])
        comp.append(bl["per_step"]["refactor"]["runs"][0]["compile_s"])
    x = np.arange(len(labels))
    ax3.bar(x, comp, 0.6, color="0.7", label="compile")
    bars = ax3.bar(x, run, 0.6, bottom=comp, color=["C3", "C0", "C7"][: len(x)], label="run")
    for r, a, b in zip(bars, run, comp):
        ax3.annotate(
            f"{a + b:.3g} s",
            (r.get_x() + r.get_width() / 2, a + b),
            ha="center",
            va="bottom",
            fontsize=8,
        )
    ax3.axhline(sw["target_s"], color="k", ls="--", lw=1, label=f"target {sw['target_s']:.0f} s")
    ax3.set_yscale("log")
    ax3.set_xticks(x, labels, fontsize=8)
    ax3.set_ylabel(f"wall time for {n} speeds (s)")
    ax3.set_title(
        f"{n}-speed sweep: per speed {sw['per_speed_s']:.2f} s, per step "
        f"{bl['per_step']['model']['per_step_s'] * 1e3:.2f} ms (cell space)",
        fontsize=9,
    )
    ax3.legend(fontsize=7)
    ax3.grid(True, axis="y", which="both", alpha=0.3)

    def lines(ax, block, x, fits):
        rows = block["rows"]
        xs = np.array([r[x] for r in rows], float)
        for m, (col, mk, label) in _STYLE.items():
            key = f"{m}_per_step_s"
            if not all(r.get(key) is not None for r in rows):
                continue
            t = np.array([r[key] for r in rows]) * 1e3
            ok = t > 0  # a step time below the timer's resolution under load is measured as 0
            if not ok.any():
                continue
            ax.plot(xs[ok], t[ok], mk, color=col, label=label)
            f = block["fits"].get(m)
            if f is not None and len(xs) > 1:
                xx = np.geomspace(xs.min(), xs.max(), 50)
                tt = (f["t0_s"] + f["a_s"] * xx ** f["power"]) * 1e3
                if np.all(tt > 0):
                    ax.plot(xx, tt, ":", color=col, lw=1, label=f"fit t₀ + a·{fits}^{f['power']}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ticks = []
        for v in sorted(set(xs.tolist())):  # the data's x values, none closer than 15 %
            if not ticks or v > 1.15 * ticks[-1]:
                ticks.append(v)
        ax.set_xticks(ticks, [f"{v:g}" for v in ticks])
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_ylabel("time per Newmark step (ms)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)

    # (d) per step vs master DOFs
    md = out["scaling"]["master_dofs"]
    lines(ax4, md, "structure_dofs", "n")
    for r in md["rows"]:
        if not r["model_per_step_s"] > 0:
            continue
        ax4.annotate(
            f"{r['modes_in_body_file']} modes"
            if r["case"] != out["case"]
            else f"{r['body'].split(' ')[0]}, {r['modes_in_body_file']} modes",
            (r["structure_dofs"], r["model_per_step_s"] * 1e3),
            fontsize=6,
            xytext=(2, -9),
            textcoords="offset points",
        )
    r0 = md["rows"][0]
    ax4.set_xlabel("structure DOFs n (shafts + condensed body: rim masters + modes)")
    ax4.set_title(
        f"per step vs n at {r0['cells_per_position']} cells, window {r0['window_dofs']} DOFs",
        fontsize=9,
    )

    # (e) per step vs cells
    cs = out["scaling"]["cells"]
    lines(ax5, cs, "cells_per_position", "c")
    ax5.set_xlabel("contact cells per position (lines × slices)")
    ax5.set_title(
        f"per step vs cells at n = {cs['rows'][0]['structure_dofs']}, window "
        f"{cs['rows'][0]['window_dofs']} DOFs",
        fontsize=9,
    )

    # (f) per-step ratio to the cell space
    for block, x, mk, lab in (
        (md, "structure_dofs", "o", "vs n"),
        (cs, "cells_per_position", "s", "vs cells"),
    ):
        for m, (col, _, label) in _STYLE.items():
            rows = block["rows"]
            if m == "model" or not all(r.get(f"{m}_per_step_s") for r in rows):
                continue
            if not all(r.get("model_per_step_s") for r in rows):
                continue
            xs = [r[x] for r in block["rows"]]
            ratio = [r[f"{m}_per_step_s"] / r["model_per_step_s"] for r in block["rows"]]
            ax6.plot(
                xs,
                ratio,
                mk + ("-" if x == "structure_dofs" else "--"),
                color=col,
                label=f"{label.split(',')[1].strip()}: {lab}",
            )
    ax6.axhline(1.0, color="k", lw=0.8)
    ax6.set_xscale("log")
    ax6.set_yscale("log")
    ax6.xaxis.set_minor_formatter(NullFormatter())
    ax6.set_xlabel("n (solid) or cells (dashed)")
    ax6.set_ylabel("per-step time / cell space")
    ax6.set_title("baselines' per-step cost over the cell space's (same run)", fontsize=9)
    if ax6.get_legend_handles_labels()[0]:
        ax6.legend(fontsize=7)
    ax6.grid(True, which="both", alpha=0.3)

    m = out["machine"]
    fig.suptitle(
        f"jaxgear bench hybrid-sweep — {out['case']}, exact contact, {m['cpu_count']} CPU "
        f"({m['cpu_model']}), {out['dtype']}, JAX {out['jax']}, load "
        f"{m['load_average_at_start'][0]:.1f} → {out['load_average_end'][0]:.1f}"
        + (" — QUICK" if out["quick"] else ""),
        fontsize=10,
    )
    thin_tick_labels(fig)
    with atomic_open(path, "wb") as f:  # as the other benchmarks' figures
        fig.savefig(f, format="png", dpi=110)


def _table(out: dict) -> str:
    sw, bl, st = out["sweep"], out["baseline"], out["settings"]
    ps = bl["per_step"]
    n = len(sw["speeds_rad_s"])
    lines = [
        (
            f"hybrid sweep benchmark: {out['case']}, n = {out['setup']['structure_dofs']} DOFs, "
            f"{out['setup']['cells_per_position']} cells, window {out['setup']['window_dofs']} DOFs, "
            f"{st['steps_per_period']} steps × {st['periods']} periods per speed, {out['dtype']}, "
            f"JAX {out['jax']}, {out['machine']['cpu_count']} CPU"
        ),
        (
            f"{n} speeds: {sw['total_wall_s']:.1f} s wall (compile {sw['compile_s']:.1f} s, run "
            f"{sw['run_after_compile_s']:.1f} s; target < {sw['target_s']:.0f} s: "
            f"{'met' if sw['meets_target'] else 'missed'}), {sw['per_speed_s']:.2f} s per speed, "
            f"{sw['per_step_s'] * 1e3:.2f} ms per step with set-up"
        ),
        *(
            [
                (
                    f"modal basis (m = {mb['modes']}): {mb['total_wall_s']:.1f} s wall (compile "
                    f"{mb['compile_s']:.1f} s), {mb['ratio_total_wall_vs_cell_space']:.2f}× the cell "
                    f"space's; max |DF error| {mb['max_abs_df_error_vs_cell_space'] * 100:.2f} % at "
                    f"{mb['speed_of_max_df_error_rad_s']:.0f} rad/s (target < "
                    f"{mb['target_s']:.0f} s and 1 %: {'met' if mb['meets_target'] else 'missed'})"
                )
            ]
            if (mb := out.get("sweep_modal_basis"))
            else []
        ),
        "per step at {:.0f} rad/s: ".format(bl["per_step_speed_rad_s"])
        + ", ".join(f"{m} {ps[m]['per_step_s'] * 1e3:.2f} ms" for m in _METHODS if m in ps)
        + "; ratios "
        + ", ".join(
            f"{m} {v:.1f}×" if v is not None else f"{m} –"
            for m, v in ps.get("ratios_to_model", {}).items()
        ),
        (
            f"DF cell space vs all coordinates at {len(bl['speeds_rad_s'])} speeds: max |Δ| "
            f"{bl['df_max_abs_diff']:.1e}; woodbury per speed {bl['woodbury_per_speed_s']:.2f} s "
            f"({bl['per_speed_ratio_woodbury_over_model']:.1f}× the sweep's)"
        ),
    ]
    for row in out["convergence"]["rows"]:
        lo, hi = row["df_range_periods_to_first_revolution"]
        lines.append(
            f"convergence {row['speed_rad_s']:.0f} rad/s: DF({st['periods']}) "
            f"{row['df_at_sweep_periods']:.4f}, DF({2 * st['periods']}) "
            f"{row['df_at_2x_periods'] or float('nan'):.4f}, DF({4 * st['periods']}) "
            f"{row['df_at_4x_periods'] or float('nan'):.4f}; range to 1 revolution "
            f"{lo:.4f}–{hi:.4f}; max over 2nd revolution "
            f"{row['df_max_over_second_revolution'] or float('nan'):.4f}"
        )
    for key, x in (("master_dofs", "structure_dofs"), ("cells", "cells_per_position")):
        for r in out["scaling"][key]["rows"]:
            lines.append(
                f"{key} {x} {r[x]}: "
                + ", ".join(
                    f"{m} {r[f'{m}_per_step_s'] * 1e3:.2f} ms"
                    for m in _METHODS
                    if r.get(f"{m}_per_step_s") is not None
                )
            )
    return "\n".join(lines)
