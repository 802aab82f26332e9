"""The nonlinear tracking model of zheng2014 Section VII.C (:class:`NonlinearScenario`): the
sensors' amplitude measurements (42), their gradient, and the sensors' own extended Kalman
filters. The fusion centre and ``run`` are in :mod:`fusioncenter.censoring.nonlinear`, which
re-exports these names."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter._compiled import amplitude_ekf
from fusioncenter._validate import posint as _posint
from fusioncenter.censoring import scenarios


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

    Parameters
    ----------
    per_side : int, optional
        Sensors per side.
    side : float, optional
        Side of the square region (m), ``> 0``.
    layout : str, optional
        ``"centres"`` or ``"edges"``.

    Returns
    -------
    numpy.ndarray
        Positions ``(per_side**2, 2)``.
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

    Parameters
    ----------
    sensors, region, power, alpha, exponent, r, sigma2, dt, T, x0, P0, initial_truth
        The fields above (paper values by default).
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
        """Number of sensors."""
        return self._cache["N"]

    @property
    def positions(self) -> np.ndarray:
        """Sensor positions ``(N, 2)`` (m)."""
        return self._cache["pos"].copy()

    @property
    def rvec(self) -> np.ndarray:
        """Measurement noise variances, one per sensor ``(N,)``."""
        return np.broadcast_to(np.asarray(self.r, dtype=float), (self.N,)).copy()

    position_index = (0, 2)
    velocity_index = (1, 3)

    def sensor_groups(self) -> list[np.ndarray]:
        # sensors at the same position with the same noise variance measure alike:
        # Scenario.sensor_groups (the nonlinear fusion centre does not group them)
        key = np.concatenate([self.positions, self.rvec[:, None]], axis=1)
        return scenarios.groups_of_rows(key)

    @property
    def choices(self) -> dict[str, str]:
        """Every choice the paper leaves open, with the value this scenario uses."""
        grid = grid_positions(3, self.region)
        default = self.positions.shape == grid.shape and np.allclose(self.positions, grid)
        P0 = ("diag" if np.ndim(self.P0) == 1 else "") + scenarios.values_text(self.P0)
        return {
            "region": f"the square [−{self.region / 2:g}, {self.region / 2:g}]² m, centred at "
                      "the origin (the paper: a 20 m × 20 m area; the centring is implied by "
                      "x₀ = (−8, −8) and by the target leaving the region near the end)",
            "sensor positions": ("centres of the 3 × 3 cells of the region, x, y ∈ {−20/3, 0, "
                                 "20/3} m (the paper: 'grid deployed', positions not given)"
                                 if default else
                                 f"given: {scenarios.values_text(self.sensors)} m"),
            "measurement": "the amplitude √(P₀/(1 + α dⁿ)) plus N(0, r) noise (the paper calls "
                           "it the received 'signal power'; its formula is the amplitude)",
            "time axis": f"x₀ at t = 0 is not measured; the sensors measure at steps k = 1, …, T "
                         f"(T = {self.T}, t = k Δt); RMSE and transmissions reported for k = "
                         "1, …, T",
            "initial state": ("the true x₀ = x̄₀ in every trial (the target always starts at "
                              f"x̄₀ = {scenarios.values_text(self.x0)}); only the filters' prior "
                              f"is N(x̄₀, P₀), P₀ = {P0}"
                              if self.initial_truth == "mean" else
                              "the true x₀ ∼ N(x̄₀, P₀) drawn for every trial, x̄₀ = "
                              f"{scenarios.values_text(self.x0)}, "
                              f"P₀ = {P0}"),
            "PF prior": "particles at t = 0 drawn from N(x̄₀, P₀)",
            "local EKFs": "every sensor's EKF starts from (x̄₀, P₀); its covariance recursion "
                          "uses its own measurement at every step (censoring only decides what "
                          "is sent); with feedback it linearizes hⁱ at the broadcast prediction "
                          "F x̂ₖ₋₁|ₖ₋₁ (Remark 3 (I)), so the FC can replay it",
            "feedback 'state'": "x̂ₖ₋₁|ₖ₋₁ (weighted particle mean before resampling) is "
                                "broadcast after step k − 1; sensors use x̂ₖ|ₖ₋₁ = F x̂ₖ₋₁|ₖ₋₁ in "
                                "the innovation and normalize by their own EKF "
                                "sₖⁱ = g Pⁱₖ|ₖ₋₁ gᵀ + r (Proposition 7); x̂₀|₀ = x̄₀",
            "feedback 'state+cov'": "also P̂ₖ₋₁|ₖ₋₁ (weighted particle covariance); "
                                    "s′ₖⁱ = g (F P̂ₖ₋₁|ₖ₋₁ Fᵀ + Q) gᵀ + r for sensors and FC "
                                    "(Proposition 8, 'CFwMD2'); P̂₀|₀ = P₀",
            "feedback 'none'": "each sensor runs a full EKF on its own data; accepted for "
                               "all-send, random and CFoMD only (no full likelihood: Remark 4 "
                               "(III))",
            "Jacobian": "gₖⁱ = ∂hⁱ/∂x at the (broadcast or local) prediction x̂ₖ|ₖ₋₁",
            "threshold": "η = the upper-(l/N) quantile of χ²₁, the same for every sensor and step "
                         "(eq. (43))",
            **scenarios.SCHEME_CHOICES,
        }

    # --- simulation
    def sample(self, rng: np.random.Generator, n: int):
        """Truth and measurements of ``n`` trials.

        Draws ``x_0`` (if ``initial_truth`` is ``"random"``), then ``T`` transitions, then all
        measurement noises.

        Parameters
        ----------
        rng : numpy.random.Generator
            The source of the draws.
        n : int
            Number of trials.

        Returns
        -------
        x : numpy.ndarray
            True states ``(n, T+1, 4)``, ``x[:, 0] = x_0``.
        z : numpy.ndarray
            Measurements ``(n, T, N)``, ``z[:, k-1]`` measured at step ``k``.
        """
        x = self._truth(rng, n, draw_x0=self.initial_truth == "random")
        noise = rng.standard_normal((n, self.T, self.N)) * np.sqrt(self.rvec)
        z = amplitude_ekf.amplitude(self, x[:, 1:, [0, 2]]) + noise
        return x, z


# ----------------------------------------------------------------------------- measurement model
def amplitude_from_d2(sc: NonlinearScenario, d2):
    """``sqrt(power / (1 + alpha d^n))`` from the squared distance (in place on ``d2``).

    Parameters
    ----------
    sc : NonlinearScenario
        The scenario (``power``, ``alpha``, ``exponent``).
    d2 : numpy.ndarray
        Squared distances, overwritten.

    Returns
    -------
    numpy.ndarray
        The amplitudes (the array ``d2``).
    """
    return amplitude_ekf.amplitude_from_d2(sc, d2)


def amplitude(scenario: NonlinearScenario, pos) -> np.ndarray:
    """``h^i`` at positions ``pos (..., 2)`` (m) for every sensor: ``(..., N)``.

    Parameters
    ----------
    scenario : NonlinearScenario
        The scenario.
    pos : array_like
        Positions ``(..., 2)`` (m).

    Returns
    -------
    numpy.ndarray
        ``h^i(pos)`` ``(..., N)`` (``0`` at an infinite distance).

    Raises
    ------
    ValueError
        If ``pos`` is text, holds a NaN, or does not end in an axis of length 2.
    """
    pos = _v.as_float("pos", pos)
    if np.isnan(pos).any():
        raise ValueError(f"pos must not be NaN (a position; +-inf is a target infinitely far "
                         f"away, amplitude 0), got {pos!r}")
    return amplitude_ekf.amplitude(scenario, pos)


def jacobian(scenario: NonlinearScenario, x) -> np.ndarray:
    """``g^i = dh^i/dx`` at states ``x (..., 4)``: ``(..., N, 4)``, zero in the velocities.

    ``h = sqrt(P0) (1 + alpha d^n)^(-1/2)`` gives ``dh/dp = -(alpha n / 2) d^(n-2) (p - p_i)
    h^3 / P0`` (for ``n = 2``: ``-alpha (p - p_i) h^3 / P0``). At ``d = 0`` with ``n < 2`` the
    gradient is taken as 0 (a measure-zero event).

    Parameters
    ----------
    scenario : NonlinearScenario
        The scenario.
    x : array_like
        States ``(..., 4)``.

    Returns
    -------
    numpy.ndarray
        ``g^i`` ``(..., N, 4)``.

    Raises
    ------
    ValueError
        If ``x`` is not finite or does not end in an axis of length 4.
    """
    return amplitude_ekf.jacobian(scenario, _v.finite("x", x))


def ekf_covariance_step(P, g, F, Q, r):
    """One EKF covariance recursion, vectorized over leading axes.

    ``P (..., d, d)``: ``P_{k-1|k-1}``; ``g (..., d)``: the measurement gradient at the
    prediction; ``r`` broadcast to ``(...)``. Returns ``P_pred = F P F^T + Q``,
    ``s = g P_pred g^T + r`` and, in Joseph form (as filterpy), ``P_upd = (I - w g) P_pred
    (I - w g)^T + r w w^T`` with the gain ``w = P_pred g^T / s`` (symmetrized).

    Parameters
    ----------
    P : numpy.ndarray
        ``P_{k-1|k-1} (..., d, d)``.
    g : numpy.ndarray
        Gradients ``(..., d)``.
    F, Q : numpy.ndarray
        Transition and process-noise covariance ``(d, d)``.
    r : array_like
        Noise variance(s).

    Returns
    -------
    tuple of numpy.ndarray
        ``(P_pred, s, P_upd)``. Where ``s = 0`` (``r = 0`` and ``g P_pred g^T = 0``: a
        noise-free measurement of a direction already known, e.g. a zero gradient) the
        measurement carries no information: the gain is 0 and ``P_upd = P_pred``.

    Raises
    ------
    ValueError
        Naming the argument that is not finite, not a covariance (``P``, ``Q``; ``P`` ``0x0``:
        no state), negative (``r``), or of the wrong shape (the message states the expected
        one).
    """
    P = _v.nonempty("P", _v.covariance("P", P, batch=True))
    d = P.shape[-1]
    g = _v.shape_is("g", _v.finite("g", g), (..., d), f"P is {d}x{d}")
    F = _v.shape_is("F", _v.finite("F", F), (d, d), f"P is {d}x{d}")
    Q = _v.covariance("Q", Q, n=d)
    r = _v.nonneg("r", r, "a noise variance")
    _v.broadcast(P=P[..., 0, 0], g=g[..., 0], r=r)
    with np.errstate(divide="ignore", invalid="ignore"):
        Pp, s, Pu = amplitude_ekf.ekf_step(P, g, F, Q, r)
    known = s == 0
    if np.any(known):  # no information: w = 0, P_upd = P_pred (symmetrized as the kernel does)
        Pu = np.where(known[..., None, None], 0.5 * (Pp + np.swapaxes(Pp, -1, -2)), Pu)
    return Pp, s, Pu


def local_ekf(scenario: NonlinearScenario, z) -> dict[str, np.ndarray]:
    """Every sensor's own EKF on its own measurements (no feedback), vectorized over trials and
    sensors: ``z (n, T, N)`` -> ``x_pred (n, T, N, 4)`` (``xhat^i_{k|k-1}``), ``P_pred (n, T, N,
    4, 4)``, ``s (n, T, N)``, ``nu (n, T, N)`` (innovations ``z - h^i(xhat^i_{k|k-1})``),
    ``x_upd`` and ``P_upd`` (``xhat^i_{k|k}``, ``P^i_{k|k}``). Every filter starts from
    ``(x0, P0)`` and linearizes ``h^i`` at its own prediction.

    Parameters
    ----------
    scenario : NonlinearScenario
        The scenario.
    z : array_like
        Measurements ``(n, T, N)``.

    Returns
    -------
    dict of str to numpy.ndarray
        The arrays named above.
    """
    sc = scenario
    z = _v.finite("z", z)
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
        g = amplitude_ekf.jacobian(sc, xp)[:, idx, idx]  # sensor i's gradient at its own prediction
        Pp, s, P = amplitude_ekf.ekf_step(P, g, F, Q, r)
        nu = z[:, t] - amplitude_ekf.amplitude(sc, xp[..., [0, 2]])[:, idx, idx]
        xh = xp + (Pp @ g[..., None])[..., 0] * (nu / s)[..., None]
        out["x_pred"][:, t], out["P_pred"][:, t], out["s"][:, t] = xp, Pp, s
        out["nu"][:, t], out["x_upd"][:, t], out["P_upd"][:, t] = nu, xh, P
    return out
