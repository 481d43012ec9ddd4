//! Checks of the bridge models and the integrator.

use std::f64::consts::PI;

use nalgebra::{DMatrix, DVector};

use super::harness::{
    manufactured_history, moving_force_history, ManufacturedCase, MovingForceCase,
};
use super::CheckRow;
use crate::error::Result;
use crate::physics::bridge::{
    BeamProperties, BridgeModel, LumpedStiffness, ModelSpec, PointQuantity, SparseVec,
};
use crate::physics::linalg::SymMatrix;
use crate::physics::solver::{Newmark, NewmarkCoefficients, NewmarkParams, SolveMode, Storage};
use crate::studies::analytic::{ModalDamping, MovingForceSolution, SimplySupportedBeam};

fn lumped(nodes: usize) -> ModelSpec {
    ModelSpec::LumpedMass {
        nodes,
        stiffness: LumpedStiffness::Auto,
    }
}

fn fe(elements: usize) -> ModelSpec {
    ModelSpec::FiniteElement { elements }
}

fn analytic_beam(beam: &BeamProperties) -> Result<SimplySupportedBeam> {
    SimplySupportedBeam::new(
        beam.length_m(),
        beam.flexural_rigidity_n_m2,
        beam.mass_per_length_kg_m,
    )
}

/// f1..f3 of both discretizations against `n^2 pi / (2 L^2) sqrt(EI/m)`.
pub fn frequencies() -> Result<Vec<CheckRow>> {
    let beam = BeamProperties::paper_default();
    let mut rows = Vec::new();
    for (spec, h_scale) in [
        (lumped(7), 8.0f64),
        (lumped(20), 21.0),
        (lumped(100), 101.0),
        (fe(4), 4.0),
        (fe(10), 10.0),
        (fe(40), 40.0),
    ] {
        let model = BridgeModel::build(&beam, &spec, 0.0)?;
        for n in 1..=3 {
            let exact = beam.closed_form_frequency_hz(n);
            // Lumped masses on the exact flexibility err at O((n h / L)^4), from below: the
            // error is known in closed form (`lumped_frequency_error`, which the measured
            // errors follow to 1 %), and 1.5x it is allowed, plus 1e-9 for the round-off of
            // the eigen-solution (3e-10 measured on f1 at N = 100, where the error itself
            // is 6.5e-10). Hermite elements with consistent mass err at
            // O((n h / L)^4); the leading term is below (n pi h / L)^4 / 720 (Rayleigh
            // quotient of the cubic interpolant), and we allow that bound.
            let tolerance = match spec {
                ModelSpec::LumpedMass { .. } => {
                    1.5 * lumped_frequency_error(n, h_scale as usize - 1).abs() + 1e-9
                }
                _ => (n as f64 * PI / h_scale).powi(4) / 720.0,
            };
            rows.push(CheckRow::relative(
                "frequencies",
                format!("f{n} {}", spec.label()),
                "closed form (Hz)",
                exact,
                model.frequency_hz(n),
                tolerance,
            ));
        }
    }
    Ok(rows)
}

/// Relative error of mode `n` of `nodes` equal masses `m h` (h = L / (nodes + 1)) on the
/// exact flexibility of a simply supported uniform beam: `(1 + S)^(-1/2) - 1`, with
/// `S = sum_{j >= 1} (n / (2 j (N + 1) - n))^4 + (n / (2 j (N + 1) + n))^4`.
///
/// Derivation: the flexibility kernel is `sum_k 2 / (m L) sin(k pi x / L) sin(k pi xi / L)
/// / w_k^2`; at the nodes `x_i = i h` the discrete sines are orthogonal, and `sin(k pi x_i
/// / L)` equals `+-sin(n pi x_i / L)` for the aliases `k = 2 j (N + 1) +- n`, so the node
/// values of `sin(n pi x / L)` are an exact eigenvector of the lumped model, with
/// `1 / w_h^2 = (1 / w_n^2) (1 + S)` (`w_k ~ k^2`). The leading term is
/// `S ~ (n pi h / L)^4 / 720`, a frequency error of `-(n pi h / L)^4 / 1440`.
pub fn lumped_frequency_error(n: usize, nodes: usize) -> f64 {
    let (n, period) = (n as f64, 2.0 * (nodes as f64 + 1.0));
    // The terms fall as j^-4: 2000 of them leave < 1e-10 of S.
    let s: f64 = (1..=2000)
        .map(|j| {
            let base = j as f64 * period;
            (n / (base - n)).powi(4) + (n / (base + n)).powi(4)
        })
        .sum();
    (1.0 + s).powf(-0.5) - 1.0
}

/// Static midspan deflection `P L^3 / 48 EI` for both models (nodally exact: round-off only).
pub fn static_deflection() -> Result<Vec<CheckRow>> {
    let beam = BeamProperties::paper_default();
    let p_n = 100_000.0;
    let exact = p_n * beam.length_m().powi(3) / (48.0 * beam.flexural_rigidity_n_m2);
    let mut rows = Vec::new();
    // Odd mass counts and even element counts put a node at midspan, where the
    // discretizations are nodally exact.
    for spec in [lumped(9), lumped(101), fe(4), fe(100)] {
        let model = BridgeModel::build(&beam, &spec, 0.0)?;
        let mut op = SparseVec::default();
        let mid = beam.length_m() / 2.0;
        model.point_operator(mid, PointQuantity::Deflection, &mut op);
        let load = op.to_dense(model.n_dof()) * -p_n;
        let u = model
            .stiffness
            .to_dense()
            .lu()
            .solve(&load)
            .unwrap_or_else(|| DVector::zeros(0));
        let w = -op.dot(&u);
        // Round-off grows with the condition number of K (~N^4): 1e-8 covers N = 100.
        rows.push(CheckRow::relative(
            "static",
            format!("midspan deflection {}", spec.label()),
            "P L^3 / 48 EI (m)",
            exact,
            w,
            1e-8,
        ));
    }
    Ok(rows)
}

/// Newmark on one oscillator: period elongation and energy.
pub fn newmark_oscillator() -> Result<Vec<CheckRow>> {
    let mut rows = Vec::new();
    let omega = 2.0 * PI;
    let one = |v: f64| SymMatrix::Dense(DMatrix::from_element(1, 1, v));
    for dt_over_t in [0.02, 0.1] {
        let coefficients = NewmarkCoefficients::new(dt_over_t, NewmarkParams::default())?;
        let mut nm = Newmark::new(
            &one(1.0),
            &one(0.0),
            &one(omega * omega),
            coefficients,
            SolveMode::Prefactored(Storage::Dense),
        )?;
        nm.state.u[0] = 1.0;
        nm.state.a[0] = -omega * omega;
        let zero = DVector::zeros(1);
        let (mut crossings, mut prev) = (Vec::new(), 1.0);
        let mut energy_drift: f64 = 0.0;
        let energy = |u: f64, v: f64| 0.5 * v * v + 0.5 * omega * omega * u * u;
        let e0 = energy(1.0, 0.0);
        for step in 1..1_000_000u64 {
            nm.step(&zero);
            let u = nm.state.u[0];
            energy_drift = energy_drift.max((energy(u, nm.state.v[0]) - e0).abs() / e0);
            if prev < 0.0 && u >= 0.0 {
                crossings.push((step as f64 - 1.0 + prev / (prev - u)) * dt_over_t);
                if crossings.len() == 201 {
                    break;
                }
            }
            prev = u;
        }
        let period = (crossings[200] - crossings[0]) / 200.0;
        let wdt = omega * dt_over_t;
        let expected = wdt / (2.0 * (wdt / 2.0).atan());
        // Zero-crossing times are interpolated linearly: an O((w dt)^3) error of a period
        // at the first and last crossing only, spread over 200 periods: < 1e-6.
        rows.push(CheckRow::relative(
            "newmark",
            format!("period ratio dt/T = {dt_over_t}"),
            "w dt / (2 atan(w dt / 2))",
            expected,
            period,
            1e-6,
        ));
        // Average acceleration conserves the energy of a linear undamped system exactly.
        rows.push(CheckRow::with_error(
            "newmark",
            format!("energy drift dt/T = {dt_over_t}"),
            "conserved (relative drift)",
            0.0,
            energy_drift,
            energy_drift,
            1e-10,
        ));
    }
    Ok(rows)
}

/// Moving constant force against Fryba's closed form (100 modes).
pub fn moving_force() -> Result<Vec<CheckRow>> {
    let beam = BeamProperties::paper_default();
    let ab = analytic_beam(&beam)?;
    let force_n = 200_000.0;
    let mut rows = Vec::new();
    for (zeta, label) in [(0.0, "zeta=0"), (0.02, "Rayleigh 2%")] {
        for speed in [10.0, 20.0, 30.0] {
            for spec in [lumped(50), fe(20)] {
                let case = MovingForceCase {
                    beam: beam.clone(),
                    spec: spec.clone(),
                    damping_ratio: zeta,
                    force_n,
                    speed_m_s: speed,
                    dt_s: 1e-3,
                    free_time_s: 1.0,
                };
                let (times, numerical) = moving_force_history(&case)?;
                let model = BridgeModel::build(&beam, &spec, zeta)?;
                // The reference gets the same Rayleigh curve as the model (fitted on the
                // model's own modes 1 and 2), so only the discretization differs.
                let damping = if zeta == 0.0 {
                    ModalDamping::None
                } else {
                    ModalDamping::Rayleigh {
                        a0: model.rayleigh.a0_per_s,
                        a1: model.rayleigh.a1_s,
                    }
                };
                let reference = MovingForceSolution::new(ab, force_n, speed, damping, 100)?;
                let mid = beam.length_m() / 2.0;
                let exact: Vec<f64> = times
                    .iter()
                    .map(|&t| reference.deflection_m(mid, t))
                    .collect();
                let (peak_ref, peak_num, rms) = super::history_errors(&numerical, &exact);
                // Tolerances: the time step (dt = 1 ms, w1 dt = 0.024) shifts the phase of
                // mode 1 by (w dt)^2/12 = 5e-5 per radian (3e-4 rad over 1.5 s), and the
                // force jumps onto a node at a discrete time (O(v dt / L)); 50 masses or 20
                // elements leave < 1e-4 on the static part. Peak: 1e-3; history RMS
                // relative to the peak: 2e-3.
                let what = format!("{} v={speed} {label}", spec.label());
                rows.push(CheckRow::relative(
                    "moving_force",
                    format!("peak {what}"),
                    "Fryba 100 modes (m)",
                    peak_ref,
                    peak_num,
                    1e-3,
                ));
                rows.push(CheckRow::with_error(
                    "moving_force",
                    format!("history rms {what}"),
                    "Fryba 100 modes (rms / peak)",
                    0.0,
                    rms,
                    rms / peak_ref,
                    2e-3,
                ));
            }
        }
    }
    Ok(rows)
}

/// Undamped midspan DAF vs alpha = v / (2 f1 L), against docs/physics.md's table.
pub fn daf_table() -> Result<Vec<CheckRow>> {
    let beam = BeamProperties::paper_default();
    let f1 = beam.closed_form_frequency_hz(1);
    let static_m = beam.length_m().powi(3) / (48.0 * beam.flexural_rigidity_n_m2);
    let mut rows = Vec::new();
    for (alpha, table) in [
        (0.05, 1.048),
        (0.10, 1.097),
        (0.20, 1.065),
        (0.30, 1.411),
        (0.50, 1.705),
    ] {
        let speed = alpha * 2.0 * f1 * beam.length_m();
        let passage_s = beam.length_m() / speed;
        let case = MovingForceCase {
            beam: beam.clone(),
            spec: fe(20),
            damping_ratio: 0.0,
            force_n: 1.0,
            speed_m_s: speed,
            // 2000 steps over the passage and at least 400 per period of mode 1.
            dt_s: (passage_s / 2000.0).min(1.0 / (400.0 * f1)),
            free_time_s: 1.0 / f1,
        };
        let (_, history) = moving_force_history(&case)?;
        let daf = history.iter().fold(0.0f64, |a, &b| a.max(b.abs())) / static_m;
        // The table has 3 decimals (+-0.0005); Newmark's phase error at this step and
        // the discrete peak sampling add < 0.001.
        rows.push(CheckRow::with_error(
            "daf",
            format!("undamped midspan DAF alpha={alpha} finite_element n=20"),
            "docs/physics.md table",
            table,
            daf,
            (daf - table).abs(),
            2e-3,
        ));
    }
    Ok(rows)
}

/// Manufactured solution with three modes at 0.3 L and 0.5 L, both models.
pub fn manufactured_solution() -> Result<Vec<CheckRow>> {
    let beam = BeamProperties::paper_default();
    let mut rows = Vec::new();
    for spec in [lumped(50), fe(20)] {
        let case = ManufacturedCase {
            beam: beam.clone(),
            spec: spec.clone(),
            damping_ratio: 0.02,
            dt_s: 1e-3,
            duration_s: 2.0,
            mode: SolveMode::Prefactored(Storage::Dense),
        };
        let points = [0.3 * beam.length_m(), 0.5 * beam.length_m()];
        let result = manufactured_history(&case, &points)?;
        for (label, err) in ["0.3 L", "0.5 L"].iter().zip(&result.relative_error) {
            // The response is dominated by the 2 Hz mode-1 component; Newmark's truncation
            // error on it is of order (W dt)^2 / 12 = 1.3e-5 at dt = 1 ms, and the spatial
            // error of 50 masses / 20 elements on modes 1-3 is smaller still (see the
            // frequency rows). Tolerance: 4x the time-step estimate, 5e-5. The study
            // `discretization` shows the convergence in n and dt behind this number.
            rows.push(CheckRow::with_error(
                "manufactured",
                format!("max error at {label} {}", spec.label()),
                "manufactured w(x,t), 3 modes (max err / max |w|)",
                0.0,
                *err,
                *err,
                5e-5,
            ));
        }
    }
    Ok(rows)
}
