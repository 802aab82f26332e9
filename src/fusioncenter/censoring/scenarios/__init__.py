"""The scenarios of zheng2014 Part IV.

* :mod:`~fusioncenter.censoring.scenarios.common`: what every scenario shares (the
  :class:`Scenario` base, :data:`SCHEMES`, :data:`FEEDBACK`, :data:`LIKELIHOODS`, the checks of
  the common fields, the text of the ``choices``, the sensors' joint error recursion); the
  names the other modules use are re-exported here;
* :mod:`~fusioncenter.censoring.scenarios.linear`: the linear model of Section VII.A
  (:class:`LinearScenario`).

The vector and nonlinear scenarios are :class:`fusioncenter.censoring.vector.VectorScenario`
and :class:`fusioncenter.censoring.nonlinear_model.NonlinearScenario`. The tracking model
:func:`fusioncenter.models.wna_model` (defined once) is re-exported here too."""

from __future__ import annotations

from fusioncenter.censoring.scenarios.common import (
    FEEDBACK,
    LIKELIHOODS,
    SCHEME_CHOICES,
    SCHEMES,
    Scenario,
    groups_of_rows,
    nested_tuple,
    target_dynamics,
    values_text,
)
from fusioncenter.censoring.scenarios.linear import LinearScenario
from fusioncenter.models import wna_model

__all__ = [
    "FEEDBACK", "LIKELIHOODS", "SCHEMES", "SCHEME_CHOICES", "Scenario", "LinearScenario",
    "groups_of_rows", "nested_tuple", "target_dynamics", "values_text", "wna_model",
]
