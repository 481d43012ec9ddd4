//! Studies that reproduce the paper's figures and go past them. Each writes CSV, SVG
//! figures and a `summary.md` into its output directory.

pub mod analytic;
pub mod bench;
pub mod continuous;
pub mod discretization;
pub mod dlc;
pub mod hslm;
mod output;
pub mod plot;
pub mod solver_paths;
pub mod verify;

use std::path::Path;

use crate::error::{Error, Result};

/// The end of a divergence message in the studies and the verification ladder: they choose
/// their own step and models, so those are what to check.
pub(crate) const DIVERGENCE_HINT: &str = "check dt_s and the model";

/// Runs the named study into `out`; `progress` receives one line per case.
pub fn run_named(
    name: &str,
    out: &Path,
    quick: bool,
    progress: &mut dyn FnMut(&str),
) -> Result<()> {
    match name {
        "discretization" => discretization::run(out, quick, progress).map(|_| ()),
        "dlc" => dlc::run(out, quick, progress).map(|_| ()),
        "solver-paths" => solver_paths::run(out, quick, progress).map(|_| ()),
        "continuous" => continuous::run(out, quick, progress).map(|_| ()),
        "hslm" => hslm::run(out, quick, progress).map(|_| ()),
        other => Err(Error::invalid(
            "study",
            other,
            "is not a study (known: discretization, dlc, solver-paths, continuous, hslm)",
        )),
    }
}
