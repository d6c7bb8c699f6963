"""Benchmark of the hybrid quasi-static model: condensed FE wheel vs rigid mesh.

``bench_hybrid(out_dir)`` is the body of ``jaxgear bench hybrid``. In one run, on the
``accessory-spur-flexible`` case (the wheel a condensed fem_prep body: 1290 rim master DOFs, 12
bearing DOFs, 51 modes), float64, it measures:

(1) time per TE curve after compile, hybrid scene (cell-space contact solve) against the rigid
    mesh of the same case (``case.mesh_model``), exact and smooth contact, both inside
    ``jax.jit`` (TE only) and through the public :func:`jaxgear.quasi_static` call; the compile
    time of each (first call minus a steady call, ``jax.clear_caches()`` first) and the ratios;
    the cost split: body load (fem_prep cache) or condensation (fem_prep's own timings, never
    forced), scene build (``static_scene`` with the body given), and the stages of one hybrid
    curve (cells and deviations, window compliance C = V G Vᵀ, contact solve), each jitted alone;
    and the same curves on the scene with its window compliance cached
    (:func:`jaxgear.scenes.cache_window_compliance`: exact law on the factored full contact
    set), interleaved with the uncached and rigid ones in runs of consecutive calls;
    ``jax.jit(jax.value_and_grad)`` of the TE RMS
    with respect to a tip relief depth (an optimisation iteration), rigid, cached, uncached;
(2) the 41×41 (tip-relief depth 0–30 µm × extent 0.05–0.6, linear, both members) map of TE RMS
    with the flexible wheel, ``jax.lax.map(..., batch_size=B)`` (vmap within chunks of B): total
    time, curves/s, compile time, peak RSS, on the cached scene and on the uncached one (before
    and after, the ratio); the same for the rigid mesh; and the vmappability check: the cached
    map's TE (RMS and curve) at one grid point against single public calls on the uncached
    scene;
(3) the cell-space scaling: cost per position against the window width (the wheel's
    ``n_window`` forced larger) and against the number of cells (slices), and the same curve with
    the small ``hybrid-test-wheel`` body (30 teeth, ~4× fewer structure DOFs) at equal cells and
    equal window: the cost follows cells and window, not the body's total DOF count.

Writes ``bench_hybrid.json`` and ``bench_hybrid.png``. Benchmarks are not tests: compile
separated, warm-up, ``block_until_ready``, min of repeats; machine, dtype and versions recorded.
"""

from __future__ import annotations

import dataclasses
import math
import os
import pathlib
import resource
import time

import numpy as np

from jaxgear import ExactContact
from jaxgear.io import contact_law_from_name

from ._charts import thin_tick_labels
from ._timing import environment, min_time

__all__ = ["bench_hybrid"]

_TARGET_RATIO = 20.0  # target: hybrid curve <= 20x a rigid-mesh curve after compile
# grid points per vmap chunk, the fastest of each on 2 cores: uncached 4 (of 1/4/16/64), rigid 8;
# the cached scene 1 (of 1/2/4/8: the active-set loop of a vmapped batch runs until its slowest
# position is done, and a smaller batch waits less)
_CHUNK = {"hybrid": 1, "hybrid_uncached": 4, "rigid": 8}
_TEST_CASE = (
    pathlib.Path(__file__).resolve().parents[1] / "tests" / "data" / "hybrid-test-case.toml"
)


# ------------------------------------------------------------------------------------------
# memory


def _status_kib(key: str) -> float | None:
    """A ``/proc/self/status`` entry (kiB), or None off Linux."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith(key + ":"):
                    return float(line.split()[1])
    except OSError:
        pass
    return None


class _PeakRSS:
    """Peak resident set size inside a block (MiB): the high-water mark is reset on entry
    (``/proc/self/clear_refs``, Linux) and read on exit (VmHWM); ``ru_maxrss`` (the process's
    peak so far, ``resource.getrusage``) is recorded too."""

    def __enter__(self):
        try:
            with open("/proc/self/clear_refs", "w") as f:
                f.write("5")
            self.reset = True
        except OSError:
            self.reset = False
        self.start = _status_kib("VmRSS")
        return self

    def __exit__(self, *exc):
        hwm = _status_kib("VmHWM")
        self.result = {
            "rss_at_start_mib": None if self.start is None else self.start / 1024,
            "peak_rss_mib": hwm / 1024 if (self.reset and hwm is not None) else None,
            "ru_maxrss_process_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        }
        if self.result["peak_rss_mib"] is not None and self.start is not None:
            self.result["peak_over_start_mib"] = self.result["peak_rss_mib"] - self.start / 1024


# ------------------------------------------------------------------------------------------
# helpers


def _body_build(ref) -> dict:
    """Load (or, if not cached, build) a condensed body through fem_prep's cache and report its
    sizes and fem_prep's own timings (``summary.json``)."""
    import json

    import fem_prep

    body = fem_prep.load_body(ref)
    entry = fem_prep.cache_dir() / fem_prep.cache_key(body)  # reading it forces nothing
    hit = entry is not None and (entry / "summary.json").is_file()
    t0 = time.perf_counter()
    cond = fem_prep.condensed(ref)
    t = time.perf_counter() - t0
    summary = {}
    if entry is not None and (entry / "summary.json").is_file():
        summary = json.loads((entry / "summary.json").read_text())
    kind = np.asarray(cond.dof_map)[:, 0]
    n_modes = int(np.sum(kind < 0))
    n_rim = int(np.asarray(cond.rim_grid).size * 3)
    return {
        "body": body.name,
        "condensed_dofs": int(cond.K.shape[0]),
        "rim_master_dofs": n_rim,
        "bearing_dofs": int(cond.K.shape[0]) - n_rim - n_modes,
        "modes": n_modes,
        "full_fe_dofs": summary.get("n_dofs", cond.metadata.get("n_dofs")),
        "cache_hit": bool(hit),
        "load_or_build_s": t,
        "fem_prep_timings_s": summary.get("timings_s"),
        "note": "cache_hit: load_or_build_s is the cache read; fem_prep_timings_s are those of "
        "the condensation when the body was built (fem_prep summary.json)",
    }, cond


def _with_window(scene, member: int, n_window: int):
    """The scene with flexible member ``member``'s window forced to ``n_window`` stations."""
    import equinox as eqx

    members = list(scene.members)
    members[member] = dataclasses.replace(members[member], n_window=int(n_window))
    return eqx.tree_at(lambda s: s.members, scene, tuple(members))


def _flex_index(scene) -> int:
    from jaxgear.scenes import FlexibleMember

    return next(i for i, m in enumerate(scene.members) if isinstance(m, FlexibleMember))


def _window_dofs(scene) -> int:
    return int(sum(m.width for m in scene.members))


def _cells(mesh) -> int:
    import jax.numpy as jnp

    return int(np.prod(mesh.cells(jnp.asarray(0.0, mesh.base_pitch.dtype)).s.shape))


def _jit_te(mods, P, mode, width):
    """``jax.jit`` of the TE curve of a scene or mesh (scene and torque as arguments)."""
    import jax

    from jaxgear import quasi_static

    return jax.jit(
        lambda s, T: (
            quasi_static(
                s, mods, T, contact=contact_law_from_name(mode, width), positions_per_pitch=P
            ).transmission_error
        )
    )


# ------------------------------------------------------------------------------------------
# the benchmark


def hybrid_cases(c, case, compare_case, what: str):
    """Check that the loaded case ``c`` has a condensed body, and resolve the comparison case of
    the scaling runs: None when missing, ``None`` or the same file as ``case``."""
    if c.scene is None or not c.scene.hybrid:
        raise ValueError(f"{what}: case {c.name!r} has no condensed body ([scene.*_body])")
    if compare_case is None:
        return None
    cp = pathlib.Path(compare_case)
    same = cp.suffix == ".toml" and pathlib.Path(str(case)).resolve() == cp.resolve()
    return None if (same or (cp.suffix == ".toml" and not cp.is_file())) else cp


def bench_hybrid(
    out_dir,
    quick: bool = False,
    case: str = "accessory-spur-flexible",
    compare_case: str | os.PathLike | None = _TEST_CASE,
    progress: bool = True,
    verbose: bool = True,
) -> dict:
    """Run the hybrid benchmark and write ``bench_hybrid.json`` and ``bench_hybrid.png`` into
    ``out_dir`` (atomically).

    Args:
        out_dir: output folder (created if missing).
        quick: a smoke run: 5×5 map, 8 slices, 16 positions per pitch, fewer repeats, two
            points per scaling line.
        case: embedded case name or TOML path of a case with a condensed body (default the
            accessory pair with its flexible wheel).
        compare_case: a case with another (smaller) condensed body, timed at equal cells and
            window (default ``tests/data/hybrid-test-case.toml`` of a source checkout; skipped
            when missing, ``None`` or the same file as ``case``).
        progress: show a tqdm progress bar. verbose: print the summary table.

    Returns:
        the JSON-ready dict that was written.
    """
    import jax

    jax.config.update("jax_enable_x64", True)  # entry point: float64
    import jax.numpy as jnp
    from tqdm.auto import tqdm

    from jaxgear import LinearRelief, MemberModification, Modifications, quasi_static
    from jaxgear.io import load_case, static_scene, write_json

    block = jax.block_until_ready
    env = environment()
    c = load_case(case)
    compare_case = hybrid_cases(c, case, compare_case, "bench hybrid")
    if quick:
        slices, P, n_grid = 8, 16, 5
        rep, rep_rigid, rep_map = 3, 10, 1
        windows_extra, slices_list = (4,), (8, 16)
    else:
        slices, P, n_grid = 40, c.positions_per_pitch, 41
        rep, rep_rigid, rep_map = 20, 100, 2
        windows_extra, slices_list = (3, 7, 15), (8, 16, 24, 40, 80)
    torque = c.torque
    T = jnp.asarray(torque)
    mods = c.modifications
    width = c.smooth_width
    modes = ("exact", "smooth")
    n_steps = 2 + 8 + 1 + 1 + 1 + 3 + 2 + len(windows_extra) + 1 + len(slices_list) + 1
    bar = tqdm(total=n_steps, desc="bench hybrid", disable=not progress, leave=False)

    wall: dict = {}
    t_last = [time.perf_counter()]

    def step(msg):
        now = time.perf_counter()
        wall[msg] = now - t_last[0]
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
            "slices": slices,
            "positions_per_pitch": P,
            "torque_Nm": torque,
            "smooth_width_m": width,
            "speed_rad_s": 0.0,
            "repeats_hybrid": rep,
            "repeats_rigid": rep_rigid,
            "timing": "min of repeats after a warm-up call, jax.block_until_ready on the whole "
            "result; compile = first call (after jax.clear_caches()) minus the steady time",
        },
    }

    # (1a) body and scene: the cost split of the set-up ---------------------------------------
    bodies_info, bodies = [], []
    for ref in c.scene.bodies:
        if ref is None:
            bodies.append(None)
            continue
        info, cond = _body_build(ref)
        bodies_info.append(info)
        bodies.append(cond)
    bodies = tuple(bodies)
    step("body")
    t0 = time.perf_counter()
    sc, _ = static_scene(c, slices=slices, bodies=bodies)
    t_scene = time.perf_counter() - t0
    mesh = c.mesh_model(slices=slices)
    fi = _flex_index(sc)
    step("scene")
    out["setup"] = {
        "bodies": bodies_info,
        "static_scene_s": t_scene,
        "static_scene_note": "jaxgear.io.static_scene with the condensed body given (body "
        "already loaded): shafts, hybrid_pair (structure factored once, G), window check",
        "structure_dofs": int(sc.structure.K.shape[0]),
        "cells_per_position": _cells(sc.mesh),
        "window_stations": int(sc.members[fi].n_window),
        "window_dofs": _window_dofs(sc),
    }

    # (1b) compile time and time per TE curve ------------------------------------------------
    models = {"hybrid": sc, "rigid": mesh}
    jitted = {(m, mode): _jit_te(mods, P, mode, width) for m in models for mode in modes}

    def public(m, mode):
        return lambda: quasi_static(
            models[m], mods, T, contact=contact_law_from_name(mode, width), positions_per_pitch=P
        )

    def inside(m, mode):
        return lambda: jitted[m, mode](models[m], T)

    # the hybrid exact jit last: it stays compiled for the scaling rows at the default window
    calls = {
        (m, mode, how): (inside if how == "jit" else public)(m, mode)
        for m in ("rigid", "hybrid")
        for mode in ("smooth", "exact")
        for how in ("public", "jit")
    }
    curves: dict = {m: {mode: {} for mode in modes} for m in models}
    results = {}
    for key, fn in calls.items():
        m, mode, how = key
        jax.clear_caches()
        t0 = time.perf_counter()
        results[key] = block(fn())
        first = time.perf_counter() - t0
        t = min_time(fn, rep if m == "hybrid" else rep_rigid, block, warmup=False)
        curves[m][mode][how] = {
            "first_call_s": first,
            "compile_s": max(first - t, 0.0),
            "per_curve_s": t,
            "per_position_s": t / P,
        }
        step(f"{m} {mode} {how}")
    ratios = {
        mode: {
            how: curves["hybrid"][mode][how]["per_curve_s"]
            / curves["rigid"][mode][how]["per_curve_s"]
            for how in ("jit", "public")
        }
        for mode in modes
    }
    ratios["hybrid_public_over_rigid_jit_exact"] = (
        curves["hybrid"]["exact"]["public"]["per_curve_s"]
        / curves["rigid"]["exact"]["jit"]["per_curve_s"]
    )
    res_h = results["hybrid", "exact", "public"]
    res_r = results["rigid", "exact", "public"]
    out["te_curve"] = {
        "what": "one TE curve = positions_per_pitch positions over one mesh period; 'jit': "
        "jax.jit(lambda scene, T: quasi_static(...).transmission_error) (TE only: the "
        "coordinates X are not recovered); 'public': jaxgear.quasi_static(...) (the whole "
        "result, X included)",
        "hybrid": curves["hybrid"],
        "rigid": curves["rigid"],
        "ratio_hybrid_over_rigid": ratios,
        "target_ratio": _TARGET_RATIO,
        "meets_target_jit_exact": ratios["exact"]["jit"] <= _TARGET_RATIO,
        "meets_target_public_exact": ratios["exact"]["public"] <= _TARGET_RATIO,
        "hybrid_te_rms_m": float(res_h.te_rms),
        "rigid_te_rms_m": float(res_r.te_rms),
        "hybrid_te_mean_m": float(res_h.te_mean),
        "rigid_te_mean_m": float(res_r.te_mean),
        "hybrid_mean_contact_passes": float(jnp.mean(res_h.iterations)),
    }
    # the window compliance cached once per scene (it depends on the scene and the position
    # only) with the exact law's full-contact-set inverse: the same TE curves inside jit, each
    # measured in turns with the uncached one and the rigid mesh (the ratios robust to the load)
    from jaxgear.scenes import cache_window_compliance

    t0 = time.perf_counter()
    cached = block(cache_window_compliance(sc, positions_per_pitch=P))
    t_cache = time.perf_counter() - t0
    cached_rows = {}
    for mode in modes:
        fn = jitted["hybrid", mode]
        te_c = block(fn(cached, T))
        te_u = block(fn(sc, T))
        t_c, t_u, rigid_t = _interleaved(
            [lambda fn=fn, s=s: fn(s, T) for s in (cached, sc, mesh)], rep, block
        )
        cached_rows[mode] = {
            "per_curve_s": t_c,
            "uncached_per_curve_s": t_u,
            "rigid_per_curve_s": rigid_t,
            "speedup": t_u / t_c,
            "ratio_over_rigid_jit": t_c / rigid_t,
            "uncached_ratio_over_rigid_jit": t_u / rigid_t,
            "meets_target": t_c / rigid_t <= _TARGET_RATIO,
            "te_max_rel_diff": float(np.max(np.abs(np.asarray(te_c) - np.asarray(te_u))))
            / float(np.max(np.abs(np.asarray(te_u)))),
        }
    cc = cached.compliance
    out["te_curve"]["hybrid_cached_compliance"] = {
        "what": "jaxgear.scenes.cache_window_compliance(scene, positions_per_pitch=P): the "
        "windows, structure vectors, C = V_W G V_W^T, the inverse of each position's full "
        "contact set and the TE rows formed once per scene; the TE curve inside jit as 'jit' "
        "(a relief map, a torque sweep, an optimisation iteration). Exact: first active-set "
        "pass a product, later passes a Schur complement; smooth: Newton on the cached C. "
        f"Cached, uncached and rigid calls in turns of {_RUN} consecutive calls each, min of "
        "each (the ratio over rigid from these rigid_per_curve_s)",
        **cached_rows["exact"],
        "smooth": cached_rows["smooth"],
        "cache_build_s": t_cache,
        "cache_mib": sum(np.asarray(x).nbytes for x in jax.tree_util.tree_leaves(cc)) / 2**20,
    }
    step("hybrid exact jit, cached compliance")
    out["gradient"] = _gradients(sc, cached, mesh, mods, T, P, rep, width)
    step("gradients")
    out["cost_split"] = _profile(sc, mods, T, P, rep, curves["hybrid"]["exact"])
    step("profile")

    # (2) the relief map ---------------------------------------------------------------------
    ext = np.linspace(0.05, 0.6, n_grid)
    dep = np.linspace(0.0, 30e-6, n_grid)
    EE, GG = np.meshgrid(dep, ext, indexing="ij")  # rows: depth, columns: extent
    Ev, Gv = jnp.asarray(EE.ravel()), jnp.asarray(GG.ravel())

    def relief(e, g):
        m = MemberModification(
            tip_relief_depth=e, tip_relief_extent=g, tip_relief_shape=LinearRelief()
        )
        return Modifications.symmetric(m)

    def curve(e, g, s, T):
        return quasi_static(s, relief(e, g), T, positions_per_pitch=P)

    maps, te_map = {}, {}
    for name, s in (("rigid", mesh), ("hybrid_uncached", sc), ("hybrid", cached)):
        B = _CHUNK[name]
        fn = jax.jit(
            lambda E, G, s, T, B=B: jax.lax.map(
                lambda eg: curve(eg[0], eg[1], s, T).transmission_error, (E, G), batch_size=B
            )
        )
        with _PeakRSS() as mem:
            t0 = time.perf_counter()
            te_map[name] = np.asarray(block(fn(Ev, Gv, s, T)))
            first = time.perf_counter() - t0
            t = min_time(lambda fn=fn, s=s: fn(Ev, Gv, s, T), rep_map, block, warmup=False)
        rms = np.sqrt(np.mean((te_map[name] - te_map[name].mean(1, keepdims=True)) ** 2, 1))
        rms = rms.reshape(n_grid, n_grid)
        n = n_grid * n_grid
        k = np.unravel_index(np.argmin(rms), rms.shape)
        maps[name] = {
            "how": f"jax.jit(jax.lax.map(te_curve, grid, batch_size={B})): vmap within chunks "
            f"of {B} grid points; TE RMS about the mean per grid point",
            "batch_size": B,
            "curves": n,
            "total_s": t,
            "per_curve_s": t / n,
            "curves_per_s": n / t,
            "first_call_s": first,
            "compile_s": max(first - t, 0.0),
            "memory": mem.result,
            "te_rms_m": rms.tolist(),
            "optimum": {
                "tip_relief_depth_m": float(EE[k]),
                "tip_relief_extent": float(GG[k]),
                "te_rms_m": float(rms[k]),
            },
        }
        step(f"map {name}")
    # vmappability: the map's TE curve and RMS at one grid point = a single public call
    i, j = n_grid // 2, n_grid // 3
    kk = i * n_grid + j
    single = curve(Ev[kk], Gv[kk], sc, T)
    te_single = np.asarray(single.transmission_error)
    te_vmap = te_map["hybrid"][kk]
    hm = maps["hybrid"]
    rms_map = hm["te_rms_m"][i][j]
    hm["vmap_check"] = {
        "grid_index": [i, j],
        "tip_relief_depth_m": float(EE[i, j]),
        "tip_relief_extent": float(GG[i, j]),
        "te_rms_map_m": rms_map,
        "te_rms_single_m": float(single.te_rms),
        "te_rms_rel_diff": abs(rms_map - float(single.te_rms)) / float(single.te_rms),
        "te_curve_max_rel_diff": float(
            np.max(np.abs(te_vmap - te_single)) / np.max(np.abs(te_single))
        ),
        "what": "TE curve and TE RMS from the lax.map/vmap grid against a single "
        "jaxgear.quasi_static call at the same grid point",
    }
    step("vmap check")
    out["relief_map"] = {
        "shape": [n_grid, n_grid],
        "tip_relief_depth_m": dep.tolist(),
        "tip_relief_extent": ext.tolist(),
        "relief": "linear tip relief on both members, exact contact",
        "slices": slices,
        "positions_per_pitch": P,
        "hybrid": maps["hybrid"],
        "hybrid_uncached": maps["hybrid_uncached"],
        "rigid": maps["rigid"],
        "hybrid_what": "'hybrid': the scene with its window compliance cached "
        "(cache_window_compliance, built once, outside the timing: cache_build_s); "
        "'hybrid_uncached': the same map on the scene without the cache (before)",
        "cache_build_s": t_cache,
        "speedup_cached_over_uncached": maps["hybrid_uncached"]["total_s"]
        / maps["hybrid"]["total_s"],
        "te_rms_max_rel_diff_cached_uncached": float(
            np.max(
                np.abs(np.asarray(maps["hybrid"]["te_rms_m"]) - maps["hybrid_uncached"]["te_rms_m"])
            )
            / np.max(np.abs(maps["hybrid_uncached"]["te_rms_m"]))
        ),
        "ratio_hybrid_over_rigid_per_curve": maps["hybrid"]["per_curve_s"]
        / maps["rigid"]["per_curve_s"],
        "ratio_hybrid_uncached_over_rigid_per_curve": maps["hybrid_uncached"]["per_curve_s"]
        / maps["rigid"]["per_curve_s"],
        "per_curve_note": "the map's time per curve can be below a single curve's: the cells "
        "and the window compliance C = V G Vᵀ do not depend on the relief, so XLA evaluates them "
        "once per map call (loop-invariant in lax.map); what is left per curve is about the "
        "contact solve of cost_split",
        "memory_note": "peak_rss_mib: VmHWM of the process, reset at the start of the map "
        "(compile and runs included); ru_maxrss_process_mib: the process peak so far",
    }

    # (3) scaling: window, cells, body size ---------------------------------------------------
    te_exact = jitted["hybrid", "exact"]
    w0 = int(sc.members[fi].n_window)
    rows_w = []
    for extra in (0, *windows_extra):
        s = _with_window(sc, fi, w0 + extra)
        t = min_time(lambda s=s: te_exact(s, T), max(3, rep // 4), block)
        te_diff = float(
            jnp.max(jnp.abs(te_exact(s, T) - te_exact(sc, T))) / jnp.max(jnp.abs(te_exact(sc, T)))
        )
        rows_w.append(
            {
                "window_stations": w0 + extra,
                "window_dofs": _window_dofs(s),
                "cells_per_position": _cells(sc.mesh),
                "per_curve_s": t,
                "per_position_s": t / P,
                "te_rel_diff_to_default_window": te_diff,
            }
        )
        step(f"window {w0 + extra}")
    rows_c = []
    for n in slices_list:
        s = sc if n == slices else static_scene(c, slices=n, bodies=bodies)[0]
        t = min_time(lambda s=s: te_exact(s, T), max(3, rep // 4), block)
        rows_c.append(
            {
                "slices": n,
                "cells_per_position": _cells(s.mesh),
                "window_dofs": _window_dofs(s),
                "per_curve_s": t,
                "per_position_s": t / P,
            }
        )
        step(f"slices {n}")
    out["scaling"] = {
        "what": "hybrid exact TE curve inside jax.jit (TE only), per position; the window "
        "forced larger (FlexibleMember.n_window) at the bench slices; the slices varied at the "
        "default window",
        "window": rows_w,
        "cells": rows_c,
        "body_size": _compare_bodies(c, sc, bodies_info, compare_case, slices, P, rep, T)
        if compare_case is not None
        else {"skipped": "no other hybrid case (compare_case missing, None or the same)"},
    }
    step("body size")
    bar.close()
    out["wall_s"] = {"total": sum(wall.values()), "steps": wall}

    os.makedirs(out_dir, exist_ok=True)
    write_json(os.path.join(out_dir, "bench_hybrid.json"), out)
    hybrid_chart(out, os.path.join(out_dir, "bench_hybrid.png"))
    if verbose:
        print(_table(out))
    return out


def _compare_bodies(c, sc, bodies_info, compare_case, slices, P, rep, T) -> dict:
    """The hybrid TE curve of ``c`` and of ``compare_case`` (another condensed body) at equal
    slices and positions and an equal window width (each flexible member's window widened to
    the least common width that holds both defaults)."""
    import jax
    import jax.numpy as jnp

    from jaxgear import quasi_static
    from jaxgear.io import load_case, static_scene

    c2 = load_case(compare_case)
    info2, bodies2 = [], []
    for ref in c2.scene.bodies:
        if ref is None:
            bodies2.append(None)
            continue
        info, cond = _body_build(ref)
        info2.append(info)
        bodies2.append(cond)
    sc2 = static_scene(c2, slices=slices, bodies=tuple(bodies2))[0]
    f1, f2 = _flex_index(sc), _flex_index(sc2)
    per1 = sc.members[f1].width // sc.members[f1].n_window  # DOFs per rim station
    per2 = sc2.members[f2].width // sc2.members[f2].n_window
    lcm = per1 * per2 // math.gcd(per1, per2)
    need = max(sc.members[f1].width, sc2.members[f2].width)
    wd = lcm * math.ceil(need / lcm)
    a = _with_window(sc, f1, wd // per1)
    b = _with_window(sc2, f2, wd // per2)
    rows = []
    for name, case_, s, info in ((c.name, c, a, bodies_info), (c2.name, c2, b, info2)):
        fn = _jit_te(case_.modifications, P, "exact", case_.smooth_width)
        Tc = jnp.asarray(case_.torque)
        t = min_time(lambda fn=fn, s=s, Tc=Tc: fn(s, Tc), max(5, rep // 2), jax.block_until_ready)

        def pub(s=s, case_=case_, Tc=Tc):
            return quasi_static(s, case_.modifications, Tc, positions_per_pitch=P)

        tp = min_time(pub, max(5, rep // 2), jax.block_until_ready)
        rows.append(
            {
                "case": name,
                "body": info[0]["body"] if info else None,
                "condensed_body_dofs": info[0]["condensed_dofs"] if info else None,
                "rim_master_dofs": info[0]["rim_master_dofs"] if info else None,
                "modes": info[0]["modes"] if info else None,
                "structure_dofs": int(s.structure.size),
                "cells_per_position": _cells(s.mesh),
                "window_stations": int(s.members[_flex_index(s)].n_window),
                "window_dofs": _window_dofs(s),
                "mean_contact_passes": float(jnp.mean(pub().iterations)),
                "jit_per_curve_s": t,
                "jit_per_position_s": t / P,
                "public_per_curve_s": tp,
                "public_per_position_s": tp / P,
            }
        )
    return {
        "what": "the same hybrid TE curve (exact, slices and positions as above) with two "
        "condensed bodies of very different size, at equal cells and equal window DOFs: 'jit' "
        "(TE only) costs O(cells² + cells·window) per position; 'public' also recovers X = G "
        "(F − Vᵀ P) + N α, O(structure DOFs²) per position",
        "rows": rows,
        "jit_time_ratio": rows[0]["jit_per_curve_s"] / rows[1]["jit_per_curve_s"],
        "public_time_ratio": rows[0]["public_per_curve_s"] / rows[1]["public_per_curve_s"],
        "structure_dofs_ratio": rows[0]["structure_dofs"] / rows[1]["structure_dofs"],
    }


_RUN = 5  # consecutive calls of one function per turn of _interleaved


def _interleaved(fns, repeats: int, block) -> list[float]:
    """Min times (s) of the functions ``fns`` (each warmed up), taken in turns of :data:`_RUN`
    consecutive calls each, ``repeats`` calls in all per function: a load that comes and goes
    on a shared machine falls on all alike, and each function runs back to back as in a loop
    (a call right after another function's finds its caches evicted: alternating single calls
    of the cached curve with the uncached one's 15 MB structure compliance made it 3× slower)."""
    for fn in fns:
        block(fn())
    ts: list[list[float]] = [[] for _ in fns]
    for _ in range(max(1, -(-repeats // _RUN))):
        for fn, t in zip(fns, ts, strict=True):
            for _ in range(_RUN):
                t0 = time.perf_counter()
                block(fn())
                t.append(time.perf_counter() - t0)
    return [min(t) for t in ts]


def _gradients(sc, cached, mesh, mods, T, P, repeats, width) -> dict:
    """``jax.jit(jax.value_and_grad)`` of the TE RMS (µm) with respect to the gear's tip relief
    depth, as an optimisation iteration evaluates it: the rigid mesh, the hybrid scene with its
    window compliance cached and without, exact and smooth contact (s per evaluation, min of
    interleaved runs, :func:`_interleaved`), and the cached gradient against the uncached
    one."""
    import dataclasses

    import jax
    import jax.numpy as jnp

    from jaxgear import quasi_static

    block = jax.block_until_ready
    d0 = jnp.asarray(max(float(mods.gear.tip_relief_depth), 5e-6))

    def make(mode):
        law = contact_law_from_name(mode, width)

        def rms_um(s, d):
            g = dataclasses.replace(mods.gear, tip_relief_depth=d)
            m = dataclasses.replace(mods, gear=g)
            return quasi_static(s, m, T, contact=law, positions_per_pitch=P).te_rms / 1e-6

        return jax.jit(jax.value_and_grad(rms_um, argnums=1))

    rows = {}
    for mode in ("exact", "smooth"):
        fn = make(mode)
        block(fn(mesh, d0))
        vc, gc = block(fn(cached, d0))
        vu, gu = block(fn(sc, d0))
        t_c, t_u, t_r = _interleaved(
            [lambda fn=fn, s=s: fn(s, d0) for s in (cached, sc, mesh)], repeats, block
        )
        rows[mode] = {
            "rigid_s": t_r,
            "hybrid_cached_s": t_c,
            "hybrid_uncached_s": t_u,
            "speedup": t_u / t_c,
            "ratio_cached_over_rigid": t_c / t_r,
            "ratio_uncached_over_rigid": t_u / t_r,
            "grad_cached_um_per_m": float(gc),
            "grad_uncached_um_per_m": float(gu),
            "grad_rel_diff": abs(float(gc) - float(gu)) / abs(float(gu)),
            "value_rel_diff": abs(float(vc) - float(vu)) / abs(float(vu)),
        }
    return {
        "what": "jax.jit(jax.value_and_grad(TE RMS wrt the gear's tip relief depth)) at the "
        f"case's design ({float(d0) * 1e6:.2f} um), one evaluation of an optimisation "
        "iteration: rigid mesh, hybrid cached, hybrid uncached",
        **rows,
    }


def _profile(sc, mods, T, P, repeats, hybrid_exact) -> dict:
    """Time the stages of one hybrid exact TE curve, each jitted on its own (s)."""
    import jax

    from jaxgear import mesh_positions, separation, solve_contact_cells

    block = jax.block_until_ready
    theta = mesh_positions(sc.mesh, P)

    @jax.jit
    def cells(sc, mods, theta):
        return jax.vmap(lambda th: separation(sc.mesh, mods, th))(theta)

    @jax.jit
    def space(sc, mods, theta, T):
        def one(th):
            cl, _, d0 = separation(sc.mesh, mods, th)
            C, a0, E, b, _ = sc.cell_space(sc.window_row((cl,), (d0,)), T)
            n = cl.stiffness.size
            return (
                C,
                a0 - d0.reshape(-1),
                E,
                b,
                cl.stiffness.reshape(n),
                cl.length.reshape(n),
                cl.mask.reshape(n),
            )

        return jax.vmap(one)(theta)

    args = space(sc, mods, theta, T)

    @jax.jit
    def solve(*a):
        return jax.vmap(lambda *x: solve_contact_cells(*x, ExactContact())[1])(*a)

    t_cells = min_time(lambda: cells(sc, mods, theta), repeats, block)
    t_space = min_time(lambda: space(sc, mods, theta, T), repeats, block)
    t_solve = min_time(lambda: solve(*args), repeats, block)
    return {
        "jit_te_only_per_curve_s": hybrid_exact["jit"]["per_curve_s"],
        "public_per_curve_s": hybrid_exact["public"]["per_curve_s"],
        "public_minus_jit_s": hybrid_exact["public"]["per_curve_s"]
        - hybrid_exact["jit"]["per_curve_s"],
        "cells_and_deviations_s": t_cells,
        "cell_space_incl_cells_s": t_space,
        "window_compliance_s": max(t_space - t_cells, 0.0),
        "contact_solve_s": t_solve,
        "note": "per TE curve, exact; each stage jitted on its own and timed alone (min of "
        "repeats); cell_space = window, C = V_W G_WW V_Wᵀ, a0, E, b; public − jit = the "
        "recovery of X (O(structure DOFs²) per position), the other outputs and dispatch",
    }


# ------------------------------------------------------------------------------------------
# report


def hybrid_chart(out: dict, path: str) -> None:
    """Draw the chart of the hybrid benchmark (bench_hybrid.json: speed against accuracy of the hybrid curves and maps) from its JSON record ``out`` into
    the PNG ``path`` (written atomically); ``jaxgear bench`` calls it after a run."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import LogFormatter

    from jaxgear.io import atomic_open

    fig = Figure(figsize=(13, 9), layout="constrained")
    FigureCanvasAgg(fig)
    (ax1, ax2), (ax3, ax4) = fig.subplots(2, 2)
    tc, rm = out["te_curve"], out["relief_map"]
    ms = 1e3

    # (a) time per TE curve, log
    labels, hy, ri = [], [], []
    for mode in ("exact", "smooth"):
        for how in ("jit", "public"):
            labels.append(f"{mode}\n{'jit' if how == 'jit' else 'public'}")
            hy.append(tc["hybrid"][mode][how]["per_curve_s"] * ms)
            ri.append(tc["rigid"][mode][how]["per_curve_s"] * ms)
    cached = tc.get("hybrid_cached_compliance")
    if cached:  # the jit curves with the window compliance cached per scene
        labels.insert(1, "exact jit\ncached")
        hy.insert(1, cached["per_curve_s"] * ms)
        ri.insert(1, tc["rigid"]["exact"]["jit"]["per_curve_s"] * ms)
        if "smooth" in cached:
            labels.insert(4, "smooth jit\ncached")
            hy.insert(4, cached["smooth"]["per_curve_s"] * ms)
            ri.insert(4, tc["rigid"]["smooth"]["jit"]["per_curve_s"] * ms)
    if "hybrid_uncached" in rm:
        labels.append("map\nuncached")
        hy.append(rm["hybrid_uncached"]["per_curve_s"] * ms)
        ri.append(rm["rigid"]["per_curve_s"] * ms)
    labels.append("map\ncached")
    hy.append(rm["hybrid"]["per_curve_s"] * ms)
    ri.append(rm["rigid"]["per_curve_s"] * ms)
    x = np.arange(len(labels))
    bw = 0.38

    def paired_bars(ax, x, hybrid, rigid, hybrid_label, fmt):
        """Hybrid (red) and rigid (blue) bars side by side, each with its value on top."""
        for vals, dx, color, label in (
            (hybrid, -bw / 2, "C3", hybrid_label),
            (rigid, bw / 2, "C0", "rigid mesh"),
        ):
            for r, v in zip(ax.bar(x + dx, vals, bw, color=color, label=label), vals):
                ax.annotate(
                    format(v, fmt),
                    (r.get_x() + r.get_width() / 2, v),
                    ha="center",
                    va="bottom",
                    fontsize=7,
                    xytext=(0, 1),
                    textcoords="offset points",
                )

    paired_bars(ax1, x, hy, ri, "hybrid (FE wheel)", ".3g")
    for xi, h, r in zip(x, hy, ri):
        ax1.annotate(
            f"×{h / r:.0f}",
            (xi, 0.93),
            xycoords=("data", "axes fraction"),
            ha="center",
            fontsize=9,
            weight="bold",
        )
    ax1.hlines(
        ri[0] * _TARGET_RATIO,
        x[0] - 0.45,
        x[0] + 0.45,
        color="k",
        ls="--",
        lw=1.0,
        label=f"target: {_TARGET_RATIO:g}× rigid (exact, jax.jit)",
    )
    ax1.set_yscale("log")
    ax1.set_ylim(min(ri) / 3, max(hy) * 30)
    ax1.set_xticks(x, labels, fontsize=7)
    ax1.set_ylabel("time per TE curve after compile (ms)")
    s = out["settings"]
    ax1.set_title(
        f"per TE curve: {s['slices']} slices × {s['positions_per_pitch']} positions "
        "(bold: hybrid / rigid);\njit: TE in jax.jit; public: quasi_static(); cached: the "
        "scene cached; map: per curve",
        fontsize=9,
    )
    ax1.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, 0.9))
    ax1.grid(True, axis="y", which="both", alpha=0.3)

    # (b) compile time and map totals
    labels2, hy2, ri2 = [], [], []
    for mode in ("exact", "smooth"):
        for how in ("jit", "public"):
            labels2.append(f"compile\n{mode} {how}")
            hy2.append(tc["hybrid"][mode][how]["compile_s"])
            ri2.append(tc["rigid"][mode][how]["compile_s"])
    labels2 += ["compile\nmap", "map total\n(cached)"]
    hy2 += [rm["hybrid"]["compile_s"], rm["hybrid"]["total_s"]]
    ri2 += [rm["rigid"]["compile_s"], rm["rigid"]["total_s"]]
    if "hybrid_uncached" in rm:
        labels2.append("map total\n(uncached)")
        hy2.append(rm["hybrid_uncached"]["total_s"])
        ri2.append(rm["rigid"]["total_s"])
    x2 = np.arange(len(labels2))
    paired_bars(ax2, x2, hy2, ri2, "hybrid", ".2g")
    ax2.set_yscale("log")
    ax2.set_xticks(x2, labels2, fontsize=7)
    ax2.set_ylabel("wall time (s)")
    hmem, rmem = rm["hybrid"]["memory"], rm["rigid"]["memory"]

    def _mib(m):
        v = m.get("peak_rss_mib") or m.get("ru_maxrss_process_mib")
        return f"{v:.0f} MiB"

    ax2.set_title(
        f"compile, and the {rm['shape'][0]}×{rm['shape'][1]} relief map after compile:\n"
        f"hybrid {rm['hybrid']['curves_per_s']:.0f} curves/s cached"
        + (
            f" ({rm['hybrid_uncached']['curves_per_s']:.0f} uncached, "
            f"×{rm['speedup_cached_over_uncached']:.1f})"
            if "hybrid_uncached" in rm
            else ""
        )
        + f",\npeak RSS {_mib(hmem)}; rigid {rm['rigid']['curves_per_s']:.0f} curves/s "
        f"({_mib(rmem)})",
        fontsize=9,
    )
    ax2.legend(fontsize=7)
    ax2.grid(True, axis="y", which="both", alpha=0.3)

    def scaling_line(ax, rows, x, label, note):
        """Per-position time (µs) against ``rows[i][x]``, each point annotated ``note(row)``."""
        ax.plot(
            [r[x] for r in rows],
            [r["per_position_s"] * 1e6 for r in rows],
            "o-",
            color="C3",
            label=label,
        )
        for r in rows:
            ax.annotate(
                note(r),
                (r[x], r["per_position_s"] * 1e6),
                fontsize=7,
                xytext=(3, -9),
                textcoords="offset points",
            )

    # (c) per position vs window DOFs
    sw = out["scaling"]["window"]
    scaling_line(
        ax3,
        sw,
        "window_dofs",
        f"{out['case']}: window widened ({sw[0]['cells_per_position']} cells)",
        lambda r: f"{r['window_stations']} st.",
    )
    ax3.set_xscale("log")
    ax3.set_yscale("log")
    ax3.set_xlabel("window DOFs (rim stations under the contact × axial nodes × 3, + pinion)")
    ax3.set_ylabel("hybrid time per position (µs, jax.jit, TE only)")
    ax3.set_title("cell-space cost vs window width", fontsize=9)

    # (d) per position vs cells, and the small body at equal cells and window
    sc_ = out["scaling"]["cells"]
    scaling_line(
        ax4,
        sc_,
        "cells_per_position",
        f"{out['case']} (window {sc_[0]['window_dofs']} DOFs)",
        lambda r: f"N={r['slices']}",
    )
    bs = out["scaling"]["body_size"]
    if "rows" in bs:
        for r, mk, col in zip(bs["rows"], ("s", "D"), ("C1", "C2")):
            ax4.plot(
                [r["cells_per_position"]],
                [r["jit_per_position_s"] * 1e6],
                mk,
                color=col,
                ms=8,
                mfc="none",
                mew=1.5,
                label=f"{r['body']}: {r['structure_dofs']} structure DOFs, window "
                f"{r['window_dofs']} (jit {r['jit_per_position_s'] * 1e6:.0f} µs, public "
                f"{r['public_per_position_s'] * 1e6:.0f} µs)",
            )
    ax4.set_xscale("log")
    ax4.set_yscale("log")
    ax4.set_xlabel("contact cells per position (lines × slices)")
    ax4.set_ylabel("hybrid time per position (µs, jax.jit, TE only)")
    ax4.set_title("cell-space cost vs cells; two bodies at equal cells and window", fontsize=9)
    for a in (ax3, ax4):
        for axis in (a.xaxis, a.yaxis):
            axis.set_major_formatter(LogFormatter(labelOnlyBase=False, minor_thresholds=(2, 1)))
            axis.set_minor_formatter(LogFormatter(labelOnlyBase=False, minor_thresholds=(2, 1)))
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=7)
    m = out["machine"]
    fig.suptitle(
        f"jaxgear bench hybrid — {out['case']}: condensed FE wheel vs rigid mesh; "
        f"{m['cpu_count']} CPU ({m['cpu_model']}), {out['dtype']}, JAX {out['jax']}"
        + (" — QUICK" if out["quick"] else ""),
        fontsize=10,
    )
    thin_tick_labels(fig)
    with atomic_open(path, "wb") as f:  # as the other benchmarks' figures
        fig.savefig(f, format="png", dpi=120)


def _table(out: dict) -> str:
    tc, rm, s = out["te_curve"], out["relief_map"], out["settings"]
    ms = 1e3
    lines = [
        (
            f"hybrid benchmark: {out['case']}, {s['slices']} slices × "
            f"{s['positions_per_pitch']} positions, {out['dtype']}, JAX {out['jax']}, "
            f"{out['machine']['cpu_count']} CPU"
        ),
        (
            f"{'per TE curve (ms)':28s}{'hybrid':>10s}{'rigid':>10s}{'ratio':>8s}"
            f"{'compile h':>11s}{'compile r':>11s}"
        ),
    ]
    for mode in ("exact", "smooth"):
        for how in ("jit", "public"):
            h, r = tc["hybrid"][mode][how], tc["rigid"][mode][how]
            lines.append(
                f"{mode + ' ' + how:28s}{h['per_curve_s'] * ms:10.3f}{r['per_curve_s'] * ms:10.3f}"
                f"{h['per_curve_s'] / r['per_curve_s']:8.1f}{h['compile_s']:10.2f}s"
                f"{r['compile_s']:10.2f}s"
            )
    cc = tc.get("hybrid_cached_compliance")
    if cc:
        for mode, row in (("exact", cc), ("smooth", cc.get("smooth"))):
            if row is None:
                continue
            lines.append(
                f"{mode + ' jit, cached scene':28s}{row['per_curve_s'] * ms:10.3f}"
                f"{row.get('rigid_per_curve_s', tc['rigid'][mode]['jit']['per_curve_s']) * ms:10.3f}"
                f"{row['ratio_over_rigid_jit']:8.1f}   (x{row['speedup']:.2f} over uncached "
                f"{row['uncached_per_curve_s'] * ms:.3f} ms, TE diff {row['te_max_rel_diff']:.0e})"
            )
        lines.append(
            f"cache: {cc['cache_mib']:.1f} MiB, built in {cc.get('cache_build_s', 0):.2f} s"
        )
    gr = out.get("gradient")
    if gr:
        for mode in ("exact", "smooth"):
            g = gr[mode]
            lines.append(
                f"value_and_grad TE RMS {mode}: rigid {g['rigid_s'] * ms:.3f} ms, hybrid cached "
                f"{g['hybrid_cached_s'] * ms:.3f} ms (x{g['ratio_cached_over_rigid']:.1f} rigid), "
                f"uncached {g['hybrid_uncached_s'] * ms:.3f} ms (x{g['ratio_uncached_over_rigid']:.1f});"
                f" gradient diff {g['grad_rel_diff']:.0e}"
            )
    for name in ("hybrid", "hybrid_uncached", "rigid"):
        if name not in rm:
            continue
        g = rm[name]
        mem = g["memory"]
        lines.append(
            f"map {rm['shape'][0]}×{rm['shape'][1]} {name:15s}: {g['total_s']:.3f} s, "
            f"{g['curves_per_s']:.0f} curves/s, compile {g['compile_s']:.1f} s, peak RSS "
            f"{mem.get('peak_rss_mib') or float('nan'):.0f} MiB (process {mem['ru_maxrss_process_mib']:.0f})"
        )
    if "hybrid_uncached" in rm:
        lines.append(
            f"map cached / uncached: x{rm['speedup_cached_over_uncached']:.1f} faster, TE RMS "
            f"diff {rm['te_rms_max_rel_diff_cached_uncached']:.0e}"
        )
    vc = rm["hybrid"]["vmap_check"]
    lines.append(
        f"vmap check: TE RMS rel diff {vc['te_rms_rel_diff']:.1e}, TE curve "
        f"{vc['te_curve_max_rel_diff']:.1e}"
    )
    cs = out["cost_split"]
    lines.append(
        f"cost split (ms/curve): cells {cs['cells_and_deviations_s'] * ms:.2f}, window C "
        f"{cs['window_compliance_s'] * ms:.2f}, contact solve {cs['contact_solve_s'] * ms:.2f}, "
        f"public − jit {cs['public_minus_jit_s'] * ms:.2f}; scene build "
        f"{out['setup']['static_scene_s']:.2f} s"
    )
    bs = out["scaling"]["body_size"]
    if "rows" in bs:
        a, b = bs["rows"]
        lines.append(
            f"equal cells/window: {a['body']} ({a['structure_dofs']} DOFs) "
            f"{a['jit_per_curve_s'] * ms:.2f} ms vs {b['body']} ({b['structure_dofs']} DOFs) "
            f"{b['jit_per_curve_s'] * ms:.2f} ms (jit); public {a['public_per_curve_s'] * ms:.2f}"
            f" vs {b['public_per_curve_s'] * ms:.2f} ms"
        )
    return "\n".join(lines)
