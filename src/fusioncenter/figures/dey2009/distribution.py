"""Part II (dey2009), ``dey2009-distribution``: the whole distribution of ``p_k`` (the
paper's future work; the book's own figure).
"""

from __future__ import annotations

import numpy as np
import scipy.integrate
import scipy.stats

from fusioncenter import fading, plotting, riccati
from fusioncenter.context import Parameter
from fusioncenter.figures.common import checks_doc, compute_doc, plot_doc, register_figure, settings
from fusioncenter.figures.dey2009 import common
from fusioncenter.figures.registry import Claim

#: The overridable parameters of ``dey2009-distribution``.
SETTABLE_DIST = (
    Parameter("paths", "int", "Monte Carlo paths per fading law", dict(common.DIST_PATHS),
              minimum=4),
    Parameter("alt_paths", "int", "paths per law from the alternative p_0", dict(common.GRID_PATHS),
              minimum=2),
    Parameter("sigma_v", "float", "measurement-noise standard deviation", common.DIST["sigma_v"],
              minimum=1e-6, model=True),
)


@compute_doc("""Settings ``k``, ``levels`` (the quantile levels of :data:`DIST`), ``n_paths``,
             ``n_alt_paths``, ``seed``, ``p0``, ``p0_alt``, ``laws``, ``bins`` (61,) and
             ``lower_envelope`` (101,) the perfect-channel Riccati sequence; for each law ``L``
             in ("rayleigh", "nakagami"): ``L_quantiles`` (5, 101), ``L_mean``, ``L_stderr``,
             ``L_s`` (101,), ``L_density`` (60,) a histogram of p_100, and the scalars
             ``L_min_rel_gap``, ``L_ks_time``, ``L_ks_p0`` (KS p-values), ``L_above_mean``,
             ``L_max``, ``L_cdf_lo``, ``L_sf_hi``; the pooled 5 % and 95 % quantiles ``x_lo``,
             ``x_hi``, and the survival functions ``L_sf`` (40,) on the grid ``sf_x``.""",
             profile="Sets the number of paths (:data:`DIST_PATHS`, :data:`GRID_PATHS`).")
def compute_distribution(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-distribution``: the law of p_k beyond its mean, for both fading laws."""
    s = common.SCALAR
    v = settings("dey2009-distribution", SETTABLE_DIST, profile, over)
    sv2 = v["sigma_v"] ** 2
    n, ng = v["paths"], v["alt_paths"]
    levels = np.array(common.DIST["quantiles"])
    low = riccati.scalar_sequence(common.P0, s["a"], s["sigma_w2"], 1.0, sv2, common.STEPS)
    bins = np.geomspace(10.0, 2e4, 61)
    out: dict = {"k": np.arange(common.STEPS + 1), "levels": levels, "n_paths": n,
                 "n_alt_paths": ng, "seed": seed, "lower_envelope": low, "bins": bins,
                 "p0": common.P0, "p0_alt": common.DIST["p0_alt"],
                 "laws": np.array(["rayleigh", "nakagami"])}
    finals = {}
    for j, kind in enumerate(("rayleigh", "nakagami")):
        ch = common.scalar_channel(kind)
        res = fading.scalar_paths(s["a"], s["sigma_w2"], sv2, s["sigma_n2"], ch, common.P0,
                                  common.STEPS, n, seed + j, block_size=common.BLOCK)
        x = res.samples
        h = n // 2
        alt = fading.scalar_paths(s["a"], s["sigma_w2"], sv2, s["sigma_n2"], ch,
                                  common.DIST["p0_alt"], common.STEPS, ng, seed + 10 + j,
                                  block_size=common.BLOCK)
        final = x[:, -1]
        finals[kind] = final
        mean = final.mean()
        above = (final > mean).mean()
        out.update({
            f"{kind}_quantiles": np.quantile(x, levels, axis=0),
            f"{kind}_mean": res.mean, f"{kind}_stderr": res.stderr,
            f"{kind}_s": fading.scalar_bounds(s["a"], s["sigma_w2"], sv2, s["sigma_n2"], ch,
                                              common.P0, common.STEPS)["s"],
            f"{kind}_density": np.histogram(final, bins=bins, density=True)[0],
            f"{kind}_min_rel_gap": float(np.min((x[:, 1:] - low[1:]) / low[1:])),
            f"{kind}_ks_time": float(scipy.stats.ks_2samp(x[:h, 80], x[h:, -1]).pvalue),
            f"{kind}_ks_p0": float(scipy.stats.ks_2samp(final, alt.samples[:, -1]).pvalue),
            f"{kind}_above_mean": float(above),
            f"{kind}_max": float(final.max()),
        })
    pooled = np.concatenate([finals["rayleigh"], finals["nakagami"]])
    x_lo, x_hi = np.quantile(pooled, [0.05, 0.95])
    out["x_lo"], out["x_hi"] = float(x_lo), float(x_hi)
    for kind, final in finals.items():
        out[f"{kind}_cdf_lo"] = float((final <= x_lo).mean())
        out[f"{kind}_sf_hi"] = float((final > x_hi).mean())
    xs = np.geomspace(np.quantile(pooled, 0.5), pooled.max(), 40)
    out["sf_x"] = xs
    for kind, final in finals.items():
        out[f"{kind}_sf"] = (final[None, :] > xs[:, None]).mean(axis=1)
    if "sigma_v" in over:
        out["sigma_v"] = v["sigma_v"]
    return out


@plot_doc()
def plot_distribution(data: dict):
    """Quantile bands over time, the stationary density and its right tail, both laws."""
    fig, axes = plotting.subplots(1, 3, stack=True)
    k = data["k"]
    lv = data["levels"]
    names = {"rayleigh": "Rayleigh", "nakagami": "Nakagami(1/2)"}
    for j, kind in enumerate(("rayleigh", "nakagami")):
        col = plotting.OKABE_ITO[j]
        qs = data[f"{kind}_quantiles"]
        ax = axes[0]
        ax.fill_between(k, qs[0], qs[-1], color=col, alpha=0.15, linewidth=0)
        ax.fill_between(k, qs[1], qs[-2], color=col, alpha=0.25, linewidth=0)
        ax.plot(k, qs[len(lv) // 2], color=col, ls="-", label=f"{names[kind]}: median "
                f"(bands {lv[1]:.0%}-{lv[-2]:.0%}, {lv[0]:.0%}-{lv[-1]:.0%})")
        ax.plot(k, data[f"{kind}_mean"], color=col, ls="--", label=f"{names[kind]}: mean")
        centers = np.sqrt(data["bins"][1:] * data["bins"][:-1])
        axes[1].plot(centers, data[f"{kind}_density"] * centers, color=col, ls="-",
                     drawstyle="steps-mid", label=f"{names[kind]}")
        axes[1].axvline(data[f"{kind}_mean"][-1], color=col, ls="--", lw=0.8)
        axes[1].axvline(data[f"{kind}_s"][-1], color=col, ls=":", lw=0.8)
        axes[2].plot(data["sf_x"], data[f"{kind}_sf"], color=col, ls="-",
                     marker=plotting.MARKERS[j], mfc="none", label=names[kind])
    axes[0].plot(k, data["lower_envelope"], color="0.3", lw=0.8, ls=":",
                 label="sure lower envelope (perfect channel)")
    axes[0].set(xlabel="time step $k$", ylabel="$p_k$ (units of $x^2$)", yscale="log",
                title=f"quantiles over time; {data['n_paths']} paths")
    axes[0].legend()
    axes[1].set(xscale="log", xlabel=r"$p_{100}$ (units of $x^2$)",
                ylabel=r"density of $\ln p_{100}$ (dimensionless)",
                title="steady state (dashed: mean, dotted: bound $s^*$)")
    axes[1].legend()
    axes[2].set(xscale="log", yscale="log", xlabel=r"$x$ (units of $x^2$)",
                ylabel=r"$P(p_{100} > x)$ (dimensionless)", title="upper tail")
    common.plain_log_ticks(axes[2].xaxis)
    axes[2].legend()
    sigma_v = data.get("sigma_v", common.DIST["sigma_v"])
    return plotting.finish(fig, title=rf"Distribution of $p_k$: $\sigma_v = {sigma_v:g}$,"
                           rf" $\lambda = {common.SCALAR['lam']:g}$, $E[p_0] = {data['p0']:g}$")


@checks_doc("One claim per statement, with the measured p-values, fractions or z-scores.")
def checks_distribution(data: dict) -> list[Claim]:
    """Lower envelope, stationarity, independence of p_0, skewness and the tails."""
    n = data["n_paths"]
    claims = [
        Claim("every sampled pₖ is above the sure lower envelope (the Riccati recursion of a "
              "perfect channel, r → ∞)",
              bool(min(data["rayleigh_min_rel_gap"], data["nakagami_min_rel_gap"])
                   >= -common.REL_SLACK),
              f"min over paths and k ≥ 1 of (pₖ − lₖ)/lₖ: "
              f"{data['rayleigh_min_rel_gap']:.3e} (Rayleigh), "
              f"{data['nakagami_min_rel_gap']:.3e} (Nakagami)"),
        Claim(f"stationary by k = 80: two-sample KS (disjoint halves of the paths) of p₈₀ vs "
              f"p₁₀₀ does not reject at level {common.KS_LEVEL:g}",
              bool(min(data["rayleigh_ks_time"], data["nakagami_ks_time"]) > common.KS_LEVEL),
              f"p-values {data['rayleigh_ks_time']:.3f}, {data['nakagami_ks_time']:.3f}"),
        Claim(f"the stationary law does not depend on p₀: KS of p₁₀₀ from p₀ = {common.P0:g} vs "
              f"p₀ = {data['p0_alt']:g} does not reject at level {common.KS_LEVEL:g}",
              bool(min(data["rayleigh_ks_p0"], data["nakagami_ks_p0"]) > common.KS_LEVEL),
              f"p-values {data['rayleigh_ks_p0']:.3f}, {data['nakagami_ks_p0']:.3f}"),
    ]
    za = [(0.5 - data[f"{k}_above_mean"]) / np.sqrt(0.25 / n) for k in ("rayleigh", "nakagami")]
    claims.append(Claim("right-skewed: P(p₁₀₀ > E[p₁₀₀]) < 1/2 by more than 4 binomial s.e.",
                        bool(min(za) > common.Z_TOL),
                        f"{data['rayleigh_above_mean']:.3f}, {data['nakagami_above_mean']:.3f} "
                        f"(z = {za[0]:.1f}, {za[1]:.1f})", paper_specific=True))

    def two_prop(p1, p2):
        se = np.sqrt(p1 * (1 - p1) / n + p2 * (1 - p2) / n)
        return (p1 - p2) / se if se > 0 else 0.0
    z_lo = two_prop(data["nakagami_cdf_lo"], data["rayleigh_cdf_lo"])
    z_hi = two_prop(data["nakagami_sf_hi"], data["rayleigh_sf_hi"])
    claims.append(Claim(
        "Nakagami(1/2) spreads p more, not just shifts it: more mass below the pooled 5% "
        "quantile AND above the pooled 95% quantile than Rayleigh (> 4 s.e. each)",
        bool(z_lo > common.Z_TOL and z_hi > common.Z_TOL),
        f"P(p ≤ {data['x_lo']:.1f}): {data['nakagami_cdf_lo']:.3f} vs "
        f"{data['rayleigh_cdf_lo']:.3f} (z = {z_lo:.1f}); P(p > {data['x_hi']:.1f}): "
        f"{data['nakagami_sf_hi']:.3f} vs {data['rayleigh_sf_hi']:.3f} (z = {z_hi:.1f})",
        paper_specific=True))
    zm = common.max_finite(np.concatenate([
        common.excess_z(data[f"{k}_mean"][1:], data[f"{k}_stderr"][1:], data[f"{k}_s"][1:])
        for k in ("rayleigh", "nakagami")]))
    claims.append(Claim("the mean of the distribution stays below the tight bound sₖ (4 s.e.)",
                        bool(zm < common.Z_TOL), f"max z = {zm:.2f}"))
    return claims


register_figure(
    id="dey2009-distribution",
    paper="dey2009",
    caption="Beyond the mean: the distribution of pₖ over time (quantile bands) and at steady "
    "state (density of log p and upper tail) for Rayleigh and Nakagami(1/2) fading, Fig. 1's "
    "channel with σᵥ = 1.",
    chapter=common.CH_DIST,
    label="sec-dey2009-distribution",
    parameters={**common.SCALAR, "sigma_v": common.DIST["sigma_v"], "E[p_0]": common.P0,
                "p0_alt": common.DIST["p0_alt"], "quantiles": list(common.DIST["quantiles"]),
                "steps": common.STEPS, "paths": common.DIST_PATHS, "alt_paths": common.GRID_PATHS,
                "block_size": common.BLOCK, "ks_level": common.KS_LEVEL},
    functions=(compute_distribution, plot_distribution, checks_distribution),
    settable=SETTABLE_DIST,
    note="Our own figure: the paper leaves the distribution of the error covariance as future "
    "work.",
)
