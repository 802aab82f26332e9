"""Paired runs: the per-trial results of one scheme (:class:`Summary`), from which the RMSE, the
send rate and the calibration follow with their standard errors, and the difference of two
schemes run on the same trials with its paired standard error
(``Summary.paired_difference``); :func:`summary_from_censoring` reads a run of
:func:`fusioncenter.censoring.run` the same way."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from fusioncenter import censoring, montecarlo
from fusioncenter.comparison._args import doc

__all__ = ["COLUMNS", "Summary", "summary_from_censoring"]

#: Columns of a per-trial summary: squared error of position and velocity, trace of the FC's
#: covariance (NaN for particle filters), number of sensors that sent, number whose packet
#: arrived.
COLUMNS = ("sq_pos", "sq_vel", "trace_P", "sent", "arrived")


@doc.attributes(label=("str", "The scheme (and link) it summarizes."),
                samples=("numpy.ndarray", "``(n_trials, T, 5)``, the columns :data:`COLUMNS`."))
@dataclass(frozen=True)
class Summary(montecarlo.PerTrial):
    """Per-trial results of one scheme; ``seed`` and ``block_size`` identify the trials: two
    summaries with equal ``seed``, ``block_size`` and ``n_trials`` are paired (same trials)."""

    label: str
    samples: np.ndarray = field(repr=False)
    seed: int
    block_size: int

    def _sq(self, component: str) -> np.ndarray:
        cols = {"position": [0], "velocity": [1], "state": [0, 1]}.get(component)
        if cols is None:
            raise ValueError(f"component must be 'position', 'velocity' or 'state', "
                             f"got {component!r}")
        return self.samples[..., cols].sum(axis=-1)  # (n, T)

    def _influence(self, component: str):
        sq = self._sq(component)
        rm = np.sqrt(sq.mean(axis=0))
        with np.errstate(divide="ignore", invalid="ignore"):
            infl = np.where(rm > 0, sq / (2 * rm), 0.0).mean(axis=1)
        return float(rm.mean()), infl

    @doc(returns=("value, stderr : float",
                  "The time-averaged RMSE and its standard error (NaN for a single trial)."))
    def tavg_rmse(self, component: str = "position") -> tuple[float, float]:
        """``mean_t sqrt(mean_trials e_t^2)`` and its standard error (delta method over trials,
        as :meth:`fusioncenter.censoring.CensoringResult.time_averaged_rmse`)."""
        value, infl = self._influence(component)
        return value, _se(infl)

    @doc(returns=("rmse, stderr : numpy.ndarray",
                  "``sqrt(mean_trials e_t^2)`` per step ``(T,)``, and its standard error by the "
                  "delta method (0 where the RMSE is 0)."))
    def rmse_k(self, component: str = "position") -> tuple[np.ndarray, np.ndarray]:
        """RMSE per step and its standard error, both ``(T,)``."""
        sq = self._sq(component)
        rm = np.sqrt(sq.mean(axis=0))
        se = sq.std(axis=0, ddof=1) / math.sqrt(sq.shape[0])
        with np.errstate(divide="ignore", invalid="ignore"):
            return rm, np.where(rm > 0, se / (2 * rm), 0.0)

    @doc(returns=("value, stderr : float",
                  "The mean over trials and steps, and its standard error across trials."))
    def rate(self, column: str = "sent") -> tuple[float, float]:
        """Average number of sensors per step that sent (or whose packet ``"arrived"``), with
        its standard error across trials."""
        j = {"sent": 3, "arrived": 4}.get(column)
        if j is None:
            raise ValueError(f"column must be 'sent' or 'arrived', got {column!r}")
        per = self.samples[..., j].mean(axis=1)
        return float(per.mean()), _se(per)

    def calibration(self) -> tuple[float, float]:
        """Mean over trials and steps of ``||x - xhat||^2 - tr P`` (0 for an exact filter), with
        its standard error; NaN for particle filters.

        Returns
        -------
        value, stderr : float
            The mean excess of the squared error over the filter's ``tr P``, and its standard
            error across trials.
        """
        per = (self._sq("state") - self.samples[..., 2]).mean(axis=1)
        return float(per.mean()), _se(per)

    @doc(returns=("difference, stderr : float",
                  "This summary's value minus ``other``'s, and the standard error of the "
                  "difference over the paired trials."),
         rate=("bool, default False",
               "Compare the number of sensors that sent per step instead of the RMSE."))
    def paired_difference(self, other: Summary, component: str = "position",
                          rate: bool = False) -> tuple[float, float]:
        """This summary's time-averaged RMSE (or, with ``rate=True``, transmissions per step)
        minus ``other``'s, with the paired standard error (trials differenced one by one)."""
        if not isinstance(other, Summary):
            raise ValueError("other must be a Summary")
        if not self.same_trials(other):
            raise ValueError("the two summaries are not paired (seed, block_size and n_trials "
                             "must agree)")
        if rate:
            a, b = self.samples[..., 3].mean(axis=1), other.samples[..., 3].mean(axis=1)
            return float(a.mean() - b.mean()), _se(a - b)
        va, ia = self._influence(component)
        vb, ib = other._influence(component)
        return va - vb, _se(ia - ib)


def _se(per: np.ndarray) -> float:
    return float(per.std(ddof=1) / math.sqrt(per.size)) if per.size > 1 else math.nan


@doc(returns=("Summary", "Labelled with the result's scheme; ``trace_P`` is NaN."),
     result=("fusioncenter.censoring.CensoringResult", "A run of the particle-filter family."))
def summary_from_censoring(result) -> Summary:
    """A :class:`Summary` of a :class:`fusioncenter.censoring.CensoringResult` (its documented
    ``mc.samples`` columns ``[sq error (2) | sensors that sent | ESS | collapsed]``); every
    packet arrives (a perfect link)."""
    if not isinstance(result, censoring.CensoringResult):
        raise ValueError("result must be a fusioncenter.censoring.CensoringResult")
    s = result.mc.samples
    out = np.empty(s.shape[:2] + (len(COLUMNS),))
    out[..., 0:2] = s[..., 0:2]
    out[..., 2] = np.nan
    out[..., 3] = s[..., 2]
    out[..., 4] = s[..., 2]
    return Summary(label=result.scheme, samples=out, seed=result.mc.seed,
                   block_size=result.mc.block_size)
