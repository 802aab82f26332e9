"""The likelihoods of what the fusion centre receives (zheng2014 Propositions 1-3).

See :mod:`fusioncenter.censoring` for the erratum of Proposition 3 and its correction."""

from __future__ import annotations

import numpy as np

from fusioncenter._compiled import censored_normal
from fusioncenter._compiled.bivariate_normal import log_region_probability, log_silent_constant
from fusioncenter._validate import broadcast as _broadcast
from fusioncenter._validate import covariance as _covariance
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive
from fusioncenter._validate import received as _received


# ----------------------------------------------------------------------------- likelihoods
def log_gauss(z, mean, r):
    """The Gaussian log density ``log N(z; mean, r)`` (all constants kept).

    Parameters
    ----------
    z, mean, r : array_like
        Value, mean and variance (broadcast).

    Returns
    -------
    numpy.ndarray
        ``log N(z; mean, r)``.

    Raises
    ------
    ValueError
        If ``z`` or ``mean`` is not finite, or ``r`` is not a positive finite variance.
    """
    z, mean = _finite("z", z), _finite("mean", mean)
    return censored_normal.log_gauss(z, mean, _positive("r", r))


def check_feedback_arguments(sent, z, hx, hx_pred, s, r, eta) -> tuple:
    """The arguments of a likelihood with feedback, checked and converted: those of
    :func:`log_likelihood_feedback` (Propositions 1-2) and of
    :func:`fusioncenter.censoring.nonlinear.log_likelihood` (Propositions 7-8).

    Parameters
    ----------
    sent, z, hx, hx_pred, s, r, eta : array_like
        As in :func:`log_likelihood_feedback` (``eta`` a number).

    Returns
    -------
    tuple
        ``(sent, z, hx, hx_pred, s, r, eta)``: ``sent`` as bool, ``eta`` as a float, the others
        as float arrays (not broadcast).

    Raises
    ------
    ValueError
        Naming the argument that is not finite (``z`` only where a sensor sent), negative
        (``r``: not positive), or whose shape does not broadcast with the others.
    """
    sent, z = _received(sent, z)
    hx = _finite("hx", hx)
    hx_pred = _finite("hx_pred", hx_pred)
    r = _positive("r", r)
    s = _nonneg("s", s, "a variance")
    eta = float(_nonneg("eta", eta, "a threshold"))
    _broadcast(sent=sent, z=z, hx=hx, hx_pred=hx_pred, s=s, r=r)
    return sent, z, hx, hx_pred, s, r, eta


def log_likelihood_feedback(sent, z, hx, hx_pred, s, r, eta):
    """Propositions 1 and 2: ``log p(z_obs, m | x, xhat_{k|k-1})`` with feedback.

    ``sum_{received} log N(z^i; h_i^T x, r_i) + sum_{silent} log P(|nu^i| < sqrt(eta s_i))``,
    ``nu^i ~ N(h_i^T (x - xhat_{k|k-1}), r_i)``. Shapes broadcast: ``sent`` (bool) and ``z``
    ``(..., N)`` (``z`` is ignored where not sent), ``hx = h_i^T x`` ``(..., N)``,
    ``hx_pred = h_i^T xhat_{k|k-1}``, ``s`` (the local ``s_k^i`` for Proposition 1, the
    covariance-feedback ``s'^i_k`` for Proposition 2), ``r`` ``(N,)``; returns ``(...)``.

    As a density on the outcomes it integrates to one: a sent ``z^i`` can only lie in the send
    region ``|z^i - h_i^T xhat| >= sqrt(eta s_i)``, where the printed ``[p(z^i | x)]^{m^i}`` is
    the density of ``(m^i = 1, z^i)`` (the indicator is 1 on every possible outcome).

    Parameters
    ----------
    sent : array_like
        Who sent, bool ``(..., N)``.
    z, hx, hx_pred : array_like
        Measurements, ``h_i^T x`` and ``h_i^T xhat_{k|k-1}``, ``(..., N)``.
    s, r : array_like
        Normalizing and noise variances ``(N,)`` (``r > 0``, ``s >= 0``).
    eta : float
        Threshold, ``>= 0``.

    Returns
    -------
    numpy.ndarray
        The log likelihood ``(...)``.

    Raises
    ------
    ValueError
        From :func:`check_feedback_arguments`, which checks the arguments.
    """
    sent, z, hx, hx_pred, s, r, eta = check_feedback_arguments(sent, z, hx, hx_pred, s, r, eta)
    recv = np.where(sent, censored_normal.log_gauss(np.where(sent, z, 0.0), hx, r), 0.0)
    sd = np.sqrt(r)
    with np.errstate(invalid="ignore"):
        sil = np.where(sent, 0.0, censored_normal.prob_inside((hx - hx_pred) / sd,
                                                              np.sqrt(eta * s) / sd, log=True))
    return (recv + sil).sum(axis=-1)


def log_likelihood_no_feedback(sent, z, hx, C, r, eta, *, version: str = "corrected"):
    """Proposition 3: ``log p(m, z_obs | x)`` without feedback, under the paper's law (21)-(23).

    ``C (N, N)``: covariance of the local prediction errors in measurement space,
    ``C_ij = h_i^T Sigma^{ij}_{k|k-1} h_j`` (``C_ii = s_i - r_i``); ``s_i = C_ii + r_i``,
    ``a_i = sqrt(eta s_i)``. ``sent``, ``z``, ``hx`` as in :func:`log_likelihood_feedback`.

    * ``"printed"``: eq. (16) as printed, ``sum_{received} log N(z^i; h_i^T x, r_i) +
      log P(|V_j| < a_j for the silent j)`` with ``V_j = eps_j + n^j``: the second term does not
      depend on ``x`` (see the module docstring); any ``N``. Does not sum to one.
    * ``"corrected"``: the received sensors' conditions ``|U_i| >= a_i``,
      ``U_i = z^i - h_i^T x + eps_i``, are kept; a bivariate normal rectangle probability;
      ``N <= 2``. Sums to one.

    Parameters
    ----------
    sent, z, hx : array_like
        Who sent, the measurements and ``h_i^T x`` ``(..., N)``.
    C : array_like
        ``(N, N)``, as above: a covariance (symmetric PSD).
    r : array_like
        Noise variances, ``> 0``.
    eta : float
        Threshold, ``>= 0``.
    version : str, optional
        ``"corrected"`` or ``"printed"``.

    Returns
    -------
    numpy.ndarray
        ``log p(m, z_obs | x)`` ``(...)``.
    """
    if version not in ("corrected", "printed"):
        raise ValueError(f"version must be 'corrected' or 'printed', got {version!r}")
    sent, z = _received(sent, z)
    hx = _finite("hx", hx)
    N = hx.shape[-1]
    r = np.broadcast_to(_positive("r", r), (N,))
    eta = float(_nonneg("eta", eta))
    C = _finite("C", C)
    if C.shape != (N, N):
        raise ValueError(f"C must be ({N}, {N}), got {C.shape}")
    _covariance("C", C)  # symmetric PSD: its diagonal is a variance (a square root is taken)
    if version == "corrected" and N > 2:
        raise ValueError(f"the corrected no-feedback likelihood is implemented for N <= 2 "
                         f"sensors (a bivariate normal probability), got N = {N}")
    sent, z, hx = _broadcast(sent=sent, z=z, hx=hx)
    recv = np.where(sent, censored_normal.log_gauss(np.where(sent, z, 0.0), hx, r),
                    0.0).sum(axis=-1)
    region = no_feedback_region(sent, z, hx[..., None, :], C, r, eta, version)[..., 0]
    return recv + region


def no_feedback_region(sent, z, hx, C, r, eta, version):
    """The non-Gaussian factor of Proposition 3 (printed or corrected); no checks.

    ``sent`` (bool) and ``z``: ``(..., N)``, one pattern per row (a trial); ``hx``:
    ``(..., P, N)`` for ``P`` particles. Returns ``(..., P)``. Patterns are handled one at a
    time on the rows that have them.

    Parameters
    ----------
    sent : numpy.ndarray
        Who sent, bool ``(..., N)``.
    z : numpy.ndarray
        Measurements ``(..., N)`` (ignored where not sent).
    hx : numpy.ndarray
        ``h_i^T x`` per particle, ``(..., P, N)``.
    C : numpy.ndarray
        Covariance ``(N, N)`` of the local prediction errors in measurement space.
    r : numpy.ndarray
        Noise variances ``(N,)``.
    eta : float
        Threshold.
    version : str
        ``"corrected"`` or ``"printed"``.

    Returns
    -------
    numpy.ndarray
        The log factor ``(..., P)``.
    """
    N = hx.shape[-1]
    s = np.diag(C) + r
    a = np.sqrt(eta * s)
    out = np.zeros(hx.shape[:-1])
    for pat in np.unique(sent.reshape(-1, N), axis=0):
        rows = np.all(sent == pat, axis=-1)  # (lead,)
        silent = np.flatnonzero(~pat)
        if version == "printed":
            if silent.size:
                Vcov = C[np.ix_(silent, silent)] + np.diag(r[silent])
                out[rows] += log_silent_constant(Vcov, a[silent])
            continue
        cov = C + np.diag(np.where(pat, 0.0, r))  # V_j = eps_j + n^j adds r_j
        if not pat.any():  # all silent: a constant in x
            out[rows] += log_silent_constant(cov, a)
            continue
        # U_i has mean z^i - h_i^T x (per particle), V_j mean 0
        mean = np.where(pat, z[rows][..., None, :] - hx[rows], 0.0)
        out[rows] += log_region_probability(mean, cov, a, pat)
    return out
