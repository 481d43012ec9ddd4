//! Checks of the coupled vehicle-bridge solver (VBI) and the road input: equilibrium,
//! static loads, harmonic response on a rigid road, the sprung mass crossing a beam, the
//! moving-force and moving-mass limits, a 20 t truck, ISO 8608 statistics and unilateral
//! contact. PHYSICS.md sections 6-9.
//!
//! Sign conventions: the solver is upward positive, the analytical module downward
//! positive; every comparison below negates the solver's deflections.

use std::f64::consts::PI;

use nalgebra::{Complex, DVector, Matrix3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::harness::{moving_force_history, MovingForceCase};
use super::CheckRow;
use crate::base::signal::{welch_psd, WelchPsd};
use crate::error::{Error, Result};
use crate::physics::bridge::{
    BeamProperties, BridgeModel, LumpedStiffness, ModelSpec, PointQuantity, SparseVec,
};
use crate::physics::road::{
    iso8608_band_rms_m, iso8608_psd_m3, ConstantRoad, IsoClass, LevelRoad, RoadProfile,
    RoadProfileSpec, RoadSurface, SineRoad, DEFAULT_N1_CYCLES_M, DEFAULT_N2_CYCLES_M,
    DEFAULT_SAMPLE_SPACING_M,
};
use crate::physics::solver::{
    ContactLaw, CoupledSolver, CoupledVehicle, NewmarkCoefficients, NewmarkParams, SolveMode,
    Stepper, Storage,
};
use crate::physics::vehicle::{
    sprung_mass, HalfCarSpec, VehicleDynamics, VehicleModelSpec, GRAVITY_M_S2,
};
use crate::studies::analytic::moving_mass::{MovingMassOptions, MovingMassProblem};
use crate::studies::analytic::{
    harmonic_response, ModalDamping, MovingForceSolution, MovingLoadTrain, RoadIrregularity,
    SimplySupportedBeam, SprungMassOptions, SprungMassProblem, SprungMassVehicle,
};
use crate::studies::DIVERGENCE_HINT;

// ---------------------------------------------------------------------------------------
// Shared set-up
// ---------------------------------------------------------------------------------------

/// The VBI-2D verification beam (PHYSICS.md section 6): 25 m, E 3.5e10 Pa, I 1.3901 m^4,
/// m 18 358 kg/m (f1 = 4.09 Hz).
fn vbi_beam() -> BeamProperties {
    BeamProperties {
        span_m: 25.0,
        flexural_rigidity_n_m2: 3.5e10 * 1.3901,
        mass_per_length_kg_m: 18_358.0,
        stiffness_regions: Vec::new(),
    }
}

fn analytic_beam(beam: &BeamProperties) -> Result<SimplySupportedBeam> {
    SimplySupportedBeam::new(
        beam.span_m,
        beam.flexural_rigidity_n_m2,
        beam.mass_per_length_kg_m,
    )
}

fn fe(elements: usize) -> ModelSpec {
    ModelSpec::FiniteElement { elements }
}

fn lumped(nodes: usize) -> ModelSpec {
    ModelSpec::LumpedMass {
        nodes,
        stiffness: LumpedStiffness::Auto,
    }
}

/// A half car from its preset, with optional body-mass override.
fn half_car(preset: &str, body_mass_kg: Option<f64>) -> Result<VehicleDynamics> {
    VehicleModelSpec::HalfCar(HalfCarSpec {
        preset: Some(preset.to_string()),
        body_mass_kg,
        ..Default::default()
    })
    .build("vehicle")
}

fn coupled<'a>(
    model: &'a BridgeModel,
    road: &'a dyn RoadSurface,
    dt_s: f64,
    law: ContactLaw,
) -> Result<CoupledSolver<'a>> {
    let coefficients = NewmarkCoefficients::new(dt_s, NewmarkParams::default())?;
    CoupledSolver::new(
        model,
        road,
        coefficients,
        SolveMode::Prefactored(Storage::Dense),
        law,
    )
}

fn max_abs(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |m, v| m.max(v.abs()))
}

fn deterministic_road(spec: &RoadProfileSpec, x_start_m: f64, x_end_m: f64) -> Result<RoadProfile> {
    // Deterministic shapes draw nothing from the generator.
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    RoadProfile::build(spec, x_start_m, x_end_m, &mut rng)
}

// ---------------------------------------------------------------------------------------
// 1. Equilibrium on the approach
// ---------------------------------------------------------------------------------------

/// Vehicles driving 5 s on a rigid smooth approach (the bridge 300 m ahead) stay in their
/// static equilibrium: a level road and a road raised by 50 mm everywhere (the vehicle
/// starts translated by 50 mm, `equilibrium_on_road`).
pub fn approach_equilibrium() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_equilibrium";
    let model = BridgeModel::build(&vbi_beam(), &fe(4), 0.02)?;
    let mut rows = Vec::new();
    for preset in ["two_axle_truck", "vbi2d_e01"] {
        for raise_m in [0.0, 0.05] {
            let road = ConstantRoad {
                elevation_m: raise_m,
            };
            let mut solver = coupled(&model, &road, 1e-3, ContactLaw::Full)?;
            let vehicle = half_car(preset, None)?;
            // A raised rigid road translates every DOF by the same amount (no pitch).
            let expected = DVector::from_vec(vec![raise_m, 0.0, raise_m, raise_m]);
            let statics: Vec<f64> = vehicle.axles.iter().map(|a| a.static_load_n).collect();
            solver.add_vehicle(CoupledVehicle::new(0, vehicle, 20.0, -400.0, 0));
            let (mut max_y, mut max_force) = (0.0f64, 0.0f64);
            let stepper = Stepper::new(&model, DIVERGENCE_HINT);
            for _ in 0..5000 {
                stepper.advance(&mut solver)?;
                let v = &solver.vehicles[0];
                max_y = max_y.max(max_abs((&v.state.u - &expected).iter().copied()));
                for (f, s) in v.contact_force_n.iter().zip(&statics) {
                    max_force = max_force.max(((f - s) / s).abs());
                }
            }
            let what = format!("{preset}, road at {raise_m} m, 20 m/s for 5 s");
            // Round-off only: the state starts exactly at equilibrium and the step maps
            // equilibrium to itself; the residual is the LU solve's, ~1e-16 of the 50 mm
            // offset per step, and a stable step does not accumulate it.
            rows.push(CheckRow::with_error(
                GROUP,
                format!("max |y - y_eq| {what}"),
                "static equilibrium (m)",
                0.0,
                max_y,
                max_y,
                1e-12,
            ));
            rows.push(CheckRow::with_error(
                GROUP,
                format!("max |F - F_static| / F_static {what}"),
                "static axle loads",
                0.0,
                max_force,
                max_force,
                1e-10,
            ));
        }
    }
    Ok(rows)
}

// ---------------------------------------------------------------------------------------
// 2. Static loads
// ---------------------------------------------------------------------------------------

/// Static axle loads of both presets against the weight and the lever rule, and three
/// vehicles crawling over the bridge together: the sum of their tyre forces against the
/// sum of their weights, and the midspan deflection against the static influence lines.
pub fn static_loads() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_static_loads";
    let mut rows = Vec::new();
    for (preset, body_kg, axles_kg) in [
        ("two_axle_truck", 17_735.0, [1_500.0, 1_000.0]),
        ("vbi2d_e01", 10_500.0, [900.0, 900.0]),
    ] {
        let vehicle = half_car(preset, None)?;
        let weight_n = (body_kg + axles_kg[0] + axles_kg[1]) * GRAVITY_M_S2;
        // The presets put the CG at mid-wheelbase: the body's weight splits in half.
        let front_n = (0.5 * body_kg + axles_kg[0]) * GRAVITY_M_S2;
        // Static loads come from one LU solve of the 4x4 stiffness: round-off, ~1e-15.
        rows.push(CheckRow::relative(
            GROUP,
            format!("sum of static axle loads {preset}"),
            "gross weight (N)",
            weight_n,
            vehicle.gross_weight_n(),
            1e-12,
        ));
        rows.push(CheckRow::relative(
            GROUP,
            format!("front static axle load {preset}"),
            "lever rule, CG mid-wheelbase (N)",
            front_n,
            vehicle.axles[0].static_load_n,
            1e-12,
        ));
    }
    rows.extend(crawl_rows(GROUP)?);
    Ok(rows)
}

/// Three vehicles (two_axle_truck, vbi2d_e01, a 20 t sprung mass) 3 m apart crawl at
/// 0.5 m/s over the 30 m paper bridge (FE 20, 2 % Rayleigh damping) on a smooth road;
/// averages over the steps with every axle on the span, from 2 s after the last one came
/// on.
fn crawl_rows(group: &str) -> Result<Vec<CheckRow>> {
    let beam = BeamProperties::paper_default();
    let model = BridgeModel::build(&beam, &fe(20), 0.02)?;
    let ab = analytic_beam(&beam)?;
    let road = LevelRoad;
    let (dt_s, speed, gap_m, first_front_m) = (5e-3, 0.5, 3.0, -1.0);
    let mut solver = coupled(&model, &road, dt_s, ContactLaw::Full)?;
    let vehicles = [
        half_car("two_axle_truck", None)?,
        half_car("vbi2d_e01", None)?,
        sprung_mass(20_000.0, 4.0e6, 2.0e4),
    ];
    let mut front_m = first_front_m;
    let mut weight_n = 0.0;
    for (id, v) in vehicles.into_iter().enumerate() {
        weight_n += v.gross_weight_n();
        let length = v.wheelbase_m();
        solver.add_vehicle(CoupledVehicle::new(id as u32, v, speed, front_m, 0));
        front_m -= length + gap_m;
    }
    // Distance from the first front axle to the last axle.
    let train_m = first_front_m - (front_m + gap_m);
    let first_front = |step: u64| first_front_m + speed * step as f64 * dt_s;
    let on_from = train_m + 2.0 * speed;
    let on_to = beam.span_m - 0.5;
    let steps = ((on_to - first_front_m) / (speed * dt_s)).round() as u64;
    let mid = 0.5 * beam.span_m;
    let mut op = SparseVec::with_capacity(model.n_dof());
    let (mut sum_force, mut sum_w, mut sum_w_static, mut count) = (0.0, 0.0, 0.0, 0usize);
    let mut max_dev = 0.0f64;
    let stepper = Stepper::new(&model, DIVERGENCE_HINT);
    for step in 1..=steps {
        stepper.advance(&mut solver)?;
        if !(on_from..=on_to).contains(&first_front(step)) {
            continue;
        }
        let mut total = 0.0;
        let mut w_static = 0.0;
        for v in &solver.vehicles {
            for (j, axle) in v.dynamics.axles.iter().enumerate() {
                total += v.contact_force_n[j];
                let x = v.axle_x_m(j, step, dt_s);
                w_static += ab.static_deflection_m(mid, x, axle.static_load_n);
            }
        }
        sum_force += total;
        max_dev = max_dev.max((total - weight_n).abs() / weight_n);
        sum_w -= solver.bridge_response(mid, PointQuantity::Deflection, 0, &mut op);
        sum_w_static += w_static;
        count += 1;
    }
    let n = count.max(1) as f64;
    let window_s = n * dt_s;
    // The dynamic remainder. An axle rolling onto the span excites mode 1 by about
    // Omega / w1 of its static deflection (Omega = pi v / L = 0.052 rad/s, w1 = 23.7
    // rad/s: 2.2e-3); all axles in phase, the bridge vibrates by `vibration` x delta with
    // delta the static midspan deflection of the whole weight, and the vehicles riding on
    // it feel an acceleration `vibration` w1^2 delta, i.e. an inertial force of that over g
    // relative to their weight (following the quasi-static deflection adds v^2 w'' ~
    // 1e-6 m/s^2, negligible). The time average over the window T cancels a vibration to
    // ~2 / (w1 T) of its amplitude (the change of velocity over T). Tolerances: the max
    // deviation of the force sum within that acceleration bound; the means within 4x the
    // averaged bound (the amplitude is an order-of-magnitude estimate). The static part is
    // exact: Hermite elements with consistent point loads are nodally exact (midspan is a
    // node), and the tyre forces sum to the weight in equilibrium.
    let omega1 = model.omega_rad_s[0];
    let vibration = PI * speed / beam.span_m / omega1;
    let delta_m = ab.static_midspan_deflection_m(weight_n);
    let acceleration_g = vibration * omega1 * omega1 * delta_m / GRAVITY_M_S2;
    let averaging = 2.0 / (omega1 * window_s);
    let what = format!("3 vehicles crawling at {speed} m/s, all on the span for {window_s:.1} s");
    Ok(vec![
        CheckRow::relative(
            group,
            format!("mean sum of tyre forces, {what}"),
            "sum of weights (N)",
            weight_n,
            sum_force / n,
            4.0 * acceleration_g * averaging,
        ),
        CheckRow::with_error(
            group,
            format!("max |sum F - sum W| / sum W, {what}"),
            "0 (inertial remainder)",
            0.0,
            max_dev,
            max_dev,
            acceleration_g,
        ),
        CheckRow::relative(
            group,
            format!("mean midspan deflection, {what}"),
            "static influence lines (m)",
            sum_w_static / n,
            sum_w / n,
            4.0 * vibration * averaging,
        ),
    ])
}

// ---------------------------------------------------------------------------------------
// 3. Half car on a rigid sine road
// ---------------------------------------------------------------------------------------

/// Least-squares fit of `a + b sin(w t) + c cos(w t)`; returns the complex amplitude
/// `Y = b + i c`, so that the fitted oscillation is `Im(Y e^(i w t))`.
struct HarmonicFit {
    omega_rad_s: f64,
    normal: Matrix3<f64>,
    rhs: Vec<Vector3<f64>>,
}

impl HarmonicFit {
    fn new(omega_rad_s: f64, signals: usize) -> Self {
        HarmonicFit {
            omega_rad_s,
            normal: Matrix3::zeros(),
            rhs: vec![Vector3::zeros(); signals],
        }
    }

    fn add(&mut self, t_s: f64, values: &[f64]) {
        let (s, c) = (self.omega_rad_s * t_s).sin_cos();
        let basis = Vector3::new(1.0, s, c);
        self.normal += basis * basis.transpose();
        for (r, &v) in self.rhs.iter_mut().zip(values) {
            *r += basis * v;
        }
    }

    fn amplitudes(&self) -> Result<Vec<Complex<f64>>> {
        let lu = self.normal.lu();
        self.rhs
            .iter()
            .map(|r| {
                lu.solve(r)
                    .map(|x| Complex::new(x[1], x[2]))
                    .ok_or_else(|| Error::Factorization {
                        what: "harmonic fit normal equations".into(),
                        reason: "singular (window shorter than a period?)".into(),
                    })
            })
            .collect()
    }
}

/// Steady-state complex amplitudes (4 DOFs, then the 2 dynamic tyre forces) of a half car
/// on `r = R sin(w t)` under the front axle and `R sin(w (t - s / v))` under the rear,
/// by superposing two calls of `analytic::frf::harmonic_response` (linearity; the delay
/// multiplies the rear's complex amplitude by `e^(-i w s / v)`).
///
/// `omega_dyn_rad_s` is the frequency at which the vehicle's dynamic stiffness and
/// velocities are taken: `omega_rad_s` for the exact response, Newmark's warped
/// frequency for the time-stepped one (the road input and its rate stay at `w`).
fn half_car_frf(
    vehicle: &VehicleDynamics,
    omega_rad_s: f64,
    omega_dyn_rad_s: f64,
    amplitude_m: f64,
    delay_s: f64,
) -> Result<Vec<Complex<f64>>> {
    let n = vehicle.n_dof();
    let k = vehicle.stiffness_with_tyres();
    let c = vehicle.damping_with_tyres();
    let mut total = DVector::from_element(n, Complex::new(0.0, 0.0));
    let mut inputs = Vec::new();
    for (j, axle) in vehicle.axles.iter().enumerate() {
        let Some(dof) = axle.dof else { continue };
        let mut bk = DVector::zeros(n);
        let mut bc = DVector::zeros(n);
        bk[dof] = axle.tyre_stiffness_n_m;
        // harmonic_response multiplies B_c by i omega_dyn; the input rate is i w R.
        bc[dof] = axle.tyre_damping_n_s_m * omega_rad_s / omega_dyn_rad_s;
        let response = harmonic_response(
            &vehicle.mass,
            &c,
            &k,
            &bk,
            &bc,
            omega_dyn_rad_s,
            amplitude_m,
        )?;
        let phase = Complex::from_polar(1.0, -omega_rad_s * delay_s * j as f64);
        total += response.complex_amplitude * phase;
        inputs.push((dof, Complex::new(amplitude_m, 0.0) * phase));
    }
    let mut out: Vec<Complex<f64>> = total.iter().copied().collect();
    for ((dof, r), axle) in inputs.into_iter().zip(&vehicle.axles) {
        // f = kt (r - y) + ct (r' - y').
        let i = Complex::new(0.0, 1.0);
        let y = total[dof];
        out.push(
            (r - y) * axle.tyre_stiffness_n_m
                + i * axle.tyre_damping_n_s_m * (r * omega_rad_s - y * omega_dyn_rad_s),
        );
    }
    Ok(out)
}

/// Smallest decay rate |Re(lambda)| of the vehicle's free modes on a rigid road (1/s).
fn slowest_decay_rate(vehicle: &VehicleDynamics) -> Result<f64> {
    Ok(vehicle
        .rigid_road_eigenvalues()?
        .iter()
        .map(|l| -l.re)
        .fold(f64::INFINITY, f64::min))
}

/// two_axle_truck at 20 m/s on a rigid 5 mm sine road, excited at body bounce (1.6 Hz),
/// between the body and axle modes (5 Hz) and at axle hop (10.3 Hz).
pub fn sine_road_response() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_harmonic";
    let vehicle = half_car("two_axle_truck", None)?;
    let model = BridgeModel::build(&vbi_beam(), &fe(4), 0.0)?;
    let (speed, amplitude_m, dt_s) = (20.0, 0.005, 1e-3);
    let spacing_m = vehicle.wheelbase_m();
    let names = [
        "body bounce",
        "body pitch",
        "front axle",
        "rear axle",
        "front tyre force",
        "rear tyre force",
    ];
    // The start (rest, on the road) excites the free modes; the slowest decays as
    // e^(-sigma t) with sigma the smallest |Re(lambda)| of the first-order system (body
    // bounce, 3.6 % damping: 0.37 /s). Settle until e^(-sigma t) = 1e-9 (57 s), then fit
    // over 4 s (>= 6 periods).
    let settle_s = 9.0 * 10f64.ln() / slowest_decay_rate(&vehicle)?;
    let mut rows = Vec::new();
    for f_hz in [1.6, 5.0, 10.3] {
        let omega = 2.0 * PI * f_hz;
        let wavelength_m = speed / f_hz;
        let road = SineRoad {
            amplitude_m,
            wavenumber_rad_m: 2.0 * PI / wavelength_m,
        };
        // Start a whole number of wavelengths before x = 0, so that the front wheel sees
        // R sin(w t) with t = step * dt; the bridge (at x >= 0) is never reached.
        let travel_m = speed * (settle_s + 4.0) + 100.0;
        let start_m = -(travel_m / wavelength_m).ceil() * wavelength_m;
        let mut solver = coupled(&model, &road, dt_s, ContactLaw::Full)?;
        let statics: Vec<f64> = vehicle.axles.iter().map(|a| a.static_load_n).collect();
        solver.add_vehicle(CoupledVehicle::new(0, vehicle.clone(), speed, start_m, 0));
        let settle_steps = (settle_s / dt_s).ceil() as u64;
        let fit_steps = (4.0 / dt_s).round() as u64;
        let mut fit = HarmonicFit::new(omega, 6);
        let stepper = Stepper::new(&model, DIVERGENCE_HINT);
        for step in 1..=settle_steps + fit_steps {
            stepper.advance(&mut solver)?;
            if step > settle_steps {
                let v = &solver.vehicles[0];
                let values = [
                    v.state.u[0],
                    v.state.u[1],
                    v.state.u[2],
                    v.state.u[3],
                    v.contact_force_n[0] - statics[0],
                    v.contact_force_n[1] - statics[1],
                ];
                fit.add(step as f64 * dt_s, &values);
            }
        }
        let numerical = fit.amplitudes()?;
        let delay_s = spacing_m / speed;
        let exact = half_car_frf(&vehicle, omega, omega, amplitude_m, delay_s)?;
        // Newmark's average-acceleration rule is the trapezoidal rule: its steady state at
        // w is the exact FRF with the dynamic stiffness and the velocities taken at
        // Omega = (2/dt) tan(w dt/2) = w (1 + (w dt)^2 / 12 + ...) (the period error; the
        // road input is sampled exactly). The predicted error is the FRF's change over
        // that (w dt)^2/12 relative shift, amplified near a resonance by the FRF's slope;
        // tolerance: twice it, plus 1e-6 for the fit and the decayed transient.
        let warped = 2.0 / dt_s * (0.5 * omega * dt_s).tan();
        let newmark = half_car_frf(&vehicle, omega, warped, amplitude_m, delay_s)?;
        let mut worst_vs_newmark = 0.0f64;
        for (i, name) in names.iter().enumerate() {
            worst_vs_newmark =
                worst_vs_newmark.max((numerical[i] - newmark[i]).norm() / newmark[i].norm());
            let predicted = (newmark[i] - exact[i]).norm() / exact[i].norm();
            let error = (numerical[i] - exact[i]).norm() / exact[i].norm();
            rows.push(CheckRow::with_error(
                GROUP,
                format!("{name} at {f_hz} Hz (complex amplitude)"),
                "harmonic_response, rear delayed by s/v (|Y|)",
                exact[i].norm(),
                numerical[i].norm(),
                error,
                2.0 * predicted + 1e-6,
            ));
        }
        // The same steady state against the trapezoidal rule's own prediction: what is
        // left is the fit and the transient (1e-9 after settling), so this pins the coupling
        // terms (tyre damping with the road rate v dr/dx) far below the period error.
        rows.push(CheckRow::with_error(
            GROUP,
            format!("all 6 amplitudes at {f_hz} Hz, worst"),
            "FRF at Newmark's warped frequency (max rel. error)",
            0.0,
            worst_vs_newmark,
            worst_vs_newmark,
            1e-6,
        ));
    }
    Ok(rows)
}

// ---------------------------------------------------------------------------------------
// 4. Sprung mass crossing the VBI-2D beam
// ---------------------------------------------------------------------------------------

const SPRUNG_MASS_KG: f64 = 5_750.0;
const SPRUNG_STIFFNESS_N_M: f64 = 1.595e6;
const SPRUNG_SPEED_M_S: f64 = 25.0;
/// The VBI-2D ramp: 0 up to x = 5 m, linear to +10 mm at 10 m, +10 mm beyond.
const RAMP_START_M: f64 = 5.0;
const RAMP_END_M: f64 = 10.0;
const RAMP_HEIGHT_M: f64 = 0.010;

/// Midspan deflection history (DOWNWARD positive, one value per step from t = 0 to the
/// exit L / v) of a sprung mass on the numerical model, starting like the analytical
/// mass: at x = 0, t = 0 (front position 0, entry step 0), in static equilibrium.
fn sprung_mass_history(
    model: &BridgeModel,
    road: &dyn RoadSurface,
    vehicle: VehicleDynamics,
    speed_m_s: f64,
    dt_s: f64,
) -> Result<Vec<f64>> {
    let mut solver = coupled(model, road, dt_s, ContactLaw::Full)?;
    solver.add_vehicle(CoupledVehicle::new(0, vehicle, speed_m_s, 0.0, 0));
    let span = model.span_m();
    let steps = (span / (speed_m_s * dt_s)).round() as u64;
    let mut op = SparseVec::with_capacity(model.n_dof());
    let mut history = vec![0.0];
    let stepper = Stepper::new(model, DIVERGENCE_HINT);
    for _ in 0..steps {
        stepper.advance(&mut solver)?;
        history.push(-solver.bridge_response(0.5 * span, PointQuantity::Deflection, 0, &mut op));
    }
    Ok(history)
}

fn peak(values: &[f64]) -> f64 {
    values.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}

/// Modes of the analytical references in the ladder. Cost grows as N^3 (sprung_mass
/// module docs); 25 modes cost 1/8 of 50. Truncation: 25 modes reproduce the four
/// 100-mode VBI-2D peaks pinned in tests/analytic_references.rs within 4e-6 (measured),
/// far below every tolerance that uses them.
const REFERENCE_MODES: usize = 25;

/// The four VBI-2D sprung-mass cases (suspension damping 0 or 400 kN s/m, level road or
/// the 10 mm ramp over x = 5..10 m) on Hermite FE (20 elements) and lumped masses (49),
/// dt = 0.25 ms, against `analytic::sprung_mass`: peak midspan deflection while the mass is
/// on the beam, and the whole history, from t = 0 to the exit.
pub fn sprung_mass_crossing() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_sprung_mass";
    let beam = vbi_beam();
    let ab = analytic_beam(&beam)?;
    let dt_s = 2.5e-4;
    let models = [
        BridgeModel::build(&beam, &fe(20), 0.0)?,
        BridgeModel::build(&beam, &lumped(49), 0.0)?,
    ];
    // The same road for both: the analytical module's closure and the road module's
    // closed-form `ramp` shape.
    let ramp_spec = RoadProfileSpec::Ramp {
        start_m: RAMP_START_M,
        length_m: RAMP_END_M - RAMP_START_M,
        height_m: RAMP_HEIGHT_M,
    };
    let ramp_road = deterministic_road(&ramp_spec, -10.0, 60.0)?;
    let exit_s = beam.span_m / SPRUNG_SPEED_M_S;
    let steps = (exit_s / dt_s).round() as usize;
    let times: Vec<f64> = (0..=steps).map(|i| i as f64 * dt_s).collect();
    let mut rows = Vec::new();
    for damping in [0.0, 4.0e5] {
        for ramp in [false, true] {
            let problem = SprungMassProblem {
                beam: ab,
                vehicle: SprungMassVehicle {
                    mass_kg: SPRUNG_MASS_KG,
                    stiffness_n_m: SPRUNG_STIFFNESS_N_M,
                    damping_n_s_m: damping,
                },
                speed_m_s: SPRUNG_SPEED_M_S,
                road: if ramp {
                    Some(RoadIrregularity::linear_ramp(
                        RAMP_START_M,
                        RAMP_END_M,
                        RAMP_HEIGHT_M,
                    )?)
                } else {
                    None
                },
                options: SprungMassOptions {
                    n_modes: REFERENCE_MODES,
                    gravity_m_s2: GRAVITY_M_S2,
                    ..Default::default()
                },
            };
            let reference = problem.solve(&times)?;
            let ref_peak = reference.peak_midspan_deflection_on_beam_m;
            for model in &models {
                let road: &dyn RoadSurface = if ramp { &ramp_road } else { &LevelRoad };
                let vehicle = sprung_mass(SPRUNG_MASS_KG, SPRUNG_STIFFNESS_N_M, damping);
                let history = sprung_mass_history(model, road, vehicle, SPRUNG_SPEED_M_S, dt_s)?;
                let rms = (history
                    .iter()
                    .zip(&reference.samples)
                    .map(|(w, s)| (w - s.midspan_deflection_m).powi(2))
                    .sum::<f64>()
                    / history.len() as f64)
                    .sqrt();
                let what = format!(
                    "{} c={} kN s/m {}",
                    model.spec.label(),
                    damping / 1e3,
                    if ramp { "10 mm ramp" } else { "level" }
                );
                // Error budget at dt = 0.25 ms: Newmark's period error (w dt)^2/12 is 3e-6
                // on mode 1 and 1e-6 on the mass (2.6 Hz); sampling the peak every dt
                // costs < (w1 dt)^2 / 8 = 5e-6; the moving point load itself converges
                // more slowly than dt^2 (the moving_force harness on this beam, 40 elements:
                // history rms 6e-5, 2.3e-5, 8e-6 of the peak at dt = 0.5, 0.25, 0.125 ms);
                // 49 lumped masses leave ~1e-4 on mode 1, 20 elements far less (frequency
                // rows); 25 reference modes differ from 100 by <= 4e-6 (module docs).
                // Allowed: 1e-3, a 5x margin on the worst term and 5x inside the
                // VBI-2D acceptance of 0.5 %. With the dashpot on the ramp, the
                // dashpot force jumps by c v dr/dx at the ramp's two kinks, and a jump
                // inside a step is integrated by the trapezoidal rule with an impulse
                // error of up to (jump) dt / 2, i.e. a mode-1 deflection error of
                // (jump) dt / (M_b w1) for both kinks together: added to the tolerance.
                let jump_n =
                    damping * SPRUNG_SPEED_M_S * RAMP_HEIGHT_M / (RAMP_END_M - RAMP_START_M);
                let kinks = if ramp {
                    jump_n * dt_s / (ab.modal_mass_kg() * ab.omega_rad_s(1)) / ref_peak
                } else {
                    0.0
                };
                rows.push(CheckRow::relative(
                    GROUP,
                    format!("peak midspan {what}"),
                    "sprung_mass 25 modes (m)",
                    ref_peak,
                    peak(&history),
                    1e-3 + kinks,
                ));
                rows.push(CheckRow::with_error(
                    GROUP,
                    format!("history rms {what}"),
                    "sprung_mass 25 modes (rms / peak)",
                    0.0,
                    rms,
                    rms / ref_peak,
                    1e-3 + kinks,
                ));
            }
        }
    }
    Ok(rows)
}

// ---------------------------------------------------------------------------------------
// 5. Soft and stiff suspension limits
// ---------------------------------------------------------------------------------------

/// The sprung mass of the VBI-2D case with its stiffness scaled down tends to the moving
/// force m g, scaled up to the moving mass (`analytic::moving_mass`).
pub fn suspension_limits() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_limits";
    let beam = vbi_beam();
    let ab = analytic_beam(&beam)?;
    let dt_s = 5e-4;
    let model = BridgeModel::build(&beam, &fe(20), 0.0)?;
    let weight_n = SPRUNG_MASS_KG * GRAVITY_M_S2;
    let mut rows = Vec::new();

    // Soft limit, numerical model against the numerical moving force on the same model
    // and step, so that only the suspension differs.
    let (_, force_history) = moving_force_history(&MovingForceCase {
        beam: beam.clone(),
        spec: fe(20),
        damping_ratio: 0.0,
        force_n: weight_n,
        speed_m_s: SPRUNG_SPEED_M_S,
        dt_s,
        free_time_s: 0.0,
    })?;
    let force_peak = peak(&force_history);
    let fryba = MovingForceSolution::new(ab, weight_n, SPRUNG_SPEED_M_S, ModalDamping::None, 100)?;
    let exit_s = beam.span_m / SPRUNG_SPEED_M_S;
    let (_, fryba_peak) = fryba.peak_deflection_m(0.5 * beam.span_m, exit_s);
    let discretization = ((force_peak - fryba_peak) / fryba_peak).abs();
    // The limit itself: the same bound as the moving_force group (1e-3 on the peak).
    rows.push(CheckRow::relative(
        GROUP,
        format!(
            "moving force m g, peak midspan {} dt={dt_s}",
            model.spec.label()
        ),
        "Fryba 100 modes (m)",
        fryba_peak,
        force_peak,
        1e-3,
    ));
    for scale in [1e-1, 1e-2, 1e-3] {
        let k = SPRUNG_STIFFNESS_N_M * scale;
        let vehicle = sprung_mass(SPRUNG_MASS_KG, k, 0.0);
        let history = sprung_mass_history(&model, &LevelRoad, vehicle, SPRUNG_SPEED_M_S, dt_s)?;
        let error = ((peak(&history) - force_peak) / force_peak).abs();
        // The spring's dynamic force is k s with |s| <= |y| + |w| <= 3 w_max (the mass,
        // driven through the spring from rest, moves at most twice the base), so the
        // contact force departs from m g by <= 3 k w_max, and the peak by that fraction
        // of m g: tolerance 3 k w_max / (m g), proportional to k.
        let tolerance = 3.0 * k * force_peak / weight_n;
        rows.push(CheckRow::with_error(
            GROUP,
            format!("soft k = {k:.4e} N/m: peak midspan {}", model.spec.label()),
            "moving force m g, same model and dt",
            force_peak,
            peak(&history),
            error,
            tolerance,
        ));
    }

    // Stiff limit. A spring of frequency w_v passes the contact point's motion to the
    // mass amplified by 1 / (1 - (w / w_v)^2): once w_v is above the beam modes that
    // carry the contact point's acceleration, the sprung mass's extra inertial force, and
    // its difference from the moving mass, fall as 1/k (10x per decade of k; below that,
    // w_v crosses beam modes and the difference is not monotone: 1.9e-4 at k = 1.6e8,
    // 5.8e-5 at 1.6e9 N/m, measured). Rows: the analytic sprung mass at 1e3, 1e4, 1e5
    // times the nominal k must be within a tenth of the gap between the two limits
    // (moving force to moving mass) and then shrink >= 3x per decade; the numerical
    // model at the same k within that analytic difference plus twice its own
    // discretization error (measured on the moving force above).
    let moving_mass = MovingMassProblem {
        beam: ab,
        mass_kg: SPRUNG_MASS_KG,
        speed_m_s: SPRUNG_SPEED_M_S,
        options: MovingMassOptions {
            n_modes: REFERENCE_MODES,
            gravity_m_s2: GRAVITY_M_S2,
            ..Default::default()
        },
    }
    .solve(&[exit_s])?;
    let mm_peak = moving_mass.peak_midspan_deflection_on_beam_m;
    let fryba_25 = MovingForceSolution::new(
        ab,
        weight_n,
        SPRUNG_SPEED_M_S,
        ModalDamping::None,
        REFERENCE_MODES,
    )?;
    let gap = ((mm_peak - fryba_25.peak_deflection_m(0.5 * beam.span_m, exit_s).1) / mm_peak).abs();
    let mut previous = 10.0 * gap;
    for scale in [1e3, 1e4, 1e5] {
        let k = SPRUNG_STIFFNESS_N_M * scale;
        let sprung = SprungMassProblem {
            beam: ab,
            vehicle: SprungMassVehicle {
                mass_kg: SPRUNG_MASS_KG,
                stiffness_n_m: k,
                damping_n_s_m: 0.0,
            },
            speed_m_s: SPRUNG_SPEED_M_S,
            road: None,
            options: SprungMassOptions {
                n_modes: REFERENCE_MODES,
                gravity_m_s2: GRAVITY_M_S2,
                ..Default::default()
            },
        }
        .solve(&[exit_s])?;
        let value = sprung.peak_midspan_deflection_on_beam_m;
        let analytic_error = ((value - mm_peak) / mm_peak).abs();
        rows.push(CheckRow::with_error(
            GROUP,
            format!("stiff k = {k:.4e} N/m: peak midspan, sprung_mass 25 modes"),
            "moving_mass 25 modes (m)",
            mm_peak,
            value,
            analytic_error,
            if scale == 1e3 {
                0.1 * gap
            } else {
                previous / 3.0
            },
        ));
        previous = analytic_error;
        let vehicle = sprung_mass(SPRUNG_MASS_KG, k, 0.0);
        let history = sprung_mass_history(&model, &LevelRoad, vehicle, SPRUNG_SPEED_M_S, dt_s)?;
        let value = peak(&history);
        rows.push(CheckRow::with_error(
            GROUP,
            format!(
                "stiff k = {k:.4e} N/m: peak midspan {} dt={dt_s}",
                model.spec.label()
            ),
            "moving_mass 25 modes (m)",
            mm_peak,
            value,
            ((value - mm_peak) / mm_peak).abs(),
            analytic_error + 2.0 * discretization + 1e-6,
        ));
    }
    Ok(rows)
}

// ---------------------------------------------------------------------------------------
// 6. A 20 t truck on a smooth road
// ---------------------------------------------------------------------------------------

/// two_axle_truck with its body mass set to 17 500 kg (gross 20 000 kg instead of the
/// preset's 20 235 kg), from 30 m before the paper bridge (30 m, f1 = 3.78 Hz, 2 %
/// Rayleigh damping) at 10, 20 and 30 m/s on a smooth road: peak midspan deflection
/// against Fryba's moving forces with the truck's static axle loads.
pub fn truck_vs_moving_forces() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_truck";
    let beam = BeamProperties::paper_default();
    let ab = analytic_beam(&beam)?;
    let truck = half_car("two_axle_truck", Some(17_500.0))?;
    let dt_s = 1e-3;
    let approach_m = 30.0;
    let mid = 0.5 * beam.span_m;
    let mut rows = Vec::new();
    for spec in [fe(20), lumped(29)] {
        let model = BridgeModel::build(&beam, &spec, 0.02)?;
        let damping = ModalDamping::Rayleigh {
            a0: model.rayleigh.a0_per_s,
            a1: model.rayleigh.a1_s,
        };
        for speed in [10.0, 20.0, 30.0] {
            let mut solver = coupled(&model, &LevelRoad, dt_s, ContactLaw::Full)?;
            solver.add_vehicle(CoupledVehicle::new(0, truck.clone(), speed, -approach_m, 0));
            let travel_m = approach_m + beam.span_m + truck.wheelbase_m();
            let steps = (travel_m / (speed * dt_s)).ceil() as u64;
            let mut op = SparseVec::with_capacity(model.n_dof());
            let mut value = f64::NEG_INFINITY;
            let stepper = Stepper::new(&model, DIVERGENCE_HINT);
            for _ in 0..steps {
                stepper.advance(&mut solver)?;
                value =
                    value.max(-solver.bridge_response(mid, PointQuantity::Deflection, 0, &mut op));
            }
            let train = MovingLoadTrain {
                loads: truck
                    .axles
                    .iter()
                    .map(|a| (a.offset_m, a.static_load_n))
                    .collect(),
            };
            let reference = MovingForceSolution::for_train(ab, &train, speed, damping, 100)?;
            let (_, ref_peak) = reference.peak_deflection_m(mid, reference.exit_time_s());
            // The difference is the interaction itself, not an error: on a smooth road the
            // truck is excited only through the wheel path on the deflecting bridge, and
            // its dynamic tyre forces relative to its weight are of order
            // (a_bridge + v^2 w'') / g: at 30 m/s the bridge's vibration (DAF - 1) w1^2
            // delta ~ 3e-3 g and the path's curvature v^2 (pi / L)^2 delta ~ 2e-3 g, which
            // the lightly damped body bounce (3.6 %) amplifies; they grow with speed
            // (measured: 5e-5, 3.4e-3, 8.3e-3 at 10, 20, 30 m/s). Allowed: 1 %, the claim
            // under test (a 20 t truck on this 360 t span can be replaced by its static
            // axle loads to 1 %); the discretization adds <= 1e-3 (moving_force group).
            rows.push(CheckRow::relative(
                GROUP,
                format!("peak midspan 20 t truck v={speed} {}", spec.label()),
                "Fryba, static axle loads (m)",
                ref_peak,
                value,
                1e-2,
            ));
        }
    }
    Ok(rows)
}

// ---------------------------------------------------------------------------------------
// 7. ISO 8608 road profiles
// ---------------------------------------------------------------------------------------

/// ISO 8608 synthesis: the closed-form band RMS against PHYSICS.md's table, the RMS of
/// generated profiles (classes A-D, 8 seeds of 4 km each) against it, and the Welch PSD
/// of all 32 profiles (each divided by its class's sqrt(G_d(n0))) against the target in
/// octave bands.
pub fn road_profiles() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_road";
    let (n1, n2, dx) = (
        DEFAULT_N1_CYCLES_M,
        DEFAULT_N2_CYCLES_M,
        DEFAULT_SAMPLE_SPACING_M,
    );
    let (length_m, seeds, segment) = (4000.0, 8u64, 4096usize);
    let mut rows = Vec::new();
    // Relative sd of the mean square of one window of length T of a stationary process
    // with one-sided PSD G ~ n^-2 on [n1, n2] (Gaussian approximation, as in
    // tests/road_profiles.rs): var = (1/T) int G^2 / (int G)^2
    // = (1/3)(n1^-3 - n2^-3) / (T (1/n1 - 1/n2)^2), i.e. 1 / sqrt(3 T n1) = 9.1 %.
    let rel_var_one =
        (n1.powi(-3) - n2.powi(-3)) / (3.0 * length_m * (1.0 / n1 - 1.0 / n2).powi(2));
    let mut pooled_psd: Option<WelchPsd> = None;
    for (class, table_mm) in [
        (IsoClass::A, 3.99),
        (IsoClass::B, 7.99),
        (IsoClass::C, 15.98),
        (IsoClass::D, 31.96),
    ] {
        let gd = class.gd_n0_m3();
        let target_m = iso8608_band_rms_m(gd, n1, n2);
        // The table is rounded to 0.01 mm.
        rows.push(CheckRow::with_error(
            GROUP,
            format!("band rms class {}", class.letter()),
            "PHYSICS.md table (mm)",
            table_mm,
            1e3 * target_m,
            (1e3 * target_m - table_mm).abs(),
            0.005,
        ));
        let mut mean_square_ratio = 0.0;
        for seed in 0..seeds {
            let mut rng = ChaCha8Rng::seed_from_u64(100 * class.gd_n0_micro_m3() as u64 + seed);
            let profile =
                RoadProfile::build(&RoadProfileSpec::iso8608(class), 0.0, length_m, &mut rng)?;
            let z: Vec<f64> = profile.sample_points().map(|(_, z)| z).collect();
            let ms = z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64;
            mean_square_ratio += ms / (target_m * target_m) / seeds as f64;
            let normalised: Vec<f64> = z.iter().map(|v| v / gd.sqrt()).collect();
            let psd = welch_psd(&normalised, dx, segment)?;
            match &mut pooled_psd {
                None => pooled_psd = Some(psd),
                Some(total) => total.merge(&psd)?,
            }
        }
        // 4 sd of the mean of 8 windows in mean square, halved for the RMS: 6.5 %.
        let tolerance = 0.5 * 4.0 * (rel_var_one / seeds as f64).sqrt();
        rows.push(CheckRow::relative(
            GROUP,
            format!(
                "rms of {seeds} profiles x {} km, class {}",
                length_m / 1e3,
                class.letter()
            ),
            "sqrt(G_d(n0) n0^2 (1/n1 - 1/n2)) (m)",
            target_m,
            target_m * mean_square_ratio.sqrt(),
            tolerance,
        ));
    }
    let psd = pooled_psd.ok_or_else(|| Error::invalid("seeds", 0, "must be positive"))?;
    // Hann, 50 % overlap: the average of K periodograms has relative sd
    // sqrt((1 + 2 * 0.167^2) / K) (Welch 1967); adjacent bins are correlated, so a band of
    // b bins counts as b / 3 independent ones; the window smooths the n^-2 spectrum by a
    // relative bias (df / n)^2 (1 % at bin 10). Tolerance per band: 5 sd + bias.
    let sigma = ((1.0 + 2.0 * 0.167f64.powi(2)) / psd.segments as f64).sqrt();
    let df = psd.frequencies[0];
    let mut lo = 10.0 * df;
    while lo < n2 - 3.0 * df {
        let hi = (2.0 * lo).min(n2 - 3.0 * df);
        let ratios: Vec<f64> = psd
            .frequencies
            .iter()
            .zip(&psd.density)
            .filter(|(&n, _)| n >= lo && n < hi)
            .map(|(&n, &g)| g / iso8608_psd_m3(1.0, n))
            .collect();
        let bins = ratios.len() as f64;
        let mean = ratios.iter().sum::<f64>() / bins;
        rows.push(CheckRow::relative(
            GROUP,
            format!(
                "Welch PSD / target, n in [{lo:.3}, {hi:.3}) cycle/m, {} bins, {} segments",
                ratios.len(),
                psd.segments
            ),
            "G_d(n) / G_d (1)",
            1.0,
            mean,
            5.0 * sigma / (bins / 3.0).sqrt() + (df / lo).powi(2),
        ));
        lo = hi;
    }
    Ok(rows)
}

// ---------------------------------------------------------------------------------------
// 8. Unilateral contact
// ---------------------------------------------------------------------------------------

/// What one run over the bump recorded.
#[derive(Debug, Default)]
struct ContactRun {
    /// (step, axle) pairs with the tyre lifted off.
    airborne: u64,
    /// Largest |tyre force| while lifted off (N).
    max_force_airborne_n: f64,
    /// Landings: a tyre in contact again after a lift-off.
    recontacts: u64,
    /// Smallest total tyre force / static load.
    min_force_ratio: f64,
    /// Largest |recorded force - tyre law at the solved state| / static, tyres in contact.
    max_law_residual: f64,
    /// Largest tyre-law force (static included) / static while lifted off: <= 0 means
    /// the tyre would indeed be in tension, i.e. the gap is open.
    max_law_airborne: f64,
    /// Steps the solver counted as contact loss.
    contact_loss_steps: u64,
    /// Midspan deflection per step (m, upward).
    midspan_m: Vec<f64>,
    /// First step with a tyre lifted off or in tension.
    first_loss_step: Option<u64>,
    all_in_contact_at_end: bool,
}

/// The contact case: two_axle_truck at 20 m/s over a raised-cosine dip 40 mm deep and
/// 1 m long at x = 6 m on the VBI-2D beam (FE 20, 2 % damping). A raised 40 mm bump of
/// 0.5-2 m only unloads this heavily damped truck's tyres to 2-35 % of their static load
/// at 15-25 m/s (it lifts off for a few steps at most); over the dip the wheels cannot
/// follow the falling road and fly for ~15 ms each.
fn bump_run(law: ContactLaw) -> Result<ContactRun> {
    let (height_m, length_m, speed) = (-0.040, 1.0, 20.0);
    let beam = vbi_beam();
    let model = BridgeModel::build(&beam, &fe(20), 0.02)?;
    let bump = RoadProfileSpec::Bump {
        position_m: 6.0,
        length_m,
        height_m,
    };
    let road = deterministic_road(&bump, -50.0, 150.0)?;
    let dt_s = 5e-4;
    let mut solver = coupled(&model, &road, dt_s, law)?;
    let truck = half_car("two_axle_truck", None)?;
    solver.add_vehicle(CoupledVehicle::new(0, truck, speed, -10.0, 0));
    let steps = ((10.0 + beam.span_m + 15.0) / (speed * dt_s)).round() as u64;
    let mut run = ContactRun {
        min_force_ratio: f64::INFINITY,
        max_law_airborne: f64::NEG_INFINITY,
        ..Default::default()
    };
    let mut op = SparseVec::with_capacity(model.n_dof());
    let mut was_airborne = [false; 2];
    let stepper = Stepper::new(&model, DIVERGENCE_HINT);
    for step in 1..=steps {
        stepper.advance(&mut solver)?;
        run.midspan_m.push(solver.bridge_response(
            0.5 * beam.span_m,
            PointQuantity::Deflection,
            0,
            &mut op,
        ));
        let v = &solver.vehicles[0];
        for (j, axle) in v.dynamics.axles.iter().enumerate() {
            let Some(dof) = axle.dof else { continue };
            let x = v.axle_x_m(j, step, dt_s);
            let w = solver.bridge_response(x, PointQuantity::Deflection, 0, &mut op);
            let w_rate = solver.bridge_response(x, PointQuantity::Deflection, 1, &mut op);
            let w_slope = solver.bridge_response(x, PointQuantity::Slope, 0, &mut op);
            let z = w + road.elevation_m(x);
            let z_rate = w_rate + speed * (w_slope + road.slope(x));
            let law = axle.static_load_n
                + axle.tyre_stiffness_n_m * (z - v.state.u[dof])
                + axle.tyre_damping_n_s_m * (z_rate - v.state.v[dof]);
            let force = v.contact_force_n[j];
            run.min_force_ratio = run.min_force_ratio.min(force / axle.static_load_n);
            if v.in_contact[j] {
                run.max_law_residual = run
                    .max_law_residual
                    .max((force - law).abs() / axle.static_load_n);
                if was_airborne[j] {
                    run.recontacts += 1;
                }
            } else {
                run.airborne += 1;
                run.max_force_airborne_n = run.max_force_airborne_n.max(force.abs());
                run.max_law_airborne = run.max_law_airborne.max(law / axle.static_load_n);
            }
            if (!v.in_contact[j] || force < 0.0) && run.first_loss_step.is_none() {
                run.first_loss_step = Some(step);
            }
            was_airborne[j] = !v.in_contact[j];
        }
        run.all_in_contact_at_end = v.in_contact.iter().all(|&c| c);
        run.contact_loss_steps = v.contact_loss_steps;
    }
    Ok(run)
}

/// A flag as a row: error 0 when `ok`, 1 otherwise.
fn flag_row(group: &str, check: String, reference: &str, value: f64, ok: bool) -> CheckRow {
    let error = if ok { 0.0 } else { 1.0 };
    CheckRow::with_error(group, check, reference, 0.0, value, error, 0.0)
}

/// Unilateral and full (tension-capable) tyres over the dip of [`bump_run`].
pub fn unilateral_contact() -> Result<Vec<CheckRow>> {
    const GROUP: &str = "vbi_contact";
    let unilateral = bump_run(ContactLaw::Unilateral)?;
    let full = bump_run(ContactLaw::Full)?;
    let what = "two_axle_truck 20 m/s, 40 mm dip";
    let mut rows = vec![
        flag_row(
            GROUP,
            format!("unilateral: tyre-steps lifted off, {what}"),
            "> 0",
            unilateral.airborne as f64,
            unilateral.airborne > 0,
        ),
        // An airborne tyre's row of the contact system pins f = -F_static; the total
        // is then F_static + (-F_static), exactly 0.
        CheckRow::with_error(
            GROUP,
            format!("unilateral: max |F| while lifted off, {what}"),
            "0 (N)",
            0.0,
            unilateral.max_force_airborne_n,
            unilateral.max_force_airborne_n,
            0.0,
        ),
        flag_row(
            GROUP,
            format!("unilateral: landings after lift-off, {what}"),
            "> 0, all tyres in contact at the end",
            unilateral.recontacts as f64,
            unilateral.recontacts > 0 && unilateral.all_in_contact_at_end,
        ),
        flag_row(
            GROUP,
            format!("unilateral: contact_loss_steps, {what}"),
            "> 0",
            unilateral.contact_loss_steps as f64,
            unilateral.contact_loss_steps > 0,
        ),
        flag_row(
            GROUP,
            format!("unilateral: min F / F_static, {what}"),
            ">= 0 (no tension)",
            unilateral.min_force_ratio,
            unilateral.min_force_ratio >= 0.0,
        ),
        // While lifted off, the tyre law at the solved state gives tension (<= 0): the
        // wheel is really above the road, not held off it. The active set decides on the
        // same linear law, so the sign is exact up to round-off.
        flag_row(
            GROUP,
            format!("unilateral: max tyre-law force / F_static while lifted off, {what}"),
            "<= 0 (gap open)",
            unilateral.max_law_airborne,
            unilateral.max_law_airborne <= 1e-9,
        ),
    ];
    for (name, run) in [("unilateral", &unilateral), ("full", &full)] {
        // The recorded force is the tyre law kt (z - y) + ct (dz/dt - dy/dt), with the
        // convective term v (dw/dx + dr/dx), evaluated at the committed state: the
        // solver eliminates it exactly, so only round-off of the small solve remains
        // (forces ~1e5 N, states ~1e-2 m with kt ~ 4e6 N/m: ~1e-12 relative).
        rows.push(CheckRow::with_error(
            GROUP,
            format!("{name}: max |F - tyre law| / F_static in contact, {what}"),
            "0",
            0.0,
            run.max_law_residual,
            run.max_law_residual,
            1e-9,
        ));
    }
    rows.push(flag_row(
        GROUP,
        format!("full: min F / F_static, {what}"),
        "< 0 (tension)",
        full.min_force_ratio,
        full.min_force_ratio < 0.0 && full.airborne == 0 && full.contact_loss_steps > 0,
    ));
    // Both laws solve the same system until the first tyre would pull.
    let first = unilateral
        .first_loss_step
        .unwrap_or(unilateral.midspan_m.len() as u64) as usize;
    let before = max_abs(
        unilateral.midspan_m[..first.saturating_sub(1)]
            .iter()
            .zip(&full.midspan_m)
            .map(|(a, b)| a - b),
    );
    rows.push(CheckRow::with_error(
        GROUP,
        format!("unilateral vs full midspan before the first lift-off, {what}"),
        "identical (m)",
        0.0,
        before,
        before,
        0.0,
    ));
    Ok(rows)
}
