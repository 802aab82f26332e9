"""The vector-observation scenario of zheng2014 Section VII.B (:class:`VectorScenario`) and what
depends only on it: the sensors' own filters, who sends without feedback, and the constants of
the printed Proposition 6.

Proposition 6 (no feedback) has the erratum of the scalar Proposition 3 (see
``fusioncenter.censoring``): the received sensors' factor ``p(m^i = 1 | z^i, xhat^i, x) = 1`` is
dropped although ``xhat^i`` is integrated out, so (40) does not sum to one over the outcomes
(:func:`printed_mass`), and under the law (21) the silent factor does not depend on ``x``:
CFwMD as printed *is* CFoMD. ``run(..., feedback="none", likelihood="exact")`` runs the exact
no-feedback filter instead (particles carry every sensor's local prediction)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import special

from fusioncenter import _validate as _v
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import posint as _posint
from fusioncenter.censoring import probability as cprob
from fusioncenter.censoring.checks import check_eta, check_pd
from fusioncenter.censoring.ellipse import canonical_map, log_silent_probability, theta_rule
from fusioncenter.censoring.scenarios import common
from fusioncenter.models import wna_model


# ----------------------------------------------------------------------------- the scenario
@dataclass(frozen=True)
class VectorScenario(common.Scenario):
    """The tracking model of zheng2014 Section VII.B (vector observations).

    The target of Section VII.A (``x = [position, velocity]``, ``F = [[1, dt], [0, 1]]``,
    ``Q = sigma2 [[dt^4/4, dt^3/2], [dt^3/2, dt^2]]``) observed by ``N`` sensors
    ``z^i = H^i x + n^i``, ``n^i ~ N(0, R^i)`` of dimension ``m``.

    Paper values (the defaults): ``N = 2`` (Figs. 4 and 6; ``N = 4`` for Fig. 5 and Table II),
    ``H = I_2``, ``R = diag(2, 4)``, ``sigma2 = 4``, ``dt = 1``, ``x0 = [0, 10]``, ``T = 20``,
    1000 particles, 5000 trials. Every field can be overridden:

    * ``H``: ``(m, 2)`` for every sensor or ``(N, m, 2)`` per sensor (a vector ``(2,)`` is one
      row, ``m = 1``: the scalar model of Section VII.A); ``m`` in {1, 2};
    * ``R``: ``(m, m)`` for every sensor, ``(N, m, m)`` per sensor, or ``(m,)`` its diagonal;
    * ``P0``, ``feedback_moments``: as in :class:`fusioncenter.censoring.LinearScenario`.

    The choices the paper leaves open are listed, with the value used, in :attr:`choices`.

    Parameters
    ----------
    N, R, H, sigma2, T, x0, dt, P0, feedback_moments
        The fields above (paper values by default; ``sigma2 = 0`` is deterministic motion, ``P0``
        may be singular, ``R`` must be positive definite).
    """

    N: int = 2
    R: tuple = ((2.0, 0.0), (0.0, 4.0))
    H: tuple = ((1.0, 0.0), (0.0, 1.0))
    sigma2: float = 4.0
    T: int = 20
    x0: tuple = (0.0, 10.0)
    dt: float = 1.0
    P0: tuple | None = None
    feedback_moments: str = "analytic"
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        N, _, dt, sigma2 = common.check_motion(self.N, self.T, self.dt, self.sigma2)
        H = _finite("H", self.H)
        if H.ndim == 1:
            H = H[None, :]
        if H.ndim not in (2, 3) or H.shape[-1] != 2 or H.shape[-2] not in (1, 2) or \
                (H.ndim == 3 and H.shape[0] != N):
            raise ValueError(f"H must be (m, 2) or one per sensor ({N}, m, 2) with m in (1, 2), "
                             f"got shape {H.shape}")
        m = H.shape[-2]
        R = _finite("R", self.R)
        if R.ndim == 1:
            if R.shape != (m,):
                raise ValueError(f"R given as a diagonal must have length m = {m}, got {R.shape}")
            R = np.diag(R)
        if R.ndim == 0 and m == 1:
            R = R.reshape(1, 1)
        if R.ndim not in (2, 3) or R.shape[-2:] != (m, m) or (R.ndim == 3 and R.shape[0] != N):
            raise ValueError(f"R must be ({m}, {m}) or one per sensor ({N}, {m}, {m}), "
                             f"got shape {R.shape}")
        R = check_pd("R", R, m, why="a singular R makes the likelihood degenerate: the received "
                     "measurements would have no density")
        x0 = common.check_x0_pair(self.x0)
        common.check_feedback_moments(self.feedback_moments)
        P0 = np.zeros((2, 2)) if self.P0 is None else np.asarray(self.P0, dtype=float)
        F, q = wna_model(dt)
        dyn = common.target_dynamics(F, float(sigma2) * q, x0, P0)
        object.__setattr__(self, "N", N)
        object.__setattr__(self, "T", int(self.T))
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "sigma2", float(sigma2))
        object.__setattr__(self, "H", common.nested_tuple(H))
        object.__setattr__(self, "R", common.nested_tuple(R))
        object.__setattr__(self, "x0", common.nested_tuple(x0))
        if self.P0 is not None:
            object.__setattr__(self, "P0", common.nested_tuple(P0))
        self._cache["dynamics"] = dyn

    # --- model pieces (dynamics, d, F, Q: see common.Scenario)
    @property
    def m(self) -> int:
        """Dimension of every sensor's measurement."""
        return np.asarray(self.H).shape[-2]

    @property
    def Hs(self) -> np.ndarray:
        """Measurement matrices, one per sensor ``(N, m, 2)``."""
        H = np.asarray(self.H, dtype=float)
        return np.broadcast_to(H, (self.N, self.m, 2)).copy()

    @property
    def Rs(self) -> np.ndarray:
        """Measurement-noise covariances, one per sensor ``(N, m, m)``."""
        R = np.asarray(self.R, dtype=float)
        return np.broadcast_to(R, (self.N, self.m, self.m)).copy()

    @property
    def choices(self) -> dict[str, str]:
        """Every choice the paper leaves open, with the value this scenario uses."""
        P0 = "0 (x₀ = x̄₀ known exactly)" if self.P0 is None else common.values_text(self.P0)
        return {
            "time axis": common.time_axis_choice(self.T),
            "initial state": f"x₀ ∼ N(x̄₀, P₀), x̄₀ = {common.values_text(self.x0)}, P₀ = "
                             f"{P0}; the PF's particles start from the same law",
            "motion model": f"the target of Section VII.A: σ² = {self.sigma2:g} (Section "
                            "VII.B says 'the same one-dimensional moving target')",
            "sensors": f"H = {common.values_text(self.H)}, R = "
                       f"{common.values_text(self.R)} for every sensor unless given per sensor "
                       "(the paper states Rⁱ = diag(2, 4) for i = 1, 2 only; sensors 3, 4 "
                       "of Fig. 5 use the same)",
            "local Kalman filters": "every sensor's KF starts from (x̄₀, P₀) and uses all of its "
                                    "own measurements; its covariance recursion is "
                                    "data-independent, so the FC knows every Sₖⁱ",
            "initial cross-covariance": "Pⁱʲ₀|₀ = P₀ (the paper's 0 when P₀ = 0)",
            "feedback 'state'": "x̂ₖ|ₖ₋₁ broadcast at the start of step k; sensors use it in the "
                                "innovation and normalize by their own Sₖⁱ",
            "feedback 'state+cov'": "also P̂ₖ|ₖ₋₁; sensors and FC use S′ₖⁱ = Rⁱ + HⁱP̂ₖ|ₖ₋₁Hⁱᵀ "
                                    "(Proposition 5, 'CFwMD2')",
            "feedback moments": (
                "analytic: x̂ₖ|ₖ₋₁ = F x̂ₖ₋₁|ₖ₋₁, P̂ₖ|ₖ₋₁ = F P̂ₖ₋₁|ₖ₋₁ Fᵀ + Q from the weighted "
                "particle mean and covariance at k − 1 (before resampling)"
                if self.feedback_moments == "analytic" else
                "particles: mean and covariance of the propagated particle cloud at step k"),
            "threshold": f"η = the upper-(l/N) quantile of χ²ₘ with m = {self.m} (eq. (32))",
            "silent probability": "P(qᵀq < η) by quadrature (interpolated tables in the "
                                  "filter, error < 10⁻⁶ in the log); the paper sampled it",
            **common.SCHEME_CHOICES,
            "no-feedback likelihood": "'exact' (particles carry every local prediction; "
                                      "default) or 'printed' Proposition 6 (= CFoMD)",
        }

    def sample(self, rng: np.random.Generator, n: int):
        # x (n, T+1, 2), z (n, T, N, m): common.Scenario.sample
        x = self._truth(rng, n)
        noise = rng.standard_normal((n, self.T, self.N, self.m))
        L = np.linalg.cholesky(self.Rs)
        z = np.einsum("ntk,imk->ntim", x[:, 1:], self.Hs) + np.einsum("ntij,imj->ntim", noise, L)
        return x, z

    def local_filters(self) -> dict[str, np.ndarray]:
        """Data-independent quantities of the sensors' own Kalman filters, ``t = 1..T``.

        ``P_pred (T, N, 2, 2)``, ``gain (T, N, 2, m)``, ``S (T, N, m, m)``; ``Sigma (T, 2N, 2N)``:
        covariance of the joint local prediction errors ``(e^1, ..., e^N)`` (eqs. (21)-(23));
        ``A (T, N, m, 2)`` and ``a_scale (T, N, m)``: the canonical map of each sensor's silent
        region (``b = A (x - xhat)``, semi-axes ``sqrt(eta) * a_scale``, see
        :func:`canonical_map`).

        Returns
        -------
        dict of str to numpy.ndarray
            ``P_pred``, ``gain``, ``S``, ``Sigma``, ``A`` and ``a_scale`` as above (computed once,
            then cached).
        """
        if "local" in self._cache:
            return self._cache["local"]
        N, T, m = self.N, self.T, self.m
        H, R = self.Hs, self.Rs
        P_pred = np.empty((T, N, 2, 2))
        gain = np.empty((T, N, 2, m))
        S = np.empty((T, N, m, m))
        Sigma = np.empty((T, 2 * N, 2 * N))

        def update(t, Sig):  # the joint recursion: common.local_error_recursion
            Sigma[t] = Sig
            A = np.zeros((2 * N, 2 * N))
            Wn = np.zeros((2 * N, 2 * N))
            for i in range(N):
                blk = slice(2 * i, 2 * i + 2)
                Pi = Sig[blk, blk]
                P_pred[t, i] = Pi
                Si = H[i] @ Pi @ H[i].T + R[i]
                S[t, i] = 0.5 * (Si + Si.T)
                W = np.linalg.solve(S[t, i], H[i] @ Pi).T  # P H^T S^{-1}
                gain[t, i] = W
                A[blk, blk] = np.eye(2) - W @ H[i]
                Wn[blk, blk] = W @ R[i] @ W.T
            return A, Wn

        common.local_error_recursion(self, update)
        Acan, asc = canonical_map(S, np.broadcast_to(R, S.shape))
        out = {"P_pred": P_pred, "gain": gain, "S": S, "Sigma": Sigma,
               "A": Acan @ H, "a_scale": asc}
        self._cache["local"] = out
        return out

    def sensor_groups(self) -> list[np.ndarray]:
        # the groups of identical (H^i, R^i): common.Scenario.sensor_groups
        key = np.concatenate([self.Hs.reshape(self.N, -1), self.Rs.reshape(self.N, -1)], axis=1)
        return common.groups_of_rows(key)

_INV_SQRT_2PI = 1.0 / math.sqrt(2.0 * math.pi)



# ----------------------------------------------------------------------------- Proposition 6
def _ellipse_rule(a, K: int):
    """Nodes ``u (K^2, m)`` and weights of ``int_{sum u_j^2/a_j^2 < 1} g(u) phi(u) du``.

    ``m = 2``: ``u_1 = a_1 sin(theta)``, ``u_2 = a_2 cos(theta) sin(psi)``, Gauss-Legendre in
    both angles (the Jacobian ``a_1 a_2 cos^2(theta) cos(psi)`` removes the square roots at the
    boundary); ``m = 1``: ``u = a sin(theta)``. The standard normal density is in the weights.
    """
    s, c, w = theta_rule(K)
    if len(a) == 1:
        u = (a[0] * s)[:, None]
        wt = w * a[0] * c * np.exp(-0.5 * u[:, 0] ** 2) * _INV_SQRT_2PI
        return u, wt
    S1, S2 = np.meshgrid(s, s, indexing="ij")
    C1, C2 = np.meshgrid(c, c, indexing="ij")
    W = np.outer(w, w) * a[0] * a[1] * C1 * C1 * C2
    u = np.stack([a[0] * S1, a[1] * C1 * S2], axis=-1).reshape(-1, 2)
    wt = (W.ravel() * np.exp(-0.5 * (u * u).sum(axis=1)) / (2.0 * math.pi))
    return u, wt


def log_all_silent(cov, S, eta, *, K: int = 48) -> float:
    """``log P(V_j^T S_j^{-1} V_j < eta for every j)`` for jointly Gaussian ``V ~ N(0, cov)``.

    ``S``: ``(k, m, m)`` for ``k`` in {1, 2} sensors, ``cov``: ``(k m, k m)``. This is the
    constant of the printed Proposition 6 for the silent set (``V_j = H^j e^j + n^j``, with
    ``cov`` from (21)-(23)). ``k = 1``: exactly ``log P(chi2_m < eta)``-like quadrature;
    ``k = 2``: ``V_2 | V_1`` is Gaussian, so the probability is ``E[1{V_1 silent}
    P(V_2 silent | V_1)]``, a 2-D quadrature over the first ellipse (``K x K`` nodes) of the
    accurate conditional probability.

    Parameters
    ----------
    cov : array_like
        ``Cov(V) (k m, k m)``, positive definite.
    S : array_like
        ``(k, m, m)``, positive definite.
    eta : float
        Threshold, ``>= 0``.
    K : int, optional
        Quadrature nodes per axis (``k = 2``).

    Returns
    -------
    float
        The log probability.

    Raises
    ------
    ValueError
        Naming the argument that is not finite, of the wrong shape, not positive definite
        (``cov``, ``S``) or out of range (``eta``, ``K`` a positive integer).
    """
    eta = check_eta(eta)
    K = _posint("K", K)
    S = _finite("S", S)
    if S.ndim != 3 or S.shape[0] not in (1, 2) or S.shape[1] != S.shape[2]:
        raise ValueError(f"S must be (k, m, m) with k in (1, 2) silent sensors, got {S.shape}")
    k, m = S.shape[0], S.shape[1]
    S = check_pd("S", S, m)
    cov = check_pd("cov", cov, k * m)
    if k == 1:
        return float(log_silent_probability(np.zeros(m), S[0], cov, eta))
    C11, C12, C22 = cov[:m, :m], cov[:m, m:], cov[m:, m:]
    B = np.linalg.solve(C11, C12).T  # E[V2 | V1] = B V1
    Ccond = C22 - B @ C12
    A, asc = canonical_map(S[0], C11)  # u = A V1 ~ N(0, I), silent: sum u^2 / a^2 < 1
    u, wt = _ellipse_rule(math.sqrt(eta) * asc, K)
    V1 = np.linalg.solve(A, u.T).T
    inner = log_silent_probability(V1 @ B.T, S[1], Ccond, eta)
    return float(special.logsumexp(inner, b=wt))


def printed_mass(scenario: VectorScenario, l, t: int) -> float:
    """What the printed Proposition 6 sums to over all outcomes at step ``t`` (``N <= 2``).

    Integrating (40) over the received values (each ``p(z^i | x)`` integrates to one, since the
    send region depends on the unknown local prediction) and summing over the patterns ``m``
    gives ``sum_{silent sets A} P(every sensor of A silent)`` under (21)-(23): ``1 + P_1 + P_2 +
    P_12`` for ``N = 2``, ``P_j = 1 - l/N``; a likelihood would give 1.

    Parameters
    ----------
    scenario : VectorScenario
        With ``N <= 2``.
    l : float
        Target number of senders (sets ``eta``).
    t : int
        Step, ``1..T``.

    Returns
    -------
    float
        The total mass, ``> 1`` for the printed formula.
    """
    if not isinstance(scenario, VectorScenario):
        raise ValueError("scenario must be a VectorScenario")
    if scenario.N > 2:
        raise ValueError(f"printed_mass is implemented for N <= 2 sensors, got N = {scenario.N}")
    t = _posint("t", t)
    if t > scenario.T:
        raise ValueError(f"t must lie in 1..T = 1..{scenario.T}, got {t}")
    eta = cprob.threshold(l, scenario.N, dof=scenario.m)
    lf = scenario.local_filters()
    cov = silent_covariance(scenario, lf["Sigma"][t - 1])
    m, N = scenario.m, scenario.N
    total = 1.0
    for i in range(N):
        blk = slice(i * m, (i + 1) * m)
        total += math.exp(log_all_silent(cov[blk, blk], lf["S"][t - 1][i:i + 1], eta))
    if N == 2:
        total += math.exp(log_all_silent(cov, lf["S"][t - 1], eta))
    return total


def silent_covariance(sc: VectorScenario, Sigma: np.ndarray) -> np.ndarray:
    """``Cov(V) (N m, N m)`` of the sensors' own innovations ``V_j = H^j e^j + n^j`` under
    (21)-(23), from the joint local prediction-error covariance ``Sigma (2N, 2N)`` (one step of
    ``VectorScenario.local_filters()["Sigma"]``).

    Parameters
    ----------
    sc : VectorScenario
        The scenario.
    Sigma : numpy.ndarray
        ``(2N, 2N)`` joint prediction-error covariance at one step.

    Returns
    -------
    numpy.ndarray
        ``Cov(V) (N m, N m)``, symmetric.

    Raises
    ------
    ValueError
        If ``Sigma`` is not a ``(2N, 2N)`` covariance.
    """
    N, m = sc.N, sc.m
    Sigma = _v.covariance("Sigma", Sigma, n=2 * N)
    Hb = np.zeros((N * m, 2 * N))
    for i in range(N):
        Hb[i * m:(i + 1) * m, 2 * i:2 * i + 2] = sc.Hs[i]
    Rb = np.zeros((N * m, N * m))
    for i in range(N):
        Rb[i * m:(i + 1) * m, i * m:(i + 1) * m] = sc.Rs[i]
    C = Hb @ Sigma @ Hb.T + Rb
    return 0.5 * (C + C.T)


# ----------------------------------------------------------------------------- sensors
def local_decisions(sc: VectorScenario, eta: float, z: np.ndarray) -> np.ndarray:
    """Without feedback: every sensor runs its own Kalman filter on its measurements ``z (n, T,
    N, m)`` and sends when its NIS reaches ``eta``; returns ``sent (n, T, N)``.

    Parameters
    ----------
    sc : VectorScenario
        The scenario.
    eta : float
        Threshold.
    z : numpy.ndarray
        Measurements ``(n, T, N, m)``.

    Returns
    -------
    numpy.ndarray
        ``sent (n, T, N)``, bool.

    Raises
    ------
    ValueError
        If ``eta`` is not a finite non-negative number, or ``z`` is not finite of shape
        ``(n, T, N, m)``.
    """
    eta = check_eta(eta)
    z = _v.shape_is("z", _v.finite("z", z), (None, sc.T, sc.N, sc.m), "(n, T, N, m)")
    lf = sc.local_filters()
    F, H = sc.F, sc.Hs
    n, T, N, m = z.shape
    sent = np.empty((n, T, N), dtype=bool)
    xhat = np.broadcast_to(F @ sc.dynamics.m0, (n, N, 2)).copy()
    Sinv = np.linalg.inv(lf["S"])
    for t in range(T):
        nu = z[:, t] - np.einsum("nik,imk->nim", xhat, H)
        sent[:, t] = np.einsum("nim,imj,nij->ni", nu, Sinv[t], nu) >= eta
        xhat = (xhat + np.einsum("ikm,nim->nik", lf["gain"][t], nu)) @ F.T
    return sent


def whitening(R):
    """``(Linv, logdet)`` with ``R = L L^T``: ``|Linv d|^2 = d^T R^{-1} d``.

    Parameters
    ----------
    R : numpy.ndarray
        Positive-definite ``(..., m, m)``.

    Returns
    -------
    tuple
        ``Linv (..., m, m)`` and ``log det R`` (float).

    Raises
    ------
    ValueError
        If ``R`` is not a symmetric positive-definite matrix (or is ``0x0``).
    """
    R = _v.nonempty("R", _v.covariance("R", R, definite=True), "a 0x0 noise covariance")
    L = np.linalg.cholesky(R)
    return np.linalg.inv(L), 2.0 * float(np.log(np.diag(L)).sum())
