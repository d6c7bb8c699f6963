"""JSON-ready sections of ``jaxgear run``'s ``summary.json`` shared by a pair's and a train's run:
the scalar figures of a quasi-static result, the mesh settings, the environment."""

from __future__ import annotations

import platform

import jax
import numpy as np

from .. import QuasiStaticResult, __version__

__all__ = ["environment_summary", "mesh_settings_summary", "result_summary"]


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
