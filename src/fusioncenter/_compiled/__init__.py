"""The library's compiled (numba) kernels, private: one module per thing computed.

Nothing here checks its inputs: the public modules that call a kernel validate first. Each
kernel has a NumPy/SciPy reference path or a test that holds it bitwise (or to a stated
tolerance) against the steps it replaces.

The censoring filters' kernels (three of them NumPy/SciPy rather than numba: the unchecked
cores the filters call in their inner loops, beside the checked public functions):

- :mod:`~fusioncenter._compiled.censoring_decisions`: the sensors' decisions with feedback and
  the linear fusion centre's per-group counts and received means (numba);
- :mod:`~fusioncenter._compiled.censored_normal`: one normal measurement as the fusion centre
  sees it, its log density and the probability of the silent interval (NumPy/SciPy, the
  unchecked side of :mod:`fusioncenter.censoring.probability`);
- :mod:`~fusioncenter._compiled.bivariate_normal`: the bivariate normal's distribution
  function, rectangles and the regions of Proposition 3 (NumPy/SciPy, likewise);
- :mod:`~fusioncenter._compiled.amplitude_ekf`: the nonlinear model's amplitudes, their
  gradient and the EKF covariance step (NumPy, the unchecked side of
  :mod:`fusioncenter.censoring.nonlinear_model`).
"""
