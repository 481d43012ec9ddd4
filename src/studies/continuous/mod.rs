//! Continuous girders under traffic: the two-axle truck crossing the three-span example
//! (`examples/three_span_continuous.toml`: 24 + 30 + 24 m, haunched over the piers).
//!
//! (a) the paper's question on this girder: lumped masses (by condensation: the haunches
//! rule out the closed-form flexibility) against Hermite elements, f1..f3 and the peak
//! sagging moment of a crossing against a fine FE reference, with each model's build and
//! step time; (b) the dynamic amplification (DAF = dynamic peak / static peak) of the
//! sagging moment at the middle of the central span and of the hogging moment over the
//! first pier, and the DLC of each axle, vs speed on smooth, A, B and C roads, as mean and
//! 5th/95th percentiles over seeded road realisations, against the design codes' impact
//! factors at f1.
//!
//! Static peaks come from the influence lines of the same mesh (`K z = m`: one solve per
//! section, the moment under a load at x is then `h(x) . z`), so a DAF compares like with
//! like. Realisations share roads across speeds (common random numbers, as `study dlc`).

mod report;

use std::path::Path;
use std::time::Instant;

use nalgebra::DVector;

use crate::error::{Error, Result};
use crate::physics::bridge::{
    BeamProperties, BridgeModel, GaugeFactors, GaugeState, LumpedStiffness, ModelSpec, MomentGauge,
    PointQuantity, SparseVec,
};
use crate::physics::linalg::BandCholesky;
use crate::physics::road::RoadSurface;
use crate::physics::solver::{
    ContactLaw, CoupledSolver, CoupledVehicle, NewmarkCoefficients, NewmarkParams, SolveMode,
    Stepper, Storage,
};
use crate::physics::vehicle::VehicleDynamics;
use crate::scenario::Scenario;
use crate::studies::dlc::{design_codes, DlcSetup, Spread, Surface};
use crate::studies::DIVERGENCE_HINT;

/// The girder of the study: the three-span example, read from its own file so that the
/// two cannot drift apart.
const EXAMPLE: &str = include_str!("../../../examples/three_span_continuous.toml");
/// The middle of the central span and the first pier (m).
pub const SAGGING_X_M: f64 = 39.0;
pub const PIER_X_M: f64 = 24.0;
/// Hermite elements of the study's model (the example's 0.75 m elements).
const ELEMENTS: usize = 104;

/// One crossing: the moments' extremes and each axle's largest force over its static load
/// while on the girder.
#[derive(Debug, Clone, Copy)]
pub struct Crossing {
    /// Largest sagging moment at [`SAGGING_X_M`] (N m, positive).
    pub sagging_n_m: f64,
    /// Largest hogging moment over the pier (N m, positive magnitude).
    pub hogging_n_m: f64,
    /// Largest downward deflection at [`SAGGING_X_M`] (m).
    pub deflection_m: f64,
    pub dlc: [f64; 2],
}

/// One (surface, speed) case.
#[derive(Debug, Clone)]
pub struct Case {
    pub surface: Surface,
    pub speed_m_s: f64,
    pub daf_sagging: Spread,
    pub daf_hogging: Spread,
    pub dlc: [Spread; 2],
}

/// One model of part (a).
#[derive(Debug, Clone)]
pub struct ModelRow {
    pub model: &'static str,
    pub n: usize,
    pub dof: usize,
    pub frequencies_hz: [f64; 3],
    /// |f / f_ref - 1| of f1..f3.
    pub frequency_error: [f64; 3],
    /// |w / w_ref - 1| of the peak deflection at the central midspan, smooth road, 20 m/s
    /// (deflections converge as the paper measures them; a moment recovered as EI w'' is
    /// only O(h) next to a wheel inside an element, and is compared in the DAF, where
    /// static and dynamic share the operator).
    pub deflection_error: f64,
    pub build_s: f64,
    /// Wall time per coupled step (us).
    pub step_us: f64,
}

/// Everything the study computed.
#[derive(Debug, Clone)]
pub struct ContinuousReport {
    pub f1_hz: f64,
    pub codes: Vec<(&'static str, f64)>,
    pub static_sagging_n_m: f64,
    pub static_hogging_n_m: f64,
    pub models: Vec<ModelRow>,
    pub reference_frequencies_hz: [f64; 3],
    pub cases: Vec<Case>,
    pub realisations: usize,
    pub wall_s: f64,
}

/// The example's girder.
pub fn example_beam() -> Result<BeamProperties> {
    Ok(
        Scenario::from_toml(EXAMPLE, "examples/three_span_continuous.toml")?
            .bridge
            .beam(),
    )
}

/// Runs the study and writes CSV, figures and summary.md into `out`.
pub fn run(out: &Path, quick: bool, progress: &mut dyn FnMut(&str)) -> Result<ContinuousReport> {
    let started = Instant::now();
    let setup = DlcSetup {
        beam: example_beam()?,
        model: ModelSpec::FiniteElement { elements: ELEMENTS },
        ..DlcSetup::default()
    };
    let truck = DlcSetup::truck()?;
    let speeds: Vec<f64> = match quick {
        true => vec![10.0, 20.0, 30.0],
        false => (0..=10).map(|i| 5.0 + 2.5 * i as f64).collect(),
    };
    let realisations = if quick { 2 } else { 20 };
    let models = compare_models(&setup, &truck, quick, progress)?;
    let model = setup.build_model(&setup.model)?;
    let (static_sagging_n_m, static_hogging_n_m) =
        static_peaks(&setup.beam, &truck, (SAGGING_X_M, PIER_X_M), ELEMENTS)?;
    let mut cases = Vec::new();
    for surface in Surface::STUDIED {
        // A smooth road has one realisation.
        let count = if surface == Surface::Smooth {
            1
        } else {
            realisations
        };
        let roads = (0..count)
            .map(|r| setup.road(surface, r))
            .collect::<Result<Vec<_>>>()?;
        for &v in &speeds {
            let crossings = roads
                .iter()
                .map(|road| crossing(&setup, &model, &truck, road, v))
                .collect::<Result<Vec<_>>>()?;
            let spread = |f: &dyn Fn(&Crossing) -> f64| {
                Spread::of(&crossings.iter().map(f).collect::<Vec<_>>())
            };
            let case = Case {
                surface,
                speed_m_s: v,
                daf_sagging: spread(&|c| c.sagging_n_m / static_sagging_n_m),
                daf_hogging: spread(&|c| c.hogging_n_m / static_hogging_n_m),
                dlc: [spread(&|c| c.dlc[0]), spread(&|c| c.dlc[1])],
            };
            progress(&format!(
                "continuous {} {v} m/s: DAF sagging {:.3} (p95 {:.3}), hogging {:.3} (p95 {:.3}), \
                 DLC front {:.3}, rear {:.3}",
                surface.label(),
                case.daf_sagging.mean,
                case.daf_sagging.p95,
                case.daf_hogging.mean,
                case.daf_hogging.p95,
                case.dlc[0].mean,
                case.dlc[1].mean
            ));
            cases.push(case);
        }
    }
    let f1_hz = model.frequency_hz(1);
    let report = ContinuousReport {
        f1_hz,
        codes: design_codes(f1_hz),
        static_sagging_n_m,
        static_hogging_n_m,
        reference_frequencies_hz: reference_frequencies(&setup)?,
        models,
        cases,
        realisations,
        wall_s: started.elapsed().as_secs_f64(),
    };
    report::write_outputs(out, &report)?;
    Ok(report)
}

/// The static peaks (sagging at `sagging_x_m`, hogging at `hogging_x_m`; N m, positive)
/// of the truck's static axle loads moved over the girder in 5 cm steps, on a mesh of
/// `elements` Hermite elements, read by the moment gauges the dynamic runs use (a static
/// solve per position: exact moments, wherever an axle stands in a gauge's element).
pub fn static_peaks(
    beam: &BeamProperties,
    truck: &VehicleDynamics,
    (sagging_x_m, hogging_x_m): (f64, f64),
    elements: usize,
) -> Result<(f64, f64)> {
    let model = BridgeModel::build(beam, &ModelSpec::FiniteElement { elements }, 0.0)?;
    let factor = BandCholesky::factor(&model.stiffness.to_band()).map_err(|row| {
        Error::invalid(
            "bridge",
            format!("(equation {row})"),
            "is not positive definite",
        )
    })?;
    let factors = GaugeFactors::new(&model)?;
    let gauges = [sagging_x_m, hogging_x_m].map(|x| MomentGauge::with_factors(&model, &factors, x));
    let length = beam.length_m();
    let zero = DVector::zeros(model.n_dof());
    let mut u = DVector::zeros(model.n_dof());
    let mut h = SparseVec::default();
    let mut loads = Vec::new();
    let (mut sagging, mut hogging) = (0.0f64, 0.0f64);
    let steps = ((length + truck.wheelbase_m()) / 0.05).ceil() as usize;
    for i in 0..=steps {
        let front = i as f64 * 0.05;
        loads.clear();
        u.fill(0.0);
        for axle in &truck.axles {
            let x = front - axle.offset_m;
            if model.on_girder(x) {
                // A downward load is -P on the upward-positive DOFs.
                loads.push((x, -axle.static_load_n));
                model.point_operator(x, PointQuantity::Deflection, &mut h);
                h.add_scaled_to(-axle.static_load_n, &mut u);
            }
        }
        factor.solve_in_place(u.as_mut_slice());
        let state = GaugeState {
            u: &u,
            v: &zero,
            a: &zero,
            loads: &loads,
        };
        sagging = sagging.max(gauges[0].read(&state));
        hogging = hogging.max(-gauges[1].read(&state));
    }
    Ok((sagging, hogging))
}

/// One crossing of `truck` at `speed_m_s` on `road`, from the approach until the rear
/// axle leaves the girder.
fn crossing(
    setup: &DlcSetup,
    model: &BridgeModel,
    truck: &VehicleDynamics,
    road: &dyn RoadSurface,
    speed_m_s: f64,
) -> Result<Crossing> {
    let coefficients = NewmarkCoefficients::new(setup.dt_s, NewmarkParams::default())?;
    let storage = match model.spec {
        ModelSpec::FiniteElement { .. } => Storage::Sparse,
        _ => Storage::Dense,
    };
    let mut solver = CoupledSolver::new(
        model,
        road,
        coefficients,
        SolveMode::Prefactored(storage),
        ContactLaw::Full,
    )?;
    let stepper = Stepper::new(model, DIVERGENCE_HINT);
    solver.add_vehicle(CoupledVehicle::new(
        0,
        truck.clone(),
        speed_m_s,
        -setup.approach_m,
        0,
    ));
    let length = model.length_m();
    let travel_m = length + truck.wheelbase_m() + setup.approach_m;
    let steps = (travel_m / (speed_m_s * setup.dt_s)).ceil() as u64;
    let factors = GaugeFactors::new(model)?;
    let gauges = [SAGGING_X_M, PIER_X_M].map(|x| MomentGauge::with_factors(model, &factors, x));
    let mut loads = Vec::new();
    let mut mid = SparseVec::default();
    model.point_operator(SAGGING_X_M, PointQuantity::Deflection, &mut mid);
    let mut out = Crossing {
        sagging_n_m: 0.0,
        hogging_n_m: 0.0,
        deflection_m: 0.0,
        dlc: [0.0; 2],
    };
    for _ in 0..steps {
        stepper.advance(&mut solver)?;
        out.sagging_n_m = out
            .sagging_n_m
            .max(solver.gauge_moment_n_m(&gauges[0], &mut loads));
        out.hogging_n_m = out
            .hogging_n_m
            .max(-solver.gauge_moment_n_m(&gauges[1], &mut loads));
        let u = &solver.bridge.state.u;
        out.deflection_m = out.deflection_m.max(-mid.dot(u));
        let v = &solver.vehicles[0];
        for (j, dlc) in out.dlc.iter_mut().enumerate().take(v.dynamics.axles.len()) {
            if model.on_girder(v.axle_x_m(j, solver.step, setup.dt_s)) {
                *dlc = dlc.max(v.contact_force_n[j] / v.dynamics.axles[j].static_load_n);
            }
        }
    }
    Ok(out)
}

/// f1..f3 of a fine FE mesh (400 elements, 0.2 m): the reference of part (a).
fn reference_frequencies(setup: &DlcSetup) -> Result<[f64; 3]> {
    let model = setup.build_model(&ModelSpec::FiniteElement { elements: 400 })?;
    Ok([1, 2, 3].map(|k| model.frequency_hz(k)))
}

/// Part (a): lumped masses by condensation and Hermite elements of growing size against
/// a 400-element reference: frequencies, the peak deflection at the central midspan of a
/// smooth crossing at 20 m/s, build time and time per step.
fn compare_models(
    setup: &DlcSetup,
    truck: &VehicleDynamics,
    quick: bool,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<ModelRow>> {
    let sizes: &[usize] = if quick {
        &[13, 26, 52]
    } else {
        &[13, 26, 52, 104, 208]
    };
    let reference = reference_frequencies(setup)?;
    let smooth = setup.road(Surface::Smooth, 0)?;
    let fine = setup.build_model(&ModelSpec::FiniteElement { elements: 400 })?;
    let reference_m = crossing(setup, &fine, truck, &smooth, 20.0)?.deflection_m;
    let mut rows = Vec::new();
    for (name, spec) in [
        ("lumped_mass", lumped as fn(usize) -> ModelSpec),
        ("finite_element", |n| ModelSpec::FiniteElement {
            elements: n,
        }),
    ] {
        for &n in sizes {
            progress(&format!("continuous (a) {name} n={n}"));
            let t = Instant::now();
            let model = setup.build_model(&spec(n))?;
            let build_s = t.elapsed().as_secs_f64();
            let t = Instant::now();
            let c = crossing(setup, &model, truck, &smooth, 20.0)?;
            let steps =
                (model.length_m() + truck.wheelbase_m() + setup.approach_m) / (20.0 * setup.dt_s);
            let frequencies_hz = [1, 2, 3].map(|k| model.frequency_hz(k));
            rows.push(ModelRow {
                model: name,
                n,
                dof: model.n_dof(),
                frequency_error: [0, 1, 2].map(|k| (frequencies_hz[k] / reference[k] - 1.0).abs()),
                frequencies_hz,
                deflection_error: (c.deflection_m / reference_m - 1.0).abs(),
                build_s,
                step_us: 1e6 * t.elapsed().as_secs_f64() / steps,
            });
        }
    }
    Ok(rows)
}

fn lumped(n: usize) -> ModelSpec {
    ModelSpec::LumpedMass {
        nodes: n,
        stiffness: LumpedStiffness::Condensation,
    }
}
