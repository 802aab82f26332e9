"""Registry entries for the papers' own figures and tables.

Captions are ours (a description of what the figure shows, not the paper's wording); parameters
are those the paper states. An entry stays ``not-started`` until its part's issue gives it a
``compute``, a ``plot`` and ``checks``.
"""

from __future__ import annotations

from fusioncenter.figures.registry import Entry, register

_DEY = "book/dey2009/index"
_LEONG = "book/leong2011/index"
_ZHENG = "book/zheng2014/index"

_dey_scalar = {"a": 1.25, "c": 1.0, "sigma_w": 1.0, "sigma_n": 2.0, "lambda": 100.0,
               "sigma_v": "several values (not all stated)", "paths": 50_000, "steps": 100}
_dey_multi = {"a": 1.25, "c": [1.0, 1.0], "sigma_w": 1.0, "sigma_v": [1.0, 2.0], "sigma_n": 2.0,
              "lambda": "not stated", "paths": 50_000, "steps": 100}

for _id, _cap, _par in [
    ("dey2009-fig1", "Expected error covariance E[p_k] under Rayleigh fading against the "
     "tight and loose upper-bound sequences, for several measurement-noise levels.", _dey_scalar),
    ("dey2009-fig2", "As Fig. 1 for Nakagami(1/2) fading.", _dey_scalar),
    ("dey2009-fig3", "Two sensors, multi-access (coherent sum) channel: E[p_k] and the bounds "
     "s_k and t_k.", _dey_multi),
    ("dey2009-fig4", "Two sensors, orthogonal channels: E[p_k] and the bounds s_k and t_k.",
     _dey_multi),
]:
    register(Entry(id=_id, paper="dey2009", kind="figure", caption=_cap, chapter=_DEY,
                   parameters=dict(_par)), placeholder=True)

for _id, _cap in [
    ("leong2011-fig1", "Steady-state error P_inf against the number of sensors M compared with "
     "its 1/M asymptotic expression (multi-access, alpha_i = 1/sqrt(M))."),
    ("leong2011-fig2", "P_inf for general sensor parameters with the upper and lower bounds "
     "of Lemma 4 (multi-access, alpha_i = 1/sqrt(M))."),
    ("leong2011-fig3a", "Multi-access: total power of optimal vs equal allocation meeting an "
     "error-covariance target."),
    ("leong2011-fig3b", "Multi-access: error covariance of optimal vs equal allocation under a "
     "sum-power constraint."),
    ("leong2011-fig4a", "Orthogonal access: total power of optimal vs equal allocation meeting "
     "an error-covariance target."),
    ("leong2011-fig4b", "Orthogonal access: error covariance of optimal vs equal allocation "
     "under a sum-power constraint."),
    ("leong2011-fig5a", "Multi-access with fading: full channel-state information vs none, "
     "error-covariance constraint."),
    ("leong2011-fig5b", "Multi-access with fading: full channel-state information vs none, "
     "sum-power constraint."),
    ("leong2011-fig6a", "Orthogonal access with fading: full channel-state information vs none, "
     "error-covariance constraint."),
    ("leong2011-fig6b", "Orthogonal access with fading: full channel-state information vs none, "
     "sum-power constraint."),
]:
    register(Entry(id=_id, paper="leong2011", kind="figure", caption=_cap, chapter=_LEONG),
             placeholder=True)

_z_lin = {"N": 2, "T": 20, "trials": 5000, "particles": 1000}
for _id, _kind, _cap, _par in [
    ("zheng2014-fig1", "figure", "Linear tracking, scalar observations, feedback, N = 2, l = 1: "
     "position and velocity RMSE of all-send, random selection, CFoMD and CFwMD.",
     {**_z_lin, "l": 1, "feedback": "state"}),
    ("zheng2014-fig2", "figure", "Position RMSE of CFwMD with and without covariance feedback "
     "(CFwMD2) for several l, N = 4.", {**_z_lin, "N": 4, "l": [1, 1.2, 1.5, 2, 3]}),
    ("zheng2014-fig3", "figure", "As Fig. 1 without feedback.",
     {**_z_lin, "l": 1, "feedback": "none"}),
    ("zheng2014-fig4", "figure", "Vector observations (H = I, R = diag(2, 4)), feedback, N = 2: "
     "RMSE of the four schemes.", {"N": 2, "R": "diag(2, 4)"}),
    ("zheng2014-fig5", "figure", "Vector observations: CFwMD vs CFwMD2 for several l, N = 4.",
     {"N": 4}),
    ("zheng2014-fig6", "figure", "Vector observations without feedback, N = 2: RMSE of the four "
     "schemes.", {"N": 2, "feedback": "none"}),
    ("zheng2014-fig7", "figure", "Nonlinear tracking: target trajectory and the 3 x 3 sensor "
     "grid in the 20 m x 20 m region.", {"N": 9, "region_m": 20}),
    ("zheng2014-fig8", "figure", "Nonlinear tracking with state feedback, l = 2: RMSE of the "
     "four schemes.", {"N": 9, "l": 2, "trials": 200, "particles": 10_000}),
    ("zheng2014-fig9", "figure", "Nonlinear tracking: RMSE against the average number of "
     "transmissions per step.", {"N": 9}),
    ("zheng2014-fig10", "figure", "Nonlinear tracking: CFwMD vs CFwMD2 for l in {2, 4, 6}.",
     {"N": 9, "l": [2, 4, 6]}),
    ("zheng2014-table1", "table", "Average number of transmissions per step, scalar "
     "observations, CFwMD vs CFwMD2, for each l.", {"N": 4}),
    ("zheng2014-table2", "table", "Average number of transmissions per step, vector "
     "observations, CFwMD vs CFwMD2.", {"N": 4}),
    ("zheng2014-table3", "table", "Average number of transmissions per step, nonlinear system, "
     "CFwMD vs CFwMD2.", {"N": 9}),
]:
    register(Entry(id=_id, paper="zheng2014", kind=_kind, caption=_cap, chapter=_ZHENG,
                   parameters=dict(_par)), placeholder=True)
