"""JSON-ready scalar figures of a quasi-static result (shared by ``jaxgear run``'s sections)."""

from __future__ import annotations

import numpy as np

from .. import QuasiStaticResult

__all__ = ["result_summary"]


def result_summary(r: QuasiStaticResult) -> dict:
    """Scalar figures of a quasi-static result (SI units), JSON-ready."""
    k = np.asarray(r.mesh_stiffness)
    return {
        "te_mean_m": float(r.te_mean),
        "te_rms_m": float(r.te_rms),
        "te_ptp_m": float(r.te_ptp),
        "mesh_stiffness_mean_N_per_m": float(k.mean()),
        "mesh_stiffness_min_N_per_m": float(k.min()),
        "mesh_stiffness_max_N_per_m": float(k.max()),
        "contact_length_mean_m": float(np.mean(r.contact_length)),
        "max_line_load_N_per_m": float(r.max_line_load),
        "max_contact_iterations": int(np.max(r.iterations)),
    }
