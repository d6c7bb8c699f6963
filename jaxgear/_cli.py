"""Command line: ``jaxgear run | cases | optimise | master-curve | sweep | bench | prep``.

The CLI is an entry point, so it switches float64 on (library modules never do).
"""

from __future__ import annotations

import argparse
import json
import os
import sys

__all__ = ["main"]


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="jaxgear", description="Differentiable gear dynamics in JAX.")
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="quasi-static analysis of a case (the main job)")
    r.add_argument("case", nargs="?", default="accessory-spur",
                   help="TOML case file or embedded case name (default: accessory-spur)")
    r.add_argument("--out", help="output folder (default: jaxgear-out/<case>/)")
    r.add_argument("--json", help="also write the summary to this path")
    r.add_argument("--quiet", action="store_true", help="no progress bar")
    sub.add_parser("cases", help="list the embedded cases")
    b = sub.add_parser("bench", help="benchmarks (speed vs a baseline, speed-vs-accuracy charts)")
    b.add_argument("what", choices=["quasi-static", "optimise", "dynamics"], help="which benchmark")
    b.add_argument("--out", default="jaxgear-out/bench", help="output folder")
    b.add_argument("--quick", action="store_true", help="a small, fast version (smoke test)")
    pr = sub.add_parser("prep", help="fem_prep: mesh and condense a gear body (same as fem-prep build)")
    pr.add_argument("body", help="body TOML file or embedded body name")
    pr.add_argument("--out", help="output folder")
    from ._sweep import add_sweep_parser

    add_sweep_parser(sub)
    from optimise._cli import add_parsers as add_optimise_parsers

    add_optimise_parsers(sub)
    return p


def quasi_static_3d_summary(case) -> dict:
    """Quasi-static TE and mean bearing loads of the case's lumped 3D scene (load rotation
    grounded), with the case's modifications and exact contact."""
    import numpy as np

    from ._quasi_static import quasi_static
    from ._run import result_summary
    from ._scene import grounded
    from ._sweep import build_dynamic_model

    model, _ = build_dynamic_model(case, slices=min(case.slices, 8))
    scene = model.scene
    res = quasi_static(grounded(scene, (scene.torque_dofs[1],)), case.modifications, case.torque,
                       positions_per_pitch=case.positions_per_pitch)
    forces = np.asarray(scene.reaction_matrix()) @ np.asarray(res.x).T
    out = result_summary(res)
    out["bearing_forces_mean_N"] = dict(zip(scene.reaction_names, forces.mean(axis=1).tolist()))
    return out


def _fail(msg: str) -> int:
    print(f"jaxgear: error: {msg}", file=sys.stderr)
    return 2


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the exit status (0 ok, 2 bad input)."""
    args = _parser().parse_args(argv)
    if args.command == "prep":
        from fem_prep._cli import main as fem_main

        return fem_main(["build", args.body] + (["--out", args.out] if args.out else []))

    import jax

    jax.config.update("jax_enable_x64", True)
    import equinox as eqx

    from ._case import list_cases, load_case

    try:
        if args.command == "cases":
            for name in list_cases():
                c = load_case(name)
                print(f"{name:20s} z {c.pair.pinion.teeth}/{c.pair.gear.teeth}, "
                      f"m_n {c.pair.normal_module * 1e3:g} mm, β {c.raw['pair'].get('helix_angle_deg', 0)}°, "
                      f"T {c.torque:g} N·m, {c.stiffness_model} stiffness")
            return 0
        if args.command == "run":
            from ._run import format_table, run_case

            case = load_case(args.case)
            out = args.out or os.path.join("jaxgear-out", case.name)
            summary = run_case(case, out, show_progress=not args.quiet)
            if case.raw.get("scene"):  # the case has a dynamic scene: add the dynamic factor curve
                import numpy as np

                from ._sweep import sweep_case

                sw = sweep_case(case, np.linspace(100.0, 3000.0, 60), os.path.join(out, "sweep"),
                                slices=min(case.slices, 8), show_progress=not args.quiet)
                df = np.asarray(sw["dynamic_factor"], dtype=float)
                if case.raw["scene"].get("model") == "lumped3d":
                    summary["quasi_static_3d"] = quasi_static_3d_summary(case)
                summary["dynamics"] = {"model": case.raw["scene"].get("model", "torsional"),
                                       "speeds_rad_s": sw["speeds_rad_s"],
                                       "dynamic_factor": sw["dynamic_factor"],
                                       "max_dynamic_factor": float(np.nanmax(df)),
                                       "speed_of_max_rad_s": float(sw["speeds_rad_s"][int(np.nanargmax(df))]),
                                       "files": "sweep/sweep.json, sweep/dynamic_factor.png, sweep/campbell.png"}
                from ._util import atomic_open

                with atomic_open(os.path.join(out, "summary.json"), "w") as f:
                    json.dump(summary, f, indent=2)
            if case.raw.get("optimise"):  # the case asks for an optimisation too
                from optimise._cli import optimise_case, settings_from_case

                rep = optimise_case(case, settings_from_case(case), os.path.join(out, "optimise"),
                                    progress=not args.quiet)
                summary["optimise"] = {k: rep[k] for k in ("objective", "variables", "initial", "final",
                                                           "iterations", "evaluations", "converged")}
                from ._util import atomic_open

                with atomic_open(os.path.join(out, "summary.json"), "w") as f:
                    json.dump(summary, f, indent=2)
            if args.json:
                from ._util import atomic_open

                with atomic_open(args.json, "w") as f:
                    json.dump(summary, f, indent=2)
            print(format_table(summary))
            if "quasi_static_3d" in summary:
                q = summary["quasi_static_3d"]
                print(f"lumped 3D scene, exact: TE mean {q['te_mean_m'] * 1e6:.4f} µm, "
                      f"TE rms {q['te_rms_m'] * 1e6:.4f} µm (shaft and bearing compliance included)")
            if "dynamics" in summary:
                d = summary["dynamics"]
                print(f"dynamic factor: max {d['max_dynamic_factor']:.3f} at "
                      f"{d['speed_of_max_rad_s']:.0f} rad/s (pinion), sweep "
                      f"{d['speeds_rad_s'][0]:g}-{d['speeds_rad_s'][-1]:g} rad/s")
            print(f"written to {out}/")
            return 0
        if args.command == "optimise":
            from optimise._cli import run_optimise

            return run_optimise(args)
        if args.command == "master-curve":
            from optimise._cli import run_master_curve

            return run_master_curve(args)
        if args.command == "sweep":
            from ._sweep import run_sweep

            return run_sweep(args)
        if args.command == "bench":
            if args.what == "dynamics":
                from ._bench_dynamics import bench_dynamics

                print(json.dumps(bench_dynamics(args.out, quick=args.quick), indent=2))
                return 0
            if args.what == "optimise":
                from optimise._bench import bench_optimise

                bench_optimise(args.out, quick=args.quick)
                return 0
            from ._bench import bench_quasi_static

            bench_quasi_static(args.out, quick=args.quick)
            return 0
    except (ValueError, FileNotFoundError) as err:
        return _fail(str(err))
    except eqx.EquinoxRuntimeError as err:
        return _fail(str(err).strip().splitlines()[0])
    return _fail(f"unknown command {args.command!r}")


if __name__ == "__main__":
    sys.exit(main())
