"""A linear-Gaussian state-space model and its Kalman filter, vectorized across Monte Carlo trials.

Conventions (shared with :mod:`fusioncenter.riccati`): ``x_0 ~ N(m0, P0)``,
``x_{k+1} = A x_k + w_k``, ``y_k = C x_k + v_k`` for ``k = 0..steps``; the filter starts from the
prior ``(m0, P0)`` as its prediction for ``k = 0``. Arrays of trajectories are shaped
``(trials, steps + 1, dim)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter.riccati import measurement_update, singular, solve_psd

__all__ = ["LinearGaussianModel", "constant_velocity"]


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
        Naming the field that is not finite, has the wrong shape, or is not a covariance.
    """

    A: np.ndarray
    Q: np.ndarray
    C: np.ndarray
    R: np.ndarray
    m0: np.ndarray
    P0: np.ndarray

    def __post_init__(self) -> None:
        A = _matrix("A", self.A)
        n = A.shape[0]
        if A.shape != (n, n):
            raise ValueError(f"A must be square, got {A.shape}")
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

    def sample(self, rng: np.random.Generator, n: int, steps: int):
        """Draw ``n`` independent trajectories: ``(x, y)`` shaped ``(n, steps+1, nx|ny)``.

        Parameters
        ----------
        rng : numpy.random.Generator
            The source of randomness.
        n : int
            Number of trajectories, ``>= 1``.
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
        n = _v.posint("n", n)
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
            If ``y`` is not finite or has the wrong shape.
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
            S = self.C @ P @ self.C.T + self.R
            K = solve_psd(S, self.C @ P, singular=r_singular).T  # R = 0: the R -> 0 limit
            innov = y[:, k] - m @ self.C.T
            post_m = m + innov @ K.T
            post_P = measurement_update(P, self.C, self.R, check=k == 0)  # later P: computed
            xhat[:, k] = post_m
            Ps[k] = post_P
            m = post_m @ self.A.T
            P = self.A @ post_P @ self.A.T + self.Q
        return xhat, Ps


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
