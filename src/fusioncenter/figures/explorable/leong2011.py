"""Part III's explorable figure, ``leong2011-explore``: the total power budget, multi-access.

The static channels of the paper's Figs. 3-4 (random sensors: ``σᵢ² ~ χ²(1)``, ``hᵢ = dᵢ⁻²``
with ``dᵢ ~ U(20, 100)`` m, ``a = 0.9``, ``σ_w² = 1``, ``σₙ² = 10⁻⁹``, ``cᵢ = 1``) with the
sensors adding up on one multi-access channel, at the total power budget ``γ_total`` of the
slider (the paper's Fig. 3(b) has ``10⁻³``): the mean steady-state error ``P∞`` of the optimal
allocation (the corrected (24), :func:`fusioncenter.power.min_error`) and of equal power (16)
against the number of sensors ``M``, with the 1/M law each approaches.

The 1/M laws. With the budget spent optimally the SNR is a sum over the sensors,
``S* = Σᵢ sᵢ`` with ``sᵢ = ρᵢ² γ/(γ τᵢ + κᵢ σₙ²)``, so ``E[S*] = M s̄`` exactly; with equal
shares ``αᵢ² = γ/(M κᵢ)`` it is ``(γ/M)(Σ ρᵢ/√κᵢ)²/((γ/M) Σ τᵢ/κᵢ + σₙ²) ≈ M s̄_eq`` with
``s̄_eq = γ E[ρ/√κ]²/(γ E[τ/κ] + σₙ²)`` for large ``M``. Since ``P∞ − σ_w² ≈ a²/S`` for a
large SNR, both errors approach ``σ_w² + a²/(M s̄)``: the asymptote as ``M → ∞`` at a fixed
budget. The means ``s̄`` are integrals over the sensor law, computed here without sampling:
in the noise, ``E[1/(1 + c Z²)] = √(π/(2c)) erfcx(1/√(2c))`` for ``Z ~ N(0, 1)`` (as
``σᵢ² = Z²``); in the distance, Gauss-Legendre quadrature; the checks compare them with the
sample means.

Every frame draws the same sensors (the seed of each ``M`` does not depend on the budget), so
a larger budget lowers the error of each draw, and the means fall exactly.
"""

from __future__ import annotations

import functools

import numpy as np
from scipy import integrate, special

from fusioncenter import context, montecarlo, plotting, power
from fusioncenter.context import Parameter
from fusioncenter.figures import common
from fusioncenter.figures.explorable import declare
from fusioncenter.figures.leong2011.common import CH_ALLOCATION, STATIC, Z_TOL, draw_sensors, m_seed
from fusioncenter.figures.registry import Claim

OWN_IDS = ("leong2011-explore",)

#: The model of Figs. 3-4 (the sensors are drawn per realization).
MODEL = {"a": STATIC["a"], "sigma_w2": STATIC["sigma_w2"], "sigma_n2": STATIC["sigma_n2"],
         "c": STATIC["c"], "d_range": (20.0, 100.0)}
#: The numbers of sensors: 1 to 128, doubling.
MS = (1, 2, 4, 8, 16, 32, 64, 128)
#: The M that the caption quotes (besides the largest).
M_QUOTED = 16
#: The slider's grid: γ_total = 10^(k/4), k = -20..-4 (10⁻⁵ to 10⁻¹; the paper's 10⁻³ in the
#: middle).
BUDGETS = tuple(float(10.0 ** (k / 4)) for k in range(-20, -3))
#: Random sensor draws per M (the paper's 1000 in the paper profile, as Figs. 3-4).
REALIZATIONS = {"fast": 100, "paper": 1000}
#: Gauss-Legendre nodes of the distance integrals.
N_NODES = 64
#: The vertical ranges of the panels (the same in every frame).
YLIM_P = (0.8, 5.6)
YLIM_EXCESS = (1e-3, 20.0)
SETTABLE = (
    Parameter("gamma_total", "float", "total power budget γ_total of the sensors (power units)",
              1e-3, minimum=0.0, exclusive_minimum=True, model=True),
    common.trials_parameter(REALIZATIONS, "random sensor draws per number of sensors",
                            name="realizations"),
)
#: The slider over the grid: its text beside the value, the first frame and those of print.
SLIDER = {"parameter": "gamma_total", "values": BUDGETS,
          "label": "total power budget γ_total (power units)", "symbol": "γ_total",
          "fmt": "{:.2g}", "start": 8, "print_at": (0, 8, 12, 16)}


def _chunk(rng: np.random.Generator, n: int, *, M: int, gamma: float) -> np.ndarray:
    """``n`` draws of ``M`` sensors; columns ``P_opt, P_eq, S_opt/M, budget residuals``."""
    p = MODEL
    a, sw, sn = p["a"], p["sigma_w2"], p["sigma_n2"]
    sv, d = draw_sensors(rng, n, M)
    h, c = d**-2.0, np.full(sv.shape, p["c"])
    kap = power.kappa(a, sw, c, sv)
    opt = power.min_error("multi-access", gamma, a, sw, h, c, sv, sn)
    eq = power.equal_power(a, sw, c, sv, gamma_total=gamma)
    s_opt = power.snr("multi-access", opt, h, c, sv, sn)
    s_eq = power.snr("multi-access", eq, h, c, sv, sn)
    return np.column_stack([
        power.steady_state(a, sw, s_opt), power.steady_state(a, sw, s_eq), s_opt / M,
        np.sum(opt**2 * kap, -1) / gamma - 1, np.sum(eq**2 * kap, -1) / gamma - 1])


@functools.cache
def _moments() -> tuple[float, float, float]:
    """``E[h]``, ``E[h²]`` (``h = d⁻²``, ``d`` uniform) and ``E[1/√(K₀ + Z²)]``."""
    p = MODEL
    lo, hi = p["d_range"]
    e_h = (1 / lo - 1 / hi) / (hi - lo)
    e_h2 = (lo**-3 - hi**-3) / (3 * (hi - lo))
    k0 = p["c"] ** 2 * p["sigma_w2"] / (1 - p["a"] ** 2)
    val, _ = integrate.quad(lambda z: np.exp(-z * z / 2) / np.sqrt(2 * np.pi * (k0 + z * z)),
                            -np.inf, np.inf, epsabs=0, epsrel=1e-13, limit=200)
    return e_h, e_h2, val


def _inverse_mean(c):
    """``E[1/(1 + c Z²)]`` for ``Z ~ N(0, 1)`` and ``c > 0``."""
    c = np.asarray(c, dtype=float)
    return np.sqrt(np.pi / (2 * c)) * special.erfcx(1 / np.sqrt(2 * c))


def mean_snr(gamma: float) -> tuple[float, float]:
    """The mean SNR one sensor adds at the budget ``gamma``: optimal and equal allocation.

    Parameters
    ----------
    gamma : float
        The total power budget (``> 0``).

    Returns
    -------
    tuple of float
        ``(s̄, s̄_eq)``: ``E[ρ² γ/(γ τ + κ σₙ²)]`` (exact for every ``M``: ``E[S*] = M s̄``) and
        ``γ E[ρ/√κ]²/(γ E[τ/κ] + σₙ²)`` (the large-``M`` limit of ``S_eq/M``), over the sensor
        law of :data:`MODEL`.

    Raises
    ------
    ValueError
        If ``gamma`` is not a positive finite number.
    """
    if not (isinstance(gamma, int | float) and np.isfinite(gamma) and gamma > 0):
        raise ValueError(f"gamma must be a positive finite number, got {gamma!r}")
    p = MODEL
    a, sw, sn, c = p["a"], p["sigma_w2"], p["sigma_n2"], p["c"]
    k0 = c**2 * sw / (1 - a**2)
    lo, hi = p["d_range"]
    x, w = np.polynomial.legendre.leggauss(N_NODES)
    h = (0.5 * (lo + hi) + 0.5 * (hi - lo) * x) ** -2.0
    # s = h² c² γ/(Z² (γ h² + σₙ²) + K₀ σₙ²), averaged over Z, then over d
    s_of_d = h**2 * c**2 * gamma / (k0 * sn) * _inverse_mean((gamma * h**2 + sn) / (k0 * sn))
    s_opt = float(np.sum(w * s_of_d) / 2)
    e_h, e_h2, e_root = _moments()
    e_tau_kappa = e_h2 * (1 - _inverse_mean(1 / k0))  # E[Z²/(K₀ + Z²)] = 1 − E[1/(1 + Z²/K₀)]
    s_eq = gamma * (c * e_h * e_root) ** 2 / (gamma * e_tau_kappa + sn)
    return s_opt, float(s_eq)


@common.compute_doc("""``gamma_total``; ``M`` (8,); per M: ``optimal``, ``equal`` (with
             ``*_stderr``) the mean P∞ of both allocations, ``snr_per_sensor`` (with
             ``_stderr``) the mean of ``S*/M``, ``min_gap`` the smallest
             ``(P_eq − P_opt)/P_opt`` over the draws, ``max_residual`` the largest
             ``|Σ αᵢ² κᵢ/γ − 1|`` of both allocations; ``sbar_optimal``, ``sbar_equal`` the
             mean SNR per sensor of :func:`mean_snr`; ``law_optimal``, ``law_equal`` (8,) the
             1/M laws ``σ_w² + a²/(M s̄)``; ``sigma_w2``, ``p_none`` (the error without
             measurements); ``n_realizations``.""",
             profile="Sets the number of draws (:data:`REALIZATIONS`).")
def compute(profile: str, seed: int, **over) -> dict:
    """Data of ``leong2011-explore``: P∞ against M for both allocations at one budget."""
    par = common.settings("leong2011-explore", SETTABLE, profile, over)
    gamma, n = float(par["gamma_total"]), int(par["realizations"])
    rows = []
    for M in MS:
        fn = functools.partial(_chunk, M=M, gamma=gamma)
        rows.append(montecarlo.simulate(fn, n, m_seed(seed, M), executor=context.executor())
                    .samples)
    s = np.stack(rows)  # (M, n, 5)
    p = MODEL
    a, sw = p["a"], p["sigma_w2"]
    s_opt, s_eq = mean_snr(gamma)
    Ms = np.array(MS)
    se = s.std(1, ddof=1) / np.sqrt(n)
    return {
        "gamma_total": gamma, "M": Ms, "n_realizations": n,
        "optimal": s[:, :, 0].mean(1), "optimal_stderr": se[:, 0],
        "equal": s[:, :, 1].mean(1), "equal_stderr": se[:, 1],
        "snr_per_sensor": s[:, :, 2].mean(1), "snr_per_sensor_stderr": se[:, 2],
        "min_gap": np.min((s[:, :, 1] - s[:, :, 0]) / s[:, :, 0], axis=1),
        "max_residual": np.max(np.abs(s[:, :, 3:]), axis=(1, 2)),
        "sbar_optimal": s_opt, "sbar_equal": s_eq,
        "law_optimal": sw + a**2 / (Ms * s_opt), "law_equal": sw + a**2 / (Ms * s_eq),
        "sigma_w2": sw, "p_none": float(power.stationary_variance(a, sw)),
    }


@common.plot_doc()
def plot(data: dict):
    """Two panels: (a) the mean P∞ against M; (b) its excess over σ_w² on log axes, with the
    1/M laws (straight lines of slope −1)."""
    fig, (ax1, ax2) = plotting.subplots(2, 1, stack=True)
    M, sw = data["M"], data["sigma_w2"]
    names = {"optimal": "optimal allocation", "equal": "equal power"}
    for key, name in names.items():
        kw = {"mfc": "none", "capsize": 2, **plotting.look(key)}
        err = 1.96 * data[f"{key}_stderr"]
        ax1.errorbar(M, data[key], yerr=err, label=f"{name} (mean ± 1.96 s.e.)", **kw)
        ax2.errorbar(M, data[key] - sw, yerr=err,
                     label=f"{name}: " + r"$P_\infty - \sigma_w^2$", **kw)
        ax2.plot(M, data[f"law_{key}"] - sw, label=f"1/M law of {name}",
                 **plotting.look(key, "limit", marker="None", lw=1.4))
    ax1.axhline(data["p_none"], label=r"no measurements: $\sigma_w^2/(1 - a^2)$",
                **plotting.look(quantity="limit"))
    ax1.axhline(sw, label=r"floor $\sigma_w^2$ ($M \to \infty$)",
                **plotting.look(quantity="limit", ls=":"))
    for ax in (ax1, ax2):
        ax.set_xscale("log", base=2)
        ax.set_xticks(M, [str(m) for m in M])
        ax.set_xlim(0.8, 160)
        ax.set_xlabel("number of sensors $M$ (sensors)")
        ax.legend(loc="upper right", ncol=2)
    ax1.set(ylim=YLIM_P, ylabel=r"steady-state error $P_\infty$ (state units$^2$)",
            title=rf"(a) budget $\gamma_{{\mathrm{{total}}}}$ = {data['gamma_total']:.2g}; "
                  f"{data['n_realizations']} draws of the sensors per M")
    ax2.set_yscale("log")
    ax2.set(ylim=YLIM_EXCESS, ylabel=r"$P_\infty - \sigma_w^2$ (state units$^2$)",
            title=f"(b) mean SNR per sensor s̄ = {data['sbar_optimal']:.3g} (optimal), "
                  f"{data['sbar_equal']:.3g} (equal power)")
    return plotting.finish(fig)


@common.checks_doc()
def checks(data: dict) -> list[Claim]:
    """Optimal never worse, the budget spent, one sensor the same, the mean SNR of the 1/M
    law against the draws, and the trend in M."""
    z = np.abs(data["snr_per_sensor"] - data["sbar_optimal"]) / data["snr_per_sensor_stderr"]
    one = abs(data["optimal"][0] / data["equal"][0] - 1)
    out = []
    for key, name in (("optimal", "optimal allocation"), ("equal", "equal power")):
        m, se = data[key], data[f"{key}_stderr"]
        out.append(Claim(
            f"{name}: the mean error at M = {data['M'][-1]} is below M = {data['M'][0]}'s by "
            f"more than {Z_TOL:.0f} s.e.", bool(m[0] - m[-1] > Z_TOL * np.hypot(se[0], se[-1])),
            f"{m[0]:.4f} → {m[-1]:.4f}"))
    return [
        Claim("the optimal allocation's error is never above equal power's (every draw, "
              "every M)", bool(np.all(data["min_gap"] >= -1e-9)),
              f"smallest (equal − optimal)/optimal P∞ {np.min(data['min_gap']):.2e}"),
        Claim("both allocations spend exactly the budget",
              bool(np.all(data["max_residual"] < 1e-9)),
              f"largest |Σ αᵢ² κᵢ/γ − 1| {np.max(data['max_residual']):.1e}"),
        Claim("with one sensor the two allocations are the same", one < 1e-12,
              f"relative difference {one:.1e}"),
        Claim("the mean SNR per sensor s̄ of the 1/M law (quadrature) is the draws' mean of "
              f"S*/M within {Z_TOL:.0f} s.e. at every M", bool(np.all(z < Z_TOL)),
              "z = " + ", ".join(f"{v:.2f}" for v in z)),
        *out,
    ]


def _facts(data: dict) -> dict[str, str]:
    i = int(np.flatnonzero(data["M"] == M_QUOTED)[0])
    return {"p_opt": f"{data['optimal'][i]:.3f}", "p_eq": f"{data['equal'][i]:.3f}",
            "p_opt_max": f"{data['optimal'][-1]:.4f}",
            "law_max": f"{data['law_optimal'][-1]:.4f}",
            "sbar": f"{data['sbar_optimal']:.3g}", "draws": f"{data['n_realizations']}"}


def _decreasing(values) -> bool:
    return bool(np.all(np.diff(np.asarray(values, dtype=float), axis=0) < 0))


@declare.sweep_doc("""The optimal allocation's error is never above equal power's, at
                   every budget, M and draw; both mean errors fall from one budget to the next
                   at every M.""", budgets=("tuple of float", "The slider's budgets, increasing."))
def sweep(budgets, frames) -> list[Claim]:
    """Along the slider: optimal never worse, and more power never hurts."""
    gap = min(float(np.min(f["min_gap"])) for f in frames)
    opt = np.array([f["optimal"] for f in frames])  # (budgets, M)
    eq = np.array([f["equal"] for f in frames])
    return [
        Claim(f"the optimal allocation's error is never above equal power's, at all "
              f"{len(frames)} budgets and every M (every draw)", gap >= -1e-9,
              f"smallest (equal − optimal)/optimal P∞ {gap:.2e}"),
        Claim("the mean error falls as the budget grows, at every M, for both allocations",
              _decreasing(opt) and _decreasing(eq),
              f"optimal at M = {frames[0]['M'][-1]}: {opt[0, -1]:.4f} at "
              f"γ_total = {budgets[0]:.2g} down to {opt[-1, -1]:.4f} at {budgets[-1]:.2g}"),
    ]


declare.register(
    id="leong2011-explore",
    paper="leong2011",
    caption="Multi-access over static channels (the sensors of Figs. 3-4), at the total power "
    "budget γ_total of the slider: the mean steady-state error of the optimal allocation "
    "(corrected (24)) and of equal power (16) against the number of sensors M, with the 1/M "
    "law each approaches.",
    chapter=CH_ALLOCATION,
    label="sec-leong2011-alloc-explore",
    parameters={**MODEL, "sigma_v2": STATIC["sigma_v2"], "h": STATIC["h"], "M": list(MS),
                "realizations": REALIZATIONS, "gamma_total_grid": list(BUDGETS)},
    functions=(compute, plot, checks, sweep, _facts),
    settable=SETTABLE,
    note="Our own figure, on the model of the paper's Figs. 3-4 (multi-access); M up to 128 "
    "and the 1/M laws at a fixed budget are ours.",
    slider=SLIDER,
)
