"""Marks shared by the library's tests.

``heavy``: a test that computes registry entries (the papers' Monte Carlo at the fast profile),
sweeps numerical accuracy against mpmath, or starts a cluster of worker processes: seconds
each, about three quarters of the library suite's time, and numbers that come from NumPy, SciPy
and mpmath at the lock's versions. ``make test`` runs every test on the book's Python (3.11);
CI's ``make test WITH="pythons student"`` also runs every test but these on Python 3.12
(``tools/test_pythons.py --quick``); ``make test-pythons`` runs all of them on 3.12 and 3.13.
The list names test functions (every parametrization of one is marked);
``tests/test_run_tests.py`` checks that each names a test function that exists, so the list
cannot go stale silently.
"""

from __future__ import annotations

import pytest

HEAVY = (
    "test_plotting_style.py::test_registry_figure_uses_the_visual_language",
    "test_figures_dey2009.py::test_entry_computes_plots_and_passes",
    "test_figures_leong2011.py::test_entry_computes_plots_and_passes",
    "test_figures_mo2015.py::test_entry_computes_plots_and_passes",
    "test_figures_zheng2014.py::test_entry_computes_plots_and_passes",
    "test_registry_cli.py::test_own_entries_compute_plot_and_pass_their_checks",
    "test_settable_parts.py::test_an_override_reaches_the_data_and_is_recorded",
    "test_zheng2014_reading.py::test_payoff_rows_are_consistent_with_the_entries",
    "test_zheng2014_reading.py::test_bandwidth_claims_pass_on_the_fast_profile",
    "test_zheng2014_reading.py::test_bandwidth_table_of_table3_reproduces_the_registrys_z",
    "test_zheng2014_reading.py::test_bandwidth_claims_fail_on_corrupted_tables",
    "test_zheng2014_reading.py::test_payoff_claims_pass_on_the_fast_profile",
    "test_synthesis.py::test_entry_computes_plots_and_passes",
    "test_figures_zheng2014.py::test_choices_checks_fail_when_the_schemes_swap",
    "test_figures_mo2015.py::test_tracking_check_fails_on_an_optimistic_covariance",
    "test_censoring.py::test_log_region_probability_is_relative_accurate_in_the_tails",
    "test_censoring.py::test_bivariate_rectangle_is_relative_accurate_in_the_tails",
    "test_censoring.py::test_exact_filters_are_calibrated_and_proposition3_is_not",
    "test_censoring_vector.py::test_elongated_covariance_meets_the_documented_accuracy",
    "test_censoring_vector.py::test_far_tail_no_underflow_against_mpmath",
    "test_censoring_vector.py::test_very_elongated_ellipse_against_mpmath",
    "test_censoring_vector.py::test_printed_proposition6_does_not_sum_to_one",
    "test_context.py::test_data_are_bitwise_identical_under_every_executor",
    "test_cli_claims.py::test_module_entry_point_exit_codes",
    "test_interrupts.py::test_cli_signal_ends_the_run_and_its_pool",
    "test_interrupts.py::test_cli_a_dask_scheduler_killed_mid_run_exits_3",
    "test_registry_texts.py::test_claims_print_no_ascii_math_or_repr",
    "test_registry_texts.py::test_zheng2014_reading_claims_are_typeset",
)


def pytest_collection_modifyitems(config, items):
    for item in items:
        if f"{item.path.name}::{getattr(item, 'originalname', None) or item.name}" in HEAVY:
            item.add_marker(pytest.mark.heavy)
