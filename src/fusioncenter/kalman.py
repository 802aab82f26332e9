"""A linear-Gaussian state-space model, and the one Kalman step, vectorized across trials.

The library's linear-Gaussian vocabulary (shared with :mod:`fusioncenter.riccati`,
:mod:`fusioncenter.particle`, :mod:`fusioncenter.models`, :mod:`fusioncenter.event` and
:mod:`fusioncenter.comparison`; the letters of mo2015, dey2009 and leong2011):
``x_0 ~ N(m0, P0)``, ``x_{k+1} = A x_k + w_k``, ``w ~ N(0, Q)``, ``y_k = C x_k + v_k``,
``v ~ N(0, R)``. zheng2014 writes ``F`` for ``A`` and ``H`` for ``C``: those names are kept as
read-only aliases where a public class uses them (``LinearGaussianModel.F`` / ``.H``,
``particle.LinearGaussianDynamics.F``, the censoring scenarios' ``F`` and ``H``).

The filter starts from the prior ``(m0, P0)`` as its prediction for ``k = 0``; arrays of
trajectories are shaped ``(trials, steps + 1, dim)``.

Every Kalman-filter loop of the library (:meth:`LinearGaussianModel.filter`,
:func:`fusioncenter.event.event_kf_run`, :func:`fusioncenter.comparison.kf_filter`) advances
with :func:`kalman_step`: a measurement update with the step's own ``C_k`` and ``R_k`` followed
by a time update. Event-triggered measurements, lost packets and censoring are expressed
through them: a sensor that is dropped is a zero row of ``C_k``, a silent sensor that is used
(mo2015's trigger) is the innovation ``0`` with a larger variance in ``R_k``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter._compiled import kalman_step as step_kernel
from fusioncenter.riccati import singular

__all__ = ["LinearGaussianModel", "KalmanStep", "kalman_step", "constant_velocity"]


def _matrix(name: str, value, shape: tuple[int, int] | None = None) -> np.ndarray:
    arr = np.atleast_2d(_v.finite(name, value))
    if arr.ndim != 2:
        raise ValueError(f"{name} must be a matrix, got shape {arr.shape}")
    if shape is not None and arr.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {arr.shape}")
    return arr


def _covariance(name: str, value, n: int) -> np.ndarray:
    return _v.covariance(name, _matrix(name, value, (n, n)))


@dataclass(frozen=True)
class LinearGaussianModel:
    """``x_{k+1} = A x_k + w_k``, ``y_k = C x_k + v_k``, ``x_0 ~ N(m0, P0)``.

    Parameters
    ----------
    A : array_like
        State transition ``(n, n)``, finite.
    Q : array_like
        Process-noise covariance ``(n, n)``, symmetric PSD (``0``: deterministic dynamics).
    C : array_like
        Measurement matrix ``(m, n)``, finite.
    R : array_like
        Measurement-noise covariance ``(m, m)``, symmetric PSD (``0``: noise-free sensors; the
        filter then uses the limit of the Kalman gain as ``R -> 0``).
    m0 : array_like
        Prior mean of ``x_0``, length ``n``.
    P0 : array_like
        Prior covariance of ``x_0`` ``(n, n)``, symmetric PSD.

    Raises
    ------
    ValueError
        Naming the field that is not finite, has the wrong shape (``A`` ``0x0``: no state), or
        is not a covariance.
    """

    A: np.ndarray
    Q: np.ndarray
    C: np.ndarray
    R: np.ndarray
    m0: np.ndarray
    P0: np.ndarray

    def __post_init__(self) -> None:
        A = _v.nonempty("A", _v.square("A", _matrix("A", self.A)))
        n = A.shape[0]
        C = _matrix("C", self.C)
        if C.shape[1] != n:
            raise ValueError(f"C must have {n} columns (the state dimension), got {C.shape}")
        m = C.shape[0]
        object.__setattr__(self, "A", A)
        object.__setattr__(self, "C", C)
        object.__setattr__(self, "Q", _covariance("Q", self.Q, n))
        object.__setattr__(self, "R", _covariance("R", self.R, m))
        m0 = _v.finite("m0", self.m0).reshape(-1)
        if m0.shape != (n,):
            raise ValueError(f"m0 must have length {n}, got {m0.shape}")
        object.__setattr__(self, "m0", m0)
        object.__setattr__(self, "P0", _covariance("P0", self.P0, n))

    @property
    def nx(self) -> int:
        return self.A.shape[0]

    @property
    def ny(self) -> int:
        return self.C.shape[0]

    @property
    def F(self) -> np.ndarray:
        """zheng2014's name for ``A`` (read-only alias)."""
        return self.A

    @property
    def H(self) -> np.ndarray:
        """zheng2014's name for ``C`` (read-only alias)."""
        return self.C

    def sample(self, rng: np.random.Generator, n: int, steps: int):
        """Draw ``n`` independent trajectories: ``(x, y)`` shaped ``(n, steps+1, nx|ny)``.

        Parameters
        ----------
        rng : numpy.random.Generator
            The source of randomness.
        n : int
            Number of trajectories, ``>= 0`` (``0``: empty arrays).
        steps : int
            Number of transitions, ``>= 0``.

        Returns
        -------
        x, y : numpy.ndarray
            States ``(n, steps + 1, nx)`` and measurements ``(n, steps + 1, ny)``.

        Raises
        ------
        ValueError
            If ``rng`` is not a Generator, or ``n`` or ``steps`` is not an integer in range.
        """
        if not isinstance(rng, np.random.Generator):
            raise ValueError(f"rng must be a numpy.random.Generator, got {rng!r}")
        n = _v.integer("n", n, 0)
        steps = _v.integer("steps", steps, 0)
        lq = _psd_factor(self.Q)
        lr = _psd_factor(self.R)
        l0 = _psd_factor(self.P0)
        x = np.empty((n, steps + 1, self.nx))
        x[:, 0] = self.m0 + rng.standard_normal((n, self.nx)) @ l0.T
        for k in range(steps):
            x[:, k + 1] = x[:, k] @ self.A.T + rng.standard_normal((n, self.nx)) @ lq.T
        y = x @ self.C.T + rng.standard_normal((n, steps + 1, self.ny)) @ lr.T
        return x, y

    def filter(self, y: np.ndarray):
        """Kalman filter of many trials at once.

        Returns ``(xhat, P)``: filtered means ``(n, steps+1, nx)`` and the filtered covariances
        ``P_{k|k}`` shaped ``(steps+1, nx, nx)`` (the same for every trial: the gains do not depend
        on the data).

        Parameters
        ----------
        y : array_like
            Measurements ``(trials, steps + 1, ny)``, finite.

        Returns
        -------
        xhat : numpy.ndarray
            Filtered means ``(trials, steps + 1, nx)``.
        P : numpy.ndarray
            Filtered covariances ``(steps + 1, nx, nx)``.

        Raises
        ------
        ValueError
            If ``y`` is not finite or has the wrong shape, or (``R`` singular) if a noise-free
            measurement contradicts what the filter knows exactly (no posterior exists).
        """
        y = _v.finite("y", y)
        if y.ndim != 3 or y.shape[2] != self.ny:
            raise ValueError(f"y must be shaped (trials, steps+1, {self.ny}), got {y.shape}")
        n, T1, _ = y.shape
        xhat = np.empty((n, T1, self.nx))
        Ps = np.empty((T1, self.nx, self.nx))
        m = np.broadcast_to(self.m0, (n, self.nx))
        P = self.P0
        r_singular = singular(self.R)
        for k in range(T1):
            innov = y[:, k] - m @ self.C.T
            try:
                xhat[:, k], Ps[k], m, P = step_kernel.kalman_step(
                    m, P, innov, self.C, self.R, self.A, self.Q, r_singular=r_singular,
                    check=k == 0)
            except ValueError as err:
                if not str(err).startswith("innov contradicts"):
                    raise
                raise ValueError(f"y at step {k} contradicts the model: a noise-free sensor "
                                 f"(R = 0) measures a direction the filter already knows "
                                 f"exactly, and y differs from its prediction "
                                 f"({str(err).split('prediction there by ')[1]}") from None
        return xhat, Ps


class KalmanStep(NamedTuple):
    """Result of :func:`kalman_step`: the filtered moments at step ``k`` and the predicted ones
    for step ``k + 1``.

    Attributes
    ----------
    x_post : numpy.ndarray
        ``E[x_k | y_0..y_k]``, shaped like the predicted means.
    P_post : numpy.ndarray
        ``P_{k|k}``, shaped like the predicted covariance(s).
    x_pred : numpy.ndarray
        ``E[x_{k+1} | y_0..y_k] = A x_post``.
    P_pred : numpy.ndarray
        ``P_{k+1|k} = A P_{k|k} A^T + Q``.
    """

    x_post: np.ndarray
    P_post: np.ndarray
    x_pred: np.ndarray
    P_pred: np.ndarray


def kalman_step(x, P, innov, C, R, A, Q, *, r_singular: bool | None = None,
                check: bool = True) -> KalmanStep:
    """One Kalman-filter step over many trials: measurement update, then time update.

    ``S = C P C^T + R``, ``x_post = x + P C^T S^{-1} innov``, ``P_post = P - P C^T S^{-1} C P``
    (:func:`fusioncenter.riccati.measurement_update`), ``x_pred = A x_post``,
    ``P_pred = A P_post A^T + Q``. The caller forms the innovation ``innov = y - C x`` (it often
    needs it first: an event trigger decides on it) and chooses ``C`` and ``R`` of the step: a
    sensor that sent nothing and is dropped is a zero row of ``C`` (and a zero innovation); a
    silent sensor that is used (mo2015) keeps its row with the innovation ``0`` and the noise
    variance ``r_i + delta_i``; a lost packet is dropped the same way.

    Two arithmetic forms, chosen by the shape of ``P``:

    * *shared* (``P``, ``C``, ``R`` single matrices; the gains do not depend on the data): the
      gain ``K = P C^T S^{-1}`` is computed once and applied to every trial's innovation,
      ``x_post = x + innov K^T``; ``P_pred`` is not symmetrized;
    * *per trial* (``P (n, nx, nx)``, ``C (n, m, nx)`` and ``R (n, m, m)`` broadcasting): each
      trial solves ``S^{-1} innov``; ``P_pred`` is symmetrized.

    Parameters
    ----------
    x : numpy.ndarray
        Predicted means ``x_{k|k-1}`` ``(n, nx)``.
    P : numpy.ndarray
        Predicted covariance ``P_{k|k-1}``: ``(nx, nx)`` shared by the trials, or ``(n, nx, nx)``.
    innov : numpy.ndarray
        Innovations ``(n, m)`` (zero in the rows that carry no measurement).
    C : numpy.ndarray
        The step's measurement matrix ``C_k``: ``(m, nx)``, or ``(n, m, nx)`` per trial.
    R : numpy.ndarray
        The step's noise covariance ``R_k``: ``(m, m)``, or ``(n, m, m)`` per trial.
    A : numpy.ndarray
        State transition ``(nx, nx)``.
    Q : numpy.ndarray
        Process-noise covariance ``(nx, nx)``.
    r_singular : bool, optional
        Whether ``R`` is singular (noise-free sensors: the gain is the limit ``R -> 0``, see
        :func:`fusioncenter.riccati.solve_psd`); computed with
        :func:`fusioncenter.riccati.singular` when omitted.
    check : bool
        Check that ``P``, ``R`` and ``Q`` are covariances (symmetric PSD; default). ``False``
        trusts them (covariances the caller computed itself, e.g. a filter's own after its first
        step); shapes and finiteness are checked either way.

    Returns
    -------
    KalmanStep
        ``(x_post, P_post, x_pred, P_pred)``.

    Raises
    ------
    ValueError
        If an argument is not finite or has the wrong shape (the message names it and the
        expected shape), or ``P`` is ``0x0`` (no state); with ``check=True`` also if ``P``,
        ``R`` or ``Q`` is not symmetric PSD; if
        ``R`` is singular and an innovation has a component along a direction with ``S = C P
        C^T + R`` zero (``P = 0`` and ``R = 0`` there: the measurement contradicts the model,
        no posterior exists; a zero innovation there is fine).
    """
    x, P, innov, C, R, A, Q = (_v.finite(k, v) for k, v in zip(
        ("x", "P", "innov", "C", "R", "A", "Q"), (x, P, innov, C, R, A, Q), strict=True))
    _step_shapes(x, P, innov, C, R, A, Q)
    if check:
        _v.covariance("Q", Q)
    return KalmanStep(*step_kernel.kalman_step(x, P, innov, C, R, A, Q,
                                               r_singular=r_singular, check=check))


def _step_shapes(x, P, innov, C, R, A, Q) -> None:
    """Shapes of :func:`kalman_step`'s arguments (cheap: no pass over the data)."""
    nx = np.shape(P)[-1] if np.ndim(P) >= 2 else None
    if nx is None or np.shape(P)[-2] != nx:
        raise ValueError(f"P must be (nx, nx) or (n, nx, nx), got shape {np.shape(P)}")
    _v.nonempty("P", P)
    _v.shape_is("A", A, (nx, nx), f"P is {nx}x{nx}")
    _v.shape_is("Q", Q, (nx, nx), f"P is {nx}x{nx}")
    _v.shape_is("C", C, (..., None, nx), f"P is {nx}x{nx}")
    m = np.shape(C)[-1 - 1]
    _v.shape_is("R", R, (..., m, m), f"C has {m} rows")
    _v.shape_is("x", x, (..., nx), f"P is {nx}x{nx}")
    _v.shape_is("innov", innov, (..., m), f"C has {m} rows")


def _psd_factor(M: np.ndarray) -> np.ndarray:
    """A square root ``L`` with ``L L^T = M`` for positive semi-definite ``M``."""
    w, V = np.linalg.eigh(M)
    return V * np.sqrt(np.clip(w, 0.0, None))


def constant_velocity(dt: float = 1.0, q: float = 1.0, r: float = 1.0,
                      m0=(0.0, 1.0), P0=None) -> LinearGaussianModel:
    """Position–velocity model with white-noise acceleration (intensity ``q``), position measured.

    ``Q = q [[dt^3/3, dt^2/2], [dt^2/2, dt]]``, ``C = [1, 0]``, ``R = r``.

    Parameters
    ----------
    dt : float
        Sampling period, ``> 0``.
    q : float
        Acceleration-noise intensity, ``>= 0``.
    r : float
        Position-measurement noise variance, ``>= 0`` (``0``: a noise-free sensor).
    m0 : array_like
        Prior mean ``[position, velocity]``.
    P0 : array_like, optional
        Prior covariance (default ``diag(10, 1)``).

    Returns
    -------
    LinearGaussianModel
        Two states (position, velocity), one sensor.

    Raises
    ------
    ValueError
        If ``dt`` is not positive, ``q`` or ``r`` negative, or any argument not finite.
    """
    dt = float(_v.positive("dt", dt, "a sampling period"))
    q = float(_v.nonneg("q", q, "a noise intensity"))
    r = float(_v.nonneg("r", r, "a noise variance"))
    A = np.array([[1.0, dt], [0.0, 1.0]])
    Q = q * np.array([[dt**3 / 3, dt**2 / 2], [dt**2 / 2, dt]])
    P0 = np.diag([10.0, 1.0]) if P0 is None else P0
    return LinearGaussianModel(A=A, Q=Q, C=np.array([[1.0, 0.0]]), R=np.array([[r]]),
                               m0=np.asarray(m0, dtype=float), P0=P0)
