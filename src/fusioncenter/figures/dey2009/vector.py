"""Part II (dey2009), ``dey2009-vector``: a 2-state example of Section 3.2, ``E[P_k]`` against
``Zbar_k`` (the book's own figure).
"""

from __future__ import annotations

import itertools

import numpy as np
import scipy.integrate
import scipy.stats

from fusioncenter import fading, plotting
from fusioncenter.context import Parameter
from fusioncenter.figures.common import checks_doc, compute_doc, plot_doc, register_figure, settings
from fusioncenter.figures.dey2009.common import (
    BLOCK,
    CH_VECTOR,
    N_DIRECTIONS,
    PATHS,
    STEPS,
    VECTOR,
    Z_TOL,
    abs_z,
    dominance_claim,
    stationary_claim,
    window_stats,
)
from fusioncenter.figures.registry import Claim

#: The overridable parameters of ``dey2009-vector``.
SETTABLE_VECTOR = (
    Parameter("paths", "int", "Monte Carlo paths", dict(PATHS), minimum=2),
    Parameter("lam", "float", "Rayleigh parameter lambda of the channel (1 / mean power gain)",
              VECTOR["lam"], minimum=1e-6, model=True),
)


def _vector_model(lam: float):
    v = VECTOR
    return (np.array(v["A"]), np.array(v["c"]), np.array(v["Sigma_w"]), v["sigma_v2"],
            v["sigma_n2"], fading.Rayleigh(lam), np.array(v["P0"]))


def _theorem33_by_quadrature(Z, A, c, Sw, sv2, sn2, lam) -> np.ndarray:
    """``E_r[f_r(Z)]`` of (14) for Rayleigh ``r``, each entry by ``scipy.integrate.quad``."""
    def f(r):
        S = c @ Z @ c + sv2
        Zc = Z @ c
        post = Z - np.outer(Zc, Zc) / S * r / (r + sn2 / S)
        return A @ post @ A.T + Sw

    out = np.empty_like(Z)
    for i, j in itertools.product(range(Z.shape[0]), repeat=2):
        out[i, j] = scipy.integrate.quad(lambda r, i=i, j=j: f(r)[i, j] * lam * np.exp(-lam * r),
                                         0.0, np.inf, epsabs=0.0, epsrel=1e-12, limit=200)[0]
    return out


@compute_doc("""``k`` (101,), ``n_paths``, ``seed``; ``mean_triu``, ``stderr_triu`` (101, 3) the
             Monte Carlo mean of (P11, P12, P22) and its standard error; ``Z`` (101, 2, 2) the
             bounding sequence; ``theta`` (:data:`N_DIRECTIONS`,) directions and ``mean_vPv``,
             ``stderr_vPv``, ``Z_vPv`` (101, directions) the quadratic forms v^T E[P_k] v
             and v^T Zbar_k v; ``min_eig_Z_minus_mean`` (101,); ``quad_k`` (5,) steps at which
             ``Z_next_quadrature`` (5, 2, 2) evaluates Theorem 3.3's recursion (14) by
             quadrature; ``window_diff`` and ``window_diff_stderr`` (float) for the trace; with
             ``lam`` overridden, ``lam``.""",
             profile="Sets the number of paths (:data:`PATHS`).")
def compute_vector(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-vector``: E[P_k] of the 2-state example against Zbar_k (Section 3.2)."""
    v = settings("dey2009-vector", SETTABLE_VECTOR, profile, over)
    A, c, Sw, sv2, sn2, ch, P0m = _vector_model(v["lam"])
    n = v["paths"]
    res = fading.vector_paths(A, c, Sw, sv2, sn2, ch, P0m, STEPS, n, seed, block_size=BLOCK)
    Z = fading.vector_bound(A, c, Sw, sv2, sn2, ch, P0m, STEPS)
    theta = np.linspace(0.0, np.pi, N_DIRECTIONS, endpoint=False)
    # v' P v from the upper triangle (P11, P12, P22)
    W = np.stack([np.cos(theta) ** 2, 2 * np.cos(theta) * np.sin(theta), np.sin(theta) ** 2], 1)
    # the quadratic forms (n, k, directions) one step at a time: all at once they take n * 101
    # * 48 doubles (1.9 GB for the paper's 50 000 paths) and three temporaries of that size
    mean_vpv, std_vpv = np.empty((STEPS + 1, theta.size)), np.empty((STEPS + 1, theta.size))
    for k in range(STEPS + 1):
        quad_form = res.samples[:, k] @ W.T  # (n, directions)
        mean_vpv[k], std_vpv[k] = quad_form.mean(axis=0), quad_form.std(axis=0, ddof=1)
    trace = res.samples[..., 0] + res.samples[..., 2]
    d, dse = window_stats(trace)
    qk = (0, 1, 10, 50, STEPS - 1)
    out = {
        "k": np.arange(STEPS + 1), "n_paths": n, "seed": seed,
        "mean_triu": res.mean, "stderr_triu": res.stderr, "Z": Z,
        "theta": theta, "mean_vPv": mean_vpv, "stderr_vPv": std_vpv / np.sqrt(n),
        "Z_vPv": np.einsum("kij,di,dj->kd", Z, np.stack([np.cos(theta), np.sin(theta)], 1),
                           np.stack([np.cos(theta), np.sin(theta)], 1)),
        "min_eig_Z_minus_mean": np.linalg.eigvalsh(
            Z - fading.triu_to_symmetric(res.mean, 2)).min(axis=1),
        "quad_k": np.array(qk),
        "Z_next_quadrature": np.array([_theorem33_by_quadrature(Z[k], A, c, Sw, sv2, sn2,
                                                                v["lam"]) for k in qk]),
        "window_diff": d, "window_diff_stderr": dse,
    }
    if "lam" in over:
        out["lam"] = v["lam"]
    return out


@plot_doc()
def plot_vector(data: dict):
    """(a) The entries of E[P_k] against Zbar_k and (b) the PSD order by direction."""
    fig, (ax, ax2) = plotting.subplots(1, 2, stack=True)
    k = data["k"]
    names = [(0, (0, 0), "$[E P_k]_{11}$", r"$\bar Z_{k,11}$"),
             (1, (0, 1), "$[E P_k]_{12}$", r"$\bar Z_{k,12}$"),
             (2, (1, 1), "$[E P_k]_{22}$", r"$\bar Z_{k,22}$")]
    for j, (col, (a, b), mname, zname) in enumerate(names):
        color = plotting.OKABE_ITO[j]
        plotting.errorband(ax, k, data["mean_triu"][:, col], data["stderr_triu"][:, col],
                           color=color, ls="-", label=f"{mname} (MC)")
        ax.plot(k, data["Z"][:, a, b], color=color, ls="--", label=zname)
    ax.set(xlabel="time step $k$", ylabel="error covariance entries (units of $x^2$)",
           yscale="log", title="2-state example, Rayleigh $\\lambda$ = "
           f"{data.get('lam', VECTOR['lam']):g}; "
           f"{data['n_paths']} paths")
    ax.legend(ncol=2)
    ratio = data["mean_vPv"][-1] / data["Z_vPv"][-1]
    se = data["stderr_vPv"][-1] / data["Z_vPv"][-1]
    plotting.errorband(ax2, data["theta"], ratio, se, color=plotting.OKABE_ITO[0], ls="-",
                       label=rf"$v^\top E[P_{{{k[-1]}}}]\,v\,/\,v^\top \bar Z_{{{k[-1]}}}\,v$"
                       " ± 1.96 s.e.")
    ax2.axhline(1.0, color="0.2", lw=0.8, label="bound")
    ax2.set(xlabel=r"direction $v = (\cos\theta, \sin\theta)$: angle $\theta$ (rad)",
            ylabel="ratio of quadratic forms (dimensionless)", title="PSD order, steady state")
    ax2.legend()
    return plotting.finish(fig)


@checks_doc("One claim per statement, each with the measured z-score or difference.")
def checks_vector(data: dict) -> list[Claim]:
    """E[P_k] <= Zbar_k in the PSD order, exactness at k = 1, the closed form, convergence."""
    Z = data["Z"]
    iu = np.triu_indices(2)
    z1 = abs_z(data["mean_triu"][1], data["stderr_triu"][1], Z[1][iu])
    qk = data["quad_k"]
    closed = Z[qk + 1]
    quad_rel = np.max(np.abs(closed - data["Z_next_quadrature"])) / np.max(np.abs(closed))
    conv = np.max(np.abs(Z[-1] - Z[-2])) / np.max(np.abs(Z[-1]))
    return [
        Claim("exact at k = 1 (P₀ deterministic): E[P₁] = Z̄₁ entrywise within 4 s.e.",
              bool(np.all(z1 < Z_TOL)), f"|z| = {', '.join(f'{x:.2f}' for x in z1)} "
              "(0 where the entry is deterministic)"),
        dominance_claim(f"E[Pₖ] ≤ Z̄ₖ in the PSD order: vᵀE[Pₖ]v ≤ vᵀZ̄ₖv + 4 s.e. "
                         f"for {N_DIRECTIONS} directions and every k",
                         data["mean_vPv"].T, data["stderr_vPv"].T, data["Z_vPv"].T),
        Claim("the closed form of Section 3.2 equals Theorem 3.3's recursion (14) evaluated by "
              "quadrature", bool(quad_rel < 1e-8), f"max relative difference {quad_rel:.1e}"),
        Claim("Z̄ₖ converges (|Z̄₁₀₀ − Z̄₉₉| ≤ 10⁻⁹ |Z̄₁₀₀|)", bool(conv < 1e-9),
              f"{conv:.1e}", paper_specific=True),
        stationary_claim("E[tr Pₖ] has converged: windows 60 ≤ k < 80 and 80 ≤ k ≤ 100 agree "
                          "within 4 s.e.", [data["window_diff"]], [data["window_diff_stderr"]],
                          paper_specific=True),
    ]


register_figure(
    id="dey2009-vector",
    paper="dey2009",
    caption="Vector state, scalar measurement (Section 3.2): the entries of E[Pₖ] by Monte "
    "Carlo against the bounding sequence Z̄ₖ for a 2-state example; below: the PSD order at "
    "steady state, direction by direction.",
    chapter=CH_VECTOR,
    label="sec-dey2009-vector",
    parameters={**VECTOR, "steps": STEPS, "paths": PATHS, "directions": N_DIRECTIONS,
                "block_size": BLOCK, "note": "Our own example: an unstable mode (1.25) driving "
                "a stable one (0.9), only the first state measured."},
    functions=(compute_vector, plot_vector, checks_vector),
    settable=SETTABLE_VECTOR,
    note="Our own figure (the paper has none for Section 3.2); E[Pₖ] ≤ Z̄ₖ in the PSD "
    "order within the stated Monte Carlo error.",
)

