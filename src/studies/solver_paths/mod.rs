//! Solver paths measured against each other on the paper's case: the lumped-mass model
//! with low-rank contact coupling (dense K = F^-1, factorized once), Hermite finite
//! elements (banded sparse Cholesky) and modal reduction (the first m modes of an FE
//! model), all with `CoupledSolver` and bilateral contact at dt = 1 ms.
//!
//! The reference is a converged full-order solution: FE with 400 elements at dt = 0.25 ms,
//! checked against 200 elements at 0.5 ms (halving both moves it by less than the
//! tolerances in [`REFERENCE_TOLERANCE`], so its own error is a fraction of that: Newmark
//! is second order in dt). FE with 400 elements at the paths' dt = 1 ms gives the time-step
//! floor: what no spatial refinement at dt = 1 ms can remove.
//!
//! The case: the 30 m bridge (EI 5.629e10 N m^2, 12 000 kg/m, 2 % Rayleigh on modes 1
//! and 2), the `two_axle_truck` half car at 20 m/s from 100 m before the bridge, on a
//! smooth road and on realisation 0 of the DLC study's ISO 8608 class A road (seed
//! 1964200), until 1 s after the rear axle leaves.

mod history;
mod metrics;
mod recommend;
mod report;
mod summary;

use std::path::Path;

use serde::Serialize;

use super::dlc::{DlcSetup, Surface};
use crate::error::Result;
use crate::physics::bridge::{BeamProperties, BridgeModel, LumpedStiffness, ModelSpec};
use crate::physics::road::{IsoClass, RoadProfile};
use crate::physics::vehicle::VehicleDynamics;

pub use history::{run_crossing, storage_for, CrossingInput, History};
pub use metrics::{compare, low_pass, PathErrors};
pub use recommend::{recommended, smallest_adequate_size, Candidate, MOMENT_TARGET};

/// One way of solving the coupled problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverPath {
    /// N lumped masses, K = F^-1 dense, prefactored dense Cholesky, low-rank contacts.
    LumpedLowRank,
    /// N Hermite elements, banded sparse Cholesky, low-rank contacts.
    FeBanded,
    /// The first m modes of an FE model (4 x m elements, at least 40), diagonal matrices.
    Modal,
}

impl SolverPath {
    pub const ALL: [SolverPath; 3] = [
        SolverPath::LumpedLowRank,
        SolverPath::FeBanded,
        SolverPath::Modal,
    ];

    /// Name in tables and files.
    pub fn name(self) -> &'static str {
        match self {
            SolverPath::LumpedLowRank => "lumped_low_rank",
            SolverPath::FeBanded => "fe_banded",
            SolverPath::Modal => "modal",
        }
    }

    /// What `size` counts.
    pub fn size_name(self) -> &'static str {
        match self {
            SolverPath::LumpedLowRank => "masses",
            SolverPath::FeBanded => "elements",
            SolverPath::Modal => "modes",
        }
    }

    /// The model of this path with `size` masses, elements or modes.
    pub fn spec(self, size: usize) -> ModelSpec {
        match self {
            SolverPath::LumpedLowRank => ModelSpec::LumpedMass {
                nodes: size,
                stiffness: LumpedStiffness::Auto,
            },
            SolverPath::FeBanded => ModelSpec::FiniteElement { elements: size },
            SolverPath::Modal => ModelSpec::Modal {
                modes: size,
                elements: None,
            },
        }
    }
}

/// The scenario every path runs.
#[derive(Debug, Clone)]
pub struct PathsCase {
    pub beam: BeamProperties,
    /// Rayleigh damping ratio on modes 1 and 2.
    pub damping_ratio: f64,
    pub speed_m_s: f64,
    /// Front axle this far before the bridge at t = 0 (m).
    pub approach_m: f64,
    /// Free vibration after the rear axle leaves (s).
    pub free_time_s: f64,
    /// Time step of the paths (s).
    pub dt_s: f64,
    /// Master seed of the class A road (the DLC study's).
    pub seed: u64,
}

impl Default for PathsCase {
    fn default() -> Self {
        PathsCase {
            beam: BeamProperties::paper_default(),
            damping_ratio: 0.02,
            speed_m_s: 20.0,
            approach_m: 100.0,
            free_time_s: 1.0,
            dt_s: 1e-3,
            seed: 1_964_200,
        }
    }
}

/// The two roads of the study.
pub const SURFACES: [Surface; 2] = [Surface::Smooth, Surface::Iso(IsoClass::A)];

/// Elements of the reference, and its steps per path step (0.25 ms at dt = 1 ms).
pub const REFERENCE_ELEMENTS: usize = 400;
const REFERENCE_STEPS: usize = 4;
/// Elements and steps per path step of the reference's check (half of each).
pub const CHECK_ELEMENTS: usize = 200;
const CHECK_STEPS: usize = 2;

/// Largest change allowed between the reference and its check (FE 200, dt x 2): well
/// below the errors the paths show at dt = 1 ms (time-step floor: deflection ~1e-4,
/// acceleration RMS ~1e-2, force ~1e-4 of static).
pub const REFERENCE_TOLERANCE: PathErrors = PathErrors {
    deflection: 1e-4,
    acceleration_max: 2e-2,
    acceleration_rms: 1e-2,
    force: 1e-4,
    moment: 1e-3,
    peak_deflection: 1e-4,
    peak_force: 1e-4,
};

impl PathsCase {
    /// Simulated time: until the rear axle is `free_time_s` past the bridge, rounded up to
    /// a whole number of path steps (so every finer grid lands on the same instants).
    pub fn duration_s(&self, vehicle: &VehicleDynamics) -> f64 {
        let travel_m = self.approach_m + self.beam.length_m() + vehicle.wheelbase_m();
        let t = travel_m / self.speed_m_s + self.free_time_s;
        (t / self.dt_s).ceil() * self.dt_s
    }

    /// The road of `surface` (realisation 0 of the DLC study's stream for the class).
    pub fn road(&self, surface: Surface) -> Result<RoadProfile> {
        let setup = DlcSetup {
            beam: self.beam.clone(),
            approach_m: self.approach_m,
            seed: self.seed,
            ..DlcSetup::default()
        };
        setup.road(surface, 0)
    }

    /// Builds the model of `spec` on this case's beam.
    pub fn model(&self, spec: &ModelSpec) -> Result<BridgeModel> {
        BridgeModel::build(&self.beam, spec, self.damping_ratio)
    }

    /// One crossing of `model` at time step `dt_s` on `road`.
    pub fn run(
        &self,
        model: &BridgeModel,
        dt_s: f64,
        vehicle: &VehicleDynamics,
        road: &RoadProfile,
    ) -> Result<History> {
        run_crossing(
            model,
            &CrossingInput {
                vehicle,
                road,
                speed_m_s: self.speed_m_s,
                approach_m: self.approach_m,
                duration_s: self.duration_s(vehicle),
                dt_s,
            },
        )
    }

    /// The converged reference on `road`, its own check and the time-step floor.
    pub fn reference(
        &self,
        models: &ReferenceModels,
        vehicle: &VehicleDynamics,
        road: &RoadProfile,
    ) -> Result<Reference> {
        let history = self.run(
            &models.fine,
            self.dt_s / REFERENCE_STEPS as f64,
            vehicle,
            road,
        )?;
        let check_dt = self.dt_s / CHECK_STEPS as f64;
        let check = compare(&self.run(&models.check, check_dt, vehicle, road)?, &history);
        let same_dt = self.run(&models.fine, self.dt_s, vehicle, road)?;
        let time_step_floor = compare(&same_dt, &history);
        Ok(Reference {
            history,
            check,
            same_dt,
            time_step_floor,
        })
    }
}

/// The two FE models of the reference (built once: each build solves a dense
/// eigenproblem of its size for the Rayleigh fit, about a second at 800 DOFs).
pub struct ReferenceModels {
    /// `REFERENCE_ELEMENTS` elements.
    pub fine: BridgeModel,
    /// `CHECK_ELEMENTS` elements.
    pub check: BridgeModel,
}

impl ReferenceModels {
    /// Builds both on `case`'s beam.
    pub fn build(case: &PathsCase) -> Result<Self> {
        let fe = |elements| case.model(&ModelSpec::FiniteElement { elements });
        Ok(ReferenceModels {
            fine: fe(REFERENCE_ELEMENTS)?,
            check: fe(CHECK_ELEMENTS)?,
        })
    }
}

/// The reference of one road.
#[derive(Debug, Clone)]
pub struct Reference {
    /// FE 400 elements at dt / 4: the converged solution.
    pub history: History,
    /// FE 200 elements at dt / 2 against it.
    pub check: PathErrors,
    /// FE 400 elements at the paths' dt: the spatially converged solution at that dt.
    pub same_dt: History,
    /// `same_dt` against `history`: the time-step error alone, which no spatial
    /// refinement at the paths' dt removes.
    pub time_step_floor: PathErrors,
}

impl Reference {
    /// The reference's own convergence check, on the history metrics (deflection,
    /// acceleration RMS, force): (i) halving the elements and the step moves it by at most
    /// [`REFERENCE_TOLERANCE`], and (ii) by at most `CHECK_TO_FLOOR` of the time-step
    /// floor. Newmark's error goes as dt^2, so with space converged the change
    /// (dt/2 -> dt/4) is (1/4 - 1/16) / (1 - 1/16) = 0.2 of the floor (dt -> dt/4); a
    /// larger ratio means the reference is not in the asymptotic range, or space is not
    /// converged at 200 elements. Passing both puts the reference's own error (about a
    /// third of the change) at about 1/15 of the floor.
    pub fn converged(&self) -> bool {
        let (c, f, t) = (&self.check, &self.time_step_floor, &REFERENCE_TOLERANCE);
        [
            (c.deflection, f.deflection, t.deflection),
            (c.acceleration_rms, f.acceleration_rms, t.acceleration_rms),
            (c.force, f.force, t.force),
        ]
        .iter()
        .all(|&(change, floor, tol)| change <= tol && change <= CHECK_TO_FLOOR * floor)
    }
}

/// Largest ratio change / time-step floor the reference check accepts (0.2 expected).
pub const CHECK_TO_FLOOR: f64 = 0.35;

/// One path at one size on one road.
#[derive(Debug, Clone, Serialize)]
pub struct PathPoint {
    pub path: SolverPath,
    pub size: usize,
    pub dof: usize,
    pub surface: String,
    /// Against the converged reference (time step and space).
    pub errors: PathErrors,
    /// Against FE 400 at the same dt: the spatial (or modal truncation) error alone.
    pub spatial: PathErrors,
    /// Wall time of the whole crossing per step, approach included (us; see `bench`).
    pub us_per_step: f64,
}

/// Everything the study computed.
#[derive(Debug, Clone)]
pub struct SolverPathsReport {
    pub case: PathsCase,
    pub points: Vec<PathPoint>,
    /// (road label, reference) per road.
    pub references: Vec<(String, Reference)>,
    /// Histories for the figures: per road the reference and each path at its smallest size.
    pub examples: Vec<Example>,
    /// Each path at its smallest adequate size, timed on the default scenario.
    pub candidates: Vec<Candidate>,
}

/// One history kept for the figures.
#[derive(Debug, Clone)]
pub struct Example {
    pub surface: String,
    pub label: String,
    pub history: History,
}

impl SolverPathsReport {
    /// The point of `path` at `size` on `surface`.
    pub fn point(&self, path: SolverPath, size: usize, surface: &str) -> Option<&PathPoint> {
        self.points
            .iter()
            .find(|p| p.path == path && p.size == size && p.surface == surface)
    }

    /// The reference of `surface`.
    pub fn reference(&self, surface: &str) -> Option<&Reference> {
        self.references
            .iter()
            .find(|(s, _)| s == surface)
            .map(|(_, r)| r)
    }
}

/// The sizes of each path (masses, elements or modes).
pub fn sizes(path: SolverPath, quick: bool) -> &'static [usize] {
    match (path, quick) {
        (SolverPath::Modal, false) => &[3, 5, 10, 20, 40],
        (SolverPath::Modal, true) => &[3, 5, 10],
        // 30 elements: the default scenario's model.
        (SolverPath::FeBanded, false) => &[10, 20, 30, 50, 100, 300],
        (_, false) => &[10, 20, 50, 100, 300],
        (_, true) => &[10, 20, 50],
    }
}

/// Runs every path and size on both roads against the reference and writes CSV, figures
/// and summary.md into `out`.
pub fn run(out: &Path, quick: bool, progress: &mut dyn FnMut(&str)) -> Result<SolverPathsReport> {
    let case = PathsCase::default();
    let truck = DlcSetup::truck()?;
    let mut report = SolverPathsReport {
        case: case.clone(),
        points: Vec::new(),
        references: Vec::new(),
        examples: Vec::new(),
        candidates: Vec::new(),
    };
    progress("solver-paths reference models");
    let models = ReferenceModels::build(&case)?;
    for surface in SURFACES {
        let road = case.road(surface)?;
        progress(&format!("solver-paths reference, road {}", surface.label()));
        let reference = case.reference(&models, &truck, &road)?;
        report.examples.push(example(
            surface,
            "reference FE 400, dt/4",
            &reference.history,
        ));
        for path in SolverPath::ALL {
            for (i, &size) in sizes(path, quick).iter().enumerate() {
                let label = format!("{} {size}", path.name());
                progress(&format!("solver-paths {label}, road {}", surface.label()));
                let model = case.model(&path.spec(size))?;
                let history = case.run(&model, case.dt_s, &truck, &road)?;
                report
                    .points
                    .push(point(path, size, surface, &history, &reference));
                if i == 0 {
                    report.examples.push(example(surface, &label, &history));
                }
            }
        }
        report.references.push((surface.label(), reference));
    }
    report.candidates = recommend::candidates(&report, if quick { 3 } else { 5 }, progress)?;
    report::write_outputs(out, &report)?;
    Ok(report)
}

fn point(
    path: SolverPath,
    size: usize,
    surface: Surface,
    history: &History,
    reference: &Reference,
) -> PathPoint {
    PathPoint {
        path,
        size,
        dof: dof(path, size),
        surface: surface.label(),
        errors: compare(history, &reference.history),
        spatial: compare(history, &reference.same_dt),
        us_per_step: 1e6 * history.loop_wall_s / (history.len() - 1) as f64,
    }
}

fn example(surface: Surface, label: &str, history: &History) -> Example {
    Example {
        surface: surface.label(),
        label: label.to_string(),
        history: history.clone(),
    }
}

/// DOFs of a path's model.
pub fn dof(path: SolverPath, size: usize) -> usize {
    match path {
        SolverPath::FeBanded => 2 * size,
        _ => size,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A history with no samples (the convergence check only reads the error sets).
    fn empty_history() -> History {
        History {
            dt_s: 1e-3,
            deflection_m: Vec::new(),
            acceleration_m_s2: Vec::new(),
            moment_n_m: Vec::new(),
            force_n: [Vec::new(), Vec::new()],
            on_span: [Vec::new(), Vec::new()],
            static_n: [1.0, 1.0],
            loop_wall_s: 0.0,
        }
    }

    fn reference(check: PathErrors, floor: PathErrors) -> Reference {
        Reference {
            history: empty_history(),
            check,
            same_dt: empty_history(),
            time_step_floor: floor,
        }
    }

    fn errors(deflection: f64, acceleration_rms: f64, force: f64) -> PathErrors {
        PathErrors {
            deflection,
            acceleration_rms,
            force,
            ..PathErrors::default()
        }
    }

    #[test]
    fn convergence_check_needs_small_changes_that_shrink_like_dt_squared() {
        let floor = errors(8e-5, 2e-2, 1.4e-4);
        // As measured: changes ~0.2 of the floor, within the tolerances.
        assert!(reference(errors(1.9e-5, 4e-3, 2.8e-5), floor).converged());
        // A change at half the floor: not in the asymptotic range (or space unconverged).
        assert!(!reference(errors(1.9e-5, 1e-2, 2.8e-5), floor).converged());
        // Within the ratio but above the absolute tolerance.
        let big_floor = errors(1e-3, 2e-2, 1.4e-4);
        assert!(!reference(errors(2e-4, 4e-3, 2.8e-5), big_floor).converged());
    }

    #[test]
    fn durations_land_on_the_coarse_grid() {
        let case = PathsCase::default();
        let truck = DlcSetup::truck().unwrap();
        let t = case.duration_s(&truck);
        let steps = t / case.dt_s;
        assert!((steps - steps.round()).abs() < 1e-9, "{t}");
        // 100 m approach + 30 m span + 4.27 m wheelbase at 20 m/s, plus 1 s.
        assert!((t - (134.27 / 20.0 + 1.0)).abs() < case.dt_s);
    }
}
