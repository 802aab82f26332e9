"""Part III (leong2011): the parameters shared by the figures, and their helpers."""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter.context import Parameter
from fusioncenter.figures.registry import Claim, Entry, register

#: Ids of the book's own figures registered here (not figures of the paper).
OWN_IDS: tuple[str, ...] = ()

CH_ASYMPTOTICS = "book/leong2011/asymptotics"
CH_ALLOCATION = "book/leong2011/allocation"
CH_FADING = "book/leong2011/fading"

#: Fig. 1 (paper, Section V.A); the range of M is our choice (the paper does not state it).
FIG1 = {"a": 0.8, "sigma_w2": 1.5, "sigma_n2": 1.0, "c": 1.0, "sigma_v2": 1.0, "h": 0.8,
        "alpha": "1/sqrt(M)", "M": [1, 100], "M_note": "range of M chosen (not stated)"}
#: Fig. 2: ranges from the paper; uniform draws, nested sensors and M range are our choices.
FIG2 = {"a": 0.9, "sigma_w2": 1.0, "sigma_n2": 1.0, "c_range": [0.5, 1.0],
        "sigma_v2_range": [0.5, 1.0], "h_range": [0.5, 1.0], "alpha": "1/sqrt(M)",
        "M": [1, 100],
        "draws": "one seeded draw of 100 sensors, each uniform on its range (distribution not "
                 "stated); the first M sensors are used for each M",
        "bounds": "(37) with the range endpoints as h_min, h_max, c_min, c_max, sigma_min^2, "
                  "sigma_max^2"}
#: Figs. 3-6: the paper's parameters; M grid, infeasibility handling and initial variances are
#: our choices.
STATIC = {"a": 0.9, "sigma_w2": 1.0, "sigma_n2": 1e-9, "c": 1.0,
          "sigma_v2": "chi2(1) per sensor", "h": "d^-2 with d ~ U(20, 100) m per sensor",
          "D": 2.0, "gamma_total": 1e-3, "M": list(range(2, 21, 2)),
          "realizations": {"fast": 100, "paper": 1000},
          "equal_power": "(a): least common per-sensor power (15) meeting D, alpha_i c_i > 0; "
                         "(b): (16)",
          "infeasible": "realizations where a compared scheme cannot meet D are redrawn "
                        "(M grid chosen; the paper states neither)"}
#: Figs. 5-6 (fading channels), as in :data:`STATIC` apart from the channel model.
FADING = {"a": 0.9, "sigma_w2": 1.0, "sigma_n2": 1e-9, "c": 1.0,
          "sigma_v2": "chi2(1) per sensor",
          "h": "Re, Im of h~_{i,k} i.i.d. d_i^-2 N(mu_i, 1); d_i ~ U(20, 100) m, "
               "mu_i ~ U(1/2, 1)",
          "D": 2.0, "gamma_total": 1e-3, "M": list(range(2, 21, 2)),
          "steps": {"fast": 200, "paper": 1000}, "realizations": {"fast": 20, "paper": 100},
          "P0": "(a) P_0 = D (the greedy scheme starts at the target, so every step solves the "
                "same problem, Section IV.D.1); (b) P_0 = sigma_w2/(1-a^2); averages over "
                "P_1..P_steps",
          "no_csi": "alpha~_i = alpha_i conj(E h~_i)/|E h~_i|, alpha optimized once for the "
                    "steady state of the linear MMSE estimator (32)",
          "lmmse_check": {"trials": {"fast": 1000, "paper": 2000}, "steps": 60},
          "infeasible": "(a): realizations where either scheme cannot meet D are redrawn "
                        "(M grid, P_0 and the redraw are our choices)"}

#: z-score tolerance of the Monte Carlo checks (as in the other parts).
Z_TOL = 4.0
#: closed forms against the numerical optimizer / constraint equalities
REL_TOL = 1e-6



def xy(D, a, sw):
    """The two sides of the error-target constraint ``P_inf <= D``.

    Parameters
    ----------
    D : float
        The error target.
    a, sw : float
        The state transition and the process-noise variance.

    Returns
    -------
    tuple of float
        ``(x, y) = (a^2 D + sw - D, D (D - sw))``: the target is met iff the SNR is at least
        ``x / y``.
    """
    return a**2 * D + sw - D, D * (D - sw)


def draw_sensors(rng: np.random.Generator, n: int, M: int) -> tuple[np.ndarray, np.ndarray]:
    """The random sensors of Figs. 3-6: ``sigma_v2 ~ chi2(1)``, distance ``d ~ U(20, 100)`` m.

    Parameters
    ----------
    rng : numpy.random.Generator
        The stream (``sigma_v2`` is drawn first, then ``d``).
    n, M : int
        Realizations and sensors per realization.

    Returns
    -------
    tuple of numpy.ndarray
        ``(sigma_v2, d)``, each ``(n, M)``.
    """
    return rng.chisquare(1, (n, M)), rng.uniform(20.0, 100.0, (n, M))


def m_seed(seed: int, M: int, salt: int = 0) -> int:
    """The seed of one point (``M`` sensors) of a figure, derived from the entry's seed.

    Parameters
    ----------
    seed : int
        The entry's seed.
    M : int
        The number of sensors.
    salt : int
        Separates the streams of different uses at the same ``M``.

    Returns
    -------
    int
        A 32-bit seed from ``numpy.random.SeedSequence([seed, M, salt])``.
    """
    return int(np.random.SeedSequence([seed, M, salt]).generate_state(1)[0])


#: The overridable parameters (Monte Carlo accuracy only: every claim applies).
SETTABLE_STATIC = (Parameter("realizations", "int", "random sensor draws per point",
                             dict(STATIC["realizations"]), minimum=2),)
SETTABLE_FADING = (Parameter("realizations", "int", "fading realizations per point",
                             dict(FADING["realizations"]), minimum=2),
                   Parameter("steps", "int", "fading steps per realization",
                             dict(FADING["steps"]), minimum=2))
#: Figs. 3-6 by the figure numbers of the multi-access and the orthogonal scheme: the chapter,
#: the parameters and the settable ones, the same for the four panels.
PANEL_GROUPS = {
    ("3", "4"): (CH_ALLOCATION, STATIC, SETTABLE_STATIC),
    ("5", "6"): (CH_FADING, FADING, SETTABLE_FADING),
}


#: The descriptions of the arguments that :func:`register_panels` binds in the compute functions
#: of Figs. 3-6 (for :func:`fusioncenter.figures.common.compute_doc`); these computes read their
#: overrides without checking them (:meth:`~fusioncenter.figures.registry.Entry.run_compute`
#: does), so they raise nothing of their own.
PANEL_DOC = {
    "access": ('{"multi-access", "orthogonal"}', "The access scheme."),
    "panel": ('{"a", "b"}', "Panel (a): the total power meeting the error target D = 2; (b): "
              "the error under the sum-power budget gamma_total."),
    "raises": (),
}

#: How a caption names each access scheme ("multi-access" already says "access").
ACCESS_NAMES = {"multi-access": "Multi-access", "orthogonal": "Orthogonal access"}


def register_panels(figs: tuple[str, str], functions: tuple, *, caption: str, error: str,
                    note: str) -> None:
    """Register panels (a) and (b) of a multi-access and an orthogonal figure (Figs. 3-6).

    Parameters
    ----------
    figs : tuple of str
        The figure numbers of the multi-access and the orthogonal scheme, a key of
        :data:`PANEL_GROUPS` (which gives the chapter, the parameters and the settable ones).
    functions : tuple
        ``(compute, plot, checks)``; ``compute(profile, seed, *, access, panel, **over)``.
    caption : str
        A template with ``{access}`` (capitalized) and ``{what}`` (the panel's quantity).
    error : str
        What panel (b) shows under the sum-power budget; panel (a) shows the total power meeting
        the error target.
    note : str
        The entries' note.

    Returns
    -------
    None
    """
    compute, plot, checks = functions
    chapter, parameters, settable = PANEL_GROUPS[figs]
    for fig, access in zip(figs, ("multi-access", "orthogonal"), strict=True):
        for panel in ("a", "b"):
            what = ("total power meeting the error target D = 2" if panel == "a" else
                    f"{error} under the sum-power budget γ_total = 10⁻³")
            register(Entry(
                id=f"leong2011-fig{fig}{panel}", paper="leong2011", kind="figure",
                caption=caption.format(access=ACCESS_NAMES[access], what=what),
                label=f"sec-leong2011-fig{fig}{panel}",
                compute=functools.partial(compute, access=access, panel=panel), plot=plot,
                checks=checks, status="reproduced", chapter=chapter, parameters=parameters,
                settable=settable, note=note))



def pooled_claims(data: dict, key: str, statement: str, ratios: tuple) -> list[Claim]:
    """The claim that orthogonal access gains or loses more than multi-access, pooled over M.

    Only the orthogonal figures (4 and 6) compute the comparison; for the others the list is
    empty. The realizations at each M are independent, so the mean over M of the paired
    differences has the standard error ``sqrt(sum(stderr**2)) / len(M)``; at the smallest M the
    two schemes are close and either may win on a given seed, the gap opens with M.

    Parameters
    ----------
    data : dict
        A panel's data; the comparison, where computed, is ``data[key + "_diff"]`` (per M, the
        paired difference, orthogonal minus multi-access) and its standard error
        ``data[key + "_diff_stderr"]``.
    key : str
        What is compared (``"benefit"``, ``"loss"``).
    statement : str
        What is claimed, without the closing ``", pooled over M (paired, 4 s.e.)"``.
    ratios : tuple
        ``(name, orthogonal, multi_access, digits)``: the data keys of the ratios shown in the
        detail, their name and the digits printed.

    Returns
    -------
    list of Claim
        Empty without the comparison, else the claim, true when the pooled z-score exceeds
        :data:`Z_TOL`.
    """
    if f"{key}_diff" not in data:
        return []
    diff, stderr = data[f"{key}_diff"], data[f"{key}_diff_stderr"]
    z = diff / stderr
    pooled = np.mean(diff) / (np.sqrt(np.sum(stderr ** 2)) / z.size)
    name, orthogonal, multi, digits = ratios
    return [Claim(
        f"{statement}, pooled over M (paired, {Z_TOL:.0f} s.e.)", bool(pooled > Z_TOL),
        f"pooled z = {pooled:.1f}; per M z = " + ", ".join(f"{v:.1f}" for v in z)
        + f"; {name}orthogonal " + ", ".join(f"{r:.{digits}f}" for r in data[orthogonal])
        + "; multi-access " + ", ".join(f"{r:.{digits}f}" for r in data[multi]))]


def _model(name: str, doc: str, default: float, minimum: float = 1e-9) -> Parameter:
    return Parameter(name, "float", doc, default, minimum=minimum, model=True)


#: The overridable parameters of Fig. 1: its symmetric model, and the largest M (our choice).
SETTABLE_FIG1 = (
    Parameter("a", "float", "state transition", FIG1["a"], minimum=-0.99, maximum=0.99,
              model=True),
    _model("sigma_w2", "process-noise variance", FIG1["sigma_w2"]),
    _model("sigma_n2", "channel-noise variance at the fusion centre", FIG1["sigma_n2"]),
    _model("c", "measurement gain of every sensor", FIG1["c"]),
    _model("sigma_v2", "measurement-noise variance of every sensor", FIG1["sigma_v2"]),
    _model("h", "channel gain of every sensor", FIG1["h"]),
    Parameter("M_max", "int", "largest number of sensors (M = 1..M_max)", FIG1["M"][1],
              minimum=50, maximum=10_000),
)
#: The overridable parameters of Fig. 2: its model (the sensor ranges are fixed), the largest M.
SETTABLE_FIG2 = (
    Parameter("a", "float", "state transition", FIG2["a"], minimum=-0.99, maximum=0.99,
              model=True),
    _model("sigma_w2", "process-noise variance", FIG2["sigma_w2"]),
    _model("sigma_n2", "channel-noise variance at the fusion centre", FIG2["sigma_n2"]),
    Parameter("M_max", "int", "largest number of sensors (one draw of M_max sensors)",
              FIG2["M"][1], minimum=5, maximum=10_000),
)
