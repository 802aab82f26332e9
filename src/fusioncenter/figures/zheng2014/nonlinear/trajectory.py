"""zheng2014 Fig. 7: the sensor grid and where the target goes (no filtering).

One sample trajectory of :data:`~fusioncenter.figures.zheng2014.nonlinear.scenario.SCENARIO`
and an ensemble of :data:`TRAJECTORIES` for the statements: the target leaves the region near
the end, so the nearest sensor recedes.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from fusioncenter import censoring, plotting
from fusioncenter.context import Parameter
from fusioncenter.figures.common import checks_doc, compute_doc, plot_doc
from fusioncenter.figures.registry import Claim
from fusioncenter.figures.zheng2014.contrasts import z_score
from fusioncenter.figures.zheng2014.nonlinear.scenario import SCENARIO, Z_ORDER, entry

#: Trajectories simulated for the statements of Fig. 7 (cheap: no filtering).
TRAJECTORIES = 10_000
#: The overridable parameters of Fig. 7.
SETTABLE_FIG7 = (
    Parameter("trajectories", "int", "simulated trajectories (the ensemble of the statements)",
              TRAJECTORIES, minimum=2),
    Parameter("sigma2", "float", "process noise intensity sigma^2 of the white-noise "
              "acceleration (m^2/s^3)", SCENARIO.sigma2, minimum=1e-12, model=True),
)


@compute_doc(
    "``time`` (T+1,) s; ``trajectory``, ``velocity`` (T+1, 2) of the sample; ``mean_path`` "
    "(T+1, 2); ``sensors`` (N, 2), ``region_half_width``; ``fraction_outside`` and "
    "``nearest_distance`` (T+1,) over the ensemble, ``nearest_distance_increase`` (last 5 s) "
    "with its ``_stderr``; ``ensemble`` (its size), ``x0``, ``seed``.", raises=(),
    profile="Unused: the data are the same in both profiles.")
def compute_fig7(profile: str, seed: int, **over) -> dict:
    """Fig. 7: one sample trajectory, and an ensemble of ``trajectories`` (default
    :data:`TRAJECTORIES`, process noise ``sigma2``) for where the target goes (no filtering)."""
    sc = SCENARIO
    if "sigma2" in over:
        sc = dataclasses.replace(sc, sigma2=over["sigma2"])
    rng = np.random.default_rng(seed)
    x, _ = sc.sample(rng, 1)
    ens, _ = sc.sample(rng, over.get("trajectories", TRAJECTORIES))
    half = sc.region / 2
    pos = ens[..., [0, 2]]  # (n, T+1, 2)
    outside = np.any(np.abs(pos) > half, axis=-1)
    dist = np.linalg.norm(pos[:, :, None, :] - sc.positions, axis=-1).min(axis=-1)
    dist_d = dist[:, -1] - dist[:, sc.T // 2]
    return {"time": np.arange(sc.T + 1) * sc.dt, "trajectory": x[0][:, [0, 2]],
            "velocity": x[0][:, [1, 3]], "mean_path": pos.mean(axis=0),
            "sensors": sc.positions, "region_half_width": half,
            "fraction_outside": outside.mean(axis=0), "nearest_distance": dist.mean(axis=0),
            "nearest_distance_increase": float(dist_d.mean()),
            "nearest_distance_increase_stderr": float(dist_d.std(ddof=1) / math.sqrt(dist_d.size)),
            "ensemble": int(ens.shape[0]), "x0": np.asarray(sc.x0), "seed": seed}


@plot_doc()
def plot_fig7(data: dict):
    """Fig. 7: the region, the numbered sensors, the sample trajectory and the mean path."""
    fig, ax = plotting.subplots(figsize=(6.4, 7.4), stack=True)  # a square map, full width
    h = data["region_half_width"]
    ax.plot([-h, h, h, -h, -h], [-h, -h, h, h, -h], color="0.4", lw=1.0, ls="-",
            label="region of interest")
    s = data["sensors"]
    ax.plot(s[:, 0], s[:, 1], ls="none", marker="^", markersize=8, color=plotting.OKABE_ITO[1],
            label="sensors")
    for i, (px, py) in enumerate(s):
        ax.annotate(str(i + 1), (px, py), textcoords="offset points", xytext=(5, 4), fontsize=8)
    tr = data["trajectory"]
    ax.plot(tr[:, 0], tr[:, 1], marker="o", markersize=3, color=plotting.OKABE_ITO[0],
            ls="-", label="sample trajectory (0.5 s steps)")
    ax.plot(*data["mean_path"].T, color="0.3", ls="--", lw=1.0, label="mean path")
    ax.plot(*tr[0], marker="s", color="k", ls="none", label="start ($t = 0$)")
    ax.set(xlabel="x (m)", ylabel="y (m)", aspect="equal",
           title="Sensor grid and target trajectory")
    ax.legend(ncol=2)
    return plotting.finish(fig)


@checks_doc()
def checks_fig7(data: dict) -> list[Claim]:
    """Fig. 7: the grid, the start, the target leaving, the nearest sensor receding at the end."""
    s, h = data["sensors"], data["region_half_width"]
    xs, ys = np.unique(np.round(s[:, 0], 9)), np.unique(np.round(s[:, 1], 9))
    grid = len(s) == 9 and len(xs) == 3 and len(ys) == 3 and np.all(np.abs(s) <= h)
    tr = data["trajectory"]
    inside = np.all(np.abs(tr) <= h, axis=-1)
    fo = data["fraction_outside"]
    T = len(fo) - 1
    z_d = z_score(data["nearest_distance_increase"], data["nearest_distance_increase_stderr"])
    xy = [censoring.scenarios.values_text(np.round(v, 2)) for v in (xs, ys, tr[0], tr[-1])]
    return [
        Claim("N = 9 sensors on a 3 × 3 grid inside the 20 m × 20 m region", bool(grid),
              f"abscissae {xy[0]} m, ordinates {xy[1]} m, half-width {h:g} m"),
        Claim("the sample trajectory starts at x₀ = (−8, −8) m inside the region and crosses it",
              bool(np.allclose(tr[0], data["x0"][[0, 2]]) and inside[: T // 2].all()
                   and np.ptp(tr[:, 0]) > h and np.ptp(tr[:, 1]) > h),
              f"start {xy[2]} m, end {xy[3]} m", paper_specific=True),
        Claim("the target moves out of the region near the end (most trajectories are inside at "
              "t = 5 s and outside at t = 10 s)", bool(fo[T // 2] < 0.1 and fo[-1] > 0.5),
              f"fraction outside: {fo[T // 2]:.3f} at 5 s, {fo[-1]:.3f} at 10 s "
              f"({data['ensemble']} trajectories)", paper_specific=True),
        Claim("so the distance to the nearest sensor grows over the last 5 s (less information "
              "at the end)", bool(z_d > Z_ORDER),
              f"mean increase {data['nearest_distance_increase']:.2f} m, z = {z_d:.1f}",
              paper_specific=True),
    ]



entry(
    "zheng2014-fig7", "figure", "reproduced", (compute_fig7, plot_fig7, checks_fig7),
    {"trajectories": TRAJECTORIES},
    "Nonlinear tracking: the 3 × 3 sensor grid in the 20 m × 20 m region and a sample "
    "target trajectory (with the mean path).",
    "The sensor positions are our choice (the paper draws them but does "
    "not list them); the statements checked are where the target goes (it leaves the region "
    "near the end), from 10⁴ simulated trajectories.", settable=SETTABLE_FIG7)

