//! The end-to-end tests, one module per subject, in one binary: the crate and its dependencies
//! are linked once, not once per file. Two tests keep binaries of their own, because they
//! measure the whole process: `tests/ldl_cache.rs` (process-wide cache counts that must start at
//! zero) and `tests/ipopt_leaks.rs` (the resident memory, which other tests running beside it
//! would move).

#[path = "../support/mod.rs"]
mod support;

mod added_terms;
mod built_in_task;
mod check_cli;
mod check_findings;
mod cluster_cli;
mod cycle_time_cli;
mod docs_cli;
mod docs_links;
mod dynamics_alloc;
mod dynamics_cli;
mod ends_cli;
mod evaluation_log;
mod examples_cli;
mod experiment_cli;
mod export_cli;
mod hold_cli;
mod horizon_cli;
mod hostile_cli;
mod index_page;
mod limits_cli;
mod linkage_numbers_cli;
mod migrate_cli;
mod motions_cli;
mod motors_cli;
mod ocp_reference;
mod optimize_cli;
mod outputs_cli;
mod parts_cli;
mod plot_figures_cli;
mod plots_cli;
mod poses_cli;
mod reliability_cli;
mod run_summary_cli;
mod solve_cli;
mod start_cli;
mod table_cli;
mod tcp_goal_cli;
mod urdf_idioms;
mod via_cli;
