"""Part I's explorable figure, ``mo2015-explore``: the trigger parameter δ of one sensor.

The likelihood of a silence, the posterior it leaves (on a grid and in closed form), and the
sensor's (communication rate, mean squared error) point moving along its trade-off curve, all
in closed form for a scalar state and one sensor (no Monte Carlo).
"""

from __future__ import annotations

import numpy as np
from scipy import integrate
from scipy.stats import norm

from fusioncenter import event, plotting
from fusioncenter.context import Parameter
from fusioncenter.figures import common
from fusioncenter.figures.explorable import declare
from fusioncenter.figures.registry import Claim

OWN_IDS = ("mo2015-explore",)

# ------------------------------------------------------------------- mo2015: the trigger's δ
#: One sensor measuring a scalar state: ``y = a x + v``, ``x ~ N(xbar, Sigma)``, ``v ~ N(0, r)``.
MO = {"xbar": 1.0, "Sigma": 1.0, "a": 1.0, "r": 0.25}
#: The slider's grid: δ = 2^(k/2) for k = -8..8 (1/16 to 16; 1 in the middle).
MO_DELTAS = tuple(float(2.0 ** (k / 2)) for k in range(-8, 9))
#: The trade-off curve: δ from 10⁻³ to 10³.
MO_CURVE = np.geomspace(1e-3, 1e3, 241)
#: The state grid of the posterior's normalisation by quadrature (x̄ ± 8 prior standard
#: deviations), and the part of it that the data keep and the figure shows.
MO_X = np.linspace(-7.0, 9.0, 3201)
MO_XLIM = (-3.0, 5.0)
MO_SHOWN = slice(800, 2401, 4)  # x from -3 to 5 in steps of 0.02
SETTABLE_MO = (
    Parameter("delta", "float", "trigger parameter δ of the sensor (units of y²)", 1.0,
              minimum=0.0, exclusive_minimum=True, model=True),
)
#: The slider over the grid: its text beside the value, the first frame and those of print.
SLIDER_MO = {"parameter": "delta", "values": MO_DELTAS,
             "label": "trigger parameter δ (units of y²)", "symbol": "δ", "fmt": "{:.3g}",
             "start": 8, "print_at": (0, 8, 12, 16)}


def _mo_moments(delta: float) -> tuple[float, float, float, float]:
    """(rate, x̃, P̃ after a silence, P after a transmission) at ``delta``."""
    s = MO
    args = ([s["xbar"]], [[s["Sigma"]]], [[s["a"]]], [s["r"]], delta)
    rate = float(event.communication_rate(args[1], args[2], args[3], delta, args[0])[0])
    xt, Pt = event.posterior(*args, [0], [np.nan])
    _, Ps = event.posterior(*args, [1], [0.0])  # the covariance does not depend on y
    return rate, float(xt[0]), float(Pt[0, 0]), float(Ps[0, 0])


@common.compute_doc("""``delta`` the trigger parameter; ``x`` (401,) the state from −3 to 5;
             ``prior``, ``likelihood`` (P(γ = 0 | x)), ``posterior_grid`` (prior × likelihood,
             normalised by quadrature) and ``posterior`` (the closed form N(x̃, P̃)) on it;
             ``rate``, ``mse``, ``xtilde``, ``ptilde``, ``p_send`` (floats); ``curve_delta``,
             ``curve_rate``, ``curve_mse`` (241,) the trade-off curve.""",
             profile="Unused (deterministic).", seed="Unused.")
def compute_mo(profile: str, seed: int, **over) -> dict:
    """Data of ``mo2015-explore``: one sensor's silence and trade-off at one δ."""
    delta = common.settings("mo2015-explore", SETTABLE_MO, profile, over)["delta"]
    s = MO
    prior = norm.pdf(MO_X, s["xbar"], np.sqrt(s["Sigma"]))
    # P(γ = 0 | x) = 1 - P(γ = 1) for a measurement y ~ N(a x, r)
    likelihood = 1.0 - np.asarray(event.trigger_probability(s["r"], delta, s["a"] * MO_X))
    joint = prior * likelihood
    rate, xt, pt, ps = _mo_moments(delta)
    shown = MO_SHOWN
    return {
        "delta": float(delta), "x": MO_X[shown], "prior": prior[shown],
        "likelihood": likelihood[shown],
        "posterior_grid": (joint / integrate.trapezoid(joint, MO_X))[shown],
        "posterior": norm.pdf(MO_X[shown], xt, np.sqrt(pt)),
        "rate": rate, "mse": rate * ps + (1 - rate) * pt, "xtilde": xt, "ptilde": pt,
        "p_send": ps, "curve_delta": MO_CURVE, **_mo_curve(MO_CURVE),
    }


def _mo_curve(deltas) -> dict:
    """The trade-off curve in closed form (a scalar state and one sensor): the rate is
    ``1 - √(δ/(δ + s)) exp(-(a x̄)²/(2(δ + s)))`` with ``s = a²Σ + r``, and the error after a
    silence ``P̃ = (1/Σ + a²/(r + δ))⁻¹``, after a transmission ``(1/Σ + a²/r)⁻¹``."""
    s = MO
    d = np.asarray(deltas, dtype=float)
    var_y = s["a"] ** 2 * s["Sigma"] + s["r"]
    rate = 1 - np.sqrt(d / (d + var_y)) * np.exp(-(s["a"] * s["xbar"]) ** 2 / (2 * (d + var_y)))
    pt = 1.0 / (1.0 / s["Sigma"] + s["a"] ** 2 / (s["r"] + d))
    ps = 1.0 / (1.0 / s["Sigma"] + s["a"] ** 2 / s["r"])
    return {"curve_rate": rate, "curve_mse": rate * ps + (1 - rate) * pt}


@common.plot_doc()
def plot_mo(data: dict):
    """Three panels: (a) the likelihood of a silence, (b) the posterior it leaves,
    (c) the (rate, mean squared error) point on the trade-off curve."""
    fig, (ax1, ax2, ax3) = plotting.subplots(3, 1, stack=True)
    x, c = data["x"], plotting.OKABE_ITO
    ax1.plot(x, data["likelihood"], color=c[1], label=r"$P(\gamma = 0 \mid x)$")
    ax1.set(xlim=MO_XLIM, ylim=(0, 1.05), xlabel=r"state $x$ (units of $x$)",
            ylabel="probability of silence (dimensionless)",
            title=rf"(a) likelihood of a silence, $\delta$ = {data['delta']:.3g}")
    ax1.legend(loc="upper right")
    # the same vertical scale for every δ of the slider: the narrowest posterior is at the
    # smallest δ, P̃ = (1/Σ + a²/(r + δ))⁻¹
    s = MO
    p_min = 1.0 / (1.0 / s["Sigma"] + s["a"] ** 2 / (s["r"] + min(MO_DELTAS[0], data["delta"])))
    ax2.plot(x, data["prior"], color="0.5", ls=":", label=r"prior $\mathcal{N}(1, 1)$")
    ax2.plot(x, data["posterior_grid"], color=c[0], lw=3.0,
             label="posterior after a silence (grid)")
    ax2.plot(x, data["posterior"], color=c[2], ls="--",
             label=r"closed form $\mathcal{N}(\tilde x, \tilde P)$")
    ax2.set(xlim=MO_XLIM, ylim=(0, 1.1 / np.sqrt(2 * np.pi * p_min)),
            xlabel=r"state $x$ (units of $x$)", ylabel=r"density (per unit of $x$)",
            title=rf"(b) $\tilde x$ = {data['xtilde']:.3f}, $\tilde P$ = {data['ptilde']:.3f}")
    ax2.legend(loc="upper left")
    ax3.plot(data["curve_rate"], data["curve_mse"], color="0.4",
             label=r"trade-off, $\delta$ from $10^{-3}$ to $10^{3}$")
    ax3.plot([data["rate"]], [data["mse"]], "o", color=c[1], ms=10,
             label=rf"$\delta$ = {data['delta']:.3g}")
    ax3.axhline(data["p_send"], color=c[0], ls=":", label="always send")
    ax3.axhline(MO["Sigma"], color="0.5", ls=":", label="never send (prior)")
    ax3.set(xlim=(0, 1), ylim=(0, 1.05 * MO["Sigma"]),
            xlabel="communication rate $P(\\gamma = 1)$ (dimensionless)",
            ylabel=r"mean squared error (units of $x^2$)",
            title=f"(c) rate {data['rate']:.3f}, mean squared error {data['mse']:.3f}")
    ax3.legend(loc="upper right")
    return plotting.finish(fig)


@common.checks_doc()
def checks_mo(data: dict) -> list[Claim]:
    """The closed form against the grid and against the rate's own closed form."""
    s = MO
    gap = np.max(np.abs(data["posterior_grid"] - data["posterior"])) / np.max(data["posterior"])
    at = _mo_curve([data["delta"]])
    silent = 1 - at["curve_rate"][0]
    return [
        Claim("the posterior after a silence is the Gaussian N(x̃, P̃) (grid against closed "
              "form, relative to its peak)", gap < 1e-6, f"largest gap {gap:.1e}"),
        Claim("the rate is 1 − √(δ/(δ + s)) exp(−(a x̄)²/(2(δ + s))), s = a²Σ + r",
              abs(data["rate"] - (1 - silent)) < 1e-12,
              f"{data['rate']:.6f} vs {1 - silent:.6f}"),
        Claim("the trade-off curve's closed form gives the library's error at δ",
              abs(at["curve_mse"][0] - data["mse"]) < 1e-12,
              f"{at['curve_mse'][0]:.6f} vs {data['mse']:.6f}"),
        Claim("the mean squared error lies between always sending and never sending",
              bool(data["p_send"] <= data["mse"] <= s["Sigma"]),
              f"{data['p_send']:.4f} ≤ {data['mse']:.4f} ≤ {s['Sigma']:g}"),
    ]


def _facts_mo(data: dict) -> dict[str, str]:
    return {"rate": f"{data['rate']:.3f}", "mse": f"{data['mse']:.3f}",
            "ptilde": f"{data['ptilde']:.3f}", "xtilde": f"{data['xtilde']:.3f}"}


def _increasing(values) -> bool:
    return bool(np.all(np.diff(np.asarray(values, dtype=float)) > 0))


@declare.sweep_doc("The rate falls, the mean squared error and P̃ grow, from one value to the "
                   "next.", deltas=("tuple of float", "The slider's values of δ, increasing."))
def sweep_mo(deltas, frames) -> list[Claim]:
    """Along the slider: sending less costs accuracy, and a silence says less."""
    rate = [f["rate"] for f in frames]
    mse = [f["mse"] for f in frames]
    pt = [f["ptilde"] for f in frames]
    return [
        Claim("the communication rate falls as δ grows", _increasing(-np.asarray(rate)),
              f"{rate[0]:.3f} at δ = {deltas[0]:.3g} down to {rate[-1]:.3f} at "
              f"δ = {deltas[-1]:.3g}"),
        Claim("the mean squared error grows as δ grows", _increasing(mse),
              f"{mse[0]:.4f} up to {mse[-1]:.4f}"),
        Claim("a silence leaves a wider posterior as δ grows (P̃ increases)", _increasing(pt),
              f"P̃ from {pt[0]:.4f} to {pt[-1]:.4f}"),
    ]


declare.register(
    id="mo2015-explore",
    paper="mo2015",
    caption="One sensor under the stochastic trigger, at the trigger parameter δ of the slider: "
    "the likelihood of a silence, the Gaussian posterior it leaves, and the sensor's "
    "(communication rate, mean squared error) point on its trade-off curve.",
    chapter="book/mo2015/rate",
    label="sec-mo2015-rate-explore",
    parameters={"model": MO, "delta_grid": list(MO_DELTAS)},
    functions=(compute_mo, plot_mo, checks_mo, sweep_mo, _facts_mo),
    settable=SETTABLE_MO,
    note="Our own figure, on the model of the notes' single-sensor example; deterministic.",
    slider=SLIDER_MO,
)
