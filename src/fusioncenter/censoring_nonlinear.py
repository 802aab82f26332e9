"""Compatibility module: the nonlinear tracker of zheng2014 Sections VI and VII.C now lives in
:mod:`fusioncenter.censoring.nonlinear`; this module re-exports its public names."""

from __future__ import annotations

from fusioncenter.censoring.nonlinear import (
    FEEDBACK,
    SCHEMES,
    SILENT_STEP,
    NonlinearScenario,
    amplitude,
    ekf_covariance_step,
    grid_positions,
    jacobian,
    local_ekf,
    log_likelihood,
    log_silent_probability,
    run,
    silent_terms,
)

__all__ = [
    "SCHEMES", "FEEDBACK", "SILENT_STEP", "NonlinearScenario", "amplitude", "ekf_covariance_step",
    "grid_positions", "jacobian", "local_ekf", "log_likelihood", "log_silent_probability", "run",
    "silent_terms",
]
