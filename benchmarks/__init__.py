"""Benchmarks (``jaxgear bench …``) and the NumPy/SciPy baselines they compare against.

A folder of the source checkout, not part of the installed package: nothing in ``jaxgear``,
``fem_prep`` or ``optimise`` imports it except the ``jaxgear bench`` command, which finds it next
to the ``jaxgear`` package (editable install) or in the current folder. The benchmarks use
jaxgear's public API and read ``tests/data`` of the checkout. Timing lives here, never in tests.
"""

from ._backlash import (
    REGIMES as BACKLASH_REGIMES,
    STEPS as BACKLASH_STEPS,
    SWEEP as BACKLASH_SWEEP,
    SWEEP_STEPS as BACKLASH_SWEEP_STEPS,
    WINDOW as BACKLASH_WINDOW,
    jaxgear_model as backlash_model,
    reference as backlash_reference,
)
from ._backlash_reference import response as dead_zone_response, sweep as dead_zone_sweep
from ._baseline import (
    BaselineMesh as BaselineMesh,
    baseline_mesh as baseline_mesh,
    mods_params as mods_params,
    te_curve_numpy as te_curve_numpy,
    te_rms as te_rms,
)
from ._baseline_dynamics import (
    ReferenceModel as ReferenceModel,
    numba_available as numba_available,
    reference_response as reference_response,
)
from ._charts import thin_tick_labels as thin_tick_labels
from ._device import bench_device as bench_device
from ._dynamics import bench_dynamics as bench_dynamics, stability_map as stability_map
from ._hybrid import bench_hybrid as bench_hybrid, hybrid_chart as hybrid_chart
from ._hybrid_sweep import (
    bench_hybrid_sweep as bench_hybrid_sweep,
    hybrid_sweep_chart as hybrid_sweep_chart,
)
from ._modal_basis import (
    bench_modal_basis as bench_modal_basis,
    modal_basis_chart as modal_basis_chart,
)
from ._optimise import bench_optimise as bench_optimise
from ._processes import free_port as free_port, run_processes as run_processes
from ._quasi_static import bench_quasi_static as bench_quasi_static
from ._robust import bench_robust as bench_robust
from ._stiffness import bench_stiffness as bench_stiffness
from ._two_stage_reference import (
    DEFAULT_CARRIER_SPEEDS as TWO_STAGE_SPEEDS,
    TwoStageReference as TwoStageReference,
    harmonic_steady_state as two_stage_harmonic_state,
    reference_dynamic_factors as two_stage_dynamic_factors,
    spur_pair as reference_spur_pair,
    steady_state as two_stage_steady_state,
)
from ._train_cost import bench_trains as bench_trains, train_cost_chart as train_cost_chart
from ._xla_cache import (
    bench_xla_cache as bench_xla_cache,
    xla_cache_chart as xla_cache_chart,
)
