//! A half car on a rigid sine road: the steady state against the exact FRF and against
//! Newmark's own prediction (docs/physics.md section 6).

use std::f64::consts::PI;

use nalgebra::{Complex, DVector, Matrix3, Vector3};

use crate::error::{Error, Result};
use crate::physics::bridge::BridgeModel;
use crate::physics::road::SineRoad;
use crate::physics::solver::{ContactLaw, CoupledVehicle, Stepper};
use crate::physics::vehicle::VehicleDynamics;
use crate::studies::analytic::harmonic_response;
use crate::studies::verify::CheckRow;
use crate::studies::DIVERGENCE_HINT;

use super::{coupled, fe, half_car, vbi_beam};

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
