"""Benchmark models shared by several chapters.

:func:`wna_model` is the one definition of the white-noise-acceleration tracking model (zheng2014
Section VII.A): :func:`tracking_model` here and the censoring scenarios
(:class:`fusioncenter.censoring.LinearScenario` and the vector and nonlinear ones) take their
``A`` (zheng2014's ``F``) and ``Q`` from it.

:func:`tracking_model` returns a :class:`fusioncenter.kalman.LinearGaussianModel` (fields
``A, Q, C, R, m0, P0``; ``m0`` is the prior mean of ``x_0``, the papers' ``x_0``), so it can be
sampled (``model.sample``), filtered with every sensor sending (``model.filter``) and run under
an event trigger (:func:`fusioncenter.event.event_kf_run`).
"""

from __future__ import annotations

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter.kalman import LinearGaussianModel

__all__ = ["wna_model", "tracking_model"]


def wna_model(dt: float) -> tuple[np.ndarray, np.ndarray]:
    """``(A, Q / sigma2)`` of the white-noise-acceleration model in one axis, step ``dt``.

    ``A = [[1, dt], [0, 1]]`` (zheng2014's ``F``), ``Q / sigma2 = [[dt^4/4, dt^3/2], [dt^3/2,
    dt^2]]`` (an acceleration ``sigma2``-variance, constant over a step; rank one).

    Parameters
    ----------
    dt : float
        Sampling period, ``> 0``.

    Returns
    -------
    A : numpy.ndarray
        ``(2, 2)`` state transition.
    Q1 : numpy.ndarray
        ``(2, 2)`` process-noise covariance per unit ``sigma2``.

    Raises
    ------
    ValueError
        If ``dt`` is not a positive finite number.
    """
    if (isinstance(dt, bool | str | bytes) or not np.isscalar(dt)
            or not np.isfinite(_v.finite("dt", dt)) or not dt > 0):
        raise ValueError(f"dt must be a positive finite number, got {dt!r}")
    return (np.array([[1.0, dt], [0.0, 1.0]]),
            np.array([[dt**4 / 4, dt**3 / 2], [dt**3 / 2, dt**2]]))


def tracking_model(n_sensors: int = 2, *, dt: float = 1.0, sigma2: float = 4.0, r: float = 1.0,
                   x0=(0.0, 10.0), P0=None) -> LinearGaussianModel:
    """One-dimensional target tracking of zheng2014, Section VII.A (scalar observations).

    State ``x_k = [position, velocity]``, white-noise acceleration:

    * ``A = F = [[1, dt], [0, 1]]``,
    * ``Q = sigma2 * [[dt^4/4, dt^3/2], [dt^3/2, dt^2]]``,
    * ``n_sensors`` identical sensors ``y_{i,k} = h^T x_k + v_{i,k}`` with ``h^T = [1, 0]``
      (position only): ``C`` is ``(n_sensors, 2)`` with rows ``[1, 0]``,
    * ``R = r * I`` (independent sensor noises, as the event trigger requires).

    What the paper states: ``dt = 1`` s, ``sigma^2 = 4``, ``h^T = [1, 0]``, ``r^i = 1`` (stated
    "for i = 1, 2"; we also use it for the N = 4 example of its Fig. 2), initial state
    ``[0, 10]``, ``N = 2`` (Figs. 1, 3) or ``N = 4`` (Fig. 2), 20 time steps, 5000 trials.

    What we chose: the paper does not say how uncertain the initial state is, nor how its
    particle filter is initialised. We read "the initial state of the target is chosen to be
    [0 10]" literally: ``x_0 = [0, 10]`` is known, ``P0 = 0`` (pass ``P0`` to change it; ``x0``
    is then the prior mean). We measure at every step ``k = 0..steps`` (the library's
    convention); the paper's 20 steps are ``steps = 19``.

    Parameters
    ----------
    n_sensors : int
        Number of sensors, ``>= 1`` (a NumPy integer is accepted, ``True`` is not).
    dt : float
        Sampling period, ``> 0``.
    sigma2 : float
        Acceleration-noise variance, ``>= 0`` (``0``: a deterministic constant velocity).
    r : float
        Each sensor's noise variance, ``>= 0`` (``0``: noise-free sensors).
    x0 : array_like
        Prior mean ``[position, velocity]`` of ``x_0``.
    P0 : array_like, optional
        Prior covariance of ``x_0`` (default ``0``: known).

    Returns
    -------
    LinearGaussianModel
        ``A`` and ``Q = sigma2 Q1`` from :func:`wna_model`, ``C`` ``(n_sensors, 2)``,
        ``R = r I``, ``m0 = x0``, ``P0``.

    Raises
    ------
    ValueError
        Naming the argument that is out of range, not finite, or of the wrong shape.
    """
    n_sensors = _v.posint("n_sensors", n_sensors)
    dt = float(_v.positive("dt", dt, "a sampling period"))
    sigma2 = float(_v.nonneg("sigma2", sigma2, "a variance"))
    r = float(_v.nonneg("r", r, "a noise variance"))
    A, Q1 = wna_model(dt)
    Q = sigma2 * Q1
    C = np.tile([1.0, 0.0], (int(n_sensors), 1))
    R = r * np.eye(int(n_sensors))
    x0 = _v.finite("x0", x0)
    if x0.shape != (2,):
        raise ValueError(f"x0 must be a finite [position, velocity] pair, got {x0!r}")
    P0 = np.zeros((2, 2)) if P0 is None else np.asarray(P0, dtype=float)
    return LinearGaussianModel(A=A, Q=Q, C=C, R=R, m0=x0, P0=P0)
