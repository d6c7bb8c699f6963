"""Benchmark of the quasi-static solver: jaxgear (jit) against the NumPy/brentq baseline.

``bench_quasi_static(out_dir)`` is the body of ``jaxgear bench quasi-static``. In one run, on the
accessory spur pair (float64) it measures:

(a) compile time of jaxgear exact and smooth modes (first call minus a steady call, caches
    cleared first);
(b) time per TE curve after compile (``block_until_ready``, min of repeats) of jaxgear exact and
    smooth against :mod:`benchmarks._baseline`, their ratio, and the largest relative difference of
    the results (TE, mesh stiffness, contact length; must be <= 1e-9), for each contact model
    like with like: the case's (contact beyond the theoretical path where it has it, both codes
    with the tip corners) and the theoretical path (both codes without);
(c) a 41×41 (Γ, E) grid of TE RMS (symmetric linear tip relief, exact mode) by ``jax.vmap``,
    time after compile, and the same grid by the baseline extrapolated from a few points;
(d) a speed-vs-accuracy chart: time per TE curve vs TE RMS error against a converged reference,
    for exact mode over slices × positions per pitch (each contact model against its own
    reference) and smooth mode over widths, with the baseline's points;
and a break-down of where jaxgear's time per TE curve goes (Python preparation and dispatch, cell
layout, deviations, contact solve), each stage jitted on its own.

Benchmarks are not tests (timings are measured, never asserted): compile separately, warm up,
``block_until_ready``, min of repeats; device, dtype and versions are recorded.
"""

from __future__ import annotations

import json
import os
import platform
import time

import numpy as np

from jaxgear import SmoothContact, TheoreticalPath
from jaxgear.io import contact_law_from_name

from ._charts import thin_tick_labels
from ._curve_dispatch import paired_dispatch_modes
from ._timing import cpu_model as _cpu_model, first_call as _first_call, min_time as _min_time

__all__ = ["bench_quasi_static"]

_TOL = 1e-9
_CHUNK = 8  # grid points per vmap chunk in the chunked grid (fastest of 1..512 on 2 cores)


def _rel(a, b) -> float:
    """max |a − b| / max |b| (norm-wise relative difference)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def _rms(te) -> float:
    te = np.asarray(te, dtype=float)
    return float(np.sqrt(np.mean((te - te.mean()) ** 2)))


def bench_quasi_static(
    out_dir,
    quick: bool = False,
    case: str = "accessory-spur",
    progress: bool = True,
    verbose: bool = True,
) -> dict:
    """Run the quasi-static benchmark and write ``bench_quasi_static.json`` and
    ``speed_accuracy_quasi_static.png`` into ``out_dir`` (atomically).

    Args:
        out_dir: output folder (created if missing).
        quick: shrink everything (5×5 grid, 1×2 refinements, 2 widths, fewer repeats) for a
            smoke test (< 60 s on an idle 2-core CPU).
        case: embedded case name or TOML path (default the accessory spur pair).
        progress: show a tqdm progress bar. verbose: print the summary table.

    Returns:
        the JSON-ready dict that was written.

    Raises:
        RuntimeError: jaxgear and the baseline disagree by more than 1e-9 relative.
    """
    import jax

    jax.config.update("jax_enable_x64", True)  # entry point: float64
    import jax.numpy as jnp
    import matplotlib
    import scipy
    from tqdm.auto import tqdm

    from jaxgear import LinearRelief, MemberModification, Modifications, quasi_static
    from jaxgear.io import atomic_open, load_case

    from . import _baseline as bl

    c = load_case(case)
    torque = c.torque
    P0, N0 = c.positions_per_pitch, c.slices
    if quick:
        rep_jax, rep_np = 5, 2
        n_grid, n_grid_np = 5, 2
        sweep_slices, sweep_ppp = (10,), (16, 32)
        widths = (1e-7, 1e-8)
        ref_slices, ref_ppp = 20, 128
    else:
        rep_jax, rep_np = 50, 10
        n_grid, n_grid_np = 41, 5
        sweep_slices, sweep_ppp = (10, 20, 40, 80), (16, 32, 64, 128)
        widths = (1e-6, 3e-7, 1e-7, 3e-8, 1e-8)
        ref_slices, ref_ppp = 160, 512
    n_steps = 10 + 1 + 4 + 2 + 2 + 2 * len(sweep_slices) * len(sweep_ppp) + len(widths)
    bar = tqdm(total=n_steps, desc="bench quasi-static", disable=not progress, leave=False)

    def step(msg):
        bar.set_postfix_str(msg)
        bar.update(1)

    block = jax.block_until_ready
    dev = jax.devices()[0]
    out: dict = {
        "case": c.name,
        "quick": bool(quick),
        "machine": {
            "device": str(dev),
            "platform": dev.platform,
            "device_kind": getattr(dev, "device_kind", ""),
            "cpu_model": _cpu_model(),
            "cpu_count": os.cpu_count(),
            "cpu_affinity": (
                len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None
            ),
            "load_average_at_start": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
        },
        "dtype": str(jnp.result_type(float)),
        "versions": {
            "jax": jax.__version__,
            "jaxlib": getattr(jax.lib, "__version__", None) or jax.__version__,
            "numpy": np.__version__,
            "scipy": scipy.__version__,
            "python": platform.python_version(),
        },
        "settings": {
            "slices": N0,
            "positions_per_pitch": P0,
            "torque_Nm": torque,
            "smooth_width_m": c.smooth_width,
            "repeats_jax": rep_jax,
            "repeats_baseline": rep_np,
            "timing": "min of repeats after a warm-up call, "
            "jax.block_until_ready on the whole result",
            "cpu_async_dispatch": jax.config.values.get("jax_cpu_enable_async_dispatch"),
        },
    }
    mesh = c.mesh_model()
    mods = c.modifications
    bmesh = bl.baseline_mesh(c)  # the same contact model as the case's mesh model
    bmods = bl.mods_params(mods)
    width = c.smooth_width
    # the contact models compared like with like: the case's (key "case") and, where the case
    # has contact beyond the path, the theoretical path in both codes
    models = {"case": (mesh, bmesh)}
    if mesh.contact_geometry.reaches_beyond_path:
        models["theoretical_path"] = (
            mesh.with_contact_geometry(TheoreticalPath()),
            bl.baseline_mesh(c, extended_contact=False),
        )
    out["settings"]["extended_contact"] = bool(mesh.contact_geometry.reaches_beyond_path)
    out["settings"]["contact_models"] = {
        "case": "contact beyond the theoretical path (tip corners), in jaxgear and the baseline"
        if mesh.contact_geometry.reaches_beyond_path
        else "the theoretical path",
        **({"theoretical_path": "the theoretical path, in both"} if len(models) > 1 else {}),
    }

    # (a) compile time ---------------------------------------------------------------------
    jax.clear_caches()
    calls = {
        mode: (
            lambda mode=mode: quasi_static(
                mesh,
                mods,
                torque,
                contact=contact_law_from_name(mode, width),
                positions_per_pitch=P0,
            )
        )
        for mode in ("exact", "smooth")
    }
    compile_ = {}
    for mode in ("exact", "smooth"):
        first = _first_call(calls[mode], block)
        steady = _min_time(calls[mode], 3, block)
        compile_[mode] = {"first_call_s": first, "compile_s": first - steady}
        step(f"compile {mode}")
    out["compile"] = compile_

    # (b) time per TE curve, each contact model like with like ---------------------------------
    per_model = {}
    for model, (m_mesh, m_bmesh) in models.items():
        m_calls = calls if model == "case" else {
            mode: (
                lambda mode=mode, m_mesh=m_mesh: quasi_static(
                    m_mesh, mods, torque, contact=contact_law_from_name(mode, width),
                    positions_per_pitch=P0,
                )
            )
            for mode in ("exact", "smooth")
        }
        per_model[model] = _per_curve(
            m_calls, m_bmesh, bmods, torque, width, P0, rep_jax, rep_np, bl, block, step
        )
    per_curve = per_model["case"]
    out["per_te_curve"] = per_curve
    out["per_te_curve_by_contact_model"] = per_model


    # where jaxgear's time per curve goes (each stage jitted on its own; exact mode)
    out["profile_exact"] = _profile(
        mesh, mods, torque, P0, rep_jax, per_curve["exact"]["jaxgear_s"]
    )
    step("profile")

    # (c) (Γ, E) grid by vmap -------------------------------------------------------------------
    gam = np.linspace(0.05, 0.6, n_grid)
    dep = np.linspace(0.0, 40e-6, n_grid)
    GG, EE = np.meshgrid(gam, dep, indexing="ij")

    def grid_rms(g, e, mesh, torque):
        m = MemberModification(
            tip_relief_depth=e, tip_relief_extent=g, tip_relief_shape=LinearRelief()
        )
        return quasi_static(mesh, Modifications.symmetric(m), torque, positions_per_pitch=P0).te_rms

    grid_fn = jax.jit(jax.vmap(grid_rms, in_axes=(0, 0, None, None)))
    gargs = (jnp.asarray(GG.ravel()), jnp.asarray(EE.ravel()), mesh, jnp.asarray(torque))
    first = _first_call(lambda: grid_fn(*gargs), block)
    step("grid compile")
    t_grid = _min_time(lambda: grid_fn(*gargs), 2 if quick else 3, block)
    rms_grid = np.asarray(grid_fn(*gargs)).reshape(n_grid, n_grid)
    step("grid")
    # the same grid in chunks of CHUNK points (lax.map over vmap): keeps the working set in cache
    chunk_fn = jax.jit(
        lambda G, E, mesh, torque: jax.lax.map(
            lambda ge: grid_rms(ge[0], ge[1], mesh, torque), (G, E), batch_size=_CHUNK
        )
    )
    first_c = _first_call(lambda: chunk_fn(*gargs), block)
    t_chunk = _min_time(lambda: chunk_fn(*gargs), 2 if quick else 3, block)
    rms_chunk = np.asarray(chunk_fn(*gargs)).reshape(n_grid, n_grid)
    chunk_diff = float(np.max(np.abs(rms_chunk - rms_grid)) / np.max(rms_grid))
    step("grid chunked")
    # baseline: a few points spread over the grid, extrapolated to the whole grid
    rng = np.random.default_rng(0)
    picks = rng.choice(n_grid * n_grid, size=n_grid_np, replace=False)
    t_pts, diffs = [], []
    for p in picks:
        i, j = divmod(int(p), n_grid)
        mp = {
            t: bl.member_params(tip_relief_depth=EE[i, j], tip_relief_extent=GG[i, j])
            for t in ("pinion", "gear")
        }
        t0 = time.perf_counter()
        r = bl.te_curve_numpy(bmesh, mp, torque, "exact", positions_per_pitch=P0)
        t_pts.append(time.perf_counter() - t0)
        diffs.append(abs(rms_grid[i, j] - bl.te_rms(r["te"])) / np.max(rms_grid))
    step("grid baseline points")
    k_opt = np.unravel_index(np.argmin(rms_grid), rms_grid.shape)
    t_np_grid = float(np.mean(t_pts)) * n_grid * n_grid
    out["grid"] = {
        "shape": [n_grid, n_grid],
        "gamma": gam.tolist(),
        "tip_relief_depth_m": dep.tolist(),
        "relief": "symmetric linear tip relief, exact contact",
        "slices": N0,
        "positions_per_pitch": P0,
        "jaxgear_compile_s": first - t_grid,
        "jaxgear_first_call_s": first,
        "jaxgear_s": t_grid,
        "jaxgear_per_curve_s": t_grid / (n_grid * n_grid),
        "baseline_s_extrapolated": t_np_grid,
        "baseline_extrapolation": f"mean time of {n_grid_np} baseline TE curves at random grid "
        f"points × {n_grid * n_grid} (not run in full)",
        "ratio": t_np_grid / t_grid,
        "max_rel_diff_at_baseline_points": float(max(diffs)),
        "rel_diff_definition": "|RMS_jaxgear − RMS_baseline| / max over the grid of RMS",
        "target_s": 5.0,
        "meets_target": t_grid < 5.0,
        "chunked": {
            "how": f"jax.lax.map(..., batch_size={_CHUNK}) over the grid points (vmap "
            f"within chunks of {_CHUNK})",
            "jaxgear_s": t_chunk,
            "jaxgear_compile_s": first_c - t_chunk,
            "ratio_to_baseline": t_np_grid / t_chunk,
            "max_rel_diff_to_full_vmap": chunk_diff,
        },
        "te_rms_m": rms_grid.tolist(),
        "optimum": {
            "gamma": float(GG[k_opt]),
            "tip_relief_depth_m": float(EE[k_opt]),
            "te_rms_m": float(rms_grid[k_opt]),
        },
    }

    # (b2) repeated single curves through a cached jax.jit; (c2) batched throughput -------------
    out["cached_jit"] = _cached_jit(mesh, mods, torque, width, P0, rep_jax, per_curve)
    out["cached_jit"]["paired"] = _paired(
        mesh,
        mods,
        torque,
        P0,
        lambda: bl.te_curve_numpy(bmesh, bmods, torque, "exact", width, P0),
        rounds=3 if quick else 15,
    )
    step("cached jit")
    # the public per-curve call under both CPU dispatch modes, in interleaved blocks
    out["per_curve_blocks"] = paired_dispatch_modes(case, quick)
    step("per-curve blocks")
    out["batched"] = _batched(mesh, torque, P0, quick, per_curve)
    step("batched")

    # (d) speed vs accuracy: each contact model against its own converged reference ----------
    references, points = {}, []
    for model in models:
        extended = model == "case" and mesh.contact_geometry.reaches_beyond_path

        def mesh_of(n, extended=extended):
            m_n = c.mesh_model(slices=n)
            return m_n if extended else m_n.with_contact_geometry(TheoreticalPath())

        ref = quasi_static(mesh_of(ref_slices), mods, torque, positions_per_pitch=ref_ppp)
        ref_np = bl.te_curve_numpy(
            bl.baseline_mesh(c, slices=ref_slices, extended_contact=extended),
            bmods,
            torque,
            "exact",
            positions_per_pitch=ref_ppp,
        )
        references[model] = {
            "mode": "exact",
            "contact_model": model,
            "slices": ref_slices,
            "positions_per_pitch": ref_ppp,
            "te_rms_m": float(ref.te_rms),
            "baseline_te_rms_m": bl.te_rms(ref_np["te"]),
            "baseline_rel_diff": _rel(ref.transmission_error, ref_np["te"]),
        }
        ref_rms = float(ref.te_rms)
        step(f"reference ({model})")
        for n in sweep_slices:
            m_n = mesh_of(n)
            bm_n = bl.baseline_mesh(c, slices=n, extended_contact=extended)
            for p in sweep_ppp:
                fn = lambda m_n=m_n, p=p: quasi_static(m_n, mods, torque, positions_per_pitch=p)
                t_j = _min_time(fn, max(3, rep_jax // 3), block)
                rj = _rms(fn().transmission_error)
                t_b = _min_time(
                    lambda bm_n=bm_n, p=p: bl.te_curve_numpy(
                        bm_n, bmods, torque, "exact", positions_per_pitch=p
                    ),
                    rep_np,
                )
                rb = bl.te_rms(
                    bl.te_curve_numpy(bm_n, bmods, torque, "exact", positions_per_pitch=p)["te"]
                )
                points.append(
                    {
                        "mode": "exact",
                        "contact_model": model,
                        "slices": n,
                        "positions_per_pitch": p,
                        "jaxgear_s": t_j,
                        "baseline_s": t_b,
                        "te_rms_m": rj,
                        "error": abs(rj - ref_rms) / ref_rms,
                        "baseline_error": abs(rb - ref_rms) / ref_rms,
                    }
                )
                step(f"exact {model} N={n} P={p}")
    ref_rms = references["case"]["te_rms_m"]
    exact_same = _rms(calls["exact"]().transmission_error)
    for w in widths:
        fn = lambda w=w: quasi_static(
            mesh, mods, torque, contact=SmoothContact(w), positions_per_pitch=P0
        )
        t_j = _min_time(fn, max(3, rep_jax // 3), block)
        rj = _rms(fn().transmission_error)
        t_b = _min_time(
            lambda w=w: bl.te_curve_numpy(bmesh, bmods, torque, "smooth", w, P0), rep_np
        )
        rb = bl.te_rms(bl.te_curve_numpy(bmesh, bmods, torque, "smooth", w, P0)["te"])
        points.append(
            {
                "mode": "smooth",
                "contact_model": "case",
                "width_m": w,
                "slices": N0,
                "positions_per_pitch": P0,
                "jaxgear_s": t_j,
                "baseline_s": t_b,
                "te_rms_m": rj,
                "error": abs(rj - ref_rms) / ref_rms,
                "baseline_error": abs(rb - ref_rms) / ref_rms,
                "error_vs_exact_same_discretisation": abs(rj - exact_same) / exact_same,
            }
        )
        step(f"smooth w={w:g}")
    out["speed_accuracy"] = {
        "reference": references["case"],
        "references": references,
        "error": "|TE RMS − TE RMS_ref| / TE RMS_ref, each contact model against its own "
        "reference",
        "points": points,
        "chart": "speed_accuracy_quasi_static.png",
    }

    out["targets"] = {
        "per_curve_ratio_target": 50.0,
        "per_curve_ratio_exact": per_curve["exact"]["ratio"],
        "per_curve_ratio_smooth": per_curve["smooth"]["ratio"],
        "meets_ratio_exact": per_curve["exact"]["ratio"] >= 50.0,
        "meets_ratio_smooth": per_curve["smooth"]["ratio"] >= 50.0,
        "per_curve_ratio_cached_jit_exact": out["cached_jit"]["exact"]["ratio"],
        "per_curve_ratio_cached_jit_smooth": out["cached_jit"]["smooth"]["ratio"],
        "per_curve_ratio_public_compiled_exact": out["cached_jit"]["exact"][
            "ratio_public_compiled"
        ],
        "meets_ratio_public_compiled_exact": out["cached_jit"]["exact"]["ratio_public_compiled"]
        >= 50.0,
        "public_compiled_over_compute_target": 2.0,
        "public_compiled_over_compute_exact": out["cached_jit"]["exact"][
            "public_compiled_over_compute"
        ],
        "meets_public_compiled_over_compute_exact": out["cached_jit"]["exact"][
            "public_compiled_over_compute"
        ]
        <= 2.0,
        "per_curve_ratio_public_compiled_free_tip_exact": out["cached_jit"]["exact"][
            "ratio_public_compiled_free_tip"
        ],
        "meets_ratio_public_compiled_free_tip_exact": out["cached_jit"]["exact"][
            "ratio_public_compiled_free_tip"
        ]
        >= 50.0,
        "public_compiled_free_tip_over_compute_exact": out["cached_jit"]["exact"][
            "public_compiled_free_tip_over_compute"
        ],
        **_block_targets(out["per_curve_blocks"]),
        "batched_target_curves_per_s": 10000.0,
        "batched_curves_per_s": out["batched"]["best_curves_per_s"],
        "meets_batched": out["batched"]["best_curves_per_s"] >= 10000.0,
        "grid_target_s": 5.0,
        "grid_s": t_grid,
        "meets_grid": t_grid < 5.0,
        "agreement_1e-9": all(
            rec[m]["agree_1e-9"] for rec in per_model.values() for m in rec
        )
        and out["grid"]["max_rel_diff_at_baseline_points"] <= _TOL
        and all(r["baseline_rel_diff"] <= _TOL for r in references.values()),
    }
    bar.close()
    if hasattr(os, "getloadavg"):
        out["machine"]["load_average_at_end"] = list(os.getloadavg())

    os.makedirs(out_dir, exist_ok=True)
    _chart(out, os.path.join(out_dir, "speed_accuracy_quasi_static.png"), matplotlib, atomic_open)
    with atomic_open(os.path.join(out_dir, "bench_quasi_static.json"), "w") as f:
        json.dump(out, f, indent=1)
    if verbose:
        print(_table(out))
    if not out["targets"]["agreement_1e-9"]:
        raise RuntimeError(
            "jaxgear and the NumPy baseline disagree by more than 1e-9 relative: "
            f"see {os.path.join(out_dir, 'bench_quasi_static.json')}"
        )
    return out


def _per_curve(calls, bmesh, bmods, torque, width, P, rep_jax, rep_np, bl, block, step) -> dict:
    """Time per TE curve of jaxgear (``calls``: mode -> call) and of the baseline on ``bmesh``
    (the same contact model), exact and smooth: min of repeats, their ratio and the largest
    relative differences of TE, mesh stiffness, contact length and TE RMS."""
    per_curve = {}
    for mode in ("exact", "smooth"):
        t_jax = _min_time(calls[mode], rep_jax, block)
        step(f"jaxgear {mode}")
        res = calls[mode]()
        t_np = _min_time(
            lambda mode=mode: bl.te_curve_numpy(bmesh, bmods, torque, mode, width, P), rep_np
        )
        ref = bl.te_curve_numpy(bmesh, bmods, torque, mode, width, P)
        step(f"baseline {mode}")
        diff = {
            "te": _rel(res.transmission_error, ref["te"]),
            "mesh_stiffness": _rel(res.mesh_stiffness, ref["mesh_stiffness"]),
            "contact_length": _rel(res.contact_length, ref["contact_length"]),
            "te_rms": abs(float(res.te_rms) - bl.te_rms(ref["te"])) / bl.te_rms(ref["te"]),
        }
        per_curve[mode] = {
            "jaxgear_s": t_jax,
            "baseline_s": t_np,
            "ratio": t_np / t_jax,
            "max_rel_diff": diff,
            "agree_1e-9": max(diff.values()) <= _TOL,
            "te_rms_m": float(res.te_rms),
            "te_mean_m": float(res.te_mean),
            "baseline_mean_brentq_evaluations": float(np.mean(ref["evaluations"])),
        }
    return per_curve


def _block_targets(blocks: dict) -> dict:
    """The per-curve targets of the interleaved blocks (``per_curve_blocks``), per dispatch
    mode: the free-tip public call's ratio to the baseline (wall time; CPU time, the robust one
    under load) and its time over its compute, as median and quartiles over the blocks, and
    whether each target holds in the median and in the worse quartile."""
    out = {}
    for mode, rec in blocks["modes"].items():
        ratio = rec["ratio_baseline_over_public_free_tip"]
        over = rec["public_free_tip_over_compute"]
        key = f"public_compiled_free_tip_blocks_{mode}"
        out[f"{key}_ratio_median"] = ratio["median"]
        out[f"{key}_ratio_q1"] = ratio["q1"]
        out[f"{key}_ratio_q3"] = ratio["q3"]
        out[f"{key}_ratio_cpu_median"] = rec["ratio_baseline_over_public_free_tip_cpu"]["median"]
        out[f"{key}_ratio_cpu_q1"] = rec["ratio_baseline_over_public_free_tip_cpu"]["q1"]
        out[f"{key}_over_compute_median"] = over["median"]
        out[f"{key}_over_compute_q3"] = over["q3"]
        low = rec["public_free_tip_over_compute_from_block_minima"]
        out[f"{key}_over_compute_from_block_minima_median"] = low["median"]
        out[f"{key}_over_compute_from_block_minima_q3"] = low["q3"]
        out[f"meets_{key}_ratio_median"] = ratio["median"] >= 50.0
        out[f"meets_{key}_ratio_q1"] = ratio["q1"] >= 50.0
        out[f"meets_{key}_ratio_cpu_q1"] = out[f"{key}_ratio_cpu_q1"] >= 50.0
        out[f"meets_{key}_over_compute_median"] = over["median"] <= 2.0
        out[f"meets_{key}_over_compute_q3"] = over["q3"] <= 2.0
        out[f"meets_{key}_over_compute_from_block_minima_q3"] = low["q3"] <= 2.0
    return out


def _cached_jit(mesh, mods, torque, width, P, repeats, per_curve) -> dict:
    """Repeated single TE curves through a ``jax.jit`` built once (what a caller looping over
    curves should hold), and where the per-call time goes: dispatch vs compute."""
    import functools

    import jax
    import jax.numpy as jnp

    from jaxgear import compile_quasi_static, quasi_static

    block = jax.block_until_ready
    t = jnp.asarray(torque)
    out = {}
    # dispatch alone: a jitted identity taking the same pytrees (flatten, cache hit, launch)
    ident = jax.jit(lambda mesh, mods, t: t)
    t_dispatch = _min_time(lambda: ident(mesh, mods, t), repeats, block)
    ident1 = jax.jit(lambda t: t)
    t_dispatch1 = _min_time(lambda: ident1(t), repeats, block)
    for mode in ("exact", "smooth"):
        law = contact_law_from_name(mode, width)
        qs = functools.partial(quasi_static, contact=law, positions_per_pitch=P)
        full = jax.jit(qs)  # mesh and modifications as arguments
        te = jax.jit(lambda mesh, mods, t, qs=qs: qs(mesh, mods, t).transmission_error)
        closed = jax.jit(lambda t, qs=qs: qs(mesh, mods, t).transmission_error)  # constants
        t_full = _min_time(lambda full=full: full(mesh, mods, t), repeats, block)
        t_te = _min_time(lambda te=te: te(mesh, mods, t), repeats, block)
        t_closed = _min_time(lambda closed=closed: closed(t), repeats, block)
        # compute alone: 64 curves in one call (lax.map, no vmap), per curve
        many = jax.jit(lambda ts, qs=qs: jax.lax.map(lambda x: qs(mesh, mods, x).te_rms, ts))
        ts = jnp.full((64,), t)
        t_many = _min_time(lambda many=many, ts=ts: many(ts), max(3, repeats // 10), block) / 64
        # the public entry: jaxgear.compile_quasi_static, called with (design vector, torque)
        pub = compile_quasi_static(mesh, mods, contact=law, positions_per_pitch=P)
        pub_te = compile_quasi_static(
            mesh, mods, contact=law, positions_per_pitch=P, output=lambda r: r.transmission_error
        )
        x0 = pub.design0
        # compute alone when the design varies (the modifications' separation is then computed
        # in the program, not folded as a constant)
        t_many_x = _compute_per_design(qs, mesh, pub, t, repeats)
        # the design an optimiser of the pinion's tip relief varies (with_free): (E, Γ), the other
        # leaves compiled in as constants; its compute alone likewise
        free = lambda m: (m.pinion.tip_relief_depth, m.pinion.tip_relief_extent)
        pub_free = pub_te.with_free(free)
        xf = pub_free.design0
        t_many_f = _compute_per_design(qs, mesh, pub_free, t, repeats)
        t_pub_free = _min_time(lambda pf=pub_free, xf=xf: pf(xf, torque), repeats, block)
        t_pub = _min_time(lambda pub=pub, x0=x0: pub(x0, torque), repeats, block)
        t_pub_te = _min_time(lambda pub_te=pub_te, x0=x0: pub_te(x0, torque), repeats, block)
        t_api = _min_time(lambda qs=qs: qs(mesh, mods, torque), max(3, repeats // 5), block)
        diff_pub = _rel(pub(x0, torque).transmission_error, qs(mesh, mods, t).transmission_error)
        best = min(t_full, t_te, t_closed)
        base = per_curve[mode]["baseline_s"]
        out[mode] = {
            "jit_full_result_s": t_full,
            "jit_te_only_s": t_te,
            "jit_closure_te_only_s": t_closed,
            "compute_per_curve_in_loop_s": t_many,
            "best_s": best,
            "ratio": base / best,
            "ratio_compute_only": base / t_many,
            "public_quasi_static_s": t_api,
            "public_compiled_s": t_pub,
            "public_compiled_te_only_s": t_pub_te,
            "compute_per_curve_design_varying_s": t_many_x,
            "public_compiled_over_compute_design_varying": t_pub / t_many_x,
            "public_compiled_te_only_over_compute_design_varying": t_pub_te / t_many_x,
            "public_compiled_over_compute": t_pub / t_many,
            "public_compiled_te_only_over_compute": t_pub_te / t_many,
            "ratio_public_compiled": base / t_pub,
            "ratio_public_compiled_te_only": base / t_pub_te,
            "public_compiled_max_rel_diff_te": diff_pub,
            "public_compiled_free_tip_te_only_s": t_pub_free,
            "compute_per_curve_free_tip_s": t_many_f,
            "public_compiled_free_tip_over_compute": t_pub_free / t_many_f,
            "ratio_public_compiled_free_tip": base / t_pub_free,
        }
    out["dispatch_identity_same_args_s"] = t_dispatch
    out["dispatch_identity_scalar_s"] = t_dispatch1
    out["how"] = (
        "jax.jit(functools.partial(quasi_static, contact=..., positions_per_pitch=...)) "
        "built once and called with (mesh, mods, torque); te-only: the jitted function returns "
        "the TE array only; closure: mesh and mods closed over (constants), torque the only "
        "argument; compute per curve: 64 curves in one jitted lax.map, divided by 64; public "
        "compiled: jaxgear.compile_quasi_static(mesh, mods, contact=..., positions_per_pitch=...) "
        "built once, called as compiled(design0, torque) (the whole QuasiStaticResult, or with "
        "output= the TE only), input checks and result codes read at each call; public "
        "quasi_static: the plain jaxgear.quasi_static call; compute per curve, design varying: 64 "
        "design vectors (0.9..1.1 x the case's) in one jitted lax.map, divided by 64 (the "
        "compiled call's own reference: the other compute time has the modifications folded as "
        "constants); free tip: the TE-only compiled call's with_free(lambda m: "
        "(m.pinion.tip_relief_depth, m.pinion.tip_relief_extent)), the design of a tip-relief "
        "optimisation (2 leaves, the others compiled in as constants), and its compute alone "
        "(64 such designs in one jitted lax.map, divided by 64)"
    )
    return out


def _paired(mesh, mods, torque, P, baseline, rounds: int) -> dict:
    """The public compiled call against the NumPy/brentq baseline, interleaved in ``rounds``
    rounds (each: one baseline curve, 20 calls of each public form, one 64-design compute-only
    loop), min per curve over every call of wall time and of CPU time (``time.process_time``:
    every thread of the process); pairing in one process keeps the ratios meaningful under
    other jobs' load."""
    import jax
    import jax.numpy as jnp

    from jaxgear import compile_quasi_static, quasi_static

    block = jax.block_until_ready
    free = lambda m: (m.pinion.tip_relief_depth, m.pinion.tip_relief_extent)
    whole = compile_quasi_static(mesh, mods, positions_per_pitch=P)
    tip = compile_quasi_static(
        mesh, mods, positions_per_pitch=P, output=lambda r: r.transmission_error
    ).with_free(free)
    xs = tip.design0[None, :] * jnp.linspace(0.9, 1.1, 64)[:, None]
    t = jnp.asarray(torque)
    many = jax.jit(
        lambda xs: jax.lax.map(
            lambda x: quasi_static(mesh, tip.modifications(x), t, positions_per_pitch=P).te_rms,
            xs,
        )
    )
    calls = {  # name: (call, calls per round, curves per call)
        "public_compiled_free_tip_te_only": (lambda: tip(tip.design0, torque), 20, 1),
        "public_compiled_whole_result": (lambda: whole(whole.design0, torque), 20, 1),
        "compute_per_curve_free_tip": (lambda: many(xs), 1, 64),
        "baseline": (baseline, 1, 1),
    }
    wall = dict.fromkeys(calls, float("inf"))
    cpu = dict(wall)
    for fn, _, _ in calls.values():
        block(fn())
    for _ in range(rounds):
        for name, (fn, n, curves) in calls.items():
            for _ in range(n):
                w0, c0 = time.perf_counter(), time.process_time()
                block(fn())
                wall[name] = min(wall[name], (time.perf_counter() - w0) / curves)
                cpu[name] = min(cpu[name], (time.process_time() - c0) / curves)
    out = {
        "how": "min per curve over interleaved rounds, each: one baseline curve (NumPy/brentq, "
        "exact), 20 calls of the public compiled call with a 2-leaf tip-relief design "
        "(with_free, TE only, called as f(x, torque) with x a JAX array and torque a float), 20 "
        "with every modification leaf a design variable (whole result), and 64 tip-relief "
        "designs in one jitted lax.map (compute only, per curve); wall time and CPU time "
        "(time.process_time, all threads)",
        "rounds": rounds,
        "wall_s": wall,
        "cpu_s": cpu,
    }
    for clock in ("wall", "cpu"):
        best = out[f"{clock}_s"]
        out[clock] = {
            "ratio_public_compiled_free_tip": best["baseline"]
            / best["public_compiled_free_tip_te_only"],
            "ratio_public_compiled_whole_result": best["baseline"]
            / best["public_compiled_whole_result"],
            "public_compiled_free_tip_over_compute": best["public_compiled_free_tip_te_only"]
            / best["compute_per_curve_free_tip"],
        }
    return out


def _compute_per_design(qs, mesh, compiled, torque, repeats: int) -> float:
    """Compute alone of a compiled call's program when its design varies: 64 design vectors
    (0.9..1.1 x ``compiled.design0``) mapped to ``qs(mesh, compiled.modifications(x),
    torque).te_rms`` in one jitted ``lax.map`` (no vmap), min time over repeats divided by 64
    (s per curve)."""
    import jax
    import jax.numpy as jnp

    xs = compiled.design0[None, :] * jnp.linspace(0.9, 1.1, 64)[:, None]
    many = jax.jit(
        lambda xs: jax.lax.map(lambda x: qs(mesh, compiled.modifications(x), torque).te_rms, xs)
    )
    return _min_time(lambda: many(xs), max(3, repeats // 10), jax.block_until_ready) / 64


def _batched(mesh, torque, P, quick, per_curve) -> dict:
    """Throughput (curves/s) of batched exact TE curves: vmap over torques and over (Γ, E) tip
    reliefs, in chunks (``lax.map(..., batch_size=B)``) of several sizes."""
    import jax
    import jax.numpy as jnp

    from jaxgear import LinearRelief, MemberModification, Modifications, quasi_static

    block = jax.block_until_ready
    n = 256 if quick else 4096
    sizes = (8, 64) if quick else (8, 32, 128, 512)
    reps = 1 if quick else 2
    rng = np.random.default_rng(1)
    torques = jnp.asarray(torque * rng.uniform(0.5, 1.5, n))
    gam = jnp.asarray(rng.uniform(0.05, 0.6, n))
    dep = jnp.asarray(rng.uniform(0.0, 40e-6, n))

    def by_torque(x):
        m = MemberModification(tip_relief_depth=15e-6, tip_relief_extent=0.25)
        return quasi_static(mesh, Modifications.symmetric(m), x, positions_per_pitch=P).te_rms

    def by_relief(ge):
        m = MemberModification(
            tip_relief_depth=ge[1], tip_relief_extent=ge[0], tip_relief_shape=LinearRelief()
        )
        return quasi_static(mesh, Modifications.symmetric(m), torque, positions_per_pitch=P).te_rms

    rows = []
    for what, fn, args in (("torque", by_torque, torques), ("relief", by_relief, (gam, dep))):
        for b in sizes:
            g = jax.jit(lambda a, fn=fn, b=b: jax.lax.map(fn, a, batch_size=b))
            first = _first_call(lambda g=g, args=args: g(args), block)
            t = _min_time(lambda g=g, args=args: g(args), reps, block, warmup=False)
            rows.append(
                {
                    "vmap_over": what,
                    "batch_size": b,
                    "curves": n,
                    "time_s": t,
                    "compile_s": max(first - t, 0.0),
                    "curves_per_s": n / t,
                }
            )
    best = max(rows, key=lambda r: r["curves_per_s"])
    return {
        "how": "jax.jit(lambda a: jax.lax.map(curve_te_rms, a, batch_size=B)): vmap within "
        "chunks of B, exact contact, one TE curve = positions_per_pitch positions",
        "rows": rows,
        "best_curves_per_s": best["curves_per_s"],
        "best": {k: best[k] for k in ("vmap_over", "batch_size")},
        "baseline_curves_per_s": 1.0 / per_curve["exact"]["baseline_s"],
        "target_curves_per_s": 10000.0,
    }


def _profile(mesh, mods, torque, P, repeats, total_s) -> dict:
    """Time the stages of one exact TE curve, each jitted on its own (s)."""
    import jax
    import jax.numpy as jnp

    from jaxgear import mesh_positions, quasi_static, solve_contact

    block = jax.block_until_ready
    theta = mesh_positions(mesh, P)

    @jax.jit
    def cells(mesh, theta):
        return jax.vmap(mesh.cells)(theta)

    @jax.jit
    def deviations(mesh, mods, theta):
        c = jax.vmap(mesh.cells)(theta)
        e = mods.deviation(c.s / mesh.path_of_contact, c.z / mesh.face_width)
        e_max = jnp.max(jnp.where(c.mask, e, -jnp.inf), axis=(1, 2), keepdims=True)
        return c, jnp.where(c.mask, e_max - e, 0.0)

    c, d0 = deviations(mesh, mods, theta)
    n = c.s.shape[1] * c.s.shape[2]
    args = (
        c.stiffness.reshape(P, n),
        c.length.reshape(P, n),
        d0.reshape(P, n),
        c.mask.reshape(P, n),
    )
    Ks = jnp.zeros((1, 1))
    F = jnp.reshape(mesh.normal_load(jnp.asarray(torque)), (1,))
    V = jnp.ones((n, 1))

    @jax.jit
    def solve(k, l, d, m):
        def one(k, l, d, m):
            return solve_contact(Ks, F, V, k, l, d, m).x

        return jax.vmap(one)(k, l, d, m)

    @jax.jit
    def kernel(mesh, mods, theta, torque):
        r = quasi_static(mesh, mods, torque, theta)
        return r.transmission_error

    t_cells = _min_time(lambda: cells(mesh, theta), repeats, block)
    t_dev = _min_time(lambda: deviations(mesh, mods, theta), repeats, block)
    t_solve = _min_time(lambda: solve(*args), repeats, block)
    t_kernel = _min_time(lambda: kernel(mesh, mods, theta, jnp.asarray(torque)), repeats, block)
    return {
        "api_call_s": total_s,
        "jitted_kernel_te_only_s": t_kernel,
        "python_prep_and_dispatch_s": total_s - t_kernel,
        "cells_s": t_cells,
        "deviations_incl_cells_s": t_dev,
        "contact_solve_s": t_solve,
        "note": "each stage jitted on its own and timed alone (min of repeats); stages overlap "
        "in the fused kernel, so they need not add up to it",
    }


def _chart(out, path, matplotlib, atomic_open) -> None:
    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    pts = out["speed_accuracy"]["points"]
    model_of = lambda p: p.get("contact_model", "case")  # older records have none
    ex = [p for p in pts if p["mode"] == "exact" and model_of(p) == "case"]
    ex_th = [p for p in pts if p["mode"] == "exact" and model_of(p) == "theoretical_path"]
    sm = [p for p in pts if p["mode"] == "smooth"]
    floor = 1e-16
    r = out["speed_accuracy"]["reference"]
    extended = out["settings"].get("extended_contact", False)
    panels = 3 if ex_th else 2
    fig, axes = plt.subplots(1, panels, figsize=(5.5 * panels, 5), sharey=True)
    ax, ax2 = axes[0], axes[-1]
    ppp = sorted({p["positions_per_pitch"] for p in ex})
    cmap = plt.get_cmap("viridis")
    exact_panels = [(ax, ex, "contact beyond the path" if extended else "theoretical path")]
    if ex_th:
        exact_panels.append((axes[1], ex_th, "theoretical path"))
    for a, points, what in exact_panels:
        for i, p_ in enumerate(ppp):
            col = cmap(i / max(len(ppp) - 1, 1))
            sel = [p for p in points if p["positions_per_pitch"] == p_]
            a.plot(
                [p["jaxgear_s"] for p in sel],
                [max(p["error"], floor) for p in sel],
                "o-",
                color=col,
                label=f"jaxgear exact, P = {p_}",
            )
            a.plot(
                [p["baseline_s"] for p in sel],
                [max(p["baseline_error"], floor) for p in sel],
                "x--",
                color=col,
                label=f"baseline exact, P = {p_}",
            )
            for p in sel:
                a.annotate(
                    f"N={p['slices']}",
                    (p["jaxgear_s"], max(p["error"], floor)),
                    fontsize=6,
                    xytext=(2, 3),
                    textcoords="offset points",
                    color=col,
                )
        a.set_title(
            f"exact, {what} (both codes):\nN slices × P positions per pitch", fontsize=9
        )
    if sm:
        disc = f"{sm[0]['slices']}×{sm[0]['positions_per_pitch']}"
        ax2.plot(
            [p["jaxgear_s"] for p in sm],
            [max(p["error"], floor) for p in sm],
            "^-",
            color="C3",
            label=f"jaxgear smooth {disc}: vs converged reference",
        )
        ax2.plot(
            [p["baseline_s"] for p in sm],
            [max(p["baseline_error"], floor) for p in sm],
            "v-",
            color="C1",
            label=f"baseline smooth {disc}: vs converged reference",
        )
        ax2.plot(
            [p["jaxgear_s"] for p in sm],
            [max(p["error_vs_exact_same_discretisation"], floor) for p in sm],
            "^:",
            color="C3",
            mfc="none",
            label=f"jaxgear smooth: vs exact {disc} (contact-law error)",
        )
        for p in sm:
            ax2.annotate(
                f"w={p['width_m'] * 1e6:g} µm",
                (p["jaxgear_s"], max(p["error"], floor)),
                fontsize=6,
                xytext=(3, 3),
                textcoords="offset points",
                color="C3",
            )
        same = [
            p
            for p in ex
            if p["slices"] == sm[0]["slices"]
            and p["positions_per_pitch"] == sm[0]["positions_per_pitch"]
        ]
        if same:
            ax2.axhline(
                max(same[0]["error"], floor),
                color="grey",
                lw=0.8,
                ls="--",
                label=f"jaxgear exact {disc} (discretisation error)",
            )
        ax2.set_title(
            f"smooth, contact {'beyond the path' if extended else 'theoretical path'}: width w",
            fontsize=9,
        )
    for a in axes:
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlabel("time per TE curve (s, after compile)")
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=6)
    ax.set_ylabel(
        f"rel. TE RMS error vs exact {r['slices']} × {r['positions_per_pitch']} "
        "(same contact model)"
    )
    m = out["machine"]
    fig.suptitle(
        f"{out['case']}: speed vs accuracy — {m['cpu_count']} CPU ({m['cpu_model']}), "
        f"{out['dtype']}, JAX {out['versions']['jax']}",
        fontsize=9,
    )
    fig.tight_layout()
    thin_tick_labels(fig)
    with atomic_open(path, "wb") as f:
        fig.savefig(f, format="png", dpi=120)
    plt.close(fig)


def _table(out) -> str:
    pc, g = out["per_te_curve"], out["grid"]
    cpu = out["cached_jit"]["paired"]
    opt = g["optimum"]
    lines = [
        (
            f"quasi-static benchmark: {out['case']}, {out['settings']['slices']} slices × "
            f"{out['settings']['positions_per_pitch']} positions, {out['dtype']}, JAX "
            f"{out['versions']['jax']}, {out['machine']['device']}, "
            f"{out['machine']['cpu_count']} CPU"
        ),
        f"{'':24s}{'exact':>12s}{'smooth':>12s}",
        (
            f"{'compile (s)':24s}{out['compile']['exact']['compile_s']:12.3f}"
            f"{out['compile']['smooth']['compile_s']:12.3f}"
        ),
        (
            f"{'jaxgear per curve (ms)':24s}{pc['exact']['jaxgear_s'] * 1e3:12.3f}"
            f"{pc['smooth']['jaxgear_s'] * 1e3:12.3f}"
        ),
        (
            f"{'baseline per curve (ms)':24s}{pc['exact']['baseline_s'] * 1e3:12.3f}"
            f"{pc['smooth']['baseline_s'] * 1e3:12.3f}"
        ),
        f"{'ratio (target >= 50)':24s}{pc['exact']['ratio']:12.1f}{pc['smooth']['ratio']:12.1f}",
        (
            f"{'max rel diff (TE)':24s}{pc['exact']['max_rel_diff']['te']:12.1e}"
            f"{pc['smooth']['max_rel_diff']['te']:12.1e}"
        ),
        *_model_lines(out),
        (
            f"grid {g['shape'][0]}×{g['shape'][1]} (Γ, E), exact, vmap: {g['jaxgear_s']:.3f} s "
            f"after compile ({g['jaxgear_compile_s']:.1f} s compile; target < 5 s); baseline "
            f"~{g['baseline_s_extrapolated']:.1f} s (extrapolated), ratio {g['ratio']:.1f}"
        ),
        (
            f"same grid in vmap chunks of {_CHUNK} (lax.map): {g['chunked']['jaxgear_s']:.3f} s, "
            f"ratio {g['chunked']['ratio_to_baseline']:.1f}"
        ),
        (
            f"grid optimum: Γ = {opt['gamma']:.3f}, E = {opt['tip_relief_depth_m'] * 1e6:.1f} µm, "
            f"TE RMS = {opt['te_rms_m'] * 1e9:.1f} nm"
        ),
        (
            f"cached jax.jit, per curve (ms): exact "
            f"{out['cached_jit']['exact']['best_s'] * 1e3:.3f} "
            f"({out['cached_jit']['exact']['ratio']:.1f}×), smooth "
            f"{out['cached_jit']['smooth']['best_s'] * 1e3:.3f} "
            f"({out['cached_jit']['smooth']['ratio']:.1f}×); compute only (64 in one call) "
            f"{out['cached_jit']['exact']['compute_per_curve_in_loop_s'] * 1e3:.3f} / "
            f"{out['cached_jit']['smooth']['compute_per_curve_in_loop_s'] * 1e3:.3f} "
            f"({out['cached_jit']['exact']['ratio_compute_only']:.1f}× / "
            f"{out['cached_jit']['smooth']['ratio_compute_only']:.1f}×); dispatch "
            f"{out['cached_jit']['dispatch_identity_same_args_s'] * 1e3:.3f}"
        ),
        (
            f"public compiled call (compile_quasi_static), per curve (ms): exact "
            f"{out['cached_jit']['exact']['public_compiled_s'] * 1e3:.3f} "
            f"({out['cached_jit']['exact']['ratio_public_compiled']:.1f}× baseline, "
            f"{out['cached_jit']['exact']['public_compiled_over_compute_design_varying']:.2f}× "
            "compute with the design varying), TE only "
            f"{out['cached_jit']['exact']['public_compiled_te_only_s'] * 1e3:.3f} "
            f"({out['cached_jit']['exact']['ratio_public_compiled_te_only']:.1f}×), free tip "
            f"relief (2 design leaves), TE only "
            f"{out['cached_jit']['exact']['public_compiled_free_tip_te_only_s'] * 1e3:.3f} "
            f"({out['cached_jit']['exact']['ratio_public_compiled_free_tip']:.1f}×, "
            f"{out['cached_jit']['exact']['public_compiled_free_tip_over_compute']:.2f}× its "
            "compute); plain "
            f"quasi_static {out['cached_jit']['exact']['public_quasi_static_s'] * 1e3:.3f}"
        ),
        (
            "paired in one process (min per curve, wall / CPU): public compiled free tip "
            f"{cpu['wall_s']['public_compiled_free_tip_te_only'] * 1e3:.3f} / "
            f"{cpu['cpu_s']['public_compiled_free_tip_te_only'] * 1e3:.3f} ms "
            f"({cpu['wall']['ratio_public_compiled_free_tip']:.1f}× / "
            f"{cpu['cpu']['ratio_public_compiled_free_tip']:.1f}× baseline, "
            f"{cpu['wall']['public_compiled_free_tip_over_compute']:.2f}× / "
            f"{cpu['cpu']['public_compiled_free_tip_over_compute']:.2f}× its compute), whole "
            f"result {cpu['wall_s']['public_compiled_whole_result'] * 1e3:.3f} ms "
            f"({cpu['wall']['ratio_public_compiled_whole_result']:.1f}×); baseline "
            f"{cpu['wall_s']['baseline'] * 1e3:.3f} ms"
        ),
        *_block_lines(out["per_curve_blocks"]),
        (
            f"batched exact curves: best {out['batched']['best_curves_per_s']:.0f} curves/s "
            f"(vmap over {out['batched']['best']['vmap_over']}, chunks of "
            f"{out['batched']['best']['batch_size']}; target >= 10000)"
        ),
        f"chart: {out['speed_accuracy']['chart']}",
    ]
    return "\n".join(lines)


def _model_lines(out) -> list[str]:
    """The table's line saying which contact model the rows above compare, and a line per
    other contact model (both codes on it): per curve, ratio and largest TE difference."""
    models = out["settings"].get("contact_models", {})
    lines = [f"{'contact model':24s}{models.get('case', 'the case’s')}"]
    for name, rec in out.get("per_te_curve_by_contact_model", {}).items():
        if name == "case":
            continue
        e, s = rec["exact"], rec["smooth"]
        lines.append(
            f"{models.get(name, name)}: jaxgear {e['jaxgear_s'] * 1e3:.3f} / "
            f"{s['jaxgear_s'] * 1e3:.3f} ms, baseline {e['baseline_s'] * 1e3:.3f} / "
            f"{s['baseline_s'] * 1e3:.3f} ms (exact / smooth), ratio {e['ratio']:.1f} / "
            f"{s['ratio']:.1f}, max rel diff (TE) {e['max_rel_diff']['te']:.1e} / "
            f"{s['max_rel_diff']['te']:.1e}"
        )
    return lines


def _block_lines(blocks: dict) -> list[str]:
    """The table's lines of the interleaved blocks: per dispatch mode, the free-tip public
    call, its compute, the baseline and the ratios, median [q1, q3] over the blocks."""

    def ms(rec) -> str:
        return f"{rec['median'] * 1e3:.3f} [{rec['q1'] * 1e3:.3f}, {rec['q3'] * 1e3:.3f}]"

    def x(rec, digits: int) -> str:
        return f"{rec['median']:.{digits}f} [{rec['q1']:.{digits}f}, {rec['q3']:.{digits}f}]"

    lines = [
        (
            f"public free-tip call in {blocks['blocks']} interleaved blocks, median [q1, q3] "
            "over the blocks (ms, ×):"
        )
    ]
    for mode, rec in blocks["modes"].items():
        t = rec["seconds_per_curve"]
        lines.append(
            f"  {mode:5s} dispatch: call {ms(t['public_free_tip'])}, compute "
            f"{ms(t['compute_free_tip'])}, baseline {ms(t['baseline'])}; "
            f"{x(rec['ratio_baseline_over_public_free_tip'], 1)}× baseline (CPU time "
            f"{x(rec['ratio_baseline_over_public_free_tip_cpu'], 1)}×), "
            f"{x(rec['public_free_tip_over_compute'], 2)}× compute (block minima "
            f"{x(rec['public_free_tip_over_compute_from_block_minima'], 2)}×); whole result "
            f"{ms(t['public_whole_result'])}; program on the {rec['anatomy'].get('program_ran_on')}"
        )
    return lines
