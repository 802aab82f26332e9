"""The linear tracking model of zheng2014 Section VII.A, scalar observations
(:class:`LinearScenario`): its fields, its ``choices`` and its sensors' own Kalman filters."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from fusioncenter._validate import finite as _finite
from fusioncenter._validate import positive as _positive
from fusioncenter.censoring.scenarios.common import (
    SCHEME_CHOICES,
    Scenario,
    check_feedback_moments,
    check_motion,
    check_x0_pair,
    local_error_recursion,
    nested_tuple,
    target_dynamics,
    time_axis_choice,
    values_text,
)
from fusioncenter.models import wna_model


def _as_tuple(value):
    arr = np.asarray(value, dtype=float)
    return float(arr) if arr.ndim == 0 else tuple(np.asarray(arr).tolist())



@dataclass(frozen=True)
class LinearScenario(Scenario):
    """The linear tracking model of zheng2014 Section VII.A (scalar observations).

    ``x_k = [position, velocity]``, ``x_{k+1} = F x_k + u_k``, ``F = [[1, dt], [0, 1]]``,
    ``Q = sigma2 [[dt^4/4, dt^3/2], [dt^3/2, dt^2]]`` (white-noise acceleration; rank one);
    ``N`` sensors ``z_k^i = h_i^T x_k + n_k^i``, ``n^i ~ N(0, r_i)``, ``h = [1, 0]``.

    Paper values (the defaults): ``N = 2`` (Figs. 1, 3; ``N = 4`` for Fig. 2 and Table I),
    ``r = 1``, ``sigma2 = 4``, ``dt = 1``, ``x0 = [0, 10]``, ``T = 20`` steps, ``N_s = 1000``
    particles, 5000 trials. Every field can be overridden (``dataclasses.replace`` or keywords):

    * ``r``: one variance for every sensor or one per sensor; ``h``: one measurement vector for
      every sensor, or one row per sensor (shape ``(N, 2)``);
    * ``P0``: covariance of ``x_0`` (``None``: zero, ``x_0 = x0`` known);
    * ``feedback_moments``: how the FC forms what it feeds back, ``"analytic"`` (default:
      ``xhat_{k|k-1} = F xhat_{k-1|k-1}``, ``P_{k|k-1} = F P_{k-1|k-1} F^T + Q`` from the weighted
      particle mean and covariance at ``k-1``) or ``"particles"`` (mean and covariance of the
      propagated particle cloud; requires resampling at every step).

    The choices the paper leaves open are listed, with the value used, in :attr:`choices`.

    Parameters
    ----------
    N, r, sigma2, T, x0, dt, h, P0, feedback_moments
        The fields above (paper values by default; ``sigma2 = 0`` is deterministic motion).
    """

    N: int = 2
    r: float | tuple = 1.0
    sigma2: float = 4.0
    T: int = 20
    x0: tuple = (0.0, 10.0)
    dt: float = 1.0
    h: tuple = (1.0, 0.0)
    P0: tuple | None = None
    feedback_moments: str = "analytic"
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        N, _, dt, sigma2 = check_motion(self.N, self.T, self.dt, self.sigma2)
        r = _positive("r", self.r)
        if r.ndim > 1 or (r.ndim == 1 and r.shape != (N,)):
            raise ValueError(f"r must be a scalar or have one variance per sensor ({N},), "
                             f"got shape {r.shape}")
        x0 = check_x0_pair(self.x0)
        h = _finite("h", self.h)
        if h.shape not in ((2,), (N, 2)) or np.any(np.all(h.reshape(-1, 2) == 0, axis=-1)):
            raise ValueError(f"h must be a non-zero vector (2,) or one per sensor ({N}, 2), "
                             f"got {self.h!r}")
        check_feedback_moments(self.feedback_moments)
        P0 = np.zeros((2, 2)) if self.P0 is None else np.asarray(self.P0, dtype=float)
        F, q = wna_model(dt)
        dyn = target_dynamics(F, sigma2 * q, x0, P0)  # validates P0
        object.__setattr__(self, "N", N)
        object.__setattr__(self, "T", int(self.T))
        object.__setattr__(self, "r", _as_tuple(r))
        object.__setattr__(self, "h", _as_tuple(h) if h.ndim == 1 else nested_tuple(h))
        object.__setattr__(self, "x0", _as_tuple(x0))
        if self.P0 is not None:
            object.__setattr__(self, "P0", nested_tuple(P0))
        self._cache["dynamics"] = dyn

    # --- model pieces (dynamics, d, F, Q: see Scenario)
    @property
    def H(self) -> np.ndarray:
        """Measurement vectors, one row per sensor ``(N, 2)``."""
        return np.broadcast_to(np.asarray(self.h, dtype=float), (self.N, 2)).copy()

    @property
    def rvec(self) -> np.ndarray:
        """Measurement-noise variances ``(N,)``."""
        return np.broadcast_to(np.asarray(self.r, dtype=float), (self.N,)).copy()

    @property
    def choices(self) -> dict[str, str]:
        """Every choice the paper leaves open, with the value this scenario uses."""
        P0 = "0 (x₀ = x̄₀ known exactly)" if self.P0 is None else values_text(self.P0)
        return {
            "time axis": time_axis_choice(self.T),
            "initial state": f"x₀ ∼ N(x̄₀, P₀), x̄₀ = {values_text(self.x0)}, P₀ = {P0} "
                             "(the paper: the initial state 'is chosen to be [0 10]')",
            "PF prior": "particles at t = 0 drawn from N(x̄₀, P₀): all equal to x̄₀ when P₀ = 0",
            "local Kalman filters": "every sensor's KF starts from (x̄₀, P₀) and uses all of its "
                                    "own measurements (censoring only decides what is sent); "
                                    "its covariance recursion is data-independent, so the FC "
                                    "knows every sₖⁱ (Remark 1 (I))",
            "initial cross-covariance": "Pⁱʲ₀|₀ = P₀ (all sensors start from the same x̄₀; the "
                                        "paper's Pⁱʲ₀|₀ = 0 is this with P₀ = 0)",
            "feedback 'state'": "x̂ₖ|ₖ₋₁ broadcast at the start of step k; sensors use it in the "
                                "innovation but normalize by their own sₖⁱ = r + hᵀPⁱₖ|ₖ₋₁h "
                                "(Remark 1 (III))",
            "feedback 'state+cov'": "also P̂ₖ|ₖ₋₁; sensors and FC use s′ₖⁱ = r + hᵀP̂ₖ|ₖ₋₁h "
                                    "(Proposition 2, 'CFwMD2')",
            "feedback moments": (
                "analytic: x̂ₖ|ₖ₋₁ = F x̂ₖ₋₁|ₖ₋₁, P̂ₖ|ₖ₋₁ = F P̂ₖ₋₁|ₖ₋₁ Fᵀ + Q, from the weighted "
                "particle mean and covariance at k − 1 (before resampling); x̂₁|₀ = F x̄₀, "
                "P̂₁|₀ = F P₀ Fᵀ + Q"
                if self.feedback_moments == "analytic" else
                "particles: mean and covariance of the propagated particle cloud at step k"),
            "threshold": "η = the upper-(l/N) quantile of χ²₁, the same for every sensor and step "
                         "(eq. (8))",
            **SCHEME_CHOICES,
            "no-feedback likelihood": "'corrected' (default) or 'printed' Proposition 3, both with "
                                      "the paper's law (21)–(23) for the local predictions, or "
                                      "'exact' (particles carry the local predictions)",
        }

    def sample(self, rng: np.random.Generator, n: int):
        # x (n, T+1, 2), z (n, T, N): Scenario.sample
        x = self._truth(rng, n)
        noise = rng.standard_normal((n, self.T, self.N)) * np.sqrt(self.rvec)
        z = x[:, 1:] @ self.H.T + noise
        return x, z

    def local_filters(self) -> dict[str, np.ndarray]:
        """Data-independent quantities of the sensors' own Kalman filters, ``t = 1..T``.

        ``P_pred (T, N, 2, 2)``: ``P^i_{t|t-1}``; ``gain (T, N, 2)``: ``w_t^i``;
        ``s (T, N)``: ``s_t^i``; ``C (T, N, N)``: covariance of the local prediction errors in
        measurement space, ``h_i^T Sigma^{ij}_{t|t-1} h_j`` (eqs. (21)-(23); diagonal
        ``s_t^i - r_i``). Computed on the joint error vector ``(e^1, ..., e^N)``
        (:func:`~fusioncenter.censoring.scenarios.common.local_error_recursion`): ``Sigma_{t|t} =
        A Sigma_{t|t-1} A^T + blockdiag(w r w^T)`` with ``A = blockdiag(I - w^i h_i^T)``.

        Returns
        -------
        dict of str to numpy.ndarray
            ``P_pred``, ``gain``, ``s`` and ``C`` as above (computed once, then cached).
        """
        if "local" in self._cache:
            return self._cache["local"]
        N, T = self.N, self.T
        H, r = self.H, self.rvec
        P_pred = np.empty((T, N, 2, 2))
        gain = np.empty((T, N, 2))
        s = np.empty((T, N))
        Cm = np.empty((T, N, N))
        Hblk = np.zeros((N, 2 * N))
        for i in range(N):
            Hblk[i, 2 * i:2 * i + 2] = H[i]

        def update(t, Sig):
            A = np.zeros((2 * N, 2 * N))
            W = np.zeros((2 * N, 2 * N))
            for i in range(N):
                Pi = Sig[2 * i:2 * i + 2, 2 * i:2 * i + 2]
                P_pred[t, i] = Pi
                s[t, i] = H[i] @ Pi @ H[i] + r[i]
                w = Pi @ H[i] / s[t, i]
                gain[t, i] = w
                A[2 * i:2 * i + 2, 2 * i:2 * i + 2] = np.eye(2) - np.outer(w, H[i])
                W[2 * i:2 * i + 2, 2 * i:2 * i + 2] = r[i] * np.outer(w, w)
            Cm[t] = Hblk @ Sig @ Hblk.T
            return A, W

        local_error_recursion(self, update)
        out = {"P_pred": P_pred, "gain": gain, "s": s, "C": Cm}
        self._cache["local"] = out
        return out

    def sensor_groups(self) -> list[np.ndarray]:
        # the groups of identical (h_i, r_i): Scenario.sensor_groups
        key = np.concatenate([self.H, self.rvec[:, None]], axis=1)
        _, inv = np.unique(key, axis=0, return_inverse=True)
        return [np.flatnonzero(inv.ravel() == g) for g in range(inv.max() + 1)]
