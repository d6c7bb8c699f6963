"""Condensation error vs number of retained modes, Craig-Bampton vs Herting (Fig. III-13's question).

Builds a small thin-webbed wheel, computes its first 20 frequencies with the bearings held
(full model), condenses it with 0..80 modes by both methods, and plots the largest relative
frequency error.  Also prints the nodal diameters / circles of the first modes and their
rotating-frame resonance orders (seed (3.2), (3.9)).

Run: ``python examples/fem_prep_modes_error.py [out.png]``
"""

import sys

import numpy as np

import fem_prep

BODY = """
name = "example-wheel"
[body]
bore_radius_mm = 10.0
hub_outer_radius_mm = 16.0
hub_width_mm = 16.0
web_thickness_mm = 2.0
rim_inner_radius_mm = 40.0
rim_outer_radius_mm = 45.0
rim_width_mm = 10.0
[[bearings]]
axial_position_mm = -8.0
[[bearings]]
axial_position_mm = 8.0
[mesh]
size_mm = 5.0
[condensation]
method = "craig-bampton"
modes = 50
teeth = 24
axial_master_nodes = 3
[centrifugal]
speed_rad_s = 1000.0
"""


def main(out: str = "fem_prep_modes_error.png") -> dict:
    body = fem_prep.parse_body(BODY)
    prep = fem_prep.prepare(body)
    modes = [0, 5, 10, 20, 30, 50, 80]
    curves = fem_prep.frequency_error_vs_modes(prep, modes)
    for method, errs in curves.items():
        print(method, " ".join(f"{m}:{e:.2e}" for m, e in zip(modes, errs)))
    for row in fem_prep.critical_speeds(body.condensation.teeth, prep.families[:10]):
        print(
            f"{row['frequency_hz']:9.1f} Hz  ND {row['nodal_diameters']}  NC {row['nodal_circles']}"
            f"  orders Z+n={row['backward_order']} Z-n={row['forward_order']}"
        )
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 3.5))
    for method, errs in curves.items():
        ax.semilogy(modes, np.maximum(errs, 1e-12), "o-", label=method)
    ax.set_xlabel("retained modes")
    ax.set_ylabel("max rel. error, first 20 frequencies")
    ax.set_title(f"{body.name}, {prep.mesh.n_dofs} DOFs, bearings held")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    return curves


if __name__ == "__main__":
    main(*sys.argv[1:])
