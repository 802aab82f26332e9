"""The library's compiled (numba) kernels, private: one module per thing computed.

Nothing here checks its inputs: the public modules that call a kernel validate first. Each
kernel has a NumPy/SciPy reference path or a test that holds it bitwise (or to a stated
tolerance) against the steps it replaces.
"""
