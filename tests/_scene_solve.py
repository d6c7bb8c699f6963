"""Shared by the lumped 3D scene tests: the case's dynamic model and its quasi-static solve with
the load rotation grounded (16 positions per mesh period, 6 slices)."""

from __future__ import annotations

import jaxgear as jg
from jaxgear.dynamics import build_dynamic_model


def grounded_solve(case, spec=None):
    """(DynamicModel, QuasiStaticResult) of ``case`` with scene ``spec`` (default the case's)."""
    model, _ = build_dynamic_model(case, spec, slices=6)
    sc = model.scene
    r = jg.quasi_static(
        jg.grounded(sc, (sc.torque_dofs[1],)),
        case.modifications,
        case.torque,
        positions_per_pitch=16,
    )
    return model, r
