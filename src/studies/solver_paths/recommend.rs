//! Which path and size to use by default: the candidates that meet the accuracy targets,
//! each timed where the choice is felt, on the default scenario (physics and sensor
//! chains, records dropped): the per-step solve is not the whole cost, since every sensor
//! read and the deflected shape go through the model's point operators, which are 4
//! entries for FE but dense over the masses (lumped) or the modes (modal).

use std::hint::black_box;
use std::time::Instant;

use serde::Serialize;

use super::{SolverPath, SolverPathsReport};
use crate::error::Result;
use crate::scenario::Scenario;
use crate::sim::{prepare, run, Record, Recorder};

/// Largest midspan moment error (max-norm over the peak) accepted for the default: what
/// the midspan strain gauge of the default scenario reads.
pub const MOMENT_TARGET: f64 = 1e-2;

/// A path at the smallest size that meets the targets, timed on the default scenario.
#[derive(Debug, Clone, Serialize)]
pub struct Candidate {
    pub path: SolverPath,
    pub size: usize,
    /// Median wall time of the default scenario with this model, physics and sensors
    /// only (ms).
    pub scenario_physics_ms: f64,
    /// Simulated time of that scenario (s).
    pub scenario_simulated_s: f64,
}

/// Smallest size of `path` whose spatial error is at most the time-step floor for the
/// deflection, acceleration RMS and tyre forces on every road (so refining further cannot
/// gain more than a factor 2 at dt = 1 ms), and whose moment error is within
/// `moment_target`.
pub fn smallest_adequate_size(
    report: &SolverPathsReport,
    path: SolverPath,
    moment_target: f64,
) -> Option<usize> {
    let mut sizes: Vec<usize> = report
        .points
        .iter()
        .filter(|p| p.path == path)
        .map(|p| p.size)
        .collect();
    sizes.sort_unstable();
    sizes.dedup();
    sizes.into_iter().find(|&size| {
        report.references.iter().all(|(surface, reference)| {
            report.point(path, size, surface).is_some_and(|p| {
                let (s, f) = (&p.spatial, &reference.time_step_floor);
                s.deflection <= f.deflection
                    && s.acceleration_rms <= f.acceleration_rms
                    && s.force <= f.force
                    && p.errors.moment <= moment_target
            })
        })
    })
}

/// Every path's candidate (paths with no adequate size have none), timed.
pub fn candidates(
    report: &SolverPathsReport,
    repetitions: usize,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<Candidate>> {
    let mut out = Vec::new();
    for path in SolverPath::ALL {
        if let Some(size) = smallest_adequate_size(report, path, MOMENT_TARGET) {
            progress(&format!(
                "solver-paths candidate {} {size}: default scenario timing",
                path.name()
            ));
            let (physics_s, simulated_s) = scenario_physics_s(path, size, repetitions)?;
            out.push(Candidate {
                path,
                size,
                scenario_physics_ms: 1e3 * physics_s,
                scenario_simulated_s: simulated_s,
            });
        }
    }
    Ok(out)
}

/// The cheapest candidate on the default scenario.
pub fn recommended(candidates: &[Candidate]) -> Option<&Candidate> {
    candidates
        .iter()
        .min_by(|a, b| a.scenario_physics_ms.total_cmp(&b.scenario_physics_ms))
}

/// Drops every record (the output is not what is compared).
struct Discard;

impl Recorder for Discard {
    fn record(&mut self, record: Record) -> Result<()> {
        black_box(&record);
        Ok(())
    }
}

/// Median wall time of the default scenario with `path` at `size` (after a warm-up run),
/// and its simulated time (s).
fn scenario_physics_s(path: SolverPath, size: usize, repetitions: usize) -> Result<(f64, f64)> {
    let mut scenario = Scenario::default_scenario();
    scenario.bridge.model = path.spec(size);
    let resolved = scenario.resolve()?;
    let prepared = prepare(&resolved)?;
    let mut times = Vec::new();
    for i in 0..=repetitions.max(1) {
        let started = Instant::now();
        run(&resolved, &prepared, &mut Discard, &mut |_, _| {})?;
        if i > 0 {
            times.push(started.elapsed().as_secs_f64());
        }
    }
    times.sort_by(f64::total_cmp);
    Ok((times[times.len() / 2], resolved.duration_s()))
}
