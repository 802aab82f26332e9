"""The linear fusion centre's bookkeeping of a step, compiled: the sensors' decisions with
feedback and, per group of equal sensors, the received mean, count and silent count
(:class:`fusioncenter.censoring.fusion.LinearFusionCentre`), with NumPy's arithmetic in its
order, so that the filter's results are those of the NumPy expressions they replace."""

from __future__ import annotations

import numba

#: Largest group of sensors whose sum :func:`group_stats` forms as NumPy does: NumPy's
#: ``sum(axis=1)`` over a row of at most 7 numbers adds them left to right (8 and more:
#: pairwise, with 8 accumulators; the caller keeps NumPy for those).
GROUP_SUM_MAX = 7


@numba.njit(cache=True, nogil=True)
def censor_decisions(z, k, hx, s, eta, sent):
    """The sensors' decisions at step ``k`` with feedback: ``sent[b, k, i] = (z[b, k, i] -
    hx[b, i])^2 >= eta * s[b, i]`` (``s``: ``(n, N)`` or ``(1, N)``): the NumPy expression
    ``nu * nu >= eta * s`` of ``censoring.fusion``, element by element, in its order.

    Parameters
    ----------
    z : numpy.ndarray
        Measurements ``(n, T, N)``.
    k : int
        The step.
    hx : numpy.ndarray
        The fed-back predicted measurements ``(n, N)``.
    s : numpy.ndarray
        Innovation variances ``(n, N)`` or ``(1, N)``.
    eta : float
        Censoring threshold.
    sent : numpy.ndarray
        Boolean decisions ``(n, T, N)``; step ``k`` is written.

    Returns
    -------
    None
    """
    n, N = hx.shape
    one = s.shape[0] == 1
    for b in range(n):
        sb = 0 if one else b
        for i in range(N):
            e = z[b, k, i] - hx[b, i]
            sent[b, k, i] = e * e >= eta * s[sb, i]


@numba.njit(cache=True, nogil=True)
def group_stats(sent, z, k, g, c, zbar, coef, n_sil):
    """For the group of sensors ``g`` (at most :data:`GROUP_SUM_MAX`) at step ``k``, per row
    ``b``: the mean of the received measurements ``zbar[b]`` (0 if none), ``coef[b] = c *
    n_obs`` and ``n_sil[b] = len(g) - n_obs``, with the NumPy arithmetic of ``censoring.fusion``
    (``where(sent, z, 0).sum(axis=1) / maximum(n_obs, 1)``, the sum left to right from +0.0),
    and how many rows have a received sensor and how many a silent one.

    Parameters
    ----------
    sent : numpy.ndarray
        Boolean decisions ``(n, T, N)``.
    z : numpy.ndarray
        Measurements ``(n, T, N)``.
    k : int
        The step.
    g : numpy.ndarray
        The group's sensor indices (int64), at most :data:`GROUP_SUM_MAX`.
    c : float
        ``-1 / (2 r)`` of the group.
    zbar, coef : numpy.ndarray
        ``(n,)`` float outputs.
    n_sil : numpy.ndarray
        ``(n,)`` int64 output.

    Returns
    -------
    tuple of int
        The numbers of rows with a received sensor and with a silent one.
    """
    n = sent.shape[0]
    m = g.shape[0]
    any_obs = 0
    any_sil = 0
    for b in range(n):
        cnt = 0
        acc = 0.0
        for j in range(m):
            i = g[j]
            v = z[b, k, i] if sent[b, k, i] else 0.0
            acc = acc + v  # from +0.0, as NumPy's reduction (a lone -0.0 sums to +0.0)
            cnt += 1 if sent[b, k, i] else 0
        zbar[b] = acc / max(cnt, 1)
        coef[b] = c * cnt
        n_sil[b] = m - cnt
        any_obs += 1 if cnt > 0 else 0
        any_sil += 1 if cnt < m else 0
    return any_obs, any_sil
