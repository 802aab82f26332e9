"""What the scenarios of zheng2014 Part IV share: the :class:`Scenario` base (the target's law
and the simulation of its trajectories), the schemes and feedbacks of a run, the validation of
the fields every scenario has, the text of their ``choices``, and the joint recursion of the
sensors' own Kalman filters (:func:`local_error_recursion`)."""

from __future__ import annotations

import abc

import numpy as np

from fusioncenter import particle
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import posint as _posint

#: Schemes of :func:`fusioncenter.censoring.run`: every sensor sends; each sends independently
#: with probability ``l / N`` (missing completely at random); NIS censoring with the silent
#: sensors dropped (CFoMD); NIS censoring with the full likelihood (CFwMD).
SCHEMES = ("all-send", "random", "cfomd", "cfwmd")
#: What the FC broadcasts at the start of each step: its predicted state (CFwMD, Propositions 1),
#: predicted state and covariance (CFwMD2, Proposition 2), or nothing (Proposition 3).
FEEDBACK = ("state", "state+cov", "none")
#: How ``scheme="cfwmd"`` fuses without feedback: Proposition 3 ``"corrected"`` or as
#: ``"printed"`` (both under the paper's law (21) for the local predictions), or ``"exact"``: the
#: particles also carry every sensor's local prediction, which makes the likelihood exact.
LIKELIHOODS = ("corrected", "printed", "exact")


def nested_tuple(arr: np.ndarray):
    """A float array (``ndim >= 1``) as nested tuples of floats (hashable dataclass fields).

    Parameters
    ----------
    arr : numpy.ndarray
        Floats, ``ndim >= 1``.

    Returns
    -------
    tuple
        Nested tuples of floats, one level per axis.
    """
    return tuple(nested_tuple(a) for a in arr) if arr.ndim > 1 else tuple(float(v) for v in arr)


def target_dynamics(F, Q, x0, P0) -> particle.LinearGaussianDynamics:
    """The target's law; an invalid ``P0`` is reported as such (``"P0: ..."``).

    Parameters
    ----------
    F, Q : array_like
        Transition and process-noise covariance (PSD).
    x0, P0 : array_like
        Mean and covariance (PSD, singular allowed) of ``x_0``.

    Returns
    -------
    fusioncenter.particle.LinearGaussianDynamics
        The law of the target.
    """
    try:
        return particle.LinearGaussianDynamics(F=F, Q=Q, m0=x0, P0=P0)
    except ValueError as err:
        raise ValueError(f"P0: {err}") from None


def check_motion(N, T, dt, sigma2) -> tuple[int, int, float, float]:
    """The fields every tracking scenario shares, validated.

    Parameters
    ----------
    N : int
        Number of sensors, a positive integer.
    T : int
        Number of measured time steps, a positive integer.
    dt : float
        Sampling interval, a positive number.
    sigma2 : float
        Process-noise intensity, ``>= 0`` (``0``: deterministic motion at constant velocity,
        ``Q = 0`` is a valid covariance).

    Returns
    -------
    tuple of (int, int, float, float)
        ``(N, T, dt, sigma2)`` as Python numbers.

    Raises
    ------
    ValueError
        Naming the field that is not of the stated kind.
    """
    N = _posint("N", N)
    T = _posint("T", T)
    dt_ = _finite("dt", dt)
    if dt_.ndim or dt_ <= 0:
        raise ValueError(f"dt must be a positive number, got {dt!r}")
    s2 = _finite("sigma2", sigma2)
    if s2.ndim or s2 < 0:
        raise ValueError(f"sigma2 must be a non-negative number (0: deterministic motion), "
                         f"got {sigma2!r}")
    return N, T, float(dt_), float(s2)


def check_x0_pair(value) -> np.ndarray:
    """The initial mean ``x0``: a finite ``[position, velocity]`` pair.

    Parameters
    ----------
    value : array_like
        The pair.

    Returns
    -------
    numpy.ndarray
        ``x0 (2,)``.
    """
    x0 = _finite("x0", value)
    if x0.shape != (2,):
        raise ValueError(f"x0 must be a [position, velocity] pair, got {value!r}")
    return x0


def check_feedback_moments(value) -> None:
    """Check ``feedback_moments`` (``"analytic"`` or ``"particles"``; ``ValueError`` otherwise).

    Parameters
    ----------
    value : str
        The field's value.

    Returns
    -------
    None
    """
    if value not in ("analytic", "particles"):
        raise ValueError(f"feedback_moments must be 'analytic' or 'particles', got {value!r}")


def values_text(value) -> str:
    """A number, a vector or a matrix as a reader sees it in a scenario's ``choices``.

    Numbers are written with ``:g`` and a true minus sign (``−8``), sequences in parentheses:
    ``(−8, 2, −8, 2)``, ``((1, 0), (0, 1))``.

    Parameters
    ----------
    value : float or sequence
        A number or a (nested) sequence of numbers.

    Returns
    -------
    str
        The text.
    """
    if isinstance(value, str):
        return value
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        return f"{float(arr) + 0.0:g}".replace("-", "−")
    return "(" + ", ".join(values_text(v) for v in arr) + ")"


def time_axis_choice(T: int) -> str:
    """The ``"time axis"`` entry of a scenario's ``choices``.

    Parameters
    ----------
    T : int
        Number of measured steps.

    Returns
    -------
    str
        The sentence.
    """
    return (f"x₀ at t = 0 is not measured; the sensors measure at t = 1, …, T (T = {T}); RMSE "
            "and transmissions are reported for t = 1, …, T")


#: The choices of
#: :attr:`~fusioncenter.censoring.scenarios.linear.LinearScenario.choices`
#: that every scenario shares (the schemes and the particle filter).
SCHEME_CHOICES = {
    "random selection": "each sensor sends independently with probability l/N",
    "all-send": "every sensor sends at every step (l is ignored)",
    "CFoMD": "same censoring as CFwMD (and the same feedback), silent sensors dropped",
    "resampling": "systematic, at every step (A1.6); the estimate is the weighted mean "
                  "before resampling (A1.5)",
}


def local_error_recursion(sc, update) -> None:
    """The covariance ``Sigma`` of the joint prediction errors ``(e^1, ..., e^N)`` of the
    sensors' own Kalman filters (eqs. (21)-(23)) of a linear scenario ``sc``, step by step.

    From ``Sigma_{0|0} = 1 1^T (x) P0``, for ``t = 0..T-1``: ``Sigma_{t+1|t} = (I (x) F)
    Sigma_{t|t} (I (x) F)^T + 1 1^T (x) Q``; ``update(t, Sigma_{t+1|t})`` records what it needs
    and returns ``(A, W)`` (``2N x 2N``, block diagonal: ``I - w^i h_i^T`` and the gain times the
    noise covariance times the gain transposed), and ``Sigma_{t+1|t+1} = A Sigma A^T + W``. Both
    covariances are symmetrized.

    Parameters
    ----------
    sc : LinearScenario or VectorScenario
        The scenario (``N``, ``T``, ``F``, ``Q``, ``dynamics.P0``).
    update : callable
        ``update(t, Sigma)`` -> ``(A, W)``, see above.

    Returns
    -------
    None
        What is needed is recorded by ``update``.
    """
    N = sc.N
    ones = np.ones((N, N))
    Sig = np.kron(ones, sc.dynamics.P0)
    IF = np.kron(np.eye(N), sc.F)
    for t in range(sc.T):
        Sig = IF @ Sig @ IF.T + np.kron(ones, sc.Q)
        Sig = 0.5 * (Sig + Sig.T)
        A, W = update(t, Sig)
        Sig = A @ Sig @ A.T + W
        Sig = 0.5 * (Sig + Sig.T)


def groups_of_rows(key: np.ndarray) -> list[np.ndarray]:
    """The indices of identical rows of ``key``, one array per group, in the order of each
    group's first row (the sensors' groups of :meth:`Scenario.sensor_groups`).

    Parameters
    ----------
    key : numpy.ndarray
        One row per sensor ``(N, k)``: what its observation model depends on.

    Returns
    -------
    list of numpy.ndarray
        Sensor indices per group.

    Raises
    ------
    ValueError
        If ``key`` is not a finite 2-D array with at least one row.
    """
    key = np.asarray(key, dtype=float)
    if key.ndim != 2 or key.shape[0] == 0 or not np.all(np.isfinite(key)):
        raise ValueError(f"key must be a finite 2-D array with at least one row, "
                         f"got shape {key.shape}")
    _, inv = np.unique(key, axis=0, return_inverse=True)
    inv = inv.ravel()
    order = sorted(range(inv.max() + 1), key=lambda g: int(np.flatnonzero(inv == g)[0]))
    return [np.flatnonzero(inv == g) for g in order]


class Scenario(abc.ABC):
    """What the scenarios (``censoring.scenarios.LinearScenario``,
    ``censoring.vector.VectorScenario``, ``censoring.nonlinear_model.NonlinearScenario``: frozen
    dataclasses keeping their :class:`fusioncenter.particle.LinearGaussianDynamics` in
    ``_cache["dynamics"]``) share: the target's law, and the simulation of the true
    trajectories.

    Attributes
    ----------
    position_index : tuple of int
        The state components that are positions (the RMSE's components).
    velocity_index : tuple of int
        The state components that are velocities.
    dynamics : fusioncenter.particle.LinearGaussianDynamics
        The target's law (read-only property).
    d : int
        Dimension of the state (read-only property).
    F : numpy.ndarray
        Transition matrix of ``dynamics`` (read-only property).
    Q : numpy.ndarray
        Process-noise covariance of ``dynamics`` (read-only property).
    """

    position_index = (0,)
    velocity_index = (1,)

    @property
    def dynamics(self) -> particle.LinearGaussianDynamics:
        """Initial law and transition (for the PF and for simulating the truth)."""
        return self._cache["dynamics"]

    @property
    def d(self) -> int:
        """Dimension of the state."""
        return self.dynamics.dim

    @property
    def F(self) -> np.ndarray:
        """Transition matrix ``(d, d)``."""
        return self.dynamics.F

    @property
    def Q(self) -> np.ndarray:
        """Process-noise covariance ``(d, d)``."""
        return self.dynamics.Q

    @abc.abstractmethod
    def sample(self, rng: np.random.Generator, n: int):
        """Truth and measurements of ``n`` trials: draws ``x_0``, then ``T`` transitions, then
        all measurement noises.

        Parameters
        ----------
        rng : numpy.random.Generator
            The stream of the draws.
        n : int
            Number of trials.

        Returns
        -------
        x : numpy.ndarray
            True states ``(n, T+1, d)`` (``x[:, 0] = x_0``).
        z : numpy.ndarray
            Measurements ``(n, T, N, ...)`` (``z[:, t-1]`` measured at time ``t``), one entry or
            vector per sensor.
        """

    @abc.abstractmethod
    def sensor_groups(self) -> list[np.ndarray]:
        """Indices of sensors with identical observation models (they share every likelihood
        term).

        Returns
        -------
        list of numpy.ndarray
            One array of sensor indices per group, in the order of their first sensor.
        """

    def _truth(self, rng: np.random.Generator, n: int, *, draw_x0: bool = True) -> np.ndarray:
        """True trajectories ``x (n, T+1, d)`` of ``n`` trials: draws ``x_0`` (else ``x_0`` is
        the prior mean), then ``T`` transitions."""
        dyn = self.dynamics
        x = np.empty((n, self.T + 1, self.d))
        if draw_x0:
            x[:, 0] = dyn.initial(rng, n, 1)[:, 0]
        else:
            x[:, 0] = dyn.m0
        for t in range(1, self.T + 1):
            x[:, t] = dyn.transition(rng, t, x[:, t - 1])
        return x
