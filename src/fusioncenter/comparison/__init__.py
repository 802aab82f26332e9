"""One tracking problem, four ideas: the schemes of Parts I-IV on the same data, over a faded link.

What the other modules cannot express, and only that:

* the Kalman-filter family (all-send, random selection, mo2015's stochastic trigger with its
  exact filter) run on *given* data, so that it can be paired trial by trial with
  :func:`fusioncenter.censoring.run` (the particle-filter family of zheng2014);
* a packet link with Rayleigh block fading between each sensor and the fusion centre (FC), for
  both families, with two receivers: one that knows the channel gains (dey2009's channel-state
  information at the receiver) and a naive one that reads every missing packet as silence.

The model is :class:`fusioncenter.censoring.LinearScenario` (zheng2014 Section VII.A). Time runs
``t = 1..T``; ``x_0`` is the prior mean (known when ``P0 = 0``), as in ``censoring``.

The link. Sensor ``i``'s packet at step ``t`` goes through a channel whose power gain
``g = h^2`` is exponential with mean ``1 / lam`` (Rayleigh fading, dey2009 Section 3.1.1;
:class:`fusioncenter.fading.Rayleigh`), drawn independently per sensor and step (block fading). A
packet is decoded iff ``g >= g_th``: the outage probability is
``eps = P(g < g_th) = 1 - exp(-lam g_th)`` (:func:`outage_threshold` inverts it). Transmit power
enters only through ``g_th`` (a receiver needs ``g P / sigma_n^2 >= theta``, so ``g_th = theta
sigma_n^2 / P``): spending the same average energy on fewer packets lowers their outage,
``eps(rate) = 1 - (1 - eps_1)^rate`` (:func:`energy_matched_outage`).

Receivers. ``"csi"``: the FC knows every channel gain (estimated from pilots, dey2009 Remark 1),
so it knows which sensors were in outage; a sensor in outage tells it nothing (whether the sensor
sent or not, nothing arrives), a sensor with a good channel that delivered nothing was silent.
Then every filter here stays exact: mo2015's silent sensor is still the measurement ``0`` with
variance ``r_i + delta_i``, and zheng2014's silent-sensor probability is still the right
likelihood. ``"naive"``: the FC ignores the channel and treats every missing packet as silence
(what Parts I and IV do, since they assume a perfect link). All-send, random selection and CFoMD
drop missing packets, which is exact (all-send, random: the loss is independent of the data) or
already an approximation (CFoMD) whatever the receiver.

The package, one idea per module:

- :mod:`~fusioncenter.comparison.link`             the faded packet link (``RECEIVERS``,
  :func:`outage_threshold`, :func:`energy_matched_outage`) and one block of trials with its
  channel gains (:class:`Draw`, :func:`draw`);
- :mod:`~fusioncenter.comparison.kalman_family`    the Kalman-filter family on given data
  (:data:`KF_SCHEMES`, :func:`scenario_model`, :func:`kf_filter`, :class:`KFRun`,
  :func:`kf_chunk`, :func:`run_kf`);
- :mod:`~fusioncenter.comparison.particle_family`  zheng2014's particle filters over the link
  (:data:`PF_SCHEMES`, :func:`run_pf`);
- :mod:`~fusioncenter.comparison.paired`           the paired runs: per-trial results of a
  scheme and the paired differences of two (:class:`Summary`,
  :func:`summary_from_censoring`);
- :mod:`~fusioncenter.comparison.cost`             the operation counts of a step
  (:func:`kf_flops`, :func:`pf_flops`).

The names are re-exported here (``comparison.run_kf``, ``comparison.Summary``, ...).
"""

from __future__ import annotations

from fusioncenter.comparison.cost import kf_flops, pf_flops
from fusioncenter.comparison.kalman_family import (
    KF_SCHEMES,
    KFOutput,
    KFRun,
    kf_chunk,
    kf_filter,
    run_kf,
    scenario_model,
)
from fusioncenter.comparison.link import (
    RECEIVERS,
    Draw,
    draw,
    energy_matched_outage,
    outage_threshold,
)
from fusioncenter.comparison.paired import Summary, summary_from_censoring
from fusioncenter.comparison.particle_family import PF_SCHEMES, run_pf

__all__ = [
    "KF_SCHEMES",
    "PF_SCHEMES",
    "RECEIVERS",
    "scenario_model",
    "outage_threshold",
    "energy_matched_outage",
    "Draw",
    "draw",
    "KFOutput",
    "kf_filter",
    "KFRun",
    "kf_chunk",
    "run_kf",
    "run_pf",
    "Summary",
    "summary_from_censoring",
    "kf_flops",
    "pf_flops",
]
