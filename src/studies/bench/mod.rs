//! `bridgetwin bench`: one table, measured in one run, of what a coupled step costs on
//! each solver path and how accurate that path is, against the paper's direct method, plus
//! the end-to-end real-time factor of the default scenario.
//!
//! Per-step times are medians of repetitions after a warm-up (`timing`), with the truck's
//! two axles on the span (`setup`, shared with the criterion bench `coupled_step`). The
//! accuracy of each path at each size comes from the solver-paths study's converged
//! reference (FE 400 elements, dt = 0.25 ms) on its class A road: the relative errors of
//! the peak midspan deflection and the peak tyre force.

pub mod chains;
mod end_to_end;
pub mod girder;
mod report;
pub mod setup;
pub mod timing;

use std::collections::BTreeMap;
use std::time::Instant;

use serde::Serialize;

use crate::error::Result;
use crate::physics::bridge::BridgeModel;
use crate::physics::road::{IsoClass, RoadProfile};
use crate::physics::vehicle::VehicleDynamics;
use crate::studies::dlc::Surface;
use crate::studies::solver_paths::{compare, PathErrors, PathsCase, Reference, ReferenceModels};

pub use end_to_end::{
    collect_records, default_scenario, measure as measure_end_to_end, physics_only, write_mcap,
    Discard, EndToEnd,
};
pub use setup::BenchPath;
use timing::{time_per_step, TimingPlan};

/// Node counts of the full bench and of `--quick`.
pub fn node_counts(quick: bool) -> &'static [usize] {
    if quick {
        &[50, 100]
    } else {
        &[50, 100, 300, 1000]
    }
}

/// One path at one node count.
#[derive(Debug, Clone, Serialize)]
pub struct BenchRow {
    pub path: BenchPath,
    pub nodes: usize,
    pub dof: usize,
    /// Median wall time of one coupled step (us).
    pub us_per_step: f64,
    pub us_per_step_min: f64,
    pub us_per_step_max: f64,
    pub steps_per_repetition: u64,
    pub repetitions: usize,
    /// The direct method's median at the same node count (us).
    pub direct_us_per_step: f64,
    /// direct_us_per_step / us_per_step.
    pub speedup_vs_direct: f64,
    /// Wall time to build the bridge model (s).
    pub model_build_s: f64,
    /// Against the reference; `None` for the direct method, which gives the lumped
    /// low-rank path's response to round-off (tested in `solver::direct`).
    pub accuracy: Option<PathErrors>,
}

/// What the reference of the accuracy columns is and whether it passed its check.
#[derive(Debug, Clone, Serialize)]
pub struct ReferenceSummary {
    pub description: String,
    pub converged: bool,
    /// FE 200 elements at dt = 0.5 ms against the reference.
    pub check: PathErrors,
    /// FE 400 elements at dt = 1 ms against the reference.
    pub time_step_floor: PathErrors,
}

/// Everything `bridgetwin bench` measured.
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    pub quick: bool,
    pub nodes: Vec<usize>,
    pub rows: Vec<BenchRow>,
    pub reference: ReferenceSummary,
    pub end_to_end: EndToEnd,
    /// 16 realistic measurement chains against ideal sensors.
    pub chains: chains::ChainCost,
    /// The three-span example against the single span, 150 FE elements each.
    pub girder: girder::GirderCost,
    pub wall_s: f64,
}

impl BenchReport {
    /// The plain-text table `bridgetwin bench` prints.
    pub fn to_table(&self) -> String {
        report::table(self)
    }
}

/// Runs the bench; `progress` receives one line per measurement.
pub fn run(quick: bool, progress: &mut dyn FnMut(&str)) -> Result<BenchReport> {
    let started = Instant::now();
    let plan = TimingPlan::for_bench(quick);
    let vehicle = setup::truck()?;
    let accuracy = Accuracy::new(&vehicle, progress)?;
    let mut rows = Vec::new();
    for &nodes in node_counts(quick) {
        rows.extend(rows_at(nodes, &plan, &vehicle, &accuracy, progress)?);
    }
    progress("end to end, default scenario");
    let end_to_end = end_to_end::measure(if quick { 3 } else { 7 })?;
    progress("measurement chains: 16 channels, ideal vs mems_lownoise + clocks + faults");
    let chains = chains::measure(if quick { 1 } else { 5 })?;
    progress("continuous girder: three spans vs one, 150 elements");
    let girder = girder::measure(&plan, if quick { 1 } else { 3 })?;
    Ok(BenchReport {
        quick,
        nodes: node_counts(quick).to_vec(),
        rows,
        reference: accuracy.summary(),
        end_to_end,
        chains,
        girder,
        wall_s: started.elapsed().as_secs_f64(),
    })
}

/// Times every path at `nodes` and fills in the ratios to the direct method.
fn rows_at(
    nodes: usize,
    plan: &TimingPlan,
    vehicle: &VehicleDynamics,
    accuracy: &Accuracy,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<BenchRow>> {
    let mut models: BTreeMap<&str, (BridgeModel, f64)> = BTreeMap::new();
    let mut rows = Vec::new();
    for path in BenchPath::ALL {
        // The direct method runs on the lumped model: the paper's method.
        let key = path.model_key();
        if !models.contains_key(key) {
            let t = Instant::now();
            let model = path.model(nodes)?;
            models.insert(key, (model, t.elapsed().as_secs_f64()));
        }
        let (model, build_s) = &models[key];
        progress(&format!("{} nodes={nodes}: timing", path.name()));
        let timing = time_per_step(plan, setup::path_timer(path, model, vehicle));
        let accuracy = match path {
            BenchPath::Direct => None,
            _ => {
                progress(&format!("{} nodes={nodes}: accuracy run", path.name()));
                Some(accuracy.of(model, vehicle)?)
            }
        };
        rows.push(BenchRow {
            path,
            nodes,
            dof: model.n_dof(),
            us_per_step: 1e6 * timing.median_step_s,
            us_per_step_min: 1e6 * timing.min_step_s,
            us_per_step_max: 1e6 * timing.max_step_s,
            steps_per_repetition: timing.steps_per_rep,
            repetitions: timing.repetitions,
            direct_us_per_step: f64::NAN,
            speedup_vs_direct: f64::NAN,
            model_build_s: *build_s,
            accuracy,
        });
    }
    let direct = rows
        .iter()
        .find(|r| r.path == BenchPath::Direct)
        .map_or(f64::NAN, |r| r.us_per_step);
    for row in &mut rows {
        row.direct_us_per_step = direct;
        row.speedup_vs_direct = direct / row.us_per_step;
    }
    Ok(rows)
}

/// The solver-paths reference on the class A road, for the accuracy columns.
struct Accuracy {
    case: PathsCase,
    road: RoadProfile,
    reference: Reference,
}

impl Accuracy {
    fn new(vehicle: &VehicleDynamics, progress: &mut dyn FnMut(&str)) -> Result<Self> {
        progress("accuracy reference (FE 400 elements, dt = 0.25 ms, class A road)");
        let case = PathsCase::default();
        let road = case.road(Surface::Iso(IsoClass::A))?;
        let models = ReferenceModels::build(&case)?;
        let reference = case.reference(&models, vehicle, &road)?;
        Ok(Accuracy {
            case,
            road,
            reference,
        })
    }

    /// The errors of `model` (low-rank coupling, dt = 1 ms) against the reference.
    fn of(&self, model: &BridgeModel, vehicle: &VehicleDynamics) -> Result<PathErrors> {
        let history = self.case.run(model, self.case.dt_s, vehicle, &self.road)?;
        Ok(compare(&history, &self.reference.history))
    }

    fn summary(&self) -> ReferenceSummary {
        ReferenceSummary {
            description: "FE 400 elements at dt = 0.25 ms; two_axle_truck at 20 m/s on \
                          the ISO 8608 class A road of the solver-paths study"
                .into(),
            converged: self.reference.converged(),
            check: self.reference.check,
            time_step_floor: self.reference.time_step_floor,
        }
    }
}
