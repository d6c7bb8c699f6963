"""The NREL 5 MW gearbox's stage-3 bearings from their geometry against the published stiffnesses.

Nejad et al. ("Development of a 5 MW reference gearbox for offshore wind turbines", Wind Energy
19 (2016) 1089-1106, Tables VI and IX) publish each bearing's type, boundary dimensions, C and
ISO 281's e with a linear stiffness (K_x axial; K_y, K_z radial; K_beta, K_gamma tilt), which the
embedded case ``nrel-5mw-stage3-housed`` holds its shafts on. :data:`TABLE` transcribes the six
stage-3 bearings as the open-source port github.com/gfsReboucas/Drivetrain (commit 4a88df3,
@NREL_5MW/NREL_5MW.m, ``NREL_5MW.bearing(3)``) gives them: its comment table's designations and
dimensions (its code swaps the HS and IMS dimensions; the HS-B/C bore is printed 200 and queried:
the SKF 32060 X is 300 x 460 x 100 mm) and its code's stiffnesses (for IMS-B its comment
repeats IMS-C's row; the code's, which the embedded case uses, are taken).

Each bearing is built from that geometry (:func:`bearing`: HS-A and IMS-A cylindrical roller
bearings without axial location, the four others single-row tapered ones at α = atan(e/1.5)),
its rollers ESTIMATED by :func:`jaxgear.bearings.estimated_rollers` (the table gives none), and
loaded with what the published case puts on it: the quasi-static solve of
``nrel-5mw-stage3-housed``'s lumped 3D scene on its published springs at rated torque (the
housing rigid, the mean over a mesh period; :func:`published_loads`). A cylindrical roller bearing
takes the radial load (it carries no axial load, and no moment: its tilt is free at zero
moment); a tapered one, held against tilting by its partner, the radial load and the axial load
of a pair set to zero end play, the half-loaded raceway F_a = 1.260 F_r tan α (Sjövall), or the
case's axial share where that is larger (a single-row bearing cannot carry its radial load with
less: its partner supplies it). Its tangent stiffness at the displacement that carries that
(:func:`operating_displacement`) gives the radial stiffness along the load and across it, the
axial and the tilt stiffness, compared with the published values (:func:`compare`); the
cylindrical ones also with a diametral clearance (50 and 100 µm).

How much the estimate of the rollers moves it: HS-A with the roller diameter or length
scaled by 0.8 and 1.2 (:func:`roller_sensitivity`). The stage-1 spherical roller bearings of
the same table (the catalogue's 231/750 CA and 240/710 ECA) at the radial load of their
20-year rating life (:func:`spherical_at_design_load`).

The example's tapered pairs at the example's own operating point (:func:`pairs_at_operating_point`:
HS-B/C and IMS-B/C each one :class:`jaxgear.bearings.TaperedRollerPair` node, its load, its rows'
shares and its tangent stiffness there).

Then the mesh mode of the pair (the mode of the largest mesh energy, mesh-averaged) with both
bearing sets: the published springs (``nrel-5mw-stage3-housed`` without its housing) and
examples/nrel-5mw-stage3-rolling.toml (HS-A and IMS-A, and the tapered pairs, from their
geometry at the case's own operating point); and the whine
of the stage in nrel-5mw-stage3-housed's box on both sets (:func:`whine_both`: two ``jaxgear
run``, the overall ERP and the order-1 TE over the turbine's speeds).

Run from the checkout's root::

    python -m benchmarks.nrel_stage3_bearings --out docs/bench/nrel_stage3_bearings.json

It writes the record and a PNG beside it (the ratios, geometry over published, per bearing).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import tomllib

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLE = os.path.join(ROOT, "examples", "nrel-5mw-stage3-rolling.toml")
HOUSED = os.path.join(ROOT, "jaxgear", "cases", "nrel-5mw-stage3-housed.toml")

#: the port's table (module docstring): name -> designation, type, d, D, B (mm), C (kN), e,
#: K_x (N/m, axial), K_y, K_z (N/m, radial), K_beta, K_gamma (N·m/rad, tilt); shaft and index
#: of the bearing in nrel-5mw-stage3-housed's [scene] (pinion = the high-speed shaft HS)
TABLE = {
    "HS-A": dict(designation="SKF NCF 2240 ECJB", type="CRB", d=200.0, D=360.0, B=98.0,
                 C_kN=1460.0, e=0.3, K_x=1.3e8, K_y=8.2e8, K_z=8.2e8, K_beta=1.7e5,
                 K_gamma=1.0e6, shaft="pinion_shaft", index=0),
    "HS-B": dict(designation="SKF 32060 X", type="TRB", d=300.0, D=460.0, B=100.0,
                 C_kN=1644.0, e=0.43, K_x=6.7e7, K_y=8.0e8, K_z=1.3e8, K_beta=1.7e5,
                 K_gamma=1.0e6, shaft="pinion_shaft", index=1),
    "HS-C": dict(designation="SKF 32060 X", type="TRB", d=300.0, D=460.0, B=100.0,
                 C_kN=1644.0, e=0.43, K_x=8.0e7, K_y=1.0e9, K_z=7.3e7, K_beta=1.7e5,
                 K_gamma=1.0e6, shaft="pinion_shaft", index=2),
    "IMS-A": dict(designation="SKF NNCF 4880 CV", type="CRB", d=400.0, D=500.0, B=100.0,
                  C_kN=1420.0, e=0.15, K_x=0.0, K_y=6.0e7, K_z=1.2e9, K_beta=7.5e4,
                  K_gamma=7.5e4, shaft="gear_shaft", index=0),
    "IMS-B": dict(designation="SKF LM 567949/910/HA1", type="TRB", d=410.0, D=550.0, B=86.0,
                  C_kN=1467.0, e=0.4, K_x=7.4e7, K_y=5.0e8, K_z=5.0e8, K_beta=1.6e6,
                  K_gamma=1.8e6, shaft="gear_shaft", index=1),
    "IMS-C": dict(designation="SKF LM 567949/910/HA1", type="TRB", d=410.0, D=550.0, B=86.0,
                  C_kN=1467.0, e=0.4, K_x=7.8e7, K_y=7.4e8, K_z=3.3e8, K_beta=1.1e6,
                  K_gamma=2.5e6, shaft="gear_shaft", index=2),
}
#: the diametral clearances (m) the cylindrical roller bearings are also evaluated with
CLEARANCES = (0.0, 50e-6, 100e-6)
#: Sjövall's F_a / (F_r tan α) of a line-contact raceway loaded over half its circle (ε = 0.5)
HALF_LOADED = 1.260


def bearing(name: str, clearance: float = 0.0):
    """The bearing ``name`` of :data:`TABLE` from its geometry (SI), rollers estimated."""
    import jaxgear.bearings as jb

    row = TABLE[name]
    d, D, B = row["d"] * 1e-3, row["D"] * 1e-3, row["B"] * 1e-3
    args = dict(bore=d, outer_diameter=D, width=B, clearance=clearance,
                dynamic_rating=row["C_kN"] * 1e3, **jb.estimated_rollers(d, D, B))
    if row["type"] == "CRB":
        return jb.CylindricalRoller(**args)
    return jb.TaperedRoller(**args, contact_angle=math.atan(row["e"] / 1.5))


def published_case():
    """``nrel-5mw-stage3-housed`` without its housing: the pair on the published springs."""
    import jaxgear.io as jio

    return jio.load_case("nrel-5mw-stage3-housed")


def published_loads(case=None) -> dict:
    """Each stage-3 bearing's load f = (F_x, F_y, F_z, M_x, M_y) (N, N·m) in the published
    case (scene frame: z along the shaft, x from the pinion's axis to the wheel's): K_b u at its
    node, u the mean over one mesh period of the quasi-static solve at the case's torque with
    the wheel's load rotation held (as :func:`jaxgear.io.operating_point` solves a case), the
    bearings on the ground."""
    from jaxgear import quasi_static
    from jaxgear.scenes import bearing_dofs, grounded, lumped_pair

    case = published_case() if case is None else case
    spec = case.scene
    shafts = (spec.pinion_shaft, spec.gear_shaft)
    # masses and inertias do not enter a quasi-static solve
    scene = lumped_pair(case.pair, case.mesh_model(), *shafts, masses=(1.0, 1.0),
                        inertias=((1.0, 1.0), (1.0, 1.0)), youngs_modulus=case.youngs_modulus,
                        poisson_ratio=case.poisson_ratio, density=case.density)
    scene = grounded(scene, (scene.torque_dofs[1],))
    res = quasi_static(scene, case.mesh_modifications(), case.torque,
                       positions_per_pitch=case.positions_per_pitch)
    u = np.asarray(res.x).mean(axis=0)
    dofs = bearing_dofs(shafts)
    names = {"pinion_shaft": 0, "gear_shaft": 1}
    out = {}
    for name, row in TABLE.items():
        i, j = names[row["shaft"]], row["index"]
        k = dofs[i][j]
        out[name] = shafts[i].bearings[j].stiffness_matrix()[:5] @ u[k : k + 6]
    return out


def bearing_load(name: str, f) -> np.ndarray:
    """The load the bearing from geometry is evaluated at (module docstring), in its own frame
    (a tapered bearing carries +z: a case load along −z is mirrored, z → −z)."""
    f = np.asarray(f, float)
    Fr = math.hypot(f[0], f[1])
    if TABLE[name]["type"] == "CRB":
        return np.array([f[0], f[1], 0.0, 0.0, 0.0])
    alpha = math.atan(TABLE[name]["e"] / 1.5)
    Fa = max(abs(f[2]), HALF_LOADED * Fr * math.tan(alpha))
    return np.array([f[0], f[1], Fa, 0.0, 0.0])


def operating_displacement(b, load) -> tuple[np.ndarray, float]:
    """(d, residual): the ring displacement at which ``b`` carries ``load``. A cylindrical
    roller bearing: :func:`jaxgear.bearings.solve_displacement` (no axial load, its tilt free at
    zero moment). A tapered one: held against tilting by its partner (γ = 0), its translation
    solved (Newton on the three forces, the Jacobian its stiffness) for (F_x, F_y, F_a); the
    moment it then carries is its partner's to balance."""
    import scipy.optimize

    import jaxgear.bearings as jb

    if isinstance(b, jb.CylindricalRoller):
        s = jb.solve_displacement(b, load)
        return np.asarray(s.displacement), float(s.residual)
    F = np.asarray(load[:3], float)
    scale = float(np.max(np.abs(F)))

    def residual(x):
        d = np.concatenate([x, [0.0, 0.0]])
        return (np.asarray(b.load(d))[:3] - F) / scale

    def jacobian(x):
        d = np.concatenate([x, [0.0, 0.0]])
        return np.asarray(b.stiffness(d))[:3, :3] / scale

    Fr = math.hypot(F[0], F[1])
    d0 = 2.0 * (Fr / (b.elements * float(b.hertz_constant))) ** 0.9
    x0 = np.array([F[0] / Fr * d0, F[1] / Fr * d0, 0.0])
    sol = scipy.optimize.root(residual, x0, jac=jacobian, method="hybr", tol=1e-14)
    return np.concatenate([sol.x, [0.0, 0.0]]), float(np.max(np.abs(residual(sol.x))))


def stiffness_figures(b, load) -> dict:
    """The radial stiffness along the radial load and across it (N/m), the axial (N/m) and the
    two tilt stiffnesses (N·m/rad, about the axes along and across the load) at ``load``
    (:func:`operating_displacement`)."""
    d, residual = operating_displacement(b, load)
    K = np.asarray(b.stiffness(d))
    Fr = math.hypot(load[0], load[1])
    n = np.array([load[0], load[1]]) / Fr
    t = np.array([-n[1], n[0]])
    Kr = K[:2, :2]
    Kt = K[3:, 3:]
    return {
        "radial_along": float(n @ Kr @ n), "radial_across": float(t @ Kr @ t),
        "axial": float(K[2, 2]), "tilt_along": float(n @ Kt @ n),
        "tilt_across": float(t @ Kt @ t), "residual": residual,
        "displacement": [float(x) for x in d],
        "rollers_loaded": int(np.sum(np.asarray(b.element_loads(d)).sum(axis=-1) > 0)),
        "moment_Nm": [float(x) for x in np.asarray(b.load(d))[3:]],
    }


def compare(loads: dict | None = None) -> dict:
    """Per bearing: the published load, the load evaluated, the estimated rollers, the
    stiffness from geometry (each clearance for the cylindrical ones) and the published values,
    with the ratios geometry / published of the radial (mean of the two), axial and tilt (mean
    of the two) stiffnesses (None where a value is 0)."""
    loads = published_loads() if loads is None else loads
    out = {}
    for name, row in TABLE.items():
        f = np.asarray(loads[name], float)
        load = bearing_load(name, f)
        clearances = CLEARANCES if row["type"] == "CRB" else (0.0,)
        b0 = bearing(name)
        entry = {
            "designation": row["designation"], "type": row["type"],
            "published": {k: row[k] for k in ("K_x", "K_y", "K_z", "K_beta", "K_gamma")},
            "case_load_N": [float(x) for x in f],
            "evaluated_load_N": [float(x) for x in load],
            "rollers": {"elements": b0.elements, "diameter_mm": float(b0.element_diameter) * 1e3,
                        "length_mm": float(b0.effective_length) * 1e3,
                        "pitch_diameter_mm": float(b0.pitch_diameter) * 1e3,
                        "contact_angle_deg": math.degrees(float(b0.nominal_angle))},
            "geometry": {},
        }
        kr = 0.5 * (row["K_y"] + row["K_z"])
        kt = 0.5 * (row["K_beta"] + row["K_gamma"])
        for c in clearances:
            g = stiffness_figures(bearing(name, c), load)
            g["ratio_radial"] = 0.5 * (g["radial_along"] + g["radial_across"]) / kr
            # None where either is 0 (IMS-A published without, the kind NU carrying none)
            g["ratio_axial"] = g["axial"] / row["K_x"] if row["K_x"] > 0 < g["axial"] else None
            g["ratio_tilt"] = 0.5 * (g["tilt_along"] + g["tilt_across"]) / kt
            entry["geometry"][f"{c * 1e6:g}um"] = g
        out[name] = entry
    return out


#: the stage-1 spherical roller bearings of the same table (the embedded catalogue entries):
#: published K_x, K_y, K_z (N/m), K_beta, K_gamma (N·m/rad)
SPHERICAL = {
    "INP-B": dict(designation="231/750 CA", K_x=4.06e8, K_y=1.54e10, K_z=1.54e10, K_beta=0.0,
                  K_gamma=0.0),
    "PLC-A": dict(designation="240/710 ECA", K_x=6.6e4, K_y=1.7e9, K_z=1.1e9, K_beta=5.6e5,
                  K_gamma=1.3e5),
}
#: the rotor's (and the carrier's) rated speed (rad/s) and the design life (s): 12.1 rpm, 20 years
ROTOR_SPEED, DESIGN_LIFE = 12.1 * 2 * math.pi / 60, 20 * 365.25 * 24 * 3600.0


def spherical_at_design_load() -> dict:
    """The stage-1 spherical roller bearings (the catalogue's 231/750 CA and 240/710 ECA, rollers
    estimated) at the radial load P that gives ISO 281's L10 of the 20-year design life at the
    rotor's rated 12.1 rpm, P = C (L10 / 10⁶)^(−3/10) (no model of the main shaft's and the
    carrier's loads here): their radial, axial and tilt stiffness against the published."""
    import jaxgear.bearings as jb

    revolutions = ROTOR_SPEED / (2 * math.pi) * DESIGN_LIFE
    out = {}
    for name, row in SPHERICAL.items():
        b = jb.catalogue(row["designation"])
        P = float(b.dynamic_rating) * (revolutions / 1e6) ** -0.3
        s = jb.solve_displacement(b, np.array([P, 0.0, 0.0, 0.0, 0.0]))
        K = np.asarray(s.stiffness)
        out[name] = {
            "designation": row["designation"],
            "published": {k: row[k] for k in ("K_x", "K_y", "K_z", "K_beta", "K_gamma")},
            "radial_load_N": P, "life_revolutions": revolutions,
            "radial_along": float(K[0, 0]), "radial_across": float(K[1, 1]),
            "axial": float(K[2, 2]), "tilt": float(max(K[3, 3], K[4, 4])),
            "residual": float(s.residual),
            "ratio_radial": float(0.5 * (K[0, 0] + K[1, 1]) / (0.5 * (row["K_y"] + row["K_z"]))),
            "ratio_axial": float(K[2, 2] / row["K_x"]),
        }
    return out


def roller_sensitivity(loads: dict, name: str = "HS-A") -> list:
    """How much the estimate of the rollers moves a cylindrical bearing's radial stiffness:
    ``name`` at its evaluated load (zero clearance) with the roller diameter (the count
    following, the rule's 0.8 π d_m / D_w) or the length scaled by 0.8 and 1.2."""
    import jaxgear.bearings as jb

    row = TABLE[name]
    d, D, B = row["d"] * 1e-3, row["D"] * 1e-3, row["B"] * 1e-3
    base = jb.estimated_rollers(d, D, B)
    load = bearing_load(name, loads[name])
    out = []
    for fd, fl in ((1.0, 1.0), (0.8, 1.0), (1.2, 1.0), (1.0, 0.8), (1.0, 1.2)):
        Dw = base["element_diameter"] * fd
        b = jb.CylindricalRoller(bore=d, outer_diameter=D, width=B, pitch_diameter=base[
            "pitch_diameter"], element_diameter=Dw, elements=int(
                0.8 * math.pi * base["pitch_diameter"] / Dw),
            effective_length=base["effective_length"] * fl)
        g = stiffness_figures(b, load)
        out.append({"diameter_scale": fd, "length_scale": fl, "elements": b.elements,
                    "radial_along": g["radial_along"], "radial_across": g["radial_across"]})
    return out


#: the example's tapered pairs: name -> (shaft, bearing index in the example)
PAIRS = {"HS-B/C": ("pinion_shaft", 1), "IMS-B/C": ("gear_shaft", 1)}


def pairs_at_operating_point(case=None) -> dict:
    """The example's tapered pairs at its own operating point (:func:`jaxgear.io.operating_point`:
    the fixed point of the quasi-static solve at rated torque on the bearings' tangent
    stiffness): per pair its load f (N, N·m), displacement, the pressure centres' spread (m),
    each row's load about its own mid-plane (radial, axial; N), the number of rollers loaded per
    row and the tangent stiffness's diagonal (N/m, N·m/rad); and the cylindrical ones' loads."""
    import jaxgear.io as jio

    case = jio.load_case(EXAMPLE) if case is None else case
    point = jio.operating_point(case, case.scene)
    shafts = {"pinion_shaft": 0, "gear_shaft": 1}
    out = {"iterations": int(point.iterations), "change": float(point.change), "pairs": {},
           "cylindrical_loads_N": {}}
    for name, (shaft, j) in PAIRS.items():
        i = shafts[shaft]
        st = point.states[i][j]
        b = point.shafts[i].bearings[j].rolling
        d = np.asarray(st.displacement)
        rows = []
        own = np.asarray(b.row_loads(d))  # each row in its own frame (+z: the way it carries)
        q = np.asarray(b.element_loads(d)).sum(axis=-1)
        for f, qi in zip(own, q, strict=True):
            rows.append({"radial_N": float(math.hypot(f[0], f[1])), "axial_N": float(f[2]),
                         "rollers_loaded": int(np.sum(qi > 0))})
        K = np.asarray(st.stiffness)
        out["pairs"][name] = {
            "load_N": [float(x) for x in np.asarray(point.loads[i][j])],
            "displacement": [float(x) for x in d], "spread_m": float(b.spread),
            "rows": rows, "stiffness_diagonal": [float(K[k, k]) for k in range(5)],
            "residual": float(st.residual)}
    for name, (shaft, j) in (("HS-A", ("pinion_shaft", 0)), ("IMS-A", ("gear_shaft", 0))):
        out["cylindrical_loads_N"][name] = [
            float(x) for x in np.asarray(point.loads[shafts[shaft]][j])]
    return out


def mesh_modes(case, count: int = 4) -> dict:
    """The mesh-averaged system's modes of the largest mesh energy: the mesh mode (the
    largest) and the ``count`` largest with their frequency (Hz) and share of mesh energy."""
    from jaxgear.dynamics import mesh_averaged_modes
    from jaxgear.io import build_dynamic_model

    model, _ = build_dynamic_model(case)
    modes = mesh_averaged_modes(model, speed=case.speed, positions_per_pitch=16)
    f = np.asarray(modes.omega) / (2 * math.pi)
    e = np.asarray(modes.mesh_energy)
    order = np.argsort(-e)[:count]
    return {"mesh_mode_Hz": float(f[order[0]]),
            "largest": [{"Hz": float(f[i]), "mesh_energy": float(e[i])} for i in order]}


def unhoused(case_name: str):
    """A case without its ``[housing]`` (and ``[whine]``, which reads the housing's points)."""
    import jaxgear.io as jio

    with open(os.path.join(ROOT, "jaxgear", "cases", f"{case_name}.toml"), encoding="utf-8") as f:
        data = tomllib.loads(f.read())
    for key in ("housing", "whine"):
        data.pop(key, None)
    return jio.parse_case(data)


def housed_rolling_text() -> str:
    """examples/nrel-5mw-stage3-rolling.toml in nrel-5mw-stage3-housed's housing: that case's
    ``[housing]``, its points and its ``[whine]`` appended (the same box, speeds and orders)."""
    with open(EXAMPLE, encoding="utf-8") as f:
        example = f.read()
    with open(HOUSED, encoding="utf-8") as f:
        housed = f.read()
    example = example.replace('name = "nrel-5mw-stage3-rolling"',
                              'name = "nrel-5mw-stage3-rolling-housed"')
    return example + "\n" + housed[housed.index("\n[housing]") + 1 :]


def whine_run(case: str, out: str) -> dict:
    """``jaxgear run`` of ``case`` (a path or an embedded name) into ``out`` (a fresh process of
    this tree): the overall ERP (dB) and the order-1 TE amplitude (µm) at each speed, and
    their largest."""
    code = "import jaxgear_start; jaxgear_start.entry()"
    subprocess.run([sys.executable, "-c", code, "run", case, "--out", out, "--quiet"], cwd=ROOT,
                   env={**os.environ, "PYTHONPATH": ROOT}, check=True)
    with open(os.path.join(out, "whine", "housing.json"), encoding="utf-8") as f:
        housing = json.load(f)
    with open(os.path.join(out, "whine", "whine.json"), encoding="utf-8") as f:
        whine = json.load(f)
    erp = [float(x) for x in housing["overall_erp_level_dB"]]
    order1 = whine["orders"].index(1.0)
    te = [float(a[order1][0]) * 1e6 for a in whine["transmission_error_m"]["amplitude"]]
    speeds = [float(x) for x in housing["speeds_rad_s"]]
    i, j = int(np.argmax(erp)), int(np.argmax(te))
    return {"speeds_rad_s": speeds, "overall_erp_dB": erp, "te_order1_um": te,
            "max_overall_erp_dB": erp[i], "speed_of_max_erp_rad_s": speeds[i],
            "max_te_order1_um": te[j], "speed_of_max_te_rad_s": speeds[j]}


def modes_in_band(case, lo: float, hi: float, least: float = 0.01) -> list:
    """The mesh-averaged modes of ``case`` between ``lo`` and ``hi`` (Hz) with at least
    ``least`` of their energy in the mesh: (Hz, mesh energy) each."""
    from jaxgear.dynamics import mesh_averaged_modes
    from jaxgear.io import build_dynamic_model

    model, _ = build_dynamic_model(case)
    modes = mesh_averaged_modes(model, speed=case.speed, positions_per_pitch=16)
    f = np.asarray(modes.omega) / (2 * math.pi)
    e = np.asarray(modes.mesh_energy)
    return [{"Hz": float(f[i]), "mesh_energy": float(e[i])} for i in range(len(f))
            if lo <= f[i] <= hi and e[i] >= least]


def whine_both() -> dict:
    """The whine of the housed stage on both bearing sets (:func:`whine_run`): the published
    springs (the embedded nrel-5mw-stage3-housed) and the bearings from geometry
    (:func:`housed_rolling_text`)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "nrel-5mw-stage3-rolling-housed.toml")
        with open(path, "w", encoding="utf-8") as f:
            f.write(housed_rolling_text())
        return {"published springs": whine_run("nrel-5mw-stage3-housed",
                                               os.path.join(tmp, "published")),
                "from geometry": whine_run(path, os.path.join(tmp, "geometry"))}


def chart(result: dict, path: str) -> None:
    """Bars of geometry / published per bearing (radial, axial, tilt; zero clearance)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(result["bearings"])
    whine = result.get("whine")
    fig, axes = plt.subplots(1, 2 if whine else 1, figsize=(14 if whine else 8, 4.2))
    ax = axes[0] if whine else axes
    width = 0.27
    for k, (key, label) in enumerate((("ratio_radial", "radial"), ("ratio_axial", "axial"),
                                      ("ratio_tilt", "tilt"))):
        vals = [result["bearings"][n]["geometry"]["0um"][key] for n in names]
        xs = [i + (k - 1) * width for i, v in enumerate(vals) if v is not None]
        ax.bar(xs, [v for v in vals if v is not None], width, label=label)
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_yscale("log")
    ax.set_xticks(range(len(names)), names)
    ax.set_ylabel("from geometry / published")
    ax.set_title("NREL 5 MW stage 3: bearing stiffness from geometry (zero clearance)\n"
                 "at the published case's loads, against Nejad et al. 2016")
    ax.legend()
    if whine:
        for label, run in whine.items():
            axes[1].plot(run["speeds_rad_s"], run["overall_erp_dB"], marker=".", label=label)
        axes[1].set_xlabel("pinion speed (rad/s)")
        axes[1].set_ylabel("overall ERP (dB re 1 pW)")
        axes[1].set_title("the housed stage's whine with both bearing sets")
        axes[1].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", required=True, help="the JSON record to write (a PNG beside it)")
    p.add_argument("--no-modes", action="store_true", help="skip the mesh modes")
    p.add_argument("--no-whine", action="store_true", help="skip the two housed whine runs")
    a = p.parse_args(argv)
    import jax

    jax.config.update("jax_enable_x64", True)
    import jaxgear.io as jio

    from ._timing import environment, write_record

    t0 = time.perf_counter()
    result = {
        "benchmark": "nrel-stage3-bearings",
        "what": "the NREL 5 MW stage-3 bearings from their geometry (rollers estimated) at the "
                "published case's loads against the published stiffnesses (Nejad et al. 2016 "
                "via gfsReboucas/Drivetrain 4a88df3); the mesh mode with both bearing sets",
        "date": time.strftime("%Y-%m-%d", time.gmtime()),
        "environment": environment(),
    }
    loads = published_loads()
    result["bearings"] = compare(loads)
    result["roller_sensitivity_HS-A"] = roller_sensitivity(loads)
    result["spherical_stage1"] = spherical_at_design_load()
    result["pairs_at_operating_point"] = pairs_at_operating_point()
    if not a.no_modes:
        case = jio.load_case(EXAMPLE)
        result["rated_mesh_frequency_Hz"] = case.pair.pinion.teeth * case.speed / (2 * math.pi)
        result["modes"] = {
            "published springs": mesh_modes(unhoused("nrel-5mw-stage3-housed")),
            "from geometry": mesh_modes(case),
        }
    if not a.no_whine:
        result["whine"] = whine_both()
        # the housed systems' mesh-coupled modes over the order-1 band of the [whine] speeds
        housed = {"published springs": jio.load_case("nrel-5mw-stage3-housed"),
                  "from geometry": jio.parse_case(tomllib.loads(housed_rolling_text()))}
        per_rad_s = housed["published springs"].pair.pinion.teeth / (2 * math.pi)
        speeds = [x for w in result["whine"].values() for x in w["speeds_rad_s"]]
        result["housed_modes_in_order1_band"] = {
            k: modes_in_band(c, min(speeds) * per_rad_s, max(speeds) * per_rad_s)
            for k, c in housed.items()}
    result["seconds"] = time.perf_counter() - t0
    write_record(a.out, result)
    chart(result, os.path.splitext(a.out)[0] + ".png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
