"""Censoring and fusion with missing data for a nonlinear tracker (zheng2014 Sections VI, VII.C).

A source moves in the plane with the white-noise-acceleration model, ``x = [x, xdot, y, ydot]``
(eq. (41) with a linear ``f``), and ``N = 9`` sensors on a 3 x 3 grid measure the amplitude of
its signal (Section VII.C)

    z_k^i = sqrt(P_0 / (1 + alpha d_k^i ** n)) + n_k^i,   n_k^i ~ N(0, r_i)      (42)

(``d_k^i`` the distance from the source to sensor ``i``). Each sensor runs an extended Kalman
filter (EKF) and sends ``z_k^i`` only if its normalized innovation squared is large,
``(z_k^i - h^i(xhat_{k|k-1}))^2 / s_k^i >= eta``, ``eta = chi2_1(l / N)`` (eq. (43)). The fusion
centre (FC) runs a particle filter and broadcasts after every step

* ``feedback="state"`` (Proposition 7, "CFwMD"): its estimate ``xhat_{k-1|k-1}``; every sensor
  predicts ``xhat_{k|k-1} = F xhat_{k-1|k-1}``, linearizes ``h^i`` there (``g_k^i``) and
  normalizes by its own EKF covariance, ``s_k^i = g_k^i P^i_{k|k-1} g_k^iT + r_i``;
* ``feedback="state+cov"`` (Proposition 8, "CFwMD2"): also ``Phat_{k-1|k-1}``; the sensors use
  ``s'^i_k = g_k^i (F Phat_{k-1|k-1} F^T + Q) g_k^iT + r_i``;
* ``feedback="none"``: nothing; each sensor runs a complete EKF on its own measurements. The
  paper gives no full likelihood for this case (Remark 4 (III)), so only all-send, random
  selection and CFoMD accept it.

Given the broadcast the FC knows every ``s_k^i`` (it replays the sensors' EKF covariance
recursions, Remark 3 (I)), and the likelihood of Propositions 7-8 is *exact*: a silent sensor
contributes ``P(|h^i(x_k) + n - h^i(xhat_{k|k-1})| < sqrt(eta s_k^i))``, a Gaussian interval
probability in the particle's own amplitude. The Gaussian approximation of the innovation
enters only the threshold design, i.e. how many sensors send on average (Table III).

For ``10^4`` particles the silent factors dominate the cost. Within one trial and sensor they are
a smooth function of one variable (log-concave, curvature in ``[-1, 0]``), so the FC tabulates
them with exact values and slopes and interpolates (cubic Hermite, error below ``1e-9`` in the
log weights, :func:`silent_terms`); for CFoMD and random selection it computes the amplitudes of the
received sensors only.

Entry points (signature, one line each):

* ``NonlinearScenario(...)``: the model of Section VII.C; ``.choices`` states every open choice.
* ``amplitude(scenario, pos) -> (..., N)``, ``jacobian(scenario, x) -> (..., N, 4)``: ``h`` and
  its gradient ``g`` (zero in the velocity components).
* ``ekf_covariance_step(P, g, F, Q, r) -> (P_pred, s, P_upd)``: one EKF covariance recursion,
  vectorized over any leading axes (trials, sensors).
* ``local_ekf(scenario, z) -> dict``: every sensor's own EKF on its own data (no feedback).
* ``log_silent_probability(m, h)``: ``log P(|Z + m| < h)``, ``Z ~ N(0, 1)``, for the particles.
* ``log_likelihood(sent, z, hx, hx_pred, s, r, eta, scheme="cfwmd")``: Propositions 7-8 (or
  the received sensors only, CFoMD) for given amplitudes.
* ``run(scenario, scheme, *, l, n_trials, n_particles, seed, feedback="state", ...)
  -> censoring.CensoringResult``: the four schemes, through ``montecarlo.simulate``; the same
  signature and result type as :func:`fusioncenter.censoring.run`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from fusioncenter import _kernels, montecarlo, particle
from fusioncenter._validate import one_of as _one_of
from fusioncenter._validate import posint as _posint
from fusioncenter.censoring import fusion, results, scenarios
from fusioncenter.censoring import probability as cprob

#: The schemes of :func:`run` (as in :mod:`fusioncenter.censoring`).
SCHEMES = scenarios.SCHEMES
#: What the FC broadcasts: its estimate (Proposition 7), estimate and covariance (Proposition 8,
#: CFwMD2), or nothing (no likelihood for CFwMD: Remark 4 (III)).
FEEDBACK = ("state", "state+cov", "none")


# ----------------------------------------------------------------------------- validation
def _posfloat(name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise ValueError(f"{name} must be a positive number, got {value!r}")
    v = float(value)
    if not math.isfinite(v) or v <= 0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return v


def grid_positions(per_side: int = 3, side: float = 20.0, *, layout: str = "centres"):
    """Sensor positions ``(per_side**2, 2)`` (m) on a square grid in ``[-side/2, side/2]^2``.

    ``layout="centres"``: the centres of the ``per_side x per_side`` cells (for 3 x 3 in 20 m:
    ``-20/3, 0, 20/3``); ``"edges"``: equally spaced including the border (``-10, 0, 10``).
    Ordered row by row from the bottom left (``x`` fastest).
    """
    per_side = _posint("per_side", per_side)
    side = _posfloat("side", side)
    if layout == "centres":
        c = (np.arange(per_side) + 0.5) * side / per_side - side / 2
    elif layout == "edges":
        c = np.linspace(-side / 2, side / 2, per_side) if per_side > 1 else np.zeros(1)
    else:
        raise ValueError(f"layout must be 'centres' or 'edges', got {layout!r}")
    gx, gy = np.meshgrid(c, c)
    return np.stack([gx.ravel(), gy.ravel()], axis=-1)


# ----------------------------------------------------------------------------- the scenario
@dataclass(frozen=True)
class NonlinearScenario(scenarios.Scenario):
    """The nonlinear tracking model of zheng2014 Section VII.C.

    State ``x = [x, xdot, y, ydot]`` (m, m/s); ``x_{k+1} = F x_k + u_k``, ``F`` and
    ``Q = sigma2 blockdiag(q, q)``, ``q = [[dt^4/4, dt^3/2], [dt^3/2, dt^2]]`` (white-noise
    acceleration in each axis); sensor ``i`` at ``sensors[i]`` measures
    ``sqrt(power / (1 + alpha d^exponent)) + n``, ``n ~ N(0, r_i)``.

    Paper values (the defaults): ``N = 9`` sensors in a 20 m x 20 m region, ``power`` (the
    paper's ``P_0``) ``= 1e3``, ``alpha = 1``, ``exponent`` (the paper's ``n``) ``= 2``,
    ``r = 1``, ``sigma2 = 0.1``, ``dt = 0.5`` s, ``T = 20`` steps (10 s), prior
    ``x_0 ~ N(x0, P0)`` with ``x0 = [-8, 2, -8, 2]``, ``P0 = diag(9, 4, 9, 4)`` ("a poor prior
    on the initial state"); 200 trials, ``N_s = 10^4`` particles. The paper does not give the
    sensor positions: ``sensors=None`` puts them at the centres of the 3 x 3 cells of
    ``[-10, 10]^2`` (:func:`grid_positions`). Nor does it say whether the true ``x_0`` is drawn
    from the prior in every trial: ``initial_truth="mean"`` (default) starts every true
    trajectory at ``x0`` (the filters still start from the prior ``N(x0, P0)``), ``"random"``
    draws it from ``N(x0, P0)``. Every field can be overridden; the open choices are listed in
    :attr:`choices`.

    Fields: ``sensors`` ``(N, 2)`` or ``None``; ``region`` (side of the square, m, centred at
    the origin); ``r`` (one variance or one per sensor); ``P0`` as a diagonal ``(4,)`` or a full
    ``(4, 4)`` covariance.
    """

    sensors: tuple | None = None
    region: float = 20.0
    power: float = 1e3
    alpha: float = 1.0
    exponent: float = 2.0
    r: float | tuple = 1.0
    sigma2: float = 0.1
    dt: float = 0.5
    T: int = 20
    x0: tuple = (-8.0, 2.0, -8.0, 2.0)
    P0: tuple = (9.0, 4.0, 9.0, 4.0)
    initial_truth: str = "mean"
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        region = _posfloat("region", self.region)
        sensors = grid_positions(3, region) if self.sensors is None else \
            np.asarray(self.sensors, dtype=float)
        if sensors.ndim != 2 or sensors.shape[1] != 2 or sensors.shape[0] < 1 \
                or not np.all(np.isfinite(sensors)):
            raise ValueError(f"sensors must be finite (x, y) positions, shape (N, 2), got "
                             f"{self.sensors!r}")
        N = sensors.shape[0]
        for name in ("power", "alpha", "exponent", "sigma2", "dt"):
            object.__setattr__(self, name, _posfloat(name, getattr(self, name)))
        T = _posint("T", self.T)
        if self.initial_truth not in ("mean", "random"):
            raise ValueError(f"initial_truth must be 'mean' or 'random', got "
                             f"{self.initial_truth!r}")
        r = np.asarray(self.r, dtype=float)
        if r.ndim > 1 or (r.ndim == 1 and r.shape != (N,)) or not np.all(np.isfinite(r)) \
                or np.any(r <= 0):
            raise ValueError(f"r must be a positive variance or one per sensor ({N},), "
                             f"got {self.r!r}")
        x0 = np.asarray(self.x0, dtype=float)
        if x0.shape != (4,) or not np.all(np.isfinite(x0)):
            raise ValueError(f"x0 must be a finite [x, xdot, y, ydot] vector, got {self.x0!r}")
        P0 = np.asarray(self.P0, dtype=float)
        if P0.shape == (4,):
            if np.any(P0 < 0) or not np.all(np.isfinite(P0)):
                raise ValueError(f"P0 (diagonal) must be finite and non-negative, got {self.P0!r}")
            P0m = np.diag(P0)
        elif P0.shape == (4, 4):
            P0m = P0
        else:
            raise ValueError(f"P0 must be a diagonal (4,) or a (4, 4) covariance, got {self.P0!r}")
        F1, q = scenarios.wna_model(self.dt)
        dyn = scenarios.target_dynamics(np.kron(np.eye(2), F1), self.sigma2 * np.kron(np.eye(2), q),
                                  x0, P0m)
        object.__setattr__(self, "sensors", scenarios.nested_tuple(sensors))
        object.__setattr__(self, "region", region)
        object.__setattr__(self, "T", T)
        object.__setattr__(self, "r", float(r) if r.ndim == 0 else tuple(r.tolist()))
        object.__setattr__(self, "x0", tuple(x0.tolist()))
        object.__setattr__(self, "P0",
                           tuple(P0.tolist()) if P0.ndim == 1 else scenarios.nested_tuple(P0))
        self._cache["dynamics"] = dyn
        self._cache["pos"] = sensors
        self._cache["N"] = N

    # --- model pieces (the attributes CensoringResult and the FC use; dynamics, d, F, Q: see
    # scenarios.Scenario)
    @property
    def N(self) -> int:
        return self._cache["N"]

    @property
    def positions(self) -> np.ndarray:
        """Sensor positions ``(N, 2)`` (m)."""
        return self._cache["pos"].copy()

    @property
    def rvec(self) -> np.ndarray:
        return np.broadcast_to(np.asarray(self.r, dtype=float), (self.N,)).copy()

    position_index = (0, 2)
    velocity_index = (1, 3)

    @property
    def choices(self) -> dict[str, str]:
        """Every choice the paper leaves open, with the value this scenario uses."""
        grid = grid_positions(3, self.region)
        default = self.positions.shape == grid.shape and np.allclose(self.positions, grid)
        return {
            "region": f"the square [-{self.region / 2:g}, {self.region / 2:g}]^2 m, centred at "
                      "the origin (the paper: a 20 m x 20 m area; the centring is implied by "
                      "x0 = (-8, -8) and by the target leaving the region near the end)",
            "sensor positions": ("centres of the 3 x 3 cells of the region, x, y in {-20/3, 0, "
                                 "20/3} m (the paper: 'grid deployed', positions not given)"
                                 if default else f"given: {self.sensors}"),
            "measurement": "the amplitude sqrt(P0 / (1 + alpha d^n)) plus N(0, r) noise (the "
                           "paper calls it the received 'signal power'; its formula is the "
                           "amplitude)",
            "time axis": f"x_0 at t = 0 is not measured; the sensors measure at steps k = 1..T "
                         f"(T = {self.T}, t = k dt); RMSE and transmissions reported for k = "
                         "1..T",
            "initial state": ("the true x_0 = x0 in every trial (the target always starts at "
                              f"{self.x0}); only the filters' prior is N(x0, P0), P0 = {self.P0}"
                              if self.initial_truth == "mean" else
                              f"the true x_0 ~ N(x0, P0) drawn for every trial, x0 = {self.x0}, "
                              f"P0 = {self.P0}"),
            "PF prior": "particles at t = 0 drawn from N(x0, P0)",
            "local EKFs": "every sensor's EKF starts from (x0, P0); its covariance recursion "
                          "uses its own measurement at every step (censoring only decides what "
                          "is sent); with feedback it linearizes h^i at the broadcast prediction "
                          "F xhat_{k-1|k-1} (Remark 3 (I)), so the FC can replay it",
            "feedback 'state'": "xhat_{k-1|k-1} (weighted particle mean before resampling) is "
                                "broadcast after step k-1; sensors use xhat_{k|k-1} = F "
                                "xhat_{k-1|k-1} in the innovation and normalize by their own "
                                "EKF s_k^i = g P^i_{k|k-1} g^T + r (Proposition 7); xhat_{0|0} "
                                "= x0",
            "feedback 'state+cov'": "also Phat_{k-1|k-1} (weighted particle covariance); "
                                    "s'^i_k = g (F Phat_{k-1|k-1} F^T + Q) g^T + r for sensors "
                                    "and FC (Proposition 8, 'CFwMD2'); Phat_{0|0} = P0",
            "feedback 'none'": "each sensor runs a full EKF on its own data; accepted for "
                               "all-send, random and CFoMD only (no full likelihood: Remark 4 "
                               "(III))",
            "Jacobian": "g_k^i = dh^i/dx at the (broadcast or local) prediction xhat_{k|k-1}",
            "threshold": "eta = chi2_1 upper-(l/N) quantile, the same for every sensor and step "
                         "(eq. (43))",
            **scenarios.SCHEME_CHOICES,
        }

    # --- simulation
    def sample(self, rng: np.random.Generator, n: int):
        """Truth and measurements of ``n`` trials: ``x (n, T+1, 4)`` (``x[:, 0] = x_0``), ``z (n,
        T, N)`` (``z[:, k-1]`` measured at step ``k``). Draws ``x_0`` (if ``initial_truth`` is
        ``"random"``), then ``T`` transitions, then all measurement noises."""
        x = self._truth(rng, n, draw_x0=self.initial_truth == "random")
        noise = rng.standard_normal((n, self.T, self.N)) * np.sqrt(self.rvec)
        z = amplitude(self, x[:, 1:, [0, 2]]) + noise
        return x, z


# ----------------------------------------------------------------------------- measurement model
def _amp_from_d2(sc: NonlinearScenario, d2):
    """``sqrt(power / (1 + alpha d^n))`` from the squared distance (in place on ``d2``)."""
    if sc.exponent != 2.0:
        np.power(d2, sc.exponent / 2, out=d2)
    if sc.alpha != 1.0:
        d2 *= sc.alpha
    d2 += 1.0
    np.divide(sc.power, d2, out=d2)
    return np.sqrt(d2, out=d2)


def amplitude(scenario: NonlinearScenario, pos) -> np.ndarray:
    """``h^i`` at positions ``pos (..., 2)`` (m) for every sensor: ``(..., N)``."""
    pos = np.asarray(pos, dtype=float)
    if pos.shape[-1:] != (2,):
        raise ValueError(f"pos must end in an (x, y) axis of length 2, got {pos.shape}")
    diff = pos[..., None, :] - scenario.positions  # (..., N, 2)
    d2 = np.einsum("...k,...k->...", diff, diff)
    return _amp_from_d2(scenario, d2)


def jacobian(scenario: NonlinearScenario, x) -> np.ndarray:
    """``g^i = dh^i/dx`` at states ``x (..., 4)``: ``(..., N, 4)``, zero in the velocities.

    ``h = sqrt(P0) (1 + alpha d^n)^(-1/2)`` gives ``dh/dp = -(alpha n / 2) d^(n-2) (p - p_i)
    h^3 / P0`` (for ``n = 2``: ``-alpha (p - p_i) h^3 / P0``). At ``d = 0`` with ``n < 2`` the
    gradient is taken as 0 (a measure-zero event).
    """
    x = np.asarray(x, dtype=float)
    if x.shape[-1:] != (4,):
        raise ValueError(f"x must end in a state axis of length 4, got {x.shape}")
    sc = scenario
    diff = x[..., None, [0, 2]] - sc.positions  # (..., N, 2)
    d2 = np.einsum("...k,...k->...", diff, diff)
    h = _amp_from_d2(sc, d2.copy())
    coef = -0.5 * sc.alpha * sc.exponent * h**3 / sc.power
    if sc.exponent != 2.0:
        with np.errstate(divide="ignore", invalid="ignore"):
            dn = np.where(d2 > 0, d2 ** (sc.exponent / 2 - 1), 0.0)
        coef = coef * dn
    g = np.zeros((*diff.shape[:-1], 4))
    g[..., 0] = coef * diff[..., 0]
    g[..., 2] = coef * diff[..., 1]
    return g


def ekf_covariance_step(P, g, F, Q, r):
    """One EKF covariance recursion, vectorized over leading axes.

    ``P (..., d, d)``: ``P_{k-1|k-1}``; ``g (..., d)``: the measurement gradient at the
    prediction; ``r`` broadcast to ``(...)``. Returns ``P_pred = F P F^T + Q``,
    ``s = g P_pred g^T + r`` and, in Joseph form (as filterpy), ``P_upd = (I - w g) P_pred
    (I - w g)^T + r w w^T`` with the gain ``w = P_pred g^T / s`` (symmetrized).
    """
    Pp = F @ P @ F.T + Q
    Pg = (Pp @ g[..., None])[..., 0]  # (..., d)
    s = np.einsum("...k,...k->...", g, Pg) + r
    w = Pg / s[..., None]
    A = np.eye(P.shape[-1]) - w[..., :, None] * g[..., None, :]
    Pu = A @ Pp @ np.swapaxes(A, -1, -2) + np.asarray(r)[..., None, None] * (
        w[..., :, None] * w[..., None, :])
    Pu = 0.5 * (Pu + np.swapaxes(Pu, -1, -2))
    return Pp, s, Pu


def local_ekf(scenario: NonlinearScenario, z) -> dict[str, np.ndarray]:
    """Every sensor's own EKF on its own measurements (no feedback), vectorized over trials and
    sensors: ``z (n, T, N)`` -> ``x_pred (n, T, N, 4)`` (``xhat^i_{k|k-1}``), ``P_pred (n, T, N,
    4, 4)``, ``s (n, T, N)``, ``nu (n, T, N)`` (innovations ``z - h^i(xhat^i_{k|k-1})``),
    ``x_upd`` and ``P_upd`` (``xhat^i_{k|k}``, ``P^i_{k|k}``). Every filter starts from
    ``(x0, P0)`` and linearizes ``h^i`` at its own prediction."""
    sc = scenario
    z = np.asarray(z, dtype=float)
    if z.ndim != 3 or z.shape[1:] != (sc.T, sc.N):
        raise ValueError(f"z must have shape (n, T, N) = (n, {sc.T}, {sc.N}), got {z.shape}")
    n, T, N = z.shape
    F, Q, r = sc.F, sc.Q, sc.rvec
    idx = np.arange(N)
    xh = np.broadcast_to(sc.dynamics.m0, (n, N, 4)).copy()
    P = np.broadcast_to(sc.dynamics.P0, (n, N, 4, 4)).copy()
    out = {k: np.empty((n, T, N, 4)) for k in ("x_pred", "x_upd")}
    out.update({k: np.empty((n, T, N, 4, 4)) for k in ("P_pred", "P_upd")})
    out.update({k: np.empty((n, T, N)) for k in ("s", "nu")})
    for t in range(T):
        xp = xh @ F.T
        g = jacobian(sc, xp)[:, idx, idx]  # sensor i's gradient at its own prediction
        Pp, s, P = ekf_covariance_step(P, g, F, Q, r)
        nu = z[:, t] - amplitude(sc, xp[..., [0, 2]])[:, idx, idx]
        xh = xp + (Pp @ g[..., None])[..., 0] * (nu / s)[..., None]
        out["x_pred"][:, t], out["P_pred"][:, t], out["s"][:, t] = xp, Pp, s
        out["nu"][:, t], out["x_upd"][:, t], out["P_upd"][:, t] = nu, xh, P
    return out


# ----------------------------------------------------------------------------- likelihood
_R2 = 1.0 / math.sqrt(2.0)


def log_silent_probability(m, h):
    """``log P(|Z + m| < h)`` for ``Z ~ N(0, 1)``, ``h >= 0``: a silent sensor's factor.

    The one implementation of the package,
    :func:`fusioncenter.censoring.probability.log_prob_inside` (two ``ndtr`` calls, the careful
    branch deep in the tails and for tiny ``h``).

    Parameters
    ----------
    m, h : array_like
        The interval's offset and half-width, in units of the noise standard deviation
        (broadcast).

    Returns
    -------
    numpy.ndarray
        ``log P(|Z + m| < h)``, finite for any finite ``m`` and ``h > 0``.
    """
    m, h = np.broadcast_arrays(np.asarray(m, dtype=float), np.asarray(h, dtype=float))
    return cprob.log_prob_inside(m, h)


def log_likelihood(sent, z, hx, hx_pred, s, r, eta, scheme: str = "cfwmd"):
    """Propositions 7 and 8: ``log p(z_obs, m | x, broadcast)`` up to a constant.

    ``sum_{received} log N(z^i; h^i(x), r_i) + sum_{silent} log P(|nu^i| < sqrt(eta s_i))``,
    ``nu^i ~ N(h^i(x) - h^i(xhat_{k|k-1}), r_i)``; ``scheme="cfomd"`` keeps the first sum only.
    Shapes broadcast: ``sent``, ``z``, ``hx`` (the amplitudes ``h^i(x)``), ``hx_pred``
    (``h^i(xhat_{k|k-1})``), ``s`` (``s_k^i`` for Proposition 7, ``s'^i_k`` for 8): ``(..., N)``;
    ``r (N,)``. Returns ``(...)``. The normalizing constants ``-log(2 pi r_i)/2`` are kept.
    """
    if scheme not in ("cfwmd", "cfomd"):
        raise ValueError(f"scheme must be 'cfwmd' or 'cfomd', got {scheme!r}")
    sent = np.asarray(sent, dtype=bool)
    hx = np.asarray(hx, dtype=float)
    r = np.asarray(r, dtype=float)
    if np.any(r <= 0):
        raise ValueError("r must be positive (a variance)")
    s = np.asarray(s, dtype=float)
    if np.any(s < 0):
        raise ValueError("s must be non-negative")
    if eta < 0:
        raise ValueError(f"eta must be non-negative, got {eta!r}")
    z = np.asarray(z, dtype=float)
    recv = np.where(sent, -0.5 * np.log(2 * np.pi * r) - 0.5 * (np.where(sent, z, 0.0) - hx)
                    ** 2 / r, 0.0)
    out = recv.sum(axis=-1)
    if scheme == "cfwmd":
        sd = np.sqrt(r)
        sil = log_silent_probability((hx - hx_pred) / sd, np.sqrt(eta * s) / sd)
        out = out + np.where(sent, 0.0, sil).sum(axis=-1)
    return out


#: Node spacing of the tabulated silent-sensor term (units of the noise standard deviation):
#: cubic Hermite interpolation error below 5e-10 in the log weight (tested).
SILENT_STEP = 0.025
_LOG_SQRT_2PI = 0.5 * math.log(2.0 * math.pi)


def silent_terms(a: np.ndarray, h: np.ndarray, step: float = SILENT_STEP) -> np.ndarray:
    """``log P(|Z + a| < h)`` for every row of ``a (rows, P) >= 0`` with its own ``h (rows,)``.

    Within a row ``h`` is fixed, and ``g(a) = log P(|Z + a| < h)`` is a smooth function of one
    variable: ``g(a) = -a^2/2 + K(a) + const``, ``K`` the cumulant generating function of a
    standard normal truncated to ``(-h, h)``, so ``g'' = Var - 1`` lies in ``[-1, 0]`` and the
    fourth derivative is a fourth cumulant of a law on an interval of length ``2 h``. Each row
    is tabulated on the nodes ``0, step, 2 step, ...`` up to its largest ``a``, with the exact
    values (:func:`log_silent_probability`) and derivatives ``g'(a) = -(phi(h - a) -
    phi(h + a)) / P``, and evaluated by cubic Hermite interpolation: 4 table look-ups and a
    cubic per particle instead of two normal cdfs and a log. Rows whose range would need more
    nodes than a quarter of their particles are evaluated directly.

    Parameters
    ----------
    a : numpy.ndarray
        Offsets ``(rows, P)``, non-negative, in noise standard deviations.
    h : numpy.ndarray
        Half-widths ``(rows,)``.
    step : float, optional
        Node spacing (:data:`SILENT_STEP`).

    Returns
    -------
    numpy.ndarray
        ``log P(|Z + a| < h)`` ``(rows, P)`` (error below 5e-10).
    """
    rows, P = a.shape
    out = np.array(a, dtype=float)
    if rows == 0:
        return out
    _silent_rows(out[:, None, :], np.arange(rows), np.zeros(rows, dtype=np.int64),
                 a.max(axis=1), h, step)
    return out


def _silent_rows(a: np.ndarray, rb: np.ndarray, ri: np.ndarray, amax: np.ndarray,
                 h: np.ndarray, step: float = SILENT_STEP) -> None:
    """:func:`silent_terms` in place on the rows ``a[rb[k], ri[k], :]`` of ``a (n, N, P)``
    (offsets, maxima ``amax (rows,)``, half-widths ``h (rows,)``)."""
    P = a.shape[2]
    J = np.floor(amax / step).astype(np.int64) + 2  # nodes per row
    direct = J > max(64, P // 4)
    if direct.any():
        db, di = rb[direct], ri[direct]
        a[db, di] = log_silent_probability(a[db, di], h[direct][:, None])
    tab = np.flatnonzero(~direct)
    if tab.size == 0:
        return
    Jt = J[tab]
    off = np.cumsum(Jt) - Jt
    owner = np.repeat(np.arange(tab.size), Jt)
    node = np.arange(owner.size) - off[owner]
    an = node * step
    hn = h[tab][owner]
    g = log_silent_probability(an, hn)
    with np.errstate(over="ignore", under="ignore"):
        dg = (np.exp(-0.5 * (hn + an) ** 2 - _LOG_SQRT_2PI - g)
              - np.exp(-0.5 * (hn - an) ** 2 - _LOG_SQRT_2PI - g)) * step
    # interval [node, node + 1] of each row: c0 + f (c1 + f (c2 + f c3)); the last node of a
    # row starts no interval (its coefficients are never read)
    gn = np.append(g[1:], 0.0)
    dn = np.append(dg[1:], 0.0)
    diff = gn - g
    c2 = 3.0 * diff - 2.0 * dg - dn
    c3 = -2.0 * diff + dg + dn
    _kernels.hermite_rows(a, rb[tab], ri[tab], off, 1.0 / step, g, dg, c2, c3)


# ----------------------------------------------------------------------------- the fusion centre
class _FusionCentre(fusion.ReferenceFC):
    """The FC's particle-filter model (a :class:`fusioncenter.particle.FilterModel`) for one
    block of trials; it also plays the sensors (with feedback their decisions at step ``t``
    depend on the FC's broadcast after step ``t - 1``)."""

    dim = 4

    def __init__(self, sc: NonlinearScenario, scheme: str, feedback: str, eta: float, l: float,
                 z: np.ndarray, sel_u: np.ndarray):
        self.sc, self.scheme, self.feedback, self.eta = sc, scheme, feedback, eta
        self.z = z
        n, T, N = z.shape
        self.n, self.N = n, N
        self.pos = sc.positions
        self.r = sc.rvec
        self.sd = np.sqrt(self.r)
        self.sent = np.zeros((n, T, N), dtype=bool)
        self.s = np.full((n, T, N), np.nan)  # what the sensors normalized by
        self.censor = scheme in ("cfomd", "cfwmd")
        self.live = self.censor and feedback != "none"  # decisions depend on the broadcast
        self.needs_cov = self.live and feedback == "state+cov"
        dyn = sc.dynamics
        self.est = np.broadcast_to(dyn.m0, (n, 4)).copy()  # xhat_{t-1|t-1} broadcast
        self.est_cov = np.broadcast_to(dyn.P0, (n, 4, 4)).copy()
        self.P_loc = np.broadcast_to(dyn.P0, (n, N, 4, 4)).copy()  # P^i_{t-1|t-1}
        self.hx_pred = None
        self.hh = None
        self._fixed_decisions(feedback, l, sel_u)

    # --- sensors
    def _local_decisions(self) -> None:
        """No feedback: every sensor runs a full EKF on its own measurements."""
        loc = local_ekf(self.sc, self.z)
        self.sent[:] = loc["nu"] ** 2 >= self.eta * loc["s"]
        self.s[:] = loc["s"]

    def _feedback_decisions(self, k: int) -> None:
        """Decisions at step ``k + 1`` from the broadcast ``xhat_{k|k}`` (and ``Phat_{k|k}``)."""
        sc = self.sc
        xp = self.est @ sc.F.T  # xhat_{k+1|k}, every sensor's prediction
        g = jacobian(sc, xp)  # (n, N, 4)
        if self.feedback == "state":
            _, s, self.P_loc = ekf_covariance_step(self.P_loc, g, sc.F, sc.Q, self.r)
        else:
            Pp = sc.F @ self.est_cov @ sc.F.T + sc.Q  # (n, 4, 4)
            s = np.einsum("nik,nkl,nil->ni", g, Pp, g) + self.r
        self.hx_pred = amplitude(sc, xp[:, [0, 2]])  # (n, N)
        nu = self.z[:, k] - self.hx_pred
        self.sent[:, k] = nu * nu >= self.eta * s
        self.s[:, k] = s
        self.hh = np.sqrt(self.eta * s) / self.sd  # half-width of the silent interval / sd

    # --- FilterModel (initial, transition: see fusion.ReferenceFC)
    def log_weight(self, t: int, x: np.ndarray) -> np.ndarray:
        k = t - 1
        if self.live:
            self._feedback_decisions(k)
        sent = self.sent[:, k]  # (n, N)
        if self.scheme != "cfwmd" and not sent.all():
            return self._received_only(k, x)
        amp = self._amplitudes(x)  # (n, N, P): h^i(x) for every particle
        # amp becomes the per-sensor log-likelihood terms, in place (compiled): received,
        # log N(z; h(x), r); silent (CFwMD), the offsets, then their factors
        amax = np.empty(sent.shape)
        _kernels.sensor_terms(amp, sent, self.z[:, k], -0.5 / self.r, self.hx_pred
                              if self.hx_pred is not None else amax, self.sd, amax)
        if not sent.all():
            rb, ri = np.nonzero(~sent)
            _silent_rows(amp, rb, ri, amax[rb, ri], self.hh[rb, ri])
        if amp.shape[2] < 2:
            return amp.sum(axis=1)
        out = np.empty((amp.shape[0], amp.shape[2]))
        _kernels.sum_sensors(amp, out)  # amp.sum(axis=1), one pass
        return out

    def _received_only(self, k: int, x: np.ndarray) -> np.ndarray:
        """``sum_{received} log N(z^i; h^i(x), r_i)`` computing ``h^i`` only where needed
        (compiled for the exponent 2)."""
        n, P = x.shape[:2]
        out = np.zeros((n, P))
        if self.sc.exponent == 2.0 and self.N <= 129:
            _kernels.received_terms(x, self.pos, float(self.sc.alpha), float(self.sc.power),
                                    self.sent[:, k], self.z[:, k], -0.5 / self.r, out)
            return out
        b, i = np.nonzero(self.sent[:, k])  # row-major: b is non-decreasing
        if b.size == 0:
            return out
        d2 = x[b, :, 0] - self.pos[i, 0][:, None]
        d2 *= d2
        dy = x[b, :, 2] - self.pos[i, 1][:, None]
        dy *= dy
        d2 += dy
        e = _amp_from_d2(self.sc, d2)
        e -= self.z[b, k, i][:, None]
        e *= e
        e *= (-0.5 / self.r[i])[:, None]
        rows, start = np.unique(b, return_index=True)
        out[rows] = np.add.reduceat(e, start, axis=0)
        return out

    def _amplitudes(self, x: np.ndarray) -> np.ndarray:
        """``h^i(x)`` for every trial, sensor and particle: ``(n, N, P)`` (compiled for the
        exponent 2). The squared distances are assembled from the distinct sensor abscissae
        and ordinates (3 + 3 on a grid)."""
        n, P = x.shape[:2]
        if self.sc.exponent == 2.0:
            out = np.empty((n, self.N, P))
            _kernels.amplitudes(x, self.pos, float(self.sc.alpha), float(self.sc.power), out)
            return out
        px = np.ascontiguousarray(x[..., 0])
        py = np.ascontiguousarray(x[..., 2])
        ux, ix = np.unique(self.pos[:, 0], return_inverse=True)
        uy, iy = np.unique(self.pos[:, 1], return_inverse=True)
        dx2 = np.square(px[:, None, :] - ux[None, :, None])  # (n, #x, P)
        dy2 = np.square(py[:, None, :] - uy[None, :, None])
        d2 = np.empty((n, self.N, P))
        for i in range(self.N):
            np.add(dx2[:, ix[i]], dy2[:, iy[i]], out=d2[:, i])
        return _amp_from_d2(self.sc, d2)

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None:
        self.est = mean
        if cov is not None:
            self.est_cov = cov


def _chunk(rng: np.random.Generator, n: int, *, scenario: NonlinearScenario, scheme: str,
           feedback: str, eta: float, l: float, n_particles: int,
           ess_threshold: float) -> np.ndarray:
    """``chunk_fn`` for :func:`fusioncenter.montecarlo.simulate`: ``(n, T, d + 3)`` per trial,
    the layout of :class:`fusioncenter.censoring.CensoringResult` (squared error per state
    component, number of sensors that sent, ESS / particles, collapsed). As in
    :mod:`fusioncenter.censoring`, the first of two spawned streams draws the truth, the
    measurements and the random-selection uniforms (trials are paired across schemes, ``l`` and
    feedback), the second the filter's particles and resampling uniforms."""
    rng_data, rng_pf = rng.spawn(2)
    x, z = scenario.sample(rng_data, n)
    sel_u = rng_data.random(z.shape)
    fc = _FusionCentre(scenario, scheme, feedback, eta, l, z, sel_u)
    out = particle.run_filter(fc, rng_pf, n, n_particles, scenario.T,
                              ess_threshold=ess_threshold)
    sq = (out.mean - x[:, 1:]) ** 2
    return np.concatenate([sq, fc.sent.sum(axis=-1, keepdims=True).astype(float),
                           out.ess[..., None] / n_particles,
                           out.collapsed[..., None].astype(float)], axis=-1)


# ----------------------------------------------------------------------------- run
def run(scenario: NonlinearScenario, scheme: str, *, l, n_trials: int, n_particles: int,
        seed: int, feedback: str = "state", likelihood: str = "corrected",
        ess_threshold: float = 1.0, chunk_size: int | None = None, executor=None,
        progress: bool = False,
        block_size: int = montecarlo.DEFAULT_BLOCK_SIZE) -> results.CensoringResult:
    """Simulate ``n_trials`` trials of ``scenario`` and track them with the FC's particle filter.

    The signature and the result of :func:`fusioncenter.censoring.run`: ``scheme`` in
    :data:`SCHEMES`, ``feedback`` in :data:`FEEDBACK` (``"state"``: Proposition 7, CFwMD;
    ``"state+cov"``: Proposition 8, CFwMD2; ``"none"``: not for ``"cfwmd"``), ``l`` the target
    average number of sending sensors (``eta = threshold(l, N)``; ``p = l / N`` for random
    selection). ``likelihood`` only concerns CFwMD without feedback in the linear model; it is
    validated and recorded, and has no effect here. Runs through
    :func:`fusioncenter.montecarlo.simulate`: results are bitwise identical for any
    ``chunk_size`` and executor, and trials are paired across schemes for the same ``seed``,
    ``n_trials`` and ``block_size``.

    Peak memory of a task (tracemalloc): about 350 bytes per particle of a block (``block_size
    * n_particles`` particles) for CFwMD, 290 for all-send, 150 for CFoMD, so ``block_size=25``
    with ``10^4`` particles needs about 85 MB per worker on top of the interpreter (about 100 MB
    with numpy and scipy).
    """
    if not isinstance(scenario, NonlinearScenario):
        raise ValueError("scenario must be a NonlinearScenario")
    results.check_scheme(scheme, feedback)
    if scheme == "cfwmd" and feedback == "none":
        raise ValueError("feedback='none' is not available for scheme='cfwmd': without feedback "
                         "the paper gives no full likelihood for the nonlinear system (Remark 4 "
                         "(III)); use feedback='state' or 'state+cov'")
    _one_of("likelihood", likelihood, scenarios.LIKELIHOODS)
    eta = cprob.threshold(l, scenario.N)
    n_particles = _posint("n_particles", n_particles)
    return results.run_chunks(_chunk, scenario, scheme, feedback, likelihood, l=l, eta=eta,
                                 n_particles=n_particles, ess_threshold=ess_threshold,
                                 n_trials=n_trials, seed=seed, chunk_size=chunk_size,
                                 executor=executor, progress=progress, block_size=block_size,
                                 chunk_kwargs={})
