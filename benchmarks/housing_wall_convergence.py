"""The embedded housed case's walls under mesh refinement (docs/housing.md, "How fine the
walls"), measured:

``power-helical-housed`` (the cheapest housed pair: a 92 x 340 x 240 mm cast aluminium box, 12 mm
walls, four 66 mm bores, Tet10, fixed-interface modes to the 6.75 kHz cut-off) meshed by the
structured mesher at ``mesh_size_mm`` 40 (the shipped mesh), 20 and 10 and ``layers`` 1, 2 and 3
(cells through the wall). For each mesh: its DOFs, its fixed-interface modes (Hz), the CPU and
wall seconds of meshing and condensing it (``jaxgear run``'s path, ``Case.housing_body``, in a
fresh fem_prep cache folder so nothing is read back), and the whine and ERP of the case's own
``[whine]`` (its 36 speeds, H = 8) on that housing: the overall ERP in the band (dB re 1 pW), each
order's ERP, each named point's normal velocity and the TE per order, against the finest mesh's.

The modes' limit: Richardson extrapolation of the three 2-layer meshes (40, 20, 10 mm; each of
the finest mesh's lowest eight matched in every mesh by its largest MAC, the shapes sampled at
the shipped mesh's nodes), ``f_inf = f_10 - (f_20 - f_10) r / (1 - r)``, ``r = (f_20 - f_10) / (f_40 -
f_20)``, where 0 < r < 1.

Writes docs/bench/housing_wall_convergence.json (``--quick``: the 40 and 20 mm meshes only, to
/tmp; ``--compare ROWS``: the comparison again from the rows a run saved, ``rows.pickle`` in the
cache folder it prints; with ``--planetary``, the planetary case's part measured again). Then
``nrel-5mw-planetary-housed``'s box (its shipped Tet4 cells of 250 mm in one layer on 60 mm
walls, the same cells in Tet10, Tet10 cells of 125 and 83.3 mm in two layers): its
fixed-interface modes to 1 kHz, and how many lie below the case's 300 Hz cut-off.

From the repository root: ``python -m benchmarks.housing_wall_convergence`` (about 6 min of wall
time on the 2-core host under a load of 8-11: the six whines, the 10 mm mesh's condensation, 30 s
of CPU, and the planetary box's 83.3 mm mesh's, 54 s). Times measured with
``time.process_time`` (CPU) and ``time.perf_counter`` (wall); the load average is recorded (the
planetary part's is not: its times are not quoted).
"""

from __future__ import annotations

import json
import os
import pathlib
import sys
import tempfile
import time
import tomllib

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
CASE = "power-helical-housed"
#: (mesh_size_mm, layers): the shipped mesh first, the 2-layer sequence for Richardson
MESHES = ((40.0, 1), (40.0, 2), (20.0, 1), (20.0, 2), (20.0, 3), (10.0, 2))
QUICK = ((40.0, 1), (20.0, 2))
#: the modes compared: the finest mesh's lowest, each matched in every mesh by its largest MAC
N_MODES = 8
#: the points at which the modes' shapes are compared (the shipped mesh's nodes; set in main)
SAMPLES: list = []


def _case(size_mm: float, layers: int):
    import jaxgear.io as jio

    data = tomllib.loads(jio.embedded_case_text(CASE))
    data["housing"]["mesh_size_mm"] = size_mm
    data["housing"]["layers"] = layers
    return jio.parse_case(data, CASE)


def _abs_spread(d) -> dict:
    """The largest and the median |d| (dB) over the entries that are numbers."""
    return {"max_abs": float(np.nanmax(np.abs(d))), "median_abs": float(np.nanmedian(np.abs(d)))}


def measure(size_mm: float, layers: int) -> dict:
    """One mesh: its cost, modes and the case's whine and ERP on it."""
    import jaxgear.io as jio
    from jaxgear.acoustics import housing_vibration, total_level
    from jaxgear.dynamics import whine_response

    case = _case(size_mm, layers)
    c0, t0 = time.process_time(), time.perf_counter()
    body = case.housing_body()  # meshed and condensed (a fresh cache folder: built here)
    cpu, wall = time.process_time() - c0, time.perf_counter() - t0
    if not SAMPLES:  # the first (shipped) mesh's nodes
        SAMPLES.append(np.asarray(body.mesh.nodes))
    modes = np.asarray(body.condensed.modes_hz, dtype=float)
    inputs = jio.whine_of(case)
    model, _ = jio.build_dynamic_model(case)
    housed = jio.housed_acoustics(case)  # the condensed housing just built (cached)
    first = model.scene.structure.node(f"housing {housed.body.condensed.seat_names[0]}")
    w = whine_response(model, np.asarray(inputs.speeds), inputs.method, positions=inputs.positions)
    speeds = np.asarray(w.speed, dtype=float)
    f1 = np.asarray(w.frequency, dtype=float)
    orders_all = np.asarray(w.orders, dtype=float)
    keep = orders_all > 0
    orders = orders_all[keep]
    freq = f1[:, None] * orders[None, :]
    n_c = int(housed.acoustics.K.shape[0])
    q = np.asarray(w.coordinates)[:, keep, first : first + n_c]
    r = housing_vibration(housed.acoustics, q, freq)
    power = np.asarray(r.power, dtype=float)
    band = float(body.condensed.cutoff_hz) / 1.5
    in_band = freq <= band
    overall = np.asarray(total_level(np.where(in_band, power, 0.0)), dtype=float)
    te = np.abs(np.asarray(w.transmission_error))[:, keep, 0]  # (S, O) m
    pv = np.abs(np.asarray(r.point_velocity))  # (S, O, P) m/s
    # each fixed-interface mode's displacement at the sample points' nearest nodes, for the MAC
    from scipy.spatial import cKDTree

    idx = cKDTree(body.mesh.nodes).query(SAMPLES[0])[1]
    rows = (3 * idx[:, None] + np.arange(3)).ravel()
    shapes = np.asarray(body.condensed.recovery)[rows, body.condensed.n_seat_dofs :]
    return {
        "_shapes": shapes,
        "mesh_size_mm": size_mm,
        "layers": layers,
        "dofs": int(body.mesh.n_dofs),
        "cells": int(body.mesh.mesh.t.shape[1]),
        "modes_kept": int(modes.size),
        "condensed_coordinates": n_c,
        "condense_cpu_s": round(cpu, 2),
        "condense_wall_s": round(wall, 2),
        "modes_hz": modes.tolist(),
        "speeds_rad_s": speeds.tolist(),
        "orders": orders.tolist(),
        "in_band": in_band.tolist(),
        "overall_erp_db": overall.tolist(),
        "erp_db": np.asarray(r.level, dtype=float).tolist(),
        "te_um": (te * 1e6).tolist(),
        "point_names": list(housed.acoustics.point_names),
        "point_velocity_mm_s": (pv * 1e3).tolist(),
    }


PLANETARY = "nrel-5mw-planetary-housed"
#: its shipped mesh (Tet4, 250 mm, one layer), the same cells in Tet10, a half and a third of them
#: in two layers
PLANETARY_MESHES = (
    ("tet4", 250.0, 1),
    ("tet10", 250.0, 1),
    ("tet10", 125.0, 2),
    ("tet10", 250.0 / 3, 2),
)
#: the cut-off its fixed-interface modes are found to here (its own: 300 Hz)
PLANETARY_CUTOFF_HZ = 1000.0


def planetary() -> dict:
    """The planetary housed case's box (3.6 x 3.6 x 0.8 m, 60 mm cast-iron walls): its lowest
    fixed-interface modes to 1 kHz and how many lie below its own 300 Hz cut-off, on its
    shipped Tet4 mesh and on Tet10 meshes (no whine: the modes say whether its band holds a
    panel resonance)."""
    import dataclasses

    import jaxgear.io as jio

    case = jio.load_case(PLANETARY)
    spec = case.housing
    rows = []
    for element, size_mm, layers in PLANETARY_MESHES:
        s = dataclasses.replace(
            spec,
            element=element,
            mesh_size=size_mm * 1e-3,
            layers=layers,
            cutoff=PLANETARY_CUTOFF_HZ,
        )
        c0 = time.process_time()
        body = dataclasses.replace(case, housing=s).housing_body()  # the stage's box
        cpu = time.process_time() - c0
        f = np.asarray(body.condensed.modes_hz, dtype=float)
        rows.append(
            {
                "element": element,
                "mesh_size_mm": size_mm,
                "layers": layers,
                "dofs": int(body.mesh.n_dofs),
                "modes_hz": f.tolist(),
                "modes_below_case_cutoff": int(np.sum(f <= spec.cutoff)),
                "condense_cpu_s": round(cpu, 2),
            }
        )
        print(rows[-1], flush=True)
    return {
        "case": PLANETARY,
        "shipped": {
            "element": spec.element,
            "mesh_size_mm": spec.mesh_size * 1e3,
            "layers": spec.layers,
        },
        "case_cutoff_hz": spec.cutoff,
        "cutoff_hz": PLANETARY_CUTOFF_HZ,
        "meshes": rows,
    }


def _db(x):
    return 20 * np.log10(np.maximum(np.asarray(x, dtype=float), 1e-300))


def _mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The modal assurance criterion of the columns of a (m, p) against those of b (m, q)."""
    num = np.abs(a.T @ b) ** 2
    return num / np.outer(np.sum(a * a, axis=0), np.sum(b * b, axis=0))


def compare(rows: list[dict]) -> dict:
    """Each mesh's modes against the Richardson limit of the finest's lowest (matched by MAC
    at the shipped mesh's nodes), its ERP and whine against the finest mesh's."""
    finest = max(rows, key=lambda r: r["dofs"])
    n = min(N_MODES, len(finest["modes_hz"]))
    ref_shapes = finest["_shapes"][:, :n]
    matched = {}
    for r in rows:  # for each of the finest mesh's modes: its partner in r (largest MAC)
        mac = _mac(r["_shapes"], ref_shapes)  # (modes of r, n)
        j = np.argmax(mac, axis=0)
        matched[id(r)] = (np.asarray(r["modes_hz"])[j], mac[j, np.arange(n)], j)
    out: dict = {"modes_compared": n}
    two = {r["mesh_size_mm"]: r for r in rows if r["layers"] == 2}
    if all(s in two for s in (40.0, 20.0, 10.0)):
        f40, f20, f10 = (matched[id(two[s])][0] for s in (40.0, 20.0, 10.0))
        ratio = (f20 - f10) / (f40 - f20)
        ok = (ratio > 0) & (ratio < 1)
        limit = np.where(ok, f10 - (f20 - f10) * ratio / (1 - ratio), f10)
        out["richardson"] = {
            "ratio": ratio.tolist(),
            "valid": ok.tolist(),
            "limit_hz": limit.tolist(),
        }
    else:
        limit = np.asarray(finest["modes_hz"][:n])
        ok = np.ones(n, bool)
        out["richardson"] = None
    out["reference_mesh"] = {"mesh_size_mm": finest["mesh_size_mm"], "layers": finest["layers"]}
    ref_erp = np.asarray(finest["overall_erp_db"])
    ref_order = np.asarray(finest["erp_db"])
    band = np.asarray(finest["in_band"])
    ref_te = np.asarray(finest["te_um"])
    ref_pv = np.asarray(finest["point_velocity_mm_s"])
    per = []
    for r in rows:
        f, mac, j = matched[id(r)]
        above = 100 * (f / limit - 1)
        d_erp = np.asarray(r["overall_erp_db"]) - ref_erp
        d_order = np.where(band, np.asarray(r["erp_db"]) - ref_order, np.nan)
        d_te = np.where(band, _db(r["te_um"]) - _db(ref_te), np.nan)
        d_pv = np.where(band[:, :, None], _db(r["point_velocity_mm_s"]) - _db(ref_pv), np.nan)
        i1 = 0  # order 1's column
        per.append(
            {
                "mesh_size_mm": r["mesh_size_mm"],
                "layers": r["layers"],
                "dofs": r["dofs"],
                "condense_cpu_s": r["condense_cpu_s"],
                "matched_modes_hz": f.tolist(),
                "matched_mode_rank": j.tolist(),
                "matched_mac": mac.tolist(),
                "modes_above_limit_percent": above.tolist(),
                # over the modes whose extrapolation holds (0 < r < 1)
                "modes_above_limit_percent_range": [
                    float(above[ok].min()),
                    float(above[ok].max()),
                ],
                "overall_erp_max_db": float(np.max(r["overall_erp_db"])),
                "overall_erp_max_speed_rad_s": float(
                    r["speeds_rad_s"][int(np.argmax(r["overall_erp_db"]))]
                ),
                "overall_erp_change_db": {
                    "max_abs": float(np.max(np.abs(d_erp))),
                    "median_abs": float(np.median(np.abs(d_erp))),
                },
                "order_erp_change_db": _abs_spread(d_order),
                "order1_te_change_db": _abs_spread(d_te[:, i1]),
                "te_change_db": _abs_spread(d_te),
                "point_velocity_change_db": _abs_spread(d_pv),
            }
        )
    out["meshes"] = per
    return out


def main(argv=None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    if "--compare" in argv:  # the comparison again from a run's saved rows, into the record
        import pickle

        with open(argv[argv.index("--compare") + 1], "rb") as fh:
            rows = pickle.load(fh)
        path = ROOT / "docs" / "bench" / "housing_wall_convergence.json"
        record = json.loads(path.read_text(encoding="utf-8"))
        record["comparison"] = compare(rows)
        if "--planetary" in argv:
            cache = tempfile.mkdtemp(prefix="housing-wall-cache-")
            os.environ["FEM_PREP_CACHE"] = cache
            record["planetary"] = planetary()
        path.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
        print("wrote", path)
        return
    quick = "--quick" in argv
    cache = tempfile.mkdtemp(prefix="housing-wall-cache-")
    print("cache folder", cache, flush=True)
    os.environ["FEM_PREP_CACHE"] = cache  # nothing read back: each condensation timed cold
    from ._timing import environment

    load0 = os.getloadavg()
    rows = []
    for size, layers in QUICK if quick else MESHES:
        print(f"{size} mm, {layers} layer(s) ...", flush=True)
        rows.append(measure(size, layers))
        print(
            f"  {rows[-1]['dofs']} DOFs, {rows[-1]['modes_kept']} modes, "
            f"{rows[-1]['condense_cpu_s']} s CPU; modes {np.round(rows[-1]['modes_hz'][:8])}",
            flush=True,
        )
    import pickle

    with open(os.path.join(cache, "rows.pickle"), "wb") as fh:  # kept should compare() fail
        pickle.dump(rows, fh)
    record = {
        "case": CASE,
        "how": __doc__.split("\n\n")[1].replace("\n", " "),
        "load_average_at_start": list(load0),
        "load_average_at_end": list(os.getloadavg()),
        "environment": environment(),
        "comparison": compare(rows),
        "planetary": None if quick else planetary(),
        "rows": [{k: v for k, v in r.items() if k != "_shapes"} for r in rows],
    }
    path = pathlib.Path(tempfile.gettempdir()) if quick else ROOT / "docs" / "bench"
    path = path / "housing_wall_convergence.json"
    path.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
    print(json.dumps(record["comparison"], indent=1))
    print("wrote", path)


if __name__ == "__main__":
    main()
