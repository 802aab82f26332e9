"""The fusion-centre models of the linear scenario for :func:`fusioncenter.particle.run_filter`,
and what every fusion centre shares.

* :mod:`~fusioncenter.censoring.fusion.base`: the four methods the loop calls
  (:class:`FusionCentreModel`), the bases :class:`ReferenceFC`, :class:`FeedbackModel` and
  :class:`ExactModel` the vector and nonlinear models build on, and the sensors' decisions every
  scheme shares (:func:`decisions_in_advance`, :func:`silent_rows`);
* :mod:`~fusioncenter.censoring.fusion.linear`: :class:`LinearFusionCentre` (every scheme),
  organized for speed, and its :func:`sub_blocks`;
* :mod:`~fusioncenter.censoring.fusion.exact`: :class:`ExactFusionCentre` (the exact
  no-feedback filter).

The names below are re-exported here."""

from __future__ import annotations

from fusioncenter.censoring.fusion.base import (
    ExactModel,
    FeedbackModel,
    FusionCentreModel,
    ReferenceFC,
    decisions_in_advance,
    silent_rows,
)
from fusioncenter.censoring.fusion.exact import ExactFusionCentre
from fusioncenter.censoring.fusion.linear import LinearFusionCentre, sub_blocks

__all__ = [
    "FusionCentreModel", "ReferenceFC", "FeedbackModel", "ExactModel", "decisions_in_advance",
    "silent_rows", "ExactFusionCentre", "LinearFusionCentre", "sub_blocks",
]
