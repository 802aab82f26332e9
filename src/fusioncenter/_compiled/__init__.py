"""The library's compiled (numba) kernels, private: one module per thing computed.

Nothing here checks its inputs: the public modules that call a kernel validate first. Each
kernel has a NumPy/SciPy reference path or a test that holds it bitwise (or to a stated
tolerance) against the steps it replaces. The modules of the particle filters and of the
scalar, vector and nonlinear fusion centres (numba, but for the Kalman step):

* :mod:`~fusioncenter._compiled.weights` -- a particle-filter step's log weights shifted by
  their maximum, then the weight sum, weighted means and effective sample size;
* :mod:`~fusioncenter._compiled.resampling` -- systematic resampling: the ancestors, the
  gather, and the two fused;
* :mod:`~fusioncenter._compiled.transitions` -- the particles' transitions (white-noise
  acceleration, linear-Gaussian), with the process noise given or drawn inline: NumPy's
  standard normals (the SFC64 and PCG64 generators and the ziggurat), bit for bit;
* :mod:`~fusioncenter._compiled.ziggurat` -- NumPy's ziggurat tables, read from the installed
  NumPy and checked, the generators' state in and out, and ``standard_normal`` through them;
* :mod:`~fusioncenter._compiled.normal_cdf` -- SciPy's ``ndtr`` bit for bit, and the
  probability of an interval from it in one pass;
* :mod:`~fusioncenter._compiled.log_table` -- the scalar fusion centre's log-weight terms: the
  received sensors' Gaussian terms and the silent sensors' interpolation table;
* :mod:`~fusioncenter._compiled.ellipse_tables` -- the vector silent probability's bicubic
  tables at the particles;
* :mod:`~fusioncenter._compiled.vector_terms` -- the vector fusion centre's passes (the
  sensors' local Kalman step, the exact filter's received terms, the whitened Gaussian terms,
  rejection sampling in an ellipse);
* :mod:`~fusioncenter._compiled.amplitude_terms` -- the nonlinear model's sensor amplitudes
  and log-weight terms;
* :mod:`~fusioncenter._compiled.kalman_step` -- the Kalman step of the library's Kalman-filter
  loops without its shape checks (NumPy).

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
