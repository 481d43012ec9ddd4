//! The paper's section 11 and past it: dynamic axle loads of the two-axle truck crossing
//! the paper's 30 m bridge, against the impact factors of four design codes.
//!
//! (a) convergence of the midspan response and the contact forces with the node count
//! (lumped mass, Hermite FE) and with the time step; (b) smooth-road responses vs speed
//! (peak deflection, DAF against the static peak, peak acceleration; VBI and moving force);
//! (c) the paper's `DLC = max axle force / static` and the classic `sigma / static`
//! (Sweatman, Cebon) per axle vs speed on smooth, A, B and C roads, as mean and 5th/95th
//! percentiles over seeded road realisations; (d) the code impact factors at f1
//! (docs/physics.md section 8) and where the simulated DLC exceeds them.
//!
//! Every crossing starts the truck in static equilibrium `approach_m` before the bridge on
//! one continuous profile; only the tyre forces while the axle is on the span count.
//! Realisation r of a class uses its own child RNG stream (seed, class, r), and the same
//! road at every speed (common random numbers: the speed trend is not blurred by
//! road-to-road scatter).

mod codes;
mod crossing;
mod figures;
mod report;
mod stats;

use std::path::Path;
use std::time::Instant;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::error::Result;
use crate::physics::bridge::{BeamProperties, BridgeModel, LumpedStiffness, ModelSpec};
use crate::physics::road::{IsoClass, RoadProfile, RoadProfileSpec};
use crate::physics::vehicle::{HalfCarSpec, VehicleDynamics, VehicleModelSpec};

pub use codes::{china_jtg_d60_factor, design_codes};
pub use crossing::{simulate_crossing, Crossing};
pub use stats::{run_case, static_peak_midspan_m, DlcCase, Spread};

/// A road surface of the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Surface {
    Smooth,
    Iso(IsoClass),
}

impl Surface {
    /// The study's four surfaces, smoothest first.
    pub const STUDIED: [Surface; 4] = [
        Surface::Smooth,
        Surface::Iso(IsoClass::A),
        Surface::Iso(IsoClass::B),
        Surface::Iso(IsoClass::C),
    ];

    /// "smooth", "A", "B", ...
    pub fn label(self) -> String {
        match self {
            Surface::Smooth => "smooth".into(),
            Surface::Iso(c) => c.letter().to_string(),
        }
    }

    fn spec(self) -> RoadProfileSpec {
        match self {
            Surface::Smooth => RoadProfileSpec::Smooth,
            Surface::Iso(c) => RoadProfileSpec::iso8608(c),
        }
    }

    fn stream(self) -> u64 {
        match self {
            Surface::Smooth => 0,
            Surface::Iso(c) => 1 + c as u64,
        }
    }
}

/// The fixed parts of every crossing.
#[derive(Debug, Clone)]
pub struct DlcSetup {
    /// Default: the paper's 30 m bridge (f1 = 3.78 Hz).
    pub beam: BeamProperties,
    /// Rayleigh damping ratio on modes 1 and 2 (default 0.02).
    pub damping_ratio: f64,
    /// Bridge model of parts (b)-(d) (default Hermite FE, 30 elements; see part (a)).
    pub model: ModelSpec,
    /// Time step (default 1 ms).
    pub dt_s: f64,
    /// Distance of the front axle before the bridge at the start (default 100 m).
    pub approach_m: f64,
    /// Master seed of the road realisations (default 1964200, the paper's article number).
    pub seed: u64,
}

impl Default for DlcSetup {
    fn default() -> Self {
        DlcSetup {
            beam: BeamProperties::paper_default(),
            damping_ratio: 0.02,
            model: ModelSpec::FiniteElement { elements: 30 },
            dt_s: 1e-3,
            approach_m: 100.0,
            seed: 1_964_200,
        }
    }
}

impl DlcSetup {
    /// The truck of the study: `two_axle_truck` (docs/physics.md section 6).
    pub fn truck() -> Result<VehicleDynamics> {
        VehicleModelSpec::HalfCar(HalfCarSpec {
            preset: Some("two_axle_truck".into()),
            ..Default::default()
        })
        .build("vehicle")
    }

    /// Builds a bridge model of this setup's beam and damping.
    pub fn build_model(&self, spec: &ModelSpec) -> Result<BridgeModel> {
        BridgeModel::build(&self.beam, spec, self.damping_ratio)
    }

    /// The road of realisation `realisation` of `surface`, over every x the truck visits
    /// (the range does not depend on the speed, so neither does the realisation).
    pub fn road(&self, surface: Surface, realisation: usize) -> Result<RoadProfile> {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        rng.set_stream((surface.stream() << 32) | realisation as u64);
        let end_m = self.beam.length_m() + ROAD_PAST_BRIDGE_M;
        let start_m = -self.approach_m - 10.0;
        RoadProfile::build(&surface.spec(), start_m, end_m, &mut rng)
    }
}

/// Free vibration simulated after the rear axle leaves, for the smooth-road peaks (s).
const FREE_TIME_S: f64 = 1.0;

/// Road modelled past the bridge end (m): the front axle reaches at most
/// wheelbase + 30 m/s x `FREE_TIME_S` < 40 m past it; the profile is clamped beyond.
const ROAD_PAST_BRIDGE_M: f64 = 60.0;

/// One point of the convergence part (a).
#[derive(Debug, Clone)]
pub struct ConvergencePoint {
    /// "lumped_mass" or "finite_element"; `n` masses or elements.
    pub model: &'static str,
    pub n: usize,
    pub dof: usize,
    pub dt_s: f64,
    pub crossing: Crossing,
    pub wall_s: f64,
}

/// One speed of the smooth-road part (b).
#[derive(Debug, Clone)]
pub struct SmoothPoint {
    pub speed_m_s: f64,
    pub vbi: Crossing,
    /// The same axle loads as constant moving forces.
    pub moving_force: Crossing,
    pub static_peak_m: f64,
}

/// Everything the study computed.
#[derive(Debug, Clone)]
pub struct DlcReport {
    pub convergence: Vec<ConvergencePoint>,
    pub time_step: Vec<ConvergencePoint>,
    pub smooth: Vec<SmoothPoint>,
    pub cases: Vec<DlcCase>,
    pub realisations: usize,
    pub f1_hz: f64,
    pub codes: Vec<(&'static str, f64)>,
    pub wall_s: f64,
}

/// The convergence scenario: class B realisation 0 at 20 m/s; the time-step scenario:
/// class C realisation 0 at 30 m/s (the fastest, roughest case).
pub(super) const CONVERGENCE_SPEED_M_S: f64 = 20.0;
pub(super) const TIME_STEP_SPEED_M_S: f64 = 30.0;

/// Runs the study and writes CSV, figures and summary.md into `out`.
pub fn run(out: &Path, quick: bool, progress: &mut dyn FnMut(&str)) -> Result<DlcReport> {
    let started = Instant::now();
    let setup = DlcSetup::default();
    let truck = DlcSetup::truck()?;
    let nodes: &[usize] = if quick {
        &[10, 20, 40]
    } else {
        &[10, 15, 20, 30, 40, 60, 100, 200, 300]
    };
    let dts: &[f64] = if quick {
        &[2e-3, 1e-3]
    } else {
        &[2e-3, 1e-3, 5e-4, 2.5e-4]
    };
    let speeds: Vec<f64> = if quick {
        vec![10.0, 20.0, 30.0]
    } else {
        (0..=10).map(|i| 5.0 + 2.5 * i as f64).collect()
    };
    let realisations = if quick { 4 } else { 50 };

    // (a) convergence with the node count, then with the time step.
    let mut convergence = Vec::new();
    let rough_b = setup.road(Surface::Iso(IsoClass::B), 0)?;
    for (name, make) in [
        ("lumped_mass", lumped as fn(usize) -> ModelSpec),
        ("finite_element", fe as fn(usize) -> ModelSpec),
    ] {
        for &n in nodes {
            progress(&format!(
                "dlc (a) convergence {name} n={n}, class B, {CONVERGENCE_SPEED_M_S} m/s"
            ));
            let model = setup.build_model(&make(n))?;
            let t = Instant::now();
            let crossing =
                simulate_crossing(&setup, &model, &truck, &rough_b, CONVERGENCE_SPEED_M_S, 0.0)?;
            convergence.push(ConvergencePoint {
                model: name,
                n,
                dof: model.n_dof(),
                dt_s: setup.dt_s,
                crossing,
                wall_s: t.elapsed().as_secs_f64(),
            });
        }
    }
    let model = setup.build_model(&setup.model)?;
    let rough_c = setup.road(Surface::Iso(IsoClass::C), 0)?;
    let mut time_step = Vec::new();
    for &dt_s in dts {
        progress(&format!(
            "dlc (a) time step {dt_s} s, class C, {TIME_STEP_SPEED_M_S} m/s"
        ));
        let s = DlcSetup {
            dt_s,
            ..setup.clone()
        };
        let t = Instant::now();
        let crossing = simulate_crossing(&s, &model, &truck, &rough_c, TIME_STEP_SPEED_M_S, 0.0)?;
        time_step.push(ConvergencePoint {
            model: "finite_element",
            n: fe_elements(&setup.model),
            dof: model.n_dof(),
            dt_s,
            crossing,
            wall_s: t.elapsed().as_secs_f64(),
        });
    }

    // (b) smooth road: VBI and moving forces.
    let level = setup.road(Surface::Smooth, 0)?;
    let loads: Vec<f64> = truck.axles.iter().map(|a| a.static_load_n).collect();
    let offsets: Vec<f64> = truck.axles.iter().map(|a| a.offset_m).collect();
    let forces = VehicleDynamics::moving_forces(&loads, &offsets);
    let static_peak_m = static_peak_midspan_m(&setup.beam, &truck);
    let mut smooth = Vec::new();
    for &v in &speeds {
        progress(&format!("dlc (b) smooth road {v} m/s"));
        smooth.push(SmoothPoint {
            speed_m_s: v,
            vbi: simulate_crossing(&setup, &model, &truck, &level, v, FREE_TIME_S)?,
            moving_force: simulate_crossing(&setup, &model, &forces, &level, v, FREE_TIME_S)?,
            static_peak_m,
        });
    }

    // (c) DLC statistics.
    let mut cases = Vec::new();
    for surface in Surface::STUDIED {
        for &v in &speeds {
            let case = run_case(&setup, &model, &truck, surface, v, realisations)?;
            progress(&format!(
                "dlc (c) {} {v} m/s: {} crossings, DLC front {:.3} (p95 {:.3}), rear {:.3} (p95 {:.3})",
                surface.label(),
                case.crossings.len(),
                case.dlc[0].mean,
                case.dlc[0].p95,
                case.dlc[1].mean,
                case.dlc[1].p95
            ));
            cases.push(case);
        }
    }

    let f1_hz = model.frequency_hz(1);
    let report = DlcReport {
        convergence,
        time_step,
        smooth,
        cases,
        realisations,
        f1_hz,
        codes: design_codes(f1_hz),
        wall_s: started.elapsed().as_secs_f64(),
    };
    report::write_outputs(out, &setup, &report)?;
    Ok(report)
}

fn lumped(n: usize) -> ModelSpec {
    ModelSpec::LumpedMass {
        nodes: n,
        stiffness: LumpedStiffness::Auto,
    }
}

fn fe(n: usize) -> ModelSpec {
    ModelSpec::FiniteElement { elements: n }
}

pub(super) fn fe_elements(spec: &ModelSpec) -> usize {
    match spec {
        ModelSpec::FiniteElement { elements } => *elements,
        _ => 0,
    }
}

pub(super) const AXLES: [&str; 2] = ["front", "rear"];
