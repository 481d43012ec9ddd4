//! The paper's section 11 and past it: dynamic axle loads of the two-axle truck crossing
//! the paper's 30 m bridge, against the impact factors of four design codes.
//!
//! (a) convergence of the midspan response and the contact forces with the node count
//! (lumped mass, Hermite FE) and with the time step; (b) smooth-road responses vs speed
//! (peak deflection, DAF against the static peak, peak acceleration; VBI and moving force);
//! (c) the paper's `DLC = max axle force / static` and the classic `sigma / static`
//! (Sweatman, Cebon) per axle vs speed on smooth, A, B and C roads, as mean and 5th/95th
//! percentiles over seeded road realisations; (d) the code impact factors at f1
//! (PHYSICS.md section 8) and where the simulated DLC exceeds them.
//!
//! Every crossing starts the truck in static equilibrium `approach_m` before the bridge on
//! one continuous profile; only the tyre forces while the axle is on the span count.
//! Realisation r of a class uses its own child RNG stream (seed, class, r), and the same
//! road at every speed (common random numbers: the speed trend is not blurred by
//! road-to-road scatter).

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::error::Result;
use crate::physics::bridge::{
    unit_load_deflection_m_per_n, BeamProperties, BridgeModel, LumpedStiffness, ModelSpec,
    PointQuantity, SparseVec,
};
use crate::physics::road::{IsoClass, RoadProfile, RoadProfileSpec, RoadSurface};
use crate::physics::solver::{
    ContactLaw, CoupledSolver, CoupledVehicle, NewmarkCoefficients, NewmarkParams, SolveMode,
    Stepper, Storage,
};
use crate::physics::vehicle::{HalfCarSpec, VehicleDynamics, VehicleModelSpec};
use crate::studies::plot::{Chart, Figure, Scale, Series};

use super::output::{write_file, write_svg_file};
use super::DIVERGENCE_HINT;

/// Impact factor `1 + mu` of the Chinese code JTG D60-2015 (PHYSICS.md section 8):
/// mu = 0.05 below 1.5 Hz, `0.1767 ln f - 0.0157` from 1.5 to 14 Hz, 0.45 above.
pub fn china_jtg_d60_factor(f1_hz: f64) -> f64 {
    let mu = if f1_hz < 1.5 {
        0.05
    } else if f1_hz <= 14.0 {
        0.1767 * f1_hz.ln() - 0.0157
    } else {
        0.45
    };
    1.0 + mu
}

/// The design codes' allowed amplification at the bridge's f1 (the paper's Table 5;
/// the first three are the values those codes give for f1 = 3.78 Hz).
pub fn design_codes(f1_hz: f64) -> Vec<(&'static str, f64)> {
    vec![
        ("AASHTO", 1.33),
        ("Australia", 1.4),
        ("Switzerland", 1.8),
        ("China JTG D60", china_jtg_d60_factor(f1_hz)),
    ]
}

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
    /// The truck of the study: `two_axle_truck` (PHYSICS.md section 6).
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
        let end_m = self.beam.span_m + ROAD_PAST_BRIDGE_M;
        let start_m = -self.approach_m - 10.0;
        RoadProfile::build(&surface.spec(), start_m, end_m, &mut rng)
    }
}

/// Free vibration simulated after the rear axle leaves, for the smooth-road peaks (s).
const FREE_TIME_S: f64 = 1.0;

/// Road modelled past the bridge end (m): the front axle reaches at most
/// wheelbase + 30 m/s x `FREE_TIME_S` < 40 m past it; the profile is clamped beyond.
const ROAD_PAST_BRIDGE_M: f64 = 60.0;

/// What one crossing gives. Forces are total tyre forces over the static axle load, taken
/// while the axle is on the span; the bridge peaks are at midspan over the whole run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// max F / F_static per axle (front, rear): the paper's DLC.
    pub dlc: [f64; 2],
    /// std(F) / F_static per axle: the classic DLC.
    pub sigma_ratio: [f64; 2],
    /// min F / F_static per axle (negative: the linear tyre pulls, contact lost).
    pub min_ratio: [f64; 2],
    /// Largest downward midspan deflection (m, positive down).
    pub peak_deflection_m: f64,
    /// Largest |midspan acceleration| (m/s^2).
    pub peak_acceleration_m_s2: f64,
}

fn storage_for(spec: &ModelSpec) -> Storage {
    match spec {
        // Hermite FE matrices are banded: sparse Cholesky keeps the band.
        ModelSpec::FiniteElement { .. } => Storage::Sparse,
        _ => Storage::Dense,
    }
}

/// Runs one crossing of `vehicle` at `speed_m_s`, from `approach_m` before the bridge until
/// the rear axle leaves it (plus `free_time_s` of free vibration).
pub fn simulate_crossing(
    setup: &DlcSetup,
    model: &BridgeModel,
    vehicle: &VehicleDynamics,
    road: &dyn RoadSurface,
    speed_m_s: f64,
    free_time_s: f64,
) -> Result<Crossing> {
    let coefficients = NewmarkCoefficients::new(setup.dt_s, NewmarkParams::default())?;
    let mode = SolveMode::Prefactored(storage_for(&model.spec));
    let mut solver = CoupledSolver::new(model, road, coefficients, mode, ContactLaw::Full)?;
    let stepper = Stepper::new(model, DIVERGENCE_HINT);
    let start_m = -setup.approach_m;
    solver.add_vehicle(CoupledVehicle::new(
        0,
        vehicle.clone(),
        speed_m_s,
        start_m,
        0,
    ));
    let span = model.span_m();
    let travel_m = span + vehicle.wheelbase_m() - start_m + speed_m_s * free_time_s;
    let steps = (travel_m / (speed_m_s * setup.dt_s)).ceil() as u64;
    let mut mid = SparseVec::with_capacity(model.n_dof());
    model.point_operator(0.5 * span, PointQuantity::Deflection, &mut mid);
    let axles = vehicle.axles.len().min(2);
    let mut force = [Moments::default(); 2];
    let (mut peak_u, mut peak_a) = (0.0f64, 0.0f64);
    for _ in 0..steps {
        stepper.advance(&mut solver)?;
        let v = &solver.vehicles[0];
        for (j, moments) in force.iter_mut().enumerate().take(axles) {
            if model.on_span(v.axle_x_m(j, solver.step, setup.dt_s)) {
                moments.push(v.contact_force_n[j] / v.dynamics.axles[j].static_load_n);
            }
        }
        let u = mid.dot(&solver.bridge.state.u);
        let a = mid.dot(&solver.bridge.state.a);
        peak_u = peak_u.max(-u);
        peak_a = peak_a.max(a.abs());
    }
    Ok(Crossing {
        dlc: [force[0].max, force[1].max],
        sigma_ratio: [force[0].std(), force[1].std()],
        min_ratio: [force[0].min, force[1].min],
        peak_deflection_m: peak_u,
        peak_acceleration_m_s2: peak_a,
    })
}

/// Running max, min, mean and variance (Welford).
#[derive(Debug, Clone, Copy)]
struct Moments {
    n: u64,
    mean: f64,
    m2: f64,
    max: f64,
    min: f64,
}

impl Default for Moments {
    fn default() -> Self {
        Moments {
            n: 0,
            mean: 0.0,
            m2: 0.0,
            max: f64::NAN,
            min: f64::NAN,
        }
    }
}

impl Moments {
    fn push(&mut self, x: f64) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (x - self.mean);
        self.max = if self.n == 1 { x } else { self.max.max(x) };
        self.min = if self.n == 1 { x } else { self.min.min(x) };
    }

    /// Population standard deviation over the samples.
    fn std(&self) -> f64 {
        if self.n == 0 {
            f64::NAN
        } else {
            (self.m2 / self.n as f64).sqrt()
        }
    }
}

/// Mean and percentiles of one statistic over the realisations of a case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    pub mean: f64,
    /// 5th percentile (linear interpolation between order statistics, Hyndman-Fan type 7).
    pub p5: f64,
    pub p95: f64,
    pub max: f64,
}

impl Spread {
    /// Over `values` (at least one).
    pub fn of(values: &[f64]) -> Spread {
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let pct = |p: f64| {
            let h = p * (sorted.len() - 1) as f64;
            let lo = h.floor() as usize;
            let hi = (lo + 1).min(sorted.len() - 1);
            sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
        };
        Spread {
            mean: sorted.iter().sum::<f64>() / sorted.len() as f64,
            p5: pct(0.05),
            p95: pct(0.95),
            max: sorted[sorted.len() - 1],
        }
    }
}

/// The statistics of one (surface, speed) case.
#[derive(Debug, Clone)]
pub struct DlcCase {
    pub surface: Surface,
    pub speed_m_s: f64,
    pub crossings: Vec<Crossing>,
    /// DLC per axle (front, rear).
    pub dlc: [Spread; 2],
    pub sigma_ratio: [Spread; 2],
    /// Midspan deflection DAF against the static peak.
    pub daf: Spread,
    /// Crossings in which a tyre force went negative (contact lost under a real tyre).
    pub crossings_with_tension: usize,
}

/// Runs `realisations` crossings (one for the smooth road) of `surface` at `speed_m_s`.
pub fn run_case(
    setup: &DlcSetup,
    model: &BridgeModel,
    vehicle: &VehicleDynamics,
    surface: Surface,
    speed_m_s: f64,
    realisations: usize,
) -> Result<DlcCase> {
    let count = if surface == Surface::Smooth {
        1
    } else {
        realisations.max(1)
    };
    let static_peak_m = static_peak_midspan_m(&setup.beam, vehicle);
    let mut crossings = Vec::with_capacity(count);
    for r in 0..count {
        let road = setup.road(surface, r)?;
        crossings.push(simulate_crossing(
            setup, model, vehicle, &road, speed_m_s, 0.0,
        )?);
    }
    let per = |f: &dyn Fn(&Crossing) -> f64| -> Spread {
        Spread::of(&crossings.iter().map(f).collect::<Vec<_>>())
    };
    Ok(DlcCase {
        surface,
        speed_m_s,
        dlc: [per(&|c| c.dlc[0]), per(&|c| c.dlc[1])],
        sigma_ratio: [per(&|c| c.sigma_ratio[0]), per(&|c| c.sigma_ratio[1])],
        daf: per(&|c| c.peak_deflection_m / static_peak_m),
        crossings_with_tension: crossings
            .iter()
            .filter(|c| c.min_ratio.iter().any(|&m| m < 0.0))
            .count(),
        crossings,
    })
}

/// Largest static midspan deflection (m, down) as the axles' static loads roll across a
/// uniform beam: the closed-form influence line (PHYSICS.md section 2), scanned at 1 cm.
pub fn static_peak_midspan_m(beam: &BeamProperties, vehicle: &VehicleDynamics) -> f64 {
    let l = beam.span_m;
    let positions = ((l + vehicle.wheelbase_m()) / 0.01).ceil() as usize;
    (0..=positions)
        .map(|i| {
            let front = i as f64 * 0.01;
            vehicle
                .axles
                .iter()
                .map(|a| {
                    let x = front - a.offset_m;
                    if (0.0..=l).contains(&x) {
                        a.static_load_n * unit_load_deflection_m_per_n(beam, 0.5 * l, x)
                    } else {
                        0.0
                    }
                })
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

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
const CONVERGENCE_SPEED_M_S: f64 = 20.0;
const TIME_STEP_SPEED_M_S: f64 = 30.0;

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
    write_outputs(out, &setup, &report)?;
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

fn fe_elements(spec: &ModelSpec) -> usize {
    match spec {
        ModelSpec::FiniteElement { elements } => *elements,
        _ => 0,
    }
}

const AXLES: [&str; 2] = ["front", "rear"];

fn write_outputs(out: &Path, setup: &DlcSetup, r: &DlcReport) -> Result<()> {
    let mut csv = String::from(
        "model,n,dof,dt_s,peak_deflection_mm,peak_acceleration_m_s2,dlc_front,dlc_rear,sigma_front,sigma_rear,wall_s\n",
    );
    for p in r.convergence.iter().chain(&r.time_step) {
        let c = &p.crossing;
        let _ = writeln!(
            csv,
            "{},{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.3}",
            p.model,
            p.n,
            p.dof,
            p.dt_s,
            1e3 * c.peak_deflection_m,
            c.peak_acceleration_m_s2,
            c.dlc[0],
            c.dlc[1],
            c.sigma_ratio[0],
            c.sigma_ratio[1],
            p.wall_s
        );
    }
    write_file(&out.join("convergence.csv"), &csv)?;

    let mut csv = String::from("speed_m_s,static_peak_mm,peak_deflection_mm,daf_vbi,daf_moving_force,peak_acceleration_m_s2,peak_acceleration_moving_force_m_s2,dlc_front,dlc_rear\n");
    for p in &r.smooth {
        let _ = writeln!(
            csv,
            "{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6}",
            p.speed_m_s,
            1e3 * p.static_peak_m,
            1e3 * p.vbi.peak_deflection_m,
            p.vbi.peak_deflection_m / p.static_peak_m,
            p.moving_force.peak_deflection_m / p.static_peak_m,
            p.vbi.peak_acceleration_m_s2,
            p.moving_force.peak_acceleration_m_s2,
            p.vbi.dlc[0],
            p.vbi.dlc[1]
        );
    }
    write_file(&out.join("smooth_road.csv"), &csv)?;

    let mut csv = String::from("surface,speed_m_s,realisations,axle,dlc_mean,dlc_p5,dlc_p95,dlc_max,sigma_mean,sigma_p5,sigma_p95,daf_mean,daf_p95,crossings_with_tension\n");
    let mut raw = String::from("surface,speed_m_s,realisation,dlc_front,dlc_rear,sigma_front,sigma_rear,min_front,min_rear,peak_deflection_mm,peak_acceleration_m_s2\n");
    for c in &r.cases {
        for (j, axle) in AXLES.iter().enumerate() {
            let (d, s) = (c.dlc[j], c.sigma_ratio[j]);
            let _ = writeln!(
                csv,
                "{},{},{},{axle},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{}",
                c.surface.label(),
                c.speed_m_s,
                c.crossings.len(),
                d.mean,
                d.p5,
                d.p95,
                d.max,
                s.mean,
                s.p5,
                s.p95,
                c.daf.mean,
                c.daf.p95,
                c.crossings_with_tension
            );
        }
        for (i, x) in c.crossings.iter().enumerate() {
            let _ = writeln!(
                raw,
                "{},{},{i},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6}",
                c.surface.label(),
                c.speed_m_s,
                x.dlc[0],
                x.dlc[1],
                x.sigma_ratio[0],
                x.sigma_ratio[1],
                x.min_ratio[0],
                x.min_ratio[1],
                1e3 * x.peak_deflection_m,
                x.peak_acceleration_m_s2
            );
        }
    }
    write_file(&out.join("dlc.csv"), &csv)?;
    write_file(&out.join("dlc_crossings.csv"), &raw)?;

    let mut csv = String::from("surface,speed_m_s,axle,statistic,dlc,code,code_factor,exceeds\n");
    for c in &r.cases {
        for (j, axle) in AXLES.iter().enumerate() {
            for (stat, value) in [("mean", c.dlc[j].mean), ("p95", c.dlc[j].p95)] {
                for (code, factor) in &r.codes {
                    let _ = writeln!(
                        csv,
                        "{},{},{axle},{stat},{value:.5},{code},{factor:.4},{}",
                        c.surface.label(),
                        c.speed_m_s,
                        value > *factor
                    );
                }
            }
        }
    }
    write_file(&out.join("code_comparison.csv"), &csv)?;

    write_svg_file(&out.join("dlc_vs_speed.svg"), &dlc_figure(r))?;
    write_svg_file(&out.join("sigma_vs_speed.svg"), &sigma_figure(r))?;
    write_svg_file(&out.join("convergence.svg"), &convergence_figure(r))?;
    write_svg_file(&out.join("smooth_road.svg"), &smooth_figure(r))?;
    write_file(&out.join("summary.md"), &summary(setup, r))?;
    Ok(())
}

fn cases_of(r: &DlcReport, surface: Surface) -> impl Iterator<Item = &DlcCase> {
    r.cases.iter().filter(move |c| c.surface == surface)
}

fn dlc_figure(r: &DlcReport) -> String {
    // One y range for all four charts, so that the classes compare at a glance.
    let top = r
        .cases
        .iter()
        .map(|c| c.dlc[0].p95.max(c.dlc[1].p95))
        .fold(2.0, f64::max);
    let charts: Vec<Chart> = Surface::STUDIED
        .iter()
        .map(|&surface| {
            let mut chart = Chart::new(
                format!("DLC = max F / F_static, road {}", surface.label()),
                "speed (m/s)",
                "DLC",
            )
            .with_y_range(0.9, 1.05 * top);
            for (j, axle) in AXLES.iter().enumerate() {
                let cases: Vec<&DlcCase> = cases_of(r, surface).collect();
                let mean = cases.iter().map(|c| (c.speed_m_s, c.dlc[j].mean)).collect();
                let band = cases
                    .iter()
                    .map(|c| (c.speed_m_s, c.dlc[j].p5, c.dlc[j].p95))
                    .collect();
                chart.series.push(
                    Series::line_markers(format!("{axle} axle: mean, p5-p95"), mean)
                        .with_band(band),
                );
            }
            for (code, factor) in &r.codes {
                chart.hlines.push((*factor, format!("{code} {factor:.2}")));
            }
            chart
        })
        .collect();
    Figure::grid(2, 2, &charts)
}

fn sigma_figure(r: &DlcReport) -> String {
    let charts: Vec<Chart> = AXLES
        .iter()
        .enumerate()
        .map(|(j, axle)| {
            let mut chart = Chart::new(
                format!("sigma_F / F_static, {axle} axle (on the bridge)"),
                "speed (m/s)",
                "sigma / static",
            );
            for surface in Surface::STUDIED {
                let cases: Vec<&DlcCase> = cases_of(r, surface).collect();
                let mean = cases
                    .iter()
                    .map(|c| (c.speed_m_s, c.sigma_ratio[j].mean))
                    .collect();
                let band = cases
                    .iter()
                    .map(|c| (c.speed_m_s, c.sigma_ratio[j].p5, c.sigma_ratio[j].p95))
                    .collect();
                chart.series.push(
                    Series::line_markers(format!("road {}", surface.label()), mean).with_band(band),
                );
            }
            chart
        })
        .collect();
    Figure::grid(1, 2, &charts)
}

type Metric = (&'static str, &'static str, fn(&Crossing) -> f64);

const CONVERGENCE_METRICS: [Metric; 4] = [
    ("Peak midspan deflection", "mm", |c| {
        1e3 * c.peak_deflection_m
    }),
    ("Peak midspan acceleration", "m/s^2", |c| {
        c.peak_acceleration_m_s2
    }),
    ("DLC front axle", "max F / F_static", |c| c.dlc[0]),
    ("DLC rear axle", "max F / F_static", |c| c.dlc[1]),
];

/// Relative differences to the finest FE model, on log axes (the absolute values agree
/// to 5-6 digits and would plot as flat lines).
fn convergence_figure(r: &DlcReport) -> String {
    let reference = r
        .convergence
        .iter()
        .filter(|p| p.model == "finite_element")
        .max_by_key(|p| p.n);
    let charts: Vec<Chart> = CONVERGENCE_METRICS
        .iter()
        .map(|(title, _unit, metric)| {
            let mut chart = Chart::new(
                format!("{title} (class B, {CONVERGENCE_SPEED_M_S} m/s)"),
                "n (masses or elements)",
                format!(
                    "|q - q_ref| / q_ref, ref FE n={}",
                    reference.map_or(0, |p| p.n)
                ),
            )
            .with_scales(Scale::Log10, Scale::Log10);
            let q_ref = reference.map_or(f64::NAN, |p| metric(&p.crossing));
            for model in ["lumped_mass", "finite_element"] {
                let pts = r
                    .convergence
                    .iter()
                    .filter(|p| p.model == model)
                    .map(|p| (p.n as f64, rel(metric(&p.crossing), q_ref)))
                    .collect();
                chart
                    .series
                    .push(Series::line_markers(model, pts).with_dashed(model == "finite_element"));
            }
            chart
        })
        .collect();
    Figure::grid(2, 2, &charts)
}

fn smooth_figure(r: &DlcReport) -> String {
    let line = |f: &dyn Fn(&SmoothPoint) -> f64| -> Vec<(f64, f64)> {
        r.smooth.iter().map(|p| (p.speed_m_s, f(p))).collect()
    };
    let deflection = Chart::new("Smooth road: peak midspan deflection", "speed (m/s)", "mm")
        .with_series(Series::line_markers(
            "vehicle-bridge interaction",
            line(&|p| 1e3 * p.vbi.peak_deflection_m),
        ))
        .with_series(
            Series::line_markers(
                "moving forces",
                line(&|p| 1e3 * p.moving_force.peak_deflection_m),
            )
            .with_dashed(true),
        );
    let mut daf = Chart::new(
        "Smooth road: DAF = peak / static peak deflection",
        "speed (m/s)",
        "DAF",
    )
    .with_series(Series::line_markers(
        "vehicle-bridge interaction",
        line(&|p| p.vbi.peak_deflection_m / p.static_peak_m),
    ))
    .with_series(
        Series::line_markers(
            "moving forces",
            line(&|p| p.moving_force.peak_deflection_m / p.static_peak_m),
        )
        .with_dashed(true),
    );
    for (code, factor) in &r.codes {
        daf.hlines.push((*factor, format!("{code} {factor:.2}")));
    }
    let acceleration = Chart::new(
        "Smooth road: peak midspan acceleration",
        "speed (m/s)",
        "m/s^2",
    )
    .with_series(Series::line_markers(
        "vehicle-bridge interaction",
        line(&|p| p.vbi.peak_acceleration_m_s2),
    ))
    .with_series(
        Series::line_markers(
            "moving forces",
            line(&|p| p.moving_force.peak_acceleration_m_s2),
        )
        .with_dashed(true),
    );
    let dlc = Chart::new("Smooth road: DLC", "speed (m/s)", "max F / F_static")
        .with_series(Series::line_markers("front axle", line(&|p| p.vbi.dlc[0])))
        .with_series(Series::line_markers("rear axle", line(&|p| p.vbi.dlc[1])));
    Figure::grid(2, 2, &[deflection, daf, acceleration, dlc])
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn summary(setup: &DlcSetup, r: &DlcReport) -> String {
    let mut md =
        String::from("# Dynamic load coefficient study (the paper's section 11 and past it)\n\n");
    let _ = writeln!(
        md,
        "Bridge: the paper's 30 m simply supported beam (EI {:.4e} N m^2, m {} kg/m, f1 = {:.3} Hz), Rayleigh {} % on modes 1-2, model {} ({:?} storage). Vehicle: `two_axle_truck` (PHYSICS.md section 6). Newmark average acceleration, dt = {} s, linear tyres (`ContactLaw::Full`, tension counted as contact loss). Each crossing starts in static equilibrium {} m before the bridge on one continuous profile; forces count while the axle is on the span. ISO 8608 roads with the class's geometric-mean G_d(n0) (A 16e-6, B 64e-6, C 256e-6 m^3), n in [0.01, 4] cycle/m, no tyre-patch filter; {} seeded realisations per class and speed (child stream per class and realisation, the same roads at every speed). Run time {:.1} s on one core.\n",
        setup.beam.flexural_rigidity_n_m2,
        setup.beam.mass_per_length_kg_m,
        r.f1_hz,
        100.0 * setup.damping_ratio,
        setup.model.label(),
        storage_for(&setup.model),
        setup.dt_s,
        setup.approach_m,
        r.realisations,
        r.wall_s
    );
    md.push_str("DLC = max F / F_static (the paper's); sigma/static = std F / F_static (Sweatman, Cebon). Percentiles: type 7 (linear between order statistics).\n\n");

    // (a)
    let _ = writeln!(
        md,
        "## (a) Convergence (class B realisation 0, {CONVERGENCE_SPEED_M_S} m/s, dt = {} s)\n",
        setup.dt_s
    );
    md.push_str("| model | n | DOF | peak defl. (mm) | peak acc. (m/s^2) | DLC front | DLC rear | sigma front | sigma rear | wall (s) |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for p in &r.convergence {
        let c = &p.crossing;
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.2} |",
            p.model,
            p.n,
            p.dof,
            1e3 * c.peak_deflection_m,
            c.peak_acceleration_m_s2,
            c.dlc[0],
            c.dlc[1],
            c.sigma_ratio[0],
            c.sigma_ratio[1],
            p.wall_s
        );
    }
    let finest = |model: &str| {
        r.convergence
            .iter()
            .filter(|p| p.model == model)
            .max_by_key(|p| p.n)
    };
    let chosen = fe_elements(&setup.model);
    let chosen_point = r
        .convergence
        .iter()
        .find(|p| p.model == "finite_element" && p.n == chosen);
    match (
        chosen_point,
        finest("finite_element"),
        finest("lumped_mass"),
    ) {
        (Some(p), Some(f), Some(l)) => {
            let (c, fc, lc) = (&p.crossing, &f.crossing, &l.crossing);
            let dlc_err = rel(c.dlc[0], fc.dlc[0]).max(rel(c.dlc[1], fc.dlc[1]));
            let sigma_err = rel(c.sigma_ratio[0], fc.sigma_ratio[0])
                .max(rel(c.sigma_ratio[1], fc.sigma_ratio[1]));
            let _ = writeln!(
                md,
                "\nThe model used below, FE with {chosen} elements, against FE with {} elements: peak deflection {:.2e}, DLC {:.2e}, sigma/static {:.2e}, peak acceleration {:.2e} relative difference; against lumped mass with {} masses: deflection {:.2e}, DLC {:.2e}, acceleration {:.2e}. {}\n",
                f.n,
                rel(c.peak_deflection_m, fc.peak_deflection_m),
                dlc_err,
                sigma_err,
                rel(c.peak_acceleration_m_s2, fc.peak_acceleration_m_s2),
                l.n,
                rel(c.peak_deflection_m, lc.peak_deflection_m),
                rel(c.dlc[0], lc.dlc[0]).max(rel(c.dlc[1], lc.dlc[1])),
                rel(c.peak_acceleration_m_s2, lc.peak_acceleration_m_s2),
                convergence_verdict(r, c, fc, chosen)
            );
        }
        _ => {
            let _ = writeln!(md, "\n(The quick grid does not contain FE with {chosen} elements; run the full study for the convergence check of the model used below.)\n");
        }
    }
    let _ = writeln!(
        md,
        "Time step (FE {chosen} elements, class C realisation 0, {TIME_STEP_SPEED_M_S} m/s, the fastest and roughest case):\n\n| dt (s) | DLC front | DLC rear | sigma front | sigma rear | peak acc. (m/s^2) |\n|---|---|---|---|---|---|"
    );
    for p in &r.time_step {
        let c = &p.crossing;
        let _ = writeln!(
            md,
            "| {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} |",
            p.dt_s,
            c.dlc[0],
            c.dlc[1],
            c.sigma_ratio[0],
            c.sigma_ratio[1],
            c.peak_acceleration_m_s2
        );
    }

    // (b)
    md.push_str("\n## (b) Smooth road\n\n| speed (m/s) | peak defl. (mm) | static peak (mm) | DAF VBI | DAF moving forces | peak acc. VBI (m/s^2) | peak acc. moving forces | DLC front | DLC rear |\n|---|---|---|---|---|---|---|---|---|\n");
    for p in &r.smooth {
        let _ = writeln!(
            md,
            "| {} | {:.3} | {:.3} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} |",
            p.speed_m_s,
            1e3 * p.vbi.peak_deflection_m,
            1e3 * p.static_peak_m,
            p.vbi.peak_deflection_m / p.static_peak_m,
            p.moving_force.peak_deflection_m / p.static_peak_m,
            p.vbi.peak_acceleration_m_s2,
            p.moving_force.peak_acceleration_m_s2,
            p.vbi.dlc[0],
            p.vbi.dlc[1]
        );
    }

    // (c)
    md.push_str("\n## (c) DLC and sigma/static per axle\n\n| road | speed (m/s) | n | front mean | front p5 | front p95 | rear mean | rear p5 | rear p95 | sigma front mean (p95) | sigma rear mean (p95) | bridge DAF mean (p95) | crossings with tension |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for c in &r.cases {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} ({:.3}) | {:.3} ({:.3}) | {:.3} ({:.3}) | {} |",
            c.surface.label(),
            c.speed_m_s,
            c.crossings.len(),
            c.dlc[0].mean,
            c.dlc[0].p5,
            c.dlc[0].p95,
            c.dlc[1].mean,
            c.dlc[1].p5,
            c.dlc[1].p95,
            c.sigma_ratio[0].mean,
            c.sigma_ratio[0].p95,
            c.sigma_ratio[1].mean,
            c.sigma_ratio[1].p95,
            c.daf.mean,
            c.daf.p95,
            c.crossings_with_tension
        );
    }

    let tension: usize = r.cases.iter().map(|c| c.crossings_with_tension).sum();
    let total: usize = r.cases.iter().map(|c| c.crossings.len()).sum();
    let by_road: Vec<String> = Surface::STUDIED
        .iter()
        .map(|&s| {
            let n: usize = cases_of(r, s).map(|c| c.crossings_with_tension).sum();
            format!("{} {n}", s.label())
        })
        .collect();
    let _ = writeln!(
        md,
        "\n{tension} of {total} crossings put a tyre into tension (by road: {}): the linear tyre of the paper pulls where a real one would lift off and land again (`ContactLaw::Unilateral`), so the statistics of those cases are approximate.\n",
        by_road.join(", ")
    );

    // (d)
    let _ = writeln!(
        md,
        "\n## (d) Design codes at f1 = {:.3} Hz\n\n| code | allowed factor |\n|---|---|",
        r.f1_hz
    );
    for (code, factor) in &r.codes {
        let _ = writeln!(md, "| {code} | {factor:.3} |");
    }
    let _ = writeln!(
        md,
        "\nChina: JTG D60 `1 + mu`, mu = 0.1767 ln f1 - 0.0157 = {:.4} at f1 = {:.3} Hz (PHYSICS.md section 8).\n",
        china_jtg_d60_factor(r.f1_hz) - 1.0,
        r.f1_hz
    );
    for (stat, pick) in [
        ("mean", (|s: &Spread| s.mean) as fn(&Spread) -> f64),
        ("p95", |s: &Spread| s.p95),
    ] {
        let _ = write!(
            md,
            "Axles whose DLC {stat} exceeds the code factor (F front, R rear, - none):\n\n| road | speed (m/s) |"
        );
        for (code, factor) in &r.codes {
            let _ = write!(md, " {code} {factor:.2} |");
        }
        md.push_str("\n|---|---|");
        md.push_str(&"---|".repeat(r.codes.len()));
        md.push('\n');
        for c in &r.cases {
            let _ = write!(md, "| {} | {} |", c.surface.label(), c.speed_m_s);
            for (_, factor) in &r.codes {
                let cell: Vec<&str> = ["F", "R"]
                    .iter()
                    .enumerate()
                    .filter(|(j, _)| pick(&c.dlc[*j]) > *factor)
                    .map(|(_, a)| *a)
                    .collect();
                let cell = if cell.is_empty() {
                    "-".to_string()
                } else {
                    cell.join(" ")
                };
                let _ = write!(md, " {cell} |");
            }
            md.push('\n');
        }
        md.push('\n');
    }

    md.push_str(&conclusions(r));
    md.push_str("\nFigures: `dlc_vs_speed.svg` (DLC mean with p5-p95 band per class, code factors as lines), `sigma_vs_speed.svg`, `convergence.svg`, `smooth_road.svg`. Data: `convergence.csv`, `smooth_road.csv`, `dlc.csv`, `dlc_crossings.csv` (every crossing), `code_comparison.csv`.\n");
    md
}

/// What part (a) says about the model used in (b)-(d), from the numbers.
fn convergence_verdict(r: &DlcReport, c: &Crossing, fine: &Crossing, chosen: usize) -> String {
    let dlc_err = rel(c.dlc[0], fine.dlc[0]).max(rel(c.dlc[1], fine.dlc[1]));
    let sigma_err =
        rel(c.sigma_ratio[0], fine.sigma_ratio[0]).max(rel(c.sigma_ratio[1], fine.sigma_ratio[1]));
    let acc_err = rel(c.peak_acceleration_m_s2, fine.peak_acceleration_m_s2);
    let coarse_err = r
        .convergence
        .iter()
        .map(|p| rel(p.crossing.dlc[0], fine.dlc[0]).max(rel(p.crossing.dlc[1], fine.dlc[1])))
        .fold(0.0, f64::max);
    let mut text = if dlc_err < 1e-3 && sigma_err < 1e-3 {
        format!("Contact forces (DLC, sigma/static) are converged to better than 0.1 %: FE with {chosen} elements is accurate enough for them (every model of the grid, down to 10 masses or elements, gives the DLC within {coarse_err:.1e}: the tyre forces hardly feel the bridge's higher modes).")
    } else {
        format!("The contact forces are NOT converged to 0.1 % with FE {chosen} (DLC {dlc_err:.1e}, sigma {sigma_err:.1e}); read the DLC tables with that error in mind.")
    };
    if acc_err < 1e-2 {
        text += " Peak acceleration is converged to 1 % as well (Rayleigh damping suppresses the high modes a finer mesh would add).";
    } else {
        text += &format!(
            " Peak acceleration differs by {acc_err:.1e} from the finest model: indicative only."
        );
    }
    text
}

/// The explicit answers to the paper's conclusions.
fn conclusions(r: &DlcReport) -> String {
    let mut md = String::from("## Do the paper's conclusions hold?\n\n");
    let worst = |surfaces: &[Surface], pick: fn(&DlcCase) -> f64| -> Option<(f64, String)> {
        r.cases
            .iter()
            .filter(|c| surfaces.contains(&c.surface))
            .map(|c| {
                (
                    pick(c),
                    format!("road {} at {} m/s", c.surface.label(), c.speed_m_s),
                )
            })
            .max_by(|a, b| a.0.total_cmp(&b.0))
    };
    let ab = [Surface::Iso(IsoClass::A), Surface::Iso(IsoClass::B)];
    let p95 = worst(&ab, |c| c.dlc[0].p95.max(c.dlc[1].p95));
    let max = worst(&ab, |c| c.dlc[0].max.max(c.dlc[1].max));
    if let (Some((p, pw)), Some((m, mw))) = (p95, max) {
        let verdict = match (p <= 2.0, m <= 2.0) {
            (true, true) => "holds",
            (true, false) => "holds for the 95th percentile, not for every crossing",
            _ => "does not hold",
        };
        let _ = writeln!(
            md,
            "1. \"DLC within 2.0 for classes A and B\": **{verdict}**. The largest 95th percentile over both axles and all speeds is {p:.3} ({pw}); the largest single crossing {m:.3} ({mw})."
        );
    }
    let c_worst = worst(&[Surface::Iso(IsoClass::C)], |c| {
        c.dlc[0].p95.max(c.dlc[1].p95)
    });
    if let Some((p, w)) = c_worst {
        let _ = writeln!(
            md,
            "   Class C goes past it: largest 95th percentile {p:.3} ({w})."
        );
    }
    let china = china_jtg_d60_factor(r.f1_hz);
    let lowest = r
        .codes
        .iter()
        .all(|(name, f)| *name == "China JTG D60" || *f > china);
    let count = |surface: Surface, value: fn(&DlcCase) -> f64| {
        let cases: Vec<&DlcCase> = cases_of(r, surface).collect();
        let above = cases.iter().filter(|c| value(c) > china).count();
        format!("{} {above}/{}", surface.label(), cases.len())
    };
    let per_class = |value: fn(&DlcCase) -> f64| {
        Surface::STUDIED
            .iter()
            .map(|&s| count(s, value))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let smooth_worst = cases_of(r, Surface::Smooth)
        .map(|c| c.daf.max.max(c.dlc[0].max).max(c.dlc[1].max))
        .fold(f64::NAN, f64::max);
    let holds = lowest && cases_of(r, Surface::Iso(IsoClass::A)).any(|c| c.daf.p95 > china);
    let _ = writeln!(
        md,
        "2. \"The Chinese code is low near 4 Hz\": at f1 = {:.2} Hz JTG D60 gives {china:.3}, {} of the four codes (AASHTO 1.33, Australia 1.4, Switzerland 1.8). Speeds at which the simulated axle DLC (worse axle) exceeds it, by the mean: {}; by the 95th percentile: {}. The bridge's own midspan DAF (the quantity the codes' factors amplify) exceeds it by the mean at {} and by the 95th percentile at {} speeds. On the smooth road the largest DAF or DLC is {smooth_worst:.3}, inside every code. So **{}**: {}.",
        r.f1_hz,
        if lowest { "the lowest" } else { "not the lowest" },
        per_class(|c| c.dlc[0].mean.max(c.dlc[1].mean)),
        per_class(|c| c.dlc[0].p95.max(c.dlc[1].p95)),
        per_class(|c| c.daf.mean),
        per_class(|c| c.daf.p95),
        if holds { "it holds" } else { "it does not hold" },
        if holds {
            "the Chinese factor is the lowest and the first one exceeded, by the axle loads and, from class A on (95th percentile), by the bridge response too"
        } else {
            "either another code is lower or the bridge response on class A roads stays inside the Chinese factor"
        }
    );
    md.push_str("\nNote: the paper compares axle-force DLC with bridge impact factors; these are different quantities (a tyre force ratio vs a bridge response ratio), so the code table says how large the wheel loads get, not whether the codes are unsafe for the bridge.\n");
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chinese_factor_follows_jtg_d60() {
        // PHYSICS.md section 8: 1.22 at 3.78 Hz (two decimals); the branches at the ends.
        assert!((china_jtg_d60_factor(3.78) - 1.22).abs() < 0.005);
        assert_eq!(china_jtg_d60_factor(1.0), 1.05);
        assert_eq!(china_jtg_d60_factor(20.0), 1.45);
    }

    #[test]
    fn percentiles_interpolate_order_statistics() {
        let values: Vec<f64> = (0..=20).map(f64::from).collect();
        let s = Spread::of(&values);
        // Type 7 on 0..=20: p = 0.05 -> rank 1.0, p = 0.95 -> rank 19.0 exactly.
        assert!((s.p5 - 1.0).abs() < 1e-12 && (s.p95 - 19.0).abs() < 1e-12);
        assert_eq!((s.mean, s.max), (10.0, 20.0));
    }

    #[test]
    fn static_peak_of_one_load_is_pl3_over_48ei() {
        // A single axle: the peak is at midspan, P L^3 / (48 EI) (PHYSICS.md section 1).
        let beam = BeamProperties::paper_default();
        let force = VehicleDynamics::moving_forces(&[1e5], &[0.0]);
        let expected = 1e5 * 30f64.powi(3) / (48.0 * beam.flexural_rigidity_n_m2);
        assert!((static_peak_midspan_m(&beam, &force) - expected).abs() < 1e-12 * expected);
    }
}
