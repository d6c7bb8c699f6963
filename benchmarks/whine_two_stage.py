"""Gear whine of the embedded ``two-stage`` case (two meshes at mesh frequencies in the ratio
35/127) over 200 speeds and 10 orders (orders 1-5 of each mesh's own frequency) by the
quasi-periodic harmonic balance (:class:`jaxgear.dynamics.QuasiPeriodicBalance`, docs/whine.md,
"Trains of several mesh frequencies") against the time-domain Newmark sweep of the same range.

Accuracy matched: at one speed of the range (first mesh at 300 Hz) the orders 1-5 of each mesh's
TE and mesh force by the balance are compared with Newmark's (3 spans of 127 periods, the last
Fourier analysed at the exact frequencies) at the case's own 140 steps per first-mesh period and
at CHECK_STEPS = 560, the converged reference (tests/test_whine_quasi_periodic.py: the first
mesh's orders 3-5 move by 3.2 % from 140 steps to 560, by 0.7 % from 280); the Newmark sweep is
priced at 140 steps, which hold orders 1-2 of both meshes and 1-5 of the second to 0.2 % of the
converged reference (the first mesh's orders 3-5 to 3.2 %). The Newmark sweep is timed on NEWMARK_SPEEDS of the
200 speeds (each speed an independent run of the same fixed number of steps: the same cost), and
its 200-speed cost is that mean times 200 (stated in the JSON). Wall and CPU seconds (the machine
is shared). From the repository root: ``python -m benchmarks.whine_two_stage`` (``--housed``:
the same in the box housing of the embedded ``two-stage-housed``,
docs/bench/whine_two_stage_housed.json);
``--housed --timing-only``: the costs alone on the housed case (no accuracy check: see
``--accuracy --housed`` below), the balance's 200 speeds with
OpenBLAS on one thread and on its default threads (threadpoolctl, where installed) in the same
run, into docs/bench/whine_two_stage_housed_timing.json;
``python -m benchmarks.whine_two_stage --figure`` draws docs/img/whine_two_stage_spectrum.png
only (each mesh's TE spectrum of the Newmark run at the check speed, the balance's lines on it).

Equal accuracy on all 10 lines: ``--positions N`` (the balance's positions per first-mesh
period, a multiple of 35; ``N1/N2``: each mesh-frequency group's own, the first mesh's axis of
the torus grid on N1 and the second's on N2, ``QuasiPeriodicBalance``'s per-group positions) and ``--steps N`` (Newmark's steps per first-mesh period, a multiple
of 35) replace POSITIONS and STEPS in any mode; ``--out PATH`` names the JSON.
``--accuracy`` (on the unhoused ``two-stage`` unless ``--housed``): at CHECK_SPEED, every line
of the 10 (TE and mesh force) by the balance at each of the comma-separated ``--positions`` and
by Newmark at each of the ``--steps``, against Newmark at CHECK_STEPS (``--reference-steps``),
into docs/bench/whine_two_stage_accuracy.json (``--housed``: ..._housed_accuracy.json): the
grid and steps that hold every line within 1 % and 1 degree of the converged reference.
Without the box 140 positions and 280 steps; with it Newmark needs 560 (its first-mesh order 5
sits where the box responds; reference 1120 steps: ``--accuracy --housed --positions 140,35
--steps 560,420,280 --reference-steps 1120``). ``--one-thread`` (with ``--timing-only``): the
balance on one OpenBLAS thread only (first call included), as ``jaxgear`` commands run it. The
housed figures at equal accuracy: ``python -m benchmarks.whine_two_stage --housed --timing-only
--one-thread --positions 140 --steps 560 --out
docs/bench/whine_two_stage_housed_timing_equal_accuracy.json``.
"""

from __future__ import annotations

import json
import math
import pathlib
import time

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np

import jaxgear.io as jio
from jaxgear.dynamics import Newmark, QuasiPeriodicBalance, SteadyState, simulate, whine_response

from ._timing import environment

ROOT = pathlib.Path(__file__).resolve().parents[1]
SPEEDS = np.linspace(20.0, 100.0, 200)  # input speed (rad/s): first mesh 89-446 Hz
ORDERS = 5  # of each mesh: 10 lines
METHOD = QuasiPeriodicBalance(8, 0)
POSITIONS = 35
STEPS = 140
CHECK_STEPS = 560  # the accuracy's converged reference
NEWMARK_SPEEDS = 2
CHECK_SPEED = 2 * math.pi * 300.0 / 28


def _clock():
    return time.perf_counter(), time.process_time()


def _since(c):
    w, p = _clock()
    return w - c[0], p - c[1]


def _newmark(model, speed, steps=STEPS):
    return simulate(model, speed, integrator=Newmark(steps), window=SteadyState(3 * 127, 127))


def _time_orders(t, x, freqs):
    t, x = np.asarray(t), np.asarray(x)
    return np.array([2 * np.mean(x * np.exp(-1j * f * t)) for f in freqs])


def _lines(w, result) -> dict:
    """Orders 1-ORDERS of each mesh's own frequency, TE and mesh force (complex, m and N):
    from a balance's :class:`~jaxgear.dynamics.WhineResponse` ``w`` at one speed when
    ``result`` is ``w``, else from a time run's kept span at the same exact frequencies."""
    groups, orders, rel = (np.asarray(a) for a in (w.order_group, w.group_order, w.orders))
    w1 = 2 * math.pi * float(w.frequency[0])
    out = {}
    for k in range(len(w.mesh_group)):
        pick = [int(np.flatnonzero((groups == w.mesh_group[k]) & (orders == o))[0])
                for o in range(1, ORDERS + 1)]
        for name, field in (("te", "transmission_error"), ("mesh_force", "mesh_force")):
            if result is w:
                out[f"mesh{k + 1}_{name}"] = np.asarray(getattr(w, field))[0, pick, k]
            else:
                td = getattr(result.meshes[k], field)
                out[f"mesh{k + 1}_{name}"] = _time_orders(result.time, td, rel[pick] * w1)
    return out


def _errors(got: dict, ref: dict) -> dict:
    """Amplitude (%) and phase (degrees) errors of ``got``'s lines against ``ref``'s."""
    return {key: {"amplitude_error_percent":
                  (100 * (np.abs(got[key]) / np.abs(ref[key]) - 1)).round(3).tolist(),
                  "phase_error_deg": np.degrees(np.angle(got[key] / ref[key])).round(3).tolist()}
            for key in ref}


def _worst(errors: dict) -> dict:
    """The largest absolute amplitude (%) and phase (degrees) error over every line."""
    amp = max(abs(a) for e in errors.values() for a in e["amplitude_error_percent"])
    deg = max(abs(a) for e in errors.values() for a in e["phase_error_deg"])
    return {"amplitude_percent": amp, "phase_deg": deg}


def _path(out: str | None, name: str) -> pathlib.Path:
    return pathlib.Path(out) if out else ROOT / "docs" / "bench" / name


def figure() -> None:
    """docs/img/whine_two_stage_spectrum.png: the Newmark TE of each mesh over the kept span
    (its DFT, one-sided) and the balance's orders 1-5 of each mesh's own frequency."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    model, _ = jio.build_dynamic_model(jio.load_case("two-stage"))
    w = whine_response(model, CHECK_SPEED, METHOD, positions=POSITIONS)
    r = _newmark(model, CHECK_SPEED)
    f1 = float(w.frequency[0])
    groups, orders, rel = (np.asarray(a) for a in (w.order_group, w.group_order, w.orders))
    fig = Figure(figsize=(9, 6.5))
    FigureCanvasAgg(fig)
    t = np.asarray(r.time)
    for k, mesh in enumerate(r.meshes):
        ax = fig.add_subplot(2, 1, k + 1)
        x = np.asarray(mesh.transmission_error)
        spec = 2 * np.abs(np.fft.rfft(x - x.mean())) / x.size
        freq = np.fft.rfftfreq(x.size, t[1] - t[0]) / f1
        keep = freq <= 5.5
        ax.semilogy(freq[keep], spec[keep] * 1e6, "-", color="0.6", lw=0.8,
                    label="Newmark, 140 steps per first-mesh period (DFT of the kept span)")
        for g, mark in ((0, "o"), (1, "s")):
            pick = (groups == g) & (orders >= 1) & (orders <= ORDERS)
            ax.semilogy(rel[pick], np.abs(np.asarray(w.transmission_error[0, pick, k])) * 1e6,
                        mark, mfc="none", ms=7,
                        label=f"QuasiPeriodicBalance, orders 1-{ORDERS} of mesh {g + 1}")
        ax.set_ylim(1e-5, 2.0)
        ax.set_ylabel(f"TE of mesh {k + 1} (µm)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    ax.set_xlabel("frequency / first mesh frequency")
    fig.suptitle(f"two-stage at {CHECK_SPEED:.1f} rad/s (first mesh {f1:.0f} Hz, second "
                 f"{f1 * 35 / 127:.1f} Hz): time domain and quasi-periodic balance", fontsize=10)
    fig.tight_layout()
    fig.savefig(ROOT / "docs" / "img" / "whine_two_stage_spectrum.png", dpi=100)


def _case(housed: bool):
    """``--housed``: the embedded ``two-stage-housed`` (the ``two-stage`` in a cast aluminium box
    round its three shafts, 360 x 400 mm across them, cut-off 3.45 kHz: its file's header); its
    own ``[whine]`` table is not used here (the speeds and method above are)."""
    return jio.load_case("two-stage-housed" if housed else "two-stage")


def _newmark_timed(model, picks, steps):
    """(wall seconds, CPU seconds) of the Newmark run at each speed ``SPEEDS[picks]``."""
    walls, cpus = [], []
    for j in picks:
        c = _clock()
        jax.block_until_ready(_newmark(model, SPEEDS[j], steps).meshes[0].transmission_error)
        wall, cpu = _since(c)
        walls.append(wall)
        cpus.append(cpu)
        print("newmark speed", SPEEDS[j], wall, cpu, flush=True)
    return walls, cpus


def main(housed: bool = False, positions: int = POSITIONS, steps: int = STEPS,
         out: str | None = None) -> dict:
    env = environment()
    model, _ = jio.build_dynamic_model(_case(housed))
    # accuracy at one speed: every line of the 10 against Newmark's
    w = whine_response(model, CHECK_SPEED, METHOD, positions=positions)
    print("balance at one speed done", flush=True)
    c = _clock()
    r = _newmark(model, CHECK_SPEED, steps)  # (its first call: with compilation)
    jax.block_until_ready(r.meshes[0].transmission_error)
    nm_first = _since(c)
    print("newmark at one speed", nm_first, flush=True)
    fine = _newmark(model, CHECK_SPEED, CHECK_STEPS)
    checks = {f"newmark_{n}_steps": _errors(_lines(w, w), _lines(w, run))
              for n, run in ((steps, r), (CHECK_STEPS, fine))}
    # the balance over the 200 speeds: first call (with compilation), then again
    c = _clock()
    sweep = whine_response(model, SPEEDS, METHOD, positions=positions)
    jax.block_until_ready(sweep.transmission_error)
    first = _since(c)
    c = _clock()
    sweep = whine_response(model, SPEEDS, METHOD, positions=positions)
    jax.block_until_ready(sweep.transmission_error)
    hb = _since(c)
    print("balance sweep", first, hb, flush=True)
    loss = int(np.asarray(sweep.contact_loss).any(axis=1).sum())
    # Newmark on a few of the speeds (the first compiles), priced for 200
    picks = np.linspace(0, len(SPEEDS) - 1, NEWMARK_SPEEDS).round().astype(int)
    walls, cpus = _newmark_timed(model, picks, steps)
    nm_wall, nm_cpu = float(np.mean(walls)) * len(SPEEDS), float(np.mean(cpus)) * len(SPEEDS)
    record = {
        "case": "two-stage (lumped 3D, its own 20 slices)" + (
            ", in the cast aluminium box of the embedded two-stage-housed"
            if housed else ""),
        "coordinates": int(model.scene.mass().shape[0]),
        "speeds": len(SPEEDS),
        "speed_range_rad_s": [float(SPEEDS[0]), float(SPEEDS[-1])],
        "orders": f"1-{ORDERS} of each mesh's own frequency ({2 * ORDERS} lines)",
        "method": f"QuasiPeriodicBalance(harmonics={METHOD.harmonics}, "
        f"sidebands={METHOD.sidebands}), positions={positions}",
        "newmark": f"Newmark({steps}), SteadyState({3 * 127}, 127) per speed, independent speeds",
        "accuracy_at_rad_s": CHECK_SPEED,
        "accuracy_balance_vs_newmark": checks,
        "contact_loss_speeds": loss,
        "balance_first_call_s": {"wall": first[0], "cpu": first[1]},
        "balance_sweep_s": {"wall": hb[0], "cpu": hb[1]},
        "newmark_first_speed_s_with_compilation": {"wall": nm_first[0], "cpu": nm_first[1]},
        "newmark_per_speed_s": {"wall": float(np.mean(walls)), "cpu": float(np.mean(cpus)),
                                "speeds_timed": len(walls)},
        "newmark_sweep_s_priced": {"wall": nm_wall, "cpu": nm_cpu,
                                   "how": f"mean of {len(walls)} timed speeds x {len(SPEEDS)}"},
        "ratio_wall": nm_wall / hb[0],
        "ratio_cpu": nm_cpu / hb[1],
        "ratio_wall_balance_with_compilation": nm_wall / first[0],
        "environment": env,
    }
    path = _path(out, f"whine_two_stage{'_housed' if housed else ''}.json")
    path.write_text(json.dumps(record, indent=1) + "\n")
    print(json.dumps({k: record[k] for k in record if k not in (
        "environment", "accuracy_balance_vs_newmark")}, indent=1))
    print(json.dumps(checks))
    return record


def timing_only(housed: bool = True, positions: int = POSITIONS, steps: int = STEPS,
                out: str | None = None, one_thread: bool = False) -> dict:
    """The balance's 200 speeds (first call, then again) and Newmark at NEWMARK_SPEEDS speeds, in
    one run: the ratio without the accuracy check; the balance again with OpenBLAS's threads
    limited to one and left at its default (threadpoolctl), paired, when it is installed
    (``one_thread``: on one thread only, its first call too)."""
    import os

    env = environment()
    model, _ = jio.build_dynamic_model(_case(housed))
    try:
        from threadpoolctl import threadpool_info, threadpool_limits
    except ImportError:  # pragma: no cover - optional
        threadpool_limits = None
    if one_thread and threadpool_limits is None:
        raise SystemExit("--one-thread needs threadpoolctl")
    variants = ([] if one_thread else [("default", None)]) + (
        [("one_thread", 1)] if threadpool_limits else [])

    def limit(n):
        return threadpool_limits(limits=n, user_api="blas") if n else _Null()

    def sweep():
        jax.block_until_ready(
            whine_response(model, SPEEDS, METHOD, positions=positions).coordinates)

    with limit(1 if one_thread else None):
        c = _clock()
        sweep()
        first = _since(c)
    print("balance first call", first, flush=True)
    balance = {}
    for name, n in variants:
        with limit(n):
            c = _clock()
            sweep()
            wall, cpu = _since(c)
        balance[name] = {"wall": wall, "cpu": cpu, "load_average_after": list(os.getloadavg())}
        print("balance sweep", name, wall, cpu, flush=True)
    picks = np.linspace(0, len(SPEEDS) - 1, NEWMARK_SPEEDS).round().astype(int)
    c = _clock()
    jax.block_until_ready(_newmark(model, SPEEDS[picks[0]], steps).meshes[0].transmission_error)
    nm_first = _since(c)
    print("newmark first call", nm_first, flush=True)
    walls, cpus = _newmark_timed(model, picks, steps)
    nm_wall, nm_cpu = float(np.mean(walls)) * len(SPEEDS), float(np.mean(cpus)) * len(SPEEDS)
    blas = [] if threadpool_limits is None else [
        {k: p.get(k) for k in ("internal_api", "num_threads", "version")}
        for p in threadpool_info() if p.get("user_api") == "blas"]
    record = {
        "case": "two-stage-housed (the embedded case's 360 mm box), lumped 3D",
        "coordinates": int(model.scene.mass().shape[0]),
        "speeds": len(SPEEDS),
        "method": f"QuasiPeriodicBalance(harmonics={METHOD.harmonics}, "
        f"sidebands={METHOD.sidebands}), positions={positions}",
        "newmark": f"Newmark({steps}), SteadyState({3 * 127}, 127) per speed (compiled first)",
        "balance_first_call_s": {"wall": first[0], "cpu": first[1],
                                 "blas": "one_thread" if one_thread else "default"},
        "balance_sweep_s": balance,
        "newmark_first_call_s": {"wall": nm_first[0], "cpu": nm_first[1]},
        "newmark_per_speed_s": {"wall": float(np.mean(walls)), "cpu": float(np.mean(cpus)),
                                "speeds_timed": len(walls)},
        "newmark_sweep_s_priced": {"wall": nm_wall, "cpu": nm_cpu},
        "ratio_wall": {k: nm_wall / v["wall"] for k, v in balance.items()},
        "ratio_cpu": {k: nm_cpu / v["cpu"] for k, v in balance.items()},
        "blas": blas,
        "load_average_at_end": list(os.getloadavg()),
        "environment": env,
    }
    path = _path(out, "whine_two_stage_housed_timing.json")
    path.write_text(json.dumps(record, indent=1) + "\n")
    print(json.dumps({k: record[k] for k in record if k != "environment"}, indent=1))
    return record


def accuracy(housed: bool = False, positions=(POSITIONS,), steps=(STEPS,),
             out: str | None = None, reference: int = CHECK_STEPS) -> dict:
    """At CHECK_SPEED, every line of the 10 (TE and mesh force of orders 1-ORDERS of each mesh)
    by the balance at each of ``positions`` and by Newmark at each of ``steps``, against Newmark
    at ``reference`` steps (CHECK_STEPS: the converged reference): per-line errors and the
    worst over all lines; each balance call's seconds (its first: with compilation)."""
    import os

    env = environment()
    model, _ = jio.build_dynamic_model(_case(housed))
    c = _clock()
    fine = _newmark(model, CHECK_SPEED, reference)
    jax.block_until_ready(fine.meshes[0].transmission_error)
    print("reference", _since(c), flush=True)
    balances, seconds = {}, {}
    for p in positions:
        c = _clock()
        balances[p] = whine_response(model, CHECK_SPEED, METHOD, positions=p)
        jax.block_until_ready(balances[p].coordinates)
        seconds[p] = dict(zip(("wall", "cpu"), _since(c)))
    w = balances[positions[0]]
    ref = _lines(w, fine)
    record = {"case": "two-stage-housed (360 mm box)" if housed else "two-stage (20 slices)",
              "coordinates": int(model.scene.mass().shape[0]),
              "accuracy_at_rad_s": CHECK_SPEED,
              "first_mesh_hz": float(w.frequency[0]),
              "reference": f"Newmark({reference}), SteadyState({3 * 127}, 127)",
              "lines": f"orders 1-{ORDERS} of each mesh's own frequency, TE and mesh force",
              "contact_loss": bool(np.asarray(w.contact_loss).any()),
              "balance": {}, "newmark": {}}
    for p, wp in balances.items():
        e = _errors(_lines(wp, wp), ref)
        name = "/".join(map(str, p)) if isinstance(p, tuple) else p
        record["balance"][f"positions_{name}"] = {
            "method": f"QuasiPeriodicBalance({METHOD.harmonics}, {METHOD.sidebands})",
            "worst": _worst(e), "one_speed_call_s_with_compilation": seconds[p], "lines": e}
        print("balance", p, _worst(e), flush=True)
    for n in steps:
        c = _clock()
        run = _newmark(model, CHECK_SPEED, n)
        jax.block_until_ready(run.meshes[0].transmission_error)
        e = _errors(_lines(w, run), ref)
        record["newmark"][f"steps_{n}"] = {"worst": _worst(e), "lines": e}
        print("newmark", n, _worst(e), _since(c), flush=True)
    record["load_average_at_end"] = list(os.getloadavg())
    record["environment"] = env
    path = _path(out, f"whine_two_stage{'_housed' if housed else ''}_accuracy.json")
    path.write_text(json.dumps(record, indent=1) + "\n")
    return record


class _Null:
    def __enter__(self):
        return self

    def __exit__(self, *a):
        return False


def _cli(argv=None) -> None:
    import argparse

    ap = argparse.ArgumentParser(prog="python -m benchmarks.whine_two_stage",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("--housed", action="store_true")
    ap.add_argument("--figure", action="store_true")
    ap.add_argument("--timing-only", action="store_true")
    ap.add_argument("--accuracy", action="store_true")
    ap.add_argument("--one-thread", action="store_true")
    ap.add_argument("--positions", default=str(POSITIONS),
                    help="positions per first-mesh period (--accuracy: comma-separated)")
    ap.add_argument("--steps", default=str(STEPS),
                    help="Newmark steps per first-mesh period (--accuracy: comma-separated)")
    ap.add_argument("--reference-steps", type=int, default=CHECK_STEPS,
                    help="--accuracy: the reference Newmark's steps (default the converged 560)")
    ap.add_argument("--out", default=None, help="the JSON's path")
    a = ap.parse_args(argv)
    # "140/35": each mesh-frequency group's own positions (per first-mesh period), first mesh first
    positions = [tuple(int(g) for g in v.split("/")) if "/" in v else int(v)
                 for v in a.positions.split(",")]
    flat = [g for v in positions for g in (v if isinstance(v, tuple) else (v,))]
    steps = [int(v) for v in a.steps.split(",") if v]  # --accuracy --steps "": none
    for name, vals in (("positions", flat), ("steps", steps or [STEPS]),
                       ("reference-steps", [a.reference_steps])):
        bad = [v for v in vals if v < 35 or v % 35]
        if bad:
            ap.error(f"--{name} = {bad[0]}: a multiple of 35 (the period ratio 35/127's), >= 35")
        if len(vals) > 1 and not a.accuracy and name != "positions":
            ap.error(f"--{name} = {vals}: one value (lists only with --accuracy)")
    if len(positions) > 1 and not a.accuracy:
        ap.error(f"--positions = {a.positions}: one value (lists only with --accuracy)")
    if a.figure:
        figure()
    elif a.accuracy:
        accuracy(a.housed, positions, steps, a.out, a.reference_steps)
    elif a.timing_only:
        timing_only(True, positions[0], (steps or [STEPS])[0], a.out, a.one_thread)
    else:
        main(a.housed, positions[0], (steps or [STEPS])[0], a.out)


if __name__ == "__main__":
    _cli()
