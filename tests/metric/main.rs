//! The metric layers (`grid`, `localize`, `baseline`, `coop`): hand-worked cases, brute-force
//! properties, and the MRCLAM runs.

#[allow(dead_code)]
#[path = "../support/mod.rs"]
mod support;

mod baseline_pf;
mod baseline_rmcl;
mod baseline_sim;
mod coop_cases;
mod coop_mrclam;
mod grid_cases;
mod grid_mrclam;
mod grid_place;
mod grid_props;
mod grid_robust;
mod localize_perturb;
