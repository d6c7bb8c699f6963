"""JSON-ready sections of ``jaxgear run``'s ``summary.json`` shared by a pair's and a train's run:
the scalar figures of a quasi-static result, the mesh settings, the environment."""

from __future__ import annotations

import functools
import platform

import jax
import numpy as np

from .. import FE2D, AbstractStiffness, Modifications, QuasiStaticResult, Weber, __version__

__all__ = [
    "environment_summary",
    "format_table",
    "has_modifications",
    "mesh_settings_summary",
    "result_summary",
    "stiffness_line",
    "stiffness_note",
    "stiffness_reference",
]


def result_summary(r: QuasiStaticResult, mesh: int | None = None, pressure=None) -> dict:
    """Scalar figures of a quasi-static result (SI units), JSON-ready: of its one mesh, or of
    mesh ``mesh`` of a scene with several (a train); with that mesh's
    :class:`~jaxgear.ContactPressure`, its largest Hertzian pressure ``max_contact_pressure_Pa``
    and the half-width there ``contact_half_width_at_max_m``."""
    m = r if mesh is None else r.meshes[mesh]
    k = np.asarray(m.mesh_stiffness)
    extra = {}
    if pressure is not None:
        p = np.asarray(pressure.max_pressure)
        i = np.unravel_index(int(np.argmax(p)), p.shape)
        extra = {
            "max_contact_pressure_Pa": float(p[i]),
            "contact_half_width_at_max_m": float(np.asarray(pressure.half_width)[i]),
        }
    return {
        "te_mean_m": float(m.te_mean),
        "te_rms_m": float(m.te_rms),
        "te_ptp_m": float(m.te_ptp),
        "mesh_stiffness_mean_N_per_m": float(k.mean()),
        "mesh_stiffness_min_N_per_m": float(k.min()),
        "mesh_stiffness_max_N_per_m": float(k.max()),
        "contact_length_mean_m": float(np.mean(m.contact_length)),
        "max_line_load_N_per_m": float(m.max_line_load),
        "max_contact_iterations": int(np.max(r.iterations)),
        **extra,
    }


def mesh_settings_summary(case) -> dict:
    """``summary.json``'s ``mesh``: the mesh-model settings of a pair or train case."""
    return {
        **case.stiffness.summary(),  # stiffness, foundation, fe2d_size_m
        "slices": case.slices,
        "positions_per_pitch": case.positions_per_pitch,
        "smooth_width_m": case.smooth_width,
    }


def environment_summary(dtype) -> dict:
    """``summary.json``'s ``environment``: versions, backend and the run's ``dtype``."""
    return {
        "jaxgear": __version__,
        "jax": jax.__version__,
        "backend": jax.default_backend(),
        "dtype": str(dtype),
        "python": platform.python_version(),
    }


# the deviations a MemberModification adds: all zero = no modifications
_MODIFYING = ("tip_relief_depth", "root_relief_depth", "crowning_depth", "end_relief_depth",
              "helix_slope_deviation", "profile_deviation")


def has_modifications(mods: Modifications) -> bool:
    """Whether ``mods`` modifies a flank (a non-zero relief or crowning depth, helix slope or
    profile deviation on either member): a case without any has its "modified" results equal
    to the unmodified ones, and the table and the figures show them once."""
    return any(
        bool(np.any(np.asarray(getattr(m, name)) != 0))
        for m in (mods.pinion, mods.gear)
        for name in _MODIFYING
    )


@functools.singledispatch
def stiffness_line(model: AbstractStiffness) -> str:
    """Which mesh stiffness model ran, as ``jaxgear run``'s table says it (by the model's type:
    its foundation term, the FE model's element size)."""
    return f"mesh stiffness model: {model.name}"


@stiffness_line.register
def _(model: Weber) -> str:
    return f"mesh stiffness model: weber (foundation {model.foundation.name})"


@stiffness_line.register
def _(model: FE2D) -> str:
    part = "tooth + body to the bore" if model.foundation.fe_body else "tooth only"
    size = "m_n/6" if model.size is None else f"{model.size * 1e6:g} µm"
    return f"mesh stiffness model: fe2d (plane-strain FE, {part}, element size {size})"


def stiffness_reference(case, result) -> dict:
    """``summary.json``'s ``mesh_stiffness_reference`` of a pair run: the stiffness model's own
    reference figures at the case's pair and load (:meth:`~jaxgear.AbstractStiffness.summary_at`;
    ``iso6336``: c_γα and c_γα b / cos² β_b) beside the means of ``result`` (the unmodified
    flanks' exact quasi-static result, where every cell on the path is loaded): the loaded mean
    mesh stiffness (the table's "K mean", the tip corners' contact beyond the path included
    where the case has it) and its part on the theoretical path (N/m). Empty for a model
    without reference figures."""
    reference = case.stiffness.summary_at(case.pair, case.mesh_conditions())
    if not reference:
        return {}
    return {
        **reference,
        "mesh_stiffness_mean_N_per_m": float(np.mean(result.mesh_stiffness)),
        "mesh_stiffness_on_path_mean_N_per_m": float(np.mean(result.mesh_stiffness_on_path)),
        "extended_contact": bool(case.contact_geometry.reaches_beyond_path),
        "flanks": "unmodified, exact contact",
    }


def stiffness_note(summary: dict) -> str | None:
    """The printed line of a pair's ``summary`` that says which mean mesh stiffness the
    table's "K mean" is and sets the model's reference beside it
    (:func:`stiffness_reference`; ``iso6336``: c_γα, whose c_γα b / cos² β_b is the mean on
    the theoretical path): None without a reference."""
    ref = summary.get("mesh_stiffness_reference")
    if not ref:
        return None
    k, on_path = ref["mesh_stiffness_mean_N_per_m"], ref["mesh_stiffness_on_path_mean_N_per_m"]
    text = f"K mean (unmodified, exact) {k / 1e6:.2f} N/µm"
    if ref["extended_contact"]:
        text += (
            f" with the tip corners' contact beyond the theoretical path, {on_path / 1e6:.2f} "
            "N/µm on the path"
        )
    cga = ref.get("c_gamma_alpha_N_per_m2")
    if cga is not None:
        text += (
            f"; ISO 6336-1 c_γα = {cga * 1e-9:.2f} N/(mm·µm), c_γα b/cos² β_b = "
            f"{ref['mesh_stiffness_on_path_iso_N_per_m'] / 1e6:.2f} N/µm: the mean on the path"
        )
    return text


def format_table(summary: dict, stiffness: AbstractStiffness, modified: bool = True) -> str:
    """A short plain-text table of the main figures of a pair's ``summary``, run with the mesh
    stiffness model ``stiffness`` (:func:`stiffness_line`). ``modified``: whether the case has
    modifications (:func:`has_modifications`; without, its rows once, "no modifications");
    where they raise the exact TE RMS above the unmodified flanks', a line says by how much."""
    g = summary["geometry"]
    lines = [
        (
            f"case {summary['case']}: ε_α = {g['transverse_contact_ratio']:.4f}, "
            f"ε_β = {g['overlap_ratio']:.4f}, a_w = {g['center_distance_m'] * 1e3:.4f} mm, "
            f"p_bt = {g['base_pitch_m'] * 1e3:.4f} mm, T = {summary['operating']['torque_Nm']:g} N·m"
        ),
        stiffness_line(stiffness),
        f"{'':24s}{'TE mean µm':>12s}{'TE rms µm':>12s}{'TE ptp µm':>12s}{'K mean N/µm':>13s}{'max N/mm':>10s}",
    ]
    rows = (("quasi_static_unmodified", "unmodified"), ("quasi_static", "modified"))
    if not modified:  # no modifications: the rows once
        rows = (("quasi_static", "no modifications"),)
    for key, lab in rows:
        for m in ("exact", "smooth"):
            q = summary[key][m]
            lines.append(
                f"{lab + ' ' + m:24s}{q['te_mean_m'] * 1e6:12.4f}{q['te_rms_m'] * 1e6:12.4f}"
                f"{q['te_ptp_m'] * 1e6:12.4f}{q['mesh_stiffness_mean_N_per_m'] / 1e6:13.2f}"
                f"{q['max_line_load_N_per_m'] / 1e3:10.1f}"
            )
    note = stiffness_note(summary)
    if note:
        lines.append(note)
    rms, rms_flanks = (summary[k]["exact"]["te_rms_m"]
                       for k in ("quasi_static", "quasi_static_unmodified"))
    worse = rms / rms_flanks if rms_flanks > 0 else 1.0  # 0: a constant TE, nothing to raise
    if modified and worse > 1.0:  # say it: a reader takes "modified" for "improved"
        lines.append(
            f"note: the case's modifications raise the TE RMS {worse:.2f}× over the unmodified "
            f"flanks at {summary['operating']['torque_Nm']:g} N·m (exact contact): they do "
            "not lower the TE (a design for another goal, or none: jaxgear optimise --objective "
            "te_rms --write writes the lower of its optimum, this design and the bare flanks)"
        )
    return "\n".join(lines)
