"""Interpolation tables of smooth log-probabilities, evaluated at many particles.

:class:`LogTable` (fixed nodes, one polynomial per interval, compiled evaluation),
:func:`interp_rows` (one function per row), and the cached tables of the linear fusion centre."""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter._compiled import log_table
from fusioncenter._compiled.bivariate_normal import log_region_probability
from fusioncenter._compiled.censored_normal import prob_inside

# ----------------------------------------------------------------------------- tables, the FC model
#: The tables cover ``|x| < 48`` (beyond, the exact function is evaluated).
TABLE_EXTENT = 48.0


class LogTable:
    """A smooth log-probability ``f(x)`` tabulated for fast evaluation at many particles.

    ``f`` is evaluated exactly at the fixed nodes ``x_k = k * step``; on ``[x_j, x_{j+1})`` the
    table holds the polynomial of degree ``degree`` (odd) through the ``degree + 1`` nodes
    around the interval (Horner form in ``x / step - j``). The interpolation error is about
    ``C step^(degree+1) max |f^(degree+1)|`` (``C = 0.014`` for cubics, ``0.005`` for quintics):
    below ``5e-12`` in absolute value for :func:`silent_table` and ``1e-10`` for
    :func:`region_table`, except at the first step of the no-feedback filter with a known
    ``x_0`` (large high derivatives: up to ``5e-8``; checked against ``f`` itself in the tests),
    far below any Monte Carlo effect. The value at ``x`` depends only
    on ``f`` at the nodes around it, never on which other points are evaluated, so a trial's
    weights do not depend on the other trials. Outside ``|x| < 48`` and on intervals with a
    non-finite node, ``f`` is evaluated exactly. ``even=True``: ``f(-x) = f(x)``, tabulated on
    ``[0, 48)``.

    Parameters
    ----------
    fn : callable
        ``f``, elementwise on arrays.
    even : bool
        ``f(-x) = f(x)``: tabulate ``[0, 48)`` only.
    step : float
        Node spacing.
    degree : int
        Odd polynomial degree.
    """

    def __init__(self, fn, *, even: bool, step: float, degree: int):
        self.fn, self.even, self.step = fn, even, step
        kmax = int(round(TABLE_EXTENT / step))
        self.k0 = 0 if even else -kmax
        self.n_int = kmax - self.k0
        lo = -(degree // 2)  # nodes j + lo .. j + lo + degree
        vinv = _vinv(degree)
        k = np.arange(self.k0 + lo, kmax + lo + degree + 1)
        vals = np.asarray(fn(k * step), dtype=float)
        win = np.lib.stride_tricks.sliding_window_view(vals, degree + 1)[: self.n_int]
        coef = win @ vinv.T  # (n_int, degree + 1): increasing powers
        finite = np.all(np.isfinite(win), axis=1)
        coef[~finite] = np.nan  # evaluated exactly instead
        self.all_finite = bool(finite.all())
        self.coef = np.ascontiguousarray(coef[:, ::-1])  # Horner order

    def __call__(self, x: np.ndarray) -> np.ndarray:
        t = np.abs(x) if self.even else x - self.k0 * self.step
        t *= 1.0 / self.step
        return self._finish(t, lambda far: x[far])

    def shifted(self, y: np.ndarray, shift: np.ndarray, scale: float,
                work: np.ndarray) -> np.ndarray:
        """``f((y - shift[:, None]) * scale)`` for an even table, using ``work`` (the shape of
        ``y``) as scratch (saves three array passes over ``__call__``).

        Parameters
        ----------
        y : numpy.ndarray
            Points ``(rows, P)``.
        shift : numpy.ndarray
            One shift per row ``(rows,)``.
        scale : float
            Factor applied after the shift.
        work : numpy.ndarray
            Scratch of the shape of ``y``; it receives the result.

        Returns
        -------
        numpy.ndarray
            ``work``, holding the values.
        """
        out = work
        if log_table.table_shifted(self.coef, self.n_int, y, shift, scale / self.step, out):
            far = np.isnan(out)  # beyond the table, or an interval with a non-finite node
            out[far] = self.fn((y - shift[:, None])[far] * scale)
        return out

    def shifted_add(self, y: np.ndarray, shift: np.ndarray, scale: float, ns: np.ndarray,
                    out: np.ndarray, work: np.ndarray, gauss: tuple | None = None) -> None:
        """``out += where(ns == 0, 0, f((y - shift[:, None]) * scale) * ns[:, None])`` for an
        even table (no product where ``ns = 1``), in one compiled pass per row
        (:func:`fusioncenter._compiled.log_table.table_shifted_add`); the rows with a point
        beyond the table go through :meth:`shifted` (``work`` as scratch, the shape of ``y``),
        so every value is the arithmetic of :meth:`shifted` followed by the product and the sum.
        ``gauss = (zbar, coef, add)``: first, in the same call, the received sensors' terms of
        :func:`fusioncenter._compiled.log_table.gauss_terms` (written to ``out`` or added to
        it), row by row (:func:`fusioncenter._compiled.log_table.gauss_table_add`; the same
        floats as the two calls).

        Parameters
        ----------
        y, shift, scale
            As in :meth:`shifted`.
        ns : numpy.ndarray
            Per row, how many times the factor counts (integers ``(rows,)``).
        out : numpy.ndarray
            Log weights ``(rows, P)``, added to (or written, see ``gauss``).
        work : numpy.ndarray
            Scratch of the shape of ``y``.
        gauss : tuple, optional
            ``(zbar, coef, add)`` of the received sensors' terms, or ``None``.
        """
        rows = np.empty(y.shape[0], dtype=np.intp)
        if gauss is None:
            k = log_table.table_shifted_add(self.coef, self.n_int, y, shift, scale / self.step,
                                            ns, out, rows)
        else:
            k = log_table.gauss_table_add(self.coef, self.n_int, y, shift, scale / self.step, ns,
                                          out, rows, *gauss)
        if k:
            rows = rows[:k]
            val = self.shifted(y[rows], shift[rows], scale, work[:k])
            nsr = ns[rows]
            if np.any(nsr > 1):
                val *= nsr[:, None]
            out[rows] += val

    def _finish(self, t: np.ndarray, exact_x) -> np.ndarray:
        """Interpolate at ``t = (x - x_k0) / step`` (overwritten); ``exact_x(mask)`` gives the
        arguments where the exact function is needed."""
        j = t.astype(np.intp)
        t -= j
        c = np.take(self.coef, j, axis=0, mode="clip")  # (..., degree + 1)
        out = np.multiply(c[..., 0], t)
        out += c[..., 1]
        for i in range(2, c.shape[-1]):
            out *= t
            out += c[..., i]
        far = j >= self.n_int
        if not self.even:
            far |= j < 0
            far |= t < 0  # x below the table (astype truncates towards zero)
        if not self.all_finite:
            far |= np.isnan(out)
        if far.any():
            out[far] = self.fn(exact_x(far))
        return out


def interp_rows(fn, c: np.ndarray, *, step: float = 1.0 / 16, degree: int = 7) -> np.ndarray:
    """``f_b(c[b, j])`` for every row ``b`` of ``c (rows, P)``, interpolated like
    :class:`LogTable` from exact values at the fixed nodes ``k * step`` that a row's particles
    need (``fn(row_indices, x)`` evaluates ``f_b(x)`` elementwise). Degree 7 on a 1/16 grid:
    error about ``0.002 step^8 max |f^(8)|`` (below 1e-11 here, checked in the tests). Used
    when each row has its own function of one variable; a row's values depend only on its own
    function and particles. Points whose nodes include a non-finite value are evaluated exactly.

    Parameters
    ----------
    fn : callable
        ``fn(rows, x)``: the row's function at the points ``x`` (elementwise).
    c : numpy.ndarray
        Points ``(rows, P)``.
    step : float, optional
        Node spacing.
    degree : int, optional
        Odd polynomial degree.

    Returns
    -------
    numpy.ndarray
        ``f_b(c[b, j])`` ``(rows, P)``.
    """
    rows_n = c.shape[0]
    lo = -(degree // 2)
    vinv = _vinv(degree)
    kmin = np.floor(c.min(axis=1) / step).astype(np.intp)
    kmax = np.floor(c.max(axis=1) / step).astype(np.intp)
    n_node = kmax - kmin + 1 + degree  # nodes kmin + lo .. kmax + lo + degree
    start = np.concatenate([[0], np.cumsum(n_node)[:-1]])
    owner = np.repeat(np.arange(rows_n), n_node)
    k = np.arange(int(n_node.sum())) - np.repeat(start - (kmin + lo), n_node)
    vals = np.asarray(fn(owner, k * step), dtype=float)
    win = np.lib.stride_tricks.sliding_window_view(vals, degree + 1)
    coef = np.ascontiguousarray((win @ vinv.T)[:, ::-1])
    t = c / step
    kk = np.floor(t)
    t -= kk
    idx = start[:, None] + (kk.astype(np.intp) - kmin[:, None])
    cf = np.take(coef, idx, axis=0)
    out = np.multiply(cf[..., 0], t)
    out += cf[..., 1]
    for i in range(2, degree + 1):
        out *= t
        out += cf[..., i]
    if not np.all(np.isfinite(vals)):
        bad = ~np.all(np.isfinite(np.take(win, idx, axis=0)), axis=-1)
        if bad.any():
            rb = np.broadcast_to(np.arange(rows_n)[:, None], c.shape)[bad]
            out[bad] = fn(rb, c[bad])
    return out


@functools.lru_cache(maxsize=8)
def _vinv(degree: int) -> np.ndarray:
    """Maps the values at the nodes ``lo .. lo + degree`` (``lo = -(degree // 2)``) to the
    coefficients (increasing powers) of the interpolating polynomial."""
    lo = -(degree // 2)
    offsets = np.arange(lo, lo + degree + 1).astype(float)
    return np.linalg.inv(np.vander(offsets, degree + 1, increasing=True))


@functools.lru_cache(maxsize=256)
def silent_table(h: float) -> LogTable:
    """``m -> log P(|Z + m| < h)``: the silent factor of Propositions 1-2 in units of ``sd``.

    Parameters
    ----------
    h : float
        Half-width in standard deviations.

    Returns
    -------
    LogTable
        The even table of ``m -> log P(|Z + m| < h)`` (cached).
    """
    return LogTable(lambda m: prob_inside(m, h, log=True), even=True, step=1.0 / 256, degree=3)


@functools.lru_cache(maxsize=256)
def region_table(a: tuple, cov: tuple, outside: tuple, which: int) -> LogTable:
    """``c -> log P(region)`` of :func:`log_region_probability` with component ``which`` of the
    mean at ``c`` and the others at 0 (Proposition 3 corrected, one sensor received).

    Parameters
    ----------
    a : tuple of float
        Half-widths ``(K,)``.
    cov : tuple of tuple of float
        Covariance ``(K, K)`` of ``W``.
    outside : tuple of bool
        Per component, outside (``True``) or inside.
    which : int
        The component whose mean is the table's argument.

    Returns
    -------
    LogTable
        The table of ``c -> log P(region)`` (cached).
    """
    a_arr, cov_arr = np.array(a), np.array(cov)

    def fn(c):
        mean = np.zeros((*np.shape(c), len(a)))
        mean[..., which] = c
        return log_region_probability(mean, cov_arr, a_arr, outside)

    return LogTable(fn, even=False, step=1.0 / 32, degree=5)
