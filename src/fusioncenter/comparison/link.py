"""The faded packet link between each sensor and the fusion centre: Rayleigh block fading, a
packet lost when its channel's power gain is below a threshold (:func:`outage_threshold`), the
outage of a sensor that spends the same energy on fewer packets
(:func:`energy_matched_outage`), and one block of trials drawn with its channel gains
(:func:`draw`) exactly as :func:`fusioncenter.censoring.run` draws its data."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter._validate import finite as _finite
from fusioncenter.comparison._args import RECEIVERS, check_outage, check_scenario, doc
from fusioncenter.fading import Rayleigh

__all__ = ["RECEIVERS", "outage_threshold", "energy_matched_outage", "Draw", "draw"]


@doc(returns=("float", "``g_th >= 0``."))
def outage_threshold(outage, channel: Rayleigh | None = None) -> float:
    """The power-gain threshold ``g_th`` with ``P(g < g_th) = outage`` for a Rayleigh channel.

    ``g ~ Exp(mean 1/lam)``: ``g_th = -log(1 - outage) / lam``.
    """
    eps = check_outage(outage)
    channel = Rayleigh(1.0) if channel is None else channel
    if not isinstance(channel, Rayleigh):
        raise ValueError(f"channel must be a fusioncenter.fading.Rayleigh, got {channel!r}")
    return float(-math.log1p(-eps) / channel.lam)


@doc(returns=("float or numpy.ndarray", "The outage probability, broadcast over the arguments."),
     outage_full=("array_like", "Outage when sending at every step, in ``[0, 1)``."),
     rate=("array_like", "Fraction of the steps with a packet, in ``[0, 1]``."))
def energy_matched_outage(outage_full, rate):
    """Outage of a sensor that sends a fraction ``rate`` of the steps with the energy that
    sending at every step with outage ``outage_full`` would use.

    Per-packet power ``P / rate`` lowers the threshold to ``rate g_th``, so
    ``eps = 1 - exp(-lam rate g_th) = 1 - (1 - outage_full)^rate``. Broadcasts.
    """
    eps = _finite("outage_full", outage_full)
    rate = _finite("rate", rate)
    if np.any((eps < 0) | (eps >= 1)) or not np.all(np.isfinite(eps)):
        raise ValueError(f"outage_full must lie in [0, 1), got {outage_full!r}")
    if np.any((rate < 0) | (rate > 1)) or not np.all(np.isfinite(rate)):
        raise ValueError(f"rate must lie in [0, 1], got {rate!r}")
    out = -np.expm1(rate * np.log1p(-eps))
    return out[()] if out.ndim == 0 else out


class Draw(NamedTuple):
    """One block of trials (:func:`draw`).

    Attributes
    ----------
    x : numpy.ndarray
        The truth ``(n, T+1, 2)`` (``x[:, 0] = x_0``).
    z : numpy.ndarray
        The measurements ``(n, T, N)``.
    xi : numpy.ndarray
        Uniforms ``(n, T, N)``: random selection sends iff ``xi < p``, the trigger iff
        ``xi > exp(-nu^2 / (2 delta))``.
    gain : numpy.ndarray
        Channel power gains ``(n, T, N)``.
    rng_pf : numpy.random.Generator
        The generator left for the particle filter.
    """

    x: np.ndarray
    z: np.ndarray
    xi: np.ndarray
    gain: np.ndarray
    rng_pf: np.random.Generator


@doc(returns=("Draw", "The block's truth, measurements, uniforms, gains and particle stream."))
def draw(rng: np.random.Generator, n: int, scenario, channel: Rayleigh | None = None) -> Draw:
    """Draw a block of trials exactly as :func:`fusioncenter.censoring.run` does, plus the link.

    ``rng.spawn(3)``: the first child draws the truth, the measurements and the uniforms in
    ``censoring``'s documented order (so a run here with the same ``seed``, ``n_trials`` and
    ``block_size`` as ``censoring.run`` sees the same trajectories and measurements), the second
    is the particle filter's, the third draws the channel gains. The gains do not depend on the
    outage probability, so the lost packets at a larger outage include those at a smaller one
    (nested losses, for paired comparisons).
    """
    sc = check_scenario(scenario)
    channel = Rayleigh(1.0) if channel is None else channel
    rng_data, rng_pf, rng_chan = _v.generator("rng", rng).spawn(3)
    x, z = sc.sample(rng_data, _v.integer("n", n))
    xi = rng_data.random(z.shape)
    gain = channel.sample(rng_chan, z.shape)
    return Draw(x, z, xi, gain, rng_pf)
