"""fusioncenter: the shared library of the companion book.

In all four papers the question is what the fusion centre can compute from what the sensors
chose, or managed, to send. One module per topic:

- :mod:`fusioncenter.riccati`     Kalman covariance (Riccati) recursions and steady states
- :mod:`fusioncenter.kalman`      a linear-Gaussian model and its Kalman filter, batched over trials
- :mod:`fusioncenter.event`       the stochastic event trigger and its exact filter (mo2015)
- :mod:`fusioncenter.models`      shared example models (the tracking model of zheng2014)
- :mod:`fusioncenter.fading`      fading laws, the random Riccati recursion and its bounds (dey2009)
- :mod:`fusioncenter.power`       steady state, 1/M laws and power allocation (leong2011)
- :mod:`fusioncenter.censoring`   innovation censoring and its likelihoods (zheng2014); vector
  observations (Section V) in :mod:`fusioncenter.censoring.vector` and its neighbours, the
  nonlinear sensor-grid tracker (Section VI) in :mod:`fusioncenter.censoring.nonlinear`
- :mod:`fusioncenter.comparison`  the four papers' schemes on one problem, over faded links
- :mod:`fusioncenter.particle`    a particle filter vectorized over trials and particles
- :mod:`fusioncenter.montecarlo`  the one Monte Carlo runner (chunk- and executor-independent)
- :mod:`fusioncenter.figures`     the registry of every figure and table of the papers;
  zheng2014's three settings read together in :mod:`fusioncenter.figures.zheng2014.reading`
- :mod:`fusioncenter.plotting`    the one plotting style
- :mod:`fusioncenter.profile`     the ``fast`` / ``paper`` execution profiles
"""

from fusioncenter.profile import current_profile

__all__ = ["current_profile", "__version__"]
__version__ = "0.1.0"
