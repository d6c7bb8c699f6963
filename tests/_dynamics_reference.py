"""Continuous-time reference for the 1-DOF relative-approach model (NumPy/SciPy only).

The code lives in :mod:`benchmarks` (shared with ``jaxgear bench dynamics``, which uses it as
the fine reference of its accuracy columns); this module re-exports it for the tests.
"""

from benchmarks import ReferenceModel, reference_response

__all__ = ["ReferenceModel", "reference_response"]
