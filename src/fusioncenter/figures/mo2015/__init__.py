"""Part I (mo2015): the book's own figures on the stochastic event trigger.

The notes have no figures; these three entries check their formulas and extend them:

* ``mo2015-rate`` (:mod:`~fusioncenter.figures.mo2015.rate`): the communication rate against the
  trigger parameter ``delta``, in closed form (the notes' zero-mean formula and our extension to
  a non-zero prior mean) and by simulation.
* ``mo2015-tradeoff`` (:mod:`~fusioncenter.figures.mo2015.tradeoff`): mean squared error against
  communication rate for a static 2-state, 3-sensor example: stochastic trigger vs random
  selection at the same rate vs all-send, with exact curves (pattern probabilities in closed
  form) and Monte Carlo points.
* ``mo2015-tracking`` (:mod:`~fusioncenter.figures.mo2015.event_kf`): the event-triggered Kalman
  filter on the tracking model of zheng2014, Section VII.A: RMSE against average transmissions
  per step.

The static example and the closed forms that the figures need and the library does not (yet)
provide (the joint probability of a transmission pattern, the exact expected trace of the
posterior covariance under each scheduler, the posterior of a centre that simply drops silent
sensors) are in :mod:`~fusioncenter.figures.mo2015.static`. Importing the package registers the
three entries; the names the chapters use (``mo2015.example``, ``mo2015.tracking``, ...) are
re-exported here.
"""

from __future__ import annotations

from fusioncenter.figures.mo2015.static import (
    EXAMPLE,
    Z_TOL,
    all_silent_probability,
    conditional_chunk,
    draw_example,
    drop_covariances,
    drop_posterior,
    example,
    expected_trace_random,
    expected_trace_stochastic,
    output_variances,
    pattern_code,
    pattern_covariances,
    pattern_probabilities,
    patterns,
)

# isort: off
# (the registration order is the order of the entries in the registry)
from fusioncenter.figures.mo2015.rate import (  # registers mo2015-rate
    CHAPTER_RATE,
    RATE_DELTAS,
    RATE_TRIALS,
    SETTABLE_RATE,
    checks_rate,
    compute_rate,
    plot_rate,
)
from fusioncenter.figures.mo2015.tradeoff import (  # registers mo2015-tradeoff
    CHAPTER_CM,
    SETTABLE_TRADEOFF,
    TRADEOFF_RATES,
    TRADEOFF_TRIALS,
    checks_tradeoff,
    compute_tradeoff,
    plot_tradeoff,
    tradeoff_deltas,
)
from fusioncenter.figures.mo2015.event_kf import (  # registers mo2015-tracking
    CALIBRATION_TRIALS,
    CHAPTER_KF,
    SETTABLE_TRACKING,
    TRACKING,
    TRACKING_TRIALS,
    checks_tracking,
    compute_tracking,
    plot_tracking,
    tracking,
)
# isort: on

#: The book's own figures that this package registers (the notes have no figures of their own).
OWN_IDS = ("mo2015-rate", "mo2015-tradeoff", "mo2015-tracking")

__all__ = [
    "CALIBRATION_TRIALS",
    "CHAPTER_CM",
    "CHAPTER_KF",
    "CHAPTER_RATE",
    "EXAMPLE",
    "OWN_IDS",
    "RATE_DELTAS",
    "RATE_TRIALS",
    "SETTABLE_RATE",
    "SETTABLE_TRACKING",
    "SETTABLE_TRADEOFF",
    "TRACKING",
    "TRACKING_TRIALS",
    "TRADEOFF_RATES",
    "TRADEOFF_TRIALS",
    "Z_TOL",
    "all_silent_probability",
    "checks_rate",
    "checks_tracking",
    "checks_tradeoff",
    "compute_rate",
    "compute_tracking",
    "compute_tradeoff",
    "conditional_chunk",
    "draw_example",
    "drop_covariances",
    "drop_posterior",
    "example",
    "expected_trace_random",
    "expected_trace_stochastic",
    "output_variances",
    "pattern_code",
    "pattern_covariances",
    "pattern_probabilities",
    "patterns",
    "plot_rate",
    "plot_tracking",
    "plot_tradeoff",
    "tracking",
    "tradeoff_deltas",
]
