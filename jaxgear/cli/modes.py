"""``jaxgear modes CASE``: the natural frequencies (Hz) with their mode type, for every kind of
case, written to ``modes.json`` (atomically, into ``--out``, default
``jaxgear-out/<case>/modes/``) and printed as a table.

By the case's form (:class:`jaxgear.io.CaseForm`, :func:`case_modes`):

* **a planetary stage** (:class:`~jaxgear.io.PlanetaryForm`): the lumped planar and torsional
  models' modes (:func:`jaxgear.planetary.planetary_modes`), typed by
  :func:`jaxgear.planetary.classify_modes` (rotational, translational, planet; Lin & Parker 1999),
  with their multiplicities — the same lists as ``jaxgear run``'s ``modes.json``;
* **pairs and trains** (torsional and lumped 3D scenes, the case's ``[scene]``, else the
  torsional model): the modes of the scene's linearised model at the mean loaded mesh
  stiffness (:func:`jaxgear.dynamics.mesh_averaged_modes`, the modes ``jaxgear sweep`` reads),
  each typed by the **coordinate group carrying most of its kinetic energy**: a shaft node's
  u_x, u_y, φ_x, φ_y ``bending``, u_z ``axial``, φ_z ``torsional`` (the shaft axis z); a
  torsional scene's coordinates are all ``torsional``, a flexible housing's (``[housing]``:
  its seats' and its modal coordinates) ``housing``. The share of mode i in group g is
  e_g = Σ_{j∈g} φ_ji (M φ_i)_j (mass-normalised φ_i: the shares sum to 1); a rigid mode
  (0 Hz: the drive rotation) is typed ``rigid``;
* **a gearbox** (:class:`~jaxgear.io.GearboxForm`): the modes its dynamic model
  (:class:`jaxgear.gearbox.GearboxModel`) lists (:meth:`~jaxgear.gearbox.GearboxModel.
  natural_modes`: without a shared housing the torsional chain's, with one the coupled
  modes), each typed by the **stage holding most of its kinetic energy** (``stage<k>``,
  :attr:`jaxgear.dynamics.ModalAnalysis.kinetic`; 0 Hz: ``rigid body``) with the stages'
  shares, ``torsional_chain``; with the housing each typed as
  :func:`jaxgear.gearbox.coupled_mode_table` types it (the mesh, a shaft, the output hold,
  the housing or the structure) with the stages' and the housing's kinetic shares,
  ``coupled_with_housing``;
* **flexible cases** (condensed FE bodies: the hybrid model): the lowest
  :data:`HYBRID_MODES` modes of the condensed bodies' scene at the operating speed, typed by
  the **part storing most of their strain energy** (``mesh`` or a body or bearing part of the
  scene, :attr:`jaxgear.dynamics.ModalAnalysis.parts`).
"""

from __future__ import annotations

import functools
import itertools
import os

import numpy as np

from .. import io as case_io
from ..dynamics import DynamicModel, HybridModel
from ..gearbox import GearboxModel, coupled_mode_table, gearbox_coupled_modes
from ..io import write_json
from ._paths import check_case_outputs, staged_outputs
from .planetary import mode_list, mode_models

__all__ = [
    "DOF_GROUPS",
    "HYBRID_MODES",
    "MODES_SLICES",
    "case_modes",
    "group_shares",
    "mode_table",
    "run_modes",
]

#: the type of each coordinate of a structure node, by the node's number of coordinates
DOF_GROUPS = {
    6: ("bending", "bending", "axial", "bending", "bending", "torsional"),
    1: ("torsional",),
}
#: the modes a hybrid model lists (of thousands of coordinates)
HYBRID_MODES = 20
#: slices per contact line of the models whose modes are listed (``jaxgear run``'s sweep's)
MODES_SLICES = 8


def group_shares(
    mass, shapes, node_dofs: int, housing_from: int | None = None
) -> tuple[tuple, np.ndarray]:
    """(group names, shares (g, n)): each mode's kinetic-energy share per coordinate group
    (:data:`DOF_GROUPS` of ``node_dofs`` coordinates per node; the coordinates from
    ``housing_from`` on, a flexible housing's seats and modal coordinates, the group
    ``housing``), mass-normalised ``shapes`` (n_dof, n) and ``mass`` (n_dof, n_dof)."""
    labels = DOF_GROUPS[node_dofs]
    phi = np.asarray(shapes)
    energy = phi * (np.asarray(mass) @ phi)  # (n_dof, n): sums to 1 over the coordinates
    n = phi.shape[0] if housing_from is None else housing_from
    names = tuple(dict.fromkeys(labels)) + (() if housing_from is None else ("housing",))
    of = np.array(
        [names.index(labels[j % node_dofs]) for j in range(n)]
        + [len(names) - 1] * (phi.shape[0] - n)
    )
    shares = np.stack([energy[of == g].sum(axis=0) for g in range(len(names))])
    return names, shares


@functools.singledispatch
def typed_modes(model, modes) -> dict:
    """``modes.json``'s list of a dynamic model's ``modes`` (:class:`~jaxgear.dynamics.
    ModalAnalysis`), each typed (module docstring)."""
    raise TypeError(f"jaxgear modes: no modes of a {type(model).__name__}")


@typed_modes.register
def _(model: DynamicModel, modes) -> dict:
    scene = model.scene
    seats = [first for name, first in scene.structure.nodes if name.startswith("housing ")]
    names, shares = group_shares(
        scene.mass(), modes.shapes, scene.structure.node_dofs, min(seats) if seats else None
    )
    rigid = np.asarray(modes.rigid)
    rows = []
    for i, f in enumerate(np.asarray(modes.frequency)):
        kind = "rigid" if rigid[i] else names[int(np.argmax(shares[:, i]))]
        rows.append({
            "frequency_Hz": float(f),
            "type": kind,
            "kinetic_energy_shares": {n: float(shares[g, i]) for g, n in enumerate(names)},
        })
    return {
        "classification": "coordinate group of the largest kinetic energy",
        "mesh_stiffness_mean_N_per_m": float(model.mesh_stiffness_mean),
        "modes": rows,
    }


@typed_modes.register
def _(model: HybridModel, modes) -> dict:
    parts = modes.parts
    energy = np.asarray(modes.energy)[:, :HYBRID_MODES]
    rigid = np.asarray(modes.rigid)
    housing = _housing_share(model.scene, np.asarray(modes.shapes)[:, :HYBRID_MODES])
    rows = []
    for i, f in enumerate(np.asarray(modes.frequency)[:HYBRID_MODES]):
        kind = "rigid" if rigid[i] else parts[int(np.argmax(energy[:, i]))]
        rows.append({
            "frequency_Hz": float(f),
            "type": kind,
            "strain_energy_shares": {p: float(energy[k, i]) for k, p in enumerate(parts)},
            **({} if housing is None else {"housing_kinetic_energy_share": float(housing[i])}),
        })
    return {"classification": "part storing the largest strain energy", "modes": rows}


@typed_modes.register
def _(model: GearboxModel, modes) -> dict:
    f, rigid = np.asarray(modes.frequency), np.asarray(modes.rigid)
    shares = np.asarray(modes.kinetic)
    stages = [g for g, name in enumerate(modes.groups) if name != "housing"]
    if model.chain.housing is None:
        rows = [{
            "frequency_Hz": float(f[j]),
            "type": "rigid body" if rigid[j] else modes.groups[int(np.argmax(shares[:, j]))],
            "stage_energy": [float(v) for v in shares[stages, j]],
        } for j in range(f.size)]
        return {"model": "gearbox torsional chain",
                "classification": "the stage holding most of the kinetic energy",
                "torsional_chain": rows}
    # the coupled modes' types by their strain energy (mesh, joint) or housing share
    table = coupled_mode_table(model.chain, gearbox_coupled_modes(model.chain, model.run))
    housing = modes.groups.index("housing")
    rows = [dict(row, stage_energy=[float(v) for v in shares[stages, j]],
                 housing_energy=float(shares[housing, j]))
            for j, row in enumerate(table)]
    return {"model": "coupled gearbox on its housing",
            "classification": "the stage or the housing holding most of the kinetic energy",
            "coupled_with_housing": rows}


def _housing_share(scene, shapes) -> np.ndarray | None:
    """Each mass-normalised mode's (columns of ``shapes``) share of kinetic energy in a hybrid
    scene's flexible housing: e = Σ_{j∈housing} φ_j (M φ)_j over its coordinates (its seats'
    six each from the node ``housing <seat>`` of the lowest index on, then its modal ones, up
    to the bodies' rim masters and modal coordinates, which follow it); None without a
    housing."""
    nodes = [first for name, first in scene.structure.nodes if name.startswith("housing ")]
    if not nodes:
        return None
    M = np.asarray(scene.mass())
    after = [
        int(d)
        for m in scene.members
        if hasattr(m, "rim_dofs")
        for d in np.concatenate([np.ravel(m.rim_dofs), np.ravel(m.body_dofs)])
        if d >= max(nodes) + 6
    ]
    h = slice(min(nodes), min(after, default=M.shape[0]))
    return np.einsum("ji,ji->i", shapes[h], (M @ shapes)[h])


@functools.singledispatch
def _modes_slices(form, case) -> int | None:
    """The slices per contact line of the dynamic model whose modes a case of ``form`` lists:
    :data:`MODES_SLICES` at most (``jaxgear run``'s sweep's), the case's if fewer."""
    return min(case.slices, MODES_SLICES)


@_modes_slices.register
def _(form: case_io.GearboxForm, case) -> None:
    return None  # the coupled model's own (jaxgear run's coupled sweep's, jaxgear sweep's)


@functools.singledispatch
def case_modes(form, case) -> dict:
    """``modes.json`` of a case of ``form`` (module docstring): the natural modes of its
    dynamic model (:func:`jaxgear.io.build_dynamic_model`,
    :meth:`~jaxgear.dynamics.AbstractDynamicModel.natural_modes`: a pair's, a train's or a
    gearbox's), typed by the model's kind (:func:`typed_modes`)."""
    spec = case.scene if case.scene is not None else case_io.SceneSpec()
    bodies = case_io.load_bodies(spec, progress=False) if spec.hybrid else None
    model, spec = case_io.build_dynamic_model(
        case, spec, slices=_modes_slices(form, case), bodies=bodies
    )
    modes = model.natural_modes(speed=case.speed,
                                positions_per_pitch=spec.steps_per_period or 64)
    return {"case": case.name, "model": spec.model, **typed_modes(model, modes)}


@case_modes.register
def _(form: case_io.PlanetaryForm, case) -> dict:
    stage = form.spec.stage(case)
    return {
        "case": case.name,
        "model": "planetary (lumped)",
        "classification": "Lin & Parker 1999: rotational, translational, planet; 3D (helical): "
        "Eritenel & Parker 2009: rotational-axial, translational-tilting, planet",
        **{name: mode_list(model, stage) for name, model in mode_models(stage, case).items()},
    }


def mode_table(data: dict) -> list[str]:
    """The printed table of ``modes.json``'s content: one row per mode, except that the modes of
    one type at one frequency (to 1e-6 Hz: a planetary stage's degenerate pairs, a symmetric
    train's repeated modes) share a row that gives their numbers (``5-6``) and their count
    (``× 2``, or the classifier's multiplicity where it says more), with a note under the
    table saying so; ``modes.json`` keeps every mode."""
    lists = {k: v for k, v in data.items() if isinstance(v, list)}
    lines = [f"{data['case']}: natural frequencies ({data['classification']}; # from 1, "
             "as the sweep's figures number the modes)"]
    merged = False
    for name, rows in lists.items():
        lines.append(f"{name}:" if len(lists) > 1 else "")
        lines.append(f"{'#':>7} {'frequency (Hz)':>16}  type")
        numbered = list(enumerate(rows, start=1))
        groups = itertools.groupby(
            numbered, key=lambda im: (im[1]["type"], round(im[1]["frequency_Hz"], 6))
        )
        for _, group in groups:
            group = list(group)
            (i, m), last = group[0], group[-1][0]
            count = max(len(group), m.get("multiplicity", 1))
            merged |= len(group) > 1
            number = f"{i}" if last == i else f"{i}-{last}"
            extra = f" × {count}" if count > 1 else ""
            lines.append(f"{number:>7} {m['frequency_Hz']:>16.6g}  {m['type']}{extra}")
    if merged:
        lines.append("(a row numbered i-j holds the modes of one type at one frequency: a "
                     "repeated or degenerate mode, × its count; modes.json lists each)")
    return [line for line in lines if line]


def default_modes_dir(case_name: str) -> str:
    """``jaxgear modes``' default folder, ``jaxgear-out/<case>/modes``."""
    return os.path.join("jaxgear-out", case_name, "modes")


def run_modes(args) -> int:
    """Run ``jaxgear modes`` (float64 on: the CLI does it). Returns 0."""
    case = case_io.load_case(args.case)
    out = check_case_outputs(case, "modes", args.out or default_modes_dir(case.name),
                             force=args.force)
    data = case_modes(case.form, case)
    with staged_outputs(out, "modes") as work:
        write_json(os.path.join(work, "modes.json"), data)
    print("\n".join(mode_table(data)))
    print(f"written to {out}/")
    return 0
