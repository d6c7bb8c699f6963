"""fem_prep: offline finite-element pre-processing of flexible gear bodies (NumPy/SciPy/skfem)."""
