"""Benchmarks (``jaxgear bench …``) and the NumPy/SciPy baselines they compare against.

Not imported by the model; timing lives here, never in tests.
"""

from ._dynamics import bench_dynamics as bench_dynamics, stability_map as stability_map
from ._hybrid import bench_hybrid as bench_hybrid
from ._hybrid_sweep import bench_hybrid_sweep as bench_hybrid_sweep
from ._optimise import bench_optimise as bench_optimise
from ._quasi_static import bench_quasi_static as bench_quasi_static
from ._stiffness import bench_stiffness as bench_stiffness
