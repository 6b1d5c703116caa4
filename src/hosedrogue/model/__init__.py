"""Numerical core of the hose model (numba kernels) and its Python wrapper."""
