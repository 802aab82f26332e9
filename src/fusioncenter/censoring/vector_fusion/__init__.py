"""The fusion centres of the vector scenario for :func:`fusioncenter.particle.run_filter`, and
its ``run`` (zheng2014 Section V; Figs. 4-6, Table II).

* :mod:`~fusioncenter.censoring.vector_fusion.reference`: the reference models
  :class:`VectorFC` and :class:`VectorExactFC` (the silent factor by tables, quadrature or
  sampling at every particle) and the imputation of a silent measurement
  (:func:`sample_in_ellipse`);
* :mod:`~fusioncenter.censoring.vector_fusion.fused`: :class:`FusedVectorFC`, the same model
  with the tables, organized for speed (the default);
* :mod:`~fusioncenter.censoring.vector_fusion.simulation`: ``run``, the Monte Carlo run.

The names below are re-exported here."""

from __future__ import annotations

from fusioncenter.censoring.vector_fusion.fused import FusedVectorFC
from fusioncenter.censoring.vector_fusion.reference import (
    VectorExactFC,
    VectorFC,
    sample_in_ellipse,
)
from fusioncenter.censoring.vector_fusion.simulation import run

__all__ = ["VectorFC", "VectorExactFC", "FusedVectorFC", "sample_in_ellipse", "run"]
