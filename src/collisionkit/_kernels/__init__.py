"""Numba kernels, one module per domain.

These are plain functions on contiguous float64 arrays with no argument
checking: the public modules validate and normalise input, then call them.
"""
