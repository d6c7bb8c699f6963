"""``jaxgear run`` on a case with a ``lumped3d`` scene: the quasi-static TE of the scene (shafts,
bearings and, when the scene has them, condensed FE bodies), bearing forces, centrifugal rim
growth, load maps and a VTU of the deformed body (``quasi_static_scene`` in ``summary.json``)."""

from __future__ import annotations

import dataclasses
import functools
import os
from typing import NamedTuple

import numpy as np

from .. import contact_pressure, load_map, quasi_static
from .. import dynamics, io as case_io
from ..io import Case, atomic_open, write_vtu
from ..scenes import FlexibleMember, HybridScene
from . import _plots
from ._housing_run import hybrid_seats_line, hybrid_seats_section
from ._progress import inner_bars, progress as progress_bar
from ._stress_outputs import body_stress_outputs
from ._summary import result_summary

__all__ = ["SCENE_LINES", "condensed_outputs", "scene_lines", "scene_model", "scene_outputs"]


def _rot(angle, v):
    c, s = np.cos(angle), np.sin(angle)
    out = np.array(v, dtype=float)
    out[:, 0], out[:, 1] = c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]
    return out


def _body_vtu(path, member, body, theta, x, extra=None) -> None:
    """One flexible body deformed by the coordinates ``x`` at pinion angle ``theta`` (fixed
    frame: the body turned to that position, centred on its axis)."""
    q = x[np.asarray(member.body_dofs)]
    u = (np.asarray(body.recovery, dtype=float) @ q).reshape(-1, 3)
    ang = float(member.frame_angle(theta))
    pts = _rot(ang, np.asarray(body.recovery_coords)) + np.asarray(member.centre)
    write_vtu(
        path,
        pts,
        [("hexahedron", np.asarray(body.recovery_cells))],
        {"displacement_m": _rot(ang, u), **(extra or {})},
    )


@functools.singledispatch
def _first_body_coordinate(member) -> int | None:
    """The first of a member's condensed-body coordinates (the key of its body: two gears on
    one body share it); None for a member without a body (rigid, torsional)."""
    return None


@_first_body_coordinate.register
def _(member: FlexibleMember) -> int | None:
    return int(np.asarray(member.body_dofs)[0])


def _flexible(scene, bodies, names=None):
    """(name, member, body) of each condensed body; ``names``: {member index: name} (default a
    pair's "pinion" and "gear"). A body carrying two gears (members on the same body
    coordinates) comes once, named by its gears joined with "+" (``wheel+pinion``)."""
    names = names or {0: "pinion", 1: "gear"}
    out: dict[int, list] = {}  # first body coordinate -> [names, member, body]
    for m, (member, body) in enumerate(zip(scene.members, bodies, strict=True)):
        key = _first_body_coordinate(member)
        if key is None or body is None:
            continue
        if key in out:
            out[key][0].append(names[m])
        else:
            out[key] = [[names[m]], member, body]
    return [("+".join(n), member, body) for n, member, body in out.values()]


def write_bodies_vtu(out_dir, scene, bodies, res, k: int, names=None) -> list[str]:
    """``body_<name>.vtu`` of each condensed body deformed by the quasi-static result ``res``
    at its position ``k`` (fixed frame: each body turned to its own angle there, centred on its
    axis); ``names``: {member index: name} (a train's gear names; default a pair's "pinion"
    and "gear"; a body carrying two gears is written once, ``body_<gear>+<gear>.vtu``).
    Returns the file names."""
    theta = float(res.theta[k])
    x = np.asarray(res.x[k])
    written = []
    for name, member, body in _flexible(scene, bodies, names):
        _body_vtu(os.path.join(out_dir, f"body_{name}.vtu"), member, body, theta, x)
        written.append(f"body_{name}.vtu")
    return written


def body_outputs(out_dir, scene, bodies, res, k: int, names=None):
    """Each condensed body at the quasi-static result ``res``'s position ``k``: its deformed
    ``body_<name>.vtu`` (:func:`write_bodies_vtu`) and its rim and web stresses there
    (:func:`jaxgear.cli.body_stress_outputs`); ``names`` as :func:`write_bodies_vtu`'s.
    Returns (the body VTU files, the ``body_stress`` section, the stress VTU files)."""
    vtu = write_bodies_vtu(out_dir, scene, bodies, res, k, names)
    stress, stress_files = body_stress_outputs(out_dir, _flexible(scene, bodies, names), res.x[k])
    return vtu, stress, stress_files


#: positions whose largest line load is within this relative distance of the largest count as
#: tied: a load plateau (one tooth pair carrying the whole load) repeats the same peak over many
#: positions to round-off, and np.argmax's pick among them moved with BLAS threading
PEAK_RTOL = 1e-9


def first_peak(peak, rtol: float = PEAK_RTOL) -> int:
    """The first index of ``peak`` (1-D) within ``rtol`` (default :data:`PEAK_RTOL`) of its
    largest value: the position a body's deformation and stresses are reported at, the same
    whatever round-off decides among a plateau's equal peaks."""
    peak = np.asarray(peak)
    top = peak.max()
    return int(np.flatnonzero(peak >= top - rtol * abs(top))[0])


def peak_position(res) -> int:
    """The position index of a one-mesh result's largest line load (:func:`first_peak`)."""
    return first_peak(np.asarray(res.line_load).reshape(res.line_load.shape[0], -1).max(axis=1))


def write_contact_vtu(out_dir, scene, res, pressure, k: int) -> list[str]:
    """``contact.vtu``: the loaded contact cells of ``res`` at its position ``k`` with their
    line loads (N/m), Hertzian pressures (Pa) and contact half-widths (m), SI as the body VTUs
    (``pressure``: the result's :class:`~jaxgear.ContactPressure`)."""
    written = []
    cells = scene.mesh.cells(res.theta[k])
    on = np.asarray(cells.mask).reshape(-1)
    P = np.asarray(scene.points(cells)).reshape(-1, 3)[on]
    load = np.asarray(res.line_load[k]).reshape(-1)[on]
    p0 = np.asarray(pressure.max_pressure[k]).reshape(-1)[on]
    half = np.asarray(pressure.half_width[k]).reshape(-1)[on]
    write_vtu(
        os.path.join(out_dir, "contact.vtu"),
        P,
        [("vertex", np.arange(P.shape[0])[:, None])],
        {"line_load_N_per_m": load, "contact_pressure_Pa": p0, "contact_half_width_m": half},
    )
    written.append("contact.vtu")
    return written


#: what each scene model is, as a legend says it (the rigid mesh: both bodies rigid, no shafts)
SCENE_LABELS = {
    "rigid": "rigid mesh (rigid bodies)",
    "lumped3d": "lumped 3D scene (shafts, bearings)",
    "hybrid": "hybrid scene (condensed FE bodies, shafts, bearings)",
}


def scene_outputs(
    case: Case, out_dir: str, *, progress: bool = False, curves: dict | None = None
) -> dict:
    """Quasi-static solve of the case's scene (exact and smooth contact, one mesh period),
    written to ``out_dir``.

    Returns the ``quasi_static_scene`` entry of ``summary.json``: per contact mode the keys of
    ``quasi_static`` plus ``bearing_forces_mean_N`` (fixed frame); for a hybrid scene also
    ``centrifugal`` (rim radial growth per body at the case's speed), the load maps and the VTU
    files (written to ``out_dir``, the run's ``scene/`` folder: :func:`condensed_outputs`).

    ``progress``: a bar over the steps (the condensed bodies, built by fem-prep with its own
    bar on the first run and then read from its cache; the scene; each quasi-static solve; the
    maps and VTU files).

    ``curves``: a dict to fill with the scene's results, for ``te.csv``, ``mesh_stiffness.csv``
    and their plots beside the rigid mesh's, and for the rating's measured K_Hβ and K_Hα
    (:func:`jaxgear.cli._rating_report.scene_loads`): ``model`` ("lumped3d" or "hybrid"),
    ``base_planes`` (the scene's mesh models) and ``results`` ({"exact": ..., "smooth": ...} at the case's speed, and "exact_at_rest" when it
    is not 0).
    """
    hybrid = case.scene.hybrid
    n_steps = (6 if case.speed > 0 else 5) if hybrid else 3
    bar = progress_bar(total=n_steps, desc=f"jaxgear run {case.name}: scene", disable=not progress)
    # the case's [mesh] slices as they are (not capped); a hybrid case's
    # slices must nest in its bodies' axial rim faces (static_scene says so otherwise)
    slices = case.slices
    bodies = None
    if hybrid:
        bar.set_postfix_str("condensed bodies (fem-prep: built once, then cached)")
        bodies = case_io.load_bodies(case.scene, progress=inner_bars(progress))
        bar.update()
    bar.set_postfix_str("building the scene")
    scene, bodies = case_io.static_scene(case, slices=slices, bodies=bodies)
    out: dict = {"slices": slices, "model": scene_model(scene)}
    res, pressure = {}, {}
    for mode in ("exact", "smooth"):
        bar.update()
        bar.set_postfix_str(f"quasi-static, {mode} contact")
        res[mode] = quasi_static(
            scene,
            case.modifications,
            case.torque,
            speed=case.speed,
            contact=case.contact_law(mode),
            positions_per_pitch=case.positions_per_pitch,
        )
        pressure[mode] = _hertz(case, res[mode])
        out[mode] = result_summary(res[mode], None, pressure[mode])
        out[mode]["bearing_forces_mean_N"] = dynamics.bearing_forces(scene, res[mode])
    bar.update()
    if curves is not None:
        curves["model"] = out["model"]
        curves["results"] = dict(res)
        curves["base_planes"] = scene.base_planes
    run = _SceneRun(case, out_dir, bar, curves)
    out.update(condensed_outputs(scene, run, bodies, res, pressure))
    if (seated := hybrid_seats_section(case)) is not None:  # [housing] of a hybrid case
        out["housing"] = seated
    bar.close()
    return out


class _SceneRun(NamedTuple):
    """What :func:`condensed_outputs` writes to: the case, the run's ``scene/`` folder, its
    progress bar and the curves for ``te.csv`` (:func:`scene_outputs`' ``curves``)."""

    case: Case
    out_dir: str
    bar: object  # its progress bar (jaxgear.cli._progress.progress)
    curves: dict | None


def _hertz(case: Case, r):
    """The Hertzian contact pressure of the quasi-static result ``r`` of the case's pair."""
    return contact_pressure(case.pair, r, case.youngs_modulus, case.poisson_ratio)


@functools.singledispatch
def scene_model(scene) -> str:
    """``quasi_static_scene``'s ``model`` of a quasi-static scene, by its type: shafts and
    bearings (a grounded lumped 3D scene), "lumped3d"."""
    return "lumped3d"


@scene_model.register
def _(scene: HybridScene) -> str:
    return "hybrid"


@functools.singledispatch
def condensed_outputs(scene, run: _SceneRun, bodies, res: dict, pressure: dict) -> dict:
    """The outputs of the condensed FE bodies of a quasi-static ``scene`` solved as ``res``
    (:func:`scene_outputs`' exact and smooth results, their contact pressures ``pressure``),
    by the scene's type: none for a scene
    without condensed bodies; a :class:`~jaxgear.scenes.HybridScene`'s centrifugal rim growth,
    the solve at rest (the case's speed > 0), its load and pressure maps and VTU files, as
    ``quasi_static_scene`` keys."""
    return {}


@condensed_outputs.register
def _(scene: HybridScene, run: _SceneRun, bodies, res: dict, pressure: dict) -> dict:
    case, out_dir, bar, curves = run
    pair = case.pair
    ppp = case.positions_per_pitch
    growth = scene.rim_radial_growth(case.speed)
    out: dict = {"bodies": [b for b in case.scene.bodies], "speed_rad_s": case.speed}
    out["centrifugal"] = {
        "speed_rad_s": case.speed,
        "rim_radial_growth_m": {
            name: float(g)
            for name, g, b in zip(("pinion", "gear"), growth, bodies, strict=True)
            if b is not None
        },
    }
    files = []
    maps = [("load_map.png", res["exact"], "at rest" if case.speed == 0 else "")]
    if case.speed > 0:
        bar.set_postfix_str("quasi-static at rest")
        rest = quasi_static(
            scene,
            case.modifications,
            case.torque,
            positions_per_pitch=ppp,
        )
        out["exact_at_rest"] = result_summary(rest, None, _hertz(case, rest))
        if curves is not None:
            curves["results"]["exact_at_rest"] = rest
        maps = [
            ("load_map.png", rest, "at rest"),
            ("load_map_speed.png", res["exact"], f"at {case.speed:g} rad/s (pinion)"),
        ]
        bar.update()
    bar.set_postfix_str("load and pressure maps, VTU files")
    for kind, field, label, unit in (
        ("load", lambda r: None, "max line load (N/mm)", 1e3),
        ("pressure", lambda r: _hertz(case, r).max_pressure, "max contact pressure (MPa)", 1e6),
    ):
        grids = _common_bins([
            load_map(r, ppp, pair.base_pitch, pair.path_of_contact, field=field(r))
            for _, r, _ in maps
        ])
        vmax = max(float(np.nanmax(m)) for _, _, m in grids)  # one scale: at rest vs at speed
        for (name, _, when), (s_edges, z, grid) in zip(maps, grids, strict=True):
            name = name.replace("load_map", f"{kind}_map")
            dz = pair.face_width / len(z)
            _plots.load_map_plot(
                os.path.join(out_dir, name),
                s_edges,
                np.concatenate([[0.0], z + dz / 2]),
                grid,
                title=f"{case.name}: {kind} map, hybrid scene {when}".rstrip(),
                vmax=vmax,
                label=label,
                unit=unit,
            )
            files.append(name)
        if len(grids) == 2:  # the change the speed makes, on a scale of its own
            name = f"{kind}_map_speed_minus_rest.png"
            s_edges, z, _ = grids[1]
            dz = pair.face_width / len(z)
            _plots.map_difference_plot(
                os.path.join(out_dir, name),
                s_edges,
                np.concatenate([[0.0], z + dz / 2]),
                grids[1][2] - grids[0][2],
                title=f"{case.name}: {kind} map {maps[1][2]} minus at rest, hybrid scene",
                label=label.replace("max ", "Δ max "),
                unit=unit,
            )
            files.append(name)
    # the bodies deformed, their rim and web stresses and the contact cells (fixed frame) at
    # the position of the largest line load
    r = res["exact"]
    k = peak_position(r)
    vtu, out["body_stress"], stress_files = body_outputs(out_dir, scene, bodies, r, k)
    files += vtu + write_contact_vtu(out_dir, scene, r, pressure["exact"], k) + stress_files
    out["files"] = [f"{os.path.basename(out_dir)}/{f}" for f in files]
    bar.set_postfix_str("")
    bar.update()
    return out


@dataclasses.dataclass(frozen=True)
class SceneLines:
    """How the printed summary tells a ``quasi_static_scene`` section of one scene model:
    ``label``, its name there."""

    label: str

    def lines(self, q: dict) -> list[str]:
        """The section's lines: the exact solve's TE and largest line load."""
        e = q["exact"]
        return [
            f"{self.label}, exact: TE mean {e['te_mean_m'] * 1e6:.4f} µm, TE rms "
            f"{e['te_rms_m'] * 1e6:.4f} µm, max line load "
            f"{e['max_line_load_N_per_m'] / 1e3:.1f} N/mm"
        ]


class CondensedSceneLines(SceneLines):
    """A section with condensed bodies: each body's centrifugal rim growth after the TE."""

    def lines(self, q: dict) -> list[str]:
        c = q["centrifugal"]
        return super().lines(q) + [
            f"  {name} rim radial growth at {c['speed_rad_s']:g} rad/s (pinion): {g * 1e6:.3f} µm"
            for name, g in c["rim_radial_growth_m"].items()
        ] + hybrid_seats_line(q.get("housing"))


#: each scene model of ``quasi_static_scene`` (:func:`scene_model`) as the printed summary
#: tells it
SCENE_LINES = {
    "lumped3d": SceneLines("lumped 3D scene"),
    "hybrid": CondensedSceneLines("hybrid scene (condensed bodies)"),
}


def scene_lines(q: dict) -> list[str]:
    """Plain-text lines for the printed summary of a ``quasi_static_scene`` section ``q``."""
    return SCENE_LINES[q["model"]].lines(q)


def write_body_series(out_dir, scene, bodies, dyn, names=None) -> list[str]:
    """VTU time series of each flexible body over the kept steps of one speed
    (:class:`jaxgear.dynamics.DynamicResponse` with ``states``): ``body_<name>_NNNN.vtu`` and a
    ParaView collection ``body_<name>.pvd`` (time in s), written atomically; ``names``:
    {member index: name} (a train's gear names; default a pair's "pinion" and "gear"). Each
    body is drawn in the fixed frame, turned to its own angle at each step (its speed ratio
    and sense)."""
    states = np.asarray(dyn.states)
    theta = np.asarray(dyn.theta)
    dt = float(dyn.time_step)
    written = []
    for name, member, body in _flexible(scene, bodies, names):
        rows = []
        for k in range(states.shape[0]):
            fname = f"body_{name}_{k:04d}.vtu"
            _body_vtu(os.path.join(out_dir, fname), member, body, float(theta[k]), states[k])
            rows.append(f'    <DataSet timestep="{k * dt:.9e}" part="0" file="{fname}"/>')
            written.append(fname)
        pvd = os.path.join(out_dir, f"body_{name}.pvd")
        with atomic_open(pvd) as f:
            f.write(
                '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                "  <Collection>\n" + "\n".join(rows) + "\n  </Collection>\n</VTKFile>\n"
            )
        written.append(f"body_{name}.pvd")
    return written


def _common_bins(grids: list) -> list:
    """:func:`jaxgear.load_map` grids (s_edges, z, map) on the union of their bins, NaN where
    a grid has none: with contact beyond the theoretical path each map reaches as far as its
    own loaded cells (at rest and at speed differ), on one lattice of equal bins from s = 0."""
    width = float(grids[0][0][1] - grids[0][0][0])
    lo = min(float(g[0][0]) for g in grids)
    hi = max(float(g[0][-1]) for g in grids)
    n = int(round((hi - lo) / width))
    out = []
    for edges, z, grid in grids:
        k = int(round((float(edges[0]) - lo) / width))
        full = np.full((n, grid.shape[1]), np.nan)
        full[k : k + grid.shape[0]] = grid
        out.append((np.linspace(lo, hi, n + 1), z, full))
    return out

