"""Part III (leong2011), Figs. 5-6: Rician fading, greedy allocation with full CSI vs the
linear MMSE estimator without CSI.
"""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter import context, montecarlo, plotting, power
from fusioncenter.figures.common import checks_doc, compute_doc, plot_doc
from fusioncenter.figures.leong2011 import common
from fusioncenter.figures.registry import Claim
from fusioncenter.profile import by_profile


def _draw_fading(rng: np.random.Generator, n: int, M: int):
    sv, d = common.draw_sensors(rng, n, M)
    mu = rng.uniform(0.5, 1.0, (n, M))
    return sv, d, mu


def _fading_stats(d, mu):
    """Channel statistics: mean ``d^-2 mu (1 + j)``, variances ``d^-4`` of Re and Im."""
    return d**-2.0 * mu * (1 + 1j), d**-4.0, d**-4.0


def _fading_feasible(access: str, sv, d, mu) -> np.ndarray:
    p = common.FADING
    x, y = common.xy(p["D"], p["a"], p["sigma_w2"])
    c = np.full(sv.shape, p["c"])
    ok = np.sum(c**2 / sv, -1) > x / y  # CSI: the threshold does not depend on the gains
    rho, tau, _ = power.lmmse_coefficients(p["a"], p["sigma_w2"], c, sv, *_fading_stats(d, mu))
    return ok & (np.sum(rho**2 / tau, -1) > x / y)


def _fading_values(access: str, panel: str, h, c, sv, hm, vr, vi):
    """Per realization: (CSI value, no-CSI value, CSI residual, no-CSI residual)."""
    p = common.FADING
    a, sw, sn, D, g = p["a"], p["sigma_w2"], p["sigma_n2"], p["D"], p["gamma_total"]
    kap = power.kappa(a, sw, c, sv)
    if panel == "a":
        P, pw = power.greedy_min_power(access, D, a, sw, h, c, sv, sn, infeasible="nan")
        al = power.lmmse_min_power(access, D, a, sw, c, sv, sn, hm, vr, vi)
        P_nocsi = power.lmmse_steady_state(access, al, a, sw, c, sv, sn, hm, vr, vi)
        return (pw.mean(-1), np.sum(al**2 * kap, -1), np.max(P[:, 1:], -1) / D - 1,
                P_nocsi / D - 1)
    P, _, spent = power.greedy_min_error(access, g, a, sw, h, c, sv, sn)
    al = power.lmmse_min_error(access, g, a, sw, c, sv, sn, hm, vr, vi)
    P_nocsi = power.lmmse_steady_state(access, al, a, sw, c, sv, sn, hm, vr, vi)
    return (P[:, 1:].mean(-1), P_nocsi, np.max(np.abs(spent / g - 1), -1),
            np.sum(al**2 * kap, -1) / g - 1)


def _fading_chunk(rng: np.random.Generator, n: int, *, access: str, panel: str, M: int,
                  steps: int, other: bool) -> np.ndarray:
    """``n`` realizations, each simulated for ``steps`` fading steps. Columns: ``[CSI value,
    no-CSI value, CSI residual, no-CSI residual, draws]`` where the value is the time-averaged
    sum power (a) or P (b), and the residuals are ``max_k P_{k+1}/D - 1`` / ``P_inf/D - 1``
    (a) or the power residuals (b); with ``other``, the other access scheme's two values on the
    same realizations and fading follow."""
    p = common.FADING
    keep: list[tuple] = []
    draws = []
    since = 0
    while len(keep) < n:
        sv, d, mu = _draw_fading(rng, n, M)
        ok = _fading_feasible(access, sv, d, mu) if panel == "a" else np.ones(n, bool)
        for i in np.flatnonzero(ok)[: n - len(keep)]:
            draws.append(since + i + 1)
            since = -(i + 1)
            keep.append((sv[i], d[i], mu[i]))
        since += n
    sv, d, mu = (np.array([k[j] for k in keep]) for j in range(3))
    c = np.full(sv.shape, p["c"])
    hm, vr, vi = _fading_stats(d, mu)
    # fading: h~_{i,k} = d^-2 (mu + N + j (mu + N')), i.i.d. over k
    scale = d[:, None, :] ** -2.0
    hre = scale * (mu[:, None, :] + rng.standard_normal((n, steps, M)))
    him = scale * (mu[:, None, :] + rng.standard_normal((n, steps, M)))
    h = np.hypot(hre, him)
    cols = list(_fading_values(access, panel, h, c, sv, hm, vr, vi)) + [np.array(draws, float)]
    if other:
        o = "orthogonal" if access == "multi-access" else "multi-access"
        cols += list(_fading_values(o, panel, h, c, sv, hm, vr, vi)[:2])
    return np.column_stack(cols)


def _lmmse_trial(rng: np.random.Generator, n: int, *, access: str, steps: int, alpha_t, c, sv,
                 hm, vr, vi) -> np.ndarray:
    """Per trial: time average of ``(x_k - xhat_{k|k-1})^2 / P_{k|k-1} - 1`` (mean 0 if the
    filter's variances are its true errors)."""
    p = common.FADING
    x, xp, P = power.simulate_nocsi(rng, n, steps, access, alpha_t, p["a"], p["sigma_w2"], c,
                                    sv, p["sigma_n2"], hm, vr, vi)
    return ((x - xp) ** 2 / P - 1).mean(-1)


def _lmmse_check(profile: str, seed: int, access: str, panel: str):
    """Simulate the system and the no-CSI filter for one realization at three values of M."""
    p = common.FADING
    n = by_profile(profile, **p["lmmse_check"]["trials"])
    rng = np.random.default_rng(seed)
    Ms = (p["M"][0], p["M"][len(p["M"]) // 2], p["M"][-1])
    z, ratio = [], []
    for M in Ms:
        while True:
            sv, d, mu = _draw_fading(rng, 1, M)
            if panel == "b" or _fading_feasible(access, sv, d, mu)[0]:
                break
        c = np.full(M, p["c"])
        hm, vr, vi = _fading_stats(d[0], mu[0])
        if panel == "a":
            al = power.lmmse_min_power(access, p["D"], p["a"], p["sigma_w2"], c, sv[0],
                                       p["sigma_n2"], hm, vr, vi)
        else:
            al = power.lmmse_min_error(access, p["gamma_total"], p["a"], p["sigma_w2"], c,
                                       sv[0], p["sigma_n2"], hm, vr, vi)
        fn = functools.partial(_lmmse_trial, access=access, steps=p["lmmse_check"]["steps"],
                               alpha_t=power.beamformed(al, hm), c=c, sv=sv[0], hm=hm, vr=vr,
                               vi=vi)
        res = montecarlo.simulate(fn, n, common.m_seed(seed, M, 2))
        z.append(float(res.mean / res.stderr))
        ratio.append(float(1 + res.mean))
    return np.array(Ms), np.array(z), np.array(ratio), n


@compute_doc("""``M``, ``n_realizations``, ``steps``, ``seed``, ``access``, ``panel``; per M:
             ``csi``, ``nocsi`` (with ``*_stderr``) the mean power (a) or error variance (b) with
             and without CSI, ``log_ratio(_stderr)`` the paired mean log(no-CSI / CSI),
             ``csi_wins``, ``loss_ratio``, ``max_residual_csi``, ``max_residual_nocsi`` (the
             constraints), ``acceptance``; ``lmmse_M``, ``lmmse_z``, ``lmmse_mse_ratio``,
             ``lmmse_trials``, ``lmmse_steps`` (the check of (32)-(33)); orthogonal access also
             ``multi_loss_ratio``, ``loss_diff(_stderr)``.""", **common.PANEL_DOC,
             over="Overrides of ``realizations`` and ``steps`` (``SETTABLE_FADING``).")
def compute_fading(profile: str, seed: int, *, access: str, panel: str, **over) -> dict:
    """Data of ``leong2011-fig5a`` ... ``fig6b``: full CSI against no CSI on Rician fading,
    per number of sensors (paired realizations)."""
    p = common.FADING
    n = over.get("realizations") or by_profile(profile, **p["realizations"])
    steps = over.get("steps") or by_profile(profile, **p["steps"])
    other = access == "orthogonal"  # Fig. 6 also computes the multi-access loss
    rows = []
    for M in p["M"]:
        fn = functools.partial(_fading_chunk, access=access, panel=panel, M=M, steps=steps,
                               other=other)
        rows.append(montecarlo.simulate(fn, n, common.m_seed(seed, M), executor=context.executor()))
    s = np.stack([r.samples for r in rows])
    lr = np.log(s[:, :, 1] / s[:, :, 0])  # log(no-CSI / CSI), paired per realization
    Ms, z, ratio, n_mc = _lmmse_check(profile, common.m_seed(seed, 0, 3), access, panel)
    rt = np.sqrt(n)
    out = {
        "M": np.array(p["M"]), "n_realizations": n, "steps": steps, "seed": seed,
        "access": access, "panel": panel,
        "csi": s[:, :, 0].mean(1), "csi_stderr": s[:, :, 0].std(1, ddof=1) / rt,
        "nocsi": s[:, :, 1].mean(1), "nocsi_stderr": s[:, :, 1].std(1, ddof=1) / rt,
        "log_ratio": lr.mean(1), "log_ratio_stderr": lr.std(1, ddof=1) / rt,
        "csi_wins": np.mean(lr > 0, axis=1),
        "loss_ratio": s[:, :, 1].mean(1) / s[:, :, 0].mean(1),
        "max_residual_csi": np.max(s[:, :, 2], axis=1) if panel == "a"
        else np.max(np.abs(s[:, :, 2]), axis=1),
        "max_residual_nocsi": np.max(np.abs(s[:, :, 3]), axis=1),
        "acceptance": n / s[:, :, 4].sum(1),
        "lmmse_M": Ms, "lmmse_z": z, "lmmse_mse_ratio": ratio, "lmmse_trials": n_mc,
        "lmmse_steps": p["lmmse_check"]["steps"],
    }
    if other:
        lr2 = np.log(s[:, :, 6] / s[:, :, 5])
        d = lr - lr2
        out.update({"multi_loss_ratio": s[:, :, 6].mean(1) / s[:, :, 5].mean(1),
                    "loss_diff": d.mean(1), "loss_diff_stderr": d.std(1, ddof=1) / rt})
    return out


@plot_doc()
def plot_fading(data: dict):
    """Mean (and 1.96 s.e.) of both schemes against M (log scale in panel (a))."""
    fig, ax = plotting.subplots(stack=True)
    M = data["M"]
    names = (["full CSI, greedy per step (time average)", "no CSI, linear MMSE (32) "
              "(steady state)"] if data["panel"] == "b" else
             ["full CSI, greedy per step (time average)", "no CSI, linear MMSE (32)"])
    for key, scheme, name in zip(("csi", "nocsi"), ("full-csi", "no-csi"), names, strict=True):
        kw = {"mfc": "none", "capsize": 2, "label": f"{name} (mean ± 1.96 s.e.)",
              **plotting.look(scheme)}
        if data["panel"] == "a":  # a bar reaching zero is clipped at the axis, with a note
            plotting.errorbar_log(ax, M, data[key], 1.96 * data[f"{key}_stderr"], xname="M",
                                  **kw)
        else:
            ax.errorbar(M, data[key], yerr=1.96 * data[f"{key}_stderr"], **kw)
    if data["panel"] == "a":
        ylabel = "total transmit power $\\sum_i \\gamma_i$ (power units)"
        cons = "$D = 2$"
    else:
        ylabel = "error variance $P_{k+1|k}$ (state units$^2$)"
        cons = r"$\gamma_{\mathrm{total}} = 10^{-3}$"
    ax.set_xticks(M)
    ax.set(xlabel="number of sensors $M$", ylabel=ylabel,
           title=f"{data['access']}, Rician fading, {cons}; {data['n_realizations']} "
                 f"realizations × {data['steps']} steps")
    ax.legend()
    return plotting.finish(fig)


@checks_doc()
def checks_fading(data: dict) -> list[Claim]:
    """Full CSI beats no CSI, the constraints, the LMMSE variance (and, Fig. 6, the loss
    compared with multi-access)."""
    z = data["log_ratio"] / data["log_ratio_stderr"]
    what = "sum power" if data["panel"] == "a" else "error variance"
    if data["panel"] == "a":
        res = Claim("CSI: Pₖ₊₁ ≤ D at every step; no CSI: P∞ = D (relative 10⁻⁹)",
                    bool(np.all(data["max_residual_csi"] < 1e-9)
                         and np.all(data["max_residual_nocsi"] < 1e-9)),
                    f"max Pₖ/D − 1 = {np.max(data['max_residual_csi']):.1e}; "
                    f"|P∞/D − 1| ≤ {np.max(data['max_residual_nocsi']):.1e}")
    else:
        res = Claim("both schemes spend exactly γ_total (relative 10⁻⁹)",
                    bool(np.all(data["max_residual_csi"] < 1e-9)
                         and np.all(data["max_residual_nocsi"] < 1e-9)),
                    f"max residuals {np.max(data['max_residual_csi']):.1e}, "
                    f"{np.max(data['max_residual_nocsi']):.1e}")
    zl = data["lmmse_z"]
    wins = np.min(data["csi_wins"])  # floored, so that "at least" stays true when printed
    wins = ("every realization" if wins == 1 else
            f"at least {np.floor(1000 * wins) / 10:.1f} % of the realizations")
    out = [
        Claim(f"full CSI beats no CSI ({what}): mean log(no-CSI / CSI) > 0 at every M by more "
              f"than {common.Z_TOL:.0f} s.e. (paired)", bool(np.all(z > common.Z_TOL)),
              f"smallest z = {np.min(z):.1f}; CSI better on {wins} at every M; ratio "
              "of means no-CSI / CSI = " + ", ".join(f"{r:.3f}" for r in data["loss_ratio"])),
        res,
        Claim(f"the linear MMSE variance (32)-(33) is the simulated error: time-averaged "
              f"eₖ²/Pₖ = 1 within {common.Z_TOL:.0f} s.e. (system + fading + filter simulated)",
              bool(np.all(np.abs(zl) < common.Z_TOL)),
              "M = " + ", ".join(str(m) for m in data["lmmse_M"]) + ": ratio "
              + ", ".join(f"{r:.4f}" for r in data["lmmse_mse_ratio"])
              + f"; max |z| = {np.max(np.abs(zl)):.2f} ({data['lmmse_trials']} trials)"),
    ]
    return out + common.pooled_claims(
        data, "loss", "the loss without CSI is larger for orthogonal than for multi-access: mean "
        "log(no-CSI / CSI) larger", ("no-CSI / CSI ", "loss_ratio", "multi_loss_ratio", 2))


common.register_panels(
    ("5", "6"), (compute_fading, plot_fading, checks_fading), error="error variance",
    caption="{access}, Rician fading: full CSI (greedy allocation at every step) vs no CSI "
    "(linear MMSE estimator), {what}, against the number of sensors M.",
    note="Paper's parameters, 1000 steps × 100 realizations (paper profile). Our choices: M = 2, "
    "4, …, 20; P₀ = D in (a), σ_w²/(1 − a²) in (b); realizations where a scheme cannot "
    "meet D are redrawn (acceptance in the data).")
