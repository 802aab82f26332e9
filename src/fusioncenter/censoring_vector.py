"""Compatibility module: the vector-observation censoring of zheng2014 Part IV(b) now lives in
:mod:`fusioncenter.censoring.ellipse` (the silent probability), :mod:`fusioncenter.censoring.vector`
(the scenario), :mod:`fusioncenter.censoring.vector_likelihood` (Propositions 4-6) and
:mod:`fusioncenter.censoring.vector_fusion` (the fusion centre and ``run``);
this module re-exports their public names."""

from __future__ import annotations

from fusioncenter.censoring.ellipse import (
    FEEDBACK,
    LIKELIHOODS,
    PROBABILITIES,
    SCHEMES,
    censored_probability,
    eval_silent,
    grid_terms,
    log_canon,
    log_censored_probability,
    log_silent_probability,
    log_silent_table,
)
from fusioncenter.censoring.vector import (
    VectorScenario,
    local_decisions,
    log_all_silent,
    printed_mass,
    silent_covariance,
)
from fusioncenter.censoring.vector_fusion import run
from fusioncenter.censoring.vector_likelihood import (
    censored_probability_sampled,
    log_likelihood_feedback,
    log_likelihood_no_feedback_printed,
)

__all__ = [
    "SCHEMES", "FEEDBACK", "LIKELIHOODS", "PROBABILITIES", "log_censored_probability",
    "censored_probability", "censored_probability_sampled", "log_silent_probability",
    "log_likelihood_feedback", "log_likelihood_no_feedback_printed", "log_silent_table",
    "eval_silent", "grid_terms", "log_canon", "VectorScenario", "local_decisions",
    "log_all_silent", "printed_mass", "silent_covariance", "run",
]
