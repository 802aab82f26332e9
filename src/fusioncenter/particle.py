"""A bootstrap particle filter vectorized across Monte Carlo trials.

The design follows Chopin's ``particles`` package: the *model* (initial law, transition, the
log-likelihood of whatever the fusion centre received) is kept apart from the *algorithm* (the
one sequential Monte Carlo loop :func:`run_filter`), with one more leading axis for Monte Carlo
trials. Shapes:

* particles ``x``: ``(n, P, d)`` -- ``n`` independent trials, ``P`` particles, state dimension
  ``d``;
* log weights ``logw``: ``(n, P)``; every trial is normalized on its own (log-sum-exp);
* per-trial uniforms ``u``: ``(n,)`` (one systematic-resampling uniform per trial and step).

Everything that touches one trial's particles uses only that trial's row, so splitting the trials
into blocks (as :func:`fusioncenter.montecarlo.simulate` does) never changes a row's result.

Letters: the library's linear-Gaussian vocabulary (:mod:`fusioncenter.kalman`), ``x_t = A x_{t-1}
+ u``, ``u ~ N(0, Q)``, measurements ``C x + v``; zheng2014's ``F`` (for ``A``) and ``H`` (for
``C``) are aliases where a public class uses them (``LinearGaussianDynamics.F``, the censoring
scenarios' ``F`` and ``H``).

A model for :func:`run_filter` is any object with (see :class:`FilterModel`)

* ``dim`` -- the state dimension ``d``;
* ``initial(rng, n, P) -> (n, P, d)`` -- draw the particles of the prior of ``x_0``;
* ``transition(rng, t, x) -> (n, P, d)`` -- draw ``x_t`` given ``x_{t-1}`` for every particle;
* ``log_weight(t, x) -> (n, P)`` -- the incremental log weight at time ``t`` (the log-likelihood
  of the data received at ``t``; additive constants may be dropped); the loop normalizes it in
  place, so the model must not rely on its content afterwards (it may reuse the buffer);
* ``observe(t, mean, cov)`` -- called after weighting with the filter's estimate ``E[x_t | data]``
  ``(n, d)`` and its covariance ``(n, d, d)``: this is where a fusion centre records its estimate
  and prepares what it feeds back to the sensors for time ``t + 1``. May do nothing;
* optional ``needs_cov`` (default ``True``): ``False`` skips the weighted covariance (then
  ``observe`` receives ``cov=None`` and :attr:`FilterOutput.cov` is NaN).

Functions (signature, one line each):

* ``log_normalize(logw) -> (logw_normalized, log_sum)``: log-sum-exp over the last axis.
* ``ess(logw) -> (...)``: effective sample size ``1 / sum w^2`` of (any) log weights.
* ``systematic_counts(logw, u) -> int (..., P)``: offspring counts of systematic resampling.
* ``systematic_resample(logw, u) -> int (..., P)``: ancestor indices (sorted within a row).
* ``resample(x, idx)``: ``x[..., idx, :]`` row by row.
* ``weighted_mean(x, logw)``, ``weighted_mean_cov(x, logw)``: posterior mean (and covariance).
* ``LinearGaussianDynamics(A, Q, m0, P0)``: ``x_0 ~ N(m0, P0)``, ``x_t = A x_{t-1} + u``,
  ``u ~ N(0, Q)``; its ``initial`` / ``transition`` draw only ``rank(P0)`` / ``rank(Q)`` normals
  per particle.
* ``run_filter(model, rng, n_trials, n_particles, steps, *, ess_threshold=1.0) -> FilterOutput``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from fusioncenter import _kernels, _transition_kernels, _ziggurat
from fusioncenter._docstrings import Glossary
from fusioncenter._validate import as_float as _v_as_float
from fusioncenter._validate import covariance as _covariance
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import is_text
from fusioncenter._validate import nonempty as _nonempty
from fusioncenter._validate import square as _square

__all__ = [
    "log_normalize",
    "ess",
    "systematic_counts",
    "systematic_resample",
    "resample",
    "weighted_mean",
    "weighted_mean_cov",
    "by_component",
    "psd_factor",
    "LinearGaussianDynamics",
    "FilterModel",
    "FilterOutput",
    "run_filter",
]


#: The arguments of the weight and resampling functions, by name.
_doc = Glossary("""
logw : array_like
    Log weights ``(..., P)``, not necessarily normalized; ``-inf`` (weight zero) allowed, NaN
    and ``+inf`` not.
x : array_like
    Particles ``(..., P, d)``.
u : array_like
    One uniform in ``[0, 1)`` per row, shaped like the leading axes ``(...)`` of ``logw``.
idx : array_like
    Ancestor indices ``(..., P)``, integers in ``[0, P)``.
""", raises="""
ValueError
    If ``logw`` has no particle on its last axis or holds NaN or ``+inf``.
""")
#: The ``Raises`` section of the functions that also take resampling uniforms.
_RAISES_U = (("ValueError", "If ``logw`` has no particle on its last axis or holds NaN or "
                            "``+inf``, or ``u``\nis not one uniform in ``[0, 1)`` per row."),)


# ----------------------------------------------------------------------------- weights
@_doc(returns=(("numpy.ndarray", "The normalized log weights ``(..., P)`` (uniform for a row "
                                 "without weight)."),
               ("numpy.ndarray", "``log sum exp logw`` per row ``(...)`` (``-inf`` for such a "
                                 "row).")))
def log_normalize(logw):
    """Normalize log weights over the last axis: ``(logw - log sum exp logw, log sum exp logw)``.

    The maximum is subtracted before exponentiating, so weights never overflow and at least one
    weight per row is exactly representable. A row whose weights are all zero (all ``-inf``: no
    particle is compatible with the data) has no normalization; it is returned as *uniform*
    weights with ``log_sum = -inf``, so the caller can detect and count the collapse (the filter
    then simply ignores that step's data for that trial).
    """
    logw = np.asarray(logw, dtype=float)
    if logw.ndim < 1 or logw.shape[-1] < 1:
        raise ValueError(f"logw must have at least one particle on its last axis, got {logw.shape}")
    if np.any(np.isnan(logw)) or np.any(logw == np.inf):
        raise ValueError("logw must not contain NaN or +inf")
    mx = logw.max(axis=-1, keepdims=True)
    dead = mx == -np.inf
    mx_safe = np.where(dead, 0.0, mx)
    with np.errstate(divide="ignore"):
        lse = mx_safe + np.log(np.exp(logw - mx_safe).sum(axis=-1, keepdims=True))
    out = np.where(dead, -np.log(logw.shape[-1]), logw - np.where(dead, 0.0, lse))
    lse = np.where(dead, -np.inf, lse)
    return out, lse[..., 0]


@_doc(returns=("numpy.ndarray", "``(...)``, in ``[1, P]``."))
def ess(logw):
    """Effective sample size ``1 / sum_j w_j^2`` per row (weights normalized first), in [1, P]."""
    lw, _ = log_normalize(logw)
    return np.exp(-np.log(np.exp(2.0 * lw).sum(axis=-1)))


def _check_u(u, lead: tuple[int, ...]) -> np.ndarray:
    u = np.asarray(u, dtype=float)
    if u.shape != lead:
        raise ValueError(f"u must have one uniform per row, shape {lead}, got {u.shape}")
    if np.any((u < 0) | (u >= 1)) or not np.all(np.isfinite(u)):
        raise ValueError("u must lie in [0, 1)")
    return u


@_doc(returns=("numpy.ndarray", "``int64 (..., P)``; every row sums to ``P``."), raises=_RAISES_U)
def systematic_counts(logw, u) -> np.ndarray:
    """Number of offspring of each particle under systematic resampling, ``int64 (..., P)``.

    Row ``b`` places the ``P`` points ``(u_b + i) / P``, ``i = 0..P-1``, on the cumulative
    normalized weights ``c_j``; particle ``j`` gets the points in ``[c_{j-1}, c_j)``:
    ``count_j = ceil(P c_j - u) - ceil(P c_{j-1} - u)`` (with ``c_{-1} = 0`` and ``c_{P-1} = 1``
    set exactly, so every row's counts sum to ``P``). ``E[count_j] = P w_j`` for ``u ~ U[0, 1)``
    (unbiased), and ``|count_j - P w_j| < 1``. Rows are computed independently of each other
    (sequential ``cumsum`` within a row), so the result of a row does not depend on which other
    rows are in the batch.
    """
    lw, _ = log_normalize(logw)
    u = _check_u(u, lw.shape[:-1])
    return _counts(np.exp(lw), u)


def _counts(w, u) -> np.ndarray:
    """Systematic offspring counts from *normalized* weights ``w (..., P)``; no checks."""
    P = w.shape[-1]
    c = np.cumsum(w, axis=-1)
    c /= c[..., -1:]
    c[..., -1] = 1.0
    edges = np.ceil(P * c - u[..., None])
    return np.diff(edges, axis=-1, prepend=0.0).astype(np.int64)


def _systematic_flat(w, u) -> np.ndarray:
    """Ancestor indices into the flattened ``(n * P)`` particles, from normalized ``w (n, P)``."""
    counts = _counts(w, u)
    return np.repeat(np.arange(counts.size), counts.ravel())


@_doc(returns=("numpy.ndarray", "``int64 (..., P)``, non-decreasing within each row."),
      raises=_RAISES_U)
def systematic_resample(logw, u) -> np.ndarray:
    """Ancestor indices ``int64 (..., P)`` of systematic resampling (see :func:`systematic_counts`).

    Within each row the indices are non-decreasing. Vectorized: one ``np.repeat`` over all rows
    (every row's counts sum to ``P``, so the flat result splits back into rows).
    """
    counts = systematic_counts(logw, u)
    P = counts.shape[-1]
    flat = counts.reshape(-1, P)
    idx = np.repeat(np.tile(np.arange(P), flat.shape[0]), flat.ravel())
    return idx.reshape(counts.shape)


@_doc(returns=("numpy.ndarray", "The selected particles ``(..., K, d)``, a new array."),
      raises=(("ValueError", "If ``x`` is not ``(..., P, d)``, ``idx`` is not an integer array "
                             "whose leading axes\nmatch ``x``'s, or an index lies outside "
                             "``[0, P)`` (negative indices are not\nwrapped around)."),))
def resample(x, idx) -> np.ndarray:
    """Select particles row by row: ``out[..., j, :] = x[..., idx[..., j], :]``."""
    x = np.asarray(x)
    idx = np.asarray(idx)
    if x.ndim < 2:
        raise ValueError(f"x must be particles (..., P, d), got shape {x.shape}")
    if idx.dtype.kind not in "iu":
        raise ValueError(f"idx must be an integer array of ancestor indices, got dtype "
                         f"{idx.dtype}")
    if idx.ndim < 1 or idx.shape[:-1] != x.shape[:-2]:
        raise ValueError(f"idx must have shape {(*x.shape[:-2], 'K')} (the leading axes of x "
                         f"{x.shape}), got {idx.shape}")
    P = x.shape[-2]
    if idx.size and (idx.min() < 0 or idx.max() >= P):
        raise ValueError(f"idx must lie in [0, {P}) (ancestor indices of {P} particles), got "
                         f"values in [{idx.min()}, {idx.max()}]")
    return np.take_along_axis(x, idx[..., None], axis=-2)


def _weighted_args(x, logw) -> np.ndarray:
    """``x (..., P, d)`` finite and matching ``logw (..., P)`` (the weighted statistics)."""
    x = _finite("x", x)
    lw = tuple(np.shape(logw))
    ok = x.ndim >= 2 and x.shape[-2] == lw[-1]
    if ok:
        try:
            np.broadcast_shapes(x.shape[:-2], lw[:-1])
        except ValueError:
            ok = False
    if not ok:
        raise ValueError(f"x must have shape {(*lw, 'd')} (logw is {tuple(lw)}: (..., P)), got "
                         f"{x.shape}")
    return x


@_doc(returns=("numpy.ndarray", "``(..., d)``."))
def weighted_mean(x, logw) -> np.ndarray:
    """``sum_j w_j x_j`` per row: ``x (..., P, d)``, ``logw (..., P)`` -> ``(..., d)``."""
    lw, _ = log_normalize(logw)
    x = _weighted_args(x, logw)
    w = np.exp(lw)
    return (w[..., None, :] @ x)[..., 0, :]


@_doc(returns=(("numpy.ndarray", "The mean ``(..., d)``."),
               ("numpy.ndarray", "The covariance ``(..., d, d)``, symmetric.")))
def weighted_mean_cov(x, logw) -> tuple[np.ndarray, np.ndarray]:
    """Weighted mean ``(..., d)`` and covariance ``sum_j w_j (x_j - m)(x_j - m)^T`` ``(..., d, d)``.

    The covariance is the plug-in (biased, normalized by ``sum w = 1``) estimate, symmetrized.
    """
    lw, _ = log_normalize(logw)
    x = _weighted_args(x, logw)
    w = np.exp(lw)
    mean = (w[..., None, :] @ x)[..., 0, :]
    dev = x - mean[..., None, :]
    cov = np.swapaxes(dev * w[..., None], -1, -2) @ dev
    cov = 0.5 * (cov + np.swapaxes(cov, -1, -2))
    return mean, cov


def by_component(x) -> np.ndarray:
    """The particles ``x (n, P, d)`` stored component by component, seen as ``(n, P, d)``.

    Returns a view of a C-contiguous ``(n, d, P)`` copy: ``out[..., j]`` is then an ``(n, P)``
    array with contiguous rows, which makes elementwise work on one component (a position, a
    velocity) as fast as on a separate array. :func:`run_filter` keeps whatever layout the
    model's ``initial`` returns (its resampling buffer is ``numpy.empty_like`` of the particles).

    Parameters
    ----------
    x : array_like
        Particles ``(n, P, d)``.

    Returns
    -------
    numpy.ndarray
        The same values ``(n, P, d)``, with strides ``(d P, 1, P)`` elements.

    Raises
    ------
    ValueError
        If ``x`` is text or not 3-D (the values are copied as they are: a layout, not a
        computation, so NaN stays NaN).
    """
    x = _v_as_float("x", x)
    if x.ndim != 3:
        raise ValueError(f"x must be particles (n, P, d), got shape {x.shape}")
    return np.ascontiguousarray(np.swapaxes(x, 1, 2)).swapaxes(1, 2)


# ----------------------------------------------------------------------------- dynamics
def psd_factor(M, *, rtol: float = 1e-12) -> np.ndarray:
    """A thin factor ``L`` (``d x rank``) with ``L L^T = M`` for a symmetric PSD matrix ``M``.

    Eigenvalues below ``rtol * max(eig)`` are treated as zero and their columns dropped, so a
    rank-deficient ``M`` (e.g. zheng2014's white-noise-acceleration ``Q``, rank 1) is sampled with
    ``rank`` normals per draw. ``M = 0`` gives a ``d x 0`` factor.

    Parameters
    ----------
    M : array_like
        A covariance ``(d, d)``: finite, symmetric and positive semi-definite (tolerances of
        :func:`fusioncenter._validate.covariance`).
    rtol : float
        Relative threshold below which an eigenvalue counts as zero, in ``[0, 1)``.

    Returns
    -------
    numpy.ndarray
        ``L`` shaped ``(d, rank)``.

    Raises
    ------
    ValueError
        If ``M`` is not finite, not square (or ``0x0``), not symmetric or not PSD, or ``rtol``
        is out of range.
    """
    M = _nonempty("M", _covariance("M", M), "a 0x0 covariance has no state")
    rtol = float(_finite("rtol", rtol))
    if not 0.0 <= rtol < 1.0:
        raise ValueError(f"rtol must lie in [0, 1), got {rtol!r}")
    w, V = np.linalg.eigh(0.5 * (M + M.T))
    top = max(float(w.max(initial=0.0)), 0.0)
    keep = w > rtol * top if top > 0 else np.zeros_like(w, dtype=bool)
    return V[:, keep] * np.sqrt(w[keep])


def _matrix(name: str, value, shape=None) -> np.ndarray:
    arr = np.asarray(value, dtype=float) if not is_text(value) else _finite(name, value)
    if arr.ndim != 2 or (shape is not None and arr.shape != shape):
        raise ValueError(f"{name} must be a matrix of shape {shape}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite")
    return arr


def _psd(name: str, value, d: int) -> np.ndarray:
    arr = _matrix(name, value, (d, d))
    scale = max(1.0, float(np.abs(arr).max()))
    if np.any(np.abs(arr - arr.T) > 1e-10 * scale):
        raise ValueError(f"{name} must be symmetric")
    arr = 0.5 * (arr + arr.T)
    if np.linalg.eigvalsh(arr).min() < -1e-10 * scale:
        raise ValueError(f"{name} must be positive semi-definite (a covariance)")
    return arr


@dataclass(frozen=True, init=False)
class LinearGaussianDynamics:
    """``x_0 ~ N(m0, P0)``, ``x_t = A x_{t-1} + u_{t-1}``, ``u ~ N(0, Q)`` (zheng2014 eq. (1)).

    The initial law and the transition of a :class:`FilterModel`; a scenario combines it with its
    observation model. ``Q`` and ``P0`` may be singular (only ``rank`` normals are drawn). The
    letters are the library's (:mod:`fusioncenter.kalman`); zheng2014's ``F`` is an alias: the
    keyword ``F=`` is accepted for ``A`` and the attribute ``F`` returns ``A``.

    Parameters
    ----------
    A, Q, m0, P0 : array_like
        As the fields of :class:`fusioncenter.kalman.LinearGaussianModel` (``F=`` is accepted
        for ``A``); ``Q`` and ``P0`` are stored symmetrized.

    Raises
    ------
    ValueError
        If ``A`` and ``F`` are both given or both missing, or a field is not finite, of the
        wrong shape (``A`` ``0x0``: no state) or (``Q``, ``P0``) not a covariance; the message
        names it.
    """

    A: np.ndarray
    Q: np.ndarray
    m0: np.ndarray
    P0: np.ndarray

    def __init__(self, A=None, Q=None, m0=None, P0=None, *, F=None) -> None:
        if (A is None) == (F is None):
            raise ValueError("give the state transition once, as A (or its alias F)")
        name, A = ("A", A) if F is None else ("F", F)
        A = _nonempty(name, _square(name, _matrix(name, A)))
        d = A.shape[0]
        mean = np.asarray(m0, dtype=float).reshape(-1)
        if mean.shape != (d,) or not np.all(np.isfinite(mean)):
            raise ValueError(f"m0 must be a finite vector of length {d}, got {m0!r}")
        object.__setattr__(self, "A", A)
        object.__setattr__(self, "Q", _psd("Q", Q, d))
        object.__setattr__(self, "m0", mean)
        object.__setattr__(self, "P0", _psd("P0", P0, d))
        object.__setattr__(self, "_LQ", psd_factor(self.Q))
        object.__setattr__(self, "_L0", psd_factor(self.P0))

    @property
    def F(self) -> np.ndarray:
        """zheng2014's name for ``A`` (read-only alias)."""
        return self.A

    @property
    def dim(self) -> int:
        return self.A.shape[0]

    def initial(self, rng: np.random.Generator, n: int, P: int) -> np.ndarray:
        """``(n, P, d)`` draws from ``N(m0, P0)`` (no random numbers used when ``P0 = 0``)."""
        x = np.broadcast_to(self.m0, (n, P, self.dim)).copy()
        if self._L0.shape[1]:
            x += rng.standard_normal((n, P, self._L0.shape[1])) @ self._L0.T
        return x

    def transition(self, rng: np.random.Generator, t: int, x: np.ndarray) -> np.ndarray:
        """``A x + u`` for every particle; ``x (..., d)``. On an SFC64 or PCG64 (NumPy's
        default) stream the normals are drawn inside the compiled pass, NumPy's numbers bit for
        bit (:mod:`fusioncenter._ziggurat`)."""
        # stacked matmul: one small BLAS call per trial (a single (n P) x d product would be
        # split over BLAS threads, which is slow for d = 2 on a busy machine)
        k = self._LQ.shape[1]
        if (x.ndim == 3 and x.shape[1] >= 2 and x.shape[2] >= 2 and x.dtype == np.float64
                and x.flags.c_contiguous):
            # compiled: the arithmetic of BLAS dgemm (what matmul calls here) in one pass
            out = np.empty_like(x)
            bits = type(rng.bit_generator)
            draw = {np.random.SFC64: (_ziggurat.tables,
                                      _transition_kernels.linear_transition_draw),
                    np.random.PCG64: (_ziggurat.pcg64_tables,
                                      _transition_kernels.linear_transition_draw_pcg64),
                    }.get(bits) if k else None
            zig = draw[0]() if draw else None
            if zig is not None:  # NumPy's normals drawn inside the pass, in the same order
                st = _ziggurat.draw_state(rng)
                draw[1](x, self.A, self._LQ, st, *zig, out)
                _ziggurat.set_state(rng, st)
                return out
            g = rng.standard_normal((*x.shape[:-1], k)) if k else np.empty((*x.shape[:2], 0))
            _transition_kernels.linear_transition(x, self.A, g, self._LQ, out)
            return out
        out = x @ self.A.T
        if k:
            out += rng.standard_normal((*x.shape[:-1], k)) @ self._LQ.T
        return out


# ----------------------------------------------------------------------------- the loop
class FilterModel(Protocol):
    """What :func:`run_filter` needs from a model (see the module docstring).

    Attributes
    ----------
    dim : int
        The state dimension ``d``. The methods ``initial``, ``transition``, ``log_weight`` and
        ``observe`` are described in the module docstring.
    """

    dim: int

    def initial(self, rng: np.random.Generator, n: int, P: int) -> np.ndarray: ...

    def transition(self, rng: np.random.Generator, t: int, x: np.ndarray) -> np.ndarray: ...

    def log_weight(self, t: int, x: np.ndarray) -> np.ndarray: ...

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None: ...


@dataclass(frozen=True)
class FilterOutput:
    """Output of :func:`run_filter` for ``n`` trials and times ``t = 1..steps``.

    Attributes
    ----------
    mean : numpy.ndarray
        ``(n, steps, d)``: the weighted estimate of ``x_t`` given the data up to ``t`` (before
        resampling).
    cov : numpy.ndarray
        ``(n, steps, d, d)``: its weighted covariance; NaN unless the model ``needs_cov``.
    ess : numpy.ndarray
        ``(n, steps)``: effective sample size after weighting.
    log_evidence : numpy.ndarray
        ``(n,)``: ``sum_t log(mean_j w_{t,j})`` (the log-likelihood of the data under the
        weights' model, up to the constants the model dropped).
    collapsed : numpy.ndarray
        ``(n, steps)``, bool: no particle had positive weight (the step's data were ignored for
        that trial).
    """

    mean: np.ndarray
    cov: np.ndarray
    ess: np.ndarray
    log_evidence: np.ndarray
    collapsed: np.ndarray


def run_filter(model: FilterModel, rng: np.random.Generator, n_trials: int, n_particles: int,
               steps: int, *, ess_threshold: float = 1.0) -> FilterOutput:
    """The bootstrap particle filter (zheng2014 Algorithm 1, steps A1.3--A1.6) on ``n_trials``.

    The one sequential Monte Carlo loop of the library: every fusion centre is a model of it
    (:class:`FilterModel`). For ``t = 1..steps``: propagate every particle
    (``model.transition``), add ``model.log_weight(t, x)`` to the log weights, normalize, estimate
    the mean (and the covariance if ``model.needs_cov``), tell the model (``model.observe``), then
    resample (systematic, one uniform per trial) the trials whose ESS is at most
    ``ess_threshold * n_particles`` (``1.0``: every step whatever the ESS, as Algorithm 1 does;
    ``0.0``: never). The uniforms are drawn at every step for every trial whether used or not, so
    the random stream does not depend on the data.

    The hot pieces are compiled (:mod:`fusioncenter._kernels`): after subtracting each trial's
    maximum log weight and exponentiating, one pass per trial gives the weight sum, the weighted
    means and the ESS (:func:`fusioncenter._kernels.weighted_moments`), and one more systematic
    resampling fused with the gather (:func:`fusioncenter._kernels.resample_rows`: the
    ancestors of :func:`fusioncenter._kernels.systematic_ancestors`, without storing them).
    Everything is row by row: a trial's result
    does not depend on the other trials of the batch. A trial whose weights are all zero (no
    particle compatible with the data) keeps uniform weights for that step and is flagged in
    :attr:`FilterOutput.collapsed`.

    Random-number order per step: ``model.transition`` draws first, then ``u (n_trials,)``.

    Parameters
    ----------
    model : FilterModel
        Initial law, transition, log weights and the estimate's consumer (see the module
        docstring); ``model.dim`` is the state dimension ``d``.
    rng : numpy.random.Generator
        The filter's random stream (particles, resampling uniforms, whatever the model draws).
    n_trials, n_particles : int
        Independent trials ``n`` and particles per trial ``P`` (positive).
    steps : int
        Number of time steps (non-negative).
    ess_threshold : float, optional
        Resample a trial when its ESS is at most ``ess_threshold * n_particles``; in ``[0, 1]``.

    Returns
    -------
    FilterOutput
        Means ``(n, steps, d)``, covariances (NaN unless ``model.needs_cov``), ESS after
        weighting, log evidence and the collapsed flags.
    """
    for name, value in (("n_trials", n_trials), ("n_particles", n_particles)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
    if isinstance(steps, bool) or not isinstance(steps, int | np.integer) or steps < 0:
        raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
    if not 0.0 <= ess_threshold <= 1.0:
        raise ValueError(f"ess_threshold must lie in [0, 1], got {ess_threshold}")
    n, P, d = int(n_trials), int(n_particles), int(model.dim)
    need_cov = bool(getattr(model, "needs_cov", True))
    means = np.empty((n, steps, d))
    covs = np.full((n, steps, d, d), np.nan)
    esss = np.empty((n, steps))
    collapsed = np.zeros((n, steps), dtype=bool)
    log_ev = np.zeros(n)
    x = np.asarray(model.initial(rng, n, P))
    if x.dtype != np.float64:
        x = x.astype(float)
    if x.shape != (n, P, d):
        raise ValueError(f"model.initial returned shape {x.shape}, expected {(n, P, d)}")
    every_step = ess_threshold >= 1.0
    # log weights carried over from the last step for the trials not resampled (normalized),
    # 0 for the others; ``offset`` is log(sum of the carried weights) (log P after resampling)
    carried = None if every_step else np.zeros((n, P))
    offset = np.full(n, math.log(P))
    S, ess_b, mx = np.empty(n), np.empty(n), np.empty(n)
    mean = np.empty((n, d))
    spare = np.empty_like(x)  # the same memory layout as x (see by_component)
    all_rows = np.ones(n, dtype=bool)
    for t in range(1, steps + 1):
        x = model.transition(rng, t, x)
        if x.shape != (n, P, d):
            raise ValueError(f"model.transition returned shape {x.shape}, expected {(n, P, d)}")
        u = rng.random(n)
        lw = np.asarray(model.log_weight(t, x), dtype=float)
        if not (lw.flags.writeable and lw.flags.owndata):
            lw = lw.copy()  # normalized in place below
        if lw.shape != (n, P):
            raise ValueError(f"model.log_weight returned shape {lw.shape}, expected {(n, P)}")
        if carried is not None:
            lw += carried
        # lw -= its row maximum (rows of -inf, no particle compatible with the data, set to 0:
        # they are ignored), in one compiled pass: NumPy's max and subtraction, the same floats
        _kernels.shift_by_row_max(lw, mx)
        if not np.isfinite(mx.sum()) and (np.isnan(mx).any() or np.any(mx == np.inf)):
            raise ValueError("log weights must not be NaN or +inf")
        dead = mx == -np.inf
        if dead.any():
            mx[dead] = 0.0
        w = np.exp(lw, out=lw)
        _kernels.weighted_moments(w, x, S, mean, ess_b)
        collapsed[:, t - 1] = dead
        inc = np.log(S)
        inc += mx
        inc -= offset
        if dead.any():
            inc[dead] = 0.0
        log_ev += inc
        means[:, t - 1] = mean
        esss[:, t - 1] = ess_b
        cov = None
        if need_cov:
            dev = x - mean[:, None, :]
            cov = np.swapaxes(dev * (w / S[:, None])[..., None], -1, -2) @ dev
            cov = 0.5 * (cov + np.swapaxes(cov, -1, -2))
            covs[:, t - 1] = cov
        model.observe(t, mean.copy(), cov)
        todo = all_rows if every_step else ess_b <= ess_threshold * P
        if carried is not None:
            with np.errstate(divide="ignore"):
                carried = np.where(todo[:, None], 0.0, np.log(w / S[:, None]))
            offset = np.where(todo, math.log(P), 0.0)
        _kernels.resample_rows(w, S, u, todo, x, spare)
        x, spare = spare, x
    return FilterOutput(mean=means, cov=covs, ess=esss, log_evidence=log_ev, collapsed=collapsed)
